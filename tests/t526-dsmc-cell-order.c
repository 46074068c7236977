/* t526-dsmc-cell-order.c - the cell selector's cell order (from 3e5 particles the particles of each
 * species are moved into cell order every few steps, src/dsmc/cell.cpp cell_reorder): the tests of
 * t520-t521 run below that size, so these repeat the checks that the order must not change at
 * N = 3.2e5 (binary mixture and one species):
 *  - positions, velocities and displacements move together: x(t) - R(t) mod L (R the displacement,
 *    the unwrapped path) is, as a set, the set of the initial positions (1e-7 L; a particle's
 *    velocity or displacement left behind by a move breaks it), species ranges stay as they were
 *    (gran_dsmc_species_offsets) and every particle of a range has that species;
 *  - Haff cooling of a binary mixture (m = 1, 2; eps = 0.8, 2 seeds each): T_1, T_2 and the collision
 *    counts against the low-rank selector within 4 standard errors (the seeds' spread plus the
 *    Poisson sqrt(count) of the counts; per-species T with sqrt(2/(3 N_k)) T), and the MSD of an
 *    elastic gas against the low-rank selector's (dt = tau/8, within 4 standard errors + 1 %: the
 *    time-step error measured in t520 is 0.1 % at tau/8);
 *  - a run to t = 30 in one go and a run written at t = 13.3, read back and continued end bit for
 *    bit (velocities, positions, displacements, counters, ledger), with displacements observed. */
#define _POSIX_C_SOURCE 200809L
#include <unistd.h>

#include "dsmc_util.h"

#include <string.h>

static const double kN = 0.01;

static gran_mixture *binary(double eps) {
  double m[2] = {1, 2}, s[2] = {1, 1.2599210498948732}, n[2] = {0.6 * kN, 0.4 * kN};
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  return mix;
}

static gran_dsmc *make_cell(gran_mixture *mix, int64_t N, uint64_t seed, double dt, int64_t cells, int observe) {
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, seed, (double)N / kN, observe);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.dt = dt;
  c.cells = cells;
  gran_dsmc *d = NULL;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d));
  return d;
}

static int cmp3(const void *a, const void *b) {
  const double *x = (const double *)a, *y = (const double *)b;
  for (int k = 0; k < 3; k++)
    if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
  return 0;
}

/* (x - R) mod L into [0, L) at a step time t, R = r + v (t - t_last) the displacement (values within
 * 1e-7 L below L go to the 0 side, like the start positions) */
static void starts(const gran_particles *p, double L, double t, double *out) {
  for (int64_t j = 0; j < p->n; j++)
    for (int k = 0; k < 3; k++) {
      const double R = p->r[3 * j + k] + p->v[3 * j + k] * (t - p->t_last[j]);
      double y = fmod(p->x[3 * j + k] - R, L);
      if (y < 0) y += L;
      if (y > L * (1 - 1e-7)) y -= L;
      out[3 * j + k] = y;
    }
}

static void test_moves_together(void **state) {
  (void)state;
  gran_mixture *mix = binary(0.8);
  const int64_t N = 320000;
  gran_dsmc *d = make_cell(mix, N, 3, 2.0, 25, GRAN_OBSERVE_DISPLACEMENT);
  const gran_particles *p;
  GRAN_ASSERT_OK(gran_dsmc_particles(d, &p));
  const int64_t n = p->n;
  assert_true(n >= 300000); /* the cell order is on */
  double *x0 = malloc(sizeof(double) * 3 * (size_t)n), *y = malloc(sizeof(double) * 3 * (size_t)n);
  memcpy(x0, p->x, sizeof(double) * 3 * (size_t)n);
  int64_t off0[3], off[3];
  GRAN_ASSERT_OK(gran_dsmc_species_offsets(d, off0));
  double L;
  GRAN_ASSERT_OK(gran_dsmc_cell_info(d, NULL, &L, NULL));
  qsort(x0, (size_t)n, 3 * sizeof(double), cmp3);
  GRAN_ASSERT_OK(gran_dsmc_advance(d, 100.0)); /* 50 steps (a step time: R is then x - x(0)): several reorders */
  assert_true(dsmc_collisions(d) > 10000);
  GRAN_ASSERT_OK(gran_dsmc_particles(d, &p));
  starts(p, L, 100.0, y);
  qsort(y, (size_t)n, 3 * sizeof(double), cmp3);
  double worst = 0;
  for (int64_t j = 0; j < 3 * n; j++) worst = fmax(worst, fabs(y[j] - x0[j]));
  if (!(worst < 1e-7 * L)) fprintf(stderr, "largest difference %g (L = %g)\n", worst, L);
  assert_true(worst < 1e-7 * L);
  GRAN_ASSERT_OK(gran_dsmc_species_offsets(d, off));
  assert_memory_equal(off, off0, sizeof off);
  for (int k = 0; k < 2; k++)
    for (int64_t j = off[k]; j < off[k + 1]; j++) assert_int_equal(p->species[j], k);
  free(x0);
  free(y);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  gran_mixture_destroy(&mix);
}

