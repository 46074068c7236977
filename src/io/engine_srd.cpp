/* engine_srd.cpp - the GSRD engine (src/srd) behind the run driver's engine interface (engine.h):
 * `[engine] type = "srd"` scenes (parsed by src/srd/scene_srd.cpp into gran_scene::srd).
 *
 * Time: the engine advances in whole steps; the scene's output times are already on the step
 * grid (times[i] = out_steps[i] dt). Observables at each output time come from gran_srd_observe
 * (which also turns eps_eff clamps of the interval into a warning with dt_max), S(k) from
 * gran_srd_structure_factor, cell fields from gran_srd_fields. The Lees-Edwards stress is the
 * average over the interval since the previous output time (gran_srd_stress_reset after each
 * record; the fill value for a zero-length interval). Field snapshots are held by replica 0 only (the
 * replica whose seed is the scene's, or whose checkpoint group is /engine), written into the
 * output under /fields with an XDMF sidecar (OUTPUT.xmf) that ParaView opens, and kept in the
 * checkpoint so that a resumed run writes the same file.
 * Checkpoint: the engine's state group (gran_srd_checkpoint_write_h5_, src/srd/checkpoint.cpp:
 * options, counters, ledger, particles, every RNG state as named fields), every stored physics
 * option compared with the scene's on resume; the adapter adds the stress window's start and the
 * snapshots to the same group. */
#include <hdf5.h>

#include <dirent.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "io/engine.h"
#include "srd/bricks.h"
#include "srd/fields.h"
#include "srd/srd_theory.h"

namespace {

struct H5Obj {
  hid_t id = -1;
  herr_t (*close)(hid_t) = nullptr;
  H5Obj(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~H5Obj() {
    if (id >= 0 && close) close(id);
  }
};

/* One field snapshot (replica 0). */
struct Snap {
  int64_t index = 0; /* output index */
  std::vector<double> count, vel, temp;
};


/* OUTPUT.h5 -> OUTPUT.xmf (any other name: NAME.xmf) */
std::string xmf_path(const std::string &h5) {
  const size_t n = h5.size();
  if (n > 3 && h5.compare(n - 3, 3, ".h5") == 0) return h5.substr(0, n - 3) + ".xmf";
  return h5 + ".xmf";
}

std::string base_name(const std::string &p) {
  const size_t s = p.find_last_of('/');
  return s == std::string::npos ? p : p.substr(s + 1);
}

/* XML attribute text: & < > " escaped */
std::string xml_escape(const std::string &s) {
  std::string o;
  for (char c : s) {
    if (c == '&') o += "&amp;";
    else if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '"') o += "&quot;";
    else o += c;
  }
  return o;
}

class SrdEngine : public gran_engine {
 public:
  explicit SrdEngine(const gran_scene *s) : s_(s), o_(s->srd.opt) {}
  ~SrdEngine() override {
    gran_srd_destroy(&srd_);
    srd_bricks_close_(&bst_);
  }
  const char *type() const override { return "srd"; }

  /* the device is gran_srd_create's: "cuda" without a GPU fails there (GRAN_ERR_UNSUPPORTED, naming
   * why), "auto" falls back to the CPU engine with a warning.
   * A split gas ([engine] decomposition, split_gas) over the run's P > 1 processes: this process
   * holds one brick (srd_bricks_open_ over srd_bricks_run_comm_), every call but write_output is
   * collective and every process records the same rows (the observables and S(k) are all-reduced);
   * in one process the undivided decomposable engine is the same gas bit for bit. */
  int prepare() {
    cells_ = 1;
    for (int k = 0; k < o_.dim; ++k) cells_ *= o_.cells[k];
    N_ = (int64_t)std::floor(o_.n0 * (double)cells_ + 0.5);
    const auto &q = s_->srd;
    if (s_->split_gas) {
      const srd_bricks_comm *c = srd_bricks_run_comm_();
      const int64_t nb = (int64_t)q.decomp_grid[0] * q.decomp_grid[1] * q.decomp_grid[2];
      GRAN_CHECK(nb == 0 || nb == c->size, GRAN_ERR_ARG,
                 "scene key 'engine.decomposition' = [%d, %d, %d] has %lld bricks, and this run has %d process(es)%s: "
                 "start it on %lld (mpirun -n %lld build/granary-mpi run ...), or give \"auto\"",
                 q.decomp_grid[0], q.decomp_grid[1], q.decomp_grid[2], (long long)nb, c->size,
                 s_->replicas > 1 ? " per replica" : "", (long long)(nb * s_->replicas), (long long)(nb * s_->replicas));
      if (c->size > 1) {
        split_ = true;
        comm_ = *c;
        /* what a split gas cannot give yet: each refusal names its key */
        GRAN_CHECK(!q.obs_profile || o_.cells[1] <= SRD_BRICKS_PROFILE_MAX_LAYERS, GRAN_ERR_UNSUPPORTED,
                   "scene key 'observables.velocity_profile': the velocity profile of a gas split over processes has at "
                   "most %d layers of y, and the box has %lld", SRD_BRICKS_PROFILE_MAX_LAYERS, (long long)o_.cells[1]);
        GRAN_CHECK(!q.obs_sk || q.sk_bins <= SRD_BRICKS_SK_MAX_BINS, GRAN_ERR_ARG,
                   "scene key 'observables.structure_factor.bins' = %lld: a split gas's S(k) has at most %d shells",
                   (long long)q.sk_bins, SRD_BRICKS_SK_MAX_BINS);
        GRAN_CHECK(!q.obs_sk || comm_.fft_r2c, GRAN_ERR_UNSUPPORTED,
                   "scene key 'observables.structure_factor': S(k) of a gas split over %d processes needs FFTW's MPI "
                   "interface, and this build/granary-mpi has none (install Debian libfftw3-mpi-dev, then make)", c->size);
        if (nb == 0) GRAN_CALL(srd_bricks_auto_(&o_, c->size, pgrid_));
        else for (int k = 0; k < 3; ++k) pgrid_[k] = q.decomp_grid[k];
        for (int k = 0; k < 3; ++k) { /* the split fits the grid: refused before any process opens its brick */
          const int64_t nc = k < o_.dim ? o_.cells[k] + (k == o_.wall_axis ? 1 : 0) : 1;
          GRAN_CHECK(pgrid_[k] >= 1 && pgrid_[k] <= nc, GRAN_ERR_ARG,
                     "scene key 'engine.decomposition': %d bricks along axis %d, which has %lld cells to split", pgrid_[k],
                     k, (long long)nc);
        }
      }
    }
    return GRAN_SUCCESS;
  }

