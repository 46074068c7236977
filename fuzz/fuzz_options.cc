/* fuzz_options.cc - libFuzzer harness for the option structs of the engines' C API: the first byte
 * picks gran_srd_create, gran_dsmc_create_cell or gran_dsmc_create_agg; every field of the options
 * (and of the mixture, counts and start temperatures of the DSMC engines) is then its default or,
 * as the bytes ask, an edge value (NaN, inf, 1e300, 5e-324, -0, 2^63-1, ...), a scaled default or
 * raw bits. What is created is stepped a few times and observed (GSRD: also with velocities
 * written through gran_srd_particles), then destroyed. Every status must be a listed code with a
 * message; nothing returned with GRAN_SUCCESS may be inf or NaN.
 *
 * Work is bounded here, not by the library: option sets above the caps (particles, cells, counts)
 * are not created, and the steps asked for are few. Threads are the defaults' unless the bytes ask
 * for another value, which the library must bound. */
#include <algorithm>

#include "fuzz_common.h"
#include "srd/bricks.h"

namespace {

const double kMaxParticles = 4096;
const double kMaxCells = 16384;

void obs_srd(gran_srd *srd, const char *when) {
  gran_srd_obs o;
  if (fz::check(gran_srd_observe(srd, &o), "gran_srd_observe")) return;
  const double v[] = {o.time,        o.temperature, o.theta_cells, o.energy,      o.e_initial, o.e_collisions,
                      o.e_external,  o.ledger_error, o.momentum[0], o.momentum[1], o.momentum[2], o.e_kin,
                      o.mach,        o.sigma_rho,   o.a2,          o.stress_xy,   o.stress_kin};
  static const char *names[] = {"time", "temperature", "theta_cells", "energy", "e_initial", "e_collisions",
                                "e_external", "ledger_error", "momentum[0]", "momentum[1]", "momentum[2]",
                                "e_kin", "mach", "sigma_rho", "a2", "stress_xy", "stress_kin"};
  for (size_t k = 0; k < sizeof v / sizeof v[0]; ++k) {
    char b[96];
    std::snprintf(b, sizeof b, "gran_srd_observe %s (%s)", names[k], when);
    fz::finite_or_fail(v[k], b);
  }
  if (!(o.dt_max >= 0)) fz::fail("gran_srd_observe dt_max is NaN or negative", when);
}

/* the decomposable engine split into bricks of the bytes' grid against the undivided engine: the
 * same status, and on success the same particles, cells and ledger, S(k), observables and velocity
 * profile bit for bit */
void bricks_against_plain(const gran_srd_options &o, fz::Bytes &in) {
  const int d = o.dim == 3 ? 3 : 2;
  int pg[3] = {1, 1, 1};
  for (int a = 0; a < d; ++a) pg[a] = 1 + (int)(in.u8() % (uint8_t)std::min<int64_t>(4, o.cells[a] + (a == o.wall_axis)));
  const int64_t steps = 1 + in.u8() % 6, nbins = 1 + in.u8() % 8;
  srd_bricks_out b, p;
  const int eb = srd_bricks_run_(&o, pg, steps, 1, &b);
  gran_srd *s = nullptr;
  int ep = gran_srd_create(&o, &s);
  if (ep == GRAN_SUCCESS) ep = gran_srd_advance(s, steps);
  double kp[8], sp[8], kb[8], sb[8];
  int64_t cp[8], cb[8];
  const int esp = ep == GRAN_SUCCESS ? gran_srd_structure_factor(s, nbins, kp, sp, cp) : ep;
  if (ep == GRAN_SUCCESS) ep = srd_bricks_gather_plain_(s, &p);
  /* the observables with the velocity profile (after the gather: an observation resets the clamps) */
  gran_srd_obs op, ob;
  std::vector<double> up((size_t)(3 * o.cells[1])), ub(up.size());
  const int eop = ep == GRAN_SUCCESS ? srd_cells_observe_(s, &op, up.data()) : ep;
  gran_srd_destroy(&s);
  if (ep == GRAN_SUCCESS) { /* S(k) of the split gas: the undivided engine's status and bits */
    srd_bricks_state *st = nullptr;
    int esb = srd_bricks_open_(&o, pg, nullptr, &st);
    if (esb == GRAN_SUCCESS) esb = srd_bricks_step_(st, steps);
    if (esb == GRAN_SUCCESS) esb = srd_bricks_structure_factor_(st, nbins, kb, sb, cb);
    const int eob = esb == GRAN_SUCCESS ? srd_bricks_observe_profile_(st, &ob, ub.data()) : esb;
    srd_bricks_close_(&st);
    if (esb == GRAN_SUCCESS && (eob == GRAN_SUCCESS) != (eop == GRAN_SUCCESS)) {
      std::fprintf(stderr, "fuzz: observables of bricks %d x %d x %d: status %d, the undivided engine %d (%s)\n", pg[0],
                   pg[1], pg[2], eob, eop, gran_last_error_message());
      fz::fail("srd_bricks_observe_profile_ and srd_cells_observe_ disagree on success", "bricks observables");
    }
    if (esb == GRAN_SUCCESS && eob == GRAN_SUCCESS &&
        (std::memcmp(&ob, &op, sizeof ob) || std::memcmp(ub.data(), up.data(), ub.size() * sizeof(double))))
      fz::fail("the split gas's observables or velocity profile differ from the undivided engine's", "bricks observables");
    if ((esb == GRAN_SUCCESS) != (esp == GRAN_SUCCESS)) {
      std::fprintf(stderr, "fuzz: S(k) of bricks %d x %d x %d: status %d, the undivided engine %d (%s)\n", pg[0], pg[1],
                   pg[2], esb, esp, gran_last_error_message());
      fz::fail("srd_bricks_structure_factor_ and gran_srd_structure_factor disagree on success", "bricks S(k)");
    }
    if (esb == GRAN_SUCCESS)
      for (int64_t q = 0; q < nbins; ++q) {
        fz::finite_or_fail(sb[q], "the split gas's S(k)");
        if (cb[q] != cp[q] || std::memcmp(&sb[q], &sp[q], sizeof sb[q]) || std::memcmp(&kb[q], &kp[q], sizeof kb[q]))
          fz::fail("the split gas's S(k) differs from the undivided engine's", "bricks S(k)");
      }
  }
  if ((eb == GRAN_SUCCESS) != (ep == GRAN_SUCCESS)) {
    std::fprintf(stderr, "fuzz: bricks %d x %d x %d, %lld steps: status %d, the undivided engine %d (%s)\n", pg[0], pg[1],
                 pg[2], (long long)steps, eb, ep, gran_last_error_message());
    fz::fail("srd_bricks_run_ and gran_srd_advance disagree on success", "bricks");
  }
  if (eb != GRAN_SUCCESS) return;
  uint64_t b1, b2, p1, p2;
  srd_bricks_digest_(&b, d, &b1, &b2);
  srd_bricks_digest_(&p, d, &p1, &p2);
  const bool same = b1 == p1 && b2 == p2 && b.n == p.n && !std::memcmp(&b.e_coll, &p.e_coll, sizeof b.e_coll) &&
                    !std::memcmp(&b.e_ext, &p.e_ext, sizeof b.e_ext) && b.clamped == p.clamped && b.step == p.step;
  srd_bricks_out_free_(&b);
  srd_bricks_out_free_(&p);
  if (!same) {
    std::fprintf(stderr, "fuzz: bricks %d x %d x %d, %lld steps differ from the undivided engine\n", pg[0], pg[1], pg[2],
                 (long long)steps);
    fz::fail("the split run differs from the undivided engine", "bricks");
  }
}

void run_srd(fz::Bytes &in) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = in.i32(in.u8() & 1 ? 3 : 2, 1, 4);
  o.cells[0] = in.i64(8, 1, 16);
  o.cells[1] = in.i64(6, 1, 16);
  o.cells[2] = in.i64(4, 1, 16);
  o.n0 = in.dbl(4);
  o.a = in.dbl(1);
  o.dt = in.dbl(0.5);
  o.alpha_deg = in.dbl(120);
  o.eps = in.dbl(0.9);
  o.sigma = in.dbl(0.1);
  o.T0 = in.dbl(1);
  o.shear_rate = in.dbl(0);
  for (double &g : o.accel) g = in.dbl(0);
  o.wall_axis = in.i32(-1, -1, 3);
  o.wall_rule = in.i32(1, 0, 3);
  o.vib_amp = in.dbl(0);
  o.vib_omega = in.dbl(0);
  o.wall_T = in.dbl(0);
  o.thermostat = in.i32(0, -1, 3);
  o.seed = in.u8() < 128 ? 7 : in.u64();
  o.sort_every = in.i32(2, -1, 8);
  o.threads = in.i32(1, 0, 2);
  o.device = in.i32(0, -1, 4); /* 3: the GPU algorithm on the host (float storage with precision 1) */
  o.precision = in.i32(0, -1, 2);
  o.creation = in.i32(0, -1, 2); /* 1: creation by cells and the decomposable engine (src/srd/bricks.cpp) */
  /* the caps, for options the library would otherwise accept */
  double box = 1, bin = 1;
  const int d = o.dim == 3 ? 3 : 2;
  for (int k = 0; k < d; ++k) {
    box *= (double)std::max<int64_t>(o.cells[k], 1);
    bin *= (double)std::max<int64_t>(o.cells[k], 1) + (k == o.wall_axis ? 1 : 0);
  }
  if (bin > kMaxCells || (std::isfinite(o.n0) && o.n0 * box > kMaxParticles)) return;
  if (getenv("GRAN_FUZZ_VERBOSE"))
    std::fprintf(stderr,
                 "fuzz: srd options creation %d dim %d cells %lld %lld %lld a %g n0 %g dt %g alpha %g eps %g sigma %g T0 %g shear %g "
                 "accel %g %g %g wall_axis %d rule %d vib %g %g wall_T %g thermostat %d seed %llu sort %d threads %d "
                 "device %d precision %d\n",
                 o.creation, o.dim, (long long)o.cells[0], (long long)o.cells[1], (long long)o.cells[2], o.a, o.n0, o.dt,
                 o.alpha_deg, o.eps, o.sigma, o.T0, o.shear_rate, o.accel[0], o.accel[1], o.accel[2], o.wall_axis,
                 o.wall_rule, o.vib_amp, o.vib_omega, o.wall_T, o.thermostat, (unsigned long long)o.seed, o.sort_every,
                 o.threads, o.device, o.precision);
  gran_srd *srd = nullptr;
  if (fz::check(gran_srd_create(&o, &srd), "gran_srd_create")) return;
  obs_srd(srd, "created");
  if (o.creation == GRAN_SRD_CREATE_CELLS && o.device == GRAN_SRD_DEVICE_CPU && in.u8() >= 128)
    bricks_against_plain(o, in);
  for (int r = 0; r < 3; ++r) {
    if (in.u8() >= 200) { /* velocities or positions written through gran_srd_particles */
      int64_t n = 0;
      double *x, *y, *z, *vx, *vy, *vz;
      if (!fz::check(gran_srd_particles(srd, &n, &x, &y, &z, &vx, &vy, &vz), "gran_srd_particles") && n > 0) {
        double *arr[] = {x, y, z, vx, vy, vz};
        double *a = arr[in.u8() % 6];
        if (a) a[in.u16() % n] = in.edge_double();
      }
    }
    if (fz::check(gran_srd_advance(srd, 1 + in.u8() % 3), "gran_srd_advance")) break;
    obs_srd(srd, "advanced");
    if (in.u8() >= 230) {
      double k[8], s[8];
      int64_t c[8];
      const int64_t nb = 1 + in.u8() % 8;
      if (!fz::check(gran_srd_structure_factor(srd, nb, k, s, c), "gran_srd_structure_factor"))
        for (int64_t i = 0; i < nb; ++i) /* an empty shell has no S(k); one with modes has a finite one */
          if (c[i] > 0) fz::finite_or_fail(s[i], "gran_srd_structure_factor (shell with modes)");
    }
  }
  gran_srd_destroy(&srd);
}

