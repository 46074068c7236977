/* t531-dsmc-cell-streams.c - the cell selector with streams by cell (GRAN_CELL_STREAMS_CELLS: one
 * keyed stream per cell and step, each cell's particles in the order of their keys, exact global
 * sums, the cells collided in OpenMP threads):
 *  - the same state bit for bit (velocities, positions, displacements, counters, ledger, collision
 *    counts, trajectories) on 1, 2, 3 and 5 threads: one and three species, matrix and viscoelastic
 *    restitution, the thermostat and the bath, displacements, trajectories, and a gas of 3.2e5
 *    particles (the cell order moves the particles every 8 steps);
 *  - the initial state drawn cell by cell: the cell counts a multinomial sample (mean N/C, variance
 *    N/C (1 - 1/C), 4 standard errors of the sample variance), every species at its T0 (4 standard
 *    errors sqrt(2/(3 N_k)) T0), zero momentum, e_initial the kinetic energy (1e-12);
 *  - physics against the serial streams (the same algorithm with other random numbers, so the same
 *    expectations): a cooling binary mixture (eps = 0.8) over 8 seeds each, T_1, T_2 and the collisions
 *    within 4 standard errors of the difference; an elastic gas keeps its energy (1e-12) and collides
 *    at Eq. 35's rate (4 Poisson standard errors);
 *  - a run written at t1 (between two steps; on 2 threads), read back and continued on 1 and 3 threads
 *    ends bit for bit as the run in one go, and so does one whose particles (with their keys) were put
 *    in reverse order in the file (counters and ledger; the arrays then differ in order); a checkpoint whose keys do not match the positions is
 *    refused with GRAN_ERR_IO naming 'cell_keys';
 *  - refusals: streams = 7 (GRAN_ERR_ARG), aggregation with streams by cell (GRAN_ERR_UNSUPPORTED),
 *    and the scene key [cell] streams (its values, an unknown one, with e_agg). */
#define _POSIX_C_SOURCE 200809L
#include "io_test_util.h" /* first: it sets the feature-test macros */
#include <unistd.h>

#include <hdf5.h>

#include "dsmc_util.h"

#include <string.h>

static const double kN = 0.01;
static char g_path[256], g_edit[300];

static int setup(void **state) {
  (void)state;
  dsmc_ckpt_path(g_path, sizeof g_path, "t531");
  snprintf(g_edit, sizeof g_edit, "%s.edit", g_path);
  return 0;
}
static int teardown(void **state) {
  (void)state;
  remove(g_path);
  remove(g_edit);
  GRAN_ASSERT_OK(gran_set_threads(0));
  return 0;
}

static gran_mixture *mixture(int M, int model, double eps) {
  double m[3] = {1, 2, 3}, s[3] = {1, 1.26, 1.44}, n[3] = {0.6 * kN, 0.3 * kN, 0.1 * kN};
  if (M == 1) n[0] = kN;
  if (M == 2) n[0] = 0.6 * kN, n[1] = 0.4 * kN;
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, m, s, n, &mix));
  if (model == 0) GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  if (model == 1) {
    double e[9];
    for (int i = 0; i < M * M; i++) e[i] = 0.7 + 0.05 * (double)((i / M + i % M) % 3);
    GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(mix, e));
  }
  if (model == 2) GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.1));
  return mix;
}

static gran_dsmc *make(gran_mixture *mix, int64_t N, uint64_t seed, int observe, int64_t cells, double dt, double heat,
                       double bath, int streams) {
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, seed, (double)N / kN, observe);
  o.traj_per_species = 2;
  o.traj_dt = 0.7;
  o.traj_samples = 40;
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.cells = cells;
  c.dt = dt;
  c.heat_rate = heat;
  c.bath_density = bath;
  c.streams = streams;
  gran_dsmc *d = NULL;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d));
  return d;
}

