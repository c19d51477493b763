// parakin C runtime: the path tracker of a parameter homotopy H(z, s) = 0, from a start solution
// at s = 1 to s = 0 (parakin.solvers.path_tracking.track_hermite is its NumPy reference: the same
// algorithm and constants). Copied into every homotopy package's driver by the generator
// (generator/emit.py), and compiled on its own with a test homotopy by tests/test_c_runtime.py.
//
// The includer defines, before including it (after complex.h):
//   NZ                  the unknowns (a constant: every work array is on the stack)
//   CORRECTIONS, INITIAL_STEP, PREDICTOR_TARGET, STEP_SAFETY, STEP_GROW, STEP_SHRINK,
//   MIN_STEP, ESCAPE, MAX_STEPS, REFINE, END_GAP, RATIONAL_GUARD, ONE_STEP_BASIN, ONE_STEP_ERROR,
//   OMEGA_DECAY, ONE_STEP_GOAL, OMEGA_FADE, END_REACH, REFINE_ERROR, ACROSS_NOISE
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

// Row k of a (and of b, c) swapped with the row at or below it whose column-k entry is largest;
// 0 where that column is zero from row k down (singular). A second call at the same k swaps
// nothing: the largest is already there.
static inline int c_pivot(cplx* a, cplx* b, cplx* c, int k) {
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
    return 1;
}

// Column k's elimination below the pivot (row k already pivoted)
static inline void c_eliminate(cplx* a, cplx* b, cplx* c, int k) {
    cplx inverse = c_inv(a[k * NZ + k]);
    for (int r = k + 1; r < NZ; ++r) {
        cplx f = c_mul(a[r * NZ + k], inverse);
        for (int j = k + 1; j < NZ; ++j) a[r * NZ + j] = c_sub(a[r * NZ + j], c_mul(f, a[k * NZ + j]));
        b[r] = c_sub(b[r], c_mul(f, b[k]));
        if (c) c[r] = c_sub(c[r], c_mul(f, c[k]));
    }
}

// Row k of the back substitution (rows below it solved)
static inline void c_back(const cplx* a, cplx* b, cplx* c, int k) {
    cplx inverse = c_inv(a[k * NZ + k]), sum = b[k];
    for (int j = k + 1; j < NZ; ++j) sum = c_sub(sum, c_mul(a[k * NZ + j], b[j]));
    b[k] = c_mul(sum, inverse);
    if (c) {
        sum = c[k];
        for (int j = k + 1; j < NZ; ++j) sum = c_sub(sum, c_mul(a[k * NZ + j], c[j]));
        c[k] = c_mul(sum, inverse);
    }
}

// c_solve's elimination from column first on (the columns before it done)
static int c_solve_from(cplx* a, cplx* b, cplx* c, int first) {
    for (int k = first; k < NZ; ++k) {
        if (!c_pivot(a, b, c, k)) return 0;
        c_eliminate(a, b, c, k);
    }
    for (int k = NZ - 1; k >= 0; --k) c_back(a, b, c, k);
    return 1;
}

// a x = b, and a y = c where c is not NULL, in place by Gaussian elimination with partial
// pivoting (a destroyed): one factorisation serves both right-hand sides; 0 when singular.
// tests/test_c_runtime.py checks its arithmetic bit for bit against the same elimination in
// Python's floats. Measured and not kept (issue 33): the augmented rows [a | b | c] with real
// and imaginary parts apart, padded for vector lanes, branchless pivots, the pivots' inverses
// kept for the back substitution, all bit-equal: 0.34 -> 0.27 us on stewart's Jacobians alone,
// but in the packages' pipelines stewart within noise, rps3 3 % and planar_3rrr 10 % slower
// (the elimination is a chain of dependent divisions and updates, not a throughput problem).
static int c_solve(cplx* a, cplx* b, cplx* c) { return c_solve_from(a, b, c, 0); }

