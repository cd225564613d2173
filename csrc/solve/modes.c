/* modes.c -- linearized modes (docs/method.md section 7): stiffness and damping blocks on the
 * tangent space (csrc/solve/linearize.c); then, for small models, the lowest eigenpairs of the
 * dense reduced problem on the null space of the constraint Jacobian (LAPACK dsygvx), and for
 * large ones subspace iteration on the sparse KKT system (O(N) per iteration). */
#include "solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"

/* ---------------------------------------------------------------- large models: sparse modes */
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

/* y = M x for the block-diagonal mass (6x6 per carrier). */
static void mass_mv(const phm_model *m, const double *x, double *y) {
  for (int c = 0; c < m->nc; c++) phm_mv6(m->car[c].M, x + 6 * c, y + 6 * c);
}

/* W_j = (K - sigma M)^-1 M V_j for the b columns of V (6 nc each; W may be V) through the
 * factored KKT system: the solution satisfies G W_j = 0. rhs: scratch of 6 nc + nk. */
static phm_status apply_op(const phm_model *m, lin_kkt_t *S, const double *V, double *W, int b,
                           int n6, int nk, double *rhs, phm_error *err) {
  for (int j = 0; j < b; j++) {
    mass_mv(m, V + (size_t)j * n6, rhs);
    memset(rhs + n6, 0, sizeof(double) * (size_t)nk);
    if (lin_kkt_solve(S, rhs)) return PHM_FAIL(err, PHM_ESOLVER, "modes: KLU solve failed");
    memcpy(W + (size_t)j * n6, rhs, sizeof(double) * (size_t)n6);
  }
  return PHM_OK;
}

/* The lowest nf modes by subspace iteration with shift-invert on the constraint manifold:
 * Y = (K - sigma M)^-1 M X through the KKT system [K - sigma M, G^T; G, 0] (KLU, O(N) per
 * solve; Y satisfies G Y = 0), Y made M-orthonormal, then Rayleigh-Ritz on the inverse
 * operator (K symmetrized blockwise, as the dense path symmetrizes its reduced matrices). A block of
 * b = max(2 nf, nf + 8) vectors converges mode i at the rate (lambda_i - sigma)/(lambda_b+1 -
 * sigma) per iteration and holds repeated eigenvalues (up to b of them) that one Krylov vector
 * would miss. sigma < 0 keeps K - sigma M nonsingular for rigid-body modes. Returns PHM_OK,
 * PHM_ESINGULAR when the KKT matrix is singular (the caller then takes the dense path), or an
 * error. */
