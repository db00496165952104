#!/usr/bin/env bash
# Runs clippy with warnings as errors, then every test of the workspace. Installs Mesa's software
# Vulkan driver (lavapipe) first when no Vulkan driver is present, so the GPU tests run on
# machines without a GPU; Debian's Chromium when absent, for the report's browser tests (it also
# brings SwiftShader, a second software Vulkan driver, ARCHITECTURE §7); and the Khronos
# validation layer when absent, for the validation test. With CI set, a GPU test that finds no
# adapter, the browser tests without Chromium and the validation test without the layer fail
# instead of skipping.
set -euo pipefail
cd "$(dirname "$0")/.."

have_vulkan_icd() {
    # Either directory may be absent; one driver manifest in either is enough.
    compgen -G '/usr/share/vulkan/icd.d/*.json' >/dev/null || compgen -G '/etc/vulkan/icd.d/*.json' >/dev/null
}

if ! have_vulkan_icd; then
    echo "no Vulkan driver found: installing mesa-vulkan-drivers (lavapipe)" >&2
    if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq mesa-vulkan-drivers >/dev/null
fi

if ! command -v chromium >/dev/null 2>&1; then
    echo "no chromium found: installing Debian's chromium (the report's browser test)" >&2
    if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq chromium >/dev/null
fi

if ! compgen -G '/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json' >/dev/null; then
    echo "no Vulkan validation layer found: installing vulkan-validationlayers" >&2
    if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq vulkan-validationlayers >/dev/null
fi

# Mesa's device-select layer prints harmless XDG_RUNTIME_DIR warnings without this.
export NODEVICE_SELECT=1
# Clippy first (it fails fast), so that the test runner's summary closes the output.
cargo clippy --release --workspace --all-targets -- -D warnings
# The binary `scripts/bench.sh` runs, built as it builds it (the tests' feature set differs), so
# that the benchmark after the tests compiles nothing; quiet, so that the tests' summary closes
# the output.
cargo test --release --workspace --all-targets "$@"
cargo build --release --bin scatterbench --quiet
