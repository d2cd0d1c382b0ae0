"""Measured and synthetic surfaces: reading profiles, maps and spectrum tables
(:mod:`~fastline.surfaces.read`, :mod:`~fastline.surfaces.files`), their spectra
(:mod:`~fastline.surfaces.profiles`, :mod:`~fastline.surfaces.maps`), the isotropic spectrum
of a line scan (the Abel transform of :mod:`~fastline.surfaces.abel`) and a self-affine fit
(:mod:`~fastline.surfaces.fit`), all gathered in :mod:`~fastline.surfaces.topography` (also
``fastline.topography``), and the whole analysis of a scan (:mod:`~fastline.surfaces.scan`)."""

from __future__ import annotations

import lazy_loader as _lazy

#: what the other subpackages may use, by the module that defines it (loaded on first use)
__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submodules=["topography"],
    submod_attrs={
        "read": ["read_spectrum", "read_table"],
        "scan": ["LIMIT_RULES", "ScanSpectrum", "analyse_scan"],
    },
)
