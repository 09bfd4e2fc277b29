"""The load paths sampled to fit a response surface: biaxial rays and pure shear (design.md).

A biaxial ray of direction theta prescribes F11 = 1 + t cos(theta), F22 = 1 + t sin(theta)
(engineering strains along a fixed ratio, F12 = F21 = 0); pure shear prescribes
F = [[1, g], [g, 1]]. The rays are spread evenly over an angle range (by default the full circle,
so tension, compression and mixed states are all sampled) and each one ends where the first
engineering strain component reaches the tension limit or the compression limit, so the ray
ends lie on the box [-max_compression, max_tension]^2. The RVE follows a ray as far as the
cell supports it (a run that stops early keeps its converged steps).

The box must hold the states a tensile test passes through: a knit pulled along one direction
narrows across it by up to nu x strain (nu up to 0.9 for a jersey knit wale-wise). A plan
without a compression limit follows the fabric: its two `contraction_paths` (uniaxial tension
to max_tension, the stress across free) are run first, and `following` sets the limit to
`compression_box` of the contraction they show for the rays with a component in tension, and
to MIN_COMPRESSION for the others (`slack_compression`).
"""

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from rve_rod import limits
from rve_rod.errors import InputError, check_integer, check_range
from rve_rod.limits import check_count

__all__ = [
    "CONTRACTION_MARGIN",
    "MIN_COMPRESSION",
    "LoadPath",
    "SamplingPlan",
    "compression_box",
    "contraction",
]

LOAD_KINDS = ("biaxial", "shear", "uniaxial")

UNIAXIAL_ANGLES = (0.0, 90.0)
"""Directions of the uniaxial paths: course-wise (along x) and wale-wise (along y)."""

CONTRACTION_MARGIN = 1.25
"""How far the sampled box reaches beyond the fabric's own contraction in uniaxial tension: the
clamped patch narrows more next to its free edges than the fabric pulled alone (measured on the
50 mm patch of cotton stitch 5.5 at 20 %, free-fibre bending: 1.07 times course-wise, 1.12 times
wale-wise; docs/pipeline.md)."""

MIN_COMPRESSION = 0.10
"""The smallest compression limit of a box that follows the fabric (-), and its limit for the
rays with no component in tension (the slack states that shear and buckled regions of a part
pass through; further out a knit buckles out of plane, no tensile test goes there, and the
cell's runs there are the hardest: cotton 20s/2 stitch 4.5-7.0 at the fast level, equibiaxial
compression to 0.20 took up to 24.7 s and 16 cutbacks and stopped, course-wise compression
to 0.25 stopped at 0.05)."""


@dataclass(frozen=True)
class LoadPath:
    """One RVE run: a straight path in engineering-strain space from the reference state.

    Attributes:
        kind: "biaxial" (a ray), "shear" or "uniaxial" (tension along angle_deg 0 (x) or
            90 (y) with the stress across it free: the RVE finds the stretch across).
        angle_deg: ray direction theta in degrees (biaxial, uniaxial); 0 for shear.
        max_load: final load factor t (biaxial), shear g or engineering strain (uniaxial)
            (dimensionless).
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
        if self.kind == "uniaxial" and self.angle_deg not in UNIAXIAL_ANGLES:
            raise InputError(f"angle_deg={self.angle_deg} must be 0 or 90 for uniaxial")
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
        """The prescribed F at the output steps, shape (steps, 2, 2); of a uniaxial path only
        the stretch along the load is prescribed (the one across is 1 here)."""
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
            0.10); rays end on the box [-max_compression, max_tension]^2. None: follow the
            fabric's contraction (`following`).
        slack_compression: the compression limit of the rays with no component in tension
            (biaxial compression, where a knit buckles and a tensile test never goes); None
            (default): max_compression. `following` sets it to MIN_COMPRESSION.
        steps_per_ray: output steps of each ray (default 10).
        max_shear: final shear g of the pure-shear run (default 0.30, as the paper).
        shear_steps: output steps of the shear run (default 15).
    """

    rays: int = 16
    angle_range_deg: tuple[float, float] = (0.0, 360.0)
    max_tension: float = 0.20
    max_compression: float | None = 0.10
    slack_compression: float | None = None
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
        for name in ("max_compression", "slack_compression"):
            if getattr(self, name) is not None:
                check_range(name, getattr(self, name), 0.0, 0.5)
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
        components = (math.cos(theta), math.sin(theta))
        compression = self.max_compression
        if self.slack_compression is not None and max(components) <= 1e-12:
            compression = self.slack_compression
        lengths = []
        for component in components:
            if component > 1e-12:
                lengths.append(self.max_tension / component)
            elif component < -1e-12:
                lengths.append(compression / -component)
        return min(lengths)

    def contraction_paths(self) -> tuple[LoadPath, ...]:
        """Uniaxial tension course-wise and wale-wise to max_tension, in steps_per_ray steps:
        the runs whose contraction a plan without a compression limit follows."""
        return tuple(
            LoadPath("uniaxial", angle, self.max_tension, self.steps_per_ray)
            for angle in UNIAXIAL_ANGLES
        )

    def following(self, runs) -> "SamplingPlan":
        """This plan with max_compression = `compression_box` of the contraction the runs
        (RveRun, one per `contraction_paths`) show, where one component is in tension (the
        states of a tensile test), and MIN_COMPRESSION where none is."""
        box = compression_box(contraction(self.contraction_paths(), runs))
        return dataclasses.replace(
            self, max_compression=box, slack_compression=min(MIN_COMPRESSION, box)
        )

    def load_paths(self) -> tuple[LoadPath, ...]:
        """The rays that have a nonzero length, then the shear run."""
        if self.max_compression is None:
            raise InputError(
                "the sampling plan has no max_compression: resolve it with following() "
                "from the runs of contraction_paths()"
            )
        rays = [
            LoadPath("biaxial", float(angle), self.ray_length(angle), self.steps_per_ray)
            for angle in self.angles_deg()
            if self.ray_length(angle) > 0.0
        ]
        shear = LoadPath("shear", 0.0, self.max_shear, self.shear_steps)
        return (*rays, shear)


def contraction(paths: tuple[LoadPath, ...], runs) -> float:
    """The largest narrowing -(F_across - 1) (engineering strain, >= 0) of uniaxial runs at
    their paths' end; a run that stopped early is extrapolated linearly from its last state
    (a run with no converged state counts as not narrowing)."""
    largest = 0.0
    for path, run in zip(paths, runs, strict=True):
        if path.kind != "uniaxial":
            raise InputError(f"contraction needs uniaxial paths, not {path.kind!r}")
        F = run.deformation_gradient
        if F.shape[0] == 0:
            continue
        along = 0 if path.angle_deg == 0.0 else 1
        reached = F[-1, along, along] - 1.0
        narrowing = 1.0 - F[-1, 1 - along, 1 - along]
        largest = max(largest, narrowing * path.max_load / reached)
    return largest


def compression_box(narrowing: float) -> float:
    """The compression limit of a box that follows a fabric narrowing by `narrowing`
    (engineering strain) in uniaxial tension: CONTRACTION_MARGIN times it, rounded up to a
    multiple of 0.05 (nearby fabrics and levels share a box), at least MIN_COMPRESSION and at
    most 0.5."""
    step = 0.05
    reach = math.ceil(round(CONTRACTION_MARGIN * narrowing / step, 9)) * step
    return round(min(max(MIN_COMPRESSION, reach), 0.5), 9)
