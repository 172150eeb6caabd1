"""The all-mode FRF's nested solves, counted, and the element's estimate along it against a finer bar.

``python benchmarks/bench_allmode_solves.py --solves [repeats]``: the default case's all-mode FRF at
tol = 1e-3 once to warm up, then ``repeats`` times (default 3) with every nested solve
(``FixedBar.solve``) timed by rung and by who asked (a continuation or a curve estimate), and what the solves
are made of, by coefficients a node: the evaluations of the bar's balance (``FixedBar.evaluate``: the return
map and the AFT), the Jacobians (``jenkins_jacobian``), the factorisations (``factorise``), and, with the
compiled kernels, the Newton loops of more than 20 coefficients a node done in one call each
(``FixedBar.compiled_newton``: their evaluations, Jacobians and factorisations inside it are not counted apart);
and for each continuation the Newton updates its points took.  Medians over the repeats
(docs/performance.md, "The all-mode FRF: one nested solve on the finest rung").

``python benchmarks/bench_allmode_solves.py --survey [tol] [step]``: the same FRF at ``tol`` (default
1e-3); at every ``step``-th point (default 2) the element of that point's rung is asked at the
point's amplitude (``a sin``) for its force and its estimate (``model_error(..., parts=True)``), and
the force is compared with the bar on 512 cells, H = 31 and 496 samples, component by component
relative to max(|f|, 0.01 k* a) as the estimate is (docs/validation.md, "The element's estimate along
the default FRF").
"""

from __future__ import annotations

import collections
import re
import statistics
import sys
import time
import warnings

import numpy as np

from common import machine, machine_line, table

TOL = 1e-3
#: The reference bar of the survey: cells, H, samples.
REFERENCE = (512, 31, 496)


def _frf(tol: float):
    from hbm import frequency_response
    from hbm.cli.cases import default_case

    from contact_models import AllModeMicroslip

    case = default_case()
    el = AllModeMicroslip(case.element.bar, case.element.load, tol=tol)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return case, frequency_response(case.blade, el, omega_range=case.omega_range, tol=tol)


def _wrap(owner, name: str, record) -> None:
    fn = getattr(owner, name)

    def wrapper(*args, **kwargs):
        t = time.perf_counter()
        out = fn(*args, **kwargs)
        record(args, out, time.perf_counter() - t)
        return out

    setattr(owner, name, wrapper)


def solve_rows(repeats: int = 3) -> None:
    """The nested solves of the default all-mode FRF by rung and caller, and the parts of a solve on the
    finest rung (module docstring)."""
    from hbm import continuation as cont
    from hbm.balance import errors

    from contact_models.allmode import coupled as C
    from contact_models.allmode import solve as S

    saved = (S.FixedBar.solve, C.factorise, S.FixedBar.evaluate, S.jenkins_jacobian, S.FixedBar.compiled_newton,
             cont.continuation, errors.estimate)
    caller = ["trace"]
    runs: list = []
    counts: collections.Counter = collections.Counter()
    times: collections.Counter = collections.Counter()
    updates: list = []

    def solved(args, out, dt):
        key = (caller[0], args[0].cells, args[0].H)
        counts[key] += 1
        times[key] += dt

    def part(kind, size):
        def record(args, out, dt):
            counts[(kind, size(args))] += 1
            times[(kind, size(args))] += dt
        return record

    def traced(args, out, dt):
        updates.append(np.bincount(np.asarray(out.iterations, dtype=int), minlength=5)[:5])

    def estimating(fn):
        def wrapper(*args, **kwargs):
            caller[0] = "estimate"
            try:
                return fn(*args, **kwargs)
            finally:
                caller[0] = "trace"
        return wrapper

    _wrap(S.FixedBar, "solve", solved)
    _wrap(C, "factorise", part("factorisations", lambda a: a[0].shape[1]))
    _wrap(S.FixedBar, "evaluate", part("evaluations", lambda a: a[1].shape[1]))
    _wrap(S, "jenkins_jacobian", part("Jacobians", lambda a: a[2].shape[1]))
    _wrap(S.FixedBar, "compiled_newton", part("compiled Newton loops", lambda a: a[2].U.shape[1]))
    _wrap(cont, "continuation", traced)
    errors.estimate = estimating(errors.estimate)
    try:
        _frf(TOL)
        for _ in range(repeats):
            counts.clear()
            times.clear()
            updates.clear()
            t = time.perf_counter()
            _, frf = _frf(TOL)
            runs.append((time.perf_counter() - t, dict(counts), dict(times), [u.copy() for u in updates], len(frf)))
    finally:
        (S.FixedBar.solve, C.factorise, S.FixedBar.evaluate, S.jenkins_jacobian, S.FixedBar.compiled_newton,
         cont.continuation, errors.estimate) = saved
    print(machine_line(machine()))
    print(f"all-mode FRF at tol = {TOL:g}: median of {repeats} {statistics.median(r[0] for r in runs):.2f} s, "
          f"{runs[-1][4]} points")
    keys = sorted(runs[-1][1], key=lambda k: -runs[-1][2][k])

    def med(k, i):
        return statistics.median(r[i].get(k, 0) for r in runs)

    rows = [[" ".join(str(x) for x in k), f"{med(k, 1):.0f}", f"{med(k, 2):.3f} s",
             f"{1e3 * med(k, 2) / max(med(k, 1), 1):.2f} ms"] for k in keys if med(k, 2) >= 0.01]
    print(table(["what (caller or part, cells, H; or part, coefficients a node)", "calls", "time", "each"], rows))
    print("Newton updates per point of each continuation (0, 1, 2, 3, 4):")
    for u in runs[-1][3]:
        print("  ", " ".join(str(int(x)) for x in u))


