#!/bin/bash
# Runs on a GPU machine, from the repository root, with .device/ and
# .gl/ carried (scripts/device/bundle.sh makes .device/bundle.tar.xz). It checks the
# shaders on the real driver (test_host with the validation layer on), then measures the
# MPU evaluation throughput and the whole run against the peers, writing logs to $OUT.
set -uo pipefail
OUT=${OUT:-/tmp/out}; mkdir -p "$OUT"
for f in .gl/*.deb; do dpkg -x "$f" /; done; ldconfig
B=/tmp/bundle; mkdir -p $B && tar -C $B -xJf .device/bundle.tar.xz
export LD_LIBRARY_PATH=$B/lib VK_LAYER_PATH=$B/layers
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f $icd ] && export VK_DRIVER_FILES=$icd __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
nvidia-smi -L; nproc; grep -m1 'model name' /proc/cpuinfo
$B/bin/mpumesh devices
ct=$B/Cranium.inv3
step=${1:-all}
if [[ $step == all || $step == tests ]]; then
  MPUMESH_REQUIRE_VULKAN=1 MPUMESH_VALIDATION=1 $B/bin/test_host 2>&1 | tee "$OUT/test_host.log" | grep -E '^\[  (PASSED|FAILED|SKIPPED) |FAILED|tests ran'
fi
if [[ $step == all || $step == mpu ]]; then
  $B/bin/mpumesh_bench_mpu $ct 226 ${MPU_QUERIES:-4000000} 5 2>&1 | tee "$OUT/bench_mpu.txt"
fi
if [[ $step == all || $step == run ]]; then
  timer=""; [ -x /usr/bin/time ] && timer="/usr/bin/time -v"
  for be in gpu cpu; do
    $timer $B/bin/mpumesh run $ct --threshold 226 --particles 40000 --backend $be \
      -o /tmp/ct_$be.ply --report "$OUT/run_$be.json" 2>"$OUT/run_$be.time" | tail -3
    grep -E 'Elapsed|Maximum resident' "$OUT/run_$be.time"
  done
  $B/bin/mpumesh_bench_run $ct 226 40000 3.4 0.72 2>&1 | tee "$OUT/bench_run.txt"
fi
if [[ $step == all || $step == render ]]; then
  # The HTML report made on the GPU, and the renderer's time on both backends.
  $B/bin/mpumesh run $ct --threshold 226 --particles 40000 --backend gpu -o /tmp/ct_r.ply \
    --html "$OUT/report_gpu.html" --report "$OUT/run_html.json" --no-self-intersections --quiet
  $B/bin/mpumesh mc $ct --threshold 226 -o /tmp/mc.ply --quiet
  for be in gpu cpu; do
    $B/bin/mpumesh render /tmp/mc.ply -o "$OUT/mc_$be.png" --color curvature --wireframe --size 2048x1536 \
      --backend $be --json | grep -A12 stage_seconds | tr -d '\n '; echo " ($be)"
  done
fi
if [[ $step == all || $step == large ]]; then
  # The full-resolution case (scripts/bench_large.sh) on both backends.
  $B/bin/mpumesh convert $ct -o /tmp/cranium512.mha --size 512x512x324 --quiet
  for be in gpu cpu; do
    $B/bin/mpumesh run /tmp/cranium512.mha --threshold 226 -o /tmp/skull512_$be.ply --report "$OUT/large_$be.json" \
      --no-self-intersections --quiet --backend $be
    /usr/bin/python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(sys.argv[2], j['stage_seconds'], j['memory'])" \
      "$OUT/large_$be.json" $be
  done
fi

