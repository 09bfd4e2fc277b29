"""Response-surface fits against known laws: exact reproduction of polynomials in the spline space,
energy recovery, constraints, convergence under knot refinement, asymmetry reporting."""

import dataclasses

import numpy as np
import pytest
import scipy.optimize

from rve_rod.errors import InputError
from rve_rod.homogenize.analytic import AnalyticRve
from rve_rod.homogenize.fit import (
    FitOptions,
    _bounded_least_squares,
    fit_energy_surface,
    fit_report,
    fit_stress_surface,
    knot_vector,
)
from rve_rod.homogenize.generate import execute
from rve_rod.homogenize.samples import RveCase, RveRun, stored_samples, surface_samples
from rve_rod.homogenize.sampling import SamplingPlan
from rve_rod.presets import load_preset
from rve_rod.stress_measures import green_lagrange, voigt
from rve_rod.surface import read_surface, write_surface

FABRIC = load_preset("cotton-20s2", 5.5)
RNG = np.random.default_rng(17)


def law_samples(stress, plan=None):
    """Samples of a stress law S(E) (m, 3) -> (m, 3) along the load paths of `plan`."""
    plan = plan or SamplingPlan()
    paths = plan.load_paths()
    runs = []
    for path in paths:
        F = path.deformation_gradients()
        S = stress(voigt(green_lagrange(F)))
        tensor = np.stack([S[:, [0, 2]], S[:, [2, 1]]], axis=1)
        runs.append(RveRun(F, F @ tensor))
    return surface_samples(paths, tuple(runs))


def polynomial_stress(E):
    """Degree <= 2 in each of E11, E22 (non-symmetric tangent), S(0) = 0, linear odd S12."""
    E11, E22, E12 = E.T
    S11 = 0.3 * E11 + 0.1 * E22 + 2 * E11**2 - 0.5 * E11 * E22 + E11 * E22**2
    S22 = 0.2 * E22 + 0.05 * E11 + 3 * E22**2 + E11**2 * E22**2 - E11**2
    return np.stack([S11, S22, 0.07 * E12], axis=1)


def cubic_shear_stress(E):
    E11, E22, E12 = E.T
    return np.stack([0.3 * E11, 0.2 * E22, 0.05 * E12 + 0.4 * E12**3], axis=1)


def inside_points(surface, m=2000):
    E = np.stack([RNG.uniform(*surface.domain[a], m) for a in range(3)], axis=1)
    assert not surface.stress(E).outside.any()
    return E


@pytest.mark.parametrize("regularization", [1e-8, 1e-3, 1e-1])
@pytest.mark.parametrize("spans", [3, 6])
def test_polynomial_law_in_the_spline_space_is_reproduced(regularization, spans):
    # the jump penalty vanishes on polynomials of degree 2 per input: any weight keeps them
    # (a weight is needed: 6 spans leave cells between the rays without samples)
    # (the law softens in parts of the box: the fit without the monotone condition)
    samples = law_samples(polynomial_stress)
    options = FitOptions(spans=spans, regularization=regularization, monotone=False)
    surface = fit_stress_surface(samples, options)
    E = inside_points(surface)
    np.testing.assert_allclose(surface.stress(E).S, polynomial_stress(E), rtol=0, atol=1e-10)
    for stats in fit_report(surface).residuals.values():
        assert stats.max_abs < 1e-10


def monotone_polynomial_stress(E):
    """Degree <= 2 per input, dS11/dE11 >= 0.08 and dS22/dE22 >= 0.03 over the sampled box."""
    E11, E22, E12 = E.T
    S11 = 0.3 * E11 + 0.1 * E22 + 1.0 * E11**2 - 0.2 * E11 * E22
    S22 = 0.2 * E22 + 0.05 * E11 + 0.8 * E22**2 + 0.3 * E11 * E22 - E11**2
    return np.stack([S11, S22, 0.07 * E12], axis=1)


@pytest.mark.parametrize("spans", [3, 6])
def test_monotone_law_in_the_spline_space_is_reproduced_by_the_monotone_fit(spans):
    # No bound is active: the monotone fit is the plain one, and reproduces the law.
    samples = law_samples(monotone_polynomial_stress)
    surface = fit_stress_surface(samples, FitOptions(spans=spans, monotone=True))
    E = inside_points(surface)
    np.testing.assert_allclose(surface.stress(E).S, monotone_polynomial_stress(E), atol=1e-10)


