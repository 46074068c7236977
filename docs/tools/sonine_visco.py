#!/usr/bin/env python3
"""First Sonine collision moments with viscoelastic (impact-velocity dependent) restitution
(src/theory/sonine.cpp, visco pair terms; docs/physics-sonine.md Sec. 6).

For the pair (k, i), per unit w = n_i sigma_ki^2 g2_ki, the rates of <v^2> and <v^4> of species k
    R[psi] = 4 pi E[ Theta(g_z) g_z (psi(v1') - psi(v1)) (1 + a2_k S2(c1^2) + a2_i S2(c2^2)) ],
    v1' = v1 - A(g_z) g_z e_z,   A(g_z) = mu (1 + eps(g_z)),
with the Gaussian (G, g) variables of docs/physics-sonine.md Sec. 2. The integrand is a polynomial
in G, g_x, g_y, g_z and A; A depends on g_z only, so every term is a Gaussian moment of G, g_x, g_y
times a half-line moment H_jk = E[g_z^k A(g_z)^j Theta(g_z)]. With A = 2 mu p, p = (1 + eps)/2,
    H_jk = (2 mu)^j h_k (1 + D_jk),  h_k = E[g_z^k Theta(g_z)],
    D_jk = <p^j - 1>_k = Int_0^inf u^((k-1)/2) e^-u (p(x)^j - 1) du / Gamma((k+1)/2),
    x = z u^(1/20),  z = sqrt(beta) (2 s^2)^(1/20)      (u = g_z^2 / (2 s^2)),
and R = R(eps = 1) + sum_jk C_jk D_jk. With eps = 1 + sum_n h_n x^n (Bodrova & Osinsky App. A),
p^j - 1 = sum_n c_jn x^n and D_jk = sum_n c_jn z^n Gamma((k+1)/2 + n/20) / Gamma((k+1)/2).

Prints the list of (j, k) needed, the C code of the C_jk (per unit w), and checks:
  1. constant A reproduces the closed forms of sonine.cpp (R2, R4);
  2. the series D_jk against direct quadrature (mpmath) at several z, to 1e-8;
  3. the whole R2, R4 with eps(g_z) against a direct 1-D quadrature over g_z of the same
     integrand (Gaussian moments of the rest done exactly) at one unequal state;
  4. one species at leading order in beta: the cooling law of docs/physics.md (B = 6.5536217 beta n
     sigma^2) and the quasi-static a2 = c_a beta T^(1/10) that tests/t417-sonine-visco.c asserts.
Run: python3 docs/tools/sonine_visco.py   (sympy + mpmath; about a minute)
"""
import sys

import mpmath as mp
import sympy as sp

ak, ai, mu = sp.symbols('ak ai mu', positive=True)
a2k, a2i = sp.symbols('a2k a2i')
Gx, Gy, Gz, gx, gy, gz, AA = sp.symbols('Gx Gy Gz gx gy gz AA', real=True)
s2 = ak + ai
b = ak * ai / s2

H = [1.0, 0.0, -1.1534488580952887991, 0.0, 0.79826656094479540625, 0.26666666666666666667,
     -0.5228825680884149639, -0.46137954323811551965, 0.34874267526038503473, 0.45235105120205073021,
     -0.14643146535257773367, -0.36772830083814517031, -0.043248983015276303036, 0.28180423421853528868,
     0.14785258773191059115, -0.17944206016930798518, -0.17846603342860487393, 0.065933589474841266813,
     0.17135861854697103935, 0.025249822049520526812, -0.1379234993765172905]


def S2(x):
    return x**2 / 2 - sp.Rational(5, 2) * x + sp.Rational(15, 8)


