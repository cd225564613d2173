/* linear_model.c -- the linear port-Hamiltonian model (docs/method.md section 7.4): the reduced
 * K, D, M of reduce.c and the input matrix of the ports' generalized forces; with the
 * components' laws linearized at the point (phm_linear_closed_loop, section 7.5: controllers,
 * motors, friction). */
#include "analyze.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"

/* ---------------------------------------------------------------- linear port-Hamiltonian model */
int phm_linear_port_columns(const phm_model *m, int nports, const phm_linear_port *ports) {
  int n = 0;
  for (int i = 0; i < nports; i++)
    n += ports[i].kind == PHM_PORT_PAIR ? (ports[i].index >= 0 && ports[i].index < m->np ? m->pair_k[ports[i].index] : 0)
         : ports[i].kind == PHM_PORT_LOAD ? 1 : 6;
  return n;
}

/* Row i (0..5) of carrier c's block of the null-space basis Z (reduce.c): Z[6 c + i, a]. */
static double z_entry(const lin_red_t *R, int c, int i, int a) {
  if (R->red[c] >= 0) return a == R->red[c] + i;
  return a < R->n0 ? R->U0[(size_t)a * R->n6c + 6 * R->cmap[c] + i] : 0.0;
}

/* Zp (12 x nr, row-major): the rows of Z of pair ip's carriers a, b (zero for the ground). */
static void pair_basis(const lin_red_t *R, const phm_model *m, int ip, double *Zp) {
  int ab[2] = {m->pair[ip].a, m->pair[ip].b}, nr = R->nr;
  for (int s = 0; s < 2; s++)
    for (int i = 0; i < 6; i++)
      for (int a = 0; a < nr; a++)
        Zp[(size_t)(6 * s + i) * nr + a] = ab[s] >= 0 ? z_entry(R, ab[s], i, a) : 0.0;
}

/* The components' linearized laws at R's point (phm_linear_components; the states at cp->z or
 * their initial values), at rest: each component's tangent (phm_component_tangent) through the
 * rows of Z of the pair it drives (Zd) and of the pair it measures (Zs). Zd, Zs: 12 x nr
 * scratch; f6: 12 nc, zero: nz + 1 scratch. */
