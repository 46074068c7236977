/* aggregation.cpp - temperature-dependent Smoluchowski kinetics of aggregating and fragmenting
 * granular gases (the DSMC outline, aggregation part; docs/physics.md, "Oracles for tests").
 *
 * State: number density n_k and thermal energy density e_k = (3/2) n_k T_k of every size k = 1..M
 * (species k of the mixture is the k-mer: m_k = k m_1), plus an overflow reservoir (number, mass in
 * monomers, energy) for clusters that would exceed M: truncation at M, the reservoir does not
 * collide further. For a pair (i, j) of Maxwellian species, with A = T_i/m_i + T_j/m_j,
 * T_ij = mu A, x = mu g^2/(2 T_ij) and s = E_n/E = (g.e)^2/g^2, the collision-weighted law is
 * x ~ Gamma(2) and s ~ U(0, 1) independent (flux weight |g.e| = g cos(theta): s = cos^2 theta has
 * density 2 c dc / (2 c) = 1). Hence, with w_a = E_agg/T_ij, w_f = E_frag/T_ij, L = max(w_a, w_f):
 *   P(stick) = P(x < w_a) = 1 - (1 + w_a) e^-w_a
 *   P(frag)  = P(s x > w_f, x >= w_a) = (1 + L - w_f) e^-L    (= e^-w_f when w_f >= w_a)
 *   E[x; stick] = 2 P(3, w_a),   E[s x; stick] = P(3, w_a)
 *   E[x; frag] = (L^2 + 2L + 2 - w_f (L + 1)) e^-L,   E[s x; frag] = (L^2 + 2L + 2 - w_f^2) e^-L / 2
 *   E[s x; bounce] = 1 - E[s x; stick] - E[s x; frag]   (E[s x] = 1: <E_n> = T_ij)
 * The centre-of-mass velocity V given g is Gaussian with mean c g, c = (T_i - T_j)/(M_ij A)
 * (g = v_i - v_j), and per-component variance Vres = (m_i T_i + m_j T_j)/M_ij^2 - c^2 A; the energy
 * of particle i in an event is (m_i/2)[3 Vres + (c + mu/m_i)^2 g^2]; a merged cluster carries
 * (M/2)[3 Vres + c^2 g^2]; fragments carry that plus eps_f^2 mu g^2/2 (Eq. 10); a bounce changes
 * E_i by -2 E_n [(1 + eps) c + (1 - eps^2) mu/(2 m_i)] on average over V (Eq. 66).
 * Rates: collisions per volume n_i n_j pi sigma_ij^2 g2 <|g_ij|> / (1 + delta_ij) (the DSMC outline Eq. 57).
 * Integrated with GSL odeiv2 (rk8pd); every pair term moves mass from i, j to i + j (or to i + j
 * monomers) in one place, so sum k n_k + overflow mass is a linear invariant of the right-hand side
 * and Runge-Kutta keeps it to rounding. Sizes with n_k <= 1e-40 n_0 are skipped (pairwise, so the
 * invariant is kept). */
#include "theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

/* Regularised lower incomplete gamma P(a, q) for a = 2, 3, without cancellation at small q. */
double gamma_p_int(int a, double q) {
  if (!(q > 0)) return 0.0;
  if (!(q < HUGE_VAL)) return 1.0;
  if (q < 1.0) {
    /* P(a, q) = q^a e^-q / a! sum_n q^n / ((a+1)...(a+n)) */
    double term = 1.0, sum = 0.0;
    for (int n = 1; n < 60 && term > 1e-18 * sum; n++) {
      sum += term;
      term *= q / (a + n);
    }
    double fact = (a == 2) ? 2.0 : 6.0;
    return std::pow(q, a) * std::exp(-q) / fact * sum;
  }
  const double e = std::exp(-q);
  if (a == 2) return 1.0 - (1.0 + q) * e;
  return 1.0 - (1.0 + q + 0.5 * q * q) * e;
}

