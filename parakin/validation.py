"""Input validation shared by every public entry point: one place that turns a user value into a
float array of the right shape, or into a ``BadInputError`` naming the value and what is wrong.

Accepted numbers: integers and reals (Python, NumPy). Rejected: complex values (their imaginary
part would be dropped), booleans, strings, bytes, None and object arrays, even when NumPy could
convert them, so that a typo never becomes a number. Batches follow one rule everywhere: the
leading (batch) axes of the inputs broadcast (``broadcast_shapes``), or a BadInputError names them.
"""

from __future__ import annotations

import difflib
import functools
import inspect
import math
import numbers
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from parakin.errors import BadInputError, UnknownKeywordError, at_index, first_index

Array = NDArray[np.float64]

#: the largest magnitude of a length or angle input or parameter (m, rad): beyond it
#: double-precision kinematics means nothing (squares and products overflow or lose every digit)
MAX_MAGNITUDE = 1e9
#: the largest iteration count an option accepts (the C driver counts in 64 bits; this bounds time)
MAX_ITERATIONS = 1_000_000


def as_array(value: ArrayLike, name: str, trailing: tuple[int, ...], finite: bool = True) -> Array:
    """``value`` as a float array whose last axes are ``trailing``, checked.

    Parameters
    ----------
    value : array_like
        Real numbers (int or float), any leading batch shape.
    name : str
        The argument's name, for messages.
    trailing : tuple of int
        The shape of the last axes, e.g. ``(6,)`` for a wrench or ``(4, 4)`` for a pose.
    finite : bool
        Refuse NaN and infinite values (default); False lets them pass, for functions that flag them.

    Returns
    -------
    numpy.ndarray, shape (..., *trailing)
        The values as float64.

    Raises
    ------
    BadInputError
        Not numeric (a string, None, complex, boolean or object values), ragged, of the wrong
        trailing shape, or (with ``finite``) not finite, naming the first bad index.

    Examples
    --------
    >>> from parakin.validation import as_array
    >>> as_array([[1, 2], [3, 4]], "points", (2,)).dtype.name
    'float64'
    >>> as_array([1.0, float("nan")], "rates", (2,))
    Traceback (most recent call last):
        ...
    parakin.errors.BadInputError: rates has a non-finite value at index (1,)
    """
    if isinstance(value, str | bytes) or value is None:
        raise BadInputError(f"{name} must be numeric, got {type(value).__name__}")
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError) as error:  # ragged nested sequences
        raise BadInputError(f"{name} must be a numeric array of one shape, got {type(value).__name__}") from error
    if raw.dtype.kind not in "iuf":
        what = {"c": "complex", "b": "boolean", "U": "string", "S": "bytes", "O": "object"}.get(raw.dtype.kind)
        raise BadInputError(f"{name} must be real numbers, got {what or raw.dtype} values")
    array = raw.astype(float)
    if array.ndim < len(trailing) or array.shape[array.ndim - len(trailing) :] != trailing:
        expected = "(..., " + ", ".join(str(n) for n in trailing) + ")"
        raise BadInputError(f"{name} must have shape {expected}, got {array.shape}")
    if finite and not np.isfinite(array).all():
        raise BadInputError(f"{name} has a non-finite value at index {first_index(~np.isfinite(array))}")
    return array


def real_number(value: object, name: str) -> float:
    """A finite real scalar (int or float, not bool/complex/str), or BadInputError."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise BadInputError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    number = float(value)
    if not math.isfinite(number):
        raise BadInputError(f"{name} must be finite, got {number}")
    return number


def positive_number(value: object, name: str, allow_zero: bool = False, maximum: float = 1e100) -> float:
    """A finite number > 0 (>= 0 with ``allow_zero``) and at most ``maximum`` (squares and
    products of it must not overflow), or BadInputError."""
    number = real_number(value, name)
    if number < 0 or (number == 0 and not allow_zero) or number > maximum:
        low = ">= 0" if allow_zero else "> 0"
        raise BadInputError(f"{name} must be {low} and <= {maximum:g}, got {number}")
    return number


#: the smallest Newton residual tolerance (m, rad): the closure's rounding floor reaches ~5e-15 on
#: some shipped mechanisms (measured: a planar and a spherical one) and differs between the NumPy, CasADi and C kernels,
#: so a smaller tolerance would converge on one backend and not another; 1e-13 is met by all
MIN_TOLERANCE = 1e-13


def newton_tolerance(value: object) -> float:
    """A residual tolerance in [MIN_TOLERANCE, 1] (``MIN_TOLERANCE`` = 1e-13: below it rounding,
    not the tolerance, decides convergence, and backends would disagree), or BadInputError."""
    number = positive_number(value, "tolerance")
    if not MIN_TOLERANCE <= number <= 1.0:
        raise BadInputError(
            f"tolerance must be in [{MIN_TOLERANCE:g}, 1], got {number:g} (below {MIN_TOLERANCE:g} the "
            "closure's rounding decides, differently on each backend)"
        )
    return number


def in_magnitude(value: float, name: str, bound: float = MAX_MAGNITUDE) -> float:
    """A value (a parameter, a fixed sweep value, named ``name`` in the message) of magnitude at
    most ``bound`` (SI): beyond it the kinematics overflows."""
    if abs(value) > bound:
        raise BadInputError(f"{name} = {value:g} exceeds {bound:g} in magnitude (SI units)")
    return value


def integer_in_range(value: object, name: str, minimum: int = 0, maximum: int = MAX_ITERATIONS) -> int:
    """An integer in [minimum, maximum] (no bool, no float), or BadInputError."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Integral):
        raise BadInputError(f"{name} must be an integer, got {type(value).__name__} {value!r}")
    number = int(value)
    if not minimum <= number <= maximum:
        raise BadInputError(f"{name} must be in [{minimum}, {maximum}], got {number}")
    return number


