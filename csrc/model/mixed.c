/* mixed.c -- Golo's mixed finite element for the linear planar Timoshenko beam (docs/method.md
 * section 4.8).
 *
 * References: Golo, Talasila, van der Schaft, Maschke, "Hamiltonian discretization of boundary
 * control systems", Automatica 40 (2004) (the paper's [51]); Bassi, Macchelli, Melchiorri (2006)
 * for 1-D systems with a zero-order term ([52]); Macchelli, Stramigioli, Melchiorri (2007) for the
 * flexible link ([49]).
 *
 * PDE (port-Hamiltonian form, s in [0, L]); energy variables per unit length
 *   p_t = rhoA w_t, eps = w_s - phi, p_r = rhoI phi_t, kappa = phi_s;
 * co-energy variables v = p_t/rhoA, Qs = kGA eps, omega = p_r/rhoI, M = EI kappa:
 *   d/dt p_t   = d/ds Qs            d/dt eps   = d/ds v - omega
 *   d/dt p_r   = d/ds M + Qs        d/dt kappa = d/ds omega
 * i.e. two conservation-law pairs (p_t, eps) <-> (v, Qs) and (p_r, kappa) <-> (omega, M) plus the
 * skew zero-order coupling (omega into eps, Qs into p_r). dH/dt = [v Qs + omega M]_0^L.
 *
 * Derivation of one element [a, b], h = b - a (Golo's mixed element):
 *  1. Energy variables (1-forms) are constant on the element: p_t(s) = P_t/h etc., so the state
 *     is x = (P_t, E_s, P_r, K), the integrals over the element; H_e = x^T Q_e x / 2 with
 *     Q_e = diag(1/(rhoA h), kGA/h, 1/(rhoI h), EI/h), and the element efforts
 *     e = Q_e x = (v_e, Qs_e, omega_e, M_e).
 *  2. Co-energy variables (0-forms) are linear: v(s) = v_a (b-s)/h + v_b (s-a)/h, etc. Integrating
 *     the PDE over the element is then exact:
 *       P_t' = Qs_b - Qs_a,  E_s' = v_b - v_a - int omega,  P_r' = M_b - M_a + int Qs,  K' = om_b - om_a.
 *  3. The element efforts are tied to the nodal values by Golo's weights; power consistency of the
 *     conservation-law pairs requires the complementary weights alpha and 1 - alpha:
 *       v_e = alpha v_a + (1-alpha) v_b,       omega_e = alpha omega_a + (1-alpha) omega_b,
 *       Qs_e = (1-alpha) Qs_a + alpha Qs_b,    M_e = (1-alpha) M_a + alpha M_b.
 *     Then v_e (Qs_b - Qs_a) + Qs_e (v_b - v_a) = v_b Qs_b - v_a Qs_a for every alpha. alpha = 1/2
 *     (the paper's element) is the symmetric choice, where the element effort is the mean of the
 *     linear interpolant. The zero-order terms are taken as h omega_e and h Qs_e; for alpha = 1/2
 *     this IS the exact integral of the linear interpolant (h (Qs_a + Qs_b)/2), for other alpha it
 *     is the power-consistent (skew) choice of [52].
 *  4. Causality: one effort of each conjugate pair is an input at each end. The inputs are the
 *     flows (v_a, omega_a) at the left node and the forces (Qs_b, M_b) at the right node, so that
 *     with beta = 1/(1-alpha), d = alpha beta:
 *       v_b = beta v_e - d v_a,  omega_b = beta omega_e - d omega_a,
 *       Qs_a = beta Qs_e - d Qs_b,  M_a = beta M_e - d M_b,
 *     and the element is x' = J_e e + B_e u, y = B_e^T e + D_e u with
 *       u = (v_a, omega_a, Qs_b, M_b), y = (-Qs_a, -M_a, v_b, omega_b) (u^T y = power in),
 *       J_e = [[0,-beta,0,0],[beta,0,-h,0],[0,h,0,-beta],[0,0,beta,0]],
 *       B_e = [[0,0,beta,0],[-beta,0,0,0],[0,0,0,beta],[0,-beta,0,0]],
 *       D_e: D[0][2] = d, D[2][0] = -d, D[1][3] = d, D[3][1] = -d (skew feedthrough).
 *  5. Chain: element k spans nodes k, k+1; the velocities propagate left to right
 *     (v_{k+1} = beta v_e^k - d v_k from v_0), the forces right to left
 *     (Qs_k = beta Qs_e^k - d Qs_{k+1} from Qs_N), so the interconnection has no algebraic loop:
 *       v_k = sum_{j<k} beta (-d)^(k-1-j) v_e^j + (-d)^k v_0,
 *       Qs_k = sum_{j>=k} beta (-d)^(j-k) Qs_e^j + (-d)^(N-k) Qs_N.
 *     For alpha = 1/2 (d = 1) these are alternating sums; for alpha > 1/2 (d > 1) they grow like
 *     d^N, which is why alpha > 1/2 is refused once d^N > 1e6.
 */
