/* fmu.c -- phmech's FMU instance (fmu.h): the model file, the model built from it, the state and a
 * step, for the FMI 2.0 (fmi2.c) and FMI 3.0 (fmi3.c) co-simulation functions (python/phmech/fmu.py
 * writes the FMU; docs/user_guide.md, "Mechanisms as FMUs").
 *
 * The model comes from resources/model.phm, written by phmech.export_fmu: a sequence of records
 *   key (ASCII, NUL-terminated) | uint64 n (little-endian) | n float64 (little-endian)
 * holding the exact inputs of phm_model_create (the columns of python/phmech/_marshal.py, at
 * the consistent initial configuration phmech found), the integrator options, and the FMU's
 * variables (inputs, outputs). Time laws are encoded as flat numbers (law_decode). No Python.
 *
 * Inputs are held constant over a communication step (zero-order hold): the law of each input
 * (an effort actuator's or an applied wrench's) is a CALLBACK law returning the current input
 * value. A step (fmu_advance) integrates from the state reached at the end of the previous step
 * (poses, twists, and the joint coordinates as branch references) to t + h with phm_simulate;
 * its consistent-initial-value projection at the start of each step leaves a consistent state
 * unchanged up to the solver's tolerance. */
#define _POSIX_C_SOURCE 200809L /* strdup */
#include "fmu.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FMU_FILE "model.phm"

/* ------------------------------------------------------------------ logging */
void fmu_log(fmu *c, fmi2Status st, const char *fmt, ...) {
  if (!c || (!c->cb.logger && !c->log3)) return;
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (c->log3) { /* fmi2Status and fmi3Status number OK, Warning, Discard, Error alike */
    c->log3(c->env3, (fmi3Status)st, st == fmi2OK ? "logAll" : "logStatusError", buf);
    return;
  }
  c->cb.logger(c->cb.componentEnvironment, c->name, st, st == fmi2OK ? "logAll" : "logStatusError", "%s", buf);
}

/* ------------------------------------------------------------------ the file */
static void free_records(record *r, int n) {
  for (int i = 0; i < n; i++) {
    free(r[i].key);
    free(r[i].v);
  }
  free(r);
}

static int read_records(const char *path, record **out, int *nout, char *msg, size_t nmsg) {
  FILE *f = fopen(path, "rb");
  if (!f) {
    snprintf(msg, nmsg, "cannot open %s", path);
    return -1;
  }
  record *r = NULL;
  int n = 0, cap = 0;
  for (;;) {
    char key[256];
    int k = 0, ch;
    while ((ch = fgetc(f)) != EOF && ch != 0 && k < 255) key[k++] = (char)ch;
    if (ch == EOF && k == 0) break;
    if (ch != 0) goto bad;
    key[k] = 0;
    unsigned char nb[8];
    if (fread(nb, 1, 8, f) != 8) goto bad;
    uint64_t cnt = 0;
    for (int i = 7; i >= 0; i--) cnt = (cnt << 8) | nb[i];
    if (cnt > (uint64_t)1 << 32) goto bad;
    if (n == cap) {
      cap = cap ? 2 * cap : 64;
      record *nr = realloc(r, (size_t)cap * sizeof *r);
      if (!nr) goto bad;
      r = nr;
    }
    r[n].key = malloc((size_t)k + 1);
    r[n].v = malloc(cnt ? (size_t)cnt * sizeof(double) : 1);
    r[n].n = cnt;
    if (!r[n].key || !r[n].v) {
      free(r[n].key);
      free(r[n].v);
      goto bad;
    }
    memcpy(r[n].key, key, (size_t)k + 1);
    n++;
    if (cnt && fread(r[n - 1].v, sizeof(double), (size_t)cnt, f) != cnt) goto bad; /* x86-64: LE */
  }
  fclose(f);
  *out = r;
  *nout = n;
  return 0;
bad:
  fclose(f);
  free_records(r, n);
  snprintf(msg, nmsg, "%s: malformed (not written by phmech.export_fmu?)", path);
  return -1;
}

const record *fmu_record(const fmu *c, const char *key) {
  for (int i = 0; i < c->nrec; i++)
    if (strcmp(c->rec[i].key, key) == 0) return &c->rec[i];
  return NULL;
}

