"""Harmonics and model chosen along the curve (``hbm.adapt``): windows traced again, one result of segments.

References: the true periodic responses of ``tests/data/periodic_reference.json`` (shooting on the
exact event-driven integration) and the chain's true peak of ``benchmarks/chain_peak_reference.py``
(0.5212270 rad/s, 0.1592898 m); the balance at one H solved by Newton at a point's frequency.
"""

from __future__ import annotations

import csv
import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import hbm.frf
from contact_models import AccuracyWarning, CubicSpring, Macroslip
from hbm import Contact, Steps, Structure, continuation as cont, frequency_response
from hbm.adapt import lift, windows
from hbm.balance import errors
from hbm.balance.residual import HarmonicBalance
from hbm.frf import MAX_HARMONICS, start_harmonics
from hbm.output import csv_lines

DATA = json.loads((Path(__file__).parent / "data" / "periodic_reference.json").read_text())
CHAIN = DATA["chain"]["parameters"]
CHAIN_PEAK = 0.1592898  # m, benchmarks/chain_peak_reference.py
P1 = DATA["jenkins"]["P1"]["peak_amplitude"]["amplitude"]


def chain():
    s = Structure(CHAIN["M"], CHAIN["C"], CHAIN["K"], force=CHAIN["force"])
    return s, [Contact(Macroslip(1.0, 0.02), dof=0), Contact(Macroslip(1.0, 0.05), dofs=(0, 1))]


def one_dof():
    return Structure([[1.0]], [[0.004]], [[1.0]], force=[0.01])


