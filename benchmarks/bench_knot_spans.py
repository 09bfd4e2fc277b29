"""Knot spans of the stress fit against independent truth, on the levels' own RVE runs.

Reads the results that `benchmarks/bench_pipeline.py --keep DIR` left for each level (its
surface file holds the samples it was fitted to) and refits those samples with other knot
spans (the level's other fit options kept; no RVE run). Each refit is measured against:

* the reference's samples (64 rays of 20 steps at 132 control points) inside the level's
  sampled box: RMS and largest error of S11 and S22, relative to the largest |S| of that
  component there (the level's own discretization error included, the same for every span);
* the level's own uniaxial RVE runs (its meso stage): the material alone in uniaxial tension
  (`homogeneous_response`) against them at 5, 10 and 20 %, course- and wale-wise. These states
  lie between the rays, where the knit's lateral stress turns from slack to taut;
* the surface checks (`surface_problems`).

Run: .venv/bin/python benchmarks/bench_knot_spans.py DIR [--levels fast,balanced,accurate,reference]
         [--spans 12,16,18,20,22,24,28]
"""

import argparse
import dataclasses
import json
from pathlib import Path

import numpy as np

from rve_rod.homogenize.acceptance import surface_problems
from rve_rod.homogenize.fit import FitOptions, fit_stress_surface
from rve_rod.homogenize.samples import stored_samples
from rve_rod.surface import homogeneous_response, read_surface
from rve_rod.units import n_per_mm_to_gf_per_cm

STRAINS = (0.05, 0.10, 0.20)


def rve_force(summary: dict, direction: str, strain: float) -> float:
    """The level's uniaxial RVE force (gf/cm) at the output state `strain`."""
    run = summary["meso"][f"uniaxial-{direction}"]
    index = int(np.argmin(np.abs(np.array(run["strain"]) - strain)))
    if abs(run["strain"][index] - strain) > 1e-9:
        raise ValueError(f"the {direction} run has no state at {strain}")
    return run["force_gf_per_cm"][index]


def measure(level_dir: Path, reference, spans: int) -> dict:
    """Errors (%) of the level's samples refitted on `spans` knot spans (module docstring)."""
    shipped = read_surface(level_dir / "surface.h5")
    summary = json.loads((level_dir / "summary.json").read_text())
    samples = stored_samples(shipped)
    options = {k: v for k, v in shipped.parameters["fit"].items() if k != "kind"}
    surface = fit_stress_surface(samples, FitOptions(**{**options, "spans": spans}))
    surface = dataclasses.replace(surface, parameters={**shipped.parameters, **surface.parameters})
    box = samples.biaxial_strain[:, :2]
    strain = reference.biaxial_strain[:, :2]
    inside = np.all((strain >= box.min(0)) & (strain <= box.max(0)), axis=1)
    truth = reference.biaxial_stress[inside, :2]
    fitted = np.stack([surface.s11(*strain[inside].T), surface.s22(*strain[inside].T)], axis=1)
    error = (fitted - truth) / np.abs(truth).max(axis=0)
    uniaxial = {}
    for direction in ("course", "wale"):
        force = n_per_mm_to_gf_per_cm(homogeneous_response(surface, list(STRAINS), direction))
        for value, strain_ in zip(force, STRAINS, strict=True):
            rve = rve_force(summary, direction, strain_)
            uniaxial[f"{direction[0]}{round(100 * strain_)}"] = 100 * (value / rve - 1)
    return {
        "rms": 100 * np.sqrt(np.mean(error**2, axis=0)),
        "max": 100 * np.abs(error).max(axis=0),
        "uniaxial": uniaxial,
        "problems": len(surface_problems(surface)),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("keep", type=Path, help="the --keep folder of bench_pipeline.py")
    parser.add_argument("--levels", default="fast,balanced,accurate,reference")
    parser.add_argument("--spans", default="12,16,18,20,22,24,28")
    args = parser.parse_args()
    reference = stored_samples(read_surface(args.keep / "reference" / "results" / "surface.h5"))
    print("errors in %: S11/S22 against the reference's samples (RMS, largest); the material")
    print("alone against the level's uniaxial RVE runs (c: course-, w: wale-wise, at 5/10/20 %)")
    print(
        "level      spans  rms S11/S22  max S11/S22      c5    c10    c20     w5    w10    w20"
        "  worst  problems"
    )
    for level in args.levels.split(","):
        for spans in (int(value) for value in args.spans.split(",")):
            row = measure(args.keep / level / "results", reference, spans)
            uniaxial = row["uniaxial"]
            worst = max(abs(value) for value in uniaxial.values())
            print(
                f"{level:10s} {spans:5d}  {row['rms'][0]:5.2f}/{row['rms'][1]:5.2f}"
                f"  {row['max'][0]:5.1f}/{row['max'][1]:5.1f}  "
                + " ".join(f"{uniaxial[key]:+6.1f}" for key in uniaxial)
                + f"  {worst:5.1f}  {row['problems']:8d}",
                flush=True,
            )


if __name__ == "__main__":
    main()
