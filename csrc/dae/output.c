/* output.c -- what a simulation hands back at each output time (the table of result quantities,
 * csrc/include/phmech_results.h): each array's shape, and record(), which fills them: the
 * recorded poses and twists, multipliers, joint coordinates, rates and efforts, pair wrenches,
 * port energies, the energy ledger, each pair's constraint residual and each element's strain
 * energy; every output checked finite before it counts. */
#include "dae.h"

#include <math.h>
#include <string.h>

#include "phm_check.h"
#include "linalg.h"

int phm_result_shape(const phm_model *m, int nrecord, int f, long dims[3], const char *names[3]) {
  const phm_result_field *r = phm_result_field_at(f);
  if (!r) return 0;
  long n = 0;
  switch (r->over) {
  case PHM_OVER_RECORDED: n = m ? (nrecord >= 0 ? nrecord : m->nc) : 0; names[0] = "carrier"; break;
  case PHM_OVER_CONSTRAINTS: n = m ? m->ncons : 0; names[0] = "constraint"; break;
  case PHM_OVER_ENERGIES: n = PHM_NENERGY; names[0] = "energy_kind"; break;
  case PHM_OVER_JOINTS: n = m ? m->nj : 0; names[0] = "joint"; break;
  case PHM_OVER_PAIRS: n = m ? m->np : 0; names[0] = "pair"; break;
  case PHM_OVER_PORTS: n = m ? m->nport : 0; names[0] = "port"; break;
  case PHM_OVER_COMPONENT_STATES: n = m ? m->nz : 0; names[0] = "component_state"; break;
  case PHM_OVER_ELEMENTS: n = m ? m->ne : 0; names[0] = "element"; break;
  }
  dims[0] = n;
  switch (r->item) {
  case PHM_ITEM_SCALAR: return 1;
  case PHM_ITEM_SCREW: dims[1] = 6; names[1] = "component"; return 2;
  case PHM_ITEM_POSE: dims[1] = dims[2] = 4; names[1] = "row"; names[2] = "col"; return 3;
  }
  return 0;
}

/* Output iout must be finite: a NaN or inf in a result is never handed back silently. PHM_OK, or
 * PHM_ESOLVER naming the quantity (output iout is then not counted as done). */
static phm_status check_output(const dae_t *d, const phm_sim_output *out, int iout, double time,
                               phm_error *err) {
  const int nrecord = out->record ? out->nrecord : -1;
  for (int f = 0; f < PHM_NRESULT_FIELDS; f++) {
    long dims[3];
    const char *names[3];
    size_t n = 1;
    for (int k = phm_result_shape(d->m, nrecord, f, dims, names); k > 0; k--) n *= (size_t)dims[k - 1];
    if (!out->field[f] || !n) continue;
    const double *o = out->field[f] + (size_t)iout * n;
    long j = phm_first_nonfinite(o, n);
    if (j >= 0)
      return PHM_FAIL(err, PHM_ESOLVER,
                           "non-finite %s at t = %.9g s (entry %ld is %g): the model's numbers "
                           "overflow double precision (check for huge or tiny masses, stiffnesses, "
                           "loads, lengths or initial values)",
                           phm_result_field_at(f)->noun, time, j, o[j]);
  }
  return PHM_OK;
}

