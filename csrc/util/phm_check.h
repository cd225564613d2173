/* phm_check.h -- error handling inside the library: every failure records its status, a message and
 * the file:line that raised it (phm_error.file/.line), then returns the status up the stack. */
#ifndef PHM_PHM_CHECK_H
#define PHM_PHM_CHECK_H

#include "phmech.h"

/* phm_error_set with the caller's file:line (csrc/util/error.c). */
phm_status phm_error_set_at(phm_error *err, phm_status code, const char *file, int line,
                            const char *fmt, ...);

/* Record a failure here: `return PHM_FAIL(err, PHM_EINVAL, "pair %d: ...", ip);` */
#define PHM_FAIL(err, code, ...) phm_error_set_at((err), (code), __FILE__, __LINE__, __VA_ARGS__)
/* Fail with code and message unless cond holds. */
#define PHM_CHECK(cond, err, code, ...)                                                          \
  do {                                                                                           \
    if (!(cond)) return PHM_FAIL((err), (code), __VA_ARGS__);                                    \
  } while (0)
/* Return the status of a call that failed (its message is already recorded). */
#define PHM_CALL(call)                                                                           \
  do {                                                                                           \
    phm_status call_status_ = (call);                                                            \
    if (call_status_ != PHM_OK) return call_status_;                                             \
  } while (0)

#endif