// Two systems (a, b, c) and (a2, b2, c2) solved side by side, each by exactly c_solve's operations
// (its own pivots): the two dependency chains overlap. Bit 0 set where the first is solved, bit 1
// the second (a singular one's arrays are left part-eliminated, as c_solve leaves them). Measured
// on stewart's Jacobians (issue 33): two c_solve 0.70-0.77 us, c_solve2 0.48-0.57 us.
static int c_solve2(cplx* a, cplx* b, cplx* c, cplx* a2, cplx* b2, cplx* c2) {
    for (int k = 0; k < NZ; ++k) {
        if (!c_pivot(a, b, c, k)) return c_solve_from(a2, b2, c2, k) ? 2 : 0;
        if (!c_pivot(a2, b2, c2, k)) return c_solve_from(a, b, c, k);
        c_eliminate(a, b, c, k);
        c_eliminate(a2, b2, c2, k);
    }
    for (int k = NZ - 1; k >= 0; --k) {
        c_back(a, b, c, k);
        c_back(a2, b2, c2, k);
    }
    return 3;
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

// max_k |d_k - v_k (v^H d) / (v^H v)| of the update d = before - after: its part across the path
// whose slope is v (an update along v moves the point along its own path); path_tracking._across
static double c_across(const cplx* before, const cplx* after, const cplx* v) {
    cplx d[NZ];
    double vv = 0.0, re = 0.0, im = 0.0;
    for (int k = 0; k < NZ; ++k) {
        d[k] = c_sub(before[k], after[k]);
        vv += v[k].re * v[k].re + v[k].im * v[k].im;
        re += v[k].re * d[k].re + v[k].im * d[k].im;
        im += v[k].re * d[k].im - v[k].im * d[k].re;
    }
    re /= vv;
    im /= vv;
    double largest = 0.0;
    for (int k = 0; k < NZ; ++k) {
        double x = d[k].re - (v[k].re * re - v[k].im * im), y = d[k].im - (v[k].re * im + v[k].im * re);
        double size = x * x + y * y;
        largest = size > largest ? size : largest;
    }
    return sqrt(largest);
}

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
// The end of a Newton step whose LU solved value (and velocity): z -= the update, the slope's
// sign; the update relative to |z|.
static double newton_update(cplx* z, const cplx* value, cplx* velocity) {
    for (int k = 0; k < NZ; ++k) z[k] = c_sub(z[k], value[k]);
    if (velocity)
        for (int k = 0; k < NZ; ++k) velocity[k] = (cplx){-velocity[k].re, -velocity[k].im};
    return c_max_abs(value) / c_size(z);
}

static double newton_step(const coefficients_at* at, cplx* z, cplx* velocity, track_counts* counts) {
    cplx value[NZ], jacobian[NZ * NZ];
    counts->evaluations += 1;
    if (!homotopy_eval(at, z, value, jacobian, velocity)) return INFINITY;
    counts->factorisations += 1;
    if (!c_solve(jacobian, value, velocity)) return INFINITY;
    return newton_update(z, value, velocity);
}

// Two independent Newton steps (newton_step's at, z, velocity for each) side by side: each
// path's arithmetic is newton_step's, operation for operation (so its results are bit for bit
// newton_step's); the two LUs overlap (c_solve2: two chains of dependent divisions and updates).
// The two evaluations run one after the other: the unrolled evaluation has independent terms
// enough, and a generated two-point one (each term's products for both) measured slower than
// two (issue 33, stewart: 15 % more time in it than in the two; with it, the pipeline 2 % slower
// than one path at a time, with only the LUs paired 12 % faster). The two updates in size[0],
// size[1].
static void newton_step2(const coefficients_at* at, cplx* z, cplx* velocity, const coefficients_at* at2, cplx* z2,
                         cplx* velocity2, track_counts* counts, double* size) {
    cplx value[NZ], jacobian[NZ * NZ], value2[NZ], jacobian2[NZ * NZ];
    counts->evaluations += 2;
    int finite = homotopy_eval(at, z, value, jacobian, velocity), solved = 0;
    finite |= homotopy_eval(at2, z2, value2, jacobian2, velocity2) << 1;
    counts->factorisations += (finite & 1) + (finite >> 1);
    if (finite == 3) solved = c_solve2(jacobian, value, velocity, jacobian2, value2, velocity2);
    else if (finite == 1) solved = c_solve(jacobian, value, velocity);
    else if (finite == 2) solved = 2 * c_solve(jacobian2, value2, velocity2);
    size[0] = solved & 1 ? newton_update(z, value, velocity) : INFINITY;
    size[1] = solved & 2 ? newton_update(z2, value2, velocity2) : INFINITY;
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
// sized to bring it to a goal (it grows as the step^4; Euler's, on the first step, as the step^2),
// within [STEP_SHRINK, STEP_GROW] times this one; a rejected step is retried shorter from the same
// point. The goal is PREDICTOR_TARGET, or on the final steps (where the next step by that goal
// would cover END_REACH of the rest of the path) and where the path's omega is large the first
// correction that the one-correction rule accepts, sqrt(ONE_STEP_GOAL ONE_STEP_ERROR / omega)
// (one LU per step instead of two or three, and fewer rejections: issue 33, Dietmaier's paths
// near s = 0); the omega of the goal fades by OMEGA_FADE per accepted step that measured none. At s = 0 the
// endpoint is refined by Newton until the update stops shrinking, reaches rounding, or leaves an
// error d (d / previous)^2 below REFINE_ERROR (quadratic convergence; the first update's previous
// is the final step's last correction; the certificate begins with Newton steps of its own).
// A step short of s = 0 whose updates stop contracting is accepted where its updates across
// the path (c_across: without their part along the slope) converged, contracting to the
// tolerance or twice below it, and its last update is below ACROSS_NOISE: near a large endpoint
// H_z's near-null direction is the slope's and Newton's rounding noise runs along the path (issue
// 33, rps3: 1e-5 of |z| along it, 1e-13 across it), which no step size removes.
//
// Written as a path_lane that stops before each Newton step (its at, z, velocity in want_*) and
// resumes with that step's update (lane_resume), so that two paths can be advanced together
// (track_paths): each path's sequence of operations is the same either way.
typedef struct {
    const sparse_system* system;
    double tolerance;
    cplx* z;
    step_coefficients* at;
    track_counts* counts;
    double s, s_previous, h, omega, fade, step, target, first, update, error, measured, before, across, across_error;
    int history, steps, iteration, contracting, across_contracting, across_done, phase, result;
    cplx slope[NZ], z_previous[NZ], slope_previous[NZ], corrected[NZ], next_slope[NZ], trial[NZ];
    const coefficients_at* want_at;  // the Newton step the lane waits for
    cplx *want_z, *want_velocity;
} path_lane;

enum { LANE_START, LANE_CORRECT, LANE_REFINE };

static int lane_wants(path_lane* lane, const coefficients_at* at, cplx* z, cplx* velocity) {
    lane->want_at = at;
    lane->want_z = z;
    lane->want_velocity = velocity;
    return 1;
}

static int lane_ends(path_lane* lane, int result) {
    lane->result = result;
    return 0;
}

// the next step's prediction and its first correction
static int lane_step(path_lane* lane) {
    lane->step = smaller(lane->h, lane->s);
    lane->target = lane->s - lane->step < END_GAP ? 0.0 : lane->s - lane->step;
    coefficients(lane->system, lane->target, &lane->at->target);
    predict(lane->history, lane->s_previous, lane->z_previous, lane->slope_previous, lane->s, lane->z, lane->slope,
            lane->target, lane->corrected);
    lane->counts->steps += 1;
    lane->first = lane->update = lane->error = lane->measured = lane->across = lane->across_error = INFINITY;
    lane->contracting = lane->across_contracting = 1;
    lane->across_done = 0;
    lane->iteration = 0;
    lane->phase = LANE_CORRECT;
    memcpy(lane->trial, lane->corrected, sizeof(lane->trial));  // the point before the correction
    return lane_wants(lane, &lane->at->target, lane->corrected, lane->next_slope);
}

// at s = 0: refined while the update shrinks
static int lane_refine(path_lane* lane) {
    if (!(c_size(lane->z) - 1.0 < ESCAPE)) return lane_ends(lane, PATH_DIVERGED);
    coefficients(lane->system, 0.0, &lane->at->target);
    lane->before = lane->update;  // the final step's last correction
    lane->update = INFINITY;
    lane->iteration = 0;
    lane->phase = LANE_REFINE;
    if (!(lane->iteration < REFINE && lane->update > 1e-15)) return lane_ends(lane, PATH_REACHED);
    memcpy(lane->trial, lane->z, sizeof(lane->trial));
    return lane_wants(lane, &lane->at->target, lane->trial, NULL);
}

// A path's start (s = 1): its first Newton step wanted
static void lane_begin(path_lane* lane, const sparse_system* system, double tolerance, cplx* z, step_coefficients* at,
                       track_counts* counts) {
    lane->system = system;
    lane->tolerance = tolerance;
    lane->z = z;
    lane->at = at;
    lane->counts = counts;
    lane->s = lane->s_previous = 1.0;
    lane->h = INITIAL_STEP;
    lane->omega = INFINITY;
    lane->fade = 1.0;
    lane->history = 0;
    lane->steps = 0;
    lane->phase = LANE_START;
    counts->paths += 1;
    coefficients(system, lane->s, &at->here);
    // the start's slope (and its start solution refined once)
    lane_wants(lane, &at->here, z, lane->slope);
}

// The lane resumed with the update of the Newton step it wanted: 1 where it wants another (in
// want_*), 0 where the path has ended (result: PATH_REACHED, PATH_FAILED or PATH_DIVERGED).
static int lane_resume(path_lane* lane, double size) {
    if (lane->phase == LANE_START) {
        if (!isfinite(size)) return lane_ends(lane, PATH_FAILED);
        return lane_step(lane);
    }
    if (lane->phase == LANE_REFINE) {
        if (!(size < lane->update)) return lane_ends(lane, PATH_REACHED);
        memcpy(lane->z, lane->trial, sizeof(lane->trial));
        lane->update = size;
        lane->iteration += 1;
        double ratio = size / lane->before;
        lane->before = size;
        if (!(lane->iteration < REFINE && lane->update > 1e-15) || size * ratio * ratio < REFINE_ERROR)
            return lane_ends(lane, PATH_REACHED);
        memcpy(lane->trial, lane->z, sizeof(lane->trial));
        return lane_wants(lane, &lane->at->target, lane->trial, NULL);
    }
    // the update across the path: without its part along the slope (ACROSS_NOISE)
    double cross = isfinite(size) ? c_across(lane->trial, lane->corrected, lane->next_slope) / c_size(lane->corrected)
                                  : INFINITY;
    if (lane->iteration) {
        lane->contracting &= size <= 0.5 * lane->update;
        lane->across_contracting &= cross <= 0.5 * lane->across;
        // quadratic convergence: the error this update leaves is about omega size^2,
        // omega = size / update^2 from the two last updates
        double ratio = size / lane->update, across_ratio = cross / lane->across;
        lane->error = size * ratio * ratio;
        lane->across_error = cross * across_ratio * across_ratio;
        // across the path converged: as the tolerance asks, or two updates below it
        lane->across_done = (lane->across_contracting && lane->across_error < lane->tolerance) ||
                            (cross < lane->tolerance && lane->across < lane->tolerance);
        if (lane->iteration == 1) lane->measured = ratio / lane->update;
    } else {
        lane->first = lane->error = size;
        // one correction suffices where the path's running Newton constant omega says
        // that it started well inside the basin (omega size <= ONE_STEP_BASIN, as in
        // Kantorovich's theorem) and left an error omega size^2 below ONE_STEP_ERROR
        if (lane->omega * size <= ONE_STEP_BASIN && lane->omega * size * size < ONE_STEP_ERROR) lane->error = 0.0;
    }
    lane->update = size;
    lane->across = cross;
    // converged iterates stop; so do those that stop contracting, unless the updates across
    // the path may still converge (rounding noise along the path: ACROSS_NOISE)
    int hope = !lane->across_done && size < ACROSS_NOISE && lane->target > 0.0 &&
               (lane->across_contracting || cross < lane->tolerance);
    if (!(lane->error < lane->tolerance) && (lane->contracting || hope) && ++lane->iteration < CORRECTIONS) {
        memcpy(lane->trial, lane->corrected, sizeof(lane->trial));
        return lane_wants(lane, &lane->at->target, lane->corrected, lane->next_slope);
    }
    int accepted = lane->contracting && lane->error < lane->tolerance && isfinite(lane->update);
    // else, updates that stopped contracting short of s = 0, where those across the path
    // converged and the last is below ACROSS_NOISE: a point of its own path, shifted along it by
    // rounding (no omega measured)
    if (!lane->contracting && lane->across_done && lane->update < ACROSS_NOISE && lane->target > 0.0) {
        accepted = 1;
        lane->measured = INFINITY;
    }
    double first = lane->first, step = lane->step;
    // the omega of the next step: this step's measurement (at least OMEGA_DECAY times the one
    // before), else the one before faded once more; the goal, the first correction it aims at
    double measured = lane->measured, omega = lane->omega;
    int fresh = isfinite(measured) && measured > 0.0;
    double ahead = fresh ? (isfinite(omega) ? larger(measured, OMEGA_DECAY * omega) : measured)
                         : omega * (lane->fade * OMEGA_FADE);
    double goal = isfinite(ahead) ? smaller(PREDICTOR_TARGET, sqrt(ONE_STEP_GOAL * ONE_STEP_ERROR / ahead))
                                  : PREDICTOR_TARGET;
    double power = lane->history ? 0.25 : 0.5;
    double factor = !isfinite(first) ? 0.0 : first > 0.0 ? STEP_SAFETY * pow(goal / first, power) : STEP_GROW;
    double plain = !isfinite(first) ? 0.0 : first > 0.0 ? STEP_SAFETY * pow(PREDICTOR_TARGET / first, power) : STEP_GROW;
    // the goal only where the next step (by PREDICTOR_TARGET) would cover END_REACH of what is
    // left of the path: the final steps
    double reach = accepted ? step * smaller(STEP_GROW, larger(0.5, plain)) : step * smaller(0.5, larger(STEP_SHRINK, plain));
    if (!(reach >= END_REACH * (accepted ? lane->target : lane->s))) factor = plain;
    if (accepted) {
        memcpy(lane->z_previous, lane->z, sizeof(lane->slope));
        memcpy(lane->slope_previous, lane->slope, sizeof(lane->slope));
        lane->s_previous = lane->s;
        memcpy(lane->z, lane->corrected, sizeof(lane->slope));
        memcpy(lane->slope, lane->next_slope, sizeof(lane->slope));
        lane->s = lane->target;
        lane->history = 1;
        // the Newton constant of the path: the latest measured (size / update^2 of a step's
        // first two corrections), at least OMEGA_DECAY times the one before
        if (fresh) lane->omega = ahead;
        lane->fade = fresh ? 1.0 : lane->fade * OMEGA_FADE;
        lane->h = step * smaller(STEP_GROW, larger(0.5, factor));
        if (lane->s <= 0.0) return lane_refine(lane);
    } else {
        lane->counts->rejected += 1;
        lane->omega = INFINITY;  // measured anew before one correction suffices again
        lane->fade = 1.0;
        lane->h = step * smaller(0.5, larger(STEP_SHRINK, factor));
        if (lane->h < MIN_STEP) return lane_ends(lane, PATH_FAILED);
    }
    if (!(c_size(lane->z) - 1.0 < ESCAPE)) return lane_ends(lane, PATH_DIVERGED);
    if (lane->steps == MAX_STEPS - 1) return lane_ends(lane, PATH_FAILED);
    lane->steps += 1;
    return lane_step(lane);
}

static int track_path(const sparse_system* system, double tolerance, cplx* z, step_coefficients* at, track_counts* counts) {
    path_lane lane;
    lane_begin(&lane, system, tolerance, z, at, counts);
    while (lane_resume(&lane, newton_step(lane.want_at, lane.want_z, lane.want_velocity, counts))) {
    }
    return lane.result;
}

// The paths starting at z[order[0]], ..., z[order[count - 1]] (each tracked in place, its end
// in ended[order[i]]), two at a time: two lanes advanced together, each Newton step of the one
// paired with the other's (newton_step2); a lane whose path ends takes the next path, and the
// last path runs alone. Each path's arithmetic is track_path's, bit for bit, and the counts are
// the same sums. at: two coefficient sets, one per lane. Measured against one path at a time
// (issue 33; "C only" per input, the libraries interleaved in one process; every array of
// compiled_modes and the counts bit-identical on 200 inputs per family, rus6 20): stewart
// (Dietmaier) 3.89 -> 3.42 ms, prs3 0.75 -> 0.68-0.70, rps3 0.82 -> 0.71, tricept 0.273 ->
// 0.235, rus6 13.0 -> 12.7 (14.8 -> 13.0 in another run), planar_3rrr (4 unknowns, 6 paths)
// 0.097 -> 0.098: the overlap pays with the size of the LU.
static void track_paths(const sparse_system* system, double tolerance, cplx (*z)[NZ], const int* order, int count,
                        int* ended, step_coefficients* at, track_counts* counts) {
    path_lane lane[2];
    int path[2] = {0, 0}, live[2] = {0, 0}, next = 0;
    for (;;) {
        for (int l = 0; l < 2; ++l)
            if (!live[l] && next < count) {
                path[l] = order[next++];
                lane_begin(&lane[l], system, tolerance, z[path[l]], &at[l], counts);
                live[l] = 1;
            }
        double size[2];
        if (live[0] && live[1])
            newton_step2(lane[0].want_at, lane[0].want_z, lane[0].want_velocity, lane[1].want_at, lane[1].want_z,
                         lane[1].want_velocity, counts, size);
        else if (live[0] || live[1]) {
            int l = live[1];
            size[l] = newton_step(lane[l].want_at, lane[l].want_z, lane[l].want_velocity, counts);
        } else
            return;
        for (int l = 0; l < 2; ++l)
            if (live[l] && !lane_resume(&lane[l], size[l])) {
                ended[path[l]] = lane[l].result;
                live[l] = 0;
            }
    }
}

#endif
