/* run.cpp - `granary run SCENE [-o FILE] [--checkpoint FILE | --no-checkpoint] [--quiet]
 *            [--stop-after-checkpoints N]` and `granary run --resume CHECKPOINT [-o FILE]`.
 * Progress goes to stderr: one line rewritten with \r on a terminal, a plain line every 10 s
 * otherwise (logs stay readable). At the end: where the output went, and a short table of the
 * simulated T_k and MSD_k beside the theory, read back from the output file. */
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include "cli.h"
#include "io/engine.h"

namespace {

/* SIGINT (Ctrl-C) and SIGTERM (what batch systems send before they kill a job) stop the run at
 * the next output time with a checkpoint and the partial output; the exit code is 128 + the
 * signal (130, 143). A second one of the same signal kills at once. */
volatile std::sig_atomic_t g_interrupted = 0; /* the signal that stopped the run, 0: none */
void on_stop_signal(int sig) {
  g_interrupted = sig;
  std::signal(sig, SIG_DFL);
}
int stop_code() { return g_interrupted ? 128 + (int)g_interrupted : 0; }

void run_usage(FILE *f) {
  std::fprintf(f,
               "usage: granary run SCENE [-o FILE] [--checkpoint FILE | --no-checkpoint] [--force] [--quiet]\n"
               "       granary run --resume CHECKPOINT [-o FILE] [--force] [--quiet]\n"
               "  -o FILE                    HDF5 output (default: the scene's [output] path)\n"
               "  --checkpoint FILE          checkpoint file (default: the scene's, else OUTPUT.ckpt of -o)\n"
               "  --force                    overwrite an existing output file (refused otherwise)\n"
               "  --replicas R               R independent runs (default: the scene's [engine] replicas, 1);\n"
               "                             the output holds the mean X and its standard error X_se\n"
               "  --threads N                threads for the replicas (default: OMP_NUM_THREADS or all cores)\n"
               "  --no-checkpoint            write no checkpoints\n"
               "  --resume CHECKPOINT        continue a run from its checkpoint, bit for bit\n"
               "  --stop-after-checkpoints N stop after writing N checkpoints (for testing resume)\n"
               "  --quiet                    no progress line, no summary table\n"
               "  --verbose                  error messages name the library function and source line\n"
               "  Ctrl-C (SIGINT) or SIGTERM stops at the next output time after writing a checkpoint; what\n"
               "  was recorded so far goes to OUTPUT.partial.h5 (root attribute complete = 0).\n"
               "exit codes: 0 done (or stopped by --stop-after-checkpoints), 1 error (bad scene, refused\n"
               "  files, a failed run or write), 2 bad command line, 130 stopped by SIGINT, 143 by SIGTERM.\n");
}

struct Progress {
  bool tty = false, quiet = false;
  double last_print = -1e300;
  int width = 0;
};

std::string hms(double s) {
  if (!(s >= 0) || !std::isfinite(s)) return "?";
  char b[32];
  long t = (long)(s + 0.5);
  if (t >= 3600) std::snprintf(b, sizeof b, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else std::snprintf(b, sizeof b, "%ld:%02ld", t / 60, t % 60);
  return b;
}

int progress_cb(const gran_run_progress *p, void *params) {
  Progress *pr = static_cast<Progress *>(params);
  if (!pr->quiet) {
    const bool last = p->output_index == p->noutputs;
    if (pr->tty || last || p->wall_seconds - pr->last_print >= 10.0) {
      char line[256];
      int n = std::snprintf(line, sizeof line, "[%5.1f%%] t = %-11.5g collisions %-11" PRId64 " %9.3g coll/s  ETA %s",
                            100.0 * p->fraction, p->time, p->collisions, p->collisions_per_second,
                            hms(p->eta_seconds).c_str());
      if (pr->tty) {
        std::fprintf(stderr, "\r%s%*s", line, pr->width > n ? pr->width - n : 0, "");
        if (last) std::fputc('\n', stderr);
        pr->width = n;
      } else {
        std::fprintf(stderr, "%s\n", line);
      }
      std::fflush(stderr);
      pr->last_print = p->wall_seconds;
    }
  }
  return g_interrupted ? 1 : 0;
}

/* The summary: a few output times (spread over the run), each column pair the engine lists in
 * the output's `summary_columns` attribute (simulated beside theory, only observables that are on). */
void summary(const std::string &path) {
  int64_t f = gran_h5::open_file(path.c_str(), 0);
  if (f < 0) return;
  const char *p = path.c_str();
  std::string spec;
  std::vector<double> t;
  struct Col {
    std::string label;
    std::vector<double> sim, se, th;
    int64_t M = 0;
  };
  std::vector<Col> cols;
  bool haveTime = !gran_h5::read_double(f, "time", t, nullptr, p);
  if (!gran_h5::read_attr_string(f, "summary_columns", spec, p)) {
    size_t at = 0;
    while (at < spec.size()) {
      size_t e = spec.find(';', at);
      if (e == std::string::npos) e = spec.size();
      std::string item = spec.substr(at, e - at);
      at = e + 1;
      size_t c1 = item.find(':'), c2 = item.find(':', c1 == std::string::npos ? 0 : c1 + 1);
      if (c1 == std::string::npos || c2 == std::string::npos) continue;
      Col c;
      c.label = item.substr(0, c1);
      std::string sim = item.substr(c1 + 1, c2 - c1 - 1), th = item.substr(c2 + 1);
      std::vector<int64_t> d;
      if (!gran_h5::exists(f, sim.substr(0, sim.find('/')).c_str()) || gran_h5::read_double(f, sim.c_str(), c.sim, &d, p)) continue;
      c.M = d.size() > 1 ? d[1] : 1;
      const std::string se = sim + "_se";
      if (!gran_h5::exists(f, se.c_str()) || gran_h5::read_double(f, se.c_str(), c.se, nullptr, p)) c.se.clear();
      if (!th.empty() && !gran_h5::exists(f, th.c_str())) th.clear();
      if (!th.empty() && gran_h5::read_double(f, th.c_str(), c.th, nullptr, p)) c.th.clear();
      if (c.th.size() != c.sim.size()) c.th.assign(c.sim.size(), NAN);
      if (c.se.size() != c.sim.size()) c.se.clear();
      for (auto *v : {&c.sim, &c.se}) /* the fill value (no value) prints as nan */
        for (double &x : *v)
          if (x == gran_row_fill) x = NAN;
      cols.push_back(std::move(c));
    }
  }
  std::vector<double> ek, e0, mass, dens;
  std::vector<int64_t> coll;
  bool haveE = gran_h5::exists(f, "energy") && !gran_h5::read_double(f, "energy/e_kin", ek, nullptr, p) &&
               !gran_h5::read_double(f, "energy/e_initial", e0, nullptr, p);
  bool haveC = gran_h5::exists(f, "stats") && !gran_h5::read_int64(f, "stats/collisions", coll, nullptr, p);
  if (!gran_h5::exists(f, "species") || gran_h5::read_double(f, "species/mass", mass, nullptr, p) ||
      gran_h5::read_double(f, "species/density", dens, nullptr, p)) {
    mass.clear();
    dens.clear();
  }
  int64_t nrep = 1;
  if (H5Aexists((hid_t)f, "nreplicas") > 0) gran_h5::read_attr_int64(f, "nreplicas", &nrep, p);
  gran_h5::close_file(f);
  gran_clear_error();
  if (!haveTime || cols.empty() || t.empty()) return;
  const int64_t nt = (int64_t)t.size();
  int64_t M = 0;
  for (const auto &c : cols) M = std::max(M, c.M);
  /* rows: about 5 output times spread evenly over the index range (log-spaced times stay log-spaced) */
  std::vector<int64_t> rows;
  const int want = 5;
  for (int i = 0; i < want; i++) {
    int64_t r = nt <= 1 ? 0 : (int64_t)std::llround((double)(nt - 1) * (i + 1) / want);
    if (rows.empty() || rows.back() != r) rows.push_back(r);
  }
  const int64_t Mshow = M > 6 ? 6 : M;
  /* footnotes where the Maxwellian theory is known to be off (docs/physics.md; Bodrova & Osinsky) */
  const bool mixture = (int64_t)mass.size() == M && M > 1;
  double mmin = INFINITY, ntot = 0;
  for (double m : mass) mmin = std::min(mmin, m);
  for (double n : dens) ntot += n;
  auto note = [&](const std::string &label, int64_t k) -> const char * {
    if (!mixture) return "";
    const double mk = mass[(size_t)k], nk = dens[(size_t)k];
    /* heavy and dilute (tracer limit): Bodrova & Osinsky Sec. II F, Eq. 35 */
    if (mk >= 10.0 * mmin && nk <= 0.05 * ntot) return "c";
    /* light among heavy: the species at least 10x heavier outnumber it */
    double nheavy = 0;
    for (int64_t j = 0; j < M; j++)
      if (mass[(size_t)j] >= 10.0 * mk) nheavy += dens[(size_t)j];
    if (label == "MSD" && nheavy > nk) return "b";
    if (label == "T") return "a";
    return "";
  };
  bool used[3] = {false, false, false};
  std::printf("\n%12s %4s", "time", "k");
  for (const auto &c : cols) {
    if (c.se.empty()) std::printf(" | %12s %12s %8s", (c.label + "_sim").c_str(), (c.label + "_theory").c_str(), "dev");
    else std::printf(" | %12s %10s %12s %8s %8s", (c.label + "_sim").c_str(), "+- se", (c.label + "_theory").c_str(), "dev", "dev/se");
  }
  std::printf("\n");
  auto dev = [](double a, double b) -> std::string {
    char s[32];
    if (!std::isfinite(a) || !std::isfinite(b) || b == 0) return "";
    std::snprintf(s, sizeof s, "%+.2f%%", 100.0 * (a - b) / b);
    return s;
  };
  for (int64_t r : rows) {
    for (int64_t k = 0; k < Mshow; k++) {
      std::printf("%12.5g %4" PRId64, t[(size_t)r], k + 1);
      for (const auto &c : cols) {
        const size_t i = (size_t)(r * c.M + k);
        const double a = k < c.M ? c.sim[i] : NAN, b = k < c.M ? c.th[i] : NAN;
        const char *n = k < c.M && std::isfinite(b) ? note(c.label, k) : "";
        if (*n) used[*n - 'a'] = true;
        if (c.se.empty()) {
          std::printf(" | %12.6g %12.6g %8s", a, b, dev(a, b).c_str());
        } else {
          const double e = k < c.M ? c.se[i] : NAN;
          char z[32] = "";
          if (std::isfinite(a) && std::isfinite(b) && e > 0) std::snprintf(z, sizeof z, "%+.1f%s", (a - b) / e, n);
          std::printf(" | %12.6g %10.3g %12.6g %8s %8s", a, e, b, dev(a, b).c_str(), z);
        }
      }
      std::printf("\n");
    }
  }
  if (Mshow < M) std::printf("(species 1..%" PRId64 " of %" PRId64 " shown; everything is in %s)\n", Mshow, M, p);
  if (nrep > 1) {
    std::printf("mean over %" PRId64 " replicas +- its standard error; dev/se: (sim - theory) / se\n", nrep);
    if (used[0])
      std::printf("  a: the Maxwellian theory of T_k in a mixture is off by about 0.6-1.2 %% (first Sonine correction)\n");
    if (used[1])
      std::printf("  b: light species among heavy ones diffuse 10-14 %% faster than Eq. 4 predicts (Lorentz gas: 32/(9 pi))\n");
    if (used[2])
      std::printf("  c: a heavy, dilute species (tracer limit, Bodrova & Osinsky Eq. 35) runs hotter than the Maxwellian theory:\n"
                  "     near or in the ordered phase of Santos and Dufty (b > 1) T_k/T_1 is well above it (physics, not noise)\n");
  }
  if (haveE && !ek.empty())
    std::printf("at t = %.6g: total kinetic energy %.6g (initially %.6g)%s", t.back(), ek.back(), e0.back(),
                haveC && !coll.empty() ? "" : "\n");
  if (haveC && !coll.empty())
    std::printf("%s%" PRId64 " collisions%s\n", haveE ? ", " : "", coll.back(), nrep > 1 ? " (all replicas)" : "");
}

/* The title and main parameters, printed before the run starts. */
void header(const gran_scene *s, const std::string &out, const std::string &ck) {
  std::printf("%s\n", s->title.empty() ? s->name.c_str() : s->title.c_str());
  if (s->engine_type == "srd") { /* GSRD scene (src/io/engine_srd.cpp): its own parameters */
    const gran_srd_options &o = s->srd.opt;
    double nc = 1;
    for (int k = 0; k < o.dim; k++) nc *= (double)o.cells[k];
    std::printf("  engine srd (%s), %d-D, %.0f cells of a = %g, %.0f particles, dt = %g, alpha = %g, eps = %g\n",
                s->srd.device.c_str(), (int)o.dim, nc, o.a, std::floor(o.n0 * nc + 0.5), o.dt, o.alpha_deg, o.eps);
    std::printf("  t = 0 .. %g (%lld steps), %zu output times, seed %llu", s->t_end, (long long)s->srd.steps,
                s->times.size(), (unsigned long long)s->seed);
    if (s->replicas > 1) std::printf(", %" PRId64 " replicas", s->replicas);
    std::printf("\n  output %s, checkpoint %s\n", out.c_str(), ck.empty() ? "(none)" : ck.c_str());
    std::fflush(stdout);
    return;
  }
  int64_t N = 0;
  for (int64_t c : s->counts) N += c;
  std::printf("  engine %s (%s), %" PRId64 " species", s->engine_type.c_str(),
              s->selector == GRAN_SELECTOR_BIRD ? "bird" : s->selector == GRAN_SELECTOR_CELL ? "cell" : "lowrank",
              s->nspecies);
  if (s->counts_kind == 0) std::printf(", %" PRId64 " particles", N);
  else if (s->counts_kind == 1) std::printf(", N1 = %.6g", s->N1);
  else std::printf(", volume %.6g", s->volume);
  std::printf(", restitution %s", s->model == GRAN_RESTITUTION_VISCOELASTIC ? "viscoelastic" : "constant");
  if (s->model != GRAN_RESTITUTION_VISCOELASTIC && s->eps_matrix.empty()) std::printf(" eps = %g", s->eps);
  std::printf("\n  t = %g .. %g, %zu output times, seed %llu", s->t_start, s->t_end, s->times.size(),
              (unsigned long long)s->seed);
  if (s->replicas > 1) {
    int32_t th = 1;
    gran_get_threads(&th);
    const int P = cli_mpi_size();
    const int64_t per = (s->replicas + P - 1) / P;
    if (P > 1) std::printf(", %" PRId64 " replicas on %d processes x %d thread(s)", s->replicas, P, (int)std::min<int64_t>(th, per));
    else std::printf(", %" PRId64 " replicas on %d thread(s)", s->replicas, (int)std::min<int64_t>(th, s->replicas));
  }
  std::printf("\n  output %s, checkpoint %s\n", out.c_str(), ck.empty() ? "(none)" : ck.c_str());
  std::fflush(stdout);
}

bool file_exists(const std::string &p) {
  struct stat sb;
  return stat(p.c_str(), &sb) == 0;
}

/* A run stopped before its end: what was recorded is in the partial output. */
int stopped(const gran_run_result &res, const std::string &out, const std::string &ck) {
  const std::string part = gran_partial_path_(out);
  std::fprintf(stderr, "granary run: stopped at t = %.6g after %" PRId64 " checkpoint(s); the output times recorded so far are in\n"
                       "  %s (complete = 0); %s is written when the run finishes.\n", res.time, res.checkpoints,
               part.c_str(), out.c_str());
  if (ck.empty()) std::fprintf(stderr, "  No checkpoint was written (--no-checkpoint): the run cannot be continued.\n");
  else std::fprintf(stderr, "  Continue with: granary run --resume %s\n", ck.c_str());
  return stop_code();
}

int fail(const char *what) {
  /* a collective failure carries the same message on every process: rank 0 prints it */
  if (cli_mpi_rank() == 0) std::fprintf(stderr, "granary run: %s: %s\n", what, cli_error());
  return 1;
}

/* A failure only this process saw (several processes): it prints it, naming itself. */
int fail_here(const char *what) {
  if (cli_mpi_size() > 1) std::fprintf(stderr, "granary run: process %d of %d: %s: %s\n", cli_mpi_rank(), cli_mpi_size(), what, cli_error());
  else std::fprintf(stderr, "granary run: %s: %s\n", what, cli_error());
  return 1;
}

}  // namespace

int cli_run(int argc, char **argv) {
  const char *scene_path = nullptr, *output = nullptr, *checkpoint = nullptr, *resume = nullptr;
  bool quiet = false, no_ckpt = false, force = false;
  long long stop_after = 0, replicas = 0, threads = -1;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    auto need = [&](const char *opt) -> const char * {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "granary run: %s needs an argument\n", opt);
        return nullptr;
      }
      return argv[++i];
    };
    if (!std::strcmp(a, "--help") || !std::strcmp(a, "-h")) {
      run_usage(stdout);
      return 0;
    } else if (!std::strcmp(a, "-o") || !std::strcmp(a, "--output")) {
      if (!(output = need(a))) return 2;
    } else if (!std::strcmp(a, "--checkpoint")) {
      if (!(checkpoint = need(a))) return 2;
    } else if (!std::strcmp(a, "--replicas") || !std::strcmp(a, "--threads")) {
      const char *v = need(a);
      if (!v) return 2;
      char *end = nullptr;
      long long x = std::strtoll(v, &end, 10);
      const bool rep = a[2] == 'r';
      if (*end || x < (rep ? 1 : 0) || x > (rep ? 1000000 : 4096)) {
        std::fprintf(stderr, "granary run: %s '%s': expected an integer in %s\n", a, v, rep ? "1..1000000" : "0..4096");
        return 2;
      }
      (rep ? replicas : threads) = x;
    } else if (!std::strcmp(a, "--verbose")) {
      cli_verbose = 1;
    } else if (!std::strcmp(a, "--force")) {
      force = true;
    } else if (!std::strcmp(a, "--no-checkpoint")) {
      no_ckpt = true;
    } else if (!std::strcmp(a, "--resume")) {
      if (!(resume = need(a))) return 2;
    } else if (!std::strcmp(a, "--quiet") || !std::strcmp(a, "-q")) {
      quiet = true;
    } else if (!std::strcmp(a, "--stop-after-checkpoints")) {
      const char *v = need(a);
      if (!v) return 2;
      char *end = nullptr;
      stop_after = std::strtoll(v, &end, 10);
      if (*end || stop_after < 1) {
        std::fprintf(stderr, "granary run: --stop-after-checkpoints '%s': expected an integer >= 1\n", v);
        return 2;
      }
    } else if (a[0] == '-' && a[1] != '\0') {
      std::fprintf(stderr, "granary run: unknown option '%s'\n", a);
      run_usage(stderr);
      return 2;
    } else if (!scene_path) {
      scene_path = a;
    } else {
      std::fprintf(stderr, "granary run: more than one scene given ('%s')\n", a);
      return 2;
    }
  }
  if (!!scene_path == !!resume) {
    std::fprintf(stderr, "granary run: give a SCENE or --resume CHECKPOINT (exactly one)\n");
    run_usage(stderr);
    return 2;
  }
  if (resume && (checkpoint || no_ckpt)) {
    std::fprintf(stderr, "granary run: --resume keeps writing checkpoints to the file it resumes from\n");
    return 2;
  }
  if (checkpoint && no_ckpt) {
    std::fprintf(stderr, "granary run: --checkpoint and --no-checkpoint exclude each other\n");
    return 2;
  }

  if (resume && replicas) {
    std::fprintf(stderr, "granary run: --resume continues with the replicas of the checkpoint (no --replicas)\n");
    return 2;
  }
  if (threads >= 0 && gran_set_threads((int32_t)threads)) return fail("--threads");
  /* several processes (build/granary-mpi under mpirun): rank 0 alone prints progress and results,
   * and every decision that ends the run early is taken by all processes together */
  const bool root = cli_mpi_rank() == 0;
  if (!root) quiet = true;
  Progress pr;
  pr.tty = isatty(2);
  pr.quiet = quiet;
  gran_run_control ctl = {};
  ctl.stop_after_checkpoints = stop_after;
  ctl.progress = progress_cb;
  ctl.progress_params = &pr;
  gran_run_result res = {};
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  /* a write beyond the file size limit fails with EFBIG (a named error) instead of killing */
  std::signal(SIGXFSZ, SIG_IGN);

  std::string out_path;
  int st;
  if (resume) {
    if (output) {
      out_path = output;
    } else if (root) {
      /* the output path stored in the checkpoint (read first: a finished run removes the file) */
      int64_t f = gran_h5::open_file(resume, 0);
      std::string o;
      if (f >= 0 && !gran_h5::read_attr_string(f, "output", o, resume)) out_path = o;
      gran_h5::close_file(f);
      gran_clear_error();
    }
    const bool exists = root && !force && !out_path.empty() && file_exists(out_path);
    if (exists)
      std::fprintf(stderr, "granary run: output '%s' exists; give --force to overwrite it, or -o another file\n",
                   out_path.c_str());
    if (!cli_mpi_all(!exists)) return 1;
    st = gran_scene_resume(resume, output, &ctl, &res);
    if (st) return fail("resume failed");
  } else {
    gran_scene *scene = nullptr;
    const int loaded = gran_scene_load(scene_path, &scene) == GRAN_SUCCESS;
    if (!loaded) fail_here("invalid scene");
    if (!cli_mpi_all(loaded)) {
      gran_scene_destroy(&scene);
      return 1;
    }
    if (replicas && gran_scene_set_replicas(scene, replicas, scene->keep_replicas)) {
      gran_scene_destroy(&scene);
      return fail("--replicas");
    }
    const char *p = nullptr;
    gran_scene_output_path(scene, &p);
    out_path = output ? output : p;
    const bool exists = root && !force && file_exists(out_path);
    if (exists)
      std::fprintf(stderr, "granary run: output '%s' exists; give --force to overwrite it, or -o another file\n",
                   out_path.c_str());
    if (!cli_mpi_all(!exists)) {
      gran_scene_destroy(&scene);
      return 1;
    }
    const std::string ck_path = no_ckpt ? "" : gran_run_checkpoint_path_(scene, output, checkpoint);
    if (!quiet) header(scene, out_path, ck_path);
    st = gran_scene_run(scene, output, no_ckpt ? "" : checkpoint, &ctl, &res);
    if (st) {
      fail("run failed");
      gran_scene_destroy(&scene);
      return 1;
    }
    gran_scene_destroy(&scene);
    if (!res.finished) return root ? stopped(res, out_path, ck_path) : stop_code();
  }
  if (!res.finished) return root ? stopped(res, out_path, resume) : stop_code();
  if (!root) return 0;
  int64_t nwarn = 0;
  gran_warning_count(&nwarn);
  if (nwarn > 0) {
    char w[1024];
    gran_last_warning_copy(w, sizeof w);
    std::fprintf(stderr, "granary run: %" PRId64 " warning(s); last: %s\n", nwarn, w);
  }
  /* the work unit of the engine that wrote the file: DSMC collisions, GSRD particle-steps */
  std::string eng = "dsmc";
  {
    const int64_t f = gran_h5::open_file(out_path.c_str(), 0);
    if (f >= 0) {
      if (gran_h5::read_attr_string(f, "engine", eng, out_path.c_str()) != GRAN_SUCCESS) eng = "dsmc";
      gran_h5::close_file(f);
    }
    gran_clear_error();
  }
  const char *unit = eng == "srd" ? "particle-steps" : "collisions";
  std::printf("granary run: wrote %s (%" PRId64 " %s, t = %.6g, %.1f s, %.3g %s/s)\n", out_path.c_str(), res.collisions,
              unit, res.time, res.wall_seconds, res.wall_seconds > 0 ? (double)res.collisions / res.wall_seconds : 0.0, unit);
  if (!quiet) summary(out_path);
  if (!quiet && cli_mpi_size() > 1) {
    long long steps = 0, bytes = 0;
    cli_mpi_stats(&steps, &bytes);
    std::printf("mpi: %d processes; rank 0 received %lld bytes from the others in %lld gathers\n", cli_mpi_size(), bytes,
                steps);
  }
  return 0;
}
