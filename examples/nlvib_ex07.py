"""NLvib's example 7 from built-in elements: a chain of three oscillators with two Jenkins elements,
two cubic springs and a unilateral spring behind a gap.

The system of NLvib 1.3's ``EXAMPLES/07_multiDOFoscillator_multipleNonlinearities``: unit masses,
springs ``k = 1`` to ground at both ends and between the masses, dampers ``0.02 k``, the force
``cos(Om t)`` on the middle mass; Jenkins elements (``knl = 20``, ``muN = 1``) from mass 1 to ground
and between masses 1 and 2, cubic springs (``1 x^3``) from mass 2 to ground and between masses 2
and 3, and a unilateral spring (``k = 1``, gap ``0.25``) at mass 3.  H = 7, 1024 samples, Om from
0.5 to 2.  NLvib's points come from ``benchmarks/peers/nlvib_ex07.m`` in two runs:
``docs/data/nlvib_ex07.csv`` (the example's own run, upwards from Om = 0.5) and
``docs/data/nlvib_ex07_from2.csv`` (downwards from Om = 2); ``docs/data/nlvib_ex07_attempts*.csv``
log every corrector solve of those runs (NLvib's fsolve exit flag and residual norm).

``main()`` traces the branch through every fold with both slider conventions of the Jenkins
elements (``Macroslip(..., slider=...)``), marks stability, and for every NLvib point solves our
balance at NLvib's Om from NLvib's coefficients and from our traced branch, sorts the points into
stretches of the branch, cuts the residual along the segment where NLvib's upward run leaves the
branch, and draws ``docs/figures/nlvib_ex07.png``.  Run: ``python3 -m examples.nlvib_ex07``.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

import hbm
from contact_models import CubicSpring, Gap, Macroslip
from hbm import HarmonicBalance

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "docs" / "data"
NLVIB_CSV = DATA / "nlvib_ex07.csv"
#: NLvib's two runs: upwards from Om = 0.5 (the example's) and downwards from Om = 2.
NLVIB_RUNS = {"upward": NLVIB_CSV, "downward": DATA / "nlvib_ex07_from2.csv"}
FIGURE = ROOT / "docs" / "figures" / "nlvib_ex07.png"
H, N_T, OMEGA = 7, 1024, (0.5, 2.0)
#: Octave's fsolve stops with exit flag 1 when |R| <= TolFun n |Y| (TolFun = 1e-6, n = 46 unknowns
#: of NLvib's extended system): a point whose own residual passes that test is "converged".
FSOLVE_TOLFUN, N_UNKNOWNS = 1e-6, 3 * (2 * H + 1) + 1
#: Newton iterations at a fixed Om (from a converged NLvib point our Newton takes 2-3).
NEWTON_ITERATIONS = 15
#: The stretches of the branch the comparison is reported in (docs/contacts_normal.md).
STRETCHES = ("Om < 1.57", "1.57 <= Om, before the first fold", "between the first and last fold", "after the last fold")


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


def balance(slider: str = "from rest") -> HarmonicBalance:
    """Our harmonic balance of the example (H = 7, 1024 samples)."""
    return HarmonicBalance(system(), contacts(slider), harmonics=H, n_t=N_T)


def rms(X: np.ndarray) -> np.ndarray:
    """NLvib's plotted amplitude per DOF: sqrt(sum of squared coefficients)/sqrt(2); X (..., 3, 2H+1)."""
    return np.sqrt(np.sum(X**2, axis=-1) / 2.0)


def read_nlvib(path: Path = NLVIB_CSV) -> tuple[np.ndarray, np.ndarray]:
    """NLvib's points in the order NLvib accepted them: Om (k,) and the coefficients (k, 3, 2H+1)."""
    return read_run(path)[:2]


def read_run(path: Path = NLVIB_CSV) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """NLvib's points in the order NLvib accepted them: Om (k,), the coefficients (k, 3, 2H+1) and
    the norm of NLvib's own residual at each point (k,) (NaN where the CSV has no such column)."""
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    data = np.array(rows[1:], dtype=float)
    n = 3 * (2 * H + 1)
    res = data[:, 4 + n] if data.shape[1] > 4 + n else np.full(len(data), np.nan)
    return data[:, 0], data[:, 4:4 + n].reshape(-1, 3, 2 * H + 1), res


def fsolve_converged(omega: np.ndarray, X: np.ndarray, res: np.ndarray) -> np.ndarray:
    """True where NLvib's residual passes Octave's fsolve test for exit flag 1 (``FSOLVE_TOLFUN``)."""
    size = np.sqrt(np.sum(X.reshape(len(omega), -1) ** 2, axis=1) + omega**2)
    return res <= FSOLVE_TOLFUN * N_UNKNOWNS * size


