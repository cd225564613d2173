/* test_modes.c -- the dense modes' block split (csrc/analyze/modes.c, modes_dense_eigs): the
 * reduced problem solved on the connected components of the coupling graph of Kr and Mr against
 * the same problem solved whole. A cantilever of 8 elements clamped at its root, straight and
 * bent in the x-z plane (its reduced Kr, Mr decouple: in-plane, out-of-plane; the split must find
 * more than one block) and at random 3-D poses (coupled: one block, and then the results must be
 * the whole solve's, bit for bit); random symmetric pencils with planted blocks on interleaved
 * coordinates, cross entries below the coupling threshold (left out: the planted blocks) and one
 * above it (two blocks merged), with and without a singular Kr. Eigenvalues to 1e-9 relative
 * (of max(|lambda_k|, 1e-6 max_a |K_aa| / M_aa): zero ones), eigenvectors of separated
 * eigenvalues as M-inner products |y_split^T Mr y_whole| = 1 - 1e-7, and unit modal mass. */
#include <float.h>

#include "check.h"
#include "linalg.h"
#include "analyze.h"

enum { NE = 8, NF = 12 };

/* The cantilever of NE elements along x clamped at carrier 0 (distinct section stiffness and
 * carrier inertia per direction: no equal frequencies in different blocks). */
static phm_model *cantilever(void) {
  phm_carrier_desc car[NE + 1];
  phm_element_desc el[NE];
  phm_pair_desc pair;
  const double md[6] = {0.013, 0.021, 0.034, 1.0, 1.0, 1.0}, k[6] = {3.1, 1.0, 5.3, 70.0, 40.0, 60.0};
  straight_beam(NE, 1.0, k, car, el, &pair);
  for (int c = 0; c <= NE; c++)
    for (int i = 0; i < 6; i++) car[c].M[7 * i] = md[i];
  phm_model_desc d = {.ncarriers = NE + 1, .carriers = car, .nelements = NE, .elements = el,
                      .npairs = 1, .pairs = &pair};
  return create_model(&d);
}

/* The split solve of (K, M) (n x n) against the whole one: worst eigenvalue and eigenvector
 * errors into check_worst; returns the split's block count (0: a solve failed). Eigenvalues
 * relative to max(|lambda_k|, 1e-6 max_a |K_aa| / M_aa) (zero ones: round-off);
 * eigenvectors of eigenvalues 1e-6 apart from their neighbours (the whole solve's nf + 1). */
static int split_vs_whole(const char *what, int n, const double *K, const double *M, int nf) {
  int nfw = nf < n ? nf + 1 : n;
  double *ev = malloc(sizeof(double) * (size_t)n), *Y = malloc(sizeof(double) * (size_t)n * nfw);
  double *ev1 = malloc(sizeof(double) * (size_t)n), *Y1 = malloc(sizeof(double) * (size_t)n * nfw);
  phm_error err;
  int nb = 0, nb1 = 0;
  if (!ev || !Y || !ev1 || !Y1) goto done;
  if (modes_dense_eigs(n, K, M, nfw, 0, ev1, Y1, &nb1, &err) ||
      modes_dense_eigs(n, K, M, nf, 1, ev, Y, &nb, &err)) {
    check_fail("%s: %s", what, err.msg);
    nb = 0;
    goto done;
  }
  CHECK(nb1 == 1, "%s: the whole solve is one block (got %d)", what, nb1);
  double floor = 0, e_lam = 0, e_vec = 0, e_mass = 0;
  for (int a = 0; a < n; a++) floor = fmax(floor, 1e-6 * fabs(K[(size_t)a * n + a]) / M[(size_t)a * n + a]);
  if (nb == 1 && nfw == nf) { /* nothing split: the whole solve itself */
    CHECK(memcmp(ev, ev1, sizeof(double) * (size_t)nf) == 0 &&
          memcmp(Y, Y1, sizeof(double) * (size_t)n * nf) == 0, "%s: one block = the whole solve, "
          "bit for bit", what);
    goto done;
  }
  for (int k = 0; k < nf; k++) {
    double sc = fmax(fabs(ev1[k]), floor);
    e_lam = fmax(e_lam, fabs(ev[k] - ev1[k]) / sc);
    const double *y = Y + (size_t)k * n, *y1 = Y1 + (size_t)k * n;
    double p = 0, q = 0;
    for (int a = 0; a < n; a++)
      for (int b = 0; b < n; b++) {
        p += y[a] * M[(size_t)a * n + b] * y1[b];
        q += y[a] * M[(size_t)a * n + b] * y[b];
      }
    int apart = (k == 0 || ev1[k] - ev1[k - 1] > 1e-6 * sc) && (k + 1 >= nfw || ev1[k + 1] - ev1[k] > 1e-6 * sc);
    if (apart) e_vec = fmax(e_vec, 1 - fabs(p));
    e_mass = fmax(e_mass, fabs(q - 1));
  }
  check_worst("eigenvalues: split = whole (relative)", e_lam, 1e-9);
  check_worst("eigenvectors: |y^T M y_whole| = 1", e_vec, 1e-7);
  check_worst("eigenvectors: unit modal mass", e_mass, 1e-9);
done:
  free(ev); free(Y); free(ev1); free(Y1);
  return nb;
}