def survey_rows(tol: float = TOL, step: int = 2) -> None:
    """The element's estimate against the reference bar along the FRF at ``tol`` (module docstring)."""
    from contact_models import AllModeMicroslip

    case, frf = _frf(tol)
    bar, load = case.element.bar, case.element.load
    ref = AllModeMicroslip(bar, load, REFERENCE[0], REFERENCE[1], n_t=REFERENCE[2])
    elements: dict = {}
    rows, above = [], 0
    for i in range(0, len(frf.omega), step):
        m = re.match(r"AllModeMicroslip\(cells=(\d+), H=(\d+)\)", str(frf.point_models[i]))
        if m is None:  # a point of another model (none on the default case)
            continue
        n, H = int(m[1]), int(m[2])
        el = elements.setdefault((n, H), AllModeMicroslip(bar, load, n, H))
        w, a = float(frf.omega[i]), float(frf.amplitude[i])
        X = np.array([0.0, 0.0, a])
        e_s, e_c = (float(v) for v in el.model_error(a, w, parts=True))
        F, Fr = el.harmonic_force(X, w)[0], ref.harmonic_force(X, w)[0]
        floor = 0.01 * bar.k_star * a
        t_s = abs(F[2] - Fr[2]) / max(abs(Fr[2]), floor)
        t_c = abs(F[1] - Fr[1]) / max(abs(Fr[1]), floor)
        ratio = max(t_s / e_s if e_s > 0 else 0.0, t_c / e_c if e_c > 0 else 0.0)
        above += ratio > 1.0
        rows.append([f"{w:.1f}", f"{n}, {H}", f"{a:.3e}", f"{e_s:.1e}", f"{e_c:.1e}", f"{t_s:.1e}", f"{t_c:.1e}",
                     f"{ratio:.2f}"])
    print(machine_line(machine()))
    print(f"all-mode FRF at tol = {tol:g}, {len(frf.omega)} points; one in {step} against {REFERENCE[0]} cells, "
          f"H = {REFERENCE[1]}, {REFERENCE[2]} samples: {above} of {len(rows)} with a component above its estimate")
    print(table(["omega (rad/s)", "rung (cells, H)", "a (m)", "estimate f_s", "estimate f_c", "off f_s", "off f_c",
                 "largest off / estimate"], rows))


if __name__ == "__main__":
    args = sys.argv[1:]
    if args and args[0] == "--survey":
        survey_rows(float(args[1]) if len(args) > 1 else TOL, int(args[2]) if len(args) > 2 else 2)
    elif args and args[0] == "--solves":
        solve_rows(int(args[1]) if len(args) > 1 else 3)
    else:
        sys.exit(__doc__)
