"""express.base.threads: the numerical paths limit BLAS threads themselves and restore them."""

from __future__ import annotations

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from express.analysis.frequency import frequency
from express.analysis.stability import stability
from express.analysis.time import simulate
from express.base import threads
from express.base.threads import ENVIRONMENT_VARIABLE, blas_limit, blas_threads, limited_blas
from express.io import load_model
from express.numeric.statespace import vehicle_model
from express.rail.track import paper_curve

KMH = 1 / 3.6


def blas_counts() -> list[int]:
    """Threads of every BLAS library loaded (NumPy's and SciPy's)."""
    return [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"]


@pytest.fixture(scope="module")
def car():
    return vehicle_model(load_model("examples/conventional.toml"))


@pytest.fixture
def two_threads(monkeypatch):
    """The caller's BLAS setting: 2 threads (restored by the test afterwards)."""
    monkeypatch.delenv(ENVIRONMENT_VARIABLE, raising=False)
    threads._blas_controller()  # both BLAS libraries loaded
    with threadpool_limits(limits=2, user_api="blas"):
        assert set(blas_counts()) == {2}
        yield


@pytest.fixture
def spy(monkeypatch):
    """Record the BLAS threads whenever NumPy solves or computes eigenvalues."""
    seen: list[list[int]] = []
    for name in ("solve", "eig", "eigvals", "inv"):
        original = getattr(np.linalg, name)

        def recording(*args, _original=original, **kwargs):
            seen.append(blas_counts())
            return _original(*args, **kwargs)

        monkeypatch.setattr(np.linalg, name, recording)
    return seen


CALLS = {
    "frequency_response": lambda car: frequency.frequency_response(car, [1.0, 2.0]),
    "root_locus": lambda car: stability.root_locus(car, [10.0, 20.0]),
    "max_real_part": lambda car: stability.max_real_part(car, [10.0, 20.0]),
    "eigen_analysis": lambda car: stability.eigen_analysis(car, 30.0),
    "critical_speed": lambda car: stability.critical_speed(car, v_max=60.0, points=8),
    "critical_speed_vs_conicity": lambda car: stability.critical_speed_vs_conicity(car, [0.1], v_max=60.0, points=8),
    "with_values": lambda car: car.with_values({"Gamma": 0.2}),
    "eigenvalues": lambda car: car.eigenvalues(30.0),
    "simulate": lambda car: simulate.simulate(car, paper_curve(), end=20.0),
}


@pytest.mark.parametrize("name", list(CALLS))
def test_numerical_paths_run_on_one_blas_thread_and_restore_it(car, two_threads, spy, name):
    CALLS[name](car)
    assert spy, f"{name} did no linear algebra through numpy.linalg"
    assert all(set(counts) == {1} for counts in spy), spy
    assert set(blas_counts()) == {2}


def test_an_outer_limit_is_kept_by_the_calls_inside(car, two_threads, spy):
    with blas_threads(2):
        stability.root_locus(car, [10.0, 20.0])
        car.with_values({"Gamma": 0.3})
    assert spy and all(set(counts) == {2} for counts in spy)
    assert set(blas_counts()) == {2}


def test_limits_nest_and_restore_in_order(two_threads):
    with blas_threads(1):
        assert set(blas_counts()) == {1}
        with blas_threads(2):  # inner: the outer limit stays
            assert set(blas_counts()) == {1}
        assert set(blas_counts()) == {1}
    assert set(blas_counts()) == {2}


def test_restored_after_an_exception(two_threads):
    @limited_blas
    def failing():
        assert set(blas_counts()) == {1}
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError, match="boom"):
        failing()
    assert set(blas_counts()) == {2}
    assert threads._depth == 0


@pytest.mark.parametrize("text, limit", [("", 1), ("1", 1), ("2", 2), (" 3 ", 3), ("0", None), ("none", None), ("None", None)])
def test_the_environment_variable_sets_the_limit(monkeypatch, text, limit):
    monkeypatch.setenv(ENVIRONMENT_VARIABLE, text)
    assert blas_limit() == limit


@pytest.mark.parametrize("text", ["-1", "two", "1.5"])
def test_a_bad_environment_variable_is_a_clear_error(monkeypatch, text):
    monkeypatch.setenv(ENVIRONMENT_VARIABLE, text)
    with pytest.raises(ValueError, match=ENVIRONMENT_VARIABLE):
        blas_limit()


