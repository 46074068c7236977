/* b803-srd-mpi.c - one GSRD gas over MPI processes (`granary decompose`, one brick per process):
 * the rate of each process on P = 1 and 2 processes of this machine, side by side in one run
 * (interleaved rounds, medians), the bytes each process sends per step, and from those a model of
 * weak scaling to 1,000 processes on two stated networks.
 *
 * Set-up (the comparison): 3-D, n0 = 10, dt = 0.1, kT = 1, alpha = 130, sort every 50,
 * creation by cells, one thread per process; 64^3 cells (BENCH_QUICK=1: 32^3), 100 steps (20),
 * 3 rounds (2). P = 1 is the same program with one brick (the undivided decomposable engine: the
 * same code path, no exchange); P = 2 splits x in two (2 x 1 x 1). The rate of a process is its
 * particle-steps over the wall time of its steps (creation left out); with 2 processes on 2 cores
 * the measurement needs the machine otherwise idle (the load is printed: above about 0.5 the
 * ratio measures the other work). Also printed: the CPU seconds of all processes per
 * particle-step (an MPI process that waits spins, so it includes the waits), and the time of one
 * S(k) of the final state (`--sk 32`) in each, and of one observation (gran_srd_observe's values of
 * the split gas: the unshifted cells gathered, exact sums), against the time of one step; and the
 * time of one checkpoint of `granary run` (one process's file against a split gas's set of parts).
 *
 * Model (per step of a process holding a 64^3 brick in a 3-D split of P processes, 26 neighbours):
 * t = t_comp + t_comm, t_comp = n_rank / r2 (r2 the measured rate per process at P = 2),
 * t_comm = 2 log2(P) (alpha + 4.4 kB / beta) / 64 (the ledger's exact all-reduce: 4.4 kB records,
 *          one all-reduce per 64 steps)
 *        + 2 log2(P) alpha (the exchange's closing barrier)
 *        + 26 alpha (the messages to the 26 neighbours, not overlapped)
 *        + 6 F / beta (F the bytes per face measured here, scaled to a 64^3 face).
 * Networks: TCP over 10 GbE (alpha = 50 us, beta = 1.25 GB/s); InfiniBand HDR (2 us, 12 GB/s). */
#define _DEFAULT_SOURCE /* getloadavg */
#include "bench_util.h"

#include <math.h>
#include <sys/resource.h>
#include <unistd.h>

static double children_cpu(void) {
  struct rusage ru;
  getrusage(RUSAGE_CHILDREN, &ru);
  return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
         1e-6 * (double)ru.ru_stime.tv_usec;
}

/* the number after "key": in a one-line JSON object (NaN if absent) */
static double jget(const char *js, const char *key) {
  char pat[128];
  snprintf(pat, sizeof pat, "\"%s\": ", key);
  const char *p = strstr(js, pat);
  return p ? strtod(p + strlen(pat), NULL) : NAN;
}

typedef struct {
  double secs, rate, bytes, cpu, particles, far, sk, obs, open;
} run_t;

enum { kSkBins = 32 }; /* S(k) of the final state, in as many shells */
static const char *kEnv = "OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                          "OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_btl=self,vader "
                          "OMPI_MCA_mpi_yield_when_idle=1";

/* the JSON report of a started command (exits on failure) */
static void report_of(FILE *p, const char *cmd, char *js, size_t njs) {
  js[0] = 0;
  char line[8192];
  while (fgets(line, sizeof line, p))
    if (line[0] == '{') snprintf(js, njs, "%s", line);
  const int rc = pclose(p);
  if (rc != 0 || !js[0]) {
    fprintf(stderr, "b803: '%s' failed (status %d)\n", cmd, rc);
    exit(1);
  }
}

static FILE *start(const char *cmd) {
  FILE *p = popen(cmd, "r");
  if (!p) {
    fprintf(stderr, "b803: cannot run %s\n", cmd);
    exit(1);
  }
  return p;
}

