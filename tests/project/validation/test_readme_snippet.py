"""The README's Python snippet runs as printed (in a fresh process, in an empty folder), and its
`print(surface)` is a few lines, not the arrays."""

import os
import re
import subprocess
import sys
from pathlib import Path

README = Path(__file__).resolve().parents[3] / "README.md"


def python_snippet() -> str:
    """The Python block under "Python API in brief"."""
    section = README.read_text().split("## Python API in brief", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.DOTALL).group(1)


def test_the_readme_python_snippet_runs(tmp_path):
    script = tmp_path / "snippet.py"
    script.write_text(python_snippet())
    environment = {"XDG_CACHE_HOME": str(tmp_path / "cache"), "MPLBACKEND": "Agg"}
    run = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=1200,
        check=False,
        env={**os.environ, **environment},
    )
    assert run.returncode == 0, run.stderr[-3000:]
    assert "gcc" not in run.stderr  # FFCx's build lines (about 20 before issue 31)
    assert (tmp_path / "cotton.h5").is_file() and (tmp_path / "results" / "summary.json").is_file()
    (surface_line,) = [line for line in run.stdout.splitlines() if "ResponseSurface(" in line]
    assert "checks passed" in surface_line and len(surface_line) < 400
