"""End, joint and user-defined conditions: the equations that close the collocation system.

Every patch end (RodEnd) owns six residual rows (see `layout`). A condition claims some ends,
fills their rows, and may add equations for extra global unknowns. The model evaluates each
condition with a `ConditionContext` (the end values and their derivatives) and adds the
returned `Block`s into the residual and the Jacobian. Blocks may also add into rows the
condition does not own (e.g. a reaction applied as a point load); ownership only decides which
rows must be filled exactly once.

To write a condition (e.g. the periodic link of a knit cell): subclass `Condition`, list the
ends it claims in `ends`, set `extra_equations` if it closes extra unknowns, and return blocks
whose rows and columns do not change from call to call (the sparsity pattern is fixed when
the model is built); values may change freely.
"""

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from rve_rod.errors import InputError
from rve_rod.rod import quaternion
from rve_rod.rod.layout import DOFS_PER_POINT, END, START, DofLayout, RodEnd

if TYPE_CHECKING:
    from rve_rod.rod.model import RodModel

__all__ = [
    "Block",
    "Clamp",
    "Condition",
    "ConditionContext",
    "EndCondition",
    "EndLoad",
    "EndValues",
    "Joint",
    "Offset",
    "OffsetFunction",
    "Pin",
    "PointSupport",
    "as_vector",
    "check_claims",
]


class Block(NamedTuple):
    """A contribution to the residual and the Jacobian.

    Attributes:
        rows: (r,) residual rows.
        residual: (r,) values added to those rows.
        columns: (c,) state indices the rows depend on (may repeat; entries are summed).
        jacobian: (r, c) derivative of `residual` w.r.t. state[columns].
    """

    rows: np.ndarray
    residual: np.ndarray
    columns: np.ndarray
    jacobian: np.ndarray


class EndValues(NamedTuple):
    """State of the rod at one end, with derivatives w.r.t. the state entries `columns`.

    Attributes:
        columns: (7(p+1),) state indices of the p+1 control points acting at the end.
        position: (3,) centreline position (mm); d_position (3, c).
        quaternion: (4,) rotation quaternion (unit after convergence); d_quaternion (4, c).
        force: (3,) internal force n (N), spatial; d_force (3, c).
        moment: (3,) internal moment m (N mm), spatial; d_moment (3, c).
        reference_position: (3,) position in the reference configuration (mm).
        reference_quaternion: (4,) quaternion in the reference configuration.
    """

    columns: np.ndarray
    position: np.ndarray
    d_position: np.ndarray
    quaternion: np.ndarray
    d_quaternion: np.ndarray
    force: np.ndarray
    d_force: np.ndarray
    moment: np.ndarray
    d_moment: np.ndarray
    reference_position: np.ndarray
    reference_quaternion: np.ndarray


class ConditionContext(NamedTuple):
    """What a condition sees when it is evaluated.

    Attributes:
        state: (n_dofs,) the global state vector.
        ends: EndValues of the condition's claimed ends, in the order of `Condition.ends`.
        rows: (6 * len(ends) + extra_equations,) the rows the condition owns: six per end,
            then its extra equations.
        model: the RodModel (layout, collocation data, point-load weights).
    """

    state: np.ndarray
    ends: tuple[EndValues, ...]
    rows: np.ndarray
    model: "RodModel"


class Condition(ABC):
    """Equations at rod ends, joints, or for extra unknowns (see the module docstring)."""

    extra_equations: int = 0
    """Number of equations this condition adds for the model's extra unknowns."""

    @property
    @abstractmethod
    def ends(self) -> tuple[RodEnd, ...]:
        """The rod ends whose six rows this condition fills."""

    @abstractmethod
    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        """Residual and Jacobian blocks at the current state and load factor."""

    def row_scales(self, length: float, force: float) -> np.ndarray:
        """Typical magnitude of each owned row for the convergence norm.

        `length` (mm) and `force` (N) are the model's characteristic length and force.
        The default treats rows as dimensionless; built-in conditions override it.
        """
        return np.ones(6 * len(self.ends) + self.extra_equations)


def as_vector(name: str, value) -> np.ndarray:
    """`value` as a float array of shape (3,), or InputError naming `name`."""
    array = np.asarray(value, dtype=float)
    if array.shape != (3,) or not np.all(np.isfinite(array)):
        raise InputError(f"{name}={value!r} must be three finite numbers")
    return array


