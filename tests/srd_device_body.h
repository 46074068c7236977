/* srd_device_body.h - GSRD test bodies run on every device (as SUNDIALS' test_nvector.h):
 * tests/t890-srd-device.c runs them on the host reference of the device algorithm (device =
 * GRAN_SRD_DEVICE_REFERENCE) in `make test`, tests/gpu/t850-srd-gpu.c on the GPU (CUDA) in
 * `make test-gpu`, each against the CPU engine or the reference.
 *
 * Two levels:
 *  - sdb_*: the launchers of cuda/srd_cuda.h directly (gran_srd_launchers_get): a periodic box,
 *    conservation of N, momentum and energy.
 *  - sde_*: the engine through the public API (gran_srd_create with options.device), one scene per
 *    effect (periodic, eps < 1 with clamps, thermostat, no-slip walls with gravity and a vibrating
 *    wall, slip walls, Lees-Edwards with dissipation, body force), two devices side by side: every
 *    position and velocity, the energy ledger, the Lees-Edwards stress, the wall impulse, the clamp
 *    counts, the observables, S(k) and a checkpoint that moves the run from one device to the
 *    other. */
#ifndef GRAN_SRD_DEVICE_BODY_H
#define GRAN_SRD_DEVICE_BODY_H

#include <stdio.h>

#include "granary_test.h"
#include "srd_cuda.h"

/* ---- launcher level ------------------------------------------------------------------------- */

typedef struct sdb_state {
  int device;              /* GRAN_SRD_DEVICE_REFERENCE or GRAN_SRD_DEVICE_CUDA */
  const gran_srd_launchers *L;
  gran_cuda_srd_params p;
  int64_t ncell;
  double *x[3], *v[3];     /* host copy */
  gran_rng *cell_rng;
  gran_rng shift_rng;      /* stream 0 of the seed: the grid shift */
  gran_cuda_srd *dev;
  int64_t nclamp;
} sdb_state;

/* periodic box of L^dim cells, n0 particles per cell, temperature 1 around the flow u. */
static void sdb_init(sdb_state *st, int device, int dim, int64_t L, int n0, double alpha_deg, double eps,
                     int precision, uint64_t seed) {
  memset(st, 0, sizeof *st);
  st->device = device;
  st->L = gran_srd_launchers_get(device);
  assert_non_null(st->L);
  srd_geom *g = &st->p.geom;
  g->dim = dim;
  g->wall_axis = -1;
  g->a = 1.0;
  g->inv_a = 1.0;
  for (int k = 0; k < 3; ++k) {
    g->L[k] = g->nc[k] = k < dim ? L : 1;
    g->box[k] = (double)g->L[k];
  }
  st->ncell = g->nc[0] * g->nc[1] * g->nc[2];
  st->p.n = st->ncell * n0;
  st->p.precision = precision;
  st->p.fx = eps < 1.0 ? SRD_FX_EPS : 0;
  st->p.dt = 0.1;
  st->p.alpha = alpha_deg * 3.14159265358979323846 / 180.0;
  st->p.coef = (1.0 - eps * eps) * 1.0 * st->p.dt; /* sigma = 1 */
  const double u[3] = {0.3, -0.2, 0.1};
  gran_rng r;
  GRAN_ASSERT_OK(gran_rng_stream(seed, 1u << 30, &r)); /* initial condition: its own stream */
  for (int k = 0; k < 3; ++k) {
    st->x[k] = calloc((size_t)st->p.n, sizeof(double));
    st->v[k] = calloc((size_t)st->p.n, sizeof(double));
    assert_non_null(st->x[k]);
    assert_non_null(st->v[k]);
  }
  for (int64_t i = 0; i < st->p.n; ++i)
    for (int k = 0; k < dim; ++k) {
      st->x[k][i] = g->box[k] * srd_rng_uniform(&r);
      st->v[k][i] = u[k] + srd_rng_normal(&r);
    }
  st->cell_rng = malloc(sizeof(gran_rng) * (size_t)st->ncell);
  assert_non_null(st->cell_rng);
  GRAN_ASSERT_OK(gran_rng_stream(seed, 0, &st->shift_rng));
  gran_rng c = st->shift_rng;
  for (int64_t i = 0; i < st->ncell; ++i) { /* cell i owns stream i + 1: consecutive jumps */
    GRAN_ASSERT_OK(gran_rng_jump(&c));
    st->cell_rng[i] = c;
  }
  GRAN_ASSERT_OK(st->L->create(&st->p, (const double *const *)st->x, (const double *const *)st->v, st->cell_rng,
                               &st->dev));
  /* the host copy holds what the device stores (float: rounded) */
  GRAN_ASSERT_OK(st->L->download(st->dev, st->x, st->v, NULL, NULL));
}

