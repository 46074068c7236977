/* run.cpp - running a scene: engine, observers at the output times, HDF5 output, checkpoints.
 *
 * The engine is only ever advanced to the scene's output times (then to t_end), whether or not a
 * checkpoint is written there, so a run split by checkpoints makes exactly the same calls as an
 * uninterrupted one: resuming is bit for bit. Recorded rows live in named buffers [ntimes x row];
 * the output file and the checkpoint's /observer group are written from the same buffers.
 * Every engine is reached through the interface of engine.h (one adapter per engine). */
#include <hdf5.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <sys/stat.h>
#include <climits>
#include <cstdlib>
#include <unistd.h>

#include "io/engine.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

const char *kCheckpointFormat = "granary-checkpoint 1";
const char *kOutputFormat = "granary-output 1";

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/* One independent run of the scene: its engine and its recorded rows. */
struct Replica {
  std::unique_ptr<gran_engine> eng;
  std::vector<gran_row_buf> bufs;
};

struct Run {
  const gran_scene *s = nullptr;
  gran_scene *owned_scene = nullptr;
  std::vector<Replica> reps; /* R >= 1; replica 0 is the run without replicas */
  int64_t R = 1;
  int keep = 0;              /* keep_replicas */
  int threads = 1;           /* threads used for the replicas */
  int64_t next = 0;          /* output times recorded */
  std::string out, ckpt;
  gran_engine *eng() const { return reps[0].eng.get(); }
  ~Run() {
    reps.clear();
    gran_scene_destroy(&owned_scene);
  }
};

int g_threads = 0; /* gran_set_threads; 0: the OpenMP default (OMP_NUM_THREADS) */

/* fn(r) for every replica, in `threads` OpenMP threads. Errors are per thread (thread-local
 * messages): the first failing replica, in replica order, is reported on the calling thread. */
template <class F>
int for_replicas(Run &r, F fn) {
  if (r.R == 1) return fn((int64_t)0);
  std::vector<int> st((size_t)r.R, GRAN_SUCCESS);
  std::vector<std::string> msg((size_t)r.R);
  const int64_t R = r.R;
#pragma omp parallel for schedule(dynamic, 1) num_threads(r.threads)
  for (int64_t k = 0; k < R; k++) {
    int x = GRAN_SUCCESS;
    try {
      x = fn(k);
    } catch (...) {
      x = GRAN_ERROR(GRAN_ERR_INTERNAL, "exception in replica %" PRId64, k);
    }
    st[(size_t)k] = x;
    if (x != GRAN_SUCCESS) msg[(size_t)k] = gran_last_error_message();
  }
  for (int64_t k = 0; k < R; k++)
    if (st[(size_t)k] != GRAN_SUCCESS)
      return GRAN_ERROR(st[(size_t)k], "replica %" PRId64 ": %s", k, msg[(size_t)k].c_str());
  return GRAN_SUCCESS;
}

/* Seed of replica k: the scene's seed for replica 0, else the first number of RNG stream k. */
int replica_seed(uint64_t seed, int64_t k, uint64_t *out) {
  if (k == 0) {
    *out = seed;
    return GRAN_SUCCESS;
  }
  gran_rng g;
  GRAN_CALL(gran_rng_stream(seed, (uint64_t)k, &g));
  return gran_rng_u64(&g, 1, out);
}

/* MemAvailable of /proc/meminfo in bytes (< 0 when unknown). */
double memory_available() {
  FILE *f = std::fopen("/proc/meminfo", "r");
  if (!f) return -1;
  char line[256];
  double kb = -1;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "MemAvailable: %lf kB", &kb) == 1) break;
  std::fclose(f);
  return kb >= 0 ? kb * 1024.0 : -1;
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

/* Identity of a file: "dev:inode" when it exists, else the real path of its folder plus its name
 * (two spellings of one file, links and ./ prefixes compare equal). */
