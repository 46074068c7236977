/* srd_device_body.h - GSRD test bodies run on both devices (STYLE rule 13, SUNDIALS test_nvector.h):
 * tests/t890-srd-device.c runs them on the CPU reference below in `make test`, tests/gpu/t850-srd-gpu.c
 * on the GPU launchers of cuda/srd_cuda.h in `make test-gpu`, and compares the two.
 *
 * The CPU reference is the GPU algorithm written as plain loops over the same shared functions of
 * src/srd/srd_kernels.h: pass 1 stream + wrap + bin under the shift + cell sums relative to the
 * cell's previous mean; per cell moments, axis from the cell's stream (only for n >= 2), eps_eff;
 * pass 2 rotate-and-scale. */
#ifndef GRAN_SRD_DEVICE_BODY_H
#define GRAN_SRD_DEVICE_BODY_H

#include "granary_test.h"
#include "srd_cuda.h"

typedef struct sdb_state {
  int gpu;                 /* 0: CPU reference, 1: cuda launchers */
  gran_cuda_srd_params p;
  int64_t ncell;
  double *x[3], *v[3];     /* host copy (CPU: the state itself) */
  gran_rng *cell_rng;
  srd_cell_sum *sums;
  double *vref;
  srd_cell_rot *rot;
  int *active;
  gran_rng shift_rng;      /* stream 0 of the seed: the grid shift */
  gran_cuda_srd *dev;
  int64_t nclamp;
} sdb_state;

/* periodic box of L^dim cells, n0 particles per cell, temperature T0 around the flow u. */
static void sdb_init(sdb_state *st, int gpu, int dim, int64_t L, int n0, double alpha_deg, double eps,
                     int precision, uint64_t seed) {
  memset(st, 0, sizeof *st);
  st->gpu = gpu;
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
  st->p.dissip = eps < 1.0;
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
  if (gpu) {
    GRAN_ASSERT_OK(gran_cuda_srd_create(&st->p, (const double *const *)st->x, (const double *const *)st->v,
                                        st->cell_rng, &st->dev));
  } else {
    st->sums = calloc((size_t)st->ncell, sizeof(srd_cell_sum));
    st->vref = calloc((size_t)st->ncell * 3, sizeof(double));
    st->rot = calloc((size_t)st->ncell, sizeof(srd_cell_rot));
    st->active = calloc((size_t)st->ncell, sizeof(int));
    assert_true(st->sums && st->vref && st->rot && st->active);
  }
}

static void sdb_free(sdb_state *st) {
  for (int k = 0; k < 3; ++k) {
    free(st->x[k]);
    free(st->v[k]);
  }
  free(st->cell_rng);
  free(st->sums);
  free(st->vref);
  free(st->rot);
  free(st->active);
  GRAN_ASSERT_OK(gran_cuda_srd_destroy(&st->dev));
}

