"""A thin-walled closed-end tube under internal pressure (orthotropic SVK, course around the
circumference, on a curved gmsh surface): hoop force p r, axial force p R^2 / (2 r), and the
radius and length from the SVK law; the same answer on 1 and 2 MPI ranks. A tube of two
regions selected along its axis (z): each far from the joint takes its own material's state."""

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize

from fabric_dolfinx.material import OrthotropicSVK, svk_material
from fabric_dolfinx.mesh.surfaces import tube_mesh
from fabric_dolfinx.part.fields import PartFields
from fabric_dolfinx.part.problem import PartProblem
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.expression import SPACE, FieldExpression
from fabric_dolfinx.spec.part import BoundaryCondition
from fabric_dolfinx.spec.space import SpaceSpec

RADIUS, LENGTH, PRESSURE, SIZE = 10.0, 20.0, 0.01, 2.5  # mm, mm, N/mm^2, mm
SVK = OrthotropicSVK(
    course_stiffness=2.0, wale_stiffness=1.0, poissons_ratio=0.3, shear_stiffness=0.3
)
AROUND = math.ceil(0.5 * math.pi * RADIUS / SIZE)  # facets per quadrant
FACETED = math.cos(0.25 * math.pi / AROUND)  # apothem / circumradius of the faceted tube


def quarter_tube(comm=None, regions=None, length=LENGTH):
    """A quadrant with symmetry conditions; the closed end's axial force p pi R^2 as the dead
    load p R / 2 per length on the top edge. One region of SVK unless `regions` are given."""
    kwargs = {} if comm is None else {"comm": comm}
    tagged = tube_mesh(RADIUS, length, SIZE, quarter=True, **kwargs)
    return PartProblem(
        tagged,
        regions or [Region("fabric", svk_material(SVK))],
        [
            BoundaryCondition("bottom", "roller", component="z"),
            BoundaryCondition("x0", "roller", component="x"),
            BoundaryCondition("y0", "roller", component="y"),
            BoundaryCondition("top", "traction", (0.0, 0.0, PRESSURE * RADIUS / 2)),
        ],
        space=SpaceSpec(pressure=PRESSURE, course="around"),
        options=SolverOptions(steps=2),
    )


def expected_stretches(
    faceted: float, svk: OrthotropicSVK = SVK, shoulder: float | None = None
) -> np.ndarray:
    """(hoop, axial) stretches of the uniform state: S = C E with S11 = sigma_t l_z / l_t,
    S22 = sigma_z l_t / l_z, sigma_t = p r `faceted` (r = l_t R), sigma_z = p R / (2 l_t).

    With `shoulder` (the hoop stretch of the part of the tube between this one and the loaded
    end), the pressure on the shoulder between the two adds to the axial force: p times the
    difference of the two faceted quadrants' areas, AROUND r^2 sin(pi / (2 AROUND)) / 2."""
    matrix = svk.plane_stress_matrix()
    chords = 2 * AROUND * math.sin(0.25 * math.pi / AROUND)  # per unit radius

    def equations(stretch):
        hoop, axial = stretch
        strain = 0.5 * (np.array([hoop, axial]) ** 2 - 1.0)
        stress = matrix[:2, :2] @ strain
        sigma_hoop = PRESSURE * RADIUS * hoop * faceted
        sigma_axial = PRESSURE * RADIUS / (2 * hoop)
        if shoulder is not None:
            area = 0.5 * AROUND * math.sin(0.5 * math.pi / AROUND) * (hoop**2 - shoulder**2)
            sigma_axial += PRESSURE * RADIUS * area / (chords * hoop)
        return [stress[0] - sigma_hoop * axial / hoop, stress[1] - sigma_axial * hoop / axial]

    return scipy.optimize.fsolve(equations, [1.0, 1.0], xtol=1e-13)


@pytest.fixture(scope="module")
def inflated():
    problem = quarter_tube()
    return problem, problem.run()


