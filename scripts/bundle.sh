#!/usr/bin/env bash
# Writes a self-contained benchmark bundle to OUT: the stripped release binary, the scene
# library, the reference cache of the default run (every library scene, every frame) at the
# bundle's resolutions, and run.sh, which runs the default benchmark on any Linux machine with
# a Vulkan loader and driver, without a Rust toolchain (docs/ARCHITECTURE.md §7).
#
#   scripts/bundle.sh OUT [--res 256,1024] [--scenes all] [--cache-from results/cache]
#                         [--skip RES:SCENE,...] [--binary PATH] [--max-mb 60]
#
# --res          resolutions whose references are shipped (default 256,1024)
# --scenes       scenes whose references are shipped (default all: the library)
# --cache-from   a reference cache to copy entries from before rendering missing ones
# --skip         ship no references of these scenes at this resolution (repeatable), e.g.
#                1024:smoke-point, whose 1024² reference takes about 5 h on 2 cores; listed in
#                the bundle's SKIPPED, and rendered by run.sh on the machine that needs them
# --binary       use this scatterbench binary instead of building one with the bundle profile
#                (it is stripped in OUT)
# --max-mb       refuse (exit 1) a bundle larger than this many MB (10⁶ bytes; default 60)
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 1 ] || usage
out=$1; shift
res=256,1024; scenes=all; cache_from=results/cache; binary=""; max_mb=60; skips=()
while [ $# -gt 0 ]; do
    case "$1" in
        --res) res=$2; shift 2 ;;
        --scenes) scenes=$2; shift 2 ;;
        --cache-from) cache_from=$2; shift 2 ;;
        --skip)
            case "$2" in *:?*) skips+=("$2") ;; *) echo "bundle.sh: --skip '$2' is not RES:SCENE[,SCENE...]" >&2; exit 2 ;; esac
            shift 2 ;;
        --binary) binary=$2; shift 2 ;;
        --max-mb) max_mb=$2; shift 2 ;;
        *) echo "bundle.sh: unknown argument '$1'" >&2; usage ;;
    esac
done
case "$max_mb" in ''|*[!0-9]*) echo "bundle.sh: --max-mb '$max_mb' is not a whole number of MB" >&2; exit 2 ;; esac
if [ -e "$out" ] && [ -n "$(ls -A "$out" 2>/dev/null)" ]; then
    echo "bundle.sh: $out exists and is not empty" >&2; exit 2
fi

if [ -z "$binary" ]; then
    # Cargo.toml's bundle profile: release with fat LTO, stripped (a few MB smaller).
    cargo build --profile bundle --bin scatterbench
    binary=target/bundle/scatterbench
fi
[ -x "$binary" ] || { echo "bundle.sh: --binary $binary is not an executable" >&2; exit 2; }

mkdir -p "$out/bin" "$out/cache"
cp "$binary" "$out/bin/scatterbench"
strip "$out/bin/scatterbench"
cp -r scenes/library "$out/scenes"
cp scripts/bundle/run.sh "$out/run.sh"
cp scripts/bundle/README.md "$out/README.md"
chmod +x "$out/run.sh"
git describe --always --dirty --abbrev=12 >"$out/COMMIT" 2>/dev/null || echo unknown >"$out/COMMIT"

copy=()
[ -d "$cache_from" ] && copy=(--copy-from "$cache_from")
[ "$scenes" = all ] && scenes=$(cd scenes/library && ls *.json | sed 's/\.json$//' | paste -sd,)
# Whether a --skip names scene $2 at resolution $1.
skipped() {
    local skip
    for skip in "${skips[@]}"; do
        [ "${skip%%:*}" = "$1" ] && [[ ",${skip#*:}," == *",$2,"* ]] && return 0
    done
    return 1
}
: >"$out/SKIPPED"
for r in ${res//,/ }; do
    kept=()
    for s in ${scenes//,/ }; do
        if skipped "$r" "$s"; then echo "$r $s" >>"$out/SKIPPED"; else kept+=("$s"); fi
    done
    [ ${#kept[@]} -gt 0 ] || continue
    # 20 mantissa bits: at most 4.8e-7 relative, under half the reference's own quadrature
    # tolerance (1e-6); a quarter smaller than lossless (docs/ARCHITECTURE.md §9.1).
    NODEVICE_SELECT=1 "$out/bin/scatterbench" references --scenes "$(IFS=,; echo "${kept[*]}")" --res "$r" \
        --cache "$out/cache" --mantissa-bits 20 "${copy[@]}"
done

# Bytes the files hold (not disk blocks), in MB of 10⁶ bytes.
mb() { du -sb "$1" | awk '{printf "%.1f", $1 / 1e6}'; }
size_b=$(du -sb "$out" | cut -f1)
echo "bundle: $out, $(mb "$out") MB ($(mb "$out/bin") binary, $(mb "$out/cache") references)"
if [ "$size_b" -gt $((max_mb * 1000000)) ]; then
    echo "bundle.sh: the bundle is $(mb "$out") MB, over the limit of $max_mb MB" >&2
    exit 1
fi
