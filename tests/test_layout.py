"""The package's layout holds: layers that import only downwards, no import circles, no private
names across subpackages, readable units (docs/architecture.md).

The layering itself is import-linter's contracts in pyproject.toml (run here as the command
``lint-imports``). The other counts come from the package's own import statements, read with
:mod:`ast`: every import, including those inside function bodies; imports under
``if TYPE_CHECKING:`` are annotations, not dependencies, and are left out (as the contracts
leave them out).
"""

from __future__ import annotations

import ast
import os
import shutil
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

import pytest

import fastline

PACKAGE = Path(fastline.__file__).parent
ROOT = Path(__file__).resolve().parents[1]

#: readable units
MAX_FUNCTION_LINES = 60  # a def, its docstring included
MAX_KERNEL_PARAMETERS = 10
MAX_MODULE_LINES = 750  # "about 700"

LAZY_IMPORTS = (
    "matplotlib",
    "mpl_toolkits",
    "dask",
    "distributed",
    "pandas",
    "SurfaceTopography",
    "scipy",
    "tqdm",
    "multiprocessing",
    "pyfftw",
)


def _modules() -> dict[str, Path]:
    mods = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        name = ".".join(rel.parts)
        mods[name.removesuffix(".__init__")] = path
    return mods


MODULES = _modules()


def _parents(tree: ast.AST) -> dict:
    return {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}


def _enclosing(node, parents, kinds) -> ast.AST | None:
    while node in parents:
        node = parents[node]
        if isinstance(node, kinds):
            return node
    return None


def _type_checking(node, parents) -> bool:
    while node in parents:
        node = parents[node]
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            return True
    return False


def _target(module: str, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".")
    if not MODULES[module].name == "__init__.py":
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports():
    """(importer, imported module, name or None, inside a function) of every import."""
    for module, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        parents = _parents(tree)
        for node in ast.walk(tree):
            if not isinstance(node, ast.Import | ast.ImportFrom) or _type_checking(node, parents):
                continue
            inside = _enclosing(node, parents, ast.FunctionDef | ast.AsyncFunctionDef) is not None
            if isinstance(node, ast.Import):
                for alias in node.names:
                    yield module, alias.name, None, inside
                continue
            target = _target(module, node)
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in MODULES:
                    yield module, sub, None, inside
                else:
                    yield module, target, alias.name, inside


IMPORTS = list(_imports())


def _subpackage(module: str) -> str:
    return ".".join(module.split(".")[:2])


def _cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return found


def test_import_contracts_hold():
    """import-linter's layers, independence and forbidden contracts (pyproject.toml)."""
    exe = shutil.which("lint-imports") or os.path.join(
        os.path.dirname(sys.executable), "lint-imports"
    )
    if not os.path.exists(exe):
        pytest.skip("import-linter is not installed (the test extra)")
    run = subprocess.run([exe], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "0 broken" in run.stdout


def test_no_import_circles_between_modules():
    edges = defaultdict(set)
    for importer, imported, _, _ in IMPORTS:
        if imported in MODULES and imported != importer:
            edges[importer].add(imported)
    edges.pop("fastline", None)  # the package's lazy face imports nothing at run time
    assert _cycles(edges) == []


def test_no_private_names_across_subpackages():
    crossing = sorted(
        (importer, f"{imported}.{name}")
        for importer, imported, name, _ in IMPORTS
        if imported.startswith("fastline")
        and name is not None
        and name.startswith("_")
        and not name.startswith("__")
        and _subpackage(importer) != _subpackage(imported)
    )
    assert crossing == []


def test_no_fastline_imports_inside_functions():
    """fastline's own modules are imported at module top, where a reader sees the dependencies
    (a subpackage loads lazily through its ``__init__``); third-party imports inside functions
    remain for optional dependencies and for start-up cost, each with its comment."""
    inside = sorted(
        (importer, imported)
        for importer, imported, _, is_inside in IMPORTS
        if is_inside and imported.split(".")[0] == "fastline"
    )
    assert inside == []


def test_functions_are_short():
    """Every function, its docstring included, fits in MAX_FUNCTION_LINES (a long one is split
    into named stages)."""
    long = []
    for module, path in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                lines = node.end_lineno - node.lineno + 1
                if lines > MAX_FUNCTION_LINES:
                    long.append((module, node.name, lines))
    assert long == []


def test_kernels_take_few_parameters():
    wide = []
    for module, path in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef):
                compiled = any("jit" in ast.unparse(d) for d in node.decorator_list)
                if compiled and len(node.args.args) > MAX_KERNEL_PARAMETERS:
                    wide.append((module, node.name, len(node.args.args)))
    assert wide == []


def test_modules_are_short():
    sizes = {m: len(p.read_text(encoding="utf-8").splitlines()) for m, p in MODULES.items()}
    assert {m: n for m, n in sizes.items() if n > MAX_MODULE_LINES} == {}


def test_the_public_api_is_listed_once_and_resolves():
    """Every name of the stub is in ``fastline.__all__`` and resolves; nothing else is."""
    stub = ast.parse((PACKAGE / "__init__.pyi").read_text(encoding="utf-8"))
    names = {
        a.asname or a.name for n in stub.body if isinstance(n, ast.ImportFrom) for a in n.names
    }
    assert names == set(fastline.__all__)
    for name in names:
        assert getattr(fastline, name) is not None


def test_import_fastline_is_light():
    code = "import sys, fastline; print(' '.join(sorted(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = set(out.stdout.split())
    assert not loaded & {"numba", "matplotlib", "dask", "scipy", "fastline.contact"}


def _interface(subpackage: str) -> set[str]:
    """The names a subpackage offers the others: its ``__all__`` (a lazy table or a module's)."""
    module = __import__(subpackage, fromlist=["__all__"])
    return set(getattr(module, "__all__", ()))


def test_siblings_use_what_a_subpackage_names():
    """A name imported from another subpackage is one its ``__init__`` names, or one of a public
    module it names (``fastline.reports.plotting``); ``_lib`` and ``errors`` hold shared
    plumbing, their modules' ``__all__`` are the interface."""
    outside = set()
    for importer, imported, name, _ in IMPORTS:
        theirs = _subpackage(imported)
        if not imported.startswith("fastline.") or theirs == _subpackage(importer):
            continue
        if theirs in ("fastline._lib", "fastline.errors", "fastline") or name is None:
            continue
        offered = _interface(theirs)
        public_module = imported.rsplit(".", 1)[-1] in offered  # e.g. fastline.reports.plotting
        if name not in offered and not (public_module and name in _interface(imported)):
            outside.add((importer, f"{imported}.{name}"))
    assert sorted(outside) == []
