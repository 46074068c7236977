/* b801-srd.c - GSRD speed: particle-steps per second for 3-D, n0 = 10, dt = 0.1, kT = 1, boxes of
 * 32^3 and 64^3 cells (BENCH_QUICK: 32^3 only), on 1 thread (per wall and per CPU second) and on all
 * threads; bytes moved per particle-step
 * (a model count of the passes, stated below) against a memory-copy roofline measured in the same
 * run; the cost of each effect on/off (32^3); memory per particle; the set-up time of the per-cell
 * RNG streams; a whole run (creation + 100 steps, one thread, dt = 0.1) with the particles in cell order from
 * creation against the same run with them shuffled back to creation order (what every run did
 * before the creation sort). HOOMD-blue MPCD (not a dependency) runs side by side in the same
 * process tree when `python3 -c "import hoomd"` works: the same set-up (3-D, n0 = 10, dt = 0.1,
 * kT = 1, SRD angle 130 degrees, cell size 1 with the random grid shift, sort every 50 steps, one
 * CPU thread, the 51 steps through its first sort untimed), and the ratio of the two rates measured
 * in this run is printed; otherwise b801 says so and prints granary's numbers only (the external
 * reference measurement is printed as a line of text, with no ratio computed against it). LAMMPS
 * `fix srd` runs the whole-run set-up side by side when `lmp` exists (see lammps_input).
 * GRAN_SRD_PHASES=1 in the environment makes the engine print the time of each phase of every
 * gran_srd_advance to stderr (ns per particle-step: streaming, cell sums, cell rules, rotation, sort).
 * Bytes per particle-step of the model (the passes of src/srd/engine.cpp): stream r+w 48+48 and
 * the block's slab list w 2; per slab: sums r 2 (list) + 48 (positions and velocities), rotation
 * r 2 + 48, w 24 (velocities) -> 222 B (the rotation's second read of a slab's particles, 2 MB at
 * n0 = 10, is counted although it often still comes from cache). */
#include "bench_util.h"

#include <math.h>
#include <malloc.h>


static double copy_bw(size_t bytes) {
  double *a = malloc(bytes), *b = malloc(bytes);
  size_t n = bytes / sizeof(double);
  for (size_t i = 0; i < n; ++i) a[i] = (double)i;
  memcpy(b, a, bytes);
  double t0 = bench_now();
  int reps = 5;
  for (int r = 0; r < reps; ++r) {
    memcpy(b, a, bytes);
    a[r] = b[n - 1 - r];
  }
  double t = bench_now() - t0;
  free(a);
  free(b);
  return 2.0 * (double)bytes * reps / t; /* read + write */
}

/* particle-steps per wall second; *cpu_rate (when not NULL): per CPU second of the process */
static double rate_cpu(gran_srd_options o, int threads, int steps, double *setup, double *cpu_rate) {
  o.threads = threads;
  gran_srd *s = NULL;
  double t0 = bench_now();
  BENCH_CHECK(gran_srd_create(&o, &s));
  if (setup) *setup = bench_now() - t0;
  BENCH_CHECK(gran_srd_advance(s, o.sort_every + 1)); /* through the first sort by cell: the
                                                         particles of a long run are sorted */
  t0 = bench_now();
  const double c0 = bench_cpu_now();
  BENCH_CHECK(gran_srd_advance(s, steps));
  const double t = bench_now() - t0, c = bench_cpu_now() - c0;
  gran_srd_obs ob;
  BENCH_CHECK(gran_srd_observe(s, &ob));
  BENCH_CHECK(gran_srd_destroy(&s));
  if (cpu_rate) *cpu_rate = c > 0 ? (double)ob.n * steps / c : 0.0;
  return (double)ob.n * steps / t;
}
static double rate(gran_srd_options o, int threads, int steps, double *setup) {
  return rate_cpu(o, threads, steps, setup, NULL);
}

/* HOOMD-blue's MPCD with the set-up of the rate rows (3-D, L^3 cells, n0 = 10, dt = 0.1, kT = 1,
 * SRD angle 130 degrees, no thermostat, sort every 50 steps, one CPU thread): particle-steps per CPU
 * second of `steps` steps after 51 untimed ones; -1 when the script fails. */
