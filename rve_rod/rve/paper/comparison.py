"""Our RVE along the paper group's runs: the same F at every converged state of theirs.

`compare_run(fabric, run, settings)` runs our cell along a biaxial ray or the picture-frame shear
of `rve_rod.rve.paper.data` to the last converged state of theirs, with one output state per
state of theirs (t = k/20), and measures the difference state by state: at state k,

    error_k = max_ab |S_ab(ours) - S_ab(theirs)| / max_{j <= k} max_ab |S_ab(theirs)_j|,

over S11 and S22 on a ray, S12 (the symmetric part of theirs) in shear: relative to the largest
stress of their run up to that state, so that a state near zero stress on a ray that was loaded
before is not judged by its own tiny value. A run of ours that stops early is compared where it
got (the rest is NaN and counts as a failure).

`uniaxial_comparison(fabric, settings)` gives our uniaxial course- and wale-wise forces and
Poisson ratios at the strains of `paper.data.UNIAXIAL_READINGS`; `secant_at_rest` the secant
stiffness at rest through the first states of their two rays nearest the axes (`axis_rays`);
`first_increment_ratio` whether a ray starts slack (and stiffens) or taut; `taut_loop_split`
how much of a stiffness at rest runs through the length of the loop; `loop_profile_runner` any
of these on a loop of another out-of-plane profile, `depth_held_runner` on a cell whose depth is
held from its rest state on (a diagnostic); `loop_extents` the depth and the lengths of a run's
deformed loop, `length_budget` where it found the yarn an affine stretch would need,
`contact_points` and `contact_directions` which way its contacts push.
"""

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rve_rod.contact import CompressibleYarnLaw
from rve_rod.errors import ConvergenceError, InputError
from rve_rod.geometry.bspline import BSplineCurve
from rve_rod.geometry.loop import single_jersey_loop
from rve_rod.presets import Fabric
from rve_rod.rve.cell import LoopCell
from rve_rod.rve.load_cases import BiaxialRay, LoadCase, PictureFrameShear, load_case
from rve_rod.rve.paper.data import GroupRun, biaxial_rays
from rve_rod.rve.simulation import RveResult, RveSettings, loop_curves, run_cell, simulate
from rve_rod.rve.ties import DepthHold
from rve_rod.rve.yarn import yarn_model
from rve_rod.stress_measures import green_lagrange

__all__ = [
    "AXIS_RAYS",
    "TARGET",
    "TENSION_RAYS",
    "ContactPoints",
    "LengthBudget",
    "LoopExtent",
    "RunComparison",
    "TautLoopSplit",
    "UniaxialComparison",
    "axis_rays",
    "compare_run",
    "contact_directions",
    "contact_points",
    "depth_held_runner",
    "first_increment_ratio",
    "length_budget",
    "loop_extents",
    "loop_profile_runner",
    "run_case",
    "run_or_history",
    "secant_at_rest",
    "shear_share",
    "taut_loop_split",
    "uniaxial_comparison",
]

AXIS_RAYS = (6.4, 83.6)
"""The group's rays nearest the course and wale axes (degrees in the strain plane)."""

TENSION_RAYS = (6.4, 45.0, 83.6)
"""The group's rays that stretch both ways (degrees): near the course axis, equibiaxial, near
the wale axis."""

TARGET = 0.2
"""The target (issue 27): every converged state within 20 % of the run's largest stress."""

Runner = Callable[[Fabric, LoadCase, RveSettings], RveResult]
"""How a case is run: `simulate` by default; a run that stops early returns its history."""


@dataclass(frozen=True, eq=False)
class RunComparison:
    """Our RVE along one run of the group's.

    Attributes:
        reference: their run.
        states: how many of their states are compared (their converged prefix, or fewer).
        second_piola: (states, 2, 2) our S at those states, NaN beyond where our run got (N/mm).
        reached: how many of the states our run reached.
        wall_time_s: our run's wall time (s).
    """

    reference: GroupRun
    states: int
    second_piola: np.ndarray
    reached: int
    wall_time_s: float

    @property
    def components(self) -> tuple[tuple[int, int], ...]:
        """The compared components (a, b) of S: S11 and S22 on a ray, S12 in shear."""
        return ((0, 1),) if self.reference.kind == "shear" else ((0, 0), (1, 1))

    def errors(self) -> np.ndarray:
        """(states,) error_k of the module docstring; NaN where our run did not get."""
        theirs = _symmetric(self.reference.second_piola[: self.states])
        ours = self.second_piola
        difference = np.max(
            [np.abs(ours[:, a, b] - theirs[:, a, b]) for a, b in self.components], axis=0
        )
        scale = np.maximum.accumulate(
            np.max([np.abs(theirs[:, a, b]) for a, b in self.components], axis=0)
        )
        return difference / np.maximum(scale, np.finfo(float).tiny)

    def worst(self) -> float:
        """The largest error over the compared states (inf if our run stopped before any)."""
        errors = self.errors()
        if errors.size == 0:
            return 0.0
        return float(np.inf if np.isnan(errors).any() else errors.max())

    def passed(self, target: float = TARGET) -> bool:
        return self.worst() <= target


