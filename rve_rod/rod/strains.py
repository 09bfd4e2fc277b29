"""The rod's strain measures, section forces and equilibrium residual in plain NumPy.

The readable form of what the collocation kernel (`rve_rod.rod._kernels.collocation_equations`)
evaluates, and the reference its tests compare it with. Simo-Reissner rod (docs/rod.md), with
' = d/du (u the curve parameter), s the reference arc length (ds = J du):

    gamma = R^T r',  k = 2/|q|^2 vec(conj(q) q')           (material stretch-shear, curvature)
    Gamma = (gamma - g0) / J,  K = (k - k0) / J              (strains per reference arc length)
    N = A Gamma,  M = C K,  n = R N,  m = R M                (material and spatial section forces)
    residual = (n' / J, (m' + r' x n) / J, |q|^2 - 1)        (force, moment balance, gauge)

Here the balance is written in spatial form, n' = R' N + R N' with R' = R [k]x, a different
route from the kernel's material form. Arrays are components first, collocation points last;
every function works on complex arrays, so the complex step differentiates it exactly. The
layout of `kinematics` (18, m) and `reference` (14, m) is the kernel's (`_kernels` docstring).
"""

from typing import NamedTuple

import numpy as np

from rve_rod.rod import quaternion

__all__ = [
    "Strains",
    "collocation_equations",
    "strains",
]


class Strains(NamedTuple):
    """Strain measures at m collocation points and their derivatives d/du.

    Attributes:
        rotation, rotation_rate: (3, 3, m) R and R' = R [k]x.
        stretch, stretch_rate: (3, m) Gamma = (gamma - g0) / J (-) and d/du.
        bending, bending_rate: (3, m) K = (k - k0) / J (1/mm) and d/du.
    """

    rotation: np.ndarray
    rotation_rate: np.ndarray
    stretch: np.ndarray
    stretch_rate: np.ndarray
    bending: np.ndarray
    bending_rate: np.ndarray


def strains(kinematics: np.ndarray, reference: np.ndarray) -> Strains:
    """Strains from the local variables (18, m) and the reference data (14, m)."""
    ru, ruu = kinematics[0:3], kinematics[3:6]
    q, qd, qdd = kinematics[6:10], kinematics[10:14], kinematics[14:18]
    g0, g0u, k0, k0u = reference[0:3], reference[3:6], reference[6:9], reference[9:12]
    jac, jac_u = reference[12], reference[13]
    rotation = quaternion.rotation_matrix(q.T).transpose(1, 2, 0)
    k = quaternion.curvature(q.T, qd.T).T
    k_u = quaternion.curvature_rate(q.T, qd.T, qdd.T).T
    rotation_rate = np.einsum("ijm,jkm->ikm", rotation, quaternion.skew(k.T).transpose(1, 2, 0))
    gamma = np.einsum("jim,jm->im", rotation, ru)
    gamma_u = np.einsum("jim,jm->im", rotation_rate, ru) + np.einsum("jim,jm->im", rotation, ruu)
    stretch = (gamma - g0) / jac
    bending = (k - k0) / jac
    return Strains(
        rotation=rotation,
        rotation_rate=rotation_rate,
        stretch=stretch,
        stretch_rate=(gamma_u - g0u) / jac - stretch * jac_u / jac,
        bending=bending,
        bending_rate=(k_u - k0u) / jac - bending * jac_u / jac,
    )


def collocation_equations(
    kinematics: np.ndarray, reference: np.ndarray, stiffness: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Residual (7, m) without external loads and spatial section forces (n, m) (6, m).

    Args:
        kinematics: (18, m) local variables r', r'', q, q', q''.
        reference: (14, m) g0, g0', k0, k0', J, J'.
        stiffness: (6, m) diag(A) (N) and diag(C) (N mm^2).
    """
    rot, rot_u, strain, strain_u, bend, bend_u = strains(kinematics, reference)
    jac = reference[12]
    big_n, big_nu = stiffness[:3] * strain, stiffness[:3] * strain_u
    big_m, big_mu = stiffness[3:] * bend, stiffness[3:] * bend_u
    n = np.einsum("ijm,jm->im", rot, big_n)
    m = np.einsum("ijm,jm->im", rot, big_m)
    n_u = np.einsum("ijm,jm->im", rot_u, big_n) + np.einsum("ijm,jm->im", rot, big_nu)
    m_u = np.einsum("ijm,jm->im", rot_u, big_m) + np.einsum("ijm,jm->im", rot, big_mu)
    q = kinematics[6:10]
    gauge = np.sum(q * q, axis=0) - 1.0
    residual = np.concatenate(
        [n_u / jac, (m_u + np.cross(kinematics[0:3], n, axis=0)) / jac, gauge[None]], axis=0
    )
    return residual, np.concatenate([n, m], axis=0)
