"""The interface to the RVE (one run per load path) and the (E, S) samples its runs give.

An RVE engine is any picklable callable `run(case: RveCase) -> RveRun` (the rod RVE of
`rve_rod.rve`, or `analytic.AnalyticRve` for tests). It returns the converged output steps of
the case's load path. A path that the cell cannot follow to its end (typically in compression)
ends early: the engine returns the converged steps with `complete=False`, or raises
`ConvergenceError` whose `history` is that RveRun. If an engine has settings that change its
results, it should be a frozen dataclass: its fields are part of the cache key.
"""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from rve_rod.errors import InputError
from rve_rod.homogenize.sampling import LoadPath
from rve_rod.presets import Fabric
from rve_rod.stress_measures import membrane_state
from rve_rod.surface import ResponseSurface

__all__ = [
    "RveCase",
    "RveRun",
    "SurfaceSamples",
    "stored_samples",
    "surface_samples",
]


@dataclass(frozen=True)
class RveCase:
    """Everything one RVE run needs besides the engine's own settings.

    Attributes:
        fabric: yarn and knit.
        load: the load path to follow.
    """

    fabric: Fabric
    load: LoadPath


@dataclass(frozen=True, eq=False)
class RveRun:
    """The converged output steps of one RVE run (the reference state is not included).

    Attributes:
        deformation_gradient: (s, 2, 2) prescribed macro F of each converged step.
        first_piola: (s, 2, 2) first Piola-Kirchhoff membrane stress P (N/mm) of each step.
        complete: True when the whole load path converged.
    """

    deformation_gradient: np.ndarray
    first_piola: np.ndarray
    complete: bool = True

    def __post_init__(self):
        F = np.asarray(self.deformation_gradient, dtype=float).reshape(-1, 2, 2)
        P = np.asarray(self.first_piola, dtype=float).reshape(-1, 2, 2)
        if F.shape != P.shape:
            raise InputError(f"RveRun: F has {F.shape[0]} steps but P has {P.shape[0]}")
        object.__setattr__(self, "deformation_gradient", F)
        object.__setattr__(self, "first_piola", P)
        object.__setattr__(self, "complete", bool(self.complete))

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The run as named arrays (for the cache)."""
        return {
            "deformation_gradient": self.deformation_gradient,
            "first_piola": self.first_piola,
            "complete": np.array(self.complete),
        }

    @classmethod
    def from_arrays(cls, arrays) -> "RveRun":
        """Inverse of `to_arrays`."""
        return cls(arrays["deformation_gradient"], arrays["first_piola"], bool(arrays["complete"]))


class SurfaceSamples(NamedTuple):
    """(E, S) samples of the biaxial rays and of the shear run, Voigt order (11, 22, 12).

    Attributes:
        biaxial_strain: (m, 3) Green-Lagrange strain E of all converged ray steps.
        biaxial_stress: (m, 3) second Piola-Kirchhoff stress S (N/mm) of those steps.
        shear_strain: (k, 3) E of the converged steps of the shear run.
        shear_stress: (k, 3) S (N/mm) of those steps.
        complete: (number of runs,) whether each run reached the end of its path.
        max_asymmetry: largest |S_12 - S_21| (N/mm) over all samples (equilibrium check).
    """

    biaxial_strain: np.ndarray
    biaxial_stress: np.ndarray
    shear_strain: np.ndarray
    shear_stress: np.ndarray
    complete: np.ndarray
    max_asymmetry: float


def surface_samples(paths: tuple[LoadPath, ...], runs: tuple[RveRun, ...]) -> SurfaceSamples:
    """Convert the runs of `paths` into (E, S) samples with S = F^-1 P, E = (F^T F - I)/2."""
    if len(paths) != len(runs):
        raise InputError(f"{len(paths)} load paths but {len(runs)} runs")
    grouped = {"biaxial": ([], []), "shear": ([], [])}
    asymmetry = 0.0
    for path, run in zip(paths, runs, strict=True):
        expected = path.deformation_gradients()[: run.deformation_gradient.shape[0]]
        if not np.allclose(run.deformation_gradient, expected, rtol=0.0, atol=1e-12):
            raise InputError(f"the run of {path} did not follow its load path")
        if run.deformation_gradient.shape[0] == 0:
            continue
        state = membrane_state(run.deformation_gradient, run.first_piola)
        grouped[path.kind][0].append(state.E)
        grouped[path.kind][1].append(state.S)
        asymmetry = max(asymmetry, float(state.asymmetry.max()))
    stacked = {
        kind: tuple(np.concatenate(parts) if parts else np.zeros((0, 3)) for parts in pair)
        for kind, pair in grouped.items()
    }
    return SurfaceSamples(
        biaxial_strain=stacked["biaxial"][0],
        biaxial_stress=stacked["biaxial"][1],
        shear_strain=stacked["shear"][0],
        shear_stress=stacked["shear"][1],
        complete=np.array([run.complete for run in runs]),
        max_asymmetry=asymmetry,
    )


def stored_samples(surface: ResponseSurface) -> SurfaceSamples:
    """The samples a surface file stores, as the fit takes them (to refit a surface with other
    `FitOptions` without its RVE runs).

    S11 and S22 share the (E11, E22) inputs, S12 has E12 only; the fit reads no other
    component, so the others are left 0. Which runs the samples came from is not stored
    (`complete` is a single True) and neither is the equilibrium check (`max_asymmetry` 0).
    """
    groups = surface.samples
    if not groups:
        raise InputError("the surface stores no samples (an analytic or hand-made surface)")
    if not np.array_equal(groups["S11"].inputs, groups["S22"].inputs):
        raise InputError("the surface's S11 and S22 samples have different inputs")
    biaxial_strain = np.zeros((groups["S11"].values.size, 3))
    biaxial_strain[:, :2] = groups["S11"].inputs
    biaxial_stress = np.zeros_like(biaxial_strain)
    biaxial_stress[:, 0], biaxial_stress[:, 1] = groups["S11"].values, groups["S22"].values
    shear_strain = np.zeros((groups["S12"].values.size, 3))
    shear_strain[:, 2] = groups["S12"].inputs[:, 0]
    shear_stress = np.zeros_like(shear_strain)
    shear_stress[:, 2] = groups["S12"].values
    return SurfaceSamples(
        biaxial_strain, biaxial_stress, shear_strain, shear_stress, np.ones(1, bool), 0.0
    )
