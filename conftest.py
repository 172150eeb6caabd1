"""Collection of the docstring examples (``pytest --doctest-modules contact_models hbm``).

A module left at an old path replaces itself with its new module when imported
(``contact_models.numerics.compat.moved_module``); it holds no example of its own, and importing
it under its file name would only warn, so it is not collected.
"""

from pathlib import Path

ROOT = Path(__file__).resolve().parent
collect_ignore = [str(p.relative_to(ROOT)) for package in ("contact_models", "hbm")
                  for p in sorted((ROOT / package).rglob("*.py"))
                  if "moved_module(__name__" in p.read_text(encoding="utf-8")
                  or "warn_moved(__name__" in p.read_text(encoding="utf-8")]
