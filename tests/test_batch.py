"""fl.sweep: a table of scenes on serial, process-pool, thread-pool and dask executors.

What is held: every executor gives the serial numbers bit for bit (also for failing scenes);
each row is what ``LineContact.sweep`` gives for its piece of the plan, in the input order; a
spectrum and material build one theory per worker process; failing scenes and failing tasks
stay in their rows; bad tables are refused before any task is submitted; CSV and pandas
round trips; warnings once per cause.
"""

from __future__ import annotations

import concurrent.futures as cf
import logging
import multiprocessing
import os
import pickle
import warnings

import numpy as np
import pytest

import fastline as fl
import fastline.contact.diagnostics as _diagnostics
import fastline.contact.line as _line_contact
import fastline.contact.point as _point_contact
import fastline.theory.variants as _variants
from fastline import batch
from fastline.batch.scenes import BY_NAME
from fastline.cli import sphere as cli_sphere
from fastline.contact.diagnostics import ValidityWarning
from fastline.contact.line import ConvergenceWarning
from fastline.io import read_csv

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLE_PSD = os.path.join(ROOT, "examples", "psd_example.txt")
E_STAR, RADIUS, N = 1.33e9, 0.01, 96
#: a sweep (warm starts) vs independent solves at tol 1e-8 (as in tests/test_embedding.py)
RTOL_CONTINUATION = 1e-7
SURFACES = ((10e-6, 0.8), (10e-6, 1.0), (1e-6, 0.8))  # the paper's (h_rms [m], H)
ALPHAS = np.geomspace(1e-2, 1e2, 8)


def scene(h_rms, hurst, load, **extra) -> dict:
    """A self-affine scene (q0, qr, q1 of the paper) at n = N, with ``extra`` columns."""
    base = dict(h_rms=h_rms, hurst=hurst, q0=1e3, qr=1e4, q1=1e9, E_star=E_STAR, radius=RADIUS)
    return {**base, "load": float(load), "n": N, **extra}


def paper_scenes(seed=0) -> list[dict]:
    """3 surfaces x 8 loads (alpha 1e-2..1e2), shuffled, plus three failing scenes."""
    rows = [scene(h, H, fl.paper.load_for_alpha(a, h)) for h, H in SURFACES for a in ALPHAS]
    rng = np.random.default_rng(seed)
    rows = [rows[i] for i in rng.permutation(len(rows))]
    rows.insert(5, scene(1e-6, 1.5, 1e4))  # Hurst exponent out of range: the model fails
    rows.insert(11, scene(1e-6, 0.8, -1e4))  # a negative load: this scene only
    rows.insert(17, {**scene(1e-6, 0.8, 1e4), "n": 8})  # grid too small
    return rows


def assert_same_table(a: fl.SweepTable, b: fl.SweepTable) -> None:
    """Every column equal, bit for bit (NaN where NaN)."""
    assert a.columns == b.columns
    for name in a.columns:
        x, y = a[name], b[name]
        if x.dtype.kind == "f":
            assert np.array_equal(x.view(np.int64), y.view(np.int64)), name
        else:
            assert np.array_equal(x, y), name


def run(scenes, executor="serial", **kw) -> fl.SweepTable:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fl.sweep(scenes, executor, progress=False, **kw)


@pytest.fixture(scope="module")
def pool():
    ctx = multiprocessing.get_context("spawn")
    with cf.ProcessPoolExecutor(2, mp_context=ctx) as ex:
        yield ex


@pytest.fixture(scope="module")
def dask_client():
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(
        n_workers=2,
        processes=True,
        threads_per_worker=1,
        dashboard_address=None,
        silence_logs=logging.ERROR,
    )
    client = distributed.Client(cluster)
    yield client
    client.close()
    cluster.close()


@pytest.fixture(scope="module")
def serial():
    return run(paper_scenes(), chunksize=5)


# ---- what each row is -----------------------------------------------------------------------
def test_rows_are_the_plan_sweeps_in_input_order():
    """Shuffled loads of one model, chunksize 4: each row equals LineContact.sweep over its
    piece (4 consecutive loads in increasing order), bit for bit, and independent solves to
    the solver tolerance."""
    loads = fl.paper.load_for_alpha(np.geomspace(1e-2, 1e2, 12), 10e-6)
    order = np.random.default_rng(1).permutation(loads.size)
    res = run([scene(10e-6, 0.8, loads[i]) for i in order], chunksize=4)
    assert np.array_equal(res["load"], loads[order])
    lc = fl.LineContact(fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9), E_STAR, RADIUS, n=N)
    ascending = np.sort(loads)
    swept = [r for k in range(0, 12, 4) for r in lc.sweep(ascending[k : k + 4])]
    row_of = {f: i for i, f in enumerate(res["load"])}
    for r in swept:
        i = row_of[r.load]
        assert (res["p0"][i], res["fwhm"][i], res["s"][i]) == (r.p0, r.fwhm, r.s)
        assert res["convolutions"][i] == r.convolutions and res["converged"][i]
        alone = lc.solve(r.load)
        assert res["p0_ratio"][i] == pytest.approx(alone.p0_ratio, rel=RTOL_CONTINUATION)
        assert res["alpha"][i] == alone.alpha
    assert res.stats.tasks == 3 and not res.failed.any()


def test_serial_failures_stay_in_their_rows(serial):
    err = serial["error"]
    assert "hurst must lie in (0, 1]" in err[5]
    assert "load must lie in" in err[11]
    assert "n must be an integer in [16" in err[17]
    assert np.count_nonzero(err != "") == 3
    good = err == ""
    assert serial["converged"][good].all() and np.isfinite(serial["p0"][good]).all()
    assert np.isnan(serial["p0"][~good]).all() and (serial["iterations"][~good] == 0).all()
    assert np.array_equal(serial.ok, good)
    # the rest of the failing scene's piece is still solved (load by load)
    assert serial.stats.scenes == 27


# ---- the same numbers on every executor -------------------------------------------------------
def test_process_pool_equals_serial(serial, pool):
    res = run(paper_scenes(), pool, chunksize=5)
    assert_same_table(res, serial)
    assert res.stats.executor == "ProcessPoolExecutor" and res.stats.tasks == serial.stats.tasks
    assert serial.stats.tasks >= 6 and res.stats.workers == 2


def test_default_local_pool_equals_serial(serial):
    res = run(paper_scenes(), None, workers=2, chunksize=5)
    assert_same_table(res, serial)
    assert res.stats.executor == "local process pool (2 workers)" and res.stats.workers <= 2


def test_thread_pool_equals_serial(serial):
    with cf.ThreadPoolExecutor(4) as ex:
        assert_same_table(run(paper_scenes(), ex, chunksize=5), serial)


def test_dask_local_cluster_equals_serial(serial, dask_client):
    """The CI check: a LocalCluster with 2 worker processes, bit for bit (a Client
    and its get_executor() both accepted)."""
    assert_same_table(run(paper_scenes(), dask_client, chunksize=5), serial)
    res = run(paper_scenes(), dask_client.get_executor(), chunksize=5)
    assert_same_table(res, serial)
    address = dask_client.scheduler.address
    assert_same_table(run(paper_scenes(), address, chunksize=5), serial)


# ---- theories shared on each worker -----------------------------------------------------------
def test_serial_builds_one_theory_per_spectrum():
    """3 spectra x 8 loads in 12 tasks of 2 scenes, plus a second n for surface 1 (another
    model, the same theory): 3 theories and 4 models, not one per task or scene."""
    rows = [scene(h, H, f) for h, H in SURFACES for f in (1e3, 3e3, 1e4, 3e4)]
    rows += [{**scene(10e-6, 0.8, f), "n": 64} for f in (1e3, 1e4, 1e5, 1e6)]
    res = run(rows, chunksize=2)
    assert res.stats.tasks == 8
    assert (res.stats.theory_builds, res.stats.model_builds) == (3, 4)


