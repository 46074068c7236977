#!/bin/sh
# t004-figures-reader.sh - the figures' reader module (figures/granary_h5.py) on a tiny run of the
# command-line driver: datasets, units, attributes (str and bytes), the Sonine level of
# T_theory_sonine (first, second with sonine_order = 3), the replica layout (X, X_se, X_replicas,
# nreplicas) read from a copy of the file with those added, and the ballistic MSD against theory.
# Skipped (exit 0, with a message) when Debian's /usr/bin/python3 lacks h5py.
set -eu
src=${GRAN_SOURCE_DIR:-.}
cli=${GRAN_CLI:-$src/build/granary}
py=${FIG_PYTHON:-/usr/bin/python3}
if ! [ -x "$py" ] || ! "$py" -c 'import h5py, numpy' >/dev/null 2>&1; then
  echo "SKIP: $py cannot import h5py and numpy (apt-get install -y python3-h5py); reader not tested"
  exit 0
fi
tmp=$(mktemp -d /tmp/granary-t801-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
cat > "$tmp/tiny.toml" <<'TOML'
title = "t801 tiny binary mixture"
[mixture]
mass = [1.0, 4.0]
sigma = [1.0, 1.5]
density = [0.1, 0.05]
[restitution]
eps = 0.8
[initial]
temperatures = "hcs"
T_mean = 1.0
[engine]
counts = [4000, 2000]
seed = 801
t_end = 20.0
[observables]
times = { log = { start = 0.001, stop = 20.0, n = 6 } }
tamsd = { tracers = 20, dt = 0.5, samples = 41, lags = [0.5, 1.0, 2.0] }
[output]
checkpoint_interval = 0.0
TOML
"$cli" run "$tmp/tiny.toml" -o "$tmp/tiny.h5" --no-checkpoint --quiet
"$cli" run "$tmp/tiny.toml" -o "$tmp/son2.h5" --no-checkpoint --quiet --set observables.theory_sonine=true
"$cli" run "$tmp/tiny.toml" -o "$tmp/son3.h5" --no-checkpoint --quiet --set observables.theory_sonine=true \
  --set observables.sonine_order=3
PYTHONDONTWRITEBYTECODE=1 GRAN_T801_FILE="$tmp/tiny.h5" GRAN_T801_TMP="$tmp" PYTHONPATH="$src/figures" "$py" - <<'PY'
import os, shutil
import numpy as np
import h5py
import granary_h5
from granary_h5 import Output, attr_str

path, tmp = os.environ["GRAN_T801_FILE"], os.environ["GRAN_T801_TMP"]
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        fails.append(what)

with Output(path) as o:
    check(o.title == "t801 tiny binary mixture", "title is the scene's, as str: %r" % o.title)
    check(isinstance(o.scene, str) and "t801 tiny" in o.scene, "scene text stored")
    check(o.nspecies == 2 and o.nreplicas == 1 and o.complete, "nspecies 2, nreplicas 1 (absent), complete")
    t = o.times("msd")
    check(len(t) == 6 and abs(t[-1] - 20.0) < 1e-12 and np.all(np.diff(t) > 0), "6 increasing output times up to 20")
    check(np.array_equal(o.times(), o.get("time")), "times() is /time")
    msd, th, T = o.msd(), o.msd_theory(), o.T()
    check(msd.shape == (6, 2) and th.shape == (6, 2) and o.T_theory().shape == (6, 2), "MSD, theory, T_theory are [nt x M]")
    check(o.msd_se() is None and o.T_se() is None and o.replicas("msd/msd") is None, "no _se, no _replicas for one replica")
    check(o.units("msd/msd") == "length^2" and o.units("time") == "time", "units: %r" % o.units("msd/msd"))
    check(len(o.description("temperatures/T")) > 0 and "[" in o.label("msd/msd"), "description and label")
    check(np.array_equal(o.species("counts"), [4000, 2000]), "species/counts")
    check(o.tau0 is not None and o.tau0 > 0, "tau0 attribute")
    check(o.lags().shape == (3,) and o.tamsd().shape == (3, 2) and o.tamsd_theory().shape == (3, 2), "TAMSD at 3 lags")
    # physics: at t = 1e-3 (<< collision time) the motion is ballistic, MSD_k = 3 T_k(0) t^2 / m_k
    # with T_k(0) the scene's (/species/T0), not the sampled one.
    # Relative standard error of <v^2> over N Maxwellian particles: sqrt(2/(3N)); tolerance 5 se.
    m, N = o.species("mass"), o.species("counts")
    for k in range(2):
        ball = 3.0 * o.species("T0")[k] * t[0] ** 2 / m[k]
        se = ball * np.sqrt(2.0 / (3.0 * N[k]))
        check(abs(msd[0, k] - ball) < 5 * se, "species %d ballistic MSD %.6g vs 3 T t^2/m = %.6g (%.1f se)"
              % (k + 1, msd[0, k], ball, abs(msd[0, k] - ball) / se))
        check(abs(msd[0, k] / th[0, k] - 1) < 5 * np.sqrt(2.0 / (3.0 * N[k])) + 1e-3,
              "species %d MSD theory at t[0] within 5 se" % (k + 1))
    # energy: e_initial = e_kin + e_dissipated at every time (to rounding)
    ek, ei, ed = o.energy(), o.energy("e_initial"), o.energy("e_dissipated")
    check(np.allclose(ek + ed, ei, rtol=1e-9), "e_kin + e_dissipated = e_initial")
    check(o.sonine_level() is None and o.T_theory_sonine() is None, "no Sonine theory: sonine_level() is None")
with Output(os.path.join(tmp, "son2.h5")) as o:
    check(o.sonine_level() == "first" and o.get("temperatures/a3_theory_sonine") is None,
          "theory_sonine = true: the first Sonine level, no a3")
with Output(os.path.join(tmp, "son3.h5")) as o:
    check(o.sonine_level() == "second" and o.get("temperatures/a3_theory_sonine").shape == (6, 2),
          "sonine_order = 3: the second Sonine level with a3 [nt x M]")

# The replica layout: X beside X_se and X_replicas, root attribute nreplicas; strings
# written as bytes (fixed-length ASCII) must come back as str.
rep = os.path.join(tmp, "replicas.h5")
shutil.copy(path, rep)
R = 3
with h5py.File(rep, "r+") as f:
    f.attrs["nreplicas"] = np.int64(R)
    f.attrs["title"] = np.bytes_(b"bytes title")
    x = f["msd/msd"][()]
    f["msd/msd_se"] = 0.01 * x
    f["msd/msd_replicas"] = np.stack([x * (1 + 0.01 * r) for r in range(R)])
    f["msd/msd"].attrs["units"] = np.bytes_(b"length^2")
with Output(rep) as o:
    check(o.nreplicas == R, "nreplicas from the attribute")
    check(o.title == "bytes title", "bytes attribute returned as str")
    check(o.units("msd/msd") == "length^2", "bytes units returned as str")
    check(np.allclose(o.msd_se(), 0.01 * o.msd()), "msd_se reads msd/msd_se")
    check(o.replicas("msd/msd").shape == (R, 6, 2), "per-replica rows, replica first")
    check(o.T_se() is None, "an observable without _se still gives None")
check(attr_str(np.array([b"x"])) == "x" and attr_str("y") == "y", "attr_str unwraps and decodes")

# anything that is not a granary output is refused with a message naming the file
other = os.path.join(tmp, "other.h5")
with h5py.File(other, "w") as f:
    f["x"] = [1.0]
try:
    Output(other)
    check(False, "non-granary file refused")
except ValueError as e:
    check("other.h5" in str(e), "non-granary file refused: %s" % e)
if fails:
    raise SystemExit("%d check(s) failed" % len(fails))
print("all reader checks passed")
PY
# the figure scripts at least compile (plots are made by `make figures`)
for f in "$src"/figures/*.py; do
  "$py" -c 'import ast, sys; ast.parse(open(sys.argv[1]).read(), sys.argv[1])' "$f"
done
echo "ok: figures/*.py parse"
# with matplotlib: every scene a figure names exists (full and --quick), and Fig. 1's abscissa
# (Eq. 6, int_0^t sqrt(T/T0) dt on the output grid) is exact for constant T and within 0.5 % of
# tau0 ln(1 + t/tau0) for Haff's law on the 36-point log grid of the Fig. 1 scenes
if "$py" -c 'import matplotlib' >/dev/null 2>&1; then
  (cd "$src" && PYTHONDONTWRITEBYTECODE=1 PYTHONPATH="$src/figures" "$py" - <<'PY'
import os
import numpy as np
import make_figures as mf
import make_srd_figures as ms
import outline_figures as of
missing = []
for quick in (False, True):
    for fig, names in mf.SCENES.items():
        for n in names:
            p = of.scene_path(n, quick) if fig in of.SCENES else mf.scene_path(n, quick)
            if not os.path.exists(p):
                missing.append(p)
    for names in ms.SCENES.values():
        missing += ["scenes/srd/%s.toml" % n for n in names if not os.path.exists("scenes/srd/%s.toml" % n)]
assert not missing, "scenes the figures name are missing: %s" % missing
assert all(("outline-fig%d" % k) in mf.SCENES for k in range(1, 7)), "the six outline figures"
t = np.logspace(-2, 5, 36)
c = mf.reduced_time(t, np.full_like(t, 2.0), 2.0)
assert np.allclose(c, t, rtol=1e-12), "constant T: tau = t"
tau0 = 10.0
h = mf.reduced_time(t, 1.0 / (1 + t / tau0) ** 2, 1.0)
err = np.abs(h / (tau0 * np.log1p(t / tau0)) - 1).max()
assert err < 5e-3, "Haff: reduced time off by %.2g" % err
print("ok: %d figures name existing scenes; Eq. 6 abscissa exact for constant T, %.2g for Haff" % (len(mf.SCENES) + len(ms.SCENES), err))
PY
  )
else
  echo "SKIP: $py cannot import matplotlib; figure scenes and Fig. 1 abscissa not checked"
fi
