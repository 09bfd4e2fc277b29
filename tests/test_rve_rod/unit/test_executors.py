"""Executor choice: checked settings, and the mpi executor refuses a launch it cannot use."""

import pytest

from rve_rod.errors import InputError
from rve_rod.homogenize.executors import ExecutorChoice, InProcessExecutor


@pytest.mark.parametrize(
    ("kind", "jobs", "message"),
    [
        ("slurm", 1, "executor='slurm' is not one of local, mpi"),
        ("local", 0, "jobs=0 is outside the valid range [1, 256]"),
        ("local", 1.5, "jobs=1.5 must be an integer"),
    ],
)
def test_bad_settings_name_the_parameter(kind, jobs, message):
    with pytest.raises(InputError, match=message.replace("[", r"\[").replace("]", r"\]")):
        ExecutorChoice(kind, jobs)


def test_mpi_outside_mpi4py_futures_says_how_to_launch():
    with pytest.raises(InputError, match=r"mpirun -n N python -m mpi4py\.futures -m knitmech"):
        ExecutorChoice("mpi").workers()


def test_in_process_executor_keeps_exceptions_in_the_future():
    with InProcessExecutor() as pool:
        good, bad = pool.submit(divmod, 7, 2), pool.submit(divmod, 1, 0)
    assert good.result() == (3, 1)
    assert isinstance(bad.exception(), ZeroDivisionError)
    assert ExecutorChoice("local", 3).describe() == "local, 3 jobs"
