"""Building blocks of the scene schema: a key's check, its default and its doc.

A check is a callable ``check(value) -> converted value`` that raises :class:`Invalid` with what
is allowed.  The constructors below (:func:`number`, :func:`integer`, :func:`choice`, ...) make
the checks of every built-in key; a user's model registered with
:func:`hbm.scenes.register_model` declares its own keys with them.
"""

from __future__ import annotations

import difflib
import json
import math
from typing import Any, Callable, Iterable, NamedTuple

from .._validation import InputError


class SceneError(InputError):
    """An invalid scene: ``problems`` lists every message (file, table.key, value, what is allowed).

    A ``ValueError``: its text is the problems, one a line.

    Parameters
    ----------
    problems : iterable of str
        Every problem found, each naming the file, ``table.key``, the value and what is allowed.

    Examples
    --------
    >>> from hbm.scenes import SceneError
    >>> err = SceneError(["a.toml: sweep.omega is missing", "a.toml: [damper] is missing"])
    >>> len(err.problems), isinstance(err, ValueError)
    (2, True)
    """

    def __init__(self, problems: Iterable[str]) -> None:
        self.problems = list(problems)
        super().__init__("\n".join(self.problems))


class Invalid(Exception):
    """A value check failed; the argument says what is allowed.

    Raised by a key's check (``number``, ``choice``, ...); validation turns it into one problem of
    a ``SceneError``, prefixed with the file, ``table.key`` and the value.

    Parameters
    ----------
    *args : str
        What is allowed, e.g. ``"must be a number > 0 (N)"``.
    """


#: Marker: the key must be given.
REQUIRED = object()  # marker: the key must be given (whatever else the scene says)
OPTIONAL = None  # the key may be left out; its meaning then depends on other keys (see doc)


class Key(NamedTuple):
    """One key of a table: ``check(value) -> converted`` (raises :class:`Invalid`), default, doc.

    ``default`` is a value, :data:`REQUIRED` (the key must be given) or :data:`OPTIONAL` (it may
    be left out; its meaning then depends on other keys).

    Parameters
    ----------
    check : callable
        ``check(value) -> converted value``, raising ``Invalid`` with what is allowed.
    default : object
        The value taken when the key is left out, ``REQUIRED`` or ``OPTIONAL``.
    doc : str
        One line on the key's meaning and units, for messages, ``python3 -m hbm keys`` and the docs.

    Examples
    --------
    >>> from hbm.scenes import Key, number
    >>> key = Key(number(gt=0, unit="N"), 1.0, "slip force (N)")
    >>> key.check(2), key.default
    (2.0, 1.0)
    """

    check: Callable[[Any], Any]
    default: Any
    doc: str


class _GivenInvalid:
    """The type of :data:`GIVEN_INVALID`."""

    def __repr__(self) -> str:
        return "GIVEN_INVALID"


#: The value a rule sees for a key given with an invalid value: given (not None, which is a key's absent
#: default), so a model's ``needs`` and the rules that ask whether a key is given do not report a
#: follow-on problem of a key whose own problem is already said.
GIVEN_INVALID = _GivenInvalid()


