/* run.cpp - running a scene: engine, observers at the output times, HDF5 output, checkpoints.
 *
 * The engine is only ever advanced to the scene's output times (then to t_end), whether or not a
 * checkpoint is written there, so a run split by checkpoints makes exactly the same calls as an
 * uninterrupted one: resuming is bit for bit. Recorded rows live in named buffers [ntimes x row];
 * the output file and the checkpoint's /observer group are written from the same buffers.
 * Every engine is reached through the interface of engine.h (one adapter per engine). */
#include <hdf5.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <sys/stat.h>
#include <climits>
#include <cstdlib>
#include <unistd.h>

#include "io/engine.h"
#include "io/run_comm.h"

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
  gran_run_comm comm;        /* the processes (run_comm.h); size 1: this process alone */
  std::vector<int64_t> mine; /* the replicas this process runs: k % comm.size == comm.rank */
  int64_t events_all = 0;    /* rank 0: engine events of all replicas at the last exchange */
  int64_t R = 1;
  int keep = 0;              /* keep_replicas */
  int threads = 1;           /* threads used for the replicas */
  int64_t next = 0;          /* output times recorded */
  std::string out, ckpt;
  gran_engine *eng() const { return reps[0].eng.get(); } /* rank 0 only (it runs replica 0) */
  bool root() const { return comm.rank == 0; }
  bool owns(int64_t k) const { return k % comm.size == comm.rank; }
  ~Run() {
    reps.clear();
    gran_scene_destroy(&owned_scene);
  }
};

int g_threads = 0; /* gran_set_threads; 0: the OpenMP default (OMP_NUM_THREADS) */
gran_run_comm g_comm; /* gran_run_set_comm_; size 1: one process */

/* fn(k) for every replica k of this process, in `threads` OpenMP threads. Errors are per thread
 * (thread-local messages): the first failing replica, in replica order, is reported on the
 * calling thread. */
template <class F>
int for_replicas(Run &r, F fn) {
  const int64_t n = (int64_t)r.mine.size();
  if (n == 0) return GRAN_SUCCESS; /* an idle process (fewer replicas than processes) */
  if (r.R == 1) return fn(r.mine[0]);
  std::vector<int> st((size_t)n, GRAN_SUCCESS);
  std::vector<std::string> msg((size_t)n);
#pragma omp parallel for schedule(dynamic, 1) num_threads(r.threads)
  for (int64_t j = 0; j < n; j++) {
    const int64_t k = r.mine[(size_t)j];
    int x = GRAN_SUCCESS;
    try {
      x = fn(k);
    } catch (...) {
      x = GRAN_ERROR(GRAN_ERR_INTERNAL, "exception in replica %" PRId64, k);
    }
    st[(size_t)j] = x;
    if (x != GRAN_SUCCESS) msg[(size_t)j] = gran_last_error_message();
  }
  for (int64_t j = 0; j < n; j++)
    if (st[(size_t)j] != GRAN_SUCCESS)
      return GRAN_ERROR(st[(size_t)j], "replica %" PRId64 ": %s", r.mine[(size_t)j], msg[(size_t)j].c_str());
  return GRAN_SUCCESS;
}

/* ---- the processes of an MPI run (run_comm.h) -----------------------------------------------
 * Each step of a run with P > 1 is collective: every rank sends rank 0 a Part (its status, the
 * message of a failure, its engine events and a payload), rank 0 answers every rank with one
 * Verdict (the first failure in rank order, or go on; stop; write a checkpoint). With P = 1 both
 * are local and a failure keeps its message as it was set. */
struct Part {
  int64_t st = 0, events = 0;
  std::string msg, payload;
};
struct Verdict {
  int64_t st = 0, stop = 0, ckpt = 0;
  std::string msg;
};

void put_i64(std::string &s, int64_t v) { s.append(reinterpret_cast<const char *>(&v), sizeof v); }
bool get_i64(const std::string &s, size_t &at, int64_t *v) {
  if (at + sizeof *v > s.size()) return false;
  std::memcpy(v, s.data() + at, sizeof *v);
  at += sizeof *v;
  return true;
}
int comm_error(const char *what) { return GRAN_ERROR(GRAN_ERR_IO, "MPI: %s failed", what); }

