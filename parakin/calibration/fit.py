"""``calibrate``: the geometric parameters, actuated-joint offsets (and scales) and unknown
instrument frames that best explain measured poses, by Levenberg-Marquardt on whitened residuals
with analytic Jacobians, and what the measurements leave undetermined.

The problem (implicit loop). Pose k was measured with encoder readings theta_k; the model's joints
are theta'_k = scale * theta_k + offset. Its passive joints q_k are unknowns estimated with the
parameters: they close the loop c(theta'_k, q_k; p) = 0, and the platform pose P(theta'_k, q_k; p)
seen through the tracker and tool frames is compared with the measurement (the pose noise
dominates: the encoders are taken as exact). Each iteration eliminates the q_k by the implicit
function theorem (dq_k = -C_q^-1 (C_p dp + C_theta dtheta')), so the Jacobian of the residuals
with respect to the parameters is exact:

    dr/dp = dr/dy dy/dP (P_p - P_q C_q^-1 C_p),   dr/dtheta' = dr/dy dy/dP (P_theta - P_q C_q^-1 C_theta)

with C_p and P_p from the generated ``parameter_jacobians`` kernel, C_q from ``loop_closure``,
C_theta from ``loop_closure_actuated``, dy/dP and the frames' derivatives in closed form
(``parakin.calibration.data.predict``). P_q and P_theta, the pose kernel's partial derivatives in the
joints, come from central differences of the ``platform_pose`` kernel (one batched call; the
kernels have no such output; exact for the quadratic pose kernels of quaternion platforms). A
trial step moves every q_k by the linear prediction and closes each loop by Newton before its
residual is compared.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from parakin.calibration.data import CalibrationData, frame_names, predict, residual, residual_in_units
from parakin.calibration.identifiability import RANK_TOLERANCE, Combination, analyse, thin_svd
from parakin.calibration.rotation_vectors import frame_transform
from parakin.errors import (
    BadInputError,
    CalibrationDataError,
    CalibrationUnavailableError,
    ConvergenceError,
    ParakinError,
    at_index,
    first_index,
)
from parakin.mechanism import Mechanism
from parakin.packages.manifest import unknown_name
from parakin.results import Array
from parakin.validation import real_number

#: Newton iterations allowed to close one loop after a step
CLOSE_ITERATIONS = 30
#: central-difference step of the pose kernel's joint derivatives, relative to max(1, |value|)
JOINT_STEP = 1e-6
#: Levenberg-Marquardt: iteration cap, relative cost decrease that ends it, damping bounds
MAX_ITERATIONS = 200
COST_TOLERANCE = 1e-10
DAMPING = (1e-12, 1e12)
#: a step that changes the whitened residuals by less than this (in sigmas) ends the iteration
STEP_TOLERANCE = 1e-9
#: eigenvalues of the scaled normal matrix below this fraction of the largest are not stepped along
STEP_RANK = 1e-14


def require_kernel(m: Mechanism) -> None:
    """CalibrationUnavailableError unless the package has the ``parameter_jacobians`` kernel."""
    if "parameter_jacobians" not in m.manifest.kernels:
        raise CalibrationUnavailableError(
            f"{m.name}'s package has no parameter_jacobians kernel (it was generated before calibration "
            "existed): regenerate it (make regenerate, or parakin generate FILE --out DIR --force)"
        )


def joint_names(m: Mechanism) -> list[str]:
    """``<actuated>_offset`` for every actuated variable, then ``<actuated>_scale``."""
    return [f"{a}_offset" for a in m.actuated_names] + [f"{a}_scale" for a in m.actuated_names]


class Problem:
    """One calibration problem: the parameter layout, and the residuals and Jacobian of a
    parameter vector (geometric, joint offsets and scales, tracker, tool: ``names``)."""

    def __init__(
        self,
        m: Mechanism,
        data: CalibrationData,
        free: Sequence[str] | None,
        fixed: Sequence[str],
        prior: Mapping[str, tuple[float, float]] | None,
        start: Mapping[str, float] | None = None,
    ) -> None:
        require_kernel(m)
        if data.actuated.shape[1] != len(m.actuated_names):
            raise CalibrationDataError(
                f"actuated has {data.actuated.shape[1]} columns; {m.name} has {len(m.actuated_names)} "
                f"actuated variables {m.actuated_names}"
            )
        if data.passive is not None and data.passive.shape[1] != len(m.passive_names):
            raise CalibrationDataError(
                f"passive has {data.passive.shape[1]} columns; {m.name} has passive {m.passive_names}"
            )
        self.m, self.data = m, data
        self.geometric = [p.name for p in m.manifest.parameters]
        self.names = self.geometric + joint_names(m) + frame_names("tracker") + frame_names("tool")
        n_a = len(m.actuated_names)
        self.nominal = np.concatenate(
            [m.params, np.zeros(n_a), np.ones(n_a), np.array(list(data.frame_values().values()))]
        )
        for name, value in (start or {}).items():
            if name not in self.names:
                raise unknown_name("calibration parameter", name, self.names, m.name)
            self.nominal[self.names.index(name)] = float(value)
        for what, names in (("free", free), ("fixed", fixed)):
            if isinstance(names, str | bytes):
                raise CalibrationDataError(f"{what} must be a list of parameter names, got the string {names!r}")
        # a sign parameter (a configuration choice, +1 or -1) is no dimension to calibrate
        signs = [p.name for p in m.manifest.parameters if p.domain == "sign"]
        continuous = [name for name in self.geometric if name not in signs]
        chosen = list(continuous + joint_names(m)[:n_a] + data.free_frames()) if free is None else list(free)
        for name in [*chosen, *fixed]:
            if name not in self.names:
                raise unknown_name("calibration parameter", name, self.names, m.name)
            if name in signs and name in chosen:
                raise CalibrationDataError(
                    f"parameter {name!r} of {m.name} is a sign (+1 or -1, a configuration choice), not a "
                    "dimension: it cannot be calibrated; leave it out of free"
                )
        self.free = [name for name in self.names if name in chosen and name not in set(fixed)]
        if not self.free:
            raise CalibrationDataError("no parameter is free: free minus fixed is empty")
        self.index = np.array([self.names.index(name) for name in self.free], dtype=np.intp)
        self.prior_index: list[int] = []
        self.prior_mean: list[float] = []
        self.prior_sigma: list[float] = []
        for name, pair in (prior or {}).items():
            if name not in self.free:
                raise unknown_name("free parameter in prior", name, self.free, m.name)
            try:
                mean, sigma = (real_number(v, f"prior[{name!r}]") for v in pair)
            except (BadInputError, TypeError, ValueError) as error:
                raise CalibrationDataError(f"prior[{name!r}] must be (mean, sigma), got {pair!r}") from error
            if not sigma > 0:
                raise CalibrationDataError(f"prior[{name!r}] must have sigma > 0, got {sigma!r}")
            self.prior_index.append(self.free.index(name))
            self.prior_mean.append(float(mean))
            self.prior_sigma.append(float(sigma))
        self.n_g, self.n_a, self.n_p = len(self.geometric), n_a, len(m.passive_names)
        lengths = np.abs(m.params[np.isfinite(m.params)])
        # the rounding floor of a closure residual, never above 1e-3 of the manifest's tolerance
        # (parameters that are no lengths, such as stiffnesses of 1e8, must not loosen it)
        self.closure_tolerance = min(1e-15 * max(1.0, float(lengths.max(initial=1.0))), 1e-3 * m.tolerances["closure"])

    # ---------------------------------------------------------------- layout
    def full(self, x: Array) -> Array:
        """Every parameter's value with the free ones set to ``x``."""
        values = self.nominal.copy()
        values[self.index] = x
        return values

    def split(self, values: Array) -> tuple[Array, Array, Array, Array, Array]:
        """(geometric params, offsets, scales, tracker (6,), tool (6,)) of a full vector."""
        g, a = self.n_g, self.n_a
        return values[:g], values[g : g + a], values[g + a : g + 2 * a], values[-12:-6], values[-6:]

    def joints(self, values: Array) -> Array:
        """The model's actuated joints (N, n_a): scale * reading + offset."""
        _, offset, scale, _, _ = self.split(values)
        return self.data.actuated * scale + offset

    # ---------------------------------------------------------------- loop closure
    def close(self, values: Array, passive: Array) -> Array:
        """Passive values (N, n_p) that close every loop at ``values``, by Newton from ``passive``;
        ConvergenceError naming the first pose that does not close."""
        if not self.n_p:  # a serial chain: no loop
            return passive.copy()
        params = self.split(values)[0]
        theta = self.joints(values)
        q = passive.copy()
        error = np.full(len(q), np.inf)
        # Newton to the rounding floor: until every residual is below 1e-15 of the length scale,
        # or has stopped halving below 1e-3 of the manifest's closure tolerance (a looser stop
        # leaves pose errors of the residual times the condition number of the closure's
        # Jacobian, visible in noise-free fits)
        floor = 1e-3 * self.m.tolerances["closure"]
        for _ in range(CLOSE_ITERATIONS):
            with np.errstate(all="ignore"):
                out = self.m.backend.call("loop_closure", theta, q, params)
            previous, error = error, np.abs(out["residual"]).max(-1)
            stalled = (error >= 0.5 * previous) & (error <= floor)
            if ((error <= self.closure_tolerance) | stalled).all():
                break
            with np.errstate(all="ignore"):
                step = _solve(out["jacobian"], out["residual"][..., None])[..., 0]
            q = q - np.where((error > self.closure_tolerance)[:, None], step, 0.0)
        bad = ~(error <= self.m.tolerances["closure"])
        if bad.any():
            index = first_index(bad)
            raise ConvergenceError(
                f"calibration: the loop of pose{at_index(index)} does not close at these parameters (residual "
                f"{float(error[index]):.3g} > {self.m.tolerances['closure']:g}); the starting guess of its passive "
                "joints is too far (pass CalibrationData(passive=...)) or the parameters left the mechanism's domain",
                residual=float(error[index]),
            )
        return q

    def _pose_joint_derivatives(self, params: Array, theta: Array, q: Array) -> tuple[Array, Array, Array]:
        """The pose kernel's top rows (N, 12) and their central-difference derivatives in the
        passive (N, 12, n_p) and actuated (N, 12, n_a) joints (module docstring)."""
        n, n_a, n_p = len(q), self.n_a, self.n_p
        count = n_a + n_p
        joint = np.concatenate([theta, q], axis=1)
        steps = JOINT_STEP * np.maximum(1.0, np.abs(joint))
        shifted = np.repeat(joint[:, None, :], 2 * count + 1, axis=1)
        for j in range(count):
            shifted[:, 2 * j, j] += steps[:, j]
            shifted[:, 2 * j + 1, j] -= steps[:, j]
        with np.errstate(all="ignore"):
            pose = self.m.backend.call("platform_pose", shifted[..., :n_a], shifted[..., n_a:], params)["pose"]
        top = pose[..., :3, :].reshape(n, 2 * count + 1, 12)
        derivative = (top[:, 0:-1:2] - top[:, 1:-1:2]) / (2.0 * steps[:, :, None])  # (N, count, 12)
        derivative = np.swapaxes(derivative, 1, 2)
        return top[:, -1], derivative[..., n_a:], derivative[..., :n_a]

    def evaluate(self, values: Array, q: Array, jacobian: bool = True) -> tuple[Array, Array, Array]:
        """Whitened residuals (rows,), their Jacobian (rows, n_free) and the passive sensitivity
        (N, n_p, n_g + n_a) (dq = -sensitivity @ (dp, dtheta')) at closed ``q``."""
        params, _, _, tracker, tool = self.split(values)
        theta = self.joints(values)
        n = len(q)
        top, pose_passive, pose_actuated = self._pose_joint_derivatives(params, theta, q)
        y, d_platform, d_tracker, d_tool = predict(top.reshape(n, 3, 4), tracker, tool, derivatives=jacobian)
        r, d_residual = residual(self.data, y)
        prior = (self.full_x(values)[self.prior_index] - np.array(self.prior_mean)) / np.array(self.prior_sigma)
        rows = np.concatenate([r.ravel(), prior])
        if not jacobian:
            return rows, np.zeros((0, 0)), np.zeros((0, 0, 0))
        kernel = self.m.backend.call("parameter_jacobians", theta, q, params)
        if self.n_p:
            closure = self.m.backend.call("loop_closure", theta, q, params)["jacobian"]
            closure_actuated = self.m.backend.call("loop_closure_actuated", theta, q, params)["jacobian_actuated"]
            right = np.concatenate([kernel["closure_parameters"], closure_actuated], axis=2)
            sensitivity = _solve(closure, right)  # C_q^-1 [C_p, C_theta]
        else:  # a serial chain: the pose is explicit in the joints
            sensitivity = np.zeros((n, 0, self.n_g + self.n_a))
        total = np.concatenate([kernel["pose_parameters"], pose_actuated], axis=2) - pose_passive @ sensitivity
        through = d_residual @ d_platform  # (N, s, 12)
        by_joint = through @ total  # (N, s, n_g + n_a)
        g = self.n_g
        full = np.concatenate(
            [
                by_joint[..., :g],
                by_joint[..., g:],
                by_joint[..., g:] * self.data.actuated[:, None, :],
                d_residual @ d_tracker,
                d_residual @ d_tool,
            ],
            axis=2,
        )
        columns = full[..., self.index].reshape(n * full.shape[1], len(self.index))
        prior_rows = np.zeros((len(self.prior_index), len(self.index)))
        prior_rows[np.arange(len(self.prior_index)), self.prior_index] = 1.0 / np.array(self.prior_sigma)
        return rows, np.concatenate([columns, prior_rows]), sensitivity

    def full_x(self, values: Array) -> Array:
        return values[self.index]

    def predicted_passive(self, q: Array, sensitivity: Array, step_values: Array) -> Array:
        """The linear prediction q - C_q^-1 (C_p dp + C_theta dtheta') of a step of the full vector."""
        params_step = step_values[: self.n_g]
        theta_step = self.joints(self.nominal + step_values) - self.joints(self.nominal)
        combined = np.concatenate([np.broadcast_to(params_step, (len(q), self.n_g)), theta_step], axis=1)
        return q - (sensitivity @ combined[..., None])[..., 0]


