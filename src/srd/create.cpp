/* create.cpp - the initial particles of a GSRD run (src/srd/create.h).
 *
 * Serial (GRAN_SRD_CREATE_SERIAL): one stream (the seed's state after a long jump, 2^192 steps:
 * beyond every cell stream) draws every particle in turn; the engine then sorts them by cell.
 *
 * By cells (GRAN_SRD_CREATE_CELLS): the counts come from a multinomial split of N down a fixed
 * binary tree over the box cells, the particles of each cell from the cell's own generator, so the
 * particles of any cell range are the same whoever makes them (a thread, a rank of a decomposed
 * run) and come out in cell order. The generators are keyed, not jumped (core/keyed.h, with the
 * split); the tags separate the tree's nodes from the cells. A node draws a few dozen numbers (the
 * binomial), a cell about 6 n0. They are distinct from the collision streams of the cells
 * (stream c + 1 of the seed), which creation does not touch. */
#include "srd/create.h"
#include "core/keyed.h"
#include "srd/srd_impl.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace {

using gran::keyed_rng;
using gran::keyed_split;

constexpr uint64_t kTagNode = 0x6e6f64652d747265ULL; /* the tree's nodes */
constexpr uint64_t kTagCell = 0x63656c6c2d706172ULL; /* the cells' particles */

struct Layout {
  int dim;
  int64_t L[3];
  int64_t ncell; /* box cells */
  int64_t n;     /* particles */
  srd_geom gm;   /* the fields srd_bin_index reads */
};

int layout_of(const gran_srd_options *o, Layout *ly) {
  std::memset(ly, 0, sizeof *ly);
  ly->dim = o->dim;
  ly->ncell = 1;
  srd_geom &g = ly->gm;
  g.dim = o->dim;
  g.wall_axis = o->wall_axis;
  g.a = o->a;
  g.inv_a = 1.0 / o->a;
  for (int k = 0; k < 3; ++k) {
    ly->L[k] = k < o->dim ? o->cells[k] : 1;
    g.L[k] = ly->L[k];
    g.nc[k] = g.L[k] + (k == o->wall_axis ? 1 : 0);
    g.box[k] = k < o->dim ? (double)g.L[k] * o->a : o->a;
    ly->ncell *= ly->L[k];
  }
  const double nn = std::floor(o->n0 * (double)ly->ncell + 0.5);
  GRAN_CHECK(nn >= 1 && nn < 4e9, GRAN_ERR_ARG, "options 'n0' x 'cells' give %g particles (need 1 .. 4e9)", nn);
  ly->n = (int64_t)nn;
  return GRAN_SUCCESS;
}

/* counts of the leaves of node (id, [nlo, nhi), c) that lie in [lo, hi), into count[leaf - lo] */
void split(uint64_t seed, uint64_t id, int64_t nlo, int64_t nhi, int64_t c, int64_t lo, int64_t hi, int64_t *count) {
  keyed_split<false>(seed, kTagNode, id, nlo, nhi, c, lo, hi, [&](int64_t i, int64_t n) { count[i - lo] = n; });
}

/* a coordinate uniform in layer i of axis k that the engine bins into layer i (unshifted grid) */
inline int coord_in(const srd_geom *gm, int k, int64_t i, gran_rng *r, double *x) {
  for (int t = 0; t < 64; ++t) {
    const double v = ((double)i + srd_rng_uniform(r)) * gm->a;
    if (srd_bin_index(gm, k, v) == i) {
      *x = v;
      return 1;
    }
  }
  return 0;
}

