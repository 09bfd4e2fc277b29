"""The summary numbers: forces and Poisson ratios read off the curves at 5, 10, 20 %."""

import json

import numpy as np
import pytest

from fabric_dolfinx.spec.tension import TensionTest
from knitmech.report import compare_forces, poisson_ratios, summary_table, value_at
from knitmech.stages.records import (
    GeometrySummary,
    MesoSummary,
    PatchJob,
    PatchSummary,
    SurfaceSummary,
)


def curve(max_strain, steps, force, lateral):
    """An RVE run record with force(strain) and lateral(strain) sampled at `steps` states."""
    strain = np.linspace(0.0, max_strain, steps)
    return MesoSummary(
        case="uniaxial",
        complete=True,
        message="",
        strain=strain,
        force_gf_per_cm=[force(s) for s in strain],
        lateral_strain=[lateral(s) for s in strain],
        poisson_ratio=None,
        newton_iterations_total=0,
        wall_time_s=0.0,
    )


def patch(max_strain, steps, force, lateral):
    """A patch record like `curve`, whose material alone gives 0.9 times its force and whose
    centre gauge strains 1.25 times the nominal strain and contracts by 0.25 of that."""
    strain = np.linspace(0.0, max_strain, steps)
    return PatchSummary(
        direction="course",
        complete=True,
        force_positive=True,
        message="",
        strain=strain,
        force_gf_per_cm=[force(s) for s in strain],
        force_n_per_mm=[force(s) / 1019.7 for s in strain],
        material_uniaxial_gf_per_cm=[0.9 * force(s) for s in strain],
        lateral_strain=[lateral(s) for s in strain],
        poisson_ratio=[np.nan] + [-lateral(s) / s for s in strain[1:]],
        gauge_strain=1.25 * strain,
        gauge_lateral_strain=-0.25 * 1.25 * strain,
        newton_iterations=[1] * (steps - 1),
        cutbacks=0,
        outside_domain=False,
        dofs=0,
        ranks=1,
        solve_time_s=0.0,
        field_strain=0.1,
    )


def test_values_between_states_are_linear_interpolation_and_none_beyond_the_end():
    strain = [0.0, 0.04, 0.08, 0.12]
    values = [0.0, 1.0, None, 5.0]  # a missing value is skipped
    assert value_at(strain, values, 0.02) == pytest.approx(0.5)
    assert value_at(strain, values, 0.10) == pytest.approx(1.0 + 4.0 * 0.06 / 0.08)
    assert value_at(strain, values, 0.12) == pytest.approx(5.0)
    assert value_at(strain, values, 0.2) is None


def test_forces_and_poisson_ratios_of_meso_and_macro():
    meso = {
        "uniaxial-course": curve(0.2, 21, lambda s: 100 * s, lambda s: -0.1 * s),
        "uniaxial-wale": curve(0.2, 9, lambda s: 400 * s, lambda s: -0.3 * s),
    }
    macro = {"course": patch(0.2, 5, lambda s: 110 * s, lambda s: -0.2 * s)}
    forces = compare_forces(meso, macro)
    assert forces["course"]["meso_gf_per_cm"] == pytest.approx([5.0, 10.0, 20.0])
    assert forces["course"]["macro_gf_per_cm"] == pytest.approx([5.5, 11.0, 22.0])
    assert forces["course"]["surface_gf_per_cm"] == pytest.approx([4.95, 9.9, 19.8])
    assert forces["course"]["relative_difference"] == pytest.approx([0.1] * 3)
    # where the gauge reads t the nominal strain is t / 1.25: force 110 t / 1.25 = 0.88 meso
    assert forces["course"]["centre_gf_per_cm"][:2] == pytest.approx([4.4, 8.8])
    assert forces["course"]["centre_relative_difference"][:2] == pytest.approx([-0.12] * 2)
    assert forces["course"]["centre_gf_per_cm"][2] == pytest.approx(17.6)
    assert forces["wale"]["meso_gf_per_cm"] == pytest.approx([20.0, 40.0, 80.0])
    assert forces["wale"]["macro_gf_per_cm"] == [None] * 3
    ratios = poisson_ratios(meso, macro)
    assert ratios["nu12"]["meso"] == pytest.approx([0.1, 0.1])
    assert ratios["nu12"]["macro"] == pytest.approx([0.2, 0.2])
    assert ratios["nu12"]["centre"] == pytest.approx([0.25, 0.25])
    assert ratios["nu21"]["meso"] == pytest.approx([0.3, 0.3])
    assert ratios["nu21"]["macro"] == [None, None]


