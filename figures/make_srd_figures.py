#!/usr/bin/python3
"""Regenerate the GSRD figures of Zantop (2017) as PNG files (`make figures`).

Each figure runs the scenes of scenes/srd/ with `granary run` (reduced sizes, stated in each scene
file; every scene takes seconds), reads the HDF5 output through granary_h5 only, and draws GSRD
(symbols) with the theory the run wrote or a relation that must hold (lines):

  srd-haff        Fig. 3.5   T(t) of the homogeneous cooling gas beside Haff's law (Eq. 2.1 rate)
  srd-clustering  Fig. 3.12  E_kin, T, Mach number and sigma(rho) through the onset of clustering
                             at eps = 0.98, with density snapshots
  srd-a2          Fig. 3.15  Sonine a2 against time for four eps_eff(t0)
  srd-bed         Ch. 5      vibrated bed under gravity: T(t), density and temperature profiles,
                             the hydrostatic balance n theta = g x (particles above)
  srd-viscosity-2d  Fig. 3.2  standard SRD viscosity against alpha (2-D) beside Eq. 1.48 + collisional
  srd-viscosity-3d  Fig. 3.3  the same in 3-D beside Eq. 1.49 + collisional
  srd-viscosity-gsrd Fig. 3.6 GSRD (eps = 0.9) viscosity against alpha beside Eq. 2.55 + collisional

    /usr/bin/python3 figures/make_srd_figures.py [--quick] [--granary build/granary]
                                                 [--out build/figures] [--only srd-haff] [--replot]
--quick changes nothing here (the scenes are already small); it only prefixes the data files.
"""

import os
import sys
import textwrap

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from granary_h5 import Output  # noqa: E402
import figure_driver  # noqa: E402
from figure_driver import run_granary  # noqa: E402

A2_EFF = ["0.900", "0.935", "0.960", "0.980"]
VISC_2D = [30, 45, 60, 90, 120, 150]
VISC_3D = [30, 60, 90, 120, 150, 180]
VISC_GSRD = [20, 30, 45, 60, 90, 120]
SCENES = {
    "srd-haff": ["haff"],
    "srd-clustering": ["clustering"],
    "srd-a2": ["a2-eff" + e for e in A2_EFF],
    "srd-bed": ["vibrated-bed"],
    "srd-viscosity-2d": ["viscosity-2d-a%03d" % a for a in VISC_2D],
    "srd-viscosity-3d": ["viscosity-3d-a%03d" % a for a in VISC_3D],
    "srd-viscosity-gsrd": ["viscosity-gsrd-a%03d" % a for a in VISC_GSRD],
}


def run_scene(args, name, walls):
    """Run scenes/srd/NAME.toml once per invocation; return its output path."""
    out = os.path.join(args.out, "data", ("quick-" if args.quick else "") + "srd-" + name + ".h5")
    return run_granary(args, "scenes/srd/%s.toml" % name, out, walls)


def size_text(o):
    n = o.attr("N", 0, "srd")
    cells = o.get("srd/cells")
    d = int(o.attr("dimension", 3))
    box = " x ".join("%d" % c for c in cells[:d])
    s = "GSRD %d-D, %s cells, N = %d, dt = %g, alpha = %g deg, eps = %g" % (
        d, box, n, o.attr("dt", 0, "srd"), o.attr("alpha_deg", 0, "srd"), o.attr("eps", 1, "srd"))
    R = o.nreplicas
    s += ", R = %d replica%s" % (R, "" if R == 1 else "s (error bars: 1 s.e.)")
    return s


def finish(fig, o, fname, args, caption, top=0.86, size=None):
    fig.text(0.5, 0.935, size or size_text(o), ha="center", va="top", fontsize=8, color="0.25")
    text = "\n".join(textwrap.wrap(caption, 125))
    fig.text(0.01, 0.01, text, fontsize=7.5, va="bottom", ha="left")
    nlines = text.count("\n") + 1
    fig.subplots_adjust(bottom=0.1 + 0.03 * nlines, top=top, wspace=0.3, hspace=0.35)
    path = os.path.join(args.out, fname)
    fig.savefig(path, dpi=args.dpi)
    plt.close(fig)
    print("figures: wrote %s" % path, flush=True)


