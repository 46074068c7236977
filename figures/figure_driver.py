"""figure_driver.py - what every `make figures` script shares: the command line (--quick, --granary,
--out, --only, --replot, --dpi), running a scene once per invocation with `granary run`, and the
loop over the requested figures. The figure scripts (make_figures.py: Bodrova & Osinsky 2024; make_srd_figures.py:
GSRD) keep only their scenes and their plots. Not part of the reader module users import
(granary_h5.py)."""

import argparse
import os
import subprocess
import time


def run_granary(args, src, out, walls):
    """Run scene file `src` into `out` unless this invocation already did (or --replot finds it);
    record its wall time in walls[out]; return out."""
    if (args.replot and os.path.exists(out)) or out in walls:
        return out
    t0 = time.time()
    cmd = [args.granary, "run", src, "-o", out, "--force", "--no-checkpoint", "--quiet"]
    print("figures: %s" % " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)
    walls[out] = time.time() - t0
    return out


def main(doc, figures, draw, quick_help, only_example):
    """Parse the command line, then draw(args, fig, walls) for each requested figure (all of
    `figures` without --only). Returns (args, figures drawn, walls, seconds)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--granary", default="build/granary")
    ap.add_argument("--out", default="build/figures")
    ap.add_argument("--only", default="", help="comma-separated subset, e.g. " + only_example)
    ap.add_argument("--replot", action="store_true", help="reuse existing outputs, run nothing new")
    ap.add_argument("--dpi", type=int, default=110)
    args = ap.parse_args()
    os.makedirs(os.path.join(args.out, "data"), exist_ok=True)
    todo = [s for s in args.only.split(",") if s] or list(figures)
    for s in todo:
        if s not in figures:
            ap.error("unknown figure '%s' (known: %s)" % (s, ", ".join(figures)))
    walls = {}
    t0 = time.time()
    for fig in todo:
        draw(args, fig, walls)
    return args, todo, walls, time.time() - t0
