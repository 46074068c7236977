/* fuzz_run_scene.cc - libFuzzer harness that parses a scene of any engine (low-rank, Bird, the cell
 * selector with or without aggregation, GSRD 2-D/3-D with walls, shear, gravity) and runs it for
 * a few steps: the DSMC engines through gran_scene_dsmc and their observables, then every engine
 * through gran_scene_run, stopped after its second output time, and the output file it wrote is
 * scanned for non-finite values. Every status must be a listed code with a message; nothing
 * returned or written with GRAN_SUCCESS may be inf or NaN.
 *
 * Work is bounded before anything runs: scenes above the caps below (particles, cells, species,
 * output times, replicas, steps or collisions to the stop) are skipped. The public API has no size
 * query for GSRD scenes, so the parsed scene's fields are read from the library's own declaration
 * (src/io/io_impl.h); nothing is changed in it. */
#include <algorithm>

#include "fuzz_common.h"
#include "io/io_impl.h"

namespace {

const double kMaxParticles = 4096;   /* per replica */
const double kMaxCells = 8192;       /* GSRD cells (wall layer included), cell-selector cells */
const int64_t kMaxSpecies = 64;
const int64_t kMaxTimes = 2000;
const int64_t kMaxReplicas = 4;
const int64_t kMaxSteps = 200;       /* GSRD / cell steps to the stop */
const double kRefuseAbove = 1e15;    /* more steps than this: the library must refuse the scene */
const double kMaxStepWork = 1e5;     /* steps x particles */
const int64_t kMaxCollisions = 4000; /* event selectors: collisions to the stop (measured first) */
const int64_t kStopAfter = 2;        /* output times recorded before the run is stopped */

int stop_at(const gran_run_progress *p, void *params) {
  (void)params;
  return p->output_index >= kStopAfter;
}

/* the DSMC engine of the scene, stepped and observed; returns 1 when the run to the stop is
 * within the caps (the driver replays the same engine: replica 0 uses the scene's seed) */
int run_dsmc(const gran_scene *s, double t_stop) {
  gran_mixture *mix = nullptr;
  if (fz::check(gran_scene_mixture(s, &mix), "gran_scene_mixture")) return 0;
  gran_dsmc *sim = nullptr;
  int st = fz::check(gran_scene_dsmc(s, mix, &sim), "gran_scene_dsmc");
  int within = 0;
  if (st == GRAN_SUCCESS) {
    const int64_t M = s->nspecies;
    std::vector<int64_t> n((size_t)M);
    std::vector<double> T((size_t)M), a2((size_t)M);
    const bool cell = s->selector == GRAN_SELECTOR_CELL;
    const bool agg = cell ? (s->cell.e_agg > 0 || std::isfinite(s->cell.e_frag))
                          : (s->agg.e_agg > 0 || std::isfinite(s->agg.e_frag));
    double t = s->t_start;
    for (int round = 0; round < 16; ++round) {
      if (cell) {
        const double dt = s->cell.dt, tn = std::min(t_stop, t + 25 * dt);
        st = fz::check(gran_dsmc_advance(sim, tn), "gran_dsmc_advance (cell)");
      } else {
        st = fz::check(gran_dsmc_advance_collisions(sim, kMaxCollisions / 16), "gran_dsmc_advance_collisions");
      }
      if (st) break;
      gran_dsmc_stats ss;
      if (fz::check(gran_dsmc_get_stats(sim, &ss), "gran_dsmc_get_stats")) break;
      fz::finite_or_fail(ss.time, "gran_dsmc_get_stats time");
      if (!(ss.time >= t)) fz::fail("time went backwards", "gran_dsmc_get_stats");
      t = ss.time;
      if (!fz::check(gran_dsmc_counts(sim, n.data()), "gran_dsmc_counts") &&
          !fz::check(gran_dsmc_temperatures(sim, T.data()), "gran_dsmc_temperatures"))
        for (int64_t k = 0; k < M; ++k)
          if (n[(size_t)k] > 0) fz::finite_or_fail(T[(size_t)k], "gran_dsmc_temperatures (non-empty species)");
      if (!fz::check(gran_dsmc_sonine_a2(sim, a2.data()), "gran_dsmc_sonine_a2"))
        for (int64_t k = 0; k < M; ++k)
          if (n[(size_t)k] >= 8) fz::finite_or_fail(a2[(size_t)k], "gran_dsmc_sonine_a2 (>= 8 particles)");
      double e[3], p[3];
      if (!fz::check(gran_dsmc_energy(sim, &e[0], &e[1], &e[2]), "gran_dsmc_energy"))
        for (double x : e) fz::finite_or_fail(x, "gran_dsmc_energy");
      if (!fz::check(gran_dsmc_momentum(sim, p), "gran_dsmc_momentum"))
        for (double x : p) fz::finite_or_fail(x, "gran_dsmc_momentum");
      if (agg) {
        gran_dsmc_cluster_stats cs;
        if (!fz::check(gran_dsmc_get_cluster_stats(sim, &cs), "gran_dsmc_get_cluster_stats")) {
          const double v[] = {cs.mean_size, cs.e_bounce, cs.e_merge, cs.e_break, cs.e_heat};
          for (double x : v) fz::finite_or_fail(x, "gran_dsmc_get_cluster_stats");
        }
      }
      if (t >= t_stop) {
        within = 1;
        break;
      }
    }
    gran_dsmc_destroy(&sim);
  }
  gran_mixture_destroy(&mix);
  return within;
}

/* the scene's sizes against the caps: 0 skip, 1 run, 2 run the driver only (more steps to the stop
 * than any scene may ask for: the run must be refused, else it hangs and the timeout reports it);
 * the stop time (absolute) in *t_stop */
int small_enough(const gran_scene *s, double *t_stop) {
  if (s->replicas > kMaxReplicas) return 0;
  const int64_t nt = (int64_t)s->times.size();
  if (nt > kMaxTimes) return 0;
  const bool stops = nt >= kStopAfter; /* else the run goes to its end */
  if (s->engine_type == "srd") {
    const gran_srd_options &o = s->srd.opt;
    double box = 1, bin = 1;
    for (int k = 0; k < o.dim; ++k) {
      box *= (double)o.cells[k];
      bin *= (double)o.cells[k] + (k == o.wall_axis ? 1 : 0);
    }
    const double N = std::floor(o.n0 * box + 0.5);
    if (N > kMaxParticles || bin > kMaxCells) return 0;
    if (s->srd.obs_sk && s->srd.sk_bins > 4096) return 0;
    const double steps = (double)(stops ? s->srd.out_steps[kStopAfter - 1] : s->srd.steps);
    if (steps > kRefuseAbove) return 2;
    return steps <= kMaxSteps && steps * N <= kMaxStepWork;
  }
  if (s->nspecies > kMaxSpecies) return 0;
  const bool cell = s->selector == GRAN_SELECTOR_CELL;
  double N = 0;
  for (int64_t k = 0; k < s->nspecies; ++k)
    N += s->counts_kind == 0 ? (double)s->counts[(size_t)k]
                             : std::nearbyint(s->density[(size_t)k] * s->volume / (cell ? s->cell.fn : 1.0));
  if (!(N <= kMaxParticles)) return 0;
  if (s->obs_tamsd && (double)s->tamsd_tracers * (double)s->nspecies * (double)s->tamsd_samples > 1e5) return 0;
  if (s->obs_veldist && s->vd_bins > 10000) return 0;
  *t_stop = stops ? s->times[kStopAfter - 1] : std::max(s->t_end, nt > 0 ? s->times[(size_t)nt - 1] : s->t_end);
  if (cell) {
    if ((double)s->cell.cells * (double)s->cell.cells * (double)s->cell.cells > kMaxCells) return 0;
    const double steps = (*t_stop - s->t_start) / s->cell.dt;
    if (!(steps <= kRefuseAbove)) return 2;
    if (!(steps <= (double)kMaxSteps) || steps * N > kMaxStepWork) return 0;
  }
  return 1;
}

}  // namespace

