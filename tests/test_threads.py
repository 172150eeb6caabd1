"""One BLAS thread while a call solves only small systems (``hbm._threads``)."""

import ctypes
import threading
from pathlib import Path

import numpy as np
import pytest

import hbm
from contact_models import Macroslip
from hbm._threads import SMALL_SYSTEM, one_blas_thread

pytestmark = pytest.mark.skipif(not Path("/proc/self/maps").exists(), reason="reads /proc/self/maps (Linux)")


def openblas():
    """(get, set) of every OpenBLAS in this process, found independently of the code under test."""
    np.linalg.solve(np.eye(2), np.ones(2))  # numpy's OpenBLAS is loaded
    with open("/proc/self/maps") as maps:
        paths = sorted({ln.split()[-1] for ln in maps if "openblas" in ln.lower() and ".so" in ln})
    out = []
    for path in paths:
        lib = ctypes.CDLL(path)
        for prefix in ("scipy_openblas", "openblas"):
            for suffix in ("64_", ""):
                get = getattr(lib, f"{prefix}_get_num_threads{suffix}", None)
                put = getattr(lib, f"{prefix}_set_num_threads{suffix}", None)
                if get is not None and put is not None:
                    get.restype = ctypes.c_int
                    out.append((get, put))
                    break
            else:
                continue
            break
    if not out:
        pytest.skip("no OpenBLAS in this numpy")
    return out


@pytest.fixture
def two_threads():
    libs = openblas()
    before = [get() for get, _ in libs]
    for _, put in libs:
        put(ctypes.c_int(2))
    yield libs
    for (_, put), n in zip(libs, before):
        put(ctypes.c_int(n))


def test_block_runs_on_one_thread_and_restores(two_threads):
    with one_blas_thread():
        assert [get() for get, _ in two_threads] == [1] * len(two_threads)
        with one_blas_thread():  # nested: still one, and the outer block's exit restores
            assert [get() for get, _ in two_threads] == [1] * len(two_threads)
        assert [get() for get, _ in two_threads] == [1] * len(two_threads)
    assert [get() for get, _ in two_threads] == [2] * len(two_threads)
    with one_blas_thread(False):
        assert [get() for get, _ in two_threads] == [2] * len(two_threads)


def test_concurrent_blocks_restore_once_the_last_leaves(two_threads):
    inside, release = threading.Event(), threading.Event()

    def other():
        with one_blas_thread():
            inside.set()
            release.wait(10)

    t = threading.Thread(target=other)
    t.start()
    inside.wait(10)
    with one_blas_thread():
        pass
    assert [get() for get, _ in two_threads] == [1] * len(two_threads)  # the other block still runs
    release.set()
    t.join(10)
    assert [get() for get, _ in two_threads] == [2] * len(two_threads)


def test_small_frf_solves_on_one_thread_and_restores(two_threads):
    """The Jenkins oscillator (one contact DOF, at most 2 x 31 + 1 harmonics in the estimate: 127
    unknowns <= SMALL_SYSTEM) traced on one thread; the count is given back after."""
    seen = []
    s = hbm.Structure(np.eye(1), [[0.004]], np.eye(1), force=[0.01])
    frf = hbm.frequency_response(s, [hbm.Contact(Macroslip(1.0, 0.02), dof=0)], omega_range=(0.6, 1.8),
                                 harmonics=3, tol=None, callback=lambda p: seen.append(two_threads[0][0]()))
    assert frf.success and len(seen) == len(frf) > 10
    assert set(seen) == {1}
    assert [get() for get, _ in two_threads] == [2] * len(two_threads)
    assert 127 <= SMALL_SYSTEM
