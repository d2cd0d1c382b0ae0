"""Inputs a new user gets wrong, and what fastline answers: a modulus typed in MPa as Pa warns
with the likely unit (and the load that then falls out of range blames the modulus), huge
iteration caps and bin counts are refused by name, ``warn`` must be a bool, the critical gap
stays finite and silent at vanishing and enormous pressures, and a spectrum file's path is
accepted wherever a spectrum is.
"""

import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import fastline as fl
from fastline.cli.app import main
from fastline.io import read_csv

PSD = fl.SelfAffinePSD(1e-6, 0.8, 1e4, 1e4, 1e9)
E_STAR, R, LOAD = 1.33e9, 0.01, 1e4
#: the low-pressure continuation of the critical gap against direct solves (relative)
LOW_P_GAP = 1e-6


def caught(fn):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        out = fn()
    return out, w


@pytest.mark.parametrize("E, unit", [(5.0, "MPa"), (5e3, "kPa"), (5e12, "GPa")])
def test_implausible_modulus_warns_once_with_the_unit(E, unit):
    """E* outside [1e4, 1.2e12] Pa: one UnitWarning naming the likely unit, at the user's line."""
    _, w = caught(lambda: fl.LineContact(None, E, R, model="hertz"))
    slips = [x for x in w if issubclass(x.category, fl.UnitWarning)]
    assert len(slips) == 1 and unit in str(slips[0].message)
    assert slips[0].filename == __file__


def test_a_table_sweeps_modulus_warning_points_at_the_callers_line():
    """Reached through another subpackage (fl.sweep -> the scene's LineContact), the
    implausible-modulus warning still names the user's line, not fastline's."""
    scene = dict(h_rms=1e-6, hurst=0.8, q0=1e4, qr=1e4, q1=1e9, E_star=5e3, radius=R, load=1.0)
    table, w = caught(lambda: fl.sweep([scene], "serial", progress=False))
    units = [x for x in w if issubclass(x.category, fl.UnitWarning)]
    assert len(units) == 1 and units[0].filename == __file__


@pytest.mark.parametrize("E", [1e4, 1.33e9, 1.2e12])
def test_plausible_modulus_is_silent(E):
    _, w = caught(lambda: fl.check_modulus(E))
    assert not [x for x in w if issubclass(x.category, fl.UnitWarning)]


def test_load_out_of_range_blames_an_implausible_modulus():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fl.UnitWarning)
        with pytest.raises(ValueError, match="E_star = 5 Pa looks like a unit slip"):
            fl.solve_line_contact(PSD, 5.0, R, LOAD, n=64)
        with pytest.raises(ValueError, match=r"^load must lie"):  # a plausible E*: the load
            fl.solve_line_contact(PSD, E_STAR, R, 1e20, n=64)


def test_cli_modulus_in_mpa(capsys):
    status = main(["profile", "--E-star", "5", "--n", "64"])
    err = capsys.readouterr().err.splitlines()
    assert status == 2
    assert err[0].startswith("fastline: warning: --E-star = 5 Pa") and "5 MPa = 5e+06 Pa" in err[0]
    assert err[1].startswith("fastline: error: E_star = 5 Pa looks like a unit slip")
    assert len(err) == 2


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: fl.solve_line_contact(PSD, E_STAR, R, LOAD, n=64, max_iter=10**18), "max_iter"),
        (lambda: fl.LineContact(PSD, E_STAR, R, n=64, max_iter=0), "max_iter"),
        (
            lambda: fl.topography.psd_from_profile(np.sin(np.arange(256.0)), 1e-6,
                                                   bins_per_decade=10**18),
            "bins_per_decade",
        ),
    ],
)  # fmt: skip
def test_huge_counts_refused_by_name(call, name):
    with pytest.raises(ValueError, match=rf"{name} must be an integer in \[\d+, \d+\]"):
        call()


@pytest.mark.parametrize("warn", ["abc", "False", None, 2.0])
def test_warn_must_be_a_bool(warn):
    with pytest.raises(TypeError, match="warn must be True or False"):
        fl.LineContact(PSD, E_STAR, R, n=64, warn=warn)


@pytest.mark.parametrize("geometry", ["line", "point"])
def test_a_sweeps_progress_must_be_callable(geometry):
    """A progress that is not callable is refused by name before any solve (it failed with
    "'str' object is not callable" after the first load)."""
    model = (fl.LineContact if geometry == "line" else fl.PointContact)(PSD, E_STAR, R, n=64)
    with pytest.raises(TypeError, match="progress must be None or a callable"):
        model.sweep([1e3, 1e4] if geometry == "line" else [1.0, 2.0], progress="x")


@pytest.mark.parametrize("name, value", [("progress", "x"), ("warn", None), ("warn", "no")])
def test_a_table_sweeps_flags_must_be_bools(name, value):
    scenes = [dict(h_rms=1e-6, hurst=0.8, q0=1e4, q1=1e9, E_star=E_STAR, radius=R, load=LOAD)]
    with pytest.raises(TypeError, match=f"{name} must be True or False"):
        fl.sweep(scenes, "serial", **{name: value})


