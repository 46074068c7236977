/* engine_dsmc.cpp - the DSMC engine (src/dsmc) behind the run driver's engine interface
 * (engine.h): its observables, its species table and the kinetic theory written beside them. */
#include <hdf5.h>

#include <algorithm>
#include <cmath>

#include "io/engine.h"

namespace {

struct H5Group {
  int64_t id = -1;
  ~H5Group() { gran_h5::close_group(id); }
};

class DsmcEngine : public gran_engine {
 public:
  explicit DsmcEngine(const gran_scene *s) : s_(s) {}
  ~DsmcEngine() override {
    gran_dsmc_destroy(&sim_);
    gran_mixture_destroy(&mix_);
  }
  int prepare() { return gran_scene_mixture(s_, &mix_); }
  /* T0 and tau0 as the scene asks, computed once, where a run or a resume first needs them (the
   * HCS start costs passes over the M^2 species pairs: an engine built only for the list of its
   * files never pays them) */
  int initial() {
    if (!T0_.empty()) return GRAN_SUCCESS;
    std::vector<double> T0((size_t)s_->nspecies, 0.0);
    GRAN_CALL(gran_scene_T0_(s_, mix_, T0.data(), &tau0_));
    T0_ = std::move(T0);
    return GRAN_SUCCESS;
  }
  const char *type() const override { return "dsmc"; }

  int declare(std::vector<gran_row_buf> &b) override {
    const gran_scene *s = s_;
    const int64_t M = s->nspecies;
    gran_row_buf_add(b, "stats", "collisions", 1, {}, "1", "accepted collisions since the start of the run");
    gran_row_buf_add(b, "stats", "trials", 1, {}, "1", "candidate pairs drawn since the start of the run");
    if (s->obs_temperatures)
      gran_row_buf_add(b, "temperatures", "T", 0, {M}, "energy",
                       "partial temperature T_k = m_k <|v - u|^2> / 3 per species [time][k]");
    if (s->obs_msd) {
      gran_row_buf_add(b, "msd", "msd", 0, {M}, "length^2", "mean-squared displacement per species [time][k]");
      gran_row_buf_add(b, "msd", "msd_total", 0, {}, "length^2", "mean-squared displacement of all particles (Eq. 3)");
    }
    if (s->obs_energy) {
      gran_row_buf_add(b, "energy", "e_kin", 0, {}, "energy", "total kinetic energy sum m v^2 / 2");
      gran_row_buf_add(b, "energy", "e_initial", 0, {}, "energy", "total kinetic energy at the start");
      gran_row_buf_add(b, "energy", "e_dissipated", 0, {}, "energy", "energy dissipated in collisions so far");
    }
    if (s->obs_momentum)
      gran_row_buf_add(b, "momentum", "p", 0, {3}, "mass*length/time", "total momentum (x, y, z) of the gas");
    if (s->obs_collision_counts)
      gran_row_buf_add(b, "collision_counts", "counts", 1, {M, M}, "1",
                       "accepted collisions between species i and j since the start [time][i][j], symmetric");
    if (s->obs_sonine_a2)
      gran_row_buf_add(b, "sonine_a2", "a2", 0, {M}, "1", "Sonine coefficient a2 = 3 <c^4>/5 <c^2>^2 - 1 per species");
    if (agg()) { /* aggregation / fragmentation (any selector) */
      gran_row_buf_add(b, "clusters", "stats", 1, {6}, "1",
                       "clusters, largest size, sizes present, merges, breakups, bounces since the start [time][6]");
      gran_row_buf_add(b, "clusters", "n", 1, {M}, "1", "clusters of size k = 1..nspecies [time][k]");
      gran_row_buf_add(b, "clusters", "ledger", 0, {4}, "energy",
                       "energy dissipated in bounces, lost in merges, lost in breakups, added by the thermostat [time][4]");
    }
    if (s->obs_veldist)
      gran_row_buf_add(b, "velocity_distribution", "pdf", 0, {M, s->vd_bins}, "1",
                       "speed histogram of c = |v - u_k| / sqrt(2 T_k / m_k), normalised by N_k dc [time][k][bin]");
    /* the axes over the species (the driver attaches the group's `species` scale to them) */
    const char *per_species[][2] = {{"temperatures", "T"}, {"msd", "msd"}, {"sonine_a2", "a2"}, {"clusters", "n"},
                                    {"velocity_distribution", "pdf"}};
    for (const auto &gn : per_species) gran_row_buf_species_axes(b, gn[0], gn[1], {0});
    gran_row_buf_species_axes(b, "collision_counts", "counts", {0, 1});
    /* per-species values of a species without particles (record allows NaN only there) */
    const char *empty = "a species without particles";
    gran_row_buf_allow_fill(b, "temperatures", "T", empty);
    gran_row_buf_allow_fill(b, "msd", "msd", empty);
    gran_row_buf_allow_fill(b, "sonine_a2", "a2", empty);
    gran_row_buf_allow_fill(b, "velocity_distribution", "pdf", empty);
    return GRAN_SUCCESS;
  }