static void sdb_free(sdb_state *st) {
  for (int k = 0; k < 3; ++k) {
    free(st->x[k]);
    free(st->v[k]);
  }
  free(st->cell_rng);
  GRAN_ASSERT_OK(st->L->destroy(&st->dev));
}

/* nsteps steps; the host copy x, v, cell_rng is current afterwards. */
static void sdb_run(sdb_state *st, int nsteps) {
  for (int t = 0; t < nsteps; ++t) {
    double s[3] = {0, 0, 0};
    for (int k = 0; k < st->p.geom.dim; ++k) s[k] = st->p.geom.a * srd_rng_uniform(&st->shift_rng);
    GRAN_ASSERT_OK(st->L->step(st->dev, &st->p.geom, s, &st->nclamp, NULL));
  }
  GRAN_ASSERT_OK(st->L->download(st->dev, st->x, st->v, NULL, st->cell_rng));
}

/* total momentum and kinetic energy from the host copy, in long double */
static void sdb_totals(const sdb_state *st, double mom[3], double *ekin) {
  long double m[3] = {0, 0, 0}, e = 0;
  for (int64_t i = 0; i < st->p.n; ++i)
    for (int k = 0; k < st->p.geom.dim; ++k) {
      m[k] += st->v[k][i];
      e += 0.5L * (long double)st->v[k][i] * st->v[k][i];
    }
  for (int k = 0; k < 3; ++k) mom[k] = (double)m[k];
  *ekin = (double)e;
}

/* Conservation for eps = 1: momentum and energy to rounding (double: 1e-12 relative; float storage:
 * 1e-5, about 100 ulp of float over the run), positions inside the box. eps < 1: momentum kept,
 * energy falls every step. */
static void sdb_body_conservation(int device, int dim, int precision, double eps) {
  sdb_state st;
  sdb_init(&st, device, dim, dim == 3 ? 8 : 16, 10, 130.0, eps, precision, 2024);
  double m0[3], e0, m1[3], e1;
  sdb_totals(&st, m0, &e0);
  const double tol = precision ? 1e-5 : 1e-12;
  const char *who = st.L->name;
  double eprev = e0;
  for (int rep = 0; rep < 5; ++rep) {
    sdb_run(&st, 4);
    sdb_totals(&st, m1, &e1);
    const double pscale = sqrt(2.0 * e0); /* momentum scale: |p| can be small in one component */
    for (int k = 0; k < dim; ++k)
      if (fabs(m1[k] - m0[k]) > tol * pscale * sqrt((double)st.p.n))
        fail_msg("%s dim %d: momentum[%d] %.17g -> %.17g", who, dim, k, m0[k], m1[k]);
    if (eps == 1.0) {
      if (!gran_test_rel_ok(e1, e0, tol)) fail_msg("%s dim %d: energy %.17g -> %.17g", who, dim, e0, e1);
    } else {
      if (!(e1 < eprev)) fail_msg("%s eps = %g: energy did not fall (%.17g -> %.17g)", who, eps, eprev, e1);
    }
    eprev = e1;
  }
  for (int64_t i = 0; i < st.p.n; ++i)
    for (int k = 0; k < dim; ++k)
      if (!(st.x[k][i] >= 0.0 && st.x[k][i] < st.p.geom.box[k])) fail_msg("%s: particle outside the box", who);
  sdb_free(&st);
}

