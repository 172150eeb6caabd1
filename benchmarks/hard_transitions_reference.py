"""Independent references for ``tests/test_hard_transitions.py``: the periodic responses of the
hard continuation cases by time integration and shooting, written to ``tests/data/hard_transitions.json``.

Each case is a small structure (M = I) with one contact, its parameters stored with its
reference so that the test builds exactly the system measured here:

- ``ir31``: two DOFs whose stuck modes are at exactly 1 and 3 rad/s (the stuck stiffness
  ``K + k_j e0 e0^T = Q diag(1, 9) Q^T``, Q the rotation by 60 degrees, ``k_j = 0.3 (Q diag(1, 9) Q^T)_00``),
  0.5 % modal damping of the stuck modes, a unit force on DOF 0 and a Jenkins element at DOF 0
  whose slip force is 1/20 of the stuck resonance's spring force there (slips over most of the
  resonance; its third harmonic drives the mode at 3 rad/s);
- ``ir31_light``: the same with 0.05 % damping and a slip force 1/100 of the stuck resonance's;
- ``stiff``: the chain ground-k-1-k-2 (k = 1, force 0.1 on DOF 1) with a Jenkins element of
  stiffness 100 k at DOF 0, slip force 0.1, 0.5 % damping of the stuck modes;
- ``ir21_gap``: two DOFs whose modes with the gap open are at exactly 1 and 2 rad/s (Q by 30
  degrees), 1 % modal damping, a unilateral spring (``Gap``) at DOF 0 that closes near the first
  resonance; the gap is the asymmetry whose even harmonics reach the mode at 2 rad/s;
- ``gap``: one DOF (m = k = 1, 2 % damping) against a gap spring of stiffness 2 k.

Jenkins cases: ``hbm.periodic_response`` / ``hbm.periodic_peak`` (event-driven exact stick/slip
integration and shooting, ``hbm.reference.shooting``).  Gap cases: the same method written here,
since that reference has no unilateral spring: between contact events the motion is linear and
integrated by DOP853 at rtol 1e-12, the events (the gap's relative displacement crossing zero)
located by the integrator's root finding, and Newton on ``Phi_T(y0) - y0`` with a forward
difference Jacobian; the first harmonic from 1024 samples of the period by FFT.  Neither uses the
harmonic balance.  Peaks: Brent's bounded search over omega (warm-started shooting).

Run: ``PYTHONPATH=. python3 benchmarks/hard_transitions_reference.py [case ...]`` (the Jenkins
cases take about ten seconds each; the gap's shooting with difference Jacobians much longer).
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

import hbm
from contact_models import Gap, Macroslip

OUT = Path(__file__).resolve().parents[1] / "tests" / "data" / "hard_transitions.json"
#: Samples per period of the references' first harmonic.
SAMPLES = 1024


def _rotation(phi):
    return np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])


def internal_resonance_chain(ratio, zeta, slip_ratio, phi=math.pi / 3, share=0.3, force=1.0):
    """The two-DOF chain whose stuck modes are at 1 and ``ratio`` rad/s, with a Jenkins element at DOF 0."""
    Q = _rotation(phi)
    Ks = Q @ np.diag([1.0, ratio**2]) @ Q.T
    kj = share * Ks[0, 0]
    K = Ks.copy()
    K[0, 0] -= kj
    C = Q @ np.diag([2 * zeta, 2 * zeta * ratio]) @ Q.T
    stuck = np.linalg.solve(Ks - np.eye(2) + 1j * C, [force, 0.0])  # at the stuck resonance
    return {"M": np.eye(2).tolist(), "C": C.tolist(), "K": K.tolist(), "force": [force, 0.0],
            "jenkins": {"dof": 0, "stiffness": kj, "slip_force": abs(stuck[0]) * kj / slip_ratio}}


def stiff_chain():
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    kj = 100.0
    w2, Q = np.linalg.eigh(K + np.diag([kj, 0.0]))
    C = Q @ np.diag(2 * 0.005 * np.sqrt(w2)) @ Q.T
    return {"M": np.eye(2).tolist(), "C": C.tolist(), "K": K.tolist(), "force": [0.0, 0.1],
            "jenkins": {"dof": 0, "stiffness": kj, "slip_force": 0.1}}


def gap_chain():
    Q = _rotation(math.pi / 6)
    K = Q @ np.diag([1.0, 4.0]) @ Q.T
    C = Q @ np.diag([2 * 0.01, 2 * 0.01 * 2.0]) @ Q.T
    return {"M": np.eye(2).tolist(), "C": C.tolist(), "K": K.tolist(), "force": [0.02, 0.0],
            "gap": {"dof": 0, "stiffness": 0.5, "gap": 0.5}}


def gap_oscillator():
    return {"M": [[1.0]], "C": [[0.04]], "K": [[1.0]], "force": [0.05],
            "gap": {"dof": 0, "stiffness": 2.0, "gap": 0.6}}


CASES = {
    "ir31": (internal_resonance_chain(3.0, 0.005, 20.0), (0.6, 1.3), [0.8, 0.95, 1.0, 1.05, 1.2]),
    "ir31_light": (internal_resonance_chain(3.0, 0.0005, 100.0), (0.6, 1.3), [0.8, 0.95, 1.0, 1.05, 1.2]),
    "stiff": (stiff_chain(), (0.5, 1.2), [0.55, 0.58, 0.6, 0.7, 1.0]),
    "ir21_gap": (gap_chain(), (0.7, 1.3), [0.8, 0.95, 1.05, 1.2]),
    "gap": (gap_oscillator(), (0.7, 1.5), [0.8, 1.0, 1.2, 1.4]),
}


def build(case):
    """``(Structure, contacts)`` of a case's parameters (the test builds them the same way)."""
    s = hbm.Structure(np.array(case["M"]), np.array(case["C"]), np.array(case["K"]), force=case["force"])
    if "jenkins" in case:
        j = case["jenkins"]
        return s, [hbm.Contact(Macroslip(j["stiffness"], j["slip_force"]), dof=j["dof"])]
    g = case["gap"]
    return s, [hbm.Contact(Gap(g["stiffness"], g["gap"]), dof=g["dof"])]


