"""Tests of ``fastline psd SCAN`` and ``--scan`` on profile, sweep and leak.

Small seeded synthetic scans written to temporary files (a 256 x 256 Gaussian surface of a
self-affine spectrum, 2 um spacing): the files the command writes, its numbers against the
elementary topography API on the same heights, the round trip psd --out -> profile --psd ->
the same pressure as profile --scan, bad input (missing --dx, a spectrum passed as a scan, NaN
dropouts, ...), unit warnings, exit statuses and output paths checked before any work.
"""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import warnings

import numpy as np
import pytest

import fastline as fl
import fastline.surfaces
from fastline.cli.app import main
from fastline.contact.line import solve_line_contact
from fastline.io import read_csv, read_spectrum
from fastline.surfaces import topography as tp

pytest.importorskip("matplotlib")

#: the files hold repr() of the API's numbers: equal to round-off of the same computation
SAME = 1e-12
DX = 2e-6  # m
TRUTH = fl.SelfAffinePSD(0.5e-6, 0.8, 2e4, 1e5, 1e9)
N = 128  # grid of the solves
MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "svg": b"<?xml"}
SCENE = ["--E-star", 1e7, "--radius", 0.01, "--n", N]


def run(argv, capsys):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def warning_lines(err):
    return [ln for ln in err.splitlines() if ln.startswith("fastline: warning:")]


def error_lines(err):
    return [ln for ln in err.splitlines() if ln.startswith("fastline: error:")]


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    """rows.txt: 8 parallel traces in um, one per line; trace.csv: one trace, x [mm], h [um]
    with a header; map.npy: the map in m; column.txt: one trace in m."""
    d = tmp_path_factory.mktemp("scans")
    h = tp.synthetic_surface(TRUTH, 256, DX, seed=3)
    np.savetxt(d / "rows.txt", h[::32] * 1e6, fmt="%.17g", header="8 traces [um], dx 2 um")
    x_mm = np.arange(256) * DX * 1e3
    np.savetxt(
        d / "trace.csv", np.column_stack([x_mm, h[5] * 1e6]), fmt="%.17g", delimiter=",",
        header="x [mm], z [um]", comments="",
    )  # fmt: skip
    np.save(d / "map.npy", h)
    np.savetxt(d / "column.txt", h[7], fmt="%.17g")
    return d, h


def rows_api(d):
    """The elementary calls on the rows file's heights (as read: um x 1e-6): spectrum, C(q),
    fit."""
    spectrum = tp.psd_from_profile(np.loadtxt(d / "rows.txt") * 1e-6, DX)
    iso = tp.isotropic_from_1d(spectrum.k, spectrum.C1D)
    return spectrum, iso, tp.fit_self_affine(spectrum, q0=iso.q0)


ROWS = ["--dx", DX, "--units", "um"]


# ----------------------------------------------------------------------------------------------
# psd
# ----------------------------------------------------------------------------------------------
def test_psd_summary_table_and_figure_equal_the_api(scans, tmp_path, capsys):
    d, h = scans
    out, png = tmp_path / "psd.csv", tmp_path / "psd.png"
    status, stdout, err = run(["psd", d / "rows.txt", *ROWS, "--out", out, "--plot", png], capsys)
    assert status == 0 and error_lines(err) == []
    spectrum, iso, fit = rows_api(d)
    table = read_spectrum(out)
    np.testing.assert_allclose(table.q, iso.q, rtol=SAME)
    np.testing.assert_allclose(table.C, iso.C, rtol=SAME)
    lo, hi = spectrum.q_range
    for text in (
        "8 parallel profiles of 256 points",
        f"h_rms {spectrum.h_rms:.4g} m, rms slope {spectrum.rms_slope:.4g}",
        f"q range used     {lo:.4g}-{hi:.4g} 1/m; low end: scan length",
        "high end: sampling",
        f"H {fit.hurst:.3f} ± {fit.hurst_err:.2g}, q_r {fit.qr:.4g}",
        f"h_rms {fit.h_rms:.4g} ± {fit.h_rms_err:.2g} m",
        f"C(q) table       {iso.q.size} points, q {iso.q0:.4g}-{iso.q1:.4g} 1/m: h_rms "
        f"{iso.h_rms:.4g} m, rms slope {iso.rms_slope:.4g}",
        f"wrote {out}, {png}",
    ):
        assert text in stdout, text
    assert "continued" not in stdout
    meta = dict(ln[2:].split(": ", 1) for ln in out.read_text().splitlines() if ": " in ln[:40])
    assert float(meta["fit_hurst"]) == pytest.approx(fit.hurst, rel=SAME)
    assert float(meta["h_rms_data_m"]) == pytest.approx(spectrum.h_rms, rel=SAME)
    assert meta["q_range_high_rule"] == "sampling" and meta["fastline_version"] == fl.__version__
    assert png.read_bytes()[:8] == MAGIC["png"]


