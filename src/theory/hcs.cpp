/* hcs.cpp - homogeneous cooling state of a mixture (Bodrova & Osinsky Eq. 16-21, 25): temperatures with
 * equal cooling rates xi_k = c, normalised by the number-weighted mean (Eq. 25) or by T_1, and
 * tau0 = 2/c (Eq. 21).
 *
 * Unknowns u_k = log T_k (species `ref`, the densest, fixed at u = 0) and c. xi is homogeneous of
 * degree 1/2 in T, so the ratios fix the state; the normalisation is applied at the end. The
 * convergence measure is max_k |xi_k - c*|/nu_k, with nu_k the collision frequency of species k and
 * c* the least-squares common rate: it measures |du| independently of (1 - eps^2), so eps -> 1
 * stays well posed (eps = 1 exactly: equipartition, tau0 = inf, no solve).
 *
 * Solvers (why): Newton from equipartition overshoots by orders of magnitude (xi_k is flat in T_k
 * near equipartition and grows like T^(3/2) beyond), and GSL's hybridsj/gnewton then stall. Every
 * Newton step is therefore clamped to |du| <= 1 (a factor e in T per step), which converges from
 * equipartition in all cases tried (mass ratios up to 1e8).
 *  - M <= HCS_DENSE_MAX (64): clamped Newton on the bordered system (exact analytic Jacobian, GSL LU)
 *    down to a residual of 1e-8, then GSL multiroots hybridsj (analytic Jacobian) polishes to
 *    1e-14 on F_k = (xi_k - xi_ref)/nu_k.
 *  - Larger M (a dense Jacobian is O(M^2) memory and O(M^3) time: 1e5 species would need 80 GB):
 *    clamped Newton whose Jacobian J = diag(d) + L is kept exact on the diagonal and has its
 *    smooth kernel part L_kj = n_j K(k, j) compressed by adaptive cross approximation (rank r at
 *    relative accuracy 1e-12, typically r ~ 20-60), solved by the Woodbury identity in O(M r^2).
 *    The start comes from the HCS of a coarse mixture (<= 48 species binned in log mass, densities
 *    summed), interpolated in log mass. Each iteration costs one O(M^2) pass (xi and d together,
 *    vectorised, each unordered pair visited once) plus O(r M) kernel entries: 3-6 passes in total.
 *    The pair sums themselves stay exact. */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multiroots.h>

#include <algorithm>
#include <cstdio>
#include <numeric>