static const char *const hoomd_script =
    "import sys, time\n"
    "import numpy as np\n"
    "import hoomd\n"
    "L, steps = int(sys.argv[1]), int(sys.argv[2])\n"
    "sim = hoomd.Simulation(device=hoomd.device.CPU(num_cpu_threads=1), seed=1)\n"
    "snap = hoomd.Snapshot()\n"
    "N = 10 * L ** 3\n"
    "if snap.communicator.rank == 0:\n"
    "    snap.configuration.box = [L, L, L, 0, 0, 0]\n"
    "    snap.particles.types = ['A']\n"
    "    snap.mpcd.types = ['S']\n"
    "    snap.mpcd.N = N\n"
    "    rng = np.random.default_rng(1)\n"
    "    snap.mpcd.position[:] = rng.uniform(-L / 2, L / 2, (N, 3))\n"
    "    v = rng.normal(0.0, 1.0, (N, 3))\n"
    "    snap.mpcd.velocity[:] = v - v.mean(axis=0)\n"
    "sim.create_state_from_snapshot(snap)\n"
    "ig = hoomd.mpcd.Integrator(dt=0.1)\n"
    "ig.collision_method = hoomd.mpcd.collide.StochasticRotationDynamics(period=1, angle=130)\n"
    "ig.streaming_method = hoomd.mpcd.stream.Bulk(period=1)\n"
    "ig.mpcd_particle_sorter = hoomd.mpcd.tune.ParticleSorter(trigger=50)\n"
    "sim.operations.integrator = ig\n"
    "sim.run(51)\n"
    "t0 = time.process_time()\n"
    "sim.run(steps)\n"
    "print(N * steps / (time.process_time() - t0))\n";
static int hoomd_available(void) { return system("python3 -c 'import hoomd' >/dev/null 2>&1") == 0; }
static double hoomd_rate(int L, int steps) {
  char path[] = "/tmp/b801-hoomd-XXXXXX";
  const int fd = mkstemp(path);
  if (fd < 0) return -1.0;
  FILE *f = fdopen(fd, "w");
  if (!f) return -1.0;
  fputs(hoomd_script, f);
  fclose(f);
  char cmd[256];
  snprintf(cmd, sizeof cmd, "OMP_NUM_THREADS=1 python3 %s %d %d 2>&1", path, L, steps);
  FILE *p = popen(cmd, "r");
  double r = -1.0;
  char line[512];
  while (p && fgets(line, sizeof line, p)) {
    char *end;
    const double x = strtod(line, &end);
    if (end != line && x > 0) r = x;
    else fprintf(stderr, "b801 (hoomd): %s", line);
  }
  if (p) pclose(p);
  remove(path);
  return r;
}

/* LAMMPS `fix srd` (Debian package lammps, not a dependency) with the set-up of the whole-run row:
 * a pure SRD fluid (no big particles), 3-D, L^3 cells of size 1, n0 = 10 (create_atoms random),
 * dt = 0.1, kT = 1, the grid shifted every step, no rescaling, LAMMPS' own sorting off (fix srd
 * bins the SRD particles every step itself), one process, OMP_NUM_THREADS = 1. Its rotation
 * angle is its own (fix srd has no angle keyword); the cost of a step does not depend on it. Runs
 * `run 1` then `run steps`; *step_rate: particle-steps per second of the second run (LAMMPS' loop
 * time); returns the wall seconds of the whole process (start, creation, both runs), -1 on failure. */
static const char *const lammps_input =
    "variable L index 16\n"
    "variable S index 100\n"
    "variable N equal 10*${L}^3\n"
    "units lj\n"
    "atom_style atomic\n"
    "dimension 3\n"
    "boundary p p p\n"
    "region box block 0 ${L} 0 ${L} 0 ${L}\n"
    "create_box 1 box\n"
    "create_atoms 1 random ${N} 12345 box\n"
    "mass 1 1.0\n"
    "velocity all create 1.0 593849 loop geom\n"
    "neighbor 0.3 bin\n"
    "neigh_modify delay 1 every 1 check no\n"
    "atom_modify sort 0 0.0\n"
    "timestep 0.1\n"
    "fix 1 all srd 1 NULL 1.0 1.0 49894 shift yes 54979 rescale no\n"
    "thermo 1000\n"
    "run 1\n"
    "run ${S}\n";
