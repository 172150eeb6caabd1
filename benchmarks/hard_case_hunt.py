"""Hard cases for the front door ``hbm.frequency_response(system, contacts, omega_range, tol=...)`` at
its default settings (H chosen by the tolerance, default steps), against independent periodic
responses; the references are written to ``tests/data/hard_case_hunt.json``.

Every case is a small structure with Jenkins contacts (``Macroslip``; one with a cubic spring too),
its parameters stored with its references so that ``tests/test_hard_case_hunt.py`` rebuilds
exactly that system (``build``).
What makes each hard is in ``CASES`` (``what``): internal resonances 2:1, 3:1, 5:1, 11:1 reached
by the contact's harmonics, a contact between two masses, two contacts with very different slip
forces, a slip onset at the peak and peaks on a slip-onset corner, a sharp peak, damping down to
1e-4, slip forces tiny and huge against the force, a stiff contact whose stuck and slipped
resonances are far apart, a hardening cubic spring (folds), ranges that start or end on the
resonance, and every case traced in both directions.

References: ``hbm.periodic_response`` / ``hbm.periodic_peak`` (``hbm.reference.shooting``:
shooting on event-driven exact stick/slip integration; it does not use the balance).  Each
reference frequency is compared at the same omega: the balance's branch is solved there
(``at_omega``: the branch point where omega crosses w, located between the two points that
bracket it) and every crossing is compared (a fold gives several); each shooting starts from the
balance's first harmonics there (it selects the branch; the answer is the shooting's).  The true
peak is ``periodic_peak`` in a bracket about the balance's peak.

Per case, direction and tolerance the script records the true relative error of the first-harmonic
amplitude of the response DOF at each reference frequency, the balance's estimate there (the
larger of the two bracketing points' ``error_estimate``), whether an ``AccuracyWarning`` was
emitted, whether the branch reached the end of the range, the peak's error against the true peak,
and the time of the call; and prints which of the contract's properties fail silently:

- a point's true error above ``tol`` with no warning;
- an estimate below half the true error where the true error exceeds tol/10 (warned or not);
- a branch that stops before the end of the range with no warning;
- ``peak()`` more than ``tol`` off the true peak (amplitude) with no warning, or a peak at an
  end of the range not flagged (``interior`` False and a warning).

Run: ``PYTHONPATH=. python3 benchmarks/hard_case_hunt.py [case ...]`` (all cases: a few minutes;
named cases are recomputed and merged into the stored file, the others kept).  ``--check`` only
evaluates the front door against the stored references (no shooting) and prints the table.
"""

from __future__ import annotations

import argparse

import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import hbm
from contact_models import AccuracyWarning, CubicSpring, Macroslip
from hbm import continuation

OUT = Path(__file__).resolve().parents[1] / "tests" / "data" / "hard_case_hunt.json"
#: Tolerances asked of the front door.
TOLS = (1e-3, 1e-5)


# ------------------------------------------------------------------ the systems
def _rotation(phi):
    return np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])


def _attach(n, at):
    b = np.zeros(n)
    if isinstance(at, int):
        b[at] = 1.0
    else:
        b[at[0]], b[at[1]] = 1.0, -1.0
    return b


