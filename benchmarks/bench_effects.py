"""What a scene saves by leaving an effect out: the table "Effects: cost of damper inertia" of
docs/performance.md.

Each row is one scene run (``run_scene``: the FRF and its peak, ``summary.json``'s ``time_s``), the
median of ``--repeats`` runs, each from a freshly loaded scene so that no loading path is cached
from the previous run.  "element evals" is the run's ``nfev``; "paths" the loading paths the
microslip element (the wrapped one of a ``QuasiStatic``) builds during the run: with inertia, one
per frequency the trace or the estimate asks; quasi-static, the trace's one at omega = 0 and the
estimate's at the curve's points (the inertia it leaves out, stated in the model source).

Run: ``PYTHONPATH=. python3 benchmarks/bench_effects.py [--repeats 5]``.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import warnings
from pathlib import Path

from hbm.scenes import load_scene, plan_scene, run_scene

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
ROWS = [
    ("default_microslip_frf", "(0.24..0.33 omega_c)", "inertia on", {"effects.inertia": "on"}),
    ("default_microslip_frf", "", "inertia off (`QuasiStatic`)", {"effects.inertia": "off"}),
    ("three_region_concave_frf", "(ratio 12)", "inertia on", {"effects.inertia": "on"}),
    ("three_region_concave_frf", "", "inertia off", {"effects.inertia": "off"}),
    ("quasi_static_low_frequency", "(0.016..0.022 omega_c)", "inertia on", {"effects.inertia": "on"}),
    ("quasi_static_low_frequency", "", "inertia auto (dropped: 3.6e-4 < 1e-3)", {}),
    ("default_microslip_frf", "at N = 3000 N", "slip never reached: linear spring (`StuckContact`)",
     {"damper.load.N": 3000.0}),
]


def counted(element) -> list:
    """Count the loading paths the microslip element inside ``element`` builds (its ``_build_path`` calls)."""
    inner = getattr(element, "element", element)
    built = []
    if hasattr(inner, "_build_path"):
        build = inner._build_path

        def counting(omega):
            built.append(omega)
            return build(omega)

        inner._build_path = counting
    return built


def one(name: str, overrides: dict, folder: Path) -> tuple[float, int, int, int, float]:
    scene = load_scene(SCENES / f"{name}.toml", overrides={**overrides, "output.formats": ["json"]})
    plan = plan_scene(scene)
    built = counted(plan.runs[0].element)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_scene(scene, folder, plan=plan)
    run = result.runs[0]
    return run.seconds, len(run.frf), run.frf.nfev, len(built), run.peak.amplitude


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    print("| scene (examples/scenes) | effects | points | wall (s) | element evals | paths | peak amplitude (m) |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, where, label, overrides in ROWS:
            runs = [one(name, overrides, Path(tmp) / f"r{k}") for k in range(args.repeats)]
            t = statistics.median(r[0] for r in runs)
            _, n, nfev, npaths, peak = runs[-1]
            scene = f"`{name}` {where}".strip() if where or label.startswith("inertia on") else "same"
            print(f"| {scene} | {label} | {n} | {t:.3f} | {nfev} | {npaths} | {peak:.9e} |", flush=True)


if __name__ == "__main__":
    main()
