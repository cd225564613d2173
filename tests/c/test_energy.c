/* test_energy.c -- csrc/model/energy.c: the kinetic, elastic and gravitational energy of a state
 * against closed forms computed here (1/2 t^T M t; h/2 de^T K de with de = log(Ha^-1 Hb)/h -
 * eps_hat; k/2 (d - d0)^2; -m g . x_com), and the applied wrenches of csrc/model/applied.c as
 * minus the gradient of that energy. */
#include "check.h"
#include "model.h"

enum { NC = 3, NS = 2 };

typedef struct {
  phm_carrier_desc car[NC];
  phm_element_desc el;
  phm_spring_desc spr[NS];
  phm_model_desc desc;
} scene;

/* Three carriers (random inertia, mass, centre of mass), an element 0-1, springs 1-2 and
 * ground-2, random gravity. */
static void rand_scene(scene *s) {
  memset(s, 0, sizeof *s);
  for (int c = 0; c < NC; c++) {
    carrier_unit(&s->car[c]);
    rand_spd6(s->car[c].M, 1.0);
    s->car[c].mass = 0.5 + rand01();
    for (int i = 0; i < 3; i++) s->car[c].com[i] = 0.3 * rand11();
  }
  s->el.a = 0;
  s->el.b = 1;
  s->el.h = 0.2 + 0.3 * rand01();
  rand_spd6(s->el.K, 2.0);
  rand_spd6(s->el.D, 0.5);
  s->el.eps_hat[2] = rand11();
  s->el.eps_hat[3] = 1.0;
  for (int k = 0; k < NS; k++) {
    s->spr[k].a = k == 0 ? 1 : -1;
    s->spr[k].b = 2;
    for (int i = 0; i < 3; i++) {
      s->spr[k].pa[i] = rand11();
      s->spr[k].pb[i] = rand11();
    }
    s->spr[k].k = 1 + rand01();
    s->spr[k].c = rand01();
    s->spr[k].d0 = 0.5 * rand01();
  }
  s->desc.ncarriers = NC;
  s->desc.carriers = s->car;
  s->desc.nelements = 1;
  s->desc.elements = &s->el;
  s->desc.nsprings = NS;
  s->desc.springs = s->spr;
  for (int i = 0; i < 3; i++) s->desc.gravity[i] = 10 * rand11();
}

/* The model of a random scene (rand_scene). */
static phm_model *scene_model(scene *s) {
  rand_scene(s);
  return create_model(&s->desc);
}

static void energy_terms_match_their_closed_forms(void) {
  for (int trial = 0; trial < 10; trial++) {
    scene s;
    phm_model *m = scene_model(&s);
    if (!m) return;
    double H[16 * NC], tw[6 * NC], e[3], e0[3];
    for (int c = 0; c < NC; c++) {
      rand_pose(H + 16 * c, 1.0);
      for (int i = 0; i < 6; i++) tw[6 * c + i] = rand11();
    }
    phm_model_energy(m, H, tw, e);
    phm_model_energy(m, H, NULL, e0);
    double K = 0, Vg = 0, Vel = 0;
    for (int c = 0; c < NC; c++) {
      double x[3];
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) K += 0.5 * tw[6 * c + i] * s.car[c].M[6 * i + j] * tw[6 * c + j];
      point_world(H, c, s.car[c].com, x);
      for (int i = 0; i < 3; i++) Vg -= s.car[c].mass * s.desc.gravity[i] * x[i];
    }
    { /* element: h/2 de^T K de */
      double Hai[16], Hab[16], X[6], de[6];
      phm_se3_inverse(H, Hai);
      phm_se3_compose(Hai, H + 16, Hab);
      phm_se3_log(Hab, X);
      for (int i = 0; i < 6; i++) de[i] = X[i] / s.el.h - s.el.eps_hat[i];
      for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) Vel += 0.5 * s.el.h * de[i] * s.el.K[6 * i + j] * de[j];
    }
    for (int k = 0; k < NS; k++) {
      double d = spring_length(&s.spr[k], H) - s.spr[k].d0;
      Vel += 0.5 * s.spr[k].k * d * d;
    }
    check("kinetic energy = sum 1/2 t^T M t", fabs(e[0] - K) / K, 1e-14);
    check("elastic energy = element h/2 de^T K de + springs k/2 (d - d0)^2", fabs(e[1] - Vel) / Vel, 1e-12);
    check("gravity energy = -sum m g . x_com", fabs(e[2] - Vg) / (1 + fabs(Vg)), 1e-14);
    check("no twists: no kinetic energy, the same potential energies",
          fabs(e0[0]) + fabs(e0[1] - e[1]) + fabs(e0[2] - e[2]), 0.0);
    phm_model_free(m);
  }
}

/* The static applied wrenches (element, springs, gravity; phm_applied without twists) are minus
 * the derivative of the elastic + gravity energy for H_c -> H_c exp(delta) (central FD). */
static void static_applied_wrenches_are_minus_the_potential_energy_gradient(void) {
  for (int trial = 0; trial < 10; trial++) {
    scene s;
    phm_model *m = scene_model(&s);
    if (!m) return;
    double H[16 * NC], wr[6 * NC], eps = 1e-6, errmax = 0, wmax = 0;
    for (int c = 0; c < NC; c++) rand_pose(H + 16 * c, 1.0);
    phm_applied(m, H, NULL, NULL, 0.0, 0.5, 1.0, wr, NULL, NULL, NULL, NULL, NULL);
    for (int c = 0; c < NC; c++)
      for (int j = 0; j < 6; j++) {
        double d[6] = {0}, Hp[16 * NC], Hm[16 * NC], ep[3], em[3];
        d[j] = 1;
        memcpy(Hp, H, sizeof Hp);
        memcpy(Hm, H, sizeof Hm);
        perturbed(H + 16 * c, d, eps, Hp + 16 * c);
        perturbed(H + 16 * c, d, -eps, Hm + 16 * c);
        phm_model_energy(m, Hp, NULL, ep);
        phm_model_energy(m, Hm, NULL, em);
        double fd = -((ep[1] + ep[2]) - (em[1] + em[2])) / (2 * eps);
        errmax = fmax(errmax, fabs(fd - wr[6 * c + j]));
        wmax = fmax(wmax, fabs(wr[6 * c + j]));
      }
    check("applied wrenches = -d(elastic + gravity energy)/ddelta (central FD)", errmax / wmax, 1e-6);
    phm_model_free(m);
  }
}

CHECK_MAIN(CHECK_CASE(energy_terms_match_their_closed_forms),
           CHECK_CASE(static_applied_wrenches_are_minus_the_potential_energy_gradient))
