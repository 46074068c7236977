/* checkpoint.cpp - complete engine state in an HDF5 group; a restart continues bit for bit. */
#include "dsmc_impl.h"

GRAN_EXTERN int gran_dsmc_checkpoint_write(const gran_dsmc *sim, const char *path, const char *group) {
  (void)sim; (void)path; (void)group;
  return GRAN_ERROR(GRAN_ERR_UNSUPPORTED, "gran_dsmc_checkpoint_write is not implemented yet");
}
GRAN_EXTERN int gran_dsmc_checkpoint_read(const char *path, const char *group, const gran_mixture *mix,
                                          gran_dsmc **sim) {
  (void)path; (void)group; (void)mix; (void)sim;
  return GRAN_ERROR(GRAN_ERR_UNSUPPORTED, "gran_dsmc_checkpoint_read is not implemented yet");
}
