/* modes_sparse.c -- the modes of large models (docs/method.md section 7.2): subspace iteration
 * with shift-invert on the sparse KKT system [K - sigma M, G^T; G, 0] (csrc/analyze/linearize.c,
 * O(N) per iteration), its result checked against the count of eigenvalues below the shift (the
 * KKT matrix's inertia) and the spectrum sliced when eigenvalues were missed; phm_modes_count. */
#include "analyze.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"

/* y = B x for the block-sparse B (36 per slot of the carrier graph ptr/nbr), x and y of 6 nc. */
static void block_mv(int nc, const int *ptr, const int *nbr, const double *B, const double *x,
                     double *y) {
  for (int r = 0; r < nc; r++) {
    double acc[6] = {0};
    for (int q = ptr[r]; q < ptr[r + 1]; q++) {
      const double *Bq = B + 36 * (size_t)q, *xc = x + 6 * nbr[q];
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) acc[i] += Bq[6 * i + j] * xc[j];
    }
    memcpy(y + 6 * r, acc, sizeof acc);
  }
}

/* y = M x for the mass blocks of L (carriers' inertias, consistent elements' couplings). */
static void mass_mv(const lin_t *L, const double *x, double *y) {
  block_mv(L->m->nc, L->ptr, L->nbr, L->Mb, x, y);
}

/* W_j = (K - sigma M)^-1 M V_j for the b columns of V (6 nc each; W may be V) through the
 * factored KKT system, equilibrated: S's matrix is diag(sc) KKT diag(sc). The solution
 * satisfies G W_j = 0. rhs: scratch of 6 nc + nk. */
static phm_status apply_op(const lin_t *L, lin_kkt_t *S, const double *sc, const double *V,
                           double *W, int b, int n6, int nk, double *rhs, phm_error *err) {
  for (int j = 0; j < b; j++) {
    mass_mv(L, V + (size_t)j * n6, rhs);
    for (int i = 0; i < n6; i++) rhs[i] *= sc[i];
    memset(rhs + n6, 0, sizeof(double) * (size_t)nk);
    if (lin_kkt_solve(S, rhs)) return PHM_FAIL(err, PHM_ESOLVER, "modes: KLU solve failed");
    for (int i = 0; i < n6; i++) W[(size_t)j * n6 + i] = sc[i] * rhs[i];
  }
  return PHM_OK;
}

/* The sparse path's state: K symmetrized blockwise (as the dense path symmetrizes its reduced
 * matrices), the constraint blocks, the KKT matrix [K - sigma M, G^T; G, 0] at the current shift
 * sigma (KLU, O(N) per solve) and its LDL' factorization for the inertia. */
typedef struct {
  const phm_model *m;
  lin_t *L;
  const double *Ksym0; /* K symmetrized (36 per graph slot) */
  double *Ks, *Gp;     /* K - sigma M + Aug (the KKT matrix's block), constraint blocks */
  double *Aug;         /* sum over constraint rows of rho_r g_r^T g_r (36 per graph slot) */
  double *sc, *work;   /* the symmetric scaling of the factored matrix (lin_kkt_equilibrate) */
  lin_kkt_t S;
  lin_ldl_t F;
  double sigma, scale; /* the current shift; tr K / tr M (its unit) */
  int below;           /* eigenvalues below sigma on the constraint manifold, -1: not counted */
  double check;        /* the count's certificate (lin_ldl_negative): trusted below
                        * PHM_INERTIA_CHECK */
} sparse_t;

static void sparse_free(sparse_t *P) {
  lin_kkt_free(&P->S);
  lin_ldl_free(&P->F);
  free((double *)P->Ksym0); free(P->Ks); free(P->Gp); free(P->Aug);
  free(P->sc); free(P->work);
}