namespace {

using namespace gran;


struct Pass {
  std::vector<double> xi, d, l, nu;
};

void do_pass(const gran_mixture *mix, const double *T, Pass &P) {
  const size_t M = (size_t)mix->M;
  P.xi.resize(M);
  P.d.resize(M);
  P.l.resize(M);
  P.nu.resize(M);
  cooling_pass(mix, T, P.xi.data(), P.d.data(), P.l.data(), P.nu.data());
}

const int64_t HCS_DENSE_MAX = 64;
const int HCS_COARSE_BINS = 48; /* <= HCS_DENSE_MAX: the coarse problem is solved densely */
const double RES_TOL = 1e-13;

/* Column part of the Jacobian: L_kj = d f_kj / d u_j (the smooth kernel compressed by ACA). */
inline double lcol(const gran_mixture *mix, const double *T, const double *scale, int64_t k, int64_t j) {
  const double nj = mix->n[(size_t)j];
  if (nj == 0.0) return 0.0;
  const double mk = mix->m[(size_t)k], mj = mix->m[(size_t)j];
  const double sg = 0.5 * (mix->sigma[(size_t)k] + mix->sigma[(size_t)j]);
  const double ak = T[k] / mk, aj = T[j] / mj, S = std::sqrt(ak + aj), inv = 1.0 / (mj + mk);
  const double mu = mj * inv, omu = mk * inv, r = T[j] / T[k], omr = (T[k] - T[j]) / T[k];
  const double eps = mix_eps(mix, k, j), p = 0.5 * (1.0 + eps), q = 0.5 * (1.0 - eps);
  const double B = omu * omr + q * (mu + r * omu);
  const double W = C15 * nj * sg * sg * mix_g2(mix, k, j) * mu * 2.0 * p;
  return (scale ? scale[k] : 1.0) * W * (0.5 * aj * B / S - S * p * r * omu);
}

/* Least-squares common rate c* = sum xi_k/nu_k^2 / sum 1/nu_k^2 and the residual max |xi - c*|/nu. */
double residual(const Pass &P, double *cstar) {
  double num = 0.0, den = 0.0;
  for (size_t k = 0; k < P.xi.size(); k++) {
    const double w = 1.0 / (P.nu[k] * P.nu[k]);
    num += w * P.xi[k];
    den += w;
  }
  const double c = num / den;
  double r = 0.0;
  for (size_t k = 0; k < P.xi.size(); k++) r = std::max(r, std::fabs(P.xi[k] - c) / P.nu[k]);
  if (cstar) *cstar = c;
  return r;
}

/* ---- adaptive cross approximation of L (partial pivoting): L ~ U V^T, U, V column-major M*r --- */
struct LowRank {
  int r = 0;
  std::vector<double> U, V;
};

void aca(const gran_mixture *mix, const double *T, const double *scale, double tol, int rmax, LowRank &LR) {
  const int64_t M = mix->M;
  LR.r = 0;
  LR.U.clear();
  LR.V.clear();
  std::vector<char> usedr((size_t)M, 0), usedc((size_t)M, 0);
  std::vector<double> row((size_t)M), col((size_t)M);
  double norm2 = 0.0;
  int64_t i = 0;
  /* start from the densest species' row: the largest entries live in its column */
  for (int64_t k = 1; k < M; k++)
    if (mix->n[(size_t)k] > mix->n[(size_t)i]) i = k;
  int misses = 0;
  while (LR.r < rmax) {
    usedr[(size_t)i] = 1;
    for (int64_t j = 0; j < M; j++) row[(size_t)j] = lcol(mix, T, scale, i, j);
    for (int l = 0; l < LR.r; l++) {
      const double ui = LR.U[(size_t)l * M + i];
      const double *v = LR.V.data() + (size_t)l * M;
      for (int64_t j = 0; j < M; j++) row[(size_t)j] -= ui * v[j];
    }
    int64_t jp = -1;
    double best = 0.0;
    for (int64_t j = 0; j < M; j++)
      if (!usedc[(size_t)j] && std::fabs(row[(size_t)j]) > best) {
        best = std::fabs(row[(size_t)j]);
        jp = j;
      }
    if (jp < 0 || best <= 1e-300) {
      /* row already represented: try another unused row */
      if (++misses > 3) break;
      int64_t next = -1;
      for (int64_t k = 0; k < M; k++)
        if (!usedr[(size_t)k]) {
          next = k;
          break;
        }
      if (next < 0) break;
      i = next;
      continue;
    }
    usedc[(size_t)jp] = 1;
    const double piv = row[(size_t)jp];
    for (int64_t k = 0; k < M; k++) col[(size_t)k] = lcol(mix, T, scale, k, jp);
    for (int l = 0; l < LR.r; l++) {
      const double vj = LR.V[(size_t)l * M + jp];
      const double *u = LR.U.data() + (size_t)l * M;
      for (int64_t k = 0; k < M; k++) col[(size_t)k] -= vj * u[k];
    }
    for (auto &v : row) v /= piv;
    double uu = 0.0, vv = 0.0, cross = 0.0;
    for (int64_t k = 0; k < M; k++) {
      uu += col[(size_t)k] * col[(size_t)k];
      vv += row[(size_t)k] * row[(size_t)k];
    }
    for (int l = 0; l < LR.r; l++) {
      double a = 0.0, b = 0.0;
      const double *u = LR.U.data() + (size_t)l * M, *v = LR.V.data() + (size_t)l * M;
      for (int64_t k = 0; k < M; k++) {
        a += u[k] * col[(size_t)k];
        b += v[k] * row[(size_t)k];
      }
      cross += a * b;
    }
    norm2 += uu * vv + 2.0 * cross;
    LR.U.insert(LR.U.end(), col.begin(), col.end());
    LR.V.insert(LR.V.end(), row.begin(), row.end());
    LR.r++;
    misses = 0;
    if (std::sqrt(uu * vv) <= tol * std::sqrt(std::fabs(norm2))) break;
    int64_t ip = -1;
    best = -1.0;
    for (int64_t k = 0; k < M; k++)
      if (!usedr[(size_t)k] && std::fabs(col[(size_t)k]) > best) {
        best = std::fabs(col[(size_t)k]);
        ip = k;
      }
    if (ip < 0) break;
    i = ip;
  }
}

/* ---- Newton on the bordered system [J -1; e_ref^T 0] [du; dc] = [c - xi; -u_ref] -------------- */
struct Newton {
  const gran_mixture *mix;
  int64_t M, ref;
  bool dense;
  std::vector<double> u, T;
  double c = 0.0;
  double res = HUGE_VAL;
  int iters = 0, rank = 0;
  Pass P;
  const double *scale = nullptr; /* rates xi_k scale_k (frozen factors), NULL: 1 */
  const HcsPass *first = nullptr; /* the pass at the start u (unscaled), NULL: computed */
  int max_steps = -1;            /* >= 0: return after this many steps without a final check */
};

int solve_dense_step(Newton &N, std::vector<double> &du, double &dc) {
  const int64_t M = N.M;
  std::vector<double> xi((size_t)M), J((size_t)(M * M));
  cooling_jacobian(N.mix, N.T.data(), xi.data(), J.data());
  if (N.scale)
    for (int64_t k = 0; k < M; k++) {
      xi[(size_t)k] *= N.scale[k];
      for (int64_t j = 0; j < M; j++) J[(size_t)(k * M + j)] *= N.scale[k];
    }
  gsl_matrix *A = gsl_matrix_calloc((size_t)M + 1, (size_t)M + 1);
  gsl_vector *b = gsl_vector_alloc((size_t)M + 1);
  gsl_permutation *perm = gsl_permutation_alloc((size_t)M + 1);
  if (!A || !b || !perm) {
    gsl_matrix_free(A);
    gsl_vector_free(b);
    gsl_permutation_free(perm);
    return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate the HCS Newton system (M = %" PRId64 ")", M);
  }
  for (int64_t k = 0; k < M; k++) {
    for (int64_t j = 0; j < M; j++) gsl_matrix_set(A, (size_t)k, (size_t)j, J[(size_t)(k * M + j)]);
    gsl_matrix_set(A, (size_t)k, (size_t)M, -1.0);
    gsl_vector_set(b, (size_t)k, N.c - xi[(size_t)k]);
  }
  gsl_matrix_set(A, (size_t)M, (size_t)N.ref, 1.0);
  gsl_vector_set(b, (size_t)M, -N.u[(size_t)N.ref]);
  int sgn = 0;
  int st = gsl_linalg_LU_decomp(A, perm, &sgn);
  if (st == GSL_SUCCESS) st = gsl_linalg_LU_svx(A, perm, b);
  for (int64_t k = 0; k < M; k++) du[(size_t)k] = gsl_vector_get(b, (size_t)k);
  dc = gsl_vector_get(b, (size_t)M);
  gsl_matrix_free(A);
  gsl_vector_free(b);
  gsl_permutation_free(perm);
  if (st != GSL_SUCCESS)
    return GRAN_ERROR(GRAN_ERR_NUMERIC, "HCS Newton system is singular (GSL: %s)", gsl_strerror(st));
  return GRAN_SUCCESS;
}

int solve_lowrank_step(Newton &N, std::vector<double> &du, double &dc) {
  const int64_t M = N.M;
  LowRank LR;
  aca(N.mix, N.T.data(), N.scale, 1e-12, (int)std::min<int64_t>(M, 256), LR);
  const int r = LR.r;
  N.rank = r;
  /* D' = d + l - diag(U V^T): the Jacobian's diagonal stays exact */
  std::vector<double> Dinv((size_t)M);
  for (int64_t k = 0; k < M; k++) {
    double uv = 0.0;
    for (int l = 0; l < r; l++) uv += LR.U[(size_t)l * M + k] * LR.V[(size_t)l * M + k];
    const double D = N.P.d[(size_t)k] + N.P.l[(size_t)k] - uv;
    if (!(std::fabs(D) > 0.0) || !std::isfinite(D))
      return GRAN_ERROR(GRAN_ERR_NUMERIC, "HCS Newton: zero diagonal for species %" PRId64, k);
    Dinv[(size_t)k] = 1.0 / D;
  }
  /* capacitance I + V^T D^-1 U (r x r) */
  gsl_matrix *Cap = nullptr;
  gsl_permutation *perm = nullptr;
  gsl_vector *z = nullptr;
  if (r > 0) {
    Cap = gsl_matrix_alloc((size_t)r, (size_t)r);
    perm = gsl_permutation_alloc((size_t)r);
    z = gsl_vector_alloc((size_t)r);
    if (!Cap || !perm || !z) {
      gsl_matrix_free(Cap);
      gsl_permutation_free(perm);
      gsl_vector_free(z);
      return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate the HCS capacitance matrix (rank %d)", r);
    }
    for (int a = 0; a < r; a++)
      for (int b = 0; b < r; b++) {
        double sum = a == b ? 1.0 : 0.0;
        const double *v = LR.V.data() + (size_t)a * M, *u = LR.U.data() + (size_t)b * M;
        for (int64_t k = 0; k < M; k++) sum += v[k] * Dinv[(size_t)k] * u[k];
        gsl_matrix_set(Cap, (size_t)a, (size_t)b, sum);
      }
    int sgn = 0;
    int st = gsl_linalg_LU_decomp(Cap, perm, &sgn);
    if (st != GSL_SUCCESS) {
      gsl_matrix_free(Cap);
      gsl_permutation_free(perm);
      gsl_vector_free(z);
      return GRAN_ERROR(GRAN_ERR_NUMERIC, "HCS Newton: singular capacitance matrix (GSL: %s)", gsl_strerror(st));
    }
  }
  auto apply_inv = [&](std::vector<double> &x) -> int { /* x <- J^-1 x */
    for (int64_t k = 0; k < M; k++) x[(size_t)k] *= Dinv[(size_t)k];
    if (r == 0) return GSL_SUCCESS;
    for (int a = 0; a < r; a++) {
      double sum = 0.0;
      const double *v = LR.V.data() + (size_t)a * M;
      for (int64_t k = 0; k < M; k++) sum += v[k] * x[(size_t)k];
      gsl_vector_set(z, (size_t)a, sum);
    }
    int st = gsl_linalg_LU_svx(Cap, perm, z);
    if (st != GSL_SUCCESS) return st;
    for (int a = 0; a < r; a++) {
      const double za = gsl_vector_get(z, (size_t)a);
      const double *u = LR.U.data() + (size_t)a * M;
      for (int64_t k = 0; k < M; k++) x[(size_t)k] -= Dinv[(size_t)k] * u[k] * za;
    }
    return GSL_SUCCESS;
  };
  std::vector<double> x1((size_t)M), x2((size_t)M, 1.0);
  for (int64_t k = 0; k < M; k++) x1[(size_t)k] = N.c - N.P.xi[(size_t)k];
  int st = apply_inv(x1);
  if (st == GSL_SUCCESS) st = apply_inv(x2);
  gsl_matrix_free(Cap);
  gsl_permutation_free(perm);
  gsl_vector_free(z);
  if (st != GSL_SUCCESS) return GRAN_ERROR(GRAN_ERR_NUMERIC, "HCS Newton: solve failed (GSL: %s)", gsl_strerror(st));
  const size_t rf = (size_t)N.ref;
  if (!(std::fabs(x2[rf]) > 0.0)) return GRAN_ERROR(GRAN_ERR_NUMERIC, "HCS Newton: degenerate bordered system");
  dc = (-N.u[rf] - x1[rf]) / x2[rf];
  for (int64_t k = 0; k < M; k++) du[(size_t)k] = x1[(size_t)k] + dc * x2[(size_t)k];
  return GRAN_SUCCESS;
}

/* Clamped Newton until the residual is below `tol` (or stagnates below 1e-10). */
int newton(Newton &N, double tol, int maxit) {
  const int64_t M = N.M;
  std::vector<double> du((size_t)M);
  double prev = HUGE_VAL;
  int stall = 0;
  for (N.iters = 0;; N.iters++) {
    for (int64_t k = 0; k < M; k++) N.T[(size_t)k] = std::exp(N.u[(size_t)k]);
    if (N.iters == 0 && N.first) {
      N.P.xi.assign(N.first->xi, N.first->xi + M);
      N.P.d.assign(N.first->d, N.first->d + M);
      N.P.l.assign(N.first->l, N.first->l + M);
      N.P.nu.assign(N.first->nu, N.first->nu + M);
    } else {
      do_pass(N.mix, N.T.data(), N.P);
    }
    if (N.scale)
      for (int64_t k = 0; k < M; k++) {
        N.P.xi[(size_t)k] *= N.scale[k];
        N.P.d[(size_t)k] *= N.scale[k];
        N.P.l[(size_t)k] *= N.scale[k];
      }
    double cstar = 0.0;
    N.res = residual(N.P, &cstar);
    if (!std::isfinite(N.res)) return GRAN_ERROR(GRAN_ERR_NUMERIC, "HCS: non-finite cooling rates during the solve");
    if (N.iters == 0) N.c = cstar;
#ifdef GRAN_HCS_DEBUG
    std::fprintf(stderr, "hcs: M = %" PRId64 " %s iteration %d residual %.3e rank %d\n", M, N.dense ? "dense" : "aca",
                 N.iters, N.res, N.rank);
#endif
    if (N.res <= tol) return GRAN_SUCCESS;
    if (N.res > 0.5 * prev) stall++;
    else stall = 0;
    if (stall >= 3 && N.res < 1e-10) return GRAN_SUCCESS; /* rounding floor */
    if (N.iters >= maxit)
      return GRAN_ERROR(GRAN_ERR_NOCONV, "HCS (M = %" PRId64 ") did not converge: residual %.3g after %d Newton steps",
                        M, N.res, N.iters);
    prev = std::min(prev, N.res);
    double dc = 0.0;
    GRAN_CALL(N.dense ? solve_dense_step(N, du, dc) : solve_lowrank_step(N, du, dc));
    double big = 0.0;
    for (double v : du) big = std::max(big, std::fabs(v));
    if (!std::isfinite(big)) return GRAN_ERROR(GRAN_ERR_NUMERIC, "HCS Newton: non-finite step");
    const double sc = big > 1.0 ? 1.0 / big : 1.0;
    for (int64_t k = 0; k < M; k++) N.u[(size_t)k] += sc * du[(size_t)k];
    N.c += sc * dc;
    if (N.max_steps >= 0 && N.iters + 1 >= N.max_steps) return GRAN_SUCCESS;
  }
}

/* ---- GSL hybridsj polish (M <= HCS_DENSE_MAX) -------------------------------------------------- */
struct HcsSys {
  const gran_mixture *mix;
  int64_t ref;
  std::vector<double> T, xi, J, nu;
};

void set_T(HcsSys *h, const gsl_vector *x) {
  const int64_t M = h->mix->M;
  for (int64_t k = 0, j = 0; k < M; k++) h->T[(size_t)k] = k == h->ref ? 1.0 : std::exp(gsl_vector_get(x, (size_t)j++));
}

int hcs_fdf(const gsl_vector *x, void *params, gsl_vector *f, gsl_matrix *Jm) {
  HcsSys *h = static_cast<HcsSys *>(params);
  const int64_t M = h->mix->M, ref = h->ref;
  set_T(h, x);
  cooling_jacobian(h->mix, h->T.data(), h->xi.data(), h->J.data());
  for (int64_t k = 0, a = 0; k < M; k++) {
    if (k == ref) continue;
    const double fk = (h->xi[(size_t)k] - h->xi[(size_t)ref]) / h->nu[(size_t)k];
    if (!std::isfinite(fk)) return GSL_EBADFUNC;
    if (f) gsl_vector_set(f, (size_t)a, fk);
    if (Jm)
      for (int64_t j = 0, b = 0; j < M; j++) {
        if (j == ref) continue;
        gsl_matrix_set(Jm, (size_t)a, (size_t)b++,
                       (h->J[(size_t)(k * M + j)] - h->J[(size_t)(ref * M + j)]) / h->nu[(size_t)k]);
      }
    a++;
  }
  return GSL_SUCCESS;
}
int hcs_f(const gsl_vector *x, void *params, gsl_vector *f) { return hcs_fdf(x, params, f, nullptr); }
int hcs_df(const gsl_vector *x, void *params, gsl_matrix *J) { return hcs_fdf(x, params, nullptr, J); }

double max_abs(const gsl_vector *v) {
  double a = 0.0;
  for (size_t i = 0; i < v->size; i++) a = std::max(a, std::fabs(gsl_vector_get(v, i)));
  return a;
}

/* Polish u (u[ref] = 0) with GSL hybridsj; keeps the input when GSL does not improve it. */
void hcs_hybridsj(const gran_mixture *mix, int64_t ref, std::vector<double> &u) {
  const int64_t M = mix->M;
  HcsSys h;
  h.mix = mix;
  h.ref = ref;
  h.T.assign((size_t)M, 1.0);
  h.xi.assign((size_t)M, 0.0);
  h.J.assign((size_t)(M * M), 0.0);
  h.nu.assign((size_t)M, 1.0);
  for (int64_t k = 0; k < M; k++) h.T[(size_t)k] = std::exp(u[(size_t)k] - u[(size_t)ref]);
  collision_scale(mix, h.T.data(), h.nu.data());
  const size_t dim = (size_t)(M - 1);
  gsl_multiroot_function_fdf F{hcs_f, hcs_df, hcs_fdf, dim, &h};
  gsl_vector *x = gsl_vector_alloc(dim);
  gsl_multiroot_fdfsolver *sv = gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_hybridsj, dim);
  if (x && sv) {
    for (int64_t k = 0, a = 0; k < M; k++)
      if (k != ref) gsl_vector_set(x, (size_t)a++, u[(size_t)k] - u[(size_t)ref]);
    if (gsl_multiroot_fdfsolver_set(sv, &F, x) == GSL_SUCCESS) {
      const double res0 = max_abs(sv->f);
      double res = res0;
      for (int iter = 0; iter < 50 && res > 1e-15; iter++) {
        if (gsl_multiroot_fdfsolver_iterate(sv) != GSL_SUCCESS) break;
        res = max_abs(sv->f);
        if (gsl_multiroot_test_delta(sv->dx, sv->x, 1e-17, 1e-16) == GSL_SUCCESS) break;
      }
      if (res <= res0)
        for (int64_t k = 0, a = 0; k < M; k++)
          u[(size_t)k] = k == ref ? 0.0 : gsl_vector_get(sv->x, (size_t)a++);
    }
  }
  gsl_vector_free(x);
  gsl_multiroot_fdfsolver_free(sv);
}

