/* b504-mpi.c - replicas over MPI processes: replicas per second on P = 1 and 2 processes of this
 * machine (build/granary-mpi under mpirun, one thread each), measured side by side in one run,
 * the bytes rank 0 gathers per output time (measured: the driver's count; model: R x row bytes),
 * and a model of the wall time on P machines.
 *
 * Scene: the Bodrova & Osinsky Fig. 2 mixture (m = (1, 100), n = (0.1, 0.001), eps = 0.5, HCS
 * start) at N_1 = 1e4, R = 64 replicas (16 with BENCH_QUICK=1), outputs at t = 1, 10, 100. Every output time
 * each rank sends rank 0 its replicas' rows (T[2], msd[2], msd_total, collisions, trials: 56
 * bytes a replica here); rank 0 reduces them in replica order (bit for bit the threaded run: test
 * t611). Model on P machines: wall(P) = ceil(R/P) t_rep + n_out [(P-1) alpha + R b / beta] with
 * t_rep the CPU time of one replica at P = 1 (its wall time on a free core; the CPU time of all processes is printed too:
 * on a machine shared with other work the wall-clock speed-up says little, the CPU time of P = 2
 * against P = 1 says what the processes cost beyond the work), b the row bytes of one replica, alpha = 50 us and
 * beta = 1 GB/s (plain TCP; an InfiniBand network is better on both). Skips without MPI. */
#include "bench_util.h"

#include <hdf5.h>
#include <unistd.h>

static const char *kScene =
    "title = \"b503: Fig. 2 mixture, replicas over MPI\"\n"
    "[mixture]\nnspecies = 2\nmass = [1.0, 100.0]\nsigma = [1.0, 4.641588833612779]\ndensity = [0.1, 0.001]\n"
    "[restitution]\neps = 0.5\n[initial]\ntemperatures = \"hcs\"\n[engine]\nN1 = 1e4\nseed = 7\nt_end = 100.0\n"
    "replicas = %d\nkeep_replicas = true\n[observables]\ntimes = [1.0, 10.0, 100.0]\nenergy = false\n"
    "[output]\npath = \"/tmp/granary-b503.h5\"\ncheckpoint = \"\"\n";

/* CPU seconds (user + system) of the waited-for child processes so far: mpirun waits for its
 * ranks, so their time is included once mpirun has been waited for */
static double children_cpu(void) {
  struct rusage ru;
  getrusage(RUSAGE_CHILDREN, &ru);
  return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
         1e-6 * (double)ru.ru_stime.tv_usec;
}

/* wall seconds of one command (*cpu: CPU seconds of all its processes); *bytes, *gathers from
 * the driver's "mpi:" line (P > 1) */
static double run_cmd(const char *cmd, long long *bytes, long long *gathers, double *cpu) {
  const double w0 = bench_now(), c0 = children_cpu();
  FILE *p = popen(cmd, "r");
  if (!p) {
    fprintf(stderr, "b503: cannot run %s\n", cmd);
    exit(1);
  }
  char line[512];
  int procs = 0;
  while (fgets(line, sizeof line, p))
    if (sscanf(line, "mpi: %d processes; rank 0 received %lld bytes from the others in %lld gathers", &procs, bytes,
               gathers) == 3) {
    }
  const int rc = pclose(p);
  const double w = bench_now() - w0;
  *cpu = children_cpu() - c0;
  if (rc != 0) {
    fprintf(stderr, "b503: '%s' failed (status %d)\n", cmd, rc);
    exit(1);
  }
  return w;
}

/* row bytes of one replica at one output time: the per-replica datasets [R][ntimes][...] */
static double row_bytes(const char *path, int R, int nt) {
  static const char *names[] = {"temperatures/T_replicas", "msd/msd_replicas", "msd/msd_total_replicas",
                                "stats/collisions_replicas", "stats/trials_replicas", "energy/e_kin_replicas"};
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  double b = 0;
  for (size_t i = 0; f >= 0 && i < sizeof names / sizeof *names; i++) {
    if (H5Lexists(f, names[i], H5P_DEFAULT) <= 0) continue;
    hid_t d = H5Dopen2(f, names[i], H5P_DEFAULT), s = H5Dget_space(d);
    b += 8.0 * (double)H5Sget_simple_extent_npoints(s) / (double)R / (double)nt;
    H5Sclose(s);
    H5Dclose(d);
  }
  if (f >= 0) H5Fclose(f);
  return b;
}

