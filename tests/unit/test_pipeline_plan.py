"""A scene and a fidelity level resolve into the settings of every stage."""

from knitmech.fidelity import LEVELS
from knitmech.scene import load_scene, scene_from_dict
from knitmech.stages import plan_run


def test_settings_come_from_the_scene_and_the_level():
    level = LEVELS["fast"]
    plan = plan_run(load_scene(), level)
    assert plan.rve.cell.control_points == level.control_points
    assert plan.rve.yarn.friction  # cotton has mu = 0.15
    assert (plan.sampling.rays, plan.sampling.steps_per_ray) == (level.rays, level.steps_per_ray)
    assert plan.sampling.shear_steps == level.shear_steps
    assert (plan.sampling.max_tension, plan.sampling.max_compression) == (0.25, 0.10)
    assert (plan.fit.spans, plan.fit.shear_spans) == (level.spans, level.shear_spans)
    assert plan.scene.fidelity == "fast" and plan.scene.macro.elements == level.elements


def test_a_frictionless_yarn_skips_the_friction_path():
    scene = scene_from_dict(
        {"fabric": {"preset": "cotton-20s2", "stitch": 5.5, "friction": 0.0}, "meso": {"steps": 5}}
    )
    plan = plan_run(scene, LEVELS["balanced"])
    assert not plan.rve.yarn.friction
    assert plan.scene.meso.steps == 5
