#!/bin/sh
# t616-mpi-checkpoint-split.sh - checkpoints of a GSRD gas split over the processes of `granary run`
# (the checkpoint set: one part file per process, committed by the run's checkpoint; src/io/engine_srd.cpp,
# src/srd/bricks.cpp, src/srd/checkpoint.cpp). A run on 2 processes stopped after its second
# checkpoint leaves the checkpoint and the 2 parts of that generation (the first generation's gone);
# resumed in one process (the parts merged by key), on 2 (each process its own part) and on 3 (each
# process reads every part and keeps its brick's share), its output holds the same datasets BIT FOR
# BIT as the uninterrupted run in one process, for a periodic 3-D inelastic gas with a2 and S(k),
# 2-D Lees-Edwards with the global thermostat, the stress and the velocity profile, and 2-D no-slip
# walls with gravity, the vibrating wall, clamped cells and field snapshots (those recorded before
# the checkpoint kept in it); a finished run leaves no part. A resumed
# run checkpoints on its own split (3 parts, the 2 of the set it resumed gone) and resumes again
# on 2. A one-process checkpoint resumes split on 3. Replicas of split gases (2 on 4 processes)
# resume on 4, 2 and 1. Refused, each named once: a missing part, a part of another checkpoint, a
# part with a byte changed, parts swapped between processes. Parts of other generations left by an
# earlier run go after the first commit. A process killed while the run checkpoints: the last
# committed set resumes.
# Skips (exit 0, saying so) only when MPI is not installed (no mpirun or no build/granary-mpi).
set -eu
name=t616
. "${GRAN_SOURCE_DIR:-.}/tests/mpi_env.sh.inc"
fail=0
cc $(pkg-config --cflags hdf5) "${GRAN_SOURCE_DIR:-.}/tests/h5same.c" -o "$tmp/h5same" $(pkg-config --libs hdf5)

scene() {
  name=$1; dim=$2; cells=$3; shift 3
  srd_scene "$tmp/$name.toml" "$dim" "$cells" 'decomposition = "auto"' "steps = 30" "sort_every = 7" "$@"
}
scene periodic3 3 "[9, 8, 7]" "n0 = 5" "dt = 0.5" "eps = 0.8" "sigma = 0.4" "seed = 21" \
  "[observables]" "every = 6" "sonine_a2 = true" "structure_factor = {bins = 6}" "[output]" "checkpoint_every = 1"
scene shear2 2 "[10, 9]" "n0 = 6" "dt = 0.4" "seed = 11" "thermostat = \"global\"" \
  "[boundaries]" "lees_edwards = {shear_rate = 0.05}" "[observables]" "every = 5" "structure_factor = true" \
  "velocity_profile = true" "[output]" "checkpoint_every = 1"
scene walls2 2 "[8, 9]" "n0 = 6" "dt = 1.0" "eps = 0.5" "sigma = 0.5" "seed = 9" \
  "[boundaries]" "walls = {axis = \"y\", rule = \"no-slip\", T = 0.5}" "vibrating_wall = {amplitude = 0.1, omega = 0.3}" \
  "[forces]" "gravity = [0, -0.02]" "[observables]" "every = 10" "snapshots = {every = 1}" "[output]" "checkpoint_every = 1"

# run N ARGS...: build/granary (N = 1) or build/granary-mpi on N processes, quiet, no log
run() { n=$1; shift; if [ "$n" = 1 ]; then "$cli" run "$@" --no-log -q; else mpi "$n" run "$@" --no-log -q; fi; }
# same A B WHAT: the two outputs bit for bit
same() {
  "$tmp/h5same" "$1" "$2" > "$tmp/same" 2>&1 || { echo "FAIL: $3:"; cat "$tmp/same"; fail=1; }
}
# parts DIR: the part files in DIR, one name per line
parts() { ls "$1" | grep -F '.part-' || true; }
# set_from SRC DST: a copy of a checkpoint set (the checkpoint c.ckpt and its parts)
set_from() { rm -rf "$2"; mkdir -p "$2"; cp "$1"/c.ckpt* "$2"/ 2>/dev/null || true; }