/* ---- coarse start for large M ------------------------------------------------------------------ */
int solve_u(const gran_mixture *mix, std::vector<double> &u, int64_t *ref_out, double *cbar, double tol,
            int *passes);

void coarse_start(const gran_mixture *mix, std::vector<double> &u) {
  const int64_t M = mix->M;
  std::fill(u.begin(), u.end(), 0.0);
  if (mix->model != GRAN_RESTITUTION_CONSTANT || !mix->g2_mat.empty()) return;
  std::vector<double> key((size_t)M);
  double kmin = HUGE_VAL, kmax = -HUGE_VAL;
  for (int64_t k = 0; k < M; k++) {
    key[(size_t)k] = std::log(mix->m[(size_t)k]);
    kmin = std::min(kmin, key[(size_t)k]);
    kmax = std::max(kmax, key[(size_t)k]);
  }
  if (!(kmax - kmin > 1e-9)) return;
  const int nb = HCS_COARSE_BINS;
  std::vector<double> bn((size_t)nb, 0.0), blm((size_t)nb, 0.0), bls((size_t)nb, 0.0), bw((size_t)nb, 0.0);
  std::vector<int64_t> bin((size_t)M);
  for (int64_t k = 0; k < M; k++) {
    int b = (int)((key[(size_t)k] - kmin) / (kmax - kmin) * nb);
    b = std::min(std::max(b, 0), nb - 1);
    bin[(size_t)k] = b;
    const double w = mix->n[(size_t)k] > 0.0 ? mix->n[(size_t)k] : 1e-300;
    bn[(size_t)b] += mix->n[(size_t)k];
    bw[(size_t)b] += w;
    blm[(size_t)b] += w * key[(size_t)k];
    bls[(size_t)b] += w * std::log(mix->sigma[(size_t)k]);
  }
  std::vector<double> cm, cs, cn, ck;
  for (int b = 0; b < nb; b++) {
    if (bw[(size_t)b] == 0.0) continue;
    ck.push_back(blm[(size_t)b] / bw[(size_t)b]);
    cm.push_back(std::exp(ck.back()));
    cs.push_back(std::exp(bls[(size_t)b] / bw[(size_t)b]));
    cn.push_back(bn[(size_t)b]);
  }
  gran_mixture coarse;
  coarse.M = (int64_t)cm.size();
  coarse.m = cm;
  coarse.sigma = cs;
  coarse.n = cn;
  coarse.model = GRAN_RESTITUTION_CONSTANT;
  coarse.eps = mix->eps;
  coarse.visco = GRAN_VISCO_CONSTANT;
  coarse.beta = 0.0;
  coarse.matA = coarse.matY = coarse.matNu = coarse.rho_pref = 0.0;
  coarse.g2 = mix->g2;
  std::vector<double> uc((size_t)coarse.M, 0.0);
  int64_t rc = 0;
  if (solve_u(&coarse, uc, &rc, nullptr, RES_TOL, nullptr) != GRAN_SUCCESS) {
    gran_clear_error();
    return;
  }
  /* piecewise-linear interpolation in log m (ck is increasing) */
  const size_t nc = ck.size();
  for (int64_t k = 0; k < M; k++) {
    const double x = key[(size_t)k];
    if (x <= ck[0]) {
      u[(size_t)k] = uc[0];
    } else if (x >= ck[nc - 1]) {
      u[(size_t)k] = uc[nc - 1];
    } else {
      const size_t j = (size_t)(std::upper_bound(ck.begin(), ck.end(), x) - ck.begin());
      const double f = (x - ck[j - 1]) / (ck[j] - ck[j - 1]);
      u[(size_t)k] = (1.0 - f) * uc[j - 1] + f * uc[j];
    }
  }
}

