/* engine.cpp - the engine table (keyed by the scene's `[engine] type`: factory, scene schema and
 * parser, memory model) and the row buffers the engines record into. See engine.h for how a new
 * engine plugs in. */
#include <hdf5.h>

#include <cmath>
#include <cstdio>
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

void gran_row_buf_species_axes(std::vector<gran_row_buf> &bufs, const char *group, const char *name, std::vector<int> axes) {
  gran_row_buf *b = gran_row_buf_find(bufs, group, name);
  if (b) b->species_axes = std::move(axes);
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

int gran_write_unit_system_(int64_t file, const char *fname, const char *engine, double mass, double length,
                            double energy) {
  const bool dsmc = std::strcmp(engine, "DSMC") == 0;
  const char *m = dsmc ? "m_1" : "m", *l = dsmc ? "sigma_1" : "a";
  const double time = length * std::sqrt(mass / energy);
  char buf[512];
  /* all three 1 (to rounding: the mean temperature is a sum): the units are the reference values */
  auto one = [](double x) { return std::fabs(x - 1.0) <= 1e-12; };
  if (one(mass) && one(length) && one(energy))
    std::snprintf(buf, sizeof buf,
                  "%s units: mass %s (%s), length %s (%s), energy k_B T0 (%s; k_B = 1); time unit: %s sqrt(%s/(k_B T0))",
                  engine, m, dsmc ? "the mass of species 1" : "the particle mass", l,
                  dsmc ? "the diameter of species 1" : "the cell size",
                  dsmc ? "T0 the mean initial temperature <T(t_start)>" : "T0 the scene's T0", l, m);
  else
    std::snprintf(buf, sizeof buf, "%s units: those of the scene's numbers (mass: %s = %.6g; length: %s = %.6g; energy: that "
                  "of the temperatures, k_B T0 = %.6g, k_B = 1); time unit: length sqrt(mass/energy), in which "
                  "%s sqrt(%s/(k_B T0)) = %.6g",
                  engine, m, mass, l, length, energy, l, m, time);
  GRAN_CALL(gran_h5::attr_string(file, "unit_system", buf, fname));
  GRAN_CALL(gran_h5::attr_double(file, "reference_mass", mass, fname));
  GRAN_CALL(gran_h5::attr_double(file, "reference_length", length, fname));
  GRAN_CALL(gran_h5::attr_double(file, "reference_energy", energy, fname));
  return gran_h5::attr_double(file, "reference_time", time, fname);
}
