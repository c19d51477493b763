// parakin C runtime: Krawczyk's certificate of candidate roots of square polynomial systems in
// complex interval arithmetic with outward rounding (parakin.solvers.certify.certify_roots is
// its NumPy reference: the same test, radii, scaling and realness arguments; there the rounding
// errors are bounded by an a-priori model, here every operation is enclosed as it is done).
// Copied into every homotopy package's driver by the generator (generator/emit.py), which
// exports it as NAME_certify_roots; compiled on its own by tests/test_c_runtime.py.
//
// A system of n equations in n unknowns z: term t is c_t prod_i z_i^a_ti in equation e_t. For a
// centre x, any matrix Y and the polydisc B(x, r) = {z : |z_i - x_i| <= r}, if
//     ||Y F(x)|| + (||I - Y J(x)|| + ||Y|| L(r)) r < r,   L(r) >= max_{z in B} ||J(z) - J(x)||
// (max-norm, operator infinity norm), B holds exactly one root (Krawczyk 1969; Rump, Acta
// Numerica 2010). Row k of J(z) - J(x) sums to at most r H_k(|x| + r), H_k(rho) = sum_{t in k}
// |c_t| sum_{i,j} a_ti (a_tj - [i = j]) rho^(a_t - e_i - e_j) (certify.py's module docstring);
// here ||Y|| L(r) is bounded by max_k sum_i |Y_ki| H_i r (certify.py: ||Y|| max_i H_i r), never
// larger, and much smaller where the equations' scales differ (roots of very different sizes);
// and ||Y F(x)|| by the computed Y F~ with its rounding and Y's image of F's radius (certify.py:
// || |Y| |F~| ||), far smaller where J is ill conditioned (kw_bound).
//
// Rounding: IEEE double, round to nearest, no FMA contraction needed nor harmful, no -ffast-math.
// A rounded result c of one operation is within 2^-53 |c| + 2^-1075 of the exact one, so
// kw_up(c) >= exact >= kw_down(c) (kw_up's result is at least the next double above c). F(x) and
// J(x) are evaluated in circular complex arithmetic (kw_disc: a midpoint and a radius that
// encloses the rounding errors so far); every upper bound (norms, radii, H, the test's left
// side) is a chain of operations on non-negative upper bounds, each rounded up by kw_up (or a
// short group of them at once, kw_up_expression / kw_up_count, with a proven slack). The test
// is therefore exact: a box that passes holds exactly one root of the given coefficients.
//
// Where the first attempt fails although its candidate is near a root (the Newton step stalls
// at double precision's rounding of F: terms that cancel by many orders, close roots), a second
// attempt evaluates F in double-word arithmetic (kw_accurate_f, about 2^-100 of the terms'
// sizes), whose Newton steps may move the candidate KW_REACH (a candidate tracked in double near
// an ill-conditioned root stops up to ~0.2 of its size from it): certify.py leaves such roots to its
// exact-arithmetic certificate (rus6's roots near infinity, ~20 ms each in Python, are decided
// here in ~0.3 ms each). Where J is conditioned beyond double, that attempt also takes Y = Y2 Y1
// (kw_precondition, Rump's preconditioner). So every box the NumPy reference certifies is
// certified here too, and some more.
//
// Realness: a box B(x, r) that passes holds one root z*; where some |Im x_i| > r (affine) it
// misses the real space, so z* is not real. Where the system's coefficients are real (the given
// ones, and the scaled ones: real numbers times powers of two, in discs about themselves), the
// conjugate of a root is a root (conj F(z) = F(conj z)), and |conj(z*)_i - x_i| <= |z*_i - x_i| +
// 2 |Im x_i|: conj z* lies in B(x, R), R = r + 2 max |Im x_i|. Where the test passes on B(x, R)
// as well, that box holds exactly one root, both z* and conj z* lie in it, so conj z* = z*: real.
// The test never passes on a box holding two conjugate roots z != conj z: it proves exactly one.
// So one evaluation, inverse and bound at x decide uniqueness and realness together:
// - at a real centre (R = r: the box is its own conjugate) for a real system's candidate whose
//   imaginary parts are within the test's reach (KW_NEAR of its size): projected on the real
//   space, sharpened by Newton steps kept real, tested there alone (kw_real_centre). Where that
//   fails (a non-real root near the real space, a stalled step) the complex sequence below runs
//   as if it had not been tried;
// - there, at the complex centre, the same bounds (||Y F(x)||, ||I - Y J(x)||, ||Y||) on B(x, R)
//   too: kw_passes once more (the Lipschitz term, O(terms)); where that fails, a second test at
//   Re x with the radius max |Im x_i| + r, whose box B(Re x, need) holds B(x, r) and is its own
//   conjugate;
// - homogeneous (projective): the same with the patched system's mirror s (kw_mirror_radius: a
//   root's conjugate moved back into the complex patch, a root again; its fixed points are the
//   real projective points) on a box about x holding B(x, r) and its image, before the test in
//   the real chart.
// The outward rounding is the same throughout: each argument needs only that a test passes, on
// a radius bounded above with every operation rounded up.
//
// Needs <math.h>. No allocation: the caller passes a workspace of kw_workspace_bytes().
#ifndef PARAKIN_RUNTIME_KRAWCZYK_H
#define PARAKIN_RUNTIME_KRAWCZYK_H

// certify.py's constants: NEAR, MULTIPLIERS, NEWTON_STEPS, FLOOR, UNIT
#define KW_NEAR 1e-06
// How far (times the candidate's max-norm) the second (double-word) attempt's Newton steps may
// move a candidate that double precision could not certify within KW_NEAR: rus6's endpoints
// near roots of size 1e5..1e8 (near infinity) stop 1e-7..0.2 of their size from the root. Any
// root certified is a root, and distinct ones are counted as distinct however far their
// candidates moved (the exact-arithmetic certificate, which this one replaces there, moves
// them without a limit); its box is still at most KW_NEAR of the centre's size wide.
#define KW_REACH 0.25
// Newton steps with the preconditioned Y (kw_precondition) where the double-word attempt's test fails
#define KW_PRECONDITIONED_STEPS 2
#define KW_RADII 5
static const double kw_multipliers[KW_RADII] = {2.0, 8.0, 64.0, 1024.0, 65536.0};
#define KW_NEWTON_STEPS 2
// certify.py's SETTLED: the Newton steps stop after one of at most this times the centre's
// max-norm. Newton converges quadratically: after a step of relative size d the centre is within
// ~K d^2 of the root (K: J's conditioning times the curvature), at rounding for d <= 1e-10 unless
// J is ill conditioned, and the tracker's endpoints (refined to ~1e-12) take one such step. Sound
// for any value: Newton only sharpens the centre, the test decides; where it fails the complex
// sequence and the double-word attempt (all of its steps) follow as before. Dietmaier's 40 and
// the captured jobs of 6 families: the same decisions, 9-13 % less time.
#define KW_SETTLED 1e-10
#define KW_FLOOR 0x1p-600
// certify.py's ZERO_SIZE: a coordinate of a candidate at most this times the candidate's largest
// is a zero to rounding and gives its coordinate no typical size
#define KW_ZERO_SIZE 0x1p-40
#define KW_UNIT 0x1p-53
// the most unknowns a system may have (a job with more is refused)
#define KW_MAX_UNKNOWNS 64
// n rounded up to a multiple of 4: rows of this stride let loops over a row run in whole vectors
#define KW_PAD(n) (((n) + 3) / 4 * 4)

// the least double above every real within 2^-53 |v| + 2^-1075 of v (at least the next double)
static inline double kw_up(double v) { return v + (fabs(v) * 0x1p-52 + 0x1p-1074); }
static inline double kw_down(double v) { return v - (fabs(v) * 0x1p-52 + 0x1p-1074); }
// rounded-up sum and product of non-negative upper bounds
static inline double kw_add_up(double a, double b) { return kw_up(a + b); }
static inline double kw_mul_up(double a, double b) { return kw_up(a * b); }
// a bound on the rounding errors of operations whose rounded results have magnitudes summing to
// s (at most 16 of them, s computed in round to nearest): 2^-53 s + 16 * 2^-1075 and more
static inline double kw_error(double s) { return s * 0x1p-52 + 0x1p-1070; }

// fmax and fmin without the library call (x86-64 has no instruction with their NaN rule): the
// larger (smaller) of a and b, and the other where one is NaN; where both are zeros, a (fmax may
// give either: every caller's zeros are +0)
static inline double kw_max(double a, double b) { return (b > a || a != a) ? b : a; }
static inline double kw_min(double a, double b) { return (b < a || a != a) ? b : a; }

// 2^e for -1022 <= e <= 1023 (a normal double), from its bits
static inline double kw_pow2(long long e) {
    union { unsigned long long bits; double value; } v;
    v.bits = (unsigned long long)(e + 1023) << 52;
    return v.value;
}
// ldexp(v, e) without the library call where 2^e is a normal double: v 2^e rounded once, as
// ldexp rounds it (exact unless it leaves the normal range)
static inline double kw_ldexp(double v, long long e) { return e >= -1022 && e <= 1023 ? v * kw_pow2(e) : ldexp(v, (int)e); }

// upper and lower bounds on |re + i im|
static inline double kw_abs_up(double re, double im) {
    double v = kw_up(sqrt(kw_add_up(kw_mul_up(re, re), kw_mul_up(im, im))));
    double other = kw_add_up(fabs(re), fabs(im));  // where the squares overflow (a select: loops over it vectorize)
    return isinf(v) && isfinite(re) && isfinite(im) ? other : v;
}
static double kw_abs_down(double re, double im) {
    double a = fabs(re), b = fabs(im), big = a > b ? a : b;
    double s = kw_down(kw_down(a * a) + kw_down(b * b));
    double v = s > 0.0 ? kw_down(sqrt(s)) : 0.0;
    if (!(v <= INFINITY) || isinf(v) || v < big) v = big;  // max(|re|, |im|) <= |z| always
    return v;
}

// the complex numbers within r of re + i im
typedef struct { double re, im, r; } kw_disc;

static inline kw_disc kw_point(double re, double im) { return (kw_disc){re, im, 0.0}; }

// An upper bound on the exact value of a non-negative expression v computed in round to nearest
// by at most 32 operations: a sum of products, each factor a double or a sum of doubles (no
// subtraction, no division, no product of a product that may underflow): each rounding is
// relative, at most 2^-53, or absolute, at most 2^-1075 (an underflowing product, summed, never
// multiplied afterwards), so exact <= v (1 + 2^-53)^32 + 32 * 2^-1075 <= v (1 + 2^-46) + 2^-1068,
// and the rounding of this last sum is covered by the slack (a group of operations rounded up
// at once).
static inline double kw_up_expression(double v) { return v + (v * 0x1p-46 + 0x1p-1066); }

// The same for at most 4096 such operations (sums of products of two factors): exact <= v (1 +
// 2^-53)^4096 + 4096 * 2^-1075 <= v (1 + 2^-40) + 2^-1050, with the slack covering this sum
static inline double kw_up_long(double v) { return v + (v * 0x1p-40 + 0x1p-1050); }

