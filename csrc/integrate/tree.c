/* tree.c -- the "tree" integrator: a tree of rigid bodies in joint coordinates (the model's
 * articulated-body dynamics, tree_aba.c) integrated by the explicit Dormand-Prince 5(4) pair
 * (FSAL, PI step-size control on rtol, atol over the joint coordinates and rates, its continuous
 * extension for the outputs), with the energy ledger's integrals as extra states. Steps land on
 * the laws' breakpoints (a new piece: its tref, and a fresh first stage). At each output the
 * DAE's state is rebuilt -- poses (quaternion signs continued), twists, joint coordinates, the
 * ledger, lambda from the joints' wrenches, mu = 0 -- and emitted by the DAE's output routine
 * (csrc/dae/output.c), so every result field is the one the other integrators give. */
#include "tree_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phm_check.h"
#include "pose.h"

phm_status tree_check(const phm_sim_options *opt, phm_error *err) {
  if (opt->planar)
    return PHM_FAIL(err, PHM_EINVAL, "the tree integrator runs the 3-D model (planar = 0)");
  return PHM_OK;
}

phm_status tree_setup(dae_t *d, const phm_sim_options *opt, void **work, phm_error *err) {
  (void)opt;
  tree_work *w = calloc(1, sizeof *w);
  if (!w) return PHM_FAIL(err, PHM_ENOMEM, "out of memory");
  phm_status st = tree_build(d, w, err);
  if (st) {
    free(w);
    return st;
  }
  *work = w;
  return PHM_OK;
}

void tree_release(void *work) {
  if (!work) return;
  tree_free(work);
  free(work);
}

/* Dormand-Prince 5(4): nodes, stages, the error's weights (5th minus 4th order) and the dense
 * output's (Hairer, Norsett & Wanner, dopri5) */
static const double C2 = 0.2, C3 = 0.3, C4 = 0.8, C5 = 8.0 / 9.0;
static const double A21 = 0.2, A31 = 3.0 / 40.0, A32 = 9.0 / 40.0, A41 = 44.0 / 45.0,
                    A42 = -56.0 / 15.0, A43 = 32.0 / 9.0, A51 = 19372.0 / 6561.0,
                    A52 = -25360.0 / 2187.0, A53 = 64448.0 / 6561.0, A54 = -212.0 / 729.0,
                    A61 = 9017.0 / 3168.0, A62 = -355.0 / 33.0, A63 = 46732.0 / 5247.0,
                    A64 = 49.0 / 176.0, A65 = -5103.0 / 18656.0, A71 = 35.0 / 384.0,
                    A73 = 500.0 / 1113.0, A74 = 125.0 / 192.0, A75 = -2187.0 / 6784.0,
                    A76 = 11.0 / 84.0;
static const double E1 = 71.0 / 57600.0, E3 = -71.0 / 16695.0, E4 = 71.0 / 1920.0,
                    E5 = -17253.0 / 339200.0, E6 = 22.0 / 525.0, E7 = -1.0 / 40.0;
static const double D1 = -12715105075.0 / 11282082432.0, D3 = 87487479700.0 / 32700410799.0,
                    D4 = -10690763975.0 / 1880347072.0, D5 = 701980252875.0 / 199316789632.0,
                    D6 = -1453857185.0 / 822651844.0, D7 = 69997945.0 / 29380423.0;

/* The RMS of v over the error weights of the joint coordinates and rates (the ledger follows). */
static double wnorm(const tree_work *w, const double *v, const double *ya, const double *yb,
                    double rtol, double atol) {
  int n = 2 * w->nj;
  double s = 0;
  for (int i = 0; i < n; i++) {
    double sc = atol + rtol * fmax(fabs(ya[i]), yb ? fabs(yb[i]) : 0.0);
    double e = v[i] / sc;
    s += e * e;
  }
  return n ? sqrt(s / n) : 0.0;
}

/* The first step of a piece (Hairer's hinit), from the first stage f0 = ks[0] at y. */
static double first_step(tree_work *w, double t, double tref, double hmax, double rtol,
                         double atol, long *nfev) {
  double d0 = wnorm(w, w->y, w->y, NULL, rtol, atol), d1 = wnorm(w, w->ks[0], w->y, NULL, rtol, atol);
  double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
  h0 = fmin(h0, hmax);
  for (int i = 0; i < w->N; i++) w->yt[i] = w->y[i] + h0 * w->ks[0][i];
  if (tree_eval(w, t + h0, tref, w->yt, w->ks[1])) return h0 * 1e-3;
  (*nfev)++;
  for (int i = 0; i < w->N; i++) w->err[i] = w->ks[1][i] - w->ks[0][i];
  double d2 = wnorm(w, w->err, w->y, NULL, rtol, atol) / h0;
  double dm = fmax(d1, d2);
  double h1 = dm <= 1e-15 ? fmax(1e-6, h0 * 1e-3) : pow(0.01 / dm, 0.2);
  return fmin(fmin(100 * h0, h1), hmax);
}

