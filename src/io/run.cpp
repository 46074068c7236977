/* run.cpp - running a scene: engine, observers at the output times, HDF5 output, checkpoints.
 *
 * The engine is only ever advanced to the scene's output times (then to t_end), whether or not a
 * checkpoint is written there, so a run split by checkpoints makes exactly the same calls as an
 * uninterrupted one: resuming is bit for bit. Recorded rows live in named buffers [ntimes x row];
 * the output file and the checkpoint's /observer group are written from the same buffers. */
#include <hdf5.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <sys/stat.h>
#include <unistd.h>

#include "io/io_impl.h"

namespace {

const char *kCheckpointFormat = "granary-checkpoint 1";
const char *kOutputFormat = "granary-output 1";

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/* One recorded quantity: row `i` belongs to output time i. */
struct Buf {
  std::string group, name;
  int is_int = 0;
  std::vector<int64_t> row_dims; /* shape of one row */
  int64_t row = 1;               /* elements per row */
  std::vector<double> d;
  std::vector<int64_t> n;
};

struct Run {
  const gran_scene *s = nullptr;
  gran_scene *owned_scene = nullptr;
  gran_mixture *mix = nullptr;
  gran_dsmc *sim = nullptr;
  std::vector<double> T0;
  double tau0 = NAN;
  double tau_c0 = NAN; /* mean collision time of species 1 at the start (Eq. 7) */
  std::vector<Buf> bufs;
  int64_t next = 0; /* output times recorded */
  std::string out, ckpt;
  ~Run() {
    gran_dsmc_destroy(&sim);
    gran_mixture_destroy(&mix);
    gran_scene_destroy(&owned_scene);
  }
  Buf &buf(const char *g, const char *nm) {
    for (auto &b : bufs)
      if (b.group == g && b.name == nm) return b;
    throw std::logic_error("no buffer");
  }
};

void add_buf(Run &r, const char *g, const char *nm, int is_int, std::vector<int64_t> row_dims) {
  Buf b;
  b.group = g;
  b.name = nm;
  b.is_int = is_int;
  b.row_dims = std::move(row_dims);
  for (int64_t x : b.row_dims) b.row *= x;
  const size_t total = (size_t)(b.row * (int64_t)r.s->times.size());
  if (is_int) b.n.assign(total, 0);
  else b.d.assign(total, 0.0);
  r.bufs.push_back(std::move(b));
}

void setup_buffers(Run &r) {
  const gran_scene *s = r.s;
  const int64_t M = s->nspecies;
  add_buf(r, "stats", "collisions", 1, {});
  add_buf(r, "stats", "trials", 1, {});
  if (s->obs_temperatures) add_buf(r, "temperatures", "T", 0, {M});
  if (s->obs_msd) {
    add_buf(r, "msd", "msd", 0, {M});
    add_buf(r, "msd", "msd_total", 0, {});
  }
  if (s->obs_energy) {
    add_buf(r, "energy", "e_kin", 0, {});
    add_buf(r, "energy", "e_initial", 0, {});
    add_buf(r, "energy", "e_dissipated", 0, {});
  }
  if (s->obs_momentum) add_buf(r, "momentum", "p", 0, {3});
  if (s->obs_collision_counts) add_buf(r, "collision_counts", "counts", 1, {M, M});
  if (s->obs_sonine_a2) add_buf(r, "sonine_a2", "a2", 0, {M});
  if (s->obs_veldist) add_buf(r, "velocity_distribution", "pdf", 0, {M, s->vd_bins});
}

/* Speed histogram of c = |v - u_k| / sqrt(2 T_k / m_k) per species (gran_speed_histogram),
 * normalised by N_k dc. */
int record_veldist(Run &r, double *row) {
  const gran_scene *s = r.s;
  const int64_t M = s->nspecies, B = s->vd_bins;
  const gran_particles *p = nullptr;
  std::vector<int64_t> off((size_t)M + 1);
  std::vector<double> T((size_t)M);
  GRAN_CALL(gran_dsmc_particles(r.sim, &p));
  GRAN_CALL(gran_dsmc_species_offsets(r.sim, off.data()));
  GRAN_CALL(gran_dsmc_temperatures(r.sim, T.data()));
  for (int64_t k = 0; k < M; k++) {
    double *h = row + k * B;
    std::fill(h, h + B, 0.0);
    const int64_t n = off[(size_t)k + 1] - off[(size_t)k];
    if (n <= 0 || !(T[(size_t)k] > 0)) continue;
    const double scale = std::sqrt(2.0 * T[(size_t)k] / s->mass[(size_t)k]);
    GRAN_CALL(gran_speed_histogram(n, p->v + 3 * off[(size_t)k], scale, B, s->vd_cmax, h, nullptr));
  }
  return GRAN_SUCCESS;
}

int record(Run &r, int64_t i) {
  const int64_t M = r.s->nspecies;
  gran_dsmc_stats st;
  GRAN_CALL(gran_dsmc_get_stats(r.sim, &st));
  for (auto &b : r.bufs) {
    double *d = b.is_int ? nullptr : b.d.data() + i * b.row;
    int64_t *n = b.is_int ? b.n.data() + i * b.row : nullptr;
    const std::string &g = b.group, &nm = b.name;
    if (g == "stats") {
      n[0] = nm == "collisions" ? st.collisions : st.trials;
    } else if (g == "temperatures") {
      GRAN_CALL(gran_dsmc_temperatures(r.sim, d));
    } else if (g == "msd" && nm == "msd") {
      double total = 0;
      GRAN_CALL(gran_dsmc_msd(r.sim, d, &total));
      r.buf("msd", "msd_total").d[(size_t)i] = total;
    } else if (g == "energy" && nm == "e_kin") {
      double e, e0, ed;
      GRAN_CALL(gran_dsmc_energy(r.sim, &e, &e0, &ed));
      d[0] = e;
      r.buf("energy", "e_initial").d[(size_t)i] = e0;
      r.buf("energy", "e_dissipated").d[(size_t)i] = ed;
    } else if (g == "momentum") {
      GRAN_CALL(gran_dsmc_momentum(r.sim, d));
    } else if (g == "collision_counts") {
      GRAN_CALL(gran_dsmc_collision_counts(r.sim, n));
    } else if (g == "sonine_a2") {
      GRAN_CALL(gran_dsmc_sonine_a2(r.sim, d));
    } else if (g == "velocity_distribution") {
      GRAN_CALL(record_veldist(r, d));
    }
  }
  /* a non-finite observable is an error, not a value in the file (NaN is allowed only where it
   * means "no particles": per-species values of an empty species) */
  std::vector<int64_t> counts((size_t)M);
  GRAN_CALL(gran_dsmc_counts(r.sim, counts.data()));
  for (const auto &b : r.bufs) {
    if (b.is_int) continue;
    const double *d = b.d.data() + i * b.row;
    const bool per_species = !b.row_dims.empty() && b.row_dims[0] == M;
    for (int64_t e = 0; e < b.row; e++) {
      if (std::isfinite(d[e])) continue;
      const int64_t k = per_species ? e / (b.row / M) : -1;
      if (std::isnan(d[e]) && k >= 0 && counts[(size_t)k] == 0) continue;
      return GRAN_ERROR(GRAN_ERR_NUMERIC, "observable '%s/%s' is %g at t = %g (element %" PRId64 "): the run stops here",
                        b.group.c_str(), b.name.c_str(), d[e], r.s->times[(size_t)i], e);
    }
  }
  return GRAN_SUCCESS;
}

/* mkdir -p of the folder holding `path` */
int make_parent(const std::string &path) {
  size_t s = path.find_last_of('/');
  if (s == std::string::npos || s == 0) return GRAN_SUCCESS;
  std::string dir = path.substr(0, s);
  for (size_t i = 1; i <= dir.size(); i++) {
    if (i == dir.size() || dir[i] == '/') {
      std::string d = dir.substr(0, i);
      if (mkdir(d.c_str(), 0777) != 0 && errno != EEXIST)
        return GRAN_ERROR(GRAN_ERR_IO, "cannot create folder '%s' for '%s': %s", d.c_str(), path.c_str(),
                          std::strerror(errno));
    }
  }
  return GRAN_SUCCESS;
}

/* Writability check before any work: create PATH.tmp, then remove it. */
int check_writable(const std::string &path, const char *what) {
  GRAN_CALL(make_parent(path));
  std::string tmp = path + ".tmp";
  FILE *f = std::fopen(tmp.c_str(), "wb");
  if (!f) return GRAN_ERROR(GRAN_ERR_IO, "%s '%s' is not writable: %s", what, tmp.c_str(), std::strerror(errno));
  std::fclose(f);
  std::remove(tmp.c_str());
  struct stat sb;
  if (stat(path.c_str(), &sb) == 0 && S_ISDIR(sb.st_mode))
    return GRAN_ERROR(GRAN_ERR_IO, "%s '%s' is a folder", what, path.c_str());
  return GRAN_SUCCESS;
}

/* Output, checkpoint and scene file must be three different files: compared by identity (two
 * spellings of one file are one file), after the folders exist. */
int check_distinct(const Run &r) {
  const std::string &scene = r.s->name;
  GRAN_CHECK(!gran_io_same_file_(r.out, r.ckpt), GRAN_ERR_ARG,
             "the output '%s' and the checkpoint '%s' are the same file", r.out.c_str(), r.ckpt.c_str());
  GRAN_CHECK(!gran_io_same_file_(r.out, scene), GRAN_ERR_ARG,
             "the output '%s' is the scene file '%s': it would overwrite the scene", r.out.c_str(), scene.c_str());
  GRAN_CHECK(!gran_io_same_file_(r.ckpt, scene), GRAN_ERR_ARG,
             "the checkpoint '%s' is the scene file '%s': it would overwrite the scene", r.ckpt.c_str(), scene.c_str());
  GRAN_CHECK(!gran_io_same_file_(r.out + ".tmp", r.ckpt) && !gran_io_same_file_(r.ckpt + ".tmp", r.out),
             GRAN_ERR_ARG, "the output '%s' and the checkpoint '%s' collide through their temporary files",
             r.out.c_str(), r.ckpt.c_str());
  return GRAN_SUCCESS;
}

/* ---- HDF5 writing -------------------------------------------------------------------------- */

struct H5File {
  int64_t id = -1;
  ~H5File() { gran_h5::close_file(id); }
};
struct H5Group {
  int64_t id = -1;
  ~H5Group() { gran_h5::close_group(id); }
};

int write_root_attrs(Run &r, int64_t f, const char *file, const char *format) {
  const gran_scene *s = r.s;
  GRAN_CALL(gran_h5::attr_string(f, "format", format, file));
  GRAN_CALL(gran_h5::attr_string(f, "scene", s->text, file));
  GRAN_CALL(gran_h5::attr_string(f, "scene_file", s->name, file));
  GRAN_CALL(gran_h5::attr_string(f, "title", s->title, file));
  GRAN_CALL(gran_h5::attr_string(f, "granary_version", GRAN_VERSION_STRING, file));
  GRAN_CALL(gran_h5::attr_uint64(f, "seed", s->seed, file));
  GRAN_CALL(gran_h5::attr_string(f, "selector", s->selector == GRAN_SELECTOR_BIRD ? "bird" : "lowrank", file));
  GRAN_CALL(gran_h5::attr_int64(f, "nspecies", s->nspecies, file));
  GRAN_CALL(gran_h5::attr_double(f, "t_start", s->t_start, file));
  GRAN_CALL(gran_h5::attr_double(f, "t_end", s->t_end, file));
  return GRAN_SUCCESS;
}

/* Theory beside the simulation; a theory call that fails leaves a warning and an attribute. */
int write_theory(Run &r, int64_t f, const char *file, const std::vector<double> &tt) {
  const gran_scene *s = r.s;
  const int64_t M = s->nspecies, nt = (int64_t)tt.size();
  std::vector<int64_t> dims = {nt, M};
  if (s->obs_temperatures) {
    H5Group g;
    g.id = H5Gopen2((hid_t)f, "temperatures", H5P_DEFAULT);
    std::vector<double> T((size_t)(nt * M));
    int st = gran_theory_temperatures(r.mix, r.T0.data(), nt, tt.data(), s->theory_rtol, T.data());
    if (st == GRAN_SUCCESS) {
      GRAN_CALL(gran_h5::write_double(g.id, "T_theory", dims, T.data(), file));
    } else {
      gran_warning_add("no T_theory in the output: %s", gran_last_error_message());
      GRAN_CALL(gran_h5::attr_string(g.id, "theory_error", gran_last_error_message(), file));
    }
  }
  if (s->obs_msd) {
    H5Group g;
    g.id = H5Gopen2((hid_t)f, "msd", H5P_DEFAULT);
    std::vector<double> m((size_t)(nt * M)), mt((size_t)nt);
    const bool hcs = s->init == SCENE_INIT_HCS && s->model != GRAN_RESTITUTION_VISCOELASTIC && std::isfinite(r.tau0);
    int st = hcs ? gran_theory_msd_hcs(r.mix, r.T0.data(), r.tau0, nt, tt.data(), m.data(), mt.data())
                 : gran_theory_msd(r.mix, r.T0.data(), nt, tt.data(), s->theory_rtol, m.data(), mt.data());
    if (st == GRAN_SUCCESS) {
      GRAN_CALL(gran_h5::write_double(g.id, "msd_theory", dims, m.data(), file));
      GRAN_CALL(gran_h5::write_double(g.id, "msd_total_theory", {nt}, mt.data(), file));
      GRAN_CALL(gran_h5::attr_string(g.id, "theory", hcs ? "gran_theory_msd_hcs (Eq. 22)" : "gran_theory_msd (Eq. 4)", file));
    } else {
      gran_warning_add("no msd_theory in the output: %s", gran_last_error_message());
      GRAN_CALL(gran_h5::attr_string(g.id, "theory_error", gran_last_error_message(), file));
    }
  }
  return GRAN_SUCCESS;
}

/* TAMSD of the recorded tracer trajectories, averaged over the tracers of each species
 * (gran_tamsd_plan_*: delta^2(L) = 1/(S-L) sum_{j<S-L} |R_{j+L} - R_j|^2, Eq. 26 on the grid).
 * Lags are rounded to whole sampling intervals; /tamsd/lag holds the lags used. */
int write_tamsd(Run &r, int64_t f, const char *file) {
  const gran_scene *s = r.s;
  const int64_t M = s->nspecies, nl = (int64_t)s->tamsd_lags.size();
  int64_t ntraj = 0, ns = 0;
  const double *xyz = nullptr;
  const int32_t *sp = nullptr;
  GRAN_CALL(gran_dsmc_trajectories(r.sim, &ntraj, &ns, &xyz, &sp));
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
  std::vector<double> xs, full((size_t)Lmax + 1);
  int st = GRAN_SUCCESS;
  for (int64_t k = 0; k < M && st == GRAN_SUCCESS; k++) {
    xs.clear();
    for (int64_t j = 0; j < ntraj; j++)
      if (sp[j] == k) {
        ntr[(size_t)k]++;
        xs.insert(xs.end(), xyz + j * ns * 3, xyz + (j + 1) * ns * 3);
      }
    if (!ntr[(size_t)k]) {
      for (int64_t l = 0; l < nl; l++) ta[(size_t)(l * M + k)] = NAN;
      continue;
    }
    st = gran_tamsd_plan_execute(plan, ntr[(size_t)k], xs.data(), Lmax + 1, full.data());
    for (int64_t l = 0; l < nl && st == GRAN_SUCCESS; l++) ta[(size_t)(l * M + k)] = full[(size_t)L[(size_t)l]];
  }
  gran_tamsd_plan_destroy(&plan);
  GRAN_CALL(st);
  H5Group g;
  GRAN_CALL(gran_h5::make_group(f, "tamsd", &g.id, file));
  const double t_meas = s->tamsd_dt * (double)(ns - 1);
  GRAN_CALL(gran_h5::write_double(g.id, "lag", {nl}, lag.data(), file));
  GRAN_CALL(gran_h5::write_double(g.id, "tamsd", {nl, M}, ta.data(), file));
  GRAN_CALL(gran_h5::write_int64(g.id, "tracers", {M}, ntr.data(), file));
  GRAN_CALL(gran_h5::attr_double(g.id, "t_meas", t_meas, file));
  GRAN_CALL(gran_h5::attr_double(g.id, "dt", s->tamsd_dt, file));
  GRAN_CALL(gran_h5::attr_int64(g.id, "samples", ns, file));
  if (s->obs_theory) {
    std::vector<double> th((size_t)(nl * M));
    /* the theory averaged over the same sample grid as the simulation (Eq. 27 is its dt -> 0 limit) */
    int st = std::isfinite(r.tau0) ? gran_theory_tamsd_sampled(r.mix, r.T0.data(), r.tau0, s->tamsd_dt, ns, nl, L.data(),
                                                               s->theory_rtol, th.data())
                                   : GRAN_ERROR(GRAN_ERR_DOMAIN, "tau0 of the HCS is not finite");
    if (st == GRAN_SUCCESS) {
      GRAN_CALL(gran_h5::write_double(g.id, "tamsd_theory", {nl, M}, th.data(), file));
      GRAN_CALL(gran_h5::attr_string(g.id, "theory",
                                     "gran_theory_tamsd_sampled: Eq. 26 summed over the sample times of the simulation", file));
    } else {
      gran_warning_add("no tamsd_theory in the output: %s", gran_last_error_message());
      GRAN_CALL(gran_h5::attr_string(g.id, "theory_error", gran_last_error_message(), file));
    }
  }
  return GRAN_SUCCESS;
}

/* The output file with the first `nt` output times (all of them when the run finished; fewer when
 * it was stopped: attribute complete = 0, and no TAMSD, whose trajectories are not complete). */
/* Units and a description for every dataset of the output file ("group/name"; "*" matches any
 * group). Units are those of the scene: masses in units of its m, lengths of its sigma, energies
 * with k_B = 1; time in the unit that follows from them. */
struct DatasetDoc {
  const char *path, *units, *description;
};
const DatasetDoc kDocs[] = {
    {"time", "time", "output times (absolute; the run starts at the scene's t_start)"},
    {"*/time", "time", "output times of the rows of this group"},
    {"species/mass", "mass", "mass m_k of each species"},
    {"species/sigma", "length", "diameter sigma_k of each species"},
    {"species/density", "1/length^3", "number density n_k of each species (0: tracer)"},
    {"species/counts", "1", "simulated particles N_k of each species"},
    {"species/T0", "energy (k_B = 1)", "initial temperature T_k(0) of each species"},
    {"stats/collisions", "1", "accepted collisions since the start [time]"},
    {"stats/trials", "1", "candidate pairs drawn since the start [time]"},
    {"temperatures/T", "energy (k_B = 1)", "partial temperature T_k = m_k <|v - u|^2>/3 [time][species] (NaN: empty species)"},
    {"temperatures/T_theory", "energy (k_B = 1)", "kinetic theory T_k(t), seed 000 Eqs. 14-15 [time][species]"},
    {"msd/msd", "length^2", "mean squared displacement MSD_k (Eq. 45) [time][species]"},
    {"msd/msd_total", "length^2", "MSD of all particles, Eq. 3 [time]"},
    {"msd/msd_theory", "length^2", "kinetic theory MSD_k(t) (Eq. 22 in the HCS, else Eq. 4) [time][species]"},
    {"msd/msd_total_theory", "length^2", "kinetic theory of the total MSD, Eq. 3 [time]"},
    {"energy/e_kin", "energy", "total kinetic energy (1/2) sum m v^2 [time]"},
    {"energy/e_initial", "energy", "kinetic energy at the start [time]"},
    {"energy/e_dissipated", "energy", "energy dissipated in collisions so far; e_initial - e_dissipated = e_kin [time]"},
    {"momentum/p", "mass x velocity", "total momentum [time][xyz]"},
    {"collision_counts/counts", "1", "collisions per species pair since the start, i <= j used [time][i][j]"},
    {"sonine_a2/a2", "1", "Sonine coefficient a2 = (3/5)<c^4>/<c^2>^2 - 1 per species [time][species]"},
    {"velocity_distribution/pdf", "1", "density of c = |v - u| / sqrt(2 T_k/m_k) per species [time][species][bin]"},
    {"velocity_distribution/edges", "1", "bin edges of c"},
    {"velocity_distribution/pdf_maxwell", "1", "Maxwell density of c averaged over each bin"},
    {"tamsd/lag", "time", "lags (whole sampling intervals)"},
    {"tamsd/tamsd", "length^2", "time-averaged MSD over the tracers of each species (Eq. 26 on the sample grid) [lag][species]"},
    {"tamsd/tamsd_theory", "length^2", "kinetic theory of the TAMSD on the same sample grid [lag][species]"},
    {"tamsd/tracers", "1", "tracer trajectories averaged per species"},
};

herr_t annotate_cb(hid_t loc, const char *name, const H5O_info_t *info, void *op) {
  if (info->type != H5O_TYPE_DATASET) return 0;
  const char *file = static_cast<const char *>(op);
  const char *slash = std::strrchr(name, '/');
  const std::string any = std::string("*/") + (slash ? slash + 1 : name);
  for (const DatasetDoc &d : kDocs)
    if (!std::strcmp(d.path, name) || (slash && any == d.path))
      return gran_h5::describe(loc, name, d.units, d.description, file) == GRAN_SUCCESS ? 0 : -1;
  gran_error_set(GRAN_ERR_INTERNAL, __FILE__, __LINE__, __func__, "dataset '%s' of '%s' has no description", name, file);
  return -1;
}

/* units and description attributes on every dataset (an undocumented dataset is an internal error) */
int annotate(int64_t f, const char *file) {
  if (H5Ovisit((hid_t)f, H5_INDEX_NAME, H5_ITER_NATIVE, annotate_cb, (void *)file) < 0) {
    if (!gran_last_error_message()[0]) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot annotate the datasets of '%s'", file);
    return GRAN_ERR_INTERNAL;
  }
  return GRAN_SUCCESS;
}

int write_output(Run &r, const std::string &path, int64_t nt) {
  const gran_scene *s = r.s;
  const int64_t M = s->nspecies;
  const int complete = nt == (int64_t)s->times.size();
  const char *file = path.c_str();
  {
    H5File f;
    f.id = gran_h5::create_memory_file();
    GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "HDF5: cannot create the output file '%s' in memory", file);
    GRAN_CALL(write_root_attrs(r, f.id, file, kOutputFormat));
    GRAN_CALL(gran_h5::attr_int64(f.id, "complete", complete, file));
    {
      H5Group g;
      GRAN_CALL(gran_h5::make_group(f.id, "species", &g.id, file));
      std::vector<int64_t> counts((size_t)M);
      GRAN_CALL(gran_dsmc_counts(r.sim, counts.data()));
      GRAN_CALL(gran_h5::write_double(g.id, "mass", {M}, s->mass.data(), file));
      GRAN_CALL(gran_h5::write_double(g.id, "sigma", {M}, s->sigma.data(), file));
      GRAN_CALL(gran_h5::write_double(g.id, "density", {M}, s->density.data(), file));
      GRAN_CALL(gran_h5::write_int64(g.id, "counts", {M}, counts.data(), file));
      GRAN_CALL(gran_h5::write_double(g.id, "T0", {M}, r.T0.data(), file));
      GRAN_CALL(gran_h5::attr_double(g.id, "tau0", r.tau0, file));
    }
    GRAN_CALL(gran_h5::write_double(f.id, "time", {nt}, s->times.data(), file));
    for (const auto &b : r.bufs) {
      H5Group g;
      if (gran_h5::exists(f.id, b.group.c_str())) {
        g.id = H5Gopen2((hid_t)f.id, b.group.c_str(), H5P_DEFAULT);
      } else {
        GRAN_CALL(gran_h5::make_group(f.id, b.group.c_str(), &g.id, file));
        GRAN_CALL(gran_h5::write_double(g.id, "time", {nt}, s->times.data(), file));
      }
      std::vector<int64_t> dims = {nt};
      dims.insert(dims.end(), b.row_dims.begin(), b.row_dims.end());
      if (b.is_int) GRAN_CALL(gran_h5::write_int64(g.id, b.name.c_str(), dims, b.n.data(), file));
      else GRAN_CALL(gran_h5::write_double(g.id, b.name.c_str(), dims, b.d.data(), file));
    }
    if (s->obs_veldist) {
      H5Group g;
      g.id = H5Gopen2((hid_t)f.id, "velocity_distribution", H5P_DEFAULT);
      const int64_t B = s->vd_bins;
      const double dc = s->vd_cmax / (double)B;
      std::vector<double> edges((size_t)B + 1), maxw((size_t)B);
      auto F = [](double c) { return std::erf(c) - 2.0 * c / std::sqrt(M_PI) * std::exp(-c * c); };
      for (int64_t b = 0; b <= B; b++) edges[(size_t)b] = dc * (double)b;
      for (int64_t b = 0; b < B; b++) maxw[(size_t)b] = (F(edges[(size_t)b + 1]) - F(edges[(size_t)b])) / dc;
      GRAN_CALL(gran_h5::write_double(g.id, "edges", {B + 1}, edges.data(), file));
      GRAN_CALL(gran_h5::write_double(g.id, "pdf_maxwell", {B}, maxw.data(), file));
      GRAN_CALL(gran_h5::attr_string(g.id, "variable", "c = |v| / sqrt(2 T_k / m_k)", file));
    }
    if (s->obs_theory) {
      std::vector<double> tt((size_t)nt);
      for (int64_t i = 0; i < nt; i++) tt[(size_t)i] = s->times[(size_t)i] - s->t_start;
      GRAN_CALL(write_theory(r, f.id, file, tt));
    }
    if (s->obs_tamsd && complete) GRAN_CALL(write_tamsd(r, f.id, file));
    gran_clear_error();
    GRAN_CALL(annotate(f.id, file));
    return gran_h5::commit_memory_file(&f.id, path, "output file");
  }
}

