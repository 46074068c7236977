#!/usr/bin/env python3
"""Collision matrix K of the two-moment velocity correlation (src/theory/sonine_diffusion.cpp,
docs/physics-sonine.md Sec. 5) to first order in the Sonine coefficients a2, with a check by
direct quadrature of the collision integral.

    K_ba = w Int dv1 dv2 f_k(v1) phi_a(v1) f_i(v2) Int dn Theta(g.n) (g.n) [phi_b(v1') - phi_b(v1)] / 3,
    v1' = v1 - A (g.n) n,  g = v1 - v2,  phi_1 = v, phi_2 = v v^2 (dot product of the vectors / 3:
    K_ba delta_xy is the isotropic tensor Int phi_b,x J[f phi_a,y]),
    f_k = f_M,k [1 + a2_k S2(c1^2)],  f_i = f_M,i [1 + a2_i S2(c2^2)],  S2(x) = x^2/2 - 5x/2 + 15/8,

per unit w = n_i sigma_ki^2 g2_ki, a = T/m, s^2 = a_k + a_i, A = mu (1 + eps). Terms a2_k a2_i are
dropped. Derivation as in docs/physics-sonine.md Sec. 2: v1 = G + (a_k/s^2) g, v2 = G - (a_i/s^2) g
with G (variance a_k a_i/s^2 per component) independent of g (variance s^2), n = e_z by isotropy,
Gaussian moments of G, g_x, g_y and the half-line moments of g_z.

The check integrates the same integral without the (G, g) variables: in the Cartesian components of
v1 and v2 (n = e_z; x, y: exact Gaussian moments of the independent components; z: the 2-D integral
over (v1z, v2z) on v1z > v2z, Gauss-Legendre 160 x 160 in (v1z, v1z - v2z)).

Run: python3 docs/tools/sonine_diffusion_a2.py      (sympy; a few minutes)
Prints the closed forms, the check, and the values that tests/t414-sonine-diffusion.c asserts.
"""
import itertools
import sys

import math

import sympy as sp
from sympy.integrals.quadrature import gauss_legendre

_x, _w = gauss_legendre(160, 20)
NODES = ([float(x) for x in _x], [float(w) for w in _w])

ak, ai, A, s = sp.symbols('a_k a_i A s', positive=True)
a2k, a2i = sp.symbols('a2_k a2_i')
Gx, Gy, Gz, gx, gy, gz = sp.symbols('Gx Gy Gz gx gy gz', real=True)


def S2(x):
    return x**2 / 2 - sp.Rational(5, 2) * x + sp.Rational(15, 8)


def half_moment(q):
    """E[g_z^q Theta(g_z)] for g_z ~ N(0, s^2)"""
    return s**q * sp.sqrt(2)**q * sp.gamma(sp.Rational(q + 1, 2)) / (2 * sp.sqrt(sp.pi))


