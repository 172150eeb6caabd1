"""Shared checks: of the input (every failure a ValueError naming the parameter and its value), and of
what a contact element returns (the contract: type, shape, finiteness, naming the element)."""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray


def positive(name: str, value: object) -> float:
    """Return ``value`` as float if it is finite and > 0, else raise ValueError."""
    v = _scalar(name, value)
    if not v > 0.0:
        raise ValueError(f"{name} must be positive, got {name}={value!r}")
    return v


def relative(name: str, value: object) -> float:
    """Return ``value`` as float if it is in (0, 1) (a relative accuracy), else raise ValueError."""
    v = _scalar(name, value)
    if not 0.0 < v < 1.0:
        raise ValueError(f"{name} must be in (0, 1) (a relative accuracy), got {name}={value!r}")
    return v


def nonnegative(name: str, value: object) -> float:
    """Return ``value`` as float if it is finite and >= 0, else raise ValueError."""
    v = _scalar(name, value)
    if not v >= 0.0:
        raise ValueError(f"{name} must be >= 0, got {name}={value!r}")
    return v


def finite(name: str, value: object) -> float:
    """Return ``value`` as a finite float, else raise ValueError."""
    return _scalar(name, value)


def count(name: str, value: object, minimum: int = 1, maximum: int | None = None, bound: str = "") -> int:
    """Return ``value`` as an int >= ``minimum`` (and, with ``maximum``, <= it), else raise ValueError.

    A number only: an integer, or a float with an integral value; booleans and strings (``"3"``,
    which ``int()`` would read) are refused.  With ``maximum`` the error says the range and the
    constant ``bound`` that sets it (a bound on the work a request starts), to raise it.
    """
    ok = not isinstance(value, (bool, str, bytes))
    try:
        ok = ok and float(value) == int(value) and int(value) >= minimum
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {name}={value!r}")
    if maximum is not None and int(value) > maximum:
        raise ValueError(f"{name} must be an integer in {minimum}..{maximum}, got {name}={value!r} (the bound is "
                         f"{bound}: raise it to go further)")
    return int(value)


def derived(owner: str, params: dict, compute: Callable[[], dict], *, positive_names: tuple = ()) -> dict:
    """``compute()``: the quantities an element derives from its parameters (a dict), each finite
    (and > 0 for ``positive_names``); else a ValueError naming the parameters, the quantity and its
    value (parameters near the float limits, e.g. a stiffness of 1e-300 beside one of 1e300)."""
    shown = ", ".join(f"{k}={v!r}" for k, v in params.items())
    try:
        with np.errstate(all="raise"):
            out = compute()
    except (ZeroDivisionError, OverflowError, FloatingPointError) as exc:
        raise ValueError(f"{owner}({shown}): the parameters are too far apart for double precision (deriving the "
                         f"element's constants: {exc}); keep their ratios within about 1e150") from None
    for name, v in out.items():
        v = float(v)
        if not math.isfinite(v) or (name in positive_names and not v > 0.0):
            raise ValueError(f"{owner}({shown}): the parameters give {name} = {v!r}, which must be finite"
                             f"{' and > 0' if name in positive_names else ''}; keep their ratios within about 1e150")
    return out


def flag(name: str, value: object) -> bool:
    """``value`` if it is a bool (``True``, ``False`` or a numpy bool), else raise ValueError: a string
    such as ``"no"`` would be taken as True."""
    if value is True or value is False or isinstance(value, np.bool_):
        return bool(value)
    raise ValueError(f"{name} must be True or False, got {name}={value!r}")


