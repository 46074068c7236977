#!/usr/bin/env python3
"""Second Sonine (a2, a3) collision moments of an inelastic hard-sphere mixture (docs/physics-sonine.md Sec. 4).

f_k = Maxwellian_k [1 + a2_k S2(c^2) + a3_k S3(c^2)], c^2 = v^2/(2 a_k), a_k = T_k/m_k, and per pair (k, i)
    R[psi] = n_i sigma_ki^2 g2 Int dv1 dv2 f_k f_i Int dn Theta(g.n)(g.n) [psi(v1') - psi(v1)],
psi = v^2, v^4, v^6, to first order in (a2_k, a3_k, a2_i, a3_i) (the route of Sec. 2: v1 = G + (a_k/s^2) g,
v2 = G - (a_i/s^2) g with G, g independent Gaussians, n = e_z, Gaussian and half-line moments; exact
rational arithmetic in sympy's sparse polynomial rings).

  python3 docs/tools/sonine_second.py          derive, check the first-order part against Sec. 2 (R2, R4),
                                               write the coefficients to /tmp/sonine_second_coeffs.txt
Each coefficient is returned as (polynomial in ak, ai, A, s) / s^p times sqrt(2 pi) n_i sigma_ki^2 g2.
"""
import math
import sys
import sympy as sp
from sympy.polys.rings import ring
from sympy.polys.domains import QQ
from math import factorial

R, Gx, Gy, Gz, gx, gy, gz, ak, ai, A, w = ring("Gx Gy Gz gx gy gz ak ai A w", QQ)
# w = 1/s^2 (s^2 = ak + ai); G variance per component ak ai w, g variance s^2


def dfact(n):
    r = 1
    while n > 1:
        r *= n
        n -= 2
    return r


def expect(P):
    """E over G (variance ak ai / s^2), g_x, g_y (variance s^2) and Theta(g_z) over g_z (variance s^2) of the
    polynomial P; returns a dict power-of-s -> polynomial in ak, ai, A, w (times 1/sqrt(2 pi) for odd g_z)."""
    out = {}
    for mon, c in P.terms():
        px, py, pz, qx, qy, qz, e_ak, e_ai, e_A, e_w = mon
        if px % 2 or py % 2 or pz % 2 or qx % 2 or qy % 2:
            continue
        assert qz % 2 == 1
        # G moments: (ak ai w)^(p/2) (p-1)!!
        gp = (px + py + pz) // 2
        coef = c * dfact(px - 1) * dfact(py - 1) * dfact(pz - 1) * dfact(qx - 1) * dfact(qy - 1)
        # g_x, g_y: s^(qx+qy) = w^(-(qx+qy)/2); half line g_z^qz: s^qz 2^j j! / sqrt(2 pi), j = (qz-1)/2
        j = (qz - 1) // 2
        coef *= 2 ** j * factorial(j)
        spow = qz + qx + qy - 2 * (e_w + gp)  # net power of s (w = s^-2)
        key = spow
        term = R({(0, 0, 0, 0, 0, 0, e_ak + gp, e_ai + gp, e_A, 0): coef})
        out[key] = out.get(key, R(0)) + term
    return out


def to_expr(d):
    s = sp.Symbol("s", positive=True)
    AK, AI, AA = sp.symbols("ak ai A", positive=True)
    e = 0
    for p, poly in d.items():
        e += poly.as_expr().subs({sp.Symbol("ak"): AK, sp.Symbol("ai"): AI, sp.Symbol("A"): AA}) * s ** p
    return e


