"""The layout of both packages: no import circles, every module importable alone, modules and
functions of a readable size, and the old paths of moved modules still answering (with a warning).

The import graph is read from the source with ``ast`` (every ``import`` and ``from ... import``,
at module level, under ``if TYPE_CHECKING:`` and inside functions alike), so a circle held open
by an import inside a function counts as a circle.
"""

from __future__ import annotations

import ast
import importlib
import io
import json
import subprocess
import sys
import tokenize
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("contact_models", "hbm")
#: No library module above this many lines.
MAX_MODULE_LINES = 600
#: No function above this many lines of code (docstrings, comments and blank lines not counted).
MAX_FUNCTION_CODE = 80
#: Old module paths kept as shims: old -> new.
MOVED = {
    "hbm.shooting": "hbm.reference.shooting",
    "hbm.transient": "hbm.reference.transient",
    "hbm._piecewise": "hbm.reference.piecewise",
    "hbm._newmark": "hbm.reference.newmark",
    "hbm.progress": "hbm.cli.progress",
    "hbm.cases": "hbm.cli.cases",
    "hbm.scenes.study": "hbm.scenes.sampling",
}


# ------------------------------------------------------------------------------ the import graph
def module_files() -> dict[str, Path]:
    """Every module of both packages: dotted name -> file (a package's name -> its ``__init__.py``)."""
    out = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = path
    return out


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    """The absolute module named by ``from <node.module> import ...`` in ``module``."""
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _known(name: str, modules) -> str | None:
    """The longest prefix of ``name`` that is one of ``modules`` (an attribute import names its module)."""
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        candidate = ".".join(parts[:k])
        if candidate in modules:
            return candidate
    return None


def import_edges(name: str, path: Path, modules) -> set[str]:
    """The modules of both packages that ``name`` imports anywhere in its source.

    ``from . import x`` is an edge to the submodule ``x`` when ``x`` is a module, else to the
    package; an edge to a package is an edge to its ``__init__``."""
    tree = ast.parse(path.read_text(), str(path))
    is_package = path.name == "__init__.py"
    edges = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = _resolve(name, is_package, node)
            targets = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base for alias in node.names]
        else:
            continue
        for target in targets:
            found = _known(target, modules)
            if found is not None and found != name:
                edges.add(found)
    return edges


def import_graph() -> dict[str, set[str]]:
    files = module_files()
    return {name: import_edges(name, path, files) for name, path in files.items()}


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One circle ``[a, b, ..., a]`` per strongly connected component of more than one module."""
    index, low, stack, on_stack, components = {}, {}, [], set(), []
    counter = [0]

    def visit(v):  # Tarjan's algorithm, iteratively (deep graphs would exhaust the recursion)
        work = [(v, iter(sorted(graph[v])))]
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        while work:
            node, children = work[-1]
            for w in children:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on_stack:
                    low[node] = min(low[node], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        component.append(w)
                        if w == node:
                            break
                    if len(component) > 1:
                        components.append(component)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return [_cycle_in(sorted(c), graph) for c in components]


def _cycle_in(component: list[str], graph: dict[str, set[str]]) -> list[str]:
    """A shortest circle through the component's first module, staying inside the component."""
    members, start = set(component), component[0]
    paths, seen = [[start]], {start}
    while paths:
        path = paths.pop(0)
        for w in sorted(graph[path[-1]] & members):
            if w == start:
                return path + [start]
            if w not in seen:
                seen.add(w)
                paths.append(path + [w])
    return component


def test_the_graph_sees_relative_and_function_level_imports():
    graph = import_graph()
    assert "hbm.frf" in graph["hbm"] and "contact_models.numerics.roots" in graph["hbm.continuation"]
    assert "hbm.reference.shooting" in graph["hbm"]  # from .reference.shooting import ...
    assert "hbm.cli.main" in graph["hbm.__main__"]
    # the check can fail: a circle through a function-level import is found and named
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert circles(graph) == [["a", "b", "c", "a"]]


