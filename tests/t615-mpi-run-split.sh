#!/bin/sh
# t615-mpi-run-split.sh - one GSRD gas split over the processes of `granary run`
# ([engine] decomposition, src/io/engine_srd.cpp, src/io/run.cpp, src/srd/bricks.cpp): the output
# file of the scene run on 2, 3 and 4 processes (one brick each) holds the same datasets BIT FOR BIT
# as the run in one process (build/granary: the undivided decomposable engine), for a periodic 3-D
# inelastic gas with a2 and S(k) (FFTW's MPI transform), 2-D Lees-Edwards with the global
# thermostat, the stress (the stress window reset at every output time) and the velocity profile
# (exact layer sums), 2-D no-slip walls with gravity, the vibrating wall and eps < 1 with clamped
# cells, and 3-D slip walls with gravity and eps < 1 (sigma_rho over the box cells), the last two
# with field snapshots (gathered on rank 0; their XDMF sidecar the same too); an explicit
# split too, and replicas of a split gas (2 replicas on 4 processes, each gas on 2: the threaded
# replicas' output, per-replica rows, means and standard errors). Physics on the outputs: the
# energy ledger closes at every output time (ledger_error < 1e-12), the inelastic gas cools, the
# clamps are counted. A process stopped (SIGSTOP) during the steps ends the run within the
# timeout, named; one killed ends it. Refusals, each naming its key or option, said once: a split
# whose bricks are not the process count, replicas that do not divide the processes. (Checkpoints
# of a split gas: t616.)
# Skips (exit 0, saying so) only when MPI is not installed (no mpirun or no build/granary-mpi).
set -eu
name=t615
. "${GRAN_SOURCE_DIR:-.}/tests/mpi_env.sh.inc"
fail=0
cc $(pkg-config --cflags hdf5) "${GRAN_SOURCE_DIR:-.}/tests/h5same.c" -o "$tmp/h5same" $(pkg-config --libs hdf5)

# scene NAME DIM CELLS EXTRA...: a split GSRD scene ([observables] lines after a "[observables]" entry)
scene() {
  name=$1; dim=$2; cells=$3; shift 3
  srd_scene "$tmp/$name.toml" "$dim" "$cells" 'decomposition = "auto"' "steps = 30" "sort_every = 7" "$@"
}
scene periodic3 3 "[9, 8, 7]" "n0 = 5" "dt = 0.5" "eps = 0.8" "sigma = 0.4" "seed = 21" \
  "[observables]" "every = 6" "sonine_a2 = true" "structure_factor = {bins = 6}"
scene shear2 2 "[10, 9]" "n0 = 6" "dt = 0.4" "seed = 11" "thermostat = \"global\"" \
  "[boundaries]" "lees_edwards = {shear_rate = 0.05}" "[observables]" "every = 5" "structure_factor = true" \
  "velocity_profile = true"
scene walls2 2 "[8, 9]" "n0 = 6" "dt = 1.0" "eps = 0.5" "sigma = 0.5" "seed = 9" \
  "[boundaries]" "walls = {axis = \"y\", rule = \"no-slip\", T = 0.5}" "vibrating_wall = {amplitude = 0.1, omega = 0.3}" \
  "[forces]" "gravity = [0, -0.02]" "[observables]" "every = 10" "snapshots = {every = 1}"
scene walls3 3 "[5, 4, 6]" "n0 = 4" "dt = 0.5" "eps = 0.95" "sigma = 0.2" "seed = 7" \
  "[boundaries]" "walls = {axis = \"z\", rule = \"slip\", T = 0.5}" "[forces]" "gravity = [0.005, 0, -0.01]" \
  "[observables]" "every = 10" "sonine_a2 = true" "snapshots = {every = 2}"

