/* test_mixed.c -- csrc/model/mixed.c: Golo's mixed finite element for the linear Timoshenko beam
 * (element matrices, the assembled chain against sequential substitution, pinned-pinned
 * frequencies against the exact Timoshenko ones, refused inputs). */
#include "check.h"

/* Table I parameters */
static phm_mixed_beam table1(int N, double alpha) {
  phm_mixed_beam b = {N, 1.0, 5143.0, 656625.0, 873.0, 2.1797, alpha};
  return b;
}

static double max_skew_defect(const double *M, int n) {
  double m = 0.0, s = 0.0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      m = fmax(m, fabs(M[i * n + j] + M[j * n + i]));
      s = fmax(s, fabs(M[i * n + j]));
    }
  return m / (s > 0 ? s : 1);
}

/* Exact pinned-pinned Timoshenko frequencies: w = W sin(k s), phi = Phi cos(k s), k = j pi / L:
 * det [[kGA k^2 - rhoA w^2, -kGA k], [-kGA k, EI k^2 + kGA - rhoI w^2]] = 0 (both branches). */
static void exact_pinned(const phm_mixed_beam *b, int n, double *out) {
  double all[80];
  int m = 0;
  for (int j = 1; j <= 40; j++) {
    const double k = j * CHECK_PI / b->L;
    const double a = b->rhoA * b->rhoI;
    const double bb = -(b->rhoA * (b->EI * k * k + b->kGA) + b->rhoI * b->kGA * k * k);
    const double c = b->kGA * k * k * b->EI * k * k;
    const double disc = sqrt(bb * bb - 4 * a * c);
    all[m++] = sqrt((-bb - disc) / (2 * a));
    all[m++] = sqrt((-bb + disc) / (2 * a));
  }
  for (int i = 0; i < m; i++) /* insertion sort */
    for (int j = i; j > 0 && all[j] < all[j - 1]; j--) {
      double t = all[j];
      all[j] = all[j - 1];
      all[j - 1] = t;
    }
  memcpy(out, all, (size_t)n * sizeof *out);
}

static void element_matrices_have_the_structure_of_the_alpha_family(void) {
  double J[16], Q[16], B[16], D[16];
  phm_error err;
  const double alphas[3] = {0.0, 0.5, 0.3};
  for (int a = 0; a < 3; a++) {
    CHECK(phm_mixed_element(0.1, 5143, 656625, 873, 2.1797, alphas[a], J, Q, B, D, &err) == PHM_OK,
          "element");
    CHECK(max_skew_defect(J, 4) == 0.0, "element J skew");
    CHECK(max_skew_defect(D, 4) == 0.0, "element D skew");
    int ok = 1;
    for (int i = 0; i < 4; i++)
      for (int j = 0; j < 4; j++) ok &= (i == j) ? Q[i * 4 + j] > 0 : Q[i * 4 + j] == 0;
    CHECK(ok, "element Q diagonal positive");
  }
  /* alpha = 1/2: v_b = 2 v_e - v_a, so E_s' = v_b - v_a - h om_e = 2 v_e - 2 v_a - h om_e. */
  phm_mixed_element(0.1, 1, 1, 1, 1, 0.5, J, Q, B, D, &err);
  CHECK(J[1 * 4 + 0] == 2.0 && B[1 * 4 + 0] == -2.0 && J[1 * 4 + 2] == -0.1 && D[0 * 4 + 2] == 1.0,
        "alpha = 1/2 element coefficients");
}

/* The chain, rebuilt independently from the element matrices by sequential substitution:
 * velocities from the left, forces from the right, then each element's x' = J_e e + B_e u_e and
 * output y_e = B_e^T e + D_e u_e. Compared with phm_mixed_assemble on random e, u. */
