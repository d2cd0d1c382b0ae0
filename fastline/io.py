"""Files: measured spectra in, results out (CSV with the whole scene in its header).

Spectrum files hold two columns, wavenumber q [1/m] and isotropic power spectrum C(q) [m^4] in
Persson's convention (``h_rms^2 = 2 pi int q C dq``, docs/theory.md section 2), separated by
blanks, tabs, commas or semicolons, after any header lines; ``#`` starts a comment (the
tolerant table reader of :mod:`fastline.surfaces.read`, shared with the scan files).
:func:`read_spectrum` checks that the table is a plausible spectrum before it is used (a height
profile, x [m] against h [m], starts at x = 0 and is refused). :func:`write_spectrum` writes
such a table (``fastline psd --out``) with the measurement it came from in ``#`` header lines.

Result files are CSV: ``# key: value`` lines describing the scene (spectrum and where it came
from, its h_rms, rms slope and q range, E*, R, model, gamma, n, fastline version), then a
header row of column names with units, then rows written with full double precision.
:func:`read_csv` reads them back.

SI units throughout.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from fastline._lib.version import __version__
from fastline.errors import SpectrumFileError
from fastline.surfaces.read import read_spectrum
from fastline.theory.spectra import PSD, TabulatedPSD

if TYPE_CHECKING:  # annotations only: results of the layers above the spectra
    from fastline.contact.line import LineContactResult
    from fastline.contact.point import PointContactResult
    from fastline.leakage.flow import LeakResult

__all__ = [
    "SpectrumFileError",
    "read_spectrum",
    "spectrum_summary",
    "scene_metadata",
    "check_output_file",
    "check_output_dir",
    "write_csv",
    "write_profile_csv",
    "write_sweep_csv",
    "sweep_rows",
    "read_csv",
    "PROFILE_COLUMNS",
    "SWEEP_COLUMNS",
    "write_leak_csv",
    "write_leak_sweep_csv",
    "leak_metadata",
    "leak_sweep_rows",
    "strip_causes",
    "LEAK_COLUMNS",
    "LEAK_SWEEP_COLUMNS",
    "POINT_LEAK_COLUMNS",
    "POINT_LEAK_SWEEP_COLUMNS",
    "POINT_PROFILE_COLUMNS",
    "POINT_SWEEP_COLUMNS",
    "write_point_profile_csv",
    "write_point_sweep_csv",
    "SPECTRUM_COLUMNS",
    "write_spectrum",
]

#: columns of :func:`write_profile_csv`
PROFILE_COLUMNS = ("x_m", "p_Pa", "u_m")
#: columns of :func:`write_point_profile_csv` (a point contact: r from the axis)
POINT_PROFILE_COLUMNS = ("r_m", "p_Pa", "u_m")
#: columns of :func:`write_point_sweep_csv` (the load F on a sphere in N)
POINT_SWEEP_COLUMNS = (
    "load_N",
    "alpha",
    "p0_Pa",
    "p0_ratio",
    "s_m",
    "w_m",
    "w_over_s",
    "converged",
)
#: columns of :func:`write_spectrum` (written as a comment: the file stays a two-column table)
SPECTRUM_COLUMNS = ("q_1_per_m", "C_m4")
#: columns of :func:`write_sweep_csv`
SWEEP_COLUMNS = (
    "load_N_per_m",
    "alpha",
    "p0_Pa",
    "p0_ratio",
    "s_m",
    "w_m",
    "w_over_s",
    "converged",
)

#: columns of :func:`write_leak_csv` (one row per strip of the contact)
LEAK_COLUMNS = (
    "x_m",
    "p_Pa",
    "u_c_m",
    "sigma_m3_per_Pa_s",
    "resistance_share",
    "cumulative_share",
    "sealed",
    "sealed_by",
)
#: columns of :func:`write_leak_sweep_csv` (one row per load)
LEAK_SWEEP_COLUMNS = (
    "load_N_per_m",
    "alpha",
    "p0_Pa",
    "Q_m3_per_s",
    "conductance_m2_per_Pa_s",
    "sealed",
    "sealed_by",
    "share_in_fwhm",
    "resistance_width_m",
    "min_gap_m",
    "converged",
)
#: columns of :func:`write_leak_csv` for radial flow (a point contact: rings at r from the axis)
POINT_LEAK_COLUMNS = ("r_m", *LEAK_COLUMNS[1:])
#: columns of :func:`write_leak_sweep_csv` for radial flow (the load F on a sphere in N; the
#: conductance of the whole contact, not per unit seal length)
POINT_LEAK_SWEEP_COLUMNS = tuple(
    {"load_N_per_m": "load_N", "conductance_m2_per_Pa_s": "conductance_m3_per_Pa_s"}.get(c, c)
    for c in LEAK_SWEEP_COLUMNS
)


def spectrum_summary(psd: PSD) -> dict:
    """h_rms [m], rms slope [-] and the wavenumber range [1/m] of a spectrum.

    Returns
    -------
    dict
        ``h_rms``, ``rms_slope``, ``q0``, ``q1`` and ``longest_wavelength`` (``2 pi / q0``, m).
    """
    return {
        "h_rms": float(psd.h_rms),
        "rms_slope": float(psd.rms_slope),
        "q0": float(psd.q0),
        "q1": float(psd.q1),
        "longest_wavelength": float(2.0 * np.pi / psd.q0),
    }


def scene_metadata(
    psd: PSD | None,
    E_star: float,
    radius: float,
    *,
    model: str,
    gamma: float,
    n: int,
    source: str | None = None,
    **extra: object,
) -> dict:
    """The ``key: value`` lines of a result file's header (see :func:`write_csv`).

    Parameters
    ----------
    psd : PSD or None
        The spectrum (None for smooth surfaces).
    E_star, radius : float
        Effective modulus in Pa and cylinder radius in m.
    model : str
        ``"persson"``, ``"exponential"`` or ``"hertz"``.
    gamma : float
        Yang-Persson parameter of the theory.
    n : int
        Grid points.
    source : str, optional
        The spectrum file the spectrum was read from.
    **extra
        Further entries (e.g. the load), written after these.
    """
    meta: dict = {"fastline_version": __version__}
    if psd is None:
        meta["spectrum"] = "none (smooth surfaces)"
    else:
        meta["spectrum"] = f"file {source}" if source else repr(psd)
        s = spectrum_summary(psd)
        meta["h_rms_m"] = s["h_rms"]
        meta["rms_slope"] = s["rms_slope"]
        meta["q0_1_per_m"] = s["q0"]
        meta["q1_1_per_m"] = s["q1"]
    meta.update(E_star_Pa=float(E_star), radius_m=float(radius), model=model, gamma=float(gamma))
    meta["n"] = int(n)
    meta.update(extra)
    return meta


def _quoted(text: str) -> str:
    """A text cell as CSV writes it (RFC 4180): in double quotes, inner quotes doubled, when
    it holds a comma, a quote, a line break or outer blanks; else as it is."""
    if any(c in text for c in ',"\r\n') or text != text.strip():
        return '"' + text.replace('"', '""') + '"'
    return text


def _fmt(v) -> str:
    if isinstance(v, bool | np.bool_):
        return str(int(v))
    if isinstance(v, str):
        return _quoted(v)
    if isinstance(v, int | np.integer):
        return str(int(v))
    return repr(float(v))


def check_output_file(path: str | os.PathLike) -> str:
    """Check, before any work, that a file can be written at ``path``; returns it as str.

    Raises
    ------
    ValueError
        When the path is a directory, its directory does not exist or is not writable.
    """
    path = os.fspath(path)
    if os.path.isdir(path):
        raise ValueError(f"{path} is a directory, not a file")
    parent = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(parent):
        raise ValueError(f"cannot write {path}: directory {parent} does not exist")
    if not os.access(parent, os.W_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
        raise ValueError(f"cannot write {path}: permission denied")
    return path


def check_output_dir(path: str | os.PathLike) -> str:
    """Create the directory ``path`` if needed and check it is writable; returns it as str.

    Raises
    ------
    ValueError
        When it cannot be created or written to.
    """
    path = os.fspath(path)
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise ValueError(f"cannot create directory {path}: {e.strerror}") from None
    if not os.access(path, os.W_OK):
        raise ValueError(f"cannot write to directory {path}: permission denied")
    return path


def write_csv(
    path: str | os.PathLike,
    columns: Sequence[str],
    rows: Iterable[Sequence],
    meta: Mapping | None = None,
    title: str | None = None,
) -> None:
    """Write a CSV result file: ``# title``, ``# key: value`` lines, header row, rows.

    Numbers are written with full double precision (``repr``), booleans as 0/1.
    """
    path = os.fspath(path)
    try:
        with open(path, "w", encoding="utf-8") as fh:
            if title:
                for line in title.splitlines():
                    fh.write(f"# {line}\n")
            for k, v in (meta or {}).items():
                fh.write(f"# {k}: {v if isinstance(v, str) else _fmt(v)}\n")
            fh.write(",".join(columns) + "\n")
            for row in rows:
                fh.write(",".join(_fmt(v) for v in row) + "\n")
    except OSError as e:
        raise ValueError(f"cannot write {path}: {e.strerror}") from None


def _is_point(result) -> bool:
    """Whether ``result`` is a point contact's (it has a Hertz radius): else a line contact's,
    or a row of a table sweep."""
    return hasattr(result, "hertz_radius")


def write_profile_csv(
    path: str | os.PathLike,
    result: LineContactResult | PointContactResult,
    meta: Mapping | None = None,
) -> None:
    """Write p(x) of one result: columns ``x_m, p_Pa, u_m``; ``meta`` as the header.

    The load, alpha, p0, p0 / p0_Hertz, widths and convergence of the result are added to the
    header. A point contact's result is written as :func:`write_point_profile_csv` writes it
    (p(r), the load in N).
    """
    if _is_point(result):
        write_point_profile_csv(path, result, meta)
        return
    if not (hasattr(result, "x") and hasattr(result, "p0_ratio")):
        raise TypeError(
            f"expected a LineContactResult or PointContactResult, got {type(result).__name__}"
        )
    info = dict(meta or {})
    info.update(
        load_N_per_m=result.load,
        alpha=result.alpha,
        p0_Pa=result.p0,
        p0_ratio=result.p0_ratio,
        s_m=result.s,
        w_m=result.fwhm,
        w_over_s=result.w_over_s,
        converged=result.converged,
    )
    rows = zip(result.x, result.pressure, result.separation, strict=True)
    write_csv(path, PROFILE_COLUMNS, rows, info, title="fastline profile: p(x) and u(x)")


def sweep_rows(results: Iterable) -> list[tuple]:
    """One row of :data:`SWEEP_COLUMNS` per result."""
    return [
        (r.load, r.alpha, r.p0, r.p0_ratio, r.s, r.fwhm, r.w_over_s, r.converged) for r in results
    ]


def write_sweep_csv(
    path: str | os.PathLike, results: Sequence, meta: Mapping | None = None
) -> None:
    """Write a load sweep: one row per result, columns :data:`SWEEP_COLUMNS`; a point
    contact's sweep as :func:`write_point_sweep_csv` writes it (the load in N)."""
    results = list(results)
    kinds = {_is_point(r) for r in results}
    if len(kinds) > 1:
        raise ValueError("results mix line and point contacts: write each sweep on its own")
    if kinds == {True}:
        write_point_sweep_csv(path, results, meta)
        return
    write_csv(path, SWEEP_COLUMNS, sweep_rows(results), meta, title="fastline sweep")