static void test_statistics(void **state) {
  (void)state;
  gran_mixture *mix = binary(0.8);
  const int64_t N = 320000;
  const double t = 120;
  enum { S = 2 };
  double T[2][2][S], C[2][S]; /* [selector][species][seed] */
  int64_t counts[2];
  for (int sel = 0; sel < 2; sel++)
    for (int s = 0; s < S; s++) {
      gran_dsmc *d;
      if (sel == 0) {
        d = make_cell(mix, N, 40 + s, 2.0, 25, 0);
      } else {
        gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 40 + s, (double)N / kN, 0);
        GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &d));
      }
      GRAN_ASSERT_OK(gran_dsmc_advance(d, t));
      double Tk[2];
      GRAN_ASSERT_OK(gran_dsmc_temperatures(d, Tk));
      GRAN_ASSERT_OK(gran_dsmc_counts(d, counts));
      T[sel][0][s] = Tk[0];
      T[sel][1][s] = Tk[1];
      C[sel][s] = (double)dsmc_collisions(d);
      GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
    }
  for (int k = 0; k < 2; k++) {
    double mc, sc, ml, sl;
    dsmc_mean_se(T[0][k], S, &mc, &sc);
    dsmc_mean_se(T[1][k], S, &ml, &sl);
    const double se = sqrt(2.0 / (3.0 * (double)counts[k] * S)) * ml; /* per run, averaged over S */
    GRAN_ASSERT_SIGMA(mc, ml, sqrt(2.0) * se, 4);
  }
  double mc, sc, ml, sl;
  dsmc_mean_se(C[0], S, &mc, &sc);
  dsmc_mean_se(C[1], S, &ml, &sl);
  GRAN_ASSERT_SIGMA(mc, ml, sqrt(2.0 * ml / S), 4);
  gran_mixture_destroy(&mix);

  /* MSD of an elastic gas at t = 10 tau, dt = tau/8, one species */
  mix = dsmc_mono(kN, 1.0);
  const int64_t N1 = 320000;
  const double tau = 1 / (4 * sqrt(M_PI) * kN), t1 = 10 * tau;
  double msd[2];
  for (int sel = 0; sel < 2; sel++) {
    gran_dsmc *d;
    if (sel == 0) {
      d = make_cell(mix, N1, 7, tau / 8, 25, GRAN_OBSERVE_DISPLACEMENT);
    } else {
      gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 7, (double)N1 / kN, GRAN_OBSERVE_DISPLACEMENT);
      GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &d));
    }
    GRAN_ASSERT_OK(gran_dsmc_advance(d, t1));
    GRAN_ASSERT_OK(gran_dsmc_msd(d, NULL, &msd[sel]));
    GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  }
  /* the squared displacement of one particle has a relative spread of about sqrt(5/3) at t >> tau
   * (3-D Gaussian: Var(R^2) = (2/3) <R^2>^2); 4 standard errors of the difference + 1 % */
  const double se = sqrt(2.0 / 3.0 / (double)N1) * msd[1];
  GRAN_ASSERT_SIGMA(msd[0], msd[1], sqrt(2.0) * se + 0.01 * msd[1] / 4, 4);
  gran_mixture_destroy(&mix);
}

static void test_resume(void **state) {
  (void)state;
  char path[256];
  snprintf(path, sizeof path, "/tmp/granary-t526-%ld.h5", (long)getpid());
  remove(path);
  gran_mixture *mix = binary(0.7);
  const int64_t N = 320000;
  gran_dsmc *a = make_cell(mix, N, 9, 0.6, 25, GRAN_OBSERVE_DISPLACEMENT);
  gran_dsmc *b = make_cell(mix, N, 9, 0.6, 25, GRAN_OBSERVE_DISPLACEMENT);
  gran_dsmc *r = NULL;
  GRAN_ASSERT_OK(gran_dsmc_advance(a, 30.0));
  GRAN_ASSERT_OK(gran_dsmc_advance(b, 13.3)); /* step 22 of 50: between two reorders */
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(b, path, "/engine"));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(path, "/engine", mix, &r));
  GRAN_ASSERT_OK(gran_dsmc_advance(r, 30.0));
  const gran_particles *pa, *pr;
  GRAN_ASSERT_OK(gran_dsmc_particles(a, &pa));
  GRAN_ASSERT_OK(gran_dsmc_particles(r, &pr));
  assert_int_equal(pa->n, pr->n);
  assert_memory_equal(pa->v, pr->v, sizeof(double) * 3 * (size_t)pa->n);
  assert_memory_equal(pa->x, pr->x, sizeof(double) * 3 * (size_t)pa->n);
  assert_memory_equal(pa->r, pr->r, sizeof(double) * 3 * (size_t)pa->n);
  gran_dsmc_stats sa, sr;
  GRAN_ASSERT_OK(gran_dsmc_get_stats(a, &sa));
  GRAN_ASSERT_OK(gran_dsmc_get_stats(r, &sr));
  assert_memory_equal(&sa, &sr, sizeof sa);
  assert_true(sa.collisions > 10000);
  double ea[3], er[3];
  GRAN_ASSERT_OK(gran_dsmc_energy(a, &ea[0], &ea[1], &ea[2]));
  GRAN_ASSERT_OK(gran_dsmc_energy(r, &er[0], &er[1], &er[2]));
  assert_memory_equal(ea, er, sizeof ea);
  double ma, mr;
  GRAN_ASSERT_OK(gran_dsmc_msd(a, NULL, &ma));
  GRAN_ASSERT_OK(gran_dsmc_msd(r, NULL, &mr));
  assert_true(ma == mr);
  gran_dsmc_destroy(&a);
  gran_dsmc_destroy(&b);
  gran_dsmc_destroy(&r);
  gran_mixture_destroy(&mix);
  remove(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_moves_together),
      cmocka_unit_test(test_statistics),
      cmocka_unit_test(test_resume),
  };
  return cmocka_run_group_tests_name("t526-dsmc-cell-order", tests, NULL, NULL);
}
