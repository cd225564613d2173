/* quat.c -- unit quaternions (q_w, q_x, q_y, q_z) <-> rotation matrices (the public phm_quat_*;
 * conventions: csrc/include/phmech_types.h, docs/method.md section 3). A quaternion about a
 * coordinate axis (a planar scene's) takes the general path's arithmetic without its exact-zero
 * terms: the same numbers (tests/c/test_se3.c compares the two). No allocation. */
#include "linalg.h"

#include <math.h>
#include <string.h>

/* The general quaternion -> rotation (phm_quat_to_rot_general; inlined into each caller). */
static inline void quat_to_rot_gen(const double q[4], double R[9]) {
  double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  if (!(n2 > 0.0)) { /* zero quaternion: identity (callers should reject it) */
    static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(R, I, sizeof I);
    return;
  }
  double s = 2.0 / n2;
  double w = q[0], x = q[1], y = q[2], z = q[3];
  R[0] = 1.0 - s * (y * y + z * z);
  R[1] = s * (x * y - w * z);
  R[2] = s * (x * z + w * y);
  R[3] = s * (x * y + w * z);
  R[4] = 1.0 - s * (x * x + z * z);
  R[5] = s * (y * z - w * x);
  R[6] = s * (x * z - w * y);
  R[7] = s * (y * z + w * x);
  R[8] = 1.0 - s * (x * x + y * y);
}

/* phm_quat_to_rot at q = (q_w, q_k e_k) (k constant): the general path's arithmetic without its
 * exact-zero terms (the same numbers), n2 > 0 and s = 2 / n2 given. */
PHM_AXIS_INLINE void quat_to_rot_axis(int k, const double q[4], double s, double R[9]) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  double c = q[1 + k], wc = s * (q[0] * c);
  R[3 * k + k] = 1.0;
  R[3 * i + i] = R[3 * j + j] = 1.0 - s * (c * c);
  R[3 * j + i] = wc;
  R[3 * i + j] = -wc;
  R[3 * i + k] = R[3 * k + i] = R[3 * j + k] = R[3 * k + j] = 0.0;
}

void phm_quat_to_rot(const double q[4], double R[9]) {
  /* a planar scene's quaternions turn about one axis: two vector components exactly zero */
  int k = q[1] == 0.0 ? (q[2] == 0.0 ? 2 : q[3] == 0.0 ? 1 : -1) : q[2] == 0.0 && q[3] == 0.0 ? 0 : -1;
  if (k >= 0) {
    double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (n2 > 0.0) {
      PHM_AXIS_CALL(k, quat_to_rot_axis, q, 2.0 / n2, R);
      return;
    }
  }
  quat_to_rot_gen(q, R);
}

void phm_quat_to_rot_general(const double q[4], double R[9]) { quat_to_rot_gen(q, R); }

void phm_quat_from_rot(const double R[9], double q[4]) {
  double tr = R[0] + R[4] + R[8];
  double d[4] = {tr, R[0], R[4], R[8]};
  int k = 0;
  for (int i = 1; i < 4; i++)
    if (d[i] > d[k]) k = i;
  double r, f;
  switch (k) {
  case 0:
    r = sqrt(fmax(1.0 + tr, 0.0));
    f = r > 0.0 ? 0.5 / r : 0.0;
    q[0] = 0.5 * r;
    q[1] = (R[7] - R[5]) * f;
    q[2] = (R[2] - R[6]) * f;
    q[3] = (R[3] - R[1]) * f;
    break;
  case 1:
    r = sqrt(fmax(1.0 + R[0] - R[4] - R[8], 0.0));
    f = r > 0.0 ? 0.5 / r : 0.0;
    q[0] = (R[7] - R[5]) * f;
    q[1] = 0.5 * r;
    q[2] = (R[1] + R[3]) * f;
    q[3] = (R[2] + R[6]) * f;
    break;
  case 2:
    r = sqrt(fmax(1.0 - R[0] + R[4] - R[8], 0.0));
    f = r > 0.0 ? 0.5 / r : 0.0;
    q[0] = (R[2] - R[6]) * f;
    q[1] = (R[1] + R[3]) * f;
    q[2] = 0.5 * r;
    q[3] = (R[5] + R[7]) * f;
    break;
  default:
    r = sqrt(fmax(1.0 - R[0] - R[4] + R[8], 0.0));
    f = r > 0.0 ? 0.5 / r : 0.0;
    q[0] = (R[3] - R[1]) * f;
    q[1] = (R[2] + R[6]) * f;
    q[2] = (R[5] + R[7]) * f;
    q[3] = 0.5 * r;
    break;
  }
  double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!(n > 0.0)) { /* not a rotation matrix */
    q[0] = 1.0;
    q[1] = q[2] = q[3] = 0.0;
    return;
  }
  double sg = q[0] < 0.0 ? -1.0 / n : 1.0 / n;
  for (int i = 0; i < 4; i++) q[i] *= sg;
}
