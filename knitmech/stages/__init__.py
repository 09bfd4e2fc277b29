"""The stages of a run as `Stage`s: their inputs (the cache key) and what they compute.

geometry -> meso (the RVE load cases the scene asks for) -> surface (RVE runs along the
sampling plan, fit, surface file) -> macro (patch tension per direction). Each function
returns the stages of one kind for a `RunPlan`; `knitmech.pipeline` runs them through the
stage cache. Files are written relative to the folder `compute` is given: `figures/`,
`paraview/`, `meso/` and `surface.h5` of the results folder (docs/pipeline.md).
"""

import dataclasses
import hashlib
import json
import logging
import shutil
from pathlib import Path
from typing import NamedTuple, TextIO

from fabric_dolfinx.spec.tension import TensionTest
from knitmech.fidelity import Fidelity
from knitmech.jobs.launch import run_job
from knitmech.scene import Scene
from knitmech.stages.cache import Stage
from knitmech.stages.records import GeometrySummary, MesoSummary, PatchJob, SurfaceSummary
from rve_rod.cache import ResultCache
from rve_rod.errors import ConvergenceError
from rve_rod.geometry.loop import loop_geometry
from rve_rod.geometry.pattern_cell import pattern_geometry
from rve_rod.homogenize.acceptance import SOFTENING_TOLERANCE
from rve_rod.homogenize.executors import ExecutorChoice
from rve_rod.homogenize.fit import FitOptions
from rve_rod.homogenize.generate import engine_identity, generate_surface
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.jsonable import to_jsonable
from rve_rod.pattern import JERSEY
from rve_rod.presets import Fabric
from rve_rod.rve import RodRve, RveSettings, load_case, simulate
from rve_rod.rve.engine import fabric_settings
from rve_rod.surface import read_surface, softest_normal_tangents, write_surface
from rve_rod.vtk import write_vtk

__all__ = [
    "DIRECTION_CASES",
    "FIELD_STRAINS",
    "SOFTENING_TOLERANCE",
    "STAGE_VERSION",
    "SURFACE_FIGURE",
    "SURFACE_FILE",
    "RunPlan",
    "SurfaceRuns",
    "file_digest",
    "geometry_stage",
    "given_surface",
    "macro_stages",
    "meso_stages",
    "plan_run",
    "surface_stage",
    "surface_summary",
]

logger = logging.getLogger(__name__)

SURFACE_FILE = "surface.h5"
"""Name of the surface file in the results folder."""
SURFACE_FIGURE = "figures/surfaces.png"
"""The figure of the surface (the paper's Figure 7)."""

FIELD_STRAINS = {"course": 0.10, "wale": 0.10}
"""Strains of the stress maps; the nearest load step is used. The same in both directions, so
that the two maps compare (the paper's Figure 8 shows 10 % course-wise and 9 % wale-wise;
`demos/demo_patch_tension.py` keeps those)."""

STAGE_VERSION = 3
"""Part of every stage's cache key: raised whenever what a stage computes or writes changes
without a new package version (the package version is part of every key already)."""

DIRECTION_CASES = {"course": "uniaxial-course", "wale": "uniaxial-wale"}
"""The meso-scale load case a patch direction is compared with."""


class RunPlan(NamedTuple):
    """Everything a run does, resolved from a scene and a fidelity level.

    Attributes:
        scene: the scene with every setting filled in (the scene as run).
        fidelity: the level that filled it.
        fabric: yarn and knit.
        rve: settings of every RVE run (meso and surface).
        sampling: the surface's load paths.
        fit: the surface fit's options.
    """

    scene: Scene
    fidelity: Fidelity
    fabric: Fabric
    rve: RveSettings
    sampling: SamplingPlan
    fit: FitOptions


def plan_run(scene: Scene, level: Fidelity) -> RunPlan:
    """Resolve `scene` with `level` into the settings of every stage."""
    scene = scene.resolved(level)
    fabric = scene.fabric_model()
    rve = fabric_settings(fabric, scene.meso.control_points, scene.fabric.bending)
    if rve.cell.control_points != scene.meso.control_points:
        logger.info(
            "the RVE runs at %d control points per quarter, not the %d of the scene (fidelity "
            "%s): its cell of several courses needs them (docs/patterns.md, 'Resolution')",
            rve.cell.control_points,
            scene.meso.control_points,
            level.name,
        )
    sampling = SamplingPlan(
        rays=scene.surface.rays,
        max_tension=scene.surface.max_strain,
        max_compression=scene.surface.max_compression,
        steps_per_ray=level.steps_per_ray,
        max_shear=scene.surface.shear_max_strain,
        shear_steps=level.shear_steps,
    )
    fit = FitOptions(spans=level.spans, shear_spans=level.shear_spans)
    return RunPlan(scene, level, fabric, rve, sampling, fit)


