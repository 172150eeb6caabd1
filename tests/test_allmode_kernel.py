"""The all-mode bar's nested solve against an independent dense one.

The Jacobian of every node is assembled here sample by sample, ``dT/dU = kc P M E`` with the
(n_t, n_t) matrix ``M`` of ``df_k/du_j / kc`` (1 on a stuck sample, -1 at its anchor; a row that never
slips: ``f = kc (u - (u_max + u_min)/2)``), without the prefix sums, the grouping of runs or the
block elimination of the library.  The bar's Jacobian is then the dense (n s, n s) matrix, Newton
runs on it with ``numpy.linalg.solve`` to the residual's rounding floor, and the end force and its
derivatives follow from dense solves (the Schur complement of the end node).  Each check runs on
the numpy path and on the compiled kernels (where numba is installed)."""

import os

import numpy as np
import pytest

from contact_models.allmode import compiled
from contact_models.allmode.warm import warm
from contact_models.allmode.solve import FixedBar, transferred
from contact_models.allmode.balance import (BandedBlockTridiagonal, BlockTridiagonal, aft_matrices, jacobian_prefix,
                                            jenkins_jacobian, jenkins_periodic, jenkins_state)
from contact_models.allmode import AllModeMicroslip
from hbm.cli.cases import default_case


def dense_node_jacobians(U, kc, p, E, P):
    """dT/dU (m, s, s) of every node, by samples (an independent assembly)."""
    u = U @ E.T
    _, stuck, anchor, never = jenkins_periodic(u, kc, p)
    m, n_t = u.shape
    J = np.empty((m, E.shape[1], E.shape[1]))
    k = np.arange(n_t)
    for i in range(m):
        M = np.zeros((n_t, n_t))
        if never[i]:
            M[k, k] = 1.0
            M[:, np.argmax(u[i])] -= 0.5
            M[:, np.argmin(u[i])] -= 0.5
        else:
            s = stuck[i]
            M[k[s], k[s]] += 1.0
            np.subtract.at(M, (k[s], anchor[i, s]), 1.0)
        J[i] = kc[i] * (P @ M @ E)
    return J


def dense_tridiagonal(J, lin, c, n, s):
    """The bar's Jacobian (n s, n s) densely: node i's block ``J[i] + diag(lin[i])``, ``diag(c)`` beside it
    (c one coupling or one per coefficient)."""
    A = np.zeros((n * s, n * s))
    C = np.diag(np.broadcast_to(c, (s,)))
    for i in range(n):
        A[i * s:(i + 1) * s, i * s:(i + 1) * s] = J[i] + np.diag(lin[i])
        if i:
            A[i * s:(i + 1) * s, (i - 1) * s:i * s] = C
            A[(i - 1) * s:i * s, i * s:(i + 1) * s] = C
    return A


def dense_matrix(fb, U, X, omega, b):
    """The bar's residual R (n s) and its dense Jacobian (n s, n s) at U."""
    d = fb.disc
    full = np.vstack([U, X[None, :]])
    T, _, _ = jenkins_state(full, d.kc, d.p, b.E, b.P)
    J = dense_node_jacobians(full, d.kc, d.p, b.E, b.P)
    lin, c = fb.linear(omega, b.order, b.odd)[:2]
    n, s = U.shape
    R = lin[:-1] * U + T[:-1]
    R[1:] += c * U[:-1]
    R[:-1] += c * U[1:]
    R[-1] += c * X
    A = dense_tridiagonal(J, lin, c, n, s)
    return R.ravel(), A, T, J, lin


@pytest.fixture(scope="module", autouse=True)
def warm_kernels():
    """The compiled kernels in numba's cache before the first check asks for them (a clean clone has none,
    and the library would then compile them in the background: ``contact_models.allmode.compiled``)."""
    if os.environ.get("FRICTIONDAMP_COMPILED", "") != "0":
        try:
            import numba  # noqa: F401
        except ImportError:
            return
        warm()


@pytest.fixture(params=["numpy", "compiled"], autouse=True)
def path(request):
    """Every check on the numpy path and, where numba is installed, on the compiled kernels."""
    if request.param == "numpy":
        with compiled.numpy_only():
            yield
    elif compiled.kernels(load=True) is None:
        pytest.skip("the compiled kernels are off: numba not installed (the fast extra) or FRICTIONDAMP_COMPILED=0")
    else:
        yield


