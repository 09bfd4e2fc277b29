"""Atomic writes: the file appears complete under its name, or not at all."""

import os
import stat

import pytest

from rve_rod.atomic import atomic_write


def test_written_file_replaces_the_old_one_and_no_temporary_stays(tmp_path):
    target = tmp_path / "result.txt"
    target.write_text("old")
    with atomic_write(target) as temporary:
        assert temporary.parent == tmp_path and temporary != target
        temporary.write_text("new")
        assert target.read_text() == "old"  # unchanged until the block ends
    assert target.read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["result.txt"]


def test_exception_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "result.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError, match="failed"), atomic_write(target) as temporary:
        temporary.write_text("partial")
        raise RuntimeError("failed")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["result.txt"]


@pytest.mark.parametrize("umask", [0o022, 0o077])
def test_written_file_has_the_permissions_of_a_new_file(tmp_path, umask):
    previous = os.umask(umask)
    try:
        with atomic_write(tmp_path / "surface.h5") as temporary:
            temporary.write_bytes(b"data")
    finally:
        os.umask(previous)
    assert stat.S_IMODE((tmp_path / "surface.h5").stat().st_mode) == 0o666 & ~umask