@dataclass(frozen=True)
class UniaxialComparison:
    """Our uniaxial runs at the strains of the readings.

    Attributes:
        strains: (m,) engineering strains.
        course_force, wale_force: (m,) gf/cm (NaN beyond where a run stopped).
        nu12, nu21: (m,) -lateral strain / strain.
    """

    strains: np.ndarray
    course_force: np.ndarray
    wale_force: np.ndarray
    nu12: np.ndarray
    nu21: np.ndarray


def run_case(run: GroupRun, states: int) -> LoadCase:
    """The load case of ours through their states 1..states (t = k/20 of their run)."""
    if run.kind == "shear":
        angle = float(
            np.arctan2(run.deformation[states - 1, 0, 1], run.deformation[states - 1, 1, 1])
        )
        return PictureFrameShear(steps=states + 1, max_angle=angle)
    direction = run.direction * states / run.states
    return BiaxialRay(
        steps=states + 1,
        angle_deg=float(np.degrees(np.arctan2(direction[1], direction[0]))),
        max_load=float(np.hypot(*direction)),
    )


def compare_run(
    fabric: Fabric,
    run: GroupRun,
    settings: RveSettings,
    *,
    states: int | None = None,
    runner: Runner | None = None,
) -> RunComparison:
    """Our RVE along `run` to its last converged state (or its first `states` states);
    `runner` replaces `simulate` (a variant of the model: benchmarks/paper_rve_sensitivity.py)."""
    count = run.converged if states is None else min(states, run.converged)
    ours = np.full((count, 2, 2), np.nan)
    if count == 0:
        return RunComparison(run, 0, ours, 0, 0.0)
    started = time.perf_counter()
    result = (runner or run_or_history)(fabric, run_case(run, count), settings)
    steps = result.steps[1:]
    for k, step in enumerate(steps):
        s11, s22, s12 = step.second_piola
        ours[k] = [[s11, s12], [s12, s22]]
    return RunComparison(run, count, ours, len(steps), time.perf_counter() - started)


def uniaxial_comparison(
    fabric: Fabric,
    settings: RveSettings,
    strains=(0.05, 0.1, 0.2, 0.3),
    steps_per_percent=1,
    runner: Runner | None = None,
) -> UniaxialComparison:
    """Our uniaxial runs to the largest of `strains` (`steps_per_percent` output states per
    percent of strain), read at each of them."""
    strains = np.asarray(strains, dtype=float)
    steps = round(float(strains.max()) * 100 * steps_per_percent) + 1
    values = {}
    for name, lateral in (("uniaxial-course", (1, 1)), ("uniaxial-wale", (0, 0))):
        case = load_case(name, float(strains.max()), steps)
        result = (runner or run_or_history)(fabric, case, settings)
        reached = np.array([step.strain for step in result.steps])
        force = result.series("force_gf_per_cm")
        contraction = np.array([1.0 - step.deformation[lateral] for step in result.steps])
        read = [np.flatnonzero(np.isclose(reached, strain))[:1] for strain in strains]
        values[name] = [
            np.array([series[i[0]] if i.size else np.nan for i in read])
            for series in (force, contraction)
        ]
    course, wale = values["uniaxial-course"], values["uniaxial-wale"]
    return UniaxialComparison(
        strains=strains,
        course_force=course[0],
        wale_force=wale[0],
        nu12=course[1] / strains,
        nu21=wale[1] / strains,
    )


def run_or_history(fabric: Fabric, case: LoadCase, settings: RveSettings) -> RveResult:
    """`simulate`, or the converged states of a run that stopped early."""
    return _run_or_history(fabric, case, settings, None)