@pytest.fixture(scope="module")
def bar_load():
    case = default_case()
    return case.element.bar, case.element.load


def test_node_jacobians_match_the_sample_assembly(bar_load):
    bar, load = bar_load
    el = AllModeMicroslip(bar, load, cells=32, harmonics=31)
    sol = el.solve(1.5355e-6, 38820.0)
    fb = el._level(32, 31)
    d = fb.disc
    for odd in (True, False):
        b = fb.basis(odd)
        U = sol.U[:, b.idx]
        U = U + 1e-8 * np.cos(np.arange(U.size)).reshape(U.shape)  # even harmonics too where not odd
        state = jenkins_state(U, d.kc, d.p, b.E, b.P)[2]
        assert state[3].any() and not state[3].all()  # rows that never slip and rows that do
        J = jenkins_jacobian(state, d.kc, b.E, b.P, b.prefix)
        Jd = dense_node_jacobians(U, d.kc, d.p, b.E, b.P)
        assert np.max(np.abs(J - Jd)) <= 1e-12 * np.max(np.abs(Jd))


@pytest.mark.parametrize("linear", ["exact", "lumped"])
@pytest.mark.parametrize("a, omega", [(1.5355e-6, 38820.0), (3e-6, 37000.0)])
def test_nested_solve_matches_a_dense_newton(bar_load, a, omega, linear):
    """The block elimination, the warm starts and the implicit function theorem against dense linear
    algebra on the same balance (its linear part ``FixedBar.linear``, checked on its own in
    ``test_bar_segments.py``)."""
    bar, load = bar_load
    cells, H = 32, 31
    el = AllModeMicroslip(bar, load, cells=cells, harmonics=H, linear=linear)
    sol = el.solve(a, omega)
    fb = FixedBar(bar, load, cells, H, el._level(cells, H).n_t, linear)
    b = fb.basis(True)
    X = np.zeros(2 * H + 1)
    X[2] = a
    Xb = X[b.idx]
    d = fb.disc
    U = fb.linear_guess(Xb, omega, b)
    n, s = U.shape
    for _ in range(60):  # plain Newton to the rounding floor (the residual is piecewise linear)
        R, A, T, J, lin = dense_matrix(fb, U, Xb, omega, b)
        step = np.linalg.solve(A, -R).reshape(n, s)
        U = U + step
        if np.max(np.abs(step)) <= 1e-15 * np.max(np.abs(U)):
            break
    R, A, T, J, lin = dense_matrix(fb, U, Xb, omega, b)
    assert np.max(np.abs(R)) <= 1e-12 * fb.scale(Xb)
    _, c, dlin, dc = fb.linear(omega, b.order, b.odd)
    F = lin[-1] * Xb + c * U[-1] + T[-1]
    Ainv_last = np.linalg.solve(A, np.vstack([np.zeros(((n - 1) * s, s)), np.eye(s)]))[-s:]
    dF_dX = np.diag(lin[-1]) + J[-1] - c[:, None] * Ainv_last * c[None, :]
    dR_dw = dlin[:-1] * U
    dR_dw[1:] += dc * U[:-1]
    dR_dw[:-1] += dc * U[1:]
    dR_dw[-1] += dc * Xb
    dU_dw = np.linalg.solve(A, -dR_dw.ravel()).reshape(n, s)
    dF_dw = dlin[-1] * Xb + dc * U[-1] + c * dU_dw[-1]
    ix = np.ix_(b.idx, b.idx)
    assert sol.success
    # measured: F to 2e-14, dF_dX and dF_domega to 2e-12 (the bar's Jacobian has a condition number
    # near 1e5-1e6 at the peak, and the library stops Newton at a residual of 1e-11 of the force scale)
    assert np.max(np.abs(sol.F[b.idx] - F)) <= 1e-10 * np.max(np.abs(F))
    assert np.max(np.abs(sol.dF_dX[ix] - dF_dX)) <= 1e-10 * np.max(np.abs(dF_dX))
    assert np.max(np.abs(sol.dF_domega[b.idx] - dF_dw)) <= 1e-10 * np.max(np.abs(dF_dw))


