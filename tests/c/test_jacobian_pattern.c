/* test_jacobian_pattern.c -- the DAE Jacobian's sparsity pattern (csrc/dae/jacobian.c, built
 * from the coupling graph of csrc/model/graph.c in time linear in the nonzeros) against the
 * straightforward O(n^2) construction it replaced, kept here as the reference: the CSC pattern
 * (row indices ascending in each column) must be identical, since KLU's elimination order
 * follows the pattern and IDA's Newton on the leaf spring depends on it (tests/test_scenes.py).
 * (The Jacobian's values are all in closed form: the column colouring of its former finite
 * differences is gone.) Models: a chain of beam elements, a closed loop
 * with every pair type (dropped rows, a free pair, a driven pair), springs and loads with
 * reactions, pairs to the ground on either side, and random models. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "dae.h"


/* ---------------------------------------------------------------- the reference */
/* The pattern as csrc/dae/jacobian.c built it before the coupling graph: a dense block
 * adjacency, every row tested for every column. */
typedef struct {
  int nnz;
  sunindextype *colptr, *rowind;
} pattern;

static void pattern_free(pattern *p) {
  free(p->colptr);
  free(p->rowind);
}

static int reference_pattern(const dae_t *d, pattern *p) {
  const phm_model *m = d->m;
  int n = d->n, nc = m->nc;
  int nb = nc + m->np; /* blocks: carriers, then pairs (their lambda and mu) */
  char *adj = calloc((size_t)nb * nb, 1);
  if (!adj) return 1;
  for (int c = 0; c < nc; c++) adj[(size_t)c * nb + c] = 1;
  for (int ie = 0; ie < m->ne; ie++) {
    int a = m->el[ie].a, b = m->el[ie].b;
    adj[(size_t)a * nb + b] = adj[(size_t)b * nb + a] = 1;
  }
  for (int is = 0; is < m->ns; is++) {
    int a = m->spr[is].a, b = m->spr[is].b;
    if (a >= 0 && b >= 0) adj[(size_t)a * nb + b] = adj[(size_t)b * nb + a] = 1;
  }
  for (int il = 0; il < m->nl; il++) {
    int a = m->load[il].carrier, b = m->load[il].reaction;
    if (a >= 0 && b >= 0) adj[(size_t)a * nb + b] = adj[(size_t)b * nb + a] = 1;
  }
  for (int ip = 0; ip < m->np; ip++) {
    int a = m->pair[ip].a, b = m->pair[ip].b, q = nc + ip;
    adj[(size_t)q * nb + q] = 1; /* joint coordinates' own rate, the multipliers' regularization */
    if (a >= 0 && b >= 0) adj[(size_t)a * nb + b] = adj[(size_t)b * nb + a] = 1;
    if (a >= 0) adj[(size_t)a * nb + q] = adj[(size_t)q * nb + a] = 1;
    if (b >= 0) adj[(size_t)b * nb + q] = adj[(size_t)q * nb + b] = 1;
  }
  int *blk = malloc(sizeof(int) * (size_t)n);
  p->colptr = malloc(sizeof(sunindextype) * (size_t)(n + 1));
  for (int i = 0; i < n; i++) {
    if (i < d->ix) blk[i] = i / PHM_NSTATE;
    else if (i < d->ie) {
      int ip = 0;
      while (ip + 1 < m->np && m->pair_j[ip + 1] <= i - d->ix) ip++;
      blk[i] = nc + ip;
    } else if (i < d->il) blk[i] = -1; /* ledger */
    else {
      int r = (i < d->im ? i - d->il : i - d->im), ip = 0;
      while (ip + 1 < m->np && m->pair_row[ip + 1] <= r) ip++;
      blk[i] = nc + ip;
    }
  }
  long nnz = 0;
  for (int j = 0; j < n; j++) {
    int bj = blk[j];
    if (bj < 0) { nnz += 1; continue; }
    for (int i = 0; i < n; i++) {
      int bi = blk[i];
      if (bi >= 0 && adj[(size_t)bi * nb + bj]) nnz++;
    }
  }
  p->nnz = (int)nnz;
  p->rowind = malloc(sizeof(sunindextype) * (size_t)(nnz + 1));
  long k = 0;
  for (int j = 0; j < n; j++) {
    p->colptr[j] = k;
    int bj = blk[j];
    if (bj < 0) { p->rowind[k++] = j; continue; }
    for (int i = 0; i < n; i++) {
      int bi = blk[i];
      if (bi >= 0 && adj[(size_t)bi * nb + bj]) p->rowind[k++] = i;
    }
  }
  p->colptr[n] = k;
  free(adj);
  free(blk);
  return 0;
}