static void test_threads(void **state) {
  (void)state;
  const struct {
    int M, model, observe;
    int64_t N, cells;
    double heat, bath, t;
  } cases[] = {
      {1, 0, 0, 12000, 10, 0, 0, 20},
      {3, 1, GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS, 20000, 10, 0, 0, 20},
      {2, 2, GRAN_OBSERVE_TRAJECTORIES, 20000, 8, 0, 0, 20},
      {2, 0, GRAN_OBSERVE_DISPLACEMENT, 20000, 10, 0.5, 0.001, 20},
      {2, 0, GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS, 320000, 25, 0.1, 0, 20},
  };
  const int threads[4] = {1, 2, 3, 5};
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    if (DSMC_ASAN && cases[k].N > 100000) continue;
    gran_mixture *mix = mixture(cases[k].M, cases[k].model, 0.8);
    gran_dsmc *ref = NULL;
    for (int q = 0; q < 4; q++) {
      GRAN_ASSERT_OK(gran_set_threads(threads[q]));
      gran_dsmc *d = make(mix, cases[k].N, 7, cases[k].observe, cases[k].cells, 0.5, cases[k].heat, cases[k].bath,
                          GRAN_CELL_STREAMS_CELLS);
      GRAN_ASSERT_OK(gran_dsmc_advance(d, cases[k].t));
      if (!ref) {
        ref = d;
        assert_true(dsmc_collisions(ref) > 1000);
        continue;
      }
      dsmc_assert_same_state(ref, d, cases[k].observe, cases[k].M, 1);
      if (cases[k].observe & GRAN_OBSERVE_COLLISION_COUNTS) {
        int64_t ca[9], cb[9];
        GRAN_ASSERT_OK(gran_dsmc_collision_counts(ref, ca));
        GRAN_ASSERT_OK(gran_dsmc_collision_counts(d, cb));
        assert_memory_equal(ca, cb, sizeof(int64_t) * (size_t)(cases[k].M * cases[k].M));
      }
      if (cases[k].observe & GRAN_OBSERVE_TRAJECTORIES) {
        int64_t na, sa, nb, sb;
        const double *xa, *xb;
        GRAN_ASSERT_OK(gran_dsmc_trajectories(ref, &na, &sa, &xa, NULL));
        GRAN_ASSERT_OK(gran_dsmc_trajectories(d, &nb, &sb, &xb, NULL));
        assert_true(na == nb && sa == sb && sa > 0);
        assert_memory_equal(xa, xb, sizeof(double) * 3 * (size_t)(na * sa));
      }
      gran_dsmc_destroy(&d);
    }
    double P[3], e, e0, ed;
    GRAN_ASSERT_OK(gran_dsmc_momentum(ref, P));
    GRAN_ASSERT_OK(gran_dsmc_energy(ref, &e, &e0, &ed));
    if (cases[k].bath == 0) /* momentum kept (the bath exchanges momentum with the gas) */
      for (int d = 0; d < 3; d++) GRAN_ASSERT_ABS(P[d], 0.0, 1e-9 * sqrt(e * (double)cases[k].N));
    gran_dsmc_destroy(&ref);
    gran_mixture_destroy(&mix);
  }
}