@pytest.mark.parametrize("linear", ["exact", "lumped"])
def test_even_block_matches_the_dense_schur_complement(bar_load, linear):
    """A half-wave symmetric solution (odd basis) gets its even-even block of dF/dX from the
    return map's state its solve kept; here from the dense full-basis Jacobian's even part."""
    bar, load = bar_load
    cells, H, omega = 32, 31, 38820.0
    fb = FixedBar(bar, load, cells, H, AllModeMicroslip(bar, load, cells=cells, harmonics=H)._level(cells, H).n_t,
                  linear)
    X = np.zeros(2 * H + 1)
    X[2] = 1.5355e-6
    sol = fb.solve(X, omega, odd=True)
    fb.even_block(sol)
    b = fb.basis(False)
    d = fb.disc
    even = np.flatnonzero(b.order % 2 == 0)
    J = dense_node_jacobians(sol.U, d.kc, d.p, b.E, b.P)[:, even][:, :, even]
    lin, c = fb.linear(omega, b.order[even], "dense")[:2]
    n, s = cells, even.size
    A = dense_tridiagonal(J, lin, c, n, s)
    Ainv_last = np.linalg.solve(A, np.vstack([np.zeros(((n - 1) * s, s)), np.eye(s)]))[-s:]
    block = np.diag(lin[-1]) + J[-1] - c[:, None] * Ainv_last * c[None, :]
    got = sol.dF_dX[np.ix_(even, even)]
    assert np.max(np.abs(got - block)) <= 1e-10 * np.max(np.abs(block))  # measured 6e-14


def test_jacobian_prefix_needs_a_trigonometric_basis():
    E, P, _ = aft_matrices(3, 16)
    jacobian_prefix(E[:, [1, 2, 5]], P[[1, 2, 5]])  # any subset of the columns
    with pytest.raises(ValueError, match="aft_matrices"):
        jacobian_prefix(E + 0.1, P)
    with pytest.raises(ValueError, match="aft_matrices"):
        jacobian_prefix(E, 2.0 * P[::-1])


@pytest.mark.parametrize("k", [1, 5, 12])
def test_block_elimination_of_a_diagonal_start_is_the_dense_one_bit_for_bit(k):
    """The first k blocks diagonal (the nodes that never slip, in the odd basis): eliminated as
    vectors, the factorisation solves bit for bit as the one by dense blocks, and as a dense solve."""
    rng = np.random.default_rng(k)
    n, s, c = 12, 24, -1.3
    B = 0.1 * rng.normal(size=(n, s, s)) + 5.0 * np.eye(s)
    B[:k] = 0.0
    B[:k, np.arange(s), np.arange(s)] = rng.uniform(3.0, 6.0, (k, s))
    fast, plain = BlockTridiagonal(B, c, diagonal=k), BlockTridiagonal(B, c)
    assert np.array_equal(fast.last_inverse(), plain.last_inverse())
    A = dense_tridiagonal(B, np.zeros((n, s)), c, n, s)
    for r in (rng.normal(size=(n, s)), rng.normal(size=(n, s, 3))):
        x = fast.solve(r)
        assert np.array_equal(x, plain.solve(r))
        dense = np.linalg.solve(A, r.reshape(n * s, -1)).reshape(r.shape)
        assert np.max(np.abs(x - dense)) <= 1e-12 * np.max(np.abs(dense))


@pytest.mark.parametrize("k", [1, 5, 12])
def test_block_elimination_of_a_start_diagonal_but_for_the_first_row_is_the_dense_one(k):
    """The first k blocks diagonal but for their first row (the nodes that never slip, in a basis with
    the mean): eliminated in that form, the factorisation solves as a dense solve, and its last pivot
    inverse is the dense inverse's last diagonal block."""
    rng = np.random.default_rng(10 + k)
    n, s, c = 12, 24, -1.3
    B = 0.1 * rng.normal(size=(n, s, s)) + 5.0 * np.eye(s)
    B[:k] = 0.0
    B[:k, np.arange(s), np.arange(s)] = rng.uniform(3.0, 6.0, (k, s))
    B[:k, 0, 1:] = rng.normal(size=(k, s - 1))
    fac = BlockTridiagonal(B, c, diagonal=k, row0=True)
    A = dense_tridiagonal(B, np.zeros((n, s)), c, n, s)
    Ainv_last = np.linalg.inv(A)[-s:, -s:]
    assert np.max(np.abs(fac.last_inverse() - Ainv_last)) <= 1e-12 * np.max(np.abs(Ainv_last))
    for r in (rng.normal(size=(n, s)), rng.normal(size=(n, s, 3))):
        x = fac.solve(r)
        dense = np.linalg.solve(A, r.reshape(n * s, -1)).reshape(r.shape)
        assert np.max(np.abs(x - dense)) <= 1e-12 * np.max(np.abs(dense))


