"""Input validation shared by the public wrappers.

Every public function checks its arguments here before any compiled kernel sees them, so a
bad value produces a ``ValueError`` that names the parameter and the allowed range instead of a
NaN, an inf or a hang deep inside Numba code.
"""

from __future__ import annotations

import math
import operator

import numpy as np

#: physical ranges fastline accepts (SI). Wide enough for every scene we know of, narrow enough
#: that no intermediate quantity over- or underflows in float64.
E_STAR_RANGE = (1.0, 1e13)  # Pa: from soft gels to diamond
LENGTH_RANGE = (1e-12, 0.1)  # m: rms roughness amplitudes
WAVENUMBER_RANGE = (1e-3, 1e13)  # 1/m: wavelengths from 6 km down to 0.6 pm
RADIUS_RANGE = (1e-9, 1e3)  # m
#: iteration caps a user may set (Newton steps, Picard sweeps, CG iterations): a solve keeps a
#: history row per step (24 bytes), and 1e6 steps is days of a large solve
MAX_ITER_RANGE = (1, 1_000_000)
#: bins per decade of a binned spectrum: 1e4 already resolves a ratio 1.00023 of wavenumbers
BINS_PER_DECADE_RANGE = (2, 10_000)


def _refuse_complex(name: str, value) -> None:
    """A TypeError for complex input (numpy would drop the imaginary part with a warning)."""
    if np.iscomplexobj(value):
        raise TypeError(f"{name} must be real, got complex values ({np.asarray(value).dtype})")


#: entries an array of numbers refuses, and how a message names them: NumPy would read True as
#: 1.0 and "1e4" as 1e4, and None as NaN (the scalar checks, :func:`finite_scalar`, refuse them)
_NOT_NUMBERS = {bool: "a bool", np.bool_: "a bool", str: "a string", bytes: "a string"}
#: array kinds (``dtype.kind``) that hold real numbers
_REAL_KINDS = "fiu"


def _refuse_entries(name: str, arr: np.ndarray) -> None:
    """A TypeError naming ``name`` for an object array holding bools, strings, None or complex
    numbers (what :func:`real_array` refuses); other entries are left to the float conversion."""
    for x in arr.flat:
        what = _NOT_NUMBERS.get(type(x))
        if what is None and x is None:
            what = "None"
        elif what is None and isinstance(x, complex | np.complexfloating):
            raise TypeError(f"{name} must be real, got complex values ({x!r})")
        if what is not None:
            raise TypeError(f"{name} must hold real numbers, not {what} ({x!r})")


def real_array(name: str, value) -> np.ndarray:
    """``value`` as a float64 array; a TypeError naming ``name`` for complex, bool, string or
    None entries (in a list, a NumPy array or alone), the array-valued twin of
    :func:`finite_scalar`'s type checks. No other check: for evaluations that accept any real
    value (the pressure laws' protocol); :func:`finite_array` adds the range checks."""
    if type(value) is np.ndarray and value.dtype.kind in _REAL_KINDS:  # the solvers' own
        return value.astype(np.float64, copy=False)
    if isinstance(value, list | tuple):  # keep each entry's type: [1e4, True] is not floats
        arr = np.array(value, dtype=object)
    else:
        arr = np.asarray(value)
    kind = arr.dtype.kind
    if kind == "O":
        _refuse_entries(name, arr)
    elif kind == "c":
        raise TypeError(f"{name} must be real, got complex values ({arr.dtype})")
    elif kind not in _REAL_KINDS:
        what = {"b": "bools", "U": "strings", "S": "strings"}.get(kind, f"{arr.dtype} values")
        raise TypeError(f"{name} must hold real numbers, not {what} ({arr.dtype})")
    try:
        return np.asarray(arr, dtype=np.float64)
    except TypeError:
        raise TypeError(f"{name} must hold real numbers, got {type(value).__name__}") from None
    except ValueError:  # a ragged nesting of sequences
        raise ValueError(f"{name} must be an array of real numbers") from None


def boolean(name: str, value) -> bool:
    """A bool (Python's or NumPy's; 0 and 1 too): a TypeError naming ``name`` otherwise (a
    string such as "no" would be truthy)."""
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if type(value) is int and value in (0, 1):
        return bool(value)
    raise TypeError(f"{name} must be True or False, got {type(value).__name__} ({value!r})")


def finite_scalar(name: str, value) -> float:
    """Return ``value`` as a float, rejecting NaN, inf, bools, complex and non-numbers."""
    _refuse_complex(name, value)
    if isinstance(value, bool | np.bool_):
        raise TypeError(f"{name} must be a real number, not a bool ({value!r})")
    if isinstance(value, str | bytes):
        raise TypeError(f"{name} must be a real number, not a string ({value!r})")
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise TypeError(
            f"{name} must be a real number, got {type(value).__name__} ({value!r})"
        ) from None
    if not math.isfinite(out):
        raise ValueError(f"{name} must be finite (not NaN or inf), got {value!r}")
    return out


def positive(name: str, value, unit: str = "") -> float:
    """A finite scalar > 0."""
    out = finite_scalar(name, value)
    if out <= 0.0:
        u = f" {unit}" if unit else ""
        raise ValueError(f"{name} must be > 0{u} (allowed range (0, inf)), got {out!r}")
    return out


def in_range(name: str, value, lo: float, hi: float, lo_open=True, hi_open=False) -> float:
    """A finite scalar inside the interval (lo, hi], brackets as given."""
    out = finite_scalar(name, value)
    ok_lo = out > lo if lo_open else out >= lo
    ok_hi = out < hi if hi_open else out <= hi
    if not (ok_lo and ok_hi):
        lb = "(" if lo_open else "["
        rb = ")" if hi_open else "]"
        raise ValueError(f"{name} must lie in {lb}{lo:g}, {hi:g}{rb}, got {out!r}")
    return out


def finite_array(name: str, value, ndim: int | None = None) -> np.ndarray:
    """A float64 array with no NaN or inf (a TypeError for complex, bool, string or None
    entries: :func:`real_array`)."""
    arr = real_array(name, value)
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-dimensional, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite values (no NaN or inf)")
    return arr


def positive_array(name: str, value) -> np.ndarray:
    """A finite float64 array whose entries are all > 0."""
    arr = finite_array(name, value)
    if np.any(arr <= 0.0):
        raise ValueError(f"{name} must be > 0 everywhere (allowed range (0, inf))")
    return arr


def integer(name: str, value, minimum: int, maximum: int | None = None, why: str = "") -> int:
    """An integer in ``[minimum, maximum]`` (bools and non-integral floats rejected);
    ``why`` explains the maximum in the message."""
    if not isinstance(value, bool | np.bool_):
        try:
            out = operator.index(value)
        except TypeError:
            out = None
        if out is not None and out >= minimum and (maximum is None or out <= maximum):
            return out
    bound = f">= {minimum}" if maximum is None else f"in [{minimum}, {maximum}]"
    raise ValueError(f"{name} must be an integer {bound}{why}, got {value!r}")


def in_span(name: str, value, span: tuple[float, float], unit: str) -> float:
    """A finite scalar inside the closed interval ``span`` (with its unit in the message)."""
    out = finite_scalar(name, value)
    lo, hi = span
    if not lo <= out <= hi:
        raise ValueError(f"{name} must lie in [{lo:g}, {hi:g}] {unit}, got {out!r}")
    return out
