import os
from pathlib import Path

import pytest
from hypothesis import settings

from contact_models import Bar, QuadraticLoad, ThreeRegionMicroslip, TwoRegionMicroslip, UniformLoad

# CI is deterministic: the "ci" profile draws the same examples on every run (derandomize).
# "random" is the same with fresh examples each run, to hunt for failures
# (`HYPOTHESIS_PROFILE=random pytest -q --hypothesis-seed=N`); a failure it finds is a bug to fix.
settings.register_profile("ci", max_examples=25, deadline=None, derandomize=True)
settings.register_profile("random", max_examples=25, deadline=None)
settings.register_profile("long", max_examples=400, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

#: The reference bar (docs/theory.md).
BAR = dict(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)


@pytest.fixture(scope="session")
def bar():
    return Bar(**BAR)


@pytest.fixture(scope="session")
def two(bar):
    return TwoRegionMicroslip(bar, UniformLoad(N=100.0))


@pytest.fixture(scope="session")
def three(bar):
    return ThreeRegionMicroslip(bar, QuadraticLoad.from_ratio(N=100.0, ratio=12.0))


#: The default blade with a macroslip damper on the reference bar: the body of the small scenes
#: the study, fault and progress tests run (each adds its title, effects, sweep and study).
MACROSLIP_BLADE = """[blade]
mass = 0.08771473371579717
stiffness = 1.0e8
damping_ratio = 2.0e-3
force = 8.0
[damper]
model = "macroslip"
E = 2.0e11
rho = 7850.0
A = 1.0e-5
L = 0.05
k = 8.0e8
beta = 4.0e7
mu = 0.3
[damper.load]
kind = "uniform"
N = 100.0
"""


def scene_data(path, **changes):
    """The scene file ``path``'s tables as a dict, with ``{"table.key": value}`` changes (None
    deletes a key or a table)."""
    import tomllib  # the standard library's TOML reader, only for the scene tests

    data = tomllib.loads(Path(path).read_text())
    for dotted, value in changes.items():
        *tables, key = dotted.split(".")
        node = data
        for t in tables:
            node = node.setdefault(t, {})
        if value is None:
            node.pop(key, None)
        else:
            node[key] = value
    return data


def scene_problems(data, path, plan=False):
    """The problems (one string, a line each) of the SceneError that reading the scene tables
    ``data`` as the file ``path`` raises (and, with ``plan``, planning it)."""
    from hbm.scenes import SceneError, plan_scene, scene_from_dict  # only for the scene tests

    with pytest.raises(SceneError) as err:
        scene = scene_from_dict(data, path)
        if plan:
            plan_scene(scene)
    return "\n".join(err.value.problems)