static phm_status modes_sparse(const phm_model *m, lin_t *L, const double *H, const double *Kb,
                               const double *Db, int nf, double *omega, double *zeta,
                               double *shapes, phm_error *err) {
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk, nb = L->ptr[nc];
  const int *ptr = L->ptr, *nbr = L->nbr;
  int b = 2 * nf > nf + 8 ? 2 * nf : nf + 8;
  if (b > n6 / 2) b = n6 / 2;
  phm_status st = PHM_OK;
  lin_kkt_t S;
  memset(&S, 0, sizeof S);
  double *Ks = malloc(sizeof(double) * 36 * (size_t)nb), *Gp = malloc(sizeof(double) * 12 * (size_t)(nk + 1));
  double *X = malloc(sizeof(double) * (size_t)n6 * b), *Y = malloc(sizeof(double) * (size_t)n6 * b);
  double *MY = malloc(sizeof(double) * (size_t)n6 * b), *rhs = malloc(sizeof(double) * (size_t)N);
  double *A = malloc(sizeof(double) * (size_t)b * b), *ev = malloc(sizeof(double) * (size_t)b);
  double *prev = malloc(sizeof(double) * (size_t)b), *t6 = malloc(sizeof(double) * (size_t)n6);
  double *W = malloc(sizeof(double) * (size_t)n6 * b), *ev2 = malloc(sizeof(double) * (size_t)b);
  int *order = malloc(sizeof(int) * (size_t)b);
  double *work = NULL;
  if (!Ks || !Gp || !X || !Y || !MY || !rhs || !A || !ev || !prev || !t6 || !W || !ev2 || !order) {
    st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
    goto done;
  }
  /* K symmetrized blockwise, the shift */
  double trK = 0, trM = 0;
  for (int r = 0; r < nc; r++)
    for (int q = ptr[r]; q < ptr[r + 1]; q++) {
      int c = nbr[q], qt = ptr[c];
      while (nbr[qt] != r) qt++; /* slot (c, r): the graph is symmetric */
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++)
          Ks[36 * (size_t)q + 6 * i + j] = 0.5 * (Kb[36 * (size_t)q + 6 * i + j] + Kb[36 * (size_t)qt + 6 * j + i]);
      if (c == r)
        for (int i = 0; i < 6; i++) { trK += Ks[36 * (size_t)q + 7 * i]; trM += m->car[r].M[7 * i]; }
    }
  double sigma = trK > 0 && trM > 0 ? -1e-9 * trK / trM : -1.0;
  for (int r = 0; r < nc; r++)
    for (int q = ptr[r]; q < ptr[r + 1]; q++)
      if (nbr[q] == r)
        for (int i = 0; i < 36; i++) Ks[36 * (size_t)q + i] -= sigma * m->car[r].M[i];
  if (nk) lin_constraint_blocks(L, H, Gp);
  if ((st = lin_kkt_build(&S, L, err))) goto done;
  /* singular or nearly (dependent constraint rows at this configuration): the caller falls back
   * to the dense path, whose SVD finds the rank; no message */
  if (lin_kkt_factor(&S, Ks, Gp) || !klu_rcond(S.sym, S.num, &S.common) || !(S.common.rcond > 1e-15)) {
    st = PHM_ESINGULAR;
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
  if ((st = apply_op(m, &S, W, W, b, n6, nk, rhs, err))) goto done; /* W = Op(random) */
  int converged = 0;
  for (int it = 0; it < 1000 && !converged; it++) {
    /* Y = W, M-orthonormal (modified Gram-Schmidt, twice) */
    memcpy(Y, W, sizeof(double) * (size_t)n6 * b);
    for (int j = 0; j < b; j++) {
      double *yj = Y + (size_t)j * n6;
      for (int pass = 0; pass < 2; pass++)
        for (int i = 0; i < j; i++) {
          double s = phm_dot(MY + (size_t)i * n6, yj, n6);
          const double *yi = Y + (size_t)i * n6;
          for (int k = 0; k < n6; k++) yj[k] -= s * yi[k];
        }
      mass_mv(m, yj, MY + (size_t)j * n6);
      double nrm = sqrt(phm_dot(MY + (size_t)j * n6, yj, n6));
      if (!(nrm > 0) || !isfinite(nrm)) {
        st = PHM_FAIL(err, PHM_ESOLVER, "modes: the subspace iteration lost rank (the mass "
                      "matrix is not positive definite on the constraint manifold?)");
        goto done;
      }
      for (int k = 0; k < n6; k++) { yj[k] /= nrm; MY[(size_t)j * n6 + k] /= nrm; }
    }
    /* W = (K - sigma M)^-1 M Y; T = Y^T M W has the eigenvalues theta = 1/(lambda - sigma), the
     * wanted (smallest) lambda the largest |theta|: relative accuracy where it matters */
    if ((st = apply_op(m, &S, Y, W, b, n6, nk, rhs, err))) goto done;
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
    for (int k = 0; k < b; k++) if (ev[k] < 0) order[np_++] = k;
    for (int k = b - 1; k >= 0; k--) if (ev[k] >= 0) order[np_++] = k;
    /* converged: the wanted theta settle to 1e-12, or to their round-off floor (1e-15 of the
     * largest |theta|, which the Ritz matrix resolves in absolute terms) */
    converged = it > 0;
    double thmax = fmax(fabs(ev[0]), fabs(ev[b - 1]));
    for (int k = 0; k < nf; k++) {
      double th = ev[order[k]];
      if (!(fabs(th - prev[k]) <= 1e-12 * fabs(th) + 1e-15 * thmax)) converged = 0;
      prev[k] = th;
    }
    /* Ritz vectors X = Y Z (ordered) and the next subspace W Z */
    for (int k = 0; k < b; k++) {
      const double *z = A + (size_t)order[k] * b;
      double *xk = X + (size_t)k * n6, *wk = MY + (size_t)k * n6; /* MY reused as scratch */
      memset(xk, 0, sizeof(double) * (size_t)n6);
      memset(wk, 0, sizeof(double) * (size_t)n6);
      for (int j = 0; j < b; j++) {
        const double *yj = Y + (size_t)j * n6, *wj = W + (size_t)j * n6;
        for (int i = 0; i < n6; i++) { xk[i] += z[j] * yj[i]; wk[i] += z[j] * wj[i]; }
      }
    }
    memcpy(W, MY, sizeof(double) * (size_t)n6 * b);
    for (int k = 0; k < b; k++) ev2[k] = ev[order[k]];
  }
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
done:
  lin_kkt_free(&S);
  free(Ks); free(Gp); free(X); free(Y); free(MY); free(rhs); free(A); free(ev); free(prev);
  free(t6); free(work); free(W); free(ev2); free(order);
  return st;
}

