/* ode.cpp - partial temperatures T_k(t) from any start (Bodrova & Osinsky Eq. 13) with GSL odeiv2.
 *
 * Variables: s = log(1 + t/ts), z_k = log(T_k/T0_k) + 2 s: dz_k/ds = 2 - xi_k(T) ts e^s. Haff's law
 * gives T ~ t^-2, so z tends to a constant for t >> tau0: the state stays O(1) and the step size in
 * s stays O(1) from t = 0 to t = 1e15 tau0 and beyond. Optional u_k = int_0^t sqrt(T_k/T0_k) dt' (du_k/ds =
 * ts e^s e^(y_k/2)) for the reduced times of Eq. 6.
 *
 * Stepper: msbdf (variable-order BDF) with the analytic Jacobian (constant/matrix restitution)
 * or a finite-difference Jacobian (viscoelastic). The problem is stiff: the temperature ratios relax
 * on the collision time, which is up to (1 - eps^2)^-1 shorter than the cooling time. Above
 * ODE_IMPLICIT_MAX species the M*M Jacobian is not affordable and rk8pd (explicit) is used. */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <numeric>

namespace {

using namespace gran;

const int64_t ODE_IMPLICIT_MAX = 2048;

/* state z_k = log(T_k/T0_k) + 2 s (bounded: Haff's law gives z -> 2 log(tau0/ts)), u_k */
int rhs(double s, const double y[], double f[], void *params) {
  Traj *tr = static_cast<Traj *>(params);
  const int64_t M = tr->M;
  for (int64_t k = 0; k < M; k++) {
    if (!std::isfinite(y[k])) return GSL_EBADFUNC;
    tr->T[(size_t)k] = tr->T0[(size_t)k] * std::exp(y[k] - 2.0 * s);
  }
  const double g = tr->ts * std::exp(s);
  int st = cooling_rates(tr->mix, tr->T.data(), tr->xi.data());
  if (st) {
    tr->status = st;
    return GSL_EBADFUNC;
  }
  tr->nrhs++;
  for (int64_t k = 0; k < M; k++) f[k] = 2.0 - g * tr->xi[(size_t)k];
  if (tr->with_u)
    for (int64_t k = 0; k < M; k++) f[M + k] = g * std::exp(0.5 * (y[k] - 2.0 * s));
  return GSL_SUCCESS;
}

int jac(double s, const double y[], double *dfdy, double dfdt[], void *params) {
  Traj *tr = static_cast<Traj *>(params);
  const int64_t M = tr->M;
  const int dim = tr->dim;
  const double g = tr->ts * std::exp(s);
  for (int64_t k = 0; k < M; k++) tr->T[(size_t)k] = tr->T0[(size_t)k] * std::exp(y[k] - 2.0 * s);
  tr->njac++;
  if (tr->mix->model != GRAN_RESTITUTION_VISCOELASTIC) {
    cooling_jacobian(tr->mix, tr->T.data(), tr->xi.data(), tr->J.data());
  } else {
    /* forward differences in log T, step 1e-7 */
    int st = cooling_rates(tr->mix, tr->T.data(), tr->xi.data());
    if (st) {
      tr->status = st;
      return GSL_EBADFUNC;
    }
    std::vector<double> Tp(tr->T), xp((size_t)M);
    const double h = 1e-7;
    for (int64_t j = 0; j < M; j++) {
      Tp[(size_t)j] = tr->T[(size_t)j] * std::exp(h);
      st = cooling_rates(tr->mix, Tp.data(), xp.data());
      if (st) {
        tr->status = st;
        return GSL_EBADFUNC;
      }
      for (int64_t k = 0; k < M; k++) tr->J[(size_t)(k * M + j)] = (xp[(size_t)k] - tr->xi[(size_t)k]) / h;
      Tp[(size_t)j] = tr->T[(size_t)j];
    }
  }
  std::fill(dfdy, dfdy + (size_t)dim * (size_t)dim, 0.0);
  for (int64_t k = 0; k < M; k++) {
    double rowsum = 0.0;
    for (int64_t j = 0; j < M; j++) {
      const double Jkj = tr->J[(size_t)(k * M + j)];
      dfdy[(size_t)k * dim + (size_t)j] = -g * Jkj;
      rowsum += Jkj;
    }
    /* d/ds at fixed z: g' = g and d log T/ds = -2 */
    dfdt[k] = -g * tr->xi[(size_t)k] + 2.0 * g * rowsum;
  }
  if (tr->with_u)
    for (int64_t k = 0; k < M; k++) {
      const double e = g * std::exp(0.5 * (y[k] - 2.0 * s));
      dfdy[(size_t)(M + k) * dim + (size_t)k] = 0.5 * e;
      dfdt[M + k] = 0.0; /* g e^(-s) is constant in s */
    }
  return GSL_SUCCESS;
}

/* ---- step control with per-component tolerances: D_i = abs_i + rel_i |y_i| (GSL's standard
 * heuristics otherwise). GSL's scaled control shares one relative tolerance across components;
 * here z needs a pure absolute one (log T) and u a pure relative one. */
struct Ctl {
  std::vector<double> abs, rel;
};
void *ctl_alloc() { return new (std::nothrow) Ctl(); }
int ctl_init(void *, double, double, double, double) { return GSL_SUCCESS; }
int ctl_hadjust(void *state, size_t dim, unsigned int ord, const double y[], const double yerr[], const double *,
                double *h) {
  const Ctl *c = static_cast<const Ctl *>(state);
  const double S = 0.9, h_old = *h;
  double rmax = 2.2250738585072014e-308;
  for (size_t i = 0; i < dim; i++) {
    const double D0 = c->abs[i] + c->rel[i] * std::fabs(y[i]);
    rmax = std::max(rmax, std::fabs(yerr[i]) / D0);
  }
  if (rmax > 1.1) {
    *h = std::max(0.2, S / std::pow(rmax, 1.0 / ord)) * h_old;
    return GSL_ODEIV_HADJ_DEC;
  }
  if (rmax < 0.5) {
    *h = std::min(5.0, std::max(1.0, S / std::pow(rmax, 1.0 / (ord + 1.0)))) * h_old;
    return GSL_ODEIV_HADJ_INC;
  }
  return GSL_ODEIV_HADJ_NIL;
}
int ctl_errlevel(void *state, const double y, const double, const double, const size_t ind, double *errlev) {
  const Ctl *c = static_cast<const Ctl *>(state);
  *errlev = c->abs[ind] + c->rel[ind] * std::fabs(y);
  return *errlev > 0.0 ? GSL_SUCCESS : GSL_EINVAL;
}
int ctl_set_driver(void *, const gsl_odeiv2_driver *) { return GSL_SUCCESS; }
void ctl_free(void *state) { delete static_cast<Ctl *>(state); }
const gsl_odeiv2_control_type ctl_type = {"granary-per-component", ctl_alloc,      ctl_init, ctl_hadjust,
                                          ctl_errlevel,            ctl_set_driver, ctl_free};

int map_gsl(int st, const Traj &tr, double s) {
  if (tr.status) return tr.status;
  if (st == GSL_EBADFUNC)
    return GRAN_ERROR(GRAN_ERR_NUMERIC, "temperature ODE: non-finite state at t = %g", traj_t_of_s(tr, s));
  return GRAN_ERROR(GRAN_ERR_NOCONV, "temperature ODE failed at t = %g: GSL: %s", traj_t_of_s(tr, s),
                    gsl_strerror(st));
}

} // namespace

