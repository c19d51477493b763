/* real_roots.h: isolated real roots of a univariate polynomial, allocation-free.
 *
 * Copied verbatim into every generated package; parakin/solvers/polynomial.py (isolate_real_roots) is the
 * same algorithm vectorised in NumPy and makes the same floating-point operations in the same
 * order, so both return the same roots, bit for bit, as long as this file is compiled without
 * floating-point contraction (ISO C mode, e.g. -std=c99, or -ffp-contract=off): a fused
 * multiply-add in Horner's rule changes the last bits and so, rarely, a decision at a threshold.
 *
 * Method (complete by construction): the real roots of p are separated by the real roots of p'.
 * Level L of the recursion is the derivative of order m - L of p (m its effective degree), so
 * level 1 is linear and level m is p. The distinct real roots z_1 < ... < z_r of level L - 1 cut
 * the real line into r + 1 intervals on which level L is monotone; an interval holds one root iff
 * the polynomial changes sign over it, and that root is refined in its bracket (closed form for
 * degrees 1 and 2, safeguarded Newton otherwise). At each z_i the critical value is compared with
 * the size of the terms, S(z) = sum_k |q_k| |z|^k: |q(z)| / S(z) is the smallest relative change
 * of the coefficients that makes z a root (the backward error), so
 *   |q(z)| <= PK_CLUSTER_TOLERANCE * S(z)   -> z is a multiple root to working precision (cluster);
 *   |q(z)| <= near_tolerance * S(z), a local minimum of |q| that does not cross zero
 *                                           -> a complex pair close to z (near-real candidate).
 */
#ifndef PARAKIN_REAL_ROOTS_H
#define PARAKIN_REAL_ROOTS_H

#include <math.h>

#define PK_MAX_DEGREE 64
#define PK_ROOT_SIMPLE 0
#define PK_ROOT_CLUSTER 1
#define PK_ROOT_NEAR 2
/* absolute rounding noise of computed coefficients, relative to the largest one */
#define PK_NOISE (64.0 * 2.220446049250313e-16)

#define PK_EPS 2.220446049250313e-16
/* One ulp of backward error. Measured on the Wilkinson polynomial prod_{k=1..20} (x - k), whose
   coefficients are rounded to doubles: its smallest critical value is 1.77 eps S(z) (between 14
   and 15), while Horner's actual error there is below 0.1 eps S. A larger factor (a worst-case
   evaluation bound, ~2m ulps) would call its middle roots one cluster although doubles resolve
   them; a multiple root formed with a few roundings that lands above this bound is still
   reported, as two close simple roots or as a near-real candidate. */
#define PK_CLUSTER_TOLERANCE (1.0 * PK_EPS)
/* A largest coefficient below this is a vanishing polynomial, and a leading coefficient below it
   (relative to the largest) is dropped whatever leading_tolerance says: the Cauchy bound
   1 + max|q_k| / |q_L| must stay finite. */
#define PK_TINY 1e-300
/* Bisection in the exponent reaches the roots' scale from a 1e300 bound in ~20 steps, then
   bisection and Newton need at most ~60 more; the rest is margin. */
#define PK_MAX_ITERATIONS 200

static int pk_sign(double v) { return (v > 0.0) - (v < 0.0); }

/* q(x), q''(x) and S(x) = sum_k |q_k| |x|^k, the scale of the rounding in q(x), in one pass. */
static double pk_value_curvature_size(const double* q, int n, double x, double* curvature, double* size)
{
    double p = q[n], d = 0.0, dd = 0.0, ax = fabs(x), s = fabs(q[n]);
    int k;
    for (k = n - 1; k >= 0; --k) {
        dd = dd * x + d;
        d = d * x + p;
        p = p * x + q[k];
        s = s * ax + fabs(q[k]);
    }
    *curvature = 2.0 * dd;
    *size = s;
    return p;
}

/* q(x), q'(x) and S(x) in one pass. */
static double pk_value_slope_size(const double* q, int n, double x, double* slope, double* size)
{
    double p = q[n], d = 0.0, ax = fabs(x), s = fabs(q[n]);
    int k;
    for (k = n - 1; k >= 0; --k) {
        d = d * x + p;
        p = p * x + q[k];
        s = s * ax + fabs(q[k]);
    }
    *slope = d;
    *size = s;
    return p;
}

/* A point strictly inside (lo, hi). Far from the origin the bracket is split in the exponent
   (geometric mean), because the Cauchy bound can exceed the roots by many orders of magnitude. */
static double pk_split(double lo, double hi)
{
    if (lo >= 1.0 && hi > 4.0 * lo) return sqrt(lo) * sqrt(hi);
    if (hi <= -1.0 && lo < 4.0 * hi) return -(sqrt(-lo) * sqrt(-hi));
    if (lo < -4.0 && hi > 4.0) return 0.0;
    if (lo < 1.0 && hi > 4.0) return sqrt(hi);
    if (hi > -1.0 && lo < -4.0) return -sqrt(-lo);
    return 0.5 * (lo + hi);
}

