"""True periodic responses of two one-DOF cases with a time law the shooting reference
(``hbm.periodic_response``, Jenkins and cubic springs only) does not take, computed here without
the harmonic balance, for ``tests/test_estimate_honest.py`` (``tests/data/estimate_references.json``):

- ``gap``: ``x'' + 0.01 x' + x + k max(0, x - g) = F cos(omega t)``, a unilateral spring (``Gap``).
  Shooting on ``(x, v)`` at t = 0 over one period, integrated by DOP853 (rtol 1e-13) segment by
  segment between the contact's closing and opening (located as events, the right-hand side
  linear and smooth on each segment); Newton with the period map's Jacobian from the variational
  equations integrated alongside.  The first harmonic from 2^14 samples of the period (the
  displacement is C^2 with a kink in x''': the trapezoidal rule's error falls like n^-4).
- ``iwan``: ``m x'' + c x' + k x + f = F cos(omega t)`` with Segalman's Iwan element, whose
  steady loop under a cosine force is half-wave symmetric with two reversals a period (checked:
  the velocity keeps its sign between them): from the minimum ``x = -A``, ``v = 0`` at the time
  ``t_r`` the force on the way up is Masing's ``-phi(A) + 2 phi((x + A)/2)`` from the element's
  virgin curve ``phi`` (Segalman's closed form, ``Iwan.loading_curve``); shooting on
  ``(t_r, A)`` so that half a period later ``x = A``, ``v = 0``.

``gap_fold``: the gap at frequencies near its fold, on either side of it (``GAP_FOLD``), by the same shooting.

Run: ``PYTHONPATH=. python3 benchmarks/estimate_references.py [--out PATH]`` (about a minute).
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "tests" / "data" / "estimate_references.json"

#: The Gap case: m = k = 1, c = 0.01, force F, gap element (stiffness, gap); frequencies compared.
GAP = dict(mass=1.0, damping=0.01, stiffness=1.0, force=0.01, k_gap=1.0, gap=0.2)
GAP_OMEGA = [0.98, 1.0, 1.0204, 1.05, 1.08, 1.1]
#: Frequencies near the gap's fold (1.12899 rad/s), on its upper side (the branch's first crossing) and on
#: the side it comes back down (its last crossing above ``FOLD_FLOOR``, below the upper side's amplitude).
GAP_FOLD = [(1.1284, "upper"), (1.1286, "upper"), (1.1288, "upper"), (1.1284, "lower"), (1.1286, "lower"),
            (1.12869, "lower"), (1.128745, "lower"), (1.1288, "lower"), (1.1289, "lower")]
FOLD_FLOOR = 0.5
#: The Iwan case (the Iwan element of tests/test_iwan.py on a blade: slip at every amplitude).
IWAN = dict(mass=1.0, damping=0.004, stiffness=1.0, force=0.01, slip_force=0.02, k_t=1.0, chi=-0.5, beta=0.1)
IWAN_OMEGA = [0.95, 1.0, 1.05, 1.1, 1.15, 1.2]
SAMPLES = 2**14
RTOL = 1e-13


def first_harmonic(x: np.ndarray) -> float:
    """The amplitude of the first harmonic of one period of equally spaced samples."""
    return float(2.0 * abs(np.fft.rfft(x)[1]) / len(x))


# ------------------------------------------------------------------ the gap
def _gap_rhs(p, w, closed):
    kc = p["k_gap"] if closed else 0.0

    def f(t, y):
        x, v = y[0], y[1]
        a = (p["force"] * math.cos(w * t) - p["damping"] * v - p["stiffness"] * x - kc * (x - p["gap"])) / p["mass"]
        # variational equations: d/dt [dx, dv] = [[0, 1], [-(k + kc)/m, -c/m]] [dx, dv], two columns
        Phi = y[2:].reshape(2, 2)
        A = np.array([[0.0, 1.0], [-(p["stiffness"] + kc) / p["mass"], -p["damping"] / p["mass"]]])
        return np.concatenate([[v, a], (A @ Phi).ravel()])
    return f


def gap_period(p, w, y0, t_eval=None):
    """``(y(T), dy(T)/dy0, samples of x at t_eval)`` over one period from ``y0`` at t = 0, segment by
    segment between the contact's changes (the force is continuous at x = g, so the variational state
    carries across unchanged: the saltation matrix is the identity)."""
    T = 2.0 * math.pi / w
    t, y = 0.0, np.concatenate([y0, np.eye(2).ravel()])
    closed = y0[0] > p["gap"]
    ts, xs = [], []
    while True:
        def crossing(t, y):
            return y[0] - p["gap"]
        crossing.terminal = True
        crossing.direction = -1.0 if closed else 1.0  # the next change only: leaving this side
        te = None if t_eval is None else t_eval[t_eval >= t]
        sol = solve_ivp(_gap_rhs(p, w, closed), (t, T), y, method="DOP853", rtol=RTOL, atol=1e-15,
                        events=crossing, t_eval=te, dense_output=t_eval is not None)
        if t_eval is not None:
            end = float(sol.t_events[0][0]) if sol.status == 1 else T
            tt = te[te < end] if sol.status == 1 else te
            ts.append(tt)
            xs.append(sol.sol(tt)[0] if len(tt) else np.empty(0))
        if sol.status != 1:
            y = sol.y[:, -1]
            break
        t, y = float(sol.t_events[0][0]), sol.y_events[0][0].copy()
        closed = not closed
    x = np.concatenate(xs)[np.argsort(np.concatenate(ts))] if t_eval is not None else None
    return y[:2], y[2:].reshape(2, 2), x


def gap_reference(p, w, y0):
    """``(y0, amplitude of the first harmonic, |y(T) - y0|)`` of the periodic response near ``y0``."""
    for _ in range(40):
        yT, Phi, _ = gap_period(p, w, y0)
        dy = np.linalg.solve(Phi - np.eye(2), -(yT - y0))
        y0 = y0 + dy
        if np.max(np.abs(dy)) < 1e-15 * max(1.0, float(np.max(np.abs(y0)))):
            break
    yT = gap_period(p, w, y0)[0]
    T = 2.0 * math.pi / w
    x = gap_period(p, w, y0, np.arange(SAMPLES) * T / SAMPLES)[2]
    assert len(x) == SAMPLES, len(x)
    return y0, first_harmonic(x), float(np.max(np.abs(yT - y0)))


# ------------------------------------------------------------------ the Iwan element
def virgin(p):
    """Segalman's virgin loading curve ``F(u)`` of the four-parameter Iwan element (u >= 0), from its
    density ``R phi^chi`` on (0, phi_max) plus ``S delta(phi - phi_max)``."""
    chi, beta, fs, kt = p["chi"], p["beta"], p["slip_force"], p["k_t"]
    c = (chi + 1.0) / (chi + 2.0)
    phi_max = fs * (1.0 + beta) / (kt * (beta + c))
    R = fs * (chi + 1.0) / (phi_max ** (chi + 2.0) * (beta + c))

    def F(u):
        u = max(u, 0.0)
        return fs if u >= phi_max else kt * u - R * u ** (chi + 2.0) / ((chi + 1.0) * (chi + 2.0))
    return F, phi_max


def iwan_half(p, w, t_r, A, dense=False):
    """From the minimum ``x = -A``, ``v = 0`` at ``t_r``, half a period on the loop's way up."""
    F, phi_max = virgin(p)
    top = -F(A)

    def rhs(t, y):
        f = top + 2.0 * F(0.5 * (y[0] + A))
        return [y[1], (p["force"] * math.cos(w * t) - p["damping"] * y[1] - p["stiffness"] * y[0] - f) / p["mass"]]

    def macro(t, y):  # the last element slips: the force's slope jumps, the integration restarts there
        return 0.5 * (y[0] + A) - phi_max
    macro.terminal, macro.direction = True, 1.0
    T2 = math.pi / w
    t, y, pieces = t_r, [-A, 0.0], []
    while True:
        sol = solve_ivp(rhs, (t, t_r + T2), y, method="DOP853", rtol=RTOL, atol=1e-15 * A, events=macro,
                        dense_output=dense)
        pieces.append(sol)
        if sol.status != 1:
            return sol.y[:, -1], pieces
        t, y = float(sol.t_events[0][0]), sol.y_events[0][0]
        macro.terminal = False  # once past phi_max the force stays F_S (x rises monotonically)


