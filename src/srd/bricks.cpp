/* bricks.cpp - the decomposable GSRD engine: one box as P bricks of the binning grid (bricks.h;
 * design and measurements: docs/developers/domain-decomposition.md, "Step 2" and "Step 3"; one
 * brick per MPI process: srd_bricks_open_).
 *
 * A brick holds a window [lo, lo + w) per axis of the binning grid (s->gm.nc cells per axis; the
 * wall axis has L + 1 layers), the cells' persistent data of that window (reference velocity V,
 * RNG state: stream gc + 1 of the seed for global cell gc), the particles whose cell of the
 * current grid shift lies in the window, and a copy of the run's scalar state (time, step, the
 * shift stream, the ledger). One step, on every brick (the phases below; the driver runs each
 * phase on every brick before the next one, which is what an MPI rank does for its one brick):
 *   stream:   draw the shift (the same draw on every brick); move the brick's particles in place
 *             (srd_rule_move; its streaming terms kept per particle), skipping the holes; bin each
 *             under the new shift (srd_bin's arithmetic, Lees-Edwards included): the global cell
 *             and its owner; the particles that left are packed per destination and sent, and
 *             their slots become holes;
 *   receive:  the arrivals go into the holes nearest their cells (the rest appended), marked late
 *             until the next sort;
 *   sums:     a stable counting sort of the particles by local cell; a cell holding a late
 *             particle has its list put in key order (insertion by key: the list is in slot
 *             order, the residents in key order); per cell its sums in key
 *             order, and the per-particle streaming terms of its particles summed in the same
 *             order into one double per cell, added to exact accumulators (one exact add per cell
 *             and quantity); then, without the global thermostat, at once the cell's rule
 *             (srd_rule_cell: the global cell index for the geometry, the cell's own RNG) and the
 *             collision of its particles (srd_rule_collide), their energy change, virial and
 *             Lees-Edwards work per cell into exact accumulators; with the global thermostat the
 *             cells' thermal energies are added exactly and all-reduced first;
 *   collide:  (the global thermostat) the rules and collisions with the reduced factor; at a sort
 *             step the particles are reordered by cell (key order) and get new keys (global cell
 *             << 32 | rank in the cell);
 *   finish:   the step's ledger accumulators are queued; every 64 steps (and at the end) the
 *             queued records are all-reduced at once and each step's exact sums rounded once and
 *             added to the ledger doubles in step order.
 * Every particle's key orders it as the single-process array does, so a cell adds the same
 * numbers in the same order on any split, and the exact sums do not depend on the order at all:
 * results are bit for bit independent of the split. The single-process engine in this mode
 * (gran_srd_advance with creation = GRAN_SRD_CREATE_CELLS) is this code with one brick. */
#include "srd/bricks.h"
#include "srd/create.h"
#include "srd/srd_impl.h"
#include "srd/rules.h"
#include "core/exactsum.h"
#include "../cuda/srd_cuda.h" /* srd_rule_const_of */

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numeric>
#include <type_traits>
#include <utility>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace {

/* ---- the all-reduce record: exact accumulators, integer counts, a minimum ---- */
enum { RQ_DE, RQ_VIR, RQ_LEW, RQ_FLUX, RQ_EXT, RQ_IMP, RQ_TH, RQ_N };
struct Red {
  gran_exactsum a[RQ_N];
  int64_t clamped, dof;
  double dt_max;
  void clear() {
    for (auto &q : a) gran_exactsum_init_(&q);
    clamped = dof = 0;
    dt_max = INFINITY;
  }
  void merge(const Red &o) {
    for (int q = 0; q < RQ_N; ++q) gran_exactsum_merge_(&a[q], &o.a[q]);
    clamped += o.clamped;
    dof += o.dof;
    dt_max = std::min(dt_max, o.dt_max);
  }
};

/* ---- the transport between bricks ----
 * Messages are arrays of 8-byte words. A round: every brick posts one message to every other
 * brick (empty ones too), then takes the one from every other brick; an all-reduce: every brick
 * posts its records, then takes their merge of all of them (exact: the same for any merge order).
 * The in-process transport moves buffers between the bricks of this process; CommTransport (one
 * brick per process) hands a round and an all-reduce to a srd_bricks_comm (bricks.h; over MPI in
 * src/cli/mpi.cpp). */
class Transport {
 public:
  virtual ~Transport() = default;
  virtual int size() const = 0;
  /* buf is consumed (its contents may be swapped out) */
  virtual int send(int from, int to, std::vector<double> &buf) = 0;
  virtual int recv(int to, int from, std::vector<double> &buf) = 0;
  /* an all-reduce of n records at once (element by element) */
  virtual int reduce_post(int rank, const Red *r, size_t n) = 0;
  virtual int reduce_take(int rank, Red *r, size_t n) = 0;
  int reduce_post(int rank, const Red &r) { return reduce_post(rank, &r, 1); }
  int reduce_take(int rank, Red &r) { return reduce_take(rank, &r, 1); }
};

class LocalTransport final : public Transport {
 public:
  explicit LocalTransport(int p) : P(p), box((size_t)p * p), full((size_t)p * p, 0), red((size_t)p), rposted((size_t)p, 0) {}
  int size() const override { return P; }
  int send(int from, int to, std::vector<double> &buf) override {
    const size_t k = (size_t)from * P + to;
    GRAN_CHECK(!full[k], GRAN_ERR_INTERNAL, "brick transport: a second message from brick %d to %d in one round", from, to);
    bytes += (int64_t)(buf.size() * sizeof(double));
    box[k].swap(buf);
    buf.clear();
    full[k] = 1;
    return GRAN_SUCCESS;
  }
  int recv(int to, int from, std::vector<double> &buf) override {
    const size_t k = (size_t)from * P + to;
    GRAN_CHECK(full[k], GRAN_ERR_INTERNAL, "brick transport: no message from brick %d to %d", from, to);
    buf.swap(box[k]);
    box[k].clear();
    full[k] = 0;
    return GRAN_SUCCESS;
  }
  using Transport::reduce_post;
  using Transport::reduce_take;
  int reduce_post(int rank, const Red *r, size_t n) override {
    GRAN_CHECK(!rposted[(size_t)rank], GRAN_ERR_INTERNAL, "brick transport: brick %d posted twice to one all-reduce", rank);
    red[(size_t)rank].assign(r, r + n);
    rposted[(size_t)rank] = 1;
    ++posted;
    return GRAN_SUCCESS;
  }
  int reduce_take(int rank, Red *r, size_t n) override {
    GRAN_CHECK(posted == P, GRAN_ERR_INTERNAL, "brick transport: brick %d takes an all-reduce that %d of %d bricks posted",
               rank, posted, P);
    if (taken == 0) {
      sum.assign(n, Red());
      for (Red &q : sum) q.clear();
      for (int b = 0; b < P; ++b) {
        GRAN_CHECK(red[(size_t)b].size() == n, GRAN_ERR_INTERNAL, "brick transport: brick %d posted %zu records, not %zu",
                   b, red[(size_t)b].size(), n);
        for (size_t i = 0; i < n; ++i) sum[i].merge(red[(size_t)b][i]);
      }
    }
    std::copy(sum.begin(), sum.end(), r);
    if (++taken == P) {
      posted = taken = 0;
      std::fill(rposted.begin(), rposted.end(), 0);
    }
    return GRAN_SUCCESS;
  }
  int64_t bytes = 0;

 private:
  int P;
  std::vector<std::vector<double>> box;
  std::vector<char> full;
  std::vector<std::vector<Red>> red;
  std::vector<char> rposted;
  int posted = 0, taken = 0;
  std::vector<Red> sum;
};

static_assert(std::is_trivially_copyable<Red>::value, "the all-reduce record is sent as bytes");

/* merge for srd_bricks_comm::allreduce of a T with a merge(const T &) (MPI's buffers need not be
 * aligned for T: copied) */
template <class T>
void merge_bytes(void *inout, const void *in) {
  T a, b;
  std::memcpy((void *)&a, inout, sizeof a);
  std::memcpy((void *)&b, in, sizeof b);
  a.merge(b);
  std::memcpy(inout, (const void *)&a, sizeof a);
}

/* One brick per process over a srd_bricks_comm: the sends of a round are collected, the first
 * receive runs the round; the all-reduce is the comm's, with Red's exact merge. */
class CommTransport final : public Transport {
 public:
  CommTransport(const srd_bricks_comm &c, const std::vector<int> &peers)
      : c_(c), out_((size_t)c.size), in_((size_t)c.size), sent_((size_t)c.size, 0), peer_((size_t)c.size, 0) {
    for (int p : peers) peer_[(size_t)p] = 1;
  }
  int size() const override { return c_.size; }
  int send(int from, int to, std::vector<double> &buf) override {
    GRAN_CHECK(from == c_.rank && to >= 0 && to < c_.size && to != from && !sent_[(size_t)to], GRAN_ERR_INTERNAL,
               "brick transport: process %d cannot send from brick %d to %d in this round", c_.rank, from, to);
    bytes += (int64_t)(buf.size() * sizeof(double));
    if (!buf.empty() && !peer_[(size_t)to]) ++far;
    out_[(size_t)to].swap(buf);
    buf.clear();
    sent_[(size_t)to] = 1;
    return GRAN_SUCCESS;
  }
  int recv(int to, int from, std::vector<double> &buf) override {
    GRAN_CHECK(to == c_.rank && from >= 0 && from < c_.size && from != to, GRAN_ERR_INTERNAL,
               "brick transport: process %d cannot receive for brick %d from %d", c_.rank, to, from);
    if (!done_) {
      for (int p = 0; p < c_.size; ++p)
        GRAN_CHECK(p == c_.rank || sent_[(size_t)p], GRAN_ERR_INTERNAL,
                   "brick transport: process %d receives before it sent to %d", c_.rank, p);
      GRAN_CHECK(c_.round(c_.ctx, out_, in_) == 0, GRAN_ERR_IO,
                 "decomposed GSRD run: the particle exchange of process %d failed (a process of the run stopped or "
                 "the transport broke)",
                 c_.rank);
      for (auto &m : out_) m.clear();
      std::fill(sent_.begin(), sent_.end(), 0);
      done_ = true;
    }
    buf.swap(in_[(size_t)from]);
    in_[(size_t)from].clear();
    if (++taken_ == c_.size - 1) {
      done_ = false;
      taken_ = 0;
    }
    return GRAN_SUCCESS;
  }
  using Transport::reduce_post;
  using Transport::reduce_take;
  int reduce_post(int rank, const Red *r, size_t n) override {
    GRAN_CHECK(rank == c_.rank && !posted_, GRAN_ERR_INTERNAL, "brick transport: process %d posted brick %d's record",
               c_.rank, rank);
    red_.assign(r, r + n);
    posted_ = true;
    return GRAN_SUCCESS;
  }
  int reduce_take(int rank, Red *r, size_t n) override {
    GRAN_CHECK(rank == c_.rank && posted_ && red_.size() == n, GRAN_ERR_INTERNAL,
               "brick transport: process %d takes records it did not post", c_.rank);
    GRAN_CHECK(c_.allreduce(c_.ctx, red_.data(), sizeof(Red), n, &merge_bytes<Red>) == 0, GRAN_ERR_IO,
               "decomposed GSRD run: the all-reduce of process %d failed (a process of the run stopped or the "
               "transport broke)",
               c_.rank);
    std::copy(red_.begin(), red_.end(), r);
    posted_ = false;
    return GRAN_SUCCESS;
  }
  int64_t bytes = 0;
  int64_t far = 0; /* messages sent beyond the bricks around this one */

 private:
  srd_bricks_comm c_;
  std::vector<std::vector<double>> out_, in_;
  std::vector<char> sent_;
  std::vector<char> peer_;
  bool done_ = false, posted_ = false;
  int taken_ = 0;
  std::vector<Red> red_;
};

/* ---- the split of the binning grid ---- */
struct Split {
  int P[3] = {1, 1, 1};
  std::vector<int64_t> cut[3];  /* brick b along axis a holds grid indices [cut[a][b], cut[a][b + 1]) */
  std::vector<int32_t> own[3];  /* grid index along a -> brick coordinate */
  int nbricks() const { return P[0] * P[1] * P[2]; }
  int rank(const int b[3]) const { return b[0] + P[0] * (b[1] + P[1] * b[2]); }
};

using CellVec = std::vector<srd_cpu_cell, srd_uninit_alloc<srd_cpu_cell>>;
using RngVec = std::vector<gran_rng, srd_uninit_alloc<gran_rng>>;

struct Brick {
  int rank = 0;
  int64_t lo[3] = {0, 0, 0}, w[3] = {1, 1, 1}, ncl = 1;
  /* particles, in key order */
  std::vector<double> x, y, z, vx, vy, vz;
  std::vector<uint64_t> key;
  std::vector<double> cf, ce, ci; /* this step's streaming terms: kinetic flux, external work, wall impulse */
  std::vector<uint32_t> lc;       /* this step's local cell (top bit: seen across the Lees-Edwards boundary) */
  /* cells of the window */
  CellVec cell;
  RngVec rng;
  /* the run's scalar state (the same on every brick) */
  gran_rng shift_rng;
  double shift[3] = {0, 0, 0};
  int64_t step = 0;
  double time = 0, e_coll = 0, e_ext = 0, flux_kin = 0, flux_coll = 0, wall_impulse[3] = {0, 0, 0}, dt_max = INFINITY;
  int64_t clamped = 0;
  int64_t clamped_obs = 0;        /* the clamps, and their smallest dt_max, since the last observation */
  double dt_max_obs = INFINITY;
  /* step work */
  srd_geom g;
  double sh[3] = {0, 0, 0};
  /* dest[i]: -1 a particle of this brick, -2 one that arrived since the last sort (its slot is
   * out of key order); >= 0 a hole: the slot of a particle that left (its destination until it is
   * packed, then kHole), refilled by arrivals or dropped at the next sort */
  std::vector<int32_t> dest;
  std::vector<uint32_t> start, order;
  std::vector<srd_cell_sum> W;
  std::vector<std::vector<double>> out;
  std::vector<double> in, arr;
  std::vector<int64_t> ord;                 /* the arrivals' slots (receive) */
  std::vector<int64_t> holes;               /* the holes' slots */
  std::vector<std::vector<int64_t>> leave;  /* per thread: the slots that left this step */
  int64_t late = 0;                         /* particles arrived since the last sort */
  std::vector<Red> ledger_q;                /* the ledger records of the steps not yet all-reduced */
  std::vector<uint8_t> dirty;               /* per local cell: holds such a particle */
  Red red, red_th;
  double gscale = 1.0; /* the global thermostat's factor of the step */
  int64_t moved = 0; /* particles sent */
  int64_t psteps = 0; /* particle-steps of this brick (its particles summed over the steps) */
};

struct Ctx {
  const gran_srd_options *o;
  srd_geom gm;
  srd_rule_const K;
  Split sp;
  int nth = 1; /* threads of a brick's loops (the results do not depend on them) */
};

constexpr uint32_t kLeBit = 0x80000000u;
constexpr int32_t kHole = INT32_MAX; /* dest of a hole whose particle has been sent */
constexpr int32_t kLate = -2;        /* dest of a particle that arrived since the last sort */

inline int owner_of(const Split &sp, const int64_t c[3]) {
  const int b[3] = {sp.own[0][(size_t)c[0]], sp.own[1][(size_t)c[1]], sp.own[2][(size_t)c[2]]};
  return sp.rank(b);
}
inline uint32_t local_of(const Brick &B, const int64_t c[3]) {
  return (uint32_t)((c[0] - B.lo[0]) + B.w[0] * ((c[1] - B.lo[1]) + B.w[1] * (c[2] - B.lo[2])));
}
inline int64_t global_of(const Ctx &C, const Brick &B, int64_t l) {
  const int64_t i0 = l % B.w[0], r = l / B.w[0], i1 = r % B.w[1], i2 = r / B.w[1];
  return (B.lo[0] + i0) + C.gm.nc[0] * ((B.lo[1] + i1) + C.gm.nc[1] * (B.lo[2] + i2));
}
inline uint64_t key_of(double w) {
  uint64_t k;
  std::memcpy(&k, &w, sizeof k);
  return k;
}
inline double word_of(uint64_t k) {
  double w;
  std::memcpy(&w, &k, sizeof w);
  return w;
}

/* flush-to-zero and denormals-are-zero inside the step's loops, as the serial engine (engine.cpp,
 * FtzScope): per thread, restored when its share ends */
struct Ftz {
#if defined(__SSE__) || defined(__x86_64__)
  unsigned old;
  Ftz() : old(_mm_getcsr()) { _mm_setcsr(old | 0x8040u); }
  ~Ftz() { _mm_setcsr(old); }
#endif
};

enum { BP_STREAM, BP_RECV, BP_SUMS, BP_COLL, BP_SORT, BP_RED, BP_N };

template <int FXF>
struct Fx {
  static constexpr bool LE = FXF & SRD_FX_LE, WALL = FXF & SRD_FX_WALL, ACCEL = FXF & SRD_FX_ACCEL,
                        DISSIP = FXF & SRD_FX_DISSIP, STR = LE || WALL || ACCEL;
};
template <int DIM, int FXF>
constexpr int words_per_particle() {
  return 2 * DIM + 1 + (Fx<FXF>::STR ? 3 : 0);
}