def test_psd_two_column_file_with_units(scans, capsys):
    d, h = scans
    status, stdout, _ = run(["psd", d / "trace.csv", "--units", "um", "--x-units", "mm"], capsys)
    assert status == 0
    spectrum = tp.psd_from_profile(h[5], DX)
    assert "one profile of 256 points, dx 2e-06 m" in stdout
    assert f"h_rms {spectrum.h_rms:.4g} m, rms slope {spectrum.rms_slope:.4g}" in stdout


def test_psd_map_and_its_rows(scans, tmp_path, capsys):
    d, h = scans
    out, svg = tmp_path / "map.csv", tmp_path / "map.svg"
    argv = ["psd", d / "map.npy", "--dx", DX, "--map", "--out", out, "--plot", svg]
    status, stdout, _ = run(argv + ["--q1", 1e8, "--extend"], capsys)
    assert status == 0
    measured = tp.psd_from_map(h, DX)
    fit = tp.fit_self_affine(measured)
    expected = tp.extend_psd(measured, 1e8, hurst=fit.hurst)
    table = read_spectrum(out)
    np.testing.assert_allclose(table.q, expected.q, rtol=SAME)
    np.testing.assert_allclose(table.C, expected.C, rtol=SAME)
    assert "height map 256 x 256 points" in stdout and "ring-averaged" in stdout
    assert f"continued        above {measured.q1:.4g} 1/m to q1 = 1e+08 1/m" in stdout
    assert svg.read_bytes()[:5] == MAGIC["svg"]
    # without --map the rows of the same file are parallel line scans
    status, stdout, _ = run(["psd", d / "map.npy", "--dx", DX], capsys)
    assert status == 0 and "256 parallel profiles of 256 points" in stdout


def test_psd_cut_and_extend(scans, tmp_path, capsys):
    d, h = scans
    _, iso, fit = rows_api(d)
    out = tmp_path / "cut.csv"
    assert run(["psd", d / "rows.txt", *ROWS, "--q1", 3e5, "--out", out], capsys)[0] == 0
    cut = tp.extend_psd(iso, 3e5)
    np.testing.assert_allclose(read_spectrum(out).C, cut.C, rtol=SAME)
    status, stdout, err = run(["psd", d / "rows.txt", *ROWS, "--q1", 1e9], capsys)
    assert status == 2 and stdout == ""
    assert "above the usable range" in err and "--extend" in err and "extend=True" not in err


# ----------------------------------------------------------------------------------------------
# straight from the scan to the pressure
# ----------------------------------------------------------------------------------------------
def test_round_trip_out_psd_equals_scan_and_api(scans, tmp_path, capsys):
    d, h = scans
    table = tmp_path / "psd.csv"
    extend = ["--q1", 1e8, "--extend"]
    assert run(["psd", d / "rows.txt", *ROWS, *extend, "--out", table], capsys)[0] == 0
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    status, out_a, _ = run(["profile", "--psd", table, *SCENE, "--csv", a], capsys)
    assert status == 0
    argv = ["profile", "--scan", d / "rows.txt", *ROWS, *extend, *SCENE, "--csv", b]
    status, out_b, _ = run(argv, capsys)
    assert status == 0
    _, iso, fit = rows_api(d)
    psd = tp.extend_psd(iso, 1e8, hurst=fit.hurst)
    r = solve_line_contact(psd, 1e7, 0.01, 1e4, n=N)
    meta_a, cols_a = read_csv(a)
    meta_b, cols_b = read_csv(b)
    np.testing.assert_allclose(cols_a["p_Pa"], r.pressure, rtol=SAME)
    np.testing.assert_allclose(cols_b["p_Pa"], r.pressure, rtol=SAME)
    assert f"{r.p0:.6g} Pa" in out_a and f"{r.p0:.6g} Pa" in out_b
    # the scan run says where its spectrum came from, on screen and in the file
    assert f"measured, scan {d / 'rows.txt'}" in out_b and "fit              H" in out_b
    assert meta_b["spectrum"] == f"measured: scan {d / 'rows.txt'}"
    assert float(meta_b["fit_hurst"]) == pytest.approx(fit.hurst, rel=SAME)
    assert float(meta_b["extended_above_1_per_m"]) == pytest.approx(iso.q1, rel=SAME)
    assert float(meta_a["rms_slope"]) == pytest.approx(float(meta_b["rms_slope"]), rel=SAME)