def kinked_stress(E):
    """A knit-like law: the lateral stress almost vanishes in compression (slope 1/100 of
    tension's) and stiffens in tension, with a kink at E = 0 in each input."""
    E11, E22, E12 = E.T
    soft = np.where(E11 < 0, 0.01, 1.0) * E11, np.where(E22 < 0, 0.01, 1.0) * E22
    S11 = 0.3 * soft[0] + 2.0 * np.maximum(E11, 0) ** 2 + 0.02 * soft[1]
    S22 = 0.6 * soft[1] + 4.0 * np.maximum(E22, 0) ** 2 + 0.05 * soft[0]
    return np.stack([S11, S22, 0.07 * E12], axis=1)


def test_monotone_fit_of_a_kinked_law_keeps_the_stiffness_floor():
    samples = law_samples(kinked_stress)
    fits = {
        monotone: fit_stress_surface(samples, FitOptions(monotone=monotone))
        for monotone in (False, True)
    }
    (x0, x1), (y0, y1) = fits[True].domain[:2]  # (outside, the C1 extension decides)
    x, y = np.meshgrid(np.linspace(x0, x1, 75), np.linspace(y0, y1, 75))
    grid = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    slopes = {
        monotone: np.diagonal(surface.stress(grid).tangent, axis1=1, axis2=2)[:, :2]
        for monotone, surface in fits.items()
    }
    scale = 0.6  # the law's smallest tension slope, N/mm
    assert slopes[False].min() < -0.01 * scale  # the plain fit undershoots at the kink
    # the stiffness floor: 1 % of each component's mean slope over the data
    S, E = samples.biaxial_stress[:, :2], samples.biaxial_strain[:, :2]
    floor = FitOptions().stiffness_floor * np.ptp(S, axis=0) / np.ptp(E, axis=0)
    assert np.all(slopes[True].min(axis=0) >= floor * (1 - 1e-9))
    plain, monotone = (fit_report(fits[m]).residuals for m in (False, True))
    for group in ("S11", "S22"):
        assert monotone[group].max_abs < 2.0 * plain[group].max_abs + 1e-4


def test_cubic_shear_reproduced_with_degree_three():
    samples = law_samples(cubic_shear_stress)
    surface = fit_stress_surface(samples, FitOptions(degree=3, spans=4))
    E = inside_points(surface)
    np.testing.assert_allclose(surface.stress(E).S, cubic_shear_stress(E), rtol=0, atol=1e-10)


def cubic_energy(E):
    """psi(E11, E22) of degree 3 per input with psi(0) = 0 and grad psi(0) = 0."""
    E11, E22, _ = E.T
    return (
        0.2 * E11**2
        + 0.05 * E11 * E22
        + 0.4 * E22**2
        + 1.5 * E11**3
        - 0.3 * E11**2 * E22
        + 2.0 * E22**3
        + 4.0 * E11**3 * E22**3
    )


def cubic_energy_stress(E):
    E11, E22, E12 = E.T
    S11 = 0.4 * E11 + 0.05 * E22 + 4.5 * E11**2 - 0.6 * E11 * E22 + 12.0 * E11**2 * E22**3
    S22 = 0.05 * E11 + 0.8 * E22 - 0.3 * E11**2 + 6.0 * E22**2 + 12.0 * E11**3 * E22**2
    # psi_shear = 0.03 E12^2 + 0.1 E12^4 has degree 4: use its quadratic part only
    return np.stack([S11, S22, 0.06 * E12], axis=1)


@pytest.mark.parametrize("regularization", [0.0, 1e-3])
def test_energy_fit_recovers_the_energy_it_was_sampled_from(regularization):
    samples = law_samples(cubic_energy_stress)
    surface = fit_energy_surface(samples, FitOptions(spans=5, regularization=regularization))
    E = inside_points(surface)
    np.testing.assert_allclose(surface.psi(E[:, 0], E[:, 1]), cubic_energy(E), rtol=0, atol=1e-11)
    np.testing.assert_allclose(surface.psi_shear(E[:, 2]), 0.03 * E[:, 2] ** 2, atol=1e-12)
    np.testing.assert_allclose(surface.stress(E).S, cubic_energy_stress(E), rtol=0, atol=1e-10)


