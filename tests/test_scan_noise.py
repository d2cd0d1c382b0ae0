"""Measured scans as instruments deliver them: noise floors, noisy C1D, exports, units, bad input.

Synthetic scans are seeded pieces (a quarter) of periodic Gaussian profiles drawn from the exact
1D spectrum of a self-affine isotropic surface (tests/naive.py), tilted, with white instrument
noise of a given fraction of their rms. Their truth is the generating spectrum; the noise's own
effect is the same analysis of the same scan without noise. The fixture exports in
tests/data/exports hold x_j = 0.5 j um, h_j = 100 sin(0.3 j) + 20 cos(1.7 j) nm (64 points),
written in seven layouts (their header says which).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import naive
import numpy as np
import pytest
from scipy.optimize import isotonic_regression

import fastline as fl
from fastline.surfaces import analyse_scan
from fastline.surfaces import files as files_module
from fastline.surfaces import topography as tp
from fastline.surfaces.profiles import non_increasing
from fastline.surfaces.ranges import log_bins, span_bins

EXPORTS = Path(__file__).parent / "data" / "exports"
#: the targets for one profile at the defaults: H to this absolute error and within this many
#: of its own standard errors; the noise changes the fitted h_rms and the table's rms slope by
#: less than these fractions
TOL_H, TOL_H_ERRORS, TOL_H_RMS, TOL_SLOPE = 0.05, 2.0, 0.03, 0.05
#: the fit's +-2 standard errors hold the true H in at least this share of the repeats
COVERAGE, REPEATS = 0.90, 50
#: q_r of a roll-off 16 modes up, one profile of 2048 points, QR_REPEATS seeded repeats: the
#: two-standard-error interval holds the truth in at least QR_COVERAGE of them (~0.92 expected)
QR_COVERAGE, QR_REPEATS = 0.75, 16
#: the found white-noise level against the true sigma^2 dx / (2 pi) (from ~1000 values: ~10 %)
TOL_LEVEL = 0.3


def _scans(H, qr_modes, noise, n, dx, count, seed):
    """(noisy, noise-free) scans (count, n) in m and the truth: pieces of periodic profiles 4 n
    long with q_r ``qr_modes`` Fourier modes up (0: no roll-off), a tilt, white noise of rms
    ``noise`` times the rms of the noise-free scan."""
    L = n * dx
    q0 = 2.0 * math.pi / (4.0 * L)
    truth = fl.SelfAffinePSD(1e-6, H, q0, max(q0, qr_modes * 2.0 * math.pi / L), 100 * math.pi / dx)
    h = naive.gaussian_profiles(lambda k: naive.self_affine_1d(truth, k), 4 * n, dx, count, seed)
    h = h[:, :n] + 2e-4 * dx * np.arange(n)
    sigma = noise * float(np.std(h))
    rng = np.random.default_rng(seed + 1)
    return h + sigma * rng.standard_normal(h.shape), h, truth, sigma


def _quiet(f, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tp.TopographyWarning)
        return f(*args, **kwargs)


# ----------------------------------------------------------------------------------------------
# the noise floor: found, cut, taken off the fit
# ----------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def noisy():
    """One profile, H 0.8 with a roll-off, 1 % noise: the floor lies inside the measured range."""
    h, clean, truth, sigma = _scans(0.8, 16, 0.01, 8192, 2e-7, 1, seed=7)
    dx = 2e-7
    spectrum = _quiet(tp.psd_from_profile, h[0], dx)
    return h[0], clean[0], truth, sigma, dx, spectrum


def test_floor_is_found_and_cut(noisy):
    """The range ends where the power law falls to NOISE_MARGIN x the plateau, i.e. a factor
    NOISE_MARGIN^(-1/(1+2H)) below where the true C1D meets the noise; the level is the noise's."""
    _, _, truth, sigma, dx, s = noisy
    level = sigma**2 * dx / (2.0 * math.pi)
    k = np.geomspace(1e5, math.pi / dx, 2000)
    meets = k[np.argmax(naive.self_affine_1d(truth, k) < level)]
    expected = meets * tp.NOISE_MARGIN ** (-1.0 / (1.0 + 2.0 * truth.hurst))
    assert s.limits["high"] == "noise floor found"
    assert s.noise_floor == pytest.approx(level, rel=TOL_LEVEL)
    assert s.q_range[1] == pytest.approx(expected, rel=0.3)


