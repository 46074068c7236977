#!/bin/sh
# t614-mpi-decompose.sh - one GSRD gas split over MPI processes (`granary decompose`,
# src/cli/decompose.cpp, src/cli/mpi.cpp, src/srd/bricks.cpp: one brick per process, no process
# holding more). For every scene below (2-D and 3-D; periodic with eps < 1 and clamped cells;
# Lees-Edwards with the global thermostat and a body force; the cell thermostat; no-slip walls,
# gravity and the vibrating wall; slip walls with gravity on two axes and eps < 1) the digests of
# the final state (every particle's position and velocity bits, every cell's V and RNG state),
# the momentum, the energy ledger and the cell observables (gran_srd_observe's theta_cells, E_kin,
# Mach, sigma_rho, a2, stress: each process gathers the particles of its unshifted cells) are the
# same BIT FOR BIT on 1, 2, 3 and 4 processes, on
# several splits, in one process with virtual bricks, and in the undivided engine (--reference).
# Physics on every run: the particle count is the scene's, the ledger closes (kinetic energy =
# initial + collisions + external work, to 1e-12 of the initial energy), the momentum of a
# periodic gas without forces, shear or thermostat stays 0 (to 1e-12 of sum |v|); particles
# change brick (the exchange is exercised); rows of the global observables every K steps are the
# same on every split, close the ledger and cool the inelastic gas; particles faster than a brick per step reach bricks
# beyond the neighbouring ones (any process may send to any); a process killed during the steps
# ends the run on every process within 30 s, the rank named; one stopped (SIGSTOP, alive but not
# answering) ends it after --timeout, said so, also while the others are inside FFTW's transform.
# Bad input: each refusal names what was wrong (a split's memory beyond the machine's included),
# once (a process whose error differs from rank 0's adds its own, named).
# Skips (exit 0, saying so) only when MPI is not installed (no mpirun or no build/granary-mpi).
set -eu
name=t614
. "${GRAN_SOURCE_DIR:-.}/tests/mpi_env.sh.inc"
fail=0

# scene NAME DIM CELLS EXTRA...: a GSRD scene of the decomposable engine
scene() {
  name=$1; dim=$2; cells=$3; shift 3
  srd_scene "$tmp/$name.toml" "$dim" "$cells" "steps = 24" "sort_every = 5" "alpha = 120" "$@"
}
scene periodic3 3 "[7, 6, 5]" "n0 = 5" "dt = 0.6" "eps = 0.7" "sigma = 0.6" "seed = 3"
scene shear2 2 "[9, 8]" "n0 = 6" "dt = 0.4" "seed = 11" "thermostat = \"global\"" \
  "[boundaries]" "lees_edwards = {shear_rate = 0.05}" "[forces]" "body_force = [0.001, 0]"
scene shear3 3 "[6, 6, 5]" "n0 = 4" "dt = 0.5" "eps = 0.9" "sigma = 0.3" "seed = 5" \
  "[boundaries]" "lees_edwards = {shear_rate = 0.1}"
scene thermo2 2 "[10, 7]" "n0 = 8" "dt = 0.5" "seed = 2" "thermostat = \"cell\""
scene walls2 2 "[8, 9]" "n0 = 6" "dt = 0.5" "seed = 9" \
  "[boundaries]" "walls = {axis = \"y\", rule = \"no-slip\", T = 0.5}" "vibrating_wall = {amplitude = 0.1, omega = 0.3}" \
  "[forces]" "gravity = [0, -0.02]"
scene walls3 3 "[5, 4, 6]" "n0 = 4" "dt = 0.5" "eps = 0.95" "sigma = 0.2" "T0 = 1.5" "seed = 7" \
  "[boundaries]" "walls = {axis = \"z\", rule = \"slip\", T = 0.5}" "vibrating_wall = {amplitude = 0.1, omega = 0.3}" \
  "[forces]" "gravity = [0.005, 0, -0.01]"

