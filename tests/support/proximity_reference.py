"""The clearance search's kernels as plain NumPy/SciPy: the references the compiled
`rve_rod.geometry._kernels` are checked against (the library's implementations before the
kernels)."""

import numpy as np
import scipy.spatial

from rve_rod.geometry import proximity
from rve_rod.geometry.bspline import basis_functions


def _evaluate(chain, s: np.ndarray, order: int = 0) -> np.ndarray:
    """Points of a `proximity._Chain` at s and their derivatives up to `order`."""
    basis = basis_functions(chain.knots, chain.degree, s - np.floor(s), order)
    return chain.evaluate(s, basis)


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
        return np.linalg.norm(
            _evaluate(first, at_s)[0] - _evaluate(second, at_t)[0] - shift, axis=1
        )

    s, t = s.astype(float), t.astype(float)
    current = distance(s, t, offsets)
    limit = 4.0 / proximity._SAMPLES_PER_CURVE
    active = np.ones(k, dtype=bool)
    for _ in range(proximity._NEWTON_ITERATIONS):
        if not active.any():
            break
        values = np.concatenate([_evaluate(first, s, 2), _evaluate(second, t, 2)], axis=1)
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
