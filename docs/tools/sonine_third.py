#!/usr/bin/env python3
"""Beyond the second Sonine level (docs/physics-sonine.md Sec. 4, "What remains"): two HCS variants of a mixture of
inelastic hard spheres, each printed beside the linear second Sonine level of docs/tools/sonine_second.py.

  third:    f_k = Maxwellian [1 + a2 S2 + a3 S3 + a4 S4] (Sonine polynomials L_p^(1/2)), the balances of
            <x^p>, x = c^2, p = 2..4, linear in (a2, a3, a4); psi = v^8 and the S4 weights added to Sec. 2's route;
  bilinear: the second Sonine level with the products a_qk a_pi of the collision integrals (the Boltzmann operator
            is bilinear: f_k f_i) and the products zeta1 a of the moment equations kept.

  third, a4 given: a4_k held at DSMC's values, the <x^4> balance dropped (one species, the binary, the ternary);

  python3 docs/tools/sonine_third.py        (about a minute; sympy, mpmath)
"""
import math
import os
import sys

import mpmath as mpm
import sympy as sp
from sympy.polys.domains import QQ

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sonine_second as S  # noqa: E402

R, Gx, Gy, Gz, gx, gy, gz, ak, ai, A, w = S.R, S.Gx, S.Gy, S.Gz, S.gx, S.gy, S.gz, S.ak, S.ai, S.A, S.w
AK, AI, AA = sp.symbols("ak ai A", positive=True)
s = sp.Symbol("s", positive=True)
x = sp.Symbol("x")
v1 = [Gx + ak * w * gx, Gy + ak * w * gy, Gz + ak * w * gz]
v2 = [Gx - ai * w * gx, Gy - ai * w * gy, Gz - ai * w * gz]
X1 = sum(c * c for c in v1)
X2 = sum(c * c for c in v2)
D = -2 * A * gz * v1[2] + A * A * gz * gz  # v1'^2 - v1^2
PSI = {1: D, 2: 2 * X1 * D + D ** 2, 3: 3 * X1 ** 2 * D + 3 * X1 * D ** 2 + D ** 3,
       4: 4 * X1 ** 3 * D + 6 * X1 ** 2 * D ** 2 + 4 * X1 * D ** 3 + D ** 4}  # v1'^(2p) - v1^(2p)


def sonine(p):
    return sp.expand(sp.assoc_laguerre(p, sp.Rational(1, 2), x))


def weight(p, X, a):
    """a^p S_p(X/(2a)) as a ring polynomial"""
    out = R(0)
    for (e,), c in sp.Poly(sonine(p), x).terms():
        out += QQ(c.p, c.q) * X ** e * a ** (p - e) * QQ(1, 2 ** e)
    return out


def coeff(p, wt, dk, di):
    e = 2 * S.to_expr(S.expect(gz * PSI[p] * wt)) / (AK ** dk * AI ** di)
    return sp.lambdify((AK, AI, AA), sp.expand(e).subs(s, sp.sqrt(AK + AI)), "math")


def moment(p, q):
    """<x^p S_q(x)> over the Maxwellian (x = c^2, density ~ sqrt(x) e^-x)"""
    y = sp.Symbol("y", positive=True)
    f = sp.sqrt(y) * sp.exp(-y)
    g = 1 if q == 0 else sonine(q).subs(x, y)
    return float(sp.integrate(y ** p * g * f, (y, 0, sp.oo)) / sp.integrate(f, (y, 0, sp.oo)))


def pair_w(m, sig, n, eps, k, i):
    return (1 + eps) * m[i] / (m[k] + m[i]), math.sqrt(2 * math.pi) * n[i] * (0.5 * (sig[k] + sig[i])) ** 2


def solve(F, x0):
    sol = mpm.findroot(F, x0, tol=1e-22, maxsteps=100)
    return [float(v) for v in sol] if hasattr(sol, "rows") else [float(sol)]


