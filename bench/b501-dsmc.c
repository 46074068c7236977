/* b501-dsmc.c - DSMC engine: speed on Bodrova & Osinsky Table I, low-rank against Bird, the cost
 * of displacement tracking, memory per particle, accuracy versus cost.
 *   BENCH_QUICK=1     N_1 = 1e5 instead of 1e6 (Table I), accuracy table up to N_1 = 1e5
 *   BENCH_DSMC_BIRD=f run Bird to the fraction f of Table I's time (default 1: the whole run; the
 *                     paper variant of Bird always runs to t = 25)
 *   BENCH_DSMC_ONLY=speed  only the speed tables of the three systems
 * Times: wall clock and CPU time of the advance call (the CPU time is the steadier number on a
 * shared machine). Speeds are compared as collisions per CPU second of rows measured in this same
 * run (a partial run is reported as what it measured, never extrapolated), against no typed-in
 * number: machines of one kind differ by 2x. */
#include "bench_util.h" /* first: it sets _POSIX_C_SOURCE */

#include <math.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

static double cpu_now(void) {
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec;
}

/* current resident set size in bytes (/proc/self/statm) */
static double rss_now(void) {
  FILE *f = fopen("/proc/self/statm", "r");
  long pages = 0, res = 0;
  if (f) {
    if (fscanf(f, "%ld %ld", &pages, &res) != 2) res = 0;
    fclose(f);
  }
  return (double)res * 4096.0;
}

/* Table I species: n_k = 0.1 k^-3 while N_k = round(N_1 k^-3) >= 1 */
static int table1_species(double N1) {
  int M = 0;
  while (llround(N1 * pow(M + 1, -3.0)) >= 1) M++;
  return M;
}

typedef struct {
  const char *name;
  int selector, observe;
  double t_end;   /* simulated */
  double frac;    /* fraction of Table I's t = 100 simulated (reported as measured, never extrapolated) */
  int classes;    /* opt.speed_classes */
} variant;

