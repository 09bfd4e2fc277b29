"""The paper's yarn model: adjusted radius, stiffness scalings and contact laws from the presets."""

import dataclasses
import math

import pytest

from rve_rod.errors import InputError
from rve_rod.presets import Fabric, Knit, Yarn, load_preset, stitch_values
from rve_rod.rve.yarn import (
    YarnSettings,
    bending_model,
    yarn_model,
)


@pytest.mark.parametrize("stitch", stitch_values("cotton-20s2"))
def test_cotton_fabrics_are_squeezed_to_a_wale_width_over_eight(stitch):
    fabric = load_preset("cotton-20s2", stitch)
    model = yarn_model(fabric, YarnSettings(bending="section"))
    r0, E0 = 0.19, 80.0
    r = fabric.knit.wale_width / 8
    ratio = r0 / r
    assert model.radius == pytest.approx(r) and model.adjusted
    # A with E_A = E0 scaled by (r0/r)^4, C with E_C = E0/2 scaled by (r0/r)^6, I = pi r^4/4
    assert model.section.axial == pytest.approx(E0 * math.pi * r**2 * ratio**4)
    assert model.section.bending_1 == pytest.approx(0.5 * E0 * math.pi * r**4 / 4 * ratio**6)
    assert model.section.torsion == pytest.approx(0.5 * E0 / 2.6 * math.pi * r**4 / 2 * ratio**6)
    assert model.law.stiffness == pytest.approx(0.01 * E0 * ratio**8)
    assert model.law.exponent == pytest.approx(3 - ratio**3)
    assert model.friction.coefficient == 0.15


def test_loose_knit_keeps_the_measured_radius_and_the_papers_inertia_option():
    fabric = load_preset("vassiliadis-sample2")  # w/8 = 0.104 > r0 = 0.0923
    model = yarn_model(
        fabric, YarnSettings(second_moment="paper", friction=False, bending="section")
    )
    r = 0.0923
    assert model.radius == r and not model.adjusted
    assert model.section.bending_1 == pytest.approx(0.5 * 800 * math.pi * r**4 / 12)
    assert model.law.exponent == 2.0
    assert model.friction is None


def test_frictionless_yarn_has_no_friction_law():
    fabric = Fabric(Yarn(0.19, 80.0, friction_coefficient=0.0), Knit(1.33, 1.26))
    assert yarn_model(fabric).friction is None


def test_exponent_limit_is_a_clear_error():
    # r = w/8 = 0.14 mm, r0/r = 1.357: p = 3 - 2.5 = 0.5 < 1
    fabric = Fabric(Yarn(0.19, 80.0), Knit(1.12, 1.0))
    with pytest.raises(InputError, match=r"contact exponent p=3-\(r0/r\)\^3=0\.5"):
        yarn_model(fabric)


def test_bad_settings_are_refused():
    with pytest.raises(InputError, match="second_moment='hollow'"):
        YarnSettings(second_moment="hollow")
    with pytest.raises(InputError, match="rotational_modulus_factor=-1"):
        YarnSettings(rotational_modulus_factor=-1)
    with pytest.raises(InputError, match=r"prestrain=-0\.01"):
        YarnSettings(prestrain=-0.01)
    with pytest.raises(InputError, match=r"prestrain=0\.3"):
        YarnSettings(prestrain=0.3)
    with pytest.raises(InputError, match="natural_length='spun' is unknown"):
        YarnSettings(natural_length="spun")
    with pytest.raises(InputError, match=r"natural_curvature=1\.5"):
        YarnSettings(natural_curvature=1.5)
    with pytest.raises(InputError, match=r"contact_exponent_shift=-1\.5"):
        YarnSettings(contact_exponent_shift=-1.5)


def test_the_contact_exponent_shift_moves_p_and_stops_at_one():
    """p = 3 - (r0/r)^3 + dp, floored at 1 (stitch 4.5: p = 1.24 - 0.25 < 1), shifted where it
    stays above (6.5: 1.75 - 0.25); the law's stiffness k is not touched."""
    for stitch, expected in ((4.5, 1.0), (6.5, 3.0 - (0.19 / (1.41 / 8)) ** 3 - 0.25)):
        fabric = load_preset("cotton-20s2", stitch)
        paper = yarn_model(fabric).law
        shifted = yarn_model(fabric, YarnSettings(contact_exponent_shift=-0.25)).law
        assert paper.exponent == pytest.approx(3.0 - (0.19 / (fabric.knit.wale_width / 8)) ** 3)
        assert shifted.exponent == pytest.approx(expected, rel=1e-12)
        assert shifted.stiffness == paper.stiffness


