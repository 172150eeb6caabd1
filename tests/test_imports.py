"""``import contact_models`` and ``import hbm`` stay light (issue 15): scipy.optimize,
scipy.integrate and matplotlib are imported where they are used, not at package import."""

import json
import subprocess
import sys

import pytest

#: Heavy modules no package import may pull in (0.1-0.5 s each on the CI machine).
HEAVY = ("scipy.optimize", "scipy.integrate", "matplotlib")


@pytest.mark.parametrize("package", ["contact_models", "hbm"])
def test_package_import_leaves_heavy_modules_out(package):
    code = (f"import sys, json, {package}; "
            f"print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in ('scipy', 'matplotlib'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    loaded = json.loads(out)
    heavy = [m for m in loaded if any(m == h or m.startswith(h + ".") for h in HEAVY)]
    assert heavy == [], f"import {package} imports {heavy}"


def test_heavy_modules_are_imported_when_used():
    """The check above can fail: using a solver that needs scipy.optimize does import it."""
    code = ("import sys, contact_models; "
            "contact_models.Bar(E=2e11, rho=7850, A=1e-5, L=0.05, k=8e8, beta=4e7, mu=0.3).omega_c; "
            "print('scipy.optimize' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "True"