def two_mode(ratio, zeta, contacts, *, phi=math.pi / 3, force=(1.0, 0.0)):
    """Two DOFs (M = I) whose stuck modes are at exactly 1 and ``ratio`` rad/s (stuck stiffness
    ``Q diag(1, ratio^2) Q^T``, Q the rotation by ``phi``), modal damping ``zeta`` of the stuck modes.

    ``contacts``: ``(at, share, slip_ratio)`` per Jenkins element, ``at`` a DOF or a pair ``(i, j)``;
    its stiffness is ``share`` times the largest the attachment can take out of the stuck stiffness
    with K staying positive semi-definite (``1 / b^T Ks^-1 b``), its slip force the stuck
    resonance's spring force there (linear, all stuck, at 1 rad/s) over ``slip_ratio``.
    """
    Q = _rotation(phi)
    Ks = Q @ np.diag([1.0, ratio**2]) @ Q.T
    C = Q @ np.diag([2 * zeta, 2 * zeta * ratio]) @ Q.T
    stuck = np.linalg.solve(Ks - np.eye(2) + 1j * C, np.asarray(force, dtype=float))
    K, out = Ks.copy(), []
    for at, share, slip_ratio in contacts:
        b = _attach(2, at)
        kj = share / float(b @ np.linalg.solve(Ks, b))
        K -= kj * np.outer(b, b)
        out.append({**({"dof": at} if isinstance(at, int) else {"dofs": list(at)}), "stiffness": kj,
                    "slip_force": abs(b @ stuck) * kj / slip_ratio})
    return {"M": np.eye(2).tolist(), "C": C.tolist(), "K": K.tolist(), "force": list(force), "jenkins": out}


def one_dof(zeta, kt, slip_ratio, *, k=1.0, force=1.0):
    """One DOF (m = 1, spring k to ground) with a Jenkins element of stiffness ``kt``: stuck at
    sqrt(k + kt), slipped at sqrt(k); damping ``zeta`` of the stuck mode; slip force the stuck
    resonance's spring force over ``slip_ratio`` (1: the stuck peak just touches it)."""
    ks = k + kt
    c = 2 * zeta * math.sqrt(ks)
    w = math.sqrt(ks - c * c / 2)  # the stuck linear peak
    a = force / abs(ks - w * w + 1j * c * w)
    return {"M": [[1.0]], "C": [[c]], "K": [[k]], "force": [force],
            "jenkins": [{"dof": 0, "stiffness": kt, "slip_force": a * kt / slip_ratio}]}


def chain3(kj, fs, zeta=0.005):
    """Three unit masses ground-1-2-3 with unit springs, a unit force on DOF 0, a Jenkins element
    between DOFs 1 and 2 (stiffness ``kj``, slip force ``fs``); ``zeta`` modal damping of the stuck
    modes."""
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    b = _attach(3, (1, 2))
    w2, Q = np.linalg.eigh(K + kj * np.outer(b, b))
    C = Q @ np.diag(2 * zeta * np.sqrt(w2)) @ Q.T
    return {"M": np.eye(3).tolist(), "C": C.tolist(), "K": K.tolist(), "force": [1.0, 0.0, 0.0],
            "jenkins": [{"dofs": [1, 2], "stiffness": kj, "slip_force": fs}]}


def stiff_chain(kj, fs, zeta=0.005):
    """The chain ground-k-1-k-2 (k = 1, force 0.1 on DOF 1) with a Jenkins element of stiffness
    ``kj`` at DOF 0 and slip force ``fs``, ``zeta`` modal damping of the stuck modes."""
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    w2, Q = np.linalg.eigh(K + np.diag([kj, 0.0]))
    C = Q @ np.diag(2 * zeta * np.sqrt(w2)) @ Q.T
    return {"M": np.eye(2).tolist(), "C": C.tolist(), "K": K.tolist(), "force": [0.0, 0.1],
            "jenkins": [{"dof": 0, "stiffness": kj, "slip_force": fs}]}


def build(p):
    """``(Structure, contacts)`` of a case's stored parameters."""
    s = hbm.Structure(np.array(p["M"]), np.array(p["C"]), np.array(p["K"]), force=p["force"])
    cs = []
    for j in p["jenkins"]:
        at = {"dof": j["dof"]} if "dof" in j else {"dofs": tuple(j["dofs"])}
        cs.append(hbm.Contact(Macroslip(j["stiffness"], j["slip_force"]), **at))
    for c in p.get("cubic", ()):
        cs.append(hbm.Contact(CubicSpring(c["k3"]), dof=c["dof"]))
    return s, cs