@pytest.mark.parametrize(
    "command, column",
    [
        (["sweep", "--loads-from", 1e3, "--loads-to", 1e5, "--loads-num", 2], "p0_Pa"),
        (["leak", "--pressure-drop", 1e3, "--viscosity", 1e-3, "--load", 2e3], "u_c_m"),
    ],
)
def test_sweep_and_leak_scan_equal_psd_file(command, column, scans, tmp_path, capsys):
    d, _ = scans
    table = tmp_path / "psd.csv"
    assert run(["psd", d / "rows.txt", *ROWS, "--out", table], capsys)[0] == 0
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    assert run([*command, "--psd", table, *SCENE, "--csv", a], capsys)[0] == 0
    status, out, _ = run([*command, "--scan", d / "rows.txt", *ROWS, *SCENE, "--csv", b], capsys)
    assert status == 0 and "q range used" in out
    np.testing.assert_allclose(read_csv(b)[1][column], read_csv(a)[1][column], rtol=SAME)


def test_scan_exit_status_of_a_solve_that_does_not_converge(scans, capsys):
    d, _ = scans
    argv = ["profile", "--scan", d / "rows.txt", *ROWS, *SCENE, "--max-iter", 1]
    status, out, err = run(argv, capsys)
    assert status == 1 and "converged        NO" in out and "did not converge" in err


# ----------------------------------------------------------------------------------------------
# units
# ----------------------------------------------------------------------------------------------
def test_micrometres_read_as_millimetres_warn_once(scans, capsys):
    d, _ = scans
    status, _, err = run(["psd", d / "rows.txt", "--dx", DX, "--units", "mm"], capsys)
    assert status == 0  # the slope is 1e3 too large: 37, implausible but computable
    lines = [ln for ln in warning_lines(err) if "q_r" not in ln]  # short scans: q_r uncertain
    assert len(lines) == 1 and "rms slope" in lines[0] and "wrong unit" in lines[0]
    assert "--units" in lines[0]


def test_micrometres_read_as_metres_warn_then_fail(scans, capsys):
    d, _ = scans
    status, out, err = run(["psd", d / "rows.txt", "--dx", DX], capsys)
    assert status == 2 and out == ""
    assert len(warning_lines(err)) == 1 and "h_rms" in warning_lines(err)[0]
    assert len(error_lines(err)) == 1
    error = error_lines(err)[0]  # of the heights and --units, not of a spectrum file's C and q
    assert "heights" in error and "read in m" in error and "--units" in error
    assert "C in m^4" not in error


@pytest.mark.parametrize("command", ["psd", "profile"])
def test_help_states_the_units(command, capsys):
    with pytest.raises(SystemExit) as e:
        main([command, "--help"])
    assert e.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    for text in ("--dx M", "[m] (metres whatever --units)", "--units {m,mm,um,nm}", "[1/m]"):
        assert text in out, text
    # the defaults the reader applies: the header's units, else m, x following the heights
    assert "default: the unit the file's header names for them" in out and "else m;" in out
    assert "else the heights' unit (with a warning when that is not m)" in out
    assert ("--scan FILE" in out) == (command == "profile")


