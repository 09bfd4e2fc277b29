"""A fault test: two `knitmech run`s into one results folder at once (issue 31).

Before, the later run's clean-up deleted the earlier run's live `.stage-*` folder (the
earlier died with a traceback), or two different scenes both exited 0 and left a folder of
both. Now a run holds its results folder (`knitmech.stages.cache.results_folder_lock`): the
second run is refused at once with one line, the first finishes undisturbed, and once it has
ended the folder is free again.
"""

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

from knitmech.scene import default_surface_path

KNITMECH = str(Path(sys.executable).parent / "knitmech")

SCENE = """
name = "{name}"
fidelity = "fast"
[fabric]
preset = "cotton-20s2"
stitch = 5.5
[meso]
cases = []
[surface]
path = "{surface}"
[macro]
directions = ["course"]
elements = {elements}
steps = {steps}
max_strain = 0.2
"""


@pytest.mark.slow
def test_a_second_run_into_a_busy_results_folder_is_refused(tmp_path):
    results, cache = tmp_path / "results", tmp_path / "cache"
    scenes = {}
    for name, elements, steps in (("first", 24, 40), ("second", 2, 2)):
        scenes[name] = tmp_path / f"{name}.toml"
        text = SCENE.format(
            name=name, surface=default_surface_path(), elements=elements, steps=steps
        )
        scenes[name].write_text(text)
    command = [KNITMECH, "run", "-o", str(results), "--cache-dir", str(cache), "-q"]
    first = subprocess.Popen(
        [*command, str(scenes["first"])],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 120
    while not list(results.glob(".stage-*")):  # the first run is computing its macro stage
        assert first.poll() is None and time.monotonic() < deadline, first.stderr.read()
        time.sleep(0.05)
    second = subprocess.run(
        [*command, str(scenes["second"])], capture_output=True, text=True, check=False
    )
    assert second.returncode == 2
    assert second.stderr == (
        f"knitmech run: error: output {results}: another knitmech run (process {first.pid}) "
        "is writing into it; wait for it to end or give another folder\n"
    )
    _, err = first.communicate(timeout=600)
    assert first.returncode == 0, err
    summary = json.loads((results / "summary.json").read_text())
    assert summary["scene"]["name"] == "first"
    assert list(results.glob(".stage-*")) == []
    again = subprocess.run(
        [*command, str(scenes["second"])], capture_output=True, text=True, check=False
    )
    assert again.returncode == 0, again.stderr
    assert json.loads((results / "summary.json").read_text())["scene"]["name"] == "second"