def frf(slider: str = "centred") -> hbm.FrequencyResponse:
    """Our branch from Om = 0.5 to 2 through every fold (stability marked on first use)."""
    return hbm.frequency_response(system(), contacts(slider), OMEGA, harmonics=H, n_t=N_T, response_dof=1,
                                  tol=1e-5, steps=hbm.Steps(max_steps=20000))  # (the elements' rtol: tol/100)


def solve_at(bal: HarmonicBalance, X: np.ndarray, omega: float, iterations: int = 30) -> np.ndarray:
    """Newton on our balance at fixed ``omega`` from the coefficients ``X`` (3, 2H+1)."""
    return newton_at(bal, X, omega, iterations)[0]


def newton_at(bal: HarmonicBalance, X: np.ndarray, omega: float, iterations: int = 30) -> tuple[np.ndarray, bool]:
    """Newton on our balance at fixed ``omega`` from the coefficients ``X`` (3, 2H+1); returns the
    last iterate and whether the step fell to 1e-13 of the coefficients (converged)."""
    y = np.append(X.ravel(), omega)
    for _ in range(iterations):
        R, J = bal.physical(y)
        step = np.linalg.solve(J[:, :-1], R)
        y[:-1] -= step
        if not np.all(np.isfinite(y)):
            return X, False
        if np.max(np.abs(step)) <= 1e-13 * max(1.0, np.max(np.abs(y[:-1]))):
            return y[:-1].reshape(X.shape), True
    return y[:-1].reshape(X.shape), False


def nlvib_residual(bal: HarmonicBalance, X: np.ndarray, omega: float) -> float:
    """The norm of NLvib's residual (force units, HB_residual's form) evaluated with our elements:
    ``(K - (h Om)^2 M + i h Om D) Q_h + F_h - Fex_h`` per harmonic, in the real layout
    (cosine row ``K' Xc + c Xs``, sine row ``K' Xs - c Xc``, ``K' = K - (h Om)^2 M``,
    ``c = h Om D``), and the force ``cos(Om t)`` on mass 2."""
    s = system()
    K, M, D = (np.asarray(A.toarray() if hasattr(A, "toarray") else A, dtype=float) for A in (s.K, s.M, s.C))
    R = bal.forces(X, omega)[0].copy()
    R[:, 0] += K @ X[:, 0]
    for h in range(1, H + 1):
        Kh, c = K - (h * omega) ** 2 * M, h * omega * D
        R[:, 2 * h - 1] += Kh @ X[:, 2 * h - 1] + c @ X[:, 2 * h]
        R[:, 2 * h] += Kh @ X[:, 2 * h] - c @ X[:, 2 * h - 1]
    R[1, 1] -= 1.0
    return float(np.linalg.norm(R))


