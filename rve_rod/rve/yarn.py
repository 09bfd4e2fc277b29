"""The paper's yarn model of a knit: adjusted radius, section stiffness and contact laws.

From yarn (r0, E0, nu, mu) and knit (w) as design.md states it (Weeger et al.):

* adjusted radius r = min(r0, w/8): the loop is built, and the rods are sectioned, with r;
* translational stiffness A with E_A = E0, rotational stiffness C with E_C = 0.5 E0, from the
  section of radius r; A scaled by (r0/r)^4 and C by (r0/r)^6 (radius compensation (r0/r)^2
  and (r0/r)^4, knitting pre-tension (r0/r)^2 on both);
* bending and twisting rigidity (`YarnSettings.bending`): where the yarn's staple fibres are
  known (the default "auto"; or "free-fibres"), the rigidities of its fibres summed
  (`rve_rod.rod.section.free_fibre_rigidity`, the yarn's `Fibres`) in place of E_C I and
  G_C J, scaled by the pre-tension (r0/r)^2 only (they are the true yarn's; docs/validation.md,
  "The yarn's bending rigidity"); otherwise ("section", the paper's) E_C I and G_C J of the
  section, I = pi r^4/4 (solid circle, default) or the paper's pi r^4/12;
* contact: compressible-yarn penalty law k = 0.01 E0 (r0/r)^8, p = 3 - (r0/r)^3 on the
  penetration g = 2r - d (`rve_rod.contact.CompressibleYarnLaw`), Coulomb friction mu; with
  `YarnSettings.contact_radius = "measured"` the law acts at the yarn's own radius r0 instead
  (g = 2 r0 - d), so that the unloaded loop's contacts are squeezed by 2 (r0 - r)
  (`CONTACT_RADII`);
* pre-tension (`YarnSettings.prestrain`, eps0, default 0): the yarn's natural length
  1 / (1 + eps0) times the loop's (`RodModel.set_prestrain`), a taut loop held by its
  contacts (`rve_rod.rve.cell.LoopCell.rest_state`; docs/validation.md, "The paper group's
  RVE"); with `YarnSettings.natural_length = "measured"` the natural length is the fabric's
  measured loop length l / (1 + eps0) instead, so that a template longer than l is stretched
  by that much more (`NATURAL_LENGTHS`);
* natural curvature (`YarnSettings.natural_curvature`, s, default 1): the rods' stress-free
  curvature and twist s times the loop's (`RodModel.set_natural_curvature`): 1, the loop as
  built is stress-free; 0, a yarn that keeps no set, straight when free, bent into the loop and
  held there by its contacts (`rve_rod.rve.cell.LoopCell.rest_state`; docs/validation.md,
  "Friction, a straight yarn, and the trade map");
* contact exponent shift (`YarnSettings.contact_exponent_shift`, dp, default 0): the law's
  exponent p + dp, floored at 1, a contact stiffer (dp < 0) or softer at first touch
  (docs/validation.md, point 6 of "What the shape of their response says");
* torsion apart from bending (`YarnSettings.torsion`, default "bending": the bending model's):
  the twisting rigidity of the other model of BENDING_MODELS, e.g. the section's bending
  with its fibres' torsion (docs/validation.md, "The shear is the torsion's").
"""

import logging
from dataclasses import dataclass, replace
from typing import NamedTuple

from rve_rod.contact import CompressibleYarnLaw, CoulombFriction
from rve_rod.contact.law import DEFAULT_STIFFNESS_FACTOR, MINIMUM_EXPONENT
from rve_rod.errors import InputError, check_positive, check_range
from rve_rod.geometry.loop import adjusted_radius
from rve_rod.presets import Fabric
from rve_rod.rod import PAPER_CIRCLE, SOLID_CIRCLE, SectionStiffness
from rve_rod.rod.section import free_fibre_rigidity

