// Unit tests of the parakin C runtime's Krawczyk certificate (krawczyk.h) on its own;
// tests/test_c_runtime.py compiles and runs this with the system compiler. Prints "failed: ..."
// for each check that fails and "checked N" at the end; exits 1 if any failed.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "krawczyk.h"

static int failures = 0, checks = 0;

static void check(int ok, const char* what) {
    checks += 1;
    if (!ok) {
        printf("failed: %s\n", what);
        failures += 1;
    }
}

// kw_up / kw_down against the exact rounding error of a sum (Knuth's TwoSum) and of a product
// (fma: a * b - fl(a b) exactly), on values across the exponent range
static void test_rounding(void) {
    double values[] = {0.1, 1.0 / 3.0, 2.0 / 3.0, 1e-300, 3e-310, 1e300, 12345.678, 0x1p-1074, 1.0 - 0x1p-53, 7.0};
    int count = (int)(sizeof(values) / sizeof(values[0]));
    for (int i = 0; i < count; ++i)
        for (int j = 0; j < count; ++j)
            for (int sign = -1; sign <= 1; sign += 2) {
                double a = values[i], b = sign * values[j];
                double s = a + b, bb = s - a, err = (a - (s - bb)) + (b - bb);  // a + b = s + err exactly
                check(kw_up(s) - s >= err || err <= 0.0, "kw_up: a sum's exact value above the bound");
                check(s - kw_down(s) >= -err || err >= 0.0, "kw_down: a sum's exact value below the bound");
                check(kw_up(s) > s && kw_down(s) < s, "kw_up/kw_down: not strictly outside");
                double p = a * b, perr = fma(a, b, -p);  // exact when the product does not underflow
                if (fabs(p) >= 0x1p-1000 && isfinite(p)) {
                    check(kw_up(p) - p >= perr, "kw_up: a product's exact value above the bound");
                    check(p - kw_down(p) >= -perr, "kw_down: a product's exact value below the bound");
                }
            }
    // |3 + 4i| = 5 exactly; the bounds enclose it
    check(kw_abs_up(3.0, 4.0) >= 5.0 && kw_abs_down(3.0, 4.0) <= 5.0, "kw_abs: |3 + 4i| = 5 not enclosed");
    check(kw_abs_up(1e300, 1e300) >= 1e300 * sqrt(2.0) * (1 - 1e-15), "kw_abs_up: overflowing squares");
}

// one system: terms (c, a, eq), candidates z; outputs per candidate
typedef struct {
    int unique[8], real[8];
    double radius[8], center[8 * 2 * 2], radii[8 * 2];
} outcome;

static int certify(long long terms, long long n, const double* c, const long long* a, const long long* eq,
                   long long candidates, const double* z, const long long* group, long long groups, long long patch,
                   outcome* out) {
    static char space[1 << 16];
    kw_job job = {1, candidates, terms, n, c, a, eq, z, 1, group, groups, patch, out->unique, out->real,
                  out->radius, out->center, out->radii, space, (long long)sizeof(space)};
    return kw_certify(&job);
}

// z^2 - 2 = 0: +-sqrt 2 are real, simple roots; z^2 + 1: +-i are non-real; (z - 1)^2: a double root
// is never unique; a candidate far from any root is not certified; a non-finite row is no candidate
static void test_univariate(void) {
    long long a[] = {2, 0}, eq[] = {0, 0};
    double two[] = {1.0, 0.0, -2.0, 0.0};
    double z[] = {1.41421356, 1e-9, -1.4142135623730951, 0.0, 0.5, 0.0, NAN, 0.0};
    outcome out;
    check(certify(2, 1, two, a, eq, 4, z, NULL, 0, -1, &out) == 0, "z^2 - 2: refused");
    check(out.unique[0] && out.unique[1], "z^2 - 2: a simple root not certified");
    check(out.real[0] == 1 && out.real[1] == 1, "z^2 - 2: a real root not certified real");
    for (int p = 0; p < 2; ++p) {
        double root = p ? -sqrt(2.0) : sqrt(2.0);
        check(fabs(out.center[2 * p] - root) <= out.radii[p] && fabs(out.center[2 * p + 1]) <= out.radii[p],
              "z^2 - 2: the box misses the root");
        check(out.radii[p] < 1e-12, "z^2 - 2: the box is not tight");
    }
    check(!out.unique[2] && out.real[2] == 0 && isnan(out.radius[2]), "z^2 - 2: a candidate far from a root certified");
    check(!out.unique[3] && isnan(out.center[6]), "z^2 - 2: a non-finite row is a candidate");
    double one[] = {1.0, 0.0, 1.0, 0.0};
    double zi[] = {1e-12, 1.0, 0.0, -1.0};
    check(certify(2, 1, one, a, eq, 2, zi, NULL, 0, -1, &out) == 0, "z^2 + 1: refused");
    check(out.unique[0] && out.unique[1] && out.real[0] == -1 && out.real[1] == -1, "z^2 + 1: +-i not non-real");
    long long a3[] = {2, 1, 0}, eq3[] = {0, 0, 0};
    double square[] = {1.0, 0.0, -2.0, 0.0, 1.0, 0.0};
    double near[] = {1.0 + 1e-9, 0.0, 1.0, 0.0};
    check(certify(3, 1, square, a3, eq3, 2, near, NULL, 0, -1, &out) == 0, "(z - 1)^2: refused");
    check(!out.unique[0] && !out.unique[1] && out.real[0] == 0, "(z - 1)^2: a double root certified unique");
}