static run_t run(const char *cli, const char *scene, int P, int steps) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s mpirun --oversubscribe -n %d %s decompose %s --bricks %s --steps %d --sk %d --json 2>&1", kEnv, P,
           cli, scene, P == 1 ? "1x1x1" : "2x1x1", steps, kSkBins);
  const double c0 = children_cpu();
  static char js[8192];
  report_of(start(cmd), cmd, js, sizeof js);
  run_t r;
  r.cpu = children_cpu() - c0;
  r.secs = jget(js, "seconds_max");
  r.rate = jget(js, "rank0_particle_steps_per_second");
  r.bytes = jget(js, "bytes_per_step_per_brick");
  r.particles = jget(js, "particles");
  r.far = P > 1 ? jget(js, "messages_beyond_neighbours") : 0;
  r.sk = jget(js, "sk_seconds");
  r.obs = jget(js, "observe_seconds");
  r.open = jget(js, "open_seconds");
  return r;
}

/* two undivided halves side by side (one process each, different seeds): the rate of each */
static void run_halves(const char *cli, const char *half, int steps, double rate[2]) {
  char cmd[2][1024];
  FILE *p[2];
  for (int k = 0; k < 2; ++k) {
    snprintf(cmd[k], sizeof cmd[k], "%s mpirun --oversubscribe --bind-to none -n 1 %s decompose %s --bricks 1x1x1 --steps %d --set engine.seed=%d --json 2>&1",
             kEnv, cli, half, steps, 11 + k);
    p[k] = start(cmd[k]);
  }
  for (int k = 0; k < 2; ++k) {
    static char js[8192];
    report_of(p[k], cmd[k], js, sizeof js);
    rate[k] = jget(js, "rank0_particle_steps_per_second");
  }
}

static double wall_now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}
/* the wall seconds of `granary run` of the checkpoint scene on P processes, with (ckpt = 1) or
 * without a checkpoint at its output times (exits on failure) */
static double run_scene(const char *cli, const char *scene, int P, int ckpt) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s mpirun --oversubscribe -n %d %s run %s -o /tmp/granary-b803-ck.h5 %s --force -q --no-log "
           ">/dev/null 2>&1", kEnv, P, cli, scene, ckpt ? "--checkpoint /tmp/granary-b803-ck.ckpt --set output.keep_checkpoint=true" : "--no-checkpoint");
  const double t0 = wall_now();
  if (system(cmd) != 0) {
    fprintf(stderr, "b803: '%s' failed\n", cmd);
    exit(1);
  }
  return wall_now() - t0;
}
/* the bytes of the checkpoint and its parts */
static double ckpt_bytes(void) {
  FILE *p = popen("cat /tmp/granary-b803-ck.ckpt* 2>/dev/null | wc -c", "r");
  double b = NAN;
  if (p && fscanf(p, "%lf", &b) != 1) b = NAN;
  if (p) pclose(p);
  return b;
}

