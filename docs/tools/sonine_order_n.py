#!/usr/bin/env python3
"""HCS of the linear Sonine hierarchy to any order (docs/physics-sonine.md Sec. 4): f_k = Maxwellian_k
[1 + sum_{q=2..N} a_q,k S_q(c^2)] (S_q the Sonine polynomials L_q^(1/2)), zeta_k and the balances of <x^p>_k,
x = c^2, p = 2..N, linear in the a_q (N = 3: the second Sonine level of src/theory/sonine2.cpp; N = 4: the
third of sonine_third.py). The pair terms by the route of Sec. 2 (sonine_second.expect), psi = v^(2p) for
p = 1..N, evaluated in units of s^2 = a_k + a_i.

  python3 docs/tools/sonine_order_n.py N     (N = 5: about 5 minutes of sympy on the shared machine)
  python3 docs/tools/sonine_order_n.py --ccode   the N = 5 pair terms as the C++ of src/theory/sonine_n.cpp
                                                 (pair_coeffs: polynomials in x = a_k/s^2, y = a_i/s^2, A)

prints, for one species (eps = 0.5), the binary m = 1, 100 and the Fig. 3 ternary, T_k/T_1 and a_2..a_N per species.
"""
import math
import os
import sys
from math import comb

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sonine_third as T3  # noqa: E402

R, X1, X2, D, ak, ai = T3.R, T3.X1, T3.X2, T3.D, T3.ak, T3.ai
CCODE = len(sys.argv) > 1 and sys.argv[1] == "--ccode"
NMAX = 5 if CCODE or len(sys.argv) < 2 else int(sys.argv[1])
# v1'^(2p) - v1^(2p) = sum_j C(p, j) X1^(p-j) D^j
T3.PSI.update({p: sum(comb(p, j) * X1 ** (p - j) * D ** j for j in range(1, p + 1)) for p in range(1, NMAX + 1)})
qs = list(range(2, NMAX + 1))


def ccode():
    import sympy as sp
    AK, AI, AA, s = T3.AK, T3.AI, T3.AA, T3.s

    def expr(p, wt, dk, di):  # in units of s^2: s = 1, a_k + a_i = 1
        e = 2 * T3.S.to_expr(T3.S.expect(T3.gz * T3.PSI[p] * wt)) / (AK ** dk * AI ** di)
        return sp.expand(sp.expand(e).subs(s, 1))

    def c2s(c):
        c = sp.expand(c)
        if c == 0:
            return "0.0"
        parts = []
        for (i, k), v in sp.Poly(c, AI, AK).terms():
            mon = "*".join(["y"] * i + ["x"] * k)
            num, den = sp.fraction(sp.Rational(v))
            parts.append("(%s.0%s)%s" % (num, ("/" + str(den) + ".0") if den != 1 else "", ("*" + mon) if mon else ""))
        return "(" + " + ".join(parts) + ")"

    def cpoly(e):
        co = sp.Poly(e, AA).all_coeffs()
        r = c2s(co[0])
        for c in co[1:]:
            r = "(%s)*A + %s" % (r, c2s(c))
        return r
    for p in range(1, NMAX + 1):
        print("  const double c%d_0 = %s;" % (p, cpoly(expr(p, R(1), 0, 0))))
        for q in qs:
            print("  const double c%d_k%d = %s;" % (p, q, cpoly(expr(p, T3.weight(q, X1, ak), q, 0))))
            print("  const double c%d_i%d = %s;" % (p, q, cpoly(expr(p, T3.weight(q, X2, ai), 0, q))))


if CCODE:
    ccode()
    sys.exit(0)
C = {}
for p in range(1, NMAX + 1):
    C[(p, 0, "k")] = T3.coeff(p, R(1), 0, 0)
    for q in qs:
        C[(p, q, "k")] = T3.coeff(p, T3.weight(q, X1, ak), q, 0)
        C[(p, q, "i")] = T3.coeff(p, T3.weight(q, X2, ai), 0, q)
MOM = {(p, q): T3.moment(p, q) for p in range(1, NMAX + 1) for q in [0] + qs}


def rates(m, sig, n, eps, T, a, lin=True):
    """collisional rates of <x^p>_k at fixed temperatures"""
    M = len(m)
    Rp = [[0.0] * (NMAX + 1) for _ in range(M)]
    for k in range(M):
        akv = T[k] / m[k]
        for i in range(M):
            aiv = T[i] / m[i]
            Av, wv = T3.pair_w(m, sig, n, eps, k, i)
            s2 = akv + aiv
            x, y = akv / s2, aiv / s2
            for p in range(1, NMAX + 1):
                val = C[(p, 0, "k")](x, y, Av)
                if lin:
                    val += sum(C[(p, q, "k")](x, y, Av) * a[k][q] + C[(p, q, "i")](x, y, Av) * a[i][q] for q in qs)
                Rp[k][p] += wv * val * s2 ** ((2 * p + 1) / 2) / (2 * akv) ** p
    return Rp


CASES = [("mono0.5", [1.0], [1.0], [0.1], 0.5, [1]),
         ("binary", [1.0, 100.0], [1.0, 100 ** (1 / 3)], [0.1, 0.1], 0.5, [1, 13.5]),
         ("ternary", [1.0, 100.0, 500.0], [1.0, 100 ** (1 / 3), 500 ** (1 / 3)], [0.1] * 3, 0.5, [1, 23, 38.2])]
for name, m, sig, n, eps, start in CASES:
    M, nq = len(m), len(qs)

    def unpack(xv):
        T = [1.0] + [math.exp(float(v)) for v in xv[:M - 1]]
        return T, [{q: float(xv[M - 1 + nq * k + j]) for j, q in enumerate(qs)} for k in range(M)]

    def F(*xv):
        T, a = unpack(xv)
        Rp, R0 = rates(m, sig, n, eps, T, a), rates(m, sig, n, eps, T, a, False)
        zeta = [-Rp[k][1] / 1.5 for k in range(M)]
        zeta0 = [-R0[k][1] / 1.5 for k in range(M)]
        out = [math.log(zeta[k] / zeta[0]) for k in range(1, M)]
        for k in range(M):
            for p in qs:  # d<x^p>/dt = Rp + p zeta <x^p>, linear in a
                xp = MOM[(p, 0)] + sum(a[k][q] * MOM[(p, q)] for q in qs)
                out.append((Rp[k][p] + p * (zeta0[k] * xp + (zeta[k] - zeta0[k]) * MOM[(p, 0)])) / zeta0[0])
        return out

    x0 = [math.log(start[k] / start[0]) for k in range(1, M)] + [0.0] * (nq * M)
    sol = T3.mpm.findroot(F, x0, tol=1e-16, maxsteps=100)
    T, a = unpack([float(v) for v in sol] if hasattr(sol, "rows") else [float(sol)])
    print("order %d %-8s T_k/T_1 %s  a_2..a_%d per species: %s" % (
        NMAX, name, " ".join("%.4f" % t for t in T[1:]), NMAX,
        "  ".join(" ".join("%.4f" % b[q] for q in qs) for b in a)), flush=True)
