/* errors.cpp - error codes, thread-local messages and warnings, version and build information. */
#include "granary_impl.h"

#include <cstdarg>
#include <cstdio>

#ifndef GRAN_BUILD_CONFIG
#define GRAN_BUILD_CONFIG "unknown"
#endif

namespace {
thread_local char g_message[1024] = "";
thread_local char g_location[512] = "";
thread_local char g_warning[1024] = "";
thread_local int64_t g_nwarning = 0;

int copy_out(const char *src, char *buf, int64_t len) {
  if (!buf || len <= 0) return GRAN_ERROR(GRAN_ERR_ARG, "argument 'buf' is NULL or 'len' <= 0");
  std::snprintf(buf, (size_t)len, "%s", src);
  return GRAN_SUCCESS;
}
}  // namespace

int gran_error_set(int code, const char *file, int line, const char *func, const char *fmt, ...) {
  char msg[768];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  /* the message says what was wrong in the user's terms; where it was found (the library's own
   * function and source line) is kept apart, for --verbose and bug reports */
  const char *base = std::strrchr(file, '/');
  std::snprintf(g_message, sizeof g_message, "%s", msg);
  std::snprintf(g_location, sizeof g_location, "%s (%s:%d), %s", func, base ? base + 1 : file, line,
                gran_strerror(code));
  return code;
}

void gran_warning_add(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(g_warning, sizeof g_warning, fmt, ap);
  va_end(ap);
  g_nwarning++;
}

#define GRAN_ERROR_CASE_(name, value, msg) \
  case value:                              \
    return #name ": " msg;

/** @brief Static description of an error code; never NULL. */
GRAN_EXTERN const char *gran_strerror(int code) {
  switch (code) {
    GRAN_ERROR_LIST(GRAN_ERROR_CASE_)
    default:
      return "GRAN_ERR_UNKNOWN: unknown error code";
  }
}
#undef GRAN_ERROR_CASE_

GRAN_EXTERN const char *gran_last_error_message(void) { return g_message; }
GRAN_EXTERN int gran_last_error_copy(char *buf, int64_t len) { return copy_out(g_message, buf, len); }
GRAN_EXTERN int gran_last_error_location_copy(char *buf, int64_t len) { return copy_out(g_location, buf, len); }
/** @brief Record a failure found outside the library (a binding's argument check): the thread's
 *  last error message becomes `message`; returns `code`. */
GRAN_EXTERN int gran_set_error_message(int code, const char *message) {
  if (code >= 0 || code <= GRAN_ERROR_LIST_END_)
    return GRAN_ERROR(GRAN_ERR_ARG, "argument 'code' must be a negative GRAN_ERR_* code, got %d", code);
  if (!message) return GRAN_ERROR(GRAN_ERR_ARG, "argument 'message' is NULL");
  std::snprintf(g_message, sizeof g_message, "%s", message);
  std::snprintf(g_location, sizeof g_location, "the caller of gran_set_error_message, %s", gran_strerror(code));
  return code;
}
GRAN_EXTERN int gran_clear_error(void) {
  g_message[0] = '\0';
  g_location[0] = '\0';
  return GRAN_SUCCESS;
}
GRAN_EXTERN int gran_warning_count(int64_t *count) {
  GRAN_CHECK_PTR(count);
  *count = g_nwarning;
  return GRAN_SUCCESS;
}
GRAN_EXTERN int gran_last_warning_copy(char *buf, int64_t len) { return copy_out(g_warning, buf, len); }

GRAN_EXTERN int gran_get_version(int *major, int *minor, int *patch) {
  GRAN_CHECK_PTR(major);
  GRAN_CHECK_PTR(minor);
  GRAN_CHECK_PTR(patch);
  *major = GRAN_VERSION_MAJOR;
  *minor = GRAN_VERSION_MINOR;
  *patch = GRAN_VERSION_PATCH;
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_get_build_config(const char **config) {
  GRAN_CHECK_PTR(config);
  *config = GRAN_BUILD_CONFIG;
  return GRAN_SUCCESS;
}
