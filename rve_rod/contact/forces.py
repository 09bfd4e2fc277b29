"""Contact line loads at the slave points and their derivatives.

Notation per contact (arrays components first, contacts last): x_s the slave collocation
point, x_m = C(tau) + F L the closest master point (L the reference lattice shift of its
image), C' = dC/dtau and C'' at tau, v = x_s - x_m, d = |v|, n = v / d (from master to slave),
g = 2r - d the penetration, H = C'.C' - C''.v > 0 (the stationarity curvature). Closest-point
stationarity C'.v = 0 gives the parameter sensitivity

    dtau = [v.dC' + C'.(dx_s - dx_m)] / H,   dv = Q (dx_s - dx_m) - C' v.dC' / H,
    Q = I - C' C'^T / H,   dd = n.(dx_s - dx_m),   dn = (I - n n^T) dv / d.

The normal line load f_n(g) and its slope come from the law
(`CompressibleYarnLaw.load_and_slope`), evaluated here on the penetrations; the kernel takes
them as arrays. Each load derivative is returned as 3x3 blocks with respect to x_s, x_m (at
fixed tau), C'(tau) (at fixed tau) and the friction anchor x_a (`_kernels.contact_loads`); the
caller chains them with the basis functions of the control points (and with F through x_m,
x_a).
"""

from typing import NamedTuple

import numpy as np

from rve_rod.contact import _kernels
from rve_rod.contact.law import CompressibleYarnLaw, CoulombFriction

__all__ = [
    "ANCHOR",
    "MASTER",
    "SLAVE",
    "TANGENT",
    "ContactLoads",
    "Kinematics",
    "contact_loads",
    "kinematics",
]

SLAVE, MASTER, TANGENT, ANCHOR = range(4)
"""Order of the derivative blocks: w.r.t. x_s, x_m, C'(tau) and the anchor x_a."""


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


class ContactLoads(NamedTuple):
    """Line loads of k contacts and their derivatives.

    Attributes:
        load: (3, k) total line load f_n n + f_t on the slave point (N/mm).
        normal_force: (k,) f_n (N/mm).
        friction_load: (3, k) f_t (N/mm), zero without an anchor.
        sliding: (k,) True where the return mapping slipped.
        elastic_slip: (3, k) g_e = -f_t / k_t, the slip an anchor keeps (mm).
        blocks: (4, 3, 3, k) d load / d (x_s, x_m, C', x_a) in the order SLAVE, MASTER,
            TANGENT, ANCHOR (N/mm^2).
    """

    load: np.ndarray
    normal_force: np.ndarray
    friction_load: np.ndarray
    sliding: np.ndarray
    elastic_slip: np.ndarray
    blocks: np.ndarray


def kinematics(
    slave: np.ndarray, master: np.ndarray, tangent: np.ndarray, curvature: np.ndarray
) -> Kinematics:
    """Kinematics from slave points, closest points, dC/dtau and d2C/dtau2, all (3, k)."""
    gap_vector = slave - master
    distance = np.linalg.norm(gap_vector, axis=0)
    normal = gap_vector / distance
    metric = np.einsum("ck,ck->k", tangent, tangent) - np.einsum("ck,ck->k", curvature, gap_vector)
    return Kinematics(gap_vector, distance, normal, tangent, metric)


def contact_loads(
    state: Kinematics,
    law: CompressibleYarnLaw,
    friction: CoulombFriction | None,
    slip_vector: np.ndarray,
    anchored: np.ndarray,
) -> ContactLoads:
    """Normal and friction line loads of k contacts and their derivative blocks.

    Args:
        state: closest-point kinematics.
        law: the normal law.
        friction: Coulomb friction, or None.
        slip_vector: (3, k) w = x_s - x_a - o, the slave point relative to its stick anchor
            (anchor point x_a on the master, offset o); the slip is g_T = (I - n n^T) w.
        anchored: (k,) True where a contact has an anchor; friction acts only there.

    Stick (|k_t g_T| <= mu f_n): f_t = -k_t g_T. Slip: f_t = mu f_n t with t = -g_T / |g_T|.
    """
    k = state.distance.size
    penetration = 2.0 * law.yarn_radius - state.distance
    normal_law = law.load_and_slope(penetration)
    coefficients = (
        (0.0, 1.0) if friction is None else (friction.coefficient, friction.tangential_stiffness)
    )
    geometry = _kernels.ContactGeometry(
        gap_vector=np.ascontiguousarray(state.gap_vector),
        tangent=np.ascontiguousarray(state.tangent),
        metric=np.ascontiguousarray(state.metric),
        slip_vector=np.ascontiguousarray(slip_vector),
        anchored=np.ascontiguousarray(anchored),
    )
    out = _kernels.LoadOutput(
        load=np.empty((3, k)), blocks=np.empty((4, 3, 3, k)), state=np.empty(k, dtype=np.int8)
    )
    _kernels.contact_loads(geometry, normal_law, np.array(coefficients), out)
    load, force, blocks, flags = out.load, normal_law[0], out.blocks, out.state
    friction_load = load - force * state.normal
    return ContactLoads(
        load=load,
        normal_force=force,
        friction_load=friction_load,
        sliding=flags == 2,
        elastic_slip=-friction_load / coefficients[1],
        blocks=blocks,
    )