# ledger NAME FILE: every output time's ledger_error below 1e-12 (h5dump's text of the dataset)
ledger() {
  h5dump -d /energy/ledger_error -y -w 0 "$2" > "$tmp/dump" 2>&1 || { echo "FAIL: $1: no /energy/ledger_error in $2"; fail=1; return; }
  python3 - "$1" "$tmp/dump" <<'PYEOF' || fail=1
import re, sys
text = open(sys.argv[2]).read().split("DATA {", 1)[1].split("}", 1)[0]
v = [float(x) for x in re.findall(r"[-+]?\d[\d.]*(?:e[-+]?\d+)?", text)]
if not v or max(abs(x) for x in v) >= 1e-12:
    print("FAIL: %s: ledger_error %s" % (sys.argv[1], v))
    sys.exit(1)
PYEOF
}

for name in periodic3 shear2 walls2 walls3; do
  f="$tmp/$name.toml"
  if ! "$cli" run "$f" -o "$tmp/$name-1.h5" --no-checkpoint --no-log -q > /dev/null 2> "$tmp/err"; then
    echo "FAIL: $name in one process: $(cat "$tmp/err")"; fail=1; continue
  fi
  ledger "$name" "$tmp/$name-1.h5"
  for n in 2 3 4; do
    if ! mpi "$n" run "$f" -o "$tmp/$name-$n.h5" --no-checkpoint --no-log -q > /dev/null 2> "$tmp/err"; then
      echo "FAIL: $name on $n processes: $(cat "$tmp/err")"; fail=1; continue
    fi
    "$tmp/h5same" "$tmp/$name-1.h5" "$tmp/$name-$n.h5" > "$tmp/same" || { echo "FAIL: $name on $n processes:"; cat "$tmp/same"; fail=1; }
    # the snapshots' XDMF sidecar: the same but for the file it names
    if [ -f "$tmp/$name-1.xmf" ]; then
      sed "s/$name-1\.h5/OUT/" "$tmp/$name-1.xmf" > "$tmp/a.xmf"
      sed "s/$name-$n\.h5/OUT/" "$tmp/$name-$n.xmf" > "$tmp/b.xmf" 2>/dev/null || true
      cmp -s "$tmp/a.xmf" "$tmp/b.xmf" || { echo "FAIL: $name on $n processes: the XDMF sidecar differs"; fail=1; }
    fi
  done
done
# the 2-D inelastic gas between walls clamps its cells' restitution (the test wants clamps)
h5dump -d /clamps/count -y -w 0 "$tmp/walls2-1.h5" > "$tmp/dump"
python3 - "$tmp/dump" <<'PYEOF' || fail=1
import re, sys
v = [int(x) for x in re.findall(r"\d+", open(sys.argv[1]).read().split("DATA {", 1)[1].split("}", 1)[0])]
if not sum(v) > 0:
    print("FAIL: walls2: no clamped cell (%s)" % v)
    sys.exit(1)
PYEOF
# an explicit split (bricks along y and z) on 4 processes
mpi 4 run "$tmp/periodic3.toml" --set 'engine.decomposition=[1, 2, 2]' -o "$tmp/grid.h5" --no-checkpoint --no-log -q \
  > /dev/null 2> "$tmp/err" || { echo "FAIL: decomposition [1, 2, 2] on 4 processes: $(cat "$tmp/err")"; fail=1; }
"$tmp/h5same" "$tmp/periodic3-1.h5" "$tmp/grid.h5" > "$tmp/same" || { echo "FAIL: decomposition [1, 2, 2]:"; cat "$tmp/same"; fail=1; }
# replicas of a split gas: 2 replicas on 4 processes (each gas split over 2) and on 2 (one process
# each) write the threaded one-process run's replicas, means and standard errors
"$cli" run "$tmp/periodic3.toml" --replicas 2 --set engine.keep_replicas=true -o "$tmp/rep-1.h5" --no-checkpoint \
  --no-log -q > /dev/null 2> "$tmp/err" || { echo "FAIL: 2 replicas in one process: $(cat "$tmp/err")"; fail=1; }
