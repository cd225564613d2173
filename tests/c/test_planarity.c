/* test_planarity.c -- csrc/model/planarity.c: a scene planar about z passes about z only, with
 * its out-of-plane rows dropped; each check, failed by the last item alone (1e-3 against entries
 * of order 1), names that item in planar.py's words; a malformed scene is refused; and a model's
 * actuated revolute (phm_planar_check) is planar exactly when its axis is the plane's normal, for
 * carriers turned about it and pair frames turned about the axis (a prismatic: along x or y,
 * its frames aligned with the world's; a helical never: it also moves along its axis). */
#include "check.h"

enum { N = 3 };

typedef struct {
  phm_carrier_desc car[N];
  phm_element_desc el[N];
  double cMc[N * 144];
  phm_load_desc load[N];
  phm_spring_desc spr[1];
  phm_actuator_desc act[1];
  phm_pair_desc pair[2];
  int row[2], m[2], k[2];
  double H[16 * N], t[6 * N], G[7 * N * 6];
  int Gcar[7 * N];
  phm_planar_scene s;
} scene;

/* A random symmetric n x n matrix (n = 6, 12) with no in-plane / out-of-plane entry for z. */
static void decoupled(int n, double *A) {
  for (int r = 0; r < n; r++)
    for (int c = 0; c <= r; c++) {
      int ir = r % 6 == 2 || r % 6 == 3 || r % 6 == 4, ic = c % 6 == 2 || c % 6 == 3 || c % 6 == 4;
      A[n * r + c] = A[n * c + r] = ir == ic ? randn() : 0.0;
    }
}

/* planar.py's synthetic scene of tests/test_planar.py, in C: N carriers turned about z, N
 * elements, couplings and loads, a spring, pair 0 with one in-plane and one out-of-plane row,
 * pair 1 (k = 1, actuated) with 5 rows on carrier 1 leaving v_x free. */
static void make_scene(scene *S) {
  memset(S, 0, sizeof *S);
  for (int c = 0; c < N; c++) {
    carrier_unit(&S->car[c]);
    decoupled(6, S->car[c].M);
    S->car[c].com[0] = randn();
    S->car[c].com[1] = randn();
    double a = 0.3 * c, *H = S->H + 16 * c;
    for (int i = 0; i < 16; i++) H[i] = i % 5 == 0;
    H[0] = H[5] = cos(a);
    H[1] = -sin(a);
    H[4] = sin(a);
    H[3] = randn();
    H[7] = randn();
    S->t[6 * c + 2] = randn();
    S->t[6 * c + 3] = randn();
    S->t[6 * c + 4] = randn();
    decoupled(6, S->el[c].K);
    decoupled(6, S->el[c].D);
    decoupled(6, S->el[c].Ms);
    decoupled(12, S->el[c].Mc);
    S->el[c].eps_hat[2] = S->el[c].eps_hat[3] = 1.0;
    decoupled(12, S->cMc + 144 * c);
    S->load[c].carrier = c;
    S->load[c].w[2] = S->load[c].w[3] = S->load[c].w[4] = 1.0;
    S->load[c].point[0] = S->load[c].point[1] = 1.0;
  }
  S->spr[0] = (phm_spring_desc){.a = 0, .b = -1, .pa = {0.5, 0.2, 0}, .pb = {1, 1, 0}};
  S->spr[0].pb[2] = S->H[11]; /* carrier 0's z: the ground point in its plane */
  S->pair[0] = (phm_pair_desc){.a = -1, .b = 0};
  S->pair[1] = (phm_pair_desc){.a = -1, .b = 1};
  S->act[0].pair = 1;
  S->row[0] = 0, S->m[0] = 2, S->k[0] = 0;
  S->row[1] = 2, S->m[1] = 5, S->k[1] = 1;
  for (int i = 0; i < 7 * N; i++) S->Gcar[i] = i % N;
  S->G[2] = S->G[3] = 1.0;          /* row 0: omega_z, v_x of carrier 0: in-plane     */
  S->G[6 * N + 0] = S->G[6 * N + 5] = 1.0; /* row 1: omega_x, v_z: out-of-plane      */
  const int fixed[5] = {0, 1, 2, 4, 5};  /* pair 1 fixes all but v_x of carrier 1       */
  for (int r = 0; r < 5; r++) S->G[(2 + r) * 6 * N + 6 + fixed[r]] = 1.0;
  S->s = (phm_planar_scene){.gravity = {0, -9.81, 0}, .nc = N, .H = S->H, .t = S->t, .car = S->car,
                            .ne = N, .el = S->el, .ncoup = N, .coupling_Mc = S->cMc, .nl = N,
                            .load = S->load, .ns = 1, .spr = S->spr, .na = 1, .act = S->act,
                            .np = 2, .pair = S->pair, .pair_row = S->row, .pair_m = S->m,
                            .pair_k = S->k, .names = NULL, .nrow = 7, .nblk = N, .G = S->G,
                            .Gcar = S->Gcar};
}

