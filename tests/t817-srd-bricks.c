/* t817-srd-bricks.c - the brick layer of the GSRD domain decomposition (src/srd/bricks.h): one box
 * split into P virtual bricks of the binning grid in one process, particles and exact-sum
 * accumulators exchanged through the in-process transport.
 *  - bit identity: for every effect set (periodic 2-D and 3-D; eps < 1 with clamps; the cell
 *    thermostat; the global thermostat; Lees-Edwards 2-D and 3-D; walls with gravity and the
 *    vibrating wall, 2-D and 3-D) the gathered particles (key order), the cells' V and RNG states
 *    and the ledger (e_coll, e_ext, flux_kin, flux_coll, wall impulse, clamps, dt_max) of P = 2, 3,
 *    4, 6 bricks on even and uneven grids equal P = 1 bit for bit (memcmp), after 30 steps with a
 *    sort every 3 (so keys of several epochs) and with particles changing brick, also when each
 *    brick creates its own cells' particles and streams (momentum and energy all-reduced);
 *  - P = 1 bricks equal the plain engine in the decomposable mode (gran_srd_advance, creation =
 *    GRAN_SRD_CREATE_CELLS), also when advanced in two calls; 3 threads (P = 1 and the first
 *    split) equal 1;
 *  - physics that can fail: the particle number; the momentum (periodic, no thermostat, no
 *    gravity, no shear) conserved to 1e-10 (rounding of ~1e5 additions of O(1) velocities: ~1e-12); the energy
 *    ledger E - E0 = e_coll + e_ext to 1e-12 relative, for every effect set and split;
 *  - the decomposable engine's T at t = 10, 20, 30 of a cooling 3-D gas agrees with the serial
 *    engine's within 4 standard errors (6 seeds each; se of the difference of the means from the
 *    seeds' spread), and its ledger closes to 1e-12;
 *  - a sparse gas (most cells empty; bricks without particles) split as one brick;
 *  - S(k) of a split gas (srd_bricks_structure_factor_, all bricks in this process): the undivided
 *    engine's (gran_srd_structure_factor) bit for bit, for every split (3-D with eps < 1 after 30
 *    steps, 2-D Lees-Edwards); the initial
 *    ideal gas (multinomial cell counts) has S = 1 over all modes within 4 standard errors
 *    (se = sqrt(2 / modes): the half spectrum's modes come in conjugate pairs); walls and a number
 *    of shells outside [1, SRD_BRICKS_SK_MAX_BINS] are refused, naming them;
 *  - the observables of a split gas (srd_bricks_observe_, every effect set and split above): the
 *    decomposable engine's gran_srd_observe bit for bit, twice (the clamps since the last observation,
 *    the stress window reset between), with the velocity profile by layers of y (finite; a sheared
 *    gas's u_x rising from the bottom layer to the top), and the identities sum |v|^2 = d N theta_cells + N e_kin,
 *    theta_cells <= T, the closed ledger; sigma_rho of the initial gas (uniform and by cells, periodic
 *    and with walls) is the multinomial count's within 4 se;
 *  - the cell fields of snapshots (srd_bricks_fields_, every effect set and split above): the
 *    decomposable engine's gran_srd_fields bit for bit, which agree with a direct long-double
 *    computation from the particles (counts exact, means and temperatures to 1e-12), sum to N, to
 *    the momentum and to d N theta_cells;
 *  - bad arguments (serial creation, a pgrid entry beyond the grid or beyond dim) are refused
 *    naming them. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granary_test.h"
#include "srd/bricks.h"

static gran_srd_options base_opts(int dim) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = dim;
  o.cells[0] = dim == 2 ? 13 : 9;
  o.cells[1] = dim == 2 ? 10 : 7;
  o.cells[2] = dim == 2 ? 1 : 6;
  o.n0 = dim == 2 ? 8 : 5;
  o.dt = 0.5; /* a few tenths of a cell per step: particles cross the brick faces */
  o.alpha_deg = 130;
  o.seed = 817;
  o.threads = 1;
  o.sort_every = 3;
  o.creation = GRAN_SRD_CREATE_CELLS;
  return o;
}

enum { NSTEPS = 30 };

static int same(const void *a, const void *b, size_t bytes) { return memcmp(a, b, bytes) == 0; }

