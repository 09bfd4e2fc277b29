"""The family of a knit's response surfaces in the stitch value, evaluated with NumPy.

A family holds the surfaces of one knit at a few stitch values s_0 < s_1 < ... < s_n (the
preset's measured values, each surface made by a surface stage) together with each member's
wale width w and course height c (mm). At a stitch value s its law is the graded law of
`fabric_dolfinx.graded`,

    S(E; s) = sum_k N_k(s) S_k(E),

with N_k the hat functions on the members' stitch values (`graded.stitch_weights`; constant
beyond the ends), and its loop geometry is interpolated with the same weights,
w(s) = sum_k N_k(s) w_k, c(s) = sum_k N_k(s) c_k. The weights and the weighted sum are those
the membrane evaluates at its quadrature points (`fabric_dolfinx.graded`, NumPy only). No
DOLFINx here: the design's cheap models (the material's uniaxial curves, the sleeve's Laplace
law) evaluate the family with NumPy, in microseconds per strain.
"""

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fabric_dolfinx.graded import graded_stress, stitch_weights
from rve_rod.errors import InputError
from rve_rod.surface import ResponseSurface, StressResult, homogeneous_response, read_surface

__all__ = [
    "FamilyLaw",
    "FamilyMember",
    "SurfaceFamily",
]


@dataclass(frozen=True)
class FamilyMember:
    """One member of a family.

    Attributes:
        stitch: the stitch value (mm).
        path: its response-surface file.
        wale_width, course_height: the knit's loop width w and height c at rest (mm).
    """

    stitch: float
    path: str
    wale_width: float
    course_height: float


@dataclass(frozen=True)
class FamilyLaw:
    """The family's law at one stitch value: an object with `stress(E)` like a
    `ResponseSurface` (what `homogeneous_response` needs).

    Attributes:
        surfaces: the members' surfaces; weights: (n,) their weights at the stitch value.
    """

    surfaces: tuple[ResponseSurface, ...]
    weights: np.ndarray

    def stress(self, E: np.ndarray) -> StressResult:
        """S (m, 3), dS/dE (m, 3, 3) and `outside` (m,) at strains E (m, 3) or (3,): the
        weighted sum over the members that act (outside where any of them is)."""
        return graded_stress([surface.stress for surface in self.surfaces], self.weights, E)


@dataclass(frozen=True)
class SurfaceFamily:
    """A knit's surfaces at increasing stitch values, with their loop geometry.

    Attributes:
        members: the members, by increasing stitch value.
        surfaces: their response surfaces (read from the members' files when not given).
    """

    members: tuple[FamilyMember, ...]
    surfaces: tuple[ResponseSurface, ...] = field(default=())

    def __post_init__(self):
        members = tuple(sorted(self.members, key=lambda member: member.stitch))
        if not members:
            raise InputError("a family needs at least one member")
        stitches = [member.stitch for member in members]
        if np.any(np.diff(stitches) <= 0.0):
            raise InputError(f"family members' stitch values {stitches} must differ")
        surfaces = self.surfaces
        if not surfaces:
            surfaces = tuple(read_surface(Path(member.path)) for member in members)
        elif len(surfaces) != len(members):
            raise InputError(f"{len(surfaces)} surfaces for {len(members)} family members")
        object.__setattr__(self, "members", members)
        object.__setattr__(self, "surfaces", tuple(surfaces))

    @property
    def stitch_values(self) -> np.ndarray:
        """(n,) the members' stitch values (mm)."""
        return np.array([member.stitch for member in self.members])

    @property
    def stitch_range(self) -> tuple[float, float]:
        """(smallest, largest) stitch value of the family (mm)."""
        return float(self.stitch_values[0]), float(self.stitch_values[-1])

    @property
    def domain(self) -> np.ndarray:
        """(3, 2) the strains where every member rests on data: the intersection of the
        members' domains (E11, E22, E12 min and max)."""
        stacked = np.stack([surface.domain for surface in self.surfaces])
        return np.column_stack([stacked[:, :, 0].max(axis=0), stacked[:, :, 1].min(axis=0)])

    def check_stitch(self, name: str, stitch: float) -> float:
        """`stitch` as float, or InputError naming `name` when it leaves the family's range."""
        low, high = self.stitch_range
        if not np.isfinite(stitch) or not low - 1e-12 <= stitch <= high + 1e-12:
            raise InputError(
                f"{name}={stitch!r} mm is outside the family's range [{low:g}, {high:g}] mm"
            )
        return float(stitch)

    def weights(self, stitch: float) -> np.ndarray:
        """(n,) the members' weights N_k at `stitch` (mm)."""
        return stitch_weights(self.stitch_values, stitch)

    def law(self, stitch: float) -> FamilyLaw:
        """The family's law at `stitch` (mm)."""
        return FamilyLaw(self.surfaces, self.weights(stitch))

    def wale_width(self, stitch: float) -> float:
        """w(s) (mm): the members' wale widths interpolated with the law's weights."""
        return float(self.weights(stitch) @ [m.wale_width for m in self.members])

    def course_height(self, stitch: float) -> float:
        """c(s) (mm): the members' course heights interpolated with the law's weights."""
        return float(self.weights(stitch) @ [m.course_height for m in self.members])

    def uniaxial(self, stitch: float, strain: np.ndarray, direction: str) -> np.ndarray:
        """(m,) force per width (N/mm) in homogeneous uniaxial tension (lateral stress 0,
        `rve_rod.surface.homogeneous_response`) at engineering `strain` (m,) along
        `direction` ("course" or "wale"), of the law at `stitch` (mm)."""
        return homogeneous_response(self.law(stitch), np.asarray(strain, float), direction)
