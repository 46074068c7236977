/* run_comm.h - how the run driver (src/io/run.cpp) spreads replicas over processes without
 * libgranary linking MPI.
 *
 * libgranary holds no MPI call: a driver built with MPI (src/cli/mpi.cpp, compiled into
 * build/granary-mpi by mpicxx) fills a gran_run_comm with its rank, size and two byte-moving
 * functions over MPI_COMM_WORLD and installs it with gran_run_set_comm_ before it runs a scene.
 * Without one (every C/Fortran user, build/granary), a run is one process, exactly as before.
 *
 * With P > 1 processes replica k runs on rank k % P (RNG stream k wherever it runs); at each
 * output time rank 0 gathers every replica's row, in rank order, and reduces them in replica order
 * when it writes (the threaded code path): the output equals the threaded run bit for bit. Rank 0
 * alone writes the output file and the checkpoint (it gathers the other ranks' engine states into
 * the one file); resume reads the checkpoint on rank 0 and broadcasts its bytes, so it works with
 * any P. Every step ends in a verdict rank 0 broadcasts: an error on any rank stops every rank
 * with that rank's message. Both functions are called from the main thread only, by every rank in
 * the same order; they return 0 on success. */
#ifndef GRANARY_IO_RUN_COMM_H
#define GRANARY_IO_RUN_COMM_H

#include <cstdint>
#include <string>
#include <vector>

struct gran_run_comm {
  int rank = 0, size = 1;
  void *ctx = nullptr;
  /* rank 0: all[p] = the bytes rank p passed (all[0] = its own); other ranks: all is untouched */
  int (*gather)(void *ctx, const std::string &mine, std::vector<std::string> *all) = nullptr;
  /* rank 0's bytes to every rank */
  int (*bcast)(void *ctx, std::string *bytes) = nullptr;
};

/* Install the process group for gran_scene_run / gran_scene_resume (nullptr or size 1: one
 * process). The struct is copied. Not thread-safe: call before running. */
void gran_run_set_comm_(const gran_run_comm *comm);

#endif
