"""Measured and synthetic surfaces: reading profiles, maps and spectrum tables
(:mod:`~fastline.surfaces.read`, :mod:`~fastline.surfaces.files`), their spectra
(:mod:`~fastline.surfaces.profiles`, :mod:`~fastline.surfaces.maps`), the isotropic spectrum
of a line scan (the Abel transform of :mod:`~fastline.surfaces.abel`) and a self-affine fit
(:mod:`~fastline.surfaces.fit`), all gathered in :mod:`~fastline.surfaces.topography` (also
``fastline.topography``), and the whole analysis of a scan (:mod:`~fastline.surfaces.scan`)."""

from __future__ import annotations

from fastline.surfaces import topography
from fastline.surfaces.read import read_spectrum, read_table
from fastline.surfaces.scan import LIMIT_RULES, ScanSpectrum, analyse_scan

__all__ = [
    "topography",
    "read_spectrum",
    "read_table",
    "analyse_scan",
    "ScanSpectrum",
    "LIMIT_RULES",
]
