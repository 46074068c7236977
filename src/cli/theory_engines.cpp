/* theory_engines.cpp - `granary theory SCENE` for the scenes the cooling-mixture theory of
 * theory.cpp does not describe:
 *  - aggregating DSMC scenes (e_agg > 0 or a finite e_frag, any selector): the temperature-dependent
 *    Smoluchowski kinetics, gran_theory_aggregation_law with the scene's processes, initial
 *    temperatures and theory_rtol, as the run driver writes it (src/io/engine_dsmc.cpp:
 *    clusters/n_theory = n_k x volume, temperatures/T_theory = T_k);
 *  - GSRD scenes: Haff's law with the mean-field rate of the run driver (temperature/T_theory) and
 *    with the Poisson-occupancy factor, and under Lees-Edwards shear the kinetic + collisional
 *    viscosity (src/srd/theory.cpp);
 *  - an engine without a theory: a line that says so, exit status 0.
 * What the engine has no theory for is said in one line ("no theory here for: ..."; JSON
 * "not_covered"). */
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "srd/srd_theory.h"
#include "theory_util.h"

namespace {

int fail(const char *what) {
  std::fprintf(stderr, "granary theory: %s: %s\n", what, cli_error());
  return 1;
}

std::string join(const std::vector<std::string> &v, const char *sep) {
  std::string o;
  for (const std::string &x : v) o += (o.empty() ? "" : sep) + x;
  return o;
}

void json_strings(std::string &o, const std::vector<std::string> &v) {
  o += '[';
  for (size_t i = 0; i < v.size(); i++) {
    if (i) o += ", ";
    cli_json::str(o, v[i]);
  }
  o += ']';
}

std::string fmt(const char *f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

const char *start_name(const gran_scene *s) {
  return s->init == SCENE_INIT_HCS     ? "in the homogeneous cooling state"
         : s->init == SCENE_INIT_EQUAL ? "with equal temperatures"
                                       : "with the listed temperatures";
}

}  // namespace

/* ---- aggregation and fragmentation ------------------------------------------------------------ */

int cli_theory_aggregation(const gran_scene *s, const cli_theory_request &r) {
  if (!r.lags.empty()) {
    std::fprintf(stderr, "granary theory: --lags: scene '%s' aggregates or fragments; the aggregation kinetics has no "
                         "TAMSD theory\n", r.scene_path);
    return 2;
  }
  if (r.approx == GRAN_THEORY_SONINE) {
    std::fprintf(stderr, "granary theory: --approximation sonine: scene '%s' aggregates or fragments; the first Sonine "
                         "approximation is implemented for a mixture of fixed species only\n", r.scene_path);
    return 2;
  }
  gran_mixture *mix = nullptr;
  struct Guard {
    gran_mixture **m;
    ~Guard() { gran_mixture_destroy(m); }
  } guard{&mix};
  if (gran_scene_mixture(s, &mix)) return fail("cannot build the mixture");
  int64_t M = 0;
  gran_mixture_nspecies(mix, &M);
  const size_t MM = (size_t)M;
  std::vector<double> m(MM), sg(MM), n0(MM), T0(MM);
  gran_mixture_get(mix, m.data(), sg.data(), n0.data());
  if (gran_scene_initial_temperatures(s, mix, T0.data(), nullptr)) return fail("cannot compute the initial temperatures");
  const gran_dsmc_agg_options &ag = s->agg; /* the cell selector's values too */
  const int64_t nt = (int64_t)r.times.size();
  std::vector<double> n((size_t)nt * MM), T((size_t)nt * MM), ovf((size_t)nt * 3), ntot((size_t)nt), Tmean((size_t)nt);
  if (nt && gran_theory_aggregation_law(mix, T0.data(), ag.e_agg, ag.e_frag, ag.eps_f, ag.frag_law, nt, r.times.data(),
                                        s->theory_rtol, n.data(), T.data(), ovf.data()))
    return fail("aggregation kinetics (gran_theory_aggregation_law) failed");
  /* totals over the sizes 1..M: number density and number-weighted mean temperature */
  auto totals = [M](const double *nk, const double *Tk, double *nsum, double *Tm) {
    double a = 0, b = 0;
    for (int64_t k = 0; k < M; k++) {
      a += nk[k];
      b += nk[k] * Tk[k];
    }
    *nsum = a;
    *Tm = a > 0 ? b / a : NAN;
  };
  double ntot0 = 0, Tmean0 = 0;
  totals(n0.data(), T0.data(), &ntot0, &Tmean0);
  for (int64_t i = 0; i < nt; i++) totals(&n[(size_t)i * MM], &T[(size_t)i * MM], &ntot[(size_t)i], &Tmean[(size_t)i]);

  const char *sel = s->selector == GRAN_SELECTOR_CELL ? "cell" : s->selector == GRAN_SELECTOR_BIRD ? "bird" : "lowrank";
  const char *law = ag.frag_law == GRAN_FRAG_BINARY ? "binary" : "monomers";
  const char *model = s->model == GRAN_RESTITUTION_MATRIX ? "matrix" : "constant";
  std::vector<std::string> nc = {"the HCS (tau0), tau_v, D, MSD, TAMSD and the first Sonine level (the theory of a "
                                 "mixture of fixed species)"};
  if (s->selector == GRAN_SELECTOR_CELL && s->cell.heat_rate > 0)
    nc.push_back("the white-noise thermostat (heat_rate): the kinetics cools freely");
  if (s->selector == GRAN_SELECTOR_CELL && s->cell.bath_density > 0)
    nc.push_back("the molecular-gas bath: the kinetics has no bath collisions");

  if (r.json) {
    using namespace cli_json;
    std::string o = "{\"scene\": ";
    str(o, r.scene_path);
    key(o, "engine");
    str(o, "dsmc");
    key(o, "theory");
    str(o, "aggregation");
    key(o, "selector");
    str(o, sel);
    o += ", \"nspecies\": " + std::to_string(M);
    key(o, "restitution");
    str(o, model);
    key(o, "hcs_start");
    o += s->init == SCENE_INIT_HCS ? "true" : "false";
    field(o, "t_start", s->t_start);
    field(o, "e_agg", ag.e_agg);
    field(o, "e_frag", ag.e_frag); /* null: no fragmentation */
    field(o, "eps_f", ag.eps_f);
    key(o, "frag_law");
    str(o, law);
    field(o, "rtol", s->theory_rtol);
    field(o, "n_total0", ntot0);
    field(o, "T_mean0", Tmean0);
    o += ", \"species\": [";
    for (size_t k = 0; k < MM; k++) {
      if (k) o += ", ";
      o += "{\"k\": " + std::to_string(k + 1);
      field(o, "n", n0[k]);
      field(o, "m", m[k]);
      field(o, "sigma", sg[k]);
      field(o, "T0", T0[k]);
      o += "}";
    }
    o += "]";
    if (nt) {
      key(o, "times");
      arr(o, r.times.data(), nt);
      key(o, "n");
      mat(o, n.data(), nt, M);
      key(o, "T");
      mat(o, T.data(), nt, M);
      key(o, "n_total");
      arr(o, ntot.data(), nt);
      key(o, "T_mean");
      arr(o, Tmean.data(), nt);
      key(o, "overflow");
      mat(o, ovf.data(), nt, 3);
    }
    key(o, "not_covered");
    json_strings(o, nc);
    o += "}\n";
    std::fputs(o.c_str(), stdout);
    return 0;
  }

  std::printf("scene %s: aggregation%s, %" PRId64 " cluster sizes (species k = the k-mer, m_k = k m_1), selector %s, "
              "restitution %s, start %s\n",
              r.scene_path, std::isfinite(ag.e_frag) ? " and fragmentation" : "", M, sel, model, start_name(s));
  std::printf("theory: the temperature-dependent Smoluchowski equations (gran_theory_aggregation_law): E_agg = %g, "
              "E_frag = %s, eps_f = %g, fragments: %s; clusters larger than %" PRId64 " leave the system; "
              "rtol %g (theory_rtol)\n",
              ag.e_agg, std::isfinite(ag.e_frag) ? fmt("%g", ag.e_frag).c_str() : "inf (none)", ag.eps_f, law, M,
              s->theory_rtol);
  std::printf("n(0) = %.10g (number density of all clusters), T(0) = %.10g (number-weighted mean temperature)\n", ntot0,
              Tmean0);
  const double shown = 1e-12; /* sizes below this fraction of the total density are not listed */
  std::printf("%4s %14s %14s %16s %16s   (sizes with n_k >= %g n; --json lists every size)\n", "k", "m_k", "sigma_k",
              "n_k(0)", "T_k(0)", shown);
  for (size_t k = 0; k < MM; k++)
    if (n0[k] >= shown * ntot0)
      std::printf("%4zu %14.8g %14.8g %16.10g %16.10g\n", k + 1, m[k], sg[k], n0[k], T0[k]);
  if (nt) {
    std::printf("\nn_k(t) and T_k(t) (the run driver writes n_k(t) x the volume as clusters/n_theory and T_k(t) as "
                "temperatures/T_theory); all: the sizes 1..%" PRId64 "; >%" PRId64 ": number density beyond them\n",
                M, M);
    std::printf("%14s %5s %16s %16s\n", "t", "k", "n_k(t)", "T_k(t)");
    for (int64_t i = 0; i < nt; i++) {
      const size_t I = (size_t)i;
      for (size_t k = 0; k < MM; k++)
        if (n[I * MM + k] >= shown * ntot[I])
          std::printf("%14.8g %5zu %16.10g %16.10g\n", r.times[I], k + 1, n[I * MM + k], T[I * MM + k]);
      std::printf("%14.8g %5s %16.10g %16.10g\n", r.times[I], "all", ntot[I], Tmean[I]);
      std::printf("%14.8g %4s%" PRId64 " %16.10g\n", r.times[I], ">", M, ovf[I * 3]);
    }
  }
  std::printf("no theory here for: %s\n", join(nc, "; ").c_str());
  return 0;
}

/* ---- GSRD ------------------------------------------------------------------------------------- */

int cli_theory_srd(const gran_scene *s, const cli_theory_request &r) {
  if (!r.lags.empty()) {
    std::fprintf(stderr, "granary theory: --lags: scene '%s' is a GSRD scene; granary has no TAMSD theory for it\n",
                 r.scene_path);
    return 2;
  }
  if (r.approx_given) {
    std::fprintf(stderr, "granary theory: --approximation: scene '%s' is a GSRD scene; the approximations are those of "
                         "the DSMC mixture theory\n", r.scene_path);
    return 2;
  }
  const gran_srd_options &o = s->srd.opt;
  const int d = o.dim;
  const bool haff = gran_srd_haff_applies_(&o) != 0, shear = o.shear_rate != 0;
  const double vol = d == 3 ? o.a * o.a * o.a : o.a * o.a;
  const double rate = haff ? gran_srd_haff_rate_(&o) : NAN;
  const double pf = gran_srd_haff_poisson_factor_(d, o.n0), rate_p = rate * pf;
  const int64_t nt = (int64_t)r.times.size();
  std::vector<double> T((size_t)nt, NAN), Tp((size_t)nt, NAN);
  for (int64_t i = 0; i < nt && haff; i++) {
    T[(size_t)i] = gran_srd_haff_T_(&o, 1.0, r.times[(size_t)i]);
    Tp[(size_t)i] = gran_srd_haff_T_(&o, pf, r.times[(size_t)i]);
  }
  std::vector<std::string> nc;
  double nu_kin = NAN, nu_coll = NAN;
  bool visc = false;
  if (shear) {
    if (gran_srd_viscosity_theory_(&o, o.T0, &nu_kin, &nu_coll) == GRAN_SUCCESS) visc = true;
    else nc.push_back(std::string("the viscosity: ") + gran_last_error_message());
  }
  const double one_m_eff = (1.0 - o.eps * o.eps) * o.sigma * o.sigma * (o.n0 / vol) * std::sqrt(o.T0) * o.dt;
  if (!haff) {
    std::vector<std::string> why;
    if (o.thermostat) why.push_back("the thermostat holds it");
    if (shear) why.push_back("the Lees-Edwards shear heats it");
    if (o.wall_axis >= 0) why.push_back(o.vib_omega != 0 && o.vib_amp != 0 ? "walls, one vibrating" : "walls");
    if (o.accel[0] != 0 || o.accel[1] != 0 || o.accel[2] != 0) why.push_back("gravity or a body force");
    if (why.empty()) why.push_back("no dissipation (eps = 1 or sigma = 0)");
    nc.push_back("T(t) (not free cooling: " + join(why, ", ") + ")");
  }
  if (visc && o.eps < 1 && o.sigma > 0)
    nc.push_back("the granular terms of Eq. 2.55 in the viscosity (1 - eps_eff(T0) = " + fmt("%.3g", one_m_eff) + ")");
  if (visc && !o.thermostat) nc.push_back("the steady temperature under shear (the viscosity is at theta = T0)");
  if (s->srd.obs_clustering) nc.push_back("clustering (E_kin, Mach)");
  if (s->srd.obs_sk) nc.push_back("S(k)");
  if (s->srd.obs_a2) nc.push_back("a2");
  if (s->srd.obs_profile) nc.push_back("the velocity profile");
  if (!s->srd.snap_index.empty()) nc.push_back("the cell fields");
  const bool none = !haff && !visc;

  if (r.json) {
    using namespace cli_json;
    std::string j = "{\"scene\": ";
    str(j, r.scene_path);
    key(j, "engine");
    str(j, "srd");
    key(j, "theory");
    str(j, none ? "none" : "gsrd");
    j += ", \"dimension\": " + std::to_string(d);
    key(j, "cells");
    const double cells[3] = {(double)o.cells[0], (double)o.cells[1], (double)o.cells[2]};
    arr(j, cells, d);
    field(j, "a", o.a);
    field(j, "n0", o.n0);
    field(j, "dt", o.dt);
    field(j, "alpha", o.alpha_deg);
    field(j, "eps", o.eps);
    field(j, "sigma", o.sigma);
    field(j, "T0", o.T0);
    field(j, "shear_rate", o.shear_rate);
    key(j, "haff");
    if (haff) {
      j += "{\"rate\": ";
      num(j, rate);
      field(j, "tau", 1.0 / rate);
      field(j, "poisson_factor", pf);
      field(j, "rate_poisson", rate_p);
      j += "}";
    } else j += "null";
    if (nt) {
      key(j, "times");
      arr(j, r.times.data(), nt);
      key(j, "T");
      arr(j, T.data(), nt);
      key(j, "T_poisson");
      arr(j, Tp.data(), nt);
    }
    key(j, "viscosity");
    if (visc) {
      j += "{\"theta\": ";
      num(j, o.T0);
      key(j, "kinetic_equation");
      str(j, d == 2 ? "Eq. 1.48" : "Eq. 1.49");
      field(j, "nu_kinetic", nu_kin);
      field(j, "nu_collisional", nu_coll);
      field(j, "nu", nu_kin + nu_coll);
      field(j, "eta", o.n0 / vol * (nu_kin + nu_coll));
      j += "}";
    } else j += "null";
    key(j, "not_covered");
    json_strings(j, nc);
    j += "}\n";
    std::fputs(j.c_str(), stdout);
    return 0;
  }

  std::printf("scene %s: GSRD, %d-D, %lld", r.scene_path, d, (long long)o.cells[0]);
  for (int k = 1; k < d; k++) std::printf(" x %lld", (long long)o.cells[k]);
  std::printf(" cells of size a = %g, n0 = %g, dt = %g, alpha = %g deg, eps = %g, sigma = %g, T0 = %g\n", o.a, o.n0,
              o.dt, o.alpha_deg, o.eps, o.sigma, o.T0);
  if (none) {
    std::printf("no theory for this scene: Haff's law needs free cooling (eps < 1, sigma > 0, no thermostat, shear, "
                "walls or forces), the viscosity Lees-Edwards shear\n");
    std::printf("no theory here for: %s\n", join(nc, "; ").c_str());
    return 0;
  }
  if (haff) {
    std::printf("Haff's law T(t) = T0 / (1 + t/tau)^2, 1/tau = k (1 - eps^2) sigma^2 (n0/a^d) sqrt(T0) = %.10g "
                "(k = %s; the mean-field rate of Eq. 2.1, the run driver's temperature/T_theory)\n",
                rate, d == 3 ? "2/3" : "1");
    std::printf("Poisson occupancy of the cells: 1/tau = %.10g x the mean field = %.10g (first order in 1 - eps_eff)\n",
                pf, rate_p);
    if (nt) {
      std::printf("%14s %16s %16s\n", "t", "T(t)", "T(t) Poisson");
      for (int64_t i = 0; i < nt; i++)
        std::printf("%14.8g %16.10g %16.10g\n", r.times[(size_t)i], T[(size_t)i], Tp[(size_t)i]);
    }
  }
  if (visc) {
    std::printf("shear viscosity at theta = T0 = %g (Lees-Edwards shear rate %g): nu_kin = %.10g (%s), nu_coll = %.10g "
                "(collisional: (a^2/(6 d dt)) (q/M) (1 - cos alpha)), nu = %.10g; eta = (n0/a^d) nu = %.10g (what stress/eta "
                "measures)\n",
                o.T0, o.shear_rate, nu_kin, d == 2 ? "Eq. 1.48" : "Eq. 1.49", nu_coll, nu_kin + nu_coll,
                o.n0 / vol * (nu_kin + nu_coll));
  }
  if (!nc.empty()) std::printf("no theory here for: %s\n", join(nc, "; ").c_str());
  return 0;
}

/* ---- an engine without a theory --------------------------------------------------------------- */

int cli_theory_none(const gran_scene *s, const cli_theory_request &r, const std::string &why) {
  if (r.json) {
    using namespace cli_json;
    std::string o = "{\"scene\": ";
    str(o, r.scene_path);
    key(o, "engine");
    str(o, s->engine_type);
    key(o, "theory");
    str(o, "none");
    key(o, "not_covered");
    json_strings(o, {why});
    o += "}\n";
    std::fputs(o.c_str(), stdout);
    return 0;
  }
  std::printf("scene %s: engine \"%s\": no theory for this scene (%s)\n", r.scene_path, s->engine_type.c_str(),
              why.c_str());
  return 0;
}