def test_floor_found_through_dropouts(noisy):
    """Two percent of the points lost in runs of 5 (bridged): the same floor and H."""
    h, _, truth, _, dx, s = noisy
    lost = h.copy()
    starts = np.random.default_rng(3).choice(h.size - 5, size=h.size // 250, replace=False)
    for j in starts:
        lost[j : j + 5] = np.nan
    bridged = _quiet(tp.psd_from_profile, lost, dx, nan="interpolate")
    assert bridged.limits["high"] == "noise floor found"
    assert bridged.noise_floor == pytest.approx(s.noise_floor, rel=TOL_LEVEL)
    fit = _quiet(tp.fit_self_affine, bridged)
    assert abs(fit.hurst - truth.hurst) < min(TOL_H, TOL_H_ERRORS * fit.hurst_err)


def test_no_floor_on_a_noise_free_scan(noisy):
    _, clean, _, _, dx, _ = noisy
    s = _quiet(tp.psd_from_profile, clean, dx)
    assert s.limits["high"] == "sampling"
    assert s.noise_floor == 0.0


def test_noise_leaves_the_fit_as_without_it(noisy):
    """H within TOL_H of the truth and TOL_H_ERRORS of its error; h_rms of the fit and the rms
    slope of the table as the same analysis of the noise-free scan over the same range."""
    h, clean, truth, _, dx, s = noisy
    fit = _quiet(tp.fit_self_affine, s)
    ref_spectrum = _quiet(tp.psd_from_profile, clean, dx, q_range=s.q_range)
    ref = _quiet(tp.fit_self_affine, ref_spectrum)
    assert abs(fit.hurst - truth.hurst) < min(TOL_H, TOL_H_ERRORS * fit.hurst_err)
    assert fit.h_rms == pytest.approx(ref.h_rms, rel=TOL_H_RMS)
    slope, ref_slope = s.isotropic().rms_slope, ref_spectrum.isotropic().rms_slope
    assert slope == pytest.approx(ref_slope, rel=TOL_SLOPE)


@pytest.mark.parametrize(
    ("H", "qr_modes", "noise", "n", "dx"),
    [(0.3, 16, 0.003, 8192, 1e-6), (1.0, 0, 0.01, 4096, 1e-7), (0.5, 64, 0.03, 8192, 5e-8)],
)
def test_hurst_of_one_noisy_profile(H, qr_modes, noise, n, dx):
    """Every H, with and without roll-off: H within TOL_H and TOL_H_ERRORS errors; a roll-off
    64 modes up is measured within 25 %, none is flagged as not resolved."""
    h, _, truth, _ = _scans(H, qr_modes, noise, n, dx, 1, seed=round(100 * H))
    fit = _quiet(tp.fit_self_affine, _quiet(tp.psd_from_profile, h[0], dx))
    if fit.hurst_at_bound:
        assert fit.hurst == H
    else:
        assert abs(fit.hurst - H) < min(TOL_H, TOL_H_ERRORS * fit.hurst_err)
    if qr_modes == 0:
        assert fit.qr_at_bound
    elif qr_modes >= 64:
        assert fit.qr == pytest.approx(truth.qr, rel=0.25)


def test_fit_errors_cover_the_truth():
    """Seeded repeats of one noisy profile (H 0.8, roll-off, 1 % noise): the true H inside
    +-2 reported standard errors in at least COVERAGE of REPEATS."""
    h, _, truth, _ = _scans(0.8, 16, 0.01, 2048, 1e-6, REPEATS, seed=11)
    inside = 0
    for row in h:
        fit = _quiet(tp.fit_self_affine, _quiet(tp.psd_from_profile, row, 1e-6))
        inside += abs(fit.hurst - truth.hurst) <= 2.0 * fit.hurst_err
    assert inside >= COVERAGE * REPEATS


def test_rolloff_few_modes_up_is_said_to_be_uncertain():
    """A roll-off 16 modes up, one profile each: the q_r interval holds the truth in at least
    QR_COVERAGE of the repeats, and no fit gives a q_r off by more than 25 % without saying it
    is uncertain (``qr_uncertain``, a warning); eight such profiles together measure it."""
    h, _, truth, _ = _scans(0.8, 16, 0.01, 2048, 1e-6, QR_REPEATS + 8, seed=23)
    inside = 0
    for row in h[:QR_REPEATS]:
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always", tp.TopographyWarning)
            fit = tp.fit_self_affine(_quiet(tp.psd_from_profile, row, 1e-6))
        lo, hi = fit.qr_interval
        inside += lo <= truth.qr <= hi
        assert fit.qr_uncertain or fit.qr == pytest.approx(truth.qr, rel=0.25)
        assert fit.qr_uncertain == any("q_r" in str(w.message) for w in said)
    assert inside >= QR_COVERAGE * QR_REPEATS
    fit = tp.fit_self_affine(_quiet(tp.psd_from_profile, h[QR_REPEATS:], 1e-6))
    lo, hi = fit.qr_interval
    assert lo <= truth.qr <= hi and fit.qr == pytest.approx(truth.qr, rel=0.25)


def test_scan_summary_says_what_was_cut(noisy, tmp_path):
    h, *_ = noisy
    path = tmp_path / "scan.npy"
    np.save(path, h / 1e-6)
    scan = _quiet(analyse_scan, path, dx=2e-7, unit="um")
    text = scan.summary()
    assert str(scan) == text and scan.describe() == text
    one = scan.one_line()  # the first line, without the path
    assert "\n" not in one and text.splitlines()[0].endswith(one) and "window" in one
    assert "q range used" in text and "fit " in text and "C(q) table" in text
    left = [line for line in text.splitlines() if line.startswith("left out")]
    assert scan.limits["high"] == "noise floor found" and "noise floor found" in text
    assert len(left) == 1 and "rms noise" in left[0] and "Nyquist" in left[0]
    assert scan.metadata()["noise_floor_C1D_m3"] == scan.spectrum.noise_floor


# ----------------------------------------------------------------------------------------------
# the inverse Abel transform of a noisy C1D keeps its low end
# ----------------------------------------------------------------------------------------------
def test_falling_envelope_is_the_least_squares_one():
    rng = np.random.default_rng(0)
    for _ in range(20):
        y = np.exp(rng.normal(size=12).cumsum() * 0.3)
        ref = np.exp(isotonic_regression(np.log(y), increasing=False).x)
        np.testing.assert_allclose(non_increasing(y), ref, rtol=1e-12)


def test_noisy_c1d_keeps_every_point():
    """A C1D that rises at its low end (noise) still gives C(q) > 0 at every point, from the
    first, with a warning; a falling one is transformed as it is."""
    truth = fl.SelfAffinePSD(1e-6, 0.8, 1e4, 1e5, 1e8)
    k = np.geomspace(2e4, 1e7, 40)
    C1D = naive.self_affine_1d(truth, k) * np.where(np.arange(40) % 3 == 1, 1.6, 1.0)
    with pytest.warns(tp.TopographyWarning, match="non-increasing"):
        psd = tp.isotropic_from_1d(k, C1D)
    assert psd.q.size == k.size and psd.q[0] == k[0] and np.all(psd.C > 0.0)
    smooth = naive.self_affine_1d(truth, k)
    with warnings.catch_warnings():
        warnings.simplefilter("error", tp.TopographyWarning)
        assert tp.isotropic_from_1d(k, smooth).C.size == k.size


# ----------------------------------------------------------------------------------------------
# exports as they come, and their units
# ----------------------------------------------------------------------------------------------
def _fixture_heights():
    j = np.arange(64)
    return (100.0 * np.sin(0.3 * j) + 20.0 * np.cos(1.7 * j)) * 1e-9


@pytest.mark.parametrize("name", sorted(p.name for p in EXPORTS.iterdir()))
def test_exports_read_with_their_units(name):
    """Each layout gives the same heights (m, to the file's rounding) and dx = 0.5 um, with the
    units its header names (one column needs dx)."""
    dx = 5e-7 if name.startswith("count") else None
    profile = _quiet(tp.read_profile, EXPORTS / name, dx=dx)
    np.testing.assert_allclose(profile.heights, _fixture_heights(), rtol=0, atol=1e-12)
    assert profile.dx == pytest.approx(5e-7, rel=1e-6)


def test_header_units_and_options(tmp_path):
    x, h = np.arange(40) * 0.5, _fixture_heights()[:40] * 1e9
    named = tmp_path / "named.csv"
    named.write_text(
        "Position [um],Height [nm]\n" + "".join(f"{a},{b}\n" for a, b in zip(x, h, strict=True))
    )
    agree = tp.read_profile(named, unit="nm", x_unit="um")
    np.testing.assert_allclose(agree.heights, h * 1e-9)
    with pytest.raises(ValueError, match=r"unit='mm' \(--units mm\) contradicts.*nm"):
        tp.read_profile(named, unit="mm")
    with pytest.raises(ValueError, match=r"x_unit='nm' \(--x-units nm\) contradicts.*um"):
        tp.read_profile(named, x_unit="nm")
    bare = tmp_path / "bare.txt"
    bare.write_text("".join(f"{a} {b}\n" for a, b in zip(x, h, strict=True)))
    with pytest.warns(tp.TopographyWarning, match="x column is taken in nm"):
        assert tp.read_profile(bare, unit="nm").dx == pytest.approx(0.5e-9)
    assert tp.read_profile(bare, unit="nm", x_unit="um").dx == pytest.approx(0.5e-6)


def test_unreadable_text_names_the_layouts_tried(tmp_path, monkeypatch):
    bad = tmp_path / "bad.txt"
    bad.write_text("a,b\n1,2\n3,4\n5,6\nseven,8\n")

    def refuse(path):
        raise RuntimeError("no reader for this file")

    monkeypatch.setattr(files_module, "_surfacetopography", refuse)
    with pytest.raises(ValueError, match="bad.txt:5.*Layouts tried.*UTF-16.*SurfaceTopography"):
        tp.read_profile(bad)


def test_text_goes_to_surfacetopography_before_giving_up(tmp_path, monkeypatch):
    """A text file fastline's reader refuses is handed to SurfaceTopography's readers."""
    odd = tmp_path / "odd.txt"
    odd.write_text("1 2 3\n4 5 6\n7 8 9\n")
    seen = []

    def read(path):
        seen.append(path)
        return 1, np.linspace(0.0, 1e-6, 64), (1e-6,)

    monkeypatch.setattr(files_module, "_surfacetopography", read)
    assert tp.read_profile(odd).heights.size == 64 and seen == [str(odd)]


# ----------------------------------------------------------------------------------------------
# bad input: one clear error naming it
# ----------------------------------------------------------------------------------------------
_H = np.random.default_rng(1).standard_normal(128) * 1e-6
_MAP = np.random.default_rng(2).standard_normal((64, 64)) * 1e-6


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: tp.psd_from_profile([1e-6], 1e-6), "at least 32 points"),
        (lambda: tp.psd_from_profile([1e-6, 2e-6], 1e-6), "at least 32 points"),
        (lambda: tp.psd_from_profile(_H * 1e306, 1e-6), "h: the heights reach"),
        (lambda: tp.psd_from_profile(_H * 1e-294, 1e-6), "h: the heights reach"),
        (lambda: tp.psd_from_profile(_H, 1e300), "dx must lie in"),
        (lambda: tp.psd_from_profile(_H, 1e-300), "dx must lie in"),
        (lambda: tp.psd_from_profile(_H + 1j * _H, 1e-6), "h must be real"),
        (lambda: tp.psd_from_profile([str(v) for v in _H], 1e-6), "h must hold real numbers"),
        (lambda: tp.psd_from_map(_MAP * 1e300, 1e-6), "h: the heights reach"),
        (lambda: tp.psd_from_map(_MAP, 1e-300), "dx must lie in"),
        (lambda: tp.psd_from_map(_MAP, 1e-6, dy=1e300), "dy must lie in"),
        (lambda: tp.psd_from_map(_MAP * (1 + 1j), 1e-6), "h must be real"),
        (
            lambda: tp.psd_from_map(
                np.vstack([_MAP[:-1], np.full(64, np.nan)]), 1e-6, nan="interpolate"
            ),
            "row 63 holds no data",
        ),
    ],
)
def test_bad_input_is_one_clear_error(call, match):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no NumPy warning on the way
        with pytest.raises(ValueError, match=match):
            call()


