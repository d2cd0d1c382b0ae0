"""fastline: nominal contact pressure of a cylinder or a sphere on a randomly rough elastic
half-space, with Persson's contact theory.

Full Persson contact theory (compiled with Numba) and fast line- and point-contact solvers
(log-kernel convolution by zero-padded FFT; an axisymmetric ring operator), from measured
spectra to seal leak rates. See README.md and docs/ (docs/architecture.md for the layout).

The public names are listed once, in ``__init__.pyi`` beside this file; each loads its
subpackage on first access (SPEC 1 lazy loading), so ``import fastline`` compiles nothing and
imports neither matplotlib nor dask.
"""

from __future__ import annotations

import lazy_loader as _lazy

from fastline._lib.version import __version__ as __version__

_lazy_getattr, __dir__, __all__ = _lazy.attach_stub(__name__, __file__)


def __getattr__(name: str) -> object:
    if name not in __all__:
        raise AttributeError(f"module 'fastline' has no attribute {name!r}")
    return _lazy_getattr(name)
