"""Reading text tables as spreadsheets and instruments export them, and spectrum files.

:func:`read_table` is the tolerant reader shared by spectrum files (:func:`read_spectrum`,
two columns q [1/m] and C(q) [m^4] in Persson's convention) and the height profiles and maps of
:mod:`fastline.surfaces.topography`. SI units throughout. They sit with the spectra, beneath the
contact solvers, so that a solve given a spectrum file's path reads it by the same rules as
``fastline.io.read_spectrum`` and :func:`fastline.sweep`.
"""

from __future__ import annotations

import io
import math
import os
import re
from typing import NamedTuple

import numpy as np

from fastline.errors import SpectrumFileError
from fastline.theory.spectra import TabulatedPSD

__all__ = ["Table", "parse_table", "read_table", "read_spectrum", "split_fields"]


#: a field with a decimal comma: digits, one comma, digits (an exponent allowed)
_DECIMAL_COMMA = re.compile(r"^[-+]?\d*,\d+([eE][-+]?\d+)?$")


def split_fields(line: str) -> list[str]:
    """The fields of one data line: ';'-separated or tab-separated (decimal commas allowed in
    both), blank-separated fields with decimal commas (each field a number with one comma),
    else ','-separated, else separated by blanks."""
    if ";" in line:
        return [f.strip().replace(",", ".") for f in line.split(";")]
    if "\t" in line:
        return [f.strip().replace(",", ".") for f in line.split("\t")]
    if "," in line:
        words = line.split()
        if len(words) > 1 and all(_DECIMAL_COMMA.match(w) or "," not in w for w in words):
            return [w.replace(",", ".") for w in words]
        return [f.strip() for f in line.split(",")]
    return line.split()


#: byte-order marks of UTF-16 (spreadsheets' "Unicode text" exports) and their codecs
_UTF16_BOMS = ((b"\xff\xfe", "utf-16-le"), (b"\xfe\xff", "utf-16-be"))
#: control characters that no text table holds (everything below a blank but \t \n \v \f \r)
_BINARY = re.compile("[\x00-\x08\x0e-\x1f]")


def _utf16_without_bom(data: bytes) -> str | None:
    """The codec of UTF-16 text without a byte-order mark (ASCII text in it has every other
    byte NUL), or None."""
    head = data[:4096]
    if len(head) < 4 or len(head) % 2:
        head = head[: len(head) - len(head) % 2]
    if len(head) < 4:
        return None
    odd, even = head[1::2], head[0::2]
    if odd.count(0) >= 0.9 * len(odd) and even.count(0) == 0:
        return "utf-16-le"
    if even.count(0) >= 0.9 * len(even) and odd.count(0) == 0:
        return "utf-16-be"
    return None


def _decode(data: bytes, path: str, error: type[ValueError]) -> str:
    """The text of a table file: UTF-16 when it starts with a UTF-16 byte-order mark or has
    every other byte NUL, else UTF-8 (a UTF-8 byte-order mark dropped, undecodable bytes
    replaced); ``error`` when the bytes are not text (NUL or other control characters)."""
    text = None
    for bom, codec in _UTF16_BOMS:
        if data.startswith(bom):
            text = data[len(bom) :].decode(codec, errors="replace")
    if text is None and (codec := _utf16_without_bom(data)) is not None:
        text = data.decode(codec, errors="replace")
    if text is None:
        text = data.decode("utf-8-sig", errors="replace")
    if "\x00" in text or _BINARY.search(text, 0, 1 << 16):  # the head, and any NUL
        raise error(f"{path}: not a text file")
    return text


class Table(NamedTuple):
    """The numeric block of a text table: rows (n, columns; NaN for empty fields), the line
    number (1-based) of each row, and the non-empty lines before the block (its header,
    parameter blocks and column names, for the callers' units)."""

    rows: np.ndarray
    lines: np.ndarray
    header: list[str]


def _numbers(line: str) -> list[float] | None:
    """The numbers of one line (NaN for empty fields or ``nan``), None when it is text or empty
    (a comment after ``#`` is dropped)."""
    fields = split_fields(line.split("#", 1)[0].strip())
    if not any(fields):
        return None
    try:
        return [float(f) if f else math.nan for f in fields]
    except ValueError:
        return None


#: the data begin at the first run of this many numeric lines of one width: a count line, a
#: lone number in a parameter block or a units line before them is header
_RUN = 3


