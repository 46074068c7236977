#!/bin/sh
# t611-mpi.sh - replicas over MPI processes (build/granary-mpi, src/cli/mpi.cpp, src/io/run_comm.h):
# a scene of 5 replicas run on 2 and 3 processes gives output datasets equal BIT FOR BIT to the
# threaded run (every dataset of the file, X, X_se and X_replicas included, compared byte for
# byte by a small HDF5 program built here); a run stopped after 2 checkpoints on 2 processes and
# resumed on 3 (and one resumed without MPI) also; more processes than replicas (idle ranks)
# also; an error on rank 0 (output not writable) ends every process with one message; a process
# that stops answering (SIGSTOP) ends the run after `--timeout`, named.
# Skips (exit 0, saying so) only when MPI is not installed (no mpirun or no build/granary-mpi).
set -eu
name=t611
. "${GRAN_SOURCE_DIR:-.}/tests/mpi_env.sh.inc"

# h5same A B: the same datasets in both files, each with the same shape, type and bytes
cc $(pkg-config --cflags hdf5) "${GRAN_SOURCE_DIR:-.}/tests/h5same.c" -o "$tmp/h5same" $(pkg-config --libs hdf5)
same() { "$tmp/h5same" "$tmp/$1" "$tmp/$2"; }

cat > "$tmp/ens.toml" <<'TEOF'
title = "t611: binary mixture, 5 replicas"
[mixture]
nspecies = 2
mass = [1.0, 4.0]
sigma = [1.0, 1.0]
density = [0.1, 0.05]
[restitution]
model = "constant"
eps = 0.8
[initial]
temperatures = "equal"
T_mean = 1.0
[engine]
selector = "lowrank"
counts = [400, 200]
seed = 7
t_end = 40
replicas = 5
keep_replicas = true
[observables]
times = { log = { start = 0.1, stop = 40, n = 12 } }
temperatures = true
msd = true
energy = true
collision_counts = true
[output]
path = "ens.h5"
checkpoint_every = 3
checkpoint_interval = 0
TEOF
cd "$tmp"
"$cli" run ens.toml -o thr.h5 --threads 2 --quiet
# the comparison sees a difference: another seed differs
sed 's/^seed = 7/seed = 8/' ens.toml > seed8.toml
"$cli" run seed8.toml -o seed8.h5 --threads 2 --quiet
if same thr.h5 seed8.h5 > cmp.log; then echo "FAIL: the comparison did not see another seed"; exit 1; fi
echo "ok: the comparison tells seed 7 from seed 8 ($(grep -c 'values differ' cmp.log) datasets differ)"
mpi 2 run ens.toml -o p2.h5 --quiet
same thr.h5 p2.h5
mpi 3 run ens.toml -o p3.h5 --quiet
same thr.h5 p3.h5
# checkpoints hold every replica whatever P: stop on 2 processes, resume on 3, and without MPI
mpi 2 run ens.toml -o s23.h5 --quiet --stop-after-checkpoints 2 >/dev/null 2>&1
[ -f s23.h5.ckpt ] && [ ! -f s23.h5 ] || { echo "FAIL: the stopped run left no checkpoint"; exit 1; }
mpi 3 run --resume s23.h5.ckpt --quiet
same thr.h5 s23.h5
mpi 3 run ens.toml -o s30.h5 --quiet --stop-after-checkpoints 1 >/dev/null 2>&1
"$cli" run --resume s30.h5.ckpt --quiet
same thr.h5 s30.h5
# fewer replicas than processes: the idle rank waits, the result is the threaded one
"$cli" run ens.toml -o thr2.h5 --replicas 2 --no-checkpoint --quiet
mpi 3 run ens.toml -o p3r2.h5 --replicas 2 --no-checkpoint --quiet
same thr2.h5 p3r2.h5
# an error on rank 0 (the output's folder is a file) ends every process, with one message
: > notafolder
if mpi 3 run ens.toml -o notafolder/out.h5 --quiet > err.log 2>&1; then echo "FAIL: an unwritable output was accepted"; exit 1; fi
n=$(grep -c "granary run: run failed:.*notafolder" err.log || true)
[ "$n" = 1 ] || { echo "FAIL: expected the error once, got $n times:"; cat err.log; exit 1; }
echo "ok: unwritable output on rank 0 ends all 3 processes, message printed once"
# a process that stops answering without dying (SIGSTOP on rank 1): rank 0 waits at most --timeout
# in the gather of the replicas' output, names rank 1 and stops every process; --timeout takes
# seconds >= 0
( if mpi 2 run ens.toml -o hang.h5 --quiet --no-checkpoint --replicas 2 --timeout 2 --set restitution.eps=1 \
      --set engine.t_end=1e5 --set 'observables.times={linear = {start = 1, stop = 1e5, n = 10000}}' > hang.out 2> hang.err;
  then echo 0; else echo $?; fi > hang.rc ) &
runner=$!
victim=$(rank1_pid "run ens.toml -o hang.h5")
t0=$(date +%s)
[ -n "$victim" ] && kill -STOP "$victim"
( sleep 60; kill -9 "$victim" 2>/dev/null ) & # a missing timeout fails the test instead of hanging it
watchdog=$!
wait "$runner" || true
dt=$(( $(date +%s) - t0 ))
kill "$watchdog" 2>/dev/null || true
kill -9 "$victim" 2>/dev/null || true
if [ -z "$victim" ] || [ "$(cat hang.rc 2>/dev/null)" = 0 ] || [ $dt -gt 30 ] ||
   ! grep -q "granary-mpi: rank 0: waited [0-9]* s in the gather of the replicas' output for rank 1, which does not answer .*(the limit: --timeout 2)" hang.err; then
  echo "FAIL: a stopped process: exit $(cat hang.rc 2>/dev/null) after ${dt} s (want non-zero within 30 s, naming rank 1): $(cat hang.err)"
  exit 1
fi
[ ! -f hang.h5 ] || { echo "FAIL: the stopped run left hang.h5"; exit 1; }
echo "ok: a stopped process ends the run after --timeout 2 (in ${dt} s), rank 1 named"
if "$cli" run ens.toml -o x.h5 --timeout -1 > /dev/null 2> to.err || ! grep -q "\-\-timeout '-1'" to.err; then
  echo "FAIL: --timeout -1 not refused: $(cat to.err)"; exit 1
fi
echo "9 passed, 0 failed"
