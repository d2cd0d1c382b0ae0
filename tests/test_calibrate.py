"""The calibrated law: its fit and joins, its file, fl.calibrate against the plain BEM
ensemble, the solvers and the leak rate with it, and the command line.

Tolerances are named by what limits them: the CCG tolerance (the calibration's warm-started
solves against cold ones), round-off (the same Hermite cells), the monotone Hermite's
interpolation error (a law fed another law's points).
"""

from __future__ import annotations

import json
import math
import zipfile
from contextlib import redirect_stderr, redirect_stdout
from io import StringIO

import naive
import numpy as np
import pytest

import fastline as fl
from fastline import bem
from fastline.bem import calibration
from fastline.cli.app import main
from fastline.theory.calibrated import CalibrationPoints, isotonic_decreasing

#: warm-started and cold CCG solves of one surface (tol 1e-9 on the pressure change)
SOLVER_AGREEMENT = 1e-6
#: the warm-started flow of a calibration (CG to a relative residual 1e-8, conductance from the
#: dissipation) against the sparse LU
FLOW_AGREEMENT = 1e-7
#: the same Hermite cells evaluated twice (round-off of ln p -> p -> ln p)
ROUND_OFF = 1e-12
#: a law through 3 points per decade of another smooth law, between its nodes
INTERPOLATION = 3e-3
#: the cube of a gap interpolated as a piecewise power law through 3 points per decade
GAP_CUBED_INTERPOLATION = 1e-2

E_STAR = 10e6
Q0 = 2 * math.pi / 40e-6
PSD = fl.SelfAffinePSD(0.5e-6, 0.8, Q0, Q0, 4 * Q0)
PRESSURES = np.array([1e3, 5e3, 2e4, 8e4])


@pytest.fixture(scope="module")
def theory():
    return fl.PerssonTheory(PSD, E_STAR)


@pytest.fixture(scope="module")
def calibrated():
    """A small calibration: 32 x 32 cells, 3 surfaces, 4 pressures, the finer check."""
    return fl.calibrate(PSD, E_STAR, PRESSURES, realizations=3, periods=2)


def _points(theory, p, u_scale=1.0, gap_scale=1.0, u_error=0.01):
    u = theory.separation(p) * u_scale
    g = theory.critical_gap(p).u_c * gap_scale
    a = theory.contact_area(p)
    return CalibrationPoints(p, u, u_error * u, a, 0 * p, g, 0.02 * g, g, 0.02 * g)


# ---- the fit ----------------------------------------------------------------------------------
def test_isotonic_regression_pools_violators_into_weighted_means():
    fit, block = isotonic_decreasing([3.0, 1.0, 2.0, 0.0], [1.0, 1.0, 1.0, 1.0])
    np.testing.assert_array_equal(fit, [3.0, 1.5, 1.5, 0.0])
    np.testing.assert_array_equal(block, [0, 1, 1, 2])
    fit, _ = isotonic_decreasing([1.0, 2.0, 3.0], [1.0, 1.0, 2.0])
    np.testing.assert_allclose(fit, 2.25, rtol=ROUND_OFF)


def test_fit_is_monotone_and_continuous_across_the_joins(theory):
    p = np.geomspace(1e3, 1e5, 7)
    law = fl.CalibratedLaw(_points(theory, p, u_scale=0.9), PSD, E_STAR)
    v = np.linspace(math.log(1e-2), math.log(1e8), 4001)
    u, dudv = law.separation_and_slope(v)
    assert np.all(dudv < 0.0) and np.all(np.diff(u) < 0.0)
    for end in law.p_range:  # value and slope continuous at the joins
        (a, b), (da, db) = law.separation_and_slope(np.log(end) + np.array([-1e-9, 1e-9]))
        assert abs(a - b) < 1e-6 * a and abs(da - db) < 1e-6 * abs(da)
    # the stated rule outside: Persson's u scaled to meet the fit (a node a decade out)
    for far in (1e2, 1e6):
        ratio = 0.9  # the fit's end value over Persson's there
        got = law.separation_and_slope(np.log([far]))[0][0]
        assert got == pytest.approx(ratio * theory.separation(far), rel=ROUND_OFF * 100)
    h = law.hydraulic_gap(np.geomspace(1e1, 1e5, 200))
    assert np.all(np.diff(h[h > 0]) < 0.0)