def main():
    v1 = [Gx + ak * w * gx, Gy + ak * w * gy, Gz + ak * w * gz]
    v2 = [Gx - ai * w * gx, Gy - ai * w * gy, Gz - ai * w * gz]
    X1 = sum(c * c for c in v1)
    X2 = sum(c * c for c in v2)
    Delta = -2 * A * gz * v1[2] + A * A * gz * gz  # v1'^2 - v1^2
    # c^2 = X/(2a); S2 = x^2/2 - 5x/2 + 15/8; S3 = -x^3/6 + 7x^2/4 - 35x/8 + 35/16
    # a_k^p S_p(c1^2) as polynomials without 1/a_k: multiply through by powers of ak
    x1n = X1  # = 2 ak c1^2
    S2k = (x1n ** 2) * QQ(1, 8) - x1n * ak * QQ(5, 4) + ak ** 2 * QQ(15, 8)  # ak^2 S2(c1^2)
    S3k = -(x1n ** 3) * QQ(1, 48) + (x1n ** 2) * ak * QQ(7, 16) - x1n * ak ** 2 * QQ(35, 16) + ak ** 3 * QQ(35, 16)
    S2i = (X2 ** 2) * QQ(1, 8) - X2 * ai * QQ(5, 4) + ai ** 2 * QQ(15, 8)
    S3i = -(X2 ** 3) * QQ(1, 48) + (X2 ** 2) * ai * QQ(7, 16) - X2 * ai ** 2 * QQ(35, 16) + ai ** 3 * QQ(35, 16)
    psis = {
        2: Delta,
        4: 2 * X1 * Delta + Delta ** 2,
        6: 3 * X1 ** 2 * Delta + 3 * X1 * Delta ** 2 + Delta ** 3,
    }
    weights = {"0": (R(1), 0, 0), "a2k": (S2k, 2, 0), "a3k": (S3k, 3, 0), "a2i": (S2i, 0, 2), "a3i": (S3i, 0, 3)}
    res = {}
    for p, dpsi in psis.items():
        for name, (wt, dk, di) in weights.items():
            d = expect(gz * dpsi * wt)
            # 4 pi (n-average) / sqrt(2 pi) = 2 sqrt(2 pi): result in units sqrt(2 pi) n sigma^2 g2;
            # divide by ak^dk ai^di (the weights carried a_k^p, a_i^p)
            e = 2 * to_expr(d)
            AK, AI = sp.symbols("ak ai", positive=True)
            e = sp.expand(e / (AK ** dk * AI ** di))
            res[(p, name)] = e
            print(p, name, "done", file=sys.stderr)
    s = sp.Symbol("s", positive=True)
    AK, AI, AA = sp.symbols("ak ai A", positive=True)
    # check against Sec. 2 (R = sqrt(2 pi) factored out)
    R2_doc = AA * (4 * s * (AA * s ** 2 - 2 * AK))
    R2k_doc = AA * AK ** 2 * (3 * AA * s ** 2 - 6 * AK - 8 * AI) / (2 * s ** 3)
    R2i_doc = AA * AI ** 2 * (3 * AA * s ** 2 + 2 * AK) / (2 * s ** 3)
    R4_doc = AA * 8 * (AA * s ** 2 - 2 * AK) * (2 * AA ** 2 * s ** 4 - 4 * AA * AK * s ** 2 + 6 * AK ** 2 + 5 * AK * AI) / s
    Pk = (30 * AA ** 3 * s ** 6 - AA ** 2 * (120 * AK ** 3 + 336 * AK ** 2 * AI + 312 * AK * AI ** 2 + 96 * AI ** 3)
          + AA * (210 * AK ** 3 + 561 * AK ** 2 * AI + 483 * AK * AI ** 2 + 132 * AI ** 3)
          - (180 * AK ** 3 + 462 * AK ** 2 * AI + 368 * AK * AI ** 2 + 80 * AI ** 3))
    Pi = (30 * AA ** 3 * s ** 6 - 24 * AA ** 2 * AK * s ** 4 + AA * (6 * AK ** 3 + 21 * AK ** 2 * AI + 15 * AK * AI ** 2)
          + 4 * AK ** 3 + 10 * AK ** 2 * AI)
    R4k_doc = AA * AK ** 2 * Pk / s ** 5
    R4i_doc = AA * AI ** 2 * Pi / s ** 5
    sub = {s: sp.sqrt(AK + AI)}
    for key, ref in [((2, "0"), R2_doc), ((2, "a2k"), R2k_doc), ((2, "a2i"), R2i_doc), ((4, "0"), R4_doc),
                     ((4, "a2k"), R4k_doc), ((4, "a2i"), R4i_doc)]:
        diff = sp.simplify((res[key] - ref).subs(sub))
        print("check", key, "difference to Sec. 2:", diff)
        assert diff == 0
    # elastic one species (a_k = a_i = a, A = 1): the linearised collision operator is symmetric,
    # <S2 L S3> = <S3 L S2>; with x^2 = 2 S2 + ..., x^3 = -6 S3 + 21 S2 + ... (x = c^2) and K(p, q) the
    # a_q coefficient of d<x^p>/dt: K(2, 3)/2 = -(K(3, 2) - 21 K(2, 2)/2)/6 (tests R6's a2 and R4's a3 terms)
    a = sp.Symbol("a", positive=True)
    one = {AK: a, AI: a, AA: 1}
    K = lambda p, q: sp.simplify((res[(2 * p, "a%dk" % q)] + res[(2 * p, "a%di" % q)]).subs(sub).subs(one) / (2 * a) ** p)
    diff = sp.simplify(K(2, 3) / 2 + (K(3, 2) - sp.Rational(21, 2) * K(2, 2)) / 6)
    print("check elastic symmetry <S2 L S3> - <S3 L S2>:", diff)
    assert diff == 0
    # elastic pair, any temperatures: energy conserved, m_k R2(k, i) + m_i R2(i, k) = 0, term by term
    mk, mi, Tk, Ti = sp.symbols("mk mi Tk Ti", positive=True)
    for nk, ni in [("a2k", "a2i"), ("a3k", "a3i")]:
        r2 = lambda name, x, y, A_: res[(2, name)].subs(sub).subs({AK: x, AI: y, AA: A_}, simultaneous=True)
        e = mk * r2(nk, Tk / mk, Ti / mi, 2 * mi / (mk + mi)) + mi * r2(ni, Ti / mi, Tk / mk, 2 * mk / (mk + mi))
        diff = sp.simplify(e)
        print("check elastic energy conservation (%s, %s):" % (nk, ni), diff)
        assert diff == 0
    with open("/tmp/sonine_second_coeffs.txt", "w") as f:
        for key, e in res.items():
            f.write("%d %s %s\n" % (key[0], key[1], sp.sstr(sp.factor(e.subs(sub)))))
    return res


