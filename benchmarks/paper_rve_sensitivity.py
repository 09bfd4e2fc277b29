"""Which ingredient makes our RVE differ from the paper group's: a sensitivity table (issue 27).

Each row varies ONE ingredient, from the paper's section model (`bending="section"`) or from
the default (free-fibre bending), and is compared with the group's data at stitch 4.5, 5.5
and 6.5 (`rve_rod.rve.paper.comparison`): along their 12 biaxial rays at every converged state
of theirs (rays within the 20 % target; the median over the rays of each ray's worst error;
the mean error at the first state, which measures the stiffness at rest; below each row C at
rest and the median over the rays of `first_increment_ratio`: slack or taut), their picture-frame
shear (the error at their state 6, 20 degrees, and 12, 40 degrees), and the uniaxial forces and
Poisson ratios at 20 % against their readings. The last rows combine ingredients; the rows
"prestrain" and "natural length" are the taut-loop experiment (a yarn shorter than its loop,
`YarnSettings.prestrain`; docs/validation.md, "The taut loop"), the row "point loads" the
reading of the law as a force at each collocation point (`ContactOptions.lumping`), the rows
"balanced contact" the contact whose passes balance (`ContactOptions.balance`), the rows
"natural curvature" and "straight yarn" a yarn that keeps no set
(`YarnSettings.natural_curvature`), the rows "friction mu" the friction coefficient, the rows
"torsion" the twisting rigidity apart from the bending (`YarnSettings.torsion`), the rows
"r0 = ..." the yarn's radius in the law and the section's scaling (`Variant.minimal_radius`), the
row "contact regions off" every distance minimum a full contact (`Variant.region_arc_length`),
the row "contacts held" the squeezed rest whose pressed contacts all stick (friction 10, a stiff
stick). The table goes into docs/validation.md ("The paper group's RVE");
`benchmarks/paper_rve_trade.py` draws it.

    .venv/bin/python benchmarks/paper_rve_sensitivity.py [--control-points 28]
        [--stitches 4.5,5.5,6.5] [--only NAME ...] [--lateral | --directions | --shear-normal]

With --directions, which way the contacts push at the first state of their two rays nearest
the axes (`paper.comparison.contact_directions`) and the coupling at rest C21 / C11 and C12 /
C22 (`secant_at_rest`), ours and theirs, for the rows of DIRECTION_ROWS.

With --shear-normal, for the rows of LATERAL_ROWS, the normal stresses S11, S22 beside S12 of
their picture-frame shear (F = [[1, sin a], [0, cos a]], E11 = E22 = 0) at 20 and 40 degrees,
ours / theirs (gf/cm): what a cell held at its lengths pushes or pulls as it is sheared.

With --lateral, the lateral pull instead, for the rows of LATERAL_ROWS (docs/validation.md,
"The diagnosis in brief"): along their two rays nearest the axes to their last converged
states, the stress across the pull at the last state (S22 on the course-wise ray, S11 on the
wale-wise ray) and the stress along it, ours / theirs (gf/cm): how much of their cell's pull
across a stretch each ingredient gives (a few seconds a row and stitch value).

A row (three stitch values) took 6-60 s at 28 control points and 30-340 s at 68-132 on the
shared 2-core machine (2026-11-27, after issue 29).
"""

import argparse
import dataclasses
import functools
import time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from rve_rod import units
from rve_rod.contact import ContactOptions, CoulombFriction
from rve_rod.errors import ConvergenceError, InputError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.geometry.loop import single_jersey_loop
from rve_rod.presets import Fabric, load_preset
from rve_rod.rve.cell import CellSettings, LoopCell
from rve_rod.rve.load_cases import BiaxialRay, LoadCase
from rve_rod.rve.paper.comparison import (
    AXIS_RAYS,
    axis_rays,
    compare_run,
    contact_directions,
    first_increment_ratio,
    run_case,
    run_or_history,
    secant_at_rest,
    uniaxial_comparison,
)
from rve_rod.rve.paper.data import UNIAXIAL_READINGS, biaxial_rays, shear_run
from rve_rod.rve.simulation import RveSettings, build_cell, loop_curves, run_cell
from rve_rod.rve.yarn import YarnModel, YarnSettings, yarn_model


