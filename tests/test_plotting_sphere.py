"""fastline.reports.plotting with point-contact results: p along a diameter, the sphere's
references."""

import numpy as np
import pytest

import fastline as fl
from fastline.reports import paper, plotting

pytest.importorskip("matplotlib")

ALPHAS = (0.01, 1.0, 100.0)


@pytest.fixture(scope="module")
def sweep():
    psd = paper.surfaces()[0]
    loads = paper.sphere_load_for_alpha(np.array(ALPHAS), psd.h_rms)
    return fl.PointContact(psd, paper.E_STAR, paper.RADIUS, n=64, warn=False).sweep(loads)


def texts(fig):
    out = [t.get_text() for ax in fig.axes for t in ax.texts]
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend()] + fig.legends
    return out + [t.get_text() for legend in legends for t in legend.get_texts()]


def test_profile_along_a_diameter(sweep):
    r = sweep[1]
    fig = plotting.plot_profile(r)
    ax = fig.axes[0]
    assert "diameter" in ax.get_xlabel() and "(mm)" in ax.get_xlabel()
    rough, hertz = ax.get_lines()[:2]
    x = rough.get_xdata()
    assert np.allclose(x, -x[::-1]) and rough.get_ydata().max() == pytest.approx(r.p0 / 1e6)
    hz = fl.hertz_point_contact(r.E_star, r.radius, r.load)
    assert hertz.get_ydata().max() == pytest.approx(hz.p0 / 1e6, rel=1e-3)


def test_sphere_references(sweep):
    gu = fl.PerssonTheory(paper.surfaces()[0], paper.E_STAR).exponential_fit().gamma_u
    fig = plotting.plot_sweep(sweep, gamma_u=gu, x="alpha")
    ax_ws, ax_p0 = fig.axes
    assert fl.WS_HERTZ_SPHERE in [line.get_ydata()[0] for line in ax_ws.get_lines()]
    assert ax_ws.get_ylim()[1] > fl.WS_HERTZ_SPHERE
    assert ax_p0.get_yscale() == "log"
    assert ax_p0.get_ylim()[0] < min(r.p0_ratio for r in sweep)
    text = " ".join(texts(fig))
    assert r"\sqrt{15}" in text and r"1/(3\gamma_u\alpha)" in text and "eq. 14" not in text
    dashed = [ln for ln in ax_p0.get_lines() if ln.get_linestyle() == "--"][0]
    a, y = dashed.get_xdata(), dashed.get_ydata()
    assert np.allclose(y, 1.0 / (3.0 * gu * a))