def with_cubic(p, dof, k3):
    """The parameters ``p`` with a cubic spring ``k3 x_dof^3`` added (a hardening Duffing term for k3 > 0)."""
    return {**p, "cubic": [*p.get("cubic", []), {"dof": dof, "k3": k3}]}


#: name: (parameters, omega_range as traced ascending, what makes it hard, peak bracket).  A range
#: given as "peak-start"/"peak-end" starts/ends at the true peak (computed first, stored).
CASES = {
    "ir51": (two_mode(5.0, 0.005, [(0, 0.5, 20.0)]), (0.6, 1.3),
             "5:1 internal resonance: the contact's 5th harmonic drives the mode at 5 rad/s"),
    "ir51_light": (two_mode(5.0, 0.0005, [(0, 0.5, 100.0)]), (0.6, 1.3),
                   "5:1 internal resonance, 0.05 % damping, slip force 1/100"),
    "ir21": (two_mode(2.0, 0.005, [(0, 0.5, 20.0)]), (0.6, 1.3),
             "2:1 modes: the symmetric contact has no even harmonic to drive the upper mode"),
    "ir31_between": (two_mode(3.0, 0.005, [((0, 1), 0.5, 20.0)]), (0.6, 1.3),
                     "3:1 internal resonance through a contact between the two masses"),
    "ir31_vlight": (two_mode(3.0, 1e-4, [(0, 0.5, 50.0)]), (0.6, 1.3),
                    "3:1 internal resonance at 0.01 % damping"),
    "ir31_default": (two_mode(3.0, 0.005, [(0, 0.7, 20.0)]), (0.6, 1.3),
                     "3:1 internal resonance (as tests/test_hard_transitions.py) at default H"),
    "two_contacts": (two_mode(2.7, 0.005, [(0, 0.4, 20.0), (1, 0.4, 0.2)]), (0.6, 1.3),
                     "two contacts: one slips through the resonance, one (slip force 5x) stays stuck"),
    "two_contacts_onset": (two_mode(2.7, 0.005, [(0, 0.4, 20.0), ((0, 1), 0.4, 0.9)]), (0.6, 1.3),
                           "two contacts with slip forces 20x apart: the strong one slips only at the peak"),
    "onset_graze": (one_dof(0.005, 0.3, 1.0), (0.8, 1.4),
                    "slip onset exactly at the stuck peak (slip force = the stuck peak's spring force)"),
    "onset_just": (one_dof(0.005, 0.3, 1.05), (0.8, 1.4),
                   "slip just past onset over a narrow band at the peak"),
    "light_1e4": (one_dof(1e-4, 0.3, 5.0), (0.8, 1.4), "0.01 % damping, slipping at the peak"),
    "light_1e4_onset": (one_dof(1e-4, 0.3, 1.01), (1.1, 1.2),
                        "0.01 % damping with the slip onset 1 % below the stuck peak"),
    "nearly_free": (one_dof(0.005, 0.3, 1000.0), (0.8, 1.4),
                    "slip force 1e-3 of the stuck force: nearly free, friction the main damping"),
    "nearly_stuck": (one_dof(0.005, 0.3, 0.01), (0.8, 1.4), "slip force 100x the stuck force: never slips"),
    "stiff_far": (one_dof(0.005, 99.0, 50.0), (0.5, 12.0),
                  "stiff contact (100 k): stuck at 10 rad/s, slipped at 1, the whole range between"),
    "stiff_1000": (stiff_chain(1000.0, 0.1), (0.5, 1.2),
                   "chain with a contact 1000 k: slowly decaying contact-force harmonics"),
    "chain3_between": (chain3(1.0, 0.05), (0.3, 1.1),
                       "three masses, contact between DOFs 1 and 2: two resonances in the range"),
    "sharp_peak_two": (two_mode(5.0, 1e-4, [(1, 0.5, 100.0), (0, 0.25, 5.0)], phi=math.pi / 6), (0.6, 1.3),
                       "0.01 % damping, two contacts: past the sharp peak the corrector's hyperplane also "
                       "crosses the other flank"),
    "kink_peak_two": (two_mode(1.5, 0.005, [((0, 1), 0.2, 1000.0), (1, 0.1, 1.2)], phi=math.pi / 3), (0.6, 1.3),
                      "the peak is a corner: the stronger of two contacts starts slipping at the maximum"),
    "kink_peak": (two_mode(1.5, 0.02, [((0, 1), 0.2, 1.5)], phi=0.4 * math.pi), (0.6, 1.3),
                  "2 % damping, slip onset just below the stuck peak: the maximum is a corner"),
    "ir111_light": (two_mode(11.0, 1e-4, [(0, 0.5, 50.0)]), (0.6, 1.3),
                    "11:1 internal resonance at 0.01 % damping: the 11th harmonic resonates with Q = 5000"),
    "duffing_jenkins": (with_cubic(one_dof(0.005, 0.3, 3.0), 0, 1e-3), (0.8, 2.0),
                        "hardening cubic spring with a Jenkins contact: two folds, three coexisting responses"),
    "start_on_peak": (one_dof(0.005, 0.3, 5.0), "peak-start", "range starting exactly on the true peak"),
    "end_on_peak": (one_dof(0.005, 0.3, 5.0), "peak-end", "range ending exactly on the true peak"),
    "end_on_peak_ir31": (two_mode(3.0, 0.005, [(0, 0.5, 20.0)]), "peak-end",
                         "3:1 chain, range ending exactly on the true peak"),
    "end_on_ir_peak": (two_mode(3.0, 0.005, [(0, 0.5, 20.0)]), "peak-end",
                       "3:1 chain, range ending on the internal resonance's local maximum (the range's "
                       "largest response)"),
}
#: Where to look for each case's true peak when the range is built from it.
PEAK_SEARCH = {"start_on_peak": (0.8, 1.4), "end_on_peak": (0.8, 1.4), "end_on_peak_ir31": (0.85, 0.95),
               "end_on_ir_peak": (0.98, 1.05)}


