"""The material-level inverse: the stitch value whose uniaxial curves fit targets.

The targets are made from the synthetic family itself (tests/support/design_cases.py): a
member's own curves must return the member, the law's curves between two members the stitch
value they were made at, and the mean of two members' curves a value between them.
"""

import numpy as np
import pytest
from support.design_cases import curve_at, synthetic_family

from knitmech.design.material import UniaxialTarget, fit_stitch, read_curve
from rve_rod.errors import InputError
from rve_rod.units import GRAM_FORCE


@pytest.fixture(scope="module")
def family():
    return synthetic_family()


def targets_at(family, stitch):
    return [UniaxialTarget(d, *curve_at(family, stitch, d)) for d in ("course", "wale")]


def test_a_members_curves_return_the_member(family):
    fit = fit_stitch(family, targets_at(family, 6.0))
    assert fit.stitch == pytest.approx(6.0, abs=1e-6)
    assert fit.met
    assert max(fit.misses) < 1e-6


@pytest.mark.parametrize("stitch", [4.62, 5.75, 6.9])
def test_the_laws_curves_between_members_return_their_stitch(family, stitch):
    fit = fit_stitch(family, targets_at(family, stitch))
    assert fit.stitch == pytest.approx(stitch, abs=1e-5)


def test_the_mean_of_two_members_curves_lies_between_them(family):
    course = [curve_at(family, s, "course") for s in (5.5, 6.0)]
    wale = [curve_at(family, s, "wale") for s in (5.5, 6.0)]
    targets = [
        UniaxialTarget("course", course[0][0], 0.5 * (course[0][1] + course[1][1])),
        UniaxialTarget("wale", wale[0][0], 0.5 * (wale[0][1] + wale[1][1])),
    ]
    fit = fit_stitch(family, targets)
    assert 5.5 < fit.stitch < 6.0
    # the fit is a least-squares optimum: moving the stitch either way costs more
    cost = [
        sum(
            float(np.sum(((t.predicted(family, s) - t.force) / t.force.max()) ** 2))
            for t in targets
        )
        for s in (fit.stitch - 1e-3, fit.stitch, fit.stitch + 1e-3)
    ]
    assert cost[1] < min(cost[0], cost[2])


def test_a_target_beyond_the_family_returns_the_nearest_end_and_its_miss(family):
    strain, force = curve_at(family, 4.5, "course")
    fit = fit_stitch(family, [UniaxialTarget("course", strain, 2.0 * force, tolerance=0.05)])
    assert fit.stitch == pytest.approx(4.5, abs=1e-9)
    assert not fit.met
    assert fit.misses[0] == pytest.approx(0.5, rel=1e-6)


def test_bounds_within_the_family_bound_the_answer(family):
    fit = fit_stitch(family, targets_at(family, 6.0), bounds=(4.5, 5.5))
    assert fit.stitch == pytest.approx(5.5, abs=1e-9)
    with pytest.raises(InputError, match=r"stitch upper bound=7.5 mm is outside"):
        fit_stitch(family, targets_at(family, 6.0), bounds=(4.5, 7.5))


def test_a_curve_file_in_gf_per_cm_reads_as_n_per_mm(tmp_path):
    path = tmp_path / "course.csv"
    path.write_text("# measured\nstrain, force_gf_per_cm\n0.05, 2.0\n0.10, 5.0\n\n")
    strain, force = read_curve(path)
    np.testing.assert_array_equal(strain, [0.05, 0.1])
    np.testing.assert_allclose(force, np.array([2.0, 5.0]) * GRAM_FORCE / 10.0, rtol=1e-15)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "is empty"),
        ("strain, force\n0.1, 1\n", "needs a header naming 'strain' and 'force_n_per_mm' or"),
        ("strain, force_n_per_mm\n0.1, a\n", "row 2"),
        ("strain, force_n_per_mm\n", "no data rows"),
    ],
)
def test_bad_curve_files_are_refused_naming_the_problem(tmp_path, text, message):
    path = tmp_path / "curve.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        read_curve(path, "design.target[0].file")


@pytest.mark.parametrize(
    ("target", "message"),
    [
        (UniaxialTarget("bias", [0.1], [1.0]), "course or wale"),
        (UniaxialTarget("course", [0.2, 0.1], [1.0, 2.0]), "must increase"),
        (UniaxialTarget("course", [0.1, 0.2], [1.0]), "the same number"),
        (UniaxialTarget("course", [0.1], [0.0]), "nothing to fit"),
    ],
)
def test_bad_targets_are_refused_naming_the_problem(target, message):
    with pytest.raises(InputError, match=message):
        target.check("design.target[0]")
