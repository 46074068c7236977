/* b802-srd-bricks.c - the decomposable GSRD engine (src/srd/bricks.h; docs/developers/
 * domain-decomposition.md, "Step 2"): 3-D, n0 = 10, dt = 0.1, kT = 1, alpha = 130, sort every 50,
 * one thread, boxes of 32^3 and 64^3 cells (BENCH_QUICK: 32^3 only).
 *  - ns per particle-step of the serial engine (creation serial) and of the decomposable one
 *    (creation by cells: the brick layer with one brick, exact sums), interleaved rounds, medians;
 *  - P = 2 virtual bricks (2 x 1 x 1) against P = 1 through srd_bricks_run_ (the steps only),
 *    interleaved, medians; the bytes the transport carried per step and brick face, against the
 *    design's estimate E|ds + v dt| / a x n0 x (face cells) x 56 B (ds the difference of two
 *    uniform shifts: E|ds| = a / 3; plus (v dt)^2 f(0) = 0.01 for kT = 1, dt = 0.1: 0.343 of a layer);
 *  - the exact accumulator's add (src/core/exactsum.h) on values of one scale (what the engine's
 *    per-cell partials are) against a plain double sum.
 * GRAN_SRD_PHASES=1 prints the phases of every advance (both engines) to stderr. */
#include "bench_util.h"

#include <math.h>
#include <stdlib.h>

#include "core/exactsum.h"
#include "srd/bricks.h"

static gran_srd_options opts(int L, int creation) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = 3;
  o.cells[0] = o.cells[1] = o.cells[2] = L;
  o.n0 = 10;
  o.dt = 0.1;
  o.alpha_deg = 130;
  o.T0 = 1;
  o.sort_every = 50;
  o.seed = 802;
  o.threads = 1;
  o.creation = creation;
  return o;
}

static int cmp_d(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}
static double median(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp_d);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

enum { R = 5 };

int main(void) {
  const int quick = bench_quick();
  const int sizes[2] = {32, 64};
  for (int si = 0; si < (quick ? 1 : 2); ++si) {
    const int L = sizes[si];
    const int64_t steps = L == 32 ? 60 : 12;
    double t[2][R];
    for (int r = 0; r < R; ++r)
      for (int m = 0; m < 2; ++m) { /* interleaved: serial, cells, serial, ... */
        gran_srd_options o = opts(L, m);
        gran_srd *s = NULL;
        BENCH_CHECK(gran_srd_create(&o, &s));
        BENCH_CHECK(gran_srd_advance(s, 2));
        const double t0 = bench_now();
        BENCH_CHECK(gran_srd_advance(s, steps));
        const double n = o.n0 * L * L * L;
        t[m][r] = (bench_now() - t0) * 1e9 / (n * (double)steps);
        BENCH_CHECK(gran_srd_destroy(&s));
      }
    const double ms = median(t[0], R), mc = median(t[1], R);
    printf("%d^3 n0 = 10, 1 thread, %lld steps x %d rounds: serial engine %.2f ns/particle-step, decomposable "
           "(1 brick) %.2f (ratio %.3f)\n",
           L, (long long)steps, R, ms, mc, mc / ms);
    /* P = 1 vs P = 2 virtual bricks */
    double tb[2][R], bpf = 0, sent = 0;
    for (int r = 0; r < R; ++r)
      for (int m = 0; m < 2; ++m) {
        gran_srd_options o = opts(L, GRAN_SRD_CREATE_CELLS);
        const int pg[2][3] = {{1, 1, 1}, {2, 1, 1}};
        srd_bricks_out out;
        BENCH_CHECK(srd_bricks_run_(&o, pg[m], steps, 0, &out));
        tb[m][r] = out.seconds * 1e9 / ((double)out.n * (double)steps);
        if (m == 1) {
          bpf = (double)out.bytes_sent / ((double)steps * (double)out.faces);
          sent = (double)out.particles_sent / ((double)steps * (double)out.faces);
        }
        srd_bricks_out_free_(&out);
      }
    const double m1 = median(tb[0], R), m2 = median(tb[1], R);
    const double est_layers = 1.0 / 3.0 + 0.01, face = (double)L * L;
    printf("%d^3 bricks: P = 1 %.2f ns/particle-step, P = 2 (2x1x1) %.2f (ratio %.3f); per step and face: %.0f "
           "particles = %.3f layers, %.0f B (estimate %.3f layers, %.0f B)\n",
           L, m1, m2, m2 / m1, sent, sent / (10.0 * face), bpf, est_layers, est_layers * 10.0 * face * 56.0);
  }
  /* the exchange volume over many steps (the shift difference is one draw per step: 600 steps
   * give the mean layer fraction to about 0.24 / sqrt(600) = 0.01) */
  {
    gran_srd_options o = opts(16, GRAN_SRD_CREATE_CELLS);
    const int pg[3] = {2, 1, 1};
    const int64_t steps = 600;
    srd_bricks_out out;
    BENCH_CHECK(srd_bricks_run_(&o, pg, steps, 0, &out));
    const double face = 16.0 * 16.0, per = (double)out.particles_sent / ((double)steps * (double)out.faces);
    printf("16^3, 2 bricks, %lld steps: per step and face %.1f particles = %.4f layers (estimate %.4f), %.0f B "
           "(%.0f B per particle)\n",
           (long long)steps, per, per / (10.0 * face), 1.0 / 3.0 + 0.01,
           (double)out.bytes_sent / ((double)steps * (double)out.faces),
           (double)out.bytes_sent / (double)out.particles_sent);
    srd_bricks_out_free_(&out);
  }
  /* the exact add on values of one scale */
  {
    const int64_t n = (int64_t)1 << 24;
    double *v = malloc((size_t)n * sizeof *v);
    uint64_t z = 802;
    for (int64_t i = 0; i < n; ++i) {
      z = z * 6364136223846793005ULL + 1442695040888963407ULL;
      v[i] = ((double)(z >> 11) / 9007199254740992.0 - 0.5) * 0.02;
    }
    double te[R], tp[R], sink = 0;
    for (int r = 0; r < R; ++r) {
      gran_exactsum a;
      gran_exactsum_init_(&a);
      double t0 = bench_now();
      for (int64_t i = 0; i < n; ++i) gran_exactsum_add_(&a, v[i]);
      sink += gran_exactsum_value_(&a);
      te[r] = (bench_now() - t0) * 1e9 / (double)n;
      t0 = bench_now();
      double p = 0;
      for (int64_t i = 0; i < n; ++i) p += v[i];
      sink += p;
      tp[r] = (bench_now() - t0) * 1e9 / (double)n;
    }
    printf("exact add (values in [-0.01, 0.01]): %.2f ns per add, plain double sum %.2f ns (%d rounds, medians; %g)\n",
           median(te, R), median(tp, R), R, sink * 0);
    free(v);
  }
  return 0;
}
