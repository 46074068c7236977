/* info.cpp - `granary info`: version, build configuration, CUDA backend and visible GPUs. */
#include <cstdio>
#include <cstring>

#include <string>

#include "cli.h"

/* The value of KEY in the build configuration "key=value; key=value; ...", or "" when absent. */
static std::string config_field(const char *cfg, const char *key) {
  std::string c(cfg), k = std::string(key) + "=";
  size_t at = 0;
  while (at < c.size()) {
    size_t end = c.find("; ", at);
    if (end == std::string::npos) end = c.size();
    if (c.compare(at, k.size(), k) == 0) return c.substr(at + k.size(), end - at - k.size());
    at = end + 2;
  }
  return "";
}

int cli_info(int argc, char **argv) {
  if (argc > 1 && (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h"))) {
    std::printf("usage: granary info [--gpu-count]\n"
                "  version, build configuration (compiler and its __VERSION__, OPT flags, CUDA architectures\n"
                "  built: sm_XX cubins, compute_XX PTX), CUDA backend and visible GPUs; --gpu-count prints\n"
                "  only the number of visible GPUs\n");
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
  /* the compiler of the library (build configuration) and of this driver (__VERSION__) */
  std::string compiler = config_field(cfg, "cxx"), opt = config_field(cfg, "opt"), san = config_field(cfg, "san");
  std::printf("compiler:     %s (__VERSION__ \"%s\")\n", compiler.empty() ? "unknown" : compiler.c_str(), __VERSION__);
  std::printf("flags:        %s%s%s\n", opt.empty() ? "unknown" : opt.c_str(), san.empty() ? "" : " ", san.c_str());
  std::printf("CUDA backend: %s\n", compiled ? "compiled" : "not compiled (no nvcc at build time)");
  /* the CUDA code built in: cubins (sm_XX) for those GPUs, PTX (compute_XX) JIT-compiled on later ones */
  std::string arch = config_field(cfg, "cuda_arch");
  if (compiled) {
    std::printf("CUDA code:    %s%s\n", arch.empty() ? "unknown" : arch.c_str(),
                arch.find("sm_") == std::string::npos && !arch.empty()
                    ? " (PTX only: compiled for the GPU at the first launch)"
                    : "");
  } else {
    std::printf("CUDA code:    none (built with the CUDA stub: CUDA calls report GRAN_ERR_UNSUPPORTED, 0 devices)\n");
  }
  std::printf("GPUs visible: %d\n", ngpu);
  return 0;
}
