"""Tests of ``fastline leak`` (one scene and ``--sweep``) and the leak figures and files behind it.

The command's numbers against the API's (``fl.leak_rate`` on the same solve), the files it
writes (CSV header and columns, figure magic bytes), the seal designer's curve (Q non-increasing
with load, sealed loads marked), warnings once per cause, exit statuses, bad input and output
paths checked before any solve. Small settings (n = 128) on the O-ring-like scene of
docs/leakage.md: rubber (E 10 MPa, nu 0.5) on steel, h_rms 0.3 um, H 0.85, R 1.5 mm, water;
with ``--geometry sphere`` the rubber ball of its example 3 (R 10 mm) on a seat with a hole of
20 um radius: radial flow, the same checks plus the rings in series recomputed from the CSV.
"""

import dataclasses
from contextlib import redirect_stderr, redirect_stdout
from io import StringIO

import numpy as np
import pytest

import fastline as fl
import fastline.contact.line
import fastline.contact.point
from fastline.cli.app import main
from fastline.io import (
    LEAK_COLUMNS,
    LEAK_SWEEP_COLUMNS,
    POINT_LEAK_COLUMNS,
    POINT_LEAK_SWEEP_COLUMNS,
    read_csv,
)
from fastline.reports import plotting

pytest.importorskip("matplotlib")

#: the CSVs hold repr() of the API's numbers: equal to round-off of the same computation
SAME = 1e-12
#: the CSV's Q against its own columns (a sum of 128 strips recomputed from the written values)
SUM = 1e-12
N = 128
MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "svg": b"<?xml"}

E_STAR = fl.effective_modulus(10e6, 0.5, 210e9, 0.3)
PSD = fl.SelfAffinePSD(0.3e-6, 0.85, q0=5e4, qr=5e5, q1=1e9)
RADIUS, LOAD, DP, ETA, LENGTH = 1.5e-3, 300.0, 1e4, 1e-3, 0.0785
SCENE = ["--h-rms", 0.3e-6, "--hurst", 0.85, "--q0", 5e4, "--qr", 5e5, "--q1", 1e9]
SCENE += ["--E1", 10e6, "--nu1", 0.5, "--E2", 210e9, "--nu2", 0.3, "--radius", RADIUS]
FLUID = ["--pressure-drop", DP, "--viscosity", ETA, "--length", LENGTH, "--n", N]
ONE = ["leak", *SCENE, "--load", LOAD, *FLUID]
#: 30 to 6000 N/m: the seal closes near 3 kN/m (peak pressure 2.89 MPa)
SWEEP_LOADS = (30.0, 6000.0, 6)
SWEEP = ["leak", "--sweep", *SCENE, *FLUID, "--loads-from", SWEEP_LOADS[0]]
SWEEP += ["--loads-to", SWEEP_LOADS[1], "--loads-num", SWEEP_LOADS[2]]


def run(argv, capsys):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def warning_lines(err):
    return [ln for ln in err.splitlines() if ln.startswith("fastline: warning:")]


@pytest.fixture(scope="module")
def theory():
    return fl.PerssonTheory(PSD, E_STAR)


@pytest.fixture(scope="module")
def one_scene(theory):
    """The API's solve and leak rate of ``ONE``."""
    r = fl.solve_line_contact(PSD, E_STAR, RADIUS, LOAD, n=N, theory=theory, warn=False)
    return r, fl.leak_rate(r, DP, ETA, LENGTH, warn=False)


@pytest.fixture(scope="module")
def swept(theory):
    """The API's sweep (continuation, one theory) and leak rates of ``SWEEP``."""
    loads = np.geomspace(*SWEEP_LOADS)
    model = fl.LineContact(PSD, E_STAR, RADIUS, n=N, theory=theory, warn=False)
    results = model.sweep(loads)
    return loads, results, [fl.leak_rate(r, DP, ETA, LENGTH, warn=False) for r in results]


def _sweep_once(tmp_path_factory, name, argv, figure):
    """``(status, stdout, stderr, csv path, figure path)`` of one sweep run for a module-scoped
    fixture (capsys is function-scoped)."""
    out = tmp_path_factory.mktemp(name)
    csv_path, fig = out / "sweep.csv", out / f"sweep.{figure}"
    so, se = StringIO(), StringIO()
    with redirect_stdout(so), redirect_stderr(se):
        status = main([str(a) for a in argv + ["--csv", csv_path, "--plot", fig]])
    return status, so.getvalue(), se.getvalue(), csv_path, fig


