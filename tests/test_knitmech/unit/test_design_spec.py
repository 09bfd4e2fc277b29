"""Bad design files are refused before anything runs: every problem at once, one line each
naming its key (issue 30: no variables, a target on an unknown boundary, bounds outside the
family, ...), and `knitmech design` exits with status 2 writing nothing."""

import copy
from pathlib import Path

import pytest

from knitmech.cli import main
from knitmech.design.spec import design_from_dict, load_design
from knitmech.scene import SceneError
from rve_rod.units import MMHG

PART = {
    "fidelity": "fast",
    "fabric": {
        "preset": "cotton-20s2",
        "stitch": 5.5,
        "shape": {"kind": "rectangle", "width": 50.0, "height": 100.0},
    },
    "region": [{"name": "fabric", "angle": 90.0}],
    "boundary": [
        {"name": "bottom", "kind": "clamp"},
        {"name": "top", "kind": "displacement", "displacement": [0.0, 10.0]},
    ],
    "probe": [{"name": "centre", "x": 25.0, "y": 50.0}],
    "design": {
        "variable": [{"region": "fabric", "bounds": [5.0, 6.0]}],
        "target": [
            {"kind": "force", "boundary": "top", "value": 0.2},
            {"kind": "probe", "probe": "centre", "quantity": "strain_yy", "value": 0.1},
        ],
    },
}

SLEEVE = {
    "fabric": {"preset": "cotton-20s2", "stitch": 5.5},
    "sleeve": {"limb": [[0.0, 35.0], [200.0, 50.0]], "bands": 4},
    "design": {"target": [{"kind": "pressure", "profile": [[0.0, 4.0], [200.0, 3.0]]}]},
}


def problems(data):
    with pytest.raises(SceneError) as error:
        design_from_dict(data)
    return error.value.problems


def edited(base, change):
    data = copy.deepcopy(base)
    change(data)
    return data


def test_a_valid_part_design_reads():
    scene, design = design_from_dict(PART)
    assert design.kind == "part"
    assert design.variables[0].bounds == (5.0, 6.0)
    assert [t.kind for t in design.targets] == ["force", "probe"]
    assert scene.part.regions[0].name == "fabric"


def test_a_valid_sleeve_design_reads_with_pressures_in_n_per_mm2():
    _, design = design_from_dict(SLEEVE)
    assert design.kind == "sleeve"
    assert design.bounds == (4.5, 7.0)  # the family's range
    assert design.sleeve.needles is None  # designed
    assert design.targets[0].profile[0] == (0.0, pytest.approx(4.0 * MMHG))


def test_no_variables_is_refused():
    found = problems(edited(PART, lambda d: d["design"].pop("variable")))
    assert found == [
        "design.variable: no variables to design; add [[design.variable]] with the region "
        "whose stitch value is designed"
    ]


def test_every_problem_of_a_part_design_at_once():
    def change(data):
        data["design"]["variable"][0]["bounds"] = [4.0, 6.0]
        data["design"]["variable"].append({"region": "sleeve"})
        data["design"]["target"][0]["boundary"] = "left"
        data["design"]["target"][1]["quantity"] = "strain_zz"
        data["design"]["target"].append({"kind": "pressure", "profile": [[0, 1]]})
        data["design"]["tolerance"] = -1.0

    found = problems(edited(PART, change))
    keys = sorted(problem.split(":")[0] for problem in found)
    assert keys == [
        "design.target[0].boundary",
        "design.target[1].quantity",
        "design.target[2].kind",
        "design.tolerance",
        "design.variable[0].bounds",
        "design.variable[1].region",
    ]
    text = "\n".join(found)
    assert "[4.0, 6.0] mm leaves the family's range [4.5, 7] mm" in text
    assert "no boundary condition on 'left'; its boundaries: bottom, top" in text
    assert "a pressure target belongs to a sleeve design; this is a part design" in text


@pytest.mark.parametrize(
    ("change", "key", "words"),
    [
        (lambda d: d["design"].pop("target"), "design.target", "no targets"),
        (lambda d: d["fabric"].update(preset="vassiliadis-sample2"), "fabric.preset", "several"),
        (lambda d: d["sleeve"].update(limb=[[0.0, 35.0]]), "sleeve.limb", ">= 2 points"),
        (lambda d: d["sleeve"].update(needles=[100, 120]), "sleeve.needles", "2 counts for 4"),
        (lambda d: d["design"].update(bounds=[5.0, 7.5]), "design.bounds", "leaves the family"),
        (lambda d: d["design"]["target"][0].update(unit="psi"), "design.target[0].unit", "psi"),
        (lambda d: d.pop("design"), "design", "needs a [design] table"),
    ],
)
def test_bad_sleeve_input_names_its_key(change, key, words):
    found = problems(edited(SLEEVE, change))
    assert any(p.startswith(f"{key}:") and words in p for p in found), found


def test_knitmech_design_exits_2_and_writes_nothing(tmp_path, capsys):
    path = tmp_path / "design.toml"
    path.write_text('[fabric]\npreset = "cotton-20s2"\nstitch = 5.5\n[design]\n')
    status = main(
        ["design", str(path), "-o", str(tmp_path / "out"), "--cache-dir", str(tmp_path / "c")]
    )
    assert status == 2
    assert "design.target: no targets" in capsys.readouterr().err
    assert not (tmp_path / "out").exists() and not (tmp_path / "c").exists()


EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "design"


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.stem)
def test_every_example_design_reads(path):
    _, design = load_design(path)
    assert design.targets
    assert design.kind in ("material", "part", "sleeve")
