"""Atomic file writes: write to a temporary file in the target's folder, then rename.

A process killed while writing leaves at most a stray `.<name>.*.tmp` file, never a damaged
file under the final name (the rename is atomic on POSIX file systems).
"""

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = [
    "atomic_write",
]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to `path` to write to; on success it is flushed to disk
    (fsync), given the permissions of a new file (0666 less the umask: 0644 by default) and
    renamed to `path`; on any exception it is removed and `path` is untouched."""
    path = Path(path)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(handle)
    try:
        yield Path(temporary)
        with open(temporary, "rb+") as stream:
            os.fsync(stream.fileno())
        os.chmod(temporary, 0o666 & ~_umask())  # as open() would make it, not mkstemp's 0600
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