@pytest.mark.parametrize("engine", ["pool", "dask_client"])
def test_workers_build_one_theory_per_spectrum(engine, request):
    """A fresh material (so no earlier test filled the workers' caches): at most one build per
    spectrum and worker process over 36 tasks (one per task without the cache)."""
    executor = request.getfixturevalue(engine)
    E_star = 1.2345e9 if engine == "pool" else 1.3456e9
    rows = [scene(h, H, f, E_star=E_star) for h, H in SURFACES for f in np.geomspace(1e3, 1e5, 12)]
    res = run(rows, executor, chunksize=1)
    assert res.stats.tasks == 36 and not res.failed.any()
    assert 1 <= res.stats.workers <= 2
    assert 3 <= res.stats.theory_builds <= 3 * res.stats.workers
    assert res.stats.model_builds == res.stats.theory_builds


# ---- failures ------------------------------------------------------------------------------
class FlakyExecutor(cf.Executor):
    """Runs tasks in this thread; the second task's future fails (a worker lost)."""

    def __init__(self):
        self.calls = 0

    def submit(self, fn, /, *args, **kwargs):
        self.calls += 1
        fut = cf.Future()
        if self.calls == 2:
            fut.set_exception(RuntimeError("worker lost"))
        else:
            fut.set_result(fn(*args, **kwargs))
        return fut


def test_failing_task_is_reported_in_its_rows():
    rows = [scene(10e-6, 0.8, f) for f in np.geomspace(1e3, 1e5, 9)]
    res = run(rows, FlakyExecutor(), chunksize=3)
    lost = res["error"] == "task failed: RuntimeError: worker lost"
    assert lost.sum() == 3 and np.array_equal(res["load"][lost], np.sort(res["load"])[3:6])
    assert res["converged"][~lost].all()


def test_spectrum_file_errors_are_per_scene(tmp_path):
    bad = tmp_path / "profile.txt"
    bad.write_text("0 1e-6\n1e-3 2e-6\n")  # x starts at 0: a height profile, refused
    rows = [
        dict(psd=str(bad), E_star=E_STAR, radius=RADIUS, load=1e4, n=N),
        dict(psd=str(tmp_path / "missing.txt"), E_star=E_STAR, radius=RADIUS, load=1e4, n=N),
        dict(psd=EXAMPLE_PSD, E_star=5e6, radius=2e-3, load=500.0, n=N),
        dict(psd=None, E_star=E_STAR, radius=RADIUS, load=1e4, n=N),  # persson needs a psd
    ]
    res = run(rows)
    assert "looks like a height profile" in res["error"][0]
    assert "cannot read spectrum file" in res["error"][1]
    assert res["error"][2] == "" and res["converged"][2]
    assert "psd must be a PSD" in res["error"][3]


# ---- the spectrum given three ways; table forms --------------------------------------------
def test_psd_objects_files_and_parameters_agree():
    h, H = 10e-6, 0.8
    psd = fl.SelfAffinePSD(h, H, 1e3, 1e4, 1e9)
    loads = [1e3, 1e4, 1e5]
    by_params = run([scene(h, H, f) for f in loads])
    keys = ("E_star", "radius", "load", "n")
    by_object = run([{"psd": psd, **{k: scene(h, H, f)[k] for k in keys}} for f in loads])
    for name in batch.RESULT_COLUMNS:
        assert np.array_equal(by_params[name], by_object[name]), name
    assert by_object["psd"][0] is psd
    tab = fl.io.read_spectrum(EXAMPLE_PSD)
    from_file = run([dict(psd=EXAMPLE_PSD, E_star=5e6, radius=2e-3, load=f, n=N) for f in loads])
    from_obj = run([dict(psd=tab, E_star=5e6, radius=2e-3, load=f, n=N) for f in loads])
    assert np.array_equal(from_file["p0"], from_obj["p0"]) and from_file.ok.all()
    hertz = run([dict(psd=None, E_star=E_STAR, radius=RADIUS, load=1e4, n=N, model="hertz")])
    assert hertz["p0_ratio"][0] == pytest.approx(1.0, rel=1e-2) and hertz["alpha"][0] == 0.0


class FrameLike:
    """What sweep reads of a pandas DataFrame: ``columns``, ``to_dict``, ``df[name].tolist()``."""

    def __init__(self, columns: dict):
        self._cols = columns
        self.columns = list(columns)

    def to_dict(self):  # pragma: no cover - only its presence matters
        return self._cols

    def __getitem__(self, name):
        return np.array(self._cols[name])


def test_table_forms_agree():
    rows = [scene(10e-6, 0.8, f, label=f"f{k}") for k, f in enumerate((1e3, 1e4, 1e5))]
    ref = run(rows)
    columns = {k: [r[k] for r in rows] for k in rows[0]}
    assert_same_table(run(columns), ref)
    names = list(rows[0])
    dtype = [(k, "U8" if k == "label" else ("i8" if k == "n" else "f8")) for k in names]
    arr = np.array([tuple(r[k] for k in names) for r in rows], dtype=dtype)
    assert_same_table(run(arr), ref)
    assert_same_table(run(FrameLike(columns)), ref)
    pd = pytest.importorskip("pandas")  # not in the test extra: +25 s on a fresh install
    assert_same_table(run(pd.DataFrame(rows)), ref)
    df = ref.to_pandas()
    assert list(df.columns) == list(ref.columns) and np.array_equal(df["p0"], ref["p0"])
    assert list(df["label"]) == ["f0", "f1", "f2"]


def test_missing_optional_cells_take_defaults():
    rows = [scene(10e-6, 0.8, 1e4, gamma=None, hardness=float("nan"), model=None, variant=None)]
    rows.append(scene(10e-6, 0.8, 1e4, gamma=float("nan"), variant="wang-mueser"))
    res = run(rows)
    assert res["gamma"][0] == 0.45 and np.isnan(res["hardness"][0]) and res["model"][0] == "persson"
    assert res["geometry"][0] == "cylinder" and res["max_iter"][0] == 0 and res.ok.all()
    assert res["variant"][0] == "yang-persson-energy"
    assert res["gamma"][1] == 5.0 / 9.0  # the variant's own gamma


def test_a_new_geometry_plugs_in(monkeypatch):
    """The seam the sphere will use: a builder registered under a new ``geometry`` name gets
    its own models and shares the spectrum's theory."""
    built = []

    def builder(spec, psd, theory):
        built.append(spec.geometry)
        return batch.GEOMETRIES["cylinder"](spec, psd, theory)

    monkeypatch.setitem(batch.GEOMETRIES, "other", builder)
    rows = [scene(10e-6, 0.8, f, geometry=g) for g in ("cylinder", "other") for f in (1e3, 1e4)]
    res = run(rows)
    assert built == ["other"] and list(res["geometry"]) == ["cylinder"] * 2 + ["other"] * 2
    assert np.array_equal(res["p0"][:2], res["p0"][2:])
    assert (res.stats.theory_builds, res.stats.model_builds) == (1, 2)


# ---- the theory's variant ----------------------------------------------------------------------
VARIANTS = tuple(_variants.VARIANTS)
#: least change of p0 by the printed bracket at alpha = 1 (expected: several per cent)
MIN_VARIANT_EFFECT = 0.03


def variant_scenes() -> list[dict]:
    """3 variants x 3 loads (alpha 0.1, 1, 10) interleaved, and a row without a variant."""
    loads = fl.paper.load_for_alpha(np.array([0.1, 1.0, 10.0]), 10e-6)
    rows = [scene(10e-6, 0.8, f, variant=v, label=v) for f in loads[::-1] for v in VARIANTS]
    return rows + [scene(10e-6, 0.8, loads[1], label="default")]


