"""The compiled sweep of a line contact (fastline.contact.line_sweep) against the Python loop of
fastline.contact.model.ContactModel._sweep, its reference: the same predictions, the same solutions,
the same work; repeated loads, failed predictions, progress, threads."""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest

import fastline as fl
from fastline._lib import fftw as _fftw
from fastline.contact import line_sweep as _line_sweep
from fastline.contact import model as _contact
from fastline.contact.model import ContactModel
from fastline.theory.limits import hertz_line_unchecked

# tiered tolerances
RTOL_ROUNDOFF = 1e-12  # the same arithmetic in another order (compiled vs Python predictor)
RTOL_SAME_START = 1e-9  # solutions of the same scene from starts equal to round-off, tol 1e-8
RTOL_CONTINUATION = 1e-7  # a sweep vs independent solves, tol 1e-8 in u/u0
#: the compiled and the Python sweep do the same work; a start differing at round-off may, in
#: a rare scene, take one line-search trial more or less
COUNT_SLACK = 0.02

E_STAR, RADIUS = 1.33e9, 0.01
ORDER = _contact.SWEEP_PREDICTOR_ORDER
SURFACES = fl.paper.surfaces()
#: loads from alpha 1e3 down to 1e-3 (surface 1), a 64-load sweep
LOADS = np.array([fl.paper.load_for_alpha(a) for a in np.geomspace(1e3, 1e-3, 64)])

pytestmark = pytest.mark.skipif(not _fftw.AVAILABLE, reason="the compiled path needs FFTW")


def python_sweep(model, loads):
    """The reference: the Python continuation loop (the same predictor, stage by stage)."""
    return ContactModel._sweep(model, loads, None)


@pytest.mark.parametrize("psd", SURFACES[:2], ids=["surface1", "surface2"])
def test_compiled_sweep_equals_the_python_loop(psd):
    lc = fl.LineContact(psd, E_STAR, RADIUS, n=256, warn=False)
    fast, ref = lc.sweep(LOADS), python_sweep(lc, LOADS)
    for a, b in zip(fast, ref, strict=True):
        assert a.converged and b.converged and a.load == b.load
        assert a.p0 == pytest.approx(b.p0, rel=RTOL_SAME_START)
        assert a.w_over_s == pytest.approx(b.w_over_s, rel=RTOL_SAME_START)
        big = b.pressure > 1e-6 * b.p0
        assert np.allclose(a.pressure[big], b.pressure[big], rtol=1e-7, atol=0.0)
        assert a.convolutions == a.diagnostics["k_applications"] + a.diagnostics["circulant_solves"]
    total_fast = sum(r.convolutions for r in fast)
    total_ref = sum(r.convolutions for r in ref)
    assert abs(total_fast - total_ref) <= COUNT_SLACK * total_ref


@pytest.mark.parametrize("model", ["exponential", "tabulated"])
def test_compiled_sweep_of_other_shipped_laws(model):
    """The exponential and a tabulated law run the same compiled loop (their own law kinds)."""
    theory = fl.PerssonTheory(SURFACES[0], E_STAR)
    if model == "tabulated":
        p = np.geomspace(1e-2, 1e8, 200)  # Pa
        law = fl.TabulatedLaw(theory.separation(p), p)
    else:
        law = fl.ExponentialLaw.from_theory(theory)
    lc = fl.LineContact(SURFACES[0], E_STAR, RADIUS, model=law, n=128, warn=False)
    assert lc._law_form() is not None  # the compiled path is taken
    fast, ref = lc.sweep(LOADS[10:40:3]), python_sweep(lc, LOADS[10:40:3])
    for a, b in zip(fast, ref, strict=True):
        assert a.converged and b.converged
        assert a.p0 == pytest.approx(b.p0, rel=RTOL_SAME_START)
        assert a.w_over_s == pytest.approx(b.w_over_s, rel=RTOL_SAME_START)


