"""Input checks: accepted values pass through, refused ones name parameter, value and range."""

import os
import signal
import sys
import time

import numpy as np
import pytest
from support.signals import signal_inside_an_ignoring_callback

from rve_rod import errors
from rve_rod.errors import (
    ConvergenceError,
    InputError,
    check_integer,
    check_positive,
    check_range,
    cli_exit_status,
    raise_pending_interrupt,
    terminate_as_interrupt,
)


@pytest.mark.parametrize("value", [3, 3.0, np.int64(3), np.int32(3), np.float64(3.0)])
def test_check_integer_accepts_integral_numbers_of_any_type(value):
    assert check_integer("count", value, 1) == 3


@pytest.mark.parametrize("value", [2.5, float("nan"), float("inf"), True, "3", None])
def test_check_integer_refuses_non_integers(value):
    with pytest.raises(InputError, match=r"count=.* must be an integer"):
        check_integer("count", value, 1)


def test_messages_name_parameter_value_and_range():
    with pytest.raises(InputError, match=r"steps=0 is outside the valid range \[2, 50\]"):
        check_integer("steps", 0, 2, 50)
    with pytest.raises(InputError, match=r"yarn_radius=-0.1 mm must be > 0"):
        check_positive("yarn_radius", -0.1, "mm")
    with pytest.raises(InputError, match=r"nu=0.7 is outside the valid range \[0, 0.5\]"):
        check_range("nu", 0.7, 0.0, 0.5)
    with pytest.raises(InputError, match="must be a finite number"):
        check_positive("wale_width", float("nan"), "mm")


@pytest.mark.parametrize(
    ("error", "status", "line"),
    [
        (InputError("steps=0 must be >= 1"), 2, "tool run: error: steps=0 must be >= 1\n"),
        (ConvergenceError("t=0.5 not reached"), 3, "tool run: not converged: t=0.5 not reached\n"),
        (KeyboardInterrupt(), 130, "tool run: interrupted\n"),
    ],
)
def test_the_exit_status_of_each_outcome_with_one_line(capsys, error, status, line):
    assert cli_exit_status("tool run", error) == status
    assert capsys.readouterr().err == line
    assert cli_exit_status("tool run", error, quiet=True) == status
    assert capsys.readouterr().err == ""


def test_resumable_errors_say_so_and_other_errors_propagate(capsys):
    resumable = (LookupError,)
    assert cli_exit_status("tool", KeyError("disk"), resumable=resumable) == 1
    assert cli_exit_status("tool", KeyboardInterrupt(), resumable=resumable) == 130
    assert capsys.readouterr().err.splitlines() == [
        "tool: stopped: 'disk'; run again to resume",
        "tool: interrupted; run again to resume",
    ]
    with pytest.raises(ZeroDivisionError):
        cli_exit_status("tool", ZeroDivisionError("bug"))


def interrupted(*args, **kwargs):
    raise KeyboardInterrupt


@pytest.mark.parametrize("program", ["rve-rod", "knitmech", "fabric-dolfinx"])
def test_every_command_line_exits_130_on_ctrl_c(monkeypatch, capsys, program):
    """The three tools share the mapping: an interrupt inside a subcommand gives 130."""
    if program == "rve-rod":
        from rve_rod.cli import geometry, main  # noqa: PLC0415

        monkeypatch.setattr(geometry, "loop_geometry", interrupted)
        argv = ["geometry", "--preset", "cotton-20s2", "--stitch", "5.5"]
    elif program == "knitmech":
        from knitmech import cli  # noqa: PLC0415

        main = cli.main
        monkeypatch.setattr(cli, "run_scene", interrupted)
        argv = ["run"]
    else:
        from fabric_dolfinx import cli  # noqa: PLC0415 (dolfinx)

        main = cli.main
        monkeypatch.setattr(cli, "TensionSetup", interrupted)
        argv = ["tension", "--svk", "1,1,0.1,1"]
    assert main(argv) == 130
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert last.startswith(f"{program} {argv[0]}: interrupted")


@pytest.mark.parametrize(
    ("program", "module"),
    [
        ("rve-rod", "rve_rod.cli"),
        ("knitmech", "knitmech.cli"),
        ("fabric-dolfinx", "fabric_dolfinx.cli"),
    ],
)
@pytest.mark.parametrize(
    ("argv", "message"),
    [([], "the following arguments are required"), (["no-such-command"], "invalid choice")],
)
def test_every_command_line_gives_usage_errors_one_line_and_exit_2(
    capsys, program, module, argv, message
):
    """The three tools share the parser (`CommandLineParser`): no usage text, status 2."""
    main = __import__(module, fromlist=["main"]).main
    assert main(argv) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"{program}: error: ")
    assert message in lines[0]


@pytest.mark.parametrize(
    ("signum", "expected"),
    [(signal.SIGINT, KeyboardInterrupt), (signal.SIGTERM, errors.Terminated)],
)
def test_a_signal_lost_in_a_callback_is_raised_where_the_run_waits(
    signal_handlers, monkeypatch, signum, expected
):
    lost = []
    monkeypatch.setattr(sys, "unraisablehook", lambda unraisable: lost.append(unraisable.exc_type))
    terminate_as_interrupt()
    raise_pending_interrupt()  # nothing pending: nothing raised
    signal_inside_an_ignoring_callback(signum)  # the run went on: the signal was lost here
    assert lost == [expected]
    with pytest.raises(expected):
        raise_pending_interrupt()
    raise_pending_interrupt()  # raised once


def test_an_interrupt_handled_at_the_top_is_not_raised_again(signal_handlers, capsys):
    terminate_as_interrupt()
    with pytest.raises(KeyboardInterrupt) as caught:
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1.0)
    assert cli_exit_status("rve-rod simulate", caught.value) == errors.EXIT_INTERRUPTED
    raise_pending_interrupt()  # handled: nothing pending


def test_an_ignored_ctrl_c_stays_ignored(signal_handlers):
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a background job's
    terminate_as_interrupt()
    assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
