"""The geometry's kernels as plain NumPy/SciPy: the references the compiled
`rve_rod.geometry._kernels` are checked against (the library's implementations before the
kernels: B-spline basis functions, the clearance search's nearest samples and refinement)."""

import numpy as np
import scipy.spatial

from rve_rod.geometry import proximity
from rve_rod.geometry.bspline import BasisValues, find_spans


def basis_functions_reference(
    knots: np.ndarray, degree: int, params: np.ndarray, derivatives: int = 0
) -> BasisValues:
    """`rve_rod.geometry.bspline.basis_functions` vectorized over the parameters (A2.3; loops
    over the degree only). Returns BasisValues with values (derivatives+1, m, degree+1)."""
    p = degree
    params = np.atleast_1d(np.asarray(params, dtype=float))
    spans = find_spans(knots, p, params)
    m = params.size
    # ndu[:, j, r] for r >= j holds basis values N_{r,j} (upper triangle, A2.2) and for r < j
    # the knot differences used by the derivative recursion (lower triangle).
    ndu = np.empty((m, p + 1, p + 1))
    ndu[:, 0, 0] = 1.0
    left = np.empty((m, p + 1))
    right = np.empty((m, p + 1))
    for j in range(1, p + 1):
        left[:, j] = params - knots[spans + 1 - j]
        right[:, j] = knots[spans + j] - params
        saved = np.zeros(m)
        for r in range(j):
            ndu[:, j, r] = right[:, r + 1] + left[:, j - r]
            temp = ndu[:, r, j - 1] / ndu[:, j, r]
            ndu[:, r, j] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        ndu[:, j, j] = saved
    values = np.zeros((derivatives + 1, m, p + 1))
    values[0] = ndu[:, :, p]
    a = np.empty((2, m, p + 1))
    for r in range(p + 1):
        s1, s2 = 0, 1
        a[0, :, 0] = 1.0
        for k in range(1, min(derivatives, p) + 1):
            d = np.zeros(m)
            rk, pk = r - k, p - k
            if r >= k:
                a[s2, :, 0] = a[s1, :, 0] / ndu[:, pk + 1, rk]
                d = a[s2, :, 0] * ndu[:, rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = k - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[s2, :, j] = (a[s1, :, j] - a[s1, :, j - 1]) / ndu[:, pk + 1, rk + j]
                d = d + a[s2, :, j] * ndu[:, rk + j, pk]
            if r <= pk:
                a[s2, :, k] = -a[s1, :, k - 1] / ndu[:, pk + 1, r]
                d = d + a[s2, :, k] * ndu[:, r, pk]
            values[k, :, r] = d
            s1, s2 = s2, s1
    factor = float(p)
    for k in range(1, min(derivatives, p) + 1):
        values[k] *= factor
        factor *= p - k
    return BasisValues(spans=spans, values=values)


def nearest_reference(samples, offset, shift, adjacent_arc):
    """(distances, partners) of `_kernels.nearest_samples`: the row minima of the full matrix
    cdist(first, second + offset), the pairs closer than `adjacent_arc` along the yarn set to
    inf, and their first indices (numpy.argmin)."""
    distances = scipy.spatial.distance.cdist(samples.first, samples.second + offset)
    along = np.abs(samples.first_arcs[:, None] - (samples.second_arcs[None, :] + shift))
    distances[along < adjacent_arc] = np.inf
    return distances.min(axis=1), np.argmin(distances, axis=1)


def refine_reference(
    first, second, s: np.ndarray, t: np.ndarray, offsets: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local minima of |X(s) - Y(t) - offset| near each pair (s, t), X on the chain `first`,
    Y on `second` (`proximity._Chain`s), offsets (k, 3) (mm): `proximity._refine`'s
    saddle-free Newton method, vectorized over the pairs. Returns (distances, s, t)."""
    k = s.size

    def distance(at_s: np.ndarray, at_t: np.ndarray, shift: np.ndarray) -> np.ndarray:
        return np.linalg.norm(first.evaluate(at_s)[0] - second.evaluate(at_t)[0] - shift, axis=1)

    s, t = s.astype(float), t.astype(float)
    current = distance(s, t, offsets)
    limit = 4.0 / proximity._SAMPLES_PER_CURVE
    active = np.ones(k, dtype=bool)
    for _ in range(proximity._NEWTON_ITERATIONS):
        if not active.any():
            break
        values = np.concatenate([first.evaluate(s, 2), second.evaluate(t, 2)], axis=1)
        d = values[0, :k] - values[0, k:] - offsets
        xs, xt = values[1, :k], values[1, k:]
        gradient = np.stack([np.sum(d * xs, 1), -np.sum(d * xt, 1)], axis=1)
        hessian = np.empty((k, 2, 2))
        hessian[:, 0, 0] = np.sum(xs * xs, 1) + np.sum(d * values[2, :k], 1)
        hessian[:, 1, 1] = np.sum(xt * xt, 1) - np.sum(d * values[2, k:], 1)
        hessian[:, 0, 1] = hessian[:, 1, 0] = -np.sum(xs * xt, 1)
        # Newton's step with the Hessian's eigenvalues replaced by their magnitudes: the same
        # where the distance is convex, and a descent step that follows the negative
        # curvature where it is not (a yarn wrapping around another at about the distance
        # gives long, curved valleys in which steepest descent crawls)
        curvature, axes = np.linalg.eigh(hessian)
        magnitude = np.maximum(np.abs(curvature), 1e-12 * np.abs(curvature).max(1, keepdims=True))
        along = np.einsum("kji,kj->ki", axes, gradient) / np.maximum(magnitude, 1e-300)
        step = -np.einsum("kij,kj->ki", axes, along)
        largest = np.abs(step).max(axis=1)
        step *= np.minimum(1.0, limit / np.maximum(largest, 1e-300))[:, None]
        step[~active] = 0.0
        trial = distance(s + step[:, 0], t + step[:, 1], offsets)
        for _ in range(6):  # halve the steps that do not decrease the distance
            worse = active & (trial > current)
            if not worse.any():
                break
            step[worse] *= 0.5
            trial[worse] = distance(
                s[worse] + step[worse, 0], t[worse] + step[worse, 1], offsets[worse]
            )
        accepted = active & (trial <= current)
        improvement = np.where(accepted, current - trial, 0.0)
        s, t = s + np.where(accepted, step[:, 0], 0.0), t + np.where(accepted, step[:, 1], 0.0)
        current = np.where(accepted, trial, current)
        active = accepted & (np.abs(step).max(axis=1) > 1e-12) & (improvement > 1e-15 * current)
    return current, s, t