/* u = log T up to a constant (u[ref] = 0), ref = densest species; cbar = number-weighted mean xi
 * at T = exp(u) (may be NULL). */
int solve_u(const gran_mixture *mix, std::vector<double> &u, int64_t *ref_out, double *cbar, double tol = RES_TOL,
            int *passes = nullptr) {
  const int64_t M = mix->M;
  Newton N;
  N.mix = mix;
  N.M = M;
  N.ref = 0;
  for (int64_t k = 1; k < M; k++)
    if (mix->n[(size_t)k] > mix->n[(size_t)N.ref]) N.ref = k;
  *ref_out = N.ref;
  N.dense = M <= HCS_DENSE_MAX;
  N.T.assign((size_t)M, 1.0);
  N.u = u;
  if (!N.dense) coarse_start(mix, N.u);
  const double shift = N.u[(size_t)N.ref];
  for (auto &v : N.u) v -= shift;
  if (N.dense) {
    GRAN_CALL(newton(N, std::max(tol, 1e-8), 200));
    if (passes) *passes += N.iters + 1;
    if (tol < 1e-8) {
      hcs_hybridsj(mix, N.ref, N.u);
      GRAN_CALL(newton(N, tol, 200)); /* final check (and refinement if GSL stopped early) */
      if (passes) *passes += N.iters + 1;
    }
  } else {
    GRAN_CALL(newton(N, tol, 100));
    if (passes) *passes += N.iters + 1;
  }
  u = N.u;
  if (cbar) {
    double num = 0.0, den = 0.0;
    for (int64_t k = 0; k < M; k++) {
      num += mix->n[(size_t)k] * N.P.xi[(size_t)k];
      den += mix->n[(size_t)k];
    }
    *cbar = num / den;
  }
  return GRAN_SUCCESS;
}

} // namespace

