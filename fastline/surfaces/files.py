"""Height profiles and maps from files: text, ``.npy`` and instrument formats.

Text and ``.npy`` files are read here (the tolerant table reader of
:mod:`fastline.surfaces.read`); instrument formats through the optional SurfaceTopography.
Heights and spacings are returned in m, whatever the file's units.
"""

from __future__ import annotations

import math
import os
from typing import NamedTuple

import numpy as np

from fastline._lib.validate import positive
from fastline.surfaces.heights import MIN_POINTS
from fastline.surfaces.read import read_table

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


def _unit(name: str, unit) -> float:
    if unit not in UNITS:
        raise ValueError(f"{name} must be one of {', '.join(UNITS)}, got {unit!r}")
    return UNITS[unit]


def _uniform_spacing(x: np.ndarray, path: str) -> float:
    """dx of positions x that must lie on a uniform grid (to 1 % of dx)."""
    j = np.arange(x.size)
    slope, offset = np.polyfit(j, x, 1)
    if slope == 0.0:
        raise ValueError(f"{path}: the x column is constant")
    worst = float(np.max(np.abs(x - (offset + slope * j)))) / abs(slope)
    if worst > 0.01:
        raise ValueError(
            f"{path}: x is not uniformly spaced (a point lies {worst:.2g} spacings off the "
            "uniform grid): resample the profile onto a uniform grid first"
        )
    return abs(float(slope))


def _surfacetopography(path: str):
    """(dimension, heights in m, spacings in m) of an instrument file, via SurfaceTopography."""
    try:
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


def _load(path, *, dx, unit, x_unit, kind):
    """(dimension, heights, spacings) from a text, .npy or instrument file (kind: profile,
    map or None for either)."""
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if not os.path.exists(path):
        raise FileNotFoundError(f"no such file: {path}")
    if ext not in _TEXT + _NUMPY:
        return _surfacetopography(path)
    scale = _unit("unit", unit)
    scale_x = _unit("x_unit", unit if x_unit is None else x_unit)
    data = np.load(path, allow_pickle=False) if ext in _NUMPY else read_table(path)[0]
    data = np.asarray(data, dtype=np.float64)
    columns = 1 if data.ndim == 1 else data.shape[1]
    if kind != "map" and data.ndim == 2 and columns > 2:
        _refuse_columns(path, columns, traces=kind is None)
    if kind == "map" or (kind is None and data.ndim == 2 and columns > 2):
        if data.ndim != 2 or min(data.shape) < 2:
            raise ValueError(f"{path}: a map needs a 2D array of heights, got shape {data.shape}")
        if dx is None:
            raise ValueError(f"{path}: a height map from a text or .npy file needs dx (m)")
        return 2, data * scale, (dx, None)
    if columns == 1:
        if dx is None:
            raise ValueError(f"{path}: one column of heights: dx (m) is required")
        return 1, data.ravel() * scale, (dx,)
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
    unit: str = "m",
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
    unit, x_unit : str
        Units of the file's height and x columns (``"m"``, ``"mm"``, ``"um"``, ``"nm"``, ...;
        x_unit defaults to unit). Ignored for instrument files.

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
    path: str | os.PathLike, *, dx: float | None = None, dy: float | None = None, unit: str = "m"
) -> Map:
    """Read a height map (heights converted to m), rows along x.

    Text (one row of heights per line) or ``.npy`` (2D array) with ``dx`` (and ``dy``, default
    dx) in m; any other extension via SurfaceTopography as :func:`read_profile`.

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
    unit: str = "m",
    x_unit: str | None = None,
) -> Profile | Map:
    """A :class:`Profile` or a :class:`Map`, whichever the file holds (text or ``.npy`` with
    one or two columns is a profile, more columns a map; see :func:`read_profile`)."""
    dx = None if dx is None else positive("dx", dx, "m")
    dim, h, spacing = _load(path, dx=dx, unit=unit, x_unit=x_unit, kind=None)
    if dim == 1:
        return Profile(h, spacing[0])
    return Map(h, spacing[0], spacing[1] if spacing[1] is not None else spacing[0])