class Variant(NamedTuple):
    """One row: its name, YarnSettings fields, changes of the yarn model (a function of the
    model and the fabric) or the loop, the contact's lumping (`ContactOptions.lumping`) and
    balance (`ContactOptions.balance`), and
    the yarn's r0 (mm) in place of the preset's 0.19 (None: the preset's): the radius of the
    contact law and of the section's scaling, the loop keeps r = w/8; the contact regions' arc
    (`ContactOptions.region_arc_length`, None: the default)."""

    name: str
    yarn_settings: dict
    yarn: Callable[[YarnModel, Fabric], YarnModel] | None = None
    profile: str = "band"
    lumping: str = "line"
    balance: bool = False
    tightening: float = 0.04
    minimal_radius: float | None = None
    region_arc_length: float | None = None


def with_exponent(exponent: float) -> Callable[[YarnModel, Fabric], YarnModel]:
    def change(yarn: YarnModel, _fabric: Fabric) -> YarnModel:
        return yarn._replace(law=dataclasses.replace(yarn.law, exponent=exponent))

    return change


def with_friction(
    coefficient: float, stiffness_ratio: float = 1.0
) -> Callable[[YarnModel, Fabric], YarnModel]:
    """The yarn with Coulomb friction of `coefficient` (the preset's cotton: 0.15) and
    k_t = stiffness_ratio k."""

    def change(yarn: YarnModel, _fabric: Fabric) -> YarnModel:
        return yarn._replace(
            friction=CoulombFriction.for_law(yarn.law, coefficient, stiffness_ratio)
        )

    return change


