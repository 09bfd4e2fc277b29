"""Accuracy and time of `measure_photo` on synthetic photos with known w, c and angle.

Run: .venv/bin/python benchmarks/imaging_accuracy.py [--random N] [--timing] (prints the
markdown tables of docs/imaging.md; with --timing only the time table of docs/benchmarks.md).
Photos are 512 x 512 px at 25 px/mm unless a condition says otherwise; they show the loop of
`rve_rod.geometry.loop` for each fabric's w, c and r0 (the yarn drawn with r = min(r0, w/8)).
"""

import argparse
import time

import numpy as np

from rve_rod.errors import InputError
from rve_rod.imaging.measure import measure_photo
from rve_rod.imaging.synthetic import SyntheticPhoto, render_photo
from rve_rod.presets import load_preset, stitch_values

CONDITIONS = {
    "clean": {},
    "typical": {"angle_deg": 15.0, "blur_mm": 0.04, "noise": 0.1, "lighting": 0.4},
    "harsh": {
        "angle_deg": -12.0,
        "blur_mm": 0.1,
        "noise": 0.3,
        "lighting": 0.6,
        "side": "back",
    },
    "low-res": {
        "angle_deg": 7.0,
        "blur_mm": 0.05,
        "noise": 0.15,
        "pixels_per_mm": 10.0,
        "width_px": 256,
        "height_px": 256,
    },
}


def fabrics():
    named = [(f"cotton {s}", load_preset("cotton-20s2", s)) for s in stitch_values("cotton-20s2")]
    named.append(("Vassiliadis 2", load_preset("vassiliadis-sample2")))
    return [
        (name, f.knit.wale_width, f.knit.course_height, f.yarn.minimal_radius) for name, f in named
    ]


