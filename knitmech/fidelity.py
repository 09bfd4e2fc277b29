"""Fidelity levels: named sets of discretization settings that trade accuracy for speed.

A scene picks a level (`fast`, `balanced` (default), `accurate`); every setting a scene leaves
out comes from it. `REFERENCE` is the finest set, against which `benchmarks/bench_pipeline.py`
measures the levels (docs/pipeline.md has the table); it is not meant for everyday runs.

The load steps are chosen so that 5, 10 and 20 % strain are output states of a 0-20 % path
(step sizes 2.5, 1 and 0.5 %), where the summary reports forces.
"""

from dataclasses import dataclass

from rve_rod.errors import InputError

__all__ = [
    "DEFAULT",
    "LEVELS",
    "REFERENCE",
    "Fidelity",
    "fidelity_level",
]


@dataclass(frozen=True)
class Fidelity:
    """Discretization of every stage of a run.

    Attributes:
        name: the level's name.
        control_points: control points per quarter loop curve of every RVE run (meso runs and
            surface runs alike, so that both see the same yarn model; the paper uses 68; at 20
            the free-fibre yarn's Poisson ratios are 9-12 % off, at 28 within 3 %; a pattern's
            cell of several courses runs at least
            `rve_rod.rve.engine.SEVERAL_COURSES_CONTROL_POINTS`, 36).
        meso_steps: output states of a meso-scale run, the unloaded one included.
        rays: biaxial rays of the surface sampling over the full circle.
        steps_per_ray: output steps along each ray.
        shear_steps: output steps of the pure-shear run.
        spans: knot spans per input of the S11, S22 surfaces (fine enough that the knit's
            lateral stress, which turns from slack to taut within about 0.02 of strain near
            the free contraction, is resolved; as many as the rays support:
            docs/benchmarks.md, "Knot spans").
        shear_spans: knot spans of the S12 curve (even).
        elements: elements per side of the fabric patch.
        macro_steps: load steps of the fabric patch.
        element_degree: Lagrange degree of the patch's displacement (1 or 2).
    """

    name: str
    control_points: int
    meso_steps: int
    rays: int
    steps_per_ray: int
    shear_steps: int
    spans: int
    shear_spans: int
    elements: int
    macro_steps: int
    element_degree: int = 1


LEVELS: dict[str, Fidelity] = {
    level.name: level
    for level in (
        Fidelity(
            name="fast",
            control_points=28,
            meso_steps=9,
            rays=24,
            steps_per_ray=5,
            shear_steps=6,
            spans=20,
            shear_spans=4,
            elements=6,
            macro_steps=8,
        ),
        Fidelity(
            name="balanced",
            control_points=36,
            meso_steps=21,
            rays=32,
            steps_per_ray=10,
            shear_steps=15,
            spans=22,
            shear_spans=10,
            elements=10,
            macro_steps=20,
        ),
        Fidelity(
            name="accurate",
            control_points=68,
            meso_steps=41,
            rays=48,
            steps_per_ray=20,
            shear_steps=30,
            spans=24,
            shear_spans=12,
            elements=20,
            macro_steps=40,
        ),
    )
}
"""The levels a scene may name, from the cheapest to the most accurate (chosen from the
measurements of benchmarks/bench_pipeline.py, docs/pipeline.md)."""

DEFAULT = "balanced"
"""The level of a scene that names none."""

REFERENCE = Fidelity(
    name="reference",
    control_points=132,
    meso_steps=41,
    rays=64,
    steps_per_ray=20,
    shear_steps=30,
    spans=28,
    shear_spans=16,
    elements=40,
    macro_steps=40,
    element_degree=2,
)
"""The finest settings: what the levels are measured against (benchmarks only)."""


def fidelity_level(name: str) -> Fidelity:
    """The level called `name` (one of LEVELS, or "reference")."""
    if name == REFERENCE.name:
        return REFERENCE
    if name not in LEVELS:
        raise InputError(f"fidelity={name!r} is not one of {', '.join(LEVELS)}")
    return LEVELS[name]