@pytest.fixture(scope="module")
def sweep_run(tmp_path_factory):
    return _sweep_once(tmp_path_factory, "leak_sweep", SWEEP, "svg")


# ----------------------------------------------------------------------------------------------
# one scene
# ----------------------------------------------------------------------------------------------
def test_leak_numbers_match_api(one_scene, tmp_path, capsys):
    csv_path, png = tmp_path / "leak.csv", tmp_path / "leak.png"
    status, out, err = run(ONE + ["--csv", csv_path, "--plot", png, "--dpi", 60], capsys)
    assert status == 0
    r, leak = one_scene
    assert not leak.sealed and leak.Q > 0.0  # the scene leaks: the numbers below mean something
    assert f"leak rate Q      {leak.Q:.6g} m^3/s" in out
    assert f"conductance      {leak.conductance:.6g} m^2/(Pa s)" in out
    assert "sealed           no" in out
    assert f"{leak.share_in_fwhm:.1%} of it inside the FWHM" in out
    assert f"within {leak.resistance_width:.4g} m" in out
    assert f"peak pressure p0 {r.p0:.6g} Pa" in out  # the solve is reported as by `profile`
    assert png.read_bytes()[:8] == MAGIC["png"]
    # the half-space warning of the solve, once (half-width 14 % of R at 300 N/m)
    assert len([ln for ln in warning_lines(err) if "half-space" in ln]) == 1


def test_leak_csv_columns_and_header(one_scene, tmp_path, capsys):
    path = tmp_path / "leak.csv"
    assert run(ONE + ["--csv", path], capsys)[0] == 0
    r, leak = one_scene
    meta, cols = read_csv(path)
    assert tuple(cols) == LEAK_COLUMNS
    np.testing.assert_allclose(cols["x_m"], r.x, rtol=SAME)
    np.testing.assert_allclose(cols["p_Pa"], r.pressure, rtol=SAME)
    np.testing.assert_allclose(cols["u_c_m"], leak.u_c, rtol=SAME)
    np.testing.assert_allclose(cols["sigma_m3_per_Pa_s"], leak.sigma, rtol=SAME)
    np.testing.assert_allclose(cols["resistance_share"], leak.resistance_share, rtol=SAME)
    assert np.all(cols["sealed"] == 0)
    expected = {
        "pressure_drop_Pa": DP,
        "viscosity_Pa_s": ETA,
        "length_m": LENGTH,
        "threshold": 0.42,
        "Q_m3_per_s": leak.Q,
        "load_N_per_m": LOAD,
        "E_star_Pa": E_STAR,
        "radius_m": RADIUS,
        "h_rms_m": 0.3e-6,
        "q0_1_per_m": 5e4,
        "n": N,
    }
    for key, value in expected.items():
        assert float(meta[key]) == pytest.approx(value, rel=SAME), key
    assert meta["method"] == "critical-junction" and meta["sealed"] == "0"
    # how a strip would be judged sealed: the floor given (the default) and, per strip, no cause
    assert float(meta["gap_floor_m"]) == leak.gap_floor == 1e-9
    assert np.all(cols["sealed_by"] == "") and "sealed_by" not in meta
    # the file is self-consistent: strips in series, Q = L dP / sum(dx / sigma) (uniform grid)
    dx = np.diff(cols["x_m"]).mean()
    q_from_columns = LENGTH * DP / np.sum(dx / cols["sigma_m3_per_Pa_s"])
    assert q_from_columns == pytest.approx(float(meta["Q_m3_per_s"]), rel=SUM)
    assert cols["resistance_share"].sum() == pytest.approx(1.0, rel=SUM)


def test_leak_scales_with_inputs(one_scene, capsys):
    """Q doubles with the pressure drop and the length, halves with the viscosity (exactly)."""
    leak = one_scene[1]
    argv = ["leak", *SCENE, "--load", LOAD, "--n", N, "--pressure-drop", 2 * DP]
    status, out, _ = run(argv + ["--viscosity", 2 * ETA, "--length", 2 * LENGTH], capsys)
    assert status == 0
    assert f"leak rate Q      {2 * leak.Q:.6g} m^3/s" in out


