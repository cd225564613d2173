/* sundials_compat.h -- the SUNDIALS headers the core uses, and one spelling for what SUNDIALS 6
 * (Debian 12's 6.4.1, the default build) and 7 name differently (kept here only: the rest of
 * csrc/ uses the names below and the 6.x/7.x names both versions share, e.g. sunrealtype).
 * Built and tested against both: docs/building.md. */
#ifndef PHM_SUNDIALS_COMPAT_H
#define PHM_SUNDIALS_COMPAT_H

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* SUNContext (every object's first argument) came with 6.0. */
#if !defined(SUNDIALS_VERSION_MAJOR) || SUNDIALS_VERSION_MAJOR < 6
#error "phmech builds against SUNDIALS 6.x (6.4 tested) or 7.x"
#endif

/* Where IDA's error messages go: fn(ud, function, message), called inside the failing IDA call;
 * the caller copies the message into its own phm_error text (csrc/integrate/ida.c). */
typedef struct {
  void (*fn)(void *ud, const char *function, const char *msg);
  void *ud;
} phm_sun_errsink;

#if SUNDIALS_VERSION_MAJOR >= 7

/* 7 returns SUN_SUCCESS from SUNLinSolInitialize/Setup/Solve; 6's SUNLS_SUCCESS is gone. */
#define PHM_SUN_SUCCESS SUN_SUCCESS

static inline void phm_sun_errsink_call(int line, const char *func, const char *file,
                                        const char *msg, SUNErrCode code, void *ud,
                                        SUNContext ctx) {
  (void)line;
  (void)file;
  (void)code;
  (void)ctx;
  const phm_sun_errsink *s = (const phm_sun_errsink *)ud;
  s->fn(s->ud, func, msg ? msg : "");
}

/* A context that prints nothing. 7's context starts with the error handler SUNLogErrHandlerFn
 * (errors to stderr) and, when SUNDIALS was built with logging (SUNDIALS_LOGGING_LEVEL >= 1; the
 * upstream default is 2), a logger that writes warnings to stdout: both are removed. Without a
 * logger (a documented state: what a build without logging has) SUNLogger_QueueMsg returns an
 * error code that SUNDIALS ignores. IDA's warnings are then dropped; with 6 they reached the
 * handler of phm_ida_set_errsink, which kept only the last message anyway. */
static inline int phm_sun_context_create(SUNContext *ctx) {
  *ctx = NULL;
  if (SUNContext_Create(SUN_COMM_NULL, ctx) != SUN_SUCCESS) return -1;
  if (SUNContext_ClearErrHandlers(*ctx) != SUN_SUCCESS ||
      SUNContext_SetLogger(*ctx, NULL) != SUN_SUCCESS) {
    SUNContext_Free(ctx);
    return -1;
  }
  return 0;
}

/* Errors of IDA (and of any object on its context) go to sink, which must outlive mem. */
static inline int phm_ida_set_errsink(void *mem, SUNContext ctx, phm_sun_errsink *sink) {
  (void)mem;
  return SUNContext_PushErrHandler(ctx, phm_sun_errsink_call, sink) == SUN_SUCCESS ? 0 : -1;
}

#else /* SUNDIALS 6 */

#define PHM_SUN_SUCCESS SUNLS_SUCCESS

static inline void phm_sun_errsink_call(int code, const char *module, const char *function,
                                        char *msg, void *ud) {
  (void)code;
  (void)module;
  const phm_sun_errsink *s = (const phm_sun_errsink *)ud;
  s->fn(s->ud, function, msg ? msg : "");
}

/* 6's context takes a void* communicator (NULL: none) and prints nothing by itself (Debian's
 * 6.4.1 is built without logging; errors and warnings go to the IDA error handler). */
static inline int phm_sun_context_create(SUNContext *ctx) {
  *ctx = NULL;
  return SUNContext_Create(NULL, ctx) == 0 ? 0 : -1;
}

/* Errors and warnings of IDA go to sink, which must outlive mem. */
static inline int phm_ida_set_errsink(void *mem, SUNContext ctx, phm_sun_errsink *sink) {
  (void)ctx;
  return IDASetErrHandlerFn(mem, phm_sun_errsink_call, sink) == IDA_SUCCESS ? 0 : -1;
}

#endif

#endif
