"""The compiled kernels of the all-mode bar (the optional ``fast`` extra, numba) against the numpy
path, which stays the library's definition: the same numbers to 1e-12 relative, kernel by kernel,
solve by solve and along a whole FRF (measured on the development machine: equal bit for bit).
Skipped where numba is not installed or ``FRICTIONDAMP_COMPILED=0`` turns the kernels off;
``tests/test_allmode_kernel.py`` runs its independent dense checks on both paths."""

import os
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("numba")
if os.environ.get("FRICTIONDAMP_COMPILED", "1") == "0":
    pytest.skip("FRICTIONDAMP_COMPILED=0 turns the compiled kernels off", allow_module_level=True)

from contact_models import AllModeMicroslip  # noqa: E402
from contact_models.allmode import compiled
from contact_models.allmode.warm import warm  # noqa: E402
from contact_models.allmode.solve import FixedBar  # noqa: E402
from contact_models.allmode.balance import (BlockTridiagonal, aft_matrices, jenkins_jacobian,  # noqa: E402
                                            jenkins_periodic, jenkins_state, scalar_tridiagonal)
from hbm import frequency_response  # noqa: E402
from hbm.cli.cases import default_case  # noqa: E402

#: The agreement asked of the two paths.
RTOL = 1e-12

warm()  # the kernels in numba's cache (a clean clone has none): every test below loads them


def test_a_cold_cache_starts_the_warm_up_in_the_background_and_the_numpy_path_answers(monkeypatch, tmp_path):
    """No marker beside numba's cache (a first run after a clone): the rule that would load the kernels
    starts one background warm-up instead and this process stays on the numpy path, looking for the marker
    again after each LOOK_AGAIN seconds of nested solves; once the marker of this numba and source is there,
    the same process loads the kernels."""
    import numba

    started = []
    monkeypatch.delenv("FRICTIONDAMP_COMPILED", raising=False)
    monkeypatch.setattr(compiled, "_cache_folder", lambda: tmp_path)
    monkeypatch.setattr(compiled, "_start_warming", lambda: started.append(1))
    monkeypatch.setattr(compiled, "_TRIED", False)
    monkeypatch.setattr(compiled, "_KERNELS", None)
    monkeypatch.setattr(compiled, "_WARMING_STARTED", False)
    monkeypatch.setattr(compiled, "_LOOK_AT", 0.0)
    monkeypatch.setattr(compiled, "_NUMPY_SECONDS", 1.0)  # past LOAD_AFTER: the rule would load them
    assert not compiled.cache_ready(numba)
    assert compiled.kernels() is None and started == [1]
    assert compiled._LOOK_AT == 1.0 + compiled.LOOK_AGAIN and compiled.numpy_clock() is not None  # still counted
    assert compiled.kernels(load=True) is None and started == [1]  # one warm-up a process
    (tmp_path / compiled.MARKER).write_text(compiled._stamp(numba))
    assert compiled.cache_ready(numba)
    assert compiled.kernels() is None  # not looked for again before LOOK_AGAIN more seconds of numpy work
    monkeypatch.setattr(compiled, "_NUMPY_SECONDS", 1.0 + compiled.LOOK_AGAIN)
    assert compiled.kernels() is not None and started == [1]  # the marker found: loaded in this process
    assert compiled.numpy_clock() is None
    (tmp_path / compiled.MARKER).write_text("numba 0.0 source 0 0\n")  # another numba or an edited source
    assert not compiled.cache_ready(numba)


