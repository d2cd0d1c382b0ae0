"""Tests of fastline.contact.diagnostics.assess (regimes, warnings, exponential-law range)."""

import math
import warnings

import numpy as np
import pytest

import fastline as fl
import fastline.contact.diagnostics as _diagnostics
from fastline.contact.diagnostics import ValidityWarning, assess, regime
from fastline.contact.line import solve_line_contact

E_STAR = 1.33e9  # Pa
H_RMS = 1e-6  # m


@pytest.fixture(scope="module")
def psd():
    return fl.SelfAffinePSD(H_RMS, 0.8, 1e3, 1e4, 1e9)


@pytest.fixture(scope="module")
def theory(psd):
    return fl.PerssonTheory(psd, E_STAR)


def load_for(alpha, h_rms=H_RMS):
    """f_N [N/m] giving alpha = h_rms / delta with delta = 4 f_N / (pi E*)."""
    return fl.paper.load_for_alpha(alpha, h_rms, E_STAR)


def solve(psd, theory, alpha, radius=1.0, **kw):
    return solve_line_contact(psd, E_STAR, radius, load_for(alpha), theory=theory, n=256, **kw)


def test_regime_thresholds():
    assert regime(0.009) == "Hertz-like"
    assert regime(0.01) == regime(10.0) == "transition"
    assert regime(10.1) == "Gaussian-like"


