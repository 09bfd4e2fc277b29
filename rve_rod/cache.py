"""Content-addressed on-disk cache of computed results (arrays), keyed by all their inputs.

A key is the SHA-256 of the canonical JSON of the inputs together with the package version,
so a result is reused only when every input is the same, and any change of an input (or of the
package version) computes it again. Entries are `.npz` files written atomically (temporary
file in the same folder, then rename): a process killed while writing leaves at most a stray
`.<key>.npz.*.tmp` file, never a damaged entry under the final name. An entry that cannot be read
(or whose stored inputs differ from the requested ones) is deleted and reported as missing.

Canonical JSON: mappings with sorted string keys, tuples as lists, dataclasses as their fields
plus their type name, numpy scalars and arrays as plain numbers and lists, every real number
as a float (so 5 and 5.0 are the same input) with -0.0 read as 0.0; NaN and infinity are
rejected.
"""

import dataclasses
import hashlib
import json
import logging
import math
import os
import zipfile
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from rve_rod import __version__
from rve_rod.atomic import atomic_write
from rve_rod.errors import InputError

__all__ = [
    "ResultCache",
    "cache_key",
    "canonical_json",
    "default_cache_root",
    "default_runs_dir",
]

logger = logging.getLogger(__name__)

_INPUTS_MEMBER = "__inputs__"


def default_cache_root() -> Path:
    """$XDG_CACHE_HOME/knitmech, or ~/.cache/knitmech when XDG_CACHE_HOME is unset or empty:
    the root of every cache of the project (`rve-runs/`, the pipeline's `stages/`)."""
    root = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(root) / "knitmech"


def default_runs_dir() -> Path:
    """`default_cache_root()/rve-runs`: the RVE runs of response surfaces, shared by
    `rve-rod surface` and `knitmech run`."""
    return default_cache_root() / "rve-runs"


def _canonical(value):
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = {f.name: _canonical(getattr(value, f.name)) for f in dataclasses.fields(value)}
        return {"__type__": type(value).__qualname__, **fields}
    if isinstance(value, Mapping):
        return {str(key): _canonical(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_canonical(item) for item in value]
    if isinstance(value, np.ndarray | np.generic):
        return _canonical(value.tolist())
    if isinstance(value, int | float) and not isinstance(value, bool):
        number = float(value)
        if not math.isfinite(number):
            raise InputError(f"cache inputs must be finite numbers, got {value}")
        return 0.0 if number == 0.0 else number
    if isinstance(value, bool | str) or value is None:
        return value
    raise InputError(f"cannot use a {type(value).__name__} as a cache input: {value!r}")


def canonical_json(inputs) -> str:
    """The canonical JSON text of `inputs` (see the module docstring)."""
    return json.dumps(_canonical(inputs), sort_keys=True, separators=(",", ":"), allow_nan=False)


def cache_key(inputs) -> str:
    """SHA-256 hex digest of the canonical JSON of `inputs` and the package version."""
    text = canonical_json({"inputs": inputs, "package_version": __version__})
    return hashlib.sha256(text.encode()).hexdigest()


@dataclasses.dataclass(frozen=True)
class ResultCache:
    """A folder of cached results, one `.npz` per key in `<folder>/<key[:2]>/<key>.npz`.

    Attributes:
        folder: root folder of the cache (created on the first store).
    """

    folder: Path

    def __post_init__(self):
        object.__setattr__(self, "folder", Path(self.folder))

    def path(self, inputs) -> Path:
        """Where the result for `inputs` is (or would be) stored."""
        key = cache_key(inputs)
        return self.folder / key[:2] / f"{key}.npz"

    def load(self, inputs) -> dict[str, np.ndarray] | None:
        """The stored arrays for `inputs`, or None when missing or unreadable (then deleted)."""
        path = self.path(inputs)
        if not path.is_file():
            return None
        try:
            with np.load(path, allow_pickle=False) as archive:
                arrays = {name: archive[name] for name in archive.files}
            stored_inputs = str(arrays.pop(_INPUTS_MEMBER))
        except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as error:
            logger.warning("cache entry %s is unreadable (%s): recomputing it", path, error)
            path.unlink(missing_ok=True)
            return None
        if stored_inputs != canonical_json(inputs):
            logger.warning("cache entry %s holds other inputs: recomputing it", path)
            path.unlink(missing_ok=True)
            return None
        return arrays

    def store(self, inputs, arrays: Mapping[str, np.ndarray]) -> Path:
        """Store `arrays` for `inputs` atomically; returns the entry's path."""
        if _INPUTS_MEMBER in arrays:
            raise InputError(f"array name {_INPUTS_MEMBER!r} is reserved by the cache")
        path = self.path(inputs)
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_write(path) as temporary, open(temporary, "wb") as stream:
            # a file object: np.savez would append ".npz" to a file name
            np.savez(
                stream,
                **{_INPUTS_MEMBER: np.array(canonical_json(inputs))},
                **{name: np.asarray(array) for name, array in arrays.items()},
            )
        return path
