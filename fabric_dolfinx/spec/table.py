"""Numeric tables in CSV files with a header (a measured curve, a limb's radius profile).

Lines that start with # are comments, empty lines are skipped, the first other line is the
header (names matched without case and surrounding spaces), every further line holds numbers.
"""

import csv
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from rve_rod.errors import InputError

__all__ = ["read_table"]


def read_table(
    path: str | Path, name: str, columns: Sequence[Sequence[str]]
) -> dict[str, np.ndarray]:
    """Column name -> (rows,) values of the CSV file `path`: for each group of `columns`
    exactly one of its names must head a column (e.g. (("strain",), ("force_n_per_mm",
    "force_gf_per_cm"))). InputError naming `name`, the file and the problem otherwise."""
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            rows = list(csv.reader(line for line in handle if not line.startswith("#")))
    except OSError as error:
        raise InputError(f"{name}: {path} cannot be read ({error.strerror})") from None
    rows = [row for row in rows if any(cell.strip() for cell in row)]
    if not rows:
        raise InputError(f"{name}: {path} is empty")
    header = [cell.strip().lower() for cell in rows[0]]
    chosen = []
    for group in columns:
        found = [column for column in group if column in header]
        if len(found) != 1:
            wanted = " and ".join(" or ".join(repr(c) for c in g) for g in columns)
            raise InputError(
                f"{name}: {path} needs a header naming {wanted}; it has {', '.join(header)}"
            )
        chosen.append(found[0])
    indices = [header.index(column) for column in chosen]
    values = []
    for number, row in enumerate(rows[1:], start=2):
        try:
            values.append([float(row[index]) for index in indices])
        except (ValueError, IndexError):
            raise InputError(
                f"{name}: {path} data row {number}: {row!r} is not {len(indices)} numbers"
            ) from None
    if not values:
        raise InputError(f"{name}: {path} has no data rows")
    table = np.array(values)
    return {column: table[:, i] for i, column in enumerate(chosen)}