def test_energy_fit_tangent_is_symmetric_inside_and_outside():
    samples = law_samples(AnalyticRve(coupling_11_22=0.02, coupling_22_11=0.3).stress)
    surface = fit_energy_surface(samples)
    E = np.stack([RNG.uniform(-0.4, 0.4, 3000) for _ in range(3)], axis=1)
    result = surface.stress(E)
    assert 0.2 < result.outside.mean() < 0.99
    asymmetry = np.abs(result.tangent - result.tangent.transpose(0, 2, 1)).max()
    assert asymmetry < 1e-13 * np.abs(result.tangent).max()


@pytest.mark.parametrize("fitter", [fit_stress_surface, fit_energy_surface])
def test_zero_stress_at_zero_strain_and_odd_shear(fitter):
    samples = law_samples(AnalyticRve().stress)
    noisy = samples._replace(biaxial_stress=samples.biaxial_stress + 1e-3)
    surface = fitter(noisy)
    np.testing.assert_allclose(surface.stress(np.zeros(3)).S, 0.0, atol=1e-15)
    shear = np.linspace(-0.5, 0.5, 101)
    E = np.stack([np.zeros_like(shear), np.zeros_like(shear), shear], axis=1)
    S12 = surface.stress(E).S[:, 2]
    np.testing.assert_allclose(S12, -S12[::-1], rtol=0, atol=1e-15)


def test_stress_fit_converges_under_knot_refinement():
    # A smooth law (not in any spline space): error at the samples falls at a rate near p+1 = 3.
    rve = AnalyticRve()
    samples = law_samples(rve.stress, SamplingPlan(rays=32, steps_per_ray=48))
    spans = np.array([3, 6, 12])
    errors = []
    for n in spans:
        surface = fit_stress_surface(samples, FitOptions(spans=int(n), regularization=1e-8))
        errors.append(max(surface.samples[g].stats().max_rel for g in ("S11", "S22")))
    slope = -np.polyfit(np.log(spans), np.log(errors), 1)[0]
    assert 2.7 < slope < 3.6
    assert errors[-1] < 2.5e-4


def test_regularization_keeps_unsampled_regions_sane():
    # A cell that cannot follow compression leaves the box corners empty; the default fit must
    # stay within the range of the data there, and close to the law between the rays.
    rve = AnalyticRve(compression_limit=0.03)
    plan = SamplingPlan()
    paths = plan.load_paths()
    samples = surface_samples(paths, tuple(execute(rve, RveCase(FABRIC, p)) for p in paths))
    surface = fit_stress_surface(samples)
    (x0, x1), (y0, y1) = surface.domain[:2]
    x, y = np.meshgrid(np.linspace(x0, x1, 61), np.linspace(y0, y1, 61))
    grid = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], axis=1)
    S = surface.stress(grid).S[:, :2]
    scale = np.abs(samples.biaxial_stress[:, :2]).max(axis=0)
    assert np.all(np.abs(S) <= 1.2 * scale)
    error = np.abs(S - rve.stress(grid)[:, :2]) / scale
    assert error.max() < 0.06


