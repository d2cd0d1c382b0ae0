"""Persson's contact theory and what it rests on: spectra, the theory and its variants,
pressure laws u(p), the asperity law, closed-form limits, the universal functions and the
statistics of the interface at a magnification zeta.

The bottom layer of the physics: it imports nothing of fastline but :mod:`fastline._lib` and
:mod:`fastline.errors`. Modules: :mod:`~fastline.theory.spectra`,
:mod:`~fastline.theory.persson`, :mod:`~fastline.theory.variants`,
:mod:`~fastline.theory.laws`, :mod:`~fastline.theory.calibrated` (a law calibrated on
boundary-element ensembles), :mod:`~fastline.theory.lawdata` (tabulated and calibrated laws as
plain arrays, for workers), :mod:`~fastline.theory.asperity`,
:mod:`~fastline.theory.limits`, :mod:`~fastline.theory.interface`,
:mod:`~fastline.theory.special` (the universal functions F), :mod:`~fastline.theory.files`
(spectrum files and the tolerant table reader), :mod:`~fastline.theory.tables`
(the compiled u(p) and p(u) tables), :mod:`~fastline.theory.quadrature`
(quadrature over tabulated spectra).
"""

from __future__ import annotations

import lazy_loader as _lazy

#: what the other subpackages may use, by the module that defines it (loaded on first use)
__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submod_attrs={
        "spectra": [
            "PSD",
            "SelfAffinePSD",
            "TabulatedPSD",
            "SumPSD",
            "effective_modulus",
            "check_modulus",
            "modulus_slip",
            "E_STAR_PLAUSIBLE",
        ],
        "files": ["Table", "parse_table", "read_spectrum", "read_table", "split_fields"],
        "quadrature": ["EtaRule", "interval_moments", "tabulated_quadrature"],
        "special": [
            "universal_F",
            "f_coefficients",
            "G0",
            "area_tables",
            "area_functions",
            "AreaTables",
        ],
        "variants": ["Variant", "VariantName", "VARIANTS", "DEFAULT_VARIANT", "get_variant"],
        "interface": [
            "CriticalGap",
            "apparent_area",
            "mean_separation",
            "edge_separation",
            "critical_gap",
            "THRESHOLD_PERSSON",
            "THRESHOLD_NUMERICAL",
            "THRESHOLD_BRUGGEMAN",
            "check_threshold",
            "gap_table",
            "interface_cache",
            "sealing_argument",
        ],
        "tables": ["PerssonTables", "pressure_at", "separation_at", "solver_law"],
        "persson": ["PerssonTheory", "ExponentialFit", "TableSettings", "GAMMA_RANGE"],
        "laws": [
            "PressureLaw",
            "PerssonLaw",
            "ExponentialLaw",
            "TabulatedLaw",
            "check_law",
            "hermite",
        ],
        "calibrated": ["CalibratedLaw", "CalibrationPoints", "isotonic_decreasing"],
        "lawdata": [
            "LawData",
            "LAW_KINDS",
            "law_data",
            "read_law_file",
            "restore_law",
            "check_law_scene",
        ],
        "asperity": ["SummitStatistics", "GreenwoodWilliamsonLaw", "summit_integral"],
        "limits": [
            "WS_GAUSSIAN",
            "WS_HERTZ",
            "WS_HERTZ_SPHERE",
            "GaussianLineContact",
            "GaussianPointContact",
            "HertzLineContact",
            "HertzPointContact",
            "alpha",
            "gaussian_line_contact",
            "gaussian_point_contact",
            "hertz_line_contact",
            "hertz_point_contact",
            "p0_ratio_gaussian",
            "p0_ratio_gaussian_sphere",
            "penetration",
            "hertz_line_unchecked",
            "gaussian_line_unchecked",
        ],
    },
)
