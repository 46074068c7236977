/* fuzz_common.h - what the engine harnesses (fuzz_run_scene, fuzz_checkpoint, fuzz_options)
 * share: a reader of the fuzz bytes that favours edge values, the status check every call gets,
 * a private scratch folder, and a scan of an HDF5 file for non-finite values. Everything is a
 * function of the input bytes alone (no clock, no time-dependent seed), so an input replays. */
#ifndef GRANARY_FUZZ_COMMON_H
#define GRANARY_FUZZ_COMMON_H

#include <dirent.h>
#include <hdf5.h>
#include <omp.h>
#include <unistd.h>

#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "granary.h"

namespace fz {

/* A finding: what broke, on stderr, then abort() (libFuzzer saves the input as a crash). */
[[noreturn]] inline void fail(const char *what, const char *detail) {
  std::fprintf(stderr, "FUZZ FINDING: %s%s%s\n", what, detail && detail[0] ? ": " : "", detail ? detail : "");
  std::fflush(stderr);
  std::abort();
}

/* Every status a call returns: a listed code, and a non-empty message when it is an error. */
inline int check(int st, const char *call) {
  switch (st) {
#define FZ_CASE_(name, value, msg) case value:
    GRAN_ERROR_LIST(FZ_CASE_)
#undef FZ_CASE_
    break;
  default: {
    char b[160];
    std::snprintf(b, sizeof b, "%s returned %d, not a GRAN_ERR_* code", call, st);
    fail("status out of range", b);
  }
  }
  if (st != GRAN_SUCCESS && gran_last_error_message()[0] == '\0') fail("error without a message", call);
  static const bool verbose = getenv("GRAN_FUZZ_VERBOSE") != nullptr; /* what each call returned */
  if (verbose) std::fprintf(stderr, "fuzz: %s -> %d %s\n", call, st, st ? gran_last_error_message() : "");
  return st;
}

inline void finite_or_fail(double x, const char *what) {
  if (!std::isfinite(x)) {
    char b[200];
    std::snprintf(b, sizeof b, "%s = %g", what, x);
    fail("non-finite result returned with GRAN_SUCCESS", b);
  }
}

/* Edge values for doubles and integers: the table a harness draws from when a byte asks for it. */
static const double kDoubles[] = {NAN, INFINITY, -INFINITY, 0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 3.0, 10.0, 1e300, -1e300,
                                  1e-300, 5e-324, DBL_MAX, -DBL_MAX, DBL_MIN, 1e154, 1e-154, 1e32, 1e60, 1e-9, 1e9,
                                  1e15, 1e20, 9.3e18, 9007199254740992.0, 0.999999999, 1.000000001, 1e-30, 1e30,
                                  180.0, 1e266, -1e-300, 0.1};
static const int64_t kInts[] = {0, 1, -1, 2, 3, 4, 7, 8, 64, 255, 256, 4096, 1000000, (int64_t)1 << 20,
                                ((int64_t)1 << 20) + 1, (int64_t)1 << 31, INT32_MAX, INT32_MIN, INT64_MAX, INT64_MIN,
                                (int64_t)1 << 53, (int64_t)9200000000000000000LL, -2};

/* The fuzz bytes as a stream; past the end every read is 0 (so short inputs keep the defaults). */
struct Bytes {
  const uint8_t *p;
  size_t n, at = 0;
  Bytes(const uint8_t *d, size_t s) : p(d), n(s) {}
  uint8_t u8() { return at < n ? p[at++] : 0; }
  uint16_t u16() { return (uint16_t)(u8() | (u8() << 8)); }
  uint64_t u64() {
    uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v |= (uint64_t)u8() << (8 * k);
    return v;
  }
  double raw_double() {
    uint64_t v = u64();
    double d;
    std::memcpy(&d, &v, 8);
    return d;
  }
  /* half the draws from the values that break arithmetic most often, half from the whole table */
  double edge_double() {
    static const double potent[] = {NAN, INFINITY, -INFINITY, 1e300, -1e300, 1e266, 5e-324, -0.0, DBL_MAX, 1e-300};
    const uint8_t c = u8();
    return c & 1 ? potent[(c >> 1) % (sizeof potent / sizeof potent[0])] : kDoubles[(c >> 1) % (sizeof kDoubles / sizeof kDoubles[0])];
  }
  int64_t edge_int() { return kInts[u8() % (sizeof kInts / sizeof kInts[0])]; }
  /* a double field: mostly its default (so that engines get created and stepped), else an edge
   * value, the default scaled by a power of two, or raw bits */
  double dbl(double def) {
    const uint8_t c = u8();
    if (c < 120) return def;
    if (c < 200) return edge_double();
    if (c < 240) return std::ldexp(def == 0 ? 1.0 : def, (int8_t)u8() / 2);
    return raw_double();
  }
  int64_t i64(int64_t def, int64_t lo, int64_t hi) {
    const uint8_t c = u8();
    if (c < 120) return def;
    if (c < 200) return edge_int();
    if (c < 240) return lo + (int64_t)(u16() % (uint64_t)(hi - lo + 1));
    return (int64_t)u64();
  }
  int32_t i32(int32_t def, int32_t lo, int32_t hi) {
    const int64_t v = i64(def, lo, hi);
    return (int32_t)(v > INT32_MAX || v < INT32_MIN ? (uint32_t)v : v);
  }
};

/* The numbers of a TOML text outside strings and comments, as [start, end) byte ranges. */
inline std::vector<std::pair<size_t, size_t>> toml_numbers(const char *t, size_t n) {
  std::vector<std::pair<size_t, size_t>> r;
  bool str = false, comment = false;
  auto alnum = [](char c) { return std::isalnum((unsigned char)c) || c == '_'; };
  for (size_t i = 0; i < n;) {
    const char c = t[i];
    if (c == '\n') comment = false;
    if (comment) {
      ++i;
      continue;
    }
    if (c == '"') str = !str;
    if (!str && c == '#') comment = true;
    const bool starts = !str && !comment && (std::isdigit((unsigned char)c) || ((c == '-' || c == '+' || c == '.') &&
                                                                              i + 1 < n && std::isdigit((unsigned char)t[i + 1])));
    if (starts && !(i > 0 && (alnum(t[i - 1]) || t[i - 1] == '.'))) {
      size_t j = i + 1;
      while (j < n && (alnum(t[j]) || std::strchr(".+-", t[j]))) ++j;
      r.push_back({i, j});
      i = j;
    } else {
      ++i;
    }
  }
  return r;
}
/* Edge values in TOML spelling (floats and integers) */
static const char *const kTomlValues[] = {"nan", "inf", "-inf", "0", "-0.0", "1e300", "-1e300", "1e-300", "5e-324",
                                          "1.7976931348623157e308", "9223372036854775807", "-9223372036854775808",
                                          "2", "1", "-1", "3", "4", "1e15", "1e20", "0.5", "1e-9", "1e154", "1e-154",
                                          "1e32", "1e33", "1e60", "1.0000001", "4096", "1000000", "1e9", "0.999",
                                          "180", "1e-30", "1e30", "65536", "2147483648"};
inline const char *toml_edge(unsigned k) { return kTomlValues[k % (sizeof kTomlValues / sizeof kTomlValues[0])]; }

/* One scratch folder per process; emptied after every input. */
inline const std::string &scratch() {
  static std::string dir;
  if (dir.empty()) {
    char t[] = "/tmp/granary-fuzz-XXXXXX";
    if (!mkdtemp(t)) fail("mkdtemp failed", t);
    dir = t;
  }
  return dir;
}
inline void clean_scratch() {
  DIR *d = opendir(scratch().c_str());
  if (!d) return;
  std::vector<std::string> names;
  while (struct dirent *e = readdir(d))
    if (std::strcmp(e->d_name, ".") && std::strcmp(e->d_name, "..")) names.push_back(e->d_name);
  closedir(d);
  for (const std::string &n : names) std::remove((scratch() + "/" + n).c_str());
}

/* Work bound for the process: one OpenMP thread and one replica thread (2 shared cores; the
 * result does not depend on the thread count), HDF5 quiet. Call once per input (cheap). */
inline void setup() {
  static bool done = false;
  if (done) return;
  done = true;
  setenv("OMP_NUM_THREADS", "1", 1);
  omp_set_num_threads(1);
  gran_set_threads(1);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  (void)scratch();
}

/* Every floating-point dataset of an HDF5 file (groups walked in name order) must be finite:
 * a run that returns GRAN_SUCCESS may not have written inf or NaN. Datasets up to 4M values. */
struct ScanCtx {
  std::string bad;
};
inline herr_t scan_one(hid_t loc, const char *name, const H5O_info_t *info, void *op) {
  ScanCtx *c = (ScanCtx *)op;
  if (info->type != H5O_TYPE_DATASET || !c->bad.empty()) return 0;
  hid_t ds = H5Dopen2(loc, name, H5P_DEFAULT);
  if (ds < 0) return 0;
  hid_t ty = H5Dget_type(ds), sp = H5Dget_space(ds);
  const hssize_t np = sp >= 0 ? H5Sget_simple_extent_npoints(sp) : -1;
  if (ty >= 0 && H5Tget_class(ty) == H5T_FLOAT && np > 0 && np <= (hssize_t)1 << 22) {
    std::vector<double> v((size_t)np);
    if (H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0)
      for (size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i]) && !(v[i] > 0 && std::strstr(name, "dt_max"))) {
          char b[64];
          std::snprintf(b, sizeof b, "[%zu] = %g", i, v[i]);
          c->bad = std::string(name) + b;
          break;
        }
  }
  if (sp >= 0) H5Sclose(sp);
  if (ty >= 0) H5Tclose(ty);
  H5Dclose(ds);
  return 0;
}
/* "" when every value is finite (or the file does not exist), else the first bad dataset. The one
 * non-finite value a run may write: dt_max = +inf ("no clamp happened", gran_srd_obs). */
