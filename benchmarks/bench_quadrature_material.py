"""The material at the quadrature points (issue 29): FFCx compilation, assembly per Newton
iteration and `make demo`, for the code of a tree (this one, or another commit's copy).

Sections (all by default, or pick with --section):

  compile   a patch in tension (`TensionSetup`, the demo's macro part: 50 mm, 10 x 10 Q1) with
            the shipped surface, built in a fresh process with an empty FFCx cache
            (XDG_CACHE_HOME): seconds to build it (almost all FFCx) and modules compiled;
            then in the same cache a part with another surface (the coefficients scaled),
            and a graded region over `--members` scaled surfaces: the seconds and the
            modules each adds.
  assembly  per Newton iteration, warm: the residual assembly (with the material's NumPy
            update where the tree has one) and the Jacobian assembly, best of 7, at 10 x 10,
            40 x 40 and 100 x 100 Q1 at 10 % course-wise strain.
  demo      `knitmech run -o DIR` (= `make demo`) in a fresh copy of the tree with empty
            XDG_CACHE_HOME and NUMBA_CACHE_DIR: the command's stage times and the FFCx
            modules in the cache afterwards.

    python benchmarks/bench_quadrature_material.py [--section compile|assembly|demo]
        [--commit REV] [--members 6]

--commit REV runs the code of `git archive REV` (e.g. the commit before issue 29's change, to
measure "before"); default: this working tree. Timings on a shared machine are noisy: the
load average is printed; repeat and take the minimum.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import timeit
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SURFACE = ROOT / "knitmech" / "data" / "cotton-20s2_stitch-5.5.h5"
ENV = {
    **os.environ,
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
    "MPLBACKEND": "Agg",
}


def scaled(surface, factor):
    """The surface with every stress coefficient times `factor` (a different surface of the
    same structure)."""
    groups = {
        name: replace(spline, coefficients=factor * spline.coefficients)
        for name, spline in (("s11", surface.s11), ("s22", surface.s22), ("s12", surface.s12))
    }
    return replace(surface, **groups)


def child_build(kind, members):
    """In a fresh process: build one part and print the seconds it took."""
    from fabric_dolfinx.material import surface_material  # noqa: PLC0415
    from fabric_dolfinx.part.regions import Region  # noqa: PLC0415
    from fabric_dolfinx.part.tension import TensionSetup  # noqa: PLC0415
    from fabric_dolfinx.solve import SolverOptions  # noqa: PLC0415
    from fabric_dolfinx.spec.tension import TensionTest  # noqa: PLC0415
    from rve_rod.surface import read_surface  # noqa: PLC0415

    surface = read_surface(SURFACE)
    test, options = TensionTest(max_strain=0.1), SolverOptions(steps=2)
    start = time.perf_counter()
    if kind == "first":
        TensionSetup(surface_material(surface), test, options)
    elif kind == "other":
        TensionSetup(surface_material(scaled(surface, 1.3)), test, options)
    else:
        from fabric_dolfinx.mesh.shapes import make_mesh  # noqa: PLC0415
        from fabric_dolfinx.part.problem import PartProblem  # noqa: PLC0415
        from fabric_dolfinx.spec.expression import FieldExpression  # noqa: PLC0415
        from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec  # noqa: PLC0415

        family = tuple(
            (4.5 + 0.5 * k, surface_material(scaled(surface, 1.0 + 0.1 * k)))
            for k in range(members)
        )
        stitch = FieldExpression(f"4.5 + {0.5 * (members - 1)} * x / 50")
        PartProblem(
            make_mesh(MeshSpec("rectangle", {"width": 50.0, "height": 50.0}, element_size=5.0)),
            [Region("fabric", None, stitch=stitch, family=family)],
            [BoundaryCondition("left"), BoundaryCondition("right", "displacement", (5.0, 0.0))],
            options=options,
        )
    print(f"seconds {time.perf_counter() - start:.3f}")


def child_assembly(elements):
    """In a fresh process: warm per-iteration assembly times at 10 % strain (JSON line)."""
    import dolfinx.fem.petsc  # noqa: PLC0415

    from fabric_dolfinx.material import surface_material  # noqa: PLC0415
    from fabric_dolfinx.part.tension import TensionSetup  # noqa: PLC0415
    from fabric_dolfinx.solve import SolverOptions  # noqa: PLC0415
    from fabric_dolfinx.spec.tension import TensionTest  # noqa: PLC0415
    from rve_rod.surface import read_surface  # noqa: PLC0415

    material = surface_material(read_surface(SURFACE))
    setup = TensionSetup(
        material, TensionTest(elements=elements, max_strain=0.1), SolverOptions(steps=2)
    )
    result = setup.run()
    stepper = setup.stepper

    def jacobian():
        stepper._matrix.zeroEntries()
        dolfinx.fem.petsc.assemble_matrix(stepper._matrix, stepper._jacobian_form, bcs=stepper.bcs)
        stepper._matrix.assemble()

    def best(function):
        return min(timeit.repeat(function, repeat=7, number=1))

    update = getattr(getattr(setup.problem, "material", None), "update", None)
    record = {
        "elements": elements,
        "residual_s": best(stepper._assemble_residual),
        "jacobian_s": best(jacobian),
        "update_s": best(update) if update is not None else None,
        "newton": int(result.newton_iterations.sum()),
        "force": float(result.force_n_per_mm[-1]),
    }
    print(json.dumps(record))


def run_child(tree, cache, *arguments):
    """Run this script's child mode with the code of `tree` and the FFCx cache `cache`."""
    env = {**ENV, "XDG_CACHE_HOME": str(cache), "PYTHONPATH": str(tree)}
    command = [sys.executable, __file__, "--child", *arguments]
    output = subprocess.run(command, check=True, capture_output=True, text=True, env=env)
    return output.stdout.strip().splitlines()[-1]


