#!/usr/bin/env bash
# Looks at the report in a real browser: headless Chromium screenshots index.html at a
# 1280×800 window (what a laptop shows first: the verdict and the top of the matrix) and the
# script checks that the screenshot is a real, non-blank page of the requested size.
#
#   scripts/report-screenshot.sh [RUN_DIR] [OUT.png] [WIDTHxHEIGHT] [TOP]
#
# Without RUN_DIR (or with "") it builds the report of the synthetic fixture run (no GPU
# needed). TOP (pixels, default 0) shows the page from that height down instead of from its
# top, e.g. the first scene's image viewer (headless Chromium paints nothing when it opens a
# page at an anchor, so the script shoots a window TOP + HEIGHT tall and keeps its bottom).
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
TOP=${4:-0}
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
    --user-data-dir="$WORK/profile" --screenshot="$WORK/window.png" --window-size="$WIDTH,$((TOP + HEIGHT))" \
    --virtual-time-budget=5000 "file://$INDEX" >"$WORK/chromium.log" 2>&1 || {
    cat "$WORK/chromium.log"
    echo "report-screenshot: 0 passed, 1 failed"
    exit 1
}

# The window's bottom HEIGHT rows (a PNG cropped with the standard library alone).
python3 - "$WORK/window.png" "$OUT" "$TOP" <<'PY'
import struct, sys, zlib
src, dst, top = sys.argv[1], sys.argv[2], int(sys.argv[3])
data = open(src, "rb").read()
chunks, i = [], 8
while i < len(data):
    n, kind = struct.unpack(">I4s", data[i:i + 8])
    chunks.append((kind, data[i + 8:i + 8 + n]))
    i += 12 + n
w, h, depth, colour = struct.unpack(">IIBB", chunks[0][1][:10])
assert depth == 8 and colour in (2, 6), f"unexpected PNG format {depth}/{colour}"
bpp = 3 if colour == 2 else 4
raw = zlib.decompress(b"".join(c for k, c in chunks if k == b"IDAT"))
stride, prev, rows = w * bpp, bytearray(w * bpp), []
for y in range(h):
    f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for x in range(stride):
        a = line[x - bpp] if x >= bpp else 0
        b, c = prev[x], prev[x - bpp] if x >= bpp else 0
        if f == 1: line[x] = (line[x] + a) & 255
        elif f == 2: line[x] = (line[x] + b) & 255
        elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(bytes(line))
    prev = line
kept = rows[top:]
def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
ihdr = struct.pack(">IIBBBBB", w, len(kept), 8, colour, 0, 0, 0)
idat = zlib.compress(b"".join(b"\0" + r for r in kept), 9)
open(dst, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b""))
PY

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
