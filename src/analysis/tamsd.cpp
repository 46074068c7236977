/* tamsd.cpp - time-averaged mean squared displacement of trajectories on a uniform time grid.
 *
 *   delta^2(L) = 1/(N-L) sum_{i=0}^{N-1-L} |R_{i+L} - R_i|^2,   L = 0 .. nlag-1 (in samples)
 *
 * FFT method, O(N log N) per trajectory (the standard decomposition, e.g. Calandrini et al.,
 * Collection SFN 12, 201 (2011)): |R_{i+L} - R_i|^2 = D_{i+L} + D_i - 2 R_{i+L}.R_i with
 * D_i = |R_i|^2, so
 *   (N-L) delta^2(L) = Q_L - 2 S(L),   Q_L = sum_{i=0}^{N-1-L} (D_i + D_{i+L}),
 *   Q_0 = 2 sum D,  Q_L = Q_{L-1} - D_{L-1} - D_{N-L},   S(L) = sum_i R_{i+L}.R_i,
 * and S is the autocorrelation of the zero-padded coordinates (FFT length >= 2N, no wrap-around):
 * S = IFFT(sum_c |FFT(x_c)|^2) / length, so three real forward transforms and one inverse per
 * trajectory. Each trajectory's mean position is subtracted first (delta^2 is translation
 * invariant): it keeps D small and the cancellation in Q_L - 2 S(L) mild. The last
 * ntail = sqrt(N log2 N) lags, whose few terms the FFT's absolute rounding would swamp, are summed
 * directly at a cost below the FFT's (see gran_tamsd_plan_create).
 *
 * FFTW's planner is not thread-safe: plan creation and destruction take one process-wide mutex
 * (gran_fftw_planner_mutex, for any other FFTW user of the library too); execution is.
 */
#include "granary_impl.h"

#include <fftw3.h>

#include <algorithm>
#include <mutex>

/* The one lock around FFTW's planner (fftw_plan_*, fftw_destroy_plan) in the library. */
std::mutex &gran_fftw_planner_mutex() {
  static std::mutex m;
  return m;
}

struct gran_tamsd_plan {
  int64_t n = 0;         /* samples per trajectory */
  int64_t len = 0;       /* FFT length >= 2n */
  double *in = nullptr;  /* 3 * len real inputs (x, y, z) */
  fftw_complex *spec = nullptr; /* 3 * (len/2 + 1) spectra */
  fftw_complex *pow = nullptr;  /* len/2 + 1 power spectrum, summed over xyz */
  double *acf = nullptr; /* len: len * autocorrelation */
  double *d = nullptr;   /* n: |R_i - mean|^2 */
  int64_t ntail = 0;     /* the last ntail lags are summed directly (see gran_tamsd_plan_create) */
  fftw_plan fwd = nullptr, inv = nullptr;
};