static phm_status sparse_init(sparse_t *P, const phm_model *m, lin_t *L, const double *H,
                              const double *Kb, phm_error *err) {
  int nc = m->nc, nk = m->ncons, nb = L->ptr[nc];
  const int *ptr = L->ptr, *nbr = L->nbr;
  memset(P, 0, sizeof *P);
  P->m = m;
  P->L = L;
  double *Ksym = malloc(sizeof(double) * 36 * (size_t)nb);
  P->Ksym0 = Ksym;
  P->Ks = malloc(sizeof(double) * 36 * (size_t)nb);
  P->Gp = malloc(sizeof(double) * 12 * (size_t)(nk + 1));
  P->Aug = calloc(36 * (size_t)nb + 1, sizeof(double));
  double *Lm = malloc(sizeof(double) * 36 * (size_t)(nc + 1));
  if (!Ksym || !P->Ks || !P->Gp || !P->Aug || !Lm) {
    free(Lm);
    return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  }
  double trK = 0, trM = 0;
  for (int r = 0; r < nc; r++)
    for (int q = ptr[r]; q < ptr[r + 1]; q++) {
      int c = nbr[q], qt = lin_slot(L, c, r); /* found: the graph is symmetric */
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++)
          Ksym[36 * (size_t)q + 6 * i + j] = 0.5 * (Kb[36 * (size_t)q + 6 * i + j] + Kb[36 * (size_t)qt + 6 * j + i]);
      if (c == r)
        for (int i = 0; i < 6; i++) { trK += Ksym[36 * (size_t)q + 7 * i]; trM += L->Mb[36 * (size_t)q + 7 * i]; }
    }
  P->scale = trK > 0 && trM > 0 ? trK / trM : 1e9;
  if (nk) lin_constraint_blocks(L, H, P->Gp);
  /* The augmented Lagrangian [K - sigma M + G^T R G, G^T; G, 0] = T^T KKT T, T = [I, 0; R G / 2,
   * I]: the same inertia and the same solutions (G x = 0), but the constrained directions of a
   * body with no stiffness of its own (a rigid body's translations) are no longer pivots of
   * size |sigma| m in the LDL' factorization, which eliminates the carriers first. Row r weighs
   * rho_r = s m_r: m_r = 1 / (g_r M_d^-1 g_r^T) its effective mass (M_d: the carriers' own mass
   * blocks), s = |tr K| / tr M (else 1): a constrained direction about as stiff as the model's
   * average. The count's certificate at shifts -1e-9 .. -1 (rad/s)^2, with / without it (both
   * equilibrated, sparse_shift): a hanging chain of 60 rigid bars beside an inverted pendulum
   * 1.5e-8 / 0.25, an upright chain of 60 bars 1.1e-8 / 0.17, the Table I cantilever (60
   * elements) carrying an inverted pendulum 1.7e-10 / 0.022. */
  double s = trM > 0 && fabs(trK) > 0 ? fabs(trK) / trM : 1.0;
  int singular_mass = 0;
  for (int c = 0; c < nc; c++) {
    singular_mass |= phm_chol6(L->Mb + 36 * (size_t)lin_slot(L, c, c), 0.0, 0.0, Lm + 36 * (size_t)c);
  }
  for (int ip = 0; ip < m->np && !singular_mass; ip++) {
    int cr[2] = {m->pair[ip].a, m->pair[ip].b};
    for (int r = m->pair_row[ip]; r < m->pair_row[ip] + m->pair_m[ip]; r++) {
      const double *g = P->Gp + 12 * (size_t)r;
      double den = 0;
      for (int side = 0; side < 2; side++) {
        if (cr[side] < 0) continue;
        double x[6];
        memcpy(x, g + 6 * side, sizeof x);
        phm_chol6_solve(Lm + 36 * (size_t)cr[side], x);
        den += phm_dot(g + 6 * side, x, 6);
      }
      if (!(den > 0)) continue;
      double rho = s / den;
      for (int si = 0; si < 2; si++)
        for (int sj = 0; sj < 2; sj++) {
          if (cr[si] < 0 || cr[sj] < 0) continue;
          int q = lin_slot(L, cr[si], cr[sj]);
          if (q < 0) continue; /* not reached: a pair's carriers are neighbours */
          for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++)
              P->Aug[36 * (size_t)q + 6 * i + j] += rho * g[6 * si + i] * g[6 * sj + j];
        }
    }
  }
  free(Lm);
  phm_status st = lin_kkt_build(&P->S, L, err);
  if (st) return st;
  P->sc = malloc(sizeof(double) * (size_t)P->S.n);
  P->work = malloc(sizeof(double) * (size_t)P->S.n);
  if (!P->sc || !P->work) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  return lin_ldl_analyze(&P->F, L, &P->S, err);
}

