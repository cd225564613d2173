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

/* y = M x for the mass blocks of L (carriers' inertias, consistent elements' couplings). */
static void mass_mv(const lin_t *L, const double *x, double *y) {
  block_mv(L->m->nc, L->ptr, L->nbr, L->Mb, x, y);
}

/* W_j = (K - sigma M)^-1 M V_j for the b columns of V (6 nc each; W may be V) through the
 * factored KKT system: the solution satisfies G W_j = 0. rhs: scratch of 6 nc + nk. */
static phm_status apply_op(const lin_t *L, lin_kkt_t *S, const double *V, double *W, int b,
                           int n6, int nk, double *rhs, phm_error *err) {
  for (int j = 0; j < b; j++) {
    mass_mv(L, V + (size_t)j * n6, rhs);
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
 * b vectors (phm_modes: max(2 nf, nf + 8), at most half the manifold) converges mode i at the rate (lambda_i - sigma)/(lambda_b+1 - sigma)
 * per iteration and holds repeated eigenvalues (up to b of them) that one Krylov vector would
 * miss. sigma < 0 keeps K - sigma M nonsingular for rigid-body modes. Returns PHM_OK,
 * PHM_ESINGULAR when the KKT matrix is singular (the caller then takes the dense path), or an
 * error. */
static phm_status modes_sparse(const phm_model *m, lin_t *L, const double *H, const double *Kb,
                               const double *Db, int nf, int b, double *omega, double *zeta,
                               double *shapes, phm_error *err) {
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons, N = n6 + nk, nb = L->ptr[nc];
  const int *ptr = L->ptr, *nbr = L->nbr;
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
        for (int i = 0; i < 6; i++) { trK += Ks[36 * (size_t)q + 7 * i]; trM += L->Mb[36 * (size_t)q + 7 * i]; }
    }
  double sigma = trK > 0 && trM > 0 ? -1e-9 * trK / trM : -1.0;
  for (size_t i = 0; i < 36 * (size_t)nb; i++) Ks[i] -= sigma * L->Mb[i];
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
  if ((st = apply_op(L, &S, W, W, b, n6, nk, rhs, err))) goto done; /* W = Op(random) */
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
      mass_mv(L, yj, MY + (size_t)j * n6);
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
    if ((st = apply_op(L, &S, Y, W, b, n6, nk, rhs, err))) goto done;
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

/* ---------------------------------------------------------------- the reduced linear model */
/* The linearization at poses H shared by the modes and the linear port-Hamiltonian model: the
 * stiffness K = -df/ddelta and damping D = -df/dt as blocks on the carrier coupling graph
 * (closed form, csrc/solve/linearize.c), and, for the dense path, their reduction to
 * the null space of the constraint Jacobian G. G touches only the carriers of the pairs, so the
 * null-space basis is Z = diag(U0, I): U0 from the SVD of G restricted to the constrained
 * carriers, identity on the free ones. Reduced coordinates: first the n0 null-space directions
 * of the constrained carriers (U0 = columns rank.. of U), then 6 per free carrier in carrier
 * order (red[c]: first index; -1 for a constrained carrier, cmap[c]: its place among them). */
typedef struct {
  lin_t L;
  double *H, *Db;           /* poses (nc x 16), damping blocks (36 per graph slot); K in L.Kb */
  int *cmap, *red;          /* constrained carriers' places, free carriers' first reduced index */
  int n6c, n0, nr;          /* constrained carriers' coordinates, their null space, reduced size */
  double *U;                /* n6c x n6c, column-major; U0 = U + rank n6c (column a contiguous) */
  const double *U0;
  double *Kr, *Dr, *Mr;     /* reduced stiffness, damping, mass (nr x nr, symmetrized) */
} lin_red_t;

static void lin_red_free(lin_red_t *R) {
  lin_free(&R->L);
  free(R->H); free(R->Db); free(R->cmap); free(R->red); free(R->U);
  free(R->Kr); free(R->Dr); free(R->Mr);
}

/* K and D blocks at poses (NULL: H0) with constraint wrenches lambda (NULL: none), loads at time. */
static phm_status lin_red_blocks(lin_red_t *R, const phm_model *m, const double *poses,
                                 const double *lambda, double time, phm_error *err) {
  int nc = m->nc;
  lin_t *L = &R->L;
  phm_status st;
  if ((st = lin_alloc(L, m, err)) || (st = lin_graph(L, err))) return st;
  int nb = L->ptr[nc];
  R->H = malloc(sizeof(double) * 16 * (size_t)nc);
  R->Db = calloc((size_t)nb * 36, sizeof(double));
  if (!R->H || !R->Db) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  double *H = R->H, *Kb = L->Kb, *Db = R->Db;
  L->time = time;
  L->tref = phm_model_tref(m, time, NULL);
  L->scale = 1.0;
  L->lam = lambda;
  for (int c = 0; c < nc; c++) memcpy(H + 16 * c, poses ? poses + 16 * c : m->car[c].H0, 16 * sizeof(double));
  /* stiffness K = -d f / d delta, block-sparse */
  lin_force_jacobian_blocks(L, H);
  for (size_t i = 0; i < (size_t)nb * 36; i++) Kb[i] = -Kb[i];
  /* damping D = -dw/dt, in closed form (lin_closed_form_blocks; the pairs' wrenches do not
   * depend on the twists) */
  lin_closed_form_blocks(L, H, NULL, Db);
  for (size_t i = 0; i < (size_t)nb * 36; i++) Db[i] = -Db[i];
  return PHM_OK;
}

/* The null space of G and the reduced Kr, Dr, Mr (symmetrized) from the blocks. */
static phm_status lin_red_reduce(lin_red_t *R, const phm_model *m, phm_error *err) {
  int nc = m->nc, nk = m->ncons;
  const int *ptr = R->L.ptr, *nbr = R->L.nbr;
  const double *Kb = R->L.Kb, *Db = R->Db;
  double *Gc = NULL, *sv = NULL, *work = NULL;
  int *clist = NULL;
  phm_status st = PHM_OK;
  R->cmap = malloc(sizeof(int) * (size_t)nc);
  clist = malloc(sizeof(int) * (size_t)(nc + 1));
  if (!R->cmap || !clist) goto oom;
  int *cmap = R->cmap, ncc = 0;
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
    R->U = malloc(sizeof(double) * (size_t)n6c * n6c);
    sv = malloc(sizeof(double) * (size_t)(nk < n6c ? nk : n6c) + sizeof(double));
    if (!Gc || !R->U || !sv) goto oom;
    /* row-major G over the constrained carriers' columns: column-major G^T for dgesvd */
    phm_constraints_columns(m, R->H, NULL, R->L.time, R->L.tref, cmap, n6c, NULL, Gc, NULL);
    int lw = -1, info = 0, one = 1;
    double wq;
    dgesvd_("A", "N", &n6c, &nk, Gc, &n6c, sv, R->U, &n6c, NULL, &one, &wq, &lw, &info);
    lw = (int)wq + 1;
    work = malloc(sizeof(double) * (size_t)lw);
    if (!work) goto oom;
    dgesvd_("A", "N", &n6c, &nk, Gc, &n6c, sv, R->U, &n6c, NULL, &one, work, &lw, &info);
    if (info != 0) {
      st = PHM_FAIL(err, PHM_ESINGULAR, "SVD of the constraint Jacobian failed (dgesvd info %d)", info);
      goto done;
    }
    int ns = nk < n6c ? nk : n6c;
    for (int i = 0; i < ns; i++)
      if (sv[i] > 1e-10 * sv[0]) rank++;
    n0 = n6c - rank;
  }
  R->red = malloc(sizeof(int) * (size_t)nc);
  if (!R->red) goto oom;
  int *red = R->red, nr = n0;
  for (int c = 0; c < nc; c++) {
    red[c] = cmap[c] < 0 ? nr : -1;
    if (cmap[c] < 0) nr += 6;
  }
  R->n6c = n6c;
  R->n0 = n0;
  R->nr = nr;
  if (nr == 0) {
    st = PHM_FAIL(err, PHM_EINVAL, "the mechanism has no degree of freedom: no modes");
    goto done;
  }
  R->Kr = calloc((size_t)nr * nr, sizeof(double));
  R->Mr = calloc((size_t)nr * nr, sizeof(double));
  R->Dr = calloc((size_t)nr * nr, sizeof(double));
  if (!R->Kr || !R->Mr || !R->Dr) goto oom;
  const double *U0 = R->U0 = R->U ? R->U + (size_t)rank * n6c : NULL; /* column a: U0[a * n6c + i] */
  /* X_r = Z^T X Z block by block; (Kr, Dr) from the blocks, Mr from the block-diagonal mass */
  for (int w = 0; w < 3; w++) {
    double *out = w == 0 ? R->Kr : w == 1 ? R->Dr : R->Mr;
    for (int r = 0; r < nc; r++)
      for (int q = ptr[r]; q < ptr[r + 1]; q++) {
        int c = nbr[q];
        const double *B;
        B = (w == 0 ? Kb : w == 1 ? Db : R->L.Mb) + 36 * (size_t)q;
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
  if (!phm_all_finite(R->Kr, (size_t)nr * nr) || !phm_all_finite(R->Mr, (size_t)nr * nr) ||
      !phm_all_finite(R->Dr, (size_t)nr * nr))
    st = PHM_FAIL(err, PHM_ESOLVER, "linearization: the stiffness, damping or mass is not "
                       "finite: the model's numbers overflow double precision");
  goto done;
oom:
  st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
done:
  free(clist); free(Gc); free(sv); free(work);
  return st;
}

/* x = Z y: a reduced vector y (nr) as carrier tangent coordinates x (6 nc). */
static void lin_red_expand(const lin_red_t *R, int nc, const double *y, double *x) {
  for (int c = 0; c < nc; c++)
    for (int i = 0; i < 6; i++) {
      double s = 0;
      if (R->red[c] >= 0) s = y[R->red[c] + i];
      else
        for (int a = 0; a < R->n0; a++) s += R->U0[(size_t)a * R->n6c + 6 * R->cmap[c] + i] * y[a];
      x[6 * c + i] = s;
    }
}

/* y = Z^T f: carrier wrenches f (6 nc) as reduced generalized forces y (nr). */
static void lin_red_project(const lin_red_t *R, int nc, const double *f, double *y) {
  for (int a = 0; a < R->n0; a++) y[a] = 0;
  for (int c = 0; c < nc; c++)
    if (R->red[c] >= 0)
      for (int i = 0; i < 6; i++) y[R->red[c] + i] = f[6 * c + i];
    else
      for (int a = 0; a < R->n0; a++)
        for (int i = 0; i < 6; i++) y[a] += R->U0[(size_t)a * R->n6c + 6 * R->cmap[c] + i] * f[6 * c + i];
}

/* ---------------------------------------------------------------- modes */
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
  lin_red_t R;
  memset(&R, 0, sizeof R);
  int *iwork = NULL, *ifail = NULL;
  double *work = NULL, *ev = NULL, *Y = NULL, *A = NULL, *Bm = NULL, *evi = NULL, *Yi = NULL;
  if ((st = lin_red_blocks(&R, m, poses, lambda, time, err))) goto done;
  int sparse = method == PHM_MODES_SPARSE || (method == PHM_MODES_AUTO && n6 >= PHM_SPARSE_MODES_MIN);
  /* the subspace iteration's block, max(2 nf, nf + 8) vectors, must be at most half the
   * manifold's dimension n6 - nk (the kept rows are independent: redundant ones are dropped): a
   * block beyond it held round-off vectors whose Ritz values (theta ~ -1e-15) came first (a
   * hanging chain of 10 bars with 5 revolute pairs, 60 coordinates: -1.9e8 rad/s for its 2.18
   * rad/s mode), and on a whole-manifold block they never settled ("did not converge in 1000
   * iterations"). Smaller manifolds: dense. */
  int block = 2 * nmodes > nmodes + 8 ? 2 * nmodes : nmodes + 8;
  if (sparse && 2 * block <= n6 - nk) {
    st = modes_sparse(m, &R.L, R.H, R.L.Kb, R.Db, nmodes, block, omega, zeta, shapes, err);
    /* with an unstable mode, shift-invert has found the unstable modes nearest its shift, not
     * necessarily the most unstable (an upright chain of 60 bars: -13.0 rad/s where the lowest
     * is -142.9; docs/validation.md, finding 9): AUTO redoes it densely where that is
     * affordable (PHM_DENSE_MODES_MAX manifold coordinates) */
    int unstable = st == PHM_OK && method == PHM_MODES_AUTO && omega[0] < 0 &&
                   n6 - nk <= PHM_DENSE_MODES_MAX;
    if (st == PHM_OK && !unstable) {
      *nfound = nmodes;
      goto done;
    }
    if (st != PHM_OK && st != PHM_ESINGULAR) goto done;
    if (st == PHM_ESINGULAR && method == PHM_MODES_SPARSE) {
      st = PHM_FAIL(err, PHM_ESINGULAR, "modes: the KKT matrix [K - sigma M, G^T; G, 0] is singular "
                    "(dependent constraint rows at this configuration?); the dense method handles it");
      goto done;
    }
    st = PHM_OK; /* singular KKT matrix (dependent constraint rows here), or unstable: dense below */
  }
  /* dense: the reduced problem Kr y = lambda Mr y (lambda = omega^2), the lowest modes only
   * (dsygvx). Shift-invert first: Mr y = theta (Kr - sigma Mr) y with theta = 1/(lambda - sigma)
   * and sigma < 0 as in the sparse path; its largest theta are the lowest lambda, to relative
   * accuracy eps theta_1 / theta_k, where the direct pencil loses eps ||Mr^-1 Kr|| / lambda_k (a
   * flexible link's axial modes make that 4e-6 on the leaf spring's first bending mode). Modes
   * with theta_k < PHM_MODES_RESOLVED theta_1 (more than 1e6 times the first eigenvalue, or below
   * round-off: a massless direction) and every mode when Kr - sigma Mr is not positive definite
   * (an unstable configuration) come from the direct pencil. */
  if ((st = lin_red_reduce(&R, m, err))) goto done;
  int nr = R.nr, nf = nmodes < nr ? nmodes : nr, mfound = 0, nres = 0;
  ev = malloc(sizeof(double) * (size_t)nr);
  Y = malloc(sizeof(double) * (size_t)nr * nf);
  evi = malloc(sizeof(double) * (size_t)nr);
  Yi = malloc(sizeof(double) * (size_t)nr * nf);
  iwork = malloc(sizeof(int) * 5 * (size_t)nr);
  ifail = malloc(sizeof(int) * (size_t)nr);
  A = malloc(sizeof(double) * (size_t)nr * nr);
  Bm = malloc(sizeof(double) * (size_t)nr * nr);
  if (!ev || !Y || !evi || !Yi || !iwork || !ifail || !A || !Bm) goto oom;
  {
    double trK = 0, trM = 0;
    for (int a = 0; a < nr; a++) { trK += R.Kr[(size_t)a * nr + a]; trM += R.Mr[(size_t)a * nr + a]; }
    double sigma = trK > 0 && trM > 0 ? -1e-9 * trK / trM : -1.0;
    int one = 1, lw = -1, info = 0;
    double wq, vl = 0, vu = 0, abstol = 2 * dlamch_("S");
    for (int inv = 1; inv >= 0; inv--) {
      /* inv: (A, B) = (Mr, Kr - sigma Mr), theta nr-nf+1..nr into evi, Yi; else (Kr, Mr),
       * lambda 1..nf into ev, Y */
      int lo = inv ? nr - nf + 1 : 1, hi = inv ? nr : nf;
      double *e = inv ? evi : ev, *V = inv ? Yi : Y;
      for (int pass = 0; pass < 2; pass++) { /* workspace query, then the solve */
        for (size_t i = 0; i < (size_t)nr * nr; i++) {
          A[i] = inv ? R.Mr[i] : R.Kr[i];
          Bm[i] = inv ? R.Kr[i] - sigma * R.Mr[i] : R.Mr[i];
        }
        if (pass == 0) {
          lw = -1;
          dsygvx_(&one, "V", "I", "U", &nr, A, &nr, Bm, &nr, &vl, &vu, &lo, &hi, &abstol, &mfound,
                  e, V, &nr, &wq, &lw, iwork, ifail, &info);
          lw = (int)wq + 1;
          if (lw < 8 * nr) lw = 8 * nr;
          free(work);
          work = malloc(sizeof(double) * (size_t)lw);
          if (!work) goto oom;
        } else
          dsygvx_(&one, "V", "I", "U", &nr, A, &nr, Bm, &nr, &vl, &vu, &lo, &hi, &abstol, &mfound,
                  e, V, &nr, work, &lw, iwork, ifail, &info);
      }
      if (inv) {
        if (info != 0 || mfound != nf || !(evi[nf - 1] > 0)) continue; /* nres = 0 */
        /* mode k (ascending lambda) is column nf-1-k: lambda = sigma + 1/theta; y^T (Kr - sigma
         * Mr) y = 1, so y^T Mr y = theta: rescaled to unit modal mass */
        for (int k = 0; k < nf / 2; k++) {
          double t = evi[k];
          evi[k] = evi[nf - 1 - k];
          evi[nf - 1 - k] = t;
          for (int a = 0; a < nr; a++) {
            t = Yi[(size_t)k * nr + a];
            Yi[(size_t)k * nr + a] = Yi[(size_t)(nf - 1 - k) * nr + a];
            Yi[(size_t)(nf - 1 - k) * nr + a] = t;
          }
        }
        while (nres < nf && evi[nres] > PHM_MODES_RESOLVED * evi[0]) {
          double sc = 1.0 / sqrt(evi[nres]);
          for (int a = 0; a < nr; a++) Yi[(size_t)nres * nr + a] *= sc;
          evi[nres] = sigma + 1.0 / evi[nres];
          nres++;
        }
        if (nres == nf) break;
      } else if (info != 0 || mfound < nf) {
        st = PHM_FAIL(err, PHM_ESINGULAR, "generalized eigenproblem failed (dsygvx info %d, %d of "
                           "%d eigenvalues found%s)", info, mfound, nf,
                           info > nr ? ": mass matrix not positive definite" : "");
        goto done;
      }
    }
    memcpy(ev, evi, sizeof(double) * (size_t)nres);   /* the resolved modes from the inverse */
    memcpy(Y, Yi, sizeof(double) * (size_t)nres * nr);
  }
  for (int k = 0; k < nf; k++) {
    double lamk = ev[k];
    omega[k] = lamk >= 0 ? sqrt(lamk) : -sqrt(-lamk);
    const double *yk = Y + (size_t)k * nr; /* column-major: eigenvector k is contiguous */
    if (zeta) {
      double s = 0;
      for (int a = 0; a < nr; a++) {
        double t = 0;
        for (int b = 0; b < nr; b++) t += R.Dr[(size_t)a * nr + b] * yk[b];
        s += yk[a] * t;
      }
      zeta[k] = omega[k] > 0 ? s / (2 * omega[k]) : 0.0;
    }
    if (shapes) lin_red_expand(&R, nc, yk, shapes + (size_t)k * n6);
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
  lin_red_free(&R);
  free(iwork); free(ifail); free(work); free(ev); free(Y); free(A); free(Bm); free(evi); free(Yi);
  return st;
}

/* ---------------------------------------------------------------- linear port-Hamiltonian model */
int phm_linear_port_columns(const phm_model *m, int nports, const phm_linear_port *ports) {
  int n = 0;
  for (int i = 0; i < nports; i++)
    n += ports[i].kind == PHM_PORT_PAIR ? (ports[i].index >= 0 && ports[i].index < m->np ? m->pair_k[ports[i].index] : 0)
         : ports[i].kind == PHM_PORT_LOAD ? 1 : 6;
  return n;
}

phm_status phm_linear_model(const phm_model *m, const double *poses, const double *lambda,
                            double time, int nports, const phm_linear_port *ports, int *nr,
                            double *K, double *D, double *M, double *Z, double *B,
                            phm_error *err) {
  phm_error_clear(err);
  if (!m || !nr || !K || !D || !M || (nports > 0 && (!ports || !B)))
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
  *nr = n;
done:
  lin_red_free(&R);
  free(F); free(y);
  return st;
}
