/* engine.h - the one interface between the run driver (src/io/run.cpp) and the engines.
 *
 * HOW A NEW ENGINE PLUGS IN
 *   1. Write src/<engine>/... as usual (its own public gran_<engine>_* API), then one adapter file
 *      src/io/engine_<type>.cpp with a class derived from gran_engine (below) and a factory
 *        int gran_engine_<type>_create_(const gran_scene *s, std::unique_ptr<gran_engine> &out);
 *      and src/<engine>/scene_<engine>.cpp (its scene keys as data and the parser of its tables,
 *      docs/developers/schema.md) and src/<engine>/memory.cpp (its memory model).
 *   2. Add one line to the table in src/io/engine.cpp (gran_engine_entry, below).
 *      The table is keyed by the scene's `[engine] type` (gran_scene::engine_type, default "dsmc").
 *   3. That is all: the driver writes the output file (root attributes, /time, one group per row
 *      buffer, units/description attributes), checkpoints (engine state in a group the driver
 *      names, the recorded rows in /observer), resume, the progress line (ETA from work()) and the
 *      end-of-run summary (from summary_columns()) for every engine.
 *
 * The driver's calling sequence (run and resume make exactly the same engine calls, so a resumed
 * run is bit for bit the uninterrupted one):
 *   create (factory) -> declare(bufs) -> memory() -> start(seed) | checkpoint_read(file, group, seed)
 *   -> for each output time i >= next: advance(t_i), record(bufs, i) [, checkpoint_write(...)]
 *   -> advance(t_end) -> write_output(file, ntimes): the engine's own groups and the theory.
 * After each record(bufs, i) the driver checks row i of every buffer: non-finite values stop the
 * run with GRAN_ERR_NUMERIC naming the dataset (the partial output keeps rows 0..i-1), except NaN
 * in buffers marked with gran_row_buf_allow_fill, stored as the fill value gran_row_fill.
 *   A run stopped early (signal, progress callback) writes a partial output: write_output(file, next).
 * An engine never writes the output file's common parts and never prints.
 * Replicas: the driver creates one engine per replica (`[engine] replicas`), drives them in OpenMP
 * threads (different engine objects may run concurrently; one object is used by one thread at a
 * time) and, in build/granary-mpi, spreads them over the MPI processes (replica r on rank r mod P;
 * src/io/run_comm.h: rank 0 gathers every replica's rows at each output time and writes the one
 * checkpoint), reduces the row buffers in replica order (mean and standard error: bit for bit the
 * same for any P and thread count) and calls write_output on replica 0 only (its theory and
 * species table serve all replicas). An engine needs nothing of this: it never sees MPI.
 * A gas split over processes (gran_scene.split_gas: a GSRD `[engine] decomposition` on P > R
 * processes; run_impl.h Run.split): each replica is held by a group of P / R processes, every
 * call but write_output is made on every process of the group in the same order (collective),
 * the group records the same rows, and its first process's rows and events are the replica's;
 * the engine reaches its group through its own layer's process group (src/srd/bricks.h), not MPI.
 * Every method returns a granary status (GRAN_ERROR with a named message on failure). */
#ifndef GRANARY_IO_ENGINE_H
#define GRANARY_IO_ENGINE_H

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "io/io_impl.h"