def write_point_profile_csv(
    path: str | os.PathLike, result: PointContactResult, meta: Mapping | None = None
) -> None:
    """Write p(r) of a point contact: columns ``r_m, p_Pa, u_m``; ``meta`` as the header.

    The load F [N], alpha, p0, p0 / p0_Hertz (the sphere's), widths (s, the FWHM along a
    diameter w), the Hertz radius, the radius holding 99 % of the load and the radius where p
    falls to 1 % of p0 are added to the header.
    """
    info = dict(meta or {})
    info.update(
        geometry="sphere",
        load_N=result.load,
        alpha=result.alpha,
        p0_Pa=result.p0,
        p0_ratio=result.p0_ratio,
        s_m=result.s,
        w_m=result.fwhm,
        w_over_s=result.w_over_s,
        hertz_radius_m=result.hertz_radius,
        load_radius_99_m=result.load_radius(0.99),
        pressure_radius_1pct_m=result.pressure_radius(0.01),
        converged=result.converged,
    )
    rows = zip(result.r, result.pressure, result.separation, strict=True)
    write_csv(path, POINT_PROFILE_COLUMNS, rows, info, title="fastline profile: p(r) and u(r)")


def write_point_sweep_csv(
    path: str | os.PathLike, results: Sequence, meta: Mapping | None = None
) -> None:
    """Write a point-contact load sweep: one row per result, columns
    :data:`POINT_SWEEP_COLUMNS` (the same numbers as :func:`sweep_rows`, the load in N)."""
    info = {**(meta or {}), "geometry": "sphere"}
    write_csv(path, POINT_SWEEP_COLUMNS, sweep_rows(results), info, title="fastline sweep")