int write_checkpoint(Run &r) {
  const char *file = r.ckpt.c_str();
  {
    H5File f;
    f.id = gran_h5::create_memory_file();
    GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "HDF5: cannot create the checkpoint '%s' in memory", file);
    /* the engine, then the observer state beside it */
    GRAN_CALL(gran_dsmc_checkpoint_write_h5_(r.sim, f.id, "/engine", file));
    GRAN_CALL(write_root_attrs(r, f.id, file, kCheckpointFormat));
    GRAN_CALL(gran_h5::attr_string(f.id, "output", r.out, file));
    GRAN_CALL(gran_h5::attr_int64(f.id, "next_index", r.next, file));
    H5Group g;
    GRAN_CALL(gran_h5::make_group(f.id, "observer", &g.id, file));
    for (const auto &b : r.bufs) {
      const std::string nm = b.group + "." + b.name;
      const int64_t total = b.row * (int64_t)r.s->times.size();
      if (b.is_int) GRAN_CALL(gran_h5::write_int64(g.id, nm.c_str(), {total}, b.n.data(), file));
      else GRAN_CALL(gran_h5::write_double(g.id, nm.c_str(), {total}, b.d.data(), file));
    }
    gran_h5::close_group(g.id);
    g.id = -1;
    return gran_h5::commit_memory_file(&f.id, r.ckpt, "checkpoint");
  }
}

