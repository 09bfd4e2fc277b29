"""The fabric's lattice from the peaks of its power spectrum: indexing, fit, periods, cell.

The peaks of a periodic texture lie on its reciprocal lattice, but not every lattice point
shows a peak: the single-jersey loop has a glide symmetry (x, y) -> (x + w/2, -y) that makes
the (1, 0) peak vanish (or nearly, under oblique light), and the strongest peak is usually
the (2, 0) harmonic of the two legs of a loop. The fundamental lattice is therefore not "the
two strongest peaks" but the coarsest reciprocal lattice that still indexes nearly all peaks:
candidate basis vectors are the peaks and their differences (every difference of two
lattice points is a lattice vector), each non-parallel pair is reduced and scored, and the
largest reciprocal cell (the smallest real-space cell) that indexes the strongest peaks,
most of the peak power and most of the peaks wins. Its basis is then refined by least
squares over all indexed peaks.

When the odd-order peaks drown (a photo of few loops, blur), the spectrum's lattice is too
fine; `confirm_periods` checks in real space that the photo repeats with it and otherwise
takes the coarser lattice it does repeat with.

A single-jersey lattice is rectangular with one loop per cell, (w, 0) and (0, c) in the
fabric frame. A rhombic lattice is also centred rectangular: when the pattern only looks
centred (e.g. loop heads and sinker loops alike), its conventional rectangular cell
u + v, u - v is the fabric's (`fabric_cell`).
"""

import logging
import math
from typing import NamedTuple

import numpy as np
import scipy.ndimage

from rve_rod.errors import InputError
from rve_rod.imaging.autocorrelation import shift_correlation, strongest_repeat

__all__ = [
    "MIN_INDEXED",
    "FabricCell",
    "LatticeFit",
    "Periods",
    "confirm_periods",
    "fabric_cell",
    "fit_basis",
    "index_peaks",
    "reduce_basis",
    "refit_on",
    "spans_plane",
]

logger = logging.getLogger(__name__)

MIN_INDEXED = 3
"""Fewest peaks a lattice must index: two independent peaks fit any lattice containing them."""

REPEAT_OVERLAP = 0.3
"""Smallest overlap (fraction of the photo) of the shifts searched for the photo's best
repeat: a true period of a photo of 3 x 3 loops overlaps 4/9 of it or more (along a
diagonal), while the correlation over much smaller overlaps scatters by chance."""


class LatticeFit(NamedTuple):
    """A reciprocal lattice fitted to spectral peaks.

    Attributes:
        basis: (2, 2) reciprocal basis vectors b1, b2 as columns (cycles per pixel).
        indices: (K, 2) integer indices (n1, n2) of each peak: f = n1 b1 + n2 b2.
        indexed: (K,) True for the peaks the lattice explains within the tolerance.
        covariance: (4, 4) covariance of basis.ravel() from the fit residuals.
        residual_rms: root-mean-square distance of indexed peaks from their lattice points.
    """

    basis: np.ndarray
    indices: np.ndarray
    indexed: np.ndarray
    covariance: np.ndarray
    residual_rms: float


class FabricCell(NamedTuple):
    """The real-space cell of the fabric in the image frame (X right, Y up).

    Attributes:
        wale_vector: (2,) the lattice vector across the wales, length w, X component > 0.
        course_vector: (2,) the lattice vector along the wales, length c, Y component > 0.
        centred: True when the peaks generated a centred lattice (conventional cell used).
    """

    wale_vector: np.ndarray
    course_vector: np.ndarray
    centred: bool