std::string file_identity(const std::string &path) {
  struct stat sb;
  if (stat(path.c_str(), &sb) == 0) return "inode " + std::to_string((unsigned long long)sb.st_dev) + ":" +
                                           std::to_string((unsigned long long)sb.st_ino);
  size_t sl = path.find_last_of('/');
  std::string dir = sl == std::string::npos ? "." : (sl == 0 ? "/" : path.substr(0, sl));
  std::string base = sl == std::string::npos ? path : path.substr(sl + 1);
  char buf[PATH_MAX];
  if (realpath(dir.c_str(), buf)) return std::string("path ") + buf + "/" + base;
  return "path " + path;
}

/* Refuse two roles for one file (output, checkpoint, scene, partial output), by identity. */
int check_distinct(const Run &r, const std::string &scene_file) {
  struct Role {
    const char *what;
    std::string path;
  };
  std::vector<Role> roles = {{"output", r.out}, {"checkpoint", r.ckpt}, {"scene file", scene_file},
                             {"partial output", gran_partial_path_(r.out)}};
  for (size_t a = 0; a < roles.size(); a++)
    for (size_t b = a + 1; b < roles.size(); b++) {
      if (roles[a].path.empty() || roles[b].path.empty()) continue;
      if (file_identity(roles[a].path) == file_identity(roles[b].path))
        return GRAN_ERROR(GRAN_ERR_ARG, "the %s '%s' and the %s '%s' are the same file", roles[a].what,
                          roles[a].path.c_str(), roles[b].what, roles[b].path.c_str());
    }
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
  GRAN_CALL(gran_h5::attr_string(f, "engine", r.eng()->type(), file));
  GRAN_CALL(gran_h5::attr_double(f, "t_start", s->t_start, file));
  GRAN_CALL(gran_h5::attr_double(f, "t_end", s->t_end, file));
  return GRAN_SUCCESS;
}

/* Buffer q over the replicas, rows 0..dims[0]-1: double rows as the mean and its standard error
 * (X, X_se); integer rows (event counts) as the sum over replicas (X) and the standard error of
 * that sum (X_se); the per-replica rows as X_replicas [R][time]... when keep_replicas. Sums run
 * in replica order, so the result does not depend on how replicas were spread over threads. */
