"""Shared test settings (non-interactive plotting, Open MPI allowed as root) and fixtures."""

import os
import signal
import zlib

import numpy as np
import pytest

from rve_rod import errors
from rve_rod.geometry.loop import loop_geometry
from rve_rod.presets import load_preset

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")


@pytest.fixture(scope="session")
def cotton_loop():
    """The loop of cotton 20s/2 at stitch 5.5 (w = 1.33 mm, c = 1.26 mm, r0 = 0.19 mm, so
    r = w/8): built once per session (about 2 s)."""
    fabric = load_preset("cotton-20s2", 5.5)
    return loop_geometry(fabric.knit, fabric.yarn.minimal_radius)


@pytest.fixture(autouse=True)
def _draws_of_the_test_alone(request):
    """A module's shared `RNG` restarted for every test from a seed of the test's own id, so
    that what a test draws does not depend on which tests ran before it in the process (the
    selection, `-k`, the xdist worker): a test that passed or failed with the order of the
    suite is a test of nothing."""
    if isinstance(getattr(request.module, "RNG", None), np.random.Generator):
        request.module.RNG = np.random.default_rng(zlib.crc32(request.node.nodeid.encode()))


@pytest.fixture
def signal_handlers():
    """Python's SIGINT handler for the test, the process's handlers and no pending signal after."""
    previous = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous[0])
    signal.signal(signal.SIGTERM, previous[1])
    errors._pending.clear()
