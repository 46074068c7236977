/* b503-cell.c - the time-step/cell selector (the DSMC outline) against the low-rank event selector:
 *   1. collisions per CPU second on a monodisperse gas (N = 1e5 and 1e6; BENCH_QUICK: 1e5), eps = 0.8,
 *      about 20 particles per cell, dt = tau/10, tau/4 and tau/2 (tau the mean free time), to t = 5 tau;
 *   2. the same on Bodrova & Osinsky's Table I system (N_1 = 1e6; quick 1e5), to t = 5 (Table I runs to 100);
 *   3. the cost of aggregation and fragmentation on (e_agg, e_frag set so that a few % of the
 *      collisions merge or shatter; the mixture holds k-mers) against off, per collision;
 *   4. accuracy versus cost: an elastic gas to t = 10 tau (N = 1e5; quick 2e4), dt from tau to tau/16
 *      and 1 or ~20 particles per cell: the MSD, T and collision count relative to the low-rank
 *      selector's, and the CPU time.
 * Ratios are of rows measured side by side in this run (CPU seconds of the advance calls); no
 * number is typed in. Section 1 also prints the CPU seconds of the creations (outside the ratio, for
 * both selectors; the cell selector's includes its first sort into cell order). On a shared machine the CPU time is the steadier number.
 * B503_ONLY=mono runs section 1 only. */
#include "bench_util.h" /* first: it sets _POSIX_C_SOURCE */

#include <math.h>
#include <string.h>
#include <sys/resource.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double cpu_now(void) {
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec;
}

typedef struct {
  double cpu, wall;
  int64_t coll;
  double T, msd;
} run_out;

static gran_dsmc *make(const gran_mixture *mix, const double *T0, double volume, int cell, double dt, int64_t cells,
                       double e_agg, double e_frag, int observe, uint64_t seed) {
  gran_dsmc_options o;
  BENCH_CHECK(gran_dsmc_options_default(&o));
  o.seed = seed;
  o.volume = volume;
  o.observe = observe;
  gran_dsmc *d = NULL;
  if (cell) {
    gran_dsmc_cell_options c;
    BENCH_CHECK(gran_dsmc_cell_options_default(&c));
    c.dt = dt;
    c.cells = cells;
    c.e_agg = e_agg;
    c.e_frag = e_frag;
    c.eps_f = 0.7;
    BENCH_CHECK(gran_dsmc_create_cell(mix, NULL, T0, &o, &c, &d));
  } else {
    BENCH_CHECK(gran_dsmc_create(mix, NULL, T0, &o, &d));
  }
  return d;
}

static run_out run(gran_dsmc *d, double t) {
  run_out r;
  const double c0 = cpu_now(), w0 = bench_now();
  BENCH_CHECK(gran_dsmc_advance(d, t));
  r.cpu = cpu_now() - c0;
  r.wall = bench_now() - w0;
  gran_dsmc_stats st;
  BENCH_CHECK(gran_dsmc_get_stats(d, &st));
  r.coll = st.collisions;
  double *T = malloc(sizeof(double) * (size_t)st.nspecies);
  BENCH_CHECK(gran_dsmc_temperatures(d, T));
  r.T = T[0];
  free(T);
  r.msd = NAN;
  const gran_particles *p;
  BENCH_CHECK(gran_dsmc_particles(d, &p));
  if (p->r) BENCH_CHECK(gran_dsmc_msd(d, NULL, &r.msd));
  return r;
}

static int64_t cells_for(double N, double per) {
  int64_t c = (int64_t)llround(cbrt(N / per));
  return c < 1 ? 1 : c > 1024 ? 1024 : c;
}

/* reps seeds of one row of the monodisperse table (cell: the cell selector with dt, nc cells per
 * side), summed (T their mean); *create the CPU seconds of the creations, outside the ratio (the cell
 * selector sorts its particles into cell order there) */
static run_out mono_row(const gran_mixture *mix, double N, double n, double T0, double t, int cell, double dt,
                        int64_t nc, int reps, double *create) {
  run_out sum = {0, 0, 0, 0, 0};
  *create = 0;
  for (int r = 0; r < reps; r++) {
    const double c0 = cpu_now();
    gran_dsmc *d = make(mix, &T0, N / n, cell, dt, nc, 0, INFINITY, 0, 1 + (uint64_t)r);
    *create += cpu_now() - c0;
    const run_out o = run(d, t);
    gran_dsmc_destroy(&d);
    sum.cpu += o.cpu;
    sum.coll += o.coll;
    sum.T += o.T / reps;
  }
  return sum;
}

