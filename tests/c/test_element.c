/* test_element.c -- csrc/model/element.c, the se3 beam element: its node wrenches against central
 * finite differences of its elastic energy, its power balance and dissipation, and
 * phm_model_stress_resultants against sigma = K (log(Ha^-1 Hb)/h - eps_hat) + D eps' computed
 * here (eps' by central differences); the consistent mass (its rigid-motion energy, its
 * gyroscopic terms' power). */
#include "check.h"
#include "model.h"
#include "linalg.h"

/* A random element: length in [0.1, 0.5), K and D symmetric positive definite, a curved
 * unstressed shape (kappa_x, kappa_z, stretch 1). */
static void rand_element(phm_element_desc *e) {
  memset(e, 0, sizeof *e);
  e->h = 0.1 + 0.4 * fabs(rand11());
  rand_spd6(e->K, 2.0);
  rand_spd6(e->D, 0.5);
  e->eps_hat[0] = 0.5 * rand11();
  e->eps_hat[2] = 2.0 * rand11();
  e->eps_hat[3] = 1.0;
}

static void element_wrenches_are_minus_energy_gradient_and_power_balances(void) {
  for (int trial = 0; trial < 20; trial++) {
    phm_element_desc e;
    rand_element(&e);
    double Ha[16], Hb[16], E[16], x[6];
    rand_pose(Ha, 1.0);
    for (int i = 0; i < 6; i++) x[i] = e.h * (e.eps_hat[i] + 0.3 * rand11()); /* large strain */
    if (trial % 4 == 0) for (int i = 0; i < 3; i++) x[i] *= 8.0;          /* rotations up to ~ 3 rad */
    phm_se3_exp(x, E);
    phm_se3_compose(Ha, E, Hb);
    double wa[6], wb[6], V;
    phm_element_eval(&e, Ha, Hb, NULL, NULL, wa, wb, &V, NULL, NULL);
    /* generalized force = -dV/d(delta) for H -> H exp(delta) */
    double errmax = 0, wmax = 0, eps = 1e-6;
    for (int node = 0; node < 2; node++)
      for (int j = 0; j < 6; j++) {
        double d[6] = {0}, Hp[16], Hm[16], Vp, Vm, ta[6], tb[6];
        d[j] = 1;
        perturbed(node ? Hb : Ha, d, eps, Hp);
        perturbed(node ? Hb : Ha, d, -eps, Hm);
        phm_element_eval(&e, node ? Ha : Hp, node ? Hp : Hb, NULL, NULL, ta, tb, &Vp, NULL, NULL);
        phm_element_eval(&e, node ? Ha : Hm, node ? Hm : Hb, NULL, NULL, ta, tb, &Vm, NULL, NULL);
        double fd = -(Vp - Vm) / (2 * eps), w = node ? wb[j] : wa[j];
        errmax = fmax(errmax, fabs(fd - w));
        wmax = fmax(wmax, fabs(w));
      }
    check("element wrenches = -dV/ddelta (central FD)", errmax / (wmax + 1e-300), 1e-6);
    /* power balance: wa.ta + wb.tb + dV/dt + P_diss = 0 */
    double ta[6], tb[6];
    for (int i = 0; i < 6; i++) {
      ta[i] = rand11();
      tb[i] = rand11();
    }
    double P, V1, V2, dummy[6], dummy2[6];
    phm_element_eval(&e, Ha, Hb, ta, tb, wa, wb, &V, &P, NULL);
    double tau = 1e-6, H1a[16], H1b[16], H2a[16], H2b[16];
    perturbed(Ha, ta, tau, H1a);
    perturbed(Hb, tb, tau, H1b);
    perturbed(Ha, ta, -tau, H2a);
    perturbed(Hb, tb, -tau, H2b);
    phm_element_eval(&e, H1a, H1b, NULL, NULL, dummy, dummy2, &V1, NULL, NULL);
    phm_element_eval(&e, H2a, H2b, NULL, NULL, dummy, dummy2, &V2, NULL, NULL);
    double Vdot = (V1 - V2) / (2 * tau), pw = 0, scale = fabs(Vdot) + P;
    for (int i = 0; i < 6; i++) pw += wa[i] * ta[i] + wb[i] * tb[i];
    check("element power balance (node powers + dV/dt + dissipation = 0)", fabs(pw + Vdot + P) / scale, 1e-7);
    check("element dissipation >= 0", P >= 0 ? 0 : -P, 0);
  }
}

