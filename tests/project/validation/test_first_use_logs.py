"""What a new user sees on stderr from `fabric-dolfinx` on first use (FFCx compiles its forms
into a fresh cache): nothing at default verbosity (no gcc command lines), and with -v the
tool's `[rank N]` format on every line."""

import os
import subprocess
import sys
from pathlib import Path

FABRIC_DOLFINX = str(Path(sys.executable).parent / "fabric-dolfinx")
ARGS = ["tension", "--svk", "10,8,0.3,2", "--elements", "2", "--steps", "2"]


def test_first_use_is_quiet_and_verbose_logs_carry_the_rank(tmp_path):
    environment = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}

    def run(*extra):
        command = [FABRIC_DOLFINX, *extra, *ARGS]
        return subprocess.run(command, capture_output=True, text=True, env=environment, check=True)

    first = run()
    assert (tmp_path / "cache").is_dir()  # FFCx compiled into the fresh cache
    assert first.stderr == ""
    verbose = run("-v")
    lines = verbose.stderr.splitlines()
    assert lines and all(line.startswith("[rank 0] ") for line in lines)
