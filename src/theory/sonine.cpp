/* sonine.cpp - first Sonine approximation of a polydisperse granular gas of inelastic hard spheres
 * (3-D, constant, matrix or viscoelastic restitution): cooling rates zeta_k corrected by the Sonine coefficients
 * a2_k, the fourth-moment balance that fixes a2_k, the homogeneous cooling state and the
 * trajectories T_k(t), a2_k(t). Derivation, sources and checks: docs/physics-sonine.md.
 *
 * Species k has f_k = n_k phi_k [1 + a2_k S2(c^2)], c^2 = m_k v^2/(2 T_k), S2(x) = x^2/2 - 5x/2 + 15/8
 * (Garzo & Dufty, Phys. Rev. E 60, 5706 (1999), Eq. 3.1-3.3, for every species of the mixture).
 * The pair (k, i), with a_k = T_k/m_k, s^2 = a_k + a_i, mu = m_i/(m_i+m_k), A = mu (1 + eps_ki) and
 * w = n_i sigma_ki^2 g2_ki, contributes to the rates of <v^2> and <v^4> of species k
 *   R2 = R w A [4 s (A s^2 - 2 a_k) + a2_k a_k^2 (3 A s^2 - 6 a_k - 8 a_i)/(2 s^3)
 *                                  + a2_i a_i^2 (3 A s^2 + 2 a_k)/(2 s^3)]
 *   R4 = R w A [8 (A s^2 - 2 a_k)(2 A^2 s^4 - 4 A a_k s^2 + 6 a_k^2 + 5 a_k a_i)/s
 *                + a2_k a_k^2 P_k/s^5 + a2_i a_i^2 P_i/s^5]          (R = sqrt(2 pi); P_k, P_i below)
 * to first order in a2 (products a2_k a2_i dropped), from the Gaussian moments of the bi-Maxwellian
 * written in the relative velocity g and the part of the centre-of-mass velocity independent of g.
 * Then zeta_k = -sum_i R2/(3 a_k) (dT_k/dt = -zeta_k T_k) and, since <v^4>_k = 15 a_k^2 (1 + a2_k),
 *   da2_k/dt = Phi_k = sum_i R4/(15 a_k^2) + 2 zeta_k (1 + a2_k)      (linear in a2).
 * One species gives van Noije & Ernst's a2 (Granular Matter 1, 57 (1998), Eq. 16) and
 * zeta = zeta_0 (1 + 3 a2/16) (Brilliantov & Poeschel, Kinetic Theory of Granular Gases (2004), Eq. 7.27).
 * The factor A s^2 - 2 a_k = -2 a_k [(1 - mu)(1 - T_i/T_k) + (1 - eps)/2 Gamma] is written without
 * cancellation, Gamma = mu + (1 - mu) T_i/T_k, as in cooling.cpp: eps -> 1 stays exact.
 * Viscoelastic restitution (rates and trajectories only; no HCS): the elastic pair terms plus
 * corrections linear in the moments <p^j - 1>_k of p = (1 + eps(g_n))/2 (pair_terms_visco,
 * docs/physics-sonine.md Sec. 6). */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multiroots.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <complex>
#include <cstdio>
#include <cstring>
#include <ctime>

#include "theory/theory_simd.h"
#include <numeric>