# check NAME LABEL JSON_FILE: the report's physics; prints "digests momentum ledger" for comparison
check() {
  python3 - "$1" "$2" "$3" <<'PYEOF' || fail=1
import json, sys
name, label, path = sys.argv[1:4]
r = json.load(open(path))
cells = {"periodic3": 7 * 6 * 5 * 5, "shear2": 9 * 8 * 6, "shear3": 6 * 6 * 5 * 4, "thermo2": 10 * 7 * 8,
         "walls2": 8 * 9 * 6, "walls3": 5 * 4 * 6 * 4}[name]
bad = []
if r["particles"] != cells: bad.append("particles %d, not %d" % (r["particles"], cells))
if r["steps"] != 24 or abs(r["time"] - 24 * {"periodic3": 0.6, "shear2": 0.4}.get(name, 0.5)) > 1e-9:
    bad.append("steps %s, time %s" % (r["steps"], r["time"]))
closure = r["kinetic_energy"] - (r["e_initial"] + r["e_coll"] + r["e_ext"])
if not abs(closure) <= 1e-12 * r["e_initial"]: bad.append("ledger off by %g" % closure)
if name == "periodic3":
    p = max(abs(x) for x in r["momentum"])
    if not p <= 1e-12 * (2 * r["kinetic_energy"] * r["particles"]) ** 0.5: bad.append("momentum %g" % p)
    if r["clamped"] <= 0: bad.append("no clamped cell (the test wants clamps)")
if r["processes"] > 1 and r["particles_sent"] <= 0: bad.append("no particle changed brick")
# the cell observables: the unshifted cells whole on their process (sum |v|^2 = d N theta + N E_kin),
# theta_cells <= T, the ledger closed
ob, N, d = r["observables"], r["particles"], 2 if name.endswith("2") else 3
two_e = 2 * r["kinetic_energy"]
if not abs(two_e - (d * N * ob["theta_cells"] + N * ob["E_kin"])) <= 1e-12 * two_e:
    bad.append("sum |v|^2 %r, d N theta + N E_kin %r" % (two_e, d * N * ob["theta_cells"] + N * ob["E_kin"]))
if not ob["theta_cells"] <= ob["T"] * (1 + 1e-12): bad.append("theta_cells %r > T %r" % (ob["theta_cells"], ob["T"]))
if not abs(ob["ledger_error"]) < 1e-12: bad.append("ledger_error %r" % ob["ledger_error"])
if bad:
    print("FAIL: %s %s: %s" % (name, label, "; ".join(bad)))
    sys.exit(1)
print(r["digest_particles"], r["digest_cells"], repr(r["momentum"]), repr(r["kinetic_energy"]), repr(r["e_coll"]),
      repr(r["e_ext"]), repr(r["flux_kin"]), repr(r["flux_coll"]), repr(r["wall_impulse"]), r["clamped"],
      json.dumps(ob, sort_keys=True))
PYEOF
}