def pts(ax, x, y, se, color, label, marker="o"):
    good = np.isfinite(y) & (y > 0)
    if se is not None:
        ax.errorbar(x[good], y[good], yerr=se[good], fmt=marker, ms=3.5, mfc="none", color=color,
                    label=label, elinewidth=0.8, capsize=1.5)
    else:
        ax.plot(x[good], y[good], marker, ms=3.5, mfc="none", color=color, label=label)


def srd_haff(args, f):
    with Output(f["haff"]) as o:
        t, T, se, th = o.times("temperature"), o.get("temperature/T"), o.se("temperature/T"), o.get("temperature/T_theory")
        rate = o.attr("haff_rate", float("nan"), "temperature")
        fig, (ax, bx) = plt.subplots(1, 2, figsize=(10, 4.8))
        pts(ax, t, T, se, "C0", "GSRD: T(t)")
        ax.plot(t, th, "k-", lw=1.2, label="Haff's law, 1/tau = %.4g (mean field, Eq. 2.1)" % rate)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("t [%s]" % o.units("temperature/time"))
        ax.set_ylabel("T [%s]" % o.units("temperature/T"))
        ax.legend(fontsize=7.5, loc="lower left")
        bx.plot(t, np.sqrt(T[0] / T), "o", ms=3.5, mfc="none", color="C0", label="GSRD: sqrt(T(0) / T)")
        bx.plot(t, 1 + rate * t, "k-", lw=1.2, label="Haff: 1 + t / tau")
        bx.set_xlabel("t")
        bx.set_ylabel("sqrt(T(0) / T)")
        bx.legend(fontsize=7.5, loc="upper left")
        dev = 100 * (T[-1] / th[-1] - 1)
        fig.suptitle("Haff's law of the homogeneous cooling GSRD gas (thesis Fig. 3.5, reduced)", fontsize=10)
        finish(fig, o, "srd-haff.png", args,
               "T falls by %.1f decades; at the end it lies %+.1f %% from the mean-field Haff law "
               "(the rate uses the cell density n0 and T, not the Poisson occupancy and the (n - 1)/n of the cell "
               "temperature; the thesis fits the rate). Right: sqrt(T(0)/T) is linear in t as Haff's law says."
               % (np.log10(T[0] / T[-1]), dev))