int write_reduced(const Run &r, size_t q, int64_t g, const std::vector<int64_t> &dims, const char *file) {
  const gran_row_buf &b = r.reps[0].bufs[q];
  const int64_t R = r.R;
  size_t n = 1;
  for (int64_t x : dims) n *= (size_t)x;
  std::vector<double> mean(n, 0.0), se(n, 0.0);
  auto val = [&](int64_t k, size_t i) -> double {
    const gran_row_buf &c = r.reps[(size_t)k].bufs[q];
    return c.is_int ? (double)c.n[i] : c.d[i];
  };
  for (int64_t k = 0; k < R; k++)
    for (size_t i = 0; i < n; i++) mean[i] += val(k, i);
  for (size_t i = 0; i < n; i++) mean[i] /= (double)R;
  for (int64_t k = 0; k < R; k++)
    for (size_t i = 0; i < n; i++) {
      const double d = val(k, i) - mean[i];
      se[i] += d * d;
    }
  /* sample variance / R: the standard error of the mean; for a sum, R times that */
  for (size_t i = 0; i < n; i++) se[i] = std::sqrt(se[i] / (double)(R - 1) / (double)R) * (b.is_int ? (double)R : 1.0);
  const std::string nse = b.name + "_se", nrep = b.name + "_replicas";
  if (b.is_int) {
    std::vector<int64_t> sum(n, 0);
    for (int64_t k = 0; k < R; k++)
      for (size_t i = 0; i < n; i++) sum[i] += r.reps[(size_t)k].bufs[q].n[i];
    GRAN_CALL(gran_h5::write_int64(g, b.name.c_str(), dims, sum.data(), file));
    GRAN_CALL(gran_describe_(g, b.name.c_str(), b.units.c_str(), (b.description + "; summed over the replicas").c_str(), file));
  } else {
    GRAN_CALL(gran_h5::write_double(g, b.name.c_str(), dims, mean.data(), file));
    GRAN_CALL(gran_describe_(g, b.name.c_str(), b.units.c_str(), (b.description + "; mean over the replicas").c_str(), file));
  }
  GRAN_CALL(gran_h5::write_double(g, nse.c_str(), dims, se.data(), file));
  GRAN_CALL(gran_describe_(g, nse.c_str(), b.units.c_str(),
                           ("standard error of " + b.name + (b.is_int ? " (the sum)" : " (the mean)") + " from the replicas").c_str(), file));
  if (r.keep) {
    std::vector<int64_t> rd = {R};
    rd.insert(rd.end(), dims.begin(), dims.end());
    if (b.is_int) {
      std::vector<int64_t> all;
      for (int64_t k = 0; k < R; k++) all.insert(all.end(), r.reps[(size_t)k].bufs[q].n.begin(), r.reps[(size_t)k].bufs[q].n.begin() + (ptrdiff_t)n);
      GRAN_CALL(gran_h5::write_int64(g, nrep.c_str(), rd, all.data(), file));
    } else {
      std::vector<double> all;
      for (int64_t k = 0; k < R; k++) all.insert(all.end(), r.reps[(size_t)k].bufs[q].d.begin(), r.reps[(size_t)k].bufs[q].d.begin() + (ptrdiff_t)n);
      GRAN_CALL(gran_h5::write_double(g, nrep.c_str(), rd, all.data(), file));
    }
    GRAN_CALL(gran_describe_(g, nrep.c_str(), b.units.c_str(), (b.description + "; per replica [replica][...]").c_str(), file));
  }
  return GRAN_SUCCESS;
}

/* The output file with the first nrec output times (all of them for a finished run; a stopped
 * run writes what it recorded, with the root attribute complete = 0). */
int write_output(Run &r, const std::string &path, int64_t nrec) {
  const gran_scene *s = r.s;
  const int64_t nt = nrec;
  const char *file = path.c_str();
  {
    /* built in memory, written with its checksum header (gran_h5::commit_memory_file): HDF5
     * never writes to disk itself, so a full disk is a plain GRAN_ERR_IO */
    H5File f;
    f.id = gran_h5::create_memory_file();
    GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "HDF5: cannot create the output file '%s' in memory", file);
    GRAN_CALL(write_root_attrs(r, f.id, file, kOutputFormat));
    std::string cols;
    for (const auto &c : r.eng()->summary_columns()) cols += c.label + ":" + c.sim + ":" + c.theory + ";";
    GRAN_CALL(gran_h5::attr_string(f.id, "summary_columns", cols, file));
    GRAN_CALL(gran_h5::attr_int64(f.id, "complete", nrec == (int64_t)s->times.size(), file));
    GRAN_CALL(gran_h5::attr_int64(f.id, "recorded", nrec, file));
    GRAN_CALL(gran_h5::write_double(f.id, "time", {nt}, s->times.data(), file));
    GRAN_CALL(gran_describe_(f.id, "time", "time", "the output times", file));
    for (size_t q = 0; q < r.reps[0].bufs.size(); q++) {
      const gran_row_buf &b = r.reps[0].bufs[q];
      H5Group g;
      if (gran_h5::exists(f.id, b.group.c_str())) {
        g.id = H5Gopen2((hid_t)f.id, b.group.c_str(), H5P_DEFAULT);
      } else {
        GRAN_CALL(gran_h5::make_group(f.id, b.group.c_str(), &g.id, file));
        GRAN_CALL(gran_h5::write_double(g.id, "time", {nt}, s->times.data(), file));
        GRAN_CALL(gran_describe_(g.id, "time", "time", "the output times (rows of this group's datasets)", file));
      }
      std::vector<int64_t> dims = {nt};
      dims.insert(dims.end(), b.row_dims.begin(), b.row_dims.end());
      if (r.R == 1) {
        if (b.is_int) GRAN_CALL(gran_h5::write_int64(g.id, b.name.c_str(), dims, b.n.data(), file));
        else GRAN_CALL(gran_h5::write_double(g.id, b.name.c_str(), dims, b.d.data(), file));
        GRAN_CALL(gran_describe_(g.id, b.name.c_str(), b.units.c_str(), b.description.c_str(), file));
        continue;
      }
      GRAN_CALL(write_reduced(r, q, g.id, dims, file));
    }
    GRAN_CALL(gran_h5::attr_int64(f.id, "nreplicas", r.R, file));
    GRAN_CALL(r.eng()->write_output(f.id, file, nrec));
    if (r.R > 1 && gran_h5::exists(f.id, "tamsd")) {
      H5Group g;
      g.id = H5Gopen2((hid_t)f.id, "tamsd", H5P_DEFAULT);
      GRAN_CALL(gran_h5::attr_string(g.id, "replicas", "from replica 0 only", file));
    }
    return gran_h5::commit_memory_file(&f.id, path, "output file");
  }
}

