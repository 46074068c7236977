/* scene_dsmc.cpp - the DSMC engine's scene: its keys (declared once, as data: `granary keys dsmc`),
 * the parser of its tables (called by the core parser, src/io/scene.cpp, through the engine table)
 * and the DSMC part of the gran_scene_* API (mixture, initial temperatures, engine options).
 * How to add a key: docs/developers/schema.md. */
#include "io/scene_impl.h"

#include <cmath>

#include "io/engine.h"
#include "core/derived.h"
#include "core/run_bounds.h"

using gran_scene_io::Tab;
using gran_scene_io::gb;
using gran_scene_io::parse_times;
using gran_scene_io::require;
using gran_scene_io::require_run_steps;

/* ---- the keys of a DSMC scene: {table, key, type, default, bounds, unit, meaning, C field, why} ----
 * `why` set: the reader checks `bounds` with that message; else the parser below checks them.
 * Units: the scene's own (masses, lengths and densities as given; time in the unit of the
 * densities and speeds, T in energy units). */
const gran_scene_key gran_dsmc_scene_keys_[] = {
    {"", "mixture", "table", "required", "", "", "the species", "gran_scene_mixture", ""},
    {"", "restitution", "table", "eps = 1", "", "", "the restitution model", "gran_scene_mixture", ""},
    {"", "initial", "table", "HCS, <T> = 1", "", "", "the initial state (Maxwellian, zero momentum)",
     "gran_scene_initial_temperatures", ""},
    {"", "cell", "table", "", "", "", "the time-step/cell selector (needs selector = \"cell\")", "gran_dsmc_cell_options", ""},
    {"", "aggregation", "table", "off", "", "", "aggregation and fragmentation in any selector", "gran_dsmc_agg_options", ""},

    {"mixture", "nspecies", "integer", "length of the arrays", "1..1e8", "", "number of species M",
     "gran_mixture_create(nspecies)", ""},
    {"mixture", "mass", "float array (M)", "m1 * k", "> 0", "mass", "masses m_k", "gran_mixture_create(mass)", ""},
    {"mixture", "m1", "float", "1", "> 0", "mass", "mass of species 1 when mass is absent", "gran_mixture_create(mass)",
     "must be > 0"},
    {"mixture", "sigma", "float array (M)", "sigma1 * k^(1/3)", "> 0", "length", "diameters sigma_k",
     "gran_mixture_create(sigma)", ""},
    {"mixture", "sigma1", "float", "1", "> 0", "length", "diameter of species 1 when sigma is absent",
     "gran_mixture_create(sigma)", "must be > 0"},
    {"mixture", "density", "float array (M)", "required (or density_law)", ">= 0, n_1 > 0", "1/length^3",
     "number densities n_k (n_k = 0: tracers)", "gran_mixture_create(density)", ""},
    {"mixture", "density_law", "table", "", "", "", "n_k = n1 k^-theta", "gran_mixture_create(density)", ""},
    {"mixture.density_law", "n1", "float", "required", "> 0", "1/length^3", "density of species 1",
     "gran_mixture_create(density)", "must be > 0"},
    {"mixture.density_law", "theta", "float", "0", "", "", "exponent of the power law", "gran_mixture_create(density)", ""},
    {"mixture", "g2", "float", "1", "> 0", "", "contact value of the pair correlation, all pairs", "gran_mixture_set_g2",
     "must be > 0"},
    {"mixture", "g2_matrix", "float matrix (M x M)", "", "> 0, symmetric", "", "g2 per pair", "gran_mixture_set_g2_matrix", ""},

    {"restitution", "model", "string", "from the keys given", "\"constant\" | \"matrix\" | \"viscoelastic\"", "",
     "which restitution model", "gran_mixture_restitution_model", ""},
    {"restitution", "eps", "float", "1", "[0, 1]", "", "constant restitution coefficient", "gran_mixture_set_restitution",
     "restitution coefficient must be in [0, 1], got {}"},
    {"restitution", "eps_matrix", "float matrix (M x M)", "", "[0, 1], symmetric", "", "eps per pair",
     "gran_mixture_set_restitution_matrix", ""},
    {"restitution", "beta", "float", "", ">= 0", "", "viscoelastic beta = A kappa^(2/5), all pairs",
     "gran_mixture_set_viscoelastic", "must be >= 0"},
    {"restitution", "beta_matrix", "float matrix (M x M)", "", ">= 0, symmetric", "", "beta per pair",
     "gran_mixture_set_viscoelastic_matrix", ""},
    {"restitution", "material", "table", "", "", "", "beta per pair from one material",
     "gran_mixture_set_viscoelastic_material", ""},
    {"restitution.material", "A", "float", "required", ">= 0", "time", "dissipative constant A",
     "gran_mixture_set_viscoelastic_material(A)", "must be >= 0"},
    {"restitution.material", "Y", "float", "required", "> 0", "pressure", "Young's modulus",
     "gran_mixture_set_viscoelastic_material(Y)", "must be > 0"},
    {"restitution.material", "nu", "float", "required", "(-1, 0.5)", "", "Poisson ratio",
     "gran_mixture_set_viscoelastic_material(nu)", "Poisson ratio must be in (-1, 0.5)"},

    {"initial", "temperatures", "string | float array (M)", "\"hcs\"", "\"hcs\" | \"equal\" | M values > 0", "energy",
     "HCS temperature ratios, all equal, or listed (viscoelastic: not \"hcs\")", "gran_dsmc_create(T0)", ""},
    {"initial", "T_mean", "float", "1", "> 0", "energy", "\"hcs\": number-weighted mean <T(0)>; \"equal\": the common T",
     "gran_theory_hcs(GRAN_HCS_NORM_MEAN)", "must be > 0"},
    {"initial", "T1", "float", "", "> 0", "energy", "\"hcs\" normalised by T_1(0) instead",
     "gran_theory_hcs(GRAN_HCS_NORM_T1)", "must be > 0"},
    {"initial", "t_start", "float", "0", "", "time", "time of the initial state", "gran_dsmc_options.t_start", ""},

    {"engine", "selector", "string", "\"lowrank\"", "\"lowrank\" | \"bird\" | \"cell\"", "", "pair selection",
     "gran_dsmc_options.selector", ""},
    {"engine", "t_end", "float", "last output time", "> t_start", "time", "end of the run", "gran_dsmc_advance(t_end)", ""},
    {"engine", "counts", "integer array (M)", "one of counts / N1 / volume", ">= 0, N_1 >= 1", "", "particle numbers N_k",
     "gran_dsmc_create(counts)", ""},
    {"engine", "N1", "float", "", "[1, 1e12]", "", "N_1; V = N1 / n_1, N_k = round(n_k V)", "gran_dsmc_options.volume",
     "must be in [1, 1e12], got {}"},
    {"engine", "volume", "float", "", "> 0", "length^3", "V; N_k = round(n_k V)", "gran_dsmc_options.volume", "must be > 0"},
    {"engine", "bound_refresh", "integer", "0", ">= 0", "collisions", "collisions between tightenings of the speed bounds (0: N)",
     "gran_dsmc_options.bound_refresh", "must be >= 0"},
    {"engine", "speed_classes", "boolean | string", "\"auto\"", "true | false | \"auto\"", "",
     "speed classes of the event selectors", "gran_dsmc_options.speed_classes", ""},

    {"cell", "cells", "integer", "1", "1..1024", "", "cells per side of the box", "gran_dsmc_cell_options.cells",
     "must be in 1..1024 (cells per side of the box)"},
    {"cell", "dt", "float", "required", "> 0", "time", "time step", "gran_dsmc_cell_options.dt", "must be > 0"},
    {"cell", "fn", "float", "1", "> 0", "", "real particles per simulated particle; the box grows to fn V",
     "gran_dsmc_cell_options.fn", "must be > 0 (real particles per simulated particle)"},
    {"cell", "e_agg", "float", "0", ">= 0", "energy", "merge when mu g^2/2 < e_agg (0: off)", "gran_dsmc_cell_options.e_agg",
     "must be >= 0 (0: no aggregation)"},
    {"cell", "e_frag", "float", "inf", ">= 0", "energy", "shatter when mu g_n^2/2 > e_frag (inf: off)",
     "gran_dsmc_cell_options.e_frag", ""},
    {"cell", "eps_f", "float", "1", "[0, 1]", "", "the pieces keep eps_f^2 of the impact energy in the CM frame",
     "gran_dsmc_cell_options.eps_f", "must be in [0, 1]"},
    {"cell", "heat_rate", "float", "0", ">= 0", "energy/time", "white-noise thermostat heating dT/dt (0: off)",
     "gran_dsmc_cell_options.heat_rate", "must be >= 0 (0: no thermostat)"},
    {"cell", "bath_density", "float", "0", ">= 0", "1/length^3", "molecular-gas bath density n_b (0: off)",
     "gran_dsmc_cell_options.bath_density", "must be >= 0 (0: no bath)"},
    {"cell", "bath_mass", "float", "1", "> 0", "mass", "bath particles' mass", "gran_dsmc_cell_options.bath_mass",
     "must be > 0"},
    {"cell", "bath_T", "float", "1", ">= 0", "energy", "bath temperature", "gran_dsmc_cell_options.bath_T", "must be >= 0"},
    {"cell", "bath_sigma", "float", "1", ">= 0", "length", "bath particles' diameter", "gran_dsmc_cell_options.bath_sigma",
     "must be >= 0"},
    {"cell", "placement", "string", "\"random\"", "\"random\" | \"collision\"", "",
     "where merged clusters and fragments go", "gran_dsmc_cell_options.placement", ""},
    {"cell", "streams", "string", "\"serial\"", "\"serial\" | \"cells\"", "",
     "random numbers: one stream cell after cell, or one per cell and step (the same run on any number of threads; "
     "no aggregation yet)",
     "gran_dsmc_cell_options.streams", ""},

    {"aggregation", "e_agg", "float", "0", ">= 0", "energy", "merge when mu g^2/2 < e_agg (0: off)",
     "gran_dsmc_agg_options.e_agg", "must be >= 0 (0: no aggregation)"},
    {"aggregation", "e_frag", "float", "inf", ">= 0", "energy", "shatter when mu g_n^2/2 > e_frag (inf: off)",
     "gran_dsmc_agg_options.e_frag", ""},
    {"aggregation", "eps_f", "float", "1", "[0, 1]", "", "the pieces keep eps_f^2 of the impact energy in the CM frame",
     "gran_dsmc_agg_options.eps_f", "must be in [0, 1]"},
    {"aggregation", "frag_law", "string", "\"monomers\"", "\"monomers\" | \"binary\"", "", "fragment law",
     "gran_dsmc_agg_options.frag_law", ""},

    {"observables", "times", "times", "41 log-spaced times up to t_end", "in [t_start, t_end], increasing", "time",
     "output times: a list, {linear = {start, stop, n}} or {log = {start, stop, n}}", "gran_scene.times", ""},
    {"observables", "temperatures", "boolean", "true", "", "", "T_k(t) and the theory T_k(t)", "gran_scene.obs_temperatures", ""},
    {"observables", "msd", "boolean", "true (false with aggregation)", "", "", "MSD_k(t), total MSD and theory",
     "GRAN_OBSERVE_DISPLACEMENT", ""},
    {"observables", "energy", "boolean", "true", "", "", "kinetic, initial and dissipated energy", "gran_scene.obs_energy", ""},
    {"observables", "momentum", "boolean", "false", "", "", "total momentum", "gran_scene.obs_momentum", ""},
    {"observables", "collision_counts", "boolean", "false", "", "", "collisions per species pair (cumulative)",
     "GRAN_OBSERVE_COLLISION_COUNTS", ""},
    {"observables", "sonine_a2", "boolean", "false", "", "", "Sonine coefficient a2 per species", "gran_scene.obs_sonine_a2", ""},
    {"observables", "theory", "boolean", "true", "", "", "write the theory curves", "gran_scene.obs_theory", ""},
    {"observables", "theory_rtol", "float", "1e-8", "(0, 1)", "", "tolerance of the theory integrations",
     "gran_scene.theory_rtol", "must be in (0, 1)"},
    {"observables", "theory_sonine", "boolean", "false", "", "", "also the first Sonine T_k(t), a2_k(t)",
     "gran_scene.obs_theory_sonine", ""},
    {"observables", "sonine_order", "integer", "2", "[2, 3]", "",
     "level of theory_sonine: 2 the first Sonine (a2), 3 the second (a2, a3; msd_theory_sonine on its trajectory)",
     "gran_scene.theory_sonine_order",
     "must be 2 (first Sonine level: a2) or 3 (second: a2, a3), got {}"},
    {"observables", "velocity_distribution", "boolean | table", "false", "", "",
     "density of c = |v - u_k| / sqrt(2 T_k/m_k) per species", "gran_scene.obs_veldist", ""},
    {"observables.velocity_distribution", "bins", "integer", "60", "[1, 1e6]", "", "histogram bins", "gran_scene.vd_bins",
     "must be in [1, 1e6]"},
    {"observables.velocity_distribution", "cmax", "float", "4", "> 0", "", "largest reduced speed c", "gran_scene.vd_cmax",
     "must be > 0"},
    {"observables", "tamsd", "table", "off", "", "", "TAMSD of tracer trajectories", "GRAN_OBSERVE_TRAJECTORIES", ""},
    {"observables.tamsd", "tracers", "integer", "required", ">= 1", "", "trajectories per species",
     "gran_dsmc_options.traj_per_species", "must be >= 1, got {}"},
    {"observables.tamsd", "dt", "float", "required", "> 0", "time", "sampling interval", "gran_dsmc_options.traj_dt",
     "must be > 0"},
    {"observables.tamsd", "samples", "integer", "required", "[2, 1e8]", "", "samples from t_start (t_start + dt (samples-1) <= t_end)",
     "gran_dsmc_options.traj_samples", "must be in [2, 1e8]"},
    {"observables.tamsd", "lags", "times", "30 log-spaced", "in [dt, dt (samples-1))", "time",
     "lags, rounded to multiples of dt", "gran_scene.tamsd_lags", ""},
};
const size_t gran_dsmc_scene_nkeys_ = sizeof gran_dsmc_scene_keys_ / sizeof gran_dsmc_scene_keys_[0];