// The same for a sum of at most `count` (< 2^40) such operations: exact <= v (1 + 2^-53)^count
// + count 2^-1075 <= v (1 + count 2^-51) + count 2^-1073
static inline double kw_up_count(double v, double count) { return v + (v * (count * 0x1p-51) + count * 0x1p-1073); }

static inline kw_disc kw_add(kw_disc a, kw_disc b) {
    kw_disc out = {a.re + b.re, a.im + b.im, 0.0};
    // radii plus the two roundings: 2^-53 (|re| + |im|) (additions do not underflow)
    out.r = kw_up_expression(a.r + b.r + (fabs(out.re) + fabs(out.im)) * 0x1p-52);
    return out;
}

static inline kw_disc kw_mul(kw_disc a, kw_disc b) {
    kw_disc out = {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re, 0.0};
    // ma = |re| + |im| >= |a~|, so |a b - a~ b~| <= ma r_b + mb r_a + r_a r_b; the midpoint's six
    // roundings are each within 2^-53 of their results, whose magnitudes sum to at most
    // 2 (1 + 2^-53)^2 ma mb (the four products sum to ma mb, each part of the result to its two),
    // + 2^-1075 for each product that underflows: 2^-51 ma mb (its own two roundings at most
    // 2^-1074 below) + 2^-1068 bounds them all
    double ma = fabs(a.re) + fabs(a.im), mb = fabs(b.re) + fabs(b.im);
    out.r = kw_up_expression(ma * mb * 0x1p-51 + ma * b.r + mb * a.r + a.r * b.r + 0x1p-1068);
    return out;
}

static inline double kw_disc_abs_up(kw_disc a) { return kw_add_up(kw_abs_up(a.re, a.im), a.r); }
static inline int kw_finite(kw_disc a) { return isfinite(a.re) && isfinite(a.im) && isfinite(a.r); }

// One system: term t has coefficient (c[2t], c[2t + 1]) within cr[t], exponents a[t * n ...],
// equation eq[t]; deg the largest exponent of any unknown.
typedef struct {
    long long terms, n, deg;
    const double* c;
    const double* cr;
    const long long* a;
    const long long* eq;
    double* size;  // |c_t| + cr_t rounded up (kw_sizes)
    int accurate;  // F in double-word arithmetic (kw_accurate_f): the second attempt
    // the terms' supports (kw_supports): term t's unknowns of nonzero exponent, increasing, at
    // support[t * n ...], count[t] of them, total[t] its degree
    long long* support;
    long long* count;
    long long* total;
    // the terms by equation taken in turn (each equation's terms in order: kw_passes' sums over
    // them run side by side), and for a term of degree 2 its sum of second-derivative weights
    // (kw_passes: no power of rho in it)
    long long* turns;
    double* fixed;
} kw_system;

// the supports of a system's terms, once per set of exponents (the loops over a term's unknowns
// visit its support alone, in the same order: the same operations as a scan of all n)
static void kw_supports(kw_system* s) {
    long long n = s->n;
    for (long long t = 0; t < s->terms; ++t) {
        const long long* a = s->a + t * n;
        long long q = 0, total = 0;
        for (long long i = 0; i < n; ++i)
            if (a[i]) { s->support[t * n + q++] = i; total += a[i]; }
        s->count[t] = q;
        s->total[t] = total;
        // kw_passes' sum for a term of degree 2: every pair's factors have exponent 0
        double sum = 0.0;
        const long long* support = s->support + t * n;
        for (long long u = 0; u < q && total == 2; ++u) {
            long long i = support[u];
            for (long long v = 0; v < q; ++v) {
                long long j = support[v], pair = a[i] * (a[j] - (i == j));
                if (pair > 0) sum = kw_add_up(sum, (double)pair);
            }
        }
        s->fixed[t] = sum;
    }
    // turns: term t is its equation's rank-th; the terms by rank, then in order (a counting sort)
    long long* rank = s->turns + s->terms;  // scratch: terms + 1 counts, then the ranks
    long long* seen = rank + s->terms + 1;
    for (long long k = 0; k < n; ++k) seen[k] = 0;
    for (long long t = 0; t <= s->terms; ++t) rank[t] = 0;
    for (long long t = 0; t < s->terms; ++t) ++rank[seen[s->eq[t]]++ + 1];
    for (long long t = 1; t <= s->terms; ++t) rank[t] += rank[t - 1];
    for (long long k = 0; k < n; ++k) seen[k] = 0;
    for (long long t = 0; t < s->terms; ++t) s->turns[rank[seen[s->eq[t]]++]++] = t;
}

// the coefficients' sizes of a system, once per set of coefficients
static void kw_sizes(kw_system* s) {
    for (long long t = 0; t < s->terms; ++t) s->size[t] = kw_add_up(kw_abs_up(s->c[2 * t], s->c[2 * t + 1]), s->cr[t]);
}

// Scratch of one candidate (carved from the caller's workspace by kw_carve)
typedef struct {
    kw_disc* powers;  // n x (deg + 1): x_i^e
    kw_disc* f;       // n
    kw_disc* jac;     // n x n, row-major
    double* mag;      // n + n x n: kw_evaluate's sums of partial sums' magnitudes
    double* lu;       // n x n complex
    double* y;        // n x n complex: the approximate inverse
    double* absy;     // n x n: |y|, rounded up
    long long* pivot; // n
    double* rho;      // n x (deg + 1): rho_i^e, rounded up
    double* step;     // n complex
    double* dw;       // n x (deg + 1) x 5: double-word powers (kw_accurate_f)
    double* y1;       // n x n complex: kw_precondition's first inverse
    kw_disc* m;       // n x n: its Y1 J
    kw_disc* g;       // n: its Y1 F
    double* absy2;    // n x n: |Y| kept while kw_precondition tries
    double* dwj;      // n x n x 5: double-word J (kw_accurate_j)
    double* jre;      // n x n: jac's midpoints' real parts, imaginary parts and radii (kw_ingredients)
    double* jim;
    double* jrad;
    double* vre;      // n x n: kw_inverse's n solves side by side (column col: the solve for e_col)
    double* vim;
    double* term;     // n x n: kw_ingredients' bounds on |(I - Y J)_kj|
} kw_scratch;

// sum += term in round to nearest, the term's radius added to sum's (a plain sum) and the new
// midpoint's |re| + |im| to mag: kw_evaluate widens both at the end (kw_up_count), not each time
static inline void kw_accumulate(kw_disc* sum, double* mag, kw_disc term) {
    sum->re += term.re;
    sum->im += term.im;
    sum->r += term.r;
    *mag += fabs(sum->re) + fabs(sum->im);
}

// F~ and J~ in round to nearest from the powers' midpoints (radii left 0): the Newton steps
static int kw_evaluate_midpoints(const kw_system* s, kw_scratch* w) {
    long long n = s->n, deg = s->deg;
    const kw_disc* powers = w->powers;
    kw_disc* f = w->f;
    kw_disc* jac = w->jac;
    for (long long t = 0; t < s->terms; ++t) {
        const long long* a = s->a + t * n;
        const long long* support = s->support + t * n;
        long long k = s->eq[t], q = s->count[t];
        double cr = s->c[2 * t], ci = s->c[2 * t + 1], mr = 1.0, mi = 0.0;
        for (long long u = 0; u < q; ++u) {
            long long i = support[u];
            const kw_disc* p = powers + i * (deg + 1) + a[i];
            double r = mr * p->re - mi * p->im;
            mi = mr * p->im + mi * p->re;
            mr = r;
        }
        f[k].re += cr * mr - ci * mi;
        f[k].im += cr * mi + ci * mr;
        for (long long u = 0; u < q; ++u) {
            long long i = support[u];
            double dr = cr * (double)a[i], di = ci * (double)a[i];
            for (long long v = 0; v < q; ++v) {
                long long j = support[v], e = a[j] - (j == i);
                if (!e) continue;
                const kw_disc* p = powers + j * (deg + 1) + e;
                double r = dr * p->re - di * p->im;
                di = dr * p->im + di * p->re;
                dr = r;
            }
            jac[k * n + i].re += dr;
            jac[k * n + i].im += di;
        }
    }
    for (long long i = 0; i < n; ++i)
        if (!kw_finite(f[i])) return 0;
    for (long long k = 0; k < n * n; ++k)
        if (!kw_finite(jac[k])) return 0;
    return 1;
}

// F and J at the point x (n complex) in disc arithmetic (rigorous: 1), or their midpoints alone
// (0); 0 when not finite
static int kw_evaluate(const kw_system* s, const double* x, kw_scratch* w, int rigorous) {
    long long n = s->n, deg = s->deg;
    for (long long i = 0; i < n; ++i) {
        kw_disc* p = w->powers + i * (deg + 1);
        p[0] = kw_point(1.0, 0.0);
        if (deg >= 1) p[1] = kw_point(x[2 * i], x[2 * i + 1]);
        if (rigorous)
            for (long long e = 2; e <= deg; ++e) p[e] = kw_mul(p[e - 1], p[1]);
        else  // kw_mul's midpoint alone (the radii are not read)
            for (long long e = 2; e <= deg; ++e) {
                double ar = p[e - 1].re, ai = p[e - 1].im, br = p[1].re, bi = p[1].im;
                p[e] = (kw_disc){ar * br - ai * bi, ar * bi + ai * br, 0.0};
            }
        w->f[i] = kw_point(0.0, 0.0);
    }
    for (long long k = 0; k < n * n; ++k) w->jac[k] = kw_point(0.0, 0.0);
    if (!rigorous) return kw_evaluate_midpoints(s, w);
    for (long long k = 0; k < n + n * n; ++k) w->mag[k] = 0.0;
    for (long long t = 0; t < s->terms; ++t) {
        const long long* a = s->a + t * n;
        const long long* support = s->support + t * n;
        long long k = s->eq[t], q = s->count[t];
        kw_disc c = {s->c[2 * t], s->c[2 * t + 1], s->cr[t]};
        kw_disc m = kw_point(1.0, 0.0);
        for (long long u = 0; u < q; ++u) {
            long long i = support[u];
            kw_disc p = w->powers[i * (deg + 1) + a[i]];
            m = u ? kw_mul(m, p) : p;
        }
        kw_accumulate(w->f + k, w->mag + k, q ? kw_mul(c, m) : c);
        for (long long u = 0; u < q; ++u) {  // d/dz_i: a_ti c_t z^(a_t - e_i)
            long long i = support[u];
            kw_disc d = a[i] == 1 ? c : kw_mul(c, kw_point((double)a[i], 0.0));  // c * 1 is exact
            for (long long v = 0; v < q; ++v) {
                long long j = support[v], e = a[j] - (j == i);
                if (e) d = kw_mul(d, w->powers[j * (deg + 1) + e]);
            }
            kw_accumulate(w->jac + k * n + i, w->mag + n + k * n + i, d);
        }
    }
    // each entry: its midpoint's roundings (2^-53 of each partial sum's |re| + |im|, summed in
    // mag) and its terms' radii (summed in r), at most 4 terms + 4 roundings per term
    double count = 8.0 * (double)s->terms + 8.0;
    for (long long i = 0; i < n; ++i) w->f[i].r = kw_up_count(w->f[i].r + w->mag[i] * 0x1p-52, count);
    for (long long k = 0; k < n * n; ++k) w->jac[k].r = kw_up_count(w->jac[k].r + w->mag[n + k] * 0x1p-52, count);
    for (long long i = 0; i < n; ++i)
        if (!kw_finite(w->f[i])) return 0;
    for (long long k = 0; k < n * n; ++k)
        if (!kw_finite(w->jac[k])) return 0;
    return 1;
}

