/* test_applied.c -- csrc/model/applied.c, the applied wrenches: an actuator on every pair type
 * (its wrenches deliver u . xdot, the port's power; the PD law). */
#include "check.h"
#include "model.h"

/* Every pair type: an actuator's wrenches on the two carriers deliver exactly u . xdot, which is
 * also its port power and the supplied power; its PD effort follows
 * u = -kp (x - x_set - s vec) - kd (xdot - ds vec). */
static void actuator_power_is_effort_times_joint_rate_on_every_pair_type(void) {
  for (int type = 1; type < phm_pair_type_count(); type++)
    for (int trial = 0; trial < 6; trial++) {
      char name[96];
      const char *tn = phm_pair_type(type)->name;
      int k = 6 - phm_pair_type(type)->m;
      phm_pair_desc pr;
      rand_pair(type, trial, &pr);
      double x[6];
      rand_joint_coordinates(type, trial - 2, x);
      pr.has_x0 = 1;
      memcpy(pr.x0, x, sizeof x);
      phm_actuator_desc ac;
      memset(&ac, 0, sizeof ac);
      ac.pair = 0;
      ac.kind = PHM_ACT_PD;
      for (int i = 0; i < 6; i++) {
        ac.kp[i] = 1 + fabs(rand11());
        ac.kd[i] = fabs(rand11());
        ac.x_set[i] = rand11();
        ac.vec[i] = rand11();
      }
      ac.law.kind = PHM_LAW_SINE;
      ac.law.amplitude = 0.5;
      ac.law.frequency = 0.7;
      phm_model *m = two_carrier_model(&pr, &ac, 1);
      if (!m) continue;
      double H[32], h[16], xref[6], tw[12], wr[12], Pp[1], eff[6], Ps = 0, xe[6], xd[6];
      rand_pose(H, 1.0);
      phm_pair_type_pose(type, pr.pitch, x, h);
      place_b(pr.a < 0 ? NULL : H, pr.Ta, pr.Tb, h, H + 16);
      for (int i = 0; i < 6; i++) xref[i] = x[i] + 0.3 * rand11();
      for (int i = 0; i < 12; i++) tw[i] = rand11();
      if (pr.a < 0) for (int i = 0; i < 6; i++) tw[i] = 0;
      phm_applied(m, H, tw, xref, 0.3, 0.3, 1.0, wr, NULL, NULL, &Ps, Pp, eff);
      double pw = 0;
      for (int i = 0; i < 12; i++) pw += wr[i] * tw[i];
      phm_pair_joint(m, 0, pr.a < 0 ? NULL : H, H + 16, pr.a < 0 ? NULL : tw, tw + 6, xref, xe, xd);
      double ux = 0;
      for (int i = 0; i < k; i++) ux += eff[i] * xd[i];
      snprintf(name, sizeof name, "%s: actuator wrench power = u . xdot = port power", tn);
      check(name, fabs(pw - ux) + fabs(Pp[0] - ux) + fabs(Ps - ux), 1e-11 * (1 + fabs(ux)));
      double ds, s = phm_law_eval(&ac.law, 0.3, 0.3, &ds, NULL), eu = 0;
      for (int i = 0; i < k; i++)
        eu = fmax(eu, fabs(eff[i] - (-ac.kp[i] * (xe[i] - ac.x_set[i] - s * ac.vec[i]) - ac.kd[i] * (xd[i] - ds * ac.vec[i]))));
      snprintf(name, sizeof name, "%s: PD effort formula", tn);
      check(name, eu, 1e-12);
      phm_model_free(m);
    }
}

CHECK_MAIN(CHECK_CASE(actuator_power_is_effort_times_joint_rate_on_every_pair_type))