namespace {

/* A scene of the cell selector ([cell] parsed, t_end known): every species with a density gets
 * particles (an empty gas has no temperature: NaN is never an output; with aggregation the
 * species are cluster sizes, which may be empty: the monomers must not be), and the run's steps
 * (t_end - t_start) / dt are within the shared bound. */
void check_cell_run(Tab &top, Tab &en, const gran_scene &s) {
  Tab ce = top.sub("cell");
  const gran_dsmc_cell_options &c = s.cell;
  const bool agg = c.e_agg > 0 || std::isfinite(c.e_frag);
  if (agg && c.streams == GRAN_CELL_STREAMS_CELLS)
    ce.fail("streams", "\"cells\" does not take aggregation or fragmentation yet (e_agg, e_frag): use \"serial\"");
  double N = 0;
  for (int64_t k = 0; k < s.nspecies; k++) {
    const double nk = s.counts_kind == 0 ? (double)s.counts[(size_t)k] : std::nearbyint(s.density[(size_t)k] * s.volume / c.fn);
    if (s.counts_kind != 0 && s.density[(size_t)k] > 0 && !(nk >= 1) && (!agg || k == 0)) {
      const std::string msg = "n_k V / fn = " + Tab::num_str(s.density[(size_t)k]) + " x " + Tab::num_str(s.volume) +
                              " / " + Tab::num_str(c.fn) + " gives " + Tab::num_str(nk) + " simulated particles of species " +
                              std::to_string(k) + " (at least 1 needed: an empty species has no temperature)";
      if (c.fn > 1 && std::nearbyint(s.density[(size_t)k] * s.volume) >= 1) ce.fail("fn", msg);
      en.fail(s.counts_kind == 1 ? "N1" : "volume", msg);
    }
    N += nk;
  }
  const double C = (double)c.cells * (double)c.cells * (double)c.cells;
  require_run_steps(ce, "dt", (s.t_end - s.t_start) / c.dt, N + C,
                    "[engine] t_end - t_start = " + Tab::num_str(s.t_end - s.t_start) + " in steps of dt = " +
                        Tab::num_str(c.dt));
}

/* What the tables of one DSMC scene share while they are read. */
struct Ctx {
  Tab &top;
  gran_scene &s;
  double mem_limit;
  int64_t M = -1;      /* species */
  std::string M_from;  /* the key that gave M (named when an array disagrees) */
};

/* [mixture]: the species (required) */
void parse_mixture(Ctx &c) {
  Tab &top = c.top;
  gran_scene &s = c.s;
  const double mem_limit = c.mem_limit;
  /* ---- [mixture] ---- */
  if (!top.has("mixture")) top.fail_missing("mixture", "the [mixture] table is required");
  Tab mx = top.sub("mixture");
  mx.set_known();
  int64_t &M = c.M;
  std::string &M_from = c.M_from;
  if (mx.has("nspecies")) {
    M = mx.count("nspecies");
    require(M >= 1, mx, "nspecies", "must be >= 1, got " + std::to_string(M));
    require(M <= 100000000, mx, "nspecies", "must be <= 1e8, got " + std::to_string(M));
    /* every species costs a few hundred bytes in the scene, the mixture, the trees and the engine */
    require(400.0 * (double)M <= mem_limit, mx, "nspecies",
            std::to_string(M) + " species need about " + gb(400.0 * (double)M) + ", more than the " + gb(mem_limit) +
                " available (set [engine] max_memory_gb to allow more)");
    M_from = "nspecies";
  }
  std::vector<double> mass, sigma, density;
  auto take = [&](const char *k, std::vector<double> &v) {
    if (!mx.has(k)) return;
    v = mx.numbers(k);
    if (M < 0) {
      M = (int64_t)v.size();
      M_from = k;
      if (M < 1) mx.fail(k, "the array is empty");
    } else if ((int64_t)v.size() != M) {
      mx.fail(k, "has " + std::to_string(v.size()) + " entries, but " + M_from + " gives " + std::to_string(M) +
                     " species");
    }
  };
  take("mass", mass);
  take("sigma", sigma);
  take("density", density);
  if (M < 0) mx.fail_missing("nspecies", "or give the arrays mass / sigma / density");
  s.nspecies = M;
  const double m1 = mx.real("m1"), sigma1 = mx.real("sigma1");
  if (mx.has("mass") && mx.has("m1")) mx.fail("m1", "give either 'mass' or 'm1', not both");
  if (mx.has("sigma") && mx.has("sigma1")) mx.fail("sigma1", "give either 'sigma' or 'sigma1', not both");
  if (mass.empty()) {
    mass.resize((size_t)M);
    for (int64_t k = 0; k < M; k++) mass[(size_t)k] = m1 * (double)(k + 1);
  }
  if (sigma.empty()) {
    sigma.resize((size_t)M);
    for (int64_t k = 0; k < M; k++) sigma[(size_t)k] = sigma1 * std::cbrt((double)(k + 1));
  }
  for (int64_t k = 0; k < M; k++) {
    require(mass[(size_t)k] > 0, mx, "mass", "entry " + std::to_string(k + 1) + " must be > 0");
    require(sigma[(size_t)k] > 0, mx, "sigma", "entry " + std::to_string(k + 1) + " must be > 0");
  }
  if (mx.has("density") && mx.has("density_law")) mx.fail("density_law", "give either 'density' or 'density_law', not both");
  if (mx.has("density_law")) {
    Tab law = mx.sub("density_law");
    law.set_known();
    if (!law.has("n1")) law.fail_missing("n1");
    const double n1 = law.value("n1"), theta = law.real("theta");
    law.finish();
    density.resize((size_t)M);
    for (int64_t k = 0; k < M; k++) density[(size_t)k] = n1 * std::pow((double)(k + 1), -theta);
  } else if (density.empty()) {
    mx.fail_missing("density", "or density_law = {n1 = ..., theta = ...}");
  }
  for (int64_t k = 0; k < M; k++)
    require(density[(size_t)k] >= 0, mx, mx.has("density") ? "density" : "density_law",
            "entry " + std::to_string(k + 1) + " is negative");
  require(density[0] > 0, mx, mx.has("density") ? "density" : "density_law",
          "the first species must have a positive density (it sets the time unit)");
  if (mx.has("g2") && mx.has("g2_matrix")) mx.fail("g2_matrix", "give either 'g2' or 'g2_matrix', not both");
  if (mx.has("g2_matrix")) {
    s.g2_is_matrix = 1;
    s.g2_matrix = mx.matrix("g2_matrix", M);
    for (double g : s.g2_matrix) require(g > 0, mx, "g2_matrix", "entries must be > 0");
  } else {
    s.g2 = mx.real("g2");
  }
  mx.finish();
  s.mass = mass;
  s.sigma = sigma;
  s.density = density;
}

/* [restitution]: the model (absent: eps = 1) */
void parse_restitution(Ctx &c) {
  Tab &top = c.top;
  gran_scene &s = c.s;
  const int64_t M = c.M;
  const std::vector<double> &mass = s.mass, &sigma = s.sigma;
  /* ---- [restitution] ---- */
  if (top.has("restitution")) {
    Tab rs = top.sub("restitution");
    rs.set_known();
    std::string model = rs.string("model", rs.has("eps_matrix") ? "matrix" : (rs.has("beta") || rs.has("beta_matrix") || rs.has("material")) ? "viscoelastic" : "constant");
    auto forbid = [&](const char *k, const char *m) {
      if (rs.has(k)) rs.fail(k, std::string("not used by model = \"") + m + "\"");
    };
    if (model == "constant") {
      s.model = GRAN_RESTITUTION_CONSTANT;
      forbid("eps_matrix", "constant"), forbid("beta", "constant"), forbid("beta_matrix", "constant"), forbid("material", "constant");
      s.eps = rs.real("eps");
    } else if (model == "matrix") {
      s.model = GRAN_RESTITUTION_MATRIX;
      forbid("eps", "matrix"), forbid("beta", "matrix"), forbid("beta_matrix", "matrix"), forbid("material", "matrix");
      if (!rs.has("eps_matrix")) rs.fail_missing("eps_matrix", "model = \"matrix\" needs it");
      s.eps_matrix = rs.matrix("eps_matrix", M);
      for (double e : s.eps_matrix)
        require(e >= 0 && e <= 1, rs, "eps_matrix", "restitution coefficients must be in [0, 1], got " + Tab::num_str(e));
    } else if (model == "viscoelastic") {
      s.model = GRAN_RESTITUTION_VISCOELASTIC;
      forbid("eps", "viscoelastic"), forbid("eps_matrix", "viscoelastic");
      int n = rs.has("beta") + rs.has("beta_matrix") + rs.has("material");
      if (n == 0) rs.fail_missing("beta", "model = \"viscoelastic\" needs beta, beta_matrix or material");
      if (n > 1) rs.fail(rs.has("material") ? "material" : "beta_matrix", "give only one of beta, beta_matrix, material");
      if (rs.has("beta")) {
        s.visco_kind = 0;
        s.beta = rs.value("beta");
      } else if (rs.has("beta_matrix")) {
        s.visco_kind = 1;
        s.beta_matrix = rs.matrix("beta_matrix", M);
        for (double b : s.beta_matrix) require(b >= 0, rs, "beta_matrix", "entries must be >= 0");
      } else {
        s.visco_kind = 2;
        Tab mt = rs.sub("material");
        mt.set_known();
        for (const char *k : {"A", "Y", "nu"})
          if (!mt.has(k)) mt.fail_missing(k);
        s.mat_A = mt.value("A");
        s.mat_Y = mt.value("Y");
        s.mat_nu = mt.value("nu");
        mt.finish();
        /* the largest beta_ij (gran_mixture_set_viscoelastic_material) must be finite */
        double smax = 0, mmin = HUGE_VAL;
        for (int64_t k = 0; k < M; k++) smax = std::fmax(smax, sigma[(size_t)k]), mmin = std::fmin(mmin, mass[(size_t)k]);
        const double rho = 2.0 * s.mat_Y / (3.0 * (1.0 - s.mat_nu) * (1.0 + s.mat_nu));
        const double bmax = 1.5 * s.mat_A * std::pow(rho * std::sqrt(0.5 * smax) / (0.5 * mmin), 0.4);
        require(std::isfinite(rho) && std::isfinite(bmax), rs, "material",
                "A and Y give a viscoelastic beta that overflows (" + Tab::num_str(bmax) + ")");
      }
    } else {
      rs.fail("model", "unknown model \"" + model + "\" (constant, matrix or viscoelastic)");
    }
    rs.finish();
  }
}

/* [initial]: the initial temperatures (absent: the HCS with <T> = 1) */
void parse_initial(Ctx &c) {
  Tab &top = c.top;
  gran_scene &s = c.s;
  const int64_t M = c.M;
  const std::string &M_from = c.M_from;
  const std::vector<double> &mass = s.mass;
  /* ---- [initial] ---- */
  if (top.has("initial")) {
    Tab in = top.sub("initial");
    in.set_known();
    s.t_start = in.real("t_start");
    if (in.has("T_mean") && in.has("T1")) in.fail("T1", "give either 'T_mean' or 'T1', not both");
    if (in.has("temperatures")) {
      const toml::value &x = in.get("temperatures");
      if (x.is_string()) {
        const std::string &v = x.as_string().str;
        if (v == "hcs") s.init = SCENE_INIT_HCS;
        else if (v == "equal") s.init = SCENE_INIT_EQUAL;
        else in.fail("temperatures", "expected \"hcs\", \"equal\" or an array, got \"" + v + "\"");
      } else if (x.is_array()) {
        s.init = SCENE_INIT_LIST;
        for (const auto &e : x.as_array()) s.T_list.push_back(in.num("temperatures", e));
        if ((int64_t)s.T_list.size() != M)
          in.fail("temperatures", "has " + std::to_string(s.T_list.size()) + " entries, but " + M_from + " gives " +
                                      std::to_string(M) + " species");
        for (double T : s.T_list) require(T > 0, in, "temperatures", "must be > 0");
      } else {
        in.fail("temperatures", std::string("expected \"hcs\", \"equal\" or an array, got ") + Tab::type_name(x));
      }
    }
    if (s.model == GRAN_RESTITUTION_VISCOELASTIC && s.init == SCENE_INIT_HCS)
      in.fail("temperatures", std::string(in.has("temperatures") ? "\"hcs\"" : "the default \"hcs\"") +
                                  ": viscoelastic restitution has no homogeneous cooling state with constant "
                                  "temperature ratios; give temperatures = \"equal\" or a list");
    if (s.init == SCENE_INIT_LIST && (in.has("T_mean") || in.has("T1")))
      in.fail(in.has("T1") ? "T1" : "T_mean", "not used when temperatures are listed");
    if (in.has("T1")) {
      if (s.init != SCENE_INIT_HCS) in.fail("T1", "only with temperatures = \"hcs\"");
      s.hcs_norm = GRAN_HCS_NORM_T1;
      s.T_value = in.value("T1");
    } else {
      s.T_value = in.real("T_mean");
    }
    /* derived values must stay finite: squared speeds 3 T/m (far tails: x 100) and the energy of
     * up to 4e9 particles */
    double mmin = HUGE_VAL, Tmax = s.T_value;
    for (double m : mass) mmin = std::fmin(mmin, m);
    for (double T : s.T_list) Tmax = std::fmax(Tmax, T);
    const char *tk = s.init == SCENE_INIT_LIST ? "temperatures" : in.has("T1") ? "T1" : "T_mean";
    require(gran_derived_finite(300.0 * Tmax / mmin) && gran_derived_finite(1.5 * Tmax * 4e9 * 100.0), in, tk,
            "temperature " + Tab::num_str(Tmax) + " is too large: speeds and energies would overflow");
    in.finish();
  } else if (s.model == GRAN_RESTITUTION_VISCOELASTIC) {
    top.fail_missing("initial", "viscoelastic restitution has no homogeneous cooling state: give [initial] "
                                "temperatures = \"equal\" or a list");
  }
}

/* [engine]: the selector, the particle numbers, the end time (the shared keys: the core) */
void parse_engine(Ctx &c) {
  Tab &top = c.top;
  gran_scene &s = c.s;
  const int64_t M = c.M;
  const std::string &M_from = c.M_from;
  /* ---- [engine] ---- */
  if (!top.has("engine")) top.fail_missing("engine", "the [engine] table is required");
  Tab en = top.sub("engine");
  en.set_known();
  gran_scene_engine_common_(en, s); /* type, seed, replicas, keep_replicas, max_memory_gb */
  const std::string sel = en.word("selector");
  if (sel == "lowrank") s.selector = GRAN_SELECTOR_LOWRANK;
  else if (sel == "bird") s.selector = GRAN_SELECTOR_BIRD;
  else if (sel == "cell") s.selector = GRAN_SELECTOR_CELL; /* [cell] below */
  else en.fail("selector", "unknown selector \"" + sel + "\" (lowrank, bird or cell)");
  int nc = en.has("counts") + en.has("N1") + en.has("volume");
  if (nc == 0) en.fail_missing("counts", "give the particle numbers as counts = [...], N1 = ... or volume = ...");
  if (nc > 1) en.fail(en.has("volume") ? "volume" : "N1", "give only one of counts, N1, volume");
  if (en.has("counts")) {
    s.counts_kind = 0;
    const toml::value &x = en.get("counts");
    if (!x.is_array()) en.fail("counts", std::string("expected an array of integers, got ") + Tab::type_name(x));
    for (const auto &e : x.as_array()) {
      int64_t c = en.cnt("counts", e);
      if (c < 0) en.fail("counts", "particle numbers must be >= 0, got " + std::to_string(c));
      s.counts.push_back(c);
    }
    if ((int64_t)s.counts.size() != M)
      en.fail("counts", "has " + std::to_string(s.counts.size()) + " entries, but " + M_from + " gives " +
                            std::to_string(M) + " species");
    if (s.counts[0] < 1) en.fail("counts", "the first species needs at least one particle");
  } else if (en.has("N1")) {
    s.counts_kind = 1;
    s.N1 = en.value("N1");
    s.volume = s.N1 / s.density[0];
  } else {
    s.counts_kind = 2;
    s.volume = en.value("volume");
  }
  if (s.counts_kind != 0) {
    double total = 0;
    for (double n : s.density) total += std::nearbyint(n * s.volume);
    require(total <= 4e9, en, s.counts_kind == 1 ? "N1" : "volume", "gives " + Tab::num_str(total) + " particles (limit 4e9)");
  }
  s.bound_refresh = en.integer("bound_refresh");
  /* true, false or "auto" (the default: GRAN_SPEED_CLASSES_AUTO) */
  s.speed_classes = GRAN_SPEED_CLASSES_AUTO;
  if (en.has("speed_classes")) {
    const toml::value &sc = en.get("speed_classes");
    if (sc.is_boolean()) s.speed_classes = sc.as_boolean() ? GRAN_SPEED_CLASSES_ON : GRAN_SPEED_CLASSES_OFF;
    else if (!sc.is_string() || sc.as_string().str != "auto") en.fail("speed_classes", "expected true, false or \"auto\"");
  }
  if (en.has("t_end")) s.t_end = en.number("t_end");
  en.finish();
}

/* [cell] (the time-step/cell selector) and [aggregation] */
void parse_cell_aggregation(Ctx &c) {
  Tab &top = c.top;
  gran_scene &s = c.s;
  /* ---- [cell]: the time-step/cell selector (src/dsmc/cell.cpp) ---- */
  /* e_agg, e_frag, eps_f of [cell] or [aggregation] (absent: the defaults) */
  auto agg_keys = [](Tab &t, double *e_agg, double *e_frag, double *eps_f) {
    *e_agg = t.real("e_agg");
    if (t.has("e_frag")) {
      const toml::value &x = t.get("e_frag");
      *e_frag = x.is_floating() ? x.as_floating() : t.number("e_frag");
      require(!std::isnan(*e_frag) && *e_frag >= 0, t, "e_frag", "must be >= 0 (inf or absent: no fragmentation)");
    }
    *eps_f = t.real("eps_f");
  };
  gran_dsmc_cell_options_default(&s.cell);
  if (s.selector == GRAN_SELECTOR_CELL && !top.has("cell"))
    top.fail_missing("cell", "selector \"cell\" needs a [cell] table (at least dt)");
  if (top.has("cell")) {
    if (s.selector != GRAN_SELECTOR_CELL) top.fail("cell", "the [cell] table needs [engine] selector = \"cell\"");
    Tab ce = top.sub("cell");
    ce.set_known();
    gran_dsmc_cell_options &c = s.cell;
    c.cells = ce.integer("cells");
    if (!ce.has("dt")) ce.fail_missing("dt", "the time step dt is required");
    c.dt = ce.value("dt");
    c.fn = ce.real("fn");
    agg_keys(ce, &c.e_agg, &c.e_frag, &c.eps_f);
    c.heat_rate = ce.real("heat_rate");
    c.bath_density = ce.real("bath_density");
    c.bath_mass = ce.real("bath_mass");
    c.bath_T = ce.real("bath_T");
    c.bath_sigma = ce.real("bath_sigma");
    const std::string pl = ce.word("placement");
    if (pl == "random") c.placement = GRAN_PLACE_RANDOM;
    else if (pl == "collision") c.placement = GRAN_PLACE_COLLISION;
    else ce.fail("placement", "unknown placement \"" + pl + "\" (random or collision)");
    const std::string st = ce.word("streams");
    if (st == "serial") c.streams = GRAN_CELL_STREAMS_SERIAL;
    else if (st == "cells") c.streams = GRAN_CELL_STREAMS_CELLS;
    else ce.fail("streams", "unknown streams \"" + st + "\" (serial or cells)");
    ce.finish();
  }

  /* ---- [aggregation]: aggregation and fragmentation in any selector (src/dsmc/agg_event.cpp;
   * for selector "cell" the same keys as [cell], which then must not repeat them) ---- */
  gran_dsmc_agg_options_default(&s.agg);
  if (top.has("aggregation")) {
    Tab ag = top.sub("aggregation");
    ag.set_known();
    if (s.selector == GRAN_SELECTOR_CELL && top.has("cell")) {
      Tab ce = top.sub("cell");
      for (const char *k : {"e_agg", "e_frag", "eps_f"})
        if (ce.has(k) && ag.has(k)) ag.fail(k, std::string("is given in [cell] too: give it in one table"));
    }
    if (s.speed_classes == GRAN_SPEED_CLASSES_ON) top.fail("aggregation", "speed classes ([engine] speed_classes) have no aggregation");
    gran_dsmc_agg_options &a = s.agg;
    agg_keys(ag, &a.e_agg, &a.e_frag, &a.eps_f);
    const std::string law = ag.word("frag_law");
    if (law == "monomers") a.frag_law = GRAN_FRAG_MONOMERS;
    else if (law == "binary") a.frag_law = GRAN_FRAG_BINARY;
    else ag.fail("frag_law", "unknown fragment law \"" + law + "\" (monomers or binary)");
    ag.finish();
    if (s.selector == GRAN_SELECTOR_CELL) { /* the cell selector's options hold them */
      if (ag.has("e_agg")) s.cell.e_agg = a.e_agg;
      if (ag.has("e_frag")) s.cell.e_frag = a.e_frag;
      if (ag.has("eps_f")) s.cell.eps_f = a.eps_f;
      s.cell.frag_law = a.frag_law;
    }
  }
  if (s.selector == GRAN_SELECTOR_CELL) { /* one truth: the cell options */
    s.agg.e_agg = s.cell.e_agg;
    s.agg.e_frag = s.cell.e_frag;
    s.agg.eps_f = s.cell.eps_f;
    s.agg.frag_law = s.cell.frag_law;
  }
}

/* [observables]: output times and what is recorded */
void parse_observables(Ctx &c) {
  Tab &top = c.top;
  gran_scene &s = c.s;
  const int64_t M = c.M;
  Tab en = top.sub("engine");
  const bool have_tend = en.has("t_end");
  /* ---- [observables] ---- */
  Tab ob = top.sub_or_empty("observables");
  ob.set_known();
  if (ob.has("times")) {
    s.times = parse_times(ob, "times");
  } else {
    if (!have_tend) en.fail_missing("t_end", "or give [observables] times");
    double span = s.t_end - s.t_start;
    if (!(span > 0)) en.fail("t_end", "end time " + Tab::num_str(s.t_end) + " is not after t_start = " + Tab::num_str(s.t_start));
    const int n = 41;
    for (int i = 0; i < n; i++) s.times.push_back(s.t_start + span * std::pow(10.0, -3.0 + 3.0 * i / (n - 1)));
    s.times.back() = s.t_end;
  }
  if (!have_tend) s.t_end = s.times.back();
  if (!(s.t_end > s.t_start))
    en.fail("t_end", "end time " + Tab::num_str(s.t_end) + " is not after t_start = " + Tab::num_str(s.t_start));
  if (s.selector == GRAN_SELECTOR_CELL) check_cell_run(top, en, s);
  if (s.times.front() < s.t_start)
    ob.fail("times", "first output time " + Tab::num_str(s.times.front()) + " is before t_start = " + Tab::num_str(s.t_start));
  if (s.times.back() > s.t_end)
    ob.fail("times", "last output time " + Tab::num_str(s.times.back()) + " is after t_end = " + Tab::num_str(s.t_end));
  if (s.selector == GRAN_SELECTOR_CELL) /* the cell selector counts steps of cell.dt from t_start */
    gran_scene_io::step_of(have_tend ? en : ob, have_tend ? "t_end" : "times", s.t_end - s.t_start, s.cell.dt, "cell.dt");
  if (ob.has("velocity_distribution") && ob.get("velocity_distribution").is_table()) {
    Tab vd = ob.sub("velocity_distribution");
    vd.set_known();
    s.obs_veldist = 1;
    s.vd_bins = vd.integer("bins");
    s.vd_cmax = vd.real("cmax");
    vd.finish();
  } else {
    s.obs_veldist = ob.flag("velocity_distribution");
  }
  s.obs_temperatures = ob.flag("temperatures");
  /* with aggregation or fragmentation particles merge and split: displacements, trajectories and
   * per-pair collision counts are not defined, so msd defaults to off there and is refused on */
  const bool aggr = s.agg.e_agg > 0 || std::isfinite(s.agg.e_frag);
  s.obs_msd = ob.boolean("msd", !aggr);
  if (aggr && s.obs_msd)
    ob.fail("msd", "the mean-squared displacement is not defined with aggregation or fragmentation (clusters appear and "
                   "vanish): set msd = false or leave it out (its default is false there)");
  s.obs_energy = ob.flag("energy");
  s.obs_momentum = ob.flag("momentum");
  s.obs_collision_counts = ob.flag("collision_counts");
  if (aggr && s.obs_collision_counts)
    ob.fail("collision_counts", "per-pair collision counts are not defined with aggregation or fragmentation");
  if (aggr && ob.has("tamsd"))
    ob.fail("tamsd", "trajectories are not defined with aggregation or fragmentation (clusters appear and vanish)");
  s.obs_sonine_a2 = ob.flag("sonine_a2");
  s.obs_theory = ob.flag("theory");
  s.theory_rtol = ob.real("theory_rtol");
  /* the first Sonine trajectory (gran_theory_temperatures_approx) exists for a gas whose species
   * are fixed (viscoelastic included: its two-moment MSD does not, and the output says so) */
  s.obs_theory_sonine = ob.flag("theory_sonine");
  if (s.obs_theory_sonine) {
    if (!s.obs_theory) ob.fail("theory_sonine", "needs theory = true (it is written beside T_theory)");
    if (!s.obs_temperatures) ob.fail("theory_sonine", "needs temperatures = true (it is written beside T_theory)");
    if (s.agg.e_agg > 0 || std::isfinite(s.agg.e_frag))
      ob.fail("theory_sonine", "no Sonine theory for aggregation or fragmentation (the species change)");
  }
  s.theory_sonine_order = ob.integer("sonine_order");
  if (ob.has("sonine_order") && !s.obs_theory_sonine)
    ob.fail("sonine_order", "needs theory_sonine = true (it sets the level of T_theory_sonine)");
  if (s.theory_sonine_order == 3 && s.model == GRAN_RESTITUTION_VISCOELASTIC)
    ob.fail("sonine_order", "= 3 (the second Sonine level) needs constant or matrix restitution, not viscoelastic");
  if (ob.has("tamsd")) {
    Tab ta = ob.sub("tamsd");
    ta.set_known();
    for (const char *k : {"tracers", "dt", "samples"})
      if (!ta.has(k)) ta.fail_missing(k);
    s.obs_tamsd = 1;
    s.tamsd_tracers = ta.count_value("tracers");
    s.tamsd_dt = ta.value("dt");
    s.tamsd_samples = ta.count_value("samples");
    const double traj_bytes = 24.0 * (double)s.tamsd_tracers * (double)M * (double)s.tamsd_samples;
    require(traj_bytes <= 16e9, ta, "samples",
            "tracers x species x samples x 24 bytes = " + Tab::num_str(traj_bytes) + " bytes of trajectories (limit 16e9)");
    double t_meas = s.tamsd_dt * (double)(s.tamsd_samples - 1);
    require(s.t_start + t_meas <= s.t_end * (1 + 1e-12), ta, "samples",
            "trajectories need t_start + dt*(samples-1) = " + Tab::num_str(s.t_start + t_meas) + " <= t_end = " +
                Tab::num_str(s.t_end));
    if (ta.has("lags")) {
      s.tamsd_lags = parse_times(ta, "lags");
    } else {
      int n = 30;
      for (int i = 0; i < n; i++) s.tamsd_lags.push_back(s.tamsd_dt * std::pow(0.5 * (double)(s.tamsd_samples - 1), (double)i / (n - 1)));
    }
    for (double &L : s.tamsd_lags) {
      require(L >= s.tamsd_dt * (1 - 1e-12) && L < t_meas, ta, "lags",
              "lag " + Tab::num_str(L) + " outside [dt, dt*(samples-1)) = [" + Tab::num_str(s.tamsd_dt) + ", " + Tab::num_str(t_meas) + ")");
    }
    /* lags are whole sampling intervals: round them, and keep each once */
    std::vector<double> lags;
    for (double L : s.tamsd_lags) {
      const int64_t n = std::max<int64_t>(1, (int64_t)std::llround(L / s.tamsd_dt));
      const double r = (double)n * s.tamsd_dt;
      if (lags.empty() || r > lags.back()) lags.push_back(r);
    }
    s.tamsd_lags = lags;
    ta.finish();
  }
  ob.finish();
}

/* The theory a DSMC scene computes beside its run, against the theory work bound of
 * core/run_bounds.h. Passes over the M^2 species pairs, a lower bound: tau0 (1), the HCS start
 * (8, as measured for 1e4 - 3e4 species), and the ODE trajectories of the theory observables (at
 * least one pass per output time: T_theory, msd_theory unless the HCS closed form serves it, the
 * first Sonine trajectory at about 11 Maxwellian passes, the second (sonine_order = 3) at 400: 40x the first
 * at M = 100, measured, and as much again for its msd_theory_sonine; the TAMSD at one per lag). Above the
 * bound the scene is refused naming mixture.nspecies; above the warning level it warns. */
void check_theory_work(Ctx &c) {
  const gran_scene &s = c.s;
  const double nt = (double)s.times.size();
  const bool aggr = s.agg.e_agg > 0 || std::isfinite(s.agg.e_frag);
  double passes = 1.0;
  if (s.init == SCENE_INIT_HCS) passes += 8.0;
  if (s.obs_theory && !aggr) {
    if (s.obs_temperatures) passes += nt;
    const bool msd_closed = s.init == SCENE_INIT_HCS && s.model != GRAN_RESTITUTION_VISCOELASTIC;
    if (s.obs_msd && !msd_closed) passes += nt;
    if (s.obs_theory_sonine) passes += (s.theory_sonine_order == 3 ? 400.0 : 11.0) * nt;
    if (s.obs_theory_sonine && s.obs_msd && s.theory_sonine_order == 3) passes += 400.0 * nt; /* its MSD trajectory */
    if (s.obs_tamsd) passes += (double)s.tamsd_lags.size();
  }
  char why[320];
  const int level = gran::gran_theory_work_check(passes, (double)s.nspecies, why, sizeof why);
  if (level == 0) return;
  const std::string what = std::string("the kinetic theory beside this run (tau0") +
                           (s.init == SCENE_INIT_HCS ? ", the HCS start" : "") +
                           (s.obs_theory && !aggr ? ", the theory observables" : "") + ") needs at least " + why;
  Tab mx = c.top.sub("mixture");
  if (level == 2)
    mx.fail("nspecies", what + "; set [observables] theory = false and give the initial temperatures (\"equal\" or a "
                        "list) instead of \"hcs\", or use fewer species");
  gran_warning_add("scene key '%s': %s", mx.key("nspecies").c_str(), what.c_str());
}

}  // namespace

