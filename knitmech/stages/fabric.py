"""The stages of a scene with a fabric part: one surface per knit that occurs, the part solved.

Each region's material is, in this order: its `surface` file, its `svk` constants, or the
response surface of its knit (the [fabric] knit with the region's knit values on top). The
surfaces of the knits that occur are computed, each once, through the stage cache: the
scene's own knit by the scene's surface stage (`surface.h5`, or the scene's `surface.path`),
every other knit by a surface stage writing into `knits/<label>/`. A region with a surface
file or SVK constants needs no surface run. No DOLFINx here: the fabric stage runs the
`fabric` job (`knitmech.jobs`) when it computes.
"""

import dataclasses
import logging
from pathlib import Path
from typing import NamedTuple

from knitmech.jobs.fabric_spec import FabricJob, RegionMaterial
from knitmech.jobs.launch import run_job
from knitmech.scene.fabric import knit_fabric, region_knit
from knitmech.stages import STAGE_VERSION, SURFACE_FILE, RunPlan, file_digest
from knitmech.stages.cache import Stage
from rve_rod.pattern import pattern_chart
from rve_rod.presets import Fabric

__all__ = [
    "KnitSurfaces",
    "fabric_job",
    "fabric_stage",
    "fabric_table",
    "in_subfolder",
    "knit_label",
    "knit_surfaces",
]

logger = logging.getLogger(__name__)


class KnitSurfaces(NamedTuple):
    """The response surfaces a part needs.

    Attributes:
        scene_knit: whether a region uses the scene's [fabric] knit (its surface stage runs).
        others: label -> Fabric of every other knit that occurs (one surface stage each).
        region_knits: per region, the label of its knit ("" for the scene's knit), or None
            for a region with its own surface file or SVK constants, or a graded region.
        region_families: per region, ((stitch, label), ...) of a graded region's members,
            else None.
    """

    scene_knit: bool
    others: dict[str, Fabric]
    region_knits: tuple[str | None, ...]
    region_families: tuple[tuple[tuple[float, str], ...] | None, ...]


def knit_surfaces(plan: RunPlan) -> KnitSurfaces:
    """Which surfaces the part of `plan` needs (only the knits that occur, each once)."""
    fabric_table = dataclasses.asdict(plan.scene.fabric)
    others: dict[str, Fabric] = {}
    labels: list[str | None] = []
    families: list[tuple[tuple[float, str], ...] | None] = []

    def label_of(arguments: dict) -> str:
        fabric = knit_fabric(arguments)
        if fabric == plan.fabric:
            return ""
        label = next((k for k, v in others.items() if v == fabric), None)
        if label is None:
            label = knit_label(arguments, len(others))
            others[label] = fabric
        return label

    for region in plan.scene.part.regions:
        arguments = region_knit(fabric_table, region)
        if region.graded_stitch is not None:
            labels.append(None)
            families.append(
                tuple((s, label_of({**arguments, "stitch": s})) for s in region.members)
            )
        elif region.surface is not None or region.svk is not None:
            labels.append(None)
            families.append(None)
        else:
            labels.append(label_of(arguments))
            families.append(None)
    used = set(labels) | {label for family in families if family for _, label in family}
    return KnitSurfaces("" in used, others, tuple(labels), tuple(families))


def knit_label(arguments: dict, count: int) -> str:
    """The folder name of a knit's surface under `knits/`: `<preset>_stitch-<s>` for a preset
    knit (with `_<pattern>` when a pattern is given), `knit-<count + 1>` for one with
    values of its own."""
    if set(arguments) <= {"preset", "stitch", "pattern", "chart"} and "preset" in arguments:
        stitch = arguments.get("stitch")
        label = arguments["preset"] + (f"_stitch-{stitch:g}" if stitch is not None else "")
        pattern = arguments.get("pattern") or arguments.get("chart")
        if pattern is not None:  # a name, or the chart's rows joined by dashes
            chart = pattern_chart(list(pattern) if isinstance(pattern, tuple) else pattern)
            label += "_" + (chart.name or "-".join(chart.rows))
        return label
    return f"knit-{count + 1}"


def in_subfolder(stage: Stage, label: str) -> Stage:
    """`stage` with its files under `knits/<label>/` of the results folder."""

    def compute(folder: Path) -> dict:
        target = folder / "knits" / label
        target.mkdir(parents=True)
        return stage.compute(target)

    return stage._replace(item=label, compute=compute)