static void check_chain(int N, double alpha) {
  phm_mixed_beam b = table1(N, alpha);
  const int n = 4 * N;
  double *J = malloc(sizeof(double) * n * n), *Q = malloc(sizeof(double) * n * n);
  double *B = malloc(sizeof(double) * n * 4), D[16];
  double *e = malloc(sizeof(double) * n), *xd = malloc(sizeof(double) * n);
  double *vn = malloc(sizeof(double) * (N + 1)), *wn = malloc(sizeof(double) * (N + 1));
  double *qn = malloc(sizeof(double) * (N + 1)), *mn = malloc(sizeof(double) * (N + 1));
  phm_error err;
  CHECK(phm_mixed_assemble(&b, J, Q, B, D, &err) == PHM_OK, "assemble N=%d: %s", N, err.msg);
  CHECK(max_skew_defect(J, n) == 0.0, "J skew N=%d alpha=%g", N, alpha);
  CHECK(max_skew_defect(D, 4) == 0.0, "D skew");
  int qok = 1;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) qok &= (i == j) ? Q[i * n + j] > 0 : Q[i * n + j] == 0;
  CHECK(qok, "Q diagonal positive definite");

  double Je[16], Qe[16], Be[16], De[16];
  phm_mixed_element(b.L / N, b.EI, b.kGA, b.rhoA, b.rhoI, alpha, Je, Qe, Be, De, &err);
  CHECK(Qe[5] == Q[1 * n + 1] && Qe[15] == Q[(n - 1) * n + n - 1], "element Q = block of chain Q");
  for (int trial = 0; trial < 3; trial++) {
    double u[4];
    for (int i = 0; i < n; i++) e[i] = rand11();
    for (int i = 0; i < 4; i++) u[i] = rand11();
    /* forward: element outputs v_b = y_e[2], om_b = y_e[3] depend on (e, v_a, om_a) only */
    vn[0] = u[0];
    wn[0] = u[1];
    for (int k = 0; k < N; k++) {
      double ue[4] = {vn[k], wn[k], 0.0, 0.0}, y[4];
      for (int r = 2; r < 4; r++) {
        y[r] = 0;
        for (int i = 0; i < 4; i++) y[r] += Be[i * 4 + r] * e[4 * k + i] + De[r * 4 + i] * ue[i];
      }
      vn[k + 1] = y[2];
      wn[k + 1] = y[3];
    }
    qn[N] = u[2];
    mn[N] = u[3];
    for (int k = N - 1; k >= 0; k--) {
      double ue[4] = {0.0, 0.0, qn[k + 1], mn[k + 1]}, y[2];
      for (int r = 0; r < 2; r++) {
        y[r] = 0;
        for (int i = 0; i < 4; i++) y[r] += Be[i * 4 + r] * e[4 * k + i] + De[r * 4 + i] * ue[i];
      }
      qn[k] = -y[0];
      mn[k] = -y[1];
    }
    double dmax = 0.0, scale = 0.0;
    for (int k = 0; k < N; k++) {
      double ue[4] = {vn[k], wn[k], qn[k + 1], mn[k + 1]};
      for (int r = 0; r < 4; r++) {
        double ref = 0.0, got = 0.0;
        for (int i = 0; i < 4; i++) ref += Je[r * 4 + i] * e[4 * k + i] + Be[r * 4 + i] * ue[i];
        for (int i = 0; i < n; i++) got += J[(4 * k + r) * n + i] * e[i];
        for (int i = 0; i < 4; i++) got += B[(4 * k + r) * 4 + i] * u[i];
        xd[4 * k + r] = got;
        dmax = fmax(dmax, fabs(got - ref));
        scale = fmax(scale, fabs(ref));
      }
    }
    CHECK(dmax <= 1e-12 * scale, "chain dynamics N=%d alpha=%g: defect %g (scale %g)", N, alpha,
          dmax, scale);
    /* chain output y = (-Qs_0, -M_0, v_N, om_N) = B^T e + D u */
    double yref[4] = {-qn[0], -mn[0], vn[N], wn[N]}, ydef = 0.0;
    for (int r = 0; r < 4; r++) {
      double got = 0.0;
      for (int i = 0; i < n; i++) got += B[i * 4 + r] * e[i];
      for (int i = 0; i < 4; i++) got += D[r * 4 + i] * u[i];
      ydef = fmax(ydef, fabs(got - yref[r]));
    }
    CHECK(ydef <= 1e-12 * fmax(1.0, scale), "chain output N=%d alpha=%g: defect %g", N, alpha, ydef);
    /* power balance dH/dt = e^T x' = u^T y */
    double dH = 0.0, py = 0.0;
    for (int i = 0; i < n; i++) dH += e[i] * xd[i];
    for (int r = 0; r < 4; r++) py += u[r] * yref[r];
    CHECK(fabs(dH - py) <= 1e-12 * scale * n, "power balance N=%d: dH=%g u^T y=%g", N, dH, py);
  }
  free(J);
  free(Q);
  free(B);
  free(e);
  free(xd);
  free(vn);
  free(wn);
  free(qn);
  free(mn);
}

