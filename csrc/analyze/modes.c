/* modes.c -- linearized modes (docs/method.md section 7): stiffness and damping blocks on the
 * tangent space (csrc/analyze/linearize.c); then, for small models, the lowest eigenpairs of the
 * dense reduced problem on the null space of the constraint Jacobian (LAPACK dsygvx), and for
 * large ones subspace iteration on the sparse KKT system (O(N) per iteration). */
#include "analyze.h"

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

/* The lowest nf modes by subspace iteration with shift-invert on the constraint manifold at
 * P's shift sigma (sparse_shift): Y = (K - sigma M)^-1 M X through the KKT system (Y satisfies
 * G Y = 0), Y made M-orthonormal, then Rayleigh-Ritz on the inverse operator. A block of b
 * vectors (phm_modes: max(2 nf, nf + 8), at most half the manifold) converges to the b
 * eigenvalues nearest sigma, mode i at the rate |lambda_i - sigma|/|lambda_b+1 - sigma| per
 * iteration, and holds repeated eigenvalues (up to b of them) that one Krylov vector would miss.
 * They are returned ascending: those below sigma first. *nbelow: how many of the block's Ritz
 * values are below sigma; the result is the nf lowest of the whole spectrum when that is
 * P->below, the number of eigenvalues below sigma (then the block holds them all, and the
 * nearest above). Returns PHM_OK or an error. */
static phm_status modes_sparse(sparse_t *P, const double *Db, int nf, int b, double *omega,
                               double *zeta, double *shapes, int *nbelow, phm_error *err) {
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
  for (int k = 0; k < b; k++) *nbelow += ev2[k] < 0;
done:
  free(X); free(Y); free(MY); free(rhs); free(A); free(ev); free(prev);
  free(t6); free(work); free(W); free(ev2); free(order);
  return st;
}

/* ---------------------------------------------------------------- the reduced linear model */
/* The linearization at poses H shared by the modes and the linear port-Hamiltonian model: the
 * stiffness K = -df/ddelta and damping D = -df/dt as blocks on the carrier coupling graph
 * (closed form, csrc/analyze/linearize.c), and, for the dense path, their reduction to
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
static phm_status sparse_path(lin_red_t *R, const phm_model *m, int nf, int b, int slice,
                              double *omega, double *zeta, double *shapes, int *ok,
                              phm_error *err) {
  sparse_t P;
  int nb = 0, n6 = 6 * m->nc;
  double *oB = NULL, *zB = NULL, *sB = NULL;
  *ok = 0;
  phm_status st = sparse_init(&P, m, &R->L, R->H, R->L.Kb, err);
  if (st || (st = sparse_shift(&P, -1e-9 * P.scale))) goto done;
  double sigma = P.sigma;
  int below = P.below;
  double check = P.check;
  if (below >= 0 && check < PHM_INERTIA_CHECK && below < b) {
    if ((st = modes_sparse(&P, R->Db, nf, b, omega, zeta, shapes, &nb, err))) goto done;
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
  if ((st = modes_sparse(&P, R->Db, nB, b, oB, zB, sB, &nbB, err))) goto done;
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
  int sparse = method == PHM_MODES_SPARSE ||
               (method == PHM_MODES_AUTO && n6 >= PHM_SPARSE_MODES_MIN + 6 * nmodes);
  /* the subspace iteration's block, max(2 nf, nf + 8) vectors, must be at most half the
   * manifold's dimension n6 - nk (the kept rows are independent: redundant ones are dropped): a
   * block beyond it held round-off vectors whose Ritz values (theta ~ -1e-15) came first (a
   * hanging chain of 10 bars with 5 revolute pairs, 60 coordinates: -1.9e8 rad/s for its 2.18
   * rad/s mode), and on a whole-manifold block they never settled ("did not converge in 1000
   * iterations"). Smaller manifolds: dense. */
  int block = 2 * nmodes > nmodes + 8 ? 2 * nmodes : nmodes + 8;
  if (sparse && 2 * block <= n6 - nk) {
    /* the result is checked against the count of eigenvalues below the shift (finding 9 of
     * docs/validation.md: alone, shift-invert finds the eigenvalues nearest its shift, and an
     * unstable mode farther away than the stable ones asked for went unseen); unverified, AUTO
     * redoes it densely where that is affordable (PHM_DENSE_MODES_MAX manifold coordinates),
     * the sparse method and larger models slice the spectrum */
    int slice = method == PHM_MODES_SPARSE || n6 - nk > PHM_DENSE_MODES_MAX, ok = 0;
    st = sparse_path(&R, m, nmodes, block, slice, omega, zeta, shapes, &ok, err);
    if (st == PHM_OK && ok) {
      *nfound = nmodes;
      goto done;
    }
    if (st != PHM_OK && st != PHM_ESINGULAR) goto done;
    if (st == PHM_ESINGULAR && method == PHM_MODES_SPARSE) {
      st = PHM_FAIL(err, PHM_ESINGULAR, "modes: the KKT matrix [K - sigma M, G^T; G, 0] is singular "
                    "(dependent constraint rows at this configuration?); the dense method handles it");
      goto done;
    }
    st = PHM_OK; /* singular KKT matrix (dependent constraint rows here), or unverified: dense */
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