def show(v: Any) -> str:
    """A value as it would be written in TOML."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, float) and math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if isinstance(v, float) and math.isnan(v):
        return "nan"
    if isinstance(v, (list, tuple)):  # a checked list key holds a tuple: shown as written
        return "[" + ", ".join(show(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {show(x)}" for k, x in v.items()) + "}"
    return repr(v)


def number(*, gt: float | None = None, ge: float | None = None, lt: float | None = None, unit: str = "",
           allow_inf: bool = False) -> Callable[[Any], float]:
    """A check of a number with optional bounds ``gt``, ``ge``, ``lt`` (``unit`` is shown in messages).

    The check returns the value as a float and raises :class:`Invalid` saying what is allowed.

    Parameters
    ----------
    gt, ge, lt : float or None, optional
        Bounds: the value must be ``> gt``, ``>= ge`` and ``< lt``; None (default) for no bound.
    unit : str, optional
        The unit, shown in messages (default ``""``, none).
    allow_inf : bool, optional
        Accept ``+inf`` (default False: finite values only; NaN is always refused).

    Returns
    -------
    callable
        ``check(value) -> float``; booleans and non-numbers raise ``Invalid``.  Its ``what``
        attribute says what is allowed, in words.

    Examples
    --------
    >>> from hbm.scenes import number
    >>> number(gt=0, unit="N")(8)
    8.0
    >>> number(gt=0, unit="N").what
    'a number > 0 (N)'
    """
    parts = [p for p in (f"> {gt:g}" if gt is not None else None, f">= {ge:g}" if ge is not None else None,
                         f"< {lt:g}" if lt is not None else None) if p]
    what = "a number" + (" " + " and ".join(parts) if parts else "") + (f" ({unit})" if unit else "")
    if allow_inf:
        what += " or inf"

    def check(v: Any) -> Any:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise Invalid(f"must be {what}")
        v = float(v)
        if math.isnan(v) or (math.isinf(v) and not (allow_inf and v > 0)):
            raise Invalid(f"must be {what} (finite)" if not allow_inf else f"must be {what}")
        if ((gt is not None and not v > gt) or (ge is not None and not v >= ge)
                or (lt is not None and not v < lt)):
            raise Invalid(f"must be {what}")
        return v

    check.what = what
    return check


def integer(minimum: int) -> Callable[[Any], int]:
    """A check of an integer >= ``minimum`` (booleans refused); raises :class:`Invalid`.

    Parameters
    ----------
    minimum : int
        The smallest value allowed.

    Returns
    -------
    callable
        ``check(value) -> int``, raising ``Invalid`` for a non-integer or a value below ``minimum``.

    Examples
    --------
    >>> from hbm.scenes import integer
    >>> integer(1)(3)
    3
    """

    def check(v: Any) -> Any:
        if isinstance(v, bool) or not isinstance(v, int) or v < minimum:
            raise Invalid(f"must be an integer >= {minimum}")
        return int(v)

    return check


def boolean(v: Any) -> bool:
    """Check of a TOML boolean: returns ``v``, or raises :class:`Invalid` for anything else.

    Parameters
    ----------
    v : object
        The value read from the scene.

    Returns
    -------
    bool
        ``v`` itself.

    Raises
    ------
    Invalid
        When ``v`` is not ``True`` or ``False``.
    """
    if not isinstance(v, bool):
        raise Invalid("must be true or false")
    return v


#: The deepest nesting of tables and arrays a scene may have (its own deepest is 4, [damper.load] in a list).
MAX_NESTING = 16
#: What a scene nested past the TOML reader's recursion is told.
TOO_DEEP = f"its arrays or tables nest too deeply for the TOML reader; a scene nests at most {MAX_NESTING} levels"


def nesting(value: Any) -> int:
    """The depth of nested dicts and lists in ``value`` (0 for a scalar), counted without recursion."""
    deepest, stack = 0, [(value, 0)]
    while stack:
        v, depth = stack.pop()
        if isinstance(v, dict):
            v = list(v.values())
        if isinstance(v, list):
            depth += 1
            deepest = max(deepest, depth)
            stack.extend((item, depth) for item in v if isinstance(item, (dict, list)))
    return deepest


def refuse_nesting(value: Any, where: str) -> None:
    """:class:`SceneError` (``where``: the file or option) when ``value`` nests past ``MAX_NESTING``."""
    deepest = nesting(value)
    if deepest > MAX_NESTING:
        raise SceneError([f"{where}: its arrays or tables nest {deepest} levels deep; a scene nests at most "
                          f"{MAX_NESTING} levels"])


def inner_folder(v: Any) -> str:
    """Check of an output folder: a relative path inside the scene's folder (no absolute path, no
    ``..``, not empty), or :class:`Invalid`; the command line's ``--out`` writes anywhere.

    Examples
    --------
    >>> from hbm.scenes.checks import inner_folder
    >>> inner_folder("results/run1")
    'results/run1'
    """
    import pathlib

    if not isinstance(v, str) or not v.strip():
        raise Invalid("must be a folder name (a string)")
    parts = pathlib.PurePath(v).parts
    if pathlib.PurePosixPath(v).is_absolute() or pathlib.PureWindowsPath(v).is_absolute() or ".." in parts \
            or pathlib.PureWindowsPath(v).drive or "\0" in v:
        raise Invalid("must be a folder inside the scene's folder (a relative path without ..): a scene writes "
                      "only beside itself; give --out DIR on the command line to write elsewhere")
    return v


def text(v: Any) -> str:
    """Check of a string: returns ``v``, or raises :class:`Invalid` for anything else.

    Parameters
    ----------
    v : object
        The scene's value of a key that takes a string.

    Returns
    -------
    str
        ``v`` itself.

    Raises
    ------
    Invalid
        When ``v`` is not a string.
    """
    if not isinstance(v, str):
        raise Invalid("must be a string")
    return v


def choice(*names: str) -> Callable[[Any], str]:
    """A check that the value is one of ``names``; the message suggests the closest name.

    Parameters
    ----------
    *names : str
        The allowed values.

    Returns
    -------
    callable
        ``check(value) -> str``: the value, or ``Invalid`` listing ``names`` (and the closest one
        to a misspelt string: the same name in other case first, as "Hz" for "hz").  Its ``names`` attribute holds ``names``.

    Examples
    --------
    >>> from hbm.scenes import Invalid, choice
    >>> check = choice("uniform", "quadratic")
    >>> check("quadratic")
    'quadratic'
    >>> try:
    ...     check("unifrom")
    ... except Invalid as exc:
    ...     print(exc)
    must be one of "uniform", "quadratic" (did you mean "uniform"?)
    """
    allowed = ", ".join(json.dumps(n) for n in names)

    def check(v: Any) -> Any:
        if not isinstance(v, str) or v not in names:
            hint = ""
            if isinstance(v, str):  # a name spelt in other case first ("hz": "Hz"), then the closest
                close = [n for n in names if n.lower() == v.lower()] or difflib.get_close_matches(v, names, n=1)
                hint = f" (did you mean {json.dumps(close[0])}?)" if close else ""
            raise Invalid(f"must be one of {allowed}{hint}")
        return v

    check.names = names
    return check


def number_or_name(number_check: Callable[[Any], float], names: dict) -> Callable[[Any], float]:
    """A number that ``number_check`` accepts, or a name of ``names`` standing for its number (the
    named tolerances ``"fast"``, ``"default"``, ``"precise"`` of ``frequency_response``'s ``tol``).

    Returns
    -------
    callable
        ``check(value) -> float``: the number, or the named one; ``Invalid`` saying both forms.

    Examples
    --------
    >>> from hbm.scenes import Invalid, number, number_or_name
    >>> check = number_or_name(number(gt=0, lt=1), {"fast": 1e-2, "precise": 1e-5})
    >>> check("precise"), check(0.002)
    (1e-05, 0.002)
    >>> try:
    ...     check("fats")
    ... except Invalid as exc:
    ...     print(exc)
    must be a number > 0 and < 1 or one of "fast" (0.01), "precise" (1e-05) (did you mean "fast"?)
    """
    allowed = ", ".join(f"{json.dumps(n)} ({v:g})" for n, v in names.items())
    what = f"{number_check.what} or one of {allowed}"

    def check(v: Any) -> float:
        if isinstance(v, str):
            if v in names:
                return float(names[v])
            close = [n for n in names if n.lower() == v.lower()] or difflib.get_close_matches(v, list(names), n=1)
            raise Invalid(f"must be {what}" + (f" (did you mean {json.dumps(close[0])}?)" if close else ""))
        try:
            return number_check(v)
        except Invalid:
            raise Invalid(f"must be {what}") from None

    check.what = what
    return check


def one_or_list(item: Callable[[Any], Any], what: str) -> Callable[[Any], tuple]:
    """A single value or a non-empty list of distinct values (a study over them); returns a tuple.

    Parameters
    ----------
    item : callable
        The check of one value.
    what : str
        One value in words, for messages (e.g. ``"a number > 0 (N)"``).

    Returns
    -------
    callable
        ``check(value) -> tuple``: each value passed through ``item``; ``Invalid`` for an empty
        list, a value ``item`` refuses, or a repeated value.

    Examples
    --------
    >>> from hbm.scenes import number, one_or_list
    >>> check = one_or_list(number(gt=0), "a number > 0")
    >>> check(5), check([1, 2])
    ((5.0,), (1.0, 2.0))
    """

    def check(v: Any) -> Any:
        values = v if isinstance(v, list) else [v]
        if not values:
            raise Invalid(f"must be {what}, or a non-empty list of them")
        try:
            out = tuple(item(x) for x in values)
        except Invalid as exc:
            raise Invalid(f"{exc} (or a list of such values)") from None
        if len(set(out)) != len(out):
            raise Invalid("must not repeat a value")
        return out

    return check


def number_list(item: Callable[[Any], float], *, length: int | None = None,
                minimum: int = 1) -> Callable[[Any], tuple]:
    """A check of a list of numbers, each passing ``item`` (``length`` exactly, or ``minimum`` at least).

    The check returns a tuple of floats and raises :class:`Invalid` saying what is allowed.

    Parameters
    ----------
    item : callable
        The check of one number, made by ``number`` (its ``what`` attribute is used in messages).
    length : int or None, optional
        The exact length required; default None (any length of at least ``minimum``).
    minimum : int, optional
        The smallest length allowed when ``length`` is None (default 1).

    Returns
    -------
    callable
        ``check(value) -> tuple of float``.

    Examples
    --------
    >>> from hbm.scenes import number, number_list
    >>> number_list(number(ge=0), length=2)([1, 2.5])
    (1.0, 2.5)
    """

    def check(v: Any) -> Any:
        if not isinstance(v, list) or (length is not None and len(v) != length) or len(v) < minimum:
            n = f"{length}" if length is not None else f"at least {minimum}"
            raise Invalid(f"must be a list of {n} numbers, each {item.what}")
        try:
            return tuple(item(x) for x in v)
        except Invalid as exc:
            raise Invalid(f"must be a list of {len(v)} numbers, each {item.what}") from exc

    return check


def formats(v: Any) -> tuple:
    """A list of distinct output names out of "csv", "png", "json"."""
    names = ("csv", "png", "json")
    if not isinstance(v, list) or any(x not in names for x in v) or len(set(v)) != len(v):
        raise Invalid('must be a list of distinct names out of "csv", "png", "json"')
    return tuple(v)


def dot(table: str, key: str) -> str:
    """``table.key`` (a top-level key bare)."""
    return f"{table}.{key}" if table else key


positive = number(gt=0)
nonnegative = number(ge=0)