/* Factor the KKT matrix at the shift sigma and count the eigenvalues below it (P->below, with
 * its certificate P->check): PHM_OK, or PHM_ESINGULAR when it is singular or nearly (dependent
 * constraint rows at this configuration, or sigma on an eigenvalue). */
static phm_status sparse_shift(sparse_t *P, double sigma) {
  size_t n = 36 * (size_t)P->L->ptr[P->m->nc];
  for (size_t i = 0; i < n; i++) P->Ks[i] = P->Ksym0[i] - sigma * P->L->Mb[i] + P->Aug[i];
  P->sigma = sigma;
  P->below = -1;
  P->check = INFINITY;
  /* equilibrated (a congruence: the same inertia): unscaled, the constraint rows' eigenvalues of
   * the KKT matrix (about -|g|^2 / k beside stiffnesses k) make the condition estimate 1e24 and
   * the certificate 1e6 .. 3e7 on the Table I cantilever (60 elements; 2e-10 scaled) */
  lin_kkt_values(&P->S, P->Ks, P->Gp);
  lin_kkt_equilibrate(&P->S, P->sc, P->work);
  if (lin_kkt_refactor(&P->S) || !klu_rcond(P->S.sym, P->S.num, &P->S.common) ||
      !(P->S.common.rcond > 1e-15))
    return PHM_ESINGULAR;
  /* Sylvester: inertia(KKT) = inertia(Z^T (K - sigma M) Z) + (nk positive, nk negative) for
   * the nk independent constraint rows (Haynsworth; Z: the null space of G) */
  int neg = lin_ldl_negative(&P->F, &P->S, &P->check);
  if (neg >= P->m->ncons) P->below = neg - P->m->ncons;
  else P->check = INFINITY;
  return PHM_OK;
}

/* Y = W made M-orthonormal (modified Gram-Schmidt, twice), MY = M Y: b columns of n6. */
static phm_status m_orthonormalize(const lin_t *L, const double *W, double *Y, double *MY, int b,
                                   int n6, phm_error *err) {
  memcpy(Y, W, sizeof(double) * (size_t)n6 * b);
  for (int j = 0; j < b; j++) {
    double *yj = Y + (size_t)j * n6;
    for (int pass = 0; pass < 2; pass++)
      for (int i = 0; i < j; i++) {
        double s = phm_dot(MY + (size_t)i * n6, yj, n6);
        const double *yi = Y + (size_t)i * n6;
        for (int k = 0; k < n6; k++) yj[k] -= s * yi[k];
      }
    mass_mv(L, yj, MY + (size_t)j * n6);
    double nrm = sqrt(phm_dot(MY + (size_t)j * n6, yj, n6));
    if (!(nrm > 0) || !isfinite(nrm))
      return PHM_FAIL(err, PHM_ESOLVER, "modes: the subspace iteration lost rank (the mass "
                      "matrix is not positive definite on the constraint manifold?)");
    for (int k = 0; k < n6; k++) { yj[k] /= nrm; MY[(size_t)j * n6 + k] /= nrm; }
  }
  return PHM_OK;
}

/* Ritz vectors X = Y Z (Z: the Ritz matrix's eigenvectors, columns of A in the given order) and
 * the next subspace W Z, through S (b columns of n6 each). */
static void ritz_vectors(const double *A, const int *order, const double *Y, double *W, double *X,
                         double *S, int b, int n6) {
  for (int k = 0; k < b; k++) {
    const double *z = A + (size_t)order[k] * b;
    double *xk = X + (size_t)k * n6, *wk = S + (size_t)k * n6;
    memset(xk, 0, sizeof(double) * (size_t)n6);
    memset(wk, 0, sizeof(double) * (size_t)n6);
    for (int j = 0; j < b; j++) {
      const double *yj = Y + (size_t)j * n6, *wj = W + (size_t)j * n6;
      for (int i = 0; i < n6; i++) { xk[i] += z[j] * yj[i]; wk[i] += z[j] * wj[i]; }
    }
  }
  memcpy(W, S, sizeof(double) * (size_t)n6 * b);
}

