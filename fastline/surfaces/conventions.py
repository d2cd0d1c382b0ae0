"""Other codes' normalisations of a roughness spectrum, and the conversion to fastline's.

q is always the wavenumber ``2 pi / wavelength`` in 1/m; 2D spectra in m^4, 1D spectra in m^3.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from fastline._lib.validate import real_array

#: name -> (dimension, factor): a spectrum in that convention is ``factor`` times fastline's
#: (Persson's) spectrum of the same dimension at the same wavenumber q = 2 pi / wavelength.
CONVENTIONS = {
    # isotropic 2D, h_rms^2 = 2 pi int q C dq
    "persson": (2, 1.0),
    # SurfaceTopography / contact.engineering: C_iso = |h~(q)|^2 / A with
    # h~ = dx dy sum h exp(-i q.x), h_rms^2 = (1/2 pi) int q C_iso dq
    "surfacetopography": (2, (2.0 * math.pi) ** 2),
    "contact.engineering": (2, (2.0 * math.pi) ** 2),
    # 1D, two-sided: h_rms^2 = 2 int_0^inf C1D dk
    "persson-1d": (1, 1.0),
    # SurfaceTopography / contact.engineering: C1D = |h~(q)|^2 / L, h_rms^2 = (1/pi) int_0^inf
    "surfacetopography-1d": (1, 2.0 * math.pi),
    "contact.engineering-1d": (1, 2.0 * math.pi),
    # one-sided PSD per unit wavenumber k: h_rms^2 = int_0^inf G dk
    "one-sided-1d": (1, 2.0),
    # one-sided PSD per unit spatial frequency f = k / (2 pi) (cycles/m): h_rms^2 = int G_f df
    "one-sided-1d-frequency": (1, 4.0 * math.pi),
}
#: the names of :data:`CONVENTIONS` (``from_`` and ``to`` of :func:`convert_psd`)
Convention = Literal[
    "persson",
    "surfacetopography",
    "contact.engineering",
    "persson-1d",
    "surfacetopography-1d",
    "contact.engineering-1d",
    "one-sided-1d",
    "one-sided-1d-frequency",
]


def convert_psd(
    C: ArrayLike,
    q: ArrayLike,
    from_: Convention = "surfacetopography",
    to: Convention = "persson",
) -> np.ndarray:
    """A spectrum in another code's normalisation (same dimension, same q).

    Conventions (``CONVENTIONS``; q always the wavenumber ``2 pi / wavelength`` in 1/m):

    ==========================  ====  ========================================  =============
    name                        dim   normalisation                             x fastline's
    ==========================  ====  ========================================  =============
    ``persson``                 2D    ``h_rms^2 = 2 pi int q C dq``             1
    ``surfacetopography``       2D    ``h_rms^2 = (1/2 pi) int q C dq``         (2 pi)^2
    ``persson-1d``              1D    ``h_rms^2 = 2 int_0^inf C dk``            1
    ``surfacetopography-1d``    1D    ``h_rms^2 = (1/pi) int_0^inf C dk``       2 pi
    ``one-sided-1d``            1D    ``h_rms^2 = int_0^inf G dk``              2
    ``one-sided-1d-frequency``  1D    ``h_rms^2 = int_0^inf G_f df``, f=k/2pi   4 pi
    ==========================  ====  ========================================  =============

    ``contact.engineering`` and ``contact.engineering-1d`` are the SurfaceTopography ones
    (T. D. B. Jacobs, T. Junge, L. Pastewka, Surf. Topogr.: Metrol. Prop. 5, 013001 (2017),
    doi:10.1088/2051-672X/aa51f8; the docstrings of SurfaceTopography's
    ``power_spectrum_from_profile`` and ``power_spectrum_from_area``, version 1.27,
    https://contactengineering.github.io/SurfaceTopography/; the tests hold both estimators,
    converted, equal to fastline's). For ``one-sided-1d-frequency`` tabulated against
    f, pass ``q = 2 pi f``.

    A 1D and a 2D spectrum are not related point by point: the 2D spectrum of a line scan is
    :func:`isotropic_from_1d` (the factor 2 people lose is this, not a normalisation).

    Parameters
    ----------
    C : array_like
        Spectrum values (>= 0, finite).
    q : array_like
        Wavenumbers in 1/m (> 0), same shape.
    from_, to : str
        Names in ``CONVENTIONS``.
    """
    names = ", ".join(repr(n) for n in CONVENTIONS)
    for arg, name in (("from_", from_), ("to", to)):
        if name not in CONVENTIONS:
            raise ValueError(f"{arg} must be one of {names}, got {name!r}")
    (d_from, f_from), (d_to, f_to) = CONVENTIONS[from_], CONVENTIONS[to]
    if d_from != d_to:
        raise ValueError(
            f"{from_!r} is a {d_from}D and {to!r} a {d_to}D spectrum: they are not related point "
            "by point; use isotropic_from_1d (the inverse Abel transform) for 1D -> 2D"
        )
    C = real_array("C", C)
    q = real_array("q", q)
    if C.shape != q.shape:
        raise ValueError(f"C and q must have the same shape, got {C.shape} and {q.shape}")
    if not (np.all(np.isfinite(C)) and np.all(C >= 0.0)):
        raise ValueError("C must be finite and >= 0")
    if not (np.all(np.isfinite(q)) and np.all(q > 0.0)):
        raise ValueError("q must be finite and > 0 (1/m)")
    return C * (f_to / f_from)