static void table1(double N1) {
  const int M = table1_species(N1);
  gran_mixture *mix;
  BENCH_CHECK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
  double *T0 = malloc(sizeof(double) * (size_t)M);
  for (int k = 0; k < M; k++) T0[k] = 1.0;
  const char *fb = getenv("BENCH_DSMC_BIRD");
  double fbird = fb ? atof(fb) : 1.0;
  if (!(fbird > 0 && fbird <= 1)) fbird = 1.0;
  const variant vs[] = {
      {"low-rank", GRAN_SELECTOR_LOWRANK, 0, 100.0, 1.0, 0},
      {"low-rank + MSD", GRAN_SELECTOR_LOWRANK, GRAN_OBSERVE_DISPLACEMENT, 100.0, 1.0, 0},
      {"low-rank + MSD + counts", GRAN_SELECTOR_LOWRANK, GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS,
       100.0, 1.0, 0},
      {"low-rank, paper's rule", GRAN_SELECTOR_LOWRANK_PAPER, 0, 100.0, 1.0, 0},
      /* speed classes: rows 4, 5 */
      {"low-rank + classes", GRAN_SELECTOR_LOWRANK, 0, 100.0, 1.0, 1},
      {"low-rank + classes + MSD", GRAN_SELECTOR_LOWRANK, GRAN_OBSERVE_DISPLACEMENT, 100.0, 1.0, 1},
      {"Bird", GRAN_SELECTOR_BIRD, 0, 100.0 * fbird, fbird, 0},
      {"Bird + MSD", GRAN_SELECTOR_BIRD, GRAN_OBSERVE_DISPLACEMENT, 100.0 * fbird, fbird, 0},
      {"Bird, paper's rule", GRAN_SELECTOR_BIRD_PAPER, 0, 25.0, 0.25, 0},
      /* the default (speed_classes = GRAN_SPEED_CLASSES_AUTO): row 9 */
      {"low-rank default (auto)", GRAN_SELECTOR_LOWRANK, 0, 100.0, 1.0, GRAN_SPEED_CLASSES_AUTO},
  };
  const int nv = (int)(sizeof vs / sizeof vs[0]);
  printf("\nTable I (Bodrova & Osinsky): N_1 = %.0e, n_k = 0.1 k^-3, N_k = round(N_1 k^-3) >= 1 -> %d species, ", N1, M);
  {
    gran_dsmc_options o;
    BENCH_CHECK(gran_dsmc_options_default(&o));
    o.volume = N1 / 0.1;
    gran_dsmc *sim;
    BENCH_CHECK(gran_dsmc_create(mix, NULL, T0, &o, &sim));
    gran_dsmc_stats st;
    BENCH_CHECK(gran_dsmc_get_stats(sim, &st));
    printf("N = %lld, eps = 0.5, T(0) = 1, t = 100\n", (long long)st.nparticles);
    gran_dsmc_destroy(&sim);
  }
  printf("paper (authors' Fortran, their machine): low-rank 12072722 collisions, 28 s; Bird 12067760, 1128 s;\n"
         "  their E = 1.233e5 is a misprinted exponent: the authors' code prints sum m v^2 = 2.468e4 at N_1 = 1e6,\n"
         "  and E_kin = (1/2) sum m v^2 = 1.234e4\n");
  printf("%-26s %8s %12s %11s %9s %9s %11s %8s %9s\n", "method", "t", "collisions", "E_kin", "wall [s]", "cpu [s]",
         "coll/s(cpu)", "accept", "x paper");
  double rate[16] = {0};
  for (int q = 0; q < nv; q++) {
    gran_dsmc_options o;
    BENCH_CHECK(gran_dsmc_options_default(&o));
    o.selector = vs[q].selector;
    o.observe = vs[q].observe;
    o.volume = N1 / 0.1;
    o.seed = 2024;
    o.speed_classes = vs[q].classes;
    gran_dsmc *sim;
    BENCH_CHECK(gran_dsmc_create(mix, NULL, T0, &o, &sim));
    const double w0 = bench_now(), c0 = cpu_now();
    BENCH_CHECK(gran_dsmc_advance(sim, vs[q].t_end));
    const double wall = bench_now() - w0, cpu = cpu_now() - c0;
    gran_dsmc_stats st;
    double ek;
    BENCH_CHECK(gran_dsmc_get_stats(sim, &st));
    BENCH_CHECK(gran_dsmc_energy(sim, &ek, NULL, NULL));
    rate[q] = (double)st.collisions / cpu;
    printf("%-26s %8.4g %12lld %11.4e %9.2f %9.2f %11.3e %8.4f", vs[q].name, vs[q].t_end, (long long)st.collisions, ek,
           wall, cpu, rate[q], (double)st.collisions / (double)st.trials);
    if (q > 3) printf(" %9.2f", rate[q] / rate[3]);
    else printf(" %9s", q == 3 ? "1" : "");
    if (vs[q].classes) /* speed classes (or auto): moves per collision, overflow re-sorts, raises of top bounds */
      printf("  moves/coll %.2f, overflow re-sorts %lld, raises %lld", (double)st.class_moves / (double)st.collisions,
             (long long)st.class_rebuilds, (long long)st.bound_raises);
    printf("\n");
    fflush(stdout);
    gran_dsmc_destroy(&sim);
  }
  /* "x paper" of the low-rank rows, now that the paper-rule row (q = 3) is measured */
  printf("speed in collisions per CPU second, measured side by side in this run:\n");
  printf("  low-rank / low-rank paper's rule: %.2f without displacements, %.2f with (targets 5.3 and 4.2)\n",
         rate[0] / rate[3], rate[1] / rate[3]);
  printf("  low-rank + speed classes / paper's rule: %.2f without displacements, %.2f with; classes / without: %.2f, %.2f\n",
         rate[4] / rate[3], rate[5] / rate[3], rate[4] / rate[0], rate[5] / rate[1]);
  printf("  low-rank default (auto) / paper's rule: %.2f\n", rate[9] / rate[3]);
  printf("  low-rank / Bird: %.2f (the paper's machine: 1128 s / 28 s = 40 with their codes)\n", rate[0] / rate[6]);
  printf("  Bird / Bird paper's rule: %.2f (the paper-rule row ran to t = 25 only: its rate, not its time, is compared)\n",
         rate[6] / rate[8]);
  free(T0);
  gran_mixture_destroy(&mix);
}

/* Memory per particle: each engine (N_1 as Table I) is made in a child process, so that its peak
 * RSS is its own: peak RSS growth (bench_peak_rss) and current RSS growth while the engine exists,
 * per particle, and the bytes of its particle arrays (gran_particles_memory); without and with
 * displacement arrays. */
