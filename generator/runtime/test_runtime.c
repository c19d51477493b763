// Unit tests of the parakin C runtime on its own (tests/test_c_runtime.py compiles and runs this
// with the system compiler): the complex LU with two right-hand sides, the predictors (cubic and rational Hermite), and
// the path tracker on test homotopies whose paths are known in closed form. Prints one line per
// tracked path ("path <kind> <start> <status> <z re/im ...> <steps> <rejected> <evaluations>
// <factorisations>") for the Python side to compare with parakin.solvers.path_tracking.track_hermite,
// and "failed: ..." for each check that fails; exits 1 if any did.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "complex.h"

#define NZ 2
#define CORRECTIONS 3
#define INITIAL_STEP 0.05
#define PREDICTOR_TARGET 0.005
#define STEP_SAFETY 0.8
#define STEP_GROW 2.0
#define STEP_SHRINK 0.25
#define MIN_STEP 1e-12
#define ESCAPE 1e8
#define MAX_STEPS 2000
#define REFINE 8
#define END_GAP 1e-13
#define RATIONAL_GUARD 0.3
#define ONE_STEP_BASIN 0.25
#define ONE_STEP_ERROR 1e-5
#define OMEGA_DECAY 0.5
#define ONE_STEP_GOAL 0.7
#define OMEGA_FADE 0.7
#define END_REACH 0.5
#define REFINE_ERROR 1e-12
#define ACROSS_NOISE 1e-3
enum { PATH_REACHED = 0, PATH_FAILED = 1, PATH_DIVERGED = 2 };

// The test homotopies, equation k in z_k alone:
//   kind 0: z_k^2 - ((1 - s) a_k + s)    from z_k = +-1 at s = 1 to z_k = +-sqrt(a_k) at s = 0
//   kind 1: s z_k - 1                    z_k = 1/s: to infinity as s -> 0
typedef struct { int kind; cplx a[NZ]; } sparse_system;
typedef struct { const sparse_system* system; double s; } coefficients_at;

static void coefficients(const sparse_system* system, double s, coefficients_at* at) {
    at->system = system;
    at->s = s;
}

static int homotopy_eval(const coefficients_at* at, const cplx* z, cplx* value, cplx* jacobian, cplx* rate) {
    double s = at->s;
    for (int k = 0; k < NZ * NZ; ++k) jacobian[k] = (cplx){0.0, 0.0};
    for (int k = 0; k < NZ; ++k) {
        cplx a = at->system->a[k];
        if (at->system->kind == 0) {
            cplx target = c_add(c_scale(1.0 - s, a), (cplx){s, 0.0});
            if (value) value[k] = c_sub(c_mul(z[k], z[k]), target);
            jacobian[k * NZ + k] = c_scale(2.0, z[k]);
            if (rate) rate[k] = c_sub(a, (cplx){1.0, 0.0});
        } else {
            if (value) value[k] = c_sub(c_scale(s, z[k]), (cplx){1.0, 0.0});
            jacobian[k * NZ + k] = (cplx){s, 0.0};
            if (rate) rate[k] = z[k];
        }
    }
    return 1;
}

#include "tracker.h"

static int failures = 0;

static void check(int ok, const char* what) {
    if (!ok) {
        printf("failed: %s\n", what);
        failures += 1;
    }
}

static void test_solve(void) {
    // a x = b and a y = c against products computed here: a (row-major), x, y chosen
    cplx a[NZ * NZ] = {{0.0, 1e-3}, {2.0, -1.0}, {3.0, 0.5}, {-1.0, 4.0}};  // a pivot swap
    cplx x[NZ] = {{1.0, -2.0}, {0.5, 0.25}}, y[NZ] = {{-3.0, 1.0}, {0.0, 7.0}};
    cplx b[NZ], c[NZ], copy[NZ * NZ];
    for (int r = 0; r < NZ; ++r) {
        b[r] = c[r] = (cplx){0.0, 0.0};
        for (int j = 0; j < NZ; ++j) {
            b[r] = c_add(b[r], c_mul(a[r * NZ + j], x[j]));
            c[r] = c_add(c[r], c_mul(a[r * NZ + j], y[j]));
        }
    }
    memcpy(copy, a, sizeof(a));
    check(c_solve(copy, b, c), "c_solve: a regular matrix is singular");
    for (int k = 0; k < NZ; ++k) {
        check(c_abs(c_sub(b[k], x[k])) < 1e-14, "c_solve: first right-hand side");
        check(c_abs(c_sub(c[k], y[k])) < 1e-14, "c_solve: second right-hand side");
    }
    cplx singular[NZ * NZ] = {{1.0, 1.0}, {2.0, 2.0}, {0.0, 0.0}, {0.0, 0.0}};
    check(!c_solve(singular, b, NULL), "c_solve: a zero row is not singular");
}

