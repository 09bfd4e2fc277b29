"""The surfaces of a knit's family: one surface stage per stitch value, as `knitmech run` makes
them for a graded region.

A member is the scene's [fabric] knit at another of its preset's stitch values (the yarn
values of [fabric] kept). The member that is the scene's own knit takes the scene's surface
(its `[surface] path`, or the scene's surface stage, `surface.h5`); every other member a
surface stage of its own in `knits/<preset>_stitch-<s>/`, with the same cache keys as the
graded regions of `knitmech run`, so a design and a run of its scene share their surfaces.
"""

import dataclasses
import shutil
from collections.abc import Callable, Sequence
from pathlib import Path

from knitmech.design.family import FamilyMember
from knitmech.stages import SURFACE_FILE, RunPlan, SurfaceRuns, surface_stage
from knitmech.stages.cache import Stage
from knitmech.stages.fabric import in_subfolder, knit_label
from rve_rod.errors import InputError
from rve_rod.presets import make_fabric, stitch_values

__all__ = [
    "FAMILY_KNIT_KEYS",
    "family_members",
    "family_stitches",
]

FAMILY_KNIT_KEYS = ("yarn_radius", "youngs_modulus", "poissons_ratio", "friction")
"""The [fabric] values a family keeps for every member (its wale width and course height are
the preset's at each stitch value)."""


def family_stitches(plan: RunPlan, bounds: tuple[float, float] | None = None) -> list[float]:
    """The preset's stitch values (mm) from the largest at or below `bounds[0]` to the
    smallest at or above `bounds[1]` (all of them without bounds); InputError when the scene
    has no preset measured at several stitch values, or gives w or c itself."""
    fabric = plan.scene.fabric
    values = sorted(float(v) for v in stitch_values(fabric.preset)) if fabric.preset else []
    if len(values) < 2:
        raise InputError(
            f"fabric.preset: {fabric.preset!r} is not measured at several stitch values; a "
            "design needs a family (e.g. cotton-20s2) or its members given ([[design.member]])"
        )
    for key in ("wale_width", "course_height"):
        if getattr(fabric, key) is not None:
            raise InputError(
                f"fabric.{key}: a design takes each member's {key} from the preset; remove it"
            )
    if bounds is None:
        return values
    low, high = bounds
    first = max(i for i, v in enumerate(values) if v <= low + 1e-9)
    last = min(i for i, v in enumerate(values) if v >= high - 1e-9)
    return values[first : last + 1]


def family_members(
    plan: RunPlan,
    stitches: Sequence[float],
    run: Callable[[Stage], dict],
    runs: SurfaceRuns,
    folder: Path,
) -> tuple[FamilyMember, ...]:
    """The family's members at `stitches` (mm), their surfaces made by `run` (the stage
    cache's runner; files into `folder`, see the module docstring)."""
    table = dataclasses.asdict(plan.scene.fabric)
    kept = {key: table[key] for key in FAMILY_KNIT_KEYS if table[key] is not None}
    members = []
    for index, stitch in enumerate(stitches):
        arguments = {"preset": plan.scene.fabric.preset, "stitch": stitch, **kept}
        knit = make_fabric(**arguments)
        if knit == plan.fabric:
            path = folder / SURFACE_FILE
            if plan.scene.surface.path is not None:
                shutil.copyfile(plan.scene.surface.path, path)
            else:
                run(surface_stage(plan, runs))
        else:
            label = knit_label(arguments, index)
            run(in_subfolder(surface_stage(plan._replace(fabric=knit), runs), label))
            path = folder / "knits" / label / SURFACE_FILE
        members.append(
            FamilyMember(stitch, str(path.resolve()), knit.knit.wale_width, knit.knit.course_height)
        )
    return tuple(members)