def _solve(matrix: Array, right: Array) -> Array:
    """matrix^-1 right for a batch; the least-squares solution where the closure is not square."""
    if matrix.shape[-1] == matrix.shape[-2]:
        return np.asarray(np.linalg.solve(matrix, right))
    return np.asarray(np.linalg.pinv(matrix) @ right)


@dataclass(frozen=True)
class CalibrationResult:
    """What ``calibrate`` found.

    Attributes
    ----------
    names : tuple of str
        The free (estimated) parameters, in the order of ``covariance``.
    values, nominal : dict
        Every calibration parameter (geometric, ``<actuated>_offset`` / ``_scale``, ``tracker_*``,
        ``tool_*``) after and before the fit (m, rad, 1).
    standard_errors : dict
        One standard deviation of each free parameter (NaN for one that is not identifiable).
    covariance : (n_free, n_free)
        Covariance of the free parameters (the pseudo-inverse over the identifiable subspace).
    rank, singular_values, observability
        Rank of the whitened Jacobian (column-scaled), its singular values, O1..O5
        (``parakin.calibration.identifiability``).
    identifiable : tuple of str
        Free parameters that the measurements determine individually.
    unidentifiable : tuple of Combination
        The null directions, named in parameter terms (``str(c)`` reads ``R + r``).
    null_space : (n_free, k)
        Their basis in parameter units (unit columns).
    residuals_before, residuals_after : dict
        Residuals in measurement units per component ('position' (N, 3) m, 'angle' (N, 3) rad,
        'z' or 'distance' (N,) m).
    rms_before, rms_after : dict
        Root-mean-square of each component.
    chi2, dof : float, int
        Sum of squared whitened residuals at the solution and rows minus rank.
    iterations, seconds : int, float
    passive : (N, n_p)
        The estimated passive joints of every pose.
    mechanism : Mechanism
        The mechanism loaded with the calibrated geometric parameters.
    """

    names: tuple[str, ...]
    values: dict[str, float]
    nominal: dict[str, float]
    standard_errors: dict[str, float]
    covariance: Array
    rank: int
    singular_values: Array
    observability: dict[str, float]
    identifiable: tuple[str, ...]
    unidentifiable: tuple[Combination, ...]
    null_space: Array
    residuals_before: dict[str, Array]
    residuals_after: dict[str, Array]
    rms_before: dict[str, float]
    rms_after: dict[str, float]
    chi2: float
    dof: int
    iterations: int
    seconds: float
    passive: Array
    mechanism: Mechanism

    @property
    def offsets(self) -> dict[str, float]:
        """``<actuated>_offset`` values."""
        return {k: v for k, v in self.values.items() if k.endswith("_offset")}

    @property
    def tracker(self) -> Array:
        """^B_W T (4, 4) at the calibrated values."""
        return frame_transform(np.array([self.values[n] for n in frame_names("tracker")]))

    @property
    def tool(self) -> Array:
        """^P_T T (4, 4) at the calibrated values."""
        return frame_transform(np.array([self.values[n] for n in frame_names("tool")]))

    def joints(self, readings: ArrayLike) -> Array:
        """The calibrated model's actuated joints for encoder readings: scale * reading + offset,
        with the calibrated ``<actuated>_scale`` and ``<actuated>_offset``.

        Parameters
        ----------
        readings : array_like, shape (..., n_a)
            Encoder readings (m or rad), in ``mechanism.actuated_names`` order; any leading
            batch shape.

        Returns
        -------
        numpy.ndarray, shape (..., n_a)
            The joints (m or rad) of ``mechanism``, the calibrated model, at those readings.

        Raises
        ------
        ValueError
            ``readings`` whose last axis is not n_a, or not numbers (NumPy's broadcasting or
            conversion error).

        Examples
        --------
        A delta whose first encoder reads 2 mrad low, calibrated from 12 measured positions:

        >>> import numpy as np, parakin
        >>> from parakin.calibration import CalibrationData, calibrate
        >>> m = parakin.load("delta", backend="numpy")
        >>> built = parakin.load("delta", backend="numpy", L=0.351)
        >>> points = m.home_passive + np.random.default_rng(0).uniform(-0.05, 0.05, (12, 3))
        >>> readings = built.inverse_pose(points).actuated[:, 0] - [0.002, 0.0, 0.0]
        >>> result = calibrate(m, CalibrationData(readings, points, kind="position", sigma=20e-6))
        >>> bool(np.allclose(result.joints(readings), readings + [0.002, 0.0, 0.0], rtol=0, atol=1e-9))
        True
        """
        names = self.mechanism.actuated_names
        reading = np.asarray(readings, dtype=float)
        scale = np.array([self.values[f"{a}_scale"] for a in names])
        offset = np.array([self.values[f"{a}_offset"] for a in names])
        return reading * scale + offset

    def readings(self, joints: ArrayLike) -> Array:
        """The encoder readings that put the calibrated model's joints at ``joints`` (inverse of
        ``joints``): what to command.

        Parameters
        ----------
        joints : array_like, shape (..., n_a)
            Actuated joints (m or rad) of ``mechanism``, the calibrated model (e.g. from its
            ``inverse_pose``), in ``mechanism.actuated_names`` order; any leading batch shape.

        Returns
        -------
        numpy.ndarray, shape (..., n_a)
            The encoder readings (m or rad): (joint - offset) / scale.

        Raises
        ------
        ValueError
            ``joints`` whose last axis is not n_a, or not numbers (NumPy's broadcasting or
            conversion error).

        Examples
        --------
        The readings that put the calibrated delta's platform at a wanted point (the setup of
        ``joints``: encoder 1 reads 2 mrad low):

        >>> import numpy as np, parakin
        >>> from parakin.calibration import CalibrationData, calibrate
        >>> m = parakin.load("delta", backend="numpy")
        >>> built = parakin.load("delta", backend="numpy", L=0.351)
        >>> points = m.home_passive + np.random.default_rng(0).uniform(-0.05, 0.05, (12, 3))
        >>> readings = built.inverse_pose(points).actuated[:, 0] - [0.002, 0.0, 0.0]
        >>> result = calibrate(m, CalibrationData(readings, points, kind="position", sigma=20e-6))
        >>> target = result.mechanism.inverse_pose(m.home_passive).actuated[0]
        >>> (result.readings(target) - target).round(9).tolist()
        [-0.002, 0.0, 0.0]
        """
        names = self.mechanism.actuated_names
        scale = np.array([self.values[f"{a}_scale"] for a in names])
        offset = np.array([self.values[f"{a}_offset"] for a in names])
        return (np.asarray(joints, dtype=float) - offset) / scale

    def interval(self, name: str, level: float = 0.95) -> tuple[float, float]:
        """The two-sided normal confidence interval of a free parameter: value -+ z sigma, with
        its standard error sigma (first order, from the covariance at the solution).

        Parameters
        ----------
        name : str
            A free parameter (``names``), e.g. ``"L"`` or ``"theta1_offset"``.
        level : float
            The confidence level: 0.95 (z = 1.96) or 0.99 (z = 2.576).

        Returns
        -------
        tuple of (float, float)
            The interval's ends, in the parameter's unit (m, rad or 1); (nan, nan) for a
            parameter that the measurements do not identify (``unidentifiable``).

        Raises
        ------
        CalibrationDataError
            ``level`` not 0.95 or 0.99.
        BadInputError
            ``name`` not a free parameter (the message suggests the closest names).

        Examples
        --------
        The delta of ``joints`` (upper arms 1 mm longer than drawn, L = 0.351 m):

        >>> import numpy as np, parakin
        >>> from parakin.calibration import CalibrationData, calibrate
        >>> m = parakin.load("delta", backend="numpy")
        >>> built = parakin.load("delta", backend="numpy", L=0.351)
        >>> points = m.home_passive + np.random.default_rng(0).uniform(-0.05, 0.05, (12, 3))
        >>> readings = built.inverse_pose(points).actuated[:, 0] - [0.002, 0.0, 0.0]
        >>> result = calibrate(m, CalibrationData(readings, points, kind="position", sigma=20e-6))
        >>> low, high = result.interval("L")
        >>> bool(low < 0.351 < high), round(high - low, 5)
        (True, 0.00165)
        >>> result.interval("R")  # only R + r is determined by positions
        (nan, nan)
        >>> result.interval("L", level=0.9)
        Traceback (most recent call last):
        ...
        parakin.errors.CalibrationDataError: level must be 0.95 or 0.99, got 0.9
        """
        z = {0.95: 1.959963984540054, 0.99: 2.5758293035489004, 0.6826894921370859: 1.0}.get(level)
        if z is None:
            raise CalibrationDataError(f"level must be 0.95 or 0.99, got {level!r}")
        if name not in self.standard_errors:
            raise unknown_name("free parameter", name, self.names, self.mechanism.name)
        value, error = self.values[name], self.standard_errors[name]
        return value - z * error, value + z * error

    def summary(self) -> str:
        """A text table: every free parameter (nominal, calibrated, one sigma), then the null
        combinations, the rms before and after and O1..O5.

        Returns
        -------
        str
            Lines of ``parameter nominal calibrated sigma`` (the unit of each parameter; an
            unidentifiable one shows ``(unid.)``), the rank, each unidentifiable combination,
            the rms of each residual component before and after (m or rad), the observability
            indices and the iterations and seconds taken.

        Examples
        --------
        The delta of ``joints``:

        >>> import numpy as np, parakin
        >>> from parakin.calibration import CalibrationData, calibrate
        >>> m = parakin.load("delta", backend="numpy")
        >>> built = parakin.load("delta", backend="numpy", L=0.351)
        >>> points = m.home_passive + np.random.default_rng(0).uniform(-0.05, 0.05, (12, 3))
        >>> readings = built.inverse_pose(points).actuated[:, 0] - [0.002, 0.0, 0.0]
        >>> result = calibrate(m, CalibrationData(readings, points, kind="position", sigma=20e-6))
        >>> print(result.summary())
        parameter              nominal    calibrated      sigma
        R                          0.2           0.2   (unid.)
        r                         0.05          0.05   (unid.)
        L                         0.35         0.351    0.00042
        l                          1.3           1.3     0.0011
        theta1_offset                0         0.002    0.00295
        ...
        rank 6 of 7; 1 unidentifiable combination(s)
          unidentifiable: R + r
        rms position: 0.001137 before, ... after
        observability: O1 = 0.0681, ...
        """
        lines = [f"{'parameter':<16} {'nominal':>13} {'calibrated':>13} {'sigma':>10}"]
        for name in self.names:
            error = self.standard_errors[name]
            shown = f"{error:10.3g}" if np.isfinite(error) else "  (unid.)"
            lines.append(f"{name:<16} {self.nominal[name]:13.7g} {self.values[name]:13.7g} {shown}")
        lines.append(f"rank {self.rank} of {len(self.names)}; {len(self.unidentifiable)} unidentifiable combination(s)")
        lines += [f"  unidentifiable: {c}" for c in self.unidentifiable]
        for key in self.rms_before:
            lines.append(f"rms {key}: {self.rms_before[key]:.4g} before, {self.rms_after[key]:.4g} after")
        lines.append("observability: " + ", ".join(f"{k} = {v:.3g}" for k, v in self.observability.items()))
        lines.append(f"{self.iterations} iterations, {self.seconds:.3g} s")
        return "\n".join(lines)


