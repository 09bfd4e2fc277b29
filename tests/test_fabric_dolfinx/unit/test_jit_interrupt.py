"""`fabric_dolfinx.jit`: a Ctrl-C that Python loses during a compilation (raised inside a
finalizer of the C build's objects, printed and ignored) stops the run once the compilation has
ended, instead of being lost (tests/test_fabric_dolfinx/validation/test_fault_jit.py met it:
the run went on to the end)."""

import signal
import sys

import pytest
from support.signals import signal_inside_an_ignoring_callback

from fabric_dolfinx import jit
from rve_rod.errors import terminate_as_interrupt


def test_a_ctrl_c_lost_during_a_compilation_is_raised_when_it_ends(signal_handlers, monkeypatch):
    lost = []
    monkeypatch.setattr(sys, "unraisablehook", lambda unraisable: lost.append(unraisable.exc_type))
    terminate_as_interrupt()
    compiled = []

    def compile_function():
        signal_inside_an_ignoring_callback(signal.SIGINT)  # lost inside the build
        compiled.append("module")
        return "module"

    with pytest.raises(KeyboardInterrupt):
        jit._guarded(compile_function)()
    assert lost == [KeyboardInterrupt]  # Python did lose it where it arrived
    assert compiled == ["module"]  # the compilation ended first
    assert jit._Compilation.lock is None
    assert jit._guarded(lambda: "again")() == "again"  # raised once
