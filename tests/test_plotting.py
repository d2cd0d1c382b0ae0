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
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend()] + fig.legends
    return [t.get_text() for ax in fig.axes for t in ax.texts] + [
        t.get_text() for legend in legends for t in legend.get_texts()
    ]


def test_plot_sweep_axes(sweep):
    gu = fl.PerssonTheory(paper.surfaces()[0], paper.E_STAR).exponential_fit().gamma_u
    fig = plotting.plot_sweep(sweep, gamma_u=gu)
    ax_ws, ax_p0 = [ax for ax in fig.axes if ax.get_ylabel()]
    for ax in (ax_ws, ax_p0):  # the load below, alpha on a secondary axis on top
        assert ax.get_xscale() == "log" and "load" in ax.get_xlabel() and "(N/m)" in ax.get_xlabel()
        (top,) = ax.child_axes
        assert r"\alpha" in top.get_xlabel()
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
    """The legend above the axes (never over the data), the axes the figure's full width (a
    legend on the right left ~35 % of the canvas empty)."""
    fig = plotting.plot_w_over_s({"a": sweep, "b": sweep[:2]})
    (ax,) = fig.axes
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["a", "b"]
    assert ax.get_legend().get_bbox_to_anchor().y0 >= ax.get_window_extent().y1 - 1
    assert ax.get_position().x1 >= 0.95 and ax.get_position().x0 <= 0.15


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
    # an explicit format for a file without an extension; an extension that names another
    # format is refused (a .jpg holding PNG bytes)
    path = plotting.save_figure(fig, tmp_path / "g", format=fmt)
    assert open(path, "rb").read(len(magic)) == magic
    with pytest.raises(ValueError, match=r"g\.dat: figures are written as png, pdf, svg"):
        plotting.save_figure(fig, tmp_path / "g.dat", format=fmt)


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


# ---- figures for design -------------------------------------------------------------------------
def _overlaps(boxes) -> bool:
    return any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])


def _drawn(fig):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    return fig.canvas.get_renderer()


def test_alpha_axis_is_the_closed_form(sweep):
    """The secondary axis maps the load to alpha = h_rms / delta, delta = 4 f_N / (pi E*):
    alpha ~ 1 / f_N exactly for a cylinder."""
    from fastline.reports.contact_figures import _alpha_law

    c, k = _alpha_law(sweep)
    assert k == pytest.approx(-1.0, abs=1e-9)
    h = paper.surfaces()[0].h_rms
    assert c == pytest.approx(h * np.pi * paper.E_STAR / 4.0, rel=1e-8)


def test_eq14_listed_only_where_it_is_drawn(sweep):
    """Near Hertz (alpha <= 0.1), eq. 14 exceeds the axes everywhere: neither drawn nor in the
    legend; the data series always has its entry."""
    gu = fl.PerssonTheory(paper.surfaces()[0], paper.E_STAR).exponential_fit().gamma_u
    near_hertz = [r for r in sweep if r.alpha < 0.1]
    text = all_text(plotting.plot_sweep(near_hertz, gamma_u=gu))
    assert "eq. 14" not in " ".join(text) and "rough (persson)" in text
    fig = plotting.plot_p0_ratio(sweep, gamma_u=gu)
    (ax,) = fig.axes
    lo, hi = ax.get_ylim()
    for line in ax.get_lines():
        y = np.asarray(line.get_ydata(), dtype=float)
        assert np.all((y >= lo) & (y <= hi)), line.get_label()  # nothing off the axes


def test_coinciding_series_all_show(sweep):
    """Three series on the same points: each its own open marker, later markers larger, so
    that none hides another (surface 1 vanished under surface 2's)."""
    fig = plotting.plot_w_over_s({"1": sweep, "2": sweep, "3": sweep})
    lines = [ln for ln in fig.axes[0].get_lines() if ln.get_label() in ("1", "2", "3")]
    assert len({ln.get_marker() for ln in lines}) == 3
    assert all(ln.get_markerfacecolor() == "none" for ln in lines)
    sizes = [ln.get_markersize() for ln in lines]
    assert sizes == sorted(sizes) and len(set(sizes)) == 3


def test_profile_shows_load_and_alpha_without_tick_collisions():
    """An O-ring's narrow contact (|x| < 0.7 mm): x tick labels apart; the legend names the
    load and alpha; result.plot() draws the same figure."""
    psd = fl.SelfAffinePSD(1e-6, 0.8, 1e4, 1e4, 1e9)
    r = fl.solve_line_contact(psd, 5e6, 2e-3, 500.0, n=128, warn=False)
    fig = r.plot()
    renderer = _drawn(fig)
    (ax,) = fig.axes
    boxes = [t.get_window_extent(renderer) for t in ax.get_xticklabels() if t.get_text()]
    assert len(boxes) >= 3 and not _overlaps(boxes)
    title = ax.get_legend().get_title().get_text()
    assert "500 N/m" in title and f"{r.alpha:.3g}" in title
    same = plotting.plot_profile(r).axes[0].get_lines()
    for a, b in zip(ax.get_lines(), same, strict=True):
        assert np.array_equal(a.get_ydata(), b.get_ydata())


def test_notebook_views(sweep):
    html = sweep[0]._repr_html_()
    assert html.startswith("<table") and "converged" in html and "N/m" in html
    assert "LineContactResult(" in repr(sweep[0])
    base = dict(h_rms=1e-6, hurst=0.8, q0=1e3, qr=1e4, q1=1e9, E_star=paper.E_STAR, n=64)
    scenes = [{**base, "radius": paper.RADIUS, "load": f, "label": "a, b"} for f in (1e3, 1e4)]
    table = fl.sweep(scenes, "serial", progress=False, warn=False)
    html = table._repr_html_()
    assert "<table>" in html and html.count("<tr>") == 3 and "a, b" in html