  /* gran_scene_dsmc with the replica's seed */
  int start(uint64_t seed) override {
    GRAN_CALL(initial());
    const std::vector<double> &T0 = T0_;
    gran_dsmc_options opt;
    GRAN_CALL(gran_scene_dsmc_options(s_, &opt, nullptr, nullptr));
    opt.seed = seed;
    if (s_->selector == GRAN_SELECTOR_CELL) /* cell selector */
      return gran_dsmc_create_cell(mix_, s_->counts_kind == 0 ? s_->counts.data() : nullptr, T0.data(), &opt,
                                   &s_->cell, &sim_);
    /* event selectors: [aggregation] (off: the plain engine) */
    return gran_dsmc_create_agg(mix_, s_->counts_kind == 0 ? s_->counts.data() : nullptr, T0.data(), &opt, &s_->agg,
                                &sim_);
  }
  /* one engine of this scene: the memory model the scene check uses too (src/dsmc/memory.cpp) */
  int memory(int64_t *bytes) override {
    std::vector<gran_mem_part> parts;
    const double b = gran_dsmc_memory_(*s_, parts);
    *bytes = b < 9e18 ? (int64_t)b : INT64_MAX;
    return GRAN_SUCCESS;
  }
  int advance(double t) override { return gran_dsmc_advance(sim_, t); }
  int state(gran_engine_state *st) override {
    gran_dsmc_stats x;
    GRAN_CALL(gran_dsmc_get_stats(sim_, &x));
    st->time = x.time;
    st->events = x.collisions;
    st->temperature = last_T_;
    return GRAN_SUCCESS;
  }

  /* The theory's expected collision count from t_start to each t (gran_theory_collision_counts:
   * an ODE over the M^2 pairs, with M^2 counts per time) up to kWorkSpeciesExact species, Haff's
   * law of the mean beyond; where the theory cannot say (it fails or is not finite), the
   * simulated time span. Only the progress line's fraction and ETA use it. */
  static constexpr int64_t kWorkSpeciesExact = 64;
  int work(int64_t n, const double *t, double *w) override {
    const int64_t M = s_->nspecies;
    GRAN_CALL(initial());
    gran_dsmc_stats x;
    GRAN_CALL(gran_dsmc_get_stats(sim_, &x));
    std::vector<double> tt((size_t)n);
    for (int64_t i = 0; i < n; i++) tt[(size_t)i] = std::max(0.0, t[i] - s_->t_start);
    if (M > kWorkSpeciesExact) { /* Haff's law: collisions ~ tau0 ln(1 + t / tau0) (t: elastic) */
      for (int64_t i = 0; i < n; i++)
        w[i] = std::isfinite(tau0_) && tau0_ > 0 ? tau0_ * std::log1p(tt[(size_t)i] / tau0_) : tt[(size_t)i];
      return GRAN_SUCCESS;
    }
    std::vector<double> c((size_t)(n * M * M));
    bool ok = gran_theory_collision_counts(mix_, T0_.data(), x.volume, n, tt.data(), 1e-6, c.data()) == GRAN_SUCCESS;
    for (int64_t i = 0; i < n && ok; i++) {
      double sum = 0;
      for (int64_t a = 0; a < M; a++)
        for (int64_t b = a; b < M; b++) sum += c[(size_t)((i * M + a) * M + b)];
      w[i] = sum;
      ok = std::isfinite(sum);
    }
    if (!ok) {
      gran_clear_error();
      for (int64_t i = 0; i < n; i++) w[i] = tt[(size_t)i];
    }
    return GRAN_SUCCESS;
  }

