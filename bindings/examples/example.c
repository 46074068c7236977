/* Fig. 2 of Bodrova & Osinsky: HCS theory, then a small low-rank DSMC run beside it. */
#include <stdio.h>
#include "granary.h"

int main(void) {
  double m[2] = {1, 100}, sigma[2] = {1, 4.6415888336127789}, n[2] = {0.1, 0.001};
  double T0[2], tau0, T[2], Tth[2], t = 5.0;
  gran_mixture *mix = NULL;
  gran_dsmc *sim = NULL;
  gran_dsmc_options opt;
  gran_dsmc_options_default(&opt);
  opt.volume = 2e4 / 0.1; /* N_1 = 20000 */
  if (gran_mixture_create(2, m, sigma, n, &mix) || gran_mixture_set_restitution(mix, 0.5) ||
      gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, T0, &tau0) ||
      gran_theory_temperatures(mix, T0, 1, &t, 1e-10, Tth) ||
      gran_dsmc_create(mix, NULL, T0, &opt, &sim) || gran_dsmc_advance(sim, t) ||
      gran_dsmc_temperatures(sim, T)) {
    fprintf(stderr, "granary: %s\n", gran_last_error_message());
    return 1;
  }
  printf("tau0 = %.3f  T(0) = %.4f %.4f\n", tau0, T0[0], T0[1]);
  printf("t = %g: DSMC T = %.4f %.4f  theory T = %.4f %.4f\n", t, T[0], T[1], Tth[0], Tth[1]);
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
  return 0;
}