static int lammps_available(void) { return system("command -v lmp >/dev/null 2>&1") == 0; }
static double lammps_run(int L, int steps, double *step_rate) {
  char path[] = "/tmp/b801-lammps-XXXXXX";
  const int fd = mkstemp(path);
  *step_rate = -1.0;
  if (fd < 0) return -1.0;
  FILE *f = fdopen(fd, "w");
  if (!f) return -1.0;
  fputs(lammps_input, f);
  fclose(f);
  char cmd[320];
  snprintf(cmd, sizeof cmd, "OMP_NUM_THREADS=1 lmp -in %s -var L %d -var S %d -log none 2>&1", path, L, steps);
  const double t0 = bench_now();
  FILE *p = popen(cmd, "r");
  char line[512];
  double loop = -1.0;
  long long atoms = 0;
  int nsteps = 0, procs = 0;
  while (p && fgets(line, sizeof line, p)) {
    double x;
    int pr, st;
    long long na;
    if (sscanf(line, "Loop time of %lf on %d procs for %d steps with %lld atoms", &x, &pr, &st, &na) == 4 &&
        st == steps) {
      loop = x;
      procs = pr;
      nsteps = st;
      atoms = na;
    } else if (strstr(line, "ERROR"))
      fprintf(stderr, "b801 (lammps): %s", line);
  }
  const int rc = p ? pclose(p) : -1;
  const double wall = bench_now() - t0;
  remove(path);
  if (rc != 0 || loop <= 0 || procs != 1) return -1.0;
  *step_rate = (double)atoms * nsteps / loop;
  return wall;
}

/* heap bytes in use now (malloc'ed incl. mmapped chunks), glibc mallinfo2 */
static double heap_now(void) {
  const struct mallinfo2 mi = mallinfo2();
  return (double)mi.uordblks + (double)mi.hblkhd;
}

/* measured memory per particle: heap growth over create + 2 steps over N, 1 thread and all threads,
 * at n0 = 5, 10, 20; model: 48 B of positions and velocities + 2 B slab list per particle + 56 B
 * per cell (24 B reference velocity + 32 B RNG state) / n0 (the slab starts of each block of 4096
 * particles and the thread-local slab records are below 0.1 B per particle here) */
static void memory_per_particle(gran_srd_options o) {
  const double n0s[3] = {5, 10, 20};
  for (int k = 0; k < 3; ++k) {
    o.n0 = n0s[k];
    for (int t = 0; t < 2; ++t) {
      o.threads = t == 0 ? 1 : 0;
      const double r0 = heap_now();
      gran_srd *s = NULL;
      BENCH_CHECK(gran_srd_create(&o, &s));
      BENCH_CHECK(gran_srd_advance(s, 2));
      const double r1 = heap_now();
      gran_srd_obs ob;
      BENCH_CHECK(gran_srd_observe(s, &ob));
      printf("memory per particle (%lld^3 cells, n0 = %g, %s): %.1f B measured (heap in use / N); "
             "model 48 B particle state + 2 B slab list + 56 B per cell / n0 = %.1f B\n",
             (long long)o.cells[0], o.n0, t == 0 ? "1 thread" : "all threads", (r1 - r0) / (double)ob.n,
             50.0 + 56.0 / o.n0);
      BENCH_CHECK(gran_srd_destroy(&s));
    }
  }
}

