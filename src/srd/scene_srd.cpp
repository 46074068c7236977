/* scene_srd.cpp - the GSRD engine's scene (`[engine] type = "srd"`): its keys (declared once, as
 * data: `granary keys srd`) and the parser of its tables (called by the core parser,
 * src/io/scene.cpp, through the engine table). Tables: [engine] (the gran_srd_options keys, steps
 * or t_end, device), [boundaries] (lees_edwards, walls, vibrating_wall), [forces] (gravity,
 * body_force), [observables]; the core reads [output]. How to add a key:
 * docs/developers/schema.md. */
#include "io/scene_impl.h"

#include <algorithm>
#include <cmath>

#include "io/engine.h"
#include "srd/srd_limits.h" /* the bounds on what a GSRD run derives from its inputs */

using gran_scene_io::Tab;
using gran_scene_io::parse_times;
using gran_scene_io::require;
using gran_scene_io::require_run_steps;

/* ---- the keys of a GSRD scene: {table, key, type, default, bounds, unit, meaning, C field, why} ----
 * `why` set: the reader checks `bounds` with that message; else the parser below checks them.
 * Units: lengths in the scene's length unit (the cell size a is one), time in the unit of dt,
 * temperatures in energy units of a particle of mass 1. */
const gran_scene_key gran_srd_scene_keys_[] = {
    {"", "boundaries", "table", "periodic", "", "", "Lees-Edwards shear, walls, a vibrating wall", "gran_srd_options", ""},
    {"", "forces", "table", "none", "", "", "uniform accelerations", "gran_srd_options.accel", ""},

    {"engine", "dimension", "integer", "3", "2..3", "", "dimension of the box", "gran_srd_options.dim",
     "must be 2 or 3, got {}"},
    {"engine", "cells", "integer | integer array", "required (or box)", "1..2^20 per axis", "",
     "cells per axis: one integer (all axes) or `dimension` integers", "gran_srd_options.cells", ""},
    {"engine", "box", "float | float array", "", "whole numbers of cells", "length",
     "box lengths (instead of cells), each a whole number of cells of size a", "gran_srd_options.cells", ""},
    {"engine", "a", "float", "1", "> 0", "length", "cell size", "gran_srd_options.a", "cell size must be > 0, got {}"},
    {"engine", "n0", "float", "10", "> 0", "particles per cell", "mean particles per cell; N = round(n0 x cells)",
     "gran_srd_options.n0", "mean particles per cell must be > 0, got {}"},
    {"engine", "particles_per_cell", "float", "10", "> 0", "particles per cell", "the same as n0 (give one of them)",
     "gran_srd_options.n0", "mean particles per cell must be > 0, got {}"},
    {"engine", "dt", "float", "1", "> 0", "time", "time step", "gran_srd_options.dt", "time step must be > 0, got {}"},
    {"engine", "alpha", "float", "130", "(0, 180]", "degrees", "rotation angle of the collision step",
     "gran_srd_options.alpha_deg", "rotation angle must be in (0, 180] degrees, got {}"},
    {"engine", "eps", "float", "1", "[0, 1]", "", "restitution coefficient (eps < 1 needs sigma > 0)", "gran_srd_options.eps",
     "restitution coefficient must be in [0, 1], got {}"},
    {"engine", "sigma", "float", "0", ">= 0", "length", "particle diameter of the inelastic rule", "gran_srd_options.sigma",
     "particle diameter must be >= 0, got {}"},
    {"engine", "T0", "float", "1", "> 0", "energy", "initial temperature (and of the thermostats)", "gran_srd_options.T0",
     "temperature must be > 0, got {}"},
    {"engine", "steps", "integer", "required (or t_end, or the last output time)", "[1, 1e15]", "steps",
     "length of the run (shared bound on steps x particles: src/core/run_bounds.h)", "gran_scene.srd.steps",
     "must be in [1, 1e15], got {}"},
    {"engine", "t_end", "float", "", "> 0", "time", "length of the run as a time (a whole number of steps)", "gran_scene.srd.steps",
     "must be > 0"},
    {"engine", "sort_every", "integer", "50", "0..2147483647", "steps", "sort particles by cell every k steps (0: never)",
     "gran_srd_options.sort_every", "must be >= 0 (0: never sort)"},
    {"engine", "threads", "integer", "0", "0..4096", "", "OpenMP threads of one engine (0: all cores)",
     "gran_srd_options.threads", "must be in 0..4096 (0: all cores)"},
    {"engine", "device", "string", "\"cpu\"", "\"cpu\" | \"cuda\" | \"auto\" | \"reference\"", "",
     "where the engine runs", "gran_srd_options.device", ""},
    {"engine", "precision", "string", "\"double\"", "\"double\" | \"float\"", "", "particle storage on a device",
     "gran_srd_options.precision", ""},
    {"engine", "creation", "string", "\"serial\"", "\"serial\" | \"cells\"", "",
     "initial particles: one stream (serial) or a multinomial split over the cells, each cell its own generator",
     "gran_srd_options.creation", ""},
    {"engine", "decomposition", "string | integer array", "\"none\"", "\"none\" | \"auto\" | [Px, Py(, Pz)]", "",
     "one gas split over the run's processes (build/granary-mpi): none, the split with the fewest cut cells, or the "
     "bricks per axis (their product the process count); needs creation = \"cells\" and the CPU",
     "gran_scene.srd.decomp_grid", ""},
    {"engine", "thermostat", "boolean | string", "false", "false | true | \"off\" | \"cell\" | \"global\"", "",
     "cell-level Maxwell-Boltzmann thermostat (true, \"cell\") or one global factor (\"global\") at T0",
     "gran_srd_options.thermostat", ""},

    {"boundaries", "lees_edwards", "table", "off", "", "", "Lees-Edwards shear: flow x, gradient y", "gran_srd_options.shear_rate", ""},
    {"boundaries.lees_edwards", "shear_rate", "float", "required", "!= 0", "1/time", "shear rate", "gran_srd_options.shear_rate", ""},
    {"boundaries", "walls", "table", "off", "", "", "walls at 0 and L on one axis", "gran_srd_options.wall_axis", ""},
    {"boundaries.walls", "axis", "string | integer", "required", "\"x\" | \"y\" | \"z\" | 0..2, below dimension", "",
     "the walls' normal (not x or y under shear)", "gran_srd_options.wall_axis", ""},
    {"boundaries.walls", "rule", "string", "\"no-slip\"", "\"no-slip\" | \"slip\"", "",
     "bounce-back with virtual particles, or specular", "gran_srd_options.wall_rule", ""},
    {"boundaries.walls", "T", "float", "0", ">= 0", "energy", "temperature of the virtual particles (0: T0)",
     "gran_srd_options.wall_T", "virtual-particle temperature must be >= 0 (0: T0)"},
    {"boundaries", "vibrating_wall", "table", "off", "", "", "the lower wall moves with velocity amplitude omega cos(omega t)",
     "gran_srd_options.vib_amp", ""},
    {"boundaries.vibrating_wall", "amplitude", "float", "required", ">= 0", "length", "amplitude of the wall's motion",
     "gran_srd_options.vib_amp", "must be >= 0"},
    {"boundaries.vibrating_wall", "omega", "float", "required", ">= 0", "1/time", "angular frequency",
     "gran_srd_options.vib_omega", "must be >= 0"},

    {"forces", "gravity", "float array (dimension)", "0", "", "length/time^2", "uniform acceleration (summed with body_force)",
     "gran_srd_options.accel", ""},
    {"forces", "body_force", "float array (dimension)", "0", "", "length/time^2", "uniform acceleration (summed with gravity)",
     "gran_srd_options.accel", ""},

    {"observables", "times", "times", "", ">= 0, within the run", "time",
     "output times (list, {linear = ...}, {log = ...}), rounded to the step grid, repeats dropped",
     "gran_scene.srd.out_steps", ""},
    {"observables", "every", "integer", "max(1, steps / 50)", ">= 1", "steps", "output every k steps from step 0 (instead of times)",
     "gran_scene.srd.out_steps", "must be >= 1 (steps between output times)"},
    {"observables", "temperature", "boolean", "true", "", "", "temperature and Haff's law", "gran_scene.srd.obs_temperature", ""},
    {"observables", "energy", "boolean", "true", "", "", "energies", "gran_scene.srd.obs_energy", ""},
    {"observables", "momentum", "boolean", "true", "", "", "total momentum", "gran_scene.srd.obs_momentum", ""},
    {"observables", "clustering", "boolean", "true", "", "", "clustering measures", "gran_scene.srd.obs_clustering", ""},
    {"observables", "sonine_a2", "boolean", "false", "", "", "Sonine coefficient a2", "gran_scene.srd.obs_a2", ""},
    {"observables", "structure_factor", "boolean | table", "false", "periodic boxes only", "", "S(k) in shells",
     "gran_scene.srd.obs_sk", ""},
    {"observables.structure_factor", "bins", "integer", "0", "0..1000000", "", "S(k) shells (0: cells[0] / 2)",
     "gran_scene.srd.sk_bins", "must be in [1, 1e6] (0: cells / 2)"},
    {"observables", "stress", "boolean", "true when sheared", "under shear only", "", "Lees-Edwards stress and viscosity",
     "gran_scene.srd.obs_stress", ""},
    {"observables", "velocity_profile", "boolean", "false", "", "", "mean velocity per layer of y", "gran_scene.srd.obs_profile", ""},
    {"observables", "theory", "boolean", "true", "", "", "Haff's law beside T when it applies", "gran_scene.srd.obs_theory", ""},
    {"observables", "snapshots", "boolean | table", "false", "", "", "field snapshots: true (every output time) or a table",
     "gran_scene.srd.snap_index", ""},
    {"observables.snapshots", "times", "times", "", "within the run", "time", "snapshot times (they join the output times)",
     "gran_scene.srd.snap_index", ""},
    {"observables.snapshots", "every", "integer", "", ">= 1", "output times", "a snapshot every k-th output time",
     "gran_scene.srd.snap_index", "must be >= 1 (output times between snapshots)"},
};
const size_t gran_srd_scene_nkeys_ = sizeof gran_srd_scene_keys_ / sizeof gran_srd_scene_keys_[0];