/* The one root of q (degree n >= 3, monotone on the bracket) in (lo, hi), where q has sign s_hi
   near hi and -s_hi near lo, starting at x inside. Newton is taken when it stays in the bracket
   and at least halves the previous step (otherwise a far start creeps in steps of x / n); else
   the bracket is split. The bracket is closed: a converged Newton step below half an ulp lands on
   the end it came from. Stops when the next correction would be below 4 eps (1 + |x|): after a
   split, the step just taken; after two Newton steps, the quadratic prediction step * ratio^2
   (saves the confirming evaluation); and once |q(x)| <= eps S(x), when x is a root to one ulp of
   backward error, after the Newton step from there (further steps would only chase rounding:
   bisecting on in an ill-conditioned root's noise band costs ~40 evaluations). */
static double pk_refine(const double* q, int n, double lo, double hi, int s_hi, double x)
{
    double last = hi - lo;
    int newton_before = 0, it;
    for (it = 0; it < PK_MAX_ITERATIONS; ++it) {
        double slope, size, v = pk_value_slope_size(q, n, x, &slope, &size);
        double step, newton, next, moved, ratio, predicted;
        int s = pk_sign(v), inside, use_newton;
        if (v == 0.0) break;
        /* overflow far out in an outer interval: the sign there is that of the nearer infinity */
        if (v != v) s = x > 0.0 ? s_hi : -s_hi;
        if (s == s_hi)
            hi = x;
        else
            lo = x;
        step = v / slope;
        newton = x - step;
        inside = newton >= lo && newton <= hi;
        if (fabs(v) <= PK_CLUSTER_TOLERANCE * size) {
            if (inside) x = newton;
            break;
        }
        use_newton = inside && fabs(step) <= 0.5 * fabs(last);
        next = use_newton ? newton : pk_split(lo, hi);
        moved = next - x;
        ratio = moved / last;
        predicted = use_newton && newton_before ? fabs(moved) * ratio * ratio : fabs(moved);
        last = moved;
        x = next;
        newton_before = use_newton;
        if (predicted <= 4.0 * PK_EPS * (1.0 + fabs(x))) break;
    }
    return x;
}

/* Root of the quadratic q in (lo, hi): the lower one for the left interval, else the upper one.
   The cancellation-free formula; clamped because a root next to a critical point can round out. */
static double pk_quadratic_root(const double* q, double lo, double hi, int upper)
{
    double disc = q[1] * q[1] - 4.0 * q[0] * q[2];
    double t = -0.5 * (q[1] + copysign(sqrt(disc > 0.0 ? disc : 0.0), q[1]));
    double r1 = t / q[2], r2 = t != 0.0 ? q[0] / t : r1;
    double x = upper ? (r1 > r2 ? r1 : r2) : (r1 < r2 ? r1 : r2);
    return x < lo ? lo : (x > hi ? hi : x);
}

/* One level: roots of q (degree n >= 1) given the distinct real roots z[0..r-1] of q'. Writes
   roots and kinds in ascending order and returns their number (at most r + 1 <= n). */
