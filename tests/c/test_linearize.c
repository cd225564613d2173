/* test_linearize.c -- the stiffness and damping blocks of modes and statics (csrc/analyze/linearize.c:
 * all in closed form) against central
 * differences computed here, carrier by carrier and direction by direction, of the generalized
 * forces f_c(delta) = dexp_{-delta}^T w_c(H_c exp(delta)) (docs/method.md section 7.1) and of the
 * wrenches in the twists. A chain of four elements, bent and twisted, clamped to the ground, a
 * revolute pair with constraint wrenches lambda and a PD actuator, a spring-damper to the ground,
 * gravity and a world-fixed load; and every pair type's geometric stiffness alone. Reference steps
 * 1e-6 (rad, m; truncation ~ 1e-12, round-off ~ 1e-10 relative): 1e-7 relative. The KKT
 * matrix's inertia (lin_ldl_negative) against the dense matrix's eigenvalues (LAPACK dsyev). */
#include "check.h"
#include "linalg.h"
#include "analyze.h"

enum { NC = 5 };

/* The worst error of L->Kb (lin_force_jacobian_blocks at poses H of NC carriers) against central
 * differences of f_c(delta) = dexp_{-delta}^T w_c(H_c exp(delta)), relative to the largest entry. */
static double stiffness_error(lin_t *L, const double *H) {
  double fp[6 * NC], fm[6 * NC], Hp[16 * NC], err_k = 0, big_k = 0, s = 1e-6;
  for (int c = 0; c < NC; c++)
    for (int j = 0; j < 6; j++) {
      for (int side = 0; side < 2; side++) {
        double dl[6] = {0}, md[6], D[36], *f = side ? fm : fp;
        dl[j] = side ? -s : s;
        for (int i = 0; i < 6; i++) md[i] = -dl[i];
        memcpy(Hp, H, sizeof Hp);
        perturbed(H + 16 * c, dl, 1.0, Hp + 16 * c);
        lin_total_force(L, Hp, f);
        phm_se3_dexp(md, D);
        double w[6];
        for (int i = 0; i < 6; i++) {
          w[i] = 0;
          for (int q = 0; q < 6; q++) w[i] += D[6 * q + i] * f[6 * c + q];
        }
        memcpy(f + 6 * c, w, sizeof w);
      }
      for (int r = 0; r < NC; r++) {
        int q = L->ptr[r];
        while (q < L->ptr[r + 1] && L->nbr[q] != c) q++;
        for (int i = 0; i < 6; i++) {
          double ref = (fp[6 * r + i] - fm[6 * r + i]) / (2 * s);
          double got = q < L->ptr[r + 1] ? L->Kb[36 * q + 6 * i + j] : 0.0;
          err_k = fmax(err_k, fabs(ref - got));
          big_k = fmax(big_k, fabs(ref));
        }
      }
    }
  return err_k / big_k;
}

/* L's blocks at poses H (lin_force_jacobian_blocks) at time and load scale, with random
 * constraint wrenches lam (ncons). */
static void blocks_at(lin_t *L, const double *H, double time, double scale, double *lam) {
  for (int i = 0; i < L->m->ncons; i++) lam[i] = 5.0 * rand11();
  L->time = time;
  L->tref = 0.5;
  L->scale = scale;
  L->lam = lam;
  lin_force_jacobian_blocks(L, H);
}

/* The pairs' constraint wrenches alone, in closed form (phm_pair_tangent): every pair type
 * between carriers and from the ground, random frames and poses (off the joint manifold: the
 * geometric stiffness holds anywhere), random lambda, a driven fixed pair and driven joint
 * coordinates; no differences are taken (no load, spring or actuator). */