/* The HCS of rates scale_k xi_k(T) (scale frozen) from the start u (log T, any constant), by the
 * clamped Newton above (dense or low rank by M); u[ref] = 0 on return, ref the densest species. */
int gran::hcs_solve_scaled(const gran_mixture *mix, const double *scale, std::vector<double> &u, int64_t *ref_out,
                           double tol, int max_steps, int *passes) {
  return hcs_solve_scaled(mix, scale, nullptr, u, ref_out, tol, max_steps, passes);
}

int gran::hcs_solve_scaled(const gran_mixture *mix, const double *scale, const HcsPass *first, std::vector<double> &u,
                           int64_t *ref_out, double tol, int max_steps, int *passes) {
  const int64_t M = mix->M;
  Newton N;
  N.mix = mix;
  N.M = M;
  N.ref = 0;
  for (int64_t k = 1; k < M; k++)
    if (mix->n[(size_t)k] > mix->n[(size_t)N.ref]) N.ref = k;
  *ref_out = N.ref;
  N.dense = M <= HCS_DENSE_MAX;
  N.T.assign((size_t)M, 1.0);
  N.u = u;
  N.scale = scale;
  N.first = first;
  N.max_steps = max_steps;
  const double shift = N.u[(size_t)N.ref];
  for (auto &v : N.u) v -= shift;
  const int st = newton(N, tol, 100);
  if (passes) *passes += N.iters + (first ? 0 : 1);
  if (st) return st;
  u = N.u;
  return GRAN_SUCCESS;
}