namespace {

using namespace gran;

const double SQ2PI = 2.5066282746310002;

/* Per-species sums of one pass over the ordered pairs (k, i), n_i > 0. */
struct SPass {
  std::vector<double> z0;   /* Maxwellian zeta_k */
  std::vector<double> z1;   /* a2 part of zeta_k */
  std::vector<double> phi;  /* da2_k/dt */
  std::vector<double> diag; /* d phi_k / d a2_k */
  std::vector<double> off;  /* sum_{i != k} d phi_k / d a2_i */
  std::vector<double> zdg;  /* d zeta_k / d a2_k */
  std::vector<double> nu;   /* collision frequency scale (for the residuals) */
  /* the Maxwellian pass of hcs.cpp at the same T (cooling_pass: xi_k = z0_k, d_k, l_k, nu_k =
   * (8/3) nu above), so that the temperature step needs no pass of its own */
  std::vector<double> d, l;
  int status = GRAN_SUCCESS; /* viscoelastic pass: the moments' quadrature may fail */
};

/* Contributions of partner i to the sums of species k (own): w = sqrt(2 pi) n_i sigma_ki^2 g2,
 * mu = m_i/(m_i+m_k), r = T_i/T_k, omr = 1 - r, s = sqrt(a_k + a_i), is = 1/s. */
template <typename V> struct PairOut {
  V zm, czo, czp, pm, cpo, cpp;
  V dm, lm; /* d zm/d log T_k and d zm/d log T_i (the Maxwellian Jacobian terms of cooling_pass) */
};
template <typename V, typename S = double>
static inline PairOut<V> pair_terms(V w, S p, S q, V mu, V omu, V r, V omr, V ak, V ai, V iak, V s, V is) {
  PairOut<V> o;
  const V Gam = mu + r * omu, Bm = omu * omr + q * Gam; /* Bm = 1 - p Gamma = (2 a_k - A s^2)/(2 a_k) */
  const V A = S(2.0) * mu * p;
  const V s2 = s * s, is2 = is * is, is3 = is2 * is, is5 = is3 * is2;
  const V As2 = A * s2, G2 = S(2.0) * p * Gam; /* A s^2 / a_k */
  const V wA = w * A;
  o.zm = (S(8.0) / S(3.0)) * wA * s * Bm;
  {
    const V t1 = S(0.5) * Bm * is, t2 = s * p * r * omu; /* dBm/d log T_k = p r (1 - mu) */
    o.dm = (S(8.0) / S(3.0)) * wA * (ak * t1 + t2);
    o.lm = (S(8.0) / S(3.0)) * wA * (ai * t1 - t2);
  }
  o.pm = (S(16.0) / S(15.0)) * wA * ak * is * Bm * (G2 * (S(4.0) - S(2.0) * G2) - S(1.0));
  o.czo = (-S(1.0) / S(6.0)) * wA * ak * (S(3.0) * As2 - S(6.0) * ak - S(8.0) * ai) * is3;
  const V ai2 = ai * ai, ak2 = ak * ak, s4 = s2 * s2, s6 = s4 * s2;
  o.czp = (-S(1.0) / S(6.0)) * wA * ai2 * (S(3.0) * As2 + S(2.0) * ak) * is3 * iak;
  /* P_k, P_i of the header (Horner in A and in a_i) */
  const V C2 = ((S(96.0) * ai + S(312.0) * ak) * ai + S(336.0) * ak2) * ai + S(120.0) * ak2 * ak;
  const V C1 = ((S(132.0) * ai + S(483.0) * ak) * ai + S(561.0) * ak2) * ai + S(210.0) * ak2 * ak;
  const V C0 = ((S(80.0) * ai + S(368.0) * ak) * ai + S(462.0) * ak2) * ai + S(180.0) * ak2 * ak;
  const V Pk = ((S(30.0) * s6 * A - C2) * A + C1) * A - C0;
  const V Pi = ((S(30.0) * s6 * A - S(24.0) * ak * s4) * A + ak * ((S(15.0) * ai + S(21.0) * ak) * ai + S(6.0) * ak2)) * A +
               ak2 * (S(4.0) * ak + S(10.0) * ai);
  const V c4o = (S(1.0) / S(15.0)) * wA * Pk * is5;
  const V c4p = (S(1.0) / S(15.0)) * wA * ai2 * Pi * is5 * iak * iak;
  o.cpo = c4o + S(2.0) * o.czo + S(2.0) * o.zm; /* d Phi/d a2_k: R4, 2 zeta_1, 2 zeta_0 a2_k */
  o.cpp = c4p + S(2.0) * o.czp;
  return o;
}

using namespace gran_theory_simd;

/* Viscoelastic pair: the elastic pair terms (eps = 1) plus the corrections linear in the moments
 * D_jk = <p^j - 1>_k of viscoelastic.cpp (p = (1 + eps(g_n))/2): R = R(eps = 1) + w sum_jk C_jk D_jk,
 * C_jk per unit w = sqrt(2 pi) n_i sigma_ki^2 g2 from docs/tools/sonine_visco.py (split into the
 * a2-free, a2_k and a2_i parts; s^2 = a_k + a_i, mu = m_i/(m_k + m_i)). */
static PairOut<double> pair_terms_visco(double w, double mu, double omu, double r, double omr, double ak, double ai,
                                        double s, const double D[5][10]) {
  PairOut<double> o = pair_terms<double>(w, 1.0, 0.0, mu, omu, r, omr, ak, ai, 1.0 / ak, s, 1.0 / s);
  const double is = 1.0 / s, is3 = is * is * is, is5 = is3 * is * is, s2 = ak + ai;
  const double ak2 = ak * ak, ak3 = ak2 * ak, ak4 = ak3 * ak, ak5 = ak4 * ak, ai2 = ai * ai;
  const double m1 = mu, m2 = mu * mu, m3 = m2 * mu, m4 = m2 * m2;
  double R20 = 0, R2k = 0, R2i = 0, R40 = 0, R4k = 0, R4i = 0;
  R20 += D[1][3] * (-16 * ak * m1 * s);
  R2k += D[1][3] * ((24 * ai * ak2 - 6 * ak3) * m1 * is3);
  R2i += D[1][3] * (-30 * ai2 * ak * m1 * is3);
  R2k += D[1][5] * ((-32 * ai * ak2 + 48 * ak3) * m1 * is3);
  R2i += D[1][5] * (80 * ai2 * ak * m1 * is3);
  R2k += D[1][7] * (-48 * ak3 * m1 * is3);
  R2i += D[1][7] * (-48 * ai2 * ak * m1 * is3);
  R20 += D[2][3] * (16 * s2 * s2 * m2 * is);
  R2k += D[2][3] * (6 * ak2 * m2 * is);
  R2i += D[2][3] * (6 * ai2 * m2 * is);
  R2k += D[2][5] * (-48 * ak2 * m2 * is);
  R2i += D[2][5] * (-48 * ai2 * m2 * is);
  R2k += D[2][7] * (48 * ak2 * m2 * is);
  R2i += D[2][7] * (48 * ai2 * m2 * is);
  R40 += D[1][3] * ((-160 * ai * ak2 - 64 * ak3) * m1 * is);
  R4k += D[1][3] * ((ai * (ai * (-160 * ai * ak2 + 288 * ak3) + 36 * ak4) + 8 * ak5) * m1 * is5);
  R4i += D[1][3] * (ai2 * (-300 * ai * ak2 + 120 * ak3) * m1 * is5);
  R40 += D[1][5] * (-128 * ak3 * m1 * is);
  R4k += D[1][5] * ((ai * (-1024 * ai * ak3 + 672 * ak4) + 16 * ak5) * m1 * is5);
  R4i += D[1][5] * (ai2 * (800 * ai * ak2 - 880 * ak3) * m1 * is5);
  R4k += D[1][7] * ((-1632 * ai * ak4 + 384 * ak5) * m1 * is5);
  R4i += D[1][7] * (ai2 * (-480 * ai * ak2 + 1536 * ak3) * m1 * is5);
  R4k += D[1][9] * (-768 * ak5 * m1 * is5);
  R4i += D[1][9] * (-768 * ai2 * ak3 * m1 * is5);
  R40 += D[2][3] * ((ai * (160 * ai * ak + 224 * ak2) + 64 * ak3) * m2 * is);
  R4k += D[2][3] * ((ai * (-176 * ai * ak2 - 4 * ak3) - 8 * ak4) * m2 * is3);
  R4i += D[2][3] * (ai2 * (60 * ai * ak - 120 * ak2) * m2 * is3);
  R40 += D[2][5] * (384 * ak2 * m2 * s);
  R4k += D[2][5] * ((ai * (704 * ai * ak2 - 1376 * ak3) + 80 * ak4) * m2 * is3);
  R4i += D[2][5] * (ai2 * (-480 * ai * ak + 1680 * ak2) * m2 * is3);
  R4k += D[2][7] * ((2784 * ai * ak3 - 1536 * ak4) * m2 * is3);
  R4i += D[2][7] * (ai2 * (480 * ai * ak - 3840 * ak2) * m2 * is3);
  R4k += D[2][9] * (2304 * ak4 * m2 * is3);
  R4i += D[2][9] * (2304 * ai2 * ak2 * m2 * is3);
  R40 += D[3][5] * (-512 * s2 * s2 * ak * m3 * is);
  R4k += D[3][5] * ((768 * ai * ak2 - 192 * ak3) * m3 * is);
  R4i += D[3][5] * (-960 * ai2 * ak * m3 * is);
  R4k += D[3][7] * ((-1536 * ai * ak2 + 2304 * ak3) * m3 * is);
  R4i += D[3][7] * (3840 * ai2 * ak * m3 * is);
  R4k += D[3][9] * (-3072 * ak3 * m3 * is);
  R4i += D[3][9] * (-3072 * ai2 * ak * m3 * is);
  R40 += D[4][5] * (256 * s2 * s2 * m4 * s);
  R4k += D[4][5] * (96 * ak2 * m4 * s);
  R4i += D[4][5] * (96 * ai2 * m4 * s);
  R4k += D[4][7] * (-1152 * ak2 * m4 * s);
  R4i += D[4][7] * (-1152 * ai2 * m4 * s);
  R4k += D[4][9] * (1536 * ak2 * m4 * s);
  R4i += D[4][9] * (1536 * ai2 * m4 * s);
  /* zeta = -R2/(3 a_k) (the a2_i part per unit a2_i); Phi = R4/(15 a_k^2) + 2 zeta (1 + a2_k), linear */
  const double i3 = -w / (3.0 * ak), i15 = w / (15.0 * ak2);
  const double dzm = i3 * R20, dzo = i3 * R2k, dzp = i3 * R2i;
  o.zm += dzm;
  o.czo += dzo;
  o.czp += dzp;
  o.pm += i15 * R40 + 2.0 * dzm;
  o.cpo += i15 * R4k + 2.0 * dzo + 2.0 * dzm;
  o.cpp += i15 * R4i + 2.0 * dzp;
  return o;
}

void spass_general(const gran_mixture *mix, const double *T, const double *a2, SPass &P);

/* Constant eps and g2: the pairs (k, i < k) VWT at a time, both directions per pair; R = double
 * (VV = vd) or float (VV = vf: the early sweeps of the HCS solve, see sonine_hcs). */
inline vd ld(const double *p) { return vload(p); }
inline vf ld(const float *p) { return vloadf(p); }
template <typename R, typename VV, int VWT>
void spass_fast_t(const gran_mixture *mix, const double *T_, const double *a2_, SPass &P) {
  const int64_t M = mix->M;
  for (auto *v : {&P.z0, &P.z1, &P.phi, &P.diag, &P.off, &P.zdg, &P.nu, &P.d, &P.l}) v->assign((size_t)M, 0.0);
  std::vector<R> buf((size_t)(14 * M), R(0));
  R *m = buf.data(), *sg = m + M, *n = sg + M, *T = n + M, *a2 = T + M;
  R *z0 = a2 + M, *z1 = z0 + M, *phi = z1 + M, *dg = phi + M, *of = dg + M, *nu = of + M, *zd = nu + M, *dd = zd + M,
    *ll = dd + M;
  for (int64_t k = 0; k < M; k++) {
    m[k] = (R)mix->m[(size_t)k];
    sg[k] = (R)mix->sigma[(size_t)k];
    n[k] = (R)mix->n[(size_t)k];
    T[k] = (R)T_[k];
    a2[k] = (R)a2_[k];
  }
  const R p = (R)(0.5 * (1.0 + mix->eps)), q = (R)(0.5 * (1.0 - mix->eps)), W = (R)(SQ2PI * mix->g2);
  std::vector<R> av((size_t)M), iT((size_t)M), ia((size_t)M);
  for (int64_t k = 0; k < M; k++) {
    av[(size_t)k] = T[k] / m[k];
    iT[(size_t)k] = R(1.0) / T[k];
    ia[(size_t)k] = m[k] / T[k];
  }
  for (int64_t k = 0; k < M; k++) {
    const R mk = m[k], Tk = T[k], ak = av[(size_t)k], iTk = iT[(size_t)k], nk = n[k], sk = sg[k], a2k = a2[k];
    const R iak = ia[(size_t)k];
    { /* self pair */
      const R w = W * sk * sk * nk, s = std::sqrt(2.0 * ak);
      const PairOut<R> o = pair_terms<R>(w, p, q, R(0.5), R(0.5), R(1.0), R(0.0), ak, ak, iak, s, R(1.0) / s);
      z0[k] += o.zm;
      dd[k] += o.dm;
      ll[k] = o.lm;
      z1[k] += (o.czo + o.czp) * a2k;
      phi[k] += o.pm + (o.cpo + o.cpp) * a2k;
      dg[k] += o.cpo + o.cpp;
      zd[k] += o.czo + o.czp;
      nu[k] += w * R(0.5) * s;
    }
    VV vz0 = {}, vz1 = {}, vph = {}, vdg = {}, vof = {}, vnu = {}, vzd = {}, vdd = {};
    int64_t i = 0;
    for (; i + VWT <= k; i += VWT) {
      const VV mi = ld(m + i), Ti = ld(T + i), ai = ld(av.data() + i), iTi = ld(iT.data() + i),
               ni = ld(n + i), si = ld(sg + i), a2i = ld(a2 + i);
      const VV sgm = R(0.5) * (sk + si);
      const VV w0 = W * sgm * sgm;
      const VV inv = R(1.0) / (mi + mk), mu = mi * inv, omu = mk * inv;
      const VV s = vsqrt(ak + ai), is = R(1.0) / s;
      const VV akv = ak + (VV){}, Tkv = Tk + (VV){}, iakv = iak + (VV){}, iai = ld(ia.data() + i);
      {
        const VV w = w0 * ni;
        const PairOut<VV> o = pair_terms<VV>(w, p, q, mu, omu, Ti * iTk, (Tkv - Ti) * iTk, akv, ai, iakv, s, is);
        vz0 += o.zm;
        vdd += o.dm;
        vz1 += o.czo * a2k + o.czp * a2i;
        vph += o.pm + o.cpo * a2k + o.cpp * a2i;
        vdg += o.cpo;
        vof += o.cpp;
        vzd += o.czo;
        vnu += w * mu * s;
      }
      {
        const VV w = w0 * nk;
        const PairOut<VV> o = pair_terms<VV>(w, p, q, omu, mu, Tk * iTi, (Ti - Tkv) * iTi, ai, akv, iai, s, is);
        vstore(z0 + i, ld(z0 + i) + o.zm);
        vstore(dd + i, ld(dd + i) + o.dm);
        vstore(z1 + i, ld(z1 + i) + o.czo * a2i + o.czp * a2k);
        vstore(phi + i, ld(phi + i) + o.pm + o.cpo * a2i + o.cpp * a2k);
        vstore(dg + i, ld(dg + i) + o.cpo);
        vstore(of + i, ld(of + i) + o.cpp);
        vstore(zd + i, ld(zd + i) + o.czo);
        vstore(nu + i, ld(nu + i) + w * omu * s);
      }
    }
    R sz0 = hsum(vz0), sz1 = hsum(vz1), sph = hsum(vph), sdg = hsum(vdg), sof = hsum(vof), snu = hsum(vnu),
           szd = hsum(vzd), sdd = hsum(vdd);
    for (; i < k; i++) {
      const R mi = m[i], Ti = T[i], ai = av[(size_t)i], sgm = R(0.5) * (sk + sg[i]), w0 = W * sgm * sgm;
      const R inv = R(1.0) / (mi + mk), mu = mi * inv, omu = mk * inv, s = std::sqrt(ak + ai), is = R(1.0) / s;
      {
        const R w = w0 * n[i];
        const PairOut<R> o = pair_terms<R>(w, p, q, mu, omu, Ti * iTk, (Tk - Ti) * iTk, ak, ai, iak, s, is);
        sz0 += o.zm;
        sdd += o.dm;
        sz1 += o.czo * a2k + o.czp * a2[i];
        sph += o.pm + o.cpo * a2k + o.cpp * a2[i];
        sdg += o.cpo;
        sof += o.cpp;
        szd += o.czo;
        snu += w * mu * s;
      }
      {
        const R w = w0 * nk, iTi = iT[(size_t)i];
        const PairOut<R> o =
            pair_terms<R>(w, p, q, omu, mu, Tk * iTi, (Ti - Tk) * iTi, ai, ak, ia[(size_t)i], s, is);
        z0[i] += o.zm;
        dd[i] += o.dm;
        z1[i] += o.czo * a2[i] + o.czp * a2k;
        phi[i] += o.pm + o.cpo * a2[i] + o.cpp * a2k;
        dg[i] += o.cpo;
        of[i] += o.cpp;
        zd[i] += o.czo;
        nu[i] += w * omu * s;
      }
    }
    zd[k] += szd;
    dd[k] += sdd;
    z0[k] += sz0;
    z1[k] += sz1;
    phi[k] += sph;
    dg[k] += sdg;
    of[k] += sof;
    nu[k] += snu;
  }
  for (int64_t k = 0; k < M; k++) {
    P.z0[(size_t)k] = z0[k];
    P.z1[(size_t)k] = z1[k];
    P.phi[(size_t)k] = phi[k];
    P.diag[(size_t)k] = dg[k];
    P.off[(size_t)k] = of[k];
    P.zdg[(size_t)k] = zd[k];
    P.nu[(size_t)k] = nu[k];
    P.d[(size_t)k] = dd[k];
    P.l[(size_t)k] = ll[k];
  }
}

void spass_fast(const gran_mixture *mix, const double *T, const double *a2, SPass &P) {
  spass_fast_t<double, vd, VW>(mix, T, a2, P);
}

/* The single-precision pass is used only where every quantity it forms stays far inside float's
 * range: masses, diameters, densities and temperatures (T_ref = 1) within [1e-6, 1e6]. */
bool spass_lo_ok(const gran_mixture *mix, const double *T) {
  if (mix->model != GRAN_RESTITUTION_CONSTANT || !mix->g2_mat.empty()) return false;
  if (!(mix->g2 >= 1e-6 && mix->g2 <= 1e6)) return false;
  auto in = [](double x) { return x >= 1e-6 && x <= 1e6; };
  for (int64_t k = 0; k < mix->M; k++)
    if (!in(mix->m[(size_t)k]) || !in(mix->sigma[(size_t)k]) || !in(T[k]) ||
        !(mix->n[(size_t)k] == 0.0 || in(mix->n[(size_t)k])))
      return false;
  return true;
}

void spass_visco(const gran_mixture *mix, const double *T, const double *a2, SPass &P);

void spass(const gran_mixture *mix, const double *T, const double *a2, SPass &P) {
  P.status = GRAN_SUCCESS;
  if (mix->model == GRAN_RESTITUTION_VISCOELASTIC) spass_visco(mix, T, a2, P);
  else if (mix->model == GRAN_RESTITUTION_CONSTANT && mix->g2_mat.empty()) spass_fast(mix, T, a2, P);
  else spass_general(mix, T, a2, P);
}

/* Viscoelastic restitution: each unordered pair once, the moments D_jk at z = sqrt(beta_ki) (2 s^2)^(1/20)
 * once per pair (twice when beta_ki != beta_ik). Fills z0, z1, phi, nu (what the trajectories and
 * gran_theory_sonine_rates use); diag, off, zdg, d, l stay 0 (there is no HCS solve). */
void spass_visco(const gran_mixture *mix, const double *T, const double *a2, SPass &P) {
  const int64_t M = mix->M;
  for (auto *v : {&P.z0, &P.z1, &P.phi, &P.diag, &P.off, &P.zdg, &P.nu, &P.d, &P.l}) v->assign((size_t)M, 0.0);
  const double *m = mix->m.data(), *sg = mix->sigma.data(), *n = mix->n.data();
  double *z0 = P.z0.data(), *z1 = P.z1.data(), *phi = P.phi.data(), *nu = P.nu.data();
  double Dk[5][10], Di[5][10];
  for (int64_t k = 0; k < M; k++) {
    const double mk = m[k], Tk = T[k], ak = Tk / mk;
    for (int64_t i = 0; i <= k; i++) {
      if (n[i] == 0.0 && n[k] == 0.0) continue;
      const double mi = m[i], Ti = T[i], ai = Ti / mi;
      const double sgm = 0.5 * (sg[k] + sg[i]);
      const double w0 = SQ2PI * sgm * sgm * mix_g2(mix, k, i);
      const double inv = 1.0 / (mi + mk), mu = mi * inv, omu = mk * inv;
      const double s2 = ak + ai, s = std::sqrt(s2);
      const double bk = mix_beta(mix, k, i), bi = mix_beta(mix, i, k), sc = std::pow(2.0 * s2, 0.05);
      int st = visco_sonine_moments(std::sqrt(bk) * sc, Dk);
      if (st == GRAN_SUCCESS && bi != bk) st = visco_sonine_moments(std::sqrt(bi) * sc, Di);
      if (st != GRAN_SUCCESS) {
        P.status = st;
        return;
      }
      const double(*D2)[10] = bi != bk ? Di : Dk;
      if (n[i] != 0.0) { /* partner i acting on k */
        const double w = w0 * n[i];
        const PairOut<double> o = pair_terms_visco(w, mu, omu, Ti / Tk, (Tk - Ti) / Tk, ak, ai, s, Dk);
        z0[k] += o.zm;
        z1[k] += o.czo * a2[k] + o.czp * a2[i];
        phi[k] += o.pm + o.cpo * a2[k] + o.cpp * a2[i];
        nu[k] += w * mu * s;
      }
      if (i != k && n[k] != 0.0) { /* partner k acting on i */
        const double w = w0 * n[k];
        const PairOut<double> o = pair_terms_visco(w, omu, mu, Tk / Ti, (Ti - Tk) / Ti, ai, ak, s, D2);
        z0[i] += o.zm;
        z1[i] += o.czo * a2[i] + o.czp * a2[k];
        phi[i] += o.pm + o.cpo * a2[i] + o.cpp * a2[k];
        nu[i] += w * omu * s;
      }
    }
  }
}

/* Any restitution/g2 matrices: each unordered pair once with the accessors. */
void spass_general(const gran_mixture *mix, const double *T, const double *a2, SPass &P) {
  const int64_t M = mix->M;
  for (auto *v : {&P.z0, &P.z1, &P.phi, &P.diag, &P.off, &P.zdg, &P.nu, &P.d, &P.l}) v->assign((size_t)M, 0.0);
  const double *m = mix->m.data(), *sg = mix->sigma.data(), *n = mix->n.data();
  double *z0 = P.z0.data(), *z1 = P.z1.data(), *phi = P.phi.data(), *dg = P.diag.data(), *of = P.off.data(),
         *nu = P.nu.data(), *zd = P.zdg.data(), *dd = P.d.data(), *ll = P.l.data();
  for (int64_t k = 0; k < M; k++) {
    const double mk = m[k], Tk = T[k], ak = Tk / mk;
    for (int64_t i = 0; i <= k; i++) {
      if (n[i] == 0.0 && n[k] == 0.0) continue;
      const double mi = m[i], Ti = T[i], ai = Ti / mi;
      const double sgm = 0.5 * (sg[k] + sg[i]);
      const double w0 = SQ2PI * sgm * sgm * mix_g2(mix, k, i);
      const double eps = mix_eps(mix, k, i), p = 0.5 * (1.0 + eps), q = 0.5 * (1.0 - eps);
      const double inv = 1.0 / (mi + mk), mu = mi * inv, omu = mk * inv;
      const double s = std::sqrt(ak + ai), is = 1.0 / s;
      if (n[i] != 0.0) { /* partner i acting on k */
        const double w = w0 * n[i];
        const PairOut<double> o = pair_terms<double>(w, p, q, mu, omu, Ti / Tk, (Tk - Ti) / Tk, ak, ai, 1.0 / ak, s, is);
        z0[k] += o.zm;
        dd[k] += o.dm;
        z1[k] += o.czo * a2[k] + o.czp * a2[i];
        phi[k] += o.pm + o.cpo * a2[k] + o.cpp * a2[i];
        dg[k] += o.cpo;
        zd[k] += o.czo;
        if (i == k) dg[k] += o.cpp, zd[k] += o.czp, ll[k] = o.lm;
        else of[k] += o.cpp;
        nu[k] += w * mu * s;
      }
      if (i != k && n[k] != 0.0) { /* partner k acting on i */
        const double w = w0 * n[k];
        const PairOut<double> o = pair_terms<double>(w, p, q, omu, mu, Tk / Ti, (Ti - Tk) / Ti, ai, ak, 1.0 / ai, s, is);
        z0[i] += o.zm;
        dd[i] += o.dm;
        z1[i] += o.czo * a2[i] + o.czp * a2[k];
        phi[i] += o.pm + o.cpo * a2[i] + o.cpp * a2[k];
        dg[i] += o.cpo;
        of[i] += o.cpp;
        zd[i] += o.czo;
        nu[i] += w * omu * s;
      }
    }
  }
}

bool all_elastic(const gran_mixture *mix) {
  if (mix->model == GRAN_RESTITUTION_CONSTANT) return mix->eps == 1.0;
  for (double e : mix->eps_mat)
    if (e != 1.0) return false;
  return true;
}

/* Residuals: max |zeta_k - c*|/nu_k (c* least-squares common rate) and max |phi_k|/nu_k. */
void sresidual(const SPass &P, double *rT, double *rA, double *cstar) {
  double num = 0.0, den = 0.0;
  const size_t M = P.z0.size();
  for (size_t k = 0; k < M; k++) {
    const double w = 1.0 / (P.nu[k] * P.nu[k]);
    num += w * (P.z0[k] + P.z1[k]);
    den += w;
  }
  const double c = num / den;
  double a = 0.0, b = 0.0;
  for (size_t k = 0; k < M; k++) {
    a = std::max(a, std::fabs(P.z0[k] + P.z1[k] - c) / P.nu[k]);
    b = std::max(b, std::fabs(P.phi[k]) / P.nu[k]);
  }
  *rT = a;
  *rA = b;
  if (cstar) *cstar = c;
}

const int64_t SON_DENSE_MAX = 64; /* GSL hybrids polish of the 2M-1 unknowns up to here */
const double SON_TOL = 1e-13;
const double SON_ACA_TOL = 1e-6; /* the coupling kernels of the sweep (an approximate Jacobian) */
const double SON_START_TOL = 1e-4; /* the Maxwellian start beyond SON_DENSE_MAX species */
const double SON_LO_TOL = 1e-4;    /* single-precision passes while the residuals are above this */

/* ---- GSL hybrids on x = (log T_k - log T_ref for k != ref, a2_k) ---------------------------- */
struct SSys {
  const gran_mixture *mix;
  int64_t ref;
  std::vector<double> T, a2, nu;
  SPass P;
};

int sys_f(const gsl_vector *x, void *params, gsl_vector *f) {
  SSys *h = static_cast<SSys *>(params);
  const int64_t M = h->mix->M, ref = h->ref;
  for (int64_t k = 0, j = 0; k < M; k++) h->T[(size_t)k] = k == ref ? 1.0 : std::exp(gsl_vector_get(x, (size_t)j++));
  for (int64_t k = 0; k < M; k++) h->a2[(size_t)k] = gsl_vector_get(x, (size_t)(M - 1 + k));
  spass(h->mix, h->T.data(), h->a2.data(), h->P);
  const double zr = h->P.z0[(size_t)ref] + h->P.z1[(size_t)ref];
  for (int64_t k = 0, j = 0; k < M; k++) {
    if (k != ref) {
      const double fk = (h->P.z0[(size_t)k] + h->P.z1[(size_t)k] - zr) / h->nu[(size_t)k];
      if (!std::isfinite(fk)) return GSL_EBADFUNC;
      gsl_vector_set(f, (size_t)j++, fk);
    }
    const double gk = h->P.phi[(size_t)k] / h->nu[(size_t)k];
    if (!std::isfinite(gk)) return GSL_EBADFUNC;
    gsl_vector_set(f, (size_t)(M - 1 + k), gk);
  }
  return GSL_SUCCESS;
}

double max_abs(const gsl_vector *v) {
  double a = 0.0;
  for (size_t i = 0; i < v->size; i++) a = std::max(a, std::fabs(gsl_vector_get(v, i)));
  return a;
}

/* Polish (u, a2) with GSL hybrids (finite-difference Jacobian); keeps the input unless improved. */
void polish_hybrids(const gran_mixture *mix, int64_t ref, std::vector<double> &u, std::vector<double> &a2,
                    const std::vector<double> &nu, int *passes) {
  const int64_t M = mix->M;
  SSys h;
  h.mix = mix;
  h.ref = ref;
  h.T.assign((size_t)M, 1.0);
  h.a2.assign((size_t)M, 0.0);
  h.nu = nu;
  const size_t dim = (size_t)(2 * M - 1);
  gsl_multiroot_function F{sys_f, dim, &h};
  gsl_vector *x = gsl_vector_alloc(dim);
  gsl_multiroot_fsolver *sv = gsl_multiroot_fsolver_alloc(gsl_multiroot_fsolver_hybrids, dim);
  if (x && sv) {
    for (int64_t k = 0, j = 0; k < M; k++) {
      if (k != ref) gsl_vector_set(x, (size_t)j++, u[(size_t)k] - u[(size_t)ref]);
      gsl_vector_set(x, (size_t)(M - 1 + k), a2[(size_t)k]);
    }
    if (gsl_multiroot_fsolver_set(sv, &F, x) == GSL_SUCCESS) {
      const double res0 = max_abs(sv->f);
      double res = res0;
      for (int iter = 0; iter < 40 && res > 1e-15; iter++) {
        if (gsl_multiroot_fsolver_iterate(sv) != GSL_SUCCESS) break;
        res = max_abs(sv->f);
        if (gsl_multiroot_test_delta(sv->dx, sv->x, 1e-17, 1e-16) == GSL_SUCCESS) break;
      }
      if (res < res0)
        for (int64_t k = 0, j = 0; k < M; k++) {
          u[(size_t)k] = k == ref ? 0.0 : gsl_vector_get(sv->x, (size_t)j++);
          a2[(size_t)k] = gsl_vector_get(sv->x, (size_t)(M - 1 + k));
        }
    }
    if (passes) *passes += (int)(3 * dim); /* GSL's evaluations: about one Jacobian (dim passes) per polish */
  }
  gsl_vector_free(x);
  gsl_multiroot_fsolver_free(sv);
}

/* Anderson acceleration (type II, depth <= 5) of a fixed-point iteration x <- G(x): given the
 * iterate xin and gx = G(xin), replaces gx by the mixed next iterate. The sweep map below
 * converges linearly (factor ~ 1/12 per sweep alone: the lag between its temperature step and the
 * a2 that follows); the mixing brings it to ~ 1/30. */
struct Anderson {
  int depth = 5;
  std::vector<std::vector<double>> dF, dG; /* differences of residuals f = G(x) - x and of G */
  std::vector<double> fold, gold;
};

void anderson(Anderson &A, const std::vector<double> &xin, std::vector<double> &gx) {
  const size_t n = gx.size();
  std::vector<double> f(n);
  for (size_t i = 0; i < n; i++) f[i] = gx[i] - xin[i];
  if (!A.fold.empty()) {
    std::vector<double> df(n), dg(n);
    for (size_t i = 0; i < n; i++) {
      df[i] = f[i] - A.fold[i];
      dg[i] = gx[i] - A.gold[i];
    }
    A.dF.push_back(df);
    A.dG.push_back(dg);
    if ((int)A.dF.size() > A.depth) {
      A.dF.erase(A.dF.begin());
      A.dG.erase(A.dG.begin());
    }
  }
  A.fold = f;
  A.gold = gx;
  const int m = (int)A.dF.size();
  if (m == 0) return;
  /* least squares min |f - dF gamma| by the normal equations (m <= 5), Tikhonov-regularised */
  std::vector<double> H((size_t)(m * m)), b((size_t)m);
  double tr = 0.0;
  for (int a = 0; a < m; a++) {
    for (int c = 0; c < m; c++) {
      double sum = 0.0;
      for (size_t i = 0; i < n; i++) sum += A.dF[(size_t)a][i] * A.dF[(size_t)c][i];
      H[(size_t)(a * m + c)] = sum;
    }
    double sb = 0.0;
    for (size_t i = 0; i < n; i++) sb += A.dF[(size_t)a][i] * f[i];
    b[(size_t)a] = sb;
    tr += H[(size_t)(a * m + a)];
  }
  if (!(tr > 0.0) || !std::isfinite(tr)) return;
  for (int a = 0; a < m; a++) H[(size_t)(a * m + a)] += 1e-12 * tr;
  /* Gaussian elimination with partial pivoting */
  for (int c = 0; c < m; c++) {
    int pr = c;
    for (int r = c + 1; r < m; r++)
      if (std::fabs(H[(size_t)(r * m + c)]) > std::fabs(H[(size_t)(pr * m + c)])) pr = r;
    if (!(std::fabs(H[(size_t)(pr * m + c)]) > 0.0)) return;
    if (pr != c) {
      for (int j = 0; j < m; j++) std::swap(H[(size_t)(c * m + j)], H[(size_t)(pr * m + j)]);
      std::swap(b[(size_t)c], b[(size_t)pr]);
    }
    for (int r = c + 1; r < m; r++) {
      const double fct = H[(size_t)(r * m + c)] / H[(size_t)(c * m + c)];
      for (int j = c; j < m; j++) H[(size_t)(r * m + j)] -= fct * H[(size_t)(c * m + j)];
      b[(size_t)r] -= fct * b[(size_t)c];
    }
  }
  std::vector<double> gam((size_t)m);
  for (int c = m - 1; c >= 0; c--) {
    double sum = b[(size_t)c];
    for (int j = c + 1; j < m; j++) sum -= H[(size_t)(c * m + j)] * gam[(size_t)j];
    gam[(size_t)c] = sum / H[(size_t)(c * m + c)];
  }
  for (int a = 0; a < m; a++)
    if (!std::isfinite(gam[(size_t)a])) return;
  for (int a = 0; a < m; a++)
    for (size_t i = 0; i < n; i++) gx[i] -= gam[(size_t)a] * A.dG[(size_t)a][i];
}

/* T_i d/dT_i of partner i's term in Phi_k at fixed a2 (complex step: exact to rounding). Entry
 * (k, k) is the partner part of the self pair. A smooth kernel in (k, i): compressed by ACA. */
double lphi(const gran_mixture *mix, const double *T, const double *a2, int64_t k, int64_t i) {
  typedef std::complex<double> cd;
  const double ni = mix->n[(size_t)i];
  if (ni == 0.0) return 0.0;
  const double mk = mix->m[(size_t)k], mi = mix->m[(size_t)i], Tk = T[k], h = 1e-30;
  const double sgm = 0.5 * (mix->sigma[(size_t)k] + mix->sigma[(size_t)i]);
  const double w = SQ2PI * sgm * sgm * mix_g2(mix, k, i) * ni;
  const double eps = mix_eps(mix, k, i), p = 0.5 * (1.0 + eps), q = 0.5 * (1.0 - eps);
  const double inv = 1.0 / (mi + mk), mu = mi * inv, omu = mk * inv, ak = Tk / mk;
  const cd Ti(T[i], T[i] * h), ai = Ti / mi, s = std::sqrt(ak + ai);
  const PairOut<cd> o = pair_terms<cd>(cd(w), p, q, cd(mu), cd(omu), Ti / Tk, (Tk - Ti) / Tk, cd(ak), ai,
                                       cd(1.0 / ak), s, 1.0 / s);
  return std::imag(o.pm + o.cpo * a2[k] + o.cpp * a2[i]) / h;
}

/* d zeta_k / d a2_i of partner i (the coefficient czp of pair_terms); entry (k, k) the partner part
 * of the self pair. A smooth kernel in (k, i): compressed by ACA. */
double lzeta(const gran_mixture *mix, const double *T, int64_t k, int64_t i, bool phi = false) {
  const double ni = mix->n[(size_t)i];
  if (ni == 0.0) return 0.0;
  const double mk = mix->m[(size_t)k], mi = mix->m[(size_t)i], Tk = T[k], Ti = T[i];
  const double sgm = 0.5 * (mix->sigma[(size_t)k] + mix->sigma[(size_t)i]);
  const double w = SQ2PI * sgm * sgm * mix_g2(mix, k, i) * ni;
  const double eps = mix_eps(mix, k, i), p = 0.5 * (1.0 + eps), q = 0.5 * (1.0 - eps);
  const double inv = 1.0 / (mi + mk), mu = mi * inv, omu = mk * inv, ak = Tk / mk, ai = Ti / mi;
  const double s = std::sqrt(ak + ai);
  const PairOut<double> o = pair_terms<double>(w, p, q, mu, omu, Ti / Tk, (Tk - Ti) / Tk, ak, ai, 1.0 / ak, s, 1.0 / s);
  return phi ? o.cpp : o.czp;
}

/* U (V^T x) of a rank-r factorisation (column-major M x r) */
void lr_apply(int64_t M, int r, const std::vector<double> &U, const std::vector<double> &V, const double *x,
              double *y) {
  std::vector<double> t((size_t)r, 0.0);
  for (int l = 0; l < r; l++)
    for (int64_t k = 0; k < M; k++) t[(size_t)l] += V[(size_t)l * M + k] * x[k];
  for (int64_t k = 0; k < M; k++) {
    double sum = 0.0;
    for (int l = 0; l < r; l++) sum += U[(size_t)l * M + k] * t[(size_t)l];
    y[k] = sum;
  }
}

/* Adaptive cross approximation (partial pivoting) of the M x M kernel entry(k, j) ~ U V^T (U, V
 * column-major M x r), relative accuracy tol. */
template <class F>
void aca_kernel(int64_t M, int64_t start, F entry, double tol, int rmax, std::vector<double> &U, std::vector<double> &V,
                int *rank) {
  int r = 0;
  U.clear();
  V.clear();
  std::vector<char> usedr((size_t)M, 0), usedc((size_t)M, 0);
  std::vector<double> row((size_t)M), col((size_t)M);
  double norm2 = 0.0;
  int64_t i = start;
  int misses = 0;
  while (r < rmax) {
    usedr[(size_t)i] = 1;
    for (int64_t j = 0; j < M; j++) row[(size_t)j] = entry(i, j);
    for (int l = 0; l < r; l++) {
      const double ui = U[(size_t)l * M + i];
      for (int64_t j = 0; j < M; j++) row[(size_t)j] -= ui * V[(size_t)l * M + j];
    }
    int64_t jp = -1;
    double best = 0.0;
    for (int64_t j = 0; j < M; j++)
      if (!usedc[(size_t)j] && std::fabs(row[(size_t)j]) > best) best = std::fabs(row[(size_t)(jp = j)]);
    if (jp < 0 || best <= 1e-300) {
      if (++misses > 3) break;
      int64_t next = -1;
      for (int64_t k = 0; k < M && next < 0; k++)
        if (!usedr[(size_t)k]) next = k;
      if (next < 0) break;
      i = next;
      continue;
    }
    usedc[(size_t)jp] = 1;
    const double piv = row[(size_t)jp];
    for (int64_t k = 0; k < M; k++) col[(size_t)k] = entry(k, jp);
    for (int l = 0; l < r; l++) {
      const double vj = V[(size_t)l * M + jp];
      for (int64_t k = 0; k < M; k++) col[(size_t)k] -= vj * U[(size_t)l * M + k];
    }
    for (auto &v : row) v /= piv;
    double uu = 0.0, vv = 0.0, cross = 0.0;
    for (int64_t k = 0; k < M; k++) {
      uu += col[(size_t)k] * col[(size_t)k];
      vv += row[(size_t)k] * row[(size_t)k];
    }
    for (int l = 0; l < r; l++) {
      double a = 0.0, b = 0.0;
      for (int64_t k = 0; k < M; k++) {
        a += U[(size_t)l * M + k] * col[(size_t)k];
        b += V[(size_t)l * M + k] * row[(size_t)k];
      }
      cross += a * b;
    }
    norm2 += uu * vv + 2.0 * cross;
    U.insert(U.end(), col.begin(), col.end());
    V.insert(V.end(), row.begin(), row.end());
    r++;
    misses = 0;
    if (std::sqrt(uu * vv) <= tol * std::sqrt(std::fabs(norm2))) break;
    int64_t ip = -1;
    best = -1.0;
    for (int64_t k = 0; k < M; k++)
      if (!usedr[(size_t)k] && std::fabs(col[(size_t)k]) > best) best = std::fabs(col[(size_t)(ip = k)]);
    if (ip < 0) break;
    i = ip;
  }
  *rank = r;
}

/* The Sonine HCS: u = log T (u[ref] = 0), a2, the mean rate c at T = exp(u).
 * Start: the Maxwellian HCS (u0, a2 = 0). Each sweep is one block Gauss-Seidel step of Newton's
 * method on (a2, u) with one Sonine pass at (T, a2):
 *  1. a2: Phi is linear in a2, d Phi_k/d a2_i = diag_k (i = k) + C_ki; the partner kernel C is
 *     compressed by ACA and diag da + C da = -Phi solved by D-preconditioned Richardson steps
 *     (D_k = diag_k + the partner sum when it has the same sign: exact when all a2 are equal);
 *  2. u: zeta_k at the new a2 (z1_k plus its change through the own coefficient and the ACA of
 *     the partner kernel Z_ki = d zeta_k/d a2_i), then one clamped Newton step of the HCS of the
 *     rates zeta_k = z0_k (1 + z1_k/z0_k) with the factors frozen (hcs_solve_scaled, warm);
 *  3. a2 again, for that temperature step du: a2_k -= (dPhi_k/du . du)/D_k, the partner part of
 *     dPhi_k/du_i an ACA-compressed kernel (complex-step derivatives of the pair terms) and the
 *     own part from the homogeneity of Phi (degree 1/2 in T).
 * The sweep map is Anderson-mixed; each sweep reduces the residuals ~30x (the plain sweep without
 * steps 1's partner kernel, 2's a2 change and 3 gained ~5x). M <= SON_DENSE_MAX: GSL hybrids
 * polishes the 2M - 1 unknowns together. */
int sonine_hcs(const gran_mixture *mix, std::vector<double> &u, std::vector<double> &a2, double *cbar,
               int *passes_out) {
  const int64_t M = mix->M;
  int passes = 0;
  std::vector<double> T((size_t)M), scale((size_t)M, 1.0), da((size_t)M, 0.0), Dk((size_t)M), a2p, uold,
      nuc((size_t)M);
  /* the three coupling kernels (ACA factors, self entries): an approximate Jacobian, refreshed
   * while the state still moves (residuals above 1e-4) and then kept */
  std::vector<double> UC, VC, UZ, VZ, UL, VL, Ckk((size_t)M), Zkk((size_t)M);
  int rc = 0, rz = 0, rk = 0;
  a2.assign((size_t)M, 0.0);
  SPass P;
  int64_t ref = 0;
  for (int64_t k = 1; k < M; k++)
    if (mix->n[(size_t)k] > mix->n[(size_t)ref]) ref = k;
  double rT = HUGE_VAL, rA = HUGE_VAL, c = 0.0;
  const int maxit = 200;
  Anderson AA;
  std::vector<double> X((size_t)(2 * M)), xprev((size_t)(2 * M));
  bool polished = false, was_lo = false;
  for (int it = 0;; it++) {
    for (int64_t k = 0; k < M; k++) {
      xprev[(size_t)k] = u[(size_t)k] - u[(size_t)ref];
      xprev[(size_t)(M + k)] = a2[(size_t)k];
    }
    const double shift = u[(size_t)ref];
    for (int64_t k = 0; k < M; k++) T[(size_t)k] = std::exp(u[(size_t)k] - shift);
    /* while the residuals are above SON_LO_TOL the sweep needs the rates to a few digits only:
     * the single-precision pass (twice the lanes), then the double one to the end */
    const bool lo = M > SON_DENSE_MAX && std::max(rT, rA) > SON_LO_TOL && spass_lo_ok(mix, T.data());
    if (lo) spass_fast_t<float, vf, VWF>(mix, T.data(), a2.data(), P);
    else spass(mix, T.data(), a2.data(), P);
    if (!lo && was_lo) AA = Anderson(); /* the map changed by the rounding of the float pass */
    was_lo = lo;
    a2p = a2;
    passes++;
    sresidual(P, &rT, &rA, &c);
#ifdef GRAN_HCS_DEBUG
    std::fprintf(stderr, "sonine: M = %" PRId64 " sweep %d residuals %.3e %.3e passes %d\n", M, it, rT, rA, passes);
#endif
    if (!std::isfinite(rT) || !std::isfinite(rA))
      return GRAN_ERROR(GRAN_ERR_NUMERIC, "Sonine HCS: non-finite rates during the solve");
    if (!lo && rT <= SON_TOL && rA <= SON_TOL) break;
    if (M > 1 && M <= SON_DENSE_MAX && !polished && rT <= 1e-9 && rA <= 1e-9) {
      /* GSL hybrids on the 2M - 1 unknowns together; the sweeps continue if it stops short */
      polished = true;
      for (auto &v : u) v -= u[(size_t)ref];
      polish_hybrids(mix, ref, u, a2, P.nu, &passes);
      AA = Anderson();
      it--;
      continue;
    }
    if (it >= maxit)
      return GRAN_ERROR(GRAN_ERR_NOCONV,
                        "Sonine HCS (M = %" PRId64 ") did not converge: residuals %.3g (T), %.3g (a2) after %d sweeps",
                        M, rT, rA, it);
    const bool refresh = std::max(rT, rA) > 1e-4 || UC.empty();
    for (int64_t k = 0; k < M; k++) {
      const double D = P.diag[(size_t)k] + (P.off[(size_t)k] * P.diag[(size_t)k] > 0.0 ? P.off[(size_t)k] : 0.0);
      if (!(std::fabs(D) > 0.0) || !std::isfinite(D))
        return GRAN_ERROR(GRAN_ERR_NUMERIC, "Sonine HCS: zero a2 relaxation rate for species %" PRId64, k);
      Dk[(size_t)k] = D;
      da[(size_t)k] = -P.phi[(size_t)k] / D;
    }
    if (M > 1) {
      /* Phi is linear in a2: solve diag da + C da = -Phi (C_ki = d Phi_k/d a2_i, i != k, ACA)
       * by a few D-preconditioned Richardson steps from the Jacobi step above */
      if (refresh) {
        aca_kernel(M, ref, [&](int64_t k, int64_t i) { return lzeta(mix, T.data(), k, i, true); }, SON_ACA_TOL,
                   (int)std::min<int64_t>(M, 64), UC, VC, &rc);
        aca_kernel(M, ref, [&](int64_t k, int64_t i) { return lzeta(mix, T.data(), k, i); }, SON_ACA_TOL,
                   (int)std::min<int64_t>(M, 64), UZ, VZ, &rz);
        aca_kernel(M, ref, [&](int64_t k, int64_t i) { return lphi(mix, T.data(), a2p.data(), k, i); }, SON_ACA_TOL,
                   (int)std::min<int64_t>(M, 64), UL, VL, &rk);
        for (int64_t k = 0; k < M; k++) {
          Ckk[(size_t)k] = lzeta(mix, T.data(), k, k, true);
          Zkk[(size_t)k] = lzeta(mix, T.data(), k, k);
        }
      }
      std::vector<double> Cda((size_t)M);
      for (int it2 = 0; it2 < 4; it2++) {
        lr_apply(M, rc, UC, VC, da.data(), Cda.data());
        for (int64_t k = 0; k < M; k++) {
          const double res = P.phi[(size_t)k] + (P.diag[(size_t)k] - Ckk[(size_t)k]) * da[(size_t)k] + Cda[(size_t)k];
          da[(size_t)k] -= res / Dk[(size_t)k];
        }
      }
    }
    for (int64_t k = 0; k < M; k++) a2[(size_t)k] += da[(size_t)k];
    if (M > 1) {
      /* zeta_k at the updated a2: z1_k + d zeta_k/d a2_k da_k + sum_{i != k} Z_ki da_i (Z: ACA) */
      std::vector<double> Zda((size_t)M);
      lr_apply(M, rz, UZ, VZ, da.data(), Zda.data());
      for (int64_t k = 0; k < M; k++) {
        const double z0 = P.z0[(size_t)k];
        const double dz = P.zdg[(size_t)k] * da[(size_t)k] + Zda[(size_t)k] - Zkk[(size_t)k] * da[(size_t)k];
        scale[(size_t)k] = 1.0 + (P.z1[(size_t)k] + dz) / z0;
        if (!(z0 > 0.0) || !(scale[(size_t)k] > 0.0) || !std::isfinite(scale[(size_t)k]))
          return GRAN_ERROR(GRAN_ERR_NUMERIC, "Sonine HCS: cooling rate of species %" PRId64 " is not positive", k);
      }
      int64_t r2 = 0;
      const double tin = std::max(0.01 * SON_TOL, 0.01 * std::max(rT, rA));
      uold = u;
#ifdef GRAN_HCS_DEBUG
      const clock_t c0 = clock();
#endif
      /* the pass above was at T = exp(u - u_ref): its Maxwellian part is the Newton step's first pass */
      for (int64_t k = 0; k < M; k++) nuc[(size_t)k] = (8.0 / 3.0) * P.nu[(size_t)k];
      const HcsPass first{P.z0.data(), P.d.data(), P.l.data(), nuc.data()};
      GRAN_CALL(hcs_solve_scaled(mix, scale.data(), &first, u, &r2, tin, 1, &passes));
#ifdef GRAN_HCS_DEBUG
      std::fprintf(stderr, "sonine: newton step %.3f s\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
#endif
      /* step 3: dPhi_k/du . du = Phi_k du_k/2 + sum_i L_ki (du_i - du_k), L_ki = lphi (ACA; the
       * homogeneity sum_i dPhi_k/du_i = Phi_k/2 gives the own part) */
#ifdef GRAN_HCS_DEBUG
      std::fprintf(stderr, "sonine: lphi rank %d\n", rk);
#endif
      std::vector<double> du((size_t)M), vd((size_t)rk, 0.0), v1((size_t)rk, 0.0);
      for (int64_t k = 0; k < M; k++) du[(size_t)k] = u[(size_t)k] - (uold[(size_t)k] - uold[(size_t)ref]);
      for (int l = 0; l < rk; l++)
        for (int64_t k = 0; k < M; k++) {
          vd[(size_t)l] += VL[(size_t)l * M + k] * du[(size_t)k];
          v1[(size_t)l] += VL[(size_t)l * M + k];
        }
      for (int64_t k = 0; k < M; k++) {
        double Ld = 0.0, L1 = 0.0;
        for (int l = 0; l < rk; l++) {
          Ld += UL[(size_t)l * M + k] * vd[(size_t)l];
          L1 += UL[(size_t)l * M + k] * v1[(size_t)l];
        }
        const double J = 0.5 * P.phi[(size_t)k] * du[(size_t)k] + Ld - du[(size_t)k] * L1;
        a2[(size_t)k] -= J / Dk[(size_t)k];
      }
    }
    /* Anderson mixing of the sweep map x -> G(x), x = (u - u_ref, a2) */
    for (int64_t k = 0; k < M; k++) {
      X[(size_t)k] = u[(size_t)k] - u[(size_t)ref];
      X[(size_t)(M + k)] = a2[(size_t)k];
    }
    anderson(AA, xprev, X);
    for (int64_t k = 0; k < M; k++) {
      u[(size_t)k] = X[(size_t)k];
      a2[(size_t)k] = X[(size_t)(M + k)];
    }
  }
  const double shift = u[(size_t)ref];
  for (auto &v : u) v -= shift;
  double num = 0.0, den = 0.0;
  for (int64_t k = 0; k < M; k++) {
    num += mix->n[(size_t)k] * (P.z0[(size_t)k] + P.z1[(size_t)k]);
    den += mix->n[(size_t)k];
  }
  *cbar = num / den;
  if (passes_out) *passes_out = passes;
  return GRAN_SUCCESS;
}

int check_approx(int approximation) {
  GRAN_CHECK(approximation == GRAN_THEORY_MAXWELLIAN || approximation == GRAN_THEORY_SONINE, GRAN_ERR_ARG,
             "argument 'approximation' = %d is not a gran_theory_approximation (0 Maxwellian, 1 Sonine)",
             approximation);
  return GRAN_SUCCESS;
}

int check_sonine_model(const gran_mixture *mix) {
  GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
             "mixture 'mix' has viscoelastic restitution: there is no homogeneous cooling state (the first Sonine "
             "HCS and MSD are implemented for constant or matrix restitution only)");
  return GRAN_SUCCESS;
}


/* ---- trajectories: y = (z_k = log(T_k/T0_k) + 2 s, a2_k), s = log(1 + t/ts) ----------------- */
struct STraj {
  const gran_mixture *mix;
  int64_t M;
  double ts;
  std::vector<double> T0, T, a2;
  SPass P;
  /* the start: T0 (M), a20 (M; NULL: 0) */
  void start(const gran_mixture *m, const double *T0_, const double *a20) {
    mix = m;
    M = m->M;
    T0.assign(T0_, T0_ + M);
    T = T0;
    a2.assign((size_t)M, 0.0);
    if (a20) a2.assign(a20, a20 + M);
  }
};

int traj_rhs(double s, const double y[], double f[], void *params) {
  STraj *tr = static_cast<STraj *>(params);
  const int64_t M = tr->M;
  for (int64_t k = 0; k < M; k++) {
    if (!std::isfinite(y[k]) || !std::isfinite(y[M + k])) return GSL_EBADFUNC;
    tr->T[(size_t)k] = tr->T0[(size_t)k] * std::exp(y[k] - 2.0 * s);
    tr->a2[(size_t)k] = y[M + k];
  }
  spass(tr->mix, tr->T.data(), tr->a2.data(), tr->P);
  if (tr->P.status != GRAN_SUCCESS) return GSL_EBADFUNC;
  const double g = tr->ts * std::exp(s);
  for (int64_t k = 0; k < M; k++) {
    f[k] = 2.0 - g * (tr->P.z0[(size_t)k] + tr->P.z1[(size_t)k]);
    f[M + k] = g * tr->P.phi[(size_t)k];
  }
  return GSL_SUCCESS;
}

/* Dense trajectory for Eq. 4 at the first Sonine level: y = (z_k, u_k, a2_k), dim 3M, with
 * u_k = int_0^t sqrt(T_k/T0_k) dt' (du_k/ds = ts exp(z_k/2)), the layout of Traj with_u plus a2. */
int dense_rhs(double s, const double y[], double f[], void *params) {
  STraj *tr = static_cast<STraj *>(params);
  const int64_t M = tr->M;
  for (int64_t k = 0; k < M; k++) {
    if (!std::isfinite(y[k]) || !std::isfinite(y[2 * M + k])) return GSL_EBADFUNC;
    tr->T[(size_t)k] = tr->T0[(size_t)k] * std::exp(y[k] - 2.0 * s);
    tr->a2[(size_t)k] = y[2 * M + k];
  }
  spass(tr->mix, tr->T.data(), tr->a2.data(), tr->P);
  const double g = tr->ts * std::exp(s);
  for (int64_t k = 0; k < M; k++) {
    const double z = tr->P.z0[(size_t)k] + tr->P.z1[(size_t)k], ph = tr->P.phi[(size_t)k];
    if (!std::isfinite(z) || !std::isfinite(ph)) return GSL_EBADFUNC;
    f[k] = 2.0 - g * z;
    f[M + k] = tr->ts * std::exp(0.5 * y[k]);
    f[2 * M + k] = g * ph;
  }
  return GSL_SUCCESS;
}

} // namespace

