/* io_impl.h - private declarations of the io module (scenes, runs, HDF5 output, checkpoints).
 * scene.cpp parses and validates a TOML scene into gran_scene; run.cpp drives the engine and
 * writes HDF5 (h5.cpp holds the thin HDF5 helpers). */
#ifndef GRANARY_IO_IMPL_H
#define GRANARY_IO_IMPL_H

#include <string>
#include <vector>

#include "granary_impl.h"

enum scene_init { SCENE_INIT_HCS = 0, SCENE_INIT_EQUAL = 1, SCENE_INIT_LIST = 2 };

/* The validated scene. Every field has its default filled in by the parser. */
struct gran_scene {
  std::string text;  /* the whole scene file */
  std::string name;  /* file name used in messages */
  std::string title;

  /* [mixture] */
  int64_t nspecies = 0;
  std::vector<double> mass, sigma, density;
  int g2_is_matrix = 0;
  double g2 = 1.0;
  std::vector<double> g2_matrix;

  /* [restitution] */
  int model = GRAN_RESTITUTION_CONSTANT;
  double eps = 1.0;
  std::vector<double> eps_matrix;
  int visco_kind = 0; /* 0 beta, 1 beta_matrix, 2 material */
  double beta = 0.0;
  std::vector<double> beta_matrix;
  double mat_A = 0, mat_Y = 0, mat_nu = 0;

  /* [initial] */
  int init = SCENE_INIT_HCS;
  int hcs_norm = GRAN_HCS_NORM_MEAN;
  double T_value = 1.0;
  std::vector<double> T_list;
  double t_start = 0.0;

  /* [engine] */
  std::string engine_type = "dsmc"; /* `[engine] type`: the key of the engine table (src/io/engine.cpp) */
  int selector = GRAN_SELECTOR_LOWRANK;
  uint64_t seed = 1;
  double t_end = 0.0;
  int counts_kind = 0; /* 0 counts, 1 N1, 2 volume */
  std::vector<int64_t> counts;
  double N1 = 0.0;
  double volume = 0.0;
  int64_t bound_refresh = 0;
  int speed_classes = -1; /* `[engine] speed_classes`: gran_dsmc_options.speed_classes (-1: auto) */
  int64_t replicas = 1;   /* independent runs (run.cpp); replica r draws from RNG stream r of seed */
  double max_memory = 0;  /* [engine] max_memory_gb in bytes; 0: MemAvailable at the check */
  int keep_replicas = 0;  /* also write the per-replica rows */
  /* the engine's one gas is split over the run's processes (GSRD `[engine] decomposition`): under
   * build/granary-mpi on P > 1 processes every process holds a part of replica 0 and every engine
   * call is collective (run.cpp); in one process it changes nothing */
  int split_gas = 0;

  /* [cell] (selector = "cell": src/dsmc/cell.cpp) */
  gran_dsmc_cell_options cell{};
  /* [aggregation] of the event selectors (src/dsmc/agg_event.cpp); for "cell" it fills cell */
  gran_dsmc_agg_options agg{};

  /* [observables] */
  std::vector<double> times;
  int obs_temperatures = 1, obs_msd = 1, obs_energy = 1, obs_momentum = 0;
  int obs_collision_counts = 0, obs_sonine_a2 = 0, obs_theory = 1;
  int obs_theory_sonine = 0; /* T_theory_sonine, a2_theory_sonine beside T_theory */
  int64_t theory_sonine_order = 2; /* 2: first Sonine level (a2); 3: second (a2, a3, a3_theory_sonine) */
  double theory_rtol = 1e-8;
  int obs_veldist = 0;
  int64_t vd_bins = 60;
  double vd_cmax = 4.0;
  int obs_tamsd = 0;
  int64_t tamsd_tracers = 0;
  double tamsd_dt = 0.0;
  int64_t tamsd_samples = 0;
  std::vector<double> tamsd_lags;

  /* [output] */
  std::string output_path;
  std::string checkpoint_path; /* "" = none */
  int checkpoint_explicit = 0;  /* 1: [output] checkpoint was given (else it follows the output path) */
  double checkpoint_interval = 600.0;
  int64_t checkpoint_every = 0;
  int keep_checkpoint = 0;