/* a and b equal bit for bit (particles, cells, ledger) */
static void assert_same_out(const srd_bricks_out *a, const srd_bricks_out *b, int dim, const char *what) {
  const size_t n = (size_t)a->n, nc = (size_t)a->ncell;
  assert_int_equal(a->n, b->n);
  assert_int_equal(a->ncell, b->ncell);
  const double *pa[6] = {a->x, a->y, a->z, a->vx, a->vy, a->vz}, *pb[6] = {b->x, b->y, b->z, b->vx, b->vy, b->vz};
  for (int q = 0; q < 6; ++q) {
    if (dim == 2 && (q == 2 || q == 5)) continue;
    if (!same(pa[q], pb[q], n * sizeof(double))) fail_msg("%s: particle array %d differs", what, q);
  }
  if (!same(a->V, b->V, nc * 3 * sizeof(double))) fail_msg("%s: the cells' V differ", what);
  if (!same(a->rng, b->rng, nc * 4 * sizeof(uint64_t))) fail_msg("%s: the cells' RNG states differ", what);
  const double la[9] = {a->time, a->e_initial, a->e_coll, a->e_ext, a->flux_kin, a->flux_coll, a->wall_impulse[0],
                        a->wall_impulse[1], a->wall_impulse[2]};
  const double lb[9] = {b->time, b->e_initial, b->e_coll, b->e_ext, b->flux_kin, b->flux_coll, b->wall_impulse[0],
                        b->wall_impulse[1], b->wall_impulse[2]};
  for (int q = 0; q < 9; ++q)
    if (!same(&la[q], &lb[q], sizeof(double))) fail_msg("%s: ledger term %d differs: %.17g vs %.17g", what, q, la[q], lb[q]);
  if (!same(&a->dt_max, &b->dt_max, sizeof(double))) fail_msg("%s: dt_max differs", what);
  assert_int_equal(a->step, b->step);
  assert_int_equal(a->clamped, b->clamped);
}

static double kinetic(const srd_bricks_out *r, int dim) {
  double e = 0;
  for (int64_t i = 0; i < r->n; ++i)
    e += 0.5 * (r->vx[i] * r->vx[i] + r->vy[i] * r->vy[i] + (dim == 3 ? r->vz[i] * r->vz[i] : 0.0));
  return e;
}

/* the physics of one run's gathered state */
static void check_physics(const gran_srd_options *o, const srd_bricks_out *r, const double P0[3]) {
  const int64_t N = (int64_t)floor(o->n0 * (double)(o->cells[0] * o->cells[1] * (o->dim == 3 ? o->cells[2] : 1)) + 0.5);
  assert_int_equal(r->n, N);
  assert_int_equal(r->step, NSTEPS);
  const double E = kinetic(r, o->dim);
  const double err = (r->e_initial + r->e_coll + r->e_ext - E) / r->e_initial;
  if (!(fabs(err) < 1e-12)) fail_msg("ledger: E - E0 - e_coll - e_ext = %.3g relative", err);
  const int conserving = o->thermostat == 0 && o->wall_axis < 0 && o->shear_rate == 0 && o->accel[0] == 0 && o->accel[1] == 0 && o->accel[2] == 0;
  if (conserving) {
    double P[3] = {0, 0, 0};
    for (int64_t i = 0; i < r->n; ++i) {
      P[0] += r->vx[i];
      P[1] += r->vy[i];
      if (o->dim == 3) P[2] += r->vz[i];
    }
    for (int k = 0; k < 3; ++k) GRAN_ASSERT_ABS(P[k], P0[k], 1e-10);
  }
}

/* the fields f (count, velocity [3], temperature of nbox cells) of state s against a direct
 * computation from its particles in long double: each cell's count exact, its mean velocity and
 * temperature within 1e-12 (relative to the cell's thermal speed); sum count = N; sum n V = the
 * observation's momentum and sum d n T = d N theta_cells, to 1e-12 relative */