#include "linalg.h"
#include "phm_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


static int pos_finite(double x) { return isfinite(x) && x > 0.0; }

phm_status phm_mixed_check(const phm_mixed_beam *b, phm_error *err) {
  if (!b) return PHM_FAIL(err, PHM_EINVAL, "mixed beam: NULL parameters");
  if (b->N < 1 || b->N > PHM_MIXED_NMAX)
    return PHM_FAIL(err, PHM_EINVAL, "mixed beam: N = %d elements, need 1 <= N <= %d", b->N,
                         PHM_MIXED_NMAX);
  const double v[5] = {b->L, b->EI, b->kGA, b->rhoA, b->rhoI};
  const char *nm[5] = {"L", "EI", "kGA", "rhoA", "rhoI"};
  for (int i = 0; i < 5; i++)
    if (!pos_finite(v[i]))
      return PHM_FAIL(err, PHM_EINVAL, "mixed beam: %s = %g must be finite and > 0", nm[i],
                           v[i]);
  if (!isfinite(b->alpha) || b->alpha < 0.0 || b->alpha >= 1.0)
    return PHM_FAIL(err, PHM_EINVAL, "mixed beam: alpha = %g, need 0 <= alpha < 1", b->alpha);
  return PHM_OK;
}

phm_status phm_mixed_bc_from_name(const char *name, phm_mixed_bc *bc, phm_error *err) {
  static const char *names[] = {"clamped-free", "clamped-clamped", "pinned-pinned",
                                "clamped-pinned"};
  if (name)
    for (int i = 0; i < 4; i++)
      if (strcmp(name, names[i]) == 0) {
        *bc = (phm_mixed_bc)i;
        return PHM_OK;
      }
  return PHM_FAIL(err, PHM_EINVAL,
                       "mixed beam: unknown boundary condition '%s' (expected clamped-free, "
                       "clamped-clamped, pinned-pinned or clamped-pinned)",
                       name ? name : "(null)");
}

void phm_mixed_bc_ports(phm_mixed_bc bc, int c[4]) {
  /* ports: u = (v(0), omega(0), Qs(L), M(L)); 1 = the conjugate output is constrained to 0. */
  c[0] = 0; /* v(0) = 0 in every supported case */
  c[1] = 0;
  c[2] = 0;
  c[3] = 0;
  switch (bc) {
  case PHM_MIXED_CLAMPED_FREE: break;                 /* omega(0) = 0, Qs(L) = M(L) = 0 */
  case PHM_MIXED_CLAMPED_CLAMPED: c[2] = c[3] = 1; break; /* v(L) = omega(L) = 0        */
  case PHM_MIXED_PINNED_PINNED: c[1] = c[2] = 1; break;   /* M(0) = 0; v(L) = 0, M(L) = 0 */
  case PHM_MIXED_CLAMPED_PINNED: c[2] = 1; break;         /* v(L) = 0, M(L) = 0          */
  }
}

