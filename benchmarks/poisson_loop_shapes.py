"""Literature loop shapes against the model's loop: the Poisson ratios (issue 14 experiment).

Cotton 20s/2 at stitch 5.5 in uniaxial tension course- and wale-wise, 0-20 %, at the coarse
settings of benchmarks/poisson_sensitivity.py (20 control points per quarter, 11 states). Each
row builds the loop with one out-of-plane profile of `rve_rod.geometry.loop.OUT_OF_PLANE_PROFILES`
("band" is the model; "parabolic" Crane's, "helical" Kurbak-like legs; same projection,
symmetries and clearance rule, the depth and shoulder found as for the model), with the
paper's friction or frictionless; control rows (`ROWS`) put the model's loop at the depth of
another profile's, use the paper's second moment, or let the contact law act on a smaller
radius than the loop's. It prints the loop (length against the measured 5.50 mm, depth), the
force at 10 and 20 % (gf/cm), the Poisson ratio at 20 %, the lateral macro stress at 20 % split
into the yarn force through the cut and the normal and friction loads of the contacts (gf/cm;
they sum to zero), and, for the course-wise runs with friction, that P22 split by contact
group (crossing, oblique, in plane). The tables go into docs/validation.md ("Literature loop
shapes").

    .venv/bin/python benchmarks/poisson_loop_shapes.py [--control-points 20] [--steps 11]
        [--only PROFILE ...] [--frictionless]

About 1 s per run on a quiet machine (2 runs per row, 15 rows; 68 control points and 21 states:
about 10 s per row).
"""

import argparse
import dataclasses
import time
from typing import NamedTuple

import numpy as np
from poisson_sensitivity import at, ratio  # the sensitivity table's reading of a run

from rve_rod.errors import ConvergenceError
from rve_rod.geometry.loop import (
    OUT_OF_PLANE_PROFILES,
    LoopGeometry,
    LoopShape,
    single_jersey_loop,
)
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings, LoopCell
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.macro import image_weights
from rve_rod.rve.simulation import RveResult, RveSettings, run_cell
from rve_rod.rve.yarn import YarnSettings, yarn_model
from rve_rod.units import n_per_mm_to_gf_per_cm

CASES = ("uniaxial-course", "uniaxial-wale")
LATERAL_AXIS = {"uniaxial-course": 1, "uniaxial-wale": 0}
"""The free normal component of each case: P22 course-wise, P11 wale-wise."""


class Row(NamedTuple):
    """One row: the loop's profile, friction on or off, optionally the model's ("band") loop at
    the depth of another profile's loop (a control: depth alone), optionally the paper's second
    moment or a contact law acting on a smaller radius `law_radius` r than the loop is built
    with (the built-in contacts at W open by 2 (1 - law_radius) r: a control of the jammed row;
    both not the model's, marked in the table)."""

    profile: str
    friction: bool = True
    depth_of: str | None = None
    paper_second_moment: bool = False
    law_radius: float = 1.0

    def label(self) -> str:
        label = self.profile if self.depth_of is None else f"band at the {self.depth_of} depth"
        if self.law_radius != 1.0:
            label += f", contact law on {self.law_radius:g} r (not the model)"
        return label + (", paper I (not the model)" if self.paper_second_moment else "")


ROWS = (
    *(Row(profile) for profile in OUT_OF_PLANE_PROFILES),
    Row("band", depth_of="parabolic"),
    Row("band", depth_of="helical"),
    *(Row(profile, friction=False) for profile in OUT_OF_PLANE_PROFILES),
    Row("band", friction=False, depth_of="parabolic"),
    Row("band", paper_second_moment=True),
    Row("parabolic", paper_second_moment=True),
    *(
        Row(profile, law_radius=factor)
        for factor in (0.95, 0.9)
        for profile in ("band", "parabolic")
    ),
)


def loop_of(profile: str) -> LoopGeometry:
    """The loop of cotton 20s/2 stitch 5.5 with the out-of-plane `profile`."""
    fabric = load_preset("cotton-20s2", 5.5)
    knit = fabric.knit
    return single_jersey_loop(
        knit.wale_width, knit.course_height, fabric.yarn.minimal_radius, profile=profile
    )


def curves_of(row: Row) -> list:
    """The 4 curves of the row's loop."""
    loop = loop_of(row.profile)
    if row.depth_of is None:
        return list(loop.curves)
    depth = loop_of(row.depth_of).depth
    shape = LoopShape(
        loop.wale_width, loop.course_height, loop.yarn_radius, loop.shape_parameter, depth
    )
    return list(shape.curves())


def run(row: Row, case_name: str, control_points: int, steps: int) -> tuple[RveResult, LoopCell]:
    """One uniaxial run of cotton 20s/2 stitch 5.5 on the row's loop, and its cell (which keeps
    the friction anchors of the last state)."""
    fabric = load_preset("cotton-20s2", 5.5)
    yarn = YarnSettings(  # the section model the experiment diagnosed (issue 14)
        friction=row.friction,
        second_moment="paper" if row.paper_second_moment else "solid",
        bending="section",
    )
    settings = RveSettings(cell=CellSettings(control_points=control_points), yarn=yarn)
    model = yarn_model(fabric, settings.yarn)
    law = dataclasses.replace(model.law, yarn_radius=row.law_radius * model.radius)
    cell = LoopCell(
        curves_of(row),
        fabric.knit,
        model._replace(law=law),
        load_case(case_name, 0.2, steps),
        settings.cell,
    )
    try:
        return run_cell(cell, fabric, settings), cell
    except ConvergenceError as error:
        return error.history, cell


