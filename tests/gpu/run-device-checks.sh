#!/bin/sh
# run-device-checks.sh - every GPU check of the CUDA backend in one command, for a session with a GPU:
# builds for one architecture (CUDA_ARCH, default 90 = H100/H200), runs `make test-gpu` (tests/gpu),
# the device part of `make test` (t890: device selection with a GPU present, host reference against
# the CPU engine) and `make bench-gpu` (bench/gpu), and copies build/gpu-results/ to $OUT when set.
# Each stage has its own time limit (TEST_TIMEOUT, BENCH_TIMEOUT seconds); a failing stage does not
# stop the next one. SKIP_BUILD=1 uses binaries already in build/ (built elsewhere with the same
# CUDA_ARCH). Exit status: 0 when the tests passed (the bench only reports).
set -u
cd "$(dirname "$0")/../.." || exit 2
ARCH=${CUDA_ARCH:-90}
JOBS=${JOBS:-$(nproc 2>/dev/null || echo 4)}
RES=build/gpu-results
MK="make --no-print-directory CUDA_ARCH=$ARCH CUDA_PTX=$ARCH"
mkdir -p "$RES"
t0=$(date +%s)
{
  echo "run-device-checks: $(date -u) host $(hostname) CUDA_ARCH=$ARCH jobs=$JOBS"
  nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.memory --format=csv 2>&1 || echo "nvidia-smi: not available"
} > "$RES/device.txt"
cat "$RES/device.txt"
rc=0
if [ "${SKIP_BUILD:-0}" != 1 ]; then
  echo "== build (make -j$JOBS CUDA_ARCH=$ARCH)"
  if ! $MK -j"$JOBS" all build/tests/t890-srd-device > "$RES/build.txt" 2>&1; then
    echo "build failed (last lines of $RES/build.txt):"; tail -30 "$RES/build.txt"; rc=1
  fi
  echo "build: $(( $(date +%s) - t0 )) s"
fi
echo "== make test-gpu"
timeout "${TEST_TIMEOUT:-300}" $MK test-gpu || rc=1
echo "== make test T='t89*' (device selection, reference)"
timeout 120 $MK test T='t89*' > "$RES/test-t89.txt" 2>&1 || rc=1
cat "$RES/test-t89.txt" | tail -5
echo "== make bench-gpu"
timeout "${BENCH_TIMEOUT:-240}" $MK bench-gpu || echo "bench-gpu: exit status $? (see $RES/bench-gpu.txt)"
echo "run-device-checks: done in $(( $(date +%s) - t0 )) s, tests $( [ $rc = 0 ] && echo passed || echo FAILED )" | tee -a "$RES/device.txt"
if [ -n "${OUT:-}" ]; then mkdir -p "$OUT/gpu-results" && cp -r "$RES"/. "$OUT/gpu-results/"; fi
exit $rc