@pytest.fixture(scope="module")
def variant_serial():
    return run(variant_scenes(), chunksize=4)


def test_variant_column_is_line_contact_variant(variant_serial):
    """Each row equals LineContact(..., variant=...).sweep over its variant's loads (in the
    plan's order: by load, stably), bit for bit; the row without a variant is the default
    variant's; one theory per variant; the printed bracket moves p0 at alpha = 1."""
    res, psd = variant_serial, fl.SelfAffinePSD(10e-6, 0.8, 1e3, 1e4, 1e9)
    assert res.stats.tasks == 3 and res.stats.theory_builds == 3 and res.ok.all()
    for v in VARIANTS:
        rows = np.flatnonzero(res["variant"] == v)
        rows = rows[np.argsort(res["load"][rows], kind="stable")]
        lc = fl.LineContact(psd, E_STAR, RADIUS, n=N, variant=v)
        for i, r in zip(rows, lc.sweep(res["load"][rows]), strict=True):
            assert (res["p0"][i], res["s"][i], res["fwhm"][i]) == (r.p0, r.s, r.fwhm), v
            assert res["convolutions"][i] == r.convolutions
        assert np.all(res["gamma"][rows] == lc.theory.gamma)
    at_1 = np.isclose(res["alpha"], 1.0)
    p0 = dict(zip(res["label"][at_1], res["p0"][at_1], strict=True))
    assert p0["yang-persson-printed"] > (1.0 + MIN_VARIANT_EFFECT) * p0["yang-persson-energy"]
    assert p0["default"] == pytest.approx(p0["yang-persson-energy"], rel=RTOL_CONTINUATION)


def test_variant_column_on_a_process_pool(variant_serial, pool):
    res = run(variant_scenes(), pool, chunksize=4)
    assert_same_table(res, variant_serial)
    assert res.stats.workers == 2


# ---- spheres: geometry="sphere" rows are PointContact scenes --------------------------------
N_SPHERE = 48  # cells of the sphere's grid (kept small: the ring operator is dense)
SPHERE_LOADS = (0.05, 0.3, 2.0, 12.0)  # N: alpha about 3 .. 0.03 for h_rms = 1e-6 m


def sphere_scene(load, **extra) -> dict:
    return scene(1e-6, 0.8, load, geometry="sphere", n=N_SPHERE, **extra)


def point_contact(**kw) -> fl.PointContact:
    psd = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)
    return fl.PointContact(psd, E_STAR, RADIUS, n=N_SPHERE, warn=False, **kw)


def assert_rows_are(res, rows, results) -> None:
    """Every result column of the rows equals the results' attribute, bit for bit."""
    for i, r in zip(rows, results, strict=True):
        for name in batch.RESULT_COLUMNS[:10]:
            assert res[name][i] == getattr(r, name), (i, name)


@pytest.mark.parametrize("engine", ["serial", "pool"])
def test_sphere_rows_are_point_contact_solves(engine, request):
    """chunksize 1: each sphere row is PointContact(...).solve(load), bit for bit, in the
    serial engine and on a 2-process pool."""
    executor = "serial" if engine == "serial" else request.getfixturevalue("pool")
    loads = SPHERE_LOADS[::-1]
    res = run([sphere_scene(f) for f in loads], executor, chunksize=1)
    assert res.ok.all() and list(res["geometry"]) == ["sphere"] * 4
    pc = point_contact()
    assert_rows_are(res, range(4), [pc.solve(f) for f in loads])
    assert res["alpha"][0] == pytest.approx(1e-6 * RADIUS / pc.solve(loads[0]).hertz_radius ** 2)


def test_sphere_pieces_are_point_contact_sweeps(pool):
    """chunksize 2: the rows are PointContact.sweep over pairs of consecutive loads, on the
    serial engine and on a pool alike."""
    rows = [sphere_scene(f) for f in SPHERE_LOADS]
    res = run(rows, chunksize=2)
    pc = point_contact()
    assert_rows_are(res, range(4), pc.sweep(SPHERE_LOADS[:2]) + pc.sweep(SPHERE_LOADS[2:]))
    assert_same_table(run(rows, pool, chunksize=2), res)


def test_mixed_cylinder_and_sphere_table(tmp_path):
    """Cylinders and spheres of one spectrum in one table: each row equals its geometry's
    model, one theory serves both, n defaults to the geometry's own, a bad sphere load fails
    its row only, the validity warnings name each geometry's loads in its unit, and the CSV
    file names the load column by its unit."""
    sphere_rows = [sphere_scene(f) for f in SPHERE_LOADS[:2]]
    cylinder_rows = [scene(1e-6, 0.8, f) for f in (1e4, 1e5)]
    defaults = [{**sphere_scene(1.0), "n": None}, {**scene(1e-6, 0.8, 1e4), "n": None}]
    rows = [*sphere_rows, *cylinder_rows, *defaults, sphere_scene(-1.0)]
    res = run(rows, chunksize=1)
    geometries = ["sphere", "sphere", "cylinder", "cylinder", "sphere", "cylinder", "sphere"]
    assert list(res["geometry"]) == geometries
    assert_rows_are(res, (0, 1), [point_contact().solve(f) for f in SPHERE_LOADS[:2]])
    lc = fl.LineContact(fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9), E_STAR, RADIUS, n=N)
    assert_rows_are(res, (2, 3), [lc.solve(f) for f in (1e4, 1e5)])
    assert res["n"][4] == _point_contact.DEFAULT_N and res["n"][5] == _line_contact.DEFAULT_N
    psd = fl.SelfAffinePSD(1e-6, 0.8, 1e3, 1e4, 1e9)
    assert res["p0"][4] == fl.PointContact(psd, E_STAR, RADIUS, warn=False).solve(1.0).p0
    assert res.stats.theory_builds == 1 and res.stats.model_builds == 4
    assert "load must lie in" in res["error"][6] and " N (" in res["error"][6]
    assert np.count_nonzero(res.failed) == 1
    narrow = [m for c, m in res.warnings if c == "narrow_contact"]
    assert len(narrow) == 2
    assert any("[3 of 3 solves: F = 0.05, 0.3, 1 N]" in m for m in narrow)
    assert any("[3 of 3 solves: f_N = 1e+04" in m and m.endswith(" N/m]") for m in narrow)
    res.to_csv(tmp_path / "mixed.csv")
    meta, cols = read_csv(tmp_path / "mixed.csv")
    assert "load" in cols and meta["load_unit"] == "N (sphere); N/m (cylinder)"
    spheres = run(sphere_rows)
    spheres.to_csv(tmp_path / "spheres.csv")
    _, cols = read_csv(tmp_path / "spheres.csv")
    assert "load_N" in cols and "load_N_per_m" not in cols
    (tmp_path / "scenes.csv").write_text(
        "h_rms,hurst,q0,qr,q1,E_star,radius,geometry,load_N,n\n"
        f"1e-6,0.8,1e3,1e4,1e9,{E_STAR},{RADIUS},sphere,{SPHERE_LOADS[0]},{N_SPHERE}\n"
    )
    again = run(batch.read_scenes(tmp_path / "scenes.csv"))
    assert again["p0"][0] == res["p0"][0] and again["geometry"][0] == "sphere"


# ---- bad tables: refused before any task is submitted -----------------------------------------
class SpyExecutor(cf.Executor):
    def __init__(self):
        self.calls = 0

    def submit(self, fn, /, *args, **kwargs):  # pragma: no cover - must not be reached
        self.calls += 1
        raise AssertionError("a task was submitted")