def srd_clustering(args, f):
    with Output(f["clustering"]) as o:
        t = o.times("clustering")
        T, th, Ek = o.get("temperature/T"), o.get("temperature/theta_cells"), o.get("clustering/E_kin")
        M, sr, Tt = o.get("clustering/mach"), o.get("clustering/sigma_rho"), o.get("temperature/T_theory")
        fig = plt.figure(figsize=(11, 8))
        ax = fig.add_subplot(2, 2, 1)
        pts(ax, t, th, None, "C0", "theta (thermal, cells)")
        pts(ax, t, Ek, None, "C3", "E_kin (convective, Eq. 3.1)", "s")
        pts(ax, t, T, None, "C2", "T (global)", "^")
        if Tt is not None:
            ax.plot(t, Tt, "k-", lw=1, label="Haff's law (Eq. 2.1 rate)")
        cross = np.nonzero(M > 1)[0]
        tc = t[cross[0]] if len(cross) else None
        for a in [ax]:
            if tc is not None:
                a.axvline(tc, color="0.5", ls=":", lw=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("t")
        ax.set_ylabel("energy per particle")
        ax.legend(fontsize=7)
        ax.set_title("(a) E_kin and temperature", fontsize=9)
        bx = fig.add_subplot(2, 2, 2)
        bx.plot(t, sr / sr[0], "o-", ms=3, mfc="none", color="C1")
        if tc is not None:
            bx.axvline(tc, color="0.5", ls=":", lw=1, label="Mach = 1 at t = %g" % tc)
            bx.legend(fontsize=7)
        bx.set_xscale("log")
        bx.set_xlabel("t")
        bx.set_ylabel("sigma(rho) / sigma(rho)(0)")
        bx.set_title("(b) density fluctuations", fontsize=9)
        cx = fig.add_subplot(2, 2, 3)
        cx.plot(t, M, "o-", ms=3, mfc="none", color="C4", label="global Mach number sqrt(E_kin / theta)")
        cx.axhline(1, color="k", lw=0.8)
        cx.set_xscale("log")
        cx.set_yscale("log")
        cx.set_xlabel("t")
        cx.set_ylabel("Mach")
        cx.legend(fontsize=7)
        cx.set_title("(c) Mach number crossing one", fontsize=9)
        dx = fig.add_subplot(2, 2, 4)
        snaps = sorted(k for k in o.file["fields"] if k.startswith("snap_"))
        last = snaps[-1]
        rho = o.get("fields/%s/density" % last)
        im = dx.imshow(np.log10(np.maximum(rho, 0.1)), origin="lower", cmap="viridis")
        fig.colorbar(im, ax=dx, label="log10 density (floor 0.1)")
        dx.set_title("(d) density at t = %g (XDMF: open the .xmf in ParaView)" % o.attr("time", 0, "fields/" + last),
                     fontsize=9)
        fig.suptitle("Onset of clustering at eps = 0.98 (thesis Fig. 3.12, reduced)", fontsize=10)
        grow = sr[-1] / sr[0]
        finish(fig, o, "srd-clustering.png", args,
               "While the gas cools homogeneously the Mach number stays near its noise level (cell means of n0 "
               "particles) and T follows Haff's law; Mach crosses one at t = %s (dotted line), E_kin overtakes theta, "
               "T (global, with the flow) leaves Haff's law and sigma(rho) grows %.1f-fold by the end: the inhomogeneous cooling state. "
               "The thesis sees the transition after about 3e3 steps in a 120^3 box at n0 = 25." %
               ("%g" % tc if tc is not None else "(not reached)", grow), top=0.9)


def srd_a2(args, f):
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    o0 = None
    mins = []
    for k, e in enumerate(A2_EFF):
        o = Output(f["a2-eff" + e])
        t, a2 = o.times("sonine_a2"), o.get("sonine_a2/a2")
        t = t / o.attr("dt", 1.0, "srd")  # steps, as the thesis' axis (t in units of dt)
        mins.append("%s: %.3f at %g steps" % (e, a2.min(), t[np.argmin(a2)]))
        ax.plot(t, a2, "o-", ms=3, mfc="none", color="C%d" % k, label="eps_eff(t0) = %s (eps = %.6g)" % (e, o.attr("eps", 1, "srd")))
        if o0 is None:
            o0 = o
        else:
            o.close()
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("t / dt (steps)")
    ax.set_ylabel("a2 (thermal velocities v - V_cell)")
    ax.legend(fontsize=7.5)
    fig.suptitle("Second Sonine coefficient of the freely cooling GSRD gas (thesis Fig. 3.15, reduced)", fontsize=10)
    finish(fig, o0, "srd-a2.png", args,
           "a2 first decreases (0.900 barely), then returns towards zero, as in the thesis (minima near 500 steps there). "
           "Minima (eps_eff(t0): a2): %s. As in "
           "the thesis, the minima are lower for higher eps_eff(t0), and the strongly dissipating runs turn positive "
           "later. The scenes keep the thesis' n0 = 25, T0 = 100, dt = 0.01 (streaming length dt sqrt(T0) = 0.1 a); "
           "with dt sqrt(T0) = a the order reverses (README, GSRD Sonine a2). a2 is that of the thermal velocities, "
           "corrected for the cell-mean subtraction (0 for a Maxwellian). No theory is drawn (physics notes, \"Oracles for tests\": GSRD "
           "a2 is an observable, not a test). eps differs between the four runs, the line above names the first." % "; ".join(mins))
    o0.close()


def srd_bed(args, f):
    with Output(f["vibrated-bed"]) as o:
        t, T, th = o.times("temperature"), o.get("temperature/T"), o.get("temperature/theta_cells")
        g = -o.get("srd/accel")[1]
        a = o.attr("a", 1.0, "srd")
        snaps = sorted(k for k in o.file["fields"] if k.startswith("snap_"))
        use = snaps[len(snaps) // 2:]  # the second half: steady state
        cnt = np.mean([o.get("fields/%s/count" % s) for s in use], axis=0)  # [y][x]
        tmp = [o.get("fields/%s/temperature" % s) for s in use]
        cn = [o.get("fields/%s/count" % s) for s in use]
        nth = np.mean([c * x for c, x in zip(cn, tmp)], axis=0)  # n theta per cell
        Lx = cnt.shape[1]
        n_y = cnt.mean(axis=1) / a**2
        p_y = nth.mean(axis=1) / a**2
        T_y = np.where(n_y > 0, p_y / np.maximum(n_y, 1e-300), np.nan)
        above = np.cumsum(cnt.sum(axis=1)[::-1])[::-1] - 0.5 * cnt.sum(axis=1)  # particles above the layer centre
        hydro = g * above / (Lx * a)
        y = (np.arange(len(n_y)) + 0.5) * a
        fig, (ax, bx, cx) = plt.subplots(1, 3, figsize=(12, 4.6))
        ax.plot(t, T, "o", ms=3, mfc="none", color="C0", label="T (global)")
        ax.plot(t, th, "s", ms=3, mfc="none", color="C3", label="theta (thermal, cells)")
        ax.set_xlabel("t")
        ax.set_ylabel("temperature")
        ax.legend(fontsize=7)
        ax.set_title("(a) the wall's heating balances dissipation", fontsize=9)
        bx.plot(n_y, y, "-", color="C1", label="density n(y)")
        bx.set_xlabel("(b) density n(y), solid (time and x average)")
        bx.set_ylabel("y")
        b2 = bx.twiny()
        b2.plot(T_y, y, "--", color="C4", label="temperature theta(y)")
        b2.set_xlabel("theta(y) (dashed)")
        cx.semilogx(p_y, y, "o", ms=3, mfc="none", color="C0", label="n theta (GSRD)")
        cx.semilogx(hydro, y, "k-", lw=1, label="g x particles above / L_x")
        cx.set_xlabel("pressure")
        cx.set_ylabel("y")
        cx.legend(fontsize=7)
        cx.set_title("(c) hydrostatic balance", fontsize=9)
        good = (hydro > 0) & (p_y > 0) & (y < 0.5 * y[-1])
        dev = np.median(np.abs(p_y[good] / hydro[good] - 1)) * 100 if good.any() else float("nan")
        fig.suptitle("Vibrated granular bed under gravity (thesis Ch. 5, reduced)", fontsize=10)
        finish(fig, o, "srd-bed.png", args,
               "Averages over %d snapshots of the second half of the run. The ideal SRD gas in steady state "
               "carries its weight: n theta = g x (particles above y) per unit length; in the lower half of the bed "
               "the median deviation is %.0f %% (the thermal pressure leaves out the momentum flux of the mean flow "
               "the wall drives, and theta of sparsely filled cells is biased low at the top)." % (len(use), dev),
               top=0.8)


# ---- viscosity (Figs. 3.2, 3.3, 3.6) ------------------------------------------------------------------
# Units a = dt = m = 1; M = n0 (mean particles per cell), q = M - 1 + e^-M (Poisson occupancy).


def nu_kinetic(dim, M, alpha_deg, theta=1.0):
    """Eq. 1.48 (2-D) / Eq. 1.49 (3-D): kinetic viscosity of standard SRD (the formulas of bench/b801)."""
    al = np.radians(alpha_deg)
    q = M - 1 + np.exp(-M)
    if dim == 2:
        return theta * (M / (q * (1 - np.cos(2 * al))) - 0.5)
    return theta * (5 * M / (q * (4 - 2 * np.cos(al) - 2 * np.cos(2 * al))) - 0.5)


def nu_collisional(dim, M, alpha_deg):
    """Collisional viscosity (a^2 / (6 d dt)) (M - 1 + e^-M) / M (1 - cos alpha)."""
    q = M - 1 + np.exp(-M)
    return q / M * (1 - np.cos(np.radians(alpha_deg))) / (6.0 * dim)


def nu_eq255(M, alpha_deg, theta, kappa):
    """Eq. 2.55 (2-D GSRD kinetic viscosity, as it stands in the thesis; bench/b801 prints it too)
    with kappa = (1 - eps^2) sigma^2 dt sqrt(theta) (Eq. 2.53); kappa = 0 gives Eq. 1.48."""
    al = np.radians(alpha_deg)
    q = M - 1 + np.exp(-M)
    c2 = np.cos(2 * al)
    return theta * (M / (q * (1 - c2) - (2 * M * kappa + (M - 2) * kappa * kappa) * c2) - 0.5)


def visc_runs(f, names, drop):
    """Per scene: alpha, nu = eta / n0 (mean and s.e. over the output intervals after the first
    `drop`), the mean thermal temperature theta (cell temperatures corrected for n - 1), the output."""
    rows = []
    for name in names:
        o = Output(f[name])
        n0 = o.attr("n0", 0, "srd")
        eta = o.get("stress/eta")[1 + drop:] / n0  # row 0 is t = 0 (NaN)
        tc = o.get("temperature/theta_cells")[1 + drop:]
        theta = tc.mean() / (1 - (1 - np.exp(-n0)) / n0)
        rows.append(dict(alpha=o.attr("alpha_deg", 0, "srd"), nu=eta.mean(), se=eta.std(ddof=1) / np.sqrt(len(eta)),
                         nblk=len(eta), theta=theta, n0=n0, o=o))
    return rows


def visc_figure(args, rows, dim, fname, fig_no, eq, kinetic, theory_pts, extra_caption, who="SRD"):
    al = np.array([r["alpha"] for r in rows])
    nu = np.array([r["nu"] for r in rows])
    se = np.array([r["se"] for r in rows])
    M = rows[0]["n0"]
    th = np.array(theory_pts)
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.5, 7.6), sharex=True, gridspec_kw={"height_ratios": [2.2, 1]})
    a = np.linspace(min(10.0, al.min()), 180.0 if dim == 3 else 170.0, 400)
    kin = kinetic(a)
    col = nu_collisional(dim, M, a)
    ax.plot(a, kin + col, "k-", lw=1.3, label="total: %s + collisional" % eq)
    ax.plot(a, kin, "--", color="C0", lw=1, label="kinetic (%s)" % eq)
    ax.plot(a, col, ":", color="C3", lw=1.2, label="collisional, (M - 1 + e^-M) / (6 d M) (1 - cos alpha)")
    ax.errorbar(al, nu, yerr=se, fmt="o", ms=5, mfc="none", color="C2", capsize=2, label="%s under Lees-Edwards shear (+- 1 s.e.)" % who)
    ax.set_yscale("log")
    ax.set_ylabel("kinematic viscosity nu [a^2 / dt]")
    ax.legend(fontsize=7.5)
    bx.errorbar(al, 100 * (nu / th - 1), yerr=100 * se / th, fmt="o", ms=5, mfc="none", color="C2", capsize=2)
    bx.axhline(0, color="k", lw=0.8)
    bx.set_xlabel("rotation angle alpha [deg]")
    bx.set_ylabel("measured / theory - 1 [%]")
    bx.set_xlim(0, 180)
    tab = "; ".join("%g: %.4f +- %.4f (%.4f)" % (r["alpha"], r["nu"], r["se"], t) for r, t in zip(rows, th))
    fig.suptitle("%s shear viscosity against the rotation angle (thesis Fig. %s, reduced)" % (who, fig_no), fontsize=10)
    o = rows[0]["o"]
    cells = o.get("srd/cells")
    size = "%s %d-D, %s cells, n0 = %g, dt = %g, eps = %g, %d scenes (one per alpha), error bars: 1 s.e." % (
        who, dim, " x ".join("%d" % c for c in cells[:dim]), M, o.attr("dt", 0, "srd"), o.attr("eps", 1, "srd"), len(rows))
    finish(fig, o, fname, args, size=size, caption=
           "Symbols: nu = Lees-Edwards stress / (n0 shear rate), mean and standard error of %d output intervals "
           "after the start-up. alpha: measured +- s.e. (theory): %s. %s" % (rows[0]["nblk"], tab, extra_caption),
           top=0.9)
    for r in rows:
        r["o"].close()