static void check_fields(const gran_srd_options *o, gran_srd *s, const double *f, int64_t nbox, const gran_srd_obs *ob,
                         const char *name) {
  int64_t n;
  double *x[3], *v[3];
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x[0], &x[1], &x[2], &v[0], &v[1], &v[2]));
  const int d = o->dim;
  const int64_t L[3] = {o->cells[0], o->cells[1], d == 3 ? o->cells[2] : 1};
  long double *S = calloc((size_t)nbox * 5, sizeof(long double));
  int64_t *cn = calloc((size_t)nbox, sizeof(int64_t)), *ci = malloc(sizeof(int64_t) * (size_t)n);
  assert_non_null(S);
  assert_non_null(cn);
  assert_non_null(ci);
  for (int64_t i = 0; i < n; ++i) {
    int64_t c = 0, stride = 1;
    for (int k = 0; k < d; ++k) {
      int64_t q = (int64_t)floor(x[k][i] / o->a);
      if (q >= L[k]) q = L[k] - 1;
      c += q * stride;
      stride *= L[k];
    }
    ci[i] = c;
    cn[c]++;
    for (int k = 0; k < d; ++k) S[5 * c + k] += v[k][i];
  }
  for (int64_t i = 0; i < n; ++i)
    for (int k = 0; k < d; ++k) {
      const long double u = v[k][i] - S[5 * ci[i] + k] / cn[ci[i]];
      S[5 * ci[i] + 4] += u * u;
    }
  double N = 0, P[3] = {0, 0, 0}, Q = 0;
  for (int64_t c = 0; c < nbox; ++c) {
    if (f[c] != (double)cn[c]) fail_msg("%s: cell %lld holds %g particles in the fields, %lld counted", name, (long long)c, f[c], (long long)cn[c]);
    N += f[c];
    const double m = f[c], T = f[4 * nbox + c];
    if (m == 0) {
      if (T != 0 || f[nbox + 3 * c] != 0) fail_msg("%s: empty cell %lld has T %g, V_x %g", name, (long long)c, T, f[nbox + 3 * c]);
      continue;
    }
    const double Td = (double)(S[5 * c + 4] / (d * m)), vt = sqrt(Td) + 1e-300;
    for (int k = 0; k < 3; ++k) {
      const double V = f[nbox + 3 * c + k], Vd = k < d ? (double)(S[5 * c + k] / m) : 0.0;
      if (!(fabs(V - Vd) <= 1e-12 * (vt + fabs(Vd)))) fail_msg("%s: cell %lld V_%d %.17g, direct %.17g", name, (long long)c, k, V, Vd);
      P[k] += m * V;
    }
    if (!(fabs(T - Td) <= 1e-12 * Td + 1e-300)) fail_msg("%s: cell %lld T %.17g, direct %.17g", name, (long long)c, T, Td);
    Q += d * m * T;
  }
  assert_true(N == (double)n);
  for (int k = 0; k < 3; ++k)
    if (!(fabs(P[k] - ob->momentum[k]) <= 1e-12 * (fabs(ob->momentum[k]) + sqrt(2.0 * ob->energy * N))))
      fail_msg("%s: sum n V_%d = %.17g, the momentum %.17g", name, k, P[k], ob->momentum[k]);
  GRAN_ASSERT_REL(Q, d * N * ob->theta_cells, 1e-12);
  free(S);
  free(cn);
  free(ci);
}

/* gran_srd_observe of the decomposable engine against srd_bricks_observe_ of every split (all bricks
 * in this process), bit for bit: after 13 steps, then (the stress window reset, the clamps counted
 * since the first observation) after 17 more; on each the identities that can fail: the ledger
 * closes, sum |v|^2 = d N theta_cells + N e_kin (the unshifted cells whole: a cell's particles
 * split between bricks would break it), theta_cells <= T, the temperature is the report's */