struct PairFrac {
  double ps, pf;    /* P(stick), P(frag) */
  double xs, xf;    /* E[x; stick], E[x; frag] */
  double sxs, sxf;  /* E[s x; stick], E[s x; frag] */
};

PairFrac pair_fractions(double wa, double wf) {
  PairFrac p;
  p.ps = gamma_p_int(2, wa);
  const double p3 = gamma_p_int(3, wa);
  p.xs = 2.0 * p3;
  p.sxs = p3;
  const double L = std::max(wa, wf);
  if (L < 745.0) {
    const double e = std::exp(-L);
    p.pf = (1.0 + L - wf) * e;
    p.xf = (L * L + 2 * L + 2 - wf * (L + 1)) * e;
    p.sxf = 0.5 * (L * L + 2 * L + 2 - wf * wf) * e;
  } else {
    p.pf = p.xf = p.sxf = 0.0;
  }
  return p;
}

struct AggSys {
  const gran_mixture *mix = nullptr; /* null: constant kernel */
  int64_t M = 0;
  double K = 0;      /* constant kernel */
  double Ea = 0, Ef = HUGE_VAL, epsf2 = 0;
  int law = GRAN_FRAG_MONOMERS; /* fragment law (gran_frag_law) */
  double n0 = 1, e0 = 1; /* scales of the state */
  std::vector<double> T;
  std::vector<int64_t> act;
};

