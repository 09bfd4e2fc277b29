"""Conversion of results to plain JSON data: numpy values to Python numbers, NaN to null.

Every JSON record of the project (command-line `--json` output, the pipeline's stage
summaries and results folder, the RVE records) goes through `to_jsonable`, so that numpy
scalars and arrays, tuples and non-finite floats are written the same way everywhere.
"""

import math

import numpy as np

__all__ = ["to_jsonable"]


def to_jsonable(value):
    """`value` with numpy scalars and arrays as Python numbers and lists, tuples as lists,
    dict keys as strings and non-finite floats (NaN, inf) as None; other values unchanged."""
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, np.generic):
        return to_jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
