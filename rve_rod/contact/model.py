"""Yarn-to-yarn contact at collocation points: line loads, friction and their linearization.

`ContactModel` is what a rod solver calls. Per evaluation (positions of all control points,
macro deformation gradient F):

1. broad phase: boxes of the knot spans from their control points, over the cell and the
   lattice images that can reach it (translated by F (i a1 + j a2)); a sweep finds the span
   pairs whose boxes come within the detection radius 2r + margin (`broad_phase`);
2. narrow phase: every collocation point of a candidate slave span is projected onto the
   candidate master spans (safeguarded Newton, `closest_point`); each local minimum of the
   distance on another part of the yarn or on an image is a contact candidate;
3. the compressible-yarn law gives the normal line load at each slave point with penetration
   g = 2r - d > 0, and penalty-regularized Coulomb friction the tangential one (`forces`);
4. the loads (3, m) are summed per collocation point, and their consistent derivatives are
   assembled with respect to the control points (sparse) and to F11, F12, F21, F22 (dense).

Every collocation point of every yarn acts as slave (two-pass): a point receives the load of
its own penetration only, never the reaction of another point's contact, which is how the
collocation scheme takes a line load. Friction history changes only on `commit`.
"""

import logging
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.sparse

from rve_rod.contact import _kernels
from rve_rod.contact.broad_phase import find_candidates, group_boxes, group_spans, select_images
from rve_rod.contact.closest_point import project
from rve_rod.contact.forces import (
    ANCHOR,
    MASTER,
    SLAVE,
    ContactLoads,
    Kinematics,
    contact_loads,
    kinematics,
)
from rve_rod.contact.friction import FrictionHistory, MacroTurn, match_anchors, sort_anchors
from rve_rod.contact.law import CompressibleYarnLaw, CoulombFriction
from rve_rod.contact.layout import (
    ContactLayout,
    Patch,
    PeriodicLattice,
    YarnChain,
    build_layout,
)
from rve_rod.contact.regions import (
    RegionWeights,
    StrandGeometry,
    StrandPoints,
    WeightTerms,
    region_weights,
)
from rve_rod.errors import InputError, check_integer, check_positive

__all__ = [
    "DEFORMATION_COMPONENTS",
    "ActiveContacts",
    "ContactDerivatives",
    "ContactModel",
    "ContactOptions",
    "ContactResult",
    "ContactStatistics",
]

logger = logging.getLogger(__name__)

DEFORMATION_COMPONENTS = ("F11", "F12", "F21", "F22")
"""Columns of `ContactResult.deformation_jacobian`."""

LUMPINGS = ("line", "point")
"""How the law's value acts on a slave point (`ContactOptions.lumping`)."""


@dataclass(frozen=True)
class ContactOptions:
    """Search settings.

    Attributes:
        search_margin: detection radius beyond touching, d < 2r + margin (mm); points within
            it get friction anchors before they touch. None: half the yarn radius.
        exclusion_arc_length: a distance minimum on the point's own yarn closer than this
            reference arc length to the point is adjacency, not contact, and is ignored (mm).
            None: four yarn radii.
        region_arc_length: minima of one slave point on one strand whose reference arc
            coordinates are closer than this to their neighbour's share one contact, weighted
            by their prominence (`rve_rod.contact.regions`) (mm). None: the exclusion arc
            length.
        max_image_shift: largest |i|, |j| of the lattice images searched (default 3).
        spans_per_box: consecutive knot spans bounded by one box in the broad phase (default
            8; 1 is one box per span). Changes the cost only, never the result.
        lumping: how the law acts at a slave point, one of LUMPINGS. "line" (default): the
            law's f_n(g) is the line load (N/mm) at the point. "point": r f_n(g) =
            k r^2/p (g/r)^p is a force (N) at the point, applied as the line load
            r f_n(g) / h_i with h_i the point's collocation weight (mm), friction scaled with
            it (k_t r N/mm per mm of slip); an experiment (docs/validation.md, issue 27),
            whose stiffness depends on the discretization through r / h_i.
        balance: apply each slave point's load also, reversed, to its master (default False:
            two-pass, each point loaded by its own penetration only). The reaction of the load
            q of slave point s (collocation weight w_s) at the master span's parameter tau is
            the line load -q w_s N_a(tau) / w_a at the span's collocation points a (control
            point a <-> collocation point a), and both passes act at half, so that the
            contact forces sum to zero by the collocation weights (action = reaction). An
            issue-27 experiment (docs/contact.md, "Approximation: action-reaction").
    """

    search_margin: float | None = None
    exclusion_arc_length: float | None = None
    region_arc_length: float | None = None
    max_image_shift: int = 3
    spans_per_box: int = 8
    lumping: str = "line"
    balance: bool = False

    def __post_init__(self):
        if self.search_margin is not None:
            check_positive("search_margin", self.search_margin, "mm")
        if self.exclusion_arc_length is not None:
            check_positive("exclusion_arc_length", self.exclusion_arc_length, "mm")
        if self.region_arc_length is not None:
            check_positive("region_arc_length", self.region_arc_length, "mm")
        check_integer("max_image_shift", self.max_image_shift, 1, 100)
        check_integer("spans_per_box", self.spans_per_box, 1)
        if not isinstance(self.balance, bool):
            raise InputError(f"balance={self.balance!r} must be True or False")
        if self.lumping not in LUMPINGS:
            raise InputError(
                f"lumping={self.lumping!r} is unknown; valid: {', '.join(map(repr, LUMPINGS))}"
            )