/* stream and bin in place, pack and send the leavers (their slots become holes) */
template <int DIM, int FXF>
int phase_stream(const Ctx &C, Brick &B, Transport &T) {
  using F = Fx<FXF>;
  const gran_srd_options &o = *C.o;
  const double dt = o.dt;
  srd_geom g = C.gm;
  if (F::LE) { /* offset at the end of the step */
    double dx = std::fmod(o.shear_rate * g.box[1] * (B.time + dt), g.box[0]);
    if (dx < 0) dx += g.box[0];
    g.le_dx = dx;
  }
  if (F::WALL) g.wall_u_lo = o.vib_amp * o.vib_omega * std::cos(o.vib_omega * (B.time + dt));
  for (int k = 0; k < 3; ++k) B.shift[k] = k < DIM ? srd_rng_uniform(&B.shift_rng) * o.a : 0.0;
  const double sh[3] = {B.shift[0], B.shift[1], B.shift[2]};
  B.g = g;
  for (int k = 0; k < 3; ++k) B.sh[k] = sh[k];
  const int64_t n = (int64_t)B.x.size();
  if (F::STR)
    for (std::vector<double> *v : {&B.cf, &B.ce, &B.ci}) v->resize((size_t)n);
  B.lc.resize((size_t)n);
  B.dest.resize((size_t)n, -1);
  double *px = B.x.data(), *py = B.y.data(), *pz = DIM == 3 ? B.z.data() : nullptr;
  double *vx = B.vx.data(), *vy = B.vy.data(), *vz = DIM == 3 ? B.vz.data() : nullptr;
  double *cf = F::STR ? B.cf.data() : nullptr, *ce = F::STR ? B.ce.data() : nullptr, *ci = F::STR ? B.ci.data() : nullptr;
  uint32_t *lcp = B.lc.data();
  int32_t *dest = B.dest.data();
  const Split &sp = C.sp;
  const bool single = sp.nbricks() == 1, holes = !B.holes.empty();
  const int64_t lo0 = B.lo[0], lo1 = B.lo[1], lo2 = B.lo[2];
  const uint64_t w0 = (uint64_t)B.w[0], w1 = (uint64_t)B.w[1], w2 = (uint64_t)B.w[2];
  double chk = 0.0;
  const srd_rule_const K = C.K;
  B.leave.resize((size_t)C.nth);
  for (auto &l : B.leave) l.clear();
#pragma omp parallel num_threads(C.nth) reduction(+ : chk)
  {
    Ftz ftz;
    const srd_geom gl = g;
    int tid = 0, nt = 1;
#ifdef _OPENMP
    tid = omp_get_thread_num();
    nt = omp_get_num_threads();
#endif
    std::vector<int64_t> &lv = B.leave[(size_t)tid];
    const int64_t lo = n * tid / nt, hi = n * (tid + 1) / nt;
    for (int64_t i = lo; i < hi; ++i) {
      if (holes && dest[i] >= 0) continue;
      const int32_t fx = srd_rule_fx_fold(FXF, K.fx);
      double p[3] = {px[i], py[i], DIM == 3 ? pz[i] : 0.0};
      double v[3] = {vx[i], vy[i], DIM == 3 ? vz[i] : 0.0};
      double acc[SRD_ACC_N] = {0, 0, 0, 0, 0, 0, 0};
      srd_rule_move(fx, DIM, &K, &gl, p, v, acc);
      chk += p[0] + p[1] + p[2];
      px[i] = p[0];
      py[i] = p[1];
      vx[i] = v[0];
      vy[i] = v[1];
      if (DIM == 3) {
        pz[i] = p[2];
        vz[i] = v[2];
      }
      if (F::STR) {
        cf[i] = acc[SRD_ACC_FLUX];
        ce[i] = acc[SRD_ACC_EXT];
        ci[i] = acc[SRD_ACC_IMP];
      }
      int64_t c[3];
      double dvx;
      srd_bin3(&gl, sh, p, c, &dvx);
      const bool mine = single || ((uint64_t)(c[0] - lo0) < w0 && (uint64_t)(c[1] - lo1) < w1 &&
                                   (uint64_t)(c[2] - lo2) < w2);
      if (mine) {
        lcp[i] = local_of(B, c) | (F::LE && dvx != 0.0 ? kLeBit : 0u);
      } else {
        dest[i] = owner_of(sp, c);
        lv.push_back(i);
      }
    }
  }
  if (chk - chk != 0.0) {
    static const char *const names[6] = {"x", "y", "z", "vx", "vy", "vz"};
    const double *a[6] = {px, py, pz, vx, vy, vz};
    for (int64_t i = 0; i < n; ++i)
      for (int q : {3, 4, 5, 0, 1, 2})
        if (a[q] && dest[i] < 0 && !std::isfinite(a[q][i]))
          return GRAN_ERROR(GRAN_ERR_NUMERIC,
                            "GSRD step %lld: particle %lld of brick %d has a non-finite %s (%g) after its move; the run "
                            "cannot continue",
                            (long long)B.step + 1, (long long)i, B.rank, names[q], a[q][i]);
  }
  const int P = T.size();
  if (P == 1) return GRAN_SUCCESS;
  constexpr int WPP = words_per_particle<DIM, FXF>();
  B.out.resize((size_t)P);
  for (auto &m : B.out) m.clear();
  int64_t nleave = 0;
  for (const auto &lv : B.leave) /* the leavers in slot order, per destination */
    for (const int64_t i : lv) {
      std::vector<double> &m = B.out[(size_t)dest[i]];
      double rec[WPP];
      int q = 0;
      rec[q++] = px[i];
      rec[q++] = py[i];
      if (DIM == 3) rec[q++] = pz[i];
      rec[q++] = vx[i];
      rec[q++] = vy[i];
      if (DIM == 3) rec[q++] = vz[i];
      rec[q++] = word_of(B.key[(size_t)i]);
      if (F::STR) {
        rec[q++] = cf[i];
        rec[q++] = ce[i];
        rec[q++] = ci[i];
      }
      m.insert(m.end(), rec, rec + WPP);
      dest[i] = kHole;
      B.holes.push_back(i);
      ++nleave;
    }
  B.moved += nleave;
  for (int r = 0; r < P; ++r)
    if (r != B.rank) GRAN_CALL(T.send(B.rank, r, B.out[(size_t)r]));
  return GRAN_SUCCESS;
}

/* greedy matching of two lists sorted by cell: for each entry of the shorter list (in order) the
 * nearest unused entry of the longer one that still leaves enough for the rest; pick[k] = the
 * index into `longer` of short entry k */
void match_by_cell(const std::vector<std::pair<uint32_t, int64_t>> &shorter,
                   const std::vector<std::pair<uint32_t, int64_t>> &longer, std::vector<int64_t> &pick) {
  const int64_t ns = (int64_t)shorter.size(), nl = (int64_t)longer.size();
  pick.resize((size_t)ns);
  int64_t i = 0;
  for (int64_t k = 0; k < ns; ++k) {
    const int64_t c = shorter[(size_t)k].first;
    while (nl - (i + 1) >= ns - k && std::llabs((int64_t)longer[(size_t)i + 1].first - c) <=
                                           std::llabs((int64_t)longer[(size_t)i].first - c))
      ++i;
    pick[(size_t)k] = i++;
  }
}

/* receive the arrivals and put them into the holes nearest their cells (the rest appended); the
 * cell pass puts each cell's particles in key order */
template <int DIM, int FXF>
int phase_recv(const Ctx &C, Brick &B, Transport &T) {
  using F = Fx<FXF>;
  const int P = T.size();
  if (P == 1) return GRAN_SUCCESS;
  constexpr int WPP = words_per_particle<DIM, FXF>();
  B.arr.clear();
  for (int r = 0; r < P; ++r) {
    if (r == B.rank) continue;
    GRAN_CALL(T.recv(B.rank, r, B.in));
    B.arr.insert(B.arr.end(), B.in.begin(), B.in.end());
  }
  const int64_t m = (int64_t)(B.arr.size() / WPP);
  if (m == 0) return GRAN_SUCCESS;
  const double *A = B.arr.data();
  /* the arrivals' local cells (the top bit: seen across the Lees-Edwards boundary) */
  std::vector<uint32_t> alc((size_t)m);
  std::vector<std::pair<uint32_t, int64_t>> ac((size_t)m), hc(B.holes.size());
  for (int64_t j = 0; j < m; ++j) {
    const double *rec = A + j * WPP;
    const double p[3] = {rec[0], rec[1], DIM == 3 ? rec[2] : 0.0};
    int64_t c[3];
    double dvx;
    srd_bin3(&B.g, B.sh, p, c, &dvx);
    GRAN_CHECK(owner_of(C.sp, c) == B.rank, GRAN_ERR_INTERNAL, "brick %d received a particle of brick %d", B.rank,
               owner_of(C.sp, c));
    alc[(size_t)j] = local_of(B, c) | (F::LE && dvx != 0.0 ? kLeBit : 0u);
    ac[(size_t)j] = {alc[(size_t)j] & ~kLeBit, j};
  }
  for (size_t h = 0; h < B.holes.size(); ++h) hc[h] = {B.lc[(size_t)B.holes[h]] & ~kLeBit, B.holes[h]};
  std::sort(ac.begin(), ac.end());
  std::sort(hc.begin(), hc.end());
  /* slot of each arrival (in ac order): the matched holes, then appended slots */
  const int64_t H = (int64_t)hc.size(), n0 = (int64_t)B.x.size();
  std::vector<int64_t> &slot = B.ord, pick;
  slot.assign((size_t)m, -1);
  std::vector<char> used((size_t)H, 0);
  if (m <= H) {
    match_by_cell(ac, hc, pick);
    for (int64_t k = 0; k < m; ++k) {
      slot[(size_t)k] = hc[(size_t)pick[(size_t)k]].second;
      used[(size_t)pick[(size_t)k]] = 1;
    }
  } else {
    match_by_cell(hc, ac, pick);
    for (int64_t h = 0; h < H; ++h) slot[(size_t)pick[(size_t)h]] = hc[(size_t)h].second;
    std::fill(used.begin(), used.end(), 1);
  }
  int64_t n = n0;
  for (int64_t k = 0; k < m; ++k)
    if (slot[(size_t)k] < 0) slot[(size_t)k] = n++;
  B.holes.clear();
  for (int64_t h = 0; h < H; ++h)
    if (!used[(size_t)h]) B.holes.push_back(hc[(size_t)h].second);
  B.late += m;
  for (std::vector<double> *v : {&B.x, &B.y, &B.vx, &B.vy}) v->resize((size_t)n);
  if (DIM == 3) {
    B.z.resize((size_t)n);
    B.vz.resize((size_t)n);
  }
  if (F::STR)
    for (std::vector<double> *v : {&B.cf, &B.ce, &B.ci}) v->resize((size_t)n);
  B.key.resize((size_t)n);
  B.lc.resize((size_t)n);
  B.dest.resize((size_t)n, -1);
  for (int64_t k = 0; k < m; ++k) {
    const int64_t j = ac[(size_t)k].second, t = slot[(size_t)k];
    const double *rec = A + j * WPP;
    int q = 0;
    B.x[(size_t)t] = rec[q++];
    B.y[(size_t)t] = rec[q++];
    if (DIM == 3) B.z[(size_t)t] = rec[q++];
    B.vx[(size_t)t] = rec[q++];
    B.vy[(size_t)t] = rec[q++];
    if (DIM == 3) B.vz[(size_t)t] = rec[q++];
    B.key[(size_t)t] = key_of(rec[q++]);
    if (F::STR) {
      B.cf[(size_t)t] = rec[q++];
      B.ce[(size_t)t] = rec[q++];
      B.ci[(size_t)t] = rec[q++];
    }
    B.lc[(size_t)t] = alc[(size_t)j];
    B.dest[(size_t)t] = kLate;
  }
  return GRAN_SUCCESS;
}

/* the rule of local cell c (sums cs) and the collision of its particles; the clamps, the energy
 * change, the virial and the Lees-Edwards work into R */
template <int DIM, int FXF>
inline void collide_cell(const Ctx &C, Brick &B, int64_t c, const srd_cell_sum &cs, double gscale, Red &R,
                         const srd_geom &g, const double sh[3], const srd_rule_const &K) {
  using F = Fx<FXF>;
  const int32_t fx = srd_rule_fx_fold(FXF, K.fx);
  const uint32_t *start = B.start.data(), *order = B.order.data(), *lc = B.lc.data();
  double *vx = B.vx.data(), *vy = B.vy.data(), *vz = DIM == 3 ? B.vz.data() : nullptr;
  const double *py = B.y.data();
  srd_cell_rot cr;
  int cl;
  double dtm;
  srd_rule_cell(fx, DIM, &K, &g, sh, global_of(C, B, c), &cs, gscale, B.cell[(size_t)c].V, &B.rng[(size_t)c], &cr, &cl,
                &dtm);
  if (cl) {
    ++R.clamped;
    R.dt_max = std::min(R.dt_max, dtm);
  }
  const uint32_t j0 = start[c], j1 = start[c + 1];
  if (j0 == j1) return;
  double acc[SRD_ACC_N] = {0, 0, 0, 0, 0, 0, 0};
  for (uint32_t j = j0; j < j1; ++j) {
    const uint32_t i = order[j];
    double v[3] = {vx[i], vy[i], DIM == 3 ? vz[i] : 0.0};
    const double dvx = F::LE && (lc[i] & kLeBit) ? -g.le_dv : 0.0;
    srd_rule_collide(fx, DIM, &K, &g, &cr, dvx, py[i], v, acc);
    vx[i] = v[0];
    vy[i] = v[1];
    if (DIM == 3) vz[i] = v[2];
  }
  if (F::DISSIP || F::WALL) gran_exactsum_add_(&R.a[RQ_DE], acc[SRD_ACC_DE]);
  if (F::LE) {
    gran_exactsum_add_(&R.a[RQ_VIR], acc[SRD_ACC_VIR]);
    gran_exactsum_add_(&R.a[RQ_LEW], acc[SRD_ACC_LEW]);
  }
}

/* the particles by local cell (stable counting sort), the cell sums, the streaming terms per cell,
 * the thermostat's sums (posted) */
template <int DIM, int FXF>
int phase_sums(const Ctx &C, Brick &B, Transport &T) {
  using F = Fx<FXF>;
  const int32_t fx = srd_rule_fx_fold(FXF, C.K.fx);
  const int64_t n = (int64_t)B.x.size(), ncl = B.ncl;
  const int64_t nhole = (int64_t)B.holes.size();
  B.psteps += n - nhole;
  B.start.assign((size_t)ncl + 1, 0);
  B.order.resize((size_t)(n - nhole));
  uint32_t *start = B.start.data(), *order = B.order.data();
  const uint32_t *lc = B.lc.data();
  const int32_t *dest = B.dest.data();
  const bool dead = nhole > 0; /* the holes (dest >= 0) are not counted */
  const bool late = B.late > 0; /* some slots are out of key order: their cells are marked */
  B.dirty.assign(late ? (size_t)ncl : 0, 0);
  uint8_t *dirty = B.dirty.data();
  for (int64_t i = 0; i < n; ++i)
    if (!dead || dest[i] < 0) start[(lc[i] & ~kLeBit) + 1]++;
  for (int64_t c = 0; c < ncl; ++c) start[c + 1] += start[c];
  {
    std::vector<uint32_t> cur(B.start.begin(), B.start.end() - 1);
    for (int64_t i = 0; i < n; ++i)
      if (!dead || dest[i] < 0) {
        const uint32_t c = lc[i] & ~kLeBit;
        order[cur[c]++] = (uint32_t)i;
        if (late && dest[i] == kLate) dirty[c] = 1;
      }
  }
  const uint64_t *key = B.key.data();
  B.W.resize((size_t)ncl);
  B.red.clear();
  B.red_th.clear();
  const double *vx = B.vx.data(), *vy = B.vy.data(), *vz = DIM == 3 ? B.vz.data() : nullptr;
  const double ledv = B.g.le_dv;
  const bool gth = fx & SRD_FX_GTHERMO;
  const srd_geom g = B.g;
  const double sh[3] = {B.sh[0], B.sh[1], B.sh[2]};
  const srd_rule_const K = C.K;
  std::vector<Red> tred((size_t)C.nth);
#pragma omp parallel num_threads(C.nth)
  {
    Ftz ftz;
#ifdef _OPENMP
    Red &R = tred[(size_t)omp_get_thread_num()];
#else
    Red &R = tred[0];
#endif
    R.clear();
#pragma omp for schedule(dynamic, 256)
    for (int64_t c = 0; c < ncl; ++c) {
      srd_cell_sum &cs = B.W[(size_t)c];
      srd_sum_clear(&cs);
      const uint32_t j0 = start[c], j1 = start[c + 1];
      if (j0 == j1) {
        if (!gth) collide_cell<DIM, FXF>(C, B, c, cs, 1.0, R, g, sh, K);
        continue;
      }
      /* a cell holding particles that arrived since the last sort (in holes and at the end): its
       * list (in slot order: the residents in key order, arrivals among them) into key order */
      if (late && dirty[c] && j1 - j0 > 1)
        for (uint32_t a = j0 + 1; a < j1; ++a) {
          const uint32_t v = order[a];
          const uint64_t kv = key[v];
          uint32_t b = a;
          for (; b > j0 && key[order[b - 1]] > kv; --b) order[b] = order[b - 1];
          order[b] = v;
        }
      const double *ref = B.cell[(size_t)c].V;
      double pf = 0.0, pe = 0.0, pi = 0.0;
      for (uint32_t j = j0; j < j1; ++j) {
        const uint32_t i = order[j];
        double v[3] = {vx[i], vy[i], DIM == 3 ? vz[i] : 0.0};
        if (F::LE && (lc[i] & kLeBit)) v[0] += -ledv;
        srd_sum_add(&cs, v, ref, DIM);
        if (F::STR) {
          pf += B.cf[i];
          pe += B.ce[i];
          pi += B.ci[i];
        }
      }
      if (F::STR) {
        if (F::LE) gran_exactsum_add_(&R.a[RQ_FLUX], pf);
        gran_exactsum_add_(&R.a[RQ_EXT], pe);
        if (F::WALL) gran_exactsum_add_(&R.a[RQ_IMP], pi);
      }
      if (gth) {
        double e, d;
        if (srd_rule_thermal(DIM, &cs, ref, &e, &d)) {
          gran_exactsum_add_(&R.a[RQ_TH], e);
          R.dof += (int64_t)d;
        }
      } else { /* the cell's particles are in cache: collide them now */
        collide_cell<DIM, FXF>(C, B, c, cs, 1.0, R, g, sh, K);
      }
    }
  }
  /* the threads' exact partials (any merge order gives the same state) */
  for (const Red &R : tred) {
    for (int q : {RQ_FLUX, RQ_EXT, RQ_IMP, RQ_DE, RQ_VIR, RQ_LEW}) gran_exactsum_merge_(&B.red.a[q], &R.a[q]);
    gran_exactsum_merge_(&B.red_th.a[RQ_TH], &R.a[RQ_TH]);
    B.red_th.dof += R.dof;
    B.red.clamped += R.clamped;
    B.red.dt_max = std::min(B.red.dt_max, R.dt_max);
  }
  if (fx & SRD_FX_GTHERMO) GRAN_CALL(T.reduce_post(B.rank, B.red_th));
  return GRAN_SUCCESS;
}

