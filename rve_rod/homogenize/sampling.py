"""The load paths sampled to fit a response surface: biaxial rays and pure shear (design.md).

A biaxial ray of direction theta prescribes F11 = 1 + t cos(theta), F22 = 1 + t sin(theta)
(engineering strains along a fixed ratio, F12 = F21 = 0); pure shear prescribes
F = [[1, g], [g, 1]]. The rays are spread evenly over an angle range (by default the full circle,
so tension, compression and mixed states are all sampled) and each one ends where the first
engineering strain component reaches the tension limit or the compression limit, so the ray
ends lie on the box [-max_compression, max_tension]^2. The RVE follows a ray as far as the
cell supports it (a run that stops early keeps its converged steps).
"""

import math
from dataclasses import dataclass

import numpy as np

from rve_rod import limits
from rve_rod.errors import InputError, check_integer, check_range
from rve_rod.limits import check_count

__all__ = [
    "LoadPath",
    "SamplingPlan",
]

LOAD_KINDS = ("biaxial", "shear")


@dataclass(frozen=True)
class LoadPath:
    """One RVE run: a straight path in engineering-strain space from the reference state.

    Attributes:
        kind: "biaxial" (a ray) or "shear".
        angle_deg: ray direction theta in degrees (biaxial); 0 for shear.
        max_load: final load factor t (biaxial) or shear g (dimensionless).
        steps: number of output steps after the reference state, at t_k = k max_load / steps.
    """

    kind: str
    angle_deg: float
    max_load: float
    steps: int

    def __post_init__(self):
        if self.kind not in LOAD_KINDS:
            raise InputError(f"load kind={self.kind!r} must be one of {LOAD_KINDS}")
        check_range("max_load", self.max_load, 0.0, 10.0, closed=False)
        check_integer("steps", self.steps, 1)
        if self.kind == "shear" and self.angle_deg != 0:
            raise InputError(f"angle_deg={self.angle_deg} must be 0 for shear")
        final = self.deformation_gradients()[-1]
        if np.linalg.det(final) <= 0.0 or min(final[0, 0], final[1, 1]) <= 0.0:
            raise InputError(
                f"{self.kind} path to max_load={self.max_load} at {self.angle_deg} deg ends at "
                f"F = {final.tolist()}: stretches and det F must stay > 0"
            )

    def load_factors(self) -> np.ndarray:
        """t_k (or g_k) of the output steps k = 1..steps, shape (steps,)."""
        return self.max_load * np.arange(1, self.steps + 1) / self.steps

    def deformation_gradients(self) -> np.ndarray:
        """The prescribed F at the output steps, shape (steps, 2, 2)."""
        factors = self.load_factors()
        F = np.zeros((factors.size, 2, 2))
        if self.kind == "shear":
            F[:, 0, 0] = F[:, 1, 1] = 1.0
            F[:, 0, 1] = F[:, 1, 0] = factors
        else:
            theta = math.radians(self.angle_deg)
            F[:, 0, 0] = 1.0 + factors * math.cos(theta)
            F[:, 1, 1] = 1.0 + factors * math.sin(theta)
        return F


@dataclass(frozen=True)
class SamplingPlan:
    """Which RVE runs a response surface is fitted to.

    Attributes:
        rays: number of biaxial rays (>= 3).
        angle_range_deg: (first, last) ray angle in degrees; a range of 360 degrees is the full
            circle (last angle excluded), otherwise both ends are included. Default: full
            circle, 16 rays (every 22.5 degrees, including the course-wise (0), wale-wise (90)
            and the two compression (180, 270) directions).
        max_tension: largest engineering strain of a component in tension (default 0.20, the
            paper's 0-20 % range).
        max_compression: largest engineering strain of a component in compression (default
            0.10); rays end on the box [-max_compression, max_tension]^2.
        steps_per_ray: output steps of each ray (default 10).
        max_shear: final shear g of the pure-shear run (default 0.30, as the paper).
        shear_steps: output steps of the shear run (default 15).
    """

    rays: int = 16
    angle_range_deg: tuple[float, float] = (0.0, 360.0)
    max_tension: float = 0.20
    max_compression: float = 0.10
    steps_per_ray: int = 10
    max_shear: float = 0.30
    shear_steps: int = 15

    def __post_init__(self):
        check_integer("rays", self.rays, 3, limits.RAYS[1])
        first, last = (float(a) for a in self.angle_range_deg)
        if not 0.0 < last - first <= 360.0:
            raise InputError(
                f"angle_range_deg={self.angle_range_deg} must satisfy first < last <= first + 360"
            )
        object.__setattr__(self, "angle_range_deg", (first, last))
        check_range("max_tension", self.max_tension, 0.0, 0.9, closed=False)
        check_range("max_compression", self.max_compression, 0.0, 0.5)
        check_count("steps_per_ray", self.steps_per_ray, limits.STEPS_PER_RAY)
        check_range("max_shear", self.max_shear, 0.0, 0.9, closed=False)
        check_count("shear_steps", self.shear_steps, limits.STEPS_PER_RAY)

    def angles_deg(self) -> np.ndarray:
        """The ray angles in degrees, shape (rays,)."""
        first, last = self.angle_range_deg
        full_circle = math.isclose(last - first, 360.0)
        return np.linspace(first, last, self.rays, endpoint=not full_circle)

    def ray_length(self, angle_deg: float) -> float:
        """Largest t of the ray: where the first component reaches a strain limit (or 0)."""
        theta = math.radians(angle_deg)
        lengths = []
        for component in (math.cos(theta), math.sin(theta)):
            if component > 1e-12:
                lengths.append(self.max_tension / component)
            elif component < -1e-12:
                lengths.append(self.max_compression / -component)
        return min(lengths)

    def load_paths(self) -> tuple[LoadPath, ...]:
        """The rays that have a nonzero length, then the shear run."""
        rays = [
            LoadPath("biaxial", float(angle), self.ray_length(angle), self.steps_per_ray)
            for angle in self.angles_deg()
            if self.ray_length(angle) > 0.0
        ]
        shear = LoadPath("shear", 0.0, self.max_shear, self.shear_steps)
        return (*rays, shear)