class ContactStatistics(NamedTuple):
    """Cost and state of one evaluation.

    Attributes:
        active_contacts: slave points in contact (pairs with penetration > 0).
        max_penetration: largest penetration g = 2r - d (mm), 0 without contact.
        images: lattice images searched (including the cell itself).
        box_pairs: (collocation point, span-group box) pairs found by the broad phase.
        span_tests: (collocation point, span) pairs the narrow phase examined (the spans of
            the candidate groups, own-yarn neighbours excluded).
        all_pairs: all (collocation point, span, image) pairs: what a search without broad
            phase would project.
        closest_points: local distance minima found within the detection radius.
        sticking, sliding: active contacts in stick and in slip (0 without friction).
        without_anchor: active contacts without a friction anchor (first touch this step).
        shared: distance minima that share one contact with a neighbouring minimum (regions of
            more than one minimum, `rve_rod.contact.regions`).
    """

    active_contacts: int
    max_penetration: float
    images: int
    box_pairs: int
    span_tests: int
    all_pairs: int
    closest_points: int
    sticking: int
    sliding: int
    without_anchor: int
    shared: int = 0


class ActiveContacts(NamedTuple):
    """The active contacts (arrays over k contacts).

    Attributes:
        slave: (k,) collocation point loaded by the contact.
        patch: (k,) master patch; parameter: (k,) master patch parameter u of the closest point.
        image: (k, 2) lattice image (i, j) of the master.
        penetration: (k,) g = 2r - d (mm).
        normal: (3, k) unit normal from master to slave.
        normal_load: (k,) f_n (N/mm), times the contact's region weight.
        friction_load: (3, k) f_t (N/mm), times the region weight; zeros without friction.
        weight: (k,) region weight of the contact, in [0, 1] (`rve_rod.contact.regions`).
        sliding: (k,) True where friction slips.
    """

    slave: np.ndarray
    patch: np.ndarray
    parameter: np.ndarray
    image: np.ndarray
    penetration: np.ndarray
    normal: np.ndarray
    normal_load: np.ndarray
    friction_load: np.ndarray
    sliding: np.ndarray
    weight: np.ndarray

    @property
    def load(self) -> np.ndarray:
        """(3, k) total line load f_n n + f_t of each contact on its slave point (N/mm)."""
        return self.normal_load * self.normal + self.friction_load


class ContactDerivatives(NamedTuple):
    """Derivatives of the loads of k active contacts, in the compact form their assemblies
    read: 3x3 blocks chained to the control points of their spans (`_kernels.block_entries`).

    Attributes:
        blocks: (4, 3, 3, b) d load / d (x_s, x_m, C', x_a) of b block sets: the k contacts'
            own (the weighted loads' derivatives), then one per region-weight term (the
            weight's derivative times the load; `rve_rod.contact.regions`) (N/mm^2).
        contact: (b,) the contact each block set belongs to: 0 ... k-1, then the terms'.
        chain: `_kernels.SpanChain` of the b block sets.
        deformation: (3k, 4) d load / d (F11, F12, F21, F22) per contact, row c k + i for
            component c of contact i (N/mm).
        slave: (k,) collocation point loaded by each contact.
        n_points: collocation points m; n_control_points: control points n.
    """

    blocks: np.ndarray
    contact: np.ndarray
    chain: _kernels.SpanChain
    deformation: np.ndarray
    slave: np.ndarray
    n_points: int
    n_control_points: int

    def entries(self, rows: np.ndarray, columns: np.ndarray) -> _kernels.CooEntries:
        """The COO entries (repeated entries to be summed) of d load / d positions in the
        numbering of the caller's matrix: component c of contact i in row rows[c, i] (left
        out where -1), coordinate j of control point a in column columns[a, j].

        Args:
            rows: (3, k) int; columns: (n, 3) int.
        """
        rows = np.ascontiguousarray(np.asarray(rows, dtype=np.int64)[:, self.contact])
        capacity = 27 * self.chain.basis.shape[1] * self.contact.size
        out = _kernels.CooEntries.empty(capacity)
        count = _kernels.block_entries(
            self.blocks, rows, np.asarray(columns, dtype=np.int64), self.chain, out
        )
        return _kernels.CooEntries(*(field[:count] for field in out))

    def matrix(self, rows: np.ndarray, n_rows: int) -> scipy.sparse.coo_matrix:
        """(n_rows, 3n) COO d load / d positions, component c of contact i in row rows[c, i],
        column 3a + j coordinate j of control point a."""
        n = self.n_control_points
        columns = 3 * np.arange(n)[:, None] + np.arange(3)[None, :]
        entries = self.entries(rows, columns)
        return scipy.sparse.coo_matrix(
            (entries.values, (entries.rows, entries.columns)), shape=(n_rows, 3 * n)
        )


