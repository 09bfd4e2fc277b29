"""The load cases of the knit RVE (design.md) as frozen dataclasses.

Every case prescribes some components of the in-plane macro deformation gradient
F = [[F11, F12], [F21, F22]] along a path from the identity, for the load factor t in [0, 1]
(a straight path F(t) = I + t (F_end - I) except the picture-frame shear), and leaves the others
free (macro unknowns whose conjugate
stress P_ab vanishes). A case's `steps` counts the output states including the unloaded one:
the default 21 steps from 0 to 20 % are 0, 1, ..., 20 % (the paper's load steps). Axis 1 is
course-wise (x, across the wales), axis 2 wale-wise (y).

| name | prescribed at t = 1 | free |
|---|---|---|
| uniaxial-course | F11 = 1 + eps | F22 (zero net force along y) |
| uniaxial-wale | F22 = 1 + eps | F11 (zero net force along x) |
| strip-biaxial-course | F11 = 1 + eps, F22 = 1 | |
| strip-biaxial-wale | F22 = 1 + eps, F11 = 1 | |
| biaxial | F11 = 1 + t_max cos(theta), F22 = 1 + t_max sin(theta) | |
| shear | F12 = F21 = g_max | |
| picture-frame-shear | F = [[1, sin(t a)], [0, cos(t a)]], a = a_max | |

The picture-frame shear turns the wale-wise lattice vector by the angle a towards the course
axis and keeps both lengths (E11 = E22 = 0, E12 = sin(a)/2): the textile picture-frame test,
and the shear run of the paper group's data (`rve_rod.rve.paper.data`). The off-diagonal
components are held at 0 except in the two shears (the loop is mirror symmetric about
the wale axis, so normal strains cause no shear stress). A negative strain is compression.
"""

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from rve_rod import limits
from rve_rod.errors import InputError, check_range
from rve_rod.limits import check_count

__all__ = [
    "CASES",
    "COMPONENTS",
    "BiaxialRay",
    "LoadCase",
    "NormalStrain",
    "PictureFrameShear",
    "Shear",
    "StripBiaxialCourse",
    "StripBiaxialWale",
    "UniaxialCourse",
    "UniaxialWale",
    "load_case",
]

COMPONENTS = ((0, 0), (0, 1), (1, 0), (1, 1))
"""The in-plane components (a, b) of F in the order F11, F12, F21, F22."""

MAX_STRAIN = 0.9
"""Largest |strain| a case accepts; beyond it a knit loop has long stopped being one."""

MAX_SHEAR_ANGLE = 1.4
"""Largest |angle| (rad, 80 degrees) of the picture-frame shear: the paper group's shear runs
go to 1.15 rad (66 degrees); at pi/2 the lattice vectors would be parallel."""


@dataclass(frozen=True)
class LoadCase:
    """Base of the load cases: a path F(t) = I + t (F_end - I) of the prescribed components.

    Attributes:
        steps: output states including the unloaded one (>= 2); state k is at
            t_k = k / (steps - 1).
    """

    steps: int = 21

    name: ClassVar[str] = ""
    """The case's name on the command line."""

    free: ClassVar[tuple[tuple[int, int], ...]] = ()
    """Components (a, b) of F that are macro unknowns with P_ab = 0."""

    def __post_init__(self):
        check_count("steps", self.steps, limits.RVE_STEPS)

    def final_deformation(self) -> np.ndarray:
        """F_end (2, 2): the prescribed components at t = 1 (free ones hold their identity
        value, which is only the initial guess)."""
        raise NotImplementedError

    def control(self) -> float:
        """The case's control variable at t = 1: eps, t_max or g_max."""
        raise NotImplementedError

    def load_factors(self) -> np.ndarray:
        """t of the output states, shape (steps,), from 0 to 1."""
        return np.linspace(0.0, 1.0, self.steps)

    def prescribed(self, load_factor: float) -> np.ndarray:
        """F(t) (2, 2) with the free components at their identity values."""
        return np.eye(2) + load_factor * (self.final_deformation() - np.eye(2))

    def load_direction(self) -> np.ndarray:
        """The unit direction D (2, 2) of the measured force P : D (N/mm): dF/dt normalized,
        with the sign of the control value, so that a uniaxial or strip case measures P11
        (P22) and a compressive one reports a negative force at a negative strain."""
        rate = self.final_deformation() - np.eye(2)
        return np.sign(self.control()) * rate / np.linalg.norm(rate)

    @property
    def lateral(self) -> tuple[int, int] | None:
        """The free normal component whose strain is the lateral strain, if any."""
        return self.free[0] if self.free else None


def _check_strain(name: str, value: float) -> float:
    number = check_range(name, value, -MAX_STRAIN, MAX_STRAIN)
    if number == 0.0:
        raise InputError(f"{name}=0 gives no load path; use a nonzero strain")
    return number


@dataclass(frozen=True)
class NormalStrain(LoadCase):
    """Base of the uniaxial and strip cases: F_aa = 1 + t max_strain along one axis a.

    Attributes:
        max_strain: eps at t = 1 (engineering strain, default 0.2; negative: compression).
    """

    max_strain: float = 0.2

    axis: ClassVar[int] = 0
    """The stretched axis: 0 course-wise (x), 1 wale-wise (y)."""

    def __post_init__(self):
        super().__post_init__()
        _check_strain("max_strain", self.max_strain)

    def final_deformation(self) -> np.ndarray:
        stretch = np.ones(2)
        stretch[self.axis] += self.max_strain
        return np.diag(stretch)

    def control(self) -> float:
        return self.max_strain


