/* phmech.h -- the public C API of phmech, one section per concept.
 *
 * Conventions (DESIGN.md section 3):
 *   - every matrix is a row-major (C-ordered) array of doubles: a 3x3 is double[9],
 *     a 4x4 homogeneous pose is double[16], a 6x6 is double[36];
 *   - twist t = (omega, v), wrench w = (tau, f): angular part first;
 *   - pose H = [[R, p], [0, 1]]; body-frame twist: H^-1 dH/dt = hat(t);
 *   - ad_t = [[hat(w), 0], [hat(v), hat(w)]],  Ad_H = [[R, 0], [hat(p) R, R]];
 *     the duals ad*_t := ad_t^T and Ad*_H := Ad_H^T act on wrenches;
 *   - dexp_X = sum_k ad_X^k / (k+1)!, so that H = H0 exp(hat X) gives H^-1 dH/dt = dexp_{-X} dX/dt;
 *   - quaternions are scalar first: q = (w, x, y, z), unit norm.
 * The library never prints, exits or aborts: functions that can fail return a phm_status and
 * leave a message in a phm_error.
 */
#ifndef PHMECH_H
#define PHMECH_H

#include <stddef.h>

#define PHM_VERSION "0.1.0"

/* ---------------------------------------------------------------- errors */
typedef enum {
  PHM_OK = 0,
  PHM_EINVAL = 1,    /* bad model or argument (Python: ValueError subclass)      */
  PHM_ENOMEM = 2,    /* allocation failed (Python: MemoryError)                    */
  PHM_ESOLVER = 3,   /* integrator / nonlinear solver failure (Python: RuntimeError) */
  PHM_ESINGULAR = 4, /* singular or indefinite matrix (Python: RuntimeError)       */
  PHM_EINTERRUPT = 5 /* stopped by the caller's interrupt callback                  */
} phm_status;

typedef struct {
  phm_status code;
  char msg[512];
} phm_error;

/* Record code and a printf-style message in err (err may be NULL); returns code. */
phm_status phm_error_set(phm_error *err, phm_status code, const char *fmt, ...);
/* Reset err to PHM_OK with an empty message. */
void phm_error_clear(phm_error *err);

/* ---------------------------------------------------------------- so(3) / SO(3) */
void phm_so3_hat(const double w[3], double W[9]);        /* W = hat(w), W x = w cross x   */
void phm_so3_vee(const double W[9], double w[3]);        /* inverse of hat (skew part)    */
void phm_so3_exp(const double w[3], double R[9]);        /* Rodrigues, series near 0      */
void phm_so3_log(const double R[9], double w[3]);        /* |w| in [0, pi], robust near pi */
void phm_so3_jac(const double w[3], double A[9]);        /* sum_k hat(w)^k/(k+1)! (left Jacobian) */
void phm_so3_jac_inv(const double w[3], double Ai[9]);   /* inverse of phm_so3_jac, |w| < 2 pi */

/* ---------------------------------------------------------------- se(3) / SE(3) */
void phm_se3_hat(const double x[6], double X[16]);       /* 4x4 matrix of twist coordinates */
void phm_se3_vee(const double X[16], double x[6]);
void phm_se3_exp(const double x[6], double H[16]);
void phm_se3_log(const double H[16], double x[6]);       /* |omega| in [0, pi]               */
void phm_se3_compose(const double A[16], const double B[16], double AB[16]);
void phm_se3_inverse(const double H[16], double Hi[16]);
void phm_se3_Ad(const double H[16], double A[36]);       /* Ad_H                          */
void phm_se3_Ad_dual(const double H[16], double A[36]);  /* Ad*_H = Ad_H^T (wrenches)      */
void phm_se3_ad(const double x[6], double a[36]);        /* ad_x                          */
void phm_se3_ad_dual(const double x[6], double a[36]);   /* ad*_x = ad_x^T                 */
void phm_se3_dexp(const double x[6], double D[36]);      /* sum_k ad_x^k/(k+1)!            */
void phm_se3_dexp_inv(const double x[6], double Di[36]); /* its inverse, |omega| < 2 pi    */

/* ---------------------------------------------------------------- quaternions */
void phm_quat_to_rot(const double q[4], double R[9]);    /* q need not be normalized       */
void phm_quat_from_rot(const double R[9], double q[4]);  /* Shepperd; returns q with w >= 0 */

/* ---------------------------------------------------------------- mixed finite element (beam_mixed.c) */

/* ---------------------------------------------------------------- model, simulation, modes (model.c) */

#endif /* PHMECH_H */
