"""Re-make the docs' figures and printed table of the default scene from the current code, in
one command (`make figures`).

Runs `knitmech run` on the built-in default scene at its level (balanced, what `make demo`
runs) with an empty cache (so that nothing comes from results of older code), then copies
its figures into docs/figures/ and writes its printed table into docs/pipeline.md between
the markers BEGIN and END. tests/test_knitmech/regression/test_documented_headline.py checks
that the numbers there (and the README's agreement figures) are what the code gives.

    .venv/bin/python scripts/docs_figures.py [--jobs N] [--cache-dir DIR] [--output DIR]

About a minute on 2 cores.
"""

import argparse
import logging
import shutil
import sys
import tempfile
from pathlib import Path

from knitmech.pipeline import run_scene
from knitmech.scene import load_scene
from rve_rod.limits import available_cores

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
FIGURES = {
    "figures/force_strain.png": "pipeline_force_strain.png",
    "figures/stress_course.png": "pipeline_stress_course.png",
    "figures/loop.png": "loop.png",
    "figures/surfaces.png": "surfaces_cotton.png",
}
"""Results-folder file -> docs/figures/ file."""
TABLE_DOC = DOCS / "pipeline.md"
BEGIN = "<!-- begin: the printed table of `knitmech run`, written by `make figures` -->"
END = "<!-- end: the printed table -->"


def replace_table(text: str, table: str) -> str:
    """`text` with the block between BEGIN and END replaced by `table` (fenced)."""
    head, found, rest = text.partition(BEGIN)
    _, found_end, tail = rest.partition(END)
    if not (found and found_end):
        raise SystemExit(f"{TABLE_DOC}: the markers {BEGIN!r} and {END!r} are missing")
    return f"{head}{BEGIN}\n```\n{table}\n```\n{END}{tail}"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=available_cores())
    parser.add_argument("--cache-dir", help="cache to use (default: a new, empty one)")
    parser.add_argument("--output", help="results folder (default: a temporary one)")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    logging.getLogger("knitmech").setLevel(logging.INFO)
    with tempfile.TemporaryDirectory(prefix="docs-figures-") as scratch:
        cache = Path(args.cache_dir) if args.cache_dir else Path(scratch) / "cache"
        output = Path(args.output) if args.output else Path(scratch) / "results"
        result = run_scene(
            load_scene(), output=output, cache_dir=cache, jobs=args.jobs, progress=sys.stderr
        )
        for source, target in FIGURES.items():
            shutil.copyfile(output / source, DOCS / "figures" / target)
            print(f"wrote docs/figures/{target}")
    TABLE_DOC.write_text(replace_table(TABLE_DOC.read_text(), result.table))
    print(f"wrote the printed table into {TABLE_DOC.relative_to(ROOT)}")
    print(result.table)


if __name__ == "__main__":
    main()