static void test_hermite_cubic(void) {
    // z(s) = p0 + p1 s + p2 s^2 + p3 s^3: Hermite from (s0, s1) reproduces it beyond s1
    cplx p[4][NZ] = {{{1, 2}, {0, -1}}, {{-2, 0.5}, {3, 0}}, {{0.25, -1}, {1, 1}}, {{4, 0}, {-0.5, 2}}};
    double s0 = 0.9, s1 = 0.7, target = 0.45;
    cplx z0[NZ], v0[NZ], z1[NZ], v1[NZ], exact[NZ], out[NZ];
    double at[3] = {s0, s1, target};
    cplx* values[3] = {z0, z1, exact};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < NZ; ++k) {
            double s = at[i];
            values[i][k] = c_add(c_add(p[0][k], c_scale(s, p[1][k])), c_add(c_scale(s * s, p[2][k]), c_scale(s * s * s, p[3][k])));
        }
    for (int k = 0; k < NZ; ++k) {
        v0[k] = c_add(p[1][k], c_add(c_scale(2 * s0, p[2][k]), c_scale(3 * s0 * s0, p[3][k])));
        v1[k] = c_add(p[1][k], c_add(c_scale(2 * s1, p[2][k]), c_scale(3 * s1 * s1, p[3][k])));
    }
    hermite_cubic(1, s0, z0, v0, s1, z1, v1, target, out);
    for (int k = 0; k < NZ; ++k) check(c_abs(c_sub(out[k], exact[k])) < 1e-12, "hermite_cubic: a cubic is not reproduced");
    for (int history = 0; history < 2; ++history) {
        hermite_cubic(history, s0, z0, v0, s1, z1, v1, target, out);
        if (!history) {
            for (int k = 0; k < NZ; ++k) {
                cplx euler = c_add(z1[k], c_scale(target - s1, v1[k]));
                check(c_abs(c_sub(out[k], euler)) < 1e-15, "hermite_cubic: without history it is not Euler");
            }
        }
        cplx predicted[NZ];
        predict(history, s0, z0, v0, s1, z1, v1, target, predicted);
        if (!history)
            for (int k = 0; k < NZ; ++k)
                check(c_abs(c_sub(predicted[k], out[k])) < 1e-15, "predict: without history it is not Euler");
    }
}

// z_k(s) = c_k / (s - pole_k) + b_k: the rational predictor is exact where the pole is away from
// the step (the cubic is not: its error is checked to be far larger), and falls back to the cubic
// for an unknown whose pole lies in the step
static void test_predict(void) {
    cplx c[NZ] = {{1.0, 0.5}, {-0.25, 2.0}}, b[NZ] = {{0.5, -1.0}, {3.0, 0.0}};
    cplx pole[NZ] = {{0.3, 0.02}, {0.52, 0.0}};  // 0.52: inside the step from 0.7 to 0.45
    double s0 = 0.9, s1 = 0.7, target = 0.45;
    cplx z0[NZ], v0[NZ], z1[NZ], v1[NZ], exact[NZ], out[NZ], cubic[NZ];
    double at[3] = {s0, s1, target};
    cplx* values[3] = {z0, z1, exact};
    cplx* slopes[2] = {v0, v1};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < NZ; ++k) {
            cplx gap = c_sub((cplx){at[i], 0.0}, pole[k]);
            values[i][k] = c_add(c_div(c[k], gap), b[k]);
            if (i < 2) slopes[i][k] = c_sub((cplx){0.0, 0.0}, c_div(c[k], c_mul(gap, gap)));
        }
    predict(1, s0, z0, v0, s1, z1, v1, target, out);
    hermite_cubic(1, s0, z0, v0, s1, z1, v1, target, cubic);
    double scale = c_abs(exact[0]);
    check(c_abs(c_sub(out[0], exact[0])) < 1e-12 * scale, "predict: a simple pole is not followed exactly");
    check(c_abs(c_sub(cubic[0], exact[0])) > 1e-3 * scale, "predict: the test pole is too far for the cubic to miss");
    check(c_abs(c_sub(out[1], cubic[1])) == 0.0, "predict: a pole inside the step does not fall back to the cubic");
    // a quadratic b + c s + e s^2 (q = 0: no pole) is exact too
    cplx e[NZ] = {{-2.0, 1.0}, {0.75, 0.25}};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < NZ; ++k) {
            double s = at[i];
            values[i][k] = c_add(b[k], c_add(c_scale(s, c[k]), c_scale(s * s, e[k])));
            if (i < 2) slopes[i][k] = c_add(c[k], c_scale(2.0 * s, e[k]));
        }
    predict(1, s0, z0, v0, s1, z1, v1, target, out);
    for (int k = 0; k < NZ; ++k) check(c_abs(c_sub(out[k], exact[k])) < 1e-12, "predict: a quadratic is not reproduced");
}

