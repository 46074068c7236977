/* mpi.cpp - the processes of build/granary-mpi (compiled with -DGRAN_MPI by mpicxx); without
 * GRAN_MPI (build/granary) one process and no MPI at all.
 *
 * Installs a gran_run_comm (src/io/run_comm.h) over MPI_COMM_WORLD: gather = every rank sends its
 * bytes to rank 0, which receives them in rank order (point to point, 1 GiB pieces, so a
 * checkpoint's engine states may exceed 2 GiB); bcast = rank 0's bytes to every rank. The run
 * driver in libgranary calls them from its main thread only (MPI_THREAD_FUNNELED). Both are
 * non-blocking calls waited for at most the timeout (`granary run --timeout`; none by default:
 * a process honestly waits there for the slowest replica's steps and for rank 0's writing).
 *
 * And a srd_bricks_comm (src/srd/bricks.h) for `granary decompose`, one GSRD brick per process:
 * round = the non-blocking consensus exchange (MPI_Issend of the non-empty messages, MPI_Iprobe,
 * MPI_Ibarrier: below); allreduce = MPI_Iallreduce of records, each one contiguous type, with an
 * MPI_Op over libgranary's exact merge (commutative). A process waits in one round or reduction at
 * most the timeout (cli_mpi_set_timeout; `granary decompose --timeout`): beyond it, a process that
 * stopped answering without dying (stopped, hung, its machine gone quiet) is named where the
 * exchange knows it, and the round fails, which stops every process. With FFTW's MPI interface
 * (GRAN_HAVE_FFTW_MPI: Debian libfftw3-mpi-dev) also fft_r2c = FFTW's distributed real-to-complex
 * transform (fftw_mpi_plan_many_dft_r2c in the slabs libgranary chose, planned once per shape).
 *
 * The polled waits cannot see a process stuck inside MPI itself: a blocking collective (FFTW's
 * transform), or a transfer whose sender stopped halfway through its fragments. So every wait is
 * also watched by a thread of its own (it calls no MPI): a wait that lasts a second beyond the
 * limit is named on stderr by that thread, which ends the process (_exit(1)); mpirun then stops
 * every other process. */
#ifdef GRAN_MPI
#include <mpi.h>
#ifdef GRAN_HAVE_FFTW_MPI
#include <fftw3-mpi.h>
#endif
#endif

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "cli.h"
#include "io/run_comm.h"
#include "srd/bricks.h"

namespace {
int g_rank = 0, g_size = 1, g_local = 1;
/* seconds one process waits in one round or reduction (the watchdog reads it too); 0: no limit */
std::atomic<double> g_timeout{600.0};
long long g_steps = 0, g_bytes = 0; /* collective gathers and bytes rank 0 received from the others */
}  // namespace