def _side_sign(end: RodEnd) -> float:
    """+1 at END, -1 at START: n(end) = sign * (force applied on the rod at that end)."""
    if end.side not in (START, END):
        raise InputError(f"side={end.side!r} is not one of {START!r}, {END!r}")
    return 1.0 if end.side == END else -1.0


def _rotation_error_matrix(target: np.ndarray) -> np.ndarray:
    """(3, 4) matrix E with E q = vec(conj(target) * q); E q = 0 iff R(q) = R(target)."""
    return quaternion.left_matrix(quaternion.conjugate(target))[1:]


def _position_block(rows, values: EndValues, target: np.ndarray) -> Block:
    """x(end) - target = 0."""
    return Block(rows, values.position - target, values.columns, values.d_position)


def _force_block(rows, values: EndValues, applied: np.ndarray) -> Block:
    """n(end) - applied = 0."""
    return Block(rows, values.force - applied, values.columns, values.d_force)


def _moment_block(rows, values: EndValues, applied: np.ndarray) -> Block:
    """m(end) - applied = 0."""
    return Block(rows, values.moment - applied, values.columns, values.d_moment)


@dataclass(frozen=True, eq=False)
class EndCondition(Condition):
    """Base of the conditions that fill the six rows of a single rod end.

    Attributes:
        end: the rod end.
    """

    end: RodEnd

    def __post_init__(self):
        _side_sign(self.end)

    @property
    def ends(self) -> tuple[RodEnd, ...]:
        return (self.end,)


@dataclass(frozen=True, eq=False)
class Clamp(EndCondition):
    """Prescribed position and rotation of a rod end (Dirichlet).

    At load factor t the end sits at x_ref + t * displacement and its frame is the reference
    frame rotated by the rotation vector t * rotation (spatial axis, rad).

    Attributes:
        end: the clamped end.
        displacement: (3,) end displacement at t = 1 (mm).
        rotation: (3,) end rotation vector at t = 1 (rad).
    """

    displacement: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rotation: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "displacement", as_vector("displacement", self.displacement))
        object.__setattr__(self, "rotation", as_vector("rotation", self.rotation))

    def row_scales(self, length: float, force: float) -> np.ndarray:
        return np.array([length] * 3 + [1.0] * 3)

    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        values = context.ends[0]
        rows = context.rows
        target_position = values.reference_position + load_factor * self.displacement
        reference = values.reference_quaternion / np.linalg.norm(values.reference_quaternion)
        target = quaternion.multiply(
            quaternion.from_rotation_vector(load_factor * self.rotation), reference
        )
        error = _rotation_error_matrix(target)
        return [
            _position_block(rows[:3], values, target_position),
            Block(
                rows[3:6], error @ values.quaternion, values.columns, error @ values.d_quaternion
            ),
        ]


@dataclass(frozen=True, eq=False)
class EndLoad(EndCondition):
    """Prescribed (dead) force and moment on a rod end (Neumann); zero values: a free end.

    At the END side the internal force equals the applied force, n = t F; at the START side
    n = -t F (the internal force acts on the part of the rod beyond the section).

    Attributes:
        end: the loaded end.
        force: (3,) force at t = 1 (N), fixed direction.
        moment: (3,) moment at t = 1 (N mm), fixed direction.
    """

    force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    moment: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "force", as_vector("force", self.force))
        object.__setattr__(self, "moment", as_vector("moment", self.moment))

    def row_scales(self, length: float, force: float) -> np.ndarray:
        return np.array([force] * 3 + [force * length] * 3)

    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        values = context.ends[0]
        rows = context.rows
        sign = _side_sign(self.end)
        return [
            _force_block(rows[:3], values, sign * load_factor * self.force),
            _moment_block(rows[3:6], values, sign * load_factor * self.moment),
        ]


@dataclass(frozen=True, eq=False)
class Pin(EndCondition):
    """Prescribed position and (dead) moment of a rod end: a ball joint.

    Attributes:
        end: the pinned end.
        displacement: (3,) end displacement at t = 1 (mm).
        moment: (3,) moment applied at the end at t = 1 (N mm), as in EndLoad.
    """

    displacement: np.ndarray = field(default_factory=lambda: np.zeros(3))
    moment: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "displacement", as_vector("displacement", self.displacement))
        object.__setattr__(self, "moment", as_vector("moment", self.moment))

    def row_scales(self, length: float, force: float) -> np.ndarray:
        return np.array([length] * 3 + [force * length] * 3)

    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        values = context.ends[0]
        rows = context.rows
        target = values.reference_position + load_factor * self.displacement
        sign = _side_sign(self.end)
        return [
            _position_block(rows[:3], values, target),
            _moment_block(rows[3:6], values, sign * load_factor * self.moment),
        ]