/* the global thermostat's factor from the all-reduced thermal energy and degrees of freedom */
template <int DIM, int FXF>
int phase_thermo(const Ctx &C, Brick &B, Transport &T) {
  if (!(srd_rule_fx_fold(FXF, C.K.fx) & SRD_FX_GTHERMO)) return GRAN_SUCCESS;
  Red th;
  th.clear();
  GRAN_CALL(T.reduce_take(B.rank, th));
  B.gscale = srd_rule_gscale(gran_exactsum_value_(&th.a[RQ_TH]), (double)th.dof, C.K.T0);
  return GRAN_SUCCESS;
}

/* with the global thermostat the cells' rules and the rotation (else done in the sums pass); the sort;
 * the step's ledger record queued */
template <int DIM, int FXF>
int phase_collide(const Ctx &C, Brick &B, double *t_sort) {
  const bool gth = srd_rule_fx_fold(FXF, C.K.fx) & SRD_FX_GTHERMO;
  const int64_t ncl = B.ncl;
  const uint32_t *start = B.start.data(), *order = B.order.data();
  const srd_geom g = B.g;
  const double sh[3] = {B.sh[0], B.sh[1], B.sh[2]};
  const srd_rule_const K = C.K;
  /* without the global thermostat the cells collided in the sums pass */
  if (gth) {
    const double gscale = B.gscale;
    std::vector<Red> tred((size_t)C.nth);
#pragma omp parallel num_threads(C.nth)
    {
      Ftz ftz;
#ifdef _OPENMP
      Red &R = tred[(size_t)omp_get_thread_num()];
#else
      Red &R = tred[0];
#endif
      R.clear();
#pragma omp for schedule(dynamic, 256)
      for (int64_t c = 0; c < ncl; ++c) collide_cell<DIM, FXF>(C, B, c, B.W[(size_t)c], gscale, R, g, sh, K);
    }
    for (const Red &R : tred) {
      for (int q : {RQ_DE, RQ_VIR, RQ_LEW}) gran_exactsum_merge_(&B.red.a[q], &R.a[q]);
      B.red.clamped += R.clamped;
      B.red.dt_max = std::min(B.red.dt_max, R.dt_max);
    }
  }
  const gran_srd_options &o = *C.o;
  if (o.sort_every > 0 && (B.step + 1) % o.sort_every == 0) {
    const double t0 = t_sort ? srd_clock_s() : 0.0;
    const int64_t n = (int64_t)start[ncl]; /* the holes are dropped */
    std::vector<double> tmp((size_t)n);
    std::vector<double> *arr[6] = {&B.x, &B.y, &B.z, &B.vx, &B.vy, &B.vz};
    for (int q = 0; q < 6; ++q) {
      if (DIM == 2 && (q == 2 || q == 5)) continue;
      std::vector<double> &A = *arr[q];
      tmp.resize((size_t)n);
#pragma omp parallel for schedule(static) num_threads(C.nth)
      for (int64_t j = 0; j < n; ++j) tmp[(size_t)j] = A[order[j]];
      A.swap(tmp);
    }
    for (int64_t c = 0; c < ncl; ++c) {
      const uint64_t gc = (uint64_t)global_of(C, B, c) << 32;
      for (uint32_t j = start[c]; j < start[c + 1]; ++j) B.key[j] = gc | (uint64_t)(j - start[c]);
    }
    B.key.resize((size_t)n);
    B.dest.assign((size_t)n, -1);
    B.holes.clear();
    B.late = 0;
    if (t_sort) *t_sort += srd_clock_s() - t0;
  }
  B.ledger_q.push_back(B.red); /* all-reduced in batches (flush_ledger) */
  return GRAN_SUCCESS;
}

/* the end of a step: its time */
int phase_finish(const Ctx &C, Brick &B) {
  B.time += C.o->dt;
  B.step += 1;
  return GRAN_SUCCESS;
}

/* the ledger of the steps since the last flush: their records all-reduced at once (one
 * all-reduce per kLedgerBatch steps rather than per step), then each step's exact sums rounded
 * once and added to the ledger doubles in step order: the same doubles as a reduction per step */
constexpr size_t kLedgerBatch = 64;
template <int DIM, int FXF>
void ledger_add(const Ctx &C, Brick &B, Red &r) {
  using F = Fx<FXF>;
  if (F::STR) {
    if (F::LE) B.flux_kin += gran_exactsum_value_(&r.a[RQ_FLUX]);
    B.e_ext += gran_exactsum_value_(&r.a[RQ_EXT]);
    if (F::WALL) B.wall_impulse[C.gm.wall_axis] += gran_exactsum_value_(&r.a[RQ_IMP]);
  }
  if (F::DISSIP || F::WALL) B.e_coll += gran_exactsum_value_(&r.a[RQ_DE]);
  if (F::LE) {
    B.flux_coll += gran_exactsum_value_(&r.a[RQ_VIR]);
    B.e_ext += gran_exactsum_value_(&r.a[RQ_LEW]);
  }
  B.clamped += r.clamped;
  B.dt_max = std::min(B.dt_max, r.dt_max);
  B.clamped_obs += r.clamped;
  B.dt_max_obs = std::min(B.dt_max_obs, r.dt_max);
}
template <int DIM, int FXF>
int flush_ledger(const Ctx &C, std::vector<Brick> &bs, Transport &T) {
  const size_t n = bs[0].ledger_q.size();
  if (n == 0) return GRAN_SUCCESS;
  for (Brick &B : bs) GRAN_CALL(T.reduce_post(B.rank, B.ledger_q.data(), B.ledger_q.size()));
  for (Brick &B : bs) {
    GRAN_CALL(T.reduce_take(B.rank, B.ledger_q.data(), n));
    for (Red &r : B.ledger_q) ledger_add<DIM, FXF>(C, B, r);
    B.ledger_q.clear();
  }
  return GRAN_SUCCESS;
}

/* GRAN_SRD_PHASES=1: the phases' seconds of the steps so far and their particle-steps, printed by
 * phases_print (per gran_srd_advance call; a split gas's, summed over its step calls, at close) */
struct Phases {
  double ph[BP_N] = {0, 0, 0, 0, 0, 0};
  double tsort = 0, psteps = 0;
  int64_t steps = 0, particles = 0;
  int bricks = 0;
};
void phases_print(const Phases &q) {
  if (!(q.psteps > 0)) return;
  const double u = 1e9 / q.psteps;
  std::fprintf(stderr,
               "GSRD bricks phases, ns per particle-step (%lld steps, %lld particles, %d bricks): stream + bin + pack "
               "%.2f, receive + append %.2f, cell order + sums (+ rules + rotation without the global thermostat) %.2f, "
               "rules + rotation after the thermostat's reduction, and the sort %.2f (sort %.2f of it), "
               "ledger (all-reduced every %d steps) %.2f\n",
               (long long)q.steps, (long long)q.particles, q.bricks, q.ph[BP_STREAM] * u, q.ph[BP_RECV] * u,
               q.ph[BP_SUMS] * u, q.ph[BP_COLL] * u, q.tsort * u, (int)kLedgerBatch, q.ph[BP_RED] * u);
}

/* nsteps steps of every brick in bs (an MPI rank: its one brick), each phase on every brick
 * before the next phase; with GRAN_SRD_PHASES=1 the phases' times are added to *acc (NULL: printed
 * at the end of this call) */
template <int DIM, int FXF>
int run_steps(const Ctx &C, std::vector<Brick> &bs, Transport &T, int64_t nsteps, Phases *acc) {
  const bool prof = srd_phase_timing();
  double ph[BP_N] = {0, 0, 0, 0, 0, 0};
  double tq = prof ? srd_clock_s() : 0.0;
  auto lap = [&](int k) {
    if (!prof) return;
    const double t = srd_clock_s();
    ph[k] += t - tq;
    tq = t;
  };
  double tsort = 0.0;
  auto steps = [&]() -> int {
    for (int64_t st = 0; st < nsteps; ++st) {
      for (Brick &B : bs) GRAN_CALL((phase_stream<DIM, FXF>(C, B, T)));
      lap(BP_STREAM);
      for (Brick &B : bs) GRAN_CALL((phase_recv<DIM, FXF>(C, B, T)));
      lap(BP_RECV);
      for (Brick &B : bs) GRAN_CALL((phase_sums<DIM, FXF>(C, B, T)));
      lap(BP_SUMS);
      for (Brick &B : bs) GRAN_CALL((phase_thermo<DIM, FXF>(C, B, T)));
      for (Brick &B : bs) GRAN_CALL((phase_collide<DIM, FXF>(C, B, prof ? &tsort : nullptr)));
      lap(BP_COLL);
      for (Brick &B : bs) GRAN_CALL(phase_finish(C, B));
      if (bs[0].ledger_q.size() >= kLedgerBatch || st + 1 == nsteps) GRAN_CALL((flush_ledger<DIM, FXF>(C, bs, T)));
      lap(BP_RED);
    }
    return GRAN_SUCCESS;
  };
  if (const int e = steps()) { /* the steps done keep their ledger (bricks all in this process: the flush is local) */
    if (bs.size() == (size_t)T.size()) (void)flush_ledger<DIM, FXF>(C, bs, T);
    return e;
  }
  if (prof && nsteps > 0) {
    int64_t n = 0;
    for (const Brick &B : bs) n += (int64_t)(B.x.size() - B.holes.size());
    Phases here, &q = acc ? *acc : here;
    for (int k = 0; k < BP_N; ++k) q.ph[k] += ph[k];
    q.tsort += tsort;
    q.psteps += (double)n * (double)nsteps;
    q.steps += nsteps;
    q.particles = n;
    q.bricks = (int)bs.size();
    if (!acc) phases_print(q);
  }
  return GRAN_SUCCESS;
}

using run_fn = int (*)(const Ctx &, std::vector<Brick> &, Transport &, int64_t, Phases *);
constexpr int fxf_of(int i) {
  return (i & 1 ? SRD_FX_ACCEL : 0) | (i & 2 ? SRD_FX_WALL : 0) | (i & 4 ? SRD_FX_LE : 0) | (i & 8 ? SRD_FX_DISSIP : 0);
}
template <int DIM, int... I>
constexpr std::array<run_fn, 16> table_of(std::integer_sequence<int, I...>) {
  return {{&run_steps<DIM, fxf_of(I)>...}};
}
run_fn pick(int dim, int32_t fx) {
  static constexpr std::array<run_fn, 16> t2 = table_of<2>(std::make_integer_sequence<int, 16>{});
  static constexpr std::array<run_fn, 16> t3 = table_of<3>(std::make_integer_sequence<int, 16>{});
  const int i = (fx & SRD_FX_ACCEL ? 1 : 0) | (fx & SRD_FX_WALL ? 2 : 0) | (fx & SRD_FX_LE ? 4 : 0) |
                (fx & SRD_FX_DISSIP ? 8 : 0);
  return dim == 2 ? t2[(size_t)i] : t3[(size_t)i];
}

int make_ctx(const gran_srd *s, const int pg[3], Ctx &C) {
  C.o = &s->opt;
  C.gm = s->gm;
  const gran_cuda_srd_params prm = srd_params_of(s);
  C.K = srd_rule_const_of(&prm);
  C.nth = srd_threads_used(s->opt.threads);
  for (int a = 0; a < 3; ++a) {
    const int64_t nc = s->gm.nc[a];
    GRAN_CHECK(pg[a] >= 1 && (int64_t)pg[a] <= nc, GRAN_ERR_ARG,
               "argument 'pgrid[%d]' must be in [1, %lld] (the binning grid's cells along axis %d; got %d)", a,
               (long long)nc, a, pg[a]);
    C.sp.P[a] = pg[a];
    C.sp.cut[a].resize((size_t)pg[a] + 1);
    for (int b = 0; b <= pg[a]; ++b) C.sp.cut[a][(size_t)b] = srd_brick_cut(b, nc, pg[a]);
    C.sp.own[a].resize((size_t)nc);
    for (int b = 0; b < pg[a]; ++b)
      for (int64_t i = C.sp.cut[a][(size_t)b]; i < C.sp.cut[a][(size_t)b + 1]; ++i) C.sp.own[a][(size_t)i] = b;
  }
  return GRAN_SUCCESS;
}

void window_of(const Ctx &C, int rank, Brick &B) {
  B.rank = rank;
  int b[3] = {rank % C.sp.P[0], (rank / C.sp.P[0]) % C.sp.P[1], rank / (C.sp.P[0] * C.sp.P[1])};
  B.ncl = 1;
  for (int a = 0; a < 3; ++a) {
    B.lo[a] = C.sp.cut[a][(size_t)b[a]];
    B.w[a] = C.sp.cut[a][(size_t)b[a] + 1] - B.lo[a];
    B.ncl *= B.w[a];
  }
}

/* the bricks around brick `rank` (its 3^d - 1 neighbours on the brick grid, periodic axes
 * wrapped; with Lees-Edwards the bricks across the y boundary are any along x, since the image
 * is displaced by the offset), sorted, without rank itself: where a particle that streams less
 * than a brick's width, under a shift of less than a cell, can go */
std::vector<int> peers_of(const Ctx &C, int rank) {
  const Split &sp = C.sp;
  const int b[3] = {rank % sp.P[0], (rank / sp.P[0]) % sp.P[1], rank / (sp.P[0] * sp.P[1])};
  const bool le = C.o->shear_rate != 0;
  std::vector<int> out;
  for (int d2 = -1; d2 <= 1; ++d2)
    for (int d1 = -1; d1 <= 1; ++d1)
      for (int d0 = -1; d0 <= 1; ++d0) {
        int q[3] = {b[0] + d0, b[1] + d1, b[2] + d2};
        bool ok = true, across_y = false;
        for (int a = 0; a < 3; ++a) {
          if (q[a] >= 0 && q[a] < sp.P[a]) continue;
          if (a == C.o->wall_axis || a >= C.o->dim) {
            ok = false;
            break;
          }
          if (a == 1) across_y = true;
          q[a] = (q[a] + sp.P[a]) % sp.P[a];
        }
        if (!ok) continue;
        if (le && across_y) {
          for (int x = 0; x < sp.P[0]; ++x) {
            const int r[3] = {x, q[1], q[2]};
            out.push_back(sp.rank(r));
          }
        } else {
          out.push_back(sp.rank(q));
        }
      }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  out.erase(std::remove(out.begin(), out.end(), rank), out.end());
  return out;
}

void scalars_from(const gran_srd *s, Brick &B) {
  B.shift_rng = s->shift_rng;
  for (int k = 0; k < 3; ++k) B.shift[k] = s->shift[k];
  B.step = s->step;
  B.time = s->time;
  B.e_coll = s->e_coll;
  B.e_ext = s->e_ext;
  B.flux_kin = s->flux_kin;
  B.flux_coll = s->flux_coll;
  for (int k = 0; k < 3; ++k) B.wall_impulse[k] = s->wall_impulse[k];
  B.clamped = B.clamped_obs = s->clamped; /* the plain engine counts them since its last observation */
  B.dt_max = B.dt_max_obs = s->dt_max;
}
void scalars_to(const Brick &B, gran_srd *s) {
  s->shift_rng = B.shift_rng;
  for (int k = 0; k < 3; ++k) s->shift[k] = B.shift[k];
  s->step = B.step;
  s->time = B.time;
  s->e_coll = B.e_coll;
  s->e_ext = B.e_ext;
  s->flux_kin = B.flux_kin;
  s->flux_coll = B.flux_coll;
  for (int k = 0; k < 3; ++k) s->wall_impulse[k] = B.wall_impulse[k];
  s->clamped = B.clamped;
  s->dt_max = B.dt_max;
}

/* the state's arrays lent to one brick, given back whatever happens */
struct Lend {
  gran_srd *s;
  Brick &B;
  Lend(gran_srd *s_, Brick &B_) : s(s_), B(B_) { swap_all(); }
  ~Lend() { swap_all(); }
  void swap_all() {
    s->x.swap(B.x);
    s->y.swap(B.y);
    s->z.swap(B.z);
    s->vx.swap(B.vx);
    s->vy.swap(B.vy);
    s->vz.swap(B.vz);
    s->cell.swap(B.cell);
    s->rng.swap(B.rng);
  }
};

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

double *dup_of(const std::vector<double> &v) {
  double *p = (double *)std::malloc(std::max<size_t>(1, v.size()) * sizeof(double));
  if (p && !v.empty()) std::memcpy(p, v.data(), v.size() * sizeof(double));
  return p;
}

} // namespace

/* adds 0.5 |v|^2 of particles [0, n) to *acc, exactly (one compiled instance: the creation's energy
 * of the plain engine and of the bricks, the same bits) */
__attribute__((noinline)) void srd_kinetic_exact_(const double *vx, const double *vy, const double *vz, int64_t n,
                                                  gran_exactsum *acc) {
  for (int64_t i = 0; i < n; ++i)
    gran_exactsum_add_(acc, 0.5 * (vx[i] * vx[i] + vy[i] * vy[i] + (vz ? vz[i] * vz[i] : 0.0)));
}

