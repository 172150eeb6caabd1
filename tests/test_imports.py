"""``import contact_models`` and ``import hbm`` stay light (import time): scipy.optimize,
scipy.integrate and matplotlib are imported where they are used, not at package import."""

import json
import subprocess
import sys

import pytest

#: Heavy modules no package import may pull in (0.1-0.5 s each on the CI machine).
HEAVY = ("scipy.optimize", "scipy.integrate", "matplotlib")


def _heavy_after(code):
    code += ("; import sys, json; print(json.dumps(sorted(m for m in sys.modules "
             "if m.split('.')[0] in ('scipy', 'matplotlib'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    return [m for m in json.loads(out) if any(m == h or m.startswith(h + ".") for h in HEAVY)]


@pytest.mark.parametrize("package", ["contact_models", "hbm"])
def test_package_import_leaves_heavy_modules_out(package):
    heavy = _heavy_after(f"import {package}")
    assert heavy == [], f"import {package} imports {heavy}"


def test_the_check_sees_a_heavy_import():
    """The check above can fail: a package that imported scipy.optimize would be caught."""
    assert "scipy.optimize" in _heavy_after("import contact_models, scipy.optimize")


def _cases():
    import math

    return [
        (lambda x: x * math.sin(x) - 0.37 * math.cos(x), 0.0, 0.5 * math.pi, dict(xtol=1e-15, rtol=1e-15)),
        (lambda x: x**3 - 2.0 * x - 5.0, 2.0, 3.0, {}),
        (lambda x: math.exp(x) - 1e6, 0.0, 40.0, dict(xtol=1e-300, rtol=8.9e-16)),
        (lambda x: math.tanh(50.0 * (x - 0.3)) + 1e-9, -1.0, 1.0, dict(xtol=1e-14, rtol=4 * 2.220446049250313e-16)),
        (lambda x: (x - 1e-3) * (1.0 + x * x), 0.0, 10.0, dict(xtol=1e-12)),
        (lambda x: -math.atan(x - 7.5), 0.0, 100.0, {}),
    ]


@pytest.mark.parametrize("case", range(6))
def test_own_brentq_matches_scipy_to_the_bit(case):
    from scipy.optimize import brentq as scipy_brentq

    from contact_models.numerics.roots import brentq

    f, a, b, kw = _cases()[case]
    calls_own, calls_scipy = [], []
    root = brentq(lambda x: calls_own.append(x) or f(x), a, b, **kw)
    ref = scipy_brentq(lambda x: calls_scipy.append(x) or f(x), a, b, **kw)
    assert root == ref
    assert calls_own == calls_scipy  # the same iterates, not only the same end point


def test_own_brentq_refuses_like_scipy():
    import math

    from contact_models.numerics.roots import brentq

    with pytest.raises(ValueError, match="different signs"):
        brentq(lambda x: x * x + 1.0, -1.0, 1.0)
    with pytest.raises(ValueError, match="NaN"):
        brentq(lambda x: float("nan") if x > 0.5 else -1.0, 0.0, 1.0)
    with pytest.raises(RuntimeError, match="maxiter"):
        brentq(lambda x: math.tanh(50.0 * (x - 0.3)), -1.0, 1.0, maxiter=3)