def _start(problem: Problem) -> Array:
    """Starting passive joints: given, or Newton from the measured pose (kind 'pose', with an
    inverse) or from the mode nearest home, on the nominal model at the readings."""
    m, data = problem.m, problem.data
    if data.passive is not None:
        return problem.close(problem.nominal, data.passive)
    theta = problem.joints(problem.nominal)
    if not m.passive_names:  # a serial chain: nothing to close
        return np.zeros((len(data), 0))
    guess: Array | None = None
    if data.kind == "pose" and m.capabilities.inverse is not None:
        guess = data.tracker @ data.measured @ np.linalg.inv(data.tool)
    solved = m.forward_pose(theta, guess=guess, strict=False)
    # a pose where Newton did not converge is no candidate (its passive values need not close)
    pose = np.where(np.asarray(solved.converged)[:, None, None], np.asarray(solved.pose, float), np.nan)
    passive = _measured_modes(problem, theta, pose, np.asarray(solved.passive, float))
    return problem.close(problem.nominal, passive)


def _measured_modes(problem: Problem, theta: Array, pose: Array, passive: Array) -> Array:
    """The assembly mode the measurements say each pose is in: of every mode of the nominal model
    at the readings (``forward_pose_all``), the one whose predicted measurement is nearest the
    measured one, where it is nearer than Newton's from the guess. A mechanism near its home
    can have several modes close together (stewart has up to 40), and Newton from the mode
    nearest home may land on another than the robot's: the fit would then explain the
    measurements with the wrong mode (a silent 0.4 m misfit)."""
    m = problem.m
    if not m.capabilities.forward_methods:
        return passive
    try:
        modes = m.forward_pose_all(theta, strict=False)
    except ParakinError:
        return passive
    _, _, _, tracker, tool = problem.split(problem.nominal)

    def misfit(poses: Array) -> Array:
        with np.errstate(all="ignore"):
            whitened = residual(problem.data, predict(poses[:, :3, :], tracker, tool, derivatives=False)[0])[0]
        return np.where(np.isfinite(whitened).all(-1), (whitened**2).sum(-1), np.inf)

    best, chosen = misfit(pose), passive.copy()
    for k in range(modes.poses.shape[1]):
        candidate = np.where(np.asarray(modes.valid)[:, k, None, None], modes.poses[:, k], np.nan)
        error = misfit(candidate)
        nearer = error < best
        best = np.where(nearer, error, best)
        chosen[nearer] = modes.passive[nearer, k]
    return chosen