GOOD = scene(10e-6, 0.8, 1e4)
BAD_TABLES = [
    ([{**GOOD, "loads": 1e4}], ValueError, r"unknown columns \['loads'\]"),
    ([{**GOOD, "p0": 1.0}], ValueError, r"unknown columns \['p0'\]"),
    ([{k: v for k, v in GOOD.items() if k != "E_star"}], ValueError, r"missing columns \['E_st"),
    ([{k: v for k, v in GOOD.items() if k != "q1"}], ValueError, "missing columns.*q1"),
    ([{**GOOD, "psd": EXAMPLE_PSD}], ValueError, "either as a psd column or as h_rms"),
    ([GOOD, {k: v for k, v in GOOD.items() if k != "load"}], ValueError, "'load' is missing in"),
    ([GOOD, {**GOOD, "h_rms": None}], ValueError, "'h_rms' has no value in row 1"),
    ([{**GOOD, "load": "1e4"}], TypeError, "'load' must hold a real number; row 0 holds '1e4'"),
    ([{**GOOD, "E_star": True}], TypeError, "'E_star' must hold a real number"),
    (
        [GOOD, {**GOOD, "radius": True}],
        TypeError,
        "'radius' must hold a real number; row 1 holds T",
    ),
    ([GOOD, {**GOOD, "n": 96.0}, {**GOOD, "n": 96.5}], TypeError, "'n' must hold an integer"),
    ([{**GOOD, "n": 128.5}], TypeError, "'n' must hold an integer"),
    ([{**GOOD, "model": 3}], TypeError, "'model' must hold a model name"),
    (  # a law object: one line naming the in-process sweep that takes it
        [{**GOOD, "model": fl.ExponentialLaw(1e-6, 1e5, 1.33e9)}],
        TypeError,
        r"'model' must hold a model name .*in this process: LineContact\(psd, E_star, radius, "
        r"model=law\)\.sweep\(loads\).*row 0 holds ExponentialLaw",
    ),
    ([{**GOOD, "model": "Persson"}], ValueError, "'model' must be one of .*row 0 is 'Persson'"),
    ([{**GOOD, "method": "bfgs"}], ValueError, "'method' must be one of"),
    (
        [GOOD, {**GOOD, "variant": "persson"}],
        ValueError,
        r"'variant' must be one of \('yang-persson-energy', .*row 1 is 'persson'",
    ),
    ([{**GOOD, "variant": 3}], TypeError, "'variant' must hold a string"),
    (
        [GOOD, {**GOOD, "geometry": "line"}],
        ValueError,
        r"'geometry' must be one of \('cylinder', 'sphere'\); row 1 is 'line'",
    ),
    ([{**GOOD, "geometry": 2}], TypeError, "'geometry' must hold a string; row 0 holds 2"),
    ([{"psd": 1.0, **{k: GOOD[k] for k in ("E_star", "radius", "load")}}], TypeError, "PSD, the"),
    ([], ValueError, "at least one scene"),
    ([GOOD, 3], TypeError, "row 1 must be a dict"),
    ("scenes.csv", TypeError, "scenes must be a list of dicts"),
    (np.zeros((2, 2)), TypeError, "1-D NumPy structured array"),
    ({"load": [1.0, 2.0], "E_star": [1.0]}, ValueError, "same length"),
    ({"load": [1.0, 2.0], "E_star": 1.33e9}, TypeError, "column 'E_star' .* sequence of cells"),
    ({"load": [1.0], "psd": "examples/psd_example.txt"}, TypeError, "column 'psd'"),  # not chars
]


@pytest.mark.parametrize("scenes, error, match", BAD_TABLES)
def test_bad_tables_are_refused_before_any_work(scenes, error, match):
    spy = SpyExecutor()
    with pytest.raises(error, match=match):
        fl.sweep(scenes, spy, progress=False)
    assert spy.calls == 0


@pytest.mark.parametrize(
    "kw, error, match",
    [
        (dict(chunksize=0), ValueError, "chunksize must be an integer >= 1"),
        (dict(executor="serial", workers=2), ValueError, "workers applies only"),
        (dict(workers=0), ValueError, "workers must be an integer >= 1"),
        (dict(executor="local"), ValueError, 'executor must be None, "serial"'),
        (dict(executor=4), TypeError, "got int"),
    ],
)
def test_bad_options_are_refused(kw, error, match):
    with pytest.raises(error, match=match):
        fl.sweep([GOOD], progress=False, **kw)


def test_scheduler_address_without_dask_says_how_to_install(monkeypatch):
    monkeypatch.setitem(__import__("sys").modules, "distributed", None)
    with pytest.raises(ImportError, match=r"fastline-contact\[dask\]"):
        fl.sweep([GOOD], "tcp://127.0.0.1:1", progress=False)


# ---- files, warnings ---------------------------------------------------------------------
def test_csv_round_trip(serial, tmp_path):
    path = tmp_path / "out.csv"
    serial.to_csv(path)
    meta, cols = read_csv(path)
    assert meta["scenes"] == "27" and meta["failed"] == "3" and meta["chunksize"] == "5"
    for name, col in zip(serial.columns, cols, strict=True):
        c = BY_NAME[name]
        assert col == c.csv_name
        if c.kind == "float":
            assert np.array_equal(cols[col], serial[name], equal_nan=True), name
    assert "load_N_per_m" in cols and "p0_Pa" in cols and "E_star_Pa" in cols
    assert "," in serial["error"][5] and cols["error"][5] == serial["error"][5]  # quoted as CSV
    again = run(batch.read_scenes(path), chunksize=5)  # result columns skipped on reading
    assert_same_table(again, serial)


def test_read_scenes(tmp_path):
    (tmp_path / "spectra").mkdir()
    text = open(EXAMPLE_PSD).read()
    (tmp_path / "spectra" / "a.txt").write_text(text)
    (tmp_path / "scenes.csv").write_text(
        "# a design study\n"
        "label,psd,E_star_Pa,radius,load_N_per_m,n,hardness\n"
        '"seal, soft",spectra/a.txt,5e6,2e-3,500,96,\n'
        "seal hard,spectra/a.txt,5e7,2e-3,500,,2e8\n"
    )
    cols = batch.read_scenes(tmp_path / "scenes.csv")
    assert cols["label"] == ["seal, soft", "seal hard"]
    assert cols["psd"][0] == str(tmp_path / "spectra" / "a.txt")
    assert cols["n"] == [96.0, None] and cols["hardness"] == [None, 2e8]
    res = run(cols)
    assert res["n"].tolist() == [96, 1024] and res.ok.all()
    (tmp_path / "bad.csv").write_text("psd,E_star,radius,load,mu\na.txt,1,1,1,0.3\n")
    with pytest.raises(ValueError, match=r"unknown columns \['mu'\]"):
        batch.read_scenes(tmp_path / "bad.csv")
    (tmp_path / "short.csv").write_text("psd,E_star,radius,load\na.txt,1,1\n")
    with pytest.raises(ValueError, match="short.csv:2: 3 cells, the header names 4"):
        batch.read_scenes(tmp_path / "short.csv")
    with pytest.raises(ValueError, match="cannot read scene table"):
        batch.read_scenes(tmp_path / "nope.csv")


def test_warnings_once_per_cause():
    rows = paper_scenes()
    rows.append(scene(10e-6, 0.8, 1e4, method="picard", max_iter=1))  # one sweep: not converged
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = fl.sweep(rows, "serial", progress=False, chunksize=5)
    kinds = [w.category for w in caught]
    causes = [c for c, _ in res.warnings]
    assert causes[:2] == ["failed", "not_converged"]
    assert kinds.count(batch.SceneFailureWarning) == 1 and kinds.count(ConvergenceWarning) == 1
    validity = [c for c in causes if c in _diagnostics.CAUSES]
    assert validity and kinds.count(ValidityWarning) == len(validity)
    assert "3 of 28 scenes failed (rows 5, 11, 17)" in res.warnings[0][1]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fl.sweep(rows, "serial", progress=False, chunksize=5, warn=False)
    assert not caught