def test_compiled_sweep_equals_independent_solves_in_any_order():
    lc = fl.LineContact(SURFACES[2], E_STAR, RADIUS, n=256, warn=False)
    loads = np.random.default_rng(7).permutation(LOADS[8:40])  # steps of ln 1.25
    swept = lc.sweep(loads)
    for f, r in zip(loads, swept, strict=True):
        alone = lc.solve(float(f))
        assert r.load == f and r.converged
        assert r.p0_ratio == pytest.approx(alone.p0_ratio, rel=RTOL_CONTINUATION)
        assert r.w_over_s == pytest.approx(alone.w_over_s, rel=RTOL_CONTINUATION)
        assert np.array_equal(r.x, alone.x)
    # continuation: fewer convolutions than independent solves
    assert sum(r.convolutions for r in swept) < sum(lc.solve(float(f)).convolutions for f in loads)


def _history(lc, loads):
    """Solutions of a model as both predictors keep them: the Python list of _Solved and the
    compiled history arrays (filled by the compiled _remember)."""
    solved, arrays = [], _line_sweep.history_arrays(ORDER, lc.n)
    scal, cells, count = arrays
    for f in loads:
        grid = lc._grid(f)
        res = lc.solve(f)
        solved.append(lc._solved(grid, res))
        v = np.log(np.maximum(res.pressure, 1e-300))
        count[0] = _line_sweep._remember(
            math.log(f), grid.x, v, grid.dx, res.s, scal, cells, count[0]
        )
    return solved[-(ORDER + 1) :], arrays


@pytest.mark.parametrize("next_load", [2.3e4, 2.9e4], ids=["short", "long"])
def test_predictor_equals_the_python_predictor(next_load):
    lc = fl.LineContact(SURFACES[0], E_STAR, RADIUS, n=128, warn=False)
    loads = [1e4, 1.2e4, 1.4e4, 1.6e4, 1.8e4, 2e4, 2.2e4][-(ORDER + 2) :]
    solved, (scal, cells, count) = _history(lc, loads)
    assert count[0] == ORDER + 1  # the oldest dropped
    grid = lc._grid(next_load)
    ref = lc._predict(grid, solved)
    out, work = np.empty(lc.n), np.empty(2 * lc.n)
    consts = (ORDER, *_contact.CORE_DEPTH)
    _line_sweep.predict_into(math.log(next_load), *consts, scal, cells, count[0], grid.x, work, out)
    assert np.allclose(out, ref, rtol=RTOL_ROUNDOFF, atol=RTOL_ROUNDOFF * np.abs(ref).max())
    # and the prediction is a good one: near the solution in the contact
    sol = np.log(np.maximum(lc.solve(next_load).pressure, 1e-300))
    core = sol > sol.max() - 3.0
    assert np.abs(out - sol)[core].max() < 0.5


def test_slopes_are_numpy_gradient():
    x = np.linspace(-2.0, 3.0, 41)
    y = np.sin(x) * np.exp(x)
    out = np.empty_like(y)
    _line_sweep._slopes(x[1] - x[0], y, out)
    assert np.allclose(out, np.gradient(y, x, edge_order=2), rtol=RTOL_ROUNDOFF, atol=1e-13)
    q = 1.5 * x**2 - x + 2.0  # exact for quadratics, ends included
    _line_sweep._slopes(x[1] - x[0], q, out)
    assert np.allclose(out, 3.0 * x - 1.0, rtol=0.0, atol=1e-11)


def test_repeated_loads():
    """A load given twice: no two history rows at one load (the Lagrange weights would divide
    by zero; the Python loop raised ZeroDivisionError, for the sphere too)."""
    lc = fl.LineContact(SURFACES[0], E_STAR, RADIUS, n=128, warn=False)
    loads = [1e4, 1e4, 1.1e4, 1.1e4, 1.2e4]
    for res in (lc.sweep(loads), python_sweep(lc, loads)):
        assert all(r.converged for r in res)
        assert res[0].p0 == res[1].p0
        assert res[4].p0 == pytest.approx(lc.solve(1.2e4).p0, rel=RTOL_CONTINUATION)
    pc = fl.PointContact(SURFACES[0], E_STAR, RADIUS, n=64, warn=False)
    assert all(r.converged for r in pc.sweep([1.0, 1.0, 1.1]))


