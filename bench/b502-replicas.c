/* b502-replicas.c - replicas: accuracy against cost, and replica scaling over threads.
 *
 * Accuracy versus cost, for two scenes of Bodrova & Osinsky, outputs at t = 1, 10, 100:
 *   fig2:   the Fig. 2 binary mixture (m = (1, 100), n = (0.1, 0.001), eps = 0.5, HCS start);
 *           k = 2 (the heavy species);
 *   table1: the Table I mixture (n_k = 0.1 k^-3, m_k = k, 125 species, eps = 0.5, T(0) = 1);
 *           k = 2 (the most populated heavier species; the heavier ones have few particles).
 * For each N_1 and R: the total CPU time, and at each time the relative standard error (from the
 * per-replica rows) of T_k/T_1, of MSD_1 and of MSD_k; se(T_k/T_1) x sqrt(N_1 R), which the
 * 1/sqrt(N R) law keeps constant; and the model error of the theory (|mean - theory| / theory of
 * T_k/T_1): where se falls below it, more particles or replicas resolve the physics the Maxwellian
 * theory misses, not the theory. Grid: N_1 in {1e4, 1e5, 1e6} x R in {1, 10, 100} (R = 100 at
 * N_1 = 1e6 in 10 batches of 10 replicas, scene seeds 7..16, so that 10 engines, not 100, are in
 * memory at once; the replicas of all batches are independent); BENCH_QUICK=1: N_1 in {1e4, 1e5}
 * x R in {1, 10} and (1e4, 100).
 * Scaling: 8 replicas of N_1 = 1e4 on 1 thread and on all threads, replicas per second and the
 * ratio, measured side by side in this run; the reduction per output time moves
 * R x (row bytes) through memory, printed as bytes (what rank 0 gathers with MPI: b503). */
#include "bench_util.h"

#include <hdf5.h>
#include <math.h>

static const char *kFig2 =
    "[mixture]\nnspecies = 2\nmass = [1.0, 100.0]\nsigma = [1.0, 4.641588833612779]\ndensity = [0.1, 0.001]\n"
    "[restitution]\neps = 0.5\n[initial]\ntemperatures = \"hcs\"\n[engine]\nN1 = %g\nseed = %d\nt_end = 100.0\n"
    "replicas = %d\nkeep_replicas = true\n[observables]\ntimes = [1.0, 10.0, 100.0]\nenergy = false\n"
    "[output]\npath = \"%s\"\ncheckpoint = \"\"\n";
static const char *kTable1 =
    "[mixture]\nnspecies = 125\ndensity_law = { n1 = 0.1, theta = 3.0 }\n"
    "[restitution]\neps = 0.5\n[initial]\ntemperatures = \"equal\"\nT_mean = 1.0\n[engine]\nN1 = %g\nseed = %d\n"
    "t_end = 100.0\nreplicas = %d\nkeep_replicas = true\n[observables]\ntimes = [1.0, 10.0, 100.0]\nenergy = false\n"
    "[output]\npath = \"%s\"\ncheckpoint = \"\"\n";

static double *rd(hid_t f, const char *name, size_t n) {
  double *x = calloc(n, sizeof *x);
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0 || H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x) < 0) {
    fprintf(stderr, "cannot read %s\n", name);
    exit(1);
  }
  H5Dclose(d);
  return x;
}

static double run_fmt(const char *fmt, double N1, int seed, int R, int threads, const char *out, double *cpu) {
  char text[2048];
  snprintf(text, sizeof text, fmt, N1, seed, R, out);
  gran_scene *s = NULL;
  BENCH_CHECK(gran_scene_parse(text, "b502.toml", &s));
  BENCH_CHECK(gran_set_threads(threads));
  remove(out);
  const double w0 = bench_now();
  const clock_t c0 = clock();
  BENCH_CHECK(gran_scene_run(s, NULL, "", NULL, NULL));
  *cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
  const double wall = bench_now() - w0;
  gran_scene_destroy(&s);
  return wall;
}

static double run(double N1, int R, int threads, const char *out, double *cpu) {
  return run_fmt(kFig2, N1, 7, R, threads, out, cpu);
}

static void fmt_g(char *b, size_t n, const char *f, double x, int ok) {
  if (ok) snprintf(b, n, f, x);
  else snprintf(b, n, "-");
}

/* One scene at (N1, R): per-replica rows of T and MSD (batches of at most 10 replicas when
 * N1 >= 1e6), then the table rows at the three times. */
