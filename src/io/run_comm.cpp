/* run_comm.cpp - the collective steps of a run over processes (run_comm.h): parts gathered to rank
 * 0, its verdict broadcast back, and the rows of each output time exchanged. With one process every
 * step is local. */
#include <cstring>

#include "io/run_impl.h"

namespace gran_run {

namespace {

void put_i64(std::string &s, int64_t v) { s.append(reinterpret_cast<const char *>(&v), sizeof v); }
bool get_i64(const std::string &s, size_t &at, int64_t *v) {
  if (at + sizeof *v > s.size()) return false;
  std::memcpy(v, s.data() + at, sizeof *v);
  at += sizeof *v;
  return true;
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

/* Rank 0: rows i of the replicas of process p (k = p, p + P, ...; split: its group's) from its payload. */
int unpack_rows(Run &r, int64_t i, size_t p, const std::string &b) {
  size_t at = 0;
  for (int64_t k : r.rows_of((int)p))
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

}  // namespace

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

/* Collective: statuses and events of every rank (rows i with them when i >= 0) to rank 0, which
 * files the rows and sums the events into r.events_all; v gets the first failure. */
int exchange(Run &r, int st, int64_t i, Verdict *v) {
  int64_t ev = 0;
  /* a split gas: the group's first process sends its replica's rows and events (the others hold the same) */
  const bool member = r.split && r.comm.rank % r.bricks != 0;
  if (st == GRAN_SUCCESS && !member) st = local_events(r, &ev);
  std::string rows;
  if (st == GRAN_SUCCESS && i >= 0 && !r.root() && !member) rows = pack_rows(r, i);
  std::vector<Part> parts;
  GRAN_CALL(gather_parts(r, st, ev, std::move(rows), &parts));
  if (!r.root()) return GRAN_SUCCESS;
  first_failure(r, parts, v);
  if (v->st) return GRAN_SUCCESS;
  r.events_all = 0;
  for (size_t p = 0; p < parts.size(); p++) {
    r.events_all += parts[p].events;
    if (p > 0 && i >= 0 && !r.rows_of((int)p).empty() && (st = unpack_rows(r, i, p, parts[p].payload)) != GRAN_SUCCESS) {
      v->st = st;
      v->msg = gran_last_error_message();
      return GRAN_SUCCESS;
    }
  }
  return GRAN_SUCCESS;
}

}  // namespace gran_run
