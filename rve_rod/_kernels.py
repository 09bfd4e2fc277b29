"""What the numba kernels of `rve_rod` share: a fast typing of their records.

The kernels take NamedTuples of arrays ("records", e.g. `rve_rod.rod._kernels.PointEquations`).
numba's dispatcher types a NamedTuple argument in Python at every call, array by array (its C
fast path knows plain arrays and plain tuples only): 40 us for a record of five arrays, 88 us
a call on average in the reference RVE run, more than many of the kernels take (21 us with
the cache, timer included; docs/benchmarks.md). `record` registers for a record class a
typing that looks its type up by the properties of its arrays that numba's typing of an array
reads (dtype, dimension, layout, writeability: numba.core.typing.typeof._typeof_ndarray), and
types it the usual way the first time a combination is seen.
"""

from numba.core import types
from numba.extending import typeof_impl

__all__ = ["record"]


def record(cls):
    """Class decorator: numba types arguments of the NamedTuple class `cls` through a cache
    (module docstring). Records with a field that is not an array are typed as usual."""
    known = {}

    @typeof_impl.register(cls)
    def _typeof_record(value, context):
        try:
            key = tuple(
                (
                    field.dtype,
                    field.ndim,
                    field.flags.c_contiguous,
                    field.flags.f_contiguous,
                    field.flags.writeable,
                )
                for field in value
            )
        except AttributeError:  # a field that is not an array
            key = None
        found = known.get(key) if key is not None else None
        if found is None:
            fields = [typeof_impl(field, context) for field in value]
            if any(field is None for field in fields):
                return None
            found = types.BaseTuple.from_types(fields, type(value))
            if key is not None:
                known[key] = found
        return found

    return cls