phm_status phm_mixed_element(double h, double EI, double kGA, double rhoA, double rhoI,
                             double alpha, double J[16], double Q[16], double B[16], double D[16],
                             phm_error *err) {
  phm_mixed_beam b = {1, h, EI, kGA, rhoA, rhoI, alpha};
  phm_status st = phm_mixed_check(&b, err);
  if (st) return st;
  const double beta = 1.0 / (1.0 - alpha), d = alpha * beta;
  if (J) {
    memset(J, 0, 16 * sizeof *J);
    J[0 * 4 + 1] = -beta;
    J[1 * 4 + 0] = beta;
    J[1 * 4 + 2] = -h;
    J[2 * 4 + 1] = h;
    J[2 * 4 + 3] = -beta;
    J[3 * 4 + 2] = beta;
  }
  if (Q) {
    memset(Q, 0, 16 * sizeof *Q);
    Q[0] = 1.0 / (rhoA * h);
    Q[5] = kGA / h;
    Q[10] = 1.0 / (rhoI * h);
    Q[15] = EI / h;
  }
  if (B) {
    memset(B, 0, 16 * sizeof *B);
    B[0 * 4 + 2] = beta;  /* P_t' += beta Qs_b   */
    B[1 * 4 + 0] = -beta; /* E_s' -= beta v_a    */
    B[2 * 4 + 3] = beta;  /* P_r' += beta M_b    */
    B[3 * 4 + 1] = -beta; /* K'   -= beta om_a   */
  }
  if (D) {
    memset(D, 0, 16 * sizeof *D);
    D[0 * 4 + 2] = d;
    D[2 * 4 + 0] = -d;
    D[1 * 4 + 3] = d;
    D[3 * 4 + 1] = -d;
  }
  return PHM_OK;
}