int read_checkpoint_observer(Run &r, const char *path) {
  H5File f;
  f.id = gran_h5::open_file(path, 0);
  GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "cannot open checkpoint '%s'", path);
  int64_t next = -1;
  GRAN_CALL(gran_h5::read_attr_int64(f.id, "next_index", &next, path));
  GRAN_CHECK(next >= 0 && next <= (int64_t)r.s->times.size(), GRAN_ERR_IO,
             "checkpoint '%s': next_index %" PRId64 " out of range", path, next);
  r.next = next;
  H5Group g;
  g.id = H5Gopen2((hid_t)f.id, "observer", H5P_DEFAULT);
  GRAN_CHECK(g.id >= 0, GRAN_ERR_IO, "checkpoint '%s' has no /observer group", path);
  for (auto &b : r.bufs) {
    const std::string nm = b.group + "." + b.name;
    const size_t total = (size_t)(b.row * (int64_t)r.s->times.size());
    if (b.is_int) {
      std::vector<int64_t> v;
      GRAN_CALL(gran_h5::read_int64(g.id, nm.c_str(), v, nullptr, path));
      GRAN_CHECK(v.size() == total, GRAN_ERR_IO, "checkpoint '%s': '%s' has the wrong size", path, nm.c_str());
      b.n = v;
    } else {
      std::vector<double> v;
      GRAN_CALL(gran_h5::read_double(g.id, nm.c_str(), v, nullptr, path));
      GRAN_CHECK(v.size() == total, GRAN_ERR_IO, "checkpoint '%s': '%s' has the wrong size", path, nm.c_str());
      b.d = v;
    }
  }
  return GRAN_SUCCESS;
}