// Double-word arithmetic (Joldes, Muller, Popescu, "Tight and rigorous error bounds for basic
// building blocks of double-word arithmetic", ACM TOMS 44(2), 2017): a value h + l, |l| <= ulp(h)/2.
// AccurateDWPlusDW (their Algorithm 6) has relative error below 3u^2/(1 - 4u) and DWTimesDW3
// (Algorithm 12, with fma) below 4u^2, u = 2^-53, without underflow. A complex double-word
// product then errs by at most 2 (4u^2 + 3u^2 (1 + 4u^2)) (ma mb) < 2^-100 ma mb (ma: |re| + |im|),
// a sum by at most 3u^2 (1 + 4u)^-1 (|a| + |b|) < 2^-102 (ma + mb). Underflow is kept out: a part
// below 2^-400 (a low part below 2^-500) moves into the radius, so every product of two parts is
// above 2^-1000 and normal, and the few subnormal intermediates err by 2^-1075, far below the
// relative bounds (products above 2^-800 carry a bound above 2^-900).
typedef struct { double h, l; } kw_dw;
typedef struct { kw_dw re, im; double r; } kw_dw_disc;

static inline kw_dw kw_two_sum(double a, double b) {
    double s = a + b, bb = s - a;
    return (kw_dw){s, (a - (s - bb)) + (b - bb)};
}
static inline kw_dw kw_fast_two_sum(double a, double b) {  // |a| >= |b| or a = 0
    double s = a + b;
    return (kw_dw){s, b - (s - a)};
}
static inline kw_dw kw_dw_add(kw_dw x, kw_dw y) {  // AccurateDWPlusDW
    kw_dw s = kw_two_sum(x.h, y.h), t = kw_two_sum(x.l, y.l);
    kw_dw v = kw_fast_two_sum(s.h, s.l + t.h);
    return kw_fast_two_sum(v.h, t.l + v.l);
}
static inline kw_dw kw_dw_mul(kw_dw x, kw_dw y) {  // DWTimesDW3
    double ch = x.h * y.h, cl1 = fma(x.h, y.h, -ch);
    double tl1 = fma(x.h, y.l, x.l * y.l), cl2 = fma(x.l, y.h, tl1);
    return kw_fast_two_sum(ch, cl1 + cl2);
}
static inline kw_dw kw_dw_neg(kw_dw x) { return (kw_dw){-x.h, -x.l}; }
static inline double kw_dw_size(kw_dw_disc a) {  // >= |re| + |im| of the midpoint
    return kw_add_up(kw_add_up(fabs(a.re.h), fabs(a.re.l)), kw_add_up(fabs(a.im.h), fabs(a.im.l)));
}
// a part too small for the error bounds moves into the radius
static inline void kw_dw_flush(kw_dw* v, double* r) {
    if (fabs(v->h) < 0x1p-400) { *r = kw_add_up(*r, kw_add_up(fabs(v->h), fabs(v->l))); v->h = v->l = 0.0; }
    else if (fabs(v->l) < 0x1p-500) { *r = kw_add_up(*r, fabs(v->l)); v->l = 0.0; }
}
static inline kw_dw_disc kw_dw_disc_mul(kw_dw_disc a, kw_dw_disc b) {
    kw_dw_disc out;
    out.re = kw_dw_add(kw_dw_mul(a.re, b.re), kw_dw_neg(kw_dw_mul(a.im, b.im)));
    out.im = kw_dw_add(kw_dw_mul(a.re, b.im), kw_dw_mul(a.im, b.re));
    double ma = kw_dw_size(a), mb = kw_dw_size(b);
    double spread = kw_add_up(kw_add_up(kw_mul_up(ma, b.r), kw_mul_up(mb, a.r)), kw_mul_up(a.r, b.r));
    out.r = kw_add_up(spread, kw_mul_up(kw_mul_up(ma, mb), 0x1p-100));
    kw_dw_flush(&out.re, &out.r);
    kw_dw_flush(&out.im, &out.r);
    return out;
}
static inline kw_dw_disc kw_dw_disc_add(kw_dw_disc a, kw_dw_disc b) {
    kw_dw_disc out = {kw_dw_add(a.re, b.re), kw_dw_add(a.im, b.im), 0.0};
    out.r = kw_add_up(kw_add_up(a.r, b.r), kw_mul_up(kw_add_up(kw_dw_size(a), kw_dw_size(b)), 0x1p-102));
    kw_dw_flush(&out.re, &out.r);
    kw_dw_flush(&out.im, &out.r);
    return out;
}
static inline kw_dw_disc kw_dw_point(double re, double im) {
    kw_dw_disc out = {{re, 0.0}, {im, 0.0}, 0.0};
    kw_dw_flush(&out.re, &out.r);
    kw_dw_flush(&out.im, &out.r);
    return out;
}

// F at the point x in double-word disc arithmetic, replacing w->f (midpoint the high parts, the
// low parts added to the radius): its rounding errors about 2^-100 of the terms' sizes, where
// double's are 2^-52 (roots of large size, whose terms cancel by many orders); 0 when not finite
static int kw_accurate_f(const kw_system* s, const double* x, kw_scratch* w) {
    long long n = s->n, deg = s->deg;
    kw_dw_disc* powers = (kw_dw_disc*)w->dw;
    kw_dw_disc f[KW_MAX_UNKNOWNS];
    for (long long i = 0; i < n; ++i) {
        kw_dw_disc* p = powers + i * (deg + 1);
        p[0] = kw_dw_point(1.0, 0.0);
        p[1] = kw_dw_point(x[2 * i], x[2 * i + 1]);
        for (long long e = 2; e <= deg; ++e) p[e] = kw_dw_disc_mul(p[e - 1], p[1]);
        f[i] = kw_dw_point(0.0, 0.0);
    }
    for (long long t = 0; t < s->terms; ++t) {
        const long long* a = s->a + t * n;
        kw_dw_disc m = kw_dw_point(s->c[2 * t], s->c[2 * t + 1]);
        m.r = kw_add_up(m.r, s->cr[t]);
        for (long long i = 0; i < n; ++i)
            if (a[i]) m = kw_dw_disc_mul(m, powers[i * (deg + 1) + a[i]]);
        f[s->eq[t]] = kw_dw_disc_add(f[s->eq[t]], m);
    }
    for (long long k = 0; k < n; ++k) {
        double r = kw_add_up(kw_add_up(f[k].r, fabs(f[k].re.l)), fabs(f[k].im.l));
        w->f[k] = (kw_disc){f[k].re.h, f[k].im.h, r};
        if (!kw_finite(w->f[k])) return 0;
    }
    return 1;
}

// J at the point of the last kw_accurate_f (its double-word powers in w->dw) in double-word disc
// arithmetic, replacing w->jac (midpoints the high parts, the low parts added to the radii): for
// kw_precondition, where J's enclosure in double (2^-52 of its terms' sizes) times |Y1| would be
// all of ||I - Y J||; 0 when not finite
static int kw_accurate_j(const kw_system* s, kw_scratch* w) {
    long long n = s->n, deg = s->deg;
    const kw_dw_disc* powers = (const kw_dw_disc*)w->dw;
    kw_dw_disc* jac = (kw_dw_disc*)w->dwj;
    for (long long k = 0; k < n * n; ++k) jac[k] = kw_dw_point(0.0, 0.0);
    for (long long t = 0; t < s->terms; ++t) {
        const long long* a = s->a + t * n;
        long long k = s->eq[t];
        kw_dw_disc c = kw_dw_point(s->c[2 * t], s->c[2 * t + 1]);
        c.r = kw_add_up(c.r, s->cr[t]);
        for (long long i = 0; i < n; ++i) {  // d/dz_i: a_ti c_t z^(a_t - e_i)
            if (!a[i]) continue;
            kw_dw_disc d = a[i] == 1 ? c : kw_dw_disc_mul(c, kw_dw_point((double)a[i], 0.0));
            for (long long j = 0; j < n; ++j) {
                long long e = a[j] - (j == i);
                if (e) d = kw_dw_disc_mul(d, powers[j * (deg + 1) + e]);
            }
            jac[k * n + i] = kw_dw_disc_add(jac[k * n + i], d);
        }
    }
    for (long long k = 0; k < n * n; ++k) {
        double r = kw_add_up(kw_add_up(jac[k].r, fabs(jac[k].re.l)), fabs(jac[k].im.l));
        w->jac[k] = (kw_disc){jac[k].re.h, jac[k].im.h, r};
        if (!kw_finite(w->jac[k])) return 0;
    }
    return 1;
}

// LU with partial pivoting of the midpoints of jac into w->lu (n x n real parts, then n x n
// imaginary parts: rows contiguous, so that the loops over a row run in vector registers; each
// entry's operations are the same, in the same order) and w->pivot (round to nearest); 0 when a
// pivot is exactly zero
static int kw_factor(long long n, kw_scratch* w) {
    double* are = w->lu;
    double* aim = w->lu + n * n;
    for (long long k = 0; k < n * n; ++k) { are[k] = w->jac[k].re; aim[k] = w->jac[k].im; }
    for (long long k = 0; k < n; ++k) {
        long long best = k;
        double largest = fabs(are[k * n + k]) + fabs(aim[k * n + k]);
        for (long long r = k + 1; r < n; ++r) {
            double v = fabs(are[r * n + k]) + fabs(aim[r * n + k]);
            if (v > largest) { best = r; largest = v; }
        }
        if (!(largest > 0.0)) return 0;
        w->pivot[k] = best;
        if (best != k)
            for (long long j = 0; j < n; ++j) {
                double t = are[k * n + j];
                are[k * n + j] = are[best * n + j];
                are[best * n + j] = t;
                t = aim[k * n + j];
                aim[k * n + j] = aim[best * n + j];
                aim[best * n + j] = t;
            }
        double pr = are[k * n + k], pi = aim[k * n + k], d = pr * pr + pi * pi;
        double ir = pr / d, ii = -pi / d;
        const double* ur = are + k * n;
        const double* ui = aim + k * n;
        for (long long r = k + 1; r < n; ++r) {
            double* rr = are + r * n;
            double* ri = aim + r * n;
            double fr = rr[k] * ir - ri[k] * ii, fi = rr[k] * ii + ri[k] * ir;
            rr[k] = fr;
            ri[k] = fi;
            for (long long j = k + 1; j < n; ++j) {
                rr[j] -= fr * ur[j] - fi * ui[j];
                ri[j] -= fr * ui[j] + fi * ur[j];
            }
        }
    }
    return 1;
}