@dataclass(frozen=True, eq=False)
class ContactResult:
    """Line loads at the collocation points and their derivatives.

    Attributes:
        line_load: (3, m) contact force per unit length at each collocation point (N/mm).
        derivatives: the derivatives of the active contacts' loads (`ContactDerivatives`,
            which assembles them into any matrix: `rve_rod.rve.coupling`), None if not
            requested; the properties below give them as matrices.
        contacts: the active contacts.
        statistics: counts of the search and of the contact states.
        trial_history: the friction anchors this state would leave if committed (None without
            friction).
        line_derivatives: the derivatives of `line_load` in the same form: `derivatives`
            itself for the two-pass contact; with `ContactOptions.balance`, half of them and
            the reactions on the masters as further contacts (their `slave` the masters'
            collocation points). None if not requested.
    """

    line_load: np.ndarray
    derivatives: ContactDerivatives | None
    contacts: ActiveContacts
    statistics: ContactStatistics
    trial_history: FrictionHistory | None
    line_derivatives: ContactDerivatives | None

    @property
    def jacobian(self) -> scipy.sparse.coo_matrix | None:
        """(3m, 3n) sparse d line_load / d positions in COO form with repeated entries (summed
        by `.tocsr()`; map `.row`, `.col` to global equations and dofs before assembling);
        row c m + j is line_load[c, j] (the C order of line_load, as the rod's LineLoads),
        column 3i + c is positions[i, c] (N/mm^2). None if not requested."""
        derivatives = self.line_derivatives
        if derivatives is None:
            return None
        m = derivatives.n_points
        rows = m * np.arange(3)[:, None] + derivatives.slave[None, :]
        return derivatives.matrix(rows, 3 * m)

    @property
    def deformation_jacobian(self) -> np.ndarray | None:
        """(3m, 4) d line_load / d (F11, F12, F21, F22) (N/mm), rows as in `jacobian`. None if
        not requested."""
        derivatives = self.line_derivatives
        if derivatives is None:
            return None
        slave, k = derivatives.slave, derivatives.slave.size
        per_contact = derivatives.deformation.reshape(3, k, 4).transpose(0, 2, 1).reshape(12, k)
        summed = _sum_per_point(slave, per_contact, derivatives.n_points)
        return summed.reshape(3, 4, -1).transpose(0, 2, 1).reshape(-1, 4)

    @property
    def contact_jacobian(self) -> scipy.sparse.coo_matrix | None:
        """(3k, 3n) sparse COO d load / d positions of each active contact (row c k + i is
        component c of contact i's load, `ActiveContacts.load`), for callers that weight
        contacts individually (e.g. by their lattice image, as the macro stress of the
        periodic cell does). None if not requested."""
        derivatives = self.derivatives
        if derivatives is None:
            return None
        k = derivatives.slave.size
        return derivatives.matrix(k * np.arange(3)[:, None] + np.arange(k)[None, :], 3 * k)

    @property
    def contact_deformation_jacobian(self) -> np.ndarray | None:
        """(3k, 4) d load / d (F11, F12, F21, F22) per contact, rows as in
        `contact_jacobian`. None if not requested."""
        return None if self.derivatives is None else self.derivatives.deformation


class _Anchors(NamedTuple):
    """Friction anchors of the active contacts (span -1: no anchor)."""

    span: np.ndarray  # (k,)
    tau: np.ndarray  # (k,)
    shift: np.ndarray  # (k, 3) reference lattice shift of the anchor's image
    slip_vector: np.ndarray  # (3, k) w = x_s - x_a - R o (mm), zero without anchor
    turning: np.ndarray  # (3, k, 4) d(R o) / d(F11, F12, F21, F22) (mm)

    @classmethod
    def none(cls, k: int) -> "_Anchors":
        """k contacts without anchors."""
        return cls(
            np.full(k, -1), np.zeros(k), np.zeros((k, 3)), np.zeros((3, k)), np.zeros((3, k, 4))
        )


class _SearchCounts(NamedTuple):
    """Cost counts of one search (see ContactStatistics)."""

    images: int
    box_pairs: int
    span_tests: int
    all_pairs: int


