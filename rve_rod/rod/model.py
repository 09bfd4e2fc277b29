"""Cosserat rods by isogeometric collocation: patches, assembly of residual and Jacobian.

A `RodModel` is one or more B-spline patches (same degree p >= 2), each with its reference
centreline r0(u), reference quaternion field q0(u) and section stiffness, plus conditions (ends,
joints, user equations for extra unknowns) and loads. Its state vector holds the control
points (x_i, q_i) of all patches and the extra unknowns (numbering: `layout`). Evaluating the
model at a state gives the collocation residual (7 equations at every Greville point, rows
of rod ends replaced by the conditions) and its analytic Jacobian, assembled into a CSR matrix
whose sparsity pattern is fixed when the model is built.

For couplings such as contact the model exposes the collocation parameters, the basis values
at them, the dof layout, centreline positions and section forces at collocation points, and
accepts state-dependent line loads (`loads.StateDependentLoad`).
"""

import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.sparse

from rve_rod.errors import InputError
from rve_rod.geometry.bspline import BSplineCurve, basis_functions
from rve_rod.newton import NonlinearProblem
from rve_rod.rod import _kernels, quaternion
from rve_rod.rod.conditions import (
    Block,
    Condition,
    ConditionContext,
    EndValues,
    check_claims,
)
from rve_rod.rod.frames import reference_quaternions
from rve_rod.rod.layout import DOFS_PER_POINT, DofLayout, RodEnd
from rve_rod.rod.loads import DistributedLoad, LineLoads, PointLoad, StateDependentLoad
from rve_rod.rod.section import SectionStiffness

__all__ = [
    "CollocationData",
    "ControlPoints",
    "Evaluation",
    "PointLoadWeights",
    "RodModel",
    "RodPatch",
    "SectionForces",
    "SectionPoints",
]

logger = logging.getLogger(__name__)

_CURVATURE_ROWS = slice(6, 12)
"""Rows of the reference data holding the reference curvature k0 and its rate k0_u."""

_STRETCH_ROWS = slice(0, 6)
"""Rows of the reference data holding the reference stretch-shear g0 and its rate g0_u."""

_QUADRATURE_POINTS_PER_SPAN = 8
"""Gauss points per knot span for tributary lengths (the integrand N_i |r0'| is smooth)."""


@dataclass(frozen=True, eq=False)
class RodPatch:
    """One B-spline patch of a rod in its stress-free reference configuration.

    Attributes:
        centreline: reference centreline r0(u), a 3D BSplineCurve of degree p >= 2 (mm).
        quaternions: (n, 4) reference quaternion control points on the same knots; the frame
            (d1, d2, d3) = R(q0) should have d3 close to the tangent (see `frames`).
        section: section stiffness of the patch.
    """

    centreline: BSplineCurve
    quaternions: np.ndarray
    section: SectionStiffness

    def __post_init__(self):
        curve = self.centreline
        if curve.dim != 3:
            raise InputError(f"centreline has dimension {curve.dim}; rods need 3D curves")
        if curve.degree < 2:
            raise InputError(
                f"degree={curve.degree} is outside the valid range [2, inf): collocation of "
                "the second-order rod equations needs C1 splines"
            )
        controls = np.asarray(self.quaternions, dtype=float)
        if controls.shape != (curve.n_control_points, 4):
            raise InputError(
                f"quaternions have shape {controls.shape}; expected "
                f"({curve.n_control_points}, 4), one per control point"
            )
        object.__setattr__(self, "quaternions", controls)

    @property
    def degree(self) -> int:
        return self.centreline.degree

    @property
    def n_control_points(self) -> int:
        return self.centreline.n_control_points

    @property
    def frame_curve(self) -> BSplineCurve:
        """The reference quaternion field q0(u) as a 4D BSplineCurve."""
        return BSplineCurve(self.degree, self.centreline.knots, self.quaternions)

    @classmethod
    def chain(
        cls,
        curves: Sequence[BSplineCurve],
        section: SectionStiffness,
        initial_normal: np.ndarray | None = None,
    ) -> list["RodPatch"]:
        """Patches along consecutive curves with a rotation-minimizing reference frame that is
        continuous across the joints (`frames.reference_quaternions`)."""
        frames = reference_quaternions(curves, initial_normal)
        return [cls(curve, q, section) for curve, q in zip(curves, frames, strict=True)]


class CollocationData(NamedTuple):
    """Collocation points of one patch and the basis functions acting there.

    Attributes:
        parameters: (n,) Greville abscissae u_i (collocation point i <-> control point i).
        points: (n,) global collocation (= control point) indices.
        first: (n,) global index of the first of the p+1 control points acting at each point.
        basis: (3, p+1, n) values, first and second u-derivatives of those p+1 functions.
    """

    parameters: np.ndarray
    points: np.ndarray
    first: np.ndarray
    basis: np.ndarray

    def matrix(self, derivative: int = 0) -> scipy.sparse.csr_matrix:
        """Sparse (n, n_patch) matrix B[i, a] = d^k N_a / du^k at u_i, local columns."""
        n, width = self.parameters.size, self.basis.shape[1]
        offset = int(self.points[0])
        columns = (self.first - offset)[:, None] + np.arange(width)[None, :]
        return scipy.sparse.csr_matrix(
            (self.basis[derivative].T.ravel(), (np.repeat(np.arange(n), width), columns.ravel())),
            shape=(n, n),
        )