// the scratch kw_bound and kw_passes use (the first attempt's: no double-word parts) for n unknowns
static kw_scratch scratch(char* space, long long n, long long deg) {
    char* cursor = space;
    kw_scratch w;
    memset(&w, 0, sizeof(w));
    w.powers = (kw_disc*)kw_take(&cursor, n * (deg + 1) * (long long)sizeof(kw_disc));
    w.f = (kw_disc*)kw_take(&cursor, n * (long long)sizeof(kw_disc));
    w.jac = (kw_disc*)kw_take(&cursor, n * n * (long long)sizeof(kw_disc));
    w.mag = (double*)kw_take(&cursor, (n + n * n) * (long long)sizeof(double));
    w.lu = (double*)kw_take(&cursor, 2 * n * n * (long long)sizeof(double));
    w.y = (double*)kw_take(&cursor, 2 * n * n * (long long)sizeof(double));
    w.absy = (double*)kw_take(&cursor, n * n * (long long)sizeof(double));
    w.pivot = (long long*)kw_take(&cursor, n * (long long)sizeof(long long));
    w.rho = (double*)kw_take(&cursor, n * (deg + 1) * (long long)sizeof(double));
    w.step = (double*)kw_take(&cursor, 2 * n * (long long)sizeof(double));
    w.jre = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.jim = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.jrad = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.vre = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.vim = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.term = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    return w;
}

