"""Crossed rods pressed together: the line loads reproduce the law at the exact penetration,
the resultants converge to the continuum integral, and the two-pass imbalance is the one the
continuum two-pass model predicts."""

import numpy as np
import pytest
import scipy.integrate
from support.contact_scenes import crossed_rods

from rve_rod.contact import CompressibleYarnLaw, ContactModel, ContactOptions, Patch, YarnChain
from rve_rod.contact import _kernels as contact_kernels
from rve_rod.geometry.bspline import greville_abscissae, interpolate, open_knot_vector

RADIUS = 0.15
LAW = CompressibleYarnLaw(stiffness=5.0, exponent=1.5, yarn_radius=RADIUS)


def evaluate(scene):
    model = ContactModel(scene.patches, scene.positions, LAW, yarns=scene.yarns)
    return model, model.evaluate(scene.positions)


@pytest.mark.parametrize("angle", [0.5 * np.pi, 0.25 * np.pi])
@pytest.mark.parametrize("penetration", [0.001, 0.03, 0.12])
def test_line_load_matches_the_law_at_the_exact_penetration(angle, penetration):
    separation = 2 * RADIUS - penetration
    scene = crossed_rods(separation, angle, length=2.0, n_control_points=41)
    _, result = evaluate(scene)
    # Rod 0 point (s, 0, h/2) is sqrt(h^2 + s^2 sin^2) from rod 1 along n = v / |v|.
    s = 2.0 * (greville_abscissae(scene.patches[0].knots, 4) - 0.5)
    v = np.stack(
        [s * np.sin(angle) ** 2, -s * np.sin(angle) * np.cos(angle), np.full_like(s, separation)]
    )
    distance = np.linalg.norm(v, axis=0)
    expected = LAW.line_load(2 * RADIUS - distance) * v / distance
    np.testing.assert_allclose(result.line_load[:, :41], expected, rtol=1e-12, atol=1e-15)
    # Rod 1 sees the mirror image: the same profile with the opposite normal component.
    assert result.statistics.active_contacts == 2 * np.count_nonzero(distance < 2 * RADIUS)
    np.testing.assert_allclose(result.line_load[2, 41:], -expected[2], rtol=1e-12, atol=1e-15)
    assert result.statistics.max_penetration == pytest.approx(penetration, rel=1e-12)


@pytest.mark.parametrize("angle", [0.5 * np.pi, 0.25 * np.pi])
def test_resultant_converges_to_the_continuum_integral(angle):
    separation = 2 * RADIUS - 0.1
    half_width = np.sqrt((2 * RADIUS) ** 2 - separation**2) / np.sin(angle)

    def density(s):
        d = np.hypot(separation, s * np.sin(angle))
        return LAW.line_load(2 * RADIUS - d) * separation / d

    exact = scipy.integrate.quad(density, -half_width, half_width, epsabs=0, epsrel=1e-13)[0]
    sizes = [16, 32, 64, 128]
    errors = []
    for n in sizes:
        model, result = evaluate(crossed_rods(separation, angle, n_control_points=n))
        weights = model.collocation_weights[:n]
        errors.append(abs(np.sum(weights * result.line_load[2, :n]) - exact) / exact)
    slope = np.polyfit(np.log(sizes), np.log(errors), 1)[0]
    assert slope < -1.5
    assert errors[-1] < 2e-4


def straight_and_arc(n, bend_radius, separation):
    """Rod 0 straight along x; rod 1 in the y-z plane, bent around rod 0 with radius R."""
    degree = 4

    def rod(count, points_of):
        knots = open_knot_vector(degree, count)
        params = greville_abscissae(knots, degree)
        curve = interpolate(points_of(params), degree, params=params, knots=knots)
        return Patch(degree, knots), curve.control_points

    patch_0, points_0 = rod(n, lambda g: np.stack([2 * g - 1, 0 * g, 0 * g + separation / 2], 1))

    def arc(g):
        t = 2.4 * g - 1.2  # arc length from the crossing
        if np.isinf(bend_radius):
            return np.stack([0 * g, t, 0 * g - separation / 2], 1)
        y = bend_radius * np.sin(t / bend_radius)
        z = bend_radius * (1 - np.cos(t / bend_radius)) - separation / 2
        return np.stack([0 * g, y, z], 1)

    patch_1, points_1 = rod(int(1.5 * n) + 1, arc)
    return [patch_0, patch_1], np.vstack([points_0, points_1])


def test_two_pass_imbalance_vanishes_for_straight_rods_under_refinement():
    imbalances = []
    for n in (16, 32, 64, 128):
        patches, positions = straight_and_arc(n, np.inf, 0.25)
        model = ContactModel(patches, positions, LAW, yarns=[YarnChain((0,)), YarnChain((1,))])
        loads = model.evaluate(positions).line_load * model.collocation_weights
        total_0, total_1 = loads[:, :n].sum(axis=1), loads[:, n:].sum(axis=1)
        imbalances.append(np.linalg.norm(total_0 + total_1) / np.linalg.norm(total_0))
    assert imbalances[-1] < 1e-3
    assert imbalances[-1] < 0.05 * imbalances[0]


