"""The design job: from a design file to the knit that meets its targets, in a results folder.

    knitmech design SCENE.toml [-o design/] [--fidelity fast|balanced|accurate] [--jobs N]

`run_design` resolves the family (the preset's surfaces at the scene's fidelity, through the
stage cache, or the given member files), searches the design (`knitmech.design.solve`) with
the model of its kind, and writes

- `design.json`: the variables (value, bounds), every target against what is achieved (its
  miss and whether it is met), the knitting instructions, evaluations and times;
- `design.txt`: the same as the printed table;
- `figures/design.png`: target against achieved;
- material: the family's surfaces (`surface.h5`, `knits/*/surface.h5`);
- sleeve: the same, and with `[sleeve] contact` the contact model's results
  (`sleeve/curves.json`, `paraview/sleeve.xdmf`);
- part: the designed scene's results folder (`knitmech run`'s: `summary.json`, `fabric/`,
  `paraview/`, ...) and `designed_scene.toml`, the scene with the designed stitch values.

Every evaluation of a part is a fabric stage, cached like every stage: a rerun, or a changed
target whose search passes the same designs, takes them from the cache. The material's and
the Laplace model's evaluations cost microseconds to milliseconds on the cached surfaces and
are not stored.
"""

import copy
import dataclasses
import datetime
import json
import logging
import shutil
import time
from pathlib import Path
from typing import NamedTuple, TextIO

import numpy as np

from fabric_dolfinx.spec.expression import piecewise_linear
from knitmech.design.family import FamilyMember, SurfaceFamily
from knitmech.design.material import fit_stitch
from knitmech.design.plot import plot_material, plot_part, plot_sleeve
from knitmech.design.sleeve import PressureTarget, design_sleeve, stretched_band
from knitmech.design.solve import Variable, solve_least_squares
from knitmech.design.spec import PRESSURE_UNITS, PROBE_QUANTITIES, DesignSpec, VariableSpec
from knitmech.fidelity import fidelity_level
from knitmech.jobs.launch import run_job
from knitmech.jobs.sleeve_spec import SleeveJob
from knitmech.pipeline import check_plan, run_scene
from knitmech.scene import Scene, scene_from_dict
from knitmech.stages import STAGE_VERSION, RunPlan, SurfaceRuns, file_digest, plan_run
from knitmech.stages.cache import Stage, StageCache, remove_stale_work, results_folder_lock
from knitmech.stages.family import family_members, family_stitches
from rve_rod import __version__
from rve_rod.cache import ResultCache, default_cache_root
from rve_rod.errors import check_integer
from rve_rod.homogenize.executors import ExecutorChoice
from rve_rod.jsonable import to_jsonable
from rve_rod.outputs import check_output_folder
from rve_rod.units import KPA, MMHG

__all__ = [
    "DESIGN_FILE",
    "DesignResult",
    "run_design",
]

logger = logging.getLogger(__name__)

DESIGN_FILE = "design.json"
FIGURE = "figures/design.png"
EVALUATIONS = ".design-evaluations"
"""Folder of a part design's evaluations inside the results folder (removed at the end)."""
CONTACT_ELEMENT_SIZE = {"fast": 5.0, "balanced": 2.5, "accurate": 1.25}
"""The contact model's quadrilateral edge (mm) per fidelity level (docs/design.md: the
pressure's error against the closed form on a cylinder, +3.2, +0.7, +0.1 %)."""


class DesignResult(NamedTuple):
    """A finished design.

    Attributes:
        folder: the results folder.
        summary: the content of design.json.
        table: the printed report (also design.txt).
        met: whether every target is met.
    """

    folder: Path
    summary: dict
    table: str
    met: bool


class _Outcome(NamedTuple):
    """What a kind of design returns to the report."""

    variables: list[dict]
    targets: list[dict]
    instructions: list[dict]
    evaluations: int
    search_time_s: float
    message: str
    extra: dict


