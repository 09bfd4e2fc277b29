"""Generating a response surface: independent RVE runs in parallel, cached and resumable, then fit.

Every run is stored in a `ResultCache` under a key made of all its inputs (fabric, load path,
the engine and its settings, the package version) the moment its result reaches the driver
(this process). An interrupted generation (killed worker, Ctrl-C, a crash) therefore resumes
where it stopped, and an unchanged run is never computed twice. A run that raises does not
stop the others: they finish and are cached, and the failures are reported together. Runs go
to an executor (`rve_rod.homogenize.executors`: local worker processes, or the ranks of an MPI
job); the driver keeps their order, so the results do not depend on the executor or on the
number of workers.
"""

import concurrent.futures
import dataclasses
import logging
import math
import time
from collections.abc import Sequence
from typing import NamedTuple, TextIO

from rve_rod.cache import ResultCache
from rve_rod.errors import ConvergenceError, InputError, raise_pending_interrupt
from rve_rod.homogenize.acceptance import surface_problems
from rve_rod.homogenize.executors import ExecutorChoice, isolated_process
from rve_rod.homogenize.fit import (
    FitOptions,
    FitReport,
    fit_energy_surface,
    fit_report,
    fit_stress_surface,
)
from rve_rod.homogenize.progress import Progress
from rve_rod.homogenize.samples import RveCase, RveRun, SurfaceSamples, surface_samples
from rve_rod.homogenize.sampling import SamplingPlan, contraction
from rve_rod.presets import Fabric
from rve_rod.surface import ResponseSurface

__all__ = [
    "PENETRATION_STOP",
    "WORKER_DIED",
    "GeneratedSurface",
    "GenerationError",
    "RunFailure",
    "RunTask",
    "RunsResult",
    "cached_count",
    "case_inputs",
    "engine_identity",
    "execute",
    "failure_message",
    "follow_fabric",
    "generate_surface",
    "run_cases",
    "run_tasks",
    "surface_from_runs",
]

logger = logging.getLogger(__name__)


class GenerationError(RuntimeError):
    """Runs of a batch failed; every other run finished and is cached.

    Attributes:
        failures: the failed runs and why.
    """

    def __init__(self, message: str, failures: tuple["RunFailure", ...] = ()):
        super().__init__(message)
        self.failures = failures


class RunTask(NamedTuple):
    """One RVE run to do.

    Attributes:
        engine: the RVE engine, a picklable callable (module-level function or dataclass).
        case: the fabric and load path to run.
    """

    engine: object
    case: RveCase


class RunFailure(NamedTuple):
    """A run that did not give a result.

    Attributes:
        index: its position in the batch.
        case: its fabric and load path.
        reason: the exception it raised ("TypeName: message"), or that its worker died.
    """

    index: int
    case: RveCase
    reason: str


class RunsResult(NamedTuple):
    """The runs of a batch, in the order of the cases.

    Attributes:
        runs: one RveRun per case; None for a failed run.
        computed: how many were computed now (failed ones not counted).
        cached: how many came from the cache.
        wall_time_s: wall time of the batch (s).
        run_times_s: compute time of each run in its worker (s); NaN if cached or failed.
        failures: the runs that failed, in the order of the cases.
    """

    runs: tuple[RveRun | None, ...]
    computed: int
    cached: int
    wall_time_s: float
    run_times_s: tuple[float, ...] = ()
    failures: tuple[RunFailure, ...] = ()


WORKER_DIED = "its worker process died (killed, out of memory or crashed) when it ran alone"
"""The reason of a run whose worker died: when a pool breaks before any of its runs ended,
the first unfinished run is run alone in a new process; if that dies too, the run failed."""


def engine_identity(run) -> dict:
    """What identifies an engine in cache keys: its import name and, for a dataclass, fields.

    An engine may define `cache_identity() -> dict` instead, e.g. to leave out settings that
    do not change its results (verbosity) or to declare itself equivalent to another engine.
    """
    if hasattr(run, "cache_identity"):
        return dict(run.cache_identity())
    target = run if not dataclasses.is_dataclass(run) else type(run)
    name = f"{target.__module__}.{target.__qualname__}"
    settings = dataclasses.asdict(run) if dataclasses.is_dataclass(run) else {}
    return {"engine": name, "settings": settings}