static void a_scene_fails_each_check_by_its_last_item(void) {
  static scene S;
  char why[PHM_PLANAR_WHY];
  int drop[2] = {-1, -1};
  phm_error err;
  make_scene(&S);
  phm_status st = phm_planar_check_scene(&S.s, 2, drop, why, &err);
  CHECK(st == PHM_OK && why[0] == '\0' && drop[0] == 2 && drop[1] == 0x13,
        "planar about z, row 1 of pair 0 dropped (%d: %s; drop %d %d)", st, why, drop[0], drop[1]);
  st = phm_planar_check_scene(&S.s, 0, NULL, why, &err);
  CHECK(st == PHM_OK && strcmp(why, "carrier 1's initial rotation is not about x") == 0, "not about x: %s", why);
  st = phm_planar_check_scene(&S.s, 1, NULL, why, &err);
  CHECK(st == PHM_OK && strcmp(why, "gravity (0.0, -9.81, 0.0) has a component along y") == 0, "not about y: %s", why);
  const char *names[2] = {"p", "q"};
  struct {
    int what;
    const char *message;
  } cases[] = {
      {0, "gravity (0.0, -9.81, 0.001) has a component along z"},
      {1, "carrier 2's initial rotation is not about z"},
      {2, "carrier 2's initial twist has out-of-plane components [0.    0.    0.001]"},
      {3, "carrier 2's inertia couples"},
      {4, "carrier 2's centre of mass is off"},
      {5, "element 2's D couples"},
      {6, "element 2's consistent mass"},
      {7, "element 2's unstressed curvature"},
      {8, "inertial coupling 2 couples"},
      {9, "load 2 has out-of-plane components [0.    0.    0.001]"},
      {10, "load 2 acts at a point off the plane"},
      {11, "spring 0 has its points off the plane"},
      {12, "pair 'q' is actuated or driven along an out-of-plane axis"},
      {13, "pair 'q' is actuated or driven along more than one coordinate"},
      {14, "pair 'p''s constraint row 1 mixes"},
      {15, "pair 'p' is actuated or driven along more than one coordinate"},
      {16, "element 2's K couples"},
      {17, "element 2's Ms couples"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    make_scene(&S);
    S.s.names = names;
    switch (cases[i].what) {
    case 0: S.s.gravity[2] = 1e-3; break;
    case 1: S.H[16 * 2 + 2] = 1e-3; break;
    case 2: S.t[6 * 2 + 5] = 1e-3; break;
    case 3: S.car[2].M[2] = S.car[2].M[12] = 1e-3; break;
    case 4: S.car[2].com[2] = 1e-3; break;
    case 5: S.el[2].D[6 * 5 + 3] = 1e-3; break;
    case 6: S.el[2].Mc[12 * 6 + 8] = 1e-3; break;
    case 7: S.el[2].eps_hat[0] = 1e-3; break;
    case 8: S.cMc[144 * 2 + 12 * 9] = 1e-3; break;
    case 9: S.load[2].w[5] = 1e-3; break;
    case 10: S.load[2].point[2] = 1e-3; break;
    case 11: S.spr[0].pa[2] = 1e-3; break;
    case 12: /* pair q's rows on carrier 1 leave omega_x free instead of v_x */
      S.G[(2 + 0) * 6 * N + 6 + 0] = 0, S.G[(2 + 0) * 6 * N + 6 + 3] = 1.0;
      break;
    case 13: S.k[1] = 2; break;
    case 14: S.G[6 * N + 6 * 2 + 4] = 1e-3; break;
    case 15: S.pair[0].driven = 1; break;
    case 16: S.el[2].K[6 * 0 + 2] = 1e-3; break;
    case 17: S.el[2].Ms[6 * 3 + 5] = 1e-3; break;
    }
    st = phm_planar_check_scene(&S.s, 2, drop, why, &err);
    CHECK(st == PHM_OK && strncmp(why, cases[i].message, strlen(cases[i].message)) == 0,
          "case %d: '%s' (expected '%s...')", cases[i].what, why, cases[i].message);
  }
  /* malformed scenes are refused, never read out of range */
  make_scene(&S);
  S.Gcar[4] = N;
  check_refused("a row's carrier out of range", phm_planar_check_scene(&S.s, 2, drop, why, &err),
                PHM_EINVAL, &err, "carrier out of range");
  make_scene(&S);
  S.m[1] = 6;
  check_refused("a pair's rows beyond G", phm_planar_rows(&S.s, 2, drop, &err), PHM_EINVAL, &err,
                "rows out of range");
  make_scene(&S);
  S.act[0].pair = 2;
  check_refused("an actuator's pair out of range", phm_planar_check_scene(&S.s, 2, drop, why, &err),
                PHM_EINVAL, &err, "pair out of range");
  make_scene(&S);
  check_refused("axis 3", phm_planar_check_scene(&S.s, 3, drop, why, &err), PHM_EINVAL, &err, "axis 3");
  check_refused("no scene", phm_planar_rows(NULL, 2, drop, &err), PHM_EINVAL, &err, "NULL scene");
}

/* A body on an actuated pair of one coordinate (revolute, prismatic, helical) turned so its
 * axis is world axis `ax`, its carrier turned about z: planar about z exactly when the pair
 * moves in the x-y plane (a revolute or helical about z; a prismatic along x or y). */
static void a_models_actuated_pair_is_planar_when_it_moves_in_the_plane(void) {
  const char *types[3] = {"revolute", "prismatic", "helical"};
  for (int ty = 0; ty < 3; ty++)
    for (int ax = 0; ax < 3; ax++)
      for (int trial = 0; trial < 3; trial++) {
        phm_carrier_desc car;
        carrier_unit(&car);
        phm_pair_desc pr = {.type = pair_code(types[ty]), .a = -1, .b = 0, .pitch = ty == 2 ? 0.1 : 0};
        phm_actuator_desc act = {.pair = 0, .kind = PHM_ACT_EFFORT, .vec = {1}};
        act.law.kind = PHM_LAW_CONSTANT;
        act.law.amplitude = 1;
        /* the joint axis (local z of both frames) along world axis ax, turned about it by a */
        double a = ty == 1 ? 0.0 : rand11(), R[16], spin[16], T[16]; /* a prismatic turned
                                    * about its axis: rows mixing in- and out-of-plane motion */
        const double toax[3][16] = {{0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 0, 1},
                                    {1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1},
                                    {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
        double z[6] = {0, 0, a, 0, 0, 0};
        phm_se3_exp(z, spin);
        memcpy(R, toax[ax], sizeof R);
        phm_se3_compose(R, spin, T);
        T[3] = rand11(), T[7] = rand11(); /* an offset in the plane */
        memcpy(pr.Ta, T, sizeof T);
        memcpy(pr.Tb, T, sizeof T);
        /* the carrier turned about z (the pair's coordinate: the frames then differ by it) */
        double th = trial * 0.4, w[6] = {0, 0, th, 0, 0, 0}, H[16];
        phm_se3_exp(w, H);
        if (ty != 0 || ax != 2) memcpy(H, (double[16]){1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, sizeof H);
        memcpy(car.H0, H, sizeof H);
        phm_model_desc d = {.ncarriers = 1, .carriers = &car, .npairs = 1, .pairs = &pr,
                            .nactuators = 1, .actuators = &act};
        phm_model *m = create_model(&d);
        if (!m) continue;
        double t[6] = {0};
        const char *names[1] = {"h"};
        int axis = -9, drop[1] = {-1};
        char why[3][PHM_PLANAR_WHY];
        phm_error err;
        phm_status st = phm_planar_check(m, H, t, names, &axis, drop, why, &err);
        int in_plane = ty == 0 ? ax == 2 : ty == 1 ? ax != 2 : 0; /* a helical: along its axis too */
        if (in_plane)
          CHECK(st == PHM_OK && axis == 2, "%s along %c, carrier turned %.1f: planar about z (axis %d: %s)",
                types[ty], "xyz"[ax], th, axis, why[2]);
        else
          CHECK(st == PHM_OK && axis != 2 && strstr(why[2], "pair 'h' is actuated or driven along an out-of-plane axis"),
                "%s along %c: not planar about z (axis %d: %s)", types[ty], "xyz"[ax], axis, why[2]);
        phm_model_free(m);
      }
}

CHECK_MAIN(CHECK_CASE(a_scene_fails_each_check_by_its_last_item),
           CHECK_CASE(a_models_actuated_pair_is_planar_when_it_moves_in_the_plane))
