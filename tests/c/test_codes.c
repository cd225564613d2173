/* test_codes.c -- csrc/util/codes.c: every row of every code table names its enum constant (the
 * lower-case name of the enum value), the values of a table are distinct, a table is found by
 * its name, and the result fields follow phm_sim_output's arrays. */
#include "check.h"

#include <ctype.h>
#include <string.h>

static int value_of(const char *table, const char *name) {
  const phm_code_table *t = phm_code_table_named(table);
  for (int i = 0; t && i < t->nrows; i++)
    if (strcmp(t->rows[i].name, name) == 0) return t->rows[i].value;
  return -1;
}

static void rows_match_the_enums(void) {
  CHECK(value_of("law_kinds", "constant") == PHM_LAW_CONSTANT && value_of("law_kinds", "step") == PHM_LAW_STEP &&
            value_of("law_kinds", "pulse") == PHM_LAW_PULSE && value_of("law_kinds", "sine") == PHM_LAW_SINE &&
            value_of("law_kinds", "table") == PHM_LAW_TABLE && value_of("law_kinds", "cycloidal") == PHM_LAW_CYCLOIDAL &&
            value_of("law_kinds", "linear") == PHM_LAW_LINEAR && value_of("law_kinds", "ppoly") == PHM_LAW_PPOLY &&
            value_of("law_kinds", "callback") == PHM_LAW_CALLBACK && value_of("law_kinds", "expr") == PHM_LAW_EXPR &&
            value_of("law_kinds", "sum") == PHM_LAW_SUM && value_of("law_kinds", "product") == PHM_LAW_PRODUCT,
        "law kinds match phm_law_kind");
  CHECK(phm_code_table_named("law_kinds")->nrows == PHM_LAW_PRODUCT + 1, "every law kind has a row");
  CHECK(value_of("actuator_kinds", "effort") == PHM_ACT_EFFORT && value_of("actuator_kinds", "pd") == PHM_ACT_PD &&
            value_of("actuator_kinds", "spring") == PHM_ACT_SPRING,
        "actuator kinds match phm_actuator_kind");
  CHECK(value_of("mass_kinds", "lumped") == PHM_MASS_LUMPED && value_of("mass_kinds", "consistent") == PHM_MASS_CONSISTENT &&
            value_of("mass_kinds", "given") == PHM_MASS_GIVEN,
        "mass kinds match phm_element_mass_kind");
  const phm_code_table *r = phm_code_table_named("result_fields");
  CHECK(r && r->nrows == PHM_NRESULT_FIELDS, "one result field per phm_sim_output array");
  for (int i = 0; r && i < r->nrows; i++)
    CHECK(r->rows[i].value == i, "result field %s at its position %d", r->rows[i].name, i);
  CHECK(value_of("result_fields", "poses") == PHM_RESULT_POSES &&
            value_of("result_fields", "port_energy") == PHM_RESULT_PORT_ENERGY,
        "result fields named");
  /* the rows of the table of result quantities (csrc/include/phmech_results.h): named as the
   * code table, each with a shape whose dimensions are named */
  for (int i = 0; r && i < r->nrows; i++) {
    const phm_result_field *f = phm_result_field_at(i);
    long dims[3];
    const char *names[3] = {NULL, NULL, NULL};
    int nd = phm_result_shape(NULL, -1, i, dims, names);
    CHECK(f && strcmp(f->name, r->rows[i].name) == 0 && f->unit[0] && f->noun[0] && f->text[0],
          "result field %d described (%s)", i, r->rows[i].name);
    CHECK(nd >= 1 && nd <= 3 && names[0] && (nd < 2 || names[1]) && (nd < 3 || names[2]),
          "result field %s: %d named dimensions", r->rows[i].name, nd);
  }
  CHECK(phm_result_field_at(-1) == NULL && phm_result_field_at(PHM_NRESULT_FIELDS) == NULL,
        "result fields out of range are NULL");
}

static void tables_are_well_formed(void) {
  CHECK(phm_code_table_count() == 5, "five code tables (%d; the integrators: test_integrators.c)", phm_code_table_count());
  CHECK(phm_code_table_at(-1) == NULL && phm_code_table_at(phm_code_table_count()) == NULL &&
            phm_code_table_named("nope") == NULL && phm_code_table_named(NULL) == NULL,
        "unknown tables are NULL");
  for (int k = 0; k < phm_code_table_count(); k++) {
    const phm_code_table *t = phm_code_table_at(k);
    CHECK(phm_code_table_named(t->name) == t, "table %s found by name", t->name);
    for (int i = 0; i < t->nrows; i++) {
      int lower = 1;
      for (const char *c = t->rows[i].name; *c; c++) lower &= !isupper((unsigned char)*c);
      CHECK(lower && t->rows[i].name[0], "%s: name %s lower case", t->name, t->rows[i].name);
      for (int j = 0; j < i; j++)
        CHECK(t->rows[j].value != t->rows[i].value && strcmp(t->rows[j].name, t->rows[i].name) != 0,
              "%s: rows %d and %d distinct", t->name, j, i);
    }
  }
}

CHECK_MAIN(CHECK_CASE(rows_match_the_enums), CHECK_CASE(tables_are_well_formed))