static void test_creation(void **state) {
  (void)state;
  gran_mixture *mix = mixture(3, 0, 0.8);
  const int64_t N = 60000, nc = 12, C = nc * nc * nc;
  double T0[3] = {1.0, 2.0, 0.5};
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 11, (double)N / kN, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.cells = nc;
  c.dt = 0.5;
  c.streams = GRAN_CELL_STREAMS_CELLS;
  gran_dsmc *d = NULL;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, T0, &o, &c, &d));
  const gran_particles *p;
  GRAN_ASSERT_OK(gran_dsmc_particles(d, &p));
  double L;
  GRAN_ASSERT_OK(gran_dsmc_cell_info(d, NULL, &L, NULL));
  int64_t *count = calloc((size_t)C, sizeof *count);
  for (int64_t j = 0; j < p->n; j++) {
    int64_t q = 0;
    for (int k = 0; k < 3; k++) {
      assert_true(p->x[3 * j + k] >= 0 && p->x[3 * j + k] < L);
      q = q * nc + (int64_t)floor(p->x[3 * j + k] / L * (double)nc);
    }
    count[q]++;
  }
  double s = 0, s2 = 0;
  for (int64_t q = 0; q < C; q++) {
    s += (double)count[q];
    s2 += (double)count[q] * (double)count[q];
  }
  const double mean = s / (double)C, var = (s2 - s * s / (double)C) / (double)(C - 1);
  const double lam = (double)p->n / (double)C, expect = lam * (1 - 1.0 / (double)C);
  GRAN_ASSERT_ABS(mean, lam, 1e-12 * lam);
  /* the sample variance of C Poisson-like counts: se^2 = (2 lam^2 + lam) / C (the fourth cumulant lam) */
  GRAN_ASSERT_SIGMA(var, expect, sqrt((2 * lam * lam + lam) / (double)C), 4);
  double T[3];
  int64_t Nk[3];
  GRAN_ASSERT_OK(gran_dsmc_temperatures(d, T));
  GRAN_ASSERT_OK(gran_dsmc_counts(d, Nk));
  for (int k = 0; k < 3; k++) GRAN_ASSERT_SIGMA(T[k], T0[k], sqrt(2.0 / (3.0 * (double)Nk[k])) * T0[k], 4);
  double P[3], e, e0, ed;
  GRAN_ASSERT_OK(gran_dsmc_momentum(d, P));
  GRAN_ASSERT_OK(gran_dsmc_energy(d, &e, &e0, &ed));
  for (int k = 0; k < 3; k++) GRAN_ASSERT_ABS(P[k], 0.0, 1e-12 * sqrt(2 * e * 3.0 * (double)p->n));
  GRAN_ASSERT_REL(e0, e, 1e-12);
  assert_true(ed == 0);
  free(count);
  gran_dsmc_destroy(&d);
  gran_mixture_destroy(&mix);
}

/* mean and standard error over seeds of T_1, T_2 and the collisions at t */
static void cooling(int streams, int nseed, double t, double mean[3], double se[3]) {
  gran_mixture *mix = mixture(2, 0, 0.8);
  const int64_t N = (int64_t)(20000 * dsmc_scale());
  double x[3][16];
  for (int r = 0; r < nseed; r++) {
    gran_dsmc *d = make(mix, N, 100 + (uint64_t)r + (streams ? 1000 : 0), 0, 10, 0.5, 0, 0, streams);
    GRAN_ASSERT_OK(gran_dsmc_advance(d, t));
    double T[2];
    GRAN_ASSERT_OK(gran_dsmc_temperatures(d, T));
    x[0][r] = T[0];
    x[1][r] = T[1];
    x[2][r] = (double)dsmc_collisions(d);
    gran_dsmc_destroy(&d);
  }
  for (int k = 0; k < 3; k++) dsmc_mean_se(x[k], nseed, &mean[k], &se[k]);
  gran_mixture_destroy(&mix);
}

static void test_physics(void **state) {
  (void)state;
  const int nseed = 8;
  double ma[3], sa[3], mb[3], sb[3];
  cooling(GRAN_CELL_STREAMS_CELLS, nseed, 60.0, ma, sa);
  cooling(GRAN_CELL_STREAMS_SERIAL, nseed, 60.0, mb, sb);
  assert_true(ma[0] < 0.8 && ma[1] < 0.8); /* it cooled */
  for (int k = 0; k < 3; k++) {
    /* the seeds' spread, and at least the single-run noise of T (sqrt(2/(3 N_k)) T) and the
     * Poisson noise of the counts, for a spread estimated from 8 seeds */
    const double floor_se = k < 2 ? sqrt(2.0 / (3.0 * 0.5 * 20000 * dsmc_scale())) * mb[k] : sqrt(mb[2]);
    const double se = sqrt(sa[k] * sa[k] + sb[k] * sb[k] + 2 * floor_se * floor_se / nseed);
    GRAN_ASSERT_SIGMA(ma[k], mb[k], se, 4);
  }
  /* elastic: energy kept, the collision rate of Eq. 35 */
  gran_mixture *mix = dsmc_mono(kN, 1.0);
  const int64_t N = (int64_t)(20000 * dsmc_scale());
  const double t = 100;
  double T0 = 1;
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 3, (double)N / kN, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.cells = 10;
  c.dt = 0.5;
  c.streams = GRAN_CELL_STREAMS_CELLS;
  gran_dsmc *d = NULL;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, &T0, &o, &c, &d));
  GRAN_ASSERT_OK(gran_dsmc_advance(d, t));
  double e, e0, ed;
  GRAN_ASSERT_OK(gran_dsmc_energy(d, &e, &e0, &ed));
  GRAN_ASSERT_REL(e, e0, 1e-12);
  double T;
  GRAN_ASSERT_OK(gran_dsmc_temperatures(d, &T));
  const double expect = 0.5 * (double)N * 4 * sqrt(M_PI) * kN * sqrt(T) * t;
  GRAN_ASSERT_SIGMA((double)dsmc_collisions(d), expect, sqrt(expect), 4);
  gran_dsmc_destroy(&d);
  gran_mixture_destroy(&mix);
}

