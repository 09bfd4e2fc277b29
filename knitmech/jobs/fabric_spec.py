"""The job of the fabric stage, without DOLFINx (the pipeline plans and caches with it).

`knitmech.jobs.fabric` runs it (in-process or under mpirun, after a JSON round trip).
"""

import dataclasses
from dataclasses import dataclass

from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from fabric_dolfinx.spec.space import IndenterSpec, SpaceSpec
from knitmech.scene.fabric import PartSpec, RegionSpec
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
        part = data["part"]
        boundaries = tuple(
            BoundaryCondition(**{**b, "vector": tuple(b["vector"])}) for b in part["boundaries"]
        )
        return cls(
            part=PartSpec(
                mesh=MeshSpec(**part["mesh"]),
                regions=tuple(
                    RegionSpec(**{**r, "members": tuple(r["members"])}) for r in part["regions"]
                ),
                boundaries=boundaries,
                probes={k: tuple(v) for k, v in part["probes"].items()},
                space=_space(part.get("space")),
            ),
            materials=tuple(
                RegionMaterial(
                    **{**m, "family": tuple(map(tuple, m["family"])) if m["family"] else None}
                )
                for m in data["materials"]
            ),
            steps=data["steps"],
            element_degree=data["element_degree"],
        )


def _space(data: dict | None) -> SpaceSpec | None:
    if data is None:
        return None
    indenter = data["indenter"]
    if indenter is not None:
        vectors = ("centre", "point", "normal", "travel")
        indenter = IndenterSpec(
            **{k: tuple(v) if k in vectors and v is not None else v for k, v in indenter.items()}
        )
    return SpaceSpec(
        **{
            **data,
            "indenter": indenter,
            "axis": tuple(data["axis"]),
            "axis_point": tuple(data["axis_point"]),
        }
    )
