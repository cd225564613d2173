/* pose.c -- pose <-> (quaternion, position) and the retraction H exp(delta) (csrc/util/pose.h). */
#include "pose.h"

#include <string.h>

#include "phmech.h"

void phm_qp_to_H(const double q[4], const double p[3], double H[16]) {
  double R[9];
  phm_quat_to_rot(q, R);
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) H[4 * i + j] = R[3 * i + j];
    H[4 * i + 3] = p[i];
  }
  H[12] = H[13] = H[14] = 0;
  H[15] = 1;
}

void phm_H_to_qp(const double H[16], double q[4], double p[3]) {
  double R[9];
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) R[3 * i + j] = H[4 * i + j];
    p[i] = H[4 * i + 3];
  }
  phm_quat_from_rot(R, q);
}

void phm_H_to_qp_near(const double H[16], const double *qprev, double q[4], double p[3]) {
  double qn[4];
  phm_H_to_qp(H, qn, p);
  const int flip = qprev && qn[0] * qprev[0] + qn[1] * qprev[1] + qn[2] * qprev[2] + qn[3] * qprev[3] < 0;
  for (int i = 0; i < 4; i++) q[i] = flip ? -qn[i] : qn[i];
}

void phm_retract(double H[16], const double delta[6]) {
  double E[16], HE[16];
  phm_se3_exp(delta, E);
  phm_se3_compose(H, E, HE);
  memcpy(H, HE, sizeof HE);
}
