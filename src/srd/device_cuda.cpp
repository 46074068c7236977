/* device_cuda.cpp - which device a GSRD run uses ([engine] device = "cpu" | "cuda" | "auto").
 * "auto" takes the GPU when the CUDA backend is compiled and a device is visible, else the CPU
 * with a warning; "cuda" without either is GRAN_ERR_UNSUPPORTED. */
#include <cstring>

#include "granary_impl.h"
#include "srd/device_cuda.h"

int gran_srd_device_resolve(const char *device, int *use_cuda) {
  GRAN_CHECK_PTR(device);
  GRAN_CHECK_PTR(use_cuda);
  *use_cuda = 0;
  const bool cpu = !std::strcmp(device, "cpu"), cuda = !std::strcmp(device, "cuda"), aut = !std::strcmp(device, "auto");
  GRAN_CHECK(cpu || cuda || aut, GRAN_ERR_ARG, "device = \"%s\": must be \"cpu\", \"cuda\" or \"auto\"", device);
  if (cpu) return GRAN_SUCCESS;
  int compiled = 0, count = 0;
  GRAN_CALL(gran_cuda_compiled(&compiled));
  if (compiled) GRAN_CALL(gran_cuda_device_count(&count));
  const char *why = !compiled ? "the CUDA backend was not compiled (no nvcc at build time)" : "no CUDA device is visible";
  if (cuda) {
    GRAN_CHECK(compiled && count > 0, GRAN_ERR_UNSUPPORTED, "device = \"cuda\": %s", why);
  } else if (!(compiled && count > 0)) {
    gran_warning_add("device = \"auto\": %s; running on the CPU", why);
    return GRAN_SUCCESS;
  }
  *use_cuda = 1;
  return GRAN_SUCCESS;
}
