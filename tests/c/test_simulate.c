/* test_simulate.c -- csrc/solve/simulate.c (with the integrators of csrc/solve/ida.c and
 * galpha.c): whole runs checked against conservation laws -- a free rigid body's energy. */
#include "check.h"

/* IDA at tolerances rtol, atol (the rest of the options at their defaults). */
static phm_sim_options ida_options(double rtol, double atol) {
  return (phm_sim_options){.rtol = rtol, .atol = atol, .error_test = PHM_ERRTEST_ALL,
                           .integrator = PHM_INTEGRATOR_IDA};
}

/* Run m from its initial state with IDA (rtol, atol), outputs at 0, dt, ..., (nout - 1) dt, the
 * energy ledger (nout x PHM_NENERGY) into energy; checks "<what> simulation runs" and "<what>:
 * all outputs". Returns the number of outputs done. */
static int run_energy(const phm_model *m, double dt, int nout, double rtol, double atol,
                      double *energy, const char *what) {
  char name[96];
  double *tout = malloc(sizeof(double) * (size_t)nout);
  if (!tout) {
    check_fail("out of memory");
    return 0;
  }
  phm_sim_options opt = ida_options(rtol, atol);
  phm_sim_output out;
  phm_error err;
  memset(&out, 0, sizeof out);
  out.energy = energy;
  for (int i = 0; i < nout; i++) tout[i] = dt * i;
  phm_status st = phm_simulate(m, NULL, NULL, tout, nout, &opt, &out, &err);
  free(tout);
  snprintf(name, sizeof name, "%s simulation runs", what);
  if (!check(name, st == PHM_OK ? 0 : 1, 0)) printf("  %s\n", err.msg);
  snprintf(name, sizeof name, "%s: all outputs", what);
  check(name, out.nout_done == nout ? 0 : 1, 0);
  return out.nout_done;
}

/* Free rigid body with offset centre of mass, no gravity: energy conserved through an
 * intermediate-axis spin. */
static void free_body_conserves_energy(void) {
  phm_carrier_desc c;
  carrier_unit(&c);
  double I[3] = {1.0, 2.0, 3.0}, mass = 2.0, r[3] = {0.1, -0.05, 0.2};
  memset(c.M, 0, sizeof c.M);
  /* M = [[I - m r^2, m r^], [-m r^, m 1]]  (body inertia about the frame origin) */
  double rh[9] = {0, -r[2], r[1], r[2], 0, -r[0], -r[1], r[0], 0};
  for (int i = 0; i < 3; i++) {
    c.M[7 * i] = I[i];
    c.M[6 * (i + 3) + i + 3] = mass;
    for (int j = 0; j < 3; j++) {
      double rr = 0;
      for (int k = 0; k < 3; k++) rr += rh[3 * i + k] * rh[3 * k + j];
      c.M[6 * i + j] -= mass * rr;
      c.M[6 * i + j + 3] = mass * rh[3 * i + j];
      c.M[6 * (i + 3) + j] = -mass * rh[3 * i + j];
    }
  }
  c.mass = mass;
  memcpy(c.com, r, sizeof r);
  double t0[6] = {0.01, 5.0, 0.02, 0.1, 0.0, -0.2};
  memcpy(c.t0, t0, sizeof t0);
  phm_model_desc d = {.ncarriers = 1, .carriers = &c};
  phm_model *m = create_model(&d);
  if (!m) return;
  enum { NOUT = 21 };
  double energy[NOUT * PHM_NENERGY];
  int nout_done = run_energy(m, 0.5, NOUT, 1e-10, 1e-12, energy, "free body");
  double e0 = energy[5], de = 0;
  for (int i = 0; i < nout_done; i++) de = fmax(de, fabs(energy[i * PHM_NENERGY + 5] - e0));
  check("free body (intermediate-axis spin, offset CoM): energy drift / E0", de / e0, 1e-7);
  phm_model_free(m);
}

CHECK_MAIN(CHECK_CASE(free_body_conserves_energy))
