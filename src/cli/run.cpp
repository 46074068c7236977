/* run.cpp - `granary run SCENE [-o FILE] [--checkpoint FILE | --no-checkpoint] [--quiet]
 *            [--stop-after-checkpoints N]` and `granary run --resume CHECKPOINT [-o FILE]`.
 * Progress goes to stderr: one line rewritten with \r on a terminal, a plain line every 10 s
 * otherwise (logs stay readable). At the end: where the output went, and a short table of the
 * simulated T_k and MSD_k beside the theory, read back from the output file. */
#include <hdf5.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unistd.h>
#include <vector>

#include "cli.h"
#include "io/io_impl.h"

namespace {

volatile std::sig_atomic_t g_interrupted = 0;
void on_sigint(int) {
  g_interrupted = 1;
  std::signal(SIGINT, SIG_DFL); /* a second Ctrl-C kills at once */
}

void run_usage(FILE *f) {
  std::fprintf(f,
               "usage: granary run SCENE [-o FILE] [--force] [--checkpoint FILE | --no-checkpoint] [--quiet]\n"
               "       granary run --resume CHECKPOINT [-o FILE] [--quiet]\n"
               "  -o FILE                    HDF5 output (default: the scene's [output] path)\n"
               "  --force                    overwrite an existing output file (refused without it)\n"
               "  --checkpoint FILE          checkpoint file (default: the scene's [output] checkpoint,\n"
               "                             else OUTPUT.ckpt next to the output)\n"
               "  --no-checkpoint            write no checkpoints\n"
               "  --resume CHECKPOINT        continue a run from its checkpoint, bit for bit\n"
               "  --stop-after-checkpoints N stop after writing N checkpoints (for testing resume)\n"
               "  --quiet                    no progress line, no summary table\n"
               "  --verbose                  error messages name the function and source line\n"
               "  Ctrl-C stops at the next output time: the output file then holds the output times\n"
               "  reached (attribute complete = 0) and a checkpoint lets --resume finish the run.\n");
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

/* The summary: a few output times (spread over the run), simulated beside theory. */
void summary(const std::string &path) {
  int64_t f = gran_h5::open_file(path.c_str(), 0);
  if (f < 0) return;
  std::vector<double> t, T, Tth, msd, msdth;
  std::vector<int64_t> dT, dm;
  const char *p = path.c_str();
  bool haveT = gran_h5::exists(f, "temperatures") && !gran_h5::read_double(f, "temperatures/T", T, &dT, p);
  bool haveTth = haveT && gran_h5::exists(f, "temperatures/T_theory") && !gran_h5::read_double(f, "temperatures/T_theory", Tth, nullptr, p);
  bool haveM = gran_h5::exists(f, "msd") && !gran_h5::read_double(f, "msd/msd", msd, &dm, p);
  bool haveMth = haveM && gran_h5::exists(f, "msd/msd_theory") && !gran_h5::read_double(f, "msd/msd_theory", msdth, nullptr, p);
  bool haveTime = !gran_h5::read_double(f, "time", t, nullptr, p);
  std::vector<double> ek, e0;
  std::vector<int64_t> coll;
  bool haveE = gran_h5::exists(f, "energy") && !gran_h5::read_double(f, "energy/e_kin", ek, nullptr, p) &&
               !gran_h5::read_double(f, "energy/e_initial", e0, nullptr, p);
  bool haveC = !gran_h5::read_int64(f, "stats/collisions", coll, nullptr, p);
  gran_h5::close_file(f);
  gran_clear_error();
  if (!haveTime || (!haveT && !haveM)) return;
  const int64_t nt = (int64_t)t.size();
  const int64_t M = haveT ? dT[1] : dm[1];
  /* rows: about 5 output times spread evenly over the index range (log-spaced times stay log-spaced) */
  std::vector<int64_t> rows;
  const int want = 5;
  for (int i = 0; i < want; i++) {
    int64_t r = nt <= 1 ? 0 : (int64_t)std::llround((double)(nt - 1) * (i + 1) / want);
    if (rows.empty() || rows.back() != r) rows.push_back(r);
  }
  const int64_t Mshow = M > 6 ? 6 : M;
  /* only the columns the run recorded: no MSD columns when MSD was off, no theory when it was off */
  std::printf("\n%12s %4s", "time", "k");
  if (haveT) std::printf(" | %12s %12s %8s", "T_sim", haveTth ? "T_theory" : "", haveTth ? "dev" : "");
  if (haveM) std::printf(" | %12s %12s %8s", "MSD_sim", haveMth ? "MSD_theory" : "", haveMth ? "dev" : "");
  std::printf("\n");
  auto dev = [](double a, double b) -> std::string {
    char s[32];
    if (!std::isfinite(a) || !std::isfinite(b) || b == 0) return "";
    std::snprintf(s, sizeof s, "%+.2f%%", 100.0 * (a - b) / b);
    return s;
  };
  auto cell = [](double x) -> std::string {
    char s[32];
    if (std::isnan(x)) return "-"; /* an empty species */
    std::snprintf(s, sizeof s, "%.6g", x);
    return s;
  };
  for (int64_t r : rows) {
    for (int64_t k = 0; k < Mshow; k++) {
      const size_t i = (size_t)(r * M + k);
      std::printf("%12.5g %4" PRId64, t[(size_t)r], k + 1);
      if (haveT)
        std::printf(" | %12s %12s %8s", cell(T[i]).c_str(), haveTth ? cell(Tth[i]).c_str() : "",
                    haveTth ? dev(T[i], Tth[i]).c_str() : "");
      if (haveM)
        std::printf(" | %12s %12s %8s", cell(msd[i]).c_str(), haveMth ? cell(msdth[i]).c_str() : "",
                    haveMth ? dev(msd[i], msdth[i]).c_str() : "");
      std::printf("\n");
    }
  }
  if (Mshow < M) std::printf("(species 1..%" PRId64 " of %" PRId64 " shown; everything is in %s)\n", Mshow, M, p);
  if (haveE && !ek.empty())
    std::printf("at t = %.6g: total kinetic energy %.6g (initially %.6g)%s", t.back(), ek.back(), e0.back(),
                haveC && !coll.empty() ? "" : "\n");
  if (haveC && !coll.empty()) std::printf("%s%" PRId64 " collisions\n", haveE ? ", " : "", coll.back());
}

int fail(const char *what) {
  std::fprintf(stderr, "granary run: %s: %s\n", what, cli_error());
  return 1;
}

}  // namespace

int cli_run(int argc, char **argv) {
  const char *scene_path = nullptr, *output = nullptr, *checkpoint = nullptr, *resume = nullptr;
  bool quiet = false, no_ckpt = false, force = false;
  long long stop_after = 0;
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
    } else if (!std::strcmp(a, "--no-checkpoint")) {
      no_ckpt = true;
    } else if (!std::strcmp(a, "--force")) {
      force = true;
    } else if (!std::strcmp(a, "--verbose")) {
      cli_verbose = 1;
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

  Progress pr;
  pr.tty = isatty(2);
  pr.quiet = quiet;
  gran_run_control ctl = {};
  ctl.stop_after_checkpoints = stop_after;
  ctl.progress = progress_cb;
  ctl.progress_params = &pr;
  gran_run_result res = {};
  std::signal(SIGINT, on_sigint);

  std::string out_path;
  int st;
  if (resume) {
    if (output) {
      out_path = output;
    } else {
      /* the output path stored in the checkpoint (read first: a finished run removes the file) */
      int64_t f = gran_h5::open_file(resume, 0);
      std::string o;
      if (f >= 0 && !gran_h5::read_attr_string(f, "output", o, resume)) out_path = o;
      gran_h5::close_file(f);
      gran_clear_error();
    }
    st = gran_scene_resume(resume, output, &ctl, &res);
    if (st) return fail("resume failed");
  } else {
    gran_scene *scene = nullptr;
    if (gran_scene_load(scene_path, &scene)) return fail("invalid scene");
    const char *p = nullptr;
    gran_scene_output_path(scene, &p);
    out_path = output ? output : p;
    if (!quiet) {
      /* what is about to run, before any work */
      int64_t M = 0, nt = 0, nl = 0, c = 0;
      double t0 = 0, t1 = 0;
      gran_scene_sizes(scene, &M, &nt, &nl, &t0, &t1);
      std::vector<int64_t> counts((size_t)M);
      gran_dsmc_options opt;
      int64_t N = 0;
      if (gran_scene_dsmc_options(scene, &opt, counts.data(), nullptr) == GRAN_SUCCESS)
        for (int64_t x : counts) N += x;
      (void)c;
      std::string ck = no_ckpt ? "none" : checkpoint ? checkpoint
                                        : (output && !scene->checkpoint_explicit && !scene->checkpoint_path.empty())
                                            ? out_path + ".ckpt"
                                            : scene->checkpoint_path.empty() ? "none" : scene->checkpoint_path;
      std::printf("granary run: %s\n", scene->title.empty() ? scene_path : scene->title.c_str());
      std::printf("  scene %s: %" PRId64 " species, %" PRId64 " particles, %s selector, seed %" PRIu64 "\n", scene_path,
                  M, N, scene->selector == GRAN_SELECTOR_BIRD ? "Bird" : "low-rank", scene->seed);
      std::printf("  t = %g .. %g, %" PRId64 " output times%s\n", t0, t1, nt, nl ? ", TAMSD" : "");
      std::printf("  output %s, checkpoint %s\n", out_path.c_str(), ck.c_str());
      std::fflush(stdout);
    }
    if (!force && access(out_path.c_str(), F_OK) == 0) {
      std::fprintf(stderr, "granary run: the output file '%s' exists; give --force to overwrite it (or -o FILE)\n",
                   out_path.c_str());
      gran_scene_destroy(&scene);
      return 1;
    }
    st = gran_scene_run(scene, output, no_ckpt ? "" : checkpoint, &ctl, &res);
    if (st) {
      fail("run failed");
      gran_scene_destroy(&scene);
      return 1;
    }
    std::string ck_default = scene->checkpoint_path;
    if (output && !scene->checkpoint_explicit && !ck_default.empty()) ck_default = std::string(output) + ".ckpt";
    if (!res.finished && !checkpoint && !no_ckpt) checkpoint = ck_default.c_str();
    std::string ck = checkpoint ? checkpoint : "";
    gran_scene_destroy(&scene);
    if (!res.finished) {
      std::fprintf(stderr, "granary run: stopped at t = %.6g after %" PRId64 " checkpoint(s)%s%s; continue with\n"
                           "  granary run --resume %s\n", res.time, res.checkpoints,
                   g_interrupted ? "; output times reached so far are in " : "", g_interrupted ? out_path.c_str() : "",
                   ck.empty() ? "(no checkpoint)" : ck.c_str());
      return g_interrupted ? 130 : 0;
    }
  }
  if (!res.finished) {
    std::fprintf(stderr, "granary run: stopped at t = %.6g after %" PRId64 " checkpoint(s); continue with\n"
                         "  granary run --resume %s\n", res.time, res.checkpoints, resume);
    return g_interrupted ? 130 : 0;
  }
  int64_t nwarn = 0;
  gran_warning_count(&nwarn);
  if (nwarn > 0) {
    char w[1024];
    gran_last_warning_copy(w, sizeof w);
    std::fprintf(stderr, "granary run: %" PRId64 " warning(s); last: %s\n", nwarn, w);
  }
  std::printf("granary run: wrote %s (%" PRId64 " collisions, t = %.6g, %.1f s, %.3g collisions/s)\n", out_path.c_str(),
              res.collisions, res.time, res.wall_seconds, res.wall_seconds > 0 ? (double)res.collisions / res.wall_seconds : 0.0);
  if (!quiet) summary(out_path);
  return 0;
}