def _rms(parts: dict[str, Array]) -> dict[str, float]:
    return {k: float(np.sqrt(np.mean(np.sum(v.reshape(len(v), -1) ** 2, axis=1)))) for k, v in parts.items()}


def calibrate(
    m: Mechanism,
    data: CalibrationData,
    free: Sequence[str] | None = None,
    fixed: Sequence[str] = (),
    prior: Mapping[str, tuple[float, float]] | None = None,
    rank_tolerance: float = RANK_TOLERANCE,
) -> CalibrationResult:
    """Identify a mechanism's geometric parameters, actuated-joint offsets (and scales) and
    unknown instrument frames from measurements (module docstring: the method).

    Parameters
    ----------
    m : Mechanism
        The nominal model (its parameters are the starting values).
    data : CalibrationData
        The measurements (N poses; kinds, frames and sigma in ``parakin.calibration.data``).
    free : sequence of str, optional
        The parameters to estimate. Default: every geometric parameter, every
        ``<actuated>_offset``, and the frame parameters of the unknown frames.
    fixed : sequence of str
        Parameters held at their starting values (removed from ``free``).
    prior : mapping name -> (mean, sigma), optional
        A Gaussian prior on free parameters (units of the parameter), as extra residuals.
    rank_tolerance : float
        Relative singular value below which a direction is unidentifiable.

    Returns
    -------
    CalibrationResult
        The calibrated values with their standard errors and covariance, what is identifiable
        and the null combinations, the residuals before and after, and the calibrated model
        (``.mechanism``).

    Raises
    ------
    CalibrationUnavailableError
        The package lacks the ``parameter_jacobians`` kernel (regenerate it).
    CalibrationDataError, BadInputError
        Measurements of the wrong shape, an unknown parameter name.
    ConvergenceError
        A pose whose loop cannot be closed from its starting guess.

    Examples
    --------
    A delta built with upper arms 1 mm longer than drawn (L = 0.351 m) and its first encoder
    reading 2 mrad low; a tracker measured its platform at 12 points (exact here):

    >>> import numpy as np, parakin
    >>> from parakin.calibration import CalibrationData, calibrate
    >>> m = parakin.load("delta", backend="numpy")  # the drawing
    >>> built = parakin.load("delta", backend="numpy", L=0.351)
    >>> points = m.home_passive + np.random.default_rng(0).uniform(-0.05, 0.05, (12, 3))
    >>> readings = built.inverse_pose(points).actuated[:, 0] - [0.002, 0.0, 0.0]
    >>> result = calibrate(m, CalibrationData(readings, points, kind="position", sigma=20e-6))
    >>> round(result.values["L"], 9), round(result.values["theta1_offset"], 9)
    (0.351, 0.002)
    >>> result.rank, [str(c) for c in result.unidentifiable]  # positions cannot tell R from r
    (6, ['R + r'])
    >>> calibrate(m, CalibrationData(readings, points, kind="position"), free=["L", "theta1_ofset"])
    Traceback (most recent call last):
    ...
    parakin.errors.BadInputError: unknown calibration parameter 'theta1_ofset' for 'delta'; did you mean 'theta1_offset' ...
    """
    began = time.perf_counter()
    problem = Problem(m, data, free, fixed, prior)
    q = _start(problem)
    values = problem.nominal.copy()
    r, jacobian, sensitivity = problem.evaluate(values, q)
    first = r
    cost = float(r @ r)
    damping = 1e-3
    iterations = 0
    for iterations in range(1, MAX_ITERATIONS + 1):  # noqa: B007  (reported)
        # the damped step min |J d + r|^2 + damping |W d|^2 (W: column norms, Marquardt's
        # scaling) for every damping from one eigendecomposition of the scaled normal matrix
        # (small, and cheap on any BLAS); directions with eigenvalue below STEP_RANK of the
        # largest (singular value below sqrt(STEP_RANK)) are not moved along: they change no residual
        weights = np.linalg.norm(jacobian, axis=0)
        weights = np.where(weights > 0.0, weights, 1.0)
        scaled = jacobian / weights
        eigenvalues, vectors = np.linalg.eigh(scaled.T @ scaled)
        keep = eigenvalues > STEP_RANK * eigenvalues[-1]
        projected = vectors[:, keep].T @ (scaled.T @ r)
        if np.any(~keep & (eigenvalues > 0.01 * rank_tolerance**2 * eigenvalues[-1])):
            # directions the normal matrix cannot resolve but the rank test may count: the SVD
            # (through QR) resolves singular values down to rank_tolerance
            u, singular, vt = thin_svd(scaled)
            keep = singular > rank_tolerance * singular[0]
            eigenvalues, vectors = singular[keep] ** 2, vt[: singular.size][keep].T
            projected = singular[keep] * (u[:, : singular.size][:, keep].T @ r)
            keep = np.ones(eigenvalues.size, dtype=bool)
        while True:
            step = -(vectors[:, keep] @ (projected / (eigenvalues[keep] + damping))) / weights
            trial = problem.full(values[problem.index] + step)
            try:
                trial_q = problem.close(trial, problem.predicted_passive(q, sensitivity, trial - values))
                trial_r = problem.evaluate(trial, trial_q, jacobian=False)[0]
                trial_cost = float(trial_r @ trial_r)
            except ConvergenceError:
                trial_cost = np.inf
            if trial_cost < cost:
                damping = max(damping / 10.0, DAMPING[0])
                break
            damping *= 10.0
            if damping > DAMPING[1]:
                break
        if not trial_cost < cost:
            break
        decrease = cost - trial_cost
        # the step's size in residual units (each parameter's change times its column's norm)
        moved = float(np.linalg.norm(step * weights))
        values, q, cost = trial, trial_q, trial_cost
        r, jacobian, sensitivity = problem.evaluate(values, q)
        if decrease <= COST_TOLERANCE * max(cost, 1e-300) + 1e-30 or moved <= STEP_TOLERANCE:
            break
    analysis = analyse(jacobian, problem.free, len(data), rank_tolerance)
    standard = np.sqrt(np.maximum(np.diag(analysis.covariance), 0.0))
    errors = {
        name: float(standard[i]) if name in analysis.identifiable else float("nan")
        for i, name in enumerate(problem.free)
    }
    n_rows = len(data) * data.size
    before = residual_in_units(data, first[:n_rows].reshape(len(data), data.size))
    after = residual_in_units(data, r[:n_rows].reshape(len(data), data.size))
    final = dict(zip(problem.names, (float(v) for v in values), strict=True))
    calibrated = _reload(m, {name: final[name] for name in problem.geometric})
    return CalibrationResult(
        names=tuple(problem.free),
        values=final,
        nominal=dict(zip(problem.names, (float(v) for v in problem.nominal), strict=True)),
        standard_errors=errors,
        covariance=analysis.covariance,
        rank=analysis.rank,
        singular_values=analysis.singular_values,
        observability=analysis.observability,
        identifiable=analysis.identifiable,
        unidentifiable=analysis.combinations,
        null_space=analysis.null_space,
        residuals_before=before,
        residuals_after=after,
        rms_before=_rms(before),
        rms_after=_rms(after),
        chi2=cost,
        dof=int(len(r) - analysis.rank),
        iterations=iterations,
        seconds=time.perf_counter() - began,
        passive=q,
        mechanism=calibrated,
    )


