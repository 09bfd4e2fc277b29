"""A knitted compression sleeve on a limb: its course bands and the Laplace model of its pressure.

The limb is a body of revolution r(z) (`fabric_dolfinx.spec.revolution.RadiusProfile`, mm),
the sleeve covers it from the profile's first to its last point in `bands` course bands of
equal length on the limb. Band k is knitted at stitch value s_k on N_k needles in n_k courses:
at rest a tube of circumference N_k w(s_k) and length n_k c(s_k) (w, c the family's wale width
and course height, `knitmech.design.family`). Worn, the course runs around the limb (axis 1 =
hoop) and the wales along it (axis 2 = axial), with the stretches at the band's centre z_k

    lambda_1 = 2 pi r(z_k) / (N_k w(s_k)),     lambda_2 = L / sum_j n_j c(s_j),

L the sleeve's length on the limb: the axial stretch is the sleeve's worn over its knitted
length, the same in every band (a band's own courses fix where it sits, not its stretch: on
the frictionless limb of the contact model the sleeve's axial force evens its axial stretch,
docs/design.md). The designed courses make it `SleeveSpec.axial_stretch`. The band's
membrane law at E = (lambda^2 - 1) / 2 gives
S11 (N/mm per undeformed width), the hoop tension per worn length T = lambda_1 S11 / lambda_2
(the Cauchy membrane force sigma_11) and Laplace's law the interface pressure

    p_k = T_k / r(z_k)                                           (N/mm^2).

The model ignores what a band's neighbours and the limb's slope and curvature along z add
(the membrane of revolution's meridional term, docs/design.md); the contact model
(`knitmech.jobs.sleeve`) has them.

`design_sleeve` finds the bands' stitch values (and, when the needles are designed, their
needle counts aiming at `SleeveSpec.hoop_strain`) whose Laplace pressures meet a target at
the band centres, by least squares (`knitmech.design.solve`; a band's pressure depends on its
own band only, so each Jacobian costs two evaluations whatever the number of bands). The
knitting instructions are whole needles and courses: they are rounded, and the stitch
values fitted again with them.
"""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from fabric_dolfinx.spec.expression import piecewise_linear
from fabric_dolfinx.spec.revolution import RadiusProfile
from knitmech.design.family import SurfaceFamily
from knitmech.design.solve import SolverSettings, Variable, solve_least_squares
from rve_rod.errors import InputError, check_integer, check_positive

__all__ = [
    "BandState",
    "PressureTarget",
    "RelaxedTube",
    "SleeveDesign",
    "SleeveSpec",
    "band_state",
    "design_sleeve",
    "laplace_pressure",
    "relaxed_tube",
    "stretched_band",
]


@dataclass(frozen=True)
class SleeveSpec:
    """The sleeve and the limb it is drawn over.

    Attributes:
        limb: the limb's radius profile; the sleeve covers its table's extent.
        bands: course bands of equal length on the limb.
        needles: the needle count of every band, or None when the needles are designed.
        axial_stretch: the sleeve's worn length over its knitted length (-): the courses
            of a band are its limb length / (axial_stretch c(s)).
        hoop_strain: when the needles are designed, the hoop strain lambda_1 - 1 they aim
            at (a target of the design beside the pressure).
        contact: whether the design is verified by the contact model (`knitmech.jobs.sleeve`).
        element_size: the contact model's quadrilateral edge (mm); None: the fidelity
            level's (CONTACT_ELEMENT_SIZE).
    """

    limb: RadiusProfile
    bands: int
    needles: tuple[float, ...] | None = None
    axial_stretch: float = 1.0
    hoop_strain: float = 0.15
    contact: bool = True
    element_size: float | None = None

    def __post_init__(self):
        check_integer("sleeve.bands", self.bands, 1, 200)
        check_positive("sleeve.axial_stretch", self.axial_stretch)
        check_positive("sleeve.hoop_strain", self.hoop_strain)
        if self.element_size is not None:
            check_positive("sleeve.element_size", self.element_size, "mm")
        if self.needles is not None:
            if len(self.needles) != self.bands:
                raise InputError(
                    f"sleeve.needles: {len(self.needles)} counts for {self.bands} bands"
                )
            for needles in self.needles:
                check_positive("sleeve.needles", needles)

    @property
    def edges(self) -> np.ndarray:
        """(bands + 1,) the bands' ends on the limb (mm)."""
        return np.linspace(*self.limb.extent, self.bands + 1)

    @property
    def centres(self) -> np.ndarray:
        """(bands,) the bands' centres on the limb (mm)."""
        edges = self.edges
        return 0.5 * (edges[:-1] + edges[1:])

    @property
    def band_length(self) -> float:
        """L_k, every band's length on the limb (mm)."""
        first, last = self.limb.extent
        return (last - first) / self.bands

    def courses(self, family: SurfaceFamily, stitch: float) -> float:
        """The courses n of a band at `stitch` (mm) for the axial stretch (not rounded)."""
        return self.band_length / (self.axial_stretch * family.course_height(stitch))