# ---- command line ------------------------------------------------------------------------
def cli(argv) -> tuple[int, str, str]:
    from contextlib import redirect_stderr, redirect_stdout
    from io import StringIO

    from fastline.cli.app import main

    out, err = StringIO(), StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main([str(a) for a in argv])
    return status, out.getvalue(), err.getvalue()


SWEEP_ARGS = ["sweep", "--h-rms", "1e-6", "--n", N, "--loads-num", 24]


def test_cli_sweep_on_workers_and_scheduler(tmp_path, dask_client):
    """--workers 2, --workers 1 and --scheduler write the same file, byte for byte; it agrees
    with the in-process continuation sweep to the solver tolerance."""
    files = {}
    for name, extra in [
        ("pool", ["--workers", 2]),
        ("one", ["--workers", 1]),
        ("dask", ["--scheduler", dask_client.scheduler.address]),
        ("plain", []),
    ]:
        files[name] = tmp_path / f"{name}.csv"
        status, out, err = cli([*SWEEP_ARGS, *extra, "--chunksize", 5, "--csv", files[name]])
        assert status == 0, err
        warned = [ln for ln in err.splitlines() if ln.startswith("fastline: warning:")]
        assert len(warned) == len(set(warned)) >= 1  # once per cause
        assert "narrower than the longest roughness wavelength" in err
    text = {k: f.read_bytes() for k, f in files.items()}
    assert text["pool"] == text["one"] == text["dask"]
    _, a = read_csv(files["pool"])
    _, b = read_csv(files["plain"])
    assert np.array_equal(a["load_N_per_m"], b["load_N_per_m"])
    np.testing.assert_allclose(a["p0_ratio"], b["p0_ratio"], rtol=RTOL_CONTINUATION)


def test_cli_sweep_variant_on_workers(tmp_path):
    """--variant reaches the tasks: --workers 2 and --workers 1 write the same file, byte for
    byte; it agrees with the in-process sweep of that variant to the solver tolerance and
    moves p0 against the default variant's."""
    argv = ["sweep", "--h-rms", "1e-6", "--n", N, "--loads-num", 8, "--chunksize", 3]
    files = {}
    for name, extra in [
        ("pool", ["--workers", 2]),
        ("one", ["--workers", 1]),
        ("plain", []),
        ("default", ["--workers", 1]),
    ]:
        files[name] = tmp_path / f"{name}.csv"
        variant = [] if name == "default" else ["--variant", "yang-persson-printed"]
        status, _, err = cli([*argv, *variant, *extra, "--csv", files[name]])
        assert status == 0, err
    assert files["pool"].read_bytes() == files["one"].read_bytes()
    meta, a = read_csv(files["pool"])
    _, b = read_csv(files["plain"])
    _, c = read_csv(files["default"])
    assert meta["variant"] == "yang-persson-printed" and meta["gamma"] == "0.45"
    np.testing.assert_allclose(a["p0_ratio"], b["p0_ratio"], rtol=RTOL_CONTINUATION)
    assert np.max(a["p0_ratio"] / c["p0_ratio"]) > 1.0 + MIN_VARIANT_EFFECT


SPHERE_SWEEP_ARGS = ["sweep", "--geometry", "sphere", "--h-rms", "1e-6", "--n", N_SPHERE]
SPHERE_SWEEP_ARGS += ["--loads-num", 6, "--chunksize", 2]


def table_lines(out: str) -> list[str]:
    """The printed table of a sweep (after its header line)."""
    lines = out.splitlines()
    start = next(k for k, ln in enumerate(lines) if ln.lstrip().startswith("load"))
    return lines[start:]


def test_cli_sphere_sweep_on_workers_and_scheduler(tmp_path, dask_client, monkeypatch):
    """--geometry sphere with --workers 2, --workers 1 and --scheduler runs fastline.sweep on
    sphere scenes (it was ignored before) and writes the same file, byte for byte; the printed
    table is the serial sweep's, the file agrees with it to the solver tolerance."""
    calls = []

    def spy(scenes, executor=None, **kw):
        calls.append((set(scenes["geometry"]), executor, kw["workers"]))
        return real(scenes, executor, **kw)

    real = batch.sweep
    monkeypatch.setattr(fl, "sweep", spy)  # the name the CLI calls
    monkeypatch.setattr(batch, "sweep", spy)
    files, printed = {}, {}
    for name, extra in [
        ("pool", ["--workers", 2]),
        ("one", ["--workers", 1]),
        ("dask", ["--scheduler", dask_client.scheduler.address]),
        ("plain", []),
    ]:
        files[name] = tmp_path / f"{name}.csv"
        status, out, err = cli([*SPHERE_SWEEP_ARGS, *extra, "--csv", files[name]])
        assert status == 0, err
        printed[name] = table_lines(out)
        warned = [ln for ln in err.splitlines() if ln.startswith("fastline: warning:")]
        assert len(warned) == len(set(warned)) >= 1  # once per cause
    assert [(g, w) for g, _, w in calls] == [({"sphere"}, 2), ({"sphere"}, 1), ({"sphere"}, None)]
    assert calls[2][1] is not None  # the dask client
    text = {k: f.read_bytes() for k, f in files.items()}
    assert text["pool"] == text["one"] == text["dask"]
    assert printed["pool"] == printed["plain"] and len(printed["plain"]) == 7
    meta, a = read_csv(files["pool"])
    _, b = read_csv(files["plain"])
    assert meta["geometry"] == "sphere" and np.array_equal(a["load_N"], b["load_N"])
    for col in ("p0_Pa", "p0_ratio", "s_m", "w_m", "w_over_s", "alpha"):
        np.testing.assert_allclose(a[col], b[col], rtol=RTOL_CONTINUATION, err_msg=col)


def test_cli_sphere_sweep_plot_on_workers(tmp_path, monkeypatch):
    """The figure of a parallel sphere sweep draws the Hertz sphere's w/s, sqrt(15)."""
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    figures = []
    monkeypatch.setattr(cli_sphere, "save", lambda fig, path, args: figures.append(fig))
    status, _, err = cli([*SPHERE_SWEEP_ARGS, "--workers", 2, "--plot", tmp_path / "s.png"])
    assert status == 0, err
    ws_axes = figures[0].axes[0]
    levels = [ln.get_ydata()[0] for ln in ws_axes.get_lines() if len(set(ln.get_ydata())) == 1]
    assert any(np.isclose(y, np.sqrt(15.0)) for y in levels)
    plt.close(figures[0])


@pytest.mark.parametrize(
    "argv, message",
    [
        (["sweep", "--geometry", "ball", "--workers", 2], "--geometry: invalid choice: 'ball'"),
        (["sweep", "--geometry", "sphere", "--workers", 0], "--workers: must be >= 1"),
    ],
)
def test_cli_sphere_sweep_bad_options(argv, message):
    status, _, err = cli(argv)
    assert status == 2 and message in err


