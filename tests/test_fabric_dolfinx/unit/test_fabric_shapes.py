"""Built-in shapes and user gmsh files: areas, boundary lengths, regions, clear errors."""

import math

import numpy as np
import pytest
from support.mesh_measures import integrate

from fabric_dolfinx.mesh.shapes import make_mesh
from fabric_dolfinx.spec.expression import FieldExpression
from fabric_dolfinx.spec.part import MeshSpec
from rve_rod.errors import InputError


def test_rectangle_strip_has_the_element_size_and_its_boundaries():
    tagged = make_mesh(MeshSpec("rectangle", {"width": 50.0, "height": 200.0}, element_size=10.0))
    assert tagged.mesh.topology.index_map(2).size_global == 5 * 20
    assert integrate(tagged) == pytest.approx(10000.0, rel=1e-12)
    lengths = {name: integrate(tagged, name) for name in tagged.boundaries}
    assert lengths == pytest.approx({"left": 200.0, "right": 200.0, "bottom": 50.0, "top": 50.0})
    assert tagged.regions == {"fabric": pytest.approx(tagged.regions["fabric"])}


def test_patch_is_the_papers_50_mm_square():
    tagged = make_mesh(MeshSpec("patch", element_size=5.0))
    assert tagged.mesh.topology.index_map(2).size_global == 100
    assert integrate(tagged) == pytest.approx(2500.0, rel=1e-12)


def test_cruciform_is_a_conforming_cross_with_free_edges():
    """Core 40 mm, arms 30 mm: area 5 squares of 40 x 40 ... the arms are 40 x 30."""
    spec = MeshSpec("cruciform", {"width": 40.0, "arm_length": 30.0}, element_size=10.0)
    tagged = make_mesh(spec)
    assert integrate(tagged) == pytest.approx(40.0 * 40.0 + 4 * 40.0 * 30.0, rel=1e-12)
    for name in ("left", "right", "bottom", "top"):
        assert integrate(tagged, name) == pytest.approx(40.0, rel=1e-12)
    assert integrate(tagged, "edges") == pytest.approx(8 * 30.0, rel=1e-12)
    # conforming: 16 core + 4 x 12 arm cells, nodes shared (no duplicate at the core edges)
    assert tagged.mesh.topology.index_map(2).size_global == 16 + 4 * 12
    assert tagged.mesh.topology.index_map(0).size_global == 25 + 4 * 15


def test_disc_area_converges_to_pi_r_squared_with_the_element_size():
    errors = []
    for size in (4.0, 2.0, 1.0):
        tagged = make_mesh(MeshSpec("disc", {"radius": 10.0}, element_size=size))
        errors.append(abs(integrate(tagged) - math.pi * 100.0))
    rim = integrate(make_mesh(MeshSpec("disc", {"radius": 10.0}, element_size=1.0)), "rim")
    assert rim == pytest.approx(2 * math.pi * 10.0, rel=2e-3)
    # polygonal rim: the area error falls with the square of the element size
    assert np.log2(errors[0] / errors[1]) == pytest.approx(2.0, abs=0.2)
    assert np.log2(errors[1] / errors[2]) == pytest.approx(2.0, abs=0.2)


def test_plate_with_hole_names_the_hole():
    tagged = make_mesh(MeshSpec("plate_with_hole", {"radius": 8.0}, element_size=5.0))
    assert set(tagged.boundaries) == {"left", "right", "bottom", "top", "hole"}
    assert integrate(tagged, "hole") == pytest.approx(2 * math.pi * 8.0, rel=0.02)


