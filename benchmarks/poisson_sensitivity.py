"""Why the knit contracts too little: sensitivity of the RVE's Poisson ratios (issue 14).

Cotton 20s/2 at stitch 5.5 in uniaxial tension course- and wale-wise, 0-20 %, at coarse
settings (20 control points per quarter, 11 output states unless a row says otherwise). Each
row varies ONE ingredient of the model from the paper's (the section's bending rigidity,
`bending="section"`, the default before version 0.3.0: the model this diagnosis is of) and
prints the force at 10 and 20 %
(gf/cm) and the Poisson ratio at 20 % of both directions; the rows of the last group are
other definitions of the ratio, read off the default runs. The table goes into
docs/validation.md ("Why the knit contracts too little").

    .venv/bin/python benchmarks/poisson_sensitivity.py [--control-points 20] [--steps 11]
        [--only NAME ...]

About 2-4 s per run on a quiet machine (2 runs per row).
"""

import argparse
import dataclasses
import time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from rve_rod import __version__
from rve_rod.errors import ConvergenceError
from rve_rod.geometry.loop import LoopShape, loop_geometry, single_jersey_loop
from rve_rod.presets import Fabric, load_preset
from rve_rod.rve.cell import CellSettings, LoopCell
from rve_rod.rve.load_cases import load_case
from rve_rod.rve.simulation import RveResult, RveSettings, run_cell
from rve_rod.rve.yarn import YarnModel, YarnSettings, yarn_model

CASES = ("uniaxial-course", "uniaxial-wale")


class Variant(NamedTuple):
    """One row: a name, the ingredient's value, and how it changes the default model."""

    ingredient: str
    value: str
    fabric: Callable[[Fabric], Fabric] = lambda fabric: fabric
    yarn_settings: dict | None = None
    cell_settings: dict | None = None
    contact_options: dict | None = None
    yarn: Callable[[YarnModel], YarnModel] = lambda yarn: yarn
    curves: Callable[[Fabric], list] | None = None
    steps: int | None = None


def with_friction(coefficient: float) -> Callable[[Fabric], Fabric]:
    def change(fabric: Fabric) -> Fabric:
        yarn = dataclasses.replace(fabric.yarn, friction_coefficient=coefficient)
        return dataclasses.replace(fabric, yarn=yarn)

    return change


def with_exponent(exponent: float) -> Callable[[YarnModel], YarnModel]:
    def change(yarn: YarnModel) -> YarnModel:
        return yarn._replace(law=dataclasses.replace(yarn.law, exponent=exponent))

    return change


def pre_loaded(factor: float) -> Callable[[YarnModel], YarnModel]:
    """The contact law on a radius `factor` r: the loop, built with r, overlaps by 2 (factor - 1)
    r where its yarns touch, and the zero-strain solve relaxes it to a pre-loaded equilibrium."""

    def change(yarn: YarnModel) -> YarnModel:
        law = dataclasses.replace(yarn.law, yarn_radius=factor * yarn.radius)
        return yarn._replace(law=law)

    return change


def shoulder(factor: float) -> Callable[[Fabric], list]:
    """The loop with shoulder radius rho = factor r (depth from the clearance condition)."""

    def curves(fabric: Fabric) -> list:
        base = loop_geometry(fabric.knit, fabric.yarn.minimal_radius)
        knit = fabric.knit
        loop = single_jersey_loop(
            knit.wale_width,
            knit.course_height,
            fabric.yarn.minimal_radius,
            shoulder_radius=factor * base.yarn_radius,
        )
        return list(loop.curves)

    return curves


def deeper(factor: float) -> Callable[[Fabric], list]:
    """The minimum-length loop's shape with its depth d multiplied by `factor` (>= 1: every
    distance to a yarn at another height grows, so the loop still clears its neighbours)."""

    def curves(fabric: Fabric) -> list:
        base = loop_geometry(fabric.knit, fabric.yarn.minimal_radius)
        shape = LoopShape(
            base.wale_width,
            base.course_height,
            base.yarn_radius,
            base.shape_parameter,
            factor * base.depth,
        )
        return list(shape.curves())

    return curves


VARIANTS = (
    Variant(f"default ({__version__})", "-"),
    Variant("friction coefficient mu", "0 (frictionless)", with_friction(0.0)),
    Variant("friction coefficient mu", "0.3", with_friction(0.3)),
    Variant("stick stiffness k_t / k", "0.1", yarn_settings={"friction_stiffness_ratio": 0.1}),
    Variant("stick stiffness k_t / k", "10", yarn_settings={"friction_stiffness_ratio": 10.0}),
    Variant("anchors kept within 2r + margin", "margin 0.01 r", contact_options={"margin": 0.01}),
    Variant("load steps (friction path)", "21 states", steps=21),
    Variant("second moment I", "pi r^4/12 (paper)", yarn_settings={"second_moment": "paper"}),
    Variant("contact stiffness factor", "0.001", yarn_settings={"contact_stiffness_factor": 1e-3}),
    Variant("contact stiffness factor", "0.1", yarn_settings={"contact_stiffness_factor": 0.1}),
    Variant("contact exponent p", "1.0", yarn=with_exponent(1.0)),
    Variant("contact exponent p", "2.5", yarn=with_exponent(2.5)),
    Variant("contact pre-load (law radius)", "1.01 r", yarn=pre_loaded(1.01)),
    Variant("contact pre-load (law radius)", "1.03 r", yarn=pre_loaded(1.03)),
    Variant("loop shoulder rho", "1.6 r", curves=shoulder(1.6)),
    Variant("loop depth d", "1.3 x minimum", curves=deeper(1.3)),
    Variant("loop depth d", "1.6 x minimum", curves=deeper(1.6)),
)


