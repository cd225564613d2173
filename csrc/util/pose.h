/* pose.h -- the SE(3) helpers of the core's inner loops: a carrier's pose H as the state stores
 * it (unit quaternion q, position p; its sign continued), the retraction used by every Newton update on SE(3)
 * (csrc/util/pose.c), and ad*_t applied to a momentum. */
#ifndef PHM_POSE_H
#define PHM_POSE_H

void phm_qp_to_H(const double q[4], const double p[3], double H[16]);
void phm_H_to_qp(const double H[16], double q[4], double p[3]);
/* phm_H_to_qp with q's sign that of qprev's hemisphere (q and -q are the same rotation: a state
 * keeps its quaternions continuous along a run); qprev NULL: as phm_H_to_qp; it may be q. */
void phm_H_to_qp_near(const double H[16], const double *qprev, double q[4], double p[3]);
void phm_retract(double H[16], const double delta[6]); /* H <- H exp(delta) */

/* h = A^-1 B (A, B: their first three rows read): R_A^T R_B, R_A^T p_B + (-R_A^T p_A), the
 * arithmetic of phm_se3_inverse then phm_se3_compose (the same numbers) without their copies. */
static inline void phm_inv_compose(const double A[16], const double B[16], double h[16]) {
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) h[4 * i + j] = A[i] * B[j] + A[4 + i] * B[4 + j] + A[8 + i] * B[8 + j];
    double qa = -(A[i] * A[3] + A[4 + i] * A[7] + A[8 + i] * A[11]);
    h[4 * i + 3] = (A[i] * B[3] + A[4 + i] * B[7] + A[8 + i] * B[11]) + qa;
  }
  h[12] = h[13] = h[14] = 0.0;
  h[15] = 1.0;
}

/* out = ad_t x for twists t = (omega, v), x = (w, u): (omega x w, v x w + omega x u), the twists'
 * bracket (docs/method.md section 3.4); phm_ad_dual_apply is its transpose. */
static inline void phm_ad_apply(const double t[6], const double x[6], double out[6]) {
  const double *om = t, *v = t + 3, *w = x, *u = x + 3;
  out[0] = om[1] * w[2] - om[2] * w[1];
  out[1] = om[2] * w[0] - om[0] * w[2];
  out[2] = om[0] * w[1] - om[1] * w[0];
  out[3] = v[1] * w[2] - v[2] * w[1] + om[1] * u[2] - om[2] * u[1];
  out[4] = v[2] * w[0] - v[0] * w[2] + om[2] * u[0] - om[0] * u[2];
  out[5] = v[0] * w[1] - v[1] * w[0] + om[0] * u[1] - om[1] * u[0];
}

/* out = ad*_t mm = ad_t^T mm for a momentum mm = (L, P) and a twist t = (omega, v):
 * (-omega x L - v x P, -omega x P) (docs/method.md section 3.4): the gyroscopic term. */
static inline void phm_ad_dual_apply(const double t[6], const double mm[6], double out[6]) {
  const double *w = t, *v = t + 3, *L = mm, *P = mm + 3;
  out[0] = -(w[1] * L[2] - w[2] * L[1]) - (v[1] * P[2] - v[2] * P[1]);
  out[1] = -(w[2] * L[0] - w[0] * L[2]) - (v[2] * P[0] - v[0] * P[2]);
  out[2] = -(w[0] * L[1] - w[1] * L[0]) - (v[0] * P[1] - v[1] * P[0]);
  out[3] = -(w[1] * P[2] - w[2] * P[1]);
  out[4] = -(w[2] * P[0] - w[0] * P[2]);
  out[5] = -(w[0] * P[1] - w[1] * P[0]);
}

#endif