static void accuracy(const char *name, const char *fmt, int M, int k, double N1, int R, const char *out) {
  const int batch = N1 >= 1e6 && R > 10 ? 10 : R, nb = R / batch, nt = 3;
  double *T = calloc((size_t)R * nt * M, sizeof *T), *Ms = calloc((size_t)R * nt * M, sizeof *Ms), *Tth = NULL;
  double cpu = 0;
  for (int b = 0; b < nb; b++) {
    double c = 0;
    run_fmt(fmt, N1, 7 + b, batch, 0, out, &c);
    cpu += c;
    hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
    double *t = rd(f, batch > 1 ? "temperatures/T_replicas" : "temperatures/T", (size_t)batch * nt * M);
    double *m = rd(f, batch > 1 ? "msd/msd_replicas" : "msd/msd", (size_t)batch * nt * M);
    if (!Tth) Tth = rd(f, "temperatures/T_theory", (size_t)nt * M);
    H5Fclose(f);
    memcpy(T + (size_t)b * batch * nt * M, t, sizeof *t * (size_t)batch * nt * M);
    memcpy(Ms + (size_t)b * batch * nt * M, m, sizeof *m * (size_t)batch * nt * M);
    free(t);
    free(m);
  }
  const double tt[3] = {1, 10, 100};
  for (int i = 0; i < nt; i++) {
    double mr = 0, m1 = 0, mk = 0, vr = 0, v1 = 0, vk = 0;
    for (int r = 0; r < R; r++) {
      const double *row = T + ((size_t)r * nt + i) * M, *mrow = Ms + ((size_t)r * nt + i) * M;
      mr += row[k - 1] / row[0];
      m1 += mrow[0];
      mk += mrow[k - 1];
    }
    mr /= R;
    m1 /= R;
    mk /= R;
    for (int r = 0; r < R; r++) {
      const double *row = T + ((size_t)r * nt + i) * M, *mrow = Ms + ((size_t)r * nt + i) * M;
      vr += (row[k - 1] / row[0] - mr) * (row[k - 1] / row[0] - mr);
      v1 += (mrow[0] - m1) * (mrow[0] - m1);
      vk += (mrow[k - 1] - mk) * (mrow[k - 1] - mk);
    }
    const int ok = R > 1;
    const double ser = ok ? sqrt(vr / (R - 1) / R) / mr : 0, se1 = ok ? sqrt(v1 / (R - 1) / R) / m1 : 0,
                 sek = ok ? sqrt(vk / (R - 1) / R) / mk : 0;
    const double th = Tth[(size_t)i * M + k - 1] / Tth[(size_t)i * M];
    char a[16], b[16], c[16], d[16];
    fmt_g(a, sizeof a, "%.2g", ser, ok);
    fmt_g(b, sizeof b, "%.2g", se1, ok);
    fmt_g(c, sizeof c, "%.2g", sek, ok);
    fmt_g(d, sizeof d, "%.3g", ser * sqrt(N1 * R), ok);
    if (i == 0) printf("%-6s %6.0e %4d %8.2f", name, N1, R, cpu);
    else printf("%-6s %6s %4s %8s", "", "", "", "");
    printf(" | %5g | %12s %10s %10s | %12s | %.2g\n", tt[i], a, b, c, d, fabs(mr - th) / th);
  }
  fflush(stdout);
  free(T);
  free(Ms);
  free(Tth);
}

int main(void) {
  const int quick = bench_quick();
  const char *out = "/tmp/granary-b502.h5";
  struct {
    double N1;
    int R;
  } grid[] = {{1e4, 1}, {1e4, 10}, {1e4, 100}, {1e5, 1}, {1e5, 10}, {1e5, 100}, {1e6, 1}, {1e6, 10}, {1e6, 100}};
  const int ng = 9;
  printf("accuracy versus cost, t = 1, 10, 100; se relative, from the replicas; CPU s of all threads; machine shared\n"
         "fig2: Bodrova & Osinsky Fig. 2 mixture (k = 2: the heavy species); table1: the Table I mixture, 125 species (k = 2)\n");
  printf("%-6s %6s %4s %8s | %5s | %12s %10s %10s | %12s | %s\n", "scene", "N1", "R", "CPU s", "t", "se(Tk/T1)", "se(MSD1)",
         "se(MSDk)", "se(Tk/T1)*", "model error");
  printf("%-6s %6s %4s %8s | %5s | %12s %10s %10s | %12s | %s\n", "", "", "", "", "", "", "", "", "sqrt(N1 R)",
         "of Tk/T1");
  for (int sc = 0; sc < 2; sc++)
    for (int g = 0; g < ng; g++) {
      if (quick && (grid[g].N1 > 1e5 || (grid[g].R == 100 && grid[g].N1 > 1e4))) continue;
      if (sc == 0) accuracy("fig2", kFig2, 2, 2, grid[g].N1, grid[g].R, out);
      else accuracy("table1", kTable1, 125, 2, grid[g].N1, grid[g].R, out);
    }
  /* replica scaling over threads, side by side */
  const int R = quick ? 4 : 8;
  int32_t nth = 1;
  BENCH_CHECK(gran_set_threads(0));
  BENCH_CHECK(gran_get_threads(&nth));
  double cpu1 = 0, cpun = 0;
  const double w1 = run(1e4, R, 1, out, &cpu1), wn = run(1e4, R, nth, out, &cpun);
  printf("\nreplica scaling (N1 = 1e4, %d replicas): 1 thread %.3g replicas/s, %d threads %.3g replicas/s, ratio %.2f\n", R,
         R / w1, (int)nth, R / wn, w1 / wn);
  /* bytes reduced per output time (what one MPI allreduce of the rows would move): T, MSD, msd_total,
   * collisions, trials per replica row */
  printf("reduction per output time: %d replicas x %d B = %d B (rows of T[2], msd[2], msd_total, collisions, trials)\n", R,
         7 * 8, R * 7 * 8);
  remove(out);
  BENCH_CHECK(gran_set_threads(0));
  return 0;
}