/* Move the shift towards the lowest eigenvalue when nothing is below it (P->below == 0). The
 * first shift, sigma0 = -1e-9 tr K / tr M, is far below the lowest modes of a fine mesh (tr K /
 * tr M grows as N^2 with the elements' axial stiffness): mode i converges at the rate
 * |lambda_i - sigma| / |lambda_b+1 - sigma| per iteration, 0.93 for a 10 000-element hanging
 * cable (sigma0 -360 (rad/s)^2, its lambda_1 0.14 and lambda_11 28: 391 iterations; 6 at 300
 * elements). lambda_1 <= lam1 = sigma + 1/theta_1 (theta_1 the largest Ritz value of the
 * inverse operator, all positive: Courant-Fischer), so tau = -max(4 lam1, 1e-3 |sigma0|) stays
 * below zero and the lowest mode, within 5 lam1 of it; the floor keeps rigid-body modes at zero
 * 1e-12 tr K / tr M away from the shift (1e-3 of the first shift's distance). Taken when tau is
 * closer to zero than sigma / 10 and certified at tau with nothing below it; otherwise the
 * factorization at sigma is restored. *moved = 1 when the shift moved. Returns PHM_OK, or
 * PHM_ESOLVER when the factorization at sigma could not be restored (P is then unusable). */
static phm_status sparse_reshift(sparse_t *P, double sigma0, double theta1, int *moved,
                                 phm_error *err) {
  double sigma = P->sigma;
  *moved = 0;
  if (P->below != 0 || !(theta1 > 0)) return PHM_OK;
  double lam1 = sigma + 1.0 / theta1;
  if (!(lam1 > 0)) return PHM_OK;
  double tau = -fmax(4.0 * lam1, 1e-3 * fabs(sigma0));
  if (!(tau > 0.1 * sigma)) return PHM_OK;
  if (!sparse_shift(P, tau) && P->below == 0 && P->check < PHM_INERTIA_CHECK) {
    *moved = 1;
    return PHM_OK;
  }
  /* factored there before: the same factors, count and certificate */
  if (sparse_shift(P, sigma))
    return PHM_FAIL(err, PHM_ESOLVER, "modes: the KKT matrix at the shift %.6g (rad/s)^2, "
                    "factored there before, could not be factored again after a trial shift to "
                    "%.6g (rad/s)^2", sigma, tau);
  return PHM_OK;
}

/* The lowest nf modes by subspace iteration with shift-invert on the constraint manifold at
 * P's shift sigma (sparse_shift): Y = (K - sigma M)^-1 M X through the KKT system (Y satisfies
 * G Y = 0), Y made M-orthonormal, then Rayleigh-Ritz on the inverse operator. A block of b
 * vectors (phm_modes: max(2 nf, nf + 8), at most half the manifold) converges to the b
 * eigenvalues nearest sigma, mode i at the rate |lambda_i - sigma|/|lambda_b+1 - sigma| per
 * iteration, and holds repeated eigenvalues (up to b of them) that one Krylov vector would miss.
 * They are returned ascending: those below sigma first. *nbelow: how many of the block's Ritz
 * values are below sigma; the result is the nf lowest of the whole spectrum when that is
 * P->below, the number of eigenvalues below sigma (then the block holds them all, and the
 * nearest above). With `reshift`, when nothing is below sigma, the shift moves towards zero as
 * the iteration goes (sparse_reshift). stats: its iterations added, its moves of the shift
 * and its last shift set. Returns PHM_OK or an error. */
