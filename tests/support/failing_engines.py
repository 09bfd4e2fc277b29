"""Test-only RVE engines that fail on chosen runs (importable by worker processes and ranks:
tests/ is on their PYTHONPATH)."""

import dataclasses
import os
import signal

from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.generate import engine_identity


@dataclasses.dataclass(frozen=True)
class FailingRve(AnalyticRve):
    """The analytic RVE that raises (or kills its process) on the wale-wise ray of the knits
    whose wale width is `wale_width` (None: of every knit); same cache identity as
    AnalyticRve, so its finished runs are the analytic ones."""

    how: str = "raise"
    wale_width: float | None = None

    def cache_identity(self):
        return engine_identity(AnalyticRve())

    def fails(self, case) -> bool:
        knit = self.wale_width is None or case.fabric.knit.wale_width == self.wale_width
        return knit and case.load.kind == "biaxial" and case.load.angle_deg == 90.0

    def __call__(self, case):
        if self.fails(case):
            if self.how == "kill":
                os.kill(os.getpid(), signal.SIGKILL)
            raise RuntimeError("simulated crash")
        return super().__call__(case)
