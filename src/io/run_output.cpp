/* run_output.cpp - the output file of a run: root attributes, the rows of every replica (reduced to
 * mean and standard error when there are several), the partial output of a stopped run, and the
 * row rule every recorded row obeys (check_row). */
#include <hdf5.h>
#include <hdf5_hl.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sys/stat.h>

#include "io/run_impl.h"

namespace gran_run {

namespace {

/* Dataset `name` of `loc` as an HDF5 dimension scale of that name (H5DSset_scale: h5py's
 * Dataset.dims, xarray's dimension names). */
int make_scale(int64_t loc, const char *name, const char *file) {
  hid_t d = H5Dopen2((hid_t)loc, name, H5P_DEFAULT);
  GRAN_CHECK(d >= 0, GRAN_ERR_IO, "cannot open dataset '%s' in '%s'", name, file);
  const herr_t e = H5DSset_scale(d, name);
  H5Dclose(d);
  GRAN_CHECK(e >= 0, GRAN_ERR_IO, "HDF5: cannot make '%s' a dimension scale in '%s'", name, file);
  return GRAN_SUCCESS;
}

/* The scale of the species axes of buffer b in its group g: `species` (k = 1..M) for the first,
 * `species_2` for a second (the partner of collision_counts), written once per group. */
const char *species_scale(size_t a) { return a == 0 ? "species" : "species_2"; }
/* dataset nm = 1..M in g, described, made a scale */
int write_species_scale(int64_t g, const char *nm, int64_t M, const char *description, const char *file) {
  std::vector<int64_t> k((size_t)M);
  for (int64_t i = 0; i < M; i++) k[(size_t)i] = i + 1;
  GRAN_CALL(gran_h5::write_int64(g, nm, {M}, k.data(), file));
  GRAN_CALL(gran_describe_(g, nm, "1", description, file));
  return make_scale(g, nm, file);
}
int species_scales(int64_t g, const gran_row_buf &b, const char *file) {
  for (size_t a = 0; a < b.species_axes.size(); a++) {
    const char *nm = species_scale(a);
    const int ax = b.species_axes[a];
    GRAN_CHECK(ax >= 0 && ax < (int)b.row_dims.size(), GRAN_ERR_INTERNAL, "dataset '%s/%s': species axis %d out of range",
               b.group.c_str(), b.name.c_str(), ax);
    const int64_t M = b.row_dims[(size_t)ax];
    std::vector<int64_t> have;
    if (gran_h5::exists(g, nm)) {
      GRAN_CALL(gran_h5::read_int64(g, nm, have, nullptr, file));
      GRAN_CHECK((int64_t)have.size() == M, GRAN_ERR_INTERNAL, "group '%s': species axes of %zu and %" PRId64 " species",
                 b.group.c_str(), have.size(), M);
      continue;
    }
    GRAN_CALL(write_species_scale(g, nm, M,
                                  a == 0 ? "species index k = 1..M (the species axis of this group's datasets)"
                                         : "species index l = 1..M (the second species axis, [time][k][l])",
                                  file));
  }
  return GRAN_SUCCESS;
}

/* The group's `time` scale on axis `off` of dataset `name` (the rows of buffer b), its species
 * scales on the species axes after it; off = 1 for X_replicas ([replica][time]...). */
int attach_scales(int64_t g, const gran_row_buf &b, const char *name, int off, const char *file) {
  std::vector<std::string> axes((size_t)off + 1 + b.row_dims.size());
  axes[(size_t)off] = "time";
  for (size_t a = 0; a < b.species_axes.size(); a++) axes[(size_t)(off + 1 + b.species_axes[a])] = species_scale(a);
  return gran_attach_scales_(g, name, axes, file);
}

/* The _FillValue attribute (gran_row_fill) of dataset `name` in `loc`. */
int fill_attr(int64_t loc, const char *name, const char *file) {
  hid_t d = H5Dopen2((hid_t)loc, name, H5P_DEFAULT);
  GRAN_CHECK(d >= 0, GRAN_ERR_IO, "cannot open dataset '%s' in '%s'", name, file);
  const int st = gran_h5::attr_double(d, "_FillValue", gran_row_fill, file);
  H5Dclose(d);
  return st;
}

/* Buffer q over the replicas, rows 0..dims[0]-1: double rows as the mean and its standard error
 * (X, X_se); integer rows (event counts) as the sum over replicas (X) and the standard error of
 * that sum (X_se); the per-replica rows as X_replicas [R][time]... when keep_replicas. Sums run
 * in replica order, so the result does not depend on how replicas were spread over threads. */
int write_reduced(const Run &r, size_t q, int64_t g, const std::vector<int64_t> &dims, const char *file) {
  const gran_row_buf &b = r.reps[0].bufs[q];
  const int64_t R = r.R;
  size_t n = 1;
  for (int64_t x : dims) n *= (size_t)x;
  std::vector<double> mean(n, 0.0), se(n, 0.0);
  auto val = [&](int64_t k, size_t i) -> double {
    const gran_row_buf &c = r.reps[(size_t)k].bufs[q];
    return c.is_int ? (double)c.n[i] : c.d[i];
  };
  /* with fill: over the replicas that have a value (none: fill; fewer than 2: no standard error) */
  std::vector<int64_t> cnt(n, R);
  if (b.fill)
    for (size_t i = 0; i < n; i++) {
      cnt[i] = 0;
      for (int64_t k = 0; k < R; k++) cnt[i] += val(k, i) != gran_row_fill;
    }
  auto has = [&](int64_t k, size_t i) { return !b.fill || val(k, i) != gran_row_fill; };
  for (int64_t k = 0; k < R; k++)
    for (size_t i = 0; i < n; i++)
      if (has(k, i)) mean[i] += val(k, i);
  for (size_t i = 0; i < n; i++) mean[i] = cnt[i] > 0 ? mean[i] / (double)cnt[i] : gran_row_fill;
  for (int64_t k = 0; k < R; k++)
    for (size_t i = 0; i < n; i++) {
      if (!has(k, i)) continue;
      const double d = val(k, i) - mean[i];
      se[i] += d * d;
    }
  /* sample variance / R: the standard error of the mean; for a sum, R times that */
  for (size_t i = 0; i < n; i++)
    se[i] = cnt[i] < 2 ? gran_row_fill
                       : std::sqrt(se[i] / (double)(cnt[i] - 1) / (double)cnt[i]) * (b.is_int ? (double)R : 1.0);
  for (size_t i = 0; i < n; i++)
    GRAN_CHECK(std::isfinite(mean[i]) && std::isfinite(se[i]), GRAN_ERR_NUMERIC,
               "dataset '%s/%s': the mean over the replicas or its standard error is not finite (element %zu of '%s')",
               b.group.c_str(), b.name.c_str(), i, file);
  const std::string nse = b.name + "_se", nrep = b.name + "_replicas";
  if (b.is_int) {
    std::vector<int64_t> sum(n, 0);
    for (int64_t k = 0; k < R; k++)
      for (size_t i = 0; i < n; i++) sum[i] += r.reps[(size_t)k].bufs[q].n[i];
    GRAN_CALL(gran_h5::write_int64(g, b.name.c_str(), dims, sum.data(), file));
    GRAN_CALL(gran_describe_(g, b.name.c_str(), b.units.c_str(), (b.description + "; summed over the replicas").c_str(), file));
  } else {
    GRAN_CALL(gran_h5::write_double(g, b.name.c_str(), dims, mean.data(), file));
    GRAN_CALL(gran_describe_(g, b.name.c_str(), b.units.c_str(), (b.description + "; mean over the replicas").c_str(), file));
  }
  GRAN_CALL(gran_h5::write_double(g, nse.c_str(), dims, se.data(), file));
  GRAN_CALL(gran_describe_(g, nse.c_str(), b.units.c_str(),
                           ("standard error of " + b.name + (b.is_int ? " (the sum)" : " (the mean)") + " from the replicas").c_str(), file));
  if (b.fill) {
    GRAN_CALL(fill_attr(g, b.name.c_str(), file));
    GRAN_CALL(fill_attr(g, nse.c_str(), file));
  }
  GRAN_CALL(attach_scales(g, b, b.name.c_str(), 0, file));
  GRAN_CALL(attach_scales(g, b, nse.c_str(), 0, file));
  if (r.keep) {
    std::vector<int64_t> rd = {R};
    rd.insert(rd.end(), dims.begin(), dims.end());
    if (b.is_int) {
      std::vector<int64_t> all;
      for (int64_t k = 0; k < R; k++) all.insert(all.end(), r.reps[(size_t)k].bufs[q].n.begin(), r.reps[(size_t)k].bufs[q].n.begin() + (ptrdiff_t)n);
      GRAN_CALL(gran_h5::write_int64(g, nrep.c_str(), rd, all.data(), file));
    } else {
      std::vector<double> all;
      for (int64_t k = 0; k < R; k++) all.insert(all.end(), r.reps[(size_t)k].bufs[q].d.begin(), r.reps[(size_t)k].bufs[q].d.begin() + (ptrdiff_t)n);
      GRAN_CALL(gran_h5::write_double(g, nrep.c_str(), rd, all.data(), file));
    }
    GRAN_CALL(gran_describe_(g, nrep.c_str(), b.units.c_str(), (b.description + "; per replica [replica][...]").c_str(), file));
    if (b.fill) GRAN_CALL(fill_attr(g, nrep.c_str(), file));
    GRAN_CALL(attach_scales(g, b, nrep.c_str(), 1, file));
  }
  return GRAN_SUCCESS;
}

/* The output file with the first nrec output times (all of them for a finished run; a stopped
 * run writes what it recorded, with the root attribute complete = 0). */
int write_output_file(Run &r, const std::string &path, int64_t nrec);

}  // namespace

/* Row i of every buffer of a replica, right after record: every double finite, except NaN in a
 * buffer with fill (no value), stored as gran_row_fill. Anything else stops the run. */
int check_row(std::vector<gran_row_buf> &bufs, int64_t i, const gran_scene *s) {
  /* Fault injection for the tests of this rule: GRAN_FAULT_ROW = I puts NaN into the first element
   * of the first buffer without fill at output time I (engines no longer produce such rows from
   * accepted inputs, so only this reaches the stop path from a scene). */
  const char *fe = std::getenv("GRAN_FAULT_ROW"); /* once per output time: negligible */
  const int64_t fault = fe && *fe ? (int64_t)std::strtoll(fe, nullptr, 10) : (int64_t)-1;
  if (fault == i)
    for (auto &b : bufs)
      if (!b.is_int && !b.fill && b.row > 0) {
        b.d[(size_t)(i * b.row)] = NAN;
        break;
      }
  for (auto &b : bufs) {
    if (b.is_int) continue;
    double *d = b.d.data() + i * b.row;
    for (int64_t e = 0; e < b.row; e++) {
      if (std::isfinite(d[e])) continue;
      if (b.fill && std::isnan(d[e])) {
        d[e] = gran_row_fill;
        continue;
      }
      return GRAN_ERROR(GRAN_ERR_NUMERIC, "dataset '%s/%s' is %g at output time %" PRId64 " (t = %g, element %" PRId64
                        "): the run stops here", b.group.c_str(), b.name.c_str(), d[e], i, s->times[(size_t)i], e);
    }
  }
  return GRAN_SUCCESS;
}

int write_root_attrs(Run &r, int64_t f, const char *file, const char *format) {
  const gran_scene *s = r.s;
  GRAN_CALL(gran_h5::attr_string(f, "format", format, file));
  GRAN_CALL(gran_h5::attr_string(f, "scene", s->text, file));
  GRAN_CALL(gran_h5::attr_string(f, "scene_file", s->name, file));
  GRAN_CALL(gran_h5::attr_string(f, "title", s->title, file));
  GRAN_CALL(gran_h5::attr_string(f, "granary_version", GRAN_VERSION_STRING, file));
  GRAN_CALL(gran_h5::attr_uint64(f, "seed", s->seed, file));
  GRAN_CALL(gran_h5::attr_string(f, "engine", r.eng()->type(), file));
  GRAN_CALL(gran_h5::attr_double(f, "t_start", s->t_start, file));
  GRAN_CALL(gran_h5::attr_double(f, "t_end", s->t_end, file));
  return GRAN_SUCCESS;
}

/* The output file and its sidecars (gran_engine::sidecars): each sidecar is written as PATH.tmp
 * with the output and renamed into place only after the output file is committed; a sidecar of
 * an earlier run that this one did not write is removed (it would describe another file); on
 * failure no sidecar .tmp is left. */
int write_output(Run &r, const std::string &path, int64_t nrec) {
  const std::vector<std::string> side = r.eng()->sidecars(path);
  for (const auto &p : side) std::remove((p + ".tmp").c_str());
  const int st = write_output_file(r, path, nrec);
  if (st != GRAN_SUCCESS) {
    for (const auto &p : side) std::remove((p + ".tmp").c_str());
    return st;
  }
  for (const auto &p : side) {
    const std::string tmp = p + ".tmp";
    struct stat sb;
    if (stat(tmp.c_str(), &sb) != 0) {
      std::remove(p.c_str());
      continue;
    }
    const int cst = gran_io_commit_file_(tmp, p);
    if (cst != GRAN_SUCCESS) {
      std::remove(tmp.c_str());
      return cst;
    }
  }
  return GRAN_SUCCESS;
}

/* A finished run: the partial output of an earlier stop and its sidecars go. */
void remove_partial(Run &r) {
  const std::string part = gran_partial_path_(r.out);
  std::remove(part.c_str());
  for (const auto &p : r.eng()->sidecars(part)) std::remove(p.c_str());
}

namespace {

int write_output_file(Run &r, const std::string &path, int64_t nrec) {
  const gran_scene *s = r.s;
  const int64_t nt = nrec;
  const char *file = path.c_str();
  {
    /* built in memory, written with its checksum header (gran_h5::commit_memory_file): HDF5
     * never writes to disk itself, so a full disk is a plain GRAN_ERR_IO */
    H5File f;
    f.id = gran_h5::create_memory_file();
    GRAN_CHECK(f.id >= 0, GRAN_ERR_IO, "HDF5: cannot create the output file '%s' in memory", file);
    GRAN_CALL(write_root_attrs(r, f.id, file, kOutputFormat));
    std::string cols;
    for (const auto &c : r.eng()->summary_columns()) cols += c.label + ":" + c.sim + ":" + c.theory + ";";
    GRAN_CALL(gran_h5::attr_string(f.id, "summary_columns", cols, file));
    GRAN_CALL(gran_h5::attr_int64(f.id, "complete", nrec == (int64_t)s->times.size(), file));
    GRAN_CALL(gran_h5::attr_int64(f.id, "recorded", nrec, file));
    GRAN_CALL(gran_h5::write_double(f.id, "time", {nt}, s->times.data(), file));
    GRAN_CALL(gran_describe_(f.id, "time", "time", "the output times", file));
    GRAN_CALL(make_scale(f.id, "time", file));
    for (size_t q = 0; q < r.reps[0].bufs.size(); q++) {
      const gran_row_buf &b = r.reps[0].bufs[q];
      H5Group g;
      if (gran_h5::exists(f.id, b.group.c_str())) {
        g.id = H5Gopen2((hid_t)f.id, b.group.c_str(), H5P_DEFAULT);
      } else {
        GRAN_CALL(gran_h5::make_group(f.id, b.group.c_str(), &g.id, file));
        GRAN_CALL(gran_h5::write_double(g.id, "time", {nt}, s->times.data(), file));
        GRAN_CALL(gran_describe_(g.id, "time", "time", "the output times (rows of this group's datasets)", file));
        GRAN_CALL(make_scale(g.id, "time", file));
      }
      GRAN_CALL(species_scales(g.id, b, file));
      std::vector<int64_t> dims = {nt};
      dims.insert(dims.end(), b.row_dims.begin(), b.row_dims.end());
      if (r.R == 1) {
        if (b.is_int) GRAN_CALL(gran_h5::write_int64(g.id, b.name.c_str(), dims, b.n.data(), file));
        else GRAN_CALL(gran_h5::write_double(g.id, b.name.c_str(), dims, b.d.data(), file));
        GRAN_CALL(gran_describe_(g.id, b.name.c_str(), b.units.c_str(), b.description.c_str(), file));
        if (b.fill) GRAN_CALL(fill_attr(g.id, b.name.c_str(), file));
        GRAN_CALL(attach_scales(g.id, b, b.name.c_str(), 0, file));
        continue;
      }
      GRAN_CALL(write_reduced(r, q, g.id, dims, file));
    }
    GRAN_CALL(gran_h5::attr_int64(f.id, "nreplicas", r.R, file));
    GRAN_CALL(r.eng()->write_output(f.id, file, nrec));
    if (r.R > 1 && gran_h5::exists(f.id, "tamsd")) {
      H5Group g;
      g.id = H5Gopen2((hid_t)f.id, "tamsd", H5P_DEFAULT);
      GRAN_CALL(gran_h5::attr_string(g.id, "replicas", "from replica 0 only", file));
    }
    return gran_h5::commit_memory_file(&f.id, path, "output file");
  }
}

}  // namespace

}  // namespace gran_run

