/* srd_theory.h - the GSRD theory that the run driver writes beside a GSRD run
 * (src/io/engine_srd.cpp: temperature/T_theory) and that `granary theory` prints
 * (src/cli/theory_engines.cpp); src/srd/theory.cpp. Plain C declarations, so that the C tests call
 * them too. Units of the engine: particle mass 1, k_B = 1; gran_srd_options as gran_srd_create
 * takes it (docs/physics.md, docs/guide/gsrd.md). */
#ifndef GRAN_SRD_THEORY_H
#define GRAN_SRD_THEORY_H

#include "granary.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1 when the gas cools freely (Haff's law applies): eps < 1, sigma > 0, and no thermostat,
 * Lees-Edwards shear, walls or acceleration acting on it; else 0. */
int gran_srd_haff_applies_(const gran_srd_options *o);

/* The mean-field Haff rate of Eq. 2.1 (corrected Eqs. 2.11-2.12, docs/physics.md):
 * 1/tau = k (1 - eps^2) sigma^2 (n0 / a^d) sqrt(T0), k = 1 in 2-D, 2/3 in 3-D (only the velocity
 * components perpendicular to the rotation axis are scaled). T(t) = T0 / (1 + t / tau)^2. */
double gran_srd_haff_rate_(const gran_srd_options *o);
/* Haff's law T0 / (1 + f t / tau)^2 at time t >= 0 with the rate of gran_srd_haff_rate_ times f > 0
 * (f = 1, or the Poisson factor), its product f t / tau formed from logarithms, so that a rate that
 * overflows (sigma = 1e154) gives T0 at t = 0 and 0 after (never 0 * inf). */
double gran_srd_haff_T_(const gran_srd_options *o, double f, double t);

/* The factor by which Poisson occupancy of the cells (uncorrelated Maxwellian velocities, cell
 * temperature theta_c = 2 E_c / (d n_c), E_c the thermal energy of the cell relative to its mean
 * velocity) changes the mean-field rate, to first order in 1 - eps_eff:
 *   sum_n P(n; n0) 2 sqrt(2 n / d) Gamma(k/2 + 3/2) / Gamma(k/2) / (d n0^2),  k = d (n - 1),
 * P the Poisson distribution of mean n0 (cells with n < 2 lose nothing). 0.98882 in 2-D and 0.97728
 * in 3-D at n0 = 10; 1 - (1/2 - 3/(4 d)) / n0 + O(n0^-2) for large n0. 0 for a bad dim or n0. */
double gran_srd_haff_poisson_factor_(int dim, double n0);

/* Kinematic shear viscosity of SRD at temperature theta (mass 1; M = n0, q = M - 1 + e^-M):
 * kinetic part, Zantop's Eq. 1.48 (2-D) theta dt [M / (q (1 - cos 2 alpha)) - 1/2] and Eq. 1.49
 * (3-D) theta dt [5 M / (q (4 - 2 cos alpha - 2 cos 2 alpha)) - 1/2]; collisional part
 * (a^2 / (6 d dt)) (q / M) (1 - cos alpha). The shear stress over the shear rate (what the run
 * driver records as stress/eta) is (n0 / a^d) (nu_kin + nu_coll). The granular (kappa) terms of
 * Eq. 2.55 are not included. GRAN_ERR_ARG for options outside gran_srd_create's ranges or a theta
 * not finite and >= 0; GRAN_ERR_DOMAIN where the kinetic part diverges (2-D, alpha = 180). */
int gran_srd_viscosity_theory_(const gran_srd_options *o, double theta, double *nu_kin, double *nu_coll);

#ifdef __cplusplus
}
#endif

#endif