def nearest_on_branch(omega_b: np.ndarray, X_b: np.ndarray, omega: float,
                      X: np.ndarray) -> tuple[int, np.ndarray, float]:
    """The point of the traced branch's polygon nearest ``(omega, X)`` in (Om, coefficients):
    the index of the branch point it follows, the interpolated coefficients and the distance."""
    Y = np.column_stack([omega_b, X_b.reshape(len(omega_b), -1)])
    y = np.append(omega, X.ravel())
    a, d = Y[:-1], np.diff(Y, axis=0)
    t = np.clip(np.einsum("ij,ij->i", y - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0.0, 1.0)
    dist = np.sum((a + t[:, None] * d - y) ** 2, axis=1)
    i = int(np.argmin(dist))
    return i, (a[i] + t[i] * d[i])[1:].reshape(X.shape), float(np.sqrt(dist[i]))


def compare(slider: str, omega: np.ndarray, X: np.ndarray,
            branch: tuple[np.ndarray, np.ndarray] | None = None) -> dict:
    """At each NLvib point: our balance's largest residual component (m) at NLvib's coefficients
    (``res``); the relative difference of NLvib's RMS amplitude (largest over the DOFs) from our
    Newton at NLvib's Om started from NLvib's coefficients (``rel``, ``ok`` where Newton
    converged in ``NEWTON_ITERATIONS``).  With ``branch`` (our traced branch's Om (m,) and
    coefficients (m, 3, 2H+1)): the index of the nearest branch point (``index``), the same
    difference from our Newton started on the branch (``rel_branch``; NaN where the Newton from
    NLvib's point did not converge), and whether both Newtons found the same solution (``same``, to 1e-8 m), and the distance in
    (Om, coefficients) from NLvib's point to the branch's polygon (``dist``).  ``res_nlvib`` is
    NLvib's own residual norm as our elements give it (:func:`nlvib_residual`)."""
    bal = balance(slider)
    out: dict = {k: [] for k in ("res", "res_nlvib", "rel", "ok", "index", "rel_branch", "same", "dist")}
    for w, Xk in zip(omega, X):
        w = float(w)
        out["res"].append(np.max(np.abs(bal.physical(np.append(Xk.ravel(), w))[0])))
        out["res_nlvib"].append(nlvib_residual(bal, Xk, w))
        ours, ok = newton_at(bal, Xk, w, NEWTON_ITERATIONS)
        out["ok"].append(ok)
        out["rel"].append(np.max(np.abs(rms(ours) - rms(Xk)) / rms(Xk)))
        if branch is not None:
            i, start, dist = nearest_on_branch(branch[0], branch[1], w, Xk)
            on, ok_b = newton_at(bal, start, w, NEWTON_ITERATIONS) if ok else (start, False)
            out["index"].append(i)
            out["dist"].append(dist)
            out["rel_branch"].append(np.max(np.abs(rms(on) - rms(Xk)) / rms(Xk)) if ok_b else np.nan)
            out["same"].append(bool(ok and ok_b and np.max(np.abs(on - ours)) < 1e-8))
    return {k: np.array(v) for k, v in out.items() if len(v)}


def stretch(index: np.ndarray, omega: np.ndarray, fold_after: np.ndarray) -> np.ndarray:
    """Which of ``STRETCHES`` each point is in, from the index of its nearest branch point and our
    branch's folds (``fold_after``: the branch index each fold follows)."""
    first, last = fold_after[0], fold_after[-1]
    return np.where(index > last, 3, np.where(index > first, 2, np.where(omega < 1.57, 0, 1)))


def summarize(cmp: dict, omega: np.ndarray, converged: np.ndarray, fold_after: np.ndarray) -> list[dict]:
    """Per stretch: NLvib points, those converged by fsolve's test, and over the converged ones the
    max and median relative amplitude difference from our branch at NLvib's Om; the same max over
    the points whose residual in our balance is below 1e-6 m (``tight``)."""
    where = stretch(cmp["index"], omega, fold_after)
    rows = []
    for s, name in enumerate(STRETCHES):
        here = where == s
        good = here & converged
        rel, tight = cmp["rel_branch"][good], cmp["rel_branch"][good & (cmp["res"] < 1e-6)]
        rows.append({"stretch": name, "points": int(here.sum()), "converged": int(good.sum()),
                     "same_solution": int(np.sum(cmp["same"][good])),
                     "max_rel": float(np.nanmax(rel)) if rel.size else np.nan,
                     "median_rel": float(np.nanmedian(rel)) if rel.size else np.nan,
                     "tight": int(tight.size), "max_rel_tight": float(np.nanmax(tight)) if tight.size else np.nan})
    return rows


def residual_cut(bal: HarmonicBalance, a: tuple[float, np.ndarray], b: tuple[float, np.ndarray],
                 samples: int = 201) -> tuple[np.ndarray, np.ndarray]:
    """The 1-D cut ``y(t) = (1 - t) y_a + t y_b`` (Om and the coefficients together) between two
    points: t and our balance's residual norm (m) at each."""
    ya, yb = np.append(a[1].ravel(), a[0]), np.append(b[1].ravel(), b[0])
    t = np.linspace(0.0, 1.0, samples)
    return t, np.array([np.linalg.norm(bal.physical((1 - s) * ya + s * yb)[0]) for s in t])


def jump_evidence(bal: HarmonicBalance, omega: np.ndarray, X: np.ndarray, converged: np.ndarray) -> dict:
    """Where a run first accepts an unconverged point ``b`` after a converged one ``a``: our
    residual norm (m) at both, the largest change of the residual between neighbouring samples
    of the cut from ``a`` to ``b`` at three samplings of the steepest interval (falling tenfold
    per tenfold refinement: continuous), and our residual norm along the Newton step ``d`` at
    ``b`` (fixed Om), ``|R(X_b + s d)|`` for the fractions ``s``, against the linear model's
    ``(1 - s) |R(X_b)|``."""
    b = int(np.flatnonzero(~converged)[0])
    a = b - 1
    ya, yb = np.append(X[a].ravel(), omega[a]), np.append(X[b].ravel(), omega[b])
    t, r = residual_cut(bal, (omega[a], X[a]), (omega[b], X[b]), samples=101)
    k = int(np.argmax(np.abs(np.diff(r))))
    jumps = []
    for n in (2, 11, 101):
        s = np.linspace(t[k], t[k + 1], n)
        jumps.append(float(np.max(np.abs(np.diff([np.linalg.norm(bal.physical((1 - u) * ya + u * yb)[0])
                                                   for u in s])))))
    R, J = bal.physical(yb)
    d = -np.linalg.solve(J[:, :-1], R)
    fractions = (1e-4, 1e-3, 1e-2, 1e-1)
    along = [float(np.linalg.norm(bal.physical(yb + np.append(f * d, 0.0))[0])) for f in fractions]
    return {"rows": (a, b), "omega": (float(omega[a]), float(omega[b])), "res": (float(r[0]), float(r[-1])),
            "cut_max": float(r.max()), "max_change_at_spacing": dict(zip(("1e-2", "1e-3", "1e-4"), jumps)),
            "newton_step_norm": float(np.linalg.norm(d)), "along_newton": dict(zip(fractions, along)),
            "linear_model": {f: float((1 - f) * np.linalg.norm(R)) for f in fractions}}


def draw(branches: dict, runs: dict, show: bool = False) -> None:
    """q2 against Om: our branches (stability dashed), NLvib's points (open: not converged)."""
    import matplotlib  # lazily: only to draw

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # lazily: only to draw

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), gridspec_kw={"width_ratios": [3, 2]})
    for ax in axes:
        for (slider, r), color in zip(branches.items(), ("C0", "C1")):
            amp = rms(r._X)[:, 1]
            for part, style in ((r.stable, "-"), (~r.stable, "--")):
                ax.plot(r.omega, np.where(part, amp, np.nan), style, color=color, lw=1.2, zorder=3,
                        label=f"frictiondamp, slider={slider!r}" if style == "-" else None)
        for (name, (om, X, conv)), (marker, ms) in zip(runs.items(), (("o", 4.0), ("s", 2.5))):
            ax.plot(om[conv], rms(X)[conv, 1], "k" + marker, ms=ms, mfc="none", mew=0.6,
                    label=f"NLvib 1.3, {name} run")
            ax.plot(om[~conv], rms(X)[~conv, 1], "rx", ms=3.5, mew=0.6,
                    label=f"NLvib, {name} run, not converged" if np.any(~conv) else None)
        ax.set_xlabel("excitation frequency Om (rad/s)")
    axes[1].set_xlim(1.54, 1.70)
    axes[1].set_ylim(0.02, 0.19)
    axes[0].set_ylabel("q2 amplitude (RMS measure of NLvib)")
    axes[0].set_title("NLvib example 7 (H = 7)")
    axes[1].set_title("the folds")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(FIGURE, dpi=120)
    if show:
        plt.show()
    plt.close(fig)