class ControlPoints(NamedTuple):
    """Control points of one patch: positions (n, 3) (mm) and quaternions (n, 4)."""

    positions: np.ndarray
    quaternions: np.ndarray


class PointLoadWeights(NamedTuple):
    """How a point load is lumped: line load f = P * weights (1/mm) at collocation `points`."""

    points: np.ndarray
    weights: np.ndarray


class SectionForces(NamedTuple):
    """Internal force and moment at the collocation points (global order, M points).

    Attributes:
        force: (3, M) spatial internal force n (N).
        moment: (3, M) spatial internal moment m (N mm).
    """

    force: np.ndarray
    moment: np.ndarray


class SectionPoints(NamedTuple):
    """Points of one patch where `RodModel.section_forces` evaluates the rod's n and m.

    Attributes:
        patch: the patch.
        first: (m,) index within the patch of the first of the p+1 control points acting.
        basis: (3, p+1, m) their basis values and first and second u-derivatives.
        reference: (14, m) the reference data there, as built (`_kernels` module docstring).
    """

    patch: int
    first: np.ndarray
    basis: np.ndarray
    reference: np.ndarray


class Evaluation(NamedTuple):
    """The model evaluated at one state and load factor.

    Attributes:
        residual: (n_dofs,) the collocation residual (rows as in `layout`).
        jacobian: (n_dofs, n_dofs) CSR matrix d residual / d state, or None if not requested.
        section: internal forces and moments at the collocation points.
    """

    residual: np.ndarray
    jacobian: scipy.sparse.csr_matrix | None
    section: SectionForces


class _EndConstant(NamedTuple):
    """The state-independent parts of the EndValues at one end collocation point."""

    columns: np.ndarray
    d_position: np.ndarray
    d_quaternion: np.ndarray
    reference_position: np.ndarray
    reference_quaternion: np.ndarray
    position_indices: np.ndarray  # (p+1, 3) state indices of the acting control points
    chain: np.ndarray  # (18, 7(p+1)): d/d local variables -> d/d control dofs (_chain_basis)


class _Pattern(NamedTuple):
    """Fixed CSR pattern and the data positions of every contribution."""

    indices: np.ndarray
    indptr: np.ndarray
    interior: np.ndarray  # (7, 7, p+1, M) int32 data positions, -1 for end rows
    conditions: list  # per condition: list of (r*c,) data positions per block
    condition_targets: np.ndarray  # the distinct data positions of all of `conditions`
    condition_slots: np.ndarray  # all of `conditions` concatenated in order, as indices of
    # condition_targets (the conditions' entries are summed on these few, not on all of data)
    unwritten: np.ndarray  # the data positions `interior` does not cover (zeroed, not all)


