/* theory.cpp - `granary theory SCENE [--times ...] [--lags ...] [--approximation ...] [--json]`:
 * kinetic theory of the scene's mixture (HCS temperatures, relaxation and correlation times,
 * diffusion coefficients; T_k(t), MSD_k(t) and TAMSD at requested times and lags; with
 * --approximation sonine also the first Sonine HCS (T_k, a2_k, tau0) and T_k(t), a2_k(t), and the
 * MSD_k(t) and D_k(0) of the two-moment velocity correlation). Aggregating DSMC scenes, GSRD scenes
 * and engines without a theory go to theory_engines.cpp. */
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cli.h"
#include "io/io_impl.h"
#include "theory_util.h"

namespace {

void theory_usage(FILE *f) {
  std::fprintf(f,
               "usage: granary theory SCENE [--times t1,t2,...|scene] [--lags l1,l2,...] [--approximation A]\n"
               "                      [--sonine-order N] [--json]\n"
               "  Prints, per species, n_k, m_k, sigma_k, T_k(0), gamma_k1 = T_k(0)/T_1(0), tau_v,k(0), D_k(0),\n"
               "  and tau0 of the homogeneous cooling state. Times are measured from the scene's t_start.\n"
               "  --times  also T_k(t) and MSD_k(t) at these times\n"
               "  --lags   also the TAMSD at these lags, for a measurement time equal to each of --times\n"
               "  --approximation maxwellian (default: the reference level above) or sonine: also the first\n"
               "           Sonine HCS (T_k, T_k/T_1, a2_k, tau0) and, with --times, T_k(t) and a2_k(t) from the\n"
               "           scene's start (a2 = the Sonine HCS's when it starts in the HCS, else 0); constant or\n"
               "           matrix restitution only. MSD and TAMSD stay at the Maxwellian level.\n"
               "  --sonine-order N (2..5, with --approximation sonine): also the HCS of the linear Sonine\n"
               "           hierarchy to a_N (T_k, T_k/T_1, a_2..a_N, tau0; 3 = the second Sonine level; up to 64\n"
               "           species; N = 5 closes the first level's gap in mass-disparate mixtures, not in the\n"
               "           ordered phase of a heavy tracer: docs/physics-sonine.md Sec. 4)\n"
               "  --json   the same as one JSON object on stdout (numbers %%.17g, inf/nan as null)\n"
               "  --times scene: the scene's own output times (from t_start), the times of the run driver's theory\n"
               "  Aggregating scenes (e_agg > 0 or a finite e_frag): the Smoluchowski kinetics n_k(t), T_k(t), the\n"
               "  total density and mean temperature instead. GSRD scenes: Haff's law T(t) when the gas cools freely\n"
               "  and the shear viscosity under Lees-Edwards shear. What the engine has no theory for is named in\n"
               "  one line; a scene without any theory says so and exits 0.\n");
}

/* comma-separated list of finite numbers */
bool parse_list(const char *s, std::vector<double> &out) {
  out.clear();
  std::string str(s);
  size_t pos = 0;
  while (pos <= str.size()) {
    size_t c = str.find(',', pos);
    std::string tok = str.substr(pos, c == std::string::npos ? std::string::npos : c - pos);
    char *end = nullptr;
    double v = std::strtod(tok.c_str(), &end);
    if (tok.empty() || *end != '\0' || !std::isfinite(v)) return false;
    out.push_back(v);
    if (c == std::string::npos) break;
    pos = c + 1;
  }
  return !out.empty();
}

/* the JSON writers of theory_util.h */
void jnum(std::string &o, double x) { cli_json::num(o, x); }
void jstr(std::string &o, const std::string &x) { cli_json::str(o, x); }
void jarr(std::string &o, const double *x, int64_t n) { cli_json::arr(o, x, n); }
void jmat(std::string &o, const double *x, int64_t rows, int64_t cols) { cli_json::mat(o, x, rows, cols); }

int fail(const char *what) {
  std::fprintf(stderr, "granary theory: %s: %s\n", what, cli_error());
  return 1;
}

}  // namespace

