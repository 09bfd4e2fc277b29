"""The example scenes of examples/ run through `knitmech run` at the fast level, each asserting
one physical number against an expectation computed another way.

* patch (course, wale): the part's clamp force equals the [macro] patch test of
  `fabric_dolfinx.tension` on the same mesh and steps (separate code: its own boundary
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
"""

import tomllib
from pathlib import Path

import numpy as np
import pytest

from fabric_dolfinx.material import surface_material
from fabric_dolfinx.solve import SolverOptions
from fabric_dolfinx.tension import TensionSetup
from fabric_dolfinx.tension_spec import TensionTest
from knitmech.pipeline import run_scene
from knitmech.scene import load_scene, scene_from_dict
from rve_rod.surface import homogeneous_response, read_surface

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SCENES = sorted(EXAMPLES.glob("*.toml"))
"""The example scenes (examples/sweeps/ holds sweep files: tests/unit/test_sweep.py)."""


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
    assert force[-1] == pytest.approx(uniaxial, rel=0.02)


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
        svk(course_stiffness=100.0, wale_stiffness=100.0, poissons_ratio=0.0, shear_stiffness=0.05)(
            data
        )
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