def in_domain(value: float, name: str, domain: str) -> None:
    """Check a parameter against its manifest domain (real, positive, nonnegative, nonzero, sign)."""
    allowed = {
        "real": True,
        "positive": value > 0,
        "nonnegative": value >= 0,
        "nonzero": value != 0,
        "sign": value in (1.0, -1.0),
    }
    if domain not in allowed:
        raise BadInputError(f"parameter {name!r} has an unknown domain {domain!r} in its manifest")
    if not allowed[domain]:
        wanted = {"positive": "> 0", "nonnegative": ">= 0", "nonzero": "!= 0", "sign": "+1 or -1"}[domain]
        raise BadInputError(f"parameter {name!r} must be {wanted}, got {value}")


def within_ranges(values: Array, names: Sequence[str], low: Array, high: Array, what: str) -> None:
    """Every entry of ``values`` (..., n) inside its closed range [low, high], or BadInputError
    naming the variable, its value, its range and the batch index."""
    outside = (values < low) | (values > high)
    if outside.any():
        where = first_index(outside)
        k = where[-1]
        at = at_index(where[:-1])
        raise BadInputError(f"{what} {names[k]} = {values[where]:g}{at} is outside its range [{low[k]:g}, {high[k]:g}]")


def bounded_vector(value: ArrayLike, name: str, components: Sequence[str], bound: float = MAX_MAGNITUDE) -> Array:
    """``value`` as (..., len(components)): finite reals of magnitude at most ``bound``.

    ``bound`` (SI units) is the one every input has: beyond it, products with the kinematics
    overflow to inf and NaN.

    Parameters
    ----------
    value : array_like, shape (..., len(components))
        The vectors (SI units).
    name : str
        The argument's name, for messages.
    components : sequence of str
        The components' names (e.g. ``("fx", "fy", "fz")``), for messages.
    bound : float
        The largest magnitude accepted.

    Returns
    -------
    numpy.ndarray, shape (..., len(components))
        The vectors as float64.

    Raises
    ------
    BadInputError
        Not numeric, of the wrong length, not finite, or a component beyond ``bound`` (naming the
        component and the batch index).

    Examples
    --------
    >>> from parakin.validation import bounded_vector
    >>> bounded_vector([0.0, -10.0], "wrench", ("fx", "fy")).tolist()
    [0.0, -10.0]
    """
    array = as_array(value, name, (len(components),))
    limit = np.full(len(components), bound)
    within_ranges(array, components, -limit, limit, name)
    return array


def stiffness_matrix(value: ArrayLike, name: str, size: int) -> Array:
    """A stiffness matrix (size, size), checked: positive diagonal, or symmetric positive definite.

    Parameters
    ----------
    value : array_like, shape (size,) or (size, size)
        The diagonal (every entry > 0), or a full matrix, symmetric to 1e-10 relative and
        positive definite (N/m or N m/rad).
    name : str
        The argument's name, for messages.
    size : int
        The number of actuators.

    Returns
    -------
    numpy.ndarray, shape (size, size)
        The matrix (a diagonal given as a vector is expanded).

    Raises
    ------
    BadInputError
        A diagonal entry not > 0, the wrong shape, an asymmetric matrix (naming the entry) or
        one that is not positive definite (naming its smallest eigenvalue).

    Examples
    --------
    >>> from parakin.validation import stiffness_matrix
    >>> stiffness_matrix([1000.0, 2000.0], "actuator_stiffness", 2).tolist()
    [[1000.0, 0.0], [0.0, 2000.0]]
    >>> stiffness_matrix([[1.0, 2.0], [2.0, 1.0]], "actuator_stiffness", 2)
    Traceback (most recent call last):
        ...
    parakin.errors.BadInputError: actuator_stiffness is not positive definite: smallest eigenvalue -1 (must be > 0)
    """
    k = as_array(value, name, ())
    if k.shape == (size,):
        bad = ~(k > 0)
        if bad.any():
            index = first_index(bad)
            raise BadInputError(f"{name}[{index[0]}] = {k[index]:g}: every actuator stiffness must be > 0")
        return np.diag(k)
    if k.shape != (size, size):
        raise BadInputError(f"{name} must have shape ({size},) or ({size}, {size}), got {k.shape}")
    scale = np.abs(k).max(initial=0.0)
    asymmetry = np.abs(k - k.T).max(initial=0.0)
    if asymmetry > 1e-10 * scale:
        where = first_index(np.abs(k - k.T) == asymmetry)
        raise BadInputError(
            f"{name} is not symmetric: entry {where} = {k[where]:g} but its transpose entry is {k[where[::-1]]:g}"
        )
    smallest = float(np.linalg.eigvalsh(k).min()) if size else 1.0
    if not smallest > 0:
        raise BadInputError(f"{name} is not positive definite: smallest eigenvalue {smallest:g} (must be > 0)")
    return k


