/* modes.c -- linearized modes (docs/method.md section 7.2): stiffness and damping blocks on the
 * tangent space (csrc/analyze/linearize.c); then, for small models, the lowest eigenpairs of the
 * dense reduced problem on the null space of the constraint Jacobian (LAPACK dsygvx, on
 * reduce.c's K_r, M_r), and for large ones subspace iteration on the sparse KKT system
 * (modes_sparse.c, O(N) per iteration). */
#include "analyze.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"

/* ---------------------------------------------------------------- the dense path */
/* The nf lowest eigenpairs of Kr y = lambda Mr y (nr x nr, symmetric) into ev, Y (nr x nf,
 * column-major; unit modal mass), the resolved ones from the pencil shift-inverted at sigma < 0
 * (see modes_dense). A, Bm: nr x nr scratch; evi, Yi as ev, Y; iwork 5 nr, ifail nr. */
static phm_status dense_eigs(int nr, const double *Kr, const double *Mr, double sigma, int nf,
                             double *ev, double *Y, double *evi, double *Yi, double *A,
                             double *Bm, int *iwork, int *ifail, phm_error *err) {
  int mfound = 0, nres = 0, inv_all = 0;
  phm_status st = PHM_OK;
  double *work = NULL;
  int one = 1, lw = -1, info = 0;
  double wq, vl = 0, vu = 0, abstol = 2 * dlamch_("S");
  for (int inv = 1; inv >= 0; inv--) {
    /* inv: (A, B) = (Mr, Kr - sigma Mr), theta nr-nf+1..nr into evi, Yi; else (Kr, Mr),
     * lambda 1..nf into ev, Y */
    int lo = inv ? nr - nf + 1 : 1, hi = inv ? nr : nf;
    double *e = inv ? evi : ev, *V = inv ? Yi : Y;
    for (int pass = 0; pass < 2; pass++) { /* workspace query, then the solve */
      for (size_t i = 0; i < (size_t)nr * nr; i++) {
        A[i] = inv ? Mr[i] : Kr[i];
        Bm[i] = inv ? Kr[i] - sigma * Mr[i] : Mr[i];
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
      /* against the largest theta, read before the loop turns evi[0] into lambda_1 (it read
       * evi[0] inside: every mode after the first failed the test and came from the direct
       * solve below, and each call solved twice; modes 3-5 of the Table I cantilever moved by
       * 3e-12 relative with the fix, the eigensolve 63 -> 40 us at N = 3) */
      double theta1 = evi[0];
      while (nres < nf && evi[nres] > PHM_MODES_RESOLVED * theta1) nres++;
      /* every pair converted: the unresolved ones are the fallback if the direct pencil fails */
      inv_all = 1;
      for (int k = 0; k < nf; k++) {
        if (!(evi[k] > 0)) { inv_all = 0; break; }
        double sc = 1.0 / sqrt(evi[k]);
        for (int a = 0; a < nr; a++) Yi[(size_t)k * nr + a] *= sc;
        evi[k] = sigma + 1.0 / evi[k];
      }
      if (nres == nf) break;
    } else if ((info != 0 || mfound < nf) && inv_all) {
      /* the direct pencil failed where the inverse found every pair: those, less accurate
       * (carriers' masses beyond what double precision resolves, a link of density 1e-300 on a
       * 1 kg pendulum: _model.warn_unresolvable_masses warns of it; tests/test_fuzz_findings.py) */
      nres = nf;
    } else if (info != 0 || mfound < nf) {
      st = PHM_FAIL(err, PHM_ESINGULAR, "generalized eigenproblem failed (dsygvx info %d, %d of "
                         "%d eigenvalues found%s)", info, mfound, nf,
                         info > nr ? ": mass matrix not positive definite" : "");
      goto done;
    }
  }
  memcpy(ev, evi, sizeof(double) * (size_t)nres);   /* the resolved modes from the inverse */
  memcpy(Y, Yi, sizeof(double) * (size_t)nres * nr);
  goto done;
oom:
  st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
done:
  free(work);
  return st;
}

/* The block split of the dense problem. A planar mechanism at a planar equilibrium, a beam's
 * axial and torsional motions at a straight configuration, ...: Kr and Mr are then (up to a
 * permutation) block diagonal, and the eigenpairs of (Kr, Mr) are those of the blocks, each
 * eigenvector zero outside its block. The blocks are the connected components of the coupling
 * graph: coordinates a != b are coupled when |X_ab| > SPLIT_TOL sqrt(|X_aa X_bb|) for X = Kr or
 * Mr. SPLIT_TOL = DBL_EPSILON: an entry left out is within the bound on the componentwise
 * backward error of the Cholesky factorization dsygvx makes of the pencil's B, about (n + 1) eps
 * sqrt(B_aa B_bb) per entry (B = Kr - sigma Mr or Mr: an entry dropped from both Kr and Mr is
 * below eps sqrt(B_aa B_bb) there too, Cauchy-Schwarz, for Kr_aa >= 0), and relative to its row's and
 * column's own scales, not the matrix's norm, so it cannot hide a small stiffness coupling of
 * soft directions; the Table I cantilever's and planar models' decoupled entries are exact zeros
 * (benchmarks/bench_overhead.py). A zero diagonal (a massless or unloaded direction) keeps every
 * nonzero entry of its row. The cost is the sum of the blocks' n_b^3 instead of nr^3 (the Table I
 * cantilever at N = 9: blocks 9, 18, 18, 9 for 54 coordinates). */
#define SPLIT_TOL DBL_EPSILON

/* The connected components of the coupling graph of (Kr, Mr) (see SPLIT_TOL): comp[a], numbered
 * in the order of their first coordinates; returns their number. stack: nr, dg: 2 nr scratch. */
static int coupling_blocks(int nr, const double *Kr, const double *Mr, int *comp, int *stack,
                           double *dg) {
  for (int a = 0; a < nr; a++) {
    comp[a] = -1;
    dg[2 * a] = sqrt(fabs(Kr[(size_t)a * nr + a]));
    dg[2 * a + 1] = sqrt(fabs(Mr[(size_t)a * nr + a]));
  }
  int nb = 0;
  for (int a0 = 0; a0 < nr; a0++) {
    if (comp[a0] >= 0) continue;
    int top = 0;
    comp[a0] = nb;
    stack[top++] = a0;
    while (top > 0) {
      int a = stack[--top];
      const double *ka = Kr + (size_t)a * nr, *ma = Mr + (size_t)a * nr;
      for (int b = 0; b < nr; b++)
        if (comp[b] < 0 && (fabs(ka[b]) > SPLIT_TOL * dg[2 * a] * dg[2 * b] ||
                            fabs(ma[b]) > SPLIT_TOL * dg[2 * a + 1] * dg[2 * b + 1])) {
          comp[b] = nb;
          stack[top++] = b;
        }
    }
    nb++;
  }
  return nb;
}

/* dense_eigs on the whole problem, with its scratch. */
static phm_status whole_eigs(int nr, const double *Kr, const double *Mr, double sigma, int nf,
                             double *ev, double *Y, phm_error *err) {
  phm_status st = PHM_OK;
  double *evi = malloc(sizeof(double) * (size_t)nr), *Yi = malloc(sizeof(double) * (size_t)nr * nf);
  double *A = malloc(sizeof(double) * (size_t)nr * nr), *Bm = malloc(sizeof(double) * (size_t)nr * nr);
  int *iwork = malloc(sizeof(int) * 5 * (size_t)nr), *ifail = malloc(sizeof(int) * (size_t)nr);
  if (!evi || !Yi || !A || !Bm || !iwork || !ifail) st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  else st = dense_eigs(nr, Kr, Mr, sigma, nf, ev, Y, evi, Yi, A, Bm, iwork, ifail, err);
  free(evi); free(Yi); free(A); free(Bm); free(iwork); free(ifail);
  return st;
}

phm_status modes_dense_eigs(int nr, const double *Kr, const double *Mr, int nf, int split,
                            double *ev, double *Y, int *nblocks, phm_error *err) {
  phm_status st = PHM_OK;
  int *comp = NULL, *idx = NULL, *first = NULL, *iwork = NULL, *ifail = NULL, *taken = NULL;
  double *dg = NULL, *A = NULL, *Bm = NULL, *Kb = NULL, *Mb = NULL, *evb = NULL, *Yb = NULL;
  double *evi = NULL, *Yi = NULL, *evc = NULL, *Yc = NULL;
  double trK = 0, trM = 0;
  for (int a = 0; a < nr; a++) { trK += Kr[(size_t)a * nr + a]; trM += Mr[(size_t)a * nr + a]; }
  /* one shift for every block: the whole problem's */
  double sigma = trK > 0 && trM > 0 ? -1e-9 * trK / trM : -1.0;
  int nb = 1;
  if (split && nr > 1) {
    comp = malloc(sizeof(int) * (size_t)nr);
    idx = malloc(sizeof(int) * (size_t)nr);
    dg = malloc(sizeof(double) * 2 * (size_t)nr);
    if (!comp || !idx || !dg) goto oom;
    nb = coupling_blocks(nr, Kr, Mr, comp, idx, dg);
  }
  if (nblocks) *nblocks = nb;
  if (nb == 1) { /* the whole problem, as it is */
    st = whole_eigs(nr, Kr, Mr, sigma, nf, ev, Y, err);
    goto done;
  }
  /* the blocks' coordinates in idx (ascending within each block), block b at first[b] .. */
  first = calloc((size_t)nb + 2, sizeof(int));
  if (!first) goto oom;
  for (int a = 0; a < nr; a++) first[comp[a] + 2]++;
  int nmax = 0, ncand = 0;
  for (int b = 0; b < nb; b++) {
    int nbk = first[b + 2];
    if (nbk > nmax) nmax = nbk;
    ncand += nf < nbk ? nf : nbk;
    first[b + 2] += first[b + 1];
  }
  for (int a = 0; a < nr; a++) idx[first[comp[a] + 1]++] = a;
  /* now first[b] .. first[b + 1] - 1 hold block b */
  evi = malloc(sizeof(double) * (size_t)nmax);
  evb = malloc(sizeof(double) * (size_t)nmax);
  Yi = malloc(sizeof(double) * (size_t)nmax * nf);
  Yb = malloc(sizeof(double) * (size_t)nmax * nf);
  iwork = malloc(sizeof(int) * 5 * (size_t)nmax);
  ifail = malloc(sizeof(int) * (size_t)nmax);
  A = malloc(sizeof(double) * (size_t)nmax * nmax);
  Bm = malloc(sizeof(double) * (size_t)nmax * nmax);
  Kb = malloc(sizeof(double) * (size_t)nmax * nmax);
  Mb = malloc(sizeof(double) * (size_t)nmax * nmax);
  evc = malloc(sizeof(double) * (size_t)ncand);
  Yc = malloc(sizeof(double) * (size_t)nr * nf);
  taken = malloc(sizeof(int) * (size_t)nb);
  if (!evi || !evb || !Yi || !Yb || !iwork || !ifail || !A || !Bm || !Kb || !Mb || !evc || !Yc ||
      !taken)
    goto oom;
  /* each block's nf lowest (or all of it) */
  for (int b = 0, ec = 0; b < nb; b++) {
    const int *ib = idx + first[b];
    int nbk = first[b + 1] - first[b], nfb = nf < nbk ? nf : nbk;
    for (int i = 0; i < nbk; i++)
      for (int j = 0; j < nbk; j++) {
        Kb[(size_t)i * nbk + j] = Kr[(size_t)ib[i] * nr + ib[j]];
        Mb[(size_t)i * nbk + j] = Mr[(size_t)ib[i] * nr + ib[j]];
      }
    if ((st = dense_eigs(nbk, Kb, Mb, sigma, nfb, evb, Yb, evi, Yi, A, Bm, iwork, ifail, err))) {
      if (st == PHM_ENOMEM) goto done;
      /* a block that fails alone, where the whole problem may not (masses beyond what double
       * precision resolves: a link of density 1e-300 on a 1 kg body, whose block's pencils both
       * fail where the whole one's shift-invert finds every pair, tests/test_fuzz_findings.py):
       * the whole problem, as without the split, with its result or its error */
      phm_error_clear(err);
      if (nblocks) *nblocks = 1;
      st = whole_eigs(nr, Kr, Mr, sigma, nf, ev, Y, err);
      goto done;
    }
    memcpy(evc + ec, evb, sizeof(double) * (size_t)nfb);
    memcpy(Yc + (size_t)first[b] * nf, Yb, sizeof(double) * (size_t)nbk * nfb);
    ec += nfb;
  }
  /* the nf lowest of them, ascending (equal ones: the block of the lower coordinates first),
   * each eigenvector zero outside its block; the blocks' candidates start at first[b] * nf in Yc
   * (column-major, nbk rows) and at cstart[b] in evc (comp reused), taken[b] of them merged */
  int *cstart = comp;
  for (int b = 0, ec = 0; b < nb; b++) {
    int nbk = first[b + 1] - first[b];
    cstart[b] = ec;
    taken[b] = 0;
    ec += nf < nbk ? nf : nbk;
  }
  memset(Y, 0, sizeof(double) * (size_t)nr * nf);
  for (int k = 0; k < nf; k++) {
    int best = -1;
    for (int b = 0; b < nb; b++) {
      int nbk = first[b + 1] - first[b];
      if (taken[b] < (nf < nbk ? nf : nbk) &&
          (best < 0 || evc[cstart[b] + taken[b]] < evc[cstart[best] + taken[best]]))
        best = b;
    }
    int nbk = first[best + 1] - first[best];
    const double *y = Yc + (size_t)first[best] * nf + (size_t)taken[best] * nbk;
    ev[k] = evc[cstart[best] + taken[best]];
    for (int i = 0; i < nbk; i++) Y[(size_t)k * nr + idx[first[best] + i]] = y[i];
    taken[best]++;
  }
  goto done;
oom:
  st = PHM_FAIL(err, PHM_ENOMEM, "out of memory");
done:
  free(comp); free(idx); free(first); free(iwork); free(ifail); free(taken); free(dg); free(A); free(Bm);
  free(Kb); free(Mb); free(evb); free(Yb); free(evi); free(Yi); free(evc); free(Yc);
  return st;
}

/* The dense path: phm_modes' results from the reduced problem of R (its blocks set). */
static phm_status modes_dense(lin_red_t *R, const phm_model *m, int nmodes, double *omega,
                              double *zeta, double *shapes, int *nfound, phm_error *err) {
  int nc = m->nc, n6 = 6 * nc;
  phm_status st = PHM_OK;
  double *ev = NULL, *Y = NULL;
  /* dense: the reduced problem Kr y = lambda Mr y (lambda = omega^2), the lowest modes only
   * (dsygvx). Shift-invert first: Mr y = theta (Kr - sigma Mr) y with theta = 1/(lambda - sigma)
   * and sigma < 0 as in the sparse path; its largest theta are the lowest lambda, to relative
   * accuracy eps theta_1 / theta_k, where the direct pencil loses eps ||Mr^-1 Kr|| / lambda_k (a
   * flexible link's axial modes make that 4e-6 on the leaf spring's first bending mode). Modes
   * with theta_k < PHM_MODES_RESOLVED theta_1 (more than 1e6 times the first eigenvalue, or below
   * round-off: a massless direction) and every mode when Kr - sigma Mr is not positive definite
   * (an unstable configuration) come from the direct pencil. */
  if ((st = lin_red_reduce(R, m, err))) goto done;
  int nr = R->nr, nf = nmodes < nr ? nmodes : nr;
  ev = malloc(sizeof(double) * (size_t)nr);
  Y = malloc(sizeof(double) * (size_t)nr * nf);
  if (!ev || !Y) goto oom;
  if ((st = modes_dense_eigs(nr, R->Kr, R->Mr, nf, 1, ev, Y, NULL, err))) goto done;
  for (int k = 0; k < nf; k++) {
    double lamk = ev[k];
    omega[k] = lamk >= 0 ? sqrt(lamk) : -sqrt(-lamk);
    const double *yk = Y + (size_t)k * nr; /* column-major: eigenvector k is contiguous */
    if (zeta) {
      double s = 0;
      for (int a = 0; a < nr; a++) {
        double t = 0;
        for (int b = 0; b < nr; b++) t += R->Dr[(size_t)a * nr + b] * yk[b];
        s += yk[a] * t;
      }
      zeta[k] = omega[k] > 0 ? s / (2 * omega[k]) : 0.0;
    }
    if (shapes) lin_red_expand(R, nc, yk, shapes + (size_t)k * n6);
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
  free(ev); free(Y);
  return st;
}

/* ---------------------------------------------------------------- modes */
phm_status phm_modes(const phm_model *m, const double *poses, const double *lambda, double time,
                     int nmodes, int method, double *omega, double *zeta, double *shapes,
                     int *nfound, phm_modes_stats *stats, phm_error *err) {
  phm_error_clear(err);
  phm_modes_stats own;
  if (!stats) stats = &own;
  memset(stats, 0, sizeof *stats);
  if (!m || !omega || !nfound) return PHM_FAIL(err, PHM_EINVAL, "phm_modes: NULL argument");
  if (nmodes < 1) return PHM_FAIL(err, PHM_EINVAL, "number of modes must be >= 1 (got %d)", nmodes);
  PHM_CHECK(method >= PHM_MODES_AUTO && method <= PHM_MODES_SPARSE, err, PHM_EINVAL,
            "unknown modes method %d (0 auto, 1 dense, 2 sparse)", method);
  *nfound = 0;
  int nc = m->nc, n6 = 6 * nc, nk = m->ncons;
  phm_status st = PHM_OK;
  lin_red_t R;
  memset(&R, 0, sizeof R);
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
    st = modes_sparse_path(&R, m, nmodes, block, slice, omega, zeta, shapes, &ok, stats, err);
    if (st == PHM_OK && ok) {
      *nfound = nmodes;
      stats->method = PHM_MODES_SPARSE;
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
  memset(stats, 0, sizeof *stats);
  stats->method = PHM_MODES_DENSE;
  st = modes_dense(&R, m, nmodes, omega, zeta, shapes, nfound, err);
done:
  lin_red_free(&R);
  return st;
}