/* The DSMC tables: [mixture], [restitution], [initial], [engine], [cell], [aggregation],
 * [observables] (the core reads the title, the shared [engine] keys, [output] and the memory
 * check), in this order: each table's checks may use the tables before it. */
void gran_dsmc_scene_parse_(const gran_scene_doc &doc, gran_scene &s) {
  Ctx c{*doc.top, s, doc.mem_limit, -1, ""};
  parse_mixture(c);
  parse_restitution(c);
  parse_initial(c);
  parse_engine(c);
  parse_cell_aggregation(c);
  parse_observables(c);
  check_theory_work(c);
}


int gran_scene_T0_(const gran_scene *s, const gran_mixture *mix, double *T0, double *tau0) {
  const int64_t M = s->nspecies;
  if (s->init == SCENE_INIT_HCS) {
    double t0 = NAN;
    GRAN_CALL(gran_theory_hcs(mix, s->hcs_norm, s->T_value, T0, &t0));
  } else if (s->init == SCENE_INIT_EQUAL) {
    for (int64_t k = 0; k < M; k++) T0[k] = s->T_value;
  } else {
    for (int64_t k = 0; k < M; k++) T0[k] = s->T_list[(size_t)k];
  }
  /* tau0 = 2 / xi_1(T(0)) (Eq. 21): in the HCS every species gives the same value */
  if (tau0) {
    std::vector<double> xi((size_t)M);
    if (gran_theory_cooling_rates(mix, T0, xi.data()) == GRAN_SUCCESS) {
      *tau0 = xi[0] > 0 ? 2.0 / xi[0] : INFINITY;
    } else {
      *tau0 = NAN;
      gran_clear_error();
    }
  }
  return GRAN_SUCCESS;
}