# ------------------------------------------------------------------ the balance at one omega
def crossings(frf, w):
    """Indices i with the branch's omega crossing ``w`` between points i and i + 1 (or at a point)."""
    om = frf.omega
    return [int(i) for i in np.flatnonzero((om[:-1] - w) * (om[1:] - w) <= 0.0)]


def at_omega(frf, i, w):
    """``(amplitude, estimate)`` of the branch where omega = w between its points i and i + 1: the
    balance solved there (``continuation.locate`` on the chord of the single-balance result that holds
    the interval); where the chord's Newton fails (a branch bending sharply between two close points),
    the amplitude interpolated linearly between them (the first harmonics' phase may turn fast there;
    the amplitude does not).  The estimate is the larger of the two points'."""
    est = float(max(frf.error_estimate[i], frf.error_estimate[i + 1]))
    for k in (i, i + 1):
        if frf.omega[k] == w:
            return float(frf.amplitude[k]), est
    f, j = frf._interval(i)
    pr = f._problem
    loc = continuation.locate(pr, f._run.y[j], f._run.y[j + 1], lambda y, t: y[-1] * pr.omega_ref - w,
                              tol=f.newton_tol, scale=f._scale, xtol=1e-13)
    if loc is None:
        wa, wb = frf.omega[i], frf.omega[i + 1]
        return float(frf.amplitude[i] + (w - wa) / (wb - wa) * (frf.amplitude[i + 1] - frf.amplitude[i])), est
    X = pr.to_physical(loc.y)[0]
    r = pr.dofs.index(pr.response_dof)
    return float(math.hypot(X[r, 1], X[r, 2])), est


def front_door(p, rng, tol):
    s, cs = build(p)
    t = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        frf = hbm.frequency_response(s, cs, omega_range=tuple(rng), tol=tol)
    said = [str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)]
    return frf, said, time.perf_counter() - t