  int record(std::vector<gran_row_buf> &bufs, int64_t i) override {
    gran_dsmc_stats st;
    GRAN_CALL(gran_dsmc_get_stats(sim_, &st));
    /* one energy sum per output time, for the energy row and the progress report's T */
    double e, e0, ed;
    GRAN_CALL(gran_dsmc_energy(sim_, &e, &e0, &ed));
    last_T_ = st.nparticles > 0 ? 2.0 * e / (3.0 * (double)st.nparticles) : NAN;
    for (auto &b : bufs) {
      double *d = b.is_int ? nullptr : b.d.data() + i * b.row;
      int64_t *n = b.is_int ? b.n.data() + i * b.row : nullptr;
      const std::string &g = b.group, &nm = b.name;
      if (g == "stats") {
        n[0] = nm == "collisions" ? st.collisions : st.trials;
      } else if (g == "temperatures") {
        GRAN_CALL(gran_dsmc_temperatures(sim_, d));
      } else if (g == "msd" && nm == "msd") {
        double total = 0;
        GRAN_CALL(gran_dsmc_msd(sim_, d, &total));
        gran_row_buf_find(bufs, "msd", "msd_total")->d[(size_t)i] = total;
      } else if (g == "energy" && nm == "e_kin") {
        d[0] = e;
        gran_row_buf_find(bufs, "energy", "e_initial")->d[(size_t)i] = e0;
        gran_row_buf_find(bufs, "energy", "e_dissipated")->d[(size_t)i] = ed;
      } else if (g == "momentum") {
        GRAN_CALL(gran_dsmc_momentum(sim_, d));
      } else if (g == "collision_counts") {
        GRAN_CALL(gran_dsmc_collision_counts(sim_, n));
      } else if (g == "sonine_a2") {
        GRAN_CALL(gran_dsmc_sonine_a2(sim_, d));
      } else if (g == "clusters") { /* cell selector with aggregation */
        gran_dsmc_cluster_stats c;
        GRAN_CALL(gran_dsmc_get_cluster_stats(sim_, &c));
        if (nm == "stats") {
          const int64_t row[6] = {c.nclusters, c.largest, c.nsizes, c.merges, c.breakups, c.bounces};
          std::copy(row, row + 6, n);
        } else if (nm == "n") {
          GRAN_CALL(gran_dsmc_counts(sim_, n));
        } else {
          d[0] = c.e_bounce;
          d[1] = c.e_merge;
          d[2] = c.e_break;
          d[3] = c.e_heat;
        }
      } else if (g == "velocity_distribution") {
        GRAN_CALL(record_veldist(d));
      }
    }
    /* a non-finite observable is an error, not a value in the file (NaN is allowed only where it
     * means "no particles": per-species values of an empty species) */
    const int64_t M = s_->nspecies;
    std::vector<int64_t> counts((size_t)M);
    GRAN_CALL(gran_dsmc_counts(sim_, counts.data()));
    for (const auto &b : bufs) {
      if (b.is_int) continue;
      const double *d = b.d.data() + i * b.row;
      const bool per_species = !b.row_dims.empty() && b.row_dims[0] == M;
      for (int64_t e = 0; e < b.row; e++) {
        if (std::isfinite(d[e])) continue;
        const int64_t k = per_species ? e / (b.row / M) : -1;
        if (std::isnan(d[e]) && k >= 0 && counts[(size_t)k] == 0) continue;
        return GRAN_ERROR(GRAN_ERR_NUMERIC, "observable '%s/%s' is %g at t = %g (element %" PRId64 "): the run stops here",
                          b.group.c_str(), b.name.c_str(), d[e], s_->times[(size_t)i], e);
      }
    }
    return GRAN_SUCCESS;
  }

  int write_output(int64_t f, const char *file, int64_t nrec) override {
    GRAN_CALL(initial());
    const gran_scene *s = s_;
    const int64_t M = s->nspecies, nt = nrec;
    const bool complete = nrec == (int64_t)s->times.size();
    GRAN_CALL(gran_h5::attr_string(f, "selector",
                                   s->selector == GRAN_SELECTOR_BIRD   ? "bird"
                                   : s->selector == GRAN_SELECTOR_CELL ? "cell"
                                                                       : "lowrank",
                                   file));
    if (s->selector == GRAN_SELECTOR_CELL) { /* cell selector: its options as attributes */
      GRAN_CALL(gran_h5::attr_int64(f, "cells", s->cell.cells, file));
      GRAN_CALL(gran_h5::attr_double(f, "dt", s->cell.dt, file));
      GRAN_CALL(gran_h5::attr_double(f, "fn", s->cell.fn, file));
    }
    GRAN_CALL(gran_h5::attr_int64(f, "nspecies", M, file));
    {
      /* the units (docs/units.md): m_1, sigma_1 and the number-weighted mean initial temperature */
      double nsum = 0, nT = 0;
      for (int64_t k = 0; k < M; k++) {
        nsum += s->density[(size_t)k];
        nT += s->density[(size_t)k] * T0_[(size_t)k];
      }
      const double Tm = nsum > 0 ? nT / nsum : T0_[0];
      GRAN_CALL(gran_write_unit_system_(f, file, "DSMC", s->mass[0], s->sigma[0], Tm));
    }
    {
      H5Group g;
      GRAN_CALL(gran_h5::make_group(f, "species", &g.id, file));
      std::vector<int64_t> counts((size_t)M);
      GRAN_CALL(gran_dsmc_counts(sim_, counts.data()));
      GRAN_CALL(gran_h5::write_double(g.id, "mass", {M}, s->mass.data(), file));
      GRAN_CALL(gran_describe_(g.id, "mass", "mass", "particle mass m_k per species", file));
      GRAN_CALL(gran_h5::write_double(g.id, "sigma", {M}, s->sigma.data(), file));
      GRAN_CALL(gran_describe_(g.id, "sigma", "length", "particle diameter sigma_k per species", file));
      GRAN_CALL(gran_h5::write_double(g.id, "density", {M}, s->density.data(), file));
      GRAN_CALL(gran_describe_(g.id, "density", "1/length^3", "number density n_k per species", file));
      GRAN_CALL(gran_h5::write_int64(g.id, "counts", {M}, counts.data(), file));
      GRAN_CALL(gran_describe_(g.id, "counts", "1", "simulated particles N_k per species", file));
      GRAN_CALL(gran_h5::write_double(g.id, "T0", {M}, T0_.data(), file));
      GRAN_CALL(gran_describe_(g.id, "T0", "energy", "initial partial temperatures T_k(t_start)", file));
      GRAN_CALL(gran_h5::attr_double(g.id, "tau0", tau0_, file));
    }
    if (s->obs_veldist) {
      H5Group g;
      g.id = H5Gopen2((hid_t)f, "velocity_distribution", H5P_DEFAULT);
      const int64_t B = s->vd_bins;
      const double dc = s->vd_cmax / (double)B;
      std::vector<double> edges((size_t)B + 1), maxw((size_t)B);
      auto F = [](double c) { return std::erf(c) - 2.0 * c / std::sqrt(M_PI) * std::exp(-c * c); };
      for (int64_t b = 0; b <= B; b++) edges[(size_t)b] = dc * (double)b;
      for (int64_t b = 0; b < B; b++) maxw[(size_t)b] = (F(edges[(size_t)b + 1]) - F(edges[(size_t)b])) / dc;
      GRAN_CALL(gran_h5::write_double(g.id, "edges", {B + 1}, edges.data(), file));
      GRAN_CALL(gran_describe_(g.id, "edges", "1", "bin edges of the scaled speed c", file));
      GRAN_CALL(gran_h5::write_double(g.id, "pdf_maxwell", {B}, maxw.data(), file));
      GRAN_CALL(gran_describe_(g.id, "pdf_maxwell", "1", "the Maxwellian speed distribution integrated over each bin / dc", file));
      GRAN_CALL(gran_h5::attr_string(g.id, "variable", "c = |v| / sqrt(2 T_k / m_k)", file));
    }
    if (s->obs_theory) {
      std::vector<double> tt((size_t)nt);
      for (int64_t i = 0; i < nt; i++) tt[(size_t)i] = s->times[(size_t)i] - s->t_start;
      GRAN_CALL(write_theory(f, file, tt));
    }
    if (s->obs_tamsd && complete) GRAN_CALL(write_tamsd(f, file));
    return GRAN_SUCCESS;
  }

