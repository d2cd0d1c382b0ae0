"""Array inputs: every public function that takes an array refuses bools, strings and None the
way the scalar checks do (a TypeError naming the parameter), before any work.

NumPy would read ``True`` as 1.0 and ``"1e4"`` as 1e4, so ``sweep(["1e4", True])`` used to solve
loads 1e4 and 1 N/m that ``solve("1e4")`` and ``solve(True)`` refuse.
"""

from __future__ import annotations

import numpy as np
import pytest

import fastline as fl
from fastline._lib import validate as _validate
from fastline.elastic.ring import disc_interaction
from fastline.reports import paper
from fastline.surfaces import topography
from fastline.theory import asperity

E_STAR, RADIUS = 1.33e9, 0.01
PSD = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)

#: arrays of loads/pressures with one entry that is not a real number (or all of them)
BAD = {
    "str": "1e4",
    "bytes": b"1e4",
    "bool": True,
    "list-of-str": ["1e4", "2e4"],
    "list-with-str": [1e4, "2e4"],
    "list-with-bool": [1e4, True],
    "list-with-np-bool": [1e4, np.True_],
    "list-with-None": [1e4, None],
    "nested-with-bool": [[1e4, 2e4], [3e4, False]],
    "bool-array": np.array([True, False]),
    "str-array": np.array(["1e4", "2e4"]),
    "object-array-with-str": np.array([1e4, "2e4"], dtype=object),
}


@pytest.fixture(scope="module")
def objects():
    """Models, a theory, laws and limits to call (built once: the checks come before any work)."""
    theory = fl.PerssonTheory(PSD, E_STAR)
    u = np.geomspace(1e-8, 1e-6, 5)
    return {
        "line": fl.LineContact(PSD, E_STAR, RADIUS, n=64, warn=False),
        "line-accuracy": fl.LineContact(PSD, E_STAR, RADIUS, accuracy=1e-2, warn=False),
        "point": fl.PointContact(PSD, E_STAR, RADIUS, n=32, warn=False),
        "theory": theory,
        "laws": [
            fl.PerssonLaw(theory),
            fl.ExponentialLaw.from_theory(theory),
            fl.TabulatedLaw(u, theory.pressure(u)),
            fl.GreenwoodWilliamsonLaw.from_psd(PSD, E_STAR),
        ],
        "tabulated_psd": fl.TabulatedPSD([1e3, 1e6, 1e9], [1e-20, 1e-30, 1e-40]),
        "limits": [
            fl.hertz_line_contact(E_STAR, RADIUS, 1e4),
            fl.gaussian_line_contact(1e-7, RADIUS, 1e4),
            fl.hertz_point_contact(E_STAR, RADIUS, 1.0),
            fl.gaussian_point_contact(1e-7, RADIUS, 1.0),
        ],
    }


def _law_calls(name):
    return lambda o, b: [getattr(law, name)(b) for law in o["laws"]]