// Realness from the one test (the header's argument): (z - 3)(z^2 - 2 z + 1 + b^2) = z^3 - 5 z^2 +
// (7 + b^2) z - 3 (1 + b^2), b = 2^-21 (every coefficient exact): the real root 3 and the
// conjugate pair 1 +- i b, 2b apart across the real axis. At a centre x = 3 + 5e-7 i the test's
// bounds at x pass on B(x, r) and on B(x, r + 2 |Im x|), which holds the root's conjugate: the
// root is real. At the pair's centres 1 +- i b the widened box holds both roots, so the test must
// fail there, and at the real centre 1 at every radius (a box about a real point holds both or
// neither); the pair's candidates are certified non-real, 3's real, whatever their imaginary parts.
static void test_realness_in_one_test(void) {
    long long a[] = {3, 2, 1, 0}, eq[] = {0, 0, 0, 0};
    double b = 0x1p-21, c[] = {1.0, 0.0, -5.0, 0.0, 7.0 + b * b, 0.0, -3.0 * (1.0 + b * b), 0.0};
    check(c[4] - 7.0 == b * b && c[6] + 3.0 == -3.0 * b * b, "one test: a coefficient not exact");
    double z[] = {3.0 * (1.0 + 1e-10), 5e-7, 1.0, b, 1.0, -b, 1.0 + 1e-9, 0.0, 3.0, 1e-4};
    outcome out;
    check(certify(4, 1, c, a, eq, 5, z, NULL, 0, -1, &out) == 0, "one test: refused");
    check(out.unique[0] && out.real[0] == 1, "one test: the real root 3 not certified real");
    check(fabs(out.center[0] - 3.0) <= out.radii[0] && out.radii[0] < 1e-12, "one test: the box misses 3");
    for (int p = 1; p <= 2; ++p) {
        double im = p == 1 ? b : -b;
        check(out.unique[p] && out.real[p] == -1, "one test: a root of the conjugate pair not certified non-real");
        check(fabs(out.center[2 * p] - 1.0) <= out.radii[p] && fabs(out.center[2 * p + 1] - im) <= out.radii[p] &&
                  out.radii[p] < b,
              "one test: the box misses its root of the pair or reaches the other");
    }
    check(out.real[3] != 1 || fabs(out.center[6] - 1.0) > 1.0, "one test: the point between the pair called real");
    check(out.unique[4] && out.real[4] == 1 && fabs(out.center[8] - 3.0) <= out.radii[4],
          "one test: a candidate 1e-4 off the real axis not certified real");
    // the test itself at chosen centres
    static char space[1 << 16];
    long long support[4 * 3], count[4], total[4], turns[3 * 4 + 1 + 1], deg = 3;
    double radii_c[4] = {0.0, 0.0, 0.0, 0.0}, sizes[4], fixed[4];
    kw_system s = {4, 1, deg, c, radii_c, a, eq, sizes, 0, support, count, total, turns, fixed};
    kw_supports(&s);
    kw_sizes(&s);
    kw_scratch w = scratch(space, 1, deg);
    kw_bounds bounds;
    double three[] = {3.0, 5e-7};
    check(kw_bound(&s, three, &w, &bounds), "one test: no bounds at 3 + 5e-7 i");
    double r = kw_radius(&s, three, &bounds, 0.0, 0x1p-600, INFINITY, &w);
    check(r >= 5e-7 && r < 1e-5, "one test: B(3 + 5e-7 i, r) does not reach 3 or is not tight");
    check(kw_passes(&s, three, kw_add_up(r, 2.0 * three[1]), &bounds, &w), "one test: the widened box about 3 fails");
    double pair[] = {1.0, b};
    check(kw_bound(&s, pair, &w, &bounds), "one test: no bounds at 1 + i b");
    r = kw_radius(&s, pair, &bounds, 0.0, 0x1p-600, INFINITY, &w);
    check(r > 0.0 && r < b, "one test: 1 + i b not certified in a box of its own");
    check(!kw_passes(&s, pair, kw_add_up(r, 2.0 * b), &bounds, &w), "one test: the widened box about 1 + i b passed");
    double centre[] = {1.0, 0.0};
    check(kw_bound(&s, centre, &w, &bounds), "one test: no bounds at 1");
    int passed = 0;
    for (double radius = b / 64.0; radius <= 4.0; radius *= 1.5) passed |= kw_passes(&s, centre, radius, &bounds, &w);
    check(!passed, "one test: the test passed on a real box about the conjugate pair");
}

// (z - 1)(z - 1 - 2^-30) = z^2 - (2 + 2^-30) z + 1 + 2^-30, every coefficient exact: two simple
// roots 2^-30 apart, where double precision's rounding (2^-52 of terms of size 1, over a
// derivative of 2^-30) leaves a Newton step above the test's reach; the double-word second
// attempt certifies both, each box holding its own root alone
static void test_close_roots(void) {
    long long a[] = {2, 1, 0}, eq[] = {0, 0, 0};
    double gap = 0x1p-30, c[] = {1.0, 0.0, -(2.0 + gap), 0.0, 1.0 + gap, 0.0};
    double z[] = {1.0, 0.0, 1.0 + gap, 0.0};
    outcome out;
    check(certify(3, 1, c, a, eq, 2, z, NULL, 0, -1, &out) == 0, "close roots: refused");
    check(out.unique[0] && out.unique[1], "close roots: not both certified");
    check(out.real[0] == 1 && out.real[1] == 1, "close roots: not both real");
    for (int p = 0; p < 2; ++p) {
        check(fabs(out.center[2 * p] - z[2 * p]) <= out.radii[p], "close roots: a box misses its root");
        check(out.radii[p] < gap / 4, "close roots: a box reaches the other root");
    }
}

