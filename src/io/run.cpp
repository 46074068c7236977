/* run.cpp - running a scene: engine, observers at the output times, HDF5 output, checkpoints.
 *
 * The engine is only ever advanced to the scene's output times (then to t_end), whether or not a
 * checkpoint is written there, so a run split by checkpoints makes exactly the same calls as an
 * uninterrupted one: resuming is bit for bit. Recorded rows live in named buffers [ntimes x row];
 * the output file and the checkpoint's /observer group are written from the same buffers.
 * Every engine is reached through the interface of engine.h (one adapter per engine). This file
 * holds the drive loop and the public entry points; the output file, checkpoints, the run's files
 * and the steps between processes are in the files run_impl.h lists. */
#include <hdf5.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "io/run_impl.h"

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace gran_run;

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

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

/* A scene whose gas is split over the processes ([engine] decomposition): each replica on P / R
 * of them (P = R: the replicas as without a split). */
int split_over(Run &r) {
  if (!r.s->split_gas || r.comm.size == 1) return GRAN_SUCCESS;
  GRAN_CHECK(r.comm.size % r.R == 0, GRAN_ERR_UNSUPPORTED,
             "scene '%s': %" PRId64 " replicas of a gas split over the processes ([engine] decomposition) need a "
             "multiple of %" PRId64 " processes (each replica on the same number of them), and this run has %d",
             r.s->name.c_str(), r.R, r.R, r.comm.size);
  r.bricks = r.comm.size / r.R;
  r.split = r.bricks > 1;
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
        p.temperature = x.temperature;
        p.work_unit = x.work_unit;
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
  if (!r.ckpt.empty() && !s->keep_checkpoint)
    for (int64_t k : r.mine) r.reps[(size_t)k].eng->checkpoint_remove();
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
    GRAN_CALL(split_over(r));
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
    GRAN_CALL(split_over(r));
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