def reduce_basis(first: np.ndarray, second: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lagrange-Gauss reduction of a 2D lattice basis: (u, v) with |u| <= |v| and
    |u . v| <= |u|^2 / 2, i.e. the two shortest independent lattice vectors."""
    u, v = np.array(first, dtype=float), np.array(second, dtype=float)
    for _ in range(100):
        if u @ u > v @ v:
            u, v = v, u
        shift = round(float(u @ v) / float(u @ u))
        if shift == 0:
            break
        v = v - shift * u
    return u, v


def spans_plane(indices: np.ndarray) -> bool:
    """True if the index vectors (K, 2) contain two independent ones (a basis can be fitted)."""
    return indices.shape[0] >= 2 and np.linalg.matrix_rank(indices) == 2


def fit_basis(frequencies: np.ndarray, indices: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Least-squares basis B with frequencies ~ indices @ B.T: (B, covariance (4, 4), rms).

    The covariance is that of B.ravel() from the residual variance, sigma^2 (N^T N)^-1 for
    each row of B (the x and y components are independent fits).
    """
    indices = np.asarray(indices, dtype=float)
    solution, *_ = np.linalg.lstsq(indices, frequencies, rcond=None)
    basis = solution.T
    residual = frequencies - indices @ basis.T
    count = frequencies.shape[0]
    rms = float(np.sqrt(np.sum(residual**2) / max(count, 1)))
    dof = 2 * count - 4
    if dof <= 0:
        return basis, np.full((4, 4), np.inf), rms
    variance = float(np.sum(residual**2)) / dof
    covariance = np.kron(np.eye(2), variance * np.linalg.pinv(indices.T @ indices))
    return basis, covariance, rms


def index_peaks(
    frequencies: np.ndarray,
    power: np.ndarray,
    *,
    tolerance: float,
    min_length: float,
    power_fraction: float = 0.98,
    count_fraction: float = 0.6,
    max_candidates: int = 30,
) -> LatticeFit:
    """The fundamental reciprocal lattice of the peaks (strongest first), see module docstring.

    Args:
        frequencies: (K, 2) peak positions (cycles per pixel), strongest first.
        power: (K,) peak powers.
        tolerance: largest distance of an indexed peak from its lattice point (cycles/px).
        min_length: shortest admissible reciprocal vector (cycles per pixel).
        power_fraction: share of the total peak power the lattice must index (-).
        count_fraction: share of the peaks the lattice must index (-): a wrong lattice can
            hit the few strongest peaks by chance, hardly most of them.
        max_candidates: number of shortest candidate vectors paired into bases.

    Raises InputError when no lattice indexes the strongest peaks, most of the power and of
    the peaks, and at least MIN_INDEXED of them: the texture is not (visibly) periodic.
    """
    frequencies = np.asarray(frequencies, dtype=float)
    power = np.asarray(power, dtype=float)
    candidates = _candidate_vectors(frequencies, tolerance, min_length, max_candidates)
    admissible: list[tuple[float, float, LatticeFit]] = []
    for i in range(len(candidates)):
        for j in range(i + 1, len(candidates)):
            u, v = candidates[i], candidates[j]
            cross = abs(u[0] * v[1] - u[1] * v[0])
            if cross < 0.2 * np.linalg.norm(u) * np.linalg.norm(v):
                continue
            fit = _index_with(frequencies, np.column_stack(reduce_basis(u, v)), tolerance)
            if fit is None:
                continue
            strongest = fit.indexed[: min(3, fit.indexed.size)]
            explained = power[fit.indexed].sum() / power.sum()
            share = fit.indexed.mean()
            enough = fit.indexed.sum() >= MIN_INDEXED and share >= count_fraction
            if np.all(strongest) and explained >= power_fraction and enough:
                admissible.append((abs(np.linalg.det(fit.basis)), explained, fit))
    if not admissible:
        raise InputError(
            f"no periodic structure: the {frequencies.shape[0]} spectral peaks found "
            "do not form a lattice"
        )
    # Distinct lattices differ in cell area by integer factors >= 2: take the largest
    # reciprocal cell, then the best-explained, tightest fit among bases of that lattice.
    largest = max(area for area, _, _ in admissible)
    same = [
        (explained, -fit.residual_rms, k)
        for k, (area, explained, fit) in enumerate(admissible)
        if area > 0.7 * largest
    ]
    return admissible[max(same)[2]][2]


class Periods(NamedTuple):
    """The real-space lattice the image repeats with, and how well it repeats.

    Attributes:
        basis: (2, 2) lattice vectors a1, a2 as columns (pixels, X right, Y up).
        correlations: (3,) correlation coefficients of the smoothed image with itself
            shifted by a1, a2 and a1 + a2 (1 for a perfectly periodic image; NaN where the
            shifted image overlaps too little).
    """

    basis: np.ndarray
    correlations: np.ndarray


def confirm_periods(
    contrast: np.ndarray,
    real_basis: np.ndarray,
    min_correlation: float,
    ratio: float = 0.7,
    repeat_ratio: float = 0.5,
) -> Periods:
    """The true periods of the image, starting from the spectrum's lattice (2, 2).

    In a small photo the weak odd-order peaks can drown, and the spectrum's lattice is then
    finer than the fabric's (e.g. w/2 from the two legs of a loop). The image is smoothed
    (Gaussian, 1/6 of the shortest period, so that pixel noise does not mask it) and
    correlated with itself shifted by a lattice vector v and by 2 v. The vector passes if
    its correlation is at least `min_correlation`, `ratio` times the larger of that at 2 v
    and the best seen for any vector tried so far (what a true period reaches in this
    photo), and `repeat_ratio` times the photo's best repeat (the highest maximum of its
    autocorrelation over all shifts overlapping REPEAT_OVERLAP of it); it fails if it is
    below either of the latter two. The best repeat makes the check independent of the
    spectrum's lattice: if the spectrum shows only harmonics of the loops (e.g. (2, 0),
    (4, 0) and (1, 5) in a photo of 2.3 courses), its lattice is finer by an index that no
    coarsening below tries, none of its vectors nor their doubles is a period, and they
    correlate alike (about 0.3), but the photo's own period correlates near 1. Its ratio is
    the lower one because it is the maximum over many shifts, which noise biases upwards
    (a true lattice vector of a noisy photo reached 0.71 of it, a harmonic lattice's 0.32).

    A lattice passes if two of its vectors a1, a2, a1 + a2 pass (noise can make one vector
    of the right lattice fail marginally; a lattice too fine by index 2 fails on two). The
    spectrum's lattice is kept if it passes. If two of its vectors fail, its coarser
    lattices of index 2, then 4 (Hermite normal forms) are all correlated, then judged; the
    first index with a passing lattice gives it (of several, the one with the best median
    ratio). Anything else raises
    InputError: the photo does not show whether (or with what) it repeats.
    """
    basis = np.array(real_basis, dtype=float)
    shortest = min(np.linalg.norm(basis[:, 0]), np.linalg.norm(basis[:, 1]))
    smooth = scipy.ndimage.gaussian_filter(contrast, shortest / 6.0)
    repeat = strongest_repeat(smooth, REPEAT_OVERLAP)
    floor = repeat_ratio * repeat.correlation if repeat is not None else -np.inf
    correlation_of: dict[tuple[float, float], float] = {}

    def correlation(vector: np.ndarray) -> float:
        key = (round(float(vector[0]), 6), round(float(vector[1]), 6))
        if key not in correlation_of:
            correlation_of[key] = shift_correlation(smooth, vector)
        return correlation_of[key]

    def evaluate(coarse: np.ndarray):
        u, v = reduce_basis(*(basis @ coarse).T)
        vectors = (u, v, u + v)
        values = np.array([correlation(vector) for vector in vectors])
        references = np.array([correlation(2.0 * vector) for vector in vectors])
        return np.column_stack([u, v]), values, references

    def judge(values: np.ndarray, references: np.ndarray):
        # What a true period reaches in this photo: the best correlation of any shift tried.
        # (Of a lattice too fine by index 2 or 4, one of 2 u, 2 v, 2 (u + v) is a period.)
        reference = np.fmax(references, np.nanmax(list(correlation_of.values())))
        threshold = np.fmax(ratio * reference, floor)
        # NaN (too little overlap) compares False: such a vector neither passes nor fails.
        passed = (values >= threshold) & (values >= min_correlation)
        return passed, values < threshold, reference

    spectral, spectral_values, references = evaluate(np.eye(2, dtype=int))
    passed, failed, _ = judge(spectral_values, references)
    if np.count_nonzero(passed) >= 2:
        return Periods(spectral, spectral_values)
    if np.count_nonzero(failed) < 2:
        raise InputError(
            "no periodic structure: the photo hardly repeats with the lattice vectors of its "
            f"spectrum (correlations {_listing(spectral_values)}, at least "
            f"{min_correlation:g} needed)"
        )
    for index in (2, 4):
        candidates = [evaluate(coarse) for coarse in _sublattices(index)]
        passing = []
        for candidate, values, references in candidates:
            passed, _, reference = judge(values, references)
            if np.count_nonzero(passed) >= 2:
                passing.append((np.median(values / np.maximum(reference, 1e-3)), candidate, values))
        if passing:
            logger.info("the photo repeats with a cell %d times the spectrum's", index)
            _, chosen, values = max(passing, key=lambda item: item[0])
            return Periods(chosen, values)
    best = ""
    if repeat is not None:
        shift = ", ".join(f"{component:.0f}" for component in repeat.shift)
        best = (
            f"; its best repeat is a shift of ({shift}) px (correlation {repeat.correlation:.2f})"
        )
    raise InputError(
        "no periodic structure: the photo does not repeat with the lattice of its spectrum "
        f"(correlations {_listing(spectral_values)}) nor with one of 2 or 4 times its cell{best}"
    )


def _listing(values: np.ndarray) -> str:
    return ", ".join(f"{value:.2f}" for value in values)


def _sublattices(index: int) -> list[np.ndarray]:
    """Integer bases (2, 2) (columns) of all sublattices of Z^2 of the given index.

    Hermite normal forms [[a, b], [0, d]] with a d = index and 0 <= b < a.
    """
    bases = []
    for a in range(1, index + 1):
        if index % a == 0:
            d = index // a
            bases.extend(np.array([[a, b], [0, d]]) for b in range(a))
    return bases


def refit_on(frequencies: np.ndarray, fit: LatticeFit, real_basis: np.ndarray) -> LatticeFit:
    """The fit re-expressed on a real-space lattice (2, 2) contained in the fitted one (the
    same lattice in another basis, or a coarser one from `confirm_periods`).

    The peaks the fit indexed stay indexed (a finer reciprocal lattice contains the old
    one); their indices change to the new basis and the basis is refitted to them.
    """
    reciprocal = np.linalg.inv(real_basis).T
    lattice_points = fit.indices @ fit.basis.T
    indices = np.rint(np.linalg.solve(reciprocal, lattice_points.T).T).astype(int)
    basis, covariance, rms = fit_basis(frequencies[fit.indexed], indices[fit.indexed])
    return LatticeFit(basis, indices, fit.indexed, covariance, rms)


def fabric_cell(
    real_basis: np.ndarray, rhombic_tolerance: float = 0.03, skew_tolerance_deg: float = 0.5
) -> FabricCell:
    """The wale and course vectors of a real-space lattice basis (2, 2) (columns, pixels).

    The reduced basis (u, v) is used; the wale vector is the one closer to the image X axis
    (photos must show the wales within 45 degrees of vertical). A rhombic lattice (two
    basis vectors p, q with |p| = |q| within `rhombic_tolerance`) is also centred
    rectangular, with the conventional cell (p + q, p - q) along its diagonals. The pairs
    tried are those among the three shortest lattice vectors u, v and u - v (or u + v, the
    shorter): a centred lattice whose cell has c/w near 1/sqrt(3) (the Vassiliadis
    sample's 0.58) is nearly hexagonal, all three have about the same length, and each of
    the three rhombic pairs has its own conventional cell, 60 degrees apart.

    The single-jersey cell is rectangular: of the primitive and the conventional cells,
    those within `skew_tolerance_deg` of the least skewed are kept (the pairs only nearly
    equal in length give cells skewed by about 0.65 degree per 1 % of length difference),
    and of these the one whose courses lie closest to the X axis is taken. For a
    near-square cell this needs the wales within 22.5 degrees of vertical, for a cell
    with c/w within 1 % of 1/sqrt(3) within 15 degrees.
    """
    u, v = reduce_basis(real_basis[:, 0], real_basis[:, 1])
    third = u - v if np.linalg.norm(u - v) <= np.linalg.norm(u + v) else u + v
    cells = [_oriented(u, v, centred=False)]
    for p, q in ((u, v), (u, third), (v, third)):
        lengths = np.linalg.norm(p), np.linalg.norm(q)
        if abs(lengths[0] - lengths[1]) <= rhombic_tolerance * max(lengths):
            cells.append(_oriented(p + q, p - q, centred=True))
    skews = [_skew_deg(cell) for cell in cells]
    rectangular = [
        cell
        for cell, skew in zip(cells, skews, strict=True)
        if skew <= min(skews) + skew_tolerance_deg
    ]
    # The first of equally aligned cells: the primitive one unless a conventional one is better.
    return min(rectangular, key=lambda cell: abs(_angle(cell.wale_vector)))


def _skew_deg(cell: FabricCell) -> float:
    """Deviation (degrees) of the angle between the cell's vectors from 90 degrees."""
    wale, course = cell.wale_vector, cell.course_vector
    cosine = wale @ course / (np.linalg.norm(wale) * np.linalg.norm(course))
    return abs(math.degrees(math.asin(np.clip(cosine, -1.0, 1.0))))


def _oriented(first: np.ndarray, second: np.ndarray, centred: bool) -> FabricCell:
    """The cell with the vector closer to the X axis as wale vector, both signs fixed."""
    if abs(_angle(first if first[0] >= 0 else -first)) > abs(
        _angle(second if second[0] >= 0 else -second)
    ):
        first, second = second, first
    wale = first if first[0] > 0 else -first
    course = second if second[1] > 0 else -second
    return FabricCell(wale_vector=wale, course_vector=course, centred=centred)


def _angle(vector: np.ndarray) -> float:
    return float(np.arctan2(vector[1], vector[0]))


def _candidate_vectors(
    frequencies: np.ndarray, tolerance: float, min_length: float, count: int
) -> list[np.ndarray]:
    """Peaks and pairwise differences (one sign), merged within tolerance; shortest first.

    Of vectors closer than the tolerance the one made of the stronger peaks is kept (the
    peaks are ordered strongest first), as its position is the more precise.
    """
    total = frequencies.shape[0]
    first, second = np.triu_indices(total, k=1)
    vectors = np.vstack([frequencies, frequencies[first] - frequencies[second]])
    weakest = np.concatenate([np.arange(total), second])
    vectors = vectors[np.argsort(weakest, kind="stable")]
    flip = (vectors[:, 1] < 0) | ((vectors[:, 1] == 0) & (vectors[:, 0] < 0))
    vectors[flip] *= -1.0
    lengths = np.linalg.norm(vectors, axis=1)
    # The reduced basis is no longer than the strongest few peaks.
    longest = np.linalg.norm(frequencies[: min(6, total)], axis=1).max()
    vectors = vectors[(lengths >= min_length) & (lengths <= longest + tolerance)]
    kept: list[np.ndarray] = []
    for vector in vectors:
        if all(
            min(np.linalg.norm(vector - other), np.linalg.norm(vector + other)) > tolerance
            for other in kept
        ):
            kept.append(vector)
    kept.sort(key=lambda vector: float(np.linalg.norm(vector)))
    return kept[:count]


def _index_with(frequencies: np.ndarray, basis: np.ndarray, tolerance: float) -> LatticeFit | None:
    """Index the peaks with `basis` and refit it; None if the indexed peaks are degenerate.

    The candidate basis is made of peak differences and carries their errors, which grow
    with the order of a lattice point: it is first refitted on the lowest orders that span
    the plane (within twice the tolerance), then on all peaks within the tolerance.
    """
    indices = np.rint(np.linalg.solve(basis, frequencies.T).T).astype(int)
    distance = np.linalg.norm(frequencies - indices @ basis.T, axis=1)
    near = (distance <= 2.0 * tolerance) & np.any(indices != 0, axis=1)
    order = np.abs(indices).max(axis=1)
    for max_order in np.unique(order[near]):
        low = near & (order <= max(max_order, 2))
        if spans_plane(indices[low]):
            break
    else:
        return None
    basis, covariance, rms = fit_basis(frequencies[low], indices[low])
    for _ in range(2):
        indices = np.rint(np.linalg.solve(basis, frequencies.T).T).astype(int)
        distance = np.linalg.norm(frequencies - indices @ basis.T, axis=1)
        indexed = (distance <= tolerance) & np.any(indices != 0, axis=1)
        if not spans_plane(indices[indexed]):
            return None
        basis, covariance, rms = fit_basis(frequencies[indexed], indices[indexed])
    return LatticeFit(basis, indices, indexed, covariance, rms)