class Offset(NamedTuple):
    """A joint offset that may depend on the state (e.g. on macro-strain unknowns).

    Attributes:
        value: (3,) prescribed x_second - x_first (mm).
        columns: (c,) state indices it depends on.
        derivative: (3, c) d value / d state[columns].
    """

    value: np.ndarray
    columns: np.ndarray
    derivative: np.ndarray


OffsetFunction = Callable[[np.ndarray, float], Offset]
"""offset(state, load_factor) -> Offset."""


@dataclass(frozen=True, eq=False)
class Joint(Condition):
    """Rigid connection of the END of one patch to the START of another.

    Equations (first's rows): x_second - x_first = offset, and the relative rotation of the
    two end frames stays the reference one, vec(conj(q_first) q_second conj(c)) = 0 with
    c = conj(q0_first) q0_second / |.|. Second's rows: force and moment balance,
    n_first - n_second = t P and m_first - m_second = t M for a point force P and moment M
    applied at the joint.

    A periodic link (knit cell) is a Joint from the last patch's END to the first patch's
    START whose `offset` returns F times the lattice vector, with F built from extra unknowns.

    Attributes:
        first: the END side of the preceding patch.
        second: the START side of the following patch.
        offset: None (positions coincide) or a function (state, t) -> Offset.
        force: (3,) point force at the joint at t = 1 (N).
        moment: (3,) point moment at the joint at t = 1 (N mm).
    """

    first: RodEnd
    second: RodEnd
    offset: OffsetFunction | None = None
    force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    moment: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        if self.first.side != END or self.second.side != START:
            raise InputError(
                f"a Joint links an {END!r} side to a {START!r} side; got "
                f"first={self.first}, second={self.second}"
            )
        object.__setattr__(self, "force", as_vector("force", self.force))
        object.__setattr__(self, "moment", as_vector("moment", self.moment))

    @property
    def ends(self) -> tuple[RodEnd, ...]:
        return (self.first, self.second)

    def row_scales(self, length: float, force: float) -> np.ndarray:
        return np.array([length] * 3 + [1.0] * 3 + [force] * 3 + [force * length] * 3)

    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        a, b = context.ends
        rows = context.rows
        columns, d_position, c_conj, right_c = self._constant(context)
        blocks = [Block(rows[:3], b.position - a.position, columns, d_position)]
        if self.offset is not None:
            offset = self.offset(context.state, load_factor)
            blocks.append(Block(rows[:3], -offset.value, offset.columns, -offset.derivative))
        # e = vec(conj(q_a) * q_b * conj(c)): linear in q_b and in conj(q_a)
        qb_c = quaternion.multiply(b.quaternion, c_conj)
        qa_conj = quaternion.conjugate(a.quaternion)
        d_qa = (quaternion.right_matrix(qb_c) @ np.diag([1.0, -1.0, -1.0, -1.0]))[1:]
        d_qb = (quaternion.left_matrix(qa_conj) @ right_c)[1:]
        error = quaternion.multiply(qa_conj, qb_c)[1:]
        blocks.append(
            Block(
                rows[3:6],
                error,
                columns,
                np.hstack([d_qa @ a.d_quaternion, d_qb @ b.d_quaternion]),
            )
        )
        blocks.append(
            Block(
                rows[6:9],
                a.force - b.force - load_factor * self.force,
                columns,
                np.hstack([a.d_force, -b.d_force]),
            )
        )
        blocks.append(
            Block(
                rows[9:12],
                a.moment - b.moment - load_factor * self.moment,
                columns,
                np.hstack([a.d_moment, -b.d_moment]),
            )
        )
        return blocks

    def _constant(self, context: ConditionContext) -> tuple[np.ndarray, ...]:
        """The state-independent parts of the blocks for the context's model, made at the
        first call: the columns of both ends, the positions' derivative, conj(c) and its
        right matrix."""
        kept = self.__dict__.get("_kept")
        if kept is not None and kept[0] is context.model:
            return kept[1]
        a, b = context.ends
        relative = quaternion.multiply(
            quaternion.conjugate(a.reference_quaternion), b.reference_quaternion
        )
        c_conj = quaternion.conjugate(relative / np.linalg.norm(relative))
        constant = (
            np.concatenate([a.columns, b.columns]),
            np.hstack([-a.d_position, b.d_position]),
            c_conj,
            quaternion.right_matrix(c_conj),
        )
        object.__setattr__(self, "_kept", (context.model, constant))
        return constant


