/* io_test_util.h - helpers for the io tests (t6xx): a private temporary folder, writing small
 * files, and comparing two HDF5 files dataset by dataset, bit for bit. */
#ifndef GRANARY_IO_TEST_UTIL_H
#define GRANARY_IO_TEST_UTIL_H
#define _XOPEN_SOURCE 700
#define _DEFAULT_SOURCE
#include <ctype.h>
#include <dirent.h>
#include <sys/wait.h>
#include <ftw.h>
#include <sys/stat.h>
#include <unistd.h>

#include <hdf5.h>
#include <zlib.h>

#include "granary_test.h"

static char io_tmpdir[256];

/* Creates /tmp/granary-NAME-XXXXXX once per test program; removed by io_tmp_cleanup. */
static inline const char *io_tmp(const char *name) {
  if (!io_tmpdir[0]) {
    snprintf(io_tmpdir, sizeof io_tmpdir, "/tmp/granary-%s-XXXXXX", name);
    if (!mkdtemp(io_tmpdir)) {
      fprintf(stderr, "mkdtemp failed\n");
      exit(1);
    }
  }
  return io_tmpdir;
}

static inline int io_rm_cb(const char *p, const struct stat *sb, int flag, struct FTW *ftw) {
  (void)sb, (void)flag, (void)ftw;
  return remove(p);
}
static inline void io_tmp_cleanup(void) {
  if (io_tmpdir[0] && !getenv("GRAN_KEEP_TMP")) nftw(io_tmpdir, io_rm_cb, 16, FTW_DEPTH | FTW_PHYS);
}

/* path inside the temporary folder (static ring of buffers); a test that did not call io_tmp
 * first gets one named "test" (never a path in "/") */
static inline const char *io_path(const char *leaf) {
  static char buf[8][512];
  static int i = 0;
  i = (i + 1) % 8;
  snprintf(buf[i], sizeof buf[i], "%s/%s", io_tmp("test"), leaf);
  return buf[i];
}

static inline void io_write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

static inline int io_exists(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0;
}

static inline char *io_read_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *s = malloc((size_t)n + 1);
  size_t got = fread(s, 1, (size_t)n, f);
  s[got] = '\0';
  fclose(f);
  return s;
}

/* ---- whole files as bytes (damaged-file tests) ---------------------------------------------- */
static inline unsigned char *io_read_all(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  fseek(f, 0, SEEK_END);
  *n = (size_t)ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *b = (unsigned char *)malloc(*n);
  assert_non_null(b);
  assert_int_equal(fread(b, 1, *n, f), *n);
  fclose(f);
  return b;
}
static inline void io_write_all(const char *path, const unsigned char *b, size_t n) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(b, 1, n, f), n);
  fclose(f);
}
/* Rewrite the 512-byte header of a granary file (src/io/h5.cpp: length and CRC-32 of the HDF5
 * image after it) for its current contents: an edit made through HDF5 then passes the checksum,
 * so the value checks behind it are what a test sees. */
static inline void io_refresh_crc(const char *path) {
  size_t n = 0;
  unsigned char *b = io_read_all(path, &n);
  uLong c = crc32(crc32(0L, Z_NULL, 0), b + 512, (uInt)(n - 512));
  char head[512];
  memset(head, 0, sizeof head);
  snprintf(head, sizeof head, "granary-file 1\nlength %zu\ncrc32 %08lx\n", n, (unsigned long)c);
  memcpy(b, head, 512);
  io_write_all(path, b, n);
  free(b);
}

/* Copy granary file `src` to `dst` and open the copy for writing (the edit helpers below; the
 * caller closes it and calls io_refresh_crc). */
static inline hid_t io_copy_open(const char *src, const char *dst) {
  size_t n = 0;
  unsigned char *b = io_read_all(src, &n);
  io_write_all(dst, b, n);
  free(b);
  hid_t f = H5Fopen(dst, H5F_ACC_RDWR, H5P_DEFAULT);
  assert_true(f >= 0);
  return f;
}

/* Copy granary file `src` to `dst` and set dataset[index] = value (int64 when is_int, else double)
 * through HDF5, checksum recomputed: a deliberate edit, which a reader must catch from the values. */
