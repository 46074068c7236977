/* run.cpp - `granary run SCENE [-o FILE] [--checkpoint FILE | --no-checkpoint] [--set KEY=VALUE]
 *            [--log FILE | --no-log] [--quiet] [--stop-after-checkpoints N]` and
 *            `granary run --resume CHECKPOINT [-o FILE]`.
 * Progress goes to stderr: one line rewritten with \r on a terminal, a plain line every 10 s
 * otherwise (logs stay readable). At the end: where the output went, and a short table of the
 * simulated T_k and MSD_k beside the theory, read back from the output file. The run log
 * (OUTPUT.log unless --log / --no-log) holds the input (command line, version, threads, scene
 * text), the progress, a thermo table and the summary; it is appended to line by line, so a
 * killed run leaves what it had written. */
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cinttypes>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
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
               "usage: granary run SCENE [-o FILE] [--checkpoint FILE | --no-checkpoint] [--set KEY=VALUE]...\n"
               "                   [--log FILE | --no-log] [--force] [--quiet]\n"
               "       granary run --resume CHECKPOINT [-o FILE] [--log FILE | --no-log] [--force] [--quiet]\n"
               "  -o, --output FILE          HDF5 output (default: the scene's [output] path)\n"
               "  --checkpoint FILE          checkpoint file (default: the scene's, else OUTPUT.ckpt of -o)\n"
               "  --no-checkpoint            write no checkpoints\n"
               "  --set KEY=VALUE            override a scene key (repeatable): KEY is table.key, VALUE TOML\n"
               "                             (--set engine.seed=7 --set output.path='\"x.h5\"'); checked like\n"
               "                             the scene file, and stored with the scene text (resume keeps it)\n"
               "  --log FILE                 the run log (default: OUTPUT.log; --log none: no log)\n"
               "  --no-log                   write no run log\n"
               "  --log-every N              a thermo row every N output times (default: about 50 rows)\n"
               "  --force                    overwrite an existing output file (refused otherwise)\n"
               "  --replicas R               R independent runs (default: the scene's [engine] replicas, 1);\n"
               "                             the output holds the mean X and its standard error X_se\n"
               "  --threads N                threads for the replicas (default: OMP_NUM_THREADS or all cores)\n"
               "  --resume CHECKPOINT        continue a run from its checkpoint, bit for bit\n"
               "  --stop-after-checkpoints N stop after writing N checkpoints (for testing resume)\n"
               "  --timeout S                (granary-mpi) the longest one process waits for another in one gather\n"
               "                             or broadcast of the replicas before it stops every process, naming\n"
               "                             the one it waits for (default 0: no limit; set it above the steps\n"
               "                             of the slowest replica between two output times and rank 0's\n"
               "                             writing of a checkpoint); a gas split over the processes\n"
               "                             ([engine] decomposition): every exchange of its steps too (default 600)\n"
               "  -q, --quiet                no progress line, no summary table (the log keeps both)\n"
               "  --verbose                  error messages name the library function and source line\n"
               "  -h, --help                 this text\n"
               "  Ctrl-C (SIGINT) or SIGTERM stops at the next output time after writing a checkpoint; what\n"
               "  was recorded so far goes to OUTPUT.partial.h5 (root attribute complete = 0).\n"
               "exit codes: 0 done (or stopped by --stop-after-checkpoints), 1 error (bad scene, refused\n"
               "  files, a failed run or write), 2 bad command line, 130 stopped by SIGINT, 143 by SIGTERM.\n");
}

/* The run log: appended to line by line (line buffered), so that a killed run leaves a readable
 * file. Rows of the thermo table every `every` output times; the wall time of each output time is
 * kept for the final table (read back with the temperatures from the output). */
struct RunLog {
  FILE *f = nullptr;
  std::string path;
  int64_t every = 0; /* 0: chosen at the first output time (about 50 rows) */
  bool user_every = false;
  bool header = false;
  double last_line = -1e300;
  std::vector<double> wall; /* by output index - 1; NaN: not in this process */
  void close() {
    if (f) std::fclose(f);
    f = nullptr;
  }
};

struct Progress {
  bool tty = false, quiet = false;
  double last_print = -1e300;
  int width = 0;
  RunLog *log = nullptr;
};

