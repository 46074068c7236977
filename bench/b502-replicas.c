/* b502-replicas.c - replicas: accuracy against cost, and replica scaling over threads.
 *
 * Accuracy versus cost (seed 000 Fig. 2 binary mixture: m = (1, 100), n = (0.1, 0.001), eps = 0.5,
 * HCS start, t = 1, 10, 100): for N_1 and R, the standard error of T_2/T_1 and of MSD_1 (relative,
 * from the per-replica rows) against the total CPU time, and se x sqrt(N_1 R), which the
 * 1/sqrt(N R) law keeps constant. The model error of the theory (|mean - theory| / theory) is
 * printed beside: where se falls below it, more replicas buy nothing against the Maxwellian
 * theory. Grid: N_1 in {1e4, 1e5} x R in {1, 10}, plus (1e4, 100) and (1e6, 1); (1e5, 100) and
 * (1e6, 10/100) are left out (minutes to hours on this 2-core machine).
 * Scaling: 8 replicas of N_1 = 1e4 on 1 thread and on all threads, replicas per second and the
 * ratio, measured side by side in this run; the reduction per output time moves
 * R x (row bytes) through memory, printed as bytes (the size an MPI allreduce would move). */
#include "bench_util.h"

#include <hdf5.h>
#include <math.h>

static const char *kFmt =
    "[mixture]\nnspecies = 2\nmass = [1.0, 100.0]\nsigma = [1.0, 4.641588833612779]\ndensity = [0.1, 0.001]\n"
    "[restitution]\neps = 0.5\n[initial]\ntemperatures = \"hcs\"\n[engine]\nN1 = %g\nseed = 7\nt_end = 100.0\n"
    "replicas = %d\nkeep_replicas = true\n[observables]\ntimes = [1.0, 10.0, 100.0]\nenergy = false\n"
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

static double run(double N1, int R, int threads, const char *out, double *cpu) {
  char text[2048];
  snprintf(text, sizeof text, kFmt, N1, R, out);
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

int main(void) {
  const int quick = bench_quick();
  const char *out = "/tmp/granary-b502.h5";
  struct {
    double N1;
    int R;
  } grid[] = {{1e4, 1}, {1e4, 10}, {1e4, 100}, {1e5, 1}, {1e5, 10}, {1e6, 1}};
  const int ng = quick ? 2 : 6;
  printf("accuracy versus cost: Fig. 2 mixture, t = 1, 10, 100 (tau0 = 19.3); se relative; machine shared\n");
  printf("%8s %4s %9s | %-29s | %-29s | %-26s | %s\n", "N1", "R", "CPU s", "se(T2/T1)/(T2/T1) t=1,10,100",
         "se(MSD1)/MSD1 t=1,10,100", "se(T2/T1) x sqrt(N1 R)", "model error of T2/T1 (theory)");
  for (int g = 0; g < ng; g++) {
    double cpu = 0;
    run(grid[g].N1, grid[g].R, 0, out, &cpu);
    const int R = grid[g].R;
    hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
    double *T = rd(f, R > 1 ? "temperatures/T_replicas" : "temperatures/T", (size_t)R * 6);
    double *M = rd(f, R > 1 ? "msd/msd_replicas" : "msd/msd", (size_t)R * 6);
    double *Tth = rd(f, "temperatures/T_theory", 6);
    H5Fclose(f);
    char a[3][16], b[3][16], c[3][16], e[3][16];
    for (int i = 0; i < 3; i++) {
      double mr = 0, vr = 0, mm = 0, vm = 0;
      for (int k = 0; k < R; k++) {
        mr += T[k * 6 + i * 2 + 1] / T[k * 6 + i * 2];
        mm += M[k * 6 + i * 2];
      }
      mr /= R;
      mm /= R;
      for (int k = 0; k < R; k++) {
        const double x = T[k * 6 + i * 2 + 1] / T[k * 6 + i * 2] - mr, y = M[k * 6 + i * 2] - mm;
        vr += x * x;
        vm += y * y;
      }
      const double th = Tth[i * 2 + 1] / Tth[i * 2];
      snprintf(e[i], sizeof e[i], "%.2g", fabs(mr - th) / th);
      if (R > 1) {
        const double ser = sqrt(vr / (R - 1) / R) / mr, sem = sqrt(vm / (R - 1) / R) / mm;
        snprintf(a[i], sizeof a[i], "%.2g", ser);
        snprintf(b[i], sizeof b[i], "%.2g", sem);
        snprintf(c[i], sizeof c[i], "%.3g", ser * sqrt(grid[g].N1 * R));
      } else {
        snprintf(a[i], sizeof a[i], "-");
        snprintf(b[i], sizeof b[i], "-");
        snprintf(c[i], sizeof c[i], "-");
      }
    }
    printf("%8.0e %4d %9.2f | %9s %9s %9s | %9s %9s %9s | %8s %8s %8s | %s %s %s\n", grid[g].N1, R, cpu, a[0], a[1], a[2],
           b[0], b[1], b[2], c[0], c[1], c[2], e[0], e[1], e[2]);
    fflush(stdout);
    free(T);
    free(M);
    free(Tth);
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
