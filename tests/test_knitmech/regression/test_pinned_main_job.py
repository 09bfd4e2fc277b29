"""Regression pins of the main job (tests/pins.py, MAIN_JOB_FAST): `knitmech run --fidelity
fast` on the built-in default scene, from empty caches in a temporary folder (about 12 s with 2
jobs): the patch forces at 10 and 20 % and its Poisson ratios at 20 %, both directions, and the
fast surface's fit residuals. Its meso stage is the RVE of RVE_FAST and must give those pins."""

import pytest
from pins import assert_pinned

from knitmech.pipeline import run_scene
from knitmech.scene import load_scene
from knitmech.stages.cache import COMPUTED


@pytest.fixture(scope="module")
def summary(tmp_path_factory):
    root = tmp_path_factory.mktemp("main_job_fast")
    result = run_scene(
        load_scene(), fidelity="fast", output=root / "results", cache_dir=root / "cache", jobs=2
    )
    return result.summary


def value_at(strains, values, strain):
    """The value at the output state of `strain` (one of the states)."""
    (index,) = [i for i, s in enumerate(strains) if abs(s - strain) < 1e-12]
    return values[index]


@pytest.mark.slow
def test_main_job_patch_forces_poisson_ratios_and_fit_residuals_are_pinned(summary):
    assert summary["fidelity"]["name"] == "fast"
    # computed now, nothing taken from a cache (a stale one would pin old results)
    assert {stage["status"] for stage in summary["stages"]} == {COMPUTED}
    assert summary["surface"]["runs_cached"] == 0 < summary["surface"]["runs_computed"]
    forces, ratios = summary["forces"], summary["poisson_ratios"]
    measured = {}
    for direction, name in (("course", "nu12"), ("wale", "nu21")):
        table = forces[direction]
        for strain in (0.1, 0.2):
            measured[f"patch {direction} force {100 * strain:.0f} %"] = value_at(
                table["strain"], table["macro_gf_per_cm"], strain
            )
        measured[f"patch {name} 20 %"] = value_at(
            ratios[name]["strain"], ratios[name]["macro"], 0.2
        )
    for group, stats in summary["surface"]["residuals"].items():
        measured[f"surface {group} max abs"] = stats["max_abs"]
    assert_pinned("MAIN_JOB_FAST", measured)


@pytest.mark.slow
def test_main_job_meso_stage_gives_the_pinned_rve_numbers(summary):
    measured = {}
    for direction, name in (("course", "nu12"), ("wale", "nu21")):
        run = summary["meso"][f"uniaxial-{direction}"]
        for strain in (0.1, 0.2):
            measured[f"{direction} force {100 * strain:.0f} %"] = value_at(
                run["strain"], run["force_gf_per_cm"], strain
            )
        measured[f"{name} 20 %"] = run["poisson_ratio"]
    assert_pinned("RVE_FAST", measured)