def test_membrane_forces_are_hoop_p_r_and_axial_p_r_over_two(inflated):
    problem, result = inflated
    fields = PartFields(problem)
    fields.update()
    points = problem.u.function_space.tabulate_dof_coordinates()
    deformed = points + problem.u.x.array.reshape(-1, 3)
    radius = np.hypot(deformed[:, 0], deformed[:, 1])
    assert np.ptp(radius) < 1e-10 * RADIUS
    r = radius.mean()
    principal = fields.principal_stress.x.array.reshape(-1, 2)
    # the faceted tube carries p times its apothem; the smooth tube's p r is its limit
    np.testing.assert_allclose(principal[:, 0], PRESSURE * r * FACETED, rtol=1e-9)
    np.testing.assert_allclose(principal[:, 1], PRESSURE * RADIUS**2 / (2 * r), rtol=1e-9)
    assert abs(principal[:, 0].mean() / (PRESSURE * r) - 1) < 0.01
    assert np.all(fields.slack.x.array == 0.0)
    hoop, axial = expected_stretches(FACETED)
    assert r / RADIUS == pytest.approx(hoop, rel=1e-9)
    top = points[:, 2] > LENGTH - 1e-9
    assert 1 + problem.u.x.array.reshape(-1, 3)[top, 2].mean() / LENGTH == pytest.approx(
        axial, rel=1e-9
    )
    assert hoop - 1 > 0.02
    # the bottom support carries the end load: p R / 2 times the faceted quadrant's length
    # (p pi R^2 / 4 in the limit)
    chords = 2 * AROUND * RADIUS * math.sin(0.25 * math.pi / AROUND)
    end_load = PRESSURE * RADIUS / 2 * chords
    assert -result.boundaries["bottom"].force[-1, 2] == pytest.approx(end_load, rel=1e-10)
    assert end_load == pytest.approx(PRESSURE * math.pi * RADIUS**2 / 4, rel=0.01)


MPI_CASE = """
import json, sys
from mpi4py import MPI
sys.path.insert(0, {tests!r})
from test_membrane3d_tube import quarter_tube
problem = quarter_tube(MPI.COMM_WORLD)
result = problem.run()
if MPI.COMM_WORLD.rank == 0:
    print(json.dumps({{"ranks": result.ranks, "bottom": result.boundaries["bottom"].force.tolist(),
                      "peak": result.space.peak_displacement.tolist()}}))
"""


@pytest.mark.mpi
def test_one_and_two_ranks_agree(tmp_path):
    script = tmp_path / "case.py"
    script.write_text(MPI_CASE.format(tests=str(Path(__file__).parent)))
    env = {**os.environ, "OMPI_MCA_rmaps_base_oversubscribe": "1"}
    runs = []
    for ranks in (1, 2):
        command = ["mpirun", "-n", str(ranks), sys.executable, str(script)]
        process = subprocess.run(
            command, capture_output=True, text=True, env=env, timeout=300, check=False
        )
        assert process.returncode == 0, process.stderr
        runs.append(json.loads(process.stdout.strip().splitlines()[-1]))
    assert [r["ranks"] for r in runs] == [1, 2]
    np.testing.assert_allclose(runs[1]["bottom"], runs[0]["bottom"], rtol=1e-9, atol=1e-14)
    np.testing.assert_allclose(runs[1]["peak"], runs[0]["peak"], rtol=1e-9)


def test_a_band_selected_along_the_axis_takes_its_own_material_away_from_the_joint():
    """The lower half (z < 30 mm, a region `where` on z) half as stiff around the tube: away
    from the joint at z = 30 each half is the uniform tube of its own material, the lower
    one with the axial force of the pressure on the shoulder between them added."""
    band = OrthotropicSVK(
        course_stiffness=1.0, wale_stiffness=1.0, poissons_ratio=0.3, shear_stiffness=0.3
    )
    length = 60.0
    regions = [
        Region("fabric", svk_material(SVK)),
        Region("band", svk_material(band), where=FieldExpression("z < 30", "where", SPACE)),
    ]
    problem = quarter_tube(regions=regions, length=length)
    problem.run()
    layers = np.round(problem.cells.centres[:, 2] / SIZE - 0.5).astype(int)
    np.testing.assert_array_equal(problem.cells.index, (layers < 30 / SIZE).astype(int))
    points = problem.u.function_space.tabulate_dof_coordinates()
    deformed = points + problem.u.x.array.reshape(-1, 3)
    radius = np.hypot(deformed[:, 0], deformed[:, 1]) / RADIUS
    stiff, _ = expected_stretches(FACETED)
    soft, _ = expected_stretches(FACETED, band, shoulder=stiff)
    np.testing.assert_allclose(radius[points[:, 2] >= 50.0], stiff, rtol=1e-6)
    np.testing.assert_allclose(radius[points[:, 2] <= 10.0], soft, rtol=1e-6)
    assert soft - 1 > 1.8 * (stiff - 1)
