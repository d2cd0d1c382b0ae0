"""Reading text tables as spreadsheets and instruments export them, and spectrum files.

:func:`read_table` is the tolerant reader shared by spectrum files (:func:`read_spectrum`,
two columns q [1/m] and C(q) [m^4] in Persson's convention) and the height profiles and maps of
:mod:`fastline.surfaces.topography`. SI units throughout. They sit with the spectra, beneath the
contact solvers, so that a solve given a spectrum file's path reads it by the same rules as
``fastline.io.read_spectrum`` and :func:`fastline.sweep`.
"""

from __future__ import annotations

import math
import os
import re

import numpy as np

from fastline.errors import SpectrumFileError
from fastline.theory.spectra import TabulatedPSD

__all__ = ["read_table", "read_spectrum"]


def _fields(line: str) -> list[str]:
    """The fields of one data line: ';'-separated (decimal commas allowed), else ','-separated,
    else separated by blanks or tabs."""
    if ";" in line:
        return [f.strip().replace(",", ".") for f in line.split(";")]
    if "," in line:
        return [f.strip() for f in line.split(",")]
    return line.split()


#: byte-order marks of UTF-16 (spreadsheets' "Unicode text" exports) and their codecs
_UTF16_BOMS = ((b"\xff\xfe", "utf-16-le"), (b"\xfe\xff", "utf-16-be"))
#: control characters that no text table holds (everything below a blank but \t \n \v \f \r)
_BINARY = re.compile("[\x00-\x08\x0e-\x1f]")


def _decode(data: bytes, path: str, error: type[ValueError]) -> str:
    """The text of a table file: UTF-16 when it starts with a UTF-16 byte-order mark, else
    UTF-8 (a UTF-8 byte-order mark dropped, undecodable bytes replaced); ``error`` when the
    bytes are not text (NUL or other control characters)."""
    text = None
    for bom, codec in _UTF16_BOMS:
        if data.startswith(bom):
            text = data[len(bom) :].decode(codec, errors="replace")
    if text is None:
        text = data.decode("utf-8-sig", errors="replace")
    if _BINARY.search(text):
        raise error(f"{path}: not a text file")
    return text


def read_table(
    path: str, *, what: str = "file", error: type[ValueError] = ValueError
) -> tuple[np.ndarray, np.ndarray]:
    """The numeric rows of a text table as exported by spreadsheets and instruments.

    Read as UTF-8 (a byte-order mark is dropped; undecodable bytes in header lines are
    replaced), or as UTF-16 when the file starts with its byte-order mark (a spreadsheet's
    "Unicode text" export). ``#`` starts a comment; blank lines are skipped; so are the lines
    before the first numeric row that do not parse as numbers (a header, with or without ``#``).
    Fields are separated by ``;`` (then a decimal comma is a decimal point), ``,``, tabs or
    blanks; an empty field or ``nan`` reads as NaN. A line that does not parse after the first
    numeric row is corruption, not a header: an ``error`` naming the file and line. So is a row
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
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as e:
        raise error(f"cannot read {what} {path}: {e.strerror}") from None
    rows, lines, width = [], [], None
    for number, raw in enumerate(_decode(data, path, error).splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        fields = _fields(line)
        if not any(fields):
            continue
        try:
            values = [float(f) if f else math.nan for f in fields]
        except ValueError:
            if rows:
                raise error(f"{path}:{number}: not a number in {line!r}") from None
            continue  # header lines before the data
        if width is None:
            width = len(values)
        elif len(values) != width:
            raise error(f"{path}:{number}: {len(values)} columns, expected {width}")
        rows.append(values)
        lines.append(number)
    if not rows:
        raise error(f"{path}: no numeric data found")
    return np.array(rows), np.array(lines)


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