for n in 2 4; do
  mpi "$n" run "$tmp/periodic3.toml" --replicas 2 --set engine.keep_replicas=true -o "$tmp/rep-$n.h5" --no-checkpoint \
    --no-log -q > /dev/null 2> "$tmp/err" || { echo "FAIL: 2 replicas on $n processes: $(cat "$tmp/err")"; fail=1; }
  "$tmp/h5same" "$tmp/rep-1.h5" "$tmp/rep-$n.h5" > "$tmp/same" || { echo "FAIL: 2 replicas on $n processes:"; cat "$tmp/same"; fail=1; }
done
# the inelastic gas cools (T at the last output time below half the first)
h5dump -d /temperature/T -y -w 0 "$tmp/periodic3-2.h5" > "$tmp/dump"
python3 - "$tmp/dump" <<'PYEOF' || fail=1
import re, sys
v = [float(x) for x in re.findall(r"[-+]?\d[\d.]*(?:e[-+]?\d+)?", open(sys.argv[1]).read().split("DATA {", 1)[1].split("}", 1)[0])]
if not (len(v) == 6 and v[-1] < 0.5 * v[0]):
    print("FAIL: the split eps = 0.8 gas did not cool: T %s" % v)
    sys.exit(1)
PYEOF

p3="$tmp/periodic3.toml"
expect 1 "'engine.decomposition' = [2, 1, 1] has 2 bricks, and this run has 1 process" -- \
  "$cli" run "$p3" --set 'engine.decomposition=[2, 1, 1]' -o "$tmp/x.h5" --no-checkpoint --no-log -q
expect 1 "has 2 bricks, and this run has 3 process" -- \
  mpi 3 run "$p3" --set 'engine.decomposition=[2, 1, 1]' -o "$tmp/x.h5" --no-checkpoint --no-log -q
expect 1 "2 replicas of a gas split over the processes ([engine] decomposition) need a multiple of 2 processes" -- \
  mpi 3 run "$p3" --replicas 2 -o "$tmp/x.h5" --no-checkpoint --no-log -q
expect 1 "give [engine] creation = \"cells\"" -- \
  "$cli" run "$p3" --set 'engine.creation="serial"' -o "$tmp/x.h5" --no-checkpoint --no-log -q
expect 1 "expected \"none\", \"auto\" or [Px, Py(, Pz)]" -- \
  "$cli" run "$p3" --set 'engine.decomposition="some"' -o "$tmp/x.h5" --no-checkpoint --no-log -q
# a process stopped (SIGSTOP) or killed during the steps: every process ends within 30 s, the one
# that does not answer named (stopped) or mpirun's report of the dead one (killed); the run's log
# row (--log-every 1) says the steps have begun
long="$tmp/long.toml"
sed -e 's/^steps = 30/steps = 100000000/' -e 's/^every = 6/every = 20/' -e '/structure_factor/d' "$p3" > "$long"
split_stop() {
  sig=$1
  rm -f "$tmp/long.log"
  ( if mpi 2 run "$long" -o "$tmp/long.h5" --no-checkpoint --log "$tmp/long.log" --log-every 1 -q --force \
         --timeout 2 > "$tmp/hang.out" 2> "$tmp/hang.err"; then echo 0; else echo $?; fi > "$tmp/hang.rc" ) &
  signal_rank1 "$sig" "run $long" "[ \"\$(grep -c '^ *[0-9]' '$tmp/long.log' 2>/dev/null || true)\" -ge 2 ]" $!
  want="granary-mpi: rank [01]: waited [0-9]* s in .*stopping every process (the limit: --timeout 2)"
  [ "$sig" = KILL ] && want="rank"
  if [ -z "$victim" ] || [ "$(cat "$tmp/hang.rc" 2>/dev/null)" = 0 ] || [ $dt -gt 30 ] || ! grep -q "$want" "$tmp/hang.err"; then
    echo "FAIL: a split run's process got SIG$sig: exit $(cat "$tmp/hang.rc" 2>/dev/null) after ${dt} s (want non-zero within 30 s, said): $(cat "$tmp/hang.err")"
    fail=1
  fi
}
split_stop STOP
split_stop KILL

[ $fail = 0 ] && echo "t615: all checks passed"
exit $fail
