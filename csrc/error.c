/* Error records: a status code and a message, never printed by the library. */
#include "phmech.h"

#include <stdarg.h>
#include <stdio.h>

phm_status phm_error_set(phm_error *err, phm_status code, const char *fmt, ...) {
  if (err) {
    err->code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
  }
  return code;
}

void phm_error_clear(phm_error *err) {
  if (err) {
    err->code = PHM_OK;
    err->msg[0] = '\0';
  }
}
