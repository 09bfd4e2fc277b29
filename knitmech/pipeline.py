"""The main job: run a scene from the yarn to the fabric patch into a results folder.

    geometry -> meso (RVE load cases) -> surface (RVE runs, fit, file) -> macro (patch tension)

Every stage goes through the content-addressed stage cache (`knitmech.stages.cache`): a stage
whose inputs did not change is taken from the cache, and a run that was interrupted resumes
after the last stage (and, within the surface stage, the last RVE run) that finished. Only
what the scene asks for is run: its meso load cases, its patch directions, and no surface
runs when the scene gives a surface file. The scene is checked before anything is computed;
the geometry stage, the cheapest, also checks that a loop fits the knit.

The results folder holds `summary.json`, `summary.txt` (the printed table), `scene.toml`
(the scene as run, every setting filled in; a part's gmsh file copied to `mesh/` and named
there, so that `knitmech run results/scene.toml` runs it again on its own), `surface.h5`,
`figures/*.png`, `paraview/*` and `meso/*.json` (docs/pipeline.md).
"""

import dataclasses
import datetime
import json
import logging
import shutil
import time
from pathlib import Path
from typing import NamedTuple, TextIO

from fabric_dolfinx.spec.mesh_checks import check_cells
from fabric_dolfinx.spec.part import shape_cells
from knitmech.fidelity import fidelity_level
from knitmech.report import (
    compare_forces,
    plot_comparison,
    poisson_ratios,
    stage_timings,
    summary_table,
)
from knitmech.scene import Scene, SceneError
from knitmech.scene.fabric import part_problems
from knitmech.stages import (
    SURFACE_FILE,
    RunPlan,
    SurfaceRuns,
    geometry_stage,
    given_surface,
    macro_stages,
    meso_stages,
    plan_run,
    surface_stage,
)
from knitmech.stages.cache import (
    GIVEN,
    Stage,
    StageCache,
    StageRecord,
    remove_stale_work,
    results_folder_lock,
)
from knitmech.stages.fabric import (
    fabric_job,
    fabric_stage,
    fabric_table,
    in_subfolder,
    knit_surfaces,
)
from knitmech.stages.records import GeometrySummary, MesoSummary, PatchSummary, SurfaceSummary
from rve_rod import __version__
from rve_rod.cache import ResultCache, default_cache_root
from rve_rod.errors import InputError, check_integer
from rve_rod.homogenize.executors import ExecutorChoice
from rve_rod.jsonable import to_jsonable
from rve_rod.limits import PART_CELLS, available_cores
from rve_rod.outputs import check_output_folder
from rve_rod.rve.yarn import bending_model
from rve_rod.surface import read_surface

__all__ = [
    "MESH_FOLDER",
    "SUMMARY_FILE",
    "PipelineResult",
    "check_plan",
    "run_scene",
]

logger = logging.getLogger(__name__)

SUMMARY_FILE = "summary.json"
MESH_FOLDER = "mesh"
"""Where the results folder keeps a copy of the part's gmsh file."""


class PipelineResult(NamedTuple):
    """A finished run.

    Attributes:
        plan: the resolved settings.
        folder: the results folder.
        summary: the content of summary.json.
        records: what happened to each stage (computed, cached or given) and its time.
        table: the printed summary (also in summary.txt).
    """

    plan: RunPlan
    folder: Path
    summary: dict
    records: tuple[StageRecord, ...]
    table: str