def load():
    """the coefficients of /tmp/sonine_second_coeffs.txt (main() writes them) as plain functions"""
    AK, AI, AA = sp.symbols("ak ai A", positive=True)
    fns = {}
    for line in open("/tmp/sonine_second_coeffs.txt"):
        p, name, e = line.split(" ", 2)
        fns[(int(p), name)] = sp.lambdify((AK, AI, AA), sp.sympify(e, locals={"ak": AK, "ai": AI, "A": AA}), "math")
    return fns


def rates(fns, m, sig, n, eps, T, a2, a3, order=2):
    """zeta_k, da2_k/dt, da3_k/dt, linear in (a2, a3) (order=1: a3 = 0, the first Sonine level of Sec. 2)"""
    M = len(m)
    z0, z1, r4, r6 = [0.0] * M, [0.0] * M, [0.0] * M, [0.0] * M
    for k in range(M):
        akv = T[k] / m[k]
        for i in range(M):
            aiv = T[i] / m[i]
            Av = (1 + eps) * m[i] / (m[k] + m[i])
            wv = math.sqrt(2 * math.pi) * n[i] * (0.5 * (sig[k] + sig[i])) ** 2
            c = {key: f(akv, aiv, Av) for key, f in fns.items()}

            def lin(p):
                x = c[(p, "a2k")] * a2[k] + c[(p, "a2i")] * a2[i]
                if order == 2:
                    x += c[(p, "a3k")] * a3[k] + c[(p, "a3i")] * a3[i]
                return x
            z0[k] += -wv * c[(2, "0")] / (3 * akv)
            z1[k] += -wv * lin(2) / (3 * akv)
            r4[k] += wv * (c[(4, "0")] + lin(4)) / (15 * akv ** 2)
            r6[k] += wv * (c[(6, "0")] + lin(6)) / (105 * akv ** 3)
    zeta = [z0[k] + z1[k] for k in range(M)]
    # <v^4> = 15 a^2 (1 + a2), <v^6> = 105 a^3 (1 + 3 a2 - a3), d a/dt = -zeta a; products of (a2, a3) dropped
    phi2 = [r4[k] + 2 * z0[k] * (1 + a2[k]) + 2 * z1[k] for k in range(M)]
    phi3 = [3 * phi2[k] - 3 * (z0[k] * (1 + 3 * a2[k] - a3[k]) + z1[k]) - r6[k] for k in range(M)]
    return zeta, phi2, phi3