def grid_table() -> None:
    print(
        "| fabric | w mm | c mm | photo | err w % | err c % | err angle deg | u(w) % | u(c) % | s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    worst = {}
    for index, (name, w, c, r) in enumerate(fabrics()):
        for label, condition in CONDITIONS.items():
            photo = SyntheticPhoto(w, c, r, seed=index, **condition)
            image = render_photo(photo)
            start = time.perf_counter()
            estimate = measure_photo(image, photo.pixels_per_mm)
            seconds = time.perf_counter() - start
            errors = (
                100 * (estimate.wale_width / w - 1),
                100 * (estimate.course_height / c - 1),
                estimate.angle_deg - photo.angle_deg,
            )
            worst[label] = np.maximum(worst.get(label, 0.0), np.abs(errors))
            print(
                f"| {name} | {w:g} | {c:g} | {label} | {errors[0]:+.3f} | {errors[1]:+.3f} | "
                f"{errors[2]:+.3f} | {100 * estimate.wale_width_uncertainty / w:.3f} | "
                f"{100 * estimate.course_height_uncertainty / c:.3f} | {seconds:.2f} |"
            )
    print()
    print("| photo | max err w % | max err c % | max err angle deg |")
    print("|---|---|---|---|")
    for label, values in worst.items():
        print(f"| {label} | {values[0]:.3f} | {values[1]:.3f} | {values[2]:.3f} |")


def few_loops_table() -> None:
    print("| loops across | cotton 5.5 | Vassiliadis 2 |")
    print("|---|---|---|")
    for loops in (2.0, 2.6, 2.9, 3.2, 3.5, 4.0, 5.0):
        cells = []
        for w, c, r, scale in ((1.33, 1.26, 0.19, 30.0), (0.833, 0.486, 0.0923, 50.0)):
            outcomes = []
            for angle in (0.0, 8.0, 15.0):
                photo = SyntheticPhoto(
                    w,
                    c,
                    r,
                    pixels_per_mm=scale,
                    angle_deg=angle,
                    noise=0.1,
                    blur_mm=0.03,
                    width_px=int(loops * w * scale),
                    height_px=int(loops * c * scale),
                )
                try:
                    estimate = measure_photo(render_photo(photo), scale)
                except InputError:
                    outcomes.append("refused")
                    continue
                error = max(abs(estimate.wale_width / w - 1), abs(estimate.course_height / c - 1))
                outcomes.append(f"{100 * error:.2f} %")
            cells.append(", ".join(outcomes))
        print(f"| {loops:g} | {cells[0]} | {cells[1]} |")


def random_photos(count: int, loops_range: tuple[float, float]) -> None:
    rng = np.random.default_rng(2024)
    errors, refused, unfit, z, wrong = [], 0, 0, [], []
    for seed in range(count):
        w = rng.uniform(0.8, 1.5)
        c = w * rng.uniform(0.55, 1.3)
        r = rng.uniform(0.09, 0.19)
        scale = rng.uniform(8, 40)
        loops = rng.uniform(*loops_range)
        size = max(int(loops * max(w, c) * scale), 40)
        photo = SyntheticPhoto(
            w,
            c,
            r,
            pixels_per_mm=scale,
            height_px=size,
            width_px=int(size * rng.uniform(0.7, 1.3)),
            angle_deg=rng.uniform(-15, 15),
            blur_mm=rng.uniform(0, 0.15),
            noise=rng.uniform(0, 0.4),
            lighting=rng.uniform(0, 0.6),
            side=str(rng.choice(["face", "back"])),
            seed=seed,
        )
        try:
            image = render_photo(photo)
        except InputError:  # no loop of the model fits w, c and r0
            unfit += 1
            continue
        try:
            estimate = measure_photo(image, scale)
        except InputError:
            refused += 1
            continue
        error = np.array([estimate.wale_width / w - 1, estimate.course_height / c - 1])
        errors.append(np.abs(error).max())
        if errors[-1] > 0.02:
            wrong.append(seed)
        uncertainty = np.array(
            [estimate.wale_width_uncertainty / w, estimate.course_height_uncertainty / c]
        )
        z.extend(np.abs(error) / uncertainty)
    errors, z = np.array(errors), np.array(z)
    if errors.size == 0:
        print(f"{count} random photos of {loops_range} loops: all refused")
        return
    print(
        f"{count} random photos of {loops_range[0]:g}-{loops_range[1]:g} loops (along the "
        f"longer period): {unfit} without a loop that fits; {refused} refused (InputError); "
        f"{np.count_nonzero(errors <= 0.02)} measured within 2 %, "
        f"{np.count_nonzero(errors > 0.02)} accepted but wrong by more than 2 % "
        f"(seeds {wrong}); "
        f"of the {errors.size} measured, max error {100 * errors.max():.2f} %, "
        f"median {100 * np.median(errors):.3f} %; |error| / uncertainty: median "
        f"{np.median(z):.2f}, {100 * np.mean(z < 2):.0f} % below 2"
    )


def timing_table(repeats: int = 3) -> None:
    print("| photo px | loops across | render s | measure s | tiles |")
    print("|---|---|---|---|---|")
    for size in (256, 512, 1024, 2048):
        photo = SyntheticPhoto(
            1.33,
            1.26,
            0.19,
            pixels_per_mm=25.0 * size / 512,
            width_px=size,
            height_px=size,
            angle_deg=15.0,
            blur_mm=0.04,
            noise=0.1,
            lighting=0.4,
        )
        photo.loop()  # the loop is built once per process, not part of the render time
        start = time.perf_counter()
        image = render_photo(photo)
        render = time.perf_counter() - start
        seconds = []
        for _ in range(repeats):
            start = time.perf_counter()
            estimate = measure_photo(image, photo.pixels_per_mm)
            seconds.append(time.perf_counter() - start)
        print(
            f"| {size} | {estimate.wales_in_image:.0f} | {render:.2f} | {min(seconds):.2f} | "
            f"{estimate.tiles_used} |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--random", type=int, default=200, help="number of random photos")
    parser.add_argument("--timing", action="store_true", help="only the time table")
    args = parser.parse_args()
    if args.timing:
        timing_table()
        return
    grid_table()
    print()
    few_loops_table()
    print()
    random_photos(args.random, (3.5, 20.0))
    random_photos(args.random, (1.5, 3.2))


if __name__ == "__main__":
    main()
