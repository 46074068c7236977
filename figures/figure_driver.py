"""figure_driver.py - what every `make figures` script shares: the command line (--quick, --granary,
--out, --only, --replot, --dpi), running a scene once per invocation with `granary run`, the loop
over the requested figures, and saving a figure (PNG at --dpi, 300 by default, and PDF beside it;
the numbers measured from the run, which the manual's validation page quotes, beside them in
NAME.txt). The figure scripts (make_figures.py: Bodrova & Osinsky and the DSMC outline;
make_srd_figures.py: GSRD) keep only their scenes and their plots. Not part of the reader module
users import (granary_h5.py)."""

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


def head(fig, title, subtitle, top=0.9, bottom=0.09, titled_axes=False):
    """The title and the one-line subtitle above the axes, spaced in inches (any figure height);
    `top` is lowered as far as the two lines need (further when the axes have titles)."""
    h = fig.get_figheight()
    if title is not None:
        fig.suptitle(title, fontsize=10, y=0.99, va="top")
    fig.text(0.5, 1.0 - 0.42 / h, subtitle, ha="center", va="top", fontsize=8, color="0.25")
    fig.subplots_adjust(top=min(top, 1.0 - (0.95 if titled_axes else 0.7) / h), bottom=bottom)


def save(fig, args, fname, notes=""):
    """Write fig as args.out/NAME.png (args.dpi) and NAME.pdf, and `notes` (what the run measured:
    the sentences the validation page quotes) as NAME.txt and on stdout; close fig."""
    import matplotlib.pyplot as plt
    base = os.path.join(args.out, os.path.splitext(fname)[0])
    fig.savefig(base + ".png", dpi=args.dpi)
    fig.savefig(base + ".pdf")
    plt.close(fig)
    with open(base + ".txt", "w") as fp:
        fp.write(notes.strip() + "\n")
    print("figures: wrote %s.png, .pdf, .txt" % base, flush=True)
    if notes.strip():
        print("  " + notes.strip(), flush=True)
    return base + ".png"


def main(doc, figures, draw, quick_help, only_example):
    """Parse the command line, then draw(args, fig, walls) for each requested figure (all of
    `figures` without --only). Returns (args, figures drawn, walls, seconds)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--granary", default="build/granary")
    ap.add_argument("--out", default="build/figures")
    ap.add_argument("--only", default="", help="comma-separated subset, e.g. " + only_example)
    ap.add_argument("--replot", action="store_true", help="reuse existing outputs, run nothing new")
    ap.add_argument("--dpi", type=int, default=300, help="PNG resolution (the PDF beside it is vector)")
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