__all__ = [
    "BENDING_CHOICES",
    "BENDING_MODELS",
    "CONTACT_RADII",
    "NATURAL_LENGTHS",
    "PRESTRAIN_LIMIT",
    "TORSION_CHOICES",
    "YarnModel",
    "YarnSettings",
    "bending_model",
    "check_bending",
    "yarn_model",
]

logger = logging.getLogger(__name__)

BENDING_MODELS = ("section", "free-fibres")
"""How the rods' rotational stiffness C is found: "section", E_C I and G_C J of the yarn's
section (the paper's; I from `second_moment`), or "free-fibres", the sum of its fibres'."""

BENDING_CHOICES = ("auto", *BENDING_MODELS)
"""A model of BENDING_MODELS, or "auto" (the default): "free-fibres" where the yarn's fibres
are known, "section" where they are not (`bending_model`)."""

CONTACT_RADII = ("adjusted", "measured")
"""The radius the contact law acts at: "adjusted" (the default), the loop's r = min(r0, w/8):
the yarns of the unloaded loop just touch; "measured", the yarn's own minimal radius r0: where
the knit leaves the yarn less room than it needs (r < r0), every contact of the unloaded loop
is squeezed by 2 (r0 - r), and the cell starts from that pre-loaded rest state
(`rve_rod.rve.cell.LoopCell.rest_state`; docs/validation.md, "The paper group's RVE")."""


NATURAL_LENGTHS = ("template", "measured")
"""What the prestrain eps0 is counted from: "template" (the default), the loop template's
yarn length L, natural length L / (1 + eps0); "measured", the fabric's measured loop length l,
natural length l / (1 + eps0): the rod's prestrain is then (1 + eps0) L / l - 1, larger where
the template holds more yarn than the fabric (`rve_rod.rve.cell.LoopCell.prestrain`)."""


TORSION_CHOICES = ("bending", *BENDING_MODELS)
"""The rods' twisting rigidity: "bending" (the default), the bending model's (E_C I's G_C J,
or the fibres' torsion with their bending); or a model of BENDING_MODELS of its own."""

PRESTRAIN_LIMIT = 0.2
"""Largest yarn prestrain eps0 accepted (-); the experiments of docs/validation.md ("The taut
loop") go to 0.08."""


