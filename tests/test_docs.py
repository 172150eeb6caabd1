"""The documentation site: the API reference covers every public name, the gallery and the pages
are complete, and the main entry points carry numpydoc sections with examples.

The site itself is built by ``.ci/run`` (``sphinx -W -n``), which then sets
``FRICTIONDAMP_DOCS_HTML`` so that :func:`test_built_inventory_names_every_public_name` reads the
built ``objects.inv``; without it that test is skipped (a stale local build would mislead).
"""

import importlib
import inspect
import json
import os
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

import frictiondamp_docs as fd  # noqa: E402

#: The packages whose ``__all__`` the reference documents (the two packages and the scenes subpackage).
PACKAGES = ("contact_models", "hbm", "hbm.scenes")

#: The main entry points: each docstring has these numpydoc sections.
ENTRY_POINTS = {
    "hbm.frequency_response": ("Parameters", "Returns", "Raises", "Examples"),
    "hbm.response_at": ("Parameters", "Returns", "Raises", "Examples"),
    "hbm.simulate_blade": ("Parameters", "Returns", "Raises", "Examples"),
    "hbm.Blade": ("Parameters", "Raises", "Examples"),
    "hbm.FrequencyResponse": ("Attributes", "Examples"),
    "hbm.FrequencyResponse.peak": ("Returns", "Raises", "Examples"),
    "hbm.FrequencyResponse.to_csv": ("Parameters", "Returns", "Examples"),
    "hbm.FrequencyResponse.plot": ("Parameters", "Returns", "Examples"),
    "contact_models.Bar": ("Parameters", "Raises", "Examples"),
    "contact_models.UniformLoad": ("Parameters", "Raises", "Examples"),
    "contact_models.QuadraticLoad": ("Parameters", "Raises", "Examples"),
    "contact_models.TwoRegionMicroslip": ("Parameters", "Raises", "References", "Examples"),
    "contact_models.ThreeRegionMicroslip": ("Parameters", "Raises", "References", "Examples"),
    "contact_models.Macroslip": ("Parameters", "Raises", "Examples"),
    "contact_models.PointContact": ("Parameters", "Raises", "Examples"),
    "contact_models.PointContact.fit": ("Parameters", "Returns", "Raises", "Examples"),
    "contact_models.NumericalMicroslip": ("Parameters", "Raises", "Examples"),
    "contact_models.QuasiStatic": ("Parameters", "Raises", "Examples"),
    "contact_models.ContactElement": ("Examples",),
    "contact_models.ContactElement.fourier": ("Parameters", "Returns", "Raises", "Examples"),
}


def _resolve(qualified):
    parts = qualified.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for name in parts[i:]:
            obj = getattr(obj, name)
        return obj
    raise ImportError(qualified)


def _directives(text):
    """``{target}`` of every autodoc directive / table entry of a generated reST page."""
    found = set(re.findall(r"^\.\. (?:auto(?:class|function|data|module)|py:(?:data|class|function)):: (\S+)", text,
                           re.MULTILINE))  # py:class/py:function: a name another package describes (an alias page)
    for qualified in re.findall(r":(?:class|func|mod):`~(\S+?)`", text):  # the package page's tables
        found |= {qualified, qualified.rsplit(".", 1)[1]}
    return found


def test_api_pages_name_every_public_name(tmp_path):
    pytest.importorskip("sphinx", reason="the docs extra (pip install -e '.[docs]'); .ci/run installs it")
    documented = fd.write_api_pages(tmp_path, PACKAGES)
    for package in PACKAGES:
        module = importlib.import_module(package)
        assert documented[package] == [f"{package}.{n}" for n in module.__all__]
        page = (tmp_path / f"{package}.rst").read_text()
        entries = _directives(page)
        for name in module.__all__:
            obj = getattr(module, name)
            assert name in entries, f"{package}.{name} is missing from the page of {package}"
            if inspect.isclass(obj) or inspect.isroutine(obj) or inspect.ismodule(obj):
                own = tmp_path / f"{package}.{name}.rst"
                if not (inspect.ismodule(obj) and obj.__name__ in PACKAGES):
                    assert own.exists(), f"no page for {package}.{name}"
                    text = own.read_text()
                    assert name in _directives(text) or f"{package}.{name}" in _directives(text)


