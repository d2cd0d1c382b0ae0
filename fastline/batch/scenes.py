"""The scene table of :func:`fastline.sweep`: its columns, the geometries a scene may have,
checking and completing a table before any work (:func:`normalise`) and reading one from a CSV
file (:func:`read_scenes`).

The columns (:data:`SCENE_COLUMNS`), one scene per row. Required: ``E_star`` [Pa], ``radius``
[m], ``load`` (N/m for a cylinder, N for a sphere) and the spectrum: either ``h_rms`` [m],
``hurst``, ``q0``, ``qr``, ``q1`` [1/m] (a :class:`~fastline.SelfAffinePSD`) or ``psd`` (a PSD
object, the path of a spectrum file read by :func:`fastline.io.read_spectrum` on the worker, or
None for ``model="hertz"``). Optional, with defaults: ``label`` (""), ``geometry``
("cylinder", the default, or "sphere": :data:`GEOMETRIES`), ``model`` ("persson",
"exponential", "hertz"), ``law`` (a :class:`~fastline.TabulatedLaw`, a
:class:`~fastline.CalibratedLaw` or the path of a law file, in place of the model: the row's
model becomes the law's kind, "tabulated" or "calibrated"; :mod:`fastline.batch.laws`),
``method`` ("newton", "picard"), ``n`` (the geometry's own: 1024 grid
points for a cylinder, 512 cells for a sphere; the table shows the value used), ``variant`` of
the theory's u(p) ("yang-persson-energy", the default, "yang-persson-printed" or
"wang-mueser"; :mod:`fastline.theory.variants`), ``gamma`` (the variant's own: 0.45, 5/9 for
"wang-mueser"; the table shows the value used), ``tol`` (1e-8), ``max_iter`` (0: the method's
default), ``hardness`` [Pa] (NaN: none). A missing cell (None, NaN) in an optional column takes
the default.

Each scene is solved as ``LineContact(psd, E_star, radius, model=..., variant=...,
...).solve(load)`` would (``PointContact`` for a sphere; with a law, ``model=law`` and the
spectrum's theory for the diagnostics, as ``fastline profile --law`` solves), its values
checked there (a bad value, a calibrated law made for another spectrum or E*, fails that scene
only). Scenes of either geometry that share a spectrum, E*, gamma and variant
share one Persson theory per worker. The table's shape and types (column names, value types,
geometry/model/method/variant names, a law beside another model) are checked here, before any
work, and raise.

SI units throughout: m, 1/m, Pa; loads in N/m (per unit length) for a cylinder, in N (the
total load) for a sphere.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from fastline.batch.laws import law_cell, law_csv_cell, law_kind
from fastline.contact.line import LineContact
from fastline.contact.point import PointContact
from fastline.theory.lawdata import LAW_KINDS
from fastline.theory.spectra import PSD
from fastline.theory.variants import DEFAULT_VARIANT, VARIANTS

__all__ = ["read_scenes", "SCENE_COLUMNS", "RESULT_COLUMNS", "GEOMETRIES", "LOAD_UNITS"]


# ----------------------------------------------------------------------------------------------
# the table's columns
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Column:
    """One column: name, kind (float, int, bool, text, psd), unit and default (None: required;
    ``_SPECTRUM``: required unless the spectrum is given by a ``psd`` column)."""

    name: str
    kind: str
    unit: str = ""
    default: object = None

    @property
    def csv_name(self) -> str:
        """Name in CSV files: the unit appended (``load_N_per_m``), as in :mod:`fastline.io`."""
        suffix = self.unit.replace("/", "_per_")
        return f"{self.name}_{suffix}" if self.unit and self.unit != "-" else self.name


_SPECTRUM = object()  # default marker of the self-affine spectrum columns
_ABSENT = object()  # default marker of a column left out of the table when not given (law)
_BY_GEOMETRY = object()  # default marker of a column whose default depends on the geometry
SPECTRUM_PARAMS = ("h_rms", "hurst", "q0", "qr", "q1")

#: input columns; ``default`` None means required
INPUTS = (
    Column("label", "text", default=""),
    Column("geometry", "text", default="cylinder"),
    Column("h_rms", "float", "m", _SPECTRUM),
    Column("hurst", "float", "-", _SPECTRUM),
    Column("q0", "float", "1/m", _SPECTRUM),
    Column("qr", "float", "1/m", _SPECTRUM),
    Column("q1", "float", "1/m", _SPECTRUM),
    Column("psd", "psd", default=_SPECTRUM),
    Column("E_star", "float", "Pa"),
    Column("radius", "float", "m"),
    Column("load", "float", "N/m"),  # N for a sphere (_load_csv_name)
    Column("model", "text", default="persson"),
    Column("law", "law", default=_ABSENT),
    Column("method", "text", default="newton"),
    Column("n", "int", default=_BY_GEOMETRY),  # the geometry's own (_GEOMETRY_N)
    Column("gamma", "float", "-", math.nan),  # NaN: the variant's own (normalise)
    Column("variant", "text", default=DEFAULT_VARIANT),
    Column("tol", "float", "-", 1e-8),
    Column("max_iter", "int", default=0),
    Column("hardness", "float", "Pa", math.nan),
)
#: result columns added to the inputs
OUTPUTS = (
    Column("p0", "float", "Pa"),
    Column("p0_ratio", "float", "-"),
    Column("s", "float", "m"),
    Column("fwhm", "float", "m"),
    Column("w_over_s", "float", "-"),
    Column("alpha", "float", "-"),
    Column("converged", "bool"),
    Column("iterations", "int"),
    Column("convolutions", "int"),
    Column("residual", "float", "-"),
    Column("warnings", "text"),
    Column("error", "text"),
)
BY_NAME = {c.name: c for c in INPUTS + OUTPUTS}
#: names of the scene columns (``psd`` or the five self-affine parameters give the spectrum)
SCENE_COLUMNS = tuple(c.name for c in INPUTS)
#: names of the result columns of a :class:`SweepTable` (after the scene columns)
RESULT_COLUMNS = tuple(c.name for c in OUTPUTS)
_REQUIRED = tuple(c.name for c in INPUTS if c.default is None)
NUMERIC_RESULTS = RESULT_COLUMNS[:10]  # p0 ... residual, in the order workers return them
_MODELS = ("persson", "exponential", "hertz")
#: model names of the rows with a law (the law's kind: its file or object sets it)
LAW_MODELS = tuple(LAW_KINDS)
_METHODS = ("newton", "picard")
NEEDS_THEORY = ("persson", "exponential")


# ----------------------------------------------------------------------------------------------
# geometries: how a model of a scene is built
# ----------------------------------------------------------------------------------------------
def _cylinder(spec, psd, theory):
    return LineContact(
        psd,
        spec.E_star,
        spec.radius,
        model=spec.model,
        method=spec.method,
        gamma=spec.gamma,
        variant=spec.variant,
        n=spec.n,
        tol=spec.tol,
        max_iter=spec.max_iter,
        theory=theory,
        hardness=spec.hardness,
        warn=False,
    )


def _sphere(spec, psd, theory):
    return PointContact(
        psd,
        spec.E_star,
        spec.radius,
        model=spec.model,
        method=spec.method,
        gamma=spec.gamma,
        variant=spec.variant,
        n=spec.n,
        tol=spec.tol,
        max_iter=spec.max_iter,
        theory=theory,
        hardness=spec.hardness,
        warn=False,
    )


#: ``geometry`` column value -> builder ``(spec, psd, theory) -> model`` of a model with
#: ``solve(load)`` and ``sweep(loads)`` returning results with p0, p0_ratio, s, fwhm, w_over_s,
#: alpha, converged, iterations, convolutions, residual and ``diagnostics``
GEOMETRIES = {"cylinder": _cylinder, "sphere": _sphere}
#: default ``n`` of each geometry: the model's own default (LineContact 1024, PointContact 512)
_GEOMETRY_N = {"cylinder": 1024, "sphere": 512}
#: unit of the ``load`` column for each geometry
LOAD_UNITS = {"cylinder": "N/m", "sphere": "N"}
_CATEGORIES = {
    "geometry": GEOMETRIES,
    "model": _MODELS + LAW_MODELS,
    "method": _METHODS,
    "variant": VARIANTS,
}


# ----------------------------------------------------------------------------------------------
# reading and checking the table (before any work)
# ----------------------------------------------------------------------------------------------
def _columns_of(scenes) -> dict[str, list]:
    """Column name -> list of cells, from any of the accepted table forms."""
    if isinstance(scenes, np.ndarray):
        if scenes.dtype.names is None or scenes.ndim != 1:
            raise TypeError("scenes as an array must be a 1-D NumPy structured array")
        return {name: scenes[name].tolist() for name in scenes.dtype.names}
    if hasattr(scenes, "columns") and hasattr(scenes, "to_dict"):  # a pandas DataFrame
        return {name: scenes[name].tolist() for name in scenes.columns}
    if isinstance(scenes, Mapping):
        for name, cells in scenes.items():
            if isinstance(cells, str | bytes) or not isinstance(cells, Iterable):
                raise TypeError(
                    f"scenes: column {name!r} of a dict of columns must be a sequence of cells, "
                    f"one per scene; got {type(cells).__name__} ({cells!r}): repeat a value "
                    "shared by every scene, e.g. [value] * len(loads)"
                )
        cols = {k: list(v) for k, v in scenes.items()}
        if len({len(v) for v in cols.values()}) > 1:
            raise ValueError("scenes: every column of a dict of columns must have the same length")
        return cols
    if isinstance(scenes, Iterable) and not isinstance(scenes, str | bytes):
        return _columns_of_rows(list(scenes))
    raise TypeError(
        "scenes must be a list of dicts, a dict of columns, a NumPy structured array or a "
        f"pandas DataFrame, got {type(scenes).__name__}"
    )


def _columns_of_rows(rows: list) -> dict[str, list]:
    for i, row in enumerate(rows):
        if not isinstance(row, Mapping):
            raise TypeError(f"scenes: row {i} must be a dict, got {type(row).__name__}")
    names = list(dict.fromkeys(k for row in rows for k in row))
    for name in _REQUIRED:
        missing = [i for i, row in enumerate(rows) if name in names and name not in row]
        if missing:
            raise ValueError(f"scenes: column {name!r} is missing in rows {few(missing)}")
    return {name: [row.get(name) for row in rows] for name in names}


def few(rows: Sequence[int], k: int = 5) -> str:
    return ", ".join(str(r) for r in rows[:k]) + (" ..." if len(rows) > k else "")


def _check_names(cols: Mapping) -> None:
    """Unknown and missing columns, and exactly one way of giving the spectrum."""
    bad = [k for k in cols if not isinstance(k, str)]
    unknown = [k for k in cols if k not in BY_NAME or k in RESULT_COLUMNS]
    if bad or unknown:
        raise ValueError(
            f"scenes: unknown columns {sorted(map(str, bad + unknown))}; allowed: "
            f"{', '.join(SCENE_COLUMNS)}"
        )
    if not cols or not len(next(iter(cols.values()))):
        raise ValueError("scenes must hold at least one scene")
    missing = [k for k in _REQUIRED if k not in cols]
    given = [k for k in SPECTRUM_PARAMS if k in cols]
    if "psd" in cols and given:
        raise ValueError(
            f"scenes: give the spectrum either as a psd column or as {', '.join(SPECTRUM_PARAMS)}"
            f", not both (got psd and {', '.join(given)})"
        )
    if "psd" not in cols:
        missing += [k for k in SPECTRUM_PARAMS if k not in cols]
    if missing:
        raise ValueError(
            f"scenes: missing columns {missing}; the spectrum needs a psd column (PSD objects or "
            f"spectrum files) or all of {', '.join(SPECTRUM_PARAMS)}"
        )


def _is_missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _cell(col: Column, i: int, v):
    """One cell converted to its column's type; TypeError naming the column and row."""
    if col.kind == "law":
        return law_cell(i, v)
    optional = col.default is not None and col.default is not _SPECTRUM
    if optional and _is_missing(v):
        return col.default
    if v is None and col.kind != "psd":
        raise ValueError(f"scenes: column {col.name!r} has no value in row {i}")
    if col.kind == "float":
        if isinstance(v, bool | np.bool_) or not isinstance(v, int | float | np.number):
            _type_error(col, i, v, "a real number")
        return float(v)
    if col.kind == "int":
        if isinstance(v, bool | np.bool_) or not isinstance(v, int | float | np.number):
            _type_error(col, i, v, "an integer")
        if not float(v).is_integer():
            _type_error(col, i, v, "an integer")
        return int(v)
    if col.kind == "text":
        if col.name == "model" and not isinstance(v, str):
            _type_error(col, i, v, _NOT_A_LAW)
        if not isinstance(v, str):
            _type_error(col, i, v, "a string")
        return str(v)
    return _psd_cell(col, i, v)


