/* test_applied.c -- csrc/model/applied.c, the applied wrenches: an actuator on every pair type
 * (its wrenches deliver u . xdot, the port's power; the PD law), a point-to-point spring-damper
 * (wrenches = minus the gradient of its energy, damping power), loads and interactions (body
 * wrench in closed form, port power, no work on a rigid motion); the closed-form tangent of all
 * of them (phm_applied_tangent) against central differences. */
#include "check.h"
#include "model.h"

/* Every pair type: an actuator's wrenches on the two carriers deliver exactly u . xdot, which is
 * also its port power and the supplied power; its PD effort follows
 * u = -kp (x - x_set - s vec) - kd (xdot - ds vec). */
static void actuator_power_is_effort_times_joint_rate_on_every_pair_type(void) {
  for (int type = 1; type < phm_pair_type_count(); type++)
    for (int trial = 0; trial < 6; trial++) {
      char name[96];
      const char *tn = phm_pair_type(type)->name;
      int k = 6 - phm_pair_type(type)->m;
      phm_pair_desc pr;
      rand_pair(type, trial, &pr);
      double x[6];
      rand_joint_coordinates(type, trial - 2, x);
      pr.has_x0 = 1;
      memcpy(pr.x0, x, sizeof x);
      phm_actuator_desc ac;
      memset(&ac, 0, sizeof ac);
      ac.pair = 0;
      ac.kind = PHM_ACT_PD;
      for (int i = 0; i < 6; i++) {
        ac.kp[i] = 1 + fabs(rand11());
        ac.kd[i] = fabs(rand11());
        ac.x_set[i] = rand11();
        ac.vec[i] = rand11();
      }
      ac.law.kind = PHM_LAW_SINE;
      ac.law.amplitude = 0.5;
      ac.law.frequency = 0.7;
      phm_model *m = two_carrier_model(&pr, &ac, 1);
      if (!m) continue;
      double H[32], h[16], xref[6], tw[12], wr[12], Pp[1], eff[6], Ps = 0, xe[6], xd[6];
      rand_pose(H, 1.0);
      phm_pair_type_pose(type, pr.pitch, x, h);
      place_b(pr.a < 0 ? NULL : H, pr.Ta, pr.Tb, h, H + 16);
      for (int i = 0; i < 6; i++) xref[i] = x[i] + 0.3 * rand11();
      for (int i = 0; i < 12; i++) tw[i] = rand11();
      if (pr.a < 0) for (int i = 0; i < 6; i++) tw[i] = 0;
      phm_applied(m, H, tw, xref, 0.3, 0.3, 1.0, wr, NULL, NULL, &Ps, Pp, eff);
      double pw = 0;
      for (int i = 0; i < 12; i++) pw += wr[i] * tw[i];
      phm_pair_joint(m, 0, pr.a < 0 ? NULL : H, H + 16, pr.a < 0 ? NULL : tw, tw + 6, xref, xe, xd);
      double ux = 0;
      for (int i = 0; i < k; i++) ux += eff[i] * xd[i];
      snprintf(name, sizeof name, "%s: actuator wrench power = u . xdot = port power", tn);
      check(name, fabs(pw - ux) + fabs(Pp[0] - ux) + fabs(Ps - ux), 1e-11 * (1 + fabs(ux)));
      double ds, s = phm_law_eval(&ac.law, 0.3, 0.3, &ds, NULL), eu = 0;
      for (int i = 0; i < k; i++)
        eu = fmax(eu, fabs(eff[i] - (-ac.kp[i] * (xe[i] - ac.x_set[i] - s * ac.vec[i]) - ac.kd[i] * (xd[i] - ds * ac.vec[i]))));
      snprintf(name, sizeof name, "%s: PD effort formula", tn);
      check(name, eu, 1e-12);
      phm_model_free(m);
    }
}

/* A spring-damper between two carriers (or a carrier and the ground): its body wrenches are
 * -dV/ddelta for H -> H exp(delta) (central differences), its damping power is c (dd/dt)^2 and
 * the power of its wrenches is -(dV/dt + damping power). */