def broadcast_shapes(*shapes: tuple[int, ...]) -> tuple[int, ...]:
    """``np.broadcast_shapes`` with the one batch rule of parakin: BadInputError naming them."""
    distinct = {tuple(shape) for shape in shapes if len(shape)}
    if len(distinct) <= 1:  # one batch shape, the others unbatched: the broadcast is that shape
        return next(iter(distinct), ())
    try:
        return tuple(np.broadcast_shapes(*shapes))
    except ValueError as error:
        raise BadInputError(f"batch shapes do not broadcast: {', '.join(map(str, shapes))}") from error


def batch_shape(inputs: tuple[Array, ...]) -> tuple[int, ...]:
    """The broadcast of the inputs' leading (batch) shapes, or BadInputError naming them."""
    return broadcast_shapes(*(np.shape(x)[:-1] for x in inputs))


def broadcast_batch(inputs: tuple[Array, ...]) -> tuple[tuple[int, ...], list[Array]]:
    """The common batch shape and each input reshaped to (n, size) (or (1, size) to share)."""
    shape = batch_shape(inputs)
    count = math.prod(shape)
    flat = []
    for x in inputs:
        array = np.asarray(x, dtype=float)
        size = array.shape[-1]
        if array.shape[:-1] == ():
            flat.append(np.ascontiguousarray(array.reshape(1, size)))
        elif array.shape[:-1] == shape:  # the size is explicit: an empty batch has no -1 to infer
            flat.append(np.ascontiguousarray(array.reshape(count, size)))
        else:
            flat.append(np.ascontiguousarray(np.broadcast_to(array, shape + (size,)).reshape(count, size)))
    return shape, flat


Method = TypeVar("Method", bound=Callable[..., Any])


def keywords_checked(method: Method) -> Method:
    """``method`` with its calling errors in the user's terms: a misspelt keyword (``gues=``) is an
    UnknownKeywordError (a BadInputError and a TypeError) naming it with the closest keywords of
    the method ("did you mean 'guess'?"), a missing or extra argument one naming the method;
    other TypeErrors pass unchanged.

    Parameters
    ----------
    method : callable
        A public method (its signature decides what a calling error is).

    Returns
    -------
    callable
        The same method, its errors of calling named.

    Raises
    ------
    UnknownKeywordError
        When called with arguments its signature does not accept.

    Examples
    --------
    >>> def move(distance, speed=1.0):
    ...     return distance / speed
    >>> keywords_checked(move)(2.0, sped=4.0)
    Traceback (most recent call last):
    ...
    parakin.errors.UnknownKeywordError: unknown keyword 'sped' of move; did you mean 'speed'? its keywords: ['distance', 'speed']
    """
    signature = inspect.signature(method)
    names = [p.name for p in signature.parameters.values() if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]
    names = [name for name in names if name != "self"]
    open_keywords = any(p.kind is p.VAR_KEYWORD for p in signature.parameters.values())

    @functools.wraps(method)
    def checked(*args: Any, **kwargs: Any) -> Any:
        try:
            return method(*args, **kwargs)
        except TypeError as error:
            try:
                signature.bind(*args, **kwargs)
            except TypeError as calling:
                unknown = [key for key in kwargs if key not in names] if not open_keywords else []
                if unknown:
                    close = difflib.get_close_matches(unknown[0], names, n=1, cutoff=0.6)
                    hint = f"; did you mean {close[0]!r}?" if close else ";"
                    raise UnknownKeywordError(
                        f"unknown keyword {unknown[0]!r} of {method.__name__}{hint} its keywords: {names}"
                    ) from None
                raise UnknownKeywordError(f"{method.__name__}: {calling}") from None
            raise error

    return checked  # type: ignore[return-value]