static void mono_speed(double N) {
  const double n = 0.01, eps = 0.8, T0 = 1;
  gran_mixture *mix;
  const double m = 1, s = 1;
  BENCH_CHECK(gran_mixture_create(1, &m, &s, &n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, eps));
  const double tau = 1 / (4 * sqrt(M_PI) * n), t = 5 * tau;
  const int64_t nc = cells_for(N, 20);
  const int reps = N < 1e6 ? (int)(1e6 / N) : 1; /* seeds, so that each row runs ~1e6 particles to 5 tau */
  double ca;
  const run_out ra = mono_row(mix, N, n, T0, t, 0, 0, 0, reps, &ca);
  printf("monodisperse N = %.0f, eps = 0.8, to t = 5 tau (%d seed%s; T(t) their mean):\n", N, reps, reps > 1 ? "s" : "");
  printf("  %-34s %10s %8s %14s %8s %9s\n", "selector", "collisions", "CPU s", "collisions/s", "T(t)", "create s");
  printf("  %-34s %10lld %8.2f %14.3e %8.5f %9.3f\n", "low-rank", (long long)ra.coll, ra.cpu, ra.coll / ra.cpu, ra.T,
         ca);
  const int div[3] = {10, 4, 2};
  double ratio[3];
  for (int q = 0; q < 3; q++) {
    double cb;
    const run_out rb = mono_row(mix, N, n, T0, t, 1, tau / div[q], nc, reps, &cb);
    char name[64];
    snprintf(name, sizeof name, "cell (%lld^3 cells, dt = tau/%d)", (long long)nc, div[q]);
    printf("  %-34s %10lld %8.2f %14.3e %8.5f %9.3f\n", name, (long long)rb.coll, rb.cpu, rb.coll / rb.cpu, rb.T, cb);
    ratio[q] = (rb.coll / rb.cpu) / (ra.coll / ra.cpu);
  }
  printf("  cell / low-rank collisions per CPU second: %.2f at dt = tau/10 (target >= 0.5), %.2f at tau/4, %.2f at tau/2\n\n",
         ratio[0], ratio[1], ratio[2]);
  gran_mixture_destroy(&mix);
}

static void table1_speed(double N1) {
  int M = 0;
  while (llround(N1 * pow(M + 1, -3.0)) >= 1) M++;
  gran_mixture *mix;
  BENCH_CHECK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
  double *T0 = malloc(sizeof(double) * (size_t)M);
  for (int k = 0; k < M; k++) T0[k] = 1.0;
  const double V = N1 / 0.1, t = 5;
  double Ntot = 0;
  for (int k = 0; k < M; k++) Ntot += (double)llround(N1 * pow(k + 1, -3.0));
  const double tau1 = 1 / (4 * sqrt(M_PI) * 0.1); /* monomer-monomer mean free time */
  const int64_t nc = cells_for(Ntot, 20);
  gran_dsmc *a = make(mix, T0, V, 0, 0, 0, 0, INFINITY, 0, 2);
  gran_dsmc *b = make(mix, T0, V, 1, tau1 / 10, nc, 0, INFINITY, 0, 2);
  const run_out ra = run(a, t), rb = run(b, t);
  printf("Table I system (N_1 = %.0f, %d species, %.0f particles, eps = 0.5), to t = %g:\n", N1, M, Ntot, t);
  printf("  %-34s %10lld %8.2f %14.3e\n", "low-rank", (long long)ra.coll, ra.cpu, ra.coll / ra.cpu);
  char name[64];
  snprintf(name, sizeof name, "cell (%lld^3 cells, dt = tau_1/10)", (long long)nc);
  printf("  %-34s %10lld %8.2f %14.3e\n", name, (long long)rb.coll, rb.cpu, rb.coll / rb.cpu);
  printf("  cell / low-rank collisions per CPU second: %.2f (the cell majorant uses the largest diameter\n"
         "  in the cell: acceptance falls as (sigma_pair / sigma_max)^2)\n\n",
         (rb.coll / rb.cpu) / (ra.coll / ra.cpu));
  gran_dsmc_destroy(&a);
  gran_dsmc_destroy(&b);
  free(T0);
  gran_mixture_destroy(&mix);
}

