"""The relaxed jersey cell against the six measured cotton 20s/2 fabrics and Munden's
constants (issue 28, item 3): a table for docs/patterns.md.

For each stitch value of the preset: the measured loop length l, w and c, the relaxed w and c
from l alone (`rve_rod.geometry.relaxed`), their differences, and l/w, l/c of both (Munden's
dry-relaxed plain knit: l/c about 5.0-5.5, l/w about 3.8-4.2).

    .venv/bin/python benchmarks/relaxed_jersey.py

About 2 minutes on a quiet core (the relaxed cells are cached afterwards).
"""

from rve_rod.geometry.relaxed import cached_relaxed_knit
from rve_rod.presets import load_preset, stitch_values


def main() -> None:
    print(
        "| stitch | l (mm) | w measured | w relaxed | diff | c measured | c relaxed | diff | "
        "l/w measured | relaxed | l/c measured | relaxed | r/r0 |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for stitch in stitch_values("cotton-20s2"):
        fabric = load_preset("cotton-20s2", stitch)
        knit, r0 = fabric.knit, fabric.yarn.minimal_radius
        length = knit.measured_loop_length
        relaxed = cached_relaxed_knit("jersey", length, r0)
        w, c = relaxed.wale_width, relaxed.course_height
        print(
            f"| {stitch:g} | {length:.2f} | {knit.wale_width:.3f} | {w:.3f} | "
            f"{100 * (w / knit.wale_width - 1):+.1f} % | {knit.course_height:.3f} | {c:.3f} | "
            f"{100 * (c / knit.course_height - 1):+.1f} % | {length / knit.wale_width:.2f} | "
            f"{length / w:.2f} | {length / knit.course_height:.2f} | {length / c:.2f} | "
            f"{relaxed.yarn_radius / r0:.3f} |"
        )


if __name__ == "__main__":
    main()
