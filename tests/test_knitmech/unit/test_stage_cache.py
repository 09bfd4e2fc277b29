"""The stage cache: a stage with unchanged inputs is restored (summary and files) without being
computed; an interrupted stage leaves no entry and no files."""

import subprocess
import sys

import pytest

from knitmech.stages.cache import CACHED, COMPUTED, Stage, StageCache, results_folder_lock


class Counter:
    """A stage computation that counts its calls and writes two files."""

    def __init__(self, fail: bool = False):
        self.calls = 0
        self.fail = fail

    def __call__(self, folder):
        self.calls += 1
        (folder / "figures").mkdir()
        (folder / "figures" / "a.png").write_bytes(bytes(range(256)) * 3)
        (folder / "b.json").write_text('{"x": 1}')
        if self.fail:
            raise KeyboardInterrupt
        return {"value": 2.5, "items": (1, 2)}


def test_unchanged_stage_is_restored_without_computing(tmp_path):
    cache = StageCache(tmp_path / "cache")
    compute = Counter()
    stage = Stage("meso", "uniaxial-course", {"strain": 0.2}, compute)
    first = cache.run(stage, tmp_path / "one")
    second = cache.run(stage, tmp_path / "two")
    assert compute.calls == 1
    assert (first.record.status, second.record.status) == (COMPUTED, CACHED)
    assert first.summary == second.summary == {"value": 2.5, "items": [1, 2]}
    assert first.record.key == second.record.key
    assert second.record.files == ("b.json", "figures/a.png")
    for name in second.record.files:
        assert (tmp_path / "two" / name).read_bytes() == (tmp_path / "one" / name).read_bytes()
    assert not [p for p in (tmp_path / "one").iterdir() if p.name.startswith(".stage-")]


@pytest.mark.parametrize(
    "changed",
    [
        Stage("meso", "uniaxial-course", {"strain": 0.21}, None),
        Stage("meso", "uniaxial-wale", {"strain": 0.2}, None),
        Stage("macro", "uniaxial-course", {"strain": 0.2}, None),
    ],
)
def test_any_changed_input_computes_again(tmp_path, changed):
    cache = StageCache(tmp_path / "cache")
    compute = Counter()
    cache.run(Stage("meso", "uniaxial-course", {"strain": 0.2}, compute), tmp_path)
    assert cache.run(changed._replace(compute=compute), tmp_path).record.status == COMPUTED
    assert compute.calls == 2


def test_interrupted_stage_leaves_nothing_and_runs_again(tmp_path):
    cache = StageCache(tmp_path / "cache")
    output = tmp_path / "results"
    with pytest.raises(KeyboardInterrupt):
        cache.run(Stage("surface", "", {"rays": 16}, Counter(fail=True)), output)
    assert list(output.iterdir()) == []
    assert not list((tmp_path / "cache").rglob("*.npz"))
    compute = Counter()
    result = cache.run(Stage("surface", "", {"rays": 16}, compute), output)
    assert (result.record.status, compute.calls) == (COMPUTED, 1)


def test_a_results_folder_is_held_once_per_process_and_refused_to_another(tmp_path):
    folder = tmp_path / "out"
    with results_folder_lock(folder), results_folder_lock(folder):  # a run inside a run
        holder = subprocess.run(
            [sys.executable, "-c", _HOLD.format(folder=str(folder))],
            capture_output=True,
            text=True,
            check=False,
        )
        assert "another knitmech run" in holder.stdout
    free = subprocess.run(
        [sys.executable, "-c", _HOLD.format(folder=str(folder))],
        capture_output=True,
        text=True,
        check=False,
    )
    assert free.stdout.strip() == "held"


_HOLD = """
from pathlib import Path
from knitmech.stages.cache import results_folder_lock
try:
    with results_folder_lock(Path({folder!r})):
        print("held")
except Exception as error:
    print(error)
"""
