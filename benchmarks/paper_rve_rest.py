"""How much of the stiffness at rest runs through the loop's length: theirs and ours (issue 27).

For cotton 20s/2 at stitch 4.5, 5.5 and 6.5: the secant stiffness at rest C (S = C E through
the first states of the paper group's two rays nearest the axes, `paper.comparison.secant_at_rest`),
theirs and ours (the first state of the same two rays), split by
`paper.comparison.taut_loop_split` into a part k a a^T that runs through the loop's length
(a = (w dL/dw, c dL/dc) of our minimum-length loop at the fabric's w, c and r:
`rve_rod.geometry.loop.loop_length_gradient`) and a diagonal rest. Printed per stitch value
and model: C (gf/cm), the coupling C12 C21 / (C11 C22) (1 for a loop of inextensible yarn that
deforms only at constant length, 0 for uncoupled directions), k (gf/cm per mm^2), k over the
affine yarn's EA / (L w c) (the stiffness of the loop's length if the yarn alone carried it,
EA of the model's rods, L the template's loop length), and the rest (gf/cm; negative where C
does not fit the form with our a). Then the same C split with the affine gradient a = (int
t_x^2 ds, int t_y^2 ds) of the model's loop (`affine_length_gradient`: the loop stretched with
its shape held, where the yarn's own stretch carries k a a^T). Then, per stitch value, their
C split with the length gradient of each of our loop profiles (`OUT_OF_PLANE_PROFILES`: the
model's "band" and the issue-14 experiment's literature shapes): a1 / a2 and their rest (a
negative rest: their C does not fit that loop). Last, the same split on the parabolic loop
(the one whose gradient their C fits at 4.5): theirs and ours (the default model and the
variants of `PARABOLIC_MODELS`: stiffer contacts, no friction, the pre-loaded rests, the
exponent shift, the balanced contact) split with its own a, k / affine to four digits. The
tables go into docs/validation.md ("What the shape of their response says", point 6).

    .venv/bin/python benchmarks/paper_rve_rest.py [--control-points 68] [--parabolic-only]
        [--figure docs/figures/paper_rve_held_shape.png]

About three minutes at 68 control points on the shared 2-core machine (2026-11-28).
"""

import argparse
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rve_rod.contact import ContactOptions
from rve_rod.geometry.loop import (
    OUT_OF_PLANE_PROFILES,
    affine_length_gradient,
    loop_length_gradient,
    single_jersey_loop,
)
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import (
    axis_rays,
    compare_run,
    loop_profile_runner,
    secant_at_rest,
    taut_loop_split,
)
from rve_rod.rve.simulation import RveSettings
from rve_rod.rve.yarn import YarnSettings, yarn_model
from rve_rod.units import n_per_mm_to_gf_per_cm

STITCHES = (4.5, 5.5, 6.5)
MODELS = {
    "free fibres (the default)": YarnSettings(),
    "section (the paper's ingredients)": YarnSettings(bending="section"),
    "free fibres, contact x3": YarnSettings(contact_stiffness_factor=0.03),
    "free fibres, contact at r0 (squeezed rest)": YarnSettings(contact_radius="measured"),
    "section, contact at r0": YarnSettings(bending="section", contact_radius="measured"),
    "free fibres, contact at r0, frictionless": YarnSettings(
        contact_radius="measured", friction=False
    ),
}
BALANCED = ContactOptions(balance=True)
PARABOLIC_MODELS = {
    "free fibres (the default)": (YarnSettings(), ContactOptions()),
    "free fibres, contact x1.5": (YarnSettings(contact_stiffness_factor=0.015), ContactOptions()),
    "free fibres, contact x2": (YarnSettings(contact_stiffness_factor=0.02), ContactOptions()),
    "free fibres, frictionless": (YarnSettings(friction=False), ContactOptions()),
    "free fibres, contact at r0 (squeezed rest)": (
        YarnSettings(contact_radius="measured"),
        ContactOptions(),
    ),
    "free fibres, natural length the measured loop length": (
        YarnSettings(natural_length="measured"),
        ContactOptions(),
    ),
    "free fibres, exponent p - 0.25": (
        YarnSettings(contact_exponent_shift=-0.25),
        ContactOptions(),
    ),
    "free fibres, exponent p - 0.25, frictionless": (
        YarnSettings(contact_exponent_shift=-0.25, friction=False),
        ContactOptions(),
    ),
    "free fibres, balanced contact": (YarnSettings(), BALANCED),
    "free fibres, exponent p - 0.25, balanced contact": (
        YarnSettings(contact_exponent_shift=-0.25),
        BALANCED,
    ),
}
"""The parabolic loop's models: yarn settings and contact options (`ContactOptions.balance`:
the contact whose passes balance, docs/validation.md, "What pushes the loop out of its plane")."""