static int pk_level(const double* q, int n, const double* z, int r, double near_tolerance, double* out,
                    int* out_kind)
{
    double v[PK_MAX_DEGREE], w[PK_MAX_DEGREE], size[PK_MAX_DEGREE], largest = 0.0, bound;
    int s[PK_MAX_DEGREE], keep[PK_MAX_DEGREE];
    int s_plus = pk_sign(q[n]), s_minus = (n % 2) ? -s_plus : s_plus;
    int i, k, count = 0, best = -1;

    for (k = 0; k < n; ++k)
        if (fabs(q[k]) > largest) largest = fabs(q[k]);
    bound = 1.0 + largest / fabs(q[n]);

    for (i = 0; i < r; ++i) {
        int cluster;
        v[i] = pk_value_curvature_size(q, n, z[i], &w[i], &size[i]);
        cluster = fabs(v[i]) <= PK_CLUSTER_TOLERANCE * size[i];
        s[i] = cluster ? 0 : pk_sign(v[i]);
        /* consecutive clusters: q is monotone between them, so |q| stays within the tolerance
           on the whole stretch; it is one multiple root, reported at its smallest |q| */
        keep[i] = cluster;
        if (!cluster)
            best = -1;
        else if (best < 0)
            best = i;
        else if (fabs(v[i]) < fabs(v[best])) {
            keep[best] = 0;
            best = i;
        } else
            keep[i] = 0;
    }

    for (i = 0; i <= r; ++i) {
        double lo = i == 0 ? -bound : z[i - 1], hi = i == r ? bound : z[i];
        int s_lo = i == 0 ? s_minus : s[i - 1], s_hi = i == r ? s_plus : s[i];
        /* an end that is a cluster has sign 0: a root next to it is that cluster */
        if (s_lo * s_hi < 0) {
            if (n == 1)
                out[count] = -q[0] / q[1];
            else if (n == 2)
                out[count] = pk_quadratic_root(q, lo, hi, i == r);
            else {
                /* start where the second-order model at the end critical point with the smaller
                   |q| crosses zero: Newton then needs ~5 steps instead of ~8 from the middle */
                double start = pk_split(lo, hi);
                int from = i == 0 ? i : (i == r || fabs(v[i - 1]) <= fabs(v[i]) ? i - 1 : i);
                if (from < r) {
                    double t = -2.0 * v[from] / w[from];
                    if (t > 0.0) {
                        double guess = from == i ? z[from] - sqrt(t) : z[from] + sqrt(t);
                        if (guess > lo && guess < hi) start = guess;
                    }
                }
                out[count] = pk_refine(q, n, lo, hi, s_hi, start);
            }
            out_kind[count++] = PK_ROOT_SIMPLE;
        }
        if (i == r) break;
        if (keep[i]) {
            out[count] = z[i];
            out_kind[count++] = PK_ROOT_CLUSTER;
        } else if (s[i] != 0) {
            int left = i == 0 ? s_minus : s[i - 1], right = i == r - 1 ? s_plus : s[i + 1];
            int lower_left = i == 0 || fabs(v[i]) < fabs(v[i - 1]);
            int lower_right = i == r - 1 || fabs(v[i]) < fabs(v[i + 1]);
            /* the coefficients carry absolute rounding errors (differences of O(1) terms): a
               value within that noise, PK_NOISE max|q_k| sum |z|^k, is near-real too, even where
               sum |q_k||z|^k is tiny (a double root at 0 with c0 of 1e-17) */
            double top = fmax(largest, fabs(q[n])), powers = 0.0;
            for (k = n; k >= 0; --k) powers = powers * fabs(z[i]) + 1.0;
            if (left == s[i] && right == s[i] && lower_left && lower_right &&
                fabs(v[i]) <= fmax(near_tolerance * size[i], PK_NOISE * top * powers)) {
                out[count] = z[i];
                out_kind[count++] = PK_ROOT_NEAR;
            }
        }
    }
    return count;
}

/* Real roots of sum_k c[k] x^k (degree <= PK_MAX_DEGREE). Writes sorted distinct roots to
   roots[0..n-1] and their kinds to kind[0..n-1] (both arrays of length >= degree), the number
   of roots at infinity to *at_infinity; returns n >= 0, or -1 when the polynomial vanishes.
   Leading coefficients with |c_k| <= leading_tolerance * max|c| are dropped (each one a root at
   infinity). A non-finite coefficient or max|c| < 1e-300 also returns -1 (nothing can be
   isolated); a degree outside [0, PK_MAX_DEGREE] returns -2.
   Declared inline only so that a driver that includes this file without calling it still
   compiles cleanly under -Wall (GCC and Clang do not report unused static inline functions). */
static inline int pk_real_roots(const double* c, int degree, double leading_tolerance, double near_tolerance,
                                double* roots, int* kind, int* at_infinity)
{
    double a[PK_MAX_DEGREE + 1], q[PK_MAX_DEGREE + 1], factorial[PK_MAX_DEGREE + 1];
    double z[PK_MAX_DEGREE], out[PK_MAX_DEGREE];
    int out_kind[PK_MAX_DEGREE];
    double scale = 0.0, threshold = leading_tolerance > PK_TINY ? leading_tolerance : PK_TINY;
    int k, j, m, r = 0, count = 0;

    *at_infinity = 0;
    if (degree < 0 || degree > PK_MAX_DEGREE) return -2;
    for (k = 0; k <= degree; ++k) {
        if (!isfinite(c[k])) return -1;
        if (fabs(c[k]) > scale) scale = fabs(c[k]);
    }
    if (!(scale >= PK_TINY)) return -1;
    for (k = 0; k <= degree; ++k) a[k] = c[k] / scale;
    m = degree;
    while (m > 0 && fabs(a[m]) <= threshold) --m;
    *at_infinity = degree - m;
    if (m == 0) return 0;

    factorial[0] = 1.0;
    for (k = 1; k <= m; ++k) factorial[k] = factorial[k - 1] * (double)k;
    /* level L holds p^(m-L), built upward by integrating: its constant term is a_j j!, the
       others follow from the level below (the same operations as the NumPy version) */
    q[0] = a[m] * factorial[m];
    for (j = m - 1; j >= 0; --j) {
        int level = m - j;
        for (k = level; k >= 1; --k) q[k] = q[k - 1] / (double)k;
        q[0] = a[j] * factorial[j];
        count = pk_level(q, level, z, r, near_tolerance, out, out_kind);
        if (j == 0) break;
        /* near-real candidates are not roots of this level: the next one is monotone across them */
        for (k = 0, r = 0; k < count; ++k)
            if (out_kind[k] != PK_ROOT_NEAR) z[r++] = out[k];
    }
    for (k = 0; k < count; ++k) {
        roots[k] = out[k];
        kind[k] = out_kind[k];
    }
    return count;
}

#endif /* PARAKIN_REAL_ROOTS_H */