static void linear_components(const lin_red_t *R, const phm_model *m, phm_linear_components *cp,
                              double *Zd, double *Zs, double *f6, double *zero) {
  int nr = R->nr, nz = m->nz, nc = m->nc;
  const double *H = R->H, *z = cp->z;
  double time = R->L.time, tref = R->L.tref;
  memset(cp->Kc, 0, sizeof(double) * (size_t)nr * nr);
  memset(cp->Dc, 0, sizeof(double) * (size_t)nr * nr);
  memset(cp->Kz, 0, sizeof(double) * (size_t)nr * nz);
  memset(cp->Fq, 0, sizeof(double) * (size_t)nr * nz);
  memset(cp->Fv, 0, sizeof(double) * (size_t)nr * nz);
  memset(cp->Fz, 0, sizeof(double) * (size_t)nz * nz);
  for (int ic = 0; ic < m->ncomp; ic++) {
    const phm_component_desc *c = &m->comp[ic];
    int sp = c->kind == PHM_COMP_LINEAR && c->spair >= 0 ? c->spair : c->pair;
    int nzc = phm_component_nstates(c), zc = m->comp_z[ic];
    double w[12], Ku[144], B[12], gq[12], gt[12], Kz[12 * PHM_COMP_MAXZ], Fx[12 * PHM_COMP_MAXZ];
    double Ft[12 * PHM_COMP_MAXZ], Fz[PHM_COMP_MAXZ * PHM_COMP_MAXZ];
    phm_component_tangent(m, ic, NULL, H, NULL, NULL, z, time, tref, w, Ku, B, gq, gt, Kz, Fx, Ft,
                          Fz);
    /* dw/d[da; db] at fixed u with the chart factor of f_c (linearize.c, lin_add_own_block) */
    for (int s = 0; s < 2; s++) {
      double blk[36] = {0};
      lin_add_own_block(blk, Ku + 12 * 6 * s + 6 * s, 12, w + 6 * s);
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) Ku[12 * (6 * s + i) + 6 * s + j] = blk[6 * i + j];
    }
    pair_basis(R, m, c->pair, Zd);
    pair_basis(R, m, sp, Zs);
    for (int a = 0; a < nr; a++) { /* b = Zd^T B, (Zs^T gq), (Zs^T gt); Kc -= Zd^T Ku Zd */
      double ba = 0;
      for (int i = 0; i < 12; i++) ba += Zd[(size_t)i * nr + a] * B[i];
      for (int b = 0; b < nr; b++) {
        double gqb = 0, gtb = 0, kab = 0;
        for (int j = 0; j < 12; j++) {
          gqb += gq[j] * Zs[(size_t)j * nr + b];
          gtb += gt[j] * Zs[(size_t)j * nr + b];
          double kj = 0;
          for (int i = 0; i < 12; i++) kj += Zd[(size_t)i * nr + a] * Ku[12 * i + j];
          kab += kj * Zd[(size_t)j * nr + b];
        }
        cp->Kc[(size_t)a * nr + b] -= kab + ba * gqb;
        cp->Dc[(size_t)a * nr + b] -= ba * gtb;
      }
      for (int j = 0; j < nzc; j++) {
        double s = 0;
        for (int i = 0; i < 12; i++) s += Zd[(size_t)i * nr + a] * Kz[nzc * i + j];
        cp->Kz[(size_t)a * nz + zc + j] += s;
      }
    }
    for (int r = 0; r < nzc; r++) {
      for (int b = 0; b < nr; b++) {
        double fq = 0, fv = 0;
        for (int j = 0; j < 12; j++) {
          fq += Fx[12 * r + j] * Zs[(size_t)j * nr + b];
          fv += Ft[12 * r + j] * Zs[(size_t)j * nr + b];
        }
        cp->Fq[(size_t)(zc + r) * nr + b] = fq;
        cp->Fv[(size_t)(zc + r) * nr + b] = fv;
      }
      for (int j = 0; j < nzc; j++) cp->Fz[(size_t)(zc + r) * nz + zc + j] = Fz[nzc * r + j];
    }
  }
  /* the rest residual: Z^T of the components' wrenches, and of all the forces; the states'
   * rates f(x, 0, z) (phm_components_apply's rows z' - f at z' = zero, negated) */
  memset(f6, 0, sizeof(double) * 12 * (size_t)nc);
  memset(zero, 0, sizeof(double) * (size_t)(nz + 1));
  phm_components_apply(m, NULL, H, NULL, NULL, z, zero, time, tref, f6, NULL, cp->zdot, NULL,
                       NULL, NULL);
  if (cp->zdot)
    for (int i = 0; i < nz; i++) cp->zdot[i] = -cp->zdot[i];
  if (cp->fc) lin_red_project(R, nc, f6, cp->fc);
  /* the scale of the forces that balance at a rest state: the constraint wrenches, the
   * centrifugal ones and the components' (each carrier's total is zero there) */
  double *fm = f6 + 6 * (size_t)nc;
  memset(fm, 0, sizeof(double) * 6 * (size_t)nc);
  if (R->L.lam && m->ncons) phm_constraint_forces(m, H, time, tref, R->L.lam, fm);
  lin_spin_force(&R->L, H, fm);
  cp->fmax = 0;
  for (int i = 0; i < 6 * nc; i++) cp->fmax = fmax(cp->fmax, fmax(fabs(fm[i]), fabs(f6[i])));
  if (cp->f) {
    lin_total_force((lin_t *)&R->L, H, fm);
    for (int i = 0; i < 6 * nc; i++) fm[i] += f6[i];
    lin_red_project(R, nc, fm, cp->f);
  }
}

phm_status phm_linear_model(const phm_model *m, const double *poses, const double *lambda,
                            double time, int nports, const phm_linear_port *ports, int *nr,
                            double *K, double *D, double *M, double *Z, double *B,
                            phm_error *err) {
  return phm_linear_closed_loop(m, poses, lambda, time, nports, ports, nr, K, D, M, Z, B, NULL,
                                err);
}

