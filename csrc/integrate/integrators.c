/* integrators.c -- THE table of integrators: one row per integrator (its name, the defaults of
 * its options, its checks, set-up and run; integrate.h), indexed by its code PHM_INTEGRATOR_*.
 * phm_simulate (simulate.c) dispatches through it and phmech._core.codes()["integrators"]
 * (csrc/pyext/py_codes.c) reads its names from it; tests/c/test_integrators.c checks it. */
#include "integrate.h"

#include "phm_check.h"

static const phm_integrator integrators[] = {
    [PHM_INTEGRATOR_IDA] = {"ida", {.ida = {.max_order = 0, .error_test = PHM_ERRTEST_ALL}}, 0,
                            ida_check, ida_setup, ida_release, run_ida},
    [PHM_INTEGRATOR_GALPHA] = {"generalized-alpha",
                               {.galpha = {.step = 0.0, .rho_inf = 1.0, .adaptive = 0, .band = 0.0}},
                               1, galpha_check, galpha_setup, galpha_release, run_galpha},
    [PHM_INTEGRATOR_TREE] = {"tree", {.rtol = 0.0}, 0, tree_check, tree_setup, tree_release, run_tree},
};
#define NINTEGRATORS (int)(sizeof(integrators) / sizeof(integrators[0]))

const phm_integrator *phm_integrator_get(int integrator) {
  return integrator >= 0 && integrator < NINTEGRATORS && integrators[integrator].run
             ? &integrators[integrator]
             : NULL;
}

int phm_integrator_count(void) { return NINTEGRATORS; }

const char *phm_integrator_name(int integrator) {
  const phm_integrator *ig = phm_integrator_get(integrator);
  return ig ? ig->name : NULL;
}

phm_status phm_sim_defaults(int integrator, phm_sim_options *opt, phm_error *err) {
  phm_error_clear(err);
  const phm_integrator *ig = phm_integrator_get(integrator);
  if (!opt) return PHM_FAIL(err, PHM_EINVAL, "phm_sim_defaults: NULL argument");
  if (!ig) return PHM_FAIL(err, PHM_EINVAL, "unknown integrator %d", integrator);
  *opt = ig->defaults;
  opt->integrator = integrator;
  return PHM_OK;
}