/* Rotation invariants, cell by cell: one step with a negligible streaming (dt = 1e-12), so that
 * every particle stays in its cell of the shifted grid; for eps = 1 each cell's momentum and kinetic
 * energy are unchanged (1e-12 relative to the cell's scale), for eps < 1 the momentum is and the
 * energy does not rise. Also the thermal speeds |v - V| of a cell: their sum of squares is kept. */
static void sdb_body_cell_invariants(int device, int dim, double eps) {
  sdb_state st;
  sdb_init(&st, device, dim, dim == 3 ? 6 : 12, 10, 130.0, eps, 0, 99);
  st.p.dt = 1e-12;
  GRAN_ASSERT_OK(st.L->destroy(&st.dev)); /* again with the tiny dt */
  GRAN_ASSERT_OK(st.L->create(&st.p, (const double *const *)st.x, (const double *const *)st.v, st.cell_rng, &st.dev));
  const double s[3] = {0.37, 0.81, 0.05};
  const int64_t nc = st.ncell;
  double *m0 = calloc((size_t)nc * 4, sizeof(double)), *m1 = calloc((size_t)nc * 4, sizeof(double));
  assert_true(m0 && m1);
  for (int pass = 0; pass < 2; ++pass) {
    double *m = pass ? m1 : m0;
    for (int64_t i = 0; i < st.p.n; ++i) {
      const double p[3] = {st.x[0][i], st.x[1][i], dim == 3 ? st.x[2][i] : 0.0};
      double dvx;
      const int64_t c = srd_bin(&st.p.geom, s, p, &dvx);
      for (int k = 0; k < dim; ++k) {
        m[4 * c + k] += st.v[k][i];
        m[4 * c + 3] += 0.5 * st.v[k][i] * st.v[k][i];
      }
    }
    if (pass == 0) {
      GRAN_ASSERT_OK(st.L->step(st.dev, &st.p.geom, s, NULL, NULL));
      GRAN_ASSERT_OK(st.L->download(st.dev, st.x, st.v, NULL, NULL));
    }
  }
  int64_t cells_checked = 0;
  for (int64_t c = 0; c < nc; ++c) {
    const double scale = sqrt(2.0 * m0[4 * c + 3]) + 1e-300;
    for (int k = 0; k < dim; ++k)
      if (!(fabs(m1[4 * c + k] - m0[4 * c + k]) <= 1e-11 * scale))
        fail_msg("%s cell %lld: momentum[%d] %.17g -> %.17g", st.L->name, (long long)c, k, m0[4 * c + k], m1[4 * c + k]);
    if (eps == 1.0 && !(fabs(m1[4 * c + 3] - m0[4 * c + 3]) <= 1e-11 * m0[4 * c + 3]))
      fail_msg("%s cell %lld: energy %.17g -> %.17g", st.L->name, (long long)c, m0[4 * c + 3], m1[4 * c + 3]);
    if (eps < 1.0 && !(m1[4 * c + 3] <= m0[4 * c + 3] * (1 + 1e-12)))
      fail_msg("%s cell %lld: energy rose %.17g -> %.17g", st.L->name, (long long)c, m0[4 * c + 3], m1[4 * c + 3]);
    cells_checked += m0[4 * c + 3] > 0;
  }
  assert_true(cells_checked > nc / 2);
  free(m0);
  free(m1);
  sdb_free(&st);
}

/* ---- engine level --------------------------------------------------------------------------- */

enum { SDE_PERIODIC, SDE_DISSIP, SDE_THERMO, SDE_NOSLIP, SDE_SLIP, SDE_SHEAR, SDE_BODYFORCE, SDE_GTHERMO, SDE_NSCENES };
static const char *const sde_names[SDE_NSCENES] = {"periodic 3-D",
                                                   "2-D eps 0.9 (clamps)",
                                                   "3-D thermostat eps 0.8",
                                                   "3-D no-slip walls, gravity, vibrating wall",
                                                   "2-D slip walls, gravity",
                                                   "2-D Lees-Edwards eps 0.95",
                                                   "3-D Lees-Edwards + body force",
                                                   "3-D global thermostat, Lees-Edwards"};

