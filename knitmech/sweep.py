"""Sweeps: the response surfaces of many knits from one file, all their RVE runs in one batch.

    knitmech sweep SWEEP.toml [-o sweep] [--executor local|mpi] [--jobs N] [--cache-dir DIR]

A sweep file names a fidelity level, the surface settings of a scene's `[surface]` table and
the knits: `[grid]` (every combination of its lists) and/or `[[knits]]` (one table per knit),
each table with the keys of a scene's `[fabric]` table (docs/cluster.md):

    name = "cotton 20s/2 over its six stitch values"
    fidelity = "fast"
    [grid]
    preset = "cotton-20s2"
    stitch = [4.5, 5.0, 5.5, 6.0, 6.5, 7.0]

Every knit is checked before anything runs (all problems at once, naming the knit and key).
The RVE runs of all knits go to the executor together (one progress display), each cached
the moment it finishes in the RVE-run cache that `knitmech run` and `rve-rod surface` share;
a run that fails does not stop the others. A knit whose runs all finished is fitted and its
surface file written as `<folder>/<knit>.h5`, the file `knitmech run` would write as
`surface.h5` for the same fabric and settings. The folder also gets `summary.json` and
`summary.txt` (the table printed at the end). Exit status 3 when runs failed; running the
sweep again computes only those.
"""

import dataclasses
import itertools
import json
import logging
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple, TextIO

from knitmech.fidelity import LEVELS, fidelity_level
from knitmech.scene import Scene, SceneError, scene_from_dict
from knitmech.scene.keys import read_toml, unknown_key
from knitmech.stages import RunPlan, plan_run
from rve_rod.cache import ResultCache, default_cache_root
from rve_rod.homogenize.executors import ExecutorChoice
from rve_rod.homogenize.generate import (
    GenerationError,
    RunFailure,
    RunsResult,
    RunTask,
    cached_count,
    failure_message,
    run_tasks,
    surface_from_runs,
)
from rve_rod.homogenize.progress import Progress
from rve_rod.homogenize.samples import RveCase
from rve_rod.jsonable import to_jsonable
from rve_rod.rve import RodRve
from rve_rod.surface import write_surface

__all__ = [
    "FAILED_EXIT_STATUS",
    "SUMMARY_FILE",
    "KnitOutcome",
    "Sweep",
    "SweepKnit",
    "SweepResult",
    "knit_label",
    "load_sweep",
    "rod_engine",
    "run_sweep",
    "summary_table",
    "sweep_from_dict",
]

logger = logging.getLogger(__name__)

SUMMARY_FILE = "summary.json"
FAILED_EXIT_STATUS = 3
"""Exit status of a sweep whose runs failed (the others are cached and their surfaces written)."""

_KEYS = ("name", "fidelity", "surface", "grid", "knits")


@dataclass(frozen=True)
class SweepKnit:
    """One knit of a sweep.

    Attributes:
        label: its name in the table and its surface file's stem, e.g.
            "cotton-20s2_stitch-5.5" (the preset, then key-value of every other fabric key).
        scene: a scene with its fabric and the sweep's fidelity and surface settings.
    """

    label: str
    scene: Scene


@dataclass(frozen=True)
class Sweep:
    """A checked sweep file.

    Attributes:
        name: what the sweep is for.
        fidelity: the level of every knit.
        knits: the knits, grid first, then the list, in file order.
    """

    name: str
    fidelity: str
    knits: tuple[SweepKnit, ...]


class KnitOutcome(NamedTuple):
    """What a sweep did for one knit.

    Attributes:
        label: the knit's label.
        runs: its RVE runs.
        computed: runs computed now.
        cached: runs taken from the cache.
        failures: its failed runs.
        compute_s: the summed compute time of its runs computed now (s, in the workers).
        fit_s: the time of its fit and file (s, in the driver; 0 when not fitted).
        surface_file: the written surface file, or None when runs failed.
    """

    label: str
    runs: int
    computed: int
    cached: int
    failures: tuple[RunFailure, ...]
    compute_s: float
    fit_s: float
    surface_file: Path | None


