#!/bin/sh
# t650-paraview.sh - the GSRD field snapshots in ParaView (pvbatch, else pvpython; headless): the
# shipped vibrated bed (scenes/srd/vibrated-bed.toml, copied with a smaller box, a = 0.5 and 100
# steps) in 2-D and in 3-D, opened through its XDMF sidecar with ParaView's default reader for
# .xmf. Checked against the HDF5 file (read by a small HDF5 program built here):
#  - the time steps are /fields/time;
#  - the bounds are the box: 2-D in the x-y plane (x and y the box, z extent zero), 3-D the box;
#  - the cells and the arrays count, density, temperature (1 component) and velocity (3): every
#    cell of the ParaView grid, found by its centre, holds the HDF5 values of that cell (x fastest),
#    so the velocity arrows lie along the grid; in 2-D v_z = 0 and the cells are pixels;
#  - ParaView's integral of the density over the box is N (area in 2-D, volume in 3-D);
#  - the pair of files moved to another directory opens the same (the sidecar names the HDF5
#    file relative to itself), and a script given a bare file name opens it by its absolute path;
#  - screenshots of the last snapshot are not empty (over 20 % of the pixels are not the
#    background): 2-D the default view (the reader's default representation coloured by density)
#    and the surface with velocity arrows, 3-D the surface. Saved in the test's temporary folder,
#    which is kept when the test fails.
# Skips (exit 0, saying so) when ParaView is not installed (no pvbatch or pvpython), and the
# screenshot alone when there is no X display, no Xvfb and ParaView cannot render offscreen.
set -eu
src=${GRAN_SOURCE_DIR:-.}
cli=${GRAN_CLI:-$src/build/granary}
case "$src" in /*) ;; *) src=$(cd "$src" && pwd) ;; esac
case "$cli" in /*) ;; *) cli=$(cd "$(dirname "$cli")" && pwd)/$(basename "$cli") ;; esac
pv=$(command -v pvbatch || command -v pvpython || true)
if [ -z "$pv" ]; then
  echo "SKIP: ParaView is not installed (no pvbatch or pvpython: apt-get install -y --no-install-recommends paraview python3-paraview xvfb)"
  exit 0
fi
tmp=$(mktemp -d /tmp/granary-t650-XXXXXX)
xpid=
# kept when the test fails (the screenshots and logs in it), removed when it passes
trap 'rc=$?; [ -z "$xpid" ] || kill "$xpid" 2>/dev/null || true; if [ $rc -eq 0 ]; then rm -rf "$tmp"; else echo "kept $tmp"; fi' EXIT
cd "$tmp"
# ParaView's rendering needs a display: the one there is, else a virtual one (Xvfb on a free
# display number, with -noreset: ParaView closes its first connection and opens the next at once,
# which a server resetting after its last client refuses now and then; xvfb-run starts Xvfb
# without -noreset),
# else offscreen rendering alone (builds with EGL or OSMesa)
start_xvfb() {
  command -v Xvfb >/dev/null 2>&1 || return 1
  n=90
  while [ $n -lt 140 ]; do
    if [ ! -e "/tmp/.X$n-lock" ]; then
      Xvfb ":$n" -noreset -nolisten tcp -screen 0 1024x768x24 > xvfb.log 2>&1 &
      xpid=$!
      i=0
      while [ $i -lt 100 ] && kill -0 "$xpid" 2>/dev/null; do
        if [ -S "/tmp/.X11-unix/X$n" ]; then DISPLAY=":$n"; export DISPLAY; return 0; fi
        sleep 0.1; i=$((i + 1))
      done
      kill "$xpid" 2>/dev/null || true
      xpid=
    fi
    n=$((n + 1))
  done
  return 1
}
[ -n "${DISPLAY:-}" ] || start_xvfb || true
# the checks need no display
run_pv() { timeout 300 "$pv" "$@" > pv.log 2>&1 || { echo "FAIL: $pv $*"; grep -v '^ *[0-9]* *0x' pv.log | tail -30; exit 1; }; grep '^ok:' pv.log; }

# h5fields FILE: /srd/cells, /srd/N, /fields/time and the count and velocity of the last snapshot
cat > h5fields.c <<'CEOF'
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
static double *rd(hid_t f, const char *name, hssize_t *n) {
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) { fprintf(stderr, "missing %s\n", name); exit(1); }
  hid_t s = H5Dget_space(d);
  *n = H5Sget_simple_extent_npoints(s);
  double *x = malloc(sizeof(double) * (size_t)(*n > 0 ? *n : 1));
  if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x) < 0) exit(1);
  H5Sclose(s); H5Dclose(d);
  return x;
}
static void put(const char *key, const double *x, hssize_t n) {
  printf("%s", key);
  for (hssize_t i = 0; i < n; i++) printf(" %.17g", x[i]);
  printf("\n");
}
int main(int argc, char **argv) {
  if (argc != 2) return 2;
  hid_t f = H5Fopen(argv[1], H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return 1;
  hssize_t n, nt, ni;
  double *c = rd(f, "/srd/cells", &n), N = 0, a = 0;
  put("cells", c, n);
  hid_t g = H5Gopen2(f, "/srd", H5P_DEFAULT), at = H5Aopen(g, "N", H5P_DEFAULT);
  H5Aread(at, H5T_NATIVE_DOUBLE, &N); H5Aclose(at);
  at = H5Aopen(g, "a", H5P_DEFAULT);
  H5Aread(at, H5T_NATIVE_DOUBLE, &a); H5Aclose(at); H5Gclose(g);
  put("N", &N, 1);
  put("a", &a, 1);
  double *t = rd(f, "/fields/time", &nt), *idx = rd(f, "/fields/output_index", &ni);
  put("time", t, nt);
  char nm[64];
  snprintf(nm, sizeof nm, "/fields/snap_%06lld/count", (long long)idx[ni - 1]);
  double *x = rd(f, nm, &n);
  put("count", x, n);
  free(x);
  snprintf(nm, sizeof nm, "/fields/snap_%06lld/velocity", (long long)idx[ni - 1]);
  x = rd(f, nm, &n);
  put("velocity", x, n);
  free(x); free(c); free(t); free(idx);
  H5Fclose(f);
  return 0;
}
CEOF
cc $(pkg-config --cflags hdf5) h5fields.c -o h5fields $(pkg-config --libs hdf5)

# check.py XMF FIELDS DIM: the data checks (no rendering)
cat > check.py <<'PYEOF'
import os, sys
from paraview.simple import OpenDataFile, IntegrateVariables
from paraview import servermanager as sm
xmf, fields, dim = os.path.abspath(sys.argv[1]), sys.argv[2], int(sys.argv[3])
ref = {}
for line in open(fields):
    k, *v = line.split()
    ref[k] = [float(x) for x in v]
L = [int(x) for x in ref["cells"]]
a, N = ref["a"][0], ref["N"][0]
def fail(msg):
    print("FAIL: %s: %s" % (sys.argv[1], msg)); sys.exit(1)
r = OpenDataFile(xmf)
if r is None: fail("ParaView has no reader for it")
name = r.GetXMLName()
times = list(r.TimestepValues)
if times != ref["time"]: fail("time steps %s, /fields/time %s" % (times, ref["time"]))
box = [0.0, L[0] * a, 0.0, L[1] * a, 0.0, L[2] * a if dim == 3 else 0.0]
ncell = L[0] * L[1] * (L[2] if dim == 3 else 1)
want = {"count": 1, "density": 1, "temperature": 1, "velocity": 3}
for t in times:
    r.UpdatePipeline(t)
    di = r.GetDataInformation()
    b = list(di.GetBounds())
    if any(abs(x - y) > 1e-12 * max(box) for x, y in zip(b, box)): fail("t = %g: bounds %s, the box is %s" % (t, b, box))
    if di.GetNumberOfCells() != ncell: fail("t = %g: %d cells, expected %d" % (t, di.GetNumberOfCells(), ncell))
    got = {x.Name: x.GetNumberOfComponents() for x in r.CellData}
    if got != want: fail("t = %g: cell arrays %s, expected %s" % (t, got, want))
print("ok: %s (%s): %d time steps = /fields/time, bounds %s, %d cells, arrays %s" % (sys.argv[1], name, len(times), box, ncell, sorted(want)))
# the last snapshot, cell by cell, against the HDF5 file
d = sm.Fetch(r)
while d.IsA("vtkMultiBlockDataSet") or d.IsA("vtkMultiPieceDataSet"): d = d.GetBlock(0)
if dim == 2 and d.GetDimensions()[2] != 1: fail("the 2-D grid has %d nodes along z (1 expected)" % d.GetDimensions()[2])
cnt, vel = d.GetCellData().GetArray("count"), d.GetCellData().GetArray("velocity")
for c in range(d.GetNumberOfCells()):
    cb = d.GetCell(c).GetBounds()
    i, j = int((cb[0] + cb[1]) / (2 * a)), int((cb[2] + cb[3]) / (2 * a))
    k = int((cb[4] + cb[5]) / (2 * a)) if dim == 3 else 0
    if dim == 2 and (cb[4] != 0 or cb[5] != 0): fail("cell %d spans z %g..%g" % (c, cb[4], cb[5]))
    h = i + L[0] * (j + L[1] * k)
    v = vel.GetTuple3(c)
    if cnt.GetTuple1(c) != ref["count"][h] or list(v) != ref["velocity"][3 * h:3 * h + 3]:
        fail("cell (%d, %d, %d): count %g velocity %s, the HDF5 file %g %s" % (i, j, k, cnt.GetTuple1(c), v, ref["count"][h], ref["velocity"][3 * h:3 * h + 3]))
    if dim == 2 and v[2] != 0: fail("cell (%d, %d): v_z = %g" % (i, j, v[2]))
print("ok: every cell at t = %g holds the HDF5 count and velocity of the cell at its centre (x fastest)" % times[-1])
iv = IntegrateVariables(Input=r)
iv.UpdatePipeline(times[-1])
s = sm.Fetch(iv).GetCellData()
meas = "Volume" if dim == 3 else "Area"
m, rho = s.GetArray(meas).GetTuple1(0), s.GetArray("density").GetTuple1(0)
vol = box[1] * box[3] * (box[5] if dim == 3 else 1)
if abs(m - vol) > 1e-12 * vol or abs(rho - N) > 1e-9 * N: fail("%s %g (box %g), integral of the density %g (N = %g)" % (meas, m, vol, rho, N))
print("ok: ParaView's integral of the density = %.12g = N, over the %s %g of the box" % (rho, meas.lower(), m))
PYEOF

# shot.py XMF DIM A PNG...: screenshots of the last snapshot, each checked to be not empty (over
# 20 % of its pixels differ from the background): 2-D: the reader's default representation
# coloured by density (the view ParaView opens with), then the surface with an arrow along the
# velocity at each cell centre; 3-D: the surface
cat > shot.py <<'PYEOF'
import os, sys
from paraview.simple import (OpenDataFile, GetActiveViewOrCreate, Show, ColorBy, CellCenters, Glyph, Transform,
                             ResetCamera, Render, SaveScreenshot)
from vtkmodules.vtkIOImage import vtkPNGReader
xmf, dim, a, pngs = os.path.abspath(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), sys.argv[4:]
r = OpenDataFile(xmf)
r.UpdatePipeline(r.TimestepValues[-1])
v = GetActiveViewOrCreate("RenderView")
v.ViewTime = r.TimestepValues[-1]
v.OrientationAxesVisibility = 0
d = Show(r, v)
ColorBy(d, ("CELLS", "density"))
def shot(png, what):
    ResetCamera(v)
    Render(v)
    SaveScreenshot(png, v, ImageResolution=[640, 480])
    p = vtkPNGReader(); p.SetFileName(png); p.Update()
    img = p.GetOutput().GetPointData().GetScalars()
    bg, n = img.GetTuple(0), img.GetNumberOfTuples()
    f = sum(1 for i in range(n) if img.GetTuple(i) != bg) / n
    if f < 0.2:
        print("FAIL: %s of %s: %.1f %% of the pixels are not the background (the view is nearly empty)" % (what, sys.argv[1], 100 * f))
        sys.exit(1)
    print("ok: %s of %s, %.1f %% of the pixels not the background: %s" % (what, sys.argv[1], 100 * f, png))
if dim == 2:
    shot(pngs.pop(0), "the default view (representation %s)" % d.Representation)
d.Representation = "Surface"
if dim == 2:  # an arrow a cell long along the velocity at each cell centre, black, just above the plane
    g = Glyph(Input=CellCenters(Input=r), GlyphType="Arrow", GlyphMode="All Points")
    g.OrientationArray = ["POINTS", "velocity"]
    g.ScaleArray = ["POINTS", "No scale array"]
    g.ScaleFactor = 0.9 * a
    up = Transform(Input=g)
    up.Transform.Translate = [0, 0, 0.1 * a]
    gd = Show(up, v)
    ColorBy(gd, None)
    gd.AmbientColor = gd.DiffuseColor = [0, 0, 0]
shot(pngs.pop(0), "the surface" + (" and velocity arrows" if dim == 2 else ""))
PYEOF

# the shipped vibrated bed, reduced: 2-D 16 x 24 cells and 3-D 8 x 12 x 6, a = 0.5, 100 steps,
# a snapshot at each output time (0, 50, 100)
reduce() {
  sed -e "s/^dimension = .*/dimension = $1/" -e "s/^cells = .*/cells = $2\na = 0.5/" -e 's/^steps = .*/steps = 100/' \
      -e "s/^gravity = .*/gravity = $3/" -e "s/^path = .*/path = \"bed$1.h5\"/" "$src/scenes/srd/vibrated-bed.toml" > "bed$1.toml"
}
reduce 2 "[16, 24]" "[0, -0.005]"
reduce 3 "[8, 12, 6]" "[0, -0.005, 0]"
for dim in 2 3; do
  "$cli" run "bed$dim.toml" --quiet
  ./h5fields "bed$dim.h5" > "fields$dim.txt"
  run_pv "$tmp/check.py" "./bed$dim.xmf" "fields$dim.txt" "$dim"
done
# the pair moved elsewhere; a bare name (the script opens its absolute path)
mkdir moved && mv bed2.h5 bed2.xmf moved/
run_pv "$tmp/check.py" moved/bed2.xmf fields2.txt 2
(cd moved && run_pv "$tmp/check.py" bed2.xmf ../fields2.txt 2)
# screenshots
for x in moved/bed2.xmf bed3.xmf; do
  case $x in *2.xmf) dim=2; pngs="$tmp/bed2-default.png $tmp/bed2-velocity.png" ;; *) dim=3; pngs="$tmp/bed3-surface.png" ;; esac
  if ! timeout 300 "$pv" --force-offscreen-rendering "$tmp/shot.py" "$x" "$dim" 0.5 $pngs > shot.log 2>&1; then
    if [ -z "${DISPLAY:-}" ] && grep -q "X server\|DISPLAY" shot.log; then
      echo "SKIP: screenshot: no X display, no Xvfb (apt-get install -y xvfb) and $pv cannot render offscreen"
      break
    fi
    echo "FAIL: screenshot of $x"; grep -v '^ *[0-9]* *0x' shot.log | tail -30; exit 1
  fi
  grep '^ok:' shot.log
done
echo "t650 passed"