/* Checkpoint groups of replica k: /engine and /observer for replica 0 (a run without replicas
 * writes exactly these), /replicas/k/engine and /replicas/k/observer for the others. */
std::string engine_group(int64_t k) { return k == 0 ? "/engine" : "/replicas/" + std::to_string(k) + "/engine"; }
std::string observer_group(int64_t k) { return k == 0 ? "observer" : "replicas/" + std::to_string(k) + "/observer"; }

int write_checkpoint(Run &r) {
  const char *file = r.ckpt.c_str();
  {
    /* built in memory and written with its checksum (see write_output); the engines first, then
     * the observer state beside them */
    H5File f;
    f.id = gran_h5::create_memory_file();
    GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "HDF5: cannot create the checkpoint '%s' in memory", file);
    for (int64_t k = 0; k < r.R; k++)
      GRAN_CALL(r.reps[(size_t)k].eng->checkpoint_write(f.id, file, engine_group(k).c_str()));
    GRAN_CALL(write_root_attrs(r, f.id, file, kCheckpointFormat));
    GRAN_CALL(gran_h5::attr_string(f.id, "output", r.out, file));
    GRAN_CALL(gran_h5::attr_int64(f.id, "next_index", r.next, file));
    GRAN_CALL(gran_h5::attr_int64(f.id, "nreplicas", r.R, file));
    GRAN_CALL(gran_h5::attr_int64(f.id, "keep_replicas", r.keep, file));
    for (int64_t k = 0; k < r.R; k++) {
      H5Group g;
      GRAN_CALL(gran_h5::make_group(f.id, observer_group(k).c_str(), &g.id, file));
      for (const auto &b : r.reps[(size_t)k].bufs) {
        const std::string nm = b.group + "." + b.name;
        const int64_t total = b.row * (int64_t)r.s->times.size();
        if (b.is_int) GRAN_CALL(gran_h5::write_int64(g.id, nm.c_str(), {total}, b.n.data(), file));
        else GRAN_CALL(gran_h5::write_double(g.id, nm.c_str(), {total}, b.d.data(), file));
      }
    }
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
  for (int64_t k = 0; k < r.R; k++) {
    const std::string og = observer_group(k);
    H5Group g;
    g.id = gran_h5::exists(f.id, og.c_str()) ? H5Gopen2((hid_t)f.id, og.c_str(), H5P_DEFAULT) : -1;
    GRAN_CHECK(g.id >= 0, GRAN_ERR_IO, "checkpoint '%s' has no /%s group", path, og.c_str());
    for (auto &b : r.reps[(size_t)k].bufs) {
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
  }
  return GRAN_SUCCESS;
}

/* One engine per replica and its row buffers, sized to the output times; refuses before any work
 * when the replicas would not fit in the memory available. */
int prepare(Run &r) {
  const int64_t nt = (int64_t)r.s->times.size();
  r.reps.clear();
  r.reps.resize((size_t)r.R);
  for (int64_t k = 0; k < r.R; k++) {
    Replica &p = r.reps[(size_t)k];
    GRAN_CALL(gran_engine_create_(r.s, p.eng));
    GRAN_CALL(p.eng->declare(p.bufs));
    if (k == 0) {
      int64_t bytes = 0;
      GRAN_CALL(p.eng->memory(&bytes));
      double rows = 0;
      for (const auto &b : p.bufs) rows += (double)b.row * (double)nt * 8.0;
      const double need = ((double)bytes + rows) * (double)r.R, avail = memory_available();
      GRAN_CHECK(avail < 0 || need <= avail, GRAN_ERR_NOMEM,
                 "%" PRId64 " replica(s) of this scene need about %.3g GB (%.3g GB each, all in memory at once), "
                 "more than the %.3g GB available: lower [engine] replicas (--replicas) or the particle numbers",
                 r.R, need / 1e9, need / 1e9 / (double)r.R, avail / 1e9);
    }
    for (auto &b : p.bufs) {
      if (b.is_int) b.n.assign((size_t)(b.row * nt), 0);
      else b.d.assign((size_t)(b.row * nt), 0.0);
    }
  }
  int nth = g_threads;
#ifdef _OPENMP
  if (nth <= 0) nth = omp_get_max_threads();
#endif
  if (nth <= 0) nth = 1;
  r.threads = (int)std::min<int64_t>(nth, r.R);
  return GRAN_SUCCESS;
}

/* Replica k from its seed (gran_rng_stream) or from the checkpoint. */
int start_replicas(Run &r) {
  return for_replicas(r, [&](int64_t k) {
    uint64_t seed = 0;
    GRAN_CALL(replica_seed(r.s->seed, k, &seed));
    return r.reps[(size_t)k].eng->start(seed);
  });
}

/* The loop shared by run and resume: record rows next..ntimes-1, checkpoint, finish.
 * Progress and ETA are weighted by the engine's work estimate to each output time. */
int drive(Run &r, const gran_run_control *ctl, gran_run_result *res) {
  const gran_scene *s = r.s;
  const int64_t nt = (int64_t)s->times.size();
  const double w0 = now_s();
  double w_ckpt = w0;
  /* events summed over the replicas; time: replica 0's */
  auto state = [&](gran_engine_state *x) -> int {
    gran_engine_state a, sum;
    for (int64_t k = 0; k < r.R; k++) {
      GRAN_CALL(r.reps[(size_t)k].eng->state(&a));
      if (k == 0) sum.time = a.time;
      sum.events += a.events;
    }
    *x = sum;
    return GRAN_SUCCESS;
  };
  gran_engine_state st;
  GRAN_CALL(state(&st));
  const int64_t ev0 = st.events;
  int64_t nckpt = 0;
  gran_run_result rr = {};
  auto fill = [&](int finished) {
    gran_engine_state x;
    if (state(&x) == GRAN_SUCCESS) {
      rr.collisions = x.events;
      rr.time = x.time;
    }
    rr.finished = finished;
    rr.checkpoints = nckpt;
    rr.wall_seconds = now_s() - w0;
    if (res) *res = rr;
  };
  /* work[i]: estimated work from the start to output time i; work[nt]: to t_end */
  std::vector<double> work, tw(s->times);
  if (ctl && ctl->progress) {
    tw.push_back(s->t_end);
    work.assign(tw.size(), 0.0);
    GRAN_CALL(r.eng()->work((int64_t)tw.size(), tw.data(), work.data())); /* the same for every replica */
  }
  const int64_t first = r.next;
  while (r.next < nt) {
    const int64_t i = r.next;
    GRAN_CALL(for_replicas(r, [&](int64_t k) {
      Replica &p = r.reps[(size_t)k];
      GRAN_CALL(p.eng->advance(s->times[(size_t)i]));
      return p.eng->record(p.bufs, i);
    }));
    r.next = i + 1;
    int stop = 0;
    if (ctl && ctl->progress) {
      gran_engine_state x;
      GRAN_CALL(state(&x));
      gran_run_progress p = {};
      const double wall = now_s() - w0;
      const double W = std::max(work[(size_t)nt], work[(size_t)(nt - 1)]);
      const double Wa = first > 0 ? work[(size_t)(first - 1)] : 0.0, Wi = work[(size_t)i];
      p.time = x.time;
      p.t_start = s->t_start;
      p.t_end = s->t_end;
      p.fraction = W > 0 ? std::min(1.0, Wi / W) : (double)r.next / (double)nt;
      p.wall_seconds = wall;
      p.collisions = x.events;
      p.collisions_per_second = wall > 0 ? (double)(x.events - ev0) / wall : 0.0;
      if (W > Wa && Wi > Wa && wall > 0) {
        p.eta_seconds = wall * std::max(0.0, W - Wi) / (Wi - Wa);
      } else {
        const double done = (double)(r.next - first) / (double)(nt - first);
        p.eta_seconds = done > 0 && wall > 0 ? wall * (1.0 - done) / done : -1.0;
      }
      p.output_index = r.next;
      p.noutputs = nt;
      p.checkpoints = nckpt;
      stop = ctl->progress(&p, ctl->progress_params) != 0;
    }
    if (r.next >= nt || r.ckpt.empty()) {
      if (stop && r.next < nt) {
        GRAN_CALL(write_output(r, gran_partial_path_(r.out), r.next));
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
        GRAN_CALL(write_output(r, gran_partial_path_(r.out), r.next));
        fill(0);
        return GRAN_SUCCESS;
      }
    }
  }
  GRAN_CALL(for_replicas(r, [&](int64_t k) {
    gran_engine_state x;
    GRAN_CALL(r.reps[(size_t)k].eng->state(&x));
    return x.time < s->t_end ? r.reps[(size_t)k].eng->advance(s->t_end) : GRAN_SUCCESS;
  }));
  GRAN_CALL(write_output(r, r.out, nt));
  std::remove(gran_partial_path_(r.out).c_str());
  if (!r.ckpt.empty() && !s->keep_checkpoint) std::remove(r.ckpt.c_str());
  fill(1);
  return GRAN_SUCCESS;
}

}  // namespace