SECTION = {"bending": "section"}
FIBRES = {"bending": "free-fibres"}
PAPER_I_FIBRE_TORSION = {**SECTION, "second_moment": "paper", "torsion": "free-fibres"}
MEASURED_LENGTH = {"prestrain": 0.0, "natural_length": "measured"}
"""The rods' natural length the measured loop length l (no prestrain beyond it): taut where
the template holds more yarn than the fabric (4.5: 3.2 %), slack where less (6.5: 1.4 %)."""
VARIANTS = (
    Variant("section (the paper's ingredients)", SECTION),
    Variant("section, I = pi r^4/12", {**SECTION, "second_moment": "paper"}),
    Variant("section, frictionless", {**SECTION, "friction": False}),
    Variant("section, contact stiffness x3", {**SECTION, "contact_stiffness_factor": 0.03}),
    Variant("section, contact exponent p = 1", SECTION, with_exponent(1.0)),
    Variant("section, contact at r0 (squeezed rest)", {**SECTION, "contact_radius": "measured"}),
    Variant("section, parabolic loop", SECTION, profile="parabolic"),
    Variant("free fibres (the default)", FIBRES),
    Variant("free fibres, frictionless", {**FIBRES, "friction": False}),
    Variant("free fibres, contact stiffness x3", {**FIBRES, "contact_stiffness_factor": 0.03}),
    Variant("free fibres, contact stiffness x10", {**FIBRES, "contact_stiffness_factor": 0.1}),
    Variant("free fibres, contact exponent p = 1", FIBRES, with_exponent(1.0)),
    Variant("free fibres, contact at r0 (squeezed rest)", {**FIBRES, "contact_radius": "measured"}),
    Variant("free fibres, parabolic loop", FIBRES, profile="parabolic"),
    Variant("free fibres, exponent p - 0.25", {**FIBRES, "contact_exponent_shift": -0.25}),
    Variant(
        "free fibres, parabolic loop, exponent p - 0.25",
        {**FIBRES, "contact_exponent_shift": -0.25},
        profile="parabolic",
    ),
    Variant(
        "free fibres, contact at r0 and x3",
        {**FIBRES, "contact_radius": "measured", "contact_stiffness_factor": 0.03},
    ),
    Variant(
        "section I = pi r^4/12, contact x3",
        {**SECTION, "second_moment": "paper", "contact_stiffness_factor": 0.03},
    ),
    *(
        Variant(f"free fibres, prestrain eps0 = {100 * eps0:g} %", {**FIBRES, "prestrain": eps0})
        for eps0 in (0.005, 0.01, 0.02, 0.03, 0.04, 0.06, 0.08)
    ),
    *(
        Variant(
            f"free fibres, natural length l / (1 + eps0), eps0 = {100 * eps0:g} %",
            {**FIBRES, "prestrain": eps0, "natural_length": "measured"},
        )
        for eps0 in (0.0, 0.02, 0.03, 0.04)
    ),
    Variant(
        "free fibres, contact at r0 and prestrain eps0 = 2 %",
        {**FIBRES, "contact_radius": "measured", "prestrain": 0.02},
    ),
    Variant("free fibres, natural curvature half the loop's", {**FIBRES, "natural_curvature": 0.5}),
    Variant(
        "free fibres, straight yarn (natural curvature 0)", {**FIBRES, "natural_curvature": 0.0}
    ),
    Variant("section, straight yarn (natural curvature 0)", {**SECTION, "natural_curvature": 0.0}),
    Variant(
        "free fibres, straight yarn, frictionless",
        {**FIBRES, "natural_curvature": 0.0, "friction": False},
    ),
    Variant(
        "free fibres, contact at r0, frictionless",
        {**FIBRES, "contact_radius": "measured", "friction": False},
    ),
    Variant(
        "free fibres, contact at r0, stick stiffness k_t = k / 100",
        {**FIBRES, "contact_radius": "measured", "friction_stiffness_ratio": 0.01},
    ),
    Variant("free fibres bending, the section's torsion", {**FIBRES, "torsion": "section"}),
    Variant("section bending, the fibres' torsion", {**SECTION, "torsion": "free-fibres"}),
    Variant(
        "section bending, the fibres' torsion, parabolic loop",
        {**SECTION, "torsion": "free-fibres"},
        profile="parabolic",
    ),
    Variant(
        "section bending, the fibres' torsion, parabolic loop, exponent p - 0.25",
        {**SECTION, "contact_exponent_shift": -0.25, "torsion": "free-fibres"},
        profile="parabolic",
    ),
    Variant(
        "section I = pi r^4/12, the fibres' torsion, parabolic loop",
        PAPER_I_FIBRE_TORSION,
        profile="parabolic",
    ),
    Variant(
        "section I = pi r^4/12, the fibres' torsion, parabolic loop, exponent p - 0.25",
        {**PAPER_I_FIBRE_TORSION, "contact_exponent_shift": -0.25},
        profile="parabolic",
    ),
    *(
        Variant(
            f"free fibres, frictionless, prestrain eps0 = {100 * eps0:g} %",
            {**FIBRES, "friction": False, "prestrain": eps0},
        )
        for eps0 in (0.03, 0.06)
    ),
    Variant(
        "free fibres, contact x3, frictionless",
        {**FIBRES, "contact_stiffness_factor": 0.03, "friction": False},
    ),
    *(
        Variant(f"free fibres, friction mu = {mu:g}", FIBRES, with_friction(mu))
        for mu in (0.3, 0.6, 1.2)
    ),
    Variant("free fibres, tightened loop", FIBRES, profile="tightened"),
    Variant(
        "free fibres, tightened loop, frictionless",
        {**FIBRES, "friction": False},
        profile="tightened",
    ),
    *(
        Variant(
            f"free fibres, loop tightened by {100 * eps0:g} %, frictionless",
            {**FIBRES, "friction": False},
            profile="tightened",
            tightening=eps0,
        )
        for eps0 in (0.03, 0.06)
    ),
    Variant(
        "free fibres, tightened loop, contact at r0",
        {**FIBRES, "contact_radius": "measured"},
        profile="tightened",
    ),
    Variant(
        "free fibres, tightened loop, contact at r0, frictionless",
        {**FIBRES, "contact_radius": "measured", "friction": False},
        profile="tightened",
    ),
    Variant(
        "section I = pi r^4/12, the fibres' torsion, contact x3",
        {**PAPER_I_FIBRE_TORSION, "contact_stiffness_factor": 0.03},
    ),
    Variant(
        "section I = pi r^4/12, the fibres' torsion, parabolic loop, contact x3",
        {**PAPER_I_FIBRE_TORSION, "contact_stiffness_factor": 0.03},
        profile="parabolic",
    ),
    Variant(
        "section I = pi r^4/12, the fibres' torsion, parabolic loop, r0 = 0.198 mm",
        PAPER_I_FIBRE_TORSION,
        profile="parabolic",
        minimal_radius=0.198,
    ),
    Variant(
        "section bending, the fibres' torsion, parabolic loop, r0 = 0.198 mm",
        {**SECTION, "torsion": "free-fibres"},
        profile="parabolic",
        minimal_radius=0.198,
    ),
    Variant("free fibres, balanced contact", FIBRES, balance=True),
    Variant("section, balanced contact", SECTION, balance=True),
    Variant(
        "free fibres, contact at r0 (squeezed rest), balanced contact",
        {**FIBRES, "contact_radius": "measured"},
        balance=True,
    ),
    Variant(
        "section, contact at r0, balanced contact",
        {**SECTION, "contact_radius": "measured"},
        balance=True,
    ),
    Variant(
        "section bending, the fibres' torsion, contact at r0, balanced contact",
        {**SECTION, "torsion": "free-fibres", "contact_radius": "measured"},
        balance=True,
    ),
    Variant(
        "section I = pi r^4/12, the fibres' torsion, contact at r0, balanced contact",
        {**PAPER_I_FIBRE_TORSION, "contact_radius": "measured"},
        balance=True,
    ),
    Variant(
        "free fibres, contact at r0, frictionless, balanced contact",
        {**FIBRES, "contact_radius": "measured", "friction": False},
        balance=True,
    ),
    Variant(
        "free fibres, straight yarn, contact at r0, balanced contact",
        {**FIBRES, "natural_curvature": 0.0, "contact_radius": "measured"},
        balance=True,
    ),
    Variant(
        "section, straight yarn, frictionless",
        {**SECTION, "natural_curvature": 0.0, "friction": False},
    ),
    Variant(
        "free fibres, contact at r0, balanced contact, mu = 10, k_t = 10 k (contacts held)",
        {**FIBRES, "contact_radius": "measured"},
        with_friction(10.0, 10.0),
        balance=True,
    ),
    Variant(
        "free fibres, prestrain eps0 = 2 %, balanced contact",
        {**FIBRES, "prestrain": 0.02},
        balance=True,
    ),
    Variant(
        "free fibres, parabolic loop, balanced contact", FIBRES, profile="parabolic", balance=True
    ),
    Variant(
        "free fibres, parabolic loop, exponent p - 0.25, balanced contact",
        {**FIBRES, "contact_exponent_shift": -0.25},
        profile="parabolic",
        balance=True,
    ),
    Variant(
        "section I = pi r^4/12, the fibres' torsion, parabolic loop, contact x3, balanced contact",
        {**PAPER_I_FIBRE_TORSION, "contact_stiffness_factor": 0.03},
        profile="parabolic",
        balance=True,
    ),
    Variant("section, point loads r f_n at the collocation points", SECTION, lumping="point"),
    Variant("free fibres, point loads r f_n at the collocation points", FIBRES, lumping="point"),
    Variant(
        "free fibres, contact regions off (every distance minimum a full contact)",
        FIBRES,
        region_arc_length=1e-3,
    ),
    Variant(
        "free fibres, natural length l, balanced contact",
        {**FIBRES, **MEASURED_LENGTH},
        balance=True,
    ),
    Variant(
        "free fibres, natural length l, contact x3, balanced contact",
        {**FIBRES, **MEASURED_LENGTH, "contact_stiffness_factor": 0.03},
        balance=True,
    ),
    Variant(
        "free fibres, natural length l, contact at r0, balanced contact",
        {**FIBRES, **MEASURED_LENGTH, "contact_radius": "measured"},
        balance=True,
    ),
    Variant(
        "free fibres, natural length l, contact at r0, frictionless, balanced contact",
        {**FIBRES, **MEASURED_LENGTH, "contact_radius": "measured", "friction": False},
        balance=True,
    ),
    Variant(
        "free fibres, parabolic loop, natural length l, balanced contact",
        {**FIBRES, **MEASURED_LENGTH},
        profile="parabolic",
        balance=True,
    ),
    Variant(
        "free fibres, natural length l, point loads r f_n, balanced contact",
        {**FIBRES, **MEASURED_LENGTH},
        lumping="point",
        balance=True,
    ),
)