/* Every rank's part to rank 0: parts (rank order) on rank 0; untouched on the others. */
int gather_parts(Run &r, int st, int64_t events, std::string payload, std::vector<Part> *parts) {
  Part me;
  me.st = st;
  me.events = events;
  if (st != GRAN_SUCCESS) me.msg = gran_last_error_message();
  else me.payload = std::move(payload);
  if (r.comm.size == 1) {
    parts->clear();
    parts->push_back(std::move(me));
    return GRAN_SUCCESS;
  }
  std::string b;
  put_i64(b, me.st);
  put_i64(b, me.events);
  put_i64(b, (int64_t)me.msg.size());
  b += me.msg;
  b += me.payload;
  std::string().swap(me.payload);
  std::vector<std::string> all;
  if (r.comm.gather(r.comm.ctx, b, &all)) return comm_error("gather");
  if (!r.root()) return GRAN_SUCCESS;
  GRAN_CHECK((int)all.size() == r.comm.size, GRAN_ERR_INTERNAL, "MPI: gathered %zu parts from %d processes", all.size(),
             r.comm.size);
  parts->assign(all.size(), Part());
  for (size_t p = 0; p < all.size(); p++) {
    size_t at = 0;
    int64_t n = 0;
    Part &x = (*parts)[p];
    GRAN_CHECK(get_i64(all[p], at, &x.st) && get_i64(all[p], at, &x.events) && get_i64(all[p], at, &n) && n >= 0 &&
                   at + (size_t)n <= all[p].size(),
               GRAN_ERR_INTERNAL, "MPI: malformed message from process %zu", p);
    x.msg = all[p].substr(at, (size_t)n);
    x.payload = all[p].substr(at + (size_t)n);
    std::string().swap(all[p]);
  }
  return GRAN_SUCCESS;
}

/* rank 0: the first failing part, in rank order, into v */
void first_failure(const Run &r, const std::vector<Part> &parts, Verdict *v) {
  for (size_t p = 0; p < parts.size(); p++)
    if (parts[p].st != GRAN_SUCCESS) {
      v->st = parts[p].st;
      v->msg = r.comm.size == 1 || p == 0 ? parts[p].msg
                                         : "process " + std::to_string(p) + " of " + std::to_string(r.comm.size) + ": " + parts[p].msg;
      return;
    }
}

/* Rank 0's verdict to every rank; returns its status, with its message, on every rank. */
int share_verdict(Run &r, Verdict *v) {
  if (r.comm.size == 1) return (int)v->st; /* the message is the one set where it failed */
  std::string b;
  if (r.root()) {
    put_i64(b, v->st);
    put_i64(b, v->stop);
    put_i64(b, v->ckpt);
    b += v->msg;
  }
  if (r.comm.bcast(r.comm.ctx, &b)) return comm_error("broadcast");
  size_t at = 0;
  GRAN_CHECK(get_i64(b, at, &v->st) && get_i64(b, at, &v->stop) && get_i64(b, at, &v->ckpt), GRAN_ERR_INTERNAL,
             "MPI: malformed verdict");
  v->msg = b.substr(at);
  if (v->st != GRAN_SUCCESS) return GRAN_ERROR((int)v->st, "%s", v->msg.c_str());
  return GRAN_SUCCESS;
}

/* Collective: every rank's status st; the first failure (rank order) on every rank. */
int sync_status(Run &r, int st) {
  if (r.comm.size == 1) return st;
  std::vector<Part> parts;
  GRAN_CALL(gather_parts(r, st, 0, std::string(), &parts));
  Verdict v;
  if (r.root()) first_failure(r, parts, &v);
  return share_verdict(r, &v);
}

/* An HDF5 file opened read-only from its bytes (the core driver; the bytes are copied). */
int64_t open_image(const std::string &bytes) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  static std::atomic<uint64_t> serial{0};
  char name[80];
  std::snprintf(name, sizeof name, "granary-received-image-%d-%llu", (int)getpid(),
                (unsigned long long)serial.fetch_add(1));
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  hid_t f = -1;
  if (fapl >= 0 && H5Pset_fapl_core(fapl, (size_t)1 << 20, 0) >= 0 &&
      H5Pset_file_image(fapl, const_cast<char *>(bytes.data()), bytes.size()) >= 0)
    f = H5Fopen(name, H5F_ACC_RDONLY, fapl);
  if (fapl >= 0) H5Pclose(fapl);
  return (int64_t)f;
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

/* Refuse two roles for one file, by identity: every file a run reads or writes (the scene file,
 * the checkpoint it resumes from or writes, the output and the partial output, the sidecars the
 * engine writes beside them, and the .tmp of each written file). */