int cli_theory(int argc, char **argv) {
  const char *scene_path = nullptr;
  std::vector<double> times, lags;
  bool json = false, times_scene = false, approx_given = false;
  int approx = GRAN_THEORY_MAXWELLIAN, nmax = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (!std::strcmp(a, "--help") || !std::strcmp(a, "-h")) {
      theory_usage(stdout);
      return 0;
    } else if (!std::strcmp(a, "--json")) {
      json = true;
    } else if (!std::strcmp(a, "--approximation")) {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "granary theory: --approximation needs a value (maxwellian or sonine)\n");
        return 2;
      }
      const char *v = argv[++i];
      approx_given = true;
      if (!std::strcmp(v, "maxwellian")) approx = GRAN_THEORY_MAXWELLIAN;
      else if (!std::strcmp(v, "sonine")) approx = GRAN_THEORY_SONINE;
      else {
        std::fprintf(stderr, "granary theory: --approximation '%s': expected maxwellian or sonine\n", v);
        return 2;
      }
    } else if (!std::strcmp(a, "--sonine-order")) {
      char *end = nullptr;
      const long v = i + 1 < argc ? std::strtol(argv[i + 1], &end, 10) : 0;
      if (i + 1 >= argc || !end || *end != '\0' || end == argv[i + 1] || v < 2 || v > 5) {
        std::fprintf(stderr, "granary theory: --sonine-order needs an order 2..5 (got '%s')\n",
                     i + 1 < argc ? argv[i + 1] : "");
        return 2;
      }
      nmax = (int)v;
      ++i;
    } else if (!std::strcmp(a, "--times") || !std::strcmp(a, "--lags")) {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "granary theory: %s needs a comma-separated list\n", a);
        return 2;
      }
      std::vector<double> &v = !std::strcmp(a, "--times") ? times : lags;
      if (!std::strcmp(a, "--times") && !std::strcmp(argv[i + 1], "scene")) {
        times_scene = true; /* filled in from the scene below */
        times.clear();
        ++i;
        continue;
      }
      if (!std::strcmp(a, "--times")) times_scene = false;
      if (!parse_list(argv[++i], v)) {
        std::fprintf(stderr, "granary theory: %s '%s': expected comma-separated finite numbers\n", a, argv[i]);
        return 2;
      }
      for (double x : v)
        if (x < 0) {
          std::fprintf(stderr, "granary theory: %s: values must be >= 0 (got %g)\n", a, x);
          return 2;
        }
    } else if (a[0] == '-' && a[1] != '\0') {
      std::fprintf(stderr, "granary theory: unknown option '%s'\n", a);
      theory_usage(stderr);
      return 2;
    } else if (!scene_path) {
      scene_path = a;
    } else {
      std::fprintf(stderr, "granary theory: more than one scene given ('%s')\n", a);
      return 2;
    }
  }
  if (!scene_path) {
    theory_usage(stderr);
    return 2;
  }
  if (nmax && approx != GRAN_THEORY_SONINE) {
    std::fprintf(stderr, "granary theory: --sonine-order needs --approximation sonine\n");
    return 2;
  }
  if (!lags.empty() && times.empty() && !times_scene) {
    std::fprintf(stderr, "granary theory: --lags needs --times (the measurement times of the TAMSD)\n");
    return 2;
  }

  gran_scene *scene = nullptr;
  gran_mixture *mix = nullptr;
  if (gran_scene_load(scene_path, &scene)) return fail("cannot load the scene");
  struct Guard {
    gran_scene **s;
    gran_mixture **m;
    ~Guard() {
      gran_mixture_destroy(m);
      gran_scene_destroy(s);
    }
  } guard{&scene, &mix};
  if (times_scene) /* the run driver's theory times: the output times from t_start */
    for (double t : scene->times) times.push_back(std::max(0.0, t - scene->t_start));

  /* the engines and processes the cooling-mixture theory below does not describe */
  cli_theory_request req;
  req.scene_path = scene_path;
  req.times = times;
  req.times_scene = times_scene;
  req.lags = lags;
  req.json = json;
  req.approx = approx;
  req.approx_given = approx_given;
  if (scene->engine_type == "srd") return cli_theory_srd(scene, req);
  if (scene->engine_type != "dsmc")
    return cli_theory_none(scene, req, "granary has a kinetic theory for the DSMC and GSRD engines only");
  if (scene->agg.e_agg > 0 || std::isfinite(scene->agg.e_frag)) return cli_theory_aggregation(scene, req);

  if (gran_scene_mixture(scene, &mix)) return fail("cannot build the mixture");
  int64_t M = 0;
  gran_mixture_nspecies(mix, &M);
  std::vector<double> m((size_t)M), sg((size_t)M), n((size_t)M), T0((size_t)M), tv((size_t)M),
      D((size_t)M);
  gran_mixture_get(mix, m.data(), sg.data(), n.data());
  double tau0 = NAN, tau0_hcs = NAN, inv_tc = NAN;
  if (gran_scene_initial_temperatures(scene, mix, T0.data(), &tau0)) return fail("cannot compute the initial temperatures");
  if (gran_theory_tau_v(mix, T0.data(), tv.data())) return fail("gran_theory_tau_v failed");
  if (gran_theory_diffusion(mix, T0.data(), D.data())) return fail("gran_theory_diffusion failed");
  if (gran_theory_collision_rate1(mix, T0.data(), &inv_tc)) return fail("gran_theory_collision_rate1 failed");
  int model = 0;
  gran_mixture_restitution_model(mix, &model);
  tau0_hcs = model == GRAN_RESTITUTION_VISCOELASTIC ? NAN : tau0; /* no HCS: JSON null */
  const char *model_name = model == GRAN_RESTITUTION_CONSTANT ? "constant" : model == GRAN_RESTITUTION_MATRIX ? "matrix" : "viscoelastic";

  /* initial state: the scene's; HCS flag decides which MSD formula applies */
  const char *text = nullptr;
  gran_scene_text(scene, &text);
  double t_start = 0;
  gran_scene_sizes(scene, nullptr, nullptr, nullptr, &t_start, nullptr);
  const bool hcs_start = scene->init == SCENE_INIT_HCS;
  /* driving of the cell selector: T(t) with it (gran_theory_temperatures_driven); the MSD and TAMSD
   * below are those of a freely cooling gas */
  std::vector<std::string> not_covered;
  const bool driven = gran_scene_driven_(scene);
  if (driven)
    not_covered.push_back("the MSD and TAMSD of the driven gas (thermostat or bath): those below cool freely");

  const int64_t nt = (int64_t)times.size(), nl = (int64_t)lags.size();
  std::vector<double> T((size_t)(nt * M)), msd((size_t)(nt * M)), msd_tot((size_t)nt), ta((size_t)(nt * nl * M), NAN);
  const char *msd_formula = "";
  if (nt) {
    if (driven ? gran_scene_driven_temperatures_(scene, mix, T0.data(), nt, times.data(), 1e-10, T.data())
               : gran_theory_temperatures(mix, T0.data(), nt, times.data(), 1e-10, T.data()))
      return fail(driven ? "gran_theory_temperatures_driven failed" : "gran_theory_temperatures failed");
    const bool closed = hcs_start && model != GRAN_RESTITUTION_VISCOELASTIC && std::isfinite(tau0);
    msd_formula = closed ? "Eq. 22 (HCS, closed form)" : "Eq. 4 (numerical integration)";
    int st = closed ? gran_theory_msd_hcs(mix, T0.data(), tau0, nt, times.data(), msd.data(), msd_tot.data())
                    : gran_theory_msd(mix, T0.data(), nt, times.data(), 1e-8, msd.data(), msd_tot.data());
    if (st) return fail("MSD theory failed");
    for (int64_t i = 0; i < nt && nl; i++) {
      std::vector<double> ok_lags;
      for (double L : lags)
        if (L < times[(size_t)i]) ok_lags.push_back(L);
      if (ok_lags.empty()) continue;
      std::vector<double> out(ok_lags.size() * (size_t)M);
      if (!std::isfinite(tau0)) break;
      if (gran_theory_tamsd(mix, T0.data(), tau0, times[(size_t)i], (int64_t)ok_lags.size(), ok_lags.data(), 1e-8, out.data()))
        return fail("gran_theory_tamsd failed");
      for (size_t j = 0; j < ok_lags.size(); j++)
        for (int64_t k = 0; k < M; k++) ta[(size_t)((i * nl + (int64_t)j) * M + k)] = out[j * (size_t)M + (size_t)k];
    }
  }

  /* first Sonine level: the HCS with the scene's mean temperature, and the trajectories */
  const bool son = approx == GRAN_THEORY_SONINE;
  std::vector<double> Ts((size_t)M), a2s((size_t)M), Tst((size_t)(nt * M)), a2t((size_t)(nt * M));
  std::vector<double> msds((size_t)(nt * M)), msds_tot((size_t)nt), Ds((size_t)M);
  double tau0s = NAN, tau0n = NAN;
  std::vector<double> Tn, an; /* --sonine-order: T_k and a_q,k of the hierarchy's HCS (empty: none) */
  /* --sonine-order 3 with times: T_k(t), a2_k(t), a3_k(t) and the MSD of the second Sonine trajectory (empty: none) */
  std::vector<double> T2t, a22t, a32t, msd2, msd2_tot;
  /* viscoelastic: the trajectories only (no HCS; the two-moment correlation needs constant or
   * matrix restitution) */
  const bool son_visco = son && model == GRAN_RESTITUTION_VISCOELASTIC;
  if (son_visco) {
    not_covered.push_back("the first Sonine HCS, two-moment MSD and D of a viscoelastic gas (it has no HCS; the "
                          "two-moment correlation is for constant or matrix restitution)");
    std::fill(Ts.begin(), Ts.end(), NAN);
    std::fill(a2s.begin(), a2s.end(), NAN);
    std::fill(msds.begin(), msds.end(), NAN);
    std::fill(msds_tot.begin(), msds_tot.end(), NAN);
    std::fill(Ds.begin(), Ds.end(), NAN);
    std::vector<double> a20((size_t)M, 0.0);
    if (nt && gran_theory_temperatures_approx(mix, GRAN_THEORY_SONINE, T0.data(), a20.data(), nt, times.data(), 1e-10,
                                              Tst.data(), a2t.data()))
      return fail("gran_theory_temperatures_approx (sonine) failed");
    if (nmax)
      not_covered.push_back("the Sonine hierarchy to a_" + std::to_string(nmax) +
                            " (an HCS: none for viscoelastic restitution)");
  } else if (son) {
    double num = 0, den = 0;
    for (int64_t k = 0; k < M; k++) {
      num += n[(size_t)k] * T0[(size_t)k];
      den += n[(size_t)k];
    }
    if (gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, num / den, Ts.data(), a2s.data(), &tau0s))
      return fail("gran_theory_hcs_approx (sonine) failed");
    if (nt) {
      std::vector<double> a20((size_t)M, 0.0), T0s(T0);
      if (hcs_start) {
        a20 = a2s;
        T0s = Ts;
      }
      if (gran_theory_temperatures_approx(mix, GRAN_THEORY_SONINE, T0s.data(), a20.data(), nt, times.data(), 1e-10,
                                          Tst.data(), a2t.data()))
        return fail("gran_theory_temperatures_approx (sonine) failed");
      /* MSD with the two-moment velocity correlation from the scene's start (as msd_theory_sonine) */
      const bool closed = hcs_start && std::isfinite(tau0);
      int st = closed ? gran_theory_msd_hcs_approx(mix, GRAN_THEORY_SONINE, T0.data(), nullptr, tau0, nt, times.data(),
                                                   msds.data(), msds_tot.data())
                      : gran_theory_msd_approx(mix, GRAN_THEORY_SONINE, T0.data(), nt, times.data(), 1e-8, msds.data(),
                                               msds_tot.data());
      if (st) return fail("MSD theory (sonine) failed");
    }
    if (gran_theory_diffusion_approx(mix, GRAN_THEORY_SONINE, T0.data(), nullptr, nullptr, Ds.data()))
      return fail("gran_theory_diffusion_approx (sonine) failed");
    /* --sonine-order: the HCS of the hierarchy to a_nmax, same mean temperature */
    if (nmax) {
      Tn.resize((size_t)M);
      an.resize((size_t)(M * (nmax - 1)));
      if (gran_theory_hcs_sonine_n(mix, nmax, GRAN_HCS_NORM_MEAN, num / den, Tn.data(), an.data(), &tau0n)) {
        not_covered.push_back("the Sonine hierarchy to a_" + std::to_string(nmax) + ": " + cli_error());
        Tn.clear();
      }
    }
    /* --sonine-order 3 with times: the second Sonine trajectory and Eq. 4 on it (a2 in the correlation), from
     * the scene's start (a2 = a3 = 0) or, for an HCS start, from the second Sonine HCS (as the first level's) */
    if (nmax == 3 && nt && !Tn.empty()) {
      std::vector<double> Tst2(T0), b2((size_t)M, 0.0), b3((size_t)M, 0.0);
      if (hcs_start)
        for (int64_t k = 0; k < M; k++) {
          Tst2[(size_t)k] = Tn[(size_t)k];
          b2[(size_t)k] = an[(size_t)(2 * k)];
          b3[(size_t)k] = an[(size_t)(2 * k + 1)];
        }
      T2t.resize((size_t)(nt * M));
      a22t.resize((size_t)(nt * M));
      a32t.resize((size_t)(nt * M));
      msd2.resize((size_t)(nt * M));
      msd2_tot.resize((size_t)nt);
      if (gran_theory_temperatures_sonine2(mix, Tst2.data(), b2.data(), b3.data(), nt, times.data(), 1e-10, T2t.data(),
                                           a22t.data(), a32t.data()) ||
          gran_theory_msd_sonine2(mix, Tst2.data(), b2.data(), b3.data(), 1, nt, times.data(), 1e-8, msd2.data(),
                                  msd2_tot.data())) {
        not_covered.push_back(std::string("the second Sonine trajectory: ") + cli_error());
        T2t.clear();
      }
    } else if (nmax > 3 && nt) {
      not_covered.push_back("T_k(t) and the MSD of the Sonine hierarchy beyond a_3 (--sonine-order 3 gives the "
                            "second Sonine trajectory)");
    }
  }

  if (json) {
    std::string o = "{";
    o += "\"scene\": ";
    jstr(o, scene_path);
    o += ", \"engine\": \"dsmc\", \"theory\": \"mixture\"";
    o += ", \"nspecies\": " + std::to_string(M);
    o += ", \"restitution\": ";
    jstr(o, model_name);
    o += ", \"hcs_start\": ";
    o += hcs_start ? "true" : "false";
    o += ", \"t_start\": ";
    jnum(o, t_start);
    o += ", \"tau0\": ";
    jnum(o, tau0_hcs);
    o += ", \"tau_c0\": ";
    jnum(o, 1.0 / inv_tc);
    o += ", \"approximation\": ";
    jstr(o, son ? "sonine" : "maxwellian");
    if (son) {
      std::vector<double> gs((size_t)M);
      for (int64_t k = 0; k < M; k++) gs[(size_t)k] = Ts[(size_t)k] / Ts[0];
      o += ", \"sonine\": {\"tau0\": ";
      jnum(o, tau0s);
      o += ", \"T0\": ";
      jarr(o, Ts.data(), M);
      o += ", \"gamma\": ";
      jarr(o, gs.data(), M);
      o += ", \"a2\": ";
      jarr(o, a2s.data(), M);
      o += ", \"D0\": ";
      jarr(o, Ds.data(), M);
      if (!Tn.empty()) {
        std::vector<double> gn((size_t)M);
        for (int64_t k = 0; k < M; k++) gn[(size_t)k] = Tn[(size_t)k] / Tn[0];
        o += ", \"order\": {\"nmax\": " + std::to_string(nmax) + ", \"tau0\": ";
        jnum(o, tau0n);
        o += ", \"T0\": ";
        jarr(o, Tn.data(), M);
        o += ", \"gamma\": ";
        jarr(o, gn.data(), M);
        o += ", \"a\": ";
        jmat(o, an.data(), M, nmax - 1);
        if (!T2t.empty()) {
          o += ", \"T\": ";
          jmat(o, T2t.data(), nt, M);
          o += ", \"a2_t\": ";
          jmat(o, a22t.data(), nt, M);
          o += ", \"a3_t\": ";
          jmat(o, a32t.data(), nt, M);
          o += ", \"msd\": ";
          jmat(o, msd2.data(), nt, M);
          o += ", \"msd_total\": ";
          jarr(o, msd2_tot.data(), nt);
        }
        o += "}";
      }
      if (nt) {
        o += ", \"T\": ";
        jmat(o, Tst.data(), nt, M);
        o += ", \"a2_t\": ";
        jmat(o, a2t.data(), nt, M);
        o += ", \"msd\": ";
        jmat(o, msds.data(), nt, M);
        o += ", \"msd_total\": ";
        jarr(o, msds_tot.data(), nt);
      }
      o += "}";
    }
    o += ", \"species\": [";
    for (int64_t k = 0; k < M; k++) {
      const size_t K = (size_t)k;
      if (k) o += ", ";
      o += "{\"k\": " + std::to_string(k + 1) + ", \"n\": ";
      jnum(o, n[K]);
      o += ", \"m\": ";
      jnum(o, m[K]);
      o += ", \"sigma\": ";
      jnum(o, sg[K]);
      o += ", \"T0\": ";
      jnum(o, T0[K]);
      o += ", \"gamma\": ";
      jnum(o, T0[K] / T0[0]);
      o += ", \"tau_v0\": ";
      jnum(o, tv[K]);
      o += ", \"D0\": ";
      jnum(o, D[K]);
      o += "}";
    }
    o += "]";
    if (nt) {
      o += ", \"times\": ";
      jarr(o, times.data(), nt);
      o += ", \"T\": ";
      jmat(o, T.data(), nt, M);
      o += ", \"msd\": ";
      jmat(o, msd.data(), nt, M);
      o += ", \"msd_total\": ";
      jarr(o, msd_tot.data(), nt);
      o += ", \"msd_formula\": ";
      jstr(o, msd_formula);
    }
    if (nl) {
      o += ", \"lags\": ";
      jarr(o, lags.data(), nl);
      o += ", \"tamsd\": [";
      for (int64_t i = 0; i < nt; i++) {
        if (i) o += ", ";
        o += "{\"t_meas\": ";
        jnum(o, times[(size_t)i]);
        o += ", \"tamsd\": ";
        jmat(o, ta.data() + i * nl * M, nl, M);
        o += "}";
      }
      o += "]";
    }
    o += ", \"not_covered\": [";
    for (size_t i = 0; i < not_covered.size(); i++) {
      if (i) o += ", ";
      jstr(o, not_covered[i]);
    }
    o += "]}\n";
    std::fputs(o.c_str(), stdout);
    return 0;
  }

  std::printf("scene %s: %" PRId64 " species, restitution %s, start %s\n", scene_path, M, model_name,
              scene->init == SCENE_INIT_HCS     ? "in the homogeneous cooling state"
              : scene->init == SCENE_INIT_EQUAL ? "with equal temperatures"
                                                : "with the listed temperatures");
  if (model == GRAN_RESTITUTION_VISCOELASTIC)
    std::printf("tau0: none (viscoelastic restitution has no homogeneous cooling state; T(t) ~ t^(-5/3) at late times)\n");
  else
    std::printf("tau0 = %.8g   (2/xi_1(0), Eq. 21: the temperature relaxation time of the HCS)\n", tau0_hcs);
  std::printf("tau_c(0) = %.8g   (mean collision time of species 1, Eq. 7)\n", 1.0 / inv_tc);
  std::printf("%4s %14s %14s %14s %16s %14s %14s %14s\n", "k", "n_k", "m_k", "sigma_k", "T_k(0)", "gamma_k1",
              "tau_v,k(0)", "D_k(0)");
  for (int64_t k = 0; k < M; k++) {
    const size_t K = (size_t)k;
    std::printf("%4" PRId64 " %14.8g %14.8g %14.8g %16.10g %14.8g %14.8g %14.8g\n", k + 1, n[K], m[K], sg[K], T0[K],
                T0[K] / T0[0], tv[K], D[K]);
  }
  if (nt) {
    std::printf("\nT_k(t) (Eq. 13) and MSD_k(t), %s\n", msd_formula);
    std::printf("%14s %4s %16s %16s\n", "t", "k", "T_k(t)", "MSD_k(t)");
    for (int64_t i = 0; i < nt; i++) {
      for (int64_t k = 0; k < M; k++)
        std::printf("%14.8g %4" PRId64 " %16.10g %16.10g\n", times[(size_t)i], k + 1, T[(size_t)(i * M + k)],
                    msd[(size_t)(i * M + k)]);
      std::printf("%14.8g %4s %16s %16.10g\n", times[(size_t)i], "all", "", msd_tot[(size_t)i]);
    }
  }
  if (son_visco && nt) {
    std::printf("\nT_k(t) and a2_k(t), first Sonine approximation (viscoelastic: from a2 = 0 at the start; no HCS)\n");
    std::printf("%14s %4s %16s %14s\n", "t", "k", "T_k(t)", "a2_k(t)");
    for (int64_t i = 0; i < nt; i++)
      for (int64_t k = 0; k < M; k++)
        std::printf("%14.8g %4" PRId64 " %16.10g %14.8g\n", times[(size_t)i], k + 1, Tst[(size_t)(i * M + k)],
                    a2t[(size_t)(i * M + k)]);
  } else if (son) {
    std::printf("\nFirst Sonine approximation: HCS with the same mean temperature, tau0 = %.8g\n", tau0s);
    std::printf("%4s %16s %14s %14s\n", "k", "T_k", "gamma_k1", "a2_k");
    for (int64_t k = 0; k < M; k++)
      std::printf("%4" PRId64 " %16.10g %14.8g %14.8g\n", k + 1, Ts[(size_t)k], Ts[(size_t)k] / Ts[0],
                  a2s[(size_t)k]);
    if (nt) {
      std::printf("\nT_k(t) and a2_k(t), first Sonine approximation\n");
      std::printf("%14s %4s %16s %14s\n", "t", "k", "T_k(t)", "a2_k(t)");
      for (int64_t i = 0; i < nt; i++)
        for (int64_t k = 0; k < M; k++)
          std::printf("%14.8g %4" PRId64 " %16.10g %14.8g\n", times[(size_t)i], k + 1, Tst[(size_t)(i * M + k)],
                      a2t[(size_t)(i * M + k)]);
      std::printf("\nMSD_k(t) with the two-moment (second Sonine) velocity correlation, from the scene's start\n");
      std::printf("%14s %4s %16s %16s\n", "t", "k", "MSD_k(t)", "/ Maxwellian");
      for (int64_t i = 0; i < nt; i++)
        for (int64_t k = 0; k < M; k++)
          std::printf("%14.8g %4" PRId64 " %16.10g %16.10g\n", times[(size_t)i], k + 1, msds[(size_t)(i * M + k)],
                      msds[(size_t)(i * M + k)] / msd[(size_t)(i * M + k)]);
    }
    if (!Tn.empty()) {
      std::printf("\nSonine hierarchy to a_%d: HCS with the same mean temperature, tau0 = %.8g\n", nmax, tau0n);
      std::printf("%4s %16s %14s", "k", "T_k", "gamma_k1");
      for (int q = 2; q <= nmax; q++) std::printf(" %12s%d", "a_", q);
      std::printf("\n");
      for (int64_t k = 0; k < M; k++) {
        std::printf("%4" PRId64 " %16.10g %14.8g", k + 1, Tn[(size_t)k], Tn[(size_t)k] / Tn[0]);
        for (int q = 2; q <= nmax; q++) std::printf(" %13.6g", an[(size_t)(k * (nmax - 1) + q - 2)]);
        std::printf("\n");
      }
    }
    if (!T2t.empty()) {
      std::printf("\nT_k(t), a2_k(t) and a3_k(t), second Sonine approximation (from %s)\n",
                  hcs_start ? "its HCS with the same mean temperature" : "the scene's start, a2 = a3 = 0");
      std::printf("%14s %4s %16s %14s %14s\n", "t", "k", "T_k(t)", "a2_k(t)", "a3_k(t)");
      for (int64_t i = 0; i < nt; i++)
        for (int64_t k = 0; k < M; k++)
          std::printf("%14.8g %4" PRId64 " %16.10g %14.8g %14.8g\n", times[(size_t)i], k + 1, T2t[(size_t)(i * M + k)],
                      a22t[(size_t)(i * M + k)], a32t[(size_t)(i * M + k)]);
      std::printf("\nMSD_k(t) by Eq. 4 on the second Sonine trajectory (two-moment correlation, a2 in it)\n");
      std::printf("%14s %4s %16s %16s\n", "t", "k", "MSD_k(t)", "/ Maxwellian");
      for (int64_t i = 0; i < nt; i++)
        for (int64_t k = 0; k < M; k++)
          std::printf("%14.8g %4" PRId64 " %16.10g %16.10g\n", times[(size_t)i], k + 1, msd2[(size_t)(i * M + k)],
                      msd2[(size_t)(i * M + k)] / msd[(size_t)(i * M + k)]);
    }
    std::printf("\nD_k(0) with the two-moment velocity correlation:");
    for (int64_t k = 0; k < M; k++) std::printf(" %.8g", Ds[(size_t)k]);
    std::printf("\n");
  }
  if (nl) {
    std::printf("\nTAMSD_k(lag; t_meas) (Eq. 27; lags >= t_meas are skipped)\n");
    std::printf("%14s %14s %4s %16s\n", "t_meas", "lag", "k", "TAMSD_k");
    for (int64_t i = 0; i < nt; i++)
      for (int64_t j = 0; j < nl; j++) {
        if (!(lags[(size_t)j] < times[(size_t)i])) continue;
        for (int64_t k = 0; k < M; k++)
          std::printf("%14.8g %14.8g %4" PRId64 " %16.10g\n", times[(size_t)i], lags[(size_t)j], k + 1,
                      ta[(size_t)((i * nl + j) * M + k)]);
      }
  }
  if (!not_covered.empty()) {
    std::printf("\nno theory here for:");
    for (size_t i = 0; i < not_covered.size(); i++) std::printf("%s %s", i ? ";" : "", not_covered[i].c_str());
    std::printf("\n");
  }
  (void)text;
  return 0;
}