def case_inputs(case: RveCase, run) -> dict:
    """All inputs of one run for its cache key; display names (of presets) are left out."""
    fabric = case.fabric
    yarn = {k: v for k, v in dataclasses.asdict(fabric.yarn).items() if k != "name"}
    if yarn["fibres"] is not None:
        yarn["fibres"] = {k: v for k, v in yarn["fibres"].items() if k != "name"}
    return {
        "yarn": yarn,
        "knit": dataclasses.asdict(fabric.knit),
        "load": case.load,
        **engine_identity(run),
    }


PENETRATION_STOP = "CellSettings.penetration_limit"
"""Words of the refusal of a state beyond the penetration limit (`rve_rod.rve.cell`)."""


def execute(run, case: RveCase) -> RveRun:
    """`run(case)`; a ConvergenceError carrying an RveRun becomes that (incomplete) run."""
    try:
        result = run(case)
    except ConvergenceError as error:
        if not isinstance(error.history, RveRun):
            raise
        # a ray that stops where the yarns would pass through each other is expected (the
        # fit continues the surface beyond it; the run reports a count): INFO, not WARNING
        expected = PENETRATION_STOP in str(error)
        logger.log(
            logging.INFO if expected else logging.WARNING,
            "%s stopped after %d of %d steps: %s",
            case.load,
            error.history.deformation_gradient.shape[0],
            case.load.steps,
            "at the penetration limit" if expected else error,
        )
        return dataclasses.replace(error.history, complete=False)
    if not isinstance(result, RveRun):
        raise TypeError(f"the RVE engine returned {type(result).__name__}, not RveRun")
    return result


def _compute(task: RunTask) -> tuple[dict, float]:
    """Worker task: one run's arrays and its compute time (s)."""
    started = time.perf_counter()
    arrays = execute(task.engine, task.case).to_arrays()
    return arrays, time.perf_counter() - started


def run_tasks(
    tasks: Sequence[RunTask],
    *,
    cache: ResultCache | None = None,
    executor: ExecutorChoice | None = None,
    progress: Progress | None = None,
) -> RunsResult:
    """Do every task not in the cache on `executor`; a failing run does not stop the others.

    Each result is stored in `cache` by this process (the driver) the moment it arrives, so
    the cache needs to be visible to the driver only. A run that raises is reported in
    `failures` with its exception. When a worker process dies, the runs its pool took down
    are submitted again to a fresh pool; a pool that breaks before any run ended has its
    first unfinished run run alone, which fails it (WORKER_DIED) if that process dies too.
    Every round ends a run, so this stops.

    Args:
        tasks: the runs to do (engines may differ between tasks).
        cache: where results are stored and looked up; None computes everything.
        executor: where runs are computed (default: in this process).
        progress: the progress display to advance (its total and cached counts are the
            caller's), or None.
    """
    executor = executor or ExecutorChoice()
    started = time.monotonic()
    inputs = [case_inputs(task.case, task.engine) for task in tasks]
    results: list[RveRun | None] = [None] * len(tasks)
    times = [math.nan] * len(tasks)
    if cache is not None:
        for index, key_inputs in enumerate(inputs):
            arrays = cache.load(key_inputs)
            if arrays is not None:
                results[index] = RveRun.from_arrays(arrays)
    pending = [index for index, result in enumerate(results) if result is None]
    failures: dict[int, str] = {}

    def finished(index: int, arrays: dict, seconds: float) -> None:
        if cache is not None:
            cache.store(inputs[index], arrays)
        results[index] = RveRun.from_arrays(arrays)
        times[index] = seconds
        if progress:
            progress.advance()

    def failed(index: int, reason: str) -> None:
        logger.warning(
            "run %s of %s failed: %s", tasks[index].case.load, _knit(tasks, index), reason
        )
        failures[index] = reason
        if progress:
            progress.advance(failed=True)

    queue = pending
    while queue:
        broken = _submit(tasks, queue, executor.open(len(queue)), finished, failed)
        if broken and len(broken) == len(queue):
            # the pool broke before any run ended: run the first suspect alone
            suspect, broken = broken[0], broken[1:]
            if _submit(tasks, [suspect], isolated_process(), finished, failed):
                failed(suspect, WORKER_DIED)
        if broken:
            logger.warning(
                "a worker process died: submitting %d unfinished runs again", len(broken)
            )
        queue = broken
    return RunsResult(
        runs=tuple(results),
        computed=sum(result is not None for result in results) - (len(tasks) - len(pending)),
        cached=len(tasks) - len(pending),
        wall_time_s=time.monotonic() - started,
        run_times_s=tuple(times),
        failures=tuple(
            RunFailure(index, tasks[index].case, failures[index]) for index in sorted(failures)
        ),
    )