phm_status phm_mixed_assemble(const phm_mixed_beam *beam, double *J, double *Q, double *B,
                              double *D, phm_error *err) {
  phm_status st = phm_mixed_check(beam, err);
  if (st) return st;
  const int N = beam->N, n = 4 * N;
  const double h = beam->L / N, beta = 1.0 / (1.0 - beam->alpha), d = beam->alpha * beta;
  double *pw = malloc((size_t)(N + 1) * sizeof *pw); /* pw[m] = (-d)^m */
  if (!pw) return PHM_FAIL(err, PHM_ENOMEM, "mixed beam: out of memory");
  pw[0] = 1.0;
  for (int m = 1; m <= N; m++) pw[m] = -d * pw[m - 1];
  /* alpha > 1/2: the node recursion amplifies by d = alpha/(1-alpha) > 1 per element; refuse
   * once d^N would swamp the O(1) entries in round-off (relative accuracy ~ 1e-16 d^N). */
  const double growth = fabs(pw[N]);
  if (!isfinite(growth) || growth > 1e6) {
    free(pw);
    return PHM_FAIL(err, PHM_EINVAL,
                         "mixed beam: alpha = %g with N = %d is ill-conditioned: the node "
                         "recursion grows like (alpha/(1-alpha))^N = %.3g > 1e6; use alpha <= 1/2 "
                         "or fewer elements",
                         beam->alpha, N, growth);
  }
  const size_t nn = (size_t)n * (size_t)n;
  if (Q) {
    memset(Q, 0, nn * sizeof *Q);
    for (int k = 0; k < N; k++) {
      const size_t i = (size_t)4 * k;
      Q[(i + 0) * n + i + 0] = 1.0 / (beam->rhoA * h);
      Q[(i + 1) * n + i + 1] = beam->kGA / h;
      Q[(i + 2) * n + i + 2] = 1.0 / (beam->rhoI * h);
      Q[(i + 3) * n + i + 3] = beam->EI / h;
    }
  }
  /* Coefficient of element j's flow-type effort in the nodal value at node k (j < k), and of
   * element j's force-type effort in the nodal force at node k (j >= k); see header comment. */
#define VC(k, j) ((j) < (k) ? beta * pw[(k) - 1 - (j)] : 0.0)
#define FC(k, j) ((j) >= (k) && (j) < N ? beta * pw[(j) - (k)] : 0.0)
  if (J) {
    memset(J, 0, nn * sizeof *J);
    for (int k = 0; k < N; k++) {
      double *rPt = J + (size_t)(4 * k + 0) * n, *rEs = J + (size_t)(4 * k + 1) * n;
      double *rPr = J + (size_t)(4 * k + 2) * n, *rK = J + (size_t)(4 * k + 3) * n;
      for (int j = 0; j < N; j++) {
        const double f = FC(k + 1, j) - FC(k, j), v = VC(k + 1, j) - VC(k, j);
        rPt[4 * j + 1] = f; /* Qs_{k+1} - Qs_k      */
        rPr[4 * j + 3] = f; /* M_{k+1} - M_k        */
        rEs[4 * j + 0] = v; /* v_{k+1} - v_k        */
        rK[4 * j + 2] = v;  /* om_{k+1} - om_k      */
      }
      rEs[4 * k + 2] -= h; /* - h omega_e */
      rPr[4 * k + 1] += h; /* + h Qs_e    */
    }
  }
  if (B) {
    memset(B, 0, (size_t)n * 4 * sizeof *B);
    for (int k = 0; k < N; k++) {
      const double vin = pw[k + 1] - pw[k];         /* v_0 in v_{k+1} - v_k       */
      const double fin = pw[N - k - 1] - pw[N - k]; /* Qs_N in Qs_{k+1} - Qs_k    */
      B[(size_t)(4 * k + 0) * 4 + 2] = fin;
      B[(size_t)(4 * k + 1) * 4 + 0] = vin;
      B[(size_t)(4 * k + 2) * 4 + 3] = fin;
      B[(size_t)(4 * k + 3) * 4 + 1] = vin;
    }
  }
  if (D) {
    /* y = (-Qs_0, -M_0, v_N, om_N): -Qs_0 contains -(-d)^N Qs_N, v_N contains (-d)^N v_0. */
    memset(D, 0, 16 * sizeof *D);
    D[0 * 4 + 2] = -pw[N];
    D[1 * 4 + 3] = -pw[N];
    D[2 * 4 + 0] = pw[N];
    D[3 * 4 + 1] = pw[N];
  }
#undef VC
#undef FC
  free(pw);
  return PHM_OK;
}

/* Orthonormalize column c of the n x 4 array U (row stride 4) against columns 0..k-1 (modified
 * Gram-Schmidt, two passes); returns 1 if it was independent and was normalized into column k. */
static int mgs_column(double *U, int n, int k, const double *v) {
  for (int i = 0; i < n; i++) U[(size_t)i * 4 + k] = v[i];
  for (int pass = 0; pass < 2; pass++)
    for (int m = 0; m < k; m++) {
      double dot = 0.0;
      for (int i = 0; i < n; i++) dot += U[(size_t)i * 4 + m] * U[(size_t)i * 4 + k];
      for (int i = 0; i < n; i++) U[(size_t)i * 4 + k] -= dot * U[(size_t)i * 4 + m];
    }
  double nrm = 0.0;
  for (int i = 0; i < n; i++) nrm += U[(size_t)i * 4 + k] * U[(size_t)i * 4 + k];
  nrm = sqrt(nrm);
  if (!(nrm > 0.0)) return 0;
  for (int i = 0; i < n; i++) U[(size_t)i * 4 + k] /= nrm;
  return 1;
}

