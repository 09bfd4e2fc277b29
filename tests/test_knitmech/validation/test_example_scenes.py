"""The example scenes of examples/ run through `knitmech run` at the fast level, each asserting
one physical number against an expectation computed another way.

* patch (course, wale): the part's clamp force equals the [macro] patch test of
  `fabric_dolfinx.part.tension` on the same mesh and steps (separate code: its own boundary
  conditions and reaction) to 1e-8.
* strip tensile test: the long strip contracts freely between its clamps; its force per width
  lies between the material's homogeneous uniaxial (lateral stress 0) and strip-biaxial
  (lateral stretch 1) responses, within 2 % of the uniaxial one at 20 % strain (measured
  +0.4 %).
* bias extension (SVK variant: stiff yarns, E/G = 2000, small shear angles): the central
  zone's shear angle against the pin-jointed-net kinematics 90 - 2 acos((D + d)/(sqrt 2 D)).
* cruciform (SVK variant with equal course and wale moduli): the course-wise arm force equals
  the wale-wise one (the cross and the load are symmetric under x <-> y) and the four arm
  forces are in equilibrium.
* graded strip (variant with a constant stitch of 5.5, the shipped surface's: one member):
  equals the same strip with the plain knit to round-off.
* plate with a hole (isotropic SVK variant without Poisson contraction, small strain): far
  from the hole the stress is the nominal force per width (Saint-Venant); beside the hole it
  is raised (at most the Kirsch factor 3 times the finite-width factor of Heywood).

Besides: the bias-extension run's results folder (curves, figures, every XDMF field against
the displacement it was computed from and the SVK law), its rerun from the cache, and a
two-region plate with a hole under `mpirun -n 2` against one rank.
"""

import json
import re
import tomllib
from pathlib import Path

import h5py
import numpy as np
import pytest
from PIL import Image

from fabric_dolfinx.material import OrthotropicSVK, surface_material
from fabric_dolfinx.part.tension import TensionSetup
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.spec.tension import TensionTest
from knitmech.pipeline import run_scene
from knitmech.scene import load_scene, scene_from_dict
from rve_rod.surface import homogeneous_response, read_surface

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"
SCENES = sorted(EXAMPLES.glob("*.toml"))
"""The example scenes (examples/sweeps/ holds sweep files:
tests/test_knitmech/unit/test_sweep.py)."""


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("example-cache")


def run_example(name, folder, cache, edit=None):
    """Run examples/<name>.toml at the fast level without its meso runs; `edit` changes the
    parsed TOML first. Returns the summary's part record and the scene."""
    data = tomllib.loads((EXAMPLES / f"{name}.toml").read_text())
    data["meso"]["cases"] = []
    if edit is not None:
        edit(data)
    scene = scene_from_dict(data, source=name, base=EXAMPLES)
    result = run_scene(scene, fidelity="fast", output=folder, cache_dir=cache)
    part = result.summary["part"]
    assert part["complete"], part["message"]
    return part, result


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_every_example_scene_is_valid(path):
    scene = load_scene(path)
    assert scene.part is not None
    if scene.surface.path is None:  # the stitch-pattern examples compute their knit's
        assert scene.fabric.pattern is not None or scene.fabric.chart is not None
    else:
        assert Path(scene.surface.path).is_file()


@pytest.mark.slow
@pytest.mark.parametrize(("name", "axis"), [("patch_course", 0), ("patch_wale", 1)])
def test_patch_example_equals_the_macro_patch_test(tmp_path, cache, name, axis):
    part, result = run_example(name, tmp_path / "out", cache)
    moving = "right" if axis == 0 else "top"
    force = np.array(part["boundaries"][moving]["force"])[:, axis] / 50.0
    plan = result.plan
    test = TensionTest(
        direction=("course", "wale")[axis],
        elements=6,
        max_strain=0.2,
        element_degree=plan.fidelity.element_degree,
    )
    surface = read_surface(plan.scene.surface.path)
    patch = TensionSetup(
        surface_material(surface), test, SolverOptions(steps=plan.scene.macro.steps)
    )
    expected = patch.run().force_n_per_mm
    assert part["cells"] == 36
    np.testing.assert_allclose(force, expected, rtol=1e-8, atol=1e-12)
    assert force[-1] > 0.01


