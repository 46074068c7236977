/* theory_impl.h - private declarations of the theory module (src/theory): the mixture struct,
 * inline pair accessors (usable from hot loops of the DSMC engines), and the kernels shared by
 * the theory files. Never installed. */
#ifndef GRANARY_THEORY_IMPL_H
#define GRANARY_THEORY_IMPL_H

#include "granary_impl.h"

#include <gsl/gsl_vector.h>

#include <complex>
#include <vector>

#include <gsl/gsl_odeiv2.h>

/* Viscoelastic source of beta_ij (GRAN_RESTITUTION_VISCOELASTIC). */
enum gran_visco_kind { GRAN_VISCO_CONSTANT = 0, GRAN_VISCO_MATRIX = 1, GRAN_VISCO_MATERIAL = 2 };

/* Pair matrices are allocated only when a matrix is given (M = 1e5 would need 80 GB). */
struct gran_mixture {
  int64_t M;                    /* number of species >= 1 */
  std::vector<double> m;        /* masses m_k > 0 */
  std::vector<double> sigma;    /* diameters sigma_k > 0 */
  std::vector<double> n;        /* number densities n_k >= 0 (0: tracer) */
  int model;                    /* gran_restitution_model */
  double eps;                   /* constant restitution coefficient (model CONSTANT) */
  std::vector<double> eps_mat;  /* M*M (model MATRIX), else empty */
  int visco;                    /* gran_visco_kind (model VISCOELASTIC) */
  double beta;                  /* constant beta (VISCO_CONSTANT) */
  std::vector<double> beta_mat; /* M*M (VISCO_MATRIX), else empty */
  double matA, matY, matNu;     /* material (VISCO_MATERIAL) */
  double rho_pref;              /* 2 Y / (3 (1 - nu^2)) (VISCO_MATERIAL) */
  double g2;                    /* constant contact value */
  std::vector<double> g2_mat;   /* M*M when given, else empty */
};