/* The cantilever's reduced problem at poses H (lin_red_blocks, lin_red_reduce): split vs whole. */
static int cantilever_at(phm_model *m, const double *H, const char *what) {
  lin_red_t R;
  phm_error err;
  int nb = 0;
  memset(&R, 0, sizeof R);
  if (lin_red_blocks(&R, m, H, NULL, 0.0, &err) || lin_red_reduce(&R, m, &err))
    check_fail("%s: %s", what, err.msg);
  else
    nb = split_vs_whole(what, R.nr, R.Kr, R.Mr, NF);
  lin_red_free(&R);
  return nb;
}

static void block_split_equals_the_whole_solve_on_a_cantilever(void) {
  phm_model *m = cantilever();
  if (!m) return;
  double H[16 * (NE + 1)];
  /* straight: four blocks (axial, bending about y, bending about z, torsion) */
  int nb = cantilever_at(m, NULL, "straight");
  CHECK(nb == 4, "straight cantilever: 4 blocks (got %d)", nb);
  /* bent in the x-z plane (an arc turning about y, not an equilibrium: Kr is the symmetrized
   * tangent there): in-plane and out-of-plane at least */
  for (int c = 0; c <= NE; c++) {
    double th = 0.9 * c / NE, R[9] = {cos(th), 0, sin(th), 0, 1, 0, -sin(th), 0, cos(th)};
    memset(H + 16 * c, 0, 16 * sizeof(double));
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) H[16 * c + 4 * i + j] = R[3 * i + j];
    H[16 * c + 3] = sin(th) / 0.9;
    H[16 * c + 11] = (cos(th) - 1) / 0.9;
    H[16 * c + 15] = 1;
  }
  nb = cantilever_at(m, H, "bent in the x-z plane");
  CHECK(nb >= 2, "cantilever bent in its plane: >= 2 blocks (got %d)", nb);
  /* random 3-D poses near the straight ones: one block */
  for (int trial = 0; trial < 3; trial++) {
    for (int c = 0; c <= NE; c++) {
      double d[6], H0[16];
      memset(H0, 0, sizeof H0);
      for (int i = 0; i < 4; i++) H0[5 * i] = 1;
      H0[3] = (double)c / NE;
      for (int i = 0; i < 6; i++) d[i] = 0.2 * rand11();
      perturbed(H0, d, 1.0, H + 16 * c);
    }
    nb = cantilever_at(m, H, "random 3-D poses");
    CHECK(nb == 1, "cantilever at random 3-D poses: 1 block (got %d)", nb);
  }
  phm_model_free(m);
}

/* Random pencils with nb0 planted blocks on interleaved coordinates (coordinate a in block
 * a mod nb0 after a random shuffle): K = A A^T per block of a random scale (singular: A with one
 * column fewer), M = B B^T + 0.1 I; cross entries of 0.5 DBL_EPSILON sqrt(X_aa X_bb) (below the
 * threshold: the planted blocks are found) and, in every third trial, one of 1e-3 sqrt(K_aa
 * K_bb) joining blocks 0 and 1 (nb0 - 1 blocks). */