def run(variant: Variant, case_name: str, control_points: int, steps: int) -> RveResult:
    """One uniaxial run of cotton 20s/2 stitch 5.5 with the variant's change."""
    fabric = variant.fabric(load_preset("cotton-20s2", 5.5))
    contact = CellSettings().contact
    if variant.contact_options:
        margin = variant.contact_options.get("margin")
        radius = yarn_model(fabric).radius
        contact = dataclasses.replace(contact, search_margin=margin * radius)
    settings = RveSettings(
        cell=CellSettings(control_points=control_points, contact=contact),
        yarn=YarnSettings(**{"bending": "section", **(variant.yarn_settings or {})}),
    )
    case = load_case(case_name, 0.2, variant.steps or steps)
    curves = (
        variant.curves(fabric)
        if variant.curves
        else list(loop_geometry(fabric.knit, fabric.yarn.minimal_radius).curves)
    )
    yarn = variant.yarn(yarn_model(fabric, settings.yarn))
    cell = LoopCell(curves, fabric.knit, yarn, case, settings.cell)
    try:
        return run_cell(cell, fabric, settings)
    except ConvergenceError as error:
        return error.history


def at(result: RveResult, strain: float, name: str) -> float:
    """Series `name` at the output state of `strain`, NaN if the run stopped before it."""
    strains = result.series("strain")
    hit = np.flatnonzero(np.isclose(strains, strain, atol=1e-9))
    return float(result.series(name)[hit[0]]) if hit.size else float("nan")


def ratio(result: RveResult) -> str:
    """-lateral / axial strain at 20 %, or where the run stopped."""
    if not result.steps:
        return "no unloaded equilibrium"
    if not result.complete:
        return f"stopped at {100 * result.steps[-1].strain:.0f} %"
    return f"{-at(result, 0.2, 'lateral_strain') / 0.2:.3f}"


def first_step(result: RveResult) -> str:
    """Lateral strain at the first loaded state (%)."""
    if len(result.steps) < 2:
        return "-"
    return f"{100 * result.steps[1].lateral_strain:+.2f}"


def definitions(course: RveResult, wale: RveResult) -> list[tuple[str, str, float, float]]:
    """Other definitions of nu12, nu21 from the default runs (ingredient, value, nu12, nu21)."""
    rows = []
    for label, function in (
        ("tangent -d eps_lat / d eps at 20 %", tangent_ratio),
        ("Green-Lagrange -E_lat / E at 20 %", green_ratio),
        ("logarithmic -ln(lam_lat) / ln(lam) at 20 %", log_ratio),
        ("secant from the 2 % state", preloaded_ratio),
        ("secant at 10 %", lambda result: secant_at(result, 0.1)),
    ):
        rows.append(("definition of nu", label, function(course), function(wale)))
    return rows


def _strains(result: RveResult) -> tuple[np.ndarray, np.ndarray]:
    return result.series("strain"), result.series("lateral_strain").astype(float)


def tangent_ratio(result: RveResult) -> float:
    strain, lateral = _strains(result)
    return float(-(lateral[-1] - lateral[-2]) / (strain[-1] - strain[-2]))


def green_ratio(result: RveResult) -> float:
    strain, lateral = _strains(result)
    return float(-((1 + lateral[-1]) ** 2 - 1) / ((1 + strain[-1]) ** 2 - 1))


def log_ratio(result: RveResult) -> float:
    strain, lateral = _strains(result)
    return float(-np.log1p(lateral[-1]) / np.log1p(strain[-1]))


def preloaded_ratio(result: RveResult) -> float:
    strain, lateral = _strains(result)
    lateral_stretch = (1 + lateral[-1]) / (1 + lateral[1])
    return float(-(lateral_stretch - 1) / ((1 + strain[-1]) / (1 + strain[1]) - 1))


def secant_at(result: RveResult, strain: float) -> float:
    return -at(result, strain, "lateral_strain") / strain


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=20)
    parser.add_argument("--steps", type=int, default=11)
    parser.add_argument("--only", nargs="*", help="run only rows whose ingredient contains these")
    args = parser.parse_args()
    print(
        f"cotton 20s/2 stitch 5.5, {args.control_points} control points, {args.steps} states to"
        " 20 %; forces in gf/cm\n"
    )
    print(
        "| ingredient | value | course F 10 % | course F 20 % | nu12 | course lateral at 2 % |"
        " wale F 10 % | wale F 20 % | nu21 | s |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    default_runs = None
    for variant in VARIANTS:
        if args.only and not any(word in variant.ingredient for word in args.only):
            continue
        started = time.perf_counter()
        course, wale = (run(variant, case, args.control_points, args.steps) for case in CASES)
        seconds = time.perf_counter() - started
        if variant.ingredient.startswith("default"):
            default_runs = course, wale
        print(
            f"| {variant.ingredient} | {variant.value} | {at(course, 0.1, 'force_gf_per_cm'):.4g}"
            f" | {at(course, 0.2, 'force_gf_per_cm'):.4g} | {ratio(course)} | {first_step(course)}"
            f" | {at(wale, 0.1, 'force_gf_per_cm'):.4g} | {at(wale, 0.2, 'force_gf_per_cm'):.4g}"
            f" | {ratio(wale)} | {seconds:.0f} |",
            flush=True,
        )
    if default_runs is not None:
        for ingredient, label, nu12, nu21 in definitions(*default_runs):
            print(f"| {ingredient} | {label} | | | {nu12:.3f} | | | | {nu21:.3f} | |")


if __name__ == "__main__":
    main()