  int declare(std::vector<gran_row_buf> &b) override {
    const auto &q = s_->srd;
    gran_row_buf_add(b, "stats", "steps", 1, {}, "1", "collision steps done");
    if (q.obs_temperature) {
      gran_row_buf_add(b, "temperature", "T", 0, {}, "energy",
                       "global temperature sum |v - <v>|^2 / (d N), the mean velocity of the whole gas removed");
      gran_row_buf_add(b, "temperature", "theta_cells", 0, {}, "energy",
                       "mean thermal temperature of the unshifted cells, sum over cells of sum |v - V_cell|^2 / (d N)");
    }
    if (q.obs_energy) {
      gran_row_buf_add(b, "energy", "e_kin", 0, {}, "energy", "total kinetic energy sum |v|^2 / 2 (mass 1)");
      gran_row_buf_add(b, "energy", "e_initial", 0, {}, "energy", "total kinetic energy at the start");
      gran_row_buf_add(b, "energy", "e_collisions", 0, {}, "energy",
                       "energy change in collisions so far (< 0: dissipated; thermostat and virtual particles add)");
      gran_row_buf_add(b, "energy", "e_external", 0, {}, "energy",
                       "work done by walls, the Lees-Edwards boundary and forces so far");
      gran_row_buf_add(b, "energy", "ledger_error", 0, {}, "1",
                       "(e_initial + e_collisions + e_external - e_kin - potential) / e_initial");
    }
    if (o_.eps < 1.0) {
      gran_row_buf_add(b, "clamps", "count", 1, {}, "1",
                       "cell collisions whose eps_eff (Eq. 2.1) was clamped to [0, 1] since the previous output time");
      gran_row_buf_add(b, "clamps", "dt_max", 0, {}, "time",
                       "largest dt that would have avoided those clamps");
    }
    if (q.obs_momentum)
      gran_row_buf_add(b, "momentum", "p", 0, {3}, "mass*length/time", "total momentum (x, y, z) of the gas");
    if (q.obs_clustering) {
      gran_row_buf_add(b, "clustering", "E_kin", 0, {}, "energy",
                       "convective kinetic energy per particle, Eq. 3.1: (1/N) sum_cells n_c |V_c|^2 (unshifted cells)");
      gran_row_buf_add(b, "clustering", "mach", 0, {}, "1", "global Mach number sqrt(E_kin / theta_cells)");
      gran_row_buf_add(b, "clustering", "sigma_rho", 0, {}, "1/length^d",
                       "standard deviation of the cell number density over the unshifted cells");
    }
    if (q.obs_a2)
      gran_row_buf_add(b, "sonine_a2", "a2", 0, {}, "1",
                       "Sonine coefficient a2 = (d/(d+2)) <c^4>/<c^2>^2 - 1 of the thermal velocities u = v - V_cell (cells with n >= 2), corrected for the cell-mean subtraction: 0 for a Maxwellian at any n0");
    if (q.obs_sk)
      gran_row_buf_add(b, "structure_factor", "S", 0, {q.sk_bins}, "1",
                       "density structure factor S(k) of the unshifted cell counts, radially averaged, k = 0 removed [time][shell]");
    if (q.obs_stress) {
      gran_row_buf_add(b, "stress", "xy", 0, {}, "mass/(length^(d-2) time^2)",
                       "Lees-Edwards shear stress (kinetic + collisional) averaged over the interval since the previous output "
                       "time");
      gran_row_buf_add(b, "stress", "kinetic", 0, {}, "mass/(length^(d-2) time^2)",
                       "its kinetic (plane-crossing) part, same interval");
      gran_row_buf_add(b, "stress", "eta", 0, {}, "mass/(length^(d-2) time)", "shear viscosity stress_xy / shear_rate");
    }
    if (q.obs_profile)
      gran_row_buf_add(b, "velocity_profile", "u", 0, {o_.cells[1], 3}, "length/time",
                       "mean velocity of the particles in each layer of cells along y [time][layer][component]");
    /* the values that may not exist (NaN in record; the driver writes the fill value) */
    gran_row_buf_allow_fill(b, "clamps", "dt_max", "no clamp in the interval");
    gran_row_buf_allow_fill(b, "energy", "ledger_error", "e_initial = 0");
    gran_row_buf_allow_fill(b, "structure_factor", "S", "a shell without modes");
    gran_row_buf_allow_fill(b, "stress", "xy", "an empty interval");
    gran_row_buf_allow_fill(b, "stress", "kinetic", "an empty interval");
    gran_row_buf_allow_fill(b, "stress", "eta", "an empty interval, or shear_rate = 0");
    gran_row_buf_allow_fill(b, "velocity_profile", "u", "a layer without particles");
    return GRAN_SUCCESS;
  }

  /* one engine of this scene: the memory model the scene check uses too (src/srd/memory.cpp) */
  int memory(int64_t *bytes) override {
    std::vector<gran_mem_part> parts;
    double b = gran_srd_memory_(*s_, parts);
    if (split_) { /* this process's brick, its S(k) slab (48 B per cell), the recorded rows; the group's
                     first process the snapshots and the gather of their fields (48 B per cell) */
      b = srd_bricks_memory_(&o_, comm_.size, 0) + (s_->srd.obs_sk ? 48.0 * (double)cells_ / comm_.size : 0.0);
      for (const gran_mem_part &p : parts)
        if (std::string(p.what) == "recorded rows" || (comm_.rank == 0 && std::string(p.what) == "snapshots")) b += p.engine;
      if (comm_.rank == 0 && !s_->srd.snap_index.empty()) b += 48.0 * (double)cells_;
    }
    *bytes = b < 9e18 ? (int64_t)b : INT64_MAX;
    return GRAN_SUCCESS;
  }

  int start(uint64_t seed) override {
    gran_srd_destroy(&srd_);
    srd_bricks_close_(&bst_);
    gran_srd_options o = o_;
    o.seed = seed;
    rep0_ = seed == s_->seed;
    snaps_.clear();
    if (split_) return collective(srd_bricks_open_(&o, pgrid_, &comm_, &bst_));
    return gran_srd_create(&o, &srd_);
  }

  int advance(double t) override {
    GRAN_CHECK(srd_ != nullptr || bst_ != nullptr, GRAN_ERR_STATE, "GSRD engine: advance before start");
    const int64_t target = (int64_t)std::llround(t / o_.dt), now = steps_done();
    GRAN_CHECK(target >= now, GRAN_ERR_ARG, "GSRD engine: time %g is before the current step %lld", t, (long long)now);
    if (target == now) return GRAN_SUCCESS;
    return split_ ? collective(srd_bricks_step_(bst_, target - now)) : gran_srd_advance(srd_, target - now);
  }

