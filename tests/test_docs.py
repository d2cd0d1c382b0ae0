"""Every code block in README.md and docs/*.md runs as written.

Rules (also stated in docs/usage.md's neighbourhood by example):

* ```` ```python ```` blocks are executed, each in a fresh namespace, in a temporary directory
  that holds a copy of ``examples/`` (so ``"examples/psd_example.txt"`` resolves and the files
  a block writes do not land in the repository).
* In ```` ```bash ```` blocks, each command that starts with ``fastline`` or
  ``.venv/bin/fastline`` is run in-process through :func:`fastline.cli.app.main` and must exit 0;
  other lines (``pip``, ``python -m venv``, ``pytest``, comments) are not run here: CI runs the
  README's set-up commands verbatim (``.ci/run``, checked below).
* A block preceded by the line ``<!-- docs-test: skip -->`` is not run.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import warnings
from contextlib import redirect_stderr, redirect_stdout
from io import StringIO

import pytest

from fastline.cli.app import main

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAGES = ["README.md"] + sorted(
    os.path.join("docs", f) for f in os.listdir(os.path.join(ROOT, "docs")) if f.endswith(".md")
)
SKIP = "<!-- docs-test: skip -->"
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.MULTILINE | re.DOTALL)

pytest.importorskip("matplotlib")


def blocks(page: str):
    """(language, code, line number) of each fenced block of a page not marked to skip."""
    text = open(os.path.join(ROOT, page), encoding="utf-8").read()
    for m in FENCE.finditer(text):
        before = text[: m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        if before.strip() != SKIP:
            yield m.group(1), m.group(2), text[: m.start()].count("\n") + 1


def commands(code: str) -> list[str]:
    """The fastline commands of a bash block (continuation lines joined)."""
    joined = code.replace("\\\n", " ")
    out = []
    for line in joined.splitlines():
        line = line.split(" #", 1)[0].strip()
        if line.startswith(("fastline ", ".venv/bin/fastline ")):
            out.append(line)
    return out


CASES = [
    pytest.param(page, lang, code, id=f"{page}:{line}")
    for page in PAGES
    for lang, code, line in blocks(page)
    if lang == "python" or (lang == "bash" and commands(code))
]


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    shutil.copytree(os.path.join(ROOT, "examples"), tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("page, lang, code", CASES)
def test_code_block_runs(page, lang, code, in_tmp):
    out = StringIO()
    with redirect_stdout(out), redirect_stderr(out), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the blocks show warnings; they are tested elsewhere
        if lang == "python":
            # as a script: blocks that start worker processes guard them with __main__
            exec(compile(code, page, "exec"), {"__name__": "__main__"})
        else:
            for cmd in commands(code):
                status = main(shlex.split(cmd)[1:])
                assert status == 0, f"{cmd!r} exited {status}:\n{out.getvalue()[-2000:]}"


def test_every_page_has_checked_blocks():
    assert any(c.id.startswith("README.md") for c in CASES)
    assert any(c.id.startswith("docs/usage.md") for c in CASES)


def test_install_lines_name_this_project():
    """No install line in the repository installs another distribution (``fastline`` on the
    package index is an unrelated project)."""
    pat = re.compile(r"pip install\s+(?:-\S+\s+)*(\S+)")
    found = []
    for base, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if not d.startswith(".") and d not in ("build", "dist")]
        for f in files:
            if f.endswith((".md", ".py", ".toml", ".txt")) or f == "run":
                text = open(os.path.join(base, f), encoding="utf-8", errors="ignore").read()
                found += [(f, m.group(1)) for m in pat.finditer(text)]
    ci = open(os.path.join(ROOT, ".ci", "run"), encoding="utf-8").read()
    found += [("run", m.group(1)) for m in pat.finditer(ci)]
    allowed = re.compile(r"""^["']?(\.|fastline-contact)(\[[\w,]+\])?["']?$|^matplotlib\b""")
    bad = [(f, t) for f, t in found if not allowed.match(t.rstrip("`;,)."))]
    assert found and not bad, bad


def test_ci_runs_the_readme_setup_commands():
    readme = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()
    setup = readme[readme.index("## Set-up") :]
    lang, code = FENCE.search(setup).groups()
    assert lang == "bash"
    ci = open(os.path.join(ROOT, ".ci", "run"), encoding="utf-8").read().splitlines()
    lines = [ln for ln in code.splitlines() if ln.strip()]
    assert len(lines) == 2 and all(ln in ci for ln in lines)
    assert all(".venv/bin/" in ln for ln in lines)  # no activated venv needed


def skipped_python_blocks():
    """(page, line, code) of the python blocks marked not to run."""
    for page in PAGES:
        text = open(os.path.join(ROOT, page), encoding="utf-8").read()
        for m in FENCE.finditer(text):
            before = text[: m.start()].rstrip("\n").rsplit("\n", 1)[-1]
            if m.group(1) == "python" and before.strip() == SKIP:
                yield page, text[: m.start()].count("\n") + 1, m.group(2)


def _free_names(code: str, name: str) -> set[str]:
    """Names a block reads at module level (or as globals of its functions) but never binds."""
    import builtins
    import symtable

    top = symtable.symtable(code, name, "exec")
    bound = {s.get_name() for s in top.get_symbols() if s.is_assigned() or s.is_imported()}
    read, stack = set(), [top]
    while stack:
        table = stack.pop()
        stack += table.get_children()
        for s in table.get_symbols():
            if s.is_referenced() and (table is top or s.is_global()):
                read.add(s.get_name())
    return read - bound - set(dir(builtins))


def test_skipped_blocks_are_complete():
    """A block the test does not run (it needs a cluster, a licence, ...) still compiles and
    defines or imports every name it uses: a reader can paste it as it stands."""
    found = list(skipped_python_blocks())
    assert found
    for page, line, code in found:
        where = f"{page}:{line}"
        compile(code, where, "exec")
        assert not _free_names(code, where), (where, _free_names(code, where))


def test_sphere_signature_block_is_the_real_one():
    """The signature shown in docs/sphere.md is PointContact's (names, order, defaults)."""
    import ast
    import inspect

    import fastline as fl

    text = open(os.path.join(ROOT, "docs", "sphere.md"), encoding="utf-8").read()
    params = re.search(r"^fl\.PointContact(\(.*?\))$", text, re.MULTILINE | re.DOTALL).group(1)
    shown = ast.parse(f"def f{params}: pass").body[0].args
    real = inspect.signature(fl.PointContact).parameters
    names = [a.arg for a in shown.args] + [a.arg for a in shown.kwonlyargs]
    assert names == list(real)
    defaults = dict(zip([a.arg for a in shown.kwonlyargs], shown.kw_defaults, strict=True))
    for name, node in defaults.items():
        assert ast.literal_eval(node) == real[name].default, name
    assert [a.arg for a in shown.args] == [
        p.name for p in real.values() if p.kind is p.POSITIONAL_OR_KEYWORD
    ]


def test_docstring_references_resolve():
    """Every ``:class:`~fastline.x.Y``` (func, meth, mod, ...) in the package's source names
    something that exists."""
    import importlib

    pat = re.compile(r":(?:class|func|meth|mod|attr|data|exc|obj):`~?(fastline(?:\.\w+)+)`")
    missing = []
    for base, _dirs, files in os.walk(os.path.join(ROOT, "fastline")):
        for f in files:
            if not f.endswith(".py"):
                continue
            text = open(os.path.join(base, f), encoding="utf-8").read()
            for ref in {m.group(1) for m in pat.finditer(text)}:
                parts = ref.split(".")
                for i in range(len(parts), 0, -1):
                    try:
                        obj = importlib.import_module(".".join(parts[:i]))
                    except ImportError:
                        continue
                    break
                for attr in parts[i:]:
                    obj = getattr(obj, attr, None)
                if obj is None:
                    missing.append((f, ref))
    assert not missing, missing