def _psd_cell(col: Column, i: int, v):
    if v is None or isinstance(v, PSD):
        return v
    if isinstance(v, str | os.PathLike):
        return os.path.abspath(os.fspath(v))
    _type_error(col, i, v, "a fastline PSD, the path of a spectrum file, or None")


#: why a law object is refused in the model column, and what to do instead
_NOT_A_LAW = (
    f"a model name {_MODELS} (a TabulatedLaw, a CalibratedLaw or a law file goes in the law "
    "column; a law of your own is solved in this process: LineContact(psd, E_star, radius, "
    "model=law).sweep(loads), PointContact for a sphere)"
)


def _type_error(col: Column, i: int, v, what: str):
    raise TypeError(
        f"scenes: column {col.name!r} must hold {what}; row {i} holds {v!r} ({type(v).__name__})"
    )


def _check_category(name: str, values: list) -> None:
    allowed = tuple(_CATEGORIES[name])  # GEOMETRIES read now: a geometry may be added later
    for i, v in enumerate(values):
        if v not in allowed:
            raise ValueError(f"scenes: column {name!r} must be one of {allowed}; row {i} is {v!r}")


_PLAIN_NUMBERS = {float, int, np.float64, np.float32, np.int64, np.int32}


def _fast_column(col: Column, values: list) -> list | None:
    """The column converted at once when every cell is plainly of its type (the common case,
    ~20x faster than cell by cell); None when some cell needs :func:`_cell`."""
    types = set(map(type, values))
    if col.kind == "text":
        return values if types == {str} else None
    if col.kind not in ("float", "int") or not types <= _PLAIN_NUMBERS:
        return None  # bools, strings, None, other objects: cell by cell
    arr = np.asarray(values)
    if col.kind == "float":
        if arr.dtype.kind == "f" and col.default is not None and np.isnan(arr).any():
            return None  # missing cells of an optional column take its default
        return arr.astype(np.float64).tolist()
    if arr.dtype.kind == "f" and not np.all((np.abs(arr) < 2.0**62) & (arr == np.round(arr))):
        return None  # NaN, huge or fractional cells: cell by cell
    return arr.astype(np.int64).tolist()


