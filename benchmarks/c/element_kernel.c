/* element_kernel.c -- CPU time of one se3 beam element's kernels (csrc/model/element.c): the
 * wrenches (phm_element_eval, what a residual evaluates per element), the fused wrenches and
 * tangent (phm_element_tangent, what a Jacobian evaluates per element), and the finite-difference
 * tangent it replaced (12 pose and 12 twist perturbations, one element evaluation each). A bent,
 * twisted, moving element; median of 7 repetitions of 200 000 calls.
 *   meson compile -C build/check-release bench_element_kernel && build/check-release/bench_element_kernel */
#include "bench_time.h"

#include <stdio.h>
#include <string.h>

#include "model.h"
#include "pose.h"

enum { CALLS = 200000, REPS = 7 };
static volatile double sink;

int main(void) {
  phm_element_desc e;
  memset(&e, 0, sizeof e);
  e.h = 0.05;
  for (int i = 0; i < 6; i++) {
    e.K[7 * i] = 1e3 * (i + 1);
    e.D[7 * i] = 1e-3 * (i + 1);
  }
  e.eps_hat[3] = 1.0;
  double Ha[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, Hb[16];
  double x[6] = {0.02, -0.03, 0.04, 0.051, 0.002, -0.001}, ta[6] = {1, -2, 0.5, 0.1, 0.2, -0.3},
         tb[6] = {-1, 1.5, 0.3, 0.2, -0.1, 0.4};
  phm_se3_exp(x, Hb);
  const char *name[3] = {"phm_element_eval (wrenches)", "phm_element_tangent (fused)",
                         "forward-difference tangent (24 evals)"};
  for (int k = 0; k < 3; k++) {
    double t[REPS];
    for (int r = 0; r < REPS; r++) {
      double t0 = bench_now(), acc = 0;
      for (int c = 0; c < CALLS; c++) {
        double wa[6], wb[6], Kx[144], Ct[144];
        Ha[3] = 1e-9 * c; /* defeat hoisting */
        if (k == 0) phm_element_eval(&e, Ha, Hb, ta, tb, wa, wb, NULL, NULL, NULL);
        else if (k == 1) phm_element_tangent(&e, Ha, Hb, ta, tb, wa, wb, Kx, Ct);
        else {
          for (int j = 0; j < 24; j++) { /* node a's then b's pose, then a's and b's twist */
            double Hp[16], d[6] = {0}, tp[12];
            memcpy(tp, ta, sizeof ta);
            memcpy(tp + 6, tb, sizeof tb);
            memcpy(Hp, j < 6 ? Ha : Hb, sizeof Hp);
            if (j < 12) {
              d[j % 6] = 1e-7;
              phm_retract(Hp, d);
            } else tp[j - 12] += 1e-7;
            phm_element_eval(&e, j < 6 ? Hp : Ha, j >= 6 && j < 12 ? Hp : Hb, tp, tp + 6, wa, wb,
                             NULL, NULL, NULL);
            acc += wa[0];
          }
        }
        acc += wa[0] + wb[5];
      }
      t[r] = (bench_now() - t0) / CALLS;
      sink = acc;
    }
    printf("%-40s %8.1f ns per element\n", name[k], 1e9 * bench_median(t, REPS));
  }
  return 0;
}