# ------------------------------------------------------------------ gap: event-driven shooting
class GapShooting:
    """Periodic response of ``M x'' + C x' + K x + e k_g max(0, x_d - g) = f cos(omega t)``."""

    def __init__(self, case):
        self.M = np.array(case["M"])
        self.C = np.array(case["C"])
        self.K = np.array(case["K"])
        self.f = np.array(case["force"])
        g = case["gap"]
        self.d, self.kg, self.g = g["dof"], g["stiffness"], g["gap"]
        self.n = len(self.f)
        self.Minv = np.linalg.inv(self.M)

    def _rhs(self, closed, omega):
        n, d = self.n, self.d

        def rhs(t, y):
            x, v = y[:n], y[n:]
            F = self.f * math.cos(omega * t) - self.C @ v - self.K @ x
            if closed:
                F[d] -= self.kg * (x[d] - self.g)
            return np.concatenate([v, self.Minv @ F])

        return rhs

    def period(self, y0, omega, samples=None):
        """The state after one period (and the samples of x at ``samples`` points if given)."""
        T = 2 * math.pi / omega
        n, d = self.n, self.d
        t, y = 0.0, np.array(y0, dtype=float)
        grid = np.linspace(0.0, T, samples, endpoint=False) if samples else None
        xs = []
        while t < T * (1 - 1e-15):
            closed = y[d] > self.g or (y[d] == self.g and y[n + d] > 0)

            def event(tt, yy):
                return yy[d] - self.g

            event.terminal = True
            sol = solve_ivp(self._rhs(closed, omega), (t, T), y, method="DOP853", rtol=1e-12, atol=1e-14,
                            events=event, dense_output=samples is not None)
            t_end = sol.t[-1]
            if grid is not None:
                inside = grid[(grid >= t) & (grid < t_end)] if t_end < T else grid[grid >= t]
                if inside.size:
                    xs.append(sol.sol(inside)[:n].T)
                grid = grid[grid >= t_end] if t_end < T else grid[:0]
            y = sol.y[:, -1].copy()
            if sol.status == 1:  # an event: step a hair past it on the other side
                t = t_end
                y[d] = self.g
            else:
                t = T
        return y, (np.concatenate(xs) if xs else None)

    def solve(self, omega, y0, tol=1e-11, max_iter=30):
        y = np.array(y0, dtype=float)
        scale = max(1e-3, float(np.max(np.abs(y))))
        for _ in range(max_iter):
            r = self.period(y, omega)[0] - y
            if np.max(np.abs(r)) <= tol * scale:
                return y
            J = np.empty((y.size, y.size))
            for k in range(y.size):
                h = 1e-7 * max(scale, abs(y[k]))
                e = y.copy()
                e[k] += h
                J[:, k] = (self.period(e, omega)[0] - e - r) / h
            y = y - np.linalg.solve(J, r)
        raise RuntimeError(f"gap shooting did not converge at omega={omega}")

    def amplitude(self, omega, y, dof):
        x = self.period(y, omega, SAMPLES)[1][:, dof]
        c = np.fft.rfft(x)[1] * 2 / SAMPLES
        return abs(c)

    def linear_start(self, omega):
        Z = self.K - omega**2 * self.M + 1j * omega * self.C
        X = np.linalg.solve(Z, self.f)
        return np.concatenate([X.real, (1j * omega * X).real])


