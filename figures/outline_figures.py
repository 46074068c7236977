"""outline_figures.py - the figures of the DSMC outline (the time-step/cell DSMC with aggregation
and fragmentation), drawn by `make figures` through make_figures.py (--only outline-fig1, ...):

  outline-fig1, -fig2   Figs. 1-2: monodisperse gas, N = 2000: T(t) beside Haff's law, and the
                        collision count against T (Eq. 35 over the cooling rate, Eq. 44)
  outline-fig3, -fig4   Figs. 3-4: the same at N = 1e5
  outline-fig5          Fig. 5: speed distributions after N_c ~ 1.5e5 collisions against the Maxwellian
  outline-fig6          Fig. 6: polydisperse T_k(t) from equal temperatures against Eq. 76
  outline-aggregation   aggregation and fragmentation from monomers (cell and low-rank selectors):
                        n_k(t) and the cluster-size distribution against the Smoluchowski equations
  outline-agg-frag      the aggregation-fragmentation steady state under the white-noise thermostat

Scenes: scenes/outline/NAME.toml; with --quick scenes/quick/outline-NAME.toml where that exists
(the N = 1e5 gas and the steady state to shorter times), else the full scene (they take seconds).
"""

import os

import matplotlib.pyplot as plt
import numpy as np

from granary_h5 import Output
from figure_driver import head, run_granary, save

OUTLINE = "DSMC outline"
SCENES = {
    "outline-fig1": ["fig1-2"], "outline-fig2": ["fig1-2"],
    "outline-fig3": ["fig3-4"], "outline-fig4": ["fig3-4"],
    "outline-fig5": ["fig5"], "outline-fig6": ["fig6"],
    "outline-aggregation": ["aggregation", "aggregation-event"],
    "outline-agg-frag": ["agg-frag-steady"],
}
COLORS = ["C0", "C3", "C2", "C1", "C4", "C5", "C6"]


def scene_path(name, quick):
    q = "scenes/quick/outline-%s.toml" % name
    if quick and os.path.exists(q):
        return q
    return "scenes/outline/%s.toml" % name


def run_scene(args, name, walls):
    out = os.path.join(args.out, "data", ("quick-" if args.quick else "") + "outline-" + name + ".h5")
    return run_granary(args, scene_path(name, args.quick), out, walls)


def finish(fig, o, fname, args, title, notes, subtitle, top=0.9, bottom=0.1):
    """Title and the one-line subtitle above the axes; the measured notes go to NAME.txt."""
    head(fig, title, subtitle, top, bottom, titled_axes=fname in ("outline-aggregation.png", "outline-agg-frag.png"))
    save(fig, args, fname, notes)


def two_panels(figsize=(7, 6.0)):
    fig, (ax, rx) = plt.subplots(2, 1, figsize=figsize, sharex=True,
                                 gridspec_kw={"height_ratios": [3, 1.3], "hspace": 0.06})
    rx.axhline(0.0, color="k", lw=0.8)
    return fig, ax, rx


def eps_of(o):
    """The constant restitution coefficient of the scene (the first `eps = ` of [restitution])."""
    sec = o.scene.split("[restitution]", 1)[-1].split("\n[", 1)[0]
    for line in sec.splitlines():
        line = line.split("#", 1)[0].strip()
        if line.startswith("eps") and "=" in line and line.split("=")[0].strip() == "eps":
            return float(line.split("=", 1)[1])
    return float("nan")