static void record(dae_t *d, const double *y, phm_sim_output *out, int iout, double E0[1],
                   double time) {
  const phm_model *m = d->m;
  phm_data *D = &d->data;
  int nc = m->nc;
  dae_unpack(m, y, D->H, D->tw);
  if (out->record) { /* only the carriers the caller asked for: memory stays small on long runs */
    for (int k = 0; k < out->nrecord; k++) {
      size_t o = (size_t)iout * out->nrecord + (size_t)k;
      int c = out->record[k];
      if (out->poses) memcpy(out->poses + 16 * o, D->H + 16 * c, sizeof(double) * 16);
      if (out->twists) memcpy(out->twists + 6 * o, D->tw + 6 * c, sizeof(double) * 6);
    }
  } else {
    if (out->poses) memcpy(out->poses + (size_t)iout * 16 * nc, D->H, sizeof(double) * 16 * nc);
    if (out->twists) memcpy(out->twists + (size_t)iout * 6 * nc, D->tw, sizeof(double) * 6 * nc);
  }
  if (out->constraint_wrenches && m->ncons)
    memcpy(out->constraint_wrenches + (size_t)iout * m->ncons, y + d->il, sizeof(double) * m->ncons);
  for (int i = d->im; i < d->n; i++) out->max_mu = fmax(out->max_mu, fabs(y[i]));
  /* every pair once: joint coordinates and rates, constraint wrenches, the actuators' efforts,
   * and the position constraints g when their residuals are asked for */
  dae_eval_pairs(d, time, y,
                 PHM_PAIR_ROWS | PHM_PAIR_JOINT | (out->constraint_residual ? 0 : PHM_PAIR_NO_G));
  for (int ip = 0; ip < m->np; ip++) {
    const phm_pair_data *p = D->pair + ip;
    int j0 = m->pair_j[ip];
    for (int c = 0; c < m->pair_k[ip]; c++) {
      if (out->joints) out->joints[(size_t)iout * m->nj + j0 + c] = p->x[c];
      if (out->joint_rates) out->joint_rates[(size_t)iout * m->nj + j0 + c] = p->xdot[c];
    }
    if (out->pair_wrenches)
      phm_pair_wrench(m, ip, p, y + d->il + m->pair_row[ip],
                      out->pair_wrenches + ((size_t)iout * m->np + ip) * 6);
    if (out->constraint_residual) {
      double r = 0.0;
      for (int k = 0; k < m->pair_m[ip]; k++) r = fmax(r, fabs(p->g[k]));
      out->constraint_residual[(size_t)iout * m->np + ip] = r;
    }
  }
  if (out->efforts && m->nj) {
    phm_applied_pairs(m, D->pair, D->H, D->tw, y + d->ix, time, d->tref, 1.0, D->wr, NULL, NULL,
                      NULL, NULL, D->eff);
    if (m->ncomp) /* the components' efforts too */
      phm_components_apply(m, D->pair, D->H, D->tw, y + d->ix, y + d->iz, NULL, time, d->tref,
                           NULL, D->eff, NULL, NULL, NULL, NULL);
    memcpy(out->efforts + (size_t)iout * m->nj, D->eff, sizeof(double) * (size_t)m->nj);
  }
  if (out->port_energy && m->nport)
    memcpy(out->port_energy + (size_t)iout * m->nport, y + d->ie + 2, sizeof(double) * (size_t)m->nport);
  double e[3];
  phm_model_energy_parts(m, D->H, D->tw, e,
                         out->strain_energy ? out->strain_energy + (size_t)iout * m->ne : NULL);
  if (out->components && m->nz)
    memcpy(out->components + (size_t)iout * m->nz, y + d->iz, sizeof(double) * (size_t)m->nz);
  if (m->ncomp) { /* the components' storage (bristles, inductances) with the elastic energy */
    phm_components_apply(m, D->pair, D->H, D->tw, y + d->ix, y + d->iz, NULL, time, d->tref, NULL,
                         NULL, NULL, e + 1, NULL, NULL);
  }
  double tot = e[0] + e[1] + e[2];
  if (iout == 0) E0[0] = tot;
  if (out->energy) {
    double *o = out->energy + (size_t)iout * PHM_NENERGY;
    o[0] = e[0];
    o[1] = e[1];
    o[2] = e[2];
    o[3] = y[d->ie];
    o[4] = y[d->ie + 1];
    o[5] = tot;
    o[6] = tot - E0[0] - (y[d->ie + 1] - y[d->ie]);
  }
}

/* Store output iout (state y at time t) and call the user's callbacks. PHM_EINTERRUPT if the
 * interrupt callback asks; *stop = 1 if the progress callback asks to stop quietly. */
phm_status dae_emit_output(dae_t *d, const double *y, phm_sim_output *out, int iout, double E0[1],
                              double t, const phm_sim_options *opt, int *stop, phm_error *err) {
  if (d->pl) return dae_planar_emit_output(d, y, out, iout, E0, t, opt, stop, err);
  *stop = 0;
  record(d, y, out, iout, E0, t);
  phm_status st = check_output(d, out, iout, t, err);
  if (st) return st;
  out->nout_done = iout + 1;
  if (opt->interrupt && opt->interrupt(opt->ctx, t, iout))
    return PHM_FAIL(err, PHM_EINTERRUPT, "interrupted at t = %g s", t);
  if (opt->progress && opt->progress(opt->ctx, t, iout)) *stop = 1;
  return PHM_OK;
}
