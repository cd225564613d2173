/* test_residual.c -- csrc/dae/residual.c: the generalized-alpha's stage residual makes the
 * constraint wrenches of the pairs on a loop between rigid bodies workless (workless_at_stage,
 * docs/method.md section 6.7). At random states of three rigid carriers, a triangle of revolute
 * pairs (ground, 0, 1) and a revolute hanging carrier 2 from carrier 1: the loop's pairs are
 * flagged and the branch's is not; with only the loop, the constraint wrenches' power in the
 * ledger row is lambda . v_t = 0 at the stage (to 1e-12 of sum |lambda_r (G t)_r|; the full
 * residual's lambda . G t is not), and the momentum rows move by the correction's wrench alone, whose power is
 * that lambda . G t; with kappa h bounded by DAE_WORKLESS_STEP the power left is at most the
 * bound's share. */
#include "check.h"
#include "dae.h"

enum { NC = 3 };

/* The model: carriers 0, 1 and (branch) 2 with random inertias; the triangle's three revolutes,
 * and with `branch` a fourth from carrier 1 to carrier 2. Random pair frames: the residual
 * needs no consistent configuration. */
static phm_model *triangle(int branch) {
  phm_carrier_desc car[NC];
  phm_pair_desc pr[4];
  memset(pr, 0, sizeof pr);
  for (int c = 0; c < NC; c++) {
    carrier_unit(&car[c]);
    rand_spd6(car[c].M, 0.5);
    car[c].mass = car[c].M[21];
  }
  const int ends[4][2] = {{-1, 0}, {0, 1}, {1, -1}, {1, 2}};
  for (int i = 0; i < 4; i++) {
    pr[i].type = pair_code("revolute");
    pr[i].a = ends[i][0];
    pr[i].b = ends[i][1];
    rand_pose(pr[i].Ta, 0.5);
    rand_pose(pr[i].Tb, 0.5);
  }
  phm_model_desc d = {.ncarriers = branch ? NC : NC - 1, .carriers = car, .npairs = branch ? 4 : 3,
                      .pairs = pr, .gravity = {0.0, 0.0, -9.81}};
  return create_model(&d);
}

/* Random carrier states (unit quaternions, positions, twists) and multipliers; rates 0. */
static void random_state(const dae_t *d, double *y, double *yp) {
  memset(y, 0, sizeof(double) * (size_t)d->n);
  memset(yp, 0, sizeof(double) * (size_t)d->n);
  for (int c = 0; c < d->m->nc; c++) {
    double *q = y + PHM_NSTATE * c, s = 0;
    for (int i = 0; i < 4; i++) {
      q[i] = rand11();
      s += q[i] * q[i];
    }
    for (int i = 0; i < 4; i++) q[i] /= sqrt(s);
    for (int i = 4; i < PHM_NSTATE; i++) q[i] = rand11();
  }
  for (int r = d->il; r < d->im; r++) y[r] = 10.0 * rand11();
}

static void loop_wrenches_do_no_work_at_the_stage(void) {
  for (int trial = 0; trial < 20; trial++) {
    for (int branch = 0; branch < 2; branch++) {
      phm_model *m = triangle(branch);
      if (!m) return;
      dae_t d;
      phm_error err;
      if (dae_init(&d, m, &err)) {
        check_fail("dae_init: %s", err.msg);
        phm_model_free(m);
        return;
      }
      CHECK(d.workless[0] && d.workless[1] && d.workless[2], "the triangle's pairs are workless");
      CHECK(!branch || !d.workless[3], "the branch's pair is not");
      int n = d.n, ps = d.ie + 1;
      double *y = calloc((size_t)n * 4, sizeof(double)), *yp = y + n, *F1 = yp + n, *Fs = F1 + n;
      random_state(&d, y, yp);
      dae_residual(&d, 0.0, y, yp, F1); /* G t's power, uncorrected (F = -Ps: yp's are 0) */
      d.stage_h = 1e-12;                /* the bound far away */
      dae_residual_rows(&d, 0.0, y, yp, Fs, 0);
      if (!branch) {
        /* the scale of the powers: sum_r |lambda_r (G t)_r| (the rows' regularization,
         * c lambda ~ 1e-9 lambda, is below the tolerance) */
        double S = 0;
        for (int r = d.il; r < d.im; r++) S += fabs(y[r] * F1[r]);
        CHECK(fabs(F1[ps]) > 1e-3 * S, "lambda . G t is not zero here (%g of %g)", F1[ps], S);
        check_worst("the loop's wrenches' power at the stage / lambda . G t", fabs(Fs[ps]) / S,
                    1e-12);
        /* the momentum rows moved by the correction's wrench, kappa M t, whose power is the
         * one taken out: sum_c t_c . (Fs - F1)_c = lambda . G t */
        double moved = 0;
        for (int c = 0; c < m->nc; c++)
          for (int j = 0; j < 6; j++)
            moved += y[PHM_NSTATE * c + 7 + j] * (Fs[PHM_NSTATE * c + 7 + j] - F1[PHM_NSTATE * c + 7 + j]);
        check_worst("the correction's power / lambda . G t", fabs(moved + F1[ps]) / S, 1e-12);
        /* bounded: kappa h <= DAE_WORKLESS_STEP leaves at least the rest of the power */
        d.stage_h = 1.0;
        dae_residual_rows(&d, 0.0, y, yp, Fs, 0);
        double K2 = 0;
        for (int c = 0; c < m->nc; c++) {
          double Mt[6];
          phm_mv6(m->car[m->car_u[c]].M, y + PHM_NSTATE * c + 7, Mt);
          K2 += phm_dot(y + PHM_NSTATE * c + 7, Mt, 6);
        }
        /* each carrier is in two of the three pairs: taken out at most 2 DAE_WORKLESS_STEP K2 */
        CHECK(fabs(Fs[ps] - F1[ps]) <= 2.0 * DAE_WORKLESS_STEP * K2 + 1e-12 * S,
              "bounded correction: %g taken out, bound %g", fabs(Fs[ps] - F1[ps]),
              2.0 * DAE_WORKLESS_STEP * K2);
      }
      free(y);
      dae_free(&d);
      phm_model_free(m);
    }
  }
}

CHECK_MAIN(CHECK_CASE(loop_wrenches_do_no_work_at_the_stage))