int main(void) {
  const char *cli = getenv("GRAN_MPI_CLI");
  if (!cli || !*cli || access(cli, X_OK) != 0 || system("command -v mpirun >/dev/null 2>&1") != 0) {
    printf("b504-mpi: skipped (MPI not installed: no mpirun or build/granary-mpi)\n");
    return 0;
  }
  const int R = bench_quick() ? 16 : 64, nt = 3;
  const char *scene = "/tmp/granary-b503.toml";
  FILE *f = fopen(scene, "w");
  if (!f) return 1;
  fprintf(f, kScene, R);
  fclose(f);
  const char *env = "OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                    "OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_btl=self,vader OMPI_MCA_mpi_yield_when_idle=1";
  char cmd[1024];
  double wall[3] = {0, 0, 0}, cpu[3] = {0, 0, 0};
  long long bytes[3] = {0, 0, 0}, gathers[3] = {0, 0, 0};
  /* P = 0: mpirun's own start-up (granary-mpi --version on one process) */
  for (int P = 0; P <= 2; P++) {
    if (P == 0) snprintf(cmd, sizeof cmd, "%s mpirun --oversubscribe -n 1 %s --version 2>&1", env, cli);
    else snprintf(cmd, sizeof cmd, "%s mpirun --oversubscribe -n %d %s run %s --force --no-checkpoint --threads 1 2>&1", env, P,
                  cli, scene);
    wall[P] = run_cmd(cmd, &bytes[P], &gathers[P], &cpu[P]);
  }
  const double b = row_bytes("/tmp/granary-b503.h5", R, nt);
  const double t1 = wall[1] - wall[0], t2 = wall[2] - wall[0];
  const double t_rep = (cpu[1] - cpu[0]) / R; /* CPU seconds a replica: its wall time on a free core */
  printf("replicas over MPI: Fig. 2 mixture, N1 = 1e4, R = %d, %d output times, 1 thread per process (machine shared)\n",
         R, nt);
  printf("  mpirun start-up: %.2f s (subtracted below)\n", wall[0]);
  printf("  P = 1: %.2f s, %.2f replicas/s; CPU of all processes %.2f s\n", t1, R / t1, cpu[1] - cpu[0]);
  printf("  P = 2: %.2f s, %.2f replicas/s, speed-up %.2f; CPU of all processes %.2f s (x %.2f of P = 1)\n", t2, R / t2,
         t1 / t2, cpu[2] - cpu[0], (cpu[2] - cpu[0]) / (cpu[1] - cpu[0]));
  printf("  gathered per output time (model R x row bytes): %d x %.0f B = %.0f B; measured at P = 2: %lld B from rank 1\n"
         "    in %lld gathers (%d output times + 4 set-up/final steps, 24 B of status each)\n",
         R, b, R * b, bytes[2], gathers[2], nt);
  const double alpha = 50e-6, beta = 1e9;
  printf("  model wall(P) = ceil(R/P) t_rep + n_out [(P-1) alpha + R b / beta], t_rep = %.3g s (CPU s of a replica at P = 1),\n"
         "    alpha = 50 us, beta = 1 GB/s:\n",
         t_rep);
  const int Rm = 1000;
  printf("    R = %d: ", Rm);
  for (int P = 1; P <= 1000; P *= 10) {
    const double comp = (double)((Rm + P - 1) / P) * t_rep, comm = nt * ((P - 1) * alpha + Rm * b / beta);
    printf("P = %d: %.3g s (communication %.2g s)%s", P, comp + comm, comm, P < 1000 ? "; " : ".\n");
  }
  remove(scene);
  remove("/tmp/granary-b503.h5");
  return 0;
}
