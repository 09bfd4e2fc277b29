"""Stitch patterns in scenes: [fabric] pattern or chart, regions of other patterns, their
problems one line each, and the stage cache keyed by the pattern."""

import pytest

from knitmech.fidelity import LEVELS
from knitmech.scene import SceneError, scene_from_dict
from knitmech.stages import geometry_stage, meso_stages, plan_run
from knitmech.stages.fabric import knit_surfaces

MEASURED = {"preset": "cotton-20s2", "stitch": 5.5, "wale_width": 1.33, "course_height": 1.26}


def plan(fabric: dict, **tables):
    return plan_run(scene_from_dict({"fabric": fabric, **tables}), LEVELS["fast"])


def problems(fabric: dict, **tables) -> list[str]:
    with pytest.raises(SceneError) as error:
        scene_from_dict({"fabric": fabric, **tables})
    return error.value.problems


def test_a_pattern_by_name_or_by_chart():
    rib = plan({**MEASURED, "pattern": "rib1x1"}).fabric
    assert rib.knit.pattern == ("KP",)
    assert (rib.knit.wale_width, rib.knit.course_height) == (1.33, 1.26)  # measured, kept
    seed = plan({**MEASURED, "pattern": "KP,PK"}).fabric
    assert seed.knit.pattern == ("KP", "PK")
    garter = plan({**MEASURED, "chart": ["K", "P"]}).fabric
    assert garter.knit.pattern == ("K", "P")
    assert plan({"preset": "cotton-20s2", "stitch": 5.5}).fabric.knit.pattern == ("K",)


@pytest.mark.parametrize(
    ("fabric", "message"),
    [
        ({"pattern": "rib1x1", "chart": ["KP"]}, "fabric: give pattern or chart, not both"),
        ({"pattern": "ribb"}, "fabric.pattern: pattern='ribb' is unknown"),
        ({"chart": ["KX"]}, "fabric.chart: chart row 1 ('KX') has the unknown stitch code 'X'"),
        ({"chart": ["KP", "K"]}, "fabric.chart: chart rows have unequal lengths"),
        ({"chart": ["KT", "KK"]}, "fabric.chart: chart row 1 ('KT') has a tuck ('T')"),
        ({"relaxed": True}, "fabric.relaxed: finds wale_width and course_height"),
        ({"relaxed": "yes"}, "fabric.relaxed: expected bool, got"),
    ],
)
def test_bad_patterns_are_one_problem_each(fabric, message):
    found = problems({**MEASURED, **fabric})
    assert len(found) == 1
    assert found[0].startswith(message)


def test_the_stage_cache_is_keyed_by_the_pattern():
    jersey, rib = plan(MEASURED), plan({**MEASURED, "pattern": "rib1x1"})
    assert geometry_stage(jersey).inputs != geometry_stage(rib).inputs
    assert geometry_stage(rib).inputs["pattern"] == ("KP",)
    assert meso_stages(jersey)[0].inputs != meso_stages(rib)[0].inputs


def test_a_region_of_another_pattern_gets_its_own_surface():
    shape = {"shape": {"kind": "rectangle", "width": 20.0, "height": 40.0}}
    data = {
        "fabric": {"preset": "cotton-20s2", "stitch": 5.5, **shape},
        "region": [
            {"name": "body", "where": "y >= 10"},
            {"name": "cuff", "where": "y < 10", "pattern": "rib1x1", "wale_width": 1.33},
        ],
        "boundary": [
            {"name": "left", "kind": "clamp"},
            {"name": "right", "kind": "displacement", "displacement": [2.0, 0.0]},
        ],
    }
    run = plan_run(scene_from_dict(data), LEVELS["fast"])
    knits = knit_surfaces(run)
    assert knits.scene_knit
    assert knits.region_knits[0] == ""
    (label,) = knits.others
    assert knits.region_knits[1] == label
    cuff = knits.others[label]
    assert cuff.knit.pattern == ("KP",)
    assert cuff.knit.wale_width == 1.33  # given; the course height is the preset's
    assert cuff.knit.course_height == run.fabric.knit.course_height
