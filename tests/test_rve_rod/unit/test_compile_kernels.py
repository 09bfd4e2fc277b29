"""The kernels' warm-up that `make bootstrap` runs (rve_rod.compile_kernels)."""

import re
import subprocess
import sys
from pathlib import Path

import rve_rod
from rve_rod.compile_kernels import kernels, uncached_kernels

PACKAGE = Path(rve_rod.__file__).parent


def _decorated_in_source() -> set[str]:
    """The functions under `@njit` in the package's `_kernels` modules, read from their text."""
    names = set()
    for path in PACKAGE.glob("*/_kernels.py"):
        module = f"rve_rod.{path.parent.name}._kernels"
        text = path.read_text()
        for match in re.finditer(r"^@njit[^\n]*\ndef (\w+)\(", text, flags=re.MULTILINE):
            names.add(f"{module}.{match.group(1)}")
    return names


def test_every_kernel_of_the_package_is_found():
    assert set(kernels()) == _decorated_in_source()
    assert len(kernels()) >= 30


def test_the_warm_up_leaves_every_kernel_in_numbas_cache():
    run = subprocess.run(
        [sys.executable, "-m", "rve_rod.compile_kernels"],
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    total = len(_decorated_in_source())
    assert f"{total} of {total} numba kernels compiled or in the cache" in run.stdout
    assert uncached_kernels() == []