// v (n complex) = (L U)^-1 P v in place from kw_factor's factors; 0 when not finite
static int kw_lu_solve(long long n, const kw_scratch* w, double* v) {
    const double* are = w->lu;
    const double* aim = w->lu + n * n;
    for (long long k = 0; k < n; ++k) {  // the row swaps in order, then L
        long long p = w->pivot[k];
        if (p != k) {
            double tr = v[2 * k], ti = v[2 * k + 1];
            v[2 * k] = v[2 * p]; v[2 * k + 1] = v[2 * p + 1]; v[2 * p] = tr; v[2 * p + 1] = ti;
        }
    }
    for (long long k = 0; k < n; ++k)
        for (long long r = k + 1; r < n; ++r) {
            double fr = are[r * n + k], fi = aim[r * n + k];
            v[2 * r] -= fr * v[2 * k] - fi * v[2 * k + 1];
            v[2 * r + 1] -= fr * v[2 * k + 1] + fi * v[2 * k];
        }
    for (long long k = n - 1; k >= 0; --k) {
        double sr = v[2 * k], si = v[2 * k + 1];
        for (long long j = k + 1; j < n; ++j) {
            double ur = are[k * n + j], ui = aim[k * n + j];
            sr -= ur * v[2 * j] - ui * v[2 * j + 1];
            si -= ur * v[2 * j + 1] + ui * v[2 * j];
        }
        double pr = are[k * n + k], pi = aim[k * n + k], d = pr * pr + pi * pi;
        v[2 * k] = (sr * pr + si * pi) / d;
        v[2 * k + 1] = (si * pr - sr * pi) / d;
    }
    for (long long k = 0; k < 2 * n; ++k)
        if (!isfinite(v[k])) return 0;
    return 1;
}

// y = inverse of the midpoints of jac (any matrix keeps the test sound); 0 when J~ is singular.
// The n solves of kw_lu_solve for the unit vectors, side by side: column col of (vre, vim) is
// the solve for e_col, each entry's operations those of kw_lu_solve in its order (the loops over
// the columns run in vector registers)
static int kw_inverse(long long n, kw_scratch* w) {
    if (!kw_factor(n, w)) return 0;
    const double* are = w->lu;
    const double* aim = w->lu + n * n;
    double* vre = w->vre;
    double* vim = w->vim;
    long long m = KW_PAD(n);  // the rows' stride: the columns beyond n (zero, then whatever) pad the loops to whole vectors
    for (long long k = 0; k < n; ++k)
        for (long long col = 0; col < m; ++col) {
            vre[k * m + col] = (k == col);
            vim[k * m + col] = 0.0;
        }
    for (long long k = 0; k < n; ++k) {  // the row swaps in order, then L
        long long p = w->pivot[k];
        if (p != k)
            for (long long col = 0; col < m; ++col) {
                double t = vre[k * m + col];
                vre[k * m + col] = vre[p * m + col];
                vre[p * m + col] = t;
                t = vim[k * m + col];
                vim[k * m + col] = vim[p * m + col];
                vim[p * m + col] = t;
            }
    }
    for (long long k = 0; k < n; ++k) {
        const double* kr = vre + k * m;
        const double* ki = vim + k * m;
        for (long long r = k + 1; r < n; ++r) {
            double fr = are[r * n + k], fi = aim[r * n + k];
            double* rr = vre + r * m;
            double* ri = vim + r * m;
            for (long long col = 0; col < m; ++col) {
                double vr = kr[col], vi = ki[col];
                rr[col] -= fr * vr - fi * vi;
                ri[col] -= fr * vi + fi * vr;
            }
        }
    }
    double sr[KW_MAX_UNKNOWNS], si[KW_MAX_UNKNOWNS];
    for (long long k = n - 1; k >= 0; --k) {
        for (long long col = 0; col < m; ++col) {
            sr[col] = vre[k * m + col];
            si[col] = vim[k * m + col];
        }
        for (long long j = k + 1; j < n; ++j) {
            double ur = are[k * n + j], ui = aim[k * n + j];
            const double* jr = vre + j * m;
            const double* ji = vim + j * m;
            for (long long col = 0; col < m; ++col) {
                sr[col] -= ur * jr[col] - ui * ji[col];
                si[col] -= ur * ji[col] + ui * jr[col];
            }
        }
        double pr = are[k * n + k], pi = aim[k * n + k], d = pr * pr + pi * pi;
        for (long long col = 0; col < m; ++col) {
            vre[k * m + col] = (sr[col] * pr + si[col] * pi) / d;
            vim[k * m + col] = (si[col] * pr - sr[col] * pi) / d;
        }
    }
    int finite = 1;
    for (long long k = 0; k < n; ++k)
        for (long long col = 0; col < n; ++col) {
            double re = vre[k * m + col], im = vim[k * m + col];
            finite &= isfinite(re) && isfinite(im);
            w->y[2 * (k * n + col)] = re;
            w->y[2 * (k * n + col) + 1] = im;
        }
    return finite;
}

// The Newton step J~^-1 F~ at x into w->step (round to nearest: it only sharpens the centre); 0
// when F or J is not finite or J~ is singular
static int kw_newton(const kw_system* s, const double* x, kw_scratch* w) {
    long long n = s->n;
    if (!kw_evaluate(s, x, w, 0) || (s->accurate && !kw_accurate_f(s, x, w)) || !kw_factor(n, w)) return 0;
    for (long long k = 0; k < n; ++k) { w->step[2 * k] = w->f[k].re; w->step[2 * k + 1] = w->f[k].im; }
    return kw_lu_solve(n, w, w->step);
}

// The test's ingredients at x: a >= ||Y F(x)||, b >= ||I - Y J(x)||, c >= ||Y|| (Y the inverse of
// J~); 0 when F or J is not finite or J~ is singular.
typedef struct {
    double a, b, c;
    int preconditioned;  // Y = Y2 Y1 (kw_precondition): w->y holds Y2 and w->f Y1 F
} kw_bounds;

// a >= ||Y F||, b >= ||I - Y J||, c >= ||Y|| and |Y| rounded up (absy) for y (n x n complex, as
// doubles) and the enclosures f (n) and jac (n x n) of F and J (w: scratch); 0 when not finite.
// Every sum runs over its index in order, as a row at a time would, but the n rows' sums side by
// side (their chains of dependent roundings overlap, and the loops run in vector registers).
static int kw_ingredients(long long n, const double* y, const kw_disc* f, const kw_disc* jac, double* absy,
                          kw_bounds* out, kw_scratch* w) {
    long long m = KW_PAD(n);  // the stride of the scratch rows (zeros beyond n: whole vectors)
    double* jre = w->jre;  // jac's parts
    double* jim = w->jim;
    double* jrad = w->jrad;
    double* tre = w->vre;  // y's parts and |y| transposed (tre[i m + k] = Re Y_ki)
    double* tim = w->vim;
    double* tabs = w->term;
    for (long long i = 0; i < n; ++i)
        for (long long j = 0; j < m; ++j) {
            int in = j < n;
            const kw_disc* e = jac + i * n + (in ? j : 0);
            jre[i * m + j] = in ? e->re : 0.0;
            jim[i * m + j] = in ? e->im : 0.0;
            jrad[i * m + j] = in ? e->r : 0.0;
        }
    for (long long k = 0; k < n * n; ++k) absy[k] = kw_abs_up(y[2 * k], y[2 * k + 1]);
    for (long long i = 0; i < n; ++i)
        for (long long k = 0; k < m; ++k) {
            int in = k < n;
            tre[i * m + k] = in ? y[2 * (k * n + i)] : 0.0;
            tim[i * m + k] = in ? y[2 * (k * n + i) + 1] : 0.0;
            tabs[i * m + k] = in ? absy[k * n + i] : 0.0;
        }
    // (Y F~)_k in round to nearest, bounded as (I - Y J~)_kj below: |(Y F(x))_k| <= |m| + 2^-53
    // mag + sum_i |Y_ki| r(F_i) + 4 n 2^-1075. Not || |Y| |F| ||: where J is ill conditioned
    // (rus6's roots near infinity: rows of J ~1e9 in the scaled chart, ||Y|| ~ 2), F~ at a
    // converged centre is ~1e-8 and only Y F~ is at the centre's rounding, ~1e-16.
    double rc[KW_PAD(KW_MAX_UNKNOWNS)], fr[KW_PAD(KW_MAX_UNKNOWNS)], fi[KW_PAD(KW_MAX_UNKNOWNS)];
    double fmag[KW_PAD(KW_MAX_UNKNOWNS)], fspread[KW_PAD(KW_MAX_UNKNOWNS)], ra[KW_MAX_UNKNOWNS], rb[KW_MAX_UNKNOWNS];
    for (long long k = 0; k < m; ++k) rc[k] = fr[k] = fi[k] = fmag[k] = fspread[k] = 0.0;
    for (long long i = 0; i < n; ++i) {
        double er = f[i].re, ei = f[i].im, erad = f[i].r;
        const double* yr = tre + i * m;
        const double* yi = tim + i * m;
        const double* ya = tabs + i * m;
        for (long long k = 0; k < m; ++k) {
            double size = ya[k];
            rc[k] = kw_add_up(rc[k], size);
            double p1 = yr[k] * er, p2 = yi[k] * ei, p3 = yr[k] * ei, p4 = yi[k] * er;
            double pr = p1 - p2, pi = p3 + p4, sr = fr[k] + pr, si = fi[k] + pi;
            fr[k] = sr;
            fi[k] = si;
            fmag[k] += fabs(p1) + fabs(p2) + fabs(p3) + fabs(p4) + fabs(pr) + fabs(pi) + fabs(sr) + fabs(si);
            fspread[k] += size * erad;
        }
    }
    for (long long k = 0; k < n; ++k) ra[k] = kw_add_up(kw_abs_up(fr[k], fi[k]), kw_up_long(fmag[k] * 0x1p-52 + fspread[k]));
    // (I - Y J~)_kj in round to nearest, the magnitudes of its 8 n rounded results summed (each
    // rounding within 2^-53 of its result, + 2^-1075 for a product) and the spread sum_i |Y_ki|
    // r(J_ij): |(I - Y J(x))_kj| <= |m| + 2^-53 mag + spread + 4 n 2^-1075. Row k's entries at
    // once (each j's sums over i in order), its bounds into term (tabs no longer read)
    double* term = w->term;
    for (long long k = 0; k < n; ++k) {
        double mr[KW_PAD(KW_MAX_UNKNOWNS)], mi[KW_PAD(KW_MAX_UNKNOWNS)], mag[KW_PAD(KW_MAX_UNKNOWNS)];
        double spread[KW_PAD(KW_MAX_UNKNOWNS)];
        for (long long j = 0; j < m; ++j) {
            mr[j] = k == j ? 1.0 : 0.0;
            mi[j] = mag[j] = spread[j] = 0.0;
        }
        for (long long i = 0; i < n; ++i) {
            double yr = y[2 * (k * n + i)], yi = y[2 * (k * n + i) + 1], size = absy[k * n + i];
            const double* er = jre + i * m;
            const double* ei = jim + i * m;
            const double* erad = jrad + i * m;
            for (long long j = 0; j < m; ++j) {
                double p1 = yr * er[j], p2 = yi * ei[j], p3 = yr * ei[j], p4 = yi * er[j];
                double pr = p1 - p2, pi = p3 + p4, r = mr[j] - pr, q = mi[j] - pi;
                mr[j] = r;
                mi[j] = q;
                mag[j] += fabs(p1) + fabs(p2) + fabs(p3) + fabs(p4) + fabs(pr) + fabs(pi) + fabs(r) + fabs(q);
                spread[j] += size * erad[j];
            }
        }
        for (long long j = 0; j < n; ++j)
            term[k * m + j] = kw_add_up(kw_abs_up(mr[j], mi[j]), kw_up_long(mag[j] * 0x1p-52 + spread[j]));
    }
    for (long long k = 0; k < n; ++k) rb[k] = 0.0;
    for (long long j = 0; j < n; ++j)  // b's row sums over j in order, the rows side by side
        for (long long k = 0; k < n; ++k) rb[k] = kw_add_up(rb[k], term[k * m + j]);
    double a = 0.0, b = 0.0, c = 0.0;
    for (long long k = 0; k < n; ++k) {
        a = kw_max(a, ra[k]);
        b = kw_max(b, rb[k]);
        c = kw_max(c, rc[k]);
    }
    out->a = a;
    out->b = b;
    out->c = c;
    out->preconditioned = 0;
    return isfinite(a) && isfinite(b) && isfinite(c);
}

