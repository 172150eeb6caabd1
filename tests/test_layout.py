"""The layout of both packages: no import circles, every module importable alone, the all-mode
bar's modules imported only through their package, and functions of a readable size.

The import graph is read from the source with ``ast`` by ``docs/_ext/import_graph.py`` (every
``import`` and ``from ... import``, at module level, under ``if TYPE_CHECKING:`` and inside
functions alike), so a circle held open by an import inside a function counts as a circle; the
architecture page's tables are written from the same graph.
"""

from __future__ import annotations

import ast
import importlib
import io
import json
import re
import subprocess
import sys
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "docs" / "_ext"))
import import_graph as ig  # noqa: E402  (the graph the architecture page is written from)

PACKAGES = ig.PACKAGES
#: No function above this many lines of code (docstrings, comments and blank lines not counted).
MAX_FUNCTION_CODE = 80


# ------------------------------------------------------------------------------ the import graph
def module_files() -> dict[str, Path]:
    return ig.module_files(ROOT)


def import_graph() -> dict[str, set[str]]:
    return ig.import_graph(ROOT)


def test_the_graph_sees_relative_and_function_level_imports():
    graph = import_graph()
    assert "hbm.frf" in graph["hbm"] and "contact_models.numerics.roots" in graph["hbm.continuation"]
    assert "hbm.reference.shooting" in graph["hbm"]  # from .reference.shooting import ...
    assert "hbm.cli.main" in graph["hbm.__main__"]
    # the check can fail: a circle through a function-level import is found and named
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert ig.circles(graph) == [["a", "b", "c", "a"]]


def test_each_part_imports_only_what_the_architecture_allows():
    edges = ig.part_edges(ig.read_graph(ROOT))
    extra = {part: sorted(edges[part] - ig.MAY_IMPORT[part]) for part in ig.PARTS if edges[part] - ig.MAY_IMPORT[part]}
    assert not extra, f"imports the architecture does not allow (docs/architecture.md): {extra}"


def test_every_module_belongs_to_a_part():
    for name in module_files():
        assert ig.part_of(name) in ig.PARTS


def test_no_import_circles():
    found = ig.circles(import_graph())
    assert not found, "import circles:\n" + "\n".join(" -> ".join(c) for c in found)


# ---------------------------------------------------------------------------- import alone
# Importing ``pkg.mod`` first runs ``pkg/__init__.py`` to its end, so a module that the package's
# own import already loads is imported exactly as the package is: each package is imported once
# from a clean state, then every module it did not load is imported alone, from a clean state.
_IMPORT_ALONE = """
import importlib, json, sys, traceback, warnings
warnings.simplefilter("ignore")
OURS = ("hbm", "contact_models")

def clean_import(name):
    for loaded in [m for m in sys.modules if m.split(".")[0] in OURS]:
        del sys.modules[loaded]
    try:
        importlib.import_module(name)
    except BaseException:
        failed[name] = traceback.format_exc(limit=-3)
    return {m for m in sys.modules if m.split(".")[0] == name.split(".")[0]}

failed, alone = {}, []
names = json.loads(sys.argv[1])
for package in OURS:
    with_package = clean_import(package)
    for name in names:
        if name.split(".")[0] == package and name != package and name not in with_package:
            clean_import(name)
            alone.append(name)
print(json.dumps({"failed": failed, "alone": alone}))
"""


def test_every_module_imports_alone():
    names = sorted(module_files())
    out = subprocess.run([sys.executable, "-c", _IMPORT_ALONE, json.dumps(names)], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout
    result = json.loads(out.strip().splitlines()[-1])
    assert not result["failed"], "\n".join(f"{k}:\n{v}" for k, v in result["failed"].items())
    assert "hbm.__main__" in result["alone"]  # not loaded by ``import hbm``: imported on its own


def test_a_module_that_fails_alone_is_named(tmp_path):
    """The check can fail: a module its package does not load, broken on import, is reported."""
    for package in ("hbm", "contact_models"):
        (tmp_path / package).mkdir()
        (tmp_path / package / "__init__.py").write_text("")
    (tmp_path / "hbm" / "broken.py").write_text("import hbm.nowhere\n")
    out = subprocess.run([sys.executable, "-c", _IMPORT_ALONE, json.dumps(["hbm", "hbm.broken", "contact_models"])],
                         capture_output=True, text=True, cwd=tmp_path, check=True).stdout
    result = json.loads(out.strip().splitlines()[-1])
    assert list(result["failed"]) == ["hbm.broken"] and "ModuleNotFoundError" in result["failed"]["hbm.broken"]


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


def test_no_function_over_80_lines_of_code():
    big = {f"{name}.{fn}": n for name, path in module_files().items() for fn, n in function_sizes(path)
           if n > MAX_FUNCTION_CODE}
    assert not big, f"functions over {MAX_FUNCTION_CODE} lines of code: {big}"


# ----------------------------------------------------------------------------- the architecture page
def test_every_name_on_the_architecture_page_exists():
    """The dotted names ``docs/architecture.md`` walks a frequency response through import."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    names = set(re.findall(r"`((?:hbm|contact_models)(?:\.[A-Za-z_]\w*)+)", text))
    names |= {f"contact_models.ContactElement.{n}" for n in re.findall(r"`ContactElement\.(\w+)", text)}
    assert len(names) > 25
    missing = []
    for name in sorted(names):
        parts = name.split(".")
        for k in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:k]))
            except ImportError:
                continue
            for attr in parts[k:]:
                obj = getattr(obj, attr, None)
            if obj is None:
                missing.append(name)
            break
    assert not missing, f"names on docs/architecture.md that do not exist: {missing}"


def test_hbm_imports_no_private_module_of_contact_models():
    graph = import_graph()
    private = {(a, b) for a, targets in graph.items() if a.startswith("hbm")
               for b in targets if b.startswith("contact_models") and any(p.startswith("_") for p in b.split(".")[1:])}
    assert not private, f"hbm imports private modules of contact_models: {sorted(private)}"


def test_the_allmode_modules_are_imported_only_through_their_package():
    graph = import_graph()
    inside = {(a, b) for a, targets in graph.items() for b in targets for pkg in ig.THROUGH_PACKAGE
              if b.startswith(pkg + ".") and not (a == pkg or a.startswith(pkg + "."))}
    assert not inside, f"modules of {ig.THROUGH_PACKAGE} imported from outside their package: {sorted(inside)}"