def loop_profile_runner(profile: str) -> Runner:
    """A `Runner` on the jersey loop of out-of-plane `profile` (`OUT_OF_PLANE_PROFILES` of
    `rve_rod.geometry.loop`: the issue-14 experiment's literature shapes) in place of the
    model's "band" loop; like `run_or_history`, a run that stops early returns its history."""

    def run(fabric: Fabric, case: LoadCase, settings: RveSettings) -> RveResult:
        knit = fabric.knit
        loop = single_jersey_loop(
            knit.wale_width, knit.course_height, fabric.yarn.minimal_radius, profile=profile
        )
        return _run_or_history(fabric, case, settings, list(loop.curves))

    return run


class _DepthHeldCell(LoopCell):
    """The loop cell with a `DepthHold` of kappa = alpha EA / c, engaged at its rest state."""

    def __init__(self, curves, knit, yarn, case, settings, alpha: float):
        self.depth_hold = DepthHold()
        self.alpha = alpha
        super().__init__(curves, knit, yarn, case, settings, (self.depth_hold,))

    def rest_state(self, newton, stepping) -> np.ndarray:
        rest = super().rest_state(newton, stepping)
        stiffness = self.alpha * self.yarn.section.axial / self._knit.course_height
        self.depth_hold.hold(self.model, rest, stiffness)
        return rest


def depth_held_runner(alpha: float) -> Runner:
    """A `Runner` on the model's loop with its depth held from the rest state on by springs of
    alpha EA / c each (N/mm; `rve_rod.rve.ties.DepthHold`, a diagnostic: docs/validation.md,
    "The squeezed rest, balanced"); alpha = 0 is the plain cell. Like `run_or_history`, a run
    that stops early returns its history."""

    def run(fabric: Fabric, case: LoadCase, settings: RveSettings) -> RveResult:
        yarn = yarn_model(fabric, settings.yarn)
        curves = loop_curves(fabric)
        cell = _DepthHeldCell(curves, fabric.knit, yarn, case, settings.cell, alpha)
        try:
            return run_cell(cell, fabric, settings)
        except ConvergenceError as error:
            return error.history

    return run


def _run_or_history(fabric, case, settings, curves) -> RveResult:
    try:
        return simulate(fabric, case, settings, curves=curves)
    except ConvergenceError as error:
        return error.history


def _symmetric(tensors: np.ndarray) -> np.ndarray:
    return 0.5 * (tensors + np.swapaxes(tensors, -1, -2))


def axis_rays(stitch: float, angles: tuple[float, ...] = AXIS_RAYS) -> list[GroupRun]:
    """Their rays at `stitch` nearest `angles` (degrees; by default the two nearest the course
    and the wale axis)."""
    rays = biaxial_rays(stitch)
    return [min(rays, key=lambda ray, a=a: abs(ray.angle_deg - a)) for a in angles]


def secant_at_rest(rays: list[GroupRun], stresses: np.ndarray | None = None) -> np.ndarray:
    """(2, 2) C of (S11, S22) = C (E11, E22) through the first states of two rays (their Green-
    Lagrange strains), given the (2,) diagonal stresses S (N/mm) there, one row per ray; by
    default their own first states' (their stiffness at rest)."""
    strains = np.array([np.diagonal(green_lagrange(ray.deformation[0])) for ray in rays])
    if stresses is None:
        stresses = [np.diagonal(ray.second_piola[0]) for ray in rays]
    return np.linalg.solve(strains, np.asarray(stresses)).T


def shear_share(stresses: np.ndarray) -> float:
    """How far a run under normal strains is from orthotropic: the largest |S12|, |S21| over
    the largest |S11|, |S22| of its states, stresses (k, 2, 2) (NaN states skipped; 0 for an
    orthotropic cell whose axes are the strain's, as a knit mirror symmetric about its wale;
    NaN when no state is finite)."""
    stresses = np.asarray(stresses).reshape(-1, 2, 2)
    stresses = stresses[np.isfinite(stresses).all(axis=(1, 2))]
    if stresses.size == 0:
        return float("nan")
    shear = np.abs(stresses[:, [0, 1], [1, 0]]).max()
    return float(shear / np.abs(stresses[:, [0, 1], [0, 1]]).max())


def first_increment_ratio(deformation: np.ndarray, stresses: np.ndarray) -> float:
    """The secant stiffness from rest to the first state over the stiffness of the next
    increment, |S_1| / |E_1| over |S_2 - S_1| / |E_2 - E_1| with S = (S11, S22), E = (E11,
    E22), from F (k >= 2, 2, 2) and the diagonal stresses (k, 2) of the first states of a
    ray: 1 for a linear response, below 1 where the ray starts slack and stiffens, above 1
    where it starts taut and gives way."""
    strains = np.array([np.diagonal(green_lagrange(f)) for f in deformation[:2]])
    stresses = np.asarray(stresses)[:2]
    first = np.linalg.norm(stresses[0]) / np.linalg.norm(strains[0])
    second = np.linalg.norm(stresses[1] - stresses[0]) / np.linalg.norm(strains[1] - strains[0])
    return float(first / second)


