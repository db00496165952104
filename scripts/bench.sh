#!/usr/bin/env bash
# Runs the benchmark on the whole scene library with every method (default knobs, 256²),
# installing lavapipe first when no Vulkan driver is present. Extra arguments go to
# `scatterbench run` (e.g. --res 512 --sweep).
set -euo pipefail
cd "$(dirname "$0")/.."
# Either directory may be absent; one driver manifest in either is enough.
if ! compgen -G '/usr/share/vulkan/icd.d/*.json' >/dev/null && ! compgen -G '/etc/vulkan/icd.d/*.json' >/dev/null; then
    echo "no Vulkan driver found: installing mesa-vulkan-drivers (lavapipe)" >&2
    if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq mesa-vulkan-drivers >/dev/null
fi
export NODEVICE_SELECT=1
cargo run --release -- run --scenes all --methods all --res 256 "$@"