/* Copy checkpoint src to dst with particles [0, n0) (one species) in reverse order: every
 * per-particle dataset (positions, velocities, displacements, clocks, keys), the checksum recomputed. */
static void reversed_copy(const char *src, const char *dst, int64_t n0) {
  hid_t f = io_copy_open(src, dst);
  const struct {
    const char *name;
    int width, is_int;
  } ds[] = {{"/engine/cell_x", 3, 0}, {"/engine/v", 3, 0}, {"/engine/r", 3, 0}, {"/engine/t_last", 1, 0},
            {"/engine/cell_keys", 1, 1}};
  for (size_t k = 0; k < sizeof ds / sizeof ds[0]; k++) {
    hid_t d = H5Dopen2(f, ds[k].name, H5P_DEFAULT);
    assert_true(d >= 0);
    hid_t sp = H5Dget_space(d);
    const hsize_t np = (hsize_t)H5Sget_simple_extent_npoints(sp);
    const hid_t ty = ds[k].is_int ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE;
    uint64_t *b = malloc(np * sizeof *b), tmp; /* 8-byte values either way */
    assert_true(H5Dread(d, ty, H5S_ALL, H5S_ALL, H5P_DEFAULT, b) >= 0);
    for (int64_t i = 0; i < n0 / 2; i++)
      for (int w = 0; w < ds[k].width; w++) {
        uint64_t *x = b + ds[k].width * i + w, *y = b + ds[k].width * (n0 - 1 - i) + w;
        tmp = *x;
        *x = *y;
        *y = tmp;
      }
    assert_true(H5Dwrite(d, ty, H5S_ALL, H5S_ALL, H5P_DEFAULT, b) >= 0);
    free(b);
    H5Sclose(sp);
    H5Dclose(d);
  }
  H5Fclose(f);
  io_refresh_crc(dst);
}

static void test_checkpoint(void **state) {
  (void)state;
  const int observe = GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS;
  const int64_t sizes[2] = {20000, DSMC_ASAN ? 20000 : 320000};
  for (int z = 0; z < 2; z++) {
    gran_mixture *mix = mixture(3, 0, 0.8);
    const int64_t cells = z ? 25 : 10;
    GRAN_ASSERT_OK(gran_set_threads(3));
    gran_dsmc *a = make(mix, sizes[z], 9, observe, cells, 0.5, 0.05, 0.0005, GRAN_CELL_STREAMS_CELLS);
    GRAN_ASSERT_OK(gran_dsmc_advance(a, 12.0));
    GRAN_ASSERT_OK(gran_set_threads(2));
    gran_dsmc *b = make(mix, sizes[z], 9, observe, cells, 0.5, 0.05, 0.0005, GRAN_CELL_STREAMS_CELLS);
    GRAN_ASSERT_OK(gran_dsmc_advance(b, 4.3)); /* between two steps; the cell order moved at step 8 */
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(b, g_path, "/engine"));
    for (int th = 1; th <= 3; th += 2) {
      GRAN_ASSERT_OK(gran_set_threads(th));
      gran_dsmc *r = NULL;
      GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(g_path, "/engine", mix, &r));
      dsmc_assert_same_state(b, r, observe, 3, 1);
      GRAN_ASSERT_OK(gran_dsmc_advance(r, 12.0));
      dsmc_assert_same_state(a, r, observe, 3, 1);
      gran_dsmc_destroy(&r);
    }
    { /* the particles in other places of the arrays (their keys with them): the same run */
      int64_t off[4];
      GRAN_ASSERT_OK(gran_dsmc_species_offsets(b, off));
      reversed_copy(g_path, g_edit, off[1]);
      gran_dsmc *r = NULL;
      GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(g_edit, "/engine", mix, &r));
      GRAN_ASSERT_OK(gran_dsmc_advance(r, 12.0));
      gran_dsmc_stats sa, sr;
      GRAN_ASSERT_OK(gran_dsmc_get_stats(a, &sa));
      GRAN_ASSERT_OK(gran_dsmc_get_stats(r, &sr));
      assert_memory_equal(&sa, &sr, sizeof sa);
      double ea[3], er[3];
      GRAN_ASSERT_OK(gran_dsmc_energy(a, &ea[0], &ea[1], &ea[2]));
      GRAN_ASSERT_OK(gran_dsmc_energy(r, &er[0], &er[1], &er[2]));
      assert_memory_equal(ea, er, sizeof ea);
      gran_dsmc_destroy(&r);
    }
    if (z == 0) { /* keys that do not match the positions */
      const struct {
        int64_t index;
        double value;
      } edits[] = {{0, -1.0}, {5, 4294967296.0 * 1000}, {7, 4294967296.0 * 3 + 4000}};
      for (size_t k = 0; k < sizeof edits / sizeof edits[0]; k++) {
        io_edit_copy(g_path, g_edit, "/engine/cell_keys", edits[k].index, edits[k].value, 1);
        gran_dsmc *r = NULL;
        GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_edit, "/engine", mix, &r), GRAN_ERR_IO);
        if (!strstr(gran_last_error_message(), "cell_keys"))
          fail_msg("edit %zu: message '%s' does not name cell_keys", k, gran_last_error_message());
        assert_null(r);
      }
    }
    gran_dsmc_destroy(&a);
    gran_dsmc_destroy(&b);
    gran_mixture_destroy(&mix);
  }
}

