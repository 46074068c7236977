/* scene.cpp - TOML scene files (toml11): the core of the parser and the gran_scene_* API.
 *
 * The core checks the file (size, encoding, nesting), parses the TOML, picks the engine by
 * `[engine] type` through the engine table (src/io/engine.cpp) and reads what every engine shares:
 * the title, the common [engine] keys, [output], the memory check. Each engine declares its keys
 * as data and reads its own tables (src/dsmc/scene_dsmc.cpp, src/srd/scene_srd.cpp); the reader
 * (scene_impl.h) checks every table's keys, types and declared bounds, naming FILE:LINE and the
 * key. Every failure is GRAN_ERR_PARSE with "FILE:LINE: key 'table.key': reason" (syntax errors
 * carry toml11's own line). */
#include "io/scene_impl.h"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

#include "io/engine.h"
#include "core/run_bounds.h"

using gran_scene_io::scene_error;
using gran_scene_io::Tab;
using gran_scene_io::require;
using gran_scene_io::gb;
using gran_scene_io::memory_available_bytes;
using gran_scene_io::fmt_line;

namespace {

/* Line numbers of the text toml11 parsed -> lines of the scene as written (the pre-pass below may
 * break long lines); empty: the same. Set for the duration of one parse. */
thread_local const std::vector<unsigned> *t_line_map = nullptr;

}  // namespace

std::string gran_scene_io::fmt_line(const std::string &file, unsigned line) {
  if (t_line_map && line >= 1 && line <= t_line_map->size()) line = (*t_line_map)[line - 1];
  return file + ":" + std::to_string(line);
}

bool gran_scene_bounds_(const char *b, double v, bool *ok) {
  if (!b) return false;
  const std::string s = b;
  auto num = [](const std::string &t, double *x) {
    const char *c = t.c_str();
    while (*c == ' ') c++;
    char *e = nullptr;
    *x = std::strtod(c, &e);
    if (e == c) return false;
    while (*e == ' ') e++;
    return *e == 0;
  };
  double a = 0, z = 0;
  if (s.rfind(">=", 0) == 0 && num(s.substr(2), &a)) return *ok = v >= a, true;
  if (s.rfind("<=", 0) == 0 && num(s.substr(2), &a)) return *ok = v <= a, true;
  if (s.rfind(">", 0) == 0 && num(s.substr(1), &a)) return *ok = v > a, true;
  if (s.rfind("<", 0) == 0 && num(s.substr(1), &a)) return *ok = v < a, true;
  const size_t comma = s.find(',');
  if (s.size() > 2 && (s[0] == '[' || s[0] == '(') && (s.back() == ']' || s.back() == ')') && comma != std::string::npos &&
      num(s.substr(1, comma - 1), &a) && num(s.substr(comma + 1, s.size() - comma - 2), &z))
    return *ok = (s[0] == '[' ? v >= a : v > a) && (s.back() == ']' ? v <= z : v < z), true;
  const size_t dots = s.find("..");
  if (dots != std::string::npos && num(s.substr(0, dots), &a) && num(s.substr(dots + 2), &z))
    return *ok = v >= a && v <= z, true;
  return false;
}

void gran_scene_io::require_run_steps(Tab &t, const std::string &key, double steps, double per_step,
                                      const std::string &what) {
  char why[320];
  if (!gran::gran_run_steps_ok(steps, per_step, why, sizeof why)) t.fail(key, what + ": " + why);
}

int64_t gran_scene_io::step_of(Tab &tab, const std::string &k, double t, double dt, const char *what) {
  const double q = t / dt;
  if (!(std::fabs(q) <= kMaxSteps))
    tab.fail(k, "time " + Tab::num_str(t) + " is " + Tab::num_str(q) + " steps of " + what + " = " + Tab::num_str(dt) +
                    ", more than the 1e15 steps a run may have");
  return (int64_t)std::llround(q);
}

namespace {

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

}  // namespace