/**
 * @brief Cooling rates and Sonine relaxation rates of the first Sonine approximation.
 * @param[in] T M temperatures > 0; a2 M Sonine coefficients (finite, |a2_k| < 1)
 * @param[out] zeta M cooling rates (dT_k/dt = -zeta_k T_k), may be NULL; da2dt M rates da2_k/dt, may be NULL
 */
GRAN_EXTERN int gran_theory_sonine_rates(const gran_mixture *mix, const double *T, const double *a2, double *zeta,
                                         double *da2dt) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(a2);
    for (int64_t k = 0; k < mix->M; k++)
      GRAN_CHECK(std::fabs(a2[k]) < 1.0, GRAN_ERR_ARG,
                 "argument 'a2'[%" PRId64 "] = %g: the first Sonine approximation needs |a2| < 1", k, a2[k]);
    SPass P;
    spass(mix, T, a2, P);
    if (P.status != GRAN_SUCCESS) return P.status;
    for (int64_t k = 0; k < mix->M; k++) {
      const double z = P.z0[(size_t)k] + P.z1[(size_t)k], ph = P.phi[(size_t)k];
      GRAN_CHECK(std::isfinite(z) && std::isfinite(ph), GRAN_ERR_NUMERIC,
                 "Sonine rates of species %" PRId64 " are not finite", k);
      if (zeta) zeta[k] = z;
      if (da2dt) da2dt[k] = ph;
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Homogeneous cooling state in the Maxwellian or the first Sonine approximation.
 * @param[in] approximation GRAN_THEORY_MAXWELLIAN (= gran_theory_hcs, a2 = 0) or GRAN_THEORY_SONINE
 * @param[in] norm, value as gran_theory_hcs
 * @param[out] T0 M temperatures; a2 M Sonine coefficients (may be NULL); tau0 = 2/zeta (may be NULL)
 */
GRAN_EXTERN int gran_theory_hcs_approx(const gran_mixture *mix, int approximation, int norm, double value, double *T0,
                                       double *a2, double *tau0) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_approx(approximation));
    GRAN_CALL(check_hcs_target(norm, value, T0));
    const int64_t M = mix->M;
    if (approximation == GRAN_THEORY_MAXWELLIAN) {
      GRAN_CALL(gran_theory_hcs(mix, norm, value, T0, tau0));
      if (a2) std::fill(a2, a2 + M, 0.0);
      return GRAN_SUCCESS;
    }
    GRAN_CALL(check_sonine_model(mix));
    /* Maxwellian start (also the answer when every pair is elastic: a2 = 0 at equipartition); beyond
     * SON_DENSE_MAX species only to the residual SON_START_TOL, the sweeps' own temperature steps
     * do the rest */
    std::vector<double> u((size_t)M), b((size_t)M, 0.0);
    int passes = 0;
    if (M <= SON_DENSE_MAX) {
      std::vector<double> T((size_t)M);
      GRAN_CALL(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 1.0, T.data(), nullptr));
      for (int64_t k = 0; k < M; k++) u[(size_t)k] = std::log(T[(size_t)k]);
    } else {
      GRAN_CALL(hcs_solve_start(mix, u, SON_START_TOL, &passes));
    }
    double cbar = 0.0;
    const bool elastic = all_elastic(mix);
    if (!elastic) GRAN_CALL(sonine_hcs(mix, u, b, &cbar, &passes));
