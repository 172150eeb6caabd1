"""Type hints on the public API: every public function, method and property of
every module of both packages annotates all its parameters and its return.

The public names are those of each package's ``__all__`` and of each listed module (its
``__all__`` where it has one, else its names without a leading underscore), with the classes'
public methods, properties and ``__init__``.  ``MODULES`` is every module of ``contact_models``
and ``hbm`` except the command line script ``hbm.__main__``.
"""

from __future__ import annotations

import functools
import importlib
import inspect

import pytest

import contact_models
import hbm

def _all_modules() -> list[str]:
    """Every module of both packages (private helpers included: their public names are API too)."""
    import pkgutil

    out = []
    for pkg in (contact_models, hbm):
        out.append(pkg.__name__)
        out += [m.name for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + ".")
                if m.name != "hbm.__main__"]  # the command line: a script, not an API
    return out


#: The modules checked: all of them, so a module added later is checked without an edit here.
MODULES = _all_modules()


def _module_names(module) -> list[str]:
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in vars(module) if not n.startswith("_")]
    return list(names)


def _public_callables():
    """(qualified name, function) for every public callable defined in a module of MODULES."""
    seen, out = set(), []

    def add(name, fn):
        if id(fn) not in seen:
            seen.add(id(fn))
            out.append((name, fn))

    roots = [(f"{pkg.__name__}.{n}", getattr(pkg, n)) for pkg in (contact_models, hbm) for n in pkg.__all__]
    for mod_name in MODULES:
        module = importlib.import_module(mod_name)
        roots += [(f"{mod_name}.{n}", getattr(module, n)) for n in _module_names(module)]
    for name, obj in roots:
        if getattr(obj, "__module__", None) not in MODULES:
            continue  # a constant, a module, or a name another module defines
        if inspect.isclass(obj):
            for attr, member in vars(obj).items():
                if attr.startswith("_") and attr != "__init__":
                    continue
                if isinstance(member, property):
                    add(f"{name}.{attr}", member.fget)
                elif isinstance(member, functools.cached_property):
                    add(f"{name}.{attr}", member.func)
                elif isinstance(member, (staticmethod, classmethod)):
                    add(f"{name}.{attr}", member.__func__)
                elif inspect.isfunction(member):
                    add(f"{name}.{attr}", member)
        elif inspect.isfunction(obj):
            add(name, obj)
    return out


CALLABLES = _public_callables()


def test_the_walk_finds_the_public_api():
    names = {n.rsplit(".", 2)[-2] + "." + n.rsplit(".", 1)[-1] for n, _ in CALLABLES}
    for expected in ("NumericalMicroslip.__init__", "NumericalMicroslip.simulate", "Bar.omega_c",
                     "numerical.solve_step", "continuation.continuation", "Blade.from_modal",
                     "GeneralizedAlpha.from_rho_inf", "hbm.simulate_blade"):
        assert expected in names, expected
    assert len(CALLABLES) > 80


@pytest.mark.parametrize("name, fn", CALLABLES, ids=[n for n, _ in CALLABLES])
def test_public_callable_is_annotated(name, fn):
    sig = inspect.signature(fn)
    params = list(sig.parameters.values())
    if params and params[0].name in ("self", "cls"):
        params = params[1:]
    missing = [p.name for p in params if p.annotation is inspect.Parameter.empty]
    if sig.return_annotation is inspect.Signature.empty:
        missing.append("return")
    assert not missing, f"{name}: no annotation on {', '.join(missing)}"