namespace {

/* smallest 2^a 3^b 5^c 7^d >= n: sizes FFTW transforms fastest */
int64_t fft_size(int64_t n) {
  for (int64_t m = n;; m++) {
    int64_t r = m;
    for (int64_t p : {2, 3, 5, 7})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

void plan_release(gran_tamsd_plan *p) {
  {
    std::lock_guard<std::mutex> lock(gran_fftw_planner_mutex());
    if (p->fwd) fftw_destroy_plan(p->fwd);
    if (p->inv) fftw_destroy_plan(p->inv);
  }
  fftw_free(p->in);
  fftw_free(p->spec);
  fftw_free(p->pow);
  fftw_free(p->acf);
  std::free(p->d);
  delete p;
}

int check_tamsd_args(int64_t ntraj, int64_t nsamples, const double *xyz, int64_t nlag, const double *tamsd) {
  GRAN_CHECK(ntraj >= 1, GRAN_ERR_ARG, "argument 'ntraj' = " GRAN_I64_FMT " must be >= 1", ntraj);
  GRAN_CHECK(nsamples >= 1, GRAN_ERR_ARG, "argument 'nsamples' = " GRAN_I64_FMT " must be >= 1", nsamples);
  GRAN_CHECK(nlag >= 1 && nlag <= nsamples, GRAN_ERR_ARG,
             "argument 'nlag' = " GRAN_I64_FMT " outside [1, nsamples = " GRAN_I64_FMT "]", nlag, nsamples);
  GRAN_CHECK(ntraj <= INT64_MAX / 3 / nsamples, GRAN_ERR_ARG,
             "ntraj * nsamples = " GRAN_I64_FMT " * " GRAN_I64_FMT " overflows", ntraj, nsamples);
  GRAN_CHECK_PTR(xyz);
  GRAN_CHECK_PTR(tamsd);
  return GRAN_SUCCESS;
}

int check_finite(int64_t count, const double *x, const char *name) {
  for (int64_t i = 0; i < count; i++)
    GRAN_CHECK(std::isfinite(x[i]), GRAN_ERR_ARG, "%s[" GRAN_I64_FMT "] = %g is not finite", name, i, x[i]);
  return GRAN_SUCCESS;
}

}  // namespace

/** @brief Plan for trajectories of `nsamples` samples: FFT length, buffers and FFTW plans (FFTW's
 *  planner runs under a mutex, so plans may be created from several threads).
 *  @param[in] nsamples >= 1  @param[out] plan new plan; release with gran_tamsd_plan_destroy */
GRAN_EXTERN int gran_tamsd_plan_create(int64_t nsamples, gran_tamsd_plan **plan) {
  GRAN_CHECK_PTR(plan);
  *plan = nullptr;
  GRAN_CHECK(nsamples >= 1, GRAN_ERR_ARG, "argument 'nsamples' = " GRAN_I64_FMT " must be >= 1", nsamples);
  GRAN_CHECK(nsamples <= INT32_MAX / 2, GRAN_ERR_ARG, "argument 'nsamples' = " GRAN_I64_FMT " is too large",
             nsamples);
  const int64_t len = fft_size(2 * nsamples);
  GRAN_CHECK(len <= INT32_MAX, GRAN_ERR_ARG, "argument 'nsamples' = " GRAN_I64_FMT " is too large for FFTW",
             nsamples);
  GRAN_TRY {
    gran_tamsd_plan *p = new gran_tamsd_plan;
    p->n = nsamples;
    p->len = len;
    /* The FFT's rounding error in S(L) is absolute, ~ eps sum_i |R_i|^2, while (N-L) delta^2(L)
     * shrinks with the number N-L of terms: the largest lags lose digits (1e-9 relative at
     * N = 1e5 for a random walk). Their direct sums cost ~ ntail^2 / 2 pair terms, so
     * ntail = sqrt(N log2 N) keeps the cost below the FFT's while every lag stays near 1e-12. */
    p->ntail = std::min(nsamples, (int64_t)std::ceil(std::sqrt((double)nsamples * std::log2((double)nsamples + 1.0))));
    const int64_t nc = p->len / 2 + 1;
    p->in = fftw_alloc_real((size_t)(3 * p->len));
    p->spec = fftw_alloc_complex((size_t)(3 * nc));
    p->pow = fftw_alloc_complex((size_t)nc);
    p->acf = fftw_alloc_real((size_t)p->len);
    p->d = gran_alloc<double>(nsamples);
    if (!p->in || !p->spec || !p->pow || !p->acf || !p->d) {
      plan_release(p);
      return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate FFT buffers of length " GRAN_I64_FMT, 2 * nsamples);
    }
    {
      std::lock_guard<std::mutex> lock(gran_fftw_planner_mutex());
      const int ilen = (int)len;
      /* three transforms (x, y, z) of length len, stored one after another */
      p->fwd = fftw_plan_many_dft_r2c(1, &ilen, 3, p->in, nullptr, 1, ilen, p->spec, nullptr, 1, (int)nc,
                                      FFTW_ESTIMATE | FFTW_PRESERVE_INPUT);
      p->inv = fftw_plan_dft_c2r_1d(ilen, p->pow, p->acf, FFTW_ESTIMATE);
    }
    if (!p->fwd || !p->inv) {
      plan_release(p);
      return GRAN_ERROR(GRAN_ERR_INTERNAL, "FFTW could not plan transforms of length " GRAN_I64_FMT, 2 * nsamples);
    }
    *plan = p;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Release a plan; NULL-safe, sets *plan to NULL. */
GRAN_EXTERN int gran_tamsd_plan_destroy(gran_tamsd_plan **plan) {
  if (!plan || !*plan) return GRAN_SUCCESS;
  plan_release(*plan);
  *plan = nullptr;
  return GRAN_SUCCESS;
}

/** @brief TAMSD averaged over ntraj trajectories by FFT, O(ntraj N log N). A plan holds working
 *  buffers: use one plan per thread.
 *  @param[in] plan for N = nsamples  @param[in] ntraj >= 1  @param[in] xyz ntraj*N*3 positions,
 *  layout [traj][sample][3]  @param[in] nlag 1..N  @param[out] tamsd nlag values (lags 0..nlag-1) */
GRAN_EXTERN int gran_tamsd_plan_execute(gran_tamsd_plan *plan, int64_t ntraj, const double *xyz, int64_t nlag,
                                        double *tamsd) {
  GRAN_CHECK_PTR(plan);
  GRAN_CALL(check_tamsd_args(ntraj, plan->n, xyz, nlag, tamsd));
  GRAN_CALL(check_finite(3 * ntraj * plan->n, xyz, "xyz"));
  GRAN_TRY {
    const int64_t n = plan->n, len = plan->len, nc = len / 2 + 1;
    for (int64_t l = 0; l < nlag; l++) tamsd[l] = 0.0;
    for (int64_t t = 0; t < ntraj; t++) {
      const double *r = xyz + 3 * n * t;
      double *in = plan->in;
      for (int c = 0; c < 3; c++) {
        double mean = 0.0;
        for (int64_t i = 0; i < n; i++) mean += r[3 * i + c];
        mean /= (double)n;
        double *x = in + c * len;
        for (int64_t i = 0; i < n; i++) x[i] = r[3 * i + c] - mean;
        for (int64_t i = n; i < len; i++) x[i] = 0.0;
      }
      double sum_d = 0.0;
      for (int64_t i = 0; i < n; i++) {
        const double dx = in[i], dy = in[len + i], dz = in[2 * len + i];
        plan->d[i] = dx * dx + dy * dy + dz * dz;
        sum_d += plan->d[i];
      }
      fftw_execute(plan->fwd);
      for (int64_t k = 0; k < nc; k++) {
        double p = 0.0;
        for (int c = 0; c < 3; c++) {
          const fftw_complex &z = plan->spec[c * nc + k];
          p += z[0] * z[0] + z[1] * z[1];
        }
        plan->pow[k][0] = p;
        plan->pow[k][1] = 0.0;
      }
      fftw_execute(plan->inv); /* acf[L] = len * S(L) */
      const double inv_len = 1.0 / (double)len;
      const int64_t lfft = std::min(nlag, n - plan->ntail); /* lags below: FFT; from here: direct */
      double q = 2.0 * sum_d;
      for (int64_t l = 1; l < lfft; l++) { /* l = 0 is 0 by definition */
        q -= plan->d[l - 1] + plan->d[n - l];
        tamsd[l] += (q - 2.0 * plan->acf[l] * inv_len) / (double)(n - l);
      }
      const double *x = in, *y = in + len, *z = in + 2 * len; /* kept by the r2c transform */
      for (int64_t l = std::max(lfft, INT64_C(1)); l < nlag; l++) {
        double sum = 0.0;
        for (int64_t i = 0; i + l < n; i++) {
          const double dx = x[i + l] - x[i], dy = y[i + l] - y[i], dz = z[i + l] - z[i];
          sum += dx * dx + dy * dy + dz * dz;
        }
        tamsd[l] += sum / (double)(n - l);
      }
    }
    for (int64_t l = 1; l < nlag; l++) tamsd[l] /= (double)ntraj;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief One-shot TAMSD by FFT: create a plan, execute it, destroy it. */
GRAN_EXTERN int gran_tamsd(int64_t ntraj, int64_t nsamples, const double *xyz, int64_t nlag, double *tamsd) {
  GRAN_CALL(check_tamsd_args(ntraj, nsamples, xyz, nlag, tamsd));
  gran_tamsd_plan *plan = nullptr;
  GRAN_CALL(gran_tamsd_plan_create(nsamples, &plan));
  const int ierr = gran_tamsd_plan_execute(plan, ntraj, xyz, nlag, tamsd);
  gran_tamsd_plan_destroy(&plan);
  return ierr;
}

/** @brief Reference TAMSD by the definition, O(ntraj N nlag); same arguments as gran_tamsd. */
GRAN_EXTERN int gran_tamsd_direct(int64_t ntraj, int64_t nsamples, const double *xyz, int64_t nlag,
                                  double *tamsd) {
  GRAN_CALL(check_tamsd_args(ntraj, nsamples, xyz, nlag, tamsd));
  GRAN_CALL(check_finite(3 * ntraj * nsamples, xyz, "xyz"));
  const int64_t n = nsamples;
  for (int64_t l = 0; l < nlag; l++) {
    double acc = 0.0;
    for (int64_t t = 0; t < ntraj; t++) {
      const double *r = xyz + 3 * n * t;
      double s = 0.0;
      for (int64_t i = 0; i + l < n; i++) {
        const double dx = r[3 * (i + l)] - r[3 * i], dy = r[3 * (i + l) + 1] - r[3 * i + 1],
                     dz = r[3 * (i + l) + 2] - r[3 * i + 2];
        s += dx * dx + dy * dy + dz * dz;
      }
      acc += s / (double)(n - l);
    }
    tamsd[l] = acc / (double)ntraj;
  }
  return GRAN_SUCCESS;
}
