/* info.cpp - `granary info`: version, build configuration, CUDA backend and visible GPUs. */
#include <cstdio>
#include <cstring>

#include "cli.h"

int cli_info(int argc, char **argv) {
  if (argc > 1 && (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h"))) {
    std::printf("usage: granary info [--gpu-count]\n"
                "  version, build configuration (compiler, OPT flags, CUDA architectures), CUDA backend\n"
                "  and visible GPUs; --gpu-count prints only the number of visible GPUs\n");
    return 0;
  }
  int ngpu = 0, compiled = 0;
  gran_cuda_device_count(&ngpu);
  gran_cuda_compiled(&compiled);
  if (argc > 1 && !std::strcmp(argv[1], "--gpu-count")) {
    std::printf("%d\n", ngpu);
    return 0;
  }
  if (argc > 1) {
    std::fprintf(stderr, "granary info: unknown option '%s'\n", argv[1]);
    return 2;
  }
  int maj, min, pat;
  const char *cfg = "";
  gran_get_version(&maj, &min, &pat);
  gran_get_build_config(&cfg);
  std::printf("granary %d.%d.%d\n", maj, min, pat);
  std::printf("build:        %s\n", cfg);
  std::printf("CUDA backend: %s\n", compiled ? "compiled" : "not compiled (no nvcc at build time)");
  std::printf("GPUs visible: %d\n", ngpu);
  return 0;
}
