"""The checks every table of a scene (and of a sweep or design file) shares: unknown keys,
numbers and (x, y, z) triples. Each appends the problems it finds to the caller's list, naming
the key in full (`fabric.shape.width`), so that one error reports every problem of a file at
once. `read_toml` reads such a file."""

import math
import tomllib
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from rve_rod.errors import InputError

__all__ = [
    "check_keys",
    "describe",
    "number",
    "read_toml",
    "triple",
    "unknown_key",
]


def describe(value: Any) -> str:
    """`value` for a message: its type and its repr (`int 5`, `str 'high'`)."""
    return f"{type(value).__name__} {value!r}"


def unknown_key(key: str, valid: Iterable[str]) -> str:
    """The problem of the unknown key `key` (named in full), listing the valid ones."""
    return f"{key}: unknown key (valid: {', '.join(valid)})"


def check_keys(prefix: str, table: dict, valid: Iterable[str], problems: list[str]) -> None:
    """A problem for every key of `table` (the table `prefix`) that is not in `valid`."""
    valid = tuple(valid)
    problems.extend(unknown_key(f"{prefix}.{key}", valid) for key in table if key not in valid)


def number(
    key: str, value: Any, problems: list[str], low: float = -math.inf, high: float = math.inf
) -> float | None:
    """`value` as a finite float in (low, high] (default: any finite number), or None and a
    problem naming `key`."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        problems.append(f"{key}: expected a number, got {describe(value)}")
    elif not math.isfinite(value):
        problems.append(f"{key}: expected a finite number, got {value!r}")
    elif not low < value <= high:
        problems.append(f"{key}: {value} is outside the valid range ({low}, {high}]")
    else:
        return float(value)
    return None


def triple(key: str, value: Any, problems: list[str]) -> tuple[float, float, float] | None:
    """`value` as three finite floats (x, y, z), or None and a problem naming `key`."""
    if (
        not isinstance(value, list)
        or len(value) != 3
        or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in value)
        or not all(math.isfinite(v) for v in value)
    ):
        problems.append(f"{key}: expected three numbers [x, y, z], got {value!r}")
        return None
    return tuple(float(v) for v in value)


def read_toml(path: Path, kind: str) -> dict:
    """The parsed TOML of the `kind` file ("scene file", "sweep file", ...) at `path`;
    InputError naming it when it cannot be read or is not TOML."""
    try:
        return tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as error:
        raise InputError(f"{kind} {path}: cannot be read ({error.strerror})") from None
    except tomllib.TOMLDecodeError as error:
        raise InputError(f"{kind} {path}: not valid TOML ({error})") from None