def hcs(fns, m, sig, n, eps, order=2, start=None):
    """HCS: equal zeta_k, da2/dt = da3/dt = 0; unknowns log(T_k/T_1) (k >= 2), a2_k, a3_k (mpmath findroot)"""
    import mpmath as mpm
    M = len(m)

    def F(*x):
        x = [float(v) for v in x]
        T = [1.0] + [math.exp(v) for v in x[:M - 1]]
        a2 = x[M - 1:2 * M - 1]
        a3 = x[2 * M - 1:] if order == 2 else [0.0] * M
        z, p2, p3 = rates(fns, m, sig, n, eps, T, a2, a3, order)
        out = [math.log(z[k] / z[0]) for k in range(1, M)] + [p2[k] / z[0] for k in range(M)]
        if order == 2:
            out += [p3[k] / z[0] for k in range(M)]
        return out

    if start is None:  # a rough start (T_k/T_1 ~ m_k^0.57 suits the equal-density set-ups here)
        start = ([m[k] ** 0.57 for k in range(M)], [0.02] * M, [0.0] * M)
    x0 = [math.log(start[0][k] / start[0][0]) for k in range(1, M)] + list(start[1]) + (list(start[2]) if order == 2 else [])
    sol = mpm.findroot(F, x0, tol=1e-24, maxsteps=200)
    sol = [float(v) for v in sol] if hasattr(sol, "rows") else [float(sol)]
    T = [1.0] + [math.exp(v) for v in sol[:M - 1]]
    return T, sol[M - 1:2 * M - 1], (sol[2 * M - 1:] if order == 2 else [0.0] * M)


def hcs_a3_given(fns, m, sig, n, eps, a3, start):
    """equal zeta_k and da2_k/dt = 0 with a3_k given (e.g. DSMC's): T_k/T_1 (k >= 2) and a2_k"""
    import mpmath as mpm
    M = len(m)

    def F(*x):
        x = [float(v) for v in x]
        T = [1.0] + [math.exp(v) for v in x[:M - 1]]
        z, p2, _ = rates(fns, m, sig, n, eps, T, x[M - 1:], a3, 2)
        return [math.log(z[k] / z[0]) for k in range(1, M)] + [p2[k] / z[0] for k in range(M)]

    sol = mpm.findroot(F, [math.log(start[k] / start[0]) for k in range(1, M)] + [0.0] * M, tol=1e-22)
    sol = [float(v) for v in sol] if hasattr(sol, "rows") else [float(sol)]
    return [math.exp(v) for v in sol[:M - 1]], sol[M - 1:]


def cpoly(e):
    """C expression of a polynomial in A, ak, ai: Horner in A, expanded coefficients"""
    AK, AI, AA = sp.symbols("ak ai A", positive=True)
    P = sp.Poly(sp.expand(e), AA)
    terms = []
    coeffs = P.all_coeffs()  # highest first
    def c2s(c):
        c = sp.expand(c)
        if c == 0: return "0.0"
        Q = sp.Poly(c, AI, AK)
        parts = []
        for (i, k), v in Q.terms():
            mon = "*".join(["ai"] * i + ["ak"] * k)
            parts.append("(%s.0)%s" % (v, ("*" + mon) if mon else ""))
        return "(" + " + ".join(parts) + ")"
    s = c2s(coeffs[0])
    for c in coeffs[1:]:
        s = "(%s)*A + %s" % (s, c2s(c))
    return s


def ccode():
    """the a2, a3 coefficients of R2, R4, R6 as the C++ of src/theory/sonine2.cpp (pair_terms2)"""
    AK, AI, AA = sp.symbols("ak ai A", positive=True)
    names = {"a2k": "k2", "a3k": "k3", "a2i": "i2", "a3i": "i3"}
    for line in open("/tmp/sonine_second_coeffs.txt"):
        p, name, e = line.split(" ", 2)
        if name == "0":
            continue
        e = sp.sympify(e, locals={"ak": AK, "ai": AI, "A": AA})
        n, de = sp.fraction(sp.factor(e))
        c = de.subs({AK: 1, AI: 0})
        j = int(sp.simplify(sp.expand_log(2 * sp.log(de / c) / sp.log(AI + AK), force=True)))
        print("  const double r%s%s = (%s) * is%d / %s.0;" % (p, names[name], cpoly(n), j, c))


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--ccode":
        ccode()
    else:
        main()
