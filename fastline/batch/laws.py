"""The ``law`` column of a scene table: a tabulated or calibrated law in place of the model.

A cell holds nothing (None, NaN: the row's ``model`` column applies), a law object (a
:class:`~fastline.TabulatedLaw` or :class:`~fastline.CalibratedLaw`) or the path of a law file
(``fastline calibrate --out FILE``, :meth:`~fastline.CalibratedLaw.save`).

How a law reaches a worker:

* a law object travels as data (:class:`~fastline.theory.lawdata.LawData`: float64 arrays and
  JSON metadata, never a pickled law), made once per distinct object in the table and shared
  by every piece of a task, so it is sent once per task, not once per scene; the worker
  rebuilds the same law, bit for bit, once per process (its cache is keyed by the checksum);
* a file is read by the worker from its path. The caller reads the file too when it can and
  writes its SHA-256 checksum into the cell (``path@sha256:<hex>``); a worker that reads
  another file at that path, or none, fails those scenes with a message naming the file.

The text of a file cell, ``path@sha256:<hex>`` (the checksum optional), is also its form in a
CSV file (:meth:`~fastline.SweepTable.to_csv`, :func:`~fastline.batch.scenes.read_scenes`): a
table written by a sweep runs again with the same laws, or fails by name if a file changed.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Mapping
from typing import Any

from fastline.theory.lawdata import LAW_KINDS, LawData, law_data, read_law_file
from fastline.theory.laws import TabulatedLaw

#: a cell of the law column once checked: none, a law object, or a file's text
LawCell = TabulatedLaw | str | None

__all__ = ["CHECKSUM_TAG", "law_cell", "law_kind", "law_text", "parse_law_text", "LawKeys"]

#: what separates a law file's path from its checksum in a cell's text
CHECKSUM_TAG = "@sha256:"
#: the start of the CSV text of a law object (it has no file: read back, it is refused)
_OBJECT_TEXT = "<law object "


def parse_law_text(text: str) -> tuple[str, str | None]:
    """``(path, checksum or None)`` of a file cell's text ``path[@sha256:<hex>]``."""
    path, tag, checksum = text.rpartition(CHECKSUM_TAG)
    if not tag:
        return text, None
    return path, checksum.strip().lower() or None


@functools.lru_cache(maxsize=64)
def _file_checksum(path: str, _mtime_ns: int, _size: int) -> str | None:
    """The checksum of a law file this process can read (None when it cannot)."""
    try:
        return read_law_file(path).checksum
    except (OSError, ValueError):  # missing, unreadable or corrupt: the worker says which
        return None


def _local_checksum(path: str) -> str | None:
    try:
        st = os.stat(path)
    except OSError:
        return None
    return _file_checksum(path, st.st_mtime_ns, st.st_size)


def law_cell(i: int, v: Any) -> LawCell:
    """One cell of the law column: None, a law object, or ``abspath[@sha256:<hex>]``
    (the checksum of the caller's file added when it can read it); TypeError naming the row."""
    if v is None or (isinstance(v, float) and v != v):
        return None
    if isinstance(v, str | os.PathLike):
        path, checksum = parse_law_text(os.fspath(v))
        if not path.strip():
            raise TypeError(f"scenes: column 'law' holds an empty path in row {i}")
        path = os.path.abspath(path)
        checksum = checksum or _local_checksum(path)
        return path if checksum is None else f"{path}{CHECKSUM_TAG}{checksum}"
    if law_kind(v) is None:
        raise TypeError(
            "scenes: column 'law' must hold a TabulatedLaw, a CalibratedLaw (sent to the "
            f"workers as arrays) or the path of a law file; row {i} holds "
            f"{type(v).__name__} (a law of your own is solved in this process: "
            "LineContact(psd, E_star, radius, model=law).sweep(loads))"
        )
    return v


def law_kind(cell: Any) -> str | None:
    """The kind of law of a cell (``"calibrated"`` for a file), None for an empty cell or an
    object that does not travel as data."""
    if cell is None:
        return None
    if isinstance(cell, str):
        return "calibrated"
    return next((k for k, cls in LAW_KINDS.items() if type(cell) is cls), None)


def law_text(cell: LawCell, checksum: str | None = None) -> str:
    """A cell's text in a CSV file: ``path@sha256:<hex>`` for a file, ``<law object ...>``
    with its checksum for an object, empty for none."""
    if cell is None:
        return ""
    if isinstance(cell, str):
        return cell
    return f"{_OBJECT_TEXT}{type(cell).__name__} sha256:{checksum}>"


def law_csv_cell(text: str, base: str, where: str) -> str | None:
    """A law cell read from a CSV file (paths relative to ``base``); ValueError for the text
    of a law object (``where``: the file and line)."""
    if text in ("", "none"):
        return None
    if text.startswith(_OBJECT_TEXT):
        raise ValueError(
            f"{where}: the law of this row was a law object, which has no file: save it "
            "(law.save('law.npz')) and give the file's path in the law column"
        )
    path, checksum = parse_law_text(text)
    path = os.path.join(base, path)
    return path if checksum is None else f"{path}{CHECKSUM_TAG}{checksum}"


class LawKeys:
    """The law of each row as a model key and, for objects, its data (made once per object).

    Keys: ``("none",)``; ``("data", checksum)`` for an object (its :class:`LawData` with it);
    ``("file", path, checksum or None)`` for a file."""

    def __init__(self) -> None:
        self._data: dict[int, LawData] = {}

    def column(self, cols: Mapping) -> list[tuple[tuple, LawData | None]]:
        if "law" not in cols:
            return [(("none",), None)] * len(cols["load"])
        return [self._key(cell) for cell in cols["law"]]

    def _key(self, cell: LawCell) -> tuple[tuple, LawData | None]:
        if cell is None:
            return ("none",), None
        if isinstance(cell, str):
            path, checksum = parse_law_text(cell)
            return ("file", path, checksum), None
        data = self._data.get(id(cell))
        if data is None:
            data = self._data[id(cell)] = law_data(cell)
        return ("data", data.checksum), data

    def checksum(self, cell: LawCell) -> str | None:
        """The checksum of a cell's law when known here (objects, and files read here)."""
        key, _ = self._key(cell)
        return key[-1] if key[0] != "none" else None
