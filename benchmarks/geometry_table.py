"""Loop geometry against the reference loop lengths, its sensitivity to the shoulder's aspect
ratio (a model constant), and build time: the tables of docs/geometry.md.

Run: .venv/bin/python benchmarks/geometry_table.py
"""

import time
from unittest import mock

from rve_rod.geometry import loop
from rve_rod.presets import load_preset, stitch_values

FABRICS = [("vassiliadis-sample2", None)] + [
    ("cotton-20s2", stitch) for stitch in stitch_values("cotton-20s2")
]
ASPECTS = (1.0, 1.2, 1.3, 1.4)
"""Values of loop.SHOULDER_ASPECT for the sensitivity table (1.0: a circular shoulder)."""


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
    for preset, stitch in FABRICS:
        fabric = load_preset(preset, stitch)
        geometry, seconds = build(fabric)
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
    print("| fabric | " + " | ".join(f"a/rho = {aspect:g}" for aspect in ASPECTS) + " |")
    print("|---" * (len(ASPECTS) + 1) + "|")
    for key in FABRICS:
        fabric = load_preset(*key)
        cells = []
        for aspect in ASPECTS:
            with mock.patch.object(loop, "SHOULDER_ASPECT", aspect):
                other, _ = build(fabric)
            error = 100 * (other.loop_length / fabric.knit.measured_loop_length - 1)
            cells.append(
                f"{error:+.1f} % (rho = {other.shape_parameter / other.yarn_radius:.2f} r)"
            )
        print(f"| {name(*key)} | " + " | ".join(cells) + " |")
    loop.single_jersey_loop.cache_clear()


if __name__ == "__main__":
    main()