static int cmp(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}
static double median(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int main(void) {
  const char *cli = getenv("GRAN_MPI_CLI");
  if (!cli || !*cli || access(cli, X_OK) != 0 || system("command -v mpirun >/dev/null 2>&1") != 0) {
    printf("b803-srd-mpi: skipped (MPI not installed: no mpirun or build/granary-mpi)\n");
    return 0;
  }
  const int quick = bench_quick(), L = quick ? 32 : 64, steps = quick ? 20 : 100, rounds = quick ? 2 : 3;
  const char *scene = "/tmp/granary-b803.toml";
  FILE *f = fopen(scene, "w");
  if (!f) return 1;
  fprintf(f,
          "[engine]\ntype = \"srd\"\ndimension = 3\ncells = [%d, %d, %d]\nn0 = 10\ndt = 0.1\nT0 = 1\nalpha = 130\n"
          "sort_every = 50\nsteps = %d\nseed = 1\nthreads = 1\ncreation = \"cells\"\n",
          L, L, L, steps);
  fclose(f);
  const char *half = "/tmp/granary-b803-half.toml"; /* the brick of a process at P = 2, undivided */
  f = fopen(half, "w");
  if (!f) return 1;
  fprintf(f,
          "[engine]\ntype = \"srd\"\ndimension = 3\ncells = [%d, %d, %d]\nn0 = 10\ndt = 0.1\nT0 = 1\nalpha = 130\n"
          "sort_every = 50\nsteps = %d\nseed = 1\nthreads = 1\ncreation = \"cells\"\n",
          L / 2, L, L, steps);
  fclose(f);
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 1) load[0] = NAN;
  double r1[8], r2[8], ratio[8], c1[8], c2[8], rh[8], ratio_h[8], sk1[8], sk2[8], ob1[8], ob2[8], op1[8], op2[8];
  run_t a = {0}, b = {0};
  for (int k = 0; k < rounds; ++k) {
    a = run(cli, scene, 1, steps);
    b = run(cli, scene, 2, steps);
    r1[k] = a.rate;
    r2[k] = b.rate;
    ratio[k] = b.rate / a.rate;
    sk1[k] = a.sk;
    sk2[k] = b.sk;
    ob1[k] = a.obs;
    ob2[k] = b.obs;
    op1[k] = a.open;
    op2[k] = b.open;
    c1[k] = 1e9 * a.cpu / (a.particles * steps);
    c2[k] = 1e9 * b.cpu / (b.particles * steps);
    double h[2];
    run_halves(cli, half, steps, h);
    rh[k] = 0.5 * (h[0] + h[1]);
    ratio_h[k] = b.rate / rh[k];
  }
  double load_end[3] = {0, 0, 0};
  if (getloadavg(load_end, 3) < 1) load_end[0] = NAN;
  const double m1 = median(r1, rounds), m2 = median(r2, rounds), mr = median(ratio, rounds);
  printf("GSRD over MPI processes (granary decompose): %d^3 cells, n0 = 10, dt = 0.1, %d steps, one thread each, %d "
         "interleaved rounds (load %.2f before, %.2f after)\n",
         L, steps, rounds, load[0], load_end[0]);
  printf("  rate per process, particle-steps/s: P = 1 %.4g, P = 2 (2 x 1 x 1) %.4g; ratio P = 2 / P = 1 per round:", m1, m2);
  for (int k = 0; k < rounds; ++k) printf(" %.3f", ratio[k]);
  printf(" (median %.3f; target >= 0.9)\n", mr);
  printf("  two undivided halves (%d x %d x %d cells each) side by side, one process each: %.4g per process; the split / "
         "the halves per round:",
         L / 2, L, L, median(rh, rounds));
  for (int k = 0; k < rounds; ++k) printf(" %.3f", ratio_h[k]);
  printf(" (median %.3f: the cost of the split itself, the machine's shared memory and caches the same)\n",
         median(ratio_h, rounds));
  printf("  CPU ns per particle-step, all processes (MPI waits spin): P = 1 %.1f, P = 2 %.1f\n", median(c1, rounds),
         median(c2, rounds));
  {
    const double s1 = median(sk1, rounds), s2 = median(sk2, rounds), step1 = a.particles / m1,
                 step2 = 0.5 * b.particles / m2;
    printf("  S(k) of the final state (%d shells): P = 1 %.3g s (FFTW in the process), P = 2 %.3g s (the counts sent to "
           "FFTW-MPI's slabs, the distributed transform, the shells all-reduced); one S(k) costs %.2f steps at P = 1 "
           "(%.3g s each) and %.2f at P = 2 (%.3g s)\n",
           kSkBins, s1, s2, s1 / step1, step1, s2 / step2, step2);
    const double o1 = median(ob1, rounds), o2 = median(ob2, rounds);
    printf("  one observation (gran_srd_observe's values: the particles of the unshifted cells gathered on their process, "
           "exact sums): P = 1 %.3g s (%.2f steps), P = 2 %.3g s (%.2f steps)\n",
           o1, o1 / step1, o2, o2 / step2);
    const double q1 = median(op1, rounds), q2 = median(op2, rounds);
    printf("  creation (each process its bricks' particles by cells and its cells' streams): P = 1 %.3g s (%.2f steps), "
           "P = 2 %.3g s per process (%.2f steps)\n",
           q1, q1 / step1, q2, q2 / step2);
  }
  const double faces = 2.0; /* 2 x 1 x 1 periodic: each brick has two faces */
  const double face_bytes = b.bytes / faces, face_cells = (double)L * L;
  printf("  exchanged per process and step: %.4g B (%.4g B per face of %d x %d cells: %.3g B per face cell); %g "
         "messages went beyond the neighbouring bricks\n",
         b.bytes, face_bytes, L, L, face_bytes / face_cells, b.far);
  /* weak scaling: a 64^3 brick per process, a 3-D split */
  const double n_rank = 10.0 * 64 * 64 * 64, F = face_bytes / face_cells * 64 * 64, t_comp = n_rank / m2;
  const struct {
    const char *name;
    double alpha, beta;
  } net[2] = {{"TCP, 10 GbE (alpha 50 us, beta 1.25 GB/s)", 50e-6, 1.25e9}, {"InfiniBand HDR (alpha 2 us, beta 12 GB/s)", 2e-6, 12e9}};
  printf("  model, 64^3 cells per process (t_comp = %.3g s per step at the P = 2 rate; %.3g MB per face):\n", t_comp, F / 1e6);
  for (int q = 0; q < 2; ++q) {
    printf("    %s:", net[q].name);
    static const int Ps[3] = {8, 64, 1000};
    for (int j = 0; j < 3; ++j) {
      const int P = Ps[j];
      const double lg = log2((double)P), a0 = net[q].alpha, be = net[q].beta;
      const double t_comm = 2 * lg * (a0 + 4400.0 / be) / 64 + 2 * lg * a0 + 26 * a0 + 6 * F / be;
      printf(" P = %d: efficiency %.3f (communication %.3g ms)%s", P, t_comp / (t_comp + t_comm), 1e3 * t_comm,
             j < 2 ? ";" : "\n");
    }
  }
  /* the checkpoint: one process's file against the set of a gas split over 2 (a part per process,
   * committed by rank 0's checkpoint); two checkpoints in a run of 20 steps, the run without them
   * alongside, interleaved */
  {
    const char *cs = "/tmp/granary-b803-ck.toml";
    f = fopen(cs, "w");
    if (!f) return 1;
    fprintf(f,
            "[engine]\ntype = \"srd\"\ndimension = 3\ncells = [%d, %d, %d]\nn0 = 10\ndt = 0.1\nT0 = 1\nalpha = 130\n"
            "sort_every = 50\nsteps = 20\nseed = 1\nthreads = 1\ncreation = \"cells\"\ndecomposition = \"auto\"\n"
            "[observables]\nevery = 10\n[output]\ncheckpoint_every = 1\n",
            L, L, L);
    fclose(f);
    double w[2][2][8], bytes[2] = {0, 0};
    for (int k = 0; k < rounds; ++k)
      for (int P = 1; P <= 2; ++P) {
        w[P - 1][1][k] = run_scene(cli, cs, P, 1);
        bytes[P - 1] = ckpt_bytes();
        system("rm -f /tmp/granary-b803-ck.ckpt*");
        w[P - 1][0][k] = run_scene(cli, cs, P, 0);
      }
    double per[2];
    for (int P = 0; P < 2; ++P) {
      double d[8];
      for (int k = 0; k < rounds; ++k) d[k] = (w[P][1][k] - w[P][0][k]) / 2.0;
      per[P] = median(d, rounds);
    }
    const double step1 = a.particles / m1, step2 = 0.5 * b.particles / m2;
    printf("  one checkpoint (two in a run of 20 steps, against the run without them): P = 1 %.3g s (%.2f steps; "
           "%.4g MB, one file), P = 2 %.3g s (%.2f steps; %.4g MB: the checkpoint and a part per process, each "
           "written by its process)\n",
           per[0], per[0] / step1, bytes[0] / 1e6, per[1], per[1] / step2, bytes[1] / 1e6);
    remove(cs);
    remove("/tmp/granary-b803-ck.h5");
  }
  remove(scene);
  remove(half);
  return 0;
}