/* Eq. 1.48 (2-D) / 1.49 (3-D) kinetic + collisional viscosity (a = dt = kT = m = 1, M = n0). */
static double nu_eq(int dim, double M, double alpha_deg, double *kin) {
  const double al = alpha_deg * 3.14159265358979323846 / 180, q = M - 1 + exp(-M);
  *kin = dim == 2 ? M / (q * (1 - cos(2 * al))) - 0.5 : 5 * M / (q * (4 - 2 * cos(al) - 2 * cos(2 * al))) - 0.5;
  return *kin + q / M * (1 - cos(al)) / (dim == 2 ? 12.0 : 18.0);
}

/* Figs. 3.2 / 3.3 (reduced): total viscosity under Lees-Edwards shear against alpha, global
 * thermostat (thermostat = 2), n0 = 10; mean and standard error of time blocks. */
static void viscosity_sweep(int dim, int quick) {
  const double al2[] = {30, 45, 60, 90, 120, 130, 150}, al3[] = {30, 60, 90, 120, 150, 180};
  const double *al = dim == 2 ? al2 : al3;
  const int na = dim == 2 ? 7 : 6;
  const int L = dim == 2 ? 16 : (quick ? 6 : 10), nblk = quick ? 6 : 12, blk = quick ? 100 : 250;
  printf("viscosity %d-D (%d^%d cells, n0 = 10, thermostat = 2, %d blocks of %d steps):\n", dim, L, dim, nblk, blk);
  printf("  alpha   measured     +- se      Eq.%s+coll  (kinetic)   deviation\n", dim == 2 ? "1.48" : "1.49");
  for (int k = 0; k < na; ++k) {
    gran_srd_options o;
    BENCH_CHECK(gran_srd_options_default(&o));
    o.dim = dim;
    o.cells[0] = o.cells[1] = o.cells[2] = L;
    o.n0 = 10;
    o.alpha_deg = al[k];
    o.thermostat = 2;
    double kin;
    const double th = nu_eq(dim, o.n0, al[k], &kin);
    /* shear rate: small enough that the stress correlations (about nu steps long) see a small
     * strain (Weissenberg number rate * nu < 0.1), large enough for the signal */
    o.shear_rate = fmin(0.06, 0.1 / th);
    o.seed = 99 + (uint64_t)al[k];
    o.threads = 1;
    gran_srd *s = NULL;
    BENCH_CHECK(gran_srd_create(&o, &s));
    BENCH_CHECK(gran_srd_advance(s, 2 * blk));
    double sm = 0, s2 = 0;
    for (int b = 0; b < nblk; ++b) {
      BENCH_CHECK(gran_srd_stress_reset(s));
      BENCH_CHECK(gran_srd_advance(s, blk));
      gran_srd_obs ob;
      BENCH_CHECK(gran_srd_observe(s, &ob));
      const double nu = ob.stress_xy / (o.n0 * o.shear_rate);
      sm += nu;
      s2 += nu * nu;
    }
    BENCH_CHECK(gran_srd_destroy(&s));
    const double m = sm / nblk, se = sqrt(fmax(0.0, s2 / nblk - m * m) / (nblk - 1));
    printf("  %5.0f  %9.4f  %9.4f  %9.4f  (%8.4f)  %+6.1f %% (%+.1f se)\n", al[k], m, se, th, kin,
           100 * (m / th - 1), (m - th) / se);
  }
}

/* Fig. 3.6 (reduced): 2-D GSRD under Lees-Edwards shear without thermostat (the shear heating
 * balances the dissipation), n0 = 10, eps_eff about 0.998 as in the thesis. Theory: Eq. 2.55 with
 * the measured thermal temperature theta (relative to the imposed profile) and
 * kappa = (1 - eps^2) sigma^2 dt sqrt(theta) (Eq. 2.53); printed are the form of Eq. 2.55 as it
 * stands in the thesis and the form that follows from averaging Eq. 2.52 over the Poisson
 * occupancy, 1 - h = [q (1 - cos 2a) + n0 (2 n0 kappa - (n0^2 + 2 n0) kappa^2) cos 2a] / n0 with
 * q = n0 - 1 + e^-n0 (the two differ in the kappa terms), each + collisional. */