int check_distinct(const Run &r, const std::string &scene_file) {
  struct Role {
    std::string what, path;
  };
  std::unique_ptr<gran_engine> eng; /* for its sidecars: no state is built */
  GRAN_CALL(gran_engine_create_(r.s, eng));
  std::vector<Role> roles = {{"scene file", scene_file}};
  auto written = [&](const std::string &what, const std::string &path) {
    if (path.empty()) return;
    roles.push_back({what, path});
    roles.push_back({"temporary file of the " + what, path + ".tmp"});
  };
  written("checkpoint", r.ckpt);
  const std::string part = gran_partial_path_(r.out);
  written("output", r.out);
  written("partial output", part);
  for (const auto &p : eng->sidecars(r.out)) written("sidecar of the output", p);
  for (const auto &p : eng->sidecars(part)) written("sidecar of the partial output", p);
  for (size_t a = 0; a < roles.size(); a++)
    for (size_t b = a + 1; b < roles.size(); b++) {
      if (roles[a].path.empty() || roles[b].path.empty()) continue;
      if (file_identity(roles[a].path) == file_identity(roles[b].path))
        return GRAN_ERROR(GRAN_ERR_ARG, "the %s '%s' and the %s '%s' are the same file", roles[a].what.c_str(),
                          roles[a].path.c_str(), roles[b].what.c_str(), roles[b].path.c_str());
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

/* The _FillValue attribute (gran_row_fill) of dataset `name` in `loc`. */
int fill_attr(int64_t loc, const char *name, const char *file) {
  hid_t d = H5Dopen2((hid_t)loc, name, H5P_DEFAULT);
  GRAN_CHECK(d >= 0, GRAN_ERR_IO, "cannot open dataset '%s' in '%s'", name, file);
  const int st = gran_h5::attr_double(d, "_FillValue", gran_row_fill, file);
  H5Dclose(d);
  return st;
}

/* Row i of every buffer of a replica, right after record: every double finite, except NaN in a
 * buffer with fill (no value), stored as gran_row_fill. Anything else stops the run. */
int check_row(std::vector<gran_row_buf> &bufs, int64_t i, const gran_scene *s) {
  /* Fault injection for the tests of this rule: GRAN_FAULT_ROW = I puts NaN into the first element
   * of the first buffer without fill at output time I (engines no longer produce such rows from
   * accepted inputs, so only this reaches the stop path from a scene). */
  const char *fe = std::getenv("GRAN_FAULT_ROW"); /* once per output time: negligible */
  const int64_t fault = fe && *fe ? (int64_t)std::strtoll(fe, nullptr, 10) : (int64_t)-1;
  if (fault == i)
    for (auto &b : bufs)
      if (!b.is_int && !b.fill && b.row > 0) {
        b.d[(size_t)(i * b.row)] = NAN;
        break;
      }
  for (auto &b : bufs) {
    if (b.is_int) continue;
    double *d = b.d.data() + i * b.row;
    for (int64_t e = 0; e < b.row; e++) {
      if (std::isfinite(d[e])) continue;
      if (b.fill && std::isnan(d[e])) {
        d[e] = gran_row_fill;
        continue;
      }
      return GRAN_ERROR(GRAN_ERR_NUMERIC, "dataset '%s/%s' is %g at output time %" PRId64 " (t = %g, element %" PRId64
                        "): the run stops here", b.group.c_str(), b.name.c_str(), d[e], i, s->times[(size_t)i], e);
    }
  }
  return GRAN_SUCCESS;
}

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
  /* with fill: over the replicas that have a value (none: fill; fewer than 2: no standard error) */
  std::vector<int64_t> cnt(n, R);
  if (b.fill)
    for (size_t i = 0; i < n; i++) {
      cnt[i] = 0;
      for (int64_t k = 0; k < R; k++) cnt[i] += val(k, i) != gran_row_fill;
    }
  auto has = [&](int64_t k, size_t i) { return !b.fill || val(k, i) != gran_row_fill; };
  for (int64_t k = 0; k < R; k++)
    for (size_t i = 0; i < n; i++)
      if (has(k, i)) mean[i] += val(k, i);
  for (size_t i = 0; i < n; i++) mean[i] = cnt[i] > 0 ? mean[i] / (double)cnt[i] : gran_row_fill;
  for (int64_t k = 0; k < R; k++)
    for (size_t i = 0; i < n; i++) {
      if (!has(k, i)) continue;
      const double d = val(k, i) - mean[i];
      se[i] += d * d;
    }
  /* sample variance / R: the standard error of the mean; for a sum, R times that */
  for (size_t i = 0; i < n; i++)
    se[i] = cnt[i] < 2 ? gran_row_fill
                       : std::sqrt(se[i] / (double)(cnt[i] - 1) / (double)cnt[i]) * (b.is_int ? (double)R : 1.0);
  for (size_t i = 0; i < n; i++)
    GRAN_CHECK(std::isfinite(mean[i]) && std::isfinite(se[i]), GRAN_ERR_NUMERIC,
               "dataset '%s/%s': the mean over the replicas or its standard error is not finite (element %zu of '%s')",
               b.group.c_str(), b.name.c_str(), i, file);
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
  if (b.fill) {
    GRAN_CALL(fill_attr(g, b.name.c_str(), file));
    GRAN_CALL(fill_attr(g, nse.c_str(), file));
  }
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
    if (b.fill) GRAN_CALL(fill_attr(g, nrep.c_str(), file));
  }
  return GRAN_SUCCESS;
}