static void spring_wrenches_are_minus_its_energy_gradient(void) {
  for (int trial = 0; trial < 12; trial++) {
    phm_spring_desc sp;
    memset(&sp, 0, sizeof sp);
    sp.a = trial % 3 == 0 ? -1 : 0;
    sp.b = 1;
    for (int i = 0; i < 3; i++) {
      sp.pa[i] = rand11();
      sp.pb[i] = rand11();
    }
    sp.k = 1 + fabs(rand11());
    sp.c = trial % 2 ? fabs(rand11()) : 0.0;
    sp.d0 = 0.5 * fabs(rand11());
    double H[32], tw[12], wr[12] = {0}, V, Pd, eps = 1e-6, errmax = 0, wmax = 0;
    rand_pose(H, 1.0);
    rand_pose(H + 16, 1.0);
    phm_spring_eval(&sp, H, NULL, wr, &V, NULL);
    for (int c = sp.a < 0 ? 1 : 0; c < 2; c++)
      for (int j = 0; j < 6; j++) {
        double d[6] = {0}, Hp[32], Hm[32], Vp, Vm;
        d[j] = 1;
        memcpy(Hp, H, sizeof Hp);
        memcpy(Hm, H, sizeof Hm);
        perturbed(H + 16 * c, d, eps, Hp + 16 * c);
        perturbed(H + 16 * c, d, -eps, Hm + 16 * c);
        phm_spring_eval(&sp, Hp, NULL, NULL, &Vp, NULL);
        phm_spring_eval(&sp, Hm, NULL, NULL, &Vm, NULL);
        errmax = fmax(errmax, fabs(-(Vp - Vm) / (2 * eps) - wr[6 * c + j]));
        wmax = fmax(wmax, fabs(wr[6 * c + j]));
      }
    check("spring wrenches = -dV/ddelta (central FD)", errmax / wmax, 1e-6);
    /* rates: power balance and damping power */
    for (int i = 0; i < 12; i++) tw[i] = sp.a < 0 && i < 6 ? 0 : rand11();
    memset(wr, 0, sizeof wr);
    phm_spring_eval(&sp, H, tw, wr, &V, &Pd);
    double tau = 1e-6, H1[32], H2[32], V1, V2, pw = 0;
    perturbed(H, tw, tau, H1);
    perturbed(H + 16, tw + 6, tau, H1 + 16);
    perturbed(H, tw, -tau, H2);
    perturbed(H + 16, tw + 6, -tau, H2 + 16);
    phm_spring_eval(&sp, H1, NULL, NULL, &V1, NULL);
    phm_spring_eval(&sp, H2, NULL, NULL, &V2, NULL);
    double Vdot = (V1 - V2) / (2 * tau);
    for (int i = 0; i < 12; i++) pw += wr[i] * tw[i];
    check("spring power balance (wrench power + dV/dt + damping power = 0)",
          fabs(pw + Vdot + Pd) / (fabs(Vdot) + Pd + 1e-300), 1e-7);
    /* dd/dt by central differences of the distance */
    double dd = (spring_length(&sp, H1) - spring_length(&sp, H2)) / (2 * tau);
    check("spring damping power = c (dd/dt)^2 (FD of the distance)", fabs(Pd - sp.c * dd * dd),
          1e-8 * (1 + sp.c * dd * dd));
  }
}

/* A load law(t) w at a point of carrier 0 (body or world axes): its body wrench in closed form,
 * its port power = the power of the wrenches it applies; with a reaction on carrier 1 the pair
 * of wrenches does no work on a rigid motion of both carriers. */