/* the options of one scene (small boxes: n0 = 10, 8^3 or 16^2 cells) */
static void sde_options(int scene, gran_srd_options *o) {
  GRAN_ASSERT_OK(gran_srd_options_default(o));
  o->dim = 3;
  o->cells[0] = o->cells[1] = o->cells[2] = 8;
  o->n0 = 10;
  o->dt = 0.1;
  o->alpha_deg = 130.0;
  o->seed = 4242 + (uint64_t)scene;
  o->sort_every = 7; /* sorted during the comparison: the device's order must be the engine's */
  o->threads = 1;
  switch (scene) {
  case SDE_DISSIP:
    o->dim = 2;
    o->cells[0] = o->cells[1] = 16;
    o->eps = 0.9;
    o->sigma = 1.0;
    o->dt = 0.5; /* large: dense hot cells clamp (eps_eff < 0) at first */
    break;
  case SDE_THERMO:
    o->eps = 0.8;
    o->sigma = 0.3;
    o->thermostat = 1;
    o->T0 = 0.5;
    break;
  case SDE_NOSLIP:
    o->wall_axis = 2;
    o->wall_rule = 1;
    o->accel[2] = -0.05;
    o->vib_amp = 0.02;
    o->vib_omega = 2.0;
    o->wall_T = 0.7;
    break;
  case SDE_SLIP:
    o->dim = 2;
    o->cells[0] = o->cells[1] = 16;
    o->wall_axis = 1;
    o->wall_rule = 2;
    o->accel[1] = -0.1;
    break;
  case SDE_SHEAR:
    o->dim = 2;
    o->cells[0] = o->cells[1] = 16;
    o->shear_rate = 0.05;
    o->eps = 0.95;
    o->sigma = 0.5;
    break;
  case SDE_BODYFORCE:
    o->shear_rate = 0.03;
    o->accel[0] = 0.01;
    o->accel[2] = 0.005;
    o->alpha_deg = 90.0;
    break;
  case SDE_GTHERMO: /* the viscosity set-up: the shear heats, the global thermostat holds T0 */
    o->shear_rate = 0.1;
    o->thermostat = 2;
    o->T0 = 0.8;
    break;
  default:
    break;
  }
}

static int64_t sde_n(gran_srd *s) {
  int64_t n;
  double *p[6];
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &p[0], &p[1], &p[2], &p[3], &p[4], &p[5]));
  return n;
}

/* largest |difference| of positions and velocities of two runs of the same scene */
static double sde_particles_diff(gran_srd *a, gran_srd *b, int dim) {
  int64_t na, nb;
  double *pa[6], *pb[6];
  GRAN_ASSERT_OK(gran_srd_particles(a, &na, &pa[0], &pa[1], &pa[2], &pa[3], &pa[4], &pa[5]));
  GRAN_ASSERT_OK(gran_srd_particles(b, &nb, &pb[0], &pb[1], &pb[2], &pb[3], &pb[4], &pb[5]));
  assert_int_equal(na, nb);
  double dmax = 0.0;
  for (int q = 0; q < 6; ++q) {
    if (dim == 2 && (q == 2 || q == 5)) continue;
    for (int64_t i = 0; i < na; ++i) {
      const double d = fabs(pa[q][i] - pb[q][i]);
      if (!(d <= dmax)) dmax = d; /* NaN propagates */
    }
  }
  return dmax;
}

/* |a - b| <= tol * scale, with a message naming the quantity */
static void sde_close(const char *scene, const char *what, double a, double b, double tol, double scale) {
  if (!(fabs(a - b) <= tol * scale))
    fail_msg("%s: %s %.17g vs %.17g (tolerance %.3g x %.3g)", scene, what, a, b, tol, scale);
}

/* Every observable of two runs agrees: exact = 1 for two runs of the same arithmetic in the same
 * precision (tolerance tol relative to the natural scale of each quantity); for float storage the
 * caller passes a statistical tol (standard errors are the caller's business). */
