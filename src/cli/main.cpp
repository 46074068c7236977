/* main.cpp - the granary command-line driver: subcommand dispatch. */
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "cli.h"

int cli_verbose = 0;

const char *cli_error(void) {
  static char buf[2048];
  char where[512] = "";
  gran_last_error_location_copy(where, sizeof where);
  if (cli_verbose && where[0])
    std::snprintf(buf, sizeof buf, "%s [%s]", gran_last_error_message(), where);
  else
    std::snprintf(buf, sizeof buf, "%s", gran_last_error_message());
  return buf;
}

int cli_seconds(const char *v, double *out) {
  char *end = nullptr;
  const double x = std::strtod(v, &end);
  if (end == v || *end || !(x >= 0.0 && x <= 1e7)) return 0;
  *out = x;
  return 1;
}

static void usage(FILE *f) {
  std::fprintf(f,
               "usage: granary COMMAND [ARGS]\n"
               "commands:\n"
               "  run SCENE [-o FILE] [--resume CHECKPOINT] [--quiet]\n"
               "                       simulate a scene, write HDF5 (granary run --help for all options)\n"
               "  theory SCENE [--times t1,...] [--lags l1,...] [--json]\n"
               "                       kinetic theory of the scene's mixture\n"
               "  keys [ENGINE] [--format text|markdown]\n"
               "                       the scene keys of each engine (type, default, bounds, unit, C field)\n"
               "  decompose SCENE [--bricks auto|PxQxR] [--steps N]\n"
               "                       step a GSRD gas split into bricks (one per MPI process in granary-mpi):\n"
               "                       digests, conservation, speed per process\n"
               "  info [--gpu-count]   version, build configuration, CUDA backend, visible GPUs\n"
               "  --help               this text (COMMAND --help: its options)\n"
               "  --version            the library version\n"
               "  --verbose            (before COMMAND) errors also name the library function and source line\n");
}

static int dispatch(int argc, char **argv);

int main(int argc, char **argv) {
  if (cli_mpi_init(&argc, &argv)) {
    std::fprintf(stderr, "granary: MPI could not be initialized\n");
    return 1;
  }
  const int rc = dispatch(argc, argv);
  cli_mpi_finalize();
  return rc;
}

static int dispatch(int argc, char **argv) {
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  if (!std::strcmp(argv[1], "--verbose")) {
    cli_verbose = 1;
    argv++;
    argc--;
    if (argc < 2) {
      usage(stderr);
      return 2;
    }
  }
  const char *cmd = argv[1];
  if (!std::strcmp(cmd, "--help") || !std::strcmp(cmd, "-h") || !std::strcmp(cmd, "help")) {
    usage(stdout);
    return 0;
  }
  if (!std::strcmp(cmd, "--version")) {
    std::printf("granary %s\n", GRAN_VERSION_STRING);
    return 0;
  }
  if (!std::strcmp(cmd, "info")) return cli_info(argc - 1, argv + 1);
  if (!std::strcmp(cmd, "run")) return cli_run(argc - 1, argv + 1);
  if (!std::strcmp(cmd, "theory")) return cli_theory(argc - 1, argv + 1);
  if (!std::strcmp(cmd, "keys")) return cli_keys(argc - 1, argv + 1);
  if (!std::strcmp(cmd, "decompose")) return cli_decompose(argc - 1, argv + 1);
  std::fprintf(stderr, "granary: unknown command '%s' (see granary --help)\n", cmd);
  return 2;
}