static void track(const sparse_system* system, const cplx* start, int label) {
    step_coefficients at;
    track_counts counts = {0, 0, 0, 0, 0};
    cplx z[NZ];
    memcpy(z, start, sizeof(z));
    int status = track_path(system, 1e-7, z, &at, &counts);
    printf("path %d %d %d", system->kind, label, status);
    for (int k = 0; k < NZ; ++k) printf(" %.17g %.17g", z[k].re, z[k].im);
    printf(" %lld %lld %lld %lld\n", counts.steps, counts.rejected, counts.evaluations, counts.factorisations);
    check(counts.paths == 1, "track_path: counts one path");
    check(counts.evaluations == counts.factorisations, "track_path: one LU per evaluation");
    check(counts.rejected < counts.steps, "track_path: every step rejected");
    if (system->kind == 0) {
        check(status == PATH_REACHED, "track_path: a regular path does not reach s = 0");
        for (int k = 0; k < NZ; ++k) {
            cplx square = c_mul(z[k], z[k]);
            check(c_abs(c_sub(square, system->a[k])) < 1e-13 * (1.0 + c_abs(system->a[k])), "track_path: z^2 != a");
            // the path keeps the start's sign: Re(z / start) > 0 (no jump to the other root)
            cplx ratio = c_div(z[k], start[k]);
            check(ratio.re > 0.0, "track_path: the path jumped to the other root");
        }
    } else {
        check(status == PATH_DIVERGED, "track_path: z = 1/s does not diverge");
    }
}

// c_solve2 gives each of its two systems c_solve's results bit for bit, a singular one too
static void test_solve2(void) {
    cplx systems[3][NZ * NZ] = {{{2, 1}, {-1, 0.5}, {0.25, -3}, {1, 1}},
                                {{0.1, 0}, {7, -2}, {3, 0.5}, {-0.5, 0.25}},
                                {{1, 1}, {2, 2}, {0.5, 0.5}, {1, 1}}};  // the last singular
    cplx rhs[3][NZ] = {{{1, 0}, {0, -1}}, {{-2, 3}, {0.5, 0.5}}, {{1, 0}, {1, 0}}};
    int checked = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            cplx a[NZ * NZ], b[NZ], c[NZ], a2[NZ * NZ], b2[NZ], c2[NZ], ra[2][NZ * NZ], rb[2][NZ], rc[2][NZ];
            memcpy(a, systems[i], sizeof(a)); memcpy(b, rhs[i], sizeof(b)); memcpy(c, rhs[j], sizeof(c));
            memcpy(a2, systems[j], sizeof(a)); memcpy(b2, rhs[j], sizeof(b)); memcpy(c2, rhs[i], sizeof(c));
            memcpy(ra[0], a, sizeof(a)); memcpy(rb[0], b, sizeof(b)); memcpy(rc[0], c, sizeof(c));
            memcpy(ra[1], a2, sizeof(a)); memcpy(rb[1], b2, sizeof(b)); memcpy(rc[1], c2, sizeof(c));
            int alone = c_solve(ra[0], rb[0], rc[0]) | c_solve(ra[1], rb[1], NULL) << 1;
            int together = c_solve2(a, b, c, a2, b2, NULL);
            check(alone == together, "c_solve2: another singular verdict than c_solve");
            check(alone == ((i != 2) | (j != 2) << 1), "c_solve: the singular system not found singular");
            if (alone & 1) check(!memcmp(b, rb[0], sizeof(b)) && !memcmp(c, rc[0], sizeof(c)), "c_solve2: first not c_solve's");
            if (alone & 2) check(!memcmp(b2, rb[1], sizeof(b)), "c_solve2: second not c_solve's");
            checked += 1;
        }
    check(checked == 9, "c_solve2: not every pair checked");
}