def _row(stitch, model, stiffness, gradient, affine, digits=3) -> str:
    """The table line of one C split with `gradient` (`taut_loop_split`)."""
    split = taut_loop_split(stiffness, gradient)
    c = n_per_mm_to_gf_per_cm(np.asarray(stiffness))
    k = n_per_mm_to_gf_per_cm(split.stiffness)
    rest = n_per_mm_to_gf_per_cm(split.rest)
    return (
        f"| {stitch} | {model} | {c[0, 0]:.0f} / {c[0, 1]:.0f} / {c[1, 0]:.0f} / {c[1, 1]:.0f} "
        f"| {split.coupling:.2f} | {k:.1f} | {split.stiffness / affine:.{digits}f} "
        f"| {rest[0]:.0f} / {rest[1]:.0f} |"
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--control-points", type=int, default=68)
    parser.add_argument("--parabolic-only", action="store_true", help="only the last table")
    parser.add_argument(
        "--figure", help="PNG of the yarn's share k / affine with the loop's shape held"
    )
    args = parser.parse_args()
    if args.parabolic_only:
        parabolic(args.control_points)
        return
    header = (
        "| stitch | model | C11 / C12 / C21 / C22 (gf/cm) | coupling | k (gf/cm/mm^2) "
        "| k / affine | rest C11, C22 (gf/cm) |\n|---:|---|---|---:|---:|---:|---|"
    )
    print(header)
    held = [header]  # the same C split with the affine gradient: the loop's shape held
    shares = {}  # model -> [k / affine with the shape held, per stitch value]
    for stitch in STITCHES:
        fabric = load_preset("cotton-20s2", stitch)
        w, c = fabric.knit.wale_width, fabric.knit.course_height
        loop = single_jersey_loop(w, c, fabric.yarn.minimal_radius)
        gradient = loop_length_gradient(w, c, loop.yarn_radius)
        stretched = affine_length_gradient(loop.curves)
        axes = axis_rays(stitch)
        theirs = secant_at_rest(axes)
        yarn = yarn_model(fabric)
        affine = yarn.section.axial / (loop.loop_length * w * c)
        print(
            f"| {stitch} | a = (w dL/dw, c dL/dc) = ({gradient[0]:.3f}, {gradient[1]:.3f}) mm, "
            f"L = {loop.loop_length:.3f} mm, EA = {yarn.section.axial:.2f} N | | | | | |"
        )
        print(_row(stitch, "theirs", theirs, gradient, affine), flush=True)
        held.append(
            f"| {stitch} | a = (int t_x^2 ds, int t_y^2 ds) = ({stretched[0]:.3f}, "
            f"{stretched[1]:.3f}) mm | | | | | |"
        )
        held.append(_row(stitch, "theirs", theirs, stretched, affine))
        shares.setdefault("theirs", []).append(
            taut_loop_split(theirs, stretched).stiffness / affine
        )
        for name, yarn_settings in MODELS.items():
            started = time.perf_counter()
            settings = RveSettings(
                cell=CellSettings(control_points=args.control_points), yarn=yarn_settings
            )
            first = [compare_run(fabric, ray, settings, states=1).second_piola[0] for ray in axes]
            ours = secant_at_rest(axes, [np.diagonal(s) for s in first])
            label = f"{name} ({time.perf_counter() - started:.0f} s)"
            print(_row(stitch, label, ours, gradient, affine), flush=True)
            held.append(_row(stitch, name, ours, stretched, affine))
            shares.setdefault(name, []).append(taut_loop_split(ours, stretched).stiffness / affine)
    print("\nThe same split with the affine gradient (the loop's shape held):\n")
    print("\n".join(held))
    if args.figure:
        held_shape_figure(shares, args.figure)
    profiles()
    parabolic(args.control_points)


def held_shape_figure(shares: dict[str, list[float]], path: str) -> None:
    """k / affine with the loop's shape held against the stitch value, theirs and ours (log
    scale; a share of 0, no coupling, is drawn at the axis's floor)."""
    floor = 1e-4
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for name, values in shares.items():
        theirs = name == "theirs"
        ax.plot(
            STITCHES,
            np.maximum(values, floor),
            "k*-" if theirs else "o--",
            markersize=11 if theirs else 5,
            linewidth=2 if theirs else 1,
            label="the paper group's RVE" if theirs else name,
        )
    ax.set_yscale("log")
    ax.set_ylim(floor * 0.8, 1.0)
    ax.set_xticks(STITCHES)
    ax.set_xlabel("stitch value (mm)")
    ax.set_ylabel("k / (EA / (L w c))  (0 drawn at 1e-4)")
    ax.set_title("The yarn's share of the stiffness at rest, the loop's shape held", fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    print(f"figure: {path}")


def profiles():
    """Their C at rest split with the length gradient of each loop profile (module docstring)."""
    print(
        "\n| stitch | loop profile | a1 / a2 | their rest C11, C22 (gf/cm) |\n|---:|---|---:|---|"
    )
    for stitch in STITCHES:
        fabric = load_preset("cotton-20s2", stitch)
        w, c = fabric.knit.wale_width, fabric.knit.course_height
        axes = axis_rays(stitch)
        theirs = secant_at_rest(axes)
        for profile in OUT_OF_PLANE_PROFILES:
            loop = single_jersey_loop(w, c, fabric.yarn.minimal_radius, profile=profile)
            gradient = loop_length_gradient(w, c, loop.yarn_radius, profile=profile)
            rest = n_per_mm_to_gf_per_cm(taut_loop_split(theirs, gradient).rest)
            ratio = gradient[0] / gradient[1]
            print(f"| {stitch} | {profile} | {ratio:.3f} | {rest[0]:.0f} / {rest[1]:.0f} |")


def parabolic(control_points: int):
    """Theirs and ours at rest on the parabolic loop, split with its length gradient."""
    print(
        "\n| stitch | model (parabolic loop) | C11 / C12 / C21 / C22 (gf/cm) | coupling "
        "| k (gf/cm/mm^2) | k / affine | rest C11, C22 (gf/cm) |\n|---:|---|---|---:|---:|---:|---|"
    )
    run = loop_profile_runner("parabolic")
    for stitch in STITCHES:
        fabric = load_preset("cotton-20s2", stitch)
        w, c = fabric.knit.wale_width, fabric.knit.course_height
        loop = single_jersey_loop(w, c, fabric.yarn.minimal_radius, profile="parabolic")
        gradient = loop_length_gradient(w, c, loop.yarn_radius, profile="parabolic")
        affine = yarn_model(fabric).section.axial / (loop.loop_length * w * c)
        axes = axis_rays(stitch)
        theirs = secant_at_rest(axes)
        print(_row(stitch, "theirs", theirs, gradient, affine, digits=4), flush=True)
        for name, (yarn_settings, contact) in PARABOLIC_MODELS.items():
            started = time.perf_counter()
            settings = RveSettings(
                cell=CellSettings(control_points=control_points, contact=contact),
                yarn=yarn_settings,
            )
            first = [
                compare_run(fabric, ray, settings, states=1, runner=run).second_piola[0]
                for ray in axes
            ]
            ours = secant_at_rest(axes, [np.diagonal(s) for s in first])
            label = f"{name} ({time.perf_counter() - started:.0f} s)"
            print(_row(stitch, label, ours, gradient, affine, digits=4), flush=True)


if __name__ == "__main__":
    main()