def test_sealed_scene(theory, tmp_path, capsys):
    path = tmp_path / "sealed.csv"
    # the percolation criterion alone (no molecular floor)
    argv = ["leak", *SCENE, "--load", 6000, *FLUID, "--gap-floor", 0, "--csv", path]
    status, out, _ = run(argv, capsys)
    assert status == 0
    r = fl.solve_line_contact(PSD, E_STAR, RADIUS, 6000.0, n=N, theory=theory, warn=False)
    leak = fl.leak_rate(r, DP, ETA, LENGTH, gap_floor=0.0, warn=False)
    assert leak.sealed_by == "percolation"
    assert leak.sealed
    assert "leak rate Q      0 m^3/s (sealed)" in out
    n_sealed = int(leak.sealed_strips.sum())
    assert f"sealed           yes: {n_sealed} of {N} strips" in out
    meta, cols = read_csv(path)
    assert meta["sealed"] == "1" and float(meta["Q_m3_per_s"]) == 0.0
    np.testing.assert_array_equal(cols["sealed"] == 1, leak.sealed_strips)
    assert np.all(cols["u_c_m"][leak.sealed_strips] == 0.0)


def test_cylinder_seal_length_defaults_to_1_m(one_scene, capsys):
    argv = [a for a in ONE if a not in ("--length", LENGTH)]
    status, out, _ = run(argv, capsys)
    assert status == 0 and "seal length 1 m" in out
    leak = fl.leak_rate(one_scene[0], DP, ETA, warn=False)  # the API's default length, 1 m
    assert f"leak rate Q      {leak.Q:.6g} m^3/s" in out


def test_threshold_moves_the_result(one_scene, capsys):
    # a higher percolation threshold: the critical junction at a lower magnification, wider gap
    status, out, _ = run(ONE + ["--threshold", 0.5], capsys)
    assert status == 0
    leak = fl.leak_rate(one_scene[0], DP, ETA, LENGTH, threshold=0.5, warn=False)
    assert leak.Q > one_scene[1].Q * 1.01
    assert f"leak rate Q      {leak.Q:.6g} m^3/s" in out and "threshold 0.5" in out


def test_exponential_model(theory, capsys):
    status, out, _ = run(ONE + ["--model", "exponential"], capsys)
    assert status == 0
    r = fl.solve_line_contact(
        PSD, E_STAR, RADIUS, LOAD, n=N, theory=theory, model="exponential", warn=False
    )
    leak = fl.leak_rate(r, DP, ETA, LENGTH, theory=theory, warn=False)
    assert f"leak rate Q      {leak.Q:.6g} m^3/s" in out


def test_leak_warnings_once_per_cause(capsys):
    # a gas at a mean free path of 10 um (Knudsen >> 0.1) and a pressure drop of 0.5 MPa
    # against a 0.9 MPa peak: the two leakage warnings, each once
    argv = ["leak", *SCENE, "--load", LOAD, "--n", N, "--pressure-drop", 5e5]
    status, out, err = run(argv + ["--viscosity", 1.8e-5, "--mean-free-path", 1e-5], capsys)
    assert status == 0
    lines = warning_lines(err)
    gas = [ln for ln in lines if "mean free path" in ln]
    fluid = [ln for ln in lines if "fluid pressure drop" in ln]
    assert len(gas) == 1 and len(fluid) == 1 and "[f_N = 300 N/m]" in gas[0]
    assert len(lines) == len(set(lines))
    assert "Knudsen number" in out


def test_non_converged_solve_exits_1(tmp_path, capsys):
    path = tmp_path / "leak.csv"
    status, out, err = run(ONE + ["--max-iter", 1, "--csv", path], capsys)
    assert status == 1
    assert "converged        NO" in out and "did not converge" in err
    assert read_csv(path)[0]["converged"] == "0"  # results still written, flagged
    argv = SWEEP[:-2] + ["--loads-num", 2, "--max-iter", 1]
    status, _, err = run(argv, capsys)
    assert status == 1 and "2 of 2 solves did not converge" in err


# ----------------------------------------------------------------------------------------------
# --sweep
# ----------------------------------------------------------------------------------------------
def test_sweep_numbers_match_api(sweep_run, swept):
    status, out, _, csv_path, _ = sweep_run
    assert status == 0
    loads, results, leaks = swept
    meta, cols = read_csv(csv_path)
    assert tuple(cols) == LEAK_SWEEP_COLUMNS
    np.testing.assert_allclose(cols["load_N_per_m"], loads, rtol=SAME)
    np.testing.assert_allclose(cols["Q_m3_per_s"], [k.Q for k in leaks], rtol=SAME, atol=0.0)
    np.testing.assert_allclose(cols["p0_Pa"], [r.p0 for r in results], rtol=SAME)
    np.testing.assert_array_equal(cols["sealed"] == 1, [k.sealed for k in leaks])
    assert list(cols["sealed_by"]) == [k.sealed_by or "" for k in leaks]
    assert float(meta["gap_floor_m"]) == leaks[0].gap_floor
    assert float(meta["viscosity_Pa_s"]) == ETA and float(meta["length_m"]) == LENGTH
    assert float(meta["pressure_drop_Pa"]) == DP and meta["model"] == "persson"
    for r, k in zip(results, leaks, strict=True):
        assert f"{r.load:>12.4g}{r.alpha:>11.4g}{r.p0:>12.5g}{k.Q:>13.4e}" in out


