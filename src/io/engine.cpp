/* engine.cpp - the engine table (keyed by the scene's `[engine] type`: factory, scene schema and
 * parser, memory model) and the row buffers the engines record into. See engine.h for how a new
 * engine plugs in. */
#include <hdf5.h>

#include <cstring>

#include "io/engine.h"

namespace {

/* One line per engine: its factory (the adapter in src/io/engine_<type>.cpp), its scene schema and
 * parser (src/<engine>/scene_<engine>.cpp), its memory model (src/<engine>/memory.cpp). The first
 * is the engine of a scene without `[engine] type`. */
const gran_engine_entry kEngines[] = {
    {"dsmc", "DSMC (src/dsmc)", gran_engine_dsmc_create_, gran_dsmc_scene_keys_, gran_dsmc_scene_nkeys_, nullptr,
     gran_dsmc_scene_parse_, gran_dsmc_memory_},
    {"srd", "GSRD (src/srd)", gran_engine_srd_create_, gran_srd_scene_keys_, gran_srd_scene_nkeys_,
     gran_srd_scene_before_, gran_srd_scene_parse_, gran_srd_memory_},
};

}  // namespace

const gran_engine_entry *gran_engine_entries_(size_t *n) {
  *n = sizeof kEngines / sizeof kEngines[0];
  return kEngines;
}

const gran_engine_entry *gran_engine_find_(const std::string &type) {
  for (const gran_engine_entry &e : kEngines)
    if (type == e.type) return &e;
  return nullptr;
}

double gran_row_bytes_(double nbuf, double elems, double nt) {
  return 8.0 * elems * nt + nbuf * (1.5 * (double)sizeof(gran_row_buf) + 2.0 * gran_alloc_bytes);
}

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
  for (const gran_engine_entry &e : kEngines) {
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