/* The record `kind.key` with n * width numbers (NULL, and *ok = 0, if missing or mis-sized). */
static const double *col(const fmu *c, const char *kind, const char *key, int n, int width, int *ok) {
  char k[128];
  snprintf(k, sizeof k, "%s.%s", kind, key);
  const record *r = fmu_record(c, k);
  if (!r || r->n != (uint64_t)n * (uint64_t)width) {
    *ok = 0;
    return NULL;
  }
  return r->v;
}

/* ------------------------------------------------------------------ laws
 * A law, flat: kind, amplitude, t0, duration, frequency, phase, offset, order, ndata, data[ndata],
 * nnodes, then the nnodes node laws the same way (kind -1: no law). Returns the numbers read, or
 * -1. `nodes`: where an expression's nodes go (a block with room for them: *used advances). */
static long law_decode(const double *v, long avail, phm_law *law, phm_law *nodes, int room, int *used,
                       int depth) {
  memset(law, 0, sizeof *law);
  if (avail < 10) return -1;
  law->kind = (int)v[0];
  law->amplitude = v[1];
  law->t0 = v[2];
  law->duration = v[3];
  law->frequency = v[4];
  law->phase = v[5];
  law->offset = v[6];
  law->order = (int)v[7];
  long nd = (long)v[8];
  if (nd < 0 || 9 + nd + 1 > avail) return -1;
  law->table = nd ? v + 9 : NULL;
  if (law->kind == PHM_LAW_TABLE) law->ntable = (int)(nd / 2);
  else if (law->kind == PHM_LAW_PPOLY) law->ntable = law->order > 0 ? (int)((nd - 1) / (law->order + 1)) : 0;
  else law->ntable = (int)nd;
  long pos = 9 + nd;
  int nn = (int)v[pos++];
  if (nn < 0 || (nn && (depth > 0 || *used + nn > room))) return -1;
  if (nn) {
    law->nodes = nodes + *used;
    law->nnodes = nn;
    phm_law *mine = nodes + *used;
    *used += nn;
    for (int i = 0; i < nn; i++) {
      long r = law_decode(v + pos, avail - pos, &mine[i], nodes, room, used, depth + 1);
      if (r < 0) return -1;
      pos += r;
    }
  }
  return pos;
}

/* The laws of record `kind.key`, `per` laws per component (n components), into the law field at
 * byte offset `off` (+ j sizeof(phm_law) for the j-th of a component) of each struct. */
static int decode_laws(fmu *c, const char *kind, const char *key, int n, int per, char *items,
                       size_t size, size_t off, int slot, int *xbits) {
  char k[128];
  snprintf(k, sizeof k, "%s.%s", kind, key);
  const record *r = fmu_record(c, k);
  if (!r) return n == 0 ? 0 : -1;
  int room = (int)r->n / 10 + 1, used = 0;
  phm_law *nodes = calloc((size_t)room, sizeof(phm_law));
  if (!nodes) return -1;
  c->law_nodes[slot] = nodes;
  long pos = 0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < per; j++) {
      phm_law tmp;
      long got = law_decode(r->v + pos, (long)r->n - pos, &tmp, nodes, room, &used, 0);
      if (got < 0) return -1;
      pos += got;
      if (tmp.kind < 0) continue;
      memcpy(items + (size_t)i * size + off + (size_t)j * sizeof(phm_law), &tmp, sizeof tmp);
      if (xbits) xbits[i] |= 1 << j;
    }
  return pos == (long)r->n ? 0 : -1;
}

/* CALLBACK law of an input: its current value, held. */
static int input_law(void *ctx, double t, int nder, double out[3]) {
  (void)t;
  (void)nder;
  out[0] = *(const double *)ctx;
  out[1] = out[2] = 0;
  return 0;
}

static int to_i(double v) { return (int)lround(v); }

