"""Lattice identification: reduction, fundamental lattice despite missing peaks, cells, periods."""

import math
import re

import numpy as np
import pytest

from rve_rod.errors import InputError
from rve_rod.imaging.lattice import (
    _sublattices,
    confirm_periods,
    fabric_cell,
    index_peaks,
    reduce_basis,
)
from rve_rod.imaging.spectrum import flatten_illumination
from rve_rod.imaging.synthetic import SyntheticPhoto, render_photo

WALE_PX, COURSE_PX, ANGLE = 30.0, 24.0, math.radians(10.0)
ROTATION = np.array([[math.cos(ANGLE), -math.sin(ANGLE)], [math.sin(ANGLE), math.cos(ANGLE)]])
REAL = ROTATION @ np.diag([WALE_PX, COURSE_PX])  # columns: wale and course vectors (pixels)
RECIPROCAL = np.linalg.inv(REAL).T
TOLERANCE = 0.5 / 512


def peaks_at(indices, powers, jitter=2e-5, seed=0):
    """Peaks at the given lattice indices (strongest first) with a little position noise."""
    order = np.argsort(-np.asarray(powers, dtype=float))
    indices = np.asarray(indices, dtype=float)[order]
    noise = np.random.default_rng(seed).normal(0, jitter, indices.shape)
    return indices @ RECIPROCAL.T + noise, np.asarray(powers, dtype=float)[order]


# The face of single jersey: glide symmetry, no (1, 0) peak, (2, 0) strongest.
GLIDE = [(2, 0), (1, 1), (-1, 1), (2, 1), (-2, 1), (0, 1), (4, 0), (1, 2), (-1, 2), (3, 1)]
GLIDE_POWER = [100, 30, 30, 20, 20, 10, 8, 5, 5, 3]


def test_reduction_gives_the_two_shortest_vectors():
    u, v = reduce_basis(np.array([1.0, 0.0]), np.array([5.0, 1.0]))
    np.testing.assert_allclose(u, [1.0, 0.0])
    np.testing.assert_allclose(v, [0.0, 1.0])
    u, v = reduce_basis(np.array([3.0, 1.0]), np.array([7.0, 3.0]))
    assert abs(u @ v) <= 0.5 * (u @ u) and u @ u <= v @ v
    assert abs(u[0] * v[1] - u[1] * v[0]) == pytest.approx(2.0)


def test_fundamental_lattice_despite_the_missing_first_harmonic():
    frequencies, power = peaks_at(GLIDE, GLIDE_POWER)
    fit = index_peaks(frequencies, power, tolerance=TOLERANCE, min_length=1 / 512)
    assert fit.indexed.all()
    assert abs(np.linalg.det(fit.basis)) == pytest.approx(abs(np.linalg.det(RECIPROCAL)), rel=1e-3)
    cell = fabric_cell(np.linalg.inv(fit.basis).T)
    assert np.linalg.norm(cell.wale_vector) == pytest.approx(WALE_PX, rel=1e-3)
    assert np.linalg.norm(cell.course_vector) == pytest.approx(COURSE_PX, rel=1e-3)
    assert math.atan2(cell.wale_vector[1], cell.wale_vector[0]) == pytest.approx(ANGLE, abs=1e-3)
    assert not cell.centred


def test_weak_spurious_peak_is_left_unindexed():
    frequencies, power = peaks_at(GLIDE, GLIDE_POWER)
    stray = (np.array([0.37, 0.52]) @ RECIPROCAL.T)[None, :]
    fit = index_peaks(
        np.vstack([frequencies, stray]),
        np.append(power, 1.0),
        tolerance=TOLERANCE,
        min_length=1 / 512,
    )
    assert fit.indexed[:-1].all() and not fit.indexed[-1]
    assert abs(np.linalg.det(fit.basis)) == pytest.approx(abs(np.linalg.det(RECIPROCAL)), rel=1e-3)


def test_centred_pattern_gives_the_conventional_rectangular_cell():
    # Only n + m even: the peaks generate the centred lattice of the rectangular cell.
    centred = [(1, 1), (-1, 1), (2, 0), (0, 2), (2, 2), (-2, 2), (3, 1), (-3, 1), (1, 3)]
    frequencies, power = peaks_at(centred, [50, 50, 40, 30, 10, 10, 8, 8, 5])
    fit = index_peaks(frequencies, power, tolerance=TOLERANCE, min_length=1 / 512)
    area = abs(np.linalg.det(np.linalg.inv(fit.basis)))
    assert area == pytest.approx(WALE_PX * COURSE_PX / 2, rel=1e-3)
    cell = fabric_cell(np.linalg.inv(fit.basis).T)
    assert cell.centred
    assert np.linalg.norm(cell.wale_vector) == pytest.approx(WALE_PX, rel=1e-3)
    assert np.linalg.norm(cell.course_vector) == pytest.approx(COURSE_PX, rel=1e-3)


def test_square_lattice_keeps_the_cell_closer_to_the_axes():
    angle = math.radians(12.0)
    rotation = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    cell = fabric_cell(rotation @ np.diag([20.0, 20.0]))
    assert not cell.centred
    assert math.degrees(math.atan2(cell.wale_vector[1], cell.wale_vector[0])) == pytest.approx(12)


