"""gmsh meshes: element counts, areas and boundary lengths against the geometry."""

import numpy as np
import pytest
from dolfinx.mesh import CellType
from support.mesh_measures import integrate

from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.mesh.tagged import MESH_DIRECTORY, read_geo
from fabric_dolfinx.spec.part import MeshSpec
from rve_rod.errors import InputError


def test_rectangle_has_the_requested_elements_and_tagged_edges():
    tagged = make_mesh(MeshSpec("rectangle", {"width": 30.0, "height": 20.0}, element_size=5.0))
    domain = tagged.mesh
    assert domain.topology.cell_type == CellType.quadrilateral
    assert domain.topology.index_map(2).size_global == 24
    assert integrate(tagged) == pytest.approx(600.0, rel=1e-12)
    lengths = {name: integrate(tagged, name) for name in ("left", "right", "bottom", "top")}
    assert lengths == pytest.approx({"left": 20.0, "right": 20.0, "bottom": 30.0, "top": 30.0})


def test_plate_with_hole_refines_towards_the_exact_geometry():
    """Area error of the polygonal hole falls by 4 per refinement (new nodes on the circle)."""
    exact_area = 50.0 * 50.0 - np.pi * 10.0**2
    meshes = [
        make_mesh(MeshSpec("plate_with_hole", element_size=10.0, refinements=r)) for r in range(3)
    ]
    cells = [tagged.mesh.topology.index_map(2).size_global for tagged in meshes]
    assert cells[1] == 4 * cells[0] and cells[2] == 4 * cells[1]
    errors = np.array([integrate(tagged) - exact_area for tagged in meshes])
    assert np.all(errors > 0.0)  # chords cut the circle: the hole is too small
    np.testing.assert_allclose(errors[:-1] / errors[1:], 4.0, rtol=0.05)
    circumference = integrate(meshes[-1], "hole")
    assert circumference == pytest.approx(2 * np.pi * 10.0, rel=2e-3)
    assert set(meshes[0].boundaries) == {"left", "right", "bottom", "top", "hole"}


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (
            lambda: make_mesh(MeshSpec("plate_with_hole", {"radius": 25.0})),
            "radius=25 mm must be below half the plate's smaller side (25 mm)",
        ),
        (lambda: MeshSpec("rectangle", element_size=0.0), "element_size=0 mm must be > 0"),
        (lambda: MeshSpec("rectangle", {"width": -5.0}), "width=-5 mm must be > 0"),
        (lambda: read_geo(MESH_DIRECTORY / "missing.geo"), "missing.geo does not exist"),
        (lambda: make_mesh(MeshSpec("rectangle", element_size=50.0)).facets("hole"), "'hole' is"),
    ],
)
def test_bad_mesh_input_names_the_parameter(make, message):
    with pytest.raises(InputError) as error:
        make()
    assert message in str(error.value)
