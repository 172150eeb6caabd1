"""The import graph of ``contact_models`` and ``hbm``, read from the code with ``ast``.

Used by the documentation (``docs/architecture.md``'s tables are written from it at build time,
so they cannot drift from the code) and by ``tests/test_layout.py`` (no circles; each part
imports only what :data:`MAY_IMPORT` allows).

An edge ``a -> b`` is an ``import b`` or ``from b import ...`` in module ``a``, at module level or
inside a function; ``from pkg import name`` is an edge to ``pkg.name`` when that is a module,
else to ``pkg`` (its ``__init__``).  Imports under ``if TYPE_CHECKING:`` are not edges (they do
not run).
"""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
from pathlib import Path

PACKAGES = ("contact_models", "hbm")

#: The parts of the architecture: name -> (module prefixes, what it owns).  A module belongs to
#: the first part with a prefix it starts with (most specific first).
PARTS = {
    "numerics": (("contact_models.numerics",),
                 "numerics both packages use: Brent, input checks, Masing/AFT, time stepping"),
    "elements": (("contact_models",), "contact elements: f_s, f_c of a force law, its time law, loads, the bar"),
    "continuation": (("hbm.continuation",), "pseudo-arclength continuation of any R(y) = 0; knows nothing of friction"),
    "systems": (("hbm.structure", "hbm.blade", "hbm._validation"),
                "the linear systems: Structure, Contact, Blade (a one-DOF structure); input checks"),
    "balance": (("hbm.balance",), "the one harmonic balance: residual, condensation, layout, start, stability, presets"),
    "reference": (("hbm.reference",), "time-domain references: shooting, the event integrator, Newmark, blade in time"),
    "scenes": (("hbm.scenes",), "scene files: schema, validation, models, effects, planning, running, reporting"),
    "study": (("hbm.study",), "parameter studies: designs, runs, the store, executors"),
    "cli": (("hbm.cli", "hbm.__main__"), "the command line: main, progress, the default case"),
    "front": (("hbm",), "frequency_response (validate, pick, run, wrap), its result, CSV and plots"),
}

#: What each part may import (besides itself).  ``tests/test_layout.py`` holds the code to it.
MAY_IMPORT = {
    "numerics": set(),
    "elements": {"numerics"},
    "continuation": {"numerics"},
    "systems": {"elements", "numerics"},
    "balance": {"elements", "numerics", "continuation", "systems"},
    "front": {"elements", "numerics", "continuation", "systems", "balance", "reference"},
    "reference": {"elements", "numerics", "continuation", "systems", "balance"},
    "scenes": {"elements", "numerics", "systems", "balance", "front", "reference"},
    "study": {"elements", "numerics", "systems", "balance", "front", "scenes"},
    "cli": {"elements", "numerics", "systems", "balance", "front", "reference", "scenes", "study"},
}


@dataclass
class Module:
    """One module: its file, its docstring's first line, and its imports of the two packages."""

    name: str
    path: Path
    summary: str
    imports: set[str] = field(default_factory=set)  # at module level
    lazy: set[str] = field(default_factory=set)  # inside a function


def part_of(module: str) -> str:
    """The part (a key of :data:`PARTS`) that ``module`` belongs to."""
    for part, (prefixes, _) in PARTS.items():
        if any(module == p or module.startswith(p + ".") for p in prefixes):
            return part
    raise KeyError(module)


def _modules(root: Path) -> dict[str, Path]:
    out = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = path
    return out


def _targets(node: ast.AST, module: str, is_package: bool, known: dict) -> list[str]:
    if isinstance(node, ast.Import):
        return [a.name for a in node.names if a.name.split(".")[0] in PACKAGES]
    assert isinstance(node, ast.ImportFrom)
    if node.level:
        base = module.split(".") if is_package else module.split(".")[:-1]
        base = base[:len(base) - (node.level - 1)]
        name = ".".join(base + ([node.module] if node.module else []))
    else:
        name = node.module or ""
    if name.split(".")[0] not in PACKAGES:
        return []
    subs = [f"{name}.{a.name}" for a in node.names if f"{name}.{a.name}" in known]
    return subs if len(subs) == len(node.names) else [name] + subs


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skip.update(id(n) for stmt in node.body for n in ast.walk(stmt))
    return skip


def read_graph(root: Path) -> dict[str, Module]:
    """Every module of the two packages under ``root`` with its imports."""
    known = _modules(root)
    graph = {}
    for name, path in known.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        doc = ast.get_docstring(tree) or ""
        mod = Module(name, path, doc.strip().splitlines()[0] if doc.strip() else "")
        skip = _type_checking_nodes(tree)
        inside = {id(n) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
                  for n in ast.walk(f)}
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)) and id(node) not in skip:
                for t in _targets(node, name, path.name == "__init__.py", known):
                    if t != name:
                        (mod.lazy if id(node) in inside else mod.imports).add(t)
        graph[name] = mod
    return graph


def circles(graph: dict[str, Module]) -> list[list[str]]:
    """The import circles (strongly connected components of more than one module, or a module
    importing itself), module-level and lazy imports together."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:  # Tarjan's algorithm, iterative over the edges of v
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v].imports | graph[v].lazy):
            if w not in graph:
                continue
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
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def part_edges(graph: dict[str, Module]) -> dict[str, set[str]]:
    """``{part: parts it imports}`` (module-level and lazy imports, a part's own left out)."""
    edges: dict[str, set[str]] = {p: set() for p in PARTS}
    for mod in graph.values():
        here = part_of(mod.name)
        edges[here] |= {part_of(t) for t in mod.imports | mod.lazy if t in graph} - {here}
    return edges


def write_import_tables(root: Path, path: Path) -> int:
    """Write the Markdown tables of ``docs/architecture.md``: the parts, what each owns, may and
    does import; then every module with its imports.  Returns the number of modules."""
    graph = read_graph(root)
    edges = part_edges(graph)
    lines = ["| part | modules | owns | may import | imports |", "| --- | --- | --- | --- | --- |"]
    for p, (prefixes, owns) in PARTS.items():
        where = ", ".join(f"`{q}`" for q in prefixes)
        may = ", ".join(sorted(MAY_IMPORT[p])) or "nothing"
        does = ", ".join(sorted(edges[p])) or "nothing"
        lines.append(f"| {p} | {where} | {owns} | {may} | {does} |")
    lines += ["", "| module | lines | imports (lazy ones in italics) | what it is |", "| --- | --- | --- | --- |"]
    for name, mod in sorted(graph.items()):
        n = len(mod.path.read_text(encoding="utf-8").splitlines())
        imports = [f"`{t}`" for t in sorted(mod.imports)] + [f"*{t}*" for t in sorted(mod.lazy - mod.imports)]
        summary = mod.summary.replace("|", "\\|")
        lines.append(f"| `{name}` | {n} | {', '.join(imports) or '-'} | {summary} |")
    text = "\n".join(lines) + "\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")
    return len(graph)