/** @brief A new mixture built from the scene's [mixture] and [restitution] tables. */
GRAN_EXTERN int gran_scene_mixture(const gran_scene *scene, gran_mixture **mix) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(mix);
  GRAN_CHECK(scene->engine_type != "srd", GRAN_ERR_ARG, /* GSRD scenes set their gas in [engine] */
             "scene '%s' is a GSRD scene ([engine] type = \"srd\"): it has no mixture", scene->name.c_str());
  GRAN_TRY {
    const gran_scene *s = scene;
    gran_mixture *m = nullptr;
    GRAN_CALL(gran_mixture_create(s->nspecies, s->mass.data(), s->sigma.data(), s->density.data(), &m));
    int st = GRAN_SUCCESS;
    if (s->g2_is_matrix) st = gran_mixture_set_g2_matrix(m, s->g2_matrix.data());
    else st = gran_mixture_set_g2(m, s->g2);
    if (!st) {
      if (s->model == GRAN_RESTITUTION_CONSTANT) st = gran_mixture_set_restitution(m, s->eps);
      else if (s->model == GRAN_RESTITUTION_MATRIX) st = gran_mixture_set_restitution_matrix(m, s->eps_matrix.data());
      else if (s->visco_kind == 0) st = gran_mixture_set_viscoelastic(m, s->beta);
      else if (s->visco_kind == 1) st = gran_mixture_set_viscoelastic_matrix(m, s->beta_matrix.data());
      else st = gran_mixture_set_viscoelastic_material(m, s->mat_A, s->mat_Y, s->mat_nu);
    }
    if (st) {
      gran_mixture_destroy(&m);
      return st;
    }
    *mix = m;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Initial temperatures as [initial] asks (HCS from the theory module), and
 *  tau0 = 2 / xi_1(T(0)) (Eq. 21; the HCS relaxation time when the start is the HCS). */
GRAN_EXTERN int gran_scene_initial_temperatures(const gran_scene *scene, const gran_mixture *mix, double *T0,
                                                double *tau0) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(mix);
  GRAN_CHECK_PTR(T0);
  GRAN_TRY {
    int64_t M = 0;
    GRAN_CALL(gran_mixture_nspecies(mix, &M));
    GRAN_CHECK(M == scene->nspecies, GRAN_ERR_ARG, "argument 'mix' has %" PRId64 " species, the scene %" PRId64, M,
               scene->nspecies);
    return gran_scene_T0_(scene, mix, T0, tau0);
  }
  GRAN_CATCH
}