def test_the_kernels_the_warm_up_has_cached_are_taken_up_group_by_group(monkeypatch, tmp_path):
    """While the warm-up is under way, its progress file lists the groups of kernels already in numba's cache:
    a process loads those (the others None, their callers on the numpy path), and looks again for the rest every
    LOOK_AGAIN seconds; the marker brings them all."""
    import numba

    started = []
    monkeypatch.delenv("FRICTIONDAMP_COMPILED", raising=False)
    monkeypatch.setattr(compiled, "_cache_folder", lambda: tmp_path)
    monkeypatch.setattr(compiled, "_start_warming", lambda: started.append(1))
    monkeypatch.setattr(compiled, "_TRIED", False)
    monkeypatch.setattr(compiled, "_KERNELS", None)
    monkeypatch.setattr(compiled, "_WARMING_STARTED", False)
    monkeypatch.setattr(compiled, "_LOOK_AT", 0.0)
    monkeypatch.setattr(compiled, "_NUMPY_SECONDS", 1.0)
    first, second, *rest = compiled.GROUPS
    compiled.mark_group(first)
    assert compiled.cached_groups(numba) == (first,) and not compiled.cache_ready(numba)
    fused = compiled.kernels()
    assert fused is not None and started == [1]  # the warm-up goes on for the rest
    assert all(compiled.kernel(k) is not None for k in compiled.GROUPS[first])
    assert all(getattr(fused, k) is None for g in (second, *rest) for k in compiled.GROUPS[g])
    assert compiled.kernel("newton") is None and compiled.numpy_clock() is None
    compiled.mark_group(second)
    assert compiled.kernel(compiled.GROUPS[second][0]) is None  # not looked for again before LOOK_AGAIN seconds
    monkeypatch.setattr(compiled, "_LOOK_WALL", 0.0)
    assert all(compiled.kernel(k) is not None for g in (first, second) for k in compiled.GROUPS[g])
    assert compiled.kernel("newton") is None
    (tmp_path / compiled.PROGRESS).write_text("numba 0.0 source 0 0\n" + "".join(g + "\n" for g in compiled.GROUPS))
    assert compiled.cached_groups(numba) == ()  # another numba or an edited source
    compiled.mark_warm()
    assert not (tmp_path / compiled.PROGRESS).exists() and compiled.cached_groups(numba) == tuple(compiled.GROUPS)
    monkeypatch.setattr(compiled, "_LOOK_WALL", 0.0)
    assert compiled.kernel("newton") is not None and compiled._MISSING == () and started == [1]


def _mark_all(folder, rounds):  # one process's marks, as a warm-up or pytest's worker writes them
    compiled._cache_folder = lambda: Path(folder)
    for _ in range(rounds):
        for g in compiled.GROUPS:
            compiled.mark_group(g)


