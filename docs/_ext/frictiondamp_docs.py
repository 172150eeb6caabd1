"""Build-time helpers of the documentation site (used by ``docs/conf.py``).

Everything here is generated from the code at build time, so that a new public name, a new example
or a new scene key appears on the site with no edit of the documentation:

- :func:`write_api_pages` writes one reST page per public name of each package's ``__all__`` (a
  class, a function, a public module), one page per package with a summary table, and one page
  per other public module of the two packages (:func:`public_modules`), so that no module a page or
  a docstring names is missing from the reference;
- :func:`gallery_examples` reads the examples' headers: a script whose docstring opens with a reST
  title is a gallery page; it is executed at build time unless its header shows the figure of a
  committed run (``.. image:: /figures/...``), which is what the long scripts do;
- :func:`redirect_savefig` and :func:`saved_png_scraper` let the executed examples run unchanged:
  the PNGs they write go to a temporary folder (not over the committed ``docs/figures``), and the
  gallery shows exactly those files;
- :func:`write_scene_keys` writes the page of scene keys from ``hbm.scenes.schema()``;
- :func:`write_guides_toctree` lists the Markdown pages of ``docs/`` in a fixed reading order, any
  page not named there (one added later) at the end, so that no page is left out of the site.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import re
import shutil
import tempfile
from pathlib import Path

#: Packages whose ``__all__`` makes the API reference (public modules found in them are added).
PACKAGES = ("contact_models", "hbm", "hbm.scenes", "hbm.study")

#: The top-level packages: every public module under them has a page (:func:`public_modules`).
ROOTS = ("contact_models", "hbm")

#: Members of these base classes are left out of a class page (a NamedTuple's ``count``, an
#: exception's ``args``): they are Python's, not the library's.
FOREIGN_BASES = "object, tuple, dict, list, int, Enum, IntEnum, Exception, BaseException, ValueError, ABC, Sequence"

_TITLE_RULE = re.compile(r"^([=\-~#*^\"+])\1{2,}\s*$")
_COMMITTED_FIGURE = re.compile(r"^\s*\.\. image:: /figures/", re.MULTILINE)


# --------------------------------------------------------------------------------------- API pages
def _kind(obj) -> str:
    if inspect.ismodule(obj):
        return "module"
    if inspect.isclass(obj):
        return "class"
    if inspect.isroutine(obj):
        return "function"
    return "data"


def _hinted_types(obj, package_root: str, seen: set) -> None:
    """Classes of ``package_root`` named in the type hints of ``obj`` (and of a class's methods)."""
    import typing

    targets = [obj]
    if inspect.isclass(obj):
        targets += [m for n, m in vars(obj).items() if not n.startswith("_") and inspect.isfunction(m)]
        targets += [getattr(obj, "__init__")]
    for target in targets:
        try:
            hints = typing.get_type_hints(target)
        except Exception:  # a hint that does not evaluate at run time names nothing we can document
            continue
        stack = list(hints.values())
        while stack:
            hint = stack.pop()
            stack.extend(typing.get_args(hint))
            if (inspect.isclass(hint) and hint.__module__.split(".")[0] == package_root
                    and not hint.__name__.startswith("_") and hint not in seen):
                seen.add(hint)


def returned_types(packages=PACKAGES) -> dict[str, list[str]]:
    """Classes named in the public API's type hints that have no page of their own
    (``NumericalMicroslip.simulate`` returns a ``contact_models.numerical.SimulationResult``):
    ``{package: [qualified name in its defining module]}``, each class under the first package
    whose API names it."""
    public, modules = set(), set()
    for package in packages:
        module = importlib.import_module(package)
        for name in module.__all__:
            obj = getattr(module, name)
            public.add(id(obj))
            if inspect.ismodule(obj):
                modules.add(obj.__name__)
    out: dict[str, list[str]] = {}
    claimed: set = set()
    for package in packages:
        module = importlib.import_module(package)
        seen: set = set()
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isclass(obj) or inspect.isroutine(obj):
                _hinted_types(obj, package.split(".")[0], seen)
        found = [c for c in seen if id(c) not in public and c.__module__ not in modules and c not in claimed]
        claimed.update(found)
        out[package] = sorted(f"{c.__module__}.{c.__qualname__}" for c in found)
    return out


def public_names(package: str) -> list[tuple[str, str]]:
    """``[(qualified name, kind)]`` of every name in ``package.__all__``, public modules recursed."""
    module = importlib.import_module(package)
    out = []
    for name in module.__all__:
        obj = getattr(module, name)
        out.append((f"{package}.{name}", _kind(obj)))
    return out


def _underline(title: str, char: str = "=") -> str:
    return f"{title}\n{char * len(title)}\n"


def _write(path: Path, text: str) -> None:
    """Write only when the text changed, so Sphinx does not rebuild unchanged pages."""
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def _module_page(qualified: str) -> str:
    """A public module that is not a package of ``PACKAGES`` (``hbm.continuation``)."""
    return (f"{_underline(qualified)}\n.. automodule:: {qualified}\n   :members:\n"
            f"   :inherited-members: {FOREIGN_BASES}\n   :show-inheritance:\n")


def _name_page(qualified: str, kind: str) -> str:
    package, name = qualified.rsplit(".", 1)
    head = f"{_underline(name)}\n.. currentmodule:: {package}\n\n"
    if kind == "class":
        return (head + f".. autoclass:: {name}\n   :members:\n   :inherited-members: {FOREIGN_BASES}\n"
                "   :show-inheritance:\n")
    return head + f".. autofunction:: {name}\n"


def _alias_page(qualified: str, kind: str, described_as: str) -> str:
    """The page of a name that another package exports too: a reference target of its own (no
    second description of the object, which Sphinx would refuse as a duplicate), linking to it."""
    package, name = qualified.rsplit(".", 1)
    role, directive = ("class", "py:class") if kind == "class" else ("func", "py:function")
    return (f"{_underline(name)}\n.. currentmodule:: {package}\n\n.. {directive}:: {name}\n\n"
            f"   The same object as :{role}:`{described_as}`, described there.\n")


def _summary(obj) -> str:
    """The first paragraph of ``obj``'s docstring, on one line (autosummary would cut it at "Fig.")."""
    doc = inspect.getdoc(obj) or ""
    line = [" ".join(doc.split("\n\n", 1)[0].split())]
    escape_bars(None, None, None, None, None, line)
    return line[0]


def _data_doc(package: str, name: str) -> tuple[str, str]:
    """``(value, description)`` of a data name: its ``#:`` comment where it is defined."""
    import pkgutil

    from sphinx.pycode import ModuleAnalyzer

    module = importlib.import_module(package)
    obj = getattr(module, name)
    names = [package] + [f"{package}.{m.name}" for m in pkgutil.iter_modules(module.__path__)]
    description = ""
    for modname in names:
        try:
            docs = ModuleAnalyzer.for_module(modname).find_attr_docs()
        except Exception:  # a module without source
            continue
        if ("", name) in docs:
            description = " ".join(line.strip() for line in docs[("", name)] if line.strip())
            break
    if name == "__version__" and not description:
        description = "The version of the installed package (``pyproject.toml``)."
    value = repr(obj)
    if len(value) > 70 or " at 0x" in value or "Path(" in value:  # a path would show this machine's folders
        value = ""
    return value, description


def _package_page(package: str, names: list[tuple[str, str]], pages: list[str], others: list[str]) -> str:
    text = _underline(f"``{package}``") + f"\n.. automodule:: {package}\n   :no-members:\n\n"
    text += f".. currentmodule:: {package}\n\n"
    module = importlib.import_module(package)
    roles = {"class": "class", "function": "func", "module": "mod"}
    for title, kind in (("Classes", "class"), ("Functions", "function"), ("Modules", "module")):
        entries = [q for q, k in names if k == kind]
        if entries:
            text += (_underline(title, "-") + "\n.. list-table::\n   :widths: 30 70\n\n")
            for qualified in entries:
                obj = getattr(module, qualified.rsplit(".", 1)[1])
                text += f"   * - :{roles[kind]}:`~{qualified}`\n     - {_summary(obj) or ' '}\n"
            text += "\n"
    data = [q.rsplit(".", 1)[1] for q, k in names if k == "data"]
    if data:
        text += _underline("Data", "-") + "\n"
        for name in data:
            value, description = _data_doc(package, name)
            text += f".. py:data:: {name}\n"
            if value:
                text += f"   :value: {value}\n"
            text += f"\n   {description}\n\n" if description else "\n"
    if others:
        text += (_underline("Types of the results", "-") + "\nClasses that the public API returns or takes, "
                 "documented where they are defined.\n\n")
        for qualified in others:
            text += f".. autoclass:: {qualified}\n   :members:\n   :inherited-members: {FOREIGN_BASES}\n\n"
    text += ".. toctree::\n   :hidden:\n\n" + "".join(f"   {p}\n" for p in pages)
    return text


# ------------------------------------------------------------------------------ public modules
def public_modules(roots=ROOTS) -> list[str]:
    """Every public module of ``roots``, sorted: no part of its dotted name starts with ``_``."""
    import pkgutil

    out = []
    for root in roots:
        package = importlib.import_module(root)
        names = [root] + [info.name for info in pkgutil.walk_packages(package.__path__, root + ".")]
        out += [name for name in names if not any(part.startswith("_") for part in name.split("."))]
    return sorted(out)


def _module_members(module) -> list[str]:
    """The public names of ``module``: its ``__all__``; else the classes and functions it defines
    and the data it documents with a ``#:`` comment."""
    if hasattr(module, "__all__"):
        return list(module.__all__)
    from sphinx.pycode import ModuleAnalyzer

    try:
        commented = {name for scope, name in ModuleAnalyzer.for_module(module.__name__).find_attr_docs() if not scope}
    except Exception:  # a module without source
        commented = set()
    return [n for n, obj in vars(module).items() if not n.startswith("_")
            and (((inspect.isclass(obj) or inspect.isroutine(obj)) and getattr(obj, "__module__", None) == module.__name__)
                 or (n in commented and _kind(obj) == "data"))]


def _other_module_pages(packages, paged: set, described: dict) -> dict[str, str]:
    """``{module: reST page}`` of every public module without a page yet.

    Each class or function is described once: where the packages' pages already describe it, a
    module page links there; else on the page of the module that defines it (or, when that module
    is not public, of the first module that lists it), and the other pages link to it.
    """
    modules = [m for m in public_modules() if m not in paged]
    home: dict[int, str] = {}
    for pass_ in ("defined", "listed"):  # the defining module first, then the first that lists it
        for modname in modules:
            module = importlib.import_module(modname)
            for name in _module_members(module):
                obj = getattr(module, name, None)
                if not (inspect.isclass(obj) or inspect.isroutine(obj)) or id(obj) in described or id(obj) in home:
                    continue
                if pass_ == "listed" or getattr(obj, "__module__", None) == modname:
                    home[id(obj)] = f"{modname}.{name}"
    roles = {"class": "class", "function": "func", "module": "mod"}
    pages = {}
    for modname in modules:
        module = importlib.import_module(modname)
        text = _underline(f"``{modname}``") + f"\n.. automodule:: {modname}\n   :no-members:\n\n"
        links, own, data = [], [], []
        for name in _module_members(module):
            obj = getattr(module, name, None)
            kind = _kind(obj)
            if kind == "data":
                data.append(name)
            elif kind == "module":
                if obj.__name__ in paged or obj.__name__ in modules:
                    links.append((f":mod:`~{obj.__name__}`", obj))
            elif kind in ("class", "function"):
                where = described.get(id(obj)) or home[id(obj)]
                if id(obj) not in described and where == f"{modname}.{name}":
                    own.append((name, kind))
                else:
                    links.append((f":{roles[kind]}:`{name} <{where}>`", obj))
        if links:
            text += (_underline("Documented elsewhere", "-") + "\n.. list-table::\n   :widths: 30 70\n\n"
                     + "".join(f"   * - {ref}\n     - {_summary(obj) or ' '}\n" for ref, obj in links) + "\n")
        if own or data:
            text += f".. currentmodule:: {modname}\n\n"
            for name in data:
                value = repr(getattr(module, name))
                text += f".. autodata:: {name}\n" + ("   :no-value:\n" if len(value) > 70 or " at 0x" in value or "Path(" in value else "") + "\n"
            for name, kind in own:
                if kind == "class":
                    text += (f".. autoclass:: {name}\n   :members:\n   :inherited-members: {FOREIGN_BASES}\n"
                             "   :show-inheritance:\n\n")
                else:
                    text += f".. autofunction:: {name}\n\n"
        pages[modname] = text
    return pages


def write_api_pages(outdir: Path, packages=PACKAGES) -> dict[str, list[str]]:
    """Write ``outdir/index.rst`` and one page per package and per public class, function, module.

    Returns ``{package: [qualified name of every entry of its __all__]}``, the names the reference
    documents (``tests/test_docs.py`` compares them with ``__all__`` and the built inventory), and
    under the key ``"modules"`` every public module that has a page.
    """
    outdir.mkdir(parents=True, exist_ok=True)
    documented: dict[str, list[str]] = {}
    written = {"index.rst"}
    others = returned_types(packages)
    paged = set(packages)  # modules with a page
    described: dict[int, str] = {}  # id of a class or function -> the name it is described under
    for package in packages:
        names = public_names(package)
        documented[package] = [q for q, _ in names]
        module = importlib.import_module(package)
        pages = []
        for qualified, kind in names:
            obj = getattr(module, qualified.rsplit(".", 1)[1])
            alias_of = described.get(id(obj)) if kind in ("class", "function") else None
            if kind in ("class", "function"):
                described.setdefault(id(obj), qualified)
            if kind == "data":
                continue
            if alias_of is not None and alias_of.split(".")[0] != package.split(".")[0]:  # another package's too
                _write(outdir / f"{qualified}.rst", _alias_page(qualified, kind, alias_of))
                written.add(f"{qualified}.rst")
                pages.append(qualified)
                continue
            if kind == "module" and qualified in packages:
                pages.append(qualified)
                continue
            if kind == "module":
                paged.add(obj.__name__)
                for member in vars(obj).values():  # automodule :members: describes what it defines
                    if ((inspect.isclass(member) or inspect.isroutine(member))
                            and getattr(member, "__module__", None) == obj.__name__
                            and not member.__name__.startswith("_")):
                        described.setdefault(id(member), f"{obj.__name__}.{member.__qualname__}")
            text = _module_page(qualified) if kind == "module" else _name_page(qualified, kind)
            _write(outdir / f"{qualified}.rst", text)
            written.add(f"{qualified}.rst")
            pages.append(qualified)
        _write(outdir / f"{package}.rst", _package_page(package, names, pages, others[package]))
        written.add(f"{package}.rst")
        for qualified in others[package]:
            owner, qualname = qualified.rsplit(".", 1)
            described.setdefault(id(getattr(importlib.import_module(owner), qualname)), qualified)
    modules = _other_module_pages(packages, paged, described)
    for modname, text in modules.items():
        _write(outdir / f"{modname}.rst", text)
        written.add(f"{modname}.rst")
    documented["modules"] = sorted(paged | set(modules))
    index = (_underline("API reference") + "\nGenerated at build time from the code: each package's ``__all__`` "
             "(every public name has its page, with the numpydoc sections of its docstring), then every "
             "other public module of ``contact_models`` and ``hbm`` (its docstring, the classes and functions "
             "it defines, links to those documented on another page).\n\n"
             ".. toctree::\n   :maxdepth: 2\n   :caption: Packages\n\n" + "".join(f"   {p}\n" for p in packages)
             + "\n.. toctree::\n   :maxdepth: 1\n   :caption: Modules\n\n" + "".join(f"   {m}\n" for m in modules))
    _write(outdir / "index.rst", index)
    for stale in outdir.glob("*.rst"):  # a name removed from __all__ loses its page
        if stale.name not in written:
            stale.unlink()
    return documented


def public_bases(app, name, obj, options, bases):
    """``autodoc-process-bases``: show public bases only (a private base is replaced by its own)."""
    out = []
    stack = list(bases)
    while stack:
        base = stack.pop(0)
        if base is object or getattr(base, "__name__", "").startswith("_") or base.__module__ == "abc":
            if base is not object and base.__module__ != "abc":
                stack[:0] = list(base.__bases__)
            continue
        if base not in out:
            out.append(base)
    bases[:] = out


# ----------------------------------------------------------------------------------------- gallery
def example_header(path: Path) -> str | None:
    """The module docstring of ``path`` if it opens with a reST title (a gallery page), else None."""
    try:
        doc = ast.get_docstring(ast.parse(path.read_text()), clean=False)
    except SyntaxError:
        return None
    if not doc:
        return None
    lines = doc.lstrip("\n").splitlines()
    if len(lines) >= 2 and lines[0].strip() and _TITLE_RULE.match(lines[1]):
        return doc
    return None


def gallery_examples(examples: Path) -> tuple[list[str], list[str]]:
    """``(executed, shown only)``: file names of the gallery scripts in ``examples``.

    Shown only: the header holds ``.. image:: /figures/NAME.png``, the figure of a committed run.
    """
    executed, shown = [], []
    for path in sorted(examples.glob("*.py")):
        doc = example_header(path)
        if doc is None:
            continue
        (shown if _COMMITTED_FIGURE.search(doc) else executed).append(path.name)
    return executed, shown


def gallery_patterns(examples: Path) -> tuple[str, str]:
    """sphinx-gallery's ``(filename_pattern, ignore_pattern)`` from :func:`gallery_examples`."""
    executed, shown = gallery_examples(examples)
    members = {Path(n).stem for n in executed + shown}
    ignored = [p.stem for p in examples.glob("*.py") if p.stem not in members]

    def alternatives(stems):
        return "|".join(re.escape(s) for s in sorted(stems)) or "(?!)"

    filename_pattern = r"[\\/](" + alternatives(Path(n).stem for n in executed) + r")\.py$"
    ignore_pattern = r"(__init__|" + alternatives(ignored) + r")\.py$"
    return filename_pattern, ignore_pattern


class _SavedFigures:
    """The PNGs an executed example wrote with ``Figure.savefig``, redirected to a temporary folder."""

    folder: Path | None = None
    paths: list[Path] = []
    gallery_dirs: tuple[Path, ...] = ()


def redirect_savefig(gallery_conf, fname, when=None):
    """sphinx-gallery ``reset_modules`` hook: before each example, redirect its ``savefig`` calls.

    An example writes its figure where its ``main()`` says (``docs/figures`` by default); at build
    time that file goes to a temporary folder instead, so building the site never rewrites a
    committed figure, and :func:`saved_png_scraper` shows it.  ``savefig`` into the gallery's own
    folders (sphinx-gallery's matplotlib scraper) is left alone.
    """
    import matplotlib.figure

    state = _SavedFigures
    if state.folder is None:
        state.folder = Path(tempfile.mkdtemp(prefix="frictiondamp-gallery-"))
        src = Path(gallery_conf["src_dir"])
        state.gallery_dirs = tuple((src / d).resolve() for d in _as_list(gallery_conf["gallery_dirs"]))
        original = matplotlib.figure.Figure.savefig

        def savefig(self, fname, *args, **kwargs):
            if isinstance(fname, (str, Path)):
                target = Path(fname).resolve()
                if not any(target.is_relative_to(d) for d in state.gallery_dirs):
                    target = state.folder / f"{len(state.paths):03d}_{target.name}"
                    state.paths.append(target)
                    return original(self, target, *args, **kwargs)
            return original(self, fname, *args, **kwargs)

        matplotlib.figure.Figure.savefig = savefig
    state.paths.clear()


def _as_list(value):
    return [value] if isinstance(value, str) else list(value)


def saved_png_scraper(block, block_vars, gallery_conf):
    """sphinx-gallery image scraper: the PNGs the code block wrote (see :func:`redirect_savefig`)."""
    from sphinx_gallery.scrapers import figure_rst

    state = _SavedFigures
    images = []
    for path in state.paths:
        if path.suffix.lower() == ".png" and path.exists():
            target = Path(next(block_vars["image_path_iterator"]))
            shutil.copyfile(path, target)
            images.append(str(target))
    state.paths.clear()
    return figure_rst(images, gallery_conf["src_dir"])


# -------------------------------------------------------------------------------------- scene keys
def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def write_scene_keys(path: Path) -> int:
    """The page of every scene key, from ``hbm.scenes.schema()`` as registered now; returns the count."""
    from hbm.scenes import REQUIRED, schema
    from hbm.scenes.checks import dot, show

    lines = ["# Scene keys", "",
             "Every table and key a scene file may hold, generated when the site is built from "
             "`hbm.scenes.schema()`: the fixed tables, the keys of every registered damper model and "
             "effect. `python -m hbm keys` prints the same list. See [Scenes](../scenes.md) for what a "
             "scene is and how it runs.", ""]
    count = 0
    for table, keys in schema().items():
        lines += [f"## `[{table}]`" if table else "## Top level", "", "| key | default | meaning |",
                  "|---|---|---|"]
        for key, spec in keys.items():
            if spec.default is REQUIRED:
                default = "required"
            elif spec.default is None:
                default = "optional"
            else:
                value = list(spec.default) if isinstance(spec.default, tuple) else spec.default
                default = f"`{show(value)}`"
            lines.append(f"| `{dot(table, key)}` | {_cell(default)} | {_cell(spec.doc)} |")
            count += 1
        lines.append("")
    _write(path, "\n".join(lines))
    return count


# ---------------------------------------------------------------------------------- guides toctree
#: Reading order of the Markdown pages of ``docs/``; a page not named here comes after them.
GUIDE_ORDER = ("theory", "hbm", "point_contact", "figures", "validation", "error_estimates", "performance",
               "scenes", "generated/scene_keys", "extending")
#: Pages with their own place in the home page's toctrees.
OWN_PLACE = ("index", "getting_started", "guides", "changelog")


def write_guides_toctree(docs: Path, path: Path) -> list[str]:
    """Write the toctree of the guide pages into ``path`` (included by ``index.md``)."""
    present = {p.relative_to(docs).with_suffix("").as_posix() for p in docs.glob("*.md")}
    present |= {"generated/scene_keys"}
    pages = [p for p in GUIDE_ORDER if p in present]
    pages += sorted(p for p in present if p not in pages and p not in OWN_PLACE)
    text = "```{toctree}\n:maxdepth: 1\n:caption: Topics: theory, solvers, validation\n:hidden:\n\n" + "".join(f"/{p}\n" for p in pages) + "```\n"
    _write(path, text)
    return pages


# ------------------------------------------------------------------------------------- docstrings
def _numpy_alias_patterns():
    """``[(regex, replacement)]`` that fold numpy's expanded typing aliases back into their names."""
    from numpy.typing import ArrayLike, NDArray
    from sphinx.util.typing import stringify_annotation

    out = []
    for mode, prefix in (("fully-qualified-except-typing", ""), ("smart", "~")):
        for alias, name in ((ArrayLike, "numpy.typing.ArrayLike"), (NDArray, "numpy.typing.NDArray")):
            out.append((re.compile(re.escape(stringify_annotation(alias, mode))), prefix + name))
        # NDArray[dtype]: ndarray[tuple[Any, ...], dtype[float64]] -> NDArray[float64]
        nd = re.escape(prefix) + r"numpy\.ndarray\[tuple\[Any, \.\.\.\], " + re.escape(prefix) + r"numpy\.dtype\[([~\w.]+)\]\]"
        out.append((re.compile(nd), prefix + r"numpy.typing.NDArray[\1]"))
    return out


_ALIASES: list = []


def short_numpy_types(app, what, name, obj, options, signature, return_annotation):
    """``autodoc-process-signature``: show ``ArrayLike`` and ``NDArray[...]`` by name, not as the
    unions of numpy's private protocols they expand to at run time."""
    if not _ALIASES:
        _ALIASES.extend(_numpy_alias_patterns())
    out = []
    for text in (signature, return_annotation):
        if text:
            for pattern, repl in _ALIASES:
                text = pattern.sub(repl, text)
        out.append(text)
    return tuple(out)


_LITERAL = re.compile(r"(``.*?``|:math:`[^`]*`|`[^`]*`_?)")


def escape_bars(app, what, name, obj, options, lines):
    """``autodoc-process-docstring`` (before numpydoc): a ``|x|`` written for an absolute value is
    text, not a reST substitution (this project defines none), so its bars are escaped.

    Left alone: inline literals and roles, ``.. math::`` and literal blocks (``::``), doctest
    blocks, and lines that start with ``|`` or ``+`` (tables, line blocks).
    """
    block_indent = None  # indentation of the directive or '::' paragraph whose body we are in
    in_doctest = False
    for i, line in enumerate(lines):
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if not stripped:
            in_doctest = False
            continue
        if block_indent is not None:
            if indent > block_indent:
                continue
            block_indent = None
        if stripped.startswith(">>>") or in_doctest:
            in_doctest = True
            continue
        if stripped.startswith(("|", "+")) or "|" not in line:
            pass
        else:
            parts = _LITERAL.split(line)
            lines[i] = "".join(p if k % 2 else re.sub(r"(?<!\\)\|", r"\\|", p) for k, p in enumerate(parts))
        if stripped.startswith(".. ") or stripped.endswith("::"):
            block_indent = indent


# ------------------------------------------------------------------------------------- references
_PUBLIC: dict[str, str] = {}


def _public_paths() -> dict[str, str]:
    """``{defining module path: public path}`` of every public class (``contact_models.bar.Bar``
    -> ``contact_models.Bar``)."""
    if not _PUBLIC:
        for package in PACKAGES:
            module = importlib.import_module(package)
            for name in module.__all__:
                obj = getattr(module, name)
                if inspect.isclass(obj) or inspect.isroutine(obj):
                    real = f"{obj.__module__}.{obj.__qualname__}"
                    if real != f"{package}.{name}":
                        _PUBLIC.setdefault(real, f"{package}.{name}")
    return _PUBLIC


_OBJECTS: list = []


def _public_objects() -> list[tuple[object, str]]:
    """``[(object, public path)]`` of every class, function and container in the packages' ``__all__``
    (numbers and strings left out: equal values are not the same name)."""
    if not _OBJECTS:
        for package in PACKAGES:
            module = importlib.import_module(package)
            for name in module.__all__:
                obj = getattr(module, name)
                if inspect.isclass(obj) or inspect.isroutine(obj) or isinstance(obj, (list, dict, tuple, set)):
                    _OBJECTS.append((obj, f"{package}.{name}"))
    return _OBJECTS


def _documented_as(obj) -> str | None:
    for candidate, path in _public_objects():
        if candidate is obj:
            return path
    real = f"{getattr(obj, '__module__', '')}.{getattr(obj, '__qualname__', '')}"
    if inspect.isclass(obj) or inspect.isroutine(obj):
        return _public_paths().get(real)
    return None


def _in_namespace(module: str, target: str) -> list[str]:
    """Where a name written in ``module``'s docstrings is documented, read as Python would read it
    there: ``Blade`` in ``hbm.frf`` is the ``hbm.blade.Blade`` that module imports, documented as
    ``hbm.Blade``; ``EFFECTS`` in ``hbm.scenes.effects`` is ``hbm.scenes.EFFECTS``; a dotted name
    not in the module's namespace is read from its package (``hbm.balance.HarmonicBalance``).  A
    bare name the module does not hold is the public name of that name, if there is one
    (``Structure``), else the member of the first public class of the module that has it (``on``
    in ``contact_models.loads``)."""
    try:
        namespace = importlib.import_module(module)
    except Exception:
        return []
    parts = target.split(".")
    starts = [namespace]
    if not hasattr(namespace, parts[0]) and parts[0] in ROOTS:
        starts = [importlib.import_module(parts[0])]
        parts = parts[1:]
    for obj in starts:
        for i, part in enumerate(parts):
            if not hasattr(obj, part):
                break
            obj = getattr(obj, part)
            public = _documented_as(obj)
            if public:
                return [".".join([public, *parts[i + 1:]])]
    if len(parts) == 1 and not hasattr(namespace, target):
        named = [path for _, path in _public_objects() if path.rsplit(".", 1)[1] == target]
        if len(set(named)) == 1:
            return named[:1]
        owners = [c for c in vars(namespace).values() if inspect.isclass(c) and c.__module__ == module
                  and hasattr(c, target) and _documented_as(c)]
        return [f"{_documented_as(owners[0])}.{target}"] if owners else []
    return []


def public_reference(app, env, node, contnode):
    """``missing-reference``: a reference written with a class's defining module
    (``contact_models.allmode.AllModeMicroslip.solve``, or ``AllModeMicroslip.solve`` inside that
    module) resolves to the class's public page (``contact_models.AllModeMicroslip.solve``); a
    name in a module's docstrings as that module's namespace reads it (:func:`_in_namespace`)."""
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip("~.")
    domain = env.get_domain("py")
    if node.get("py:module"):
        for new in _in_namespace(node["py:module"], target):
            found = domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], new, node, contnode)
            if found is not None:
                return found
    candidates = [target]
    if node.get("py:module"):
        candidates.append(f"{node['py:module']}.{target}")
    for candidate in candidates:
        for real, public in _public_paths().items():
            if candidate == real or candidate.startswith(real + "."):
                new = public + candidate[len(real):]
                found = domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], new, node, contnode)
                if found is not None:
                    return found
    return None


# ------------------------------------------------------------------------------------------ MathJax
def mathjax_folder() -> Path:
    """MathJax 3 as shipped by the package ``sphinx-mathjax-offline`` (the docs extra)."""
    package = importlib.import_module("sphinx-mathjax-offline")
    return Path(package.__file__).resolve().parent / "static" / "mathjax"


def copy_mathjax(app, exception):
    """``build-finished``: MathJax into the site (``mathjax_path = "mathjax/tex-chtml.js"``), so
    equations render with no network.  Done here rather than by listing that package as an
    extension, which does not declare itself safe for parallel builds (``-j``)."""
    if exception is None and app.builder.format == "html":
        from sphinx.util.fileutil import copy_asset

        copy_asset(str(mathjax_folder()), str(Path(app.outdir) / "_static" / "mathjax"))