def test_calibrated_law_reproduces_a_tabulated_law_fed_its_own_points(theory):
    p = np.geomspace(1e2, 1e5, 10)
    u = theory.separation(p)
    table = fl.TabulatedLaw(u, p)
    law = fl.CalibratedLaw(_points(theory, p, u_error=1e-4), PSD, E_STAR)
    v = np.linspace(np.log(p[1]), np.log(p[-2]), 301)  # cells with the same end slopes
    np.testing.assert_allclose(
        law.separation_and_slope(v)[0], table.separation_and_slope(v)[0], rtol=ROUND_OFF
    )
    v = np.linspace(np.log(p[0]), np.log(p[-1]), 301)  # and the Persson law it was fed
    np.testing.assert_allclose(
        law.separation_and_slope(v)[0], theory.separation(np.exp(v)), rtol=INTERPOLATION
    )


def test_joins_continue_the_fit_with_its_own_end_slopes(theory):
    """A known law of another shape than Persson's, ``u = A u_P(p)^m`` (m = 1/2: the flatter
    u(p) of a boundary-element ensemble at low pressure), fed its points on 1e2-1e5 Pa: the
    calibrated law reproduces it outside the range too, and a cylinder whose flanks lie below
    the range comes out as with the known law tabulated densely (the value-only join of
    Persson's u_P, slope 1/m times too steep below the range, widened it)."""
    A, m = 0.8e-3, 0.5
    p_all = np.geomspace(1e-3, 1e7, 81)
    known = fl.TabulatedLaw(A * theory.separation(p_all) ** m, p_all)
    p = np.geomspace(1e2, 1e5, 10)
    u = A * theory.separation(p) ** m
    a = theory.contact_area(p)
    g = theory.critical_gap(p).u_c
    pts = CalibrationPoints(p, u, 1e-4 * u, a, 0 * p, g, 0.02 * g, g, 0.02 * g)
    law = fl.CalibratedLaw(pts, PSD, E_STAR)
    v = np.linspace(math.log(1e-2), math.log(1e6), 601)
    np.testing.assert_allclose(
        law.separation_and_slope(v)[0], known.separation_and_slope(v)[0], rtol=INTERPOLATION
    )
    f = 0.5  # N/m: Hertz p0 7 kPa, the flanks of the profile below 1e2 Pa
    a, b = (fl.solve_line_contact(PSD, E_STAR, 0.0328, f, model=x, n=256) for x in (law, known))
    assert np.any(a.pressure[a.pressure > 0.0] < p[0])
    assert a.s == pytest.approx(b.s, rel=INTERPOLATION)
    assert a.p0 == pytest.approx(b.p0, rel=INTERPOLATION)


def test_rise_beyond_the_errors_is_refused_and_within_them_pooled(theory):
    p = np.geomspace(1e3, 1e5, 5)
    pts = _points(theory, p)
    u = pts.u.copy()
    u[2] = u[1] * (1 + 0.005)  # a rise of half a standard error: noise, pooled
    law = fl.CalibratedLaw(CalibrationPoints(p, u, *_rest(pts)), PSD, E_STAR)
    assert np.all(law.separation_and_slope(np.log(p))[1] < 0.0)
    u[2] = u[1] * 1.2  # twenty standard errors
    with pytest.raises(ValueError, match="not monotone within its errors"):
        fl.CalibratedLaw(CalibrationPoints(p, u, *_rest(pts)), PSD, E_STAR)


def _rest(pts):
    return (
        pts.u_error,
        pts.contact_fraction,
        pts.contact_fraction_error,
        pts.gap_x,
        pts.gap_x_error,
        pts.gap_y,
        pts.gap_y_error,
    )


# ---- the file ---------------------------------------------------------------------------------
def test_save_load_round_trip(calibrated, tmp_path):
    path = tmp_path / "law.npz"
    calibrated.save(path)
    back = fl.CalibratedLaw.load(path, psd=PSD, E_star=E_STAR)
    v = np.linspace(np.log(1.0), np.log(1e7), 200)
    np.testing.assert_array_equal(
        back.separation_and_slope(v)[0], calibrated.separation_and_slope(v)[0]
    )
    p = np.geomspace(1.0, 1e6, 50)
    for direction in ("x", "y", "mean"):
        np.testing.assert_array_equal(
            back.hydraulic_gap(p, direction), calibrated.hydraulic_gap(p, direction)
        )
    np.testing.assert_array_equal(back.real_area(p), calibrated.real_area(p))
    assert back.settings == calibrated.settings and back.p_range == calibrated.p_range
    alone = fl.CalibratedLaw.load(path)  # its own record of the spectrum
    assert alone.psd.h_rms == pytest.approx(PSD.h_rms, rel=1e-9)