namespace {

bool all_elastic(const gran_mixture *mix) {
  if (mix->model == GRAN_RESTITUTION_CONSTANT) return mix->eps == 1.0;
  for (double e : mix->eps_mat)
    if (e != 1.0) return false;
  return true;
}

} // namespace

int gran::hcs_solve_start(const gran_mixture *mix, std::vector<double> &u, double tol, int *passes) {
  int64_t ref = 0;
  u.assign((size_t)mix->M, 0.0);
  if (mix->M == 1 || all_elastic(mix)) return GRAN_SUCCESS;
  return solve_u(mix, u, &ref, nullptr, tol, passes);
}


/**
 * @brief Homogeneous cooling state: temperatures with equal cooling rates (Eq. 21).
 * @param[in] norm GRAN_HCS_NORM_MEAN (number-weighted mean over species with n_k > 0 equals value,
 *            Eq. 25) or GRAN_HCS_NORM_T1 (T of species 1 equals value)
 * @param[in] value > 0
 * @param[out] T0 M temperatures
 * @param[out] tau0 2/xi (Eq. 21); +inf when every pair is elastic (then T0 is equipartition). May be NULL.
 * Constant or matrix restitution only (the viscoelastic model has no state with constant ratios).
 */
namespace gran {
/* log of the scale lam of an HCS T_k = lam exp(u_k) under the normalisation norm = value (T_1, or
 * the number-weighted mean temperature); shared by the Maxwellian and the Sonine HCS */
double hcs_log_scale(const gran_mixture *mix, const std::vector<double> &u, int norm, double value) {
  const int64_t M = mix->M;
  const double umax = *std::max_element(u.begin(), u.end());
  if (norm == GRAN_HCS_NORM_T1) return std::log(value) - u[0];
  double num = 0.0, den = 0.0;
  for (int64_t k = 0; k < M; k++) {
    num += mix->n[(size_t)k] * std::exp(u[(size_t)k] - umax);
    den += mix->n[(size_t)k];
  }
  return std::log(value * den / num) - umax;
}
int check_hcs_target(int norm, double value, const double *T0) {
  GRAN_CHECK(norm == GRAN_HCS_NORM_MEAN || norm == GRAN_HCS_NORM_T1, GRAN_ERR_ARG,
             "argument 'norm' = %d is not a gran_hcs_norm", norm);
  GRAN_CHECK(std::isfinite(value) && value > 0.0, GRAN_ERR_ARG, "argument 'value' = %g must be finite and > 0",
             value);
  GRAN_CHECK_PTR(T0);
  return GRAN_SUCCESS;
}
}  // namespace gran

