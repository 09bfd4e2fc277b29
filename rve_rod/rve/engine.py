"""The rod RVE as the homogenization's engine: `surface_engine()` returns a picklable
`run(RveCase) -> RveRun` (see rve_rod.homogenize.samples) that follows a biaxial ray or the
pure-shear path of the sampling plan on the loop cell."""

from dataclasses import dataclass, field

from rve_rod.errors import ConvergenceError
from rve_rod.homogenize.samples import RveCase, RveRun
from rve_rod.rve.load_cases import BiaxialRay, LoadCase, Shear
from rve_rod.rve.simulation import RveSettings, simulate

__all__ = [
    "RodRve",
    "path_case",
    "surface_engine",
]


def path_case(load) -> LoadCase:
    """The load case of a sampling LoadPath: its `steps` output states after the unloaded
    one, at the same F (a LoadPath counts steps after the reference, a LoadCase with it)."""
    if load.kind == "shear":
        return Shear(steps=load.steps + 1, max_shear=load.max_load)
    return BiaxialRay(steps=load.steps + 1, angle_deg=load.angle_deg, max_load=load.max_load)


@dataclass(frozen=True)
class RodRve:
    """The rod RVE engine; its settings are part of the surface cache key.

    Attributes:
        settings: the RVE settings of every run.
    """

    settings: RveSettings = field(default_factory=RveSettings)

    def __call__(self, case: RveCase) -> RveRun:
        """Run the case's load path; a path that stops early raises ConvergenceError whose
        history is the RveRun of the converged states (complete=False)."""
        try:
            result = simulate(case.fabric, path_case(case.load), self.settings)
        except ConvergenceError as error:
            raise ConvergenceError(str(error), history=error.history.to_rve_run()) from error
        return result.to_rve_run()


def surface_engine() -> RodRve:
    """The engine `rve-rod surface` uses: the rod RVE with default settings."""
    return RodRve()
