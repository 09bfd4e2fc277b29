"""The launcher of the DOLFINx jobs: in this process alone, or under `mpirun -n ranks` in a
process group of its own that is taken down as a whole on any interruption. No DOLFINx is
imported here: a run is planned without it (`tests/project/unit/test_imports.py`).
"""

import contextlib
import importlib
import json
import logging
import os
import signal
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

__all__ = [
    "JOBS",
    "MPI_JOB_VARIABLES",
    "MPI_STOP_TIMEOUT_S",
    "StageError",
    "job_runner",
    "mpirun_environment",
    "run_job",
]

logger = logging.getLogger(__name__)

JOBS = {
    "patch": "knitmech.jobs.patch",
    "fabric": "knitmech.jobs.fabric",
    "sleeve": "knitmech.jobs.sleeve",
}
"""Job kind -> the module whose `run_request(request, folder, comm) -> dict` runs it."""

MPI_STOP_TIMEOUT_S = 10.0
"""Seconds mpirun and its ranks get to end after SIGTERM before they are killed."""

MPI_JOB_VARIABLES = (
    "PMIX_",
    "ORTE_",
    "OMPI_MCA_ess",
    "OMPI_MCA_orte_",
    "OMPI_MCA_pmix",
    "OMPI_APP_CTX_",
    "OMPI_COMM_WORLD_",
)
"""Prefixes of the environment variables of a running MPI job (set by its mpirun, or by Open
MPI for a process that initialized MPI alone): an `mpirun` started with them inherited exits
with 1 and no message, so no job's mpirun gets them (`mpirun_environment`). Such a parent
is e.g. a Python process that imported DOLFINx and then ran `knitmech run` (the test suite)."""


class StageError(RuntimeError):
    """A stage could not finish (e.g. its MPI run failed); finished stages stay cached."""


def job_runner(kind: str) -> Callable[[dict, Path, object], dict]:
    """The `run_request` of job `kind` (its module imported now: DOLFINx)."""
    return importlib.import_module(JOBS[kind]).run_request


def run_job(kind: str, request: dict, folder: Path, ranks: int, label: str = "") -> dict:
    """Run job `kind` on `request` (JSON data), its files into `folder`; returns its JSON
    summary. One rank: in this process, on MPI.COMM_SELF (under `python -m mpi4py.futures`,
    --executor mpi, the other ranks of COMM_WORLD serve RVE runs and take part in no
    collective call, not even PETSc's initialization, a no-op when PETSc is initialized
    already). More: under `mpirun -n ranks` (StageError naming `label` when it fails)."""
    if ranks == 1:
        import petsc4py  # noqa: PLC0415 (dolfinx on demand)
        from mpi4py import MPI  # noqa: PLC0415

        petsc4py.init(comm=MPI.COMM_SELF)
        return job_runner(kind)(request, Path(folder), MPI.COMM_SELF)
    folder = Path(folder)
    request_path, summary_path = folder / f".{kind}.json", folder / f".{kind}-summary.json"
    request_path.write_text(json.dumps(request))
    command = ["mpirun", "-n", str(ranks), sys.executable, "-m", "knitmech.jobs", kind]
    command += [str(request_path), str(folder), str(summary_path)]
    label = label or kind
    logger.debug("%s: %s", label, " ".join(command))
    returncode, stderr = _run_group(command, mpirun_environment())
    if returncode != 0:
        tail = "\n".join(stderr.strip().splitlines()[-5:])
        raise StageError(f"{label} under mpirun failed: {tail}")
    summary = json.loads(summary_path.read_text())
    for path in (request_path, summary_path):
        path.unlink()
    return summary


def _run_group(command: list[str], environment: dict) -> tuple[int, str]:
    """Run `command` in a process group of its own; returns its exit status and stderr.

    On any interruption (Ctrl-C, SIGTERM as `rve_rod.errors.Terminated`, an error) the whole
    group (mpirun and every rank) is sent SIGTERM, and SIGKILL after MPI_STOP_TIMEOUT_S, and
    waited for, so that no rank outlives the run or writes into a folder being removed.
    """
    process = subprocess.Popen(
        command,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env=environment,
        start_new_session=True,
    )
    try:
        _, stderr = process.communicate()
    except BaseException:
        for signum, timeout in ((signal.SIGTERM, MPI_STOP_TIMEOUT_S), (signal.SIGKILL, None)):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(process.pid, signum)
            try:
                process.wait(timeout)
                break
            except subprocess.TimeoutExpired:
                continue
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)  # ranks that outlived mpirun
        raise
    return process.returncode, stderr


def mpirun_environment() -> dict[str, str]:
    """The environment for an `mpirun` this process starts: its own, without the variables of
    an enclosing MPI job (`MPI_JOB_VARIABLES`; a job's mpirun is never meant to join one),
    with running as root and oversubscription allowed."""
    environment = {k: v for k, v in os.environ.items() if not k.startswith(MPI_JOB_VARIABLES)}
    environment.update(
        OMPI_ALLOW_RUN_AS_ROOT="1",
        OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
        OMPI_MCA_rmaps_base_oversubscribe="1",
    )
    return environment