class TautLoopSplit(NamedTuple):
    """A stiffness at rest C = k a a^T + diag(rest) (`taut_loop_split`).

    Attributes:
        stiffness: k (N/mm^3), the stiffness of the loop's length: a strain E stretches the
            loop's yarn by a . E (mm) and takes the stress k a (a . E) (N/mm).
        rest: (2,) what C11 and C22 hold besides (N/mm): bending, contacts, all that does not
            run through the loop's length; a negative value says that C does not fit this
            form with this a.
        coupling: C12 C21 / (C11 C22) (-): 0 for a cell whose two directions are uncoupled, 1
            for a loop of inextensible yarn that deforms only at constant length.
    """

    stiffness: float
    rest: np.ndarray
    coupling: float


def taut_loop_split(stiffness: np.ndarray, gradient: np.ndarray) -> TautLoopSplit:
    """Split a (2, 2) secant stiffness at rest C (N/mm; S = C E) into the part that runs through
    the loop's length, k a a^T with k = sqrt(C12 C21) / (a1 a2), and the diagonal rest
    (`TautLoopSplit`); `gradient` a (2,) (mm) is how the loop's length grows with E11 and E22:
    `rve_rod.geometry.loop.loop_length_gradient` (the loop re-shaping into the shortest one)
    or `affine_length_gradient` (its shape held)."""
    c = np.asarray(stiffness, dtype=float)
    a = np.asarray(gradient, dtype=float)
    if c.shape != (2, 2) or a.shape != (2,) or not np.all(a > 0):
        raise InputError(
            f"taut_loop_split needs a (2, 2) stiffness and a (2,) gradient of positive entries "
            f"(mm); got shapes {c.shape}, {a.shape} and gradient {a.tolist()}"
        )
    product = c[0, 1] * c[1, 0]
    k = float(np.sqrt(max(product, 0.0)) / (a[0] * a[1]))
    return TautLoopSplit(k, np.diagonal(c) - k * a**2, float(product / (c[0, 0] * c[1, 1])))


class LoopExtent(NamedTuple):
    """Where the yarn of a run's cell lies, one value per output state (mm, shape (s,) each).

    Attributes:
        depth: the centreline's extent through the thickness, max z - min z (the template's
            depth d at rest).
        in_plane_length: the length of the centreline's projection on the fabric's plane.
        length: the centreline's length (the yarn's stretch is length / length[0] - 1).
    """

    depth: np.ndarray
    in_plane_length: np.ndarray
    length: np.ndarray


def loop_extents(result: RveResult, samples: int = 4001) -> LoopExtent:
    """The depth and the lengths of the first patch's deformed centreline at each output state
    of `result`, from `samples` points evenly spaced in its parameter (`LoopExtent`): where
    the yarn a stretch needs comes from (docs/validation.md, "The bulge")."""
    extents = [_curve_extent(result.centreline(step), samples) for step in range(len(result.steps))]
    return LoopExtent(*(np.array(values) for values in zip(*extents, strict=True)))


class LengthBudget(NamedTuple):
    """Where a deformed loop found the yarn its affine image would need (`length_budget`).

    Attributes:
        demand: the affine image's length over the rest length, minus 1 (-).
        stretch: the share of the demand the yarn's own stretch met (-).
        depth: the share met by yarn given up through the thickness: the affine image's length
            beyond its in-plane projection less the deformed loop's (-).
        shape: the share met by the loop's in-plane shape: the affine image's projected
            length less the deformed loop's (-). The three shares sum to 1.
    """

    demand: float
    stretch: float
    depth: float
    shape: float