// a double-word disc as a disc: the high parts, the low parts added to the radius
static inline kw_disc kw_dw_round(kw_dw_disc v) {
    return (kw_disc){v.re.h, v.im.h, kw_add_up(kw_add_up(v.r, fabs(v.re.l)), fabs(v.im.l))};
}

// Where J is conditioned beyond double precision (||I - Y J|| >= 1 for Y the inverse of J~ in
// double: rus6's roots of size 1e6..1e8), Y = Y2 Y1 (Rump, "Inversion of extremely
// ill-conditioned matrices in floating-point", Japan J. Indust. Appl. Math. 26, 2009: one step
// of his preconditioning): Y1 the inverse of J~, J (kw_accurate_j), M = Y1 J(x) and g = Y1 F(x)
// enclosed in double-word disc arithmetic (about 2^-100 of |Y1| |J| where double's rounding of J
// and of Y1 J is the whole trouble), Y2 the inverse of M's midpoint. Y is never formed: ||Y F|| <= ||Y2 g||,
// ||I - Y J|| <= ||I - Y2 M|| (kw_ingredients on Y2, g, M), and |Y| <= |Y2| |Y1| (rounded up) for
// ||Y|| and the Lipschitz term. Any Y keeps the test sound. On success w->absy, w->y, w->f and
// w->jac hold |Y2| |Y1|, Y2, g and M (kw_passes reads absy alone) and out the bounds; 0 when a
// part is not finite or M~ is singular (w's F, J and Y are then no longer the originals).
static int kw_precondition(const kw_system* s, kw_scratch* w, kw_bounds* out) {
    long long n = s->n;
    if (!kw_accurate_j(s, w)) return 0;
    double* y1 = w->y1;
    for (long long k = 0; k < 2 * n * n; ++k) y1[k] = w->y[k];
    for (long long k = 0; k < n; ++k) {
        kw_dw_disc g = kw_dw_point(0.0, 0.0);
        for (long long i = 0; i < n; ++i) {
            kw_dw_disc f = kw_dw_point(w->f[i].re, w->f[i].im);
            f.r = kw_add_up(f.r, w->f[i].r);
            g = kw_dw_disc_add(g, kw_dw_disc_mul(kw_dw_point(y1[2 * (k * n + i)], y1[2 * (k * n + i) + 1]), f));
        }
        w->g[k] = kw_dw_round(g);
        for (long long j = 0; j < n; ++j) {
            kw_dw_disc m = kw_dw_point(0.0, 0.0);
            for (long long i = 0; i < n; ++i) {
                const kw_disc* e = w->jac + i * n + j;
                kw_dw_disc v = kw_dw_point(e->re, e->im);
                v.r = kw_add_up(v.r, e->r);
                m = kw_dw_disc_add(m, kw_dw_disc_mul(kw_dw_point(y1[2 * (k * n + i)], y1[2 * (k * n + i) + 1]), v));
            }
            w->m[k * n + j] = kw_dw_round(m);
        }
    }
    for (long long k = 0; k < n; ++k) {
        w->f[k] = w->g[k];
        if (!kw_finite(w->f[k])) return 0;
    }
    for (long long k = 0; k < n * n; ++k) {
        w->jac[k] = w->m[k];
        if (!kw_finite(w->jac[k])) return 0;
    }
    if (!kw_inverse(n, w) || !kw_ingredients(n, w->y, w->f, w->jac, w->absy, out, w)) return 0;
    // |Y2| |Y1| rounded up, into absy (|Y2| is in absy now: row k is read before it is written)
    double c = 0.0, row[KW_MAX_UNKNOWNS];
    for (long long k = 0; k < n; ++k) {
        double rc = 0.0;
        for (long long j = 0; j < n; ++j) {
            double sum = 0.0;
            for (long long i = 0; i < n; ++i)
                sum = kw_add_up(sum, kw_mul_up(w->absy[k * n + i], kw_abs_up(y1[2 * (i * n + j)], y1[2 * (i * n + j) + 1])));
            row[j] = sum;
            rc = kw_add_up(rc, sum);
        }
        for (long long j = 0; j < n; ++j) w->absy[k * n + j] = row[j];
        c = kw_max(c, rc);
    }
    out->c = c;
    out->preconditioned = 1;
    return isfinite(c);
}

// The Newton step Y2 (Y1 F~) of kw_precondition's Y into w->step (round to nearest: it only
// sharpens the centre, where J~'s LU in double stalls)
static void kw_preconditioned_step(long long n, kw_scratch* w) {
    for (long long k = 0; k < n; ++k) {
        double sr = 0.0, si = 0.0;
        for (long long i = 0; i < n; ++i) {
            double yr = w->y[2 * (k * n + i)], yi = w->y[2 * (k * n + i) + 1];
            sr += yr * w->f[i].re - yi * w->f[i].im;
            si += yr * w->f[i].im + yi * w->f[i].re;
        }
        w->step[2 * k] = sr;
        w->step[2 * k + 1] = si;
    }
}

static int kw_bound(const kw_system* s, const double* x, kw_scratch* w, kw_bounds* out) {
    long long n = s->n;
    if (!kw_evaluate(s, x, w, 1) || (s->accurate && !kw_accurate_f(s, x, w)) || !kw_inverse(n, w)) return 0;
    int ok = kw_ingredients(n, w->y, w->f, w->jac, w->absy, out, w);
    if (!s->accurate || (ok && out->b < 0.5)) return ok;
    // the double-word attempt, Y J far from I: Rump's preconditioner (kw_precondition) where
    // it gives a smaller ||I - Y J|| (w->absy restored otherwise)
    kw_bounds other;
    for (long long k = 0; k < n * n; ++k) w->absy2[k] = w->absy[k];
    if (kw_precondition(s, w, &other) && (!ok || other.b < out->b)) {
        *out = other;
        return 1;
    }
    for (long long k = 0; k < n * n; ++k) w->absy[k] = w->absy2[k];
    return ok;
}

// The test on B(x, r) with the bounds at x: 1 when it passes (its box holds exactly one root)
static int kw_passes(const kw_system* s, const double* x, double r, const kw_bounds* bounds, kw_scratch* w) {
    long long n = s->n, deg = s->deg;
    if (!(r > 0.0) || !isfinite(r)) return 0;
    for (long long i = 0; i < n; ++i) {  // rho_i^e >= (|x_i| + r)^e
        double* p = w->rho + i * (deg + 1);
        p[0] = 1.0;
        if (deg >= 1) p[1] = kw_add_up(kw_abs_up(x[2 * i], x[2 * i + 1]), r);
        for (long long e = 2; e <= deg; ++e) p[e] = kw_mul_up(p[e - 1], p[1]);
    }
    // H_k(rho), k = 0 .. n - 1, in w->step (reused: real values)
    double* h = w->step;
    for (long long k = 0; k < n; ++k) h[k] = 0.0;
    for (long long turn = 0; turn < s->terms; ++turn) {  // each h_k's sum over its terms in order
        long long t = s->turns[turn];
        const long long* a = s->a + t * n;
        const long long* support = s->support + t * n;
        long long q = s->count[t];
        if (s->total[t] < 2) continue;  // an affine term: no second derivative
        double size = s->size[t], sum = s->fixed[t];
        for (long long u = 0; u < q && s->total[t] > 2; ++u) {
            long long i = support[u];
            for (long long v = 0; v < q; ++v) {
                long long j = support[v], pair = a[i] * (a[j] - (i == j));
                if (pair <= 0) continue;
                double m = (double)pair;  // an exact small integer
                for (long long o = 0; o < q; ++o) {
                    long long l = support[o], e = a[l] - (l == i) - (l == j);
                    if (e) m = kw_mul_up(m, w->rho[l * (deg + 1) + e]);
                }
                sum = kw_add_up(sum, m);
            }
        }
        if (sum > 0.0) h[s->eq[t]] = kw_add_up(h[s->eq[t]], kw_mul_up(size, sum));
    }
    // ||Y (J(z) - J(x))|| <= max_k sum_i |Y_ki| H_i r: each row of |Y| weighs the rows of J
    // (tighter than ||Y|| max_i H_i where the equations' scales differ)
    double spread = 0.0, sum[KW_MAX_UNKNOWNS];
    for (long long k = 0; k < n; ++k) sum[k] = 0.0;
    for (long long i = 0; i < n; ++i)  // each row's sum over i in order, the rows side by side
        for (long long k = 0; k < n; ++k) sum[k] = kw_add_up(sum[k], kw_mul_up(w->absy[k * n + i], h[i]));
    for (long long k = 0; k < n; ++k) spread = kw_max(spread, sum[k]);
    double inner = kw_add_up(bounds->b, kw_mul_up(spread, r));
    double left = kw_add_up(bounds->a, kw_mul_up(inner, r));
    return left < r;
}

// The smallest passing radius of MULTIPLIERS * max(need, a) + floor, at most limit (0 when none)
static double kw_radius(const kw_system* s, const double* x, const kw_bounds* bounds, double need, double floor,
                        double limit, kw_scratch* w) {
    double base = kw_max(need, bounds->a);
    for (int m = 0; m < KW_RADII; ++m) {
        double r = kw_multipliers[m] * base + floor;
        if (!(r <= limit)) return 0.0;
        if (kw_passes(s, x, r, bounds, w)) return r;
    }
    return 0.0;
}

static inline double kw_cabs(const double* z) { return hypot(z[0], z[1]); }

static double kw_max_abs(long long n, const double* z) {
    double v = 0.0;
    for (long long i = 0; i < n; ++i) v = kw_max(v, kw_cabs(z + 2 * i));
    return v;
}

