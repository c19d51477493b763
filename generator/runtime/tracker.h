// parakin C runtime: the path tracker of a parameter homotopy H(z, s) = 0, from a start solution
// at s = 1 to s = 0 (parakin.solvers.path_tracking.track_hermite is its NumPy reference: the same
// algorithm and constants). Copied into every homotopy package's driver by the generator
// (generator/emit.py), and compiled on its own with a test homotopy by tests/test_c_runtime.py.
//
// The includer defines, before including it (after complex.h):
//   NZ                  the unknowns (a constant: every work array is on the stack)
//   CORRECTIONS, INITIAL_STEP, PREDICTOR_TARGET, STEP_SAFETY, STEP_GROW, STEP_SHRINK,
//   MIN_STEP, ESCAPE, MAX_STEPS, REFINE, END_GAP, RATIONAL_GUARD, ONE_STEP_BASIN, ONE_STEP_ERROR,
//   OMEGA_DECAY
//                       the step control and predictor (parakin.solvers.path_tracking)
//   PATH_REACHED, PATH_FAILED, PATH_DIVERGED       how a path ends
//   sparse_system       the homotopy of one input, and coefficients_at its coefficients at one s:
//   static void coefficients(const sparse_system*, double s, coefficients_at*)
//   static int homotopy_eval(const coefficients_at*, const cplx* z, cplx* value, cplx* jacobian,
//                            cplx* rate)
//       H, dH/dz (NZ x NZ, row-major) and dH/ds at z; value or rate NULL when not wanted;
//       0 when not finite.
// Needs <math.h> and <string.h>.
#ifndef PARAKIN_RUNTIME_TRACKER_H
#define PARAKIN_RUNTIME_TRACKER_H

// a x = b, and a y = c where c is not NULL, in place by Gaussian elimination with partial
// pivoting (a destroyed): one factorisation serves both right-hand sides; 0 when singular.
// tests/test_c_runtime.py checks its arithmetic bit for bit against the same elimination in
// Python's floats. Measured and not kept (issue 33): the augmented rows [a | b | c] with real
// and imaginary parts apart, padded for vector lanes, branchless pivots, the pivots' inverses
// kept for the back substitution, all bit-equal: 0.34 -> 0.27 us on stewart's Jacobians alone,
// but in the packages' pipelines stewart within noise, rps3 3 % and planar_3rrr 10 % slower
// (the elimination is a chain of dependent divisions and updates, not a throughput problem).
static int c_solve(cplx* a, cplx* b, cplx* c) {
    for (int k = 0; k < NZ; ++k) {
        int best = k;
        double largest = c_norm1(a[k * NZ + k]);
        for (int r = k + 1; r < NZ; ++r)
            if (c_norm1(a[r * NZ + k]) > largest) { best = r; largest = c_norm1(a[r * NZ + k]); }
        if (!(largest > 0.0)) return 0;
        if (best != k) {
            for (int j = 0; j < NZ; ++j) { cplx t = a[k * NZ + j]; a[k * NZ + j] = a[best * NZ + j]; a[best * NZ + j] = t; }
            cplx t = b[k]; b[k] = b[best]; b[best] = t;
            if (c) { t = c[k]; c[k] = c[best]; c[best] = t; }
        }
        cplx inverse = c_inv(a[k * NZ + k]);
        for (int r = k + 1; r < NZ; ++r) {
            cplx f = c_mul(a[r * NZ + k], inverse);
            for (int j = k + 1; j < NZ; ++j) a[r * NZ + j] = c_sub(a[r * NZ + j], c_mul(f, a[k * NZ + j]));
            b[r] = c_sub(b[r], c_mul(f, b[k]));
            if (c) c[r] = c_sub(c[r], c_mul(f, c[k]));
        }
    }
    for (int k = NZ - 1; k >= 0; --k) {
        cplx inverse = c_inv(a[k * NZ + k]), sum = b[k];
        for (int j = k + 1; j < NZ; ++j) sum = c_sub(sum, c_mul(a[k * NZ + j], b[j]));
        b[k] = c_mul(sum, inverse);
        if (c) {
            sum = c[k];
            for (int j = k + 1; j < NZ; ++j) sum = c_sub(sum, c_mul(a[k * NZ + j], c[j]));
            c[k] = c_mul(sum, inverse);
        }
    }
    return 1;
}

