#!/bin/sh
# Runs each test program given as an argument, one line per program, its log kept in
# <program>.log; prints the failing logs and closes with "N passed, N failed".
pass=0; fail=0; failed=""
for t in "$@"; do
  case "$t" in
    *.sh) mkdir -p "${GRAN_BUILD:-build}/tests"; log="${GRAN_BUILD:-build}/tests/$(basename "$t").log" ;; # scripts live in tests/
    *) log="$t.log" ;;
  esac
  start=$(date +%s)
  if "$t" >"$log" 2>&1; then
    pass=$((pass + 1)); status=ok
  else
    fail=$((fail + 1)); status=FAIL; failed="$failed $t"
  fi
  printf '%-5s %-48s %4ss\n' "$status" "$(basename "$t")" "$(( $(date +%s) - start ))"
done
for t in $failed; do
  case "$t" in *.sh) log="${GRAN_BUILD:-build}/tests/$(basename "$t").log" ;; *) log="$t.log" ;; esac
  echo "---- $log (last 40 lines)"; tail -n 40 "$log"
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
