"""Cost of one contact evaluation at the knit-cell size, and what the broad phase saves.

Scene: the loop of cotton 20s/2 at stitch 5.5 (rve_rod.geometry.loop: w = 1.33 mm, c = 1.26 mm,
r0 = 0.19 mm, r = w/8 = 0.166 mm; tests/support/contact_scenes.py knit_loop) as 4 patches of
degree 4 with 68 control points (272 collocation points), the compressible-yarn law of that yarn
with E0 = 80 MPa, Coulomb friction mu = 0.15, periodic images as needed. The loop and its images
are mapped affinely by the macro F (a load step's first guess): at F = I the yarns only touch; a
5 % compression and a 0.1 shear press them together. Prints

1. time per evaluation: search and loads only, and loads plus both derivatives (residual +
   tangent), without and with friction, at F = I, compressed and sheared;
2. the broad phase: box pairs, narrow-phase span tests and all (point, span, image) pairs
   for several spans per box (compressed);
3. the cost against the number of control points per patch (compressed);
4. the two-pass imbalance: the cell's net contact force over the sum of the contact force
   magnitudes against the number of control points;
5. the first-call numba compile time in a fresh process with an empty cache.

    .venv/bin/python benchmarks/bench_contact.py [--repeats 30] [--skip-compile]
"""

import argparse
import functools
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from rve_rod.contact import (
    CompressibleYarnLaw,
    ContactModel,
    ContactOptions,
    CoulombFriction,
)
from rve_rod.geometry.loop import loop_geometry
from rve_rod.presets import load_preset

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.contact_scenes import knit_loop  # the tests' scenes

FABRIC = load_preset("cotton-20s2", 5.5)
LOOP = loop_geometry(FABRIC.knit, FABRIC.yarn.minimal_radius)
LAW = CompressibleYarnLaw.from_yarn(
    minimal_radius=FABRIC.yarn.minimal_radius, yarn_radius=LOOP.yarn_radius, youngs_modulus=80.0
)
FRICTION = CoulombFriction.for_law(LAW, coefficient=0.15)
COMPRESSION = np.diag([0.95, 0.95, 1.0])
SHEAR = np.array([[1.0, 0.1, 0.0], [0.1, 1.0, 0.0], [0.0, 0.0, 1.0]])
STATES = (("I", np.eye(3)), ("compr.", COMPRESSION), ("shear", SHEAR))
REFINEMENTS = (12, 20, 36, 68, 132, 260)


def best_time(function, repeats):
    """Minimum and median wall time of `function` over `repeats` calls (after one warm-up)."""
    function()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times), float(np.median(times))


def model_for(control_points=68, friction=FRICTION, spans_per_box=8):
    """The contact model of the loop with `control_points` per patch, and its reference
    control points (n, 3)."""
    scene = knit_loop(LOOP, control_points)
    model = ContactModel(
        scene.patches,
        scene.positions,
        LAW,
        friction=friction,
        lattice=scene.lattice,
        options=ContactOptions(spans_per_box=spans_per_box),
    )
    return model, scene.positions


def evaluation_table(repeats):
    print("\n1. Time per contact evaluation, knit cell 4 x 68 control points, p = 4")
    print(
        f"{'friction':>9} {'F':>6} {'contacts':>9} {'images':>7} "
        f"{'loads (ms)':>17} {'loads+tangent (ms)':>19}"
    )
    print(f"{'':>9} {'':>6} {'':>9} {'':>7} {'min':>8} {'median':>8} {'min':>9} {'median':>9}")
    for friction in (None, FRICTION):
        model, reference = model_for(friction=friction)
        for name, deformation in STATES:
            positions = reference @ deformation.T
            result = model.evaluate(positions, deformation)
            evaluate = functools.partial(model.evaluate, positions, deformation)
            loads = best_time(functools.partial(evaluate, tangent=False), repeats)
            full = best_time(evaluate, repeats)
            stats = result.statistics
            label = "mu=0.15" if friction else "none"
            print(
                f"{label:>9} {name:>6} {stats.active_contacts:>9} {stats.images:>7} "
                f"{1e3 * loads[0]:>8.2f} {1e3 * loads[1]:>8.2f} "
                f"{1e3 * full[0]:>9.2f} {1e3 * full[1]:>9.2f}"
            )