def _data_start(lines: list[str]) -> int:
    """Index of the first line of the data block (len(lines) when there is none)."""
    run, width, first = 0, None, len(lines)
    for i, raw in enumerate(lines):
        values = _numbers(raw)
        if values is None:
            if raw.split("#", 1)[0].strip():
                run, width = 0, None
            continue
        if run and len(values) == width:
            run += 1
        else:
            run, width, first_of_run = 1, len(values), i
        if run == 1 and first == len(lines):
            first = i  # a file of fewer than _RUN numeric lines starts at its first
        if run == _RUN:
            return first_of_run
    return first


def _loadtxt(body: str, first: str, width: int):
    """The rows of a clean numeric block (one separator, no comments, no empty fields) parsed
    by NumPy in one pass; None when the block is not that clean (the line parser then names
    the line at fault). ``first``: its first line, which sets the separator."""
    if "#" in body or not body.strip():
        return None
    if ";" in first or "\t" in first:
        sep = ";" if ";" in first else "\t"
        body = body.replace(",", ".")
    elif "," in first and len(split_fields(first)) == len(first.split(",")):
        sep = ","
    else:
        sep = None
    fields = split_fields(first)
    used = len(fields)
    while used > 1 and not fields[used - 1]:  # trailing separators: empty columns, not read
        used -= 1
    columns = None if used == width else range(used)
    try:
        rows = np.loadtxt(
            io.StringIO(body), delimiter=sep, ndmin=2, dtype=np.float64, usecols=columns
        )
    except ValueError:
        return None
    return rows if rows.shape[1] == used else None


#: a large text's data start is sought in this many first lines (the rest is not split)
_HEAD = 4000


def _fast_table(text: str):
    """(rows, line numbers, header, first data line) of a large clean table: the data start
    found in its first lines, the rest parsed by NumPy in one pass; None when that fails (a
    blank line, a comment or a bad field in the data: the line parser takes over)."""
    head = text.split("\n", _HEAD)
    if len(head) <= _HEAD:
        return None
    lines = [ln.rstrip("\r") for ln in head[:-1]]
    start = _data_start(lines)
    if start >= len(lines) - _RUN:
        return None
    body = "\n".join(head[start:]).rstrip()
    del head
    if "\r" in body:  # Windows line ends
        body = body.replace("\r", "")
    rows = _loadtxt(body, lines[start], len(_numbers(lines[start])))
    if rows is None or rows.shape[0] != body.count("\n") + 1:
        return None
    header = [ln.strip() for ln in lines[:start] if ln.strip()]
    return rows, np.arange(start + 1, start + 1 + rows.shape[0]), header, lines[start]


def _slow_rows(lines, start, path, error):
    """Rows and line numbers of the block from ``start``, line by line: a line that does not
    parse, or has another number of columns than the first, is an ``error`` naming it."""
    rows, numbers, width = [], [], None
    for number, raw in enumerate(lines[start:], start + 1):
        line = raw.split("#", 1)[0].strip()
        if not any(split_fields(line)):
            continue
        values = _numbers(line)
        if values is None:
            raise error(f"{path}:{number}: not a number in {line!r}")
        if width is None:
            width = len(values)
        elif len(values) != width:
            raise error(f"{path}:{number}: {len(values)} columns, expected {width}")
        rows.append(values)
        numbers.append(number)
    return np.array(rows), np.array(numbers)


def _drop_empty_columns(rows: np.ndarray) -> np.ndarray:
    """Rows without the trailing columns that are empty on every row (trailing separators)."""
    keep = rows.shape[1]
    while keep > 1 and np.all(np.isnan(rows[:, keep - 1])):
        keep -= 1
    return rows[:, :keep]


def parse_table(path: str, *, what: str = "file", error: type[ValueError] = ValueError) -> Table:
    """The numeric block of a text table with the lines before it (:func:`read_table`)."""
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as e:
        raise error(f"cannot read {what} {path}: {e.strerror}") from None
    text = _decode(data, path, error)
    del data
    fast = _fast_table(text)
    if fast is not None:
        rows, numbers, header, first = fast
    else:
        lines = text.splitlines()
        start = _data_start(lines)
        if start == len(lines):
            raise error(f"{path}: no numeric data found")
        header = [ln.strip() for ln in lines[:start] if ln.strip()]
        rows, numbers, first = *_slow_rows(lines, start, path, error), lines[start]
    rows = _drop_empty_columns(rows)
    if rows.shape[1] == 1 and rows.shape[0] > 2 and rows[0, 0] == rows.shape[0] - 1:
        header.append(first.strip())  # a count line: the number of values that follow
        rows, numbers = rows[1:], numbers[1:]
    return Table(rows, numbers, header)