@dataclass(frozen=True, eq=False)
class PointSupport(Condition):
    """Holds the centreline point at parameter u* of a patch at its reference position, and
    optionally its rotation about given spatial axes, with Lagrange multipliers among the
    extra unknowns.

    The multipliers are the support reaction: a force (and moments about the axes) applied to
    the rod at u*, lumped onto the collocation points like a `loads.PointLoad`. Use it to
    remove rigid modes and nothing else: e.g. a periodic cell whose ends are linked by a
    Joint with an offset has the three translations and the rotation about the period vector
    as rigid modes, so it needs `rotation_axes=(period,)`. Holding a rotation that is not a
    rigid mode over-constrains the rod, and the reaction moment shows it. When the other
    loads are in equilibrium the reaction is zero up to the discretization error.

    Attributes:
        patch: patch index.
        parameter: u* in the patch's parameter domain.
        first_unknown: index among the extra unknowns of the first multiplier: three for the
            reaction force, then one per rotation axis for the reaction moment.
        rotation_axes: spatial axes (each 3 numbers) about which the frame at u* is held.
        rotation_stiffness: k (N mm per rad), or inf (the default): the rotations about the
            axes are held exactly; a finite k holds them by a spring instead, the reaction
            moment -k theta (theta the rotation about the axis), for a rotation that is a
            rigid mode only at rest (a cell whose contacts hold it once loaded).
    """

    patch: int
    parameter: float
    first_unknown: int = 0
    rotation_axes: tuple = ()
    rotation_stiffness: float = np.inf

    def __post_init__(self):
        axes = np.array([as_vector("rotation axis", axis) for axis in self.rotation_axes])
        axes = axes.reshape(-1, 3)
        lengths = np.linalg.norm(axes, axis=1)
        if np.any(lengths == 0.0):
            raise InputError("rotation_axes must be nonzero vectors")
        object.__setattr__(self, "rotation_axes", tuple(axes / lengths[:, None]))
        if not self.rotation_stiffness > 0.0:
            raise InputError(
                f"rotation_stiffness={self.rotation_stiffness!r} must be > 0 (inf: held)"
            )

    @property
    def ends(self) -> tuple[RodEnd, ...]:
        return ()

    @property
    def extra_equations(self) -> int:  # type: ignore[override]
        return 3 + len(self.rotation_axes)

    def row_scales(self, length: float, force: float) -> np.ndarray:
        return np.array([length] * 3 + [1.0] * len(self.rotation_axes))

    def evaluate(self, context: ConditionContext, load_factor: float) -> list[Block]:
        constant = self._constant(context.model)
        state = context.state
        rows = context.rows
        values, multipliers, weights = constant.values, constant.multipliers, constant.weights
        blocks = []
        for c in range(3):
            columns = constant.position_columns[:, c]
            blocks.append(
                Block(
                    rows[c : c + 1],
                    np.array([values @ state[columns] - constant.reference_position[c]]),
                    columns,
                    constant.d_position,
                )
            )
            # reaction force component c, lumped onto the force rows
            blocks.append(
                Block(
                    constant.load_rows[c],
                    weights * state[multipliers[c]],
                    multipliers[c : c + 1],
                    constant.d_load,
                )
            )
        if not self.rotation_axes:
            return blocks
        current = values @ state[constant.quaternion_columns]
        # the error is half the angle: theta / 2 + lambda / (2 k) = 0 holds lambda = -k theta
        compliance = 0.5 / self.rotation_stiffness
        for i, axis in enumerate(self.rotation_axes):
            blocks.append(
                Block(
                    rows[3 + i : 4 + i],
                    np.array([constant.rotation_errors[i] @ current]),
                    constant.quaternion_columns.ravel(),
                    constant.d_rotation[i],
                )
            )
            if compliance:
                blocks.append(
                    Block(
                        rows[3 + i : 4 + i],
                        np.array([compliance * state[multipliers[3 + i]]]),
                        multipliers[3 + i : 4 + i],
                        np.array([[compliance]]),
                    )
                )
            for c in range(3):
                blocks.append(
                    Block(
                        constant.load_rows[3 + c],
                        weights * axis[c] * state[multipliers[3 + i]],
                        multipliers[3 + i : 4 + i],
                        constant.d_moment[i][c],
                    )
                )
        return blocks

    def _constant(self, model: "RodModel") -> "_SupportConstant":
        """The state-independent parts of the blocks for `model`, made at the first call
        (kept for the model: its patches and layout do not change)."""
        kept = self.__dict__.get("_kept")
        if kept is not None and kept.model is model:
            return kept
        layout = model.layout
        multipliers = layout.extra_offset + self.first_unknown + np.arange(self.extra_equations)
        if self.first_unknown < 0 or multipliers[-1] >= layout.n_dofs:
            raise InputError(
                f"first_unknown={self.first_unknown} leaves no room for "
                f"{self.extra_equations} multipliers among {layout.n_extra} extra unknowns"
            )
        patch = model.patches[self.patch]
        local, values = model.point_basis(self.patch, self.parameter)
        points, weights = model.point_load_weights(self.patch, self.parameter)
        quaternion_columns = layout.quaternion_dofs(self.patch)[local]  # (p+1, 4)
        rotation_errors, d_rotation, d_moment = [], [], []
        if self.rotation_axes:
            reference = values @ patch.quaternions[local]
            reference = reference / np.linalg.norm(reference)
            # spatial small-rotation error R0 vec(conj(q0) q) (half angle times axis), linear
            # in q
            error = quaternion.rotation_matrix(reference) @ _rotation_error_matrix(reference)
            for axis in self.rotation_axes:
                row_error = axis @ error  # (4,)
                rotation_errors.append(row_error)
                d_rotation.append((values[:, None] * row_error[None, :]).reshape(1, -1))
                d_moment.append([(weights * axis[c])[:, None] for c in range(3)])
        kept = _SupportConstant(
            model=model,
            multipliers=multipliers,
            values=values,
            position_columns=layout.position_dofs(self.patch)[local],  # (p+1, 3)
            reference_position=values @ patch.centreline.control_points[local],
            d_position=values[None, :],
            load_rows=[DOFS_PER_POINT * points + c for c in range(6)],
            weights=weights,
            d_load=weights[:, None],
            quaternion_columns=quaternion_columns,
            rotation_errors=rotation_errors,
            d_rotation=d_rotation,
            d_moment=d_moment,
        )
        object.__setattr__(self, "_kept", kept)
        return kept


