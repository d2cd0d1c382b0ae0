"""How a seal is judged sealed, by cause: the real contact area percolates (``P(q1, p) >=
threshold``) or the gap is below the molecular floor; what ``fastline leak`` prints, the CSV
files record and ``plot_leak`` shades for each.

The causes are checked against the contact result's own real contact area ``P(q1, p)`` per strip
(``result.real_area``, independent of the leak rate's gap tables) and the gap floor applied to
the written gaps. The O-ring scene of docs/leakage.md at n = 128: at 2 kN/m only the floor
seals; at 5 kN/m the contact percolates in the centre and the floor seals strips on each side.
"""

from contextlib import redirect_stderr, redirect_stdout
from io import StringIO

import numpy as np
import pytest

import fastline as fl
from fastline.cli.app import main
from fastline.io import read_csv

pytest.importorskip("matplotlib")

N, RADIUS, DP, ETA, LENGTH, THRESHOLD = 128, 1.5e-3, 1e4, 1e-3, 0.0785, 0.42
E_STAR = fl.effective_modulus(10e6, 0.5, 210e9, 0.3)
PSD = fl.SelfAffinePSD(0.3e-6, 0.85, q0=5e4, qr=5e5, q1=1e9)
SCENE = ["--h-rms", 0.3e-6, "--hurst", 0.85, "--q0", 5e4, "--qr", 5e5, "--q1", 1e9]
SCENE += ["--E1", 10e6, "--nu1", 0.5, "--E2", 210e9, "--nu2", 0.3, "--radius", RADIUS]
FLUID = ["--pressure-drop", DP, "--viscosity", ETA, "--length", LENGTH, "--n", N]
#: loads per unit length (N/m): leaks, sealed by the floor alone, sealed by both causes
LEAKS, FLOOR, BOTH = 300.0, 2000.0, 5000.0


@pytest.fixture(scope="module")
def scenes():
    """{load: (result, leak rate)} of the three loads, from the API (default gap floor)."""
    th = fl.PerssonTheory(PSD, E_STAR)
    out = {}
    for f in (LEAKS, FLOOR, BOTH):
        r = fl.solve_line_contact(PSD, E_STAR, RADIUS, f, n=N, theory=th, warn=False)
        out[f] = (r, fl.leak_rate(r, DP, ETA, LENGTH, warn=False))
    return out


def cli(argv) -> tuple[int, str]:
    so, se = StringIO(), StringIO()
    with redirect_stdout(so), redirect_stderr(se):
        status = main([str(a) for a in argv])
    return status, so.getvalue()


def percolating(result) -> np.ndarray:
    """The strips whose real contact area reaches the threshold (the result's own P(q1, p))."""
    return np.asarray(result.real_area) >= THRESHOLD


def test_floor_strips_split_the_sealed_strips_by_cause(scenes):
    """sealed_strips = percolating strips + floor_strips, disjoint; the floor strips are those
    with a gap below the floor; the counts in the diagnostics agree."""
    for f, cause in ((FLOOR, "gap floor"), (BOTH, "percolation")):
        r, leak = scenes[f]
        perc = percolating(r)
        assert leak.sealed_by == cause
        np.testing.assert_array_equal(leak.sealed_strips & ~leak.floor_strips, perc)
        assert not np.any(leak.floor_strips & perc)
        assert np.all(leak.u_c[leak.floor_strips] < leak.gap_floor)
        assert np.all(leak.u_c[~leak.sealed_strips] >= leak.gap_floor)
        assert leak.diagnostics["n_below_floor"] == int(leak.floor_strips.sum())
    assert not percolating(scenes[FLOOR][0]).any() and scenes[FLOOR][1].floor_strips.any()
    assert percolating(scenes[BOTH][0]).any() and scenes[BOTH][1].floor_strips.any()