class SweepResult(NamedTuple):
    """A finished sweep.

    Attributes:
        sweep: what was run.
        folder: the output folder.
        knits: one outcome per knit, in the sweep's order.
        runs: the batch of all runs (run_times_s gives the distribution of run times).
        executor: where the runs were computed, e.g. "local, 2 jobs".
        wall_time_s: wall time of the whole sweep (s).
        table: the printed summary (also in summary.txt).
    """

    sweep: Sweep
    folder: Path
    knits: tuple[KnitOutcome, ...]
    runs: RunsResult
    executor: str
    wall_time_s: float
    table: str

    @property
    def failed(self) -> bool:
        """Whether any run failed."""
        return bool(self.runs.failures)


def load_sweep(path: str | Path) -> Sweep:
    """Read and check a sweep file (see the module docstring)."""
    path = Path(path)
    return sweep_from_dict(read_toml(path, "sweep file"), source=str(path))


def sweep_from_dict(data: dict, source: str = "<dict>") -> Sweep:
    """Build a Sweep from parsed TOML; every problem of every knit goes into one SceneError."""
    problems = [unknown_key(key, _KEYS) for key in data if key not in _KEYS]
    name = data.get("name", "sweep")
    fidelity = data.get("fidelity", "balanced")
    if fidelity not in LEVELS:
        problems.append(f"fidelity: {fidelity!r} is not one of {', '.join(LEVELS)}")
        fidelity = "balanced"
    surface = data.get("surface", {})
    if not isinstance(surface, dict) or "path" in surface:
        problems.append("surface: a table of sampling settings (without path: a sweep makes them)")
        surface = {}
    tables = _grid_tables(data.get("grid"), problems)
    listed = data.get("knits", [])
    if not isinstance(listed, list) or not all(isinstance(item, dict) for item in listed):
        problems.append("knits: expected an array of tables ([[knits]])")
        listed = []
    tables += [(f"knits[{index}]", table) for index, table in enumerate(listed)]
    if not tables and not problems:
        problems.append("grid, knits: the sweep has no knit")
    knits, labels = [], {}
    for where, table in tables:
        label = knit_label(table)
        if label in labels:
            problems.append(f"{where}: the same knit as {labels[label]} ({label})")
            continue
        labels[label] = where
        scene_data = {"name": f"{name}: {label}", "fidelity": fidelity, "fabric": table}
        try:
            scene = scene_from_dict({**scene_data, "surface": surface}, source=where)
        except SceneError as error:
            problems += [f"{where} ({label}): {problem}" for problem in error.problems]
            continue
        knits.append(SweepKnit(label, scene))
    if problems:
        raise SceneError(source, problems)
    return Sweep(str(name), fidelity, tuple(knits))


def _grid_tables(grid, problems: list[str]) -> list[tuple[str, dict]]:
    """The fabric tables of every combination of a [grid] table's values (lists or single)."""
    if grid is None:
        return []
    if not isinstance(grid, dict) or not grid:
        problems.append("grid: expected a table of fabric keys and lists of values")
        return []
    axes = [value if isinstance(value, list) else [value] for value in grid.values()]
    return [
        (f"grid[{index}]", dict(zip(grid, values, strict=True)))
        for index, values in enumerate(itertools.product(*axes))
    ]


def knit_label(table: dict) -> str:
    """ "cotton-20s2_stitch-5.5_friction-0.3": the preset, then key-value of the other keys."""
    parts = [str(table["preset"])] if "preset" in table else []
    parts += [f"{key}-{value}" for key, value in table.items() if key != "preset"]
    return "_".join(parts) or "knit"


def rod_engine(plan: RunPlan) -> RodRve:
    """The RVE engine of a knit's plan (what `knitmech run` uses for its surface)."""
    return RodRve(plan.rve)