def test_load_refuses_another_scene_a_corrupt_file_and_another_format(calibrated, tmp_path):
    path = tmp_path / "law.npz"
    calibrated.save(path)
    with pytest.raises(fl.CalibrationFileError, match="E\\* = 1e\\+07 Pa, not"):
        fl.CalibratedLaw.load(path, E_star=2 * E_STAR)
    other = fl.SelfAffinePSD(0.6e-6, 0.8, Q0, Q0, 4 * Q0)
    with pytest.raises(fl.CalibrationFileError, match="another spectrum"):
        fl.CalibratedLaw.load(path, psd=other)
    with np.load(path) as f:
        arrays = {k: f[k] for k in f.files}
    bad = dict(arrays, U=arrays["U"] * (1 + 1e-12))
    np.savez(tmp_path / "edited.npz", **bad)
    with pytest.raises(fl.CalibrationFileError, match="checksum"):
        fl.CalibratedLaw.load(tmp_path / "edited.npz")
    meta = json.loads(str(arrays["metadata"]))
    meta["format"] = "fastline-calibrated-law/0"
    np.savez(tmp_path / "old.npz", **dict(arrays, metadata=np.array(json.dumps(meta))))
    with pytest.raises(fl.CalibrationFileError, match="format is 'fastline-calibrated-law/0'"):
        fl.CalibratedLaw.load(tmp_path / "old.npz")
    np.savez(tmp_path / "pickled.npz", metadata=np.array([{"a": 1}], dtype=object))
    with pytest.raises(fl.CalibrationFileError, match="holds Python objects") as info:
        fl.CalibratedLaw.load(tmp_path / "pickled.npz")
    assert "allow_pickle" not in str(info.value)  # no invitation to load it unsafely
    (tmp_path / "text.npz").write_text("not an archive")
    (tmp_path / "bytes.dat").write_bytes(bytes(range(32)))
    for name in ("text.npz", "bytes.dat"):
        with pytest.raises(fl.CalibrationFileError, match="not a .npz archive") as info:
            fl.CalibratedLaw.load(tmp_path / name)
        assert "not a fastline calibrated-law file" in str(info.value)
    assert zipfile.is_zipfile(path)


# ---- the calibration ---------------------------------------------------------------------------
def test_calibration_equals_cold_flat_ensembles_of_the_same_surfaces(calibrated):
    """The warm-started calibration against cold solves of the same surfaces: the contact
    fraction and the effective gap averaged at each pressure, the mean gap averaged at a fixed
    gap (the loops of tests/naive.py), which differs from the mean at a fixed pressure on this
    small cell."""
    pts = calibrated.points
    seeds = np.random.SeedSequence(0).spawn(3)
    runs = []
    for p in PRESSURES:
        scene = bem.flat_contact_scene(PSD, E_STAR, float(p), periods=2)
        runs.append([bem.run_realization(s, scene) for s in seeds])
    u = np.array([[r.mean_gap for r in at_p] for at_p in runs]).T  # surface x pressure
    np.testing.assert_allclose(pts.u, naive.fixed_gap_mean(u, PRESSURES), rtol=SOLVER_AGREEMENT)
    assert np.max(np.abs(pts.u / u.mean(axis=0) - 1.0)) > 10 * SOLVER_AGREEMENT
    for k, at_p in enumerate(runs):
        area = np.mean([r.contact_fraction for r in at_p])
        assert pts.contact_fraction[k] == pytest.approx(area, abs=1e-12)
        g = np.cbrt(12e-3 * np.mean([r.conductance for r in at_p]))
        assert pts.gap_x[k] == pytest.approx(g, rel=SOLVER_AGREEMENT)
    assert np.all(pts.gap_y > 0.0) and np.all(np.diff(pts.u) < 0.0)


def test_calibration_reports_its_resolution_cost_and_check(calibrated):
    st = calibrated.settings
    assert st["grid"]["cells_per_wavelength"] == pytest.approx(4.0)
    assert st["grid"]["periods"] == pytest.approx(2.0)
    assert st["solves"]["solves"] == 3 * PRESSURES.size and st["solves"]["converged"]
    chk = st["check"]
    assert chk["kind"] == "finer" and chk["grid"][:2] == [64, 64] and len(chk["p"]) == 3
    assert calibrated.p_range == pytest.approx((PRESSURES[0], PRESSURES[-1]), rel=ROUND_OFF)