static void check_observe(const gran_srd_options *o, const int (*grids)[3], int ngrid, const char *name) {
  gran_srd *s = NULL;
  gran_srd_obs p1, p2;
  const int64_t L1 = o->cells[1];
  double *u0 = malloc(sizeof(double) * 3 * (size_t)L1), *ub = malloc(sizeof(double) * 3 * (size_t)L1);
  assert_non_null(u0);
  assert_non_null(ub);
  GRAN_ASSERT_OK(gran_srd_create(o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 13));
  GRAN_ASSERT_OK(gran_srd_observe(s, &p1));
  GRAN_ASSERT_OK(gran_srd_stress_reset(s));
  GRAN_ASSERT_OK(gran_srd_advance(s, NSTEPS - 13));
  GRAN_ASSERT_OK(srd_cells_observe_(s, &p2, u0)); /* gran_srd_observe with the velocity profile */
  /* the cell fields (gran_srd_fields of the decomposable engine) against a direct computation */
  const int64_t nbox = o->cells[0] * o->cells[1] * (o->dim == 3 ? o->cells[2] : 1);
  double *fa = malloc(sizeof(double) * 5 * (size_t)nbox), *fb = malloc(sizeof(double) * 5 * (size_t)nbox);
  assert_non_null(fa);
  assert_non_null(fb);
  GRAN_ASSERT_OK(gran_srd_fields(s, fa, fa + nbox, fa + 4 * nbox));
  check_fields(o, s, fa, nbox, &p2, name);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  for (int64_t j = 0; j < L1; ++j)
    for (int q = 0; q < 3; ++q)
      if (!isfinite(u0[3 * j + q]) || (o->dim == 2 && q == 2 && u0[3 * j + q] != 0))
        fail_msg("%s: velocity profile layer %lld component %d: %g", name, (long long)j, q, u0[3 * j + q]);
  if (o->shear_rate != 0 && !(u0[3 * (L1 - 1)] > u0[0] + 0.1 * o->shear_rate * (double)L1))
    fail_msg("%s: the sheared gas's profile u_x: %g at the bottom layer, %g at the top", name, u0[0], u0[3 * (L1 - 1)]);
  for (int g = -2; g < ngrid; ++g) {
    static const int one[3] = {1, 1, 1};
    const int *pg = g < 0 ? one : grids[g];
    gran_srd_options ot = *o;
    if (g == -2) ot.threads = 3; /* the cells' sums over 3 threads */
    srd_bricks_state *st = NULL;
    gran_srd_obs b1, b2;
    GRAN_ASSERT_OK(srd_bricks_open_(&ot, pg, NULL, &st));
    GRAN_ASSERT_OK(srd_bricks_step_(st, 13));
    GRAN_ASSERT_OK(srd_bricks_observe_(st, &b1));
    GRAN_ASSERT_OK(srd_bricks_stress_reset_(st));
    GRAN_ASSERT_OK(srd_bricks_step_(st, NSTEPS - 13));
    GRAN_ASSERT_OK(srd_bricks_observe_profile_(st, &b2, ub));
    if (!same(u0, ub, sizeof(double) * 3 * (size_t)L1))
      fail_msg("%s: the velocity profile of %d x %d x %d bricks differs from the plain engine's", name, pg[0], pg[1], pg[2]);
    memset(fb, 0xff, sizeof(double) * 5 * (size_t)nbox);
    GRAN_ASSERT_OK(srd_bricks_fields_(st, fb, fb + nbox, fb + 4 * nbox));
    if (!same(fa, fb, sizeof(double) * 5 * (size_t)nbox))
      fail_msg("%s: the cell fields of %d x %d x %d bricks differ from the plain engine's", name, pg[0], pg[1], pg[2]);
    srd_bricks_rank_out rep;
    GRAN_ASSERT_OK(srd_bricks_report_(st, &rep));
    srd_bricks_close_(&st);
    const gran_srd_obs *pa[2] = {&p1, &p2}, *pb[2] = {&b1, &b2};
    for (int w = 0; w < 2; ++w) {
      const double *a = (const double *)pa[w], *b = (const double *)pb[w];
      for (size_t q = 0; q < sizeof(gran_srd_obs) / sizeof(double); ++q) /* 8-byte fields, no padding */
        if (!same(a + q, b + q, sizeof(double)))
          fail_msg("%s: observation %d of %d x %d x %d bricks on %d thread(s): word %zu is %.17g, the plain engine's %.17g",
                   name, w + 1, pg[0], pg[1], pg[2], (int)ot.threads, q, b[q], a[q]);
    }
    const double N = (double)b2.n, scale = 2.0 * b2.energy;
    if (!(fabs(b2.ledger_error) < 1e-12)) fail_msg("%s: ledger error %g", name, b2.ledger_error);
    if (!(fabs(scale - (o->dim * N * b2.theta_cells + N * b2.e_kin)) <= 1e-12 * scale))
      fail_msg("%s: sum |v|^2 = %.17g, d N theta + N e_kin = %.17g", name, scale, o->dim * N * b2.theta_cells + N * b2.e_kin);
    if (!(b2.theta_cells <= b2.temperature * (1 + 1e-12))) fail_msg("%s: theta %g > T %g", name, b2.theta_cells, b2.temperature);
    GRAN_ASSERT_REL(b2.temperature, rep.temperature, 1e-12);
    if (!(isfinite(b2.a2) && fabs(b2.a2) < 1 && b2.sigma_rho > 0)) fail_msg("%s: a2 %g, sigma_rho %g", name, b2.a2, b2.sigma_rho);
    if (o->shear_rate != 0 && !(b2.stress_xy != 0 && b2.stress_kin != 0)) fail_msg("%s: no stress", name);
  }
  free(u0);
  free(ub);
  free(fa);
  free(fb);
}