TIGHTENING = {"contact_stiffness_factor": 0.03, "friction": False}
"""How the "tightened" loop is pulled tight: the yarn's natural length `Variant.tightening`
short (4 % unless a row says otherwise), the contact three times stiffer, frictionless (2 %
with the contact x3 and 5 % with x10 found no rest state at 5.5)."""


@functools.cache
def tightened_loop(
    stitch: float, control_points: int, prestrain: float
) -> tuple[list[BSplineCurve], float]:
    """The template of cotton `stitch` pulled tight at its measured w and c (its yarn's
    natural length `prestrain` short, TIGHTENING, at F = I: `LoopCell.rest_state`), as 4
    quarter curves from the cut (the pulled shape is the new stress-free loop), and the radius
    at which its pressed contacts just touch (r minus half the largest penetration: the rest
    state of the cell built on it grows the contacts back to r, so the loop starts pre-loaded
    as the squeezed rest does)."""
    fabric = load_preset("cotton-20s2", stitch)
    settings = RveSettings(
        cell=CellSettings(control_points=control_points),
        yarn=YarnSettings(**FIBRES, **TIGHTENING, prestrain=prestrain),
    )
    cell = build_cell(loop_curves(fabric), fabric, BiaxialRay(steps=2), settings)
    rest = cell.rest_state(settings.newton, settings.stepping)
    pulled = BSplineCurve(cell.curve.degree, cell.curve.knots, cell.positions(rest))
    penetration = cell.coupling.result(rest, 0.0, tangent=False).statistics.max_penetration
    quarters, rest_of_loop = [], pulled
    for parameter in (1.0, 2.0, 3.0):
        pieces = rest_of_loop.split(parameter)
        quarters.append(pieces.left)
        rest_of_loop = pieces.right
    quarters.append(rest_of_loop)
    print(
        f"  tightened {stitch:g} by {100 * prestrain:g} %: yarn per loop "
        f"{cell.curve.arc_length():.4f} -> "
        f"{pulled.arc_length():.4f} mm, largest penetration {penetration / cell.yarn.radius:.3f} r",
        flush=True,
    )
    return quarters, cell.yarn.radius - 0.5 * penetration - 1e-9


