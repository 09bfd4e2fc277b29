"""The cached numba typing of the kernels' records (rve_rod._kernels.record) gives the types
numba's own typing gives, for every layout, dtype and writeability of the fields."""

from typing import NamedTuple

import numpy as np
import pytest
from numba.core import types
from numba.core.typing.typeof import Purpose, typeof

from rve_rod._kernels import record
from rve_rod.contact._kernels import StrandLocations
from rve_rod.rod._kernels import PointEquations


def numba_typing(value):
    """The type numba gives a tuple without the registered typing (field by field)."""
    fields = [typeof(field, Purpose.argument) for field in value]
    return types.BaseTuple.from_types(fields, type(value))


def variants(base):
    """`base` and copies whose first 2-D field is Fortran-ordered, strided or read-only."""
    name = next(name for name, field in zip(base._fields, base, strict=True) if field.ndim >= 2)
    field = getattr(base, name)
    fortran = np.asfortranarray(np.empty((*field.shape, 2), dtype=field.dtype))[..., 0]
    strided = np.empty((*field.shape, 2), dtype=field.dtype)[..., 0]
    frozen = field.copy()
    frozen.flags.writeable = False
    return [base, *(base._replace(**{name: other}) for other in (fortran, strided, frozen))]


def point_equations():
    shapes = ((18, 5), (7, 5), (6, 5), (7, 18, 5), (6, 18, 5))
    return PointEquations(*(np.empty(shape) for shape in shapes))


def strand_locations():
    return StrandLocations(
        np.empty(4, np.int64),
        np.empty(4),
        np.empty((4, 2), np.int64),
        np.empty(4),
        np.empty(4),
        np.empty((3, 4)),
    )


@pytest.mark.parametrize("make", [point_equations, strand_locations])
def test_record_types_are_numbas_own(make):
    found = set()
    for _ in range(2):  # the second round is served by the cache
        for value in variants(make()):
            typed = typeof(value, Purpose.argument)
            assert typed == numba_typing(value)
            found.add(typed)
    assert len(found) == 4  # the layouts and the read-only field are told apart


def test_a_record_with_a_scalar_field_is_typed_as_usual():
    @record
    class Mixed(NamedTuple):
        values: np.ndarray
        count: int

    for value in (Mixed(np.zeros(3), 2), Mixed(np.zeros(3), 2.5)):
        assert typeof(value, Purpose.argument) == numba_typing(value)
