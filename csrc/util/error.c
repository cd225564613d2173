/* error.c -- error records: a status code, a message and where it was raised; never printed by
 * the library (csrc/util/phm_check.h has the macros that fill them). */
#include "phm_check.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static void error_vset(phm_error *err, phm_status code, const char *file, int line,
                       const char *fmt, va_list ap) {
  err->code = code;
  vsnprintf(err->msg, sizeof err->msg, fmt, ap);
  /* the build passes paths relative to its build folder ("../csrc/..."): keep them from csrc/ */
  const char *at = file ? strstr(file, "csrc/") : NULL;
  err->file = at ? at : file;
  err->line = line;
}

phm_status phm_error_set(phm_error *err, phm_status code, const char *fmt, ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    error_vset(err, code, NULL, 0, fmt, ap);
    va_end(ap);
  }
  return code;
}

phm_status phm_error_set_at(phm_error *err, phm_status code, const char *file, int line,
                            const char *fmt, ...) {
  if (err) {
    va_list ap;
    va_start(ap, fmt);
    error_vset(err, code, file, line, fmt, ap);
    va_end(ap);
  }
  return code;
}

void phm_error_clear(phm_error *err) {
  if (err) {
    err->code = PHM_OK;
    err->msg[0] = '\0';
    err->file = NULL;
    err->line = 0;
  }
}