# ----------------------------------------------------------------------------------------------
# bad input: one error line, exit status 2, nothing written
# ----------------------------------------------------------------------------------------------
def _bad_files(d, h):
    nan = h[7].copy()
    nan[100:103] = np.nan
    np.savetxt(d / "nan.txt", nan, fmt="%.17g")
    x = np.arange(256) * DX
    x[50] += 0.3 * DX
    np.savetxt(d / "uneven.txt", np.column_stack([x, h[7]]), fmt="%.17g")
    np.savetxt(d / "xh.txt", np.column_stack([np.arange(256) * DX, h[7]]), fmt="%.17g")
    np.savetxt(d / "short.txt", h[7, :20], fmt="%.17g")
    (d / "scan.x3p").write_bytes(b"PK\x03\x04")
    return d


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["psd", "{d}/column.txt"], "--dx [m] is required"),
        (["psd", "{d}/rows.txt", "--units", "um"], "--dx [m] is required"),
        (["psd", "{examples}/psd_example.txt"], "looks like a spectrum"),
        (["psd", "{d}/nan.txt", "--dx", DX], "--nan interpolate"),
        (["psd", "{d}/uneven.txt"], "not uniformly spaced"),
        (["psd", "{d}/xh.txt", "--dx", 2 * DX], "--dx = 4e-06 m disagrees"),
        (["psd", "{d}/short.txt", "--dx", DX], "at least 32 points"),
        (["psd", "{d}/missing.txt", "--dx", DX], "no such file"),
        (["psd", "{d}", "--dx", DX], "is a directory"),
        (["psd", "{d}/column.txt", "--dx", DX, "--extend"], "--extend needs --q1"),
        (["psd", "{d}/column.txt", "--dx", DX, "--detrend", "plane"], "--map"),
        (["psd", "{d}/column.txt", "--dx", DX, "--dy", DX], "--dy"),
        (["psd", "{d}/column.txt", "--dx", DX, "--units", "inch"], "--units"),
        (["psd", "{d}/column.txt", "--dx", "-1e-6"], "must be > 0"),
        (["psd", "{d}/column.txt", "--dx", DX, "--q-range", 1e5, 2e4], "lo < hi"),
        (["psd", "{d}/column.txt", "--dx", DX, "--window", "nonsense"], "window"),
        (["profile", "--scan", "{d}/column.txt", "--dx", DX, "--hurst", 0.7], "--hurst"),
        (["profile", "--scan", "{d}/column.txt", "--psd", "{d}/p.txt"], "--psd"),
        (["sweep", "--dx", DX, "--units", "um"], "--dx, --units need --scan"),
        (["leak", "--scan", "{examples}/psd_example.txt", "--pressure-drop", 1, "--viscosity", 1],
         "looks like a spectrum"),
    ],
)  # fmt: skip
def test_bad_input(argv, needle, scans, capsys, request):
    d, h = scans
    _bad_files(d, h)
    examples = request.config.rootpath / "examples"
    argv = [str(a).format(d=d, examples=examples) for a in argv]
    status, out, err = run(argv, capsys)
    assert status == 2 and out == "", out
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("fastline: error:"), err
    assert needle in lines[0]
    assert not list(d.glob("*.png"))


def test_dropouts_bridged_on_request(scans, capsys):
    d, h = scans
    _bad_files(d, h)
    status, stdout, _ = run(["psd", d / "nan.txt", "--dx", DX, "--nan", "interpolate"], capsys)
    assert status == 0 and "one profile of 256 points" in stdout


def test_instrument_format_without_the_extra(scans, capsys):
    try:
        import SurfaceTopography  # noqa: F401
    except ImportError:
        pass
    else:
        pytest.skip("SurfaceTopography is installed: it reads the file (a bad one) itself")
    d, h = scans
    _bad_files(d, h)
    status, _, err = run(["psd", d / "scan.x3p"], capsys)
    assert status == 2 and '"fastline-contact[topography]"' in err


@pytest.mark.parametrize(
    "argv",
    [
        ["psd", "{d}/rows.txt", "--dx", DX, "--out", "/nonexistent-dir/psd.csv"],
        ["psd", "{d}/rows.txt", "--dx", DX, "--plot", "/nonexistent-dir/psd.png"],
        ["profile", "--scan", "{d}/rows.txt", "--dx", DX, "--csv", "/nonexistent-dir/p.csv"],
        ["sweep", "--scan", "{d}/rows.txt", "--dx", DX, "--plot", "/nonexistent-dir/s.png"],
    ],
)
def test_output_paths_checked_before_work(argv, scans, monkeypatch, capsys):
    def no_work(*args, **kwargs):
        raise AssertionError("read the scan before checking the output path")

    monkeypatch.setattr(fastline.surfaces, "analyse_scan", no_work)
    d, _ = scans
    status, _, err = run([str(a).format(d=d) for a in argv], capsys)
    assert status == 2 and "/nonexistent-dir" in err and "does not exist" in err


def test_plot_without_matplotlib_is_refused_before_work(scans, monkeypatch, tmp_path, capsys):
    import sys

    d, _ = scans
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setattr(fastline.surfaces, "analyse_scan", None)  # any call would fail loudly
    status, _, err = run(["psd", d / "rows.txt", *ROWS, "--plot", tmp_path / "x.png"], capsys)
    assert status == 2 and "plotting needs matplotlib" in err