def runner(variant: Variant) -> Callable[[Fabric, LoadCase, RveSettings], object]:
    """`simulate` with the variant's yarn model and loop."""
    if variant.yarn is None and variant.profile == "band":
        return run_or_history

    def run(fabric: Fabric, case: LoadCase, settings: RveSettings):
        yarn = yarn_model(fabric, settings.yarn)
        if variant.profile == "tightened":
            stitch = fabric.knit.stitch_value
            curves, touching = tightened_loop(
                stitch, settings.cell.control_points, variant.tightening
            )
            yarn = yarn._replace(radius=touching)
            own = max(curve.n_control_points for curve in curves)
            settings = dataclasses.replace(
                settings, cell=dataclasses.replace(settings.cell, control_points=own, cut=0.0)
            )
        elif variant.profile == "band":
            curves = loop_curves(fabric)
        else:
            knit = fabric.knit
            loop = single_jersey_loop(
                knit.wale_width,
                knit.course_height,
                fabric.yarn.minimal_radius,
                profile=variant.profile,
            )
            curves = list(loop.curves)
        if variant.yarn is not None:
            yarn = variant.yarn(yarn, fabric)
        cell = LoopCell(curves, fabric.knit, yarn, case, settings.cell)
        try:
            return run_cell(cell, fabric, settings)
        except ConvergenceError as error:
            return error.history

    return run