def _fabric_inputs(fabric: Fabric) -> dict:
    """The fabric as cache inputs: values only (display names do not change results)."""
    yarn = {k: v for k, v in dataclasses.asdict(fabric.yarn).items() if k != "name"}
    return {"yarn": yarn, "knit": dataclasses.asdict(fabric.knit)}


def geometry_stage(plan: RunPlan) -> Stage:
    """The loop of the fabric: its numbers and a figure (`figures/loop.png`); for a stitch
    pattern other than jersey the template of its cell (`rve_rod.geometry.pattern_cell`), its
    numbers only."""
    knit, radius = plan.fabric.knit, plan.fabric.yarn.minimal_radius
    inputs = {
        "version": STAGE_VERSION,
        "wale_width": knit.wale_width,
        "course_height": knit.course_height,
        "minimal_radius": radius,
        "pattern": knit.pattern,
    }

    def compute(folder: Path) -> dict:
        from rve_rod.geometry.plot import plot_loop  # noqa: PLC0415 (matplotlib on demand)

        if knit.pattern != JERSEY:
            cell = pattern_geometry(knit.pattern, knit.wale_width, knit.course_height, radius)
            return GeometrySummary(cell.to_dict()).to_json()
        geometry = loop_geometry(knit, radius)
        (folder / "figures").mkdir()
        plot_loop(geometry, folder / "figures" / "loop.png")
        values = geometry.to_dict()
        del values["control_points"]
        return GeometrySummary(values).to_json()

    return Stage("geometry", "", inputs, compute)


def meso_stages(plan: RunPlan) -> list[Stage]:
    """One RVE run per load case of the scene: JSON record, curve figure, VTK per state."""
    meso = plan.scene.meso
    return [_meso_stage(plan, name, meso.max_strain, meso.steps) for name in meso.cases]


def _meso_stage(plan: RunPlan, name: str, max_strain: float, steps: int) -> Stage:
    case = load_case(name, max_strain, steps)
    inputs = {
        "version": STAGE_VERSION,
        "fabric": _fabric_inputs(plan.fabric),
        "case": case,
        "settings": plan.rve,
    }

    def compute(folder: Path) -> dict:
        from rve_rod.rve.plot import plot_curve  # noqa: PLC0415 (matplotlib on demand)

        def progress(step):  # a detail (-v): the stage's own line says when it is done
            logger.debug(
                "meso %s: strain %.4g %%, %.4g gf/cm (%d Newton iterations)",
                name,
                100 * step.strain,
                step.force_gf_per_cm,
                step.newton_iterations,
            )

        try:
            result = simulate(plan.fabric, case, plan.rve, on_step=progress)
        except ConvergenceError as error:
            logger.warning("meso %s: %s; keeping the converged states", name, error)
            result = error.history
        for part in ("meso", "figures", "paraview"):
            (folder / part).mkdir(exist_ok=True)
        record = result.to_dict()
        (folder / "meso" / f"{name}.json").write_text(json.dumps(to_jsonable(record), indent=1))
        plot_curve(result, folder / "figures" / f"rve_{name}.png")
        write_vtk(result, folder / "paraview" / f"rve_{name}")
        fields = [field.name for field in dataclasses.fields(MesoSummary)]
        return MesoSummary(**{key: record[key] for key in fields}).to_json()

    return Stage("meso", name, inputs, compute)


class SurfaceRuns(NamedTuple):
    """How the surface stage runs its RVE runs.

    Attributes:
        cache: where every single run is cached (an interrupted stage resumes from it).
        executor: where the runs are computed (local processes or MPI ranks).
        progress: stream for the progress bar (None: none).
    """

    cache: ResultCache
    executor: ExecutorChoice
    progress: TextIO | None