def run_design(  # noqa: PLR0913 (the design and the keyword options of `knitmech design`)
    scene: Scene,
    design: DesignSpec,
    *,
    fidelity: str | None = None,
    output: Path | str = "design",
    cache_dir: Path | str | None = None,
    jobs: int = 1,
    executor: str = "local",
    progress: TextIO | None = None,
) -> DesignResult:
    """Design the knit of `design` (module docstring); the options as `run_scene`'s."""
    started = time.perf_counter()
    check_integer("jobs", jobs, 1, 256)
    choice = ExecutorChoice(executor, jobs)
    folder = check_output_folder("output", output)
    if cache_dir is not None:
        cache_dir = check_output_folder("cache_dir", cache_dir)
    cache_dir = Path(cache_dir) if cache_dir is not None else default_cache_root()
    level = fidelity or scene.fidelity
    plan = plan_run(scene, fidelity_level(level))
    check_plan(plan, choice if design.kind != "part" else None)
    with results_folder_lock(folder, "output"):  # a second run into it is refused
        remove_stale_work(folder)
        options = {"cache_dir": cache_dir, "jobs": jobs, "executor": executor, "progress": progress}
        if design.kind == "part":
            outcome = _design_part(scene, design, level, folder, options)
        else:
            stages = StageCache(cache_dir / "stages")
            runs = SurfaceRuns(ResultCache(cache_dir / "rve-runs"), choice, progress)
            family = _family(plan, design, lambda s: stages.run(s, folder).summary, runs, folder)
            if design.kind == "material":
                outcome = _design_material(family, design, folder)
            else:
                outcome = _design_sleeve(family, design, folder)
                if design.sleeve.contact:
                    size = design.sleeve.element_size or CONTACT_ELEMENT_SIZE[plan.fidelity.name]
                    job = contact_job(family, design, outcome.instructions, size)
                    stage = contact_stage(job, plan.scene.macro.ranks)
                    contact = stages.run(stage, folder).summary
                    outcome = _with_contact(outcome, family, design, contact)
                (folder / "figures").mkdir(exist_ok=True)
                z = np.linspace(*design.sleeve.limb.extent, 201)
                wanted = design.targets[0].pressure_at(z) / PRESSURE_UNITS[design.targets[0].unit]
                plot_sleeve(design.sleeve, (z, wanted), outcome.targets, folder / FIGURE)
        met = all(target["met"] for target in outcome.targets)
        summary = to_jsonable(
            {
                "kind": design.kind,
                "scene": scene.name,
                "fidelity": plan.fidelity.name,
                "package_version": __version__,
                "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
                "met": met,
                "variables": outcome.variables,
                "targets": outcome.targets,
                "instructions": outcome.instructions,
                "evaluations": outcome.evaluations,
                "search_time_s": outcome.search_time_s,
                "wall_time_s": time.perf_counter() - started,
                "message": outcome.message,
                **outcome.extra,
            }
        )
        table = design_table(summary)
        (folder / DESIGN_FILE).write_text(json.dumps(summary, indent=1, allow_nan=False))
        (folder / "design.txt").write_text(table + "\n")
    return DesignResult(folder, summary, table, met)


def _family(plan: RunPlan, design: DesignSpec, run, runs: SurfaceRuns, folder: Path):
    """The family of a material or sleeve design: the given members, or the preset's
    members over the design's bounds (their surfaces through the stage cache)."""
    if design.members:
        members = tuple(
            FamilyMember(m.stitch, m.surface, m.wale_width, m.course_height) for m in design.members
        )
    else:
        stitches = family_stitches(plan, design.bounds)
        members = family_members(plan, stitches, run, runs, folder)
    return SurfaceFamily(members)


def _family_record(family: SurfaceFamily) -> dict:
    return {"family": [dataclasses.asdict(member) for member in family.members]}