def setup(variant: Variant, stitch: float, control_points: int) -> tuple[Fabric, RveSettings]:
    """The variant's fabric (cotton 20s/2 at `stitch`, its r0) and settings."""
    settings = RveSettings(
        cell=CellSettings(
            control_points=control_points,
            contact=ContactOptions(
                lumping=variant.lumping,
                balance=variant.balance,
                region_arc_length=variant.region_arc_length,
            ),
        ),
        yarn=YarnSettings(**variant.yarn_settings),
    )
    fabric = load_preset("cotton-20s2", stitch)
    if variant.minimal_radius is not None:
        yarn = dataclasses.replace(fabric.yarn, minimal_radius=variant.minimal_radius)
        fabric = dataclasses.replace(fabric, yarn=yarn)
    return fabric, settings


def measure(variant: Variant, stitch: float, control_points: int) -> dict:
    fabric, settings = setup(variant, stitch, control_points)
    run = runner(variant)
    theirs = biaxial_rays(stitch)
    rays = [compare_run(fabric, ray, settings, runner=run) for ray in theirs]
    axes = [min(range(len(theirs)), key=lambda k: abs(theirs[k].angle_deg - a)) for a in AXIS_RAYS]
    rest = [
        secant_at_rest(
            [theirs[k] for k in axes], [np.diagonal(pair.second_piola[0]) for pair in pairs]
        )
        if all(pair.states for pair in pairs)
        else np.full((2, 2), np.nan)
        for pairs in ([rays[k] for k in axes], [theirs[k] for k in axes])
    ]
    ratios = np.array(
        [
            [
                first_increment_ratio(ray.reference.deformation, np.diagonal(s, axis1=1, axis2=2))
                for s in (ray.second_piola, ray.reference.second_piola)
            ]
            for ray in rays
            if ray.states >= 2 and ray.reached >= 2
        ]
    ).reshape(-1, 2)
    rays = [ray for ray in rays if ray.states]
    worst = np.array([ray.worst() for ray in rays])
    first = np.array([ray.errors()[0] for ray in rays])
    shear = compare_run(fabric, shear_run(stitch), settings, states=12, runner=run).errors()
    uniaxial = uniaxial_comparison(fabric, settings, (0.2,), steps_per_percent=0.5, runner=run)
    return {
        "passed": int(np.sum(worst <= 0.2)),
        "rays": len(rays),
        "median": float(np.median(worst)),
        "first": float(first[np.isfinite(first)].mean()) if np.isfinite(first).any() else np.nan,
        "shear": (float(shear[5]), float(shear[11])),
        "uniaxial": uniaxial,
        "rest": rest,
        "increments": np.median(ratios, axis=0) if len(ratios) else np.full(2, np.nan),
    }


LATERAL_ROWS = (
    "free fibres (the default)",
    "section (the paper's ingredients)",
    "section, I = pi r^4/12",
    "free fibres, frictionless",
    "free fibres, friction mu = 1.2",
    "free fibres, contact stiffness x3",
    "free fibres, point loads r f_n at the collocation points",
    "free fibres, parabolic loop",
    "free fibres, prestrain eps0 = 3 %",
    "free fibres, tightened loop",
    "free fibres, contact at r0 (squeezed rest)",
    "free fibres, contact at r0 (squeezed rest), balanced contact",
    "free fibres, contact at r0, frictionless, balanced contact",
    "section I = pi r^4/12, the fibres' torsion, parabolic loop, contact x3",
    "free fibres, contact regions off (every distance minimum a full contact)",
    "free fibres, parabolic loop, natural length l, balanced contact",
)
"""The rows of the lateral-pull table (--lateral)."""


