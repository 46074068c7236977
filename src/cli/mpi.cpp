/* mpi.cpp - the processes of build/granary-mpi (compiled with -DGRAN_MPI by mpicxx); without
 * GRAN_MPI (build/granary) one process and no MPI at all.
 *
 * Installs a gran_run_comm (src/io/run_comm.h) over MPI_COMM_WORLD: gather = every rank sends its
 * bytes to rank 0, which receives them in rank order (point to point, 1 GiB pieces, so a
 * checkpoint's engine states may exceed 2 GiB); bcast = rank 0's bytes to every rank. The run
 * driver in libgranary calls them from its main thread only (MPI_THREAD_FUNNELED). */
#ifdef GRAN_MPI
#include <mpi.h>
#endif

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "cli.h"
#include "io/run_comm.h"

namespace {
int g_rank = 0, g_size = 1;
long long g_steps = 0, g_bytes = 0; /* collective gathers and bytes rank 0 received from the others */
}  // namespace

#ifdef GRAN_MPI
namespace {
const size_t kPiece = (size_t)1 << 30;

int send_bytes(const std::string &b, int dest) {
  int64_t n = (int64_t)b.size();
  if (MPI_Send(&n, 1, MPI_INT64_T, dest, 1, MPI_COMM_WORLD) != MPI_SUCCESS) return 1;
  for (size_t at = 0; at < b.size(); at += kPiece)
    if (MPI_Send(b.data() + at, (int)std::min(kPiece, b.size() - at), MPI_BYTE, dest, 2, MPI_COMM_WORLD) != MPI_SUCCESS)
      return 1;
  return 0;
}

int recv_bytes(std::string *b, int src) {
  int64_t n = 0;
  if (MPI_Recv(&n, 1, MPI_INT64_T, src, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE) != MPI_SUCCESS || n < 0) return 1;
  b->resize((size_t)n);
  for (size_t at = 0; at < b->size(); at += kPiece)
    if (MPI_Recv(&(*b)[at], (int)std::min(kPiece, b->size() - at), MPI_BYTE, src, 2, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE) != MPI_SUCCESS)
      return 1;
  return 0;
}

int gather(void *, const std::string &mine, std::vector<std::string> *all) {
  g_steps++;
  if (g_rank != 0) return send_bytes(mine, 0);
  all->assign((size_t)g_size, std::string());
  (*all)[0] = mine;
  for (int p = 1; p < g_size; p++) {
    if (recv_bytes(&(*all)[(size_t)p], p)) return 1;
    g_bytes += (long long)(*all)[(size_t)p].size();
  }
  return 0;
}

int bcast(void *, std::string *b) {
  int64_t n = (int64_t)b->size();
  if (MPI_Bcast(&n, 1, MPI_INT64_T, 0, MPI_COMM_WORLD) != MPI_SUCCESS) return 1;
  b->resize((size_t)n);
  for (size_t at = 0; at < b->size(); at += kPiece)
    if (MPI_Bcast(&(*b)[at], (int)std::min(kPiece, b->size() - at), MPI_BYTE, 0, MPI_COMM_WORLD) != MPI_SUCCESS) return 1;
  return 0;
}
}  // namespace

int cli_mpi_init(int *argc, char ***argv) {
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) return 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  gran_run_comm c;
  c.rank = g_rank;
  c.size = g_size;
  c.gather = gather;
  c.bcast = bcast;
  gran_run_set_comm_(&c);
  return 0;
}

void cli_mpi_finalize(void) { MPI_Finalize(); }

int cli_mpi_all(int ok) {
  int in = ok ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return out;
}

#else

int cli_mpi_init(int *, char ***) { return 0; }
void cli_mpi_finalize(void) {}
int cli_mpi_all(int ok) { return ok; }

#endif

int cli_mpi_rank(void) { return g_rank; }
int cli_mpi_size(void) { return g_size; }
void cli_mpi_stats(long long *steps, long long *bytes) {
  *steps = g_steps;
  *bytes = g_bytes;
}