def _design_material(family: SurfaceFamily, design: DesignSpec, folder: Path) -> _Outcome:
    curves = [target.curve for target in design.targets]
    fit = fit_stitch(family, curves, design.settings, design.bounds)
    targets = []
    for index, (curve, predicted, miss) in enumerate(
        zip(curves, fit.predicted, fit.misses, strict=True)
    ):
        targets.append(
            {
                "name": f"target[{index}] uniaxial {curve.direction}",
                "kind": "uniaxial",
                "direction": curve.direction,
                "source": curve.source,
                "strain": curve.strain,
                "target": curve.force,
                "achieved": predicted,
                "unit": "N/mm",
                "miss": miss,
                "tolerance": curve.tolerance,
                "met": miss <= curve.tolerance,
            }
        )
    (folder / "figures").mkdir(exist_ok=True)
    plot_material(family, curves, fit.stitch, folder / FIGURE)
    low, high = design.bounds
    variables = [{"name": "stitch", "value": fit.stitch, "unit": "mm", "lower": low, "upper": high}]
    instructions = [
        {
            "stitch": fit.stitch,
            "wale_width": family.wale_width(fit.stitch),
            "course_height": family.course_height(fit.stitch),
        }
    ]
    solution = fit.solution
    return _Outcome(
        variables,
        targets,
        instructions,
        solution.evaluations,
        solution.wall_time_s,
        solution.message,
        _family_record(family),
    )


def _design_sleeve(family: SurfaceFamily, design: DesignSpec, folder: Path) -> _Outcome:
    sleeve = design.sleeve
    (spec,) = design.targets
    wanted = spec.pressure_at(sleeve.centres)
    target = PressureTarget(wanted, spec.weight, spec.tolerance)
    result = design_sleeve(family, sleeve, target, design.bounds, design.settings)
    unit = PRESSURE_UNITS[spec.unit]
    edges = sleeve.edges
    instructions, targets, variables = [], [], []
    for k, state in enumerate(result.states):
        name = f"band {k + 1}"
        instructions.append(
            {
                "band": k + 1,
                "z_from": edges[k],
                "z_to": edges[k + 1],
                "limb_radius": float(sleeve.limb.radius(sleeve.centres[k])),
                "stitch": result.stitches[k],
                "needles": result.needles[k],
                "courses": result.courses[k],
                "knitted_circumference": result.needles[k] * family.wale_width(result.stitches[k]),
                "knitted_length": result.courses[k] * family.course_height(result.stitches[k]),
                "hoop_strain": state.hoop_stretch - 1.0,
                "axial_stretch": state.axial_stretch,
                "tension": state.tension,
                "pressure_mmHg": state.pressure / MMHG,
                "pressure_kPa": state.pressure / KPA,
                "outside_data": state.outside,
            }
        )
        targets.append(
            {
                "name": f"{name} pressure",
                "kind": "pressure",
                "z": sleeve.centres[k],
                "target": wanted[k] / unit,
                "achieved": state.pressure / unit,
                "unit": spec.unit,
                "miss": abs(result.misses[k]),
                "tolerance": spec.tolerance,
                "met": abs(result.misses[k]) <= spec.tolerance,
            }
        )
        variables.append(
            {
                "name": f"{name} stitch",
                "value": result.stitches[k],
                "unit": "mm",
                "lower": design.bounds[0],
                "upper": design.bounds[1],
            }
        )
        variables.append({"name": f"{name} needles", "value": int(result.needles[k]), "unit": ""})
    outside = [row["band"] for row in instructions if row["outside_data"]]
    if outside:
        logger.warning(
            "bands %s are strained beyond the family's data (their pressure is extrapolated)",
            ", ".join(map(str, outside)),
        )
    extra = {
        **_family_record(family),
        "sleeve": {
            "bands": sleeve.bands,
            "needles_designed": sleeve.needles is None,
            "hoop_strain": sleeve.hoop_strain,
            "axial_stretch": sleeve.axial_stretch,
            "limb": {"z": sleeve.limb.z, "r": sleeve.limb.r},
            "continuous": {"stitches": result.continuous[0], "needles": result.continuous[1]},
        },
    }
    return _Outcome(
        variables,
        targets,
        instructions,
        result.evaluations,
        result.search_time_s,
        result.message,
        extra,
    )


