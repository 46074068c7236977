/* fuzz_checkpoint.cc - libFuzzer harness for the value checks of checkpoint readers and the engines
 * they resume. A few valid checkpoints are written once, from fixed options and seeds, all HDF5
 * after a 512-byte header "granary-file 1\nlength N\ncrc32 C\n" holding the CRC-32 of the bytes
 * after it: GSRD states (gran_srd_checkpoint_write: group /srd of named fields, options/NAME
 * among them) and run checkpoints of a low-rank, a Bird-with-aggregation, a cell-with-aggregation,
 * a cell-with-streams-by-cell (its particles' keys) and a GSRD run. The fuzz bytes pick one and edit it, value by value: elements of any dataset
 * (edge values such as NaN, inf, 1e300, -0, 2^63-1, or raw bits), a dataset one value longer or
 * shorter, numbers in the stored scene text; then the checksum is recomputed (or, 1 in 8 for a
 * GSRD state, left stale: the reader must refuse), so that the reader's value checks and the
 * resumed engine (a few steps, observed) are what the edit reaches. A checkpoint set too: the four
 * part files of a 2-D Lees-Edwards gas split 2 x 2 (srd_bricks_save_), one of them edited so, read
 * back split 3 x 1 (srd_bricks_load_) and whole (srd_state_from_parts_), each stepped and observed.
 * Every status must be a listed code with a message; nothing returned or written with GRAN_SUCCESS
 * may be inf or NaN. */
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cstddef>

#include "fuzz_common.h"
#include "srd/bricks.h"

namespace {

std::vector<std::vector<uint8_t>> g_base;   /* the valid checkpoints */
std::vector<int> g_is_h5;                   /* 1: run checkpoint, 0: GSRD state (gran_srd_checkpoint_write) */
std::vector<std::string> g_scene;           /* the scene text of a run checkpoint */

std::vector<uint8_t> slurp(const std::string &path) {
  std::vector<uint8_t> b;
  FILE *f = std::fopen(path.c_str(), "rb");
  if (!f) return b;
  uint8_t buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) b.insert(b.end(), buf, buf + n);
  std::fclose(f);
  return b;
}
void spill(const std::string &path, const std::vector<uint8_t> &b) {
  FILE *f = std::fopen(path.c_str(), "wb");
  if (!f) fz::fail("cannot write the scratch checkpoint", path.c_str());
  if (!b.empty()) std::fwrite(b.data(), 1, b.size(), f);
  std::fclose(f);
}

/* ---- GSRD states ---- */
void srd_base(int dim, int wall, int shear, int therm) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = dim;
  o.cells[0] = 4;
  o.cells[1] = 4;
  o.cells[2] = dim == 3 ? 3 : 1;
  o.n0 = 3;
  o.dt = 0.5;
  o.eps = 0.9;
  o.sigma = 0.2;
  o.seed = 5;
  o.threads = 1;
  o.thermostat = therm;
  if (wall) {
    o.wall_axis = dim - 1;
    o.wall_rule = 1;
    o.accel[dim - 1] = -0.01;
    o.vib_amp = 0.1;
    o.vib_omega = 0.3;
  }
  if (shear) o.shear_rate = 0.05;
  gran_srd *s = nullptr;
  const std::string p = fz::scratch() + "/base.gsrd";
  if (gran_srd_create(&o, &s) || gran_srd_advance(s, 3) || gran_srd_checkpoint_write(s, p.c_str(), "/srd"))
    fz::fail("cannot write a GSRD base checkpoint", gran_last_error_message());
  gran_srd_destroy(&s);
  g_base.push_back(slurp(p));
  g_is_h5.push_back(0);
  g_scene.push_back("");
  std::remove(p.c_str());
}