def surface_stage(plan: RunPlan, runs: SurfaceRuns) -> Stage:
    """The response surface: RVE runs along the sampling plan, the fit, the file and figure."""

    engine = RodRve(plan.rve)
    inputs = {
        "version": STAGE_VERSION,
        "fabric": _fabric_inputs(plan.fabric),
        "sampling": plan.sampling,
        "fit": plan.fit,
        "kind": plan.scene.surface.kind,
        **engine_identity(engine),
    }

    def compute(folder: Path) -> dict:

        generated = generate_surface(
            plan.fabric,
            engine,
            plan.sampling,
            plan.fit,
            kind=plan.scene.surface.kind,
            cache=runs.cache,
            executor=runs.executor.kind,
            jobs=runs.executor.jobs,
            progress=runs.progress,
        )
        write_surface(folder / SURFACE_FILE, generated.surface)
        _plot_surface(generated.surface, folder)
        outcome = generated.runs
        return dataclasses.replace(
            surface_summary(generated.surface),
            fits={kind: _report_dict(report) for kind, report in generated.reports.items()},
            runs=len(outcome.runs),
            runs_computed=outcome.computed,
            runs_cached=outcome.cached,
            incomplete_runs=generated.surface.parameters["incomplete_runs"],
            max_stress_asymmetry=generated.samples.max_asymmetry,
        ).to_json()

    return Stage("surface", "", inputs, compute)


def given_surface(path: Path) -> Stage:
    """The surface file a scene gives, copied into the results folder with its figure and
    summary: keyed by the file's path and content, so that runs on one file plot it once (a
    design runs its scene at every evaluation; the plot takes about 0.5 s)."""
    path = Path(path)
    inputs = {"version": STAGE_VERSION, "path": str(path), "digest": file_digest(path)}

    def compute(folder: Path) -> dict:
        shutil.copyfile(path, folder / SURFACE_FILE)
        surface = read_surface(folder / SURFACE_FILE)
        _plot_surface(surface, folder)
        return dataclasses.replace(surface_summary(surface), source=str(path)).to_json()

    return Stage("surface", "", inputs, compute)


def surface_summary(surface) -> SurfaceSummary:
    """Kind, domain, residuals and softest normal stiffness of a surface (warned if < 0
    beyond round-off)."""
    softest = softest_normal_tangents(surface)
    for name, entry in softest.items():
        if entry["value"] < -SOFTENING_TOLERANCE * entry["largest"]:
            logger.warning(
                "the surface loses stiffness: %s = %.3g N/mm at E = (%.3g, %.3g); a patch "
                "that reaches such strains may find a spurious equilibrium",
                name,
                entry["value"],
                *entry["strain"],
            )
    return SurfaceSummary(
        kind=surface.kind,
        domain=surface.domain,
        residuals={k: v._asdict() for k, v in surface.residual_stats().items()},
        softest_tangents=softest,
    )


def _report_dict(report) -> dict:
    return {
        "residuals": {k: v._asdict() for k, v in report.residuals.items()},
        "tangent_asymmetry": report.tangent_asymmetry,
    }


def _plot_surface(surface, folder: Path) -> None:
    from rve_rod.homogenize.plot import plot_surface  # noqa: PLC0415 (matplotlib on demand)

    (folder / "figures").mkdir(exist_ok=True)
    plot_surface(surface, folder / SURFACE_FIGURE)


def file_digest(path: Path) -> str:
    """SHA-256 hex digest of a file's bytes (the surface's identity in the macro keys)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def macro_stages(plan: RunPlan, surface_path: Path) -> list[Stage]:
    """One patch tension test per direction of the scene on the surface at `surface_path`."""
    macro = plan.scene.macro
    digest = file_digest(surface_path)
    stages = []
    for direction in macro.directions:
        step = macro.max_strain / macro.steps
        nearest = min(max(round(FIELD_STRAINS[direction] / step), 1), macro.steps)
        test = TensionTest(
            direction=direction,
            size=macro.size,
            elements=macro.elements,
            max_strain=macro.max_strain,
            angle=macro.angle,
            element_degree=plan.fidelity.element_degree,
        )
        job = PatchJob(test=test, steps=macro.steps, field_step=nearest)
        inputs = {"version": STAGE_VERSION, "surface_sha256": digest, "patch": job}
        stages.append(
            Stage("macro", direction, inputs, _macro_compute(job, surface_path, macro.ranks))
        )
    return stages


def _macro_compute(job: PatchJob, surface_path: Path, ranks: int):
    def compute(folder: Path) -> dict:
        request = {"job": job.to_json(), "surface": str(surface_path)}
        return run_job("patch", request, folder, ranks, label=f"macro {job.test.direction}")

    return compute