static void pair_stiffness_is_closed_form(void) {
  static const char *const names[] = {
      "geometric stiffness of fixed pairs = central FD", "geometric stiffness of revolute pairs = central FD",
      "geometric stiffness of prismatic pairs = central FD", "geometric stiffness of helical pairs = central FD",
      "geometric stiffness of cylindrical pairs = central FD", "geometric stiffness of universal pairs = central FD",
      "geometric stiffness of spherical pairs = central FD", "geometric stiffness of planar pairs = central FD",
      "geometric stiffness of free pairs = central FD"};
  for (int type = 0; type < phm_pair_type_count() && type < 9; type++)
    for (int trial = 0; trial < 3; trial++) {
      phm_carrier_desc car[NC];
      phm_pair_desc pair[3];
      double H[16 * NC];
      memset(pair, 0, sizeof pair);
      for (int c = 0; c < NC; c++) {
        carrier_unit(&car[c]);
        rand_pose(H + 16 * c, 1.0);
      }
      int mt = phm_pair_type(type)->m, mask = phm_pair_type(type)->xdrivable;
      for (int p = 0; p < 3; p++) {
        pair[p].type = type;
        pair[p].a = p == 0 ? -1 : p;
        pair[p].b = p == 0 ? 0 : p + 2;
        pair[p].pitch = 0.3 * rand11();
        rand_pose(pair[p].Ta, 1.0);
        rand_pose(pair[p].Tb, 1.0);
        if (p == 1 && type == pair_code("fixed")) {
          pair[p].driven = 1;
          for (int i = 0; i < 6; i++) pair[p].axis[i] = rand11();
          pair[p].law = (phm_law){.kind = PHM_LAW_SINE, .amplitude = 0.7, .frequency = 0.3, .phase = 0.2};
        }
        if (p == 2)
          for (int c = 0; c < 6 - mt; c++)
            if (mask >> c & 1) {
              pair[p].xdriven |= 1 << c;
              pair[p].xlaw[c] = (phm_law){.kind = PHM_LAW_SINE, .amplitude = 0.5, .frequency = 0.3};
            }
      }
      phm_model_desc d = {.ncarriers = NC, .carriers = car, .npairs = 3, .pairs = pair};
      phm_model *m = create_model(&d);
      if (!m) continue;
      lin_t L = {0};
      phm_error err;
      if (lin_alloc(&L, m, &err) || lin_graph(&L, &err)) {
        check_fail("lin set-up: %s", err.msg);
      } else {
        double lam[24];
        blocks_at(&L, H, 0.3, 1.0, lam);
        check_worst(names[type], stiffness_error(&L, H), 1e-7);
      }
      lin_free(&L);
      phm_model_free(m);
    }
}

