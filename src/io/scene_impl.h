/* scene_impl.h - what the core scene parser (src/io/scene.cpp) shares with the engines' schemas
 * (src/dsmc/scene_dsmc.cpp, src/srd/scene_srd.cpp): the key declaration, the TOML table reader
 * that checks keys, types and bounds against the declarations, and the helpers every engine uses
 * (times, run length, memory). Included by scene files only (it includes toml11).
 *
 * Every failure is a scene_error "FILE:LINE: key 'table.key': reason", converted to GRAN_ERR_PARSE
 * at the entry point. Keys are consumed as they are read; whatever is left in a table afterwards is
 * an unknown key. The known keys of a table are the declared ones (gran_scene_key.table). */
#ifndef GRANARY_IO_SCENE_IMPL_H
#define GRANARY_IO_SCENE_IMPL_H

#include <toml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "io/io_impl.h"

namespace gran_scene_io {

/* Thrown inside the parser only; converted to GRAN_ERR_PARSE at the entry point. */
struct scene_error {
  std::string msg;
};

/* "FILE:LINE" of a line of the text toml11 parsed, as a line of the scene as written */
std::string fmt_line(const std::string &file, unsigned line);

/* One TOML table being read: remembers which keys were used; knows the declared keys. */
class Tab {
 public:
  Tab(const toml::value *v, std::string path, std::string file, const gran_scene_schema *schema)
      : v_(v), path_(std::move(path)), file_(std::move(file)), schema_(schema) {}

  bool has(const std::string &k) const { return v_ && v_->is_table() && v_->as_table().count(k); }
  std::string key(const std::string &k) const { return path_.empty() ? k : path_ + "." + k; }
  unsigned line() const { return v_ ? (unsigned)v_->location().line() : 1u; }
  unsigned line_of(const std::string &k) const { return (unsigned)v_->as_table().at(k).location().line(); }
  const std::string &path() const { return path_; }
  const std::string &file() const { return file_; }
  const gran_scene_schema *schema() const { return schema_; }

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