def test_no_import_circles():
    found = circles(import_graph())
    assert not found, "import circles:\n" + "\n".join(" -> ".join(c) for c in found)


# ---------------------------------------------------------------------------- import alone
_IMPORT_ALONE = """
import importlib, json, sys, traceback, warnings
warnings.simplefilter("ignore")
failed = {}
for name in json.loads(sys.argv[1]):
    for loaded in [m for m in sys.modules if m.split(".")[0] in ("hbm", "contact_models")]:
        del sys.modules[loaded]
    try:
        importlib.import_module(name)
    except BaseException:
        failed[name] = traceback.format_exc(limit=-3)
print(json.dumps(failed))
"""


def test_every_module_imports_alone():
    names = sorted(module_files())
    out = subprocess.run([sys.executable, "-c", _IMPORT_ALONE, json.dumps(names)], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout
    failed = json.loads(out.strip().splitlines()[-1])
    assert not failed, "\n".join(f"{k}:\n{v}" for k, v in failed.items())


# ---------------------------------------------------------------------------------------- sizes
def code_lines(source: str) -> set[int]:
    """Line numbers holding code: not blank, not only a comment, not part of a docstring."""
    lines = set()
    skip = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT,
            tokenize.ENCODING, tokenize.ENDMARKER}
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type not in skip:
            lines.update(range(tok.start[0], tok.end[0] + 1))
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
                    and isinstance(first.value.value, str)):
                lines.difference_update(range(first.lineno, first.end_lineno + 1))
    return lines


def function_sizes(path: Path) -> list[tuple[str, int]]:
    """``(qualified name, lines of code)`` of every function and method of ``path``."""
    source = path.read_text()
    code = code_lines(source)
    out = []

    def walk(node, prefix):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                name = f"{prefix}{child.name}"
                out.append((name, len([n for n in range(child.lineno, child.end_lineno + 1) if n in code])))
                walk(child, name + ".")
            elif isinstance(child, ast.ClassDef):
                walk(child, f"{prefix}{child.name}.")
            else:
                walk(child, prefix)

    walk(ast.parse(source), "")
    return out


def test_the_size_counts_leave_out_docstrings_and_comments():
    source = ('def f(x):\n    """A docstring\n\n    of four lines.\n    """\n    # a comment\n\n'
              '    y = (x +\n         1)\n    return """a string\nthat is code"""\n')
    path = ROOT / "tests" / "_layout_probe.py"
    try:
        path.write_text(source)
        assert function_sizes(path) == [("f", 5)]  # def, y = (x +, 1), return """..., that is code
    finally:
        path.unlink()


def test_no_module_over_600_lines():
    big = {name: n for name, path in module_files().items()
           if (n := len(path.read_text().splitlines())) > MAX_MODULE_LINES}
    assert not big, f"modules over {MAX_MODULE_LINES} lines: {big}"


def test_no_function_over_80_lines_of_code():
    big = {f"{name}.{fn}": n for name, path in module_files().items() for fn, n in function_sizes(path)
           if n > MAX_FUNCTION_CODE}
    assert not big, f"functions over {MAX_FUNCTION_CODE} lines of code: {big}"


# ------------------------------------------------------------------------------------ old paths
@pytest.mark.parametrize("old, new", sorted(MOVED.items()))
def test_an_old_path_warns_and_gives_the_new_module(old, new):
    module = importlib.import_module(new)
    sys.modules.pop(old, None)
    with pytest.warns(DeprecationWarning, match=f"{old} moved to {new}"):
        shim = importlib.import_module(old)
    assert shim is module
    names = getattr(module, "__all__", None) or [n for n in vars(module) if not n.startswith("_")]
    assert names
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        for name in names:
            assert getattr(shim, name) is getattr(module, name), name
        exec(f"from {old} import {names[0]} as got", scope := {})
    assert scope["got"] is getattr(module, names[0])