GRAN_EXTERN int gran_theory_hcs(const gran_mixture *mix, int norm, double value, double *T0, double *tau0) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_hcs_target(norm, value, T0));
    GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
               "mixture 'mix' has viscoelastic restitution: its temperature ratios keep changing, there is no "
               "homogeneous cooling state with constant ratios (use gran_theory_temperatures)");
    const int64_t M = mix->M;
    std::vector<double> u((size_t)M, 0.0);
    const bool elastic = all_elastic(mix);
    double cbar = NAN; /* mean cooling rate at T = exp(u) */
    if (!elastic && M > 1) {
      int64_t ref = 0;
      GRAN_CALL(solve_u(mix, u, &ref, &cbar));
    }
    /* normalise: T_k = lam exp(u_k) */
    const double loglam = hcs_log_scale(mix, u, norm, value); /* T_k = exp(loglam + u_k) */
    for (int64_t k = 0; k < M; k++) T0[k] = std::exp(loglam + u[(size_t)k]);
    for (int64_t k = 0; k < M; k++)
      GRAN_CHECK(std::isfinite(T0[k]) && T0[k] > 0.0, GRAN_ERR_NUMERIC,
                 "HCS temperature of species %" PRId64 " is not finite and positive (%g)", k, T0[k]);
    if (tau0) {
      if (elastic) {
        *tau0 = HUGE_VAL;
      } else if (M > 1) {
        *tau0 = 2.0 / (cbar * std::exp(0.5 * loglam));
        GRAN_CHECK(std::isfinite(*tau0) && *tau0 > 0.0, GRAN_ERR_NUMERIC, "HCS: tau0 = %g is not finite and positive",
                   *tau0);
      } else {
        std::vector<double> xi((size_t)M);
        GRAN_CALL(cooling_rates(mix, T0, xi.data()));
        double num = 0.0, den = 0.0;
        for (int64_t k = 0; k < M; k++) {
          num += mix->n[(size_t)k] * xi[(size_t)k];
          den += mix->n[(size_t)k];
        }
        *tau0 = 2.0 * den / num;
        GRAN_CHECK(std::isfinite(*tau0) && *tau0 > 0.0, GRAN_ERR_NUMERIC, "HCS: tau0 = %g is not finite and positive",
                   *tau0);
      }
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