namespace {

/* The creation by cells inside each brick (the box cells of its window, drawn by gran_srd_create_cells_
 * row by row along x), keys (box cell << 32 | rank in the cell: the order of the one-process
 * array), the mean momentum and the initial energy all-reduced exactly, the shear profile; the
 * cells' RNG streams and the shift stream set up by the brick. */
int bricks_create(const Ctx &C, std::vector<Brick> &bs, Transport &T, double *e_initial) {
  const gran_srd_options *o = C.o;
  const int d = o->dim;
  const srd_geom &gm = C.gm;
  int64_t N = 0;
  for (Brick &B : bs) {
    GRAN_CALL(gran_rng_stream(o->seed, 0, &B.shift_rng));
    B.cell.resize((size_t)B.ncl);
    B.rng.resize((size_t)B.ncl);
    for (int64_t l = 0; l < B.ncl; ++l) std::memset((void *)&B.cell[(size_t)l], 0, sizeof(srd_cpu_cell));
    for (int64_t l = 0; l < B.ncl; l += B.w[0]) /* a row of the window: consecutive streams */
      GRAN_CALL(srd_streams_(o->seed, (uint64_t)global_of(C, B, l) + 1, B.w[0], B.rng.data() + l));
    int64_t lo[3], hi[3]; /* the window's box cells (a wall axis has L + 1 layers, the box L) */
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(B.lo[a], gm.L[a]);
      hi[a] = std::min(B.lo[a] + B.w[a], gm.L[a]);
    }
    Red r;
    r.clear();
    std::vector<int64_t> count;
    for (int64_t cz = lo[2]; cz < hi[2]; ++cz)
      for (int64_t cy = lo[1]; cy < hi[1]; ++cy) {
        const int64_t c0 = lo[0] + gm.L[0] * (cy + gm.L[1] * cz), c1 = c0 + (hi[0] - lo[0]);
        if (c1 <= c0) continue;
        count.resize((size_t)(c1 - c0));
        GRAN_CALL(gran_srd_cell_counts_(o, c0, c1, count.data()));
        int64_t m = 0;
        for (int64_t q : count) m += q;
        if (m == 0) continue; /* a row of empty cells: nothing to draw (and no array to draw into yet) */
        const size_t at = B.x.size();
        for (std::vector<double> *v : {&B.x, &B.y, &B.vx, &B.vy}) v->resize(at + (size_t)m);
        if (d == 3) {
          B.z.resize(at + (size_t)m);
          B.vz.resize(at + (size_t)m);
        }
        GRAN_CALL(gran_srd_create_cells_(o, c0, c1, count.data(), B.x.data() + at, B.y.data() + at,
                                         d == 3 ? B.z.data() + at : nullptr, B.vx.data() + at, B.vy.data() + at,
                                         d == 3 ? B.vz.data() + at : nullptr, &r.a[0]));
        for (int64_t c = c0; c < c1; ++c)
          for (int64_t k = 0; k < count[(size_t)(c - c0)]; ++k) B.key.push_back((uint64_t)c << 32 | (uint64_t)k);
      }
    r.dof = (int64_t)B.x.size(); /* the particle count, reduced with the momentum */
    GRAN_CALL(T.reduce_post(B.rank, r));
  }
  std::vector<std::array<double, 3>> mean(bs.size());
  for (size_t b = 0; b < bs.size(); ++b) { /* every brick takes the reduction before any posts the next */
    Red r;
    r.clear();
    GRAN_CALL(T.reduce_take(bs[b].rank, r));
    N = r.dof;
    for (int k = 0; k < 3; ++k) mean[b][(size_t)k] = k < d ? gran_exactsum_value_(&r.a[k]) / (double)N : 0.0;
  }
  for (size_t b = 0; b < bs.size(); ++b) {
    Brick &B = bs[b];
    const double m[3] = {mean[b][0], mean[b][1], mean[b][2]};
    const double box1 = gm.box[1], rate = o->shear_rate;
    for (size_t i = 0; i < B.x.size(); ++i) {
      B.vx[i] -= m[0];
      B.vy[i] -= m[1];
      if (d == 3) B.vz[i] -= m[2];
      if (rate != 0) B.vx[i] = std::fma(rate, B.y[i] - 0.5 * box1, B.vx[i]);
    }
    Red e;
    e.clear();
    srd_kinetic_exact_(B.vx.data(), B.vy.data(), d == 3 ? B.vz.data() : nullptr, (int64_t)B.x.size(), &e.a[0]);
    GRAN_CALL(T.reduce_post(B.rank, e));
  }
  for (Brick &B : bs) {
    Red e;
    e.clear();
    GRAN_CALL(T.reduce_take(B.rank, e));
    *e_initial = gran_exactsum_value_(&e.a[0]);
  }
  (void)N;
  return GRAN_SUCCESS;
}

} // namespace

namespace {
/* The plain engine's state as one brick: its scalars and arrays lent to the brick (key = index: the
 * arrays are in key order, and only keys of one epoch are ever compared), fn(C, bs) called, the
 * arrays given back (whatever fn returns) */
template <class F>
int as_one_brick(gran_srd *s, F fn) {
  const int pg[3] = {1, 1, 1};
  Ctx C;
  GRAN_CALL(make_ctx(s, pg, C));
  std::vector<Brick> bs(1);
  Brick &B = bs[0];
  window_of(C, 0, B);
  scalars_from(s, B);
  Lend lend(s, B);
  B.key.resize(B.x.size());
  std::iota(B.key.begin(), B.key.end(), (uint64_t)0);
  return fn(C, bs);
}
}  // namespace

int srd_bricks_advance_(gran_srd *s, int64_t steps) {
  GRAN_TRY {
    return as_one_brick(s, [&](const Ctx &C, std::vector<Brick> &bs) {
      LocalTransport T(1);
      const int e = pick(s->opt.dim, srd_fx_of(&s->opt))(C, bs, T, steps, nullptr);
      scalars_to(bs[0], s); /* the steps done (on an error: up to the step that failed) */
      return e;
    });
  }
  GRAN_CATCH
}

extern "C" void srd_bricks_out_free_(srd_bricks_out *out) {
  if (!out) return;
  double **a[7] = {&out->x, &out->y, &out->z, &out->vx, &out->vy, &out->vz, &out->V};
  for (double **p : a) {
    std::free(*p);
    *p = nullptr;
  }
  std::free(out->rng);
  out->rng = nullptr;
}

static int gather_scalars(const gran_srd *s, srd_bricks_out *out) {
  out->time = s->time;
  out->e_initial = s->e_initial;
  out->e_coll = s->e_coll;
  out->e_ext = s->e_ext;
  out->flux_kin = s->flux_kin;
  out->flux_coll = s->flux_coll;
  for (int k = 0; k < 3; ++k) out->wall_impulse[k] = s->wall_impulse[k];
  out->dt_max = s->dt_max;
  out->step = s->step;
  out->clamped = s->clamped;
  return GRAN_SUCCESS;
}

extern "C" int srd_bricks_gather_plain_(const gran_srd *s, srd_bricks_out *out) {
  GRAN_TRY {
    GRAN_CHECK_PTR(s);
    GRAN_CHECK_PTR(out);
    std::memset(out, 0, sizeof *out);
    const bool d3 = s->opt.dim == 3;
    out->n = s->n;
    out->x = dup_of(s->x);
    out->y = dup_of(s->y);
    out->vx = dup_of(s->vx);
    out->vy = dup_of(s->vy);
    if (d3) {
      out->z = dup_of(s->z);
      out->vz = dup_of(s->vz);
    }
    out->ncell = s->ncell;
    out->V = (double *)std::malloc((size_t)s->ncell * 3 * sizeof(double));
    out->rng = (uint64_t *)std::malloc((size_t)s->ncell * 4 * sizeof(uint64_t));
    if (!out->x || !out->y || !out->vx || !out->vy || (d3 && (!out->z || !out->vz)) || !out->V || !out->rng) {
      srd_bricks_out_free_(out);
      return GRAN_ERROR(GRAN_ERR_NOMEM, "out of memory");
    }
    for (int64_t c = 0; c < s->ncell; ++c) {
      for (int k = 0; k < 3; ++k) out->V[3 * c + k] = s->cell[(size_t)c].V[k];
      for (int k = 0; k < 4; ++k) out->rng[4 * c + k] = s->rng[(size_t)c].s[k];
    }
    return gather_scalars(s, out);
  }
  GRAN_CATCH
}