inline std::string scan_h5(const std::string &path) {
  if (access(path.c_str(), R_OK) != 0) return "";
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) fail("an output file written with GRAN_SUCCESS is not HDF5", path.c_str());
  ScanCtx c;
  H5Ovisit(f, H5_INDEX_NAME, H5_ITER_INC, scan_one, &c); /* the HDF5 1.10 API (Debian 12) */
  H5Fclose(f);
  return c.bad;
}

/* GRAN_FUZZ_ALLOW_NONFINITE=1 in the environment: a non-finite value in an output file is printed
 * (once per dataset) instead of aborting, so that a run on a library that still writes them goes on
 * to look for crashes and hangs. Default: it is a finding. */
inline void output_nonfinite(const std::string &bad) {
  if (bad.empty()) return;
  static const bool allow = getenv("GRAN_FUZZ_ALLOW_NONFINITE") && !std::strcmp(getenv("GRAN_FUZZ_ALLOW_NONFINITE"), "1");
  if (!allow) fail("non-finite value in the output of a run that returned GRAN_SUCCESS", bad.c_str());
  static std::vector<std::string> seen;
  const std::string ds = bad.substr(0, bad.find('['));
  for (const std::string &x : seen)
    if (x == ds) return;
  seen.push_back(ds);
  std::fprintf(stderr, "FUZZ NOTE (allowed by GRAN_FUZZ_ALLOW_NONFINITE): non-finite output value %s\n", bad.c_str());
}

}  // namespace fz

#endif