static inline void io_edit_copy(const char *src, const char *dst, const char *dataset, int64_t index, double value,
                                int is_int) {
  hid_t f = io_copy_open(src, dst);
  hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  const hssize_t np = H5Sget_simple_extent_npoints(sp);
  assert_true(index >= 0 && index < (int64_t)np);
  if (is_int) {
    int64_t *v = (int64_t *)malloc((size_t)np * sizeof *v);
    assert_true(H5Dread(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    v[index] = (int64_t)value;
    assert_true(H5Dwrite(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    free(v);
  } else {
    double *v = (double *)malloc((size_t)np * sizeof *v);
    assert_true(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    v[index] = value;
    assert_true(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    free(v);
  }
  H5Sclose(sp);
  H5Dclose(d);
  H5Fclose(f);
  io_refresh_crc(dst);
}

/* Copy granary file `src` to `dst` and write `count` values (memory type `mt`, e.g.
 * H5T_NATIVE_UINT64) at [index, index + count) of `dataset`, checksum recomputed. */
static inline void io_edit_raw(const char *src, const char *dst, const char *dataset, int64_t index, const void *val,
                               size_t count, hid_t mt) {
  hid_t f = io_copy_open(src, dst);
  hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  if (d < 0) fprintf(stderr, "io_edit_raw: no dataset '%s' in '%s'\n", dataset, src);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  const hsize_t start = (hsize_t)index, cnt = (hsize_t)count;
  assert_true((hssize_t)(start + cnt) <= H5Sget_simple_extent_npoints(sp));
  assert_true(H5Sselect_hyperslab(sp, H5S_SELECT_SET, &start, NULL, &cnt, NULL) >= 0);
  hid_t ms = H5Screate_simple(1, &cnt, NULL);
  assert_true(H5Dwrite(d, mt, ms, sp, H5P_DEFAULT, val) >= 0);
  H5Sclose(ms);
  H5Sclose(sp);
  H5Dclose(d);
  H5Fclose(f);
  io_refresh_crc(dst);
}

/* Copy granary file `src` to `dst` with 1-D `dataset` replaced by one of `len` values of its type
 * (its values as far as they go, zeros after), or removed (len < 0); checksum recomputed. */
static inline void io_edit_resize(const char *src, const char *dst, const char *dataset, int64_t len) {
  hid_t f = io_copy_open(src, dst);
  hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t ft = H5Dget_type(d), sp = H5Dget_space(d);
  const hssize_t np = H5Sget_simple_extent_npoints(sp);
  const size_t es = H5Tget_size(ft);
  const size_t keep = len < 0 ? 0 : (size_t)(len < np ? len : np);
  unsigned char *v = (unsigned char *)calloc((size_t)(np > 0 ? np : 1) + (len > 0 ? (size_t)len : 0), es);
  assert_true(np == 0 || H5Dread(d, ft, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
  H5Sclose(sp);
  H5Dclose(d);
  assert_true(H5Ldelete(f, dataset, H5P_DEFAULT) >= 0);
  if (len >= 0) {
    const hsize_t dim = (hsize_t)len;
    hid_t ns = H5Screate_simple(1, &dim, NULL);
    hid_t nd = H5Dcreate2(f, dataset, ft, ns, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    assert_true(nd >= 0);
    memset(v + keep * es, 0, ((size_t)len - keep) * es);
    assert_true(len == 0 || H5Dwrite(nd, ft, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    H5Dclose(nd);
    H5Sclose(ns);
  }
  free(v);
  H5Tclose(ft);
  H5Fclose(f);
  io_refresh_crc(dst);
}

/* ---- HDF5 comparison ---------------------------------------------------------------------- */
typedef struct {
  hid_t other;
  int ndatasets;
  int ndiff;
  char first_diff[512];
} io_cmp_state;

static inline herr_t io_cmp_cb(hid_t obj, const char *name, const H5O_info_t *info, void *op) {
  io_cmp_state *st = (io_cmp_state *)op;
  if (info->type != H5O_TYPE_DATASET) return 0;
  st->ndatasets++;
  hid_t a = H5Dopen2(obj, name, H5P_DEFAULT), b = H5Dopen2(st->other, name, H5P_DEFAULT);
  int same = 0;
  if (a >= 0 && b >= 0) {
    hid_t ta = H5Dget_type(a), tb = H5Dget_type(b);
    hsize_t sa = H5Dget_storage_size(a), sb = H5Dget_storage_size(b);
    hid_t spa = H5Dget_space(a), spb = H5Dget_space(b);
    hssize_t na = H5Sget_simple_extent_npoints(spa), nb = H5Sget_simple_extent_npoints(spb);
    size_t es = H5Tget_size(ta);
    if (H5Tequal(ta, tb) > 0 && na == nb && H5Sextent_equal(spa, spb) > 0) {
      size_t bytes = (size_t)na * es;
      unsigned char *x = malloc(bytes + 1), *y = malloc(bytes + 1);
      hid_t mt = H5Tget_native_type(ta, H5T_DIR_DEFAULT);
      if (H5Dread(a, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, x) >= 0 && H5Dread(b, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, y) >= 0)
        same = memcmp(x, y, bytes) == 0;
      H5Tclose(mt);
      free(x);
      free(y);
    }
    (void)sa, (void)sb;
    H5Sclose(spa);
    H5Sclose(spb);
    H5Tclose(ta);
    H5Tclose(tb);
  }
  if (a >= 0) H5Dclose(a);
  if (b >= 0) H5Dclose(b);
  if (!same) {
    if (!st->ndiff) snprintf(st->first_diff, sizeof st->first_diff, "%s", name);
    st->ndiff++;
  }
  return 0;
}

/* Number of datasets of `a` that differ from `b` (missing counts as different); *ndatasets = total. */
static inline int io_h5_compare(const char *a, const char *b, int *ndatasets, char *first_diff, size_t len) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t fa = H5Fopen(a, H5F_ACC_RDONLY, H5P_DEFAULT), fb = H5Fopen(b, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (fa < 0 || fb < 0) {
    if (fa >= 0) H5Fclose(fa);
    if (fb >= 0) H5Fclose(fb);
    return -1;
  }
  io_cmp_state st;
  memset(&st, 0, sizeof st);
  st.other = fb;
  H5Ovisit2(fa, H5_INDEX_NAME, H5_ITER_INC, io_cmp_cb, &st, H5O_INFO_BASIC);
  H5Fclose(fa);
  H5Fclose(fb);
  if (ndatasets) *ndatasets = st.ndatasets;
  if (first_diff) snprintf(first_diff, len, "%s", st.first_diff);
  return st.ndiff;
}

/* dims of a dataset (returns rank, -1 when missing) */
static inline int io_h5_dims(hid_t f, const char *name, hsize_t dims[4]) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t s = H5Dget_space(d);
  int r = H5Sget_simple_extent_ndims(s);
  if (r > 4) r = 4;
  hsize_t tmp[32];
  H5Sget_simple_extent_dims(s, tmp, NULL);
  for (int i = 0; i < r; i++) dims[i] = tmp[i];
  H5Sclose(s);
  H5Dclose(d);
  return r;
}

static inline double *io_h5_read_double(hid_t f, const char *name, size_t *n) {
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) return NULL;
  hid_t s = H5Dget_space(d);
  hssize_t np = H5Sget_simple_extent_npoints(s);
  double *x = malloc(sizeof(double) * (size_t)(np > 0 ? np : 1));
  if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x) < 0) {
    free(x);
    x = NULL;
  }
  H5Sclose(s);
  H5Dclose(d);
  if (n) *n = (size_t)np;
  return x;
}

/* string attribute (malloc'ed), NULL when missing. granary writes variable-length UTF-8 strings
 * (h5py reads them as str): anything else is returned as NULL. */
static inline char *io_h5_attr_string(hid_t f, const char *name) {
  hid_t a = H5Aopen(f, name, H5P_DEFAULT);
  if (a < 0) return NULL;
  hid_t t = H5Aget_type(a);
  char *s = NULL;
  if (H5Tget_class(t) == H5T_STRING && H5Tis_variable_str(t) > 0 && H5Tget_cset(t) == H5T_CSET_UTF8) {
    hid_t mt = H5Tcopy(H5T_C_S1);
    H5Tset_size(mt, H5T_VARIABLE);
    H5Tset_cset(mt, H5T_CSET_UTF8);
    char *p = NULL;
    if (H5Aread(a, mt, &p) >= 0 && p) {
      s = strdup(p);
      H5free_memory(p);
    }
    H5Tclose(mt);
  }
  H5Tclose(t);
  H5Aclose(a);
  return s;
}

#endif