#: entry point -> (call(objects, bad), the parameter its message must name)
CALLS = {
    "LineContact.sweep": (lambda o, b: o["line"].sweep(b), "loads"),
    "LineContact.sweep (accuracy)": (lambda o, b: o["line-accuracy"].sweep(b), "loads"),
    "PointContact.sweep": (lambda o, b: o["point"].sweep(b), "loads"),
    "w_over_s": (lambda o, b: fl.w_over_s(PSD, E_STAR, RADIUS, b, n=64), "load"),
    "p0_ratio": (lambda o, b: fl.p0_ratio(PSD, E_STAR, RADIUS, b, n=64), "load"),
    "PerssonTheory.separation": (lambda o, b: o["theory"].separation(b), "p"),
    "PerssonTheory.pressure": (lambda o, b: o["theory"].pressure(b), "u"),
    "PerssonTheory.separation_table": (lambda o, b: o["theory"].separation_table(b), "p"),
    "PerssonTheory.contact_area": (lambda o, b: o["theory"].contact_area(b), "p"),
    "PerssonTheory.contact_area q": (lambda o, b: o["theory"].contact_area(1e5, b), "q"),
    "PerssonTheory.apparent_area": (lambda o, b: o["theory"].apparent_area(b, 1e5), "zeta"),
    "PerssonTheory.mean_separation": (lambda o, b: o["theory"].mean_separation(1.0, b), "p"),
    "PerssonTheory.edge_separation": (lambda o, b: o["theory"].edge_separation(1.0, b), "p"),
    "PerssonTheory.critical_gap": (lambda o, b: o["theory"].critical_gap(b), "p"),
    "law.separation_and_slope": (_law_calls("separation_and_slope"), "v"),
    "law.log_pressure": (_law_calls("log_pressure"), "u"),
    "law.pressure": (_law_calls("pressure"), "u"),
    "law.real_area": (lambda o, b: [law.real_area(b) for law in o["laws"][:3]], "p"),
    "GreenwoodWilliamsonLaw.real_area": (lambda o, b: o["laws"][3].real_area(b), "p"),
    "TabulatedLaw u": (lambda o, b: fl.TabulatedLaw(b, [1e3, 1e5]), "u"),
    "TabulatedLaw p": (lambda o, b: fl.TabulatedLaw([2e-6, 1e-6], b), "p"),
    "SelfAffinePSD()": (lambda o, b: PSD(b), "q"),
    "TabulatedPSD()": (lambda o, b: o["tabulated_psd"](b), "q"),
    "PSD.cumulative": (lambda o, b: PSD.cumulative(b), "q"),
    "TabulatedPSD q": (lambda o, b: fl.TabulatedPSD(b, [1e-20, 1e-30]), "q"),
    "limits pressure": (lambda o, b: [lim.pressure(b) for lim in o["limits"]], "x"),
    "HertzPointContact.displacement": (lambda o, b: o["limits"][2].displacement(b), "r"),
    "p0_ratio_gaussian": (lambda o, b: fl.p0_ratio_gaussian(b, 0.5), "alpha"),
    "p0_ratio_gaussian_sphere": (lambda o, b: fl.p0_ratio_gaussian_sphere(b, 0.5), "alpha"),
    "leak_rate_profile x": (
        lambda o, b: fl.leak_rate_profile(b, [1e5, 1e5], o["theory"], 1e4, 1e-3),
        "x",
    ),
    "leak_rate_profile p": (
        lambda o, b: fl.leak_rate_profile([0.0, 1e-3], b, o["theory"], 1e4, 1e-3),
        "p",
    ),
    "summit_integral": (lambda o, b: asperity.summit_integral(b), "t"),
    "paper.load_for_alpha": (lambda o, b: paper.load_for_alpha(b), "alpha"),
    "paper.sphere_load_for_alpha": (lambda o, b: paper.sphere_load_for_alpha(b), "alpha"),
    "topography.isotropic_from_1d": (
        lambda o, b: topography.isotropic_from_1d(b, [1e-20, 1e-21]),
        "k",
    ),
    "topography.convert_psd": (lambda o, b: topography.convert_psd([1e-20, 1e-21], b), "q"),
    "disc_interaction": (lambda o, b: disc_interaction(b, 1.0), "a"),
}


@pytest.mark.parametrize("bad", list(BAD.values()), ids=list(BAD))
@pytest.mark.parametrize("call", list(CALLS))
def test_array_entry_points_refuse_bools_and_strings(objects, call, bad):
    fn, name = CALLS[call]
    with pytest.raises(TypeError, match=rf"^{name} must"):
        fn(objects, bad)


@pytest.mark.parametrize("bad", [True, "1e4", None])
def test_sweep_refuses_what_solve_refuses(bad):
    """The same values, the same exception type, for one load and for a list of loads."""
    lc = fl.LineContact(PSD, E_STAR, RADIUS, n=64, warn=False)
    with pytest.raises(TypeError, match="^load must be a real number"):
        lc.solve(bad)
    with pytest.raises(TypeError, match="^loads must hold real numbers"):
        lc.sweep([1e4, bad])


@pytest.mark.parametrize(
    "value",
    [
        [1e4, 2e4],
        (1e4, 2),
        np.array([1e4, 2e4], dtype=np.float32),
        np.array([1, 2], dtype=np.int64),
        np.array([1e4, 2], dtype=object),
        np.float64(3.0),
        7,
        range(1, 4),
    ],
)
def test_real_array_keeps_numbers(value):
    """What is a number stays accepted, as float64, whatever the container."""
    seq = list(value) if isinstance(value, range) else value
    out = _validate.real_array("x", seq)
    assert out.dtype == np.float64
    assert np.array_equal(out, np.asarray(seq, dtype=np.float64))


def test_sweep_takes_any_iterable_of_numbers():
    lc = fl.LineContact(PSD, E_STAR, RADIUS, n=64, warn=False)
    a = lc.sweep(f for f in (1e4, 2e4))
    b = lc.sweep(np.array([1e4, 2e4]))
    assert [r.p0 for r in a] == [r.p0 for r in b]