@pytest.mark.slow
def test_strip_tensile_force_is_the_uniaxial_response_of_the_material(tmp_path, cache):
    part, result = run_example("strip_tensile", tmp_path / "out", cache)
    strain = np.array(part["boundaries"]["top"]["displacement"])[:, 1] / 200.0
    force = np.array(part["boundaries"]["top"]["force"])[:, 1] / 50.0
    surface = read_surface(result.plan.scene.surface.path)
    uniaxial = homogeneous_response(surface, strain[-1], "wale", "free")[0]
    strip_biaxial = homogeneous_response(surface, strain[-1], "wale", "fixed")[0]
    assert strain[-1] == pytest.approx(0.2, rel=1e-12)
    assert uniaxial < force[-1] < strip_biaxial
    # a strip four times as long as wide is nearly uniaxial: the clamps, which hold the width
    # of a fabric that narrows, add a small part of the gap to the width held all along
    assert (force[-1] - uniaxial) / (strip_biaxial - uniaxial) < 0.15


def svk(**constants):
    def edit(data):
        region = data.setdefault("region", [{"name": "fabric"}])[0]
        region["svk"] = constants

    return edit


@pytest.mark.slow
def test_bias_extension_central_zone_follows_the_pure_shear_kinematics(tmp_path, cache):
    """Stiff yarns (E1 = E2 = 100 N/mm) and a soft shear (G12 = 0.05 N/mm), 5 mm extension.

    At the fast level (8.3 mm quads) the central cell shears 1.6-2.8 % less than the
    kinematics predict; docs/scenes.md records how this depends on the mesh (bilinear quads
    lock when stiff yarns run diagonally across them)."""

    def edit(data):
        svk(**STIFF_YARNS)(data)
        data["boundary"][1]["displacement"] = [0.0, 5.0]
        data["macro"]["steps"] = 4

    part, _ = run_example("bias_extension", tmp_path / "out", cache, edit)
    extension = np.array(part["boundaries"]["top"]["displacement"])[1:, 1]
    free_length = 100.0 - 50.0
    kinematic = 90.0 - 2 * np.degrees(
        np.arccos((free_length + extension) / (np.sqrt(2.0) * free_length))
    )
    measured = np.array(part["probes"]["centre"]["shear_angle"])[1:]
    np.testing.assert_allclose(measured, kinematic, rtol=0.05)
    assert measured[-1] > 10.0
    check_results_folder(tmp_path / "out", part, STIFF_YARNS, angle=45.0, top=(0.0, 5.0))
    # unchanged, every stage comes from the cache; no surface stage: the SVK part needs none
    again, result = run_example("bias_extension", tmp_path / "again", cache, edit)
    statuses = {record["stage"]: record["status"] for record in result.summary["stages"]}
    assert statuses == {"geometry": "cached", "fabric": "cached"}
    assert again["boundaries"] == part["boundaries"]


STIFF_YARNS = {"course_stiffness": 100.0, "wale_stiffness": 100.0, "poissons_ratio": 0.0}
STIFF_YARNS["shear_stiffness"] = 0.05
FIELDS = (
    "displacement",
    "green_lagrange_strain",
    "cauchy_stress",
    "principal_stress",
    "principal_direction",
    "region",
    "stitch",
    "course_direction",
)