/* One recorded quantity: row i belongs to output time i; the buffer holds [ntimes x row]. */
struct gran_row_buf {
  std::string group, name;       /* HDF5 dataset group/name in the output file */
  int is_int = 0;                /* int64 rows (n) or double rows (d) */
  std::vector<int64_t> row_dims; /* shape of one row ({} for a scalar) */
  int64_t row = 1;               /* elements per row (product of row_dims) */
  std::string units, description;/* written as the dataset's `units` and `description` attributes */
  /* 1: an element may have no value (an empty S(k) shell, a2 of a cell-less gas, ...): the engine
   * records NaN there, and the driver stores gran_row_fill instead, with the dataset attribute
   * _FillValue = gran_row_fill (CF convention: xarray reads such elements back as NaN). Every
   * other element, and every element of a buffer without fill, must be finite: the driver stops
   * the run with GRAN_ERR_NUMERIC otherwise (gran_row_buf_allow_fill). */
  int fill = 0;
  /* the row dims (0-based, in row_dims) that run over the species k = 1..M: the driver attaches
   * its dimension scale `species` (a second such axis: `species_2`) of the group to them, as it
   * attaches the group's `time` to the time axis (gran_row_buf_species_axes) */
  std::vector<int> species_axes;
  std::vector<double> d;
  std::vector<int64_t> n;
};

/* Declare a buffer (the driver sizes it to the scene's output times). */
void gran_row_buf_add(std::vector<gran_row_buf> &bufs, const char *group, const char *name, int is_int,
                      std::vector<int64_t> row_dims, const char *units, const char *description);
/* The fill value of rows that may hold no value: netCDF's default double fill (NC_FILL_DOUBLE). */
constexpr double gran_row_fill = 9.969209968386869e36;
/* Mark buffer group/name as one whose elements may be NaN for "no value" (`when` says when, and
 * is appended to its description). Does nothing when the buffer is not declared. */
void gran_row_buf_allow_fill(std::vector<gran_row_buf> &bufs, const char *group, const char *name, const char *when);
/* Mark row dims `axes` of buffer group/name as species axes. Does nothing when it is not declared. */
void gran_row_buf_species_axes(std::vector<gran_row_buf> &bufs, const char *group, const char *name, std::vector<int> axes);
/* The buffer group/name; nullptr when not declared. */
gran_row_buf *gran_row_buf_find(std::vector<gran_row_buf> &bufs, const char *group, const char *name);

/* `units` and `description` attributes of dataset `name` in group `loc` (every dataset has both). */
int gran_describe_(int64_t loc, const char *name, const char *units, const char *description, const char *file);
/* Dimension scales beside the driver's (`time` and `species` of each row group): dataset `name` of
 * `loc` made a scale of that name; a `species` scale (k = 1..M) in `loc` unless it has one; the
 * scales named in `axes` (one per axis of dataset `name`, "" for none) attached to it. Engines call
 * them for what they write themselves (theory beside the rows, lag and k axes). */
int gran_make_scale_(int64_t loc, const char *name, const char *file);
int gran_species_scale_(int64_t loc, int64_t M, const char *file);
int gran_attach_scales_(int64_t loc, const char *name, const std::vector<std::string> &axes, const char *file);
/* The root attributes naming the units of a run (docs/units.md): `unit_system`, a sentence, and
 * the scene's values of the quantities that set them, `reference_mass`, `reference_length`,
 * `reference_energy` and `reference_time` = length sqrt(mass / energy), in the scene's units.
 * engine: "DSMC" or "GSRD"; mass, length, energy: m_1, sigma_1, <T(t_start)> (DSMC) or the
 * particle mass 1, the cell size a, T0 (GSRD). */
int gran_write_unit_system_(int64_t file, const char *fname, const char *engine, double mass, double length,
                            double energy);

/* Where the engine stands, for the progress line and the run result. */
struct gran_engine_state {
  double time = 0.0;   /* simulated time reached */
  int64_t events = 0;  /* engine events so far (DSMC: accepted collisions), including before a resume */
  double temperature = NAN; /* the gas temperature at the last recorded output time (NaN before one) */
  int32_t work_unit = GRAN_WORK_COLLISIONS; /* what `events` counts */
};

/* One column pair of the end-of-run summary: simulated dataset beside its theory ([ntimes x M]). */
struct gran_summary_column {
  std::string label;   /* short header, e.g. "T" or "MSD" */
  std::string sim;     /* dataset path in the output, e.g. "temperatures/T" */
  std::string theory;  /* dataset path of the theory ("" when none) */
};

