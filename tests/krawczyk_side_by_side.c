// krawczyk.h's reorganised loops against their one-at-a-time definitions, bit for bit (run by
// tests/test_krawczyk_side_by_side.py)
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "krawczyk.h"

static unsigned long long kt_state = 88172645463325252ULL;
static double kt_uniform(void) {  // xorshift64, in [-1, 1)
    kt_state ^= kt_state << 13;
    kt_state ^= kt_state >> 7;
    kt_state ^= kt_state << 17;
    return (double)(kt_state >> 11) * 0x1p-52 - 1.0;
}
static int kt_same(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

// the definition: (I - Y J~) and Y F~ a row k at a time, each sum over its index in order
static void kt_ingredients(long long n, const double* y, const kw_disc* f, const kw_disc* jac, double* absy,
                           double* out) {
    double a = 0.0, b = 0.0, c = 0.0;
    for (long long k = 0; k < n; ++k) {
        double rc = 0.0, fr = 0.0, fi = 0.0, fmag = 0.0, fspread = 0.0;
        for (long long i = 0; i < n; ++i) {
            double yr = y[2 * (k * n + i)], yi = y[2 * (k * n + i) + 1], size = kw_abs_up(yr, yi);
            absy[k * n + i] = size;
            rc = kw_add_up(rc, size);
            double p1 = yr * f[i].re, p2 = yi * f[i].im, p3 = yr * f[i].im, p4 = yi * f[i].re;
            double pr = p1 - p2, pi = p3 + p4;
            fr += pr;
            fi += pi;
            fmag += fabs(p1) + fabs(p2) + fabs(p3) + fabs(p4) + fabs(pr) + fabs(pi) + fabs(fr) + fabs(fi);
            fspread += size * f[i].r;
        }
        double ra = kw_add_up(kw_abs_up(fr, fi), kw_up_long(fmag * 0x1p-52 + fspread));
        double rb = 0.0;
        for (long long j = 0; j < n; ++j) {
            double mr = k == j ? 1.0 : 0.0, mi = 0.0, mag = 0.0, spread = 0.0;
            for (long long i = 0; i < n; ++i) {
                double yr = y[2 * (k * n + i)], yi = y[2 * (k * n + i) + 1];
                const kw_disc* e = jac + i * n + j;
                double p1 = yr * e->re, p2 = yi * e->im, p3 = yr * e->im, p4 = yi * e->re;
                double pr = p1 - p2, pi = p3 + p4;
                mr -= pr;
                mi -= pi;
                mag += fabs(p1) + fabs(p2) + fabs(p3) + fabs(p4) + fabs(pr) + fabs(pi) + fabs(mr) + fabs(mi);
                spread += absy[k * n + i] * e->r;
            }
            rb = kw_add_up(rb, kw_add_up(kw_abs_up(mr, mi), kw_up_long(mag * 0x1p-52 + spread)));
        }
        a = fmax(a, ra);
        b = fmax(b, rb);
        c = fmax(c, rc);
    }
    out[0] = a;
    out[1] = b;
    out[2] = c;
}

int main(void) {
    long long checked_inverse = 0, checked_ingredients = 0, checked_scale = 0, checked_max = 0, checked_turns = 0;
    enum { N = 9 };
    static double lu[2 * N * N], y[2 * N * N], step[2 * N], absy[N * N], absy_ref[N * N], v[2 * N];
    static double vre[N * KW_PAD(N)], vim[N * KW_PAD(N)], jre[N * KW_PAD(N)], jim[N * KW_PAD(N)];
    static double jrad[N * KW_PAD(N)], term[N * KW_PAD(N)];
    static long long pivot[N];
    static kw_disc jac[N * N], f[N];
    kw_scratch w;
    memset(&w, 0, sizeof w);
    w.jac = jac, w.f = f, w.lu = lu, w.y = y, w.step = step, w.absy = absy, w.pivot = pivot;
    w.vre = vre, w.vim = vim, w.jre = jre, w.jim = jim, w.jrad = jrad, w.term = term;
    for (long long n = 1; n <= N; ++n)
        for (int trial = 0; trial < 40; ++trial) {
            for (long long k = 0; k < n * n; ++k) {
                // a few exact zeros and a tiny or huge scale now and then: signed zeros, cancellation
                double scale = trial % 7 == 3 ? 1e-150 : trial % 7 == 5 ? 1e150 : 1.0;
                jac[k] = (kw_disc){kt_uniform() * scale, trial % 5 == 1 && k % 3 == 0 ? 0.0 : kt_uniform() * scale,
                                   fabs(kt_uniform()) * 1e-12 * scale};
            }
            for (long long i = 0; i < n; ++i) f[i] = (kw_disc){kt_uniform() * 1e-9, kt_uniform() * 1e-9, 1e-20};
            if (!kw_inverse(n, &w)) {
                printf("failed inverse of a random matrix, n %lld trial %d\n", n, trial);
                continue;
            }
            // each column: kw_lu_solve of the unit vector (the factors kw_inverse made)
            double worst = 0.0;
            for (long long col = 0; col < n; ++col) {
                for (long long k = 0; k < n; ++k) v[2 * k] = (k == col), v[2 * k + 1] = 0.0;
                kw_lu_solve(n, &w, v);
                for (long long k = 0; k < n; ++k)
                    if (!kt_same(v[2 * k], y[2 * (k * n + col)]) || !kt_same(v[2 * k + 1], y[2 * (k * n + col) + 1]))
                        printf("failed inverse column %lld of n %lld trial %d: not kw_lu_solve's\n", col, n, trial);
                // and Y J = I (J~ the midpoints), to the conditioning of a random matrix
                for (long long k = 0; k < n; ++k) {
                    long double sr = 0, si = 0;
                    for (long long i = 0; i < n; ++i) {
                        long double yr = y[2 * (col * n + i)], yi = y[2 * (col * n + i) + 1];
                        sr += yr * jac[i * n + k].re - yi * jac[i * n + k].im;
                        si += yr * jac[i * n + k].im + yi * jac[i * n + k].re;
                    }
                    double e = (double)fabsl(sr - (col == k)) + (double)fabsl(si);
                    worst = e > worst ? e : worst;
                }
            }
            if (!(worst < 1e-6)) printf("failed Y J = I: %g off, n %lld trial %d\n", worst, n, trial);
            ++checked_inverse;
            kw_bounds got;
            double want[3];
            int ok = kw_ingredients(n, y, f, jac, absy, &got, &w);
            kt_ingredients(n, y, f, jac, absy_ref, want);
            if (!ok || !kt_same(got.a, want[0]) || !kt_same(got.b, want[1]) || !kt_same(got.c, want[2]) ||
                memcmp(absy, absy_ref, (size_t)(n * n) * sizeof(double)))
                printf("failed ingredients n %lld trial %d: %.17g %.17g %.17g, want %.17g %.17g %.17g\n", n, trial,
                       got.a, got.b, got.c, want[0], want[1], want[2]);
            ++checked_ingredients;
        }
    // kw_ldexp: ldexp's result, normal, subnormal and overflowing
    const double values[] = {1.0, -1.5, 0x1.fffffffffffffp+1023, 0x1p-1074, 0x1.8p-1060, -0x1.23456789abcdep-900, 0.0, -0.0,
                             3.14159, 0x1.0000000000001p0, INFINITY, NAN};
    for (size_t k = 0; k < sizeof values / sizeof values[0]; ++k)
        for (long long e = -2200; e <= 2200; ++e) {
            double got = kw_ldexp(values[k], e), want = ldexp(values[k], (int)e);
            if (!kt_same(got, want) && !(isnan(got) && isnan(want)))
                printf("failed kw_ldexp(%a, %lld) = %a, ldexp %a\n", values[k], e, got, want);
            ++checked_scale;
        }
    // kw_max, kw_min: fmax's and fmin's value, NaN ignored (non-negative zeros only)
    const double pairs[] = {0.0, 1.0, 2.5, INFINITY, NAN, 1e-300, 7.0};
    for (size_t i = 0; i < 7; ++i)
        for (size_t j = 0; j < 7; ++j) {
            double a = pairs[i], b = pairs[j];
            double gmax = kw_max(a, b), wmax = fmax(a, b), gmin = kw_min(a, b), wmin = fmin(a, b);
            if (!(kt_same(gmax, wmax) || (isnan(gmax) && isnan(wmax))) || !(kt_same(gmin, wmin) || (isnan(gmin) && isnan(wmin))))
                printf("failed kw_max/kw_min(%g, %g)\n", a, b);
            ++checked_max;
        }
    // kw_supports' turns: every term once, each equation's terms in their order; degree-2 weights
    for (int trial = 0; trial < 200; ++trial) {
        enum { T = 40, U = 5 };
        static long long a[T * U], eq[T], support[(T + 2) * (U + 2)], turns[3 * (T + 2) + U];
        static double fixed[T + 2];
        long long terms = 1 + trial % T, n = 1 + trial % U;
        for (long long t = 0; t < terms; ++t) {
            eq[t] = (long long)((kt_uniform() + 1.0) * 0.5 * (double)n);
            for (long long i = 0; i < n; ++i) a[t * n + i] = (long long)((kt_uniform() + 1.0) * 1.5);
        }
        kw_system s = {terms, n, 3, NULL, NULL, a, eq, NULL, 0, support, support + (T + 2) * n,
                       support + (T + 2) * (n + 1), turns, fixed};
        kw_supports(&s);
        long long seen[T] = {0}, last[U];
        for (long long k = 0; k < n; ++k) last[k] = -1;
        for (long long u = 0; u < terms; ++u) {
            long long t = turns[u];
            if (t < 0 || t >= terms || seen[t]++ || t < last[eq[t]]) printf("failed turns, trial %d\n", trial);
            last[eq[t]] = t;
            if (s.total[t] == 2) {  // the weights: sum of a_i (a_j - [i = j]) over ordered pairs = 2
                if (!(fixed[t] >= 2.0 && fixed[t] < 2.0 + 1e-12)) printf("failed fixed weight %g, trial %d\n", fixed[t], trial);
            }
        }
        ++checked_turns;
    }
    printf("checked inverse %lld ingredients %lld ldexp %lld max %lld turns %lld\n", checked_inverse,
           checked_ingredients, checked_scale, checked_max, checked_turns);
    return 0;
}