/* P = 1 bricks against the plain engine, then every split against P = 1 */
static void check_splits(const gran_srd_options *o, const int (*grids)[3], int ngrid, const char *name) {
  srd_bricks_out one, plain, two;
  const int p1[3] = {1, 1, 1};
  GRAN_ASSERT_OK(srd_bricks_run_(o, p1, NSTEPS, 0, &one));
  /* the plain engine in the decomposable mode, in one call and in two */
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(o, &s));
  double P0[3] = {0, 0, 0};
  {
    int64_t n;
    double *vx, *vy, *vz;
    GRAN_ASSERT_OK(gran_srd_particles(s, &n, NULL, NULL, NULL, &vx, &vy, &vz));
    for (int64_t i = 0; i < n; ++i) {
      P0[0] += vx[i];
      P0[1] += vy[i];
      if (o->dim == 3) P0[2] += vz[i];
    }
  }
  GRAN_ASSERT_OK(gran_srd_advance(s, NSTEPS));
  GRAN_ASSERT_OK(srd_bricks_gather_plain_(s, &plain));
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  assert_true(fabs(ob.ledger_error) < 1e-12);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  GRAN_ASSERT_OK(gran_srd_create(o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 13));
  GRAN_ASSERT_OK(gran_srd_advance(s, NSTEPS - 13));
  GRAN_ASSERT_OK(srd_bricks_gather_plain_(s, &two));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  char what[160];
  snprintf(what, sizeof what, "%s: P = 1 bricks vs the plain engine", name);
  assert_same_out(&one, &plain, o->dim, what);
  snprintf(what, sizeof what, "%s: P = 1 bricks vs the plain engine in two calls", name);
  assert_same_out(&one, &two, o->dim, what);
  check_physics(o, &one, P0);
  for (int g = 0; g < ngrid; ++g) {
    srd_bricks_out r;
    GRAN_ASSERT_OK(srd_bricks_run_(o, grids[g], NSTEPS, 0, &r));
    snprintf(what, sizeof what, "%s: %d x %d x %d bricks vs 1", name, grids[g][0], grids[g][1], grids[g][2]);
    assert_same_out(&one, &r, o->dim, what);
    check_physics(o, &r, P0);
    if (!(r.particles_sent > 0 && r.bytes_sent > 0)) fail_msg("%s: no particle changed brick", what);
    srd_bricks_out_free_(&r);
    /* each brick drawing its own cells' particles and streams: the same run */
    GRAN_ASSERT_OK(srd_bricks_run_(o, grids[g], NSTEPS, 1, &r));
    snprintf(what, sizeof what, "%s: %d x %d x %d bricks created in the bricks vs 1", name, grids[g][0], grids[g][1],
             grids[g][2]);
    assert_same_out(&one, &r, o->dim, what);
    srd_bricks_out_free_(&r);
  }
  /* the threads of a brick's loops change nothing */
  gran_srd_options o3 = *o;
  o3.threads = 3;
  for (int g = -1; g < 1; ++g) {
    srd_bricks_out r;
    GRAN_ASSERT_OK(srd_bricks_run_(&o3, g < 0 ? p1 : grids[0], NSTEPS, 0, &r));
    snprintf(what, sizeof what, "%s: %s bricks on 3 threads vs 1 brick on 1", name, g < 0 ? "1" : "the first split's");
    assert_same_out(&one, &r, o->dim, what);
    srd_bricks_out_free_(&r);
  }
  srd_bricks_out_free_(&one);
  srd_bricks_out_free_(&plain);
  srd_bricks_out_free_(&two);
  check_observe(o, grids, ngrid, name);
}

static const int grids3[][3] = {{2, 1, 1}, {3, 1, 1}, {1, 3, 1}, {2, 2, 1}, {2, 1, 2}, {1, 2, 2}, {4, 1, 1}, {3, 2, 1}};
static const int grids2[][3] = {{2, 1, 1}, {3, 1, 1}, {1, 2, 1}, {2, 2, 1}, {4, 1, 1}, {1, 4, 1}, {3, 2, 1}};
#define NG(a) ((int)(sizeof(a) / sizeof(a[0])))

static void test_periodic(void **state) {
  (void)state;
  gran_srd_options o = base_opts(3);
  check_splits(&o, grids3, NG(grids3), "periodic 3-D");
  o = base_opts(2);
  check_splits(&o, grids2, NG(grids2), "periodic 2-D");
}

static void test_dissipation(void **state) {
  (void)state;
  gran_srd_options o = base_opts(3);
  o.eps = 0.5;
  o.sigma = 0.5; /* kappa ~ 0.75 sigma^2 n0 sqrt(T) dt ~ 0.5: some cells clamp (eps_eff < 0) */
  o.dt = 1.0;
  srd_bricks_out r;
  const int p1[3] = {1, 1, 1};
  GRAN_ASSERT_OK(srd_bricks_run_(&o, p1, NSTEPS, 0, &r));
  if (!(r.clamped > 0)) fail_msg("the clamp case has no clamped cell (%lld)", (long long)r.clamped);
  assert_true(r.e_coll < 0);
  srd_bricks_out_free_(&r);
  check_splits(&o, grids3, NG(grids3), "eps < 1, clamps, 3-D");
  gran_srd_options o2 = base_opts(2);
  o2.eps = 0.8;
  o2.sigma = 0.1;
  check_splits(&o2, grids2, NG(grids2), "eps < 1, 2-D");
}

