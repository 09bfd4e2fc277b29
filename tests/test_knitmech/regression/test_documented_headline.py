"""The headline numbers of the docs are what the code gives (issue 19, first use).

Runs the default scene at its level (balanced: what `make demo` runs and `make figures` puts
in the docs) with an empty cache and compares:

* the printed table in docs/pipeline.md (between the markers `scripts/docs_figures.py`
  writes): every force and Poisson ratio, to its printed digits (one unit of the last digit
  for round-off between machines, the pins' rtol 1e-3 beyond);
* the agreement of patch and RVE the README and docs/pipeline.md quote (-0.9..+2.4 %
  course-wise ...; at the patch's centre gauge and between its clamps), and
  docs/pipeline.md's split of the latter into the clamps' and the homogenization's share, to
  the printed 0.1 %.

A change of the physics fails this test until `make figures` is run (and the sentences are
updated with the numbers the failure prints).
"""

import re
from pathlib import Path

import numpy as np
import pytest

from knitmech.pipeline import run_scene
from knitmech.scene import load_scene

ROOT = Path(__file__).resolve().parents[3]
BEGIN = "<!-- begin: the printed table of `knitmech run`, written by `make figures` -->"
END = "<!-- end: the printed table -->"
NUMBER = r"[-+]?\d+\.\d+"


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    folder = tmp_path_factory.mktemp("demo")
    return run_scene(load_scene(), output=folder / "results", cache_dir=folder / "cache", jobs=2)


def table_numbers(table: str) -> dict[str, list[float]]:
    """The force rows (5, 10, 20 %, under their direction's header) and Poisson rows of a
    printed table, by row label ("course 5 %", ..., "nu12 at 10 %")."""
    rows, block = {}, ""
    for line in table.splitlines():
        header = re.search(r"(\w+)-wise force", line)
        if header:
            block = header.group(1) + " "
        label = re.match(r"\s*(\d+ %|nu\d\d at \d+ %)\s", line)
        if label:
            key = label.group(1) if label.group(1).startswith("nu") else block + label.group(1)
            rows[key] = [float(v) for v in re.findall(NUMBER, line[label.end() :])]
    return rows


def flat(text: str) -> str:
    return " ".join(text.split())


def span(values) -> str:
    """Range of relative differences as the docs print it, e.g. -0.9..+2.4 (%)."""
    percent = 100 * np.asarray(values)
    return f"{percent.min():+.1f}..{percent.max():+.1f}"


def test_the_printed_table_in_docs_is_what_the_default_scene_gives(demo):
    text = (ROOT / "docs" / "pipeline.md").read_text()
    documented = table_numbers(text[text.index(BEGIN) : text.index(END)])
    computed = table_numbers(demo.table)
    assert sorted(documented) == sorted(computed) and len(computed) == 10
    for label, values in computed.items():
        for doc, code in zip(documented[label], values, strict=True):
            digits = 3 if "nu" in label or abs(code) < 1 else 2
            assert doc == pytest.approx(code, abs=10**-digits + 1e-3 * abs(code)), (label, values)


def test_the_quoted_agreement_of_patch_and_rve_is_what_the_default_scene_gives(demo):
    forces = demo.summary["forces"]

    def ratio(direction, first, second):
        data = forces[direction]
        return np.divide(data[f"{first}_gf_per_cm"], data[f"{second}_gf_per_cm"]) - 1.0

    def quote(first, second, joint):
        course, wale = ratio("course", first, second), ratio("wale", first, second)
        return f"{span(course)} % course-wise{joint}{span(wale)} % wale-wise"

    centre = quote("centre", "meso", " and ")
    overall = quote("macro", "meso", " and ")
    pipeline = flat((ROOT / "docs" / "pipeline.md").read_text())
    readme = flat((ROOT / "README.md").read_text())
    assert readme.count(centre) == 2, centre
    assert overall in readme and overall in pipeline and centre in pipeline, overall
    assert f"(patch against the surface alone: {quote('macro', 'surface', ', ')})" in pipeline
    assert f"(surface alone against RVE: {quote('surface', 'meso', ', ')})" in pipeline
