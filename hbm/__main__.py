"""``python3 -m hbm``: the command line (``hbm.cli.main``)."""

import gc

from .cli.main import main as _main


def main(argv: "list[str] | None" = None) -> int:
    """The command line's entry point (``python3 -m hbm`` and the ``frictiondamp`` console script):
    ``hbm.cli.main.main``, then the process's objects frozen out of the garbage collector's reach."""
    code = _main(argv)
    # Every file is written and closed: what remains is the interpreter's exit, whose garbage
    # collections would walk every object numpy, numba and matplotlib made (about 0.35 s of the main
    # job). Frozen, the objects are still freed by their reference counts as the modules are cleared;
    # the few in reference cycles are left to the operating system, as at any process's end.
    gc.freeze()
    return code


if __name__ == "__main__":
    raise SystemExit(main())
