/* run_impl.h - what the parts of the run driver share: the Run of a scene, the messages between its
 * processes, and the functions one part calls in another.
 *   run.cpp             the drive loop, replicas and threads, the public entry points
 *   run_output.cpp      the output file (root attributes, rows reduced over replicas, partial
 *                       output of a stopped run) and the row rule (check_row)
 *   run_checkpoint.cpp  writing and reading checkpoints (engine states of every process)
 *   run_files.cpp       the files of a run: folders, writability, identity, default paths
 *   run_comm.cpp        the collective steps between processes (run_comm.h) */
#ifndef GRANARY_IO_RUN_IMPL_H
#define GRANARY_IO_RUN_IMPL_H

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/engine.h"
#include "io/run_comm.h"

namespace gran_run {

constexpr const char *kCheckpointFormat = "granary-checkpoint 1";
constexpr const char *kOutputFormat = "granary-output 1";

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
  std::vector<int64_t> mine; /* the replicas this process runs: k % comm.size == comm.rank (split: 0) */
  /* the scene's gas is split over the processes (gran_scene.split_gas, P > R): replica k on the
   * `bricks` consecutive processes from k bricks, each holding a part of it; its engine calls are
   * collective among them and give each the same rows; the group's first process sends them to
   * rank 0 and counts the events; its state is checkpointed as a set of part files, one per process
   * (the engine writes them, the checkpoint commits them) */
  bool split = false;
  int64_t bricks = 1; /* processes per replica (split) */
  int64_t events_all = 0;    /* rank 0: engine events of all replicas at the last exchange */
  int64_t R = 1;
  int keep = 0;              /* keep_replicas */
  int threads = 1;           /* threads used for the replicas */
  int64_t next = 0;          /* output times recorded */
  std::string out, ckpt;
  gran_engine *eng() const { return reps[0].eng.get(); } /* rank 0 only (it runs replica 0) */
  bool root() const { return comm.rank == 0; }
  bool owns(int64_t k) const { return split ? k == comm.rank / bricks : k % comm.size == comm.rank; }
  /* the replicas whose rows process p sends rank 0 (split: its replica, when p is its group's first) */
  std::vector<int64_t> rows_of(int p) const {
    std::vector<int64_t> v;
    if (split) {
      if (p % bricks == 0 && p / bricks < R) v.push_back(p / bricks);
    } else {
      for (int64_t k = p; k < R; k += comm.size) v.push_back(k);
    }
    return v;
  }
  ~Run() {
    reps.clear();
    gran_scene_destroy(&owned_scene);
  }
};

struct H5File {
  int64_t id = -1;
  ~H5File() { gran_h5::close_file(id); }
};
struct H5Group {
  int64_t id = -1;
  ~H5Group() { gran_h5::close_group(id); }
};

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

/* ---- run_comm.cpp ---- */
int comm_error(const char *what);
/* Every rank's part to rank 0: parts (rank order) on rank 0; untouched on the others. */
int gather_parts(Run &r, int st, int64_t events, std::string payload, std::vector<Part> *parts);
/* rank 0: the first failing part, in rank order, into v */
void first_failure(const Run &r, const std::vector<Part> &parts, Verdict *v);
/* Rank 0's verdict to every rank; returns its status, with its message, on every rank. */
int share_verdict(Run &r, Verdict *v);
/* Collective: every rank's status st; the first failure (rank order) on every rank. */
int sync_status(Run &r, int st);
/* Engine events of this process's replicas. */
int local_events(Run &r, int64_t *ev);
/* Collective: statuses and events of every rank (rows i with them when i >= 0) to rank 0, which
 * files the rows and sums the events into r.events_all; v gets the first failure. */
int exchange(Run &r, int st, int64_t i, Verdict *v);

/* ---- run_files.cpp ---- */
/* The files of a run: distinct, and writable (before any work). */
int check_files(Run &r, const std::string &scene_file);

/* ---- run_output.cpp ---- */
/* Row i of every buffer of a replica, right after record: finite, or fill where allowed. */
int check_row(std::vector<gran_row_buf> &bufs, int64_t i, const gran_scene *s);
/* The root attributes an output file and a checkpoint share. */
int write_root_attrs(Run &r, int64_t f, const char *file, const char *format);
/* The output file with the first nrec output times, and its sidecars. */
int write_output(Run &r, const std::string &path, int64_t nrec);
/* A finished run: the partial output of an earlier stop and its sidecars go. */
void remove_partial(Run &r);

/* ---- run_checkpoint.cpp ---- */
/* Checkpoint group of the engine state of replica k. */
std::string engine_group(int64_t k);
/* Collective: every rank's engine states into the one checkpoint file rank 0 writes. */
int write_checkpoint(Run &r);
/* The checkpoint: from disk with one process; from the bytes rank 0 read and broadcast with more. */
int64_t open_checkpoint(const Run &r, const char *path, const std::string &bytes);
/* The recorded rows and next_index of a checkpoint into r's buffers. */
int read_checkpoint_observer(Run &r, const char *path, const std::string &bytes);
/* Rank 0: the whole checkpoint file, after its checksum is verified. */
int read_whole(const char *path, std::string *bytes);

}  // namespace gran_run

#endif