/* y: n_k/n0 (M), e_k/e0 (M), overflow number/n0, mass/n0, energy/e0 (3). */
int agg_rhs(double, const double y[], double f[], void *params) {
  AggSys &S = *static_cast<AggSys *>(params);
  const int64_t M = S.M;
  const bool ball = S.mix != nullptr;
  const double n0 = S.n0, e0 = S.e0;
  std::fill(f, f + 2 * M + 3, 0.0);
  S.act.clear();
  for (int64_t k = 0; k < M; k++) {
    if (y[k] > 1e-40) S.act.push_back(k);
    S.T[(size_t)k] = (ball && y[k] > 0) ? std::max(0.0, y[M + k] * e0 / (1.5 * y[k] * n0)) : 0.0;
  }
  double *dn = f, *de = f + M, *ov = f + 2 * M;
  const size_t na = S.act.size();
  for (size_t a = 0; a < na; a++) {
    const int64_t i = S.act[a];
    const double ni = y[i] * n0;
    for (size_t b = a; b < na; b++) {
      const int64_t j = S.act[b];
      const double nj = y[j] * n0;
      const int64_t kk = i + j + 1; /* 0-based index of the merged (i+1)+(j+1)-mer */
      const double sz = (double)(i + j + 2);
      if (!ball) {
        double R = S.K * ni * nj * (i == j ? 0.5 : 1.0) / n0;
        dn[i] -= R;
        dn[j] -= R;
        if (kk < M) dn[kk] += R;
        else {
          ov[0] += R;
          ov[1] += R * sz;
        }
        continue;
      }
      const gran_mixture *x = S.mix;
      const double mi = x->m[(size_t)i], mj = x->m[(size_t)j], Ti = S.T[(size_t)i], Tj = S.T[(size_t)j];
      const double A = Ti / mi + Tj / mj;
      if (!(A > 0)) continue;
      const double Mt = mi + mj, mu = mi * mj / Mt, Tij = mu * A;
      const double sg = gran::mix_sigma_pair(x, i, j);
      const double Kij = M_PI * sg * sg * gran::mix_g2(x, i, j) * std::sqrt(8.0 * A / M_PI);
      const double R = Kij * ni * nj * (i == j ? 0.5 : 1.0);
      const double eps = gran::mix_eps(x, i, j);
      const PairFrac p = pair_fractions(S.Ea / Tij, S.Ef / Tij);
      const double c = (Ti - Tj) / (Mt * A);
      const double vres = std::max(0.0, (mi * Ti + mj * Tj) / (Mt * Mt) - c * c * A);
      /* bounces: E_n = T_ij s x on the bounce region */
      const double sxb = 1.0 - p.sxs - p.sxf;
      const double Enb = R * Tij * sxb;
      de[i] += -2.0 * Enb * ((1 + eps) * c + (1 - eps * eps) * mu / (2 * mi)) / e0;
      de[j] += -2.0 * Enb * (-(1 + eps) * c + (1 - eps * eps) * mu / (2 * mj)) / e0;
      const double g2f = 2.0 * Tij / mu; /* g^2 = g2f x */
      const double ci = c + mu / mi, cj = -c + mu / mj;
      /* sticking */
      if (p.ps > 0) {
        const double Rs = R * p.ps, Rx = R * p.xs;
        dn[i] -= Rs / n0;
        dn[j] -= Rs / n0;
        de[i] -= (Rs * 1.5 * mi * vres + Rx * 0.5 * mi * ci * ci * g2f) / e0;
        de[j] -= (Rs * 1.5 * mj * vres + Rx * 0.5 * mj * cj * cj * g2f) / e0;
        const double eg = Rs * 1.5 * Mt * vres + Rx * 0.5 * Mt * c * c * g2f;
        if (kk < M) {
          dn[kk] += Rs / n0;
          de[kk] += eg / e0;
        } else {
          ov[0] += Rs / n0;
          ov[1] += Rs * sz / n0;
          ov[2] += eg / e0;
        }
      }
      /* fragmentation into i + j monomers */
      if (p.pf > 0) {
        const double Rf = R * p.pf, Rx = R * p.xf;
        dn[i] -= Rf / n0;
        dn[j] -= Rf / n0;
        de[i] -= (Rf * 1.5 * mi * vres + Rx * 0.5 * mi * ci * ci * g2f) / e0;
        de[j] -= (Rf * 1.5 * mj * vres + Rx * 0.5 * mj * cj * cj * g2f) / e0;
        if (S.law == GRAN_FRAG_BINARY && sz > 2) {
          /* two pieces a, K - a, a uniform in 1..K-1: size s gets 2/(K-1) pieces per breakup, each
           * with the centre-of-mass motion of its mass and the share (K - s)/K of eps_f^2 E_imp
           * (two bodies of equal and opposite momenta in the CM frame) */
          const int64_t K = i + j + 2;
          const double w = 2.0 / (double)(K - 1), m1 = x->m[0];
          for (int64_t q = 1; q < K; q++) {
            const double ms = (double)q * m1;
            const double es = w * (Rf * 1.5 * ms * vres + Rx * (0.5 * ms * c * c * g2f +
                                                             S.epsf2 * Tij * (double)(K - q) / (double)K));
            if (q <= M) {
              dn[q - 1] += w * Rf / n0;
              de[q - 1] += es / e0;
            } else { /* a piece beyond M: the overflow reservoir */
              ov[0] += w * Rf / n0;
              ov[1] += w * Rf * (double)q / n0;
              ov[2] += es / e0;
            }
          }
        } else {
          dn[0] += Rf * sz / n0;
          de[0] += (Rf * 1.5 * Mt * vres + Rx * (0.5 * Mt * c * c * g2f + S.epsf2 * Tij)) / e0;
        }
      }
    }
  }
  for (int64_t k = 0; k < 2 * M + 3; k++)
    if (!std::isfinite(f[k])) return GSL_EBADFUNC;
  return GSL_SUCCESS;
}

int check_sorted_times(const double *t, int64_t n) {
  GRAN_CALL(gran::check_times(t, n, "t"));
  for (int64_t k = 1; k < n; k++)
    GRAN_CHECK(t[k] >= t[k - 1], GRAN_ERR_ARG, "argument 't' must be nondecreasing (t[%lld] < t[%lld])",
               (long long)k, (long long)(k - 1));
  return GRAN_SUCCESS;
}

/* Integrate S from y (scaled) to every t; write n (ntimes*M), T (ntimes*M, may be NULL), overflow
 * (ntimes*3, may be NULL). */
