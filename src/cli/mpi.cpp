/* mpi.cpp - the processes of build/granary-mpi (compiled with -DGRAN_MPI by mpicxx); without
 * GRAN_MPI (build/granary) one process and no MPI at all.
 *
 * Installs a gran_run_comm (src/io/run_comm.h) over MPI_COMM_WORLD: gather = every rank sends its
 * bytes to rank 0, which receives them in rank order (point to point, 1 GiB pieces, so a
 * checkpoint's engine states may exceed 2 GiB); bcast = rank 0's bytes to every rank. The run
 * driver in libgranary calls them from its main thread only (MPI_THREAD_FUNNELED).
 *
 * And a srd_bricks_comm (src/srd/bricks.h) for `granary decompose`, one GSRD brick per process:
 * round = an MPI_Allreduce of whether any process has a message beyond its peers (the bricks
 * around it), then, with the peers (every process when one has), the counts and the non-empty
 * payloads by MPI_Irecv / MPI_Isend and MPI_Waitall; allreduce = MPI_Allreduce of the record as one contiguous type with
 * an MPI_Op over libgranary's exact merge (commutative). */
#ifdef GRAN_MPI
#include <mpi.h>
#endif

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "cli.h"
#include "io/run_comm.h"
#include "srd/bricks.h"

namespace {
int g_rank = 0, g_size = 1;
long long g_steps = 0, g_bytes = 0; /* collective gathers and bytes rank 0 received from the others */
long long g_far_rounds = 0;         /* decomposed GSRD rounds that went beyond the peers */
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

/* the round's messages to and from the processes `who` (sorted, symmetric: each of them posts
 * to this one too): counts first, then the non-empty payloads */
int exchange(std::vector<std::vector<double>> &out, std::vector<std::vector<double>> &in, const std::vector<int> &who) {
  const size_t m = who.size();
  std::vector<int64_t> sc(m), rc(m, 0);
  std::vector<MPI_Request> rq;
  rq.reserve(2 * m);
  for (size_t j = 0; j < m; ++j) {
    sc[j] = (int64_t)out[(size_t)who[j]].size();
    rq.emplace_back();
    if (MPI_Irecv(&rc[j], 1, MPI_INT64_T, who[j], 6, MPI_COMM_WORLD, &rq.back()) != MPI_SUCCESS) return 1;
  }
  for (size_t j = 0; j < m; ++j) {
    rq.emplace_back();
    if (MPI_Isend(&sc[j], 1, MPI_INT64_T, who[j], 6, MPI_COMM_WORLD, &rq.back()) != MPI_SUCCESS) return 1;
  }
  if (MPI_Waitall((int)rq.size(), rq.data(), MPI_STATUSES_IGNORE) != MPI_SUCCESS) return 1;
  rq.clear();
  for (size_t j = 0; j < m; ++j) {
    std::vector<double> &b = in[(size_t)who[j]];
    if (rc[j] < 0 || rc[j] > INT_MAX || sc[j] > INT_MAX) return 1;
    b.resize((size_t)rc[j]);
    if (rc[j] == 0) continue;
    rq.emplace_back();
    if (MPI_Irecv(b.data(), (int)rc[j], MPI_DOUBLE, who[j], 7, MPI_COMM_WORLD, &rq.back()) != MPI_SUCCESS) return 1;
  }
  for (size_t j = 0; j < m; ++j) {
    if (sc[j] == 0) continue;
    rq.emplace_back();
    if (MPI_Isend(out[(size_t)who[j]].data(), (int)sc[j], MPI_DOUBLE, who[j], 7, MPI_COMM_WORLD, &rq.back()) !=
        MPI_SUCCESS)
      return 1;
  }
  return MPI_Waitall((int)rq.size(), rq.data(), MPI_STATUSES_IGNORE) != MPI_SUCCESS;
}

/* a round: one MPI_Allreduce of "a message beyond my peers"; none (the usual case): the peers
 * exchange; else every pair of processes */
int bricks_round(void *, std::vector<std::vector<double>> &out, std::vector<std::vector<double>> &in,
                 const std::vector<int> &peers) {
  const int P = g_size;
  std::vector<char> peer((size_t)P, 0);
  for (int p : peers) peer[(size_t)p] = 1;
  int far = 0, any = 0;
  for (int p = 0; p < P; ++p) {
    in[(size_t)p].clear();
    if (p != g_rank && !peer[(size_t)p] && !out[(size_t)p].empty()) far = 1;
  }
  if (MPI_Allreduce(&far, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD) != MPI_SUCCESS) return 1;
  g_far_rounds += any;
  if (!any) return exchange(out, in, peers);
  std::vector<int> all;
  for (int p = 0; p < P; ++p)
    if (p != g_rank) all.push_back(p);
  return exchange(out, in, all);
}

/* the MPI_Op of the all-reduce calls the merge of the record being reduced (one at a time) */
void (*g_merge)(void *, const void *) = nullptr;
size_t g_merge_bytes = 0;
void merge_op(void *in, void *inout, int *len, MPI_Datatype *) {
  for (int i = 0; i < *len; ++i)
    g_merge((char *)inout + (size_t)i * g_merge_bytes, (const char *)in + (size_t)i * g_merge_bytes);
}

int bricks_allreduce(void *, void *buf, size_t nbytes, void (*merge)(void *, const void *)) {
  static MPI_Datatype type = MPI_DATATYPE_NULL;
  static size_t type_bytes = 0;
  static MPI_Op op = MPI_OP_NULL;
  if (nbytes > (size_t)INT_MAX) return 1;
  if (type_bytes != nbytes) {
    if (type != MPI_DATATYPE_NULL) MPI_Type_free(&type);
    if (MPI_Type_contiguous((int)nbytes, MPI_BYTE, &type) != MPI_SUCCESS || MPI_Type_commit(&type) != MPI_SUCCESS)
      return 1;
    type_bytes = nbytes;
  }
  if (op == MPI_OP_NULL && MPI_Op_create(&merge_op, 1, &op) != MPI_SUCCESS) return 1;
  g_merge = merge;
  g_merge_bytes = nbytes;
  std::vector<char> res(nbytes);
  if (MPI_Allreduce(buf, res.data(), 1, type, op, MPI_COMM_WORLD) != MPI_SUCCESS) return 1;
  std::memcpy(buf, res.data(), nbytes);
  return 0;
}

srd_bricks_comm g_bricks;

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
  g_bricks.rank = g_rank;
  g_bricks.size = g_size;
  g_bricks.round = bricks_round;
  g_bricks.allreduce = bricks_allreduce;
  return 0;
}

void cli_mpi_finalize(void) { MPI_Finalize(); }

const srd_bricks_comm *cli_mpi_bricks_comm(void) { return &g_bricks; }

void cli_mpi_abort(int code) { MPI_Abort(MPI_COMM_WORLD, code); }

int cli_mpi_all(int ok) {
  int in = ok ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return out;
}

#else

int cli_mpi_init(int *, char ***) { return 0; }
void cli_mpi_finalize(void) {}
int cli_mpi_all(int ok) { return ok; }
const srd_bricks_comm *cli_mpi_bricks_comm(void) {
  static srd_bricks_comm one; /* rank 0 of 1 */
  return &one;
}
void cli_mpi_abort(int) {}

#endif

int cli_mpi_rank(void) { return g_rank; }
long long cli_mpi_far_rounds(void) { return g_far_rounds; }
int cli_mpi_size(void) { return g_size; }
void cli_mpi_stats(long long *steps, long long *bytes) {
  *steps = g_steps;
  *bytes = g_bytes;
}