// Whether the Newton step just taken (step, n complex as doubles) is at most KW_SETTLED times the
// new centre x's max-norm (their real parts only where real_only: a real centre's steps)
static int kw_settled(long long n, const double* x, const double* step, int real_only) {
    double size = 0.0, move = 0.0;
    for (long long i = 0; i < n; ++i) {
        double xi = real_only ? fabs(x[2 * i]) : kw_cabs(x + 2 * i);
        double si = real_only ? fabs(step[2 * i]) : kw_cabs(step + 2 * i);
        size = kw_max(size, xi);
        move = kw_max(move, si);
    }
    return move <= KW_SETTLED * size;
}

// At most steps Newton steps on x in place (a step leaving the finite numbers is dropped), after
// a settled one (kw_settled) no more where stop; real_only: the real parts only (a real centre's
// steps: on real F~ and J~ the imaginary parts are zeros, +0 or -0, and x stays a real point)
static void kw_sharpen(const kw_system* s, double* x, kw_scratch* w, int steps, int real_only, int stop) {
    long long n = s->n, stride = real_only ? 2 : 1;
    for (int k = 0; k < steps; ++k) {
        if (!kw_newton(s, x, w)) continue;
        int finite = 1;
        for (long long i = 0; i < 2 * n; i += stride) finite &= isfinite(x[i] - w->step[i]);
        if (!finite) continue;
        for (long long i = 0; i < 2 * n; i += stride) x[i] -= w->step[i];
        if (stop && kw_settled(n, x, w->step, real_only)) break;
    }
}

// The real centre's test (a system of real coefficients, s->accurate 0): x = Re given, sharpened by
// KW_NEWTON_STEPS Newton steps kept real (each step's imaginary parts dropped: on real F~ and J~
// they are zeros, +0 or -0, and a centre only needs to be a real point), then one test on
// B(x, r) with r at most limit and x within limit of given. Returns r (0 when it fails); on
// success x is real (imaginary parts +0) and *floor the radius floor used. Where B(x, r) passes,
// its one root is real (the header's argument: the box is its own conjugate).
static double kw_real_centre(const kw_system* s, const double* given, double limit, double* x, double* floor,
                             kw_scratch* w) {
    long long n = s->n;
    for (long long i = 0; i < n; ++i) {
        x[2 * i] = given[2 * i];
        x[2 * i + 1] = 0.0;
    }
    kw_sharpen(s, x, w, KW_NEWTON_STEPS, 1, 1);
    double moved = 0.0;
    for (long long i = 0; i < n; ++i) moved = kw_max(moved, hypot(x[2 * i] - given[2 * i], given[2 * i + 1]));
    kw_bounds bounds;
    if (!(moved <= limit) || !kw_bound(s, x, w, &bounds)) return 0.0;
    *floor = 4 * KW_UNIT * kw_max_abs(n, x) + KW_FLOOR;
    return kw_radius(s, x, &bounds, 0.0, *floor, limit, w);
}

// The job of kw_certify (a package's NAME_certify_job has the same fields; see its header)
typedef struct {
    long long systems, candidates, terms, unknowns;
    const double* coefficients;  // systems x terms x 2 (re, im)
    const long long* exponents;  // terms x unknowns
    const long long* equation;   // terms
    const double* roots;         // systems x candidates x unknowns x 2; a non-finite row: no candidate
    long long real_coefficients;
    const long long* homogeneous;  // homogeneous_count unknowns (0: the affine certificate)
    long long homogeneous_count;
    long long patch_equation;
    int* unique;        // systems x candidates
    int* real;          // systems x candidates: +1 real, -1 non-real, 0 undecided
    double* radius;     // systems x candidates (NaN where not unique)
    double* center;     // systems x candidates x unknowns x 2
    double* radii;      // systems x candidates x unknowns (NaN where not unique)
    void* workspace;
    long long workspace_bytes;
} kw_job;

// The radius about a homogeneous candidate's centre x (the patch's chart) that holds both B(x, r)
// and the image of every point of it under the patched system's mirror (0 when it cannot be
// bounded): for a root z of a system real but for its patch L(z) = sum_t c_t z_(k_t) + c0 (each
// term linear in one unknown of the group G, or constant), conj z is a root of the homogeneous
// equations, and so is s(z) = (m conj z_G, conj z_rest), m = -c0 / sum_t c_t conj(z_(k_t)), which
// also solves the patch: a root in the patch again. s(z) = z exactly where z_rest is real and z_G
// is a complex multiple of a real vector (|m| = 1): a real projective point. Over B(x, r), with
// M enclosing sum_t c_t conj(v_(k_t)) (|M| > 0), |s(v)_i - x_i| = |-c0 conj v_i - x_i M| / |M| on
// G and |conj v_i - x_i| <= r + 2 |Im x_i| elsewhere, all rounded up (disc arithmetic).
static double kw_mirror_radius(const kw_job* job, const double* c, const int* in_group, const double* x, double r) {
    long long n = job->unknowns;
    kw_disc sum = kw_point(0.0, 0.0), c0 = kw_point(0.0, 0.0);
    for (long long t = 0; t < job->terms; ++t) {
        if (job->equation[t] != job->patch_equation) continue;
        long long k = -1;
        for (long long i = 0; i < n; ++i)
            if (job->exponents[t * n + i]) k = i;  // (kw_homogeneous: at most one, of exponent 1, in G)
        kw_disc ct = kw_point(c[2 * t], c[2 * t + 1]);
        if (k < 0) c0 = kw_add(c0, ct);
        else sum = kw_add(sum, kw_mul(ct, (kw_disc){x[2 * k], -x[2 * k + 1], r}));
    }
    double low = kw_down(kw_abs_down(sum.re, sum.im) - sum.r);
    if (!(low > 0.0) || !kw_finite(sum) || !kw_finite(c0)) return 0.0;
    kw_disc minus_c0 = {-c0.re, -c0.im, c0.r};
    double wide = r;
    for (long long i = 0; i < n; ++i) {
        double gap;
        if (in_group[i]) {
            kw_disc top = kw_add(kw_mul(minus_c0, (kw_disc){x[2 * i], -x[2 * i + 1], r}),
                                 kw_mul(kw_point(-x[2 * i], -x[2 * i + 1]), sum));
            gap = kw_up(kw_disc_abs_up(top) / low);
        } else {
            gap = kw_add_up(r, 2.0 * fabs(x[2 * i + 1]));
        }
        if (!(gap <= INFINITY)) return 0.0;  // inf - inf in a bound: it proves nothing (kw_max would drop it)
        wide = kw_max(wide, gap);
    }
    return isfinite(wide) ? wide : 0.0;
}

static long long kw_degree(long long terms, long long n, const long long* a) {
    long long d = 0;
    for (long long k = 0; k < terms * n; ++k) d = a[k] > d ? a[k] : d;
    return d;
}

#define KW_ALIGN(b) (((b) + 15) / 16 * 16)

// bytes of workspace for a job of these sizes (deg: the largest exponent)
static long long kw_workspace_bytes(long long candidates, long long terms, long long n, long long deg) {
    long long b = 0;
    b += KW_ALIGN(n * (deg + 1) * (long long)sizeof(kw_disc));  // powers
    b += KW_ALIGN(n * (long long)sizeof(kw_disc));  // f
    b += KW_ALIGN(n * n * (long long)sizeof(kw_disc));  // jac
    b += KW_ALIGN((n + n * n) * (long long)sizeof(double));  // mag
    b += 2 * KW_ALIGN(2 * n * n * (long long)sizeof(double));  // lu, y
    b += KW_ALIGN(n * n * (long long)sizeof(double));  // absy
    b += KW_ALIGN(n * (long long)sizeof(long long));  // pivot
    b += KW_ALIGN(n * (deg + 1) * (long long)sizeof(double));  // rho
    b += KW_ALIGN(2 * n * (long long)sizeof(double));  // step
    b += KW_ALIGN(5 * n * (deg + 1) * (long long)sizeof(double));  // dw
    b += KW_ALIGN(2 * n * n * (long long)sizeof(double));  // y1
    b += KW_ALIGN(n * n * (long long)sizeof(kw_disc));  // m
    b += KW_ALIGN(n * (long long)sizeof(kw_disc));  // g
    b += KW_ALIGN(n * n * (long long)sizeof(double));  // absy2
    b += KW_ALIGN(5 * n * n * (long long)sizeof(double));  // dwj
    b += 6 * KW_ALIGN(n * KW_PAD(n) * (long long)sizeof(double));  // jre, jim, jrad, vre, vim, term
    b += 2 * KW_ALIGN((terms + 2) * (n + 2) * (long long)sizeof(long long));  // supports: main, chart
    b += 2 * KW_ALIGN((3 * (terms + 2) + n) * (long long)sizeof(long long));  // turns: main, chart
    b += 2 * KW_ALIGN((terms + 2) * (long long)sizeof(double));  // fixed: main, chart
    b += KW_ALIGN((candidates > 0 ? candidates : 1) * (long long)sizeof(double));  // candidates' sizes
    b += 4 * KW_ALIGN(2 * n * (long long)sizeof(double));  // x, previous, chart point, scale
    b += KW_ALIGN((candidates > 0 ? candidates : 1) * (long long)sizeof(double));  // sizes
    b += KW_ALIGN(5 * (terms + 2) * (long long)sizeof(double));  // coefficients, radii, sizes
    b += KW_ALIGN((terms + 2) * (n + 1) * (long long)sizeof(long long));  // chart exponents, equation
    b += KW_ALIGN(n * (long long)sizeof(long long));  // shifts
    return b;
}

static void* kw_take(char** cursor, long long bytes) {
    void* p = *cursor;
    *cursor += KW_ALIGN(bytes);
    return p;
}

// median of v[0 .. count) (sorted in place; count >= 1)
static double kw_median(double* v, long long count) {
    for (long long i = 1; i < count; ++i) {
        double key = v[i];
        long long j = i - 1;
        while (j >= 0 && v[j] > key) { v[j + 1] = v[j]; --j; }
        v[j + 1] = key;
    }
    return count % 2 ? v[count / 2] : 0.5 * (v[count / 2 - 1] + v[count / 2]);
}

static int kw_row_finite(long long n, const double* z) {
    for (long long i = 0; i < 2 * n; ++i)
        if (!isfinite(z[i])) return 0;
    return 1;
}

// 1 when every equation but the patch is homogeneous in the group and the patch is linear in it
static int kw_homogeneous(const kw_job* job) {
    long long n = job->unknowns;
    int present[KW_MAX_UNKNOWNS] = {0};
    long long degree[KW_MAX_UNKNOWNS];
    for (long long t = 0; t < job->terms; ++t) {
        const long long* a = job->exponents + t * n;
        long long d = 0, other = 0, k = job->equation[t];
        for (long long i = 0; i < n; ++i) {
            int member = 0;
            for (long long g = 0; g < job->homogeneous_count; ++g) member |= job->homogeneous[g] == i;
            if (member) d += a[i]; else other += a[i];
        }
        if (k == job->patch_equation) {
            if (other || d > 1) return 0;
            continue;
        }
        if (present[k] && degree[k] != d) return 0;
        present[k] = 1;
        degree[k] = d;
    }
    return 1;
}