class RodModel:
    """Rods of B-spline patches with conditions and loads; residual and Jacobian.

    Args:
        patches: the patches, all of the same degree p >= 2.
        conditions: conditions claiming every patch end exactly once (Clamp, EndLoad, Pin,
            Joint or user-defined), and closing the extra unknowns.
        loads: dead loads (DistributedLoad, PointLoad; scaled by the load factor) and
            state-dependent loads (callables, see `loads.StateDependentLoad`).
        extra_unknowns: number of global unknowns appended to the state (macro strains,
            multipliers); their equations come from the conditions.
        extra_state_scale: typical magnitude of the extra unknowns (scalar or (n_extra,)),
            for the Newton increment norm.

    Attributes:
        patches, conditions, degree, layout: as given / derived.
        collocation: CollocationData per patch (Greville points and basis values there).
        tributary_lengths: (M,) integral of N_i ds over the reference (mm), per collocation
            point; used to lump point loads.
        characteristic_length: total reference arc length L (mm).
        characteristic_force: largest translational stiffness (N); with L it scales the
            convergence norms.
    """

    def __init__(
        self,
        patches: Sequence[RodPatch],
        conditions: Sequence[Condition],
        loads: Sequence = (),
        extra_unknowns: int = 0,
        extra_state_scale: float | np.ndarray = 1.0,
    ):
        self.patches = tuple(patches)
        if not self.patches:
            raise InputError("a rod model needs at least one patch")
        degrees = {patch.degree for patch in self.patches}
        if len(degrees) != 1:
            raise InputError(f"all patches must have the same degree; got {sorted(degrees)}")
        self.degree = degrees.pop()
        self.conditions = tuple(conditions)
        self.layout = DofLayout(
            tuple(patch.n_control_points for patch in self.patches), int(extra_unknowns)
        )
        check_claims(self.conditions, self.layout)
        self._dead_loads = [load for load in loads if isinstance(load, DistributedLoad | PointLoad)]
        self._state_loads: list[StateDependentLoad] = [
            load for load in loads if not isinstance(load, DistributedLoad | PointLoad)
        ]
        for load in self._state_loads:
            if not callable(load):
                raise InputError(f"load {load!r} is neither a dead load nor callable")
        self.collocation = tuple(self._collocation_data(k) for k in range(len(self.patches)))
        self._basis = np.ascontiguousarray(
            np.concatenate([data.basis for data in self.collocation], axis=2)
        )
        self._first = np.concatenate([data.first for data in self.collocation]).astype(np.int64)
        self._reference = np.ascontiguousarray(
            np.concatenate([self._reference_data(k) for k in range(len(self.patches))], axis=1)
        )
        self._curvature = self._reference[_CURVATURE_ROWS].copy()
        self._stretch = self._reference[_STRETCH_ROWS].copy()
        self._natural_curvature = 1.0  # set_natural_curvature
        self._prestrain = 0.0  # set_prestrain
        self._stiffness = np.ascontiguousarray(
            np.concatenate(
                [
                    np.repeat(
                        np.concatenate([p.section.translational, p.section.rotational])[:, None],
                        p.n_control_points,
                        axis=1,
                    )
                    for p in self.patches
                ],
                axis=1,
            )
        )
        self.tributary_lengths = np.concatenate(
            [self._tributary_lengths(k) for k in range(len(self.patches))]
        )
        self.characteristic_length = float(
            sum(patch.centreline.arc_length() for patch in self.patches)
        )
        self.characteristic_force = float(
            max(patch.section.translational.max() for patch in self.patches)
        )
        m = self.n_collocation
        self._row_index = DOFS_PER_POINT * np.arange(m)[None, :] + np.arange(7)[:, None]
        for k in range(len(self.patches)):
            points = self.layout.points(k)
            self._row_index[:6, [points[0], points[-1]]] = -1
        self._row_mask = self._row_index >= 0
        self._point_bases: dict[tuple[int, float], tuple[np.ndarray, np.ndarray]] = {}
        self._load_rows = self._line_load_rows()
        self._load_mask = self._load_rows >= 0
        self._condition_rows = self._assign_condition_rows()
        self._dead = sum((load.line_loads(self) for load in self._dead_loads), np.zeros((6, m)))
        self._extra_scale = np.broadcast_to(
            np.asarray(extra_state_scale, dtype=float), (self.layout.n_extra,)
        ).copy()
        self._reference_state = self.reference_state()
        self._end_constants = {
            point: self._end_constant(point)
            for k in range(len(self.patches))
            for point in (self.layout.points(k)[0], self.layout.points(k)[-1])
        }
        self._evaluated: tuple[np.ndarray, _kernels.PointEquations] | None = None
        self._pattern = self._build_pattern()

    # ----------------------------------------------------------------------------- layout --

    @property
    def n_collocation(self) -> int:
        """Number of collocation points M (= number of control points) of all patches."""
        return self.layout.n_points

    @property
    def n_dofs(self) -> int:
        return self.layout.n_dofs

    def reference_state(self) -> np.ndarray:
        """State vector of the reference configuration (extra unknowns zero)."""
        state = np.zeros(self.n_dofs)
        for k, patch in enumerate(self.patches):
            state[self.layout.position_dofs(k)] = patch.centreline.control_points
            state[self.layout.quaternion_dofs(k)] = patch.quaternions
        return state

    def control_points(self, state: np.ndarray, patch: int) -> ControlPoints:
        """Positions (n_k, 3) and quaternions (n_k, 4) of the control points of `patch`."""
        state = np.asarray(state)
        return ControlPoints(
            state[self.layout.position_dofs(patch)], state[self.layout.quaternion_dofs(patch)]
        )

    def set_natural_curvature(self, scale: float) -> None:
        """Make the rods' natural (stress-free) curvature and twist `scale` times those of the
        reference configuration: 1, as built, the reference shape is stress-free; 0, naturally
        straight rods bent into the reference shape (a yarn that keeps no set:
        `YarnSettings.natural_curvature`, `benchmarks/relaxed_rod_cell.py`). Lengths and shear
        stay the reference's."""
        self._reference[_CURVATURE_ROWS] = scale * self._curvature
        self._natural_curvature = float(scale)
        self._evaluated = None  # made with the former natural shape

    def set_prestrain(self, prestrain: float) -> None:
        """Make the rods' natural (stress-free) length 1 / (1 + eps0) times the reference
        configuration's, eps0 = `prestrain` (-): the reference shape is a yarn stretched by
        eps0 (a yarn knitted under tension), and at the reference length its axial force is
        N = EA eps0 / (1 + eps0) (the strain Gamma = (gamma - g0) / J is per reference arc
        length, `rve_rod.rod.strains`, and g0 becomes g0 / (1 + eps0)). 0: as built.
        Curvature and twist stay as set (`set_natural_curvature`)."""
        if not prestrain > -1.0:
            raise InputError(f"prestrain={prestrain} must exceed -1 (a positive natural length)")
        self._reference[_STRETCH_ROWS] = self._stretch / (1.0 + prestrain)
        self._prestrain = float(prestrain)
        self._evaluated = None  # made with the former natural length

    # -------------------------------------------------------------------- post-processing --

    def positions(self, state: np.ndarray, patch: int, parameters: np.ndarray) -> np.ndarray:
        """Centreline points r(u) of `patch` at `parameters`, shape (m, 3) (mm)."""
        positions, _ = self.control_points(state, patch)
        knots = self.patches[patch].centreline.knots
        return BSplineCurve(self.degree, knots, positions)(parameters)

    def rotations(self, state: np.ndarray, patch: int, parameters: np.ndarray) -> np.ndarray:
        """Cross-section frames R(q(u)) = [d1 d2 d3] of `patch`, shape (m, 3, 3)."""
        _, controls = self.control_points(state, patch)
        knots = self.patches[patch].centreline.knots
        return quaternion.rotation_matrix(BSplineCurve(self.degree, knots, controls)(parameters))

    def section_points(self, patch: int, parameters: np.ndarray) -> "SectionPoints":
        """What `section_forces` needs at `parameters` (m,) of `patch` that does not change
        with the state: the basis functions and the reference data there."""
        parameters = np.atleast_1d(np.asarray(parameters, dtype=float))
        curve = self.patches[patch].centreline
        basis = basis_functions(curve.knots, self.degree, parameters, derivatives=2)
        return SectionPoints(
            patch,
            (basis.spans - self.degree).astype(np.int64),
            np.ascontiguousarray(np.transpose(basis.values, (0, 2, 1))),
            self._reference_data(patch, parameters),
        )

    def section_forces(self, state: np.ndarray, points: "SectionPoints") -> SectionForces:
        """Internal force n (3, m) (N) and moment m (3, m) (N mm) at any points of a patch
        (`section_points`), spatial: the constitutive law of the collocation points
        (`_kernels.collocation_equations`) there, with the natural shape as set
        (`set_natural_curvature`, `set_prestrain`). n and m are what the part of the rod
        beyond the point (larger u) exerts on the part before it."""
        reference = points.reference.copy()
        reference[_CURVATURE_ROWS] *= self._natural_curvature
        reference[_STRETCH_ROWS] /= 1.0 + self._prestrain
        m = points.first.size
        stiffness = self._stiffness[:, self.layout.points(points.patch)[:1]]
        out = _kernels.PointEquations(
            np.empty((18, m)),
            np.empty((7, m)),
            np.empty((6, m)),
            np.zeros((7, 18, 1)),  # no Jacobian
            np.zeros((6, 18, 1)),
        )
        control = np.asarray(state, dtype=float)[: DOFS_PER_POINT * self.n_collocation]
        control = control.reshape(-1, DOFS_PER_POINT)[self.layout.points(points.patch)].T
        _kernels.gather_kinematics(
            np.ascontiguousarray(control), points.first, points.basis, out.kinematics
        )
        _kernels.collocation_equations(
            out, reference, np.ascontiguousarray(np.repeat(stiffness, m, axis=1)), False
        )
        return SectionForces(out.section[:3].copy(), out.section[3:].copy())

    def centreline_at_collocation(self, state: np.ndarray) -> np.ndarray:
        """Centreline positions at all collocation points, shape (3, M) (mm)."""
        control = np.asarray(state)[: DOFS_PER_POINT * self.n_collocation]
        control = control.reshape(-1, DOFS_PER_POINT)[:, :3]
        local = control[self._first[:, None] + np.arange(self.degree + 1)[None, :]]
        return np.einsum("ja,jac->cj", self._basis[0].T, local)

    def point_load_weights(self, patch: int, parameter: float) -> PointLoadWeights:
        """Collocation points and weights (1/mm) that lump a point load at u* (see `loads`).

        Returns points (k,) and weights (k,): line load f_i = P * weights at the global
        collocation points `points`, with sum(weights * tributary_lengths[points]) = 1.
        """
        curve = self.patches[patch].centreline
        low, high = curve.domain
        if not low <= parameter <= high:
            raise InputError(
                f"parameter={parameter} is outside the valid range [{low}, {high}] of patch {patch}"
            )
        local, shares = self.point_basis(patch, parameter)
        n = curve.n_control_points
        # The end points carry end conditions: move their shares to the interior neighbours.
        local = np.where(local == 0, 1, np.where(local == n - 1, n - 2, local))
        points = self.layout.first_point(patch) + local
        return PointLoadWeights(points, shares / self.tributary_lengths[points])

    def point_basis(self, patch: int, parameter: float) -> tuple[np.ndarray, np.ndarray]:
        """The p+1 control points acting at u* of `patch` (indices within the patch) and their
        basis values there, both (p+1,); memoized (conditions ask at every evaluation)."""
        key = (int(patch), float(parameter))
        if key not in self._point_bases:
            curve = self.patches[patch].centreline
            basis = basis_functions(curve.knots, self.degree, np.array([key[1]]))
            local = basis.spans[0] - self.degree + np.arange(self.degree + 1)
            self._point_bases[key] = (local, basis.values[0, 0].copy())
        return self._point_bases[key]

    # ------------------------------------------------------------------------- evaluation --

    def evaluate(
        self, state: np.ndarray, load_factor: float = 1.0, with_jacobian: bool = True
    ) -> Evaluation:
        """Residual (and Jacobian) at `state` for the loads and conditions at `load_factor`."""
        state = np.asarray(state, dtype=float)
        if state.shape != (self.n_dofs,):
            raise InputError(f"state has shape {state.shape}; expected ({self.n_dofs},)")
        local = self._local_equations(state, with_jacobian)
        # kept for end_values at the same state (the cell's conditions ask for cut ends)
        self._evaluated = (state.copy(), local) if with_jacobian else None
        kin, local_residual, section = local.kinematics, local.residual, local.section
        d_residual, d_section = local.d_residual, local.d_section
        residual = np.zeros(self.n_dofs)
        residual[self._row_index[self._row_mask]] = local_residual[self._row_mask]
        loads = load_factor * self._dead
        load_jacobians = []  # (rows, columns, values) of the load derivatives
        for load in self._state_loads:
            contribution: LineLoads = load(self, state, load_factor)
            loads[:3] += contribution.force
            if contribution.moment is not None:
                loads[3:] += contribution.moment
            for k, derivative in enumerate(
                (contribution.force_jacobian, contribution.moment_jacobian)
            ):
                if derivative is not None and with_jacobian:
                    entries = derivative.tocoo()
                    rows = self._load_rows[k][entries.row]
                    kept = rows >= 0
                    if kept.all():  # (no load at an end point: the usual case)
                        load_jacobians.append((rows, entries.col, entries.data))
                    else:
                        load_jacobians.append((rows[kept], entries.col[kept], entries.data[kept]))
        for k in range(2):
            residual[self._load_rows[k][self._load_mask[k]]] += loads[3 * k : 3 * k + 3].ravel()[
                self._load_mask[k]
            ]
        data = None
        if with_jacobian:
            data = np.empty(self._pattern.indices.size)
            data[self._pattern.unwritten] = 0.0
            _kernels.scatter_jacobian(d_residual, self._basis, self._pattern.interior, data)
        residual_rows, residual_values, data_values = (
            [np.empty(0, np.int64)],
            [np.empty(0)],
            [np.empty(0)],
        )
        for condition, rows, positions in zip(
            self.conditions, self._condition_rows, self._pattern.conditions, strict=True
        ):
            context = self._context(
                condition, rows, state, kin=kin, section=section, d_section=d_section
            )
            blocks = condition.evaluate(context, load_factor)
            if len(blocks) != len(positions):
                raise RuntimeError(
                    f"condition {condition!r} returned {len(blocks)} blocks, "
                    f"{len(positions)} when the model was built"
                )
            for block, where in zip(blocks, positions, strict=True):
                residual_rows.append(block.rows)
                residual_values.append(block.residual)
                if with_jacobian:
                    values = np.asarray(block.jacobian, dtype=float).ravel()
                    if values.size != where.size:
                        raise RuntimeError(
                            f"condition {condition!r} changed the shape of a Jacobian block"
                        )
                    data_values.append(values)
        residual += np.bincount(
            np.concatenate(residual_rows), np.concatenate(residual_values), minlength=self.n_dofs
        )
        jacobian = None
        if with_jacobian:
            pattern = self._pattern
            data[pattern.condition_targets] += np.bincount(
                pattern.condition_slots,
                np.concatenate(data_values),
                minlength=pattern.condition_targets.size,
            )
            matrix = (self._pattern.indptr, self._pattern.indices, data)
            if load_jacobians:
                rows, columns, values = (
                    part[0] if len(part) == 1 else np.concatenate(part)
                    for part in zip(*load_jacobians, strict=True)
                )
                capacity = data.size + values.size
                out = (
                    np.empty(self.n_dofs + 1, dtype=np.int32),
                    np.empty(capacity, dtype=np.int32),
                    np.empty(capacity),
                )
                count = _kernels.add_entries(matrix, rows, columns, values, out)
                matrix = (out[0], out[1][:count], out[2][:count])
            jacobian = scipy.sparse.csr_matrix(
                (matrix[2], matrix[1], matrix[0]), shape=(self.n_dofs, self.n_dofs)
            )
            jacobian.has_sorted_indices = True  # the pattern's and the sum's columns are sorted
        forces = SectionForces(section[:3].copy(), section[3:].copy())
        return Evaluation(residual, jacobian, forces)

    def residual(self, state: np.ndarray, load_factor: float = 1.0) -> np.ndarray:
        """The residual only (no Jacobian): shape (n_dofs,)."""
        return self.evaluate(state, load_factor, with_jacobian=False).residual

    def end_values(self, state: np.ndarray, end: RodEnd) -> EndValues:
        """Position, quaternion, internal force and moment at a rod end, with derivatives."""
        state = np.asarray(state, dtype=float)
        point = self.layout.end_point(RodEnd(int(end.patch), end.side))
        evaluated = self._evaluated
        if evaluated is not None and np.array_equal(evaluated[0], state):
            local, column = evaluated[1], point  # the evaluation at this state has it
        else:
            local, column = self._local_equations(state, True, point), 0
        return self._end_values(
            point,
            state,
            kin=local.kinematics[:, column],
            section=local.section[:, column],
            d_section=local.d_section[:, :, column],
        )

    def problem(self, commit=None) -> NonlinearProblem:
        """This model as a `NonlinearProblem` for `rve_rod.newton` (with convergence scales).

        Args:
            commit: optional callable(state, load_factor) run after each converged step.
        """

        def evaluate(state, load_factor):
            evaluation = self.evaluate(state, load_factor)
            return evaluation.residual, evaluation.jacobian

        return NonlinearProblem(
            evaluate=evaluate,
            residual_scale=self.residual_scale(),
            state_scale=self.state_scale(),
            commit=commit,
            nodes=self.nodes(),
            residual=self.residual,
        )

    def nodes(self) -> np.ndarray:
        """(n_dofs,) the node of each unknown for the LU's "NODES" ordering: the control
        point of its 7 unknowns, -1 for the extra unknowns (`NonlinearProblem.nodes`)."""
        points = np.repeat(np.arange(self.n_collocation), DOFS_PER_POINT)
        return np.concatenate([points, np.full(self.layout.n_extra, -1)])

    def residual_scale(self) -> np.ndarray:
        """Typical magnitude of each residual row (for dimensionless convergence norms).

        Force rows: F/L, moment rows: F, gauge rows: 1, end rows: as the conditions say;
        F = the largest translational stiffness (N), L = the total reference length (mm).
        """
        length, force = self.characteristic_length, self.characteristic_force
        scale = np.empty(self.n_dofs)
        per_point = np.array([force / length] * 3 + [force] * 3 + [1.0])
        scale[: DOFS_PER_POINT * self.n_collocation] = np.tile(per_point, self.n_collocation)
        for condition, rows in zip(self.conditions, self._condition_rows, strict=True):
            scale[rows] = condition.row_scales(length, force)
        return scale

    def state_scale(self) -> np.ndarray:
        """Typical magnitude of each unknown: L for positions, 1 for quaternions, and the
        extra-unknown scale given to the constructor."""
        scale = np.empty(self.n_dofs)
        per_point = np.array([self.characteristic_length] * 3 + [1.0] * 4)
        scale[: DOFS_PER_POINT * self.n_collocation] = np.tile(per_point, self.n_collocation)
        scale[self.layout.extra_offset :] = self._extra_scale
        return scale

    # ---------------------------------------------------------------------------- private --

    def _collocation_data(self, k: int) -> CollocationData:
        patch = self.patches[k]
        curve = patch.centreline
        parameters = curve.greville()
        basis = basis_functions(curve.knots, self.degree, parameters, derivatives=2)
        first_point = self.layout.first_point(k)
        return CollocationData(
            parameters=parameters,
            points=first_point + np.arange(parameters.size),
            first=first_point + basis.spans - self.degree,
            basis=np.ascontiguousarray(np.transpose(basis.values, (0, 2, 1))),
        )

    def _reference_data(self, k: int, u: np.ndarray | None = None) -> np.ndarray:
        """The reference data (14, m) of patch k at the parameters u (default: its collocation
        points), as built (`_kernels` module docstring: g0, g0', k0, k0', J, J')."""
        patch = self.patches[k]
        u = self.collocation[k].parameters if u is None else u
        r = patch.centreline.derivatives(u, 2)
        q = patch.frame_curve.derivatives(u, 2)
        rot = quaternion.rotation_matrix(q[0])
        k0 = quaternion.curvature(q[0], q[1])
        k0u = quaternion.curvature_rate(q[0], q[1], q[2])
        g0 = np.einsum("mji,mj->mi", rot, r[1])
        g0u = np.einsum("mji,mj->mi", rot, r[2]) - np.cross(k0, g0)
        metric = np.linalg.norm(r[1], axis=1)
        if np.any(metric <= 0.0):
            raise InputError(f"patch {k} has a zero tangent at a collocation point")
        metric_u = np.sum(r[1] * r[2], axis=1) / metric
        return np.concatenate([g0.T, g0u.T, k0.T, k0u.T, metric[None], metric_u[None]], axis=0)

    def _tributary_lengths(self, k: int) -> np.ndarray:
        curve = self.patches[k].centreline
        edges = curve.breakpoints()
        nodes, weights = np.polynomial.legendre.leggauss(_QUADRATURE_POINTS_PER_SPAN)
        half = 0.5 * np.diff(edges)
        params = (edges[:-1, None] + half[:, None] * (nodes[None, :] + 1.0)).ravel()
        w = (half[:, None] * weights[None, :]).ravel()
        speed = np.linalg.norm(curve(params, 1), axis=1)
        basis = basis_functions(curve.knots, self.degree, params)
        lengths = np.zeros(curve.n_control_points)
        columns = basis.spans[:, None] - self.degree + np.arange(self.degree + 1)[None, :]
        np.add.at(lengths, columns, basis.values[0] * (w * speed)[:, None])
        return lengths

    def _line_load_rows(self) -> np.ndarray:
        """(2, 3M) residual row of each entry of force.ravel() and moment.ravel() (C order of
        (3, M): entry c M + j is component c at point j), -1 at patch end points (their rows
        hold the end conditions)."""
        m = self.n_collocation
        rows = np.full((2, 3, m), -1, dtype=np.int64)
        interior = np.flatnonzero(self._row_mask[0])
        for k, offset in enumerate((0, 3)):
            rows[k][:, interior] = (
                DOFS_PER_POINT * interior[None, :] + offset + np.arange(3)[:, None]
            )
        return rows.reshape(2, 3 * m)

    def _assign_condition_rows(self) -> list[np.ndarray]:
        rows = []
        next_extra = self.layout.extra_offset
        for condition in self.conditions:
            end_rows = [self.layout.end_rows(RodEnd(int(e.patch), e.side)) for e in condition.ends]
            extra = np.arange(next_extra, next_extra + int(condition.extra_equations))
            next_extra += extra.size
            rows.append(np.concatenate([*end_rows, extra]).astype(np.int64))
        return rows

    def _local_equations(
        self, state: np.ndarray, with_jacobian: bool, point=None
    ) -> _kernels.PointEquations:
        """Run the kernels at all collocation points, or at the single point `point`."""
        if point is None:
            m = self.n_collocation
            control = state[: DOFS_PER_POINT * m].reshape(m, DOFS_PER_POINT).T
            first, basis = self._first, self._basis
            reference, stiffness = self._reference, self._stiffness
        else:
            local = self._first[point] + np.arange(self.degree + 1)
            control = state[DOFS_PER_POINT * local[:, None] + np.arange(DOFS_PER_POINT)].T
            first = np.zeros(1, dtype=np.int64)
            window = slice(point, point + 1)
            basis = np.ascontiguousarray(self._basis[:, :, window])
            reference = np.ascontiguousarray(self._reference[:, window])
            stiffness = np.ascontiguousarray(self._stiffness[:, window])
        m = first.size
        out = _kernels.PointEquations(
            np.empty((18, m)),
            np.empty((7, m)),
            np.empty((6, m)),
            np.zeros((7, 18, m)),
            np.zeros((6, 18, m)),
        )
        _kernels.gather_kinematics(np.ascontiguousarray(control), first, basis, out.kinematics)
        _kernels.collocation_equations(out, reference, stiffness, with_jacobian)
        return out

    def _end_values(self, point, state, *, kin, section, d_section) -> EndValues:
        """EndValues at collocation `point` from its local variables (18,), section forces
        (6,) and their local derivatives (6, 18)."""
        constant = self._end_constants[point]
        basis = self._basis[:, :, point]
        chained = d_section @ constant.chain
        return EndValues(
            columns=constant.columns,
            position=basis[0] @ state[constant.position_indices],
            d_position=constant.d_position,
            quaternion=kin[6:10].copy(),
            d_quaternion=constant.d_quaternion,
            force=section[:3].copy(),
            d_force=chained[:3],
            moment=section[3:].copy(),
            d_moment=chained[3:],
            reference_position=constant.reference_position,
            reference_quaternion=constant.reference_quaternion,
        )

    def _end_constant(self, point: int) -> _EndConstant:
        """The state-independent parts of the EndValues at an end collocation point."""
        width = self.degree + 1
        basis = self._basis[:, :, point]
        local = self._first[point] + np.arange(width)
        columns = (DOFS_PER_POINT * local[:, None] + np.arange(DOFS_PER_POINT)[None, :]).ravel()
        d_position = np.zeros((3, width, DOFS_PER_POINT))
        d_quaternion = np.zeros((4, width, DOFS_PER_POINT))
        for c in range(3):
            d_position[c, :, c] = basis[0]
        for c in range(4):
            d_quaternion[c, :, 3 + c] = basis[0]
        reference = self._reference_state
        position_indices = DOFS_PER_POINT * local[:, None] + np.arange(3)[None, :]
        quaternion_indices = DOFS_PER_POINT * local[:, None] + 3 + np.arange(4)[None, :]
        return _EndConstant(
            columns=columns,
            d_position=d_position.reshape(3, -1),
            d_quaternion=d_quaternion.reshape(4, -1),
            reference_position=basis[0] @ reference[position_indices],
            reference_quaternion=basis[0] @ reference[quaternion_indices],
            position_indices=position_indices,
            chain=_chain_basis(np.eye(18), basis),
        )

    def _context(self, condition, rows, state, *, kin, section, d_section) -> ConditionContext:
        ends = []
        for end in condition.ends:
            point = self.layout.end_point(RodEnd(int(end.patch), end.side))
            ends.append(
                self._end_values(
                    point,
                    state,
                    kin=kin[:, point],
                    section=section[:, point],
                    d_section=d_section[:, :, point],
                )
            )
        return ConditionContext(state=state, ends=tuple(ends), rows=rows, model=self)

    def _build_pattern(self) -> _Pattern:
        """The CSR pattern of the interior equations and of the conditions' blocks (taken
        from one evaluation of the conditions at the reference state)."""
        m, width = self.n_collocation, self.degree + 1
        rows = np.broadcast_to(self._row_index[:, None, None, :], (7, 7, width, m))
        columns = (
            DOFS_PER_POINT
            * (self._first[None, None, None, :] + np.arange(width)[None, None, :, None])
            + np.arange(7)[None, :, None, None]
        )
        columns = np.broadcast_to(columns, (7, 7, width, m))
        mask = rows >= 0
        row_parts = [rows[mask]]
        column_parts = [columns[mask]]
        state = self._reference_state
        local = self._local_equations(state, True)
        kin, section, d_section = local.kinematics, local.section, local.d_section
        condition_pairs = []
        for condition, owned in zip(self.conditions, self._condition_rows, strict=True):
            context = self._context(
                condition, owned, state, kin=kin, section=section, d_section=d_section
            )
            pairs = []
            for returned in condition.evaluate(context, 0.0):
                block = _checked_block(returned, self.n_dofs, condition)
                block_rows = np.repeat(block.rows, block.columns.size)
                block_columns = np.tile(block.columns, block.rows.size)
                row_parts.append(block_rows)
                column_parts.append(block_columns)
                pairs.append((block_rows, block_columns))
            condition_pairs.append(pairs)
        all_rows = np.concatenate(row_parts).astype(np.int64)
        all_columns = np.concatenate(column_parts).astype(np.int64)
        keys = np.unique(all_rows * self.n_dofs + all_columns)
        key_rows = keys // self.n_dofs
        indices = (keys % self.n_dofs).astype(np.int32)
        indptr = np.searchsorted(key_rows, np.arange(self.n_dofs + 1)).astype(np.int32)
        # int32 (as the CSR indices): half the bytes the scatter reads at every evaluation
        interior = np.full((7, 7, width, m), -1, dtype=np.int32)
        interior[mask] = np.searchsorted(keys, rows[mask] * self.n_dofs + columns[mask])
        positions = [
            [np.searchsorted(keys, r * self.n_dofs + c) for r, c in pairs]
            for pairs in condition_pairs
        ]
        empty_rows = np.flatnonzero(np.diff(indptr) == 0)
        if empty_rows.size:
            raise InputError(
                f"the system has {empty_rows.size} empty rows (first: {empty_rows[0]}); "
                "every extra unknown needs an equation"
            )
        flat = [where for per_condition in positions for where in per_condition]
        targets, slots = np.unique(
            np.concatenate([np.empty(0, np.int64), *flat]), return_inverse=True
        )
        written = np.zeros(indices.size, dtype=bool)
        written[interior[mask]] = True
        unwritten = np.flatnonzero(~written)
        return _Pattern(indices, indptr, interior, positions, targets, slots, unwritten)