def gauss_moment(p, var):
    if p % 2:
        return 0
    return var**(p // 2) * sp.factorial2(p - 1)


def half_moment(q):
    return s2**sp.Rational(q, 2) * sp.sqrt(2)**q * sp.gamma(sp.Rational(q + 1, 2)) / (2 * sp.sqrt(sp.pi))


v1 = [Gx + ak / s2 * gx, Gy + ak / s2 * gy, Gz + ak / s2 * gz]
v2 = [Gx - ai / s2 * gx, Gy - ai / s2 * gy, Gz - ai / s2 * gz]
v1p = [v1[0], v1[1], v1[2] - AA * gz]
sq = lambda v: sum(c * c for c in v)
weight = 1 + a2k * S2(sq(v1) / (2 * ak)) + a2i * S2(sq(v2) / (2 * ai))


def moments(psi):
    """R[psi] per unit w as {(j, k): coefficient of H_jk}"""
    expr = sp.expand(gz * (psi(v1p) - psi(v1)) * weight)
    poly = sp.Poly(expr, Gx, Gy, Gz, gx, gy, gz, AA)
    out = {}
    for (px, py, pz, qx, qy, qz, j), c in poly.terms():
        m = gauss_moment(px, b) * gauss_moment(py, b) * gauss_moment(pz, b) * gauss_moment(qx, s2) * gauss_moment(qy, s2)
        if m == 0:
            continue
        out[(j, qz)] = out.get((j, qz), 0) + 4 * sp.pi * c * m
    return {key: sp.factor(sp.simplify(v)) for key, v in out.items()}


R2c = moments(lambda v: sq(v))
R4c = moments(lambda v: sq(v)**2)
keys = sorted(set(R2c) | set(R4c))
print('(j, k) needed:', keys)

# 1. constant A against the closed forms of sonine.cpp (per unit w; R = sqrt(2 pi) in the header)
A, s = sp.symbols('A s', positive=True)
Rs = sp.sqrt(2 * sp.pi)
sub = {ak: sp.Rational(13, 10), ai: sp.Rational(29, 100), a2k: sp.Rational(3, 100), a2i: sp.Rational(-5, 100)}
Aval = sp.Rational(7, 10) * sp.Rational(10, 11) * 2 * sp.Rational(17, 20)
sv = sp.sqrt(sub[ak] + sub[ai])
def const(Rc):
    return sum(c.subs(sub) * Aval**j * half_moment(k).subs(sub) for (j, k), c in Rc.items())
akv, aiv, a2kv, a2iv = sub[ak], sub[ai], sub[a2k], sub[a2i]
R2ref = Rs * Aval * (4 * sv * (Aval * sv**2 - 2 * akv) + a2kv * akv**2 * (3 * Aval * sv**2 - 6 * akv - 8 * aiv) / (2 * sv**3)
                     + a2iv * aiv**2 * (3 * Aval * sv**2 + 2 * akv) / (2 * sv**3))
Pk = (30 * Aval**3 * sv**6 - Aval**2 * (120 * akv**3 + 336 * akv**2 * aiv + 312 * akv * aiv**2 + 96 * aiv**3)
      + Aval * (210 * akv**3 + 561 * akv**2 * aiv + 483 * akv * aiv**2 + 132 * aiv**3)
      - (180 * akv**3 + 462 * akv**2 * aiv + 368 * akv * aiv**2 + 80 * aiv**3))
Pi = 30 * Aval**3 * sv**6 - 24 * Aval**2 * akv * sv**4 + Aval * (6 * akv**3 + 21 * akv**2 * aiv + 15 * akv * aiv**2) + 4 * akv**3 + 10 * akv**2 * aiv
R4ref = Rs * Aval * (8 * (Aval * sv**2 - 2 * akv) * (2 * Aval**2 * sv**4 - 4 * Aval * akv * sv**2 + 6 * akv**2 + 5 * akv * aiv) / sv
                     + a2kv * akv**2 * Pk / sv**5 + a2iv * aiv**2 * Pi / sv**5)
e2 = float(abs(const(R2c) - R2ref) / abs(R2ref))
e4 = float(abs(const(R4c) - R4ref) / abs(R4ref))
print('check 1 (constant A = closed forms of sonine.cpp): rel. diff R2 %.1e, R4 %.1e' % (e2, e4))
ok = e2 < 1e-14 and e4 < 1e-14

# C_jk = c_jk (2 mu)^j h_k, split into the a2-free, a2_k and a2_i parts; s = sqrt(ak + ai) kept symbolic
ssym = sp.Symbol('s', positive=True)
def coeffs(Rc):
    res = {}
    for (j, k), c in Rc.items():
        C = sp.expand(c * (2 * mu)**j * half_moment(k))
        parts = []
        for part in (C.subs({a2k: 0, a2i: 0}), C.diff(a2k), C.diff(a2i)):
            p = sp.simplify(part / sp.sqrt(2 * sp.pi))   # per unit w' = sqrt(2 pi) w, as in pair_terms
            p = p.subs(sp.sqrt(ak + ai), ssym)
            parts.append(sp.simplify(p))
        res[(j, k)] = parts
    return res

C2 = coeffs(R2c)
C4 = coeffs(R4c)

# 2. series D_jk against quadrature
mp.mp.dps = 30
def peps(x):
    return (1 + (1 + sum(H[n] * x**n for n in range(1, 21)))) / 2
def pcoef(j):
    poly = [1.0]
    base = [1.0] + [H[n] / 2 for n in range(1, 21)]   # p(x) = 1 + d/2
    for _ in range(j):
        new = [0.0] * (len(poly) + 20)
        for a, ca in enumerate(poly):
            for c, cb in enumerate(base):
                new[a + c] += ca * cb
        poly = new
    poly[0] -= 1.0
    return poly
def D_series(j, k, z):
    c = pcoef(j)
    a = mp.mpf(k + 1) / 2
    return sum(c[n] * mp.mpf(z)**n * mp.gamma(a + mp.mpf(n) / 20) / mp.gamma(a) for n in range(1, len(c)))
def D_quad(j, k, z):
    a = mp.mpf(k + 1) / 2
    f = lambda u: u**(a - 1) * mp.exp(-u) * (peps(z * u**(mp.mpf(1) / 20))**j - 1)
    return mp.quad(f, [0, 1, 10, 40, 120, mp.inf]) / mp.gamma(a)
worst = 0.0
for z in (0.02, 0.1, 0.2, 0.3):
    for (j, k) in keys:
        ds, dq = D_series(j, k, z), D_quad(j, k, z)
        worst = max(worst, float(abs(ds - dq) / abs(dq)))
print('check 2 (series D_jk = quadrature, z = 0.02..0.3): max rel. diff %.1e' % worst)
ok = ok and worst < 1e-8

# 3. full R2, R4 with eps(g_z): sum C_jk D_jk + constant(eps = 1) against a 1-D quadrature over g_z of
#    the integrand with the Gaussian moments of G, g_x, g_y done (exact polynomial in g_z, A)
beta = 0.05
muv = sp.Rational(10, 11)
sub = {ak: sub[ak], ai: sub[ai]}
num = {ak: sub[ak], ai: sub[ai], mu: muv, ssym: sv}
def via_D(Rc, Cc, a2kv_, a2iv_):
    z = float(beta**0.5 * (2 * (sub[ak] + sub[ai]))**0.05)
    el = sum(c.subs(sub).subs({a2k: a2kv_, a2i: a2iv_}) * (2 * muv)**j * half_moment(k).subs(sub) for (j, k), c in Rc.items())
    corr = 0
    for (j, k), parts in Cc.items():
        Cv = parts[0] + a2kv_ * parts[1] + a2iv_ * parts[2]
        corr += float(Cv.subs(num)) * float(D_series(j, k, z))
    return float(el) + float(sp.sqrt(2 * sp.pi)) * corr
def via_quad(Rc, a2kv_, a2iv_):
    sg = float(sv)
    tot = mp.mpf(0)
    for (j, k), c in Rc.items():
        cv = float(c.subs(sub).subs({a2k: a2kv_, a2i: a2iv_}))
        f = lambda g: g**k * (float(muv) * (1 + 2 * peps(mp.sqrt(beta) * g**0.1) - 1))**j * mp.exp(-g * g / (2 * sg * sg)) / mp.sqrt(2 * mp.pi * sg * sg)
        tot += cv * mp.quad(f, [0, 0.5, 2, 6, 20, mp.inf])
    return float(tot)
worst3 = 0.0
for (a2kv_, a2iv_) in ((0, 0), (0.03, -0.05)):
    for Rc, Cc in ((R2c, C2), (R4c, C4)):
        x, y = via_D(Rc, Cc, a2kv_, a2iv_), via_quad(Rc, a2kv_, a2iv_)
        worst3 = max(worst3, abs(x - y) / abs(y))
print('check 3 (R2, R4 with eps(g_z): series = quadrature, beta = 0.05): max rel. diff %.1e' % worst3)
ok = ok and worst3 < 1e-8

# 4. one species (m = 1, T): leading order in beta. d = eps - 1 = h_2 x^2 + O(x^4) (h_1 = 0), so
#    D_jk = j (h_2/2) z^2 Gamma((k+1)/2 + 1/10)/Gamma((k+1)/2) + O(z^4), z^2 = beta (4 T)^(1/10).
#    zeta = c_z beta T^(1/10) nu_T, and the quasi-static a2 (da2/dt = Phi_0 + Phi_1 a2 = 0, Phi_0 = O(beta),
#    Phi_1 the elastic relaxation rate) a2_qs = c_a beta T^(1/10) + O(beta^2).
Tn = sp.Symbol('T', positive=True)
one = {ak: Tn, ai: Tn, mu: sp.Rational(1, 2), ssym: sp.sqrt(2 * Tn)}
def lead_D(j, k):
    return j * sp.Float(H[2]) / 2 * (4 * Tn)**sp.Rational(1, 10) * sp.gamma(sp.Rational(k + 1, 2) + sp.Rational(1, 10)) / sp.gamma(sp.Rational(k + 1, 2))
R20 = sum(parts[0].subs(one) * lead_D(j, k) for (j, k), parts in C2.items())      # per unit beta, w'
R40 = sum(parts[0].subs(one) * lead_D(j, k) for (j, k), parts in C4.items())
zeta_l = -R20 / (3 * Tn)
pm_l = R40 / (15 * Tn**2) + 2 * zeta_l
# elastic relaxation: d Phi/d a2 at eps = 1 (both a2 equal for one species), constant A = 1
el4 = sum((c.diff(a2k) + c.diff(a2i)).subs({ak: Tn, ai: Tn}) * half_moment(k).subs({ak: Tn, ai: Tn}) for (j, k), c in R4c.items())
el2 = sum((c.diff(a2k) + c.diff(a2i)).subs({ak: Tn, ai: Tn}) * half_moment(k).subs({ak: Tn, ai: Tn}) for (j, k), c in R2c.items())
phi1 = (el4 / (15 * Tn**2) - 2 * el2 / (3 * Tn)) / sp.sqrt(2 * sp.pi)  # per unit w'
ca = sp.N(sp.simplify(-pm_l / phi1 / Tn**sp.Rational(1, 10)), 12)
cz = sp.N(sp.simplify(zeta_l / sp.sqrt(Tn) / Tn**sp.Rational(1, 10)), 12)
cphi = sp.N(sp.simplify(phi1 / sp.sqrt(Tn)), 12)
print('check 4 (one species, m = 1, leading order in beta; w\' = sqrt(2 pi) n sigma^2 g2):')
print('  zeta = %s w\' beta T^(3/5),  Phi_1 = %s w\' T^(1/2),  a2_qs = %s beta T^(1/10)' % (cz, cphi, ca))
# Maxwellian cooling law of t508 (B = 6.5536217 beta n sigma^2 m^(-3/5): dT/dt = -B T^(8/5))
print('  B/(beta n) = %.7f (t508: 6.5536217)' % float(cz * sp.sqrt(2 * sp.pi)))
ok = ok and abs(float(cz * sp.sqrt(2 * sp.pi)) - 6.5536217) < 1e-6

# C code of the corrections
if '--code' in sys.argv:
    for name, Cc in (('R2', C2), ('R4', C4)):
        for (j, k), parts in sorted(Cc.items()):
            for tag, p in zip(('0', 'k', 'i'), parts):
                if p != 0:
                    print('  %s%s += D[%d][%d] * (%s);' % (name, tag, j, k, sp.ccode(sp.horner(sp.expand(p)))))
print('OK' if ok else 'FAILED')
sys.exit(0 if ok else 1)