#ifdef GRAN_HCS_DEBUG
    std::fprintf(stderr, "sonine hcs: M = %" PRId64 " passes %d\n", M, passes);
#endif
    const double loglam = hcs_log_scale(mix, u, norm, value);
    for (int64_t k = 0; k < M; k++) {
      T0[k] = std::exp(loglam + u[(size_t)k]);
      GRAN_CHECK(std::isfinite(T0[k]) && T0[k] > 0.0 && std::isfinite(b[(size_t)k]), GRAN_ERR_NUMERIC,
                 "Sonine HCS of species %" PRId64 " is not finite (T = %g, a2 = %g)", k, T0[k], b[(size_t)k]);
    }
    /* |a2| >= 1 makes f_k negative at some speeds: the expansion has failed there (e.g. a heavy
     * species much hotter than the gas, the regime of Santos & Dufty's ordered phase) */
    for (int64_t k = 0; k < M; k++)
      GRAN_CHECK(std::fabs(b[(size_t)k]) < 1.0, GRAN_ERR_DOMAIN,
                 "the first Sonine approximation fails for species %" PRId64 " of mixture 'mix': a2 = %g (|a2| >= 1; "
                 "T_k/T_1 = %g, m_k/m_1 = %g)",
                 k, b[(size_t)k], T0[k] / T0[0], mix->m[(size_t)k] / mix->m[0]);
    if (a2) std::copy(b.begin(), b.end(), a2);
    if (tau0) {
      *tau0 = elastic ? HUGE_VAL : 2.0 / (cbar * std::exp(0.5 * loglam));
      GRAN_CHECK(*tau0 > 0.0 && !std::isnan(*tau0), GRAN_ERR_NUMERIC, "Sonine HCS: tau0 = %g is not positive", *tau0);
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief T_k(t) and a2_k(t) from (T0, a20) in the Maxwellian (a2 = 0, gran_theory_temperatures) or the
 * first Sonine approximation (GSL odeiv2 rk8pd in s = log(1 + t/ts), ts the shortest collision time at T0).
 * @param[in] a20 M start values (|a2| < 1; NULL: 0); ignored for the Maxwellian approximation
 * @param[out] T ntimes*M; a2 ntimes*M (may be NULL), row-major [time][species]
 */
GRAN_EXTERN int gran_theory_temperatures_approx(const gran_mixture *mix, int approximation, const double *T0,
                                                const double *a20, int64_t ntimes, const double *t, double rtol,
                                                double *T, double *a2) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_approx(approximation));
    const int64_t M = mix->M;
    if (approximation == GRAN_THEORY_MAXWELLIAN) {
      GRAN_CALL(gran_theory_temperatures(mix, T0, ntimes, t, rtol, T));
      if (a2 && ntimes > 0) std::fill(a2, a2 + ntimes * M, 0.0);
      return GRAN_SUCCESS;
    }
    GRAN_CALL(check_array(T0, M, "T0", 1));
    if (a20) {
      for (int64_t k = 0; k < M; k++)
        GRAN_CHECK(std::fabs(a20[k]) < 1.0, GRAN_ERR_ARG,
                   "argument 'a20'[%" PRId64 "] = %g: the first Sonine approximation needs |a2| < 1", k, a20[k]);
    }
    GRAN_CALL(check_output_times(ntimes, t, T, "T"));
    GRAN_CALL(check_rtol(rtol, "rtol"));
    if (ntimes == 0) return GRAN_SUCCESS;
    STraj tr;
    tr.start(mix, T0, a20);
    spass(mix, tr.T.data(), tr.a2.data(), tr.P);
    if (tr.P.status != GRAN_SUCCESS) return tr.P.status;
    double numax = 0.0;
    for (double v : tr.P.nu) numax = std::max(numax, v);
    tr.ts = numax > 0.0 ? 1.0 / numax : 1.0;
    std::vector<int64_t> idx((size_t)ntimes);
    std::iota(idx.begin(), idx.end(), (int64_t)0);
    std::stable_sort(idx.begin(), idx.end(), [&](int64_t x, int64_t y) { return t[x] < t[y]; });
    const size_t dim = (size_t)(2 * M);
    std::vector<double> y(dim, 0.0);
    for (int64_t k = 0; k < M; k++) y[(size_t)(M + k)] = tr.a2[(size_t)k];
    gsl_odeiv2_system sys{traj_rhs, nullptr, dim, &tr};
    /* local tolerance rtol/10 (as gran_theory_temperatures); absolute 1e-3 rtol on a2, z */
    gsl_odeiv2_driver *drv =
        gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-6, 1e-3 * rtol, std::max(1e-15, 0.1 * rtol));
    if (!drv) return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate the ODE driver (M = %" PRId64 ")", M);
    gsl_odeiv2_driver_set_nmax(drv, 10000000);
    double s = 0.0;
    int st = GSL_SUCCESS;
    for (int64_t j = 0; j < ntimes && st == GSL_SUCCESS; j++) {
      const int64_t o = idx[(size_t)j];
      const double so = std::log1p(t[o] / tr.ts);
      if (so > s) st = gsl_odeiv2_driver_apply(drv, &s, so, y.data());
      if (st != GSL_SUCCESS) break;
      for (int64_t k = 0; k < M; k++) {
        T[o * M + k] = T0[k] * std::exp(y[(size_t)k] - 2.0 * so);
        if (a2) a2[o * M + k] = y[(size_t)(M + k)];
      }
    }
    gsl_odeiv2_driver_free(drv);
    if (st != GSL_SUCCESS && tr.P.status != GRAN_SUCCESS) return tr.P.status;
    if (st != GSL_SUCCESS)
      return GRAN_ERROR(GRAN_ERR_NUMERIC, "Sonine trajectory (M = %" PRId64 ") failed (GSL: %s)", M,
                        gsl_strerror(st));
    for (int64_t j = 0; j < ntimes * M; j++)
      GRAN_CHECK(std::isfinite(T[j]) && T[j] > 0.0, GRAN_ERR_NUMERIC,
                 "Sonine trajectory: temperature %" PRId64 " is not finite and positive", j);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

