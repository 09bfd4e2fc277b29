"""Yarn-to-yarn contact of the knit RVE: compressible-yarn penalty law, Coulomb friction,
periodic images, evaluated at the collocation points of the rod discretization.

Entry point: `ContactModel` (see rve_rod.contact.model and docs/contact.md).
"""

from rve_rod.contact.friction import FrictionHistory
from rve_rod.contact.law import MINIMUM_EXPONENT, CompressibleYarnLaw, CoulombFriction
from rve_rod.contact.layout import Patch, PeriodicLattice, YarnChain
from rve_rod.contact.model import (
    DEFORMATION_COMPONENTS,
    ActiveContacts,
    ContactModel,
    ContactOptions,
    ContactResult,
    ContactStatistics,
)

__all__ = [
    "DEFORMATION_COMPONENTS",
    "MINIMUM_EXPONENT",
    "ActiveContacts",
    "CompressibleYarnLaw",
    "ContactModel",
    "ContactOptions",
    "ContactResult",
    "ContactStatistics",
    "CoulombFriction",
    "FrictionHistory",
    "Patch",
    "PeriodicLattice",
    "YarnChain",
]