/* Fill c->desc from the records. 0, or -1 with a message. */
static int build_desc(fmu *c, char *msg, size_t nmsg) {
  int ok = 1;
  const record *sz = fmu_record(c, "sizes");
  if (!sz || sz->n != 7) {
    snprintf(msg, nmsg, "model file: no sizes record");
    return -1;
  }
  int n[7];
  for (int i = 0; i < 7; i++) n[i] = to_i(sz->v[i]);
  phm_carrier_desc *car = calloc((size_t)n[0] + 1, sizeof *car);
  phm_element_desc *el = calloc((size_t)n[1] + 1, sizeof *el);
  phm_pair_desc *pr = calloc((size_t)n[2] + 1, sizeof *pr);
  phm_load_desc *ld = calloc((size_t)n[3] + 1, sizeof *ld);
  phm_actuator_desc *ac = calloc((size_t)n[4] + 1, sizeof *ac);
  phm_spring_desc *sp = calloc((size_t)n[5] + 1, sizeof *sp);
  phm_coupling_desc *cp = calloc((size_t)n[6] + 1, sizeof *cp);
  c->desc = (phm_model_desc){.ncarriers = n[0], .carriers = car, .nelements = n[1], .elements = el,
                             .npairs = n[2], .pairs = pr, .nloads = n[3], .loads = ld,
                             .nactuators = n[4], .actuators = ac, .nsprings = n[5], .springs = sp,
                             .ncouplings = n[6], .couplings = cp};
  if (!car || !el || !pr || !ld || !ac || !sp || !cp) {
    snprintf(msg, nmsg, "out of memory");
    return -1;
  }
  const double *v;
#define REALS(kind, key, nn, w, dst) \
  if ((v = col(c, kind, key, nn, w, &ok))) \
    for (int i = 0; i < nn; i++) memcpy(dst, v + (size_t)i * (w), (w) * sizeof(double));
  REALS("carriers", "M", n[0], 36, car[i].M)
  REALS("carriers", "mass", n[0], 1, &car[i].mass)
  REALS("carriers", "com", n[0], 3, car[i].com)
  REALS("carriers", "H0", n[0], 16, car[i].H0)
  REALS("carriers", "t0", n[0], 6, car[i].t0)
  REALS("elements", "h", n[1], 1, &el[i].h)
  if ((v = col(c, "elements", "nodes", n[1], 2, &ok)))
    for (int i = 0; i < n[1]; i++) { el[i].a = to_i(v[2 * i]); el[i].b = to_i(v[2 * i + 1]); }
  REALS("elements", "K", n[1], 36, el[i].K)
  REALS("elements", "D", n[1], 36, el[i].D)
  REALS("elements", "eps_hat", n[1], 6, el[i].eps_hat)
  if ((v = col(c, "elements", "mass", n[1], 1, &ok)))
    for (int i = 0; i < n[1]; i++) el[i].mass = to_i(v[i]);
  REALS("elements", "Ms", n[1], 36, el[i].Ms)
  REALS("elements", "Mc", n[1], 144, el[i].Mc)
  if ((v = col(c, "pairs", "type", n[2], 1, &ok)))
    for (int i = 0; i < n[2]; i++) pr[i].type = to_i(v[i]);
  if ((v = col(c, "pairs", "carriers", n[2], 2, &ok)))
    for (int i = 0; i < n[2]; i++) { pr[i].a = to_i(v[2 * i]); pr[i].b = to_i(v[2 * i + 1]); }
  REALS("pairs", "Ta", n[2], 16, pr[i].Ta)
  REALS("pairs", "Tb", n[2], 16, pr[i].Tb)
  if ((v = col(c, "pairs", "driven", n[2], 1, &ok)))
    for (int i = 0; i < n[2]; i++) pr[i].driven = v[i] != 0;
  REALS("pairs", "axis", n[2], 6, pr[i].axis)
  REALS("pairs", "pitch", n[2], 1, &pr[i].pitch)
  REALS("pairs", "x0", n[2], 6, pr[i].x0)
  if ((v = col(c, "pairs", "has_x0", n[2], 1, &ok)))
    for (int i = 0; i < n[2]; i++) pr[i].has_x0 = v[i] != 0;
  if ((v = col(c, "pairs", "drop", n[2], 1, &ok)))
    for (int i = 0; i < n[2]; i++) pr[i].drop = to_i(v[i]);
  if ((v = col(c, "loads", "carrier", n[3], 1, &ok)))
    for (int i = 0; i < n[3]; i++) ld[i].carrier = to_i(v[i]);
  if ((v = col(c, "loads", "world", n[3], 1, &ok)))
    for (int i = 0; i < n[3]; i++) ld[i].world = v[i] != 0;
  REALS("loads", "point", n[3], 3, ld[i].point)
  REALS("loads", "w", n[3], 6, ld[i].w)
  if ((v = col(c, "loads", "reaction", n[3], 1, &ok)))
    for (int i = 0; i < n[3]; i++) ld[i].reaction = to_i(v[i]);
  if ((v = col(c, "actuators", "pair", n[4], 1, &ok)))
    for (int i = 0; i < n[4]; i++) ac[i].pair = to_i(v[i]);
  if ((v = col(c, "actuators", "kind", n[4], 1, &ok)))
    for (int i = 0; i < n[4]; i++) ac[i].kind = to_i(v[i]);
  REALS("actuators", "vec", n[4], 6, ac[i].vec)
  REALS("actuators", "kp", n[4], 6, ac[i].kp)
  REALS("actuators", "kd", n[4], 6, ac[i].kd)
  REALS("actuators", "x_set", n[4], 6, ac[i].x_set)
  if ((v = col(c, "springs", "carriers", n[5], 2, &ok)))
    for (int i = 0; i < n[5]; i++) { sp[i].a = to_i(v[2 * i]); sp[i].b = to_i(v[2 * i + 1]); }
  REALS("springs", "pa", n[5], 3, sp[i].pa)
  REALS("springs", "pb", n[5], 3, sp[i].pb)
  REALS("springs", "k", n[5], 1, &sp[i].k)
  REALS("springs", "c", n[5], 1, &sp[i].c)
  REALS("springs", "rest_length", n[5], 1, &sp[i].d0)
  REALS("couplings", "Mc", n[6], 144, cp[i].Mc)
  if ((v = col(c, "couplings", "carriers", n[6], 2, &ok)))
    for (int i = 0; i < n[6]; i++) { cp[i].a = to_i(v[2 * i]); cp[i].b = to_i(v[2 * i + 1]); }
#undef REALS
  const record *g = fmu_record(c, "gravity");
  if (!g || g->n != 3) ok = 0;
  else memcpy(c->desc.gravity, g->v, sizeof c->desc.gravity);
  if (!ok) {
    snprintf(msg, nmsg, "model file: a record is missing or has the wrong size");
    return -1;
  }
  int *xbits = calloc((size_t)n[2] + 1, sizeof(int));
  if (!xbits) return -1;
  int bad = decode_laws(c, "pairs", "law", n[2], 1, (char *)pr, sizeof *pr, offsetof(phm_pair_desc, law), 0, NULL) ||
            decode_laws(c, "pairs", "xlaws", n[2], 6, (char *)pr, sizeof *pr, offsetof(phm_pair_desc, xlaw), 1, xbits) ||
            decode_laws(c, "loads", "law", n[3], 1, (char *)ld, sizeof *ld, offsetof(phm_load_desc, law), 2, NULL) ||
            decode_laws(c, "actuators", "law", n[4], 1, (char *)ac, sizeof *ac, offsetof(phm_actuator_desc, law), 3, NULL);
  for (int i = 0; i < n[2]; i++) pr[i].xdriven = xbits[i];
  free(xbits);
  if (bad) {
    snprintf(msg, nmsg, "model file: malformed time laws");
    return -1;
  }
  return 0;
}