class _Selection(NamedTuple):
    """Closest points of one evaluation (arrays over the k detected pairs)."""

    slave: np.ndarray  # (k,) collocation point
    span: np.ndarray  # (k,) master span
    tau: np.ndarray  # (k,) local parameter of the closest point
    image: np.ndarray  # (k, 2) lattice image
    shift: np.ndarray  # (k, 3) reference lattice shift of the image
    strand: np.ndarray  # (k,) strand key of the master
    arc: np.ndarray  # (k,) unwrapped reference arc coordinate of the closest point (mm)
    state: Kinematics
    counts: _SearchCounts

    def subset(self, rows: np.ndarray) -> "_Selection":
        """The pairs `rows` (an index array)."""
        return _Selection(
            slave=self.slave[rows],
            span=self.span[rows],
            tau=self.tau[rows],
            image=self.image[rows],
            shift=self.shift[rows],
            strand=self.strand[rows],
            arc=self.arc[rows],
            state=Kinematics(*(field[..., rows] for field in self.state)),
            counts=self.counts,
        )


class ContactModel:
    """Contact between yarn centrelines given as B-spline patches, with periodic images.

    Args:
        patches: the B-spline patches of all yarns (one degree), in global numbering order.
        reference_positions: (n_total, 3) control points of the reference configuration (mm);
            arc lengths and collocation weights are measured on it, and with friction the
            contacts of this configuration (at F = I) are committed as the first anchors.
        law: the normal contact law (it carries the yarn radius r).
        friction: Coulomb friction, or None (also skipped when its coefficient is 0).
        lattice: the periodic cell, or None for a scene without images.
        yarns: how patches chain into yarns. Default: one yarn of all patches in order,
            continuing into image (1, 0) if a lattice is given, open otherwise.
        options: search settings.
    """

    def __init__(
        self,
        patches: list[Patch],
        reference_positions: np.ndarray,
        law: CompressibleYarnLaw,
        *,
        friction: CoulombFriction | None = None,
        lattice: PeriodicLattice | None = None,
        yarns: list[YarnChain] | None = None,
        options: ContactOptions | None = None,
    ):
        self.options = ContactOptions() if options is None else options
        if yarns is None:
            period = (1, 0) if lattice is not None else None
            yarns = [YarnChain(tuple(range(len(patches))), period)]
        if lattice is None and any(yarn.period is not None for yarn in yarns):
            raise InputError("a periodic yarn chain needs a lattice")
        self.layout: ContactLayout = build_layout(list(patches), list(yarns), reference_positions)
        self.law = law
        self.lattice = lattice
        self.friction = friction if friction is not None and friction.coefficient > 0 else None
        radius = law.yarn_radius
        margin = self.options.search_margin
        self.search_margin = 0.5 * radius if margin is None else margin
        exclusion = self.options.exclusion_arc_length
        self.exclusion_arc_length = 4.0 * radius if exclusion is None else exclusion
        region = self.options.region_arc_length
        self.region_arc_length = self.exclusion_arc_length if region is None else region
        self._groups = group_spans(self.layout, self.options.spans_per_box)
        point_yarn = self.layout.span_yarn[self.layout.point_span]
        self._slave_strands, _ = self.layout.strands(
            point_yarn, np.zeros((point_yarn.size, 2), dtype=np.int64)
        )
        self._history = FrictionHistory.empty()
        self._sorted_anchors: tuple | None = None  # (history, sort_anchors(history))
        self.anchor_at(reference_positions, np.eye(3))

    @property
    def n_control_points(self) -> int:
        return self.layout.n_control_points

    @property
    def n_collocation_points(self) -> int:
        return self.layout.n_points

    @property
    def collocation_weights(self) -> np.ndarray:
        """(m,) reference arc length each collocation point represents (mm)."""
        return self.layout.collocation_weights

    @property
    def history(self) -> FrictionHistory:
        """The committed friction anchors."""
        return self._history

    def commit(self, result: ContactResult) -> None:
        """Adopt the friction anchors of a converged evaluation (no-op without friction)."""
        if self.friction is not None:
            self._history = result.trial_history

    def anchor_at(self, positions: np.ndarray, deformation_gradient: np.ndarray) -> None:
        """Make the contacts of this configuration the friction anchors, each at its own
        closest point (no slip): a state the path starts from (no-op without friction)."""
        if self.friction is not None:
            self._history = FrictionHistory.empty()
            here = self.evaluate(positions, deformation_gradient, tangent=False)
            self._history = here.trial_history

    def use_law(self, law: CompressibleYarnLaw) -> None:
        """Evaluate with `law` from now on (a contact radius grown towards the yarn's own:
        `rve_rod.rve.cell.LoopCell.rest_state`); the search settings derived from the first
        law's radius are kept."""
        self.law = law

    def evaluate(
        self,
        positions: np.ndarray,
        deformation_gradient: np.ndarray | None = None,
        *,
        tangent: bool = True,
    ) -> ContactResult:
        """Line loads (and derivatives) for control points (n_total, 3) and macro F (3, 3).

        positions may also be a list of per-patch (n_k, 3) arrays. F defaults to the
        identity; it only moves the lattice images. The committed history is not changed.
        """
        points = self._positions(positions)
        deformation = self._deformation(deformation_gradient)
        layout = self.layout
        slave_points = layout.collocation_positions(points)
        coefficients = layout.coefficients(points)
        detected = self._closest_points(points, coefficients, slave_points, deformation)
        regions = self._region_weights(coefficients, slave_points, deformation, detected)
        radius = self.law.yarn_radius
        active_rows = np.flatnonzero(detected.state.distance < 2.0 * radius)
        active = detected.subset(active_rows)
        k = active_rows.size
        anchors = _Anchors.none(k)
        if self.friction is not None:
            turn = MacroTurn.of(deformation)
            anchors = self._anchors(points, slave_points, deformation, turn, active)
        loads = contact_loads(
            active.state, self.law, self.friction, anchors.slip_vector, anchors.span >= 0
        )
        trial_history = None
        if self.friction is not None:
            trial_history = self._trial_history(detected, active_rows, loads, turn)
        if self.options.lumping == "point":
            loads = _as_point_forces(loads, radius / layout.collocation_weights[active.slave])
        weight = regions.weight[active_rows]
        weighted = loads._replace(
            load=loads.load * weight,
            normal_force=loads.normal_force * weight,
            friction_load=loads.friction_load * weight,
            blocks=loads.blocks * weight,
        )
        line_load = _sum_per_point(active.slave, weighted.load, layout.n_points)
        derivatives = None
        if tangent:
            terms = _active_terms(regions.terms, active_rows, detected.slave.size)
            derivatives = self._linearization(weighted, active, anchors, loads.load, terms)
        line_derivatives = derivatives
        if self.options.balance:
            line_load, line_derivatives = self._balanced(
                line_load, weighted.load, active, derivatives
            )
        penetration = 2.0 * radius - active.state.distance
        contacts = ActiveContacts(
            slave=active.slave,
            patch=layout.span_patch[active.span],
            parameter=layout.span_start[active.span] + active.tau * layout.span_length[active.span],
            image=active.image,
            penetration=penetration,
            normal=active.state.normal,
            normal_load=weighted.normal_force,
            friction_load=weighted.friction_load,
            sliding=loads.sliding,
            weight=weight,
        )
        counts = detected.counts
        anchored = anchors.span >= 0
        friction_on = self.friction is not None
        statistics = ContactStatistics(
            active_contacts=int(k),
            max_penetration=float(penetration.max()) if k else 0.0,
            images=counts.images,
            box_pairs=counts.box_pairs,
            span_tests=counts.span_tests,
            all_pairs=counts.all_pairs,
            closest_points=int(detected.slave.size),
            sticking=int(np.count_nonzero(anchored & ~loads.sliding)) if friction_on else 0,
            sliding=int(np.count_nonzero(loads.sliding)),
            without_anchor=int(np.count_nonzero(~anchored)) if friction_on else 0,
            shared=regions.shared,
        )
        logger.debug(
            "contact: %d active (%d sliding), max penetration %.3g mm, %d span tests of %d",
            statistics.active_contacts,
            statistics.sliding,
            statistics.max_penetration,
            statistics.span_tests,
            statistics.all_pairs,
        )
        return ContactResult(
            line_load=line_load,
            derivatives=derivatives,
            contacts=contacts,
            statistics=statistics,
            trial_history=trial_history,
            line_derivatives=line_derivatives,
        )

    def _anchors(
        self, points, slave_points, deformation, turn: MacroTurn, active: _Selection
    ) -> _Anchors:
        """The committed anchors of the active contacts and their slip vectors."""
        history = self._history
        if self._sorted_anchors is None or self._sorted_anchors[0] is not history:
            self._sorted_anchors = (history, sort_anchors(history))
        anchor = match_anchors(
            self._sorted_anchors[1],
            active.slave,
            active.strand,
            active.arc,
            self.exclusion_arc_length,
        )
        rows = np.flatnonzero(anchor >= 0)
        anchor = anchor[rows]
        anchors = _Anchors.none(active.slave.size)
        anchors.span[rows] = history.span[anchor]
        anchors.tau[rows] = history.tau[anchor]
        anchors.shift[rows] = self._shifts(history.image[anchor])
        anchor_points = (
            self._span_points(points, anchors.span[rows], anchors.tau[rows])
            + (anchors.shift[rows] @ deformation.T).T
        )
        offset = history.offset[:, anchor]
        anchors.slip_vector[:, rows] = (
            slave_points[:, active.slave[rows]] - anchor_points - turn.rotation @ offset
        )
        anchors.turning[:, rows] = (turn.rate @ offset)[:, :, None] * turn.gradient
        return anchors

    # -- search -------------------------------------------------------------------------------

    def _closest_points(self, points, coefficients, slave_points, deformation) -> _Selection:
        """Distance minima within the detection radius, own-yarn adjacency excluded;
        coefficients: the spans' (`ContactLayout.coefficients` of points)."""
        layout = self.layout
        radius = self.law.yarn_radius
        reach = 2.0 * radius + self.search_margin
        boxes = group_boxes(layout, self._groups, points)
        images = select_images(
            boxes, self.lattice, deformation, reach, self.options.max_image_shift
        )
        translations = self._shifts(images) @ deformation.T
        candidates = find_candidates(
            layout,
            self._groups,
            boxes,
            slave_points=slave_points,
            slave_strands=self._slave_strands,
            images=images,
            translations=translations,
            reach=reach,
            exclusion_arc_length=self.exclusion_arc_length,
        )
        targets = slave_points[:, candidates.slave] - translations[candidates.image].T
        found = project(
            coefficients,
            self._groups.spans,
            layout.span_next,
            layout.span_closed_end,
            groups=candidates.group,
            targets=targets,
            reach=reach,
        )
        # Keep minima within the detection radius that are not adjacency along the own yarn
        # (which includes every point's zero-distance minimum on itself).
        slave = candidates.slave[found.candidate]
        image = candidates.image[found.candidate]
        master = found.point + translations[image].T
        distance = np.linalg.norm(slave_points[:, slave] - master, axis=0)
        near = np.flatnonzero(distance < reach)
        span, tau, image, slave = (
            found.span[near],
            found.tau[near],
            images[image[near]],
            slave[near],
        )
        strand, shift = layout.strands(layout.span_yarn[span], image)
        arc = layout.span_arc_start[span] + tau * layout.span_arc_length[span] + shift
        apart = (strand != self._slave_strands[slave]) | (
            np.abs(arc - layout.point_arc[slave]) >= self.exclusion_arc_length
        )
        keep = near[apart]
        state = kinematics(
            slave_points[:, slave[apart]],
            master[:, keep],
            found.tangent[:, keep],
            found.curvature[:, keep],
        )
        # A zero distance or a degenerate minimum (H <= 0) has no normal: skip it.
        valid = (state.distance > 1e-12 * radius) & (state.metric > 0)
        image = image[apart][valid]
        return _Selection(
            slave=slave[apart][valid],
            span=span[apart][valid],
            tau=tau[apart][valid],
            image=image,
            shift=self._shifts(image),
            strand=strand[apart][valid],
            arc=arc[apart][valid],
            state=Kinematics(*(field[..., valid] for field in state)),
            counts=_SearchCounts(
                images=int(images.shape[0]),
                box_pairs=candidates.box_pairs,
                span_tests=int(self._groups.spans[1][candidates.group].sum()),
                all_pairs=candidates.all_pairs,
            ),
        )

    def _region_weights(self, coefficients, slave_points, deformation, detected) -> RegionWeights:
        """Region weights of the detected minima (`rve_rod.contact.regions`)."""
        geometry = StrandGeometry(
            self.layout, coefficients, self._shifts(np.eye(2, dtype=np.int64)) @ deformation.T
        )
        minima = StrandPoints(
            slave=detected.slave,
            span=detected.span,
            tau=detected.tau,
            image=detected.image,
            arc=detected.arc,
            strand=detected.strand,
            distance=detected.state.distance,
            normal=detected.state.normal,
        )
        return region_weights(
            geometry, slave_points, minima, self.law.yarn_radius, self.region_arc_length
        )

    def _shifts(self, images: np.ndarray) -> np.ndarray:
        """Reference lattice shifts (k, 3) of images (k, 2); zeros without a lattice."""
        if self.lattice is None:
            return np.zeros((images.shape[0], 3))
        return self.lattice.shifts(images)

    def _span_points(self, points, spans, tau):
        """Curve points (3, k) at local parameters tau of spans, in the cell."""
        basis = self.layout.basis(spans, tau)
        out = np.empty((3, spans.size))
        _kernels.point_positions(points, self.layout.span_first[spans], basis, out)
        return out

    def _trial_history(
        self, detected: _Selection, active_rows, loads: ContactLoads, turn: MacroTurn
    ):
        """Anchors of all detected pairs: offset v - g_e (g_e = 0 where there is no friction),
        turned back by the macro turn of F (`MacroTurn`)."""
        offset = detected.state.gap_vector.copy()
        offset[:, active_rows] -= loads.elastic_slip
        offset = turn.rotation.T @ offset
        return FrictionHistory(
            slave=detected.slave,
            strand=detected.strand,
            arc=detected.arc,
            span=detected.span,
            tau=detected.tau,
            image=detected.image,
            offset=offset,
        )

    # -- linearization --------------------------------------------------------------------------

    def _balanced(
        self,
        line_load: np.ndarray,
        load: np.ndarray,
        active: _Selection,
        derivatives: ContactDerivatives | None,
    ) -> tuple[np.ndarray, ContactDerivatives | None]:
        """The line loads of `ContactOptions.balance` and their derivatives: half the two-pass
        `line_load` (3, m) plus the reactions of the k contacts' loads `load` (3, k) on their
        masters, and `derivatives` (of the k loads) extended by the reactions as k (p+1)
        further contacts, contact j's reaction on its master span's control point a being
        contact k + j (p+1) + a. With r_ja = c_ja q_j, c_ja = -w_s N_a(tau) / (2 w_a):
        dr_ja = c_ja dq_j + c'_ja q_j dtau, c'_ja = -w_s N_a'(tau) / (2 w_a), and
        dtau = [C'.(dx_s - dx_m) + v.dC'] / H (`rve_rod.contact.forces`)."""
        layout = self.layout
        weights = layout.collocation_weights
        width = layout.degree + 1
        k = active.slave.size
        points = layout.span_first[active.span][:, None] + np.arange(width)  # (k, p+1)
        scale = -0.5 * weights[active.slave][:, None] / weights[points]
        value = scale * layout.basis(active.span, active.tau)  # c_ja
        reaction = load[:, :, None] * value[None]  # (3, k, p+1)
        balanced = 0.5 * line_load + _sum_per_point(
            points.ravel(), reaction.reshape(3, -1), layout.n_points
        )
        if derivatives is None:
            return balanced, None
        slope = scale * layout.basis(active.span, active.tau, 1)  # c'_ja
        state = active.state
        # dtau / d(x_s, x_m, C') as rows (3, k) each: C'/H, -C'/H, v/H
        sensitivity = (
            np.stack(
                [state.tangent, -state.tangent, state.gap_vector, np.zeros_like(state.tangent)]
            )
            / state.metric
        )  # (4, 3, k)
        sets = derivatives.contact  # (b,) the contact of each block set
        blocks = derivatives.blocks[..., :, None] * value[sets][None, None, None]  # (4,3,3,b,p+1)
        own = np.arange(k)
        blocks[..., own, :] += np.einsum("ck,rdk,ka->rcdka", load, sensitivity, slope)
        repeat = np.repeat(np.arange(sets.size), width)
        chain = derivatives.chain
        by_deformation = derivatives.deformation.reshape(3, k, 4)
        # dtau / dF_ab = -C'_a L_b / H, columns (F11, F12, F21, F22)
        tau_by_deformation = -(
            state.tangent[[0, 0, 1, 1]] * active.shift[:, [0, 1, 0, 1]].T / state.metric
        ).T
        reaction_by_deformation = (
            by_deformation[:, :, None, :] * value[None, :, :, None]
            + load[:, :, None, None]
            * slope[None, :, :, None]
            * tau_by_deformation[None, :, None, :]
        ).reshape(3, k * width, 4)
        extended = ContactDerivatives(
            blocks=np.concatenate([0.5 * derivatives.blocks, blocks.reshape(4, 3, 3, -1)], axis=-1),
            contact=np.concatenate(
                [sets, k + (sets[:, None] * width + np.arange(width)).ravel()]
            ).astype(np.int64),
            chain=_kernels.SpanChain(
                np.ascontiguousarray(np.concatenate([chain.first, chain.first[:, repeat]], axis=1)),
                np.ascontiguousarray(
                    np.concatenate([chain.basis, chain.basis[..., repeat]], axis=2)
                ),
            ),
            deformation=np.concatenate(
                [0.5 * by_deformation, reaction_by_deformation], axis=1
            ).reshape(-1, 4),
            slave=np.concatenate([active.slave, points.ravel()]),
            n_points=derivatives.n_points,
            n_control_points=derivatives.n_control_points,
        )
        return balanced, extended

    def _linearization(
        self,
        loads: ContactLoads,
        active: _Selection,
        anchors: _Anchors,
        unweighted: np.ndarray,
        terms: WeightTerms,
    ) -> ContactDerivatives:
        """The derivatives of the contact loads from their 3x3 derivative blocks.

        A load at slave point j depends on the control points a of its own span through
        x_s = sum_a N_a(tau_j) P_a, on those of the master span through x_m = sum_b N_b P_b + F L
        and C' = sum_b N_b' P_b, and on the anchor span's through x_a = sum_c N_c P_c + F L_a.
        loads are the weighted loads w l (blocks w dl); the weight derivatives add
        l c n_q^T (dx_s - dx_q) per term (`unweighted`: (3, k) the loads l), one block set each.
        """
        slave, span, tau, shift = active.slave, active.span, active.tau, active.shift
        layout = self.layout
        k, t = slave.size, terms.contact.size
        anchored = np.flatnonzero(anchors.span >= 0)
        outer = np.einsum(
            "ct,dt->cdt", unweighted[:, terms.contact] * terms.coefficient, terms.normal
        )
        blocks = np.zeros((4, 3, 3, k + t))
        blocks[..., :k] = loads.blocks
        blocks[SLAVE, ..., k:] = outer
        blocks[MASTER, ..., k:] = -outer
        slaves = np.concatenate([slave, slave[terms.contact]])
        first = np.full((3, k + t), -1)
        first[0] = layout.span_first[layout.point_span[slaves]]
        first[1] = layout.span_first[np.concatenate([span, terms.span])]
        first[2, anchored] = layout.span_first[anchors.span[anchored]]
        basis = np.zeros((4, k + t, layout.degree + 1))
        basis[0] = layout.point_basis[slaves]
        basis[1, :k] = layout.basis(span, tau)
        basis[1, k:] = layout.basis(terms.span, terms.tau)
        basis[2, :k] = layout.basis(span, tau, 1)
        basis[3, anchored] = layout.basis(anchors.span[anchored], anchors.tau[anchored])
        chain = _kernels.SpanChain(first, np.ascontiguousarray(basis.transpose(0, 2, 1)))
        # d load / d F_ab = (d load / d x_m)[:, a] L_b + (d load / d x_a)[:, a] L_a,b
        #   + (d load / d x_a) dR/dtheta o dtheta / dF_ab (the offset turns with F: w = x_s -
        #   x_a - R o, so d load / d(R o) = d load / d x_a).
        deformation = (
            _outer(loads.blocks[MASTER][:, :2], shift[:, :2])
            + _outer(loads.blocks[ANCHOR][:, :2], anchors.shift[:, :2])
        ).reshape(3, k, 4) + np.einsum("ijt,jtm->itm", loads.blocks[ANCHOR], anchors.turning)
        if t:
            extra = np.einsum(
                "iat,tb->tiab", -outer[:, :2], self._shifts(terms.image)[:, :2]
            ).reshape(t, 3, 4)
            np.add.at(deformation, (slice(None), terms.contact), extra.transpose(1, 0, 2))
        return ContactDerivatives(
            blocks=blocks,
            contact=np.concatenate([np.arange(k), terms.contact]).astype(np.int64),
            chain=chain,
            deformation=deformation.reshape(3 * k, 4),
            slave=slave,
            n_points=layout.n_points,
            n_control_points=layout.n_control_points,
        )

    # -- input checks ---------------------------------------------------------------------------

    def _positions(self, positions) -> np.ndarray:
        if isinstance(positions, list | tuple):
            positions = np.concatenate([np.asarray(p, dtype=float) for p in positions])
        points = np.asarray(positions, dtype=float)
        expected = (self.layout.n_control_points, 3)
        if points.shape != expected:
            raise InputError(f"positions have shape {points.shape}, expected {expected}")
        if not np.all(np.isfinite(points)):
            raise InputError("positions contain NaN or infinite values")
        return points

    @staticmethod
    def _deformation(deformation_gradient) -> np.ndarray:
        if deformation_gradient is None:
            return np.eye(3)
        deformation = np.asarray(deformation_gradient, dtype=float)
        if deformation.shape != (3, 3) or not np.all(np.isfinite(deformation)):
            raise InputError(
                f"deformation_gradient must be a finite (3, 3) array, got {deformation.shape}"
            )
        return deformation


