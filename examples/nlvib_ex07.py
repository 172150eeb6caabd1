"""NLvib's example 7 from built-in elements: a chain of three oscillators with two Jenkins elements,
two cubic springs and a unilateral spring behind a gap.

The system of NLvib 1.3's ``EXAMPLES/07_multiDOFoscillator_multipleNonlinearities``: unit masses,
springs ``k = 1`` to ground at both ends and between the masses, dampers ``0.02 k``, the force
``cos(Om t)`` on the middle mass; Jenkins elements (``knl = 20``, ``muN = 1``) from mass 1 to ground
and between masses 1 and 2, cubic springs (``1 x^3``) from mass 2 to ground and between masses 2
and 3, and a unilateral spring (``k = 1``, gap ``0.25``) at mass 3.  H = 7, 1024 samples, Om from
0.5 to 2.  NLvib's points (``docs/data/nlvib_ex07.csv``) come from ``benchmarks/peers/nlvib_ex07.m``.

``main()`` traces the branch through every fold with both slider conventions of the Jenkins
elements (``Macroslip(..., slider=...)``), marks stability, solves our balance at every NLvib
point (Newton from NLvib's coefficients at NLvib's Om) and draws ``docs/figures/nlvib_ex07.png``.
Run: ``python3 -m examples.nlvib_ex07``.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

import hbm
from contact_models import CubicSpring, Gap, Macroslip
from hbm.balance import HarmonicBalance

ROOT = Path(__file__).resolve().parents[1]
NLVIB_CSV = ROOT / "docs" / "data" / "nlvib_ex07.csv"
FIGURE = ROOT / "docs" / "figures" / "nlvib_ex07.png"
H, N_T, OMEGA = 7, 1024, (0.5, 2.0)


def system() -> hbm.Structure:
    """The linear chain: M = I, K from the springs [1, 1, 1, 1], D = 0.02 K, force on mass 2."""
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]])
    return hbm.Structure(np.eye(3), 0.02 * K, K, force=[0.0, 1.0, 0.0])


def contacts(slider: str = "centred") -> list[hbm.Contact]:
    """NLvib's five nonlinear elements; NLvib's force direction ``w`` becomes ``dof``/``dofs``."""
    return [hbm.Contact(Macroslip(20.0, 1.0, slider=slider), dof=0),         # w1 = [1, 0, 0]
            hbm.Contact(Macroslip(20.0, 1.0, slider=slider), dofs=(1, 0)),   # w2 = [-1, 1, 0]
            hbm.Contact(CubicSpring(1.0), dof=1),                            # w3 = [0, 1, 0]
            hbm.Contact(CubicSpring(1.0), dofs=(2, 1)),                      # w4 = [0, -1, 1]
            hbm.Contact(Gap(1.0, 0.25), dof=2)]                              # w5 = [0, 0, 1]


def rms(X: np.ndarray) -> np.ndarray:
    """NLvib's plotted amplitude per DOF: sqrt(sum of squared coefficients)/sqrt(2); X (..., 3, 2H+1)."""
    return np.sqrt(np.sum(X**2, axis=-1) / 2.0)


def read_nlvib(path: Path = NLVIB_CSV) -> tuple[np.ndarray, np.ndarray]:
    """NLvib's points: Om (k,) and the coefficients (k, 3, 2H+1)."""
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    data = np.array(rows[1:], dtype=float)
    return data[:, 0], data[:, 4:].reshape(-1, 3, 2 * H + 1)


def frf(slider: str = "centred") -> hbm.FrequencyResponse:
    """Our branch from Om = 0.5 to 2 through every fold (stability marked on first use)."""
    return hbm.frequency_response(system(), contacts(slider), OMEGA, harmonics=H, n_t=N_T, response_dof=1,
                                  rtol=1e-7, max_steps=20000)


def solve_at(balance: HarmonicBalance, X: np.ndarray, omega: float, iterations: int = 30) -> np.ndarray:
    """Newton on our balance at fixed ``omega`` from the coefficients ``X`` (3, 2H+1)."""
    y = np.append(X.ravel(), omega)
    for _ in range(iterations):
        R, J = balance.physical(y)
        step = np.linalg.solve(J[:, :-1], R)
        y[:-1] -= step
        if np.max(np.abs(step)) <= 1e-13 * max(1.0, np.max(np.abs(y[:-1]))):
            break
    return y[:-1].reshape(X.shape)


def compare(slider: str, omega: np.ndarray, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """At each NLvib point: the relative difference of NLvib's RMS amplitude (largest over the
    DOFs) after our Newton, and our balance's residual (m) at NLvib's own coefficients (how far
    NLvib's solver converged)."""
    balance = HarmonicBalance(system(), contacts(slider), harmonics=H, n_t=N_T)
    ours = np.array([solve_at(balance, Xk, float(w)) for w, Xk in zip(omega, X)])
    res = np.array([np.max(np.abs(balance.physical(np.append(Xk.ravel(), w))[0])) for w, Xk in zip(omega, X)])
    return np.max(np.abs(rms(ours) - rms(X)) / rms(X), axis=1), res


def main(show: bool = False) -> dict:
    """Trace, compare and draw; returns the numbers the docs page quotes."""
    import matplotlib  # lazily: only to draw

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # lazily: only to draw

    om, X = read_nlvib()
    out = {"nlvib_points": len(om)}
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for slider, color in (("centred", "C0"), ("from rest", "C1")):
        r = frf(slider)
        c2 = r.coefficients(1)  # q2's complex harmonics (points, H+1): |c_h|^2 = Xc_h^2 + Xs_h^2
        amp = np.sqrt(np.sum(np.abs(c2) ** 2, axis=1) / 2.0)
        stable = r.stable
        for part, style in ((stable, "-"), (~stable, "--")):
            ax.plot(r.omega, np.where(part, amp, np.nan), style, color=color,
                    label=f"frictiondamp, slider={slider!r}" if style == "-" else None)
        ax.plot(r.folds_omega, [np.nan] * len(r.folds_omega), "k.")
        err, res = compare(slider, om, X)
        before, tight = om < 1.57, res < 1e-6  # NLvib points converged to 1e-6 m in our balance
        out[slider] = {"success": r.success, "points": len(r), "folds": len(r.folds_omega),
                       "max_rel_before_1.57": float(np.max(err[before])),
                       "max_rel_before_1.57_converged": float(np.max(err[before & tight])),
                       "loose_nlvib_points": int(np.sum(~tight)),
                       "max_rel_before_1.65_converged": float(np.max(err[(om < 1.65) & tight])),
                       "unstable_points": int(np.sum(~stable))}
    ax.plot(om, rms(X)[:, 1], "k.", ms=2.5, label="NLvib 1.3 (Octave), q2")
    ax.set_xlabel("excitation frequency Om (rad/s)")
    ax.set_ylabel("q2 amplitude (RMS measure of NLvib)")
    ax.set_title("NLvib example 7: two Jenkins elements, two cubic springs, a gap (H = 7)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIGURE, dpi=120)
    if show:
        plt.show()
    plt.close(fig)
    return out


if __name__ == "__main__":
    for key, value in main().items():
        print(key, value)