int prepare(Run &r) {
  const int64_t M = r.s->nspecies;
  GRAN_CALL(gran_scene_mixture(r.s, &r.mix));
  r.T0.assign((size_t)M, 0.0);
  GRAN_CALL(gran_scene_T0_(r.s, r.mix, r.T0.data(), &r.tau0));
  double inv_tc = NAN;
  if (gran_theory_collision_rate1(r.mix, r.T0.data(), &inv_tc) == GRAN_SUCCESS && inv_tc > 0) r.tau_c0 = 1.0 / inv_tc;
  gran_clear_error();
  setup_buffers(r);
  return GRAN_SUCCESS;
}

/* Work (collisions, up to a constant factor) done from t_start to t, from the kinetic theory's
 * collision rate, for the progress line and its ETA: every collision rate follows sqrt(T), and
 * sqrt(T) ~ 1/(1 + t/tau0) in the HCS (Haff), ~ (1 + t/tau_c)^(-5/6) for viscoelastic cooling
 * (T ~ t^(-5/3)), and stays constant for elastic gases. Output times are often log-spaced: counting
 * them instead gave an ETA of 8 s with 37 s left. */
double work_to(const Run &r, double t) {
  const double dt = std::max(t - r.s->t_start, 0.0);
  if (r.s->model == GRAN_RESTITUTION_VISCOELASTIC && r.tau_c0 > 0)
    return 6.0 * r.tau_c0 * (std::pow(1.0 + dt / r.tau_c0, 1.0 / 6.0) - 1.0);
  if (std::isfinite(r.tau0) && r.tau0 > 0) return r.tau0 * std::log1p(dt / r.tau0);
  return dt;
}