/** @brief Engine options and particle numbers of the scene (see the header). */
GRAN_EXTERN int gran_scene_dsmc_options(const gran_scene *scene, gran_dsmc_options *opt, int64_t *counts,
                                        int *have_counts) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(opt);
  GRAN_CHECK(scene->engine_type != "srd", GRAN_ERR_ARG, /* GSRD scenes run through gran_scene_run */
             "scene '%s' is a GSRD scene ([engine] type = \"srd\"): it has no DSMC options", scene->name.c_str());
  GRAN_TRY {
    const gran_scene *s = scene;
    GRAN_CALL(gran_dsmc_options_default(opt));
    opt->selector = s->selector;
    opt->seed = s->seed;
    opt->t_start = s->t_start;
    opt->bound_refresh = s->bound_refresh;
    opt->speed_classes = s->speed_classes;
    opt->observe = 0;
    if (s->obs_msd) opt->observe |= GRAN_OBSERVE_DISPLACEMENT;
    if (s->obs_collision_counts) opt->observe |= GRAN_OBSERVE_COLLISION_COUNTS;
    if (s->obs_tamsd) {
      opt->observe |= GRAN_OBSERVE_TRAJECTORIES;
      opt->traj_per_species = s->tamsd_tracers;
      opt->traj_dt = s->tamsd_dt;
      opt->traj_samples = s->tamsd_samples;
    }
    if (s->counts_kind != 0) opt->volume = s->volume; /* the engine rounds N_k = n_k V */
    if (counts)
      for (int64_t k = 0; k < s->nspecies; k++)
        counts[k] = s->counts_kind == 0 ? s->counts[(size_t)k]
                                        : (int64_t)std::nearbyint(s->density[(size_t)k] * s->volume /
                                                                  (s->selector == GRAN_SELECTOR_CELL ? s->cell.fn : 1.0));
    if (have_counts) *have_counts = s->counts_kind == 0;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief A new DSMC engine exactly as `granary run` creates it. */
GRAN_EXTERN int gran_scene_dsmc(const gran_scene *scene, const gran_mixture *mix, gran_dsmc **sim) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(mix);
  GRAN_CHECK_PTR(sim);
  GRAN_TRY {
    const gran_scene *s = scene;
    std::vector<double> T0((size_t)s->nspecies);
    GRAN_CALL(gran_scene_initial_temperatures(s, mix, T0.data(), nullptr));
    gran_dsmc_options opt;
    GRAN_CALL(gran_scene_dsmc_options(s, &opt, nullptr, nullptr));
    if (s->selector == GRAN_SELECTOR_CELL) /* cell selector */
      return gran_dsmc_create_cell(mix, s->counts_kind == 0 ? s->counts.data() : nullptr, T0.data(), &opt, &s->cell,
                                   sim);
    /* event selectors: [aggregation] (off: the plain engine) */
    return gran_dsmc_create_agg(mix, s->counts_kind == 0 ? s->counts.data() : nullptr, T0.data(), &opt, &s->agg, sim);
  }
  GRAN_CATCH
}