# ------------------------------------------------------------------ references
def reference_frequencies(frf, lo, hi):
    """Where to compare: near both ends, the quartiles, and the peak with its flanks (0.5, 1, 3
    half-widths either side; the half-width from the balance's half-power band)."""
    a = frf.amplitude
    pk = frf.peak()
    above = frf.omega[a >= pk.amplitude / math.sqrt(2.0)]
    half = max(0.5 * (above.max() - above.min()), 1e-4 * (hi - lo))
    ws = [lo + 0.01 * (hi - lo), lo + 0.25 * (hi - lo), lo + 0.5 * (hi - lo), lo + 0.75 * (hi - lo),
          hi - 0.01 * (hi - lo), pk.omega]
    ws += [pk.omega + s * c * half for c in (0.5, 1.0, 3.0) for s in (-1, 1)]
    return sorted({round(float(w), 12) for w in ws if lo <= w <= hi})


#: The shooting's settings, tried in turn until it converges: the default (512 grid steps, period
#: residual 1e-11), then a finer grid (a slip phase a few grid steps long stalls Newton at 1e-7 on
#: 512 steps at 1e-4 damping; 2048 converges to 2e-11), then a looser residual.
SHOOTING = ({}, {"steps": 2048}, {"steps": 8192, "tol": 1e-9})


def first_harmonics(frf):
    """The first harmonics of every DOF at every branch point (points, n): the shootings' starts."""
    return np.array([frf.coefficients(d)[:, 1] for d in range(frf.structure.n)]).T


def references(p, frfs, ws):
    """The shooting's amplitude at every crossing of each frequency by the branches ``frfs`` (both
    directions: a fold or a jump gives each its own crossings), coexisting responses kept once:
    ``[(w, [amplitudes])]``."""
    s, cs = build(p)
    out = []
    starts = [(frf, first_harmonics(frf)) for frf in frfs]
    for w in ws:
        amps = []
        for frf, X1 in starts:
            for i in crossings(frf, w):
                k = i if abs(frf.omega[i] - w) <= abs(frf.omega[i + 1] - w) else i + 1
                for opts in SHOOTING:
                    r = hbm.periodic_response(s, cs, omega=w, initial=X1[k], floquet=False, **opts)
                    if r.success:
                        break
                assert r.success, (w, r.message)
                a = r.amplitude(frf._problem.response_dof)
                if all(abs(a / b - 1.0) > 1e-8 for b in amps):
                    amps.append(a)
        out.append((w, sorted(amps)))
    return out


def true_peak(p, frfs, lo, hi):
    """The true peak: ``periodic_peak`` between the points four either side of the first branch's
    sampled maximum (within the range; widened while the maximum found is at the bracket's end),
    warm-started from the shooting there (started from the balance's first harmonics); then the
    largest of that and the shootings at each branch's ``peak()`` frequency.  Each is a value of the
    true response, so the largest is the nearest to its maximum: at a corner of the response (a
    contact starting to slip at the maximum) Brent's parabolic steps can stop short of it (measured:
    1e-4 below on ``kink_peak_two``)."""
    s, cs = build(p)
    frf = frfs[0]
    i = int(np.argmax(frf.amplitude))
    r0 = hbm.periodic_response(s, cs, omega=float(frf.omega[i]), initial=first_harmonics(frf)[i], floquet=False)
    rd = frf._problem.response_dof
    for reach in (4, 16, 64):
        b = sorted((float(frf.omega[max(i - reach, 0)]), float(frf.omega[min(i + reach, len(frf) - 1)])))
        b = [max(lo, b[0]), min(hi, b[1])]
        xtol = min(1e-10, (b[1] - b[0]) / 40)
        for opts in SHOOTING:
            P = hbm.periodic_peak(s, cs, bracket=tuple(b), dof=rd, xtol=xtol,
                                  initial=r0 if r0.success else None, **opts)
            if P.success:
                break
        assert P.success, P.message
        if min(P.omega - b[0], b[1] - P.omega) > 20 * xtol or b[0] == lo and P.omega - lo <= 20 * xtol \
                or b[1] == hi and hi - P.omega <= 20 * xtol:
            break
    best = {"omega": P.omega, "amplitude": P.value, "bracket": b}
    for f in frfs:
        pk = f.peak()
        if not lo <= pk.omega <= hi:
            continue
        k = int(np.argmin(np.abs(f.omega - pk.omega)))
        for opts in SHOOTING:
            r = hbm.periodic_response(s, cs, omega=pk.omega, initial=first_harmonics(f)[k], floquet=False, **opts)
            if r.success:
                break
        if r.success and r.amplitude(rd) > best["amplitude"]:
            best = {"omega": pk.omega, "amplitude": r.amplitude(rd), "bracket": b}
    return best