/* ---------------------------------------------------------------- model descriptions */
enum { MAXC = 40, MAXE = 60, MAXP = 40, MAXL = 20, MAXS = 20, MAXA = 10 };
typedef struct {
  phm_carrier_desc car[MAXC];
  phm_element_desc el[MAXE];
  phm_pair_desc pair[MAXP];
  phm_load_desc load[MAXL];
  phm_spring_desc spr[MAXS];
  phm_actuator_desc act[MAXA];
  phm_model_desc d;
} builder;

static void identity(double H[16]) {
  memset(H, 0, 16 * sizeof(double));
  for (int i = 0; i < 4; i++) H[5 * i] = 1;
}

static void begin(builder *b, int nc) {
  memset(b, 0, sizeof *b);
  for (int c = 0; c < nc; c++) {
    for (int i = 0; i < 6; i++) b->car[c].M[7 * i] = 1.0;
    b->car[c].mass = 1.0;
    identity(b->car[c].H0);
  }
  b->d.ncarriers = nc;
  b->d.carriers = b->car;
  b->d.elements = b->el;
  b->d.pairs = b->pair;
  b->d.loads = b->load;
  b->d.springs = b->spr;
  b->d.actuators = b->act;
}

static void element(builder *b, int a, int c) {
  phm_element_desc *e = &b->el[b->d.nelements++];
  e->a = a;
  e->b = c;
  e->h = 0.1;
  for (int i = 0; i < 6; i++) e->K[7 * i] = 1e3;
  e->eps_hat[3] = 1.0;
}

static int type_code(const char *name) {
  for (int t = 0; t < phm_pair_type_count(); t++)
    if (!strcmp(phm_pair_type(t)->name, name)) return t;
  printf("no pair type %s\n", name);
  exit(2);
}

static phm_pair_desc *pair(builder *b, const char *type, int a, int c, int drop) {
  phm_pair_desc *p = &b->pair[b->d.npairs++];
  p->type = type_code(type);
  p->a = a;
  p->b = c;
  identity(p->Ta);
  identity(p->Tb);
  p->drop = drop;
  return p;
}

static void load(builder *b, int c, int reaction) {
  phm_load_desc *l = &b->load[b->d.nloads++];
  l->carrier = c;
  l->reaction = reaction;
  l->w[5] = -1.0;
  l->law.kind = PHM_LAW_CONSTANT;
  l->law.amplitude = 1.0;
}

static void spring(builder *b, int a, int c) {
  phm_spring_desc *s = &b->spr[b->d.nsprings++];
  s->a = a;
  s->b = c;
  s->k = 10.0;
  s->c = 0.1;
}

static void actuator(builder *b, int ip) {
  phm_actuator_desc *a = &b->act[b->d.nactuators++];
  a->pair = ip;
  a->kind = PHM_ACT_SPRING;
  for (int i = 0; i < 6; i++) a->kp[i] = a->kd[i] = 1.0;
}

/* ---------------------------------------------------------------- comparison */
static void compare(const char *name, builder *b) {
  phm_model *m = NULL;
  phm_error err;
  char msg[160];
  snprintf(msg, sizeof msg, "%s: model created", name);
  if (phm_model_create(&b->d, &m, &err)) {
    printf("  %s\n", err.msg);
    CHECK(0, "%s", msg);
    return;
  }
  CHECK(1, "%s", msg);
  dae_t d;
  pattern ref = {0};
  if (dae_init(&d, m, &err) || dae_jacobian_pattern(&d, &err) || reference_pattern(&d, &ref)) {
    snprintf(msg, sizeof msg, "%s: set-up", name);
    CHECK(0, "%s", msg);
    printf("  %s\n", err.msg);
    phm_model_free(m);
    return;
  }
  int same = d.nnz == ref.nnz;
  for (int j = 0; same && j <= d.n; j++) same = d.colptr[j] == ref.colptr[j];
  for (int k = 0; same && k < d.nnz; k++) same = d.rowind[k] == ref.rowind[k];
  snprintf(msg, sizeof msg, "%s: CSC pattern identical (n %d, nnz %d vs %d)", name, d.n, d.nnz, ref.nnz);
  CHECK(same, "%s", msg);
  int ascending = 1;
  for (int j = 0; j < d.n; j++)
    for (sunindextype k = d.colptr[j] + 1; k < d.colptr[j + 1]; k++) ascending &= d.rowind[k] > d.rowind[k - 1];
  snprintf(msg, sizeof msg, "%s: rows ascending in every column", name);
  CHECK(ascending, "%s", msg);
  pattern_free(&ref);
  dae_free(&d);
  phm_model_free(m);
}