static void memory(double N1) {
  const int M = table1_species(N1);
  printf("\nMemory per particle (Table I, N_1 = %.0e): budget 32 B without displacements, 64 B with\n", N1);
  printf("%-22s %12s %16s %16s %16s\n", "observables", "N", "arrays B/part", "RSS B/part", "peak RSS B/part");
  fflush(stdout);
  for (int row = 0; row < 4; row++) {
    const int disp = row & 1, classes = row >> 1; /* rows 2, 3: speed classes */
    const pid_t pid = fork();
    if (pid == 0) {
      gran_mixture *mix;
      BENCH_CHECK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &mix));
      BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
      gran_dsmc_options o;
      BENCH_CHECK(gran_dsmc_options_default(&o));
      o.volume = N1 / 0.1;
      o.observe = disp ? GRAN_OBSERVE_DISPLACEMENT : 0;
      o.speed_classes = classes;
      const double r0 = rss_now(), p0 = bench_peak_rss();
      gran_dsmc *sim;
      BENCH_CHECK(gran_dsmc_create(mix, NULL, NULL, &o, &sim));
      BENCH_CHECK(gran_dsmc_advance(sim, 1.0)); /* touch everything the loop touches */
      const double r1 = rss_now(), p1 = bench_peak_rss();
      const gran_particles *p;
      int64_t bytes;
      BENCH_CHECK(gran_dsmc_particles(sim, &p)); /* with classes: a view filled now (after the RSS readings) */
      BENCH_CHECK(gran_particles_memory(p, &bytes));
      if (classes) /* the slot arrays are internal: only the RSS growth measures them */
        printf("%-22s %12lld %16s %16.1f %16.1f\n", disp ? "classes + MSD" : "classes", (long long)p->n, "-",
               (r1 - r0) / (double)p->n, (p1 - p0) / (double)p->n);
      else
        printf("%-22s %12lld %16.1f %16.1f %16.1f\n", disp ? "MSD (displacements)" : "none", (long long)p->n,
               (double)bytes / (double)p->n, (r1 - r0) / (double)p->n, (p1 - p0) / (double)p->n);
      fflush(stdout);
      _exit(0);
    }
    int status;
    if (pid > 0) waitpid(pid, &status, 0);
  }
}

/* Accuracy versus cost on Bodrova & Osinsky Fig. 2 (binary HCS, eps = 0.5, N_2 = N_1/100): at
 * t = 100 the temperature ratio T_2/T_1 against the HCS value of the theory and MSD_1, MSD_2 against
 * gran_theory_msd_hcs. One run per N: the errors are one realisation (statistical + model). */
static void accuracy(double N1max) {
  double m[2] = {1.0, 100.0}, s[2] = {1.0, cbrt(100.0)}, n[2] = {0.1, 0.001};
  gran_mixture *mix;
  BENCH_CHECK(gran_mixture_create(2, m, s, n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.5));
  double T0[2], tau0, th[2], tot;
  const double t = 100.0;
  BENCH_CHECK(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 0.554, T0, &tau0));
  BENCH_CHECK(gran_theory_msd_hcs(mix, T0, tau0, 1, &t, th, &tot));
  printf("\nAccuracy versus cost: Bodrova & Osinsky Fig. 2 (binary, eps = 0.5, m = (1, 100), T(0) = HCS), t = 100 = 5.2 tau0\n");
  printf("%10s %8s %12s %10s %10s %10s %10s %10s\n", "N_1", "N_2", "collisions", "cpu [s]", "T2/T1 err",
         "MSD_1 err", "MSD_2 err", "MSD err");
  for (double N1 = 1e3; N1 <= N1max * 1.01; N1 *= 10) {
    gran_dsmc_options o;
    BENCH_CHECK(gran_dsmc_options_default(&o));
    o.volume = N1 / 0.1;
    o.observe = GRAN_OBSERVE_DISPLACEMENT;
    o.seed = 7;
    gran_dsmc *sim;
    BENCH_CHECK(gran_dsmc_create(mix, NULL, T0, &o, &sim));
    const double c0 = cpu_now();
    BENCH_CHECK(gran_dsmc_advance(sim, t));
    const double cpu = cpu_now() - c0;
    double T[2], msd[2], mt;
    int64_t cnt[2];
    gran_dsmc_stats st;
    BENCH_CHECK(gran_dsmc_temperatures(sim, T));
    BENCH_CHECK(gran_dsmc_msd(sim, msd, &mt));
    BENCH_CHECK(gran_dsmc_counts(sim, cnt));
    BENCH_CHECK(gran_dsmc_get_stats(sim, &st));
    printf("%10.0e %8lld %12lld %10.3f %+10.4f %+10.4f %+10.4f %+10.4f\n", N1, (long long)cnt[1],
           (long long)st.collisions, cpu, (T[1] / T[0]) / (T0[1] / T0[0]) - 1, msd[0] / th[0] - 1, msd[1] / th[1] - 1,
           mt / tot - 1);
    gran_dsmc_destroy(&sim);
  }
  printf("(relative errors; the theory is Maxwellian: DSMC's T2/T1 drifts ~ +8%% and MSD_1 ~ -2%% at large N)\n");
  gran_mixture_destroy(&mix);
}

