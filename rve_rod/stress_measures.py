"""Membrane strain and stress measures: Green-Lagrange E and second Piola-Kirchhoff S from (F, P).

The RVE prescribes the in-plane deformation gradient F and measures the first Piola-Kirchhoff
stress P (force per undeformed width, N/mm); the response surfaces are laws S(E). With
P = F S (design.md), S = F^-1 P and E = (F^T F - I) / 2. Arrays carry any leading batch shape
and end in (2, 2); Voigt vectors end in 3 = (11, 22, 12) with the tensor shear component.
"""

from typing import NamedTuple

import numpy as np

from rve_rod.errors import InputError

__all__ = [
    "MembraneState",
    "green_lagrange",
    "membrane_state",
    "second_piola_kirchhoff",
    "voigt",
]


class MembraneState(NamedTuple):
    """Strain and stress of m states in Voigt order.

    Attributes:
        E: (..., 3) Green-Lagrange strain (E11, E22, E12), dimensionless.
        S: (..., 3) second Piola-Kirchhoff stress (S11, S22, S12) in N/mm, symmetrized:
            S12 = (S_12 + S_21) / 2.
        asymmetry: (...,) |S_12 - S_21| in N/mm: zero when the moment balance of the RVE
            holds; a measure of how far the measured P is from an equilibrium state.
    """

    E: np.ndarray
    S: np.ndarray
    asymmetry: np.ndarray


def _check_tensors(name: str, tensor: np.ndarray) -> np.ndarray:
    tensor = np.asarray(tensor, dtype=float)
    if tensor.ndim < 2 or tensor.shape[-2:] != (2, 2):
        raise InputError(f"{name} must have shape (..., 2, 2), got {tensor.shape}")
    if not np.all(np.isfinite(tensor)):
        raise InputError(f"{name} must be finite")
    return tensor


def green_lagrange(F: np.ndarray) -> np.ndarray:
    """E = (F^T F - I) / 2 for F of shape (..., 2, 2)."""
    F = _check_tensors("F", F)
    return 0.5 * (np.swapaxes(F, -1, -2) @ F - np.eye(2))


def second_piola_kirchhoff(F: np.ndarray, P: np.ndarray) -> np.ndarray:
    """S = F^-1 P for F, P of shape (..., 2, 2) (not symmetrized)."""
    F = _check_tensors("F", F)
    P = _check_tensors("P", P)
    determinant = np.linalg.det(F)
    if np.any(determinant <= 0.0):
        raise InputError(f"F must have det F > 0, got min det F = {determinant.min():.6g}")
    return np.linalg.solve(F, P)


def voigt(tensor: np.ndarray) -> np.ndarray:
    """(T11, T22, (T12 + T21) / 2) of (..., 2, 2) tensors, shape (..., 3)."""
    tensor = _check_tensors("tensor", tensor)
    shear = 0.5 * (tensor[..., 0, 1] + tensor[..., 1, 0])
    return np.stack([tensor[..., 0, 0], tensor[..., 1, 1], shear], axis=-1)


def membrane_state(F: np.ndarray, P: np.ndarray) -> MembraneState:
    """E and symmetrized S (Voigt) of states given by F and P (..., 2, 2)."""
    S = second_piola_kirchhoff(F, P)
    return MembraneState(
        E=voigt(green_lagrange(F)), S=voigt(S), asymmetry=np.abs(S[..., 0, 1] - S[..., 1, 0])
    )