/* times = [..] | {linear = {start, stop, n}} | {log = {start, stop, n}} */
std::vector<double> gran_scene_io::parse_times(Tab &t, const std::string &k) {
  const toml::value &x = t.get(k);
  std::vector<double> out;
  if (x.is_array()) {
    for (const auto &e : x.as_array()) out.push_back(t.num(k, e));
    if (out.empty()) t.fail(k, "the list of times is empty");
  } else if (x.is_table()) {
    Tab tt(&x, t.key(k), t.file(), t.schema());
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

namespace {

std::string stem_of(const std::string &name) {
  std::string b = name;
  size_t s = b.find_last_of('/');
  if (s != std::string::npos) b = b.substr(s + 1);
  size_t d = b.rfind('.');
  if (d != std::string::npos && d > 0) b = b.substr(0, d);
  return b.empty() ? std::string("granary") : b;
}

}  // namespace

/* ---- the memory limit of a run ----------------------------------------------------------------
 * MemAvailable of /proc/meminfo (the memory the kernel can hand out without swapping), or
 * [engine] max_memory_gb when the scene sets it. */
double gran_scene_io::memory_available_bytes() {
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

namespace {

thread_local bool g_defer_memory_check = false; /* gran_scene_defer_memory_check_ */

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

}  // namespace

std::string gran_scene_io::gb(double bytes) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g GB", bytes / 1e9);
  return b;
}

namespace {

/* ---- the keys every engine shares (the core reads them) --------------------------------------- */
const gran_scene_key kCommonKeys[] = {
    {"", "title", "string", "\"\"", "", "", "free text, stored in the output", "gran_scene.title", ""},
    {"", "engine", "table", "required", "", "", "the engine and the length of the run", "gran_scene (engine part)", ""},
    {"", "observables", "table", "", "", "", "what is recorded, at which times", "gran_scene (observables)", ""},
    {"", "output", "table", "", "", "", "output file and checkpoints", "gran_scene (output part)", ""},
    {"engine", "type", "string", "\"dsmc\"", "a type of the engine table", "",
     "the engine (src/io/engine.cpp); its keys follow", "gran_scene.engine_type", ""},
    {"engine", "seed", "integer", "1", ">= 0", "", "RNG seed (replica r >= 1: stream r of it)", "gran_scene.seed", ""},
    {"engine", "replicas", "integer", "1", "1..1000000", "", "independent runs, reduced to mean and standard error",
     "gran_scene.replicas", "must be in 1..1000000"},
    {"engine", "keep_replicas", "boolean", "false", "", "", "also write the per-replica rows (X_replicas)",
     "gran_scene.keep_replicas", ""},
    {"engine", "max_memory_gb", "float", "MemAvailable", "> 0", "GB (1e9 bytes)",
     "memory the run may use; a scene whose estimate exceeds it is refused at load", "gran_scene.max_memory",
     "must be > 0 (GB of memory the run may use)"},
    {"output", "path", "string", "<scene name>.h5", "not empty", "", "HDF5 output file", "gran_scene.output_path", ""},
    {"output", "checkpoint", "string", "<path>.ckpt", "not the output path", "",
     "checkpoint file (\"\": none); when not given it follows the output path", "gran_scene.checkpoint_path", ""},
    {"output", "checkpoint_interval", "float", "600", ">= 0", "s (wall clock)",
     "checkpoint at the first output time this long after the last one (0: off)", "gran_scene.checkpoint_interval",
     "must be >= 0 (0: no time-based checkpoints)"},
    {"output", "checkpoint_every", "integer", "0", ">= 0", "", "checkpoint every this many output times (0: off)",
     "gran_scene.checkpoint_every", "must be >= 0 (0: off)"},
    {"output", "keep_checkpoint", "boolean", "false", "", "", "keep the checkpoint after a successful run",
     "gran_scene.keep_checkpoint", ""},
};

/* [output] (the same keys for every engine): path, checkpoint and its cadence */
void parse_output_table(Tab &top, const std::string &F, gran_scene &s) {
  Tab ou = top.sub_or_empty("output");
  ou.set_known();
  s.output_path = ou.string("path", stem_of(F) + ".h5");
  require(!s.output_path.empty(), ou, "path", "must not be empty");
  s.checkpoint_explicit = ou.has("checkpoint");
  s.checkpoint_path = ou.string("checkpoint", s.output_path + ".ckpt");
  s.checkpoint_interval = ou.real("checkpoint_interval");
  s.checkpoint_every = ou.integer("checkpoint_every");
  s.keep_checkpoint = ou.flag("keep_checkpoint");
  if (!s.checkpoint_path.empty() && s.checkpoint_path == s.output_path)
    ou.fail("checkpoint", "must differ from the output path");
  ou.finish();
}

/* ---- memory of a run, estimated before anything is allocated ----------------------------------
 * The engine's model (gran_engine_entry.memory) by part: every replica's `peak`, and what the run
 * holds once. `what` and `key` name the largest part (the scene key that sets it); `detail` lists
 * them. Returns the total. */
struct MemPart {
  const char *what, *table, *key;
  double bytes;
};
double run_memory(const gran_scene &s, std::vector<MemPart> &parts) {
  const double R = (double)s.replicas;
  const gran_engine_entry *e = gran_engine_find_(s.engine_type);
  std::vector<gran_mem_part> model;
  if (e) e->memory(s, model);
  parts.clear();
  for (const gran_mem_part &p : model) parts.push_back({p.what, p.table, p.key, R * p.peak + p.once});
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
  if (total <= limit || parts.empty()) return;
  bool rep = false;
  const MemPart &big = mem_culprit(s, parts, limit, total, &rep);
  const std::string why = "the run needs about " + gb(total) + " (" + mem_detail(parts, s.replicas) + "), more than the " +
                          gb(limit) + " available; reduce it, or set [engine] max_memory_gb to allow more";
  if (rep || !top.has(big.table) || !top.get(big.table).is_table()) {
    Tab en = top.sub("engine");
    en.fail(rep ? "replicas" : big.key, why);
  }
  Tab t = top.sub(big.table);
  t.fail(big.key, why);
}

/* The engine of the scene: `[engine] type` when it names one of the table, else the first (an
 * unknown type is refused by parse_scene, after the top-level keys are checked). */
const gran_engine_entry *scene_engine(const toml::value &root) {
  size_t n = 0;
  const gran_engine_entry *all = gran_engine_entries_(&n);
  if (root.is_table() && root.as_table().count("engine")) {
    const toml::value &en = root.as_table().at("engine");
    if (en.is_table() && en.as_table().count("type")) {
      const toml::value &t = en.as_table().at("type");
      if (t.is_string())
        if (const gran_engine_entry *e = gran_engine_find_(t.as_string().str)) return e;
    }
  }
  return &all[0];
}

/* "\"dsmc\", \"srd\"": the types of the engine table */
std::string engine_types() {
  size_t n = 0;
  const gran_engine_entry *all = gran_engine_entries_(&n);
  std::string s;
  for (size_t i = 0; i < n; i++) s += (i ? ", \"" : "\"") + std::string(all[i].type) + "\"";
  return s;
}

void parse_scene(const toml::value &root, gran_scene &s) {
  const std::string &F = s.name;
  /* a split gas (granary decompose) checks each process's share itself, after the load */
  const double mem_limit = g_defer_memory_check ? HUGE_VAL : memory_limit_bytes(root);
  s.max_memory = memory_limit_explicit(root);
  const gran_engine_entry *eng = scene_engine(root);
  const gran_scene_schema schema = {kCommonKeys, sizeof kCommonKeys / sizeof kCommonKeys[0], eng->keys, eng->nkeys};
  Tab top(&root, "", F, &schema);
  if (eng->before) eng->before(top);
  top.set_known();
  s.title = top.word("title");
  /* the engine type: it decides which tables the scene may have */
  if (top.has("engine") && top.get("engine").is_table()) {
    Tab et = top.sub("engine");
    if (et.has("type")) {
      const toml::value &t = et.get("type");
      if (!t.is_string()) et.fail("type", "must be a string: one of " + engine_types() + "; got " + Tab::type_name(t));
      if (t.as_string().str != eng->type)
        et.fail("type", "unknown engine \"" + t.as_string().str + "\" (one of " + engine_types() + ")");
    }
  }
  s.engine_type = eng->type;
  eng->parse(gran_scene_doc{&top, mem_limit}, s);
  parse_output_table(top, F, s);
  check_memory(s, mem_limit, top);
  top.finish();
}

}  // namespace

void gran_scene_engine_common_(Tab &en, gran_scene &s) {
  (void)en.string("type", s.engine_type);
  if (en.has("max_memory_gb")) (void)en.real("max_memory_gb", 0.0);
  if (en.has("seed")) {
    const toml::value &x = en.get("seed");
    if (!x.is_integer()) en.fail("seed", std::string("expected an integer, got ") + Tab::type_name(x));
    if (x.as_integer() < 0) en.fail("seed", "must be >= 0");
    s.seed = (uint64_t)x.as_integer();
  }
  s.replicas = en.integer("replicas");
  s.keep_replicas = en.flag("keep_replicas");
}

std::string gran_scene_schema_problems_(const gran_scene_key *keys, size_t n) {
  std::string p;
  for (size_t i = 0; i < n; i++) {
    const gran_scene_key &k = keys[i];
    const std::string name = std::string(k.table) + (k.table[0] ? "." : "") + k.name;
    bool ok = true;
    if (!k.name[0] || !k.type[0] || !k.meaning[0] || !k.field[0]) p += name + ": name, type, meaning and C field are required; ";
    if (k.why[0] && !gran_scene_bounds_(k.bounds, 0.0, &ok)) p += name + ": a message without checkable bounds; ";
    for (size_t j = 0; j < i; j++)
      if (!std::strcmp(keys[j].table, k.table) && !std::strcmp(keys[j].name, k.name)) p += name + ": declared twice; ";
  }
  return p;
}

const gran_scene_key *gran_scene_common_keys_(size_t *n) {
  *n = sizeof kCommonKeys / sizeof kCommonKeys[0];
  return kCommonKeys;
}

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

double gran_scene_memory_limit_(const gran_scene *s) {
  return s->max_memory > 0 ? s->max_memory : memory_available_bytes();
}

double gran_memory_available_(void) { return memory_available_bytes(); }

void gran_scene_defer_memory_check_(int on) { g_defer_memory_check = on != 0; }

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

namespace {

/* ---- gran_scene_set: one key of the scene text replaced (or added), then the whole text parsed
 * again, so that the override passes the schema's checks and is part of the stored text. ------- */
bool bare_key(const std::string &k) {
  if (k.empty()) return false;
  for (char c : k)
    if (!(std::isalnum((unsigned char)c) || c == '_' || c == '-')) return false;
  return true;
}

/* the text of the scene with `key = value` in place of the key's present value (or added) */
std::string scene_text_with(const std::string &text, const std::string &name, const std::vector<std::string> &path,
                            const std::string &shown, const std::string &value) {
  const std::string &k = path.back();
  const std::string table = shown.substr(0, shown.size() - k.size() - (path.size() > 1 ? 1 : 0));
  const std::string mark = "  # set by gran_scene_set";
  std::string prepared;
  std::vector<unsigned> line_map;
  prepass(text, name, prepared, line_map);
  std::istringstream is(prepared);
  const toml::value root = toml::parse(is, name);
  /* the original text by lines */
  std::vector<size_t> start(1, 0);
  for (size_t i = 0; i < text.size(); i++)
    if (text[i] == '\n') start.push_back(i + 1);
  auto line_text = [&](unsigned l) {  /* 1-based, without its '\n' */
    const size_t a = start[l - 1], b = l < start.size() ? start[l] - 1 : text.size();
    return text.substr(a, b - a);
  };
  auto orig_line = [&](unsigned pl) { return pl >= 1 && pl <= line_map.size() ? line_map[pl - 1] : pl; };
  const toml::value *t = &root;
  bool have_table = true;
  for (size_t i = 0; i + 1 < path.size(); i++) {
    const toml::table &tab = t->as_table();
    if (!tab.count(path[i])) {
      have_table = false;
      break;
    }
    t = &tab.at(path[i]);
    if (!t->is_table())
      throw scene_error{"'" + table + "' is " + (t->is_array() ? "an array of tables or an array" : "not a table") +
                        " in " + name + "; only keys of tables can be set"};
  }
  if (have_table && t->as_table().count(k)) {
    /* replace: the lines of the key's value become one line, padded so that later lines keep their numbers */
    const toml::source_location loc = t->as_table().at(k).location();
    size_t pstart = 0; /* offset of the value's line in the prepared text */
    for (unsigned l = 1; l < loc.line(); l++) pstart = prepared.find('\n', pstart) + 1;
    const size_t vbeg = pstart + loc.column() - 1, vend = vbeg + loc.region();
    unsigned pl_end = loc.line();
    for (size_t i = vbeg; i + 1 < vend && i < prepared.size(); i++) pl_end += prepared[i] == '\n';
    const unsigned L1 = orig_line(loc.line()), L2 = orig_line(pl_end);
    const std::string prefix = prepared.substr(pstart, loc.column() - 1);
    /* the prefix must be "key =" (the key on its own line, not inside an inline table) */
    size_t eq = prefix.find_last_not_of(" \t");
    std::string lhs = eq == std::string::npos || prefix[eq] != '=' ? "" : prefix.substr(0, eq);
    while (!lhs.empty() && (lhs.back() == ' ' || lhs.back() == '\t')) lhs.pop_back();
    if (prefix.find_first_not_of(" \t") == std::string::npos && t->as_table().at(k).is_table())
      throw scene_error{"'" + shown + "' is a table; set its keys ('" + shown + ".KEY')"};
    if (lhs.size() < k.size() || lhs.compare(lhs.size() - k.size(), k.size(), k) != 0 ||
        lhs.find_first_of("{,") != std::string::npos)
      throw scene_error{fmt_line(name, L1) + ": '" + shown + "' is inside an inline table; only keys written as " +
                        "'key = value' on their own line can be set"};
    std::string was;
    for (unsigned l = L1; l <= L2; l++) was += (l > L1 ? " " : "") + line_text(l);
    const size_t a = was.find_first_not_of(" \t");
    was = a == std::string::npos ? "" : was.substr(a);
    if (was.size() > 72) was = was.substr(0, 69) + "...";
    std::string out = text.substr(0, start[L1 - 1]) + prefix + value + mark + " (was: " + was + ")";
    out.append(L2 - L1, '\n');
    const size_t after = L2 < start.size() ? start[L2] - 1 : text.size();
    return out + text.substr(after);
  }
  const std::string line = k + " = " + value + mark + "\n";
  if (path.size() == 1) return line + text; /* a top-level key: before the first table */
  if (have_table) {
    /* after the table's header [table], when it has one */
    const unsigned L = orig_line(t->location().line());
    const std::string h = line_text(L);
    const size_t a = h.find_first_not_of(" \t"), z = h.find(']');
    std::string named; /* the header's table name without blanks: [ a . b ] -> a.b */
    if (a != std::string::npos && z != std::string::npos && z > a)
      for (size_t i = a + 1; i < z; i++)
        if (h[i] != ' ' && h[i] != '\t') named += h[i];
    if (a != std::string::npos && h[a] == '[' && h.compare(a, 2, "[[") != 0 && named == table) {
      const size_t at = L < start.size() ? start[L] : text.size();
      return text.substr(0, at) + (at == text.size() && !text.empty() && text.back() != '\n' ? "\n" : "") + line +
             text.substr(at);
    }
  }
  /* a new table at the end */
  return text + (!text.empty() && text.back() != '\n' ? "\n" : "") + "\n[" + table + "]\n" + line;
}

}  // namespace

/** @brief Override one key of a loaded scene (`key = value` in the scene text, then the whole
 *  scene validated again; on failure the scene is unchanged).
 *  @param[in] key "table.key" (a top-level key alone)  @param[in] value TOML value text */
GRAN_EXTERN int gran_scene_set(gran_scene *scene, const char *key, const char *value) {
  GRAN_CHECK_PTR(scene);
  GRAN_CHECK_PTR(key);
  GRAN_CHECK_PTR(value);
  GRAN_TRY {
    const std::string K = key, V = value;
    std::vector<std::string> path;
    for (size_t at = 0;;) {
      const size_t dot = K.find('.', at);
      path.push_back(K.substr(at, dot == std::string::npos ? std::string::npos : dot - at));
      if (dot == std::string::npos) break;
      at = dot + 1;
    }
    for (const std::string &c : path)
      GRAN_CHECK(bare_key(c), GRAN_ERR_ARG,
                 "key '%s': expected table.key (TOML bare keys: letters, digits, '_' and '-', joined by '.')", key);
    GRAN_CHECK(V.find_first_of("\r\n") == std::string::npos, GRAN_ERR_ARG,
               "key '%s': the value must be one line of TOML", key);
    /* the value alone must be one TOML value */
    try {
      std::string prepared;
      std::vector<unsigned> lm;
      prepass("v = " + V + "\n", "value", prepared, lm);
      std::istringstream is(prepared);
      const toml::value one = toml::parse(is, "value");
      GRAN_CHECK(one.is_table() && one.as_table().size() == 1 && one.as_table().count("v"), GRAN_ERR_PARSE,
                 "key '%s': the value '%s' is not one TOML value", key, value);
    } catch (const scene_error &e) {
      return GRAN_ERROR(GRAN_ERR_PARSE, "key '%s': %s", key, e.msg.c_str());
    } catch (const toml::exception &) {
      return GRAN_ERROR(GRAN_ERR_PARSE,
                        "key '%s': the value '%s' is not a TOML value (strings are quoted: \"x.h5\"; arrays: [1, 2])",
                        key, value);
    }
    std::string text;
    try {
      text = scene_text_with(scene->text, scene->name, path, K, V);
    } catch (const scene_error &e) {
      return GRAN_ERROR(GRAN_ERR_ARG, "key '%s': %s", key, e.msg.c_str());
    } catch (const toml::exception &e) {
      std::string first = e.what();
      const size_t nl = first.find('\n');
      if (nl != std::string::npos) first = first.substr(0, nl);
      return GRAN_ERROR(GRAN_ERR_PARSE, "key '%s': the scene text does not parse: %s", key, first.c_str());
    }
    gran_scene *fresh = nullptr;
    const int st = gran_scene_parse_text_(text, scene->name, &fresh);
    if (st != GRAN_SUCCESS) {
      const std::string msg = gran_last_error_message();
      return GRAN_ERROR(st, "key '%s' = %s: %s", key, value, msg.c_str());
    }
    /* replicas given through gran_scene_set_replicas stay, unless this sets them */
    if (K != "engine.replicas") fresh->replicas = scene->replicas;
    if (K != "engine.keep_replicas") fresh->keep_replicas = scene->keep_replicas;
    if (fresh->replicas > 1) {
      const int mst = gran_scene_check_memory_(fresh, "the scene's replicas");
      if (mst != GRAN_SUCCESS) {
        const std::string msg = gran_last_error_message();
        delete fresh;
        return GRAN_ERROR(mst, "key '%s' = %s: %s", key, value, msg.c_str());
      }
    }
    *scene = std::move(*fresh);
    delete fresh;
    return GRAN_SUCCESS;
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