static void sde_compare_obs(const char *scene, const gran_srd_obs *a, const gran_srd_obs *b, double tol) {
  assert_int_equal(a->steps, b->steps);
  assert_int_equal(a->n, b->n);
  const double E = a->e_initial, P = sqrt(2.0 * E * (double)a->n);
  sde_close(scene, "time", a->time, b->time, 1e-15, fabs(a->time) + 1);
  sde_close(scene, "energy", a->energy, b->energy, tol, E);
  sde_close(scene, "e_initial", a->e_initial, b->e_initial, tol, E);
  sde_close(scene, "e_collisions", a->e_collisions, b->e_collisions, tol, E);
  sde_close(scene, "e_external", a->e_external, b->e_external, tol, E);
  sde_close(scene, "ledger_error", a->ledger_error, b->ledger_error, tol, 1.0);
  for (int k = 0; k < 3; ++k) sde_close(scene, "momentum", a->momentum[k], b->momentum[k], tol, P);
  sde_close(scene, "temperature", a->temperature, b->temperature, tol, a->temperature);
  sde_close(scene, "theta_cells", a->theta_cells, b->theta_cells, tol, a->theta_cells);
  sde_close(scene, "e_kin", a->e_kin, b->e_kin, tol, a->theta_cells);
  sde_close(scene, "sigma_rho", a->sigma_rho, b->sigma_rho, tol, a->sigma_rho + 1);
  sde_close(scene, "a2", a->a2, b->a2, tol, 1.0);
  sde_close(scene, "stress_xy", a->stress_xy, b->stress_xy, tol, fabs(a->stress_xy) + a->temperature);
  sde_close(scene, "stress_kin", a->stress_kin, b->stress_kin, tol, fabs(a->stress_kin) + a->temperature);
}

/* The same scene on devices da and db (GRAN_SRD_DEVICE_*; same precision = double): after each of
 * three advances every particle agrees within xtol and every observable within otol (relative to
 * its scale), clamp counts equal; then the run on da is checkpointed, resumed and moved to db
 * (and the one on db to da) and both continue in step with the originals. Prints the largest
 * difference. */