static void sdb_cpu_step(sdb_state *st, const double s[3]) {
  const srd_geom *g = &st->p.geom;
  const int dim = g->dim;
  const double zero[3] = {0, 0, 0};
  for (int64_t i = 0; i < st->p.n; ++i) {
    double p[3] = {0, 0, 0}, v[3] = {0, 0, 0}, dvx;
    for (int k = 0; k < dim; ++k) {
      p[k] = st->x[k][i];
      v[k] = st->v[k][i];
    }
    srd_stream(p, v, st->p.dt, zero, dim, 0);
    srd_wrap(g, p, v);
    for (int k = 0; k < dim; ++k) {
      st->x[k][i] = p[k];
      st->v[k][i] = v[k];
    }
    const int64_t c = srd_bin(g, s, p, &dvx);
    v[0] += dvx;
    srd_sum_add(&st->sums[c], v, &st->vref[3 * c], dim);
  }
  const double inv_vol = 1.0 / (dim == 2 ? g->a * g->a : g->a * g->a * g->a);
  for (int64_t c = 0; c < st->ncell; ++c) {
    srd_cell_sum cs = st->sums[c];
    srd_cell_rot *cr = &st->rot[c];
    double theta;
    cr->f = cr->g = 1.0;
    cr->r[0] = cr->r[1] = cr->r[2] = 0.0;
    srd_cell_moments(&cs, &st->vref[3 * c], dim, cr->V, &theta);
    if (cs.n > 0)
      for (int k = 0; k < 3; ++k) st->vref[3 * c + k] = cr->V[k];
    st->active[c] = cs.n >= 2;
    if (st->active[c]) {
      srd_draw_axis(&st->cell_rng[c], dim, cr->r);
      if (st->p.dissip) {
        int cl;
        cr->f = srd_eps_eff(st->p.coef, (double)cs.n * inv_vol, theta, &cl);
        st->nclamp += cl;
      }
    }
    srd_sum_clear(&st->sums[c]);
  }
  const double ca = cos(st->p.alpha), sa = sin(st->p.alpha);
  for (int64_t i = 0; i < st->p.n; ++i) {
    double p[3] = {0, 0, 0}, v[3] = {0, 0, 0}, dvx;
    for (int k = 0; k < dim; ++k) p[k] = st->x[k][i];
    const int64_t c = srd_bin(g, s, p, &dvx);
    if (!st->active[c]) continue;
    for (int k = 0; k < dim; ++k) v[k] = st->v[k][i];
    v[0] += dvx;
    srd_rotate(v, &st->rot[c], ca, sa, dim, st->p.dissip);
    v[0] -= dvx;
    for (int k = 0; k < dim; ++k) st->v[k][i] = v[k];
  }
}

/* nsteps steps; the host copy x, v is current afterwards. */
static void sdb_run(sdb_state *st, int nsteps) {
  for (int t = 0; t < nsteps; ++t) {
    double s[3] = {0, 0, 0};
    for (int k = 0; k < st->p.geom.dim; ++k) s[k] = st->p.geom.a * srd_rng_uniform(&st->shift_rng);
    if (st->gpu)
      GRAN_ASSERT_OK(gran_cuda_srd_step(st->dev, &st->p.geom, s, &st->nclamp, NULL));
    else
      sdb_cpu_step(st, s);
  }
  if (st->gpu) GRAN_ASSERT_OK(gran_cuda_srd_download(st->dev, st->x, st->v, st->cell_rng));
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
static void sdb_body_conservation(int gpu, int dim, int precision, double eps) {
  sdb_state st;
  sdb_init(&st, gpu, dim, dim == 3 ? 8 : 16, 10, 130.0, eps, precision, 2024);
  double m0[3], e0, m1[3], e1;
  sdb_totals(&st, m0, &e0);
  const double tol = precision ? 1e-5 : 1e-12;
  double eprev = e0;
  for (int rep = 0; rep < 5; ++rep) {
    sdb_run(&st, 4);
    sdb_totals(&st, m1, &e1);
    const double pscale = sqrt(2.0 * e0); /* momentum scale: |p| can be small in one component */
    for (int k = 0; k < dim; ++k)
      if (fabs(m1[k] - m0[k]) > tol * pscale * sqrt((double)st.p.n))
        fail_msg("%s dim %d: momentum[%d] %.17g -> %.17g", gpu ? "GPU" : "CPU", dim, k, m0[k], m1[k]);
    if (eps == 1.0) {
      if (!gran_test_rel_ok(e1, e0, tol)) fail_msg("%s dim %d: energy %.17g -> %.17g", gpu ? "GPU" : "CPU", dim, e0, e1);
    } else {
      if (!(e1 < eprev)) fail_msg("eps = %g: energy did not fall (%.17g -> %.17g)", eps, eprev, e1);
    }
    eprev = e1;
  }
  for (int64_t i = 0; i < st.p.n; ++i)
    for (int k = 0; k < dim; ++k)
      if (!(st.x[k][i] >= 0.0 && st.x[k][i] < st.p.geom.box[k])) fail_msg("particle outside the box");
  sdb_free(&st);
}

#endif