std::string gran_partial_path_(const std::string &out) {
  const size_t n = out.size();
  if (n > 3 && out.compare(n - 3, 3, ".h5") == 0) return out.substr(0, n - 3) + ".partial.h5";
  return out + ".partial.h5";
}

std::string gran_run_checkpoint_path_(const gran_scene *s, const char *output, const char *checkpoint) {
  if (checkpoint) return checkpoint;
  /* the default checkpoint (OUTPUT.ckpt) follows -o; a path the scene names stays */
  if (output && s->checkpoint_path == s->output_path + ".ckpt") return std::string(output) + ".ckpt";
  return s->checkpoint_path;
}

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
    r.ckpt = gran_run_checkpoint_path_(scene, output, checkpoint);
    GRAN_CHECK(!r.out.empty(), GRAN_ERR_ARG, "argument 'output' is empty");
    GRAN_CALL(check_distinct(r, scene->name));
    if (result) *result = gran_run_result{};
    GRAN_CALL(check_writable(r.out, "output file"));
    if (!r.ckpt.empty()) GRAN_CALL(check_writable(r.ckpt, "checkpoint file"));
    r.R = scene->replicas;
    r.keep = scene->keep_replicas;
    GRAN_CALL(prepare(r));
    GRAN_CALL(start_replicas(r));
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
      if (H5Aexists((hid_t)f.id, "nreplicas") > 0) {
        GRAN_CALL(gran_h5::read_attr_int64(f.id, "nreplicas", &r.R, checkpoint));
        int64_t keep = 0;
        GRAN_CALL(gran_h5::read_attr_int64(f.id, "keep_replicas", &keep, checkpoint));
        r.keep = keep != 0;
        GRAN_CHECK(r.R >= 1 && r.R <= 1000000, GRAN_ERR_IO, "checkpoint '%s': nreplicas %" PRId64 " out of range", checkpoint, r.R);
      }
    }
    GRAN_CALL(gran_scene_parse_text_(text, name, &r.owned_scene));
    r.s = r.owned_scene;
    r.out = output ? output : out;
    r.ckpt = checkpoint;
    GRAN_CHECK(!r.out.empty(), GRAN_ERR_ARG, "argument 'output' is empty");
    GRAN_CALL(check_distinct(r, name));
    if (result) *result = gran_run_result{};
    GRAN_CALL(check_writable(r.out, "output file"));
    GRAN_CALL(check_writable(r.ckpt, "checkpoint file"));
    GRAN_CALL(prepare(r));
    GRAN_CALL(read_checkpoint_observer(r, checkpoint));
    {
      H5File f;
      f.id = gran_h5::open_file(checkpoint, 0);
      GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "cannot open checkpoint '%s'", checkpoint);
      for (int64_t k = 0; k < r.R; k++)
        GRAN_CALL(r.reps[(size_t)k].eng->checkpoint_read(f.id, checkpoint, engine_group(k).c_str()));
    }
    return drive(r, ctl, result);
  }
  GRAN_CATCH
}