def modules(cache):
    return len(list(Path(cache).rglob("libffcx_*.c.cached")))


def compile_section(tree, members):
    print("\n## compile: cold FFCx cache, then further parts in the same cache")
    print("| part | seconds | FFCx modules added |")
    print("|---|---:|---:|")
    with tempfile.TemporaryDirectory() as cache:
        count = 0
        for kind, label in (
            ("first", "patch, shipped surface (empty cache)"),
            ("other", "patch, another surface"),
            ("graded", f"graded region, {members} other surfaces"),
        ):
            seconds = float(run_child(tree, cache, "build", kind, str(members)).split()[-1])
            added, count = modules(cache) - count, modules(cache)
            print(f"| {label} | {seconds:.1f} | {added} |")


def assembly_section(tree):
    print("\n## assembly per Newton iteration (warm, best of 7; s)")
    print("| elements | residual (with update) | update alone | Jacobian | Newton | force |")
    print("|---|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as cache:
        for elements in (10, 40, 100):
            r = json.loads(run_child(tree, cache, "assembly", str(elements)))
            update = "-" if r["update_s"] is None else f"{r['update_s']:.5f}"
            print(
                f"| {elements} x {elements} | {r['residual_s']:.5f} | {update} | "
                f"{r['jacobian_s']:.5f} | {r['newton']} | {r['force']:.10f} |"
            )


def demo_section(tree):
    print("\n## make demo cold (knitmech run -o DIR, fresh copy, empty caches)")
    with tempfile.TemporaryDirectory() as scratch:
        cache, numba = Path(scratch) / "cache", Path(scratch) / "numba"
        env = {**ENV, "XDG_CACHE_HOME": str(cache), "NUMBA_CACHE_DIR": str(numba)}
        env["PYTHONPATH"] = str(tree)
        knitmech = Path(sys.executable).parent / "knitmech"
        command = [str(knitmech), "run", "-o", str(Path(scratch) / "out")]
        start = time.perf_counter()
        output = subprocess.run(
            command, check=True, capture_output=True, text=True, env=env, cwd=tree
        )
        total = time.perf_counter() - start
        log = output.stdout + output.stderr
        stages = re.findall(r"INFO knitmech.stages.cache: (.+): computed in ([\d.]+) s", log)
        print(f"wall time {total:.1f} s; FFCx modules {modules(cache)}")
        for name, seconds in stages:
            print(f"  {name}: {float(seconds):.1f} s")


def archived(commit, scratch):
    """A copy of the tree at `commit` (git archive) in `scratch`."""
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", commit], check=True, capture_output=True
    ).stdout
    subprocess.run(["tar", "-x", "-C", str(scratch)], input=archive, check=True)
    return Path(scratch)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--section", choices=["compile", "assembly", "demo"])
    parser.add_argument("--commit", help="measure the code of this commit (git archive)")
    parser.add_argument("--members", type=int, default=6, help="graded family size")
    parser.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        if args.child[0] == "build":
            child_build(args.child[1], int(args.child[2]))
        else:
            child_assembly(int(args.child[1]))
        return
    with tempfile.TemporaryDirectory() as scratch:
        tree = archived(args.commit, scratch) if args.commit else ROOT
        revision = args.commit or "working tree"
        print(f"# bench_quadrature_material: {revision}, load {os.getloadavg()}")
        sections = {
            "compile": lambda: compile_section(tree, args.members),
            "assembly": lambda: assembly_section(tree),
            "demo": lambda: demo_section(tree),
        }
        for name, section in sections.items():
            if args.section in (None, name):
                section()


if __name__ == "__main__":
    main()