static unsigned long long rng = 0x9E3779B97F4A7C15ULL;
static int irand(int n) { /* uniform in [0, n) */
  rng ^= rng << 13;
  rng ^= rng >> 7;
  rng ^= rng << 17;
  return (int)((rng >> 33) % (unsigned long long)n);
}

int main(void) {
  static builder b;
  /* a cantilever: a chain of beam elements clamped to the ground */
  begin(&b, 9);
  for (int i = 0; i < 8; i++) element(&b, i, i + 1);
  pair(&b, "fixed", -1, 0, 0);
  compare("chain of 8 elements, clamped", &b);

  /* a closed loop through every pair type: rows dropped, a free pair, a driven fixed pair */
  begin(&b, 8);
  pair(&b, "revolute", -1, 0, 0);
  pair(&b, "spherical", 0, 1, 0);
  pair(&b, "universal", 1, 2, 0);
  pair(&b, "prismatic", 2, 3, 0);
  pair(&b, "cylindrical", 3, 4, 2);
  pair(&b, "planar", 4, 5, 0);
  pair(&b, "helical", 5, 6, 0);
  pair(&b, "free", 6, 0, 0);
  pair(&b, "fixed", 6, 7, 1 | 8);
  phm_pair_desc *drv = pair(&b, "fixed", 7, -1, 0);
  drv->driven = 1;
  drv->axis[2] = 1.0;
  drv->law.kind = PHM_LAW_SINE;
  drv->law.amplitude = 0.1;
  drv->law.frequency = 1.0;
  pair(&b, "revolute", 3, 1, 0);
  actuator(&b, 0);
  actuator(&b, 7);
  compare("closed loop, every pair type", &b);

  /* springs and loads, to the ground and between carriers, on a beam with bodies */
  begin(&b, 10);
  for (int i = 0; i < 6; i++) element(&b, i, i + 1);
  pair(&b, "fixed", -1, 0, 0);
  pair(&b, "revolute", 6, 7, 0);
  pair(&b, "spherical", 8, 7, 0);
  spring(&b, 2, 8);
  spring(&b, -1, 9);
  spring(&b, 9, -1);
  spring(&b, 3, 5);
  load(&b, 4, -1);
  load(&b, 9, 1);
  load(&b, 8, 2);
  compare("springs and loads with reactions", &b);

  /* pairs to the ground on either side; a carrier coupled to nothing */
  begin(&b, 6);
  pair(&b, "revolute", -1, 0, 0);
  pair(&b, "prismatic", 1, -1, 0);
  pair(&b, "fixed", 2, -1, 0);
  pair(&b, "free", -1, 3, 0);
  pair(&b, "universal", 4, -1, 0);
  compare("pairs to the ground", &b);

  /* no pairs; only a free pair (no constraint rows) */
  begin(&b, 5);
  for (int i = 0; i < 4; i++) element(&b, i, i + 1);
  compare("no pairs", &b);
  pair(&b, "free", 0, 4, 0);
  compare("one free pair", &b);

  /* random models */
  const char *types[] = {"fixed", "revolute", "prismatic", "helical", "cylindrical", "universal",
                         "spherical", "planar", "free"};
  for (int trial = 0; trial < 40; trial++) {
    int nc = 1 + irand(MAXC);
    begin(&b, nc);
    if (nc > 1) {
      int ne = irand(nc + 10 < MAXE ? nc + 10 : MAXE);
      for (int i = 0; i < ne; i++) {
        int a = irand(nc), c = irand(nc);
        if (a != c) element(&b, a, c);
      }
    }
    int np = irand(MAXP);
    for (int i = 0; i < np; i++) {
      int a = irand(nc + 1) - 1, c = irand(nc + 1) - 1;
      if (a == c) continue;
      const char *t = types[irand(9)];
      int mt = phm_pair_type(type_code(t))->m;
      pair(&b, t, a, c, mt > 0 && irand(4) == 0 ? irand(1 << mt) : 0);
    }
    int ns = irand(MAXS);
    for (int i = 0; i < ns; i++) {
      int a = irand(nc + 1) - 1, c = irand(nc + 1) - 1;
      if (a != c) spring(&b, a, c);
    }
    int nl = irand(MAXL);
    for (int i = 0; i < nl; i++) {
      int c = irand(nc), r = irand(nc + 1) - 1;
      load(&b, c, r == c ? -1 : r);
    }
    char name[64];
    snprintf(name, sizeof name, "random model %d (%d carriers, %d pairs)", trial, nc, b.d.npairs);
    compare(name, &b);
  }
  printf("%d passed, %d failed\n", check_npass, check_nfail);
  return check_nfail != 0 || check_npass == 0;
}