def number_array(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """``value`` as a float array, refusing what ``numpy.asarray(value, dtype=float)`` would read or
    convert silently: strings (``"1"``), booleans (also among numbers in a list: ``[True, 2.0]``), None,
    complex numbers; finiteness is not checked."""
    if value is None or isinstance(value, (str, bytes, bool, np.bool_)) or _holds_bool(value):
        raise ValueError(f"{name} must be a number or an array of numbers, got {name}={shown(value)}")
    try:
        arr = np.asarray(value)
        kind = arr.dtype.kind
        if kind == "O" and not any(v is None or isinstance(v, (str, bytes, bool, np.bool_, complex))
                                   for v in arr.flat):
            arr, kind = arr.astype(float), "f"
    except (TypeError, ValueError):
        kind = "?"
    if kind not in "fiu":
        raise ValueError(f"{name} must be a number or an array of numbers, got {name}={shown(value)}")
    return arr.astype(float, copy=False)


def _holds_bool(value: object) -> bool:
    """Whether a list or tuple (nested) holds a boolean: ``numpy.asarray([True, 2.0])`` reads it as 1.0."""
    return isinstance(value, (list, tuple)) and any(
        isinstance(v, (bool, np.bool_)) or _holds_bool(v) for v in value)


def finite_array(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """``value`` as a float array (:func:`number_array`) whose entries are finite."""
    arr = number_array(name, value)
    if not np.all(np.isfinite(arr)):
        first = float(arr[~np.isfinite(arr)].flat[0]) if arr.ndim else float(arr)
        raise ValueError(f"{name} must be finite, got {name}={first!r}" if arr.ndim == 0 else
                         f"{name} must be finite, got {name} with an entry {first!r}")
    return arr


def nonnegative_array(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """Return ``value`` as a float array whose entries are finite and >= 0."""
    if type(value) is float and 0.0 <= value < math.inf:  # the common scalar, without numpy's checks
        return np.array(value)
    arr = number_array(name, value)
    bad = ~np.isfinite(arr) | (arr < 0.0)
    if np.any(bad):
        first = float(arr[bad].flat[0]) if arr.ndim else float(arr)
        raise ValueError(f"{name} must be finite and >= 0, got {name}={first!r}")
    return arr


def shown(value: object) -> str:
    """``repr(value)``, cut to 120 characters for a message."""
    r = repr(value)
    return r if len(r) <= 120 else r[:117] + "..."


def _scalar(name: str, value: object) -> float:
    if isinstance(value, (bool, str, bytes)):  # float("2e11") would read a string: a number only, as count
        raise ValueError(f"{name} must be a number, got {name}={value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {name}={value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {name}={value!r}")
    return v


# ---------------------------------------------------------------- what an element returns (the contract)
class ElementContractError(ValueError):
    """A contact element's hook returned the wrong type or shape (a defect of its code, not of a point):
    raised at once, also from inside a solve, naming the element, the hook and the output."""


class ElementOutputError(FloatingPointError):
    """A contact element returned a non-finite value (NaN or inf); the message names the element,
    the hook, the output and where.  A ``FloatingPointError``: the continuation takes it as a failed
    step, keeping the branch computed before it."""


def noted(exc: BaseException, element: Any, call: str, where: str) -> None:
    """Add to ``exc`` (raised by ``element``'s hook ``call``) a note naming the element, the hook and
    where it was asked, once (the innermost hook's): a solve's message then says which element failed.
    The contract's own errors name the element already (their message starts ``element=``)."""
    notes = getattr(exc, "__notes__", ())
    if not str(exc).startswith("element=") and not any(str(n).startswith("in element=") for n in notes):
        exc.add_note(f"in element={element!r}: {type(element).__name__}.{call} at {where}")


def _span(name: str, v: NDArray, unit: str) -> str:
    """``name=value unit``, or its range over an array, for a note."""
    if not v.size:
        return f"no {name}"
    lo, hi = float(np.min(v)), float(np.max(v))
    return f"{name}={lo:.6g} {unit}" if lo == hi else f"{name} in [{lo:.6g}, {hi:.6g}] {unit}"


def _own(element: object, hook: str) -> bool:
    """Whether ``element``'s class (not the contract's base) implements ``hook``."""
    owner = next((c for c in type(element).__mro__ if hook in c.__dict__), None)
    return owner is not None and not (owner.__name__ == "ContactElement" and owner.__module__ == "contact_models.base")


def fourier_checked(element: Any, a: NDArray, omega: NDArray, rtol: float, *, values: bool = False) -> list:
    """The element's ``(f_s, f_c, df_s/da, df_c/da)`` (``values``: ``(f_s, f_c)``, from ``_fourier`` where
    it implements it) for flat ``a``, ``omega``, checked: real arrays of one value per amplitude, finite;
    else ``ElementContractError`` (type, shape) or ``ElementOutputError`` naming the element, the hook and where.
    numpy's floating-point warnings inside the hook are not passed on: every value is checked here, and
    a value that left double precision is named in the error instead."""
    hook = "_fourier" if values and _own(element, "_fourier") else "_fourier_derivatives"
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            out = getattr(element, hook)(a, omega, rtol)
    except Exception as exc:
        noted(exc, element, f"{hook}(a, omega, rtol)", f"{_span('a', a, 'm')}, {_span('omega', omega, 'rad/s')}")
        raise
    if hook == "_fourier":
        return _returned(element, hook, out, 2, a, omega)
    out = _returned(element, hook, out, 4, a, omega)
    return out[:2] if values else out


def scalar_checked(element: Any, out: tuple, a: float, omega: float) -> tuple:
    """``out`` of the float path ``_derivatives_one`` at ``(a, omega)``, checked as :func:`fourier_checked`."""
    if isinstance(out, tuple) and len(out) == 4 and all(type(v) in (float, np.float64) for v in out) \
            and math.isfinite(sum(out)):
        return out
    arrays = tuple(np.array([v], dtype=float) for v in out) if isinstance(out, tuple) else out
    return tuple(float(v[0]) for v in _returned(element, "_derivatives_one", arrays, 4, np.array([a], dtype=float),
                                               np.array([omega], dtype=float)))


def _returned(element: Any, hook: str, out: Any, count: int, a: NDArray, omega: NDArray) -> list:
    n = a.size
    if type(out) is tuple and len(out) == count:  # the common case, at the solver's rate
        if all(type(v) is np.ndarray and v.dtype == np.float64 and v.size == n for v in out):
            if n == 0 or math.isfinite(sum(float(np.sum(v)) for v in out)):
                return list(out)
    name = f"element={element!r}: {type(element).__name__}.{hook}(a, omega, rtol)"
    names = ("f_s", "f_c", "df_s/da", "df_c/da")[:count]
    if not isinstance(out, (tuple, list)) or len(out) != count:
        raise ElementContractError(f"{name} must return {count} arrays ({', '.join(names)}), got {_kind(out)}")
    checked = []
    for what, v in zip(names, out):
        v = _real_array(v, f"{name}: {what}")
        if v.size != n or (v.ndim > 1 and v.shape != a.shape):
            raise ElementContractError(f"{name} must return {what} with one value per amplitude ({n}), got "
                                       f"{what} of shape {v.shape}")
        checked.append(v.reshape(n))
    _finite(checked, names, name, lambda i: f"a={float(a.flat[i]):.6g} m, omega={float(omega.flat[i]):.6g} rad/s")
    return checked


def _norm(X: NDArray) -> float:
    """The Euclidean norm of ``X`` for a message, scaled by its largest entry so that it neither overflows (an
    ``X`` of 1e200 m: numpy's "overflow encountered in dot") nor underflows to 0 (one of 1e-320 m)."""
    top = float(np.max(np.abs(X))) if X.size else 0.0
    return top * float(np.linalg.norm(X / top)) if 0.0 < top < math.inf else top


def time_law_checked(element: Any, x: NDArray, omega: float) -> tuple[NDArray, NDArray]:
    """``element._periodic_force(x, omega)`` checked: a pair ``(f, df/dx)`` of real arrays of shapes
    x's and (x.size, x.size), finite; else ``ValueError`` or ``ElementOutputError`` naming the element.
    numpy's floating-point warnings inside the hook are not passed on: a value that left double precision
    is named in the error instead (as :func:`fourier_checked` does)."""
    n = x.size
    where = f"omega={omega!r}, x of shape {x.shape} in [{float(np.min(x)):.6g}, {float(np.max(x)):.6g}]"
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            out = element._periodic_force(x, omega)
    except Exception as exc:
        noted(exc, element, "_periodic_force(x, omega)", where)
        raise
    name = f"element={element!r}: {type(element).__name__}._periodic_force(x, omega)"
    if not isinstance(out, (tuple, list)) or len(out) != 2:
        raise ElementContractError(f"{name} must return a pair (f, df_dx), got {_kind(out)}")
    checked = []
    for what, v, shape in zip(("f", "df_dx"), out, (x.shape, (n, n))):
        v = _real_array(v, f"{name}: {what}")
        if v.shape != shape:
            raise ElementContractError(f"{name} must return {what} of shape {shape} for x of shape {x.shape}, got "
                                       f"{what} of shape {v.shape}")
        checked.append(v)
    _finite(checked, ("f", "df_dx"), name, lambda i: where)
    return checked[0], checked[1]


def harmonics_asked(element: Any, X: NDArray, omega: float, n_t: int, rtol: float, *, hook: str = "_harmonic_force",
                    **kw: Any) -> Any:
    """``element.<hook>(X, omega, n_t, rtol, **kw)`` (unchecked), an exception it raises noted with the
    element and where (:func:`noted`).  numpy's floating-point warnings inside the hook are not passed on:
    every caller checks the answer (:func:`harmonics_checked`), which names a value that left double precision."""
    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return getattr(element, hook)(X, omega, n_t, rtol, **kw)
    except Exception as exc:
        noted(exc, element, f"{hook}(X, omega, n_t, rtol)", f"omega={omega!r} rad/s, |X| = {_norm(X):.6g} m")
        raise


def harmonics_checked(element: Any, out: Any, X: NDArray, omega: float) -> tuple[NDArray, NDArray, NDArray]:
    """``(F, dF/dX, dF/domega)`` of ``_harmonic_force`` checked: real arrays of X's size, its square
    and X's size, finite; else ``ValueError`` or ``ElementOutputError`` naming the element."""
    n = X.size
    if type(out) is tuple and len(out) == 3:
        F, J, Fw = out
        if (type(F) is np.ndarray and type(J) is np.ndarray and type(Fw) is np.ndarray
                and F.dtype == J.dtype == Fw.dtype == np.float64 and F.size == n == Fw.size and J.size == n * n
                and math.isfinite(float(F.sum()) + float(J.sum()) + float(Fw.sum()))):
            return out
    name = f"element={element!r}: {type(element).__name__}._harmonic_force(X, omega, n_t, rtol)"
    names = ("F", "dF_dX", "dF_domega")
    if not isinstance(out, (tuple, list)) or len(out) != 3:
        raise ElementContractError(f"{name} must return (F, dF_dX, dF_domega), got {_kind(out)}")
    checked = []
    for what, v, size in zip(names, out, (n, n * n, n)):
        v = _real_array(v, f"{name}: {what}")
        if v.size != size:
            want = f"({n}, {n})" if what == "dF_dX" else f"({n},)"
            raise ElementContractError(f"{name} must return {what} of shape {want} for X of shape {X.shape}, got "
                                       f"{what} of shape {v.shape}")
        checked.append(v)
    where = f"omega={omega!r}, |X| = {_norm(X):.6g} m"
    _finite(checked, names, name, lambda i: where)
    return tuple(checked)


def amount_checked(element: Any, hook: str, value: Any, omega: float, *, amplitude: bool = False) -> Any:
    """A scalar hook's answer at ``omega`` (a stiffness, N/m; an ``amplitude``, m, >= 0) as given, if it is
    a real number other than NaN (inf is one: a rigid contact's stiffness, an amplitude at which nothing
    slips); else ``ElementContractError`` (not a number, a negative amplitude) or ``ElementOutputError``
    (NaN) naming the element and the hook: the solver compares amplitudes with it and divides by it."""
    if type(value) is float and (value >= 0.0 if amplitude else value == value):  # the common case, at once
        return value
    name = f"element={element!r}: {type(element).__name__}.{hook}(omega)"
    if (isinstance(value, (bool, str, bytes)) or np.ndim(value) != 0 or np.iscomplexobj(value)
            or not isinstance(np.asarray(value).item(), (int, float))):
        raise ElementContractError(f"{name} must return a real number, got {_kind(value)}")
    v = float(value)
    if v != v:
        raise ElementOutputError(f"{name} returned nan (not a number) at omega={omega!r}")
    if amplitude and v < 0.0:
        raise ElementContractError(f"{name} must return an amplitude >= 0 (m), got {v!r} at omega={omega!r}")
    return value


def pair_checked(element: Any, hook: str, value: Any, omega: float) -> tuple:
    """``_linear_coefficients``' ``(k_s, k_c)`` (N/m) at ``omega``, each checked as :func:`amount_checked`."""
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        raise ElementContractError(f"element={element!r}: {type(element).__name__}.{hook}(omega) must return a "
                                   f"pair (k_s, k_c), got {_kind(value)}")
    return tuple(amount_checked(element, hook, v, omega) for v in value)


def loop_checked(element: Any, out: Any, a: float, omega: float) -> tuple[NDArray, NDArray]:
    """``_hysteresis``'s ``(x, f)`` checked: a pair of real arrays, finite."""
    name = f"element={element!r}: {type(element).__name__}._hysteresis(a, omega, n)"
    if not isinstance(out, (tuple, list)) or len(out) != 2:
        raise ElementContractError(f"{name} must return a pair (x, f), got {_kind(out)}")
    x, f = (_real_array(v, f"{name}: {w}") for v, w in zip(out, ("x", "f")))
    _finite([x, f], ("x", "f"), name, lambda i: f"a={a!r} m, omega={omega!r} rad/s")
    return x, f


def _kind(v: object) -> str:
    """What ``v`` is, for a message: its type, and its length or shape."""
    if isinstance(v, np.ndarray):
        return f"an array of shape {v.shape}"
    if isinstance(v, (tuple, list)):
        return f"a {type(v).__name__} of {len(v)}"
    return f"{type(v).__name__} {v!r}"[:200]


def _real_array(v: object, name: str) -> np.ndarray:
    """``v`` as a float64 array; ``ValueError`` naming it for a complex, a non-numeric or a ragged value."""
    if v is None or isinstance(v, (str, bytes)):
        raise ElementContractError(f"{name} must be a real array, got {_kind(v)}")
    try:
        arr = np.asarray(v)
    except (TypeError, ValueError):
        raise ElementContractError(f"{name} must be a real array, got {_kind(v)}") from None
    if np.iscomplexobj(arr):
        raise ElementContractError(f"{name} must be real, got a complex array "
                                   f"(max|Im| = {float(np.max(np.abs(arr.imag))):.3g})")
    if arr.dtype.kind not in "fiu":
        raise ElementContractError(f"{name} must be a real array, got {_kind(v)} of dtype {arr.dtype}")
    return arr.astype(float, copy=False)


def _finite(arrays: list, names: tuple, name: str, where: Callable[[int], str]) -> None:
    """Raise ``ElementOutputError`` at the first non-finite value of ``arrays`` (``where(i)`` says where)."""
    for what, v in zip(names, arrays):
        bad = ~np.isfinite(v)
        if np.any(bad):
            i = int(np.flatnonzero(bad.ravel())[0])
            raise ElementOutputError(f"{name} returned {what} = {float(v.ravel()[i])!r} (not finite) at "
                                     f"{where(i % max(1, v.size if v.ndim <= 1 else v.shape[0]))}")