  int checkpoint_write(int64_t file, const char *fname, const char *group) override {
    return gran_dsmc_checkpoint_write_h5_(sim_, file, group, fname);
  }
  int checkpoint_read(int64_t file, const char *fname, const char *group, uint64_t seed) override {
    GRAN_CALL(initial());
    gran_dsmc_destroy(&sim_);
    /* the options this replica's start() would give: the stored ones must be these */
    gran_dsmc_options expect;
    GRAN_CALL(gran_scene_dsmc_options(s_, &expect, nullptr, nullptr));
    expect.seed = seed;
    gran_dsmc_cell_options cell;
    GRAN_CALL(gran_scene_dsmc_cell_options(s_, &cell));
    gran_dsmc_agg_options agg;
    GRAN_CALL(gran_scene_dsmc_agg_options(s_, &agg));
    return gran_dsmc_checkpoint_read_h5_(file, group, mix_, &expect, expect.selector == GRAN_SELECTOR_CELL ? &cell : nullptr,
                                         expect.selector == GRAN_SELECTOR_CELL ? nullptr : &agg, &sim_, fname);
  }

  std::vector<gran_summary_column> summary_columns() const override {
    std::vector<gran_summary_column> c;
    const bool th = s_->obs_theory;
    if (s_->obs_temperatures) c.push_back({"T", "temperatures/T", th ? "temperatures/T_theory" : ""});
    if (s_->obs_msd) c.push_back({"MSD", "msd/msd", th && !gran_scene_driven_(s_) ? "msd/msd_theory" : ""});
    return c;
  }

 private:
  const gran_scene *s_;
  /* aggregation or fragmentation (any selector: s_->agg holds the cell selector's values too) */
  bool agg() const { return s_->agg.e_agg > 0 || std::isfinite(s_->agg.e_frag); }
  gran_mixture *mix_ = nullptr;
  gran_dsmc *sim_ = nullptr;
  std::vector<double> T0_;
  double tau0_ = NAN;
  double last_T_ = NAN; /* 2 E_kin / (3 N) at the last recorded output time (the progress report) */

  /* Speed histogram of c = |v - u_k| / sqrt(2 T_k / m_k) per species (gran_speed_histogram),
   * normalised by N_k dc. The velocities one species at a time (gran_dsmc_species_velocities): with
   * speed classes, gran_dsmc_particles would make the engine keep a copy of every particle (the
   * default scene's peak memory went from 47 to 80 MB with it). */
  int record_veldist(double *row) {
    const gran_scene *s = s_;
    const int64_t M = s->nspecies, B = s->vd_bins;
    std::vector<int64_t> cnt((size_t)M);
    std::vector<double> T((size_t)M);
    GRAN_CALL(gran_dsmc_counts(sim_, cnt.data()));
    GRAN_CALL(gran_dsmc_temperatures(sim_, T.data()));
    std::vector<double> v;
    for (int64_t k = 0; k < M; k++) {
      double *h = row + k * B;
      std::fill(h, h + B, 0.0);
      const int64_t n = cnt[(size_t)k];
      if (n <= 0 || !(T[(size_t)k] > 0)) continue;
      v.resize((size_t)(3 * n));
      GRAN_CALL(gran_dsmc_species_velocities(sim_, k, v.data()));
      const double scale = std::sqrt(2.0 * T[(size_t)k] / s->mass[(size_t)k]);
      GRAN_CALL(gran_speed_histogram(n, v.data(), scale, B, s->vd_cmax, h, nullptr));
    }
    return GRAN_SUCCESS;
  }