/* ---- checkpoint sets: the part files of a split gas ---- */
gran_srd_options g_part_opt;
std::vector<std::vector<uint8_t>> g_parts; /* the 4 parts of generation 1, after kPartStep steps */
constexpr int64_t kPartStep = 5;
std::vector<std::string> part_paths() {
  std::vector<std::string> p;
  for (int b = 0; b < 4; ++b) p.push_back(fz::scratch() + "/set.part-" + std::to_string(b));
  return p;
}
void parts_base() {
  gran_srd_options &o = g_part_opt;
  gran_srd_options_default(&o);
  o.dim = 2;
  o.cells[0] = 6;
  o.cells[1] = 5;
  o.n0 = 3;
  o.dt = 0.5;
  o.eps = 0.9;
  o.sigma = 0.2;
  o.seed = 5;
  o.threads = 1;
  o.shear_rate = 0.05;
  o.sort_every = 3;
  o.creation = GRAN_SRD_CREATE_CELLS;
  const int pg[3] = {2, 2, 1};
  srd_bricks_state *st = nullptr;
  const std::vector<std::string> p = part_paths();
  const char *pp[4] = {p[0].c_str(), p[1].c_str(), p[2].c_str(), p[3].c_str()};
  if (srd_bricks_open_(&o, pg, nullptr, &st) || srd_bricks_step_(st, kPartStep) || srd_bricks_save_(st, pp, 1))
    fz::fail("cannot write the base checkpoint set", gran_last_error_message());
  srd_bricks_close_(&st);
  for (const std::string &q : p) {
    g_parts.push_back(slurp(q));
    std::remove(q.c_str());
  }
}
void check_bricks(srd_bricks_state *st) {
  for (int r = 0; r < 2; ++r) {
    if (fz::check(srd_bricks_step_(st, 2), "srd_bricks_step_ (loaded)")) return;
    gran_srd_obs o;
    if (fz::check(srd_bricks_observe_(st, &o), "srd_bricks_observe_ (loaded)")) return;
    const double v[] = {o.temperature, o.theta_cells, o.energy, o.ledger_error, o.e_kin, o.mach, o.sigma_rho, o.a2,
                        o.stress_xy};
    for (double x : v) fz::finite_or_fail(x, "srd_bricks_observe_ (loaded)");
  }
}

/* ---- run checkpoints (HDF5) ---- */
int stop_first(const gran_run_progress *p, void *params) {
  (void)p, (void)params;
  return 1;
}

const char *kScenes[] = {
    /* low-rank, two species, trajectories and collision counts */
    "[mixture]\nnspecies = 2\nmass = [1.0, 4.0]\ndensity = [0.1, 0.02]\n[restitution]\neps = 0.8\n"
    "[engine]\ncounts = [40, 10]\nseed = 3\nt_end = 1.0\n[observables]\ntimes = [0.25, 0.5, 1.0]\n"
    "collision_counts = true\nsonine_a2 = true\ntamsd = { tracers = 2, dt = 0.25, samples = 5 }\n",
    /* Bird with aggregation and binary fragmentation */
    "[mixture]\nnspecies = 4\nm1 = 1.0\nsigma1 = 1.0\ndensity_law = { n1 = 0.05, theta = 3.0 }\n[restitution]\n"
    "eps = 0.9\n[initial]\ntemperatures = \"equal\"\nT_mean = 1.0\n[engine]\nselector = \"bird\"\nvolume = 2000\n"
    "seed = 7\nt_end = 1.0\n[aggregation]\ne_agg = 1.0\ne_frag = 3.0\neps_f = 0.7\nfrag_law = \"binary\"\n"
    "[observables]\ntimes = [0.25, 0.5, 1.0]\nmsd = false\n",
    /* cell selector with aggregation and a bath */
    "[mixture]\nnspecies = 4\nm1 = 1.0\nsigma1 = 1.0\ndensity_law = { n1 = 0.05, theta = 400.0 }\n[restitution]\n"
    "eps = 0.9\n[initial]\ntemperatures = \"equal\"\nT_mean = 1.0\n[engine]\nselector = \"cell\"\nvolume = 4000\n"
    "seed = 7\nt_end = 1.0\n[cell]\ncells = 2\ndt = 0.1\ne_agg = 1.0\ne_frag = 3.0\neps_f = 0.7\nheat_rate = 0.01\n"
    "bath_density = 0.01\nbath_mass = 0.5\nbath_T = 1.0\nbath_sigma = 0.5\n[observables]\ntimes = [0.2, 0.5, 1.0]\n"
    "msd = false\n",
    /* cell selector with streams by cell (the particles' keys), displacements, a thermostat and a bath */
    "[mixture]\nnspecies = 2\nmass = [1.0, 2.0]\ndensity = [0.03, 0.02]\n[restitution]\neps = 0.8\n[engine]\n"
    "selector = \"cell\"\nvolume = 3000\nseed = 5\nt_end = 1.0\n[cell]\ncells = 3\ndt = 0.1\nheat_rate = 0.01\n"
    "bath_density = 0.01\nstreams = \"cells\"\n[observables]\ntimes = [0.2, 0.5, 1.0]\n",
    /* GSRD 2-D with walls, gravity and snapshots (its state group /engine) */
    "[engine]\ntype = \"srd\"\ndimension = 2\ncells = [6, 5]\nn0 = 4\ndt = 0.5\nalpha = 120\neps = 0.9\nsigma = 0.2\n"
    "T0 = 1.0\nsteps = 8\nseed = 3\nthreads = 1\n[boundaries]\nwalls = {axis = \"y\", rule = \"slip\"}\n[forces]\n"
    "gravity = [0, -0.01]\n[observables]\nevery = 2\nsonine_a2 = true\nsnapshots = {every = 2}\n",
};