int create_range(const gran_srd_options *o, const Layout &ly, int64_t lo, int64_t hi, const int64_t *count,
                 double *x, double *y, double *z, double *vx, double *vy, double *vz, gran_exactsum *mom) {
  const double sd = std::sqrt(o->T0);
  const bool d3 = ly.dim == 3;
  int64_t p = 0;
  for (int64_t c = lo; c < hi; ++c) {
    const int64_t nc = count[c - lo];
    if (nc == 0) continue;
    const int64_t ci = c % ly.L[0], cj = (c / ly.L[0]) % ly.L[1], ck = c / (ly.L[0] * ly.L[1]);
    gran_rng r;
    keyed_rng(o->seed, kTagCell, (uint64_t)c, &r);
    double m[3] = {0.0, 0.0, 0.0};
    for (int64_t q = 0; q < nc; ++q, ++p) {
      int ok = coord_in(&ly.gm, 0, ci, &r, &x[p]) & coord_in(&ly.gm, 1, cj, &r, &y[p]);
      if (d3) ok &= coord_in(&ly.gm, 2, ck, &r, &z[p]);
      GRAN_CHECK(ok, GRAN_ERR_INTERNAL, "GSRD creation: no position inside cell %lld found (cell size 'a' = %g)",
                 (long long)c, o->a);
      vx[p] = sd * srd_rng_normal(&r);
      vy[p] = sd * srd_rng_normal(&r);
      if (d3) vz[p] = sd * srd_rng_normal(&r);
      m[0] += vx[p];
      m[1] += vy[p];
      if (d3) m[2] += vz[p];
    }
    if (mom)
      for (int k = 0; k < ly.dim; ++k) gran_exactsum_add_(&mom[k], m[k]);
  }
  return GRAN_SUCCESS;
}

int create_serial(gran_srd *s) {
  const gran_srd_options *opt = &s->opt;
  /* initial state: stream long_jump of the seed, serial */
  gran_rng r;
  gran_rng_seed(&r, opt->seed);
  gran_rng_long_jump(&r);
  const int d = opt->dim;
  const double sd = std::sqrt(opt->T0);
  double m[3] = {0, 0, 0};
  for (int64_t i = 0; i < s->n; ++i) {
    s->x[i] = srd_rng_uniform(&r) * s->gm.box[0];
    s->y[i] = srd_rng_uniform(&r) * s->gm.box[1];
    if (d == 3) s->z[i] = srd_rng_uniform(&r) * s->gm.box[2];
    s->vx[i] = sd * srd_rng_normal(&r);
    s->vy[i] = sd * srd_rng_normal(&r);
    if (d == 3) s->vz[i] = sd * srd_rng_normal(&r);
    m[0] += s->vx[i];
    m[1] += s->vy[i];
    if (d == 3) m[2] += s->vz[i];
  }
  for (int k = 0; k < 3; ++k) m[k] /= (double)s->n;
  for (int64_t i = 0; i < s->n; ++i) {
    s->vx[i] -= m[0];
    s->vy[i] -= m[1];
    if (d == 3) s->vz[i] -= m[2];
    if (opt->shear_rate != 0) s->vx[i] += opt->shear_rate * (s->y[i] - 0.5 * s->gm.box[1]);
  }
  return GRAN_SUCCESS;
}