static phm_status modes_sparse(sparse_t *P, const double *Db, int nf, int b, int reshift,
                               double *omega, double *zeta, double *shapes, int *nbelow,
                               phm_modes_stats *stats, phm_error *err) {
  const phm_model *m = P->m;
  lin_t *L = P->L;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk;
  const int *ptr = L->ptr, *nbr = L->nbr;
  double sigma = P->sigma;
  phm_status st = PHM_OK;
  double *X = malloc(sizeof(double) * (size_t)n6 * b), *Y = malloc(sizeof(double) * (size_t)n6 * b);
  double *MY = malloc(sizeof(double) * (size_t)n6 * b), *rhs = malloc(sizeof(double) * (size_t)N);
  double *A = malloc(sizeof(double) * (size_t)b * b), *ev = malloc(sizeof(double) * (size_t)b);
  double *prev = malloc(sizeof(double) * (size_t)b), *t6 = malloc(sizeof(double) * (size_t)n6);
  double *W = malloc(sizeof(double) * (size_t)n6 * b), *ev2 = malloc(sizeof(double) * (size_t)b);
  int *order = malloc(sizeof(int) * (size_t)b);
  double *work = NULL;
  *nbelow = 0;
  if (!X || !Y || !MY || !rhs || !A || !ev || !prev || !t6 || !W || !ev2 || !order) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  int lw = -1, info = 0;
  double wq;
  memset(A, 0, sizeof(double) * (size_t)b * b);
  dsyev_("V", "U", &b, A, &b, ev, &wq, &lw, &info);
  lw = (int)wq + 1;
  work = malloc(sizeof(double) * (size_t)lw);
  if (!work) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  unsigned long long rng = 88172645463325252ULL; /* deterministic start */
  for (size_t i = 0; i < (size_t)n6 * b; i++) {
    rng ^= rng << 13; rng ^= rng >> 7; rng ^= rng << 17;
    W[i] = (double)(rng >> 11) / 9007199254740992.0 - 0.5;
  }
  for (int j = 0; j < b; j++) prev[j] = INFINITY;
  if ((st = apply_op(L, &P->S, P->sc, W, W, b, n6, nk, rhs, err))) goto done; /* W = Op(random) */
  int converged = 0, settled = 0, shifts = 0;
  const double sigma0 = sigma;
  int it = 0;
  for (; it < 1000 && !converged; it++) {
    /* Y = W, M-orthonormal (modified Gram-Schmidt, twice) */
    if ((st = m_orthonormalize(L, W, Y, MY, b, n6, err))) goto done;
    /* W = (K - sigma M)^-1 M Y; T = Y^T M W has the eigenvalues theta = 1/(lambda - sigma), the
     * wanted (smallest) lambda the largest |theta|: relative accuracy where it matters */
    if ((st = apply_op(L, &P->S, P->sc, Y, W, b, n6, nk, rhs, err))) goto done;
    for (int j = 0; j < b; j++)
      for (int i = 0; i <= j; i++) {
        double tij = 0.5 * (phm_dot(MY + (size_t)i * n6, W + (size_t)j * n6, n6) +
                            phm_dot(MY + (size_t)j * n6, W + (size_t)i * n6, n6));
        A[(size_t)j * b + i] = A[(size_t)i * b + j] = tij;
      }
    dsyev_("V", "U", &b, A, &b, ev, work, &lw, &info);
    if (info != 0) {
      st = PHM_FAIL(err, PHM_ESOLVER, "modes: Rayleigh-Ritz eigenproblem failed (dsyev info %d)", info);
      goto done;
    }
    /* order by lambda = sigma + 1/theta ascending: theta < 0 (lambda below sigma) first, then
     * theta > 0 from the largest down; dsyev gave theta ascending */
    int np_ = 0;
    for (int k = b - 1; k >= 0; k--) if (ev[k] < 0) order[np_++] = k;  /* theta -> 0-: lambda -> -inf */
    for (int k = b - 1; k >= 0; k--) if (ev[k] >= 0) order[np_++] = k;
    /* converged: the wanted theta settle to 1e-12, or to their round-off floor (1e-15 of the
     * largest |theta|, which the Ritz matrix resolves in absolute terms) */
    converged = it > settled;
    double thmax = fmax(fabs(ev[0]), fabs(ev[b - 1]));
    for (int k = 0; k < nf; k++) {
      double th = ev[order[k]];
      if (!(fabs(th - prev[k]) <= 1e-12 * fabs(th) + 1e-15 * thmax)) converged = 0;
      prev[k] = th;
    }
    /* Ritz vectors X = Y Z (ordered) and the next subspace W Z (MY reused as scratch) */
    ritz_vectors(A, order, Y, W, X, MY, b, n6);
    for (int k = 0; k < b; k++) ev2[k] = ev[order[k]];
    int moved = 0;
    if (reshift && !converged && shifts < 3 &&
        (st = sparse_reshift(P, sigma0, ev[order[0]], &moved, err)))
      goto done;
    if (moved) {
      sigma = P->sigma;
      shifts++;
      settled = it + 1; /* the next iteration's theta are the new operator's: none to compare */
      for (int j = 0; j < b; j++) prev[j] = INFINITY;
    }
  }
  stats->iterations += it;
  stats->reshifts += shifts;
  stats->shift = sigma;
  if (!converged) {
    st = PHM_FAIL(err, PHM_ESOLVER, "modes: subspace iteration did not converge in 1000 iterations");
    goto done;
  }
  for (int k = 0; k < nf; k++) {
    double lamk = sigma + 1.0 / ev2[k];
    const double *xk = X + (size_t)k * n6;
    omega[k] = lamk >= 0 ? sqrt(lamk) : -sqrt(-lamk);
    if (zeta) {
      block_mv(nc, ptr, nbr, Db, xk, t6);
      zeta[k] = omega[k] > 0 ? phm_dot(xk, t6, n6) / (2 * omega[k]) : 0.0;
    }
    if (shapes) memcpy(shapes + (size_t)k * n6, xk, sizeof(double) * (size_t)n6);
  }
  for (int k = 0; k < b; k++) *nbelow += ev2[k] < 0;
done:
  free(X); free(Y); free(MY); free(rhs); free(A); free(ev); free(prev);
  free(t6); free(work); free(W); free(ev2); free(order);
  return st;
}