static void stiffness_and_damping_blocks_are_central_differences(void) {
  phm_carrier_desc car[NC];
  phm_element_desc el[NC - 1];
  phm_pair_desc pair[2];
  phm_load_desc load[1];
  memset(el, 0, sizeof el);
  memset(pair, 0, sizeof pair);
  double H[16 * NC], E[16], x[6];
  rand_pose(H, 1.0);
  for (int c = 0; c < NC; c++) {
    carrier_unit(&car[c]);
    car[c].mass = 0.5 + c;
    car[c].com[0] = 0.05 * c;
    if (c + 1 < NC) {
      for (int i = 0; i < 6; i++) x[i] = 0.3 * rand11();
      x[3] += 0.4;
      pose_expm(x, E);
      phm_se3_compose(H + 16 * c, E, H + 16 * (c + 1));
      el[c].a = c;
      el[c].b = c + 1;
      el[c].h = 0.4;
      rand_spd6(el[c].K, 50.0);
      rand_spd6(el[c].D, 0.5);
      el[c].eps_hat[2] = rand11();
      el[c].eps_hat[3] = 1.0;
    }
  }
  for (int p = 0; p < 2; p++)
    for (int i = 0; i < 4; i++) pair[p].Ta[5 * i] = pair[p].Tb[5 * i] = 1.0;
  pair[0].type = pair_code("fixed");
  pair[0].a = -1;
  pair[0].b = 0;
  pair[1].type = pair_code("revolute");
  pair[1].a = 2;
  pair[1].b = 4;
  load[0] = (phm_load_desc){.carrier = 3, .reaction = -1, .w = {0.1, 0.2, 0.3, 1, -2, 3}, .world = 1,
                            .point = {0.05, 0, 0}, .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 1.0}};
  phm_spring_desc spr[1] = {{.a = 1, .b = -1, .pa = {0.1, 0, 0}, .pb = {1, 1, 1}, .k = 30, .c = 0.5, .d0 = 0.5}};
  phm_actuator_desc act[1] = {{.pair = 1, .kind = PHM_ACT_PD, .kp = {50}, .kd = {2}, .x_set = {0.1},
                               .vec = {1}, .law = {.kind = PHM_LAW_CONSTANT, .amplitude = 0.2}}};
  phm_model_desc d = {.ncarriers = NC, .carriers = car, .nelements = NC - 1, .elements = el,
                      .npairs = 2, .pairs = pair, .nloads = 1, .loads = load, .nsprings = 1,
                      .springs = spr, .nactuators = 1, .actuators = act, .gravity = {0, 0, -9.81}};
  phm_model *m = create_model(&d);
  if (!m) return;
  lin_t L = {0};
  phm_error err;
  if (lin_alloc(&L, m, &err) || lin_graph(&L, &err)) {
    check_fail("lin set-up: %s", err.msg);
    lin_free(&L);
    phm_model_free(m);
    return;
  }
  double lam[12];
  blocks_at(&L, H, 0.0, 0.7, lam);
  double *Db = calloc(36 * (size_t)L.ptr[NC] + 1, sizeof(double));
  lin_closed_form_blocks(&L, H, NULL, Db);
  check_worst("stiffness blocks = central FD of f_c(delta)", stiffness_error(&L, H), 1e-7);
  double err_d = 0, big_d = 0;
  for (int c = 0; c < NC; c++)
    for (int j = 0; j < 6; j++) {
      /* the damping: d w/d t_c (affine in the twists: one-sided differences are exact up to
       * round-off; load scale 0 leaves the elements', the spring's and the PD actuator's) */
      double tw[6 * NC] = {0}, wr0[6 * NC], wr1[6 * NC];
      phm_applied(m, H, tw, NULL, 0.0, 0.5, 0.0, wr0, NULL, NULL, NULL, NULL, NULL);
      tw[6 * c + j] = 1.0;
      phm_applied(m, H, tw, NULL, 0.0, 0.5, 0.0, wr1, NULL, NULL, NULL, NULL, NULL);
      for (int r = 0; r < NC; r++) {
        int q = L.ptr[r];
        while (q < L.ptr[r + 1] && L.nbr[q] != c) q++;
        for (int i = 0; i < 6; i++) {
          double ref = wr1[6 * r + i] - wr0[6 * r + i];
          double got = q < L.ptr[r + 1] ? Db[36 * q + 6 * i + j] : 0.0;
          err_d = fmax(err_d, fabs(ref - got));
          big_d = fmax(big_d, fabs(ref));
        }
      }
    }
  check_worst("damping blocks (elements, spring, PD actuator) = dw/dt", err_d / big_d, 1e-10);
  free(Db);
  lin_free(&L);
  phm_model_free(m);
}

/* The KKT matrix's inertia from the LDL' factorization without pivoting (lin_ldl_negative, on the
 * equilibrated matrix) against the eigenvalues of the dense matrix: random pairs (a chain from
 * the ground, types among fixed, revolute, prismatic, universal, spherical) at random poses,
 * random symmetric stiffness blocks K + t I. t: random, or -nu_k + delta with nu_k an
 * eigenvalue of Z^T K Z (Z: the null space of G, orthonormal), so that the reduced matrix
 * Z^T K Z + t I has the eigenvalue delta, tiny (near-singular): its negative count is then
 * known without the dense KKT matrix's round-off, #{nu_i < nu_k - delta}. A count whose
 * certificate is below PHM_INERTIA_CHECK must be exact; most must be certified. */