static void test_refusals(void **state) {
  (void)state;
  gran_mixture *mix = dsmc_mono(kN, 0.9);
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 3, 1000 / kN, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.dt = 0.5;
  c.streams = 7;
  gran_dsmc *d = NULL;
  GRAN_ASSERT_ERR(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'streams'"));
  c.streams = GRAN_CELL_STREAMS_CELLS;
  c.e_agg = 0.5;
  GRAN_ASSERT_ERR(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d), GRAN_ERR_UNSUPPORTED);
  assert_non_null(strstr(gran_last_error_message(), "'streams'"));
  assert_null(d);
  gran_mixture_destroy(&mix);
  const char *base = "[mixture]\nnspecies = 1\ndensity = [0.01]\n[restitution]\neps = 0.9\n[engine]\n"
                     "selector = \"cell\"\ncounts = [500]\nt_end = 1.0\n[cell]\ndt = 0.25\n";
  const struct {
    const char *extra;
    int want;
  } scenes[] = {{"", GRAN_CELL_STREAMS_SERIAL},
                {"streams = \"serial\"\n", GRAN_CELL_STREAMS_SERIAL},
                {"streams = \"cells\"\n", GRAN_CELL_STREAMS_CELLS},
                {"streams = \"lanes\"\n", -1},
                {"streams = \"cells\"\ne_agg = 0.5\n", -1}};
  for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; k++) {
    char text[1024];
    snprintf(text, sizeof text, "%s%s", base, scenes[k].extra);
    gran_scene *sc = NULL;
    const int st = gran_scene_parse(text, "t531.toml", &sc);
    if (scenes[k].want < 0) {
      assert_int_equal(st, GRAN_ERR_PARSE);
      assert_non_null(strstr(gran_last_error_message(), "streams"));
      continue;
    }
    GRAN_ASSERT_OK(st);
    gran_dsmc_cell_options got;
    GRAN_ASSERT_OK(gran_scene_dsmc_cell_options(sc, &got));
    assert_int_equal(got.streams, scenes[k].want);
    gran_scene_destroy(&sc);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_threads, setup, teardown),
      cmocka_unit_test_setup_teardown(test_creation, setup, teardown),
      cmocka_unit_test_setup_teardown(test_physics, setup, teardown),
      cmocka_unit_test_setup_teardown(test_checkpoint, setup, teardown),
      cmocka_unit_test_setup_teardown(test_refusals, setup, teardown),
  };
  return cmocka_run_group_tests_name("t531-dsmc-cell-streams", tests, NULL, NULL);
}