  /* ---- GSRD scenes (`[engine] type = "srd"`; parsed by src/srd/scene_srd.cpp, run by
   * src/io/engine_srd.cpp). The DSMC fields above keep their defaults in such a scene. ---- */
  struct srd_part {
    gran_srd_options opt = {};       /* every engine key, as gran_srd_create takes it */
    std::string device = "cpu";      /* [engine] device: "cpu" | "cuda" | "auto" */
    int64_t steps = 0;               /* steps of the run (t_end = steps dt) */
    std::vector<int64_t> out_steps;  /* step of each output time (times[i] = out_steps[i] dt) */
    int obs_temperature = 1, obs_energy = 1, obs_momentum = 1, obs_clustering = 1, obs_a2 = 0;
    int obs_sk = 0, obs_stress = 0, obs_profile = 0, obs_theory = 1;
    int64_t sk_bins = 0;             /* S(k) shells (0: cells[0] / 2) */
    std::vector<int64_t> snap_index; /* output indices with a field snapshot */
    int decomp_grid[3] = {0, 0, 0};  /* [engine] decomposition: bricks per axis; 0 0 0 "auto" (split_gas) */
  } srd;
};

/* One scene key, declared once by the engine that reads it (or by the core for the keys every
 * engine shares). `granary keys` prints these; the parser takes the known keys of each table, the
 * defaults and (where `why` is given) the bounds from here. */
struct gran_scene_key {
  const char *table;   /* dotted table path ("engine", "boundaries.walls"); "" for the top level */
  const char *name;    /* key */
  const char *type;    /* TOML type(s) as documented: "float", "integer", "boolean", "string", "table", ... */
  const char *def;     /* default as written in a scene ("1.0", "\"cpu\"", "true"); other text (or "") when
                        * it is derived or the key is required: the parser then gives it itself */
  const char *bounds;  /* bounds as text; when `why` is set, one of "> a", ">= a", "< a", "<= a", "[a, b]",
                        * "(a, b]", "[a, b)", "(a, b)" or "a..b" (integers), checked by the reader */
  const char *unit;    /* unit of the value ("" : none) */
  const char *meaning; /* one line */
  const char *field;   /* the C field it fills */
  const char *why;     /* message when the bounds fail ("{}": the value); "": checked by the engine's code */
};

/* The keys one scene may hold: the core's shared keys and the engine's own. */
struct gran_scene_schema {
  const gran_scene_key *common;
  size_t ncommon;
  const gran_scene_key *keys;
  size_t nkeys;
};

/* The keys the core declares (title, the tables every engine has, the common [engine] keys,
 * [output]); *n of them. */
const gran_scene_key *gran_scene_common_keys_(size_t *n);

/* Problems of a schema ("" : none): a `why` without checkable bounds, an empty name or meaning
 * (scene.cpp; `granary keys` and its test refuse such a schema). */
std::string gran_scene_schema_problems_(const gran_scene_key *keys, size_t n);
/* `b` holds a checkable bound (see gran_scene_key.bounds); *ok: whether v satisfies it */
bool gran_scene_bounds_(const char *b, double v, bool *ok);

/* scene.cpp */
int gran_scene_parse_text_(const std::string &text, const std::string &name, gran_scene **scene);
/* Initial temperatures of the scene (HCS solved with the theory module when asked) and tau0. */
int gran_scene_T0_(const gran_scene *s, const gran_mixture *mix, double *T0, double *tau0);
/* Whether the cell selector's scene is driven (white-noise thermostat or molecular-gas bath), and
 * its temperatures T (ntimes*M) at times t from T0 by gran_theory_temperatures_driven: the heating
 * of species k is heat_rate (1 - m_k / sum_j N_j m_j) (the thermostat's mean kick removed), the
 * bath that of [cell]. */
bool gran_scene_driven_(const gran_scene *s);
int gran_scene_driven_temperatures_(const gran_scene *s, const gran_mixture *mix, const double *T0, int64_t ntimes,
                                    const double *t, double rtol, double *T);
/* The memory model of an engine (src/<engine>/memory.cpp), by part: what it is, the scene key that
 * sets it (named when the run does not fit), and its bytes. The engine adapter's
 * gran_engine::memory is the sum of `engine`; the scene check (load time, and again when the
 * replicas change) is the sum of replicas x `peak` + `once`. */