def run_sweep(  # noqa: PLR0913 (the sweep and the keyword options of `knitmech sweep`)
    sweep: Sweep,
    output: str | Path = "sweep",
    *,
    cache_dir: str | Path | None = None,
    executor: str = "local",
    jobs: int = 1,
    progress: TextIO | None = None,
    engine=rod_engine,
) -> SweepResult:
    """Compute the surfaces of every knit of `sweep` into the folder `output`.

    Knits whose sampled box follows the fabric (no `max_compression`) first run their two
    uniaxial contraction runs, all in one batch; the batch of the surfaces' runs (what the
    summary counts and times) follows.

    Args:
        sweep: the knits (`load_sweep`).
        output: the folder of the surface files and summaries (created).
        cache_dir: root of the caches (default: `rve_rod.cache.default_cache_root()`);
            the runs go to its `rve-runs/`.
        executor: "local" or "mpi" (`rve_rod.homogenize.executors`).
        jobs: local worker processes.
        progress: stream for the progress display of all runs (None: none).
        engine: the RVE engine of a knit's RunPlan (tests pass analytic ones).
    """
    started = time.monotonic()
    choice = ExecutorChoice(executor, jobs)
    described = choice.describe()  # checks an mpi launch before anything runs
    level = fidelity_level(sweep.fidelity)
    plans = [plan_run(knit.scene, level) for knit in sweep.knits]
    engines = [engine(plan) for plan in plans]
    cache = ResultCache(Path(cache_dir or default_cache_root()) / "rve-runs")
    plans = _follow_fabrics(plans, engines, cache, choice, progress)
    tasks, spans = [], []
    for plan, knit_engine in zip(plans, engines, strict=True):
        first = len(tasks)
        tasks += [RunTask(knit_engine, RveCase(plan.fabric, p)) for p in plan.sampling.load_paths()]
        spans.append(slice(first, len(tasks)))
    folder = Path(output)
    folder.mkdir(parents=True, exist_ok=True)
    bar = None
    if progress:
        bar = Progress(progress, len(tasks), cached_count(tasks, cache), label="sweep RVE runs")
        bar.draw()
    batch = run_tasks(tasks, cache=cache, executor=choice, progress=bar)
    knits = [
        _finish_knit(knit, plan, knit_engine, batch, span, folder=folder)
        for knit, plan, knit_engine, span in zip(sweep.knits, plans, engines, spans, strict=True)
    ]
    wall = time.monotonic() - started
    summary = _summary(sweep, knits, batch, described, wall)
    table = summary_table(summary)
    (folder / "summary.txt").write_text(table + "\n")
    (folder / SUMMARY_FILE).write_text(json.dumps(summary, indent=1, allow_nan=False))
    return SweepResult(sweep, folder, tuple(knits), batch, described, wall, table)


def _follow_fabrics(plans, engines, cache, choice, progress) -> list[RunPlan]:
    """`plans` with every sampled box that follows its fabric resolved
    (`rve_rod.homogenize.generate.follow_fabric`): the contraction runs of all such knits in
    one batch. Raises GenerationError when any of them failed (the others are cached)."""
    following = [i for i, plan in enumerate(plans) if plan.sampling.max_compression is None]
    tasks = [
        RunTask(engines[i], RveCase(plans[i].fabric, path))
        for i in following
        for path in plans[i].sampling.contraction_paths()
    ]
    if not tasks:
        return plans
    bar = None
    if progress:
        bar = Progress(progress, len(tasks), cached_count(tasks, cache), label="contraction runs")
        bar.draw()
    batch = run_tasks(tasks, cache=cache, executor=choice, progress=bar)
    if batch.failures:
        raise GenerationError(failure_message(batch, cache), batch.failures)
    resolved = list(plans)
    per_knit = len(tasks) // len(following)
    for n, i in enumerate(following):
        runs = batch.runs[n * per_knit : (n + 1) * per_knit]
        resolved[i] = plans[i]._replace(sampling=plans[i].sampling.following(runs))
    return resolved


