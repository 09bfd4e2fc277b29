"""The job of the sleeve's contact model, without DOLFINx (the design plans and caches with it).

`knitmech.jobs.sleeve` runs it (in-process or under mpirun, after a JSON round trip).
"""

import dataclasses
from dataclasses import dataclass

from knitmech.design.family import FamilyMember
from knitmech.stages.records import from_json_data
from rve_rod.jsonable import to_jsonable

__all__ = ["SleeveJob"]


@dataclass(frozen=True)
class SleeveJob:
    """A knitted sleeve drawn over a limb by an expanding mandrel (`knitmech.jobs.sleeve`).

    Attributes:
        members: the family (its surface files and loop geometry).
        limb: ((z, r), ...) the limb's radius profile (mm); the sleeve covers its extent.
        stitches, needles, courses: per course band, from the ankle (mm, -, -).
        element_size: the quadrilaterals' target edge (mm).
        penalty: the contact stiffness (N/mm^3).
        stabilization: the normal stabilization (N/mm^3, `fabric_dolfinx.part.problem`):
            it carries the steps before the tube lies on the mandrel, where the unstressed
            fabric has no radial stiffness; released after every step.
        steps: load steps of the mandrel's growth.
        element_degree: Lagrange degree of the displacement.
    """

    members: tuple[FamilyMember, ...]
    limb: tuple[tuple[float, float], ...]
    stitches: tuple[float, ...]
    needles: tuple[float, ...]
    courses: tuple[float, ...]
    element_size: float = 5.0
    penalty: float = 1.0
    stabilization: float = 1e-4
    steps: int = 10
    element_degree: int = 1

    def to_json(self) -> dict:
        return to_jsonable(dataclasses.asdict(self))

    @classmethod
    def from_json(cls, data: dict) -> "SleeveJob":
        """The job of `to_json`'s dict."""
        return from_json_data(cls, data)