static void test_thermostats(void **state) {
  (void)state;
  gran_srd_options o = base_opts(2);
  o.thermostat = 1;
  o.T0 = 1.5;
  check_splits(&o, grids2, NG(grids2), "cell thermostat, 2-D");
  o = base_opts(3);
  o.thermostat = 2;
  o.eps = 0.7;
  o.sigma = 0.2;
  o.T0 = 0.7;
  check_splits(&o, grids3, NG(grids3), "global thermostat with eps < 1, 3-D");
}

static void test_lees_edwards(void **state) {
  (void)state;
  gran_srd_options o = base_opts(2);
  o.shear_rate = 0.07;
  check_splits(&o, grids2, NG(grids2), "Lees-Edwards, 2-D");
  o = base_opts(3);
  o.shear_rate = 0.05;
  o.eps = 0.9;
  o.sigma = 0.1;
  check_splits(&o, grids3, NG(grids3), "Lees-Edwards with eps < 1, 3-D");
  srd_bricks_out r;
  const int p1[3] = {1, 1, 1};
  GRAN_ASSERT_OK(srd_bricks_run_(&o, p1, NSTEPS, 0, &r));
  assert_true(r.flux_kin != 0 && r.flux_coll != 0);
  srd_bricks_out_free_(&r);
}

static void test_walls(void **state) {
  (void)state;
  gran_srd_options o = base_opts(2);
  o.wall_axis = 1;
  o.accel[1] = -0.05;
  o.vib_amp = 0.2;
  o.vib_omega = 0.5;
  o.wall_T = 1.0;
  check_splits(&o, grids2, NG(grids2), "walls, gravity, vibrating wall, 2-D");
  o = base_opts(3);
  o.wall_axis = 2;
  o.wall_rule = 2;
  o.accel[2] = -0.05;
  o.accel[0] = 0.01;
  o.vib_amp = 0.1;
  o.vib_omega = 1.0;
  o.eps = 0.9;
  o.sigma = 0.1;
  check_splits(&o, grids3, NG(grids3), "slip walls, gravity, vibrating wall, eps < 1, 3-D");
  srd_bricks_out r;
  const int p1[3] = {1, 1, 1};
  GRAN_ASSERT_OK(srd_bricks_run_(&o, p1, NSTEPS, 0, &r));
  assert_true(r.wall_impulse[2] != 0);
  srd_bricks_out_free_(&r);
}

/* the decomposable engine (exact sums, its own step code) cools as the serial engine does */
static void test_cooling(void **state) {
  (void)state;
  enum { S = 6, NT = 3 };
  double T[2][NT][S];
  for (int cr = 0; cr < 2; ++cr)
    for (int k = 0; k < S; ++k) {
      gran_srd_options o;
      GRAN_ASSERT_OK(gran_srd_options_default(&o));
      o.dim = 3;
      o.cells[0] = o.cells[1] = o.cells[2] = 12;
      o.n0 = 5;
      o.alpha_deg = 130;
      o.eps = 0.9;
      o.sigma = sqrt(0.02 / ((1 - o.eps * o.eps) * o.n0));
      o.seed = 900 + (uint64_t)k;
      o.threads = 1;
      o.creation = cr;
      gran_srd *s = NULL;
      GRAN_ASSERT_OK(gran_srd_create(&o, &s));
      for (int q = 0; q < NT; ++q) { /* T at t = 10, 20, 30 */
        GRAN_ASSERT_OK(gran_srd_advance(s, 10));
        gran_srd_obs ob;
        GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
        assert_true(fabs(ob.ledger_error) < 1e-12);
        T[cr][q][k] = ob.temperature;
      }
      GRAN_ASSERT_OK(gran_srd_destroy(&s));
    }
  for (int q = 0; q < NT; ++q) {
    double m[2], v[2];
    for (int cr = 0; cr < 2; ++cr) {
      m[cr] = v[cr] = 0;
      for (int k = 0; k < S; ++k) m[cr] += T[cr][q][k] / S;
      for (int k = 0; k < S; ++k) v[cr] += (T[cr][q][k] - m[cr]) * (T[cr][q][k] - m[cr]) / (S - 1);
    }
    if (q == NT - 1) assert_true(m[0] < 0.95 && m[0] > 0.3); /* the gas has cooled */
    GRAN_ASSERT_SIGMA(m[1], m[0], sqrt((v[0] + v[1]) / S), 4);
  }
}

