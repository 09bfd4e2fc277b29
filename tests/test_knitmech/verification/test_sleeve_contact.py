"""The sleeve's contact model (a membrane in space drawn over a rigid body of revolution by an
expanding mandrel, frictionless) against the Laplace model, on the synthetic family.

* A cylinder: uniform pressure, the closed form p = T / r with T = lambda_1 S11 / lambda_2 of
  the knit's law at the worn stretches (the Laplace model); the fabric lies on the cylinder
  within the penalty's gap. The faceted quarter tube
  converges to it at second order (the error falls by more than 3 from 5 to 2.5 mm quads) and
  is within 1.5 % at 2.5 mm; the contact pressure equals the hoop force over the deformed
  radius (the ring's normal equilibrium) to round-off.
* The leg profile (5 mm quads, coarse; the full resolution and the cotton family in
  benchmarks/bench_design.py): the difference from the Laplace model explained term by term
  (the test's docstring).
"""

import numpy as np
import pytest
from mpi4py import MPI
from support.design_cases import synthetic_family

from fabric_dolfinx.spec.revolution import RadiusProfile
from knitmech.design.sleeve import (
    PressureTarget,
    SleeveSpec,
    design_sleeve,
    laplace_pressure,
    stretched_band,
)
from knitmech.design.solve import SolverSettings
from knitmech.jobs.sleeve import run_sleeve
from knitmech.jobs.sleeve_spec import SleeveJob
from rve_rod.units import MMHG

CYLINDER = ((0.0, 40.0), (100.0, 40.0))
LEG = RadiusProfile(
    (0, 50, 100, 150, 200, 250, 300, 350, 400), (35, 37, 41.5, 48, 54, 58, 59, 56, 52.5)
)
"""examples/design/leg.csv"""


@pytest.fixture(scope="module")
def family(tmp_path_factory):
    return synthetic_family((5.5, 6.0), tmp_path_factory.mktemp("family"))


def contact(family, limb, knit, folder, element_size):
    stitches, needles, courses = knit
    job = SleeveJob(
        family.members,
        limb,
        tuple(stitches),
        tuple(needles),
        tuple(courses),
        element_size=element_size,
        steps=8,
    )
    summary = run_sleeve(job, folder, MPI.COMM_SELF)
    assert summary["complete"], summary["message"]
    return summary


@pytest.mark.slow
def test_on_a_cylinder_the_contact_pressure_converges_to_laplaces_closed_form(family, tmp_path):
    sleeve = SleeveSpec(RadiusProfile(*zip(*CYLINDER, strict=True)), 2, (160.0, 160.0))
    stitches, needles = np.array([5.7, 5.7]), np.array([160.0, 160.0])
    courses = np.array([sleeve.courses(family, s) for s in stitches])
    expected = laplace_pressure(family, sleeve, stitches, needles, courses)[0].pressure
    errors = []
    for size in (5.0, 2.5):
        summary = contact(family, CYLINDER, (stitches, needles, courses), tmp_path, size)
        for ring in summary["bands"]:
            assert ring["pressure"] == pytest.approx(
                ring["hoop_tension"] / ring["radius"], rel=1e-6
            )
            # the penalty's gap: k gap is the pressure per undeformed area (J p), k = 1 N/mm^3
            area_ratio = ring["hoop_stretch"] * ring["axial_stretch"]
            assert ring["radius"] == pytest.approx(40.0 - area_ratio * ring["pressure"], abs=1e-5)
        errors.append(summary["bands"][0]["pressure"] / expected - 1.0)
    assert abs(errors[1]) < 0.015
    assert abs(errors[0]) / abs(errors[1]) > 3.0


@pytest.mark.slow
def test_on_the_leg_the_contact_model_explains_its_difference_from_laplace(tmp_path):
    """The designed sleeve on the leg, 5 mm quads, a knit-like family (wale four times as
    stiff as the synthetic family's). The contact pressure is the membrane of revolution's
    N_theta cos(alpha) / rho + N_phi kappa (2 %), and its hoop force is Laplace's law at the
    contact model's own stretches (1 %): what differs from the Laplace model is where the
    frictionless sleeve sits. Its hoop tension on the cone of the lower leg pushes it toward
    the ankle (the axial stretch grows from the ankle to the calf, where the design has one
    stretch), which moves the hoop strain by under 1 % and, on the knit's steep curve, the
    pressure by -13 ... +7 % (measured; bound 15 %, docs/design.md)."""
    family = synthetic_family((5.5, 6.0), tmp_path, wale_factor=4.0)
    sleeve = SleeveSpec(LEG, 8)
    target = PressureTarget(np.interp(sleeve.centres, [0, 400], [10.0, 6.0]) * MMHG)
    design = design_sleeve(family, sleeve, target, (5.5, 6.0), SolverSettings())
    assert design.met
    limb = tuple(zip(LEG.z, LEG.r, strict=True))
    knit = (design.stitches, design.needles.astype(float), design.courses.astype(float))
    rings = contact(family, limb, knit, tmp_path, 5.0)["bands"]
    laplace = np.array([state.pressure for state in design.states])
    pressure = np.array([ring["pressure"] for ring in rings])
    membrane = np.array([ring["membrane_pressure"] for ring in rings])
    np.testing.assert_array_less(np.abs(membrane / pressure - 1.0), 0.02)
    for ring in rings:
        stretches = (ring["hoop_stretch"], ring["axial_stretch"])
        own = stretched_band(family, ring["stitch"], stretches, ring["limb_radius"])
        assert ring["hoop_tension"] == pytest.approx(own.tension, rel=0.01)
    axial = [ring["axial_stretch"] for ring in rings]
    assert axial[0] < sleeve.axial_stretch - 0.01 and axial[5] > sleeve.axial_stretch + 0.01
    assert np.all(np.diff(axial[:6]) > 0)
    np.testing.assert_array_less(np.abs(pressure / laplace - 1.0)[1:-1], 0.15)