static void sde_body_devices(int scene, int da, int db, double xtol, double otol) {
  const char *name = sde_names[scene];
  gran_srd_options o;
  sde_options(scene, &o);
  gran_srd *a = NULL, *b = NULL;
  o.device = da;
  GRAN_ASSERT_OK(gran_srd_create(&o, &a));
  o.device = db;
  GRAN_ASSERT_OK(gran_srd_create(&o, &b));
  int32_t got;
  GRAN_ASSERT_OK(gran_srd_get_device(b, &got));
  assert_int_equal(got, db);
  double worst = 0.0;
  int64_t clamps = 0;
  for (int rep = 0; rep < 3; ++rep) {
    GRAN_ASSERT_OK(gran_srd_advance(a, 5 + rep));
    GRAN_ASSERT_OK(gran_srd_advance(b, 5 + rep));
    gran_srd_obs oa, ob;
    GRAN_ASSERT_OK(gran_srd_observe(a, &oa));
    GRAN_ASSERT_OK(gran_srd_observe(b, &ob));
    if (oa.clamped != ob.clamped) fail_msg("%s: clamps %lld vs %lld", name, (long long)oa.clamped, (long long)ob.clamped);
    if (oa.clamped > 0 && !gran_test_rel_ok(oa.dt_max, ob.dt_max, 1e-9))
      fail_msg("%s: dt_max %.17g vs %.17g", name, oa.dt_max, ob.dt_max);
    clamps += oa.clamped;
    sde_compare_obs(name, &oa, &ob, otol);
    const double d = sde_particles_diff(a, b, o.dim);
    worst = d > worst ? d : worst;
    if (!(d <= xtol)) fail_msg("%s: particles differ by %.3g after %lld steps", name, d, (long long)oa.steps);
  }
  if (scene == SDE_DISSIP && clamps == 0) fail_msg("%s: the scene was meant to clamp", name);
  /* S(k): from the device's cell counts (periodic scenes) */
  if (o.wall_axis < 0) {
    enum { NB = 8 };
    double ka[NB], sa[NB], kb[NB], sb[NB];
    int64_t ca[NB], cb[NB];
    GRAN_ASSERT_OK(gran_srd_structure_factor(a, NB, ka, sa, ca));
    GRAN_ASSERT_OK(gran_srd_structure_factor(b, NB, kb, sb, cb));
    for (int i = 0; i < NB; ++i) {
      assert_int_equal(ca[i], cb[i]);
      sde_close(name, "S(k)", sa[i], sb[i], 1e-9, 1.0);
      sde_close(name, "k", ka[i], kb[i], 1e-12, 1.0);
    }
  }
  /* checkpoints: a's file resumes on db, b's on da; both continue with the originals */
  char pa[64], pb[64];
  snprintf(pa, sizeof pa, "srd-device-ckpt-%d-%d-%d-a.bin", scene, da, db);
  snprintf(pb, sizeof pb, "srd-device-ckpt-%d-%d-%d-b.bin", scene, da, db);
  GRAN_ASSERT_OK(gran_srd_checkpoint_write(a, pa, "/srd"));
  GRAN_ASSERT_OK(gran_srd_checkpoint_write(b, pb, "/srd"));
  gran_srd *ra = NULL, *rb = NULL;
  GRAN_ASSERT_OK(gran_srd_checkpoint_read(pa, "/srd", &ra));
  GRAN_ASSERT_OK(gran_srd_checkpoint_read(pb, "/srd", &rb));
  GRAN_ASSERT_OK(gran_srd_get_device(ra, &got));
  assert_int_equal(got, da); /* resumes where it ran */
  GRAN_ASSERT_OK(gran_srd_set_device(ra, db));
  GRAN_ASSERT_OK(gran_srd_set_device(rb, da));
  GRAN_ASSERT_OK(gran_srd_get_device(ra, &got));
  assert_int_equal(got, db);
  remove(pa);
  remove(pb);
  GRAN_ASSERT_OK(gran_srd_advance(a, 9));
  GRAN_ASSERT_OK(gran_srd_advance(b, 9));
  GRAN_ASSERT_OK(gran_srd_advance(ra, 9));
  GRAN_ASSERT_OK(gran_srd_advance(rb, 9));
  gran_srd_obs oa, ob, ora, orb;
  GRAN_ASSERT_OK(gran_srd_observe(a, &oa));
  GRAN_ASSERT_OK(gran_srd_observe(b, &ob));
  GRAN_ASSERT_OK(gran_srd_observe(ra, &ora));
  GRAN_ASSERT_OK(gran_srd_observe(rb, &orb));
  sde_compare_obs(name, &oa, &ora, otol);
  sde_compare_obs(name, &ob, &orb, otol);
  const double d1 = sde_particles_diff(a, ra, o.dim), d2 = sde_particles_diff(b, rb, o.dim);
  if (!(d1 <= xtol && d2 <= xtol)) fail_msg("%s: resumed runs differ by %.3g / %.3g", name, d1, d2);
  worst = d1 > worst ? d1 : worst;
  worst = d2 > worst ? d2 : worst;
  printf("  %-44s %s vs %s: N = %lld, largest particle difference %.2g (27 steps), clamps %lld\n", name,
         da == 0 ? "cpu" : da == 1 ? "cuda" : "reference", db == 0 ? "cpu" : db == 1 ? "cuda" : "reference",
         (long long)sde_n(a), worst, (long long)clamps);
  GRAN_ASSERT_OK(gran_srd_destroy(&a));
  GRAN_ASSERT_OK(gran_srd_destroy(&b));
  GRAN_ASSERT_OK(gran_srd_destroy(&ra));
  GRAN_ASSERT_OK(gran_srd_destroy(&rb));
}

/* ---- physics on a device (the CPU engine's own tests are t801/t802) ---------------------------- */

/* Haff's law (2-D, eps = 0.9, mean-field rate c = (1 - eps^2) sigma^2 n0 sqrt(T0) / dt = 0.01 per
 * step): sqrt(T0 / T) linear in t down to T/T0 < 0.01 (worst residual < 3 %), slope within 25 % of
 * c (as t802 for the CPU engine), the ledger closed to 1e-12 (double) / 1e-5 (float). */