// Krawczyk's certificate of every candidate of every system (certify_roots' semantics). Returns
// 0, or -1 when the job is malformed (sizes, indices, a workspace smaller than
// kw_workspace_bytes): nothing is written then.
static int kw_certify(const kw_job* job) {
    long long n = job->unknowns, terms = job->terms, paths = job->candidates;
    if (n < 1 || n > KW_MAX_UNKNOWNS || terms < 0 || paths < 0 || job->systems < 0) return -1;
    for (long long t = 0; t < terms; ++t) {
        if (job->equation[t] < 0 || job->equation[t] >= n) return -1;
        for (long long i = 0; i < n; ++i)
            if (job->exponents[t * n + i] < 0) return -1;
    }
    long long deg = kw_degree(terms, n, job->exponents);
    deg = deg > 1 ? deg : 1;
    if (job->workspace_bytes < kw_workspace_bytes(paths, terms, n, deg)) return -1;
    int homogeneous = job->homogeneous_count > 0;
    if (homogeneous) {
        if (job->patch_equation < 0 || job->patch_equation >= n) return -1;
        for (long long g = 0; g < job->homogeneous_count; ++g)
            if (job->homogeneous[g] < 0 || job->homogeneous[g] >= n) return -1;
    }
    if (homogeneous && !kw_homogeneous(job)) return -1;
    char* cursor = (char*)job->workspace;
    kw_scratch w;
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
    w.dw = (double*)kw_take(&cursor, 5 * n * (deg + 1) * (long long)sizeof(double));
    w.y1 = (double*)kw_take(&cursor, 2 * n * n * (long long)sizeof(double));
    w.m = (kw_disc*)kw_take(&cursor, n * n * (long long)sizeof(kw_disc));
    w.g = (kw_disc*)kw_take(&cursor, n * (long long)sizeof(kw_disc));
    w.absy2 = (double*)kw_take(&cursor, n * n * (long long)sizeof(double));
    w.dwj = (double*)kw_take(&cursor, 5 * n * n * (long long)sizeof(double));
    w.jre = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.jim = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.jrad = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.vre = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.vim = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    w.term = (double*)kw_take(&cursor, n * KW_PAD(n) * (long long)sizeof(double));
    long long* support_main = (long long*)kw_take(&cursor, (terms + 2) * (n + 2) * (long long)sizeof(long long));
    long long* support_chart = (long long*)kw_take(&cursor, (terms + 2) * (n + 2) * (long long)sizeof(long long));
    long long* turns_main = (long long*)kw_take(&cursor, (3 * (terms + 2) + n) * (long long)sizeof(long long));
    long long* turns_chart = (long long*)kw_take(&cursor, (3 * (terms + 2) + n) * (long long)sizeof(long long));
    double* fixed_main = (double*)kw_take(&cursor, (terms + 2) * (long long)sizeof(double));
    double* fixed_chart = (double*)kw_take(&cursor, (terms + 2) * (long long)sizeof(double));
    double* largest = (double*)kw_take(&cursor, (paths > 0 ? paths : 1) * (long long)sizeof(double));
    double* x = (double*)kw_take(&cursor, 2 * n * (long long)sizeof(double));
    double* chart_x = (double*)kw_take(&cursor, 2 * n * (long long)sizeof(double));
    double* given = (double*)kw_take(&cursor, 2 * n * (long long)sizeof(double));
    double* scale = (double*)kw_take(&cursor, 2 * n * (long long)sizeof(double));
    double* sizes = (double*)kw_take(&cursor, (paths > 0 ? paths : 1) * (long long)sizeof(double));
    double* coefficients = (double*)kw_take(&cursor, 5 * (terms + 2) * (long long)sizeof(double));
    double* radii_c = coefficients + 2 * (terms + 2);
    double* sizes_main = radii_c + (terms + 2);
    double* sizes_chart = sizes_main + (terms + 2);
    long long* chart_a = (long long*)kw_take(&cursor, (terms + 2) * (n + 1) * (long long)sizeof(long long));
    long long* chart_eq = chart_a + (terms + 2) * n;
    long long* shift = (long long*)kw_take(&cursor, n * (long long)sizeof(long long));
    // the real chart's terms (homogeneous): every term but the patch's, then z_j and -1 in the patch
    long long chart_terms = 0;
    int in_group[KW_MAX_UNKNOWNS];
    if (homogeneous) {
        
        for (long long i = 0; i < n; ++i) in_group[i] = 0;
        for (long long g = 0; g < job->homogeneous_count; ++g) in_group[job->homogeneous[g]] = 1;
        for (long long t = 0; t < terms; ++t) {
            if (job->equation[t] == job->patch_equation) continue;
            for (long long i = 0; i < n; ++i) chart_a[chart_terms * n + i] = job->exponents[t * n + i];
            chart_eq[chart_terms++] = job->equation[t];
        }
        for (long long i = 0; i < 2 * n; ++i) chart_a[chart_terms * n + i] = 0;
        chart_eq[chart_terms] = chart_eq[chart_terms + 1] = job->patch_equation;
        chart_terms += 2;
    }
    for (long long sys = 0; sys < job->systems; ++sys) {
        const double* c = job->coefficients + 2 * sys * terms;
        int real_system = job->real_coefficients != 0;
        for (long long t = 0; t < terms; ++t)
            if (c[2 * t + 1] != 0.0 && !(homogeneous && job->equation[t] == job->patch_equation)) real_system = 0;
        // affine: each coordinate measured in a power of two near its typical size (median of the
        // |z_i| over the system's finite candidates where it is not zero to rounding, at most
        // KW_ZERO_SIZE times the candidate's largest |z_j|; 1 where there is none)
        for (long long p = 0; p < paths && !homogeneous; ++p) {  // each candidate's largest |z_j|, once
            const double* z = job->roots + 2 * ((sys * paths + p) * n);
            largest[p] = kw_row_finite(n, z) ? kw_max_abs(n, z) : NAN;
        }
        for (long long i = 0; i < n && !homogeneous; ++i) {
            long long count = 0;
            for (long long p = 0; p < paths; ++p) {
                const double* z = job->roots + 2 * ((sys * paths + p) * n);
                if (!(largest[p] == largest[p])) continue;  // not finite (kw_max_abs of a finite row is not NaN)
                double v = kw_cabs(z + 2 * i);
                if (v > 0.0 && v > KW_ZERO_SIZE * largest[p]) sizes[count++] = v;
            }
            double typical = 1.0;
            if (count) {
                double median = kw_median(sizes, count);
                if (isfinite(median) && median > 0.0) typical = exp2(nearbyint(log2(median)));
            }
            scale[2 * i] = typical;
        }
        for (long long p = 0; p < paths; ++p) {
            long long at = sys * paths + p;
            const double* z = job->roots + 2 * at * n;
            double* centre = job->center + 2 * at * n;
            int present = kw_row_finite(n, z);
            kw_system s = {terms, n, deg, c, radii_c, job->exponents, job->equation, sizes_main, 0,
                           support_main, support_main + (terms + 2) * n, support_main + (terms + 2) * (n + 1),
                           turns_main, fixed_main};
            if (sys == 0 && p == 0) kw_supports(&s);  // one set of exponents for every system
            double unit = 1e-150;
            for (long long i = 0; i < n; ++i) shift[i] = 0;
            if (!homogeneous) {
                unit = 0.5;
                for (long long i = 0; i < n; ++i) {
                    double v = kw_cabs(z + 2 * i);
                    if (isfinite(z[2 * i]) && isfinite(z[2 * i + 1]))
                        shift[i] = (long long)ceil(log2(kw_max(v, scale[2 * i])));
                }
                for (long long t = 0; t < terms; ++t) {
                    long long e = 0;
                    for (long long i = 0; i < n; ++i) e += shift[i] * job->exponents[t * n + i];
                    if (e > 4000) e = 4000;
                    if (e < -4000) e = -4000;
                    double re = kw_ldexp(c[2 * t], e), im = kw_ldexp(c[2 * t + 1], e);
                    coefficients[2 * t] = re;
                    coefficients[2 * t + 1] = im;
                    // exact unless it left the normal range: then within 2^-1074 (or infinite)
                    int exact = (re == 0.0 || fabs(re) >= 0x1p-1022) && (im == 0.0 || fabs(im) >= 0x1p-1022) &&
                                (re != 0.0 || c[2 * t] == 0.0) && (im != 0.0 || c[2 * t + 1] == 0.0);
                    radii_c[t] = exact ? 0.0 : 0x1p-1073;
                }
                s.c = coefficients;
                kw_sizes(&s);
            } else {
                for (long long t = 0; t < terms; ++t) radii_c[t] = 0.0;
                if (p == 0) kw_sizes(&s);  // the system's own coefficients: one set for every candidate
            }
            for (long long i = 0; i < n; ++i) {
                double f = kw_ldexp(1.0, shift[i]);
                given[2 * i] = z[2 * i] / f;
                given[2 * i + 1] = z[2 * i + 1] / f;
                x[2 * i] = present ? given[2 * i] : 1.0;
                x[2 * i + 1] = present ? given[2 * i + 1] : 0.0;
            }
            job->unique[at] = 0;
            job->real[at] = 0;
            job->radius[at] = NAN;
            for (long long i = 0; i < n; ++i) job->radii[at * n + i] = NAN;
            if (!present) {
                for (long long i = 0; i < 2 * n; ++i) centre[i] = NAN;
                continue;
            }
            kw_bounds bounds;
            double r = 0.0, floor = 0.0;
            // a real system's candidate whose imaginary parts are within the test's reach: first
            // one test at a real centre, which decides uniqueness and realness at once (the
            // header's argument); where it fails, the sequence below as if it had not been tried
            int real_centre = 0;
            if (real_system && !homogeneous) {
                double limit = KW_NEAR * kw_max(kw_max_abs(n, given), unit), imag = 0.0;
                for (long long i = 0; i < n; ++i) imag = kw_max(imag, fabs(given[2 * i + 1]));
                s.accurate = 0;
                if (imag <= limit) r = kw_real_centre(&s, given, limit, x, &floor, &w);
                real_centre = r > 0.0;
            }
            for (s.accurate = 0; s.accurate < 2 && !real_centre; ++s.accurate) {
                // the first attempt in double, a second with F in double-word arithmetic where the
                // first's centre stalled (its Newton step still above the test's reach) or Newton
                // in double moved it beyond KW_NEAR (the second may move it KW_REACH)
                for (long long i = 0; i < 2 * n; ++i) x[i] = given[i];
                kw_sharpen(&s, x, &w, KW_NEWTON_STEPS + s.accurate, 0, !s.accurate);  // (double-word: every step)
                for (long long i = 0; i < n; ++i) {
                    double f = kw_ldexp(1.0, shift[i]);
                    centre[2 * i] = x[2 * i] * f;
                    centre[2 * i + 1] = x[2 * i + 1] * f;
                }
                double limit = KW_NEAR * kw_max(kw_max_abs(n, given), unit);
                double reach = s.accurate ? KW_REACH / KW_NEAR * limit : limit;
                double moved = 0.0;
                for (long long i = 0; i < n; ++i) moved = kw_max(moved, hypot(x[2 * i] - given[2 * i], x[2 * i + 1] - given[2 * i + 1]));
                if (!(moved <= reach) || !kw_bound(&s, x, &w, &bounds)) continue;
                floor = 4 * KW_UNIT * kw_max_abs(n, x) + KW_FLOOR;
                r = kw_radius(&s, x, &bounds, 0.0, floor, limit, &w);
                // a centre that J~'s LU left short (J conditioned beyond double: its Newton steps
                // stall ~1e-14 away, where the Lipschitz term wants ~1e-15): steps x - Y2 (Y1 F~)
                // with kw_precondition's Y, each followed by the test
                for (int k = 0; !(r > 0.0) && bounds.preconditioned && k < KW_PRECONDITIONED_STEPS; ++k) {
                    kw_preconditioned_step(n, &w);
                    int finite = 1;
                    for (long long i = 0; i < 2 * n; ++i) finite &= isfinite(x[i] - w.step[i]);
                    if (!finite) break;
                    for (long long i = 0; i < 2 * n; ++i) x[i] -= w.step[i];
                    moved = 0.0;
                    for (long long i = 0; i < n; ++i) {
                        double f = kw_ldexp(1.0, shift[i]);
                        centre[2 * i] = x[2 * i] * f;
                        centre[2 * i + 1] = x[2 * i + 1] * f;
                        moved = kw_max(moved, hypot(x[2 * i] - given[2 * i], x[2 * i + 1] - given[2 * i + 1]));
                    }
                    if (!(moved <= reach) || !kw_bound(&s, x, &w, &bounds)) break;
                    floor = 4 * KW_UNIT * kw_max_abs(n, x) + KW_FLOOR;
                    r = kw_radius(&s, x, &bounds, 0.0, floor, limit, &w);
                }
                if (r > 0.0) break;
            }
            if (!(r > 0.0)) continue;
            if (real_centre)
                for (long long i = 0; i < n; ++i) {
                    centre[2 * i] = x[2 * i] * kw_ldexp(1.0, shift[i]);
                    centre[2 * i + 1] = 0.0;
                }
            double smallest = INFINITY;
            for (long long i = 0; i < n; ++i) {
                double f = kw_ldexp(1.0, shift[i]), v = r * f;
                // exact unless it (or the centre) left the normal range: widened over both roundings
                if (v < 0x1p-1000) v = kw_up(v) + 0x1p-1073;
                job->radii[at * n + i] = v;
                smallest = kw_min(smallest, f);
            }
            job->unique[at] = 1;
            job->radius[at] = r * smallest;
            if (real_centre) {  // B(x, r) is its own conjugate: its one root is real
                job->real[at] = 1;
                continue;
            }
            // realness: a box missing the real space holds a non-real root
            int nonreal = 0;
            for (long long i = 0; i < n; ++i)
                if ((!homogeneous || !in_group[i]) && fabs(x[2 * i + 1]) > r) nonreal = 1;
            if (!homogeneous) {
                if (!nonreal && real_system) {
                    double imag = 0.0;
                    for (long long i = 0; i < n; ++i) imag = kw_max(imag, fabs(x[2 * i + 1]));
                    // the same test (its bounds at x) on B(x, r + 2 max |Im x_i|), which holds the
                    // root and its conjugate: where it passes they are one, real
                    if (kw_passes(&s, x, kw_add_up(r, 2.0 * imag), &bounds, &w)) {
                        job->real[at] = 1;
                        continue;
                    }
                    // else a second test: B(x, r) lies in the conjugation-symmetric B(Re x, need)
                    for (long long i = 0; i < n; ++i) {
                        chart_x[2 * i] = x[2 * i];
                        chart_x[2 * i + 1] = 0.0;
                    }
                    double need = kw_add_up(imag, r);
                    if (kw_bound(&s, chart_x, &w, &bounds) && kw_radius(&s, chart_x, &bounds, need, floor, INFINITY, &w) > 0.0)
                        job->real[at] = 1;
                }
                if (nonreal) job->real[at] = -1;
                continue;
            }
            // homogeneous: j the group's unknown of largest |x_j|; a real projective point has
            // Im(z_i conj z_j) = 0, which moves at most r (|x_i| + |x_j| + r) over B(x, r)
            long long j = job->homogeneous[0];
            for (long long g = 1; g < job->homogeneous_count; ++g)
                if (kw_cabs(x + 2 * job->homogeneous[g]) > kw_cabs(x + 2 * j)) j = job->homogeneous[g];
            double xjr = x[2 * j], xji = x[2 * j + 1];
            double mj = kw_abs_up(xjr, xji), mj_low = kw_abs_down(xjr, xji);
            for (long long i = 0; i < n && !nonreal; ++i) {
                if (!in_group[i]) continue;
                double p1 = x[2 * i + 1] * xjr, p2 = x[2 * i] * xji, cross = p1 - p2;
                double low = kw_down(fabs(cross) - kw_error(fabs(p1) + fabs(p2) + fabs(cross)));
                double mi = kw_abs_up(x[2 * i], x[2 * i + 1]);
                double slack = kw_mul_up(r, kw_add_up(kw_add_up(mi, mj), r));
                if (low > slack) nonreal = 1;
            }
            if (nonreal) {
                job->real[at] = -1;
                continue;
            }
            if (!real_system) continue;
            // the same test (its bounds at x) on a box that holds B(x, r) and its mirror image
            // (kw_mirror_radius): where it passes, the root is its own mirror image, real
            double wide = kw_mirror_radius(job, c, in_group, x, r);
            if (wide > 0.0 && kw_passes(&s, x, wide, &bounds, &w)) {
                job->real[at] = 1;
                continue;
            }
            if (!(4.0 * r <= mj_low)) continue;
            // the real chart z_j = 1: w_i = Re(x_i / x_j) on the group, Re x_i elsewhere; the chart
            // image of B(x, r) lies in B(w, need) (certify.py's argument; 4 r <= |x_j|)
            double d = xjr * xjr + xji * xji, need = 0.0;
            for (long long i = 0; i < n; ++i) {
                double gap;
                if (in_group[i]) {
                    double wi = i == j ? 1.0 : (x[2 * i] * xjr + x[2 * i + 1] * xji) / d;
                    chart_x[2 * i] = wi;
                    // |x_i - w_i x_j| / |x_j| + 2 r (|x_i| + |x_j|) / |x_j|^2, rounded up
                    kw_disc v = kw_add(kw_point(x[2 * i], x[2 * i + 1]), kw_mul(kw_point(-wi, 0.0), kw_point(xjr, xji)));
                    double mi = kw_abs_up(x[2 * i], x[2 * i + 1]);
                    double spread = kw_up(kw_mul_up(2.0 * r, kw_add_up(mi, mj)) / mj_low);
                    gap = kw_up(kw_add_up(kw_disc_abs_up(v), spread) / mj_low);
                } else {
                    chart_x[2 * i] = x[2 * i];
                    gap = kw_add_up(fabs(x[2 * i + 1]), r);
                }
                chart_x[2 * i + 1] = 0.0;
                need = kw_max(need, gap);
            }
            for (long long t = 0, q = 0; t < terms; ++t) {
                if (job->equation[t] == job->patch_equation) continue;
                coefficients[2 * q] = c[2 * t];
                coefficients[2 * q + 1] = c[2 * t + 1];
                radii_c[q++] = 0.0;
            }
            for (long long i = 0; i < n; ++i) chart_a[(chart_terms - 2) * n + i] = i == j;
            coefficients[2 * (chart_terms - 2)] = 1.0;
            coefficients[2 * (chart_terms - 1)] = -1.0;
            coefficients[2 * (chart_terms - 2) + 1] = coefficients[2 * (chart_terms - 1) + 1] = 0.0;
            radii_c[chart_terms - 2] = radii_c[chart_terms - 1] = 0.0;
            kw_system chart = {chart_terms, n, deg, coefficients, radii_c, chart_a, chart_eq, sizes_chart, s.accurate,
                               support_chart, support_chart + (terms + 2) * n, support_chart + (terms + 2) * (n + 1),
                               turns_chart, fixed_chart};
            kw_sizes(&chart);
            kw_supports(&chart);
            if (kw_bound(&chart, chart_x, &w, &bounds) && kw_radius(&chart, chart_x, &bounds, need, floor, INFINITY, &w) > 0.0)
                job->real[at] = 1;
        }
    }
    return 0;
}


