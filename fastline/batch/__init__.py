"""Sweeps of many scenes on a process pool or a dask.distributed cluster: :func:`sweep`.

A *scene* is one solve: a roughness spectrum, an effective modulus, a geometry (a cylinder of
radius R, ``geometry="cylinder"``, solved by :class:`~fastline.LineContact`, or a sphere,
``geometry="sphere"``, solved by :class:`~fastline.PointContact`), a load and the solver
settings. :func:`sweep` takes a table of scenes (a list of dicts, a dict of columns, a NumPy
structured array or a pandas DataFrame; the columns are listed in :data:`SCENE_COLUMNS`), runs
it on any :class:`concurrent.futures.Executor` and returns a :class:`SweepTable`: one row per
scene, in the order given, with the inputs and the results.

How the work is cut (the *plan*):

1. scenes are grouped by *model*: everything but the load (spectrum, E*, geometry and its
   size, model, law, method, n, gamma, variant, tol, max_iter, hardness);
2. the scenes of a group are ordered by load and cut into *pieces* of at most ``chunksize``
   scenes; a piece is solved by one ``sweep`` of its model (continuation along its loads);
3. pieces are packed, in table order, into *tasks* of at most ``chunksize`` scenes: a task is
   what an executor receives (one pickle, one scheduling step).

The plan depends on the table and ``chunksize`` only, never on the executor, so a process
pool, a dask cluster and ``executor="serial"`` give the same numbers bit for bit. (A different
``chunksize`` changes the continuation starts, hence the results within the solver tolerance.)

Workers keep spectra, Persson theories and models in a per-process cache keyed by their
parameters (least recently used entries dropped beyond :data:`CACHE_SIZES`): scenes sharing a
spectrum and material share one theory per worker process, whichever task brings them, and
whichever geometry they have.

Failures stay in their rows: bad values (a Hurst exponent of 1.5, a load out of range, a
spectrum file that cannot be read) and exceptions inside a worker become the row's ``error``
text; the sweep always completes. The table's shape and types (column names, value types,
geometry/model/method names) are checked before any work and raise.

SI units throughout: m, 1/m, Pa; loads in N/m (per unit length) for a cylinder, in N (the
total load) for a sphere.

A tabulated or calibrated law (the ``law`` column: a law object or a law file) travels to the
workers as arrays, once per task, or is read there from its file, checksum checked
(:mod:`~fastline.batch.laws`).

Modules, each importing only those listed before it: :mod:`~fastline.batch.laws` (the law
column: cells, their text, their keys), :mod:`~fastline.batch.scenes` (the
columns, the geometries, checking a table, :func:`read_scenes`), :mod:`~fastline.batch.plan`
(groups, pieces, tasks), :mod:`~fastline.batch.worker` (the per-process cache, what a task
does, the loop over an executor), :mod:`~fastline.batch.table` (:class:`SweepTable`,
:class:`SweepStats`, the warnings) and :mod:`~fastline.batch.run` (:func:`sweep`).

>>> import fastline as fl
>>> scenes = [dict(h_rms=1e-6, hurst=0.8, q0=1e3, qr=1e4, q1=1e9, E_star=1.33e9,
...                radius=0.01, load=f, n=128) for f in (1e3, 1e4, 1e5)]
>>> res = fl.sweep(scenes, "serial", progress=False)
>>> res["p0"], res["w_over_s"]  # doctest: +SKIP
"""

from __future__ import annotations

import lazy_loader as _lazy

from fastline.errors import SceneFailureWarning

#: what the other subpackages may use, by the module that defines it (loaded on first use)
__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submod_attrs={
        "plan": ["DEFAULT_TASKS", "MAX_CHUNK", "MIN_CHUNK", "default_chunksize"],
        "run": ["sweep"],
        "scenes": ["GEOMETRIES", "LOAD_UNITS", "RESULT_COLUMNS", "SCENE_COLUMNS", "read_scenes"],
        "table": ["SweepStats", "SweepTable"],
        "worker": ["CACHE_SIZES"],
    },
)
__all__ += ["SceneFailureWarning"]