int agg_integrate(AggSys &S, std::vector<double> &y, double h0, int64_t ntimes, const double *t, double rtol,
                  double *n, double *T, double *overflow) {
  const int64_t M = S.M, dim = 2 * M + 3;
  S.T.assign((size_t)M, 0.0);
  gsl_odeiv2_system sys = {agg_rhs, nullptr, (size_t)dim, &S};
  gsl_odeiv2_driver *d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, h0, rtol * 1e-6, rtol);
  GRAN_CHECK(d != nullptr, GRAN_ERR_NOMEM, "out of memory (GSL ODE driver for %lld sizes)", (long long)M);
  gsl_odeiv2_driver_set_nmax(d, 10000000);
  double tc = 0.0;
  int st = GSL_SUCCESS;
  for (int64_t q = 0; q < ntimes; q++) {
    if (t[q] > tc) st = gsl_odeiv2_driver_apply(d, &tc, t[q], y.data());
    if (st != GSL_SUCCESS) break;
    for (int64_t k = 0; k < M; k++) {
      const double nk = y[(size_t)k] * S.n0;
      n[q * M + k] = nk;
      if (T) T[q * M + k] = (S.mix && y[(size_t)k] > 0) ? y[(size_t)(M + k)] * S.e0 / (1.5 * nk) : 0.0;
    }
    if (overflow) {
      overflow[3 * q] = y[(size_t)(2 * M)] * S.n0;
      overflow[3 * q + 1] = y[(size_t)(2 * M + 1)] * S.n0;
      overflow[3 * q + 2] = y[(size_t)(2 * M + 2)] * S.e0;
    }
  }
  gsl_odeiv2_driver_free(d);
  GRAN_CHECK(st == GSL_SUCCESS, GRAN_ERR_NOCONV,
             "aggregation kinetics: GSL ODE integration failed (GSL status %d: %s); try a larger rtol", st,
             gsl_strerror(st));
  return GRAN_SUCCESS;
}

} // namespace

/**
 * @brief Maxwellian fractions of the collisions of a pair (i, j) that stick (mu g^2/2 < E_agg) and
 *        that shatter (mu g_n^2/2 > E_frag and not sticking): 1 - (1 + q) e^-q, q = E_agg/T_ij, and
 *        (1 + L - w) e^-L, w = E_frag/T_ij, L = max(q, w) (= e^-w when E_frag >= E_agg).
 * @param[in] mi, mj masses > 0; Ti, Tj temperatures >= 0, not both 0; E_agg >= 0; E_frag >= 0 (inf ok)
 */