@pytest.mark.parametrize("content", ["1.0\n", "1.0\n2.0\n", "complex"])
def test_bad_scan_files(tmp_path, content):
    if content == "complex":
        path = tmp_path / "c.npy"
        np.save(path, _H + 1j * _H)
        match = "complex"
    else:
        path = tmp_path / "short.txt"
        path.write_text(content)
        match = "at least 32 points"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=match):
            analyse_scan(path, dx=1e-6)


def test_long_text_in_one_pass_and_its_errors(tmp_path):
    """A long export (CRLF, trailing separators, a header) reads as its short form does, through
    NumPy's reader; a bad line deep inside is still named by its number."""
    x = np.arange(6000) * 0.5
    h = np.sin(0.01 * np.arange(6000)) * 100.0
    text = "Scan Data,,\r\nx [um],h [nm],\r\n" + "".join(
        f"{a:.1f},{b:.6f},\r\n" for a, b in zip(x, h, strict=True)
    )
    good = tmp_path / "long.csv"
    good.write_bytes(text.encode())
    profile = tp.read_profile(good)
    np.testing.assert_allclose(profile.heights, h * 1e-9, atol=1e-15)
    assert profile.dx == pytest.approx(5e-7)
    bad = tmp_path / "bad_long.csv"
    bad.write_bytes(text.replace("2500.0,", "25oo.0,").encode())
    with pytest.raises(ValueError, match=r"bad_long.csv:5003: not a number"):
        tp.read_profile(bad)


