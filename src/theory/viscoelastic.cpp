/* viscoelastic.cpp - velocity-dependent restitution of viscoelastic spheres (Bodrova & Osinsky App. A,
 * docs/physics.md, "Viscoelastic restitution"): eps(x) = 1 + sum_{k=1..20} h_k x^k, x = sqrt(beta) |v_n|^(1/10), for
 * x <= X_SWITCH and the [3/6] Pade approximant of Mueller & Poeschel (2011) beyond. X_SWITCH is
 * the point where the two forms cross (their difference changes sign there), so eps(x) is
 * continuous to rounding (|jump| < 1e-15) without blending. Accuracy against the exact
 * collision (docs/physics.md values): 4e-16 at x = 0.1, 5e-13 at 0.3 (series); 8.6e-7 at 0.5,
 * 3.2e-5 at 0.8, 1.0e-4 at 1.0, 4.0e-4 at 1.5, 6.1e-4 at 2.0 (Pade). */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <cstring>

namespace {

/* h_0..h_20 of data/viscoelastic_hk.csv (Schwager & Poeschel 2008 delayed-recovery end). */
const double H[21] = {1.0,
                      0.0,
                      -1.1534488580952887991,
                      0.0,
                      0.79826656094479540625,
                      0.26666666666666666667,
                      -0.5228825680884149639,
                      -0.46137954323811551965,
                      0.34874267526038503473,
                      0.45235105120205073021,
                      -0.14643146535257773367,
                      -0.36772830083814517031,
                      -0.043248983015276303036,
                      0.28180423421853528868,
                      0.14785258773191059115,
                      -0.17944206016930798518,
                      -0.17846603342860487393,
                      0.065933589474841266813,
                      0.17135861854697103935,
                      0.025249822049520526812,
                      -0.1379234993765172905};

/* Crossing of the 20-term series and the Pade form (bisection in double precision). */
const double X_SWITCH = 0.4266132065880488;

/* eps - 1 from the series (Horner), x <= X_SWITCH */
inline double series_dev(double x) {
  double s = 0.0;
  for (int k = 20; k >= 1; k--) s = s * x + H[k];
  return s * x;
}

/* eps from the [3/6] Pade approximant */
inline double pade(double x) {
  if (x > 16.0) {
    /* the same ratio in powers of y = 1/x: num/den = y^3 (0.141552 + y (0.574198 + ...)) /
     * (0.235585 + y (0.467273 + ...)) never overflows (x^6 does past 1e51; beta = 1e300 gives x ~ 1e150) */
    const double y = 1.0 / x;
    const double num = 0.141552 + y * (0.574198 + y * (1.07232 + y));
    const double den = 0.235585 + y * (0.467273 + y * (1.19449 + y * (1.37842 + y * (1.72765 + y * (1.07232 + y)))));
    return y * y * y * (num / den);
  }
  const double num = 1.0 + x * (1.07232 + x * (0.574198 + x * 0.141552));
  const double den =
      1.0 + x * (1.07232 + x * (1.72765 + x * (1.37842 + x * (1.19449 + x * (0.467273 + x * 0.235585)))));
  return num / den;
}

/* eps - 1 for any x >= 0, without cancellation on the series branch */
inline double eps_dev(double x) { return x <= X_SWITCH ? series_dev(x) : pade(x) - 1.0; }

/* ---- collision-weighted averages ----------------------------------------------------------- */
struct Coeffs {
  double A[41];    /* A_n = 4 h_n + sum_{j+k=n} h_j h_k, n = 0..40 (h_n = 0 for n > 20) */
  double G[41];    /* Gamma(2 + n/20) / 2 */
  Coeffs() {
    for (int n = 0; n <= 40; n++) {
      double a = n <= 20 ? 4.0 * H[n] : 0.0;
      if (n == 0) a = 0.0;
      for (int j = 1; j < n; j++) {
        const int k = n - j;
        if (j <= 20 && k <= 20) a += H[j] * H[k];
      }
      A[n] = a;
      G[n] = 0.5 * std::tgamma(2.0 + n / 20.0);
    }
  }
};
const Coeffs &coeffs() {
  static const Coeffs c;
  return c;
}

struct AvgParams {
  double z;
  int which; /* 1: (eps-1)/2, 2: (eps-1)(eps+3)/4 */
};

double avg_integrand(double s, void *p) {
  const AvgParams *a = static_cast<const AvgParams *>(p);
  if (s <= 0.0) return 0.0;
  const double x = a->z * std::pow(s, 0.05);
  const double d = eps_dev(x);
  const double f = a->which == 1 ? 0.5 * d : 0.25 * d * (d + 4.0);
  return s * std::exp(-s) * f;
}

const double Z_SERIES = 0.35; /* x > X_SWITCH needs s > (X_SWITCH/0.35)^20 = 52: weight < 1e-20 */


/* ---- first Sonine moments (sonine.cpp, docs/physics-sonine.md Sec. 6) ---------------------------
 * D_jk = <p^j - 1>_k, p = (1 + eps)/2, the average over u = g_n^2/(2 s^2) with weight
 * u^((k-1)/2) e^-u / Gamma((k+1)/2), for j = 1..4 and k = 3, 5, 7, 9. Series: p^j - 1 = sum_n c_jn x^n
 * (degree 20 j), D_jk = sum_n c_jn z^n Gamma((k+1)/2 + n/20)/Gamma((k+1)/2). */
struct SonCoeffs {
  double c[5][81]; /* c_jn */
  double g[10][81]; /* Gamma((k+1)/2 + n/20)/Gamma((k+1)/2), odd k */
  SonCoeffs() {
    std::memset(c, 0, sizeof c);
    std::memset(g, 0, sizeof g);
    double pw[81] = {1.0}; /* p^j, starting at j = 0 */
    for (int j = 1; j <= 4; j++) {
      double nw[81] = {0.0};
      for (int a = 0; a <= 20 * (j - 1); a++)
        for (int b = 0; b <= 20; b++) nw[a + b] += pw[a] * (b == 0 ? 1.0 : 0.5 * H[b]);
      std::memcpy(pw, nw, sizeof pw);
      for (int n = 1; n <= 20 * j; n++) c[j][n] = pw[n];
    }
    for (int k = 3; k <= 9; k += 2)
      for (int n = 0; n <= 80; n++) {
        const double a = 0.5 * (k + 1);
        g[k][n] = std::exp(std::lgamma(a + n / 20.0) - std::lgamma(a));
      }
  }
};
const SonCoeffs &son_coeffs() {
  static const SonCoeffs c;
  return c;
}

struct SonGL {
  static const int NQ = 12;
  double x[NQ], w[NQ], lg[10];
  SonGL() {
    gsl_integration_glfixed_table *t = gsl_integration_glfixed_table_alloc(NQ);
    for (int q = 0; q < NQ; q++) gsl_integration_glfixed_point(-1.0, 1.0, (size_t)q, &x[q], &w[q], t);
    gsl_integration_glfixed_table_free(t);
    for (int k = 0; k < 10; k++) lg[k] = std::lgamma(0.5 * (k + 1));
  }
};
const SonGL &son_gl() {
  static const SonGL g;
  return g;
}

struct SonParams {
  double z;
  int j, k;
};

double son_integrand(double u, void *pv) {
  const SonParams *p = static_cast<const SonParams *>(pv);
  if (u <= 0.0) return 0.0;
  const double hd = 0.5 * eps_dev(p->z * std::pow(u, 0.05)); /* p - 1 */
  const double pm1 = p->j == 1 ? hd : p->j == 2 ? hd * (2.0 + hd) : p->j == 3 ? hd * (3.0 + hd * (3.0 + hd))
                                                                            : hd * (4.0 + hd * (6.0 + hd * (4.0 + hd)));
  const double a = 0.5 * (p->k + 1);
  return std::exp((a - 1.0) * std::log(u) - u - std::lgamma(a)) * pm1;
}
} // namespace