// certify.py's cluster_labels, bit for bit: the clusters of overlapping certified boxes of each
// of systems x count candidates (centre: x 2 doubles per complex coordinate, radii: per
// coordinate, unique: 1 byte each, 0 or 1). Two certified boxes are apart where in some
// coordinate k |x_pk - x_qk| (1 - 8 u) > (r_pk + r_qk) (1 + 8 u) (hypot, as NumPy's np.hypot);
// labels (int64, systems x count): each certified candidate's cluster by its least index (the
// transitive closure of "not apart"), -1 where not unique; distinct (1 byte per system): no two
// certified boxes touch. A union-find over the least indices (each link points to a smaller index).
static void kw_clusters(long long systems, long long count, long long n, const double* centre, const double* radii,
                        const unsigned char* unique, long long* labels, unsigned char* distinct) {
    const double below = 1 - 8 * KW_UNIT, above = 1 + 8 * KW_UNIT;
    for (long long s = 0; s < systems; ++s) {
        const double* x = centre + 2 * s * count * n;
        const double* r = radii + s * count * n;
        const unsigned char* u = unique + s * count;
        long long* label = labels + s * count;
        int touching = 0;
        for (long long p = 0; p < count; ++p) label[p] = u[p] ? p : -1;
        for (long long p = 0; p < count; ++p) {
            if (!u[p]) continue;
            for (long long q = p + 1; q < count; ++q) {
                if (!u[q]) continue;
                int apart = 0;
                for (long long k = 0; k < n && !apart; ++k) {
                    const double* a = x + 2 * (p * n + k);
                    const double* b = x + 2 * (q * n + k);
                    double re = a[0] - b[0], im = a[1] - b[1], sum = (r[p * n + k] + r[q * n + k]) * above;
                    // hypot's result (within an ulp) is at least (1 - 2^-52) max(|re|, |im|): where
                    // that times (1 - 16 u) exceeds sum, so does hypot's times below (rounding is
                    // monotone), without the call (NaN parts: to hypot, which may give NaN or inf)
                    double most = fabs(re) > fabs(im) ? fabs(re) : fabs(im);
                    if (re == re && im == im && most * (1 - 16 * KW_UNIT) > sum) apart = 1;
                    else apart = hypot(re, im) * below > sum;
                }
                if (apart) continue;
                touching = 1;
                long long i = p, j = q;  // the two roots: least indices of their clusters so far
                while (label[i] != i) i = label[i];
                while (label[j] != j) j = label[j];
                if (i < j) label[j] = i;
                else if (j < i) label[i] = j;
            }
        }
        for (long long p = 0; p < count && touching; ++p)  // each link's target is final before it
            if (label[p] >= 0) label[p] = label[label[p]];
        distinct[s] = !touching;
    }
}

#endif
