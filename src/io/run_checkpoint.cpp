/* run_checkpoint.cpp - checkpoints: rank 0 writes one file with the engine state of every replica
 * (the other ranks send theirs as in-memory HDF5 images) and the recorded rows; resume reads it
 * back, from disk with one process, from the bytes rank 0 broadcast with more. */
#include <hdf5.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unistd.h>

#include "io/run_impl.h"

namespace gran_run {

namespace {

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

/* Checkpoint groups of replica k: /engine and /observer for replica 0 (a run without replicas
 * writes exactly these), /replicas/k/engine and /replicas/k/observer for the others. */
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
      const std::vector<int64_t> ks = r.rows_of((int)p); /* split: a group's first process sends its group's */
      if (ks.empty()) continue;                          /* idle processes */
      H5File src;
      src.id = open_image(parts[p].payload);
      GRAN_CHECK(src.id >= 0, GRAN_ERR_IO, "checkpoint '%s': cannot read the engine states of process %zu", file, p);
      hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
      H5Pset_create_intermediate_group(lcpl, 1);
      herr_t e = 0;
      int64_t bad = -1;
      for (int64_t k : ks) {
        e = H5Ocopy((hid_t)src.id, engine_group(k).c_str(), (hid_t)f.id, engine_group(k).c_str(), H5P_DEFAULT, lcpl);
        if (e < 0) {
          bad = k;
          break;
        }
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

}  // namespace

std::string engine_group(int64_t k) { return k == 0 ? "/engine" : "/replicas/" + std::to_string(k) + "/engine"; }

/* Collective: every rank's engine states into the one checkpoint file rank 0 writes. A split gas's
 * processes each write their part file first (checkpoint_write), and the group's first process
 * sends the group's engine group; rank 0's checkpoint commits the set; then every engine settles
 * its parts (the set before goes, or, when the checkpoint failed, the parts just written). */
int write_checkpoint(Run &r) {
  std::string img;
  int st = GRAN_SUCCESS;
  if (!r.root() && !r.mine.empty()) {
    st = engine_image(r, &img);
    if (r.rows_of(r.comm.rank).empty()) img.clear(); /* a split gas: its group's first process sends it */
  }
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
  st = share_verdict(r, &v);
  for (int64_t k : r.mine) r.reps[(size_t)k].eng->checkpoint_settled(st == GRAN_SUCCESS);
  return st;
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

}  // namespace gran_run
