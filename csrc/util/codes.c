/* codes.c -- THE name tables of the core's enums (csrc/include/phmech_types.h): time-law kinds,
 * actuator kinds, element mass kinds, and the names of the arrays a simulation returns
 * (phm_sim_output, from csrc/include/phmech_results.h). One row per enum value, its name the enum's, lower case. The pair types and
 * the integrators have their own tables (csrc/model/pair_types.c, csrc/integrate/integrators.c). phmech._core.codes() (csrc/pyext/py_pairs.c)
 * hands these to Python, so that no code is retyped by hand across the boundary;
 * tests/c/test_codes.c checks each row against its enum constant. */
#include "phmech.h"

#include <stddef.h>
#include <string.h>

static const phm_code law_kinds[] = {
    {"constant", PHM_LAW_CONSTANT}, {"step", PHM_LAW_STEP},         {"pulse", PHM_LAW_PULSE},
    {"sine", PHM_LAW_SINE},         {"table", PHM_LAW_TABLE},       {"cycloidal", PHM_LAW_CYCLOIDAL},
    {"linear", PHM_LAW_LINEAR},     {"ppoly", PHM_LAW_PPOLY},       {"callback", PHM_LAW_CALLBACK},
    {"expr", PHM_LAW_EXPR},         {"sum", PHM_LAW_SUM},           {"product", PHM_LAW_PRODUCT},
};
static const phm_code actuator_kinds[] = {{"effort", PHM_ACT_EFFORT}, {"pd", PHM_ACT_PD}, {"spring", PHM_ACT_SPRING}};
static const phm_code component_kinds[] = {
    {"viscous", PHM_COMP_VISCOUS}, {"coulomb", PHM_COMP_COULOMB}, {"stribeck", PHM_COMP_STRIBECK},
    {"lugre", PHM_COMP_LUGRE},     {"motor", PHM_COMP_MOTOR},       {"linear", PHM_COMP_LINEAR},
    {"callback", PHM_COMP_CALLBACK}, {"ph", PHM_COMP_PH}};
static const phm_code mass_kinds[] = {
    {"lumped", PHM_MASS_LUMPED}, {"consistent", PHM_MASS_CONSISTENT}, {"given", PHM_MASS_GIVEN}};
/* The arrays of a simulation's result, from the table of result quantities
 * (csrc/include/phmech_results.h); the value is the position (csrc/pyext/py_simulate.c allocates
 * and names them from this table). */
#define RESULT_CODE(NAME, name, over, item, unit, noun, text) {#name, PHM_RESULT_##NAME},
static const phm_code result_fields[] = {PHM_RESULT_FIELDS(RESULT_CODE)};
#define RESULT_ROW(NAME, name, over, item, unit, noun, text) {#name, unit, noun, text, over, item},
static const phm_result_field result_rows[] = {PHM_RESULT_FIELDS(RESULT_ROW)};
/* each named array of phm_sim_output is its field[] at the table's position */
#define SAME_POINTER(NAME, name, over, item, unit, noun, text)                                       \
  _Static_assert(offsetof(phm_sim_output, name) ==                                                  \
                     offsetof(phm_sim_output, field) + PHM_RESULT_##NAME * sizeof(double *),        \
                 "phm_sim_output." #name " is field[PHM_RESULT_" #NAME "]");
PHM_RESULT_FIELDS(SAME_POINTER)

const phm_result_field *phm_result_field_at(int f) {
  return f >= 0 && f < PHM_NRESULT_FIELDS ? &result_rows[f] : NULL;
}


#define ROWS(a) (int)(sizeof(a) / sizeof(a[0]))
static const phm_code_table tables[] = {
    {"law_kinds", law_kinds, ROWS(law_kinds)},
    {"actuator_kinds", actuator_kinds, ROWS(actuator_kinds)},
    {"mass_kinds", mass_kinds, ROWS(mass_kinds)},
    {"component_kinds", component_kinds, ROWS(component_kinds)},
    {"result_fields", result_fields, ROWS(result_fields)},
};

int phm_code_table_count(void) { return ROWS(tables); }

const phm_code_table *phm_code_table_at(int i) { return i >= 0 && i < ROWS(tables) ? &tables[i] : NULL; }

const phm_code_table *phm_code_table_named(const char *name) {
  for (int i = 0; name && i < ROWS(tables); i++)
    if (strcmp(tables[i].name, name) == 0) return &tables[i];
  return NULL;
}