int gran_make_scale_(int64_t loc, const char *name, const char *file) { return gran_run::make_scale(loc, name, file); }

int gran_species_scale_(int64_t loc, int64_t M, const char *file) {
  if (gran_h5::exists(loc, "species")) return GRAN_SUCCESS;
  return gran_run::write_species_scale(loc, "species", M,
                                       "species index k = 1..M (the species axis of this group's datasets)", file);
}

int gran_attach_scales_(int64_t loc, const char *name, const std::vector<std::string> &axes, const char *file) {
  hid_t d = H5Dopen2((hid_t)loc, name, H5P_DEFAULT);
  GRAN_CHECK(d >= 0, GRAN_ERR_IO, "cannot open dataset '%s' in '%s'", name, file);
  herr_t e = 0;
  for (size_t a = 0; a < axes.size() && e >= 0; a++) {
    if (axes[a].empty()) continue;
    hid_t sc = H5Dopen2((hid_t)loc, axes[a].c_str(), H5P_DEFAULT);
    e = sc >= 0 ? H5DSattach_scale(d, sc, (unsigned)a) : -1;
    if (sc >= 0) H5Dclose(sc);
  }
  H5Dclose(d);
  GRAN_CHECK(e >= 0, GRAN_ERR_IO, "HDF5: cannot attach the dimension scales of '%s' in '%s'", name, file);
  return GRAN_SUCCESS;
}
