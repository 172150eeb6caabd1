"""The import graph of ``contact_models`` and ``hbm``, read from the code with ``ast``.

Used by the documentation (``docs/architecture.md``'s tables are written from it at build time,
so they cannot drift from the code) and by ``tests/test_layout.py`` (no circles; each part
imports only what :data:`MAY_IMPORT` allows).

An edge ``a -> b`` is an ``import b`` or ``from b import ...`` in module ``a``, at module level,
under ``if TYPE_CHECKING:`` or inside a function alike (a circle held open by an import inside a
function is a circle); ``from pkg import name`` is an edge to ``pkg.name`` when that is a
module, else to ``pkg`` (its ``__init__``).
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
    "allmode": (("contact_models.allmode",),
                "the all-mode bar (Eq. 30 with every mode): the element, its balance, Newton, error estimate"),
    "elements": (("contact_models",), "contact elements: f_s, f_c of a force law, its time law, loads, the bar"),
    "continuation": (("hbm.continuation", "hbm._steps"), "pseudo-arclength continuation of any R(y) = 0; knows nothing of friction"),
    "systems": (("hbm.structure", "hbm.blade", "hbm._validation"),
                "the linear systems: Structure, Contact, Blade (a one-DOF structure); input checks"),
    "balance": (("hbm.balance",), "the one harmonic balance: residual, condensation, layout, start, stability, presets"),
    "reference": (("hbm.reference",), "time-domain references: shooting, the event integrator, Newmark, blade in time"),
    "scenes": (("hbm.scenes",), "scene files: schema, validation, models, effects, planning, running, reporting"),
    "designs": (("hbm.designs",), "what a study runs: grids and random samples of scene keys, run ids"),
    "study": (("hbm.study",), "parameter studies: runs, the store, executors, figures"),
    "cli": (("hbm.cli", "hbm.__main__"), "the command line: main, progress, the default case"),
    "front": (("hbm",), "frequency_response (validate, pick, run, wrap), its result, CSV and plots"),
}

#: What each part may import (besides itself).  ``tests/test_layout.py`` holds the code to it, and
#: to :data:`THROUGH_PACKAGE`.
MAY_IMPORT = {
    "numerics": set(),
    "allmode": {"elements", "numerics"},
    "elements": {"numerics", "allmode"},
    "continuation": {"numerics"},
    "systems": {"elements", "numerics"},
    "balance": {"elements", "numerics", "continuation", "systems"},
    "front": {"elements", "allmode", "numerics", "continuation", "systems", "balance", "reference"},
    "reference": {"elements", "numerics", "continuation", "systems", "balance"},
    "designs": set(),
    "scenes": {"elements", "allmode", "numerics", "systems", "balance", "front", "reference", "designs"},
    "study": {"elements", "numerics", "systems", "balance", "front", "scenes", "designs"},
    "cli": {"elements", "numerics", "systems", "balance", "front", "reference", "scenes", "study", "designs"},
}


#: Subpackages whose modules are imported from outside only through the package (its
#: ``__init__``): the all-mode bar's modules are its own; the elements package, the all-mode
#: reference (``hbm.reference.amplitude``) and the scenes import ``contact_models.allmode``.
THROUGH_PACKAGE = ("contact_models.allmode",)


@dataclass
class Module:
    """One module: its file, its docstring's first line, and its imports of the two packages."""

    name: str
    path: Path
    summary: str
    imports: set[str] = field(default_factory=set)  # at module level
    lazy: set[str] = field(default_factory=set)  # inside a function
    types: set[str] = field(default_factory=set)  # under ``if TYPE_CHECKING:`` (never run)


def part_of(module: str) -> str:
    """The part (a key of :data:`PARTS`) that ``module`` belongs to."""
    for part, (prefixes, _) in PARTS.items():
        if any(module == p or module.startswith(p + ".") for p in prefixes):
            return part
    raise KeyError(module)


def module_files(root: Path) -> dict[str, Path]:
    """Every module of both packages: dotted name -> file (a package's name -> its ``__init__.py``)."""
    out = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
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


def read_module(name: str, path: Path, modules) -> Module:
    """``name`` with the modules of both packages it imports at module level, inside functions
    and under ``if TYPE_CHECKING:``."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    doc = (ast.get_docstring(tree) or "").strip()
    mod = Module(name, path, doc.splitlines()[0] if doc else "")
    inside = {id(n) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
              for n in ast.walk(f)}
    typing_only = {id(n) for f in ast.walk(tree) if isinstance(f, ast.If) and "TYPE_CHECKING" in ast.unparse(f.test)
                   for stmt in f.body for n in ast.walk(stmt)}
    is_package = path.name == "__init__.py"
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
                where = mod.types if id(node) in typing_only else mod.lazy if id(node) in inside else mod.imports
                where.add(found)
    return mod


def read_graph(root: Path) -> dict[str, Module]:
    """Every module of the two packages under ``root`` with its imports."""
    files = module_files(root)
    return {name: read_module(name, path, files) for name, path in files.items()}


def import_graph(root: Path) -> dict[str, set[str]]:
    """``{module: modules it imports anywhere}``."""
    return {name: m.imports | m.lazy | m.types for name, m in read_graph(root).items()}


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


def part_edges(graph: dict[str, Module]) -> dict[str, set[str]]:
    """``{part: parts it imports}`` (module-level and lazy imports, a part's own left out; an import
    for type hints only does not make a part depend on another)."""
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
