"""pytest's settings for the docstring examples of both packages
(``python -m pytest --doctest-modules hbm contact_models``).

A module left at an old path only aliases the new one (``contact_models.numerics.compat.moved_module``):
its examples are the new module's and are collected there; collecting the old file as well would
import the alias under the old file's name, which pytest refuses.
"""

from pathlib import Path

ROOT = Path(__file__).resolve().parent

collect_ignore = [str(path.relative_to(ROOT)) for package in ("hbm", "contact_models")
                  for path in sorted((ROOT / package).rglob("*.py"))
                  if "moved_module(__name__" in path.read_text()]