for s in periodic3 shear2 walls2; do
  f="$tmp/$s.toml"
  run 1 "$f" -o "$tmp/$s-ref.h5" --no-checkpoint > /dev/null 2> "$tmp/err" || { echo "FAIL: $s in one process: $(cat "$tmp/err")"; fail=1; continue; }
  d="$tmp/$s-set"; mkdir -p "$d"
  run 2 "$f" -o "$d/out.h5" --checkpoint "$d/c.ckpt" --stop-after-checkpoints 2 > /dev/null 2> "$tmp/err" || { echo "FAIL: $s stopped on 2: $(cat "$tmp/err")"; fail=1; continue; }
  got=$(parts "$d" | tr '\n' ' ')
  [ "$got" = "c.ckpt.part-g2-r0-b0 c.ckpt.part-g2-r0-b1 " ] || { echo "FAIL: $s: the set's parts are '$got' (want generation 2's two)"; fail=1; }
  for n in 1 2 3; do
    r="$tmp/$s-r$n"; set_from "$d" "$r"
    if run "$n" --resume "$r/c.ckpt" -o "$r/out.h5" > /dev/null 2> "$tmp/err"; then
      same "$tmp/$s-ref.h5" "$r/out.h5" "$s resumed on $n process(es)"
      [ -z "$(ls "$r" | grep -F 'c.ckpt' || true)" ] || { echo "FAIL: $s resumed on $n: the finished run left $(ls "$r" | tr '\n' ' ')"; fail=1; }
    else
      echo "FAIL: $s resumed on $n process(es): $(cat "$tmp/err")"; fail=1
    fi
  done
done

# a resumed run checkpoints on its own split; resumed again on another
f="$tmp/periodic3.toml"; d="$tmp/periodic3-set"; r="$tmp/again"
set_from "$d" "$r"
run 3 --resume "$r/c.ckpt" -o "$r/out.h5" --stop-after-checkpoints 1 > /dev/null 2> "$tmp/err" || { echo "FAIL: resume on 3, stopped: $(cat "$tmp/err")"; fail=1; }
got=$(parts "$r" | tr '\n' ' ')
[ "$got" = "c.ckpt.part-g3-r0-b0 c.ckpt.part-g3-r0-b1 c.ckpt.part-g3-r0-b2 " ] || { echo "FAIL: the set after a resume on 3 is '$got' (want generation 3's three parts)"; fail=1; }
run 2 --resume "$r/c.ckpt" -o "$r/out.h5" > /dev/null 2> "$tmp/err" || { echo "FAIL: resume on 2 of the set of 3: $(cat "$tmp/err")"; fail=1; }
same "$tmp/periodic3-ref.h5" "$r/out.h5" "periodic3 resumed on 3, stopped, resumed on 2"

# parts of another generation left beside the checkpoint path by an earlier run go after this run's
# first commit (theirs and their .tmp; another replica's stay)
r="$tmp/stale"; mkdir -p "$r"
for x in c.ckpt.part-g7-r0-b0 c.ckpt.part-g7-r0-b1.tmp c.ckpt.part-g1-r0-b2 c.ckpt.part-g7-r1-b0; do echo old > "$r/$x"; done
run 2 "$f" -o "$r/out.h5" --checkpoint "$r/c.ckpt" --stop-after-checkpoints 1 > /dev/null 2> "$tmp/err" || { echo "FAIL: a run beside stale parts: $(cat "$tmp/err")"; fail=1; }
got=$(parts "$r" | tr '\n' ' ')
[ "$got" = "c.ckpt.part-g1-r0-b0 c.ckpt.part-g1-r0-b1 c.ckpt.part-g7-r1-b0 " ] || { echo "FAIL: beside stale parts the run left '$got'"; fail=1; }

# a one-process checkpoint resumes split
r="$tmp/plain"; mkdir -p "$r"
run 1 "$f" -o "$r/out.h5" --checkpoint "$r/c.ckpt" --stop-after-checkpoints 2 > /dev/null 2>&1 || true
[ -z "$(parts "$r")" ] || { echo "FAIL: a one-process run wrote parts: $(parts "$r")"; fail=1; }
run 3 --resume "$r/c.ckpt" -o "$r/out.h5" > /dev/null 2> "$tmp/err" || { echo "FAIL: one-process checkpoint resumed on 3: $(cat "$tmp/err")"; fail=1; }
same "$tmp/periodic3-ref.h5" "$r/out.h5" "a one-process checkpoint resumed on 3"

# replicas of a split gas: 2 replicas on 4 processes (each gas on 2), resumed on 4, 2 and 1
run 1 "$f" --replicas 2 --set engine.keep_replicas=true -o "$tmp/rep-ref.h5" --no-checkpoint > /dev/null 2>&1
d="$tmp/rep-set"; mkdir -p "$d"
run 4 "$f" --replicas 2 --set engine.keep_replicas=true -o "$d/out.h5" --checkpoint "$d/c.ckpt" --stop-after-checkpoints 1 \
  > /dev/null 2> "$tmp/err" || { echo "FAIL: 2 replicas on 4, stopped: $(cat "$tmp/err")"; fail=1; }