/* ---- replicas and threads ------------------------------------------------------------------ */

/** @brief Set the number of independent replicas of a scene's run ([engine] replicas) and whether
 *  the output keeps the per-replica rows ([engine] keep_replicas). */
GRAN_EXTERN int gran_scene_set_replicas(gran_scene *scene, int64_t replicas, int32_t keep_replicas) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK(replicas >= 1 && replicas <= 1000000, GRAN_ERR_ARG, "argument 'replicas' must be in 1..1000000, got %" PRId64,
             replicas);
  GRAN_CHECK(keep_replicas == 0 || keep_replicas == 1, GRAN_ERR_ARG, "argument 'keep_replicas' must be 0 or 1, got %d",
             (int)keep_replicas);
  scene->replicas = replicas;
  scene->keep_replicas = keep_replicas;
  return GRAN_SUCCESS;
}

/** @brief The scene's replicas and keep_replicas (either output may be NULL). */
GRAN_EXTERN int gran_scene_replicas(const gran_scene *scene, int64_t *replicas, int32_t *keep_replicas) {
  GRAN_CHECK_PTR(scene);
  if (replicas) *replicas = scene->replicas;
  if (keep_replicas) *keep_replicas = scene->keep_replicas;
  return GRAN_SUCCESS;
}

/** @brief Threads over which gran_scene_run / gran_scene_resume spread the replicas of a run
 *  (process-wide; 0: the OpenMP default, i.e. OMP_NUM_THREADS or the number of cores). */
GRAN_EXTERN int gran_set_threads(int32_t nthreads) {
  GRAN_CHECK(nthreads >= 0 && nthreads <= 4096, GRAN_ERR_ARG, "argument 'nthreads' must be in 0..4096, got %d", (int)nthreads);
  g_threads = nthreads;
  return GRAN_SUCCESS;
}

/** @brief The threads a run would use for its replicas (at most the replicas; 1 without OpenMP). */
GRAN_EXTERN int gran_get_threads(int32_t *nthreads) {
  GRAN_CHECK_PTR(nthreads);
  int n = g_threads;
#ifdef _OPENMP
  if (n <= 0) n = omp_get_max_threads();
#else
  n = 1;
#endif
  *nthreads = n > 0 ? n : 1;
  return GRAN_SUCCESS;
}