def test_restarts_cold_when_the_prediction_fails():
    """A prediction that misleads Newton (from a poisoned history: ln p alternating by 60
    between cells): the load is solved again from the cold start, which is an independent
    solve bit for bit, and both attempts are counted."""
    lc = fl.LineContact(SURFACES[0], E_STAR, RADIUS, n=128, max_iter=6, warn=False)
    load = 1.2e4
    hz = hertz_line_unchecked(E_STAR, RADIUS, load)
    scal, cells, count = _line_sweep.history_arrays(ORDER, lc.n)
    scal[0] = (math.log(1.1e4), math.log(hz.a))
    cells[0, 0] = np.linspace(-4.0, 4.0, lc.n)
    cells[1, 0] = np.tile([30.0, -30.0], lc.n // 2)
    count[0] = 1
    out = _line_sweep.run_sweep(
        lc.n,
        E_STAR,
        RADIUS,
        np.array([load]),
        np.array([lc._extent("half_width", None, hz, load)]),
        np.array([lc._cold_profiles(hz)]),
        lc._law_form(),
        lc.law.u0,
        lc.tol,
        lc.max_iter,
        history=(scal, cells, count),
    )
    stats = dict(zip(_line_sweep.STATS, out.stats[0], strict=True))
    alone = lc.solve(load)
    assert stats["restarted_cold"] == 1.0 and stats["status"] == 0 and alone.converged
    assert np.array_equal(out.p[0], alone.pressure)
    # both attempts counted: the failed one made at least its first evaluation
    assert stats["k_applications"] > alone.diagnostics["k_applications"]
    assert stats["circulant_solves"] >= alone.diagnostics["circulant_solves"]
    assert count[0] == 2 and scal[1, 0] == math.log(load)  # the solution is remembered


def test_a_failed_cold_start_is_not_repeated():
    """A long step starts cold; if that fails (here: too few Newton steps) there is nothing
    else to try: the load costs what an independent solve costs, once."""
    lc = fl.LineContact(SURFACES[0], E_STAR, RADIUS, n=128, max_iter=2, warn=False)
    res = lc.sweep([1e4, 1e5])  # a step of ln 10: cold
    alone = lc.solve(1e5)
    assert not alone.converged and not res[1].converged
    assert res[1].convolutions == alone.convolutions
    assert "restarted_cold" not in res[1].diagnostics


def test_sweep_reports_the_restart(monkeypatch):
    """What a restarted load's result says (the compiled sweep's statistics, poisoned)."""
    real = _line_sweep.run_sweep

    def poisoned(*args, **kwargs):
        out = real(*args, **kwargs)
        out.stats[1:, _line_sweep.STATS.index("restarted_cold")] = 1.0
        return out

    monkeypatch.setattr(_line_sweep, "run_sweep", poisoned)
    lc = fl.LineContact(SURFACES[0], E_STAR, RADIUS, n=128, warn=False)
    res = lc.sweep([1e4, 1.1e4])
    assert "restarted_cold" not in res[0].diagnostics
    assert res[1].diagnostics["restarted_cold"] is True


def test_progress_is_called_per_load_and_changes_nothing():
    lc = fl.LineContact(SURFACES[1], E_STAR, RADIUS, n=128, warn=False)
    calls = []
    stepped = lc.sweep(LOADS[::8], progress=lambda: calls.append(1))
    whole = lc.sweep(LOADS[::8])
    assert len(calls) == LOADS[::8].size
    for a, b in zip(stepped, whole, strict=True):
        assert np.array_equal(a.pressure, b.pressure) and a.convolutions == b.convolutions


def test_threads_sweep_one_model_bit_for_bit():
    lc = fl.LineContact(SURFACES[0], E_STAR, RADIUS, n=256, warn=False)
    serial = [r.pressure for r in lc.sweep(LOADS[::4])]
    out = [None] * 4

    def run(i):
        out[i] = [r.pressure for r in lc.sweep(LOADS[::4])]

    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for got in out:
        assert all(np.array_equal(a, b) for a, b in zip(got, serial, strict=True))


def test_other_methods_take_the_python_loop():
    """Picard and user laws have no compiled path: the sweep is the Python loop's."""
    lc = fl.LineContact(SURFACES[0], E_STAR, RADIUS, n=128, method="picard", warn=False)
    a, b = lc.sweep([1e4, 2e4]), python_sweep(lc, [1e4, 2e4])
    assert all(np.array_equal(x.pressure, y.pressure) for x, y in zip(a, b, strict=True))
