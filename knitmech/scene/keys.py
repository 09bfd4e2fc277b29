"""The checks every table of a scene (and of a sweep or design file) shares: unknown keys,
numbers and (x, y, z) triples. Each appends the problems it finds to the caller's list, naming
the key in full (`fabric.shape.width`), so that one error reports every problem of a file at
once. `read_toml` reads such a file."""

import codecs
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


_BOMS = (
    (codecs.BOM_UTF8, "utf-8-sig"),
    (codecs.BOM_UTF16_LE, "utf-16"),
    (codecs.BOM_UTF16_BE, "utf-16"),
)


def read_toml(path: Path, what: str) -> dict:
    """The TOML file at `path` (a "scene file", a "sweep file") parsed, or InputError naming
    it and what is wrong: unreadable, not text, not TOML. UTF-8 is TOML's encoding; a file
    that an editor saved with a byte-order mark (UTF-8, or UTF-16 as Windows' "Unicode") is
    read too (before, a UTF-8 mark gave "Invalid statement (at line 1, column 1)" and UTF-16
    a UnicodeDecodeError traceback)."""
    try:
        data = path.read_bytes()
    except OSError as error:
        raise InputError(f"{what} {path}: cannot be read ({error.strerror})") from None
    encoding = next((name for mark, name in _BOMS if data.startswith(mark)), "utf-8")
    try:
        text = data.decode(encoding)
    except UnicodeDecodeError as error:
        raise InputError(
            f"{what} {path}: not UTF-8 text (byte 0x{data[error.start]:02x} at offset "
            f"{error.start}); save it as UTF-8"
        ) from None
    if "\x00" in text:
        raise InputError(
            f"{what} {path}: not UTF-8 text (it holds NUL bytes: UTF-16 without its "
            "byte-order mark, or not text); save it as UTF-8"
        )
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise InputError(f"{what} {path}: not valid TOML ({error})") from None