def test_table_shows_every_force_and_missing_values_as_dashes():
    meso = {"uniaxial-course": curve(0.1, 11, lambda s: 100 * s, lambda s: -0.1 * s)}
    macro = {"course": patch(0.1, 5, lambda s: 120 * s, lambda s: -0.2 * s)}
    summary = {
        "scene": {"name": "test"},
        "fidelity": {"name": "fast"},
        "forces": compare_forces(meso, macro),
        "poisson_ratios": poisson_ratios(meso, macro),
        "stages": [
            {"stage": "meso", "status": "cached"},
            {"stage": "macro", "status": "computed"},
        ],
        "timings_s": {"meso": 0.5, "macro": 2.0, "report": 0.1, "total": 2.6},
    }
    rows = summary_table(summary).splitlines()
    ten = next(row for row in rows if row.strip().startswith("10 %")).split()
    # centre: where the gauge reads 10 % (nominal 8 %) the patch carries 120 x 0.08
    assert ten[2:] == ["10.00", "10.80", "12.00", "+20.0%", "9.60", "-4.0%"]
    twenty = next(row for row in rows if row.strip().startswith("20 %")).split()
    assert twenty[2:] == ["-", "-", "-", "-", "-", "-"]
    macro_row = next(row for row in rows if row.strip().startswith("macro")).split()
    assert macro_row[1:] == ["1", "1", "0", "2.0"]


def test_a_part_scene_shows_the_rve_without_the_patchs_empty_columns():
    """A part scene has RVE curves but no patch: its table printed six columns of "-"."""
    meso = {"uniaxial-wale": curve(0.2, 11, lambda s: 100 * s, lambda s: -0.1 * s)}
    summary = {
        "scene": {"name": "strip"},
        "fidelity": {"name": "fast"},
        "forces": compare_forces(meso, {}),
        "poisson_ratios": poisson_ratios(meso, {}),
        "stages": [{"stage": "meso", "status": "computed"}],
        "timings_s": {"meso": 0.5, "report": 0.1, "total": 0.6},
    }
    rows = summary_table(summary).splitlines()
    assert rows[2] == "  strain     meso   wale-wise force (gf/cm)"
    assert next(row for row in rows if row.strip().startswith("10 %")).split() == [
        "10",
        "%",
        "10.00",
    ]


def test_records_survive_their_json_round_trip():
    """What the stage cache stores (JSON text) reads back to an equal record; NaN is null."""
    meso = curve(0.2, 5, lambda s: 100 * s, lambda s: -0.1 * s)
    macro = patch(0.2, 5, lambda s: 110 * s, lambda s: -0.2 * s)
    surface = SurfaceSummary(
        kind="stress",
        domain=np.array([[-0.1, 0.2], [-0.1, 0.2], [-0.3, 0.3]]),
        residuals={"S11": {"max_abs": 1e-4, "rms_rel": 1e-3}},
        softest_tangents={"dS11/dE11": {"value": np.float64(0.5), "strain": np.zeros(2)}},
        runs=25,
        incomplete_runs=[{"ray": 3}],
    )
    job = PatchJob(test=TensionTest(direction="wale", elements=6), steps=5, field_step=2)
    for record in (meso, macro, surface, job, GeometrySummary({"loop_length": 5.5})):
        text = json.dumps(record.to_json(), allow_nan=False)
        assert type(record).from_json(json.loads(text)) == record
    assert macro.to_json()["poisson_ratio"][0] is None
    assert "source" not in surface.to_json() and surface.to_json()["runs"] == 25
    assert job.field_strain == pytest.approx(0.08)
    assert job.to_json()["test"]["direction"] == "wale"
    changed = json.loads(json.dumps(macro.to_json()))
    changed["force_gf_per_cm"][2] += 1e-9
    assert PatchSummary.from_json(changed) != macro
