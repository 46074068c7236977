#!/bin/sh
# Runs each test program given as an argument, one line per program, its log kept in
# <program>.log; prints the failing logs and closes with "N passed, N failed".
# Up to GRAN_TEST_JOBS programs (default: the number of cores) run at once; the lines come out in
# the order of the arguments. While several run at once, each gets OMP_NUM_THREADS = cores / jobs
# (at least 1) unless OMP_NUM_THREADS is set already, so OpenMP tests do not oversubscribe the
# cores; tests that ask for a thread count themselves keep it.
log_of() {
  case "$1" in
    *.sh) echo "${GRAN_BUILD:-build}/tests/$(basename "$1").log" ;; # scripts live in tests/
    *) echo "$1.log" ;;
  esac
}

# One test: `run-tests.sh --one RESULTS INDEX PROGRAM` writes RESULTS/INDEX as "STATUS SECONDS".
if [ "${1:-}" = "--one" ]; then
  res=$2; i=$3; t=$4
  log=$(log_of "$t")
  mkdir -p "$(dirname "$log")"
  start=$(date +%s)
  if "$t" >"$log" 2>&1; then status=ok; else status=FAIL; fi
  echo "$status $(( $(date +%s) - start ))" >"$res/$i.tmp" && mv "$res/$i.tmp" "$res/$i"
  exit 0
fi

cores=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
jobs=${GRAN_TEST_JOBS:-$cores}
case "$jobs" in '' | *[!0-9]* | 0) jobs=$cores ;; esac
[ "$jobs" -gt "$#" ] && [ "$#" -gt 0 ] && jobs=$#
if [ "$jobs" -gt 1 ] && [ -z "${OMP_NUM_THREADS:-}" ]; then
  nt=$((cores / jobs)); [ "$nt" -ge 1 ] || nt=1
  OMP_NUM_THREADS=$nt; export OMP_NUM_THREADS
fi

res=$(mktemp -d "${TMPDIR:-/tmp}/granary-tests-XXXXXX")
trap 'rm -rf "$res"' EXIT
trap 'exit 130' INT TERM
n=0
for t in "$@"; do n=$((n + 1)); echo "$n $t"; done |
  xargs -P "$jobs" -L 1 sh "$0" --one "$res" &
runner=$!

pass=0; fail=0; failed=""; i=0
for t in "$@"; do
  i=$((i + 1))
  while [ ! -f "$res/$i" ]; do
    if ! kill -0 "$runner" 2>/dev/null && [ ! -f "$res/$i" ]; then echo "FAIL -1" >"$res/$i"; break; fi
    sleep 0.2
  done
  read -r status secs <"$res/$i"
  if [ "$status" = ok ]; then pass=$((pass + 1)); else fail=$((fail + 1)); failed="$failed $t"; fi
  printf '%-5s %-48s %4ss\n' "$status" "$(basename "$t")" "$secs"
done
wait "$runner"
for t in $failed; do
  log=$(log_of "$t")
  echo "---- $log (last 40 lines)"; tail -n 40 "$log"
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
