"""Tabulated and calibrated laws as plain data: arrays and JSON metadata, for other processes.

A :class:`~fastline.theory.laws.TabulatedLaw` or :class:`~fastline.theory.calibrated.CalibratedLaw`
goes to the workers of :func:`fastline.sweep` (a process pool, a dask cluster) as a
:class:`LawData`: float64 arrays and a dict of JSON values, never a pickled law object, so a
worker rebuilds exactly the law the caller holds (:func:`restore_law`: the same nodes, the same
Hermite slopes, the same numbers bit for bit) and nothing in the message can run code.

A calibrated law's data are its file's content (:meth:`CalibratedLaw.save`): the same arrays,
the same metadata and the same SHA-256 checksum, so a law and the file it was saved to share
one key (:attr:`LawData.checksum`), and :func:`read_law_file` reads a file into the same form.
A tabulated law has no file: its data are its nodes (ln p, u, and the contact fraction when it
has one), checked by the same kind of checksum.
"""

from __future__ import annotations

import json
import os
from typing import NamedTuple

import numpy as np

from fastline.errors import CalibrationFileError
from fastline.theory.calibrated import (
    CalibratedLaw,
    _check_match,
    _checksum,
    _read,
    _restore,
    _state_arrays,
    _state_meta,
)
from fastline.theory.laws import TabulatedLaw, _monotone_slopes
from fastline.theory.spectra import PSD

__all__ = ["LawData", "LAW_KINDS", "law_data", "read_law_file", "restore_law", "check_law_scene"]

#: the format tag of a tabulated law's data
TABULATED_FORMAT = "fastline-tabulated-law/1"
#: law classes that travel as data, by the ``kind`` of their :class:`LawData`
LAW_KINDS = {"calibrated": CalibratedLaw, "tabulated": TabulatedLaw}


class LawData(NamedTuple):
    """A law as plain data.

    Attributes
    ----------
    kind : {"calibrated", "tabulated"}
        The law's class (:data:`LAW_KINDS`).
    arrays : dict of str to ndarray
        Its float64 arrays, by name.
    metadata : dict
        JSON values: the format tag, and for a calibrated law E*, the version, the settings,
        the simulated range and the ``checksum`` (SHA-256 of the arrays and the metadata).
    """

    kind: str
    arrays: dict
    metadata: dict

    @property
    def checksum(self) -> str:
        """SHA-256 of the arrays and metadata (hex): a calibrated law's file has the same."""
        return str(self.metadata["checksum"])


def law_data(law: TabulatedLaw) -> LawData:
    """The data of a :class:`TabulatedLaw` or :class:`CalibratedLaw` (TypeError for any other
    law: its state is not known to be arrays)."""
    kind = next((k for k, cls in LAW_KINDS.items() if type(law) is cls), None)
    if kind is None:
        raise TypeError(
            "only a TabulatedLaw or a CalibratedLaw travels to workers as data; got "
            f"{type(law).__name__}"
        )
    if kind == "calibrated":
        arrays, meta = _state_arrays(law), _state_meta(law)
    else:
        arrays = {"V": law._V, "U": law._U}
        if law._area is not None:
            arrays["area"] = law._area
        arrays = {k: np.ascontiguousarray(v, dtype=np.float64) for k, v in arrays.items()}
        meta = {"format": TABULATED_FORMAT}
    meta = json.loads(json.dumps(meta))  # plain JSON values, as a file holds them
    meta["checksum"] = _checksum(arrays, meta)
    return LawData(kind, arrays, meta)


def read_law_file(path: str | os.PathLike) -> LawData:
    """The data of a calibrated-law file (its format and checksum checked).

    Raises
    ------
    FileNotFoundError
        No file at ``path``.
    CalibrationFileError
        Not a calibrated-law file, another format version, or a checksum that does not match.
    """
    arrays, meta = _read(os.fspath(path))
    return LawData("calibrated", arrays, meta)


def restore_law(data: LawData) -> TabulatedLaw:
    """The law of ``data``: the same nodes and slopes as the law it was taken from (a
    calibrated law's spectrum is its recorded one, as :meth:`CalibratedLaw.load` without
    ``psd`` gives it)."""
    if data.kind == "calibrated":
        return _restore(CalibratedLaw, data.arrays, data.metadata, None, None, "law data")
    if data.kind != "tabulated" or data.metadata.get("format") != TABULATED_FORMAT:
        raise CalibrationFileError(f"not the data of a known law (kind {data.kind!r})")
    law = TabulatedLaw.__new__(TabulatedLaw)
    law._V, law._U = data.arrays["V"], data.arrays["U"]
    law._S = np.ascontiguousarray(_monotone_slopes(law._V, law._U))
    law.u0 = float(-law._S[0])
    law._area = data.arrays.get("area")
    return law


def check_law_scene(data: LawData, psd: PSD | None, E_star: float, where: str) -> None:
    """Refuse a calibrated law for a scene of another spectrum or modulus
    (:class:`~fastline.errors.CalibrationFileError`, as :meth:`CalibratedLaw.load` does;
    ``where`` names the law in the message). A tabulated law fits any scene."""
    if data.kind != "calibrated":
        return
    if psd is None:
        raise CalibrationFileError(
            f"{where} was calibrated for a rough surface: the scene needs its spectrum (psd)"
        )
    _check_match(data.arrays, data.metadata, psd, E_star, where)