void h5_base(const char *text) {
  gran_scene *s = nullptr;
  const std::string out = fz::scratch() + "/base.h5", ck = fz::scratch() + "/base.ckpt";
  gran_run_control ctl = {0, stop_first, nullptr};
  if (gran_scene_parse(text, "base.toml", &s) || gran_scene_run(s, out.c_str(), ck.c_str(), &ctl, nullptr))
    fz::fail("cannot write a run base checkpoint", gran_last_error_message());
  gran_scene_destroy(&s);
  g_base.push_back(slurp(ck));
  g_is_h5.push_back(1);
  g_scene.push_back(text);
  fz::clean_scratch();
}

const size_t kUserBlock = 512;
void h5_header(std::vector<uint8_t> &b) {
  if (b.size() < kUserBlock) return;
  const uLong c = crc32(crc32(0L, Z_NULL, 0), b.data() + kUserBlock, (uInt)(b.size() - kUserBlock));
  char head[kUserBlock];
  std::memset(head, 0, sizeof head);
  std::snprintf(head, sizeof head, "granary-file 1\nlength %zu\ncrc32 %08lx\n", b.size(), (unsigned long)c);
  std::memcpy(b.data(), head, kUserBlock);
}

/* the datasets of the file in name order */
herr_t list_ds(hid_t, const char *name, const H5O_info_t *info, void *op) {
  if (info->type == H5O_TYPE_DATASET) ((std::vector<std::string> *)op)->push_back(name);
  return 0;
}

/* dataset `name` replaced by one of its own type one value longer (its last value repeated) or
 * shorter */