def test_two_processes_marking_one_cache_at_once_do_not_fail(monkeypatch, tmp_path):
    """Two processes warming one clean cache at once (pytest's two workers on a fresh clone) each write the
    progress file through a temporary file of their own: one moved the other's away (FileNotFoundError out of
    the collection of this module).  A mark lost to the other's write leaves the groups listed a prefix."""
    import multiprocessing

    import numba

    ctx = multiprocessing.get_context("fork")
    procs = [ctx.Process(target=_mark_all, args=(str(tmp_path), 40)) for _ in range(2)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(60)
    assert [p.exitcode for p in procs] == [0, 0]
    assert not list(tmp_path.glob("*.tmp"))
    (tmp_path / compiled.PROGRESS).write_text(compiled._stamp(numba) + "".join(
        g + "\n" for g in list(compiled.GROUPS)[::2]))  # the second group's mark lost
    monkeypatch.setattr(compiled, "_cache_folder", lambda: tmp_path)
    assert compiled.cached_groups(numba) == (next(iter(compiled.GROUPS)),)


def test_one_background_warm_up_at_a_time(monkeypatch, tmp_path):
    """The lock file keeps a second process from starting a second warm-up; a stale lock is replaced."""
    calls = []
    monkeypatch.setattr(compiled, "_cache_folder", lambda: tmp_path)
    monkeypatch.setattr(compiled.subprocess, "Popen", lambda *a, **k: calls.append(k["env"]["FRICTIONDAMP_COMPILED"]))
    compiled._start_warming()
    compiled._start_warming()
    assert calls == ["1"] and (tmp_path / compiled.WARMING).exists()
    old = compiled.time.time() - 2 * compiled.WARMING_STALE
    os.utime(tmp_path / compiled.WARMING, (old, old))
    compiled._start_warming()
    assert calls == ["1", "1"]


def both(run):
    """``(numpy path's answer, compiled path's answer)`` of ``run()``."""
    assert compiled.kernels(load=True) is not None
    with compiled.numpy_only():
        plain = run()
    return plain, run()


def assert_same(a, b):
    """Arrays (or tuples of them) equal to RTOL of the largest entry; masks and indices exactly."""
    if isinstance(a, (tuple, list)):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            assert_same(x, y)
        return
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape and a.dtype == b.dtype
    if a.dtype.kind in "bi":
        assert np.array_equal(a, b)
    else:
        assert np.max(np.abs(a - b), initial=0.0) <= RTOL * np.max(np.abs(a), initial=0.0)


def test_the_kernels_are_switched_off_by_the_environment_and_in_numpy_only(monkeypatch):
    assert compiled.kernels(load=True) is not None
    with compiled.numpy_only():
        assert compiled.kernels(load=True) is None
    assert compiled.kernels() is not None
    monkeypatch.setenv("FRICTIONDAMP_COMPILED", "0")
    assert compiled.kernels(load=True) is None


@pytest.fixture
def not_loaded(monkeypatch):
    """The kernels as in a fresh process: not loaded, no numpy time counted, no override."""
    monkeypatch.delenv("FRICTIONDAMP_COMPILED", raising=False)
    monkeypatch.setattr(compiled, "_TRIED", False)
    monkeypatch.setattr(compiled, "_KERNELS", None)
    monkeypatch.setattr(compiled, "_NUMPY_SECONDS", 0.0)
    monkeypatch.setattr(compiled, "_LOOK_AT", 0.0)
    monkeypatch.setattr(compiled, "_WARMING_STARTED", False)


def test_the_kernels_are_loaded_once_the_numpy_path_has_spent_load_after_in_nested_solves(not_loaded, monkeypatch,
                                                                                          bar_load):
    monkeypatch.setattr(compiled, "LOAD_AFTER", 0.02)
    fb = FixedBar(*bar_load, 16, 15, 128)
    X = np.zeros(31)
    assert compiled.kernels() is None
    solves = 0
    while compiled.kernels() is None:  # each solve on the numpy path counts its time
        assert compiled.numpy_clock() is not None and solves < 1000
        before = compiled._NUMPY_SECONDS
        X[2] = (1.0 + 0.01 * solves) * 1e-6
        fb.solve(X, 38500.0, odd=True)
        assert compiled._NUMPY_SECONDS > before
        solves += 1
    assert compiled._NUMPY_SECONDS >= 0.02 and solves >= 1
    assert compiled.numpy_clock() is None  # loaded: nothing counted any more
    with compiled.numpy_only():  # nor is the numpy path asked for explicitly
        assert compiled.numpy_clock() is None


def test_a_curve_on_the_rungs_loads_them_at_once_and_the_environment_overrides_the_rule(not_loaded, monkeypatch,
                                                                                        bar_load):
    assert compiled.kernels() is None
    assert AllModeMicroslip(*bar_load, cells=16, harmonics=7).start_rung((35000.0, 42000.0)) is None  # a fixed rung
    assert compiled.kernels() is not None and compiled._NUMPY_SECONDS == 0.0
    monkeypatch.setattr(compiled, "_TRIED", False)
    monkeypatch.setattr(compiled, "_KERNELS", None)
    assert AllModeMicroslip(*bar_load).start_rung((35000.0, 42000.0)) is not None  # a choosing element
    assert compiled.kernels() is not None and compiled._NUMPY_SECONDS == 0.0
    monkeypatch.setattr(compiled, "_TRIED", False)
    monkeypatch.setattr(compiled, "_KERNELS", None)
    monkeypatch.setenv("FRICTIONDAMP_COMPILED", "0")
    assert AllModeMicroslip(*bar_load).start_rung((35000.0, 42000.0)) is not None
    assert compiled.kernels() is None and compiled.kernels(load=True) is None
    monkeypatch.setenv("FRICTIONDAMP_COMPILED", "1")
    assert compiled.kernels() is not None  # at the first use, whatever the time spent


def test_without_a_writable_cache_the_kernels_are_compiled_uncached(monkeypatch):
    """numba finds no place for its cache (a read-only installation and home): the kernels are
    still made, uncached, instead of the error numba raises for ``cache=True``."""
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl  # its name in numba 0.61 and older
    monkeypatch.setattr(impl, "_locator_classes", [])
    monkeypatch.setattr(compiled, "_TRIED", False)
    monkeypatch.setattr(compiled, "_KERNELS", None)
    kernels = compiled.kernels(load=True)
    assert kernels is not None
    assert type(kernels.march._cache).__name__ == "NullCache"  # a dispatcher without a cache


@pytest.mark.parametrize("half", [False, True])
def test_the_return_map_is_the_numpy_one(half):
    rng = np.random.default_rng(5)
    E, P, order = aft_matrices(9, 72)
    U = rng.normal(size=(9, 19)) / (1.0 + order)
    if half:
        U[:, order % 2 == 0] = 0.0
    kc = rng.uniform(1.0, 4.0, 9)
    p = np.array([0.05, 0.3, 1.0, 2.0, 0.0, 0.6, 1.3, 50.0, 80.0])  # the last two never slip
    u = U @ E.T
    plain, fast = both(lambda: jenkins_periodic(u, kc, p, half))
    assert plain[3][-2:].all() and not plain[3][:-2].any()
    assert_same(plain, fast)


@pytest.fixture(scope="module")
def bar_load():
    case = default_case()
    return case.element.bar, case.element.load


@pytest.mark.parametrize("odd", [True, False])
def test_the_jacobians_by_stick_runs_are_the_numpy_ones(bar_load, odd):
    bar, load = bar_load
    fb = FixedBar(bar, load, 32, 31, 248)
    b, d = fb.basis(odd), fb.disc
    X = np.zeros(63)
    X[2] = 1.4e-6
    U = FixedBar(bar, load, 32, 31, 248).solve(X, 38900.0, odd=True).U[:, b.idx]
    if not odd:
        U = U + 1e-8 * np.cos(np.arange(U.size)).reshape(U.shape)  # even harmonics too
    state = jenkins_state(U, d.kc, d.p, b.E, b.P, odd)[2]
    assert state[3].any() and not state[3].all()
    plain, fast = both(lambda: jenkins_jacobian(state, d.kc, b.E, b.P, b.prefix))
    assert_same(plain, fast)


@pytest.mark.parametrize("row0", [False, True])
@pytest.mark.parametrize("k", [0, 4, 12])
def test_the_block_elimination_is_the_numpy_one(k, row0):
    rng = np.random.default_rng(k)
    n, s, c = 12, 24, 0.9
    B = 0.1 * rng.normal(size=(n, s, s)) + 4.0 * np.eye(s)
    B[:k] = 0.0
    B[:k, np.arange(s), np.arange(s)] = rng.uniform(3.0, 6.0, (k, s))
    if row0:
        B[:k, 0, 1:] = rng.normal(size=(k, s - 1))
    r2, r3 = rng.normal(size=(n, s)), rng.normal(size=(n, s, 3))

    def run():
        fac = BlockTridiagonal(B, c, diagonal=k, row0=row0)
        return fac.last_inverse(), fac.solve(r2), fac.solve(r3)

    assert_same(*both(run))


@pytest.mark.parametrize("n", [1, 2, 40])
def test_the_scalar_tridiagonal_solve_is_the_numpy_one(n):
    rng = np.random.default_rng(n)
    diag, last = rng.uniform(2.0, 5.0, (n, 7)), rng.normal(size=7)
    plain, fast = both(lambda: scalar_tridiagonal(diag, -0.9, last))
    assert_same(plain, fast)
    A = np.diag(np.ones(n - 1), 1) * -0.9 + np.diag(np.ones(n - 1), -1) * -0.9
    for j in range(7):
        rhs = np.zeros(n)
        rhs[-1] = last[j]
        np.testing.assert_allclose(plain[:, j], np.linalg.solve(A + np.diag(diag[:, j]), rhs), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("where", [0, 5])
def test_a_singular_block_is_named_on_both_paths(where):
    B = np.zeros((8, 22, 22))
    B[:, np.arange(22), np.arange(22)] = 2.0
    if where:  # C_where = B_where - c^2 C_(where-1)^-1 = 0
        B[where] = 0.25 * BlockTridiagonal(B[:where], 0.5).last_inverse()
    else:
        B[0] = 0.0
    for diagonal in (0, 8):
        with compiled.numpy_only(), pytest.raises(np.linalg.LinAlgError, match=f"singular block {where} "):
            BlockTridiagonal(B, 0.5, diagonal)
        with pytest.raises(np.linalg.LinAlgError, match=f"singular block {where} "):
            BlockTridiagonal(B, 0.5, diagonal)


@pytest.mark.parametrize("cells, H", [(16, 15), (32, 31)])
def test_the_nested_solves_are_the_numpy_ones(bar_load, cells, H):
    """Odd-basis solves with their even block, below and above slip, and a full-basis solve."""
    bar, load = bar_load

    def run():
        fb = FixedBar(bar, load, cells, H, 8 * H if H > 15 else 128)
        out = []
        for a, w in [(0.7e-6, 38000.0), (1.0e-6, 38500.0), (1.535e-6, 38820.0), (1.2e-6, 39200.0)]:
            X = np.zeros(2 * H + 1)
            X[1], X[2] = 0.1 * a, a
            sol = fb.solve(X, w, odd=True)
            fb.even_block(sol)
            out += [sol.F, sol.dF_dX, sol.dF_domega, sol.slip]
        X[0], X[3] = 1e-8, 2e-9
        sol = fb.solve(X, 38700.0, odd=False)
        return out + [sol.F, sol.dF_dX, sol.dF_domega, sol.slip]

    assert_same(*both(run))


def test_an_all_mode_frf_is_the_numpy_one(bar_load):
    bar, load = bar_load
    blade = default_case().blade

    def run():
        frf = frequency_response(blade, AllModeMicroslip(bar, load, cells=16, harmonics=15), (38400.0, 39200.0))
        return frf.omega, frf.amplitude, frf.error_estimate

    plain, fast = both(run)
    assert plain[0].size > 20
    assert_same(plain, fast)


def test_an_frf_that_loads_the_kernels_midway_is_the_numpy_one(not_loaded, monkeypatch, bar_load):
    """The rule switches paths between two nested solves of one curve: the curve is still the numpy one.
    Without an error estimate the curve does not ask the element for a start rung, which loads the kernels."""
    bar, load = bar_load
    blade = default_case().blade
    monkeypatch.setattr(compiled, "LOAD_AFTER", 0.02)

    def run():
        frf = frequency_response(blade, AllModeMicroslip(bar, load, cells=16, harmonics=15), (38400.0, 39200.0),
                                 tol=None)
        return frf.omega, frf.amplitude

    with compiled.numpy_only():  # not counted towards loading
        plain = run()
    assert compiled._NUMPY_SECONDS == 0.0 and compiled.kernels() is None
    mixed = run()
    assert compiled.kernels() is not None and compiled._NUMPY_SECONDS >= 0.02  # loaded during the curve
    assert plain[0].size > 20
    assert_same(plain, mixed)



def test_a_nan_in_the_state_gives_a_nan_residual_on_both_paths(bar_load):
    """The compiled residual's max|R| keeps a NaN as np.max does (a NaN state is never taken as converged)."""
    bar, load = bar_load
    fb = FixedBar(bar, load, 16, 31, 248)
    b = fb.basis(True)
    X = np.zeros(b.idx.size)
    X[1] = 1e-6
    U = fb.linear_guess(X, 38000.0, b)
    U[3, 2] = np.nan
    plain, fast = both(lambda: fb.evaluate(U, X, 38000.0, b, False).res)
    assert np.isnan(plain) and np.isnan(fast)