/* a sparse gas (n0 = 0.05: most cells empty): bricks whose first rows, or all rows, hold no particle are
 * created and stepped like the others, the same run as one brick */
static void test_sparse(void **state) {
  (void)state;
  gran_srd_options o = base_opts(3);
  o.n0 = 0.05;
  const int p1[3] = {1, 1, 1}, grids[2][3] = {{3, 2, 2}, {4, 1, 3}};
  srd_bricks_out one;
  GRAN_ASSERT_OK(srd_bricks_run_(&o, p1, NSTEPS, 1, &one));
  assert_true(one.n > 0);
  for (int g = 0; g < 2; ++g) {
    srd_bricks_out r;
    GRAN_ASSERT_OK(srd_bricks_run_(&o, grids[g], NSTEPS, 1, &r));
    char what[96];
    snprintf(what, sizeof what, "sparse gas: %d x %d x %d bricks vs 1", grids[g][0], grids[g][1], grids[g][2]);
    assert_same_out(&one, &r, 3, what);
    srd_bricks_out_free_(&r);
  }
  srd_bricks_out_free_(&one);
}

enum { SK_BINS = 10 };

/* S(k) of the split gas after nsteps, into k, sk, count (SK_BINS each) */
static void split_sk(const gran_srd_options *o, const int pg[3], int64_t nsteps, double *k, double *sk, int64_t *count) {
  srd_bricks_state *st = NULL;
  GRAN_ASSERT_OK(srd_bricks_open_(o, pg, NULL, &st));
  GRAN_ASSERT_OK(srd_bricks_step_(st, nsteps));
  GRAN_ASSERT_OK(srd_bricks_structure_factor_(st, SK_BINS, k, sk, count));
  srd_bricks_close_(&st);
}

static void check_sk(const gran_srd_options *o, const int (*grids)[3], int ng, const char *what) {
  double k0[SK_BINS], s0[SK_BINS], kr[SK_BINS], sr[SK_BINS];
  int64_t c0[SK_BINS], cr[SK_BINS];
  gran_srd *e = NULL; /* the undivided engine */
  GRAN_ASSERT_OK(gran_srd_create(o, &e));
  GRAN_ASSERT_OK(gran_srd_advance(e, NSTEPS));
  GRAN_ASSERT_OK(gran_srd_structure_factor(e, SK_BINS, kr, sr, cr));
  gran_srd_destroy(&e);
  for (int g = 0; g < ng; ++g) {
    double k[SK_BINS], sk[SK_BINS];
    int64_t c[SK_BINS];
    split_sk(o, grids[g], NSTEPS, k, sk, c);
    if (g == 0) {
      memcpy(k0, k, sizeof k);
      memcpy(s0, sk, sizeof sk);
      memcpy(c0, c, sizeof c);
      int64_t modes = 0;
      for (int b = 0; b < SK_BINS; ++b) {
        assert_int_equal(c[b], cr[b]);
        modes += c[b];
        if (!same(&k[b], &kr[b], sizeof k[b]) || !same(&sk[b], &sr[b], sizeof sk[b]))
          fail_msg("%s: shell %d: k %.17g S %.17g against the undivided engine's %.17g %.17g", what, b, k[b], sk[b], kr[b],
                   sr[b]);
      }
      assert_true(modes > 100);
    } else if (!same(k, k0, sizeof k) || !same(sk, s0, sizeof sk) || !same(c, c0, sizeof c)) {
      fail_msg("%s: S(k) of %d x %d x %d bricks differs from %d x %d x %d", what, grids[g][0], grids[g][1], grids[g][2],
               grids[0][0], grids[0][1], grids[0][2]);
    }
  }
}

