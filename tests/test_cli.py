"""Tests of the command-line interface (run in-process through fastline.cli.app.main).

Every command on small settings: the files it writes, its numbers against the API's, and the
defects a random campaign of scenes found (exit status of a non-converged solve, warnings
reaching ``sweep``, ``--gamma``, spectrum files, negative numbers, output paths checked before
any solve).
"""

import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from io import StringIO

import numpy as np
import pytest

import fastline as fl
import fastline.contact.line
from fastline.cli.app import main
from fastline.contact.line import solve_line_contact
from fastline.io import read_csv
from fastline.reports import paper

pytest.importorskip("matplotlib")

E_STAR, R = paper.E_STAR, paper.RADIUS
FIGS = ("fig2_psd", "fig3_profile", "fig4_ws", "fig5_p0ratio")
#: the CSVs hold repr() of the API's numbers: equal to round-off of the same computation
SAME = 1e-12
CONTINUATION = 1e-7  # a sweep (warm starts) against independent solves at tol 1e-8
PAPER_LOADS, N_SMALL = 3, 256
MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "pdf": b"%PDF", "svg": b"<?xml"}


def run(argv, capsys):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def warning_lines(err):
    return [ln for ln in err.splitlines() if ln.startswith("fastline: warning:")]


@pytest.fixture(scope="module")
def paper_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper")
    argv = ["paper", "--out", str(out), "--loads", str(PAPER_LOADS), "--n", str(N_SMALL)]
    so, se = StringIO(), StringIO()  # capsys is function-scoped
    with redirect_stdout(so), redirect_stderr(se):
        status = main(argv)
    return out, status, so.getvalue(), se.getvalue()


# ----------------------------------------------------------------------------------------------
# paper
# ----------------------------------------------------------------------------------------------
def test_paper_files(paper_run):
    out, status, stdout, stderr = paper_run
    assert status == 0
    for name in FIGS:
        assert (out / f"{name}.png").read_bytes()[:8] == MAGIC["png"]
        meta, cols = read_csv(out / f"{name}.csv")
        assert meta["E_star_Pa"] == repr(E_STAR) and meta["n"] == str(N_SMALL)
        assert meta["fastline_version"] == fl.__version__
    meta, cols = read_csv(out / "fig4_ws.csv")
    assert len(cols["load_N_per_m"]) == 3 * PAPER_LOADS
    assert set(cols["surface"]) == {1.0, 2.0, 3.0}
    assert np.all(cols["converged"] == 1)
    # the spectra are reported, and the warnings once per cause
    assert "rms slope" in stdout and "surface 3" in stdout and "gamma_u" in stdout
    causes = [ln for ln in warning_lines(stderr) if "narrower than the longest" in ln]
    assert len(causes) == 1 and "solves" in causes[0]


def test_paper_numbers_match_api(paper_run):
    out = paper_run[0]
    _, cols = read_csv(out / "fig5_p0ratio.csv")
    k = PAPER_LOADS + 1  # surface 2, second load
    psd = paper.surfaces()[1]
    r = solve_line_contact(psd, E_STAR, R, cols["load_N_per_m"][k], n=N_SMALL)
    assert cols["w_over_s"][k] == pytest.approx(r.w_over_s, rel=SAME)
    assert cols["p0_ratio"][k] == pytest.approx(r.p0_ratio, rel=SAME)
    assert cols["alpha"][k] == pytest.approx(r.alpha, rel=SAME)
    gu = fl.PerssonTheory(psd, E_STAR).exponential_fit().gamma_u
    assert cols["p0_ratio_eq14"][k] == pytest.approx(fl.p0_ratio_gaussian(r.alpha, gu), rel=SAME)
    loads = np.unique(cols["load_N_per_m"])
    np.testing.assert_allclose(loads, paper.paper_loads(PAPER_LOADS), rtol=SAME)


