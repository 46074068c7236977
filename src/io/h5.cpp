/* h5.cpp - thin helpers over the HDF5 C API (errors silenced, mapped to GRAN_ERR_IO naming the
 * file and the object) and the atomic file commit (fsync + rename + fsync of the folder). */
#include <hdf5.h>

#include <cerrno>
#include <cstdio>
#include <fcntl.h>
#include <unistd.h>

#include "io/io_impl.h"

namespace gran_h5 {

static void quiet() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

int64_t create_file(const char *path) {
  quiet();
  return (int64_t)H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
}

int64_t open_file(const char *path, int readwrite) {
  quiet();
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
  hid_t g = H5Gcreate2((hid_t)loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
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

/* Strings are variable-length UTF-8 (h5py returns them as str, not bytes). */
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
  int ok = ft >= 0 && H5Tget_class(ft) == H5T_STRING;
  const bool vlen = ok && H5Tis_variable_str(ft) > 0;
  size_t n = ok ? H5Tget_size(ft) : 0;
  herr_t st = -1;
  if (ok && vlen) {
    hid_t mt = H5Tcopy(H5T_C_S1);
    H5Tset_size(mt, H5T_VARIABLE);
    H5Tset_cset(mt, H5Tget_cset(ft));
    char *p = nullptr;
    st = H5Aread(a, mt, &p);
    if (st >= 0) value.assign(p ? p : "");
    if (p) H5free_memory(p);
    H5Tclose(mt);
  } else if (ok) {
    hid_t mt = H5Tcopy(H5T_C_S1);
    H5Tset_size(mt, n);
    H5Tset_strpad(mt, H5T_STR_NULLTERM);
    std::string buf(n, '\0');
    st = H5Aread(a, mt, &buf[0]);
    H5Tclose(mt);
    if (st >= 0) value.assign(buf.c_str());
  }
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