// max_k |v_k|: one square root of the largest squared modulus instead of a hypot per entry (the
// sizes of a tracked path are far from overflow: ESCAPE); a comparison, not fmax, which is a
// call into the C library on x86 (its result is the same: a NaN modulus is skipped by both)
static double c_max_abs(const cplx* v) {
    double largest = 0.0;
    for (int k = 0; k < NZ; ++k) {
        double size = v[k].re * v[k].re + v[k].im * v[k].im;
        largest = size > largest ? size : largest;
    }
    return sqrt(largest);
}

static double c_size(const cplx* z) { return 1.0 + c_max_abs(z); }

// fmax(a, b) and fmin(a, b) where a is not NaN (a NaN b gives a, as there), by a comparison:
// fmax and fmin are calls into the C library on x86
static inline double larger(double a, double b) { return b > a ? b : a; }
static inline double smaller(double a, double b) { return b < a ? b : a; }

// What tracking cost, summed over paths (a package's NAME_forward_pose_all_counted returns it)
typedef struct { long long paths, steps, rejected, evaluations, factorisations; } track_counts;

// One Newton step at (z, s) in place: H, H_z and H_s at z, one LU of H_z, z -= H_z^-1 H; where
// velocity is not NULL it receives dz/ds = -H_z^-1 H_s from the same LU (the path's slope for the
// next prediction: no factorisation of its own). Returns the update relative to |z| (inf when
// singular or not finite).
static double newton_step(const coefficients_at* at, cplx* z, cplx* velocity, track_counts* counts) {
    cplx value[NZ], jacobian[NZ * NZ];
    counts->evaluations += 1;
    if (!homotopy_eval(at, z, value, jacobian, velocity)) return INFINITY;
    counts->factorisations += 1;
    if (!c_solve(jacobian, value, velocity)) return INFINITY;
    for (int k = 0; k < NZ; ++k) z[k] = c_sub(z[k], value[k]);
    if (velocity)
        for (int k = 0; k < NZ; ++k) velocity[k] = (cplx){-velocity[k].re, -velocity[k].im};
    return c_max_abs(value) / c_size(z);
}

// z at s = target extrapolated from the path's last two points (s0, z0, v0) and (s1, z1, v1), v
// the slope dz/ds: the cubic Hermite interpolant of both (third order), or Euler from (s1, z1,
// v1) alone where the path has no earlier point (history 0)
static void hermite_cubic(int history, double s0, const cplx* z0, const cplx* v0, double s1, const cplx* z1,
                          const cplx* v1, double target, cplx* out) {
    if (!history) {
        double d = target - s1;
        for (int k = 0; k < NZ; ++k) out[k] = (cplx){z1[k].re + d * v1[k].re, z1[k].im + d * v1[k].im};
        return;
    }
    double span = s1 - s0, u = (target - s0) / span, u2 = u * u, u3 = u2 * u;
    double a0 = 2.0 * u3 - 3.0 * u2 + 1.0, b0 = (u3 - 2.0 * u2 + u) * span;
    double a1 = 3.0 * u2 - 2.0 * u3, b1 = (u3 - u2) * span;
    for (int k = 0; k < NZ; ++k)
        out[k] = (cplx){a0 * z0[k].re + b0 * v0[k].re + a1 * z1[k].re + b1 * v1[k].re,
                        a0 * z0[k].im + b0 * v0[k].im + a1 * z1[k].im + b1 * v1[k].im};
}