def _active_terms(terms: WeightTerms, active_rows: np.ndarray, detected: int) -> WeightTerms:
    """The weight terms of active contacts, their `contact` renumbered to active indices."""
    index = np.full(detected, -1)
    index[active_rows] = np.arange(active_rows.size)
    contact = index[terms.contact]
    keep = contact >= 0
    return WeightTerms(
        contact=contact[keep],
        span=terms.span[keep],
        tau=terms.tau[keep],
        image=terms.image[keep],
        normal=terms.normal[:, keep],
        coefficient=terms.coefficient[keep],
    )


def _as_point_forces(loads: ContactLoads, scale: np.ndarray) -> ContactLoads:
    """The loads of `ContactOptions.lumping = "point"`: each contact's line load, friction and
    derivative blocks times scale = r / h_i (k,), i.e. the force r l at the slave point spread
    over its collocation weight h_i. Stick or slip and the elastic slip do not change (the
    normal force and the tangential stiffness scale together)."""
    return loads._replace(
        load=loads.load * scale,
        normal_force=loads.normal_force * scale,
        friction_load=loads.friction_load * scale,
        blocks=loads.blocks * scale,
    )


def _outer(blocks: np.ndarray, shifts: np.ndarray) -> np.ndarray:
    """(3, k, 2, 2) blocks[i, a, k] shifts[k, b] from blocks (3, 2, k) and shifts (k, 2)."""
    return blocks.transpose(0, 2, 1)[:, :, :, None] * shifts[None, :, None, :]


def _sum_per_point(points: np.ndarray, values: np.ndarray, n_points: int) -> np.ndarray:
    """Sum columns of values (c, k) that belong to the same point: (c, n_points)."""
    index = (np.arange(values.shape[0])[:, None] * n_points + points[None, :]).ravel()
    total = np.bincount(index, weights=values.ravel(), minlength=values.shape[0] * n_points)
    return total.reshape(values.shape[0], n_points)