def third_coeffs():
    C = {}
    for p in (1, 2, 3, 4):
        C[(p, 0, "k")] = coeff(p, R(1), 0, 0)
        for q in (2, 3, 4):
            C[(p, q, "k")] = coeff(p, weight(q, X1, ak), q, 0)
            C[(p, q, "i")] = coeff(p, weight(q, X2, ai), 0, q)
    MOM = {(p, q): moment(p, q) for p in range(1, 5) for q in (0, 2, 3, 4)}
    return C, MOM


def third(cases, C, MOM, a4_given=None):
    """the third Sonine HCS; a4_given (one list per case, or None): a4_k held there and the <x^4> balance dropped"""

    def rates(m, sig, n, eps, T, a, lin=True):
        """the collisional rate of <x^p>_k at fixed temperatures, x = v^2/(2 a_k)"""
        M = len(m)
        Rp = [[0.0] * 5 for _ in range(M)]
        for k in range(M):
            akv = T[k] / m[k]
            for i in range(M):
                aiv = T[i] / m[i]
                Av, wv = pair_w(m, sig, n, eps, k, i)
                for p in range(1, 5):
                    val = C[(p, 0, "k")](akv, aiv, Av)
                    if lin:
                        val += sum(C[(p, q, "k")](akv, aiv, Av) * a[k][q] + C[(p, q, "i")](akv, aiv, Av) * a[i][q]
                                   for q in (2, 3, 4))
                    Rp[k][p] += wv * val / (2 * akv) ** p
        return Rp

    for c, (name, m, sig, n, eps, start) in enumerate(cases):
        M = len(m)
        fixed = a4_given[c] if a4_given else None
        qs = (2, 3) if fixed else (2, 3, 4)

        def unpack(xv):
            T = [1.0] + [math.exp(float(v)) for v in xv[:M - 1]]
            a = [{q: float(xv[M - 1 + len(qs) * k + j]) for j, q in enumerate(qs)} for k in range(M)]
            for k in range(M):
                if fixed:
                    a[k][4] = fixed[k]
            return T, a

        def F(*xv):
            T, a = unpack(xv)
            Rp, R0 = rates(m, sig, n, eps, T, a), rates(m, sig, n, eps, T, a, False)
            zeta = [-Rp[k][1] / 1.5 for k in range(M)]
            zeta0 = [-R0[k][1] / 1.5 for k in range(M)]
            out = [math.log(zeta[k] / zeta[0]) for k in range(1, M)]
            for k in range(M):
                for p in qs:  # d<x^p>/dt = Rp + p zeta <x^p>, linear in a
                    xp = MOM[(p, 0)] + sum(a[k][q] * MOM[(p, q)] for q in (2, 3, 4))
                    out.append((Rp[k][p] + p * (zeta0[k] * xp + (zeta[k] - zeta0[k]) * MOM[(p, 0)])) / zeta0[0])
            return out

        x0 = [math.log(start[k] / start[0]) for k in range(1, M)] + [0.0] * (len(qs) * M)
        T, a = unpack(solve(F, x0))
        print("third Sonine%s %-8s T_k/T_1 %s  (a2, a3, a4)_k %s" % (
            " (a4 given)" if fixed else "", name, " ".join("%.4f" % t for t in T[1:]),
            "  ".join("%.4f %.4f %.4f" % (b[2], b[3], b[4]) for b in a)), flush=True)