  /* Sonine T_k(t), a2_k(t) from the scene's start (T0, Maxwellian velocities: a2 = 0): the first level
   * (sonine_order = 2) or the second (3: a3 = 0 at the start, a3_theory_sonine beside). */
  int write_sonine_theory(int64_t gid, const char *file, const std::vector<double> &tt) {
    const int64_t M = s_->nspecies, nt = (int64_t)tt.size();
    const bool second = s_->theory_sonine_order == 3;
    std::vector<double> T((size_t)(nt * M)), a2((size_t)(nt * M)), a3(second ? (size_t)(nt * M) : 0);
    const int st = second ? gran_theory_temperatures_sonine2(mix_, T0_.data(), nullptr, nullptr, nt, tt.data(),
                                                             s_->theory_rtol, T.data(), a2.data(), a3.data())
                          : gran_theory_temperatures_approx(mix_, GRAN_THEORY_SONINE, T0_.data(), nullptr, nt, tt.data(),
                                                            s_->theory_rtol, T.data(), a2.data());
    if (st != GRAN_SUCCESS) {
      gran_warning_add("no T_theory_sonine in the output: %s", gran_last_error_message());
      return gran_h5::attr_string(gid, "theory_sonine_error", gran_last_error_message(), file);
    }
    const char *level = second ? "second" : "first";
    const std::string fn = second ? "gran_theory_temperatures_sonine2" : "gran_theory_temperatures_approx";
    GRAN_CALL(gran_h5::write_double(gid, "T_theory_sonine", {nt, M}, T.data(), file));
    GRAN_CALL(gran_describe_(gid, "T_theory_sonine", "energy",
                             (std::string("partial temperatures in the ") + level +
                              " Sonine approximation, from a2 = 0" + (second ? ", a3 = 0" : "") + " at the start (" + fn +
                              ") [time][k]")
                                 .c_str(),
                             file));
    GRAN_CALL(gran_attach_scales_(gid, "T_theory_sonine", {"time", "species"}, file));
    GRAN_CALL(gran_h5::write_double(gid, "a2_theory_sonine", {nt, M}, a2.data(), file));
    GRAN_CALL(gran_describe_(gid, "a2_theory_sonine", "1",
                             (std::string("Sonine coefficients a2_k in the ") + level + " Sonine approximation [time][k]")
                                 .c_str(),
                             file));
    GRAN_CALL(gran_attach_scales_(gid, "a2_theory_sonine", {"time", "species"}, file));
    if (second) {
      GRAN_CALL(gran_h5::write_double(gid, "a3_theory_sonine", {nt, M}, a3.data(), file));
      GRAN_CALL(gran_describe_(gid, "a3_theory_sonine", "1",
                               "Sonine coefficients a3_k in the second Sonine approximation [time][k]", file));
      GRAN_CALL(gran_attach_scales_(gid, "a3_theory_sonine", {"time", "species"}, file));
      GRAN_CALL(gran_h5::attr_string(gid, "theory_sonine_level", "second Sonine approximation (sonine_order = 3: a2, a3)",
                                     file));
    }
    return GRAN_SUCCESS;
  }