/* Inputs, outputs and options. 0 or -1 with a message. */
static int read_interface(fmu *c, char *msg, size_t nmsg) {
  const record *in = fmu_record(c, "inputs"), *out = fmu_record(c, "outputs"), *op = fmu_record(c, "options");
  if (!in || in->n % 3 || !out || out->n % 19 || !op || op->n != 11) {
    snprintf(msg, nmsg, "model file: no inputs, outputs or options record");
    return -1;
  }
  c->nin = (int)(in->n / 3);
  c->nout = (int)(out->n / 19);
  c->in_kind = calloc((size_t)c->nin + 1, sizeof(int));
  c->in_index = calloc((size_t)c->nin + 1, sizeof(int));
  c->u = calloc((size_t)c->nin + 1, sizeof(double));
  c->outv = calloc((size_t)c->nout + 1, sizeof(output_var));
  c->y = calloc((size_t)c->nout + 1, sizeof(double));
  if (!c->in_kind || !c->in_index || !c->u || !c->outv || !c->y) return -1;
  for (int i = 0; i < c->nin; i++) {
    c->in_kind[i] = to_i(in->v[3 * i]);
    c->in_index[i] = to_i(in->v[3 * i + 1]);
    c->u[i] = in->v[3 * i + 2];
    int lim = c->in_kind[i] == IN_ACTUATOR ? c->desc.nactuators : c->desc.nloads;
    if (c->in_index[i] < 0 || c->in_index[i] >= lim) {
      snprintf(msg, nmsg, "model file: input %d out of range", i);
      return -1;
    }
    phm_law *law = c->in_kind[i] == IN_ACTUATOR
                       ? &((phm_actuator_desc *)c->desc.actuators)[c->in_index[i]].law
                       : &((phm_load_desc *)c->desc.loads)[c->in_index[i]].law;
    memset(law, 0, sizeof *law);
    law->kind = PHM_LAW_CALLBACK;
    law->fn = input_law;
    law->ctx = &c->u[i];
  }
  for (int i = 0; i < c->nout; i++) {
    const double *o = out->v + 19 * i;
    c->outv[i].kind = to_i(o[0]);
    c->outv[i].index = to_i(o[1]);
    c->outv[i].comp = to_i(o[2]);
    memcpy(c->outv[i].T, o + 3, sizeof c->outv[i].T);
  }
  const double *v = op->v;
  memset(&c->opt, 0, sizeof c->opt);
  c->opt.integrator = to_i(v[0]);
  c->opt.rtol = v[1];
  c->opt.atol = v[2];
  c->opt.linear_solver = to_i(v[3]);
  c->opt.max_step = v[4];
  c->opt.ida.max_order = to_i(v[5]);
  c->opt.ida.error_test = to_i(v[6]);
  c->opt.galpha.step = v[7];
  c->opt.galpha.rho_inf = v[8];
  c->opt.galpha.adaptive = to_i(v[9]);
  c->opt.galpha.band = v[10];
  return 0;
}