def test_free_fibre_bending_sums_the_cotton_fibres_with_the_pre_tension_scaling():
    fabric = load_preset("cotton-20s2", 5.5)
    section = yarn_model(fabric, YarnSettings(bending="section")).section
    free = yarn_model(fabric, YarnSettings(bending="free-fibres")).section
    assert yarn_model(fabric).section == free  # the default where the fibres are known
    ratio = 0.19 / (fabric.knit.wale_width / 8)
    # 59.1 tex of 0.17 tex fibres, 0.53 and 0.16 mN mm^2/tex^2 (Morton & Hearle), times (r0/r)^2
    assert free.bending_1 == pytest.approx(0.53e-3 * 0.17 * 59.1 * ratio**2, rel=1e-12)
    assert free.bending_2 == free.bending_1
    assert free.torsion == pytest.approx(0.16e-3 * 0.17 * 59.1 * ratio**2, rel=1e-12)
    # the translational stiffness and the contact law are the paper's, unchanged
    assert free.axial == section.axial and free.shear_1 == section.shear_1
    # a staple yarn bends at about an eighth of the solid section's rigidity
    assert free.bending_1 / section.bending_1 == pytest.approx(0.130, abs=1e-3)


def test_free_fibre_bending_needs_fibre_data_and_no_second_moment():
    with pytest.raises(InputError, match="needs the yarn's fibres"):
        yarn_model(load_preset("vassiliadis-sample2"), YarnSettings(bending="free-fibres"))
    for bending in ("free-fibres", "auto"):
        with pytest.raises(InputError, match="applies to bending='section' only"):
            YarnSettings(bending=bending, second_moment="paper")
    with pytest.raises(InputError, match="bending='rope' is unknown"):
        YarnSettings(bending="rope")


def test_the_torsion_apart_from_the_bending_swaps_only_the_twisting_rigidity():
    """torsion="bending" is the bending model's section to the bit; the other model's torsion
    replaces G_C J (or the fibres') and leaves A and the bending untouched; fibre torsion needs
    fibre data, and the setting is named when it is missing or unknown."""
    fabric = load_preset("cotton-20s2", 5.5)
    for bending in ("section", "free-fibres"):
        own = yarn_model(fabric, YarnSettings(bending=bending)).section
        assert yarn_model(fabric, YarnSettings(bending=bending, torsion=bending)).section == own
        assert yarn_model(fabric, YarnSettings(bending=bending, torsion="bending")).section == own
    solid = yarn_model(fabric, YarnSettings(bending="section")).section
    free = yarn_model(fabric, YarnSettings(bending="free-fibres")).section
    mixed = yarn_model(fabric, YarnSettings(bending="section", torsion="free-fibres")).section
    assert mixed == dataclasses.replace(solid, torsion=free.torsion)
    assert free.torsion < solid.torsion / 10
    with pytest.raises(InputError, match="torsion='free-fibres' needs the yarn's fibres"):
        yarn_model(load_preset("vassiliadis-sample2"), YarnSettings(torsion="free-fibres"))
    with pytest.raises(InputError, match="torsion='rope' is unknown"):
        YarnSettings(torsion="rope")


def test_a_yarn_without_fibre_data_falls_back_to_its_section_and_says_so(caplog):
    fabric = load_preset("vassiliadis-sample2")
    assert yarn_model(fabric).section == yarn_model(fabric, YarnSettings(bending="section")).section
    assert bending_model(fabric, "auto") == "section" and not caplog.records
    assert bending_model(fabric, "auto", report=True) == "section"
    assert "has no fibre data" in caplog.records[0].getMessage()
    assert bending_model(load_preset("cotton-20s2", 5.5), "auto", report=True) == "free-fibres"
    assert len(caplog.records) == 1
