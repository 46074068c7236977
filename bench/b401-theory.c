/* b401-theory.c - accuracy versus cost of the kinetic-theory numerics (src/theory):
 *  1. temperature ODE (Eq. 13): requested rtol -> error against Haff's law (HCS start, exact) and
 *     against a tight reference (equipartition start), time;
 *  2. MSD by numerical integration of Eq. 4: error against the closed form Eq. 22, time;
 *  3. Xi(Delta) of Eq. 27 by GSL QAG: error against a tight reference (rtol 1e-14), time; and the
 *     100-lag TAMSD curve (target < 0.1 s);
 *  4. HCS solve for M = 10 .. 1e5 (n_k = 0.1 k^-3; target M = 1e4 < 1 s), and the O(M^2) pass.
 * BENCH_QUICK=1 skips M = 1e5 (about 30 s). */
#include "bench_util.h"

#include <math.h>

static double maxrel(const double *a, const double *b, int n) {
  double e = 0;
  for (int i = 0; i < n; i++) e = fmax(e, fabs(a[i] / b[i] - 1));
  return e;
}

static gran_mixture *fig3(double *T0, double *tau0) {
  const double m[3] = {1, 100, 500}, s[3] = {1, cbrt(100.0), cbrt(500.0)}, n[3] = {0.1, 0.1, 0.1};
  gran_mixture *mix = NULL;
  BENCH_CHECK(gran_mixture_create(3, m, s, n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
  BENCH_CHECK(gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, T0, tau0));
  return mix;
}

static const double RTOLS[5] = {1e-4, 1e-6, 1e-8, 1e-10, 1e-12};

static void bench_ode(void) {
  double T0[3], tau0;
  gran_mixture *mix = fig3(T0, &tau0);
  enum { NT = 31 };
  double t[NT], T[3 * NT], Tex[3 * NT], Tref[3 * NT], Te[3 * NT];
  for (int j = 0; j < NT; j++) {
    t[j] = tau0 * pow(10.0, -15.0 + j); /* 1e-15 .. 1e15 tau0 */
    for (int k = 0; k < 3; k++) Tex[3 * j + k] = T0[k] / pow(1 + t[j] / tau0, 2);
  }
  const double Teq[3] = {1, 1, 1};
  BENCH_CHECK(gran_theory_temperatures(mix, Teq, NT, t, 1e-14, Tref));
  printf("\n1. Temperature ODE (Eq. 13), Fig. 3 mixture, 31 times from 1e-15 to 1e15 tau0\n");
  printf("%10s | %14s %10s | %14s %10s\n", "rtol", "HCS start: err", "time [s]", "equip.: err", "time [s]");
  printf("%10s | %14s %10s | %14s %10s\n", "", "(vs Haff)", "", "(vs rtol 1e-14)", "");
  for (int r = 0; r < 5; r++) {
    double t0 = bench_now();
    BENCH_CHECK(gran_theory_temperatures(mix, T0, NT, t, RTOLS[r], T));
    const double e1 = bench_now() - t0;
    t0 = bench_now();
    BENCH_CHECK(gran_theory_temperatures(mix, Teq, NT, t, RTOLS[r], Te));
    const double e2 = bench_now() - t0;
    printf("%10.0e | %14.2e %10.4f | %14.2e %10.4f\n", RTOLS[r], maxrel(T, Tex, 3 * NT), e1,
           maxrel(Te, Tref, 3 * NT), e2);
  }
  gran_mixture_destroy(&mix);
}

static void bench_msd(void) {
  double T0[3], tau0;
  gran_mixture *mix = fig3(T0, &tau0);
  enum { NT = 25 };
  double t[NT], a[3 * NT], b[3 * NT];
  for (int j = 0; j < NT; j++) t[j] = tau0 * pow(10.0, -8.0 + j); /* 1e-8 .. 1e16 tau0 */
  BENCH_CHECK(gran_theory_msd_hcs(mix, T0, tau0, NT, t, a, NULL));
  printf("\n2. MSD by numerical integration of Eq. 4 (ODE + dense output + QAG), Fig. 3 mixture, HCS start,\n"
         "   25 times from 1e-8 to 1e16 tau0; error against the closed form Eq. 22\n");
  printf("%10s | %12s %10s\n", "rtol", "max rel err", "time [s]");
  for (int r = 0; r < 5; r++) {
    const double t0 = bench_now();
    BENCH_CHECK(gran_theory_msd(mix, T0, NT, t, RTOLS[r], b, NULL));
    printf("%10.0e | %12.2e %10.4f\n", RTOLS[r], maxrel(b, a, 3 * NT), bench_now() - t0);
  }
  gran_mixture_destroy(&mix);
}

static void bench_tamsd(void) {
  /* Fig. 5 tracer setup */
  const double m[2] = {1, 100}, s[2] = {1, cbrt(100.0)}, n[2] = {0.1, 0.0};
  gran_mixture *mix = NULL;
  double T0[2], tau0;
  BENCH_CHECK(gran_mixture_create(2, m, s, n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
  BENCH_CHECK(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 1.0, T0, &tau0));
  enum { NL = 100 };
  const double tm = 1e6;
  double lag[NL], ref[2 * NL], xi[2 * NL], ta[2 * NL];
  for (int i = 0; i < NL; i++) lag[i] = tm * pow(10.0, -12.0 + 12.0 * i / (NL - 1));
  lag[NL - 1] = tm * (1 - 1e-12);
  BENCH_CHECK(gran_theory_tamsd_parts(mix, T0, tau0, tm, NL, lag, 1e-14, NULL, ref));
  printf("\n3. Xi(Delta) of Eq. 27 by GSL QAG (Fig. 5 tracer mixture, t = 1e6, 100 lags from 1e-12 t to\n"
         "   t (1 - 1e-12)); error against rtol = 1e-14; and the whole TAMSD curve (Eq. 27, one integral)\n");
  printf("%10s | %12s %10s | %14s\n", "rtol", "Xi max err", "time [s]", "TAMSD time [s]");
  for (int r = 0; r < 5; r++) {
    double t0 = bench_now();
    BENCH_CHECK(gran_theory_tamsd_parts(mix, T0, tau0, tm, NL, lag, RTOLS[r], NULL, xi));
    const double e1 = bench_now() - t0;
    t0 = bench_now();
    BENCH_CHECK(gran_theory_tamsd(mix, T0, tau0, tm, NL, lag, RTOLS[r], ta));
    const double e2 = bench_now() - t0;
    printf("%10.0e | %12.2e %10.5f | %14.5f\n", RTOLS[r], maxrel(xi, ref, 2 * NL), e1, e2);
  }
  gran_mixture_destroy(&mix);
}

static void bench_hcs(void) {
  printf("\n4. HCS solve, n_k = 0.1 k^-3, m_k = k, sigma_k = k^(1/3), eps = 0.5 (target: M = 1e4 < 1 s);\n"
         "   defect = max |xi_k tau0/2 - 1| recomputed independently; O(M^2) pass = one cooling-rate evaluation\n");
  printf("%8s | %10s %12s | %12s %10s\n", "M", "HCS [s]", "defect", "pass [s]", "ns/pair");
  const int64_t Ms[5] = {10, 100, 1000, 10000, 100000};
  for (int i = 0; i < 5; i++) {
    const int64_t M = Ms[i];
    if (M > 10000 && bench_quick()) {
      printf("%8" PRId64 " | (skipped: BENCH_QUICK)\n", M);
      continue;
    }
    gran_mixture *mix = NULL;
    BENCH_CHECK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &mix));
    BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
    double *T = malloc(sizeof(double) * (size_t)M), *xi = malloc(sizeof(double) * (size_t)M), tau0;
    double t0 = bench_now();
    BENCH_CHECK(gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, T, &tau0));
    const double eh = bench_now() - t0;
    t0 = bench_now();
    BENCH_CHECK(gran_theory_cooling_rates(mix, T, xi));
    const double ep = bench_now() - t0;
    double d = 0;
    for (int64_t k = 0; k < M; k++) d = fmax(d, fabs(0.5 * xi[k] * tau0 - 1));
    printf("%8" PRId64 " | %10.4f %12.2e | %12.5f %10.3f\n", M, eh, d, ep, ep / (0.5 * (double)M * (double)M) * 1e9);
    free(T);
    free(xi);
    gran_mixture_destroy(&mix);
  }
}

