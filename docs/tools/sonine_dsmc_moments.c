/* sonine_dsmc_moments.c - per-species velocity moments of granary's DSMC in the HCS (docs/physics-sonine.md
 * Sec. 4): a2_k = (3/5) <c^4>/<c^2>^2 - 1 and a3_k = 1 + 3 a2_k - (4/35) <c^6>/<c^2>^3 (c^2 = m v^2/(2T), 3-D),
 * window means one collision per particle apart, and optionally the species' velocities of the last window
 * (raw doubles, species after species) for docs/tools/sonine_exact_zeta.py.
 *   cc -O2 -Iinclude docs/tools/sonine_dsmc_moments.c -Lbuild -lgranary -lm -o /tmp/sdm
 *   LD_LIBRARY_PATH=build /tmp/sdm SETUP N_per_species seed warm_coll_per_particle windows [velocities.bin]
 * a4_k = <S4(c^2)>/<S4^2>_M (S4 the Sonine polynomial of degree 4, <S4^2>_M = 945/384) is printed beside them.
 * SETUP: binary (m = 1, 100), ternary (m = 1, 100, 500), mono (eps = 0.5); sigma = m^(1/3), n_k = 0.1, eps = 0.5,
 * start at the first Sonine HCS with <T> = 1; tracer: Fig. 5 of the source paper (m = 1, 100, sigma = m^(1/3),
 * n = 0.1, 0: N gas particles and `tracers` heavy tracers, default 2000), started at T_2/T_1 = `ratio` (default:
 * the first Sonine HCS), windows N collisions (all pairs) apart. Output: one line per window, the means with
 * the standard error over windows, and the means with the standard error of batch means over 10 windows.
 *   LD_LIBRARY_PATH=build /tmp/sdm tracer 100000 31 50 250 - 0 0.5 2000 500   # the Fig. 5 tracer from 500 */