def quiet(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        return frequency_response(*args, **kw)


def from_three(*args, **kw):
    """``quiet`` with the coarse trace at H = 3 (``START_UNKNOWNS = 0``): the chain's sliders are in closed
    form, so ``frequency_response`` would start them at the rung the tolerance predicts; these tests are of
    the ladder from 3 and its windows, which an element with sampled harmonics always climbs."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hbm.frf, "START_UNKNOWNS", 0)
        return quiet(*args, **kw)


@pytest.fixture(scope="module")
def precise():
    """The chain at tol = 1e-5 with steps by accuracy (curve_tol 1e-5): H along the curve from 3."""
    s, cs = chain()
    return from_three(s, cs, omega_range=(0.3, 1.6), tol=1e-5, steps=Steps(max_step=0.1, curve_tol=1e-5),
                      stability=False)


@pytest.fixture(scope="module")
def default():
    """The Jenkins chain of docs/multiharmonic.md at tol = 1e-3, H along the curve from 3."""
    s, cs = chain()
    return from_three(s, cs, omega_range=(0.3, 1.8), tol=1e-3, stability=False)


def at_omega(frf, w):
    """The response DOF's first-harmonic amplitude at the branch's crossings of ``w``, each located
    on the balance of the segment holding it (``hbm.continuation.locate``)."""
    out = []
    for j in np.flatnonzero((frf.omega[:-1] - w) * (frf.omega[1:] - w) <= 0.0):
        f, k = frf._interval(int(j))
        pr = f._problem
        loc = cont.locate(pr, f._run.y[k], f._run.y[k + 1], lambda y, t: y[-1] * pr.omega_ref - w, tol=f.newton_tol,
                          scale=f._scale, xtol=1e-13)
        X = pr.to_physical(loc.y)[0]
        out.append(float(np.hypot(*X[pr.dofs.index(pr.response_dof), 1:3])))
    return out


def newton_at(problem, X, w, tol=1e-12):
    """The balance ``problem`` solved by Newton at the fixed frequency ``w`` from ``X`` (zero-padded)."""
    problem.set_scales(0.3, 1.8)
    u = lift(problem, X, w)
    for _ in range(30):
        R, J = problem(u)
        if np.linalg.norm(R) < tol:
            break
        u[:-1] -= np.linalg.solve(J[:, :-1], R)
    assert np.linalg.norm(R) < 1e-9
    X, _ = problem.to_physical(u)
    return X


# ------------------------------------------------------------------ windows
def test_windows_are_widened_to_the_nodes_below_and_merged():
    e = np.array([0.1, 0.2, 0.9, 0.8, 0.1, 0.1, 0.1, 0.7, 0.1, 0.1])
    assert windows(e, np.array([0, 4, 6, 9]), 0.5, 0, 10) == [(0, 4), (6, 9)]
    assert windows(e, np.array([0, 3, 9]), 0.5, 0, 10) == [(0, 9)]  # (0, 9) and (3, 9) merge
    assert windows(e, np.array([0, 9]), 0.5, 1, 9) == [(1, 8)]  # the stretch's ends where no node is
    assert windows(e, np.array([0, 9]), 0.95, 0, 10) == []


def test_a_window_holding_the_peak_at_its_end_is_widened_to_the_next_node_beyond():
    from hbm.adapt import _widened

    class Coarse:  # what _widened reads of a coarse result: its amplitudes, its estimate nodes, its length
        amplitude = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 4.5, 4.0, 3.0, 2.0, 1.0])
        _nodes = np.array([0, 2, 5, 7, 9])

        def __len__(self):
            return 10

    f = Coarse()
    # the coarse peak (point 4) is the window's last point: widened to node 5, the first beyond it
    assert _widened(f, f.amplitude[2:5], 2, 4, 0) == (2, 5)
    # the same at the window's start, back to the node before it (not before the last window kept)
    assert _widened(f, f.amplitude[4:8], 4, 7, 0) == (2, 7)
    assert _widened(f, f.amplitude[4:8], 4, 7, 3) == (3, 7)
    # a peak inside the window, or an end that is not the curve's peak, leaves it as it is
    assert _widened(f, f.amplitude[2:8], 2, 7, 0) is None
    assert _widened(f, f.amplitude[7:9], 7, 8, 0) is None
    # a refined trace whose peak moved to the end widens the window that its coarse points did not
    assert _widened(f, np.array([4.0, 5.0, 5.2]), 3, 5, 0) == (3, 7)


# ------------------------------------------------------------------ the start where the force is in closed form
def test_a_closed_form_force_is_traced_once_at_the_rung_its_tolerance_predicts():
    """P1 at tol = 1e-5: its slider is in closed form, so the whole range starts at H = 31 (what the ladder
    from 3 reaches near the peak) and no window is traced again; the peak is that of the ladder from 3,
    both within 1e-5 of the true peak (shooting), with fewer points traced in all."""
    cs = [Contact(Macroslip(1.0, 0.02), dof=0)]
    frf = quiet(one_dof(), cs, omega_range=(0.6, 1.8), tol=1e-5)
    ladder = from_three(one_dof(), cs, omega_range=(0.6, 1.8), tol=1e-5)
    assert frf.success and frf.harmonics == 31 and set(frf.point_harmonics) == {31} and len(frf._work) == 1
    assert set(ladder.point_harmonics) == {3, 31} and len(ladder._work) > 1
    assert float(np.max(frf.error_estimate)) < 1e-5
    true = DATA["jenkins"]["P1"]["peak_amplitude"]
    for f in (frf, ladder):
        pk = f.peak()
        assert pk.converged and abs(pk.amplitude / true["amplitude"] - 1.0) < 1e-5
        assert abs(pk.omega / true["omega"] - 1.0) < 1e-5
    assert sum(len(f) for f in frf._work) < 0.8 * sum(len(f) for f in ladder._work)


def test_the_start_follows_the_tolerance_for_closed_forms_on_small_balances_only():
    """``start_harmonics``: 3, 7, 15, 31 for a slider as tol falls; at most the rung of ``START_UNKNOWNS``
    unknowns for a balance of many contact DOFs; 3 for a force with AFT samples (a cubic spring, a slider
    "from rest")."""
    s1 = one_dof()
    slider = [Contact(Macroslip(1.0, 0.02), dof=0)]
    assert [start_harmonics(s1, slider, None, t) for t in (0.2, 1e-2, 1e-3, 1e-4, 1e-6)] == [3, 7, 15, 31, 31]
    n = 10
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    many = Structure(np.eye(n), 0.004 * K, K, force=[0.0] * (n - 1) + [0.01])
    sliders = [Contact(Macroslip(1.0, 0.02), dof=i) for i in range(n)]
    assert start_harmonics(many, sliders, n - 1, 1e-5) == 7  # 10 DOFs: 10 (2H + 1) <= 200 at H = 7, not 15
    assert start_harmonics(s1, [Contact(CubicSpring(1.0), dof=0)], None, 1e-5) == 3
    assert start_harmonics(s1, [Contact(Macroslip(1.0, 0.02, slider="from rest"), dof=0)], None, 1e-5) == 3


# ------------------------------------------------------------------ the chain, precise
def test_chain_peak_is_within_tol_of_the_true_peak_with_high_H_only_near_it(precise):
    pk = precise.peak()
    assert precise.success and abs(pk.amplitude / CHAIN_PEAK - 1.0) < 1e-5
    i = int(np.argmax(precise.amplitude))
    assert precise.point_harmonics[i] == MAX_HARMONICS == precise.harmonics
    assert precise.point_harmonics[0] == precise.point_harmonics[-1] == 3
    far = (precise.omega < 0.45) | ((precise.omega > 0.75) & (precise.omega < 1.3))
    assert np.all(precise.point_harmonics[far] == 3)
    high = precise.omega[precise.point_harmonics == 31]
    assert 0.0 < high.min() < 0.5213 < high.max() and np.ptp(precise.omega[precise.point_harmonics == 31]) < 1.1


def test_segments_describe_the_points(precise):
    seg = precise.segments
    assert seg[0].start == 0 and seg[-1].stop == len(precise) and len(seg) > 3
    assert all(a.stop == b.start for a, b in zip(seg, seg[1:]))
    for sg in seg:
        assert np.all(precise.point_harmonics[sg.start:sg.stop] == sg.harmonics)
        assert set(precise.point_models[sg.start:sg.stop]) == {"Macroslip+Macroslip"} == {sg.model}
    assert precise.n_t == max(sg.n_t for sg in seg)
    C = precise.coefficients(2)
    assert C.shape == (len(precise), 32)
    low = precise.point_harmonics == 3
    assert np.all(C[low, 4:] == 0.0) and np.any(C[~low, 4:] != 0.0)
    np.testing.assert_allclose(np.abs(C[:, 1]), precise.amplitude, rtol=1e-15)
    assert precise.coefficients(1).shape == (len(precise), 32)  # a DOF recovered from the forces


def test_splice_is_continuous(precise):
    w = precise.omega
    assert len(precise.fold_after) == 0 and np.all(np.diff(w) > 0.0)  # no duplicate, no step back
    d = np.hypot(np.diff(w) / np.ptp(w), np.diff(precise.amplitude) / precise.amplitude.max())
    for sg in precise.segments[1:]:  # no gap: the step across a splice is like its neighbours
        i = sg.start - 1
        assert d[i] <= 3.0 * max(d[max(i - 3, 0):i].max(), d[i + 1:i + 4].max())


# ------------------------------------------------------------------ the Jenkins chain, tol = 1e-3
def test_segmented_chain_agrees_with_the_global_high_H_balance(default):
    H = default.harmonics
    assert H > 3 and len(set(default.point_harmonics.tolist())) > 1
    s, cs = chain()
    top = HarmonicBalance(s, cs, harmonics=H, n_t=max(sg.n_t for sg in default.segments), response_dof=2)
    for i in range(0, len(default), 9):
        X = newton_at(top, default._X[i], float(default.omega[i]))
        a = float(np.hypot(*X[top.dofs.index(2), 1:3]))
        assert abs(default.amplitude[i] / a - 1.0) < 1e-3, (i, default.omega[i], default.point_harmonics[i])


def test_segmented_chain_is_within_tol_of_the_true_response(default):
    for ref in DATA["chain"]["points"]:
        for a in at_omega(default, ref["omega"]):
            assert abs(a / ref["amplitude"][2] - 1.0) < 1e-3, ref["omega"]
    assert abs(default.peak().amplitude / CHAIN_PEAK - 1.0) < 1e-3


# ------------------------------------------------------------------ one DOF: stability, CSV, one segment
@pytest.fixture(scope="module")
def p1():
    return from_three(one_dof(), [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8), tol=1e-4)


def test_one_dof_peak_stability_and_counters(p1):
    assert len(p1.segments) > 1 and abs(p1.peak().amplitude / P1 - 1.0) < 1e-4
    assert p1.exponents.shape == (len(p1), 2) and p1.stable.all()  # 2 n_s exponents at any H
    assert p1.nfev > sum(f._problem.nfev for f, _, _ in p1._segments_of[1:2]) > 0
    assert p1.nsteps >= len(p1) - 1 and p1.error_estimate.shape == (len(p1),)
    assert set(p1.error_sources) == {"harmonics", "sampling", "element", "model", "peak"}


def test_csv_has_H_column_where_it_varies(p1, tmp_path):
    rows = list(csv.reader(csv_lines(p1.to_csv(tmp_path / "a.csv").open())))
    head, body = rows[0], rows[1:]
    assert head[-1] == "H" and "model" not in head and len(body) == len(p1)
    assert [int(r[-1]) for r in body] == p1.point_harmonics.tolist()
    assert head[head.index("Xc1_m") + 2 * (p1.harmonics - 1) + 1] == f"Xs{p1.harmonics}_m"
    first = body[0]  # an H = 3 point: its harmonics above 3 are written as zeros
    assert all(float(v) == 0.0 for v in first[head.index("Xc4_m"):head.index("stable")])
    one = frequency_response(one_dof(), [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8),
                             harmonics=3, tol=0.5, stability=False)
    assert len(one.segments) == 1 and one._segments_of is None
    assert "H" not in next(csv.reader(csv_lines(one.to_csv(tmp_path / "b.csv").open())))


def test_one_segment_is_the_plain_solve():
    a = from_three(one_dof(), [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8), tol=0.05,
                   stability=False)
    b = frequency_response(one_dof(), [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8), harmonics=3,
                           tol=0.05, stability=False)
    assert a._segments_of is None and a.harmonics == 3
    np.testing.assert_array_equal(a.amplitude, b.amplitude)
    assert a.peak() == b.peak() and a.nfev == b.nfev


# ------------------------------------------------------------------ the model along the curve
class Standing(Macroslip):
    """A Jenkins element that says it is 1 % off its physical contact above 0.02 m (a stand-in for a
    single-mode bar); its refined model is ``refined`` (a plain Jenkins element, or a failing one)."""

    refined = None

    def _model_error(self, a, omega):
        return np.where(np.asarray(a) > 0.02, 0.01, 0.0)

    def _refined_model(self):
        return self.refined(1.0, 0.02)


class Brittle(Macroslip):
    """A Jenkins element whose evaluation fails above 0.025 m."""

    def _harmonic_force(self, X, omega, n_t, rtol):
        if np.hypot(X[1], X[2]) > 0.025:
            raise FloatingPointError("Brittle: beyond 0.025 m")
        return super()._harmonic_force(X, omega, n_t, rtol)


def model_run(refined):
    el = Standing(1.0, 0.02)
    el.refined = refined
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", AccuracyWarning)
        frf = frequency_response(one_dof(), [Contact(el, dof=0)], omega_range=(0.6, 1.8), harmonics=3, tol=1e-3,
                                 model="auto", stability=False)
    return frf, [str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)]


def test_model_auto_refines_only_the_window_where_the_model_error_is_large():
    frf, _ = model_run(Macroslip)
    models = frf.point_models
    assert set(models.tolist()) == {"Standing", "Macroslip"} and models[0] == models[-1] == "Standing"
    assert frf.amplitude[models == "Macroslip"].max() == frf.amplitude.max()
    assert frf.amplitude[models == "Standing"].min() < 0.02
    assert np.all(frf.error_sources["model"][models == "Macroslip"] == 0.0)
    assert frf.element.__class__ is Macroslip  # the peak's segment
    assert np.all(np.diff(frf.omega[:np.argmax(frf.amplitude)]) > 0.0)


def test_a_failed_window_keeps_the_coarse_points_and_says_so():
    frf, heard = model_run(Brittle)
    plain, _ = model_run(Macroslip)
    assert frf.success and set(frf.point_models.tolist()) == {"Standing"}
    assert "failed" in frf.message and "kept" in frf.message
    assert len(heard) == 1 and "failed" in heard[0] and frf.accuracy_warning == heard[0]
    assert abs(frf.peak().amplitude / plain.peak().amplitude - 1.0) < 1e-6  # the same force law, kept


def test_callbacks_get_the_spliced_points_once_at_the_end(p1):
    got, harm = [], []
    frf = from_three(one_dof(), [Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8), tol=1e-4,
                     on_point=lambda w, xc, xs, r: got.append((w, xc, xs, r)), on_harmonics=lambda w, X: harm.append(X))
    assert len(frf.segments) > 1
    np.testing.assert_array_equal([g[0] for g in got], frf.omega)
    np.testing.assert_array_equal([g[1] for g in got], frf.x_c)
    assert {len(X) for X in harm} == {2 * frf.harmonics + 1}
    np.testing.assert_array_equal(np.array(harm)[:, 1], frf.x_c)


# ------------------------------------------------------------------ the estimate that decides the windows
def test_precise_chain_meets_its_tolerance_and_says_nothing(precise):
    """H along the curve at tol = 1e-5: every point's estimate within tol (no warning), and the peak's
    source, once the peak is located, the Newton tolerance instead of the parabola's bound."""
    assert precise.accuracy_warning is None and float(precise.error_estimate.max()) <= 1e-5
    i = int(np.argmax(precise.amplitude))
    precise.peak()
    # the Newton tolerance relative to the response DOF: the balance's residual is measured against the larger of
    # the static deflection and the contact DOFs' first harmonics (hbm.balance.residual.HarmonicBalance.__call__)
    first = np.sqrt(sum(abs(precise.coefficients(d)[i, 1]) ** 2 for d in precise.dofs))
    scale = max(precise._problem.x_ref, first) / precise.amplitude[i]
    assert scale > 1.0  # the chain's other DOFs move more than its response DOF at the peak
    assert precise.peak_refined and precise.error_sources["peak"][i] == pytest.approx(
        errors.NEWTON_SHARE * precise.rtol * scale, rel=1e-9)


def test_the_harmonics_source_sees_a_resonance_between_the_nodes():
    """At H = 3 the harmonics source is computed at every point: near 0.62 rad/s (3 omega on the
    slipping chain's third mode) it is within a factor 2 of the true error (interpolated between the
    24 nodes it read 2.2e-4 against 1.6e-3)."""
    s, cs = chain()
    frf = quiet(s, cs, omega_range=(0.3, 1.8), harmonics=3, tol=1e-3, stability=False)
    ref = next(p for p in DATA["chain"]["points"] if p["omega"] == 0.62)
    (a,) = at_omega(frf, 0.62)
    true = abs(a / ref["amplitude"][2] - 1.0)
    i = int(np.argmin(np.abs(frf.omega - 0.62)))
    assert true > 1e-3 and frf.error_sources["harmonics"][i] >= 0.5 * true


def test_folds_and_stability_across_a_splice():
    """A hardening Duffing oscillator (a cubic spring, k3 = 1) at tol 1e-4: H = 7 only over part of
    the resonance, the splice between its two folds.  Both folds are located, each in its own
    segment, where the whole curve at H = 7 has them; the middle branch between them, and nothing
    else, is unstable (Hill's method per segment, across the splice)."""
    s = Structure(np.eye(1), [[0.02]], np.eye(1), force=[0.1])
    frf = quiet(s, [Contact(CubicSpring(1.0), dof=0)], omega_range=(0.5, 3.0), tol=1e-4)
    ref = quiet(s, [Contact(CubicSpring(1.0), dof=0)], omega_range=(0.5, 3.0), harmonics=7)
    assert len(frf.fold_after) == 2 == len(ref.fold_after)
    i0, i1 = (int(i) for i in frf.fold_after)
    splices = [sg.start for sg in frf.segments[1:]]
    assert any(i0 < j <= i1 for j in splices)  # the unstable branch is split between two balances
    assert {int(frf.point_harmonics[i0]), int(frf.point_harmonics[i1])} == {3, 7}
    np.testing.assert_allclose(frf.folds_omega, ref.folds_omega, rtol=1e-4)
    np.testing.assert_allclose(frf.folds_amplitude, ref.folds_amplitude, rtol=1e-4)
    unstable = np.flatnonzero(~frf.stable)
    assert unstable.tolist() == list(range(i0 + 1, i1 + 1))
    assert [c.kind for c in frf.stability_changes] == ["fold", "fold"]


def test_a_splices_stability_is_computed_at_the_points_it_keeps_only(monkeypatch):
    """Hill's method on a spliced curve asks each segment's balance for the points the splice keeps of it:
    one perturbation Jacobian per point of the curve (a segment's own trace holds more, its window's overlap),
    and the exponents are each segment's own at those points."""
    from hbm.balance.residual import HarmonicBalance

    s = Structure(np.eye(1), [[0.02]], np.eye(1), force=[0.1])
    frf = quiet(s, [Contact(CubicSpring(1.0), dof=0)], omega_range=(0.5, 3.0), tol=1e-4)
    assert frf._segments_of is not None and sum(len(f) for f, _, _ in frf._segments_of) > len(frf)
    calls, asked = [0], HarmonicBalance.perturbation_jacobian

    def counted(self, *args, **kwargs):
        calls[0] += 1
        return asked(self, *args, **kwargs)

    monkeypatch.setattr(HarmonicBalance, "perturbation_jacobian", counted)
    exponents = frf.exponents
    assert calls[0] == len(frf) and exponents.shape == (len(frf), 2)
    own = np.concatenate([f.exponents[lo:hi] for f, lo, hi in frf._segments_of])  # each segment whole
    np.testing.assert_array_equal(exponents, own)


def test_a_window_whose_lifted_start_fails_is_started_in_stages(monkeypatch):
    """Windows that jump two rungs of H (forced here: H -> 4H + 3) whose start lifted straight from the coarse H
    fails (made to fail here: its first residual raises) are started from the point solved at the H between and
    at their own (``hbm.adapt.staged``); the curve is the one traced without the failure, and no window is given
    up."""
    import hbm.adapt as adapt

    s, cs = chain()
    monkeypatch.setattr(adapt, "next_harmonics", lambda H, excess, top: min(4 * H + 3, top))
    monkeypatch.setattr(hbm.frf, "START_UNKNOWNS", 0)  # the ladder from 3 (the chain's sliders are closed forms)
    plain = quiet(s, cs, omega_range=(0.3, 1.8), tol=1e-3, stability=False)
    trace, staged, failed = adapt.trace, adapt.staged, []

    class FailsFirst:  # the balance whose first residual fails (the window's lifted start)
        def __init__(self, problem):
            self.problem, self.calls = problem, 0

        def __getattr__(self, name):
            return getattr(self.problem, name)

        def __call__(self, u):
            self.calls += 1
            if self.calls == 1:
                raise FloatingPointError("made to fail")
            return self.problem(u)

    def failing(problem, knobs, *, start=None, **kw):  # every window's first start, not its retry
        if start is not None and len(failed) < 3 and not (failed and failed[-1] is None):
            failed.append(None)
            return trace(FailsFirst(problem), knobs, start=start, **kw)
        if failed and failed[-1] is None:
            failed[-1] = True
        return trace(problem, knobs, start=start, **kw)

    calls = []
    monkeypatch.setattr(adapt, "trace", failing)
    monkeypatch.setattr(adapt, "staged", lambda *a: calls.append(a[4:]) or staged(*a))
    frf = quiet(s, cs, omega_range=(0.3, 1.8), tol=1e-3, stability=False)
    assert failed and len(calls) == len(failed) and all(H > H0 for H0, H in calls)
    assert "failed" not in frf.message and len(frf) == len(plain)
    assert frf.peak().amplitude == pytest.approx(plain.peak().amplitude, rel=1e-8)


def test_a_window_widened_into_the_next_one_leaves_it_the_points_after_its_own(monkeypatch):
    """Windows (0, 4) and (6, 9) on the nodes 0, 4, 6, 9, the coarse peak at point 4: the first is traced
    to node 6, so the second is traced from point 7, and the segments hold every point of the coarse
    curve's range once (no point twice where the two windows meet)."""
    import hbm.adapt as adapt

    class Coarse:  # what refine reads of a coarse result
        amplitude = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 4.0, 3.0, 2.0, 1.5, 1.0])
        omega = np.linspace(1.0, 1.9, 10)
        _nodes = np.array([0, 4, 6, 9])
        harmonics, contacts = 1, []
        _estimate_failed = None  # its estimate computed

        def __len__(self):
            return 10

    class Trace:  # a refined trace of the points i0..i1, its peak inside
        _estimate_failed = None

        def __init__(self, i0, i1):
            self.span = (i0, i1)
            self.amplitude = np.r_[0.0, np.ones(i1 - i0 - 1), 0.0]
            self._nodes = np.array([0, i1 - i0])

        def __len__(self):
            return self.span[1] - self.span[0] + 1

    f = Coarse()
    traced = []

    def retrace(setup, g, i0, i1, *args):
        traced.append((i0, i1))
        return Trace(i0, i1)

    monkeypatch.setattr(adapt, "asks", lambda g, k, tol: np.ones(len(g)) * (2.0 if g is f else 0.0))
    monkeypatch.setattr(adapt, "windows", lambda e, nodes, t, lo, hi: [(0, 4), (6, 9)] if e[0] > 1.0 else [])
    monkeypatch.setattr(adapt, "_retrace", retrace)
    knob = adapt.Knob("harmonics", 0.5, lambda g, excess, span: {"H": 3})
    setup = type("Setup", (), {"tolerance": 1e-3})()
    out = adapt.refine(setup, [knob], f, False, frozenset(), [], [], set())
    assert traced == [(0, 6), (7, 9)]
    assert [(type(g).__name__, lo, hi) for g, lo, hi in out] == [("Trace", 0, 7), ("Trace", 0, 3)]
    assert sum(hi - lo for _, lo, hi in out) == len(f)