def two_region_geo(tmp_path, recombine=True):
    """A 20 x 10 strip of two conforming squares, regions "a" and "b"."""
    text = """
Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {20, 0, 0};
Point(4) = {20, 10, 0}; Point(5) = {10, 10, 0}; Point(6) = {0, 10, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5};
Line(5) = {5, 6}; Line(6) = {6, 1}; Line(7) = {2, 5};
Curve Loop(1) = {1, 7, 5, 6}; Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, -7}; Plane Surface(2) = {2};
Transfinite Curve{:} = 5; Transfinite Surface{1, 2};
Physical Curve("clamp") = {6}; Physical Curve("pull") = {3};
Physical Surface("a") = {1}; Physical Surface("b") = {2};
"""
    if recombine:
        text += "Recombine Surface{1, 2};\n"
    path = tmp_path / ("strip.geo" if recombine else "strip_triangles.geo")
    path.write_text(text)
    return path


def test_a_gmsh_file_names_its_regions_and_boundaries_and_is_conforming(tmp_path):
    tagged = make_mesh(MeshSpec(shape=None, file=str(two_region_geo(tmp_path))))
    assert set(tagged.regions) == {"a", "b"} and set(tagged.boundaries) == {"clamp", "pull"}
    areas = [tagged.cells(name).size for name in ("a", "b")]
    assert sum(areas) == tagged.mesh.topology.index_map(2).size_local == 32
    assert tagged.mesh.topology.index_map(0).size_global == 9 * 5  # shared interface nodes


def test_a_msh_file_is_read_as_it_is(tmp_path):
    import gmsh  # noqa: PLC0415

    geo = two_region_geo(tmp_path)
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(geo))
        gmsh.model.mesh.generate(2)
        gmsh.write(str(tmp_path / "strip.msh"))
    finally:
        gmsh.finalize()
    tagged = make_mesh(MeshSpec(shape=None, file="strip.msh"), base=tmp_path)
    assert tagged.mesh.topology.index_map(2).size_global == 32
    assert integrate(tagged, "pull") == pytest.approx(10.0, rel=1e-12)


def test_a_mesh_with_triangles_is_refused_with_a_hint(tmp_path):
    with pytest.raises(InputError, match=r"Triangle.*only 4-node quadrilaterals.*Recombine"):
        make_mesh(MeshSpec(shape=None, file=str(two_region_geo(tmp_path, recombine=False))))


def test_unknown_names_list_the_names_the_mesh_has():
    tagged = make_mesh(MeshSpec("patch", element_size=25.0))
    with pytest.raises(InputError, match=r"'side' is not tagged; tagged: .*'bottom', 'left'"):
        tagged.facets("side")
    with pytest.raises(InputError, match=r"'core' is not tagged; tagged: \['fabric'\]"):
        tagged.cells("core")


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        (dict(shape="circle"), "shape='circle' is not one of rectangle, patch"),
        (dict(shape="disc", dimensions={"width": 3.0}), "'width' is not a dimension of disc"),
        (dict(shape="rectangle", dimensions={"width": -3.0}), "width"),
        (dict(shape="patch", file="x.geo"), "exactly one of shape and file"),
        (dict(shape="patch", element_size=0.0), "element_size"),
    ],
)
def test_bad_mesh_specs_name_the_parameter(spec, message):
    with pytest.raises(InputError, match=message):
        MeshSpec(**spec)


def test_field_expressions_evaluate_elementwise_and_refuse_anything_else():
    x, y = np.array([0.0, 50.0, 100.0]), np.array([0.0, 10.0, 20.0])
    angle = FieldExpression("45 + 10 * sin(pi * x / 200)")
    np.testing.assert_allclose(angle(x, y), 45 + 10 * np.sin(np.pi * x / 200), rtol=1e-15)
    band = FieldExpression("5 < y <= 20 and x > 10")
    np.testing.assert_array_equal(band(x, y), [0.0, 1.0, 1.0])
    for text, message in (
        ("__import__('os')", "unknown function '__import__'"),
        ("x.real", "Attribute"),
        ("z + 1", "unknown name 'z'"),
        ("x +", "not an expression"),
        ("'a'", "non-number"),
    ):
        with pytest.raises(InputError, match=message):
            FieldExpression(text, key="region.angle")
    with pytest.raises(InputError, match="not finite"):
        FieldExpression("1 / x")(x, y)