def lateral(variant: Variant, stitch: float, control_points: int) -> str:
    """Table cells of the lateral pull: per axis ray, across / along at the last converged
    state, ours / theirs (gf/cm)."""
    fabric, settings = setup(variant, stitch, control_points)
    cells = []
    for ray, (along, across) in zip(axis_rays(stitch), ((0, 1), (1, 0)), strict=True):
        comparison = compare_run(fabric, ray, settings, runner=runner(variant))
        if comparison.reached == 0:
            cells.append("stopped")
            continue
        last = comparison.reached - 1
        ours = units.n_per_mm_to_gf_per_cm(np.diagonal(comparison.second_piola[last]))
        theirs = units.n_per_mm_to_gf_per_cm(np.diagonal(ray.second_piola[last]))
        stopped = "" if comparison.reached == comparison.states else f" (state {last + 1})"
        cells.append(
            f"{ours[across]:.1f} / {theirs[across]:.1f} ({ours[across] / theirs[across]:.2f}); "
            f"{ours[along]:.1f} / {theirs[along]:.1f}{stopped}"
        )
    return " | ".join(cells)


SHEAR_STATES = (5, 11)
"""Their picture-frame shear states of the --shear-normal table (20 and 40 degrees)."""


def shear_normal(variant: Variant, stitch: float, control_points: int) -> str:
    """Table cells of the normal stresses of their picture-frame shear (E11 = E22 = 0): at 20
    and 40 degrees S11, S22, S12, ours / theirs (gf/cm)."""
    fabric, settings = setup(variant, stitch, control_points)
    run = shear_run(stitch)
    ours = compare_run(fabric, run, settings, states=12, runner=runner(variant)).second_piola
    cells = []
    for state in SHEAR_STATES:
        pairs = units.n_per_mm_to_gf_per_cm(
            np.stack([ours[state], run.second_piola[state]])[:, [0, 1, 0], [0, 1, 1]]
        )
        cells.append(", ".join(f"{a:.1f} / {b:.1f}" for a, b in pairs.T))
    return " | ".join(cells)


DIRECTION_ROWS = (
    "free fibres (the default)",
    "free fibres, parabolic loop",
    "free fibres, tightened loop",
    "free fibres, contact at r0 (squeezed rest), balanced contact",
    "free fibres, natural length l, contact x3, balanced contact",
    "free fibres, straight yarn (natural curvature 0)",
    "free fibres, contact at r0, balanced contact, mu = 10, k_t = 10 k (contacts held)",
)
"""The rows of the contact-direction table (--directions)."""


def directions(variant: Variant, stitch: float, control_points: int) -> str:
    """Table cells of the contact directions at the first state of their two rays nearest
    the axes (`paper.comparison.contact_directions`: |n_x| / |n_y| / |n_z| weighted by the
    normal force) and the coupling at rest C21 / C11, C12 / C22 (`secant_at_rest`), ours and
    theirs."""
    fabric, settings = setup(variant, stitch, control_points)
    rays = axis_rays(stitch)
    cells, first = [], []
    for ray in rays:
        result = runner(variant)(fabric, run_case(ray, 1), settings)
        f = np.eye(3)
        f[:2, :2] = result.steps[1].deformation
        try:
            shares = contact_directions(
                result.centreline(1), result.cell_lattice @ f.T, result.yarn.radius, result.yarn.law
            )
        except InputError:  # no point of the yarn within the law's reach at that state
            cells.append("no contact found")
        else:
            cells.append(" / ".join(f"{share:.2f}" for share in shares))
        first.append(np.asarray(result.steps[1].second_piola)[:2])  # S11, S22
    ours = secant_at_rest(rays, first)
    theirs = secant_at_rest(rays)
    coupling = [f"{c[1, 0] / c[0, 0]:.2f}, {c[0, 1] / c[1, 1]:.2f}" for c in (ours, theirs)]
    return " | ".join([*cells, f"{coupling[0]} ({coupling[1]})"])