def normalise(scenes) -> dict[str, list]:
    """The table as complete, typed columns (defaults filled in); raises before any work."""
    cols = _columns_of(scenes)
    _check_names(cols)
    size = len(next(iter(cols.values())))
    out = {}
    for col in INPUTS:
        if col.name in cols:
            values = cols[col.name]
            fast = _fast_column(col, values)
            out[col.name] = (
                fast if fast is not None else [_cell(col, i, v) for i, v in enumerate(values)]
            )
        elif col.default is not _SPECTRUM and col.default is not _ABSENT:
            out[col.name] = [col.default] * size
    for name in _CATEGORIES:
        _check_category(name, out[name])
    _check_laws(out)
    out["n"] = [
        _GEOMETRY_N.get(g, 1024) if n is _BY_GEOMETRY else n
        for n, g in zip(out["n"], out["geometry"], strict=True)
    ]
    out["gamma"] = [
        VARIANTS[v].default_gamma if math.isnan(g) else g
        for g, v in zip(out["gamma"], out["variant"], strict=True)
    ]
    return out


def _check_laws(cols: dict[str, list]) -> None:
    """A row with a law takes the law's kind as its model (``"calibrated"``, ``"tabulated"``);
    a law beside another model, or a law's model name without a law, is refused by row."""
    laws = cols.get("law") or [None] * len(cols["model"])
    models = cols["model"]
    for i, (law, model) in enumerate(zip(laws, models, strict=True)):
        kind = law_kind(law)
        if kind is None and model in LAW_MODELS:
            raise ValueError(
                f"scenes: row {i} has model={model!r} but no law: give the law (a law object or "
                "the path of a law file) in the law column"
            )
        if kind is not None and model not in ("persson", kind):
            raise ValueError(
                f"scenes: row {i} has a law and model={model!r}: the law replaces the model; "
                "leave the model empty (or 'persson') in the rows with a law"
            )
        if kind is not None:
            models[i] = kind