/* X <- X - U (U^T X) for the m x m matrix X whose entry (a, b) is C[a rs + b cs]: C itself
 * (rs = m, cs = 1) or its transpose (rs = 1, cs = m: then C <- C - (C U) U^T, the same sums in
 * the same order); U m x k (row stride 4), W scratch of m x 4. */
static void project_out(double *C, size_t rs, size_t cs, int m, const double *U, int k, double *W) {
  for (int j = 0; j < m; j++)
    for (int q = 0; q < k; q++) {
      double acc = 0.0;
      for (int i = 0; i < m; i++) acc += U[(size_t)i * 4 + q] * C[(size_t)i * rs + (size_t)j * cs];
      W[(size_t)j * 4 + q] = acc;
    }
  for (int i = 0; i < m; i++)
    for (int j = 0; j < m; j++) {
      double acc = 0.0;
      for (int q = 0; q < k; q++) acc += U[(size_t)i * 4 + q] * W[(size_t)j * 4 + q];
      C[(size_t)i * rs + (size_t)j * cs] -= acc;
    }
}

/* C <- (I - Ul Ul^T) C (I - Ur Ur^T), C m x m row-major, Ul m x kl, Ur m x kr (row stride 4),
 * W scratch of m x 4. */
static void project(double *C, int m, const double *Ul, int kl, const double *Ur, int kr,
                    double *W) {
  if (kr > 0) project_out(C, 1, (size_t)m, m, Ur, kr, W); /* C <- C - (C Ur) Ur^T */
  if (kl > 0) project_out(C, (size_t)m, 1, m, Ul, kl, W); /* C <- C - Ul (Ul^T C) */
}

/* Frequencies. With z = S x, S = Q^1/2, the closed chain is z' = A z + G lambda, A = S J S skew,
 * G^T z = 0 for the constrained ports (G = S B_c). J only couples momenta (P_t, P_r) with strains
 * (E_s, K), so in the ordering z = (z_p, z_q) A = [[0, C], [-C^T, 0]] with C (2N x 2N), and the
 * constraint directions lie either in momentum space (ports Qs(L), M(L)) or in strain space
 * (ports v(0), omega(0)). On the constraint subspace the dynamics is z' = P A P z with
 * P = diag(P_p, P_q), still of that form with C_c = P_p C P_q; its eigenvalues are +-i sigma for
 * the singular values sigma of C_c (the exact zeros belong to the constraint directions and to
 * rigid-body modes). Singular values (dgesvd) of the 2N x 2N block are cheaper and more accurate
 * than a general eigensolver on the 4N x 4N skew matrix. */