// The tracker's predictor (parakin.solvers.path_tracking.rational_predict): each unknown at s =
// target from the rational Hermite interpolant of the path's last two points and slopes, a
// quadratic over a linear polynomial in t = s - s1,
//     r(t) = (z1 + (v1 + q z1) t + p2 t^2) / (1 + q t),
// with r = z and r' = v at t = 0 and at t = a = s0 - s1; with the secant d = (z0 - z1) / a,
//     q = n / m,  n = v0 + v1 - 2 d,  m = a (d - v0),  p2 = (d - v1) / a + q d,
// evaluated as r = (m (z1 + v1 t + (d - v1) t^2 / a) + n (z1 t + d t^2)) / (m + n t): one
// division. It has the cubic's order (error ~ step^4) and follows a simple pole of the path (z
// ~ c / (s - s*), a path passing near a singular point of the homotopy or heading to infinity)
// exactly, where a polynomial needs tiny steps. An unknown whose interpolant is not finite or
// whose denominator |1 + q t'| comes within RATIONAL_GUARD of 0 for t' between 0 and t (a pole
// in or next to the step) takes the cubic Hermite value instead (hermite_cubic); Euler where
// there is no history.
static void predict(int history, double s0, const cplx* z0, const cplx* v0, double s1, const cplx* z1, const cplx* v1,
                    double target, cplx* out) {
    hermite_cubic(history, s0, z0, v0, s1, z1, v1, target, out);
    if (!history) return;
    double a = s0 - s1, t = target - s1, inverse = 1.0 / a, t2 = t * t;
    double guard = RATIONAL_GUARD * RATIONAL_GUARD;
    for (int k = 0; k < NZ; ++k) {
        cplx d = c_scale(inverse, c_sub(z0[k], z1[k]));
        cplx n = c_sub(c_add(v0[k], v1[k]), c_scale(2.0, d));
        cplx m = c_scale(a, c_sub(d, v0[k]));
        cplx quadratic = c_add(c_add(z1[k], c_scale(t, v1[k])), c_scale(t2 * inverse, c_sub(d, v1[k])));
        cplx above = c_add(c_mul(m, quadratic), c_mul(n, c_add(c_scale(t, z1[k]), c_scale(t2, d))));
        cplx below = c_add(m, c_scale(t, n));
        // |m + l t n|^2 = mm + 2 l t mn + l^2 t^2 nn, least over l in [0, 1]: against guard^2 mm
        double mm = m.re * m.re + m.im * m.im, nn = n.re * n.re + n.im * n.im, mn = m.re * n.re + m.im * n.im;
        double l = 0.0;
        if (t2 * nn > 0.0) {
            l = -(t * mn) / (t2 * nn);
            l = l < 0.0 ? 0.0 : (l > 1.0 ? 1.0 : l);
        }
        double least = mm + 2.0 * l * t * mn + l * l * t2 * nn;
        double size = below.re * below.re + below.im * below.im, scale = 1.0 / size;
        cplx r = {(above.re * below.re + above.im * below.im) * scale, (above.im * below.re - above.re * below.im) * scale};
        if (least > guard * mm && isfinite(r.re) && isfinite(r.im)) out[k] = r;
    }
}

// The coefficient sets of one step: in the caller's storage, as with hundreds of terms they are
// too large for a small thread stack
typedef struct { coefficients_at here, target; } step_coefficients;