/* The output file with the first nrec output times (all of them for a finished run; a stopped
 * run writes what it recorded, with the root attribute complete = 0). */
int write_output_file(Run &r, const std::string &path, int64_t nrec);

/* The output file and its sidecars (gran_engine::sidecars): each sidecar is written as PATH.tmp
 * with the output and renamed into place only after the output file is committed; a sidecar of
 * an earlier run that this one did not write is removed (it would describe another file); on
 * failure no sidecar .tmp is left. */
int write_output(Run &r, const std::string &path, int64_t nrec) {
  const std::vector<std::string> side = r.eng()->sidecars(path);
  for (const auto &p : side) std::remove((p + ".tmp").c_str());
  const int st = write_output_file(r, path, nrec);
  if (st != GRAN_SUCCESS) {
    for (const auto &p : side) std::remove((p + ".tmp").c_str());
    return st;
  }
  for (const auto &p : side) {
    const std::string tmp = p + ".tmp";
    struct stat sb;
    if (stat(tmp.c_str(), &sb) != 0) {
      std::remove(p.c_str());
      continue;
    }
    const int cst = gran_io_commit_file_(tmp, p);
    if (cst != GRAN_SUCCESS) {
      std::remove(tmp.c_str());
      return cst;
    }
  }
  return GRAN_SUCCESS;
}

/* A finished run: the partial output of an earlier stop and its sidecars go. */
void remove_partial(Run &r) {
  const std::string part = gran_partial_path_(r.out);
  std::remove(part.c_str());
  for (const auto &p : r.eng()->sidecars(part)) std::remove(p.c_str());
}

int write_output_file(Run &r, const std::string &path, int64_t nrec) {
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
        if (b.fill) GRAN_CALL(fill_attr(g.id, b.name.c_str(), file));
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

/* The engine states of this process's replicas as the bytes of an HDF5 file built in memory
 * (groups named as in the checkpoint), for rank 0 to copy into the one checkpoint file. */
int engine_image(Run &r, std::string *img) {
  const char *file = r.ckpt.c_str();
  H5File f;
  f.id = gran_h5::create_memory_file();
  GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "HDF5: cannot create the engine states for '%s' in memory", file);
  for (int64_t k : r.mine) GRAN_CALL(r.reps[(size_t)k].eng->checkpoint_write(f.id, file, engine_group(k).c_str()));
  ssize_t n = H5Fflush((hid_t)f.id, H5F_SCOPE_GLOBAL) >= 0 ? H5Fget_file_image((hid_t)f.id, nullptr, 0) : -1;
  if (n > 0) {
    img->resize((size_t)n);
    if (H5Fget_file_image((hid_t)f.id, &(*img)[0], (size_t)n) != n) n = -1;
  }
  GRAN_CHECK(n > 0, GRAN_ERR_IO, "HDF5: cannot assemble the engine states for '%s' in memory", file);
  return GRAN_SUCCESS;
}