  /* events: particle collision updates (steps x N) */
  int state(gran_engine_state *st) override {
    GRAN_CHECK(srd_ != nullptr || bst_ != nullptr, GRAN_ERR_STATE, "GSRD engine: state before start");
    const int64_t k = steps_done();
    st->time = (double)k * o_.dt;
    st->events = N_ > 0 && k > INT64_MAX / N_ ? INT64_MAX : k * N_;
    st->temperature = last_T_;
    st->work_unit = GRAN_WORK_PARTICLE_STEPS;
    return GRAN_SUCCESS;
  }

  /* the cost of a step does not depend on time: work is the time span */
  int work(int64_t n, const double *t, double *w) override {
    for (int64_t i = 0; i < n; ++i) w[i] = std::max(0.0, t[i]);
    return GRAN_SUCCESS;
  }

  int record(std::vector<gran_row_buf> &bufs, int64_t i) override {
    GRAN_CHECK(srd_ != nullptr || bst_ != nullptr, GRAN_ERR_STATE, "GSRD engine: record before start");
    const auto &q = s_->srd;
    gran_srd_obs ob;
    /* the decomposable engine (creation by cells, CPU) and a split gas give the velocity profile
     * with their observables (exact layer sums, the same bits for any split); the serial engine
     * and the devices from the cell fields */
    std::vector<double> prof;
    int32_t dev = GRAN_SRD_DEVICE_CPU;
    if (srd_) GRAN_CALL(gran_srd_get_device(srd_, &dev));
    const bool cells_obs = split_ || (o_.creation == GRAN_SRD_CREATE_CELLS && dev == GRAN_SRD_DEVICE_CPU);
    if (q.obs_profile && cells_obs) prof.resize((size_t)(3 * o_.cells[1]));
    double *pp = prof.empty() ? nullptr : prof.data();
    if (split_) GRAN_CALL(collective(srd_bricks_observe_profile_(bst_, &ob, pp)));
    else if (cells_obs) GRAN_CALL(srd_cells_observe_(srd_, &ob, pp));
    else GRAN_CALL(gran_srd_observe(srd_, &ob));
    last_T_ = ob.temperature;
    std::vector<double> sk_k, sk_s;
    std::vector<int64_t> sk_c;
    if (q.obs_sk) {
      sk_k.resize((size_t)q.sk_bins);
      sk_s.resize((size_t)q.sk_bins);
      sk_c.resize((size_t)q.sk_bins);
      if (split_) GRAN_CALL(collective(srd_bricks_structure_factor_(bst_, q.sk_bins, sk_k.data(), sk_s.data(), sk_c.data())));
      else GRAN_CALL(gran_srd_structure_factor(srd_, q.sk_bins, sk_k.data(), sk_s.data(), sk_c.data()));
      sk_k_ = sk_k; /* the shells' geometry, for write_output (k and modes do not depend on the state) */
      sk_c_ = sk_c;
      for (int64_t b = 0; b < q.sk_bins; ++b)
        if (sk_c[(size_t)b] == 0) sk_s[(size_t)b] = NAN;
    }
    std::vector<double> cnt, vel, tmp;
    const bool snap = rep0_ && std::binary_search(q.snap_index.begin(), q.snap_index.end(), i);
    if (snap && split_) { /* collective: the fields gathered on the group's first process, which keeps them */
      const bool keep = comm_.rank == 0;
      if (keep) {
        cnt.resize((size_t)cells_);
        vel.resize((size_t)cells_ * 3);
        tmp.resize((size_t)cells_);
      }
      GRAN_CALL(collective(srd_bricks_fields_(bst_, keep ? cnt.data() : nullptr, keep ? vel.data() : nullptr,
                                              keep ? tmp.data() : nullptr)));
    } else if (snap || (q.obs_profile && !pp)) {
      cnt.resize((size_t)cells_);
      vel.resize((size_t)cells_ * 3);
      if (snap) tmp.resize((size_t)cells_);
      GRAN_CALL(gran_srd_fields(srd_, cnt.data(), vel.data(), snap ? tmp.data() : nullptr));
    }
    const double span = ob.time - stress_t0_;
    for (auto &b : bufs) {
      double *d = b.is_int ? nullptr : b.d.data() + i * b.row;
      int64_t *n = b.is_int ? b.n.data() + i * b.row : nullptr;
      const std::string &g = b.group, &nm = b.name;
      if (g == "stats") n[0] = ob.steps;
      else if (g == "temperature") d[0] = nm == "T" ? ob.temperature : ob.theta_cells;
      else if (g == "energy") {
        d[0] = nm == "e_kin" ? ob.energy : nm == "e_initial" ? ob.e_initial : nm == "e_collisions" ? ob.e_collisions
             : nm == "e_external" ? ob.e_external : ob.e_initial != 0 ? ob.ledger_error : NAN;
      } else if (g == "clamps") {
        if (b.is_int) n[0] = ob.clamped;
        else d[0] = ob.clamped > 0 ? ob.dt_max : NAN; /* no clamp: no bound on dt */
      } else if (g == "momentum") {
        for (int k = 0; k < 3; ++k) d[k] = ob.momentum[k];
      } else if (g == "clustering") {
        d[0] = nm == "E_kin" ? ob.e_kin : nm == "mach" ? ob.mach : ob.sigma_rho;
      } else if (g == "sonine_a2") {
        d[0] = ob.a2;
      } else if (g == "structure_factor") {
        std::copy(sk_s.begin(), sk_s.end(), d);
      } else if (g == "stress") {
        const double v = nm == "xy" ? ob.stress_xy : nm == "kinetic" ? ob.stress_kin
                       : o_.shear_rate != 0 ? ob.stress_xy / o_.shear_rate : NAN;
        d[0] = span > 0 ? v : NAN;
      } else if (g == "velocity_profile") {
        if (pp) std::copy(prof.begin(), prof.end(), d);
        else profile(cnt, vel, d);
      }
    }
    if (q.obs_stress) {
      if (split_) GRAN_CALL(srd_bricks_stress_reset_(bst_));
      else GRAN_CALL(gran_srd_stress_reset(srd_));
      stress_t0_ = ob.time;
    }
    if (snap && (!split_ || comm_.rank == 0)) {
      Snap sn;
      sn.index = i;
      sn.count = std::move(cnt);
      sn.vel = std::move(vel);
      sn.temp = std::move(tmp);
      snaps_.push_back(std::move(sn));
    }
    return GRAN_SUCCESS;
  }

