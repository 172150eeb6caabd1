"""Sphinx configuration of the frictiondamp documentation site.

Build (no network needed): ``python3 -m sphinx -W -n -b html docs docs/_build/html``, then open
``docs/_build/html/index.html``.  The API reference (``docs/generated/api``), the scene-keys page
the guides' toctree and the architecture page's import tables are written here at build time from the code (``_ext/frictiondamp_docs.py``);
the gallery (``docs/auto_examples``) from ``examples/*.py`` by sphinx-gallery.  None of them is
committed.  ``FRICTIONDAMP_GALLERY_RUN=False`` builds without running the examples (quick drafts).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
EXAMPLES = ROOT / "examples"
GENERATED = DOCS / "generated"
sys.path[:0] = [str(ROOT), str(DOCS / "_ext"), str(EXAMPLES)]  # the worktree's packages first

import frictiondamp_docs as fd  # noqa: E402
import import_graph  # noqa: E402
from contact_models import __version__  # noqa: E402

project = "frictiondamp"
author = "The frictiondamp developers"
copyright = "2026, The frictiondamp developers"
version = release = __version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
]
# MathJax 3 from the package sphinx-mathjax-offline, copied into the site (fd.copy_mathjax): equations
# render with no network
mathjax_path = "mathjax/tex-chtml.js"

exclude_patterns = ["_build", "_ext", "figures", "**/*.ipynb", "auto_examples/*.md5",
                    "auto_examples/*.py", "auto_examples/*.zip"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"

# ---------------------------------------------------------------------------- generated at build
GENERATED.mkdir(exist_ok=True)
API_NAMES = fd.write_api_pages(GENERATED / "api")
SCENE_KEY_COUNT = fd.write_scene_keys(GENERATED / "scene_keys.md")
GUIDES = fd.write_guides_toctree(DOCS, GENERATED / "guides_toctree.md")
MODULE_COUNT = import_graph.write_import_tables(ROOT, GENERATED / "imports.md")  # docs/architecture.md

# --------------------------------------------------------------------------------- theme (furo)
# furo: maintained, one self-contained package (its CSS, JS and fonts ship in the wheel, nothing is
# fetched when a page is opened), light and dark modes, a search box and a left navigation tree that
# suits a site of this size; sphinx-gallery's thumbnails and tables render well in it.
html_theme = "furo"
html_title = f"frictiondamp {release}"
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_show_sourcelink = False
html_last_updated_fmt = None

# -------------------------------------------------------------------------------- MyST (Markdown)
# dollarmath: $...$ and $$...$$; amsmath: \begin{align}...; heading anchors for links "page.md#1-model".
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
myst_heading_anchors = 3

# ------------------------------------------------------------------------------ autodoc / numpydoc
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
# numpy's typing aliases (ArrayLike, NDArray) are shown by name by frictiondamp_docs.short_numpy_types
# (autodoc_type_aliases would render them inside a union as TypeAliasForwardRef(...))
autosummary_generate = False  # the pages are written by frictiondamp_docs.write_api_pages
numpydoc_show_class_members = False  # autodoc's :members: lists them on the class page
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

# Nitpicky mode (-n) checks every cross-reference of the public API.  The exceptions, each with its
# reason: third-party names, because the build is offline (no intersphinx inventories), so numpy,
# scipy, matplotlib and standard-library classes in type hints cannot resolve; and two kinds of type
# hint that name nothing documented.
nitpicky = True
nitpick_ignore_regex = [
    ("py:.*", r"(numpy|np|numpy\.typing|npt)\..*"),  # type hints: np.ndarray, npt.ArrayLike
    ("py:.*", r"(scipy|matplotlib)\..*"),  # type hints: matplotlib.axes.Axes
    ("py:.*", r"(pathlib|os|collections\.abc|typing|types|dataclasses|enum|abc|argparse|concurrent)\..*"),  # stdlib, no inventory
    # Private helper types in signatures (a counter passed between the continuation's own calls).
    ("py:class", r"(contact_models|hbm)(\.\w+)*\._\w+(\.\w+)*"),  # and names in a private module (a base class)
    ("py:class", r"_\w+"),  # the same written bare in a module's own hints (the all-mode bar's ``_Basis``)
    # A module's own alias of numpy's array types in its hints (``Array = NDArray[np.float64]``).
    ("py:class", r"Array(Like)?"),
    ("py:class", "Axes"),  # matplotlib.axes.Axes imported for type checking only: the hint stays a bare name
]

# ------------------------------------------------------------------------------- sphinx-gallery
_FILENAME_PATTERN, _IGNORE_PATTERN = fd.gallery_patterns(EXAMPLES)
sphinx_gallery_conf = {
    "examples_dirs": str(EXAMPLES),
    "gallery_dirs": "auto_examples",
    # Executed: every gallery script without a committed figure in its header (the fast ones).
    "filename_pattern": _FILENAME_PATTERN,
    # Left out: helpers without a reST title in their docstring (paper_figures, validation_common).
    "ignore_pattern": _IGNORE_PATTERN,
    "image_scrapers": ("frictiondamp_docs.saved_png_scraper", "matplotlib"),
    "reset_modules": ("matplotlib", "frictiondamp_docs.redirect_savefig"),
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "min_reported_time": 1,
    "show_signature": False,
    "copyfile_regex": "",
    "plot_gallery": os.environ.get("FRICTIONDAMP_GALLERY_RUN", "True"),
}


def setup(app):
    app.connect("autodoc-process-bases", fd.public_bases)
    app.connect("autodoc-process-signature", fd.short_numpy_types)
    app.connect("autodoc-process-docstring", fd.escape_bars, priority=400)  # before numpydoc (500)
    app.connect("missing-reference", fd.public_reference)
    app.connect("build-finished", fd.copy_mathjax)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
