"""The command line with --geometry sphere: profile, sweep and the sphere versions of Figs. 3-5.

Run in-process through fastline.cli.app.main, on small settings; the numbers are held against the
API's, the units against what a sphere's load is (N, never N/m).
"""

import numpy as np
import pytest

import fastline as fl
import fastline.contact.point
from fastline.cli.app import main
from fastline.io import read_csv
from fastline.reports import paper

pytest.importorskip("matplotlib")

SAME = 1e-12  # the CSVs hold repr() of the API's numbers
N_SMALL = 64
PNG = b"\x89PNG\r\n\x1a\n"


def run(argv, capsys):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def test_profile_sphere_vs_api_and_units(tmp_path, capsys):
    csv, png = tmp_path / "p.csv", tmp_path / "p.png"
    argv = ["profile", "--geometry", "sphere", "--load", 500, "--E1", 2.1e11, "--nu1", 0.3]
    argv += ["--E2", 7e10, "--nu2", 0.33, "--radius", 0.02, "--h-rms", 5e-6, "--q0", 1e4]
    argv += ["--qr", 1e5, "--q1", 1e8, "--n", N_SMALL, "--csv", csv, "--plot", png]
    status, out, err = run(argv, capsys)
    assert status == 0, err
    E = fl.effective_modulus(2.1e11, 0.3, 7e10, 0.33)
    psd = fl.SelfAffinePSD(5e-6, 0.8, 1e4, 1e5, 1e8)
    r = fl.solve_point_contact(psd, E, 0.02, 500.0, n=N_SMALL, warn=False)
    assert "load F           500 N (total load on the sphere)" in out
    assert "N/m" not in out + err
    assert f"{r.p0:.6g} Pa" in out and f"{r.w_over_s:.6g}" in out
    assert "Hertz sphere 3.873" in out and "operator applications" in out
    meta, cols = read_csv(csv)
    assert meta["geometry"] == "sphere" and meta["n"] == str(N_SMALL)
    assert float(meta["load_N"]) == 500.0
    assert float(meta["load_radius_99_m"]) == pytest.approx(r.load_radius(0.99), rel=SAME)
    np.testing.assert_allclose(cols["r_m"], r.r, rtol=SAME)
    np.testing.assert_allclose(cols["p_Pa"], r.pressure, rtol=SAME)
    assert png.read_bytes()[:8] == PNG


def test_profile_sphere_defaults(capsys):
    status, out, _ = run(["profile", "--geometry", "sphere"], capsys)
    assert status == 0
    assert "load F           10 N" in out and "n = 512 cells" in out


def test_cylinder_defaults_unchanged(tmp_path, capsys):
    status, out, _ = run(["profile", "--csv", tmp_path / "c.csv"], capsys)
    assert status == 0 and "load f_N         10000 N/m" in out
    meta, cols = read_csv(tmp_path / "c.csv")
    assert meta["n"] == "1024" and "x_m" in cols


def test_sweep_sphere_vs_api(tmp_path, capsys):
    csv = tmp_path / "s.csv"
    argv = ["sweep", "--geometry", "sphere", "--loads-from", 1, "--loads-to", 100]
    argv += ["--loads-num", 3, "--n", N_SMALL, "--csv", csv]
    status, out, err = run(argv, capsys)
    assert status == 0, err
    assert "load F [N]" in out and "N/m" not in out + err
    assert "model            persson" in out
    meta, cols = read_csv(csv)
    assert meta["geometry"] == "sphere"
    np.testing.assert_allclose(cols["load_N"], [1.0, 10.0, 100.0], rtol=SAME)
    psd = fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)
    r = fl.solve_point_contact(psd, 1.33e9, 0.01, 10.0, n=N_SMALL, warn=False)
    assert cols["w_over_s"][1] == pytest.approx(r.w_over_s, rel=1e-7)  # continuation vs cold


def test_paper_sphere(tmp_path, capsys):
    status, out, err = run(
        ["paper", "--geometry", "sphere", "--out", tmp_path, "--loads", 3, "--n", N_SMALL], capsys
    )
    assert status == 0, err
    for name in ("fig3_profile_sphere", "fig4_ws_sphere", "fig5_p0ratio_sphere"):
        assert (tmp_path / f"{name}.png").read_bytes()[:8] == PNG
    meta, cols = read_csv(tmp_path / "fig4_ws_sphere.csv")
    assert meta["geometry"] == "sphere" and len(cols["load_N"]) == 9
    lo, hi = paper.SPHERE_ALPHA_RANGE
    np.testing.assert_allclose(cols["alpha"], np.tile([lo, 1.0, hi], 3), rtol=1e-9)
    np.testing.assert_allclose(
        cols["p0_ratio_gaussian"], 1.0 / (3.0 * cols["gamma_u"] * cols["alpha"]), rtol=SAME
    )
    assert np.all(cols["converged"] == 1)
    assert "alpha 0.001..1000" in out and "N/m" not in out + err


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["profile", "--geometry", "ball"], "--geometry"),
        (["profile", "--geometry", "sphere", "--load", "-5"], "must be > 0"),
        (["profile", "--geometry", "sphere", "--n", "5000"], "dense"),
        (["profile", "--geometry", "sphere", "--load", "1e30"], "N ([1e-18, 1e+06] E* R^2)"),
        (["sweep", "--geometry", "sphere", "--loads-from", "10", "--loads-to", "1"], "--loads-to"),
        (
            ["leak", "--geometry", "sphere", "--pressure-drop", "1", "--viscosity", "1"],
            "--geometry",
        ),
    ],
)
def test_bad_sphere_options(argv, needle, capsys):
    status, out, err = run(argv, capsys)
    assert status == 2
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("fastline: error:") and needle in lines[0]


def test_sphere_output_paths_checked_before_solving(monkeypatch, capsys):
    def no_solve(*args, **kwargs):
        raise AssertionError("solved before checking the output path")

    monkeypatch.setattr(fl, "solve_point_contact", no_solve)  # the name the CLI calls
    monkeypatch.setattr(fastline.contact.point, "solve_point_contact", no_solve)
    status, _, err = run(["profile", "--geometry", "sphere", "--csv", "/nonexistent/p.csv"], capsys)
    assert status == 2 and "/nonexistent" in err


@pytest.mark.parametrize("sub", ["profile", "sweep", "paper"])
def test_help_names_both_units(sub, capsys):
    with pytest.raises(SystemExit):
        main([sub, "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "--geometry" in out and "sphere" in out
    if sub != "paper":
        assert "[N/m]" in out and "[N]" in out