namespace gran {

double sonine_zeta_one(const gran_mixture *mix, const double *T, const double *a2, int64_t k) {
  const int64_t M = mix->M;
  const double mk = mix->m[(size_t)k], Tk = T[k], ak = Tk / mk, sk = mix->sigma[(size_t)k];
  double z = 0.0;
  for (int64_t i = 0; i < M; i++) {
    const double ni = mix->n[(size_t)i];
    if (ni == 0.0) continue;
    const double mi = mix->m[(size_t)i], Ti = T[i], ai = Ti / mi, sg = 0.5 * (sk + mix->sigma[(size_t)i]);
    const double eps = mix_eps(mix, k, i), p = 0.5 * (1.0 + eps), q = 0.5 * (1.0 - eps);
    const double inv = 1.0 / (mi + mk), mu = mi * inv, omu = mk * inv, s = std::sqrt(ak + ai);
    const double w = SQ2PI * sg * sg * mix_g2(mix, k, i) * ni;
    const PairOut<double> o = pair_terms<double>(w, p, q, mu, omu, Ti / Tk, (Tk - Ti) / Tk, ak, ai, 1.0 / ak, s, 1.0 / s);
    z += o.zm + o.czo * a2[k] + o.czp * a2[i];
  }
  return z;
}

int sonine_dense_evolve(Traj &out, gsl_odeiv2_system sys, std::vector<double> &y, std::vector<double> &scale, double ts,
                        double rtol, double hmax, double s_end, const char *what, unsigned long maxsteps,
                        int (*check)(const double *y, int64_t M, double t)) {
  const size_t dim = sys.dimension;
  const int64_t M = out.M;
  std::vector<double> f(dim);
  gsl_odeiv2_step *stp = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, dim);
  gsl_odeiv2_control *ctl = gsl_odeiv2_control_scaled_new(rtol, rtol, 1.0, 0.0, scale.data(), dim);
  gsl_odeiv2_evolve *ev = gsl_odeiv2_evolve_alloc(dim);
  int ret = GRAN_SUCCESS;
  if (!stp || !ctl || !ev) ret = GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate the ODE solver (M = %" PRId64 ")", M);
  double s = 0.0, h = std::min(1e-6, hmax);
  auto store = [&]() -> int {
    const int st = sys.function(s, y.data(), f.data(), sys.params);
    if (st != GSL_SUCCESS) return st;
    out.s.push_back(s);
    out.Y.insert(out.Y.end(), y.begin(), y.end());
    out.F.insert(out.F.end(), f.begin(), f.end());
    return GSL_SUCCESS;
  };
  if (ret == GRAN_SUCCESS && store() != GSL_SUCCESS)
    ret = GRAN_ERROR(GRAN_ERR_NUMERIC, "%s: rates at the start are not finite", what);
  while (ret == GRAN_SUCCESS && s < s_end) {
    h = std::min(h, hmax);
    int st = gsl_odeiv2_evolve_apply(ev, ctl, stp, &sys, &s, std::min(s_end, s + hmax), &h, y.data());
    if (st == GSL_SUCCESS && !(h > 0.0 && std::isfinite(h))) st = GSL_FAILURE;
    if (st == GSL_SUCCESS) st = store();
    if (st == GSL_SUCCESS) ret = check(y.data(), M, ts * std::expm1(s));
    if (st != GSL_SUCCESS)
      ret = GRAN_ERROR(GRAN_ERR_NUMERIC, "%s (M = %" PRId64 ") failed at t = %g (GSL: %s)", what, M, ts * std::expm1(s),
                       gsl_strerror(st));
    if (ret == GRAN_SUCCESS && ev->count > maxsteps)
      ret = GRAN_ERROR(GRAN_ERR_NOCONV, "%s: more than %.0e steps (t = %g)", what, (double)maxsteps, ts * std::expm1(s));
  }
  if (ev) gsl_odeiv2_evolve_free(ev);
  if (ctl) gsl_odeiv2_control_free(ctl);
  if (stp) gsl_odeiv2_step_free(stp);
  return ret;
}