def read_scenes(path: str | os.PathLike) -> dict[str, list]:
    """Read a scene table from a CSV file, for :func:`sweep` (``fastline batch``).

    The file has a header row of column names (:data:`SCENE_COLUMNS`, or the same names with
    their units as :meth:`SweepTable.to_csv` writes them: ``E_star_Pa``, ``load_N_per_m``...)
    and one row per scene, comma-separated (double quotes allowed around a cell); ``#`` lines
    are comments. An empty cell takes the column's default. The result columns of a
    :meth:`SweepTable.to_csv` file (:data:`RESULT_COLUMNS`, ``p0_Pa``...) are recognised and
    skipped: such a file is read as the campaign it ran. Spectrum files in a ``psd`` column
    and law files in a ``law`` column (``path`` or ``path@sha256:<hex>``, as a table writes
    them: :mod:`fastline.batch.laws`) are relative to the CSV file's directory; ``none`` there
    means no spectrum (hertz) or no law.

    Returns
    -------
    dict
        Column name -> list of cells (numbers as floats, text as str), for :func:`sweep`.

    Raises
    ------
    ValueError
        When the file cannot be read, a row has the wrong number of cells, or a column is
        unknown (each named).
    """
    path = os.fspath(path)
    header, body = _csv_rows(path)
    aliases = {c.csv_name: c.name for c in INPUTS} | {c.name: c.name for c in INPUTS}
    aliases["load_N"] = "load"  # the load on a sphere (SweepTable.to_csv names it so)
    results = {c.csv_name for c in OUTPUTS} | set(RESULT_COLUMNS)  # a SweepTable's: skipped
    unknown = [k for k in header if k not in aliases and k not in results]
    if unknown:
        raise ValueError(f"{path}: unknown columns {unknown}; allowed: {', '.join(SCENE_COLUMNS)}")
    base = os.path.dirname(os.path.abspath(path))
    cols = {}
    for j, key in enumerate(header):
        if key not in aliases:
            continue
        col = BY_NAME[aliases[key]]
        if col.kind == "law":
            cells = [law_csv_cell(row[j].strip(), base, f"{path}:{k}") for k, row in body]
        else:
            cells = [_csv_cell(col, row[j].strip(), base) for _line, row in body]
        cols[col.name] = cells
    return cols


def _csv_rows(path: str) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Header and (line number, cells) of the data rows of a CSV file."""
    try:
        with open(path, encoding="utf-8", newline="") as fh:
            lines = [(k, ln) for k, ln in enumerate(fh, 1) if ln.strip() and ln[0] != "#"]
    except OSError as e:
        raise ValueError(f"cannot read scene table {path}: {e.strerror}") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file") from None
    if len(lines) < 2:
        raise ValueError(f"{path}: need a header row and at least one scene")
    rows = [(k, row) for (k, _), row in zip(lines, csv.reader(ln for _, ln in lines), strict=True)]
    header = [h.strip() for h in rows[0][1]]
    for k, row in rows[1:]:
        if len(row) != len(header):
            raise ValueError(f"{path}:{k}: {len(row)} cells, the header names {len(header)}")
    return header, rows[1:]


def _csv_cell(col: Column, text: str, base: str):
    if text == "":
        return None
    if col.kind in ("float", "int"):
        try:
            return float(text)
        except ValueError:
            return text  # reported by sweep's type check, with its row
    if col.kind == "psd":
        return None if text == "none" else os.path.join(base, text)
    return text
