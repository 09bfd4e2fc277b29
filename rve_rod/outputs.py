"""Output paths, checked before anything is computed: one rule for the three command-line tools
and the `knitmech` pipeline.

The rule: an output goes into a folder that exists and can be written; nothing creates a
missing parent folder (a typo in a path is refused, not turned into a new tree of folders).
An output file must not be an existing folder; an output folder may exist (it is reused) or
not (it is created, its parent must exist) but must not be an existing file. Every check
raises `InputError` naming the option, the path and what is wrong, so a tool exits with
status 2 before it computes anything and no result is lost at the end of a run.

`ignore_broken_pipe` restores Python's own handling of a closed stdout (`... --json | head`)
where an extension (PETSc) installed a SIGPIPE handler that aborts the process; the tools
then stop quietly with status 141 (`rve_rod.errors.cli_exit_status`).
"""

import os
import signal
from pathlib import Path

from rve_rod.errors import InputError

__all__ = [
    "check_output_file",
    "check_output_folder",
    "figure_formats",
    "ignore_broken_pipe",
    "image_formats",
]


def _check_parent(name: str, path: Path) -> None:
    parent = path.parent
    if parent.exists() and not parent.is_dir():
        raise InputError(f"{name} {path}: {parent} is a file, not a folder")
    if not parent.is_dir():
        raise InputError(f"{name} {path}: folder {parent} does not exist (create it first)")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{name} {path}: folder {parent} is not writable")


def figure_formats() -> tuple[str, ...]:
    """The file suffixes matplotlib writes figures in (png, pdf, svg, ...)."""
    from matplotlib.backend_bases import FigureCanvasBase  # noqa: PLC0415 (on demand)

    return tuple(sorted(FigureCanvasBase.get_supported_filetypes()))


def image_formats() -> tuple[str, ...]:
    """The file suffixes Pillow writes images in (png, jpg, tif, ...)."""
    from PIL import Image  # noqa: PLC0415 (on demand)

    Image.init()
    extensions = Image.registered_extensions().items()
    return tuple(sorted(e[1:] for e, kind in extensions if kind in Image.SAVE))


def check_output_file(
    name: str, path: str | os.PathLike, formats: tuple[str, ...] | None = None
) -> Path:
    """`path` as a Path, or InputError unless a file can be written there (see the module)
    and, when `formats` are given (`figure_formats()`, `image_formats()`), its suffix is one
    of them (a figure named x.foo used to fail after the computation, its result lost).

    Args:
        name: the option or key that gave the path (e.g. "--output", "macro.xdmf").
        path: the file to write.
        formats: the suffixes (without the dot, lower case) the writer knows, or None.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{name} {path}: is a folder; give a file name")
    if formats is not None and path.suffix.lower()[1:] not in formats:
        raise InputError(
            f"{name} {path}: {path.suffix or 'no suffix'} is not a format it can be written "
            f"in (valid: {', '.join(formats)})"
        )
    _check_parent(name, path)
    if path.exists() and not os.access(path, os.W_OK):
        raise InputError(f"{name} {path}: the file is not writable")
    return path


def check_output_folder(name: str, path: str | os.PathLike) -> Path:
    """`path` as a Path, or InputError unless it is a folder or can be created as one (its
    parent exists; see the module).

    Args:
        name: the option or key that gave the path (e.g. "--output", "--cache-dir").
        path: the folder to write into.
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise InputError(f"{name} {path}: is a file, not a folder")
    if path.is_dir():
        if not os.access(path, os.W_OK | os.X_OK):
            raise InputError(f"{name} {path}: the folder is not writable")
        return path
    _check_parent(name, path)
    return path


def ignore_broken_pipe() -> None:
    """Let a write to a closed stdout raise BrokenPipeError again (Python's default; PETSc's
    signal handler would abort the MPI job instead). Call it before writing results."""
    signal.signal(signal.SIGPIPE, signal.SIG_IGN)
