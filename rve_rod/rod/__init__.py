"""Geometrically exact (Simo-Reissner) Cosserat rods by isogeometric collocation.

Centreline and quaternion fields are B-splines on the same knots; the strong-form balance
equations are collocated at the Greville points (Weeger, Yeung & Dunn, CMAME 316, 2017).
See docs/rod.md for the formulation, the extension API and the verification results.
"""

from rve_rod.rod.conditions import (
    Block,
    Clamp,
    Condition,
    ConditionContext,
    EndCondition,
    EndLoad,
    EndValues,
    Joint,
    Offset,
    Pin,
    PointSupport,
)
from rve_rod.rod.frames import quaternions_from_frames, reference_quaternions
from rve_rod.rod.layout import END, START, DofLayout, RodEnd
from rve_rod.rod.loads import DistributedLoad, LineLoads, PointLoad, StateDependentLoad
from rve_rod.rod.model import (
    CollocationData,
    ControlPoints,
    Evaluation,
    PointLoadWeights,
    RodModel,
    RodPatch,
    SectionForces,
)
from rve_rod.rod.section import PAPER_CIRCLE, SOLID_CIRCLE, SectionStiffness

__all__ = [
    "END",
    "PAPER_CIRCLE",
    "SOLID_CIRCLE",
    "START",
    "Block",
    "Clamp",
    "CollocationData",
    "Condition",
    "ConditionContext",
    "ControlPoints",
    "DistributedLoad",
    "DofLayout",
    "EndCondition",
    "EndLoad",
    "EndValues",
    "Evaluation",
    "Joint",
    "LineLoads",
    "Offset",
    "Pin",
    "PointLoad",
    "PointLoadWeights",
    "PointSupport",
    "RodEnd",
    "RodModel",
    "RodPatch",
    "SectionForces",
    "SectionStiffness",
    "StateDependentLoad",
    "quaternions_from_frames",
    "reference_quaternions",
]