namespace {

/* an axis: "x" | "y" | "z" or 0 | 1 | 2, below dim */
int srd_axis(Tab &t, const std::string &k, int dim) {
  const toml::value &x = t.get(k);
  int ax = -1;
  if (x.is_string()) {
    const std::string &v = x.as_string().str;
    ax = v == "x" ? 0 : v == "y" ? 1 : v == "z" ? 2 : -2;
    if (ax == -2) t.fail(k, "expected \"x\", \"y\" or \"z\", got \"" + v + "\"");
  } else if (x.is_integer()) {
    ax = (int)std::max<int64_t>(-1, std::min<int64_t>(3, x.as_integer()));
    if (ax < 0 || ax > 2) t.fail(k, "expected 0, 1 or 2 (or \"x\", \"y\", \"z\")");
  } else {
    t.fail(k, std::string("expected an axis (\"x\", \"y\", \"z\"), got ") + Tab::type_name(x));
  }
  if (ax >= dim) t.fail(k, "axis " + std::to_string(ax) + " does not exist in " + std::to_string(dim) + "-D");
  return ax;
}

/* a vector of `dim` numbers */
void srd_vector(Tab &t, const std::string &k, int dim, double out[3]) {
  std::vector<double> v = t.numbers(k);
  if ((int)v.size() != dim)
    t.fail(k, "has " + std::to_string(v.size()) + " entries, expected dimension = " + std::to_string(dim));
  for (int i = 0; i < 3; i++) out[i] = i < dim ? v[(size_t)i] : 0.0;
}

/* the step of time t on the grid of [engine] dt */
int64_t srd_step_of(Tab &tab, const std::string &k, double t, double dt) {
  return gran_scene_io::step_of(tab, k, t, dt, "engine.dt");
}

}  // namespace