def read_csv(path: str | os.PathLike) -> tuple[dict, dict]:
    """Read a file written by :func:`write_csv`.

    Returns
    -------
    meta : dict
        The ``# key: value`` header entries (values as strings).
    columns : dict
        Column name -> float ndarray (non-numeric columns as arrays of str).
    """
    meta: dict = {}
    lines = []
    with open(os.fspath(path), encoding="utf-8", newline="") as fh:
        for line in fh:
            if line.startswith("#"):
                key, sep, value = line[1:].strip().partition(": ")
                if sep and key.isidentifier():
                    meta[key] = value
            elif line.strip():
                lines.append(line)
    names, *body = csv.reader(lines)  # quoted text cells may hold commas
    columns = {}
    for j, name in enumerate(names):
        col = [row[j] for row in body]
        try:
            columns[name] = np.array([float(v) for v in col])
        except ValueError:
            columns[name] = np.array(col)
    return meta, columns


def leak_metadata(leak: LeakResult) -> dict:
    """The inputs of a leak rate as header entries: ``pressure_drop_Pa``, ``viscosity_Pa_s``,
    ``length_m`` (radial flow: ``inner_radius_m`` instead), ``threshold``, ``method`` and
    ``gap_floor_m``, the molecular floor of the gap (0: none), which with the threshold says
    how a strip was judged sealed (add ``mean_free_path_m`` yourself when used)."""
    path = (
        {"length_m": float(leak.length)}
        if leak.inner_radius is None
        else {"inner_radius_m": float(leak.inner_radius)}
    )
    return {
        "pressure_drop_Pa": float(leak.pressure_drop),
        "viscosity_Pa_s": float(leak.viscosity),
        **path,
        "threshold": float(leak.threshold),
        "method": str(leak.method),
        "gap_floor_m": float(leak.gap_floor),
    }