def test_paper_fig2_fig3(paper_run):
    out = paper_run[0]
    _, f2 = read_csv(out / "fig2_psd.csv")
    q = f2["q_1_per_m"][100]
    assert f2["C3_m4"][100] == pytest.approx(float(paper.surfaces()[2](q)), rel=SAME)
    meta, f3 = read_csv(out / "fig3_profile.csv")
    dx = f3["x_m"][1] - f3["x_m"][0]
    assert f3["p_rough_Pa"].sum() * dx == pytest.approx(paper.FIG3_LOAD, rel=1e-9)
    hz = fl.hertz_line_contact(E_STAR, R, paper.FIG3_LOAD)
    assert f3["p_hertz_Pa"].max() == pytest.approx(hz.p0, rel=1e-2)
    assert f3["p_rough_Pa"].max() < f3["p_hertz_Pa"].max()  # roughness lowers the peak


@pytest.mark.parametrize("fmt", ["pdf", "svg"])
def test_paper_vector_figures(fmt, tmp_path, capsys):
    status, _, _ = run(
        ["paper", "--out", tmp_path, "--loads", 2, "--n", 64, "--format", fmt], capsys
    )
    assert status == 0
    for name in FIGS:
        assert (tmp_path / f"{name}.{fmt}").read_bytes()[:5].startswith(MAGIC[fmt][:4])
        assert not (tmp_path / f"{name}.png").exists()


def test_paper_write_files_from_python(tmp_path):
    """fastline.reports.paper.write_files (what `fastline paper` calls): the files it names, in the
    format asked, with the data's variant and numbers in the CSVs."""
    data = paper.paper_data(loads=2, n=64, variant="yang-persson-printed")
    assert data.variant == "yang-persson-printed"
    written = paper.write_files(data, tmp_path, format="svg", dpi=40)
    expected = {f"{name}.{ext}" for name in FIGS for ext in ("csv", "svg")}
    assert len(written) == len(expected) and set(written) == expected
    assert {p.name for p in tmp_path.iterdir()} == expected
    meta, cols = read_csv(tmp_path / "fig4_ws.csv")
    assert meta["variant"] == "yang-persson-printed" and meta["n"] == "64"
    alphas = [r.alpha for s in data.surfaces for r in s.results]
    np.testing.assert_allclose(cols["alpha"], alphas, rtol=SAME)


# ----------------------------------------------------------------------------------------------
# profile
# ----------------------------------------------------------------------------------------------
PROFILE = ["profile", "--h-rms", 2e-6, "--hurst", 0.9, "--q1", 1e8, "--E-star", 2e9]
PROFILE += ["--radius", 0.02, "--load", 3e4, "--n", N_SMALL]


def test_profile_vs_api_and_csv_header(tmp_path, capsys):
    csv_path, png = tmp_path / "p.csv", tmp_path / "p.png"
    status, out, err = run(
        PROFILE + ["--csv", csv_path, "--plot", png, "--hardness", 1e12, "--dpi", 60], capsys
    )
    assert status == 0
    psd = fl.SelfAffinePSD(2e-6, 0.9, 1e3, 1e4, 1e8)
    r = solve_line_contact(psd, 2e9, 0.02, 3e4, n=N_SMALL)
    assert f"{r.p0:.6g} Pa" in out and f"{r.w_over_s:.6g}" in out
    assert "regime" in out and "converged        yes" in out and "plastic likely   no" in out
    assert f"rms slope h' {psd.rms_slope:.4g}" in out
    meta, cols = read_csv(csv_path)
    np.testing.assert_allclose(cols["p_Pa"], r.pressure, rtol=SAME)
    np.testing.assert_allclose(cols["u_m"], r.separation, rtol=SAME)
    expected = {
        "h_rms_m": 2e-6,
        "q0_1_per_m": 1e3,
        "q1_1_per_m": 1e8,
        "E_star_Pa": 2e9,
        "radius_m": 0.02,
        "gamma": 0.45,
        "n": N_SMALL,
        "load_N_per_m": 3e4,
        "rms_slope": psd.rms_slope,
    }
    for key, value in expected.items():
        assert float(meta[key]) == pytest.approx(value, rel=SAME), key
    assert meta["model"] == "persson" and meta["fastline_version"] == fl.__version__
    assert "SelfAffinePSD" in meta["spectrum"]
    assert png.read_bytes()[:8] == MAGIC["png"]


