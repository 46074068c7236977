/* newton.cpp - the damped Newton iteration of the higher Sonine HCS systems (sonine2.cpp, sonine_n.cpp). */
#include "theory/theory_impl.h"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include <algorithm>
#include <cmath>

namespace gran {

namespace {
double max_abs(const gsl_vector *v) {
  double a = 0.0;
  for (size_t j = 0; j < v->size; j++) a = std::max(a, std::fabs(gsl_vector_get(v, j)));
  return a;
}
}  // namespace

int sonine_newton(gsl_vector *x, size_t nlog, int (*fn)(const gsl_vector *, void *, gsl_vector *), void *ctx,
                  const char *what, double *res_out) {
  const size_t dim = x->size;
  gsl_vector *f = gsl_vector_alloc(dim), *xt = gsl_vector_alloc(dim), *ft = gsl_vector_alloc(dim),
             *fp = gsl_vector_alloc(dim), *dx = gsl_vector_alloc(dim);
  gsl_matrix *J = gsl_matrix_alloc(dim, dim);
  gsl_permutation *perm = gsl_permutation_alloc(dim);
  int status = GRAN_SUCCESS;
  double res = HUGE_VAL;
  if (!f || !xt || !ft || !fp || !dx || !J || !perm) status = GRAN_ERR_NOMEM;
  if (status == GRAN_SUCCESS) {
    if (fn(x, ctx, f) != GSL_SUCCESS) status = GRAN_ERR_NUMERIC;
    else res = max_abs(f);
  }
  for (int it = 0; it < 60 && status == GRAN_SUCCESS && res > 1e-15; it++) {
    for (size_t c = 0; c < dim && status == GRAN_SUCCESS; c++) {
      const bool logT = c < nlog;
      const double step = logT ? 1e-5 : 1e-3;
      gsl_vector_memcpy(xt, x);
      gsl_vector_set(xt, c, gsl_vector_get(x, c) + step);
      if (fn(xt, ctx, fp) != GSL_SUCCESS) status = GRAN_ERR_NUMERIC;
      if (logT) {
        gsl_vector_set(xt, c, gsl_vector_get(x, c) - step);
        if (status == GRAN_SUCCESS && fn(xt, ctx, ft) != GSL_SUCCESS) status = GRAN_ERR_NUMERIC;
        for (size_t r = 0; r < dim; r++)
          gsl_matrix_set(J, r, c, (gsl_vector_get(fp, r) - gsl_vector_get(ft, r)) / (2.0 * step));
      } else {
        for (size_t r = 0; r < dim; r++) gsl_matrix_set(J, r, c, (gsl_vector_get(fp, r) - gsl_vector_get(f, r)) / step);
      }
    }
    if (status != GRAN_SUCCESS) break;
    int sgn = 0;
    if (gsl_linalg_LU_decomp(J, perm, &sgn) != GSL_SUCCESS || gsl_linalg_LU_solve(J, perm, f, dx) != GSL_SUCCESS) {
      status = GRAN_ERR_NOCONV;
      break;
    }
    double lam = 1.0, rt = HUGE_VAL;
    for (int ls = 0; ls < 30; ls++, lam *= 0.5) {
      gsl_vector_memcpy(xt, x);
      gsl_blas_daxpy(-lam, dx, xt);
      if (fn(xt, ctx, ft) == GSL_SUCCESS && (rt = max_abs(ft)) < res) break;
    }
    if (!(rt < res)) break; /* no decrease: the residual is at rounding level */
    gsl_vector_memcpy(x, xt);
    gsl_vector_memcpy(f, ft);
    res = rt;
  }
  for (gsl_vector *v : {f, xt, ft, fp, dx}) gsl_vector_free(v);
  gsl_matrix_free(J);
  gsl_permutation_free(perm);
  *res_out = res;
  GRAN_CHECK(status != GRAN_ERR_NOMEM, GRAN_ERR_NOMEM, "%s: no memory for the %zu unknowns", what, dim);
  GRAN_CHECK(status == GRAN_SUCCESS, status, "%s: the Newton iteration failed (%s)", what,
             status == GRAN_ERR_NUMERIC ? "non-finite rates" : "singular Jacobian");
  return GRAN_SUCCESS;
}

}  // namespace gran
