"""`rve-rod surface` reproduces the surface of a fidelity level (issue 19): given the level's
settings as options it runs the same RVE runs (every one is taken from the cache `knitmech run`
filled: the same cache keys) and writes the same surface file (coefficients and parameters).

The level is `fast` on the default scene's fabric and sampled domain, with no meso case and no
patch (only the surface stage runs).
"""

import numpy as np

import rve_rod.cli
from knitmech.fidelity import fidelity_level
from knitmech.pipeline import run_scene
from knitmech.scene import scene_from_dict
from knitmech.stages import plan_run
from rve_rod.surface import read_surface

SCENE = {
    "name": "surface only",
    "fidelity": "fast",
    "fabric": {"preset": "cotton-20s2", "stitch": 5.5},
    "meso": {"cases": []},
    "surface": {"max_strain": 0.25},
    "macro": {"directions": []},
}


def test_rve_rod_surface_at_a_levels_settings_writes_the_levels_surface(tmp_path, capsys):
    scene = scene_from_dict(SCENE)
    run_scene(scene, output=tmp_path / "results", cache_dir=tmp_path / "cache", jobs=2)
    plan = plan_run(scene, fidelity_level("fast"))
    sampling = plan.sampling
    arguments = (
        f"surface --preset cotton-20s2 --stitch 5.5 -o {tmp_path / 'cli.h5'} "
        f"--rays {sampling.rays} --steps {sampling.steps_per_ray} "
        f"--shear-steps {sampling.shear_steps} --max-strain {sampling.max_tension} "
        f"--control-points {plan.rve.cell.control_points} "
        f"--spans {plan.fit.spans} --shear-spans {plan.fit.shear_spans} "
        f"--cache-dir {tmp_path / 'cache' / 'rve-runs'} --jobs 2"
    )
    capsys.readouterr()
    assert rve_rod.cli.main(arguments.split()) == 0
    runs = sampling.rays + 1
    assert f"{runs} RVE runs (0 computed, {runs} cached)" in capsys.readouterr().out

    level, cli = (
        read_surface(tmp_path / "results" / "surface.h5"),
        read_surface(tmp_path / "cli.h5"),
    )
    assert cli.parameters == level.parameters
    for name in ("s11", "s22", "s12"):
        np.testing.assert_array_equal(
            getattr(cli, name).coefficients, getattr(level, name).coefficients
        )