namespace {
/* |a2_k| < 1 along the first Sonine trajectory (y = z, u, a2) */
int check_first(const double *y, int64_t M, double t) {
  for (int64_t k = 0; k < M; k++)
    if (!(std::fabs(y[2 * M + k]) < 1.0))
      return GRAN_ERROR(GRAN_ERR_DOMAIN,
                        "Sonine trajectory: a2 of species %" PRId64 " reaches %g at t = %g (|a2| >= 1: the first "
                        "Sonine approximation fails)",
                        k, y[2 * M + k], t);
  return GRAN_SUCCESS;
}
}  // namespace

int sonine_traj_dense(Traj &out, const gran_mixture *mix, const double *T0, const double *a20, double ts, double rtol,
                      double hmax, double s_end) {
  GRAN_CALL(check_sonine_model(mix));
  const int64_t M = mix->M;
  STraj tr;
  tr.start(mix, T0, a20);
  tr.ts = ts;
  out = Traj();
  out.mix = mix;
  out.M = M;
  out.dim = (int)(3 * M);
  out.with_u = true;
  out.ts = tr.ts;
  out.T0 = tr.T0;
  const size_t dim = (size_t)(3 * M);
  std::vector<double> y(dim, 0.0), scale(dim, 1.0);
  for (int64_t k = 0; k < M; k++) {
    y[(size_t)(2 * M + k)] = tr.a2[(size_t)k];
    scale[(size_t)(M + k)] = 1e-30 * tr.ts; /* u_k: relative error control (u -> 0 at s -> 0) */
  }
  gsl_odeiv2_system sys{dense_rhs, nullptr, dim, &tr};
  return sonine_dense_evolve(out, sys, y, scale, tr.ts, rtol, hmax, s_end, "Sonine trajectory", 50000000UL, check_first);
}

} // namespace gran