namespace gran {

/* Prefactor of the cooling rates and velocity correlation times, Eqs. 11 and 15: (8/3) sqrt(2 pi). */
constexpr double C15 = 8.0 / 3.0 * 2.5066282746310002;


/* sigma_ki = (sigma_k + sigma_i)/2 */
static inline double mix_sigma_pair(const gran_mixture *x, int64_t k, int64_t i) {
  return 0.5 * (x->sigma[(size_t)k] + x->sigma[(size_t)i]);
}
static inline double mix_g2(const gran_mixture *x, int64_t k, int64_t i) {
  return x->g2_mat.empty() ? x->g2 : x->g2_mat[(size_t)(k * x->M + i)];
}
/* Restitution of pair (k, i) for the constant and matrix models (1 for viscoelastic). */
static inline double mix_eps(const gran_mixture *x, int64_t k, int64_t i) {
  if (x->model == GRAN_RESTITUTION_CONSTANT) return x->eps;
  if (x->model == GRAN_RESTITUTION_MATRIX) return x->eps_mat[(size_t)(k * x->M + i)];
  return 1.0;
}
/* Viscoelastic beta_ki = (3/2) A (rho/m_eff)^(2/5), rho = 2 Y sqrt(R_eff)/(3(1-nu^2)),
 * R_eff = R_k R_i/(R_k + R_i) with R = sigma/2, i.e. R_eff = sigma_k sigma_i/(2(sigma_k+sigma_i)),
 * m_eff = m_k m_i/(m_k + m_i). 0 for the non-viscoelastic models. */
static inline double mix_beta(const gran_mixture *x, int64_t k, int64_t i) {
  if (x->model != GRAN_RESTITUTION_VISCOELASTIC) return 0.0;
  if (x->visco == GRAN_VISCO_CONSTANT) return x->beta;
  if (x->visco == GRAN_VISCO_MATRIX) return x->beta_mat[(size_t)(k * x->M + i)];
  const double sk = x->sigma[(size_t)k], si = x->sigma[(size_t)i];
  const double mk = x->m[(size_t)k], mi = x->m[(size_t)i];
  const double reff = sk * si / (2.0 * (sk + si));
  const double meff = mk * mi / (mk + mi);
  const double rho = x->rho_pref * std::sqrt(reff);
  return 1.5 * x->matA * std::pow(rho / meff, 0.4);
}

/* ---- argument checks shared by the theory entry points (return a status; 0 = fine) --------- */
int check_mixture(const gran_mixture *mix, const char *name);
/* n values finite and (positive when positive != 0, else >= 0). */
int check_array(const double *a, int64_t n, const char *name, int positive);
/* Times: finite, >= 0. */
int check_times(const double *t, int64_t n, const char *name);
/* ntimes >= 0; with ntimes > 0 the times t (check_times) and the output array out (not NULL,
 * named out_name in the message) */
int check_output_times(int64_t ntimes, const double *t, const void *out, const char *out_name);
int check_rtol(double rtol, const char *name);

/* ---- viscoelastic averages ------------------------------------------------------------------
 * For a pair with z = sqrt(beta) (2 v^2)^(1/20), v^2 = T_k/m_k + T_i/m_i, the collision-weighted
 * averages over the Maxwellian normal relative speed (weight s e^-s ds, x = z s^(1/20)):
 *   q1 = <(1 + eps)/2> - 1 = sum_n h_n B_n,   q2 = <((1 + eps)/2)^2> - 1 = (1/2) sum_n A_n B_n
 * with B_n = (1/2) z^n Gamma(2 + n/20) (Bodrova & Osinsky App. A). Series for z <= 0.35 (exact for the
 * polynomial branch of eps), GSL quadrature of the real eps(x) beyond. */
int visco_averages(double z, double *q1, double *q2);
double visco_eps(double x); /* no argument checks; x >= 0 finite */
/* First Sonine moments D[j][k] = <p^j - 1>_k (p = (1 + eps)/2, j = 1..4, k = 3, 5, 7, 9; others 0) over
 * u = g_n^2/(2 s^2) with weight u^((k-1)/2) e^-u/Gamma((k+1)/2), x = z u^(1/20) (docs/physics-sonine.md
 * Sec. 6). D[1][3] = q1 and D[2][3] = q2 of visco_averages. Series for z <= 0.35, a composite
 * Gauss-Legendre rule beyond; _ref: GSL adaptive quadrature (the check of both). */
int visco_sonine_moments(double z, double D[5][10]);
int visco_sonine_moments_ref(double z, double D[5][10]);

/* ---- kinetic kernels (cooling.cpp) -----------------------------------------------------------
 * xi_k (Eq. 15 / A7) for every k at temperatures T (any of xi, dxi_dlogT_self, may be NULL).
 * Returns a status (viscoelastic quadrature may fail). */
int cooling_rates(const gran_mixture *mix, const double *T, double *xi);
/* One pass over the pairs (constant/matrix restitution): xi_k, d_k = sum_i d xi_ki/d log T_k (row
 * part of the Jacobian), l_k = d xi_kk/d log T_k through the partner's temperature (diagonal of
 * the column part) and the collision frequency nu_k. Constant eps and g2: each unordered pair once,
 * vectorised. All outputs required (length M). */
void cooling_pass(const gran_mixture *mix, const double *T, double *xi, double *d, double *l, double *nu);
/* xi_k and J_kj = d xi_k / d log T_j (row-major M*M); constant/matrix restitution only. */
void cooling_jacobian(const gran_mixture *mix, const double *T, double *xi, double *J);
/* 1/tau_v,k (Eq. 11 / A6). */
int inv_tau_v(const gran_mixture *mix, const double *T, double *inv_tv);
/* 1/tau_v,k of one species k, O(M). */
int inv_tau_v_one(const gran_mixture *mix, const double *T, int64_t k, double *inv_tv);

/* g(y) = y - 1 + exp(-y) >= 0 without cancellation (series below y = 1); g(inf) = inf.
 * Eq. 22 is MSD_k = 6 D_k tau_v,k g(beta_k log(1 + t/tau0)). */
static inline double g_fun(double y) {
  if (!(y < 1.0)) return y + std::expm1(-y);
  double term = 0.5 * y * y, sum = 0.0;
  for (int n = 2; n < 40 && std::fabs(term) > 1e-17 * sum; n++) {
    sum += term;
    term *= -y / (n + 1);
  }
  return sum;
}
/* Collision frequency scale nu_k = sum_i n_i sigma_ki^2 g2 sqrt(T_k/m_k + T_i/m_i) m_i/(m_i+m_k)
 * (used to scale residuals). */
void collision_scale(const gran_mixture *mix, const double *T, double *nu);

/* ---- HCS solves (hcs.cpp) ---------------------------------------------------------------------
 * HCS of the rates scale_k xi_k(T) with frozen factors scale_k > 0 (NULL: 1), from the start u =
 * log T (any constant); on return u[ref] = 0, ref = the densest species. Constant/matrix
 * restitution. max_steps >= 0: return after at most that many Newton steps (no final check;
 * -1: until the residual is <= tol). passes (may be NULL) is incremented by the number of O(M^2)
 * pair passes used. */
int hcs_solve_scaled(const gran_mixture *mix, const double *scale, std::vector<double> &u, int64_t *ref_out,
                     double tol, int max_steps, int *passes);
/* The same with the first pass given: the unscaled outputs of cooling_pass (xi, d, l, nu, length M)
 * at T = exp(u - u[ref]), e.g. accumulated by another pass over the pairs at that T. */
struct HcsPass {
  const double *xi, *d, *l, *nu;
};
int hcs_solve_scaled(const gran_mixture *mix, const double *scale, const HcsPass *first, std::vector<double> &u,
                     int64_t *ref_out, double tol, int max_steps, int *passes);
/* Maxwellian HCS u = log T (u[ref] = 0, ref the densest species) to the residual tol (a start for
 * another solve; gran_theory_hcs solves to 1e-13); passes as above (may be NULL). */
int hcs_solve_start(const gran_mixture *mix, std::vector<double> &u, double tol, int *passes);

/* ---- two-moment velocity correlation (sonine_diffusion.cpp) -----------------------------------
 * Species k at temperatures T with cooling rate zeta_k (NaN: the Maxwellian xi_k at T) and the Sonine
 * coefficients a2 of all species (NULL: 0; the partners' a2_i and the weight f_k in the collision
 * matrix, a2_k also in the initial moments): <v(t0).v(t0 + tau)> = (3 T_k/m_k) Re(c_0 e^(-lam_0 tau) + c_1 e^(-lam_1 tau)),
 * c_0 + c_1 = 1; both rates real and positive, or a complex-conjugate pair with Re > 0. */
typedef std::complex<double> cd;
int sonine_modes(const gran_mixture *mix, const double *T, int64_t k, double zeta_k, const double *a2, cd lam[2],
                 cd c[2]);
/* g_fun for complex y */
cd g_cplx(cd y);

/* ---- Eq. 4 at the first Sonine level (sonine.cpp) ---------------------------------------------
 * zeta_k of the first Sonine approximation at (T, a2) for one species k, O(M) (the z0 + z1 of the
 * pair pass). */
double sonine_zeta_one(const gran_mixture *mix, const double *T, const double *a2, int64_t k);
struct Traj;
/* Dense output of the first Sonine trajectory from (T0, a20 or NULL: 0) up to s_end, steps <= hmax
 * (GSL rk8pd, local tolerance rtol): out.dim = 3M, components z_k = log(T_k/T0_k) + 2 s, u_k (as
 * Traj with_u) and a2_k; s = log(1 + t/ts), out.ts = ts. GRAN_ERR_DOMAIN when some |a2_k| reaches 1. */
int sonine_traj_dense(Traj &out, const gran_mixture *mix, const double *T0, const double *a20, double ts, double rtol,
                      double hmax, double s_end);
/* The dense output of a Sonine trajectory (sonine.cpp): sys from s = 0 (y the start, overwritten) to s_end,
 * steps <= hmax, GSL rk8pd with the error control scaled by `scale` (tolerance rtol), every accepted step stored
 * in out.s, out.Y, out.F; after each step check(y, M, t) returns GRAN_SUCCESS or the error of a closure that
 * breaks down; `what` names the trajectory in the other errors; at most maxsteps steps. */
int sonine_dense_evolve(Traj &out, gsl_odeiv2_system sys, std::vector<double> &y, std::vector<double> &scale, double ts,
                        double rtol, double hmax, double s_end, const char *what, unsigned long maxsteps,
                        int (*check)(const double *y, int64_t M, double t));
/* The second Sonine level (sonine2.cpp): zeta_k at (T, a2, a3) for one species, O(M); the dense trajectory from
 * (T0, a20, a30; NULL: 0) with out.dim = 4M, the components of the first level's and a3_k after them.
 * GRAN_ERR_DOMAIN when some |a2_k| or |a3_k| reaches 1. */
double sonine2_zeta_one(const gran_mixture *mix, const double *T, const double *a2, const double *a3, int64_t k);
/* GRAN_ERR_ARG naming argument `name`[k] unless c is not NULL and every |c[k]| < 1 (finite) */
int sonine2_check_coeffs(const double *c, int64_t M, const char *name);
int sonine2_traj_dense(Traj &out, const gran_mixture *mix, const double *T0, const double *a20, const double *a30,
                       double ts, double rtol, double hmax, double s_end);

/* ---- HCS states (msd.cpp) ---------------------------------------------------------------------
 * Checks that (T0, tau0) is a homogeneous cooling state (|xi_k tau0/2 - 1| <= 1e-3; tau0 = inf:
 * elastic at equipartition) and returns D_k(0) (may be NULL) and tau_v,k(0). */
int hcs_state(const gran_mixture *mix, const double *T0, double tau0, double *D, double *tau_v);
int check_hcs_args(const gran_mixture *mix, const double *T0, double tau0);
/* check_hcs_args, then t_meas > 0, nlag >= 0, rtol, and lags (check_times) <= t_meas (tamsd.cpp) */
int check_tamsd_args(const gran_mixture *mix, const double *T0, double tau0, double t_meas, int64_t nlag,
                     const double *lag, double rtol);

/* ---- temperature trajectories (ode.cpp) -----------------------------------------------------
 * Eq. 13 integrated with GSL odeiv2 (msbdf with the analytic Jacobian; stiff: relaxation of the
 * ratios is up to ~1/(1-eps) faster than the cooling) in the log-time s = log(1 + t/ts), with
 * state z_k = log(T_k/T0_k) + 2 s and, when with_u, u_k = int_0^t sqrt(T_k/T0_k) dt' (Eq. 6 times
 * tau_c(0)). T decays as t^-2 over 30 decades while dy/ds stays O(1). ts is the shortest
 * collision time at T0. */
struct Traj {
  const gran_mixture *mix = nullptr;
  int64_t M = 0;
  int dim = 0;     /* M or 2M */
  bool with_u = false;
  double ts = 1.0; /* time scale of s */
  std::vector<double> T0;
  std::vector<double> uscale; /* absolute scale of u_k in the error control: tau_v,k(T0) */
  /* dense output (when requested): nodes s_j, states Y (nodes*dim), derivatives F = dY/ds */
  std::vector<double> s, Y, F;
  /* workspace */
  std::vector<double> T, xi, J, Jfd;
  int status = 0; /* granary status of a failure inside a GSL callback */
  int64_t nrhs = 0, njac = 0;
};

double traj_s_of_t(const Traj &tr, double t);
double traj_t_of_s(const Traj &tr, double s);
int traj_init(Traj &tr, const gran_mixture *mix, const double *T0, bool with_u);
/* Integrate from s = 0 to each of the nout sorted s_out (Y_out nout*dim exact at those points,
 * may be NULL); when dense, store every step up to s_end with steps <= hmax. */
int traj_run(Traj &tr, int64_t nout, const double *s_out, double *Y_out, double rtol, bool dense, double hmax,
             double s_end);
/* Cubic Hermite interpolation of component c at s (dense output); traj_locate finds the node
 * interval of s once for several components (traj_eval_at). */
double traj_eval(const Traj &tr, double s, int c);
size_t traj_locate(const Traj &tr, double s);
double traj_eval_at(const Traj &tr, size_t j, double s, int c);
/* All M temperatures at s (dense output). */
void traj_temperatures(const Traj &tr, double s, double *T);

} // namespace gran

namespace gran {
/* hcs.cpp: the arguments every HCS entry point takes (GRAN_ERR_ARG naming them): norm a gran_hcs_norm,
 * value finite and > 0, T0 not NULL */
int check_hcs_target(int norm, double value, const double *T0);
double hcs_log_scale(const gran_mixture *mix, const std::vector<double> &u, int norm, double value);
/* newton.cpp: f(x) = 0 by Newton's method from x (in place), for the higher Sonine HCS systems: the
 * Jacobian by differences, central of step 1e-5 in the first nlog columns (log T), one-sided of step
 * 1e-3 in the others (exact where the residuals are linear, the Sonine coefficients), LU (GSL); the
 * step halved while it does not lower the largest residual; at most 60 iterations, done below 1e-15
 * or at the rounding level. fn returns GSL_SUCCESS or an error (GRAN_ERR_NUMERIC then). *res_out:
 * the largest residual. Errors name `what`. */
int sonine_newton(gsl_vector *x, size_t nlog, int (*fn)(const gsl_vector *, void *, gsl_vector *), void *ctx,
                  const char *what, double *res_out);
}
#endif
