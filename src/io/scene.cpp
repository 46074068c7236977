/* scene.cpp - TOML scene files (toml11): parsing, complete validation, and the gran_scene_* API.
 *
 * Every failure is GRAN_ERR_PARSE with "FILE:LINE: key 'table.key': reason" (syntax errors carry
 * toml11's own line). Keys are consumed as they are read; whatever is left in a table afterwards
 * is an unknown key. */
#include <toml.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

#include "io/engine.h" /* gran_row_buf: the memory of the recorded rows */
#include "io/io_impl.h"
#include "core/run_bounds.h"
#include "srd/srd_impl.h" /* SRD_SLAB_CELLS: the memory estimate of a GSRD engine */
#include "srd/srd_limits.h" /* the bounds on what a GSRD run derives from its inputs */
#include "core/derived.h"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

/* Thrown inside the parser only; converted to GRAN_ERR_PARSE at the entry point. */
struct scene_error {
  std::string msg;
};

/* Line numbers of the text toml11 parsed -> lines of the scene as written (the pre-pass below may
 * break long lines); empty: the same. Set for the duration of one parse. */
thread_local const std::vector<unsigned> *t_line_map = nullptr;

std::string fmt_line(const std::string &file, unsigned line) {
  if (t_line_map && line >= 1 && line <= t_line_map->size()) line = (*t_line_map)[line - 1];
  return file + ":" + std::to_string(line);
}

/* ---- pre-pass: what toml11 3.7 must never see ------------------------------------------------
 * toml11 overflows its stack on arrays or inline tables nested a few thousand deep, reads past a
 * buffer on invalid UTF-8 inside a literal string, and takes time quadratic in the length of a
 * line (a 1e5-number array on one line: 40 s). One linear scan that knows TOML's strings and
 * comments checks the encoding (UTF-8, no NUL), bounds the nesting depth, and puts a line break
 * after every comma of an array that lies outside any inline table (TOML allows newlines there),
 * keeping a map back to the original line numbers for messages. */
const size_t kMaxSceneBytes = (size_t)16 << 20;
const int kMaxNesting = 32;