/** @brief The scene's aggregation and fragmentation ([aggregation], or [cell] of the cell selector). */
GRAN_EXTERN int gran_scene_dsmc_agg_options(const gran_scene *scene, gran_dsmc_agg_options *agg) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(agg);
  GRAN_TRY {
    *agg = scene->agg;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief The [cell] table of the scene (defaults where a key is not given). */
GRAN_EXTERN int gran_scene_dsmc_cell_options(const gran_scene *scene, gran_dsmc_cell_options *cell) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(cell);
  GRAN_TRY {
    *cell = scene->cell;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

bool gran_scene_driven_(const gran_scene *s) {
  return s->engine_type == "dsmc" && s->selector == GRAN_SELECTOR_CELL &&
         (s->cell.heat_rate > 0 || s->cell.bath_density > 0);
}

int gran_scene_driven_temperatures_(const gran_scene *s, const gran_mixture *mix, const double *T0, int64_t ntimes,
                                    const double *t, double rtol, double *T) {
  const gran_dsmc_cell_options &c = s->cell;
  const int64_t M = s->nspecies;
  std::vector<double> H((size_t)M, 0.0);
  if (c.heat_rate > 0) {
    double mass = 0; /* of the simulated particles: the thermostat removes their mass-weighted mean kick */
    for (int64_t k = 0; k < M; k++) {
      const double nk = s->counts_kind == 0 ? (double)s->counts[(size_t)k]
                                            : std::nearbyint(s->density[(size_t)k] * s->volume / c.fn);
      mass += nk * s->mass[(size_t)k];
    }
    for (int64_t k = 0; k < M; k++) H[(size_t)k] = mass > 0 ? c.heat_rate * (1.0 - s->mass[(size_t)k] / mass) : 0.0;
  }
  return gran_theory_temperatures_driven(mix, T0, H.data(), c.bath_density, c.bath_mass, c.bath_T, c.bath_sigma, ntimes,
                                         t, rtol, T);
}