# ------------------------------------------------------------------ evaluation of the contract
def evaluate(case, tol, reverse):
    """The front door against the stored references: a dict of the measured numbers and the list of
    the contract's properties that fail silently."""
    p = case["parameters"]
    lo, hi = case["omega_range"]
    frf, said, dt = front_door(p, (hi, lo) if reverse else (lo, hi), tol)
    warned = bool(said)
    rows, fails = [], []
    for w, refs in case["points"]:
        for i in crossings(frf, w) if refs else ():  # each crossing against the nearest coexisting reference
            a, est = at_omega(frf, i, w)
            rows.append((w, min(abs(a / ref - 1.0) for ref in refs), est))
    true_max = max((e for _, e, _ in rows), default=float("nan"))
    est_max = float(np.max(frf.error_estimate)) if len(frf) else float("nan")
    for w, err, est in rows:
        if err > tol and not warned:
            fails.append(f"omega={w:.6g}: true error {err:.3g} > tol, no warning")
        if err > tol / 10 and est < err / 2:  # a warning does not excuse a wrong estimate
            fails.append(f"omega={w:.6g}: estimate {est:.3g} under-reads the true error {err:.3g}")
    end = lo if reverse else hi
    reached = bool(frf.success) and len(frf) > 0 and abs(frf.omega[-1] - end) <= 1e-9 * end
    if not reached and not warned:
        fails.append(f"stops at omega={frf.omega[-1]:.6g} before the end {end} with no warning")
    pk, ref = frf.peak(), case["peak"]
    peak_err = abs(pk.amplitude / ref["amplitude"] - 1.0)
    if peak_err > tol and not warned:
        fails.append(f"peak amplitude off by {peak_err:.3g} > tol, no warning")
    at_edge = min(abs(ref["omega"] - lo), abs(ref["omega"] - hi)) <= 1e-7 * hi
    if at_edge and (pk.interior or not warned):
        fails.append(f"peak at the range's edge not flagged (interior={pk.interior}, warned={warned})")
    return {"tol": tol, "reverse": reverse, "true_max": true_max, "estimate_max": est_max,
            "estimate_at_worst": max(rows, key=lambda r: r[1])[2] if rows else float("nan"),
            "peak_error": peak_err, "peak_estimate": pk.estimate, "peak_interior": pk.interior,
            "warned": warned, "reached": reached, "time": dt, "points": len(frf), "H": int(frf.harmonics),
            "compared": len(rows), "fails": fails, "warning": said[0] if said else ""}


def compute(name):
    """Shoot the references of case ``name``: parameters, range, reference points and true peak."""
    p, rng, what = CASES[name]
    if isinstance(rng, str):
        b = PEAK_SEARCH[name]
        s, cs = build(p)
        P = hbm.periodic_peak(s, cs, bracket=b, xtol=1e-10)
        assert P.success, P.message
        rng = (P.omega, b[1]) if rng == "peak-start" else (b[0], P.omega)
    lo, hi = rng
    frf, _, _ = front_door(p, (lo, hi), min(TOLS))
    down, _, _ = front_door(p, (hi, lo), min(TOLS))
    ws = reference_frequencies(frf, lo, hi)
    refs = references(p, (frf, down), ws)
    peak = true_peak(p, (frf, down), lo, hi)
    if isinstance(CASES[name][1], str) and P.value > peak["amplitude"]:  # the range's end is the maximum
        peak = {"omega": P.omega, "amplitude": P.value, "bracket": list(b)}
    return {"what": what, "parameters": p, "omega_range": [lo, hi], "points": refs, "peak": peak}