phm_status phm_mixed_frequencies(const phm_mixed_beam *beam, phm_mixed_bc bc, int nfreq,
                                 double *omega, phm_error *err) {
  phm_status st = phm_mixed_check(beam, err);
  if (st) return st;
  if ((int)bc < 0 || (int)bc > 3) return PHM_FAIL(err, PHM_EINVAL, "mixed beam: bad bc");
  const int N = beam->N, n = 4 * N, m = 2 * N;
  if (nfreq < 1 || nfreq > m)
    return PHM_FAIL(err, PHM_EINVAL, "mixed beam: %d frequencies requested, need 1..%d",
                         nfreq, m);
  if (!omega) return PHM_FAIL(err, PHM_EINVAL, "mixed beam: NULL output");
  int con[4];
  phm_mixed_bc_ports(bc, con);

  const size_t nn = (size_t)n * (size_t)n;
  double *J = malloc(nn * sizeof *J), *C = malloc((size_t)m * m * sizeof *C);
  double *Qm = malloc(nn * sizeof *Qm), *B = malloc((size_t)n * 4 * sizeof *B);
  double *Up = malloc((size_t)m * 4 * sizeof *Up), *Uq = malloc((size_t)m * 4 * sizeof *Uq);
  double *W = malloc((size_t)m * 4 * sizeof *W), *v = malloc((size_t)m * sizeof *v);
  double *s = malloc((size_t)n * sizeof *s), *sv = malloc((size_t)m * sizeof *sv), *work = NULL;
  if (!J || !C || !Qm || !B || !Up || !Uq || !W || !v || !s || !sv) {
    st = PHM_FAIL(err, PHM_ENOMEM, "mixed beam: out of memory (N = %d)", N);
    goto done;
  }
  st = phm_mixed_assemble(beam, J, Qm, B, NULL, err);
  if (st) goto done;
  for (int i = 0; i < n; i++) s[i] = sqrt(Qm[(size_t)i * n + i]);
  /* momentum r of element k: state 4k + 2(r%2)... i.e. index map ip(i) = 4(i/2) + 2(i%2);
   * strain: iq(j) = 4(j/2) + 2(j%2) + 1. */
#define IP(i) (4 * ((i) / 2) + 2 * ((i) % 2))
#define IQ(j) (4 * ((j) / 2) + 2 * ((j) % 2) + 1)
  for (int i = 0; i < m; i++)
    for (int j = 0; j < m; j++)
      C[(size_t)i * m + j] = s[IP(i)] * J[(size_t)IP(i) * n + IQ(j)] * s[IQ(j)];
  int kp = 0, kq = 0;
  for (int c = 0; c < 4; c++) {
    if (!con[c]) continue;
    if (c < 2) { /* v(0), omega(0): B column in strain rows */
      for (int j = 0; j < m; j++) v[j] = s[IQ(j)] * B[(size_t)IQ(j) * 4 + c];
      kq += mgs_column(Uq, m, kq, v);
    } else { /* Qs(L), M(L): momentum rows */
      for (int i = 0; i < m; i++) v[i] = s[IP(i)] * B[(size_t)IP(i) * 4 + c];
      kp += mgs_column(Up, m, kp, v);
    }
  }
#undef IP
#undef IQ
  project(C, m, Up, kp, Uq, kq, W);

  int lwork = -1, info = 0, one = 1;
  double wq = 0.0, dummy = 0.0;
  dgesvd_("N", "N", &m, &m, C, &m, sv, &dummy, &one, &dummy, &one, &wq, &lwork, &info);
  if (info != 0) {
    st = PHM_FAIL(err, PHM_ESOLVER, "mixed beam: dgesvd workspace query failed (%d)", info);
    goto done;
  }
  lwork = (int)wq;
  if (lwork < 5 * m) lwork = 5 * m;
  work = malloc((size_t)lwork * sizeof *work);
  if (!work) {
    st = PHM_FAIL(err, PHM_ENOMEM, "mixed beam: out of memory");
    goto done;
  }
  dgesvd_("N", "N", &m, &m, C, &m, sv, &dummy, &one, &dummy, &one, work, &lwork, &info);
  if (info != 0) {
    st = PHM_FAIL(err, PHM_ESOLVER, "mixed beam: dgesvd failed to converge (info = %d)", info);
    goto done;
  }
  /* sv is descending; skip the round-off zeros (~ eps sigma_max) of constraint/rigid modes. */
  const double tol = 1e-10 * sv[0];
  int cnt = 0;
  for (int i = m - 1; i >= 0; i--)
    if (sv[i] > tol) s[cnt++] = sv[i];
  if (cnt < nfreq) {
    st = PHM_FAIL(err, PHM_EINVAL,
                       "mixed beam: only %d nonzero frequencies for N = %d with these boundary "
                       "conditions, %d requested",
                       cnt, N, nfreq);
    goto done;
  }
  memcpy(omega, s, (size_t)nfreq * sizeof *omega);
  st = PHM_OK;
done:
  free(J);
  free(C);
  free(Qm);
  free(B);
  free(Up);
  free(Uq);
  free(W);
  free(v);
  free(s);
  free(sv);
  free(work);
  return st;
}