def length_budget(
    rest: BSplineCurve, deformed: BSplineCurve, deformation: np.ndarray, samples: int = 4001
) -> LengthBudget:
    """How a loop met the yarn demand of the macro `deformation` (2, 2): its rest centreline
    mapped by F (z unchanged) is the affine image, whose length over the rest's is the demand;
    the deformed centreline met it by stretching, by giving up length through the thickness
    and by changing its in-plane shape (`LengthBudget`; lengths from `samples` points evenly
    spaced in the parameter). Raises InputError when F demands no yarn (the affine image no
    longer than the rest)."""
    f = np.eye(3)
    f[:2, :2] = np.asarray(deformation, dtype=float)
    affine = BSplineCurve(rest.degree, rest.knots, rest.control_points @ f.T)
    (_, _, rest_length), (_, plane, length), (_, affine_plane, affine_length) = (
        _curve_extent(curve, samples) for curve in (rest, deformed, affine)
    )
    demand = affine_length - rest_length
    if demand <= 0.0:
        raise InputError(
            f"length_budget needs a deformation whose affine image is longer than the rest loop; "
            f"F = {f[:2, :2].tolist()} changes its length by {demand:.3g} mm"
        )
    return LengthBudget(
        demand=demand / rest_length,
        stretch=(length - rest_length) / demand,
        depth=((affine_length - affine_plane) - (length - plane)) / demand,
        shape=(affine_plane - plane) / demand,
    )


class ContactPoints(NamedTuple):
    """Contacts of a periodic yarn reconstructed from its centreline (`contact_points`; arrays
    over k contacts).

    Attributes:
        position: (k, 3) the yarn's point (mm).
        normal: (k, 3) unit normal from the touching image's point to the yarn's.
        load: (k,) the law's normal line load f_n at the penetration (N/mm).
        image: (k, 2) the lattice image (i, j) touched.
    """

    position: np.ndarray
    normal: np.ndarray
    load: np.ndarray
    image: np.ndarray


def contact_points(
    curve: BSplineCurve,
    lattice: np.ndarray,
    radius: float,
    law: CompressibleYarnLaw,
    samples: int = 1500,
) -> ContactPoints:
    """The contacts of a periodic yarn with its images, reconstructed from its centreline
    `curve` (one period along the first of the deformed `lattice` vectors (2, 3), mm), not the
    run's contact search (no region weights, one pass): from each of `samples` points of the
    yarn, the nearest point of each lattice image within two cells (its own yarn's points
    within 4 `radius` of arc excluded; a nearest point at an end of the image's period belongs
    to the neighbouring image) closer than 2 `radius`, loaded by `law`'s f_n at g = 2 radius - d
    (`ContactPoints`)."""
    points = curve(np.linspace(*curve.domain, samples))
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    period = arc[-1]  # one period: the curve ends where its image along the course starts
    found = []
    for i in range(-2, 3):
        for j in range(-2, 3):
            offsets = points[:, None, :] - (points[None, :, :] + i * lattice[0] + j * lattice[1])
            distance = np.linalg.norm(offsets, axis=2)
            if j == 0:  # the yarn's own continuation along the course
                distance[np.abs(arc[:, None] - arc[None, :] - i * period) < 4 * radius] = np.inf
            nearest = distance.argmin(axis=1)
            d = distance[np.arange(samples), nearest]
            # a nearest point at an end of the image's period is the neighbouring image's
            # minimum (or no minimum of the endless yarn): counted there, not here
            touching = np.flatnonzero((d < 2 * radius) & (nearest > 0) & (nearest < samples - 1))
            normal = offsets[touching, nearest[touching]] / d[touching, None]
            load = law.load_and_slope(2 * radius - d[touching])[0]
            found.append((points[touching], normal, load, np.tile((i, j), (touching.size, 1))))
    return ContactPoints(*(np.concatenate(parts) for parts in zip(*found, strict=True)))


def contact_directions(
    curve: BSplineCurve,
    lattice: np.ndarray,
    radius: float,
    law: CompressibleYarnLaw,
    samples: int = 1500,
) -> np.ndarray:
    """(3,) the mean |n_x|, |n_y|, |n_z| of the contact normals of a periodic yarn, weighted by
    their normal force (`contact_points`, whose arguments these are). Raises InputError when
    no two points are in contact."""
    contacts = contact_points(curve, lattice, radius, law, samples)
    total = contacts.load.sum()
    if total == 0.0:
        raise InputError("contact_directions: no point of the yarn is in contact")
    return (np.abs(contacts.normal) * contacts.load[:, None]).sum(axis=0) / total


def _curve_extent(curve: BSplineCurve, samples: int) -> tuple[float, float, float]:
    """(depth, in-plane length, length) of `curve` from `samples` points evenly spaced in its
    parameter (mm)."""
    points = curve(np.linspace(*curve.domain, samples))
    chords = np.diff(points, axis=0)
    return (
        float(np.ptp(points[:, 2])),
        float(np.linalg.norm(chords[:, :2], axis=1).sum()),
        float(np.linalg.norm(chords, axis=1).sum()),
    )
