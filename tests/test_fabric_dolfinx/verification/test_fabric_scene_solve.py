"""Fabric parts with regions and named boundary conditions against exact solutions.

- Two regions in series under an edge traction: each is in uniaxial stress (Poisson ratio 0,
  rollers on the symmetry lines), so the elongation is that of two springs in series; for the
  SVK law exactly (1 + e) E1 ((1 + e)^2 - 1) / 2 = t in each region, which the Q1 solution
  reproduces to round-off; to first order in t/E the linear springs t (L1/E1 + L2/E2).
- The course direction given as an expression of x, y: every cell's stress under a
  homogeneous deformation equals the rotated SVK law at the angle of its centre; a course
  direction of 90 degrees equals the material with its axes swapped.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize

from fabric_dolfinx.material import OrthotropicSVK, svk_material
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.fields import PartFields, principal_stresses
from fabric_dolfinx.part.problem import PartProblem
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.expression import FieldExpression
from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from rve_rod.errors import InputError

SOFT = OrthotropicSVK(course_stiffness=1.0, wale_stiffness=0.5, poissons_ratio=0.0)
STIFF = OrthotropicSVK(course_stiffness=3.0, wale_stiffness=0.5, poissons_ratio=0.0)
STRIP = MeshSpec("rectangle", {"width": 100.0, "height": 20.0}, element_size=10.0)


def uniaxial_svk_strain(stiffness: float, traction: float) -> float:
    """Engineering strain e of a Poisson-free SVK bar: (1 + e) E ((1 + e)^2 - 1) / 2 = t."""
    return scipy.optimize.brentq(
        lambda e: (1 + e) * stiffness * ((1 + e) ** 2 - 1) / 2 - traction, 0.0, 1.0, xtol=1e-15
    )


def strip_problem(regions, traction=(0.05, 0.0)):
    conditions = [
        BoundaryCondition("left", "roller", component="x"),
        BoundaryCondition("bottom", "roller", component="y"),
        BoundaryCondition("right", "traction", vector=traction),
    ]
    return PartProblem(make_mesh(STRIP), regions, conditions, options=SolverOptions(steps=2))


def test_two_regions_in_series_elongate_like_two_springs():
    traction = 0.05  # N/mm
    regions = [
        Region("fabric", svk_material(SOFT)),
        Region("stiff", svk_material(STIFF), where=FieldExpression("x > 40")),
    ]
    result = strip_problem(regions, (traction, 0.0)).run()
    elongation = result.boundaries["right"].displacement[-1, 0]
    exact = 40.0 * uniaxial_svk_strain(1.0, traction) + 60.0 * uniaxial_svk_strain(3.0, traction)
    springs = traction * (40.0 / 1.0 + 60.0 / 3.0)
    assert elongation == pytest.approx(exact, rel=1e-9)
    assert elongation == pytest.approx(springs, rel=1.5 * traction / 1.0)
    # the roller carries the applied force: 0.05 N/mm x 20 mm
    np.testing.assert_allclose(result.boundaries["right"].force[-1], [1.0, 0.0], rtol=1e-12)
    np.testing.assert_allclose(result.boundaries["left"].force[-1], [-1.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(result.load_factor, [0.0, 0.5, 1.0])


def test_course_direction_field_rotates_a_homogeneous_state_cell_by_cell():
    angle = FieldExpression("20 + 0.5 * x - 0.3 * y")
    material = OrthotropicSVK(course_stiffness=2.0, wale_stiffness=0.7, poissons_ratio=0.3)
    problem = strip_problem([Region("fabric", svk_material(material), angle=angle)])
    gradient = np.array([[0.08, 0.03], [-0.02, 0.05]])  # H, u = H X
    problem.u.interpolate(lambda X: gradient @ X[:2])
    fields = PartFields(problem)
    fields.update()
    owned = problem.tagged.mesh.topology.index_map(2).size_local
    centres = problem.cells.centres[:owned]
    F = np.eye(2) + gradient
    E = 0.5 * (F.T @ F - np.eye(2))
    C = material.plane_stress_matrix()
    dofs = problem.angle.function_space.dofmap.list.array[:owned]
    cauchy = fields.cauchy.x.array.reshape(-1, 2, 2)[dofs]
    for cell, (x, y) in enumerate(centres):
        phi = np.radians(20 + 0.5 * x - 0.3 * y)
        R = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
        Em = R.T @ E @ R
        Sm = np.array(
            [
                [C[0, 0] * Em[0, 0] + C[0, 1] * Em[1, 1], C[2, 2] * Em[0, 1]],
                [C[2, 2] * Em[0, 1], C[1, 0] * Em[0, 0] + C[1, 1] * Em[1, 1]],
            ]
        )
        expected = F @ (R @ Sm @ R.T) @ F.T / np.linalg.det(F)
        np.testing.assert_allclose(cauchy[cell], expected, rtol=1e-12, atol=1e-14)
    values, directions = principal_stresses(cauchy)
    for tensor, (largest, _), direction in zip(cauchy, values, directions, strict=True):
        np.testing.assert_allclose(tensor @ direction, largest * direction, atol=1e-13)


def test_course_direction_of_90_degrees_equals_the_swapped_material():
    material = OrthotropicSVK(course_stiffness=2.0, wale_stiffness=0.7, poissons_ratio=0.3)
    swapped = OrthotropicSVK(
        course_stiffness=0.7, wale_stiffness=2.0, poissons_ratio=0.3 * 0.7 / 2.0
    )
    rotated = strip_problem(
        [Region("fabric", svk_material(material), angle=FieldExpression("90 + 0 * x"))],
        traction=(0.1, 0.02),
    ).run()
    plain = strip_problem([Region("fabric", svk_material(swapped))], traction=(0.1, 0.02)).run()
    for name in ("left", "right", "bottom"):
        np.testing.assert_allclose(
            rotated.boundaries[name].displacement, plain.boundaries[name].displacement, atol=1e-12
        )
        np.testing.assert_allclose(
            rotated.boundaries[name].force, plain.boundaries[name].force, atol=1e-10
        )


def test_overlapping_and_unknown_boundary_conditions_are_refused():
    regions = [Region("fabric", svk_material(SOFT))]
    tagged = make_mesh(STRIP)
    twice = [BoundaryCondition("left"), BoundaryCondition("left", "roller")]
    with pytest.raises(InputError, match="overlap: left given twice"):
        PartProblem(tagged, regions, twice)
    with pytest.raises(InputError, match=r"'side' is not a physical curve.*bottom, left, right"):
        PartProblem(tagged, regions, [BoundaryCondition("side")])
    with pytest.raises(InputError, match=r"'core' is not a physical surface.*regions: fabric"):
        PartProblem(tagged, [Region("core", svk_material(SOFT))], [BoundaryCondition("left")])
    empty = [*regions, Region("none", svk_material(SOFT), where=FieldExpression("x > 500"))]
    with pytest.raises(InputError, match="none hold no cell"):
        PartProblem(tagged, empty, [BoundaryCondition("left")])
    part = [Region("half", svk_material(SOFT), where=FieldExpression("x < 50"))]
    with pytest.raises(InputError, match="10 cells belong to no region"):
        PartProblem(tagged, part, [BoundaryCondition("left")])


def test_overlapping_physical_curves_are_refused(tmp_path):
    geo = tmp_path / "square.geo"
    geo.write_text(
        "Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {10, 10, 0};\n"
        "Point(4) = {0, 10, 0}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4};\n"
        "Line(4) = {4, 1}; Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
        "Transfinite Curve{:} = 3; Transfinite Surface{1}; Recombine Surface{1};\n"
        'Physical Curve("left") = {4}; Physical Curve("edge") = {4, 1};\n'
        'Physical Curve("right") = {2}; Physical Surface("fabric") = {1};\n'
    )
    with pytest.raises(InputError, match="curve 4 belongs to the physical curves 'left' and"):
        make_mesh(MeshSpec(shape=None, file=str(geo)))


MPI_ENV = {
    **os.environ,
    "OMPI_ALLOW_RUN_AS_ROOT": "1",
    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
    "OMPI_MCA_rmaps_base_oversubscribe": "1",
}


def run_case(ranks: int) -> dict:
    command = [sys.executable, str(Path(__file__).with_name("scene_mpi_case.py"))]
    if ranks > 1:
        command = ["mpirun", "-n", str(ranks), *command]
    process = subprocess.run(
        command, check=False, capture_output=True, text=True, env=MPI_ENV, timeout=300
    )
    assert process.returncode == 0, process.stderr
    return json.loads(process.stdout)


@pytest.mark.mpi
@pytest.mark.slow
def test_a_multi_region_scene_gives_the_same_answer_on_one_and_two_ranks():
    serial, parallel = run_case(1), run_case(2)
    assert (serial["ranks"], parallel["ranks"]) == (1, 2)
    assert serial["dofs"] == parallel["dofs"]
    for name, curve in serial["boundaries"].items():
        for key in ("force", "displacement"):
            np.testing.assert_allclose(
                parallel["boundaries"][name][key], curve[key], rtol=1e-8, atol=1e-11
            )
    assert serial["boundaries"]["right"]["force"][-1][0] > 0.1