  int write_output(int64_t f, const char *file, int64_t nrec) override {
    const auto &q = s_->srd;
    GRAN_CALL(gran_h5::attr_int64(f, "dimension", o_.dim, file));
    GRAN_CALL(gran_write_unit_system_(f, file, "GSRD", 1.0, o_.a, o_.T0)); /* docs/units.md */
    {
      H5Obj g(-1, H5Gclose);
      GRAN_CALL(gran_h5::make_group(f, "srd", &g.id, file));
      std::vector<int64_t> cells = {o_.cells[0], o_.cells[1], o_.dim == 3 ? o_.cells[2] : 1};
      GRAN_CALL(gran_h5::write_int64(g.id, "cells", {3}, cells.data(), file));
      GRAN_CALL(gran_describe_(g.id, "cells", "1", "cells per axis (x, y, z; 1 on an unused axis)", file));
      GRAN_CALL(gran_h5::attr_double(g.id, "a", o_.a, file));
      GRAN_CALL(gran_h5::attr_double(g.id, "n0", o_.n0, file));
      GRAN_CALL(gran_h5::attr_int64(g.id, "N", N_, file));
      GRAN_CALL(gran_h5::attr_double(g.id, "dt", o_.dt, file));
      GRAN_CALL(gran_h5::attr_double(g.id, "alpha_deg", o_.alpha_deg, file));
      GRAN_CALL(gran_h5::attr_double(g.id, "eps", o_.eps, file));
      GRAN_CALL(gran_h5::attr_double(g.id, "sigma", o_.sigma, file));
      GRAN_CALL(gran_h5::attr_double(g.id, "T0", o_.T0, file));
      GRAN_CALL(gran_h5::attr_double(g.id, "shear_rate", o_.shear_rate, file));
      GRAN_CALL(gran_h5::attr_int64(g.id, "wall_axis", o_.wall_axis, file));
      GRAN_CALL(gran_h5::attr_int64(g.id, "steps", q.steps, file));
      int32_t dev = GRAN_SRD_DEVICE_CPU; /* a split gas: the CPU */
      if (srd_) GRAN_CALL(gran_srd_get_device(srd_, &dev));
      GRAN_CALL(gran_h5::attr_string(g.id, "device",
                                     dev == GRAN_SRD_DEVICE_CUDA ? "cuda" : dev == GRAN_SRD_DEVICE_REFERENCE ? "reference" : "cpu",
                                     file));
      { /* where the gas ran: one process, or split into bricks over processes ([engine] decomposition) */
        char dec[160];
        if (split_)
          std::snprintf(dec, sizeof dec, "%d x %d x %d bricks over %d processes", pgrid_[0], pgrid_[1], pgrid_[2], comm_.size);
        else
          std::snprintf(dec, sizeof dec, "one process");
        GRAN_CALL(gran_h5::attr_string(g.id, "decomposition", dec, file));
      }
      std::vector<double> acc = {o_.accel[0], o_.accel[1], o_.accel[2]};
      GRAN_CALL(gran_h5::write_double(g.id, "accel", {3}, acc.data(), file));
      GRAN_CALL(gran_describe_(g.id, "accel", "length/time^2", "uniform acceleration: gravity + body force per mass", file));
    }
    if (q.obs_sk) {
      H5Obj g(H5Gopen2((hid_t)f, "structure_factor", H5P_DEFAULT), H5Gclose);
      std::vector<double> k((size_t)q.sk_bins), sk((size_t)q.sk_bins);
      std::vector<int64_t> c((size_t)q.sk_bins);
      /* k and counts: geometry only, as the last record had them (a split gas's write_output is not
       * collective); without a record in this process (none since a resume) the undivided engine's */
      if (sk_k_.size() != (size_t)q.sk_bins) {
        GRAN_CHECK(!split_, GRAN_ERR_STATE, "GSRD engine: S(k) written before it was recorded");
        sk_k_.resize((size_t)q.sk_bins);
        sk_c_.resize((size_t)q.sk_bins);
        GRAN_CALL(gran_srd_structure_factor(srd_, q.sk_bins, sk_k_.data(), sk.data(), sk_c_.data()));
      }
      k = sk_k_;
      c = sk_c_;
      for (int64_t b = 0; b < q.sk_bins; ++b)
        if (c[(size_t)b] == 0) k[(size_t)b] = gran_row_fill;
      GRAN_CALL(gran_h5::write_double(g.id, "k", {q.sk_bins}, k.data(), file));
      GRAN_CALL(gran_describe_(g.id, "k", "1/length", "mean |k| of the modes in each shell; _FillValue (a shell without modes)", file));
      {
        H5Obj d(H5Dopen2(g.id, "k", H5P_DEFAULT), H5Dclose);
        GRAN_CALL(gran_h5::attr_double(d.id, "_FillValue", gran_row_fill, file));
      }
      GRAN_CALL(gran_h5::write_int64(g.id, "modes", {q.sk_bins}, c.data(), file));
      GRAN_CALL(gran_describe_(g.id, "modes", "1", "modes in each shell", file));
    }
    if (q.obs_temperature && haff_applies() && q.obs_theory) {
      H5Obj g(H5Gopen2((hid_t)f, "temperature", H5P_DEFAULT), H5Gclose);
      std::vector<double> th((size_t)nrec);
      const double rate = haff_rate();
      for (int64_t i = 0; i < nrec; ++i) th[(size_t)i] = gran_srd_haff_T_(&o_, 1.0, s_->times[(size_t)i]);
      GRAN_CALL(gran_h5::write_double(g.id, "T_theory", {nrec}, th.data(), file));
      GRAN_CALL(gran_describe_(g.id, "T_theory", "energy",
                               "Haff's law T0 / (1 + t / tau)^2 with the mean-field rate of Eq. 2.1: 1/tau = k (1 - eps^2) "
                               "sigma^2 (n0 / a^d) sqrt(T0), k = 1 in 2-D, 2/3 in 3-D (only the components perpendicular "
                               "to the axis are scaled)", file));
      GRAN_CALL(gran_attach_scales_(g.id, "T_theory", {"time"}, file));
      if (std::isfinite(rate)) GRAN_CALL(gran_h5::attr_double(g.id, "haff_rate", rate, file));
      else gran_warning_add("GSRD: the mean-field Haff rate 1/tau overflows (sigma^2 = %g): temperature/T_theory is "
                            "written from its logarithm, the attribute haff_rate is left out", o_.sigma * o_.sigma);
    }
    return write_snapshots(f, file, nrec);
  }

  /* the XDMF sidecar OUTPUT.xmf of the field snapshots (written as OUTPUT.xmf.tmp) */
  std::vector<std::string> sidecars(const std::string &output) const override {
    if (s_->srd.snap_index.empty()) return {};
    return {xmf_path(output)};
  }