def test_asymmetry_report_lets_users_choose():
    symmetric = law_samples(AnalyticRve().stress)
    asymmetric_law = AnalyticRve(coupling_11_22=0.0, coupling_22_11=0.4)
    asymmetric = law_samples(asymmetric_law.stress)
    reports = {
        (law, kind): fit_report(fitter(samples))
        for law, samples in (("symmetric", symmetric), ("asymmetric", asymmetric))
        for kind, fitter in (("stress", fit_stress_surface), ("energy", fit_energy_surface))
    }

    def worst(report):
        return max(report.residuals[g].max_rel for g in ("S11", "S22"))

    # a symmetric law: both fits are good; an asymmetric law: only the stress fit can follow it
    assert worst(reports["symmetric", "energy"]) < 2e-3
    assert worst(reports["symmetric", "stress"]) < 2e-3
    assert worst(reports["asymmetric", "energy"]) > 10 * worst(reports["asymmetric", "stress"])
    # the law's own asymmetry |c12 - c21| / max |tangent|_F, the largest tangent at the corner
    strain_corner = law_samples(asymmetric_law.stress).biaxial_strain[:, :2].max(axis=0)
    diagonal = [
        asymmetric_law.course_stiffness
        * np.exp(asymmetric_law.course_stiffening * strain_corner[0]),
        asymmetric_law.wale_stiffness * np.exp(asymmetric_law.wale_stiffening * strain_corner[1]),
    ]
    exact = 0.4 / np.sqrt(diagonal[0] ** 2 + diagonal[1] ** 2 + 0.4**2)
    assert reports["asymmetric", "stress"].tangent_asymmetry > 0.8 * exact
    # a stress fit of a hyperelastic law is not exactly symmetric: between the rays its
    # cross derivatives are free (documented in docs/surfaces.md)
    assert reports["symmetric", "stress"].tangent_asymmetry < 0.1
    for law in ("symmetric", "asymmetric"):
        assert reports[law, "energy"].tangent_asymmetry < 1e-13


def test_knot_vector_has_a_knot_at_zero_and_covers_the_data():
    knots = knot_vector(np.array([-0.1, 0.05, 0.3]), 2, 8)
    assert knots[0] == -0.1 and knots[-1] == 0.3 and 0.0 in knots
    np.testing.assert_array_equal(knots[:3], -0.1)
    assert np.unique(knots).size == 9
    only_positive = knot_vector(np.array([0.1, 0.2]), 3, 4)
    assert only_positive[0] == 0.0 and only_positive[-1] == 0.2


def test_fit_input_errors():
    samples = law_samples(polynomial_stress)
    with pytest.raises(InputError, match="no shear samples"):
        fit_stress_surface(samples._replace(shear_strain=np.zeros((0, 3))))
    with pytest.raises(InputError, match="degree"):
        FitOptions(degree=1)
    with pytest.raises(InputError, match="even"):
        FitOptions(shear_spans=5)
    with pytest.raises(
        InputError, match=r"stiffness_floor=1.5 is outside the valid range \[0, 1\]"
    ):
        FitOptions(stiffness_floor=1.5)


def test_bounded_least_squares_meets_the_optimality_conditions():
    # A random problem with free (-inf) and bounded unknowns, many bounds active: the
    # solution satisfies the KKT conditions of min |M x - b| s.t. x >= lower and equals BVLS's.
    m, n = 120, 60
    matrix = RNG.normal(size=(m, n))
    rhs = RNG.normal(size=m)
    lower = np.where(np.arange(n) % 4 == 0, -np.inf, RNG.uniform(-0.2, 0.2, n))
    x = _bounded_least_squares(matrix, rhs, lower)
    gradient = matrix.T @ (matrix @ x - rhs)
    free = np.isneginf(lower)
    at_bound = ~free & np.isclose(x, lower, rtol=0, atol=1e-12)
    assert np.all(x[~free] >= lower[~free] - 1e-12)
    assert 10 < at_bound.sum() < (~free).sum()  # the bounds matter
    np.testing.assert_allclose(gradient[~at_bound], 0.0, atol=1e-10)
    assert np.all(gradient[at_bound] >= -1e-10)
    reference = scipy.optimize.lsq_linear(
        matrix, rhs, bounds=(lower, np.inf), method="bvls", tol=1e-14
    ).x
    np.testing.assert_allclose(x, reference, atol=1e-10)


def test_stored_samples_refit_the_surface_they_were_stored_with(tmp_path):
    # A surface written and read back gives its samples to a refit with the same options:
    # the same coefficients (no RVE run needed to refit a shipped surface).
    options = FitOptions(spans=6)
    surface = fit_stress_surface(law_samples(monotone_polynomial_stress), options)
    write_surface(tmp_path / "s.h5", surface)
    refit = fit_stress_surface(stored_samples(read_surface(tmp_path / "s.h5")), options)
    for name in ("s11", "s22", "s12"):
        np.testing.assert_allclose(
            getattr(refit, name).coefficients, getattr(surface, name).coefficients, atol=1e-12
        )
    with pytest.raises(InputError, match="stores no samples"):
        stored_samples(dataclasses.replace(surface, samples={}))