def _knit(tasks: Sequence[RunTask], index: int) -> str:
    fabric = tasks[index].case.fabric
    return fabric.name or f"w={fabric.knit.wale_width} c={fabric.knit.course_height} mm"


def _submit(tasks, indices, pool: concurrent.futures.Executor, finished, failed) -> list[int]:
    """Compute the runs `indices` on `pool` (shut down here), reporting each to `finished` or
    `failed` as it ends; returns the runs left unfinished by a broken pool."""
    broken = []
    try:
        futures = {pool.submit(_compute, tasks[index]): index for index in indices}
        for future in concurrent.futures.as_completed(futures):
            raise_pending_interrupt()  # a Ctrl-C that landed in a fork's hook (rve_rod.errors)
            index = futures[future]
            try:
                arrays, seconds = future.result()
            except concurrent.futures.BrokenExecutor:
                broken.append(index)
            except Exception as error:
                failed(index, f"{type(error).__name__}: {error}")
            else:
                finished(index, arrays, seconds)
    except BaseException:
        # Ctrl-C: do not wait for the runs under way (their workers get the signal too)
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)
    return sorted(broken)


def run_cases(
    cases: list[RveCase],
    run,
    *,
    cache: ResultCache | None = None,
    executor: str = "local",
    jobs: int = 1,
    progress: TextIO | None = None,
) -> RunsResult:
    """Run `run(case)` for every case not in the cache, on `executor`.

    Args:
        cases: the runs to do.
        run: the RVE engine, a picklable callable (module-level function or dataclass).
        cache: where results are stored and looked up; None computes everything.
        executor: "local" or "mpi" (see `rve_rod.homogenize.executors`).
        jobs: local worker processes (1: in this process).
        progress: stream for a progress bar (e.g. sys.stderr), or None.

    Raises GenerationError naming the failed runs and why when any failed; every other run is
    finished and cached by then.
    """
    choice = ExecutorChoice(executor, jobs)
    choice.workers()  # an mpi launch is checked before the cache is read
    tasks = [RunTask(run, case) for case in cases]
    bar = None
    if progress:
        bar = Progress(progress, len(tasks), cached_count(tasks, cache))
        bar.draw()
    outcome = run_tasks(tasks, cache=cache, executor=choice, progress=bar)
    if outcome.failures:
        raise GenerationError(failure_message(outcome, cache), outcome.failures)
    return outcome


def cached_count(tasks: Sequence[RunTask], cache: ResultCache | None) -> int:
    """How many of `tasks` have an entry in `cache` (for the progress display)."""
    if cache is None:
        return 0
    return sum(cache.path(case_inputs(task.case, task.engine)).is_file() for task in tasks)


def failure_message(outcome: RunsResult, cache: ResultCache | None) -> str:
    """One line per failed run, after how many runs finished and where they are."""
    done = sum(run is not None for run in outcome.runs)
    where = f"cached in {cache.folder}" if cache is not None else "not cached (no cache)"
    lines = [
        f"{len(outcome.failures)} of {len(outcome.runs)} runs failed; the {done} others are "
        f"{where}: run again to compute only what is missing"
    ]
    lines += [f"  {failure.case.load}: {failure.reason}" for failure in outcome.failures]
    return "\n".join(lines)


