"""Speed: the microslip FRF, a scalar ``fourier`` call, ``import`` and ``python3 -m hbm``,
measured against the code of an earlier commit in the same run.

The earlier code (``--baseline``, default 7c28cd0, main at the start of the speed work) is
checked out with ``git archive`` into a temporary folder; every measurement runs in a
subprocess whose ``sys.path`` starts with one tree or the other, and the two trees' workers
alternate (round-robin, ``--rounds`` times, ``--repeats`` timings per worker), so that a change
of the machine's load hits both alike.  Times are process CPU time (the machine is shared; the
load average is recorded); medians over all timings of a tree; ratios are formed from the two
medians of the same run.

Measured:

- ``default FRF``: ``frequency_response`` + ``peak()`` of ``hbm.cli.cases.default_case()`` (a fresh
  case each time, so no loading path is cached), with the number of points and the peak, which
  must agree with the earlier code (same points, peak to 1e-9 relative);
- ``three-region FRF``: the same for ``examples/scenes/three_region_concave_frf.toml`` (the
  scene loaded and planned untimed);
- ``scalar fourier``: ``TwoRegionMicroslip.fourier(2 a_min, omega)`` at a new frequency (200
  frequencies, each new to the element), at a cached one, and a stuck call (0.5 a_min) at new
  frequencies with the number of loading paths it builds;
- ``fused numpy``: the same formulas as the element's scalar call written as one straight numpy
  function (``fused_two_region``): the same 65-point table, one Newton step of the inversion,
  the 12- and 24-node Gauss rules and the end node, without the element's checks (folds, the
  left-end check, bracketing) and bookkeeping; it must agree with ``fourier`` to 1e-10;
- ``free element``: the default FRF replayed with an element that answers every call from a
  dictionary recorded in a first run: the cost of the harmonic balance and continuation alone,
  i.e. the most any faster element (numba, C) could leave;
- ``import``: ``python -X importtime -c "import PKG"``, the package's cumulative microseconds;
- ``python3 -m hbm``: the whole default job (FRF, CSV, PNG) in a child process, its user + system
  CPU time (``resource.getrusage(RUSAGE_CHILDREN)``).

``--profile`` adds where the time of the current code's default FRF goes (cProfile, inclusive
times of the element's stages; cProfile's own cost inflates small calls, so the shares are
indicative).  Run: ``python benchmarks/bench_speed.py`` (about 2 minutes).
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))
from common import checkout  # noqa: E402  (the benchmarks' shared helpers)
BASELINE = "7c28cd0"
THREE_SCENE = "examples/scenes/three_region_concave_frf.toml"
#: The estimate, made before the speed work, of the default FRF's physical floor (s).
FLOOR = 0.045


# ---------------------------------------------------------------------------- workers
def _cpu(fn):
    t = time.process_time()
    value = fn()
    return time.process_time() - t, value


def _default_frf():
    from hbm.cli.cases import default_case
    from hbm.frf import frequency_response

    case = default_case()

    def run():
        frf = frequency_response(case.blade, case.element, omega_range=case.omega_range)
        return frf, frf.peak()

    return _cpu(run)


def _three_frf():
    import hbm
    from hbm.frf import frequency_response
    from hbm.scenes import load_scene, plan_scene

    # the scene file of the tree measured: a later one may set keys the earlier code does not know
    # (effects.phase_differences = "off" keeps the single-mode element, which is all the earlier had)
    plan = plan_scene(load_scene(str(Path(hbm.__file__).resolve().parents[1] / THREE_SCENE)))
    run = plan.runs[0]

    def go():
        frf = frequency_response(plan.blade, run.element, omega_range=tuple(run.omega))
        return frf, frf.peak()

    return _cpu(go)


def _frf_task(make, repeats):
    make()  # warm-up: imports, caches of the code (not of the element: each run makes its own)
    times, last = [], None
    for _ in range(repeats):
        t, last = make()
        times.append(t)
    frf, pk = last
    return {"cpu": times, "points": len(frf), "peak": [pk.omega, pk.amplitude], "nfev": frf.nfev,
            "omega": frf.omega.tolist(), "amplitude": frf.amplitude.tolist()}


def _element():
    from contact_models import Bar, TwoRegionMicroslip, UniformLoad

    bar = Bar(E=2.0e11, rho=7850.0, A=1.0e-5, L=0.05, k=8.0e8, beta=4.0e7, mu=0.3)
    return bar, TwoRegionMicroslip(bar, UniformLoad(N=100.0))


def _scalar_task(repeats):
    import numpy as np

    bar, el = _element()
    a_min = el.slip_amplitude(0.0)
    out = {"new": [], "cached": [], "stuck_new": [], "stuck_paths": 0, "values": None}
    for r in range(repeats + 1):
        ws = 0.3 * bar.omega_c * (1.0 + 1e-4 * (r + 1) + 1e-7 * np.arange(200))
        _, el = _element()
        t, vals = _cpu(lambda: [el.fourier(2.0 * a_min, w) for w in ws])
        t_c, _ = _cpu(lambda: [el.fourier(2.0 * a_min, ws[0]) for _ in ws])
        _, el = _element()
        builds = [0]
        build = el._build_path

        def counted(omega, build=build):
            builds[0] += 1
            return build(omega)

        el._build_path = counted
        t_s, _ = _cpu(lambda: [el.fourier(0.5 * a_min, w) for w in ws])
        if r:  # the first round warms up
            out["new"].append(t / len(ws))
            out["cached"].append(t_c / len(ws))
            out["stuck_new"].append(t_s / len(ws))
            out["stuck_paths"] = builds[0] / len(ws)
        out["values"] = [float(vals[0][0]), float(vals[0][1]), float(ws[0]), 2.0 * a_min]
    return out


@functools.lru_cache(maxsize=None)
def _fused_nodes(table, rules):
    """The table's t (Chebyshev-Lobatto on [0, 1]), the quadrature's tau (both rules, then 0), weights."""
    import numpy as np

    taus, wts = [], []
    for n in rules:
        x, w = np.polynomial.legendre.leggauss(n)
        taus.append(0.5 * (x + 1.0))
        wts.append(0.5 * w)
    return 0.5 * (1.0 - np.cos(np.linspace(0.0, np.pi, table))), np.concatenate(taus + [np.zeros(1)]), wts


def fused_two_region(bar, N, a, omega, table=65, rules=(12, 24), cstep=1e-30):
    """f_s, f_c of the two-region element (uniform load) at one amplitude a, in straight numpy:
    the element's formulas (``region_solution``, the loading curve, its inversion, the Gauss
    rules of the Stieltjes integrals and the stuck stretch) at its node counts, nothing else."""
    import math

    import numpy as np

    S, L, lam, mu, k, beta = bar.E * bar.A, bar.L, math.sqrt(bar.k / (bar.E * bar.A)), bar.mu, bar.k, bar.beta
    q = N / L
    a2 = bar.rho * omega * omega / bar.E
    g2 = k / S - a2
    ga, gg = math.sqrt(a2), math.sqrt(abs(g2))

    def curve(t):  # s, F, ds/dt, dF/dt at L1 = L (1 - t), complex step
        L1 = L * (1.0 - (t + 1j * cstep))
        ell = L - L1
        sn0 = np.tanh(lam * L1) / lam
        k0 = S * (S * lam * lam * sn0 + beta) / (S + beta * sn0)
        if g2 > 0.0:
            c1, sn1 = 1.0, np.tanh(gg * L1) / gg
        else:
            c1, sn1 = np.cos(gg * L1), np.sin(gg * L1) / gg
        kap = S * (S * g2 * sn1 + beta * c1) / (S * c1 + beta * sn1)
        c2, sn2 = np.cos(ga * ell), np.sin(ga * ell) / ga
        den = S * c2 + kap * sn2
        k_mid, t1 = S * (-S * a2 * sn2 + kap * c2) / den, S / den
        D2, dQ = mu / S * q * ell * ell / 2, mu / S * q * ell
        d0 = -D2 / (1.0 + k0 * ell / S)
        x = (mu * q / k - d0) / t1
        F = S * dQ + k0 * d0 + k_mid * x
        return x.real, F.real, x.imag / cstep, F.imag / cstep

    tt, tau, wts = _fused_nodes(table, rules)
    s, F, ds, _ = curve(tt)
    c, sn = (1.0, math.tanh(gg * L) / gg) if g2 > 0.0 else (math.cos(gg * L), math.sin(gg * L) / gg)
    K = S * (S * g2 * sn + beta * c) / (S * c + beta * sn)  # the stuck bar's stiffness (Eq. 14 at L1 = L)
    a_min = s[0]
    j = int(np.searchsorted(s, a))
    u = (a - s[j - 1]) / (s[j] - s[j - 1])
    lo, hi = tt[j - 1], tt[j]
    t = lo + u * u * (3 - 2 * u) * (hi - lo) + (s[j] - s[j - 1]) * u * (1 - u) * ((1 - u) / ds[j - 1] - u / ds[j])
    s1, _, ds1, _ = curve(np.array([t]))
    t_end = t - (s1[0] - a) / ds1[0]
    sq_s, _, _, dF = curve(t_end * (1.0 - tau * tau))
    g = dF * 2.0 * t_end * tau
    Js = np.sqrt(sq_s[:rules[0] + rules[1]] * np.maximum(a - sq_s[:rules[0] + rules[1]], 0.0)) * g[:-1]
    Jc = (a - 2.0 * sq_s[:-1]) * g[:-1]
    Js[:rules[0]] @ wts[0], Jc[:rules[0]] @ wts[0]  # the first rule, compared with the second by the element
    js, jc = Js[rules[0]:] @ wts[1], Jc[rules[0]:] @ wts[1]
    u0 = 2.0 * a_min / a - 1.0  # the stuck stretch [0, a_min], closed form
    js += K * a * a / 8.0 * (math.asin(u0) + u0 * math.sqrt(1.0 - u0 * u0) + math.pi / 2)
    jc += K * (a - a_min) * a_min
    return 8.0 / (math.pi * a) * js, 4.0 / (math.pi * a) * jc


def _fused_task(repeats):
    import numpy as np

    bar, el = _element()
    a = 2.0 * el.slip_amplitude(0.0)
    ws = 0.3 * bar.omega_c * (1.0 + 1e-7 * np.arange(200))
    fused_two_region(bar, 100.0, a, ws[0])
    times = []
    for _ in range(repeats):
        t, _ = _cpu(lambda: [fused_two_region(bar, 100.0, a, w) for w in ws])
        times.append(t / len(ws))
    fs, fc = fused_two_region(bar, 100.0, a, ws[0])
    ref = el.fourier(a, ws[0])
    return {"cpu": times, "rel_diff": max(abs(fs - ref[0]), abs(fc - ref[1])) / abs(complex(*ref))}


class _Replay:
    """An element that answers the solver's calls from a recording of a real element's answers."""

    frequency_dependent = True

    def __init__(self, element):
        self._el, self._rec, self.recording = element, {}, True

    def _call(self, name, *args):
        key = (name,) + tuple(float(v) if not hasattr(v, "tolist") else tuple(v.tolist()) for v in args)
        if self.recording:
            self._rec[key] = getattr(self._el, name)(*args)
        return self._rec[key]

    def fourier(self, a, omega=0.0):
        return self._call("fourier", a, omega)

    def fourier_derivatives_unchecked(self, a, omega, rtol):
        return self._call("fourier_derivatives_unchecked", a, omega, rtol)

    def linear_amplitude(self, omega=0.0):
        return self._call("linear_amplitude", omega)

    def linear_coefficients(self, omega=0.0):
        return self._call("linear_coefficients", omega)

    def stuck_stiffness(self, omega=0.0):
        return self._call("stuck_stiffness", omega)


def _free_task(repeats):
    from hbm.cli.cases import default_case
    from hbm.frf import frequency_response

    case = default_case()
    el = _Replay(case.element)

    def run():
        frf = frequency_response(case.blade, el, omega_range=case.omega_range)
        return frf, frf.peak()

    run()
    el.recording = False
    times = [_cpu(run)[0] for _ in range(repeats)]
    return {"cpu": times}


def _profile_task(repeats):
    return {"default": _profile(_default_frf), "three": _profile(_three_frf)}


def _profile(make):
    import cProfile
    import pstats

    make()  # warm-up
    prof = cProfile.Profile()
    prof.enable()
    make()
    prof.disable()
    st = pstats.Stats(prof).stats
    cum = {}
    for (path, _, name), (_, ncalls, _, ct, _) in st.items():
        if "contact_models" in path or "hbm" in path:
            key = name
            cum[key] = (cum.get(key, (0, 0.0))[0] + ncalls, cum.get(key, (0.0, 0.0))[1] + ct)
    total = sum(v[3] for (p, _, n), v in st.items() if n == "frequency_response" and "hbm" in p)
    total += sum(v[3] for (p, _, n), v in st.items() if n == "peak" and "hbm" in p)
    return {"total": total, "cum": cum}


def _numba_task(repeats):
    import math

    import numpy as np

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    t_import, numba_prototype = _cpu(lambda: __import__("numba_prototype"))
    bar, el = _element()
    tt, tau, wts = _fused_nodes(65, (12, 24))
    S = bar.E * bar.A
    a = 2.0 * el.slip_amplitude(0.0)

    def call(w):
        return numba_prototype.fused_numba(S, bar.L, math.sqrt(bar.k / S), bar.mu, bar.k, bar.beta, 100.0 / bar.L,
                                           bar.rho, bar.E, w, a, tt, tau, wts[0], wts[1], 12)

    w0 = 0.3 * bar.omega_c
    t_compile, (fs, fc) = _cpu(lambda: call(w0))
    ref = el.fourier(a, w0)
    ws = w0 * (1.0 + 1e-7 * np.arange(1, 2001))
    times = [_cpu(lambda: [call(w) for w in ws])[0] / len(ws) for _ in range(repeats)]
    return {"cpu": times, "compile": t_compile, "import": t_import,
            "rel_diff": max(abs(fs - ref[0]), abs(fc - ref[1])) / abs(complex(*ref))}


TASKS = {"default_frf": lambda r: _frf_task(_default_frf, r), "three_frf": lambda r: _frf_task(_three_frf, r),
         "scalar": _scalar_task, "fused": _fused_task, "free": _free_task, "profile": _profile_task,
         "numba": _numba_task}


def _worker(task, repeats):
    print(json.dumps(TASKS[task](repeats)))


# ---------------------------------------------------------------------------- driver
def _env(tree):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(tree)
    return env


def run_worker(tree, task, repeats):
    out = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--worker", task, "--repeats", str(repeats)],
                         cwd=tree, env=_env(tree), capture_output=True, text=True)
    if out.returncode:
        raise RuntimeError(f"worker {task} in {tree} failed:\n{out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def import_time(tree, package):
    out = subprocess.run([sys.executable, "-X", "importtime", "-c", f"import {package}"], cwd=tree, env=_env(tree),
                         capture_output=True, text=True, check=True).stderr
    for line in out.splitlines()[::-1]:
        parts = line.split("|")
        if len(parts) == 3 and parts[2].strip() == package:
            return int(parts[1]) * 1e-6
    raise RuntimeError(f"no import time for {package}")


def import_cpu(tree, package):
    """Process CPU time of ``import package`` in a fresh interpreter (steadier than -X importtime's wall clock)."""
    code = f"import time; t = time.process_time(); import {package}; print(time.process_time() - t)"
    out = subprocess.run([sys.executable, "-c", code], cwd=tree, env=_env(tree), capture_output=True, text=True,
                         check=True).stdout
    return float(out.strip())


def main_job_cpu(tree):
    out = tempfile.mkdtemp(prefix="frictiondamp-job-")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-m", "hbm", "--out", out], cwd=tree, env=_env(tree), check=True,
                   capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    shutil.rmtree(out, ignore_errors=True)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def measure(baseline=BASELINE, rounds=3, repeats=3, log=print):
    base = checkout(baseline)
    trees = {"before": base, "after": ROOT}
    res = {"baseline": baseline, "load_start": os.getloadavg()[0], "rounds": rounds, "repeats": repeats}
    try:
        samples = {k: {"default_frf": [], "three_frf": [], "scalar_new": [], "scalar_cached": [], "stuck_new": [],
                       "import_hbm": [], "import_contact_models": [], "import_cpu_hbm": [],
                       "import_cpu_contact_models": [], "main_job": []} for k in trees}
        last = {}
        for r in range(rounds):
            log(f"round {r + 1}/{rounds} (load {os.getloadavg()[0]:.1f})")
            for name, tree in trees.items():
                d = run_worker(tree, "default_frf", repeats)
                t3 = run_worker(tree, "three_frf", max(1, repeats - 1))
                sc = run_worker(tree, "scalar", repeats)
                s = samples[name]
                s["default_frf"] += d["cpu"]
                s["three_frf"] += t3["cpu"]
                s["scalar_new"] += sc["new"]
                s["scalar_cached"] += sc["cached"]
                s["stuck_new"] += sc["stuck_new"]
                for pkg in ("hbm", "contact_models"):
                    s[f"import_{pkg}"].append(import_time(tree, pkg))
                    s[f"import_cpu_{pkg}"].append(import_cpu(tree, pkg))
                s["main_job"].append(main_job_cpu(tree))
                last[name] = {"default": d, "three": t3, "scalar": sc}
        res["median"] = {k: {m: statistics.median(v) for m, v in s.items()} for k, s in samples.items()}
        res["samples"] = samples
        res["checks"] = {}
        for case in ("default", "three"):
            b, a = last["before"][case], last["after"][case]
            dw = max(abs(x / y - 1) for x, y in zip(a["omega"], b["omega"])) if a["points"] == b["points"] else None
            da = max(abs(x / y - 1) for x, y in zip(a["amplitude"], b["amplitude"])) if a["points"] == b["points"] else None
            res["checks"][case] = {"points": (b["points"], a["points"]), "omega_rel": dw, "amplitude_rel": da,
                                   "peak_rel": [abs(x / y - 1) for x, y in zip(a["peak"], b["peak"])],
                                   "nfev": (b["nfev"], a["nfev"])}
        res["stuck_paths"] = {k: last[k]["scalar"]["stuck_paths"] for k in trees}
        res["fused"] = run_worker(ROOT, "fused", 5)
        res["free"] = run_worker(ROOT, "free", 5)
        res["load_end"] = os.getloadavg()[0]
    finally:
        shutil.rmtree(base, ignore_errors=True)
    return res


STAGES = [("harmonic balance, continuation, scene (outside the element)", None),
          ("element: loading path builds", "_build_path"),
          ("  of which the L1(L2) fit (three regions)", "_fit_L1"),
          ("element: onset a_min (no path)", "_onset"),
          ("element: inversion s(t) = a (one amplitude)", "_invert_one"),
          ("element: Gauss quadrature", "_converged_rules"),
          ("element: region solution, all calls (inside the stages above)", "region_solution")]


def profile_table(prof, label):
    total, cum = prof["total"], prof["cum"]
    element = sum(cum.get(n, (0, 0.0))[1] for n in ("fourier_derivatives_unchecked", "linear_amplitude",
                                                    "linear_coefficients"))
    rows = []
    for stage, name in STAGES:
        t = total - element if name is None else cum.get(name, (0, 0.0))[1]
        calls = "" if name is None else str(cum.get(name, (0, 0.0))[0])
        rows.append(f"| {stage} | {calls} | {t:.3f} | {100 * t / total:.0f} % |")
    other = element - sum(cum.get(n, (0, 0.0))[1] for n in ("_build_path", "_onset", "_invert_one", "_converged_rules"))
    rows.insert(6, f"| element: assembly of f_s, f_c and the rest | | {other:.3f} | {100 * other / total:.0f} % |")
    head = f"| where ({label} FRF + peak, under cProfile) | calls | s | share |\n|---|---|---|---|"
    return head + "\n" + "\n".join(rows) + f"\n| **total under cProfile** | | **{total:.3f}** | 100 % |"


def report(res, prof=None):
    m = res["median"]
    b, a = m["before"], m["after"]

    def row(label, key, unit="s", scale=1.0, fmt="{:.3f}"):
        return (f"| {label} | {fmt.format(b[key] * scale)} {unit} | {fmt.format(a[key] * scale)} {unit} "
                f"| {b[key] / a[key]:.2f} |")

    lines = [f"Baseline {res['baseline']} against the working tree; {res['rounds']} rounds x {res['repeats']} timings, "
             f"medians of process CPU time; load average {res['load_start']:.1f} at the start, "
             f"{res['load_end']:.1f} at the end.", "",
             "| measurement | before | after | before / after |", "|---|---|---|---|",
             row("default FRF + peak (215 points)", "default_frf"),
             row("three-region FRF + peak", "three_frf"),
             row("scalar `fourier`, new frequency", "scalar_new", "ms", 1e3),
             row("scalar `fourier`, cached frequency", "scalar_cached", "ms", 1e3),
             row("stuck `fourier` (0.5 a_min), new frequency", "stuck_new", "ms", 1e3),
             row("`import hbm` (-X importtime, wall clock)", "import_hbm"),
             row("`import contact_models` (-X importtime, wall clock)", "import_contact_models"),
             row("`import hbm`, process CPU", "import_cpu_hbm"),
             row("`import contact_models`, process CPU", "import_cpu_contact_models"),
             row("`python3 -m hbm`, whole job (user + system CPU)", "main_job")]
    c = res["checks"]
    for case, label in (("default", "default"), ("three", "three-region")):
        k = c[case]
        lines.append("")
        lines.append(f"{label} FRF: points {k['points'][0]} before, {k['points'][1]} after; largest relative change "
                     f"of omega {k['omega_rel']:.1e}, of amplitude {k['amplitude_rel']:.1e} along the branch; peak "
                     f"omega {k['peak_rel'][0]:.1e}, amplitude {k['peak_rel'][1]:.1e}; element evaluations "
                     f"{k['nfev'][0]} / {k['nfev'][1]}.")
    f = res["fused"]
    lines.append("")
    lines.append(f"Loading paths built per stuck `fourier` call at a new frequency: {res['stuck_paths']['before']:.2f} "
                 f"before, {res['stuck_paths']['after']:.2f} after.")
    lines.append(f"Fused numpy evaluation of the same formulas (`fused_two_region`): {1e3 * statistics.median(f['cpu']):.3f} ms "
                 f"per call (agrees with `fourier` to {f['rel_diff']:.0e}); the scalar `fourier` call at a new frequency is "
                 f"{a['scalar_new'] / statistics.median(f['cpu']):.2f} times it.")
    free = statistics.median(res["free"]["cpu"])
    lines.append(f"Default FRF with a free element (answers replayed from a recording): {free:.3f} s, "
                 f"{100 * free / a['default_frf']:.0f} % of the FRF after the change; an infinitely fast element "
                 f"would make the FRF at most {a['default_frf'] / free:.1f} times faster. Floor estimate "
                 f"{FLOOR} s: the FRF is {a['default_frf'] / FLOOR:.1f} times it.")
    if "numba" in res:
        nb = res["numba"]
        t_nb = statistics.median(nb["cpu"])
        calls = res["checks"]["default"]["nfev"][1]
        projected = free + calls * t_nb
        lines.append(f"numba prototype (`benchmarks/numba_prototype.py`, the fused formulas compiled): "
                     f"{1e6 * t_nb:.1f} us per scalar call (agrees to {nb['rel_diff']:.0e}), {nb['compile']:.2f} s "
                     f"to compile on first use, {nb['import']:.2f} s to import numba; the default FRF with such an "
                     f"element ({calls} calls) would take about {projected:.3f} s, {a['default_frf'] / projected:.1f} "
                     f"times less than now, before the element's checks are ported.")
    if prof is not None:
        lines += ["", profile_table(prof["default"], "default"), "", profile_table(prof["three"], "three-region")]
    return "\n".join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--worker", help=argparse.SUPPRESS)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--baseline", default=BASELINE)
    p.add_argument("--profile", action="store_true", help="add the profile table of the current code")
    p.add_argument("--json", help="also write the measurements to this file")
    p.add_argument("--numba", action="store_true", help="add the numba prototype (needs numba installed)")
    args = p.parse_args(argv)
    if args.worker:
        _worker(args.worker, args.repeats)
        return
    log = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731
    res = measure(args.baseline, args.rounds, args.repeats, log)
    prof = run_worker(ROOT, "profile", 1) if args.profile else None
    if args.numba:
        res["numba"] = run_worker(ROOT, "numba", 5)
    if args.json:
        Path(args.json).write_text(json.dumps({"result": res, "profile": prof}, default=float))
    print(report(res, prof))


if __name__ == "__main__":
    main()