static void granular_viscosity(int quick) {
  const double al[] = {20, 30, 40};
  const int nblk = quick ? 6 : 12, blk = quick ? 150 : 300, L = quick ? 24 : 32;
  printf("GSRD viscosity 2-D (%d^2 cells, n0 = 10, eps = 0.9, no thermostat, %d blocks of %d steps):\n", L, nblk, blk);
  printf("  alpha  theta   n0 kappa  measured   +- se    Eq.2.55(thesis) Eq.2.52-avg  Eq.1.48 (all + coll)\n");
  for (int k = 0; k < 3; ++k) {
    gran_srd_options o;
    BENCH_CHECK(gran_srd_options_default(&o));
    o.dim = 2;
    o.cells[0] = o.cells[1] = L;
    o.n0 = 10;
    o.alpha_deg = al[k];
    o.eps = 0.9;
    o.sigma = 0.023; /* n0 kappa ~ 1e-3 at theta ~ 0.7: eps_eff ~ 0.999 */
    o.shear_rate = 0.03;
    o.T0 = 0.7;
    o.seed = 7 + (uint64_t)al[k];
    o.threads = 1;
    gran_srd *s = NULL;
    BENCH_CHECK(gran_srd_create(&o, &s));
    BENCH_CHECK(gran_srd_advance(s, quick ? 1000 : 3000));
    double sm = 0, s2 = 0, th = 0;
    int nth = 0;
    for (int b = 0; b < nblk; ++b) {
      BENCH_CHECK(gran_srd_stress_reset(s));
      for (int t = 0; t < blk; t += 10) {
        BENCH_CHECK(gran_srd_advance(s, 10));
        int64_t n;
        double *x, *y, *z, *vx, *vy, *vz, e = 0;
        BENCH_CHECK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
        for (int64_t i = 0; i < n; ++i) {
          const double ux = vx[i] - o.shear_rate * (y[i] - 0.5 * L);
          e += ux * ux + vy[i] * vy[i];
        }
        th += e / (2.0 * (double)n);
        ++nth;
      }
      gran_srd_obs ob;
      BENCH_CHECK(gran_srd_observe(s, &ob));
      const double nu = ob.stress_xy / (o.n0 * o.shear_rate);
      sm += nu;
      s2 += nu * nu;
    }
    BENCH_CHECK(gran_srd_destroy(&s));
    th /= nth;
    const double m = sm / nblk, se = sqrt(fmax(0.0, s2 / nblk - m * m) / (nblk - 1));
    const double n0 = o.n0, q = n0 - 1 + exp(-n0), a = al[k] * 3.14159265358979323846 / 180, c2 = cos(2 * a);
    const double kap = (1 - o.eps * o.eps) * o.sigma * o.sigma * o.dt * sqrt(th), coll = q / n0 * (1 - cos(a)) / 12;
    const double e148 = th * (n0 / (q * (1 - c2)) - 0.5) + coll;
    const double e255 = th * (n0 / (q * (1 - c2) - (2 * n0 * kap + (n0 - 2) * kap * kap) * c2) - 0.5) + coll;
    const double eavg = th * (n0 / (q * (1 - c2) + n0 * (2 * n0 * kap - (n0 * n0 + 2 * n0) * kap * kap) * c2) - 0.5) + coll;
    printf("  %5.0f  %.4f  %.5f  %8.4f  %7.4f  %8.4f (%+.1f %%)  %8.4f (%+.1f %%)  %8.4f (%+.1f %%)\n", al[k], th, n0 * kap, m,
           se, e255, 100 * (m / e255 - 1), eavg, 100 * (m / eavg - 1), e148, 100 * (m / e148 - 1));
  }
}

/* A whole run on one thread: creation, steps 1-50, steps 51-100 (wall seconds each); shuffle = 1
 * puts the particles back into a random order after creation (a uniform random permutation: the
 * order of creation, in which positions are independent of the index). */