CONTACT_GROUPS = (
    ("crossing, |n_z| > 0.7", 0.7, 1.01),
    ("oblique, 0.3 < |n_z| <= 0.7", 0.3, 0.7),
    ("in plane, |n_z| <= 0.3", -0.01, 0.3),
)
"""Contacts sorted by the out-of-plane part of their normal (as in docs/validation.md)."""


def contact_groups(
    result: RveResult, cell: LoopCell, a: int
) -> list[tuple[str, int, float, float]]:
    """The lateral P_aa of the last state split by CONTACT_GROUPS: (group, contacts, normal
    part, friction part) (gf/cm), from the contact evaluation against the committed anchors
    (for the last state its own: the converged friction loads)."""
    F = np.eye(3)
    F[:2, :2] = result.steps[-1].deformation
    coupling = cell.coupling
    contacts = coupling.contact.evaluate(result.centrelines[-1], F, tangent=False).contacts
    weights, _ = image_weights(coupling, _Evaluated(contacts), a)  # for P_aa: column a
    normal_part = weights * contacts.normal_load * contacts.normal[a]
    friction_part = weights * contacts.friction_load[a]
    rows = []
    for name, low, high in CONTACT_GROUPS:
        group = (np.abs(contacts.normal[2]) > low) & (np.abs(contacts.normal[2]) <= high)
        rows.append(
            (
                name,
                int(np.count_nonzero(group & (weights != 0))),
                float(n_per_mm_to_gf_per_cm(normal_part[group].sum())),
                float(n_per_mm_to_gf_per_cm(friction_part[group].sum())),
            )
        )
    return rows


class _Evaluated(NamedTuple):
    """A contact evaluation as `image_weights` reads it."""

    contacts: object


def lateral_split(result: RveResult, case_name: str) -> str:
    """Cut / normal / friction parts of the lateral macro stress at the last state (gf/cm)."""
    if not result.complete:
        return "-"
    a = LATERAL_AXIS[case_name]
    parts = n_per_mm_to_gf_per_cm(result.steps[-1].stress_parts[:, a, a])
    return " / ".join(f"{part:+.3g}" for part in parts)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=20)
    parser.add_argument("--steps", type=int, default=11)
    parser.add_argument("--only", nargs="*", choices=OUT_OF_PLANE_PROFILES)
    parser.add_argument("--frictionless", action="store_true", help="only frictionless rows")
    args = parser.parse_args()
    fabric = load_preset("cotton-20s2", 5.5)
    knit = fabric.knit
    print(
        f"cotton 20s/2 stitch 5.5, {args.control_points} control points, {args.steps} states to"
        f" 20 %; measured loop length {knit.measured_loop_length} mm; forces and the lateral"
        " split (cut / normal / friction) at 20 % in gf/cm\n"
    )
    print(
        "| loop | friction | loop length (dev.) | depth / r | course F 10 % | course F 20 % |"
        " nu12 | P22 split | sliding / active | wale F 10 % | wale F 20 % | nu21 | P11 split |"
        " s |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---|---:|")
    grouped = {}
    for row in ROWS:
        if (args.only and row.profile not in args.only) or (args.frictionless and row.friction):
            continue
        curves = curves_of(row)
        length = sum(curve.arc_length() for curve in curves)
        depth = loop_of(row.depth_of or row.profile).depth
        started = time.perf_counter()
        (course, course_cell), (wale, _) = (
            run(row, case, args.control_points, args.steps) for case in CASES
        )
        seconds = time.perf_counter() - started
        if row.friction and row.depth_of is None and row.law_radius == 1.0 and course.complete:
            grouped[row.label()] = contact_groups(course, course_cell, LATERAL_AXIS[CASES[0]])
        deviation = length / knit.measured_loop_length - 1
        last = course.steps[-1] if course.complete else None
        contacts = f"{last.sliding_contacts} / {last.active_contacts}" if last else "-"
        print(
            f"| {row.label()} | {'mu = 0.15' if row.friction else 'none'}"
            f" | {length:.3f} ({100 * deviation:+.1f} %)"
            f" | {depth / loop_of('band').yarn_radius:.2f}"
            f" | {at(course, 0.1, 'force_gf_per_cm'):.4g}"
            f" | {at(course, 0.2, 'force_gf_per_cm'):.4g} | {ratio(course)}"
            f" | {lateral_split(course, CASES[0])} | {contacts}"
            f" | {at(wale, 0.1, 'force_gf_per_cm'):.4g}"
            f" | {at(wale, 0.2, 'force_gf_per_cm'):.4g} | {ratio(wale)}"
            f" | {lateral_split(wale, CASES[1])} | {seconds:.0f} |",
            flush=True,
        )

    print("\n| loop (course-wise, 20 %) | contacts | count | normal part of P22 | friction part |")
    print("|---|---|---:|---:|---:|")
    for label, rows in grouped.items():
        for name, count, normal, friction in rows:
            print(f"| {label} | {name} | {count} | {normal:+.3g} | {friction:+.3g} |")


if __name__ == "__main__":
    main()