// One path from s = 1 to s = 0 (parakin.solvers.path_tracking.track_hermite, the same algorithm): each
// step predicts by the rational Hermite extrapolation of the last two points and their slopes
// (predict: quadratic over linear, the cubic where that has a pole near the step), and
// corrects by at most CORRECTIONS contracting Newton steps at the new s, accepted when the error
// the last one leaves (the update itself after one step; after more, estimated from the
// quadratic convergence of the last two) is below tolerance: contraction keeps the path on its
// own branch. One correction is enough where the path's Newton constant omega (the contraction
// size / update^2 measured by the last step that took two, reset by a rejection) says the
// first update started well inside the basin (omega size <= ONE_STEP_BASIN, Kantorovich's
// condition) and left an error omega size^2 below ONE_STEP_ERROR: during the path the iterate
// only has to stay in its own path's basin, the endpoint is refined at s = 0. The last Newton
// step's LU also gives the slope at the new point, so an accepted step costs the evaluations
// and LUs of its corrector only. The first correction is the predictor's error: the next step is
// sized to bring it to PREDICTOR_TARGET (it grows as the step^4; Euler's, on the first step, as
// the step^2), within [STEP_SHRINK, STEP_GROW] times this one; a rejected step is retried
// shorter from the same point.
static int track_path(const sparse_system* system, double tolerance, cplx* z, step_coefficients* at, track_counts* counts) {
    double s = 1.0, s_previous = 1.0, h = INITIAL_STEP, omega = INFINITY;
    int history = 0;
    cplx slope[NZ], z_previous[NZ], slope_previous[NZ];
    counts->paths += 1;
    coefficients(system, s, &at->here);
    // the start's slope (and its start solution refined once)
    if (!isfinite(newton_step(&at->here, z, slope, counts))) return PATH_FAILED;
    for (int steps = 0; steps < MAX_STEPS; ++steps) {
        double step = smaller(h, s), target = s - step < END_GAP ? 0.0 : s - step;
        cplx corrected[NZ], next_slope[NZ];
        coefficients(system, target, &at->target);
        predict(history, s_previous, z_previous, slope_previous, s, z, slope, target, corrected);
        counts->steps += 1;
        double first = INFINITY, update = INFINITY, error = INFINITY, measured = INFINITY;
        int contracting = 1;
        for (int iteration = 0; iteration < CORRECTIONS; ++iteration) {
            double size = newton_step(&at->target, corrected, next_slope, counts);
            if (iteration) {
                contracting &= size <= 0.5 * update;
                // quadratic convergence: the error this update leaves is about omega size^2,
                // omega = size / update^2 from the two last updates
                double ratio = size / update;
                error = size * ratio * ratio;
                if (iteration == 1) measured = ratio / update;
            } else {
                first = error = size;
                // one correction suffices where the path's running Newton constant omega says
                // that it started well inside the basin (omega size <= ONE_STEP_BASIN, as in
                // Kantorovich's theorem) and left an error omega size^2 below ONE_STEP_ERROR
                if (omega * size <= ONE_STEP_BASIN && omega * size * size < ONE_STEP_ERROR) error = 0.0;
            }
            update = size;
            // converged iterates stop: at an ill-conditioned solution further updates are
            // rounding noise, which need not contract
            if (error < tolerance || !contracting) break;
        }
        int accepted = contracting && error < tolerance && isfinite(update);
        double factor = !isfinite(first) ? 0.0
                        : first > 0.0   ? STEP_SAFETY * pow(PREDICTOR_TARGET / first, history ? 0.25 : 0.5)
                                        : STEP_GROW;
        if (accepted) {
            memcpy(z_previous, z, sizeof(slope));
            memcpy(slope_previous, slope, sizeof(slope));
            s_previous = s;
            memcpy(z, corrected, sizeof(slope));
            memcpy(slope, next_slope, sizeof(slope));
            s = target;
            history = 1;
            // the Newton constant of the path: the latest measured (size / update^2 of a step's
            // first two corrections), at least OMEGA_DECAY times the one before
            if (isfinite(measured) && measured > 0.0) omega = isfinite(omega) ? larger(measured, OMEGA_DECAY * omega) : measured;
            h = step * smaller(STEP_GROW, larger(0.5, factor));
            if (s <= 0.0) break;
        } else {
            counts->rejected += 1;
            omega = INFINITY;  // measured anew before one correction suffices again
            h = step * smaller(0.5, larger(STEP_SHRINK, factor));
            if (h < MIN_STEP) return PATH_FAILED;
        }
        if (!(c_size(z) - 1.0 < ESCAPE)) return PATH_DIVERGED;
        if (steps == MAX_STEPS - 1) return PATH_FAILED;
    }
    if (!(c_size(z) - 1.0 < ESCAPE)) return PATH_DIVERGED;
    // refine at s = 0 while the update shrinks
    coefficients(system, 0.0, &at->target);
    double update = INFINITY;
    for (int iteration = 0; iteration < REFINE && update > 1e-15; ++iteration) {
        cplx trial[NZ];
        memcpy(trial, z, sizeof(trial));
        double size = newton_step(&at->target, trial, NULL, counts);
        if (!(size < update)) break;
        memcpy(z, trial, sizeof(trial));
        update = size;
    }
    return PATH_REACHED;
}

#endif