/* The nf lowest modes on the sparse path, verified by the count of eigenvalues below the shift
 * (sparse_shift): shift-invert at sigma = -1e-9 tr K / tr M (just below zero: K - sigma M is
 * nonsingular for rigid-body modes) converges to the eigenvalues nearest sigma, and they are the
 * lowest when its block holds every eigenvalue below sigma. *ok = 1 then. Otherwise (an
 * unstable mode farther from the shift than the stable ones, or more unstable modes than the
 * block holds) with `slice`: the shift is lowered by factors of 10 until the count below it is
 * 0, raised again by bisection (while it stays 0), and shift-invert there finds the k - nb
 * lowest eigenvalues that the first iteration missed (k below sigma, nb of them found); they
 * come first, then the first iteration's modes (those nearest sigma, where they are accurate:
 * from the lower shift, the modes near zero converged slowly and to ~1e-12 |lambda - tau|). An
 * uncertified count is an error. Without `slice`, *ok = 0: the caller takes the dense path.
 * PHM_ESINGULAR (no message): the KKT matrix at sigma is singular. */
phm_status modes_sparse_path(lin_red_t *R, const phm_model *m, int nf, int b, int slice,
                              double *omega, double *zeta, double *shapes, int *ok,
                              phm_modes_stats *stats, phm_error *err) {
  sparse_t P;
  int nb = 0, n6 = 6 * m->nc;
  double *oB = NULL, *zB = NULL, *sB = NULL;
  *ok = 0;
  phm_status st = sparse_init(&P, m, &R->L, R->H, R->L.Kb, err);
  if (st || (st = sparse_shift(&P, -1e-9 * P.scale))) goto done;
  double sigma = P.sigma;
  stats->shift0 = stats->shift = sigma;
  int below = P.below;
  double check = P.check;
  if (below >= 0 && check < PHM_INERTIA_CHECK && below < b) {
    if ((st = modes_sparse(&P, R->Db, nf, b, 1, omega, zeta, shapes, &nb, stats, err))) goto done;
    if (nb == below) {
      *ok = 1;
      goto done;
    }
  }
  if (!slice) goto done;
  if (!(check < PHM_INERTIA_CHECK)) {
    st = PHM_FAIL(err, PHM_ESOLVER, "modes: the sparse path could not verify its result: the "
                  "count of eigenvalues below its shift is uncertain (LDL' residual x condition "
                  "estimate %.3g, must be < %g); the dense method (or a slightly different "
                  "configuration) may answer", check, PHM_INERTIA_CHECK);
    goto done;
  }
  if (nb > below) { /* not at convergence (interlacing): a Ritz value on an eigenvalue at sigma */
    st = PHM_FAIL(err, PHM_ESOLVER, "modes: the sparse path's iteration found %d eigenvalues below "
                  "its shift %.6g (rad/s)^2, its count %d; the dense method may answer", nb, sigma,
                  below);
    goto done;
  }
  /* spectrum slicing: lo with nothing below it, hi with something */
  double lo = 0, hi = sigma;
  int found = 0;
  for (int k = 1; k <= 40 && !found; k++) {
    double tau = sigma * pow(10.0, k);
    if (sparse_shift(&P, tau)) continue; /* on an eigenvalue: further down */
    if (!(P.check < PHM_INERTIA_CHECK)) break;
    if (P.below == 0) { lo = tau; found = 1; }
    else hi = tau;
  }
  for (int k = 0; k < 4 && found; k++) {
    double tau = -sqrt(lo * hi);
    /* failed: lo and hi unchanged, the next tau the same, so the same failure */
    if (sparse_shift(&P, tau) || !(P.check < PHM_INERTIA_CHECK)) break;
    if (P.below == 0) lo = tau;
    else hi = tau;
  }
  /* (P holds lo's factorization already when the last shift tried was lo) */
  if (!found || (P.sigma != lo && sparse_shift(&P, lo)) || !(P.check < PHM_INERTIA_CHECK) ||
      P.below != 0) {
    st = PHM_FAIL(err, PHM_ESOLVER, "modes: the sparse path found %d eigenvalues below its shift "
                  "%.6g (rad/s)^2 and its iteration %d, and no lower shift with none below it "
                  "could be certified; the dense method may answer", below, sigma, nb);
    goto done;
  }
  /* the nB lowest from there, before the first iteration's nf - nB (its nb below sigma, the
   * least negative, then those above) */
  int nB = below - nb < nf ? below - nb : nf, nbB = 0;
  oB = malloc(sizeof(double) * (size_t)nf);
  zB = zeta ? malloc(sizeof(double) * (size_t)nf) : NULL;
  sB = shapes ? malloc(sizeof(double) * (size_t)nf * n6) : NULL;
  if (!oB || (zeta && !zB) || (shapes && !sB)) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  if ((st = modes_sparse(&P, R->Db, nB, b, 0, oB, zB, sB, &nbB, stats, err))) goto done;
  if (nbB != 0) {
    st = PHM_FAIL(err, PHM_ESOLVER, "modes: the subspace iteration at the shift %.6g (rad/s)^2, "
                  "below every eigenvalue, returned %d below it", lo, nbB);
    goto done;
  }
  int keep = nf - nB; /* > 0 only when the first iteration ran (below < b, nf < b) */
  memmove(omega + nB, omega, sizeof(double) * (size_t)keep);
  memcpy(omega, oB, sizeof(double) * (size_t)nB);
  if (zeta) {
    memmove(zeta + nB, zeta, sizeof(double) * (size_t)keep);
    memcpy(zeta, zB, sizeof(double) * (size_t)nB);
  }
  if (shapes) {
    memmove(shapes + (size_t)nB * n6, shapes, sizeof(double) * (size_t)keep * n6);
    memcpy(shapes, sB, sizeof(double) * (size_t)nB * n6);
  }
  *ok = 1;
done:
  sparse_free(&P);
  free(oB); free(zB); free(sB);
  return st;
}