@pytest.mark.parametrize("n, s", [(1, 6), (2, 6), (9, 16), (40, 16)])
def test_banded_last_inverse_is_the_dense_inverses_last_block(n, s):
    """The band factorisation's last pivot inverse, solved on its last two blocks' rows alone, is the dense
    inverse's last diagonal block and the whole band solve's, with row swaps (blocks with small diagonals)."""
    rng = np.random.default_rng(n)
    c = 2.5
    B = rng.normal(size=(n, s, s)) + 0.1 * np.eye(s)  # small diagonals: LAPACK swaps rows across blocks
    fac = BandedBlockTridiagonal(B, c)
    assert np.any(fac._piv != np.arange(n * s))
    A = dense_tridiagonal(B, np.zeros((n, s)), c, n, s)
    Ainv_last = np.linalg.inv(A)[-s:, -s:]
    e = np.zeros((n, s, s))
    e[-1] = np.eye(s)
    whole = fac.solve(e)[-1]
    scale = np.max(np.abs(Ainv_last))
    assert np.max(np.abs(fac.last_inverse() - Ainv_last)) <= 1e-11 * scale
    assert np.max(np.abs(fac.last_inverse() - whole)) <= 1e-12 * scale


def test_block_elimination_of_a_singular_diagonal_block_says_which():
    B = np.zeros((3, 22, 22))
    B[:, np.arange(22), np.arange(22)] = 2.0
    B[1, 5, 5] = 0.5  # C_1 = B_1 - c^2 / B_0 has a zero at 5 for c = 1
    with pytest.raises(np.linalg.LinAlgError, match="singular block 1"):
        BlockTridiagonal(B, 1.0, diagonal=3)


def test_a_never_slipping_node_is_the_spring_on_every_odd_harmonic_exactly(bar_load):
    """In the odd basis the Jacobian block of a node that never slips is kc I to the bit (the
    coefficients of a constant are 0 there), so the elimination may take it as a diagonal."""
    bar, load = bar_load
    fb = FixedBar(bar, load, 32, 31, AllModeMicroslip(bar, load, cells=32, harmonics=31)._level(32, 31).n_t)
    X = np.zeros(63)
    X[2] = 1.2e-6
    sol = fb.solve(X, 39200.0, odd=True)
    b, d = fb.basis(True), fb.disc
    state = jenkins_state(sol.U[:, b.idx], d.kc, d.p, b.E, b.P)[2]
    never = np.flatnonzero(state[3])
    assert 0 < never.size < 33
    J = jenkins_jacobian(state, d.kc, b.E, b.P, b.prefix)
    assert np.array_equal(J[never], d.kc[never, None, None] * np.eye(b.idx.size)[None])


def test_transferred_moves_nodal_coefficients_between_rungs():
    """Linear in x between the nodes (exact for a motion linear in x), harmonics cut or padded with zeros."""
    def linear(cells):
        x = np.linspace(0.0, 1.0, cells + 1)[:, None]
        return np.hstack([3.0 * x, 1.0 + x, -x])  # H = 1

    U = linear(8)
    fine = transferred(U, 16, 2)
    assert fine.shape == (17, 5) and not np.any(fine[:, 3:])
    np.testing.assert_allclose(fine[:, :3], linear(16), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(transferred(U, 4, 0), U[::2, :1])


def test_a_solve_started_from_another_rung_is_the_solve(bar_load):
    """Newton started from a coarser rung's state transferred (``guess``) converges to the same state as from its
    own start: the estimate's rungs give the same force either way."""
    bar, load = bar_load
    a, w = 1.2e-6, 38400.0
    X = np.zeros(15)
    X[2] = a
    coarse = FixedBar(bar, load, 16, 7, 56).solve(X, w, True)
    plain = FixedBar(bar, load, 32, 7, 56).solve(X, w, True)
    started = FixedBar(bar, load, 32, 7, 56).solve(X, w, True, transferred(coarse.U, 32, 7))
    assert plain.success and started.success
    np.testing.assert_allclose(started.F, plain.F, rtol=0, atol=1e-9 * np.max(np.abs(plain.F)))