@dataclass(frozen=True)
class YarnSettings:
    """Choices of the yarn model that are not fabric data.

    Attributes:
        second_moment: "solid" (I = pi r^4/4, default) or "paper" (I = pi r^4/12).
        rotational_modulus_factor: E_C / E0 (default 0.5).
        contact_stiffness_factor: the 0.01 in k = 0.01 E0 (r0/r)^8.
        friction: apply Coulomb friction with the yarn's coefficient (default True); False
            makes the scene frictionless (no slip history at all).
        friction_stiffness_ratio: tangential penalty k_t / k (default 1).
        bending: one of BENDING_CHOICES (default "auto": `bending_model`).
        contact_radius: one of CONTACT_RADII (default "adjusted").
        prestrain: eps0, the loop's yarn stretched by eps0 over its natural length, in
            [0, PRESTRAIN_LIMIT] (default 0: the loop as built is stress-free).
        natural_length: one of NATURAL_LENGTHS (default "template").
        natural_curvature: s in [0, 1], the rods' stress-free curvature and twist as a
            fraction of the loop's (default 1: the loop as built is stress-free; 0: a
            naturally straight yarn).
        contact_exponent_shift: dp in [-1, 1] added to the contact law's exponent p = 3 -
            (r0/r)^3, floored at 1 (`law.MINIMUM_EXPONENT`; default 0: the paper's law). An
            issue-27 experiment (docs/validation.md, point 6): a smaller p makes the law
            stiffer at first touch.
        torsion: one of TORSION_CHOICES (default "bending"). An issue-27 experiment
            (docs/validation.md, "The shear is the torsion's").
    """

    second_moment: str = SOLID_CIRCLE
    rotational_modulus_factor: float = 0.5
    contact_stiffness_factor: float = DEFAULT_STIFFNESS_FACTOR
    friction: bool = True
    friction_stiffness_ratio: float = 1.0
    bending: str = "auto"
    contact_radius: str = "adjusted"
    prestrain: float = 0.0
    natural_length: str = "template"
    natural_curvature: float = 1.0
    contact_exponent_shift: float = 0.0
    torsion: str = "bending"

    def __post_init__(self):
        if self.second_moment not in (SOLID_CIRCLE, PAPER_CIRCLE):
            raise InputError(
                f"second_moment={self.second_moment!r} is unknown; valid: "
                f"{SOLID_CIRCLE!r}, {PAPER_CIRCLE!r}"
            )
        check_positive("rotational_modulus_factor", self.rotational_modulus_factor)
        check_positive("contact_stiffness_factor", self.contact_stiffness_factor)
        check_positive("friction_stiffness_ratio", self.friction_stiffness_ratio)
        if self.bending not in BENDING_CHOICES:
            raise InputError(
                f"bending={self.bending!r} is unknown; valid: {', '.join(BENDING_CHOICES)}"
            )
        if self.torsion not in TORSION_CHOICES:
            raise InputError(
                f"torsion={self.torsion!r} is unknown; valid: {', '.join(TORSION_CHOICES)}"
            )
        if self.contact_radius not in CONTACT_RADII:
            raise InputError(
                f"contact_radius={self.contact_radius!r} is unknown; valid: "
                f"{', '.join(CONTACT_RADII)}"
            )
        check_range("prestrain", self.prestrain, 0.0, PRESTRAIN_LIMIT)
        check_range("natural_curvature", self.natural_curvature, 0.0, 1.0)
        check_range("contact_exponent_shift", self.contact_exponent_shift, -1.0, 1.0)
        if self.natural_length not in NATURAL_LENGTHS:
            raise InputError(
                f"natural_length={self.natural_length!r} is unknown; valid: "
                f"{', '.join(NATURAL_LENGTHS)}"
            )
        if self.bending != "section" and self.second_moment != SOLID_CIRCLE:
            raise InputError(
                f"second_moment={self.second_moment!r} applies to bending='section' only "
                f"(bending={self.bending!r} takes the rigidities from the yarn's fibres where "
                "they are known): give bending='section' with it"
            )


class YarnModel(NamedTuple):
    """The yarn of one fabric as the RVE models it.

    Attributes:
        radius: r = min(r0, w/8) (mm).
        minimal_radius: r0 (mm).
        adjusted: True when r < r0 (the knit is tighter than the yarn).
        section: the scaled section stiffness of the rods.
        law: the normal contact law; its yarn_radius is the contact radius (r, or r0 with
            `YarnSettings.contact_radius = "measured"`).
        friction: Coulomb friction, or None (frictionless scene).
        prestrain: eps0 of `YarnSettings.prestrain` (-).
        natural_length: what eps0 is counted from (`YarnSettings.natural_length`).
        natural_curvature: s of `YarnSettings.natural_curvature` (-).
    """

    radius: float
    minimal_radius: float
    adjusted: bool
    section: SectionStiffness
    law: CompressibleYarnLaw
    friction: CoulombFriction | None
    prestrain: float = 0.0
    natural_length: str = "template"
    natural_curvature: float = 1.0