  /* A split gas writes this process's brick as a part file of the checkpoint set (part_path) and
   * in the checkpoint's group only what names the set: the attributes split_generation, split_step
   * and split_pgrid0..2 (every process of the gas the same; the group's first one sends it). */
  int checkpoint_write(int64_t file, const char *fname, const char *group) override {
    GRAN_CHECK(srd_ != nullptr || bst_ != nullptr, GRAN_ERR_STATE, "GSRD engine: checkpoint before start");
    H5Obj g(-1, H5Gclose);
    if (split_) {
      const int64_t gen = gen_ + 1;
      const std::string part = part_path(fname, group, gen, comm_.rank);
      const char *pp = part.c_str();
      GRAN_CALL(srd_bricks_save_(bst_, &pp, gen));
      gen_ = gen;
      cur_part_ = part;
      ckpt_ = fname;
      group_ = group;
      GRAN_CALL(gran_h5::make_group(file, group, &g.id, fname));
      GRAN_CALL(gran_h5::attr_int64(g.id, "split_generation", gen, fname));
      GRAN_CALL(gran_h5::attr_int64(g.id, "split_step", steps_done(), fname));
      for (int k = 0; k < 3; ++k)
        GRAN_CALL(gran_h5::attr_int64(g.id, ("split_pgrid" + std::to_string(k)).c_str(), pgrid_[k], fname));
    } else {
      /* the engine's state (src/srd/checkpoint.cpp), then the adapter's own part in the same group:
       * the stress window's start and replica 0's field snapshots */
      GRAN_CALL(gran_srd_checkpoint_write_h5_(srd_, file, group, fname));
      g.id = H5Gopen2((hid_t)file, group, H5P_DEFAULT);
    }
    GRAN_CHECK(g.id >= 0, GRAN_ERR_IO, "HDF5: cannot open group '%s' in '%s'", group, fname);
    GRAN_CALL(gran_h5::attr_double(g.id, "stress_t0", stress_t0_, fname));
    const int64_t ns = (int64_t)snaps_.size();
    GRAN_CALL(gran_h5::attr_int64(g.id, "snapshots", ns, fname));
    for (int64_t j = 0; j < ns; ++j) {
      const Snap &sn = snaps_[(size_t)j];
      H5Obj sg(-1, H5Gclose);
      GRAN_CALL(gran_h5::make_group(g.id, ("snap" + std::to_string(j)).c_str(), &sg.id, fname));
      GRAN_CALL(gran_h5::attr_int64(sg.id, "index", sn.index, fname));
      GRAN_CALL(gran_h5::write_double(sg.id, "count", {cells_}, sn.count.data(), fname));
      GRAN_CALL(gran_h5::write_double(sg.id, "velocity", {cells_ * 3}, sn.vel.data(), fname));
      GRAN_CALL(gran_h5::write_double(sg.id, "temperature", {cells_}, sn.temp.data(), fname));
    }
    return GRAN_SUCCESS;
  }