def test_profile_gamma_moves_the_result(capsys):
    # alpha ~ 3: gamma sets u0 = gamma_u h_rms and with it the Gaussian-like width
    _, out45, _ = run(PROFILE + ["--load", 1e3], capsys)
    status, out30, _ = run(PROFILE + ["--load", 1e3, "--gamma", 0.3], capsys)
    assert status == 0
    psd = fl.SelfAffinePSD(2e-6, 0.9, 1e3, 1e4, 1e8)
    r30 = solve_line_contact(psd, 2e9, 0.02, 1e3, n=N_SMALL, gamma=0.3)
    r45 = solve_line_contact(psd, 2e9, 0.02, 1e3, n=N_SMALL)
    assert abs(r30.p0 / r45.p0 - 1.0) > 1e-2  # the parameter matters here
    assert f"{r30.p0:.6g} Pa" in out30 and f"{r45.p0:.6g} Pa" in out45


def test_profile_psd_file_and_elastic_constants(tmp_path, capsys):
    psd = fl.SelfAffinePSD(5e-6, 0.8, 1e3, 1e4, 1e8)
    q = np.logspace(3, 8, 120)
    f = tmp_path / "psd.txt"
    body = "\n".join(f"{float(a)!r}, {float(b)!r}" for a, b in zip(q, psd(q), strict=True))
    f.write_text("# q [1/m], C [m^4]\n" + body + "\n")
    args = ["profile", "--psd", f, "--E1", 2.1e11, "--nu1", 0.3, "--E2", 3e9, "--nu2", 0.4]
    status, out, _ = run(args + ["--load", 2e4, "--n", N_SMALL, "--model", "exponential"], capsys)
    assert status == 0
    E = fl.effective_modulus(2.1e11, 0.3, 3e9, 0.4)
    tab = fl.TabulatedPSD(q, psd(q))
    r = solve_line_contact(tab, E, R, 2e4, n=N_SMALL, model="exponential")
    assert f"{r.p0:.6g} Pa" in out and "exp. law valid" in out
    assert f"file {f}" in out and f"h_rms {tab.h_rms:.4g} m" in out


def test_profile_reports_each_warning_once(capsys):
    # O-ring-like scene with the exponential law: outside the law's range and narrower
    # than the longest roughness wavelength
    argv = ["profile", "--E1", 2.1e11, "--nu1", 0.3, "--E2", 5e6, "--nu2", 0.49, "--radius"]
    argv += [1.75e-3, "--load", 50, "--model", "exponential", "--h-rms", 1e-6, "--q0", 2e3]
    status, _, err = run(argv + ["--qr", 2e4, "--n", N_SMALL], capsys)
    assert status == 0
    lines = warning_lines(err)
    assert len(lines) == 2
    assert "model='exponential' is used outside its range" in lines[0]
    assert "narrower than the longest roughness wavelength" in lines[1]


def test_height_file_rejected(tmp_path, capsys):
    x = np.linspace(0.0, 1e-3, 50)
    f = tmp_path / "height.txt"
    f.write_text("\n".join(f"{a:.9g} {1e-6 * np.sin(9e3 * a):.9g}" for a in x))
    status, out, err = run(["profile", "--psd", f], capsys)
    assert status == 2 and out == ""
    assert "this looks like a height profile, not a spectrum" in err