def test_sweep_is_the_designers_curve(sweep_run):
    """Q falls with load and the seal closes within the range: some loads leak, some are
    sealed (Q = 0), all sealed ones above all leaking ones."""
    _, out, _, csv_path, _ = sweep_run
    _, cols = read_csv(csv_path)
    Q, sealed = cols["Q_m3_per_s"], cols["sealed"] == 1
    assert np.all(np.diff(Q) <= 0.0)
    assert sealed.any() and (~sealed).any()
    assert np.all(Q[sealed] == 0.0) and np.all(Q[~sealed] > 0.0)
    f = cols["load_N_per_m"]
    assert f[sealed].min() > f[~sealed].max()
    assert f"sealed from f_N = {f[sealed].min():.4g} N/m on" in out
    assert f"leaks below it: {f[~sealed].max():.4g} N/m" in out


def test_sweep_names_the_cause_of_each_sealed_load(sweep_run, swept):
    """The 'sealed by' line lists the loads each cause seals, as the CSV's sealed_by column."""
    _, out, _, csv_path, _ = sweep_run
    _, cols = read_csv(csv_path)
    loads, by = cols["load_N_per_m"], cols["sealed_by"]
    line = next(ln for ln in out.splitlines() if ln.startswith("sealed by "))
    assert set(by) - {""} and set(by) <= {"", "gap floor", "percolation"}
    for cause, text in (("gap floor", "molecular floor"), ("percolation", "percolates")):
        f = loads[by == cause]
        assert (text in line) == bool(f.size), cause
        if f.size:
            listed = line.split(text, 1)[1].split(";")[0]
            assert f"{f.size} of {loads.size} loads" in listed
            assert f"{f.min():.4g}" in listed and f"{f.max():.4g}" in listed


@pytest.mark.parametrize("run_name", ["sweep_run", "ball_sweep_run"])
def test_sweep_csv_leaves_where_the_resistance_sits_empty_when_sealed(run_name, request):
    """The printed table shows "-" for share in FWHM and 90% width at sealed loads (the
    resistance is infinite); the CSV has NaN there (it wrote 1.0 and a width), the leaking
    loads' values as printed."""
    _, out, _, csv_path, _ = request.getfixturevalue(run_name)
    _, cols = read_csv(csv_path)
    sealed = cols["sealed"] == 1
    share, width = cols["share_in_fwhm"], cols["resistance_width_m"]
    assert sealed.any() and (~sealed).any()
    assert np.all(np.isnan(share[sealed])) and np.all(np.isnan(width[sealed]))
    assert np.all((share[~sealed] > 0.0) & (share[~sealed] <= 1.0))
    assert np.all(width[~sealed] > 0.0)
    rows = [ln for ln in out.splitlines() if ln.rstrip().endswith(("yes", "NO"))]
    for line, is_sealed, s, w in zip(rows, sealed, share, width, strict=True):
        assert (f"{'-':>9}{'-':>15}" in line) if is_sealed else (f"{s:>9.3f}{w:>15.4g}" in line)


def test_sweep_figure(sweep_run):
    svg = sweep_run[4]
    assert svg.read_bytes()[:5] == MAGIC["svg"]


def test_sweep_warnings_name_the_loads(capsys):
    argv = SWEEP + ["--mean-free-path", 1e-5]
    status, _, err = run(argv, capsys)
    assert status == 0
    gas = [ln for ln in warning_lines(err) if "mean free path" in ln]
    assert len(gas) == 1 and "of 6 loads" in gas[0]
    half = [ln for ln in warning_lines(err) if "half-space" in ln]
    assert len(half) == 1 and "of 6 solves" in half[0]


# ----------------------------------------------------------------------------------------------
# bad input: one line, exit status 2, nothing solved
# ----------------------------------------------------------------------------------------------
REQUIRED = ["--pressure-drop", DP, "--viscosity", ETA]


