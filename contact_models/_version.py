"""The library's version, read once from the installed package's metadata (pyproject.toml)."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("frictiondamp")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0+unknown"