def iwan_reference(p, w, t_r, A):
    """``(t_r, A, amplitude of the first harmonic, max velocity sign violation)`` by Newton on (t_r, A)."""
    def res(z):
        yT, _ = iwan_half(p, w, z[0], z[1])
        return np.array([(yT[0] - z[1]) / z[1], yT[1] / (w * z[1])])
    z = np.array([t_r, A])
    for _ in range(40):
        r = res(z)
        h = np.array([1e-7 / w, 1e-7 * z[1]])
        Jm = np.column_stack([(res(z + np.eye(2)[k] * h[k]) - res(z - np.eye(2)[k] * h[k])) / (2 * h[k])
                              for k in range(2)])
        dz = np.linalg.solve(Jm, -r)
        z = z + dz
        if abs(dz[0]) * w < 1e-14 and abs(dz[1]) < 1e-14 * z[1]:
            break
    T2 = math.pi / w
    _, pieces = iwan_half(p, w, z[0], z[1], dense=True)
    t = z[0] + np.arange(SAMPLES // 2) * T2 / (SAMPLES // 2)

    def at(tt):
        for s in pieces:
            if s.t[0] <= tt <= s.t[-1]:
                return s.sol(tt)
        return pieces[-1].sol(tt)
    Y = np.array([at(tt) for tt in t])
    x = np.concatenate([Y[:, 0], -Y[:, 0]])  # half-wave symmetry: x(t + T/2) = -x(t)
    return z[0], z[1], first_harmonic(x), float(np.min(Y[1:, 1]) / (w * z[1])), float(np.max(np.abs(res(z))))


# ------------------------------------------------------------------ the file
def _first_crossing(frf, w):
    """Index of the point of ``frf`` nearest ``w`` on the branch's first crossing of ``w`` (a guess only)."""
    j = int(np.flatnonzero((frf.omega[:-1] - w) * (frf.omega[1:] - w) <= 0.0)[0])
    return j if abs(frf.omega[j] - w) <= abs(frf.omega[j + 1] - w) else j + 1


def _fold_crossing(frf, w, side):
    """Index of the point of ``frf`` nearest ``w`` on the given side of the fold (``GAP_FOLD``): a guess only."""
    j = np.flatnonzero((frf.omega[:-1] - w) * (frf.omega[1:] - w) <= 0.0)
    if side == "lower":
        j = j[frf.amplitude[j] > FOLD_FLOOR]
    j = int(j[0] if side == "upper" else j[-1])
    return j if abs(frf.omega[j] - w) <= abs(frf.omega[j + 1] - w) else j + 1


def main(argv=None) -> None:
    import sys
    sys.path.insert(0, str(ROOT))
    from contact_models import Gap, Iwan
    from hbm import Blade, Contact, Structure, frequency_response

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    out = {}
    # the branch (and the guess of each shooting) from a harmonic balance: only which periodic response
    p = GAP
    s = Structure([[p["mass"]]], [[p["damping"]]], [[p["stiffness"]]], force=[p["force"]])
    guess = frequency_response(s, [Contact(Gap(p["k_gap"], p["gap"]), dof=0)], omega_range=(0.9, 1.2), harmonics=15)
    points = []
    for w in GAP_OMEGA:
        c = guess.coefficients(0)[_first_crossing(guess, w)]
        h = np.arange(len(c))
        y0 = np.array([float(np.real(np.sum(c))), float(np.real(np.sum(1j * h * w * c)))])
        y0, amp, res = gap_reference(p, w, y0)
        points.append(dict(omega=w, amplitude=amp, state=y0.tolist(), period_residual=res))
        print(f"gap omega={w}: amplitude {amp:.12g} (|y(T) - y0| = {res:.1e})")
    out["gap"] = dict(parameters=p, points=points)
    points = []
    for w, side in GAP_FOLD:
        c = guess.coefficients(0)[_fold_crossing(guess, w, side)]
        h = np.arange(len(c))
        y0 = np.array([float(np.real(np.sum(c))), float(np.real(np.sum(1j * h * w * c)))])
        y0, amp, res = gap_reference(p, w, y0)
        assert res < 1e-10, (w, side, res)  # past the true fold the shooting finds no periodic response here
        points.append(dict(omega=w, side=side, amplitude=amp, state=y0.tolist(), period_residual=res))
        print(f"gap fold omega={w} ({side}): amplitude {amp:.12g} (|y(T) - y0| = {res:.1e})")
    out["gap_fold"] = dict(parameters=p, points=points)
    p = IWAN
    blade = Blade(mass=p["mass"], stiffness=p["stiffness"], damping=p["damping"], force=p["force"])
    guess = frequency_response(blade, Iwan(slip_force=p["slip_force"], stiffness=p["k_t"], chi=p["chi"],
                                           beta=p["beta"]), omega_range=(0.6, 1.8))
    points = []
    for w in IWAN_OMEGA:
        c = guess.coefficients(0)[_first_crossing(guess, w)][1]
        t_r, A, amp, vmin, res = iwan_reference(p, w, (math.pi - float(np.angle(c))) / w, abs(c))
        assert vmin > 0.0, "more than two reversals a period: the half-period shooting does not hold"
        points.append(dict(omega=w, amplitude=amp, minimum_time=t_r, minimum=-A, half_period_residual=res))
        print(f"iwan omega={w}: amplitude {amp:.12g} (residual {res:.1e}, min v/(omega A) {vmin:.2g})")
    out["iwan"] = dict(parameters=p, points=points)
    args.out.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