  /* The declaration of key k of this table (an undeclared key is a bug of the parser: named). */
  const gran_scene_key &decl(const std::string &k) const {
    if (const gran_scene_key *d = find_decl(k)) return *d;
    throw scene_error{file_ + ": key '" + key(k) + "' is read by the parser but not declared in the engine's schema"};
  }
  const gran_scene_key *find_decl(const std::string &k) const {
    if (!schema_) return nullptr;
    for (size_t i = 0; i < schema_->ncommon; i++)
      if (path_ == schema_->common[i].table && k == schema_->common[i].name) return &schema_->common[i];
    for (size_t i = 0; i < schema_->nkeys; i++)
      if (path_ == schema_->keys[i].table && k == schema_->keys[i].name) return &schema_->keys[i];
    return nullptr;
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

  /* ---- declared keys: default and bounds from the declaration ----
   * real/integer/flag/word(k): the value, or the declared default; real/integer(k, def): the value
   * or a default the engine derives. Bounds with a `why` are checked on the value either way. */
  double real(const std::string &k) { return real(k, decl_default(k)); }
  double real(const std::string &k, double def) {
    const double v = number(k, def);
    check(k, v, num_str(v));
    return v;
  }
  int64_t integer(const std::string &k) { return integer(k, (int64_t)decl_default(k)); }
  int64_t integer(const std::string &k, int64_t def) {
    const int64_t v = count(k, def);
    check(k, (double)v, std::to_string(v));
    return v;
  }
  bool flag(const std::string &k) {
    const std::string d = decl(k).def;
    if (d != "true" && d != "false") internal(k, "has no boolean default");
    return boolean(k, d == "true");
  }
  std::string word(const std::string &k) {
    std::string d = decl(k).def;
    if (d.size() < 2 || d.front() != '"' || d.back() != '"') internal(k, "has no string default");
    return string(k, d.substr(1, d.size() - 2));
  }
  /* a key the scene has (the caller checked has(), or reports it missing): bounds checked */
  double value(const std::string &k) { return real(k, 0.0); }
  int64_t count_value(const std::string &k) { return integer(k, 0); }
  /* the declared bound of k on value v (shown as `shown`) */
  void check(const std::string &k, double v, const std::string &shown) const {
    const gran_scene_key &d = decl(k);
    if (!d.why || !d.why[0]) return;
    bool ok = true;
    if (!gran_scene_bounds_(d.bounds, v, &ok)) internal(k, "has a message but no checkable bounds");
    if (ok) return;
    std::string why = d.why;
    const size_t at = why.find("{}");
    if (at != std::string::npos) why.replace(at, 2, shown);
    fail(k, why);
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
    return Tab(&x, key(k), file_, schema_);
  }
  /* The table `k` when the scene has it, else an empty one (its keys take their defaults). */
  Tab sub_or_empty(const std::string &k) { return has(k) ? sub(k) : Tab(nullptr, key(k), file_, schema_); }
  /* every key not read is unknown; report the one on the first line */
  void finish() const {
    fail_first_unknown([&](const std::string &k) { return used_.count(k) > 0; });
  }
  /* The keys this table may hold are the declared ones (common first, then the engine's); any
   * other key fails at once (before any "missing key" message, so a misspelt key is reported as
   * such). */
  void set_known() {
    std::vector<std::string> k;
    if (schema_) {
      for (size_t i = 0; i < schema_->ncommon; i++)
        if (path_ == schema_->common[i].table) k.push_back(schema_->common[i].name);
      for (size_t i = 0; i < schema_->nkeys; i++)
        if (path_ == schema_->keys[i].table) k.push_back(schema_->keys[i].name);
    }
    set_known(std::move(k));
  }
  /* The same with the keys given (the grammar of a value, such as the times tables). */
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
      throw scene_error{fmt_line(file_, bad_line) + ": key '" + key(bad) + "': unknown key" + hint()};
  }

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
  [[noreturn]] void internal(const std::string &k, const char *what) const {
    throw scene_error{file_ + ": key '" + key(k) + "': its declaration " + what + " (a bug of the engine's schema)"};
  }
  double decl_default(const std::string &k) const {
    const char *d = decl(k).def;
    char *end = nullptr;
    const double v = std::strtod(d, &end);
    if (end == d || *end) internal(k, "has no numeric default");
    return v;
  }
  std::string hint() const {
    std::string s;
    for (const auto &k : known_) s += (s.empty() ? "" : ", ") + k;
    return s.empty() ? std::string() : " (known keys here: " + s + ")";
  }
  const toml::value *v_;
  std::string path_, file_;
  const gran_scene_schema *schema_;
  std::set<std::string> used_;
  std::vector<std::string> known_;
};

inline void require(bool ok, Tab &t, const std::string &k, const std::string &why) {
  if (!ok) t.fail(k, why);
}

/* The length of a run: the bound every time-stepped engine shares (core/run_bounds.h), naming
 * `key` of table t; per_step: the particle (and cell) updates of one step. */
void require_run_steps(Tab &t, const std::string &key, double steps, double per_step, const std::string &what);

/* times = [..] | {linear = {start, stop, n}} | {log = {start, stop, n}}: strictly increasing */
std::vector<double> parse_times(Tab &t, const std::string &k);

/* The most steps a run may have (GSRD `steps`, the cell selector's (t_end - t_start) / dt): far
 * below the 2^63 of the step counters, so a step number never overflows. */
constexpr double kMaxSteps = 1e15;

/* The step of time t (key k of table tab) on the grid of dt ('what' names dt in the message),
 * rounded; a time of more than kMaxSteps steps is refused before it is converted. */
int64_t step_of(Tab &tab, const std::string &k, double t, double dt, const char *what);

/* MemAvailable of /proc/meminfo (bytes), and bytes as "1.23 GB" */
double memory_available_bytes();
std::string gb(double bytes);

}  // namespace gran_scene_io

/* What an engine's scene parser gets: the top-level table (its known keys already checked, the
 * title and [engine] type read) and the memory the run may use. The core reads [output], checks
 * the memory (gran_engine_entry.memory) and the unknown top-level keys after it. */
struct gran_scene_doc {
  gran_scene_io::Tab *top;
  double mem_limit; /* bytes */
};

/* The core's part of [engine]: type, seed, replicas, keep_replicas, max_memory_gb (scene.cpp). */
void gran_scene_engine_common_(gran_scene_io::Tab &en, gran_scene &s);

#endif