def _public_modules():
    """Every public module of both packages, listed from the code: no part of its dotted name starts
    with ``_``."""
    import pkgutil

    found = []
    for root in ("contact_models", "hbm"):
        package = importlib.import_module(root)
        files = [(root, package.__file__)] + [(m.name, m.module_finder.find_spec(m.name).origin)
                                              for m in pkgutil.walk_packages(package.__path__, root + ".")]
        for name, origin in files:
            if not any(part.startswith("_") for part in name.split(".")):
                found.append(name)
    return found


def test_api_reference_has_a_page_for_every_public_module(tmp_path):
    pytest.importorskip("sphinx", reason="the docs extra (pip install -e '.[docs]'); .ci/run installs it")
    modules = _public_modules()
    assert {"hbm.balance.stability", "contact_models.model_range", "hbm.balance.presets",
            "contact_models.numerics.roots", "hbm.reference.shooting"} <= set(modules)
    documented = fd.write_api_pages(tmp_path)
    automodules = set()
    for page in tmp_path.glob("*.rst"):
        automodules |= set(re.findall(r"^\.\. automodule:: (\S+)", page.read_text(), re.MULTILINE))
    missing = [m for m in modules if m not in automodules]
    assert not missing, f"public modules without a page in the API reference: {missing}"
    assert set(modules) <= set(documented["modules"])
    index = (tmp_path / "index.rst").read_text()
    for module in modules:  # every page is reachable from the reference's index
        assert f"   {module}\n" in index or any(f"   {module}\n" in (tmp_path / f"{p}.rst").read_text()
                                                for p in fd.PACKAGES), module


def _built_inventory() -> dict:
    """``{kind: {name: entry}}`` of the built site's ``objects.inv`` (``FRICTIONDAMP_DOCS_HTML``);
    the test is skipped without a built site."""
    html = os.environ.get("FRICTIONDAMP_DOCS_HTML")
    if not html:
        pytest.skip("set FRICTIONDAMP_DOCS_HTML to a built site (.ci/run does) to check its inventory")
    from sphinx.util.inventory import InventoryFile  # the docs extra, with the built site

    path = Path(html)
    path = path if path.is_absolute() else ROOT / path
    with open(path / "objects.inv", "rb") as f:
        inventory = InventoryFile.load(f, str(path), lambda base, uri: uri)
    return inventory.data if hasattr(inventory, "data") else inventory


def test_built_reference_names_every_public_module():
    data = _built_inventory()
    modules = set(data.get("py:module", {}))
    missing = [m for m in _public_modules() if m not in modules]
    assert not missing, f"public modules not in the built reference: {missing}"


def test_built_pages_show_no_absolute_path_of_the_build_machine():
    """Neither the reference (a data value that is a path) nor the gallery (a printed path, a
    warning's file name) shows the folder the site was built in."""
    html = os.environ.get("FRICTIONDAMP_DOCS_HTML")
    if not html:
        pytest.skip("set FRICTIONDAMP_DOCS_HTML to a built site (.ci/run does) to check its pages")
    path = Path(html)
    path = path if path.is_absolute() else ROOT / path
    pages = [*(path / "generated" / "api").glob("*.html"), *(path / "auto_examples").glob("*.html")]
    assert len(pages) > 20
    showing = [p.relative_to(path).as_posix() for p in pages if str(ROOT) in p.read_text()]
    assert not showing, f"pages showing {ROOT}: {showing}"


