/* planar_kernels.c -- CPU time per call of the kernels a residual (and an output, a Jacobian)
 * evaluates per se3 beam element and per carrier (csrc/util/se3.c, csrc/model/element.c), at a
 * planar element (rotation about y by 0.2 or 0.05 rad, in-plane translation and twists: their
 * fast paths) and at a 3-D one (the general paths, which pay only the tests of the fast paths'
 * detection). Median of 9 repetitions of 100 000 calls, thread CPU time.
 *   meson compile -C build/check-release bench_planar_kernels && build/check-release/bench_planar_kernels */
#include "bench_time.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "model.h"
#include "pose.h"

enum { CALLS = 100000, REPS = 9, NK = 10 };
static volatile double sink;

/* called through volatile pointers: each kernel's own code, as the library's other files call it,
 * not a copy inlined into this loop (link-time optimization would inline some and not others) */
static void (*volatile so3_log)(const double *, double *) = phm_so3_log;
static void (*volatile se3_log)(const double *, double *) = phm_se3_log;
static void (*volatile log_dexp_inv)(const double *, double *, double *, double *) = phm_se3_log_dexp_inv;
static void (*volatile element_eval)(const phm_element_desc *, const double *, const double *,
                                     const double *, const double *, double *, double *, double *,
                                     double *, double *) = phm_element_eval;
static double (*volatile element_energy)(const phm_element_desc *, const double *,
                                         const double *) = phm_element_energy;
static void (*volatile element_inertia)(const double *, const unsigned short *, const double *,
                                        const double *, const double *, const double *, double,
                                        double *, double *) = phm_element_inertia;
static void (*volatile element_tangent)(const phm_element_desc *, const double *, const double *,
                                        const double *, const double *, double *, double *,
                                        double *, double *) = phm_element_tangent;
static void (*volatile dexp_inv_partials)(const double *, double (*)[9], double (*)[9]) =
    phm_se3_dexp_inv_partials;
static void (*volatile quat_to_rot)(const double *, double *) = phm_quat_to_rot;
static double (*volatile element_kinetic)(const double *, const unsigned short *, const double *,
                                          const double *) = phm_element_kinetic;

static const char *kname[NK] = {"phm_so3_log", "phm_se3_log", "phm_se3_log_dexp_inv",
                                "phm_element_eval", "phm_element_energy", "phm_element_inertia",
                                "phm_element_kinetic", "phm_element_tangent",
                                "phm_se3_dexp_inv_partials", "phm_quat_to_rot"};

static double run(int k, const phm_element_desc *e, const double *Mc, const unsigned short *rows,
                  double Ha[16], const double Hb[16], const double ta[6], const double tb[6],
                  const double dta[6], const double dtb[6]) {
  double t[REPS];
  for (int r = 0; r < REPS; r++) {
    double t0 = bench_now(), acc = 0;
    for (int c = 0; c < CALLS; c++) {
      double wa[6], wb[6], x[6], A[9], L[9], Hab[16], f[12], R[9];
      Ha[3] = 1e-12 * (c & 1023); /* defeat hoisting */
      switch (k) {
      case 0:
        phm_inv_compose(Ha, Hb, Hab);
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) R[3 * i + j] = Hab[4 * i + j];
        so3_log(R, x);
        acc += x[1];
        break;
      case 1:
        phm_inv_compose(Ha, Hb, Hab);
        se3_log(Hab, x);
        acc += x[3];
        break;
      case 2:
        phm_inv_compose(Ha, Hb, Hab);
        log_dexp_inv(Hab, x, A, L);
        acc += x[3] + L[5];
        break;
      case 3:
        element_eval(e, Ha, Hb, ta, tb, wa, wb, NULL, NULL, NULL);
        acc += wa[0] + wb[5];
        break;
      case 4: acc += element_energy(e, Ha, Hb); break;
      case 5:
        element_inertia(Mc, rows, ta, tb, dta, dtb, 0.0, f, NULL);
        acc += f[3];
        break;
      case 6: acc += element_kinetic(Mc, rows, ta, tb); break;
      case 7: {
        double Kx[144], Ct[144];
        element_tangent(e, Ha, Hb, ta, tb, wa, wb, Kx, Ct);
        acc += Kx[13] + Ct[7];
      } break;
      case 9: { /* Hb's quaternion (phm_H_to_qp; planar: (q_w, 0, q_y, 0)) */
        double q[4], p[3];
        phm_H_to_qp(Hb, q, p);
        q[0] += 1e-12 * (c & 1023);
        quat_to_rot(q, R);
        acc += R[2];
      } break;
      default: {
        double dA[6][9], dL[6][9];
        phm_inv_compose(Ha, Hb, Hab);
        log_dexp_inv(Hab, x, A, L);
        dexp_inv_partials(x, dA, dL);
        acc += dA[1][3] + dL[4][5];
      } break;
      }
    }
    t[r] = (bench_now() - t0) / CALLS;
    sink = acc;
  }
  return 1e9 * bench_median(t, REPS);
}