def strip_causes(leak: LeakResult) -> list[str]:
    """Per strip (ring) of a leak rate, what seals it: ``"percolation"``, ``"gap floor"``, or
    ``""`` where it is open (the ``sealed_by`` column of :func:`write_leak_csv`)."""
    floor = leak.floor_strips
    if floor.shape != leak.sealed_strips.shape:  # a LeakResult made without the split
        floor = np.zeros(leak.sealed_strips.shape, dtype=bool)
    return [
        ("gap floor" if f else "percolation") if s else ""
        for s, f in zip(leak.sealed_strips, floor, strict=True)
    ]


def write_leak_csv(
    path: str | os.PathLike,
    leak: LeakResult,
    meta: Mapping | None = None,
    *,
    result: LineContactResult | PointContactResult | None = None,
) -> None:
    """Write where along the contact a seal leaks: one row per strip, :data:`LEAK_COLUMNS`
    (radial flow, ``leak.inner_radius`` set: one row per ring, :data:`POINT_LEAK_COLUMNS`).

    Columns: strip centre x [m] (radial flow: the ring's radius r [m]), nominal pressure p [Pa],
    critical gap u_c [m] (the method's local gap, :attr:`LeakResult.u_c`: 0 where the real
    contact area percolates, the sub-molecular gap below ``gap_floor`` where the floor seals,
    ``inf`` where p = 0), local conductance sigma [m^3/(Pa s)] (that of u_c; the sealed column
    says which strips carry no flow), the strip's share of the flow resistance and its running
    sum, whether the strip is sealed (0/1) and by what (``sealed_by``: ``percolation``, ``gap
    floor``, empty where open; :func:`strip_causes`).

    Parameters
    ----------
    path : str or path-like
    leak : LeakResult
        From :func:`fastline.leak_rate`.
    meta : mapping, optional
        The scene (:func:`scene_metadata`); the leak's inputs (:func:`leak_metadata`) and its
        results (Q [m^3/s], conductance [m^2/(Pa s)], sealed, share in the FWHM, 90 % width
        [m]; when sealed, ``sealed_by``, :attr:`LeakResult.sealed_by`) are added.
    result : LineContactResult or PointContactResult, optional
        The solve the leak rate post-processes: its load (``load_N_per_m``, a point contact's
        ``load_N``), alpha and p0 are added.
    """
    radial = leak.inner_radius is not None
    rows = zip(
        leak.x,
        leak.pressure,
        leak.u_c,
        leak.sigma,
        leak.resistance_share,
        leak.cumulative_share,
        leak.sealed_strips,
        strip_causes(leak),
        strict=True,
    )
    title = (
        "fastline leak: p(r), critical gap u_c(r) and where the flow resistance sits (radial)"
        if radial
        else "fastline leak: p(x), critical gap u_c(x) and where the flow resistance sits"
    )
    columns = POINT_LEAK_COLUMNS if radial else LEAK_COLUMNS
    write_csv(path, columns, rows, _leak_header(leak, meta, result), title=title)


