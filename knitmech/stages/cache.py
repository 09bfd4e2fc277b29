"""Content-addressed cache of pipeline stages: a stage's summary and every file it writes.

A stage is a named computation with all of its inputs spelled out (`Stage`). Its cache key is
`rve_rod.cache.cache_key` of those inputs (which adds the package version), so a stage whose
inputs did not change is never computed again: its summary and files are taken from the cache
and written into the results folder. A stage computes into a temporary folder inside the
results folder; only when it has finished are its files stored (atomically, as one entry of
a `rve_rod.cache.ResultCache`) and moved into place, so an interrupted stage leaves neither a
cache entry nor half-written files, and the next run computes it again while every stage that
finished before is taken from the cache.
"""

import contextlib
import fcntl
import json
import logging
import os
import shutil
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from rve_rod.cache import ResultCache, cache_key
from rve_rod.errors import InputError
from rve_rod.jsonable import to_jsonable

__all__ = [
    "CACHED",
    "COMPUTED",
    "GIVEN",
    "LOCK_FILE",
    "Stage",
    "StageCache",
    "StageRecord",
    "StageResult",
    "remove_stale_work",
    "results_folder_lock",
]

logger = logging.getLogger(__name__)

COMPUTED, CACHED, GIVEN = "computed", "cached", "given"
"""Statuses of a stage record: computed now, taken from the cache, or given by the scene."""

_WORK_PREFIX = ".stage-"
_SUMMARY = "summary"
_FILES = "files"


class Stage(NamedTuple):
    """One unit of pipeline work.

    Attributes:
        name: the stage ("geometry", "meso", "surface", "macro").
        item: what within the stage (a load case, a direction), "" when there is one item.
        inputs: everything the result depends on (JSON-like; the cache key is made of it).
        compute: writes the stage's files into the folder it is given (paths relative to it
            are the paths in the results folder) and returns its JSON-ready summary.
    """

    name: str
    item: str
    inputs: dict
    compute: Callable[[Path], dict]


@dataclass(frozen=True)
class StageRecord:
    """What happened to a stage in one run.

    Attributes:
        stage: the stage's name.
        item: the item within the stage.
        status: COMPUTED, CACHED or GIVEN (the surface file a scene gives: its copy, figure
            and summary are cached all the same, under `key`).
        wall_time_s: time spent, computing or restoring from the cache (s).
        key: the cache key (SHA-256 hex).
        files: the files it wrote, relative to the results folder.
    """

    stage: str
    item: str
    status: str
    wall_time_s: float
    key: str
    files: tuple[str, ...]


class StageResult(NamedTuple):
    """A stage's summary and its record."""

    summary: dict
    record: StageRecord


@dataclass(frozen=True)
class StageCache:
    """Stage results stored under `folder` (one `.npz` per key, see `rve_rod.cache`).

    Attributes:
        folder: root folder of the stage cache.
    """

    folder: Path

    def __post_init__(self):
        object.__setattr__(self, "folder", Path(self.folder))

    def run(self, stage: Stage, output: Path) -> StageResult:
        """The stage's summary, from the cache or computed; its files end up in `output`."""
        started = time.perf_counter()
        output = Path(output)
        output.mkdir(parents=True, exist_ok=True)
        entries = ResultCache(self.folder)
        inputs = {"stage": stage.name, "item": stage.item, "inputs": stage.inputs}
        key = cache_key(inputs)
        arrays = entries.load(inputs)
        if arrays is not None:
            summary = json.loads(str(arrays[_SUMMARY]))
            names = json.loads(str(arrays[_FILES]))
            for index, name in enumerate(names):
                target = output / name
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(arrays[f"file_{index}"].tobytes())
            status = CACHED
        else:
            logger.debug("%s: computing", _label(stage))
            with tempfile.TemporaryDirectory(dir=output, prefix=_WORK_PREFIX) as temporary:
                work = Path(temporary)
                summary = to_jsonable(stage.compute(work))
                names = sorted(str(p.relative_to(work)) for p in work.rglob("*") if p.is_file())
                stored = {
                    _SUMMARY: np.array(json.dumps(summary, allow_nan=False)),
                    _FILES: np.array(json.dumps(names)),
                }
                for index, name in enumerate(names):
                    stored[f"file_{index}"] = np.frombuffer((work / name).read_bytes(), np.uint8)
                entries.store(inputs, stored)
                for name in names:
                    target = output / name
                    target.parent.mkdir(parents=True, exist_ok=True)
                    shutil.move(work / name, target)
            status = COMPUTED
        record = StageRecord(
            stage=stage.name,
            item=stage.item,
            status=status,
            wall_time_s=time.perf_counter() - started,
            key=key,
            files=tuple(names),
        )
        logger.info("%s: %s in %.2f s", _label(stage), status, record.wall_time_s)
        return StageResult(summary, record)


LOCK_FILE = ".knitmech.lock"
"""The lock file of a results folder (`results_folder_lock`)."""

_HELD: set[Path] = set()
"""The results folders this process holds (`results_folder_lock` is reentrant within it)."""


@contextlib.contextmanager
def results_folder_lock(folder: Path, name: str = "output") -> Iterator[Path]:
    """Hold the results folder `folder` (created if missing) for one run: an exclusive
    `flock` on its LOCK_FILE for as long as the block runs, released by the kernel when the
    process dies however it dies. A second run into the same folder is refused at once
    (InputError naming `name`): before, its clean-up deleted the live `.stage-*` folder of
    the first, which died with a traceback, or two scenes ran at once and left a folder of
    both. Holding the lock, the `.stage-*` folders a run finds are those of a killed run.
    Within one process the hold is reentrant: a run inside a run (`knitmech design` runs its
    designed scene into its own folder) shares the outer hold."""
    folder = Path(folder)
    folder.mkdir(exist_ok=True)
    key = folder.resolve()
    if key in _HELD:  # a run inside a run of this process (a design's final scene run)
        yield folder
        return
    descriptor = os.open(folder / LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(descriptor)
        holder = (folder / LOCK_FILE).read_text().strip() or "another process"
        raise InputError(
            f"{name} {folder}: another knitmech run ({holder}) is writing into it; wait for it "
            "to end or give another folder"
        ) from None
    try:
        os.ftruncate(descriptor, 0)
        os.write(descriptor, f"process {os.getpid()}".encode())
        _HELD.add(key)
        yield folder
    finally:
        _HELD.discard(key)
        os.close(descriptor)


def remove_stale_work(output: Path) -> list[Path]:
    """Delete the temporary folders of stages a killed run left in `output` (SIGKILL, power
    loss: nothing could clean up); returns them. Call it holding `results_folder_lock`."""
    stale = sorted(p for p in Path(output).glob(f"{_WORK_PREFIX}*") if p.is_dir())
    for path in stale:
        logger.info("removing %s, left by an interrupted run", path)
        shutil.rmtree(path, ignore_errors=True)
    return stale


def _label(stage: Stage) -> str:
    return f"{stage.name} {stage.item}".rstrip()