int main(void) {
  phm_element_desc e;
  memset(&e, 0, sizeof e);
  e.h = 1.0 / 3.0;
  for (int i = 0; i < 6; i++) {
    e.K[7 * i] = 1e3 * (i + 1);
    e.D[7 * i] = 1e-3 * (i + 1);
    e.Ms[7 * i] = 0.1 * (i + 1);
  }
  e.eps_hat[3] = 1.0;
  double Mc[144];
  unsigned short rows[12];
  phm_element_mass(e.h, e.Ms, e.eps_hat, Mc);
  phm_mass_rows(Mc, rows);
  /* planar: poses from quaternions (q_w, 0, q_y, 0), in-plane positions and twists; the element
   * turning by 0.2 rad (the trigonometric branch of the coefficients, from 0.1 rad) and by 0.05 */
  double qa[4] = {cos(0.1), 0, sin(0.1), 0}, qb[4] = {cos(0.2), 0, sin(0.2), 0};
  double qc[4] = {cos(0.125), 0, sin(0.125), 0};
  double pa[3] = {0.5, 0.0, -0.05}, pb[3] = {0.82, 0.0, -0.13};
  double Hpa[16], Hpb[16], Hpc[16];
  phm_qp_to_H(qa, pa, Hpa);
  phm_qp_to_H(qb, pb, Hpb);
  phm_qp_to_H(qc, pb, Hpc);
  double pta[6] = {0, 0.7, 0, 0.1, 0, -0.3}, ptb[6] = {0, 1.1, 0, 0.2, 0, -0.5};
  double pdta[6] = {0, 3.0, 0, 0.4, 0, -1.3}, pdtb[6] = {0, 4.1, 0, 0.5, 0, -2.0};
  /* 3-D: a bent, twisted, moving element (benchmarks/c/element_kernel.c's) */
  double Hga[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, Hgb[16];
  double xg[6] = {0.02, -0.03, 0.04, 0.051, 0.002, -0.001};
  phm_se3_exp(xg, Hgb);
  double gta[6] = {1, -2, 0.5, 0.1, 0.2, -0.3}, gtb[6] = {-1, 1.5, 0.3, 0.2, -0.1, 0.4};
  double gdta[6] = {0.3, 0.2, -0.1, 0.5, 0.6, 0.1}, gdtb[6] = {-0.2, 0.1, 0.4, -0.3, 0.2, 0.7};
  printf("%-24s %11s %11s %11s   (ns per call, median of %d x %d)\n", "kernel", "planar 0.2", "planar 0.05",
         "3-D", REPS, CALLS);
  for (int k = 0; k < NK; k++) {
    double tp = run(k, &e, Mc, rows, Hpa, Hpb, pta, ptb, pdta, pdtb);
    double tq = run(k, &e, Mc, rows, Hpa, Hpc, pta, ptb, pdta, pdtb);
    double tg = run(k, &e, Mc, rows, Hga, Hgb, gta, gtb, gdta, gdtb);
    printf("%-24s %11.1f %11.1f %11.1f\n", kname[k], tp, tq, tg);
  }
  return 0;
}