def test_cli_batch_geometry_column(tmp_path):
    """A geometry column in a batch file: sphere rows (load in N) are PointContact solves; an
    unknown geometry refuses the file (exit 2, naming the column and row)."""
    header = "label,h_rms,hurst,q0,qr,q1,E_star,radius,geometry,load,n"
    lines = [header, f"c,1e-6,0.8,1e3,1e4,1e9,{E_STAR},{RADIUS},,1e4,{N}"]
    lines += [f"s,1e-6,0.8,1e3,1e4,1e9,{E_STAR},{RADIUS},sphere,0.3,{N_SPHERE}"]
    (tmp_path / "scenes.csv").write_text("\n".join(lines) + "\n")
    status, _, err = cli(["batch", tmp_path / "scenes.csv", "--out", tmp_path / "out.csv"])
    assert status == 0, err
    meta, cols = read_csv(tmp_path / "out.csv")
    assert list(cols["geometry"]) == ["cylinder", "sphere"] and "load" in cols
    assert cols["p0_Pa"][1] == point_contact().solve(0.3).p0
    (tmp_path / "bad.csv").write_text(
        "\n".join([lines[0], lines[1], lines[2].replace("sphere", "ball")])
    )
    status, _, err = cli(["batch", tmp_path / "bad.csv", "--out", tmp_path / "bad_out.csv"])
    assert status == 2 and "column 'geometry' must be one of ('cylinder', 'sphere'); row 1" in err
    assert not (tmp_path / "bad_out.csv").exists()


def test_cli_batch_variant_column(tmp_path):
    """A variant column in a batch file: the rows equal fl.sweep of the same scenes; an
    unknown variant refuses the file (exit 2, naming the column)."""
    header = "label,h_rms,hurst,q0,qr,q1,E_star,radius,load,n,variant,gamma"
    cells = ["yang-persson-printed,", "wang-mueser,", ",", "wang-mueser,0.5"]
    lines = [header] + [
        f"s{k},1e-6,0.8,1e3,1e4,1e9,1.33e9,0.01,1e5,{N},{c}" for k, c in enumerate(cells)
    ]
    (tmp_path / "scenes.csv").write_text("\n".join(lines) + "\n")
    status, _, err = cli(["batch", tmp_path / "scenes.csv", "--out", tmp_path / "out.csv"])
    assert status == 0, err
    _, cols = read_csv(tmp_path / "out.csv")
    names = ["yang-persson-printed", "wang-mueser", "yang-persson-energy", "wang-mueser"]
    assert list(cols["variant"]) == names
    assert list(cols["gamma"]) == [0.45, 5.0 / 9.0, 0.45, 0.5]
    ref = run(batch.read_scenes(tmp_path / "scenes.csv"))
    assert list(ref["variant"]) == names
    assert np.array_equal(cols["p0_Pa"], ref["p0"]) and len(set(ref["p0"])) == 4
    (tmp_path / "bad.csv").write_text(header + "\nx,1e-6,0.8,1e3,1e4,1e9,1.33e9,0.01,1e5,96,wm,\n")
    status, _, err = cli(["batch", tmp_path / "bad.csv", "--out", tmp_path / "bad_out.csv"])
    assert status == 2 and "column 'variant' must be one of" in err
    assert not (tmp_path / "bad_out.csv").exists()


def test_cli_batch(tmp_path):
    lines = ["label,h_rms,hurst,q0,qr,q1,E_star,radius,load_N_per_m,n"]
    for k, f in enumerate(np.geomspace(1e3, 1e6, 11)):
        lines.append(f"s{k},1e-6,0.8,1e3,1e4,1e9,1.33e9,0.01,{float(f)!r},{N}")
    lines.append("bad,1e-6,1.5,1e3,1e4,1e9,1.33e9,0.01,1e4,96")
    (tmp_path / "scenes.csv").write_text("\n".join(lines) + "\n")
    outs = []
    for workers in (2, 1):
        outs.append(tmp_path / f"out{workers}.csv")
        argv = ["batch", tmp_path / "scenes.csv", "--out", outs[-1], "--workers", workers]
        status, out, err = cli(argv)
        assert status == 1  # a scene failed; the others are written
        assert "12 scenes" in out and "11 converged, 0 not converged, 1 failed" in out
        assert "1 of 12 scenes failed (rows 11)" in err and "hurst must lie in" in err
    assert outs[0].read_bytes() == outs[1].read_bytes()
    meta, cols = read_csv(outs[0])
    assert meta["failed"] == "1" and list(cols["label"][:2]) == ["s0", "s1"]
    assert cols["error"][11].startswith("ValueError: hurst must lie in (0, 1]")  # quoted
    assert np.all(cols["converged"][:11] == 1)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--workers", 2, "--scheduler", "tcp://127.0.0.1:1"], "either --workers or --scheduler"),
        (["--workers", 0], "--workers: must be >= 1"),
        (["--chunksize", "x"], "--chunksize: not an integer"),
        (["--workers", 2, "--variant", "printed"], "--variant: invalid choice: 'printed'"),
    ],
)
def test_cli_parallel_options_refused(argv, message, tmp_path):
    status, out, err = cli([*SWEEP_ARGS, *argv, "--csv", tmp_path / "s.csv"])
    assert status == 2 and message in err and not (tmp_path / "s.csv").exists()


def test_cli_batch_refuses_bad_tables_before_work(tmp_path, monkeypatch):
    (tmp_path / "bad.csv").write_text("h_rms,hurst,q0,qr,q1,E_star,radius,load,mu\n")
    (tmp_path / "typo.csv").write_text("psd,E_star,radius,load\na.txt,1.33e9,0.01,heavy\n")
    for name, message in [
        ("bad.csv", "need a header row and at least one scene"),
        ("typo.csv", "column 'load' must hold a real number; row 0 holds 'heavy'"),
        ("missing.csv", "cannot read scene table"),
    ]:
        status, _, err = cli(["batch", tmp_path / name, "--out", tmp_path / "r.csv"])
        assert status == 2 and message in err, err
    assert not (tmp_path / "r.csv").exists()
    monkeypatch.setitem(__import__("sys").modules, "distributed", None)
    status, _, err = cli([*SWEEP_ARGS, "--scheduler", "tcp://127.0.0.1:1"])
    assert status == 2 and '"fastline-contact[dask]" (the dask extra)' in err


# ---- when the default pool starts ---------------------------------------------------------------
def test_small_table_runs_here_without_a_pool():
    """A few scenes and no ``workers``: solved in this process (a pool's start-up took 5x the
    whole serial sweep of 3 scenes); ``workers`` given: the pool as asked."""
    rows = [scene(1e-6, 0.8, 1e4), scene(10e-6, 0.8, 1e4), scene(10e-6, 0.5, 1e4)]
    res = run(rows, chunksize=1)  # 3 tasks: before, a pool of one process per CPU
    assert res.stats.executor.startswith("serial") and res.stats.workers == 1