def table(data, names):
    print(f"{'case':20s} {'tol':>6s} {'dir':>4s} {'true max':>9s} {'est max':>9s} {'est@worst':>9s} "
          f"{'peak err':>9s} {'warned':>6s} {'end':>4s} {'H':>3s} {'time':>6s}")
    silent, rows = [], []
    for name in names:
        for tol in TOLS:
            for reverse in (False, True):
                r = evaluate(data[name], tol, reverse)
                rows.append((name, tol, r))
                print(f"{name:20s} {tol:6.0e} {'down' if reverse else 'up':>4s} {r['true_max']:9.2e} "
                      f"{r['estimate_max']:9.2e} {r['estimate_at_worst']:9.2e} {r['peak_error']:9.2e} "
                      f"{str(r['warned']):>6s} {str(r['reached'])[0]:>4s} {r['H']:3d} {r['time']:6.2f}")
                if r["warning"]:
                    print("    warning:", r["warning"][:400])
                for f in r["fails"]:
                    print("    SILENT:", f)
                    silent.append((name, tol, reverse, f))
                sys.stdout.flush()
    markdown(rows)
    return silent


def markdown(rows):
    """The table of ``docs/error_estimates.md`` ("Hard cases through the front door"): one row per case and
    tol, the two directions joined (the worse true error, its estimate, the largest ratio of the two)."""
    print("\n| case | tol | largest true error | estimate there | largest true/estimate | peak error | warned (up, down) "
          "| reached the end (up, down) | time (s, up + down) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for k in range(0, len(rows), 2):
        (name, tol, up), (_, _, down) = rows[k], rows[k + 1]
        worst = max((up, down), key=lambda r: r["true_max"])
        ratio = max(r["true_max"] / r["estimate_at_worst"] if r["estimate_at_worst"] > 0 else math.inf
                    for r in (up, down))
        yn = lambda v: "yes" if v else "no"  # noqa: E731
        print(f"| {name} | {tol:.0e} | {worst['true_max']:.2g} | {worst['estimate_at_worst']:.2g} | {ratio:.2f} "
              f"| {max(up['peak_error'], down['peak_error']):.2g} | {yn(up['warned'])}, {yn(down['warned'])} "
              f"| {yn(up['reached'])}, {yn(down['reached'])} | {up['time'] + down['time']:.2f} |")


def main(argv):
    parser = argparse.ArgumentParser(description="Hard cases through the front door against shooting references.")
    parser.add_argument("cases", nargs="*", metavar="case", help=f"cases to recompute (default: all): {', '.join(CASES)}")
    parser.add_argument("--check", action="store_true", help="evaluate against the stored references only")
    args = parser.parse_args(argv)
    unknown = [c for c in args.cases if c not in CASES]
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)}; the cases: {', '.join(CASES)}")
    check, names = args.check, args.cases or list(CASES)
    data = json.loads(OUT.read_text())["cases"] if OUT.exists() else {}
    if not check:
        for name in names:
            t = time.perf_counter()
            data[name] = compute(name)
            print(f"{name}: references in {time.perf_counter() - t:.1f} s", flush=True)
            OUT.write_text(json.dumps({"reference": "hbm.periodic_response / hbm.periodic_peak (event-driven "
                                       "exact stick/slip integration and shooting)", "cases": data}, indent=1) + "\n")
    silent = table(data, names)
    print(f"{len(silent)} silent failures")
    return silent


if __name__ == "__main__":
    main(sys.argv[1:])