def test_every_public_class_and_function_has_a_docstring():
    for package in PACKAGES:
        module = importlib.import_module(package)
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isclass(obj) or inspect.isroutine(obj) or inspect.ismodule(obj):
                doc = inspect.getdoc(obj) or ""
                assert len(doc.split()) >= 3, f"{package}.{name} has no docstring"


@pytest.mark.parametrize("qualified", sorted(ENTRY_POINTS))
def test_entry_points_have_numpydoc_sections(qualified):
    doc = inspect.getdoc(_resolve(qualified)) or ""
    for section in ENTRY_POINTS[qualified]:
        assert re.search(rf"^{section}\n-{{{len(section)}}}$", doc, re.MULTILINE), f"{qualified}: no {section}"
    if "Examples" in ENTRY_POINTS[qualified]:
        examples = doc.split("Examples\n--------", 1)[1]
        assert ">>> " in examples and re.search(r"^\s*[^>.\s].*\d", examples, re.MULTILINE), \
            f"{qualified}: the example asserts no number"


def test_built_inventory_names_every_public_name():
    data = _built_inventory()
    names = {name for kind, entries in data.items() if kind.startswith("py:") for name in entries}
    missing = [f"{p}.{n}" for p in PACKAGES for n in importlib.import_module(p).__all__
               if f"{p}.{n}" not in names]
    assert not missing, f"public names not in the built reference: {missing}"
    # the main entry points and their methods are documented objects of the site too
    for qualified in ENTRY_POINTS:
        assert qualified in names, qualified


def test_gallery_has_a_dozen_pages_with_figures_and_long_ones_show_a_committed_figure():
    executed, shown = fd.gallery_examples(ROOT / "examples")
    assert len(executed) + len(shown) >= 12
    for name in shown:
        header = fd.example_header(ROOT / "examples" / name)
        for figure in re.findall(r"^\s*\.\. image:: /(figures/\S+)", header, re.MULTILINE):
            assert (DOCS / figure).is_file(), f"{name} shows {figure}, which is not committed"
    # helpers without a title are left out, and are not gallery pages
    assert "paper_figures.py" not in executed + shown and "validation_common.py" not in executed + shown
    # the long scripts are not run at build time
    assert {"validation_blade.py", "validation_dynamic.py", "validation_convergence.py"} <= set(shown)
    filename_pattern, ignore_pattern = fd.gallery_patterns(ROOT / "examples")
    assert re.search(filename_pattern, "/x/examples/fig09_two_region_fs.py")
    assert not re.search(filename_pattern, "/x/examples/validation_blade.py")
    assert re.search(ignore_pattern, "/x/examples/paper_figures.py")
    assert not re.search(ignore_pattern, "/x/examples/fig09_two_region_fs.py")


def test_scene_keys_page_lists_every_key(tmp_path):
    from hbm.scenes import all_keys

    count = fd.write_scene_keys(tmp_path / "keys.md")
    text = (tmp_path / "keys.md").read_text()
    keys = list(all_keys())
    assert count == len(keys) and count > 20
    for key in keys:
        assert f"| `{key}` |" in text, key


def test_every_markdown_page_is_in_the_site(tmp_path):
    pages = fd.write_guides_toctree(DOCS, tmp_path / "toctree.md")
    own = set(fd.OWN_PLACE)
    for md in DOCS.glob("*.md"):
        assert md.stem in pages or md.stem in own, md.name
    assert pages.index("theory") < pages.index("validation")
    index = (DOCS / "index.md").read_text()
    for name in ("getting_started", "changelog", "auto_examples/index", "generated/api/index",
                 "generated/guides_toctree.md"):
        assert name in index