def test_psd_with_spectrum_options_is_an_error(tmp_path, capsys):
    f = tmp_path / "psd.txt"
    f.write_text("1e3 1e-20\n1e6 1e-30\n")
    status, _, err = run(["profile", "--psd", f, "--h-rms", 1e-6, "--hurst", 0.7], capsys)
    assert status == 2 and "--psd cannot be combined with --h-rms, --hurst" in err


def test_non_converged_solve_exits_non_zero(tmp_path, capsys):
    csv_path = tmp_path / "p.csv"
    status, out, err = run(PROFILE + ["--max-iter", 1, "--csv", csv_path], capsys)
    assert status == 1
    assert "converged        NO" in out and "did not converge" in err
    assert csv_path.exists()  # the results are still written
    status, _, err = run(
        ["sweep", "--loads-num", 2, "--n", 64, "--max-iter", 1, "--loads-to", 1e4], capsys
    )
    assert status == 1 and "2 of 2 solves did not converge" in err


# ----------------------------------------------------------------------------------------------
# sweep
# ----------------------------------------------------------------------------------------------
SWEEP = ["sweep", "--h-rms", 1e-6, "--loads-from", 1e3, "--loads-to", 1e5, "--loads-num", 4]
SWEEP += ["--n", N_SMALL]


def test_sweep_vs_api(tmp_path, capsys):
    path, png = tmp_path / "s.csv", tmp_path / "s.svg"
    status, out, _ = run(SWEEP + ["--csv", path, "--plot", png], capsys)
    assert status == 0
    meta, cols = read_csv(path)
    assert list(cols) == list(fl.io.SWEEP_COLUMNS)
    assert float(meta["h_rms_m"]) == 1e-6 and meta["model"] == "persson"
    psd = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)
    np.testing.assert_allclose(cols["load_N_per_m"], np.geomspace(1e3, 1e5, 4), rtol=SAME)
    swept = fl.LineContact(psd, E_STAR, R, n=N_SMALL).sweep(cols["load_N_per_m"])
    for k, f in enumerate(cols["load_N_per_m"]):
        r = swept[k]  # the command is LineContact.sweep
        assert cols["w_over_s"][k] == pytest.approx(r.w_over_s, rel=SAME)
        assert cols["p0_ratio"][k] == pytest.approx(r.p0_ratio, rel=SAME)
        assert cols["s_m"][k] == pytest.approx(r.s, rel=SAME)
        alone = solve_line_contact(psd, E_STAR, R, f, n=N_SMALL)  # to the solver tolerance
        assert cols["w_over_s"][k] == pytest.approx(alone.w_over_s, rel=CONTINUATION)
    assert "rms slope" in out and "model            persson (method newton" in out
    assert png.read_bytes()[:5] == MAGIC["svg"]
    status, out, _ = run(SWEEP + ["--model", "exponential"], capsys)
    assert status == 0 and "model            exponential" in out


def test_sweep_reports_warnings_once_with_loads(capsys):
    # the paper's load range: half-width 38 % of R at 1.5e6 N/m; the hardness is exceeded at
    # every load (h'E*/2 ~ 1 GPa for q1 = 1e9 1/m)
    argv = ["sweep", "--loads-num", 5, "--n", 128, "--hardness", 1e8]
    status, _, err = run(argv, capsys)
    assert status == 0
    lines = warning_lines(err)
    half = [ln for ln in lines if "half-space" in ln]
    plastic = [ln for ln in lines if "hardness" in ln]
    assert len(half) == 1 and "1.5e+06" in half[0] and "of 5 solves" in half[0]
    assert len(plastic) == 1 and "5 of 5 solves" in plastic[0]
    assert len(lines) == len(set(lines))