@pytest.mark.parametrize(
    "extra, needle",
    [
        (["--viscosity", 0], "--viscosity"),
        (["--viscosity", -1e-3], "must be > 0"),
        (["--pressure-drop", 0], "--pressure-drop"),
        (["--pressure-drop", "-1e4"], "must be > 0"),
        (["--length", 0], "--length"),
        (["--length", -1], "must be > 0"),
        (["--threshold", 0], "(0, 1)"),
        (["--threshold", 1], "(0, 1)"),
        (["--threshold", 1.5], "--threshold"),
        (["--threshold", -0.2], "--threshold"),
        (["--mean-free-path", 0], "--mean-free-path"),
        (["--model", "hertz"], "smooth surfaces"),
        (["--sweep", "--load", 100], "--load"),
        (["--loads-num", 5], "need --sweep"),
        (["--sweep", "--loads-from", 1e4, "--loads-to", 1e3], "--loads-to"),
        (["--viscosity", "water"], "--viscosity"),
    ],
)
def test_bad_options(extra, needle, monkeypatch, capsys):
    def no_solve(*args, **kwargs):
        raise AssertionError("solved before checking the input")

    monkeypatch.setattr(fl, "solve_line_contact", no_solve)  # the name the CLI calls
    monkeypatch.setattr(fastline.contact.line, "solve_line_contact", no_solve)
    monkeypatch.setattr(fastline.contact.line.LineContact, "sweep", no_solve)
    status, out, err = run(["leak", *REQUIRED, "--n", N, *extra], capsys)
    assert status == 2
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith("fastline: error:") and needle in lines[0]
    assert "Traceback" not in err + out and out == ""


@pytest.mark.parametrize("missing", ["--pressure-drop", "--viscosity"])
def test_fluid_is_required(missing, capsys):
    argv = ["leak", *REQUIRED]
    k = argv.index(missing)
    del argv[k : k + 2]
    status, _, err = run(argv, capsys)
    assert status == 2 and "required" in err and missing in err


@pytest.mark.parametrize(
    "argv",
    [
        ["leak", *REQUIRED, "--csv", "/nonexistent-dir/leak.csv"],
        ["leak", *REQUIRED, "--plot", "/nonexistent-dir/leak.png"],
        ["leak", "--sweep", *REQUIRED, "--csv", "/nonexistent-dir/sweep.csv"],
        ["leak", "--sweep", *REQUIRED, "--plot", "/nonexistent-dir/sweep.png"],
    ],
)
def test_output_paths_checked_before_solving(argv, monkeypatch, capsys):
    def no_solve(*args, **kwargs):
        raise AssertionError("solved before checking the output path")

    monkeypatch.setattr(fl, "solve_line_contact", no_solve)  # the name the CLI calls
    monkeypatch.setattr(fastline.contact.line, "solve_line_contact", no_solve)
    monkeypatch.setattr(fastline.contact.line.LineContact, "sweep", no_solve)
    status, _, err = run(argv, capsys)
    assert status == 2 and err.startswith("fastline: error:") and "nonexistent-dir" in err


def test_help_gives_units(capsys):
    with pytest.raises(SystemExit) as e:
        main(["leak", "--help"])
    assert e.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    for text in (
        "--pressure-drop PA",
        "dP [Pa]",
        "eta [Pa s]",
        "seal length L_y across the flow [m]",
        "[-], in (0, 1)",
        "mean free path of a gas [m]",
        "smallest load per unit length [N/m]",
        "u_c [m]",
    ):
        assert text in out, text
    for opt in ("--gamma", "--format", "--dpi", "--hardness", "--max-iter", "--n", "--psd"):
        assert opt in out, opt


# ----------------------------------------------------------------------------------------------
# the figures and files from Python
# ----------------------------------------------------------------------------------------------
def test_plot_leak_panels(one_scene):
    leak = one_scene[1]
    fig = plotting.plot_leak(leak)
    top, bottom = fig.axes
    assert top.get_shared_x_axes().joined(top, bottom)
    assert "(MPa)" in top.get_ylabel() and "$u_c$ (m)" in bottom.get_ylabel()
    assert bottom.get_yscale() == "log" and "(mm)" in bottom.get_xlabel()
    assert top.get_title() == bottom.get_title() == ""
    # the shaded band is the central 90 % of the resistance and its label gives its width
    labels = [t.get_text() for t in top.get_legend().get_texts()]
    assert any(f"({leak.resistance_width * 1e6:.3g} µm wide)" in t for t in labels)
    # legend above the panels, off the data
    assert top.get_legend().get_window_extent().y0 >= top.get_window_extent().y1 - 1
    # the strip of highest resistance is inside the x range shown
    x_min_gap = leak.x[np.argmax(leak.resistance_share)] * 1e3
    lo, hi = bottom.get_xlim()
    assert lo < x_min_gap < hi