class gran_engine {
 public:
  virtual ~gran_engine() = default;
  /* Declare the row buffers of the observables the scene asks for (gran_row_buf_add). */
  virtual int declare(std::vector<gran_row_buf> &bufs) = 0;
  /* Estimated peak bytes of one replica of this scene: the engine with its fixed costs and its
   * recorded rows (the engine's memory model, gran_engine_entry.memory; before
   * start: the driver refuses a run whose replicas would not fit in the memory available). */
  virtual int memory(int64_t *bytes) = 0;
  /* Build the initial state (a fresh run) from `seed`: the scene's seed for replica 0 (so one
   * replica is exactly the run without replicas), a seed drawn from RNG stream r of the scene's
   * seed for replica r >= 1 (gran_rng_stream). Engines use no other source of randomness. */
  virtual int start(uint64_t seed) = 0;
  /* Advance to simulated time t (>= the current time). */
  virtual int advance(double t) = 0;
  virtual int state(gran_engine_state *st) = 0;
  /* Estimated work (any unit, monotone in t) from the scene's start to time t: the progress line's
   * fraction and ETA are work-weighted. DSMC: the theory's expected collision count. */
  virtual int work(int64_t n, const double *t, double *w) = 0; /* w[i] for each t[i] */
  /* Fill row i of every buffer this engine declared. */
  virtual int record(std::vector<gran_row_buf> &bufs, int64_t i) = 0;
  /* The engine's own part of the output file (root attributes such as selector and nspecies, the
   * species table, theory beside the recorded rows, derived analyses). Groups of the declared
   * buffers already exist (with their /time) when this is called. nrec: output times recorded
   * (the scene's count for a finished run; fewer for the partial output of a stopped run, where
   * analyses that need the whole run are left out). */
  virtual int write_output(int64_t file, const char *fname, int64_t nrec) = 0;
  /* Engine state into / out of HDF5 group `group` of the open checkpoint file `file` (`fname`
   * names it in messages). The driver builds the file in memory and writes it with its checksum
   * (gran_h5::commit_memory_file), and verifies that checksum before a read. `seed` is the seed
   * start() would take for this replica: the stored state must have been started from it, and
   * every stored option must be the scene's (each refusal names the option). */
  virtual int checkpoint_write(int64_t file, const char *fname, const char *group) = 0;
  virtual int checkpoint_read(int64_t file, const char *fname, const char *group, uint64_t seed) = 0;
  /* Files of the engine's own beside the checkpoint (a gas split over processes writes its state
   * as one part file per process in checkpoint_write, which the checkpoint then commits: the
   * checkpoint set, docs/developers/domain-decomposition.md). checkpoint_settled is called on every
   * process after each checkpoint: committed = 1, the parts the set no longer needs (of the
   * checkpoint before) go; 0 (the checkpoint failed), the parts just written go.
   * checkpoint_remove: the run finished and its checkpoint is removed, the parts go too. */
  virtual void checkpoint_settled(bool committed) { (void)committed; }
  virtual void checkpoint_remove() {}
  /* Columns of the end-of-run summary (simulated beside theory), only of observables that are on. */
  virtual std::vector<gran_summary_column> summary_columns() const = 0;
  /* Files other than `output` that write_output(file = output) writes (GSRD: the XDMF sidecar).
   * write_output writes each as PATH.tmp only; the driver renames them into place after the
   * output itself is committed, removes the .tmp when that fails, removes a PATH left by an
   * earlier run when this run wrote none, and checks these paths (and their .tmp) against the
   * run's other files before any work. */
  virtual std::vector<std::string> sidecars(const std::string &output) const {
    (void)output;
    return {};
  }
  /* Short name ("dsmc") written as the output's `engine` attribute. */
  virtual const char *type() const = 0;
};

typedef int (*gran_engine_factory)(const gran_scene *s, std::unique_ptr<gran_engine> &out);

