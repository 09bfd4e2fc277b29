"""The scene check's meshing of a part (`fabric_dolfinx.spec.contents.part_contents`): one
child process per part and file content in a process (a design checks its scene at every
evaluation)."""

import subprocess

import pytest

from fabric_dolfinx.spec import contents
from fabric_dolfinx.spec.part import MeshSpec
from rve_rod.errors import InputError

SQUARE = """Point(1) = {{0, 0, 0, {size}}}; Point(2) = {{50, 0, 0, {size}}};
Point(3) = {{50, 50, 0, {size}}}; Point(4) = {{0, 50, 0, {size}}}; Line(1) = {{1, 2}};
Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}}; Curve Loop(1) = {{1, 2, 3, 4}};
Plane Surface(1) = {{1}}; Physical Curve("bottom") = {{1}}; Physical Surface("fabric") = {{1}};
Mesh.RecombineAll = 1;
"""


@pytest.fixture
def children(monkeypatch):
    """The child processes `part_contents` starts (their commands), with an empty memo."""
    contents._contents_of.cache_clear()
    started, real = [], subprocess.run

    def run(command, **options):
        started.append(command)
        return real(command, **options)

    monkeypatch.setattr(contents.subprocess, "run", run)
    yield started
    contents._contents_of.cache_clear()


def test_a_part_is_meshed_once_per_file_content(tmp_path, children):
    path = tmp_path / "square.geo"
    path.write_text(SQUARE.format(size=10))
    spec = MeshSpec(shape=None, file=str(path))
    first = contents.part_contents(spec)
    again = contents.part_contents(spec)
    assert len(children) == 1 and again is first
    path.write_text(SQUARE.format(size=25))
    coarser = contents.part_contents(spec)
    assert len(children) == 2
    assert len(coarser.centres["fabric"]) < len(first.centres["fabric"]) / 3
    contents.part_contents(MeshSpec(shape="patch"))
    assert len(children) == 3
    with pytest.raises(ValueError, match="read-only"):
        first.centres["fabric"][0, 0] = 1.0


def test_a_failed_meshing_is_not_kept(tmp_path, children):
    spec = MeshSpec(shape=None, file=str(tmp_path / "missing.geo"))
    for _ in range(2):
        with pytest.raises(InputError, match=r"missing\.geo"):
            contents.part_contents(spec)
    assert len(children) == 2