// With M = 2^30, M x^2 + M y^2 - 5 M = 0 and M x^2 + (M + 1) y^2 - (5 M + 3) = 0 (every
// coefficient exact; their difference is y^2 - 3): the roots (+-sqrt 2, +-sqrt 3).
// J's rows are ~2^31 and nearly parallel, ||J^-1|| ~ 1, the Hessian bound ~2^32 (rus6's roots near
// infinity in the scaled chart): at a double centre F is ~2^30 ulp, so || |Y| |F| || ~ 1e-6 is far
// above the radius the Hessian allows (~1e-10), while ||Y F|| is at the centre's rounding; the
// double-word attempt bounds Y F itself and certifies all four (the loose bound certified none).
// A candidate 1e-5 (relative) from sqrt 2, beyond KW_NEAR, is certified by that attempt.
static void test_ill_conditioned(void) {
    long long a[] = {2, 0, 0, 2, 0, 0, 2, 0, 0, 2, 0, 0}, eq[] = {0, 0, 0, 1, 1, 1};
    double m = 0x1p30, c[] = {m, 0.0, m, 0.0, -5.0 * m, 0.0, m, 0.0, m + 1.0, 0.0, -(5.0 * m + 3.0), 0.0};
    double z[16];
    for (int p = 0; p < 4; ++p) {
        z[4 * p] = (p & 1 ? -1.0 : 1.0) * sqrt(2.0) * (1.0 + 1e-9);
        z[4 * p + 1] = 1e-12;
        z[4 * p + 2] = (p & 2 ? -1.0 : 1.0) * sqrt(3.0);
        z[4 * p + 3] = 0.0;
    }
    outcome out;
    check(certify(6, 2, c, a, eq, 4, z, NULL, 0, -1, &out) == 0, "ill-conditioned: refused");
    for (int p = 0; p < 4; ++p) {
        check(out.unique[p] && out.real[p] == 1, "ill-conditioned: a simple real root not certified real");
        double x = (p & 1 ? -1.0 : 1.0) * sqrt(2.0), y = (p & 2 ? -1.0 : 1.0) * sqrt(3.0);
        // the doubles nearest sqrt 2 and sqrt 3 are within 2^-52 of them
        check(fabs(out.center[4 * p] - x) <= out.radii[2 * p] + 0x1p-52 &&
                  fabs(out.center[4 * p + 2] - y) <= out.radii[2 * p + 1] + 0x1p-52,
              "ill-conditioned: the box misses the root");
        check(out.radii[2 * p] < 1e-12, "ill-conditioned: the box is not tight");
    }
    long long a1[] = {2, 0}, eq1[] = {0, 0};
    double two[] = {1.0, 0.0, -2.0, 0.0}, far[] = {sqrt(2.0) * (1.0 + 1e-5), 0.0};
    check(certify(2, 1, two, a1, eq1, 1, far, NULL, 0, -1, &out) == 0, "z^2 - 2: refused");
    check(out.unique[0] && out.real[0] == 1 && fabs(out.center[0] - sqrt(2.0)) <= out.radii[0] + 0x1p-52,
          "z^2 - 2: a candidate 1e-5 from sqrt 2 not certified in the double-word attempt");
}

// J = [[2^30 + 6, 2^30 - 2], [2^30 + 5, 2^30 - 3]] (det -8, condition ~2^60, every entry exact)
// and F = J (z - (1, 1)): J~'s LU in double has its last pivot 16 times the true one (-2^-23 for
// -8 / (2^30 + 6)), so ||I - Y J|| is far above 1; Rump's preconditioner
// (kw_precondition: Y = Y2 Y1, Y1 J in double-word) certifies the root (1, 1), real, in a tight
// box, as exact arithmetic would (F(1, 1) = 0 exactly and J is regular).
static void test_beyond_double(void) {
    double m = 0x1p30;
    long long a[] = {1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0}, eq[] = {0, 0, 0, 1, 1, 1};
    double c[] = {m + 6.0, 0.0, m - 2.0, 0.0, -(2.0 * m + 4.0), 0.0, m + 5.0, 0.0, m - 3.0, 0.0, -(2.0 * m + 2.0), 0.0};
    double z[] = {1.0, 0.0, 1.0, 0.0};
    outcome out;
    check(certify(6, 2, c, a, eq, 1, z, NULL, 0, -1, &out) == 0, "beyond double: refused");
    check(out.unique[0] && out.real[0] == 1, "beyond double: the simple real root (1, 1) not certified real");
    check(fabs(out.center[0] - 1.0) <= out.radii[0] && fabs(out.center[2] - 1.0) <= out.radii[1] &&
              out.radii[0] < 1e-9 && out.radii[1] < 1e-9,
          "beyond double: the box misses (1, 1) or is not tight");
}