static void kkt_inertia_is_the_dense_count(void) {
  static const char *const types[] = {"fixed", "revolute", "prismatic", "universal", "spherical"};
  int certified = 0, compared = 0, near_certified = 0, near = 0;
  double worst = 0;
  for (int trial = 0; trial < 120; trial++) {
    phm_carrier_desc car[NC];
    phm_pair_desc pair[NC];
    double H[16 * NC];
    memset(pair, 0, sizeof pair);
    for (int c = 0; c < NC; c++) {
      carrier_unit(&car[c]);
      rand_pose(H + 16 * c, 1.0);
    }
    for (int p = 0; p < NC; p++) {
      pair[p].type = pair_code(types[(int)(5 * rand01()) % 5]);
      pair[p].a = p - 1;
      pair[p].b = p;
      rand_pose(pair[p].Ta, 1.0);
      rand_pose(pair[p].Tb, 1.0);
    }
    phm_model_desc d = {.ncarriers = NC, .carriers = car, .npairs = NC, .pairs = pair};
    phm_model *m = create_model(&d);
    if (!m) continue;
    int nk = phm_model_nconstraints(m), n6 = 6 * NC, N = n6 + nk;
    lin_t L = {0};
    lin_kkt_t S = {0};
    lin_ldl_t F = {0};
    phm_error err;
    double *Kb = NULL, *Gp = malloc(sizeof(double) * 12 * (size_t)(nk + 1));
    double *A = malloc(sizeof(double) * (size_t)N * N), *ev = malloc(sizeof(double) * (size_t)N);
    double *sc = malloc(sizeof(double) * (size_t)N), *work = malloc(sizeof(double) * 64 * (size_t)N);
    double *Z = malloc(sizeof(double) * (size_t)n6 * n6), *Kd = calloc((size_t)n6 * n6, sizeof(double));
    if (lin_alloc(&L, m, &err) || lin_graph(&L, &err) || lin_kkt_build(&S, &L, &err) ||
        lin_ldl_analyze(&F, &L, &S, &err) || !Gp || !A || !ev || !sc || !work || !Z || !Kd) {
      check_fail("set-up: %s", err.msg);
      goto next;
    }
    int nb = L.ptr[NC];
    Kb = calloc(36 * (size_t)nb, sizeof(double));
    if (!Kb) goto next;
    /* K: random symmetric blocks on the graph's slots, of a random scale */
    double scale = pow(10.0, 3 * rand11());
    for (int r = 0; r < NC; r++)
      for (int q = L.ptr[r]; q < L.ptr[r + 1]; q++) {
        int c = L.nbr[q];
        if (c < r) continue;
        int qt = L.ptr[c];
        while (L.nbr[qt] != r) qt++;
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) {
            double v = scale * rand11();
            if (c == r && j < i) continue;
            Kb[36 * q + 6 * i + j] = v;
            Kb[36 * qt + 6 * j + i] = v;
          }
      }
    for (int r = 0; r < NC; r++)
      for (int q = L.ptr[r]; q < L.ptr[r + 1]; q++)
        for (int i = 0; i < 6; i++)
          for (int j = 0; j < 6; j++) Kd[(size_t)(6 * r + i) * n6 + 6 * L.nbr[q] + j] = Kb[36 * q + 6 * i + j];
    lin_constraint_blocks(&L, H, Gp);
    /* the null space of G (dense, n6 columns: nk x n6 row-major = n6 x nk column-major G^T) */
    double *Gt = A, sv[6 * NC];
    memset(Gt, 0, sizeof(double) * (size_t)n6 * nk);
    for (int ip = 0; ip < NC; ip++)
      for (int r = m->pair_row[ip]; r < m->pair_row[ip] + m->pair_m[ip]; r++)
        for (int side = 0; side < 2; side++) {
          int c = side ? pair[ip].b : pair[ip].a;
          if (c >= 0)
            for (int j = 0; j < 6; j++) Gt[(size_t)r * n6 + 6 * c + j] = Gp[12 * r + 6 * side + j];
        }
    int lw = 64 * N, info = 0, one = 1;
    dgesvd_("A", "N", &n6, &nk, Gt, &n6, sv, Z, &n6, NULL, &one, work, &lw, &info);
    int nz = n6 - nk;
    if (info || sv[nk - 1] < 1e-8 * sv[0] || nz < 1) goto next; /* dependent rows: not this test */
    /* Z^T K Z on the columns nk.. of U */
    double *R = A;
    for (int a = 0; a < nz; a++)
      for (int b = 0; b < nz; b++) {
        double t = 0;
        for (int i = 0; i < n6; i++) {
          double ki = 0;
          for (int j = 0; j < n6; j++) ki += Kd[(size_t)i * n6 + j] * Z[(size_t)(nk + b) * n6 + j];
          t += Z[(size_t)(nk + a) * n6 + i] * ki;
        }
        R[(size_t)a * nz + b] = t;
      }
    dsyev_("N", "U", &nz, R, &nz, ev, work, &lw, &info);
    if (info) goto next;
    double numax = fmax(fabs(ev[0]), fabs(ev[nz - 1]));
    int k = (int)(nz * rand01()) % nz, kind = trial % 4;
    static const double deltas[4] = {0, 1e-6, 1e-10, -1e-10};
    double t = kind == 0 ? numax * rand11() : -ev[k] + deltas[kind] * numax;
    int want = 0;
    for (int i = 0; i < nz; i++) want += ev[i] + t < 0;
    if (kind != 0 && k > 0 && fabs(ev[k] - ev[k - 1]) < 1e-8 * numax) goto next;
    if (kind != 0 && k + 1 < nz && fabs(ev[k + 1] - ev[k]) < 1e-8 * numax) goto next;
    for (int r = 0; r < NC; r++) {
      int q = L.ptr[r];
      while (L.nbr[q] != r) q++;
      for (int i = 0; i < 6; i++) Kb[36 * q + 7 * i] += t;
    }
    lin_kkt_values(&S, Kb, Gp);
    lin_kkt_equilibrate(&S, sc, work);
    if (lin_kkt_refactor(&S)) goto next;
    double check = 0;
    int neg = lin_ldl_negative(&F, &S, &check);
    if (kind == 0 || deltas[kind] == 1e-6) {
      compared++;
      if (check < PHM_INERTIA_CHECK) certified++;
    } else {
      near++;
      if (check < PHM_INERTIA_CHECK) near_certified++;
    }
    if (check < PHM_INERTIA_CHECK) {
      CHECK(neg - nk == want, "trial %d (t %s): %d negative pivots - %d rows = %d, dense count %d "
            "(certificate %.2g)", trial, kind ? "near an eigenvalue" : "random", neg, nk, neg - nk,
            want, check);
      worst = fmax(worst, check);
    }
  next:
    lin_ldl_free(&F);
    lin_kkt_free(&S);
    lin_free(&L);
    phm_model_free(m);
    free(Kb); free(Gp); free(A); free(ev); free(sc); free(work); free(Z); free(Kd);
  }
  CHECK(compared >= 40 && certified >= compared - compared / 10, "%d of %d counts certified "
        "(worst certified %.2g); near-singular: %d of %d", certified, compared, worst,
        near_certified, near);
  if (check_verbose)
    printf("  kkt inertia: %d of %d certified (worst %.2g), near-singular %d of %d\n", certified,
           compared, worst, near_certified, near);
}

CHECK_MAIN(CHECK_CASE(stiffness_and_damping_blocks_are_central_differences),
           CHECK_CASE(pair_stiffness_is_closed_form), CHECK_CASE(kkt_inertia_is_the_dense_count))
