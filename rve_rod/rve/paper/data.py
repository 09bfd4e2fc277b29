"""The paper group's own RVE output for cotton single jersey, read and checked for convergence.

H. Do, Y. Y. Tan, N. Ramos, J. Kiendl, O. Weeger, "Nonlinear isogeometric multiscale simulation
for design and fabrication of functionally graded knitted textiles", Composites Part B 202,
108416 (2020); data set CPShub/sim-data, folder data/graded_knitted_textiles/, licence CC BY 4.0.
The files of stitch values 4.5, 5.5 and 6.5 are shipped unchanged in
`rve_rod/data/weeger_group_rve/` (its README: layout, licence, attribution). They are the output
of the rod RVE this package implements (Weeger et al.), for the cotton 20s/2 fabrics of our
presets, and the reference our RVE is judged by (docs/validation.md, "The paper group's RVE").

* Biaxial rays (`rsLLL_ba_EPS.dat`): F = diag(1 + t e1, 1 + t e2) at t = k/20, k = 1..20, along
  12 directions (e1, e2) of engineering strain; the file's first row of each ray (t = 0.005,
  S = 0) is a placeholder and is dropped.
* Shear (`rsLLL_ps_EPS.dat`): the picture-frame shear F = [[1, sin a], [0, cos a]] at
  a = k a1, k = 1..20 (rad): E11 = E22 = 0, E12 = sin(a)/2 (`load_cases.PictureFrameShear`).
* Their run failed where P stops equalling F S: beyond, S was extrapolated to fill their
  surface. A state counts as converged when every component of P - F S is within
  `CONVERGED_TOLERANCE` of the largest |P| of the run up to it; the states of a run up to the
  first that is not are its converged prefix (`converged`), and only those are compared.

Stresses are N/mm (membrane forces per width, as the rest of the package).
"""

import re
from dataclasses import dataclass
from functools import cache
from importlib.resources import files

import numpy as np

from rve_rod.errors import InputError

__all__ = [
    "CONVERGED_TOLERANCE",
    "PAPER_POISSON_RATIOS",
    "STITCH_VALUES",
    "UNIAXIAL_READINGS",
    "GroupRun",
    "UniaxialReading",
    "biaxial_rays",
    "converged_prefix",
    "shear_run",
]

STITCH_VALUES = (4.5, 5.5, 6.5)
"""Stitch values whose data are shipped (the set has two more, held back as a blind check)."""

CONVERGED_TOLERANCE = 0.02
"""|P - F S| up to this fraction of the run's largest |P| so far counts as a converged state."""

PAPER_POISSON_RATIOS = {"nu12": 0.43, "nu21": 0.82}
"""The paper's own RVE at stitch 5.5 and 20 % uniaxial strain (its text)."""


@dataclass(frozen=True)
class UniaxialReading:
    """A uniaxial state read from the group's data (their README's table): (a) from their
    fitted surface and (b) from their converged states alone; None where (b) lies beyond their
    converged runs. Forces in gf/cm."""

    course_force: tuple[float, float]
    nu12: tuple[float, float]
    wale_force: tuple[float, float | None]
    nu21: tuple[float, float | None]


UNIAXIAL_READINGS = {
    (4.5, 0.1): UniaxialReading((48.4, 42.8), (0.59, 0.73), (80.5, 122.9), (0.84, 0.85)),
    (4.5, 0.2): UniaxialReading((92.2, 86.3), (0.66, 0.72), (130.2, 189.4), (1.05, 1.06)),
    (5.5, 0.1): UniaxialReading((14.6, 13.5), (0.42, 0.56), (58.0, 69.4), (0.75, 0.79)),
    (5.5, 0.2): UniaxialReading((28.2, 27.2), (0.48, 0.58), (128.2, 142.6), (0.81, 0.81)),
    (6.5, 0.1): UniaxialReading((6.7, 6.3), (0.24, 0.30), (25.9, 29.9), (0.64, 0.67)),
    (6.5, 0.2): UniaxialReading((13.6, 13.2), (0.27, 0.29), (65.5, None), (0.74, None)),
}
"""(stitch, engineering strain) -> the README's two readings of the uniaxial state."""


