/* state.cpp - the state interface of state.h over the HDF5 C API: groups with a 'format'
 * attribute, 1-D typed datasets read back with their count and type class checked, scalar
 * attributes; files built in memory and committed with granary's checksum (h5.cpp). */
#include "io/state.h"

#include <hdf5.h>
#include <sys/stat.h>

#include <cstring>

#include "io/io_impl.h"

namespace gran_state {
namespace {

struct H5Obj {
  hid_t id = -1;
  herr_t (*close)(hid_t) = nullptr;
  H5Obj(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~H5Obj() {
    if (id >= 0 && close) close(id);
  }
  H5Obj(const H5Obj &) = delete;
  H5Obj &operator=(const H5Obj &) = delete;
};

void quiet() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

bool file_exists(const char *path) {
  struct stat st;
  return stat(path, &st) == 0;
}

/* what object `name` below `loc` is (H5I_BADID when none) */
H5I_type_t kind(hid_t loc, const char *name) {
  H5Obj o(H5Oopen(loc, name, H5P_DEFAULT), H5Oclose);
  return o.id >= 0 ? H5Iget_type(o.id) : H5I_BADID;
}

int put_any(hid_t g, const char *name, hid_t type, int64_t n, const void *data, const char *path) {
  GRAN_CHECK(n >= 0, GRAN_ERR_ARG, "field '%s' of '%s': %lld values", name, path, (long long)n);
  if (H5Lexists(g, name, H5P_DEFAULT) > 0)
    GRAN_CHECK(H5Ldelete(g, name, H5P_DEFAULT) >= 0, GRAN_ERR_IO, "HDF5: cannot replace dataset '%s' in '%s'", name, path);
  const hsize_t dim = (hsize_t)n;
  H5Obj space(H5Screate_simple(1, &dim, nullptr), H5Sclose);
  GRAN_CHECK(space.id >= 0, GRAN_ERR_IO, "HDF5: cannot create a dataspace for '%s' in '%s'", name, path);
  H5Obj ds(H5Dcreate2(g, name, type, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  GRAN_CHECK(ds.id >= 0, GRAN_ERR_IO, "HDF5: cannot create dataset '%s' in '%s'", name, path);
  if (n > 0)
    GRAN_CHECK(H5Dwrite(ds.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0, GRAN_ERR_IO,
               "HDF5: cannot write dataset '%s' in '%s'", name, path);
  return GRAN_SUCCESS;
}

/* exactly n values of the memory type's class (float or integer, same size: no conversion that
 * could round or clip what the file holds) */
int get_any(hid_t g, const char *name, hid_t type, int64_t n, void *data, const char *path) {
  GRAN_CHECK(H5Lexists(g, name, H5P_DEFAULT) > 0, GRAN_ERR_IO, "checkpoint '%s': field '%s' is missing", path, name);
  GRAN_CHECK(kind(g, name) == H5I_DATASET, GRAN_ERR_IO, "checkpoint '%s': field '%s' is not a dataset", path, name);
  H5Obj ds(H5Dopen2(g, name, H5P_DEFAULT), H5Dclose);
  GRAN_CHECK(ds.id >= 0, GRAN_ERR_IO, "checkpoint '%s': cannot open field '%s'", path, name);
  H5Obj space(H5Dget_space(ds.id), H5Sclose);
  H5Obj ft(H5Dget_type(ds.id), H5Tclose);
  GRAN_CHECK(space.id >= 0 && ft.id >= 0, GRAN_ERR_IO, "checkpoint '%s': cannot read field '%s'", path, name);
  const hssize_t np = H5Sget_simple_extent_npoints(space.id);
  GRAN_CHECK(np == (hssize_t)n && H5Sget_simple_extent_ndims(space.id) <= 1, GRAN_ERR_IO,
             "checkpoint '%s': field '%s' has %lld values, expected %lld", path, name, (long long)np, (long long)n);
  const H5T_class_t fc = H5Tget_class(ft.id), mc = H5Tget_class(type);
  GRAN_CHECK(fc == mc && H5Tget_size(ft.id) == H5Tget_size(type) &&
                 (mc != H5T_INTEGER || H5Tget_sign(ft.id) == H5Tget_sign(type)),
             GRAN_ERR_IO, "checkpoint '%s': field '%s' has the wrong type (expected %s%zu)", path, name,
             mc == H5T_FLOAT ? "float" : H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int", 8 * H5Tget_size(type));
  GRAN_CHECK(n == 0 || (double)H5Dget_storage_size(ds.id) >= (double)n * (double)H5Tget_size(type), GRAN_ERR_IO,
             "checkpoint '%s': field '%s' declares %lld values but holds no data for them", path, name, (long long)n);
  if (n > 0)
    GRAN_CHECK(H5Dread(ds.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0, GRAN_ERR_IO,
               "checkpoint '%s': cannot read field '%s'", path, name);
  return GRAN_SUCCESS;
}

int attr_read(hid_t g, const char *name, hid_t type, void *v, const char *path) {
  GRAN_CHECK(H5Aexists(g, name) > 0, GRAN_ERR_IO, "checkpoint '%s': attribute '%s' is missing", path, name);
  H5Obj a(H5Aopen(g, name, H5P_DEFAULT), H5Aclose);
  H5Obj sp(a.id >= 0 ? H5Aget_space(a.id) : -1, H5Sclose);
  H5Obj ft(a.id >= 0 ? H5Aget_type(a.id) : -1, H5Tclose);
  GRAN_CHECK(sp.id >= 0 && ft.id >= 0 && H5Sget_simple_extent_npoints(sp.id) == 1 &&
                 H5Tget_class(ft.id) == H5Tget_class(type),
             GRAN_ERR_IO, "checkpoint '%s': attribute '%s' is not one %s", path, name,
             H5Tget_class(type) == H5T_FLOAT ? "number" : "integer");
  GRAN_CHECK(H5Aread(a.id, type, v) >= 0, GRAN_ERR_IO, "checkpoint '%s': cannot read attribute '%s'", path, name);
  return GRAN_SUCCESS;
}

}  // namespace

/* ---- files ---- */
File::~File() {
  if (id_ >= 0) H5Fclose((hid_t)id_);
}

int File::open_update(const char *path) {
  quiet();
  GRAN_CHECK_PTR(path);
  GRAN_CHECK(id_ < 0, GRAN_ERR_STATE, "state file '%s': already open", path);
  path_ = path;
  memory_ = true;
  hid_t fid;
  if (file_exists(path)) {
    GRAN_CHECK(H5Fis_hdf5(path) > 0, GRAN_ERR_IO, "checkpoint file '%s' exists and is not an HDF5 file", path);
    H5Obj fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    H5Pset_fapl_core(fapl.id, (size_t)1 << 20, 0); /* in memory, never written back by HDF5 */
    fid = H5Fopen(path, H5F_ACC_RDWR, fapl.id);
  } else {
    fid = (hid_t)gran_h5::create_memory_file();
  }
  GRAN_CHECK(fid >= 0, GRAN_ERR_IO, "cannot open or create checkpoint file '%s' for writing", path);
  id_ = (int64_t)fid;
  return GRAN_SUCCESS;
}

int File::open_read(const char *path, const char *what, bool require_checksum) {
  quiet();
  GRAN_CHECK_PTR(path);
  GRAN_CHECK(id_ < 0, GRAN_ERR_STATE, "state file '%s': already open", path);
  path_ = path;
  memory_ = false;
  GRAN_CHECK(file_exists(path), GRAN_ERR_IO, "%s file '%s' is missing", what, path);
  /* before HDF5 parses it */
  GRAN_CALL(require_checksum ? gran_h5::verify_file(path, what) : gran_h5::verify_file_if_marked(path, what));
  GRAN_CHECK(H5Fis_hdf5(path) > 0, GRAN_ERR_IO, "%s file '%s' is not HDF5", what, path);
  const hid_t fid = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  GRAN_CHECK(fid >= 0, GRAN_ERR_IO, "cannot open %s file '%s'", what, path);
  id_ = (int64_t)fid;
  return GRAN_SUCCESS;
}

int File::commit(const char *what) {
  GRAN_CHECK(id_ >= 0 && memory_, GRAN_ERR_STATE, "state file '%s' is not open for writing", path_.c_str());
  return gran_h5::commit_memory_file(&id_, path_, what); /* closes the file: id_ = -1 */
}

/* ---- groups ---- */
Group::~Group() {
  if (id_ >= 0) H5Gclose((hid_t)id_);
}

int Group::create(int64_t loc, const char *name, const char *format, const char *path) {
  quiet();
  path_ = path;
  const hid_t l = (hid_t)loc;
  if (H5Lexists(l, name, H5P_DEFAULT) > 0)
    GRAN_CHECK(H5Ldelete(l, name, H5P_DEFAULT) >= 0, GRAN_ERR_IO, "cannot replace group '%s' in '%s'", name, path);
  H5Obj lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.id, 1);
  const hid_t g = H5Gcreate2(l, name, lcpl.id, H5P_DEFAULT, H5P_DEFAULT);
  GRAN_CHECK(g >= 0, GRAN_ERR_IO, "cannot create group '%s' in '%s'", name, path);
  id_ = (int64_t)g;
  H5Obj type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.id, std::strlen(format));
  H5Obj space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Obj at(H5Acreate2(g, "format", type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  GRAN_CHECK(at.id >= 0 && H5Awrite(at.id, type.id, format) >= 0, GRAN_ERR_IO,
             "cannot write attribute 'format' in '%s'", path);
  return GRAN_SUCCESS;
}

int Group::open(int64_t loc, const char *name, const char *path) {
  quiet();
  path_ = path;
  const hid_t l = (hid_t)loc;
  GRAN_CHECK(H5Lexists(l, name, H5P_DEFAULT) > 0, GRAN_ERR_IO, "checkpoint file '%s' has no group '%s'", path, name);
  GRAN_CHECK(kind(l, name) == H5I_GROUP, GRAN_ERR_IO, "checkpoint '%s': '%s' is not a group", path, name);
  const hid_t g = H5Gopen2(l, name, H5P_DEFAULT);
  GRAN_CHECK(g >= 0, GRAN_ERR_IO, "cannot open group '%s' in '%s'", name, path);
  id_ = (int64_t)g;
  return GRAN_SUCCESS;
}

int Group::format(std::string *fmt) const {
  fmt->clear();
  if (H5Aexists((hid_t)id_, "format") <= 0) return GRAN_SUCCESS;
  return gran_h5::read_attr_string(id_, "format", *fmt, path_);
}

bool Group::has(const char *name) const { return H5Lexists((hid_t)id_, name, H5P_DEFAULT) > 0; }

int64_t Group::npoints(const char *name) const {
  if (!has(name)) return -1;
  if (kind((hid_t)id_, name) != H5I_DATASET) return -1;
  H5Obj ds(H5Dopen2((hid_t)id_, name, H5P_DEFAULT), H5Dclose);
  if (ds.id < 0) return -1;
  H5Obj space(H5Dget_space(ds.id), H5Sclose);
  H5Obj ft(H5Dget_type(ds.id), H5Tclose);
  if (space.id < 0 || ft.id < 0) return -1;
  const int64_t np = (int64_t)H5Sget_simple_extent_npoints(space.id);
  /* a size a file declares but does not hold (no storage written) asks for memory it cannot fill */
  if (np > 0 && (double)H5Dget_storage_size(ds.id) < (double)np * (double)H5Tget_size(ft.id)) return -1;
  return np;
}

int Group::put(const char *name, int64_t n, const double *x) const {
  return put_any((hid_t)id_, name, H5T_NATIVE_DOUBLE, n, x, path_);
}
int Group::put(const char *name, int64_t n, const int64_t *x) const {
  return put_any((hid_t)id_, name, H5T_NATIVE_INT64, n, x, path_);
}
int Group::put(const char *name, int64_t n, const int32_t *x) const {
  return put_any((hid_t)id_, name, H5T_NATIVE_INT32, n, x, path_);
}
int Group::put(const char *name, int64_t n, const uint64_t *x) const {
  return put_any((hid_t)id_, name, H5T_NATIVE_UINT64, n, x, path_);
}
int Group::get(const char *name, int64_t n, double *x) const {
  return get_any((hid_t)id_, name, H5T_NATIVE_DOUBLE, n, x, path_);
}
int Group::get(const char *name, int64_t n, int64_t *x) const {
  return get_any((hid_t)id_, name, H5T_NATIVE_INT64, n, x, path_);
}
int Group::get(const char *name, int64_t n, int32_t *x) const {
  return get_any((hid_t)id_, name, H5T_NATIVE_INT32, n, x, path_);
}
int Group::get(const char *name, int64_t n, uint64_t *x) const {
  return get_any((hid_t)id_, name, H5T_NATIVE_UINT64, n, x, path_);
}

bool Group::has_attr(const char *name) const { return H5Aexists((hid_t)id_, name) > 0; }
int Group::attr_put(const char *name, const std::string &v) const { return gran_h5::attr_string(id_, name, v, path_); }
int Group::attr_put(const char *name, double v) const { return gran_h5::attr_double(id_, name, v, path_); }
int Group::attr_put(const char *name, int64_t v) const { return gran_h5::attr_int64(id_, name, v, path_); }
int Group::attr_get(const char *name, std::string *v) const {
  GRAN_CHECK(has_attr(name), GRAN_ERR_IO, "checkpoint '%s': attribute '%s' is missing", path_, name);
  return gran_h5::read_attr_string(id_, name, *v, path_);
}
int Group::attr_get(const char *name, double *v) const {
  return attr_read((hid_t)id_, name, H5T_NATIVE_DOUBLE, v, path_);
}
int Group::attr_get(const char *name, int64_t *v) const {
  return attr_read((hid_t)id_, name, H5T_NATIVE_INT64, v, path_);
}

}  // namespace gran_state