def contact_job(
    family: SurfaceFamily, design: DesignSpec, bands: list[dict], element_size: float
) -> SleeveJob:
    """The contact model of the designed sleeve (`bands`: its instructions), with the
    members its stitch values need (the fewer surfaces to read and evaluate)."""
    stitches = [row["stitch"] for row in bands]
    values = family.stitch_values
    first = max(i for i, v in enumerate(values) if v <= min(stitches) + 1e-9)
    last = min(i for i, v in enumerate(values) if v >= max(stitches) - 1e-9)
    limb = design.sleeve.limb
    return SleeveJob(
        members=family.members[first : last + 1],
        limb=tuple(zip(limb.z, limb.r, strict=True)),
        stitches=tuple(stitches),
        needles=tuple(float(row["needles"]) for row in bands),
        courses=tuple(float(row["courses"]) for row in bands),
        element_size=element_size,
    )


def contact_stage(job: SleeveJob, ranks: int) -> Stage:
    """The stage of the sleeve's contact model; its key holds the surfaces by content."""
    data = job.to_json()
    for member in data["members"]:
        member["path"] = file_digest(Path(member["path"]))
    inputs = {"version": STAGE_VERSION, "job": data}

    def compute(folder: Path) -> dict:
        return run_job("sleeve", job.to_json(), folder, ranks, label="sleeve contact model")

    return Stage("sleeve", "contact", inputs, compute)


def _with_contact(
    outcome: _Outcome, family: SurfaceFamily, design: DesignSpec, contact: dict
) -> _Outcome:
    """The sleeve design's outcome with the contact model beside the Laplace model: per band
    its pressure, hoop tension, stretches, and the Laplace model at its stretches."""
    unit = PRESSURE_UNITS[design.targets[0].unit]
    rows = []
    for target, band, ring in zip(
        outcome.targets, outcome.instructions, contact["bands"], strict=True
    ):
        at_stretches = stretched_band(
            family,
            ring["stitch"],
            (ring["hoop_stretch"], ring["axial_stretch"]),
            ring["limb_radius"],
        )
        target["contact"] = ring["pressure"] / unit
        rows.append(
            {
                "band": band["band"],
                "z": ring["z"],
                "laplace": band["pressure_mmHg"] * MMHG,
                "contact": ring["pressure"],
                "difference": ring["pressure"] / (band["pressure_mmHg"] * MMHG) - 1.0,
                "laplace_tension": band["tension"],
                "contact_tension": ring["hoop_tension"],
                "axial_tension": ring["axial_tension"],
                "hoop_stretch": ring["hoop_stretch"],
                "axial_stretch": ring["axial_stretch"],
                "designed_hoop_stretch": 1.0 + band["hoop_strain"],
                "designed_axial_stretch": band["axial_stretch"],
                "laplace_at_contact_stretches": at_stretches.pressure,
                "membrane_pressure": ring["membrane_pressure"],
                "curvature_term": ring["membrane_pressure"] - ring["laplace_term"],
            }
        )
    summary = {key: contact[key] for key in contact if key != "bands"}
    extra = {**outcome.extra, "contact": {**summary, "bands": rows}}
    return outcome._replace(extra=extra)


def stitch_expression(variable: VariableSpec, values: np.ndarray) -> str:
    """The stitch value of a region as an expression of x, y (mm): a constant, or the field
    linear between the stations along the axis and constant beyond."""
    if variable.axis is None:
        return repr(float(values[0]))
    return piecewise_linear(variable.axis, variable.stations, values)


def _variables(design: DesignSpec, family_range: tuple[float, float]) -> list[Variable]:
    variables = []
    for spec in design.variables:
        low, high = spec.bounds or family_range
        initial = spec.initial if spec.initial is not None else 0.5 * (low + high)
        if spec.axis is None:
            variables.append(Variable(f"{spec.region} stitch", low, high, initial))
        else:
            variables += [
                Variable(f"{spec.region} stitch at {spec.axis} = {station:g}", low, high, initial)
                for station in spec.stations
            ]
    return variables


