/* codes.c -- THE name tables of the core's enums (csrc/include/phmech_types.h): time-law kinds,
 * actuator kinds, element mass kinds, and the names of the arrays a simulation returns
 * (phm_sim_output). One row per enum value, its name the enum's, lower case. The pair types and
 * the integrators have their own tables (csrc/model/pair_types.c, csrc/integrate/integrators.c). phmech._core.codes() (csrc/pyext/py_pairs.c)
 * hands these to Python, so that no code is retyped by hand across the boundary;
 * tests/c/test_codes.c checks each row against its enum constant. */
#include "phmech.h"

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
/* The arrays of a simulation's result, in phm_sim_output's order; the value is the position
 * (csrc/pyext/py_simulate.c allocates and names them from this table). */
static const phm_code result_fields[] = {
    {"poses", PHM_RESULT_POSES},     {"twists", PHM_RESULT_TWISTS},   {"lambda", PHM_RESULT_LAMBDA},
    {"energy", PHM_RESULT_ENERGY},   {"joints", PHM_RESULT_JOINTS},   {"joint_rates", PHM_RESULT_JOINT_RATES},
    {"efforts", PHM_RESULT_EFFORTS}, {"pair_wrenches", PHM_RESULT_PAIR_WRENCHES},
    {"ports", PHM_RESULT_PORTS},     {"components", PHM_RESULT_COMPONENTS},
    {"constraint_residual", PHM_RESULT_CONSTRAINT_RESIDUAL},
};

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
