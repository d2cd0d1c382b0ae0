"""Measured surfaces in: from a line scan or a height map to the isotropic spectrum C(q).

Conventions (docs/topography.md, docs/theory.md section 2). SI units: heights and lengths in
m, wavenumbers in 1/m (``k = 2 pi / wavelength``).

* **1D spectrum of a profile**, two-sided: ``h_rms^2 = 2 int_0^inf C1D(k) dk`` (m^3). From N
  heights ``h_j`` at spacing dx (length ``L = N dx``) and a window ``w_j`` normalised to
  ``sum w_j^2 = N``::

      C1D(k_m) = dx^2 / (2 pi L) |sum_j w_j h_j exp(-i k_m x_j)|^2,    k_m = 2 pi m / L,

  so that ``sum_m C1D(k_m) 2 pi / L`` over all m (both signs) is ``mean((w h)^2)``: Parseval,
  exact for the rectangular window.
* **Isotropic 2D spectrum** (Persson): ``h_rms^2 = 2 pi int q C(q) dq`` (m^4). From an
  ``Ny x Nx`` map of area ``A``: ``C(q) = (dx dy)^2 / ((2 pi)^2 A) |FFT2(w h)|^2``, averaged over
  rings of ``|q|``.
* **1D to 2D** for an isotropic surface, the Abel pair
  ``C1D(k) = 2 int_k^inf C q / sqrt(q^2 - k^2) dq`` and
  ``C(q) = -(1/pi) int_q^inf C1D'(k) / sqrt(k^2 - q^2) dk`` (:func:`isotropic_from_1d`). For a
  power law the pair reduces to ``C = Gamma(1+H) / (sqrt(pi) Gamma(H+1/2)) C1D / q``; the
  shortcut ``C = C1D / (2 q)`` is exact only at H = 1/2 (14.6 % low at H = 0.8, 21.5 % low at
  H = 1: the exact C is 17 % and 27 % higher).

Other codes' conventions: :func:`convert_psd`. The usable wavenumber range of a measurement
and the rules that set it: :func:`psd_from_profile`. Files: :func:`read_topography`.

This module gathers the public names of the modules that hold the code, from the bottom up:
:mod:`~fastline.surfaces.heights` (checks, dropouts, detrending, windows),
:mod:`~fastline.surfaces.ranges` (the usable range, log binning),
:mod:`~fastline.surfaces.tables` (:func:`extend_psd`), :mod:`~fastline.surfaces.profiles`
(:func:`psd_from_profile`, :func:`isotropic_from_1d`), :mod:`~fastline.surfaces.maps`
(:func:`psd_from_map`), :mod:`~fastline.surfaces.fit` (:func:`fit_self_affine`),
:mod:`~fastline.surfaces.conventions`, :mod:`~fastline.surfaces.synthetic` and
:mod:`~fastline.surfaces.files`.
"""

from __future__ import annotations

from fastline.errors import TopographyWarning
from fastline.surfaces.conventions import CONVENTIONS, Convention, convert_psd
from fastline.surfaces.files import UNITS as UNITS
from fastline.surfaces.files import Map, Profile, read_map, read_profile, read_topography
from fastline.surfaces.fit import (
    ROLLOFF_MARGIN,
    ROLLOFF_SIGNIFICANCE,
    SelfAffineFit,
    fit_self_affine,
)
from fastline.surfaces.heights import FLAT_TOLERANCE as FLAT_TOLERANCE
from fastline.surfaces.heights import MAX_DROPOUT_FRACTION as MAX_DROPOUT_FRACTION
from fastline.surfaces.heights import MIN_POINTS as MIN_POINTS
from fastline.surfaces.heights import PLAUSIBLE_H_RMS as PLAUSIBLE_H_RMS
from fastline.surfaces.heights import PLAUSIBLE_SLOPE as PLAUSIBLE_SLOPE
from fastline.surfaces.maps import psd_from_map
from fastline.surfaces.profiles import ProfileSpectrum, isotropic_from_1d, psd_from_profile
from fastline.surfaces.ranges import LOW_MODE as LOW_MODE
from fastline.surfaces.ranges import MIN_PER_BIN as MIN_PER_BIN
from fastline.surfaces.ranges import NOISE_MARGIN as NOISE_MARGIN
from fastline.surfaces.ranges import POINTS_PER_WAVELENGTH as POINTS_PER_WAVELENGTH
from fastline.surfaces.ranges import TIP_SAFETY as TIP_SAFETY
from fastline.surfaces.ranges import QRange
from fastline.surfaces.synthetic import SYNTHETIC_MAX_POINTS as SYNTHETIC_MAX_POINTS
from fastline.surfaces.synthetic import synthetic_surface
from fastline.surfaces.tables import extend_psd

__all__ = [
    "TopographyWarning",
    "ProfileSpectrum",
    "psd_from_profile",
    "isotropic_from_1d",
    "extend_psd",
    "psd_from_map",
    "SelfAffineFit",
    "fit_self_affine",
    "ROLLOFF_MARGIN",
    "ROLLOFF_SIGNIFICANCE",
    "CONVENTIONS",
    "Convention",
    "QRange",
    "convert_psd",
    "synthetic_surface",
    "Profile",
    "Map",
    "read_profile",
    "read_map",
    "read_topography",
]