def _gap_reference(case, omegas, dof, frf):
    """Amplitudes at ``omegas`` (a sweep, each warm-started from the last) and the peak: Brent on the
    branch through the balance's largest point, below its fold (the balance gives only the start
    of the shooting Newton and the bracket; the answer is the shooting's)."""
    sh = GapShooting(case)
    out, y = [], None
    for w in omegas:
        y = sh.solve(w, sh.linear_start(w) if y is None else y)
        out.append(sh.amplitude(w, y, dof))
    i = int(np.argmax(frf.amplitude))
    w0 = float(frf.omega[i])
    c = np.array([frf.coefficients(k)[i] for k in range(sh.n)])  # x = Re sum c_h exp(i h w t)
    h = np.arange(c.shape[1])
    memo = {w0: sh.solve(w0, np.concatenate([c.sum(axis=1).real, (1j * h * w0 * c).sum(axis=1).real]))}

    def neg(w):
        yy = sh.solve(w, memo[min(memo, key=lambda k: abs(k - w))])
        memo[w] = yy
        return -sh.amplitude(w, yy, dof)

    folds = frf.omega[frf.fold_after]
    above = folds[folds > w0]
    lo, hi = w0 - 0.004, min(w0 + 0.004, float(above.min()) - 2e-4 if above.size else math.inf)
    for w in np.linspace(w0, lo, 5)[1:]:  # warm starts along the branch on both sides
        neg(w)
    for w in np.linspace(w0, hi, 5)[1:]:
        neg(w)
    pk = minimize_scalar(neg, bounds=(lo, hi), method="bounded", options={"xatol": 1e-9})
    return out, float(pk.x), float(-pk.fun)


def _jenkins_reference(case, omegas, dof, peak_guess):
    s, cs = build(case)
    out, r = [], None
    for w in omegas:
        r = hbm.periodic_response(s, cs, omega=w, steps=SAMPLES, initial=r, floquet=False)
        assert r.success, (w, r.message)
        out.append(r.amplitude(dof))
    r0 = hbm.periodic_response(s, cs, omega=peak_guess, steps=SAMPLES, floquet=True)
    pk = hbm.periodic_peak(s, cs, bracket=(peak_guess * 0.99, peak_guess * 1.01), dof=dof, initial=r0,
                           steps=SAMPLES, xtol=1e-9)
    return out, float(pk.omega), float(pk.value), bool(r0.stable)


def main(names=None):
    """The references of ``names`` (default: every case), merged into the stored file."""
    data = {"generated_by": "benchmarks/hard_transitions_reference.py", "samples": SAMPLES, "cases": {}}
    if OUT.exists():
        data["cases"].update(json.loads(OUT.read_text())["cases"])
    for name in names or CASES:
        case, rng, omegas = CASES[name]
        t0 = time.perf_counter()
        s, cs = build(case)
        dof = int(np.argmax(np.abs(case["force"])))
        frf = hbm.frequency_response(s, cs, omega_range=rng, harmonics=15)  # the peak's bracket and start only
        if "jenkins" in case:
            amps, w_pk, a_pk, stable = _jenkins_reference(case, omegas, dof, frf.peak().omega)
        else:
            (amps, w_pk, a_pk), stable = _gap_reference(case, omegas, dof, frf), None
        data["cases"][name] = {"parameters": case, "omega_range": list(rng), "dof": dof, "omega": omegas,
                               "amplitude": amps, "peak": {"omega": w_pk, "amplitude": a_pk, "stable": stable},
                               "seconds": round(time.perf_counter() - t0, 1)}
        print(name, data["cases"][name]["peak"], data["cases"][name]["seconds"], flush=True)
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(json.dumps(data, indent=1) + "\n")


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