def read_table(
    path: str, *, what: str = "file", error: type[ValueError] = ValueError
) -> tuple[np.ndarray, np.ndarray]:
    """The numeric rows of a text table as exported by spreadsheets and instruments.

    Read as UTF-8 (a byte-order mark is dropped; undecodable bytes in header lines are
    replaced), or as UTF-16 when the file starts with its byte-order mark or has every other
    byte NUL (a spreadsheet's "Unicode text" export). ``#`` starts a comment; blank lines are
    skipped. The data begin at the first run of three numeric lines with one number of
    columns: everything before (a header, blocks of scan parameters and results, column
    names, a units line, a count line) is skipped, and so is a first value that counts the
    values after it in a single column. Fields are separated by ``;`` or tabs (then
    a decimal comma is a decimal point), ``,`` or blanks (blank-separated numbers with one
    decimal comma each are read as such); an empty field or ``nan`` reads as NaN, and columns
    empty on every row (trailing separators) are dropped. A line that does not parse after the
    data began is corruption, not a header: an ``error`` naming the file and line. So is a row
    with another number of columns than the first.

    Parameters
    ----------
    path : str
    what : str
        What the file should be, for the message when it cannot be read.
    error : type
        The ValueError subclass raised.

    Returns
    -------
    rows : ndarray, shape (n, columns)
    lines : ndarray of int, shape (n,)
        The line number (1-based) of each row, for the callers' own messages.
    """
    table = parse_table(path, what=what, error=error)
    return table.rows, table.lines


def _spectrum_rows(path: str) -> np.ndarray:
    """The (q, C) rows of a spectrum file: two columns, no missing values, two rows or more."""
    rows, lines = read_table(path, what="spectrum file", error=SpectrumFileError)
    if rows.shape[1] != 2:
        raise SpectrumFileError(
            f"{path}:{lines[0]}: expected two columns q [1/m] and C [m^4], got {rows.shape[1]}"
        )
    missing = np.isnan(rows).any(axis=1)
    if missing.any():
        raise SpectrumFileError(f"{path}:{lines[np.argmax(missing)]}: a value is missing (NaN)")
    if len(rows) < 2:
        raise SpectrumFileError(f"{path}: need at least two (q, C) rows, got {len(rows)}")
    return rows


def read_spectrum(path: str | os.PathLike) -> TabulatedPSD:
    """Read a two-column spectrum file (q [1/m], C [m^4]) into a :class:`~fastline.TabulatedPSD`.

    Parameters
    ----------
    path : str or path-like
        Text file of two columns, as spreadsheets and instruments export it: separated by
        blanks, tabs, ``,`` or ``;`` (then with decimal commas allowed); header lines before
        the numbers (with or without ``#``), ``#`` comments, blank lines and a UTF-8
        byte-order mark are skipped.

    Returns
    -------
    TabulatedPSD

    Raises
    ------
    SpectrumFileError
        (a ValueError) naming the file and line when a row is malformed, when the first column
        starts at 0 (a height profile, not a spectrum), or when q or C break the rules of
        :class:`~fastline.TabulatedPSD` (q > 0 strictly increasing, C >= 0, finite).
    """
    path = os.fspath(path)
    q, C = _spectrum_rows(path).T
    if q[0] == 0.0:
        raise SpectrumFileError(
            f"{path}: the first column starts at 0: this looks like a height profile, not a "
            "spectrum (expected wavenumbers q > 0 [1/m] and C(q) [m^4])"
        )
    if np.any(C < 0.0):
        k = int(np.argmax(C < 0.0))
        raise SpectrumFileError(
            f"{path}: C(q) < 0 at q = {q[k]:g} 1/m: a power spectrum is >= 0 (is this a height "
            "profile, not a spectrum?)"
        )
    try:
        return TabulatedPSD(q, C)
    except ValueError as e:
        raise SpectrumFileError(f"{path}: {e}") from None