  /* Theory beside the simulation; a theory call that fails leaves a warning and an attribute. */
  int write_theory(int64_t f, const char *file, const std::vector<double> &tt) {
    const gran_scene *s = s_;
    const int64_t M = s->nspecies, nt = (int64_t)tt.size();
    std::vector<int64_t> dims = {nt, M};
    if (s->obs_temperatures) {
      H5Group g;
      g.id = H5Gopen2((hid_t)f, "temperatures", H5P_DEFAULT);
      std::vector<double> T((size_t)(nt * M));
      /* a driven cell gas (thermostat, bath): Eq. 13 with the driving; aggregation: the Smoluchowski
       * kinetics, which has no driving (written, and said so: the drift from it shows the drive) */
      const bool driven = gran_scene_driven_(s);
      if (driven && agg()) {
        gran_warning_add("T_theory and clusters/n_theory are the Smoluchowski kinetics without the thermostat's "
                         "heating or the bath (the library has no driven aggregation kinetics)");
        GRAN_CALL(gran_h5::attr_string(g.id, "theory_note", "Smoluchowski kinetics without the driving", file));
      }
      int st = agg()    ? write_agg_theory(f, file, tt, T.data()) /* cell selector: Smoluchowski */
               : driven ? gran_scene_driven_temperatures_(s, mix_, T0_.data(), nt, tt.data(), s->theory_rtol, T.data())
                        : gran_theory_temperatures(mix_, T0_.data(), nt, tt.data(), s->theory_rtol, T.data());
      if (st == GRAN_SUCCESS) {
        GRAN_CALL(gran_h5::write_double(g.id, "T_theory", dims, T.data(), file));
        GRAN_CALL(gran_describe_(g.id, "T_theory", "energy",
                                 driven && agg() ? "partial temperatures of the Smoluchowski kinetics WITHOUT the "
                                                   "thermostat's heating or the bath [time][k]"
                                 : driven ? "partial temperatures of the driven gas from the kinetic theory (Eq. 13 "
                                            "with the thermostat's heating and the bath, "
                                            "gran_theory_temperatures_driven) [time][k]"
                                          : "partial temperatures from the kinetic theory (Eq. 13) [time][k]",
                                 file));
        GRAN_CALL(gran_attach_scales_(g.id, "T_theory", {"time", "species"}, file));
      } else {
        gran_warning_add("no T_theory in the output: %s", gran_last_error_message());
        GRAN_CALL(gran_h5::attr_string(g.id, "theory_error", gran_last_error_message(), file));
      }
      if (s->obs_theory_sonine && !driven) GRAN_CALL(write_sonine_theory(g.id, file, tt));
      if (s->obs_theory_sonine && driven) {
        gran_warning_add("no T_theory_sonine in the output: the first Sonine theory of a driven gas is not in the library");
        GRAN_CALL(gran_h5::attr_string(g.id, "theory_sonine_error", "no first Sonine theory of a driven gas", file));
      }
    }
    if (s->obs_msd && gran_scene_driven_(s)) {
      H5Group g;
      g.id = H5Gopen2((hid_t)f, "msd", H5P_DEFAULT);
      gran_warning_add("no msd_theory in the output: the MSD theory (Eq. 4) is that of a freely cooling gas");
      GRAN_CALL(gran_h5::attr_string(g.id, "theory_error",
                                     "no MSD theory of a driven gas (Eq. 4 is that of a freely cooling gas)", file));
    } else if (s->obs_msd) {
      H5Group g;
      g.id = H5Gopen2((hid_t)f, "msd", H5P_DEFAULT);
      std::vector<double> m((size_t)(nt * M)), mt((size_t)nt);
      const bool hcs = s->init == SCENE_INIT_HCS && s->model != GRAN_RESTITUTION_VISCOELASTIC && std::isfinite(tau0_);
      int st = hcs ? gran_theory_msd_hcs(mix_, T0_.data(), tau0_, nt, tt.data(), m.data(), mt.data())
                   : gran_theory_msd(mix_, T0_.data(), nt, tt.data(), s->theory_rtol, m.data(), mt.data());
      if (st == GRAN_SUCCESS) {
        GRAN_CALL(gran_h5::write_double(g.id, "msd_theory", dims, m.data(), file));
        GRAN_CALL(gran_describe_(g.id, "msd_theory", "length^2", "mean-squared displacement from the kinetic theory [time][k]", file));
        GRAN_CALL(gran_attach_scales_(g.id, "msd_theory", {"time", "species"}, file));
        GRAN_CALL(gran_h5::write_double(g.id, "msd_total_theory", {nt}, mt.data(), file));
        GRAN_CALL(gran_describe_(g.id, "msd_total_theory", "length^2", "total mean-squared displacement from the kinetic theory", file));
        GRAN_CALL(gran_attach_scales_(g.id, "msd_total_theory", {"time"}, file));
        GRAN_CALL(gran_h5::attr_string(g.id, "theory", hcs ? "gran_theory_msd_hcs (Eq. 22)" : "gran_theory_msd (Eq. 4)", file));
      } else {
        gran_warning_add("no msd_theory in the output: %s", gran_last_error_message());
        GRAN_CALL(gran_h5::attr_string(g.id, "theory_error", gran_last_error_message(), file));
      }
      if (s->obs_theory_sonine) {
        /* from the same start (Maxwellian velocities: a2 = 0): sonine_order = 2 the two-moment velocity
         * correlation with the Maxwellian T_k(t); 3 Eq. 4 on the second Sonine trajectory of T_theory_sonine,
         * a2 in the correlation */
        const bool second = s->theory_sonine_order == 3;
        st = second ? gran_theory_msd_sonine2(mix_, T0_.data(), nullptr, nullptr, 1, nt, tt.data(), s->theory_rtol,
                                              m.data(), mt.data())
             : hcs  ? gran_theory_msd_hcs_approx(mix_, GRAN_THEORY_SONINE, T0_.data(), nullptr, tau0_, nt, tt.data(),
                                                 m.data(), mt.data())
                    : gran_theory_msd_approx(mix_, GRAN_THEORY_SONINE, T0_.data(), nt, tt.data(), s->theory_rtol,
                                             m.data(), mt.data());
        if (st == GRAN_SUCCESS) {
          GRAN_CALL(gran_h5::write_double(g.id, "msd_theory_sonine", dims, m.data(), file));
          GRAN_CALL(gran_describe_(
              g.id, "msd_theory_sonine", "length^2",
              second ? "mean-squared displacement by Eq. 4 on the second Sonine trajectory, with the two-moment velocity "
                       "correlation and a2 in it (gran_theory_msd_sonine2) [time][k]"
                     : "mean-squared displacement with the two-moment (second Sonine) velocity correlation "
                       "(gran_theory_msd_hcs_approx / gran_theory_msd_approx) [time][k]",
              file));
          GRAN_CALL(gran_attach_scales_(g.id, "msd_theory_sonine", {"time", "species"}, file));
          GRAN_CALL(gran_h5::write_double(g.id, "msd_total_theory_sonine", {nt}, mt.data(), file));
          GRAN_CALL(gran_describe_(g.id, "msd_total_theory_sonine", "length^2",
                                   "total mean-squared displacement with the two-moment velocity correlation", file));
          GRAN_CALL(gran_attach_scales_(g.id, "msd_total_theory_sonine", {"time"}, file));
        } else {
          gran_warning_add("no msd_theory_sonine in the output: %s", gran_last_error_message());
          GRAN_CALL(gran_h5::attr_string(g.id, "theory_sonine_error", gran_last_error_message(), file));
        }
      }
    }
    return GRAN_SUCCESS;
  }

