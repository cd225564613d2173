/* test_pose.c -- csrc/util/pose.c: a pose as the state stores it (unit quaternion, position) and
 * back, and the retraction H <- H exp(delta), against poses built by tests/c/check.h's expm. */
#include "check.h"
#include "pose.h"

static void quaternion_and_position_round_trip(void) {
  for (int it = 0; it < 200; it++) {
    double H[16], H2[16], q[4], p[3];
    rand_pose_class(it % 4, H);
    phm_H_to_qp(H, q, p);
    check_worst("H_to_qp: unit quaternion with w >= 0",
                fabs(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) - 1) + (q[0] >= 0 ? 0 : 1), 1e-15 * 4);
    double pr[3] = {H[3], H[7], H[11]};
    check_worst("H_to_qp: p = translation of H", maxdiff(3, p, pr), 0.0);
    phm_qp_to_H(q, p, H2);
    check_worst("qp_to_H(H_to_qp(H)) = H", maxdiff(16, H, H2), 1e-14);
  }
}

static void retraction_is_right_multiplication_by_exp(void) {
  for (int it = 0; it < 200; it++) {
    double H[16], Hr[16], E[16], ref[16], d[6], zero[6] = {0};
    rand_pose_class(0, H);
    rand_twist(it % 4, d);
    memcpy(Hr, H, sizeof H);
    phm_retract(Hr, d);
    pose_expm(d, E);
    matmul(4, H, E, ref);
    check_worst("retract(H, d) = H expm(hat d) (relative to 1 + |p|)", maxdiff(16, Hr, ref) / (1 + maxabs(16, ref)), 1e-13);
    memcpy(Hr, H, sizeof H);
    phm_retract(Hr, zero);
    check_worst("retract(H, 0) = H", maxdiff(16, Hr, H), 0.0);
  }
}

CHECK_MAIN(CHECK_CASE(quaternion_and_position_round_trip),
           CHECK_CASE(retraction_is_right_multiplication_by_exp))