#include <granary.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv) {
  if (argc < 6) {
    fprintf(stderr, "usage: %s binary|ternary|mono|tracer N seed warm windows [vel.bin] [selector 0|1] [eps] [tracers] "
                    "[ratio]\n", argv[0]);
    return 2;
  }
  const int tracer = !strcmp(argv[1], "tracer");
  int M = !strcmp(argv[1], "binary") || tracer ? 2 : !strcmp(argv[1], "ternary") ? 3 : 1;
  const double mm[3] = {1, 100, 500};
  double m[3], s[3], n[3];
  for (int k = 0; k < M; k++) m[k] = mm[k], s[k] = cbrt(mm[k]), n[k] = 0.1;
  if (tracer) n[1] = 0.0;
  const int64_t N = atoll(argv[2]);
  const uint64_t seed = strtoull(argv[3], NULL, 10);
  const double warm = atof(argv[4]);
  const int nw = atoi(argv[5]);
  const char *vel = argc > 6 && strcmp(argv[6], "-") ? argv[6] : NULL;
  const int selector = argc > 7 ? atoi(argv[7]) : GRAN_SELECTOR_LOWRANK;
  const double eps = argc > 8 ? atof(argv[8]) : 0.5;
  gran_mixture *mix = NULL;
  if (gran_mixture_create(M, m, s, n, &mix) || gran_mixture_set_restitution(mix, eps)) return 1;
  double T0[3], a2t[3], TM[3], tau0;
  if (gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, T0, a2t, &tau0)) return 1;
  if (gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, TM, NULL)) return 1;
  const int64_t ntr = tracer && argc > 9 ? atoll(argv[9]) : 2000;
  if (tracer && argc > 10) T0[1] = atof(argv[10]) * T0[0];
  printf("# theory Sonine: T_k/T_1 =");
  for (int k = 1; k < M; k++) printf(" %.5f", T0[k] / T0[0]);
  printf("  a2 =");
  for (int k = 0; k < M; k++) printf(" %.5f", a2t[k]);
  printf("  Maxwellian T_k/T_1 =");
  for (int k = 1; k < M; k++) printf(" %.5f", TM[k] / TM[0]);
  printf("\n");
  gran_dsmc_options o;
  gran_dsmc_options_default(&o);
  o.selector = selector;
  o.seed = seed;
  int64_t counts[3] = {N, tracer ? ntr : N, N};
  gran_dsmc *sim;
  if (gran_dsmc_create(mix, counts, T0, &o, &sim)) return 1;
  const int64_t Nt = tracer ? N : N * M;
  double *bat = calloc((size_t)(3 * 3 * (nw / 10 + 1)), sizeof(double)); /* batch sums of T_k/T_1, a2_k, a3_k */
  if (gran_dsmc_advance_collisions(sim, (int64_t)(warm * Nt))) return 1;
  double *v = malloc(sizeof(double) * 3 * (N > ntr ? N : ntr));
  double sr[3] = {0}, sr2[3] = {0}, sa2[3] = {0}, sa22[3] = {0}, sa3[3] = {0}, sa32[3] = {0}, sa4[3] = {0},
         sa42[3] = {0};
  for (int w = 0; w < nw; w++) {
    if (gran_dsmc_advance_collisions(sim, Nt)) return 1;
    double t, T[3];
    gran_dsmc_time(sim, &t);
    gran_dsmc_temperatures(sim, T);
    printf("%4d t = %10.4g", w, t);
    for (int k = 0; k < M; k++) {
      gran_dsmc_species_velocities(sim, k, v);
      const int64_t Nk = counts[k];
      double u[3] = {0, 0, 0};
      for (int64_t j = 0; j < Nk; j++)
        for (int d = 0; d < 3; d++) u[d] += v[3 * j + d] / Nk;
      double c2 = 0, c4 = 0, c6 = 0, c8 = 0;
      for (int64_t j = 0; j < Nk; j++) {
        double x = 0;
        for (int d = 0; d < 3; d++) x += (v[3 * j + d] - u[d]) * (v[3 * j + d] - u[d]);
        c2 += x, c4 += x * x, c6 += x * x * x, c8 += x * x * x * x;
      }
      c2 /= Nk, c4 /= Nk, c6 /= Nk, c8 /= Nk;
      /* moments of x = c^2 = v^2/(2 <v^2>/3): <x^p> = <v^(2p)> (3/(2 <v^2>))^p */
      const double h = 1.5 / c2, x1 = c2 * h, x2 = c4 * h * h, x3 = c6 * h * h * h, x4 = c8 * h * h * h * h;
      const double a4 = (x4 / 24 - 0.75 * x3 + 63.0 / 16 * x2 - 105.0 / 16 * x1 + 315.0 / 128) / (945.0 / 384);
      /* in c^2 = v^2/(2 <v^2>/3): <c^2> = 3/2, <c^4> = (15/4)(1 + a2), <c^6> = (105/8)(1 + 3 a2 - a3) */
      const double a2 = 0.6 * c4 / (c2 * c2) - 1, a3 = 1 + 3 * a2 - (9.0 / 35.0) * c6 / (c2 * c2 * c2);
      const double r = T[k] / T[0];
      sr[k] += r, sr2[k] += r * r, sa2[k] += a2, sa22[k] += a2 * a2, sa3[k] += a3, sa32[k] += a3 * a3;
      sa4[k] += a4, sa42[k] += a4 * a4;
      double *b = bat + 9 * (w / 10) + 3 * k;
      b[0] += r, b[1] += a2, b[2] += a3;
      printf("  T%d/T1 %.4f a2 %+.4f a3 %+.4f a4 %+.4f", k + 1, r, a2, a3, a4);
    }
    printf("\n");
    fflush(stdout);
  }
  printf("# mean (se over %d windows):", nw);
  for (int k = 0; k < M; k++) {
#define MS(S, S2) S[k] / nw, sqrt(fmax(S2[k] / nw - (S[k] / nw) * (S[k] / nw), 0) / (nw - 1))
    printf("  k=%d T/T1 %.4f (%.4f) a2 %+.5f (%.5f) a3 %+.5f (%.5f) a4 %+.5f (%.5f)", k + 1, MS(sr, sr2), MS(sa2, sa22),
           MS(sa3, sa32), MS(sa4, sa42));
  }
  printf("\n");
  const int nb = nw / 10;
  if (nb >= 2) {
    printf("# mean (se of %d batch means of 10 windows):", nb);
    for (int k = 0; k < M; k++) {
      printf("  k=%d", k + 1);
      for (int q = 0; q < 3; q++) {
        double sm = 0, sm2 = 0;
        for (int i = 0; i < nb; i++) {
          const double x = bat[9 * i + 3 * k + q] / 10;
          sm += x, sm2 += x * x;
        }
        const double mean = sm / nb;
        printf(" %s %.5f (%.5f)", q == 0 ? "T/T1" : q == 1 ? "a2" : "a3", mean,
               sqrt(fmax(sm2 / nb - mean * mean, 0) / (nb - 1)));
      }
    }
    printf("\n");
  }
  free(bat);
  if (vel) {
    FILE *f = fopen(vel, "wb");
    for (int k = 0; k < M; k++) {
      gran_dsmc_species_velocities(sim, k, v);
      fwrite(v, sizeof(double), 3 * counts[k], f);
    }
    fclose(f);
  }
  free(v);
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
  return 0;
}
