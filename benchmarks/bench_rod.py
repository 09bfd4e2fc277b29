"""Cost of the rod engine versus the number of control points (one core), and numba compile time.

For a single helical patch of degree 4 with n = 64 ... 1024 control points (7 n unknowns) and
for the knit-cell size (4 joined patches of 68 control points) it prints the time per
residual, per residual + Jacobian, per sparse LU solve, and per Newton iteration (Jacobian +
LU solve), and fits the growth exponent b of time ~ n^b. It then measures the first-call
compile time of the numba kernels in a fresh process with an empty cache, and the load time
with a warm cache.

    .venv/bin/python benchmarks/bench_rod.py [--repeats 5] [--skip-compile]
"""

import argparse
import itertools
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

from rve_rod.geometry.bspline import BSplineCurve, basis_matrix, open_knot_vector
from rve_rod.rod import (
    END,
    START,
    Clamp,
    EndLoad,
    Joint,
    RodEnd,
    RodModel,
    RodPatch,
    SectionStiffness,
)

SECTION = SectionStiffness.circular(0.19, 80.0, rotational_modulus=40.0)


def helix_piece(n, start=0.0, stop=1.0, degree=4):
    """A helix piece (R = 1 mm, pitch 2 mm, 2 turns in total) interpolated at Greville points."""
    knots = open_knot_vector(degree, n)
    greville = BSplineCurve(degree, knots, np.zeros((n, 3))).greville()
    t = 4 * np.pi * (start + (stop - start) * greville)
    points = np.stack([np.cos(t), np.sin(t), t / np.pi], axis=1)
    controls = np.linalg.solve(basis_matrix(knots, degree, greville).toarray(), points)
    return BSplineCurve(degree, knots, controls)


def chain_model(points_per_patch, patches=1):
    bounds = np.linspace(0, 1, patches + 1)
    curves = [helix_piece(points_per_patch, a, b) for a, b in itertools.pairwise(bounds)]
    conditions = [Clamp(RodEnd(0, START))]
    conditions += [Joint(RodEnd(k, END), RodEnd(k + 1, START)) for k in range(patches - 1)]
    conditions += [EndLoad(RodEnd(patches - 1, END), force=[0.0, 0.0, 0.01])]
    return RodModel(RodPatch.chain(curves, SECTION), conditions)


def best_time(function, repeats):
    """Smallest mean wall time (s) over `repeats` batches of calls lasting >= 0.05 s each."""
    calls = 1
    while True:
        start = time.perf_counter()
        for _ in range(calls):
            function()
        elapsed = time.perf_counter() - start
        if elapsed > 0.05:
            break
        calls *= 2
    best = elapsed / calls
    for _ in range(repeats - 1):
        start = time.perf_counter()
        for _ in range(calls):
            function()
        best = min(best, (time.perf_counter() - start) / calls)
    return best


def measure(model, repeats):
    rng = np.random.default_rng(0)
    state = model.reference_state() + 1e-3 * rng.normal(size=model.n_dofs)
    jacobian = scipy.sparse.csc_matrix(model.evaluate(state).jacobian)
    residual = model.residual(state)

    def solve():
        scipy.sparse.linalg.splu(jacobian).solve(-residual)

    def iteration():
        evaluation = model.evaluate(state)
        lu = scipy.sparse.linalg.splu(scipy.sparse.csc_matrix(evaluation.jacobian))
        lu.solve(-evaluation.residual)

    return {
        "residual": best_time(lambda: model.evaluate(state, with_jacobian=False), repeats),
        "jacobian": best_time(lambda: model.evaluate(state), repeats),
        "solve": best_time(solve, repeats),
        "iteration": best_time(iteration, repeats),
        "nnz": jacobian.nnz,
    }


COMPILE_SNIPPET = """
import time
start = time.perf_counter()
import sys
sys.path.insert(0, {path!r})
from bench_rod import chain_model
chain_model(8)
print(time.perf_counter() - start)
"""


def compile_time(cache_dir):
    """Seconds to import the package and build a small model (which runs every kernel once)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    code = COMPILE_SNIPPET.format(path=os.path.dirname(os.path.abspath(__file__)))
    output = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return float(output.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--skip-compile", action="store_true")
    args = parser.parse_args()
    chain_model(8)  # compile or load the kernels before timing
    counts = [64, 128, 256, 512, 1024]
    rows = []
    header = (
        f"{'case':>12} {'unknowns':>9} {'nnz':>8} {'residual':>10} {'res+jac':>10} "
        f"{'LU solve':>10} {'iteration':>10}   (ms)"
    )
    print(header)
    for n in counts:
        timing = measure(chain_model(n), args.repeats)
        rows.append(timing)
        print(
            f"{'n=' + str(n):>12} {7 * n:>9} {timing['nnz']:>8} {1e3 * timing['residual']:>10.3f} "
            f"{1e3 * timing['jacobian']:>10.3f} {1e3 * timing['solve']:>10.3f} "
            f"{1e3 * timing['iteration']:>10.3f}"
        )
    knit = measure(chain_model(68, patches=4), args.repeats)
    print(
        f"{'knit 4x68':>12} {7 * 272:>9} {knit['nnz']:>8} {1e3 * knit['residual']:>10.3f} "
        f"{1e3 * knit['jacobian']:>10.3f} {1e3 * knit['solve']:>10.3f} "
        f"{1e3 * knit['iteration']:>10.3f}"
    )
    print("\ngrowth exponent b of time ~ n^b (least squares; small n carry fixed overheads):")
    for key in ("residual", "jacobian", "solve", "iteration"):
        times = np.log([row[key] for row in rows])
        every = np.polyfit(np.log(counts), times, 1)[0]
        large = np.polyfit(np.log(counts[-3:]), times[-3:], 1)[0]
        print(f"  {key:>10}: b = {every:.2f} (n = 64 ... 1024), {large:.2f} (n = 256 ... 1024)")
    if not args.skip_compile:
        with tempfile.TemporaryDirectory() as cache:
            cold = compile_time(cache)
            warm = compile_time(cache)
        print(f"\nimport + first model, empty numba cache (compiles the kernels): {cold:.2f} s")
        print(f"import + first model, warm numba cache:                         {warm:.2f} s")


if __name__ == "__main__":
    main()