def _checked_block(block: Block, n_dofs: int, condition) -> Block:
    rows = np.asarray(block.rows, dtype=np.int64).ravel()
    columns = np.asarray(block.columns, dtype=np.int64).ravel()
    jacobian = np.asarray(block.jacobian, dtype=float)
    if jacobian.shape != (rows.size, columns.size):
        raise InputError(
            f"condition {condition!r} returned a Jacobian block of shape {jacobian.shape} "
            f"for {rows.size} rows and {columns.size} columns"
        )
    for name, index in (("rows", rows), ("columns", columns)):
        if index.size and (index.min() < 0 or index.max() >= n_dofs):
            raise InputError(f"condition {condition!r} has {name} outside [0, {n_dofs})")
    return Block(rows, np.asarray(block.residual, dtype=float), columns, jacobian)


def _chain_basis(d_local: np.ndarray, basis: np.ndarray) -> np.ndarray:
    """Derivatives (r, 18) w.r.t. local variables -> (r, 7(p+1)) w.r.t. control dofs, given
    the basis values (3, p+1) at the point (the NumPy twin of `_kernels.scatter_jacobian`)."""
    rows = d_local.shape[0]
    out = np.empty((rows, basis.shape[1], DOFS_PER_POINT))
    # positions enter through r' and r''; quaternions through q, q' and q''
    out[:, :, :3] = np.einsum("rkc,ka->rac", d_local[:, 0:6].reshape(rows, 2, 3), basis[1:])
    out[:, :, 3:] = np.einsum("rkc,ka->rac", d_local[:, 6:18].reshape(rows, 3, 4), basis)
    return out.reshape(rows, -1)