def test_cli_sealed_line_counts_each_cause(scenes):
    """The 'sealed' line gives the strips of each cause, counted from P(q1, p) itself, and at
    a load where no strip percolates says that no strip reaches the threshold."""
    r, leak = scenes[BOTH]
    n_perc, n_all = int(percolating(r).sum()), int(leak.sealed_strips.sum())
    status, out = cli(["leak", *SCENE, "--load", BOTH, *FLUID])
    assert status == 0
    line = next(ln for ln in out.splitlines() if ln.startswith("sealed "))
    assert f"{n_all} of {N} strips sealed: {n_perc} with a real contact area" in line
    assert f"{n_all - n_perc} more with the gap below the 1e-09 m floor" in line
    status, out = cli(["leak", *SCENE, "--load", FLOOR, *FLUID])
    line = next(ln for ln in out.splitlines() if ln.startswith("sealed "))
    assert f"{int(scenes[FLOOR][1].sealed_strips.sum())} of {N} strips have a gap below" in line
    assert "no strip reaches a real contact area P(q1, p) >= 0.42" in line
    assert "percolates at" not in line


def test_leak_csv_records_the_gap_floor_and_each_strips_cause(scenes, tmp_path):
    """The header holds the floor given; the sealed_by column names the cause per strip."""
    path = tmp_path / "leak.csv"
    status, _ = cli(["leak", *SCENE, "--load", BOTH, *FLUID, "--gap-floor", 2e-9, "--csv", path])
    assert status == 0
    meta, cols = read_csv(path)
    assert float(meta["gap_floor_m"]) == 2e-9 and meta["sealed_by"] == "percolation"
    perc = percolating(scenes[BOTH][0])
    sealed, by, u_c = cols["sealed"] == 1, cols["sealed_by"], cols["u_c_m"]
    np.testing.assert_array_equal(by == "percolation", perc)
    floor = by == "gap floor"
    np.testing.assert_array_equal(floor, sealed & ~perc)
    assert floor.any() and np.all(u_c[floor] < 2e-9)  # the sub-floor gap, as documented
    assert np.all(u_c[perc] == 0.0) and np.all(by[~sealed] == "")


def test_leak_sweep_csv_records_the_gap_floor_and_each_loads_cause(scenes, tmp_path):
    path = tmp_path / "sweep.csv"
    results, leaks = zip(*(scenes[f] for f in (LEAKS, FLOOR, BOTH)), strict=True)
    fl.io.write_leak_sweep_csv(path, results, leaks)
    meta, cols = read_csv(path)
    assert float(meta["gap_floor_m"]) == fl.leak_rate.__kwdefaults__["gap_floor"]
    assert list(cols["sealed_by"]) == ["", "gap floor", "percolation"]


def test_effective_medium_gap_is_named_u_eff(scenes):
    leak = fl.leak_rate(scenes[LEAKS][0], DP, ETA, LENGTH, method="effective-medium", warn=False)
    status, out = cli(["leak", *SCENE, "--load", LEAKS, *FLUID, "--method", "effective-medium"])
    assert status == 0
    assert f"effective gap    {leak.diagnostics['min_gap']:.6g} m (u_eff" in out
    assert "critical gap" not in out and "u_c " not in out


def _spans(ax, label_start: str) -> list[tuple[float, float]]:
    """x extents (mm) of the shaded spans whose colour is that of the legend entry."""
    entry = [h for h in ax.get_legend_handles_labels()[0] if h.get_label().startswith(label_start)]
    assert len(entry) == 1, label_start
    colour = entry[0].get_facecolor()
    spans = [p for p in ax.patches if p.get_facecolor() == colour]
    return sorted((p.get_x(), p.get_x() + p.get_width()) for p in spans)


def test_plot_leak_shades_each_cause_under_its_own_label(scenes):
    """At 5 kN/m: one span where P(q1, p) >= 0.42 (the red entry), two beside it where the
    floor seals (the other entry), each over exactly the strips of its cause."""
    r, leak = scenes[BOTH]
    bottom = fl.plotting.plot_leak(leak).axes[1]
    mid = 0.5 * (leak.x[1:] + leak.x[:-1]) * 1e3
    edges = np.concatenate([[2 * leak.x[0] * 1e3 - mid[0]], mid, [2 * leak.x[-1] * 1e3 - mid[-1]]])
    perc = np.flatnonzero(percolating(r))
    (contact,) = _spans(bottom, "sealed: $P(q_1, p)")
    np.testing.assert_allclose(contact, (edges[perc[0]], edges[perc[-1] + 1]), rtol=1e-12)
    floor = _spans(bottom, "sealed: gap below")
    assert len(floor) == 2
    left = np.flatnonzero(leak.floor_strips & (leak.x < 0.0))
    np.testing.assert_allclose(floor[0], (edges[left[0]], edges[left[-1] + 1]), rtol=1e-12)
