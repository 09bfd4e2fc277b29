"""The job of the fabric stage, without DOLFINx (the pipeline plans and caches with it).

`knitmech.jobs.fabric` runs it (in-process or under mpirun, after a JSON round trip).
"""

import dataclasses
from dataclasses import dataclass

from knitmech.scene.fabric import PartSpec
from knitmech.stages.records import from_json_data
from rve_rod.jsonable import to_jsonable

__all__ = ["FabricJob", "RegionMaterial"]


@dataclass(frozen=True)
class RegionMaterial:
    """The material of one region: a surface file, SVK constants or a graded family, and its
    stitch value.

    Attributes:
        surface: path of a response-surface file, or None.
        svk: OrthotropicSVK constants (N/mm), or None.
        stitch: the stitch value (mm) written to the output (for a graded region the
            expression of x, y the law is interpolated at), or None.
        family: a graded region's members ((stitch, surface path), ...), or None.
    """

    surface: str | None = None
    svk: dict[str, float] | None = None
    stitch: float | str | None = None
    family: tuple[tuple[float, str], ...] | None = None


@dataclass(frozen=True)
class FabricJob:
    """Everything the fabric stage needs (JSON round trip for the MPI run).

    Attributes:
        part: the resolved part (element size filled in).
        materials: one RegionMaterial per region of the part.
        steps: equal load steps from t = 0 to 1.
        element_degree: Lagrange degree of the displacement.
    """

    part: PartSpec
    materials: tuple[RegionMaterial, ...]
    steps: int
    element_degree: int = 1

    def to_json(self) -> dict:
        return to_jsonable(dataclasses.asdict(self))

    @classmethod
    def from_json(cls, data: dict) -> "FabricJob":
        """The job of `to_json`'s dict."""
        return from_json_data(cls, data)