GRAN_EXTERN int gran_theory_agg_fractions(double mi, double mj, double Ti, double Tj, double E_agg, double E_frag,
                                          double *f_stick, double *f_frag) {
  GRAN_TRY {
    GRAN_CHECK(std::isfinite(mi) && mi > 0, GRAN_ERR_ARG, "argument 'mi' must be finite and > 0 (%g)", mi);
    GRAN_CHECK(std::isfinite(mj) && mj > 0, GRAN_ERR_ARG, "argument 'mj' must be finite and > 0 (%g)", mj);
    GRAN_CHECK(std::isfinite(Ti) && Ti >= 0, GRAN_ERR_ARG, "argument 'Ti' must be finite and >= 0 (%g)", Ti);
    GRAN_CHECK(std::isfinite(Tj) && Tj >= 0, GRAN_ERR_ARG, "argument 'Tj' must be finite and >= 0 (%g)", Tj);
    GRAN_CHECK(Ti + Tj > 0, GRAN_ERR_ARG, "arguments 'Ti' and 'Tj' are both 0");
    GRAN_CHECK(std::isfinite(E_agg) && E_agg >= 0, GRAN_ERR_ARG, "argument 'E_agg' must be finite and >= 0 (%g)",
               E_agg);
    GRAN_CHECK(E_frag >= 0, GRAN_ERR_ARG, "argument 'E_frag' must be >= 0 (infinity: no fragmentation) (%g)",
               E_frag);
    GRAN_CHECK_PTR(f_stick);
    GRAN_CHECK_PTR(f_frag);
    const double Tij = (mj * Ti + mi * Tj) / (mi + mj);
    const PairFrac p = pair_fractions(E_agg / Tij, E_frag / Tij);
    *f_stick = p.ps;
    *f_frag = p.pf;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Temperature-dependent Smoluchowski equations with ballistic kernels: n_k(t), T_k(t) of the
 *        sizes k = 1..M (species k-1 of mix is the k-mer, m_k = k m_1; initial densities from mix).
 * @param[in] T0 M initial temperatures (finite >= 0; > 0 where n_k > 0)
 * @param[in] E_agg >= 0 (0: no sticking); E_frag >= 0 (INFINITY: no fragmentation); eps_f in [0, 1]
 * @param[in] t ntimes nondecreasing times >= 0; rtol in [1e-14, 0.1]
 * @param[out] n ntimes*M densities; T ntimes*M temperatures (0 where n_k = 0; may be NULL);
 *             overflow ntimes*3: number, mass (monomers) and kinetic energy per volume of clusters
 *             larger than M (truncation; they no longer collide), may be NULL
 */
GRAN_EXTERN int gran_theory_aggregation(const gran_mixture *mix, const double *T0, double E_agg, double E_frag,
                                        double eps_f, int64_t ntimes, const double *t, double rtol, double *n,
                                        double *T, double *overflow) {
  return gran_theory_aggregation_law(mix, T0, E_agg, E_frag, eps_f, GRAN_FRAG_MONOMERS, ntimes, t, rtol, n, T,
                                     overflow);
}

/** @brief gran_theory_aggregation with the fragment law (gran_frag_law): GRAN_FRAG_MONOMERS, or
 *  GRAN_FRAG_BINARY (the (i+j)-mer into two pieces of a uniform size; pieces beyond M go to the
 *  overflow reservoir). */
GRAN_EXTERN int gran_theory_aggregation_law(const gran_mixture *mix, const double *T0, double E_agg, double E_frag,
                                            double eps_f, int frag_law, int64_t ntimes, const double *t, double rtol,
                                            double *n, double *T, double *overflow) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(gran::check_mixture(mix, "mix"));
    const int64_t M = mix->M;
    GRAN_CALL(gran::check_array(T0, M, "T0", 0));
    GRAN_CHECK(mix->model == GRAN_RESTITUTION_CONSTANT || mix->model == GRAN_RESTITUTION_MATRIX,
               GRAN_ERR_UNSUPPORTED, "aggregation kinetics: restitution model %d of 'mix' is not supported "
               "(constant or matrix only)", mix->model);
    for (int64_t k = 1; k < M; k++)
      GRAN_CHECK(std::fabs(mix->m[(size_t)k] - (double)(k + 1) * mix->m[0]) <= 1e-12 * (double)(k + 1) * mix->m[0],
                 GRAN_ERR_DOMAIN, "aggregation kinetics: species %lld of 'mix' must be the %lld-mer, mass %g "
                 "(= k m_1), not %g", (long long)k, (long long)(k + 1), (double)(k + 1) * mix->m[0],
                 mix->m[(size_t)k]);
    GRAN_CHECK(std::isfinite(E_agg) && E_agg >= 0, GRAN_ERR_ARG, "argument 'E_agg' must be finite and >= 0 (%g)",
               E_agg);
    GRAN_CHECK(E_frag >= 0, GRAN_ERR_ARG, "argument 'E_frag' must be >= 0 (infinity: no fragmentation) (%g)",
               E_frag);
    GRAN_CHECK(eps_f >= 0 && eps_f <= 1, GRAN_ERR_ARG, "argument 'eps_f' must lie in [0, 1] (%g)", eps_f);
    GRAN_CHECK(frag_law == GRAN_FRAG_MONOMERS || frag_law == GRAN_FRAG_BINARY, GRAN_ERR_ARG,
               "argument 'frag_law' = %d is not a gran_frag_law", frag_law);
    GRAN_CHECK(ntimes >= 0, GRAN_ERR_ARG, "argument 'ntimes' must be >= 0 (%lld)", (long long)ntimes);
    GRAN_CALL(check_sorted_times(t, ntimes));
    GRAN_CALL(gran::check_rtol(rtol, "rtol"));
    GRAN_CHECK_PTR(n);
    AggSys S;
    S.mix = mix;
    S.M = M;
    S.Ea = E_agg;
    S.Ef = E_frag;
    S.epsf2 = eps_f * eps_f;
    S.law = frag_law;
    double ntot = 0, etot = 0, rate = 0;
    for (int64_t k = 0; k < M; k++) {
      const double nk = mix->n[(size_t)k];
      GRAN_CHECK(!(nk > 0) || T0[k] > 0, GRAN_ERR_ARG, "argument 'T0[%lld]' must be > 0 where n_k > 0 (%g)",
                 (long long)k, T0[k]);
      ntot += nk;
      etot += 1.5 * nk * T0[k];
    }
    GRAN_CHECK(ntot > 0 && etot > 0, GRAN_ERR_ARG, "argument 'mix' has no particles (all densities 0)");
    S.n0 = ntot;
    S.e0 = etot;
    std::vector<double> y((size_t)(2 * M + 3), 0.0);
    for (int64_t k = 0; k < M; k++) {
      y[(size_t)k] = mix->n[(size_t)k] / ntot;
      y[(size_t)(M + k)] = 1.5 * mix->n[(size_t)k] * T0[k] / etot;
      if (mix->n[(size_t)k] > 0) {
        const double s = mix->sigma[(size_t)k];
        rate = std::max(rate, ntot * s * s * std::sqrt(T0[k] / mix->m[(size_t)k]));
      }
    }
    const double h0 = 1e-3 / std::max(rate, 1e-300);
    return agg_integrate(S, y, h0, ntimes, t, rtol, n, T, overflow);
  }
  GRAN_CATCH
}