/* ---- speed branch: three systems, interleaved repetitions --------------------------------
 * For each system the methods run one after the other, REPS times in turn (the machine may be
 * shared: the minimum CPU time of the advance call per method is reported, and the ratios are of
 * those minima, all from this run). A method that cannot finish the system in reasonable time
 * (Bird on the 1e4-species mixture: a global bound over sigma_k up to 21.5) runs a shorter time t,
 * printed in its row, and is compared by its rate (collisions per CPU second), never extrapolated. */
typedef struct {
  const char *name;
  gran_mixture *mix;
  int64_t *counts; /* NULL: round(n_k V) */
  double volume, t_end, t_bird;
} speed_sys;

static void speed_system(const speed_sys *sy, int reps) {
  const struct { const char *name; int sel, obs, classes; } ms[] = {
      {"low-rank", GRAN_SELECTOR_LOWRANK, 0, 0},
      {"low-rank + MSD", GRAN_SELECTOR_LOWRANK, GRAN_OBSERVE_DISPLACEMENT, 0},
      {"low-rank, paper's rule", GRAN_SELECTOR_LOWRANK_PAPER, 0, 0},
      {"low-rank paper + MSD", GRAN_SELECTOR_LOWRANK_PAPER, GRAN_OBSERVE_DISPLACEMENT, 0},
      {"Bird", GRAN_SELECTOR_BIRD, 0, 0},
      /* speed classes */
      {"low-rank + classes", GRAN_SELECTOR_LOWRANK, 0, 1},
      {"low-rank + classes + MSD", GRAN_SELECTOR_LOWRANK, GRAN_OBSERVE_DISPLACEMENT, 1},
      /* the default: speed_classes = GRAN_SPEED_CLASSES_AUTO, rows 7, 8 */
      {"default (auto)", GRAN_SELECTOR_LOWRANK, 0, GRAN_SPEED_CLASSES_AUTO},
      {"default (auto) + MSD", GRAN_SELECTOR_LOWRANK, GRAN_OBSERVE_DISPLACEMENT, GRAN_SPEED_CLASSES_AUTO},
      {"Bird + MSD", GRAN_SELECTOR_BIRD, GRAN_OBSERVE_DISPLACEMENT, 0},
  };
  enum { NM = 10 };
  int64_t M;
  BENCH_CHECK(gran_mixture_nspecies(sy->mix, &M));
  double *T0 = malloc(sizeof(double) * (size_t)M);
  for (int64_t k = 0; k < M; k++) T0[k] = 1.0;
  double cmin[NM], wmin[NM], rate[NM];
  long long coll[NM], npart = 0, moves[NM], rebuilds[NM];
  double acc[NM];
  for (int q = 0; q < NM; q++) cmin[q] = wmin[q] = INFINITY;
  for (int r = 0; r < reps; r++)
    for (int q = 0; q < NM; q++) {
      gran_dsmc_options o;
      BENCH_CHECK(gran_dsmc_options_default(&o));
      o.selector = ms[q].sel;
      o.observe = ms[q].obs;
      o.volume = sy->volume;
      o.seed = 2024;
      o.speed_classes = ms[q].classes;
      gran_dsmc *sim;
      BENCH_CHECK(gran_dsmc_create(sy->mix, sy->counts, T0, &o, &sim));
      const double te = ms[q].sel == GRAN_SELECTOR_BIRD ? sy->t_bird : sy->t_end;
      const double w0 = bench_now(), c0 = cpu_now();
      BENCH_CHECK(gran_dsmc_advance(sim, te));
      const double wall = bench_now() - w0, cpu = cpu_now() - c0;
      gran_dsmc_stats st;
      BENCH_CHECK(gran_dsmc_get_stats(sim, &st));
      if (cpu < cmin[q]) cmin[q] = cpu;
      if (wall < wmin[q]) wmin[q] = wall;
      coll[q] = (long long)st.collisions;
      acc[q] = (double)st.collisions / (double)st.trials;
      moves[q] = (long long)st.class_moves;
      rebuilds[q] = (long long)st.class_rebuilds;
      npart = (long long)st.nparticles;
      gran_dsmc_destroy(&sim);
    }
  printf("\n%s: %lld species, N = %lld, t = %g; %d interleaved repetitions, min times\n", sy->name, (long long)M, npart,
         sy->t_end, reps);
  printf("%-24s %8s %12s %9s %9s %11s %8s %12s\n", "method", "t", "collisions", "wall [s]", "cpu [s]", "coll/s(cpu)",
         "accept", "/ paper rule");
  for (int q = 0; q < NM; q++) rate[q] = (double)coll[q] / cmin[q];
  for (int q = 0; q < NM; q++) {
    const double te = ms[q].sel == GRAN_SELECTOR_BIRD ? sy->t_bird : sy->t_end;
    printf("%-24s %8.4g %12lld %9.2f %9.2f %11.3e %8.4f %12.2f", ms[q].name, te, coll[q], wmin[q], cmin[q], rate[q],
           acc[q], rate[q] / rate[ms[q].obs ? 3 : 2]);
    if (ms[q].classes)
      printf("  moves/coll %.2f, overflow re-sorts %lld", (double)moves[q] / (double)coll[q], rebuilds[q]);
    printf("\n");
  }
  printf("  low-rank / paper's rule: %.2f without displacements, %.2f with (targets 5.3 and 4.2); "
         "low-rank / Bird: %.2f (rates)\n",
         rate[0] / rate[2], rate[1] / rate[3], rate[0] / rate[4]);
  printf("  with speed classes: / paper's rule %.2f without displacements, %.2f with; / without classes %.2f, %.2f\n",
         rate[5] / rate[2], rate[6] / rate[3], rate[5] / rate[0], rate[6] / rate[1]);
  printf("  default (auto: classes %s): / paper's rule %.2f without displacements, %.2f with (targets 5.3 "
         "and 4.2); / the faster of off and on %.2f, %.2f\n",
         moves[7] > 0 ? "on" : "off", rate[7] / rate[2], rate[8] / rate[3],
         rate[7] / (rate[0] > rate[5] ? rate[0] : rate[5]), rate[8] / (rate[1] > rate[6] ? rate[1] : rate[6]));
  printf("  Bird: %.3e collisions/s without displacements, %.3e with; low-rank default / Bird %.2f, %.2f (rates)\n",
         rate[4], rate[9], rate[7] / rate[4], rate[8] / rate[9]);
  fflush(stdout);
  free(T0);
}

