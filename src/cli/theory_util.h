/* theory_util.h - what the parts of `granary theory` share (src/cli/theory.cpp: the cooling
 * mixture; src/cli/theory_engines.cpp: aggregation scenes, GSRD scenes, scenes without a theory):
 * the parsed request and the JSON writers (numbers %.17g, inf and nan as null). */
#ifndef GRANARY_CLI_THEORY_UTIL_H
#define GRANARY_CLI_THEORY_UTIL_H

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cli.h"
#include "io/io_impl.h"

struct cli_theory_request {
  const char *scene_path = nullptr;
  std::vector<double> times, lags; /* times from the scene's start (t_start) */
  bool times_scene = false;        /* --times scene: the scene's output times minus t_start */
  bool json = false;
  int approx = GRAN_THEORY_MAXWELLIAN;
  bool approx_given = false; /* --approximation on the command line */
};

/* theory_engines.cpp: the theory of an aggregating DSMC scene, of a GSRD scene, and the answer for
 * an engine without one; each returns the exit status (0, 1 failure on stderr, 2 usage). */
int cli_theory_aggregation(const gran_scene *scene, const cli_theory_request &r);
int cli_theory_srd(const gran_scene *scene, const cli_theory_request &r);
int cli_theory_none(const gran_scene *scene, const cli_theory_request &r, const std::string &why);

namespace cli_json {

inline void num(std::string &o, double x) {
  if (!std::isfinite(x)) {
    o += "null";
    return;
  }
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  o += b;
}

inline void str(std::string &o, const std::string &s) {
  o += '"';
  for (unsigned char c : s) {
    if (c == '"') o += "\\\"";
    else if (c == '\\') o += "\\\\";
    else if (c == '\n') o += "\\n";
    else if (c == '\t') o += "\\t";
    else if (c == '\r') o += "\\r";
    else if (c < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      o += b;
    } else o += (char)c;
  }
  o += '"';
}

inline void arr(std::string &o, const double *x, int64_t n) {
  o += '[';
  for (int64_t i = 0; i < n; i++) {
    if (i) o += ", ";
    num(o, x[i]);
  }
  o += ']';
}

/* rows x cols row-major as an array of arrays */
inline void mat(std::string &o, const double *x, int64_t rows, int64_t cols) {
  o += '[';
  for (int64_t i = 0; i < rows; i++) {
    if (i) o += ", ";
    arr(o, x + i * cols, cols);
  }
  o += ']';
}

/* , "key": */
inline void key(std::string &o, const char *k) {
  o += ", \"";
  o += k;
  o += "\": ";
}

/* , "key": x */
inline void field(std::string &o, const char *k, double x) {
  key(o, k);
  num(o, x);
}

}  // namespace cli_json

#endif
