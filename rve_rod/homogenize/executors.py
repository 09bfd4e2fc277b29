"""Where RVE runs are computed: this process, a local process pool, or the ranks of an MPI job.

    local: `jobs` worker processes on this machine (`jobs=1`: in this process, no pickling)
    mpi:   the worker ranks of an `mpi4py.futures.MPIPoolExecutor`, when the program was
           launched as `mpirun -n N python -m mpi4py.futures -m knitmech ...` (or
           `-m rve_rod ...`): rank 0 is the driver, ranks 1..N-1 compute

The driver (`rve_rod.homogenize.generate`) submits independent runs and keeps their order, the
caching and the fit, so results do not depend on the executor or the number of workers.
mpi4py is imported only when the mpi executor is chosen.
"""

import concurrent.futures
from dataclasses import dataclass

from rve_rod.errors import InputError, check_integer

__all__ = [
    "EXECUTORS",
    "MPI_LAUNCH",
    "ExecutorChoice",
    "InProcessExecutor",
    "add_executor_argument",
    "isolated_process",
    "mpi_workers",
]

EXECUTORS: tuple[str, ...] = ("local", "mpi")
"""The executor names `--executor` accepts."""

MPI_LAUNCH = "mpirun -n N python -m mpi4py.futures -m knitmech|rve_rod ... --executor mpi"
"""How a program must be launched for the mpi executor (N >= 2: one driver, N-1 workers)."""


class InProcessExecutor(concurrent.futures.Executor):
    """Runs each submitted call at once, in this process (the `jobs=1` executor).

    An exception of the call is stored in its future, as a pool would; KeyboardInterrupt and
    other BaseExceptions propagate.
    """

    def submit(self, fn, /, *args, **kwargs) -> concurrent.futures.Future:
        future = concurrent.futures.Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception as error:
            future.set_exception(error)
        return future


def add_executor_argument(parser) -> None:
    """Add `--executor local|mpi` to an argparse parser (the CLIs that run RVE runs)."""
    parser.add_argument(
        "--executor",
        choices=EXECUTORS,
        default="local",
        help="where RVE runs are computed: local worker processes (default, --jobs) or the "
        f"worker ranks of an MPI job launched as `{MPI_LAUNCH}` (docs/cluster.md)",
    )


def isolated_process() -> concurrent.futures.Executor:
    """A pool of one fresh worker process (to tell which run kills its worker)."""
    return concurrent.futures.ProcessPoolExecutor(max_workers=1)


def mpi_workers() -> int:
    """The number of worker ranks of the mpi4py.futures pool this program runs in.

    Raises InputError (naming how to launch) when the program was not started as
    `mpirun -n N python -m mpi4py.futures ...` with N >= 2.
    """
    try:
        from mpi4py import MPI  # noqa: PLC0415 (MPI starts only when asked for)
        from mpi4py.futures import _lib  # noqa: PLC0415
    except ImportError as error:
        raise InputError(
            f"executor='mpi' needs mpi4py, which cannot be imported: {error}"
        ) from None
    size = MPI.COMM_WORLD.Get_size()
    # `python -m mpi4py.futures` installs the shared pool of the other ranks; it has no public
    # query (mpi4py 3.1), and without it every rank would run the whole program
    if _lib.SharedPool is None or size < 2:
        how = "without `-m mpi4py.futures`" if size > 1 else f"on {size} MPI rank"
        raise InputError(
            f"executor='mpi' was started {how}; launch it as `{MPI_LAUNCH}` with N >= 2 "
            "(rank 0 drives, ranks 1..N-1 compute the RVE runs)"
        )
    return size - 1


@dataclass(frozen=True)
class ExecutorChoice:
    """Where runs are computed.

    Attributes:
        kind: "local" (process pool of `jobs` workers) or "mpi" (worker ranks of an
            mpi4py.futures pool; their number is set by `mpirun -n`, `jobs` is not used).
        jobs: local worker processes, 1..256 (1: in this process).
    """

    kind: str = "local"
    jobs: int = 1

    def __post_init__(self):
        if self.kind not in EXECUTORS:
            raise InputError(f"executor={self.kind!r} is not one of {', '.join(EXECUTORS)}")
        check_integer("jobs", self.jobs, 1, 256)

    def workers(self) -> int:
        """How many runs are computed at once (checks an mpi launch; see `mpi_workers`)."""
        return mpi_workers() if self.kind == "mpi" else self.jobs

    def open(self, tasks: int) -> concurrent.futures.Executor:
        """An executor for `tasks` runs; the caller shuts it down."""
        if self.kind == "mpi":
            mpi_workers()
            from mpi4py.futures import MPIPoolExecutor  # noqa: PLC0415

            return MPIPoolExecutor()
        if self.jobs == 1:
            return InProcessExecutor()
        return concurrent.futures.ProcessPoolExecutor(max_workers=min(self.jobs, tasks))

    def describe(self) -> str:
        """e.g. "local, 2 jobs" or "mpi, 3 worker ranks"."""
        workers = self.workers()
        unit = "worker rank" if self.kind == "mpi" else "job"
        return f"{self.kind}, {workers} {unit}{'s' if workers > 1 else ''}"