/* Mutations: a third of them libFuzzer's own, two thirds replace one number of the scene (outside strings
 * and comments) by an edge value in TOML spelling (1e300, nan, 5e-324, 2^63-1, ...), which byte
 * mutations of ASCII text rarely produce. Deterministic in the seed libFuzzer passes. */
extern "C" size_t LLVMFuzzerMutate(uint8_t *data, size_t size, size_t max);
extern "C" size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max, unsigned seed) {
  uint64_t r = seed * 6364136223846793005ULL + 1442695040888963407ULL;
  if ((r >> 33) % 3 == 0) return LLVMFuzzerMutate(data, size, max);
  const auto nums = fz::toml_numbers((const char *)data, size);
  if (nums.empty()) return LLVMFuzzerMutate(data, size, max);
  const auto &at = nums[(size_t)((r >> 40) % nums.size())];
  const char *v = fz::toml_edge((unsigned)(r >> 20));
  const size_t lv = std::strlen(v), tail = size - at.second;
  if (size - (at.second - at.first) + lv > max) return LLVMFuzzerMutate(data, size, max);
  std::memmove(data + at.first + lv, data + at.second, tail);
  std::memcpy(data + at.first, v, lv);
  return at.first + lv + tail;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fz::setup();
  std::string text((const char *)data, size);
  gran_scene *s = nullptr;
  if (fz::check(gran_scene_parse(text.c_str(), "fuzz.toml", &s), "gran_scene_parse")) return 0;
  double t_stop = 0;
  const int size_class = small_enough(s, &t_stop);
  if (size_class) {
    const bool drive = size_class == 2 || s->engine_type == "srd" || run_dsmc(s, t_stop);
    if (drive) {
      const std::string out = fz::scratch() + "/out.h5";
      gran_run_control ctl = {0, stop_at, nullptr};
      gran_run_result res;
      const int st = fz::check(gran_scene_run(s, out.c_str(), "", &ctl, &res), "gran_scene_run");
      if (st == GRAN_SUCCESS) {
        fz::finite_or_fail(res.time, "gran_run_result time");
        const std::string file = res.finished ? out : fz::scratch() + "/out.partial.h5";
        fz::output_nonfinite(fz::scan_h5(file));
      }
      fz::clean_scratch();
    }
  }
  gran_scene_destroy(&s);
  return 0;
}