/* Before the top-level keys are checked: the DSMC tables, named as such. */
void gran_srd_scene_before_(Tab &top) {
  for (const char *k : {"mixture", "restitution", "initial"})
    if (top.has(k)) top.fail(k, "the [" + std::string(k) + "] table belongs to the DSMC engine; [engine] type = \"srd\" "
                                 "sets its gas in [engine] (dimension, cells, n0, T0, eps, sigma)");
}

namespace {

/* What the tables of one GSRD scene share while they are read; the tables of [boundaries] and
 * [forces] are kept for the derived-value check at the end (it names their keys). */
struct Ctx {
  Ctx(Tab &top_, gran_scene &s_)
      : top(top_), s(s_), en(nullptr, "engine", s_.name, top_.schema()),
        le_t(nullptr, "boundaries.lees_edwards", s_.name, top_.schema()),
        wl_t(nullptr, "boundaries.walls", s_.name, top_.schema()),
        vb_t(nullptr, "boundaries.vibrating_wall", s_.name, top_.schema()),
        fo_t(nullptr, "forces", s_.name, top_.schema()) {}
  Tab &top;
  gran_scene &s;
  Tab en, le_t, wl_t, vb_t, fo_t;
  double N = 0;                  /* particles */
  int64_t steps = -1;            /* steps of the run (-1: from the output times) */
  double gforce = 0, bforce = 0; /* |gravity|, |body_force| */
};

/* [engine]: the gas, the box, the step, the length of the run (the shared keys: the core) */
void parse_engine(Ctx &c) {
  Tab &top = c.top;
  gran_scene &s = c.s;
  gran_srd_options &o = c.s.srd.opt;
  /* ---- [engine] ---- */
  c.en = top.sub("engine");
  Tab &en = c.en;
  en.set_known();
  gran_scene_engine_common_(en, s); /* type, seed, replicas, keep_replicas, max_memory_gb */
  const int64_t dim = en.integer("dimension");
  o.dim = (int32_t)dim;
  o.a = en.real("a");
  if (en.has("cells") && en.has("box")) en.fail("box", "give either 'cells' or 'box', not both");
  if (!en.has("cells") && !en.has("box")) en.fail_missing("cells", "or box = [Lx, Ly(, Lz)] in length units");
  for (int k = 0; k < 3; k++) o.cells[k] = 1;
  if (en.has("cells")) {
    const toml::value &x = en.get("cells");
    std::vector<int64_t> c;
    if (x.is_array()) {
      for (const auto &e : x.as_array()) c.push_back(en.cnt("cells", e));
    } else {
      c.assign((size_t)dim, en.cnt("cells", x));
    }
    if ((int64_t)c.size() != dim)
      en.fail("cells", "has " + std::to_string(c.size()) + " entries, expected dimension = " + std::to_string(dim));
    for (int64_t k = 0; k < dim; k++) {
      require(c[(size_t)k] >= 1 && c[(size_t)k] <= (1 << 20), en, "cells",
              "cells per axis must be in [1, 2^20], got " + std::to_string(c[(size_t)k]));
      o.cells[k] = c[(size_t)k];
    }
  } else {
    const toml::value &x = en.get("box");
    std::vector<double> b;
    if (x.is_array()) {
      for (const auto &e : x.as_array()) b.push_back(en.num("box", e));
    } else {
      b.assign((size_t)dim, en.num("box", x));
    }
    if ((int64_t)b.size() != dim)
      en.fail("box", "has " + std::to_string(b.size()) + " entries, expected dimension = " + std::to_string(dim));
    for (int64_t k = 0; k < dim; k++) {
      const double L = b[(size_t)k] / o.a, r = std::nearbyint(L);
      require(b[(size_t)k] > 0, en, "box", "lengths must be > 0");
      require(std::fabs(L - r) <= 1e-9 * std::max(1.0, L) && r >= 1, en, "box",
              "length " + Tab::num_str(b[(size_t)k]) + " is not a whole number of cells of size a = " + Tab::num_str(o.a) +
                  " (" + Tab::num_str(L) + " cells)");
      require(r <= (double)(1 << 20), en, "box", "more than 2^20 cells per axis");
      o.cells[k] = (int64_t)r;
    }
  }
  double ncell = 1;
  for (int k = 0; k < dim; k++) ncell *= (double)o.cells[k];
  require(ncell * 2.0 < 4294967295.0, en, en.has("cells") ? "cells" : "box",
          Tab::num_str(ncell) + " cells: the engine indexes cells with 32 bits (at most about 2^31 cells)");
  if (en.has("n0") && en.has("particles_per_cell")) en.fail("particles_per_cell", "give either 'n0' or 'particles_per_cell', not both");
  const char *nk = en.has("particles_per_cell") ? "particles_per_cell" : "n0";
  o.n0 = en.real(nk);
  const double N = c.N = std::floor(o.n0 * ncell + 0.5);
  require(N >= 1 && N < 4e9, en, nk, "gives " + Tab::num_str(N) + " particles (need 1 .. 4e9)");
  o.dt = en.real("dt");
  o.alpha_deg = en.real("alpha");
  o.eps = en.real("eps");
  o.sigma = en.real("sigma");
  require(o.eps == 1 || o.sigma > 0, en, "eps", "eps < 1 dissipates only with sigma > 0 (Eq. 2.1): give [engine] sigma");
  o.T0 = en.real("T0");
  o.seed = s.seed;
  o.sort_every = (int32_t)en.integer("sort_every");
  o.threads = (int32_t)en.integer("threads");
  /* thermostat: false / true (= "cell"), "cell" (cell-level Maxwell-Boltzmann) or "global" (one
   * factor on the velocities relative to the cell means: the one for viscosity measurements) */
  if (en.has("thermostat") && en.get("thermostat").is_string()) {
    const std::string th_name = en.string("thermostat", "off");
    if (th_name != "off" && th_name != "cell" && th_name != "global")
      en.fail("thermostat", "expected false, true, \"off\", \"cell\" or \"global\", got \"" + th_name + "\"");
    o.thermostat = th_name == "cell" ? 1 : th_name == "global" ? 2 : 0;
  } else {
    o.thermostat = en.boolean("thermostat", false) ? 1 : 0;
  }
  s.srd.device = en.word("device");
  if (s.srd.device != "cpu" && s.srd.device != "cuda" && s.srd.device != "auto" && s.srd.device != "reference")
    en.fail("device", "expected \"cpu\", \"cuda\", \"auto\" or \"reference\", got \"" + s.srd.device + "\"");
  o.device = s.srd.device == "cuda" ? GRAN_SRD_DEVICE_CUDA
             : s.srd.device == "auto" ? GRAN_SRD_DEVICE_AUTO
             : s.srd.device == "reference" ? GRAN_SRD_DEVICE_REFERENCE
                                          : GRAN_SRD_DEVICE_CPU;
  const std::string prec = en.word("precision");
  if (prec != "double" && prec != "float")
    en.fail("precision", "expected \"double\" or \"float\" (particle storage on a device), got \"" + prec + "\"");
  o.precision = prec == "float" ? 1 : 0;
  const std::string cre = en.word("creation");
  if (cre != "serial" && cre != "cells")
    en.fail("creation", "expected \"serial\" or \"cells\" (how the initial particles are drawn), got \"" + cre + "\"");
  o.creation = cre == "cells" ? GRAN_SRD_CREATE_CELLS : GRAN_SRD_CREATE_SERIAL;
  if (en.has("decomposition")) { /* "none" | "auto" | bricks per axis */
    const toml::value &x = en.get("decomposition");
    if (x.is_string()) {
      const std::string v = x.as_string().str;
      if (v != "none" && v != "auto") en.fail("decomposition", "expected \"none\", \"auto\" or [Px, Py(, Pz)], got \"" + v + "\"");
      s.split_gas = v == "auto";
    } else if (x.is_array()) {
      std::vector<int64_t> g;
      for (const auto &e : x.as_array()) g.push_back(en.cnt("decomposition", e));
      if ((int64_t)g.size() != dim)
        en.fail("decomposition", "has " + std::to_string(g.size()) + " entries, expected dimension = " + std::to_string(dim));
      for (int64_t k = 0; k < dim; k++) {
        require(g[(size_t)k] >= 1 && g[(size_t)k] <= o.cells[k] + 1, en, "decomposition",
                "bricks along axis " + std::to_string(k) + " must be in [1, the cells along it], got " + std::to_string(g[(size_t)k]));
        s.srd.decomp_grid[k] = (int)g[(size_t)k];
      }
      for (int64_t k = dim; k < 3; k++) s.srd.decomp_grid[k] = 1;
      s.split_gas = 1;
    } else {
      en.fail("decomposition", std::string("expected \"none\", \"auto\" or an array of bricks per axis, got ") + Tab::type_name(x));
    }
    if (s.split_gas && o.creation != GRAN_SRD_CREATE_CELLS)
      en.fail("decomposition", "a split gas is the decomposable engine's: give [engine] creation = \"cells\"");
    if (s.split_gas && s.srd.device != "cpu")
      en.fail("decomposition", "a split gas steps on the CPU, and [engine] device = \"" + s.srd.device + "\"");
  }
  if (en.has("steps") && en.has("t_end")) en.fail("t_end", "give either 'steps' or 't_end', not both");
  int64_t &steps = c.steps;
  if (en.has("steps")) {
    steps = en.count_value("steps");
  } else if (en.has("t_end")) {
    const double te = en.value("t_end");
    steps = srd_step_of(en, "t_end", te, o.dt);
    require(steps >= 1 && std::fabs((double)steps * o.dt - te) <= 1e-9 * te, en, "t_end",
            "t_end = " + Tab::num_str(te) + " is not a whole number of steps dt = " + Tab::num_str(o.dt));
  }
  if (steps > 0)
    require_run_steps(en, en.has("steps") ? "steps" : "t_end", (double)steps, N,
                      std::to_string(steps) + " steps of " + Tab::num_str(N) + " particles");
  en.finish();
}

/* [boundaries]: Lees-Edwards shear, walls, a vibrating wall */
void parse_boundaries(Ctx &c) {
  Tab &top = c.top;
  gran_srd_options &o = c.s.srd.opt;
  Tab &le_t = c.le_t;
  Tab &wl_t = c.wl_t;
  Tab &vb_t = c.vb_t;
  /* ---- [boundaries] ---- (the tables are kept for the derived-value check at the end) */
  if (top.has("boundaries")) {
    Tab bd = top.sub("boundaries");
    bd.set_known();
    if (bd.has("lees_edwards")) {
      Tab le = bd.sub("lees_edwards");
      le_t = le;
      le.set_known();
      if (!le.has("shear_rate")) le.fail_missing("shear_rate");
      o.shear_rate = le.number("shear_rate");
      le.finish();
      require(o.shear_rate != 0, le, "shear_rate", "must not be 0 (leave lees_edwards out for no shear)");
    }
    if (bd.has("walls")) {
      Tab w = bd.sub("walls");
      wl_t = w;
      w.set_known();
      if (!w.has("axis")) w.fail_missing("axis", "\"x\", \"y\" or \"z\"");
      o.wall_axis = srd_axis(w, "axis", o.dim);
      const std::string rule = w.word("rule");
      if (rule == "no-slip") o.wall_rule = 1;
      else if (rule == "slip") o.wall_rule = 2;
      else w.fail("rule", "expected \"no-slip\" (bounce-back) or \"slip\" (specular), got \"" + rule + "\"");
      o.wall_T = w.real("T");
      if (o.shear_rate != 0 && o.wall_axis <= 1)
        w.fail("axis", "walls and Lees-Edwards shear on the same axis (the shear's flow is x, its gradient y)");
      w.finish();
    }
    if (bd.has("vibrating_wall")) {
      Tab v = bd.sub("vibrating_wall");
      vb_t = v;
      v.set_known();
      if (!v.has("amplitude")) v.fail_missing("amplitude");
      if (!v.has("omega")) v.fail_missing("omega");
      o.vib_amp = v.value("amplitude");
      o.vib_omega = v.value("omega");
      if (o.wall_axis < 0) bd.fail("vibrating_wall", "needs walls (the lower wall of [boundaries] walls vibrates)");
      v.finish();
    }
    bd.finish();
  }
}

/* [forces]: uniform accelerations */
void parse_forces(Ctx &c) {
  Tab &top = c.top;
  gran_srd_options &o = c.s.srd.opt;
  Tab &fo_t = c.fo_t;
  double &gforce = c.gforce;
  double &bforce = c.bforce;
  /* ---- [forces] ---- */
  if (top.has("forces")) {
    Tab fo = top.sub("forces");
    fo_t = fo;
    fo.set_known();
    double g[3] = {0, 0, 0}, f[3] = {0, 0, 0};
    if (fo.has("gravity")) srd_vector(fo, "gravity", o.dim, g);
    if (fo.has("body_force")) srd_vector(fo, "body_force", o.dim, f);
    for (int k = 0; k < 3; k++) o.accel[k] = g[k] + f[k];
    gforce = std::hypot(std::hypot(g[0], g[1]), g[2]);
    bforce = std::hypot(std::hypot(f[0], f[1]), f[2]);
    fo.finish();
  }
}

/* [observables]: output steps, what is recorded, snapshots */
void parse_observables(Ctx &c) {
  Tab &top = c.top;
  gran_scene &s = c.s;
  gran_srd_options &o = c.s.srd.opt;
  Tab &en = c.en;
  int64_t &steps = c.steps;
  const double N = c.N;
  /* ---- [observables] ---- */
  Tab ob = top.sub_or_empty("observables");
  if (ob.has("theory_sonine"))
    ob.fail("theory_sonine", "the first Sonine theory is written by DSMC scenes only, not by GSRD scenes");
  if (ob.has("sonine_order"))
    ob.fail("sonine_order", "the Sonine theory is written by DSMC scenes only, not by GSRD scenes");
  ob.set_known();
  if (ob.has("times") && ob.has("every")) ob.fail("every", "give either 'times' or 'every', not both");
  std::vector<int64_t> os;
  if (ob.has("times")) {
    std::vector<double> t = parse_times(ob, "times");
    if (t.front() < 0) ob.fail("times", "output times must be >= 0");
    for (double x : t) {
      const int64_t k = srd_step_of(ob, "times", x, o.dt);
      if (os.empty() || k > os.back()) os.push_back(k); /* rounded to the step grid; repeats dropped */
    }
    if (steps < 0) steps = std::max<int64_t>(1, os.back());
    if (os.back() > steps)
      ob.fail("times", "last output time " + Tab::num_str(t.back()) + " is after the end of the run (" +
                           std::to_string(steps) + " steps of dt = " + Tab::num_str(o.dt) + ")");
  } else {
    if (steps < 0) en.fail_missing("steps", "or t_end, or [observables] times");
    const int64_t every = ob.integer("every", std::max<int64_t>(1, steps / 50));
    require(steps / every <= 100000000, ob, "every", "gives more than 1e8 output times");
    for (int64_t k = 0; k <= steps; k += every) os.push_back(k);
  }
  if (!en.has("steps") && !en.has("t_end")) /* the length from the last output time */
    require_run_steps(ob, "times", (double)steps, N, std::to_string(steps) + " steps of " + Tab::num_str(N) + " particles");
  s.srd.steps = steps;
  s.srd.out_steps = os;
  s.srd.obs_temperature = ob.flag("temperature");
  s.srd.obs_energy = ob.flag("energy");
  s.srd.obs_momentum = ob.flag("momentum");
  s.srd.obs_clustering = ob.flag("clustering");
  s.srd.obs_a2 = ob.flag("sonine_a2");
  s.srd.obs_profile = ob.flag("velocity_profile");
  s.srd.obs_theory = ob.flag("theory");
  s.srd.obs_stress = ob.boolean("stress", o.shear_rate != 0);
  if (s.srd.obs_stress && o.shear_rate == 0) ob.fail("stress", "the stress is measured under Lees-Edwards shear only ([boundaries] lees_edwards)");
  if (s.srd.obs_profile && o.dim < 2) ob.fail("velocity_profile", "needs dimension >= 2");
  if (ob.has("structure_factor") && ob.get("structure_factor").is_table()) {
    Tab sk = ob.sub("structure_factor");
    sk.set_known();
    s.srd.obs_sk = 1;
    s.srd.sk_bins = sk.integer("bins");
    sk.finish();
  } else {
    s.srd.obs_sk = ob.flag("structure_factor");
  }
  if (s.srd.obs_sk && s.srd.sk_bins == 0) s.srd.sk_bins = std::max<int64_t>(1, o.cells[0] / 2);
  if (s.srd.obs_sk && o.wall_axis >= 0) ob.fail("structure_factor", "S(k) needs a periodic box (no [boundaries] walls)");
  if (ob.has("snapshots")) {
    const int64_t nt = (int64_t)os.size();
    const toml::value &x = ob.get("snapshots");
    if (x.is_boolean()) {
      if (x.as_boolean())
        for (int64_t i = 0; i < nt; i++) s.srd.snap_index.push_back(i);
    } else if (x.is_table()) {
      Tab sn = ob.sub("snapshots");
      sn.set_known();
      if (sn.has("times") == sn.has("every")) sn.fail(sn.has("times") ? "every" : "times", "give either 'times' or 'every' (output times between snapshots)");
      if (sn.has("every")) {
        const int64_t e = sn.count_value("every");
        for (int64_t i = 0; i < nt; i += e) s.srd.snap_index.push_back(i);
      } else {
        /* snapshot times (rounded to the step grid) join the output times */
        std::vector<int64_t> ks;
        for (double t : parse_times(sn, "times")) {
          const int64_t k = srd_step_of(sn, "times", t, o.dt);
          if (t < 0 || k > steps)
            sn.fail("times", "snapshot time " + Tab::num_str(t) + " is outside the run (0 .. " +
                                 Tab::num_str((double)steps * o.dt) + ")");
          ks.push_back(k);
        }
        std::vector<int64_t> merged(os.size() + ks.size());
        std::merge(os.begin(), os.end(), ks.begin(), ks.end(), merged.begin());
        merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
        os.swap(merged);
        for (int64_t k : ks) {
          const int64_t i = std::lower_bound(os.begin(), os.end(), k) - os.begin();
          if (s.srd.snap_index.empty() || i > s.srd.snap_index.back()) s.srd.snap_index.push_back(i);
        }
      }
      sn.finish();
    } else {
      ob.fail("snapshots", std::string("expected true, false or a table {times = [...]} / {every = k}, got ") + Tab::type_name(x));
    }
  }
  ob.finish();
  s.srd.out_steps = os;
  const int64_t nt = (int64_t)os.size();
  s.times.resize((size_t)nt);
  for (int64_t i = 0; i < nt; i++) s.times[(size_t)i] = (double)os[(size_t)i] * o.dt;
  s.t_start = 0.0;
  s.t_end = (double)steps * o.dt;
}

/* What the run derives from its inputs, named by the scene key */
void check_limits(Ctx &c) {
  gran_scene &s = c.s;
  gran_srd_options &o = c.s.srd.opt;
  Tab &en = c.en;
  Tab &le_t = c.le_t;
  Tab &wl_t = c.wl_t;
  Tab &vb_t = c.vb_t;
  Tab &fo_t = c.fo_t;
  double &gforce = c.gforce;
  double &bforce = c.bforce;
  /* ---- what the run derives from its inputs (src/srd/srd_limits.h, the bounds gran_srd_create
   * checks too, here with the run's length): named by the scene key ---- */
  {
    srd_limit_fail lf;
    if (!srd_check_limits(o, s.t_end, &lf)) {
      const std::string k = lf.key;
      if (k == "a") en.fail(en.has("a") ? "a" : en.has("box") ? "box" : "cells", lf.why);
      if (k == "wall_T") wl_t.fail("T", lf.why);
      if (k == "shear_rate") le_t.fail("shear_rate", lf.why);
      if (k == "vib_amp") vb_t.fail("amplitude", lf.why);
      if (k == "vib_omega") vb_t.fail("omega", lf.why);
      if (k == "accel") fo_t.fail(fo_t.has("gravity") && (!fo_t.has("body_force") || gforce >= bforce) ? "gravity" : "body_force", lf.why);
      en.fail(k, lf.why); /* T0, dt, sigma */
    }
  }
}

}  // namespace

/* The GSRD tables: [engine], [boundaries], [forces], [observables] (the core reads the title, the
 * shared [engine] keys, [output] and the memory check). Every check names the key and its line;
 * what gran_srd_create would refuse is refused here. */
void gran_srd_scene_parse_(const gran_scene_doc &doc, gran_scene &s) {
  gran_srd_options_default(&s.srd.opt);
  s.nspecies = 0;
  s.obs_temperatures = s.obs_msd = s.obs_energy = s.obs_theory = 0;
  Ctx c(*doc.top, s);
  parse_engine(c);
  parse_boundaries(c);
  parse_forces(c);
  parse_observables(c);
  check_limits(c);
}