@dataclass(frozen=True, eq=False)
class GroupRun:
    """One run of the group's RVE: a biaxial ray or the shear.

    Attributes:
        stitch: the fabric's stitch value (mm).
        kind: "ray" or "shear".
        deformation: (k, 2, 2) F of the states k = 1..n.
        second_piola: (k, 2, 2) their S (N/mm).
        first_piola: (k, 2, 2) their P (N/mm).
        converged: how many of the first states are converged (`converged_prefix`).
    """

    stitch: float
    kind: str
    deformation: np.ndarray
    second_piola: np.ndarray
    first_piola: np.ndarray
    converged: int

    @property
    def direction(self) -> np.ndarray:
        """(2,) engineering strain (F11 - 1, F22 - 1) of the last state, i.e. at t = 1 (rays)."""
        return np.diagonal(self.deformation[-1]) - 1.0

    @property
    def angle_deg(self) -> float:
        """The ray's direction in the engineering-strain plane (degrees), or the shear's
        final angle a (rad) converted to degrees."""
        if self.kind == "shear":
            return float(
                np.degrees(np.arctan2(self.deformation[-1, 0, 1], self.deformation[-1, 1, 1]))
            )
        e1, e2 = self.direction
        return float(np.degrees(np.arctan2(e2, e1)))

    @property
    def states(self) -> int:
        return self.deformation.shape[0]

    def largest_stress(self) -> np.ndarray:
        """(k,) the largest |S11|, |S22| (|S12| in shear) of the run up to each state (N/mm):
        the scale the comparison's errors are measured against."""
        components = self.second_piola.reshape(-1, 4)[:, [0, 3, 1]]
        if self.kind == "ray":
            components = components[:, :2]
        return np.maximum.accumulate(np.abs(components).max(axis=1))


def converged_prefix(deformation: np.ndarray, first: np.ndarray, second: np.ndarray) -> int:
    """How many leading states have P = F S within CONVERGED_TOLERANCE of the run's largest
    |P| up to them (shapes (k, 2, 2))."""
    mismatch = np.abs(first - deformation @ second).reshape(len(first), -1).max(axis=1)
    scale = np.maximum.accumulate(np.abs(first).reshape(len(first), -1).max(axis=1))
    converged = mismatch <= CONVERGED_TOLERANCE * np.maximum(scale, np.finfo(float).tiny)
    failed = np.flatnonzero(~converged)
    return int(failed[0]) if failed.size else len(first)


def biaxial_rays(stitch: float) -> tuple[GroupRun, ...]:
    """The 12 biaxial rays of the group's data at `stitch` (one of STITCH_VALUES)."""
    return _read(_check_stitch(stitch))[0]


def shear_run(stitch: float) -> GroupRun:
    """The group's picture-frame shear run at `stitch` (one of STITCH_VALUES)."""
    return _read(_check_stitch(stitch))[1]


def _check_stitch(stitch: float) -> float:
    for value in STITCH_VALUES:
        if abs(float(stitch) - value) < 1e-9:
            return value
    raise InputError(
        f"stitch={stitch!r} has no data of the paper group's RVE; shipped: "
        f"{', '.join(f'{value:g}' for value in STITCH_VALUES)}"
    )


@cache
def _read(stitch: float) -> tuple[tuple[GroupRun, ...], GroupRun]:
    folder = files("rve_rod").joinpath("data/weeger_group_rve")
    text = folder.joinpath(f"rs{stitch:g}_ba_EPS.dat").read_text(encoding="utf-8")
    blocks = [block for block in re.split(r"\n\s*\n", text.split("\n", 1)[1]) if block.strip()]
    rays = []
    for block in blocks:
        table = np.loadtxt(block.splitlines())[1:]  # row 0 (t = 0.005, S = 0) is a placeholder
        stretch = np.sqrt(1.0 + 2.0 * table[:, :2])
        rays.append(_run(stitch, "ray", _diagonal(stretch), table[:, 2:6], table[:, 6:10]))
    table = np.loadtxt(
        folder.joinpath(f"rs{stitch:g}_ps_EPS.dat").read_text(encoding="utf-8").splitlines()[2:]
    )
    angle = table[:, 0]
    deformation = np.zeros((len(angle), 2, 2))
    deformation[:, 0, 0] = 1.0
    deformation[:, 0, 1] = np.sin(angle)
    deformation[:, 1, 1] = np.cos(angle)
    return tuple(rays), _run(stitch, "shear", deformation, table[:, 2:6], table[:, 6:10])


def _diagonal(stretch: np.ndarray) -> np.ndarray:
    deformation = np.zeros((len(stretch), 2, 2))
    deformation[:, 0, 0] = stretch[:, 0]
    deformation[:, 1, 1] = stretch[:, 1]
    return deformation


def _run(stitch, kind, deformation, first, second) -> GroupRun:
    first = first.reshape(-1, 2, 2)
    second = second.reshape(-1, 2, 2)
    return GroupRun(
        stitch=stitch,
        kind=kind,
        deformation=deformation,
        second_piola=second,
        first_piola=first,
        converged=converged_prefix(deformation, first, second),
    )
