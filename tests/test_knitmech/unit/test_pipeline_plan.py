"""A scene and a fidelity level resolve into the settings of every stage."""

from knitmech.fidelity import LEVELS
from knitmech.jobs.launch import mpirun_environment
from knitmech.scene import load_scene, scene_from_dict
from knitmech.stages import plan_run


def test_settings_come_from_the_scene_and_the_level():
    level = LEVELS["fast"]
    plan = plan_run(load_scene(), level)
    assert plan.rve.cell.control_points == level.control_points
    assert plan.rve.yarn.friction  # cotton has mu = 0.15
    assert (plan.sampling.rays, plan.sampling.steps_per_ray) == (level.rays, level.steps_per_ray)
    assert plan.sampling.shear_steps == level.shear_steps
    # the compression box follows the fabric (resolved when the surface stage runs)
    assert (plan.sampling.max_tension, plan.sampling.max_compression) == (0.25, None)
    assert (plan.fit.spans, plan.fit.shear_spans) == (level.spans, level.shear_spans)
    assert plan.scene.fidelity == "fast" and plan.scene.macro.elements == level.elements


def test_a_frictionless_yarn_skips_the_friction_path():
    scene = scene_from_dict(
        {"fabric": {"preset": "cotton-20s2", "stitch": 5.5, "friction": 0.0}, "meso": {"steps": 5}}
    )
    plan = plan_run(scene, LEVELS["balanced"])
    assert not plan.rve.yarn.friction
    assert plan.scene.meso.steps == 5


def test_a_stage_mpirun_leaves_the_variables_of_an_enclosing_mpi_job_behind(monkeypatch):
    """A process that initialized MPI (a singleton: a Python session that imported DOLFINx)
    hands PMIX_*/ORTE_*/OMPI_MCA_ess... to its children; an mpirun started with them fails
    without a message (tests/test_knitmech/validation/test_fault_sigterm.py after an in-process
    part)."""
    inherited = {
        "PMIX_RANK": "0",
        "PMIX_SERVER_URI4": "1.0;tcp4://127.0.0.1:1",
        "ORTE_SCHIZO_DETECTION": "ORTE",
        "OMPI_MCA_ess": "singleton",
        "OMPI_MCA_orte_launch": "1",
        "OMPI_MCA_pmix": "^s1",
        "OMPI_APP_CTX_NUM_PROCS": "1",
    }
    for name, value in {**inherited, "OMPI_MCA_btl": "self,vader", "HOME": "/root"}.items():
        monkeypatch.setenv(name, value)
    environment = mpirun_environment()
    assert not set(inherited) & set(environment)
    assert environment["OMPI_MCA_btl"] == "self,vader" and environment["HOME"] == "/root"
    assert environment["OMPI_ALLOW_RUN_AS_ROOT"] == "1"
