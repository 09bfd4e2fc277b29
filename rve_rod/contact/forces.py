"""Contact line loads at the slave points and their derivatives (vectorized over contacts).

Notation per contact (arrays components first, contacts last): x_s the slave collocation
point, x_m = C(tau) + F L the closest master point (L the reference lattice shift of its
image), C' = dC/dtau and C'' at tau, v = x_s - x_m, d = |v|, n = v / d (from master to slave),
g = 2r - d the penetration, H = C'.C' - C''.v > 0 (the stationarity curvature). Closest-point
stationarity C'.v = 0 gives the parameter sensitivity

    dtau = [v.dC' + C'.(dx_s - dx_m)] / H,   dv = Q (dx_s - dx_m) - C' v.dC' / H,
    Q = I - C' C'^T / H,   dd = n.(dx_s - dx_m),   dn = (I - n n^T) dv / d.

Each load derivative is returned as 3x3 blocks with respect to x_s, x_m (at fixed tau),
C'(tau) (at fixed tau) and the friction anchor x_a; the caller chains them with the basis
functions of the control points (and with F through x_m and x_a).
"""

from typing import NamedTuple

import numpy as np

from rve_rod.contact.law import CompressibleYarnLaw, CoulombFriction

_IDENTITY = np.eye(3)[:, :, None]


class Kinematics(NamedTuple):
    """Closest-point kinematics of k contacts.

    Attributes:
        gap_vector: (3, k) v = x_s - x_m (mm).
        distance: (k,) d (mm).
        normal: (3, k) n = v / d.
        tangent: (3, k) C' = dC/dtau at the closest point (mm).
        metric: (k,) H = C'.C' - C''.v (mm^2), > 0 at a minimum of the distance.
    """

    gap_vector: np.ndarray
    distance: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray
    metric: np.ndarray


class LoadBlocks(NamedTuple):
    """Line loads on k slave points and their derivative blocks (3, 3, k).

    Attributes:
        load: (3, k) line load (N/mm).
        slave, master, tangent, anchor: derivatives of the load w.r.t. x_s, x_m, C'(tau)
            and the friction anchor x_a (N/mm^2; `tangent` in N/mm^2 per unit of C').
    """

    load: np.ndarray
    slave: np.ndarray
    master: np.ndarray
    tangent: np.ndarray
    anchor: np.ndarray


class FrictionState(NamedTuple):
    """Friction of k contacts after the return mapping.

    Attributes:
        load: (3, k) friction line load f_t (N/mm), tangential to the contact.
        sliding: (k,) True where |k_t g_T| exceeded mu f_n (slip), False in stick.
        elastic_slip: (3, k) g_e = -f_t / k_t, the slip the anchor keeps (mm).
    """

    load: np.ndarray
    sliding: np.ndarray
    elastic_slip: np.ndarray


def kinematics(
    slave: np.ndarray, master: np.ndarray, tangent: np.ndarray, curvature: np.ndarray
) -> Kinematics:
    """Kinematics from slave points, closest points, dC/dtau and d2C/dtau2, all (3, k)."""
    gap_vector = slave - master
    distance = np.linalg.norm(gap_vector, axis=0)
    normal = gap_vector / distance
    metric = np.einsum("ck,ck->k", tangent, tangent) - np.einsum("ck,ck->k", curvature, gap_vector)
    return Kinematics(gap_vector, distance, normal, tangent, metric)


def normal_loads(state: Kinematics, law: CompressibleYarnLaw) -> tuple[np.ndarray, LoadBlocks]:
    """Normal line loads f_n(g) n and their derivatives; returns (f_n (k,), blocks).

    d(f_n n) = K (dx_s - dx_m) - (f_n / H) C' n^T dC' with
    K = -f_n'(g) n n^T + (f_n / d)(I - n n^T) - f_n / (d H) C' C'^T.
    """
    n, d, tangent, metric = state.normal, state.distance, state.tangent, state.metric
    penetration = 2.0 * law.yarn_radius - d
    force = law.line_load(penetration)
    slope = law.line_stiffness(penetration)
    nn = _outer(n, n)
    stiffness = (
        -slope * nn
        + (force / d) * (_IDENTITY - nn)
        - (force / (d * metric)) * _outer(tangent, tangent)
    )
    blocks = LoadBlocks(
        load=force * n,
        slave=stiffness,
        master=-stiffness,
        tangent=-(force / metric) * _outer(tangent, n),
        anchor=np.zeros_like(stiffness),
    )
    return force, blocks


def friction_loads(
    state: Kinematics,
    normal_force: np.ndarray,
    normal_slope: np.ndarray,
    slip_vector: np.ndarray,
    friction: CoulombFriction,
) -> tuple[FrictionState, LoadBlocks]:
    """Friction line loads by the return mapping, and their consistent derivatives.

    Args:
        state: kinematics of the k contacts.
        normal_force, normal_slope: (k,) f_n and df_n/dg.
        slip_vector: (3, k) w = x_s - x_a - o: the slave point relative to its stick anchor
            (anchor point x_a on the master, offset o); the slip is g_T = (I - n n^T) w.
        friction: mu and k_t.

    Stick (|k_t g_T| <= mu f_n): f_t = -k_t g_T. Slip: f_t = mu f_n t with t = -g_T / |g_T|.
    """
    n, d, tangent, metric, v = (
        state.normal,
        state.distance,
        state.tangent,
        state.metric,
        state.gap_vector,
    )
    k_t, mu = friction.tangential_stiffness, friction.coefficient
    projector = _IDENTITY - _outer(n, n)
    normal_part = np.einsum("ck,ck->k", n, slip_vector)
    slip = slip_vector - normal_part * n
    # dg_T = P dw + G dv with G = -[(n.w) P + n g_T^T] / d.
    g_matrix = -(normal_part * projector + _outer(n, slip)) / d
    q_matrix = _IDENTITY - _outer(tangent, tangent) / metric
    gq = _matmul(g_matrix, q_matrix)
    d_slave = projector + gq
    d_master = -gq
    d_tangent = -_outer(np.einsum("ijk,jk->ik", g_matrix, tangent), v) / metric
    d_anchor = -projector

    trial = -k_t * slip
    trial_norm = np.linalg.norm(trial, axis=0)
    limit = mu * normal_force
    sliding = trial_norm > limit
    scale = np.where(sliding, limit / np.where(sliding, trial_norm, 1.0), 1.0)
    load = scale * trial
    # Stick: df_t = -k_t dg_T. Slip: df_t = mu f_n' t dg + mu f_n / |trial| (I - t t^T) dtrial.
    direction = trial / np.where(trial_norm > 0.0, trial_norm, 1.0)
    tangential = -k_t * scale * (_IDENTITY - sliding * _outer(direction, direction))
    normal_term = np.where(sliding, -mu * normal_slope, 0.0) * _outer(direction, n)
    blocks = LoadBlocks(
        load=load,
        slave=_matmul(tangential, d_slave) + normal_term,
        master=_matmul(tangential, d_master) - normal_term,
        tangent=_matmul(tangential, d_tangent),
        anchor=_matmul(tangential, d_anchor),
    )
    return FrictionState(load=load, sliding=sliding, elastic_slip=-load / k_t), blocks


def _outer(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, None, :] * b[None, :, :]


def _matmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("ijk,jlk->ilk", a, b)