static void pinned_pinned_frequencies_converge_at_second_order(void) {
  double ex[5], w1[5], w2[5];
  phm_error err;
  phm_mixed_beam b1 = table1(20, 0.5), b2 = table1(40, 0.5);
  exact_pinned(&b1, 5, ex);
  CHECK(phm_mixed_frequencies(&b1, PHM_MIXED_PINNED_PINNED, 5, w1, &err) == PHM_OK, "%s", err.msg);
  CHECK(phm_mixed_frequencies(&b2, PHM_MIXED_PINNED_PINNED, 5, w2, &err) == PHM_OK, "%s", err.msg);
  for (int i = 0; i < 5; i++) {
    const double e1 = fabs(w1[i] - ex[i]) / ex[i], e2 = fabs(w2[i] - ex[i]) / ex[i];
    const double order = log(e1 / e2) / log(2.0);
    CHECK(e2 < 0.02, "pinned mode %d: rel error %g at N=40", i + 1, e2);
    CHECK(order > 1.9 && order < 2.1, "pinned mode %d: observed order %g", i + 1, order);
  }
}

static void invalid_beams_are_refused(void) {
  phm_error err;
  double w[4];
  phm_mixed_beam b = table1(0, 0.5);
  CHECK(phm_mixed_frequencies(&b, PHM_MIXED_CLAMPED_FREE, 1, w, &err) == PHM_EINVAL, "N = 0");
  b = table1(4, 0.5);
  b.EI = -1;
  CHECK(phm_mixed_check(&b, &err) == PHM_EINVAL, "EI < 0");
  b = table1(4, NAN);
  CHECK(phm_mixed_check(&b, &err) == PHM_EINVAL, "alpha NaN");
  b = table1(4, 1.0);
  CHECK(phm_mixed_check(&b, &err) == PHM_EINVAL, "alpha = 1");
  b = table1(4, 0.5);
  b.rhoI = INFINITY;
  CHECK(phm_mixed_check(&b, &err) == PHM_EINVAL, "rhoI inf");
  b = table1(2, 0.5);
  CHECK(phm_mixed_frequencies(&b, PHM_MIXED_CLAMPED_FREE, 5, w, &err) == PHM_EINVAL,
        "too many frequencies");
  phm_mixed_bc bc;
  CHECK(phm_mixed_bc_from_name("free-floating", &bc, &err) == PHM_EINVAL, "bad bc name");
  CHECK(phm_mixed_bc_from_name("pinned-pinned", &bc, &err) == PHM_OK && bc == PHM_MIXED_PINNED_PINNED,
        "bc name");
  b = table1(7, 0.9); /* 9^7 > 1e6: ill-conditioned */
  double *J = malloc(sizeof(double) * 28 * 28);
  CHECK(J && phm_mixed_assemble(&b, J, NULL, NULL, NULL, &err) == PHM_EINVAL, "overflow refused");
  free(J);
}

static void chain_matches_its_elements_by_sequential_substitution(void) {
  check_chain(1, 0.5);
  check_chain(7, 0.5);
  check_chain(6, 0.3);
  check_chain(5, 0.0);
  check_chain(5, 0.7);
}

CHECK_MAIN(CHECK_CASE(element_matrices_have_the_structure_of_the_alpha_family),
           CHECK_CASE(chain_matches_its_elements_by_sequential_substitution),
           CHECK_CASE(pinned_pinned_frequencies_converge_at_second_order),
           CHECK_CASE(invalid_beams_are_refused))