static void speed_tables(double N1, int reps) {
  printf("\nSpeed of the low-rank selector against the paper's rule and Bird, measured side by side\n");
  speed_sys sy;
  /* Table I */
  const int M1 = table1_species(N1);
  BENCH_CHECK(gran_mixture_create_powerlaw(M1, 1.0, 1.0, 0.1, 3.0, &sy.mix));
  BENCH_CHECK(gran_mixture_set_restitution(sy.mix, 0.5));
  sy.name = "Table I";
  sy.counts = NULL;
  sy.volume = N1 / 0.1;
  sy.t_end = sy.t_bird = 100.0;
  speed_system(&sy, reps);
  gran_mixture_destroy(&sy.mix);
  /* monodisperse, N = N_1 */
  {
    double m = 1, sg = 1, n = 0.1;
    BENCH_CHECK(gran_mixture_create(1, &m, &sg, &n, &sy.mix));
  }
  BENCH_CHECK(gran_mixture_set_restitution(sy.mix, 0.5));
  sy.name = "Monodisperse (n = 0.1, eps = 0.5, T(0) = 1)";
  speed_system(&sy, reps);
  gran_mixture_destroy(&sy.mix);
  /* 1e4-species power law theta = 3: N_k = max(1, round(N_1 k^-3)) */
  const int64_t M = 10000;
  BENCH_CHECK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &sy.mix));
  BENCH_CHECK(gran_mixture_set_restitution(sy.mix, 0.5));
  sy.counts = malloc(sizeof(int64_t) * (size_t)M);
  for (int64_t k = 0; k < M; k++) {
    const long long c = llround(N1 * pow((double)(k + 1), -3.0));
    sy.counts[k] = c > 1 ? c : 1;
  }
  sy.name = "Power law theta = 3, 1e4 species (N_k = max(1, round(N_1 k^-3)), eps = 0.5, T(0) = 1)";
  sy.t_end = 10.0;
  sy.t_bird = 1.0;
  speed_system(&sy, reps);
  free(sy.counts);
  gran_mixture_destroy(&sy.mix);
}

int main(void) {
  const int quick = bench_quick();
  const double N1 = quick ? 1e5 : 1e6;
  printf("b501-dsmc: DSMC engine%s\n", quick ? " (BENCH_QUICK=1: reduced sizes)" : "");
  const char *only = getenv("BENCH_DSMC_ONLY");
  const int all = !(only && strcmp(only, "speed") == 0);
  if (all) memory(N1);
  if (all) table1(N1);
  speed_tables(N1, quick ? 2 : 3);
  if (all) accuracy(quick ? 1e5 : 1e6);
  return 0;
}
