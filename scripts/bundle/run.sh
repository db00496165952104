#!/usr/bin/env bash
# Runs scatterbench's default benchmark (every library scene × every method at default knobs)
# from this bundle, on this machine's first hardware adapter, or on the one --adapter names.
# Writes results.json, images and the HTML report; references come from the bundle's cache.
#
#   ./run.sh [--adapter NAME] [--res 256] [--out DIR] [--scenes all] [--methods all]
#            [other `scatterbench run` arguments]
#   ./run.sh --tune [--adapter NAME] [--res 512] [--scenes the ten homogeneous] [--time-limit S]
#            [other `scatterbench tune` arguments]: the cheapest configuration of every method
#            under each error budget, with 95 % intervals (ARCHITECTURE §4.6); references the
#            bundle lacks at that resolution are rendered here first.
#
# Needs a Vulkan loader (libvulkan.so.1) and a driver; no Rust toolchain. `bin/scatterbench
# adapters` lists what the loader finds.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="$here/bin/scatterbench"
adapter=""; res=""; out=""; scenes=""; methods=all; tune=false; rest=()
while [ $# -gt 0 ]; do
    case "$1" in
        --adapter) adapter=$2; shift 2 ;;
        --tune) tune=true; shift ;;
        --res) res=$2; shift 2 ;;
        --out) out=$2; shift 2 ;;
        --scenes) scenes=$2; shift 2 ;;
        --methods) methods=$2; shift 2 ;;
        -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) rest+=("$1"); shift ;;
    esac
done
"$bin" adapters
if [ -z "$adapter" ]; then
    adapter=$("$bin" adapters --first-hardware) || {
        echo "run.sh: no hardware adapter found; name one with --adapter (e.g. --adapter llvmpipe)" >&2
        exit 1
    }
fi
# The commit the binary was built from (results.json's run.git_commit), not the working
# directory's.
export SCATTERBENCH_COMMIT="$(cat "$here/COMMIT" 2>/dev/null || echo unknown)"
if $tune; then
    # Issue 33's ten homogeneous scenes at 512² unless told otherwise.
    : "${res:=512}" "${scenes:=sphere-point,desk-pencils,spring-point,fence-spot,window-sun,stained-glass-spot,clear-fog,pen-orbit,overlap-point,indirect-point}"
    [ -n "$out" ] || out="$here/results/tune-$(date -u +%Y-%m-%dT%H-%M-%SZ)-${res}"
    "$bin" tune --scenes "$scenes" --methods "$methods" --res "$res" --adapter "$adapter" \
        --cache "$here/cache" --out "$out" "${rest[@]}"
    echo "tune: $out/tune.json"
    exit 0
fi
: "${res:=256}" "${scenes:=all}"
[ -n "$out" ] || out="$here/results/$(date -u +%Y-%m-%dT%H-%M-%SZ)-${res}"
"$bin" run --scenes "$scenes" --methods "$methods" --res "$res" --adapter "$adapter" \
    --cache "$here/cache" --out "$out" "${rest[@]}"
echo "results: $out/results.json"