def broad_phase_table(repeats):
    print("\n2. Broad phase at the knit-cell size (compressed, with friction)")
    print(
        f"{'spans/box':>9} {'box pairs':>10} {'span tests':>11} {'all pairs':>10} "
        f"{'tested %':>9} {'min (ms)':>9}"
    )
    for spans_per_box in (1, 2, 4, 8, 16, 32):
        model, reference = model_for(spans_per_box=spans_per_box)
        evaluate = functools.partial(model.evaluate, reference @ COMPRESSION.T, COMPRESSION)
        stats = evaluate().statistics
        best, _ = best_time(evaluate, repeats)
        print(
            f"{spans_per_box:>9} {stats.box_pairs:>10} {stats.span_tests:>11} "
            f"{stats.all_pairs:>10} {100 * stats.span_tests / stats.all_pairs:>9.2f} "
            f"{1e3 * best:>9.2f}"
        )


def refinement_table(repeats):
    print("\n3. Cost against control points per patch (compressed, with friction, loads + tangent)")
    print(f"{'points':>7} {'collocation':>12} {'contacts':>9} {'span tests':>11} {'min (ms)':>9}")
    for control_points in REFINEMENTS:
        model, reference = model_for(control_points=control_points)
        evaluate = functools.partial(model.evaluate, reference @ COMPRESSION.T, COMPRESSION)
        stats = evaluate().statistics
        best, _ = best_time(evaluate, max(5, repeats // 3))
        print(
            f"{control_points:>7} {model.n_collocation_points:>12} {stats.active_contacts:>9} "
            f"{stats.span_tests:>11} {1e3 * best:>9.2f}"
        )


def imbalance_table():
    print("\n4. Two-pass imbalance: |sum of the cell's contact forces| / sum of their magnitudes")
    print(f"{'points':>7} " + " ".join(f"{name:>8}" for name, _ in STATES[1:]) + "  (z only)")
    for control_points in REFINEMENTS:
        model, reference = model_for(control_points=control_points, friction=None)
        ratios = []
        for _, deformation in STATES[1:]:
            result = model.evaluate(reference @ deformation.T, deformation, tangent=False)
            forces = result.line_load * model.collocation_weights
            ratios.append(np.linalg.norm(forces.sum(axis=1)) / np.linalg.norm(forces, axis=0).sum())
        print(f"{control_points:>7} " + " ".join(f"{100 * ratio:>7.2f}%" for ratio in ratios))


COMPILE_SNIPPET = """
import time
start = time.perf_counter()
from benchmarks.bench_contact import model_for  # builds the loop
loaded = time.perf_counter()
model, positions = model_for()
model.evaluate(positions)
print(loaded - start, time.perf_counter() - loaded)
"""


def compile_time():
    print("\n5. Fresh process: imports and the loop; then the model and its first evaluation")
    print(f"{'numba cache':>12} {'loop (s)':>9} {'first evaluation (s)':>21}")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with tempfile.TemporaryDirectory() as cache:
        environment = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=root)
        for label in ("empty cache", "warm cache"):
            output = subprocess.run(
                [sys.executable, "-c", COMPILE_SNIPPET],
                env=environment,
                capture_output=True,
                text=True,
                check=True,
                cwd=root,
            )
            loop, first = (float(value) for value in output.stdout.split())
            print(f"{label:>12} {loop:>9.2f} {first:>21.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("--skip-compile", action="store_true")
    args = parser.parse_args()
    print(
        f"law: k = {LAW.stiffness:.3f} MPa, p = {LAW.exponent:.3f}, r = {LAW.yarn_radius} mm; "
        f"friction mu = {FRICTION.coefficient}, k_t = {FRICTION.tangential_stiffness:.3f} MPa"
    )
    evaluation_table(args.repeats)
    broad_phase_table(args.repeats)
    refinement_table(args.repeats)
    imbalance_table()
    if not args.skip_compile:
        compile_time()


if __name__ == "__main__":
    main()