/* ------------------------------------------------------------------ outputs */
static void compute_outputs(fmu *c) {
  double e[3] = {0, 0, 0};
  int have_e = 0;
  for (int i = 0; i < c->nout; i++) {
    const output_var *o = &c->outv[i];
    double val = NAN;
    switch (o->kind) {
    case OUT_JOINT: val = c->x[o->index]; break;
    case OUT_RATE: val = c->xd[o->index]; break;
    case OUT_POSITION: {
      const double *H = c->H + 16 * o->index, *T = o->T;
      int r = o->comp;
      val = H[4 * r + 0] * T[3] + H[4 * r + 1] * T[7] + H[4 * r + 2] * T[11] + H[4 * r + 3];
      break;
    }
    case OUT_ENERGY:
      if (!have_e) {
        phm_model_energy(c->model, c->H, c->T, e);
        have_e = 1;
      }
      val = o->comp < 3 ? e[o->comp] : e[0] + e[1] + e[2];
      break;
    default: break;
    }
    c->y[i] = val;
  }
}

/* Integrate from c->t to t1 (nout = 2), or only project the initial state (t1 = c->t, nout = 1);
 * the state becomes the one at t1. */
fmi2Status fmu_advance(fmu *c, double t1) {
  int n = t1 > c->t ? 2 : 1;
  double tout[2] = {c->t, t1};
  size_t nc = (size_t)c->nc, nj = (size_t)c->nj;
  double *P = malloc(2 * nc * 16 * sizeof(double)), *W = malloc(2 * nc * 6 * sizeof(double)),
         *X = malloc(2 * (nj + 1) * sizeof(double)), *XD = malloc(2 * (nj + 1) * sizeof(double));
  fmi2Status st = fmi2Error;
  if (!P || !W || !X || !XD) {
    fmu_log(c, fmi2Error, "out of memory");
    goto done;
  }
  phm_sim_output out;
  memset(&out, 0, sizeof out);
  out.nrecord = c->nc;
  out.poses = P;
  out.twists = W;
  out.joints = X;
  out.joint_rates = XD;
  phm_error err;
  phm_status s = phm_simulate(c->model, c->H, c->T, tout, n, &c->opt, &out, &err);
  if (s != PHM_OK || out.nout_done != n) {
    fmu_log(c, fmi2Error, "phmech: integration from t = %.17g to %.17g s failed: %s", c->t, t1,
          s != PHM_OK ? err.msg : "stopped early");
    goto done;
  }
  int k = n - 1;
  memcpy(c->H, P + (size_t)k * nc * 16, nc * 16 * sizeof(double));
  memcpy(c->T, W + (size_t)k * nc * 6, nc * 6 * sizeof(double));
  memcpy(c->x, X + (size_t)k * nj, nj * sizeof(double));
  memcpy(c->xd, XD + (size_t)k * nj, nj * sizeof(double));
  /* the joint coordinates reached: the branch references of multi-turn angles */
  for (int ip = 0; ip < c->npairs; ip++) {
    int row, m, joint, kk;
    phm_model_pair_layout(c->model, ip, &row, &m, &joint, &kk);
    for (int j = 0; j < kk; j++) c->x0[6 * ip + j] = c->x[joint + j];
  }
  if (phm_model_set_initial(c->model, c->H, c->T, c->x0, NULL, &err) != PHM_OK) {
    fmu_log(c, fmi2Error, "phmech: %s", err.msg);
    goto done;
  }
  c->t = t1;
  compute_outputs(c);
  st = fmi2OK;
done:
  free(P);
  free(W);
  free(X);
  free(XD);
  return st;
}

