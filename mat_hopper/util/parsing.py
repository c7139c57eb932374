"""One way to read a name and one way to read a number, for the command
line and the Python API alike.

Names (conventions, behaviours, backends, samplers, segment-mass rules)
are case-insensitive, the way design names always were: ``PAPER`` is
``paper``. An unknown name is answered with the accepted ones and, where
one is close (:func:`did_you_mean`: the same name with other separators,
``rho_inc`` for ``rho-inc``, or a near spelling by
:func:`difflib.get_close_matches`), "did you mean ...?". URL schemes are too (RFC 3986, section 3.1: "schemes are
case-insensitive"; ``SQLite:///x.db`` is ``sqlite:///x.db``).

Numbers are ASCII decimals only (``12``, ``-1.5``, ``2e-4``): Python's
``float()`` also takes ``inf``, ``nan``, ``1_000`` and digits of other
scripts (``"١٢"``), none of which a user means as a run setting. A rigid
segment is the word ``rigid``, spelled out, never ``inf``.

Environment variables the tool reads ($MAT_HOPPER_PROFILE, ...) are read
by :func:`env_value`: set but empty is an error naming the variable, never
a silent default.

Every error is a ValueError naming the option or argument (`flag`) the
user typed.
"""

from __future__ import annotations

import difflib
import math
import numbers
import os
import re
from collections.abc import Iterable

RIGID = "rigid"
# Optional sign, digits with an optional fraction (or a bare fraction), optional exponent: ASCII only.
_DECIMAL = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)
_SCHEME = re.compile(r"([A-Za-z][A-Za-z0-9+.-]*):", re.ASCII)
# Separators a user may type for one another in a name: "rho_inc", "rho inc", "axial bending".
_SEPARATORS = re.compile(r"[\s_\-/+.]+")
# difflib's similarity ratio a near spelling must reach (its own default).
CLOSE_MATCH_CUTOFF = 0.6


def _name_key(text) -> str:
    return _SEPARATORS.sub("-", str(text).strip().lower()).strip("-")


def close_names(text, choices: Iterable[str], n: int = 3) -> list[str]:
    """The names of `choices` that `text` may have meant, best first: those
    equal to it but for case and separators (``rho_inc``, ``RHO INC`` for
    ``rho-inc``; ``axial bending`` for ``axial+bending``), else the one
    name `text` is a prefix of where only one is (``loss`` for
    ``loss-factor``), else up to `n` near spellings
    (:func:`difflib.get_close_matches`, cutoff
    :data:`CLOSE_MATCH_CUTOFF`, compared in lower case).

    Args:
        text: the name typed (read as str; None: no match).
        choices: the accepted names.
        n: the most near spellings returned.

    Returns:
        The matching names as spelled in `choices` (possibly empty).
    """
    choices = tuple(dict.fromkeys(choices))
    if text is None or not str(text).strip():
        return []
    keys = {}
    for c in choices:
        keys.setdefault(_name_key(c), c)
    key = _name_key(text)
    if key in keys:
        return [keys[key]]
    starting = [k for k in keys if k.startswith(key)]
    if len(starting) == 1:  # a unique prefix ("loss" for "loss-factor") is the name meant
        return [keys[starting[0]]]
    return [keys[k] for k in difflib.get_close_matches(key, list(keys), n=n, cutoff=CLOSE_MATCH_CUTOFF)]


def did_you_mean(text, choices: Iterable[str]) -> str:
    """``"did you mean X?"`` (``"X or Y"`` for two or three) for the names
    :func:`close_names` finds, or ``""`` when none is close: the clause the
    package's "unknown name" errors end with.

    Args:
        text: the name typed.
        choices: the accepted names.

    Returns:
        The clause, or an empty string.

    >>> did_you_mean("rho_inc", ["rho-inc", "rho-dec", "SS"])
    'did you mean rho-inc?'
    """
    found = close_names(text, choices)
    if not found:
        return ""
    return f"did you mean {', '.join(found[:-1]) + ' or ' + found[-1] if len(found) > 1 else found[0]}?"


