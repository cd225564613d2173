/* pose.h -- the SE(3) helpers of the core's inner loops: a carrier's pose H as the state stores
 * it (unit quaternion q, position p), the retraction used by every Newton update on SE(3)
 * (csrc/util/pose.c), and ad*_t applied to a momentum. */
#ifndef PHM_POSE_H
#define PHM_POSE_H

void phm_qp_to_H(const double q[4], const double p[3], double H[16]);
void phm_H_to_qp(const double H[16], double q[4], double p[3]);
void phm_retract(double H[16], const double delta[6]); /* H <- H exp(delta) */

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