@pytest.mark.parametrize(
    ("aspect", "angle_deg"),
    [(a, angle) for a in (0.55, 0.565, 0.595) for angle in (-15.0, -3.5, 0.0, 8.0, 15.0)]
    + [(1 / math.sqrt(3), angle) for angle in (-14.0, -3.5, 0.0, 8.0, 14.0)],
)
def test_nearly_hexagonal_centred_lattice_gives_the_rectangular_cell(aspect, angle_deg):
    # A centred lattice with c/w near 1/sqrt(3) has three shortest vectors of about equal
    # length, c and (w/2, +-c/2): three rhombic pairs, of which only ((w/2, +-c/2)) has the
    # fabric's cell (w, c) as its conventional cell (once measured as 0.58 w, 1.74 c); the
    # others' cells are skewed (or, for an exact hexagon, 30 degrees further from the axes).
    angle = math.radians(angle_deg)
    rotation = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    wale, course = 40.0, 40.0 * aspect
    centred = rotation @ np.array([[wale / 2, 0.0], [course / 2, course]])
    cell = fabric_cell(centred)
    assert cell.centred
    assert np.linalg.norm(cell.wale_vector) == pytest.approx(wale, rel=1e-9)
    assert np.linalg.norm(cell.course_vector) == pytest.approx(course, rel=1e-9)
    assert math.degrees(math.atan2(cell.wale_vector[1], cell.wale_vector[0])) == pytest.approx(
        angle_deg, abs=1e-9
    )


def test_stripes_and_scattered_points_form_no_lattice():
    stripes = np.array([[0.05, 0.0], [0.1, 0.0], [0.15, 0.0]])
    with pytest.raises(InputError, match="do not form a lattice"):
        index_peaks(stripes, np.array([3.0, 2.0, 1.0]), tolerance=TOLERANCE, min_length=1 / 512)
    scattered = np.random.default_rng(3).uniform(-0.3, 0.3, (12, 2))
    scattered[:, 1] = np.abs(scattered[:, 1])
    power = np.linspace(12, 1, 12)
    with pytest.raises(InputError, match="do not form a lattice"):
        index_peaks(scattered, power, tolerance=TOLERANCE, min_length=1 / 512)


@pytest.mark.parametrize(("index", "count"), [(1, 1), (2, 3), (4, 7)])
def test_sublattices_of_index_n_are_all_hermite_normal_forms(index, count):
    bases = _sublattices(index)
    assert len(bases) == count  # sigma(n), the number of sublattices of Z^2 of index n
    assert all(round(abs(np.linalg.det(basis))) == index for basis in bases)


def face_photo():
    photo = SyntheticPhoto(
        1.26,
        0.88,
        0.19,
        angle_deg=8.0,
        pixels_per_mm=30.0,
        width_px=160,
        height_px=130,
        noise=0.05,
        seed=2,
    )
    angle = math.radians(photo.angle_deg)
    rotation = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    real = rotation @ np.diag([1.26 * 30.0, 0.88 * 30.0])
    return flatten_illumination(render_photo(photo)), real


def test_true_periods_are_kept():
    contrast, real = face_photo()
    periods = confirm_periods(contrast, real, min_correlation=0.2)
    assert abs(np.linalg.det(periods.basis)) == pytest.approx(abs(np.linalg.det(real)), rel=1e-9)
    assert periods.correlations.min() > 0.5


def test_half_wale_lattice_is_doubled_to_the_true_one():
    contrast, real = face_photo()
    half = real @ np.diag([0.5, 1.0])
    periods = confirm_periods(contrast, half, min_correlation=0.2)
    cell = fabric_cell(periods.basis)
    assert np.linalg.norm(cell.wale_vector) == pytest.approx(1.26 * 30.0, rel=1e-9)
    assert np.linalg.norm(cell.course_vector) == pytest.approx(0.88 * 30.0, rel=1e-9)


@pytest.mark.parametrize(
    "fine",
    [np.diag([0.5, 0.5]), np.array([[0.0, 0.5], [0.5, 0.25]])],
    ids=["half-both", "cyclic-index-4"],
)
def test_lattice_too_fine_by_four_is_coarsened_to_the_true_one(fine):
    # (w/2, c/2), and (0, c/2), (w/2, c/4): a lattice of which 2 v is no period for some v.
    contrast, real = face_photo()
    periods = confirm_periods(contrast, real @ fine, min_correlation=0.2)
    cell = fabric_cell(periods.basis)
    assert np.linalg.norm(cell.wale_vector) == pytest.approx(1.26 * 30.0, rel=1e-9)
    assert np.linalg.norm(cell.course_vector) == pytest.approx(0.88 * 30.0, rel=1e-9)


def test_noise_does_not_repeat():
    noise = np.random.default_rng(0).normal(size=(130, 160))
    with pytest.raises(InputError, match="no periodic structure"):
        confirm_periods(noise, np.diag([30.0, 25.0]), min_correlation=0.2)


def test_lattice_of_harmonics_only_is_refused():
    # A photo of 2.3 courses showed only the peaks (2, 0), (4, 0) and (1, 5); the lattice
    # they generate is finer by index 10, (-w/2, c/10) and (0, c/5), which no coarsening of
    # index 2 or 4 undoes and whose vectors (and their doubles) are no periods. The photo's
    # own best repeat, a true period, shows it.
    contrast, real = face_photo()
    harmonics = real @ np.array([[-0.5, 0.0], [0.1, 0.2]])
    with pytest.raises(InputError, match="best repeat is a shift of") as refusal:
        confirm_periods(contrast, harmonics, min_correlation=0.2)
    # The repeat named is a vector of the true lattice, to the pixel.
    numbers = re.search(r"shift of \((\S+), (\S+)\) px", str(refusal.value)).groups()
    shift = np.array(numbers, dtype=float)
    indices = np.rint(np.linalg.solve(real, shift))
    assert np.any(indices != 0)
    assert np.abs(real @ indices - shift).max() <= 0.5