struct gran_mem_part {
  const char *what, *table, *key;
  double engine; /* one replica's engine and its recorded rows */
  double peak;   /* one replica at the run's peak (the engine, plus a checkpoint image or a copy) */
  double once;   /* once per run, whatever the replicas */
};
/* Fills parts (cleared first); returns the sum of `engine` (one replica). */
typedef double (*gran_engine_memory_fn)(const gran_scene &s, std::vector<gran_mem_part> &parts);
/* src/dsmc/memory.cpp: particles (28 B of state, +32 B of displacement with msd or tamsd, +24 B
 * for the selector's trees and speed classes, +36 B of positions and cell lists and 48 B per cell
 * for the cell selector; twice while a checkpoint image is assembled), species arrays and trees,
 * M x M tables where the scene asks for them, TAMSD trajectories (twice while the TAMSD is
 * computed), the structs, the recorded rows, once per run the dense theory Jacobian (M <= 2048). */
double gran_dsmc_memory_(const gran_scene &s, std::vector<gran_mem_part> &parts);
/* src/srd/memory.cpp: one GSRD CPU engine (src/srd/srd_impl.h): particles (48 B of state, 2 B of
 * slab list, +12 B while the cells are sorted every sort_every steps; their state once more while
 * a checkpoint image is assembled), cells of the binning grid (24 B reference velocity + 32 B RNG
 * + 8 B of sort offsets) plus each thread's slab work space (64 B per cell and 4 B per particle of
 * one slab of SRD_SLAB_CELLS cells), the field snapshots of replica 0 (5 doubles per cell each),
 * the structs, the recorded rows. */
double gran_srd_memory_(const gran_scene &s, std::vector<gran_mem_part> &parts);
/* The memory check of a parsed scene after an override of what it runs (replicas): the scene's
 * engine's memory model (gran_engine_entry.memory) for every replica against
 * [engine] max_memory_gb, else MemAvailable; GRAN_ERR_NOMEM naming `key` (the override) when it
 * does not fit. */
int gran_scene_check_memory_(const gran_scene *s, const char *key);
/* The bytes the run of this scene may use: [engine] max_memory_gb, else MemAvailable now. */
double gran_scene_memory_limit_(const gran_scene *s);
/* MemAvailable of this machine now (bytes; what the kernel can hand out without swapping). */
double gran_memory_available_(void);
/* on != 0: the scenes this thread loads or overrides (gran_scene_load, gran_scene_parse, gran_scene_set)
 * skip the check of the whole run's memory against one machine's; the caller checks what each process
 * will hold (granary decompose: each brick's share) before it creates anything. 0: the check again. */
void gran_scene_defer_memory_check_(int on);

/* h5.cpp: thin helpers. Every function returns a granary status; the file name goes in messages. */
namespace gran_h5 {
int64_t open_file(const char *path, int readwrite);   /* < 0 on failure */
void close_file(int64_t f);
int write_double(int64_t loc, const char *name, const std::vector<int64_t> &dims, const double *data,
                 const char *file);
int write_int64(int64_t loc, const char *name, const std::vector<int64_t> &dims, const int64_t *data,
                const char *file);
int read_double(int64_t loc, const char *name, std::vector<double> &out, std::vector<int64_t> *dims,
                const char *file);
int read_int64(int64_t loc, const char *name, std::vector<int64_t> &out, std::vector<int64_t> *dims,
               const char *file);
int make_group(int64_t loc, const char *name, int64_t *group, const char *file);
void close_group(int64_t g);
int attr_string(int64_t loc, const char *name, const std::string &value, const char *file);
int attr_double(int64_t loc, const char *name, double value, const char *file);
int attr_int64(int64_t loc, const char *name, int64_t value, const char *file);
int attr_uint64(int64_t loc, const char *name, uint64_t value, const char *file);
int read_attr_string(int64_t loc, const char *name, std::string &value, const char *file);
int read_attr_int64(int64_t loc, const char *name, int64_t *value, const char *file);
int exists(int64_t loc, const char *name);
/* Files built in memory and committed with a checksum (see h5.cpp): create_memory_file() < 0 on
 * failure; commit_memory_file() closes *file (sets it to -1) and writes PATH.tmp -> PATH;
 * verify_file() checks the header and checksum before HDF5 reads the file. `what` names the file
 * in messages ("output file", "checkpoint"). */
int64_t create_memory_file();
int commit_memory_file(int64_t *file, const std::string &path, const char *what);
int verify_file(const char *path, const char *what);
/* verify_file when the file starts with granary's header; other HDF5 files pass unchecked */
int verify_file_if_marked(const char *path, const char *what);
}  // namespace gran_h5

/* Flush a closed file to disk (fsync) and rename it over its final name; then fsync the folder. */
int gran_io_commit_file_(const std::string &tmp, const std::string &path);

#endif
