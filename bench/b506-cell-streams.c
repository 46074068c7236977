/* b506-cell-streams.c - the cell selector's streams by cell (GRAN_CELL_STREAMS_CELLS) against its
 * serial streams: a monodisperse gas (eps = 0.8, about 20 particles per cell, dt = tau/4, tau the
 * mean free time) at N = 2e5 and 1e6 (BENCH_QUICK: 2e5), stepped 20 steps after its creation:
 *   - serial streams (one thread: the serial streams have no threads);
 *   - streams by cell on 1 thread and on every thread of the machine (gran_set_threads: 1, then the
 *     OpenMP default), whose final states are checked equal (collisions, ledger) before any time is
 *     reported.
 * Rows: the wall seconds per step (min of 3 rounds, the variants alternated in each round),
 * particle-steps per second, the creation's wall seconds, and the ratios by cell / serial (1 thread)
 * and by cell at T threads / by cell at 1 thread (the threads' speed-up), all measured in this run. */
#include "bench_util.h" /* first: it sets _POSIX_C_SOURCE */

#include <math.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct {
  double step, create;
  int64_t coll;
  double ed;
} result;

static result run(int64_t N, int streams, int threads) {
  const double n = 0.01;
  double m = 1, s = 1;
  gran_mixture *mix = NULL;
  BENCH_CHECK(gran_mixture_create(1, &m, &s, &n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.8));
  gran_dsmc_options o;
  BENCH_CHECK(gran_dsmc_options_default(&o));
  o.selector = GRAN_SELECTOR_CELL;
  o.seed = 5;
  o.volume = (double)N / n;
  gran_dsmc_cell_options c;
  BENCH_CHECK(gran_dsmc_cell_options_default(&c));
  const double tau = 1.0 / (4.0 * sqrt(M_PI) * n); /* mean free time at T = 1 */
  c.dt = tau / 4;
  c.cells = (int64_t)llround(cbrt((double)N / 20.0));
  c.streams = streams;
  BENCH_CHECK(gran_set_threads(threads));
  gran_dsmc *d = NULL;
  const double t0 = bench_now();
  BENCH_CHECK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d));
  const double t1 = bench_now();
  BENCH_CHECK(gran_dsmc_advance(d, 20 * c.dt));
  const double t2 = bench_now();
  result r;
  r.create = t1 - t0;
  r.step = (t2 - t1) / 20;
  gran_dsmc_stats st;
  BENCH_CHECK(gran_dsmc_get_stats(d, &st));
  r.coll = st.collisions;
  double e, e0;
  BENCH_CHECK(gran_dsmc_energy(d, &e, &e0, &r.ed));
  gran_dsmc_destroy(&d);
  gran_mixture_destroy(&mix);
  BENCH_CHECK(gran_set_threads(0));
  return r;
}

int main(void) {
  int32_t all = 1;
  BENCH_CHECK(gran_set_threads(0));
  BENCH_CHECK(gran_get_threads(&all));
  const int64_t sizes[2] = {200000, 1000000};
  const int nsize = bench_quick() ? 1 : 2;
  printf("b506: cell selector, serial streams against streams by cell (1 and %d threads), 20 steps, min of 3\n", (int)all);
  printf("%9s %-16s %8s %12s %14s %10s\n", "N", "streams", "threads", "s/step", "part-steps/s", "create s");
  for (int z = 0; z < nsize; z++) {
    const int64_t N = sizes[z];
    result best[3];
    const int streams[3] = {GRAN_CELL_STREAMS_SERIAL, GRAN_CELL_STREAMS_CELLS, GRAN_CELL_STREAMS_CELLS};
    const int threads[3] = {1, 1, (int)all};
    for (int round = 0; round < 3; round++)
      for (int v = 0; v < 3; v++) {
        const result r = run(N, streams[v], threads[v]);
        if (round == 0 || r.step < best[v].step) {
          const double cr = round == 0 ? r.create : fmin(best[v].create, r.create);
          best[v] = r;
          best[v].create = cr;
        }
      }
    if (best[1].coll != best[2].coll || memcmp(&best[1].ed, &best[2].ed, sizeof(double)) != 0) {
      fprintf(stderr, "b506: streams by cell differ between 1 and %d threads (collisions %lld, %lld)\n", (int)all,
              (long long)best[1].coll, (long long)best[2].coll);
      return 1;
    }
    const char *names[3] = {"serial", "cells", "cells"};
    for (int v = 0; v < 3; v++)
      printf("%9lld %-16s %8d %12.5f %14.4g %10.3f\n", (long long)N, names[v], threads[v], best[v].step,
             (double)N / best[v].step, best[v].create);
    printf("%9lld ratio by cell / serial (1 thread): %.2f of the rate; by cell %d threads / 1 thread: %.2fx\n",
           (long long)N, best[0].step / best[1].step, (int)all, best[1].step / best[2].step);
  }
  return 0;
}
