"""The macro stage: the patch tension test of a scene on its response surface (DOLFINx).

`run_patch` runs one direction (`fabric_dolfinx.part.tension`), writes the XDMF file of every step
(`paraview/patch_<direction>.xdmf` with its `.h5`) and the stress map of the paper's
Figure 8 (`figures/stress_<direction>.png`), and measures the patch's lateral contraction
across its middle (the effective Poisson ratio of the clamped patch) and the strains of a gauge
at its centre, as a video extensometer does in a tensile test (`PatchProbe`, an observer of the
load path). It is collective under
MPI; the pipeline runs it as the `patch` job (`knitmech.jobs`: in-process on one rank, or
under mpirun).
"""

import logging
from pathlib import Path

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from fabric_dolfinx.io.plot import plot_cell_field
from fabric_dolfinx.material import surface_material
from fabric_dolfinx.part.probes import PointProbe
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import DIRECTIONS
from knitmech.stages.records import PatchJob, PatchSummary
from rve_rod.errors import ConvergenceError, InputError
from rve_rod.surface import homogeneous_response, read_surface
from rve_rod.units import n_per_mm_to_gf_per_cm

__all__ = [
    "GAUGE_FRACTION",
    "STRESS_COMPONENT",
    "PatchProbe",
    "run_patch",
    "run_request",
]

logger = logging.getLogger(__name__)

STRESS_COMPONENT = {"course": (0, 0), "wale": (1, 1)}
"""The Cauchy stress component drawn for each direction (along the load)."""


GAUGE_FRACTION = 0.2
"""Length of the centre gauge as a fraction of the patch size: the marks a video extensometer
follows at the sample's centre (the tests' Poisson ratios), 10 mm on the 50 mm patch."""


class PatchProbe:
    """The patch's strains as a tensile test measures them, at the current displacement (an
    observer of `TensionSetup.run`):

    - `lateral`: the change of distance between the midpoints of the two free edges over the
      patch size (the width change across the middle, clamps included);
    - `gauge`: (axial, lateral) engineering strains of the centre gauge, marks GAUGE_FRACTION x
      size apart along and across the load through the patch's centre.
    """

    def __init__(self, u: fem.Function, size: float, direction: str):
        self.load_axis = DIRECTIONS[direction][2]
        self.lateral_axis = 1 - self.load_axis
        self.size = size
        self.gauge_length = GAUGE_FRACTION * size
        points = np.full((6, 2), size / 2)
        points[0, self.lateral_axis] = 0.0
        points[1, self.lateral_axis] = size
        marks = [(axis, sign) for axis in (self.load_axis, self.lateral_axis) for sign in (-1, 1)]
        for row, (axis, sign) in enumerate(marks, start=2):
            points[row, axis] += sign * self.gauge_length / 2
        self.probe = PointProbe(u, points)

    def __call__(self) -> tuple[float, float, float]:
        """(lateral strain across the middle, gauge axial strain, gauge lateral strain) (-)."""
        u = self.probe()
        across = (u[1, self.lateral_axis] - u[0, self.lateral_axis]) / self.size
        axial = (u[3, self.load_axis] - u[2, self.load_axis]) / self.gauge_length
        lateral = (u[5, self.lateral_axis] - u[4, self.lateral_axis]) / self.gauge_length
        return across, axial, lateral


def run_patch(job: PatchJob, surface_path: Path, folder: Path, comm=MPI.COMM_WORLD) -> PatchSummary:
    """Run the tension test of `job` on the surface file; files go into `folder`.

    Returns the PatchSummary: strain, force (gf/cm, N/mm), the force of the material alone in
    homogeneous uniaxial tension (gf/cm, what the RVE's uniaxial case gives when the surface
    reproduces it), lateral strain and Poisson ratio per step, the centre gauge's strains,
    Newton iterations, cutbacks, whether strains left the surface domain, DOFs, ranks, times,
    `complete` (False when the solver gave up; the converged steps are kept) and
    `force_positive` (False flags a spurious equilibrium, e.g. on a surface that softens).
    """
    test = job.test
    folder = Path(folder)
    if comm.rank == 0:
        for part in ("figures", "paraview"):
            (folder / part).mkdir(exist_ok=True)
    comm.barrier()
    surface = read_surface(surface_path)
    material = surface_material(surface, name=Path(surface_path).name)
    setup = TensionSetup(material, test, SolverOptions(steps=job.steps), comm)
    probe = PatchProbe(setup.u, test.size, test.direction)
    field_strain = job.field_strain

    def on_step(strain, fields):
        if abs(strain - field_strain) < 1e-9:
            plot_cell_field(
                fields,
                folder / "figures" / f"stress_{test.direction}.png",
                component=STRESS_COMPONENT[test.direction],
                title=f"{test.direction}-wise tension, {100 * strain:.3g} % strain",
            )

    message = ""
    try:
        result = setup.run(
            xdmf=folder / "paraview" / f"patch_{test.direction}.xdmf",
            on_step=on_step,
            observers={"gauge": probe},
        )
    except ConvergenceError as error:
        result, message = error.history, str(error)
    strain = result.strain
    pulled = result.force_gf_per_cm[1:]
    if np.any(pulled <= 0.0):
        logger.warning(
            "macro %s: the clamp force is not positive at strain %.3g: not a physical solution "
            "(see the surface's softest_tangents in summary.json)",
            test.direction,
            strain[1:][np.argmax(pulled <= 0.0)],
        )
    alone = [0.0] + [_material_alone(surface, value, test.direction) for value in strain[1:]]
    lateral_strain, gauge_strain, gauge_lateral = np.array(result.observed["gauge"]).T
    with np.errstate(divide="ignore", invalid="ignore"):
        poisson = np.where(strain > 0, -lateral_strain / strain, np.nan)
    return PatchSummary(
        direction=test.direction,
        complete=not message,
        force_positive=bool(np.all(pulled > 0.0)),
        message=message,
        strain=strain,
        force_gf_per_cm=result.force_gf_per_cm,
        force_n_per_mm=result.force_n_per_mm,
        material_uniaxial_gf_per_cm=alone,
        lateral_strain=lateral_strain,
        gauge_strain=gauge_strain,
        gauge_lateral_strain=gauge_lateral,
        poisson_ratio=poisson,
        newton_iterations=result.newton_iterations,
        cutbacks=result.cutbacks,
        outside_domain=result.outside_domain,
        dofs=result.dofs,
        ranks=result.ranks,
        solve_time_s=result.wall_time_s,
        field_strain=field_strain,
    )


def _material_alone(surface, strain: float, direction: str) -> float | None:
    """The material's own force in homogeneous uniaxial tension (gf/cm); None where no lateral
    strain makes the lateral stress vanish (a fit that is not monotone far outside its data)."""
    try:
        force = homogeneous_response(surface, np.array([strain]), direction)[0]
    except InputError as error:
        logger.warning("material alone, %s-wise: %s", direction, error)
        return None
    return float(n_per_mm_to_gf_per_cm(force))


def run_request(request: dict, folder: Path, comm) -> dict:
    """The `patch` job (`knitmech.jobs`): request {"job": PatchJob JSON, "surface": path}."""
    job = PatchJob.from_json(request["job"])
    return run_patch(job, Path(request["surface"]), Path(folder), comm).to_json()