static void test_structure_factor(void **state) {
  (void)state;
  static const int g3[3][3] = {{1, 1, 1}, {2, 2, 1}, {3, 1, 2}}, g2[3][3] = {{1, 1, 1}, {3, 2, 1}, {1, 4, 1}};
  gran_srd_options o = base_opts(3);
  o.eps = 0.7;
  o.sigma = 0.6;
  check_sk(&o, g3, 3, "S(k), eps < 1, 3-D");
  o = base_opts(2);
  o.shear_rate = 0.07;
  check_sk(&o, g2, 3, "S(k), Lees-Edwards, 2-D");
  /* the initial ideal gas: multinomial counts, S = 1 for every k != 0 */
  o = base_opts(3);
  o.cells[0] = o.cells[1] = o.cells[2] = 16;
  const int p[3] = {2, 1, 2};
  double k[SK_BINS], sk[SK_BINS];
  int64_t c[SK_BINS];
  split_sk(&o, p, 0, k, sk, c);
  double sum = 0;
  int64_t modes = 0;
  for (int b = 0; b < SK_BINS; ++b) {
    sum += sk[b] * (double)c[b];
    modes += c[b];
  }
  assert_int_equal(modes, 16 * 16 * 16 - 1);
  const double mean = sum / (double)modes, se = sqrt(2.0 / (double)modes);
  if (!(fabs(mean - 1.0) <= 4 * se)) fail_msg("S of the ideal gas: %.6f, not 1 within 4 se (%.4f)", mean, se);
  /* refusals */
  srd_bricks_state *st = NULL;
  GRAN_ASSERT_OK(srd_bricks_open_(&o, p, NULL, &st));
  GRAN_ASSERT_ERR(srd_bricks_structure_factor_(st, 0, k, sk, c), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'nbins'"));
  double big[SRD_BRICKS_SK_MAX_BINS + 1];
  int64_t bigc[SRD_BRICKS_SK_MAX_BINS + 1];
  GRAN_ASSERT_ERR(srd_bricks_structure_factor_(st, SRD_BRICKS_SK_MAX_BINS + 1, big, big, bigc), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'nbins'"));
  srd_bricks_close_(&st);
  o = base_opts(2);
  o.wall_axis = 1;
  const int p2[3] = {2, 1, 1};
  GRAN_ASSERT_OK(srd_bricks_open_(&o, p2, NULL, &st));
  GRAN_ASSERT_ERR(srd_bricks_structure_factor_(st, SK_BINS, k, sk, c), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "periodic"));
  srd_bricks_close_(&st);
}

/* sigma_rho of the initial gas (both creations: uniform, and multinomial by cells) against the
 * variance of a multinomial count, n0 (1 - 1 / cells), within 4 se (se of a sample variance of
 * near-Poisson counts: sqrt((n0 + 2 n0^2) / cells)); with walls the binning grid's extra layer
 * holds no cell of the box and must not be counted as empty cells (it would add n0^2 / (L + 1)) */
static void test_sigma_rho(void **state) {
  (void)state;
  for (int walls = 0; walls < 2; ++walls)
    for (int cr = 0; cr < 2; ++cr) {
      gran_srd_options o = base_opts(2);
      o.cells[0] = o.cells[1] = 30;
      o.n0 = 10;
      o.wall_axis = walls ? 1 : -1;
      o.creation = cr ? GRAN_SRD_CREATE_CELLS : GRAN_SRD_CREATE_SERIAL;
      gran_srd *s = NULL;
      gran_srd_obs ob;
      GRAN_ASSERT_OK(gran_srd_create(&o, &s));
      GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
      gran_srd_destroy(&s);
      const double nb = 900, var = ob.sigma_rho * ob.sigma_rho; /* a = 1 */
      GRAN_ASSERT_SIGMA(var, o.n0 * (1 - 1 / nb), sqrt((o.n0 + 2 * o.n0 * o.n0) / nb), 4);
    }
}

static void test_bad_args(void **state) {
  (void)state;
  gran_srd_options o = base_opts(3);
  srd_bricks_out r;
  const int too_many[3] = {10, 1, 1}, beyond_dim[3] = {1, 1, 2}, zero[3] = {0, 1, 1}, ok[3] = {2, 1, 1};
  GRAN_ASSERT_ERR(srd_bricks_run_(&o, too_many, 1, 0, &r), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'pgrid[0]'"));
  GRAN_ASSERT_ERR(srd_bricks_run_(&o, zero, 1, 0, &r), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'pgrid[0]'"));
  gran_srd_options o2 = base_opts(2);
  GRAN_ASSERT_ERR(srd_bricks_run_(&o2, beyond_dim, 1, 0, &r), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'pgrid[2]'"));
  o.creation = GRAN_SRD_CREATE_SERIAL;
  GRAN_ASSERT_ERR(srd_bricks_run_(&o, ok, 1, 0, &r), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'creation'"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_periodic),    cmocka_unit_test(test_dissipation), cmocka_unit_test(test_thermostats),
      cmocka_unit_test(test_lees_edwards), cmocka_unit_test(test_walls),      cmocka_unit_test(test_cooling),
      cmocka_unit_test(test_sparse), cmocka_unit_test(test_structure_factor), cmocka_unit_test(test_sigma_rho),
      cmocka_unit_test(test_bad_args),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
