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
  degrees), 1 % modal damping, a force 0.016 on DOF 0 and a unilateral spring (``Gap``, stiffness
  0.25, gap 0.5) at DOF 0 that closes only near the first resonance (about 0.995 to 1.007 rad/s,
  where DOF 0's linear amplitude exceeds the gap); the gap is the asymmetry whose second harmonic
  reaches the mode at 2 rad/s (at the peak DOF 1's second harmonic is 7 % of its first).  No fold
  at these parameters (a force 0.02 or a stiffer spring makes the branch fold);
- ``gap``: one DOF (m = k = 1, 2 % damping) against a gap spring of stiffness 2 k.

Jenkins cases: ``hbm.periodic_response`` / ``hbm.periodic_peak`` (event-driven exact stick/slip
integration and shooting, ``hbm.reference.shooting``).  Gap cases: the same method written here,
since that reference has no unilateral spring: between contact events the motion is linear and
integrated by DOP853 at rtol ``GAP_RTOL`` = 1e-11 with the variational equations alongside, the
events (the gap's relative displacement crossing zero) located by the integrator's root finding
and the integration restarted there, and Newton on ``Phi_T(y0) - y0`` with the variational
Jacobian (period residual ~1e-15); the first harmonic from 1024 samples of the period by FFT.
Each Newton starts from the balance's nearest branch point (warm starts from the previous
frequency can wander across a contact change); the answer is the shooting's.  Checked: rtol 1e-13
and 4096 samples change the stored ``ir21_gap`` numbers by 3e-12 at most.  Neither uses the
harmonic balance.  Peaks: Brent's bounded search over omega (warm-started shooting).

Run: ``PYTHONPATH=. python3 benchmarks/hard_transitions_reference.py [case ...]`` (the Jenkins
cases take about ten seconds each, ``ir21_gap`` two).  Named cases are recomputed and merged into the
stored file; the others' stored numbers are kept as they are.
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
    return {"M": np.eye(2).tolist(), "C": C.tolist(), "K": K.tolist(), "force": [0.016, 0.0],
            "gap": {"dof": 0, "stiffness": 0.25, "gap": 0.5}}


def gap_oscillator():
    return {"M": [[1.0]], "C": [[0.04]], "K": [[1.0]], "force": [0.05],
            "gap": {"dof": 0, "stiffness": 2.0, "gap": 0.6}}


CASES = {
    "ir31": (internal_resonance_chain(3.0, 0.005, 20.0), (0.6, 1.3), [0.8, 0.95, 1.0, 1.05, 1.2]),
    "ir31_light": (internal_resonance_chain(3.0, 0.0005, 100.0), (0.6, 1.3), [0.8, 0.95, 1.0, 1.05, 1.2]),
    "stiff": (stiff_chain(), (0.5, 1.2), [0.55, 0.58, 0.6, 0.7, 1.0]),
    "ir21_gap": (gap_chain(), (0.7, 1.3), [0.9, 0.97, 0.99, 0.997, 1.0, 1.005, 1.01, 1.05]),
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
#: Relative tolerance of the gap's integration between contact events.
GAP_RTOL = 1e-11


class GapShooting:
    """Periodic response of ``M x'' + C x' + K x + e k_g max(0, x_d - g) = f cos(omega t)``.

    Between the contact's closing and opening the motion is linear; each segment is integrated by
    DOP853 with the variational equations alongside and stopped at the next crossing of
    ``x_d = g`` (leaving the current side only), then restarted with the other stiffness.  The
    contact force is zero on both sides of the crossing, so the vector field is continuous there
    and the saltation matrix is the identity: the variational state carries across unchanged.
    """

    def __init__(self, case):
        self.M = np.array(case["M"])
        self.C = np.array(case["C"])
        self.K = np.array(case["K"])
        self.f = np.array(case["force"])
        g = case["gap"]
        self.d, self.kg, self.g = g["dof"], g["stiffness"], g["gap"]
        self.n = len(self.f)
        Minv = np.linalg.inv(self.M)
        n = self.n
        self.A = {}
        for closed in (False, True):
            Kc = self.K.copy()
            if closed:
                Kc[self.d, self.d] += self.kg
            A = np.zeros((2 * n, 2 * n))
            A[:n, n:] = np.eye(n)
            A[n:, :n] = -Minv @ Kc
            A[n:, n:] = -Minv @ self.C
            self.A[closed] = A
        self.b = Minv @ self.f
        self.pre = Minv[:, self.d] * self.kg * self.g  # the closed spring's constant part, k_g g

    def _rhs(self, closed, omega):
        n, A, b = self.n, self.A[closed], self.b
        c = self.pre if closed else np.zeros(n)

        def rhs(t, y):
            z = y[: 2 * n]
            dz = A @ z
            dz[n:] += b * math.cos(omega * t) + c
            Phi = y[2 * n:].reshape(2 * n, 2 * n)
            return np.concatenate([dz, (A @ Phi).ravel()])

        return rhs

    def period(self, y0, omega, samples=None):
        """``(y(T), dy(T)/dy0, x at samples equally spaced times or None)`` from ``y0`` at t = 0."""
        T = 2 * math.pi / omega
        n, d, m = self.n, self.d, 2 * self.n
        t, y = 0.0, np.concatenate([np.asarray(y0, dtype=float), np.eye(m).ravel()])
        closed = bool(y[d] > self.g)
        grid = np.arange(samples) * T / samples if samples else None
        ts, xs = [], []
        while True:
            def crossing(tt, yy):
                return yy[d] - self.g

            crossing.terminal = True
            crossing.direction = -1.0 if closed else 1.0
            sol = solve_ivp(self._rhs(closed, omega), (t, T), y, method="DOP853", rtol=GAP_RTOL,
                            atol=1e-14, events=crossing, dense_output=grid is not None)
            end = float(sol.t_events[0][0]) if sol.status == 1 else T
            if grid is not None:
                tt = grid[(grid >= t) & (grid < end)]
                ts.append(tt)
                xs.append(sol.sol(tt)[:n].T if tt.size else np.empty((0, n)))
            if sol.status != 1:
                y = sol.y[:, -1]
                break
            t, y = end, sol.y_events[0][0].copy()
            closed = not closed
        x = np.concatenate(xs)[np.argsort(np.concatenate(ts))] if grid is not None else None
        return y[:m], y[m:].reshape(m, m), x

    def solve(self, omega, y0, tol=1e-12, max_iter=40):
        """The periodic state at t = 0 near ``y0``: Newton on ``Phi_T(y0) - y0`` with the
        variational Jacobian."""
        y = np.array(y0, dtype=float)
        for _ in range(max_iter):
            yT, Phi, _ = self.period(y, omega)
            dy = np.linalg.solve(Phi - np.eye(y.size), -(yT - y))
            y = y + dy
            if np.max(np.abs(dy)) <= tol * max(1e-3, float(np.max(np.abs(y)))):
                return y
        raise RuntimeError(f"gap shooting did not converge at omega={omega}")

    def residual(self, omega, y):
        return float(np.max(np.abs(self.period(y, omega)[0] - y)))

    def amplitude(self, omega, y, dof):
        x = self.period(y, omega, SAMPLES)[2][:, dof]
        return float(2.0 * abs(np.fft.rfft(x)[1]) / SAMPLES)

    def linear_start(self, omega):
        Z = self.K - omega**2 * self.M + 1j * omega * self.C
        X = np.linalg.solve(Z, self.f)
        return np.concatenate([X.real, (1j * omega * X).real])


def _gap_reference(case, omegas, dof, frf):
    """Amplitudes at ``omegas`` and the peak: Brent on the branch through the balance's largest
    point, below its fold if any (the balance gives only the start of each shooting Newton and the
    peak's bracket; the answers are the shooting's, converged to a period residual ~1e-15)."""
    sh = GapShooting(case)

    def start(w):  # the state at t = 0 of the balance's branch point nearest w
        i = int(np.argmin(np.abs(frf.omega - w)))
        c = np.array([frf.coefficients(k)[i] for k in range(sh.n)])  # x = Re sum c_h exp(i h w t)
        h = np.arange(c.shape[1])
        return np.concatenate([c.sum(axis=1).real, (1j * h * w * c).sum(axis=1).real])

    out = []
    for w in omegas:
        y = sh.solve(w, start(w))
        out.append(sh.amplitude(w, y, dof))
        print(f"  omega={w}: amplitude {out[-1]:.12g}, |y(T) - y0| = {sh.residual(w, y):.1e}", flush=True)
    i = int(np.argmax(frf.amplitude))
    w0 = float(frf.omega[i])

    def neg(w):  # started from the balance, not warm: Newton across a contact change can wander
        return -sh.amplitude(w, sh.solve(w, start(w)), dof)

    folds = frf.omega[frf.fold_after]
    above = folds[folds > w0]
    lo, hi = w0 - 0.004, min(w0 + 0.004, float(above.min()) - 2e-4 if above.size else math.inf)
    pk = minimize_scalar(neg, bounds=(lo, hi), method="bounded", options={"xatol": 1e-9})
    w_pk = float(pk.x)
    y_pk = sh.solve(w_pk, start(w_pk))
    multipliers = np.linalg.eigvals(sh.period(y_pk, w_pk)[1])  # Floquet: the monodromy's eigenvalues
    return out, w_pk, float(-pk.fun), bool(np.max(np.abs(multipliers)) < 1.0)


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
            amps, w_pk, a_pk, stable = _gap_reference(case, omegas, dof, frf)
        data["cases"][name] = {"parameters": case, "omega_range": list(rng), "dof": dof, "omega": omegas,
                               "amplitude": amps, "peak": {"omega": w_pk, "amplitude": a_pk, "stable": stable},
                               "seconds": round(time.perf_counter() - t0, 1)}
        print(name, data["cases"][name]["peak"], data["cases"][name]["seconds"], flush=True)
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(json.dumps(data, indent=1) + "\n")


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
