/* b101-rng.c - cost of random numbers: ns per value for u64, uniform, normal, exponential and unit
 * vectors. "batch" = one call filling 4096 values: a loop over the inline core (what hot loops in
 * the engines pay, plus one store); "single" = one library call per value (call overhead
 * included). GPU column: gran_cuda_rng_uniform including transfers, when a GPU is present. */
#include "bench_util.h"

#include <stdint.h>

#define NB 4096

typedef int (*draw_fn)(gran_rng *, int64_t, double *);

static double sink = 0;

static double ns_batch(draw_fn f, int64_t total) {
  static double buf[3 * NB];
  gran_rng g;
  BENCH_CHECK(gran_rng_seed(&g, 1));
  const double t0 = bench_now();
  for (int64_t done = 0; done < total; done += NB) {
    BENCH_CHECK(f(&g, NB, buf));
    sink += buf[NB / 2];
  }
  return 1e9 * (bench_now() - t0) / (double)total;
}

static double ns_single(draw_fn f, int64_t total) {
  double x[3];
  gran_rng g;
  BENCH_CHECK(gran_rng_seed(&g, 1));
  const double t0 = bench_now();
  for (int64_t i = 0; i < total; i++) {
    f(&g, 1, x);
    sink += x[0];
  }
  return 1e9 * (bench_now() - t0) / (double)total;
}

/* raw outputs: own buffer type */
static double ns_u64(int64_t total, int batch) {
  static uint64_t buf[NB];
  gran_rng g;
  BENCH_CHECK(gran_rng_seed(&g, 1));
  const int nb = batch ? NB : 1;
  const double t0 = bench_now();
  for (int64_t done = 0; done < total; done += nb) {
    BENCH_CHECK(gran_rng_u64(&g, nb, buf));
    sink += (double)buf[0];
  }
  return 1e9 * (bench_now() - t0) / (double)total;
}

int main(void) {
  const int64_t total = bench_quick() ? 1 << 20 : 1 << 25;
  const struct {
    const char *name;
    draw_fn f;
  } rows[] = {{"uniform [0,1)", gran_rng_uniform},       {"uniform (0,1]", gran_rng_uniform_pos},
              {"exponential", gran_rng_exponential},     {"normal (polar)", gran_rng_normal},
              {"unit vector 3-D", gran_rng_unit_vector3}, {"unit vector 2-D", gran_rng_unit_vector2}};
  printf("b101-rng: xoshiro256**, %lld values per row\n", (long long)total);
  printf("%-18s %14s %14s\n", "distribution", "batch ns/value", "single ns/val");
  printf("%-18s %14.2f %14.2f\n", "u64", ns_u64(total, 1), ns_u64(total / 4, 0));
  for (size_t r = 0; r < sizeof rows / sizeof *rows; r++)
    printf("%-18s %14.2f %14.2f\n", rows[r].name, ns_batch(rows[r].f, total),
           ns_single(rows[r].f, total / 4));

  /* seeding, jumps, streams */
  gran_rng g;
  const int nj = bench_quick() ? 1000 : 20000;
  double t0 = bench_now();
  for (int i = 0; i < nj; i++) BENCH_CHECK(gran_rng_jump(&g));
  const double t_jump = (bench_now() - t0) / nj;
  t0 = bench_now();
  for (int i = 0; i < nj; i++) BENCH_CHECK(gran_rng_stream(7, (uint64_t)i * 2654435761u, &g));
  const double t_stream = (bench_now() - t0) / nj;
  t0 = bench_now();
  for (int i = 0; i < nj; i++) BENCH_CHECK(gran_rng_stream(7, UINT64_MAX - (uint64_t)i, &g));
  const double t_stream_max = (bench_now() - t0) / nj;
  printf("\n%-40s %10.2f us\n", "jump (2^128 steps)", 1e6 * t_jump);
  printf("%-40s %10.2f us\n", "stream(seed, id), id < 2^46 (typical)", 1e6 * t_stream);
  printf("%-40s %10.2f us\n", "stream(seed, id), id ~ 2^64 (worst)", 1e6 * t_stream_max);

  /* GPU */
  const int64_t nstreams = 10000, nper = bench_quick() ? 100 : 1000;
  gran_rng *st = malloc(sizeof(gran_rng) * (size_t)nstreams);
  double *out = malloc(sizeof(double) * (size_t)(nstreams * nper));
  if (!st || !out) return 1;
  for (int64_t k = 0; k < nstreams; k++) BENCH_CHECK(gran_rng_stream(3, (uint64_t)k, &st[k]));
  t0 = bench_now();
  const int ierr = gran_cuda_rng_uniform(st, nstreams, nper, out);
  const double t_gpu = bench_now() - t0;
  if (ierr == GRAN_SUCCESS)
    printf("%-40s %10.3f ns/value (%lld streams x %lld, transfers included)\n", "GPU uniform", 1e9 * t_gpu / (nstreams * nper),
           (long long)nstreams, (long long)nper);
  else
    printf("%-40s n/a: %s\n", "GPU uniform", gran_last_error_message());
  free(st);
  free(out);
  return sink == 12345.678 ? 2 : 0;
}