def designed_scene(design: DesignSpec, scene: Scene, x: np.ndarray) -> Scene:
    """The scene with the designed regions' stitch values at `x`, without meso runs (only
    its part is needed). Each designed region is graded over the members its values need
    (`knitmech.scene.fabric`): the fewer surfaces to read and evaluate (the forms are the
    same for every combination of members: the law is evaluated at the quadrature points)."""
    data = copy.deepcopy(design.scene_data)
    if "region" not in data:
        data["region"] = [{"name": region.name} for region in scene.part.regions]
    regions = {table["name"]: table for table in data["region"]}
    position = 0
    for spec in design.variables:
        count = 1 if spec.axis is None else len(spec.stations)
        regions[spec.region]["stitch"] = stitch_expression(spec, x[position : position + count])
        position += count
    data.setdefault("meso", {})["cases"] = []
    base = Path(design.base) if design.base is not None else None
    return scene_from_dict(data, source=f"{scene.name!r} (designed)", base=base)


def target_value(target, part: dict) -> float:
    """The value a force or probe target reads from a part's summary at its step."""
    if target.kind == "force":
        force = part["boundaries"][target.boundary]["force"][target.step]
        return float(force["xy".index(target.component)])
    field, index = PROBE_QUANTITIES[target.quantity]
    value = part["probes"][target.probe][field][target.step]
    for i in index:
        value = value[i]
    return float(value)


def _design_part(
    scene: Scene, design: DesignSpec, fidelity: str, folder: Path, options
) -> _Outcome:
    preset = scene.fabric.preset
    plan = plan_run(scene, fidelity_level(fidelity))
    family_range = tuple(family_stitches(plan)[i] for i in (0, -1))
    variables = _variables(design, family_range)
    work = folder / EVALUATIONS
    count = [0]

    def evaluate(x: np.ndarray) -> np.ndarray:
        count[0] += 1
        output = work / str(count[0])
        work.mkdir(exist_ok=True)
        run = run_scene(
            designed_scene(design, scene, x),
            fidelity=fidelity,
            output=output,
            **options,
        )
        shutil.rmtree(output, ignore_errors=True)
        part = run.summary["part"]
        if not part["complete"]:
            logger.warning("design: evaluation %d stopped early: %s", count[0], part["message"])
        values = np.array([target_value(t, part) for t in design.targets])
        wanted = np.array([t.value for t in design.targets])
        weights = np.array([t.weight for t in design.targets])
        evaluate.values[x.tobytes()] = values
        return weights * (values - wanted) / np.abs(wanted)

    evaluate.values = {}
    solution = solve_least_squares(evaluate, variables, design.settings)
    shutil.rmtree(work, ignore_errors=True)
    best = designed_scene(design, scene, solution.x)
    run_scene(best, fidelity=fidelity, output=folder, **options)
    (folder / "designed_scene.toml").write_text(
        f"# {scene.name}: the designed stitch values (knitmech design, {preset})\n" + best.to_toml()
    )
    achieved = evaluate.values[solution.x.tobytes()]
    targets = []
    for index, (target, value) in enumerate(zip(design.targets, achieved, strict=True)):
        where = target.boundary if target.kind == "force" else target.probe
        what = target.component if target.kind == "force" else target.quantity
        miss = abs(value - target.value) / abs(target.value)
        targets.append(
            {
                "name": f"target[{index}] {target.kind} {where} {what}",
                "kind": target.kind,
                "step": target.step,
                "target": target.value,
                "achieved": value,
                "unit": "N" if target.kind == "force" else "",
                "miss": miss,
                "tolerance": target.tolerance,
                "met": miss <= target.tolerance,
            }
        )
    (folder / "figures").mkdir(exist_ok=True)
    plot_part(targets, folder / FIGURE)
    rows = [
        {"name": v.name, "value": float(x), "unit": v.unit, "lower": v.lower, "upper": v.upper}
        for v, x in zip(variables, solution.x, strict=True)
    ]
    instructions = [
        {"region": region.name, "stitch": region.graded_stitch}
        for region in best.part.regions
        if region.graded_stitch is not None
    ]
    return _Outcome(
        rows,
        targets,
        instructions,
        solution.evaluations,
        solution.wall_time_s,
        solution.message,
        {},
    )