void fmu_free(fmu *c) {
  if (!c) return;
  phm_model_free(c->model);
  free((void *)c->desc.carriers);
  free((void *)c->desc.elements);
  free((void *)c->desc.pairs);
  free((void *)c->desc.loads);
  free((void *)c->desc.actuators);
  free((void *)c->desc.springs);
  free((void *)c->desc.couplings);
  for (int i = 0; i < 8; i++) free(c->law_nodes[i]);
  free_records(c->rec, c->nrec);
  free(c->in_kind);
  free(c->in_index);
  free(c->u);
  free(c->outv);
  free(c->y);
  free(c->H);
  free(c->T);
  free(c->x);
  free(c->xd);
  free(c->x0);
  free(c->name);
  free(c);
}

/* file:///a/b -> /a/b (percent escapes decoded); a plain path is kept. */
static void uri_to_path(const char *uri, char *path, size_t n) {
  const char *s = uri;
  if (strncmp(s, "file://", 7) == 0) {
    s += 7;
    if (strncmp(s, "localhost/", 10) == 0) s += 9;
  } else if (strncmp(s, "file:", 5) == 0) {
    s += 5;
  }
  size_t k = 0;
  for (; *s && k + 1 < n; s++) {
    if (s[0] == '%' && s[1] && s[2]) {
      char hex[3] = {s[1], s[2], 0};
      path[k++] = (char)strtol(hex, NULL, 16);
      s += 2;
    } else {
      path[k++] = *s;
    }
  }
  path[k] = 0;
}

/* fmu.h */
fmu *fmu_new(const char *name, int logging) {
  fmu *c = calloc(1, sizeof *c);
  if (!c) return NULL;
  c->logging = logging;
  c->name = strdup(name ? name : "phmech");
  return c;
}

/* Read the model file in `resources`, build the model and the state (fmu.h). */
fmu *fmu_load(fmu *c, const char *resources, const char *refusal) {
  if (refusal || !resources) {
    fmu_log(c, fmi2Error, "%s", refusal ? refusal : "no resource location given");
    fmu_free(c);
    return NULL;
  }
  char path[4096], msg[600];
  uri_to_path(resources, path, sizeof path - sizeof FMU_FILE - 2);
  size_t L = strlen(path);
  if (L && path[L - 1] != '/') strcat(path, "/");
  strcat(path, FMU_FILE);
  if (read_records(path, &c->rec, &c->nrec, msg, sizeof msg) || build_desc(c, msg, sizeof msg) ||
      read_interface(c, msg, sizeof msg)) {
    fmu_log(c, fmi2Error, "%s", msg);
    fmu_free(c);
    return NULL;
  }
  phm_error err;
  if (phm_model_create(&c->desc, &c->model, &err) != PHM_OK) {
    fmu_log(c, fmi2Error, "phmech: the model was refused: %s", err.msg);
    fmu_free(c);
    return NULL;
  }
  c->nc = phm_model_ncarriers(c->model);
  c->nj = phm_model_njoints(c->model);
  c->npairs = phm_model_npairs(c->model);
  size_t nc = (size_t)c->nc;
  c->H = malloc(nc * 16 * sizeof(double) + 1);
  c->T = malloc(nc * 6 * sizeof(double) + 1);
  c->x = calloc((size_t)c->nj + 1, sizeof(double));
  c->xd = calloc((size_t)c->nj + 1, sizeof(double));
  c->x0 = calloc((size_t)c->npairs * 6 + 1, sizeof(double));
  if (!c->H || !c->T || !c->x || !c->xd || !c->x0) {
    fmu_free(c);
    return NULL;
  }
  for (size_t i = 0; i < nc; i++) {
    memcpy(c->H + 16 * i, c->desc.carriers[i].H0, 16 * sizeof(double));
    memcpy(c->T + 6 * i, c->desc.carriers[i].t0, 6 * sizeof(double));
  }
  for (int i = 0; i < c->npairs; i++) memcpy(c->x0 + 6 * i, c->desc.pairs[i].x0, 6 * sizeof(double));
  return c;
}
