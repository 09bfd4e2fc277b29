"""Accuracy of a graded knit's family: a member left out, predicted from its neighbours.

A graded region interpolates the response surfaces of the preset's stitch values piecewise
linearly in the stitch value (fabric_dolfinx/graded.py). Leaving a member out measures what
that interpolation costs: the surface at s is predicted as the mean of the surfaces at s - h
and s + h and compared with the surface computed at s, for the member spacings h the preset
allows (0.5 and 1.0 mm for cotton 20s/2). Two measures:

* the stress: the largest and the root-mean-square difference of S11, S22 (on a 21 x 21 grid
  of (E11, E22)) and S12 (41 values of E12) over the domain the three surfaces share,
  relative to the largest |S| of the computed surface there;
* the force a fabric shows: the homogeneous uniaxial force per width (lateral stress 0,
  `rve_rod.surface.checks.homogeneous_response`) course- and wale-wise at 10 and 20 % strain,
  predicted against computed.

The surfaces are made as `knitmech run` makes them at the chosen level (same RVE settings,
sampling and fit), through the RVE-run cache under --cache (a second run only fits).

Run: .venv/bin/python benchmarks/bench_graded_family.py [--level fast] [--jobs 2]
         [--cache DIR] [--stitches 4.5,5.0,5.5,6.0,6.5,7.0]
"""

import argparse
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

from knitmech.fidelity import fidelity_level
from knitmech.scene import scene_from_dict
from knitmech.stages import plan_run
from rve_rod.cache import ResultCache, default_cache_root
from rve_rod.homogenize.generate import generate_surface
from rve_rod.rve import RodRve
from rve_rod.surface import ResponseSurface, homogeneous_response

STRAINS = (0.1, 0.2)
"""Engineering strains of the uniaxial force comparison."""


def surface_at(stitch: float, level: str, cache: Path, jobs: int) -> ResponseSurface:
    """The cotton 20s/2 surface at `stitch` as `knitmech run` makes it at `level`."""
    scene = scene_from_dict({"fabric": {"preset": "cotton-20s2", "stitch": stitch}})
    plan = plan_run(scene, fidelity_level(level))
    started = time.perf_counter()
    generated = generate_surface(
        plan.fabric,
        RodRve(plan.rve),
        plan.sampling,
        plan.fit,
        cache=ResultCache(cache / "rve-runs"),
        jobs=jobs,
    )
    print(f"  stitch {stitch}: {time.perf_counter() - started:.0f} s")
    return generated.surface


class _Stress(NamedTuple):
    S: np.ndarray


class MeanSurface(NamedTuple):
    """The graded law half-way between two members: S = (S_below + S_above) / 2."""

    below: ResponseSurface
    above: ResponseSurface

    def stress(self, E: np.ndarray) -> _Stress:
        return _Stress(0.5 * (self.below.stress(E).S + self.above.stress(E).S))


def left_out_error(predicted: MeanSurface, computed: ResponseSurface) -> dict[str, float]:
    """Largest and RMS relative error of `predicted` against `computed` per component."""
    domain = np.stack([predicted.below.domain, computed.domain, predicted.above.domain])
    low, high = domain[:, :, 0].max(axis=0), domain[:, :, 1].min(axis=0)
    e11, e22 = np.meshgrid(np.linspace(low[0], high[0], 21), np.linspace(low[1], high[1], 21))
    normal = np.stack([e11.ravel(), e22.ravel(), np.zeros(e11.size)], axis=1)
    shear = np.zeros((41, 3))
    shear[:, 2] = np.linspace(low[2], high[2], 41)
    errors = {}
    for name, strains, component in (("S11", normal, 0), ("S22", normal, 1), ("S12", shear, 2)):
        direct = computed.stress(strains).S[:, component]
        difference = predicted.stress(strains).S[:, component] - direct
        scale = np.max(np.abs(direct))
        errors[f"{name} max"] = float(np.max(np.abs(difference)) / scale)
        errors[f"{name} rms"] = float(np.sqrt(np.mean(difference**2)) / scale)
    return errors


def force_errors(predicted: MeanSurface, computed: ResponseSurface) -> dict[str, float]:
    """Relative error of the uniaxial force per width at STRAINS, course- and wale-wise."""
    errors = {}
    for direction in ("course", "wale"):
        direct = homogeneous_response(computed, np.array(STRAINS), direction)
        estimate = homogeneous_response(predicted, np.array(STRAINS), direction)
        for strain, d, e in zip(STRAINS, direct, estimate, strict=True):
            errors[f"{direction[0]}{round(100 * strain)}"] = float((e - d) / d)
    return errors


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--level", default="fast")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--cache", type=Path, default=default_cache_root())
    parser.add_argument("--stitches", default="4.5,5.0,5.5,6.0,6.5,7.0")
    args = parser.parse_args()
    stitches = [float(s) for s in args.stitches.split(",")]
    print(f"surfaces at level {args.level}:")
    surfaces = {s: surface_at(s, args.level, args.cache, args.jobs) for s in stitches}
    stress_keys = [f"{c} {m}" for c in ("S11", "S22", "S12") for m in ("max", "rms")]
    force_keys = [f"{d}{round(100 * s)}" for d in "cw" for s in STRAINS]
    print("\nleft-out stress error (% of the largest |S|) and uniaxial force error (%)")
    header = "".join(f"{k:>9}" for k in (*stress_keys, *force_keys))
    print(f"{'left out':>9}{'spacing':>9}{header}")
    for stitch in stitches:
        for spacing in (0.5, 1.0):
            below, above = stitch - spacing, stitch + spacing
            if below in surfaces and above in surfaces:
                predicted = MeanSurface(surfaces[below], surfaces[above])
                errors = {
                    **left_out_error(predicted, surfaces[stitch]),
                    **force_errors(predicted, surfaces[stitch]),
                }
                cells = "".join(f"{100 * errors[k]:>9.2f}" for k in (*stress_keys, *force_keys))
                print(f"{stitch:>9g}{spacing:>9g}{cells}")
    print("\nuniaxial force per width (N/mm) of each member at", STRAINS)
    for stitch, surface in surfaces.items():
        course = homogeneous_response(surface, np.array(STRAINS), "course")
        wale = homogeneous_response(surface, np.array(STRAINS), "wale")
        print(f"{stitch:>9g}  course {np.round(course, 4)}  wale {np.round(wale, 4)}")


if __name__ == "__main__":
    main()
