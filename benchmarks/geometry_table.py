"""Loop geometry against the reference loop lengths, its sensitivity to the shoulder radius, and
build time: the tables of docs/geometry.md.

Run: .venv/bin/python benchmarks/geometry_table.py
"""

import time

from rve_rod.geometry import loop
from rve_rod.presets import load_preset, stitch_values

FABRICS = [("vassiliadis-sample2", None)] + [
    ("cotton-20s2", stitch) for stitch in stitch_values("cotton-20s2")
]
SHOULDER_OFFSETS = (-0.2, -0.1, 0.1, 0.2)
"""Shoulder radii around the optimum, rho* + offset r, for the sensitivity table."""


def build(fabric, shoulder_radius=None):
    loop.single_jersey_loop.cache_clear()
    start = time.perf_counter()
    geometry = loop.single_jersey_loop(
        fabric.knit.wale_width,
        fabric.knit.course_height,
        fabric.yarn.minimal_radius,
        shoulder_radius,
    )
    return geometry, time.perf_counter() - start


def name(preset, stitch):
    return preset + (f" {stitch}" if stitch else "")


def main():
    print(
        "| fabric | w | c | r | measured l | model l | error | Peirce | error | rho/r "
        "| d/r | clearance/2r | build (s) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    optima = {}
    for preset, stitch in FABRICS:
        fabric = load_preset(preset, stitch)
        geometry, seconds = build(fabric)
        optima[preset, stitch] = geometry
        w, c, r = geometry.wale_width, geometry.course_height, geometry.yarn_radius
        measured = fabric.knit.measured_loop_length
        peirce = 2 * c + w + 5.94 * 2 * r
        print(
            f"| {name(preset, stitch)} | {w:.3f} | {c:.3f} | {r:.4f} | {measured:.2f} | "
            f"{geometry.loop_length:.3f} | {100 * (geometry.loop_length / measured - 1):+.2f} % | "
            f"{peirce:.3f} | {100 * (peirce / measured - 1):+.1f} % | "
            f"{geometry.shape_parameter / r:.3f} | {geometry.depth / r:.3f} | "
            f"{geometry.min_clearance / (2 * r):.7f} | {seconds:.2f} |"
        )
    print()
    print("| fabric | " + " | ".join(f"rho* {offset:+.1f} r" for offset in SHOULDER_OFFSETS) + " |")
    print("|---" * (len(SHOULDER_OFFSETS) + 1) + "|")
    for key, best in optima.items():
        r = best.yarn_radius
        changes = []
        for offset in SHOULDER_OFFSETS:
            other, _ = build(load_preset(*key), best.shape_parameter + offset * r)
            change = 100 * (other.loop_length / best.loop_length - 1)
            changes.append(f"{change:+.2f} % (d = {other.depth / r:.2f} r)")
        print(f"| {name(*key)} | " + " | ".join(changes) + " |")


if __name__ == "__main__":
    main()