got=$(parts "$d" | tr '\n' ' ')
[ "$got" = "c.ckpt.part-g1-r0-b0 c.ckpt.part-g1-r0-b1 c.ckpt.part-g1-r1-b0 c.ckpt.part-g1-r1-b1 " ] || { echo "FAIL: the replicas' set is '$got'"; fail=1; }
for n in 4 2 1; do
  r="$tmp/rep-r$n"; set_from "$d" "$r"
  run "$n" --resume "$r/c.ckpt" -o "$r/out.h5" > /dev/null 2> "$tmp/err" || { echo "FAIL: replicas resumed on $n: $(cat "$tmp/err")"; fail=1; continue; }
  same "$tmp/rep-ref.h5" "$r/out.h5" "2 replicas resumed on $n process(es)"
done

d="$tmp/periodic3-set"
# a part missing
r="$tmp/bad1"; set_from "$d" "$r"; rm "$r/c.ckpt.part-g2-r0-b1"
expect 1 "c.ckpt.part-g2-r0-b1" -- run 2 --resume "$r/c.ckpt" -o "$r/out.h5"
expect 1 "c.ckpt.part-g2-r0-b1" -- run 1 --resume "$r/c.ckpt" -o "$r/out.h5"
# a part of another checkpoint (the first generation of another run)
o="$tmp/other"; mkdir -p "$o"
run 2 "$f" -o "$o/out.h5" --checkpoint "$o/c.ckpt" --stop-after-checkpoints 1 > /dev/null 2>&1 || true
r="$tmp/bad2"; set_from "$d" "$r"; cp "$o/c.ckpt.part-g1-r0-b1" "$r/c.ckpt.part-g2-r0-b1"
expect 1 "is of generation 1 at step 0, and the checkpoint commits generation 2 at step 6" -- run 2 --resume "$r/c.ckpt" -o "$r/out.h5"
expect 1 "is of generation 1 at step 0, and the checkpoint commits generation 2 at step 6" -- run 3 --resume "$r/c.ckpt" -o "$r/out.h5"
# a byte changed: its checksum
r="$tmp/bad3"; set_from "$d" "$r"
python3 -c "import sys; p=sys.argv[1]; b=bytearray(open(p,'rb').read()); b[len(b)//2]^=1; open(p,'wb').write(b)" "$r/c.ckpt.part-g2-r0-b0"
expect 1 "c.ckpt.part-g2-r0-b0" -- run 2 --resume "$r/c.ckpt" -o "$r/out.h5"
# parts swapped between the processes of the same split
r="$tmp/bad4"; set_from "$d" "$r"
mv "$r/c.ckpt.part-g2-r0-b0" "$r/t"; mv "$r/c.ckpt.part-g2-r0-b1" "$r/c.ckpt.part-g2-r0-b0"; mv "$r/t" "$r/c.ckpt.part-g2-r0-b1"
expect 1 "holds brick 1 of the split 2 x 1 x 1, and this process runs brick 0 of 2 x 1 x 1" -- run 2 --resume "$r/c.ckpt" -o "$r/out.h5"

# a process killed while the run checkpoints at every output time: the last committed set resumes
long="$tmp/long.toml"
sed -e 's/^steps = 30/steps = 20000/' -e 's/^every = 6/every = 2/' -e '/structure_factor/d' "$f" > "$long"
k="$tmp/kill"; mkdir -p "$k"
( if mpi 2 run "$long" -o "$k/out.h5" --checkpoint "$k/c.ckpt" --no-log -q --timeout 10 > /dev/null 2> "$tmp/kill.err"; then echo 0; else echo $?; fi > "$tmp/kill.rc" ) &
signal_rank1 KILL "run $long" "[ -f '$k/c.ckpt' ] && [ -n \"\$(ls '$k' | grep -F part-g3 || true)\" ]" $!
if [ -z "$victim" ] || [ "$(cat "$tmp/kill.rc" 2>/dev/null)" = 0 ] || [ $dt -gt 30 ]; then
  echo "FAIL: a process killed while checkpointing: exit $(cat "$tmp/kill.rc" 2>/dev/null) after ${dt} s: $(cat "$tmp/kill.err")"; fail=1
fi
run 2 --resume "$k/c.ckpt" -o "$k/out.h5" --stop-after-checkpoints 1 > /dev/null 2> "$tmp/err" || { echo "FAIL: the set left by the killed run does not resume: $(cat "$tmp/err")"; fail=1; }

[ $fail = 0 ] && echo "t616: all checks passed"
exit $fail