phm_status phm_modes_count(const phm_model *m, const double *poses, const double *lambda,
                           double time, double shift, int *below, double *check, phm_error *err) {
  phm_error_clear(err);
  if (!m || !below || !check) return PHM_FAIL(err, PHM_EINVAL, "phm_modes_count: NULL argument");
  PHM_CHECK(isfinite(shift), err, PHM_EINVAL, "modes count: the shift must be finite (got %g)", shift);
  *below = -1;
  *check = INFINITY;
  lin_red_t R;
  sparse_t P;
  memset(&R, 0, sizeof R);
  memset(&P, 0, sizeof P);
  phm_status st = lin_red_blocks(&R, m, poses, lambda, time, err);
  if (!st) st = sparse_init(&P, m, &R.L, R.H, R.L.Kb, err);
  if (!st && sparse_shift(&P, shift))
    st = PHM_FAIL(err, PHM_ESINGULAR, "modes count: the KKT matrix [K - shift M, G^T; G, 0] is "
                  "singular at shift %g (an eigenvalue there, or dependent constraint rows)", shift);
  if (!st && P.below < 0)
    st = PHM_FAIL(err, PHM_ESINGULAR, "modes count: the LDL' factorization of the KKT matrix met a "
                  "zero pivot, or fewer negative pivots than constraint rows, at shift %g", shift);
  if (!st) {
    *below = P.below;
    *check = P.check;
  }
  sparse_free(&P);
  lin_red_free(&R);
  return st;
}