/* The loop shared by run and resume: record rows next..ntimes-1, checkpoint, finish. */
int drive(Run &r, const gran_run_control *ctl, gran_run_result *res) {
  const gran_scene *s = r.s;
  const int64_t nt = (int64_t)s->times.size();
  const double w0 = now_s();
  double w_ckpt = w0;
  gran_dsmc_stats st;
  GRAN_CALL(gran_dsmc_get_stats(r.sim, &st));
  const int64_t coll0 = st.collisions;
  int64_t nckpt = 0;
  gran_run_result rr = {};
  auto fill = [&](int finished) {
    gran_dsmc_stats x;
    if (gran_dsmc_get_stats(r.sim, &x) == GRAN_SUCCESS) {
      rr.collisions = x.collisions;
      rr.time = x.time;
    }
    rr.finished = finished;
    rr.checkpoints = nckpt;
    rr.wall_seconds = now_s() - w0;
    if (res) *res = rr;
  };
  const int64_t first = r.next;
  while (r.next < nt) {
    const int64_t i = r.next;
    GRAN_CALL(gran_dsmc_advance(r.sim, s->times[(size_t)i]));
    GRAN_CALL(record(r, i));
    r.next = i + 1;
    int stop = 0;
    if (ctl && ctl->progress) {
      gran_dsmc_stats x;
      GRAN_CALL(gran_dsmc_get_stats(r.sim, &x));
      gran_run_progress p = {};
      const double wall = now_s() - w0;
      p.time = x.time;
      p.t_start = s->t_start;
      p.t_end = s->t_end;
      const double w_end = work_to(r, s->t_end), w_now = work_to(r, x.time);
      const double w_first = work_to(r, first > 0 ? s->times[(size_t)first - 1] : s->t_start);
      p.fraction = w_end > 0 ? std::min(1.0, w_now / w_end) : (double)r.next / (double)nt;
      p.wall_seconds = wall;
      p.collisions = x.collisions;
      p.collisions_per_second = wall > 0 ? (double)(x.collisions - coll0) / wall : 0.0;
      /* the wall time per unit of work so far, times the work left */
      p.eta_seconds = w_now > w_first && wall > 0 ? wall * (w_end - w_now) / (w_now - w_first) : -1.0;
      if (r.next >= nt) p.eta_seconds = 0.0;
      p.output_index = r.next;
      p.noutputs = nt;
      p.checkpoints = nckpt;
      stop = ctl->progress(&p, ctl->progress_params) != 0;
    }
    if (r.next >= nt || r.ckpt.empty()) {
      if (stop) {
        GRAN_CALL(write_output(r, r.out, r.next)); /* what was recorded so far */
        fill(0);
        return GRAN_SUCCESS;
      }
      continue;
    }
    const bool due = stop || (s->checkpoint_every > 0 && r.next % s->checkpoint_every == 0) ||
                     (s->checkpoint_interval > 0 && now_s() - w_ckpt >= s->checkpoint_interval);
    if (due) {
      GRAN_CALL(write_checkpoint(r));
      w_ckpt = now_s();
      nckpt++;
      if (stop || (ctl && ctl->stop_after_checkpoints > 0 && nckpt >= ctl->stop_after_checkpoints)) {
        if (stop) GRAN_CALL(write_output(r, r.out, r.next)); /* what was recorded so far */
        fill(0);
        return GRAN_SUCCESS;
      }
    }
  }
  double t = 0;
  GRAN_CALL(gran_dsmc_time(r.sim, &t));
  if (t < s->t_end) GRAN_CALL(gran_dsmc_advance(r.sim, s->t_end));
  GRAN_CALL(write_output(r, r.out, nt));
  if (!r.ckpt.empty() && !s->keep_checkpoint) std::remove(r.ckpt.c_str());
  fill(1);
  return GRAN_SUCCESS;
}

}  // namespace