def main(show: bool = False) -> dict:
    """Trace, compare and draw; returns the numbers the docs page quotes."""
    runs, res = {}, {}
    for name, path in NLVIB_RUNS.items():
        om, X, res[name] = read_run(path)
        runs[name] = (om, X, fsolve_converged(om, X, res[name]))
    branches = {slider: frf(slider) for slider in ("centred", "from rest")}
    out: dict = {}
    for slider, r in branches.items():
        out[slider] = {"success": r.success, "points": len(r), "folds": [float(f) for f in r.folds_omega],
                       "unstable_points": int(np.sum(~r.stable))}
        for name, (om, X, conv) in runs.items():
            cmp = compare(slider, om, X, (r.omega, r._X) if slider == "from rest" else None)
            key = f"{name} ({len(om)} points, {int(conv.sum())} converged)"
            out[slider][key] = {"max_rel_newton_converged": float(np.max(cmp["rel"][conv & cmp["ok"]])),
                                "median_rel_newton_converged": float(np.median(cmp["rel"][conv & cmp["ok"]])),
                                "max_res_ours_converged": float(np.max(cmp["res"][conv])),
                                "min_res_ours_not_converged": float(np.min(cmp["res"][~conv])) if np.any(~conv) else None}
            if slider == "from rest":
                out[slider][key]["stretches"] = summarize(cmp, om, conv, np.asarray(r.fold_after))
                out[slider][key]["nlvib_residual_reproduced"] = float(np.max(np.abs(cmp["res_nlvib"] - res[name])
                                                                             / np.maximum(res[name], 1e-9)))
            if slider == "from rest" and np.any(~conv):
                size = np.sqrt(np.sum(X[~conv].reshape(int(np.sum(~conv)), -1) ** 2, axis=1))
                out[slider][key]["not_converged"] = {
                    "rows": (int(np.flatnonzero(~conv)[0]), int(np.flatnonzero(~conv)[-1])),
                    "omega": (float(om[~conv].min()), float(om[~conv].max())),
                    "nlvib_residual": (float(res[name][~conv].min()), float(res[name][~conv].max())),
                    "rel_distance_to_branch": (float(np.min(cmp["dist"][~conv] / size)),
                                               float(np.max(cmp["dist"][~conv] / size))),
                    "our_newton_converged": int(np.sum(cmp["ok"][~conv]))}
                out[slider][key]["jump"] = jump_evidence(balance(slider), om, X, conv)
    draw(branches, runs, show)
    return out


if __name__ == "__main__":
    for key, value in main().items():
        print(key, value)