/* Strain log(Ha^-1 Hb)/h of an element at poses H (carriers a, b). */
static void strain(const phm_element_desc *e, const double *H, double eps[6]) {
  double Hai[16], Hab[16], X[6];
  phm_se3_inverse(H + 16 * e->a, Hai);
  phm_se3_compose(Hai, H + 16 * e->b, Hab);
  phm_se3_log(Hab, X);
  for (int i = 0; i < 6; i++) eps[i] = X[i] / e->h;
}

/* Four carriers, three elements (0-1, 1-2, 3-0: not every element between consecutive
 * carriers): sigma = K (eps - eps_hat) without twists, + D eps' with twists. */
static void stress_resultants_are_stiffness_times_strain_plus_damping_times_rate(void) {
  enum { NC = 4, NE = 3 };
  for (int trial = 0; trial < 10; trial++) {
    phm_carrier_desc car[NC];
    phm_element_desc el[NE];
    const int ends[NE][2] = {{0, 1}, {1, 2}, {3, 0}};
    double H[16 * NC], tw[6 * NC];
    for (int c = 0; c < NC; c++) {
      carrier_unit(&car[c]);
      for (int i = 0; i < 6; i++) tw[6 * c + i] = rand11();
    }
    rand_pose(H, 1.0);
    for (int ie = 0; ie < NE; ie++) {
      rand_element(&el[ie]);
      el[ie].a = ends[ie][0];
      el[ie].b = ends[ie][1];
    }
    for (int c = 1; c < NC; c++) { /* each carrier a strained element length from the previous */
      double x[6], E[16];
      for (int i = 0; i < 6; i++) x[i] = 0.3 * (el[0].eps_hat[i] + 0.3 * rand11());
      phm_se3_exp(x, E);
      phm_se3_compose(H + 16 * (c - 1), E, H + 16 * c);
    }
    phm_model_desc d = {.ncarriers = NC, .carriers = car, .nelements = NE, .elements = el};
    phm_model *m = create_model(&d);
    if (!m) return;
    double sig[6 * NE], sigt[6 * NE];
    phm_model_stress_resultants(m, H, NULL, sig);
    phm_model_stress_resultants(m, H, tw, sigt);
    for (int ie = 0; ie < NE; ie++) {
      const phm_element_desc *e = &el[ie];
      double eps[6], de[6], ref[6], epsdot[6], Hp[16 * NC], Hm[16 * NC], ep[6], em[6], tau = 1e-6;
      strain(e, H, eps);
      for (int i = 0; i < 6; i++) de[i] = eps[i] - e->eps_hat[i];
      for (int i = 0; i < 6; i++) {
        ref[i] = 0;
        for (int j = 0; j < 6; j++) ref[i] += e->K[6 * i + j] * de[j];
      }
      check("stress resultant = K (log(Ha^-1 Hb)/h - eps_hat)",
            maxdiff(6, sig + 6 * ie, ref) / maxabs(6, ref), 1e-12);
      for (int c = 0; c < NC; c++) {
        perturbed(H + 16 * c, tw + 6 * c, tau, Hp + 16 * c);
        perturbed(H + 16 * c, tw + 6 * c, -tau, Hm + 16 * c);
      }
      strain(e, Hp, ep);
      strain(e, Hm, em);
      for (int i = 0; i < 6; i++) epsdot[i] = (ep[i] - em[i]) / (2 * tau);
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) ref[i] += e->D[6 * i + j] * epsdot[j];
      check("stress resultant with twists = K (eps - eps_hat) + D eps' (eps' by central FD)",
            maxdiff(6, sigt + 6 * ie, ref) / maxabs(6, ref), 1e-7);
    }
    phm_model_free(m);
  }
}