void h5_resize(hid_t f, const std::string &name, hid_t ty, hssize_t np, bool longer) {
  const size_t es = H5Tget_size(ty);
  const hssize_t m = longer ? np + 1 : np - 1;
  if (np <= 0 || m < 0 || es == 0 || es > 16) return;
  std::vector<uint8_t> v((size_t)(np + 1) * es);
  hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const bool ok = d >= 0 && H5Dread(d, ty, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0;
  if (d >= 0) H5Dclose(d);
  if (!ok || H5Ldelete(f, name.c_str(), H5P_DEFAULT) < 0) return;
  std::memcpy(&v[(size_t)np * es], &v[(size_t)(np - 1) * es], es);
  hsize_t dim = (hsize_t)m;
  hid_t s2 = H5Screate_simple(1, &dim, nullptr);
  hid_t d2 = H5Dcreate2(f, name.c_str(), ty, s2, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (d2 >= 0) {
    if (m > 0) H5Dwrite(d2, ty, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Dclose(d2);
  }
  H5Sclose(s2);
}

/* one element of one dataset: an edge value or raw bits of its class; with `resize`, sometimes the
 * dataset one value longer or shorter instead */
void h5_dataset_edit(hid_t f, const std::vector<std::string> &ds, fz::Bytes &in, bool resize) {
  if (ds.empty()) return;
  const std::string &name = ds[in.u8() % ds.size()];
  hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  if (d < 0) return;
  hid_t ty = H5Dget_type(d), sp = H5Dget_space(d);
  const hssize_t np = H5Sget_simple_extent_npoints(sp);
  const H5T_class_t cl = H5Tget_class(ty);
  if (resize && H5Sget_simple_extent_ndims(sp) == 1 && in.u8() < 64) {
    H5Dclose(d);
    d = -1;
    h5_resize(f, name, ty, np, in.u8() & 1);
  } else if (np > 0 && (cl == H5T_FLOAT || cl == H5T_INTEGER)) {
    hsize_t at = (hsize_t)(((uint32_t)in.u16() << 16 | in.u16()) % (uint64_t)np), one = 1;
    /* the element in the dataset's own row-major order */
    const int rank = H5Sget_simple_extent_ndims(sp);
    std::vector<hsize_t> dims((size_t)std::max(rank, 1)), pos((size_t)std::max(rank, 1), 0);
    H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
    for (int k = rank - 1; k >= 0; --k) {
      pos[(size_t)k] = at % dims[(size_t)k];
      at /= dims[(size_t)k];
    }
    std::vector<hsize_t> cnt((size_t)std::max(rank, 1), 1);
    H5Sselect_hyperslab(sp, H5S_SELECT_SET, pos.data(), nullptr, cnt.data(), nullptr);
    hid_t ms = H5Screate_simple(1, &one, nullptr);
    const uint8_t c = in.u8();
    if (cl == H5T_FLOAT) {
      double v = c < 160 ? in.edge_double() : c < 220 ? (double)in.edge_int() : in.raw_double();
      H5Dwrite(d, H5T_NATIVE_DOUBLE, ms, sp, H5P_DEFAULT, &v);
    } else {
      int64_t v = c < 180 ? in.edge_int() : c < 220 ? (int64_t)(int8_t)in.u8() : (int64_t)in.u64();
      H5Dwrite(d, H5T_NATIVE_INT64, ms, sp, H5P_DEFAULT, &v); /* converted (clipped) to the stored type */
    }
    H5Sclose(ms);
  }
  H5Sclose(sp);
  H5Tclose(ty);
  if (d >= 0) H5Dclose(d);
}

/* one number of the stored scene text replaced by an edge value (TOML spellings) */
/* Replaces one number of the stored scene text by an edge value; *text: the text as stored. */
void h5_scene_edit(hid_t f, fz::Bytes &in, std::string *stored) {
  if (H5Aexists(f, "scene") <= 0) return;
  hid_t a = H5Aopen(f, "scene", H5P_DEFAULT);
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  char *p = nullptr;
  std::string text;
  if (a >= 0 && H5Aread(a, t, &p) >= 0 && p) text = p;
  if (p) H5free_memory(p);
  if (a >= 0) H5Aclose(a);
  const auto nums = fz::toml_numbers(text.data(), text.size());
  if (!nums.empty()) {
    const auto &r = nums[in.u8() % nums.size()];
    text.replace(r.first, r.second - r.first, fz::toml_edge(in.u8()));
    H5Adelete(f, "scene");
    hid_t s = H5Screate(H5S_SCALAR);
    a = H5Acreate2(f, "scene", t, s, H5P_DEFAULT, H5P_DEFAULT);
    const char *q = text.c_str();
    if (a >= 0) H5Awrite(a, t, &q), H5Aclose(a);
    H5Sclose(s);
    *stored = text;
  }
  H5Tclose(t);
}

/* The stored scene within the harness's caps (the resume replays it: a scene of 1e6 species is a
 * valid scene whose theory alone takes hours, which the library says with a warning; not a
 * finding). Scenes that do not parse are resumed: the resume must refuse them. */
constexpr int64_t kMaxSpecies = 64, kMaxTimes = 2000; /* those of fuzz_run_scene */
bool scene_small(const std::string &text) {
  if (text.empty()) return true;
  gran_scene *s = nullptr;
  if (gran_scene_parse(text.c_str(), "stored.toml", &s) != GRAN_SUCCESS) {
    gran_clear_error();
    return true;
  }
  int64_t M = 0, nt = 0, nl = 0;
  double t0 = 0, t1 = 0;
  const bool ok = gran_scene_sizes(s, &M, &nt, &nl, &t0, &t1) == GRAN_SUCCESS && M <= kMaxSpecies && nt <= kMaxTimes &&
                  nl <= kMaxTimes;
  gran_scene_destroy(&s);
  gran_clear_error();
  return ok;
}

void check_srd(gran_srd *srd, fz::Bytes &in) {
  const int64_t steps = 1 + in.u8() % 3;
  for (int r = 0; r < 2; ++r) {
    if (fz::check(gran_srd_advance(srd, steps), "gran_srd_advance (resumed)")) return;
    gran_srd_obs o;
    if (fz::check(gran_srd_observe(srd, &o), "gran_srd_observe (resumed)")) return;
    const double v[] = {o.time, o.temperature, o.theta_cells, o.energy, o.e_initial, o.e_collisions, o.e_external,
                        o.ledger_error, o.momentum[0], o.momentum[1], o.momentum[2], o.e_kin, o.mach, o.sigma_rho,
                        o.a2, o.stress_xy, o.stress_kin};
    static const char *names[] = {"time", "temperature", "theta_cells", "energy", "e_initial", "e_collisions",
                                  "e_external", "ledger_error", "momentum[0]", "momentum[1]", "momentum[2]",
                                  "e_kin", "mach", "sigma_rho", "a2", "stress_xy", "stress_kin"};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k) {
      char b[64];
      std::snprintf(b, sizeof b, "gran_srd_observe %s (resumed)", names[k]);
      fz::finite_or_fail(v[k], b);
    }
    if (!(o.dt_max >= 0)) fz::fail("gran_srd_observe dt_max (resumed) is NaN or negative", "");
  }
}

void check_dsmc(const std::string &scene, const std::string &path) {
  gran_scene *s = nullptr;
  gran_mixture *mix = nullptr;
  if (gran_scene_parse(scene.c_str(), "base.toml", &s) == GRAN_SUCCESS && gran_scene_mixture(s, &mix) == GRAN_SUCCESS) {
    gran_dsmc *sim = nullptr;
    if (!fz::check(gran_dsmc_checkpoint_read(path.c_str(), "/engine", mix, &sim), "gran_dsmc_checkpoint_read")) {
      int64_t M = 0;
      gran_mixture_nspecies(mix, &M);
      std::vector<int64_t> n((size_t)M);
      std::vector<double> T((size_t)M);
      for (int r = 0; r < 3; ++r) {
        if (fz::check(gran_dsmc_advance_collisions(sim, 100), "gran_dsmc_advance_collisions (resumed)")) break;
        gran_dsmc_stats ss;
        if (!fz::check(gran_dsmc_get_stats(sim, &ss), "gran_dsmc_get_stats")) fz::finite_or_fail(ss.time, "time (resumed)");
        if (!fz::check(gran_dsmc_counts(sim, n.data()), "gran_dsmc_counts") &&
            !fz::check(gran_dsmc_temperatures(sim, T.data()), "gran_dsmc_temperatures"))
          for (int64_t k = 0; k < M; ++k)
            if (n[(size_t)k] > 0) fz::finite_or_fail(T[(size_t)k], "gran_dsmc_temperatures (resumed, non-empty)");
        double e[3];
        if (!fz::check(gran_dsmc_energy(sim, &e[0], &e[1], &e[2]), "gran_dsmc_energy"))
          for (double x : e) fz::finite_or_fail(x, "gran_dsmc_energy (resumed)");
      }
      gran_dsmc_destroy(&sim);
    }
  }
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fz::setup();
  if (g_base.empty()) {
    srd_base(2, 0, 0, 0);
    srd_base(3, 1, 0, 1);
    srd_base(2, 0, 1, 2);
    for (const char *t : kScenes) h5_base(t);
    parts_base();
  }
  fz::Bytes in(data, size);
  const size_t which = in.u8() % (g_base.size() + 1);
  if (which == g_base.size()) { /* the checkpoint set: one part edited */
    const uint8_t flags = in.u8();
    const int victim = in.u8() % 4, nedit = 1 + in.u8() % 6;
    const std::vector<std::string> p = part_paths();
    for (int b = 0; b < 4; ++b) spill(p[(size_t)b], g_parts[(size_t)b]);
    hid_t f = H5Fopen(p[(size_t)victim].c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (f < 0) fz::fail("the base part does not open in HDF5", p[(size_t)victim].c_str());
    std::vector<std::string> ds;
    H5Ovisit(f, H5_INDEX_NAME, H5_ITER_INC, list_ds, &ds);
    for (int e = 0; e < nedit; ++e) h5_dataset_edit(f, ds, in, flags & 1);
    H5Fclose(f);
    std::vector<uint8_t> b = slurp(p[(size_t)victim]);
    if ((flags & 0x0e) != 0x0e) h5_header(b); /* else (1 in 8) stale: the reader must refuse */
    spill(p[(size_t)victim], b);
    const char *pp[4] = {p[0].c_str(), p[1].c_str(), p[2].c_str(), p[3].c_str()};
    const int pg[3] = {3, 1, 1};
    srd_bricks_state *st = nullptr;
    if (!fz::check(srd_bricks_load_(&g_part_opt, pg, nullptr, pp, 4, 0, 1, kPartStep, &st, nullptr), "srd_bricks_load_"))
      check_bricks(st);
    srd_bricks_close_(&st);
    gran_srd *srd = nullptr;
    if (!fz::check(srd_state_from_parts_(&g_part_opt, pp, 4, 1, kPartStep, &srd), "srd_state_from_parts_"))
      check_srd(srd, in);
    gran_srd_destroy(&srd);
    fz::clean_scratch();
    return 0;
  }
  const uint8_t flags = in.u8();
  const int nedit = 1 + in.u8() % 6;
  std::vector<uint8_t> b = g_base[which];
  const std::string path = fz::scratch() + "/in.ckpt";
  spill(path, b);
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0) fz::fail("the base checkpoint does not open in HDF5", path.c_str());
  std::vector<std::string> ds;
  H5Ovisit(f, H5_INDEX_NAME, H5_ITER_INC, list_ds, &ds); /* the HDF5 1.10 API (Debian 12) */
  std::string text;
  for (int e = 0; e < nedit; ++e) {
    if (g_is_h5[which] && in.u8() < 32) h5_scene_edit(f, in, &text);
    else h5_dataset_edit(f, ds, in, flags & 1);
  }
  H5Fclose(f);
  b = slurp(path);
  if (g_is_h5[which] || (flags & 0x0e) != 0x0e) h5_header(b); /* else (1 in 8) stale: the reader must refuse */
  spill(path, b);
  if (!g_is_h5[which]) {
    gran_srd *srd = nullptr;
    if (!fz::check(gran_srd_checkpoint_read(path.c_str(), "/srd", &srd), "gran_srd_checkpoint_read")) check_srd(srd, in);
    gran_srd_destroy(&srd);
  } else {
    if (!scene_small(text)) {
      fz::clean_scratch();
      return 0;
    }
    if (g_scene[which].find("type = \"srd\"") == std::string::npos) check_dsmc(g_scene[which], path);
    const std::string out = fz::scratch() + "/out.h5";
    gran_run_control ctl = {0, stop_first, nullptr};
    gran_run_result res;
    if (!fz::check(gran_scene_resume(path.c_str(), out.c_str(), &ctl, &res), "gran_scene_resume")) {
      fz::finite_or_fail(res.time, "gran_run_result time (resumed)");
      fz::output_nonfinite(fz::scan_h5(res.finished ? out : fz::scratch() + "/out.partial.h5"));
    }
  }
  fz::clean_scratch();
  return 0;
}