#ifdef GRAN_MPI
namespace {
const size_t kPiece = (size_t)1 << 30;
/* the process group of this process's split gas (cli_mpi_bricks_groups: replicas of a split gas, each
 * on its own group of consecutive ranks; else the world): its rank, size and first world rank */
MPI_Comm g_bcomm = MPI_COMM_NULL;
int g_brank = 0, g_bsize = 1, g_bbase = 0;

/* The wait in progress, for the watchdog thread: its start (steady clock, ns; 0: none), what it is
 * and the process it waits for (-1: cannot tell). Set by the main thread only, one wait at a time. */
std::atomic<long long> g_wait_t0{0};
std::atomic<const char *> g_wait_what{nullptr};
std::atomic<int> g_wait_peer{-1};
std::atomic<bool> g_dog_stop{false};
std::atomic<bool> g_aborting{false}; /* the polled wait has said why and called MPI_Abort */

long long now_ns() {
  return (long long)std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

/* marks the scope of one wait; nested in another (a receive inside a round), it keeps the outer
 * one's start and names its own process while it lasts */
struct Watched {
  bool outer;
  const char *what0;
  int peer0;
  Watched(const char *what, int peer) : outer(g_wait_t0.load() == 0), what0(g_wait_what.load()), peer0(g_wait_peer.load()) {
    g_wait_what.store(what);
    g_wait_peer.store(peer);
    if (outer) g_wait_t0.store(now_ns());
  }
  ~Watched() {
    if (outer) g_wait_t0.store(0);
    g_wait_what.store(what0);
    g_wait_peer.store(peer0);
  }
  Watched(const Watched &) = delete;
  Watched &operator=(const Watched &) = delete;
};

/* why this process stops every process: one line on stderr (one write, from either thread) */
void say_overdue(double waited, const char *what, int peer, double limit) {
  char line[512];
  if (peer >= 0)
    std::snprintf(line, sizeof line,
                  "granary-mpi: rank %d: waited %.0f s in %s for rank %d, which does not answer (stopped or hung); "
                  "stopping every process (the limit: --timeout %g)\n",
                  g_rank, waited, what, peer, limit);
  else
    std::snprintf(line, sizeof line,
                  "granary-mpi: rank %d: waited %.0f s in %s for a process that has not reached it (stopped, hung or "
                  "far slower); stopping every process (the limit: --timeout %g)\n",
                  g_rank, waited, what, limit);
  const ssize_t w = write(2, line, std::strlen(line));
  (void)w;
}

/* the watchdog: a wait a second past the limit ends this process (no MPI call: the main thread may
 * be inside one) */
void watchdog() {
  while (!g_dog_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const double limit = g_timeout.load();
    const long long t0 = g_wait_t0.load();
    if (!(limit > 0.0) || t0 == 0) continue;
    const double waited = 1e-9 * (double)(now_ns() - t0);
    if (waited <= limit + 1.0) continue;
    if (g_aborting.load()) _exit(1); /* MPI_Abort did not end it: the message is out already */
    const char *what = g_wait_what.load();
    say_overdue(waited, what ? what : "an exchange", g_wait_peer.load(), limit);
    _exit(1);
  }
}

int wait_for(MPI_Request *req, const char *what, int peer = -1);

/* the run driver's point-to-point pieces, each waited for at most the timeout (the process on the
 * other side named) */
int send_bytes(const std::string &b, int dest) {
  const char *what = "the gather of the replicas' output";
  int64_t n = (int64_t)b.size();
  MPI_Request req = MPI_REQUEST_NULL;
  if (MPI_Isend(&n, 1, MPI_INT64_T, dest, 1, MPI_COMM_WORLD, &req) != MPI_SUCCESS || wait_for(&req, what, dest)) return 1;
  for (size_t at = 0; at < b.size(); at += kPiece)
    if (MPI_Isend(b.data() + at, (int)std::min(kPiece, b.size() - at), MPI_BYTE, dest, 2, MPI_COMM_WORLD, &req) !=
            MPI_SUCCESS ||
        wait_for(&req, what, dest))
      return 1;
  return 0;
}

int recv_bytes(std::string *b, int src) {
  const char *what = "the gather of the replicas' output";
  int64_t n = 0;
  MPI_Request req = MPI_REQUEST_NULL;
  if (MPI_Irecv(&n, 1, MPI_INT64_T, src, 1, MPI_COMM_WORLD, &req) != MPI_SUCCESS || wait_for(&req, what, src) || n < 0)
    return 1;
  b->resize((size_t)n);
  for (size_t at = 0; at < b->size(); at += kPiece)
    if (MPI_Irecv(&(*b)[at], (int)std::min(kPiece, b->size() - at), MPI_BYTE, src, 2, MPI_COMM_WORLD, &req) !=
            MPI_SUCCESS ||
        wait_for(&req, what, src))
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

/* false while the wait that began at t0 is within the timeout; beyond it, says why on stderr and stops
 * every process */
bool overdue(double t0, const char *what, int peer) {
  if (!(g_timeout > 0.0)) return false;
  const double waited = MPI_Wtime() - t0;
  if (waited <= g_timeout) return false;
  say_overdue(waited, what, peer, g_timeout.load());
  /* the others may never answer again (MPI_Finalize would wait for them too): stop here */
  g_aborting.store(true);
  MPI_Abort(MPI_COMM_WORLD, 1);
  return true;
}

/* waits for req, at most the timeout (peer: the process it waits for, -1 when it cannot tell) */
int wait_for(MPI_Request *req, const char *what, int peer) {
  const Watched watched(what, peer);
  const double t0 = MPI_Wtime();
  for (;;) {
    int done = 0;
    if (MPI_Test(req, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS) return 1;
    if (done) return 0;
    if (overdue(t0, what, peer)) return 1;
  }
}

/* A round by the non-blocking consensus of Hoefler, Siebert and Lumsdaine (dynamic sparse data
 * exchange, PPoPP 2010): each non-empty message goes by MPI_Issend; the process receives whatever
 * MPI_Improbe finds (by MPI_Imrecv); once its own sends have been received it enters an
 * MPI_Ibarrier, and the round ends when the barrier completes (every process's sends received). No counts, no
 * all-to-all: a process only talks to the processes it has particles for. Rounds alternate tags,
 * so that a process one round ahead cannot be mistaken for this round's sender. */
int bricks_round(void *, std::vector<std::vector<double>> &out, std::vector<std::vector<double>> &in) {
  static int parity = 0;
  const int tag = 7 + parity;
  parity ^= 1;
  const int P = g_bsize;
  const Watched watched("the particle exchange", -1);
  const double t0 = MPI_Wtime();
  std::vector<MPI_Request> sq;
  std::vector<int> dest;
  for (int p = 0; p < P; ++p) {
    in[(size_t)p].clear();
    if (p == g_brank || out[(size_t)p].empty()) continue;
    if (out[(size_t)p].size() > (size_t)INT_MAX) return 1;
    dest.push_back(p);
    sq.emplace_back();
    if (MPI_Issend(out[(size_t)p].data(), (int)out[(size_t)p].size(), MPI_DOUBLE, p, tag, g_bcomm, &sq.back()) !=
        MPI_SUCCESS)
      return 1;
  }
  MPI_Request barrier = MPI_REQUEST_NULL;
  bool in_barrier = false;
  for (;;) {
    int flag = 0;
    MPI_Status st;
    MPI_Message msg = MPI_MESSAGE_NULL;
    if (MPI_Improbe(MPI_ANY_SOURCE, tag, g_bcomm, &flag, &msg, &st) != MPI_SUCCESS) return 1;
    if (flag) {
      /* the matched message, received without blocking: its sender may stop before its last fragment */
      int count = 0;
      if (MPI_Get_count(&st, MPI_DOUBLE, &count) != MPI_SUCCESS || count < 0) return 1;
      std::vector<double> &b = in[(size_t)st.MPI_SOURCE];
      b.resize((size_t)count);
      MPI_Request rq = MPI_REQUEST_NULL;
      if (MPI_Imrecv(b.data(), count, MPI_DOUBLE, &msg, &rq) != MPI_SUCCESS ||
          wait_for(&rq, "the particle exchange", g_bbase + st.MPI_SOURCE))
        return 1;
      continue;
    }
    int done = 0;
    if (!in_barrier) {
      if (MPI_Testall((int)sq.size(), sq.data(), &done, MPI_STATUSES_IGNORE) != MPI_SUCCESS) return 1;
      if (done) {
        if (MPI_Ibarrier(g_bcomm, &barrier) != MPI_SUCCESS) return 1;
        in_barrier = true;
      }
    } else {
      if (MPI_Test(&barrier, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS) return 1;
      if (done) return 0;
    }
    if (g_timeout > 0.0 && MPI_Wtime() - t0 > g_timeout) {
      int peer = -1; /* the first process that has not taken this one's message */
      for (size_t i = 0; i < sq.size() && !in_barrier && peer < 0; ++i) {
        int one = 0;
        if (MPI_Test(&sq[i], &one, MPI_STATUS_IGNORE) != MPI_SUCCESS) return 1;
        if (!one) peer = g_bbase + dest[i];
      }
      if (overdue(t0, "the particle exchange", peer)) return 1;
    }
  }
}

/* the MPI_Op of the all-reduce calls the merge of the record being reduced (one at a time) */
void (*g_merge)(void *, const void *) = nullptr;
size_t g_merge_bytes = 0;
void merge_op(void *in, void *inout, int *len, MPI_Datatype *) {
  for (int i = 0; i < *len; ++i)
    g_merge((char *)inout + (size_t)i * g_merge_bytes, (const char *)in + (size_t)i * g_merge_bytes);
}

int bricks_allreduce(void *, void *buf, size_t nbytes, size_t count, void (*merge)(void *, const void *)) {
  static MPI_Datatype type = MPI_DATATYPE_NULL;
  static size_t type_bytes = 0;
  static MPI_Op op = MPI_OP_NULL;
  if (nbytes > (size_t)INT_MAX || count > (size_t)INT_MAX || count > ((size_t)1 << 40) / std::max<size_t>(1, nbytes)) return 1;
  if (type_bytes != nbytes) {
    if (type != MPI_DATATYPE_NULL) MPI_Type_free(&type);
    if (MPI_Type_contiguous((int)nbytes, MPI_BYTE, &type) != MPI_SUCCESS || MPI_Type_commit(&type) != MPI_SUCCESS)
      return 1;
    type_bytes = nbytes;
  }
  if (op == MPI_OP_NULL && MPI_Op_create(&merge_op, 1, &op) != MPI_SUCCESS) return 1;
  g_merge = merge;
  g_merge_bytes = nbytes;
  std::vector<char> res(nbytes * count);
  MPI_Request req = MPI_REQUEST_NULL;
  if (MPI_Iallreduce(buf, res.data(), (int)count, type, op, g_bcomm, &req) != MPI_SUCCESS) return 1;
  if (wait_for(&req, "an all-reduce of the exact sums")) return 1;
  std::memcpy(buf, res.data(), nbytes * count);
  return 0;
}

#ifdef GRAN_HAVE_FFTW_MPI
/* the plan and its padded buffers, kept for the next transform of the same shape */
struct Fft {
  int dim = 0;
  ptrdiff_t n[3] = {0, 0, 0}, block = 0, rows = 0, alloc = 0;
  fftw_plan plan = nullptr;
  double *rin = nullptr;
  fftw_complex *cout = nullptr;
  void clear() {
    if (plan) fftw_destroy_plan(plan);
    fftw_free(rin);
    fftw_free(cout);
    plan = nullptr;
    rin = nullptr;
    cout = nullptr;
    dim = 0;
  }
} g_fft;
bool g_fftw_mpi = false;

int bricks_fft(void *, int dim, const int64_t n[3], int64_t block, const double *in, double *out) {
  if (dim < 2 || dim > 3) return 1;
  Fft &f = g_fft;
  bool same = f.plan && f.dim == dim && f.block == block;
  for (int a = 0; a < dim; ++a) same = same && f.n[a] == (ptrdiff_t)n[a];
  if (!same) {
    f.clear();
    if (!g_fftw_mpi) {
      fftw_mpi_init();
      g_fftw_mpi = true;
    }
    ptrdiff_t nc[3];
    for (int a = 0; a < dim; ++a) nc[a] = f.n[a] = (ptrdiff_t)n[a];
    nc[dim - 1] = n[dim - 1] / 2 + 1;
    ptrdiff_t start = 0;
    f.alloc = fftw_mpi_local_size_many(dim, nc, 1, (ptrdiff_t)block, g_bcomm, &f.rows, &start);
    const ptrdiff_t want = std::min<ptrdiff_t>(n[0], (ptrdiff_t)g_brank * block);
    const ptrdiff_t rows = std::min<ptrdiff_t>(n[0], want + block) - want; /* a process past the end has none */
    if (f.rows != rows || (rows > 0 && start != want)) {
      std::fprintf(stderr, "granary-mpi: process %d: FFTW's slab (rows %td + %td) is not the one asked for (from %td)\n",
                   g_rank, start, f.rows, want);
      return 1;
    }
    f.rin = fftw_alloc_real((size_t)std::max<ptrdiff_t>(1, 2 * f.alloc));
    f.cout = fftw_alloc_complex((size_t)std::max<ptrdiff_t>(1, f.alloc));
    if (!f.rin || !f.cout) {
      f.clear();
      return 1;
    }
    f.plan = fftw_mpi_plan_many_dft_r2c(dim, f.n, 1, (ptrdiff_t)block, (ptrdiff_t)block, f.rin, f.cout, g_bcomm,
                                        FFTW_ESTIMATE);
    if (!f.plan) {
      f.clear();
      return 1;
    }
    f.dim = dim;
    f.block = (ptrdiff_t)block;
  }
  /* rows of the real field: the last axis padded to 2 (n / 2 + 1) */
  const ptrdiff_t nl = f.n[dim - 1], nh = nl / 2 + 1, mid = dim == 3 ? f.n[1] : 1;
  for (ptrdiff_t r = 0; r < f.rows * mid; ++r) std::memcpy(f.rin + r * 2 * nh, in + r * nl, (size_t)nl * sizeof(double));
  {
    const Watched watched("FFTW's distributed transform", -1); /* its collective calls block: the watchdog's */
    fftw_execute(f.plan);
  }
  if (f.rows > 0) std::memcpy(out, f.cout, (size_t)(f.rows * mid * nh) * sizeof(fftw_complex)); /* none: out may be NULL */
  return 0;
}
#endif

srd_bricks_comm g_bricks;

/* a split gas's process failed inside a collective step: it says why (one write) and stops every
 * process (the others wait for it in the next exchange) */
void bricks_abort(void *, const char *msg) {
  char line[1200];
  std::snprintf(line, sizeof line, "granary-mpi: rank %d of %d: %s; stopping every process\n", g_rank, g_size, msg);
  const ssize_t w = write(2, line, std::strlen(line));
  (void)w;
  g_aborting.store(true);
  MPI_Abort(MPI_COMM_WORLD, 1);
  _exit(1);
}

int bcast(void *, std::string *b) {
  const char *what = "a broadcast of the run driver";
  const int peer = g_rank == 0 ? -1 : 0;
  int64_t n = (int64_t)b->size();
  MPI_Request req = MPI_REQUEST_NULL;
  if (MPI_Ibcast(&n, 1, MPI_INT64_T, 0, MPI_COMM_WORLD, &req) != MPI_SUCCESS || wait_for(&req, what, peer)) return 1;
  b->resize((size_t)n);
  for (size_t at = 0; at < b->size(); at += kPiece)
    if (MPI_Ibcast(&(*b)[at], (int)std::min(kPiece, b->size() - at), MPI_BYTE, 0, MPI_COMM_WORLD, &req) != MPI_SUCCESS ||
        wait_for(&req, what, peer))
      return 1;
  return 0;
}
}  // namespace

int cli_mpi_init(int *argc, char ***argv) {
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) return 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  try {
    std::thread(watchdog).detach(); /* ends with the process */
  } catch (const std::exception &) {
    std::fprintf(stderr, "granary-mpi: rank %d: warning: no watchdog thread (a wait held inside MPI outlasts the timeout)\n",
                 g_rank);
  }
  MPI_Comm node;
  if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node) == MPI_SUCCESS) {
    MPI_Comm_size(node, &g_local);
    MPI_Comm_free(&node);
  }
  gran_run_comm c;
  c.rank = g_rank;
  c.size = g_size;
  c.gather = gather;
  c.bcast = bcast;
  gran_run_set_comm_(&c);
  g_bcomm = MPI_COMM_WORLD;
  g_brank = g_rank;
  g_bsize = g_size;
  g_bricks.rank = g_rank;
  g_bricks.size = g_size;
  g_bricks.round = bricks_round;
  g_bricks.allreduce = bricks_allreduce;
#ifdef GRAN_HAVE_FFTW_MPI
  g_bricks.fft_r2c = bricks_fft;
#endif
  g_bricks.abort = bricks_abort;
  srd_bricks_set_run_comm_(&g_bricks); /* the run driver's split gas ([engine] decomposition) */
  return 0;
}

void cli_mpi_finalize(void) {
  g_dog_stop.store(true);
#ifdef GRAN_HAVE_FFTW_MPI
  g_fft.clear();
  if (g_fftw_mpi) fftw_mpi_cleanup();
#endif
  if (g_bcomm != MPI_COMM_WORLD && g_bcomm != MPI_COMM_NULL) MPI_Comm_free(&g_bcomm);
  MPI_Finalize();
}

const srd_bricks_comm *cli_mpi_bricks_comm(void) { return &g_bricks; }

void cli_mpi_abort(int code) { MPI_Abort(MPI_COMM_WORLD, code); }

int cli_mpi_bricks_groups(int groups) {
  if (groups <= 1 || g_size % groups != 0) return 0; /* one group (the world), or a count the run driver refuses */
  const int B = g_size / groups, color = g_rank / B;
  MPI_Comm c = MPI_COMM_NULL;
  if (MPI_Comm_split(MPI_COMM_WORLD, color, g_rank, &c) != MPI_SUCCESS) return 1;
#ifdef GRAN_HAVE_FFTW_MPI
  g_fft.clear(); /* a plan over the former group */
#endif
  g_bcomm = c;
  g_brank = g_rank % B;
  g_bsize = B;
  g_bbase = color * B;
  g_bricks.rank = g_brank;
  g_bricks.size = g_bsize;
  srd_bricks_set_run_comm_(&g_bricks);
  return 0;
}

int cli_mpi_bcast(std::string *b) { return bcast(nullptr, b); }

int cli_mpi_all(int ok) {
  int in = ok ? 1 : 0, out = 0;
  MPI_Request req = MPI_REQUEST_NULL;
  if (MPI_Iallreduce(&in, &out, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD, &req) != MPI_SUCCESS ||
      wait_for(&req, "the agreement before the steps"))
    return 0;
  return out;
}

#else

int cli_mpi_init(int *, char ***) { return 0; }
void cli_mpi_finalize(void) {}
int cli_mpi_all(int ok) { return ok; }
int cli_mpi_bcast(std::string *) { return 0; }
const srd_bricks_comm *cli_mpi_bricks_comm(void) {
  static srd_bricks_comm one; /* rank 0 of 1 */
  return &one;
}
void cli_mpi_abort(int) {}
int cli_mpi_bricks_groups(int) { return 0; }

#endif

void cli_mpi_set_timeout(double seconds) { g_timeout = seconds; }

int cli_mpi_rank(void) { return g_rank; }
int cli_mpi_size(void) { return g_size; }
int cli_mpi_local_size(void) { return g_local; }
void cli_mpi_stats(long long *steps, long long *bytes) {
  *steps = g_steps;
  *bytes = g_bytes;
}