@pytest.mark.parametrize("model", ["persson", "hertz"])
@pytest.mark.parametrize("option", [dict(u0=-1.0), dict(beta=float("nan")), dict(u0=1e-6)])
def test_exponential_parameters_with_another_model_are_refused(model, option):
    """u0 and beta belong to the exponential law: with another model they were ignored."""
    with pytest.raises(ValueError, match="u0 and beta set the exponential law"):
        fl.solve_line_contact(PSD, E_STAR, R, LOAD, model=model, n=64, **option)


def test_critical_gap_at_vanishing_pressure_is_finite_and_logarithmic():
    """Below ~1e-100 E* the direct solve's moment underflows (it gave inf): the continuation
    must be finite, fall with p, and follow the line u_c(ln p) of the direct solves above."""
    th = fl.PerssonTheory(PSD, E_STAR)
    p = np.array([1e-300, 1e-200, 1e-155, 1e-120, 1e-90, 1e-60])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        u = th.critical_gap(p).u_c
    assert np.all(np.isfinite(u)) and np.all(np.diff(u) < 0)
    slope = (u[-1] - u[-2]) / np.log(p[-1] / p[-2])  # direct solves, m above the floor
    line = u[-1] + slope * np.log(p / p[-1])
    np.testing.assert_allclose(u, line, rtol=LOW_P_GAP)


def test_critical_gap_at_huge_pressure_is_sealed_and_silent():
    th = fl.PerssonTheory(PSD, E_STAR)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an overflow RuntimeWarning would fail here
        r = th.critical_gap(1e300)
    assert r.sealed and r.u_c == 0.0


# ---- files ------------------------------------------------------------------------------------
EXAMPLE_PSD = str(Path(__file__).parent.parent / "examples" / "psd_example.txt")


def test_solve_reads_a_spectrum_path_as_sweep_does():
    direct = fl.solve_line_contact(EXAMPLE_PSD, E_STAR, R, LOAD, n=64, warn=False)
    psd = fl.io.read_spectrum(EXAMPLE_PSD)
    read = fl.solve_line_contact(psd, E_STAR, R, LOAD, n=64, warn=False)
    table = fl.sweep([dict(psd=EXAMPLE_PSD, E_star=E_STAR, radius=R, load=LOAD, n=64)],
                     progress=False)  # fmt: skip
    assert direct.p0 == read.p0 == table["p0"][0]
    assert fl.LineContact(Path(EXAMPLE_PSD), E_STAR, R, n=64).psd.h_rms == psd.h_rms
    with pytest.raises(ValueError, match="nope.txt"):
        fl.solve_line_contact("nope.txt", E_STAR, R, LOAD, n=64)


def test_profile_csv_header_has_the_p0_ratio(tmp_path):
    r = fl.solve_line_contact(None, E_STAR, R, LOAD, model="hertz", n=64)
    fl.io.write_profile_csv(tmp_path / "p.csv", r)
    meta, _ = fl.io.read_csv(tmp_path / "p.csv")
    assert float(meta["p0_ratio"]) == r.p0_ratio


def test_text_cells_quoted_as_csv(tmp_path):
    fl.io.write_csv(tmp_path / "t.csv", ["label", "x"], [('a, "b"', 1.0), ("  c", 2.0)])
    _, cols = fl.io.read_csv(tmp_path / "t.csv")
    assert cols["label"].tolist() == ['a, "b"', "  c"] and cols["x"].tolist() == [1.0, 2.0]


@pytest.mark.parametrize("name", ["out.jpg", "out.JPEG", "out.tiff"])
def test_figure_extension_written_or_refused(name, tmp_path, capsys):
    pytest.importorskip("matplotlib")
    with pytest.raises(ValueError, match=rf"{name}: figures are written as png, pdf, svg"):
        fl.plotting.figure_format(name)
    status = main(["profile", "--model", "hertz", "--n", "64", "--plot", str(tmp_path / name)])
    assert status == 2 and name in capsys.readouterr().err
    assert not (tmp_path / name).exists()
    assert fl.plotting.figure_format("out") == "png"
    assert fl.plotting.figure_format("out.SVG") == "svg"
    with pytest.raises(ValueError, match="contradicts format pdf"):
        fl.plotting.figure_format("out.png", "pdf")


def test_a_closed_pipe_ends_quietly(tmp_path):
    """``fastline ... | head -1``: the reader leaves; no BrokenPipeError traceback, the exit
    status of a Unix tool killed by SIGPIPE (128 + 13), and the files asked for are still
    written (unbuffered output: the first line already meets the closed pipe)."""
    csv = tmp_path / "profile.csv"
    argv = [sys.executable, "-u", "-m", "fastline", "profile", "--model", "hertz", "--n", "64",
            "--csv", str(csv)]  # fmt: skip
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            cwd=Path(__file__).parent.parent)  # fmt: skip
    proc.stdout.close()  # before the first line is written
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=600) == 141
    assert "Traceback" not in err and "BrokenPipe" not in err
    header, columns = read_csv(csv)
    assert header["model"] == "hertz" and len(columns["p_Pa"]) == 64
