#!/bin/sh
# Runs each test program given as an argument, one line per program, its log kept in
# <program>.log; prints the failing logs and closes with "N passed, N failed".
pass=0; fail=0; failed=""
for t in "$@"; do
  log="$t.log"
  start=$(date +%s)
  if "$t" >"$log" 2>&1; then
    pass=$((pass + 1)); status=ok
  else
    fail=$((fail + 1)); status=FAIL; failed="$failed $t"
  fi
  printf '%-5s %-48s %4ss\n' "$status" "$(basename "$t")" "$(( $(date +%s) - start ))"
done
for t in $failed; do
  echo "---- $t.log (last 40 lines)"; tail -n 40 "$t.log"
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