def bilinear(cases):
    S2k = weight(2, X1, ak)
    S3k = weight(3, X1, ak)
    S2i = weight(2, X2, ai)
    S3i = weight(3, X2, ai)
    W = {"0": (R(1), 0, 0), "a2k": (S2k, 2, 0), "a3k": (S3k, 3, 0), "a2i": (S2i, 0, 2), "a3i": (S3i, 0, 3),
         "a2k a2i": (S2k * S2i, 2, 2), "a2k a3i": (S2k * S3i, 2, 3), "a3k a2i": (S3k * S2i, 3, 2),
         "a3k a3i": (S3k * S3i, 3, 3)}
    C = {(p, nm): coeff(p, *W[nm]) for p in (1, 2, 3) for nm in W}

    def rates(m, sig, n, eps, T, a2, a3, nonlin):
        M = len(m)
        z, z0, r4, r6 = [0.0] * M, [0.0] * M, [0.0] * M, [0.0] * M
        for k in range(M):
            akv = T[k] / m[k]
            for i in range(M):
                aiv = T[i] / m[i]
                Av, wv = pair_w(m, sig, n, eps, k, i)
                cf = {"0": 1, "a2k": a2[k], "a3k": a3[k], "a2i": a2[i], "a3i": a3[i]}
                if nonlin:
                    cf.update({"a2k a2i": a2[k] * a2[i], "a2k a3i": a2[k] * a3[i], "a3k a2i": a3[k] * a2[i],
                               "a3k a3i": a3[k] * a3[i]})
                val = {p: sum(C[(p, nm)](akv, aiv, Av) * c for nm, c in cf.items()) for p in (1, 2, 3)}
                z[k] += -wv * val[1] / (3 * akv)
                z0[k] += -wv * C[(1, "0")](akv, aiv, Av) / (3 * akv)
                r4[k] += wv * val[2] / (15 * akv ** 2)
                r6[k] += wv * val[3] / (105 * akv ** 3)
        if nonlin:
            phi2 = [r4[k] + 2 * z[k] * (1 + a2[k]) for k in range(M)]
            phi3 = [3 * phi2[k] - 3 * z[k] * (1 + 3 * a2[k] - a3[k]) - r6[k] for k in range(M)]
        else:
            phi2 = [r4[k] + 2 * z0[k] * (1 + a2[k]) + 2 * (z[k] - z0[k]) for k in range(M)]
            phi3 = [3 * phi2[k] - 3 * (z0[k] * (1 + 3 * a2[k] - a3[k]) + z[k] - z0[k]) - r6[k] for k in range(M)]
        return z, phi2, phi3

    for name, m, sig, n, eps, start in cases:
        M = len(m)
        for nl in (False, True):
            def F(*xv):
                xv = [float(v) for v in xv]
                T = [1.0] + [math.exp(v) for v in xv[:M - 1]]
                z, p2, p3 = rates(m, sig, n, eps, T, xv[M - 1:2 * M - 1], xv[2 * M - 1:], nl)
                return ([math.log(z[k] / z[0]) for k in range(1, M)] + [p2[k] / z[0] for k in range(M)]
                        + [p3[k] / z[0] for k in range(M)])
            sol = solve(F, [math.log(start[k] / start[0]) for k in range(1, M)] + [0.0] * (2 * M))
            print("second Sonine %-8s %-9s T_k/T_1 %s  a2 %s  a3 %s" % (
                name, "bilinear" if nl else "linear", " ".join("%.4f" % math.exp(v) for v in sol[:M - 1]),
                " ".join("%.4f" % v for v in sol[M - 1:2 * M - 1]), " ".join("%.4f" % v for v in sol[2 * M - 1:])),
                flush=True)


CASES = [("mono0.5", [1.0], [1.0], [0.1], 0.5, [1]), ("mono0.9", [1.0], [1.0], [0.1], 0.9, [1]),
         ("binary", [1.0, 100.0], [1.0, 100 ** (1 / 3)], [0.1, 0.1], 0.5, [1, 13.6]),
         ("t412", [1.0, 10.0], [1.0, 2.0], [1.0, 0.5], 0.7, [1, 1.8]),
         ("ternary", [1.0, 100.0, 500.0], [1.0, 100 ** (1 / 3), 500 ** (1 / 3)], [0.1] * 3, 0.5, [1, 23, 38.5]),
         ("fig2", [1.0, 100.0], [1.0, 100 ** (1 / 3)], [0.1, 0.001], 0.5, [1, 89])]

# DSMC a4_k (docs/physics-sonine.md Sec. 4) of the cases above, for the variant with a4 held
A4_DSMC = [[0.0118], None, [-0.0090, 0.0106], None, [-0.0092, 0.0033, 0.0153], None]

if __name__ == "__main__":
    C, MOM = third_coeffs()
    third(CASES, C, MOM)
    sel = [c for c, a in zip(CASES, A4_DSMC) if a]
    third(sel, C, MOM, [a for a in A4_DSMC if a])
    bilinear(CASES)