phm_status phm_linear_closed_loop(const phm_model *m, const double *poses, const double *lambda,
                                  double time, int nports, const phm_linear_port *ports, int *nr,
                                  double *K, double *D, double *M, double *Z, double *B,
                                  phm_linear_components *comp, phm_error *err) {
  phm_error_clear(err);
  if (!m || !nr || !K || !D || !M || (nports > 0 && (!ports || !B)) ||
      (comp && (!comp->Kc || !comp->Dc || !comp->Kz || !comp->Fq || !comp->Fv || !comp->Fz)))
    return PHM_FAIL(err, PHM_EINVAL, "phm_linear_model: NULL argument");
  PHM_CHECK(nports >= 0, err, PHM_EINVAL, "phm_linear_model: nports must be >= 0 (got %d)", nports);
  for (int i = 0; i < nports; i++) {
    const phm_linear_port *p = &ports[i];
    int n = p->kind == PHM_PORT_PAIR ? m->np : p->kind == PHM_PORT_LOAD ? m->nl : p->kind == PHM_PORT_FRAME ? m->nc : -1;
    PHM_CHECK(n >= 0, err, PHM_EINVAL, "linear model: port %d has unknown kind %d (0 pair, 1 load, "
              "2 frame)", i, p->kind);
    PHM_CHECK(p->index >= 0 && p->index < n, err, PHM_EINVAL, "linear model: port %d (%s) index %d "
              "out of range [0, %d)", i, p->kind == PHM_PORT_PAIR ? "pair" : p->kind == PHM_PORT_LOAD
              ? "load" : "carrier", p->index, n);
    if (p->kind == PHM_PORT_FRAME)
      PHM_CHECK(phm_all_finite(p->T, 16), err, PHM_EINVAL, "linear model: port %d: non-finite "
                "frame offset", i);
  }
  *nr = 0;
  int nc = m->nc, n6 = 6 * nc, ncol = phm_linear_port_columns(m, nports, ports);
  phm_status st;
  lin_red_t R;
  memset(&R, 0, sizeof R);
  double *Zd = NULL, *f6 = NULL, *zero = NULL;
  double *F = calloc((size_t)n6 * (ncol + 1), sizeof(double)), *y = malloc(sizeof(double) * (size_t)n6);
  if (!F || !y) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  if ((st = lin_red_blocks(&R, m, poses, lambda, time, err)) || (st = lin_red_reduce(&R, m, err)))
    goto done;
  int n = R.nr;
  memcpy(K, R.Kr, sizeof(double) * (size_t)n * n);
  memcpy(D, R.Dr, sizeof(double) * (size_t)n * n);
  memcpy(M, R.Mr, sizeof(double) * (size_t)n * n);
  if (Z)
    for (int a = 0; a < n; a++) {
      for (int b = 0; b < n; b++) y[b] = a == b;
      lin_red_expand(&R, nc, y, F);                 /* column a of Z, F as scratch */
      for (int i = 0; i < n6; i++) Z[(size_t)i * n + a] = F[i];
    }
  /* the ports' generalized forces per unit input: F (ncol columns of 6 nc), then B = Z^T F */
  memset(F, 0, sizeof(double) * (size_t)n6 * (ncol + 1));
  double tref = phm_model_tref(m, time, NULL);
  int j = 0;
  for (int i = 0; i < nports; i++) {
    const phm_linear_port *p = &ports[i];
    if (p->kind == PHM_PORT_PAIR) {
      int ip = p->index, k = m->pair_k[ip];
      const phm_pair_desc *pr = &m->pair[ip];
      phm_pair_data pd;
      phm_pair_evaluate(m, ip, pr->a >= 0 ? R.H + 16 * pr->a : NULL, pr->b >= 0 ? R.H + 16 * pr->b : NULL,
                        NULL, NULL, NULL, time, tref, PHM_PAIR_JOINT, &pd);
      for (int c = 0; c < k; c++, j++) {
        double u[6] = {0};
        u[c] = 1.0;
        phm_pair_effort_wrench(m, ip, &pd, u, F + (size_t)j * n6);
      }
    } else if (p->kind == PHM_PORT_LOAD) {
      double w[6], wre[6];
      phm_load_wrench(m, p->index, R.H, 1.0, F + (size_t)j * n6, w, wre);
      j++;
    } else { /* a wrench (tau, f) in the frame's axes at its origin: Ad_{T^-1}^T w on the carrier */
      double Ti[16], A[36];
      phm_se3_inverse(p->T, Ti);
      phm_se3_Ad(Ti, A);
      for (int c = 0; c < 6; c++, j++)
        for (int r = 0; r < 6; r++) F[(size_t)j * n6 + 6 * p->index + r] = A[6 * c + r];
    }
  }
  for (int c = 0; c < ncol; c++) {
    lin_red_project(&R, nc, F + (size_t)c * n6, y);
    for (int a = 0; a < n; a++) B[(size_t)a * ncol + c] = y[a];
  }
  if (!phm_all_finite(B, (size_t)n * ncol)) {
    st = PHM_FAIL(err, PHM_ESOLVER, "linear model: non-finite input matrix");
    goto done;
  }
  if (comp) {
    int nz = m->nz;
    Zd = malloc(sizeof(double) * 24 * (size_t)n);
    f6 = malloc(sizeof(double) * 12 * (size_t)nc);
    zero = malloc(sizeof(double) * (size_t)(nz + 1));
    if (!Zd || !f6 || !zero) {
      st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
      goto done;
    }
    linear_components(&R, m, comp, Zd, Zd + 12 * (size_t)n, f6, zero);
    if (comp->G) {
      memset(comp->G, 0, sizeof(double) * (size_t)n * n);
      if (R.Gr) memcpy(comp->G, R.Gr, sizeof(double) * (size_t)n * n);
    }
    if (!phm_all_finite(comp->Kc, (size_t)n * n) || !phm_all_finite(comp->Dc, (size_t)n * n) ||
        !phm_all_finite(comp->Kz, (size_t)n * nz) || !phm_all_finite(comp->Fq, (size_t)n * nz) ||
        !phm_all_finite(comp->Fv, (size_t)n * nz) || !phm_all_finite(comp->Fz, (size_t)nz * nz)) {
      st = PHM_FAIL(err, PHM_ESOLVER, "linear model: the components' linearized laws are not "
                    "finite at this point");
      goto done;
    }
  }
  *nr = n;
done:
  lin_red_free(&R);
  free(F); free(y); free(Zd); free(f6); free(zero);
  return st;
}