static void load_wrench_and_port_power(void) {
  for (int trial = 0; trial < 8; trial++) {
    phm_carrier_desc car[2];
    carrier_unit(&car[0]);
    carrier_unit(&car[1]);
    phm_load_desc ld;
    memset(&ld, 0, sizeof ld);
    ld.carrier = 0;
    ld.world = trial % 2;
    ld.reaction = trial % 4 < 2 ? -1 : 1;
    for (int i = 0; i < 3; i++) ld.point[i] = rand11();
    for (int i = 0; i < 6; i++) ld.w[i] = rand11();
    ld.law.kind = PHM_LAW_CONSTANT;
    ld.law.amplitude = 1.3;
    phm_model_desc d = {.ncarriers = 2, .carriers = car, .nloads = 1, .loads = &ld};
    phm_model *m = create_model(&d);
    if (!m) continue;
    double H[32], tw[12], wr[12], Pp[1], Ps, scale = 0.5, s = scale * ld.law.amplitude;
    rand_pose(H, 1.0);
    rand_pose(H + 16, 1.0);
    for (int i = 0; i < 12; i++) tw[i] = rand11();
    phm_applied(m, H, tw, NULL, 0.0, 0.5, scale, wr, NULL, NULL, &Ps, Pp, NULL);
    double tau[3], f[3], w[6];
    for (int i = 0; i < 3; i++) { /* world axes: R^T tau, R^T f */
      tau[i] = s * (ld.world ? H[i] * ld.w[0] + H[4 + i] * ld.w[1] + H[8 + i] * ld.w[2] : ld.w[i]);
      f[i] = s * (ld.world ? H[i] * ld.w[3] + H[4 + i] * ld.w[4] + H[8 + i] * ld.w[5] : ld.w[3 + i]);
    }
    const double *r = ld.point;
    w[0] = tau[0] + r[1] * f[2] - r[2] * f[1];
    w[1] = tau[1] + r[2] * f[0] - r[0] * f[2];
    w[2] = tau[2] + r[0] * f[1] - r[1] * f[0];
    for (int i = 0; i < 3; i++) w[3 + i] = f[i];
    check("load: body wrench = law x (tau + r x f, f) in body axes", maxdiff(6, wr, w), 1e-14);
    double pw = 0;
    for (int i = 0; i < 12; i++) pw += wr[i] * tw[i];
    check("load: port power = supplied power = power of its wrenches", fabs(Pp[0] - pw) + fabs(Ps - pw),
          1e-14 * (1 + fabs(pw)));
    if (ld.reaction >= 0) { /* rigid motion: t_1 = Ad_{H1^-1 H0} t_0 */
      double Hi[16], T[16], Ad[36];
      phm_se3_inverse(H + 16, Hi);
      phm_se3_compose(Hi, H, T);
      phm_se3_Ad(T, Ad);
      for (int i = 0; i < 6; i++) {
        tw[6 + i] = 0;
        for (int j = 0; j < 6; j++) tw[6 + i] += Ad[6 * i + j] * tw[j];
      }
      phm_applied(m, H, tw, NULL, 0.0, 0.5, scale, wr, NULL, NULL, &Ps, Pp, NULL);
      check("interaction: no work on a rigid motion of both carriers", fabs(Pp[0]), 1e-14 * (1 + maxabs(12, wr) * maxabs(12, tw)));
    }
    phm_model_free(m);
  }
}

typedef struct {
  int n6;
  double *K, *T; /* dense d wr/d delta, d wr/d t (6 nc x 6 nc) */
} dense_sink;
static void add_dense(void *ctx, int ca, int cb, const double w[12], const double Kx[144],
                      const double Kt[144]) {
  dense_sink *s = ctx;
  int c[2] = {ca, cb};
  (void)w;
  for (int bi = 0; bi < 2; bi++)
    for (int bj = 0; bj < 2; bj++) {
      if (c[bi] < 0 || c[bj] < 0) continue;
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) {
          size_t e = (size_t)(6 * c[bi] + i) * s->n6 + 6 * c[bj] + j, q = 12 * (6 * bi + i) + 6 * bj + j;
          s->K[e] += Kx[q];
          if (Kt) s->T[e] += Kt[q];
        }
    }
}

/* phm_applied_tangent against central differences (1e-6) of phm_applied in every carrier's pose
 * (H exp(eps e_j)) and twist, at random poses and twists: actuators of every kind (PD, effort,
 * joint spring) on every pair type, between carriers and from the ground; spring-dampers between
 * carriers and to a world point; loads in world and body axes with a reaction carrier or the
 * ground. Each part (pose, twist) to 1e-7 relative to its largest entry. */