def parse_name(text, choices: Iterable[str], flag: str) -> str:
    """The choice `text` names, compared case-insensitively after trimming
    blanks; returns the choice as spelled in `choices`.

    Args:
        text: the name typed or passed (any object, read as str; None is
            refused as not given).
        choices: the accepted names.
        flag: the option or argument named in errors (``--convention``).

    Returns:
        The first of `choices` equal to `text`, case-insensitively, as
        spelled in `choices`.

    Raises:
        ValueError: None, empty, or not one of `choices` (the message lists them
            and ends with :func:`did_you_mean`'s clause where a name is
            close).
    """
    choices = tuple(choices)
    if text is None:  # not given where a name is needed: said as such, not as an empty name
        raise ValueError(f"{flag} is not given (None); accepted: {', '.join(choices)}")
    key = str(text).strip().lower()
    if not key:
        raise ValueError(f"{flag} is empty; accepted: {', '.join(choices)}")
    for c in choices:
        if c.lower() == key:
            return c
    hint = did_you_mean(text, choices)
    raise ValueError(f"unknown {flag} {text!r}; accepted: {', '.join(choices)}{f'; {hint}' if hint else ''}")


def is_decimal(text) -> bool:
    """Whether `text` is an ASCII decimal (what :func:`parse_number` reads
    from a string): ``12``, ``-1.5``, ``2e-4``; not ``inf``, ``1_0``, ``١``.

    Args:
        text: the value to test; anything but a str gives False.

    Returns:
        True when `text` is a str whose blank-trimmed text is an ASCII
        decimal (optional sign, digits, optional fraction and exponent).
    """
    return isinstance(text, str) and _DECIMAL.fullmatch(text.strip()) is not None


def env_value(name: str, hint: str = "") -> str | None:
    """The value of environment variable `name`, blanks trimmed; None when it
    is not set. Set but empty (or blanks) is an error naming the variable:
    an empty value is never read as "use the default".

    Args:
        name: the variable's name, without ``$``.
        hint: appended to the error, in parentheses, when given (e.g. the
            accepted values); default empty.

    Returns:
        The value with blanks trimmed, or None when the variable is not set.

    Raises:
        ValueError: ``$NAME is set but empty; unset it or give a value`` (and `hint`).
    """
    text = os.environ.get(name)
    if text is None:
        return None
    if not text.strip():
        raise ValueError(f"${name} is set but empty; unset it or give a value{f' ({hint})' if hint else ''}")
    return text.strip()


def is_real(value) -> bool:
    """Whether `value` is a real number a caller passed: an int or float,
    NumPy scalars included (``np.int64`` from ``np.arange``, ``np.float32``),
    a bool not (True is an int to Python, not a setting's number).

    Args:
        value: any object.

    Returns:
        True for a real number other than a bool, else False (strings too:
        :func:`parse_number` reads those).
    """
    return isinstance(value, numbers.Real) and not isinstance(value, bool)  # np.bool_ is no numbers.Real