/* The DAE's state of the tree's state Y at time t into w->ydae (d's layout), the quaternions'
 * signs continued from those already there. */
static void dae_state(tree_work *w, const dae_t *d, double t, double tref, const double *Y) {
  double *y = w->ydae;
  tree_eval(w, t, tref, Y, NULL);
  for (int c = 0; c < w->nb; c++) {
    double *yc = y + PHM_NSTATE * c;
    phm_H_to_qp_near(w->H + 16 * c, yc, yc, yc + 4);
    memcpy(yc + 7, w->v + 6 * c, sizeof(double) * 6);
  }
  memcpy(y + d->ix, Y, sizeof(double) * (size_t)w->nj);
  memcpy(y + d->ie, Y + 2 * w->nj, sizeof(double) * (size_t)w->nled);
  tree_lambda(w, t, tref, Y, y + d->il);
  for (int i = d->im; i < d->n; i++) y[i] = 0.0;
}

phm_status run_tree(dae_t *d, const phm_sim_options *opt, void *work, SUNContext ctx,
                    N_Vector yy, N_Vector yp, const double *tout, int nout, double E0[1],
                    double nbp, phm_sim_output *out, phm_error *err) {
  (void)ctx;
  (void)yp;
  tree_work *w = work;
  const phm_model *m = d->m;
  const int N = w->N, nj = w->nj;
  const double rtol = opt->rtol, atol = opt->atol;
  const double hmax = opt->max_step > 0 ? opt->max_step : INFINITY;
  const long max_steps = opt->max_steps > 0 ? opt->max_steps : 1000000L;
  double *y0 = N_VGetArrayPointer(yy);
  /* the start: joint coordinates, their rates from the consistent twists, the ledger */
  memcpy(w->ydae, y0, sizeof(double) * (size_t)d->n);
  {
    double *H = d->data.H, *tw = d->data.tw;
    dae_unpack(m, y0, H, tw);
    memcpy(w->y, y0 + d->ix, sizeof(double) * (size_t)nj);
    for (int c = 0; c < w->nb; c++) {
      int ip = w->pair[c], p = w->par[c];
      double x[6], xd[6];
      phm_pair_joint(m, ip, p >= 0 ? H + 16 * p : NULL, H + 16 * c, p >= 0 ? tw + 6 * p : NULL,
                     tw + 6 * c, y0 + d->ix + w->j0[c], x, xd);
      for (int s = 0; s < w->k[c]; s++) w->y[nj + w->j0[c] + s] = xd[s];
    }
    memcpy(w->y + 2 * nj, y0 + d->ie, sizeof(double) * (size_t)w->nled);
  }
  double t = tout[0], tref = d->tref, h = 0, facold = 1e-4;
  long nfev = 0, nacc = 0, nrej = 0, steps_iv = 0;
  int fresh = 1, reject = 0, iout = 1, stop = 0;
  phm_status st = PHM_OK;
  double hmin_seen = INFINITY, hlast = 0.0;
  while (iout < nout) {
    if (fresh) { /* a piece's first stage and step */
      if (tree_eval(w, t, tref, w->y, w->ks[0])) goto singular;
      nfev++;
      h = first_step(w, t, tref, hmax, rtol, atol, &nfev);
      fresh = 0;
    }
    double tend = fmin(tout[nout - 1], nbp);
    int last = 0;
    if (t + 1.01 * h >= tend) { /* the last step to tend, stretched up to 1 % (dopri5's rule) */
      h = tend - t;
      last = 1;
    }
    if (!(h > 16 * DBL_EPSILON * fmax(fabs(t), 1e-300))) {
      st = PHM_FAIL(err, PHM_ESOLVER, "tree: step size %g too small at t = %.9g s", h, t);
      goto done;
    }
    double *k1 = w->ks[0], *k2 = w->ks[1], *k3 = w->ks[2], *k4 = w->ks[3], *k5 = w->ks[4],
           *k6 = w->ks[5], *k7 = w->ks[6], *y = w->y, *yt = w->yt, *y1 = w->y1;
    for (int i = 0; i < N; i++) yt[i] = y[i] + h * A21 * k1[i];
    if (tree_eval(w, t + C2 * h, tref, yt, k2)) goto singular;
    for (int i = 0; i < N; i++) yt[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
    if (tree_eval(w, t + C3 * h, tref, yt, k3)) goto singular;
    for (int i = 0; i < N; i++) yt[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
    if (tree_eval(w, t + C4 * h, tref, yt, k4)) goto singular;
    for (int i = 0; i < N; i++)
      yt[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
    if (tree_eval(w, t + C5 * h, tref, yt, k5)) goto singular;
    for (int i = 0; i < N; i++)
      yt[i] = y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
    double tn = last ? tend : t + h;
    if (tree_eval(w, tn, tref, yt, k6)) goto singular;
    for (int i = 0; i < N; i++)
      y1[i] = y[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
    if (tree_eval(w, tn, tref, y1, k7)) goto singular;
    nfev += 6;
    for (int i = 0; i < N; i++)
      w->err[i] = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
    double en = wnorm(w, w->err, y, y1, rtol, atol);
    if (!isfinite(en)) en = 1e10;
    /* PI control (dopri5: beta 0.04, safety 0.9, factors in [0.2, 10]) */
    double fac11 = pow(en, 0.2 - 0.04 * 0.75);
    double fac = fac11 / pow(facold, 0.04);
    fac = fmax(0.1, fmin(5.0, fac / 0.9));
    double hnew = h / fac;
    if (en <= 1.0) {
      facold = fmax(en, 1e-4);
      nacc++;
      steps_iv++;
      hmin_seen = fmin(hmin_seen, h);
      hlast = h;
      /* a breakpoint at tn: the laws' next piece from there on; an output at tn still reads the
       * piece that ends there (its left limit, as IDA's, which restarts after that output) */
      const int bp = last && tn >= nbp;
      /* the outputs in (t, tn]: the continuous extension; one within round-off after tn is
       * tn's (outputs i dt put simulate(0.3, 0.05)'s last at 0.30000000000000004, and a law's
       * breakpoint at 0.3 would leave a step of 5.6e-17 s to it) */
      const double tn_out = tn + 16 * DBL_EPSILON * fabs(tn);
      int need = iout < nout && tout[iout] <= tn_out;
      if (need) {
        for (int i = 0; i < N; i++) {
          double dy = y1[i] - y[i], bspl = h * k1[i] - dy;
          w->rc[0][i] = y[i];
          w->rc[1][i] = dy;
          w->rc[2][i] = bspl;
          w->rc[3][i] = dy - h * k7[i] - bspl;
          w->rc[4][i] = h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
        }
      }
      while (iout < nout && tout[iout] <= tn_out) {
        const double *Yo = y1;
        if (tout[iout] < tn) {
          double th = (tout[iout] - t) / h, th1 = 1 - th;
          for (int i = 0; i < N; i++)
            yt[i] = w->rc[0][i] + th * (w->rc[1][i] + th1 * (w->rc[2][i] + th * (w->rc[3][i] + th1 * w->rc[4][i])));
          Yo = yt;
        }
        dae_state(w, d, tout[iout], tref, Yo);
        out->nsteps = nacc;
        out->nres = nfev;
        out->netf = nrej;
        out->min_step = hmin_seen;
        if ((st = dae_emit_output(d, w->ydae, out, iout, E0, tout[iout], opt, &stop, err)) || stop) goto done;
        iout++;
        steps_iv = 0;
      }
      memcpy(y, y1, sizeof(double) * (size_t)N);
      memcpy(k1, k7, sizeof(double) * (size_t)N); /* FSAL */
      t = tn;
      if (reject) hnew = fmin(hnew, h);
      reject = 0;
      if (bp) { /* the next piece: its tref, a fresh first stage */
        tref = d->tref = phm_model_tref(m, t, &nbp);
        fresh = 1;
      }
      if (opt->monitor && nacc % PHM_MONITOR_STEPS == 0 && opt->monitor(opt->ctx, t, nacc, h)) {
        st = PHM_FAIL(err, PHM_EINTERRUPT, "interrupted at t = %g s", t);
        goto done;
      }
      if (steps_iv > max_steps) {
        st = PHM_FAIL(err, PHM_ESOLVER, "tree: more than %ld steps between two outputs (t = %.9g s)", max_steps, t);
        goto done;
      }
    } else {
      hnew = h / fmin(5.0, fac11 / 0.9);
      reject = 1;
      nrej++;
    }
    h = fmin(hnew, hmax);
  }
done:
  out->last_step = hlast;
  out->last_order = 5;
  out->nsteps = nacc;
  out->nres = nfev;
  out->netf = nrej;
  out->min_step = isfinite(hmin_seen) ? hmin_seen : 0.0;
  return st;
singular:
  st = PHM_FAIL(err, PHM_ESINGULAR, "tree: a joint's articulated inertia is not positive at "
                "t = %.9g s (a body without mass or inertia along its joint's motion)", t);
  goto done;
}
