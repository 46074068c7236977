/* device_cuda.h - devices of the GSRD engine (src/srd/device_cuda.cpp): selection, and the hooks
 * through which src/srd/engine.cpp hands a run to the launchers of cuda/srd_cuda.h (the GPU, or the
 * host reference of the same algorithm). */
#ifndef GRAN_SRD_DEVICE_CUDA_H
#define GRAN_SRD_DEVICE_CUDA_H
#include <stdint.h>

#include "granary.h"
#ifdef __cplusplus
extern "C" {
#endif
/* device: "cpu", "cuda", "auto" or "reference"; *use_cuda = 1 when the run goes to the GPU. "auto"
 * without a usable GPU records a warning (gran_warning_count) and gives 0; "cuda" without one fails
 * with GRAN_ERR_UNSUPPORTED; any other string is GRAN_ERR_ARG. */
GRAN_EXTERN int gran_srd_device_resolve(const char *device, int *use_cuda);
/* The same for a scene value: *device = GRAN_SRD_DEVICE_* of the name (GRAN_ERR_ARG otherwise). */
GRAN_EXTERN int gran_srd_device_parse(const char *name, int32_t *device);
#ifdef __cplusplus
}

struct gran_srd;
struct gran_srd_dev; /* the run's device state (launchers + handle) */
void gran_srd_dev_free(gran_srd_dev *d);
/* member of struct gran_srd: the device state, NULL while the run is on the CPU engine */
struct gran_srd_dev_holder {
  gran_srd_dev *p = nullptr;
  gran_srd_dev_holder() = default;
  gran_srd_dev_holder(const gran_srd_dev_holder &) = delete;
  gran_srd_dev_holder &operator=(const gran_srd_dev_holder &) = delete;
  ~gran_srd_dev_holder() { gran_srd_dev_free(p); }
};
/* Hooks called by the engine (each a no-op cost for a CPU run beyond one pointer test there):
 * attach: after create (from_checkpoint 0) or checkpoint_read (1), start the run on opt.device;
 * advance: the steps on the device; sync: bring the host copy of the particles (cells = 1: and the
 * reference velocities and cell RNG states) up to date; touch: the host particle arrays were
 * handed out (their contents go to the device at the next advance); structure_factor: S(k) from the
 * device's cell counts. */
int gran_srd_dev_attach(gran_srd *s, int from_checkpoint);
int gran_srd_dev_advance(gran_srd *s, int64_t steps);
int gran_srd_dev_sync(const gran_srd *s, int cells);
void gran_srd_dev_touch(gran_srd *s);
int gran_srd_dev_structure_factor(gran_srd *s, int64_t nbins, double *k, double *sk, int64_t *count);
/* The one check of the launchers' parameters (cuda/srd_cuda.h), used by the GPU (cuda/srd.cu) and the
 * host reference (device_cuda.cpp) alike: shape, counts, and for float storage the lengths and the
 * speeds the parameters imply within the range of srd_limits.h. */
struct gran_cuda_srd_params;
int gran_srd_dev_check_params(const gran_cuda_srd_params *p);
/* The launchers' parameters of a run (effects: srd_fx_of of src/srd/rules.h): what the rules'
 * constants are made of (srd_rule_const_of) on the CPU engine and the devices alike. */
gran_cuda_srd_params srd_params_of(const gran_srd *s);
#endif
#endif