/** @brief Run a scene to its end, writing HDF5 output and checkpoints.
 *  @param[in] output     NULL: the scene's [output] path
 *  @param[in] checkpoint NULL: the scene's; "": no checkpoints
 *  @param[in] ctl        may be NULL  @param[out] result may be NULL */
GRAN_EXTERN int gran_scene_run(const gran_scene *scene, const char *output, const char *checkpoint,
                               const gran_run_control *ctl, gran_run_result *result) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK(!ctl || ctl->stop_after_checkpoints >= 0, GRAN_ERR_ARG,
             "argument 'ctl->stop_after_checkpoints' is negative (%" PRId64 ")", ctl ? ctl->stop_after_checkpoints : 0);
  GRAN_TRY {
    Run r;
    r.s = scene;
    r.out = output ? output : scene->output_path;
    /* the checkpoint follows the output unless the scene or the caller names it */
    r.ckpt = checkpoint ? checkpoint
                        : (output && !scene->checkpoint_explicit && !scene->checkpoint_path.empty()) ? r.out + ".ckpt"
                                                                                                     : scene->checkpoint_path;
    GRAN_CHECK(!r.out.empty(), GRAN_ERR_ARG, "argument 'output' is empty");
    if (result) *result = gran_run_result{};
    GRAN_CALL(check_writable(r.out, "output file"));
    if (!r.ckpt.empty()) GRAN_CALL(check_writable(r.ckpt, "checkpoint file"));
    GRAN_CALL(check_distinct(r));
    GRAN_CALL(prepare(r));
    GRAN_CALL(gran_scene_dsmc(scene, r.mix, &r.sim));
    return drive(r, ctl, result);
  }
  GRAN_CATCH
}

