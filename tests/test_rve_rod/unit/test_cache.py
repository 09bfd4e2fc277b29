"""The result cache: keys change with every input and only then; atomic, self-healing entries."""

import dataclasses
import logging
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import rve_rod.cache
from rve_rod.cache import ResultCache, cache_key, canonical_json
from rve_rod.errors import InputError
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.generate import case_inputs
from rve_rod.homogenize.samples import RveCase
from rve_rod.homogenize.sampling import LoadPath
from rve_rod.presets import Fabric, Knit, load_preset

BASE_FABRIC = load_preset("cotton-20s2", 5.5)
BASE_CASE = RveCase(BASE_FABRIC, LoadPath("biaxial", 22.5, 0.2, 10))
BASE_ENGINE = AnalyticRve()


def perturbed(value):
    if isinstance(value, bool):
        return not value
    if value is None:
        return 1.0
    if isinstance(value, tuple):  # a stitch pattern's chart: knit and purl swapped
        return tuple(row.translate(str.maketrans("KP", "PK")) for row in value)
    return value * 1.01 + 0.01


def variants():
    """The base case with each single input changed, by name."""
    yield "base", BASE_CASE, BASE_ENGINE
    fabric = BASE_FABRIC
    for part in ("yarn", "knit"):
        component = getattr(fabric, part)
        for field in dataclasses.fields(component):
            if field.name == "name":
                continue
            value = getattr(component, field.name)
            if dataclasses.is_dataclass(value):  # the yarn's fibres: each of their values
                changes = {
                    f"{field.name}.{inner.name}": dataclasses.replace(
                        value, **{inner.name: perturbed(getattr(value, inner.name))}
                    )
                    for inner in dataclasses.fields(value)
                    if inner.name != "name"
                }
            else:
                changes = {field.name: perturbed(value)}
            for name, changed in changes.items():
                changed_fabric = dataclasses.replace(
                    fabric, **{part: dataclasses.replace(component, **{field.name: changed})}
                )
                yield f"{part}.{name}", RveCase(changed_fabric, BASE_CASE.load), BASE_ENGINE
    for name, load in (
        ("load.angle", LoadPath("biaxial", 45.0, 0.2, 10)),
        ("load.max_load", LoadPath("biaxial", 22.5, 0.21, 10)),
        ("load.steps", LoadPath("biaxial", 22.5, 0.2, 11)),
        ("load.kind", LoadPath("shear", 0.0, 0.2, 10)),
    ):
        yield name, RveCase(fabric, load), BASE_ENGINE
    for field in dataclasses.fields(AnalyticRve):
        engine = dataclasses.replace(
            BASE_ENGINE, **{field.name: perturbed(getattr(BASE_ENGINE, field.name))}
        )
        yield f"engine.{field.name}", BASE_CASE, engine


def plain_function_engine(case):
    return BASE_ENGINE(case)


def test_keys_change_with_every_input():
    keys = {name: cache_key(case_inputs(case, engine)) for name, case, engine in variants()}
    keys["engine.function"] = cache_key(case_inputs(BASE_CASE, plain_function_engine))
    assert len(keys) > 20
    assert len(set(keys.values())) == len(keys), "two different inputs share a key"


def test_keys_do_not_change_otherwise():
    base = cache_key(case_inputs(BASE_CASE, BASE_ENGINE))
    # rebuilt from equal values, renamed, ints for floats, -0.0 for 0.0: same key
    fibres = dataclasses.replace(BASE_FABRIC.yarn.fibres, name="gossypium")
    yarn = dataclasses.replace(BASE_FABRIC.yarn, name="my cotton", fibres=fibres)
    knit = Knit(**dataclasses.asdict(BASE_FABRIC.knit))
    same = RveCase(Fabric(yarn, knit, name="explicit"), LoadPath("biaxial", 22.5, 0.2, 10))
    assert cache_key(case_inputs(same, AnalyticRve())) == base
    integer_engine = dataclasses.replace(BASE_ENGINE, wale_stiffening=10)
    assert cache_key(case_inputs(BASE_CASE, integer_engine)) == base
    assert canonical_json({"b": -0.0, "a": (1, 2)}) == canonical_json({"a": [1.0, 2.0], "b": 0})


def test_key_changes_with_package_version(monkeypatch):
    base = cache_key({"x": 1.0})
    monkeypatch.setattr(rve_rod.cache, "__version__", "99.0")
    assert cache_key({"x": 1.0}) != base


def test_non_finite_or_unknown_inputs_are_rejected():
    with pytest.raises(InputError, match="finite"):
        cache_key({"x": float("nan")})
    with pytest.raises(InputError, match="cannot use a object"):
        cache_key({"x": object()})


