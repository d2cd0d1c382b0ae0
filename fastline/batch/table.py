"""The results of a sweep: the table (:class:`SweepTable`), how the sweep ran
(:class:`SweepStats`), filling the table with the workers' rows and the warnings, once per
cause.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from html import escape
from typing import TYPE_CHECKING

import numpy as np

from fastline._lib.version import __version__
from fastline.batch.laws import LawKeys, law_text
from fastline.batch.scenes import (
    BY_NAME,
    LOAD_UNITS,
    NUMERIC_RESULTS,
    RESULT_COLUMNS,
    SCENE_COLUMNS,
    Column,
    few,
)
from fastline.batch.worker import TaskOutcome
from fastline.contact.diagnostics import summarise_warnings
from fastline.errors import ConvergenceWarning, SceneFailureWarning, ValidityWarning
from fastline.io import check_output_file, write_csv

if TYPE_CHECKING:  # annotations only: pandas is optional
    import pandas as pd

__all__ = ["SweepTable", "SweepStats"]

# ----------------------------------------------------------------------------------------------
# the result table
# ----------------------------------------------------------------------------------------------
_DTYPES = {
    "float": np.float64,
    "int": np.int64,
    "bool": np.bool_,
    "text": object,
    "psd": object,
    "law": object,
}
_OBJECT_KINDS = ("text", "psd", "law")


def _dtype(cols: Mapping) -> np.dtype:
    names = [c for c in SCENE_COLUMNS if c in cols] + list(RESULT_COLUMNS)
    return np.dtype([(name, _DTYPES[BY_NAME[name].kind]) for name in names])


def empty_table(cols: Mapping) -> np.ndarray:
    size = len(cols["load"])
    table = np.zeros(size, dtype=_dtype(cols))
    for name, values in cols.items():
        if BY_NAME[name].kind in _OBJECT_KINDS:
            table[name] = np.fromiter(values, dtype=object, count=size)  # cells kept as given
        else:
            table[name] = values
    for name in NUMERIC_RESULTS:
        if BY_NAME[name].kind == "float":
            table[name] = np.nan
    table["warnings"] = ""
    table["error"] = ""
    return table


@dataclass
class _Flagged:
    """A solved scene as :func:`fastline.contact.diagnostics.summarise_warnings` reads it (the
    load's symbol and unit those of its geometry's results)."""

    load: float
    diagnostics: dict
    LOAD_SYMBOL: str = "f_N"
    LOAD_UNIT: str = "N/m"


_UNFLAGGED = _Flagged(0.0, {})  # a solved scene without warnings
_LOAD_SYMBOLS = {"cylinder": "f_N", "sphere": "F"}


def fill_table(table: np.ndarray, outcomes: list[TaskOutcome]) -> dict[str, list[_Flagged]]:
    """Write the workers' rows into the table; returns the solved scenes (with their
    warnings) of each geometry."""
    solved, numbers, failed, errors, flagged = [], [], [], [], []
    for outcome in outcomes:
        for i, values, messages, error in outcome.rows:
            if error:
                failed.append(i)
                errors.append(error)
                continue
            solved.append(i)
            numbers.append(values)
            if messages:
                table["warnings"][i] = ";".join(messages)
                diag = {"warning_causes": list(messages), "warning_messages": messages}
                flagged.append((i, diag))
    if failed:
        table["error"][np.asarray(failed)] = np.fromiter(errors, dtype=object, count=len(errors))
    if solved:
        idx = np.asarray(solved)
        block = np.asarray(numbers, dtype=np.float64)
        for k, name in enumerate(NUMERIC_RESULTS):
            table[name][idx] = block[:, k].astype(table.dtype[name])
    return _by_geometry(table, solved, flagged)


def _by_geometry(table: np.ndarray, solved: list[int], flagged: list) -> dict[str, list]:
    """Geometry -> its solved scenes as :class:`_Flagged` (one shared entry stands for each
    scene without warnings: only the count matters)."""
    geometry, load = table["geometry"], table["load"]
    out: dict[str, list[_Flagged]] = {}
    for i, diag in flagged:
        g = geometry[i]
        symbol, unit = _LOAD_SYMBOLS.get(g, "load"), LOAD_UNITS.get(g, "N/m")
        out.setdefault(g, []).append(_Flagged(float(load[i]), diag, symbol, unit))
    counts: dict[str, int] = {}
    for g in geometry[np.asarray(solved, dtype=np.int64)]:
        counts[g] = counts.get(g, 0) + 1
    for g, k in counts.items():
        scenes = out.setdefault(g, [])
        scenes.extend([_UNFLAGGED] * (k - len(scenes)))
    return out


@dataclass
class SweepStats:
    """How a sweep ran (not part of the results: these vary from run to run).

    Attributes
    ----------
    scenes, tasks, chunksize : int
        Scenes in the table, tasks sent to the executor, scenes per task at most.
    workers : int
        Distinct processes (host:pid) that ran tasks.
    theory_builds, model_builds : int
        Persson theories and models built by the workers in this sweep (a worker's cache may
        already hold some from an earlier sweep).
    compute_seconds : float
        Time spent inside tasks, summed over tasks (s).
    compute_cpu_seconds : float
        CPU time of the threads running the tasks, summed over tasks (s): below
        ``compute_seconds`` when the workers waited for a CPU (other jobs on the machine).
    wall_seconds : float
        Wall time of the whole call: checking the table, planning, solving (including a
        process pool's start-up when :func:`sweep` made the pool) and assembling (s).
    executor : str
        What ran the tasks.
    """

    scenes: int
    tasks: int
    chunksize: int
    workers: int
    theory_builds: int
    model_builds: int
    compute_seconds: float
    compute_cpu_seconds: float
    wall_seconds: float
    executor: str

    @property
    def scenes_per_second(self) -> float:
        return self.scenes / self.wall_seconds if self.wall_seconds > 0 else math.inf


def _text_cell(v) -> str:
    """A text cell for a CSV file, on one line (:func:`fastline.io.write_csv` quotes it when
    it holds commas or quotes)."""
    text = "none" if v is None else v if isinstance(v, str) else repr(v)
    return " ".join(text.split())


class SweepTable:
    """The results of :func:`sweep`: one row per scene, in the order given.

    Attributes
    ----------
    table : numpy structured array
        The scene columns (defaults filled in; ``psd`` and ``law`` cells as given, paths made
        absolute, a law file's path followed by ``@sha256:`` and the checksum of the file this
        process read; ``model`` the law's kind in the rows with a law) followed by
        :data:`RESULT_COLUMNS`: ``p0`` [Pa], ``p0_ratio``, ``s`` [m], ``fwhm`` [m],
        ``w_over_s``, ``alpha``, ``converged``, ``iterations``, ``convolutions``,
        ``residual``, ``warnings`` (the validity causes found, ``;``-separated) and ``error``
        (empty when the scene was solved). A failed scene has NaN numbers, ``converged``
        False and zero counts. Text columns hold Python strings (object dtype).

        Each result is the attribute of that name of the scene's
        :class:`~fastline.LineContactResult` (cylinder) or
        :class:`~fastline.PointContactResult` (sphere). For a sphere: ``p0_ratio`` is
        against the Hertz *sphere*, ``s`` and ``fwhm`` are measured along a diameter
        (``s^2 = int r^2 p dA / (2F)``), ``alpha = h_rms / delta`` with ``delta = a^2/R``
        (a cylinder's ``delta = 4 f_N / (pi E*)``), ``convolutions`` counts ring-operator
        applications (products with K plus preconditioner solves; a cylinder's, FFT
        convolutions) and ``residual`` is relative to u0 as for a cylinder.
    warnings : list of (str, str)
        ``(cause, message)`` once per cause over the whole sweep: ``"failed"``,
        ``"not_converged"`` and the causes of :data:`fastline.contact.diagnostics.CAUSES`.
    stats : SweepStats
        How the sweep ran (workers, tasks, theory builds, times).

    ``table_obj["p0"]`` is a column, ``len(table_obj)`` the number of scenes.
    """

    def __init__(
        self, table: np.ndarray, warnings: list[tuple[str, str]], stats: SweepStats
    ) -> None:
        self.table = table
        self.warnings = warnings
        self.stats = stats

    @property
    def columns(self) -> tuple[str, ...]:
        return self.table.dtype.names

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of the scenes solved and converged."""
        return (self.table["error"] == "") & self.table["converged"]

    @property
    def failed(self) -> np.ndarray:
        """Boolean mask of the scenes that failed (their ``error`` text says why)."""
        return self.table["error"] != ""

    def __len__(self) -> int:
        return self.table.size

    def __getitem__(self, key):
        return self.table[key]

    def __repr__(self):
        failed = int(self.failed.sum())
        unconverged = len(self) - failed - int(self.ok.sum())
        return (
            f"SweepTable({len(self)} scenes: {int(self.ok.sum())} converged, {unconverged} not "
            f"converged, {failed} failed; warnings: {[c for c, _ in self.warnings]})"
        )

    #: the columns a notebook shows, at most ``_HTML_ROWS`` rows of them
    _HTML_COLUMNS = ("label", "geometry", "load", "alpha", "p0", "p0_ratio", "w_over_s",
                     "converged", "warnings", "error")  # fmt: skip
    _HTML_ROWS = 20

    def _repr_html_(self) -> str:
        """A notebook's view: the summary line, then the first rows of the main columns."""
        names = [c for c in self._HTML_COLUMNS if c in self.columns]
        head = "".join(f"<th>{escape(n)}</th>" for n in names)
        rows = []
        for rec in self.table[: self._HTML_ROWS]:
            cells = (rec[n] for n in names)
            text = (f"{v:.5g}" if isinstance(v, float) else str(v) for v in cells)
            rows.append("<tr>" + "".join(f"<td>{escape(t)}</td>" for t in text) + "</tr>")
        more = len(self) - self._HTML_ROWS
        tail = f"<p>... and {more} more rows (in the table attribute)</p>" if more > 0 else ""
        return f"<p>{escape(repr(self))}</p><table><tr>{head}</tr>{''.join(rows)}</table>{tail}"

    def to_csv(self, path: str | os.PathLike, meta: Mapping | None = None) -> None:
        """Write the table as a CSV file (:func:`fastline.io.write_csv`): ``# key: value``
        header lines, then columns named with their units (``load_N_per_m``, ``p0_Pa``...;
        the load is ``load_N`` when every scene is a sphere, ``load`` when the table mixes
        geometries, and the header's ``load_unit`` line says which unit each geometry's has).

        Text cells are written on one line, in double quotes when they hold a comma or a quote
        (as CSV quotes them); ``psd`` cells as the file path or the spectrum's repr; ``law``
        cells as the file path and its checksum (``path@sha256:<hex>``), a law object as
        ``<law object CalibratedLaw sha256:<hex>>`` (:func:`read_scenes` refuses that text: save
        the law to a file and put its path there).
        :func:`fastline.io.read_csv` reads the file back, :func:`read_scenes` reads its scene
        columns (and skips the result columns), so a table's file is a campaign to run again.
        """
        path = check_output_file(path)
        header = {"fastline_version": __version__, "scenes": len(self)}
        header.update(failed=int(self.failed.sum()), not_converged=self._unconverged())
        header.update(chunksize=self.stats.chunksize, **(meta or {}))
        names = self.columns
        header["load_unit"] = "; ".join(
            f"{LOAD_UNITS.get(g, 'N/m')} ({g})" for g in dict.fromkeys(self.table["geometry"])
        )
        kinds = [BY_NAME[n].kind for n in names]
        keys = LawKeys()
        cell = {
            "text": _text_cell,
            "psd": _text_cell,
            "law": lambda v: law_text(v, None if v is None else keys.checksum(v)),
        }
        rows = (
            [cell[k](v) if k in cell else v for v, k in zip(rec, kinds, strict=True)]
            for rec in self.table.tolist()
        )
        title = "fastline sweep: one row per scene (inputs, then results); SI units"
        csv_names = [self._csv_name(n) for n in names]
        write_csv(path, csv_names, rows, header, title=title)

    def _csv_name(self, name: str) -> str:
        """A column's name in CSV files; the load's unit follows the geometries of the table
        (``load_N_per_m`` for cylinders, ``load_N`` for spheres, ``load`` when mixed)."""
        if name != "load":
            return BY_NAME[name].csv_name
        units = {LOAD_UNITS.get(g, "N/m") for g in self.table["geometry"]}
        if len(units) > 1:
            return "load"
        return Column("load", "float", units.pop()).csv_name

    def _unconverged(self) -> int:
        return int(((self.table["error"] == "") & ~self.table["converged"]).sum())

    def to_pandas(self) -> pd.DataFrame:
        """The table as a pandas DataFrame (needs pandas)."""
        try:
            import pandas as pd  # optional
        except ImportError:
            raise ImportError("SweepTable.to_pandas needs pandas (not installed)") from None
        return pd.DataFrame({name: self.table[name] for name in self.columns})


# ----------------------------------------------------------------------------------------------
# warnings, once per cause
# ----------------------------------------------------------------------------------------------
def summarise(table: np.ndarray, flagged: dict[str, list[_Flagged]]) -> list[tuple[str, str]]:
    """Failed and unconverged scenes, then the validity causes once each per geometry (the
    loads of a cylinder and of a sphere are in different units)."""
    out = []
    failed = np.flatnonzero(table["error"] != "")
    if failed.size:
        first = int(failed[0])
        out.append(
            (
                "failed",
                f"{failed.size} of {table.size} scenes failed (rows {few(failed.tolist())}); "
                f"row {first}: {table['error'][first]}; see the table's error column",
            )
        )
    bad = np.flatnonzero((table["error"] == "") & ~table["converged"])
    if bad.size:
        out.append(
            (
                "not_converged",
                f"{bad.size} of {table.size} scenes did not converge (rows "
                f"{few(bad.tolist())}); see the converged and residual columns",
            )
        )
    for solved in flagged.values():
        out += summarise_warnings(solved)
    return out


def emit_warnings(summary: list[tuple[str, str]]) -> None:
    classes = {"failed": SceneFailureWarning, "not_converged": ConvergenceWarning}
    for cause, msg in summary:
        warnings.warn(f"fastline: {msg}", classes.get(cause, ValidityWarning), stacklevel=3)
