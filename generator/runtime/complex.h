// parakin C runtime: complex numbers as two doubles (C99 without <complex.h>, which MSVC lacks),
// the few operations the path tracker needs, inline. Copied into every homotopy package's driver
// by the generator (generator/emit.py), and compiled on its own by tests/test_c_runtime.py.
// Needs <math.h>.
#ifndef PARAKIN_RUNTIME_COMPLEX_H
#define PARAKIN_RUNTIME_COMPLEX_H

typedef struct { double re, im; } cplx;

static inline cplx c_mul(cplx a, cplx b) { return (cplx){a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
static inline cplx c_sub(cplx a, cplx b) { return (cplx){a.re - b.re, a.im - b.im}; }
static inline cplx c_add(cplx a, cplx b) { return (cplx){a.re + b.re, a.im + b.im}; }
static inline cplx c_scale(double f, cplx a) { return (cplx){f * a.re, f * a.im}; }
static inline double c_abs(cplx a) { return hypot(a.re, a.im); }
// |re| + |im|: within a factor sqrt(2) of |a|, enough to choose pivots and far cheaper than hypot
static inline double c_norm1(cplx a) { return fabs(a.re) + fabs(a.im); }
static inline cplx c_inv(cplx a) {
    double d = a.re * a.re + a.im * a.im;
    return (cplx){a.re / d, -a.im / d};
}
static inline cplx c_div(cplx a, cplx b) { return c_mul(a, c_inv(b)); }

#endif