def test_store_and_load_round_trip(tmp_path):
    cache = ResultCache(tmp_path)
    arrays = {"F": np.arange(12.0).reshape(3, 2, 2), "complete": np.array(True)}
    assert cache.load({"case": 1}) is None
    path = cache.store({"case": 1}, arrays)
    assert path.parent.parent == tmp_path and path.stem == cache_key({"case": 1})
    loaded = cache.load({"case": 1})
    assert set(loaded) == set(arrays)
    for name, array in arrays.items():
        np.testing.assert_array_equal(loaded[name], array)
    assert cache.load({"case": 2}) is None


@pytest.mark.parametrize("damage", ["truncate", "garbage", "empty"])
def test_corrupt_entry_is_deleted_and_recomputed(tmp_path, caplog, damage):
    cache = ResultCache(tmp_path)
    path = cache.store({"case": 1}, {"F": np.ones(100)})
    data = path.read_bytes()
    path.write_bytes(
        {"truncate": data[: len(data) // 2], "garbage": b"not a zip" * 10, "empty": b""}[damage]
    )
    with caplog.at_level(logging.WARNING):
        assert cache.load({"case": 1}) is None
    assert "unreadable" in caplog.text
    assert not path.exists()


def test_entry_with_other_inputs_is_rejected(tmp_path):
    cache = ResultCache(tmp_path)
    source = cache.store({"case": 1}, {"F": np.ones(3)})
    target = cache.path({"case": 2})
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_bytes(source.read_bytes())
    assert cache.load({"case": 2}) is None
    assert not target.exists()


def test_exception_while_storing_leaves_nothing(tmp_path, monkeypatch):
    cache = ResultCache(tmp_path)

    def failing_savez(stream, **arrays):
        stream.write(b"partial")
        raise OSError("disk full")

    monkeypatch.setattr(rve_rod.cache.np, "savez", failing_savez)
    with pytest.raises(OSError, match="disk full"):
        cache.store({"case": 1}, {"F": np.ones(3)})
    assert [p for p in tmp_path.rglob("*") if p.is_file()] == []


def test_process_killed_while_storing_leaves_no_entry(tmp_path):
    code = textwrap.dedent(
        """
        import os, signal, sys
        import numpy as np
        from rve_rod import cache

        def die(fd):
            os.kill(os.getpid(), signal.SIGKILL)

        cache.os.fsync = die
        cache.ResultCache(sys.argv[1]).store({"case": 1}, {"F": np.ones(1000)})
        """
    )
    completed = subprocess.run([sys.executable, "-c", code, str(tmp_path)], check=False)
    assert completed.returncode == -9
    cache = ResultCache(tmp_path)
    assert not cache.path({"case": 1}).exists()
    assert cache.load({"case": 1}) is None
    leftovers = [p.name for p in tmp_path.rglob("*") if p.is_file()]
    assert len(leftovers) == 1 and leftovers[0].endswith(".tmp")


def test_two_processes_storing_the_same_entry_leave_one_complete_entry(tmp_path, caplog):
    # two writers (e.g. two sweeps on a shared file system) store the same key 20 times each,
    # with different contents, while this process reads it: every read and the final entry
    # must be one writer's whole array, never a mix or a truncated file
    code = textwrap.dedent(
        """
        import sys, time
        import numpy as np
        from rve_rod.cache import ResultCache

        folder, value, start = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
        while time.time() < start:
            time.sleep(0.001)
        for _ in range(20):
            ResultCache(folder).store({"case": 1}, {"F": np.full(400_000, value)})
        """
    )
    start = f"{time.time() + 2.0}"
    writers = [
        subprocess.Popen([sys.executable, "-c", code, str(tmp_path), value, start])
        for value in ("1.0", "2.0")
    ]
    cache = ResultCache(tmp_path)
    seen = set()
    with caplog.at_level(logging.WARNING, logger="rve_rod.cache"):
        while any(writer.poll() is None for writer in writers):
            arrays = cache.load({"case": 1})
            if arrays is not None:
                values = np.unique(arrays["F"])
                assert values.size == 1 and arrays["F"].size == 400_000
                seen.add(float(values[0]))
    assert [writer.returncode for writer in writers] == [0, 0]
    assert caplog.records == []  # no unreadable entry was ever seen (and deleted)
    final = cache.load({"case": 1})["F"]
    assert final.size == 400_000 and np.unique(final).size == 1
    assert seen <= {1.0, 2.0} and seen
    assert [p.name for p in tmp_path.rglob("*") if p.is_file()] == [cache.path({"case": 1}).name]