/* The engine of the scene's `[engine] type`; named error for an unknown type. */
int gran_engine_create_(const gran_scene *s, std::unique_ptr<gran_engine> &out);

/* ---- the engine table (engine.cpp): one entry per engine ----
 * Besides the factory an entry holds the engine's scene schema (its keys, declared once as data in
 * src/<engine>/scene_<engine>.cpp), the parser of its tables and its memory model
 * (src/<engine>/memory.cpp). The core scene parser (scene.cpp) picks the entry by `[engine] type`
 * (absent: the first, "dsmc"), checks every table's keys against the schema, reads the common
 * keys and [output], and calls `parse` for the rest; `granary keys` prints the schemas. */
namespace gran_scene_io {
class Tab;
}
struct gran_scene_doc;
struct gran_scene_key;
struct gran_engine_entry {
  const char *type;              /* `[engine] type` */
  const char *name;              /* for people: "DSMC (src/dsmc)" */
  gran_engine_factory create;
  const gran_scene_key *keys;    /* the engine's scene keys */
  size_t nkeys;
  /* called before the top-level keys are checked (NULL: none); GSRD names the DSMC tables */
  void (*before)(gran_scene_io::Tab &top);
  /* the engine's tables into the scene; the [engine] table is read here too (with
   * gran_scene_engine_common_ for the shared keys) */
  void (*parse)(const gran_scene_doc &doc, gran_scene &s);
  gran_engine_memory_fn memory;  /* the memory model (io_impl.h) */
};
/* The table (*n entries), and the entry of `type` (NULL when there is none). */
const gran_engine_entry *gran_engine_entries_(size_t *n);
const gran_engine_entry *gran_engine_find_(const std::string &type);

/* Bytes of the row buffers of one replica: nbuf buffers of elems doubles a row over nt output
 * times; each buffer's descriptor (gran_row_buf; 1.5 of them: the vector grows by doubling) and
 * two allocations (its description and its rows). Measured (RSS, VmHWM): 2-D GSRD replicas of 4
 * particles with 21 output times take 9.0 kB each (1000 and 10000 replicas); this model gives 9.9. */
double gran_row_bytes_(double nbuf, double elems, double nt);
/* heap overhead of one allocation (glibc: 16 B header, 16 B rounding on average) */
constexpr double gran_alloc_bytes = 32.0;

/* src/dsmc/scene_dsmc.cpp, src/srd/scene_srd.cpp: the engines' schemas and parsers */
extern const gran_scene_key gran_dsmc_scene_keys_[];
extern const size_t gran_dsmc_scene_nkeys_;
void gran_dsmc_scene_parse_(const gran_scene_doc &doc, gran_scene &s);
extern const gran_scene_key gran_srd_scene_keys_[];
extern const size_t gran_srd_scene_nkeys_;
void gran_srd_scene_before_(gran_scene_io::Tab &top);
void gran_srd_scene_parse_(const gran_scene_doc &doc, gran_scene &s);

/* engine_dsmc.cpp */
int gran_engine_dsmc_create_(const gran_scene *s, std::unique_ptr<gran_engine> &out);
/* engine_srd.cpp (GSRD) */
int gran_engine_srd_create_(const gran_scene *s, std::unique_ptr<gran_engine> &out);

/* run_files.cpp: where a stopped run writes what it recorded (OUT.h5 -> OUT.partial.h5), and the
 * checkpoint path of a run (NULL checkpoint: the scene's; its default OUTPUT.ckpt follows output). */
std::string gran_partial_path_(const std::string &out);
/* A file's identity as the run driver compares its files ("inode dev:ino" when it exists, else the
 * real path of its folder and its name): the CLI's log check uses the same rule. */
std::string gran_file_identity_(const std::string &path);
/* mkdir -p of the folder holding `path` (as the run driver does for its output and checkpoint). */
int gran_make_parent_(const std::string &path);
std::string gran_run_checkpoint_path_(const gran_scene *s, const char *output, const char *checkpoint);

#endif