/* Maxwellian against first Sonine HCS (CPU time, steadier on a shared machine): m_k geometric from
 * 1 to 10, sigma_k = m_k^(1/3), n_k ~ m_k^-2, eps = 0.5. Accuracy: the defects of the Sonine state
 * (max |zeta_k tau0/2 - 1|, max |da2_k/dt| tau0) and how far it moves T_M/T_1 from the Maxwellian. */
static void bench_sonine(void) {
  printf("\n5. HCS: Maxwellian vs first Sonine approximation, m_k = 10^((k-1)/(M-1)), sigma_k = m_k^(1/3),\n"
         "   n_k ~ m_k^-2, eps = 0.5 (CPU seconds; target: Sonine within 10x the Maxwellian)\n");
  printf("%8s | %10s %10s %7s | %10s %10s | %12s %9s\n", "M", "Maxw. [s]", "Sonine [s]", "ratio", "zeta defect",
         "da2 defect", "T_M/T_1 shift", "a2_1");
  const int64_t Ms[4] = {10, 100, 1000, 10000};
  for (int i = 0; i < 4; i++) {
    const int64_t M = Ms[i];
    if (M > 1000 && bench_quick()) {
      printf("%8" PRId64 " | (skipped: BENCH_QUICK)\n", M);
      continue;
    }
    double *m = malloc(sizeof(double) * (size_t)M), *sg = malloc(sizeof(double) * (size_t)M),
           *n = malloc(sizeof(double) * (size_t)M), *T = malloc(sizeof(double) * (size_t)M),
           *TS = malloc(sizeof(double) * (size_t)M), *a2 = malloc(sizeof(double) * (size_t)M),
           *z = malloc(sizeof(double) * (size_t)M), *da = malloc(sizeof(double) * (size_t)M);
    for (int64_t k = 0; k < M; k++) {
      m[k] = pow(10.0, (double)k / (double)(M - 1));
      sg[k] = cbrt(m[k]);
      n[k] = pow(m[k], -2.0) / (double)M;
    }
    gran_mixture *mix = NULL;
    BENCH_CHECK(gran_mixture_create(M, m, sg, n, &mix));
    BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
    double tau0, taus, t0 = bench_cpu_now();
    BENCH_CHECK(gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, T, &tau0));
    const double em = bench_cpu_now() - t0;
    t0 = bench_cpu_now();
    BENCH_CHECK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, TS, a2, &taus));
    const double es = bench_cpu_now() - t0;
    BENCH_CHECK(gran_theory_sonine_rates(mix, TS, a2, z, da));
    double dz = 0, dd = 0;
    for (int64_t k = 0; k < M; k++) {
      dz = fmax(dz, fabs(0.5 * z[k] * taus - 1));
      dd = fmax(dd, fabs(da[k] * taus));
    }
    const double shift = (TS[M - 1] / TS[0]) / (T[M - 1] / T[0]) - 1;
    printf("%8" PRId64 " | %10.4f %10.4f %7.1f | %10.1e %10.1e | %+12.4f %9.5f\n", M, em, es, es / fmax(em, 1e-6), dz,
           dd, shift, a2[0]);
    free(m), free(sg), free(n), free(T), free(TS), free(a2), free(z), free(da);
    gran_mixture_destroy(&mix);
  }
}