class _SupportConstant(NamedTuple):
    """What a `PointSupport`'s blocks take from its model (`PointSupport._constant`)."""

    model: "RodModel"
    multipliers: np.ndarray  # (3 + a,) state indices of the multipliers
    values: np.ndarray  # (p+1,) basis values at u*
    position_columns: np.ndarray  # (p+1, 3) state indices of the acting positions
    reference_position: np.ndarray  # (3,) the held position (mm)
    d_position: np.ndarray  # (1, p+1)
    load_rows: list  # (6,) of (k,): force rows c, then moment rows c, of the lumping points
    weights: np.ndarray  # (k,) lumping weights (1/mm)
    d_load: np.ndarray  # (k, 1)
    quaternion_columns: np.ndarray  # (p+1, 4) state indices of the acting quaternions
    rotation_errors: list  # per axis (4,): the row of the linear rotation error
    d_rotation: list  # per axis (1, 4(p+1))
    d_moment: list  # per axis, per component c: (k, 1)


def check_claims(conditions, layout: DofLayout) -> None:
    """Raise InputError unless every rod end is claimed by exactly one condition and the
    conditions' extra equations match the layout's extra unknowns."""
    claimed: dict[RodEnd, int] = {}
    for index, condition in enumerate(conditions):
        for given in condition.ends:
            end = RodEnd(int(given.patch), given.side)
            layout.end_point(end)  # validates patch and side
            if end in claimed:
                raise InputError(
                    f"rod end {end} is claimed by conditions {claimed[end]} and {index}"
                )
            claimed[end] = index
    missing = [
        RodEnd(k, side)
        for k in range(layout.n_patches)
        for side in (START, END)
        if RodEnd(k, side) not in claimed
    ]
    if missing:
        raise InputError(
            f"rod ends without a condition: {', '.join(str(end) for end in missing)} "
            "(use EndLoad for a free end)"
        )
    extra = sum(int(condition.extra_equations) for condition in conditions)
    if extra != layout.n_extra:
        raise InputError(
            f"conditions add {extra} extra equations for {layout.n_extra} extra unknowns"
        )