/* Rank 0: the checkpoint file, with the engine states the other ranks sent (parts[p].payload). */
int write_checkpoint_root(Run &r, const std::vector<Part> &parts) {
  const char *file = r.ckpt.c_str();
  {
    /* built in memory and written with its checksum (see write_output); the engines first, then
     * the observer state beside them */
    H5File f;
    f.id = gran_h5::create_memory_file();
    GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "HDF5: cannot create the checkpoint '%s' in memory", file);
    for (int64_t k : r.mine)
      GRAN_CALL(r.reps[(size_t)k].eng->checkpoint_write(f.id, file, engine_group(k).c_str()));
    for (size_t p = 1; p < parts.size(); p++) {
      if ((int64_t)p >= r.R) break; /* idle processes */
      H5File src;
      src.id = open_image(parts[p].payload);
      GRAN_CHECK(src.id >= 0, GRAN_ERR_IO, "checkpoint '%s': cannot read the engine states of process %zu", file, p);
      hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
      H5Pset_create_intermediate_group(lcpl, 1);
      herr_t e = 0;
      int64_t bad = -1;
      for (int64_t k = (int64_t)p; k < r.R && e >= 0; k += r.comm.size) {
        e = H5Ocopy((hid_t)src.id, engine_group(k).c_str(), (hid_t)f.id, engine_group(k).c_str(), H5P_DEFAULT, lcpl);
        if (e < 0) bad = k;
      }
      H5Pclose(lcpl);
      GRAN_CHECK(e >= 0, GRAN_ERR_IO, "checkpoint '%s': cannot copy the engine state of replica %" PRId64, file, bad);
    }
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

/* Collective: every rank's engine states into the one checkpoint file rank 0 writes. */
int write_checkpoint(Run &r) {
  std::string img;
  int st = GRAN_SUCCESS;
  if (!r.root() && !r.mine.empty()) st = engine_image(r, &img);
  std::vector<Part> parts;
  GRAN_CALL(gather_parts(r, st, 0, std::move(img), &parts));
  Verdict v;
  if (r.root()) {
    first_failure(r, parts, &v);
    if (!v.st && (st = write_checkpoint_root(r, parts)) != GRAN_SUCCESS) {
      v.st = st;
      v.msg = gran_last_error_message();
    }
  }
  return share_verdict(r, &v);
}

/* The checkpoint: from disk with one process; from the bytes rank 0 read and broadcast with more
 * (the other ranks need not see rank 0's files). */
int64_t open_checkpoint(const Run &r, const char *path, const std::string &bytes) {
  return r.comm.size == 1 ? gran_h5::open_file(path, 0) : open_image(bytes);
}

int read_checkpoint_observer(Run &r, const char *path, const std::string &bytes) {
  H5File f;
  f.id = open_checkpoint(r, path, bytes);
  GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "cannot open checkpoint '%s'", path);
  int64_t next = -1;
  GRAN_CALL(gran_h5::read_attr_int64(f.id, "next_index", &next, path));
  GRAN_CHECK(next >= 0 && next <= (int64_t)r.s->times.size(), GRAN_ERR_IO,
             "checkpoint '%s': next_index %" PRId64 " out of range", path, next);
  r.next = next;
  for (int64_t k = 0; k < r.R; k++) {
    if (!r.root() && !r.owns(k)) continue; /* rank 0 holds every replica's rows, the others their own */
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
        /* the recorded rows obey the row rule of a run (check_row): finite, or "no value" where the
         * buffer allows it (a NaN there, from a file written before the fill value, becomes it) */
        for (size_t e = 0; e < (size_t)(b.row * next); e++) {
          if (std::isfinite(v[e]) && v[e] != gran_row_fill) continue;
          if (b.fill && (std::isnan(v[e]) || v[e] == gran_row_fill)) {
            v[e] = gran_row_fill;
            continue;
          }
          return GRAN_ERROR(GRAN_ERR_IO, "checkpoint '%s': recorded row %zu of '%s/%s' holds %g (not a value a run records)",
                            path, e / (size_t)b.row, b.group.c_str(), b.name.c_str(), v[e]);
        }
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
  r.mine.clear();
  for (int64_t k = 0; k < r.R; k++)
    if (r.owns(k)) r.mine.push_back(k);
  const int64_t nmine = (int64_t)r.mine.size(), nheld = r.root() ? r.R : nmine;
  for (int64_t k : r.mine) {
    Replica &p = r.reps[(size_t)k];
    GRAN_CALL(gran_engine_create_(r.s, p.eng));
    GRAN_CALL(p.eng->declare(p.bufs));
    if (k == r.mine[0]) {
      int64_t bytes = 0;
      GRAN_CALL(p.eng->memory(&bytes));
      double rows = 0;
      for (const auto &b : p.bufs) rows += (double)b.row * (double)nt * 8.0;
      /* engines of this process's replicas with their rows (the scene's estimate, engine.h
       * memory()); rank 0 also holds the rows of the other processes' replicas */
      const double need = (double)bytes * (double)nmine + rows * (double)(nheld - nmine),
                   avail = gran_scene_memory_limit_(r.s);
      GRAN_CHECK(need <= avail, GRAN_ERR_NOMEM,
                 "%" PRId64 " replica(s) of this scene need about %.3g GB%s (%.3g GB each, all in memory at once), "
                 "more than the %.3g GB available: lower [engine] replicas (--replicas) or the particle numbers",
                 nmine, need / 1e9, r.comm.size > 1 ? " on this process" : "", need / 1e9 / (double)nmine, avail / 1e9);
    }
  }
  /* rank 0 records the rows of the other processes' replicas: buffers laid out as replica 0's */
  if (r.root())
    for (int64_t k = 0; k < r.R; k++)
      if (!r.owns(k)) r.reps[(size_t)k].bufs = r.reps[0].bufs;
  for (int64_t k = 0; k < r.R; k++)
    for (auto &b : r.reps[(size_t)k].bufs) {
      if (b.is_int) b.n.assign((size_t)(b.row * nt), 0);
      else b.d.assign((size_t)(b.row * nt), 0.0);
    }
  int nth = g_threads;
#ifdef _OPENMP
  if (nth <= 0) nth = omp_get_max_threads();
#endif
  if (nth <= 0) nth = 1;
  r.threads = (int)std::max<int64_t>(1, std::min<int64_t>(nth, nmine));
  return GRAN_SUCCESS;
}

/* The files of a run: distinct, and writable (before any work). */
int check_files(Run &r, const std::string &scene_file) {
  GRAN_CALL(check_distinct(r, scene_file));
  GRAN_CALL(check_writable(r.out, "output file"));
  if (!r.ckpt.empty()) GRAN_CALL(check_writable(r.ckpt, "checkpoint file"));
  return GRAN_SUCCESS;
}

/* Rank 0: the whole checkpoint file, after its checksum is verified. */
int read_whole(const char *path, std::string *bytes) {
  GRAN_CALL(gran_h5::verify_file(path, "checkpoint"));
  FILE *f = std::fopen(path, "rb");
  GRAN_CHECK(f, GRAN_ERR_IO, "cannot open checkpoint '%s': %s", path, std::strerror(errno));
  char buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes->append(buf, n);
  const bool bad = std::ferror(f) != 0;
  std::fclose(f);
  GRAN_CHECK(!bad, GRAN_ERR_IO, "cannot read checkpoint '%s'", path);
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

/* Engine events of this process's replicas. */
int local_events(Run &r, int64_t *ev) {
  *ev = 0;
  for (int64_t k : r.mine) {
    gran_engine_state a;
    GRAN_CALL(r.reps[(size_t)k].eng->state(&a));
    *ev += a.events;
  }
  return GRAN_SUCCESS;
}

/* Rows i of this process's replicas (replica order, buffer order), 8 bytes an element. */
std::string pack_rows(const Run &r, int64_t i) {
  std::string b;
  for (int64_t k : r.mine)
    for (const auto &q : r.reps[(size_t)k].bufs) {
      const char *src = q.is_int ? (const char *)(q.n.data() + i * q.row) : (const char *)(q.d.data() + i * q.row);
      b.append(src, (size_t)q.row * 8);
    }
  return b;
}

/* Rank 0: rows i of the replicas of process p (k = p, p + P, ...) from its payload. */
int unpack_rows(Run &r, int64_t i, size_t p, const std::string &b) {
  size_t at = 0;
  for (int64_t k = (int64_t)p; k < r.R; k += r.comm.size)
    for (auto &q : r.reps[(size_t)k].bufs) {
      const size_t n = (size_t)q.row * 8;
      GRAN_CHECK(at + n <= b.size(), GRAN_ERR_INTERNAL, "MPI: process %zu sent %zu bytes of rows, too few", p, b.size());
      char *dst = q.is_int ? (char *)(q.n.data() + i * q.row) : (char *)(q.d.data() + i * q.row);
      std::memcpy(dst, b.data() + at, n);
      at += n;
    }
  GRAN_CHECK(at == b.size(), GRAN_ERR_INTERNAL, "MPI: process %zu sent %zu bytes of rows, %zu expected", p, b.size(), at);
  return GRAN_SUCCESS;
}

/* Collective: statuses and events of every rank (rows i with them when i >= 0) to rank 0, which
 * files the rows and sums the events into r.events_all; v gets the first failure. */
int exchange(Run &r, int st, int64_t i, Verdict *v) {
  int64_t ev = 0;
  if (st == GRAN_SUCCESS) st = local_events(r, &ev);
  std::string rows;
  if (st == GRAN_SUCCESS && i >= 0 && !r.root()) rows = pack_rows(r, i);
  std::vector<Part> parts;
  GRAN_CALL(gather_parts(r, st, ev, std::move(rows), &parts));
  if (!r.root()) return GRAN_SUCCESS;
  first_failure(r, parts, v);
  if (v->st) return GRAN_SUCCESS;
  r.events_all = 0;
  for (size_t p = 0; p < parts.size(); p++) {
    r.events_all += parts[p].events;
    if (p > 0 && i >= 0 && (int64_t)p < r.R && (st = unpack_rows(r, i, p, parts[p].payload)) != GRAN_SUCCESS) {
      v->st = st;
      v->msg = gran_last_error_message();
      return GRAN_SUCCESS;
    }
  }
  return GRAN_SUCCESS;
}

/* Collective, after a numeric failure (a non-finite row, or an engine's GRAN_ERR_NUMERIC) while
 * advancing to output time i: the rows 0..i-1 are good and go to the partial output, as for a
 * stopped run (no checkpoint: the state is not); the error is returned with where they are. */
int numeric_stop(Run &r, int64_t i) {
  const std::string msg = gran_last_error_message(), part = gran_partial_path_(r.out);
  r.next = i;
  if (i == 0) return GRAN_ERROR(GRAN_ERR_NUMERIC, "%s; no output time was recorded, no output written", msg.c_str());
  GRAN_CALL(sync_status(r, r.root() ? write_output(r, part, i) : GRAN_SUCCESS));
  return GRAN_ERROR(GRAN_ERR_NUMERIC, "%s; the %" PRId64 " output time(s) before it are in '%s' (complete = 0)", msg.c_str(),
                    i, part.c_str());
}

/* The loop shared by run and resume: record rows next..ntimes-1, checkpoint, finish.
 * Progress and ETA are weighted by the engine's work estimate to each output time. With several
 * processes every step is collective; rank 0 alone calls the progress callback, decides on
 * checkpoints and stopping, and writes files. */
int drive(Run &r, const gran_run_control *ctl, gran_run_result *res) {
  const gran_scene *s = r.s;
  const int64_t nt = (int64_t)s->times.size();
  const bool root = r.root();
  const double w0 = now_s();
  double w_ckpt = w0;
  /* events summed over the replicas (all processes, as of the last exchange); time: replica 0's */
  auto state = [&](gran_engine_state *x) -> int {
    gran_engine_state a;
    if (root) GRAN_CALL(r.reps[0].eng->state(&a));
    else if (!r.mine.empty()) GRAN_CALL(r.reps[(size_t)r.mine[0]].eng->state(&a));
    a.events = r.events_all;
    *x = a;
    return GRAN_SUCCESS;
  };
  {
    Verdict v;
    GRAN_CALL(exchange(r, GRAN_SUCCESS, -1, &v));
    GRAN_CALL(share_verdict(r, &v));
  }
  if (!root) GRAN_CALL(local_events(r, &r.events_all)); /* their own, for their (unused) result */
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
  const bool progress = root && ctl && ctl->progress;
  std::vector<double> work, tw(s->times);
  if (progress) {
    tw.push_back(s->t_end);
    work.assign(tw.size(), 0.0);
    GRAN_CALL(r.eng()->work((int64_t)tw.size(), tw.data(), work.data())); /* the same for every replica */
  }
  const int64_t first = r.next;
  while (r.next < nt) {
    const int64_t i = r.next;
    Verdict v;
    GRAN_CALL(exchange(r, for_replicas(r, [&](int64_t k) {
                          Replica &p = r.reps[(size_t)k];
                          GRAN_CALL(p.eng->advance(s->times[(size_t)i]));
                          GRAN_CALL(p.eng->record(p.bufs, i));
                          return check_row(p.bufs, i, s);
                        }),
                       i, &v));
    r.next = i + 1;
    if (root && !v.st) {
      int stop = 0;
      if (progress) {
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
        v.stop = stop && r.next < nt;
      } else {
        const bool due = stop || (s->checkpoint_every > 0 && r.next % s->checkpoint_every == 0) ||
                         (s->checkpoint_interval > 0 && now_s() - w_ckpt >= s->checkpoint_interval);
        v.ckpt = due;
        v.stop = due && (stop || (ctl && ctl->stop_after_checkpoints > 0 && nckpt + 1 >= ctl->stop_after_checkpoints));
      }
    }
    const int vst = share_verdict(r, &v);
    if (vst == GRAN_ERR_NUMERIC) return numeric_stop(r, i);
    if (vst != GRAN_SUCCESS) return vst;
    if (v.ckpt) {
      GRAN_CALL(write_checkpoint(r));
      w_ckpt = now_s();
      nckpt++;
    }
    if (v.stop) {
      GRAN_CALL(sync_status(r, root ? write_output(r, gran_partial_path_(r.out), r.next) : GRAN_SUCCESS));
      fill(0);
      return GRAN_SUCCESS;
    }
  }
  Verdict v;
  GRAN_CALL(exchange(r, for_replicas(r, [&](int64_t k) {
                        gran_engine_state x;
                        GRAN_CALL(r.reps[(size_t)k].eng->state(&x));
                        return x.time < s->t_end ? r.reps[(size_t)k].eng->advance(s->t_end) : GRAN_SUCCESS;
                      }),
                     -1, &v));
  if (!root) GRAN_CALL(local_events(r, &r.events_all));
  if (root && !v.st) {
    const int wst = write_output(r, r.out, nt);
    if (wst != GRAN_SUCCESS) {
      v.st = wst;
      v.msg = gran_last_error_message();
    } else {
      remove_partial(r);
      if (!r.ckpt.empty() && !s->keep_checkpoint) std::remove(r.ckpt.c_str());
    }
  }
  GRAN_CALL(share_verdict(r, &v));
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
    r.comm = g_comm;
    r.s = scene;
    r.out = output ? output : scene->output_path;
    r.ckpt = gran_run_checkpoint_path_(scene, output, checkpoint);
    GRAN_CHECK(!r.out.empty(), GRAN_ERR_ARG, "argument 'output' is empty");
    if (result) *result = gran_run_result{};
    /* rank 0 alone touches the output and checkpoint files */
    GRAN_CALL(sync_status(r, r.root() ? check_files(r, scene->name) : GRAN_SUCCESS));
    r.R = scene->replicas;
    r.keep = scene->keep_replicas;
    int st = prepare(r);
    if (st == GRAN_SUCCESS) st = start_replicas(r);
    GRAN_CALL(sync_status(r, st));
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
    r.comm = g_comm;
    std::string text, name, format, out, bytes;
    /* the whole file against its checksum before HDF5 parses any of it; with several processes
     * rank 0 reads it and every rank gets its bytes */
    if (r.comm.size == 1) {
      GRAN_CALL(gran_h5::verify_file(checkpoint, "checkpoint"));
    } else {
      GRAN_CALL(sync_status(r, r.root() ? read_whole(checkpoint, &bytes) : GRAN_SUCCESS));
      if (r.comm.bcast(r.comm.ctx, &bytes)) return comm_error("broadcast of the checkpoint");
    }
    {
      H5File f;
      f.id = open_checkpoint(r, checkpoint, bytes);
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
    if (result) *result = gran_run_result{};
    GRAN_CALL(sync_status(r, r.root() ? check_files(r, name) : GRAN_SUCCESS));
    auto restore = [&]() -> int {
      GRAN_CALL(prepare(r));
      GRAN_CALL(read_checkpoint_observer(r, checkpoint, bytes));
      H5File f;
      f.id = open_checkpoint(r, checkpoint, bytes);
      GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "cannot open checkpoint '%s'", checkpoint);
      for (int64_t k : r.mine) {
        uint64_t seed = 0;
        GRAN_CALL(replica_seed(r.s->seed, k, &seed));
        GRAN_CALL(r.reps[(size_t)k].eng->checkpoint_read(f.id, checkpoint, engine_group(k).c_str(), seed));
      }
      return GRAN_SUCCESS;
    };
    GRAN_CALL(sync_status(r, restore()));
    std::string().swap(bytes);
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
  const int64_t was = scene->replicas;
  scene->replicas = replicas;
  /* the memory check of the scene, again with these replicas */
  const int st = gran_scene_check_memory_(scene, "argument 'replicas'");
  if (st != GRAN_SUCCESS) {
    scene->replicas = was;
    return st;
  }
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

void gran_run_set_comm_(const gran_run_comm *comm) {
  g_comm = comm && comm->size > 1 ? *comm : gran_run_comm();
}