namespace gran {

double traj_s_of_t(const Traj &tr, double t) { return std::log1p(t / tr.ts); }
double traj_t_of_s(const Traj &tr, double s) { return tr.ts * std::expm1(s); }

int traj_init(Traj &tr, const gran_mixture *mix, const double *T0, bool with_u) {
  tr.mix = mix;
  tr.M = mix->M;
  tr.with_u = with_u;
  tr.dim = (int)(with_u ? 2 * mix->M : mix->M);
  tr.T0.assign(T0, T0 + mix->M);
  tr.T.assign((size_t)mix->M, 0.0);
  tr.xi.assign((size_t)mix->M, 0.0);
  const bool implicit = mix->M <= ODE_IMPLICIT_MAX;
  if (implicit) tr.J.assign((size_t)(mix->M * mix->M), 0.0);
  std::vector<double> nu((size_t)mix->M);
  collision_scale(mix, T0, nu.data());
  const double numax = *std::max_element(nu.begin(), nu.end());
  if (!(numax > 0.0) || !std::isfinite(numax))
    return GRAN_ERROR(GRAN_ERR_NUMERIC, "collision frequencies at T0 are not finite and positive");
  tr.ts = 1.0 / numax;
  if (with_u) {
    tr.uscale.assign((size_t)mix->M, 0.0);
    GRAN_CALL(inv_tau_v(mix, T0, tr.uscale.data()));
    for (auto &v : tr.uscale) v = 1.0 / v;
  }
  return GRAN_SUCCESS;
}

int traj_run(Traj &tr, int64_t nout, const double *s_out, double *Y_out, double rtol, bool dense, double hmax,
             double s_end) {
  const int dim = tr.dim;
  const bool implicit = !tr.J.empty();
  gsl_odeiv2_system sys{rhs, jac, (size_t)dim, &tr};
  /* error per step <= rtol on z (absolute in log T: relative error of T_k) and <= rtol |u_k| on u
   * (relative: u(t) - u(t1) at t -> 0 needs it; the floor 1e-30 tau_v avoids a zero tolerance at s = 0) */
  gsl_odeiv2_driver *d = gsl_odeiv2_driver_alloc_y_new(&sys, implicit ? gsl_odeiv2_step_msbdf : gsl_odeiv2_step_rk8pd,
                                                       1e-6, rtol, 0.0);
  if (!d) return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate the GSL ODE driver (dim %d)", dim);
  gsl_odeiv2_control *ctl = gsl_odeiv2_control_alloc(&ctl_type);
  if (!ctl) {
    gsl_odeiv2_driver_free(d);
    return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate the ODE step control");
  }
  {
    Ctl *c = static_cast<Ctl *>(ctl->state);
    c->abs.assign((size_t)dim, rtol);
    c->rel.assign((size_t)dim, 0.0);
    if (tr.with_u)
      for (int64_t k = 0; k < tr.M; k++) {
        c->abs[(size_t)(tr.M + k)] = 1e-30 * tr.uscale[(size_t)k];
        c->rel[(size_t)(tr.M + k)] = rtol;
      }
  }
  gsl_odeiv2_control_free(d->c);
  d->c = ctl;
  gsl_odeiv2_control_set_driver(d->c, d);
  std::vector<double> y((size_t)dim, 0.0), f((size_t)dim);
  double s = 0.0, h = std::min(1e-6, hmax);
  int64_t iout = 0;
  int ret = GRAN_SUCCESS;
  double s_stop = 0.0;
  if (nout > 0) s_stop = s_out[nout - 1];
  if (dense) s_stop = std::max(s_stop, s_end);
  auto store = [&]() -> int {
    if (!dense) return GSL_SUCCESS;
    int st = rhs(s, y.data(), f.data(), &tr);
    if (st != GSL_SUCCESS) return st;
    tr.s.push_back(s);
    tr.Y.insert(tr.Y.end(), y.begin(), y.end());
    tr.F.insert(tr.F.end(), f.begin(), f.end());
    return GSL_SUCCESS;
  };
  if (dense) {
    tr.s.clear();
    tr.Y.clear();
    tr.F.clear();
    int st = store();
    if (st != GSL_SUCCESS) ret = map_gsl(st, tr, s);
  }
  while (ret == GRAN_SUCCESS) {
    while (iout < nout && s_out[iout] <= s) {
      if (Y_out) std::copy(y.begin(), y.end(), Y_out + iout * dim);
      iout++;
    }
    if (s >= s_stop) break;
    double target = s_stop;
    if (iout < nout) target = std::min(target, s_out[iout]);
    if (dense) target = std::min(target, s + hmax);
    h = std::min(h, hmax);
    int st = gsl_odeiv2_evolve_apply(d->e, d->c, d->s, d->sys, &s, target, &h, y.data());
    if (st != GSL_SUCCESS) {
      ret = map_gsl(st, tr, s);
      break;
    }
    if (!(h > 0.0) || !std::isfinite(h)) {
      ret = GRAN_ERROR(GRAN_ERR_NOCONV, "temperature ODE: step size collapsed at t = %g", traj_t_of_s(tr, s));
      break;
    }
    st = store();
    if (st != GSL_SUCCESS) {
      ret = map_gsl(st, tr, s);
      break;
    }
    if (d->e->count > 50000000UL) {
      ret = GRAN_ERROR(GRAN_ERR_NOCONV, "temperature ODE: more than 5e7 steps (t = %g)", traj_t_of_s(tr, s));
      break;
    }
  }
  gsl_odeiv2_driver_free(d);
  return ret;
}

size_t traj_locate(const Traj &tr, double s) {
  const size_t n = tr.s.size();
  if (n < 2 || s <= tr.s[0]) return 0;
  if (s >= tr.s[n - 1]) return n - 2;
  return (size_t)(std::upper_bound(tr.s.begin(), tr.s.end(), s) - tr.s.begin()) - 1;
}

double traj_eval(const Traj &tr, double s, int c) { return traj_eval_at(tr, traj_locate(tr, s), s, c); }

double traj_eval_at(const Traj &tr, size_t j, double s, int c) {
  const size_t n = tr.s.size();
  const int dim = tr.dim;
  if (n == 1 || s <= tr.s[0]) return tr.Y[(size_t)c];
  if (s >= tr.s[n - 1]) return tr.Y[(n - 1) * (size_t)dim + (size_t)c];
  const double s0 = tr.s[j], h = tr.s[j + 1] - s0, x = (s - s0) / h;
  const double y0 = tr.Y[j * dim + c], y1 = tr.Y[(j + 1) * dim + c];
  const double f0 = tr.F[j * dim + c] * h, f1 = tr.F[(j + 1) * dim + c] * h;
  const double x2 = x * x, x3 = x2 * x;
  return (2 * x3 - 3 * x2 + 1) * y0 + (x3 - 2 * x2 + x) * f0 + (-2 * x3 + 3 * x2) * y1 + (x3 - x2) * f1;
}

void traj_temperatures(const Traj &tr, double s, double *T) {
  const size_t j = traj_locate(tr, s);
  for (int64_t k = 0; k < tr.M; k++) T[k] = tr.T0[(size_t)k] * std::exp(traj_eval_at(tr, j, s, (int)k) - 2.0 * s);
}

} // namespace gran

