"""Tests of the command-line interface (run in-process through fastline.cli.main)."""

import csv
import math
import subprocess
import sys

import numpy as np
import pytest

import fastline as fl
from fastline.cli import main
from fastline.line_contact import solve_line_contact

pytest.importorskip("matplotlib")

E_STAR, R = 1.33e9, 0.01
FIGS = ("fig2_psd", "fig3_profile", "fig4_ws", "fig5_p0ratio")


def read_csv(path):
    with open(path, encoding="utf-8") as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    return list(csv.DictReader(lines))


@pytest.fixture(scope="module")
def paper_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper")
    assert main(["paper", "--out", str(out), "--loads", "6", "--n", "256"]) == 0
    return out


def test_paper_files(paper_dir):
    for name in FIGS:
        png = paper_dir / f"{name}.png"
        assert png.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert (paper_dir / f"{name}.csv").stat().st_size > 0
    rows = read_csv(paper_dir / "fig4_ws.csv")
    assert len(rows) == 18
    assert {r["surface"] for r in rows} == {"1", "2", "3"}
    assert all(r["converged"] == "1" for r in rows)


def test_paper_numbers_match_api(paper_dir):
    rows = read_csv(paper_dir / "fig5_p0ratio.csv")
    row = rows[8]  # surface 2, third load
    psd = fl.SelfAffinePSD(float(row["h_rms_m"]), float(row["hurst"]), 1e3, 1e4, 1e9)
    r = solve_line_contact(psd, E_STAR, R, float(row["load_N_per_m"]), n=256)
    assert float(row["w_over_s"]) == pytest.approx(r.w_over_s, rel=1e-9)
    assert float(row["p0_ratio"]) == pytest.approx(r.p0_ratio, rel=1e-9)
    assert float(row["alpha"]) == pytest.approx(r.alpha, rel=1e-12)
    gu = fl.PerssonTheory(psd, E_STAR).exponential_fit().gamma_u
    assert float(row["p0_ratio_eq14"]) == pytest.approx(
        fl.p0_ratio_gaussian(r.alpha, gu), rel=1e-12
    )
    loads = sorted({float(r["load_N_per_m"]) for r in rows})
    assert loads[0] == pytest.approx(1e3) and loads[-1] == pytest.approx(1.5e6)


def test_paper_fig2_fig3(paper_dir):
    f2 = read_csv(paper_dir / "fig2_psd.csv")
    psd3 = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)
    q = float(f2[100]["q_1_per_m"])
    assert float(f2[100]["C3_m4"]) == pytest.approx(float(psd3(q)), rel=1e-12)
    f3 = read_csv(paper_dir / "fig3_profile.csv")
    x = np.array([float(r["x_m"]) for r in f3])
    p = np.array([float(r["p_rough_Pa"]) for r in f3])
    ph = np.array([float(r["p_hertz_Pa"]) for r in f3])
    dx = x[1] - x[0]
    assert p.sum() * dx == pytest.approx(1e4, rel=1e-6)
    assert ph.max() == pytest.approx(fl.hertz_line_contact(E_STAR, R, 1e4).p0, rel=1e-2)
    assert p.max() < ph.max()  # roughness lowers and widens the profile


def test_paper_summary_and_progress(paper_dir, tmp_path, capsys):
    assert main(["paper", "--out", str(tmp_path), "--loads", "2", "--n", "64"]) == 0
    out, err = capsys.readouterr()
    assert "surface 3" in out and "gamma_u" in out
    assert "6/6" in err and "#" in err


def test_profile_vs_api(tmp_path, capsys):
    csv_path, png = tmp_path / "p.csv", tmp_path / "p.png"
    args = [
        "profile",
        "--h-rms",
        "2e-6",
        "--hurst",
        "0.9",
        "--q1",
        "1e8",
        "--E-star",
        "2e9",
        "--radius",
        "0.02",
        "--load",
        "3e4",
        "--n",
        "256",
        "--csv",
        str(csv_path),
        "--plot",
        str(png),
        "--hardness",
        "1e12",
    ]
    assert main(args) == 0
    out = capsys.readouterr().out
    psd = fl.SelfAffinePSD(2e-6, 0.9, 1e3, 1e4, 1e8)
    r = solve_line_contact(psd, 2e9, 0.02, 3e4, n=256)
    assert f"{r.p0:.6g} Pa" in out and f"{r.w_over_s:.6g}" in out
    assert "regime" in out and "converged        yes" in out and "plastic likely   no" in out
    rows = read_csv(csv_path)
    p = np.array([float(x["p_Pa"]) for x in rows])
    u = np.array([float(x["u_m"]) for x in rows])
    np.testing.assert_allclose(p, r.pressure, rtol=1e-12)
    np.testing.assert_allclose(u, r.separation, rtol=1e-12)
    assert png.exists()


