"""The mesh checks before a part is solved (issue 31): `.geo` parameters, the size budget's
estimates against the cells gmsh makes, and the mesh's own problems on small meshes whose
answer is known."""

import math

import gmsh
import numpy as np
import pytest

from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.mesh.tagged import MESH_DIRECTORY, read_geo
from fabric_dolfinx.spec.mesh_checks import (
    check_cells,
    check_geo_parameters,
    estimated_geo_cells,
    geo_parameters,
    mesh_problems,
)
from fabric_dolfinx.spec.part import SHAPES, MeshSpec, shape_cells
from rve_rod.errors import InputError
from rve_rod.limits import PART_CELLS


def grid(nx: int, ny: int, x0: float = 0.0, h: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Points (n, 3) and counter-clockwise quads (m, 4) of an nx x ny grid of squares h."""
    x, y = np.meshgrid(x0 + h * np.arange(nx + 1), h * np.arange(ny + 1), indexing="ij")
    points = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    node = np.arange(x.size).reshape(nx + 1, ny + 1)
    quads = np.column_stack(
        [node[:-1, :-1].ravel(), node[1:, :-1].ravel(), node[1:, 1:].ravel(), node[:-1, 1:].ravel()]
    )
    return points, quads


def joined(first, second):
    points = np.concatenate([first[0], second[0]])
    return points, np.concatenate([first[1], second[1] + len(first[0])])


def test_a_conforming_grid_has_no_problem_in_either_orientation():
    points, quads = grid(4, 3)
    assert mesh_problems(points, quads, plane=True) == []
    assert mesh_problems(points, quads[:, ::-1], plane=True) == []  # clockwise cells


@pytest.mark.parametrize("divisions", [4, 5])
def test_a_seam_of_duplicated_nodes_is_not_conforming(divisions):
    """Two blocks side by side at x = 2 with their own nodes there, the same or different
    divisions along the seam: every edge of the seam lies on an edge of the other block."""
    left = grid(2, 4)
    right = grid(2, divisions, x0=2.0, h=4 / divisions)
    (problem,) = [p for p in mesh_problems(*joined(left, right), plane=True) if "conforming" in p]
    assert problem.startswith(f"the mesh is not conforming: {4 + divisions} boundary edges")


def test_two_pieces_apart_are_refused():
    problems = mesh_problems(*joined(grid(2, 2), grid(3, 1, x0=5.0)), plane=True)
    assert problems == [
        "the mesh is in 2 pieces that share no node (4, 3 cells): a part is one piece"
    ]


@pytest.mark.parametrize(
    ("corner", "count"),
    [((0.5, 0.5), 1), ((1.0, 0.0), 1), ((1.0, 1.0), 0), ((3.0, 3.0), 1)],
    ids=["reflex", "collapsed", "square", "crossed"],
)
def test_degenerate_and_inverted_cells(corner, count):
    """One cell (0,0), (1,0), C, (0,1): a reflex corner, a collapsed edge, a square and a
    crossed (bowtie) cell."""
    points = np.array([[0, 0, 0], [1, 0, 0], [*corner, 0], [0, 1, 0]], dtype=float)
    if corner == (3.0, 3.0):
        points[[1, 2]] = [[0, 1, 0], [1, 0, 0]]  # the edges cross
    problems = [p for p in mesh_problems(points, np.array([[0, 1, 2, 3]]), plane=True)]
    degenerate = [p for p in problems if "degenerate" in p]
    assert len(degenerate) == count, problems


def test_a_corner_of_half_a_degree_is_degenerate_and_one_of_two_degrees_is_not():
    for degrees, refused in ((0.5, True), (2.0, False)):
        a = math.radians(degrees)
        points = np.array([[0, 0, 0], [1, 0, 0], [1 + math.cos(a), math.sin(a), 0], [0, 1, 0]])
        problems = mesh_problems(points, np.array([[0, 1, 2, 3]]), plane=True)
        assert any("degenerate" in p for p in problems) == refused


def test_a_plane_part_must_lie_in_the_x_y_plane():
    points, quads = grid(2, 2)
    upright = points[:, [0, 2, 1]]  # drawn in x-z
    (problem,) = mesh_problems(upright, quads, plane=True)
    assert problem.startswith("the mesh is not in the x-y plane (it spans x 2 mm, y 0 mm, z 2 mm)")
    assert mesh_problems(upright, quads, plane=False) == []


def test_define_constant_names_ranges_and_includes(tmp_path):
    (tmp_path / "sizes.geo").write_text("DefineConstant[ size = {2, Min 0.5, Max 10} ];\n")
    (tmp_path / "part.geo").write_text(
        'Include "sizes.geo";\n// DefineConstant[ commented = 1 ];\n'
        'DefineConstant[\n  width = {50, Name "Parameters/width, (mm)"}\n'
        "  offset = {0, Min -5}\n];\n"
        "height = 20;\n"
    )
    path = tmp_path / "part.geo"
    assert geo_parameters(path) == {
        "size": (0.5, 10.0),
        "width": (None, None),
        "offset": (-5.0, None),
    }
    problems = check_geo_parameters(
        path, {"size": 20.0, "width": 0.0, "offset": -3.0, "height": 7.0}
    )
    assert problems == [
        "size: 20 is outside the range [0.5, 10] that part.geo declares",
        "width: 0 must be > 0 (a .geo parameter is a length or a size unless its "
        "DefineConstant declares Min and Max)",
        "height: part.geo declares no parameter 'height' (its DefineConstant parameters: "
        "offset, size, width); a variable set with a plain assignment cannot be set",
    ]


def test_read_geo_refuses_an_undeclared_parameter():
    with pytest.raises(InputError, match="declares no parameter 'sise'"):
        read_geo(MESH_DIRECTORY / "plate_with_hole.geo", parameters={"sise": 5.0})


@pytest.mark.parametrize("shape", [s for s in SHAPES if s != "tube"])
def test_the_shapes_estimate_is_at_most_their_cells_and_at_least_half(shape):
    spec = MeshSpec(shape, element_size=4.0)
    cells = make_mesh(spec).mesh.topology.index_map(2).size_global
    assert 0.5 * cells <= shape_cells(spec) <= cells


@pytest.mark.parametrize("size", [10.0, 5.0, 2.0])
def test_a_geo_files_estimate_from_its_boundary_is_at_most_its_cells_and_an_eighth(size):
    """The plate with a hole (unstructured, recombined: gmsh 4.8 splits the triangles): the
    1D estimate against the cells gmsh then makes."""
    gmsh.initialize(["fabric_dolfinx", "-setnumber", "size", repr(size)])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(MESH_DIRECTORY / "plate_with_hole.geo"))
        estimate = estimated_geo_cells()
        gmsh.model.mesh.generate(2)
        cells = sum(len(tags) for tags in gmsh.model.mesh.getElements(2)[1])
    finally:
        gmsh.finalize()
    assert cells / 8 <= estimate <= cells


def test_the_budget_counts_refinements_and_names_the_limit():
    check_cells("a part", PART_CELLS, 0)
    check_cells("a part", PART_CELLS / 4, 1)
    with pytest.raises(InputError) as error:
        check_cells("a part", PART_CELLS / 4 + 1, 1)
    message = str(error.value)
    assert message.startswith("a part gives about 4e+04 cells after 1 refinement(s)")
    assert f"at most {PART_CELLS} cells" in message


def test_make_mesh_refuses_a_shape_beyond_the_budget_before_meshing():
    with pytest.raises(InputError, match="a part may have at most 40000 cells"):
        make_mesh(MeshSpec("rectangle", element_size=0.001))