/* a mixture of M species from the bytes: k-mers (aggregation needs them) or free values */
gran_mixture *mixture(fz::Bytes &in, int64_t M, bool kmers) {
  std::vector<double> m((size_t)M), sg((size_t)M), n((size_t)M);
  for (int64_t k = 0; k < M; ++k) {
    const double km = (double)(k + 1);
    m[(size_t)k] = kmers ? km : in.dbl(km);
    sg[(size_t)k] = kmers ? std::cbrt(km) : in.dbl(std::cbrt(km));
    n[(size_t)k] = in.dbl(0.05 / km);
  }
  gran_mixture *mix = nullptr;
  if (fz::check(gran_mixture_create(M, m.data(), sg.data(), n.data(), &mix), "gran_mixture_create")) return nullptr;
  if (fz::check(gran_mixture_set_restitution(mix, in.dbl(0.9)), "gran_mixture_set_restitution")) {
    gran_mixture_destroy(&mix);
    return nullptr;
  }
  if (in.u8() >= 220) fz::check(gran_mixture_set_g2(mix, in.dbl(1.0)), "gran_mixture_set_g2");
  return mix;
}

void obs_dsmc(gran_dsmc *sim, int64_t M, bool agg) {
  gran_dsmc_stats ss;
  if (!fz::check(gran_dsmc_get_stats(sim, &ss), "gran_dsmc_get_stats")) {
    fz::finite_or_fail(ss.time, "gran_dsmc_get_stats time");
    fz::finite_or_fail(ss.volume, "gran_dsmc_get_stats volume");
  }
  std::vector<int64_t> n((size_t)M);
  std::vector<double> T((size_t)M);
  if (!fz::check(gran_dsmc_counts(sim, n.data()), "gran_dsmc_counts") &&
      !fz::check(gran_dsmc_temperatures(sim, T.data()), "gran_dsmc_temperatures"))
    for (int64_t k = 0; k < M; ++k)
      if (n[(size_t)k] > 0) fz::finite_or_fail(T[(size_t)k], "gran_dsmc_temperatures (non-empty species)");
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
      int64_t ns = 0;
      fz::check(gran_dsmc_size_distribution(sim, 0, &ns, nullptr, nullptr, nullptr), "gran_dsmc_size_distribution");
    }
  }
}