/* phm_element_tangent against central differences of phm_element_eval: Kx column j by the
 * perturbations H exp(+-s e_j) of one node (s = 1e-6: truncation ~ 1e-12, round-off ~ 1e-10 of
 * wrenches of order 1), Ct by perturbing one twist component (the wrenches are affine in the
 * twists: only round-off). At bent, twisted, stretched and moving states (rotations up to ~ 3
 * rad in a quarter of the trials); its wrenches are phm_element_eval's, bit for bit. */
static void element_tangent_is_the_derivative_of_its_wrenches(void) {
  for (int trial = 0; trial < 40; trial++) {
    phm_element_desc e;
    rand_element(&e);
    double Ha[16], Hb[16], E[16], x[6], ta[6], tb[6];
    rand_pose(Ha, 1.0);
    for (int i = 0; i < 6; i++) x[i] = e.h * (e.eps_hat[i] + 0.3 * rand11());
    if (trial % 4 == 0) for (int i = 0; i < 3; i++) x[i] *= 8.0;
    phm_se3_exp(x, E);
    phm_se3_compose(Ha, E, Hb);
    for (int i = 0; i < 6; i++) {
      ta[i] = 2.0 * rand11();
      tb[i] = 2.0 * rand11();
    }
    int moving = trial % 2;
    const double *pa = moving ? ta : NULL, *pb = moving ? tb : NULL;
    double wa[6], wb[6], wa0[6], wb0[6], Kx[144], Ct[144];
    phm_element_tangent(&e, Ha, Hb, pa, pb, wa, wb, Kx, Ct);
    phm_element_eval(&e, Ha, Hb, pa, pb, wa0, wb0, NULL, NULL, NULL);
    check("tangent's wrenches = phm_element_eval's", fmax(maxdiff(6, wa, wa0), maxdiff(6, wb, wb0)), 0.0);
    double err = 0, big = 0, errt = 0, bigt = 0, s = 1e-6;
    for (int node = 0; node < 2; node++)
      for (int j = 0; j < 6; j++) {
        double d[6] = {0}, Hp[16], Hm[16], ap[6], bp[6], am[6], bm[6];
        d[j] = 1;
        perturbed(node ? Hb : Ha, d, s, Hp);
        perturbed(node ? Hb : Ha, d, -s, Hm);
        phm_element_eval(&e, node ? Ha : Hp, node ? Hp : Hb, pa, pb, ap, bp, NULL, NULL, NULL);
        phm_element_eval(&e, node ? Ha : Hm, node ? Hm : Hb, pa, pb, am, bm, NULL, NULL, NULL);
        for (int i = 0; i < 6; i++) {
          double fa = (ap[i] - am[i]) / (2 * s), fb = (bp[i] - bm[i]) / (2 * s);
          err = fmax(err, fmax(fabs(fa - Kx[12 * i + 6 * node + j]), fabs(fb - Kx[12 * (6 + i) + 6 * node + j])));
          big = fmax(big, fmax(fabs(Kx[12 * i + 6 * node + j]), fabs(Kx[12 * (6 + i) + 6 * node + j])));
        }
        double tp[12], tm[12], st = 1e-3;
        memcpy(tp, ta, sizeof ta);
        memcpy(tp + 6, tb, sizeof tb);
        memcpy(tm, tp, sizeof tp);
        tp[6 * node + j] += st;
        tm[6 * node + j] -= st;
        phm_element_eval(&e, Ha, Hb, tp, tp + 6, ap, bp, NULL, NULL, NULL);
        phm_element_eval(&e, Ha, Hb, tm, tm + 6, am, bm, NULL, NULL, NULL);
        for (int i = 0; i < 6; i++) {
          double fa = (ap[i] - am[i]) / (2 * st), fb = (bp[i] - bm[i]) / (2 * st);
          double ca = moving ? Ct[12 * i + 6 * node + j] : 0, cb = moving ? Ct[12 * (6 + i) + 6 * node + j] : 0;
          if (!moving) { /* without twists Ct is zero and the wrenches do not see them */
            check("Ct = 0 without twists", fabs(Ct[12 * i + 6 * node + j]) + fabs(Ct[12 * (6 + i) + 6 * node + j]), 0.0);
            continue;
          }
          errt = fmax(errt, fmax(fabs(fa - ca), fabs(fb - cb)));
          bigt = fmax(bigt, fmax(fabs(ca), fabs(cb)));
        }
      }
    check_worst("element stiffness Kx = central FD of the wrenches", err / big, 1e-7);
    if (moving) check_worst("element damping tangent Ct = central FD", errt / bigt, 1e-7);
  }
}