def _leak_header(leak: LeakResult, meta: Mapping | None, result) -> dict:
    """The header of :func:`write_leak_csv`: the scene, the solve, the inputs, the results."""
    radial = leak.inner_radius is not None
    info = dict(meta or {})
    if result is not None:
        load_key = "load_N" if radial else "load_N_per_m"
        info.update({load_key: result.load, "alpha": result.alpha, "p0_Pa": result.p0})
    info.update(leak_metadata(leak))
    unit = "m3_per_Pa_s" if radial else "m2_per_Pa_s"  # the whole contact / per unit length
    info[f"conductance_{unit}"] = leak.conductance
    info.update(
        Q_m3_per_s=leak.Q,
        sealed=leak.sealed,
        share_in_fwhm=leak.share_in_fwhm,
        resistance_width_m=leak.resistance_width,
        converged=leak.converged,
    )
    if leak.sealed:
        info["sealed_by"] = leak.sealed_by
    return info


def _resistance_columns(leak: LeakResult) -> tuple[float, float]:
    """``share_in_fwhm, resistance_width`` of a leak sweep's row: NaN (a missing value, as the
    printed table's "-") when sealed, where the resistance is infinite and where it sits means
    nothing."""
    if leak.sealed:
        return math.nan, math.nan
    return leak.share_in_fwhm, leak.resistance_width