static void agg_cost(double N) {
  enum { M = 8 };
  double n[M] = {0.01}, T0[M];
  for (int k = 0; k < M; k++) T0[k] = 1;
  gran_mixture *mix;
  BENCH_CHECK(gran_mixture_create(M, NULL, NULL, n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.8));
  const double tau = 1 / (4 * sqrt(M_PI) * 0.01), t = 3 * tau;
  const int64_t nc = cells_for(N, 20);
  gran_dsmc *a = make(mix, T0, N / 0.01, 1, tau / 10, nc, 0, INFINITY, 0, 3);
  gran_dsmc *b = make(mix, T0, N / 0.01, 1, tau / 10, nc, 0.1, 6.0, 0, 3);
  const run_out ra = run(a, t), rb = run(b, t);
  gran_dsmc_cluster_stats cs;
  BENCH_CHECK(gran_dsmc_get_cluster_stats(b, &cs));
  printf("aggregation and fragmentation, N = %.0f monomers, to t = 3 tau:\n", N);
  printf("  off: %lld collisions, %.2f CPU s, %.3e /s\n", (long long)ra.coll, ra.cpu, ra.coll / ra.cpu);
  printf("  on (e_agg = 0.1, e_frag = 6: %lld merges, %lld breakups, %lld bounces): %lld collisions, %.2f CPU s, "
         "%.3e /s\n",
         (long long)cs.merges, (long long)cs.breakups, (long long)cs.bounces, (long long)rb.coll, rb.cpu,
         rb.coll / rb.cpu);
  printf("  cost per collision on / off: %.2f (target <= 1.5)\n\n", (rb.cpu / rb.coll) / (ra.cpu / ra.coll));
  gran_dsmc_destroy(&a);
  gran_dsmc_destroy(&b);
  gran_mixture_destroy(&mix);
}

static void accuracy(double N) {
  const double n = 0.01, T0 = 1, m = 1, s = 1;
  gran_mixture *mix;
  BENCH_CHECK(gran_mixture_create(1, &m, &s, &n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 1.0));
  const double tau = 1 / (4 * sqrt(M_PI) * n), t = 10 * tau;
  gran_dsmc *a = make(mix, &T0, N / n, 0, 0, 0, 0, INFINITY, GRAN_OBSERVE_DISPLACEMENT, 4);
  const run_out ra = run(a, t);
  gran_dsmc_destroy(&a);
  printf("accuracy versus cost: elastic gas, N = %.0f, to t = 10 tau (one seed: differences below ~1 %% are noise)\n",
         N);
  printf("  %-30s %8s %10s %10s %10s\n", "run", "CPU s", "MSD/ref", "T/ref", "coll/ref");
  printf("  %-30s %8.2f %10.4f %10.4f %10.4f\n", "low-rank (ref)", ra.cpu, 1.0, 1.0, 1.0);
  const double dts[3] = {1, 0.25, 1.0 / 16};
  const int64_t ncs[2] = {1, cells_for(N, 20)};
  for (int q = 0; q < 2; q++)
    for (int i = 0; i < 3; i++) {
      gran_dsmc *b = make(mix, &T0, N / n, 1, dts[i] * tau, ncs[q], 0, INFINITY, GRAN_OBSERVE_DISPLACEMENT, 4);
      const run_out rb = run(b, t);
      char name[64];
      snprintf(name, sizeof name, "cell %lld^3, dt = tau/%g", (long long)ncs[q], 1 / dts[i]);
      printf("  %-30s %8.2f %10.4f %10.4f %10.4f\n", name, rb.cpu, rb.msd / ra.msd, rb.T / ra.T,
             (double)rb.coll / (double)ra.coll);
      gran_dsmc_destroy(&b);
    }
  printf("\n");
  gran_mixture_destroy(&mix);
}

int main(void) {
  const int quick = bench_quick();
  printf("b503-cell: time-step/cell selector against the low-rank selector (CPU seconds; ratios from this run)\n\n");
  mono_speed(1e5);
  if (!quick) mono_speed(1e6);
  const char *only = getenv("B503_ONLY");
  if (only && strcmp(only, "mono") == 0) return 0;
  table1_speed(quick ? 1e5 : 1e6);
  agg_cost(quick ? 1e5 : 1e6);
  accuracy(quick ? 2e4 : 1e5);
  return 0;
}