  /* Aggregation (cell selector): n_k(t) of the temperature-dependent Smoluchowski equations
   * (gran_theory_aggregation) as clusters/n_theory (expected clusters: n_k times the volume per
   * simulated particle), and their T_k(t) into T. */
  int write_agg_theory(int64_t f, const char *file, const std::vector<double> &tt, double *T) {
    const gran_scene *s = s_;
    const int64_t M = s->nspecies, nt = (int64_t)tt.size();
    std::vector<double> n((size_t)(nt * M));
    GRAN_CALL(gran_theory_aggregation_law(mix_, T0_.data(), s->agg.e_agg, s->agg.e_frag, s->agg.eps_f, s->agg.frag_law,
                                          nt, tt.data(), s->theory_rtol, n.data(), T, nullptr));
    gran_dsmc_stats x;
    GRAN_CALL(gran_dsmc_get_stats(sim_, &x));
    for (double &v : n) v *= x.volume;
    H5Group g;
    g.id = H5Gopen2((hid_t)f, "clusters", H5P_DEFAULT);
    GRAN_CALL(gran_h5::write_double(g.id, "n_theory", {nt, M}, n.data(), file));
    GRAN_CALL(gran_describe_(g.id, "n_theory", "1",
                             "expected clusters of size k from the temperature-dependent Smoluchowski equations "
                             "(gran_theory_aggregation; sizes above nspecies leave the system) [time][k]",
                             file));
    if (gran_scene_driven_(s))
      GRAN_CALL(gran_h5::attr_string(g.id, "theory_note", "Smoluchowski kinetics without the driving", file));
    GRAN_CALL(gran_attach_scales_(g.id, "n_theory", {"time", "species"}, file));
    return GRAN_SUCCESS;
  }