static void whole_run(gran_srd_options o, int shuffle, double t[3]) {
  o.threads = 1;
  gran_srd *s = NULL;
  double t0 = bench_now();
  BENCH_CHECK(gran_srd_create(&o, &s));
  t[0] = bench_now() - t0;
  if (shuffle) {
    int64_t n;
    double *a[6] = {NULL};
    BENCH_CHECK(gran_srd_particles(s, &n, &a[0], &a[1], &a[2], &a[3], &a[4], &a[5]));
    gran_rng r;
    gran_rng_seed(&r, 12345);
    for (int64_t i = n - 1; i > 0; --i) { /* Fisher-Yates */
      uint64_t u;
      BENCH_CHECK(gran_rng_u64(&r, 1, &u));
      const int64_t j = (int64_t)(u % (uint64_t)(i + 1));
      for (int q = 0; q < 6; ++q)
        if (a[q]) {
          const double x = a[q][i];
          a[q][i] = a[q][j];
          a[q][j] = x;
        }
    }
  }
  t0 = bench_now();
  BENCH_CHECK(gran_srd_advance(s, 50));
  t[1] = bench_now() - t0;
  t0 = bench_now();
  BENCH_CHECK(gran_srd_advance(s, 50));
  t[2] = bench_now() - t0;
  BENCH_CHECK(gran_srd_destroy(&s));
}