extern "C" int srd_bricks_run_(const gran_srd_options *opt, const int pgrid[3], int64_t nsteps, int create_in_bricks,
                               srd_bricks_out *out) {
  GRAN_TRY {
    GRAN_CHECK_PTR(opt);
    GRAN_CHECK_PTR(pgrid);
    GRAN_CHECK_PTR(out);
    std::memset(out, 0, sizeof *out);
    GRAN_CHECK(opt->creation == GRAN_SRD_CREATE_CELLS, GRAN_ERR_ARG,
               "option 'creation' must be GRAN_SRD_CREATE_CELLS (the decomposable engine) for a brick run (got %d)",
               (int)opt->creation);
    GRAN_CHECK(nsteps >= 0, GRAN_ERR_ARG, "argument 'nsteps' must be >= 0 (got %lld)", (long long)nsteps);
    for (int a = opt->dim; a < 3; ++a)
      GRAN_CHECK(pgrid[a] == 1, GRAN_ERR_ARG, "argument 'pgrid[%d]' must be 1 in %d-D (got %d)", a, (int)opt->dim,
                 pgrid[a]);
    gran_srd *s = nullptr;
    GRAN_CALL(gran_srd_create(opt, &s));
    std::unique_ptr<gran_srd, void (*)(gran_srd *)> hold(s, [](gran_srd *p) { gran_srd_destroy(&p); });
    GRAN_CHECK(s->dev.p == nullptr, GRAN_ERR_ARG, "a brick run is a CPU run (option 'device' must select the CPU)");
    Ctx C;
    GRAN_CALL(make_ctx(s, pgrid, C));
    const int P = C.sp.nbricks();
    std::vector<Brick> bs((size_t)P);
    const int d = s->opt.dim;
    LocalTransport T(P);
    for (int r = 0; r < P; ++r) {
      Brick &B = bs[(size_t)r];
      window_of(C, r, B);
      scalars_from(s, B);
    }
    if (create_in_bricks) {
      double e0 = 0;
      GRAN_CALL(bricks_create(C, bs, T, &e0));
      s->e_initial = e0;
    }
    for (int r = 0; r < P && !create_in_bricks; ++r) {
      Brick &B = bs[(size_t)r];
      B.cell.resize((size_t)B.ncl);
      B.rng.resize((size_t)B.ncl);
      for (int64_t l = 0; l < B.ncl; ++l) {
        const int64_t gc = global_of(C, B, l);
        B.cell[(size_t)l] = s->cell[(size_t)gc];
        B.rng[(size_t)l] = s->rng[(size_t)gc];
      }
    }
    /* each particle to the brick of its cell under no shift (the first step bins it again), in
     * index order: key = index */
    const double zero[3] = {0, 0, 0};
    for (int64_t i = 0; i < s->n && !create_in_bricks; ++i) {
      const double p[3] = {s->x[(size_t)i], s->y[(size_t)i], d == 3 ? s->z[(size_t)i] : 0.0};
      int64_t c[3];
      double dvx;
      srd_bin3(&C.gm, zero, p, c, &dvx);
      Brick &B = bs[(size_t)owner_of(C.sp, c)];
      B.x.push_back(p[0]);
      B.y.push_back(p[1]);
      B.vx.push_back(s->vx[(size_t)i]);
      B.vy.push_back(s->vy[(size_t)i]);
      if (d == 3) {
        B.z.push_back(p[2]);
        B.vz.push_back(s->vz[(size_t)i]);
      }
      B.key.push_back((uint64_t)i);
    }
    const double t0 = srd_clock_s();
    GRAN_CALL(pick(d, srd_fx_of(&s->opt))(C, bs, T, nsteps, nullptr));
    const double t_steps = srd_clock_s() - t0;
    /* gather: every brick holds the same scalar state */
    for (int r = 1; r < P; ++r) {
      const Brick &A = bs[0], &B = bs[(size_t)r];
      GRAN_CHECK(same_bits(A.e_coll, B.e_coll) && same_bits(A.e_ext, B.e_ext) && same_bits(A.flux_kin, B.flux_kin) &&
                     same_bits(A.flux_coll, B.flux_coll) && A.clamped == B.clamped && A.step == B.step &&
                     std::memcmp(&A.shift_rng, &B.shift_rng, sizeof A.shift_rng) == 0,
                 GRAN_ERR_INTERNAL, "brick %d's scalar state differs from brick 0's", r);
    }
    std::vector<std::pair<uint64_t, std::pair<int, int64_t>>> all;
    all.reserve((size_t)s->n);
    for (int r = 0; r < P; ++r)
      for (size_t i = 0; i < bs[(size_t)r].key.size(); ++i)
        if (bs[(size_t)r].dest.empty() || bs[(size_t)r].dest[i] < 0) /* not the holes */
          all.push_back({bs[(size_t)r].key[i], {r, (int64_t)i}});
    GRAN_CHECK((int64_t)all.size() == s->n, GRAN_ERR_INTERNAL, "the bricks hold %lld particles, not %lld",
               (long long)all.size(), (long long)s->n);
    std::sort(all.begin(), all.end());
    for (int64_t i = 0; i < s->n; ++i) {
      const Brick &B = bs[(size_t)all[(size_t)i].second.first];
      const size_t j = (size_t)all[(size_t)i].second.second;
      s->x[(size_t)i] = B.x[j];
      s->y[(size_t)i] = B.y[j];
      s->vx[(size_t)i] = B.vx[j];
      s->vy[(size_t)i] = B.vy[j];
      if (d == 3) {
        s->z[(size_t)i] = B.z[j];
        s->vz[(size_t)i] = B.vz[j];
      }
    }
    for (int r = 0; r < P; ++r) {
      const Brick &B = bs[(size_t)r];
      for (int64_t l = 0; l < B.ncl; ++l) {
        const int64_t gc = global_of(C, B, l);
        s->cell[(size_t)gc] = B.cell[(size_t)l];
        s->rng[(size_t)gc] = B.rng[(size_t)l];
      }
    }
    scalars_to(bs[0], s);
    GRAN_CALL(srd_bricks_gather_plain_(s, out));
    int64_t moved = 0;
    for (const Brick &B : bs) moved += B.moved;
    out->bytes_sent = T.bytes;
    out->particles_sent = moved;
    int64_t faces = 0;
    for (int a = 0; a < d; ++a) {
      if (C.sp.P[a] == 1) continue;
      const int64_t per_row = a == s->opt.wall_axis ? C.sp.P[a] - 1 : C.sp.P[a];
      faces += per_row * (P / C.sp.P[a]);
    }
    out->faces = faces;
    out->seconds = t_steps;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/* ---- digests, the automatic split, one brick per process ---- */
namespace {

inline uint64_t mix64(uint64_t z) { /* splitmix64's finaliser */
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
inline uint64_t hash_words(const uint64_t *w, int nw) {
  uint64_t h = 0x6a09e667f3bcc909ull;
  for (int q = 0; q < nw; ++q) h = mix64(h ^ w[q]);
  return h;
}
inline uint64_t hash_particle(double x, double y, double z, double vx, double vy, double vz, bool d3) {
  uint64_t w[6];
  int q = 0;
  w[q++] = key_of(x);
  w[q++] = key_of(y);
  if (d3) w[q++] = key_of(z);
  w[q++] = key_of(vx);
  w[q++] = key_of(vy);
  if (d3) w[q++] = key_of(vz);
  return hash_words(w, q);
}
inline uint64_t hash_cell(int64_t gc, const double V[3], const uint64_t s[4]) {
  const uint64_t w[8] = {(uint64_t)gc, key_of(V[0]), key_of(V[1]), key_of(V[2]), s[0], s[1], s[2], s[3]};
  return hash_words(w, 8);
}

/* the gas's totals over the processes: digests (sums mod 2^64), counts, extremes, exact sums */
struct Tot {
  uint64_t dp, dc;
  int64_t n, nmin, nmax, bytes, moved, far;
  double tmax;
  gran_exactsum mom[3], en;
  void merge(const Tot &o) {
    dp += o.dp;
    dc += o.dc;
    n += o.n;
    nmin = std::min(nmin, o.nmin);
    nmax = std::max(nmax, o.nmax);
    bytes += o.bytes;
    moved += o.moved;
    far += o.far;
    tmax = std::max(tmax, o.tmax);
    for (int k = 0; k < 3; ++k) gran_exactsum_merge_(&mom[k], &o.mom[k]);
    gran_exactsum_merge_(&en, &o.en);
  }
};
static_assert(std::is_trivially_copyable<Tot>::value, "the totals are sent as bytes");

} // namespace

extern "C" void srd_bricks_digest_(const srd_bricks_out *o, int dim, uint64_t *particles, uint64_t *cells) {
  const bool d3 = dim == 3;
  uint64_t dp = 0, dc = 0;
  for (int64_t i = 0; i < o->n; ++i)
    dp += hash_particle(o->x[i], o->y[i], d3 ? o->z[i] : 0.0, o->vx[i], o->vy[i], d3 ? o->vz[i] : 0.0, d3);
  for (int64_t c = 0; c < o->ncell; ++c) dc += hash_cell(c, o->V + 3 * c, o->rng + 4 * c);
  *particles = dp;
  *cells = dc;
}

extern "C" double srd_bricks_memory_(const gran_srd_options *opt, int nbricks, int all_in_one) {
  double box = 1, bin = 1;
  for (int k = 0; k < opt->dim; k++) {
    box *= (double)opt->cells[k];
    bin *= (double)(opt->cells[k] + (k == opt->wall_axis ? 1 : 0));
  }
  const double N = std::floor(opt->n0 * box + 0.5), d = (double)opt->dim;
  const bool str = opt->shear_rate != 0 || opt->wall_axis >= 0 || opt->accel[0] != 0 || opt->accel[1] != 0 ||
                   opt->accel[2] != 0;
  /* per particle: state, key, local cell, dest, order, the streaming terms, the sort's copy of one
   * array, an observation's record (its unshifted cell, key and velocity: srd_bricks_observe_);
   * per cell: V, RNG, sums, start, mark */
  const double bpp = 16.0 * d + 8 + 4 + 4 + 4 + (str ? 24.0 : 0.0) + 8 + 36;
  const double bpc = 24.0 + 32.0 + (double)sizeof(srd_cell_sum) + 4 + 1;
  const double share = all_in_one ? 1.0 : 1.0 / (double)std::max(1, nbricks);
  double b = 1.1 * N * share * bpp + bin * share * bpc + 1e6;
  return b;
}

extern "C" int srd_bricks_auto_(const gran_srd_options *opt, int P, int pgrid[3]) {
  GRAN_TRY {
    GRAN_CHECK_PTR(opt);
    GRAN_CHECK_PTR(pgrid);
    GRAN_CALL(srd_check_options_(opt));
    gran_srd g;
    g.opt = *opt;
    GRAN_CALL(srd_alloc_geometry_(&g));
    const int64_t *nc = g.gm.nc;
    GRAN_CHECK(P >= 1 && (double)P <= (double)g.ncell, GRAN_ERR_ARG,
               "a split into %d bricks: the binning grid has %lld cells and a brick needs at least one (processes: "
               "at most %lld)", P, (long long)g.ncell, (long long)g.ncell);
    double best = INFINITY;
    int found = 0;
    for (int px = 1; px <= P; ++px) {
      if (P % px || px > nc[0]) continue;
      for (int py = 1; py <= P / px; ++py) {
        if ((P / px) % py || py > nc[1]) continue;
        const int pz = P / px / py;
        if (pz > nc[2] || (opt->dim == 2 && pz != 1)) continue;
        const int p[3] = {px, py, pz};
        double area = 0; /* cells on the cut planes: what the exchange moves */
        for (int a = 0; a < 3; ++a) {
          const double planes = p[a] == 1 ? 0.0 : (a == opt->wall_axis ? p[a] - 1 : p[a]);
          double face = 1;
          for (int b = 0; b < 3; ++b)
            if (b != a) face *= (double)nc[b];
          area += planes * face;
        }
        if (area < best) { /* ties keep the first: the fewest bricks along x */
          best = area;
          pgrid[0] = px;
          pgrid[1] = py;
          pgrid[2] = pz;
          found = 1;
        }
      }
    }
    GRAN_CHECK(found, GRAN_ERR_ARG,
               "no split of the binning grid (%lld x %lld x %lld cells) into %d bricks along whole cells (a brick "
               "needs at least one cell per axis)",
               (long long)nc[0], (long long)nc[1], (long long)nc[2], P);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/* ---- a split gas held by this process: its bricks (one per process over a comm, or all) ---- */
struct srd_bricks_state {
  std::unique_ptr<gran_srd> shell; /* the options and the geometry, no arrays */
  Ctx C;
  std::vector<Brick> bs;
  std::unique_ptr<LocalTransport> TL;
  std::unique_ptr<CommTransport> TC;
  Transport *T = nullptr;
  srd_bricks_comm comm;
  bool over_comm = false; /* one brick per process */
  int pgrid[3] = {1, 1, 1};
  double e0 = 0, seconds = 0;
  double stress_t0 = 0; /* the time of the last stress reset */
  Phases phases;        /* GRAN_SRD_PHASES=1: over all step calls, printed at close */
};

namespace {
/* A split gas's frame without particles: the options checked, the geometry, the split, the bricks'
 * windows (one brick over a process group of P > 1, else every brick) and the transport */
int open_shell(const gran_srd_options *opt, const int pgrid[3], const srd_bricks_comm *comm,
               std::unique_ptr<srd_bricks_state> &st) {
  GRAN_CHECK_PTR(opt);
  GRAN_CHECK_PTR(pgrid);
  GRAN_CHECK(opt->creation == GRAN_SRD_CREATE_CELLS, GRAN_ERR_ARG,
             "option 'creation' must be GRAN_SRD_CREATE_CELLS ([engine] creation = \"cells\": the decomposable "
             "engine) for a decomposed run (got %d)",
             (int)opt->creation);
  GRAN_CHECK(opt->device == GRAN_SRD_DEVICE_CPU, GRAN_ERR_ARG,
             "a decomposed GSRD run steps on the CPU (option 'device' must be GRAN_SRD_DEVICE_CPU, got %d)",
             (int)opt->device);
  for (int a = opt->dim; a < 3; ++a)
    GRAN_CHECK(pgrid[a] == 1, GRAN_ERR_ARG, "argument 'pgrid[%d]' must be 1 in %d-D (got %d)", a, (int)opt->dim,
               pgrid[a]);
  const int64_t nb = (int64_t)pgrid[0] * pgrid[1] * pgrid[2];
  const bool over = comm && comm->size > 1;
  if (comm) {
    GRAN_CHECK(comm->size >= 1 && comm->rank >= 0 && comm->rank < comm->size, GRAN_ERR_ARG,
               "the process group: rank %d of %d processes is not a process of it", comm->rank, comm->size);
    GRAN_CHECK(!over || (comm->round && comm->allreduce), GRAN_ERR_ARG,
               "the process group of %d processes has no round or all-reduce function", comm->size);
    GRAN_CHECK(!over || nb == comm->size, GRAN_ERR_ARG,
               "the split %d x %d x %d has %lld bricks, not one per process (%d processes)", pgrid[0], pgrid[1],
               pgrid[2], (long long)nb, comm->size);
  }
  GRAN_CALL(srd_check_options_(opt));
  st.reset(new srd_bricks_state);
  st->shell.reset(new gran_srd);
  st->shell->opt = *opt;
  GRAN_CALL(srd_alloc_geometry_(st->shell.get()));
  GRAN_CALL(make_ctx(st->shell.get(), pgrid, st->C));
  for (int k = 0; k < 3; ++k) st->pgrid[k] = pgrid[k];
  st->over_comm = over;
  if (over) {
    st->comm = *comm;
    st->bs.resize(1);
    window_of(st->C, comm->rank, st->bs[0]);
    st->TC.reset(new CommTransport(*comm, peers_of(st->C, comm->rank)));
    st->T = st->TC.get();
  } else {
    st->bs.resize((size_t)nb);
    for (int r = 0; r < (int)nb; ++r) window_of(st->C, r, st->bs[(size_t)r]);
    st->TL.reset(new LocalTransport((int)nb));
    st->T = st->TL.get();
  }
  return GRAN_SUCCESS;
}
}  // namespace

int srd_bricks_open_(const gran_srd_options *opt, const int pgrid[3], const srd_bricks_comm *comm,
                     srd_bricks_state **out) {
  GRAN_TRY {
    GRAN_CHECK_PTR(out);
    *out = nullptr;
    std::unique_ptr<srd_bricks_state> st;
    GRAN_CALL(open_shell(opt, pgrid, comm, st));
    for (Brick &B : st->bs) scalars_from(st->shell.get(), B);
    GRAN_CALL(bricks_create(st->C, st->bs, *st->T, &st->e0));
    *out = st.release();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

int srd_bricks_step_(srd_bricks_state *st, int64_t nsteps) {
  GRAN_TRY {
    GRAN_CHECK_PTR(st);
    GRAN_CHECK(nsteps >= 0, GRAN_ERR_ARG, "argument 'nsteps' must be >= 0 (got %lld)", (long long)nsteps);
    const double t0 = srd_clock_s();
    const gran_srd_options &o = st->shell->opt;
    const int e = pick(o.dim, srd_fx_of(&o))(st->C, st->bs, *st->T, nsteps, &st->phases);
    st->seconds += srd_clock_s() - t0;
    return e;
  }
  GRAN_CATCH
}

int srd_bricks_report_(srd_bricks_state *st, srd_bricks_rank_out *out) {
  GRAN_TRY {
    GRAN_CHECK_PTR(st);
    GRAN_CHECK_PTR(out);
    std::memset(out, 0, sizeof *out);
    const gran_srd_options &o = st->shell->opt;
    const bool d3 = o.dim == 3;
    auto all = [&](Tot &t) -> int { /* over the processes (the bricks here are merged already) */
      if (!st->over_comm) return GRAN_SUCCESS;
      GRAN_CHECK(st->comm.allreduce(st->comm.ctx, &t, sizeof t, 1, &merge_bytes<Tot>) == 0, GRAN_ERR_IO,
                 "decomposed GSRD run: the all-reduce of the report failed on process %d", st->comm.rank);
      return GRAN_SUCCESS;
    };
    auto fresh = [](Tot &t) {
      std::memset((void *)&t, 0, sizeof t);
      t.nmin = INT64_MAX;
      t.nmax = 0;
      for (int k = 0; k < 3; ++k) gran_exactsum_init_(&t.mom[k]);
      gran_exactsum_init_(&t.en);
    };
    Tot t;
    fresh(t);
    for (const Brick &B : st->bs) {
      int64_t nl = 0;
      for (size_t i = 0; i < B.x.size(); ++i) {
        if (!B.dest.empty() && B.dest[i] >= 0) continue; /* a hole */
        const double z = d3 ? B.z[i] : 0.0, vz = d3 ? B.vz[i] : 0.0;
        t.dp += hash_particle(B.x[i], B.y[i], z, B.vx[i], B.vy[i], vz, d3);
        gran_exactsum_add_(&t.mom[0], B.vx[i]);
        gran_exactsum_add_(&t.mom[1], B.vy[i]);
        if (d3) gran_exactsum_add_(&t.mom[2], vz);
        gran_exactsum_add_(&t.en, 0.5 * (B.vx[i] * B.vx[i] + B.vy[i] * B.vy[i] + vz * vz));
        ++nl;
      }
      for (int64_t l = 0; l < B.ncl; ++l)
        t.dc += hash_cell(global_of(st->C, B, l), B.cell[(size_t)l].V, B.rng[(size_t)l].s);
      t.n += nl;
      t.nmin = std::min(t.nmin, nl);
      t.nmax = std::max(t.nmax, nl);
      t.moved += B.moved;
      out->particle_steps += B.psteps;
    }
    t.bytes = st->over_comm ? st->TC->bytes : st->TL->bytes;
    t.far = st->over_comm ? st->TC->far : 0;
    t.tmax = st->seconds;
    out->n_local = t.n;
    out->seconds = st->seconds;
    out->bytes_sent = t.bytes;
    int64_t moved_here = 0;
    for (const Brick &B : st->bs) moved_here += B.moved;
    out->particles_sent = moved_here;
    GRAN_CALL(all(t));
    out->n = t.n;
    out->digest_particles = t.dp;
    out->digest_cells = t.dc;
    for (int k = 0; k < 3; ++k) out->momentum[k] = gran_exactsum_value_(&t.mom[k]);
    out->energy = gran_exactsum_value_(&t.en);
    /* the temperature: sum |v - P/N|^2 / (d N), a second exact sum with the mean flow */
    {
      const double u[3] = {out->momentum[0] / (double)t.n, out->momentum[1] / (double)t.n, out->momentum[2] / (double)t.n};
      Tot q;
      fresh(q);
      for (const Brick &B : st->bs)
        for (size_t i = 0; i < B.x.size(); ++i) {
          if (!B.dest.empty() && B.dest[i] >= 0) continue;
          const double ux = B.vx[i] - u[0], uy = B.vy[i] - u[1], uz = d3 ? B.vz[i] - u[2] : 0.0;
          gran_exactsum_add_(&q.en, ux * ux + uy * uy + uz * uz);
        }
      GRAN_CALL(all(q));
      out->temperature = gran_exactsum_value_(&q.en) / (double)(o.dim * t.n);
    }
    const Brick &B = st->bs[0]; /* the scalar state is the same on every brick */
    out->time = B.time;
    out->e_initial = st->e0;
    out->e_coll = B.e_coll;
    out->e_ext = B.e_ext;
    out->flux_kin = B.flux_kin;
    out->flux_coll = B.flux_coll;
    for (int k = 0; k < 3; ++k) out->wall_impulse[k] = B.wall_impulse[k];
    out->dt_max = B.dt_max;
    out->step = B.step;
    out->clamped = B.clamped;
    for (int k = 0; k < 3; ++k) out->bricks[k] = st->pgrid[k];
    out->seconds_max = t.tmax;
    out->bytes_sent_all = t.bytes;
    out->particles_sent_all = t.moved;
    out->n_local_min = t.nmin;
    out->n_local_max = t.nmax;
    out->far_messages_all = t.far;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

void srd_bricks_close_(srd_bricks_state **st) {
  if (!st) return;
  if (*st && srd_phase_timing()) phases_print((*st)->phases);
  delete *st;
  *st = nullptr;
}

/* ---- S(k) of a split gas ---- */
static_assert(std::is_trivially_copyable<srd_sk_bin>::value, "the shells are all-reduced as bytes");

int srd_bricks_structure_factor_(srd_bricks_state *st, int64_t nbins, double *k, double *sk, int64_t *count) {
  GRAN_TRY {
    GRAN_CHECK_PTR(st);
    GRAN_CHECK_PTR(k);
    GRAN_CHECK_PTR_AS(sk, s);
    GRAN_CHECK_PTR(count);
    const gran_srd *sh = st->shell.get();
    const gran_srd_options &o = sh->opt;
    GRAN_CHECK(o.wall_axis < 0, GRAN_ERR_ARG, "S(k) needs a periodic box (no walls)");
    GRAN_CHECK(nbins >= 1 && nbins <= SRD_BRICKS_SK_MAX_BINS, GRAN_ERR_ARG,
               "argument 'nbins' of a split gas's S(k) must be in [1, %d] (got %lld)", SRD_BRICKS_SK_MAX_BINS,
               (long long)nbins);
    const bool over = st->over_comm;
    GRAN_CHECK(!over || st->comm.fft_r2c, GRAN_ERR_ARG,
               "S(k) of a gas split over %d processes needs a distributed FFT, and this process group has none "
               "(build/granary-mpi built without FFTW's MPI interface: install Debian libfftw3-mpi-dev and rebuild)",
               st->comm.size);
    const int d = o.dim;
    const srd_sk_geom g = srd_sk_geom_of(sh, nbins);
    const int64_t L[3] = {g.n0, g.n1, g.n2};
    const int64_t N = sh->n; /* conserved: the count the creation drew */
    /* the transform's slabs: rows of the last axis (the first of the row-major layout) */
    const int64_t nA = L[d - 1], plane = d == 3 ? L[0] * L[1] : L[0];
    const int P = over ? st->comm.size : 1, me = over ? st->comm.rank : 0;
    const int64_t blk = (nA + P - 1) / P;
    const int64_t r0 = std::min(nA, (int64_t)me * blk), r1 = std::min(nA, (int64_t)(me + 1) * blk);
    std::vector<double> slab((size_t)((r1 - r0) * plane), 0.0);
    srd_geom g0 = sh->gm; /* the unshifted lattice, as gran_srd_structure_factor bins it */
    g0.le_on = 0;
    const double zero[3] = {0, 0, 0};
    const bool d3 = d == 3;
    if (!over) {
      for (const Brick &B : st->bs)
        for (size_t i = 0; i < B.x.size(); ++i) {
          if (!B.dest.empty() && B.dest[i] >= 0) continue; /* a hole */
          const double p[3] = {B.x[i], B.y[i], d3 ? B.z[i] : 0.0};
          double dvx;
          slab[(size_t)srd_bin(&g0, zero, p, &dvx)] += 1.0;
        }
    } else {
      /* the brick's particles lie in the unshifted cells of its window widened by one cell per
       * axis (dense counts); the rest (across the Lees-Edwards boundary) are listed */
      const Brick &B = st->bs[0];
      int64_t W[3] = {1, 1, 1}, lo[3] = {0, 0, 0};
      for (int a = 0; a < d; ++a) {
        W[a] = std::min(L[a], B.w[a] + 2);
        lo[a] = (B.lo[a] - 1 + L[a]) % L[a];
      }
      std::vector<int64_t> dense((size_t)(W[0] * W[1] * W[2]), 0), extra;
      for (size_t i = 0; i < B.x.size(); ++i) {
        if (!B.dest.empty() && B.dest[i] >= 0) continue;
        const double p[3] = {B.x[i], B.y[i], d3 ? B.z[i] : 0.0};
        int64_t c[3];
        double dvx;
        srd_bin3(&g0, zero, p, c, &dvx);
        int64_t r[3] = {0, 0, 0};
        bool in = true;
        for (int a = 0; a < d; ++a) {
          r[a] = (c[a] - lo[a] + L[a]) % L[a];
          in = in && r[a] < W[a];
        }
        if (in) ++dense[(size_t)(r[0] + W[0] * (r[1] + W[1] * r[2]))];
        else extra.push_back(c[0] + L[0] * (c[1] + L[1] * c[2]));
      }
      std::vector<std::vector<double>> out((size_t)P), got((size_t)P);
      auto emit = [&](int64_t gc, int64_t n) {
        const int to = (int)((gc / plane) / blk);
        if (to == me) slab[(size_t)(gc - r0 * plane)] += (double)n;
        else {
          out[(size_t)to].push_back(word_of((uint64_t)gc));
          out[(size_t)to].push_back(word_of((uint64_t)n));
        }
      };
      for (int64_t r2 = 0; r2 < W[2]; ++r2)
        for (int64_t r1_ = 0; r1_ < W[1]; ++r1_)
          for (int64_t q = 0; q < W[0]; ++q) {
            const int64_t n = dense[(size_t)(q + W[0] * (r1_ + W[1] * r2))];
            if (!n) continue;
            const int64_t c0 = (lo[0] + q) % L[0], c1 = (lo[1] + r1_) % L[1], c2 = (lo[2] + r2) % L[2];
            emit(c0 + L[0] * (c1 + L[1] * c2), n);
          }
      std::sort(extra.begin(), extra.end());
      for (size_t i = 0; i < extra.size();) {
        size_t j = i;
        while (j < extra.size() && extra[j] == extra[i]) ++j;
        emit(extra[i], (int64_t)(j - i));
        i = j;
      }
      GRAN_CHECK(st->comm.round(st->comm.ctx, out, got) == 0, GRAN_ERR_IO,
                 "decomposed GSRD run: the exchange of the cell counts for S(k) failed on process %d", me);
      for (int p = 0; p < P; ++p) {
        const std::vector<double> &m = got[(size_t)p];
        GRAN_CHECK(m.size() % 2 == 0, GRAN_ERR_IO, "S(k): process %d sent process %d a cut message of cell counts", p,
                   me);
        for (size_t i = 0; i < m.size(); i += 2) {
          const int64_t gc = (int64_t)key_of(m[i]), n = (int64_t)key_of(m[i + 1]);
          GRAN_CHECK(gc >= r0 * plane && gc < r1 * plane && n > 0, GRAN_ERR_IO,
                     "S(k): process %d sent process %d the count of cell %lld, not one of its slab", p, me,
                     (long long)gc);
          slab[(size_t)(gc - r0 * plane)] += (double)n;
        }
      }
    }
    /* the power of this process's rows of the half spectrum */
    std::vector<double> power;
    if (!over) {
      GRAN_CALL(srd_sk_power(sh, slab.data(), power));
    } else {
      const double mean = (double)N / (double)sh->ncell_box;
      for (double &c : slab) c -= mean;
      const int64_t rowc = (d3 ? L[1] : 1) * g.nh; /* complex values per row */
      std::vector<double> z((size_t)(2 * (r1 - r0) * rowc));
      const int64_t nd[3] = {d3 ? L[2] : L[1], d3 ? L[1] : L[0], d3 ? L[0] : 1};
      GRAN_CHECK(st->comm.fft_r2c(st->comm.ctx, d, nd, blk, slab.data(), z.data()) == 0, GRAN_ERR_IO,
                 "decomposed GSRD run: the distributed FFT of S(k) failed on process %d", me);
      power.resize(z.size() / 2);
      for (size_t q = 0; q < power.size(); ++q) power[q] = srd_sk_mode_power(z[2 * q], z[2 * q + 1], N);
    }
    std::vector<srd_sk_bin> bins = srd_sk_bins(nbins);
    srd_sk_bins_add(g, power.data(), r0, r1, bins.data());
    if (over)
      GRAN_CHECK(st->comm.allreduce(st->comm.ctx, bins.data(), sizeof(srd_sk_bin), bins.size(),
                                    &merge_bytes<srd_sk_bin>) == 0,
                 GRAN_ERR_IO, "decomposed GSRD run: the all-reduce of S(k)'s shells failed on process %d", me);
    srd_sk_bins_out(bins.data(), nbins, k, sk, count);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/* ---- the observables of a split gas (gran_srd_observe's, bit for bit the same on any split) ----
 * The cell observables (theta_cells, e_kin, sigma_rho, a2) are sums over the cells of the
 * unshifted lattice, whose particles lie in up to 2^d bricks (a brick holds the particles of its
 * cells under the last step's shift). Each particle's record (its unshifted cell, key and velocity)
 * goes to the brick whose window holds that cell (the particles of other processes' cells in one
 * message round); each brick then has its unshifted cells whole, puts every cell's particles in
 * key order (the order of the one-process array) and adds each cell's sums in that order, as the
 * serial engine adds them in index order; every global sum is exact (one exact add per cell and
 * quantity), all-reduced. Two passes: the momentum, the cells' means and the largest thermal
 * component first; the temperature about the mean flow and a2's moments, scaled by that
 * component's power of two, second. */
namespace {

enum { OQ_P0, OQ_P1, OQ_P2, OQ_E, OQ_EK, OQ_Q, OQ_N };   /* pass 1 */
enum { OQ_TH = 0, OQ_M2, OQ_M4, OQ_H };                  /* pass 2, in the same record */
struct ObsRed {
  gran_exactsum a[OQ_N];
  int64_t n, r2, nin; /* particles, sum of n_c^2, particles in cells of n_c >= 2 */
  double umax;        /* the largest |thermal component| in those cells */
  void clear() {
    for (auto &q : a) gran_exactsum_init_(&q);
    n = r2 = nin = 0;
    umax = 0;
  }
  void merge(const ObsRed &o) {
    for (int q = 0; q < OQ_N; ++q) gran_exactsum_merge_(&a[q], &o.a[q]);
    n += o.n;
    r2 += o.r2;
    nin += o.nin;
    umax = std::max(umax, o.umax);
  }
};
static_assert(std::is_trivially_copyable<ObsRed>::value, "the observation's sums are all-reduced as bytes");

/* the OpenMP thread of the caller (0 without OpenMP) */
inline int thread_num() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

constexpr int kObsWords = 5; /* a particle's record in a message: global cell, key, vx, vy, vz */

/* one particle of an unshifted cell: its key and velocity */
struct ObsRec {
  uint64_t key;
  double v[3];
};
/* the moments of one cell's n > 0 particles, summed in their (key) order: momentum S, kinetic
 * energy E, mean V = S / n, thermal sum Q = sum |v - V|^2 and the largest |u_k| (the arithmetic of
 * gran_srd_observe's pass over a cell and of gran_srd_fields') */
struct CellMoments {
  double S[3], E, V[3], Q, um;
};
inline void cell_moments(const ObsRec *q, int64_t n, CellMoments &m) {
  double S[3] = {0, 0, 0}, E = 0;
  for (int64_t i = 0; i < n; ++i) {
    const double *v = q[i].v;
    S[0] += v[0];
    S[1] += v[1];
    S[2] += v[2];
    E += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  for (int k = 0; k < 3; ++k) {
    m.S[k] = S[k];
    m.V[k] = S[k] / (double)n;
  }
  m.E = E;
  double Q = 0, um = 0;
  for (int64_t i = 0; i < n; ++i) {
    const double *v = q[i].v;
    const double ux = v[0] - m.V[0], uy = v[1] - m.V[1], uz = v[2] - m.V[2];
    Q += ux * ux + uy * uy + uz * uz;
    um = std::max({um, std::fabs(ux), std::fabs(uy), std::fabs(uz)});
  }
  m.Q = Q;
  m.um = um;
}
constexpr int kFieldWords = 6; /* a cell's record of the fields: box cell, count, V[3], temperature */

/* the unshifted cells of a brick's window: cell c holds rec[start[c] .. start[c + 1]), in key order,
 * and its mean velocity V[3 c ..] (pass 1) */
struct ObsCells {
  std::vector<int64_t> start;
  std::vector<ObsRec> rec;
  std::vector<double> V, S; /* S: the cell's momentum (with a velocity profile) */
};

/* one layer of y of the velocity profile: its momentum, exact, and its particles */
struct LayerRed {
  gran_exactsum u[3];
  int64_t n;
  void clear() {
    for (auto &q : u) gran_exactsum_init_(&q);
    n = 0;
  }
  void merge(const LayerRed &o) {
    for (int q = 0; q < 3; ++q) gran_exactsum_merge_(&u[q], &o.u[q]);
    n += o.n;
  }
};
static_assert(std::is_trivially_copyable<LayerRed>::value, "the profile's layers are all-reduced as bytes");

/* the particles of every brick's unshifted cells, whole and per cell in key order (comm: one brick
 * per process, the particles of other processes' cells sent in a round; NULL: every brick of the
 * split in bs) */
int obs_collect(const Ctx &C, std::vector<Brick> &bs, const srd_bricks_comm *comm, std::vector<ObsCells> &oc) {
  const int d = C.o->dim;
  const bool d3 = d == 3;
  srd_geom g0 = C.gm; /* the unshifted lattice, as gran_srd_observe bins it */
  g0.le_on = 0;
  const double zero[3] = {0, 0, 0};
  const bool over = comm != nullptr;
  const int P = over ? comm->size : (int)bs.size();
  const int me = over ? comm->rank : -1;
  const int64_t ncg = C.gm.nc[0] * C.gm.nc[1] * C.gm.nc[2];
  constexpr uint32_t kNone = UINT32_MAX; /* a hole, or a particle of another brick's cell */
  const int nt = std::max(1, C.nth);
  oc.assign(bs.size(), ObsCells());
  std::vector<std::vector<uint32_t>> lcs(bs.size()); /* per slot: its unshifted cell in the brick's window */
  /* per brick and thread (a contiguous range of slots): its particles per cell, then where they go */
  std::vector<std::vector<uint32_t>> cnt(bs.size() * (size_t)nt);
  std::vector<std::vector<double>> out((size_t)P);   /* over a comm: the records for other processes */
  std::vector<std::vector<double>> arr(bs.size());   /* per brick: the records of its cells' particles from others */
  for (size_t b = 0; b < bs.size(); ++b) {
    const Brick &B = bs[b];
    std::vector<uint32_t> &L = lcs[b];
    L.assign(B.x.size(), kNone);
    const int64_t n = (int64_t)B.x.size();
    std::vector<std::vector<std::vector<double>>> far((size_t)nt); /* per thread: records per destination */
#pragma omp parallel num_threads(nt)
    {
      const int t = thread_num();
      std::vector<uint32_t> &ct = cnt[b * (size_t)nt + (size_t)t];
      ct.assign((size_t)B.ncl, 0);
      std::vector<std::vector<double>> &ft = far[(size_t)t];
      ft.resize((size_t)P);
      for (int64_t i = n * t / nt; i < n * (t + 1) / nt; ++i) {
        if (!B.dest.empty() && B.dest[(size_t)i] >= 0) continue; /* a hole */
        const double p[3] = {B.x[(size_t)i], B.y[(size_t)i], d3 ? B.z[(size_t)i] : 0.0};
        int64_t c[3];
        double dvx;
        srd_bin3(&g0, zero, p, c, &dvx);
        const int to = owner_of(C.sp, c);
        if (over ? to == me : to == B.rank) {
          L[(size_t)i] = local_of(B, c);
          ++ct[L[(size_t)i]];
        } else {
          const int64_t gc = c[0] + C.gm.nc[0] * (c[1] + C.gm.nc[1] * c[2]);
          const double rec[kObsWords] = {word_of((uint64_t)gc), word_of(B.key[(size_t)i]), B.vx[(size_t)i],
                                         B.vy[(size_t)i], d3 ? B.vz[(size_t)i] : 0.0};
          ft[(size_t)to].insert(ft[(size_t)to].end(), rec, rec + kObsWords);
        }
      }
    }
    for (int t = 0; t < nt; ++t) /* the records in thread order (each cell is put in key order below) */
      for (int q = 0; q < P; ++q) {
        std::vector<double> &m = over ? out[(size_t)q] : arr[(size_t)q];
        m.insert(m.end(), far[(size_t)t][(size_t)q].begin(), far[(size_t)t][(size_t)q].end());
      }
  }
  if (over) {
    std::vector<std::vector<double>> got((size_t)P);
    GRAN_CHECK(comm->round(comm->ctx, out, got) == 0, GRAN_ERR_IO,
               "decomposed GSRD run: the exchange of the particles of the unshifted cells failed on process %d", me);
    for (int p = 0; p < P; ++p) {
      GRAN_CHECK(got[(size_t)p].size() % kObsWords == 0, GRAN_ERR_IO,
                 "observables: process %d sent process %d a cut message of particle records", p, me);
      arr[0].insert(arr[0].end(), got[(size_t)p].begin(), got[(size_t)p].end());
    }
  }
  for (size_t b = 0; b < bs.size(); ++b) {
    const Brick &B = bs[b];
    ObsCells &O = oc[b];
    const std::vector<double> &A = arr[b];
    const std::vector<uint32_t> &L = lcs[b];
    const int64_t na = (int64_t)(A.size() / kObsWords);
    std::vector<uint32_t> alc((size_t)na);
    for (int64_t j = 0; j < na; ++j) {
      const int64_t gc = (int64_t)key_of(A[(size_t)(j * kObsWords)]);
      GRAN_CHECK(gc >= 0 && gc < ncg, GRAN_ERR_IO, "observables: brick %d received a particle of cell %lld, outside the grid",
                 B.rank, (long long)gc);
      const int64_t c[3] = {gc % C.gm.nc[0], (gc / C.gm.nc[0]) % C.gm.nc[1], gc / (C.gm.nc[0] * C.gm.nc[1])};
      GRAN_CHECK(owner_of(C.sp, c) == B.rank, GRAN_ERR_IO, "observables: brick %d received a particle of brick %d's cell %lld",
                 B.rank, owner_of(C.sp, c), (long long)gc);
      alc[(size_t)j] = local_of(B, c);
    }
    /* a counting sort by cell: each cell's particles of thread 0's slots, thread 1's, ..., then the
     * arrivals; then each cell's particles in key order, the order of the one-process array (a
     * brick's residents are in key order by slot: the insertion moves only the others). The
     * counts become where each thread's (and the arrivals') first particle of the cell goes. */
    std::vector<int64_t> fill_a((size_t)B.ncl, 0);
    for (int64_t j = 0; j < na; ++j) ++fill_a[alc[(size_t)j]];
    O.start.assign((size_t)B.ncl + 1, 0);
    for (int64_t c = 0, at = 0; c < B.ncl; ++c) {
      for (int t = 0; t < nt; ++t) {
        uint32_t &x = cnt[b * (size_t)nt + (size_t)t][(size_t)c];
        const uint32_t k = x;
        x = (uint32_t)at; /* a brick holds fewer than 2^32 particles (N < 4e9) */
        at += k;
      }
      const int64_t k = fill_a[(size_t)c];
      fill_a[(size_t)c] = at;
      at += k;
      O.start[(size_t)c + 1] = at;
    }
    O.rec.resize((size_t)O.start[(size_t)B.ncl]);
    const int64_t n = (int64_t)L.size();
#pragma omp parallel num_threads(nt)
    {
      const int t = thread_num();
      std::vector<uint32_t> &ot = cnt[b * (size_t)nt + (size_t)t];
      for (int64_t i = n * t / nt; i < n * (t + 1) / nt; ++i) {
        const uint32_t l = L[(size_t)i];
        if (l == kNone) continue;
        O.rec[(size_t)ot[l]++] =
            ObsRec{B.key[(size_t)i], {B.vx[(size_t)i], B.vy[(size_t)i], d3 ? B.vz[(size_t)i] : 0.0}};
      }
    }
    for (int64_t j = 0; j < na; ++j) {
      const double *w = A.data() + j * kObsWords;
      O.rec[(size_t)fill_a[alc[(size_t)j]]++] = ObsRec{key_of(w[1]), {w[2], w[3], w[4]}};
    }
    for (int t = 0; t < nt; ++t) std::vector<uint32_t>().swap(cnt[b * (size_t)nt + (size_t)t]);
    std::vector<uint32_t>().swap(lcs[b]);
    std::vector<double>().swap(arr[b]);
#pragma omp parallel for schedule(static, 4096) num_threads(nt)
    for (int64_t c = 0; c < B.ncl; ++c) { /* insertion by key (the keys are distinct) */
      ObsRec *q = O.rec.data() + O.start[(size_t)c];
      const int64_t m = O.start[(size_t)c + 1] - O.start[(size_t)c];
      for (int64_t i = 1; i < m; ++i) {
        if (!(q[i - 1].key > q[i].key)) continue;
        const ObsRec t = q[i];
        int64_t j = i;
        for (; j > 0 && q[j - 1].key > t.key; --j) q[j] = q[j - 1];
        q[j] = t;
      }
    }
  }
  return GRAN_SUCCESS;
}

/* the sums of gran_srd_observe (momentum, energy, temperature, e_kin, theta_cells, mach, sigma_rho,
 * a2) of the gas in bs (comm: one brick per process; NULL: every brick here) */
int obs_sums(const Ctx &C, std::vector<Brick> &bs, const srd_bricks_comm *comm, int64_t ncell_box, gran_srd_obs *ob,
             double *profile) {
  const int d = C.o->dim;
  std::vector<ObsCells> oc;
  GRAN_CALL(obs_collect(C, bs, comm, oc));
  auto all = [&](ObsRed &r, const char *what) -> int {
    if (!comm) return GRAN_SUCCESS;
    GRAN_CHECK(comm->allreduce(comm->ctx, &r, sizeof r, 1, &merge_bytes<ObsRed>) == 0, GRAN_ERR_IO,
               "decomposed GSRD run: the all-reduce of the observables (%s) failed on process %d", what, comm->rank);
    return GRAN_SUCCESS;
  };
  /* the cells of every brick, over the brick's threads (each with its own exact accumulators,
   * merged: the same bits for any thread count); f(R, O, c) per cell */
  auto cells = [&](ObsRed &tot, auto &&f) {
    std::vector<ObsRed> tr((size_t)C.nth);
    for (ObsRed &R : tr) R.clear();
    for (size_t b = 0; b < bs.size(); ++b) {
      ObsCells &O = oc[b];
      const int64_t ncl = (int64_t)O.start.size() - 1;
#pragma omp parallel for schedule(static, 1024) num_threads(C.nth)
      for (int64_t c = 0; c < ncl; ++c) {
        ObsRed &R = tr[(size_t)thread_num()];
        const int64_t n = O.start[(size_t)c + 1] - O.start[(size_t)c];
        if (n > 0) f(R, O, c, O.rec.data() + O.start[(size_t)c], n);
      }
    }
    for (const ObsRed &R : tr) tot.merge(R);
  };
  /* pass 1: per cell its momentum and energy, mean, thermal sum and convective energy */
  ObsRed r1;
  r1.clear();
  for (ObsCells &O : oc) {
    O.V.assign((size_t)(3 * ((int64_t)O.start.size() - 1)), 0.0);
    if (profile) O.S.assign(O.V.size(), 0.0);
  }
  cells(r1, [&](ObsRed &R, ObsCells &O, int64_t c, const ObsRec *q, int64_t n) {
    CellMoments m;
    cell_moments(q, n, m);
    const double *S = m.S, E = m.E, Q = m.Q, um = m.um;
    double *V = O.V.data() + 3 * c;
    for (int k = 0; k < 3; ++k) V[k] = m.V[k];
    if (!O.S.empty())
      for (int k = 0; k < 3; ++k) O.S[(size_t)(3 * c + k)] = S[k];
    for (int k = 0; k < 3; ++k) gran_exactsum_add_(&R.a[OQ_P0 + k], S[k]);
    gran_exactsum_add_(&R.a[OQ_E], E);
    gran_exactsum_add_(&R.a[OQ_EK], (double)n * (V[0] * V[0] + V[1] * V[1] + V[2] * V[2]));
    gran_exactsum_add_(&R.a[OQ_Q], Q);
    R.n += n;
    R.r2 += n * n;
    if (n >= 2) {
      R.nin += n;
      R.umax = std::max(R.umax, um);
    }
  });
  GRAN_CALL(all(r1, "momentum and cell means"));
  const int64_t N = r1.n;
  GRAN_CHECK(N == ob->n, GRAN_ERR_INTERNAL, "GSRD observables: the bricks hold %lld particles, the gas %lld",
             (long long)N, (long long)ob->n);
  for (int k = 0; k < 3; ++k) ob->momentum[k] = gran_exactsum_value_(&r1.a[OQ_P0 + k]);
  ob->energy = gran_exactsum_value_(&r1.a[OQ_E]);
  /* pass 2: the temperature about the mean flow; a2's moments of w = u sqrt(n / (n - 1)), u scaled
   * by the power of two 2^-e that puts the largest |component| in [0.5, 1) (gran_srd_observe) */
  const double u[3] = {ob->momentum[0] / (double)N, ob->momentum[1] / (double)N, ob->momentum[2] / (double)N};
  int ex = 0;
  if (r1.umax > 0) std::frexp(r1.umax, &ex);
  const double us = std::ldexp(1.0, -ex);
  ObsRed r2;
  r2.clear();
  cells(r2, [&](ObsRed &R, ObsCells &O, int64_t c, const ObsRec *q, int64_t n) {
    double th = 0;
    for (int64_t i = 0; i < n; ++i) {
      const double *v = q[i].v;
      const double ux = v[0] - u[0], uy = v[1] - u[1], uz = d == 3 ? v[2] - u[2] : 0.0;
      th += ux * ux + uy * uy + uz * uz;
    }
    gran_exactsum_add_(&R.a[OQ_TH], th);
    if (n < 2) return;
    const double nc = (double)n, *V = O.V.data() + 3 * c;
    double m2 = 0, m4 = 0;
    for (int64_t i = 0; i < n; ++i) {
      const double *v = q[i].v;
      const double ux = (v[0] - V[0]) * us, uy = (v[1] - V[1]) * us, uz = (v[2] - V[2]) * us;
      const double w2 = (ux * ux + uy * uy + uz * uz) * nc / (nc - 1.0);
      m2 += w2;
      m4 += w2 * w2;
    }
    gran_exactsum_add_(&R.a[OQ_M2], m2);
    gran_exactsum_add_(&R.a[OQ_M4], m4);
    gran_exactsum_add_(&R.a[OQ_H], (nc * nc - 3.0 * nc + 3.0) / (nc - 1.0)); /* n h(n) */
  });
  GRAN_CALL(all(r2, "temperature and a2"));
  const double dn = (double)d * (double)N;
  ob->temperature = gran_exactsum_value_(&r2.a[OQ_TH]) / dn;
  ob->e_kin = gran_exactsum_value_(&r1.a[OQ_EK]) / (double)N;
  ob->theta_cells = gran_exactsum_value_(&r1.a[OQ_Q]) / dn;
  ob->mach = ob->theta_cells > 0 ? std::sqrt(ob->e_kin / ob->theta_cells) : 0.0;
  { /* the variance of the box cells' counts, exact before its one rounding */
    const double a = C.o->a, vol = d == 3 ? a * a * a : a * a, nb = (double)ncell_box;
    const __int128 num = (__int128)r1.r2 * ncell_box - (__int128)N * N;
    ob->sigma_rho = std::sqrt(std::max(0.0, (double)num / (nb * nb))) / vol;
  }
  {
    const double m2 = gran_exactsum_value_(&r2.a[OQ_M2]), m4 = gran_exactsum_value_(&r2.a[OQ_M4]);
    const double nin = (double)r1.nin, hsum = gran_exactsum_value_(&r2.a[OQ_H]);
    ob->a2 = m2 > 0 ? ((double)d / (d + 2.0) * m4 * nin / (m2 * m2) - 1.0) * nin / hsum : 0.0;
  }
  if (profile) { /* the mean velocity of each layer of y: its cells' momenta summed exactly, over its particles */
    const int64_t L1 = C.o->cells[1];
    auto add_layer = [&](int64_t j, LayerRed &R) { /* layer j's cells of the bricks here into R */
      for (size_t b = 0; b < bs.size(); ++b) {
        const Brick &B = bs[b];
        const int64_t i1 = j - B.lo[1];
        if (i1 < 0 || i1 >= B.w[1]) continue;
        for (int64_t i2 = 0; i2 < B.w[2]; ++i2)
          for (int64_t i0 = 0; i0 < B.w[0]; ++i0) {
            const int64_t l = i0 + B.w[0] * (i1 + B.w[1] * i2), n = oc[b].start[(size_t)l + 1] - oc[b].start[(size_t)l];
            if (n == 0) continue;
            for (int q = 0; q < 3; ++q) gran_exactsum_add_(&R.u[q], oc[b].S[(size_t)(3 * l + q)]);
            R.n += n;
          }
      }
    };
    auto mean = [&](int64_t j, LayerRed &R) {
      for (int q = 0; q < 3; ++q) profile[3 * j + q] = R.n > 0 ? gran_exactsum_value_(&R.u[q]) / (double)R.n : NAN;
    };
    if (!comm) { /* every brick here: one layer at a time (an exact sum is the same however it is grouped) */
      for (int64_t j = 0; j < L1; ++j) {
        LayerRed R;
        R.clear();
        add_layer(j, R);
        mean(j, R);
      }
    } else { /* this process's layers, all-reduced */
      std::vector<LayerRed> lay((size_t)L1);
      for (LayerRed &R : lay) R.clear();
      for (int64_t j = bs[0].lo[1]; j < std::min(L1, bs[0].lo[1] + bs[0].w[1]); ++j) add_layer(j, lay[(size_t)j]);
      GRAN_CHECK(comm->allreduce(comm->ctx, lay.data(), sizeof(LayerRed), lay.size(), &merge_bytes<LayerRed>) == 0,
                 GRAN_ERR_IO, "decomposed GSRD run: the all-reduce of the velocity profile failed on process %d", comm->rank);
      for (int64_t j = 0; j < L1; ++j) mean(j, lay[(size_t)j]);
    }
  }
  return GRAN_SUCCESS;
}

srd_obs_scalars obs_scalars_of(const Ctx &C, const Brick &B, double e_initial, double stress_t0) {
  srd_obs_scalars q;
  q.e_initial = e_initial;
  q.e_coll = B.e_coll;
  q.e_ext = B.e_ext;
  q.flux_kin = B.flux_kin;
  q.flux_coll = B.flux_coll;
  q.stress_t0 = stress_t0;
  q.shear_rate = C.o->shear_rate;
  for (int k = 0; k < 3; ++k) q.box[k] = C.gm.box[k];
  q.dim = C.o->dim;
  q.clamped = B.clamped_obs;
  q.dt_max = B.dt_max_obs;
  return q;
}

}  // namespace

int srd_observe_cells_(gran_srd *s, gran_srd_obs *ob, double *profile) {
  return as_one_brick(s, [&](const Ctx &C, std::vector<Brick> &bs) {
    return obs_sums(C, bs, nullptr, s->ncell_box, ob, profile);
  });
}

int srd_bricks_observe_(srd_bricks_state *st, gran_srd_obs *ob) { return srd_bricks_observe_profile_(st, ob, nullptr); }

int srd_bricks_observe_profile_(srd_bricks_state *st, gran_srd_obs *ob, double *profile) {
  GRAN_TRY {
    GRAN_CHECK_PTR(st);
    GRAN_CHECK_PTR_AS(ob, obs);
    GRAN_CHECK(!profile || !st->over_comm || st->shell->opt.cells[1] <= SRD_BRICKS_PROFILE_MAX_LAYERS, GRAN_ERR_ARG,
               "the velocity profile of a gas split over processes has at most %d layers of y (the box has %lld)",
               SRD_BRICKS_PROFILE_MAX_LAYERS, (long long)st->shell->opt.cells[1]);
    std::memset(ob, 0, sizeof *ob);
    const Brick &B0 = st->bs[0]; /* the scalar state is the same on every brick */
    ob->time = B0.time;
    ob->steps = B0.step;
    ob->n = st->shell->n;
    GRAN_CALL(obs_sums(st->C, st->bs, st->over_comm ? &st->comm : nullptr, st->shell->ncell_box, ob, profile));
    GRAN_CALL(srd_obs_finish_(ob, obs_scalars_of(st->C, B0, st->e0, st->stress_t0)));
    for (Brick &B : st->bs) {
      B.clamped_obs = 0;
      B.dt_max_obs = INFINITY;
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

int srd_bricks_stress_reset_(srd_bricks_state *st) {
  GRAN_CHECK_PTR(st);
  for (Brick &B : st->bs) B.flux_kin = B.flux_coll = 0.0;
  st->stress_t0 = st->bs[0].time;
  return GRAN_SUCCESS;
}

namespace {
srd_bricks_comm g_run_comm; /* srd_bricks_set_run_comm_; size 1: one process */
}  // namespace

void srd_bricks_set_run_comm_(const srd_bricks_comm *comm) { g_run_comm = comm && comm->size > 1 ? *comm : srd_bricks_comm(); }
const srd_bricks_comm *srd_bricks_run_comm_() { return &g_run_comm; }
int64_t srd_bricks_steps_(const srd_bricks_state *st) { return st ? st->bs[0].step : 0; }

/* ---- checkpoint sets: the parts of a split gas (srd_part, srd_impl.h) ---- */
namespace {

/* the scalar state of a part as words (equal across the parts of one set, bit for bit) */
constexpr int kPartWords = 20;
void part_words(const srd_part &p, uint64_t w[kPartWords]) {
  const double d[12] = {p.time,      p.e_initial,  p.e_coll,    p.e_ext,      p.dt_max,          p.dt_max_obs,
                        p.flux_kin,  p.flux_coll,  p.stress_t0, p.wall_impulse[0], p.wall_impulse[1], p.wall_impulse[2]};
  for (int k = 0; k < 12; ++k) w[k] = key_of(d[k]);
  w[12] = (uint64_t)p.step;
  w[13] = (uint64_t)p.clamped;
  w[14] = (uint64_t)p.clamped_obs;
  w[15] = (uint64_t)p.generation;
  for (int k = 0; k < 4; ++k) w[16 + k] = p.shift_rng.s[k];
}

/* the scalars of a part into a brick */
void scalars_from_part(const srd_part &p, Brick &B) {
  B.shift_rng = p.shift_rng;
  B.step = p.step;
  B.time = p.time;
  B.e_coll = p.e_coll;
  B.e_ext = p.e_ext;
  B.flux_kin = p.flux_kin;
  B.flux_coll = p.flux_coll;
  for (int k = 0; k < 3; ++k) B.wall_impulse[k] = p.wall_impulse[k];
  B.clamped = p.clamped;
  B.clamped_obs = p.clamped_obs;
  B.dt_max = p.dt_max;
  B.dt_max_obs = p.dt_max_obs;
}

/* the unshifted cell of a position (as the observation bins it) and its owner */
int owner_unshifted(const Ctx &C, const double p[3]) {
  srd_geom g0 = C.gm;
  g0.le_on = 0;
  const double zero[3] = {0, 0, 0};
  int64_t c[3];
  double dvx;
  srd_bin3(&g0, zero, p, c, &dvx);
  return owner_of(C.sp, c);
}

/* the particles [from) of brick B put in key order (a stable permutation: equal keys, which no run
 * makes, keep their order) */
void sort_by_key(Brick &B) {
  const size_t n = B.x.size();
  std::vector<uint32_t> ord(n);
  std::iota(ord.begin(), ord.end(), 0u);
  std::stable_sort(ord.begin(), ord.end(), [&](uint32_t a, uint32_t b) { return B.key[a] < B.key[b]; });
  auto perm = [&](auto &v) {
    if (v.empty()) return;
    auto w = v;
    for (size_t i = 0; i < n; ++i) w[i] = v[ord[i]];
    v.swap(w);
  };
  perm(B.x), perm(B.y), perm(B.z), perm(B.vx), perm(B.vy), perm(B.vz), perm(B.key);
}

/* over a process group: every process's load status and particle count, and the range of the
 * parts' scalar digests (one all-reduce, so that a process whose part was refused does not leave
 * the others waiting) */
struct LoadTot {
  int64_t bad, n;
  uint64_t hmin, hmax;
  int32_t first_bad;
};
void merge_load(void *io, const void *in) {
  LoadTot &a = *(LoadTot *)io;
  const LoadTot &b = *(const LoadTot *)in;
  if (b.bad && (!a.bad || b.first_bad < a.first_bad)) a.first_bad = b.first_bad;
  a.bad += b.bad;
  a.n += b.n;
  a.hmin = std::min(a.hmin, b.hmin);
  a.hmax = std::max(a.hmax, b.hmax);
}

/* the parts in paths into the bricks of st (their cells, and the particles the bricks keep:
 * own = 1 all of the one part, the brick's own; else those of the unshifted cells of each brick's
 * window); *ref the first part's scalars */
int load_parts(srd_bricks_state *st, const char *const *paths, int nparts, int64_t generation, int64_t step, bool own,
               srd_part *ref) {
  const Ctx &C = st->C;
  const bool d3 = C.o->dim == 3;
  const int64_t nb = C.sp.nbricks();
  std::vector<int> slot((size_t)nb, -1); /* brick rank -> index in st->bs */
  for (size_t b = 0; b < st->bs.size(); ++b) slot[(size_t)st->bs[b].rank] = (int)b;
  std::vector<std::vector<char>> got(st->bs.size());
  for (size_t b = 0; b < st->bs.size(); ++b) {
    Brick &B = st->bs[b];
    B.cell.resize((size_t)B.ncl);
    B.rng.resize((size_t)B.ncl);
    got[b].assign((size_t)B.ncl, 0);
  }
  uint64_t w0[kPartWords] = {0};
  int64_t set_nb = -1;
  std::vector<char> seen;
  for (int q = 0; q < nparts; ++q) {
    const char *path = paths[q];
    GRAN_CHECK_PTR(path);
    srd_part p;
    GRAN_CALL(srd_part_read_(path, st->shell.get(), &p));
    GRAN_CHECK(p.generation == generation && p.step == step, GRAN_ERR_IO,
               "checkpoint part '%s' is of generation %lld at step %lld, and the checkpoint commits generation %lld at "
               "step %lld (a part of another checkpoint)", path, (long long)p.generation, (long long)p.step,
               (long long)generation, (long long)step);
    const int64_t pb = (int64_t)p.pgrid[0] * p.pgrid[1] * p.pgrid[2];
    uint64_t w[kPartWords];
    part_words(p, w);
    if (q == 0) {
      std::memcpy(w0, w, sizeof w0);
      set_nb = pb;
      seen.assign((size_t)pb, 0);
      *ref = p;
      ref->x.clear(), ref->y.clear(), ref->z.clear(), ref->vx.clear(), ref->vy.clear(), ref->vz.clear(), ref->key.clear();
      ref->V.clear(), ref->rng.clear();
    } else {
      GRAN_CHECK(std::memcmp(w0, w, sizeof w0) == 0, GRAN_ERR_IO,
                 "checkpoint part '%s': its scalar state (time, ledger, streams) differs from that of '%s' (the parts "
                 "of one checkpoint hold the same)", path, paths[0]);
      GRAN_CHECK(std::memcmp(p.pgrid, ref->pgrid, sizeof p.pgrid) == 0, GRAN_ERR_IO,
                 "checkpoint part '%s' is of the split %d x %d x %d, '%s' of %d x %d x %d", path, p.pgrid[0], p.pgrid[1],
                 p.pgrid[2], paths[0], ref->pgrid[0], ref->pgrid[1], ref->pgrid[2]);
    }
    GRAN_CHECK(!seen[(size_t)p.brick], GRAN_ERR_IO, "checkpoint part '%s' holds brick %d, as an earlier part does", path,
               p.brick);
    seen[(size_t)p.brick] = 1;
    if (own) {
      GRAN_CHECK(nparts == 1 && pb == nb && std::memcmp(p.pgrid, st->pgrid, sizeof p.pgrid) == 0 &&
                     st->bs.size() == 1 && p.brick == st->bs[0].rank,
                 GRAN_ERR_IO, "checkpoint part '%s' holds brick %d of the split %d x %d x %d, and this process runs brick "
                 "%d of %d x %d x %d", path, p.brick, p.pgrid[0], p.pgrid[1], p.pgrid[2], st->bs[0].rank, st->pgrid[0],
                 st->pgrid[1], st->pgrid[2]);
    }
    /* the part's cells: window of its brick in its own split */
    const int64_t bq[3] = {p.brick % p.pgrid[0], (p.brick / p.pgrid[0]) % p.pgrid[1], p.brick / (p.pgrid[0] * p.pgrid[1])};
    int64_t lo[3], wd[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = srd_brick_cut(bq[a], C.gm.nc[a], p.pgrid[a]);
      wd[a] = srd_brick_cut(bq[a] + 1, C.gm.nc[a], p.pgrid[a]) - lo[a];
    }
    int64_t l = 0;
    for (int64_t k2 = 0; k2 < wd[2]; ++k2)
      for (int64_t k1 = 0; k1 < wd[1]; ++k1)
        for (int64_t k0 = 0; k0 < wd[0]; ++k0, ++l) {
          const int64_t c[3] = {lo[0] + k0, lo[1] + k1, lo[2] + k2};
          const int sb = slot[(size_t)owner_of(C.sp, c)];
          if (sb < 0) continue;
          Brick &B = st->bs[(size_t)sb];
          const uint32_t lc = local_of(B, c);
          for (int k = 0; k < 3; ++k) B.cell[lc].V[k] = p.V[(size_t)(3 * l + k)];
          for (int k = 0; k < 4; ++k) B.rng[lc].s[k] = p.rng[(size_t)(4 * l + k)];
          got[(size_t)sb][lc] = 1;
        }
    /* the particles */
    for (size_t i = 0; i < p.x.size(); ++i) {
      int sb = 0;
      if (!own) {
        const double x[3] = {p.x[i], p.y[i], d3 ? p.z[i] : 0.0};
        sb = slot[(size_t)owner_unshifted(C, x)];
        if (sb < 0) continue;
      }
      Brick &B = st->bs[(size_t)sb];
      B.x.push_back(p.x[i]);
      B.y.push_back(p.y[i]);
      B.vx.push_back(p.vx[i]);
      B.vy.push_back(p.vy[i]);
      if (d3) {
        B.z.push_back(p.z[i]);
        B.vz.push_back(p.vz[i]);
      }
      B.key.push_back(p.key[i]);
    }
    /* what this process keeps never exceeds the gas (parts that hold more are refused here, before
     * the next part is read) */
    int64_t kept = 0;
    for (const Brick &B : st->bs) kept += (int64_t)B.x.size();
    GRAN_CHECK(kept <= st->shell->n, GRAN_ERR_IO,
               "checkpoint part '%s': with it the parts hold %lld particles for this process's bricks, more than the "
               "gas's %lld", path, (long long)kept, (long long)st->shell->n);
  }
  GRAN_CHECK(nparts >= 1, GRAN_ERR_ARG, "argument 'nparts' must be >= 1 (got %d)", nparts);
  GRAN_CHECK(own || nparts == set_nb, GRAN_ERR_IO,
             "checkpoint '%s': %d parts were given, and its split %d x %d x %d has %lld bricks", paths[0], nparts,
             ref->pgrid[0], ref->pgrid[1], ref->pgrid[2], (long long)set_nb);
  for (size_t b = 0; b < st->bs.size(); ++b)
    for (int64_t lc = 0; lc < st->bs[b].ncl; ++lc)
      GRAN_CHECK(got[b][(size_t)lc], GRAN_ERR_IO, "checkpoint '%s': no part holds cell %lld of the grid", paths[0],
                 (long long)global_of(C, st->bs[b], lc));
  for (Brick &B : st->bs) {
    if (nparts > 1) sort_by_key(B);
    scalars_from_part(*ref, B);
  }
  st->e0 = ref->e_initial;
  st->stress_t0 = ref->stress_t0;
  return GRAN_SUCCESS;
}

}  // namespace

int srd_bricks_held_(const srd_bricks_state *st) { return st ? (int)st->bs.size() : 0; }
int srd_bricks_brick_(const srd_bricks_state *st, int i) {
  return st && i >= 0 && i < (int)st->bs.size() ? st->bs[(size_t)i].rank : -1;
}

int srd_bricks_save_(srd_bricks_state *st, const char *const *paths, int64_t generation) {
  GRAN_TRY {
    GRAN_CHECK_PTR(st);
    GRAN_CHECK_PTR(paths);
    GRAN_CHECK(generation >= 1, GRAN_ERR_ARG, "argument 'generation' must be >= 1 (got %lld)", (long long)generation);
    const bool d3 = st->C.o->dim == 3;
    for (size_t b = 0; b < st->bs.size(); ++b) {
      const Brick &B = st->bs[b];
      GRAN_CHECK_PTR(paths[b]);
      srd_part p;
      p.generation = generation;
      for (int k = 0; k < 3; ++k) p.pgrid[k] = st->pgrid[k];
      p.brick = B.rank;
      p.step = B.step;
      p.clamped = B.clamped;
      p.clamped_obs = B.clamped_obs;
      p.time = B.time;
      p.e_initial = st->e0;
      p.e_coll = B.e_coll;
      p.e_ext = B.e_ext;
      p.dt_max = B.dt_max;
      p.dt_max_obs = B.dt_max_obs;
      p.flux_kin = B.flux_kin;
      p.flux_coll = B.flux_coll;
      p.stress_t0 = st->stress_t0;
      for (int k = 0; k < 3; ++k) p.wall_impulse[k] = B.wall_impulse[k];
      p.shift_rng = B.shift_rng;
      /* the particles (holes left out) in key order: the arrivals since the last sort sit out of it */
      std::vector<uint32_t> ord;
      ord.reserve(B.x.size());
      for (size_t i = 0; i < B.x.size(); ++i)
        if (B.dest.empty() || B.dest[i] < 0) ord.push_back((uint32_t)i);
      std::stable_sort(ord.begin(), ord.end(), [&](uint32_t a, uint32_t c) { return B.key[a] < B.key[c]; });
      const size_t m = ord.size();
      for (std::vector<double> *v : {&p.x, &p.y, &p.vx, &p.vy}) v->resize(m);
      if (d3) p.z.resize(m), p.vz.resize(m);
      p.key.resize(m);
      for (size_t i = 0; i < m; ++i) {
        const uint32_t j = ord[i];
        p.x[i] = B.x[j];
        p.y[i] = B.y[j];
        p.vx[i] = B.vx[j];
        p.vy[i] = B.vy[j];
        if (d3) p.z[i] = B.z[j], p.vz[i] = B.vz[j];
        p.key[i] = B.key[j];
      }
      p.V.resize((size_t)(3 * B.ncl));
      p.rng.resize((size_t)(4 * B.ncl));
      for (int64_t l = 0; l < B.ncl; ++l) {
        for (int k = 0; k < 3; ++k) p.V[(size_t)(3 * l + k)] = B.cell[(size_t)l].V[k];
        for (int k = 0; k < 4; ++k) p.rng[(size_t)(4 * l + k)] = B.rng[(size_t)l].s[k];
      }
      GRAN_CALL(srd_part_write_(&st->shell->opt, p, paths[b]));
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

int srd_bricks_load_(const gran_srd_options *opt, const int pgrid[3], const srd_bricks_comm *comm,
                     const char *const *paths, int nparts, int own, int64_t generation, int64_t step,
                     srd_bricks_state **out, int *peer_failed) {
  GRAN_TRY {
    GRAN_CHECK_PTR(out);
    GRAN_CHECK_PTR(paths);
    *out = nullptr;
    if (peer_failed) *peer_failed = 0;
    std::unique_ptr<srd_bricks_state> st;
    GRAN_CALL(open_shell(opt, pgrid, comm, st));
    srd_part ref;
    const int e = load_parts(st.get(), paths, nparts, generation, step, own != 0, &ref);
    const std::string why = e != GRAN_SUCCESS ? gran_last_error_message() : "";
    LoadTot t = {e != GRAN_SUCCESS ? 1 : 0, 0, UINT64_MAX, 0, st->over_comm ? st->comm.rank : 0};
    for (const Brick &B : st->bs) t.n += (int64_t)B.x.size();
    if (e == GRAN_SUCCESS) {
      uint64_t w[kPartWords];
      part_words(ref, w);
      t.hmin = t.hmax = hash_words(w, kPartWords);
    }
    if (st->over_comm)
      GRAN_CHECK(st->comm.allreduce(st->comm.ctx, &t, sizeof t, 1, &merge_load) == 0, GRAN_ERR_IO,
                 "decomposed GSRD run: the all-reduce of the checkpoint's load failed on process %d", st->comm.rank);
    if (e != GRAN_SUCCESS) return GRAN_ERROR(e, "%s", why.c_str());
    if (t.bad && peer_failed) *peer_failed = 1;
    GRAN_CHECK(!t.bad, GRAN_ERR_IO, "checkpoint: process %d of the split gas could not read its part (it says why)",
               (int)t.first_bad);
    GRAN_CHECK(t.hmin == t.hmax, GRAN_ERR_IO,
               "checkpoint '%s': the parts' scalar states (time, ledger, streams) differ between processes (the parts of "
               "one checkpoint hold the same)", paths[0]);
    GRAN_CHECK(t.n == st->shell->n, GRAN_ERR_IO, "checkpoint '%s': its parts hold %lld particles, and the gas has %lld",
               paths[0], (long long)t.n, (long long)st->shell->n);
    *out = st.release();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

int srd_bricks_from_state_(const gran_srd *s, const int pgrid[3], const srd_bricks_comm *comm, srd_bricks_state **out) {
  GRAN_TRY {
    GRAN_CHECK_PTR(s);
    GRAN_CHECK_PTR(out);
    *out = nullptr;
    std::unique_ptr<srd_bricks_state> st;
    GRAN_CALL(open_shell(&s->opt, pgrid, comm, st));
    const Ctx &C = st->C;
    const bool d3 = s->opt.dim == 3;
    const int64_t nb = C.sp.nbricks();
    std::vector<int> slot((size_t)nb, -1);
    for (size_t b = 0; b < st->bs.size(); ++b) slot[(size_t)st->bs[b].rank] = (int)b;
    for (Brick &B : st->bs) {
      B.cell.resize((size_t)B.ncl);
      B.rng.resize((size_t)B.ncl);
      for (int64_t l = 0; l < B.ncl; ++l) {
        const int64_t gc = global_of(C, B, l);
        B.cell[(size_t)l] = s->cell[(size_t)gc];
        B.rng[(size_t)l] = s->rng[(size_t)gc];
      }
      scalars_from(s, B);
    }
    /* the arrays are in key order: the key of a particle is its index */
    for (int64_t i = 0; i < s->n; ++i) {
      const double x[3] = {s->x[(size_t)i], s->y[(size_t)i], d3 ? s->z[(size_t)i] : 0.0};
      const int sb = slot[(size_t)owner_unshifted(C, x)];
      if (sb < 0) continue;
      Brick &B = st->bs[(size_t)sb];
      B.x.push_back(s->x[(size_t)i]);
      B.y.push_back(s->y[(size_t)i]);
      B.vx.push_back(s->vx[(size_t)i]);
      B.vy.push_back(s->vy[(size_t)i]);
      if (d3) {
        B.z.push_back(s->z[(size_t)i]);
        B.vz.push_back(s->vz[(size_t)i]);
      }
      B.key.push_back((uint64_t)i);
    }
    st->e0 = s->e_initial;
    st->stress_t0 = s->stress_t0;
    *out = st.release();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

int srd_state_from_parts_(const gran_srd_options *opt, const char *const *paths, int nparts, int64_t generation,
                          int64_t step, gran_srd **out) {
  GRAN_TRY {
    GRAN_CHECK_PTR(out);
    GRAN_CHECK_PTR(paths);
    *out = nullptr;
    /* the parts loaded as the bricks of a split of one brick in this process: its cells the whole
     * grid, its particles every part's in key order */
    const int one[3] = {1, 1, 1};
    std::unique_ptr<srd_bricks_state> st;
    GRAN_CALL(open_shell(opt, one, nullptr, st));
    srd_part ref;
    GRAN_CALL(load_parts(st.get(), paths, nparts, generation, step, false, &ref));
    Brick &B = st->bs[0];
    GRAN_CHECK((int64_t)B.x.size() == st->shell->n, GRAN_ERR_IO,
               "checkpoint '%s': its parts hold %lld particles, and the gas has %lld", paths[0], (long long)B.x.size(),
               (long long)st->shell->n);
    std::unique_ptr<gran_srd> s(new gran_srd);
    s->opt = *opt;
    GRAN_CALL(srd_alloc_state_(s.get()));
    s->x.swap(B.x);
    s->y.swap(B.y);
    s->z.swap(B.z);
    s->vx.swap(B.vx);
    s->vy.swap(B.vy);
    s->vz.swap(B.vz);
    for (int64_t c = 0; c < s->ncell; ++c) {
      s->cell[(size_t)c] = B.cell[(size_t)c];
      s->rng[(size_t)c] = B.rng[(size_t)c];
    }
    scalars_to(B, s.get());
    s->clamped = B.clamped_obs; /* the plain engine counts the clamps since its last observation */
    s->dt_max = B.dt_max_obs;
    s->e_initial = st->e0;
    s->stress_t0 = st->stress_t0;
    GRAN_CALL(srd_state_check_(paths[0], s.get()));
    *out = s.release();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/* ---- field snapshots of a split gas ---- */
namespace {
/* gran_srd_fields of the gas in bs (comm: one brick per process, the fields gathered on the group's
 * first process; NULL: every brick here): each box cell's count, mean velocity and temperature
 * sum |v - V|^2 / (d n) over its particles in key order (0 for an empty cell); any output NULL */
int fields_of(const Ctx &C, std::vector<Brick> &bs, const srd_bricks_comm *comm, double *count, double *velocity,
              double *temperature) {
  std::vector<ObsCells> oc;
  GRAN_CALL(obs_collect(C, bs, comm, oc));
  const int d = C.o->dim;
  const int64_t L0 = C.gm.L[0], L1 = C.gm.L[1], L2 = d == 3 ? C.gm.L[2] : 1, nbox = L0 * L1 * L2;
  /* each non-empty box cell of this process's windows: its index, count, mean velocity and
   * temperature (over processes, the records of the message to the group's first process) */
  std::vector<double> rec;
  for (size_t b = 0; b < bs.size(); ++b) {
    const Brick &B = bs[b];
    const ObsCells &O = oc[b];
    for (int64_t l = 0; l < B.ncl; ++l) {
      const int64_t n = O.start[(size_t)l + 1] - O.start[(size_t)l];
      if (n == 0) continue;
      int64_t i[3] = {B.lo[0] + l % B.w[0], B.lo[1] + (l / B.w[0]) % B.w[1], B.lo[2] + l / (B.w[0] * B.w[1])};
      /* the wall axis's extra layer holds a particle only on the upper wall itself: the last layer's */
      const int w = C.o->wall_axis;
      if (w >= 0 && i[w] >= C.gm.L[w]) i[w] = C.gm.L[w] - 1;
      const int64_t i0 = i[0], i1 = i[1], i2 = i[2];
      CellMoments m;
      cell_moments(O.rec.data() + O.start[(size_t)l], n, m);
      const double rw[kFieldWords] = {(double)(i0 + L0 * (i1 + L1 * i2)), (double)n, m.V[0], m.V[1], m.V[2],
                                     m.Q / ((double)d * (double)n)};
      rec.insert(rec.end(), rw, rw + kFieldWords);
    }
  }
  std::vector<std::vector<double>> got;
  if (comm) {
    std::vector<std::vector<double>> out((size_t)comm->size);
    got.resize((size_t)comm->size);
    if (comm->rank != 0) out[0].swap(rec);
    GRAN_CHECK(comm->round(comm->ctx, out, got) == 0, GRAN_ERR_IO,
               "decomposed GSRD run: the gather of the cell fields failed on process %d", comm->rank);
    if (comm->rank != 0) return GRAN_SUCCESS;
  }
  if (count) std::memset(count, 0, sizeof(double) * (size_t)nbox);
  if (velocity) std::memset(velocity, 0, sizeof(double) * 3 * (size_t)nbox);
  if (temperature) std::memset(temperature, 0, sizeof(double) * (size_t)nbox);
  got.push_back(std::move(rec));
  /* the cells written so far and their moments (only a wall's last layer is written twice) */
  const bool wall = C.o->wall_axis >= 0;
  std::vector<char> seen(wall ? (size_t)nbox : 0);
  std::vector<double> seen_n(seen.size()), seen_T(seen.size()), seen_V(3 * seen.size());
  for (size_t p = 0; p < got.size(); ++p) {
    const std::vector<double> &g = got[p];
    GRAN_CHECK(g.size() % kFieldWords == 0, GRAN_ERR_IO, "cell fields: process %zu sent a cut message", p);
    for (size_t j = 0; j < g.size(); j += kFieldWords) {
      const double x = g[j];
      GRAN_CHECK(x >= 0 && x < (double)nbox && x == std::floor(x), GRAN_ERR_IO,
                 "cell fields: process %zu sent cell %g, outside the box", p, x);
      const size_t c = (size_t)x;
      double n = g[j + 1], V[3] = {g[j + 2], g[j + 3], g[j + 4]}, T = g[j + 5];
      if (wall && seen[c]) { /* a last layer and particles on the upper wall: the two records' moments combined */
        const double n1 = seen_n[c], n2 = n, nn = n1 + n2;
        double Q = (seen_T[c] * n1 + T * n2) * (double)d;
        for (int k = 0; k < 3; ++k) {
          const double Vk = (n1 * seen_V[3 * c + (size_t)k] + n2 * V[k]) / nn, a = seen_V[3 * c + (size_t)k] - Vk,
                       b = V[k] - Vk;
          Q += n1 * a * a + n2 * b * b;
          V[k] = Vk;
        }
        n = nn;
        T = Q / ((double)d * nn);
      }
      if (wall) {
        seen[c] = 1;
        seen_n[c] = n;
        seen_T[c] = T;
        for (int k = 0; k < 3; ++k) seen_V[3 * c + (size_t)k] = V[k];
      }
      if (count) count[c] = n;
      if (velocity)
        for (int k = 0; k < 3; ++k) velocity[3 * c + (size_t)k] = V[k];
      if (temperature) temperature[c] = T;
    }
  }
  return GRAN_SUCCESS;
}
}  // namespace

int srd_bricks_fields_(srd_bricks_state *st, double *count, double *velocity, double *temperature) {
  GRAN_TRY {
    GRAN_CHECK_PTR(st);
    return fields_of(st->C, st->bs, st->over_comm ? &st->comm : nullptr, count, velocity, temperature);
  }
  GRAN_CATCH
}

int srd_fields_cells_(gran_srd *s, double *count, double *velocity, double *temperature) {
  GRAN_TRY {
    return as_one_brick(s, [&](const Ctx &C, std::vector<Brick> &bs) {
      return fields_of(C, bs, nullptr, count, velocity, temperature);
    });
  }
  GRAN_CATCH
}