def prediction_covariance(
    result: CalibrationResult, readings: ArrayLike, guess: ArrayLike | None = None
) -> tuple[Array, Array]:
    """The calibrated model's platform poses at encoder readings and the covariance of their
    positions that the parameters' covariance implies (first-order propagation).

    Parameters
    ----------
    result : CalibrationResult
        What ``calibrate`` returned: its model, values and covariance.
    readings : array_like (N, n_a)
        Encoder readings (m or rad), the same kind as the calibration's.
    guess : array_like, optional
        Poses (N, 4, 4) or passive values (N, n_p) that seed Newton (default: the mode nearest home).

    Returns
    -------
    poses : numpy.ndarray, shape (N, 4, 4)
        ^B_P T of the calibrated model (its joints ``result.joints(readings)``), by Newton from
        ``guess``.
    covariance : numpy.ndarray, shape (N, 3, 3)
        Covariance (m^2) of the origin of {P} in {B}, from the covariance of the free geometric
        and joint parameters (the frames' do not move the platform).

    Raises
    ------
    BadInputError
        Readings whose joints are non-finite or outside the model's actuated ranges
        (``Mechanism.forward_pose``).
    ConvergenceError, SingularConfigurationError
        Newton did not close a pose from ``guess``, or met a type II singularity.
    ValueError
        ``readings`` whose last axis is not n_a (NumPy's broadcasting error).

    Examples
    --------
    The delta of ``calibrate``'s example, fitted on 8 of its 12 positions (20 um noise assumed);
    the other 4 are predicted, with the error the parameters' covariance implies:

    >>> import numpy as np, parakin
    >>> from parakin.calibration import CalibrationData, calibrate, prediction_covariance
    >>> m = parakin.load("delta", backend="numpy")
    >>> built = parakin.load("delta", backend="numpy", L=0.351)
    >>> points = m.home_passive + np.random.default_rng(0).uniform(-0.05, 0.05, (12, 3))
    >>> readings = built.inverse_pose(points).actuated[:, 0] - [0.002, 0.0, 0.0]
    >>> data = CalibrationData(readings, points, kind="position", sigma=20e-6)
    >>> result = calibrate(m, data.subset(np.arange(8)))
    >>> poses, cov = prediction_covariance(result, readings[8:])
    >>> poses.shape, cov.shape
    ((4, 4, 4), (4, 3, 3))
    >>> bool(np.abs(poses[:, :3, 3] - points[8:]).max() < 1e-9)  # the built robot's positions
    True
    >>> np.sqrt(np.trace(cov, axis1=1, axis2=2)).round(6).tolist()  # predicted 1-sigma (m)
    [...]
    """
    m = result.mechanism
    theta = np.asarray(readings, dtype=float)
    solved = m.forward_pose(result.joints(theta), guess=guess)
    data = CalibrationData(theta, solved.pose[:, :3, 3], kind="position", sigma=1.0, passive=solved.passive)
    movers = [name for name in result.names if not name.startswith(("tracker_", "tool_"))]
    joint_values = {k: v for k, v in result.values.items() if k.endswith(("_offset", "_scale"))}
    problem = Problem(m, data, movers, (), None, start=joint_values)
    q = problem.close(problem.nominal, solved.passive)
    jacobian = problem.evaluate(problem.nominal, q)[1].reshape(len(theta), 3, len(movers))
    pick = [result.names.index(name) for name in movers]
    covariance = result.covariance[np.ix_(pick, pick)]
    return np.asarray(solved.pose), jacobian @ covariance @ np.swapaxes(jacobian, 1, 2)


def _reload(m: Mechanism, parameters: dict[str, float]) -> Mechanism:
    """``m``'s package loaded again with new parameters, the same backend and joint ranges."""
    from parakin.loading import load

    limits: dict[str, tuple[float, float]] = {**m.limits, **m.actuated_ranges}
    try:
        return load(m.package.path, backend=m.backend.name, limits=limits, **parameters)
    except BadInputError as error:
        raise CalibrationDataError(
            f"the calibrated parameters leave {m.name}'s domain ({error}): the measurements determine this "
            "parameter poorly (see its standard error with fixed=... or a prior=...), or the model does not fit them"
        ) from error


__all__ = ["CalibrationResult", "Problem", "calibrate", "joint_names", "prediction_covariance", "require_kernel"]