def test_fit_held_at_its_bound_is_said(tmp_path, capsys):
    """C ~ q^-5 falls faster than any self-affine spectrum (H <= 1): the fit holds H = 1 and
    the summary says so instead of printing an error bar."""
    q = np.geomspace(1e3, 2e6, 50)
    steep = fl.TabulatedPSD(q, 1e-18 * (q / 1e3) ** -5.0)
    with np.errstate(divide="ignore"):  # the grid's q = 0 mode, outside the table
        h = tp.synthetic_surface(steep, 256, DX, seed=4)
    np.savetxt(tmp_path / "steep.txt", h[::32], fmt="%.17g")
    status, out, _ = run(["psd", tmp_path / "steep.txt", "--dx", DX], capsys)
    assert status == 0
    assert "fit              H 1 (held at its bound: C falls faster than self-affine can)" in out


def _named_walk(tmp_path):
    """A random walk with a header naming its units (x in um, heights in nm)."""
    x = np.arange(512) * 0.5  # um
    h = np.random.default_rng(4).standard_normal(512).cumsum() * 20.0  # nm
    path = tmp_path / "named.csv"
    path.write_text(
        "Position [um],Height [nm]\n" + "".join(f"{a},{b}\n" for a, b in zip(x, h, strict=True))
    )
    return path


def test_psd_units_from_the_header_and_contradicting_options(tmp_path, capsys):
    """A header naming the units is used; --units that contradicts it is a usage error naming
    --units; the summary says what was left out above the range."""
    path = _named_walk(tmp_path)
    status, stdout, err = run(["psd", path], capsys)
    assert status == 0 and error_lines(err) == []
    assert "dx 5e-07 m" in stdout and stdout.count("left out ") == 1
    status, _, err = run(["psd", path, "--units", "mm"], capsys)
    assert status == 2 and "--units mm" in err and "contradicts" in err


def test_profile_scan_says_what_psd_says(tmp_path, capsys):
    """profile --scan prints the scan's whole summary (ScanSpectrum.summary, which
    ScanSpectrum.describe returns), as fastline psd does: every line but psd's C(q) table line,
    the line saying what the noise floor left out included."""
    path = _named_walk(tmp_path)
    status, out_psd, _ = run(["psd", path], capsys)
    assert status == 0
    status, out, _ = run(["profile", "--scan", path, *SCENE], capsys)
    assert status == 0
    with warnings.catch_warnings():  # those of the commands above, already checked there
        warnings.simplefilter("ignore")
        scan = fastline.surfaces.analyse_scan(path)
    assert scan.describe() == scan.summary() and scan.summary(table=False) in out
    shared = [ln for ln in out_psd.splitlines() if ln.startswith(("scan ", "data ", "q range"))]
    shared += [ln for ln in out_psd.splitlines() if ln.startswith(("left out ", "fit  "))]
    assert len(shared) == 5 and all(ln in out.splitlines() for ln in shared)
    assert "C(q) table" in out_psd and "C(q) table" not in out


def test_empty_files_are_refused_before_any_reader(tmp_path, capsys):
    (tmp_path / "empty.txt").write_bytes(b"")
    (tmp_path / "empty.sur").write_bytes(b"")  # an instrument's extension: no reader either
    paths = [tmp_path / "empty.txt", tmp_path / "empty.sur"]
    paths += ["/dev/null"] if os.path.exists("/dev/null") else []
    for path in paths:
        status, out, err = run(["psd", path, "--dx", DX], capsys)
        assert status == 2 and out == "" and warning_lines(err) == [], err
        lines = error_lines(err)
        assert len(lines) == 1 and lines[0].startswith(f"fastline: error: {path} is empty"), err


def test_reading_through_surfacetopography_prints_no_mpi_note(tmp_path):
    pytest.importorskip("SurfaceTopography")
    path = tmp_path / "binary.txt"  # defeats fastline's text reader: SurfaceTopography is tried
    path.write_bytes(bytes(range(256)) * 2)
    root = pathlib.Path(__file__).resolve().parents[1]
    proc = subprocess.run(
        [sys.executable, "-m", "fastline", "psd", str(path), "--dx", str(DX)],
        cwd=root, capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert proc.returncode == 2 and "cannot read it as a scan" in proc.stderr
    assert "mpi4py" not in proc.stderr and warning_lines(proc.stderr) == [], proc.stderr