/* The consistent mass (phm_element_mass): its helix part, Mc + diag(h/2 Ms, h/2 Ms) - (h/12) d^T
 * Ms d, gives a rigidly moving element (t_b = Ad_{exp(-X)} t_a) the kinetic energy of its
 * sections integrated here independently (composite Simpson, 400 intervals, of
 * 1/2 (Ad_{exp(-s eps_hat)} t_a)^T Ms (...) over s in [0, h]); Mc is symmetric; the couplings'
 * gyroscopic terms do no work: t . f = t . Mc t' (phm_element_inertia). */
static void consistent_mass_is_the_helix_energy_and_its_gyroscopic_terms_do_no_work(void) {
  for (int trial = 0; trial < 20; trial++) {
    phm_element_desc e;
    rand_element(&e);
    rand_spd6(e.Ms, 1.0);
    double Mc[144], X[6], E[16], AdE[36], ta[6], tb[6], t[12];
    phm_element_mass(e.h, e.Ms, e.eps_hat, Mc);
    double asym = 0;
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++) asym = fmax(asym, fabs(Mc[12 * i + j] - Mc[12 * j + i]));
    check_worst("consistent mass Mc is symmetric", asym / maxabs(144, Mc), 0.0);
    for (int i = 0; i < 6; i++) X[i] = e.h * e.eps_hat[i], ta[i] = rand11();
    phm_se3_exp(X, E);
    double Ei[16];
    phm_se3_inverse(E, Ei);
    phm_se3_Ad(Ei, AdE);
    phm_mv6(AdE, ta, tb);
    memcpy(t, ta, sizeof ta);
    memcpy(t + 6, tb, sizeof tb);
    /* the helix part's energy */
    double Kh = 0, d[6];
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++) Kh += 0.5 * t[i] * Mc[12 * i + j] * t[j];
    double Mta[6], Mtb[6];
    phm_mv6(e.Ms, ta, Mta);
    phm_mv6(e.Ms, tb, Mtb);
    Kh += 0.25 * e.h * (phm_dot(ta, Mta, 6) + phm_dot(tb, Mtb, 6));
    for (int i = 0; i < 3; i++) { /* d = t_b - Ad_{R0^T} t_a */
      d[i] = tb[i] - (E[i] * ta[0] + E[4 + i] * ta[1] + E[8 + i] * ta[2]);
      d[3 + i] = tb[3 + i] - (E[i] * ta[3] + E[4 + i] * ta[4] + E[8 + i] * ta[5]);
    }
    double Md[6];
    phm_mv6(e.Ms, d, Md);
    Kh -= 0.5 * e.h / 12.0 * phm_dot(d, Md, 6);
    /* the sections' energy, Simpson */
    int n = 400;
    double Kref = 0;
    for (int k = 0; k <= n; k++) {
      double s = e.h * k / n, Y[6], G[16], Gi[16], Ad[36], ts[6], Mts[6];
      for (int i = 0; i < 6; i++) Y[i] = s * e.eps_hat[i];
      phm_se3_exp(Y, G);
      phm_se3_inverse(G, Gi);
      phm_se3_Ad(Gi, Ad);
      phm_mv6(Ad, ta, ts);
      phm_mv6(e.Ms, ts, Mts);
      double wgt = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
      Kref += wgt * 0.5 * phm_dot(ts, Mts, 6);
    }
    Kref *= e.h / (3.0 * n);
    check_worst("consistent mass: rigid motion's helix energy = sections' energy (Simpson)",
                fabs(Kh - Kref) / Kref, 1e-10);
    /* gyroscopic terms do no work */
    double dta[6], dtb[6], f[12], u[12];
    for (int i = 0; i < 6; i++) ta[i] = rand11(), tb[i] = rand11(), dta[i] = rand11(), dtb[i] = rand11();
    unsigned short rows[12], dense[12];
    phm_mass_rows(Mc, rows);
    for (int i = 0; i < 12; i++) dense[i] = 0xfff;
    phm_element_inertia(Mc, rows, ta, tb, dta, dtb, 0.0, f, NULL);
    memcpy(t, ta, sizeof ta);
    memcpy(t + 6, tb, sizeof tb);
    double td[12], P = 0, Pref = 0, scale = 0;
    memcpy(td, dta, sizeof dta);
    memcpy(td + 6, dtb, sizeof dtb);
    for (int i = 0; i < 12; i++) {
      u[i] = 0;
      for (int j = 0; j < 12; j++) u[i] += Mc[12 * i + j] * td[j];
      P += t[i] * f[i];
      Pref += t[i] * u[i];
      scale += fabs(t[i] * u[i]);
    }
    check_worst("consistent mass: t . f = d/dt (1/2 t^T Mc t)", fabs(P - Pref) / scale, 1e-13);
    /* Mc's pattern and the twists' zeros skip only zero products: the same numbers as every
     * product summed (a planar twist: zero out-of-plane components; a straight element's Mc) */
    double Ms0[36] = {0}, eps0[6] = {0, 0, 0, 1, 0, 0}, Mc0[144];
    for (int i = 0; i < 6; i++) Ms0[7 * i] = 1.0 + rand11() * 0.5;
    phm_element_mass(e.h, Ms0, eps0, Mc0);
    phm_mass_rows(Mc0, rows);
    int nnz = 0;
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++) nnz += rows[i] >> j & 1;
    CHECK(nnz < 144, "a straight element's Mc has zeros (%d nonzeros)", nnz);
    for (int i = 0; i < 6; i++) {
      int inplane = i == 2 || i == 3 || i == 4; /* omega_z, v_x, v_y */
      ta[i] *= inplane, tb[i] *= inplane, dta[i] *= inplane, dtb[i] *= inplane;
    }
    double fs[12], fd[12];
    phm_element_inertia(Mc0, rows, ta, tb, dta, dtb, 0.0, fs, NULL);
    phm_element_inertia(Mc0, dense, ta, tb, dta, dtb, 0.0, fd, NULL);
    CHECK(memcmp(fs, fd, sizeof fs) == 0, "consistent mass: the sparse products are the dense ones, bit for bit");
    double Ks = phm_element_kinetic(Mc0, rows, ta, tb), Kd = 0;
    memcpy(t, ta, sizeof ta);
    memcpy(t + 6, tb, sizeof tb);
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++) Kd += t[i] * Mc0[12 * i + j] * t[j];
    CHECK(Ks == 0.5 * Kd, "consistent mass: the sparse kinetic energy is the dense sum, bit for bit");
  }
}

CHECK_MAIN(CHECK_CASE(element_wrenches_are_minus_energy_gradient_and_power_balances),
           CHECK_CASE(consistent_mass_is_the_helix_energy_and_its_gyroscopic_terms_do_no_work),
           CHECK_CASE(stress_resultants_are_stiffness_times_strain_plus_damping_times_rate),
           CHECK_CASE(element_tangent_is_the_derivative_of_its_wrenches))