/* MSD by Eq. 4 at the four levels (CPU time; 41 log-spaced times 1e-3 .. 1e5 from the Maxwellian HCS, eps = 0.5):
 * the Fig. 3 ternary (m = 1, 100, 500, sigma = m^(1/3), equal n) and the geometric mixtures of section 5. Accuracy
 * against DSMC is t415's (docs/physics-sonine.md Sec. 5); here the cost and how far each level moves MSD_1(t = 100)
 * from the Maxwellian Eq. 4. */
static void bench_msd_levels(void) {
  printf("\n6. MSD by Eq. 4: Maxwellian, two moments (Maxwellian T), first and second Sonine trajectory (a2 in the\n"
         "   correlation); 41 times to 1e5 from the Maxwellian HCS, eps = 0.5 (CPU seconds; ratio to the Maxwellian;\n"
         "   shift = MSD_1(t = 100) / Maxwellian - 1)\n");
  printf("%10s | %9s | %9s %6s %8s | %9s %6s %8s | %9s %6s %8s\n", "mixture", "Maxw. [s]", "2 mom [s]", "ratio",
         "shift", "1st [s]", "ratio", "shift", "2nd [s]", "ratio", "shift");
  enum { NT = 41 };
  double t[NT + 1];
  for (int j = 0; j < NT; j++) t[j] = pow(10.0, -3.0 + 8.0 * j / (NT - 1));
  t[NT] = 100.0;
  const int64_t Ms[3] = {3, 10, 32};
  for (int i = 0; i < 3; i++) {
    const int64_t M = Ms[i];
    if (M > 10 && bench_quick()) {
      printf("%10" PRId64 " | (skipped: BENCH_QUICK)\n", M);
      continue;
    }
    double *m = malloc(sizeof(double) * (size_t)M), *sg = malloc(sizeof(double) * (size_t)M),
           *n = malloc(sizeof(double) * (size_t)M), *T = malloc(sizeof(double) * (size_t)M),
           *out = malloc(sizeof(double) * (size_t)(M * (NT + 1) * 4));
    for (int64_t k = 0; k < M; k++) {
      if (M == 3) {
        const double f3[3] = {1, 100, 500};
        m[k] = f3[k];
        n[k] = 0.1;
      } else {
        m[k] = pow(10.0, (double)k / (double)(M - 1));
        n[k] = pow(m[k], -2.0) / (double)M;
      }
      sg[k] = cbrt(m[k]);
    }
    gran_mixture *mix = NULL;
    BENCH_CHECK(gran_mixture_create(M, m, sg, n, &mix));
    BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
    double tau0;
    BENCH_CHECK(gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, T, &tau0));
    double sec[4];
    for (int l = 0; l < 4; l++) {
      double *o = out + (size_t)l * (size_t)(M * (NT + 1));
      const double t0 = bench_cpu_now();
      if (l == 0) BENCH_CHECK(gran_theory_msd(mix, T, NT + 1, t, 1e-8, o, NULL));
      if (l == 1) BENCH_CHECK(gran_theory_msd_approx(mix, GRAN_THEORY_SONINE, T, NT + 1, t, 1e-8, o, NULL));
      if (l == 2) BENCH_CHECK(gran_theory_msd_sonine(mix, T, NULL, 1, NT + 1, t, 1e-8, o, NULL));
      if (l == 3) BENCH_CHECK(gran_theory_msd_sonine2(mix, T, NULL, NULL, 1, NT + 1, t, 1e-8, o, NULL));
      sec[l] = bench_cpu_now() - t0;
    }
    char name[32];
    snprintf(name, sizeof name, M == 3 ? "Fig. 3" : "M = %" PRId64, M);
    printf("%10s | %9.3f", name, sec[0]);
    const double ref = out[NT * M];
    for (int l = 1; l < 4; l++)
      printf(" | %9.3f %6.1f %+8.4f", sec[l], sec[l] / fmax(sec[0], 1e-6),
             out[(size_t)l * (size_t)(M * (NT + 1)) + NT * M] / ref - 1);
    printf("\n");
    free(m), free(sg), free(n), free(T), free(out);
    gran_mixture_destroy(&mix);
  }
}

int main(void) {
  printf("b401-theory: kinetic theory numerics (accuracy versus cost). Timings are wall-clock on a shared\n"
         "machine: compare rows, not absolute values.\n");
  bench_ode();
  bench_msd();
  bench_tamsd();
  bench_hcs();
  bench_sonine();
  bench_msd_levels();
  printf("\npeak RSS %.1f MB\n", bench_peak_rss() / 1048576.0);
  return 0;
}