runs=0
for name in periodic3 shear2 shear3 thermo2 walls2 walls3; do
  f="$tmp/$name.toml"
  dim=3
  case $name in *2) dim=2 ;; esac
  if ! "$cli" decompose "$f" --reference --json > "$tmp/ref.json" 2> "$tmp/err"; then
    echo "FAIL: $name: the undivided engine and one brick differ or the run failed: $(cat "$tmp/err")"
    fail=1
    continue
  fi
  ref=$(check "$name" "one brick" "$tmp/ref.json")
  if [ "$dim" = 3 ]; then
    local_splits="2x1x1 1x3x1 2x2x1 3x2x1"
    mpi_splits="1:1x1x1 2:2x1x1 2:1x1x2 3:1x3x1 3:3x1x1 4:2x1x2 4:1x2x2 4:auto"
  else
    local_splits="2x1 1x3 2x2 3x2"
    mpi_splits="1:1x1 2:2x1 2:1x2 3:3x1 3:1x3 4:2x2 4:4x1 4:auto"
  fi
  for b in $local_splits; do
    if ! "$cli" decompose "$f" --bricks "$b" --json > "$tmp/o.json" 2> "$tmp/err"; then
      echo "FAIL: $name in one process, bricks $b: $(cat "$tmp/err")"; fail=1; continue
    fi
    got=$(check "$name" "bricks $b in one process" "$tmp/o.json")
    [ "$got" = "$ref" ] || { echo "FAIL: $name, bricks $b in one process: $got, not $ref"; fail=1; }
    runs=$((runs + 1))
  done
  for pb in $mpi_splits; do
    n=${pb%%:*}; b=${pb#*:}
    if ! mpi "$n" decompose "$f" --bricks "$b" --json > "$tmp/o.json" 2> "$tmp/err"; then
      echo "FAIL: $name on $n processes, bricks $b: $(cat "$tmp/err")"; fail=1; continue
    fi
    got=$(check "$name" "$n processes, bricks $b" "$tmp/o.json")
    [ "$got" = "$ref" ] || { echo "FAIL: $name on $n processes, bricks $b: $got, not $ref"; fail=1; }
    runs=$((runs + 1))
  done
done
echo "t614: $runs split runs compared with the undivided engine"

# particles that stream beyond the neighbouring bricks (dt = 4 on bricks 4 cells wide): messages
# go to bricks beyond the neighbouring ones, the digests are the undivided engine's
printf '[engine]\ntype = "srd"\ndimension = 2\ncells = [16, 4]\nn0 = 5\ndt = 4\nsteps = 20\ncreation = "cells"\nseed = 4\n' > "$tmp/fast.toml"
"$cli" decompose "$tmp/fast.toml" --reference --json > "$tmp/ref.json"
mpi 4 decompose "$tmp/fast.toml" --bricks 4x1 --json > "$tmp/o.json"
python3 - "$tmp/ref.json" "$tmp/o.json" <<'PYEOF' || fail=1
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
bad = [k for k in ("digest_particles", "digest_cells", "momentum", "kinetic_energy", "e_coll") if a[k] != b[k]]
if bad or not b["messages_beyond_neighbours"] > 0:
    print("FAIL: fast particles on 4 processes: differ in %s; %s messages beyond the neighbours" % (bad, b["messages_beyond_neighbours"]))
    sys.exit(1)
PYEOF

# rows every 7 steps (--every): the same on every split and process count, the final state the
# unchunked run's; each row's ledger closes, its temperature is (2 E - |P|^2 / N) / (d N), and
# the inelastic gas cools
"$cli" decompose "$tmp/periodic3.toml" --every 7 --json > "$tmp/rows1.json"
"$cli" decompose "$tmp/periodic3.toml" --every 7 --bricks 3x2x1 --json > "$tmp/rows2.json"
mpi 3 decompose "$tmp/periodic3.toml" --every 7 --bricks 1x3x1 --json > "$tmp/rows3.json"
"$cli" decompose "$tmp/periodic3.toml" --json > "$tmp/rows0.json"
python3 - "$tmp/rows0.json" "$tmp/rows1.json" "$tmp/rows2.json" "$tmp/rows3.json" <<'PYEOF' || fail=1
import json, sys
r0, r1, r2, r3 = (json.load(open(p)) for p in sys.argv[1:5])
bad = []
if not (r1["rows"] == r2["rows"] == r3["rows"]): bad.append("rows differ between splits")
if [w["step"] for w in r1["rows"]] != [0, 7, 14, 21, 24]: bad.append("row steps %s" % [w["step"] for w in r1["rows"]])
for k in ("digest_particles", "digest_cells", "e_coll", "kinetic_energy", "temperature"):
    if r1[k] != r0[k]: bad.append("%s with --every %s, without %s" % (k, r1[k], r0[k]))
N, d = r1["particles"], 3
for w in r1["rows"]:
    closure = w["kinetic_energy"] - (r1["e_initial"] + w["e_coll"] + w["e_ext"])
    if not abs(closure) <= 1e-12 * r1["e_initial"]: bad.append("row %d ledger off by %g" % (w["step"], closure))
    p2 = sum(x * x for x in w["momentum"])
    T = (2 * w["kinetic_energy"] - p2 / N) / (d * N)
    if not abs(T - w["temperature"]) <= 1e-12 * T: bad.append("row %d T %r, from E and P %r" % (w["step"], w["temperature"], T))
Ts = [w["temperature"] for w in r1["rows"]]
if not Ts[-1] < 0.5 * Ts[0]: bad.append("the eps = 0.7 gas did not cool: T %s" % Ts)
if bad:
    print("FAIL: rows: " + "; ".join(bad))
    sys.exit(1)
PYEOF

# S(k) of the split gas (--sk): the undivided engine's bit for bit (--reference checks it, exit 1
# otherwise), all modes in the shells, and the same bits on every split in one process and on
# 2, 3, 4 processes (FFTW's MPI transform over slabs of the last axis: the counts of the bricks'
# cells are sent to the slab that holds them), at every row too; periodic 3-D with eps < 1,
# 3-D Lees-Edwards (particles whose unshifted cell lies across the sheared boundary), 2-D
# Lees-Edwards and 2-D with the cell thermostat; 4 processes on 5 layers leave one without a slab
# (granary-mpi built without FFTW's MPI interface refuses S(k) on several processes: those runs are
# skipped, saying so; make deps and CI install it)
sk_mpi=1
if ! mpi 2 decompose "$tmp/periodic3.toml" --steps 0 --sk 2 > /dev/null 2> "$tmp/err"; then
  if grep -q "built without it" "$tmp/err"; then
    echo "SKIP: S(k) on several processes: granary-mpi was built without FFTW's MPI interface (libfftw3-mpi-dev)"
    sk_mpi=0
  else
    echo "FAIL: S(k) on 2 processes: $(cat "$tmp/err")"; fail=1
  fi
fi
for name in periodic3 shear3 shear2 thermo2; do
  "$cli" decompose "$tmp/$name.toml" --sk 9 --every 8 --reference --json > "$tmp/sk-ref.json" 2> "$tmp/err" ||
    { echo "FAIL: S(k) of $name: not the undivided engine's, or the run failed: $(cat "$tmp/err")"; fail=1; }
  case $name in *3) splits="1:2x2x1 2:2x1x1 3:1x3x1 4:1x2x2 4:4x1x1" ;; *) splits="1:3x2 2:1x2 3:3x1 4:2x2" ;; esac
  for pb in $splits; do
    n=${pb%%:*}; b=${pb#*:}
    if [ "$n" = 1 ]; then run="$cli"; else run="mpi $n"; [ $sk_mpi = 1 ] || continue; fi
    $run decompose "$tmp/$name.toml" --sk 9 --every 8 --bricks "$b" --json > "$tmp/sk.json" 2> "$tmp/err" ||
      { echo "FAIL: S(k) of $name on $n processes, bricks $b: the run failed: $(cat "$tmp/err")"; fail=1; continue; }
    python3 - "$tmp/sk-ref.json" "$tmp/sk.json" "$name $n x $b" <<'PYEOF' || fail=1
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
bad = []
if a["reference_sk_max_rel_diff"] != 0: bad.append("the undivided engine's S(k) differs by %g" % a["reference_sk_max_rel_diff"])
cells = {"periodic3": 7 * 6 * 5, "shear3": 6 * 6 * 5, "shear2": 9 * 8, "thermo2": 10 * 7}[sys.argv[3].split()[0]]
if sum(a["sk"]["count"]) != cells - 1: bad.append("%d modes in the shells, not %d" % (sum(a["sk"]["count"]), cells - 1))
if a["sk"] != b["sk"]: bad.append("S(k) %s, not %s" % (b["sk"]["s"], a["sk"]["s"]))
if [w["sk"] for w in a["rows"]] != [w["sk"] for w in b["rows"]]: bad.append("the rows' S(k) differ")
if [w["step"] for w in a["rows"]] != [0, 8, 16, 24] or any(len(w["sk"]) != 9 for w in a["rows"]): bad.append("rows %d" % len(a["rows"]))
if bad:
    print("FAIL: S(k), %s: %s" % (sys.argv[3], "; ".join(bad)))
    sys.exit(1)
PYEOF
  done
done
expect_sk() { # the refusals of --sk (after expect is defined below)
  expect 2 "S(k) needs a periodic box" -- "$cli" decompose "$tmp/walls2.toml" --sk 8
  expect 2 "--sk '0'" -- "$cli" decompose "$tmp/periodic3.toml" --sk 0
  expect 2 "--sk '4097'" -- "$cli" decompose "$tmp/periodic3.toml" --sk 4097
  expect 2 "S(k) needs a periodic box" -- mpi 2 decompose "$tmp/walls3.toml" --sk 8
}

# the default split on P processes is the automatic one: one brick each
mpi 2 decompose "$tmp/periodic3.toml" --json > "$tmp/o.json"
python3 -c "import json,sys; r=json.load(open(sys.argv[1])); b=r['bricks']; sys.exit(0 if b[0]*b[1]*b[2]==2 and r['processes']==2 and r['brick_particles_min']>0 else 1)" "$tmp/o.json" ||
  { echo "FAIL: the default split on 2 processes: $(cat "$tmp/o.json")"; fail=1; }

# a process killed during the steps: every process stops, and mpirun names the one that died
cp "$tmp/periodic3.toml" "$tmp/kill.toml"
( if mpi 2 decompose "$tmp/kill.toml" --steps 100000000 > "$tmp/kill.out" 2> "$tmp/kill.err"; then echo 0; else echo $?; fi \
    > "$tmp/kill.rc" ) &
victim=$(rank1_pid "decompose $tmp/kill.toml")
t0=$(date +%s)
[ -n "$victim" ] && kill -9 "$victim"
wait
dt=$(( $(date +%s) - t0 ))
if [ -z "$victim" ] || [ "$(cat "$tmp/kill.rc")" = 0 ] || [ $dt -gt 30 ] || ! grep -q "rank" "$tmp/kill.err"; then
  echo "FAIL: a killed process: exit $(cat "$tmp/kill.rc" 2>/dev/null) after ${dt} s (want non-zero within 30 s, naming the rank): $(cat "$tmp/kill.err")"
  fail=1
fi

# a process that stops answering without dying (SIGSTOP): the others wait at most --timeout in the
# exchange, then stop every process (naming the one that does not answer when it holds a message of
# theirs; one that has sent everything cannot tell which process is missing). Where the wait is
# inside MPI itself (FFTW's collective calls of the transform, a message stopped halfway) the
# watchdog thread ends it a second later with the same message.
# stopped LABEL TOML ARGS...: rank 1 of `decompose TOML --timeout 2 ARGS` stopped once the steps
# have begun (a progress line: a process stopped inside MPI_Init would hold the others there, where
# no timeout reaches); the run must end within 30 s, said so
stopped() {
  label=$1; toml=$2; shift 2
  ( if mpi 2 decompose "$toml" --timeout 2 --progress 0.01 "$@" > "$tmp/hang.out" 2> "$tmp/hang.err";
    then echo 0; else echo $?; fi > "$tmp/hang.rc" ) &
  signal_rank1 STOP "decompose $toml" "grep -q 'granary decompose: step' '$tmp/hang.err' 2>/dev/null" $!
  if [ -z "$victim" ] || [ "$(cat "$tmp/hang.rc" 2>/dev/null)" = 0 ] || [ $dt -gt 30 ] ||
     ! grep -q "granary-mpi: rank [01]: waited [0-9]* s in .* for .*stopping every process (the limit: --timeout 2)" "$tmp/hang.err"; then
    echo "FAIL: $label: exit $(cat "$tmp/hang.rc" 2>/dev/null) after ${dt} s (want non-zero within 30 s, naming the rank): $(cat "$tmp/hang.err")"
    fail=1
  fi
}
cp "$tmp/periodic3.toml" "$tmp/hang.toml"
stopped "a stopped process" "$tmp/hang.toml" --steps 100000000
# an S(k) every step of a sparse 40^3 gas: the survivor often waits inside FFTW's transform (without
# the watchdog about half of these runs held it until killed)
if [ $sk_mpi = 1 ]; then
  scene sparse3 3 "[40, 40, 40]" "n0 = 1" "dt = 0.5" "seed = 4"
  stopped "a process stopped during the S(k) transforms" "$tmp/sparse3.toml" --steps 100000 --every 1 --sk 64
fi
# --timeout takes seconds >= 0
if "$cli" decompose "$tmp/periodic3.toml" --timeout -1 > /dev/null 2> "$tmp/to.err" || ! grep -q "\-\-timeout '-1'" "$tmp/to.err"; then
  echo "FAIL: --timeout -1 not refused: $(cat "$tmp/to.err")"
  fail=1
fi

# a scene that one process cannot read: every process stops before the first exchange, the
# message names the file
cat > "$tmp/one-rank.sh" <<EOF2
#!/bin/sh
if [ "\$OMPI_COMM_WORLD_RANK" = 1 ]; then exec "$mpicli" decompose "$tmp/absent.toml"; fi
exec "$mpicli" decompose "$tmp/periodic3.toml" --steps 3
EOF2
chmod +x "$tmp/one-rank.sh"
set +e
timeout 60 mpirun --oversubscribe -n 2 "$tmp/one-rank.sh" > "$tmp/one.out" 2> "$tmp/one.err"
rc=$?
set -e
if [ $rc = 0 ] || [ $rc = 124 ] || ! grep -q "^process 1: granary decompose: invalid scene: .*absent.toml" "$tmp/one.err"; then
  echo "FAIL: a scene one process cannot read: exit $rc (want non-zero, not the timeout, process 1 named), stderr: $(cat "$tmp/one.err")"
  fail=1
fi
# an error every process meets before the steps is said once (by rank 0), not once per process
set +e
mpi 3 decompose "$tmp/absent.toml" > "$tmp/one.out" 2> "$tmp/one.err"
rc=$?
set -e
if [ $rc = 0 ] || [ "$(grep -c "absent.toml" "$tmp/one.err")" != 1 ] || grep -q "^process" "$tmp/one.err"; then
  echo "FAIL: an unreadable scene on 3 processes: exit $rc (want non-zero, the message once), stderr: $(cat "$tmp/one.err")"
  fail=1
fi

# refusals: exit status and a message naming what was wrong
expect() { # expect STATUS WORDS -- command...: fails unless the command exits STATUS with WORDS on stderr
  want=$1; words=$2; shift 3
  set +e
  "$@" > "$tmp/out" 2> "$tmp/err"
  got=$?
  set -e
  if [ "$got" != "$want" ] || ! grep -q -- "$words" "$tmp/err"; then
    echo "FAIL: '$*': exit $got (want $want), stderr: $(cat "$tmp/err") (want '$words')"
    fail=1
  fi
}
printf '[engine]\ntype = "srd"\ncells = [4, 4, 4]\nsteps = 2\n' > "$tmp/serial.toml"
printf '[engine]\ntype = "srd"\ncells = [4, 4, 4]\nsteps = 2\ncreation = "cells"\ndevice = "cuda"\n' > "$tmp/cuda.toml"
cp "$src/scenes/default.toml" "$tmp/dsmc.toml"
expect 1 'creation = "cells"' -- "$cli" decompose "$tmp/serial.toml"
expect 1 'device = "cuda"' -- "$cli" decompose "$tmp/cuda.toml"
expect 1 'GSRD scenes' -- "$cli" decompose "$tmp/dsmc.toml"
expect 2 "--bricks '2x0x1'" -- "$cli" decompose "$tmp/periodic3.toml" --bricks 2x0x1
expect 2 "--bricks '2x2'" -- "$cli" decompose "$tmp/periodic3.toml" --bricks 2x2
expect 1 "pgrid\[0\]" -- "$cli" decompose "$tmp/periodic3.toml" --bricks 8x1x1
expect 2 "--steps '-3'" -- "$cli" decompose "$tmp/periodic3.toml" --steps -3
expect 2 "--every '0'" -- "$cli" decompose "$tmp/periodic3.toml" --every 0
expect 2 "--progress 'x'" -- "$cli" decompose "$tmp/periodic3.toml" --progress x
expect_sk
expect 1 "no such file\|cannot\|not found\|open" -- "$cli" decompose "$tmp/absent.toml"
expect 2 "3 bricks for 2 processes" -- mpi 2 decompose "$tmp/periodic3.toml" --bricks 3x1x1
expect 2 "--reference runs in one process" -- mpi 2 decompose "$tmp/periodic3.toml" --reference
# memory: the whole gas need not fit one machine (the scene's own check is left to decompose, which
# checks each process's share); max_memory_gb caps the share
expect 1 "needs about .* GB (all bricks in one process" -- "$cli" decompose "$tmp/periodic3.toml" --bricks 2x1x1 --set engine.cells='[700, 700, 700]'
expect 1 "each process needs about .* GB (its brick" -- mpi 2 decompose "$tmp/periodic3.toml" --set engine.cells='[700, 700, 700]'
expect 1 "each process needs about .* GB (its brick.*more than the 5e-05 GB available to each of the 2 processes" -- mpi 2 decompose "$tmp/periodic3.toml" --set engine.max_memory_gb=0.0001
expect 1 "max_memory_gb" -- "$cli" run "$tmp/periodic3.toml" --set engine.cells='[700, 700, 700]'
expect 1 "the binning grid has 1 cells and a brick needs at least one (processes: at most 1)" -- \
  mpi 2 decompose "$tmp/periodic3.toml" --steps 1 --set engine.cells='[1, 1, 1]'
expect 1 "no split of the binning grid (2 x 2 x 2 cells) into 3 bricks" -- mpi 3 decompose "$tmp/periodic3.toml" --steps 1 --set engine.cells='[2, 2, 2]'

[ $fail = 0 ] && echo "t614: all checks passed"
exit $fail