def yarn_model(fabric: Fabric, settings: YarnSettings = YarnSettings()) -> YarnModel:
    """The rods' section stiffness and the contact laws of `fabric` (module docstring).

    Raises InputError (from the contact law) when r0/r is so large that the contact exponent
    p = 3 - (r0/r)^3 falls below 1 (docs/rve.md, "exponent limit").
    """
    yarn = fabric.yarn
    r0 = yarn.minimal_radius
    r = adjusted_radius(r0, fabric.knit.wale_width)
    ratio = r0 / r
    law = CompressibleYarnLaw.from_yarn(
        minimal_radius=r0,
        yarn_radius=r,
        youngs_modulus=yarn.youngs_modulus,
        stiffness_factor=settings.contact_stiffness_factor,
    )
    if settings.contact_exponent_shift:
        shifted = law.exponent + settings.contact_exponent_shift
        law = replace(law, exponent=max(shifted, MINIMUM_EXPONENT))
    if settings.contact_radius == "measured":
        law = replace(law, yarn_radius=r0)
    solid = SectionStiffness.circular(
        r,
        yarn.youngs_modulus,
        rotational_modulus=settings.rotational_modulus_factor * yarn.youngs_modulus,
        poissons_ratio=yarn.poissons_ratio,
        second_moment=settings.second_moment,
    ).scaled(translational=ratio**4, rotational=ratio**6)
    bending = bending_model(fabric, settings.bending)
    torsion = bending if settings.torsion == "bending" else settings.torsion
    sections = {"section": solid}
    if "free-fibres" in (bending, torsion):
        check_bending(fabric, "free-fibres", "bending" if bending == "free-fibres" else "torsion")
        sections["free-fibres"] = _free_fibre_section(solid, fabric, ratio)
    section = replace(sections[bending], torsion=sections[torsion].torsion)
    friction = None
    if settings.friction and yarn.friction_coefficient > 0.0:
        friction = CoulombFriction.for_law(
            law, yarn.friction_coefficient, settings.friction_stiffness_ratio
        )
    return YarnModel(
        radius=r,
        minimal_radius=r0,
        adjusted=r < r0,
        section=section,
        law=law,
        friction=friction,
        prestrain=settings.prestrain,
        natural_length=settings.natural_length,
        natural_curvature=settings.natural_curvature,
    )


def bending_model(fabric: Fabric, bending: str, *, report: bool = False) -> str:
    """The model of BENDING_MODELS that `bending` (one of BENDING_CHOICES) means for
    `fabric`: "auto" is "free-fibres" where the yarn's fibres are known, else "section"
    (logged as a warning when `report`: the solid section overestimates a spun yarn's
    rigidity, for cotton 20s/2 eight times, and the knit then narrows too little)."""
    if bending != "auto":
        return bending
    if fabric.yarn.fibres is not None:
        return "free-fibres"
    if report:
        logger.warning(
            "yarn %s has no fibre data: its rods bend with the solid section's rigidity "
            "(bending='section'), which overestimates a spun yarn's and underestimates the "
            "knit's contraction (docs/validation.md, 'Yarns without fibre data')",
            fabric.yarn.name or "(given by values)",
        )
    return "section"


def check_bending(fabric: Fabric, bending: str, name: str = "bending") -> None:
    """Raise InputError unless `bending` (one of BENDING_MODELS; `YarnSettings` checks the
    name), given as setting `name`, can model `fabric`'s yarn: "free-fibres" needs the yarn's
    fibre data."""
    if bending == "free-fibres" and fabric.yarn.fibres is None:
        raise InputError(
            f"{name}='free-fibres' needs the yarn's fibres (linear densities, specific "
            f"rigidities); yarn {fabric.yarn.name or '(given by values)'} has none; presets "
            "with fibre data: cotton-20s2"
        )


def _free_fibre_section(section: SectionStiffness, fabric: Fabric, ratio: float):
    """`section` with C from the yarn's fibres (bending and torsion), times the pre-tension
    scaling (r0/r)^2 of the paper's model; the fibre data checked by the caller."""
    fibres = fabric.yarn.fibres
    bending, torsion = (
        free_fibre_rigidity(rigidity, fibres.fibre_linear_density, fibres.yarn_linear_density)
        * ratio**2
        for rigidity in (fibres.specific_flexural_rigidity, fibres.specific_torsional_rigidity)
    )
    return replace(section, bending_1=bending, bending_2=bending, torsion=torsion)