@pytest.mark.parametrize("bend_radius", [3.0, 1.0, 0.5])
def test_two_pass_imbalance_of_a_wrapped_rod_is_the_continuum_one(bend_radius):
    # A rod bent around another (radius R) is within the contact distance over a longer arc:
    # its centreline is d(t)^2 = R^2 + (R-h)^2 - 2R(R-h) cos(t/R) from rod 0, so two-pass line
    # loads give it about 1/sqrt(1 - h/R) times the resultant of the straight rod.
    separation, n = 0.25, 128
    patches, positions = straight_and_arc(n, bend_radius, separation)
    model = ContactModel(patches, positions, LAW, yarns=[YarnChain((0,)), YarnChain((1,))])
    loads = model.evaluate(positions).line_load * model.collocation_weights
    total_0, total_1 = loads[2, :n].sum(), loads[2, n:].sum()

    centre = bend_radius - separation  # distance of the bend centre from rod 0

    def density_1(t):
        # Arc point relative to rod 0 (in the y-z plane) and the z part of its normal load.
        y = bend_radius * np.sin(t / bend_radius)
        z = bend_radius * (1 - np.cos(t / bend_radius)) - separation
        d = np.hypot(y, z)
        return LAW.line_load(2 * RADIUS - d) * z / d

    reach = bend_radius * np.arccos(
        (bend_radius**2 + centre**2 - (2 * RADIUS) ** 2) / (2 * bend_radius * centre)
    )
    expected_1 = scipy.integrate.quad(density_1, -reach, reach, epsrel=1e-12)[0]
    assert total_1 == pytest.approx(expected_1, rel=2e-3)
    imbalance = abs(total_0 + total_1) / total_0
    assert imbalance == pytest.approx(1 / np.sqrt(1 - separation / bend_radius) - 1, rel=0.15)


def crossing_point_load(law, penetration):
    """Line load (3,) at rod 0's middle collocation point, right above the crossing (41 Greville
    points: the middle one is at s = 0, where d = separation), and the Jacobian row sum of its
    z component over rod 0's z coordinates (d f_z / d z of a rigid lift of rod 0)."""
    scene = crossed_rods(2 * RADIUS - penetration, n_control_points=41)
    model = ContactModel(scene.patches, scene.positions, law, yarns=scene.yarns)
    result = model.evaluate(scene.positions)
    m = model.n_collocation_points
    jacobian = result.jacobian.tocsr()
    return result.line_load[:, 20], jacobian[2 * m + 20, 2 : 3 * 41 : 3].sum()


@pytest.mark.parametrize(("stiffness", "exponent"), [(5.0, 1.0), (5.0, 2.4), (20.0, 1.5)])
def test_the_law_object_sets_the_force_of_a_run(stiffness, exponent):
    # f_n = k (r/p) (g/r)^p and df_n/dg = k (g/r)^(p-1), written out here (not law.py's code);
    # a lift of rod 0 opens the gap: d f_z / d z = -df_n/dg.
    penetration = 0.03
    law = CompressibleYarnLaw(stiffness=stiffness, exponent=exponent, yarn_radius=RADIUS)
    load, lift_stiffness = crossing_point_load(law, penetration)
    expected = stiffness * (RADIUS / exponent) * (penetration / RADIUS) ** exponent
    np.testing.assert_allclose(load, [0.0, 0.0, expected], rtol=1e-12, atol=1e-15)
    slope = stiffness * (penetration / RADIUS) ** (exponent - 1.0)
    assert lift_stiffness == pytest.approx(-slope, rel=1e-10)


def test_a_run_evaluates_the_one_law_function(monkeypatch):
    # Substitute the law's one function (law.py's CompressibleYarnLaw.load_and_slope calls it)
    # by a linear penalty f_n = 7 g (N/mm): the run follows, so no copy of the formula runs.
    def linear_penalty(penetration, parameters, out):
        out[0] = 7.0 * np.maximum(penetration, 0.0)
        out[1] = np.where(penetration > 0.0, 7.0, 0.0)

    penetration = 0.03
    law = CompressibleYarnLaw(stiffness=5.0, exponent=2.4, yarn_radius=RADIUS)
    original, _ = crossing_point_load(law, penetration)
    monkeypatch.setattr(contact_kernels, "compressible_yarn_law", linear_penalty)
    load, lift_stiffness = crossing_point_load(law, penetration)
    assert abs(original[2] - 7.0 * penetration) > 0.1 * original[2]
    np.testing.assert_allclose(load, [0.0, 0.0, 7.0 * penetration], rtol=1e-12, atol=1e-15)
    assert lift_stiffness == pytest.approx(-7.0, rel=1e-10)


@pytest.mark.parametrize("n_control_points", [41, 81])
def test_point_lumping_puts_the_law_as_a_force_at_the_collocation_point(n_control_points):
    # lumping="point": the force at rod 0's middle collocation point (above the crossing,
    # d = separation) is F = k r^2/p (g/r)^p (N), written out here, applied as the line load
    # F / h with h its collocation weight, whatever the mesh; the line lumping's force there is
    # f_n h = F h / r, which halves with h.
    penetration, (k, p) = 0.03, (5.0, 1.5)
    law = CompressibleYarnLaw(stiffness=k, exponent=p, yarn_radius=RADIUS)
    scene = crossed_rods(2 * RADIUS - penetration, n_control_points=n_control_points)
    middle = n_control_points // 2
    force = k * RADIUS**2 / p * (penetration / RADIUS) ** p

    def force_at_the_crossing(lumping):
        model = ContactModel(
            scene.patches,
            scene.positions,
            law,
            yarns=scene.yarns,
            options=ContactOptions(lumping=lumping),
        )
        weight = model.collocation_weights[middle]
        return model.evaluate(scene.positions).line_load[:, middle] * weight, weight

    point, weight = force_at_the_crossing("point")
    np.testing.assert_allclose(point, [0.0, 0.0, force], rtol=1e-12, atol=1e-15)
    line, _ = force_at_the_crossing("line")
    np.testing.assert_allclose(line, [0.0, 0.0, force * weight / RADIUS], rtol=1e-12, atol=1e-15)
    assert weight == pytest.approx(2.0 / (n_control_points - 1), rel=0.1)