  /* TAMSD of the recorded tracer trajectories, averaged over the tracers of each species
   * (gran_tamsd_plan_*: delta^2(L) = 1/(S-L) sum_{j<S-L} |R_{j+L} - R_j|^2, Eq. 26 on the grid).
   * Lags are rounded to whole sampling intervals; /tamsd/lag holds the lags used. */
  int write_tamsd(int64_t f, const char *file) {
    const gran_scene *s = s_;
    const int64_t M = s->nspecies, nl = (int64_t)s->tamsd_lags.size();
    int64_t ntraj = 0, ns = 0;
    const double *xyz = nullptr;
    const int32_t *sp = nullptr;
    GRAN_CALL(gran_dsmc_trajectories(sim_, &ntraj, &ns, &xyz, &sp));
    std::vector<double> lag((size_t)nl), ta((size_t)(nl * M), 0.0);
    std::vector<int64_t> L((size_t)nl), ntr((size_t)M, 0);
    for (int64_t l = 0; l < nl; l++) {
      L[(size_t)l] = std::max<int64_t>(1, (int64_t)std::llround(s->tamsd_lags[(size_t)l] / s->tamsd_dt));
      lag[(size_t)l] = (double)L[(size_t)l] * s->tamsd_dt;
    }
    int64_t Lmax = 1;
    for (int64_t x : L) Lmax = std::max(Lmax, x);
    GRAN_CHECK(Lmax < ns, GRAN_ERR_STATE, "TAMSD lag of %" PRId64 " samples >= the %" PRId64 " recorded samples", Lmax, ns);
    gran_tamsd_plan *plan = nullptr;
    GRAN_CALL(gran_tamsd_plan_create(ns, &plan));
    /* One trajectory at a time: the mean over the tracers of a species and its standard error
     * from their spread (Welford; the tracers are distinct particles of one gas, independent up to
     * O(1/N) correlations), so that a figure can tell a deviation from the theory from noise. */
    std::vector<double> full((size_t)Lmax + 1), mean((size_t)nl), m2((size_t)nl), se((size_t)(nl * M), NAN);
    int st = GRAN_SUCCESS;
    for (int64_t k = 0; k < M && st == GRAN_SUCCESS; k++) {
      std::fill(mean.begin(), mean.end(), 0.0);
      std::fill(m2.begin(), m2.end(), 0.0);
      int64_t n = 0;
      for (int64_t j = 0; j < ntraj && st == GRAN_SUCCESS; j++) {
        if (sp[j] != k) continue;
        st = gran_tamsd_plan_execute(plan, 1, xyz + j * ns * 3, Lmax + 1, full.data());
        n++;
        for (int64_t l = 0; l < nl && st == GRAN_SUCCESS; l++) {
          const double x = full[(size_t)L[(size_t)l]], d = x - mean[(size_t)l];
          mean[(size_t)l] += d / (double)n;
          m2[(size_t)l] += d * (x - mean[(size_t)l]);
        }
      }
      ntr[(size_t)k] = n;
      for (int64_t l = 0; l < nl; l++) {
        ta[(size_t)(l * M + k)] = n ? mean[(size_t)l] : NAN;
        if (n > 1) se[(size_t)(l * M + k)] = std::sqrt(m2[(size_t)l] / (double)(n - 1) / (double)n);
      }
    }
    gran_tamsd_plan_destroy(&plan);
    GRAN_CALL(st);
    H5Group g;
    GRAN_CALL(gran_h5::make_group(f, "tamsd", &g.id, file));
    const double t_meas = s->tamsd_dt * (double)(ns - 1);
    GRAN_CALL(gran_h5::write_double(g.id, "lag", {nl}, lag.data(), file));
    GRAN_CALL(gran_describe_(g.id, "lag", "time", "lag times used (whole sampling intervals)", file));
    GRAN_CALL(gran_make_scale_(g.id, "lag", file));
    GRAN_CALL(gran_species_scale_(g.id, M, file));
    GRAN_CALL(gran_h5::write_double(g.id, "tamsd", {nl, M}, ta.data(), file));
    GRAN_CALL(gran_describe_(g.id, "tamsd", "length^2", "time-averaged MSD of the tracers, averaged over the tracers of each species [lag][k]", file));
    GRAN_CALL(gran_attach_scales_(g.id, "tamsd", {"lag", "species"}, file));
    bool have_se = true; /* a species with one tracer has no spread: then no tamsd_se at all */
    for (int64_t k = 0; k < M; k++) have_se = have_se && ntr[(size_t)k] != 1;
    if (have_se) {
      GRAN_CALL(gran_h5::write_double(g.id, "tamsd_se", {nl, M}, se.data(), file));
      GRAN_CALL(gran_describe_(g.id, "tamsd_se", "length^2", "standard error of tamsd from the spread over the tracers of each species [lag][k]", file));
      GRAN_CALL(gran_attach_scales_(g.id, "tamsd_se", {"lag", "species"}, file));
    }
    GRAN_CALL(gran_h5::write_int64(g.id, "tracers", {M}, ntr.data(), file));
    GRAN_CALL(gran_describe_(g.id, "tracers", "1", "tracers per species in the TAMSD average", file));
    GRAN_CALL(gran_attach_scales_(g.id, "tracers", {"species"}, file));
    GRAN_CALL(gran_h5::attr_double(g.id, "t_meas", t_meas, file));
    GRAN_CALL(gran_h5::attr_double(g.id, "dt", s->tamsd_dt, file));
    GRAN_CALL(gran_h5::attr_int64(g.id, "samples", ns, file));
    if (s->obs_theory) {
      std::vector<double> th((size_t)(nl * M));
      /* the theory averaged over the same sample grid as the simulation (Eq. 27 is its dt -> 0 limit) */
      int st = gran_scene_driven_(s) ? GRAN_ERROR(GRAN_ERR_DOMAIN, "no TAMSD theory of a driven gas (Eq. 27 is that of "
                                                                    "the homogeneous cooling state)")
               : std::isfinite(tau0_) ? gran_theory_tamsd_sampled(mix_, T0_.data(), tau0_, s->tamsd_dt, ns, nl, L.data(),
                                                                  s->theory_rtol, th.data())
                                      : GRAN_ERROR(GRAN_ERR_DOMAIN, "tau0 of the HCS is not finite");
      if (st == GRAN_SUCCESS) {
        GRAN_CALL(gran_h5::write_double(g.id, "tamsd_theory", {nl, M}, th.data(), file));
        GRAN_CALL(gran_describe_(g.id, "tamsd_theory", "length^2", "TAMSD from the kinetic theory: Eq. 26 summed over the simulation's sample times (gran_theory_tamsd_sampled) [lag][k]", file));
        GRAN_CALL(gran_attach_scales_(g.id, "tamsd_theory", {"lag", "species"}, file));
      } else {
        gran_warning_add("no tamsd_theory in the output: %s", gran_last_error_message());
        GRAN_CALL(gran_h5::attr_string(g.id, "theory_error", gran_last_error_message(), file));
      }
    }
    return GRAN_SUCCESS;
  }
};

}  // namespace

int gran_engine_dsmc_create_(const gran_scene *s, std::unique_ptr<gran_engine> &out) {
  std::unique_ptr<DsmcEngine> e(new DsmcEngine(s));
  GRAN_CALL(e->prepare());
  out = std::move(e);
  return GRAN_SUCCESS;
}