def test_sweep_gamma_moves_the_result(tmp_path, capsys):
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    assert run(SWEEP + ["--csv", a], capsys)[0] == 0
    assert run(SWEEP + ["--csv", b, "--gamma", 0.3], capsys)[0] == 0
    meta_b, cols_b = read_csv(b)
    assert float(meta_b["gamma"]) == 0.3
    change = np.abs(cols_b["p0_Pa"] / read_csv(a)[1]["p0_Pa"] - 1.0)
    assert change[0] > 1e-2 and np.all(change > 1e-6)  # most at the smallest load (alpha ~ 1)


# ----------------------------------------------------------------------------------------------
# bad input: one line, exit status 2, nothing solved
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "argv, needle",
    [
        (["profile", "--load", "abc"], "--load"),
        (["profile", "--load", "-5"], "must be > 0"),
        (["profile", "--load", "-1e4"], "must be > 0"),
        (["sweep", "--loads-from", "-1.5E+3"], "must be > 0"),
        (["profile", "--radius", "nan"], "--radius"),
        (["profile", "--gamma", "0"], "--gamma"),
        (["profile", "--hurst", "3"], "hurst"),  # ValueError from the library
        (["profile", "--E1", "2e11"], "--E2"),
        (
            [
                "profile",
                "--E-star",
                "1e9",
                "--E1",
                "1e9",
                "--nu1",
                "0.3",
                "--E2",
                "1e9",
                "--nu2",
                "0.3",
            ],
            "--E-star",
        ),
        (["profile", "--model", "bogus"], "--model"),
        (["profile", "--format", "jpg"], "--format"),
        (["profile", "--psd", "/nonexistent/psd.txt"], "psd.txt"),
        (["paper"], "--out"),
        (["sweep", "--loads-from", "1e5", "--loads-to", "1e3"], "--loads-to"),
        (["frobnicate"], "frobnicate"),
    ],
)
def test_bad_options(argv, needle, capsys):
    status, out, err = run(argv, capsys)
    assert status == 2
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith("fastline: error:") and needle in lines[0]
    assert "Traceback" not in err + out and "expected one argument" not in err


@pytest.mark.parametrize(
    "extra, named",
    [
        (["--h-rms", "1e-6"], ["--h-rms"]),
        (["--gamma", "0.3"], ["--gamma"]),
        (["--variant", "yang-persson-energy"], ["--variant"]),  # the default, but given
        (["--psd", "examples/psd_example.txt", "--hardness", "1e9"], ["--psd", "--hardness"]),
        (["--hurst", "0.5", "--q0", "2e3", "--qr", "2e4", "--q1", "1e8"], ["--hurst", "--q1"]),
        (["--scan", "examples/scan_example.txt", "--dx", "1e-6"], ["--scan"]),
        (["--geometry", "sphere", "--gamma", "0.5"], ["--gamma"]),
    ],
)
@pytest.mark.parametrize("command", ["profile", "sweep"])
def test_hertz_refuses_roughness_options(command, extra, named, monkeypatch, capsys):
    """--model hertz solves smooth surfaces: roughness and theory options would be silently
    ignored, so they are refused by name (one line, exit 2) before anything is read or solved."""

    def no_solve(*args, **kwargs):
        raise AssertionError("solved")

    monkeypatch.setattr(fl, "solve_line_contact", no_solve)  # the name the CLI calls
    monkeypatch.setattr(fastline.contact.line, "solve_line_contact", no_solve)
    monkeypatch.setattr(fastline.contact.line.LineContact, "sweep", no_solve)
    status, out, err = run([command, "--model", "hertz", *extra], capsys)
    assert status == 2 and out == ""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("fastline: error: --model hertz"), err
    assert all(flag in lines[0] for flag in named)


