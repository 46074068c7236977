/* decompose.cpp - `granary decompose SCENE [--bricks auto|PxQxR] [--steps N] [--set KEY=VALUE]...
 * [--reference] [--json]`: steps the GSRD gas of a scene split into bricks of its cell grid and
 * reports the state's digests, its conservation terms and the speed of each process
 * (docs/guide/decompose.md). build/granary-mpi started on P processes gives each process one brick
 * (no process holds more); build/granary steps all bricks in its one process. The digests do not
 * depend on the split: equal digests mean the same particles and cells bit for bit. */
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "core/exactsum.h"
#include "io/io_impl.h"
#include "srd/bricks.h"
#include "theory_util.h"

namespace {

void usage(FILE *f) {
  std::fprintf(f,
               "usage: granary decompose SCENE [--bricks auto|PxQxR] [--steps N] [--every K] [--sk NBINS]\n"
               "                         [--set KEY=VALUE]... [--progress S] [--timeout S] [--reference] [--json]\n"
               "  Steps the scene's GSRD gas ([engine] type = \"srd\", creation = \"cells\") split into bricks of\n"
               "  its cell grid and prints the state's digests (the same for every split), the momentum, the\n"
               "  energy ledger and each process's rate. `mpirun -n P build/granary-mpi decompose ...` gives each\n"
               "  of the P processes one brick; build/granary steps every brick in its one process.\n"
               "  --bricks auto|PxQxR   the split (PxQ in 2-D); auto: the fewest cells on the cut planes.\n"
               "                        Default: one brick per process (build/granary: 1x1x1)\n"
               "  --steps N             steps (default: the scene's engine.steps)\n"
               "  --every K             also a row every K steps (step, time, temperature, kinetic energy,\n"
               "                        ledger, momentum: exact sums over the gas, the same for every split)\n"
               "  --sk NBINS            also the density structure factor S(k) in NBINS shells (1 .. 4096) at the\n"
               "                        end and at every row (periodic box; granary-mpi: FFTW's MPI transform)\n"
               "  --set KEY=VALUE       override a scene key (as granary run)\n"
               "  --progress S          a progress line on stderr every S seconds (default 30; 0: none)\n"
               "  --timeout S           (granary-mpi) the longest a process waits in one exchange before it\n"
               "                        stops every process, naming the one that does not answer (default 600;\n"
               "                        0: no limit)\n"
               "  --reference           (one process) also step the undivided engine (gran_srd_advance) and\n"
               "                        check that its digests and its S(k) are the bricks' (exit 1 otherwise)\n"
               "  --json                the report as one JSON object\n");
}

int parse_bricks(const char *v, int dim, int pg[3], bool *autos) {
  *autos = !std::strcmp(v, "auto");
  if (*autos) return 0;
  pg[0] = pg[1] = pg[2] = 1;
  int n = 0, a = 0;
  const char *p = v;
  while (*p && a < 3) {
    char *end = nullptr;
    const long x = std::strtol(p, &end, 10);
    if (end == p || x < 1 || x > 1000000) return 1;
    pg[a++] = (int)x;
    ++n;
    p = end;
    if (*p == 'x') {
      ++p;
      if (!*p) return 1;
    } else if (*p) {
      return 1;
    }
  }
  return (*p || n != dim) ? 1 : 0;
}

double cli_clock_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string hex(uint64_t v) {
  char b[24];
  std::snprintf(b, sizeof b, "%016" PRIx64, v);
  return b;
}

} // namespace