def test_profile_elastic_constants_and_psd_file(tmp_path, capsys):
    psd = fl.SelfAffinePSD(5e-6, 0.8, 1e3, 1e4, 1e8)
    q = np.logspace(3, 8, 120)
    f = tmp_path / "psd.txt"
    body = "\n".join(f"{float(a)!r}, {float(b)!r}" for a, b in zip(q, psd(q), strict=True))
    f.write_text("# q [1/m], C [m^4]\n" + body + "\n")
    args = [
        "profile",
        "--psd",
        str(f),
        "--E1",
        "2.1e11",
        "--nu1",
        "0.3",
        "--E2",
        "3e9",
        "--nu2",
        "0.4",
        "--load",
        "2e4",
        "--n",
        "256",
        "--model",
        "exponential",
    ]
    assert main(args) == 0
    out = capsys.readouterr().out
    E = fl.effective_modulus(2.1e11, 0.3, 3e9, 0.4)
    r = solve_line_contact(fl.TabulatedPSD(q, psd(q)), E, R, 2e4, n=256, model="exponential")
    assert f"{r.p0:.6g} Pa" in out and "exp. law valid" in out


def test_sweep_vs_api(tmp_path, capsys):
    path = tmp_path / "s.csv"
    args = [
        "sweep",
        "--h-rms",
        "1e-6",
        "--loads-from",
        "1e3",
        "--loads-to",
        "1e5",
        "--loads-num",
        "4",
        "--n",
        "256",
        "--csv",
        str(path),
        "--plot",
        str(tmp_path / "s.png"),
    ]
    assert main(args) == 0
    rows = read_csv(path)
    assert len(rows) == 4
    assert list(rows[0]) == [
        "load_N_per_m",
        "alpha",
        "p0_Pa",
        "p0_ratio",
        "s_m",
        "w_m",
        "w_over_s",
        "converged",
    ]
    psd = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)
    for row, f in zip(rows, np.logspace(3, 5, 4), strict=True):
        assert float(row["load_N_per_m"]) == pytest.approx(f, rel=1e-12)
        r = solve_line_contact(psd, E_STAR, R, f, n=256)
        assert float(row["w_over_s"]) == pytest.approx(r.w_over_s, rel=1e-9)
        assert float(row["p0_ratio"]) == pytest.approx(r.p0_ratio, rel=1e-9)
        assert float(row["s_m"]) == pytest.approx(r.s, rel=1e-9)
    assert (tmp_path / "s.png").exists()


def test_module_help_subprocess():
    res = subprocess.run(
        [sys.executable, "-m", "fastline", "--help"], capture_output=True, text=True, timeout=60
    )
    assert res.returncode == 0
    assert "N/m" in res.stdout and "paper" in res.stdout and "profile" in res.stdout


@pytest.mark.parametrize("sub", ["paper", "profile", "sweep"])
def test_subcommand_help_has_units(sub, capsys):
    with pytest.raises(SystemExit) as e:
        main([sub, "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert "[1/m]" in out or "N/m" in out


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["profile", "--load", "abc"], "--load"),
        (["profile", "--load", "-5"], "--load"),
        (["profile", "--radius", "nan"], "--radius"),
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
        (["profile", "--psd", "/nonexistent/psd.txt"], "psd.txt"),
        (["paper"], "--out"),
        (["sweep", "--loads-from", "1e5", "--loads-to", "1e3"], "--loads-to"),
        (["frobnicate"], "frobnicate"),
    ],
)
def test_bad_options(argv, needle, capsys):
    assert main(argv) == 2
    out, err = capsys.readouterr()
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith("fastline: error:") and needle in lines[0]
    assert "Traceback" not in err + out


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


def test_missing_matplotlib(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert main(["paper", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "pip install fastline[plot]" in err and len(err.strip().splitlines()) == 1
    assert math.isfinite(1.0)