@pytest.mark.parametrize("geometry", ["cylinder", "sphere"])
def test_hertz_prints_no_roughness(geometry, capsys):
    """A smooth scene shows no spectrum, alpha or regime (they would describe a roughness the
    solve never saw); a rough scene of the same command still shows all three."""
    base = ["--geometry", geometry, "--n", 64]
    status, out, _ = run(["profile", "--model", "hertz", *base], capsys)
    assert status == 0 and out.startswith("spectrum         none: --model hertz")
    assert "h_rms" not in out and "\nalpha" not in out and "\nregime" not in out
    status, out, _ = run(["sweep", "--model", "hertz", "--loads-num", 2, *base], capsys)
    rows = [ln.split() for ln in out.splitlines()[-2:]]
    assert status == 0 and [row[1] for row in rows] == ["-", "-"], out
    status, out, _ = run(["profile", "--model", "persson", *base], capsys)
    assert "h_rms" in out and "\nalpha" in out and "\nregime" in out


def test_hertz_alone_and_theory_options_with_other_models(capsys):
    """The refusal is hertz's only: --model hertz alone solves, --gamma and --variant still
    reach the exponential law."""
    status, out, _ = run(["profile", "--model", "hertz", "--n", 64], capsys)
    assert status == 0 and "model            hertz" in out
    base = ["profile", "--model", "exponential", "--n", 64, "--load", 1e3]
    _, out45, _ = run(base, capsys)
    status, out30, _ = run(base + ["--gamma", 0.3, "--variant", "yang-persson-printed"], capsys)
    assert status == 0 and "model            exponential" in out30
    peak = [ln for ln in out45.splitlines() if ln.startswith("peak pressure")]
    assert peak and peak[0] not in out30  # the theory options moved the result


@pytest.mark.parametrize(
    "argv",
    [
        ["profile", "--csv", "/nonexistent-dir/p.csv"],
        ["profile", "--plot", "/nonexistent-dir/p.png"],
        ["sweep", "--csv", "/nonexistent-dir/s.csv"],
        ["paper", "--out", "/proc/fastline-out"],
    ],
)
def test_output_paths_checked_before_solving(argv, monkeypatch, capsys):
    def no_solve(*args, **kwargs):
        raise AssertionError("solved before checking the output path")

    monkeypatch.setattr(fl, "solve_line_contact", no_solve)  # the name the CLI calls
    monkeypatch.setattr(fastline.contact.line, "solve_line_contact", no_solve)
    monkeypatch.setattr(fastline.reports.paper, "paper_data", no_solve)
    status, _, err = run(argv, capsys)
    assert status == 2 and err.startswith("fastline: error:") and "/" in err


def test_output_path_is_a_directory(tmp_path, capsys):
    status, _, err = run(["profile", "--csv", tmp_path], capsys)
    assert status == 2 and "is a directory" in err


def test_missing_matplotlib(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    status, _, err = run(["paper", "--out", tmp_path], capsys)
    assert status == 2
    assert "plotting needs matplotlib" in err and len(err.strip().splitlines()) == 1


# ----------------------------------------------------------------------------------------------
# help and entry points
# ----------------------------------------------------------------------------------------------
def test_module_help_subprocess():
    res = subprocess.run(
        [sys.executable, "-m", "fastline", "--help"], capture_output=True, text=True, timeout=60
    )
    assert res.returncode == 0
    assert "N/m" in res.stdout and "paper" in res.stdout and "profile" in res.stdout


@pytest.mark.parametrize("sub", ["paper", "profile", "sweep"])
def test_subcommand_help_has_units_and_common_options(sub, capsys):
    with pytest.raises(SystemExit) as e:
        main([sub, "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert "[1/m]" in out or "N/m" in out
    for opt in ("--gamma", "--format", "--dpi", "--hardness", "--max-iter", "--n"):
        assert opt in out, opt


def test_bad_option_subprocess_no_traceback():
    res = subprocess.run(
        [sys.executable, "-m", "fastline", "profile", "--q1", "10"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert res.returncode == 2
    assert "Traceback" not in res.stderr and len(res.stderr.strip().splitlines()) == 1


def test_no_command_prints_help(capsys):
    assert main([]) == 2
    assert "usage" in capsys.readouterr().out
