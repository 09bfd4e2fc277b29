"""Accuracy and cost of the response-surface fits against spans and regularization.

The samples come from the analytic stand-in RVE (`AnalyticRve`, a stiffening exponential law
with coupling), so the exact law is known everywhere. For each fit kind, number of knot spans
and regularization weight the table gives:
  res    max |fit - sample| / max |sample| over the samples (what a user sees in the report),
  gap    the same error on rays halfway between the sampled ones (interpolation between rays),
  asym   tangent asymmetry max |dS11/dE22 - dS22/dE11| / max |dS/dE| (0 for the exact law),
  ms     fit time in milliseconds.

A second table varies the number of rays at the default fit options.

Run: .venv/bin/python benchmarks/bench_surface_fit.py [--rays 16] [--steps 10]
"""

import argparse
import time

import numpy as np

from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.fit import FitOptions, fit_energy_surface, fit_stress_surface
from rve_rod.homogenize.samples import RveCase, surface_samples
from rve_rod.homogenize.sampling import LoadPath, SamplingPlan
from rve_rod.presets import load_preset
from rve_rod.stress_measures import green_lagrange, voigt
from rve_rod.surface import tangent_asymmetry


def gap_strains(plan: SamplingPlan) -> np.ndarray:
    """Strains on rays halfway between the sampled rays, up to each ray's end."""
    step = 360.0 / plan.rays
    strains = []
    for angle in plan.angles_deg() + step / 2:
        path = LoadPath("biaxial", float(angle), plan.ray_length(angle), 4 * plan.steps_per_ray)
        strains.append(voigt(green_lagrange(path.deformation_gradients())))
    return np.concatenate(strains)


def errors(surface, samples, plan, rve):
    """(max relative residual at the samples, max relative error between the rays)."""
    gaps = gap_strains(plan)
    scale = np.abs(samples.biaxial_stress[:, :2]).max(axis=0)
    residual = max(surface.samples[name].stats().max_rel for name in ("S11", "S22"))
    gap = (np.abs(surface.stress(gaps).S[:, :2] - rve.stress(gaps)[:, :2]) / scale).max()
    return residual, gap


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rays", type=int, default=16)
    parser.add_argument("--steps", type=int, default=10)
    args = parser.parse_args()
    plan = SamplingPlan(rays=args.rays, steps_per_ray=args.steps)
    rve = AnalyticRve()
    fabric = load_preset("cotton-20s2", 5.5)
    paths = plan.load_paths()
    samples = surface_samples(paths, tuple(rve(RveCase(fabric, path)) for path in paths))
    print(
        f"{samples.biaxial_strain.shape[0]} biaxial samples on {args.rays} rays, "
        f"{samples.shear_strain.shape[0]} shear samples"
    )
    print(f"{'kind':>6} {'spans':>5} {'reg':>7} {'res':>9} {'gap':>9} {'asym':>9} {'ms':>7}")
    for kind, fitter in (("stress", fit_stress_surface), ("energy", fit_energy_surface)):
        for spans in (4, 6, 8, 10, 12):
            for regularization in (1e-8, 1e-6, 1e-4, 1e-3, 1e-2):
                options = FitOptions(spans=spans, regularization=regularization)
                started = time.perf_counter()
                surface = fitter(samples, options)
                elapsed = 1e3 * (time.perf_counter() - started)
                residual, gap = errors(surface, samples, plan, rve)
                print(
                    f"{kind:>6} {spans:>5} {regularization:>7.0e} {residual:>9.2e} "
                    f"{gap:>9.2e} {tangent_asymmetry(surface):>9.2e} {elapsed:>7.1f}"
                )

    print("\ndefault fit options, more or fewer rays:")
    print(f"{'kind':>6} {'rays':>5} {'samples':>7} {'res':>9} {'gap':>9} {'asym':>9}")
    for kind, fitter in (("stress", fit_stress_surface), ("energy", fit_energy_surface)):
        for rays in (8, 16, 32):
            plan = SamplingPlan(rays=rays, steps_per_ray=args.steps)
            paths = plan.load_paths()
            samples = surface_samples(paths, tuple(rve(RveCase(fabric, p)) for p in paths))
            surface = fitter(samples)
            residual, gap = errors(surface, samples, plan, rve)
            print(
                f"{kind:>6} {rays:>5} {samples.biaxial_strain.shape[0]:>7} {residual:>9.2e} "
                f"{gap:>9.2e} {tangent_asymmetry(surface):>9.2e}"
            )


if __name__ == "__main__":
    main()