std::string hms(double s) {
  if (!(s >= 0) || !std::isfinite(s)) return "?";
  char b[32];
  long t = (long)(s + 0.5);
  if (t >= 3600) std::snprintf(b, sizeof b, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else std::snprintf(b, sizeof b, "%ld:%02ld", t / 60, t % 60);
  return b;
}

/* The ETA once it means something: after 1 % of the work and 2 s of wall time ("?" before; the
 * first output times of a run are dominated by start-up and give estimates off by orders). */
std::string eta_text(const gran_run_progress *p) {
  if (p->noutputs > 0 && p->output_index >= p->noutputs) return hms(0.0);
  if (!(p->fraction >= 0.01) || !(p->wall_seconds >= 2.0)) return "?";
  return hms(p->eta_seconds);
}

/* the work the engine counts (gran_run_progress.work_unit): its name and the name of its rate */
const char *work_name(const gran_run_progress *p) {
  return p->work_unit == GRAN_WORK_PARTICLE_STEPS ? "particle-steps" : "collisions";
}
const char *rate_name(const gran_run_progress *p) {
  return p->work_unit == GRAN_WORK_PARTICLE_STEPS ? "psteps/s" : "coll/s";
}

void progress_line(const gran_run_progress *p, char *line, size_t len, int *n) {
  *n = std::snprintf(line, len, "[%5.1f%%] t = %-11.5g T = %-11.5g %s %-11" PRId64 " %9.3g %s  ETA %s",
                     100.0 * p->fraction, p->time, p->temperature, work_name(p), p->collisions,
                     p->collisions_per_second, rate_name(p), eta_text(p).c_str());
}

void log_progress(RunLog &lg, const gran_run_progress *p) {
  if (!lg.f) return;
  const int64_t i = p->output_index, N = p->noutputs;
  if (i >= 1 && i <= N) {
    if ((int64_t)lg.wall.size() < N) lg.wall.resize((size_t)N, NAN);
    lg.wall[(size_t)(i - 1)] = p->wall_seconds;
  }
  if (!lg.header) {
    if (lg.every <= 0) lg.every = std::max<int64_t>(1, (N + 49) / 50);
    std::fprintf(lg.f, "\n# thermo: a row every %" PRId64 " output time(s); lines starting with # are progress\n",
                 lg.every);
    std::fprintf(lg.f, "%8s %13s %13s %15s %11s %9s %7s %8s\n", "index", "t", "T", work_name(p), rate_name(p),
                 "wall_s", "done%", "ETA");
    lg.header = true;
  }
  const bool last = i == N;
  if (last || i == 1 || i % lg.every == 0)
    std::fprintf(lg.f, "%8" PRId64 " %13.6g %13.6g %15" PRId64 " %11.4g %9.2f %7.2f %8s\n", i, p->time, p->temperature,
                 p->collisions, p->collisions_per_second, p->wall_seconds, 100.0 * p->fraction, eta_text(p).c_str());
  if (p->wall_seconds - lg.last_line >= 10.0 && !last) {
    char line[256];
    int n = 0;
    progress_line(p, line, sizeof line, &n);
    std::fprintf(lg.f, "# %s\n", line);
    lg.last_line = p->wall_seconds;
  }
}

int progress_cb(const gran_run_progress *p, void *params) {
  Progress *pr = static_cast<Progress *>(params);
  if (pr->log) log_progress(*pr->log, p);
  if (!pr->quiet) {
    const bool last = p->output_index == p->noutputs;
    if (pr->tty || last || p->wall_seconds - pr->last_print >= 10.0) {
      char line[256];
      int n = 0;
      progress_line(p, line, sizeof line, &n);
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

/* What the summary and the log's final thermo table read back from the output file: the output
 * times, each column pair the engine lists in the `summary_columns` attribute (simulated beside
 * theory, only observables that are on), energy, collisions, species masses and densities. */
struct OutData {
  struct Col {
    std::string label;
    std::vector<double> sim, se, th;
    int64_t M = 0;
    bool theory = false; /* some theory value is finite */
  };
  std::vector<double> t, ek, e0, mass, dens;
  std::vector<int64_t> coll;
  std::vector<Col> cols;
  bool haveE = false, haveC = false;
  int64_t nrep = 1;
  bool ok = false;
};

OutData read_output(const std::string &path) {
  OutData d;
  int64_t f = gran_h5::open_file(path.c_str(), 0);
  if (f < 0) {
    gran_clear_error();
    return d;
  }
  const char *p = path.c_str();
  std::string spec;
  bool haveTime = !gran_h5::read_double(f, "time", d.t, nullptr, p);
  if (!gran_h5::read_attr_string(f, "summary_columns", spec, p)) {
    size_t at = 0;
    while (at < spec.size()) {
      size_t e = spec.find(';', at);
      if (e == std::string::npos) e = spec.size();
      std::string item = spec.substr(at, e - at);
      at = e + 1;
      size_t c1 = item.find(':'), c2 = item.find(':', c1 == std::string::npos ? 0 : c1 + 1);
      if (c1 == std::string::npos || c2 == std::string::npos) continue;
      OutData::Col c;
      c.label = item.substr(0, c1);
      std::string sim = item.substr(c1 + 1, c2 - c1 - 1), th = item.substr(c2 + 1);
      std::vector<int64_t> dims;
      if (!gran_h5::exists(f, sim.substr(0, sim.find('/')).c_str()) || gran_h5::read_double(f, sim.c_str(), c.sim, &dims, p))
        continue;
      c.M = dims.size() > 1 ? dims[1] : 1;
      const std::string se = sim + "_se";
      if (!gran_h5::exists(f, se.c_str()) || gran_h5::read_double(f, se.c_str(), c.se, nullptr, p)) c.se.clear();
      if (!th.empty() && !gran_h5::exists(f, th.c_str())) th.clear();
      if (!th.empty() && gran_h5::read_double(f, th.c_str(), c.th, nullptr, p)) c.th.clear();
      if (c.th.size() != c.sim.size()) c.th.assign(c.sim.size(), NAN);
      if (c.se.size() != c.sim.size()) c.se.clear();
      for (auto *v : {&c.sim, &c.se, &c.th}) /* the fill value (no value) prints as nan */
        for (double &x : *v)
          if (x == gran_row_fill) x = NAN;
      for (double x : c.th) c.theory = c.theory || std::isfinite(x);
      d.cols.push_back(std::move(c));
    }
  }
  d.haveE = gran_h5::exists(f, "energy") && !gran_h5::read_double(f, "energy/e_kin", d.ek, nullptr, p) &&
            !gran_h5::read_double(f, "energy/e_initial", d.e0, nullptr, p);
  d.haveC = gran_h5::exists(f, "stats") && !gran_h5::read_int64(f, "stats/collisions", d.coll, nullptr, p);
  if (!gran_h5::exists(f, "species") || gran_h5::read_double(f, "species/mass", d.mass, nullptr, p) ||
      gran_h5::read_double(f, "species/density", d.dens, nullptr, p)) {
    d.mass.clear();
    d.dens.clear();
  }
  if (H5Aexists((hid_t)f, "nreplicas") > 0) gran_h5::read_attr_int64(f, "nreplicas", &d.nrep, p);
  gran_h5::close_file(f);
  gran_clear_error();
  d.ok = haveTime && !d.t.empty();
  return d;
}

/* The summary: a few output times (spread over the run), each column pair of the output. A gas of
 * one species has no species column; a column without theory has no theory, dev, dev/se. */
void summary(const OutData &d, const std::string &path, FILE *o) {
  const auto &t = d.t;
  const auto &cols = d.cols;
  const auto &mass = d.mass, &dens = d.dens;
  const int64_t nrep = d.nrep;
  const char *p = path.c_str();
  if (!d.ok || cols.empty()) return;
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
  const bool kcol = M > 1;
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
  int c_hot = 0, c_cold = 0; /* footnote c on T: rows above / below the theory */
  std::fprintf(o, "\n%12s", "time");
  if (kcol) std::fprintf(o, " %4s", "k");
  for (const auto &c : cols) {
    const std::string sim = c.label + "_sim", th = c.label + "_theory";
    if (!c.theory && c.se.empty()) std::fprintf(o, " | %12s", sim.c_str());
    else if (!c.theory) std::fprintf(o, " | %12s %10s", sim.c_str(), "+- se");
    else if (c.se.empty()) std::fprintf(o, " | %12s %12s %8s", sim.c_str(), th.c_str(), "dev");
    else std::fprintf(o, " | %12s %10s %12s %8s %8s", sim.c_str(), "+- se", th.c_str(), "dev", "dev/se");
  }
  std::fprintf(o, "\n");
  auto dev = [](double a, double b) -> std::string {
    char s[32];
    if (!std::isfinite(a) || !std::isfinite(b) || b == 0) return "";
    std::snprintf(s, sizeof s, "%+.2f%%", 100.0 * (a - b) / b);
    return s;
  };
  for (int64_t r : rows) {
    for (int64_t k = 0; k < Mshow; k++) {
      std::fprintf(o, "%12.5g", t[(size_t)r]);
      if (kcol) std::fprintf(o, " %4" PRId64, k + 1);
      for (const auto &c : cols) {
        const size_t i = (size_t)(r * c.M + k);
        const double a = k < c.M ? c.sim[i] : NAN, b = k < c.M ? c.th[i] : NAN;
        const double e = k < c.M && !c.se.empty() ? c.se[i] : NAN;
        if (!c.theory) {
          if (c.se.empty()) std::fprintf(o, " | %12.6g", a);
          else std::fprintf(o, " | %12.6g %10.3g", a, e);
          continue;
        }
        const char *n = k < c.M && std::isfinite(b) ? note(c.label, k) : "";
        if (*n) used[*n - 'a'] = true;
        if (*n == 'c' && c.label == "T" && std::isfinite(a)) (a > b ? c_hot : c_cold)++;
        if (c.se.empty()) {
          std::fprintf(o, " | %12.6g %12.6g %8s", a, b, dev(a, b).c_str());
        } else {
          char z[32] = "";
          if (std::isfinite(a) && std::isfinite(b) && e > 0) std::snprintf(z, sizeof z, "%+.1f%s", (a - b) / e, n);
          std::fprintf(o, " | %12.6g %10.3g %12.6g %8s %8s", a, e, b, dev(a, b).c_str(), z);
        }
      }
      std::fprintf(o, "\n");
    }
  }
  if (Mshow < M) std::fprintf(o, "(species 1..%" PRId64 " of %" PRId64 " shown; everything is in %s)\n", Mshow, M, p);
  if (nrep > 1) {
    std::fprintf(o, "mean over %" PRId64 " replicas +- its standard error; dev/se: (sim - theory) / se\n", nrep);
    if (used[0])
      std::fprintf(o, "  a: the Maxwellian theory of T_k in a mixture is off by about 0.6-1.2 %% (first Sonine correction)\n");
    if (used[1])
      std::fprintf(o, "  b: light species among heavy ones diffuse 10-14 %% faster than Eq. 4 predicts (Lorentz gas: 32/(9 pi))\n");
    if (used[2]) {
      if (c_hot > 0 && c_cold == 0)
        std::fprintf(o, "  c: a heavy, dilute species (tracer limit, Bodrova & Osinsky Eq. 35) runs hotter than the Maxwellian theory:\n"
                        "     near or in the ordered phase of Santos and Dufty (b > 1) T_k/T_1 is well above it (physics, not noise)\n");
      else if (c_cold > 0 && c_hot == 0)
        std::fprintf(o, "  c: a heavy, dilute species (tracer limit, Bodrova & Osinsky Eq. 35) runs colder than the Maxwellian theory here\n");
      else
        std::fprintf(o, "  c: a heavy, dilute species (tracer limit, Bodrova & Osinsky Eq. 35): the Maxwellian theory of it is least accurate\n");
    }
  }
  const auto &ek = d.ek, &e0 = d.e0;
  const auto &coll = d.coll;
  const bool haveE = d.haveE, haveC = d.haveC;
  if (haveE && !ek.empty())
    std::fprintf(o, "at t = %.6g: total kinetic energy %.6g (initially %.6g)%s", t.back(), ek.back(), e0.back(),
                 haveC && !coll.empty() ? "" : "\n");
  if (haveC && !coll.empty())
    std::fprintf(o, "%s%" PRId64 " collisions%s\n", haveE ? ", " : "", coll.back(), nrep > 1 ? " (all replicas)" : "");
}

/* The log's thermo table of the finished run: every `every` output times (and the last), the
 * temperatures read back from the output (T, or T_1.. of a mixture), collisions, wall time. */
void thermo_final(const OutData &d, const RunLog &lg, FILE *o) {
  if (!d.ok) return;
  const OutData::Col *T = nullptr;
  for (const auto &c : d.cols)
    if (c.label == "T") {
      T = &c;
      break;
    }
  const int64_t nt = (int64_t)d.t.size(), every = lg.every > 0 ? lg.every : std::max<int64_t>(1, (nt + 49) / 50);
  const int64_t M = T ? T->M : 0, Ms = std::min<int64_t>(M, 4);
  std::fprintf(o, "\n# thermo of the run (from the output file): a row every %" PRId64 " output time(s)\n", every);
  std::fprintf(o, "%8s %13s", "index", "t");
  for (int64_t k = 0; k < Ms; k++) {
    char h[16];
    if (M == 1) std::snprintf(h, sizeof h, "T");
    else std::snprintf(h, sizeof h, "T_%" PRId64, k + 1);
    std::fprintf(o, " %12s", h);
  }
  if (M > Ms) std::fprintf(o, " %3s", "...");
  if (d.haveC) std::fprintf(o, " %15s", "collisions");
  std::fprintf(o, " %9s\n", "wall_s");
  for (int64_t i = 1; i <= nt; i++) {
    if (!(i == 1 || i == nt || i % every == 0)) continue;
    std::fprintf(o, "%8" PRId64 " %13.6g", i, d.t[(size_t)(i - 1)]);
    for (int64_t k = 0; k < Ms; k++) std::fprintf(o, " %12.6g", T->sim[(size_t)((i - 1) * M + k)]);
    if (M > Ms) std::fprintf(o, " %3s", "");
    if (d.haveC) {
      if ((int64_t)d.coll.size() >= i) std::fprintf(o, " %15" PRId64, d.coll[(size_t)(i - 1)]);
      else std::fprintf(o, " %15s", "-");
    }
    const double w = (int64_t)lg.wall.size() >= i ? lg.wall[(size_t)(i - 1)] : NAN;
    if (std::isfinite(w)) std::fprintf(o, " %9.2f\n", w);
    else std::fprintf(o, " %9s\n", "-"); /* before a resume */
  }
  if (M > Ms) std::fprintf(o, "(T_1..T_%" PRId64 " of %" PRId64 " species shown)\n", Ms, M);
}

/* The title and main parameters, printed before the run starts. */
void header(const gran_scene *s, const std::string &out, const std::string &ck, FILE *o) {
  std::fprintf(o, "%s\n", s->title.empty() ? s->name.c_str() : s->title.c_str());
  if (s->engine_type == "srd") { /* GSRD scene (src/io/engine_srd.cpp): its own parameters */
    const gran_srd_options &so = s->srd.opt;
    double nc = 1;
    for (int k = 0; k < so.dim; k++) nc *= (double)so.cells[k];
    std::fprintf(o, "  engine srd (%s), %d-D, %.0f cells of a = %g, %.0f particles, dt = %g, alpha = %g, eps = %g\n",
                s->srd.device.c_str(), (int)so.dim, nc, so.a, std::floor(so.n0 * nc + 0.5), so.dt, so.alpha_deg, so.eps);
    std::fprintf(o, "  t = 0 .. %g (%lld steps), %zu output times, seed %llu", s->t_end, (long long)s->srd.steps,
                s->times.size(), (unsigned long long)s->seed);
    if (s->replicas > 1) std::fprintf(o, ", %" PRId64 " replicas", s->replicas);
    if (s->split_gas && cli_mpi_size() > 1 && cli_mpi_size() > s->replicas && cli_mpi_size() % s->replicas == 0)
      std::fprintf(o, ", %s split over %lld processes", s->replicas > 1 ? "each replica's gas" : "the gas",
                   (long long)(cli_mpi_size() / s->replicas));
    std::fprintf(o, "\n  output %s, checkpoint %s\n", out.c_str(), ck.empty() ? "(none)" : ck.c_str());
    std::fflush(o);
    return;
  }
  int64_t N = 0;
  for (int64_t c : s->counts) N += c;
  std::fprintf(o, "  engine %s (%s), %" PRId64 " species", s->engine_type.c_str(),
              s->selector == GRAN_SELECTOR_BIRD ? "bird" : s->selector == GRAN_SELECTOR_CELL ? "cell" : "lowrank",
              s->nspecies);
  if (s->counts_kind == 0) std::fprintf(o, ", %" PRId64 " particles", N);
  else if (s->counts_kind == 1) std::fprintf(o, ", N1 = %.6g", s->N1);
  else std::fprintf(o, ", volume %.6g", s->volume);
  std::fprintf(o, ", restitution %s", s->model == GRAN_RESTITUTION_VISCOELASTIC ? "viscoelastic" : "constant");
  if (s->model != GRAN_RESTITUTION_VISCOELASTIC && s->eps_matrix.empty()) std::fprintf(o, " eps = %g", s->eps);
  std::fprintf(o, "\n  t = %g .. %g, %zu output times, seed %llu", s->t_start, s->t_end, s->times.size(),
              (unsigned long long)s->seed);
  if (s->replicas > 1) {
    int32_t th = 1;
    gran_get_threads(&th);
    const int P = cli_mpi_size();
    const int64_t per = (s->replicas + P - 1) / P;
    if (P > 1) std::fprintf(o, ", %" PRId64 " replicas on %d processes x %d thread(s)", s->replicas, P, (int)std::min<int64_t>(th, per));
    else std::fprintf(o, ", %" PRId64 " replicas on %d thread(s)", s->replicas, (int)std::min<int64_t>(th, s->replicas));
  }
  std::fprintf(o, "\n  output %s, checkpoint %s\n", out.c_str(), ck.empty() ? "(none)" : ck.c_str());
  std::fflush(o);
}

bool file_exists(const std::string &p) {
  struct stat sb;
  return stat(p.c_str(), &sb) == 0;
}

/* A run stopped before its end: what was recorded is in the partial output. */
int stopped(const gran_run_result &res, const std::string &out, const std::string &ck, FILE *log) {
  const std::string part = gran_partial_path_(out);
  for (FILE *o : {stderr, log}) {
    if (!o) continue;
    std::fprintf(o, "granary run: stopped at t = %.6g after %" PRId64 " checkpoint(s); the output times recorded so far are in\n"
                    "  %s (complete = 0); %s is written when the run finishes.\n", res.time, res.checkpoints,
                 part.c_str(), out.c_str());
    if (ck.empty()) std::fprintf(o, "  No checkpoint was written (--no-checkpoint): the run cannot be continued.\n");
    else std::fprintf(o, "  Continue with: granary run --resume %s\n", ck.c_str());
  }
  return stop_code();
}

FILE *g_log = nullptr; /* the run log of this process (rank 0), for the failure messages */

int fail(const char *what) {
  /* a collective failure carries the same message on every process: rank 0 prints it */
  if (cli_mpi_rank() == 0) {
    std::fprintf(stderr, "granary run: %s: %s\n", what, cli_error());
    if (g_log) std::fprintf(g_log, "granary run: %s: %s\n", what, cli_error());
  }
  return 1;
}

/* A failure only this process saw (several processes): it prints it, naming itself. */
int fail_here(const char *what) {
  if (cli_mpi_size() > 1) std::fprintf(stderr, "granary run: process %d of %d: %s: %s\n", cli_mpi_rank(), cli_mpi_size(), what, cli_error());
  else std::fprintf(stderr, "granary run: %s: %s\n", what, cli_error());
  return 1;
}

/* The log must be a file of its own: not the scene, the output, the checkpoint or their .tmp. */
bool log_path_ok(const std::string &log, const std::vector<std::pair<std::string, std::string>> &roles) {
  struct stat sb;
  if (stat(log.c_str(), &sb) == 0 && S_ISDIR(sb.st_mode)) {
    std::fprintf(stderr, "granary run: --log '%s' is a folder\n", log.c_str());
    return false;
  }
  const std::string id = gran_file_identity_(log);
  for (const auto &r : roles) {
    if (r.second.empty()) continue;
    for (const std::string &q : {r.second, r.second + ".tmp"})
      if (gran_file_identity_(q) == id) {
        std::fprintf(stderr, "granary run: the log '%s' and the %s%s '%s' are the same file; give --log another file\n",
                     log.c_str(), q == r.second ? "" : "temporary file of the ", r.first.c_str(), q.c_str());
        return false;
      }
  }
  return true;
}

/* The command line as typed (arguments with spaces or quotes in single quotes). */
std::string command_line(int argc, char **argv) {
  std::string c = "granary";
  for (int i = 0; i < argc; i++) {
    const std::string a = argv[i];
    const bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                                         "_-+=./,:@%") == std::string::npos;
    if (plain) {
      c += " " + a;
      continue;
    }
    c += " '";
    for (char ch : a) c += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    c += "'";
  }
  return c;
}

/* The input echo at the top of a log (and of each resumed part). */
void log_input(FILE *f, int argc, char **argv, const std::string &what, const std::string &text) {
  char when[64] = "";
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  if (gmtime_r(&now, &tm)) std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &tm);
  const char *cfg = "";
  gran_get_build_config(&cfg);
  int32_t th = 0;
  gran_get_threads(&th);
  const char *omp = std::getenv("OMP_NUM_THREADS");
  std::fprintf(f, "# granary run log\n");
  std::fprintf(f, "command:   %s\n", command_line(argc, argv).c_str());
  std::fprintf(f, "started:   %s\n", when);
  std::fprintf(f, "version:   granary %s (%s)\n", GRAN_VERSION_STRING, cfg);
  std::fprintf(f, "threads:   %d for the replicas (OMP_NUM_THREADS %s, %ld cores online)\n", (int)th,
               omp ? omp : "unset", sysconf(_SC_NPROCESSORS_ONLN));
  if (cli_mpi_size() > 1) std::fprintf(f, "processes: %d\n", cli_mpi_size());
  std::fprintf(f, "%s\n", what.c_str());
  std::fprintf(f, "----- scene text (as run) -----\n%s%s----- end of scene text -----\n", text.c_str(),
               !text.empty() && text.back() == '\n' ? "" : "\n");
}

}  // namespace

int cli_run(int argc, char **argv) {
  const char *scene_path = nullptr, *output = nullptr, *checkpoint = nullptr, *resume = nullptr, *log_opt = nullptr;
  bool quiet = false, no_ckpt = false, force = false, no_log = false;
  long long stop_after = 0, replicas = 0, threads = -1, log_every = 0;
  double timeout = 0.0; /* granary-mpi: seconds one process waits in a gather or broadcast; 0: no limit */
  bool timeout_given = false;
  std::vector<std::pair<std::string, std::string>> sets; /* --set KEY=VALUE, in order */
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
    } else if (!std::strcmp(a, "--set")) {
      const char *v = need(a);
      if (!v) return 2;
      const char *eq = std::strchr(v, '=');
      if (!eq || eq == v) {
        std::fprintf(stderr, "granary run: --set '%s': expected KEY=VALUE (e.g. --set engine.seed=7)\n", v);
        return 2;
      }
      sets.emplace_back(std::string(v, (size_t)(eq - v)), std::string(eq + 1));
    } else if (!std::strcmp(a, "--log")) {
      if (!(log_opt = need(a))) return 2;
      if (!*log_opt) {
        std::fprintf(stderr, "granary run: --log '': give a file, or --log none / --no-log for no log\n");
        return 2;
      }
      if (!std::strcmp(log_opt, "none")) no_log = true, log_opt = nullptr;
      else no_log = false;
    } else if (!std::strcmp(a, "--no-log")) {
      no_log = true;
      log_opt = nullptr;
    } else if (!std::strcmp(a, "--log-every")) {
      const char *v = need(a);
      if (!v) return 2;
      char *end = nullptr;
      log_every = std::strtoll(v, &end, 10);
      if (*end || log_every < 1) {
        std::fprintf(stderr, "granary run: --log-every '%s': expected an integer >= 1\n", v);
        return 2;
      }
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
    } else if (!std::strcmp(a, "--timeout")) {
      const char *v = need(a);
      if (!v) return 2;
      if (!cli_seconds(v, &timeout)) {
        std::fprintf(stderr, "granary run: --timeout '%s': expected seconds in [0, 1e7] (0: no limit)\n", v);
        return 2;
      }
      timeout_given = true;
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
  if (resume && !sets.empty()) {
    std::fprintf(stderr, "granary run: --resume continues the scene stored in the checkpoint (no --set)\n");
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
  cli_mpi_set_timeout(timeout);
  /* several processes (build/granary-mpi under mpirun): rank 0 alone prints progress and results,
   * and every decision that ends the run early is taken by all processes together */
  const bool root = cli_mpi_rank() == 0;
  if (!root) quiet = true;
  Progress pr;
  pr.tty = isatty(2);
  pr.quiet = quiet;
  RunLog lg;
  lg.every = log_every;
  lg.user_every = log_every > 0;
  gran_run_control ctl = {};
  ctl.stop_after_checkpoints = stop_after;
  ctl.progress = progress_cb;
  ctl.progress_params = &pr;
  gran_run_result res = {};
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  /* a write beyond the file size limit fails with EFBIG (a named error) instead of killing */
  std::signal(SIGXFSZ, SIG_IGN);

  /* the log: checked against the run's other files, then opened (rank 0; every process agrees) */
  auto open_log = [&](const std::string &out, const std::vector<std::pair<std::string, std::string>> &roles,
                      bool append) -> bool {
    bool ok = true;
    if (root && !no_log) {
      lg.path = log_opt ? log_opt : out + ".log";
      ok = log_path_ok(lg.path, roles);
      if (ok) {
        /* the folder of the output (out/ of a fresh checkout) is made before the run makes it */
        if (gran_make_parent_(lg.path) != GRAN_SUCCESS) gran_clear_error();
        lg.f = std::fopen(lg.path.c_str(), append ? "a" : "w");
        if (!lg.f && log_opt) {
          std::fprintf(stderr, "granary run: cannot open the log '%s': %s\n", lg.path.c_str(), std::strerror(errno));
          ok = false;
        } else if (!lg.f) { /* the default beside the output: the run's own checks name the folder */
          std::fprintf(stderr, "granary run: no log: cannot open '%s': %s\n", lg.path.c_str(), std::strerror(errno));
        } else {
          std::setvbuf(lg.f, nullptr, _IOLBF, 0);
          pr.log = &lg;
          g_log = lg.f;
        }
      }
    }
    return cli_mpi_all(ok) != 0;
  };
  struct LogCloser {
    RunLog &l;
    ~LogCloser() {
      g_log = nullptr;
      l.close();
    }
  } log_closer{lg};

  /* a split gas's processes wait for each other at every step: a stopped one is found by default;
   * replicas of a split gas: each on its own group of P / R processes (false: said why) */
  auto split_groups = [&](int64_t replicas) -> bool {
    if (cli_mpi_size() == 1) return true;
    if (!timeout_given) cli_mpi_set_timeout(600.0);
    if (cli_mpi_bricks_groups((int)std::max<int64_t>(1, std::min<int64_t>(replicas, INT32_MAX))) == 0) return true;
    std::fprintf(stderr, "granary run: MPI: cannot split the processes into the replicas' groups\n");
    return false;
  };

  std::string out_path;
  int st;
  if (resume) {
    std::string text, name, split_info; /* split_info: the replicas of a split gas ("" when not split) */
    if (output) out_path = output;
    if (root) {
      /* the output path and scene stored in the checkpoint (read first: a finished run removes the file) */
      int64_t f = gran_h5::open_file(resume, 0);
      std::string o;
      if (f >= 0 && !output && !gran_h5::read_attr_string(f, "output", o, resume)) out_path = o;
      if (f >= 0 && gran_h5::read_attr_string(f, "scene", text, resume)) text.clear();
      if (f >= 0 && gran_h5::read_attr_string(f, "scene_file", name, resume)) name.clear();
      int64_t nrep = 1;
      if (f >= 0 && H5Aexists((hid_t)f, "nreplicas") > 0 && gran_h5::read_attr_int64(f, "nreplicas", &nrep, resume)) nrep = 1;
      gran_h5::close_file(f);
      gran_clear_error();
      /* a split gas: its replicas' process groups, as for a run of the scene */
      gran_scene *sc = nullptr;
      if (!text.empty() && gran_scene_parse_text_(text, name, &sc) == GRAN_SUCCESS && sc->split_gas)
        split_info = std::to_string(nrep);
      gran_scene_destroy(&sc);
      gran_clear_error();
    }
    if (cli_mpi_size() > 1 && cli_mpi_bcast(&split_info)) {
      std::fprintf(stderr, "granary run: MPI: the broadcast of the checkpoint's split failed\n");
      return 1;
    }
    if (!split_info.empty() && !split_groups(std::atoll(split_info.c_str()))) return 1;
    const bool exists = root && !force && !out_path.empty() && file_exists(out_path);
    if (exists)
      std::fprintf(stderr, "granary run: output '%s' exists; give --force to overwrite it, or -o another file\n",
                   out_path.c_str());
    if (!cli_mpi_all(!exists)) return 1;
    if (!no_log && root && out_path.empty() && !log_opt) no_log = true; /* an unreadable checkpoint: resume names it */
    if (!open_log(out_path, {{"output", out_path}, {"checkpoint", resume}, {"partial output", out_path.empty() ? "" : gran_partial_path_(out_path)}},
                  true))
      return 1;
    if (lg.f) {
      std::fprintf(lg.f, "\n");
      log_input(lg.f, argc, argv, "resume:    " + std::string(resume) + " (scene " + name + ")", text);
      std::fprintf(lg.f, "  output %s, checkpoint %s\n", out_path.c_str(), resume);
    }
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
    for (const auto &kv : sets)
      if (gran_scene_set(scene, kv.first.c_str(), kv.second.c_str())) {
        gran_scene_destroy(&scene);
        return fail(("--set " + kv.first).c_str());
      }
    if (replicas && gran_scene_set_replicas(scene, replicas, scene->keep_replicas)) {
      gran_scene_destroy(&scene);
      return fail("--replicas");
    }
    /* a split gas's processes wait for each other at every step: a stopped one is found by default;
     * replicas of a split gas: each on its own group of P / R processes */
    if (scene->split_gas && !split_groups(scene->replicas)) {
      gran_scene_destroy(&scene);
      return 1;
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
    if (!open_log(out_path, {{"scene file", scene_path}, {"output", out_path}, {"checkpoint", ck_path},
                             {"partial output", gran_partial_path_(out_path)}},
                  false)) {
      gran_scene_destroy(&scene);
      return 1;
    }
    if (lg.f) {
      std::string what = "scene:     " + std::string(scene_path);
      for (const auto &kv : sets) what += "\n  --set    " + kv.first + " = " + kv.second;
      log_input(lg.f, argc, argv, what, scene->text);
      header(scene, out_path, ck_path, lg.f);
    }
    if (!quiet) header(scene, out_path, ck_path, stdout);
    st = gran_scene_run(scene, output, no_ckpt ? "" : checkpoint, &ctl, &res);
    if (st) {
      fail("run failed");
      gran_scene_destroy(&scene);
      return 1;
    }
    gran_scene_destroy(&scene);
    if (!res.finished) return root ? stopped(res, out_path, ck_path, lg.f) : stop_code();
  }
  if (!res.finished) return root ? stopped(res, out_path, resume, lg.f) : stop_code();
  if (!root) return 0;
  int64_t nwarn = 0;
  gran_warning_count(&nwarn);
  if (nwarn > 0) {
    char w[1024];
    gran_last_warning_copy(w, sizeof w);
    for (FILE *o : {stderr, lg.f})
      if (o) std::fprintf(o, "granary run: %" PRId64 " warning(s); last: %s\n", nwarn, w);
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
  const OutData od = quiet && !lg.f ? OutData() : read_output(out_path);
  if (lg.f) thermo_final(od, lg, lg.f);
  for (FILE *o : {stdout, lg.f}) {
    if (!o) continue;
    std::fprintf(o, "%sgranary run: wrote %s (%" PRId64 " %s, t = %.6g, %.1f s, %.3g %s/s)\n", o == stdout ? "" : "\n",
                 out_path.c_str(), res.collisions, unit, res.time, res.wall_seconds,
                 res.wall_seconds > 0 ? (double)res.collisions / res.wall_seconds : 0.0, unit);
    if (o != stdout || !quiet) summary(od, out_path, o);
    if ((o != stdout || !quiet) && cli_mpi_size() > 1) {
      long long steps = 0, bytes = 0;
      cli_mpi_stats(&steps, &bytes);
      std::fprintf(o, "mpi: %d processes; rank 0 received %lld bytes from the others in %lld gathers\n", cli_mpi_size(),
                   bytes, steps);
    }
  }
  if (lg.f && !quiet) std::printf("log: %s\n", lg.path.c_str());
  return 0;
}