class BandState(NamedTuple):
    """A band worn on the limb (Laplace model).

    Attributes:
        hoop_stretch, axial_stretch: lambda_1, lambda_2 (-).
        strain: (3,) Green-Lagrange strain (E11, E22, E12), course = hoop.
        tension: T = lambda_1 S11 / lambda_2, the hoop force per worn length (N/mm).
        pressure: p = T / r (N/mm^2).
        outside: whether the strain leaves the family's data.
    """

    hoop_stretch: float
    axial_stretch: float
    strain: np.ndarray
    tension: float
    pressure: float
    outside: bool


def band_state(
    family: SurfaceFamily, radius: float, knit: tuple[float, float], axial: float
) -> BandState:
    """A band of `knit` = (stitch s (mm), needles N) worn on a limb of `radius` (mm) with
    the axial stretch `axial`: the stretches, strain, hoop tension and Laplace pressure."""
    stitch, needles = knit
    hoop = 2.0 * np.pi * radius / (needles * family.wale_width(stitch))
    return stretched_band(family, stitch, (hoop, axial), radius)


def stretched_band(
    family: SurfaceFamily, stitch: float, stretches: tuple[float, float], radius: float
) -> BandState:
    """The Laplace model of a band at `stitch` (mm) with the stretches (hoop, axial) on a
    limb of `radius` (mm): T = lambda_1 S11 / lambda_2, p = T / r."""
    hoop, axial = stretches
    strain = np.array([0.5 * (hoop**2 - 1.0), 0.5 * (axial**2 - 1.0), 0.0])
    evaluated = family.law(stitch).stress(strain)
    tension = hoop * float(evaluated.S[0, 0]) / axial
    return BandState(hoop, axial, strain, tension, tension / radius, bool(evaluated.outside[0]))


def laplace_pressure(
    family: SurfaceFamily,
    sleeve: SleeveSpec,
    stitches: np.ndarray,
    needles: np.ndarray,
    courses: np.ndarray | None = None,
) -> list[BandState]:
    """Every band's state at its centre for `stitches` (bands,) mm and `needles` (bands,);
    the axial stretch the sleeve's worn over its knitted length, L / sum_k n_k c(s_k) with
    `courses` (bands,) n_k, or without them the design's `SleeveSpec.axial_stretch`."""
    radii = sleeve.limb.radius(sleeve.centres)
    axial = sleeve.axial_stretch
    if courses is not None:
        knitted = sum(n * family.course_height(s) for n, s in zip(courses, stitches, strict=True))
        axial = sleeve.band_length * sleeve.bands / knitted
    return [
        band_state(family, float(r), (float(s), float(n)), axial)
        for r, s, n in zip(radii, stitches, needles, strict=True)
    ]


class PressureTarget(NamedTuple):
    """The pressure a sleeve design aims at.

    Attributes:
        pressure: (bands,) at the band centres (N/mm^2).
        weight: the pressure residuals' weight.
        tolerance: a band meets it when |p - target| <= tolerance * target.
    """

    pressure: np.ndarray
    weight: float = 1.0
    tolerance: float = 0.05


class SleeveDesign(NamedTuple):
    """A designed sleeve (Laplace model).

    Attributes:
        stitches: (bands,) stitch values (mm).
        needles: (bands,) whole needle counts.
        courses: (bands,) whole course counts.
        states: the bands worn (BandState each).
        misses: (bands,) (p - target) / target.
        met: whether every band is within the tolerance.
        continuous: (stitches, needles) of the search before rounding.
        evaluations: evaluations of the Laplace model (both searches).
        search_time_s: time of both searches (s).
        message: why the searches stopped.
    """

    stitches: np.ndarray
    needles: np.ndarray
    courses: np.ndarray
    states: list[BandState]
    misses: np.ndarray
    met: bool
    continuous: tuple[np.ndarray, np.ndarray]
    evaluations: int
    search_time_s: float
    message: str


def needle_bounds(
    family: SurfaceFamily, sleeve: SleeveSpec, bounds: tuple[float, float]
) -> list[tuple[float, float]]:
    """Per band the needle counts that keep its hoop stretch 2 pi r / (N w(s)) within
    [1, the family's data] at every stitch value s of `bounds` (mm):
    N in [2 pi r / (lambda_max w_min), 2 pi r / w_max], w_min and w_max over the bounds."""
    stitches = [s for s in family.stitch_values if bounds[0] < s < bounds[1]]
    widths = [family.wale_width(s) for s in (*bounds, *stitches)]
    largest = np.sqrt(1.0 + 2.0 * family.domain[0, 1])
    radii = sleeve.limb.radius(sleeve.centres)
    return [(2 * np.pi * r / (largest * min(widths)), 2 * np.pi * r / max(widths)) for r in radii]