namespace gran {

double visco_eps(double x) { return 1.0 + eps_dev(x); }

int visco_averages(double z, double *q1, double *q2) {
  if (!(z >= 0.0) || !std::isfinite(z))
    return GRAN_ERROR(GRAN_ERR_NUMERIC, "viscoelastic scale z = %g is not finite and >= 0", z);
  if (z <= Z_SERIES) {
    const Coeffs &c = coeffs();
    double zn = 1.0, s1 = 0.0, s2 = 0.0;
    for (int n = 1; n <= 40; n++) {
      zn *= z;
      const double b = zn * c.G[n];
      if (n <= 20) s1 += H[n] * b;
      s2 += c.A[n] * b;
    }
    *q1 = s1;
    *q2 = 0.5 * s2;
    return GRAN_SUCCESS;
  }
  /* one workspace per thread, released at thread exit */
  struct Ws {
    gsl_integration_workspace *w = nullptr;
    ~Ws() { gsl_integration_workspace_free(w); }
  };
  thread_local Ws ws;
  if (!ws.w) ws.w = gsl_integration_workspace_alloc(256);
  gsl_integration_workspace *w = ws.w;
  if (!w) return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate a GSL integration workspace");
  const double ssw = std::pow(X_SWITCH / z, 20.0);
  double out[2];
  for (int which = 1; which <= 2; which++) {
    AvgParams p{z, which};
    gsl_function F{avg_integrand, &p};
    double r1 = 0.0, r2 = 0.0, e1 = 0.0, e2 = 0.0;
    int st = GSL_SUCCESS;
    if (ssw > 0.0) st = gsl_integration_qags(&F, 0.0, ssw, 0.0, 1e-12, 256, w, &r1, &e1);
    if (st == GSL_SUCCESS) st = gsl_integration_qagiu(&F, ssw, 0.0, 1e-12, 256, w, &r2, &e2);
    if (st != GSL_SUCCESS && st != GSL_EROUND)
      return GRAN_ERROR(GRAN_ERR_NOCONV, "viscoelastic average (z = %g): GSL quadrature failed: %s", z,
                        gsl_strerror(st));
    out[which - 1] = r1 + r2;
  }
  *q1 = out[0];
  *q2 = out[1];
  return GRAN_SUCCESS;
}

int visco_sonine_moments(double z, double D[5][10]) {
  if (!(z >= 0.0) || !std::isfinite(z))
    return GRAN_ERROR(GRAN_ERR_NUMERIC, "viscoelastic scale z = %g is not finite and >= 0", z);
  for (int j = 0; j < 5; j++)
    for (int k = 0; k < 10; k++) D[j][k] = 0.0;
  if (z == 0.0) return GRAN_SUCCESS;
  if (z <= Z_SERIES) { /* u > 52 (x > X_SWITCH) carries weight < 1e-16 even for k = 9 */
    const SonCoeffs &c = son_coeffs();
    /* terms past n_cut are below 1e-17 |D_jk| (|c_jn| Gamma ratio <= 68 for every j, k; D_jk ~ z^2):
     * z^(n - 2) < 1e-17 / (68 * 80 * 2) */
    const int ncut = z < 1e-300 ? 2 : std::min(80, 3 + (int)(std::log(1e-17 / (68.0 * 160.0)) / std::log(z)));
    double zn[81];
    zn[0] = 1.0;
    for (int n = 1; n <= ncut; n++) zn[n] = zn[n - 1] * z;
    for (int k = 3; k <= 9; k += 2)
      for (int j = 1; j <= 4; j++) {
        double acc = 0.0;
        for (int n = std::min(20 * j, ncut); n >= 1; n--) acc += c.c[j][n] * zn[n] * c.g[k][n];
        D[j][k] = acc;
      }
    return GRAN_SUCCESS;
  }
  /* beyond the series: u = y^20, weight 20 y^(20 a - 1) e^(-y^20) dy / Gamma(a) (smooth, peaked at
   * y ~ 1; below y = 0.2 it is < 1e-27, beyond y = 1.3 (u = 190) < 1e-70), x = z y; composite
   * 12-point Gauss-Legendre on panels of 0.05 in y, one panel boundary at the series/Pade switch
   * y = X_SWITCH/z; all 16 moments from one evaluation of eps per node */
  const SonGL &gl = son_gl();
  double acc[5][10] = {};
  const double ysw = X_SWITCH / z;
  const double Y0 = 0.2, Y1 = 1.3, H = 0.05;
  double a0 = Y0;
  while (a0 < Y1 - 1e-12) {
    double b0 = std::min(Y1, a0 + H);
    if (ysw > a0 + 1e-9 && ysw < b0 - 1e-9) b0 = ysw;
    const double c = 0.5 * (a0 + b0), h = 0.5 * (b0 - a0);
    for (int q = 0; q < SonGL::NQ; q++) {
      const double y = c + h * gl.x[q], wq = h * gl.w[q];
      const double hd = 0.5 * eps_dev(z * y); /* p - 1 */
      const double pj[5] = {0.0, hd, hd * (2.0 + hd), hd * (3.0 + hd * (3.0 + hd)),
                            hd * (4.0 + hd * (6.0 + hd * (4.0 + hd)))};
      const double y20 = std::pow(y, 20.0), ly = std::log(y);
      for (int k = 3; k <= 9; k += 2) {
        const double a = 0.5 * (k + 1);
        const double wt = wq * 20.0 * std::exp((20.0 * a - 1.0) * ly - y20 - gl.lg[k]);
        for (int j = 1; j <= 4; j++) acc[j][k] += wt * pj[j];
      }
    }
    a0 = b0;
  }
  for (int k = 3; k <= 9; k += 2)
    for (int j = 1; j <= 4; j++) D[j][k] = acc[j][k];
  return GRAN_SUCCESS;
}

/* the same moments by GSL adaptive quadrature (reference for the composite rule above; not on the hot path) */
int visco_sonine_moments_ref(double z, double D[5][10]) {
  for (int j = 0; j < 5; j++)
    for (int k = 0; k < 10; k++) D[j][k] = 0.0;
  struct Ws {
    gsl_integration_workspace *w = nullptr;
    ~Ws() { gsl_integration_workspace_free(w); }
  };
  thread_local Ws ws;
  if (!ws.w) ws.w = gsl_integration_workspace_alloc(256);
  if (!ws.w) return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate a GSL integration workspace");
  const double usw = std::pow(X_SWITCH / z, 20.0);
  for (int k = 3; k <= 9; k += 2)
    for (int j = 1; j <= 4; j++) {
      SonParams p{z, j, k};
      gsl_function F{son_integrand, &p};
      double r1 = 0.0, r2 = 0.0, e1 = 0.0, e2 = 0.0;
      int st = GSL_SUCCESS;
      if (usw > 0.0) st = gsl_integration_qags(&F, 0.0, usw, 0.0, 1e-12, 256, ws.w, &r1, &e1);
      if (st == GSL_SUCCESS || st == GSL_EROUND) st = gsl_integration_qagiu(&F, usw, 0.0, 1e-12, 256, ws.w, &r2, &e2);
      if (st != GSL_SUCCESS && st != GSL_EROUND)
        return GRAN_ERROR(GRAN_ERR_NOCONV, "viscoelastic Sonine moment (z = %g, j = %d, k = %d): GSL quadrature failed: %s",
                          z, j, k, gsl_strerror(st));
      D[j][k] = r1 + r2;
    }
  return GRAN_SUCCESS;
}

} // namespace gran