def test_calibrate_refuses_bad_input():
    with pytest.raises(ValueError, match="points_per_wavelength must be >= 4"):
        fl.calibrate(PSD, E_STAR, PRESSURES, points_per_wavelength=3)
    coarse = bem.Grid(8, 8, 5e-6, 5e-6)
    with pytest.raises(ValueError, match="cells per shortest wavelength"):
        fl.calibrate(PSD, E_STAR, PRESSURES, grid=coarse)
    with pytest.raises(ValueError, match="at least 3 distinct"):
        fl.calibrate(PSD, E_STAR, [1e3, 1e4])
    with pytest.raises(ValueError, match="radius"):
        fl.calibrate(PSD, E_STAR)
    with pytest.raises(ValueError, match="check must be one of"):
        fl.calibrate(PSD, E_STAR, PRESSURES, check="coarser")
    with pytest.raises(TypeError, match="progress must be True, False, None or a callable"):
        fl.calibrate(PSD, E_STAR, PRESSURES, progress="yes")


@pytest.mark.parametrize(
    "kwargs, error, needle",
    [
        (dict(geometry="x"), ValueError, "geometry must be 'line' or 'point'"),
        (dict(n_pressures=0), ValueError, "n_pressures"),
        (dict(n_pressures=1.5), ValueError, "n_pressures"),
        (dict(realizations=10**9), ValueError, "realizations"),
        (dict(points_per_wavelength=1e3), ValueError, "more than 16,777,216"),
        (dict(periods=1e4), ValueError, "more than 16,777,216"),
        (dict(grid=bem.Grid(4096, 4096, 1e-7, 1e-7)), ValueError, "companion grid"),
        (dict(seed=-1), ValueError, "seed"),
    ],
)
def test_calibrate_refuses_before_any_work(kwargs, error, needle, monkeypatch):
    """Every argument is checked before the first surface is drawn: given pressures do not
    skip the checks of the other arguments, and grids or ensembles too large to hold or to
    finish are refused by what sets their size."""
    monkeypatch.setattr(calibration, "random_surface", _no_work)
    with pytest.raises(error, match=needle):
        fl.calibrate(PSD, E_STAR, PRESSURES, **kwargs)
    with pytest.raises(ValueError, match="loads must hold at least one"):
        fl.calibrate(PSD, E_STAR, radius=0.01, loads=[])


def _no_work(*args, **kwargs):
    raise AssertionError("a surface was drawn before the arguments were checked")


def test_calibrate_progress_bar_or_callback(capsys):
    small = dict(realizations=2, periods=1, check=None)
    fl.calibrate(PSD, E_STAR, PRESSURES, progress=True, **small)
    assert "calibration" in capsys.readouterr().err
    fl.calibrate(PSD, E_STAR, PRESSURES, progress=False, **small)
    assert capsys.readouterr().err == ""
    calls = []
    fl.calibrate(PSD, E_STAR, PRESSURES, progress=lambda d, t: calls.append((d, t)), **small)
    assert calls == [(1, 2), (2, 2)]


def test_pressure_range_follows_the_scenes():
    lo, hi = bem.pressure_range(PSD, E_STAR, 0.0328, [1.0, 100.0])
    h = [fl.hertz_line_contact(E_STAR, 0.0328, f).p0 for f in (1.0, 100.0)]
    assert lo == pytest.approx(0.01 * h[0]) and hi == pytest.approx(1.5 * h[1])


# ---- the law in the solvers and the leak rate ------------------------------------------------
def test_calibrated_solve_is_a_tabulated_solve_and_fed_persson_gives_persson(calibrated, theory):
    R, f = 0.0328, 5.0
    a = fl.solve_line_contact(PSD, E_STAR, R, f, model=calibrated, n=256)
    table = fl.TabulatedLaw(calibrated._U, np.exp(calibrated._V))
    b = fl.solve_line_contact(PSD, E_STAR, R, f, model=table, n=256)
    assert a.converged and a.model == "calibrated"
    np.testing.assert_allclose(a.pressure, b.pressure, rtol=1e-9, atol=1e-9 * a.p0)
    assert np.trapezoid(a.pressure, a.x) == pytest.approx(f, rel=1e-6)
    p = np.geomspace(1e2, 1e5, 10)
    law = fl.CalibratedLaw(_points(theory, p), PSD, E_STAR)
    c = fl.solve_line_contact(PSD, E_STAR, R, f, model=law, n=256)
    d = fl.solve_line_contact(PSD, E_STAR, R, f, model="persson", n=256)
    assert c.p0 == pytest.approx(d.p0, rel=INTERPOLATION)
    assert c.s == pytest.approx(d.s, rel=INTERPOLATION)
    sphere = fl.solve_point_contact(PSD, E_STAR, R, 1e-3, model=law, n=128)
    assert sphere.converged