def fabric_job(plan: RunPlan, knits: KnitSurfaces, folder: Path) -> FabricJob:
    """The job of the part: each region's material from the surfaces in `folder`."""
    scene = plan.scene
    materials = []

    def surface_path(label: str) -> str:
        path = folder / SURFACE_FILE if label == "" else folder / "knits" / label / SURFACE_FILE
        return str(path.resolve())

    for region, label, family in zip(
        scene.part.regions, knits.region_knits, knits.region_families, strict=True
    ):
        if family is not None:
            members = tuple((stitch, surface_path(name)) for stitch, name in family)
            materials.append(RegionMaterial(stitch=region.graded_stitch, family=members))
        elif region.surface is not None:
            materials.append(RegionMaterial(surface=region.surface))
        elif region.svk is not None:
            materials.append(RegionMaterial(svk=region.svk))
        else:
            fabric = plan.fabric if label == "" else knits.others[label]
            materials.append(RegionMaterial(surface=surface_path(label), stitch=_stitch(fabric)))
    return FabricJob(
        part=scene.part,
        materials=tuple(materials),
        steps=scene.macro.steps,
        element_degree=plan.fidelity.element_degree,
    )


def _stitch(fabric: Fabric) -> float | None:
    """The stitch value of the knit (mm), or None for a knit given by values alone."""
    return fabric.knit.stitch_value


def fabric_stage(job: FabricJob, ranks: int) -> Stage:
    """The fabric stage of `job`; its cache key holds the surfaces by content, not path."""
    materials = [
        {
            "surface_sha256": file_digest(Path(m.surface)) if m.surface else None,
            "svk": m.svk,
            "stitch": m.stitch,
            "family": [(s, file_digest(Path(path))) for s, path in m.family or ()],
        }
        for m in job.materials
    ]
    inputs = {
        "version": STAGE_VERSION,
        "part": job.part,
        "materials": materials,
        "steps": job.steps,
        "element_degree": job.element_degree,
    }
    if job.part.mesh.file is not None:
        inputs["mesh_sha256"] = file_digest(Path(job.part.mesh.file))

    def compute(folder: Path) -> dict:
        return run_job("fabric", job.to_json(), folder, ranks)

    return Stage("fabric", "", inputs, compute)


def fabric_table(summary: dict) -> str:
    """The printed lines of the fabric stage: force and mean displacement of every boundary
    and the state of every probe at the end of the load path."""
    lines = [
        f"part: {summary['cells']} cells, {summary['dofs']} DOFs, {len(summary['load_factor']) - 1}"
        f" steps{'' if summary['complete'] else ' (INCOMPLETE: ' + summary['message'] + ')'}",
        f"  {'boundary':<12} {'kind':<13}"
        + "".join(f" {h:>11}" for h in ("Fx (N)", "Fy (N)", "ux (mm)", "uy (mm)")),
    ]
    for name, curve in summary["boundaries"].items():
        values = [*curve["force"][-1][:2], *curve["displacement"][-1][:2]]
        # a space before every number: -1.119e-15 fills its column
        lines.append(f"  {name:<12} {curve['kind']:<13}" + "".join(f" {v:>11.4g}" for v in values))
    for name, probe in summary.get("probes", {}).items():
        strain, stress = probe["strain"][-1], probe["cauchy"][-1]
        lines.append(
            f"  probe {name} at ({probe['centre'][0]:.4g}, {probe['centre'][1]:.4g}) mm: "
            f"shear angle {probe['shear_angle'][-1]:.4g} deg, E = ({strain[0][0]:.4g}, "
            f"{strain[1][1]:.4g}, {strain[0][1]:.4g}), sigma = ({stress[0][0]:.4g}, "
            f"{stress[1][1]:.4g}, {stress[0][1]:.4g}) N/mm (xx, yy, xy)"
        )
    space = summary.get("space")
    if space is not None and "indenter_resistance" in space:
        lines.append(
            f"  indenter: {space['indenter_resistance'][-1]:.4g} N at "
            f"{space['indenter_travel'][-1]:.4g} mm travel"
        )
    if space is not None and "pressure" in space:
        lines.append(
            f"  pressure: {space['pressure'][-1]:.4g} N/mm^2, largest displacement "
            f"{space['peak_displacement'][-1]:.4g} mm"
        )
    outside = [name for name, flag in summary["outside_domain"].items() if flag]
    if outside:
        lines.append(f"  strains left the surface's data in: {', '.join(outside)}")
    return "\n".join(lines)