def test_plot_leak_sealed_leaves_a_gap(theory):
    r = fl.solve_line_contact(PSD, E_STAR, RADIUS, 6000.0, n=N, theory=theory, warn=False)
    leak = fl.leak_rate(r, DP, ETA, LENGTH, gap_floor=0.0, warn=False)
    fig = plotting.plot_leak(leak)
    (line,) = fig.axes[1].get_lines()[:1]
    y = np.asarray(line.get_ydata(), dtype=float)
    assert np.all(np.isnan(y[leak.sealed_strips]))  # no segment drawn across u_c = 0
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(t.startswith("sealed") for t in labels)
    # the resistance of a sealed contact is infinite: no share of it is stated
    assert not any("resistance inside" in t for t in labels)


def test_plot_leak_sweep_marks_sealed_loads(swept):
    loads, _, leaks = swept
    fig = plotting.plot_leak_sweep(loads, leaks)
    (ax,) = fig.axes
    assert ax.get_xscale() == ax.get_yscale() == "log"
    assert "(N/m)" in ax.get_xlabel() and "(m$^3$/s)" in ax.get_ylabel()
    sealed = np.array([k.sealed for k in leaks])
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    marks = lines["sealed ($Q$ = 0)"]
    np.testing.assert_allclose(marks.get_xdata(), loads[sealed])
    np.testing.assert_array_equal(marks.get_ydata(), 0.0)  # axes fraction: the bottom
    curve = [ln for ln in ax.get_lines() if ln is not marks][0]
    np.testing.assert_allclose(curve.get_ydata(), [k.Q for k in leaks if not k.sealed])
    lo, hi = ax.get_ylim()
    assert lo < min(k.Q for k in leaks if not k.sealed) and hi > max(k.Q for k in leaks)


def test_plot_leak_sweep_circles_unconverged(swept):
    loads, _, leaks = swept
    k_open = next(i for i, k in enumerate(leaks) if not k.sealed)
    k_sealed = next(i for i, k in enumerate(leaks) if k.sealed)
    marked = list(leaks)
    for i in (k_open, k_sealed):
        marked[i] = dataclasses.replace(leaks[i], converged=False)
    (ax,) = plotting.plot_leak_sweep(loads, marked).axes
    circles = [ln for ln in ax.get_lines() if ln.get_marker() == "o" and ln.get_mec() == "r"]
    x = sorted(float(v) for ln in circles for v in ln.get_xdata())
    np.testing.assert_allclose(x, sorted([loads[k_open], loads[k_sealed]]))
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels.count("not converged") == 1


def test_plot_leak_sweep_edge_cases(swept):
    loads, _, leaks = swept
    sealed = [k for k in leaks if k.sealed]
    f_sealed = loads[[k.sealed for k in leaks]]
    plotting.plot_leak_sweep(f_sealed, sealed)  # nothing leaks: no curve, no error
    plotting.plot_leak_sweep(loads[:1], leaks[:1], label="0.1 bar")  # one load
    with pytest.raises(ValueError, match="same length"):
        plotting.plot_leak_sweep(loads[:2], leaks)
    with pytest.raises(ValueError, match="non-empty"):
        plotting.plot_leak_sweep([], [])


def test_write_leak_sweep_csv_bad_input(tmp_path):
    with pytest.raises(ValueError, match="at least one"):
        fl.io.write_leak_sweep_csv(tmp_path / "x.csv", [], [])


# ----------------------------------------------------------------------------------------------
# --geometry sphere: a ball on a flat seat with a hole, radial flow (docs/leakage.md, example 3)
# ----------------------------------------------------------------------------------------------
#: the ball of example 3: rubber on steel as above, R = 10 mm, 0.2 N, a hole of 20 um radius
BALL, BALL_LOAD, HOLE = 10e-3, 0.2, 20e-6
BALL_SCENE = ["leak", "--geometry", "sphere", *SCENE[:-2], "--radius", BALL, "--n", N]
BALL_FLUID = ["--pressure-drop", DP, "--viscosity", ETA]
BALL_ONE = [*BALL_SCENE, "--load", BALL_LOAD, "--inner-radius", HOLE, *BALL_FLUID]
#: 0.1 to 200 N: leaks at the small loads, sealed from about 90 N (p0 about 3.1 MPa)
BALL_LOADS = (0.1, 200.0, 6)
BALL_SWEEP = [*BALL_SCENE, "--sweep", "--inner-radius", HOLE, *BALL_FLUID]
BALL_SWEEP += ["--loads-from", BALL_LOADS[0], "--loads-to", BALL_LOADS[1]]
BALL_SWEEP += ["--loads-num", BALL_LOADS[2]]