def design_sleeve(
    family: SurfaceFamily,
    sleeve: SleeveSpec,
    target: PressureTarget,
    bounds: tuple[float, float],
    settings: SolverSettings,
) -> SleeveDesign:
    """The bands' stitch values (and needles) that meet `target` (module docstring)."""
    bands = sleeve.bands
    designed = sleeve.needles is None
    stitch_variables = [
        Variable(f"band {k + 1} stitch", *bounds, 0.5 * sum(bounds)) for k in range(bands)
    ]
    needle_variables = []
    if designed:
        for k, (low, high) in enumerate(needle_bounds(family, sleeve, bounds)):
            middle = (
                2
                * np.pi
                * sleeve.limb.radius(sleeve.centres[k])
                / ((1 + sleeve.hoop_strain) * family.wale_width(0.5 * sum(bounds)))
            )
            needle_variables.append(
                Variable(f"band {k + 1} needles", low, high, float(np.clip(middle, low, high)), "")
            )

    def residuals(stitches, needles, courses=None):
        states = laplace_pressure(family, sleeve, stitches, needles, courses)
        pressure = np.array([state.pressure for state in states])
        values = [target.weight * (pressure - target.pressure) / target.pressure]
        if designed and courses is None:
            hoop = np.array([state.hoop_stretch for state in states]) - 1.0
            values.append((hoop - sleeve.hoop_strain) / sleeve.hoop_strain)
        return np.concatenate(values)

    diagonal = np.eye(bands, dtype=bool)
    if designed:
        sparsity = np.block([[diagonal, diagonal], [diagonal, diagonal]])
        first = solve_least_squares(
            lambda x: residuals(x[:bands], x[bands:]),
            stitch_variables + needle_variables,
            settings,
            sparsity=sparsity,
        )
        stitches, needles = first.x[:bands], first.x[bands:]
    else:
        first = solve_least_squares(
            lambda x: residuals(x, np.array(sleeve.needles)),
            stitch_variables,
            settings,
            sparsity=diagonal,
        )
        stitches, needles = first.x, np.array(sleeve.needles)
    whole_needles = np.round(needles)
    courses = np.round([sleeve.courses(family, s) for s in stitches])
    start = [v._replace(initial=float(s)) for v, s in zip(stitch_variables, stitches, strict=True)]
    # with whole courses the axial stretch is the whole sleeve's: every band moves it
    second = solve_least_squares(lambda x: residuals(x, whole_needles, courses), start, settings)
    states = laplace_pressure(family, sleeve, second.x, whole_needles, courses)
    pressure = np.array([state.pressure for state in states])
    misses = (pressure - target.pressure) / target.pressure
    return SleeveDesign(
        stitches=second.x,
        needles=whole_needles.astype(int),
        courses=courses.astype(int),
        states=states,
        misses=misses,
        met=bool(np.all(np.abs(misses) <= target.tolerance)),
        continuous=(stitches, needles),
        evaluations=first.evaluations + second.evaluations,
        search_time_s=first.wall_time_s + second.wall_time_s,
        message="; ".join(dict.fromkeys((first.message, second.message))),
    )


class RelaxedTube(NamedTuple):
    """A knitted sleeve at rest, its course bands one after the other along z from `start`.

    Attributes:
        edges: (bands + 1,) the bands' ends (mm): band k is n_k c(s_k) long.
        centres: (bands,) their centres (mm).
        stitch: the stitch field along z, an expression of z (`piecewise_linear`): s_k at
            band k's centre, linear between centres, constant beyond.
        radius: z (any shape, mm) -> the radius N(z) w(s(z)) / 2 pi (mm) with N(z) linear
            between the centres alike.
    """

    edges: np.ndarray
    centres: np.ndarray
    stitch: str
    radius: object


def relaxed_tube(
    family: SurfaceFamily, start: float, knit: tuple[np.ndarray, np.ndarray, np.ndarray]
) -> RelaxedTube:
    """The sleeve of `knit` = (stitches (bands,) mm, needles (bands,), courses (bands,)) at
    rest, from z = `start` (mm). The contact model's reference surface: a band's stitch and
    needles change linearly to its neighbours' between their centres (so the surface is
    smooth), and at every band centre the tube is that band's knit."""
    stitches, needles, courses = (np.asarray(v, dtype=float) for v in knit)
    lengths = courses * np.array([family.course_height(s) for s in stitches])
    edges = start + np.concatenate([[0.0], np.cumsum(lengths)])
    centres = 0.5 * (edges[:-1] + edges[1:])
    stitch = piecewise_linear("z", centres, stitches)

    def radius(z):
        s = np.interp(z, centres, stitches)
        widths = np.vectorize(family.wale_width)(s)
        return np.interp(z, centres, needles) * widths / (2.0 * np.pi)

    return RelaxedTube(edges, centres, stitch, radius)