  /* The state from the checkpoint: a whole state (a run in one process), or a checkpoint set (its
   * group names the set: the parts of a split gas). Either resumes in one process (the parts merged
   * by key) or split over this run's processes, with the same split (each process reads its own
   * part) or another (each reads every part and keeps its brick's share). */
  int checkpoint_read(int64_t file, const char *fname, const char *group, uint64_t seed) override {
    gran_srd_destroy(&srd_);
    srd_bricks_close_(&bst_);
    snaps_.clear();
    prev_parts_.clear();
    cur_part_.clear();
    gen_ = 0;
    rep0_ = std::strcmp(group, "/engine") == 0;
    /* the engine's state, every stored physics option compared with the scene's (its text is
     * the checkpoint's own) before anything is allocated */
    gran_srd_options expect = o_;
    expect.seed = seed;
    H5Obj g(gran_h5::exists(file, group) ? H5Gopen2((hid_t)file, group, H5P_DEFAULT) : -1, H5Gclose);
    GRAN_CHECK(g.id >= 0, GRAN_ERR_IO, "checkpoint '%s': cannot open group '%s'", fname, group);
    int64_t next = -1;
    GRAN_CALL(gran_h5::read_attr_int64((hid_t)file, "next_index", &next, fname));
    if (H5Aexists(g.id, "split_generation") > 0) {
      int64_t gen = 0, step = -1, pg[3] = {0, 0, 0};
      GRAN_CALL(gran_h5::read_attr_int64(g.id, "split_generation", &gen, fname));
      GRAN_CALL(gran_h5::read_attr_int64(g.id, "split_step", &step, fname));
      for (int k = 0; k < 3; ++k)
        GRAN_CALL(gran_h5::read_attr_int64(g.id, ("split_pgrid" + std::to_string(k)).c_str(), &pg[k], fname));
      int64_t nb = 1;
      for (int k = 0; k < 3; ++k) {
        const int64_t nc = k < o_.dim ? o_.cells[k] + (k == o_.wall_axis ? 1 : 0) : 1;
        GRAN_CHECK(pg[k] >= 1 && pg[k] <= nc, GRAN_ERR_IO,
                   "checkpoint '%s': field 'split_pgrid%d' of '%s' = %lld outside [1, %lld] (the cells along axis %d)",
                   fname, k, group, (long long)pg[k], (long long)nc, k);
        nb *= pg[k];
      }
      GRAN_CHECK(gen >= 1 && gen < INT64_MAX, GRAN_ERR_IO, "checkpoint '%s': field 'split_generation' of '%s' = %lld",
                 fname, group, (long long)gen);
      std::vector<std::string> all((size_t)nb);
      for (int64_t b = 0; b < nb; ++b) all[(size_t)b] = part_path(fname, group, gen, (int)b);
      const bool own = split_ && pg[0] == pgrid_[0] && pg[1] == pgrid_[1] && pg[2] == pgrid_[2];
      std::vector<const char *> pp;
      if (own) pp.push_back(all[(size_t)comm_.rank].c_str());
      else
        for (const std::string &q : all) pp.push_back(q.c_str());
      if (split_) {
        int peer = 0;
        const int e = srd_bricks_load_(&expect, pgrid_, &comm_, pp.data(), (int)pp.size(), own ? 1 : 0, gen, step, &bst_,
                                       &peer);
        if (peer) { /* another process's part was refused: the driver reports that process's message */
          gran_clear_error();
          return GRAN_SUCCESS;
        }
        GRAN_CALL(e);
        if (own) prev_parts_.push_back(all[(size_t)comm_.rank]);
        else if (comm_.rank == 0) prev_parts_ = all; /* the set's parts go once this run commits its own */
      } else {
        GRAN_CALL(srd_state_from_parts_(&expect, pp.data(), (int)pp.size(), gen, step, &srd_));
        prev_parts_ = all;
      }
      gen_ = gen;
    } else if (split_) {
      /* a whole state (of one process) split: every process reads it and keeps its brick's share */
      gran_srd *whole = nullptr;
      GRAN_CALL(gran_srd_checkpoint_read_h5_(file, group, fname, &expect, &whole));
      const int e = srd_bricks_from_state_(whole, pgrid_, &comm_, &bst_);
      gran_srd_destroy(&whole);
      GRAN_CALL(e);
    } else {
      GRAN_CALL(gran_srd_checkpoint_read_h5_(file, group, fname, &expect, &srd_));
    }
    {
      /* the engine stands at the step of the last recorded output time: rows the checkpoint says
       * were recorded were recorded by this state, and none after it */
      const std::vector<int64_t> &os = s_->srd.out_steps;
      const int64_t step = steps_done();
      GRAN_CHECK(next >= 1 && next <= (int64_t)os.size() && step == os[(size_t)next - 1], GRAN_ERR_IO,
                 "checkpoint '%s': field 'next_index' = %lld does not match the GSRD state in '%s' (step %lld; the "
                 "output time %lld is at step %lld)", fname, (long long)next, group, (long long)step,
                 (long long)(next - 1), (long long)(next >= 1 && next <= (int64_t)os.size() ? os[(size_t)next - 1] : -1));
      next_ = next;
    }
    GRAN_CHECK(H5Aexists(g.id, "stress_t0") > 0, GRAN_ERR_IO, "checkpoint '%s': '%s' has no stress_t0", fname, group);
    H5Obj a(H5Aopen(g.id, "stress_t0", H5P_DEFAULT), H5Aclose);
    GRAN_CHECK(a.id >= 0 && H5Aread(a.id, H5T_NATIVE_DOUBLE, &stress_t0_) >= 0, GRAN_ERR_IO,
               "checkpoint '%s': cannot read stress_t0 of '%s'", fname, group);
    GRAN_CHECK(std::isfinite(stress_t0_) && stress_t0_ >= 0 && stress_t0_ <= (double)steps_done() * o_.dt * (1 + 1e-12),
               GRAN_ERR_IO, "checkpoint '%s': field 'stress_t0' of '%s' = %g outside [0, the state's time]", fname, group,
               stress_t0_);
    int64_t ns = 0;
    GRAN_CALL(gran_h5::read_attr_int64(g.id, "snapshots", &ns, fname));
    GRAN_CHECK(ns >= 0 && ns <= (int64_t)s_->srd.snap_index.size(), GRAN_ERR_IO, "checkpoint '%s': %lld snapshots out of range",
               fname, (long long)ns);
    {
      /* replica 0 holds one snapshot per snapshot output time recorded, the others none */
      int64_t want = 0;
      if (rep0_)
        for (int64_t i : s_->srd.snap_index) want += i < next_ ? 1 : 0;
      GRAN_CHECK(ns == want, GRAN_ERR_IO, "checkpoint '%s': field 'snapshots' of '%s' = %lld, the recorded output times "
                 "give %lld", fname, group, (long long)ns, (long long)want);
    }
    /* a split gas's snapshots are its group's first process's (the others never write them) */
    for (int64_t j = 0; j < (split_ && comm_.rank != 0 ? 0 : ns); ++j) {
      const std::string nm = "snap" + std::to_string(j);
      GRAN_CHECK(gran_h5::exists(g.id, nm.c_str()), GRAN_ERR_IO, "checkpoint '%s': '%s/%s' missing", fname, group, nm.c_str());
      H5Obj sg(H5Gopen2(g.id, nm.c_str(), H5P_DEFAULT), H5Gclose);
      Snap sn;
      GRAN_CALL(gran_h5::read_attr_int64(sg.id, "index", &sn.index, fname));
      /* snapshot j is the one of the j-th snapshot output time, taken when that row was recorded */
      GRAN_CHECK(sn.index == s_->srd.snap_index[(size_t)j] && sn.index < next_, GRAN_ERR_IO,
                 "checkpoint '%s': field 'index' of '%s/%s' = %lld (expected %lld, before the next output %lld)", fname,
                 group, nm.c_str(), (long long)sn.index, (long long)s_->srd.snap_index[(size_t)j], (long long)next_);
      GRAN_CALL(gran_h5::read_double(sg.id, "count", sn.count, nullptr, fname));
      GRAN_CALL(gran_h5::read_double(sg.id, "velocity", sn.vel, nullptr, fname));
      GRAN_CALL(gran_h5::read_double(sg.id, "temperature", sn.temp, nullptr, fname));
      GRAN_CHECK((int64_t)sn.count.size() == cells_ && (int64_t)sn.vel.size() == 3 * cells_ &&
                     (int64_t)sn.temp.size() == cells_,
                 GRAN_ERR_IO, "checkpoint '%s': snapshot '%s' has the wrong size", fname, nm.c_str());
      /* what a run records there: counts whole and >= 0, velocities and temperatures finite */
      for (double c : sn.count)
        GRAN_CHECK(c >= 0 && c <= 4e9 && c == std::floor(c), GRAN_ERR_IO,
                   "checkpoint '%s': field 'count' of snapshot '%s' holds %g (a particle count is whole and >= 0)", fname,
                   nm.c_str(), c);
      for (const std::vector<double> *f : {&sn.vel, &sn.temp})
        for (double x : *f)
          GRAN_CHECK(std::isfinite(x), GRAN_ERR_IO, "checkpoint '%s': field '%s' of snapshot '%s' holds %g", fname,
                     f == &sn.vel ? "velocity" : "temperature", nm.c_str(), x);
      snaps_.push_back(std::move(sn));
    }
    return GRAN_SUCCESS;
  }

  std::vector<gran_summary_column> summary_columns() const override {
    std::vector<gran_summary_column> c;
    if (s_->srd.obs_temperature)
      c.push_back({"T", "temperature/T", haff_applies() && s_->srd.obs_theory ? "temperature/T_theory" : ""});
    if (s_->srd.obs_clustering) c.push_back({"Mach", "clustering/mach", ""});
    if (s_->srd.obs_stress) c.push_back({"eta", "stress/eta", ""});
    return c;
  }

 private:
  const gran_scene *s_;
  gran_srd_options o_;
  gran_srd *srd_ = nullptr;
  double last_T_ = NAN; /* T at the last recorded output time (the progress report) */
  int64_t cells_ = 1, N_ = 0;
  bool rep0_ = true;
  double stress_t0_ = 0.0;
  int64_t next_ = 0; /* next output index of a resumed checkpoint */
  std::vector<Snap> snaps_;
  /* a split gas (split_): this process's bricks over comm_, the split, the shells of the last S(k) */
  bool split_ = false;
  srd_bricks_comm comm_;
  srd_bricks_state *bst_ = nullptr;
  int pgrid_[3] = {1, 1, 1};
  std::vector<double> sk_k_;
  std::vector<int64_t> sk_c_;