def srd_viscosity_2d(args, f):
    rows = visc_runs(f, ["viscosity-2d-a%03d" % a for a in VISC_2D], 2)
    th = [nu_kinetic(2, r["n0"], r["alpha"]) + nu_collisional(2, r["n0"], r["alpha"]) for r in rows]
    visc_figure(args, rows, 2, "srd-viscosity-2d.png", "3.2", "Eq. 1.48", lambda a: nu_kinetic(2, rows[0]["n0"], a), th,
                "8 x 8 cells on purpose: the 2-D viscosity grows with the box (hydrodynamic long-time tails, which Eq. 1.48 "
                "leaves out). Global thermostat at kT = 1; shear rate min(0.1, 0.05 / nu).")


def srd_viscosity_3d(args, f):
    rows = visc_runs(f, ["viscosity-3d-a%03d" % a for a in VISC_3D], 2)
    th = [nu_kinetic(3, r["n0"], r["alpha"]) + nu_collisional(3, r["n0"], r["alpha"]) for r in rows]
    visc_figure(args, rows, 3, "srd-viscosity-3d.png", "3.3", "Eq. 1.49", lambda a: nu_kinetic(3, rows[0]["n0"], a), th,
                "Global thermostat at kT = 1; shear rate min(0.05, 0.05 / nu).")