def temperature_figure(args, f, scene, fname, fig_no):
    """Figs. 1 and 3: T(t) of the monodisperse gas beside Haff's law (the theory the run wrote)."""
    with Output(f[scene]) as o:
        t, T, th = o.times("temperatures"), o.T()[:, 0], o.T_theory()[:, 0]
        N = int(o.species("counts")[0])
        eps = eps_of(o)
        fig, ax, rx = two_panels()
        ax.plot(t, T, "o", ms=4, mfc="none", color="C0", label="cell DSMC, N = %d" % N)
        ax.plot(t, th, "k-", lw=1.2, label="Haff's law, T(0) / (1 + t / tau_0)^2, tau_0 = %.4g" % o.tau0)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylabel("T [%s]" % o.units("temperatures/T"))
        ax.legend(fontsize=8, loc="lower left")
        r = 100 * (T / th - 1)
        band = 100 * np.sqrt(2.0 / (3.0 * N))  # relative s.d. of the temperature of N Maxwellian particles
        rx.plot(t, r, "o", ms=3, mfc="none", color="C0")
        rx.fill_between(t, -band, band, color="0.85", lw=0, label="+- sqrt(2 / (3N)): one sample's noise")
        rx.set_ylabel("DSMC / Haff - 1 [%]", fontsize=8)
        rx.set_xlabel("t [%s]" % o.units("temperatures/time"))
        rx.legend(fontsize=7, loc="lower left")
        notes = ("N = %d, eps = %g, tau_0 = %.4g; T falls from %.4g to %.4g by t = %g; DSMC / Haff - 1 at the end %+.2f %%, "
                 "largest |deviation| %.2f %% at t = %.3g (one sample's noise sqrt(2/(3N)) = %.2f %%)."
                 % (N, eps, o.tau0, T[0], T[-1], t[-1], r[-1], np.abs(r).max(), t[np.argmax(np.abs(r))], band))
        finish(fig, o, fname, args, "%s Fig. %d: monodisperse gas, N = %d, T(t) beside Haff's law" % (OUTLINE, fig_no, N),
               notes, subtitle="cell DSMC, N = %d, n = %g, eps = %g, one run" % (N, o.species("density")[0], eps))


