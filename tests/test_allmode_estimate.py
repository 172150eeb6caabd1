"""``AllModeMicroslip.model_error`` at many points in two halves, on two threads where they pay
(``contact_models.allmode.estimate``): the answer of the halves in turn bit for bit, independent of the threads'
timing, the one-piece answer to the nested Newton's tolerance, the same records kept, errors raised on the caller's
thread, and one thread on rungs whose Newton loop is not compiled, on the numpy path and in a study's worker
processes."""

import threading
import time

import numpy as np
import pytest

from contact_models import AllModeMicroslip
from contact_models.allmode import estimate as est
from hbm.cli.cases import default_case

#: Twelve points along the default case's resonance where the bar slips, and two below slip.
OMEGA = np.linspace(38300.0, 39300.0, 14)
AMPLITUDE = np.r_[np.linspace(1.0e-6, 1.5e-6, 12), 1e-9, 2e-9]


@pytest.fixture
def element():
    """A fixed rung of the default case's damper (each test its own: the estimates start from its states)."""
    case = default_case()
    return lambda: AllModeMicroslip(case.element.bar, case.element.load, cells=16, harmonics=15)


@pytest.fixture
def two(monkeypatch):
    monkeypatch.setattr(est, "threads", lambda el: 2)


def serial(el, monkeypatch):
    monkeypatch.setattr(est, "threads", lambda el: 1)
    try:
        return el.model_error(AMPLITUDE, OMEGA, parts=True)
    finally:
        monkeypatch.undo()


def test_two_threads_give_the_halves_in_turn_bit_for_bit_and_one_piece_to_newtons_tolerance(element, monkeypatch):
    one_el, two_el = element(), element()
    one = serial(one_el, monkeypatch)
    calls = []
    start = threading.Thread.start
    monkeypatch.setattr(threading.Thread, "start", lambda self: (calls.append(self.name), start(self)))
    monkeypatch.setattr(est, "threads", lambda el: 2)
    both = two_el.model_error(AMPLITUDE, OMEGA, parts=True)
    assert calls == ["AllModeMicroslip estimate"]  # the second half did run on a thread
    assert np.all(one[0][:12] > 0.0) and np.all(one[1][:12] > 0.0)  # slipping: estimates of both components
    for a, b in zip(one, both):
        assert np.array_equal(a, b)
    assert [s[:2] for s in two_el._seen] == [s[:2] for s in one_el._seen]  # the records, in the points' order
    assert len(two_el._seen) == 14
    monkeypatch.setattr(est, "SPLIT_MIN_POINTS", 100)  # one piece: the second half's first solves start elsewhere
    whole = element().model_error(AMPLITUDE, OMEGA, parts=True)
    for a, b in zip(whole, both):
        np.testing.assert_allclose(b, a, rtol=1e-8, atol=0.0)  # measured: 6e-11


def test_the_answer_does_not_depend_on_the_threads_timing(element, two, monkeypatch):
    first = element().model_error(AMPLITUDE, OMEGA, parts=True)
    solve = est.estimate_one

    def late(el, ai, wi, e_s, e_c, i):  # the caller's half finishes long before the second thread's
        if threading.current_thread() is not threading.main_thread():
            time.sleep(0.01)
        return solve(el, ai, wi, e_s, e_c, i)

    monkeypatch.setattr(est, "estimate_one", late)
    again = element().model_error(AMPLITUDE, OMEGA, parts=True)
    for a, b in zip(first, again):
        assert np.array_equal(a, b)


def test_an_error_on_the_second_thread_is_raised_on_the_callers(element, two, monkeypatch):
    solve = est.estimate_one

    def failing(el, ai, wi, e_s, e_c, i):
        if threading.current_thread() is not threading.main_thread():
            raise FloatingPointError("on the second thread")
        return solve(el, ai, wi, e_s, e_c, i)

    monkeypatch.setattr(est, "estimate_one", failing)
    with pytest.raises(FloatingPointError, match="on the second thread"):
        element().model_error(AMPLITUDE, OMEGA)


def test_few_points_small_rungs_the_numpy_path_a_study_worker_and_one_thread_asked_for_run_on_the_callers(
        element, monkeypatch):
    started = []
    monkeypatch.setattr(threading.Thread, "start", lambda self: started.append(self))
    monkeypatch.setattr(est, "threads", lambda el: 2)
    element().model_error(AMPLITUDE[:est.SPLIT_MIN_POINTS - 1], OMEGA[:est.SPLIT_MIN_POINTS - 1])
    assert not started
    monkeypatch.undo()
    monkeypatch.setattr(est, "kernel", lambda name: object())  # as if loaded
    monkeypatch.setattr(est.os, "cpu_count", lambda: 2)
    case = default_case()
    top = AllModeMicroslip(case.element.bar, case.element.load, cells=32, harmonics=31)
    assert est.threads(top) == 2
    for small in (element(), AllModeMicroslip(case.element.bar, case.element.load, cells=32, harmonics=7),
                  AllModeMicroslip(case.element.bar, case.element.load)):  # Python-bound rungs, a choosing element
        assert est.threads(small) == 1
    with monkeypatch.context() as m:
        m.setattr(est, "kernel", lambda name: None)  # not loaded, or its Newton loop not cached yet
        assert est.threads(top) == 1
    with monkeypatch.context() as m:
        m.setattr(est.multiprocessing, "parent_process", lambda: object())
        assert est.threads(top) == 1
    with monkeypatch.context() as m:
        m.setattr(est, "ESTIMATE_THREADS", 1)
        assert est.threads(top) == 1
