#!/usr/bin/env bash
# Looks at the report in a real browser: headless Chromium screenshots index.html at a
# 1280×800 window (what a laptop shows first: the verdict and the top of the matrix) and the
# script checks that the screenshot is a real, non-blank page of the requested size.
#
#   scripts/report-screenshot.sh [RUN_DIR] [OUT.png] [WIDTHxHEIGHT] [ANCHOR]
#
# Without RUN_DIR (or with "") it builds the report of the synthetic fixture run (no GPU
# needed). ANCHOR (an element id, e.g. a scene's section `sphere-point`) opens the page there
# instead of at the top: the scene's image viewer.
# Skipped, with a message, when Chromium is not installed (`apt-get install -y chromium`);
# not a CI requirement.
set -euo pipefail
cd "$(dirname "$0")/.."

CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$CHROMIUM" ]; then
    echo "report-screenshot: skipped — chromium is not installed (apt-get install -y chromium)"
    exit 0
fi

RUN_DIR=${1:-}
OUT=${2:-}
SIZE=${3:-1280x800}
WIDTH=${SIZE%x*}
HEIGHT=${SIZE#*x}
ANCHOR=${4:-}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

if [ -z "$RUN_DIR" ]; then
    RUN_DIR="$WORK/fixture-run"
    NODEVICE_SELECT=1 cargo run --quiet --release -p report --example fixture -- "$RUN_DIR" >/dev/null
else
    NODEVICE_SELECT=1 cargo run --quiet --release -- report "$RUN_DIR" >/dev/null
fi
INDEX=$(realpath "$RUN_DIR/report/index.html")
OUT=${OUT:-$WORK/report.png}

"$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$WORK/profile" --screenshot="$OUT" --window-size="$WIDTH,$HEIGHT" \
    "file://$INDEX${ANCHOR:+#$ANCHOR}" >"$WORK/chromium.log" 2>&1 || {
    cat "$WORK/chromium.log"
    echo "report-screenshot: 0 passed, 1 failed"
    exit 1
}

# A PNG of the window size whose size shows content: a blank or error page compresses to a
# few KB at this size, the report (images, tables, plot) to far more.
python3 - "$OUT" "$WIDTH" "$HEIGHT" <<'PY'
import struct, sys
path, w, h = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
data = open(path, "rb").read()
problems = []
if data[:8] != b"\x89PNG\r\n\x1a\n":
    problems.append("not a PNG")
else:
    pw, ph = struct.unpack(">II", data[16:24])
    if (pw, ph) != (w, h):
        problems.append(f"size {pw}x{ph}, expected {w}x{h}")
if len(data) < 30_000:
    problems.append(f"only {len(data)} bytes: the page looks blank")
if problems:
    print("report-screenshot: " + "; ".join(problems))
    print("report-screenshot: 0 passed, 1 failed")
    sys.exit(1)
print(f"report-screenshot: {path} ({len(data)} bytes)")
PY
echo "report-screenshot: 1 passed, 0 failed"