def check_plan(
    plan: RunPlan, executor: ExecutorChoice | None = None, *, oversubscribe: bool = False
) -> None:
    """Problems a scene file alone does not show: an unreadable surface file, no mpirun, more
    MPI ranks than cores (unless `oversubscribe`), an mpi executor that was not launched as
    one (InputError) or that would nest mpirun, a built-in shape whose mesh at the level's
    element size exceeds the cell budget (`fabric_dolfinx.spec.mesh_checks.check_cells`),
    and what only the part's mesh shows (`knitmech.scene.fabric.part_problems`).

    Raises SceneError listing every problem (one per key)."""
    if executor is not None and plan.scene.surface.path is None:
        executor.workers()
    problems = []
    if plan.scene.surface.path is not None:
        try:
            read_surface(plan.scene.surface.path)
        except InputError as error:
            problems.append(f"surface.path: {error}")
    if plan.scene.macro.ranks > 1 and shutil.which("mpirun") is None:
        problems.append(f"macro.ranks: {plan.scene.macro.ranks} needs mpirun, not on PATH")
    cores = available_cores()
    if plan.scene.macro.ranks > cores and not oversubscribe:
        problems.append(
            f"macro.ranks: {plan.scene.macro.ranks} is outside the valid range [1, {cores}] "
            "(the cores of this machine; --oversubscribe allows more)"
        )
    if plan.scene.macro.ranks > 1 and executor is not None and executor.kind == "mpi":
        problems.append(
            f"macro.ranks: {plan.scene.macro.ranks} would start mpirun inside the MPI job of "
            "--executor mpi; set macro.ranks = 1 (the patch then runs on rank 0)"
        )
    part = plan.scene.part
    if part is not None and part.mesh.shape is not None:
        mesh = part.mesh
        cells = shape_cells(mesh)
        try:
            check_cells(f"{mesh.shape} of element_size {mesh.element_size:.4g} mm", cells, 0)
            check_cells(f"{mesh.shape} of {cells:.4g} cells", cells, mesh.refinements)
        except InputError as error:
            key = "refinements" if cells <= PART_CELLS else "element_size"
            problems.append(f"fabric.shape.{key}: {error}")
    if part is not None and not problems:
        problems += part_problems(part)
    if problems:
        raise SceneError(repr(plan.scene.name), problems)