/**
 * @brief Smoluchowski equations with a constant kernel K (every collision sticks; rate per volume
 *        K n_i n_j / (1 + delta_ij)), sizes 1..kmax, truncation as gran_theory_aggregation.
 * @param[in] n0 kmax initial densities >= 0 (not all 0); t ntimes nondecreasing >= 0; rtol
 * @param[out] n ntimes*kmax; overflow ntimes*3 (number, mass, 0), may be NULL
 */
GRAN_EXTERN int gran_theory_smoluchowski_constant(int64_t kmax, double K, const double *n0, int64_t ntimes,
                                                  const double *t, double rtol, double *n, double *overflow) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CHECK(kmax >= 1 && kmax <= 100000000, GRAN_ERR_ARG, "argument 'kmax' must lie in [1, 1e8] (%lld)",
               (long long)kmax);
    GRAN_CHECK(std::isfinite(K) && K > 0, GRAN_ERR_ARG, "argument 'K' must be finite and > 0 (%g)", K);
    GRAN_CALL(gran::check_array(n0, kmax, "n0", 0));
    GRAN_CHECK(ntimes >= 0, GRAN_ERR_ARG, "argument 'ntimes' must be >= 0 (%lld)", (long long)ntimes);
    GRAN_CALL(check_sorted_times(t, ntimes));
    GRAN_CALL(gran::check_rtol(rtol, "rtol"));
    GRAN_CHECK_PTR(n);
    double ntot = 0;
    for (int64_t k = 0; k < kmax; k++) ntot += n0[k];
    GRAN_CHECK(ntot > 0, GRAN_ERR_ARG, "argument 'n0' is all 0");
    AggSys S;
    S.M = kmax;
    S.K = K;
    S.n0 = ntot;
    S.e0 = 1.0;
    std::vector<double> y((size_t)(2 * kmax + 3), 0.0);
    for (int64_t k = 0; k < kmax; k++) y[(size_t)k] = n0[k] / ntot;
    return agg_integrate(S, y, 1e-3 / (K * ntot), ntimes, t, rtol, n, nullptr, overflow);
  }
  GRAN_CATCH
}