// track_paths (two lanes) against track_path one at a time: every endpoint, status and count bit
// for bit, for paths in a given order (an odd count: the last runs alone)
static void test_track_paths(const sparse_system* system, cplx (*starts)[NZ], const int* order, int count) {
    cplx alone[4][NZ], together[4][NZ];
    int status[4], ended[4];
    step_coefficients at[2];
    track_counts one = {0, 0, 0, 0, 0}, two = {0, 0, 0, 0, 0};
    memcpy(alone, starts, sizeof(alone));
    memcpy(together, starts, sizeof(together));
    for (int i = 0; i < count; ++i) status[order[i]] = track_path(system, 1e-7, alone[order[i]], &at[0], &one);
    track_paths(system, 1e-7, together, order, count, ended, at, &two);
    for (int i = 0; i < count; ++i) {
        int p = order[i];
        check(status[p] == ended[p], "track_paths: another status than track_path");
        check(!memcmp(alone[p], together[p], sizeof(alone[p])), "track_paths: another endpoint than track_path");
    }
    check(one.paths == count && two.paths == count, "track_paths: paths not counted");
    check(one.steps == two.steps && one.rejected == two.rejected && one.evaluations == two.evaluations &&
              one.factorisations == two.factorisations,
          "track_paths: other counts than track_path");
    printf("paired %d %lld %lld %lld\n", count, two.steps, two.evaluations, two.factorisations);
}

// c_across: an update along the slope v has no part across it; one along v plus w (v^H w = 0,
// w = c (-conj v_1, conj v_0)) has w's, whatever the point it was made at
static void test_across(void) {
    cplx v[NZ] = {{1.0, 2.0}, {0.0, -0.5}}, along = {0.3, -0.7}, c = {-0.4, 1.1};
    cplx w[NZ] = {c_mul(c, (cplx){-v[1].re, v[1].im}), c_mul(c, (cplx){v[0].re, -v[0].im})};
    cplx after[NZ] = {{5.0, -1.0}, {0.25, 3.0}}, before[NZ], pure[NZ];
    double largest = 0.0;
    for (int k = 0; k < NZ; ++k) {
        cplx d = c_mul(v[k], along);
        pure[k] = c_add(after[k], d);
        before[k] = c_add(pure[k], w[k]);
        largest = c_abs(w[k]) > largest ? c_abs(w[k]) : largest;
    }
    check(c_across(pure, after, v) < 1e-15, "c_across: an update along the slope is across it");
    check(fabs(c_across(before, after, v) - largest) < 1e-14, "c_across: the part across the slope is not w");
}

int main(void) {
    test_solve();
    test_across();
    test_hermite_cubic();
    test_predict();
    sparse_system roots = {0, {{4.0, 1.0}, {-9.0, 0.5}}};
    cplx starts[4][NZ] = {{{1, 0}, {1, 0}}, {{-1, 0}, {1, 0}}, {{1, 0}, {-1, 0}}, {{-1, 0}, {-1, 0}}};
    for (int p = 0; p < 4; ++p) track(&roots, starts[p], p);
    sparse_system escaping = {1, {{0.0, 0.0}, {0.0, 0.0}}};
    track(&escaping, starts[0], 0);
    test_solve2();
    int all[4] = {0, 1, 2, 3}, some[3] = {2, 0, 3};
    test_track_paths(&roots, starts, all, 4);
    test_track_paths(&roots, starts, some, 3);
    test_track_paths(&escaping, starts, some, 3);
    if (failures) printf("%d checks failed\n", failures);
    return failures ? 1 : 0;
}