def row_table(
    header: str,
    names: tuple[str, ...],
    cells: Callable[[Variant, float, int], str],
    stitches: list[float],
    control_points: int,
    only: list[str] | None = None,
) -> None:
    """A table of the rows `names` (of VARIANTS; with `only`, those whose name contains one of
    its words) at each stitch value, their `cells`."""
    print(header)
    print("|---|---:|" + "---|" * (header.count("|") - 3))
    rows = {variant.name: variant for variant in VARIANTS}
    for name in names:
        if only and not any(word in name for word in only):
            continue
        for stitch in stitches:
            row = cells(rows[name], stitch, control_points)
            print(f"| {name} | {stitch:g} | {row} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--control-points", type=int, default=28)
    parser.add_argument("--stitches", default="4.5,5.5,6.5")
    parser.add_argument("--only", nargs="*", help="rows whose name contains one of these")
    parser.add_argument("--lateral", action="store_true", help="the lateral-pull table")
    parser.add_argument("--directions", action="store_true", help="the contact-direction table")
    parser.add_argument(
        "--shear-normal", action="store_true", help="the normal stresses of their shear"
    )
    args = parser.parse_args()
    stitches = [float(s) for s in args.stitches.split(",")]
    if args.directions:
        row_table(
            "| variant | stitch | course-wise ray: contact normals along x / y / z | wale-wise "
            "ray: the same | coupling at rest C21 / C11, C12 / C22, ours (theirs) |",
            DIRECTION_ROWS,
            directions,
            stitches,
            args.control_points,
            args.only,
        )
        return
    if args.shear_normal:
        row_table(
            "| variant | stitch | 20 degrees: S11, S22, S12, ours / theirs | 40 degrees: the "
            "same |",
            LATERAL_ROWS,
            shear_normal,
            stitches,
            args.control_points,
            args.only,
        )
        return
    if args.lateral:
        row_table(
            "| variant | stitch | course-wise ray: S22 across, ours / theirs (ratio); S11 along "
            "| wale-wise ray: S11 across, ours / theirs (ratio); S22 along |",
            LATERAL_ROWS,
            lateral,
            stitches,
            args.control_points,
            args.only,
        )
        return
    print(
        "| variant | stitch | rays within 20 % | median worst error | mean error at the first "
        "state | shear error at 20 / 40 deg | course F 20 % (theirs) | nu12 (theirs) | "
        "wale F 20 % (theirs) | nu21 (theirs) | wall s |"
    )
    print("|---|---:|---:|---:|---:|---|---|---|---|---|---:|")
    for variant in VARIANTS:
        if args.only and not any(word in variant.name for word in args.only):
            continue
        for stitch in stitches:
            started = time.perf_counter()
            row = measure(variant, stitch, args.control_points)
            u = row["uniaxial"]
            reading = UNIAXIAL_READINGS[(stitch, 0.2)]
            theirs = {
                name: " / ".join("-" if v is None else f"{v:g}" for v in getattr(reading, name))
                for name in ("course_force", "nu12", "wale_force", "nu21")
            }
            print(
                f"| {variant.name} | {stitch:g} | {row['passed']} of {row['rays']} | "
                f"{row['median']:.2f} | {row['first']:.2f} | "
                f"{row['shear'][0]:.2f} / {row['shear'][1]:.2f} | "
                f"{u.course_force[0]:.1f} ({theirs['course_force']}) | "
                f"{u.nu12[0]:.2f} ({theirs['nu12']}) | {u.wale_force[0]:.1f} "
                f"({theirs['wale_force']}) | {u.nu21[0]:.2f} ({theirs['nu21']}) | "
                f"{time.perf_counter() - started:.0f} |",
                flush=True,
            )
            ours, theirs = (units.n_per_mm_to_gf_per_cm(c).round(0).tolist() for c in row["rest"])
            increments = " / ".join(f"{r:.2f}" for r in row["increments"])
            print(
                f"  C at rest (gf/cm): ours {ours}, theirs {theirs}; first / second increment "
                f"(median of the rays), ours / theirs: {increments}",
                flush=True,
            )


if __name__ == "__main__":
    main()