static void applied_tangent_is_central_differences(void) {
  enum { NC = 3, N6 = 6 * NC };
  for (int type = 1; type < phm_pair_type_count(); type++)
    for (int trial = 0; trial < 3; trial++) {
      phm_carrier_desc car[NC];
      phm_pair_desc pr[2];
      phm_actuator_desc ac[2];
      phm_spring_desc sp[2];
      phm_load_desc ld[2];
      for (int c = 0; c < NC; c++) carrier_unit(&car[c]);
      memset(ac, 0, sizeof ac);
      for (int p = 0; p < 2; p++) {
        rand_pair(type, 1, &pr[p]);
        pr[p].a = p ? -1 : 0;
        pr[p].b = p ? 2 : 1;
        ac[p].pair = p;
        ac[p].kind = (trial + p) % 3 == 0 ? PHM_ACT_PD : (trial + p) % 3 == 1 ? PHM_ACT_EFFORT : PHM_ACT_SPRING;
        for (int i = 0; i < 6; i++) {
          ac[p].kp[i] = 1 + fabs(rand11());
          ac[p].kd[i] = fabs(rand11());
          ac[p].x_set[i] = rand11();
          ac[p].vec[i] = rand11();
        }
        ac[p].law = (phm_law){.kind = PHM_LAW_SINE, .amplitude = 0.5, .frequency = 0.7};
      }
      sp[0] = (phm_spring_desc){.a = 0, .b = 1, .pa = {0.1, 0, 0.2}, .pb = {0, -0.3, 0}, .k = 30, .c = 0.5, .d0 = 0.5};
      sp[1] = (phm_spring_desc){.a = 2, .b = -1, .pa = {0.2, 0.1, 0}, .pb = {1, 1, 1}, .k = 20, .c = 0.7, .d0 = 0.3};
      ld[0] = (phm_load_desc){.carrier = 1, .reaction = 2, .w = {0.1, 0.2, 0.3, 1, -2, 3}, .world = 1,
                              .point = {0.05, 0.1, 0}, .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 1.0}};
      ld[1] = (phm_load_desc){.carrier = 0, .reaction = trial == 1 ? 2 : -1, .w = {-0.3, 0.2, 0.1, 2, 1, -1},
                              .world = 0, .point = {0, 0.1, -0.2}, .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 1.0}};
      phm_model_desc d = {.ncarriers = NC, .carriers = car, .npairs = 2, .pairs = pr, .nactuators = 2,
                          .actuators = ac, .nsprings = 2, .springs = sp, .nloads = 2, .loads = ld};
      phm_model *m = create_model(&d);
      if (!m) continue;
      double H[16 * NC], tw[N6], xs[12], time = 0.3, tref = 0.5, scale = 0.8;
      for (int c = 0; c < NC; c++) rand_pose(H + 16 * c, 1.0);
      for (int i = 0; i < N6; i++) tw[i] = rand11();
      phm_model_joints(m, H, NULL, xs); /* principal values: no branch jump within the steps */
      static double K[N6 * N6], T[N6 * N6];
      memset(K, 0, sizeof K);
      memset(T, 0, sizeof T);
      dense_sink ds = {N6, K, T};
      phm_applied_tangent(m, NULL, H, tw, xs, time, tref, scale, add_dense, &ds);
      double ek = 0, bk = 0, et = 0, bt = 0, eps = 1e-6;
      for (int c = 0; c < NC; c++)
        for (int j = 0; j < 6; j++) {
          double Hp[16 * NC], Hm[16 * NC], tp[N6], tm[N6], e[6] = {0}, wp[N6], wm[N6], vp[N6], vm[N6];
          e[j] = 1.0;
          memcpy(Hp, H, sizeof Hp);
          memcpy(Hm, H, sizeof Hm);
          perturbed(H + 16 * c, e, eps, Hp + 16 * c);
          perturbed(H + 16 * c, e, -eps, Hm + 16 * c);
          phm_applied(m, Hp, tw, xs, time, tref, scale, wp, NULL, NULL, NULL, NULL, NULL);
          phm_applied(m, Hm, tw, xs, time, tref, scale, wm, NULL, NULL, NULL, NULL, NULL);
          memcpy(tp, tw, sizeof tp);
          memcpy(tm, tw, sizeof tm);
          tp[6 * c + j] += eps;
          tm[6 * c + j] -= eps;
          phm_applied(m, H, tp, xs, time, tref, scale, vp, NULL, NULL, NULL, NULL, NULL);
          phm_applied(m, H, tm, xs, time, tref, scale, vm, NULL, NULL, NULL, NULL, NULL);
          for (int i = 0; i < N6; i++) {
            double rk = (wp[i] - wm[i]) / (2 * eps), rt = (vp[i] - vm[i]) / (2 * eps);
            ek = fmax(ek, fabs(rk - K[N6 * i + 6 * c + j]));
            bk = fmax(bk, fabs(rk));
            et = fmax(et, fabs(rt - T[N6 * i + 6 * c + j]));
            bt = fmax(bt, fabs(rt));
          }
        }
      check_worst("applied tangent = central FD: d(actuators, springs, loads)/dpose", ek / bk, 1e-7);
      check_worst("applied tangent = central FD: d(actuators, springs)/dtwist", et / bt, 1e-7);
      if (!(ek <= 1e-7 * bk && et <= 1e-7 * bt))
        printf("  (%s, trial %d: pose %.2e, twist %.2e)\n", phm_pair_type(type)->name, trial, ek / bk, et / bt);
      phm_model_free(m);
    }
}

CHECK_MAIN(CHECK_CASE(actuator_power_is_effort_times_joint_rate_on_every_pair_type),
           CHECK_CASE(spring_wrenches_are_minus_its_energy_gradient),
           CHECK_CASE(load_wrench_and_port_power),
           CHECK_CASE(applied_tangent_is_central_differences))