static void block_split_of_random_planted_blocks(void) {
  for (int trial = 0; trial < 60; trial++) {
    int n = 4 + (int)(37 * rand01()), nb0 = 1 + (int)(5 * rand01()), join = trial % 3 == 2;
    int singular = trial % 2, nf = 1 + (int)(n * rand01());
    if (nb0 > n) nb0 = n;
    if (join && nb0 < 2) nb0 = 2;
    int *blk = malloc(sizeof(int) * (size_t)n), *perm = malloc(sizeof(int) * (size_t)n);
    double *K = calloc((size_t)n * n, sizeof(double)), *M = calloc((size_t)n * n, sizeof(double));
    double *A = malloc(sizeof(double) * (size_t)n * n), *B = malloc(sizeof(double) * (size_t)n * n);
    if (!blk || !perm || !K || !M || !A || !B) goto next;
    for (int a = 0; a < n; a++) perm[a] = a;
    for (int a = n - 1; a > 0; a--) {
      int b = (int)((a + 1) * rand01()), t = perm[a];
      perm[a] = perm[b];
      perm[b] = t;
    }
    for (int a = 0; a < n; a++) blk[perm[a]] = a % nb0;
    for (int i = 0; i < n * n; i++) { A[i] = rand11(); B[i] = rand11(); }
    for (int b = 0; b < nb0; b++) {
      double sc = pow(10.0, 3 * rand11());
      int nbk = 0;
      for (int a = 0; a < n; a++) nbk += blk[a] == b;
      int rank = singular && nbk > 1 ? nbk - 1 : nbk;
      for (int a = 0; a < n; a++)
        for (int c = 0; c < n; c++) {
          if (blk[a] != b || blk[c] != b) continue;
          double sk = 0, sm = a == c ? 0.1 : 0;
          for (int j = 0, jj = 0; j < n && jj < rank; j++) /* the block's own columns */
            if (blk[j] == b) { sk += A[(size_t)a * n + j] * A[(size_t)c * n + j]; jj++; }
          for (int j = 0; j < n; j++)
            if (blk[j] == b) sm += B[(size_t)a * n + j] * B[(size_t)c * n + j];
          K[(size_t)a * n + c] = sc * sk;
          M[(size_t)a * n + c] = sm;
        }
    }
    for (int a = 0; a < n; a++)
      for (int c = 0; c < a; c++)
        if (blk[a] != blk[c]) {
          double tk = 0.5 * DBL_EPSILON * sqrt(fabs(K[(size_t)a * n + a] * K[(size_t)c * n + c])) * rand11();
          double tm = 0.5 * DBL_EPSILON * sqrt(M[(size_t)a * n + a] * M[(size_t)c * n + c]) * rand11();
          K[(size_t)a * n + c] = K[(size_t)c * n + a] = tk;
          M[(size_t)a * n + c] = M[(size_t)c * n + a] = tm;
        }
    if (join) {
      int a = 0, c = 0;
      while (blk[a] != 0) a++;
      while (blk[c] != 1) c++;
      double t = 1e-3 * sqrt(fabs(K[(size_t)a * n + a] * K[(size_t)c * n + c]));
      K[(size_t)a * n + c] = K[(size_t)c * n + a] = t;
    }
    char what[96];
    snprintf(what, sizeof what, "trial %d (n %d, %d blocks%s%s, nf %d)", trial, n, nb0,
             singular ? ", singular K" : "", join ? ", two joined" : "", nf);
    int nb = split_vs_whole(what, n, K, M, nf);
    CHECK(nb == nb0 - join, "%s: %d blocks found", what, nb);
  next:
    free(blk); free(perm); free(K); free(M); free(A); free(B);
  }
}

CHECK_MAIN(CHECK_CASE(block_split_equals_the_whole_solve_on_a_cantilever),
           CHECK_CASE(block_split_of_random_planted_blocks))