using namespace gran;

/**
 * @brief T_k(t) from T0 by Eq. 13 (GSL odeiv2, msbdf, log-time variable).
 * @param[in] T0 M initial temperatures > 0 (any start: equipartition, HCS, ...)
 * @param[in] ntimes >= 0 output times t >= 0 (any order)
 * @param[in] rtol local relative error per step of T (absolute in log T), in [1e-14, 0.1]
 * @param[out] T ntimes*M temperatures, row-major [time][species]
 */
GRAN_EXTERN int gran_theory_temperatures(const gran_mixture *mix, const double *T0, int64_t ntimes, const double *t,
                                         double rtol, double *T) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T0, mix->M, "T0", 1));
    GRAN_CALL(check_output_times(ntimes, t, T, "T"));
    GRAN_CALL(check_rtol(rtol, "rtol"));
    if (ntimes == 0) return GRAN_SUCCESS;
    const int64_t M = mix->M;
    Traj tr;
    GRAN_CALL(traj_init(tr, mix, T0, false));
    std::vector<int64_t> idx((size_t)ntimes);
    std::iota(idx.begin(), idx.end(), (int64_t)0);
    std::stable_sort(idx.begin(), idx.end(), [&](int64_t a, int64_t b) { return t[a] < t[b]; });
    std::vector<double> so((size_t)ntimes), Y((size_t)(ntimes * M));
    for (int64_t j = 0; j < ntimes; j++) so[(size_t)j] = traj_s_of_t(tr, t[idx[(size_t)j]]);
    /* the local tolerance is rtol/10: the global error then stays ~rtol (bench b401) */
    GRAN_CALL(traj_run(tr, ntimes, so.data(), Y.data(), std::max(1e-15, 0.1 * rtol), false, HUGE_VAL, 0.0));
    for (int64_t j = 0; j < ntimes; j++)
      for (int64_t k = 0; k < M; k++)
        T[idx[(size_t)j] * M + k] = T0[k] * std::exp(Y[(size_t)(j * M + k)] - 2.0 * so[(size_t)j]);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