void run_dsmc(fz::Bytes &in, bool cell) {
  const int64_t M = 1 + in.u8() % 4;
  gran_dsmc_cell_options c;
  gran_dsmc_cell_options_default(&c);
  gran_dsmc_agg_options a;
  gran_dsmc_agg_options_default(&a);
  const bool agg = in.u8() & 1;
  gran_mixture *mix = mixture(in, M, agg);
  if (!mix) return;
  gran_dsmc_options o;
  gran_dsmc_options_default(&o);
  o.selector = cell ? GRAN_SELECTOR_CELL : in.i32(in.u8() & 1, -1, 5);
  o.observe = in.i32(agg ? 0 : 1, -1, 8);
  o.seed = in.u8() < 128 ? 3 : in.u64();
  o.volume = in.dbl(cell ? 4000 : 1000);
  o.t_start = in.dbl(0);
  o.bound_refresh = in.i64(0, -1, 100);
  o.traj_per_species = in.i64(1, -1, 4);
  o.traj_dt = in.dbl(0.25);
  o.traj_samples = in.i64(5, -1, 16);
  o.speed_classes = in.i32(-1, -2, 2);
  std::vector<int64_t> counts((size_t)M);
  const bool given = in.u8() < 160;
  double N = 0;
  for (int64_t k = 0; k < M; ++k) {
    counts[(size_t)k] = in.i64(40 / (k + 1), -1, 64);
    N += (double)counts[(size_t)k];
  }
  std::vector<double> T0((size_t)M);
  const bool have_T = in.u8() < 100;
  for (int64_t k = 0; k < M; ++k) T0[(size_t)k] = in.dbl(1.0);
  if (cell) {
    c.cells = in.i64(2, -1, 4);
    c.dt = in.dbl(0.1);
    c.fn = in.dbl(1);
    c.e_agg = agg ? in.dbl(1) : in.dbl(0);
    c.e_frag = agg ? in.dbl(3) : in.dbl(INFINITY);
    c.eps_f = in.dbl(0.7);
    c.heat_rate = in.dbl(0);
    c.bath_density = in.dbl(0);
    c.bath_mass = in.dbl(1);
    c.bath_T = in.dbl(1);
    c.bath_sigma = in.dbl(1);
    c.placement = in.i32(0, -1, 2);
    c.frag_law = in.i32(0, -1, 2);
    c.streams = in.i32(0, -1, 2);
  } else {
    a.e_agg = agg ? in.dbl(1) : in.dbl(0);
    a.e_frag = agg ? in.dbl(3) : in.dbl(INFINITY);
    a.eps_f = in.dbl(0.7);
    a.frag_law = in.i32(0, -1, 2);
  }
  /* the caps: particles (given counts, or n_k V (/ F_N)), cells, trajectories */
  if (!given) {
    int64_t Mq = 0;
    std::vector<double> dens((size_t)M);
    gran_mixture_nspecies(mix, &Mq);
    gran_mixture_get(mix, nullptr, nullptr, dens.data());
    N = 0;
    for (double x : dens) N += x * o.volume / (cell && c.fn > 0 ? c.fn : 1.0);
  }
  const double nc = (double)c.cells;
  const bool big = N > kMaxParticles || (cell && nc * nc * nc > kMaxCells) ||
                   (double)o.traj_per_species * (double)o.traj_samples * (double)M > 1e5;
  if (getenv("GRAN_FUZZ_VERBOSE")) {
    std::vector<double> m((size_t)M), sg((size_t)M), dn((size_t)M);
    gran_mixture_get(mix, m.data(), sg.data(), dn.data());
    std::fprintf(stderr, "fuzz: dsmc %s M %lld agg %d given_counts %d have_T0 %d selector %d observe %d volume %g t_start %g\n",
                 cell ? "cell" : "event", (long long)M, (int)agg, (int)given, (int)have_T, o.selector, o.observe, o.volume,
                 o.t_start);
    for (int64_t k = 0; k < M; ++k)
      std::fprintf(stderr, "fuzz:   species %lld mass %g sigma %g density %g count %lld T0 %g\n", (long long)k,
                   m[(size_t)k], sg[(size_t)k], dn[(size_t)k], (long long)counts[(size_t)k], T0[(size_t)k]);
    if (cell)
      std::fprintf(stderr, "fuzz:   cell cells %lld dt %g fn %g e_agg %g e_frag %g eps_f %g heat %g bath %g %g %g %g\n",
                   (long long)c.cells, c.dt, c.fn, c.e_agg, c.e_frag, c.eps_f, c.heat_rate, c.bath_density, c.bath_mass,
                   c.bath_T, c.bath_sigma);
    else
      std::fprintf(stderr, "fuzz:   agg e_agg %g e_frag %g eps_f %g law %d\n", a.e_agg, a.e_frag, a.eps_f, a.frag_law);
  }
  if (!big) {
    gran_dsmc *sim = nullptr;
    const int64_t *cp = given ? counts.data() : nullptr;
    const double *tp = have_T ? T0.data() : nullptr;
    const int st = cell ? fz::check(gran_dsmc_create_cell(mix, cp, tp, &o, &c, &sim), "gran_dsmc_create_cell")
                        : fz::check(gran_dsmc_create_agg(mix, cp, tp, &o, &a, &sim), "gran_dsmc_create_agg");
    if (st == GRAN_SUCCESS) {
      const bool aggr = cell ? (c.e_agg > 0 || std::isfinite(c.e_frag)) : (a.e_agg > 0 || std::isfinite(a.e_frag));
      obs_dsmc(sim, M, aggr);
      for (int r = 0; r < 3; ++r) {
        double t = 0;
        gran_dsmc_time(sim, &t);
        int s2;
        if (cell) { /* 1 to 3 whole steps */
          const double te = t + (double)(1 + in.u8() % 3) * c.dt;
          s2 = fz::check(gran_dsmc_advance(sim, te), "gran_dsmc_advance (cell)");
        } else {
          s2 = fz::check(gran_dsmc_advance_collisions(sim, 1 + in.u8() % 200), "gran_dsmc_advance_collisions");
        }
        if (s2) break;
        obs_dsmc(sim, M, aggr);
      }
      gran_dsmc_destroy(&sim);
    }
  }
  gran_mixture_destroy(&mix);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fz::setup();
  fz::Bytes in(data, size);
  switch (in.u8() % 3) {
  case 0: run_srd(in); break;
  case 1: run_dsmc(in, true); break;
  default: run_dsmc(in, false); break;
  }
  return 0;
}