def test_leak_rate_uses_the_calibrated_hydraulic_gap(theory):
    p = np.geomspace(1e2, 1e5, 10)
    law = fl.CalibratedLaw(_points(theory, p, gap_scale=0.8), PSD, E_STAR)
    r = fl.solve_line_contact(PSD, E_STAR, 0.0328, 2.0, n=256)
    plain = fl.leak_rate(r, 100.0, 1e-3, warn=False)
    cal = fl.leak_rate(r, 100.0, 1e-3, warn=False, law=law)
    np.testing.assert_array_equal(cal.u_c, law.hydraulic_gap(r.pressure))
    assert cal.Q / plain.Q == pytest.approx(0.8**3, rel=GAP_CUBED_INTERPOLATION)
    assert cal.diagnostics["gap_table"] == {"law": "calibrated"}
    sphere = fl.solve_point_contact(PSD, E_STAR, 0.0328, 1e-3, n=128)
    ring = fl.leak_rate(sphere, 100.0, 1e-3, inner_radius=2e-5, warn=False, law=law)
    ring0 = fl.leak_rate(sphere, 100.0, 1e-3, inner_radius=2e-5, warn=False)
    assert ring.Q / ring0.Q == pytest.approx(0.8**3, rel=GAP_CUBED_INTERPOLATION)
    with pytest.raises(TypeError, match="log_hydraulic_gap"):
        fl.leak_rate(r, 100.0, 1e-3, law=fl.TabulatedLaw([3.0, 2.0, 1.0], [1.0, 2.0, 3.0]))


# ---- command line -----------------------------------------------------------------------------
def _cli(argv):
    out, err = StringIO(), StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main([str(a) for a in argv])
    return status, out.getvalue(), err.getvalue()


SPECTRUM = ["--h-rms", 0.5e-6, "--hurst", 0.8, "--q0", Q0, "--qr", Q0, "--q1", 4 * Q0]


def test_cli_calibrate_then_solve_and_leak_with_the_law(tmp_path):
    law = tmp_path / "law.npz"
    status, out, err = _cli(
        ["calibrate", *SPECTRUM, "--E-star", E_STAR, "--pressure", 1e3, 1e4, 1e5,
         "--realizations", 2, "--periods", 2, "--check", "none", "--out", law]
    )  # fmt: skip
    assert status == 0, err
    assert "32 x 32 cells" in out and f"wrote {law}" in out
    scene = [*SPECTRUM, "--E-star", E_STAR, "--radius", 0.0328, "--load", 5.0, "--n", 256]
    status, out, err = _cli(["profile", *scene, "--law", law])
    assert status == 0, err
    assert "calibrated" in out
    status, out, err = _cli(
        ["leak", *scene, "--law", law, "--pressure-drop", 10.0, "--viscosity", 1e-3]
    )
    assert status == 0, err
    assert "hydraulic gap" in out
    status, out, err = _cli(["profile", *scene[:-6], "--E-star", 2 * E_STAR, "--law", law])
    assert status == 2 and "calibrate again for this modulus" in err
    status, out, err = _cli(["profile", *scene, "--law", tmp_path / "missing.npz"])
    assert status == 2 and "no such file" in err
    loads = ["--loads-from", 1.0, "--loads-to", 5.0, "--loads-num", 2, "--n", 256]
    status, out, err = _cli(["sweep", *scene[:-4], *loads, "--law", law, "--workers", 1])
    assert status == 0, err  # the law on fl.sweep (tests/test_batch.py: its numbers)
    other = [*scene[:-8], "--E-star", 2 * E_STAR, *scene[-6:-4]]
    status, out, err = _cli(["sweep", *other, *loads, "--law", law, "--workers", 2])
    assert status == 2 and "calibrate again for this modulus" in err  # before any pool


def test_iterative_flow_equals_the_direct_solve():
    grid = bem.spectral_grid(PSD, periods=4)  # 64 x 64: three levels
    heights = bem.random_surface(PSD, grid, 3).heights
    start = None
    for p in (1e3, 3e4, 3e5, 3e6):  # the last seals (no channel percolates)
        res = bem.solve_contact(-heights, grid, E_STAR, p * grid.lx * grid.ly)
        for gap, d in ((res.gap, (grid.dx, grid.dy)), (res.gap.T, (grid.dy, grid.dx))):
            warm = start if gap is res.gap else None
            it = bem.reynolds_flow(gap, *d, viscosity=1e-3, solver="iterative", start=warm)
            direct = bem.reynolds_flow(gap, *d, viscosity=1e-3, solver="direct")
            assert it.conductance == pytest.approx(direct.conductance, rel=FLOW_AGREEMENT, abs=0.0)
            if gap is res.gap:
                start = it
    assert it.conductance == 0.0 and not direct.percolating and it.solver == "none"