def check_results_folder(folder, part, constants, angle, top):
    """The files of a one-region SVK part whose `top` boundary is moved by `top` (mm):
    curves.json = the summary's curves; a PNG per loaded boundary; the XDMF fields at the last
    step against what they must be: the prescribed displacement on the top edge, the strain
    of the bilinear displacement at each cell centre, the Cauchy stress of the SVK law at
    `angle` (degrees) from that strain, its principal values and direction, region 0, stitch 0
    (no knit), the course direction `angle`."""
    curves = json.loads((folder / "fabric" / "curves.json").read_text())
    assert curves == part["boundaries"]
    for name, curve in curves.items():  # the same curves as CSV, units in the header
        table = np.loadtxt(folder / "fabric" / f"boundary_{name}.csv", delimiter=",", skiprows=1)
        header = (folder / "fabric" / f"boundary_{name}.csv").read_text().splitlines()[0]
        assert header == "load factor (-),Fx (N),Fy (N),ux (mm),uy (mm)"
        np.testing.assert_allclose(table[:, 0], part["load_factor"], rtol=1e-9)
        np.testing.assert_allclose(table[:, 1:3], curve["force"], rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(table[:, 3:], curve["displacement"], rtol=1e-9, atol=1e-15)
    for name, probe in part["probes"].items():
        table = np.loadtxt(folder / "fabric" / f"probe_{name}.csv", delimiter=",", skiprows=1)
        np.testing.assert_allclose(table[:, -1], probe["shear_angle"], rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(table[:, 4], np.array(probe["cauchy"])[:, 0, 0], atol=1e-12)
    for name in ("top", "bottom", "stress"):
        with Image.open(folder / "figures" / f"fabric_{name}.png") as image:
            assert min(image.size) > 100
    # the patch's comparison figure, empty for a part without a uniaxial RVE case, is not made
    assert not (folder / "figures" / "force_strain.png").exists()
    table = (folder / "summary.txt").read_text()
    assert "shear angle" in table and not re.search(r"\s-(\s|$)", table)  # no empty cell
    xdmf = (folder / "paraview" / "fabric.xdmf").read_text()
    assert all(f'Attribute Name="{name}"' in xdmf for name in FIELDS)
    with h5py.File(folder / "paraview" / "fabric.h5", "r") as h5:
        X = h5["Mesh/mesh/geometry"][:]
        quads = h5["Mesh/mesh/topology"][:]
        last = sorted(h5["Function/displacement"], key=lambda t: float(t.replace("_", ".")))[-1]
        field = {name: h5[f"Function/{name}/{last}"][:] for name in FIELDS}
    # XDMF stores vectors with 3 and tensors with 3 x 3 components
    assert last == "1"
    u = field["displacement"][:, :2]
    on_top = np.isclose(X[:, 1], X[:, 1].max())
    np.testing.assert_allclose(u[on_top], np.tile(top, (on_top.sum(), 1)), atol=1e-12)
    # bilinear quads (XDMF vertex order: counter-clockwise) at the centre
    dN = np.array([[-0.5, 0.5, 0.5, -0.5], [-0.5, -0.5, 0.5, 0.5]])
    J = np.einsum("ak,ckb->cba", dN, X[quads])  # dX/dxi per cell
    grad_u = np.einsum("ak,ckb->cba", dN, u[quads]) @ np.linalg.inv(J)
    F = np.eye(2) + grad_u
    E = 0.5 * (np.transpose(F, (0, 2, 1)) @ F - np.eye(2))
    np.testing.assert_allclose(
        field["green_lagrange_strain"].reshape(-1, 3, 3)[:, :2, :2], E, atol=1e-12
    )
    C = OrthotropicSVK(**constants).plane_stress_matrix()
    phi = np.radians(angle)
    R = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
    Em = R.T @ E @ R
    Sm = np.zeros_like(Em)
    Sm[:, 0, 0] = C[0, 0] * Em[:, 0, 0] + C[0, 1] * Em[:, 1, 1]
    Sm[:, 1, 1] = C[1, 0] * Em[:, 0, 0] + C[1, 1] * Em[:, 1, 1]
    Sm[:, 0, 1] = Sm[:, 1, 0] = C[2, 2] * Em[:, 0, 1]
    S = R @ Sm @ R.T
    cauchy = F @ S @ np.transpose(F, (0, 2, 1)) / np.linalg.det(F)[:, None, None]
    written = field["cauchy_stress"].reshape(-1, 3, 3)[:, :2, :2]
    np.testing.assert_allclose(written, cauchy, atol=1e-9 * np.abs(cauchy).max())
    largest, smallest = field["principal_stress"][:, 0], field["principal_stress"][:, 1]
    direction = field["principal_direction"][:, :2]
    np.testing.assert_allclose(largest + smallest, np.trace(written, axis1=1, axis2=2), atol=1e-12)
    np.testing.assert_allclose(largest * smallest, np.linalg.det(written), atol=1e-12)
    np.testing.assert_allclose(
        np.einsum("cij,cj->ci", written, direction), largest[:, None] * direction, atol=1e-12
    )
    np.testing.assert_array_equal(field["region"].ravel(), 0.0)
    np.testing.assert_array_equal(field["stitch"].ravel(), 0.0)
    np.testing.assert_allclose(field["course_direction"].ravel(), angle, rtol=1e-15)


@pytest.mark.slow
def test_cruciform_arms_carry_equal_forces_in_equilibrium(tmp_path, cache):
    edit = svk(course_stiffness=1.0, wale_stiffness=1.0, poissons_ratio=0.3, shear_stiffness=0.3)
    part, _ = run_example("cruciform_biaxial", tmp_path / "out", cache, edit)
    forces = {name: np.array(part["boundaries"][name]["force"][-1]) for name in part["boundaries"]}
    assert forces["right"][0] == pytest.approx(forces["top"][1], rel=1e-9)
    total = sum(forces[name] for name in ("left", "right", "bottom", "top"))
    np.testing.assert_allclose(total, 0.0, atol=1e-9 * forces["right"][0])
    assert forces["right"][0] > 0.5


@pytest.mark.slow
def test_plate_with_hole_far_field_stress_is_the_nominal_stress(tmp_path, cache):
    def edit(data):
        # isotropic, no Poisson contraction: the clamps do not disturb the far field
        svk(course_stiffness=1.0, wale_stiffness=1.0, poissons_ratio=0.0, shear_stiffness=0.5)(data)
        data["boundary"][1]["displacement"] = [0.0, 0.1]  # 0.1 %: small strain
        data["fabric"]["shape"]["element_size"] = 2.5
        # a longer plate: the hole's stress shadow (~ radius^2 / distance^2) fades
        data["fabric"]["shape"]["height"] = 200.0
        data["probe"] = [
            {"name": "beside_hole", "x": 30.5, "y": 100.0},
            {"name": "far_field", "x": 25.0, "y": 160.0},
        ]

    part, _ = run_example("plate_with_hole", tmp_path / "out", cache, edit)
    nominal = part["boundaries"]["top"]["force"][-1][1] / 50.0
    far = part["probes"]["far_field"]["cauchy"][-1][1][1]
    beside = part["probes"]["beside_hole"]["cauchy"][-1][1][1]
    assert far == pytest.approx(nominal, rel=0.02)
    heywood = 2.0 + (1.0 - 10.0 / 50.0) ** 3  # net-section factor, hole diameter / width
    assert 1.5 * nominal < beside < heywood / (1.0 - 10.0 / 50.0) * nominal


@pytest.mark.slow
def test_graded_strip_with_a_constant_stitch_equals_the_plain_knit(tmp_path, cache):
    def constant(data):
        data["region"][0]["stitch"] = "5.5 + 0 * x"

    def plain(data):
        del data["region"]

    graded, result = run_example("graded_strip", tmp_path / "graded", cache, constant)
    uniform, _ = run_example("graded_strip", tmp_path / "plain", cache, plain)
    assert result.plan.scene.part.regions[0].members == (5.5,)
    for name in ("top", "bottom"):
        np.testing.assert_allclose(
            graded["boundaries"][name]["force"],
            uniform["boundaries"][name]["force"],
            rtol=1e-12,
            atol=1e-12,
        )
    assert graded["boundaries"]["top"]["force"][-1][1] > 0.1


@pytest.mark.mpi
@pytest.mark.slow
def test_a_multi_region_part_gives_the_same_answer_under_mpirun(tmp_path):
    """The plate with a hole, its knit (the shipped surface) with a band of SVK material whose
    course direction varies with y, through `knitmech run` on one rank and under `mpirun -n
    2` ([macro] ranks; the fabric stage's cache key does not hold the ranks, so each run has
    a cache of its own)."""

    def edit(ranks):
        def change(data):
            data["macro"] = {"ranks": ranks, "steps": 3}
            data["boundary"][1]["displacement"] = [2.0, 5.0]
            data["region"] = [
                {"name": "fabric", "angle": 90.0},
                {
                    "name": "band",
                    "where": "abs(y - 50) < 12",
                    "angle": "30 + 0.2 * y",
                    "svk": {"course_stiffness": 0.5, "wale_stiffness": 1.0, "poissons_ratio": 0.2},
                },
            ]

        return change

    parts = [
        run_example(
            "plate_with_hole", tmp_path / f"out{ranks}", tmp_path / f"c{ranks}", edit(ranks)
        )
        for ranks in (1, 2)
    ]
    (serial, _), (parallel, _) = parts
    assert (serial["ranks"], parallel["ranks"]) == (1, 2)
    assert serial["dofs"] == parallel["dofs"]
    for name, curve in serial["boundaries"].items():
        for key in ("force", "displacement"):
            np.testing.assert_allclose(
                parallel["boundaries"][name][key], curve[key], rtol=1e-8, atol=1e-11
            )
    for name, probe in serial["probes"].items():
        np.testing.assert_allclose(parallel["probes"][name]["cauchy"], probe["cauchy"], atol=1e-10)
    assert serial["boundaries"]["top"]["force"][-1][1] > 0.1


@pytest.mark.slow
def test_the_slack_l_bracket_reaches_its_load_in_equilibrium(tmp_path, cache):
    """A force on a part at rest (issue 31): with increments cut no lower than 1/1024 of the
    load it stopped at 0 steps whatever the number of steps. Now every step converges; the
    held edge's reaction balances the tip's load in every step, and 10 or 40 steps end in
    the same state (the path of a hyperelastic-like law does not depend on its steps)."""
    part, _ = run_example("l_bracket", tmp_path / "ten", cache)
    load = np.array([0.035355, -0.035355]) * 40.0  # N: traction times the tip's length
    factors = np.array(part["load_factor"])
    assert factors[-1] == 1.0
    reaction = np.array(part["boundaries"]["top"]["force"])
    np.testing.assert_allclose(reaction, -factors[:, None] * load, rtol=1e-8, atol=1e-10)
    tip = np.array(part["boundaries"]["tip"]["displacement"])[-1]

    def forty_steps(data):
        data["macro"]["steps"] = 40

    finer, _ = run_example("l_bracket", tmp_path / "forty", cache, forty_steps)
    np.testing.assert_allclose(finer["boundaries"]["tip"]["displacement"][-1], tip, rtol=1e-6)
    # the results folder holds the gmsh file and a scene naming it: it runs again on its own
    assert (tmp_path / "ten" / "mesh" / "l_bracket.geo").read_text() == (
        EXAMPLES / "l_bracket.geo"
    ).read_text()
    assert 'file = "mesh/l_bracket.geo"' in (tmp_path / "ten" / "scene.toml").read_text()
    scene = load_scene(tmp_path / "ten" / "scene.toml")
    again = run_scene(scene, output=tmp_path / "again", cache_dir=cache).summary["part"]
    np.testing.assert_allclose(again["boundaries"]["tip"]["displacement"][-1], tip, rtol=1e-9)
    print(f"tip displacement {tip} mm, {len(factors) - 1} steps, {part['cutbacks']} cutbacks")