# ----------------------------------------------------------------------------------------------
# big scans: the compiled passes and the half-plane map spectrum give the plain computation
# ----------------------------------------------------------------------------------------------
def _hann(n: int) -> np.ndarray:
    """The periodic Hann window normalised to sum w^2 = n."""
    return math.sqrt(8.0 / 3.0) * 0.5 * (1.0 - np.cos(2.0 * math.pi * np.arange(n) / n))


@pytest.mark.parametrize("detrend", ["linear", "mean"])
def test_profile_passes_equal_the_plain_computation(detrend):
    """Two tilted profiles of an odd length: h_rms, rms slope and every periodogram value as
    the least-squares line (numpy.polyfit), the Hann window and the explicit Fourier sum."""
    rng = np.random.default_rng(8)
    n, dx = 1001, 1e-7
    h = np.cumsum(rng.standard_normal((2, n)), axis=1) * 1e-9 + 3e-7 + 1e-4 * dx * np.arange(n)
    s = tp.psd_from_profile(h, dx, detrend=detrend, bins_per_decade=None, q_range=None)
    j = np.arange(n)
    deg = 1 if detrend == "linear" else 0
    res = np.array([row - np.polyval(np.polyfit(j, row, deg), j) for row in h])
    assert s.h_rms == pytest.approx(math.sqrt(np.mean(res**2)), rel=1e-12)
    assert s.rms_slope == pytest.approx(math.sqrt(np.mean(np.diff(res) ** 2)) / dx, rel=1e-12)
    C = np.mean([naive.periodogram_1d(row, dx, _hann(n))[1] for row in res], axis=0)
    np.testing.assert_allclose(s.C1D, C, rtol=1e-9)