@pytest.fixture(scope="module")
def ball(theory):
    """The API's solve of the ball and its radial leak rate (``BALL_ONE``)."""
    r = fl.solve_point_contact(PSD, E_STAR, BALL, BALL_LOAD, n=N, theory=theory, warn=False)
    return r, fl.leak_rate(r, DP, ETA, inner_radius=HOLE, warn=False)


@pytest.fixture(scope="module")
def ball_swept(theory):
    loads = np.geomspace(*BALL_LOADS)
    model = fl.PointContact(PSD, E_STAR, BALL, n=N, theory=theory, warn=False)
    results = model.sweep(loads)
    leaks = [fl.leak_rate(r, DP, ETA, inner_radius=HOLE, warn=False) for r in results]
    return loads, results, leaks


@pytest.fixture(scope="module")
def ball_sweep_run(tmp_path_factory):
    return _sweep_once(tmp_path_factory, "ball_sweep", BALL_SWEEP, "png")


def test_sphere_leak_matches_api(ball, tmp_path, capsys):
    csv_path, png = tmp_path / "ball.csv", tmp_path / "ball.png"
    status, out, _ = run(BALL_ONE + ["--csv", csv_path, "--plot", png, "--dpi", 60], capsys)
    assert status == 0
    r, leak = ball
    assert not leak.sealed and leak.Q > 0.0
    meta, cols = read_csv(csv_path)
    assert float(meta["Q_m3_per_s"]) == pytest.approx(leak.Q, rel=SAME)
    assert float(meta["conductance_m3_per_Pa_s"]) == pytest.approx(leak.conductance, rel=SAME)
    assert f"leak rate Q      {leak.Q:.6g} m^3/s" in out
    assert f"conductance      {leak.conductance:.6g} m^3/(Pa s) of the whole contact" in out
    assert f"orifice share    {leak.diagnostics['orifice_share']:.3g}" in out
    assert "radial flow from r = inner radius 2e-05 m outwards" in out
    assert "seal length" not in out  # radial flow has none
    assert f"load F           {BALL_LOAD:.6g} N" in out  # the sphere's result lines
    assert f"peak pressure p0 {r.p0:.6g} Pa" in out
    assert png.read_bytes()[:8] == MAGIC["png"]


def test_sphere_csv_is_radial_and_self_consistent(ball, tmp_path, capsys):
    """The file holds the rings (r_m), the hole and the load in N; its Q is the rings in series
    recomputed from its own columns: Q = dP / sum ln(r_hi / r_lo) / (2 pi sigma) over the rings
    outside the hole (a uniform grid r_j = j dr, ring edges halfway between centres)."""
    path = tmp_path / "ball.csv"
    assert run(BALL_ONE + ["--csv", path], capsys)[0] == 0
    r, leak = ball
    meta, cols = read_csv(path)
    assert tuple(cols) == POINT_LEAK_COLUMNS
    np.testing.assert_allclose(cols["r_m"], r.r, rtol=SAME)
    np.testing.assert_allclose(cols["p_Pa"], r.pressure, rtol=SAME)
    assert float(meta["inner_radius_m"]) == HOLE and "length_m" not in meta
    assert float(meta["load_N"]) == BALL_LOAD and meta["geometry"] == "sphere"
    dr = cols["r_m"][1]
    lo = np.clip(cols["r_m"] - dr / 2, HOLE, None)
    hi = np.clip(cols["r_m"] + dr / 2, HOLE, None)
    crossed = hi > HOLE
    ln = np.log(hi[crossed] / lo[crossed])
    q_from_columns = DP / np.sum(ln / (2 * np.pi * cols["sigma_m3_per_Pa_s"][crossed]))
    assert q_from_columns == pytest.approx(float(meta["Q_m3_per_s"]), rel=SUM)
    assert np.all(cols["resistance_share"][~crossed] == 0.0)


def test_sphere_smaller_hole_leaks_less(ball, capsys):
    """A smaller hole puts more rings (those of smallest circumference, the most resistive) on
    the flow path: Q falls with the inner radius."""
    argv = [*BALL_SCENE, "--load", BALL_LOAD, *BALL_FLUID, "--inner-radius", HOLE / 4]
    status, out, _ = run(argv, capsys)
    assert status == 0
    q_small = float(out.split("leak rate Q")[1].split()[0])
    assert 0.0 < q_small < ball[1].Q