def contact_table(contact: dict, unit: str) -> list[str]:
    """The printed lines of the contact model beside the Laplace model (pressures in
    `unit`): per band both pressures, their difference, the stretches of both, the Laplace
    model at the contact model's stretches and the meridional term N_phi kappa."""
    scale = PRESSURE_UNITS[unit]
    state = "" if contact["complete"] else f" INCOMPLETE: {contact['message']}"
    lines = [
        f"  contact model: {contact['dofs']} DOFs, {contact['cells']} cells, "
        f"{len(contact['newton_iterations'])} steps, {contact['wall_time_s']:.3g} s{state}",
        f"  {'band':<5}{'z':>6}{'Laplace':>9}{'contact':>9}{'diff':>8}{'hoop L/c':>16}"
        f"{'axial L/c':>16}{'L at c':>9}{'N_phi k':>9}",
    ]
    for row in contact["bands"]:
        lines.append(
            f"  {row['band']:<5}{row['z']:>6.0f}{row['laplace'] / scale:>9.3f}"
            f"{row['contact'] / scale:>9.3f}{100 * row['difference']:>7.1f}%"
            f"{row['designed_hoop_stretch']:>8.4f}{row['hoop_stretch']:>8.4f}"
            f"{row['designed_axial_stretch']:>8.4f}{row['axial_stretch']:>8.4f}"
            f"{row['laplace_at_contact_stretches'] / scale:>9.3f}"
            f"{row['curvature_term'] / scale:>9.3f}"
        )
    return lines


def design_table(summary: dict) -> str:
    """The printed report of a design's summary (design.json)."""
    kind = summary["kind"]
    verdict = "every target met" if summary["met"] else "TARGETS MISSED (the best design found)"
    lines = [
        f"design of {summary['scene']!r} ({kind}, fidelity {summary['fidelity']}): "
        f"{summary['evaluations']} evaluations, search {summary['search_time_s']:.3g} s, "
        f"total {summary['wall_time_s']:.3g} s; {verdict}"
    ]
    if kind == "sleeve":
        unit = summary["targets"][0]["unit"]
        lines.append(
            f"  {'band':<5}{'z (mm)':>13}{'r (mm)':>8}{'stitch':>8}{'needles':>8}{'courses':>8}"
            f"{'hoop':>7}{'mmHg':>7}{'kPa':>7}{'target':>8} {unit:<6}{'miss':>7}"
        )
        for row, target in zip(summary["instructions"], summary["targets"], strict=True):
            flag = " *" if row["outside_data"] else ""
            lines.append(
                f"  {row['band']:<5}{row['z_from']:>6.0f} - {row['z_to']:<4.0f}"
                f"{row['limb_radius']:>8.1f}{row['stitch']:>8.3f}{row['needles']:>8d}"
                f"{row['courses']:>8d}{100 * row['hoop_strain']:>6.1f}%"
                f"{row['pressure_mmHg']:>7.2f}{row['pressure_kPa']:>7.3f}{target['target']:>8.3f}"
                f" {'':<6}{100 * target['miss']:>6.1f}%{flag}"
            )
        if any(row["outside_data"] for row in summary["instructions"]):
            lines.append("  * strained beyond the family's data: its pressure is extrapolated")
        contact = summary.get("contact")
        if contact:
            lines += contact_table(contact, unit)
        return "\n".join(lines)
    lines.append(f"  {'variable':<34}{'value':>10}  {'bounds':<14}")
    for variable in summary["variables"]:
        bounds = ""
        if "lower" in variable:
            bounds = f"[{variable['lower']:g}, {variable['upper']:g}]"
        lines.append(
            f"  {variable['name']:<34}{variable['value']:>10.4f}  {bounds:<14}{variable['unit']}"
        )
    lines.append(f"  {'target':<34}{'miss':>10}  {'tolerance':<10}")
    for target in summary["targets"]:
        mark = "" if target["met"] else "  MISSED"
        lines.append(
            f"  {target['name']:<34}{100 * target['miss']:>9.2f}%  "
            f"{100 * target['tolerance']:>5.1f} %{mark}"
        )
        if kind == "part":
            lines.append(
                f"    target {target['target']:.5g}, achieved {target['achieved']:.5g} "
                f"{target['unit']}"
            )
    return "\n".join(lines)