static void sde_body_haff(int device, int precision, int64_t L) {
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = 2;
  o.cells[0] = o.cells[1] = L;
  o.n0 = 10;
  o.alpha_deg = 90;
  o.eps = 0.9;
  const double c = 0.01;
  o.sigma = sqrt(c / ((1 - o.eps * o.eps) * o.n0));
  o.seed = 5;
  o.threads = 1;
  o.device = device;
  o.precision = precision;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  gran_srd_obs ob;
  enum { NT = 100 };
  double t[NT], u[NT];
  int m = 0;
  for (int k = 0; k < NT; ++k) {
    GRAN_ASSERT_OK(gran_srd_advance(s, 10));
    GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
    if (!(fabs(ob.ledger_error) < (precision ? 1e-5 : 1e-12))) fail_msg("Haff: ledger error %g", ob.ledger_error);
    t[m] = ob.time;
    u[m] = sqrt(o.T0 / ob.temperature);
    ++m;
    if (ob.temperature < 0.008 * o.T0) break;
  }
  assert_true(ob.temperature < 0.01 * o.T0); /* two decades covered */
  double st = 0, su = 0, stt = 0, stu = 0;
  for (int k = 0; k < m; ++k) {
    st += t[k];
    su += u[k];
    stt += t[k] * t[k];
    stu += t[k] * u[k];
  }
  const double slope = (m * stu - st * su) / (m * stt - st * st), icpt = (su - slope * st) / m;
  double worst = 0;
  for (int k = 0; k < m; ++k) worst = fmax(worst, fabs(icpt + slope * t[k] - u[k]) / u[k]);
  printf("  Haff (%s, %s, %lld^2): %d samples to T/T0 = %.3g, 1/tau = %.5f (mean field %.5f), worst residual %.3g\n",
         device == GRAN_SRD_DEVICE_CUDA ? "cuda" : device == GRAN_SRD_DEVICE_REFERENCE ? "reference" : "cpu",
         precision ? "float" : "double", (long long)L, m, ob.temperature, slope, c, worst);
  assert_true(worst < 0.03);
  GRAN_ASSERT_REL(slope, c, 0.25);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* Collisional viscosity of standard SRD under Lees-Edwards shear with the thermostat (kT = 1,
 * a = dt = 1): (stress_xy - stress_kin) / (n0 shear rate) against (a^2 / (6 d dt))
 * (M - 1 + e^-M) / M (1 - cos alpha), standard error from nblk time blocks, tolerance 4 se + 3 %
 * (as t802). */
static void sde_body_viscosity(int device, int precision, int dim, int64_t L, double alpha, int nblk, int blk) {
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = dim;
  o.cells[0] = o.cells[1] = o.cells[2] = L;
  o.n0 = 10;
  o.alpha_deg = alpha;
  o.thermostat = 1;
  o.shear_rate = 0.04;
  o.seed = 2024 + (uint64_t)alpha;
  o.threads = 1;
  o.device = device;
  o.precision = precision;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 100));
  double sum = 0, sum2 = 0;
  for (int b = 0; b < nblk; ++b) {
    GRAN_ASSERT_OK(gran_srd_stress_reset(s));
    GRAN_ASSERT_OK(gran_srd_advance(s, blk));
    gran_srd_obs ob;
    GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
    const double nu = (ob.stress_xy - ob.stress_kin) / (o.n0 * o.shear_rate);
    sum += nu;
    sum2 += nu * nu;
  }
  const double M = o.n0, al = alpha * 3.14159265358979323846 / 180, q = M - 1 + exp(-M);
  const double th = q / M * (1 - cos(al)) / (dim == 2 ? 12.0 : 18.0);
  const double mean = sum / nblk, se = sqrt(fmax(0.0, sum2 / nblk - mean * mean) / (nblk - 1));
  printf("  collisional viscosity (%s, %s) %dD %lld cells/axis alpha %g: %.5f +- %.5f, theory %.5f (%.2f %%)\n",
         device == GRAN_SRD_DEVICE_CUDA ? "cuda" : device == GRAN_SRD_DEVICE_REFERENCE ? "reference" : "cpu",
         precision ? "float" : "double", dim, (long long)L, alpha, mean, se, th, 100 * (mean / th - 1));
  if (!(fabs(mean - th) <= 4 * se + 0.03 * th)) fail_msg("viscosity %.5f +- %.5f against %.5f", mean, se, th);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* S(k) of an ideal SRD gas (eps = 1, dt = 1): every shell within 5 standard errors of 1 after 20
 * steps; nsamp independent runs (seeds), so that the standard error is one. */
