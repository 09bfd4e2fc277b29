"""Typed records of a run: what each stage returns, as small dataclasses with JSON round trips.

The stage cache stores a stage's summary as JSON (`to_json`) and a cached stage is read back
with `from_json`, so `Record.from_json(record.to_json()) == record`. Records hold JSON data
only: sequences are tuples, non-finite numbers are None (NaN reads as null in JSON), nested
tables are dicts of the same; the constructor normalizes numpy values and lists to that.
Every record here is dolfinx-free: `knitmech.stages` plans the macro stage with a
`PatchJob`, and `knitmech.jobs.patch` (DOLFINx) runs it and returns a `PatchSummary`.
"""

import dataclasses
import math
import types
import typing
from dataclasses import dataclass
from typing import Any, ClassVar, Self

import numpy as np

from fabric_dolfinx.spec.tension import TensionTest
from rve_rod.jsonable import to_jsonable

__all__ = [
    "GeometrySummary",
    "JsonRecord",
    "MesoSummary",
    "PatchJob",
    "PatchSummary",
    "SurfaceSummary",
    "from_json_data",
]


def _frozen(value: Any) -> Any:
    """`value` as immutable JSON data: tuples for sequences, Python numbers, None for NaN."""
    if isinstance(value, dict):
        return {str(key): _frozen(item) for key, item in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return tuple(_frozen(item) for item in value)
    if isinstance(value, np.generic):
        return _frozen(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def from_json_data(kind: Any, data: Any) -> Any:
    """`data` (JSON values: dicts, lists, numbers, strings, None) read as the type `kind`:
    a dataclass field by field from its type hints (nested ones too; missing keys take their
    defaults), a tuple from a list, a dict's values by their type, `X | None` as X unless
    None; anything else as it is. The one reader of every JSON round trip of the pipeline."""
    if data is None:
        return None
    if typing.get_origin(kind) in (types.UnionType, typing.Union):
        kind = next((option for option in typing.get_args(kind) if _reads(option, data)), Any)
    origin, arguments = typing.get_origin(kind), typing.get_args(kind)
    if dataclasses.is_dataclass(kind) and isinstance(data, dict):
        hints = typing.get_type_hints(kind)
        values = {f.name: data[f.name] for f in dataclasses.fields(kind) if f.name in data}
        return kind(**{name: from_json_data(hints[name], value) for name, value in values.items()})
    if origin is tuple and isinstance(data, list | tuple):
        if len(arguments) == 2 and arguments[1] is Ellipsis:
            arguments = (arguments[0],) * len(data)
        return tuple(from_json_data(a, item) for a, item in zip(arguments, data, strict=True))
    if origin is dict and isinstance(data, dict):
        return {key: from_json_data(arguments[1], item) for key, item in data.items()}
    return data


def _reads(kind: Any, data: Any) -> bool:
    """Whether `from_json_data` builds a `kind` of `data` (a dataclass of a dict, a tuple of a
    list, a dict of a dict), choosing among the options of a union."""
    if dataclasses.is_dataclass(kind):
        return isinstance(data, dict)
    return {tuple: list, dict: dict}.get(typing.get_origin(kind)) is type(data)


class JsonRecord:
    """Mixin of frozen dataclasses of JSON data: normalized on construction, `to_json` gives
    a JSON-ready dict and `from_json` reads it back to an equal record.

    Fields named in `OPTIONAL` are left out of the JSON when None (a key a record of that kind
    may lack, e.g. a given surface has no RVE runs).
    """

    OPTIONAL: ClassVar[tuple[str, ...]] = ()

    def __post_init__(self):
        for field in dataclasses.fields(self):
            object.__setattr__(self, field.name, _frozen(getattr(self, field.name)))

    def to_json(self) -> dict[str, Any]:
        """The record as a dict of JSON values (lists, numbers, strings, None)."""
        data = {field.name: getattr(self, field.name) for field in dataclasses.fields(self)}
        return to_jsonable(
            {k: v for k, v in data.items() if not (v is None and k in self.OPTIONAL)}
        )

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Self:
        """The record of `to_json`'s dict (keys it lacks take their defaults)."""
        return from_json_data(cls, data)


@dataclass(frozen=True)
class GeometrySummary(JsonRecord):
    """The loop of the geometry stage (`LoopGeometry.to_dict` without the control points).

    Attributes:
        values: name -> value: wale_width, course_height, minimal_radius, adjusted_radius (mm),
            loop_length (mm), min_clearance (mm), ... (docs/geometry.md).
    """

    values: dict[str, Any]

    def to_json(self) -> dict[str, Any]:
        return to_jsonable(self.values)

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Self:
        return cls(values=data)


@dataclass(frozen=True)
class MesoSummary(JsonRecord):
    """One RVE load case of the meso stage (the full record is meso/<case>.json).

    Attributes:
        case: the load case's name.
        complete: whether every output state converged.
        message: why the run stopped early ("" when complete).
        strain: (k,) the case's control value per state (-).
        force_gf_per_cm: (k,) force per width along the load (gf/cm).
        lateral_strain: (k,) F_aa - 1 of the free component (uniaxial cases), else None.
        poisson_ratio: -lateral/strain at the last state (uniaxial cases), else None.
        newton_iterations_total: all Newton iterations of the run.
        wall_time_s: time of the run (s).
    """

    case: str
    complete: bool
    message: str
    strain: tuple[float, ...]
    force_gf_per_cm: tuple[float | None, ...]
    lateral_strain: tuple[float | None, ...] | None
    poisson_ratio: float | None
    newton_iterations_total: int
    wall_time_s: float


@dataclass(frozen=True)
class SurfaceSummary(JsonRecord):
    """The response surface of the surface stage, made from RVE runs or given by the scene.

    Attributes:
        kind: "stress" or "energy".
        domain: ((min, max) of E11, E22, E12) of the samples.
        residuals: group -> fit residual statistics (N/mm and relative).
        softest_tangents: "dS11/dE11", "dS22/dE22" -> value (N/mm), strain, largest.
        fits: (made) kind -> residuals and tangent asymmetry of both fits.
        runs: (made) number of RVE runs; runs_computed and runs_cached of them.
        incomplete_runs: (made) the runs that stopped early.
        max_stress_asymmetry: (made) largest |S12 - S21| relative to |S| of the samples.
        source: (given) the surface file the scene names.
    """

    OPTIONAL: ClassVar[tuple[str, ...]] = (
        "fits",
        "runs",
        "runs_computed",
        "runs_cached",
        "incomplete_runs",
        "max_stress_asymmetry",
        "source",
    )

    kind: str
    domain: tuple[tuple[float, float], ...]
    residuals: dict[str, Any]
    softest_tangents: dict[str, Any]
    fits: dict[str, Any] | None = None
    runs: int | None = None
    runs_computed: int | None = None
    runs_cached: int | None = None
    incomplete_runs: tuple[Any, ...] | None = None
    max_stress_asymmetry: float | None = None
    source: str | None = None


@dataclass(frozen=True)
class PatchJob(JsonRecord):
    """One patch tension test of the macro stage: the test, its load steps and its figure.

    Attributes:
        test: the tension test (direction, size, elements, max_strain, angle, degree).
        steps: equal load steps to max_strain.
        field_step: the load step whose stress map is drawn (1..steps).
    """

    test: TensionTest
    steps: int
    field_step: int

    def to_json(self) -> dict[str, Any]:
        return to_jsonable({**dataclasses.asdict(self), "test": dataclasses.asdict(self.test)})

    @property
    def field_strain(self) -> float:
        """The nominal strain of `field_step` (-)."""
        return self.field_step * self.test.max_strain / self.steps


@dataclass(frozen=True)
class PatchSummary(JsonRecord):
    """The patch tension test of one direction (`knitmech.jobs.patch.run_patch`); index 0 of every
    series is the unloaded state.

    Attributes:
        direction: "course" or "wale".
        complete: False when the solver gave up (the converged steps are kept).
        force_positive: False flags a spurious equilibrium (e.g. on a softening surface).
        message: why the solver gave up ("" when complete).
        strain: (k+1,) nominal strain (-).
        force_gf_per_cm: (k+1,) moving-clamp force per width (gf/cm).
        force_n_per_mm: the same in N/mm.
        material_uniaxial_gf_per_cm: (k+1,) the material alone in homogeneous uniaxial
            tension (gf/cm; None where no lateral strain frees the lateral stress).
        lateral_strain: (k+1,) change of the width across the middle over the size (-).
        poisson_ratio: (k+1,) -lateral_strain / strain (None at strain 0).
        gauge_strain: (k+1,) engineering strain along the load of the centre gauge
            (`knitmech.jobs.patch.GAUGE_FRACTION` x size long, through the patch's centre) (-).
        gauge_lateral_strain: (k+1,) the same across the load (-).
        newton_iterations: (k,) per converged step.
        cutbacks: failed attempts retried with a smaller step.
        outside_domain: whether strains left the surface's sampled domain.
        dofs: degrees of freedom. ranks: MPI ranks.
        solve_time_s: time of the load path (s).
        field_strain: the strain of the stress map (-).
    """

    direction: str
    complete: bool
    force_positive: bool
    message: str
    strain: tuple[float, ...]
    force_gf_per_cm: tuple[float, ...]
    force_n_per_mm: tuple[float, ...]
    material_uniaxial_gf_per_cm: tuple[float | None, ...]
    lateral_strain: tuple[float, ...]
    poisson_ratio: tuple[float | None, ...]
    gauge_strain: tuple[float, ...]
    gauge_lateral_strain: tuple[float, ...]
    newton_iterations: tuple[int, ...]
    cutbacks: int
    outside_domain: bool
    dofs: int
    ranks: int
    solve_time_s: float
    field_strain: float