def test_getting_started_scripts_run_and_print_what_the_page_says(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    text = (DOCS / "getting_started.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 2
    monkeypatch.chdir(tmp_path)  # the page writes frf.csv in the current folder
    namespace = {}
    for block in blocks:
        exec(compile(block, "getting_started.md", "exec"), namespace)
    # the numbers the page states in its comments
    assert namespace["a_min"] == pytest.approx(7.5e-7, rel=1e-12)  # mu N/(k L)
    assert (namespace["f_s"], namespace["f_c"]) == pytest.approx((47.65, 7.22), abs=0.005)
    peak = namespace["frf"].peak()
    assert (peak.omega, peak.amplitude) == pytest.approx((38773.5, 1.5119e-6), rel=5e-5)
    other = namespace["pc"].peak()
    assert (other.omega, other.amplitude) == pytest.approx((39697.0, 2.195e-6), rel=5e-4)
    assert (tmp_path / "frf.csv").is_file()


#: A citation of a document that is not in the repository, or of a tracker's issue number.
INTERNAL_CITATION = re.compile(r"DESIGN\.md|CONTRACT\.md|\bissues? [0-9]+|\bissue-[0-9]+", re.IGNORECASE)


def test_no_page_example_or_docstring_cites_internal_documents_or_tracker_numbers():
    files = [*DOCS.glob("*.md"), ROOT / "README.md", *(ROOT / "examples").rglob("*.py"),
             *(ROOT / "examples").rglob("*.toml"), *(ROOT / "examples").rglob("*.mtx")]
    files += [*(ROOT / "hbm").rglob("*.py"), *(ROOT / "contact_models").rglob("*.py")]
    found = []
    for path in files:
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if INTERNAL_CITATION.search(line):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "\n".join(found)


def test_gallery_headers_show_command_lines_as_literal_blocks():
    """A command line with options (``--cells 100``) in a gallery page's header is a literal block,
    so the page shows ``--`` as typed, not turned into an en dash."""
    pytest.importorskip("docutils", reason="the docs extra (pip install -e '.[docs]'); .ci/run installs it")
    from docutils.core import publish_doctree
    from docutils.nodes import literal_block

    executed, shown = fd.gallery_examples(ROOT / "examples")
    for name in executed + shown:
        header = fd.example_header(ROOT / "examples" / name)
        commands = [line.strip() for line in header.splitlines() if line.strip().startswith(("python ", "python3 "))]
        tree = publish_doctree(header, settings_overrides={"report_level": 5})
        literal = "\n".join(node.astext() for node in tree.findall(literal_block))
        for command in commands:
            assert command in literal, f"{name}: {command!r} is not in a literal block"


def test_examples_print_readable_lines_with_paths_relative_to_the_repository(tmp_path, capsys):
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import paper_figures
    finally:
        sys.path.remove(str(ROOT / "examples"))
    paper_figures.show({"force_ratio_x0": {0.01: 0.123456789, 0.2: 2.0}, "path": str(DOCS / "figures" / "fig02.png"),
                        "mode_shape_x0": 0.5})
    out = capsys.readouterr().out
    assert out.splitlines()[0] == "wrote: docs/figures/fig02.png"
    assert "force ratio x0: 0.01: 0.123457, 0.2: 2" in out
    assert str(ROOT) not in out and "{" not in out
    assert paper_figures.display_path(ROOT / "docs" / "figures" / "x.png") == "docs/figures/x.png"
    import warnings  # a warning an example shows names its file relative to the repository too

    text = warnings.formatwarning("outside", UserWarning, str(ROOT / "examples" / "paper_figures.py"), 97)
    assert text == "examples/paper_figures.py:97: UserWarning: outside\n"


def test_quasi_static_validation_draws_a_figure_and_prints_an_aligned_table(tmp_path):
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import validation_quasi_static as vqs
    finally:
        sys.path.remove(str(ROOT / "examples"))
    rows = vqs.main(small=True, ratios=(1.5, 3.0))
    path = vqs.figure(rows, tmp_path)
    assert path.is_file() and path.stat().st_size > 10_000
    text = vqs.table(rows, markdown=False)
    lines = text.splitlines()
    assert "|" not in text and set(lines[1]) <= {"-", " "}
    assert len({len(line) for line in lines[:2]}) == 1  # the rule is as wide as the header
    assert vqs.table(rows).startswith("| load |")  # the Markdown of docs/validation.md, on request


# ------------------------------------------------------------------------------ what a user reads
#: History that belongs in a version-control log, not on a page a user reads: a commit hash (7 to
#: 40 hex digits with at least one digit and one letter, in backticks or after "commit"), the
#: narration of a measurement against an earlier state of the code, a machine's load, a timestamp.
_HASH = r"(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}"
FORBIDDEN = re.compile(
    rf"`{_HASH}`|\bcommits?\s+(?:at\s+|of\s+)?`?{_HASH}\b|\bthe (?:tree|code) before\b"
    r"|\b(?:this|the same) session\b|\bload averages?\b|\b20\d\d-[01]\d-[0-3]\d(?:T|\b)|\bUTC\b",
    re.IGNORECASE)
#: The same hash as the built HTML shows a literal: ``<code ...><span class="pre">9425403</span></code>``.
_HTML_HASH = re.compile(rf'<span class="pre">{_HASH}</span>')


def _forbidden_in(text: str) -> list[str]:
    return [m.group(0) for m in FORBIDDEN.finditer(text)]


def test_forbidden_patterns_catch_history_and_leave_facts_alone():
    """The check itself: what it must find, and legitimate content it must not."""
    caught = ["against 47.1 s for `9425403`, the same session", "at commit 22cf664", "commit `d131efd`",
              "the tree before", "The code before spent", "in this session", "load average 0.6",
              "2026-11-28T04:29", "measured 2026-11-27", "13:45 UTC"]
    for text in caught:
        assert _forbidden_in(text), text
    kept = ["version 0.1.0", "`1e-3`", "tol = 1e-3 (`tol=1e-3`)", "sha256 9255729d2645ef9d of the points",
            "`docs/data/allmode_reference.csv`", "`abcdefgh`", "`1234567`", "a commit message", "the load, 100 N",
            "`deadbeef` is a word", "Commit to a model", "`frf.to_csv()`",
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"]
    assert [t for t in kept if _forbidden_in(t)] == []  # a hex word without a digit or a letter is no hash


def test_pages_and_readme_tell_no_history():
    found = []
    for path in [*sorted(DOCS.glob("*.md")), ROOT / "README.md"]:
        for number, line in enumerate(path.read_text().splitlines(), 1):
            for match in _forbidden_in(line):
                found.append(f"{path.relative_to(ROOT)}:{number}: {match!r}")
    assert not found, "history on a page a user reads:\n" + "\n".join(found)


def _built_site() -> Path | None:
    """The built site: ``FRICTIONDAMP_DOCS_HTML`` (``.ci/run`` sets it), else ``docs/_build/html``
    where the documented build command leaves it; None when neither exists."""
    html = os.environ.get("FRICTIONDAMP_DOCS_HTML")
    path = Path(html) if html else DOCS / "_build" / "html"
    path = path if path.is_absolute() else ROOT / path
    return path if (path / "index.html").is_file() else None


def test_built_pages_tell_no_history():
    site = _built_site()
    if site is None:
        pytest.skip("no built site (docs/_build/html or FRICTIONDAMP_DOCS_HTML)")
    found = []
    for page in sorted(site.rglob("*.html")):
        html = page.read_text(errors="replace")
        text = re.sub(r"<[^>]+>", "", html)
        hits = _forbidden_in(text) + _HTML_HASH.findall(html)
        found += [f"{page.relative_to(site).as_posix()}: {hit!r}" for hit in hits]
    assert not found, "history on the built site:\n" + "\n".join(found[:50])


def _pixels(path: Path):
    from PIL import Image

    with Image.open(path) as image:
        return image.convert("RGBA").size, image.convert("RGBA").tobytes()


def _stock_thumbnails(tmp_path: Path) -> list:
    """sphinx-gallery's stand-ins for a missing figure (``no_image.png``; ``broken_example.png`` for
    a failing script), scaled as it scales a thumbnail (``scale_image`` to ``thumbnail_size``)."""
    from sphinx_gallery.gen_gallery import DEFAULT_GALLERY_CONF
    from sphinx_gallery.gen_rst import scale_image
    from sphinx_gallery import glr_path_static

    size = DEFAULT_GALLERY_CONF["thumbnail_size"]  # docs/conf.py keeps the default

    out = []
    for name in ("no_image.png", "broken_example.png"):
        target = tmp_path / name
        scale_image(str(Path(glr_path_static()) / name), str(target), *size)
        out.append(_pixels(target))
    return out


def test_built_gallery_has_no_placeholder_thumbnails(tmp_path):
    site = _built_site()
    if site is None:
        pytest.skip("no built site (docs/_build/html or FRICTIONDAMP_DOCS_HTML)")
    pytest.importorskip("sphinx_gallery", reason="the docs extra (pip install -e '.[docs]')")
    thumbs = sorted((site / "_images").glob("sphx_glr_*_thumb.png"))
    executed, shown = fd.gallery_examples(ROOT / "examples")
    assert len(thumbs) >= len(executed) + len(shown)
    stock = _stock_thumbnails(tmp_path)
    placeholders = [t.name for t in thumbs if _pixels(t) in stock]
    assert not placeholders, f"gallery thumbnails that are sphinx-gallery's stand-in image: {placeholders}"


def test_gallery_pages_shown_without_running_name_a_committed_thumbnail():
    """A page whose script is not run at build time would get sphinx-gallery's placeholder
    thumbnail: its script names the committed figure its header shows (``sphinx_gallery_thumbnail_path``)."""
    executed, shown = fd.gallery_examples(ROOT / "examples")
    for name in shown:
        source = (ROOT / "examples" / name).read_text()
        match = re.search(r"^# sphinx_gallery_thumbnail_path = [\"'](\S+)[\"']", source, re.MULTILINE)
        assert match, f"{name}: no sphinx_gallery_thumbnail_path"
        assert (DOCS / match.group(1)).is_file(), f"{name}: {match.group(1)} is not committed"


# ------------------------------------------------------------------------- the front door's scripts
def _block_after(text: str, heading: str) -> str:
    """The first ```python block after ``heading`` in a Markdown text."""
    return re.search(rf"^## {re.escape(heading)}\n.*?```python\n(.*?)```", text, re.S | re.M).group(1)


def _jenkins_first_harmonic(kt, fs, a):
    """The Jenkins element's first-harmonic stiffness p + i q at amplitude a, in closed form
    (Caughey's describing function): stuck below a_s = fs/kt; above it cos(beta) = 1 - 2 a_s/a,
    p = (kt/pi)(beta - sin(2 beta)/2), q = W/(pi a^2) with the loop's area W = 4 fs (a - a_s)."""
    import math

    a_s = fs / kt
    if a <= a_s:
        return kt, 0.0
    beta = math.acos(1.0 - 2.0 * a_s / a)
    return kt / math.pi * (beta - 0.5 * math.sin(2.0 * beta)), 4.0 * fs * (a - a_s) / (math.pi * a * a)


def _sdof_peak(m, k, c, force, stiffness_at, w_lo, w_hi):
    """The single-harmonic peak of ``m x'' + c x' + k x + f(x) = F cos(w t)`` for an element whose
    first-harmonic stiffness p + i q depends on the amplitude only: the largest a at which
    ((k + p) - m w^2)^2 + (c w + q)^2 = (F/a)^2 has a real w, by bisection on a (an independent
    solve of the balance, not the library's continuation)."""
    from scipy.optimize import minimize_scalar

    def lowest(a):
        p, q = stiffness_at(a)
        res = minimize_scalar(lambda w: ((k + p) - m * w * w) ** 2 + (c * w + q) ** 2, bounds=(w_lo, w_hi),
                              method="bounded", options={"xatol": 1e-10 * w_hi})
        return res.fun - (force / a) ** 2, res.x

    lo, hi = 1e-9, 1e-3
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if lowest(mid)[0] <= 0.0 else (lo, mid)
        if hi - lo < 1e-13 * hi:
            break
    return lowest(lo)[1], lo


def test_readme_and_home_page_open_with_the_same_ten_line_script_and_it_is_right(capsys):
    readme, home = (ROOT / "README.md").read_text(), (DOCS / "index.md").read_text()
    script = _block_after(readme, "A first script")
    assert script == _block_after(home, "A first script")
    assert len(script.strip().splitlines()) <= 10
    for command in ('python3 -m pip install -e ".[test]" && python3 -m hbm',
                    'python3 -m pip install -e ".[test,fast]" && python3 -m pytest -q'):
        assert command in readme and command in home  # CI runs the second
    assert "frictiondamp" in readme.split("## A first script")[0]  # the installed command is named
    namespace = {}
    exec(compile(script, "README.md", "exec"), namespace)
    out = capsys.readouterr().out
    peaks = {name: (float(w), float(a)) for name, w, a in
             re.findall(r"^(\w+) Peak\(omega=([\d.e+-]+), amplitude=([\d.e+-]+)", out, re.M)}
    blade, micro, macro = namespace["blade"], namespace["micro"], namespace["macro"]
    m, k, c, force = blade.mass, blade.stiffness, blade.damping, blade.force
    # the macroslip match: k* and mu N, its peak against the closed-form describing function
    assert macro.stiffness == pytest.approx(micro.stuck_stiffness(0.0)) and macro.slip_force == pytest.approx(30.0)
    for a in (5e-7, 1.5e-6):
        f_s, f_c = macro.fourier(a, 0.0)
        p, q = _jenkins_first_harmonic(macro.stiffness, macro.slip_force, a)
        assert (f_s, f_c) == pytest.approx((p * a, q * a), rel=1e-9)
    w_ref, a_ref = _sdof_peak(m, k, c, force, lambda a: _jenkins_first_harmonic(macro.stiffness, macro.slip_force, a),
                              3.2e4, 4.4e4)
    w_jen, a_jen = peaks["Macroslip"]
    assert a_jen == pytest.approx(a_ref, rel=1e-5) and w_jen == pytest.approx(w_ref, rel=1e-4)
    # the microslip peak is on the balance and no amplitude above it is reachable either side
    w_mic, a_mic = peaks["TwoRegionMicroslip"]

    def excess(a, w):  # |Z a + f|^2 - F^2 of the single-harmonic balance with the element's f_s, f_c
        f_s, f_c = micro.fourier(a, w)
        return (((k - m * w * w) * a + f_s) ** 2 + (c * w * a + f_c) ** 2) / force**2 - 1.0

    assert abs(excess(a_mic, w_mic)) < 1e-5
    assert excess(a_mic * (1 + 1e-4), w_mic) > 0
    for w in (w_mic * (1 - 5e-4), w_mic * (1 + 5e-4)):
        assert excess(a_mic, w) > 0
    assert a_mic > 1.5 * a_jen  # the bar dissipates less than its macroslip match here


def test_guides_page_runs_as_written(tmp_path, monkeypatch, capsys):
    """docs/guides.md: its blocks run in order in one namespace, and say what they print."""
    monkeypatch.chdir(tmp_path)  # the first block writes frf.csv
    blocks = re.findall(r"^```python\n(.*?)^```", (DOCS / "guides.md").read_text(), re.S | re.M)
    assert len(blocks) == 4
    ns = {}
    for i, block in enumerate(blocks):
        exec(compile(block, f"guides.md[block {i + 1}]", "exec"), ns)
    assert (tmp_path / "frf.csv").is_file()
    peak, best = ns["peak"], ns["best"]
    assert (peak.omega, peak.amplitude) == pytest.approx((38773.6, 1.512e-6), rel=1e-3)
    # the bar with every mode peaks 1.9 % above the single-mode bar (the converged peak of the main job's
    # blade, tests/data/physical_peak_reference.json, is 1.5404e-6 m against 1.512e-6 m), within tol
    assert best.amplitude / peak.amplitude - 1 == pytest.approx(0.019, abs=0.002) and best.estimate < 1e-3
    assert best.interior and best.converged
    # the Jenkins blade at two tolerances agrees within the coarser one
    out = capsys.readouterr().out
    rows = {float(t): float(a) for t, a in re.findall(r"^(0\.01|1e-05) ([\d.e+-]+) ", out, re.M)}
    assert rows[1e-2] == pytest.approx(rows[1e-5], rel=1e-2)
    assert "largest source: model" in out
    # the 2-DOF chain: its contact slides, so it peaks at the free chain's first mode
    frf = ns["frf"]
    assert frf.peak().omega == pytest.approx(((3 - 5**0.5) / 2) ** 0.5, rel=2e-2) and frf.stable.all()


#: Modules a gallery script may not import from, although public: the command line's cases and the
#: balance's internals (the library's front functions give what a user needs).
NOT_FOR_EXAMPLES = ("hbm.cli", "hbm.balance")


def test_gallery_scripts_import_the_public_api_only():
    """Every gallery page's script imports the packages of the API reference (``contact_models``,
    ``hbm``, ``hbm.scenes``, ``hbm.study``) or documented public modules, never the command line's
    or the balance's modules, and no private name; the shared helpers beside them stay importable."""
    import ast

    executed, shown = fd.gallery_examples(ROOT / "examples")
    public = set(fd.public_modules())
    found = []
    for name in executed + shown:
        tree = ast.parse((ROOT / "examples" / name).read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module:
                modules, names = [node.module], [a.name for a in node.names]
            elif isinstance(node, ast.Import):
                modules, names = [a.name for a in node.names], []
            else:
                continue
            for module in modules:
                if module.split(".")[0] not in ("hbm", "contact_models"):
                    continue
                if (module not in public or module.startswith(NOT_FOR_EXAMPLES)
                        or any(n.startswith("_") for n in names)):
                    found.append(f"{name}:{node.lineno}: from {module} import {', '.join(names)}")
    assert not found, "\n".join(found)
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import paper_figures
        import validation_common  # noqa: F401
    finally:
        sys.path.remove(str(ROOT / "examples"))
    assert callable(paper_figures.default_case)


def test_main_job_example_draws_the_landing_figure_with_the_command_lines_answer(tmp_path):
    """examples/main_job.py (the public API) gives the main job's physical curve (its peak within tol of
    the converged peak of tests/data/physical_peak_reference.json), and its macroslip match peaks where the
    closed-form Jenkins describing function puts it."""
    sys.path.insert(0, str(ROOT / "examples"))
    try:
        import main_job
        from paper_figures import default_case
    finally:
        sys.path.remove(str(ROOT / "examples"))
    out = main_job.main(outdir=tmp_path)
    assert Path(out["path"]).stat().st_size > 20_000
    w, a = out["physical_peak"]
    ref = json.loads((ROOT / "tests" / "data" / "physical_peak_reference.json").read_text())  # the converged peak
    assert abs(a / ref["amplitude"] - 1) <= 1e-3 and out["physical_error"] <= 1e-3
    assert 0.017 < a / out["peak"][1] - 1 < 0.021  # the single-mode bar's peak 1.9 % below the physical one
    case = default_case()
    b, k_star = case.blade, case.element.stuck_stiffness(0.0)
    w_ref, a_ref = _sdof_peak(b.mass, b.stiffness, b.damping, b.force,
                              lambda x: _jenkins_first_harmonic(k_star, 30.0, x), 3.2e4, 4.4e4)
    assert out["macroslip_peak"] == pytest.approx((w_ref, a_ref), rel=1e-4)
