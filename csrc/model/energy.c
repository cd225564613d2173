/* energy.c -- kinetic, elastic and gravitational energy of a state (the energy ledger's stored
 * part; the dissipated and supplied parts are integrated in the DAE, csrc/dae/residual.c). */
#include "model.h"

#include "linalg.h"

void phm_model_energy(const phm_model *m, const double *H, const double *t, double e[3]) {
  phm_model_energy_parts(m, H, t, e, NULL);
}

void phm_model_energy_parts(const phm_model *m, const double *H, const double *t, double e[3],
                            double *Ve) {
  double K = 0, Vg = 0, Vel = 0;
  for (int c = 0; c < m->nc; c++) {
    if (t) {
      double Mt[6];
      phm_mv6(m->car[c].M, t + 6 * c, Mt);
      K += 0.5 * phm_dot(Mt, t + 6 * c, 6);
    }
    const double *Hc = H + 16 * c, *r = m->car[c].com;
    for (int i = 0; i < 3; i++) {
      double x = Hc[4 * i + 3] + Hc[4 * i] * r[0] + Hc[4 * i + 1] * r[1] + Hc[4 * i + 2] * r[2];
      Vg -= m->car[c].mass * m->gravity[i] * x;
    }
  }
  if (t)
    for (int k = 0; k < m->nmc; k++) {
      const int ca = m->mc_a[k], cb = m->mc_b[k];
      K += phm_element_kinetic(m->mc + 144 * (size_t)k, m->mc_rows + 12 * (size_t)k, t + 6 * ca, t + 6 * cb);
    }
  for (int ie = 0; ie < m->ne; ie++) {
    const phm_element_desc *el = &m->el[ie];
    const double v = phm_element_energy(el, H + 16 * el->a, H + 16 * el->b);
    if (Ve) Ve[ie] = v;
    Vel += v;
  }
  for (int is = 0; is < m->ns; is++) {
    double v = 0;
    phm_spring_eval(&m->spr[is], H, NULL, NULL, &v, NULL);
    Vel += v;
  }
  e[0] = K;
  e[1] = Vel;
  e[2] = Vg;
}
