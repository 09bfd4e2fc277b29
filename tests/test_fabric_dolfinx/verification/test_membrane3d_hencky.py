"""Hencky's clamped circular membrane under uniform pressure (isotropic linear SVK, small
strain): central deflection and radial stress against Hencky's series, and the deflection's
mesh-convergence rate."""

import numpy as np
import pytest
import scipy.integrate
import scipy.optimize

from fabric_dolfinx.material import OrthotropicSVK, svk_material
from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.part.fields import PartFields
from fabric_dolfinx.part.problem import PartProblem
from fabric_dolfinx.part.regions import Region
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.part import BoundaryCondition, MeshSpec
from fabric_dolfinx.spec.space import SpaceSpec

STIFFNESS, POISSON, RADIUS, PRESSURE = 10.0, 0.3, 50.0, 2e-6  # N/mm, -, mm, N/mm^2
LOAD = PRESSURE * RADIUS / STIFFNESS  # Q = q a / (E h): strains ~ Q^(2/3) = 1e-4


def hencky_coefficients(poisson: float, terms: int = 60) -> np.ndarray:
    """b_k of N_r = C sum_k b_k rho^(2k), C = (E h q^2 a^2)^(1/3) / 4, rho = r / a.

    The Foppl equations of the axisymmetric membrane reduce to s'' + 3 s' / rho = -8 / s^2
    for s = N_r / C; the power series' coefficients follow from s^2 (s'' + 3 s' / rho) = -8
    order by order, and b_0 from the clamped rim (u(a) = 0: N_theta = nu N_r there, i.e.
    sum_k (2k + 1 - nu) b_k = 0).
    """

    def series(b0):
        b = [b0]
        for m in range(terms - 1):
            square = np.convolve(b, b)
            known = sum(4 * (j + 1) * (j + 2) * b[j + 1] * square[m - j] for j in range(m))
            c_m = ((-8.0 if m == 0 else 0.0) - known) / square[0]
            b.append(c_m / (4 * (m + 1) * (m + 2)))
        return np.array(b)

    def rim(b0):
        b = series(b0)
        return np.sum((2 * np.arange(b.size) + 1 - poisson) * b)

    return series(scipy.optimize.brentq(rim, 1.0, 3.0))


COEFFICIENTS = hencky_coefficients(POISSON)
STRESS_SCALE = (STIFFNESS * PRESSURE**2 * RADIUS**2) ** (1 / 3) / 4  # C, N/mm


def hencky_radial_stress(rho):
    return STRESS_SCALE * np.polynomial.polynomial.polyval(np.asarray(rho) ** 2, COEFFICIENTS)


def hencky_deflection():
    """w(0) = (q a^2 / 2 C) int_0^1 rho / s(rho) d rho (mm), from N_r w' = -q r / 2."""
    integral = scipy.integrate.quad(
        lambda rho: rho / hencky_radial_stress(rho) * STRESS_SCALE, 0.0, 1.0, epsabs=1e-14
    )[0]
    return PRESSURE * RADIUS**2 / (2 * STRESS_SCALE) * integral


def test_series_matches_the_published_constants():
    """b_0 = 1.7244 and w0 = 0.6535 a Q^(1/3) for nu = 0.3 (Fichter, NASA TP-3658, 1997)."""
    assert COEFFICIENTS[0] == pytest.approx(1.7244, abs=1e-4)
    assert hencky_deflection() / (RADIUS * LOAD ** (1 / 3)) == pytest.approx(0.6535, abs=1e-4)
    assert abs(COEFFICIENTS[-1]) < 1e-6 * COEFFICIENTS[0]


def solve(size):
    tagged = make_mesh(MeshSpec("disc", {"radius": RADIUS}, element_size=size))
    svk = OrthotropicSVK(STIFFNESS, STIFFNESS, POISSON, STIFFNESS / (2 * (1 + POISSON)))
    problem = PartProblem(
        tagged,
        [Region("fabric", svk_material(svk))],
        [BoundaryCondition("rim")],
        space=SpaceSpec(pressure=PRESSURE),
        options=SolverOptions(steps=1),
    )
    result = problem.run()
    return problem, result


@pytest.fixture(scope="module")
def meshes():
    return {size: solve(size) for size in (10.0, 5.0, 2.5)}


def test_central_deflection_converges_to_hencky_at_second_order(meshes):
    expected = hencky_deflection()
    errors = []
    for problem, result in meshes.values():
        displacement = problem.u.x.array.reshape(-1, 3)
        centre = np.argmin(
            np.linalg.norm(problem.u.function_space.tabulate_dof_coordinates(), axis=1)
        )
        assert result.space.peak_displacement[-1] == pytest.approx(
            displacement[centre, 2], rel=1e-12
        )
        errors.append(abs(displacement[centre, 2] - expected) / expected)
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(rates > 1.6), (errors, rates)
    assert errors[-1] < 5e-4


def test_radial_stress_follows_hencky(meshes):
    problem, result = meshes[2.5]
    fields = PartFields(problem)
    fields.update()
    mesh = problem.tagged.mesh
    cells = mesh.topology.index_map(2).size_local
    nodes = mesh.geometry.dofmap.array.reshape(-1, 4)[:cells]
    centres = mesh.geometry.x[nodes, :2].mean(axis=1)
    dofs = fields.cauchy.function_space.dofmap.list.array.reshape(-1, 1)[:cells, 0]
    cauchy = fields.cauchy.x.array.reshape(-1, 3, 3)[dofs]
    radius = np.linalg.norm(centres, axis=1)
    keep = radius > 0.1 * RADIUS
    direction = np.column_stack([centres[keep] / radius[keep, None], np.zeros(keep.sum())])
    radial = np.einsum("ni,nij,nj->n", direction, cauchy[keep], direction)
    expected = hencky_radial_stress(radius[keep] / RADIUS)
    assert np.abs(radial - expected).max() < 0.02 * expected.max()
    assert np.all(fields.slack.x.array == 0.0)
    assert (result.space.wrinkled_area[-1], result.space.slack_area[-1]) == (
        0.0,
        0.0,
    )  # taut everywhere