// the projective system x^2 - 4 y^2 = 0 with the patch (1 + i) x + (2 - i) y - 1 = 0: the real
// projective points (2 : 1) and (-2 : 1) in complex coordinates, certified real in the chart;
// x^2 + 4 y^2 = 0 has (2i : 1), (-2i : 1): non-real
static void test_homogeneous(void) {
    long long a[] = {2, 0, 0, 2, 1, 0, 0, 1, 0, 0}, eq[] = {0, 0, 1, 1, 1}, group[] = {0, 1};
    double c[] = {1.0, 0.0, -4.0, 0.0, 1.0, 1.0, 2.0, -1.0, -1.0, 0.0};
    double z[8];
    for (int p = 0; p < 2; ++p) {  // y = 1 / ((1 + i) x0 + (2 - i)), x = x0 y with x0 = +-2
        double x0 = p ? -2.0 : 2.0, dr = x0 + 2.0, di = x0 - 1.0, d = dr * dr + di * di;
        double yr = dr / d, yi = -di / d;
        z[4 * p] = x0 * yr; z[4 * p + 1] = x0 * yi; z[4 * p + 2] = yr; z[4 * p + 3] = yi;
    }
    outcome out;
    check(certify(5, 2, c, a, eq, 2, z, group, 2, 1, &out) == 0, "homogeneous: refused");
    check(out.unique[0] && out.unique[1] && out.real[0] == 1 && out.real[1] == 1, "homogeneous: real points not real");
    c[2] = 4.0;
    for (int p = 0; p < 2; ++p) {  // x0 = +-2i
        double x0i = p ? -2.0 : 2.0;
        // (1 + i)(i x0i) + 2 - i = -x0i + 2 + i (x0i - 1)
        double dr = 2.0 - x0i, di = x0i - 1.0, d = dr * dr + di * di, yr = dr / d, yi = -di / d;
        z[4 * p] = -x0i * yi; z[4 * p + 1] = x0i * yr; z[4 * p + 2] = yr; z[4 * p + 3] = yi;
    }
    check(certify(5, 2, c, a, eq, 2, z, group, 2, 1, &out) == 0, "homogeneous: refused");
    check(out.unique[0] && out.unique[1] && out.real[0] == -1 && out.real[1] == -1, "homogeneous: (+-2i : 1) not non-real");
    // the mirror's box (kw_mirror_radius) directly: x^2 - 2 x y + (1 -+ 2^-42) y^2 = 0 has the real
    // points (1 +- 2^-21 : 1) and the conjugate pair (1 +- i 2^-21 : 1); at the real point the
    // test passes on the box holding B(x, r) and its mirror image; at a point of the pair that box
    // holds its conjugate's point too, and the test fails
    long long a2[] = {2, 0, 1, 1, 0, 2, 1, 0, 0, 1, 0, 0}, eq2[] = {0, 0, 0, 1, 1, 1};
    double b = 0x1p-21;
    for (int pair = 0; pair < 2; ++pair) {
        double c2[] = {1.0, 0.0, -2.0, 0.0, pair ? 1.0 + b * b : 1.0 - b * b, 0.0, 1.0, 1.0, 2.0, -1.0, -1.0, 0.0};
        kw_job job = {1, 0, 6, 2, c2, a2, eq2, NULL, 1, group, 2, 1, NULL, NULL, NULL, NULL, NULL, NULL, 0};
        // x0 = 1 + b (real) or 1 + i b: y = 1 / ((1 + i) x0 + 2 - i), x = x0 y
        double x0r = pair ? 1.0 : 1.0 + b, x0i = pair ? b : 0.0;
        double dr = x0r - x0i + 2.0, di = x0r + x0i - 1.0, d = dr * dr + di * di, yr = dr / d, yi = -di / d;
        double point[] = {x0r * yr - x0i * yi, x0r * yi + x0i * yr, yr, yi};
        static char space2[1 << 16];
        long long support[6 * 2], count[6], total[6], turns[3 * 6 + 2 + 2];
        double radii_c[6] = {0.0}, sizes[6], fixed[6];
        kw_system s = {6, 2, 2, c2, radii_c, a2, eq2, sizes, 0, support, count, total, turns, fixed};
        kw_supports(&s);
        kw_sizes(&s);
        kw_scratch w = scratch(space2, 2, 2);
        kw_bounds bounds;
        int in_group[2] = {1, 1};
        check(kw_bound(&s, point, &w, &bounds), "mirror: no bounds");
        double r = kw_radius(&s, point, &bounds, 0.0, 0x1p-600, INFINITY, &w);
        check(r > 0.0 && r < b / 4, "mirror: the point not certified in a box of its own");
        double wide = kw_mirror_radius(&job, c2, in_group, point, r);
        check(wide >= r && isfinite(wide), "mirror: no radius");
        int passes = kw_passes(&s, point, wide, &bounds, &w);
        check(pair ? !passes : passes, pair ? "mirror: the box about a point of the conjugate pair passed"
                                            : "mirror: the box about the real point failed");
    }
    // a bound that overflows (c0 x_i ~ 1e600: inf - inf) gives no mirror radius, not r: z0 - z1 = 0
    // with the patch z0 = 1e300, at a centre whose first coordinate is visibly non-real
    {
        long long a3[] = {1, 0, 0, 1, 1, 0, 0, 0}, eq3[] = {0, 0, 1, 1};
        double c3[] = {1.0, 0.0, -1.0, 0.0, 1.0, 0.0, -1e300, 0.0}, x3[] = {1e300, 1e-3, 1e300, 0.0};
        kw_job job = {1, 0, 4, 2, c3, a3, eq3, NULL, 1, group, 2, 1, NULL, NULL, NULL, NULL, NULL, NULL, 0};
        int in_group[2] = {1, 1};
        check(kw_mirror_radius(&job, c3, in_group, x3, 1e285) == 0.0, "mirror: an overflowing bound dropped");
    }
    long long bad[] = {2, 0, 0, 1, 1, 0, 0, 1, 0, 0};  // x^2 - 4 y: not homogeneous
    check(certify(5, 2, c, bad, eq, 2, z, group, 2, 1, &out) == -1, "homogeneous: a non-homogeneous equation accepted");
}