@pytest.mark.parametrize(
    ("shape", "dx", "dy"), [((48, 64), 1.3e-6, 1e-6), ((64, 49), 1e-6, 1.3e-6)]
)
def test_map_half_plane_equals_every_mode(shape, dx, dy):
    """The real FFT's half plane, each column weighted by the modes it stands for, gives the
    rings of every mode of the full plane (plane by least squares, 2D Hann window, odd and
    even sizes, dx != dy)."""
    ny, nx = shape
    rng = np.random.default_rng(5)
    h = (
        rng.standard_normal(shape) * 1e-7
        + 1e-8 * np.arange(nx)[None, :]
        - 2e-8 * np.arange(ny)[:, None]
    )
    psd = tp.psd_from_map(h, dx, dy, q_range=None)
    y, x = np.mgrid[0:ny, 0:nx]
    V = np.column_stack([np.ones(h.size), x.ravel(), y.ravel()])
    res = h - (V @ np.linalg.lstsq(V, h.ravel(), rcond=None)[0]).reshape(shape)
    F = np.fft.fft2(res * np.outer(_hann(ny), _hann(nx)))
    C = (dx * dy) ** 2 / ((2.0 * math.pi) ** 2 * nx * dx * ny * dy) * np.abs(F.ravel()) ** 2
    q = np.hypot(
        *np.meshgrid(
            2 * math.pi * np.fft.fftfreq(ny, dy),
            2 * math.pi * np.fft.fftfreq(nx, dx),
            indexing="ij",
        )
    ).ravel()
    lo, hi = 2.0 * math.pi / max(nx * dx, ny * dy), math.pi / max(dx, dy)
    qb, Cb = span_bins(*log_bins(q, C, 20, lo, hi)[:2], lo, hi)
    np.testing.assert_allclose(psd.q, qb, rtol=1e-12)
    np.testing.assert_allclose(psd.C, Cb, rtol=1e-9)