def test_no_limit_leaves_blas_alone(car, two_threads, spy, monkeypatch):
    monkeypatch.setenv(ENVIRONMENT_VARIABLE, "none")
    stability.root_locus(car, [10.0, 20.0])
    assert spy and all(set(counts) == {2} for counts in spy)


def test_decorated_functions_keep_their_name_and_documentation():
    assert stability.root_locus.__name__ == "root_locus"
    assert "Eigenvalues of" in stability.root_locus.__doc__
    assert simulate.simulate.__wrapped__.__name__ == "simulate"


def test_a_bad_environment_variable_is_exit_2_on_the_command_line(monkeypatch, capsys):
    from express.cli import main

    monkeypatch.setenv(ENVIRONMENT_VARIABLE, "lots")
    status = main(["eigen", "examples/conventional.toml"])
    err = capsys.readouterr().err
    assert status == 2
    assert err.startswith("error: ") and ENVIRONMENT_VARIABLE in err and len(err.splitlines()) == 1


# One large dense problem (issue 24): more threads while the default limit holds

@pytest.fixture
def large_is_two(monkeypatch):
    """Two threads asked for a large problem (EXPRESS_BLAS_THREADS_LARGE=2)."""
    monkeypatch.delenv(ENVIRONMENT_VARIABLE, raising=False)
    monkeypatch.setenv(threads.LARGE_ENVIRONMENT_VARIABLE, "2")
    threads._blas_controller()


def test_by_default_a_large_problem_keeps_one_thread(monkeypatch):
    monkeypatch.delenv(ENVIRONMENT_VARIABLE, raising=False)
    monkeypatch.delenv(threads.LARGE_ENVIRONMENT_VARIABLE, raising=False)
    with blas_threads(), threads.large_problem_threads(10**4):
        assert set(blas_counts()) == {1}


@pytest.mark.parametrize("text", ["0", "-2", "two"])
def test_a_bad_large_problem_variable_is_a_clear_error(monkeypatch, text):
    monkeypatch.setenv(threads.LARGE_ENVIRONMENT_VARIABLE, text)
    with pytest.raises(ValueError, match=threads.LARGE_ENVIRONMENT_VARIABLE):
        threads.large_problem_limit()


def test_a_large_problem_gets_more_threads_inside_the_default_limit(large_is_two):
    with blas_threads():
        with threads.large_problem_threads(threads.LARGE_PROBLEM):
            assert set(blas_counts()) == {2}
        assert set(blas_counts()) == {1}
        with threads.large_problem_threads(threads.LARGE_PROBLEM - 1):  # not large
            assert set(blas_counts()) == {1}


@pytest.mark.parametrize("setting", ["1", "3"])
def test_a_set_environment_variable_holds_for_large_problems_too(large_is_two, monkeypatch, setting):
    monkeypatch.setenv(ENVIRONMENT_VARIABLE, setting)
    with blas_threads(), threads.large_problem_threads(10**4):
        assert set(blas_counts()) == {int(setting)}


def test_an_explicit_outer_limit_holds_for_large_problems(large_is_two):
    with blas_threads(1), threads.large_problem_threads(10**4):
        assert set(blas_counts()) == {1}


def test_workers_keep_one_thread_for_large_problems(large_is_two, monkeypatch):
    """A study's worker process, or a thread other than the main one, does not add threads
    for a large problem."""
    import multiprocessing
    import threading

    seen = []

    def inside():
        with blas_threads():
            before = blas_counts()
            with threads.large_problem_threads(10**4):
                seen.append((before, blas_counts()))

    worker = threading.Thread(target=inside)
    worker.start()
    worker.join()
    monkeypatch.setattr(multiprocessing, "parent_process", lambda: object())
    inside()
    assert seen[0][0] == seen[0][1]  # (OpenBLAS may ignore a limit set from another thread)
    assert set(seen[1][1]) == {1}


def test_eigen_analysis_of_a_large_a_runs_on_more_threads(car, large_is_two, spy, monkeypatch):
    monkeypatch.setattr(threads, "LARGE_PROBLEM", 2 * car.n)  # the car's A counts as large
    with blas_threads():  # as the command line does
        stability.eigen_analysis(car, 30.0)
    assert spy and all(set(counts) == {2} for counts in spy)
    assert set(blas_counts()) != {2} or threads._depth == 0