  /* checkpoint sets: the generation of the last part written (or read), the part written and not
   * yet committed, and the parts to remove once the next checkpoint commits */
  int64_t gen_ = 0;
  std::string cur_part_, ckpt_, group_; /* the part written, for the checkpoint and group it belongs to */
  std::vector<std::string> prev_parts_;

  void checkpoint_settled(bool committed) override {
    if (!committed) {
      if (!cur_part_.empty()) std::remove(cur_part_.c_str());
      cur_part_.clear();
      return;
    }
    for (const std::string &q : prev_parts_)
      if (q != cur_part_) std::remove(q.c_str());
    prev_parts_.clear();
    if (!cur_part_.empty()) {
      prev_parts_.push_back(cur_part_);
      if (split_ && comm_.rank == 0 && !stale_swept_) sweep_stale(ckpt_, group_.c_str());
    }
    cur_part_.clear();
  }
  /* once per run, after its first commit: the files of this replica's parts beside the checkpoint
   * that the committed set does not hold (another generation, a brick beyond this split, a .tmp:
   * left by an earlier run of the same checkpoint path that did not finish; no checkpoint names
   * them now) go. `part` is this process's committed part, CKPT.part-gG-rK-bB; the set's names are
   * part_path's. */
  bool stale_swept_ = false;
  void sweep_stale(const std::string &ckpt, const char *group) {
    stale_swept_ = true;
    std::vector<std::string> set;
    for (int b = 0; b < comm_.size; ++b) set.push_back(part_path(ckpt.c_str(), group, gen_, b));
    const size_t slash = ckpt.rfind('/');
    const std::string dir = slash == std::string::npos ? "." : ckpt.substr(0, slash);
    const std::string base = ckpt.substr(slash == std::string::npos ? 0 : slash + 1) + ".part-g";
    const std::string rk = set[0].substr(set[0].rfind("-r"), set[0].rfind("-b") + 2 - set[0].rfind("-r")); /* -rK-b */
    DIR *d = opendir(dir.c_str());
    if (!d) return;
    std::vector<std::string> gone;
    while (struct dirent *e = readdir(d)) {
      const std::string nm = e->d_name, path = dir + "/" + nm;
      if (nm.compare(0, base.size(), base) != 0 || nm.find(rk, base.size()) == std::string::npos) continue;
      if (std::find(set.begin(), set.end(), (slash == std::string::npos ? nm : path)) == set.end()) gone.push_back(path);
    }
    closedir(d);
    for (const std::string &q : gone) std::remove(q.c_str());
  }
  void checkpoint_remove() override {
    for (const std::string &q : prev_parts_) std::remove(q.c_str());
    prev_parts_.clear();
  }
  /* part file of brick b of the set of generation gen of the replica whose checkpoint group is
   * `group` (/engine: replica 0; /replicas/k/engine: k): CKPT.part-gG-rK-bB */
  static std::string part_path(const char *ckpt, const char *group, int64_t gen, int b) {
    long long k = 0;
    if (std::strncmp(group, "/replicas/", 10) == 0) k = std::atoll(group + 10);
    return std::string(ckpt) + ".part-g" + std::to_string(gen) + "-r" + std::to_string(k) + "-b" + std::to_string(b);
  }

  int64_t steps_done() const { return split_ ? srd_bricks_steps_(bst_) : gran_srd_steps_(srd_); }
  /* the status of a collective call of a split gas: an error on this process stops every process
   * (they would wait for it in the next exchange), through the group's abort, which prints it */
  int collective(int st) const {
    if (st != GRAN_SUCCESS && split_ && comm_.abort) comm_.abort(comm_.ctx, gran_last_error_message());
    return st;
  }

  /* homogeneous cooling: dissipation and nothing else acting on the gas; the mean-field rate
   * (src/srd/theory.cpp, which `granary theory` prints too) */
  bool haff_applies() const { return gran_srd_haff_applies_(&o_) != 0; }
  double haff_rate() const { return gran_srd_haff_rate_(&o_); }

  /* mean velocity of the particles in each y layer from the cell fields */
  void profile(const std::vector<double> &cnt, const std::vector<double> &vel, double *row) const {
    const int64_t L0 = o_.cells[0], L1 = o_.cells[1], L2 = o_.dim == 3 ? o_.cells[2] : 1;
    for (int64_t j = 0; j < L1; ++j) {
      double m = 0, u[3] = {0, 0, 0};
      for (int64_t k = 0; k < L2; ++k)
        for (int64_t i = 0; i < L0; ++i) {
          const size_t c = (size_t)(i + L0 * (j + L1 * k));
          m += cnt[c];
          for (int q = 0; q < 3; ++q) u[q] += cnt[c] * vel[3 * c + q];
        }
      for (int q = 0; q < 3; ++q) row[3 * j + q] = m > 0 ? u[q] / m : NAN;
    }
  }