@dataclass(frozen=True)
class UniaxialCourse(NormalStrain):
    """Course-wise (x) tension: F11 = 1 + t max_strain, F22 free with zero net force along y."""

    name = "uniaxial-course"
    axis = 0
    free = ((1, 1),)


@dataclass(frozen=True)
class UniaxialWale(NormalStrain):
    """Wale-wise (y) tension: F22 = 1 + t max_strain, F11 free with zero net force along x."""

    name = "uniaxial-wale"
    axis = 1
    free = ((0, 0),)


@dataclass(frozen=True)
class StripBiaxialCourse(NormalStrain):
    """Course-wise tension with lateral contraction prevented: F11 = 1 + t eps, F22 = 1."""

    name = "strip-biaxial-course"
    axis = 0


@dataclass(frozen=True)
class StripBiaxialWale(NormalStrain):
    """Wale-wise tension with lateral contraction prevented: F22 = 1 + t eps, F11 = 1."""

    name = "strip-biaxial-wale"
    axis = 1


@dataclass(frozen=True)
class BiaxialRay(LoadCase):
    """A ray of fixed strain ratio: F11 = 1 + t t_max cos(theta), F22 = 1 + t t_max sin(theta).

    Attributes:
        angle_deg: theta in degrees (0: course-wise, 90: wale-wise, 180/270: compression).
        max_load: t_max, the length of the ray in engineering strain (default 0.2).
    """

    angle_deg: float = 45.0
    max_load: float = 0.2
    name = "biaxial"

    def __post_init__(self):
        super().__post_init__()
        check_range("angle_deg", self.angle_deg, -360.0, 360.0)
        check_range("max_load", self.max_load, 0.0, MAX_STRAIN, closed=False)

    def final_deformation(self) -> np.ndarray:
        theta = math.radians(self.angle_deg)
        return np.diag(
            [1.0 + self.max_load * math.cos(theta), 1.0 + self.max_load * math.sin(theta)]
        )

    def control(self) -> float:
        return self.max_load


@dataclass(frozen=True)
class Shear(LoadCase):
    """Pure shear F = [[1, g], [g, 1]], g from 0 to max_shear.

    Attributes:
        max_shear: g at t = 1 (default 0.3, as the paper; negative: the opposite sense).
    """

    max_shear: float = 0.3
    name = "shear"

    def __post_init__(self):
        super().__post_init__()
        _check_strain("max_shear", self.max_shear)

    def final_deformation(self) -> np.ndarray:
        return np.array([[1.0, self.max_shear], [self.max_shear, 1.0]])

    def control(self) -> float:
        return self.max_shear


@dataclass(frozen=True)
class PictureFrameShear(LoadCase):
    """Picture-frame shear F = [[1, sin(t a)], [0, cos(t a)]]: the wale-wise lattice vector
    turned by t a towards the course axis, both lattice vectors keeping their lengths, so that
    E11 = E22 = 0 and E12 = sin(t a)/2 along the whole path.

    Attributes:
        max_angle: a at t = 1 (rad, default 0.3; negative: the opposite sense), below pi/2.
    """

    max_angle: float = 0.3
    name = "picture-frame-shear"

    def __post_init__(self):
        super().__post_init__()
        check_range("max_angle", self.max_angle, -MAX_SHEAR_ANGLE, MAX_SHEAR_ANGLE)
        if self.max_angle == 0.0:
            raise InputError("max_angle=0 gives no load path; use a nonzero angle")

    def final_deformation(self) -> np.ndarray:
        return self.prescribed(1.0)

    def prescribed(self, load_factor: float) -> np.ndarray:
        angle = load_factor * self.max_angle
        return np.array([[1.0, math.sin(angle)], [0.0, math.cos(angle)]])

    def load_direction(self) -> np.ndarray:
        """dF/da at a = 0 (the shear F12), signed like the angle: the measured force is P12."""
        return math.copysign(1.0, self.max_angle) * np.array([[0.0, 1.0], [0.0, 0.0]])

    def control(self) -> float:
        return self.max_angle


CASES = {
    case.name: case
    for case in (
        UniaxialCourse,
        UniaxialWale,
        StripBiaxialCourse,
        StripBiaxialWale,
        BiaxialRay,
        Shear,
        PictureFrameShear,
    )
}
"""The load case classes by name."""


def load_case(name: str, strain: float | None = None, steps: int = 21, angle_deg: float = 0.0):
    """The case `name` (a key of CASES) to `strain` (eps, t_max or g; None: the case's
    default) in `steps` output states; `angle_deg` is the ray direction of "biaxial"."""
    if name not in CASES:
        raise InputError(f"case={name!r} is unknown; valid cases: {', '.join(CASES)}")
    kwargs: dict = {"steps": steps}
    if name == "biaxial":
        kwargs["angle_deg"] = angle_deg
        if strain is not None:
            kwargs["max_load"] = strain
    elif strain is not None:
        key = {"shear": "max_shear", "picture-frame-shear": "max_angle"}.get(name, "max_strain")
        kwargs[key] = strain
    return CASES[name](**kwargs)