def test_pool_pays_from_the_stated_work():
    """The rule of docs/sweeps.md: cylinder scenes at n = 1024 weigh 1, each distinct model
    POOL_THEORY_WORK more; the pool from POOL_MIN_WORK on."""
    from fastline.batch.plan import POOL_MIN_WORK, POOL_THEORY_WORK, plan_tasks, pool_pays
    from fastline.batch.scenes import normalise

    def pays(rows, models, n=1024):
        loads = np.geomspace(1e3, 1e5, rows)
        table = [{**scene(1e-6 * (1 + i % models), 0.8, f), "n": n} for i, f in enumerate(loads)]
        return pool_pays(plan_tasks(normalise(table), 64))

    big = int(POOL_MIN_WORK - POOL_THEORY_WORK)
    assert pays(big, 1) and not pays(big - 1, 1)
    assert not pays(big, 1, n=512)  # half the work per scene
    many = int(POOL_MIN_WORK // (POOL_THEORY_WORK + 1)) + 1
    assert pays(many, many) and not pays(many, 1)


# ---- tabulated and calibrated laws in the table (the law column) ---------------------------------
LAW_E, LAW_R = 10e6, 0.0328  # the narrow-band validation scene (docs/validation.md)
LAW_Q0 = 2 * np.pi / 40e-6
LAW_SPECTRUM = dict(h_rms=0.5e-6, hurst=0.8, q0=LAW_Q0, qr=LAW_Q0, q1=4 * LAW_Q0)
LAW_PSD = fl.SelfAffinePSD(**LAW_SPECTRUM)
LAW_LOADS = (1.0, 3.0, 10.0)  # N/m: alpha ~ 4, 1.3, 0.4
#: least change of p0 between the laws of the table (u 0.8x, 1.5x Persson's: expected several %)
MIN_LAW_EFFECT = 0.03


def law_scene(load, **extra) -> dict:
    return {**LAW_SPECTRUM, "E_star": LAW_E, "radius": LAW_R, "load": load, "n": N, **extra}


@pytest.fixture(scope="module")
def laws(tmp_path_factory):
    """A calibrated law (points on 0.8x Persson's u), saved to a file, and a tabulated law
    (1.5x Persson's u), both of the narrow-band scene."""
    from fastline.theory.calibrated import CalibrationPoints

    th = fl.PerssonTheory(LAW_PSD, LAW_E)
    p = np.geomspace(1e2, 1e5, 9)
    u, g, a = th.separation(p), th.critical_gap(p).u_c, th.contact_area(p)
    points = CalibrationPoints(p, 0.8 * u, 0.008 * u, a, 0 * p, g, 0.02 * g, g, 0.02 * g)
    calibrated = fl.CalibratedLaw(points, LAW_PSD, LAW_E)
    path = tmp_path_factory.mktemp("laws") / "law.npz"
    calibrated.save(path)
    tabulated = fl.TabulatedLaw(1.5 * u, p, real_area=a)
    return dict(calibrated=calibrated, tabulated=tabulated, file=str(path), theory=th)


def law_table(laws) -> list[dict]:
    """Each load with the calibrated law (object and file), the tabulated law, Persson's and
    the exponential law, shuffled; a sphere with the law; then three rows that must fail: a
    missing law file, a file whose checksum is not the table's, a calibrated law at another
    E*."""
    rows = []
    for f in LAW_LOADS:
        rows += [law_scene(f, law=laws["calibrated"], label="calibrated")]
        rows += [law_scene(f, law=laws["file"], label="file")]
        rows += [law_scene(f, law=laws["tabulated"], label="tabulated")]
        rows += [law_scene(f, label="persson"), law_scene(f, model="exponential", label="exp")]
    rows = [rows[i] for i in np.random.default_rng(1).permutation(len(rows))]
    rows.append(law_scene(0.01, law=laws["calibrated"], geometry="sphere", n=N_SPHERE))
    wrong = f"{laws['file']}@sha256:{'0' * 64}"
    rows += [law_scene(3.0, law=laws["file"] + ".missing"), law_scene(3.0, law=wrong)]
    rows += [law_scene(3.0, law=laws["calibrated"], E_star=2 * LAW_E)]
    return rows


@pytest.fixture(scope="module")
def law_serial(laws):
    return run(law_table(laws), chunksize=4)


def test_law_rows_are_their_laws_solves(law_serial, laws):
    """Each law row is LineContact(psd, E*, R, model=law) over its piece, bit for bit (the
    law's theory gives the diagnostics); the file and the object give the same rows; the
    laws move p0 against each other and against Persson's."""
    res = law_serial
    label = res["label"]
    kw = dict(n=N, theory=laws["theory"], warn=False)
    for name, law in [("calibrated", laws["calibrated"]), ("file", laws["calibrated"]),
                      ("tabulated", laws["tabulated"])]:  # fmt: skip
        rows = np.flatnonzero(label == name)
        rows = rows[np.argsort(res["load"][rows])]
        want = fl.LineContact(LAW_PSD, LAW_E, LAW_R, model=law, **kw).sweep(LAW_LOADS)
        assert_rows_are(res, rows, want)
        assert set(res["model"][rows]) == {"tabulated" if name == "tabulated" else "calibrated"}
    p0 = {k: np.sort(res["p0"][label == k]) for k in ("calibrated", "tabulated", "persson")}
    assert np.min(np.abs(p0["calibrated"] / p0["persson"] - 1)) > MIN_LAW_EFFECT
    assert np.min(np.abs(p0["tabulated"] / p0["persson"] - 1)) > MIN_LAW_EFFECT
    sphere = int(np.flatnonzero(res["geometry"] == "sphere")[0])
    kw["n"] = N_SPHERE
    pc = fl.PointContact(LAW_PSD, LAW_E, LAW_R, model=laws["calibrated"], **kw)
    assert_rows_are(res, [sphere], [pc.solve(0.01)])


def test_law_rows_that_cannot_be_solved_fail_by_name(law_serial, laws):
    errors = list(law_serial["error"][-3:])
    assert errors[0].startswith("FileNotFoundError: law file ") and "no such file on" in errors[0]
    assert laws["file"] + ".missing" in errors[0] and "give the law object" in errors[0]
    assert errors[1].startswith("CalibrationFileError: law file ")
    assert "is not the law of the table" in errors[1] and "0000000000000000..." in errors[1]
    assert "calibrated for E* = 1e+07 Pa, not 2e+07 Pa" in errors[2]
    assert (law_serial["error"][:-3] == "").all()


def test_law_rows_on_a_process_pool_equal_serial(law_serial, laws, pool):
    """The law objects travel as arrays, the file is read by each worker: the same numbers
    and the same failures, bit for bit (a worker that used another law would move p0)."""
    assert_same_table(run(law_table(laws), pool, chunksize=4), law_serial)


def test_law_rows_on_dask_equal_serial(law_serial, laws, dask_client):
    assert_same_table(run(law_table(laws), dask_client, chunksize=4), law_serial)


def test_law_travels_once_per_task_as_arrays(laws):
    """A task of six pieces (six radii) with one calibrated law pickles the law's arrays
    once, and no law object (its class is not in the message)."""
    from fastline.batch.plan import plan_tasks
    from fastline.batch.scenes import normalise
    from fastline.theory.lawdata import law_data

    rows = [law_scene(f, law=laws["calibrated"], radius=r) for r in np.geomspace(0.01, 0.1, 6)
            for f in LAW_LOADS]  # fmt: skip
    (task,) = plan_tasks(normalise(rows), 64)
    assert len(task) == 6 and len({id(p.spec.law_data) for p in task}) == 1
    message = pickle.dumps(task)
    one = len(pickle.dumps(law_data(laws["calibrated"])))
    assert one < len(message) < one + 6 * 1000 and b"CalibratedLaw" not in message


def test_law_data_restores_the_same_law(laws, tmp_path):
    """The data of a law rebuild it bit for bit; a calibrated law's data are its file's."""
    from fastline.theory.lawdata import law_data, read_law_file, restore_law

    v = np.linspace(np.log(1.0), np.log(1e7), 513)
    u = np.geomspace(1e-9, 1e-5, 257)
    for name in ("calibrated", "tabulated"):
        law, again = laws[name], restore_law(law_data(laws[name]))
        assert type(again) is type(law)
        for a, b in zip(law.separation_and_slope(v), again.separation_and_slope(v), strict=True):
            assert np.array_equal(a, b), name
        assert np.array_equal(law.log_pressure(u), again.log_pressure(u)), name
        assert np.array_equal(law.real_area(np.exp(v)), again.real_area(np.exp(v))), name
    assert read_law_file(laws["file"]).checksum == law_data(laws["calibrated"]).checksum
    with pytest.raises(TypeError, match="only a TabulatedLaw or a CalibratedLaw"):
        law_data(fl.ExponentialLaw(1e-7, 0.4, LAW_E))


@pytest.mark.parametrize(
    "extra, error, match",
    [
        (dict(law="LAW", model="exponential"), ValueError,
         r"row 0 has a law and model='exponential': the law replaces the model"),
        (dict(model="calibrated"), ValueError, r"row 0 has model='calibrated' but no law"),
        (dict(law="EXP"), TypeError, r"column 'law' must hold a TabulatedLaw, a CalibratedLaw"),
        (dict(model="LAW"), TypeError, r"a CalibratedLaw or a law file goes in the law column"),
    ],
)  # fmt: skip
def test_law_beside_another_model_is_refused(laws, extra, error, match):
    cells = {"LAW": laws["calibrated"], "EXP": fl.ExponentialLaw(1e-7, 0.4, LAW_E)}
    extra = {k: cells.get(v, v) for k, v in extra.items()}
    with pytest.raises(error, match=match):
        fl.sweep([law_scene(1.0, **extra)], "serial", progress=False)


def test_law_csv_round_trip(laws, law_serial, tmp_path):
    """A law file is written as its path and checksum and read back (read_scenes): the table
    runs again to the same numbers; a file changed since fails its rows by name; a law object
    has no file and is refused on reading."""
    from fastline.theory.lawdata import read_law_file

    law_serial.to_csv(tmp_path / "objects.csv")
    _, cols = read_csv(tmp_path / "objects.csv")
    checksum = read_law_file(laws["file"]).checksum
    assert f"{laws['file']}@sha256:{checksum}" in list(cols["law"])
    assert f"<law object CalibratedLaw sha256:{checksum}>" in list(cols["law"])
    with pytest.raises(ValueError, match=r"objects.csv:\d+: the law of this row was a law object"):
        batch.read_scenes(tmp_path / "objects.csv")
    path = tmp_path / "law.npz"
    laws["calibrated"].save(path)
    rows = [law_scene(f, law=str(path)) for f in LAW_LOADS] + [law_scene(1.0)]
    first = run(rows, chunksize=2)
    first.to_csv(tmp_path / "files.csv")
    assert_same_table(run(batch.read_scenes(tmp_path / "files.csv"), chunksize=2), first)
    other = fl.CalibratedLaw(laws["calibrated"].points, LAW_PSD, LAW_E, settings={"k": 1})
    other.save(path)  # the same numbers, another file: its checksum differs
    again = run(batch.read_scenes(tmp_path / "files.csv"), chunksize=2)
    assert again.failed.tolist() == [True] * 3 + [False]
    assert "is not the law of the table" in again["error"][0]


def law_cli_args(law_file) -> list:
    spectrum = [f"--{k.replace('_', '-')}={v!r}" for k, v in LAW_SPECTRUM.items()]
    return ["sweep", *spectrum, "--E-star", LAW_E, "--radius", LAW_R, "--n", N, "--loads-from",
            1, "--loads-to", 10, "--loads-num", 6, "--chunksize", 2, "--law", law_file]  # fmt: skip


def test_cli_sweep_law_on_workers_and_scheduler(laws, tmp_path, pool, dask_client, monkeypatch):
    """sweep --law with --workers 2 (the module's pool), --workers 1 and --scheduler writes
    the same file, byte for byte; it agrees with the in-process --law sweep to the solver
    tolerance and differs from Persson's; a law for another E* is refused before any work."""
    real = batch.sweep

    def on_pool(scenes, executor=None, **kw):
        assert scenes["law"][0] is not None and isinstance(scenes["law"][0], fl.CalibratedLaw)
        if executor is None and kw["workers"] == 2:
            executor, kw["workers"] = pool, None
        return real(scenes, executor, **kw)

    monkeypatch.setattr(fl, "sweep", on_pool)
    files = {}
    address = dask_client.scheduler.address
    for name, extra in [("pool", ["--workers", 2]), ("one", ["--workers", 1]),
                        ("dask", ["--scheduler", address]), ("plain", [])]:  # fmt: skip
        files[name] = tmp_path / f"{name}.csv"
        status, out, err = cli([*law_cli_args(laws["file"]), *extra, "--csv", files[name]])
        assert status == 0, err
    text = {k: f.read_bytes() for k, f in files.items()}
    assert text["pool"] == text["one"] == text["dask"]
    meta, a = read_csv(files["pool"])
    _, b = read_csv(files["plain"])
    assert meta["model"] == "calibrated" and meta["law_file"] == laws["file"]
    np.testing.assert_allclose(a["p0_Pa"], b["p0_Pa"], rtol=RTOL_CONTINUATION)
    monkeypatch.setattr(fl, "sweep", real)
    argv = law_cli_args(laws["file"])
    status, _, err = cli([*argv[:-2], "--workers", 1, "--csv", tmp_path / "persson.csv"])
    _, c = read_csv(tmp_path / "persson.csv")
    assert status == 0 and np.min(np.abs(a["p0_Pa"] / c["p0_Pa"] - 1)) > MIN_LAW_EFFECT
    argv[argv.index("--E-star") + 1] = 2 * LAW_E
    status, _, err = cli([*argv, "--workers", 2, "--csv", tmp_path / "no.csv"])
    assert status == 2 and "calibrated for E* = 1e+07 Pa, not 2e+07 Pa" in err
    assert not (tmp_path / "no.csv").exists()


def test_cli_batch_law_column_and_default(laws, tmp_path):
    """batch: a law column (relative to the CSV file) and --law for the rows that name
    neither a model nor a law; the rows equal fl.sweep of the same scenes with those laws; a
    default law for another E* is refused before any work."""
    import shutil

    shutil.copy(laws["file"], tmp_path / "law.npz")
    shutil.copy(laws["file"], tmp_path / "default.npz")
    spectrum = ",".join(repr(v) for v in LAW_SPECTRUM.values())
    lines = ["label,h_rms,hurst,q0,qr,q1,E_star,radius,load,n,model,law"]
    for label, model, law in [("column", "", "law.npz"), ("default", "", ""),
                              ("persson", "persson", "")]:  # fmt: skip
        lines.append(f"{label},{spectrum},{LAW_E},{LAW_R},3.0,{N},{model},{law}")
    (tmp_path / "scenes.csv").write_text("\n".join(lines) + "\n")
    argv = ["batch", tmp_path / "scenes.csv", "--out", tmp_path / "out.csv"]
    status, _, err = cli([*argv, "--law", tmp_path / "default.npz"])
    assert status == 0, err
    _, cols = read_csv(tmp_path / "out.csv")
    assert list(cols["model"]) == ["calibrated", "calibrated", "persson"]
    assert cols["law"][1].startswith(str(tmp_path / "default.npz") + "@sha256:")
    want = run([law_scene(3.0, law=laws["calibrated"]), law_scene(3.0)])
    assert np.array_equal(cols["p0_Pa"], want["p0"][[0, 0, 1]])
    (tmp_path / "named.csv").write_text(lines[0] + "\n" + lines[3] + "\n")
    status, _, err = cli(["batch", tmp_path / "named.csv", "--out", tmp_path / "no.csv",
                          "--law", tmp_path / "default.npz"])  # fmt: skip
    assert status == 2 and "every row names a model or a law" in err
    (tmp_path / "other.csv").write_text(lines[0] + "\n" + lines[2].replace(f",{LAW_E},", ",2e7,"))
    argv = ["batch", tmp_path / "other.csv", "--out", tmp_path / "no.csv"]
    status, _, err = cli([*argv, "--law", tmp_path / "default.npz"])
    assert status == 2 and "calibrated for E* = 1e+07 Pa, not 2e+07 Pa" in err, err
    assert not (tmp_path / "no.csv").exists()
