"""Height profiles and maps from files: text, ``.npy`` and instrument formats.

Text and ``.npy`` files are read here (the tolerant table reader of
:mod:`fastline.surfaces.read`); instrument formats through the optional SurfaceTopography.
Heights and spacings are returned in m, whatever the file's units.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import stat
import warnings
from typing import NamedTuple

import numpy as np

from fastline._lib.validate import positive
from fastline.surfaces.heights import MIN_POINTS, topography_warning
from fastline.surfaces.read import parse_table, split_fields

_INSTALL = 'pip install "fastline-contact[topography]" (the optional SurfaceTopography)'


class Profile(NamedTuple):
    """A line scan: heights (N,) in m and their spacing dx in m."""

    heights: np.ndarray
    dx: float


class Map(NamedTuple):
    """A height map: heights (Ny, Nx) in m (rows along x) and the spacings dx, dy in m."""

    heights: np.ndarray
    dx: float
    dy: float


#: length units fastline converts (factor to m)
UNITS = {
    "m": 1.0,
    "mm": 1e-3,
    "um": 1e-6,
    "µm": 1e-6,
    "μm": 1e-6,
    "micron": 1e-6,
    "nm": 1e-9,
    "A": 1e-10,
    "Å": 1e-10,
    "pm": 1e-12,
}
_TEXT = (".txt", ".csv", ".dat", ".tsv", ".prn")
_NUMPY = (".npy",)


#: unit words of column headers ("Height [um]", "x (mm)", "Lateral um", "Raw Micrometer"), to
#: the keys of UNITS
_UNIT_WORDS = {
    **{u.lower(): u for u in ("m", "mm", "um", "nm", "pm")},
    **dict.fromkeys(("µm", "μm", "micron", "microns", "micrometer", "micrometers"), "um"),
    **dict.fromkeys(("micrometre", "micrometres", "mu"), "um"),
    **dict.fromkeys(("meter", "meters", "metre", "metres"), "m"),
    **dict.fromkeys(("millimeter", "millimeters", "millimetre", "millimetres"), "mm"),
    **dict.fromkeys(("nanometer", "nanometers", "nanometre", "nanometres"), "nm"),
    **dict.fromkeys(("å", "angstrom", "angstroms"), "A"),
}
_BRACKETED = re.compile(r"[\[(]\s*([^\[\]()]+?)\s*[\])]")


def _unit(name: str, unit) -> float:
    if unit not in UNITS:
        raise ValueError(f"{name} must be one of {', '.join(UNITS)}, got {unit!r}")
    return UNITS[unit]


def _holds_number(text: str) -> bool:
    """Whether a header field holds a number of its own ("dx = 0.5 um", "--dx 1e-6 --units
    um"): a scan parameter or a sentence, not a column's name ("h1" is a name)."""
    for token in re.split(r"[\s,;=:()\[\]]+", text):
        try:
            float(token)
        except ValueError:
            continue
        if any(c.isdigit() for c in token):
            return True
    return False


def _field_unit(field: str) -> str | None:
    """The unit a column header names: in brackets, or as its last word (a name without
    numbers: "Lateral um", not "dx 0.5 um"), or None."""
    found = _BRACKETED.search(field)
    if found:
        return _UNIT_WORDS.get(found.group(1).strip().lower())
    if _holds_number(field):
        return None
    for word in reversed(re.split(r"[\s_/:]+", field.strip())):
        if word.lower() in _UNIT_WORDS:
            return _UNIT_WORDS[word.lower()]
    return None


def header_units(header: list[str], columns: int) -> tuple[list[str | None], str]:
    """The unit of each of ``columns`` columns from the last header lines that name units (a
    names line "x [um], h [nm]" or a units line "um nm"), and that line; Nones and "" when
    the header names none."""
    for line in reversed(header[-3:]):
        text = line.lstrip("#").strip()
        fields = split_fields(text)
        while fields and not fields[-1]:
            fields.pop()
        if len(fields) not in (columns, columns + 1):  # names with blanks: "x [um]  h [nm]"
            found = _BRACKETED.findall(text)
            fields = [f"[{f}]" for f in found] if found else re.split(r"\s{2,}", text)
        if len(fields) not in (columns, columns + 1):
            continue
        units = [_field_unit(f) for f in fields[-columns:]]
        if any(units):
            return units, line
    return [None] * columns, ""


def _index_column(rows: np.ndarray) -> bool:
    """Whether the first of three or more columns counts the rows (0, 1, 2, ... or 1, 2, ...)."""
    if rows.shape[1] < 3 or rows.shape[0] < 2:
        return False
    first = rows[:, 0]
    return bool(first[0] in (0.0, 1.0) and np.array_equal(first, first[0] + np.arange(first.size)))


class _Columns(NamedTuple):
    """A text table as a scan: its rows (the index column dropped), the unit of each column
    from the header (None where it names none) and the header line that named them."""

    rows: np.ndarray
    units: list
    named_in: str


def _text_columns(path: str) -> _Columns:
    """The numeric block of a text file, its index column dropped, with the header's units
    (one trace per line and maps: the unit a header names once is that of every column)."""
    table = parse_table(path)
    rows = table.rows
    units, line = header_units(table.header, rows.shape[1])
    if _index_column(rows):
        rows, units = rows[:, 1:], units[1:]
    if rows.shape[1] > 2 and not any(units):  # traces or a map: every column holds heights,
        (unit,), line = header_units(table.header, 1)  # named once ("Height [um]")
        units = [None] * (rows.shape[1] - 1) + [unit]
    return _Columns(rows, units, line)


def _resolve(name: str, given, from_file, line: str, fallback: str) -> str:
    """A column's unit: the file's header and the option must agree; either alone decides."""
    if given is not None:
        _unit(name, given)
    if given is not None and from_file is not None and UNITS[given] != UNITS[from_file]:
        flag, what = {"unit": ("--units", "the heights"), "x_unit": ("--x-units", "x")}[name]
        raise ValueError(
            f"{name}={given!r} ({flag} {given}) contradicts the file, whose header gives "
            f"{what} in {from_file} ({line.strip()!r}): leave {name} out, or correct the header"
        )
    return from_file or given or fallback


def unit_advice(path, unit) -> str:
    """The unit a file's heights were read in, what set it (``unit``, the header, neither) and
    how to give the right one, in words: the end of a message about implausible heights."""
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext not in _TEXT + _NUMPY:
        return "they were read in the units the file names; check them in the instrument's export"
    if unit is not None:
        return (
            f"they were read in {unit} (unit={unit!r}, --units {unit}); give the unit the "
            "file's heights are in"
        )
    named, line = None, ""
    if ext in _TEXT:
        with contextlib.suppress(ValueError, OSError):
            columns = _text_columns(path)
            named, line = columns.units[-1], columns.named_in.strip()
    if named is not None:
        return (
            f"they were read in {named}, the unit the file's header names ({line!r}); correct "
            "the header if the heights are in another unit"
        )
    return (
        "they were read in m, neither unit= (--units) nor the file's header naming their unit; "
        "give the unit the file's heights are in, e.g. unit='um' (--units um)"
    )


def _uniform_spacing(x: np.ndarray, path: str) -> float:
    """dx of positions x that must lie on a uniform grid (to 1 % of dx)."""
    n = x.size
    centre, mean = 0.5 * (n - 1), float(np.mean(x))
    line = np.arange(n, dtype=np.float64)  # j, then the residual of the straight line
    slope = (float(np.dot(line, x)) - centre * mean * n) / (n * (n * n - 1.0) / 12.0)
    if slope == 0.0:
        raise ValueError(f"{path}: the x column is constant")
    line *= -slope
    line += x
    line -= mean - slope * centre
    worst = max(abs(float(line.max())), abs(float(line.min()))) / abs(slope)
    if worst > 0.01:
        raise ValueError(
            f"{path}: x is not uniformly spaced (a point lies {worst:.2g} spacings off the "
            "uniform grid): resample the profile onto a uniform grid first"
        )
    return abs(float(slope))


def file_path(path, name: str = "path") -> str:
    """``path`` as a string: a TypeError naming ``name`` for anything but a file name (str or
    os.PathLike)."""
    if not isinstance(path, str | os.PathLike):
        raise TypeError(
            f"{name} must be a file name (str or os.PathLike), got {type(path).__name__} ({path!r})"
        )
    return os.fspath(path)


def refuse_empty(path: str) -> None:
    """A ValueError for a file that holds nothing to read: 0 bytes, or not a regular file (a
    device such as /dev/null, a pipe: no reader can take heights from it); a directory too."""
    mode = os.stat(path).st_mode
    if stat.S_ISDIR(mode):
        raise ValueError(f"{path} is a directory, not a file")
    if not stat.S_ISREG(mode):
        raise ValueError(f"{path} is empty: not a regular file of heights (a device or a pipe)")
    if os.path.getsize(path) == 0:
        raise ValueError(f"{path} is empty (0 bytes): no heights to read")


def _surfacetopography(path: str):
    """(dimension, heights in m, spacings in m) of an instrument file, via SurfaceTopography."""
    try:
        with warnings.catch_warnings():  # its parallel backend's note says nothing to a user
            warnings.filterwarnings("ignore", "Could not import mpi4py", ImportWarning)
            import SurfaceTopography
    except ImportError:
        raise ImportError(
            f"reading {os.path.splitext(path)[1] or 'these'} files needs {_INSTALL}"
        ) from None
    topo = SurfaceTopography.read_topography(path)
    if not getattr(topo, "is_uniform", True):
        raise ValueError(f"{path}: a non-uniform line scan; resample it onto a uniform grid")
    unit = topo.unit
    if unit in UNITS:
        factor = UNITS[unit]
    else:
        from SurfaceTopography.Support.UnitConversion import get_unit_conversion_factor

        factor = get_unit_conversion_factor(unit, "m")
    heights = np.ma.filled(np.ma.asarray(topo.heights(), dtype=np.float64), np.nan) * factor
    sizes = np.atleast_1d(topo.physical_sizes) * factor
    points = np.atleast_1d(topo.nb_grid_pts)
    if topo.dim == 1:
        return 1, heights, (float(sizes[0] / points[0]),)
    return 2, heights.T, (float(sizes[0] / points[0]), float(sizes[1] / points[1]))


def _refuse_columns(path: str, columns: int, traces: bool) -> None:
    """Refuse a table of more than two columns read as a line scan, unless it can be one trace
    per line (``traces``, :func:`read_topography`) with at least MIN_POINTS heights each."""
    if traces and columns >= MIN_POINTS:
        return
    other = (
        f"; one trace per line needs at least {MIN_POINTS} heights per line"
        if traces
        else "; a height map: read_map"
    )
    raise ValueError(
        f"{path}: expected 1 column (heights, with dx) or 2 columns (x, height), got {columns}"
        + other
    )


#: what fastline's own text reader understands, for the message when a file defeats it
_LAYOUTS = (
    "one column of heights, two columns (x, h) or one scan per line; separated by commas, "
    "semicolons, tabs or blanks, decimal commas with semicolons, tabs or blanks; header lines, "
    "blocks of parameters, a names or units line and a count line before the data; an index "
    "column; trailing separators; UTF-8 or UTF-16 with or without a byte-order mark"
)


def _text_or_instrument(path: str) -> _Columns | tuple:
    """The columns of a text file (fastline's reader), or, when that fails, what
    SurfaceTopography reads of it (when installed); a ValueError naming the layouts tried."""
    try:
        columns = _text_columns(path)
        if columns.rows.shape[1] <= 2 or columns.rows.shape[1] >= MIN_POINTS:
            return columns
        own = (
            f"expected 1 column (heights, with dx) or 2 columns (x, height), got "
            f"{columns.rows.shape[1]}; one trace per line needs at least {MIN_POINTS} heights "
            "per line"
        )
    except ValueError as e:
        own = str(e)
    try:
        return _surfacetopography(path)
    except ImportError:
        other = f"SurfaceTopography's readers were not tried ({_INSTALL})"
    except Exception as e:  # noqa: BLE001 - any failure of the optional reader: say it
        first = str(e).strip().splitlines()[0] if str(e).strip() else ""
        other = f"SurfaceTopography's readers could not read it either ({type(e).__name__}"
        other += f": {first[:120]})" if first else ")"
    raise ValueError(f"{path}: cannot read it as a scan: {own}. Layouts tried: {_LAYOUTS}; {other}")


def _scales(path, columns: _Columns, unit, x_unit) -> tuple[float, float]:
    """Factors to m of the height and x columns: the header's units and the options agree, or
    one of them decides; x without either follows the heights, said once."""
    units, line = columns.units, columns.named_in
    h_unit = _resolve("unit", unit, units[-1], line, "m")
    if columns.rows.shape[1] != 2:
        return UNITS[h_unit], UNITS[h_unit]
    if x_unit is None and units[0] is None and h_unit != "m":
        topography_warning(
            f"{path}: the x column is taken in {h_unit}, like the heights: the header names no "
            "unit for it and x_unit (--x-units) was not given",
        )
    return UNITS[h_unit], UNITS[_resolve("x_unit", x_unit, units[0], line, h_unit)]


def _array(path: str, ext: str, unit, x_unit):
    """(array, height scale, x scale) of a text or .npy file (a text file that fastline cannot
    read goes to SurfaceTopography: then a ``(dim, heights, spacings)`` tuple)."""
    if ext in _NUMPY:
        data = np.load(path, allow_pickle=False)
        if data.dtype.kind == "c":
            raise ValueError(
                f"{path}: the array holds complex numbers ({data.dtype}): heights are real "
                "(take the real part or the modulus yourself if that is what was measured)"
            )
        if data.dtype.kind not in "fiu":
            raise ValueError(f"{path}: the array holds {data.dtype} values, not heights")
        h_unit = "m" if unit is None else unit
        x_scale = _unit("x_unit", h_unit if x_unit is None else x_unit)
        return np.asarray(data, dtype=np.float64), _unit("unit", h_unit), x_scale
    columns = _text_or_instrument(path)
    if not isinstance(columns, _Columns):
        return columns, None, None
    return columns.rows, *_scales(path, columns, unit, x_unit)


def _load(path, *, dx, unit, x_unit, kind):
    """(dimension, heights, spacings) from a text, .npy or instrument file (kind: profile,
    map or None for either)."""
    path = file_path(path)
    ext = os.path.splitext(path)[1].lower()
    if not os.path.exists(path):
        raise FileNotFoundError(f"no such file: {path}")
    refuse_empty(path)
    if ext not in _TEXT + _NUMPY:
        return _surfacetopography(path)
    data, scale, scale_x = _array(path, ext, unit, x_unit)
    if scale is None:
        return data
    columns = 1 if data.ndim == 1 else data.shape[1]
    if kind != "map" and data.ndim == 2 and columns > 2:
        _refuse_columns(path, columns, traces=kind is None)
    if kind == "map" or (kind is None and data.ndim == 2 and columns > 2):
        if data.ndim != 2 or min(data.shape) < 2:
            raise ValueError(f"{path}: a map needs a 2D array of heights, got shape {data.shape}")
        if dx is None:
            raise ValueError(f"{path}: a height map from a text or .npy file needs dx (m)")
        _no_x_column(path, x_unit, "rows of heights (traces or a map)")
        return 2, _scaled(data, scale), (dx, None)
    if columns == 1:
        if dx is None:
            raise ValueError(f"{path}: one column of heights: dx (m) is required")
        _no_x_column(path, x_unit, "one column of heights")
        return 1, _scaled(data.ravel(), scale), (dx,)
    return _xh_profile(path, data, scale, scale_x, dx)


def _no_x_column(path, x_unit, what: str) -> None:
    """Refuse a unit of positions for a file that holds none (its spacing is dx, in m)."""
    if x_unit is not None:
        raise ValueError(
            f"{path}: x_unit (--x-units) sets the unit of an x column; this file holds {what} "
            "without one (its spacing is dx, in m)"
        )


def _scaled(h: np.ndarray, scale: float) -> np.ndarray:
    """Heights times their unit's factor, in place (they are the reader's own array)."""
    if scale != 1.0:
        h *= scale
    return h


def _xh_profile(path, data, scale, scale_x, dx):
    """(1, heights, (dx,)) of a two-column (x, h) table."""
    x, h = data[:, 0] * scale_x, data[:, 1] * scale
    if np.any(np.isnan(x)):
        raise ValueError(f"{path}: the x column has missing values")
    if x[-1] < x[0]:
        x, h = x[::-1], h[::-1]
    spacing = _uniform_spacing(x, path)
    if dx is not None and not math.isclose(dx, spacing, rel_tol=0.01):
        raise ValueError(f"{path}: dx = {dx:g} m disagrees with the file's spacing {spacing:g} m")
    return 1, h, (spacing,)


def read_profile(
    path: str | os.PathLike,
    *,
    dx: float | None = None,
    unit: str | None = None,
    x_unit: str | None = None,
) -> Profile:
    """Read a line scan (heights converted to m).

    Text (``.txt``, ``.csv``, ``.dat``, ``.tsv``, ``.prn``: header lines skipped; comma,
    semicolon, tab or blank separated): two columns x, h (x must be uniform to 1 % of its
    spacing) or one column h with ``dx``. ``.npy``: an (N,) array of heights with ``dx`` or an
    (N, 2) array x, h. Any other extension: an instrument file read by SurfaceTopography
    (X3P, SDF, Dektak OPDx, Mitutoyo, Keyence VK, Zygo, Sensofar PLU, ...; units from the file),
    which needs ``pip install "fastline-contact[topography]"``.

    Parameters
    ----------
    path : str or path-like
    dx : float, optional
        Spacing in m (required for a single column of heights).
    unit, x_unit : str, optional
        Units of the file's height and x columns (``"m"``, ``"mm"``, ``"um"``, ``"nm"``, ...).
        Default: the units the header names ("Height [um]", "x (mm)", "Lateral um", a units
        line), else m for the heights and the heights' unit for x (said by a
        TopographyWarning). An option that contradicts the header is refused by name.
        Ignored for instrument files, which carry their own.

    Returns
    -------
    Profile
        ``heights`` (m, NaN where the file has none) and ``dx`` (m).
    """
    dx = None if dx is None else positive("dx", dx, "m")
    dim, h, spacing = _load(path, dx=dx, unit=unit, x_unit=x_unit, kind="profile")
    if dim != 1:
        raise ValueError(f"{os.fspath(path)}: holds a map of shape {h.shape}; use read_map")
    return Profile(h, spacing[0])


def read_map(
    path: str | os.PathLike,
    *,
    dx: float | None = None,
    dy: float | None = None,
    unit: str | None = None,
) -> Map:
    """Read a height map (heights converted to m), rows along x.

    Text (one row of heights per line) or ``.npy`` (2D array) with ``dx`` (and ``dy``, default
    dx) in m; any other extension via SurfaceTopography as :func:`read_profile`.

    Parameters
    ----------
    path : str or path-like
    dx, dy : float, optional
        Spacings in m along the rows and between them (a text or ``.npy`` map needs dx).
    unit : str, optional
        Unit of the heights (``"m"``, ``"um"``, ``"nm"``, ...). Default: the unit the header
        names ("Height [um]"), else m; an option that contradicts the header is refused.

    Returns
    -------
    Map
        ``heights`` (Ny, Nx) in m, ``dx``, ``dy`` in m.
    """
    dx = None if dx is None else positive("dx", dx, "m")
    dim, h, spacing = _load(path, dx=dx, unit=unit, x_unit=None, kind="map")
    if dim != 2:
        raise ValueError(f"{os.fspath(path)}: holds a line scan; use read_profile")
    sx = spacing[0]
    sy = spacing[1] if spacing[1] is not None else (sx if dy is None else positive("dy", dy, "m"))
    return Map(h, sx, sy)


def read_topography(
    path: str | os.PathLike,
    *,
    dx: float | None = None,
    unit: str | None = None,
    x_unit: str | None = None,
) -> Profile | Map:
    """A :class:`Profile` or a :class:`Map`, whichever the file holds (text or ``.npy`` with
    one or two columns is a profile, more columns a map; see :func:`read_profile`)."""
    dx = None if dx is None else positive("dx", dx, "m")
    dim, h, spacing = _load(path, dx=dx, unit=unit, x_unit=x_unit, kind=None)
    if dim == 1:
        return Profile(h, spacing[0])
    return Map(h, spacing[0], spacing[1] if spacing[1] is not None else spacing[0])