int create_by_cells(gran_srd *s) {
  const gran_srd_options *o = &s->opt;
  Layout ly;
  GRAN_CALL(layout_of(o, &ly));
  GRAN_CHECK(ly.n == s->n && ly.ncell == s->ncell_box, GRAN_ERR_INTERNAL, "GSRD creation: layout mismatch");
  const int nth = srd_threads_used(o->threads);
  /* blocks of cells: any blocking gives the same particles (each cell's are its own) */
  const int64_t nb = std::max<int64_t>(1, std::min<int64_t>(4 * (int64_t)nth, ly.ncell / 256));
  std::vector<int64_t> count((size_t)ly.ncell);
#pragma omp parallel for schedule(dynamic, 1) num_threads(nth)
  for (int64_t b = 0; b < nb; ++b) {
    const int64_t lo = ly.ncell * b / nb, hi = ly.ncell * (b + 1) / nb;
    split(o->seed, 1, 0, ly.ncell, ly.n, lo, hi, count.data() + lo);
  }
  std::vector<int64_t> start((size_t)nb + 1, 0);
  for (int64_t b = 0; b < nb; ++b) {
    const int64_t lo = ly.ncell * b / nb, hi = ly.ncell * (b + 1) / nb;
    int64_t t = 0;
    for (int64_t c = lo; c < hi; ++c) t += count[(size_t)c];
    start[(size_t)b + 1] = start[(size_t)b] + t;
  }
  GRAN_CHECK(start[(size_t)nb] == s->n, GRAN_ERR_INTERNAL, "GSRD creation: cell counts sum to %lld, not N = %lld",
             (long long)start[(size_t)nb], (long long)s->n);
  std::vector<gran_exactsum> mom((size_t)nb * 3);
  const bool d3 = o->dim == 3;
  int err = GRAN_SUCCESS;
#pragma omp parallel for schedule(dynamic, 1) num_threads(nth)
  for (int64_t b = 0; b < nb; ++b) {
    const int64_t lo = ly.ncell * b / nb, hi = ly.ncell * (b + 1) / nb, p = start[(size_t)b];
    for (int k = 0; k < 3; ++k) gran_exactsum_init_(&mom[(size_t)b * 3 + k]);
    const int e = create_range(o, ly, lo, hi, count.data() + lo, s->x.data() + p, s->y.data() + p,
                               d3 ? s->z.data() + p : nullptr, s->vx.data() + p, s->vy.data() + p,
                               d3 ? s->vz.data() + p : nullptr, &mom[(size_t)b * 3]);
    if (e != GRAN_SUCCESS) {
#pragma omp atomic write
      err = e;
    }
  }
  if (err != GRAN_SUCCESS) return err;
  /* the mean momentum: exact sums of the cells' partial sums (the same on any partition) */
  double m[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < o->dim; ++k) {
    gran_exactsum t;
    gran_exactsum_init_(&t);
    for (int64_t b = 0; b < nb; ++b) gran_exactsum_merge_(&t, &mom[(size_t)b * 3 + k]);
    m[k] = gran_exactsum_value_(&t) / (double)s->n;
  }
  const int64_t n = s->n;
  const double box1 = s->gm.box[1], rate = o->shear_rate;
  double *vx = s->vx.data(), *vy = s->vy.data(), *vz = d3 ? s->vz.data() : nullptr;
  const double *py = s->y.data();
#pragma omp parallel for schedule(static) num_threads(nth)
  for (int64_t i = 0; i < n; ++i) {
    vx[i] -= m[0];
    vy[i] -= m[1];
    if (d3) vz[i] -= m[2];
    /* one explicit fused multiply-add: the same bits whatever the compiler contracts */
    if (rate != 0) vx[i] = std::fma(rate, py[i] - 0.5 * box1, vx[i]);
  }
  return GRAN_SUCCESS;
}

/* the checks both cell-range entry points share: the options, the range, the counts */
int range_args(const gran_srd_options *o, int64_t lo, int64_t hi, const int64_t *count, Layout *ly) {
  GRAN_CHECK_PTR(o);
  GRAN_CALL(srd_check_options_(o));
  GRAN_CALL(layout_of(o, ly));
  GRAN_CHECK(0 <= lo && lo <= hi && hi <= ly->ncell, GRAN_ERR_ARG, "cell range [%lld, %lld) is not inside [0, %lld)",
             (long long)lo, (long long)hi, (long long)ly->ncell);
  GRAN_CHECK(count != nullptr || hi == lo, GRAN_ERR_ARG, "argument 'count' is NULL");
  return GRAN_SUCCESS;
}

} // namespace

extern "C" int gran_srd_cell_counts_(const gran_srd_options *o, int64_t lo, int64_t hi, int64_t *count) {
  GRAN_TRY {
    Layout ly;
    GRAN_CALL(range_args(o, lo, hi, count, &ly));
    split(o->seed, 1, 0, ly.ncell, ly.n, lo, hi, count);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

extern "C" int gran_srd_create_cells_(const gran_srd_options *o, int64_t lo, int64_t hi, const int64_t *count,
                                      double *x, double *y, double *z, double *vx, double *vy, double *vz,
                                      gran_exactsum *mom) {
  GRAN_TRY {
    Layout ly;
    GRAN_CALL(range_args(o, lo, hi, count, &ly));
    GRAN_CHECK(x && y && vx && vy && (o->dim == 2 || (z && vz)), GRAN_ERR_ARG, "a particle array is NULL");
    return create_range(o, ly, lo, hi, count, x, y, z, vx, vy, vz, mom);
  }
  GRAN_CATCH
}

extern "C" int gran_srd_initial_state_(gran_srd *s) {
  GRAN_TRY {
    GRAN_CHECK_PTR(s);
    if (s->opt.creation == GRAN_SRD_CREATE_CELLS) return create_by_cells(s);
    return create_serial(s);
  }
  GRAN_CATCH
}