int main(void) {
  const int quick = bench_quick();
  gran_srd_options o;
  BENCH_CHECK(gran_srd_options_default(&o));
  o.n0 = 10;
  const double bw = copy_bw((size_t)1 << 28);
  const double model_bytes = 222.0;
  printf("b801-srd: GSRD 3-D, n0 = 10 (machine may be shared: compare ratios within this run)\n");
  printf("memory copy: %.3g GB/s (read + write); roofline at %.0f B/particle-step: %.3g particle-steps/s\n",
         bw * 1e-9, model_bytes, bw / model_bytes);
  const int nmax = 0; /* 0: all threads (OpenMP default) */
  const int sizes[2] = {32, 64};
  const int hoomd = hoomd_available();
  if (!hoomd)
    printf("HOOMD-blue: `python3 -c \"import hoomd\"` fails here, no side-by-side run (reference measured "
           "elsewhere, not in this run: HOOMD-blue 4.8 MPCD, CPU, 1.6-2.2e7 particle-steps per CPU second at "
           "32^3 and 64^3, same set-up, 2026-12-02, AMD EPYC (Zen 4) 2-core machine of the project)\n");
  for (int k = 0; k < (quick ? 1 : 2); ++k) {
    gran_srd_options r = o;
    r.cells[0] = r.cells[1] = r.cells[2] = sizes[k];
    r.dt = 0.1; /* the set-up of the HOOMD comparison */
    const int steps = sizes[k] == 32 ? 20 : 5;
    double setup, c1;
    const double r1 = rate_cpu(r, 1, steps, &setup, &c1), rn = rate(r, nmax, steps, NULL);
    printf("%4d^3 (dt = 0.1): set-up %.3f s; 1 thread %.3g particle-steps/s (%.3g per CPU second, %.2f of "
           "roofline); all threads %.3g (%.2f of roofline)\n",
           sizes[k], setup, r1, c1, r1 / (bw / model_bytes), rn, rn / (bw / model_bytes));
    if (hoomd) {
      const double h = hoomd_rate(sizes[k], steps);
      if (h > 0)
        printf("%4d^3 HOOMD-blue MPCD, same set-up, 1 CPU thread: %.3g particle-steps per CPU second; granary "
               "1 thread / HOOMD (both per CPU second, this run): %.2f\n",
               sizes[k], h, c1 / h);
      else
        printf("%4d^3 HOOMD-blue MPCD: the script failed (its output above), no ratio\n", sizes[k]);
    }
  }
  {
    gran_srd_options w = o;
    w.dt = 0.1; /* the set-up of the HOOMD-blue and LAMMPS comparisons */
    const int L = quick ? 32 : 64;
    w.cells[0] = w.cells[1] = w.cells[2] = L;
    const double np = 10.0 * L * L * L;
    double a[3], b[3];
    /* interleaved: shuffled, sorted, [LAMMPS], shuffled, sorted, [LAMMPS]; the second granary pair
     * kept, and the faster of each code's two whole runs compared (the machine may be shared) */
    const int lmp = lammps_available();
    double lw[2] = {-1, -1}, lr[2] = {-1, -1}, ga[2], gs[2];
    for (int round = 0; round < 2; ++round) {
      whole_run(w, 1, b);
      whole_run(w, 0, a);
      ga[round] = a[0] + a[1] + a[2];
      gs[round] = a[1] + a[2];
      if (lmp) lw[round] = lammps_run(L, 100, &lr[round]);
    }
    printf("whole run %d^3, 1 thread, create + 50 + 50 steps (s): creation order %.2f + %.2f + %.2f = %.2f; "
           "cell order from creation %.2f + %.2f + %.2f = %.2f (%.2fx); steps 1-50 %.2fx faster; "
           "steps 1-100 %.3g particle-steps/s\n",
           L, b[0], b[1], b[2], b[0] + b[1] + b[2], a[0], a[1], a[2], a[0] + a[1] + a[2],
           (b[0] + b[1] + b[2]) / (a[0] + a[1] + a[2]), b[1] / a[1], np * 100 / (a[1] + a[2]));
    if (!lmp)
      printf("LAMMPS: no `lmp` here (Debian package lammps), no side-by-side run of fix srd\n");
    else if (lw[0] > 0 && lw[1] > 0) {
      const double gbest = fmin(ga[0], ga[1]), lbest = fmin(lw[0], lw[1]), lrate = fmax(lr[0], lr[1]);
      printf("whole run %d^3, LAMMPS fix srd (1 process, same set-up, interleaved with the runs above): %.2f and "
             "%.2f s for start + creation + 1 + 100 steps, %.3g and %.3g particle-steps/s in its 100 steps; "
             "granary (cell order from creation: %.2f and %.2f s) whole run %.2fx faster, per step %.2fx (the "
             "faster of each code's two runs)\n",
             L, lw[0], lw[1], lr[0], lr[1], ga[0], ga[1], lbest / gbest, (np * 100 / fmin(gs[0], gs[1])) / lrate);
    } else
      printf("whole run %d^3, LAMMPS fix srd: a run failed (its errors above), no ratio\n", L);
  }
  o.cells[0] = o.cells[1] = o.cells[2] = 32;
  const double base = rate(o, nmax, 10, NULL);
  struct {
    const char *name;
    gran_srd_options o;
  } eff[5];
  for (int i = 0; i < 5; ++i) eff[i].o = o;
  eff[0].name = "eps = 0.9";
  eff[0].o.eps = 0.9;
  eff[0].o.sigma = 0.1;
  eff[1].name = "Lees-Edwards";
  eff[1].o.shear_rate = 0.01;
  eff[2].name = "walls (no-slip)";
  eff[2].o.wall_axis = 2;
  eff[3].name = "gravity";
  eff[3].o.accel[2] = -0.001;
  eff[4].name = "thermostat";
  eff[4].o.thermostat = 1;
  printf("effects at 32^3 (all threads), time relative to none (%.3g particle-steps/s):\n", base);
  for (int i = 0; i < 5; ++i) printf("  %-16s %.2f\n", eff[i].name, base / rate(eff[i].o, nmax, 10, NULL));
  viscosity_sweep(2, quick);
  viscosity_sweep(3, quick);
  granular_viscosity(quick);
  if (!quick) { /* stream set-up of 256^3 cells (16.8M streams; few particles: only the cells count) */
    gran_srd_options q = o;
    q.cells[0] = q.cells[1] = q.cells[2] = 256;
    q.n0 = 0.01;
    gran_srd *s = NULL;
    const double t0 = bench_now();
    BENCH_CHECK(gran_srd_create(&q, &s));
    printf("256^3 cells: create (16.8M per-cell RNG streams by consecutive jumps) %.3f s, all threads\n",
           bench_now() - t0);
    BENCH_CHECK(gran_srd_destroy(&s));
  }
  o.cells[0] = o.cells[1] = o.cells[2] = quick ? 48 : 96;
  memory_per_particle(o);
  printf("peak RSS %.3g MB\n", bench_peak_rss() / 1e6);
  return 0;
}
