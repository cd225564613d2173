/* test_error.c -- csrc/util/error.c: an error record's code, message and origin, set directly
 * (phm_error_set) or by a refusal inside the library (PHM_FAIL records csrc/ file:line), and
 * cleared. */
#include "check.h"

static void error_records_code_message_and_origin(void) {
  phm_error err;
  phm_status st = phm_error_set(&err, PHM_ESINGULAR, "matrix %d of %s", 3, "five");
  CHECK(st == PHM_ESINGULAR && err.code == PHM_ESINGULAR && strcmp(err.msg, "matrix 3 of five") == 0,
        "phm_error_set returns the code and formats the message (\"%s\")", err.msg);
  CHECK(err.file == NULL && err.line == 0, "phm_error_set names no file");
  CHECK(phm_error_set(NULL, PHM_EINVAL, "ignored") == PHM_EINVAL, "phm_error_set without a record returns the code");
  char longer[700];
  memset(longer, 'x', sizeof longer - 1);
  longer[sizeof longer - 1] = '\0';
  phm_error_set(&err, PHM_EINVAL, "%s", longer);
  CHECK(strlen(err.msg) == sizeof err.msg - 1, "a long message is cut to the record (%zu chars)", strlen(err.msg));
  phm_error_clear(&err);
  CHECK(err.code == PHM_OK && err.msg[0] == '\0' && err.file == NULL && err.line == 0, "phm_error_clear empties the record");
  phm_error_clear(NULL);
  /* a refusal inside the library: the record names where, from csrc/ on */
  phm_model *m = NULL;
  st = phm_model_create(NULL, &m, &err);
  CHECK(st == PHM_EINVAL && m == NULL && strstr(err.msg, "NULL argument") != NULL,
        "phm_model_create(NULL) refused (%d: %s)", st, err.msg);
  CHECK(err.file && strcmp(err.file, "csrc/model/model.c") == 0 && err.line > 0,
        "the refusal names csrc/model/model.c:line (got %s:%d)", err.file ? err.file : "(null)", err.line);
}

CHECK_MAIN(CHECK_CASE(error_records_code_message_and_origin))
