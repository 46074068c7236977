/* b402-aggregation.c - cost and results of the temperature-dependent Smoluchowski kinetics
 * (gran_theory_aggregation) against the number of sizes M, in one run: monomers n_1 = 0.1, T = 1,
 * eps = 0.9, eps_f = 0.5, rtol 1e-8; sticking only (E_agg = 2) and sticking + shattering
 * (E_agg = 1, E_frag = 3). Prints CPU-free wall time, mean size, T_1, T_10, overflow mass and the
 * mass error at t_end = 200. BENCH_QUICK=1: M = 100 only. */
#include "bench_util.h"

#include <math.h>

static void run(int M, double Ea, double Ef) {
  double *m = malloc(M * sizeof *m), *s = malloc(M * sizeof *s), *n = calloc(M, sizeof *n);
  double *T0 = calloc(M, sizeof *T0), *nn = malloc(M * sizeof *nn), *T = malloc(M * sizeof *T), ov[3];
  for (int k = 0; k < M; k++) {
    m[k] = k + 1;
    s[k] = cbrt(k + 1.0);
  }
  n[0] = 0.1;
  T0[0] = 1;
  gran_mixture *mix = NULL;
  BENCH_CHECK(gran_mixture_create(M, m, s, n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.9));
  const double t = 200;
  const double w0 = bench_now();
  BENCH_CHECK(gran_theory_aggregation(mix, T0, Ea, Ef, 0.5, 1, &t, 1e-8, nn, T, ov));
  const double wall = bench_now() - w0;
  double N = 0, mass = 0;
  for (int k = 0; k < M; k++) {
    N += nn[k];
    mass += (k + 1) * nn[k];
  }
  printf("%6d %6.1f %6.1f %9.3f %10.4g %10.4g %10.4g %10.3g %10.2e\n", M, Ea, Ef, wall, mass / N, T[0],
         M >= 10 ? T[9] : 0.0, ov[1] / 0.1, (mass + ov[1]) / 0.1 - 1);
  gran_mixture_destroy(&mix);
  free(m), free(s), free(n), free(T0), free(nn), free(T);
}

int main(void) {
  printf("b402-aggregation: Smoluchowski kinetics with temperatures, t_end = 200\n");
  printf("%6s %6s %6s %9s %10s %10s %10s %10s %10s\n", "M", "E_agg", "E_frag", "wall_s", "mean_size", "T_1",
         "T_10", "overflow", "mass_err");
  const int Ms[3] = {100, 300, 1000};
  const int nM = bench_quick() ? 1 : 3;
  for (int i = 0; i < nM; i++) {
    run(Ms[i], 2.0, INFINITY);
    run(Ms[i], 1.0, 3.0);
  }
  return 0;
}