class GeneratedSurface(NamedTuple):
    """A generated response surface with what it was made from.

    Attributes:
        surface: the fitted surface (kind as requested), parameters filled in.
        reports: FitReport of both fits, "stress" and "energy", so users can compare.
        samples: the (E, S) samples of the runs.
        runs: the runs and how many were computed or cached.
    """

    surface: ResponseSurface
    reports: dict[str, FitReport]
    samples: SurfaceSamples
    runs: RunsResult


def generate_surface(
    fabric: Fabric,
    run,
    plan: SamplingPlan | None = None,
    options: FitOptions | None = None,
    *,
    kind: str = "stress",
    cache: ResultCache | None = None,
    executor: str = "local",
    jobs: int = 1,
    progress: TextIO | None = None,
) -> GeneratedSurface:
    """Run the RVE along every load path of `plan`, fit the surface of `kind`, report both fits.

    `run` is the RVE engine (see `rve_rod.homogenize.samples`); `plan` and `options` default
    to SamplingPlan() and FitOptions(); `executor` and `jobs` say where the runs are computed
    (`rve_rod.homogenize.executors`; the surface does not depend on them). The returned
    surface carries the parameters that regenerate it (fabric, sampling, fit, engine).

    Raises GenerationError when runs failed (the others are cached).
    """
    plan = plan or SamplingPlan()
    if kind not in ("stress", "energy"):
        raise InputError(f"kind={kind!r} must be 'stress' or 'energy'")
    where = {"cache": cache, "executor": executor, "jobs": jobs, "progress": progress}
    plan = follow_fabric(fabric, run, plan, **where)
    outcome = run_cases([RveCase(fabric, path) for path in plan.load_paths()], run, **where)
    return surface_from_runs(fabric, run, plan, options, kind=kind, outcome=outcome)


def follow_fabric(fabric: Fabric, run, plan: SamplingPlan, **where) -> SamplingPlan:
    """`plan`, or where it has no compression limit, the plan whose box follows the fabric's
    contraction: its `contraction_paths` run by `run` (`where`: cache, executor, jobs, progress
    as `run_cases`), then `SamplingPlan.following`."""
    if plan.max_compression is not None:
        return plan
    paths = plan.contraction_paths()
    outcome = run_cases([RveCase(fabric, path) for path in paths], run, **where)
    followed = plan.following(outcome.runs)
    logger.info(
        "the sampled box follows the fabric: it narrows by %.3g in uniaxial tension to %.3g, "
        "compression sampled to %.3g",
        contraction(paths, outcome.runs),
        plan.max_tension,
        followed.max_compression,
    )
    return followed


def surface_from_runs(
    fabric: Fabric,
    run,
    plan: SamplingPlan,
    options: FitOptions | None,
    *,
    kind: str,
    outcome: RunsResult,
) -> GeneratedSurface:
    """Fit the surface of `kind` (and report both fits) from the runs of `plan`'s load paths,
    done by engine `run` (`outcome.runs` in the order of `plan.load_paths()`, none failed)."""
    options = options or FitOptions()
    paths = plan.load_paths()
    samples = surface_samples(paths, outcome.runs)
    surfaces = {
        "stress": fit_stress_surface(samples, options),
        "energy": fit_energy_surface(samples, options),
    }
    incomplete = [
        dataclasses.asdict(path)
        for path, result in zip(paths, outcome.runs, strict=True)
        if not result.complete
    ]
    parameters = {
        "fabric": dataclasses.asdict(fabric),
        "sampling": dataclasses.asdict(plan),
        **surfaces[kind].parameters,
        **engine_identity(run),
        "incomplete_runs": incomplete,
    }
    checks = surface_problems(surfaces[kind])
    for problem in checks:
        logger.warning("the new %s surface fails a check: %s", kind, problem)
    parameters["checks"] = checks
    surface = dataclasses.replace(surfaces[kind], parameters=parameters)
    return GeneratedSurface(
        surface=surface,
        reports={name: fit_report(surface) for name, surface in surfaces.items()},
        samples=samples,
        runs=outcome,
    )
