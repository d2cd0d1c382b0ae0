"""fastline.surfaces.scan.analyse_scan, io.write_spectrum and plotting.plot_measured_psd.

analyse_scan only chains fastline.surfaces.topography: every number it returns is held equal to the
elementary calls on the same heights (psd_from_profile, isotropic_from_1d, psd_from_map,
fit_self_affine, extend_psd); the rest is what it records (range rules, extension point), the
files it refuses and its bad-input errors. Small seeded synthetic surfaces (256 x 256).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import fastline as fl
from fastline.io import read_spectrum, write_spectrum
from fastline.surfaces import topography as tp
from fastline.surfaces.scan import LIMIT_RULES, analyse_scan

#: the same computation on the same data: equal to round-off
SAME = 1e-12
DX = 2e-6  # m
TRUTH = fl.SelfAffinePSD(0.5e-6, 0.8, 2e4, 1e5, 1e9)
MAGIC_PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def surface():
    return tp.synthetic_surface(TRUTH, 256, DX, seed=3)  # m


@pytest.fixture(scope="module")
def files(surface, tmp_path_factory):
    d = tmp_path_factory.mktemp("scans")
    rows, heights = d / "rows.txt", d / "column.txt"
    np.savetxt(rows, surface[::32] * 1e6, header="8 traces, heights in um, dx 2 um")
    np.savetxt(heights, surface[0], header="h [m]")
    np.save(d / "map.npy", surface)
    return {"rows": rows, "column": heights, "map": d / "map.npy", "dir": d}


def test_profiles_equal_the_elementary_calls(files, surface):
    scan = analyse_scan(files["rows"], dx=DX, unit="um", q1=1e8, extend=True)
    h = np.loadtxt(files["rows"]) * 1e-6  # as written: 8 rows in um
    spectrum = tp.psd_from_profile(h, DX)
    iso = tp.isotropic_from_1d(spectrum.k, spectrum.C1D)
    fit = tp.fit_self_affine(spectrum, q0=iso.q0, q1=1e8)  # fitted to C1D, the model to q1
    table = tp.extend_psd(iso, 1e8, hurst=fit.hurst)
    assert scan.kind == "profiles" and scan.shape == (8, 256) and scan.n_profiles == 8
    np.testing.assert_allclose(scan.spectrum.C1D, spectrum.C1D, rtol=SAME)
    np.testing.assert_allclose(scan.measured.C, iso.C, rtol=SAME)
    np.testing.assert_allclose(scan.psd.q, table.q, rtol=SAME)
    np.testing.assert_allclose(scan.psd.C, table.C, rtol=SAME)
    assert scan.fit.hurst == pytest.approx(fit.hurst, rel=SAME)
    assert scan.q_range == spectrum.q_range and scan.limits == spectrum.limits
    assert scan.extended_from == pytest.approx(iso.q1, rel=SAME)
    # the raw periodogram of the figure: every mode 2 pi m / L, m = 1 .. N/2
    k, C1D = scan.raw
    np.testing.assert_allclose(k, 2 * math.pi * np.arange(1, 129) / (256 * DX), rtol=SAME)
    assert np.all(C1D > 0.0)


def test_map_equals_psd_from_map_and_names_its_rules(files, surface):
    scan = analyse_scan(files["map"], dx=DX, as_map=True)
    psd = tp.psd_from_map(surface, DX)
    np.testing.assert_allclose(scan.measured.C, psd.C, rtol=SAME)
    assert scan.psd is scan.measured and scan.extended_from is None
    assert scan.kind == "map" and scan.spectrum is None and scan.dy == DX
    assert scan.limits == {"low": "scan length", "high": "sampling"}
    assert scan.q_range == pytest.approx((4 * 2 * math.pi / (256 * DX), 2 * math.pi / (4 * DX)))
    # the noise rule (10 x the floor of 0.1 um white noise meets C at ~5e5 1/m), an explicit
    # end, all rings
    noisy = analyse_scan(files["map"], dx=DX, as_map=True, noise=1e-7)
    assert noisy.limits["high"] == "noise floor" and noisy.q_range[1] < scan.q_range[1]
    given = analyse_scan(files["map"], dx=DX, as_map=True, q_range=(None, 3e5))
    assert given.limits == {"low": "scan length", "high": "given"}
    assert given.q_range[1] == pytest.approx(3e5, rel=SAME)
    every = analyse_scan(files["map"], dx=DX, as_map=True, q_range=None)
    assert every.limits == {"low": "all", "high": "all"}
    assert set(LIMIT_RULES) >= {scan.limits["low"], noisy.limits["high"], "tip radius"}


@pytest.mark.parametrize("as_map", [False, True])
def test_the_fitted_model_spans_the_table(files, as_map):
    """fit.psd follows q1 as psd does: continued to q1 with extend, cut at q1 below the top."""
    path, unit = (files["map"], "m") if as_map else (files["rows"], "um")
    for q1, extend in ((1e8, True), (3e5, False)):
        scan = analyse_scan(path, dx=DX, unit=unit, as_map=as_map, q1=q1, extend=extend)
        assert scan.fit.psd.q1 == pytest.approx(q1, rel=SAME) == scan.psd.q1
        assert scan.fit.psd.q0 == pytest.approx(scan.psd.q0, rel=SAME)
        assert scan.fit.psd.hurst == scan.fit.hurst
    plain = analyse_scan(path, dx=DX, unit=unit, as_map=as_map)
    assert plain.fit.psd.q1 == pytest.approx(plain.measured.q1, rel=SAME)
    assert plain.fit.hurst == pytest.approx(scan.fit.hurst, rel=SAME)  # q1 moves only the range


def test_cut_at_q1_below_the_range(files):
    scan = analyse_scan(files["rows"], dx=DX, unit="um", q1=3e5)
    assert scan.psd.q1 == pytest.approx(3e5, rel=SAME) and scan.extended_from is None
    np.testing.assert_allclose(scan.psd(2e5), scan.measured(2e5), rtol=SAME)


def test_spectrum_round_trip_through_write_and_read(files, tmp_path):
    scan = analyse_scan(files["rows"], dx=DX, unit="um", q1=1e8, extend=True)
    path = tmp_path / "psd.csv"
    write_spectrum(path, scan.psd, scan.metadata(), title="a title\nsecond line")
    back = read_spectrum(path)
    np.testing.assert_array_equal(back.q, scan.psd.q)  # repr(): exact
    np.testing.assert_array_equal(back.C, scan.psd.C)
    text = path.read_text()
    assert text.startswith("# a title\n# second line\n")
    assert f"# fit_hurst: {scan.fit.hurst!r}\n" in text and "# q_1_per_m,C_m4\n" in text
    assert f"# points: {scan.psd.q.size}\n" in text
    with pytest.raises(TypeError, match="TabulatedPSD"):
        write_spectrum(tmp_path / "x.csv", TRUTH)
    with pytest.raises(ValueError, match="cannot write"):
        write_spectrum(tmp_path / "no" / "x.csv", scan.psd)


def _columns(path, a, b, delimiter=" "):
    np.savetxt(path, np.column_stack([a, b]), fmt="%.17g", delimiter=delimiter)


def test_spectrum_tables_are_refused_as_scans(tmp_path):
    q = np.geomspace(1e3, 1e7, 40)
    _columns(tmp_path / "log.txt", q, TRUTH(q))  # log-spaced q: x would not be uniform
    k = np.arange(1, 200) * 1e4
    _columns(tmp_path / "lin.csv", k, k**-3.6, ",")  # a raw periodogram: uniform q
    for name in ("log.txt", "lin.csv"):
        with pytest.raises(ValueError, match="looks like a spectrum"):
            analyse_scan(tmp_path / name)
    # a profile of positive heights from x = 0 is a profile (read_spectrum refuses x = 0)
    x = np.arange(256) * DX
    _columns(tmp_path / "pos.txt", x, 1e-6 * (2.0 + np.sin(x / 3e-5)))
    with pytest.warns(tp.TopographyWarning, match="roll-off is not resolved"):  # a sine: no q_r
        assert analyse_scan(tmp_path / "pos.txt").kind == "profile"


@pytest.mark.parametrize(
    "kwargs, needle",
    [
        ({"dx": DX, "extend": True}, "extend=True needs q1"),
        ({"dx": DX, "q1": 1e9}, "extend=True"),  # above the range without extend
        ({"dx": DX, "detrend": "plane"}, "'plane' is for a height map"),
        ({"dx": DX, "as_map": True, "detrend": "circle"}, "detrend for a map"),
        ({"dx": DX, "dy": DX}, "dy is the row spacing of a map"),
        ({"dx": DX, "q1": -1.0}, "q1"),
        ({}, "spacing dx (m) is required"),
        ({"dx": DX, "window": "nonsense"}, "window"),
        ({"dx": DX, "unit": "furlong"}, "unit"),
    ],
)
def test_bad_input(files, kwargs, needle):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tp.TopographyWarning)  # rows in um read as m
        with pytest.raises(ValueError) as e:
            analyse_scan(files["column"], **kwargs)
    assert needle in str(e.value)


def test_bad_files(files, tmp_path):
    for bad in (None, 3):
        with pytest.raises(TypeError, match=r"path must be a file name \(str or os.PathLike\)"):
            analyse_scan(bad, dx=DX)
    with pytest.raises(ValueError, match="is a directory"):
        analyse_scan(files["dir"])
    with pytest.raises(FileNotFoundError, match="no such file"):
        analyse_scan(tmp_path / "missing.txt", dx=DX)
    nan = np.loadtxt(files["column"])
    nan[100:104] = np.nan
    np.savetxt(tmp_path / "nan.txt", nan)
    with pytest.raises(ValueError, match="nan='interpolate'"):
        analyse_scan(tmp_path / "nan.txt", dx=DX)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tp.TopographyWarning)  # one noisy profile: C <= 0 points
        assert analyse_scan(tmp_path / "nan.txt", dx=DX, nan="interpolate").kind == "profile"


def test_figure_of_profiles_and_map(files, tmp_path):
    pytest.importorskip("matplotlib")
    scan = analyse_scan(files["rows"], dx=DX, unit="um", q1=1e8, extend=True)
    fig = fl.plotting.plot_measured_psd(scan)
    left, right = fig.axes
    assert "m$^3$" in left.get_ylabel() and "m$^4$" in right.get_ylabel()
    labels = right.get_legend_handles_labels()[1]
    assert any("fit" in t for t in labels) and any("continued" in t for t in labels)
    fl.plotting.save_figure(fig, tmp_path / "p.png", dpi=50)
    assert (tmp_path / "p.png").read_bytes()[:8] == MAGIC_PNG
    one = fl.plotting.plot_measured_psd(analyse_scan(files["map"], dx=DX, as_map=True))
    assert len(one.axes) == 1
    assert any("ring averages" in t for t in one.axes[0].get_legend_handles_labels()[1])


@pytest.mark.parametrize("as_map", [False, True])
def test_a_loop_of_analyses_warns_once_per_cause(files, as_map, tmp_path):
    """analyse_scan in a loop (a unit slip: the units warning at every call) shows each
    TopographyWarning once under Python's default filter: the recomputation of the raw
    spectrum is silenced without touching the warning filters, whose change would clear the
    record of warnings already shown."""
    path = tmp_path / "map_um.npy"  # heights in um, read as mm: an rms slope of ~40
    np.save(path, np.load(files["map"]) * 1e6)
    path, kwargs = (path, {"as_map": True}) if as_map else (files["rows"], {})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        for _ in range(3):
            analyse_scan(path, dx=DX, unit="mm", **kwargs)
    emitted = [str(w.message) for w in caught if issubclass(w.category, tp.TopographyWarning)]
    assert any("wrong unit" in text for text in emitted)
    assert len(emitted) == len(set(emitted)), emitted