static void test_refusals(void) {
    long long a[] = {2, 0}, eq[] = {0, 0}, wrong[] = {0, 1};
    double c[] = {1.0, 0.0, -2.0, 0.0}, z[] = {1.41421356, 0.0};
    int unique[1], real[1];
    double radius[1], center[2], radii[1], space[8];
    kw_job job = {1, 1, 2, 1, c, a, eq, z, 1, NULL, 0, -1, unique, real, radius, center, radii, space, sizeof(space)};
    check(kw_certify(&job) == -1, "a workspace too small accepted");
    static char big[1 << 12];
    job.workspace = big;
    job.workspace_bytes = sizeof(big);
    job.equation = wrong;
    check(kw_certify(&job) == -1, "an equation index out of range accepted");
    job.equation = eq;
    check(kw_certify(&job) == 0 && unique[0] && real[0] == 1, "the repaired job fails");
}

// kw_clusters: boxes on a line (one unknown): 0 and 3 overlap, 3 and 1 overlap (a chain: one
// cluster labelled 0), 2 is apart, 4 is not unique; the gap exactly equal to the radii's sum is
// not apart (the margins: (1 - 8u) gap < (1 + 8u) sum); a second system whose boxes are apart
static void test_clusters(void) {
    double x[] = {0.0, 0.0, 4.0, 0.0, 10.0, 0.0, 2.0, 0.0, 4.0, 0.0,   // system 0 (re, im)
                  0.0, 0.0, 0.0, 3.0, 9.0, 0.0, -9.0, 0.0, 0.0, -3.0};  // system 1
    double r[] = {1.0, 1.0, 1.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0};
    unsigned char unique[] = {1, 1, 1, 1, 0, 1, 1, 1, 1, 1}, distinct[2];
    long long labels[10];
    kw_clusters(2, 5, 1, x, r, unique, labels, distinct);
    check(labels[0] == 0 && labels[1] == 0 && labels[2] == 2 && labels[3] == 0 && labels[4] == -1,
          "the chain 0-3-1 is not one cluster labelled 0");
    check(!distinct[0] && distinct[1], "distinct flags wrong");
    for (int p = 0; p < 5; ++p) check(labels[5 + p] == p, "apart boxes share a label");
}

int main(void) {
    test_clusters();
    test_rounding();
    test_univariate();
    test_realness_in_one_test();
    test_close_roots();
    test_ill_conditioned();
    test_beyond_double();
    test_homogeneous();
    test_refusals();
    printf("checked %d\n", checks);
    if (failures) printf("%d checks failed\n", failures);
    return failures ? 1 : 0;
}
