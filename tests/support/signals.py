"""A signal that Python loses in a test's own process: its handler raises inside a callback
whose exceptions Python prints and ignores (the `signal_handlers` fixture of tests/conftest.py
restores the process's handlers after the test)."""

import os
import time
import weakref


def signal_inside_an_ignoring_callback(signum: int) -> weakref.ref:
    """Send `signum` to this process so that its handler runs inside a weakref callback, whose
    exceptions Python prints and ignores (as it does those of an at-fork hook: logging's lock
    release while a process pool forks a worker; or a finalizer of a C build's objects)."""

    class Owner:
        pass

    def callback(_reference):
        os.kill(os.getpid(), signum)
        time.sleep(1.0)  # the handler runs here and raises inside the callback

    owner = Owner()
    reference = weakref.ref(owner, callback)
    del owner  # runs the callback: its exception is printed, not raised
    return reference
