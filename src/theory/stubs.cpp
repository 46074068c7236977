/* stubs.cpp - temporary: theory entry points not implemented yet (removed as they land). */
#include "theory/theory_impl.h"

#define THEORY_TODO(name) \
  GRAN_TRY { return GRAN_ERROR(GRAN_ERR_UNSUPPORTED, "%s is not implemented yet", name); } GRAN_CATCH

GRAN_EXTERN int gran_theory_temperatures(const gran_mixture *mix, const double *T0, int64_t ntimes,
                                         const double *t, double rtol, double *T) {
  (void)mix; (void)T0; (void)ntimes; (void)t; (void)rtol; (void)T; THEORY_TODO("gran_theory_temperatures")
}
GRAN_EXTERN int gran_theory_msd_hcs(const gran_mixture *mix, const double *T0, double tau0,
                                    int64_t ntimes, const double *t, double *msd, double *msd_total) {
  (void)mix; (void)T0; (void)tau0; (void)ntimes; (void)t; (void)msd; (void)msd_total;
  THEORY_TODO("gran_theory_msd_hcs")
}
GRAN_EXTERN int gran_theory_msd(const gran_mixture *mix, const double *T0, int64_t ntimes,
                                const double *t, double rtol, double *msd, double *msd_total) {
  (void)mix; (void)T0; (void)ntimes; (void)t; (void)rtol; (void)msd; (void)msd_total;
  THEORY_TODO("gran_theory_msd")
}
GRAN_EXTERN int gran_theory_tamsd(const gran_mixture *mix, const double *T0, double tau0, double t_meas,
                                  int64_t nlag, const double *lag, double rtol, double *tamsd) {
  (void)mix; (void)T0; (void)tau0; (void)t_meas; (void)nlag; (void)lag; (void)rtol; (void)tamsd;
  THEORY_TODO("gran_theory_tamsd")
}
