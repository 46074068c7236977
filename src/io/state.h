/* state.h - the engines' state files: named scalars, attributes and typed arrays in an HDF5 group
 * with a format version, behind one small interface implemented once (src/io/state.cpp). Engines
 * write and read their checkpoints through it and never include <hdf5.h>.
 *
 * A state file is built in memory and committed whole: PATH.tmp with granary's checksum header
 * (length and CRC-32 of the file), fsync, rename over PATH, fsync of the folder (gran_h5 in
 * h5.cpp). A read verifies that header before HDF5 parses a byte. Every failure is a granary
 * status with a message naming the file and the field; HDF5's own error printing is silenced.
 *
 * Write:  gran_state::File f; f.open_update(path);  gran_state::Group g; g.create(f.id(), "/sim",
 *         "granary-x-state 1", path); g.put("v", n, v); ...; f.commit("checkpoint");
 * Read:   f.open_read(path, "checkpoint"); g.open(f.id(), "/sim", path); g.format(&fmt);
 *         g.get("v", n, v) (exactly n values, else refused naming the field); g.npoints("v") first
 *         to size what a file asks for. */
#ifndef GRANARY_IO_STATE_H
#define GRANARY_IO_STATE_H

#include <cstdint>
#include <string>

namespace gran_state {

class File {
 public:
  File() = default;
  ~File();
  File(const File &) = delete;
  File &operator=(const File &) = delete;
  /* for writing: an existing PATH (an HDF5 file) is read whole into memory, else a new file */
  int open_update(const char *path);
  /* for reading: PATH must be a regular file; granary's checksum header is verified first (a file
   * without one is refused with `require_checksum`, else read as it is: files of other writers);
   * `what` names the file in messages ("checkpoint") */
  int open_read(const char *path, const char *what, bool require_checksum = false);
  /* write the file (opened with open_update) to PATH atomically; closes it */
  int commit(const char *what);
  int64_t id() const { return id_; }
  const char *path() const { return path_.c_str(); }

 private:
  int64_t id_ = -1;
  bool memory_ = false;
  std::string path_;
};

class Group {
 public:
  Group() = default;
  ~Group();
  Group(const Group &) = delete;
  Group &operator=(const Group &) = delete;
  /* write: group `name` below `loc` (a file or group id), intermediate groups created, an existing
   * one of that name replaced; attribute 'format' = `format` (fixed-length ASCII) */
  int create(int64_t loc, const char *name, const char *format, const char *path);
  /* read: open group `name` below `loc` (refused naming the group when it is missing) */
  int open(int64_t loc, const char *name, const char *path);
  /* the 'format' attribute ("" when the group has none) */
  int format(std::string *fmt) const;
  int64_t id() const { return id_; }
  const char *path() const { return path_; }

  /* a dataset or group `name` exists in this group */
  bool has(const char *name) const;
  /* values of dataset `name`; -1 when it is missing or holds less data than it declares */
  int64_t npoints(const char *name) const;

  /* typed 1-D arrays of n values */
  int put(const char *name, int64_t n, const double *x) const;
  int put(const char *name, int64_t n, const int64_t *x) const;
  int put(const char *name, int64_t n, const int32_t *x) const;
  int put(const char *name, int64_t n, const uint64_t *x) const;
  /* exactly n values, else GRAN_ERR_IO naming the field and both counts */
  int get(const char *name, int64_t n, double *x) const;
  int get(const char *name, int64_t n, int64_t *x) const;
  int get(const char *name, int64_t n, int32_t *x) const;
  int get(const char *name, int64_t n, uint64_t *x) const;
  /* named scalars (arrays of one value) */
  int put1(const char *name, double x) const { return put(name, 1, &x); }
  int put1(const char *name, int64_t x) const { return put(name, 1, &x); }
  int get1(const char *name, double *x) const { return get(name, 1, x); }
  int get1(const char *name, int64_t *x) const { return get(name, 1, x); }

  /* scalar attributes of the group (strings: variable-length UTF-8) */
  bool has_attr(const char *name) const;
  int attr_put(const char *name, const std::string &v) const;
  int attr_put(const char *name, double v) const;
  int attr_put(const char *name, int64_t v) const;
  int attr_get(const char *name, std::string *v) const;
  int attr_get(const char *name, double *v) const;
  int attr_get(const char *name, int64_t *v) const;

 private:
  int64_t id_ = -1;
  const char *path_ = "";
};

/* ---- checks every engine's reader shares ----
 * A xoshiro256 state (4 words) a generator reached has 128 +- 8 of its 256 bits set; fewer than 32
 * or more than 224 (odds below 1e-30) is an edited state, zero the generator's forbidden one. */
inline int rng_bits(uint64_t a, uint64_t b, uint64_t c, uint64_t d) {
  return __builtin_popcountll(a) + __builtin_popcountll(b) + __builtin_popcountll(c) + __builtin_popcountll(d);
}
inline bool rng_plausible(uint64_t a, uint64_t b, uint64_t c, uint64_t d) {
  const int n = rng_bits(a, b, c, d);
  return n >= 32 && n <= 224;
}

}  // namespace gran_state

#endif