def srd_viscosity_gsrd(args, f):
    rows = visc_runs(f, ["viscosity-gsrd-a%03d" % a for a in VISC_GSRD], 8)
    th, kap = [], []
    for r in rows:
        o = r["o"]
        eps, sig, dt = o.attr("eps", 1, "srd"), o.attr("sigma", 0, "srd"), o.attr("dt", 1, "srd")
        k = (1 - eps * eps) * sig * sig * dt * np.sqrt(r["theta"])
        kap.append(r["n0"] * k)
        th.append(nu_eq255(r["n0"], r["alpha"], r["theta"], k) + nu_collisional(2, r["n0"], r["alpha"]))
    thetas = np.array([r["theta"] for r in rows])
    e148 = [nu_kinetic(2, r["n0"], r["alpha"], r["theta"]) + nu_collisional(2, r["n0"], r["alpha"]) for r in rows]
    dmax = max(abs(a / b - 1) for a, b in zip(th, e148)) * 100
    fig_theta = float(np.mean(thetas))
    fig_kappa = float(np.mean(kap)) / rows[0]["n0"]
    visc_figure(args, rows, 2, "srd-viscosity-gsrd.png", "3.6", "Eq. 2.55",
                lambda a: nu_eq255(rows[0]["n0"], a, fig_theta, fig_kappa), th,
                "GSRD, eps = 0.9, no thermostat: the shear heating balances the dissipation; the lines are drawn at the "
                "mean theta = %.3f and mean kappa, the lower panel compares each run with Eq. 2.55 + collisional at its own steady "
                "theta (%.3f-%.3f, theta_cells corrected for n - 1) and kappa (Eq. 2.53; n0 kappa = %.1e-%.1e, "
                "eps_eff = 1 - n0 kappa >= 0.998 as in the thesis; there Eq. 2.55 differs from Eq. 1.48 at the same theta by "
                "%.2f %% at most). 8 x 8 cells, sigma and shear rate chosen per angle (scene files)."
                % (fig_theta, thetas.min(), thetas.max(), min(kap), max(kap), dmax), who="GSRD")


def draw(args, fig, walls):
    files = {name: run_scene(args, name, walls) for name in SCENES[fig]}
    globals()[fig.replace("-", "_")](args, files)


def main():
    args, todo, walls, secs = figure_driver.main(
        __doc__, SCENES, draw, "accepted for `make figures QUICK=1`; the scenes are small", "srd-haff,srd-a2")
    print("figures: %d GSRD figure(s) in %s (%.0f s; scene runs: %s)" % (
        len(todo), args.out, secs, ", ".join("%s %.1f s" % (os.path.basename(k), v) for k, v in walls.items())))


if __name__ == "__main__":
    main()
