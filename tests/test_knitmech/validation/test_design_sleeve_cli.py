"""`knitmech design` on a sleeve, end to end: the family given as surface files (the synthetic
family, tests/support/design_cases.py), the Laplace design, the contact model beside it (coarse
quads), the results folder; a rerun takes the contact model from the stage cache."""

import json
from pathlib import Path

import pytest
from support.design_cases import synthetic_family

from knitmech.cli import main

LEG = Path(__file__).resolve().parents[3] / "examples" / "design" / "leg.csv"


@pytest.mark.slow
def test_a_sleeve_design_writes_its_instructions_and_the_contact_model_beside(tmp_path, capsys):
    family = synthetic_family((5.5, 6.0), tmp_path, wale_factor=4.0)
    members = "".join(
        f"[[design.member]]\nstitch = {m.stitch}\nsurface = {m.path!r}\n"
        f"wale_width = {m.wale_width}\ncourse_height = {m.course_height}\n"
        for m in family.members
    )
    path = tmp_path / "sleeve.toml"
    path.write_text(
        'fidelity = "fast"\n[fabric]\npreset = "cotton-20s2"\nstitch = 5.5\n'
        f'[sleeve]\nlimb = "{LEG}"\nbands = 4\nelement_size = 10.0\n'
        f"[design]\n{members}"
        '[[design.target]]\nkind = "pressure"\nprofile = [[0.0, 9.0], [400.0, 7.0]]\n'
    )
    arguments = [
        "design",
        str(path),
        "-o",
        str(tmp_path / "out"),
        "--cache-dir",
        str(tmp_path / "c"),
    ]
    assert main([*arguments, "-q"]) == 0
    summary = json.loads((tmp_path / "out" / "design.json").read_text())
    assert summary["met"]
    assert [row["band"] for row in summary["instructions"]] == [1, 2, 3, 4]
    for row, target in zip(summary["instructions"], summary["targets"], strict=True):
        assert isinstance(row["needles"], int) and isinstance(row["courses"], int)
        assert row["pressure_kPa"] == pytest.approx(row["pressure_mmHg"] * 0.133322387415)
        assert abs(target["achieved"] / target["target"] - 1) <= 0.05
        assert target["contact"] > 0
    assert len(summary["contact"]["bands"]) == 4
    assert (tmp_path / "out" / "figures" / "design.png").is_file()
    assert (tmp_path / "out" / "sleeve" / "bands.json").is_file()
    printed = capsys.readouterr().out
    assert "contact model:" in printed and "every target met" in printed
    assert main([*arguments]) == 0
    assert "sleeve contact: cached" in capsys.readouterr().err