def collision_figure(args, f, scene, fname, fig_no):
    """Figs. 2 and 4: the collision count against T. Eq. 35 over the cooling rate of Eq. 44
    (dN_c/dT = -(N omega / 2) / (zeta T) = -3 N / (2 (1 - eps^2) T), Maxwellian), integrated from
    the first output: N_c(T) = N_c(t_1) + 3 N ln(T(t_1) / T) / (2 (1 - eps^2)), which holds whatever
    T(t) does (Haff's law or not)."""
    with Output(f[scene]) as o:
        t, T = o.times("temperatures"), o.T()[:, 0]
        Nc = o.collisions().astype(float)
        N = int(o.species("counts")[0])
        eps = eps_of(o)
        K = 3.0 * N / (2.0 * (1.0 - eps * eps))
        th = Nc[0] + K * np.log(T[0] / T)
        fig, ax, rx = two_panels()
        ax.plot(T, Nc, "o", ms=4, mfc="none", color="C0", label="cell DSMC: collisions (stats/collisions)")
        ax.plot(T, th, "k-", lw=1.2, label="Eq. 35 / Eq. 44: N_c(t_1) + 3N ln(T(t_1) / T) / (2 (1 - eps^2))")
        ax.set_xscale("log")
        ax.invert_xaxis()  # time runs to the right
        ax.set_ylabel("collisions N_c")
        ax.legend(fontsize=7.5, loc="upper left")
        r = 100 * (Nc / th - 1)
        rx.plot(T, r, "o", ms=3, mfc="none", color="C0")
        rx.set_ylabel("DSMC / theory - 1 [%]", fontsize=8)
        rx.set_xlabel("T [%s] (decreasing: time runs to the right)" % o.units("temperatures/T"))
        late = slice(len(t) // 2, None)
        notes = ("N = %d, eps = %g: %.4g collisions by t = %g (%.1f per particle) as T falls to %.4g; theory "
                 "(anchored at t_1 = %g) %.4g; DSMC / theory - 1 at the end %+.2f %%, over the second half of the outputs "
                 "%+.2f to %+.2f %%." % (N, eps, Nc[-1], t[-1], 2 * Nc[-1] / N, T[-1], t[0], th[-1], r[-1],
                                         r[late].min(), r[late].max()))
        finish(fig, o, fname, args, "%s Fig. %d: collisions against the temperature, N = %d" % (OUTLINE, fig_no, N),
               notes, subtitle="cell DSMC, N = %d, n = %g, eps = %g, one run" % (N, o.species("density")[0], eps))


def outline_fig1(args, f):
    temperature_figure(args, f, "fig1-2", "outline-fig1.png", 1)


def outline_fig2(args, f):
    collision_figure(args, f, "fig1-2", "outline-fig2.png", 2)


def outline_fig3(args, f):
    temperature_figure(args, f, "fig3-4", "outline-fig3.png", 3)


def outline_fig4(args, f):
    collision_figure(args, f, "fig3-4", "outline-fig4.png", 4)


def outline_fig5(args, f):
    """Speed distributions of c = |v - u| / sqrt(2 T / m) at the output times against the
    Maxwellian integrated over each bin (velocity_distribution/pdf_maxwell)."""
    with Output(f["fig5"]) as o:
        e = o.get("velocity_distribution/edges")
        c = 0.5 * (e[1:] + e[:-1])
        dc = np.diff(e)
        pdf, pm = o.get("velocity_distribution/pdf"), o.get("velocity_distribution/pdf_maxwell")
        tv = o.times("velocity_distribution")
        Nc = np.interp(tv, o.times("stats"), o.collisions().astype(float))
        N = int(o.species("counts")[0])
        fig, ax, rx = two_panels()
        ax.plot(c, pm, "k-", lw=1.2, label="Maxwellian, 4 c^2 exp(-c^2) / sqrt(pi) (bin average)")
        notes = []
        for i, (ti, nci) in enumerate(zip(tv, Nc)):
            col = COLORS[i % len(COLORS)]
            h = pdf[i, 0]
            se = np.sqrt(np.maximum(h, 0) / (N * dc))  # Poisson count noise of a bin
            ax.errorbar(c, h, yerr=se, fmt="os^"[i % 3], ms=4, mfc="none", color=col, capsize=1.5, lw=0.7,
                        label="t = %g, N_c = %.3g" % (ti, nci))
            good = pm > 0
            rx.errorbar(c[good] + 0.01 * (i - 1), 100 * (h[good] / pm[good] - 1), yerr=100 * se[good] / pm[good],
                        fmt="os^"[i % 3], ms=3, mfc="none", color=col, capsize=1.5, lw=0.7)
            ok = pm * N * dc >= 20  # bins with >= 20 expected particles
            z = (h[ok] - pm[ok]) / se[ok]
            chi2 = float(np.sum(z * z))
            notes.append("t = %g (N_c = %.4g): chi^2 = %.1f over %d bins with >= 20 expected particles, largest "
                         "|deviation| %.1f standard errors" % (ti, nci, chi2, int(ok.sum()), np.abs(z).max()))
        ax.set_ylabel("speed distribution f(c)")
        ax.legend(fontsize=7.5, loc="upper right")
        rx.set_ylabel("DSMC / Maxwellian - 1 [%]", fontsize=8)
        rx.set_xlabel("c = |v - u| / sqrt(2 T / m)")
        rx.set_ylim(-30, 30)
        finish(fig, o, "outline-fig5.png", args, "%s Fig. 5: speed distribution after N_c ~ %.2g collisions"
               % (OUTLINE, Nc[-1]), "N = %d, eps = %g, %d bins of dc = %.3g. " % (N, eps_of(o), len(c), dc[0]) +
               "; ".join(notes) + ".",
               subtitle="cell DSMC, N = %d, n = %g, eps = %g, one run (error bars: Poisson noise of the bin counts)"
               % (N, o.species("density")[0], eps_of(o)))


def outline_fig6(args, f):
    with Output(f["fig6"]) as o:
        t, T, th = o.times("temperatures"), o.T(), o.T_theory()
        m, n = o.species("mass"), o.species("counts")
        fig, ax, rx = two_panels()
        parts = []
        for k in range(o.nspecies):
            col = COLORS[k]
            ax.plot(t, T[:, k], "o", ms=4, mfc="none", color=col, label="cell DSMC, m_%d = %g" % (k + 1, m[k]))
            ax.plot(t, th[:, k], "-", color=col, lw=1.2, label="Eq. 76, m_%d = %g" % (k + 1, m[k]))
            r = 100 * (T[:, k] / th[:, k] - 1)
            rx.plot(t, r, "o", ms=3, mfc="none", color=col)
            parts.append("m = %g: T(t_end) = %.4g (theory %.4g, %+.1f %%)" % (m[k], T[-1, k], th[-1, k], r[-1]))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylabel("T_k [%s]" % o.units("temperatures/T"))
        ax.legend(fontsize=7.5, loc="lower left")
        rx.set_ylabel("DSMC / Eq. 76 - 1 [%]", fontsize=8)
        rx.set_xlabel("t [%s]" % o.units("temperatures/time"))
        order = np.argsort(T[-1])
        notes = ("Species N_k = %s, eps = %g. At t = %g: %s. The coldest species at the end is m = %g; "
                 "T_1/T_3 = %.3f (theory %.3f)." % (", ".join("%d" % c for c in n), eps_of(o), t[-1], "; ".join(parts),
                                                   m[order[0]], T[-1, 0] / T[-1, -1], th[-1, 0] / th[-1, -1]))
        finish(fig, o, "outline-fig6.png", args, "%s Fig. 6: polydisperse gas from equal temperatures" % OUTLINE, notes,
               subtitle="cell DSMC, m = (%s), sigma = m^(1/3), n_k = %g, eps = %g, one run" % (
                   ", ".join("%g" % x for x in m), o.species("density")[0], eps_of(o)))


def cluster_panels(axn, axd, o, label):
    """n_k(t) for a few sizes (upper) and the size distribution at two times (lower), with the
    Smoluchowski solution the run wrote (clusters/n_theory) as lines; error bars sqrt(n_k)."""
    t, n, th = o.times("clusters"), o.get("clusters/n"), o.get("clusters/n_theory")
    for i, k in enumerate((1, 2, 3, 5, 8)):
        col = "C%d" % i
        axn.errorbar(t, n[:, k - 1], yerr=np.sqrt(n[:, k - 1]), fmt="o", ms=3.5, mfc="none", color=col, capsize=1.5,
                     lw=0.7, label="k = %d" % k)
        if th is not None:
            axn.plot(t, th[:, k - 1], "-", color=col, lw=1.1)
    axn.set_yscale("log")
    axn.set_ylim(bottom=0.3)
    axn.set_xlabel("t")
    axn.set_ylabel("clusters of size k, n_k(t)")
    axn.set_title(label, fontsize=9)
    axn.plot([], [], "k-", label="Smoluchowski (clusters/n_theory)")
    axn.legend(fontsize=7, loc="lower right")
    k = np.arange(1, n.shape[1] + 1)
    for j, i in enumerate((len(t) // 3, len(t) - 1)):
        col = ("C0", "C3")[j]
        sel = n[i] > 0
        axd.errorbar(k[sel], n[i][sel], yerr=np.sqrt(n[i][sel]), fmt="os"[j], ms=3.5, mfc="none", color=col,
                     capsize=1.5, lw=0.7, label="t = %g" % t[i])
        if th is not None:
            axd.plot(k, th[i], "-", color=col, lw=1.1)
    axd.set_yscale("log")
    axd.set_xscale("log")
    axd.set_ylim(bottom=0.3)
    axd.set_xlabel("cluster size k")
    axd.set_ylabel("n_k")
    axd.legend(fontsize=7, loc="upper right")
    if th is None:
        return "no clusters/n_theory"
    ok = th[-1] >= 10
    z = (n[-1][ok] - th[-1][ok]) / np.sqrt(th[-1][ok])
    st = o.get("clusters/stats")[-1]
    return ("%s at t = %g: %d clusters, largest %d, %d merges, %d breakups; sizes with >= 10 expected clusters (k <= %d): "
            "chi^2 = %.1f over %d sizes, largest |deviation| %.1f sqrt(n_k) (k = %d), monomers %+.2f %%"
            % (label, t[-1], st[0], st[1], st[3], st[4], k[ok].max(), float(np.sum(z * z)), int(ok.sum()),
               np.abs(z).max(), k[ok][np.argmax(np.abs(z))], 100 * (n[-1][0] / th[-1][0] - 1)))


def outline_aggregation(args, f):
    with Output(f["aggregation"]) as a, Output(f["aggregation-event"]) as b:
        fig, axg = plt.subplots(2, 2, figsize=(10, 7.2), gridspec_kw={"hspace": 0.35, "wspace": 0.25})
        na = cluster_panels(axg[0][0], axg[1][0], a, "cell selector, fragments: monomers")
        nb = cluster_panels(axg[0][1], axg[1][1], b, "low-rank selector, fragments: binary")
        k = np.arange(1, a.get("clusters/n").shape[1] + 1)
        N = int(round(np.sum(k * a.get("clusters/n")[0])))  # monomers: the mass is conserved
        finish(fig, a, "outline-aggregation.png", args,
               "%s: aggregation and fragmentation from monomers against the Smoluchowski equations" % OUTLINE,
               na + ". " + nb + ".", top=0.87, bottom=0.08,
               subtitle="N = %d monomers at t = 0, n_1 = 0.01, eps = %g, E_agg = 1, E_frag = 3, eps_f = 0.7, one run "
               "each (error bars: sqrt(n_k))" % (N, eps_of(a)))


def outline_agg_frag(args, f):
    with Output(f["agg-frag-steady"]) as o:
        t, n, th = o.times("clusters"), o.get("clusters/n"), o.get("clusters/n_theory")
        st, led = o.get("clusters/stats"), o.get("clusters/ledger")
        fig, (ax, bx, cx) = plt.subplots(1, 3, figsize=(12, 4.6), gridspec_kw={"wspace": 0.3})
        fig.subplots_adjust(left=0.07, right=0.98)
        for i, k in enumerate((1, 2, 3, 4)):
            col = "C%d" % i
            ax.errorbar(t, n[:, k - 1], yerr=np.sqrt(n[:, k - 1]), fmt="o", ms=3, mfc="none", color=col, lw=0.7,
                        capsize=1.2, label="k = %d" % k)
            ax.plot(t, th[:, k - 1], ":", color=col, lw=1.0)
        ax.plot([], [], "k:", label="Smoluchowski, no heating")
        ax.set_yscale("log")
        ax.set_xlabel("t")
        ax.set_ylabel("n_k(t)")
        ax.set_title("(a) cluster numbers settle", fontsize=9)
        ax.set_ylim(5, 5e5)  # room for the legend above the monomers
        ax.legend(fontsize=6.5, loc="upper center", ncol=2)
        steady = t >= t[-1] / 3
        k = np.arange(1, n.shape[1] + 1)
        mean = n[steady].mean(axis=0)
        sem = n[steady].std(axis=0, ddof=1) / np.sqrt(steady.sum())
        sel = mean > 0
        bx.errorbar(k[sel], mean[sel], yerr=sem[sel], fmt="o", ms=4, mfc="none", color="C0", capsize=2,
                    label="time average, t >= %g (%d outputs)" % (t[steady][0], steady.sum()))
        bx.set_yscale("log")
        bx.set_xlabel("cluster size k")
        bx.set_ylabel("n_k")
        bx.set_title("(b) steady size distribution", fontsize=9)
        bx.legend(fontsize=7)
        ek = o.energy()
        names = ("bounces", "merges", "breakups", "thermostat (added)")
        for j in range(4):
            cx.plot(t, led[:, j], "-" + "os^v"[j], ms=3, mfc="none", color="C%d" % j, label=names[j])
        cx.plot(o.times("energy"), ek, "k-", lw=1, label="E_kin")
        cx.set_yscale("log")
        cx.set_xlabel("t")
        cx.set_ylabel("energy (cumulative)")
        cx.set_title("(c) energy ledger", fontsize=9)
        cx.legend(fontsize=7)
        T = o.T()[:, 0]
        dl = np.diff(led[steady], axis=0).sum(axis=0)
        notes = ("From t = %g on: %.0f +- %.0f clusters (mean +- s.d. over %d outputs), largest %d-%d; monomers %.0f +- %.0f, "
                 "dimers %.0f +- %.0f; T_1 %.3f-%.3f; energy over the steady part: thermostat added %.4g, bounces %.4g, "
                 "merges %.4g, breakups %.4g (added / lost = %.3f); E_kin %.4g -> %.4g. The Smoluchowski solution has no "
                 "heating term: it drifts off after the first output (n_1 = %.0f at t = %g against %.0f)."
                 % (t[steady][0], st[steady, 0].mean(), st[steady, 0].std(ddof=1), steady.sum(), st[steady, 1].min(),
                    st[steady, 1].max(), mean[0], n[steady, 0].std(ddof=1), mean[1], n[steady, 1].std(ddof=1),
                    T[steady].min(), T[steady].max(), dl[3], dl[0], dl[1], dl[2], dl[3] / dl[:3].sum(),
                    ek[np.searchsorted(o.times("energy"), t[steady][0])], ek[-1], th[0, 0], t[0], n[0, 0]))
        finish(fig, o, "outline-agg-frag.png", args,
               "%s: aggregation-fragmentation steady state under the white-noise thermostat" % OUTLINE, notes,
               top=0.84, bottom=0.12,
               subtitle="cell DSMC, N = %d monomers at t = 0, n_1 = 0.01, eps = 0.8, E_agg = 0.5, E_frag = 2, heat_rate = 0.02, "
               "one run" % int(round(np.sum(k * n[0]))))


def draw(args, fig, walls):
    files = {name: run_scene(args, name, walls) for name in SCENES[fig]}
    globals()[fig.replace("-", "_")](args, files)
