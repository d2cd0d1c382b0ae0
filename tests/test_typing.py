"""The public API is typed: every public callable has annotations.

Public means: the names in ``fastline.__all__`` and in the ``__all__`` of every public
(non-underscore) submodule; for a class, its constructor, public methods, class and static
methods and properties, over the fastline classes of its MRO (inherited ones count once, where
they are defined). Each needs an annotation on every parameter except ``self``/``cls``
(``*args``/``**kwargs`` too) and a return annotation. Only presence is checked, with
``inspect.signature`` (no evaluation of the hints, no mypy).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import typing

import fastline

_DUNDERS_CHECKED = ("__init__", "__call__")


def _public_modules() -> list:
    mods = [fastline]
    for info in pkgutil.walk_packages(fastline.__path__, "fastline."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            mods.append(importlib.import_module(info.name))
    return mods


def _function(obj):
    """The Python function behind a numba dispatcher, or obj."""
    return getattr(obj, "py_func", obj)


def _class_members(cls: type):
    """(function, skip_first) for the public callables of a fastline class and its fastline
    bases (the first definition along the MRO wins, as attribute lookup does)."""
    seen = set()
    for klass in cls.__mro__:
        if not klass.__module__.startswith("fastline"):
            continue
        for name, attr in vars(klass).items():
            public = not name.startswith("_") or name in _DUNDERS_CHECKED
            if name in seen or not public:
                continue
            seen.add(name)
            if isinstance(attr, staticmethod):
                yield attr.__func__, False
            elif isinstance(attr, classmethod):
                yield attr.__func__, True
            elif isinstance(attr, property):
                if attr.fget is not None:
                    yield attr.fget, True
            elif inspect.isfunction(attr):
                yield attr, True


def public_callables() -> dict:
    """``{module.qualname: (function, skip_first)}`` of every public callable."""
    found = {}
    for mod in _public_modules():
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name)
            if inspect.ismodule(obj) or typing.get_origin(obj) is not None:  # modules, aliases
                continue
            if inspect.isclass(obj):
                if obj.__module__.startswith("fastline"):
                    items = list(_class_members(obj))
                else:
                    items = []
            elif callable(obj):
                items = [(_function(obj), False)]
            else:  # constants
                continue
            for func, skip_first in items:
                if (func.__module__ or "").startswith("fastline"):
                    found[f"{func.__module__}.{func.__qualname__}"] = (func, skip_first)
    return found


def missing_annotations(func, skip_first: bool) -> list[str]:
    """Names of the parameters without an annotation, plus "return" if that has none."""
    sig = inspect.signature(func)
    params = list(sig.parameters.values())[1 if skip_first else 0 :]
    out = [p.name for p in params if p.annotation is inspect.Parameter.empty]
    if sig.return_annotation is inspect.Signature.empty:
        out.append("return")
    return out


def _offenders() -> dict[str, list[str]]:
    found = {}
    for key, (func, skip_first) in public_callables().items():
        miss = missing_annotations(func, skip_first)
        if miss:
            found[key] = miss
    return found


def test_walker_sees_the_public_api():
    """The walk reaches the main entry points (a walker finding nothing passes)."""
    keys = public_callables()
    for name in (
        "fastline.theory.spectra.SelfAffinePSD.__init__",
        "fastline.theory.spectra.PSD.cumulative",
        "fastline.theory.spectra.TabulatedPSD.__call__",
        "fastline.theory.interface.InterfaceStatistics.critical_gap",
        "fastline.theory.tables.pressure_at",
        "fastline.theory.laws.TabulatedLaw.separation_and_slope",
        "fastline.theory.asperity.GreenwoodWilliamsonLaw.real_area",
        "fastline.leakage.flow.leak_rate",
        "fastline.surfaces.profiles.psd_from_profile",
        "fastline.surfaces.scan.analyse_scan",
        "fastline.contact.figure.plot_profile",
        "fastline.contact.line.profile",
    ):
        assert name in keys, name
    assert len(keys) > 150


def test_missing_annotations_detects_gaps():
    """The check itself can fail: unannotated parameters and returns are reported."""

    def bare(self, a, b: int, *args, **kw):
        return None

    def typed(a: int, *args: float, **kw: str) -> None:
        return None

    assert missing_annotations(bare, True) == ["a", "args", "kw", "return"]
    assert missing_annotations(typed, False) == []


def test_public_api_is_annotated():
    offenders = _offenders()
    lines = [f"  {k}: {', '.join(v)}" for k, v in sorted(offenders.items())]
    assert not offenders, (
        f"{len(offenders)} public callables lack annotations (parameter names, 'return'):\n"
        + "\n".join(lines)
    )