def leak_sweep_rows(results: Iterable, leaks: Iterable) -> list[tuple]:
    """One row of :data:`LEAK_SWEEP_COLUMNS` per (LineContactResult, LeakResult) pair (of
    :data:`POINT_LEAK_SWEEP_COLUMNS` per (PointContactResult, LeakResult) pair: the same
    numbers, the load in N); sealed_by is the leak's cause of sealing (``"percolation"``, ``"gap
    floor"``, ``""`` where it leaks), share_in_fwhm and resistance_width_m NaN at sealed
    loads."""
    return [
        (
            r.load,
            r.alpha,
            r.p0,
            k.Q,
            k.conductance,
            k.sealed,
            k.sealed_by or "",
            *_resistance_columns(k),
            k.diagnostics["min_gap"],
            r.converged,
        )
        for r, k in zip(results, leaks, strict=True)
    ]


def write_leak_sweep_csv(
    path: str | os.PathLike, results: Sequence, leaks: Sequence, meta: Mapping | None = None
) -> None:
    """Write leak rate against load: one row per load, columns :data:`LEAK_SWEEP_COLUMNS`
    (radial flow out of a point contact: :data:`POINT_LEAK_SWEEP_COLUMNS`, the load F in N and
    the conductance of the whole contact).

    ``results`` and ``leaks`` are the solves and their leak rates, in the same order; the
    leak's inputs (:func:`leak_metadata`, from the first) are added to ``meta``. At sealed
    loads Q and min_gap_m are 0, and share_in_fwhm and resistance_width_m are ``nan`` (the
    resistance is infinite: where it sits means nothing; the printed table shows "-").
    """
    leaks = list(leaks)
    if not leaks:
        raise ValueError("leaks must hold at least one LeakResult")
    info = {**dict(meta or {}), **leak_metadata(leaks[0])}
    rows = leak_sweep_rows(results, leaks)
    columns = LEAK_SWEEP_COLUMNS if leaks[0].inner_radius is None else POINT_LEAK_SWEEP_COLUMNS
    write_csv(path, columns, rows, info, title="fastline leak --sweep: Q against load")


def write_spectrum(
    path: str | os.PathLike,
    psd: TabulatedPSD,
    meta: Mapping | None = None,
    title: str | None = None,
) -> None:
    """Write a spectrum table that :func:`read_spectrum` (and ``--psd``) reads back exactly.

    ``# title`` and ``# key: value`` lines, the column names as a comment (``# q_1_per_m,C_m4``),
    then one ``q,C`` row per table point with full double precision: q [1/m], C(q) [m^4] in
    Persson's convention. The spectrum's h_rms, rms slope and q range are added to the header.

    Parameters
    ----------
    path : str or path-like
    psd : TabulatedPSD
        The table to write (its points ``psd.q``, ``psd.C``).
    meta : mapping, optional
        Header entries (e.g. how the spectrum was measured), written before the summary.
    title : str, optional
    """
    if not isinstance(psd, TabulatedPSD):
        raise TypeError(f"psd must be a TabulatedPSD, got {type(psd).__name__}")
    s = spectrum_summary(psd)
    info = {**(meta or {}), "h_rms_m": s["h_rms"], "rms_slope": s["rms_slope"]}
    info.update(q0_1_per_m=s["q0"], q1_1_per_m=s["q1"], points=int(psd.q.size))
    path = os.fspath(path)
    try:
        with open(path, "w", encoding="utf-8") as fh:
            for line in (title or "").splitlines():
                fh.write(f"# {line}\n")
            for k, v in info.items():
                fh.write(f"# {k}: {v if isinstance(v, str) else _fmt(v)}\n")
            fh.write("# " + ",".join(SPECTRUM_COLUMNS) + "\n")
            for q, C in zip(psd.q, psd.C, strict=True):
                fh.write(f"{_fmt(q)},{_fmt(C)}\n")
    except OSError as e:
        raise ValueError(f"cannot write {path}: {e.strerror}") from None