/* Structure: the stiffness K = -df/ddelta and damping D = -df/dt are block-sparse (only
 * neighbouring carriers couple) and computed by coloured differences; the constraint Jacobian G
 * touches only the carriers of the pairs, so the null-space basis is Z = diag(U0, I): U0 from the
 * SVD of G restricted to the constrained carriers, identity on the free ones. The reduced problem
 * Kr y = omega^2 Mr y is solved for the lowest modes only (dsygvx). */
phm_status phm_modes(const phm_model *m, const double *poses, const double *lambda, double time,
                     int nmodes, int method, double *omega, double *zeta, double *shapes,
                     int *nfound, phm_error *err) {
  phm_error_clear(err);
  if (!m || !omega || !nfound) return PHM_FAIL(err, PHM_EINVAL, "phm_modes: NULL argument");
  if (nmodes < 1) return PHM_FAIL(err, PHM_EINVAL, "number of modes must be >= 1 (got %d)", nmodes);
  PHM_CHECK(method >= PHM_MODES_AUTO && method <= PHM_MODES_SPARSE, err, PHM_EINVAL,
            "unknown modes method %d (0 auto, 1 dense, 2 sparse)", method);
  *nfound = 0;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons;
  phm_status st = PHM_OK;
  lin_t L = {0};
  int *cmap = NULL, *clist = NULL, *red = NULL;
  int *iwork = NULL, *ifail = NULL;
  double *H = malloc(sizeof(double) * 16 * (size_t)nc);
  double *f0 = malloc(sizeof(double) * (size_t)n6), *f1 = malloc(sizeof(double) * (size_t)n6);
  double *f2 = malloc(sizeof(double) * (size_t)n6), *tw = calloc((size_t)n6, sizeof(double));
  double *Db = NULL, *Gc = NULL, *U = NULL, *sv = NULL, *work = NULL;
  double *Kr = NULL, *Mr = NULL, *Dr = NULL, *ev = NULL, *Y = NULL;
  if (!H || !f0 || !f1 || !f2 || !tw) goto oom;
  if ((st = lin_alloc(&L, m, err)) || (st = lin_colour(&L, err))) goto done;
  const int *ptr = L.ptr, *nbr = L.nbr, *col = L.col, ncol = L.ncol;
  double *Kb = L.Kb;
  int nb = ptr[nc];
  Db = calloc((size_t)nb * 36, sizeof(double));
  if (!Db) goto oom;
  L.time = time;
  L.tref = phm_model_tref(m, time, NULL);
  L.scale = 1.0;
  L.lam = lambda;
  for (int c = 0; c < nc; c++) memcpy(H + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  /* stiffness K = -d f / d delta, block-sparse */
  lin_force_jacobian_blocks(&L, H, f1, f2);
  for (size_t i = 0; i < (size_t)nb * 36; i++) Kb[i] = -Kb[i];
  /* damping D = -dw/dt: the elements' in closed form (lin_closed_form_blocks), the rest (linear in
   * t) by one-sided differences, exact up to round-off */
  phm_applied_pairs(m, NULL, H, tw, NULL, time, L.tref, 1.0, 1, f0, NULL, NULL, NULL, NULL, NULL);
  for (int k = 0; k < ncol; k++)
    for (int j = 0; j < 6; j++) {
      for (int c = 0; c < nc; c++) tw[6 * c + j] = col[c] == k ? 1.0 : 0.0;
      phm_applied_pairs(m, NULL, H, tw, NULL, time, L.tref, 1.0, 1, f2, NULL, NULL, NULL, NULL, NULL);
      for (int c = 0; c < nc; c++) tw[6 * c + j] = 0.0;
      for (int r = 0; r < nc; r++)
        for (int q = ptr[r]; q < ptr[r + 1]; q++)
          if (col[nbr[q]] == k)
            for (int i = 0; i < 6; i++) Db[36 * (size_t)q + 6 * i + j] = f2[6 * r + i] - f0[6 * r + i];
    }
  lin_closed_form_blocks(&L, H, NULL, Db);
  for (size_t i = 0; i < (size_t)nb * 36; i++) Db[i] = -Db[i];
  int sparse = method == PHM_MODES_SPARSE || (method == PHM_MODES_AUTO && n6 >= PHM_SPARSE_MODES_MIN);
  if (sparse && 4 * nmodes <= n6 - nk) {
    st = modes_sparse(m, &L, H, Kb, Db, nmodes, omega, zeta, shapes, err);
    if (st == PHM_OK) {
      *nfound = nmodes;
      goto done;
    }
    if (st != PHM_ESINGULAR) goto done;
    if (method == PHM_MODES_SPARSE) {
      st = PHM_FAIL(err, PHM_ESINGULAR, "modes: the KKT matrix [K - sigma M, G^T; G, 0] is singular "
                    "(dependent constraint rows at this configuration?); the dense method handles it");
      goto done;
    }
    st = PHM_OK; /* singular KKT matrix (dependent constraint rows here): the dense path below */
  }
  /* constrained carriers and the null space of G restricted to them */
  cmap = malloc(sizeof(int) * (size_t)nc);
  clist = malloc(sizeof(int) * (size_t)(nc + 1));
  if (!cmap || !clist) goto oom;
  int ncc = 0;
  for (int c = 0; c < nc; c++) cmap[c] = -1;
  if (nk > 0)
    for (int ip = 0; ip < m->np; ip++) {
      int ab[2] = {m->pair[ip].a, m->pair[ip].b};
      for (int s = 0; s < 2; s++)
        if (ab[s] >= 0 && cmap[ab[s]] < 0) { cmap[ab[s]] = ncc; clist[ncc++] = ab[s]; }
    }
  int n6c = 6 * ncc, rank = 0, n0 = n6c;
  if (nk > 0 && n6c > 0) {
    Gc = malloc(sizeof(double) * (size_t)n6c * nk); /* column-major G^T: n6c x nk */
    U = malloc(sizeof(double) * (size_t)n6c * n6c);
    sv = malloc(sizeof(double) * (size_t)(nk < n6c ? nk : n6c) + sizeof(double));
    if (!Gc || !U || !sv) goto oom;
    /* row-major G over the constrained carriers' columns: column-major G^T for dgesvd */
    phm_constraints_columns(m, H, NULL, time, L.tref, cmap, n6c, NULL, Gc, NULL);
    int lw = -1, info = 0, one = 1;
    double wq;
    dgesvd_("A", "N", &n6c, &nk, Gc, &n6c, sv, U, &n6c, NULL, &one, &wq, &lw, &info);
    lw = (int)wq + 1;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work) goto oom;
    dgesvd_("A", "N", &n6c, &nk, Gc, &n6c, sv, U, &n6c, NULL, &one, work, &lw, &info);
    free(work);
    work = NULL;
    if (info != 0) {
      st = PHM_FAIL(err, PHM_ESINGULAR, "SVD of the constraint Jacobian failed (dgesvd info %d)", info);
      goto done;
    }
    int ns = nk < n6c ? nk : n6c;
    for (int i = 0; i < ns; i++)
      if (sv[i] > 1e-10 * sv[0]) rank++;
    n0 = n6c - rank;
  }
  /* reduced coordinates: first the n0 null-space directions of the constrained carriers (U0 =
   * columns rank.. of U), then 6 per free carrier in carrier order (red[c]: first index) */
  red = malloc(sizeof(int) * (size_t)nc);
  if (!red) goto oom;
  int nr = n0;
  for (int c = 0; c < nc; c++) {
    red[c] = cmap[c] < 0 ? nr : -1;
    if (cmap[c] < 0) nr += 6;
  }
  if (nr == 0) {
    st = PHM_FAIL(err, PHM_EINVAL, "the mechanism has no degree of freedom: no modes");
    goto done;
  }
  Kr = calloc((size_t)nr * nr, sizeof(double));
  Mr = calloc((size_t)nr * nr, sizeof(double));
  Dr = calloc((size_t)nr * nr, sizeof(double));
  ev = malloc(sizeof(double) * (size_t)nr);
  if (!Kr || !Mr || !Dr || !ev) goto oom;
  const double *U0 = U ? U + (size_t)rank * n6c : NULL; /* column a of U0: U0[a * n6c + i] */
  /* X_r = Z^T X Z block by block; (Kr, Dr) from the blocks, Mr from the block-diagonal mass */
  for (int w = 0; w < 3; w++) {
    double *out = w == 0 ? Kr : w == 1 ? Dr : Mr;
    for (int r = 0; r < nc; r++)
      for (int q = ptr[r]; q < ptr[r + 1]; q++) {
        int c = nbr[q];
        const double *B;
        if (w < 2) B = (w == 0 ? Kb : Db) + 36 * (size_t)q;
        else if (c == r) B = m->car[c].M;
        else continue;
        if (red[r] >= 0 && red[c] >= 0) {
          for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) out[(size_t)(red[r] + i) * nr + red[c] + j] += B[6 * i + j];
        } else if (red[r] >= 0) { /* row free, column constrained: B U0 */
          int c6 = 6 * cmap[c];
          for (int i = 0; i < 6; i++)
            for (int a = 0; a < n0; a++) {
              double s = 0;
              for (int j = 0; j < 6; j++) s += B[6 * i + j] * U0[(size_t)a * n6c + c6 + j];
              out[(size_t)(red[r] + i) * nr + a] += s;
            }
        } else if (red[c] >= 0) { /* row constrained: U0^T B */
          int r6 = 6 * cmap[r];
          for (int a = 0; a < n0; a++)
            for (int j = 0; j < 6; j++) {
              double s = 0;
              for (int i = 0; i < 6; i++) s += U0[(size_t)a * n6c + r6 + i] * B[6 * i + j];
              out[(size_t)a * nr + red[c] + j] += s;
            }
        } else { /* both constrained: U0^T B U0 */
          int r6 = 6 * cmap[r], c6 = 6 * cmap[c];
          for (int b = 0; b < n0; b++) {
            double BU[6];
            for (int i = 0; i < 6; i++) {
              double s = 0;
              for (int j = 0; j < 6; j++) s += B[6 * i + j] * U0[(size_t)b * n6c + c6 + j];
              BU[i] = s;
            }
            for (int a = 0; a < n0; a++) {
              double s = 0;
              for (int i = 0; i < 6; i++) s += U0[(size_t)a * n6c + r6 + i] * BU[i];
              out[(size_t)a * nr + b] += s;
            }
          }
        }
      }
    for (int a = 0; a < nr; a++)
      for (int b = 0; b < a; b++) {
        double s = 0.5 * (out[(size_t)a * nr + b] + out[(size_t)b * nr + a]);
        out[(size_t)a * nr + b] = out[(size_t)b * nr + a] = s;
      }
  }
  if (!phm_all_finite(Kr, (size_t)nr * nr) || !phm_all_finite(Mr, (size_t)nr * nr) ||
      !phm_all_finite(Dr, (size_t)nr * nr)) {
    st = PHM_FAIL(err, PHM_ESOLVER, "modes: the linearized stiffness, damping or mass is not "
                       "finite: the model's numbers overflow double precision");
    goto done;
  }
  int nf = nmodes < nr ? nmodes : nr, mfound = 0;
  Y = malloc(sizeof(double) * (size_t)nr * nf);
  iwork = malloc(sizeof(int) * 5 * (size_t)nr);
  ifail = malloc(sizeof(int) * (size_t)nr);
  if (!Y || !iwork || !ifail) goto oom;
  {
    int one = 1, lw = -1, info = 0;
    double wq, vl = 0, vu = 0, abstol = 2 * dlamch_("S");
    dsygvx_(&one, "V", "I", "U", &nr, Kr, &nr, Mr, &nr, &vl, &vu, &one, &nf, &abstol, &mfound, ev,
            Y, &nr, &wq, &lw, iwork, ifail, &info);
    lw = (int)wq + 1;
    if (lw < 8 * nr) lw = 8 * nr;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work) goto oom;
    dsygvx_(&one, "V", "I", "U", &nr, Kr, &nr, Mr, &nr, &vl, &vu, &one, &nf, &abstol, &mfound, ev,
            Y, &nr, work, &lw, iwork, ifail, &info);
    if (info != 0 || mfound < nf) {
      st = PHM_FAIL(err, PHM_ESINGULAR, "generalized eigenproblem failed (dsygvx info %d, %d of "
                         "%d eigenvalues found%s)", info, mfound, nf,
                         info > nr ? ": mass matrix not positive definite" : "");
      goto done;
    }
  }
  for (int k = 0; k < nf; k++) {
    double lamk = ev[k];
    omega[k] = lamk >= 0 ? sqrt(lamk) : -sqrt(-lamk);
    const double *yk = Y + (size_t)k * nr; /* column-major: eigenvector k is contiguous */
    if (zeta) {
      double s = 0;
      for (int a = 0; a < nr; a++) {
        double t = 0;
        for (int b = 0; b < nr; b++) t += Dr[(size_t)a * nr + b] * yk[b];
        s += yk[a] * t;
      }
      zeta[k] = omega[k] > 0 ? s / (2 * omega[k]) : 0.0;
    }
    if (shapes)
      for (int c = 0; c < nc; c++)
        for (int i = 0; i < 6; i++) {
          double s = 0;
          if (red[c] >= 0) s = yk[red[c] + i];
          else
            for (int a = 0; a < n0; a++) s += U0[(size_t)a * n6c + 6 * cmap[c] + i] * yk[a];
          shapes[(size_t)k * n6 + 6 * c + i] = s;
        }
  }
  if (!phm_all_finite(omega, (size_t)nf) || (zeta && !phm_all_finite(zeta, (size_t)nf)) ||
      (shapes && !phm_all_finite(shapes, (size_t)nf * n6))) {
    st = PHM_FAIL(err, PHM_ESOLVER, "modes: non-finite frequencies, damping ratios or mode "
                       "shapes: the model's numbers overflow double precision");
    goto done;
  }
  *nfound = nf;
  goto done;
oom:
  st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
done:
  lin_free(&L);
  free(cmap); free(clist); free(red);
  free(iwork); free(ifail);
  free(H); free(f0); free(f1); free(f2); free(tw);
  free(Db); free(Gc); free(U); free(sv); free(work);
  free(Kr); free(Mr); free(Dr); free(ev); free(Y);
  return st;
}