def gauss_moment(p, var):
    if p % 2:
        return 0
    return var**(p // 2) * sp.factorial2(p - 1)


def dot(u, v):
    return sum(x * y for x, y in zip(u, v))


def phis(v):
    v2 = dot(v, v)
    return [list(v), [x * v2 for x in v]]


def closed_forms():
    s2 = s**2
    G = [Gx, Gy, Gz]
    g = [gx, gy, gz]
    v1 = [G[j] + ak / s2 * g[j] for j in range(3)]
    v2 = [G[j] - ai / s2 * g[j] for j in range(3)]
    v1p = [v1[0], v1[1], v1[2] - A * gz]  # n = e_z, g.n = g_z
    weight = {'0': 1, 'k': S2(dot(v1, v1) / (2 * ak)), 'i': S2(dot(v2, v2) / (2 * ai))}
    varG = ak * ai / s2
    out = {}
    for a in range(2):
        for b in range(2):
            core = dot(phis(v1)[a], [x - y for x, y in zip(phis(v1p)[b], phis(v1)[b])]) * gz / 3
            for part, wgt in weight.items():
                poly = sp.Poly(sp.expand(core * wgt), Gx, Gy, Gz, gx, gy, gz)
                tot = 0
                for (p1, p2, p3, q1, q2, q3), coef in poly.terms():
                    tot += (coef * gauss_moment(p1, varG) * gauss_moment(p2, varG) * gauss_moment(p3, varG) *
                            gauss_moment(q1, s2) * gauss_moment(q2, s2) * half_moment(q3))
                # the pair integral per unit w carries the 4 pi of Int dn
                val = sp.simplify((4 * sp.pi * tot).subs(ai, s2 - ak))
                out[(b + 1, a + 1, part)] = sp.factor(sp.simplify(val))
    return out


def quadrature(b, a, part, akv, aiv, Av):
    """the same integral in the Cartesian components of v1, v2 (no G, g variables): x, y exact
    Gaussian moments of the independent components, z by 2-D Gauss-Legendre quadrature on v1z > v2z"""
    x1, y1, z1, x2, y2, z2 = sp.symbols('x1 y1 z1 x2 y2 z2', real=True)
    v1 = [x1, y1, z1]
    vv2 = [x2, y2, z2]
    gzv = z1 - z2
    v1p = [x1, y1, z1 - Av * gzv]
    c1 = dot(v1, v1) / (2 * akv)
    c2 = dot(vv2, vv2) / (2 * aiv)
    wgt = {'0': 1, 'k': S2(c1), 'i': S2(c2)}[part]
    core = dot(phis(v1)[a - 1], [p - q for p, q in zip(phis(v1p)[b - 1], phis(v1)[b - 1])]) * gzv / 3 * wgt
    poly = sp.Poly(sp.expand(core), x1, y1, x2, y2, z1, z2)
    # Gauss-Legendre in z1 on [-12 sqrt(a_k), 12 sqrt(a_k)] and in u = z1 - z2 on [0, 12 s] (the
    # integrand is smooth there and below 1e-30 beyond)
    xs, ws = NODES
    L1, U = 12 * math.sqrt(akv), 12 * math.sqrt(akv + aiv)
    z1n = [L1 * x for x in xs]
    un = [U * (x + 1) / 2 for x in xs]
    c = L1 * U / 2 / (2 * math.pi * math.sqrt(akv * aiv))
    pts = [(z, z - u, c * wz * wu * math.exp(-z * z / (2 * akv) - (z - u)**2 / (2 * aiv)))
           for z, wz in zip(z1n, ws) for u, wu in zip(un, ws)]
    cache = {}

    def zint(p, q):
        """Int dz1 Int_{z2 < z1} dz2 z1^p z2^q N(z1; a_k) N(z2; a_i)"""
        if (p, q) not in cache:
            cache[(p, q)] = math.fsum(w * z**p * y**q for z, y, w in pts)
        return cache[(p, q)]

    terms = []
    for (p1, p2, p3, p4, p5, p6), coef in poly.terms():
        m = (gauss_moment(p1, akv) * gauss_moment(p2, akv) * gauss_moment(p3, aiv) * gauss_moment(p4, aiv))
        if m != 0:
            terms.append(float(sp.Rational(coef) * sp.Rational(m)) * zint(p5, p6))
    return 4 * math.pi * math.fsum(terms)


def diffusion(K, m, sig, n, eps, T, a2, zeta):
    """D_k of the two-moment correlation (weight f_k, partners f_i), exact arithmetic: Lam =
    -K G^-1 - (zeta_k/2) diag(1, 3), m(0) = G (1, 0), D_k = (Lam^-1 m(0))_1"""
    out = []
    M = len(m)
    for k in range(M):
        akv = T[k] / m[k]
        Km = sp.zeros(2, 2)
        for i in range(M):
            if n[i] == 0:
                continue
            aiv = T[i] / m[i]
            Av = m[i] / (m[i] + m[k]) * (1 + eps)
            sk = ((sig[k] + sig[i]) / 2)**2 * n[i]
            sub = {ak: akv, s: sp.sqrt(akv + aiv), A: Av}
            for b in range(2):
                for a in range(2):
                    Km[b, a] += sk * (K[(b + 1, a + 1, '0')] + a2[i] * K[(b + 1, a + 1, 'i')] +
                                      a2[k] * K[(b + 1, a + 1, 'k')]).subs(sub)
        G = sp.Matrix([[akv, 5 * akv**2 * (1 + a2[k])], [5 * akv**2 * (1 + a2[k]), 35 * akv**3 * (1 + 3 * a2[k])]])
        Lam = -Km * G.inv() - zeta[k] / 2 * sp.diag(1, 3)
        m0 = G[:, 0]
        out.append(sp.N((Lam.inv() * m0)[0], 25))
    return out


def reference_values(K):
    """the values asserted in tests/t414-sonine-diffusion.c"""
    R = sp.Rational
    # binary mixture at an unequal state
    D = diffusion(K, [1, 10], [1, 2], [1, R(1, 2)], R(7, 10), [R(13, 10), R(29, 10)], [R(3, 100), R(-5, 100)],
                  [R(2, 5), R(9, 10)])
    print('t414 binary (m 1, 10; sigma 1, 2; n 1, 0.5; eps 0.7; T 1.3, 2.9; a2 0.03, -0.05; zeta 0.4, 0.9): '
          'D = %s, %s' % (D[0], D[1]))
    # one species, eps = 0.5, T = 1, n sigma^2 = 1: van Noije & Ernst a2 and zeta = xi (1 + 3 a2/16);
    # D_M = T/m / (nu - xi/2) the Maxwellian level
    e = R(1, 2)
    a2v = 16 * (1 - e) * (1 - 2 * e**2) / (81 - 17 * e + 30 * e**2 * (1 - e))
    xi = R(4, 3) * sp.sqrt(sp.pi) * (1 - e**2)
    nu = R(4, 3) * sp.sqrt(sp.pi) * (1 + e)
    DM = 1 / (nu - xi / 2)
    D1 = diffusion(K, [1], [1], [1], e, [1], [a2v], [xi * (1 + 3 * a2v / 16)])[0]
    D0 = diffusion(K, [1], [1], [1], e, [1], [0], [xi])[0]
    print('t414 one species eps = 1/2, a2 = %s: D/D_M = %s (a2 = 0, zeta = xi: %s)' % (a2v, sp.N(D1 / DM, 20),
                                                                                   sp.N(D0 / DM, 20)))
    # the one-moment truncations (first Sonine) of the same: weight f_k, and Maxwellian weight
    print('one moment, weight f_k: D/D_M = 1/(1 + 3 a2/16) =', sp.N(1 / (1 + 3 * a2v / 16), 15),
          '; Maxwellian weight: 1/(1 - (4 - 3 eps) a2/(16 (1 + eps))) =',
          sp.N(1 / (1 - (4 - 3 * e) * a2v / (16 * (1 + e))), 15))


def main():
    K = closed_forms()
    pre = -sp.Rational(4, 3) * sp.sqrt(2 * sp.pi) * A
    print('K_ba / pre, pre = -(4/3) sqrt(2 pi) w A, s^2 = a_k + a_i (parts: 0 Maxwellian, k: coefficient of '
          'a2_k, i: coefficient of a2_i)')
    for key in sorted(K):
        print(key, sp.factor(sp.simplify(K[key] / pre)))
    # the Maxwellian part is the K of sonine_diffusion.cpp
    old = {
        (1, 1): ak * s,
        (1, 2): ak**2 * (5 * ai + 6 * ak) / s,
        (2, 1): ak * (4 * A**2 * s**4 - A * (5 * ai**2 + 19 * ai * ak + 14 * ak**2) + 15 * ai * ak + 18 * ak**2) / s,
        (2, 2): ak**2 * (4 * A**2 * s**4 * (5 * ai + 8 * ak) - A * (25 * ai**3 + 153 * ai**2 * ak + 240 * ai * ak**2 +
                                                               112 * ak**3) + ak * (105 * ai**2 + 252 * ai * ak +
                                                                                    144 * ak**2)) / s**3,
    }
    # the a2 terms as written in sonine_diffusion.cpp: coefficients of a2_i (the partner's f_i) and of
    # a2_k (the weight f_k of the trial functions), per pre
    c0 = 90 * ak**3 + 231 * ak**2 * ai + 184 * ak * ai**2 + 40 * ai**3
    new = {
        (1, 1, 'i'): -ak * ai**2 / (8 * s**3),
        (1, 2, 'i'): -ak**2 * ai**2 * (5 * ai + 2 * ak) / (8 * s**5),
        (2, 1, 'i'): 3 * ak * ai**2 * (4 * A**2 * s**4 - A * s**2 * (2 * ak + 5 * ai) - ak * (2 * ak + 5 * ai)) / (8 * s**5),
        (2, 2, 'i'): 3 * ak**2 * ai**2 * (4 * A**2 * s**4 * (4 * ak + 5 * ai) - A * s**2 * (8 * ak**2 + 24 * ak * ai + 25 * ai**2) -
                                         ak * (8 * ak**2 + 28 * ak * ai + 35 * ai**2)) / (8 * s**7),
        (1, 1, 'k'): ak**2 * (3 * ak + 4 * ai) / (8 * s**3),
        (1, 2, 'k'): ak**2 * c0 / (8 * s**5),
        (2, 1, 'k'): 3 * ak**2 * (4 * A**2 * s**4 * (5 * ak + 4 * ai) - A * s**2 * (7 * ak + 4 * ai) * (10 * ak + 11 * ai) + c0) /
                     (8 * s**5),
        (2, 2, 'k'): ak**2 * (4 * A**2 * s**4 * (280 * ak**3 + 555 * ak**2 * ai + 312 * ak * ai**2 + 40 * ai**3) -
                              A * s**2 * (3920 * ak**4 + 10880 * ak**3 * ai + 10059 * ak**2 * ai**2 + 3272 * ak * ai**3 +
                                          200 * ai**4) +
                              9 * ak * (560 * ak**4 + 2020 * ak**3 * ai + 2659 * ak**2 * ai**2 + 1484 * ak * ai**3 +
                                        280 * ai**4)) / (8 * s**7),
    }
    ok = True
    for key, expr in sorted(new.items()):
        d = sp.simplify(K[key] - pre * expr.subs(ai, s**2 - ak))
        print('K%d%d, coefficient of a2_%s - sonine_diffusion.cpp:' % key, d)
        ok &= d == 0
    # one species (a_k = a_i, s^2 = 2 a_k): the partner part is K11^(0) (-a2/32), the momentum transfer
    # of Brey, Ruiz-Montero, Cubero and Garcia-Rojo (2000); the weight f_k adds 7 a2/32: in all
    # K11 = K11^(0) (1 + 3 a2/16), the correction of the cooling rate
    r = sp.simplify((K[(1, 1, 'i')] / K[(1, 1, '0')]).subs(s, sp.sqrt(2 * ak)))
    rk = sp.simplify((K[(1, 1, 'k')] / K[(1, 1, '0')]).subs(s, sp.sqrt(2 * ak)))
    print('one species: K11 a2_i part / K11 =', r, '; a2_k part / K11 =', rk)
    ok &= r == sp.Rational(-1, 32) and rk == sp.Rational(7, 32)
    # the Gram matrix of the weight f_k: <v_x^2 v^2>, <v_x^2 v^4> with the first Sonine f_k
    x = sp.symbols('x', positive=True)
    fk = sp.exp(-x) * sp.sqrt(x) * (1 + a2k * S2(x)) / sp.gamma(sp.Rational(3, 2))
    c4 = sp.simplify(sp.integrate(x**2 * fk, (x, 0, sp.oo)))
    c6 = sp.simplify(sp.integrate(x**3 * fk, (x, 0, sp.oo)))
    # v^2 = 2 a c^2: <v_x^2 v^2> = (4 a^2/3) <c^4>, <v_x^2 v^4> = (8 a^3/3) <c^6>
    g12, g22 = sp.expand(sp.Rational(4, 3) * c4), sp.expand(sp.Rational(8, 3) * c6)
    print('Gram: <v_x^2 v^2>/a^2 =', g12, ', <v_x^2 v^4>/a^3 =', g22)
    ok &= sp.simplify(g12 - 5 * (1 + a2k)) == 0 and sp.simplify(g22 - 35 * (1 + 3 * a2k)) == 0
    for (b, a), expr in old.items():
        d = sp.simplify(K[(b, a, '0')] - pre * expr.subs(ai, s**2 - ak))
        print('Maxwellian K%d%d - sonine_diffusion.cpp:' % (b, a), d)
        ok &= d == 0
    # quadrature check at a few points
    worst = 0.0
    for (akv, aiv, Av) in [(sp.Rational(13, 10), sp.Rational(29, 100), sp.Rational(17, 10)),
                           (sp.Rational(1, 1), sp.Rational(1, 1), sp.Rational(3, 4)),
                           (sp.Rational(1, 50), sp.Rational(7, 5), sp.Rational(99, 50))]:
        for key in sorted(K):
            b, a, part = key
            exact = K[key].subs({ak: akv, s: sp.sqrt(akv + aiv), A: Av})
            ex = float(sp.N(exact, 20))
            q = quadrature(b, a, part, akv, aiv, Av)
            rel = abs(q - ex) / abs(ex)
            worst = max(worst, float(rel))
            print('a_k %s a_i %s A %s K%d%d[%s]: closed %.15e quadrature %.15e rel %.1e' %
                  (akv, aiv, Av, b, a, part, float(ex), float(q), float(rel)))
    print('worst relative difference closed form / quadrature: %.1e' % worst)
    reference_values(K)
    ok &= worst < 1e-12
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