static void sde_body_sk_ideal(int device, int precision, int dim, int64_t L, int nsamp) {
  enum { NB = 6 };
  double k[NB], sk[NB], m1[NB] = {0}, m2[NB] = {0};
  int64_t cnt[NB];
  for (int r = 0; r < nsamp; ++r) {
    gran_srd_options o;
    sde_options(SDE_PERIODIC, &o);
    o.dim = dim;
    o.cells[0] = o.cells[1] = o.cells[2] = L;
    o.dt = 1.0;
    o.seed = 100 + (uint64_t)r;
    o.device = device;
    o.precision = precision;
    gran_srd *s = NULL;
    GRAN_ASSERT_OK(gran_srd_create(&o, &s));
    GRAN_ASSERT_OK(gran_srd_advance(s, 20));
    GRAN_ASSERT_OK(gran_srd_structure_factor(s, NB, k, sk, cnt));
    for (int b = 0; b < NB; ++b) {
      m1[b] += sk[b];
      m2[b] += sk[b] * sk[b];
    }
    GRAN_ASSERT_OK(gran_srd_destroy(&s));
  }
  for (int b = 0; b < NB; ++b) {
    const double mean = m1[b] / nsamp, se = sqrt(fmax(m2[b] / nsamp - mean * mean, 0.0) / (nsamp - 1));
    if (!(fabs(mean - 1.0) <= 5 * se + 1e-3))
      fail_msg("S(k = %.3g) = %.4f +- %.4f, not 1 (%d-D, %lld cells/axis)", k[b], mean, se, dim, (long long)L);
    if (b == 0 || b == NB - 1)
      printf("  S(k) ideal gas (%d-D %lld^d, %s, %d runs): S(%.3g) = %.4f +- %.4f\n", dim, (long long)L,
             precision ? "float" : "double", nsamp, k[b], mean, se);
  }
}

/* A cold gas in fast flow: T0 = 1e-8 around a flow of |V| ~ 1.1 (theta / V^2 ~ 1e-8), standard SRD.
 * The cell temperature on the device agrees with the CPU engine's: double to 1e-6 relative, float
 * storage (velocity resolution 6e-8 against thermal speeds of 1e-4) to 2 %. */
static void sde_body_cold_flow(int device, int precision) {
  gran_srd_options o;
  sde_options(SDE_PERIODIC, &o);
  o.T0 = 1e-8;
  o.sort_every = 0;
  gran_srd *c = NULL, *d = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &c));
  o.device = device;
  o.precision = precision;
  GRAN_ASSERT_OK(gran_srd_create(&o, &d));
  gran_srd *both[2] = {c, d};
  for (int q = 0; q < 2; ++q) {
    int64_t n;
    double *x, *y, *z, *vx, *vy, *vz;
    GRAN_ASSERT_OK(gran_srd_particles(both[q], &n, &x, &y, &z, &vx, &vy, &vz));
    for (int64_t i = 0; i < n; ++i) {
      vx[i] += 1.0;
      vy[i] -= 0.5;
    }
  }
  GRAN_ASSERT_OK(gran_srd_advance(c, 20));
  GRAN_ASSERT_OK(gran_srd_advance(d, 20));
  gran_srd_obs oc, od;
  GRAN_ASSERT_OK(gran_srd_observe(c, &oc));
  GRAN_ASSERT_OK(gran_srd_observe(d, &od));
  printf("  cold flow (%s): theta_cells cpu %.9g device %.9g (T0 1e-8)\n", precision ? "float" : "double",
         oc.theta_cells, od.theta_cells);
  assert_true(oc.theta_cells > 0.5e-8 && oc.theta_cells < 1.5e-8);
  if (!gran_test_rel_ok(od.theta_cells, oc.theta_cells, precision ? 2e-2 : 1e-6))
    fail_msg("cold flow: theta_cells cpu %.9g device %.9g", oc.theta_cells, od.theta_cells);
  GRAN_ASSERT_OK(gran_srd_destroy(&c));
  GRAN_ASSERT_OK(gran_srd_destroy(&d));
}

#endif
