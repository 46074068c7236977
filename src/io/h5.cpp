/* h5.cpp - thin helpers over the HDF5 C API (errors silenced, mapped to GRAN_ERR_IO naming the
 * file and the object) and the atomic file commit (fsync + rename + fsync of the folder). */
#include <hdf5.h>

#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstdio>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/io_impl.h"

namespace gran_h5 {

static void quiet() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

/* Only regular files are opened: a FIFO would block the open, a device or folder is no HDF5 file
 * (stat first, before anything opens the path). */
static bool regular(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

int64_t open_file(const char *path, int readwrite) {
  quiet();
  if (!regular(path)) return -1;
  return (int64_t)H5Fopen(path, readwrite ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT);
}

void close_file(int64_t f) {
  if (f >= 0) H5Fclose((hid_t)f);
}

static int write_any(int64_t loc, const char *name, const std::vector<int64_t> &dims, hid_t type, const void *data,
                     const char *file) {
  std::vector<hsize_t> d(dims.begin(), dims.end());
  hsize_t total = 1;
  for (hsize_t x : d) total *= x;
  hid_t space = d.empty() ? H5Screate(H5S_SCALAR) : H5Screate_simple((int)d.size(), d.data(), nullptr);
  if (space < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot create a dataspace for '%s' in '%s'", name, file);
  hid_t ds = H5Dcreate2((hid_t)loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  herr_t st = -1;
  if (ds >= 0) st = total ? H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
  if (ds >= 0) H5Dclose(ds);
  H5Sclose(space);
  if (ds < 0 || st < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot write dataset '%s' in '%s'", name, file);
  return GRAN_SUCCESS;
}

int write_double(int64_t loc, const char *name, const std::vector<int64_t> &dims, const double *data,
                 const char *file) {
  return write_any(loc, name, dims, H5T_NATIVE_DOUBLE, data, file);
}
int write_int64(int64_t loc, const char *name, const std::vector<int64_t> &dims, const int64_t *data,
                const char *file) {
  return write_any(loc, name, dims, H5T_NATIVE_INT64, data, file);
}

static int read_any(int64_t loc, const char *name, hid_t type, size_t esize, void *out_vec, std::vector<int64_t> *dims,
                    const char *file, int is_double) {
  hid_t ds = H5Dopen2((hid_t)loc, name, H5P_DEFAULT);
  if (ds < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: dataset '%s' missing in '%s'", name, file);
  hid_t space = H5Dget_space(ds);
  int nd = space >= 0 ? H5Sget_simple_extent_ndims(space) : -1;
  std::vector<hsize_t> d(nd > 0 ? (size_t)nd : 0);
  if (nd > 0) H5Sget_simple_extent_dims(space, d.data(), nullptr);
  hsize_t total = 1;
  for (hsize_t x : d) total *= x;
  herr_t st = -1;
  if (nd >= 0) {
    if (is_double) {
      auto &v = *static_cast<std::vector<double> *>(out_vec);
      v.resize(total);
      st = total ? H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) : 0;
    } else {
      auto &v = *static_cast<std::vector<int64_t> *>(out_vec);
      v.resize(total);
      st = total ? H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) : 0;
    }
  }
  (void)esize;
  if (space >= 0) H5Sclose(space);
  H5Dclose(ds);
  if (st < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot read dataset '%s' in '%s'", name, file);
  if (dims) dims->assign(d.begin(), d.end());
  return GRAN_SUCCESS;
}

int read_double(int64_t loc, const char *name, std::vector<double> &out, std::vector<int64_t> *dims, const char *file) {
  return read_any(loc, name, H5T_NATIVE_DOUBLE, sizeof(double), &out, dims, file, 1);
}
int read_int64(int64_t loc, const char *name, std::vector<int64_t> &out, std::vector<int64_t> *dims, const char *file) {
  return read_any(loc, name, H5T_NATIVE_INT64, sizeof(int64_t), &out, dims, file, 0);
}

int make_group(int64_t loc, const char *name, int64_t *group, const char *file) {
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE); /* a path's intermediate groups too */
  if (lcpl >= 0) H5Pset_create_intermediate_group(lcpl, 1);
  hid_t g = lcpl >= 0 ? H5Gcreate2((hid_t)loc, name, lcpl, H5P_DEFAULT, H5P_DEFAULT) : -1;
  if (lcpl >= 0) H5Pclose(lcpl);
  if (g < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot create group '%s' in '%s'", name, file);
  *group = (int64_t)g;
  return GRAN_SUCCESS;
}

void close_group(int64_t g) {
  if (g >= 0) H5Gclose((hid_t)g);
}

static int attr_any(int64_t loc, const char *name, hid_t type, const void *data, const char *file) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2((hid_t)loc, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  herr_t st = a >= 0 ? H5Awrite(a, type, data) : -1;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  if (st < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot write attribute '%s' in '%s'", name, file);
  return GRAN_SUCCESS;
}

/* Strings are variable-length UTF-8, so that h5py returns str (not bytes). */
int attr_string(int64_t loc, const char *name, const std::string &value, const char *file) {
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  const char *p = value.c_str();
  int st = attr_any(loc, name, t, &p, file);
  H5Tclose(t);
  return st;
}
int attr_double(int64_t loc, const char *name, double value, const char *file) {
  return attr_any(loc, name, H5T_NATIVE_DOUBLE, &value, file);
}
int attr_int64(int64_t loc, const char *name, int64_t value, const char *file) {
  return attr_any(loc, name, H5T_NATIVE_INT64, &value, file);
}
int attr_uint64(int64_t loc, const char *name, uint64_t value, const char *file) {
  return attr_any(loc, name, H5T_NATIVE_UINT64, &value, file);
}

int read_attr_string(int64_t loc, const char *name, std::string &value, const char *file) {
  hid_t a = H5Aopen((hid_t)loc, name, H5P_DEFAULT);
  if (a < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: attribute '%s' missing in '%s'", name, file);
  hid_t ft = H5Aget_type(a);
  hid_t sp = H5Aget_space(a);
  /* a scalar string, fixed or variable length (older files hold fixed-length ASCII) */
  const int ok = ft >= 0 && sp >= 0 && H5Tget_class(ft) == H5T_STRING && H5Sget_simple_extent_npoints(sp) == 1;
  herr_t st = -1;
  if (ok && H5Tis_variable_str(ft) > 0) {
    hid_t mt = H5Tcopy(H5T_C_S1);
    H5Tset_size(mt, H5T_VARIABLE);
    H5Tset_cset(mt, H5Tget_cset(ft));
    char *p = nullptr;
    st = H5Aread(a, mt, &p);
    if (st >= 0) {
      value.assign(p ? p : "");
      H5free_memory(p);
    }
    H5Tclose(mt);
  } else if (ok) {
    const size_t n = H5Tget_size(ft);
    if (n > 0 && n < ((size_t)1 << 30)) {
      hid_t mt = H5Tcopy(H5T_C_S1);
      H5Tset_size(mt, n + 1);
      H5Tset_strpad(mt, H5T_STR_NULLTERM);
      std::string buf(n + 1, '\0');
      st = H5Aread(a, mt, &buf[0]);
      H5Tclose(mt);
      if (st >= 0) value.assign(buf.c_str());
    }
  }
  if (sp >= 0) H5Sclose(sp);
  if (ft >= 0) H5Tclose(ft);
  H5Aclose(a);
  if (st < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot read string attribute '%s' in '%s'", name, file);
  return GRAN_SUCCESS;
}

int read_attr_int64(int64_t loc, const char *name, int64_t *value, const char *file) {
  hid_t a = H5Aopen((hid_t)loc, name, H5P_DEFAULT);
  if (a < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: attribute '%s' missing in '%s'", name, file);
  herr_t st = H5Aread(a, H5T_NATIVE_INT64, value);
  H5Aclose(a);
  if (st < 0) return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot read attribute '%s' in '%s'", name, file);
  return GRAN_SUCCESS;
}

int exists(int64_t loc, const char *name) { return H5Lexists((hid_t)loc, name, H5P_DEFAULT) > 0; }

}  // namespace gran_h5

/* ---- files built in memory, written with a checksum ------------------------------------------
 * The HDF5 library never writes to disk itself here: the file is built with the core driver (no
 * backing store), its image is copied out, the library's handle is closed (in memory: it cannot
 * fail on a full disk), and the bytes are written by write(2) into PATH.tmp, fsync'ed and renamed.
 * A full disk is then an ordinary error of ours, reported with every HDF5 object already closed.
 * The first kUserBlock bytes (an HDF5 user block: HDF5 finds the superblock at offset 512 and
 * every reader, h5py included, skips what lies before it) hold a text header with the length of the file and the CRC-32 (zlib) of everything after it;
 * open_verified() checks both before HDF5 parses a single byte of a checkpoint. */
namespace gran_h5 {

static const size_t kUserBlock = 512;
static const char kMagic[] = "granary-file 1\n";

int64_t create_memory_file() {
  quiet();
  static std::atomic<uint64_t> serial{0};
  char name[64];
  std::snprintf(name, sizeof name, "granary-memory-image-%d-%llu", (int)getpid(),
                (unsigned long long)serial.fetch_add(1));
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  hid_t f = -1;
  if (fapl >= 0 && H5Pset_fapl_core(fapl, (size_t)1 << 20, 0) >= 0) f = H5Fcreate(name, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  if (fapl >= 0) H5Pclose(fapl);
  return (int64_t)f;
}

/* write all of buf to fd; errno describes a failure */
static bool write_all(int fd, const unsigned char *buf, size_t n) {
  while (n > 0) {
    ssize_t w = write(fd, buf, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      if (w == 0) errno = ENOSPC;
      return false;
    }
    buf += w;
    n -= (size_t)w;
  }
  return true;
}

int commit_memory_file(int64_t *file, const std::string &path, const char *what) {
  const hid_t f = (hid_t)*file;
  *file = -1;
  /* the image of the file as HDF5 built it; the header goes in front of it (HDF5 finds its
   * superblock at offset 512 and takes that as the base address of the file) */
  std::vector<unsigned char> img;
  ssize_t n = H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0 ? H5Fget_file_image(f, nullptr, 0) : -1;
  if (n > 0) {
    img.resize(kUserBlock + (size_t)n);
    if (H5Fget_file_image(f, img.data() + kUserBlock, (size_t)n) != n) n = -1;
  }
  const bool closed = H5Fclose(f) >= 0;
  if (n <= 0 || !closed)
    return GRAN_ERROR(GRAN_ERR_IO, "HDF5: cannot assemble the %s '%s' in memory", what, path.c_str());
  uLong c = crc32(0L, Z_NULL, 0);
  for (size_t off = kUserBlock; off < img.size();) { /* zlib takes uInt lengths */
    const size_t len = std::min(img.size() - off, (size_t)1 << 30);
    c = crc32(c, img.data() + off, (uInt)len);
    off += len;
  }
  char head[kUserBlock];
  std::memset(head, 0, sizeof head);
  std::snprintf(head, sizeof head, "%slength %zu\ncrc32 %08lx\n", kMagic, img.size(), (unsigned long)c);
  std::memcpy(img.data(), head, kUserBlock);
  const std::string tmp = path + ".tmp";
  int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return GRAN_ERROR(GRAN_ERR_IO, "cannot create the %s '%s': %s", what, tmp.c_str(), std::strerror(errno));
  if (!write_all(fd, img.data(), img.size()) || fsync(fd) != 0) {
    const int e = errno;
    close(fd);
    std::remove(tmp.c_str());
    return GRAN_ERROR(GRAN_ERR_IO, "cannot write the %s '%s' (%zu bytes): %s; nothing was replaced", what,
                      tmp.c_str(), img.size(), std::strerror(e));
  }
  if (close(fd) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    return GRAN_ERROR(GRAN_ERR_IO, "cannot close the %s '%s': %s", what, tmp.c_str(), std::strerror(e));
  }
  const int st = gran_io_commit_file_(tmp, path);
  if (st != GRAN_SUCCESS) std::remove(tmp.c_str());
  return st;
}

int verify_file(const char *path, const char *what) {
  struct stat sb;
  if (stat(path, &sb) != 0) return GRAN_ERROR(GRAN_ERR_IO, "cannot open the %s '%s': %s", what, path, std::strerror(errno));
  if (!S_ISREG(sb.st_mode)) return GRAN_ERROR(GRAN_ERR_IO, "the %s '%s' is not a regular file", what, path);
  int fd = open(path, O_RDONLY);
  if (fd < 0) return GRAN_ERROR(GRAN_ERR_IO, "cannot open the %s '%s': %s", what, path, std::strerror(errno));
  std::vector<unsigned char> buf((size_t)1 << 20);
  size_t got = 0;
  bool ok = true;
  while (got < kUserBlock && ok) {
    ssize_t r = read(fd, buf.data() + got, kUserBlock - got);
    if (r < 0 && errno == EINTR) continue;
    ok = r > 0;
    if (ok) got += (size_t)r;
  }
  size_t length = 0;
  unsigned long want = 0;
  unsigned char first[kUserBlock];
  std::memcpy(first, buf.data(), kUserBlock);
  if (ok) {
    buf[kUserBlock - 1] = 0;
    const char *h = (const char *)buf.data();
    ok = std::strncmp(h, kMagic, sizeof kMagic - 1) == 0 &&
         std::sscanf(h + sizeof kMagic - 1, "length %zu\ncrc32 %lx\n", &length, &want) == 2;
  }
  if (!ok) {
    close(fd);
    return GRAN_ERROR(GRAN_ERR_IO, "the %s '%s' has no granary checksum header (not written by granary >= 0.2, or damaged)",
                      what, path);
  }
  if ((uint64_t)sb.st_size != (uint64_t)length) {
    close(fd);
    return GRAN_ERROR(GRAN_ERR_IO, "the %s '%s' is damaged: %lld bytes on disk, %zu written", what, path,
                      (long long)sb.st_size, length);
  }
  uLong c = crc32(0L, Z_NULL, 0);
  size_t total = kUserBlock;
  for (;;) {
    ssize_t r = read(fd, buf.data(), buf.size());
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      const int e = errno;
      close(fd);
      return GRAN_ERROR(GRAN_ERR_IO, "cannot read the %s '%s': %s", what, path, std::strerror(e));
    }
    if (r == 0) break;
    c = crc32(c, buf.data(), (uInt)r);
    total += (size_t)r;
  }
  close(fd);
  /* the header itself, byte for byte (its zero padding included) */
  char head[kUserBlock];
  std::memset(head, 0, sizeof head);
  std::snprintf(head, sizeof head, "%slength %zu\ncrc32 %08lx\n", kMagic, length, want);
  if (total != length || (unsigned long)c != want || std::memcmp(head, first, kUserBlock) != 0)
    return GRAN_ERROR(GRAN_ERR_IO, "the %s '%s' is damaged: checksum mismatch (CRC-32 %08lx, header %08lx)", what, path,
                      (unsigned long)c, want);
  return GRAN_SUCCESS;
}

int verify_file_if_marked(const char *path, const char *what) {
  char head[sizeof kMagic] = {0};
  if (!regular(path)) return verify_file(path, what); /* names a missing or non-regular file */
  FILE *f = std::fopen(path, "rb");
  if (!f) return GRAN_SUCCESS; /* the caller reports a missing file in its own words */
  const size_t got = std::fread(head, 1, sizeof kMagic - 1, f);
  std::fclose(f);
  if (got == sizeof kMagic - 1 && std::memcmp(head, kMagic, sizeof kMagic - 1) == 0) return verify_file(path, what);
  return GRAN_SUCCESS;
}

}  // namespace gran_h5

int gran_io_commit_file_(const std::string &tmp, const std::string &path) {
  int fd = open(tmp.c_str(), O_RDONLY);
  if (fd < 0) return GRAN_ERROR(GRAN_ERR_IO, "cannot reopen '%s' to flush it: %s", tmp.c_str(), std::strerror(errno));
  int st = fsync(fd);
  close(fd);
  if (st != 0) return GRAN_ERROR(GRAN_ERR_IO, "fsync of '%s' failed: %s", tmp.c_str(), std::strerror(errno));
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    return GRAN_ERROR(GRAN_ERR_IO, "cannot rename '%s' to '%s': %s", tmp.c_str(), path.c_str(), std::strerror(errno));
  std::string dir = ".";
  size_t s = path.find_last_of('/');
  if (s != std::string::npos) dir = s == 0 ? "/" : path.substr(0, s);
  int dfd = open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dfd >= 0) {
    fsync(dfd); /* best effort: makes the rename durable */
    close(dfd);
  }
  return GRAN_SUCCESS;
}