/**
 * @brief Viscoelastic restitution eps(x), x = sqrt(beta) |v_n|^(1/10): the 20-term series for
 * x <= 0.4266 and the [3/6] Pade approximant beyond (continuous at the switch).
 * @param[in] x >= 0, finite
 * @param[out] eps in (0, 1], decreasing in x
 */
GRAN_EXTERN int gran_viscoelastic_eps(double x, double *eps) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CHECK_PTR(eps);
    GRAN_CHECK(std::isfinite(x) && x >= 0.0, GRAN_ERR_ARG, "argument 'x' = %g must be finite and >= 0", x);
    *eps = gran::visco_eps(x);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief eps for a pair with parameter beta >= 0 and normal relative speed v_n (sign ignored).
 */
GRAN_EXTERN int gran_viscoelastic_eps_vn(double beta, double vn, double *eps) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CHECK_PTR(eps);
    GRAN_CHECK(std::isfinite(beta) && beta >= 0.0, GRAN_ERR_ARG, "argument 'beta' = %g must be finite and >= 0",
               beta);
    GRAN_CHECK(std::isfinite(vn), GRAN_ERR_ARG, "argument 'vn' is not finite (%g)", vn);
    const double x = std::sqrt(beta) * std::pow(std::fabs(vn), 0.1);
    *eps = gran::visco_eps(x);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