/** @brief Continue a run from its checkpoint; bit for bit the uninterrupted run.
 *  @param[in] output NULL: the output path stored in the checkpoint */
GRAN_EXTERN int gran_scene_resume(const char *checkpoint, const char *output, const gran_run_control *ctl,
                                  gran_run_result *result) {
  GRAN_CHECK_PTR(checkpoint);
  GRAN_CHECK(!ctl || ctl->stop_after_checkpoints >= 0, GRAN_ERR_ARG,
             "argument 'ctl->stop_after_checkpoints' is negative (%" PRId64 ")", ctl ? ctl->stop_after_checkpoints : 0);
  GRAN_TRY {
    Run r;
    std::string text, name, format, out;
    /* the whole file against its checksum before HDF5 parses any of it */
    GRAN_CALL(gran_h5::verify_file(checkpoint, "checkpoint"));
    {
      H5File f;
      f.id = gran_h5::open_file(checkpoint, 0);
      GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "cannot open checkpoint '%s' (missing or not HDF5)", checkpoint);
      GRAN_CALL(gran_h5::read_attr_string(f.id, "format", format, checkpoint));
      GRAN_CHECK(format == kCheckpointFormat, GRAN_ERR_IO, "'%s' is not a granary checkpoint (format '%s')", checkpoint,
                 format.c_str());
      GRAN_CALL(gran_h5::read_attr_string(f.id, "scene", text, checkpoint));
      GRAN_CALL(gran_h5::read_attr_string(f.id, "scene_file", name, checkpoint));
      GRAN_CALL(gran_h5::read_attr_string(f.id, "output", out, checkpoint));
    }
    GRAN_CALL(gran_scene_parse_text_(text, name, &r.owned_scene));
    r.s = r.owned_scene;
    r.out = output ? output : out;
    r.ckpt = checkpoint;
    GRAN_CHECK(!r.out.empty(), GRAN_ERR_ARG, "argument 'output' is empty");
    if (result) *result = gran_run_result{};
    GRAN_CALL(check_writable(r.out, "output file"));
    GRAN_CALL(check_writable(r.ckpt, "checkpoint file"));
    GRAN_CALL(check_distinct(r));
    GRAN_CALL(prepare(r));
    GRAN_CALL(read_checkpoint_observer(r, checkpoint));
    GRAN_CALL(gran_dsmc_checkpoint_read(checkpoint, "/engine", r.mix, &r.sim));
    return drive(r, ctl, result);
  }
  GRAN_CATCH
}
