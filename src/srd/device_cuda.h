/* device_cuda.h - device selection of the GSRD engine (src/srd/device_cuda.cpp). */
#ifndef GRAN_SRD_DEVICE_CUDA_H
#define GRAN_SRD_DEVICE_CUDA_H
#ifdef __cplusplus
extern "C" {
#endif
/* device: "cpu", "cuda" or "auto"; *use_cuda = 1 when the run goes to the GPU. "auto" without a
 * usable GPU records a warning (gran_warning_count) and gives 0; "cuda" without one fails with
 * GRAN_ERR_UNSUPPORTED; any other string is GRAN_ERR_ARG. */
GRAN_EXTERN int gran_srd_device_resolve(const char *device, int *use_cuda);
#ifdef __cplusplus
}
#endif
#endif
