#!/usr/bin/env bash
# Issue 33's frontier sweep on a device machine (the `device` tool's `run`), as run on
# 2026-11-27, with what that run taught added: a run directory does not survive between calls,
# so a partial run is resumed from a results.json carried back in; the GPU's clocks are logged.
#
#   devcarry/go.sh SECONDS        (from the checkout's root on the device; carry .gl, devcarry)
#
# devcarry/ holds: after, before (stripped scatterbench binaries; before = d13288c with
# ../lavapipe-frontier-512-sweep-2026-11-27/before.patch applied: the strip FLIP and
# --paired-floor), cache/ (references of the ten scenes at 512², 20 mantissa bits),
# scenes (the ten names, comma-separated), resume/{after,before}.results.json (optional: a
# partial run to resume). .gl/ holds libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0
# libgles2 (all seven: with libvulkan1 alone NVIDIA's ICD does not load). Starts no new work
# after SECONDS; results.json, the log and the clock log of each run come back in $OUT.
set -u
T0=$(date +%s); LIMIT=$1
[ -n "${LOCAL:-}" ] || { for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig; }
here=$(pwd); D=$here/devcarry; R=$here/devruns; mkdir -p $R /tmp/bwd
export NODEVICE_SELECT=1 WGPU_ADAPTER_NAME=${ADAPTER:-NVIDIA} WGPU_BACKEND=vulkan
$D/after adapters 2>&1 | tee $OUT/adapters.txt
if [ -z "${LOCAL:-}" ] && ! grep -q NVIDIA $OUT/adapters.txt; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  $D/after adapters 2>&1 | tee -a $OUT/adapters.txt
fi
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=timestamp,pstate,clocks.sm,clocks.mem,power.draw,utilization.gpu \
  --format=csv -lms 500 > $OUT/clocks.csv 2>&1 &
# before (d13288c) has no --adapter: both binaries take the adapter from WGPU_ADAPTER_NAME.
# EXTRA: more `run` arguments for both binaries, e.g. EXTRA=--paired-floor (ARCHITECTURE §4.5;
# the before binary has it with before.patch, not with the older before-scorer.patch).
A="--res ${RES:-512} --frames 3 --warmup 1 --sweep --methods all --scenes ${SCENES:-$(cat $D/scenes)} --record-timeout 60 ${EXTRA:-}"
left() { echo $(( LIMIT - ($(date +%s) - T0) )); }
one() { # name binary cache workdir commit
  local n=$1 b=$2 c=$3 wd=$4 res=""
  if [ ! -f $R/$n/results.json ] && [ -f $D/resume/$n.results.json ]; then
    mkdir -p $R/$n && cp $D/resume/$n.results.json $R/$n/results.json
  fi
  [ -f $R/$n/results.json ] && res="--resume"
  local t=$(left); [ $t -gt 20 ] || { echo "$n: no time left"; return; }
  echo "$n: start, $t s left"
  (cd $wd && SCATTERBENCH_COMMIT=$5 timeout $t $b run $A --cache $c --out $R/$n $res > $R/$n.log.part 2>&1); echo "$n rc=$?"
  cat $R/$n.log.part >> $R/$n.log; tail -3 $R/$n.log
  cp $R/$n/results.json $OUT/$n.results.json 2>/dev/null; cp $R/$n.log $OUT/$n.log
}
one after $D/after $D/cache $here "${AFTER_COMMIT:-unknown}"
# before renders its own references (d13288c reads no packed cache): ≈ 15 s on 16 cores.
one before $D/before /tmp/cb /tmp/bwd "${BEFORE_COMMIT:-d13288c+before.patch}"
echo "total $(( $(date +%s) - T0 )) s"