def test_sphere_sweep_matches_api(ball_sweep_run, ball_swept):
    status, out, _, csv_path, png = ball_sweep_run
    assert status == 0
    loads, results, leaks = ball_swept
    meta, cols = read_csv(csv_path)
    assert tuple(cols) == POINT_LEAK_SWEEP_COLUMNS
    np.testing.assert_allclose(cols["load_N"], loads, rtol=SAME)
    np.testing.assert_allclose(cols["Q_m3_per_s"], [k.Q for k in leaks], rtol=SAME, atol=0.0)
    np.testing.assert_allclose(cols["p0_Pa"], [r.p0 for r in results], rtol=SAME)
    assert float(meta["inner_radius_m"]) == HOLE and meta["geometry"] == "sphere"
    assert "load F [N]" in out
    assert png.read_bytes()[:8] == MAGIC["png"]


def test_sphere_sweep_squeeze_stops_the_leak(ball_sweep_run):
    """Q non-increasing in F while the ball leaks, then sealed (Q = 0) above every leaking
    load, reported in N."""
    _, out, _, csv_path, _ = ball_sweep_run
    _, cols = read_csv(csv_path)
    Q, sealed, F = cols["Q_m3_per_s"], cols["sealed"] == 1, cols["load_N"]
    assert np.all(np.diff(Q[~sealed]) <= 0.0) and np.all(Q[~sealed] > 0.0)
    assert sealed.any() and (~sealed).any() and F[sealed].min() > F[~sealed].max()
    assert np.all(Q[sealed] == 0.0)
    assert f"sealed from F = {F[sealed].min():.4g} N on" in out


def test_sphere_default_load(capsys):
    from fastline.cli.common import GEOMETRY_DEFAULTS

    status, out, _ = run([*BALL_SCENE, "--inner-radius", HOLE, *BALL_FLUID], capsys)
    assert status == 0
    assert f"load F           {GEOMETRY_DEFAULTS['sphere']['load']:.6g} N" in out


def test_plot_leak_sweep_of_a_sphere_labels_F(ball_swept):
    loads, _, leaks = ball_swept
    (ax,) = plotting.plot_leak_sweep(loads, leaks).axes
    assert ax.get_xlabel() == "load $F$ (N)"


@pytest.mark.parametrize(
    "argv, needle",
    [
        ([*BALL_SCENE, *BALL_FLUID], "--inner-radius"),  # missing for a sphere
        ([*BALL_SCENE, *BALL_FLUID, "--inner-radius", HOLE, "--length", 1], "--length"),
        ([*BALL_SCENE, *BALL_FLUID, "--inner-radius", HOLE, "--model", "hertz"], "--model"),
        ([*BALL_SCENE, *BALL_FLUID, "--inner-radius", HOLE, "--sweep", "--load", 1], "--load"),
        ([*BALL_SCENE, *BALL_FLUID, "--inner-radius", 0], "--inner-radius"),
        (["leak", *REQUIRED, "--n", N, "--inner-radius", HOLE], "--inner-radius"),  # cylinder
        (
            [*BALL_SCENE, *BALL_FLUID, "--inner-radius", HOLE, "--csv", "/nonexistent/b.csv"],
            "b.csv",
        ),
    ],
)
def test_sphere_bad_options(argv, needle, monkeypatch, capsys):
    def no_solve(*args, **kwargs):
        raise AssertionError("solved before checking the input")

    for module, cls in (
        (fastline.contact.point, "PointContact"),
        (fastline.contact.line, "LineContact"),
    ):
        monkeypatch.setattr(getattr(module, cls), "solve", no_solve)
        monkeypatch.setattr(getattr(module, cls), "sweep", no_solve)
    status, out, err = run(argv, capsys)
    assert status == 2
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("fastline: error:") and needle in lines[0]
    assert "Traceback" not in err + out and out == ""


@pytest.mark.parametrize("sweep", [False, True])
def test_sphere_hole_beyond_the_profile(sweep, capsys):
    """An --inner-radius at or beyond the profile's outer edge (1 m: far outside a 10 mm ball's
    contact) is one error line naming it, not a traceback."""
    argv = [*BALL_SCENE, *BALL_FLUID, "--inner-radius", 1.0]
    argv += ["--sweep", "--loads-num", 2] if sweep else []
    status, out, err = run(argv, capsys)
    assert status == 2
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("fastline: error: --inner-radius 1 m")
    assert "outer edge" in lines[0] and ("2 of 2 loads" in lines[0]) == sweep
    assert "Traceback" not in err and out == ""


def test_sphere_help(capsys):
    with pytest.raises(SystemExit):
        main(["leak", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    for text in ("--inner-radius M", "--geometry {cylinder,sphere}", "the total load F [N]"):
        assert text in out, text