@pytest.mark.parametrize(
    "alpha, expected", [(1e-3, "Hertz-like"), (1.0, "transition"), (100.0, "Gaussian-like")]
)
def test_regimes_from_solves(psd, theory, alpha, expected):
    # a big radius keeps the contact narrow compared with R and wider than the longest
    # roughness wavelength 2 pi/q0 = 6.3 mm: no warning expected
    r = solve(psd, theory, alpha, radius=100.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = assess(r, theory)
    assert d["regime"] == expected
    assert d["alpha"] == pytest.approx(alpha, rel=1e-12)
    assert d["half_space_ok"] and d["mean_field_ok"] and d["resolution_ok"]
    assert d["warnings"] == [] and d["warning_causes"] == []
    assert d["plastic_likely"] is None
    assert d["asperity_pressure"] == pytest.approx(0.5 * psd.rms_slope * E_STAR, rel=1e-12)
    assert 0.0 < d["real_area_at_peak"] < 1.0
    assert d["real_area_at_peak"] == pytest.approx(float(theory.contact_area([r.p0])[0]))
    assert "exponential_valid" not in d  # only for the exponential model


def test_real_area_grows_with_load(psd, theory):
    a = [
        assess(solve(psd, theory, al, radius=10.0), theory)["real_area_at_peak"]
        for al in (10.0, 1.0, 0.1)
    ]
    assert a[0] < a[1] < a[2]


def test_hardness_warning(psd, theory):
    r = solve(psd, theory, 1.0)
    p_asp = 0.5 * psd.rms_slope * E_STAR
    with pytest.warns(ValidityWarning, match="hardness"):
        d = assess(r, theory, hardness=0.5 * p_asp)
    assert d["plastic_likely"] is True
    d = assess(r, theory, hardness=2.0 * p_asp, warn=False)
    assert d["plastic_likely"] is False and "plastic" not in d["warning_causes"]
    with pytest.raises(ValueError):
        assess(r, theory, hardness=-1.0)


def test_half_width_warning_for_big_load(psd, theory):
    # Hertz half-width a = sqrt(R delta); R = 1 cm and f_N = 1e7 N/m give a ~ 0.98 R
    r = solve_line_contact(psd, E_STAR, 0.01, 1e7, theory=theory, n=256, warn=False)
    with pytest.warns(ValidityWarning, match="half-space"):
        d = assess(r, theory)
    assert not d["half_space_ok"]
    assert d["half_width_over_radius"] > 0.1
    assert issubclass(ValidityWarning, UserWarning)


def test_exponential_range_flag(psd, theory):
    ok = assess(solve(psd, theory, 10.0, model="exponential"), theory)
    assert ok["exponential_valid"] is True
    assert ok["exponential_max_error"] <= 0.05
    lo, hi = ok["pressure_range_met"]
    assert lo < hi <= ok["exponential_valid_range"][1]
    # near full contact (alpha = 1e-3, peak pressure ~ E*/2) the law is far off
    r = solve(psd, theory, 1e-3, radius=10.0, model="exponential")
    bad = assess(r, theory)
    assert bad["exponential_valid"] is False
    assert bad["pressure_range_met"][1] > bad["exponential_valid_range"][1]


def test_without_theory_and_from_psd(psd, theory):
    r = solve(psd, theory, 1.0)
    d = assess(r)
    assert d["rms_slope"] is None and d["regime"] == "transition"
    d2 = assess(r, psd=psd)
    assert d2["real_area_at_peak"] == pytest.approx(
        assess(r, theory)["real_area_at_peak"], rel=1e-9
    )
    h = solve_line_contact(None, E_STAR, 10.0, load_for(1.0), model="hertz", n=256)
    assert assess(h)["regime"] == "Hertz-like"  # alpha = 0 for smooth surfaces


# ----------------------------------------------------------------------------------------------
# warnings for scenes a random campaign found, once per cause
# ----------------------------------------------------------------------------------------------
#: the needle-shaped scene (docs/accuracy.md): (psd args, E* [Pa], R [m], f_N [N/m])
NEEDLE = (
    (4.0219591928945736e-08, 1.0, 232.4997741925926, 232.4997741925926, 71888266.82459533),
    402830.3189795967,
    0.002352259458219232,
    0.00015701517536695204,
)
#: an O-ring-like scene: rubber (5 MPa, nu 0.49) on steel, R = 1.75 mm, 50 N/m
ORING = dict(E_star=fl.effective_modulus(2.1e11, 0.3, 5e6, 0.49), radius=1.75e-3, load=50.0)
ORING_PSD = (1e-6, 0.8, 2e3, 2e4, 1e9)


def test_causes_are_stable_keys(psd, theory):
    assert _diagnostics.CAUSES == (
        "half_space",
        "plastic",
        "exponential_range",
        "narrow_contact",
        "truncated_domain",
        "resolution",
    )
    r = solve_line_contact(psd, E_STAR, 0.01, 1.5e6, theory=theory, n=256, warn=False)
    d = assess(r, theory, hardness=1e7, warn=False)  # h'E*/2 ~ 1e8 Pa
    assert d["warning_causes"] == ["half_space", "plastic"]
    assert list(d["warning_messages"]) == d["warning_causes"]
    assert d["warnings"] == [d["warning_messages"][c] for c in d["warning_causes"]]


def test_exponential_law_out_of_range_warns():
    """O-ring with model='exponential': p0 ~ 3 beta E*, u(p) off by a factor ~40: warned."""
    psd = fl.SelfAffinePSD(*ORING_PSD)
    r = solve_line_contact(psd, **ORING, model="exponential", n=256, warn=False)
    with pytest.warns(ValidityWarning, match="model='exponential' is used outside its range"):
        d = assess(r, psd=psd)
    assert d["exponential_valid"] is False and d["exponential_max_error"] > 1.0
    assert "exponential_range" in d["warning_causes"]
    assert d["p0_over_beta_E_star"] > 1.0


def test_narrow_contact_warns():
    """O-ring: a contact ~0.26 mm wide against a 3.1 mm longest wavelength."""
    psd = fl.SelfAffinePSD(*ORING_PSD)
    r = solve_line_contact(psd, **ORING, n=256, warn=False)
    with pytest.warns(ValidityWarning, match="narrower than the longest roughness wavelength"):
        d = assess(r, psd=psd)
    assert d["longest_wavelength"] == pytest.approx(2 * math.pi / 2e3, rel=1e-12)
    assert d["contact_width"] < d["longest_wavelength"] and d["mean_field_ok"] is False
    # the same scene with the band moved to short wavelengths is fine
    short = fl.SelfAffinePSD(1e-6, 0.8, 2e5, 2e6, 1e9)
    d2 = assess(solve_line_contact(short, **ORING, n=256, warn=False), psd=short, warn=False)
    assert d2["mean_field_ok"] is True and "narrow_contact" not in d2["warning_causes"]


def test_assess_after_a_solve_warns_only_of_new_causes():
    """A solve warns of the narrow contact; assessing its result again with a hardness warns
    of the plastic asperities only, and a second assessment of nothing; each dict still lists
    every cause."""
    psd = fl.SelfAffinePSD(*ORING_PSD)
    theory = fl.PerssonTheory(psd, ORING["E_star"])
    with warnings.catch_warnings(record=True) as solve_w:
        warnings.simplefilter("always")
        r = solve_line_contact(psd, **ORING, n=256, theory=theory)
    assert ["narrower than" in str(w.message) for w in solve_w] == [True]
    hard = 0.25 * psd.rms_slope * ORING["E_star"]
    for expected in (["hardness"], []):
        with warnings.catch_warnings(record=True) as got:
            warnings.simplefilter("always")
            d = assess(r, theory, hardness=hard)
        assert [m for m in ("hardness", "narrower") if any(m in str(w.message) for w in got)] == (
            expected
        )
        assert {"narrow_contact", "plastic"} <= set(d["warning_causes"])


def test_resolution_warns_on_a_coarse_grid():
    """The needle-shaped scene at n = 256: FWHM over 2.8 cells, p0 off by ~4 %, converged."""
    psd = fl.SelfAffinePSD(*NEEDLE[0])
    coarse = solve_line_contact(psd, *NEEDLE[1:], n=256, warn=False)
    assert coarse.converged
    with pytest.warns(ValidityWarning, match="grid cells"):
        d = assess(coarse, psd=psd)
    assert d["fwhm_cells"] < _diagnostics.RESOLUTION_CELLS and not d["resolution_ok"]
    fine = solve_line_contact(psd, *NEEDLE[1:], n=2048, warn=False)
    assert fine.diagnostics["resolution_ok"]
    assert d["fwhm_cells"] == pytest.approx(coarse.fwhm / coarse.dx, rel=1e-12)


@pytest.mark.parametrize("geometry", ["cylinder", "sphere"])
def test_a_domain_that_cuts_the_contact_warns(psd, theory, geometry):
    """A domain given as the Hertz half-width at alpha = 1: the pressure at its edge is ~0.8
    p0, p0 is 30 % (cylinder) or 300 % (sphere) off, the FWHM is NaN, yet the solve
    converges; the default domain's edge pressure is below 1e-14."""
    if geometry == "cylinder":
        model = fl.LineContact(psd, E_STAR, 0.01, n=128, theory=theory, warn=False)
        load = load_for(1.0)
        cut = {"half_width": fl.hertz_line_contact(E_STAR, 0.01, load).a}
    else:
        model = fl.PointContact(psd, E_STAR, 0.01, n=64, theory=theory, warn=False)
        load = 1.0  # N, alpha ~ 0.3
        cut = {"domain_radius": fl.hertz_point_contact(E_STAR, 0.01, load).a}
    kind = type(model)
    truncated = kind(psd, E_STAR, 0.01, n=model.n, theory=theory, warn=False, **cut).solve(load)
    assert truncated.converged and truncated.edge_pressure > 0.1
    with pytest.warns(ValidityWarning, match=f"edge of the domain.*widen {next(iter(cut))}"):
        d = assess(truncated, theory)
    assert d["warning_causes"][-1] == "truncated_domain" and not d["domain_ok"]
    assert "resolution" not in d["warning_causes"]  # a NaN FWHM is the domain's doing
    default = model.solve(load)
    assert default.edge_pressure < _diagnostics.EDGE_LIMIT * 1e-6
    assert default.diagnostics["domain_ok"]
    assert "truncated_domain" not in default.diagnostics["warning_causes"]


def test_no_numpy_runtime_warnings():
    """A campaign scene whose exponential-law check divided by zero (u = 0 at the peak)."""
    psd = fl.SelfAffinePSD(5.1164383209439226e-08, 0.8757207941263956, 796.2331572124455,
                           7153.568117496744, 19016655.890377298)  # fmt: skip
    E, R, f = 11771056.15771907, 0.0005040052439751047, 1507.3735168396597
    r = solve_line_contact(psd, E, R, f, n=256, model="exponential", warn=False)
    th = fl.PerssonTheory(psd, E)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        d = assess(r, th, warn=False)
    assert d["exponential_valid"] is False and d["exponential_max_error"] == math.inf


def test_warn_once_names_the_loads(psd, theory):
    loads = np.geomspace(1e3, 1.5e6, 6)
    rs = [solve_line_contact(psd, E_STAR, 0.01, f, theory=theory, n=128, warn=False) for f in loads]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        causes = fl.warn_once(rs)
    msgs = [str(w.message) for w in caught if issubclass(w.category, ValidityWarning)]
    assert len(msgs) == len(causes) == len(set(causes))
    half = [m for m in msgs if "half-space" in m]
    assert causes[0] == "half_space" and len(half) == 1
    n_half = sum("half_space" in r.diagnostics["warning_causes"] for r in rs)
    assert f"{n_half} of 6 solves" in half[0] and "1.5e+06" in half[0]
    summary = _diagnostics.summarise_warnings(rs)
    assert [c for c, _ in summary] == causes and [m for _, m in summary] == [
        m.removeprefix("fastline: ") for m in msgs
    ]
    assert fl.warn_once(rs[:1]) == [c for c in causes if c in rs[0].diagnostics["warning_causes"]]


def test_hardness_of_a_wrong_type(psd, theory):
    r = solve(psd, theory, 1.0)
    for bad in ("abc", [1e9], True):
        with pytest.raises(TypeError, match="hardness"):
            assess(r, theory, hardness=bad, warn=False)


def test_a_loop_of_solves_warns_once_per_cause():
    """Independent solves in a Python loop: each cause reaches the user once under Python's
    default warning filter (the emitted text is the same for every scene), while every result
    keeps its own numbers in ``warning_messages``."""
    psd = fl.SelfAffinePSD(*ORING_PSD)
    scene = {k: v for k, v in ORING.items() if k != "load"}
    loads = np.geomspace(0.5, 2.0, 6) * ORING["load"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        results = [solve_line_contact(psd, **scene, load=f, n=64) for f in loads]
    causes = [c for r in results for c in r.diagnostics["warning_causes"]]
    emitted = [str(w.message) for w in caught if issubclass(w.category, ValidityWarning)]
    assert len(causes) >= len(loads)  # narrow contact at every load
    assert len(emitted) == len(set(causes)) and len(set(emitted)) == len(emitted)
    details = {r.diagnostics["warning_messages"]["narrow_contact"] for r in results}
    assert len(details) == len(loads)  # the numbers differ from scene to scene


@pytest.mark.parametrize("model", ["line", "point"])
def test_warnings_of_a_solve_point_at_its_caller(psd, theory, model):
    """A model's ``solve`` that warns (here: stopped after one Newton step, so both a
    ConvergenceWarning and ValidityWarnings) points every warning at the line that called
    ``solve``, not inside fastline; so do :func:`assess` and ``warn_once`` called directly,
    ``sweep`` and ``solve_line_contact``."""
    if model == "line":
        contact = fl.LineContact(psd, E_STAR, 1.0, theory=theory, n=256, max_iter=1)
        load = load_for(1.0)
    else:
        contact = fl.PointContact(psd, E_STAR, 1e-2, theory=theory, n=128, max_iter=1)
        load = 1.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = contact.solve(load)
        assess(result, theory)
        _diagnostics.warn_once([result])
        contact.sweep([load, 2.0 * load])
        if model == "line":
            fl.solve_line_contact(psd, E_STAR, 1.0, load, theory=theory, n=256, max_iter=1)
    kinds = {w.category for w in caught}
    assert {fl.ConvergenceWarning, ValidityWarning} <= kinds
    assert {w.filename for w in caught} == {__file__}, [(w.filename, w.lineno) for w in caught]
