/* b201-segtree.c - cost of the sum tree: ns per sample (one uniform, O(log M) descent) and per
 * update (leaf + its ancestors), single and batched, for M = 10 .. 10^6 leaves. Indices and
 * uniforms are drawn beforehand, so the table shows the tree alone; large trees are bound by
 * memory latency (random leaves: one cache miss per level once the tree exceeds the caches). */
#include "bench_util.h"

#include <stdint.h>

#define NPRE 65536

int main(void) {
  const int64_t ms[] = {10, 1000, 100000, 1000000};
  const int64_t nop = bench_quick() ? 1 << 20 : 1 << 24;
  double *u = malloc(sizeof(double) * NPRE), *w = malloc(sizeof(double) * NPRE);
  int64_t *idx = malloc(sizeof(int64_t) * NPRE);
  if (!u || !w || !idx) return 1;
  gran_rng g;
  BENCH_CHECK(gran_rng_seed(&g, 201));
  BENCH_CHECK(gran_rng_uniform(&g, NPRE, u));
  BENCH_CHECK(gran_rng_exponential(&g, NPRE, w));
  printf("b201-segtree: %lld operations per cell\n", (long long)nop);
  printf("%10s %10s %12s %12s %14s %14s %10s\n", "M", "depth", "ns/sample", "ns/update", "ns/upd batch64",
         "ns/upd b4096", "MB");
  int64_t check = 0;
  for (size_t c = 0; c < sizeof ms / sizeof *ms; c++) {
    const int64_t m = ms[c];
    double *w0 = malloc(sizeof(double) * (size_t)m);
    if (!w0) return 1;
    BENCH_CHECK(gran_rng_exponential(&g, m, w0));
    gran_segtree t;
    BENCH_CHECK(gran_segtree_init(&t, m, w0));
    uint64_t r[1];
    for (int i = 0; i < NPRE; i++) {
      BENCH_CHECK(gran_rng_u64(&g, 1, r));
      idx[i] = (int64_t)(r[0] % (uint64_t)m);
    }
    int depth = 0;
    while ((INT64_C(1) << depth) < t.base) depth++;

    double t0 = bench_now();
    for (int64_t k = 0; k < nop; k++) {
      int64_t i;
      gran_segtree_sample(&t, u[k & (NPRE - 1)], &i);
      check += i;
    }
    const double ns_sample = 1e9 * (bench_now() - t0) / (double)nop;

    t0 = bench_now();
    for (int64_t k = 0; k < nop; k++) gran_segtree_set(&t, idx[k & (NPRE - 1)], w[k & (NPRE - 1)]);
    const double ns_update = 1e9 * (bench_now() - t0) / (double)nop;

    double ns_batch[2];
    const int64_t bs[2] = {64, 4096};
    for (int b = 0; b < 2; b++) {
      t0 = bench_now();
      for (int64_t k = 0; k < nop; k += bs[b]) {
        const int64_t off = k & (NPRE - 1);
        BENCH_CHECK(gran_segtree_set_batch(&t, bs[b], idx + off, w + off));
      }
      ns_batch[b] = 1e9 * (bench_now() - t0) / (double)nop;
    }
    printf("%10lld %10d %12.1f %12.1f %14.1f %14.1f %10.2f\n", (long long)m, depth, ns_sample, ns_update, ns_batch[0],
           ns_batch[1], 16.0 * (double)t.base / 1e6);
    BENCH_CHECK(gran_segtree_free(&t));
    free(w0);
  }
  free(u);
  free(w);
  free(idx);
  return check == -1 ? 2 : 0;
}