def run_scene(  # noqa: PLR0913 (the scene and the keyword options of `knitmech run`)
    scene: Scene,
    *,
    fidelity: str | None = None,
    output: Path | str = "results",
    cache_dir: Path | str | None = None,
    jobs: int = 1,
    executor: str = "local",
    progress: TextIO | None = None,
    oversubscribe: bool = False,
) -> PipelineResult:
    """Run every stage of `scene` and write the results folder.

    Args:
        scene: the study (`knitmech.scene.load_scene`).
        fidelity: a level name overriding the scene's.
        output: the results folder (created; files of an earlier run there are replaced;
            held for the run: a second run into it is refused, `results_folder_lock`).
        cache_dir: root of the stage cache (`stages/`) and the RVE-run cache (`rve-runs/`,
            shared with `rve-rod surface`); default `rve_rod.cache.default_cache_root()`.
        jobs: local worker processes for the surface's RVE runs.
        executor: where the surface's RVE runs are computed, "local" or "mpi"
            (`rve_rod.homogenize.executors`; the results do not depend on it).
        progress: stream for the progress bar of the RVE runs (None: none).
        oversubscribe: allow more MPI ranks (macro.ranks) than cores.

    Raises:
        SceneError: the scene cannot run (before anything is computed).
        InputError: `output` or `cache_dir` cannot be written (`rve_rod.outputs`).
    """
    started = time.perf_counter()
    check_integer("jobs", jobs, 1, 256)
    choice = ExecutorChoice(executor, jobs)
    folder = check_output_folder("output", output)
    if cache_dir is not None:
        cache_dir = check_output_folder("cache_dir", cache_dir)
    plan = plan_run(scene, fidelity_level(fidelity or scene.fidelity))
    check_plan(plan, choice, oversubscribe=oversubscribe)
    cache_dir = cache_dir if cache_dir is not None else default_cache_root()
    created = not folder.exists()
    with results_folder_lock(folder, "output"):
        _clear_previous(folder)
        remove_stale_work(folder)
        stages = StageCache(cache_dir / "stages")
        records: list[StageRecord] = []

        def run(stage: Stage) -> dict:
            outcome = stages.run(stage, folder)
            records.append(outcome.record)
            return outcome.summary

        try:
            geometry = GeometrySummary.from_json(run(geometry_stage(plan)))
        except InputError as error:
            if created:
                shutil.rmtree(folder, ignore_errors=True)
            keys = ", ".join(f"fabric.{k}" for k in ("wale_width", "course_height", "yarn_radius"))
            raise SceneError(repr(plan.scene.name), [f"{keys}: {error}"]) from None
        bending_model(plan.fabric, plan.scene.fabric.bending, report=True)  # warns of a fallback
        meso = {stage.item: MesoSummary.from_json(run(stage)) for stage in meso_stages(plan)}
        part = plan.scene.part
        knits = knit_surfaces(plan) if part is not None else None
        surface = None
        if knits is None or knits.scene_knit:
            if plan.scene.surface.path is None:
                runs = SurfaceRuns(ResultCache(cache_dir / "rve-runs"), choice, progress)
                surface = SurfaceSummary.from_json(run(surface_stage(plan, runs)))
            else:
                outcome = stages.run(given_surface(plan.scene.surface.path), folder)
                records.append(dataclasses.replace(outcome.record, status=GIVEN))
                surface = SurfaceSummary.from_json(outcome.summary)
        macro, fabric, knit_summaries = {}, None, {}
        if part is None:
            macro = {
                stage.item: PatchSummary.from_json(run(stage))
                for stage in macro_stages(plan, folder / SURFACE_FILE)
            }
        else:
            runs = SurfaceRuns(ResultCache(cache_dir / "rve-runs"), choice, progress)
            for label, knit in knits.others.items():
                stage = in_subfolder(surface_stage(plan._replace(fabric=knit), runs), label)
                knit_summaries[label] = run(stage)
            job = fabric_job(plan, knits, folder)
            fabric = run(fabric_stage(job, plan.scene.macro.ranks))

        report_started = time.perf_counter()
        records = tuple(records)
        summary = {
            "scene": plan.scene.to_dict(),
            "fidelity": dataclasses.asdict(plan.fidelity),
            "package_version": __version__,
            "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
            "fabric": dataclasses.asdict(plan.fabric),
            "geometry": geometry.to_json(),
            "meso": {name: record.to_json() for name, record in meso.items()},
            "surface": surface.to_json() if surface is not None else {},
            "macro": {name: record.to_json() for name, record in macro.items()},
            "forces": compare_forces(meso, macro),
            "poisson_ratios": poisson_ratios(meso, macro),
            "stages": [dataclasses.asdict(record) for record in records],
        }
        if part is not None:
            summary["knits"] = knit_summaries
            summary["part"] = fabric
        written = [SUMMARY_FILE, "summary.txt", "scene.toml"]
        as_run = plan.scene
        if part is not None and part.mesh.file is not None:
            copy = _copy_mesh(Path(part.mesh.file), folder)
            written.append(copy)
            as_run = dataclasses.replace(
                as_run,
                part=dataclasses.replace(part, mesh=dataclasses.replace(part.mesh, file=copy)),
            )
        header = f"# the scene as run (fidelity {plan.fidelity.name} filled in), knitmech "
        (folder / "scene.toml").write_text(f"{header}{__version__}\n" + as_run.to_toml())
        figure = folder / "figures" / "force_strain.png"
        if macro or meso:
            figure.parent.mkdir(exist_ok=True)
            title = f"{plan.scene.name} (fidelity {plan.fidelity.name})"
            plot_comparison(meso, macro, figure, title)
        if figure.is_file():
            written.append("figures/force_strain.png")
        timings = stage_timings(records)
        timings["report"] = time.perf_counter() - report_started
        timings["total"] = time.perf_counter() - started
        summary["timings_s"] = timings
        summary["files"] = sorted({name for r in records for name in r.files} | set(written))
        summary = to_jsonable(summary)
        table = summary_table(summary)
        if fabric is not None:
            table += "\n" + fabric_table(fabric)
        (folder / "summary.txt").write_text(table + "\n")
        (folder / SUMMARY_FILE).write_text(json.dumps(summary, indent=1, allow_nan=False))
        return PipelineResult(plan, folder, summary, records, table)


def _copy_mesh(path: Path, folder: Path) -> str:
    """Copy the part's gmsh file into `folder`/mesh/ (the scene.toml there names the copy, so
    that the results folder can be run again on its own); returns its relative path."""
    target = folder / MESH_FOLDER / path.name
    target.parent.mkdir(exist_ok=True)
    if path.resolve() != target.resolve():
        shutil.copyfile(path, target)
    return f"{MESH_FOLDER}/{path.name}"


def _clear_previous(folder: Path) -> None:
    """Delete the files an earlier run listed in the folder's summary.json (and that file)."""
    summary = folder / SUMMARY_FILE
    if not summary.is_file():
        return
    try:
        files = json.loads(summary.read_text()).get("files", [])
    except (OSError, ValueError, AttributeError):
        return
    for name in files:
        path = folder / name
        if path.resolve().is_relative_to(folder.resolve()) and path.is_file():
            path.unlink()
    summary.unlink(missing_ok=True)