def _finish_knit(knit, plan, knit_engine, batch: RunsResult, span: slice, *, folder: Path):
    """Fit and write one knit's surface when all its runs finished."""
    indices = range(len(batch.runs))[span]
    failures = tuple(f for f in batch.failures if f.index in indices)
    times = [t for t in batch.run_times_s[span] if not math.isnan(t)]  # NaN: cached or failed
    cached = sum(run is not None for run in batch.runs[span]) - len(times)
    path, fit_s = None, 0.0
    if not failures:
        begun = time.monotonic()
        runs = batch._replace(runs=batch.runs[span], run_times_s=batch.run_times_s[span])
        runs = runs._replace(computed=len(times), cached=cached, failures=())
        generated = surface_from_runs(
            plan.fabric,
            knit_engine,
            plan.sampling,
            plan.fit,
            kind=plan.scene.surface.kind,
            outcome=runs,
        )
        path = write_surface(folder / f"{knit.label}.h5", generated.surface)
        fit_s = time.monotonic() - begun
    return KnitOutcome(
        knit.label, len(indices), len(times), cached, failures, sum(times), fit_s, path
    )


def _summary(sweep: Sweep, knits, batch: RunsResult, executor: str, wall: float) -> dict:
    return to_jsonable(
        {
            "name": sweep.name,
            "fidelity": sweep.fidelity,
            "executor": executor,
            "wall_time_s": wall,
            "runs": len(batch.runs),
            "computed": batch.computed,
            "cached": batch.cached,
            "failed": len(batch.failures),
            "knits": [
                {
                    "knit": knit.label,
                    "fabric": {
                        key: value
                        for key, value in dataclasses.asdict(spec.scene.fabric).items()
                        if value is not None
                    },
                    "runs": knit.runs,
                    "computed": knit.computed,
                    "cached": knit.cached,
                    "failed": len(knit.failures),
                    "compute_s": knit.compute_s,
                    "fit_s": knit.fit_s,
                    "surface_file": knit.surface_file.name if knit.surface_file else None,
                    "failures": [
                        {"load": dataclasses.asdict(f.case.load), "reason": f.reason}
                        for f in knit.failures
                    ],
                }
                for knit, spec in zip(knits, sweep.knits, strict=True)
            ],
            "run_times_s": [t for t in batch.run_times_s if not math.isnan(t)],
        }
    )


def summary_table(summary: dict) -> str:
    """The table printed at the end of a sweep (also summary.txt)."""
    lines = [
        f"sweep {summary['name']!r} (fidelity {summary['fidelity']}, {summary['executor']}): "
        f"{summary['runs']} RVE runs ({summary['computed']} computed, {summary['cached']} "
        f"cached, {summary['failed']} failed) in {summary['wall_time_s']:.1f} s",
        f"{'knit':<32}{'runs':>6}{'cached':>8}{'failed':>8}{'run s':>9}{'fit s':>7}  surface file",
    ]
    for knit in summary["knits"]:
        lines.append(
            f"{knit['knit']:<32}{knit['runs']:>6}{knit['cached']:>8}{knit['failed']:>8}"
            f"{knit['compute_s']:>9.1f}{knit['fit_s']:>7.1f}  {knit['surface_file'] or '-'}"
        )
    failed = [(knit["knit"], f) for knit in summary["knits"] for f in knit["failures"]]
    if failed:
        lines.append("failed runs (run the sweep again to compute only what is missing):")
        for label, failure in failed:
            load = failure["load"]
            lines.append(
                f"  {label}: {load['kind']} angle {load['angle_deg']:g} deg: {failure['reason']}"
            )
    lines.append("run s: summed compute time of the runs computed now (in the workers)")
    return "\n".join(lines)