/* length of the valid UTF-8 sequence at p (1..4), 0 when invalid (overlong, surrogate, > U+10FFFF) */
size_t utf8_len(const unsigned char *p, const unsigned char *end) {
  const unsigned c = p[0];
  if (c < 0x80) return c == 0 ? 0 : 1;
  size_t n;
  unsigned cp;
  if (c >= 0xC2 && c <= 0xDF) n = 2, cp = c & 0x1F;
  else if (c >= 0xE0 && c <= 0xEF) n = 3, cp = c & 0x0F;
  else if (c >= 0xF0 && c <= 0xF4) n = 4, cp = c & 0x07;
  else return 0;
  if ((size_t)(end - p) < n) return 0;
  for (size_t i = 1; i < n; i++) {
    if ((p[i] & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (p[i] & 0x3F);
  }
  if ((n == 3 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
    return 0;
  return n;
}

void prepass(const std::string &in, const std::string &file, std::string &out, std::vector<unsigned> &line_map) {
  if (in.size() > kMaxSceneBytes)
    throw scene_error{file + ": the scene is " + std::to_string(in.size()) + " bytes; the limit is " +
                      std::to_string(kMaxSceneBytes) + " (16 MiB)"};
  const unsigned char *p = (const unsigned char *)in.data(), *end = p + in.size();
  out.clear();
  out.reserve(in.size() + in.size() / 8);
  line_map.assign(1, 1);
  unsigned line = 1;
  std::vector<char> stack; /* open '[' and '{' */
  int in_table = 0;        /* '{' on the stack */
  enum { kNone, kBasic, kLiteral, kMlBasic, kMlLiteral, kComment } st = kNone;
  auto at_line_start = [&]() {
    for (size_t i = out.size(); i > 0; i--) {
      const char c = out[i - 1];
      if (c == '\n') return true;
      if (c != ' ' && c != '\t') return false;
    }
    return true;
  };
  while (p < end) {
    const size_t n = utf8_len(p, end);
    if (n == 0) {
      char b[96];
      std::snprintf(b, sizeof b, ": %s (byte 0x%02X): scene files are UTF-8 text", *p ? "invalid UTF-8" : "a NUL byte",
                    (unsigned)*p);
      throw scene_error{file + ":" + std::to_string(line) + b};
    }
    const char c = (char)*p;
    out.append((const char *)p, n);
    if (c == '\n') {
      line++;
      line_map.push_back(line);
      if (st == kComment || st == kBasic || st == kLiteral) st = kNone; /* a newline ends them (or is a syntax error) */
    } else if (st == kComment) {
    } else if (st == kBasic) {
      if (c == '\\' && p + 1 < end && p[1] != '\n') out.push_back((char)*++p);
      else if (c == '"') st = kNone;
    } else if (st == kLiteral) {
      if (c == '\'') st = kNone;
    } else if (st == kMlBasic) {
      if (c == '\\' && p + 1 < end && p[1] != '\n') out.push_back((char)*++p);
      else if (c == '"' && end - p >= 3 && p[1] == '"' && p[2] == '"') out.append("\"\""), p += 2, st = kNone;
    } else if (st == kMlLiteral) {
      if (c == '\'' && end - p >= 3 && p[1] == '\'' && p[2] == '\'') out.append("''"), p += 2, st = kNone;
    } else if (c == '#') {
      st = kComment;
    } else if (c == '"') {
      if (end - p >= 3 && p[1] == '"' && p[2] == '"') out.append("\"\""), p += 2, st = kMlBasic;
      else st = kBasic;
    } else if (c == '\'') {
      if (end - p >= 3 && p[1] == '\'' && p[2] == '\'') out.append("''"), p += 2, st = kMlLiteral;
      else st = kLiteral;
    } else if (c == '[' || c == '{') {
      /* a table header [a] / [[a]] at the start of a line is not an array */
      if (c == '[' && stack.empty() && at_line_start()) {
        while (p + 1 < end && p[1] != '\n' && p[1] != '#') {
          ++p;
          out.push_back((char)*p);
          if (*p == ']' && !(p + 1 < end && p[1] == ']')) break;
        }
      } else {
        stack.push_back(c);
        in_table += c == '{';
        if ((int)stack.size() > kMaxNesting)
          throw scene_error{file + ":" + std::to_string(line) + ": arrays and inline tables nested deeper than " +
                            std::to_string(kMaxNesting) + " levels"};
      }
    } else if (c == ']' || c == '}') {
      if (!stack.empty()) {
        in_table -= stack.back() == '{';
        stack.pop_back();
      }
    } else if (c == ',' && !stack.empty() && stack.back() == '[' && !in_table) {
      out.push_back('\n');
      line_map.push_back(line);
    }
    p += n;
  }
}

/* One TOML table being read: remembers which keys were used. */
class Tab {
 public:
  Tab(const toml::value *v, std::string path, std::string file) : v_(v), path_(std::move(path)), file_(std::move(file)) {}

  bool has(const std::string &k) const { return v_ && v_->is_table() && v_->as_table().count(k); }
  std::string key(const std::string &k) const { return path_.empty() ? k : path_ + "." + k; }
  unsigned line() const { return v_ ? (unsigned)v_->location().line() : 1u; }
  unsigned line_of(const std::string &k) const { return (unsigned)v_->as_table().at(k).location().line(); }

  [[noreturn]] void fail(const std::string &k, const std::string &why) const {
    unsigned ln = has(k) ? line_of(k) : line();
    throw scene_error{fmt_line(file_, ln) + ": key '" + key(k) + "': " + why};
  }
  [[noreturn]] void fail_missing(const std::string &k, const std::string &why = "") const {
    throw scene_error{fmt_line(file_, line()) + ": key '" + key(k) + "' is missing" +
                      (why.empty() ? std::string() : " (" + why + ")")};
  }

  const toml::value &get(const std::string &k) {
    used_.insert(k);
    return v_->as_table().at(k);
  }

  /* numbers: integers are accepted where floats are expected; NaN/inf are rejected */
  double num(const std::string &k, const toml::value &x) const {
    double d;
    if (x.is_floating()) d = x.as_floating();
    else if (x.is_integer()) d = (double)x.as_integer();
    else fail(k, std::string("expected a number, got ") + type_name(x));
    if (!std::isfinite(d)) fail(k, "value is not finite (" + std::to_string(d) + ")");
    return d;
  }
  double number(const std::string &k) { return num(k, get(k)); }
  double number(const std::string &k, double def) { return has(k) ? number(k) : def; }

  /* a count: integer, or a float with an integral value (1e6) */
  int64_t cnt(const std::string &k, const toml::value &x) const {
    if (x.is_integer()) return (int64_t)x.as_integer();
    if (x.is_floating()) {
      double d = x.as_floating();
      if (!std::isfinite(d)) fail(k, "value is not finite");
      if (d != std::floor(d) || std::fabs(d) > 9.0e18) fail(k, "expected an integer, got " + num_str(d));
      return (int64_t)d;
    }
    fail(k, std::string("expected an integer, got ") + type_name(x));
  }
  int64_t count(const std::string &k) { return cnt(k, get(k)); }
  int64_t count(const std::string &k, int64_t def) { return has(k) ? count(k) : def; }

  bool boolean(const std::string &k, bool def) {
    if (!has(k)) return def;
    const toml::value &x = get(k);
    if (!x.is_boolean()) fail(k, std::string("expected true or false, got ") + type_name(x));
    return x.as_boolean();
  }
  std::string string(const std::string &k, const std::string &def) {
    if (!has(k)) return def;
    const toml::value &x = get(k);
    if (!x.is_string()) fail(k, std::string("expected a string, got ") + type_name(x));
    return x.as_string().str;
  }
  std::vector<double> numbers(const std::string &k) {
    const toml::value &x = get(k);
    if (!x.is_array()) fail(k, std::string("expected an array of numbers, got ") + type_name(x));
    std::vector<double> out;
    for (const auto &e : x.as_array()) out.push_back(num(k, e));
    return out;
  }
  std::vector<double> matrix(const std::string &k, int64_t M) {
    const toml::value &x = get(k);
    if (!x.is_array()) fail(k, "expected an array of arrays (an M x M matrix)");
    const auto &rows = x.as_array();
    if ((int64_t)rows.size() != M)
      fail(k, "has " + std::to_string(rows.size()) + " rows, expected nspecies = " + std::to_string(M));
    std::vector<double> out;
    for (const auto &r : rows) {
      if (!r.is_array()) fail(k, "expected an array of arrays (an M x M matrix)");
      if ((int64_t)r.as_array().size() != M)
        fail(k, "a row has " + std::to_string(r.as_array().size()) + " entries, expected nspecies = " +
                    std::to_string(M));
      for (const auto &e : r.as_array()) out.push_back(num(k, e));
    }
    for (int64_t i = 0; i < M; i++)
      for (int64_t j = 0; j < i; j++)
        if (out[i * M + j] != out[j * M + i])
          fail(k, "matrix is not symmetric (entry [" + std::to_string(i + 1) + "][" + std::to_string(j + 1) + "])");
    return out;
  }
  Tab sub(const std::string &k) {
    const toml::value &x = get(k);
    if (!x.is_table()) fail(k, std::string("expected a table, got ") + type_name(x));
    return Tab(&x, key(k), file_);
  }
  /* every key not read is unknown; report the one on the first line */
  void finish() const {
    fail_first_unknown([&](const std::string &k) { return used_.count(k) > 0; });
  }
  /* Declare the keys this table may hold; any other key fails at once (before any "missing key"
   * message, so a misspelt key is reported as such). */
  void set_known(std::vector<std::string> k) {
    known_ = std::move(k);
    fail_first_unknown([&](const std::string &key_) {
      return std::find(known_.begin(), known_.end(), key_) != known_.end();
    });
  }
  /* Throw for the key on the earliest line that `accepted` rejects (none: nothing). */
  template <class Accept> void fail_first_unknown(Accept accepted) const {
    if (!v_ || !v_->is_table()) return;
    std::string bad;
    unsigned bad_line = 0;
    for (const auto &kv : v_->as_table()) {
      if (accepted(kv.first)) continue;
      unsigned ln = (unsigned)kv.second.location().line();
      if (bad.empty() || ln < bad_line) {
        bad = kv.first;
        bad_line = ln;
      }
    }
    if (!bad.empty())
      throw scene_error{fmt_line(file_, bad_line) + ": key '" + key(bad) + "': unknown key" + hint(bad)};
  }
  const std::string &file() const { return file_; }

  static const char *type_name(const toml::value &x) {
    switch (x.type()) {
      case toml::value_t::boolean: return "a boolean";
      case toml::value_t::integer: return "an integer";
      case toml::value_t::floating: return "a float";
      case toml::value_t::string: return "a string";
      case toml::value_t::array: return "an array";
      case toml::value_t::table: return "a table";
      default: return "a date/time";
    }
  }
  static std::string num_str(double d) {
    char b[64];
    std::snprintf(b, sizeof b, "%.17g", d);
    return b;
  }

 private:
  std::string hint(const std::string &bad) const {
    std::string s;
    for (const auto &k : known_) s += (s.empty() ? "" : ", ") + k;
    (void)bad;
    return s.empty() ? std::string() : " (known keys here: " + s + ")";
  }
  const toml::value *v_;
  std::string path_, file_;
  std::set<std::string> used_;
  std::vector<std::string> known_;
};

void require(bool ok, Tab &t, const std::string &k, const std::string &why) {
  if (!ok) t.fail(k, why);
}

/* The length of a run: the bound every time-stepped engine shares (core/run_bounds.h), naming
 * `key` of table t; per_step: the particle (and cell) updates of one step. */
void require_run_steps(Tab &t, const std::string &key, double steps, double per_step, const std::string &what) {
  char why[320];
  if (!gran::gran_run_steps_ok(steps, per_step, why, sizeof why)) t.fail(key, what + ": " + why);
}

/* A scene of the cell selector ([cell] parsed, t_end known): every species with a density gets
 * particles (an empty gas has no temperature: NaN is never an output; with aggregation the
 * species are cluster sizes, which may be empty: the monomers must not be), and the run's steps
 * (t_end - t_start) / dt are within the shared bound. */
void check_cell_run(Tab &top, Tab &en, const gran_scene &s) {
  Tab ce = top.sub("cell");
  const gran_dsmc_cell_options &c = s.cell;
  const bool agg = c.e_agg > 0 || std::isfinite(c.e_frag);
  double N = 0;
  for (int64_t k = 0; k < s.nspecies; k++) {
    const double nk = s.counts_kind == 0 ? (double)s.counts[(size_t)k] : std::nearbyint(s.density[(size_t)k] * s.volume / c.fn);
    if (s.counts_kind != 0 && s.density[(size_t)k] > 0 && !(nk >= 1) && (!agg || k == 0)) {
      const std::string msg = "n_k V / fn = " + Tab::num_str(s.density[(size_t)k]) + " x " + Tab::num_str(s.volume) +
                              " / " + Tab::num_str(c.fn) + " gives " + Tab::num_str(nk) + " simulated particles of species " +
                              std::to_string(k) + " (at least 1 needed: an empty species has no temperature)";
      if (c.fn > 1 && std::nearbyint(s.density[(size_t)k] * s.volume) >= 1) ce.fail("fn", msg);
      en.fail(s.counts_kind == 1 ? "N1" : "volume", msg);
    }
    N += nk;
  }
  const double C = (double)c.cells * (double)c.cells * (double)c.cells;
  require_run_steps(ce, "dt", (s.t_end - s.t_start) / c.dt, N + C,
                    "[engine] t_end - t_start = " + Tab::num_str(s.t_end - s.t_start) + " in steps of dt = " +
                        Tab::num_str(c.dt));
}

double memory_available_bytes();
std::string gb(double bytes);

/* times = [..] | {linear = {start, stop, n}} | {log = {start, stop, n}} */
std::vector<double> parse_times(Tab &t, const std::string &k) {
  const toml::value &x = t.get(k);
  std::vector<double> out;
  if (x.is_array()) {
    for (const auto &e : x.as_array()) out.push_back(t.num(k, e));
    if (out.empty()) t.fail(k, "the list of times is empty");
  } else if (x.is_table()) {
    Tab tt(&x, t.key(k), t.file());
    tt.set_known({"linear", "log"});
    const char *kind = tt.has("linear") ? "linear" : tt.has("log") ? "log" : nullptr;
    if (!kind) {
      tt.finish();
      t.fail(k, "expected an array of times, {linear = {start, stop, n}} or {log = {start, stop, n}}");
    }
    if (tt.has("linear") && tt.has("log")) t.fail(k, "give either 'linear' or 'log', not both");
    Tab g = tt.sub(kind);
    g.set_known({"start", "stop", "n"});
    if (!g.has("start")) g.fail_missing("start");
    if (!g.has("stop")) g.fail_missing("stop");
    if (!g.has("n")) g.fail_missing("n");
    double a = g.number("start"), b = g.number("stop");
    int64_t n = g.count("n");
    g.finish();
    tt.finish();
    if (n < 1 || n > 100000000) g.fail("n", "number of times must be in [1, 1e8], got " + std::to_string(n));
    if (8.0 * (double)n > 0.25 * memory_available_bytes())
      g.fail("n", std::to_string(n) + " output times need " + gb(8.0 * (double)n) + " for the times alone");
    if (n == 1 && a != b) g.fail("n", "n = 1 needs start == stop");
    if (!(b >= a)) g.fail("stop", "stop (" + Tab::num_str(b) + ") is before start (" + Tab::num_str(a) + ")");
    if (!std::strcmp(kind, "log") && !(a > 0)) g.fail("start", "log spacing needs start > 0");
    out.resize((size_t)n);
    for (int64_t i = 0; i < n; i++) {
      double f = n > 1 ? (double)i / (double)(n - 1) : 0.0;
      out[(size_t)i] = !std::strcmp(kind, "log") ? a * std::pow(b / a, f) : a + (b - a) * f;
    }
    out.front() = a;
    out.back() = b;
  } else {
    t.fail(k, std::string("expected an array or a table, got ") + Tab::type_name(x));
  }
  for (size_t i = 1; i < out.size(); i++)
    if (!(out[i] > out[i - 1]))
      t.fail(k, "times must increase strictly (" + Tab::num_str(out[i]) + " after " + Tab::num_str(out[i - 1]) + ")");
  return out;
}

std::string stem_of(const std::string &name) {
  std::string b = name;
  size_t s = b.find_last_of('/');
  if (s != std::string::npos) b = b.substr(s + 1);
  size_t d = b.rfind('.');
  if (d != std::string::npos && d > 0) b = b.substr(0, d);
  return b.empty() ? std::string("granary") : b;
}

/* ---- memory of a run, estimated before anything is allocated ----------------------------------
 * The limit is MemAvailable of /proc/meminfo (the memory the kernel can hand out without swapping),
 * or [engine] max_memory_gb when the scene sets it. */
double memory_available_bytes() {
  FILE *f = std::fopen("/proc/meminfo", "r");
  if (f) {
    char line[256];
    while (std::fgets(line, sizeof line, f)) {
      unsigned long long kb = 0;
      if (std::sscanf(line, "MemAvailable: %llu kB", &kb) == 1) {
        std::fclose(f);
        return (double)kb * 1024.0;
      }
    }
    std::fclose(f);
  }
  const long pages = sysconf(_SC_AVPHYS_PAGES), psz = sysconf(_SC_PAGESIZE);
  return pages > 0 && psz > 0 ? (double)pages * (double)psz : 1e18;
}

/* [engine] max_memory_gb in bytes (0: not given), read before the tables that allocate
 * (validated again with [engine]) */
double memory_limit_explicit(const toml::value &root) {
  if (root.is_table() && root.as_table().count("engine")) {
    const toml::value &en = root.as_table().at("engine");
    if (en.is_table() && en.as_table().count("max_memory_gb")) {
      const toml::value &x = en.as_table().at("max_memory_gb");
      const double g = x.is_floating() ? x.as_floating() : x.is_integer() ? (double)x.as_integer() : NAN;
      if (std::isfinite(g) && g > 0) return g * 1e9;
    }
  }
  return 0;
}
double memory_limit_bytes(const toml::value &root) {
  const double m = memory_limit_explicit(root);
  return m > 0 ? m : memory_available_bytes();
}

std::string gb(double bytes) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g GB", bytes / 1e9);
  return b;
}

}  // namespace

namespace {
/* heap overhead of one allocation (glibc: 16 B header, 16 B rounding on average) */
const double kAllocBytes = 32.0;

/* Row buffers of one replica: nbuf buffers of elems doubles a row over nt output times; each
 * buffer's descriptor (gran_row_buf; 1.5 of them: the vector grows by doubling) and two
 * allocations (its description and its rows). Measured (RSS, VmHWM): 2-D GSRD replicas of 4
 * particles with 21 output times take 9.0 kB each (1000 and 10000 replicas); this model gives 9.9. */
double row_bytes(double nbuf, double elems, double nt) {
  return 8.0 * elems * nt + nbuf * (1.5 * (double)sizeof(gran_row_buf) + 2.0 * kAllocBytes);
}
}  // namespace

double gran_scene_dsmc_bytes_(const gran_scene &s, gran_dsmc_bytes *b) {
  const double M = (double)s.nspecies;
  double N = 0;
  for (int64_t k = 0; k < s.nspecies; k++)
    N += s.counts_kind == 0 ? (double)s.counts[(size_t)k] : std::nearbyint(s.density[(size_t)k] * s.volume);
  double pow2 = 1;
  while (pow2 < M) pow2 *= 2;
  const bool disp = s.obs_msd || s.obs_tamsd, cell = s.selector == GRAN_SELECTOR_CELL;
  const double nc = cell ? (double)s.cell.cells : 0.0;
  b->particles = N * (28.0 + 24.0 + (disp ? 32.0 : 0.0) + (cell ? 36.0 : 0.0)) + 48.0 * nc * nc * nc;
  b->species = 8.0 * M * 40.0 + 6.0 * 2.0 * pow2 * 8.0;
  b->pairs = (s.model == GRAN_RESTITUTION_MATRIX || s.g2_is_matrix || s.visco_kind == 1 ? 40.0 * M * M : 0.0) +
             (s.obs_collision_counts ? 8.0 * M * M * 2.0 : 0.0);
  b->trajectories = s.obs_tamsd ? 24.0 * (double)s.tamsd_tracers * M * (double)s.tamsd_samples : 0.0;
  /* the engine and its adapter: structs, about 40 allocations (malloc header and rounding), the
   * adapter's mixture (species tables and theory work space) */
  b->fixed = 4096.0 + 40.0 * kAllocBytes + 64.0 * M;
  /* rows: the buffers gran_engine::declare makes (DSMC adapter: stats 2, T, msd + msd_total,
   * energy 3, momentum, M x M counts, a2, the cluster rows, the speed histograms) */
  const bool agg = s.agg.e_agg > 0 || std::isfinite(s.agg.e_frag);
  double elems = 2, nbuf = 2;
  auto add = [&](bool on, double bufs, double per_row) {
    if (on) nbuf += bufs, elems += per_row;
  };
  add(s.obs_temperatures, 1, M);
  add(s.obs_msd, 2, M + 1);
  add(s.obs_energy, 3, 3);
  add(s.obs_momentum, 1, 3);
  add(s.obs_collision_counts, 1, M * M);
  add(s.obs_sonine_a2, 1, M);
  add(agg, 3, 10 + M);
  add(s.obs_veldist, 1, M * (double)s.vd_bins);
  b->rows = row_bytes(nbuf, elems, (double)s.times.size());
  return b->particles + b->species + b->pairs + b->trajectories + b->fixed + b->rows;
}

double gran_scene_srd_bytes_(const gran_scene &s, gran_srd_bytes *b) {
  const gran_srd_options &o = s.srd.opt;
  double box = 1, bin = 1;
  for (int k = 0; k < o.dim; k++) {
    box *= (double)o.cells[k];
    bin *= (double)(o.cells[k] + (k == o.wall_axis ? 1 : 0)); /* walls: one more layer to shift into */
  }
  const double N = std::floor(o.n0 * box + 0.5), slab = std::min(bin, (double)SRD_SLAB_CELLS);
  int threads = srd_threads_used(o.threads); /* the engine's count (at most 4 per processor) */
  if (threads <= 0) threads = 1;
  b->particles = N * (48.0 + 2.0 + 12.0);
  b->cells = bin * (56.0 + 8.0) + (double)threads * (64.0 * slab + 4.0 * N * slab / bin);
  b->snapshots = (double)s.srd.snap_index.size() * box * 5.0 * 8.0;
  /* struct gran_srd, its 16 allocations, the adapter (SrdEngine and its copy of the options) */
  b->fixed = (double)sizeof(gran_srd) + 16.0 * kAllocBytes + 2.0 * (double)sizeof(gran_srd_options) + 256.0;
  /* rows: the buffers of the GSRD adapter's declare (engine_srd.cpp) */
  const auto &q = s.srd;
  double elems = 1, nbuf = 1;
  auto add = [&](bool on, double bufs, double per_row) {
    if (on) nbuf += bufs, elems += per_row;
  };
  add(q.obs_temperature, 2, 2);
  add(q.obs_energy, 5, 5);
  add(o.eps < 1.0, 2, 2);
  add(q.obs_momentum, 1, 3);
  add(q.obs_clustering, 3, 3);
  add(q.obs_a2, 1, 1);
  add(q.obs_sk, 1, (double)q.sk_bins);
  add(q.obs_stress, 3, 3);
  add(q.obs_profile, 1, 3.0 * (double)o.cells[1]);
  b->rows = row_bytes(nbuf, elems, (double)s.times.size());
  return b->particles + b->cells + b->snapshots + b->fixed + b->rows;
}

namespace {

/* The memory of the run this scene asks for, by part: every replica's engine and rows (the
 * engine's estimate, gran_scene_dsmc_bytes_ / gran_scene_srd_bytes_), its particle state once
 * more while a checkpoint image is assembled, its trajectories twice while the TAMSD is
 * computed; once per run the dense theory Jacobian (M <= 2048). `what` and `key` name the largest
 * part (the scene key that sets it); `detail` lists them. Returns the total. */
struct MemPart {
  const char *what, *table, *key;
  double bytes;
};
double run_memory(const gran_scene &s, std::vector<MemPart> &parts) {
  const double R = (double)s.replicas, ck = s.checkpoint_path.empty() ? 0.0 : 1.0;
  parts.clear();
  if (s.engine_type == "srd") {
    gran_srd_bytes e;
    gran_scene_srd_bytes_(s, &e);
    const char *nk = "n0";
    parts.push_back({"particles", "engine", nk, R * (e.particles + ck * 48.0 * (e.particles / 62.0))});
    parts.push_back({"cells", "engine", "cells", R * e.cells});
    parts.push_back({"snapshots", "observables", "snapshots", R * e.snapshots});
    parts.push_back({"engine structs", "engine", "replicas", R * e.fixed});
    parts.push_back({"recorded rows", "observables", "every", R * e.rows});
  } else {
    const double M = (double)s.nspecies, nt = (double)s.times.size();
    gran_dsmc_bytes e;
    gran_scene_dsmc_bytes_(s, &e);
    parts.push_back({"particles", "engine", s.counts_kind == 0 ? "counts" : s.counts_kind == 1 ? "N1" : "volume",
                     R * e.particles * (1.0 + ck)});
    parts.push_back({"species arrays and trees", "mixture", "nspecies", R * e.species});
    parts.push_back({"M x M tables", "observables", "collision_counts", R * e.pairs});
    parts.push_back({"trajectories", "observables", "tamsd", R * 2.0 * e.trajectories});
    parts.push_back({"engine structs", "engine", "replicas", R * e.fixed});
    parts.push_back({"recorded rows", "observables", "times", R * e.rows});
    parts.push_back({"theory", "observables", "theory", s.obs_theory ? (M <= 2048 ? 32.0 * M * M : 0.0) + 3.0 * nt * M * 8.0 : 0.0});
  }
  double total = 0;
  for (const MemPart &p : parts) total += p.bytes;
  return total;
}

std::string mem_detail(const std::vector<MemPart> &parts, int64_t replicas) {
  std::string d;
  for (const MemPart &p : parts)
    if (p.bytes > 0) d += (d.empty() ? "" : ", ") + std::string(p.what) + " " + gb(p.bytes);
  if (replicas > 1) d += "; " + std::to_string(replicas) + " replicas";
  return d;
}

/* The key to name when the run does not fit: [engine] replicas when one replica would fit, else
 * the largest part's. */
const MemPart &mem_culprit(const gran_scene &s, const std::vector<MemPart> &parts, double limit, double total,
                           bool *replicas) {
  const MemPart *big = &parts[0];
  for (const MemPart &p : parts)
    if (p.bytes > big->bytes) big = &p;
  *replicas = s.replicas > 1 && total / (double)s.replicas <= limit;
  return *big;
}

/* Parse time: the run against the limit, failing with the key's line. */
void check_memory(const gran_scene &s, double limit, Tab &top) {
  std::vector<MemPart> parts;
  const double total = run_memory(s, parts);
  if (total <= limit) return;
  bool rep = false;
  const MemPart &big = mem_culprit(s, parts, limit, total, &rep);
  const std::string why = "the run needs about " + gb(total) + " (" + mem_detail(parts, s.replicas) + "), more than the " +
                          gb(limit) + " available; reduce it, or set [engine] max_memory_gb to allow more";
  if (rep || !top.has(big.table) || !top.get(big.table).is_table()) {
    Tab en = top.sub("engine");
    en.fail(rep ? "replicas" : big.key, why);
  }
  Tab t = top.sub(big.table);
  t.fail(t.has(big.key) ? big.key : std::string(big.key), why);
}

/* Parse time: the theory a DSMC scene computes beside its run, against the theory work bound of
 * core/run_bounds.h. Passes over the M^2 species pairs, a lower bound: tau0 (1), the HCS start
 * (8, as measured for 1e4 - 3e4 species), and the ODE trajectories of the theory observables (at
 * least one pass per output time: T_theory, msd_theory unless the HCS closed form serves it, the
 * first Sonine trajectory at about 11 Maxwellian passes, the TAMSD at one per lag). Above the
 * bound the scene is refused naming mixture.nspecies; above the warning level it warns. */
void check_theory_work(const gran_scene &s, Tab &top) {
  const double nt = (double)s.times.size();
  const bool aggr = s.agg.e_agg > 0 || std::isfinite(s.agg.e_frag);
  double passes = 1.0;
  if (s.init == SCENE_INIT_HCS) passes += 8.0;
  if (s.obs_theory && !aggr) {
    if (s.obs_temperatures) passes += nt;
    const bool msd_closed = s.init == SCENE_INIT_HCS && s.model != GRAN_RESTITUTION_VISCOELASTIC;
    if (s.obs_msd && !msd_closed) passes += nt;
    if (s.obs_theory_sonine) passes += 11.0 * nt;
    if (s.obs_tamsd) passes += (double)s.tamsd_lags.size();
  }
  char why[320];
  const int level = gran::gran_theory_work_check(passes, (double)s.nspecies, why, sizeof why);
  if (level == 0) return;
  const std::string what = std::string("the kinetic theory beside this run (tau0") +
                           (s.init == SCENE_INIT_HCS ? ", the HCS start" : "") +
                           (s.obs_theory && !aggr ? ", the theory observables" : "") + ") needs at least " + why;
  Tab mx = top.sub("mixture");
  if (level == 2)
    mx.fail("nspecies", what + "; set [observables] theory = false and give the initial temperatures (\"equal\" or a "
                        "list) instead of \"hcs\", or use fewer species");
  gran_warning_add("scene key '%s': %s", mx.key("nspecies").c_str(), what.c_str());
}

/* ---- GSRD scenes (`[engine] type = "srd"`) ------------------------------------------------------
 * Tables: [engine] (the gran_srd_options keys, steps or t_end, device), [boundaries]
 * (lees_edwards, walls, vibrating_wall), [forces] (gravity, body_force), [observables], [output].
 * Every check names the key and its line; what gran_srd_create would refuse is refused here. */

/* `[engine] type = "srd"` (read before anything else: the two engines have different tables) */
bool is_srd_scene(const toml::value &root) {
  if (!root.is_table() || !root.as_table().count("engine")) return false;
  const toml::value &en = root.as_table().at("engine");
  if (!en.is_table() || !en.as_table().count("type")) return false;
  const toml::value &t = en.as_table().at("type");
  return t.is_string() && t.as_string().str == "srd";
}

/* an axis: "x" | "y" | "z" or 0 | 1 | 2, below dim */
int srd_axis(Tab &t, const std::string &k, int dim) {
  const toml::value &x = t.get(k);
  int ax = -1;
  if (x.is_string()) {
    const std::string &v = x.as_string().str;
    ax = v == "x" ? 0 : v == "y" ? 1 : v == "z" ? 2 : -2;
    if (ax == -2) t.fail(k, "expected \"x\", \"y\" or \"z\", got \"" + v + "\"");
  } else if (x.is_integer()) {
    ax = (int)std::max<int64_t>(-1, std::min<int64_t>(3, x.as_integer()));
    if (ax < 0 || ax > 2) t.fail(k, "expected 0, 1 or 2 (or \"x\", \"y\", \"z\")");
  } else {
    t.fail(k, std::string("expected an axis (\"x\", \"y\", \"z\"), got ") + Tab::type_name(x));
  }
  if (ax >= dim) t.fail(k, "axis " + std::to_string(ax) + " does not exist in " + std::to_string(dim) + "-D");
  return ax;
}

/* a vector of `dim` numbers */
void srd_vector(Tab &t, const std::string &k, int dim, double out[3]) {
  std::vector<double> v = t.numbers(k);
  if ((int)v.size() != dim)
    t.fail(k, "has " + std::to_string(v.size()) + " entries, expected dimension = " + std::to_string(dim));
  for (int i = 0; i < 3; i++) out[i] = i < dim ? v[(size_t)i] : 0.0;
}

/* The most steps a run may have (GSRD `steps`, the cell selector's (t_end - t_start) / dt): far
 * below the 2^63 of the step counters, so a step number never overflows. */
const double kMaxSteps = 1e15;

/* The step of time t (key k of table tab) on the grid of dt ('what' names dt in the message),
 * rounded; a time of more than kMaxSteps steps is refused before it is converted. */
int64_t step_of(Tab &tab, const std::string &k, double t, double dt, const char *what) {
  const double q = t / dt;
  if (!(std::fabs(q) <= kMaxSteps))
    tab.fail(k, "time " + Tab::num_str(t) + " is " + Tab::num_str(q) + " steps of " + what + " = " + Tab::num_str(dt) +
                    ", more than the 1e15 steps a run may have");
  return (int64_t)std::llround(q);
}
int64_t srd_step_of(Tab &tab, const std::string &k, double t, double dt) { return step_of(tab, k, t, dt, "engine.dt"); }

/* [output] (the same keys for every engine): path, checkpoint and its cadence */
static void parse_output_table(Tab &top, const std::string &F, gran_scene &s) {
  Tab ou(nullptr, "output", F);
  if (top.has("output")) ou = top.sub("output");
  ou.set_known({"path", "checkpoint", "checkpoint_interval", "checkpoint_every", "keep_checkpoint"});
  s.output_path = ou.string("path", stem_of(F) + ".h5");
  require(!s.output_path.empty(), ou, "path", "must not be empty");
  s.checkpoint_explicit = ou.has("checkpoint");
  s.checkpoint_path = ou.string("checkpoint", s.output_path + ".ckpt");
  s.checkpoint_interval = ou.number("checkpoint_interval", 600.0);
  require(s.checkpoint_interval >= 0, ou, "checkpoint_interval", "must be >= 0 (0: no time-based checkpoints)");
  s.checkpoint_every = ou.count("checkpoint_every", 0);
  require(s.checkpoint_every >= 0, ou, "checkpoint_every", "must be >= 0 (0: off)");
  s.keep_checkpoint = ou.boolean("keep_checkpoint", false);
  if (!s.checkpoint_path.empty() && s.checkpoint_path == s.output_path)
    ou.fail("checkpoint", "must differ from the output path");
  ou.finish();
}

void parse_scene_srd(const toml::value &root, gran_scene &s, double mem_limit) {
  const std::string &F = s.name;
  Tab top(&root, "", F);
  for (const char *k : {"mixture", "restitution", "initial"})
    if (top.has(k)) top.fail(k, "the [" + std::string(k) + "] table belongs to the DSMC engine; [engine] type = \"srd\" "
                                 "sets its gas in [engine] (dimension, cells, n0, T0, eps, sigma)");
  top.set_known({"title", "engine", "boundaries", "forces", "observables", "output"});
  s.title = top.string("title", "");
  gran_srd_options &o = s.srd.opt;
  gran_srd_options_default(&o);
  s.engine_type = "srd";
  s.nspecies = 0;
  s.obs_temperatures = s.obs_msd = s.obs_energy = s.obs_theory = 0;

  /* ---- [engine] ---- */
  Tab en = top.sub("engine");
  en.set_known({"type", "dimension", "cells", "box", "a", "n0", "particles_per_cell", "dt", "alpha", "eps", "sigma",
                "T0", "steps", "t_end", "seed", "sort_every", "threads", "device", "precision", "thermostat", "replicas",
                "keep_replicas", "max_memory_gb"});
  (void)en.string("type", "srd");
  if (en.has("max_memory_gb")) require(en.number("max_memory_gb") > 0, en, "max_memory_gb", "must be > 0 (GB of memory the run may use)");
  const int64_t dim = en.count("dimension", 3);
  require(dim == 2 || dim == 3, en, "dimension", "must be 2 or 3, got " + std::to_string(dim));
  o.dim = (int32_t)dim;
  o.a = en.number("a", 1.0);
  require(o.a > 0, en, "a", "cell size must be > 0, got " + Tab::num_str(o.a));
  if (en.has("cells") && en.has("box")) en.fail("box", "give either 'cells' or 'box', not both");
  if (!en.has("cells") && !en.has("box")) en.fail_missing("cells", "or box = [Lx, Ly(, Lz)] in length units");
  for (int k = 0; k < 3; k++) o.cells[k] = 1;
  if (en.has("cells")) {
    const toml::value &x = en.get("cells");
    std::vector<int64_t> c;
    if (x.is_array()) {
      for (const auto &e : x.as_array()) c.push_back(en.cnt("cells", e));
    } else {
      c.assign((size_t)dim, en.cnt("cells", x));
    }
    if ((int64_t)c.size() != dim)
      en.fail("cells", "has " + std::to_string(c.size()) + " entries, expected dimension = " + std::to_string(dim));
    for (int64_t k = 0; k < dim; k++) {
      require(c[(size_t)k] >= 1 && c[(size_t)k] <= (1 << 20), en, "cells",
              "cells per axis must be in [1, 2^20], got " + std::to_string(c[(size_t)k]));
      o.cells[k] = c[(size_t)k];
    }
  } else {
    const toml::value &x = en.get("box");
    std::vector<double> b;
    if (x.is_array()) {
      for (const auto &e : x.as_array()) b.push_back(en.num("box", e));
    } else {
      b.assign((size_t)dim, en.num("box", x));
    }
    if ((int64_t)b.size() != dim)
      en.fail("box", "has " + std::to_string(b.size()) + " entries, expected dimension = " + std::to_string(dim));
    for (int64_t k = 0; k < dim; k++) {
      const double L = b[(size_t)k] / o.a, r = std::nearbyint(L);
      require(b[(size_t)k] > 0, en, "box", "lengths must be > 0");
      require(std::fabs(L - r) <= 1e-9 * std::max(1.0, L) && r >= 1, en, "box",
              "length " + Tab::num_str(b[(size_t)k]) + " is not a whole number of cells of size a = " + Tab::num_str(o.a) +
                  " (" + Tab::num_str(L) + " cells)");
      require(r <= (double)(1 << 20), en, "box", "more than 2^20 cells per axis");
      o.cells[k] = (int64_t)r;
    }
  }
  double ncell = 1;
  for (int k = 0; k < dim; k++) ncell *= (double)o.cells[k];
  require(ncell * 2.0 < 4294967295.0, en, en.has("cells") ? "cells" : "box",
          Tab::num_str(ncell) + " cells: the engine indexes cells with 32 bits (at most about 2^31 cells)");
  if (en.has("n0") && en.has("particles_per_cell")) en.fail("particles_per_cell", "give either 'n0' or 'particles_per_cell', not both");
  const char *nk = en.has("particles_per_cell") ? "particles_per_cell" : "n0";
  o.n0 = en.number(nk, 10.0);
  require(o.n0 > 0, en, nk, "mean particles per cell must be > 0, got " + Tab::num_str(o.n0));
  const double N = std::floor(o.n0 * ncell + 0.5);
  require(N >= 1 && N < 4e9, en, nk, "gives " + Tab::num_str(N) + " particles (need 1 .. 4e9)");
  o.dt = en.number("dt", 1.0);
  require(o.dt > 0, en, "dt", "time step must be > 0, got " + Tab::num_str(o.dt));
  o.alpha_deg = en.number("alpha", 130.0);
  require(o.alpha_deg > 0 && o.alpha_deg <= 180, en, "alpha", "rotation angle must be in (0, 180] degrees, got " + Tab::num_str(o.alpha_deg));
  o.eps = en.number("eps", 1.0);
  require(o.eps >= 0 && o.eps <= 1, en, "eps", "restitution coefficient must be in [0, 1], got " + Tab::num_str(o.eps));
  o.sigma = en.number("sigma", 0.0);
  require(o.sigma >= 0, en, "sigma", "particle diameter must be >= 0, got " + Tab::num_str(o.sigma));
  require(o.eps == 1 || o.sigma > 0, en, "eps", "eps < 1 dissipates only with sigma > 0 (Eq. 2.1): give [engine] sigma");
  o.T0 = en.number("T0", 1.0);
  require(o.T0 > 0, en, "T0", "temperature must be > 0, got " + Tab::num_str(o.T0));
  if (en.has("seed")) {
    const toml::value &x = en.get("seed");
    if (!x.is_integer()) en.fail("seed", std::string("expected an integer, got ") + Tab::type_name(x));
    if (x.as_integer() < 0) en.fail("seed", "must be >= 0");
    s.seed = (uint64_t)x.as_integer();
  }
  o.seed = s.seed;
  const int64_t se = en.count("sort_every", 50);
  require(se >= 0 && se <= INT32_MAX, en, "sort_every", "must be >= 0 (0: never sort)");
  o.sort_every = (int32_t)se;
  const int64_t th = en.count("threads", 0);
  require(th >= 0 && th <= 4096, en, "threads", "must be in 0..4096 (0: all cores)");
  o.threads = (int32_t)th;
  /* thermostat: false / true (= "cell"), "cell" (cell-level Maxwell-Boltzmann) or "global" (one
   * factor on the velocities relative to the cell means: the one for viscosity measurements) */
  if (en.has("thermostat") && en.get("thermostat").is_string()) {
    const std::string th_name = en.string("thermostat", "off");
    if (th_name != "off" && th_name != "cell" && th_name != "global")
      en.fail("thermostat", "expected false, true, \"off\", \"cell\" or \"global\", got \"" + th_name + "\"");
    o.thermostat = th_name == "cell" ? 1 : th_name == "global" ? 2 : 0;
  } else {
    o.thermostat = en.boolean("thermostat", false) ? 1 : 0;
  }
  s.srd.device = en.string("device", "cpu");
  if (s.srd.device != "cpu" && s.srd.device != "cuda" && s.srd.device != "auto" && s.srd.device != "reference")
    en.fail("device", "expected \"cpu\", \"cuda\", \"auto\" or \"reference\", got \"" + s.srd.device + "\"");
  o.device = s.srd.device == "cuda" ? GRAN_SRD_DEVICE_CUDA
             : s.srd.device == "auto" ? GRAN_SRD_DEVICE_AUTO
             : s.srd.device == "reference" ? GRAN_SRD_DEVICE_REFERENCE
                                          : GRAN_SRD_DEVICE_CPU;
  const std::string prec = en.string("precision", "double");
  if (prec != "double" && prec != "float")
    en.fail("precision", "expected \"double\" or \"float\" (particle storage on a device), got \"" + prec + "\"");
  o.precision = prec == "float" ? 1 : 0;
  s.replicas = en.count("replicas", 1);
  require(s.replicas >= 1 && s.replicas <= 1000000, en, "replicas", "must be in 1..1000000");
  s.keep_replicas = en.boolean("keep_replicas", false);
  if (en.has("steps") && en.has("t_end")) en.fail("t_end", "give either 'steps' or 't_end', not both");
  int64_t steps = -1;
  if (en.has("steps")) {
    steps = en.count("steps");
    require(steps >= 1 && steps <= (int64_t)1e15, en, "steps", "must be in [1, 1e15], got " + std::to_string(steps));
  } else if (en.has("t_end")) {
    const double te = en.number("t_end");
    require(te > 0, en, "t_end", "must be > 0");
    steps = srd_step_of(en, "t_end", te, o.dt);
    require(steps >= 1 && std::fabs((double)steps * o.dt - te) <= 1e-9 * te, en, "t_end",
            "t_end = " + Tab::num_str(te) + " is not a whole number of steps dt = " + Tab::num_str(o.dt));
  }
  if (steps > 0)
    require_run_steps(en, en.has("steps") ? "steps" : "t_end", (double)steps, N,
                      std::to_string(steps) + " steps of " + Tab::num_str(N) + " particles");
  en.finish();

  /* ---- [boundaries] ---- (the tables are kept for the derived-value check at the end) */
  Tab le_t(nullptr, "boundaries.lees_edwards", F), wl_t(nullptr, "boundaries.walls", F),
      vb_t(nullptr, "boundaries.vibrating_wall", F), fo_t(nullptr, "forces", F);
  if (top.has("boundaries")) {
    Tab bd = top.sub("boundaries");
    bd.set_known({"lees_edwards", "walls", "vibrating_wall"});
    if (bd.has("lees_edwards")) {
      Tab le = bd.sub("lees_edwards");
      le_t = le;
      le.set_known({"shear_rate"});
      if (!le.has("shear_rate")) le.fail_missing("shear_rate");
      o.shear_rate = le.number("shear_rate");
      le.finish();
      require(o.shear_rate != 0, le, "shear_rate", "must not be 0 (leave lees_edwards out for no shear)");
    }
    if (bd.has("walls")) {
      Tab w = bd.sub("walls");
      wl_t = w;
      w.set_known({"axis", "rule", "T"});
      if (!w.has("axis")) w.fail_missing("axis", "\"x\", \"y\" or \"z\"");
      o.wall_axis = srd_axis(w, "axis", o.dim);
      const std::string rule = w.string("rule", "no-slip");
      if (rule == "no-slip") o.wall_rule = 1;
      else if (rule == "slip") o.wall_rule = 2;
      else w.fail("rule", "expected \"no-slip\" (bounce-back) or \"slip\" (specular), got \"" + rule + "\"");
      o.wall_T = w.number("T", 0.0);
      require(o.wall_T >= 0, w, "T", "virtual-particle temperature must be >= 0 (0: T0)");
      if (o.shear_rate != 0 && o.wall_axis <= 1)
        w.fail("axis", "walls and Lees-Edwards shear on the same axis (the shear's flow is x, its gradient y)");
      w.finish();
    }
    if (bd.has("vibrating_wall")) {
      Tab v = bd.sub("vibrating_wall");
      vb_t = v;
      v.set_known({"amplitude", "omega"});
      if (!v.has("amplitude")) v.fail_missing("amplitude");
      if (!v.has("omega")) v.fail_missing("omega");
      o.vib_amp = v.number("amplitude");
      o.vib_omega = v.number("omega");
      require(o.vib_amp >= 0, v, "amplitude", "must be >= 0");
      require(o.vib_omega >= 0, v, "omega", "must be >= 0");
      if (o.wall_axis < 0) bd.fail("vibrating_wall", "needs walls (the lower wall of [boundaries] walls vibrates)");
      v.finish();
    }
    bd.finish();
  }

  /* ---- [forces] ---- */
  double gforce = 0, bforce = 0; /* |gravity|, |body_force| */
  if (top.has("forces")) {
    Tab fo = top.sub("forces");
    fo_t = fo;
    fo.set_known({"gravity", "body_force"});
    double g[3] = {0, 0, 0}, f[3] = {0, 0, 0};
    if (fo.has("gravity")) srd_vector(fo, "gravity", o.dim, g);
    if (fo.has("body_force")) srd_vector(fo, "body_force", o.dim, f);
    for (int k = 0; k < 3; k++) o.accel[k] = g[k] + f[k];
    gforce = std::hypot(std::hypot(g[0], g[1]), g[2]);
    bforce = std::hypot(std::hypot(f[0], f[1]), f[2]);
    fo.finish();
  }

  /* ---- [observables] ---- */
  Tab ob(nullptr, "observables", F);
  if (top.has("observables")) ob = top.sub("observables");
  if (ob.has("theory_sonine"))
    ob.fail("theory_sonine", "the first Sonine theory is written by DSMC scenes only, not by GSRD scenes");
  ob.set_known({"times", "every", "temperature", "energy", "momentum", "clustering", "sonine_a2", "structure_factor",
                "stress", "velocity_profile", "theory", "snapshots"});
  if (ob.has("times") && ob.has("every")) ob.fail("every", "give either 'times' or 'every', not both");
  std::vector<int64_t> os;
  if (ob.has("times")) {
    std::vector<double> t = parse_times(ob, "times");
    if (t.front() < 0) ob.fail("times", "output times must be >= 0");
    for (double x : t) {
      const int64_t k = srd_step_of(ob, "times", x, o.dt);
      if (os.empty() || k > os.back()) os.push_back(k); /* rounded to the step grid; repeats dropped */
    }
    if (steps < 0) steps = std::max<int64_t>(1, os.back());
    if (os.back() > steps)
      ob.fail("times", "last output time " + Tab::num_str(t.back()) + " is after the end of the run (" +
                           std::to_string(steps) + " steps of dt = " + Tab::num_str(o.dt) + ")");
  } else {
    if (steps < 0) en.fail_missing("steps", "or t_end, or [observables] times");
    int64_t every = ob.count("every", std::max<int64_t>(1, steps / 50));
    require(every >= 1, ob, "every", "must be >= 1 (steps between output times)");
    require(steps / every <= 100000000, ob, "every", "gives more than 1e8 output times");
    for (int64_t k = 0; k <= steps; k += every) os.push_back(k);
  }
  if (!en.has("steps") && !en.has("t_end")) /* the length from the last output time */
    require_run_steps(ob, "times", (double)steps, N, std::to_string(steps) + " steps of " + Tab::num_str(N) + " particles");
  s.srd.steps = steps;
  s.srd.out_steps = os;
  s.srd.obs_temperature = ob.boolean("temperature", true);
  s.srd.obs_energy = ob.boolean("energy", true);
  s.srd.obs_momentum = ob.boolean("momentum", true);
  s.srd.obs_clustering = ob.boolean("clustering", true);
  s.srd.obs_a2 = ob.boolean("sonine_a2", false);
  s.srd.obs_profile = ob.boolean("velocity_profile", false);
  s.srd.obs_theory = ob.boolean("theory", true);
  s.srd.obs_stress = ob.boolean("stress", o.shear_rate != 0);
  if (s.srd.obs_stress && o.shear_rate == 0) ob.fail("stress", "the stress is measured under Lees-Edwards shear only ([boundaries] lees_edwards)");
  if (s.srd.obs_profile && o.dim < 2) ob.fail("velocity_profile", "needs dimension >= 2");
  if (ob.has("structure_factor") && ob.get("structure_factor").is_table()) {
    Tab sk = ob.sub("structure_factor");
    sk.set_known({"bins"});
    s.srd.obs_sk = 1;
    s.srd.sk_bins = sk.count("bins", 0);
    require(s.srd.sk_bins >= 0 && s.srd.sk_bins <= 1000000, sk, "bins", "must be in [1, 1e6] (0: cells / 2)");
    sk.finish();
  } else {
    s.srd.obs_sk = ob.boolean("structure_factor", false);
  }
  if (s.srd.obs_sk && s.srd.sk_bins == 0) s.srd.sk_bins = std::max<int64_t>(1, o.cells[0] / 2);
  if (s.srd.obs_sk && o.wall_axis >= 0) ob.fail("structure_factor", "S(k) needs a periodic box (no [boundaries] walls)");
  if (ob.has("snapshots")) {
    const int64_t nt = (int64_t)os.size();
    const toml::value &x = ob.get("snapshots");
    if (x.is_boolean()) {
      if (x.as_boolean())
        for (int64_t i = 0; i < nt; i++) s.srd.snap_index.push_back(i);
    } else if (x.is_table()) {
      Tab sn = ob.sub("snapshots");
      sn.set_known({"times", "every"});
      if (sn.has("times") == sn.has("every")) sn.fail(sn.has("times") ? "every" : "times", "give either 'times' or 'every' (output times between snapshots)");
      if (sn.has("every")) {
        const int64_t e = sn.count("every");
        require(e >= 1, sn, "every", "must be >= 1 (output times between snapshots)");
        for (int64_t i = 0; i < nt; i += e) s.srd.snap_index.push_back(i);
      } else {
        /* snapshot times (rounded to the step grid) join the output times */
        std::vector<int64_t> ks;
        for (double t : parse_times(sn, "times")) {
          const int64_t k = srd_step_of(sn, "times", t, o.dt);
          if (t < 0 || k > steps)
            sn.fail("times", "snapshot time " + Tab::num_str(t) + " is outside the run (0 .. " +
                                 Tab::num_str((double)steps * o.dt) + ")");
          ks.push_back(k);
        }
        std::vector<int64_t> merged(os.size() + ks.size());
        std::merge(os.begin(), os.end(), ks.begin(), ks.end(), merged.begin());
        merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
        os.swap(merged);
        for (int64_t k : ks) {
          const int64_t i = std::lower_bound(os.begin(), os.end(), k) - os.begin();
          if (s.srd.snap_index.empty() || i > s.srd.snap_index.back()) s.srd.snap_index.push_back(i);
        }
      }
      sn.finish();
    } else {
      ob.fail("snapshots", std::string("expected true, false or a table {times = [...]} / {every = k}, got ") + Tab::type_name(x));
    }
  }
  ob.finish();
  s.srd.out_steps = os;
  const int64_t nt = (int64_t)os.size();
  s.times.resize((size_t)nt);
  for (int64_t i = 0; i < nt; i++) s.times[(size_t)i] = (double)os[(size_t)i] * o.dt;
  s.t_start = 0.0;
  s.t_end = (double)steps * o.dt;

  /* ---- what the run derives from its inputs (src/srd/srd_limits.h, the bounds gran_srd_create
   * checks too, here with the run's length): named by the scene key ---- */
  {
    srd_limit_fail lf;
    if (!srd_check_limits(o, s.t_end, &lf)) {
      const std::string k = lf.key;
      if (k == "a") en.fail(en.has("a") ? "a" : en.has("box") ? "box" : "cells", lf.why);
      if (k == "wall_T") wl_t.fail("T", lf.why);
      if (k == "shear_rate") le_t.fail("shear_rate", lf.why);
      if (k == "vib_amp") vb_t.fail("amplitude", lf.why);
      if (k == "vib_omega") vb_t.fail("omega", lf.why);
      if (k == "accel") fo_t.fail(fo_t.has("gravity") && (!fo_t.has("body_force") || gforce >= bforce) ? "gravity" : "body_force", lf.why);
      en.fail(k, lf.why); /* T0, dt, sigma */
    }
  }

  /* ---- [output] (the same keys as a DSMC scene) ---- */
  parse_output_table(top, F, s);

  /* memory of the run (every replica), against the limit */
  check_memory(s, mem_limit, top);
  top.finish();
}

void parse_scene(const toml::value &root, gran_scene &s) {
  const std::string &F = s.name;
  const double mem_limit = memory_limit_bytes(root);
  s.max_memory = memory_limit_explicit(root);
  if (is_srd_scene(root)) return parse_scene_srd(root, s, mem_limit); /* GSRD: its own tables */
  Tab top(&root, "", F);
  top.set_known({"title", "mixture", "restitution", "initial", "engine", "observables", "output", "cell", "aggregation"});
  s.title = top.string("title", "");
  /* the engine type first: it decides which tables the scene must have */
  if (top.has("engine") && top.get("engine").is_table()) {
    Tab et = top.sub("engine");
    if (et.has("type")) {
      const toml::value &t = et.get("type");
      if (!t.is_string()) et.fail("type", std::string("must be a string: one of \"dsmc\", \"srd\"; got ") + Tab::type_name(t));
      if (t.as_string().str != "dsmc")
        et.fail("type", "unknown engine \"" + t.as_string().str + "\" (one of \"dsmc\", \"srd\")");
    }
  }

  /* ---- [mixture] ---- */
  if (!top.has("mixture")) top.fail_missing("mixture", "the [mixture] table is required");
  Tab mx = top.sub("mixture");
  mx.set_known({"nspecies", "mass", "m1", "sigma", "sigma1", "density", "density_law", "g2", "g2_matrix"});
  int64_t M = -1;
  std::string M_from;
  if (mx.has("nspecies")) {
    M = mx.count("nspecies");
    require(M >= 1, mx, "nspecies", "must be >= 1, got " + std::to_string(M));
    require(M <= 100000000, mx, "nspecies", "must be <= 1e8, got " + std::to_string(M));
    /* every species costs a few hundred bytes in the scene, the mixture, the trees and the engine */
    require(400.0 * (double)M <= mem_limit, mx, "nspecies",
            std::to_string(M) + " species need about " + gb(400.0 * (double)M) + ", more than the " + gb(mem_limit) +
                " available (set [engine] max_memory_gb to allow more)");
    M_from = "nspecies";
  }
  std::vector<double> mass, sigma, density;
  auto take = [&](const char *k, std::vector<double> &v) {
    if (!mx.has(k)) return;
    v = mx.numbers(k);
    if (M < 0) {
      M = (int64_t)v.size();
      M_from = k;
      if (M < 1) mx.fail(k, "the array is empty");
    } else if ((int64_t)v.size() != M) {
      mx.fail(k, "has " + std::to_string(v.size()) + " entries, but " + M_from + " gives " + std::to_string(M) +
                     " species");
    }
  };
  take("mass", mass);
  take("sigma", sigma);
  take("density", density);
  if (M < 0) mx.fail_missing("nspecies", "or give the arrays mass / sigma / density");
  s.nspecies = M;
  double m1 = mx.number("m1", 1.0), sigma1 = mx.number("sigma1", 1.0);
  require(m1 > 0, mx, "m1", "must be > 0");
  require(sigma1 > 0, mx, "sigma1", "must be > 0");
  if (mx.has("mass") && mx.has("m1")) mx.fail("m1", "give either 'mass' or 'm1', not both");
  if (mx.has("sigma") && mx.has("sigma1")) mx.fail("sigma1", "give either 'sigma' or 'sigma1', not both");
  if (mass.empty()) {
    mass.resize((size_t)M);
    for (int64_t k = 0; k < M; k++) mass[(size_t)k] = m1 * (double)(k + 1);
  }
  if (sigma.empty()) {
    sigma.resize((size_t)M);
    for (int64_t k = 0; k < M; k++) sigma[(size_t)k] = sigma1 * std::cbrt((double)(k + 1));
  }
  for (int64_t k = 0; k < M; k++) {
    require(mass[(size_t)k] > 0, mx, "mass", "entry " + std::to_string(k + 1) + " must be > 0");
    require(sigma[(size_t)k] > 0, mx, "sigma", "entry " + std::to_string(k + 1) + " must be > 0");
  }
  if (mx.has("density") && mx.has("density_law")) mx.fail("density_law", "give either 'density' or 'density_law', not both");
  if (mx.has("density_law")) {
    Tab law = mx.sub("density_law");
    law.set_known({"n1", "theta"});
    if (!law.has("n1")) law.fail_missing("n1");
    double n1 = law.number("n1"), theta = law.number("theta", 0.0);
    law.finish();
    require(n1 > 0, law, "n1", "must be > 0");
    density.resize((size_t)M);
    for (int64_t k = 0; k < M; k++) density[(size_t)k] = n1 * std::pow((double)(k + 1), -theta);
  } else if (density.empty()) {
    mx.fail_missing("density", "or density_law = {n1 = ..., theta = ...}");
  }
  for (int64_t k = 0; k < M; k++)
    require(density[(size_t)k] >= 0, mx, mx.has("density") ? "density" : "density_law",
            "entry " + std::to_string(k + 1) + " is negative");
  require(density[0] > 0, mx, mx.has("density") ? "density" : "density_law",
          "the first species must have a positive density (it sets the time unit)");
  if (mx.has("g2") && mx.has("g2_matrix")) mx.fail("g2_matrix", "give either 'g2' or 'g2_matrix', not both");
  if (mx.has("g2_matrix")) {
    s.g2_is_matrix = 1;
    s.g2_matrix = mx.matrix("g2_matrix", M);
    for (double g : s.g2_matrix) require(g > 0, mx, "g2_matrix", "entries must be > 0");
  } else {
    s.g2 = mx.number("g2", 1.0);
    require(s.g2 > 0, mx, "g2", "must be > 0");
  }
  mx.finish();
  s.mass = mass;
  s.sigma = sigma;
  s.density = density;

  /* ---- [restitution] ---- */
  if (top.has("restitution")) {
    Tab rs = top.sub("restitution");
    rs.set_known({"model", "eps", "eps_matrix", "beta", "beta_matrix", "material"});
    std::string model = rs.string("model", rs.has("eps_matrix") ? "matrix" : (rs.has("beta") || rs.has("beta_matrix") || rs.has("material")) ? "viscoelastic" : "constant");
    auto forbid = [&](const char *k, const char *m) {
      if (rs.has(k)) rs.fail(k, std::string("not used by model = \"") + m + "\"");
    };
    if (model == "constant") {
      s.model = GRAN_RESTITUTION_CONSTANT;
      forbid("eps_matrix", "constant"), forbid("beta", "constant"), forbid("beta_matrix", "constant"), forbid("material", "constant");
      s.eps = rs.number("eps", 1.0);
      require(s.eps >= 0 && s.eps <= 1, rs, "eps", "restitution coefficient must be in [0, 1], got " + Tab::num_str(s.eps));
    } else if (model == "matrix") {
      s.model = GRAN_RESTITUTION_MATRIX;
      forbid("eps", "matrix"), forbid("beta", "matrix"), forbid("beta_matrix", "matrix"), forbid("material", "matrix");
      if (!rs.has("eps_matrix")) rs.fail_missing("eps_matrix", "model = \"matrix\" needs it");
      s.eps_matrix = rs.matrix("eps_matrix", M);
      for (double e : s.eps_matrix)
        require(e >= 0 && e <= 1, rs, "eps_matrix", "restitution coefficients must be in [0, 1], got " + Tab::num_str(e));
    } else if (model == "viscoelastic") {
      s.model = GRAN_RESTITUTION_VISCOELASTIC;
      forbid("eps", "viscoelastic"), forbid("eps_matrix", "viscoelastic");
      int n = rs.has("beta") + rs.has("beta_matrix") + rs.has("material");
      if (n == 0) rs.fail_missing("beta", "model = \"viscoelastic\" needs beta, beta_matrix or material");
      if (n > 1) rs.fail(rs.has("material") ? "material" : "beta_matrix", "give only one of beta, beta_matrix, material");
      if (rs.has("beta")) {
        s.visco_kind = 0;
        s.beta = rs.number("beta");
        require(s.beta >= 0, rs, "beta", "must be >= 0");
      } else if (rs.has("beta_matrix")) {
        s.visco_kind = 1;
        s.beta_matrix = rs.matrix("beta_matrix", M);
        for (double b : s.beta_matrix) require(b >= 0, rs, "beta_matrix", "entries must be >= 0");
      } else {
        s.visco_kind = 2;
        Tab mt = rs.sub("material");
        mt.set_known({"A", "Y", "nu"});
        for (const char *k : {"A", "Y", "nu"})
          if (!mt.has(k)) mt.fail_missing(k);
        s.mat_A = mt.number("A");
        s.mat_Y = mt.number("Y");
        s.mat_nu = mt.number("nu");
        mt.finish();
        require(s.mat_A >= 0, mt, "A", "must be >= 0");
        require(s.mat_Y > 0, mt, "Y", "must be > 0");
        require(s.mat_nu > -1 && s.mat_nu < 0.5, mt, "nu", "Poisson ratio must be in (-1, 0.5)");
        /* the largest beta_ij (gran_mixture_set_viscoelastic_material) must be finite */
        double smax = 0, mmin = HUGE_VAL;
        for (int64_t k = 0; k < M; k++) smax = std::fmax(smax, sigma[(size_t)k]), mmin = std::fmin(mmin, mass[(size_t)k]);
        const double rho = 2.0 * s.mat_Y / (3.0 * (1.0 - s.mat_nu) * (1.0 + s.mat_nu));
        const double bmax = 1.5 * s.mat_A * std::pow(rho * std::sqrt(0.5 * smax) / (0.5 * mmin), 0.4);
        require(std::isfinite(rho) && std::isfinite(bmax), rs, "material",
                "A and Y give a viscoelastic beta that overflows (" + Tab::num_str(bmax) + ")");
      }
    } else {
      rs.fail("model", "unknown model \"" + model + "\" (constant, matrix or viscoelastic)");
    }
    rs.finish();
  }

  /* ---- [initial] ---- */
  if (top.has("initial")) {
    Tab in = top.sub("initial");
    in.set_known({"temperatures", "T_mean", "T1", "t_start"});
    s.t_start = in.number("t_start", 0.0);
    if (in.has("T_mean") && in.has("T1")) in.fail("T1", "give either 'T_mean' or 'T1', not both");
    if (in.has("temperatures")) {
      const toml::value &x = in.get("temperatures");
      if (x.is_string()) {
        const std::string &v = x.as_string().str;
        if (v == "hcs") s.init = SCENE_INIT_HCS;
        else if (v == "equal") s.init = SCENE_INIT_EQUAL;
        else in.fail("temperatures", "expected \"hcs\", \"equal\" or an array, got \"" + v + "\"");
      } else if (x.is_array()) {
        s.init = SCENE_INIT_LIST;
        for (const auto &e : x.as_array()) s.T_list.push_back(in.num("temperatures", e));
        if ((int64_t)s.T_list.size() != M)
          in.fail("temperatures", "has " + std::to_string(s.T_list.size()) + " entries, but " + M_from + " gives " +
                                      std::to_string(M) + " species");
        for (double T : s.T_list) require(T > 0, in, "temperatures", "must be > 0");
      } else {
        in.fail("temperatures", std::string("expected \"hcs\", \"equal\" or an array, got ") + Tab::type_name(x));
      }
    }
    if (s.model == GRAN_RESTITUTION_VISCOELASTIC && s.init == SCENE_INIT_HCS)
      in.fail("temperatures", std::string(in.has("temperatures") ? "\"hcs\"" : "the default \"hcs\"") +
                                  ": viscoelastic restitution has no homogeneous cooling state with constant "
                                  "temperature ratios; give temperatures = \"equal\" or a list");
    if (s.init == SCENE_INIT_LIST && (in.has("T_mean") || in.has("T1")))
      in.fail(in.has("T1") ? "T1" : "T_mean", "not used when temperatures are listed");
    if (in.has("T1")) {
      if (s.init != SCENE_INIT_HCS) in.fail("T1", "only with temperatures = \"hcs\"");
      s.hcs_norm = GRAN_HCS_NORM_T1;
      s.T_value = in.number("T1");
      require(s.T_value > 0, in, "T1", "must be > 0");
    } else {
      s.T_value = in.number("T_mean", 1.0);
      require(s.T_value > 0, in, "T_mean", "must be > 0");
    }
    /* derived values must stay finite: squared speeds 3 T/m (far tails: x 100) and the energy of
     * up to 4e9 particles */
    double mmin = HUGE_VAL, Tmax = s.T_value;
    for (double m : mass) mmin = std::fmin(mmin, m);
    for (double T : s.T_list) Tmax = std::fmax(Tmax, T);
    const char *tk = s.init == SCENE_INIT_LIST ? "temperatures" : in.has("T1") ? "T1" : "T_mean";
    require(gran_derived_finite(300.0 * Tmax / mmin) && gran_derived_finite(1.5 * Tmax * 4e9 * 100.0), in, tk,
            "temperature " + Tab::num_str(Tmax) + " is too large: speeds and energies would overflow");
    in.finish();
  } else if (s.model == GRAN_RESTITUTION_VISCOELASTIC) {
    top.fail_missing("initial", "viscoelastic restitution has no homogeneous cooling state: give [initial] "
                                "temperatures = \"equal\" or a list");
  }

  /* ---- [engine] ---- */
  if (!top.has("engine")) top.fail_missing("engine", "the [engine] table is required");
  Tab en = top.sub("engine");
  en.set_known({"type", "selector", "seed", "t_end", "counts", "N1", "volume", "bound_refresh", "replicas",
                "keep_replicas", "max_memory_gb", "speed_classes"});
  if (en.has("max_memory_gb")) {
    const double g = en.number("max_memory_gb");
    require(g > 0, en, "max_memory_gb", "must be > 0 (GB of memory the run may use)");
  }
  std::string type = en.string("type", "dsmc");
  if (type != "dsmc") en.fail("type", "unknown engine \"" + type + "\" (\"dsmc\" or \"srd\")");
  s.engine_type = type;
  std::string sel = en.string("selector", "lowrank");
  if (sel == "lowrank") s.selector = GRAN_SELECTOR_LOWRANK;
  else if (sel == "bird") s.selector = GRAN_SELECTOR_BIRD;
  else if (sel == "cell") s.selector = GRAN_SELECTOR_CELL; /* [cell] below */
  else en.fail("selector", "unknown selector \"" + sel + "\" (lowrank, bird or cell)");
  if (en.has("seed")) {
    const toml::value &x = en.get("seed");
    if (!x.is_integer()) en.fail("seed", std::string("expected an integer, got ") + Tab::type_name(x));
    if (x.as_integer() < 0) en.fail("seed", "must be >= 0");
    s.seed = (uint64_t)x.as_integer();
  }
  int nc = en.has("counts") + en.has("N1") + en.has("volume");
  if (nc == 0) en.fail_missing("counts", "give the particle numbers as counts = [...], N1 = ... or volume = ...");
  if (nc > 1) en.fail(en.has("volume") ? "volume" : "N1", "give only one of counts, N1, volume");
  if (en.has("counts")) {
    s.counts_kind = 0;
    const toml::value &x = en.get("counts");
    if (!x.is_array()) en.fail("counts", std::string("expected an array of integers, got ") + Tab::type_name(x));
    for (const auto &e : x.as_array()) {
      int64_t c = en.cnt("counts", e);
      if (c < 0) en.fail("counts", "particle numbers must be >= 0, got " + std::to_string(c));
      s.counts.push_back(c);
    }
    if ((int64_t)s.counts.size() != M)
      en.fail("counts", "has " + std::to_string(s.counts.size()) + " entries, but " + M_from + " gives " +
                            std::to_string(M) + " species");
    if (s.counts[0] < 1) en.fail("counts", "the first species needs at least one particle");
  } else if (en.has("N1")) {
    s.counts_kind = 1;
    s.N1 = en.number("N1");
    require(s.N1 >= 1 && s.N1 <= 1e12, en, "N1", "must be in [1, 1e12], got " + Tab::num_str(s.N1));
    s.volume = s.N1 / s.density[0];
  } else {
    s.counts_kind = 2;
    s.volume = en.number("volume");
    require(s.volume > 0, en, "volume", "must be > 0");
  }
  if (s.counts_kind != 0) {
    double total = 0;
    for (double n : s.density) total += std::nearbyint(n * s.volume);
    require(total <= 4e9, en, s.counts_kind == 1 ? "N1" : "volume", "gives " + Tab::num_str(total) + " particles (limit 4e9)");
  }
  s.bound_refresh = en.count("bound_refresh", 0);
  require(s.bound_refresh >= 0, en, "bound_refresh", "must be >= 0");
  /* issue 11: true, false or "auto" (the default: GRAN_SPEED_CLASSES_AUTO) */
  s.speed_classes = GRAN_SPEED_CLASSES_AUTO;
  if (en.has("speed_classes")) {
    const toml::value &sc = en.get("speed_classes");
    if (sc.is_boolean()) s.speed_classes = sc.as_boolean() ? GRAN_SPEED_CLASSES_ON : GRAN_SPEED_CLASSES_OFF;
    else if (!sc.is_string() || sc.as_string().str != "auto") en.fail("speed_classes", "expected true, false or \"auto\"");
  }
  /* replicas (driver: src/io/run.cpp) */
  s.replicas = en.count("replicas", 1);
  require(s.replicas >= 1 && s.replicas <= 1000000, en, "replicas", "must be in 1..1000000");
  s.keep_replicas = en.boolean("keep_replicas", false);
  bool have_tend = en.has("t_end");
  if (have_tend) s.t_end = en.number("t_end");
  en.finish();

  /* ---- [cell]: the time-step/cell selector (src/dsmc/cell.cpp) ---- */
  /* e_agg, e_frag, eps_f of [cell] or [aggregation] (absent: the defaults) */
  auto agg_keys = [](Tab &t, double *e_agg, double *e_frag, double *eps_f) {
    *e_agg = t.number("e_agg", 0.0);
    require(*e_agg >= 0, t, "e_agg", "must be >= 0 (0: no aggregation)");
    if (t.has("e_frag")) {
      const toml::value &x = t.get("e_frag");
      *e_frag = x.is_floating() ? x.as_floating() : t.number("e_frag");
      require(!std::isnan(*e_frag) && *e_frag >= 0, t, "e_frag", "must be >= 0 (inf or absent: no fragmentation)");
    }
    *eps_f = t.number("eps_f", 1.0);
    require(*eps_f >= 0 && *eps_f <= 1, t, "eps_f", "must be in [0, 1]");
  };
  gran_dsmc_cell_options_default(&s.cell);
  if (s.selector == GRAN_SELECTOR_CELL && !top.has("cell"))
    top.fail_missing("cell", "selector \"cell\" needs a [cell] table (at least dt)");
  if (top.has("cell")) {
    if (s.selector != GRAN_SELECTOR_CELL) top.fail("cell", "the [cell] table needs [engine] selector = \"cell\"");
    Tab ce = top.sub("cell");
    ce.set_known({"cells", "dt", "fn", "e_agg", "e_frag", "eps_f", "heat_rate", "bath_density", "bath_mass", "bath_T",
                  "bath_sigma", "placement"});
    gran_dsmc_cell_options &c = s.cell;
    c.cells = ce.count("cells", 1);
    require(c.cells >= 1 && c.cells <= 1024, ce, "cells", "must be in 1..1024 (cells per side of the box)");
    if (!ce.has("dt")) ce.fail_missing("dt", "the time step dt is required");
    c.dt = ce.number("dt");
    require(c.dt > 0, ce, "dt", "must be > 0");
    c.fn = ce.number("fn", 1.0);
    require(c.fn > 0, ce, "fn", "must be > 0 (real particles per simulated particle)");
    agg_keys(ce, &c.e_agg, &c.e_frag, &c.eps_f);
    c.heat_rate = ce.number("heat_rate", 0.0);
    require(c.heat_rate >= 0, ce, "heat_rate", "must be >= 0 (0: no thermostat)");
    c.bath_density = ce.number("bath_density", 0.0);
    require(c.bath_density >= 0, ce, "bath_density", "must be >= 0 (0: no bath)");
    c.bath_mass = ce.number("bath_mass", 1.0);
    require(c.bath_mass > 0, ce, "bath_mass", "must be > 0");
    c.bath_T = ce.number("bath_T", 1.0);
    require(c.bath_T >= 0, ce, "bath_T", "must be >= 0");
    c.bath_sigma = ce.number("bath_sigma", 1.0);
    require(c.bath_sigma >= 0, ce, "bath_sigma", "must be >= 0");
    const std::string pl = ce.string("placement", "random");
    if (pl == "random") c.placement = GRAN_PLACE_RANDOM;
    else if (pl == "collision") c.placement = GRAN_PLACE_COLLISION;
    else ce.fail("placement", "unknown placement \"" + pl + "\" (random or collision)");
    ce.finish();
  }

  /* ---- [aggregation]: aggregation and fragmentation in any selector (src/dsmc/agg_event.cpp;
   * for selector "cell" the same keys as [cell], which then must not repeat them) ---- */
  gran_dsmc_agg_options_default(&s.agg);
  if (top.has("aggregation")) {
    Tab ag = top.sub("aggregation");
    ag.set_known({"e_agg", "e_frag", "eps_f", "frag_law"});
    if (s.selector == GRAN_SELECTOR_CELL && top.has("cell")) {
      Tab ce = top.sub("cell");
      for (const char *k : {"e_agg", "e_frag", "eps_f"})
        if (ce.has(k) && ag.has(k)) ag.fail(k, std::string("is given in [cell] too: give it in one table"));
    }
    if (s.speed_classes == GRAN_SPEED_CLASSES_ON) top.fail("aggregation", "speed classes ([engine] speed_classes) have no aggregation");
    gran_dsmc_agg_options &a = s.agg;
    agg_keys(ag, &a.e_agg, &a.e_frag, &a.eps_f);
    const std::string law = ag.string("frag_law", "monomers");
    if (law == "monomers") a.frag_law = GRAN_FRAG_MONOMERS;
    else if (law == "binary") a.frag_law = GRAN_FRAG_BINARY;
    else ag.fail("frag_law", "unknown fragment law \"" + law + "\" (monomers or binary)");
    ag.finish();
    if (s.selector == GRAN_SELECTOR_CELL) { /* the cell selector's options hold them */
      if (ag.has("e_agg")) s.cell.e_agg = a.e_agg;
      if (ag.has("e_frag")) s.cell.e_frag = a.e_frag;
      if (ag.has("eps_f")) s.cell.eps_f = a.eps_f;
      s.cell.frag_law = a.frag_law;
    }
  }
  if (s.selector == GRAN_SELECTOR_CELL) { /* one truth: the cell options */
    s.agg.e_agg = s.cell.e_agg;
    s.agg.e_frag = s.cell.e_frag;
    s.agg.eps_f = s.cell.eps_f;
    s.agg.frag_law = s.cell.frag_law;
  }

  /* ---- [observables] ---- */
  Tab ob(nullptr, "observables", F);
  if (top.has("observables")) ob = top.sub("observables");
  ob.set_known({"times", "temperatures", "msd", "energy", "momentum", "collision_counts", "sonine_a2", "theory",
                "theory_rtol", "theory_sonine", "velocity_distribution", "tamsd"});
  if (ob.has("times")) {
    s.times = parse_times(ob, "times");
  } else {
    if (!have_tend) en.fail_missing("t_end", "or give [observables] times");
    double span = s.t_end - s.t_start;
    if (!(span > 0)) en.fail("t_end", "end time " + Tab::num_str(s.t_end) + " is not after t_start = " + Tab::num_str(s.t_start));
    const int n = 41;
    for (int i = 0; i < n; i++) s.times.push_back(s.t_start + span * std::pow(10.0, -3.0 + 3.0 * i / (n - 1)));
    s.times.back() = s.t_end;
  }
  if (!have_tend) s.t_end = s.times.back();
  if (!(s.t_end > s.t_start))
    en.fail("t_end", "end time " + Tab::num_str(s.t_end) + " is not after t_start = " + Tab::num_str(s.t_start));
  if (s.selector == GRAN_SELECTOR_CELL) check_cell_run(top, en, s);
  if (s.times.front() < s.t_start)
    ob.fail("times", "first output time " + Tab::num_str(s.times.front()) + " is before t_start = " + Tab::num_str(s.t_start));
  if (s.times.back() > s.t_end)
    ob.fail("times", "last output time " + Tab::num_str(s.times.back()) + " is after t_end = " + Tab::num_str(s.t_end));
  if (s.selector == GRAN_SELECTOR_CELL) /* the cell selector counts steps of cell.dt from t_start */
    step_of(have_tend ? en : ob, have_tend ? "t_end" : "times", s.t_end - s.t_start, s.cell.dt, "cell.dt");
  if (ob.has("velocity_distribution") && ob.get("velocity_distribution").is_table()) {
    Tab vd = ob.sub("velocity_distribution");
    vd.set_known({"bins", "cmax"});
    s.obs_veldist = 1;
    s.vd_bins = vd.count("bins", 60);
    s.vd_cmax = vd.number("cmax", 4.0);
    vd.finish();
    require(s.vd_bins >= 1 && s.vd_bins <= 1000000, vd, "bins", "must be in [1, 1e6]");
    require(s.vd_cmax > 0, vd, "cmax", "must be > 0");
  } else {
    s.obs_veldist = ob.boolean("velocity_distribution", false);
  }
  s.obs_temperatures = ob.boolean("temperatures", true);
  /* with aggregation or fragmentation particles merge and split: displacements, trajectories and
   * per-pair collision counts are not defined, so msd defaults to off there and is refused on */
  const bool aggr = s.agg.e_agg > 0 || std::isfinite(s.agg.e_frag);
  s.obs_msd = ob.boolean("msd", !aggr);
  if (aggr && s.obs_msd)
    ob.fail("msd", "the mean-squared displacement is not defined with aggregation or fragmentation (clusters appear and "
                   "vanish): set msd = false or leave it out (its default is false there)");
  s.obs_energy = ob.boolean("energy", true);
  s.obs_momentum = ob.boolean("momentum", false);
  s.obs_collision_counts = ob.boolean("collision_counts", false);
  if (aggr && s.obs_collision_counts)
    ob.fail("collision_counts", "per-pair collision counts are not defined with aggregation or fragmentation");
  if (aggr && ob.has("tamsd"))
    ob.fail("tamsd", "trajectories are not defined with aggregation or fragmentation (clusters appear and vanish)");
  s.obs_sonine_a2 = ob.boolean("sonine_a2", false);
  s.obs_theory = ob.boolean("theory", true);
  s.theory_rtol = ob.number("theory_rtol", 1e-8);
  require(s.theory_rtol > 0 && s.theory_rtol < 1, ob, "theory_rtol", "must be in (0, 1)");
  /* the first Sonine trajectory (gran_theory_temperatures_approx) exists for constant or matrix
   * restitution of a gas whose species are fixed */
  s.obs_theory_sonine = ob.boolean("theory_sonine", false);
  if (s.obs_theory_sonine) {
    if (!s.obs_theory) ob.fail("theory_sonine", "needs theory = true (it is written beside T_theory)");
    if (!s.obs_temperatures) ob.fail("theory_sonine", "needs temperatures = true (it is written beside T_theory)");
    if (s.model == GRAN_RESTITUTION_VISCOELASTIC)
      ob.fail("theory_sonine", "the first Sonine theory is implemented for constant or matrix restitution, not "
                               "viscoelastic restitution");
    if (s.agg.e_agg > 0 || std::isfinite(s.agg.e_frag))
      ob.fail("theory_sonine", "no Sonine theory for aggregation or fragmentation (the species change)");
  }
  if (ob.has("tamsd")) {
    Tab ta = ob.sub("tamsd");
    ta.set_known({"tracers", "dt", "samples", "lags"});
    for (const char *k : {"tracers", "dt", "samples"})
      if (!ta.has(k)) ta.fail_missing(k);
    s.obs_tamsd = 1;
    s.tamsd_tracers = ta.count("tracers");
    s.tamsd_dt = ta.number("dt");
    s.tamsd_samples = ta.count("samples");
    require(s.tamsd_tracers >= 1, ta, "tracers", "must be >= 1, got " + std::to_string(s.tamsd_tracers));
    require(s.tamsd_dt > 0, ta, "dt", "must be > 0");
    require(s.tamsd_samples >= 2 && s.tamsd_samples <= 100000000, ta, "samples", "must be in [2, 1e8]");
    const double traj_bytes = 24.0 * (double)s.tamsd_tracers * (double)M * (double)s.tamsd_samples;
    require(traj_bytes <= 16e9, ta, "samples",
            "tracers x species x samples x 24 bytes = " + Tab::num_str(traj_bytes) + " bytes of trajectories (limit 16e9)");
    double t_meas = s.tamsd_dt * (double)(s.tamsd_samples - 1);
    require(s.t_start + t_meas <= s.t_end * (1 + 1e-12), ta, "samples",
            "trajectories need t_start + dt*(samples-1) = " + Tab::num_str(s.t_start + t_meas) + " <= t_end = " +
                Tab::num_str(s.t_end));
    if (ta.has("lags")) {
      s.tamsd_lags = parse_times(ta, "lags");
    } else {
      int n = 30;
      for (int i = 0; i < n; i++) s.tamsd_lags.push_back(s.tamsd_dt * std::pow(0.5 * (double)(s.tamsd_samples - 1), (double)i / (n - 1)));
    }
    for (double &L : s.tamsd_lags) {
      require(L >= s.tamsd_dt * (1 - 1e-12) && L < t_meas, ta, "lags",
              "lag " + Tab::num_str(L) + " outside [dt, dt*(samples-1)) = [" + Tab::num_str(s.tamsd_dt) + ", " + Tab::num_str(t_meas) + ")");
    }
    /* lags are whole sampling intervals: round them, and keep each once */
    std::vector<double> lags;
    for (double L : s.tamsd_lags) {
      const int64_t n = std::max<int64_t>(1, (int64_t)std::llround(L / s.tamsd_dt));
      const double r = (double)n * s.tamsd_dt;
      if (lags.empty() || r > lags.back()) lags.push_back(r);
    }
    s.tamsd_lags = lags;
    ta.finish();
  }
  ob.finish();

  /* ---- [output] ---- */
  parse_output_table(top, F, s);
  check_memory(s, mem_limit, top);
  check_theory_work(s, top);

  top.finish();
}

}  // namespace

int gran_scene_parse_text_(const std::string &text, const std::string &name, gran_scene **scene) {
  gran_scene *s = new gran_scene();
  s->text = text;
  s->name = name;
  std::vector<unsigned> line_map;
  struct MapGuard {
    ~MapGuard() { t_line_map = nullptr; }
  } guard;
  try {
    std::string prepared;
    prepass(text, name, prepared, line_map);
    t_line_map = &line_map;
    std::istringstream is(prepared);
    toml::value root = toml::parse(is, name);
    parse_scene(root, *s);
  } catch (const toml::syntax_error &e) {
    std::string first = e.what();
    /* toml11's message is multi-line; keep its first line and name the file and line */
    size_t nl = first.find('\n');
    if (nl != std::string::npos) first = first.substr(0, nl);
    if (first.rfind("[error] ", 0) == 0) first = first.substr(8);
    std::string msg = fmt_line(name, (unsigned)e.location().line()) + ": TOML syntax error: " + first;
    delete s;
    return GRAN_ERROR(GRAN_ERR_PARSE, "%s", msg.c_str());
  } catch (const scene_error &e) {
    delete s;
    return GRAN_ERROR(GRAN_ERR_PARSE, "%s", e.msg.c_str());
  } catch (const toml::exception &e) {
    std::string first = e.what();
    size_t nl = first.find('\n');
    if (nl != std::string::npos) first = first.substr(0, nl);
    delete s;
    return GRAN_ERROR(GRAN_ERR_PARSE, "%s: %s", fmt_line(name, (unsigned)e.location().line()).c_str(), first.c_str());
  } catch (...) {
    delete s;
    throw;
  }
  *scene = s;
  return GRAN_SUCCESS;
}

int gran_scene_T0_(const gran_scene *s, const gran_mixture *mix, double *T0, double *tau0) {
  const int64_t M = s->nspecies;
  if (s->init == SCENE_INIT_HCS) {
    double t0 = NAN;
    GRAN_CALL(gran_theory_hcs(mix, s->hcs_norm, s->T_value, T0, &t0));
  } else if (s->init == SCENE_INIT_EQUAL) {
    for (int64_t k = 0; k < M; k++) T0[k] = s->T_value;
  } else {
    for (int64_t k = 0; k < M; k++) T0[k] = s->T_list[(size_t)k];
  }
  /* tau0 = 2 / xi_1(T(0)) (Eq. 21): in the HCS every species gives the same value */
  if (tau0) {
    std::vector<double> xi((size_t)M);
    if (gran_theory_cooling_rates(mix, T0, xi.data()) == GRAN_SUCCESS) {
      *tau0 = xi[0] > 0 ? 2.0 / xi[0] : INFINITY;
    } else {
      *tau0 = NAN;
      gran_clear_error();
    }
  }
  return GRAN_SUCCESS;
}

double gran_scene_memory_limit_(const gran_scene *s) {
  return s->max_memory > 0 ? s->max_memory : memory_available_bytes();
}

int gran_scene_check_memory_(const gran_scene *s, const char *key) {
  std::vector<MemPart> parts;
  const double total = run_memory(*s, parts), limit = gran_scene_memory_limit_(s);
  GRAN_CHECK(total <= limit, GRAN_ERR_NOMEM,
             "%s: the run needs about %s (%s), more than the %s available; lower it, or set [engine] max_memory_gb to "
             "allow more", key, gb(total).c_str(), mem_detail(parts, s->replicas).c_str(), gb(limit).c_str());
  return GRAN_SUCCESS;
}

/* ------------------------------------------------------------------------------------------------
 * Public API
 * ---------------------------------------------------------------------------------------------- */

/** @brief Load and validate a scene file.
 *  @param[in] path  TOML file  @param[out] scene  new scene (gran_scene_destroy) */
GRAN_EXTERN int gran_scene_load(const char *path, gran_scene **scene) {
  GRAN_CHECK_PTR(path);
  GRAN_CHECK_PTR(scene);
  GRAN_TRY {
    *scene = nullptr;
    /* only a regular file of bounded size: /dev/zero would be read without end, a FIFO blocks */
    struct stat sb;
    GRAN_CHECK(stat(path, &sb) == 0, GRAN_ERR_IO, "cannot open scene file '%s': %s", path, std::strerror(errno));
    GRAN_CHECK(S_ISREG(sb.st_mode), GRAN_ERR_IO, "scene file '%s' is not a regular file", path);
    GRAN_CHECK((uint64_t)sb.st_size <= kMaxSceneBytes, GRAN_ERR_PARSE,
               "scene file '%s' is %lld bytes; the limit is %zu (16 MiB)", path, (long long)sb.st_size, kMaxSceneBytes);
    std::ifstream f(path, std::ios::binary);
    GRAN_CHECK(f.good(), GRAN_ERR_IO, "cannot open scene file '%s': %s", path, std::strerror(errno));
    std::string text((size_t)sb.st_size, '\0');
    f.read(&text[0], (std::streamsize)text.size());
    GRAN_CHECK(!f.bad() && f.gcount() == (std::streamsize)text.size(), GRAN_ERR_IO, "cannot read scene file '%s'", path);
    char extra;
    GRAN_CHECK(!f.read(&extra, 1), GRAN_ERR_IO, "scene file '%s' grew while it was read", path);
    return gran_scene_parse_text_(text, path, scene);
  }
  GRAN_CATCH
}

/** @brief Parse and validate a scene from text. @param[in] name file name for messages (NULL: "scene") */
GRAN_EXTERN int gran_scene_parse(const char *text, const char *name, gran_scene **scene) {
  GRAN_CHECK_PTR(text);
  GRAN_CHECK_PTR(scene);
  GRAN_TRY {
    *scene = nullptr;
    return gran_scene_parse_text_(text, name ? name : "scene", scene);
  }
  GRAN_CATCH
}

/** @brief Release a scene; NULL-safe, sets *scene to NULL. */
GRAN_EXTERN int gran_scene_destroy(gran_scene **scene) {
  GRAN_CHECK_PTR(scene);
  delete *scene;
  *scene = nullptr;
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_scene_text(const gran_scene *scene, const char **text) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(text);
  *text = scene->text.c_str();
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_scene_output_path(const gran_scene *scene, const char **path) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(path);
  *path = scene->output_path.c_str();
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_scene_sizes(const gran_scene *scene, int64_t *nspecies, int64_t *ntimes, int64_t *nlags,
                                 double *t_start, double *t_end) {
  GRAN_CHECK_PTR(scene);
  if (nspecies) *nspecies = scene->nspecies;
  if (ntimes) *ntimes = (int64_t)scene->times.size();
  if (nlags) *nlags = scene->obs_tamsd ? (int64_t)scene->tamsd_lags.size() : 0;
  if (t_start) *t_start = scene->t_start;
  if (t_end) *t_end = scene->t_end;
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_scene_times(const gran_scene *scene, double *times) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(times);
  std::copy(scene->times.begin(), scene->times.end(), times);
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_scene_lags(const gran_scene *scene, double *lags) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(lags);
  GRAN_CHECK(scene->obs_tamsd, GRAN_ERR_STATE, "the scene '%s' records no TAMSD ([observables] tamsd)",
             scene->name.c_str());
  std::copy(scene->tamsd_lags.begin(), scene->tamsd_lags.end(), lags);
  return GRAN_SUCCESS;
}

/** @brief A new mixture built from the scene's [mixture] and [restitution] tables. */
GRAN_EXTERN int gran_scene_mixture(const gran_scene *scene, gran_mixture **mix) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(mix);
  GRAN_CHECK(scene->engine_type != "srd", GRAN_ERR_ARG, /* GSRD scenes set their gas in [engine] */
             "scene '%s' is a GSRD scene ([engine] type = \"srd\"): it has no mixture", scene->name.c_str());
  GRAN_TRY {
    const gran_scene *s = scene;
    gran_mixture *m = nullptr;
    GRAN_CALL(gran_mixture_create(s->nspecies, s->mass.data(), s->sigma.data(), s->density.data(), &m));
    int st = GRAN_SUCCESS;
    if (s->g2_is_matrix) st = gran_mixture_set_g2_matrix(m, s->g2_matrix.data());
    else st = gran_mixture_set_g2(m, s->g2);
    if (!st) {
      if (s->model == GRAN_RESTITUTION_CONSTANT) st = gran_mixture_set_restitution(m, s->eps);
      else if (s->model == GRAN_RESTITUTION_MATRIX) st = gran_mixture_set_restitution_matrix(m, s->eps_matrix.data());
      else if (s->visco_kind == 0) st = gran_mixture_set_viscoelastic(m, s->beta);
      else if (s->visco_kind == 1) st = gran_mixture_set_viscoelastic_matrix(m, s->beta_matrix.data());
      else st = gran_mixture_set_viscoelastic_material(m, s->mat_A, s->mat_Y, s->mat_nu);
    }
    if (st) {
      gran_mixture_destroy(&m);
      return st;
    }
    *mix = m;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Initial temperatures as [initial] asks (HCS from the theory module), and
 *  tau0 = 2 / xi_1(T(0)) (Eq. 21; the HCS relaxation time when the start is the HCS). */
GRAN_EXTERN int gran_scene_initial_temperatures(const gran_scene *scene, const gran_mixture *mix, double *T0,
                                                double *tau0) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(mix);
  GRAN_CHECK_PTR(T0);
  GRAN_TRY {
    int64_t M = 0;
    GRAN_CALL(gran_mixture_nspecies(mix, &M));
    GRAN_CHECK(M == scene->nspecies, GRAN_ERR_ARG, "argument 'mix' has %" PRId64 " species, the scene %" PRId64, M,
               scene->nspecies);
    return gran_scene_T0_(scene, mix, T0, tau0);
  }
  GRAN_CATCH
}

/** @brief Engine options and particle numbers of the scene (see the header). */
GRAN_EXTERN int gran_scene_dsmc_options(const gran_scene *scene, gran_dsmc_options *opt, int64_t *counts,
                                        int *have_counts) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(opt);
  GRAN_CHECK(scene->engine_type != "srd", GRAN_ERR_ARG, /* GSRD scenes run through gran_scene_run */
             "scene '%s' is a GSRD scene ([engine] type = \"srd\"): it has no DSMC options", scene->name.c_str());
  GRAN_TRY {
    const gran_scene *s = scene;
    GRAN_CALL(gran_dsmc_options_default(opt));
    opt->selector = s->selector;
    opt->seed = s->seed;
    opt->t_start = s->t_start;
    opt->bound_refresh = s->bound_refresh;
    opt->speed_classes = s->speed_classes; /* issue 11 */
    opt->observe = 0;
    if (s->obs_msd) opt->observe |= GRAN_OBSERVE_DISPLACEMENT;
    if (s->obs_collision_counts) opt->observe |= GRAN_OBSERVE_COLLISION_COUNTS;
    if (s->obs_tamsd) {
      opt->observe |= GRAN_OBSERVE_TRAJECTORIES;
      opt->traj_per_species = s->tamsd_tracers;
      opt->traj_dt = s->tamsd_dt;
      opt->traj_samples = s->tamsd_samples;
    }
    if (s->counts_kind != 0) opt->volume = s->volume; /* the engine rounds N_k = n_k V */
    if (counts)
      for (int64_t k = 0; k < s->nspecies; k++)
        counts[k] = s->counts_kind == 0 ? s->counts[(size_t)k]
                                        : (int64_t)std::nearbyint(s->density[(size_t)k] * s->volume /
                                                                  (s->selector == GRAN_SELECTOR_CELL ? s->cell.fn : 1.0));
    if (have_counts) *have_counts = s->counts_kind == 0;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief A new DSMC engine exactly as `granary run` creates it. */
GRAN_EXTERN int gran_scene_dsmc(const gran_scene *scene, const gran_mixture *mix, gran_dsmc **sim) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(mix);
  GRAN_CHECK_PTR(sim);
  GRAN_TRY {
    const gran_scene *s = scene;
    std::vector<double> T0((size_t)s->nspecies);
    GRAN_CALL(gran_scene_initial_temperatures(s, mix, T0.data(), nullptr));
    gran_dsmc_options opt;
    GRAN_CALL(gran_scene_dsmc_options(s, &opt, nullptr, nullptr));
    if (s->selector == GRAN_SELECTOR_CELL) /* cell selector */
      return gran_dsmc_create_cell(mix, s->counts_kind == 0 ? s->counts.data() : nullptr, T0.data(), &opt, &s->cell,
                                   sim);
    /* event selectors: [aggregation] (off: the plain engine) */
    return gran_dsmc_create_agg(mix, s->counts_kind == 0 ? s->counts.data() : nullptr, T0.data(), &opt, &s->agg, sim);
  }
  GRAN_CATCH
}

/** @brief The scene's aggregation and fragmentation ([aggregation], or [cell] of the cell selector). */
GRAN_EXTERN int gran_scene_dsmc_agg_options(const gran_scene *scene, gran_dsmc_agg_options *agg) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(agg);
  GRAN_TRY {
    *agg = scene->agg;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief The [cell] table of the scene (defaults where a key is not given). */
GRAN_EXTERN int gran_scene_dsmc_cell_options(const gran_scene *scene, gran_dsmc_cell_options *cell) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(cell);
  GRAN_TRY {
    *cell = scene->cell;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
