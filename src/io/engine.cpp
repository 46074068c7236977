/* engine.cpp - the engine table (keyed by the scene's `[engine] type`) and the row buffers the
 * engines record into. See engine.h for how a new engine plugs in. */
#include <hdf5.h>

#include <cstring>

#include "io/engine.h"

namespace {

struct Entry {
  const char *type;
  gran_engine_factory create;
};

/* One line per engine. */
const Entry kEngines[] = {
    {"dsmc", gran_engine_dsmc_create_},
    {"srd", gran_engine_srd_create_}, /* GSRD (src/srd), engine_srd.cpp */
};

}  // namespace

void gran_row_buf_add(std::vector<gran_row_buf> &bufs, const char *group, const char *name, int is_int,
                      std::vector<int64_t> row_dims, const char *units, const char *description) {
  gran_row_buf b;
  b.group = group;
  b.name = name;
  b.is_int = is_int;
  b.row_dims = std::move(row_dims);
  for (int64_t x : b.row_dims) b.row *= x;
  b.units = units ? units : "";
  b.description = description ? description : "";
  bufs.push_back(std::move(b));
}

void gran_row_buf_allow_fill(std::vector<gran_row_buf> &bufs, const char *group, const char *name, const char *when) {
  gran_row_buf *b = gran_row_buf_find(bufs, group, name);
  if (!b || b->is_int) return;
  b->fill = 1;
  b->description += std::string("; _FillValue (") + when + ")";
}

gran_row_buf *gran_row_buf_find(std::vector<gran_row_buf> &bufs, const char *group, const char *name) {
  for (auto &b : bufs)
    if (b.group == group && b.name == name) return &b;
  return nullptr;
}

int gran_engine_create_(const gran_scene *s, std::unique_ptr<gran_engine> &out) {
  const std::string &type = s->engine_type;
  std::string known;
  for (const Entry &e : kEngines) {
    if (type == e.type) return e.create(s, out);
    known += known.empty() ? "" : ", ";
    known += std::string("\"") + e.type + "\"";
  }
  return GRAN_ERROR(GRAN_ERR_ARG, "scene key 'engine.type': unknown engine \"%s\" (known: %s)", type.c_str(),
                    known.c_str());
}

int gran_describe_(int64_t loc, const char *name, const char *units, const char *description, const char *file) {
  hid_t d = H5Dopen2((hid_t)loc, name, H5P_DEFAULT);
  GRAN_CHECK(d >= 0, GRAN_ERR_IO, "cannot open dataset '%s' in '%s'", name, file);
  int st = gran_h5::attr_string(d, "units", units, file);
  if (st == GRAN_SUCCESS) st = gran_h5::attr_string(d, "description", description, file);
  H5Dclose(d);
  return st;
}
