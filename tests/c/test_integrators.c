/* test_integrators.c -- csrc/integrate/integrators.c: the table of integrators is found by code,
 * its rows carry their names and option defaults (which pass their own checks where the options
 * are complete), an unknown code finds nothing, and phm_sim_defaults fills an integrator's
 * sub-struct by field name (phm_simulate's refusal of an unknown code: tests/c/test_simulate.c). */
#include "check.h"
#include "integrate.h"

static void rows_are_found_by_code(void) {
  CHECK(phm_integrator_count() == 3, "three integrators (%d)", phm_integrator_count());
  const phm_integrator *tr = phm_integrator_get(PHM_INTEGRATOR_TREE);
  CHECK(tr && strcmp(tr->name, "tree") == 0 && tr->run == run_tree && !tr->per_step,
        "PHM_INTEGRATOR_TREE is \"tree\"");
  const phm_integrator *ida = phm_integrator_get(PHM_INTEGRATOR_IDA);
  const phm_integrator *ga = phm_integrator_get(PHM_INTEGRATOR_GALPHA);
  CHECK(ida && strcmp(ida->name, "ida") == 0, "PHM_INTEGRATOR_IDA is \"ida\"");
  CHECK(ga && strcmp(ga->name, "generalized-alpha") == 0, "PHM_INTEGRATOR_GALPHA is \"generalized-alpha\"");
  CHECK(ida && ida->run == run_ida && ga && ga->run == run_galpha, "each row runs its integrator");
  CHECK(ida && !ida->per_step && ga && ga->per_step, "lambda_ref: IDA at the outputs, generalized-alpha per step");
  CHECK(phm_integrator_get(-1) == NULL && phm_integrator_get(phm_integrator_count()) == NULL,
        "an unknown code finds nothing");
  CHECK(phm_integrator_name(PHM_INTEGRATOR_GALPHA) && !strcmp(phm_integrator_name(PHM_INTEGRATOR_GALPHA), "generalized-alpha") &&
            phm_integrator_name(7) == NULL,
        "names by code");
  for (int i = 0; i < phm_integrator_count(); i++) {
    const phm_integrator *ig = phm_integrator_get(i);
    CHECK(ig && ig->name && ig->check && ig->setup && ig->release && ig->run, "row %d complete", i);
  }
}

static void defaults_fill_the_sub_struct(void) {
  phm_error err;
  phm_sim_options o;
  CHECK(phm_sim_defaults(PHM_INTEGRATOR_GALPHA, &o, &err) == PHM_OK, "generalized-alpha's defaults");
  CHECK(o.integrator == PHM_INTEGRATOR_GALPHA && o.galpha.rho_inf == 1.0 && o.galpha.step == 0.0 &&
            o.galpha.adaptive == 0 && o.galpha.band == 0.0 && o.rtol == 0.0,
        "its sub-struct at its defaults, the rest 0");
  o.galpha.adaptive = 1; /* adaptive: a step of 0 is chosen from the band */
  CHECK(phm_integrator_get(PHM_INTEGRATOR_GALPHA)->check(&o, &err) == PHM_OK, "adaptive defaults pass its check");
  o.galpha.rho_inf = 2.0;
  CHECK(phm_integrator_get(PHM_INTEGRATOR_GALPHA)->check(&o, &err) == PHM_EINVAL, "rho_inf 2 fails its check");
  CHECK(phm_sim_defaults(PHM_INTEGRATOR_IDA, &o, &err) == PHM_OK && o.integrator == PHM_INTEGRATOR_IDA &&
            o.ida.error_test == PHM_ERRTEST_ALL && o.ida.max_order == 0,
        "IDA's defaults");
  CHECK(phm_integrator_get(PHM_INTEGRATOR_IDA)->check(&o, &err) == PHM_OK, "IDA's defaults pass its check");
  CHECK(phm_sim_defaults(9, &o, &err) == PHM_EINVAL && strstr(err.msg, "unknown integrator 9"),
        "an unknown integrator has no defaults");
}

CHECK_MAIN(CHECK_CASE(rows_are_found_by_code), CHECK_CASE(defaults_fill_the_sub_struct))