int cli_decompose(int argc, char **argv) {
  const bool root = cli_mpi_rank() == 0;
  const char *scene_path = nullptr, *bricks = nullptr;
  long long steps = -1;
  bool json = false, reference = false;
  long long every = 0, sk_bins = 0;
  double progress = 30.0; /* seconds between progress lines; 0: none */
  std::vector<std::pair<std::string, std::string>> sets;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    auto value = [&](const char *opt) -> const char * {
      if (i + 1 >= argc) {
        if (root) std::fprintf(stderr, "granary decompose: %s needs a value\n", opt);
        return nullptr;
      }
      return argv[++i];
    };
    if (!std::strcmp(a, "--help") || !std::strcmp(a, "-h")) {
      if (root) usage(stdout);
      return 0;
    } else if (!std::strcmp(a, "--bricks")) {
      if (!(bricks = value(a))) return 2;
    } else if (!std::strcmp(a, "--steps")) {
      const char *v = value(a);
      if (!v) return 2;
      char *end = nullptr;
      steps = std::strtoll(v, &end, 10);
      if (end == v || *end || steps < 0 || steps > 1000000000LL) {
        if (root) std::fprintf(stderr, "granary decompose: --steps '%s': expected an integer in [0, 1e9]\n", v);
        return 2;
      }
    } else if (!std::strcmp(a, "--every")) {
      const char *v = value(a);
      if (!v) return 2;
      char *end = nullptr;
      every = std::strtoll(v, &end, 10);
      if (end == v || *end || every < 1 || every > 1000000000LL) {
        if (root) std::fprintf(stderr, "granary decompose: --every '%s': expected an integer in [1, 1e9]\n", v);
        return 2;
      }
    } else if (!std::strcmp(a, "--sk")) {
      const char *v = value(a);
      if (!v) return 2;
      char *end = nullptr;
      sk_bins = std::strtoll(v, &end, 10);
      if (end == v || *end || sk_bins < 1 || sk_bins > SRD_BRICKS_SK_MAX_BINS) {
        if (root)
          std::fprintf(stderr, "granary decompose: --sk '%s': expected a number of shells in [1, %d]\n", v,
                       SRD_BRICKS_SK_MAX_BINS);
        return 2;
      }
    } else if (!std::strcmp(a, "--progress")) {
      const char *v = value(a);
      if (!v) return 2;
      if (!cli_seconds(v, &progress)) {
        if (root) std::fprintf(stderr, "granary decompose: --progress '%s': expected seconds in [0, 1e7] (0: none)\n", v);
        return 2;
      }
    } else if (!std::strcmp(a, "--timeout")) {
      const char *v = value(a);
      if (!v) return 2;
      double sec = 0;
      if (!cli_seconds(v, &sec)) {
        if (root) std::fprintf(stderr, "granary decompose: --timeout '%s': expected seconds in [0, 1e7] (0: no limit)\n", v);
        return 2;
      }
      cli_mpi_set_timeout(sec);
    } else if (!std::strcmp(a, "--set")) {
      const char *v = value(a);
      if (!v) return 2;
      const char *eq = std::strchr(v, '=');
      if (!eq || eq == v) {
        if (root) std::fprintf(stderr, "granary decompose: --set '%s': expected KEY=VALUE (e.g. --set engine.seed=7)\n", v);
        return 2;
      }
      sets.emplace_back(std::string(v, eq), std::string(eq + 1));
    } else if (!std::strcmp(a, "--json")) {
      json = true;
    } else if (!std::strcmp(a, "--reference")) {
      reference = true;
    } else if (a[0] == '-') {
      if (root) std::fprintf(stderr, "granary decompose: unknown option '%s' (granary decompose --help)\n", a);
      return 2;
    } else if (!scene_path) {
      scene_path = a;
    } else {
      if (root) std::fprintf(stderr, "granary decompose: one scene only ('%s' is a second)\n", a);
      return 2;
    }
  }
  if (!scene_path) {
    if (root) usage(stderr);
    return 2;
  }
  const int P = cli_mpi_size();
  /* before the steps the errors of several processes are held (pre_err) and said once below */
  bool holding = P > 1;
  std::string pre_err;
  auto fail = [&](const std::string &what) {
    const std::string line = "granary decompose: " + what + ": " + cli_error();
    if (holding) {
      if (pre_err.empty()) pre_err = line;
    } else if (root || P > 1) {
      std::fprintf(stderr, "%s\n", line.c_str());
    }
    return 1;
  };
  /* the scene and the split, checked on every process; all go on only if all may (an input that
   * one process cannot read would leave the others waiting in the first exchange) */
  gran_scene *scene = nullptr;
  struct Hold {
    gran_scene *s;
    ~Hold() { gran_scene_destroy(&s); }
  } hold{nullptr};
  gran_srd_options opt;
  std::memset(&opt, 0, sizeof opt);
  int64_t nsteps = 0;
  int pg[3] = {1, 1, 1};
  long long nb = 1;
  auto prepare = [&]() -> int {
    /* the whole gas need not fit one machine: each process's share is checked below */
    struct Defer {
      Defer() { gran_scene_defer_memory_check_(1); }
      ~Defer() { gran_scene_defer_memory_check_(0); }
    } defer;
    if (gran_scene_load(scene_path, &scene)) return fail("invalid scene");
    hold.s = scene;
    for (const auto &kv : sets)
      if (gran_scene_set(scene, kv.first.c_str(), kv.second.c_str())) return fail("--set " + kv.first);
    if (scene->engine_type != "srd") {
      if (root)
        std::fprintf(stderr, "granary decompose: scene '%s' is a %s scene; decompose steps GSRD scenes ([engine] type = \"srd\")\n",
                     scene_path, scene->engine_type.c_str());
      return 1;
    }
    opt = scene->srd.opt;
    if (opt.creation != GRAN_SRD_CREATE_CELLS) {
      if (root)
        std::fprintf(stderr,
                     "granary decompose: scene '%s' creates its gas serially; a split gas needs [engine] creation = \"cells\" "
                     "(or --set engine.creation='\"cells\"')\n",
                     scene_path);
      return 1;
    }
    if (scene->srd.device != "cpu") {
      if (root)
        std::fprintf(stderr, "granary decompose: [engine] device = \"%s\": a split gas steps on the CPU (device = \"cpu\")\n",
                     scene->srd.device.c_str());
      return 1;
    }
    nsteps = steps >= 0 ? (int64_t)steps : scene->srd.steps;
    bool autos = bricks == nullptr && P > 1;
    if (bricks && parse_bricks(bricks, opt.dim, pg, &autos)) {
      if (root)
        std::fprintf(stderr, "granary decompose: --bricks '%s': expected auto or %s (positive integers)\n", bricks,
                     opt.dim == 3 ? "PxQxR" : "PxQ");
      return 2;
    }
    if (autos && srd_bricks_auto_(&opt, P, pg)) return fail("--bricks auto");
    nb = (long long)pg[0] * pg[1] * pg[2];
    if (P > 1 && nb != P) {
      if (root)
        std::fprintf(stderr, "granary decompose: --bricks %dx%dx%d is %lld bricks for %d processes (one brick each)\n", pg[0],
                     pg[1], pg[2], nb, P);
      return 2;
    }
    if (reference && P > 1) {
      if (root) std::fprintf(stderr, "granary decompose: --reference runs in one process (build/granary)\n");
      return 2;
    }
    if (sk_bins > 0 && opt.wall_axis >= 0) {
      if (root)
        std::fprintf(stderr, "granary decompose: --sk: S(k) needs a periodic box, and scene '%s' has walls (wall axis %d)\n",
                     scene_path, (int)opt.wall_axis);
      return 2;
    }
    if (sk_bins > 0 && P > 1 && !cli_mpi_bricks_comm()->fft_r2c) {
      if (root)
        std::fprintf(stderr, "granary decompose: --sk on %d processes needs FFTW's MPI interface, and this granary-mpi "
                             "was built without it (install Debian libfftw3-mpi-dev, then make)\n", P);
      return 1;
    }
    { /* the memory of this process's share against the machine's, divided among its processes (a
       * scene's max_memory_gb caps it) */
      const bool one = P == 1 && nb > 1;
      const double nrows = every > 0 ? (double)nsteps / (double)every + 2 : 0.0;
      const double rows_bytes = nrows * 2.0 * (sizeof(srd_bricks_rank_out) + 24.0 * (double)sk_bins);
      double box = 1;
      for (int k = 0; k < opt.dim; ++k) box *= (double)opt.cells[k];
      /* S(k): the slab's counts, the half spectrum and its power (48 B per cell of the slab), and
       * (one process) the reference engine's copy */
      const double sk_bytes = sk_bins > 0 ? 48.0 * box / (double)(P > 1 ? P : 1) * (reference ? 2.0 : 1.0) : 0.0;
      const double need = srd_bricks_memory_(&opt, (int)nb, one) + (reference ? srd_bricks_memory_(&opt, 1, 1) : 0.0) +
                          rows_bytes + sk_bytes; /* the rows, and their text */
      const int local = cli_mpi_local_size() > 0 ? cli_mpi_local_size() : 1;
      const double avail = std::min(gran_scene_memory_limit_(scene), gran_memory_available_()) / local;
      if (!(need <= avail)) {
        if (root)
          std::fprintf(stderr,
                       "granary decompose: %s needs about %.3g GB (%s), more than the %.3g GB available%s; use more "
                       "processes (machines) or a smaller gas\n",
                       P > 1 ? "each process" : "the run", need / 1e9,
                       one ? "all bricks in one process" : "its brick's particles and cells",
                       avail / 1e9, local > 1 ? (" to each of the " + std::to_string(local) + " processes on this machine").c_str() : "");
        return 1;
      }
    }
    return 0;
  };
  const int pre = prepare();
  holding = false;
  if (!cli_mpi_all(pre == 0)) {
    /* rank 0 says its error; another process only one that differs from it (a file that only it
     * cannot read), so an error every process meets is printed once */
    std::string first = root ? pre_err : std::string();
    if (P > 1 && cli_mpi_bcast(&first)) first.clear();
    if (root && !pre_err.empty())
      std::fprintf(stderr, "%s\n", pre_err.c_str());
    else if (!root && !pre_err.empty() && pre_err != first)
      std::fprintf(stderr, "process %d: %s\n", cli_mpi_rank(), pre_err.c_str());
    return pre ? pre : 1;
  }
  srd_bricks_rank_out r;
  std::memset(&r, 0, sizeof r);
  std::vector<srd_bricks_rank_out> rows; /* every `every` steps, and the start */
  std::vector<gran_srd_obs> row_ob;      /* the observables at each row (the clamps since the last row) */
  gran_srd_obs ob_end;
  std::memset(&ob_end, 0, sizeof ob_end);
  struct Sk {
    explicit Sk(long long n = 0) : k((size_t)n), s((size_t)n), count((size_t)n) {}
    std::vector<double> k, s;
    std::vector<int64_t> count;
  };
  std::vector<Sk> row_sk; /* with --sk: S(k) at each row */
  Sk sk_end(sk_bins);
  double sk_seconds = 0;  /* the slowest S(k) of process 0 */
  double obs_seconds = 0; /* the slowest observation of process 0 */
  double open_seconds = 0; /* process 0's creation of its bricks */
  {
    srd_bricks_state *st = nullptr;
    auto structure = [&](Sk &q) -> int {
      const double c0 = cli_clock_s();
      const int e = srd_bricks_structure_factor_(st, sk_bins, q.k.data(), q.s.data(), q.count.data());
      sk_seconds = std::max(sk_seconds, cli_clock_s() - c0);
      return e;
    };
    auto observe = [&](gran_srd_obs &ob) -> int {
      const double c0 = cli_clock_s();
      const int e = srd_bricks_observe_(st, &ob);
      obs_seconds = std::max(obs_seconds, cli_clock_s() - c0);
      return e;
    };
    auto row = [&]() -> int {
      rows.emplace_back();
      row_ob.emplace_back();
      int e = srd_bricks_report_(st, &rows.back());
      if (!e) e = observe(row_ob.back());
      if (!e && sk_bins > 0) {
        row_sk.emplace_back(sk_bins);
        e = structure(row_sk.back());
      }
      return e;
    };
    const double t_open = cli_clock_s();
    int e = srd_bricks_open_(&opt, pg, cli_mpi_bricks_comm(), &st);
    open_seconds = cli_clock_s() - t_open;
    if (!e && every > 0) e = row();
    /* the steps in chunks of about 5e7 particle-steps of a process (1-2 s; the same chunks on every
     * process, as every step call is collective; the state does not depend on them), a progress
     * line on stderr every `progress` seconds (after the chunk that passes it) */
    double box = 1;
    for (int k = 0; k < opt.dim; ++k) box *= (double)opt.cells[k];
    const double n_here = std::max(1.0, opt.n0 * box / (double)(P > 1 ? P : 1));
    const int64_t chunk = (int64_t)std::min(1e4, std::max(1.0, std::floor(5e7 / n_here)));
    const double t0 = cli_clock_s();
    double last = t0;
    int64_t next_row = every > 0 ? every : nsteps;
    for (int64_t done = 0; !e && done < nsteps;) {
      const int64_t k = std::min<int64_t>({chunk, nsteps - done, next_row - done});
      e = srd_bricks_step_(st, k);
      const double c1 = cli_clock_s();
      done += k;
      if (!e && done == next_row) {
        if (every > 0 && done < nsteps) e = row();
        next_row = every > 0 ? std::min<int64_t>(done + every, nsteps) : nsteps;
      }
      if (root && progress > 0.0 && c1 - last >= progress && done < nsteps) {
        std::fprintf(stderr, "granary decompose: step %lld of %lld, %.0f s, about %.0f s left\n", (long long)done,
                     (long long)nsteps, c1 - t0, (c1 - t0) * (double)(nsteps - done) / (double)done);
        last = c1;
      }
    }
    if (!e) e = srd_bricks_report_(st, &r);
    if (!e) e = observe(ob_end);
    if (!e && sk_bins > 0) e = structure(sk_end);
    if (!e && every > 0) {
      rows.push_back(r);
      row_ob.push_back(ob_end);
      if (sk_bins > 0) row_sk.push_back(sk_end);
    }
    srd_bricks_close_(&st);
    if (e) {
      fail(P > 1 ? "process " + std::to_string(cli_mpi_rank()) : std::string("bricks"));
      if (P > 1) cli_mpi_abort(1); /* the other processes wait in the exchange: stop them all */
      return 1;
    }
  }
  int ref_ok = 1;
  uint64_t ref_p = 0, ref_c = 0;
  double ref_sk_diff = 0; /* the largest relative difference of S(k) and k from the undivided engine's */
  std::string ref_obs_diff; /* the first observable that differs from the undivided engine's ("" none) */
  if (reference) { /* the undivided decomposable engine, observed at the same rows */
    gran_srd *s = nullptr;
    if (gran_srd_create(&opt, &s)) return fail("reference");
    Sk q(sk_bins); /* its S(k) */
    static const char *const names[] = {"time", "steps", "n", "temperature", "theta_cells", "energy", "e_initial",
                                        "e_collisions", "e_external", "ledger_error", "momentum[0]", "momentum[1]",
                                        "momentum[2]", "e_kin", "mach", "sigma_rho", "a2", "clamped", "dt_max",
                                        "stress_xy", "stress_kin"};
    static_assert(sizeof names / sizeof names[0] * 8 == sizeof(gran_srd_obs), "one name per field");
    auto compare = [&](const gran_srd_obs &a, const gran_srd_obs &b, const char *where) {
      for (size_t f = 0; f < sizeof names / sizeof names[0] && ref_obs_diff.empty(); ++f)
        if (std::memcmp((const char *)&a + 8 * f, (const char *)&b + 8 * f, 8))
          ref_obs_diff = std::string(names[f]) + " " + where;
    };
    int e = 0;
    int64_t done = 0;
    for (size_t i = 0; !e && i < rows.size(); ++i) { /* the rows (the last is the end) */
      e = gran_srd_advance(s, rows[i].step - done);
      done = rows[i].step;
      gran_srd_obs ob;
      if (!e) e = gran_srd_observe(s, &ob);
      if (!e) compare(ob, row_ob[i], ("at the row of step " + std::to_string(done)).c_str());
    }
    if (!e && every == 0) {
      e = gran_srd_advance(s, nsteps);
      gran_srd_obs ob;
      if (!e) e = gran_srd_observe(s, &ob);
      if (!e) compare(ob, ob_end, "at the end");
    }
    srd_bricks_out o;
    if (!e && sk_bins > 0) e = gran_srd_structure_factor(s, sk_bins, q.k.data(), q.s.data(), q.count.data());
    if (!e) e = srd_bricks_gather_plain_(s, &o);
    gran_srd_destroy(&s);
    if (e) return fail("reference");
    srd_bricks_digest_(&o, opt.dim, &ref_p, &ref_c);
    srd_bricks_out_free_(&o);
    ref_ok = ref_p == r.digest_particles && ref_c == r.digest_cells && ref_obs_diff.empty();
    /* S(k): the same bits (the largest relative difference reported) */
    for (size_t i = 0; i < q.count.size(); ++i) {
      if (q.count[i] != sk_end.count[i]) ref_sk_diff = INFINITY;
      if (q.count[i] > 0)
        for (double v : {std::fabs(sk_end.k[i] - q.k[i]) / std::fabs(q.k[i]),
                         std::fabs(sk_end.s[i] - q.s[i]) / std::max(std::fabs(q.s[i]), 1e-300)})
          ref_sk_diff = std::max(ref_sk_diff, v);
    }
    ref_ok = ref_ok && ref_sk_diff == 0.0;
  }
  if (!root) return 0;
  const double rate = r.seconds > 0 ? (double)r.particle_steps / r.seconds : 0.0;
  const double per_step = nsteps > 0 ? 1.0 / (double)nsteps : 0.0;
  const double bytes_step = (double)r.bytes_sent_all * per_step / (double)nb;
  if (json) {
    std::string o = "{";
    auto key = [&](const char *k) {
      if (o.size() > 1) o += ", ";
      cli_json::str(o, k);
      o += ": ";
    };
    auto num = [&](const char *k, double v) {
      key(k);
      cli_json::num(o, v);
    };
    auto str = [&](const char *k, const std::string &v) {
      key(k);
      cli_json::str(o, v);
    };
    str("scene", scene_path);
    num("dim", opt.dim);
    key("bricks");
    o += "[" + std::to_string(pg[0]) + ", " + std::to_string(pg[1]) + ", " + std::to_string(pg[2]) + "]";
    num("processes", P);
    num("steps", (double)nsteps);
    num("particles", (double)r.n);
    str("digest_particles", hex(r.digest_particles));
    str("digest_cells", hex(r.digest_cells));
    if (reference) {
      str("reference_digest_particles", hex(ref_p));
      str("reference_digest_cells", hex(ref_c));
      str("reference_observables", ref_obs_diff.empty() ? "the same" : "differ: " + ref_obs_diff);
      if (sk_bins > 0) num("reference_sk_max_rel_diff", ref_sk_diff);
    }
    key("momentum");
    o += "[";
    for (int k = 0; k < 3; ++k) {
      if (k) o += ", ";
      cli_json::num(o, r.momentum[k]);
    }
    o += "]";
    num("kinetic_energy", r.energy);
    num("e_initial", r.e_initial);
    num("e_coll", r.e_coll);
    num("e_ext", r.e_ext);
    num("flux_kin", r.flux_kin);
    num("flux_coll", r.flux_coll);
    key("wall_impulse");
    o += "[";
    for (int k = 0; k < 3; ++k) {
      if (k) o += ", ";
      cli_json::num(o, r.wall_impulse[k]);
    }
    o += "]";
    num("clamped", (double)r.clamped);
    num("time", r.time);
    num("seconds_max", r.seconds_max);
    num("rank0_seconds", r.seconds);
    num("rank0_particle_steps_per_second", rate);
    num("brick_particles_min", (double)r.n_local_min); /* the balance of the split */
    num("brick_particles_max", (double)r.n_local_max);
    num("bytes_per_step_per_brick", bytes_step);
    num("particles_sent", (double)r.particles_sent_all);
    num("temperature", r.temperature);
    auto arr = [&](const std::vector<double> &v) { cli_json::arr(o, v.data(), (int64_t)v.size()); };
    /* gran_srd_observe's cell observables (the names of the output file's datasets; its momentum and
     * energy are the report's above, there summed exactly particle by particle, here cell by cell) */
    auto observables = [&](const gran_srd_obs &b) {
      o += "{";
      const std::pair<const char *, double> kv[] = {
          {"T", b.temperature},       {"theta_cells", b.theta_cells},
          {"E_kin", b.e_kin},         {"mach", b.mach},               {"sigma_rho", b.sigma_rho},
          {"a2", b.a2},               {"ledger_error", b.ledger_error}, {"clamped", (double)b.clamped},
          {"stress_xy", b.stress_xy}, {"stress_kinetic", b.stress_kin}};
      for (size_t i = 0; i < sizeof kv / sizeof kv[0]; ++i) {
        if (i) o += ", ";
        cli_json::str(o, kv[i].first);
        o += ": ";
        cli_json::num(o, kv[i].second);
      }
      o += "}";
    };
    key("observables");
    observables(ob_end);
    num("observe_seconds", obs_seconds);
    num("open_seconds", open_seconds);
    if (sk_bins > 0) {
      key("sk");
      o += "{\"k\": ";
      arr(sk_end.k);
      o += ", \"s\": ";
      arr(sk_end.s);
      o += ", \"count\": ";
      arr(std::vector<double>(sk_end.count.begin(), sk_end.count.end()));
      o += "}";
      num("sk_seconds", sk_seconds);
    }
    if (every > 0) { /* the rows: every `every` steps from the start, and the end */
      key("rows");
      o += "[";
      for (size_t i = 0; i < rows.size(); ++i) {
        const srd_bricks_rank_out &w = rows[i];
        o += i ? ", {" : "{";
        const size_t mark = o.size();
        auto rnum = [&](const char *k, double v) {
          if (o.size() > mark) o += ", ";
          cli_json::str(o, k);
          o += ": ";
          cli_json::num(o, v);
        };
        rnum("step", (double)w.step);
        rnum("time", w.time);
        rnum("temperature", w.temperature);
        rnum("kinetic_energy", w.energy);
        rnum("e_coll", w.e_coll);
        rnum("e_ext", w.e_ext);
        o += ", \"momentum\": [";
        for (int k = 0; k < 3; ++k) {
          if (k) o += ", ";
          cli_json::num(o, w.momentum[k]);
        }
        o += "]";
        o += ", \"observables\": ";
        observables(row_ob[i]);
        if (sk_bins > 0) {
          o += ", \"sk\": ";
          arr(row_sk[i].s);
        }
        o += "}";
      }
      o += "]";
    }
    num("messages_beyond_neighbours", (double)r.far_messages_all);
    o += "}\n";
    std::fputs(o.c_str(), stdout);
  } else {
    std::printf("scene            %s (%d-D, %lld particles, %lld steps)\n", scene_path, (int)opt.dim, (long long)r.n,
                (long long)nsteps);
    std::printf("bricks           %d x %d x %d (%s)\n", pg[0], pg[1], pg[2],
                P > 1 ? (std::to_string(P) + " processes, one brick each").c_str() : "in one process");
    std::printf("digest           particles %s, cells %s\n", hex(r.digest_particles).c_str(), hex(r.digest_cells).c_str());
    if (reference)
      std::printf("reference        particles %s, cells %s: %s\n", hex(ref_p).c_str(), hex(ref_c).c_str(),
                  ref_ok ? "the same" : "DIFFERENT");
    std::printf("momentum         %.17g %.17g %.17g\n", r.momentum[0], r.momentum[1], r.momentum[2]);
    std::printf("temperature      %.17g\n", r.temperature);
    std::printf("observables      T %.10g  theta_cells %.10g  E_kin %.10g  Mach %.10g  sigma_rho %.10g  a2 %.6g%s\n",
                ob_end.temperature, ob_end.theta_cells, ob_end.e_kin, ob_end.mach, ob_end.sigma_rho, ob_end.a2,
                !reference ? "" : ref_obs_diff.empty() ? " (the undivided engine's, bit for bit)"
                                                      : (" (DIFFERENT from the undivided engine's: " + ref_obs_diff + ")").c_str());
    std::printf("energy           kinetic %.17g; ledger: initial %.17g, collisions %.17g, external work %.17g\n",
                r.energy, r.e_initial, r.e_coll, r.e_ext);
    std::printf("balance          %lld .. %lld particles per brick\n", (long long)r.n_local_min,
                (long long)r.n_local_max);
    std::printf("speed            %.3f s (slowest process); process 0: %.4g particle-steps per second\n", r.seconds_max,
                rate);
    for (size_t i = 0; i < rows.size(); ++i) {
      const srd_bricks_rank_out &w = rows[i];
      std::printf("row              step %lld  t %.10g  T %.10g  e_kin %.10g  e_coll %.10g  e_ext %.10g  Mach %.6g  a2 %.6g\n",
                  (long long)w.step, w.time, w.temperature, w.energy, w.e_coll, w.e_ext, row_ob[i].mach, row_ob[i].a2);
    }
    if (sk_bins > 0) {
      std::printf("S(k)             %lld shells at the end (%.3g s)%s\n", sk_bins, sk_seconds,
                  reference ? (ref_sk_diff == 0.0 ? "; the undivided engine's, bit for bit" : "; DIFFERENT from the undivided engine's")
                            : "");
      for (long long b = 0; b < sk_bins; ++b)
        if (sk_end.count[(size_t)b] > 0)
          std::printf("  k %.10g  S %.10g  modes %lld\n", sk_end.k[(size_t)b], sk_end.s[(size_t)b],
                      (long long)sk_end.count[(size_t)b]);
    }
    std::printf("exchange         %.4g bytes per brick and step, %lld particles changed brick\n", bytes_step,
                (long long)r.particles_sent_all);
    if (P > 1)
      std::printf("                 %lld messages went to bricks beyond the neighbouring ones\n",
                  (long long)r.far_messages_all);
  }
  return ref_ok ? 0 : 1;
}
