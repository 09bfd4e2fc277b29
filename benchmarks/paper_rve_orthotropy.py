"""Is the cell orthotropic under normal strains? Theirs against ours, two-pass and balanced
contact (issue 27).

The jersey loop is mirror symmetric about its wale, so a normal strain should cause no shear
stress. For each stitch value, along each of the paper group's biaxial rays to its last
converged state, the largest |S12| over the largest |S11|, |S22| (`paper.comparison.
shear_share`): theirs, ours with the default two-pass contact, ours with the balanced contact
(`ContactOptions(balance=True)`), over the rays that stretch both ways
(`paper.comparison.TENSION_RAYS`: the worst of the three) and over the others (the median and
the worst). The table goes into docs/validation.md ("Their cell is orthotropic in tension").

    .venv/bin/python benchmarks/paper_rve_orthotropy.py [--control-points 68]
        [--stitches 4.5,5.5,6.5]

About 40 s per stitch value at 68 control points on the shared 2-core machine (2026-11-28).
"""

import argparse

import numpy as np

from rve_rod.contact import ContactOptions
from rve_rod.presets import load_preset
from rve_rod.rve.cell import CellSettings
from rve_rod.rve.paper.comparison import TENSION_RAYS, axis_rays, compare_run, shear_share
from rve_rod.rve.paper.data import biaxial_rays
from rve_rod.rve.simulation import RveSettings


def shares(stitch: float, control_points: int) -> dict[str, tuple[list, list]]:
    """Per model, the shear shares along the tension rays and along the other rays."""
    tension = {ray.angle_deg for ray in axis_rays(stitch, TENSION_RAYS)}
    rays = [ray for ray in biaxial_rays(stitch) if ray.converged >= 2]
    fabric = load_preset("cotton-20s2", stitch)
    out = {"theirs": ([], [])}
    for ray in rays:
        out["theirs"][ray.angle_deg not in tension].append(
            shear_share(ray.second_piola[1 : ray.converged])
        )
    models = (("ours, two-pass (the default)", False), ("ours, balanced contact", True))
    for name, balance in models:
        contact = ContactOptions(balance=balance)
        settings = RveSettings(cell=CellSettings(control_points=control_points, contact=contact))
        out[name] = ([], [])
        for ray in rays:
            ours = compare_run(fabric, ray, settings)
            if ours.reached >= 2:
                out[name][ray.angle_deg not in tension].append(shear_share(ours.second_piola[1:]))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--control-points", type=int, default=CellSettings.control_points)
    parser.add_argument("--stitches", default="4.5,5.5,6.5")
    args = parser.parse_args()
    print("| stitch | model | tension rays: worst S12 share (%) | other rays: median / worst (%) |")
    print("|---:|---|---:|---|")
    for stitch in (float(s) for s in args.stitches.split(",")):
        for name, (tension, other) in shares(stitch, args.control_points).items():
            print(
                f"| {stitch:g} | {name} | {100 * max(tension):.2f} | "
                f"{100 * np.median(other):.2f} / {100 * max(other):.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
