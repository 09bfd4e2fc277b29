"""A body of revolution about the z axis: its radius profile r(z) from a table, without DOLFINx.

The table's points (z_i, r_i) (mm, z increasing, r > 0) are joined by the shape-preserving
piecewise-cubic Hermite interpolant (PCHIP: no overshoot between points, continuous slope), and
beyond the table the radius continues along the end tangents (linear, C1). The profile is held
as its polynomial pieces r(z) = sum_j a_ij (z - z_i)^j on [z_i, z_i+1] (`pieces`), so that NumPy
(`radius`, `slope`) and the UFL of the rigid body (`membrane.loads.RevolutionIndenter`)
evaluate the same function. Used for limbs (a compression sleeve's leg) and for the expanding
mandrel that draws a tube over one.
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.interpolate

from fabric_dolfinx.spec.table import read_table
from rve_rod.errors import InputError

__all__ = [
    "RadiusProfile",
    "read_profile",
]


@dataclass(frozen=True)
class RadiusProfile:
    """r(z) of a body of revolution about the z axis (module docstring).

    Attributes:
        z: (n,) the table's axial positions (mm), increasing, n >= 2.
        r: (n,) the radii there (mm), > 0.
    """

    z: tuple[float, ...]
    r: tuple[float, ...]

    def __post_init__(self):
        z, r = np.asarray(self.z, dtype=float), np.asarray(self.r, dtype=float)
        if z.ndim != 1 or z.shape != r.shape or z.size < 2:
            raise InputError(
                f"a radius profile needs >= 2 points (z, r), got {z.size} z and {r.size} r"
            )
        if not (np.all(np.isfinite(z)) and np.all(np.isfinite(r))):
            raise InputError("a radius profile's z and r must be finite numbers (mm)")
        if np.any(np.diff(z) <= 0.0):
            raise InputError(f"a radius profile's z={z.tolist()} mm must increase")
        if np.any(r <= 0.0):
            raise InputError(f"a radius profile's r={r.tolist()} mm must be > 0")
        object.__setattr__(self, "z", tuple(z.tolist()))
        object.__setattr__(self, "r", tuple(r.tolist()))

    @property
    def extent(self) -> tuple[float, float]:
        """(first, last) z of the table (mm)."""
        return self.z[0], self.z[-1]

    def pieces(self) -> np.ndarray:
        """(n - 1, 4) coefficients a_ij of r(z) = sum_j a_ij (z - z_i)^j on [z_i, z_i+1]."""
        z, r = np.asarray(self.z), np.asarray(self.r)
        if z.size == 2:
            slope = (r[1] - r[0]) / (z[1] - z[0])
            return np.array([[r[0], slope, 0.0, 0.0]])
        cubic = scipy.interpolate.PchipInterpolator(z, r)
        # PPoly holds c[k, i] for (z - z_i)^(3 - k)
        return cubic.c[::-1].T.copy()

    def end_slopes(self) -> tuple[float, float]:
        """dr/dz at the table's first and last point (the extensions' slopes)."""
        pieces = self.pieces()
        length = self.z[-1] - self.z[-2]
        last = pieces[-1]
        return float(pieces[0, 1]), float(last[1] + 2 * last[2] * length + 3 * last[3] * length**2)

    def radius(self, z: np.ndarray) -> np.ndarray:
        """r(z) (mm) at axial positions z (any shape, mm)."""
        return self._evaluate(np.asarray(z, dtype=float), 0)

    def slope(self, z: np.ndarray) -> np.ndarray:
        """dr/dz (-) at axial positions z (any shape, mm)."""
        return self._evaluate(np.asarray(z, dtype=float), 1)

    def curvature(self, z: np.ndarray) -> np.ndarray:
        """The meridian's curvature -r'' / (1 + r'^2)^(3/2) (1/mm) at z: positive where the
        body bulges (a calf), 0 beyond the table."""
        z = np.asarray(z, dtype=float)
        return -self._evaluate(z, 2) / (1.0 + self.slope(z) ** 2) ** 1.5

    def _evaluate(self, z: np.ndarray, derivative: int) -> np.ndarray:
        knots = np.asarray(self.z)
        pieces = self.pieces()
        index = np.clip(np.searchsorted(knots, z, side="right") - 1, 0, knots.size - 2)
        offset = z - knots[index]
        a = pieces[index.ravel()].reshape(*z.shape, 4)
        first, last = self.extent
        start, end = self.end_slopes()
        if derivative == 0:
            inside = a[..., 0] + offset * (a[..., 1] + offset * (a[..., 2] + offset * a[..., 3]))
            below = self.r[0] + start * (z - first)
            above = self.r[-1] + end * (z - last)
        elif derivative == 1:
            inside = a[..., 1] + offset * (2 * a[..., 2] + offset * 3 * a[..., 3])
            below, above = np.full(z.shape, start), np.full(z.shape, end)
        else:
            inside = 2 * a[..., 2] + 6 * a[..., 3] * offset
            below = above = np.zeros(z.shape)
        return np.where(z < first, below, np.where(z > last, above, inside))


def read_profile(path: str | Path, name: str = "profile") -> RadiusProfile:
    """The RadiusProfile of a CSV file with the header `z_mm, radius_mm` (or `z_mm,
    circumference_mm`, a tape measure's reading: r = C / 2 pi); InputError naming `name`,
    the file and the problem otherwise (`fabric_dolfinx.spec.table`)."""
    table = read_table(path, name, (("z_mm",), ("radius_mm", "circumference_mm")))
    radius = table.get("radius_mm")
    if radius is None:
        radius = table["circumference_mm"] / (2 * np.pi)
    try:
        return RadiusProfile(tuple(table["z_mm"]), tuple(radius))
    except InputError as error:
        raise InputError(f"{name}: {path}: {error}") from None