def parse_number(
    text,
    flag: str,
    *,
    low: float | None = None,
    high: float | None = None,
    rigid: bool = False,
    integer: bool = False,
    unit: str = "",
) -> float | int | None:
    """A number typed by the user (a string) or passed by a caller (an int
    or float): ASCII decimal, finite, in [low, high] where given.

    Args:
        text: the value; with `rigid`, the word ``rigid`` (any case) gives None.
        flag: the option or argument named in errors (``--duration``, ``duration_s``).
        low, high: inclusive bounds (None: unbounded).
        integer: the value must be a whole number (returned as int).
        unit: named in errors (``"s"``, ``"GPa"``).

    Returns:
        float (int with `integer`), or None for ``rigid``.

    Raises:
        ValueError: empty, not an ASCII decimal (``inf``, ``nan``, ``1_0``,
            ``0x10``, other scripts' digits), not whole, or out of range.
    """
    u = f" {unit}" if unit else ""
    if isinstance(text, bool):
        raise ValueError(f"{flag} must be a number{u}, got {text!r}")
    if is_real(text):
        x = float(text)
        if not math.isfinite(x):
            hint = f" (write {RIGID} for a rigid segment)" if rigid and x == math.inf else ""
            raise ValueError(f"{flag} must be a finite number{u}, got {text!r}{hint}")
    else:
        s = "" if text is None else str(text).strip()
        if not s:
            raise ValueError(f"{flag} is empty; give a number{u}")
        if rigid and s.lower() == RIGID:
            return None
        if not _DECIMAL.fullmatch(s):
            hint = f" (write {RIGID} for a rigid segment)" if rigid and "inf" in s.lower() else ""
            if s.lower().lstrip("+-") in ("inf", "infinity", "nan"):
                raise ValueError(f"{flag} must be a finite number{u}, got {text!r}{hint}")
            kind, examples = ("a whole number", "3, 12") if integer else ("a decimal number", "12, 0.5, 2e-4")
            raise ValueError(f"{flag} must be {kind}{u} (e.g. {examples}), got {text!r}{hint}")
        x = float(s)
        if not math.isfinite(x):  # 1e999
            raise ValueError(f"{flag} must be a finite number{u}, got {text!r}")
    if integer and not x.is_integer():
        raise ValueError(f"{flag} must be a whole number, got {text!r}")
    if (low is not None and x < low) or (high is not None and x > high):
        lo = "" if low is None else f"{low:g}"
        hi = "" if high is None else f"{high:g}"
        rng = f">= {lo}" if high is None else f"<= {hi}" if low is None else f"in [{lo}, {hi}]"
        raise ValueError(f"{flag} must be {rng}{u}, got {text!r}")
    return int(x) if integer else x


def url_scheme(url: str) -> str | None:
    """The scheme of `url` in lower case (RFC 3986: case-insensitive), or
    None when it has none.

    Args:
        url: the URL (read as str, blanks trimmed), e.g. ``SQLite:///x.db``.

    Returns:
        The scheme without its colon, in lower case (``sqlite``), or None
        when `url` does not start with a scheme (a letter, then letters,
        digits, ``+``, ``.`` or ``-``, then ``:``).
    """
    m = _SCHEME.match(str(url).strip())
    return m.group(1).lower() if m else None


def normalize_url(url: str) -> str:
    """`url` with its scheme in lower case (the rest as given).

    Args:
        url: the URL (read as str).

    Returns:
        `url` with blanks trimmed and its scheme (:func:`url_scheme`) in
        lower case; unchanged otherwise when it has no scheme.
    """
    url = str(url).strip()
    scheme = url_scheme(url)
    return scheme + url[len(scheme) :] if scheme else url


def check_positive(value, name: str, unit: str = "", high: float | None = None) -> float:
    """A setting that must be a finite number > 0 (and <= `high` where
    given): the one check of the package's gains, periods, durations and
    physical sizes.

    Args:
        value: the value (an int or float, NumPy scalars included; a bool or
            a string is refused).
        name: the argument's name, for the message.
        unit: its unit, for the message ("" for none).
        high: the largest accepted value, or None (default): no upper bound.

    Returns:
        The value as a float.

    Raises:
        ValueError: a bool, a non-number, nan, inf, 0, a negative value or
            one above `high`, naming `name` and the accepted range.
    """
    u = f" {unit}" if unit else ""
    rng = f"in (0, {high:g}]{u}" if high is not None else f"a finite number > 0{u}"
    ok = is_real(value)
    x = float(value) if ok else math.nan
    if not (math.isfinite(x) and x > 0 and (high is None or x <= high)):
        raise ValueError(f"{name} must be {rng}, got {value!r}")
    return x
