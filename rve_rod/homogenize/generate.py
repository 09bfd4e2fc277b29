"""Generating a response surface: independent RVE runs in parallel, cached and resumable, then fit.

Every run is stored in a `ResultCache` under a key made of all its inputs (fabric, load path,
the engine and its settings, the package version) as soon as it finishes, by the worker that
computed it. An interrupted generation (killed worker, Ctrl-C, a crash) therefore resumes
where it stopped, and an unchanged run is never computed twice. Runs go to worker processes
(`concurrent.futures.ProcessPoolExecutor`) when `jobs > 1`; the results do not depend on
`jobs`.
"""

import dataclasses
import logging
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from typing import NamedTuple, TextIO

from rve_rod.cache import ResultCache
from rve_rod.errors import ConvergenceError, InputError, check_integer
from rve_rod.homogenize.acceptance import surface_problems
from rve_rod.homogenize.fit import (
    FitOptions,
    FitReport,
    fit_energy_surface,
    fit_report,
    fit_stress_surface,
)
from rve_rod.homogenize.progress import Progress
from rve_rod.homogenize.samples import RveCase, RveRun, SurfaceSamples, surface_samples
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.presets import Fabric
from rve_rod.surface import ResponseSurface

__all__ = [
    "GeneratedSurface",
    "GenerationError",
    "RunsResult",
    "case_inputs",
    "engine_identity",
    "execute",
    "generate_surface",
    "run_cases",
]

logger = logging.getLogger(__name__)


class GenerationError(RuntimeError):
    """A batch of runs stopped (a worker died or a run failed); finished runs are cached."""


class RunsResult(NamedTuple):
    """The runs of a batch, in the order of the cases.

    Attributes:
        runs: one RveRun per case.
        computed: how many were computed now.
        cached: how many came from the cache.
        wall_time_s: wall time of the batch (s).
    """

    runs: tuple[RveRun, ...]
    computed: int
    cached: int
    wall_time_s: float


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
    return {
        "yarn": yarn,
        "knit": dataclasses.asdict(fabric.knit),
        "load": case.load,
        **engine_identity(run),
    }


def execute(run, case: RveCase) -> RveRun:
    """`run(case)`; a ConvergenceError carrying an RveRun becomes that (incomplete) run."""
    try:
        result = run(case)
    except ConvergenceError as error:
        if not isinstance(error.history, RveRun):
            raise
        logger.warning(
            "%s stopped after %d of %d steps: %s",
            case.load,
            error.history.deformation_gradient.shape[0],
            case.load.steps,
            error,
        )
        return dataclasses.replace(error.history, complete=False)
    if not isinstance(result, RveRun):
        raise TypeError(f"the RVE engine returned {type(result).__name__}, not RveRun")
    return result


def _execute_and_store(run, case: RveCase, cache: ResultCache | None, inputs: dict) -> dict:
    """Worker task: compute one run and cache it at once; returns its arrays."""
    arrays = execute(run, case).to_arrays()
    if cache is not None:
        cache.store(inputs, arrays)
    return arrays


def run_cases(
    cases: list[RveCase],
    run,
    *,
    cache: ResultCache | None = None,
    jobs: int = 1,
    progress: TextIO | None = None,
) -> RunsResult:
    """Run `run(case)` for every case not in the cache, on `jobs` worker processes.

    Args:
        cases: the runs to do.
        run: the RVE engine, a picklable callable (module-level function or dataclass).
        cache: where results are stored and looked up; None computes everything.
        jobs: worker processes (1: in this process).
        progress: stream for a progress bar (e.g. sys.stderr), or None.

    Raises GenerationError when a worker dies; every finished run is cached by then.
    """
    check_integer("jobs", jobs, 1, 256)
    started = time.monotonic()
    inputs = [case_inputs(case, run) for case in cases]
    results: list[RveRun | None] = [None] * len(cases)
    if cache is not None:
        for index, key_inputs in enumerate(inputs):
            arrays = cache.load(key_inputs)
            if arrays is not None:
                results[index] = RveRun.from_arrays(arrays)
    pending = [index for index, result in enumerate(results) if result is None]
    bar = Progress(progress, len(cases), len(cases) - len(pending)) if progress else None
    if bar:
        bar.draw()
    if jobs == 1 or len(pending) <= 1:
        for index in pending:
            results[index] = RveRun.from_arrays(
                _execute_and_store(run, cases[index], cache, inputs[index])
            )
            if bar:
                bar.advance()
    else:
        _run_parallel(
            run, cases, inputs, pending=pending, results=results, cache=cache, jobs=jobs, bar=bar
        )
    return RunsResult(
        runs=tuple(results),
        computed=len(pending),
        cached=len(cases) - len(pending),
        wall_time_s=time.monotonic() - started,
    )


def _run_parallel(run, cases, inputs, *, pending, results, cache, jobs, bar) -> None:
    """Compute the `pending` runs on `jobs` processes, filling `results` in place."""
    pool = ProcessPoolExecutor(max_workers=min(jobs, len(pending)))
    try:
        futures = {
            pool.submit(_execute_and_store, run, cases[index], cache, inputs[index]): index
            for index in pending
        }
        for future in as_completed(futures):
            results[futures[future]] = RveRun.from_arrays(future.result())
            if bar:
                bar.advance()
    except BrokenProcessPool as error:
        pool.shutdown(wait=False, cancel_futures=True)
        done = sum(result is not None for result in results)
        where = f"cached in {cache.folder}" if cache is not None else "lost (no cache)"
        raise GenerationError(
            f"a worker process died; {done} of {len(cases)} runs are {where}: run again to resume"
        ) from error
    except Exception:
        # a run failed: the runs already started finish (and are cached), the rest is dropped
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    except BaseException:
        # Ctrl-C: do not wait; started runs still finish in the background and are cached
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


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
    jobs: int = 1,
    progress: TextIO | None = None,
) -> GeneratedSurface:
    """Run the RVE along every load path of `plan`, fit the surface of `kind`, report both fits.

    `run` is the RVE engine (see `rve_rod.homogenize.samples`); `plan` and `options` default
    to SamplingPlan() and FitOptions(). The returned surface carries the parameters that
    regenerate it (fabric, sampling, fit, engine).
    """
    plan = plan or SamplingPlan()
    options = options or FitOptions()
    if kind not in ("stress", "energy"):
        raise InputError(f"kind={kind!r} must be 'stress' or 'energy'")
    paths = plan.load_paths()
    outcome = run_cases(
        [RveCase(fabric, path) for path in paths], run, cache=cache, jobs=jobs, progress=progress
    )
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
