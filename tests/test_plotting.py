"""Tests of fastline.reports.plotting: figures from the Python API (no pyplot, no files unless
asked)."""

import numpy as np
import pytest

import fastline as fl
from fastline.reports import paper, plotting

pytest.importorskip("matplotlib")

LOADS = (1e3, 1e4, 1e5, 1e6)  # N/m: alpha from ~10 to ~0.01 on surface 1


@pytest.fixture(scope="module")
def sweep():
    psd = paper.surfaces()[0]
    return [fl.solve_line_contact(psd, paper.E_STAR, paper.RADIUS, f, n=128) for f in LOADS]


def all_text(fig):
    return [t.get_text() for ax in fig.axes for t in ax.texts] + [
        t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()
    ]


def test_plot_sweep_axes(sweep):
    gu = fl.PerssonTheory(paper.surfaces()[0], paper.E_STAR).exponential_fit().gamma_u
    fig = plotting.plot_sweep(sweep, gamma_u=gu)
    ax_ws, ax_p0 = fig.axes
    for ax in (ax_ws, ax_p0):
        assert ax.get_xscale() == "log" and r"\alpha" in ax.get_xlabel()
        assert ax.get_title() == ""  # captions go in the documents
    assert "$w/s$" in ax_ws.get_ylabel() and r"p_{0,\mathrm{Hertz}}" in ax_p0.get_ylabel()
    # the p0 panel shows the data, not eq. 14 (which exceeds 10 at the smallest alpha here)
    top = max(r.p0_ratio for r in sweep)
    assert ax_p0.get_ylim()[1] <= 1.2 * max(top, 1.0)
    lo, hi = ax_ws.get_ylim()
    assert lo < fl.WS_GAUSSIAN and hi > fl.WS_HERTZ
    text = " ".join(all_text(fig))
    assert r"2\sqrt{3}" in text and r"2\sqrt{2\ln 2}" in text and "eq. 14" in text


def test_plot_series_mapping_and_legend_outside(sweep):
    fig = plotting.plot_w_over_s({"a": sweep, "b": sweep[:2]})
    (ax,) = fig.axes
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["a", "b"]
    assert ax.get_legend().get_bbox_to_anchor().x0 > ax.get_window_extent().x1 - 1


def test_plot_profile_and_psd(sweep):
    fig = plotting.plot_profile(sweep[1])
    ax = fig.axes[0]
    assert "(mm)" in ax.get_xlabel() and "(MPa)" in ax.get_ylabel()
    peak = max(line.get_ydata().max() for line in ax.get_lines())
    hz = fl.hertz_line_contact(paper.E_STAR, paper.RADIUS, LOADS[1])
    assert peak == pytest.approx(hz.p0 / 1e6, rel=1e-2)  # the Hertz curve, in MPa
    fig = plotting.plot_psd(paper.surfaces()[2])
    ax = fig.axes[0]
    assert ax.get_xscale() == ax.get_yscale() == "log" and "m$^4$" in ax.get_ylabel()


@pytest.mark.parametrize("fmt, magic", [("png", b"\x89PNG"), ("pdf", b"%PDF"), ("svg", b"<?xml")])
def test_save_figure_formats(sweep, tmp_path, fmt, magic):
    fig = plotting.plot_w_over_s(sweep)
    path = plotting.save_figure(fig, tmp_path / f"f.{fmt}", dpi=50)
    assert open(path, "rb").read(len(magic)) == magic
    # an explicit format wins over the extension
    path = plotting.save_figure(fig, tmp_path / "g.dat", format=fmt)
    assert open(path, "rb").read(len(magic)) == magic


def test_bad_input(sweep, tmp_path):
    with pytest.raises(ValueError, match="results"):
        plotting.plot_sweep([])
    fig = plotting.plot_w_over_s(sweep)
    with pytest.raises(ValueError, match="format"):
        plotting.save_figure(fig, tmp_path / "f.png", format="jpg")
    with pytest.raises(ValueError, match="dpi"):
        plotting.save_figure(fig, tmp_path / "f.png", dpi=-1)
    with pytest.raises(ValueError, match="does-not-exist"):
        plotting.save_figure(fig, tmp_path / "does-not-exist" / "f.png")
    assert np.isfinite(sweep[0].p0)
