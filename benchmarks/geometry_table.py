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


def build(fabric):
    loop.single_jersey_loop.cache_clear()
    start = time.perf_counter()
    geometry = loop.loop_geometry(fabric.knit, fabric.yarn.minimal_radius)
    return geometry, time.perf_counter() - start


def main():
    print(
        "| fabric | w | c | r | measured l | model l | error | Peirce | error | (h - c/2)/r "
        "| delta/r | clearance/2r | build (s) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for preset, stitch in FABRICS:
        fabric = load_preset(preset, stitch)
        geometry, seconds = build(fabric)
        w, c, r = geometry.wale_width, geometry.course_height, geometry.yarn_radius
        measured = fabric.knit.measured_loop_length
        peirce = 2 * c + w + 5.94 * 2 * r
        name = preset + (f" {stitch}" if stitch else "")
        print(
            f"| {name} | {w:.3f} | {c:.3f} | {r:.4f} | {measured:.2f} | "
            f"{geometry.loop_length:.3f} | {100 * (geometry.loop_length / measured - 1):+.1f} % | "
            f"{peirce:.3f} | {100 * (peirce / measured - 1):+.1f} % | "
            f"{(geometry.shape_parameter - c / 2) / r:.3f} | {geometry.depth / r:.3f} | "
            f"{geometry.min_clearance / (2 * r):.5f} | {seconds:.2f} |"
        )
    print()
    print(
        "| shoulder radius / r | "
        + " | ".join(preset + (f" {stitch}" if stitch else "") for preset, stitch in FABRICS)
        + " |"
    )
    print("|---" * (len(FABRICS) + 1) + "|")
    default = loop.SHOULDER_RADIUS_FACTOR
    lengths = {}
    try:
        for factor in (1.15, 1.25, 1.35):
            loop.SHOULDER_RADIUS_FACTOR = factor
            lengths[factor] = [build(load_preset(*key))[0].loop_length for key in FABRICS]
    finally:
        loop.SHOULDER_RADIUS_FACTOR = default
        loop.single_jersey_loop.cache_clear()
    for factor, values in lengths.items():
        changes = [
            f"{value:.3f} ({100 * (value / base - 1):+.2f} %)"
            for value, base in zip(values, lengths[default], strict=True)
        ]
        print(f"| {factor} | " + " | ".join(changes) + " |")


if __name__ == "__main__":
    main()