  /* /fields/snap_NNNNNN/{count, density, velocity, temperature} (attributes time, step,
   * output_index), /fields/{time, step, output_index} of all snapshots, and the XDMF sidecar (its
   * .tmp: the driver renames it once the output file it points to is in place). The sidecar names
   * the output by its base name: the two files sit in the same directory. */
  int write_snapshots(int64_t f, const char *file, int64_t nrec) {
    std::vector<const Snap *> use;
    for (const Snap &sn : snaps_)
      if (sn.index < nrec) use.push_back(&sn);
    if (use.empty()) return GRAN_SUCCESS;
    const int d = o_.dim;
    const int64_t L0 = o_.cells[0], L1 = o_.cells[1], L2 = d == 3 ? o_.cells[2] : 1;
    std::vector<int64_t> sdims = d == 3 ? std::vector<int64_t>{L2, L1, L0} : std::vector<int64_t>{L1, L0};
    std::vector<int64_t> vdims = sdims;
    vdims.push_back(3);
    const double vol = d == 3 ? o_.a * o_.a * o_.a : o_.a * o_.a;
    H5Obj g(-1, H5Gclose);
    GRAN_CALL(gran_h5::make_group(f, "fields", &g.id, file));
    GRAN_CALL(gran_h5::attr_string(g.id, "layout", d == 3 ? "[z][y][x], cell-centred, x fastest" : "[y][x], cell-centred, x fastest", file));
    GRAN_CALL(gran_h5::attr_double(g.id, "a", o_.a, file));
    GRAN_CALL(gran_h5::attr_string(g.id, "xdmf", base_name(xmf_path(file)), file));
    std::vector<double> times, dens((size_t)cells_);
    std::vector<int64_t> idx, steps;
    std::string grids;
    char buf[512];
    const std::string h5name = xml_escape(base_name(file));
    auto dimstr = [](const std::vector<int64_t> &v) {
      std::string s;
      for (int64_t x : v) s += (s.empty() ? "" : " ") + std::to_string(x);
      return s;
    };
    for (const Snap *sn : use) {
      char nm[32];
      std::snprintf(nm, sizeof nm, "snap_%06lld", (long long)sn->index);
      const double t = s_->times[(size_t)sn->index];
      const int64_t step = s_->srd.out_steps[(size_t)sn->index];
      times.push_back(t);
      steps.push_back(step);
      idx.push_back(sn->index);
      for (int64_t c = 0; c < cells_; ++c) dens[(size_t)c] = sn->count[(size_t)c] / vol;
      H5Obj sg(-1, H5Gclose);
      GRAN_CALL(gran_h5::make_group(g.id, nm, &sg.id, file));
      GRAN_CALL(gran_h5::attr_double(sg.id, "time", t, file));
      GRAN_CALL(gran_h5::attr_int64(sg.id, "step", step, file));
      GRAN_CALL(gran_h5::attr_int64(sg.id, "output_index", sn->index, file));
      GRAN_CALL(gran_h5::write_double(sg.id, "count", sdims, sn->count.data(), file));
      GRAN_CALL(gran_describe_(sg.id, "count", "1", "particles per cell", file));
      GRAN_CALL(gran_h5::write_double(sg.id, "density", sdims, dens.data(), file));
      GRAN_CALL(gran_describe_(sg.id, "density", "1/length^d", "number density per cell: count / a^d", file));
      GRAN_CALL(gran_h5::write_double(sg.id, "velocity", vdims, sn->vel.data(), file));
      GRAN_CALL(gran_describe_(sg.id, "velocity", "length/time", "mean velocity per cell (x, y, z; z = 0 in 2-D; 0 in empty cells)", file));
      GRAN_CALL(gran_h5::write_double(sg.id, "temperature", sdims, sn->temp.data(), file));
      GRAN_CALL(gran_describe_(sg.id, "temperature", "energy", "cell temperature sum |v - V|^2 / (d n) (0 in empty cells)", file));
      /* XDMF: a uniform grid per snapshot, always a 3DCORECTMesh: its Dimensions are node counts
       * (cells + 1) ordered z y x, Origin and Spacing of ORIGIN_DXDYDZ likewise. A 2-D snapshot is
       * the plane z = 0 (one node along z): the readers place a 2DCORECTMesh in the y-z plane,
       * where the velocity (vx, vy, 0) would not lie along the grid. */
      std::vector<int64_t> nodes = sdims;
      for (int64_t &x : nodes) x += 1;
      if (d == 2) nodes.insert(nodes.begin(), 1);
      std::string geo_s;
      for (int k = 0; k < 3; ++k) {
        std::snprintf(buf, sizeof buf, "%s%.17g", k ? " " : "", o_.a);
        geo_s += buf;
      }
      std::snprintf(buf, sizeof buf, "%.17g", t);
      grids += "      <Grid Name=\"" + std::string(nm) + "\" GridType=\"Uniform\">\n";
      grids += "        <Time Value=\"" + std::string(buf) + "\"/>\n";
      grids += "        <Topology TopologyType=\"3DCORECTMesh\" Dimensions=\"" + dimstr(nodes) + "\"/>\n";
      grids += "        <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n";
      grids += "          <DataItem Name=\"Origin\" Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
               "Format=\"XML\">0 0 0</DataItem>\n";
      grids += "          <DataItem Name=\"Spacing\" Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
               "Format=\"XML\">" + geo_s + "</DataItem>\n";
      grids += "        </Geometry>\n";
      const char *attrs[4][2] = {{"density", "Scalar"}, {"count", "Scalar"}, {"temperature", "Scalar"}, {"velocity", "Vector"}};
      for (auto &at : attrs) {
        const bool vec = !std::strcmp(at[1], "Vector");
        grids += std::string("        <Attribute Name=\"") + at[0] + "\" AttributeType=\"" + at[1] + "\" Center=\"Cell\">\n";
        grids += "          <DataItem Dimensions=\"" + dimstr(vec ? vdims : sdims) +
                 "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + h5name + ":/fields/" + nm + "/" + at[0] +
                 "</DataItem>\n";
        grids += "        </Attribute>\n";
      }
      grids += "      </Grid>\n";
    }
    const int64_t ns = (int64_t)times.size();
    GRAN_CALL(gran_h5::write_double(g.id, "time", {ns}, times.data(), file));
    GRAN_CALL(gran_describe_(g.id, "time", "time", "times of the snapshots (the Time of each grid of the XDMF sidecar)", file));
    GRAN_CALL(gran_h5::write_int64(g.id, "step", {ns}, steps.data(), file));
    GRAN_CALL(gran_describe_(g.id, "step", "1", "collision steps done at each snapshot (time = step dt)", file));
    GRAN_CALL(gran_h5::write_int64(g.id, "output_index", {ns}, idx.data(), file));
    GRAN_CALL(gran_describe_(g.id, "output_index", "1", "output index (row of /time) of each snapshot", file));
    std::string x = "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n  <Domain>\n"
                    "    <Grid Name=\"GSRD fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n" +
                    grids + "    </Grid>\n  </Domain>\n</Xdmf>\n";
    const std::string xp = xmf_path(file), tmp = xp + ".tmp";
    {
      FILE *fx = std::fopen(tmp.c_str(), "wb");
      GRAN_CHECK(fx != nullptr, GRAN_ERR_IO, "cannot write the XDMF file '%s': %s", tmp.c_str(), std::strerror(errno));
      bool ok = std::fwrite(x.data(), 1, x.size(), fx) == x.size();
      ok = std::fclose(fx) == 0 && ok;
      if (!ok) std::remove(tmp.c_str());
      GRAN_CHECK(ok, GRAN_ERR_IO, "cannot write the XDMF file '%s'", tmp.c_str());
    }
    return GRAN_SUCCESS;
  }
};

}  // namespace

int gran_engine_srd_create_(const gran_scene *s, std::unique_ptr<gran_engine> &out) {
  std::unique_ptr<SrdEngine> e(new SrdEngine(s));
  GRAN_CALL(e->prepare());
  out = std::move(e);
  return GRAN_SUCCESS;
}
