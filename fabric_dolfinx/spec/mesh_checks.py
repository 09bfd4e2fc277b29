"""Checks of a part's mesh before anything is solved on it (no DOLFINx): the `.geo` file's
parameters, the size budget, and the mesh itself (one conforming piece, no degenerate cell,
in the x-y plane for a plane part).

- **Parameters** (`check_geo_parameters`): gmsh's `-setnumber` sets a `.geo` variable only
  where the file declares it with `DefineConstant`; a name the file does not declare, or sets
  with a plain assignment, was silently ignored. A parameter is a length or a size: it must be
  > 0 unless its `DefineConstant` declares a range (`Min`, `Max`), which it must then lie in
  (a mesh size of 0 was ignored by gmsh, a negative one aborted it).
- **Size budget** (`check_cells`, `estimated_geo_cells`): a part has at most
  `rve_rod.limits.PART_CELLS` cells, refinements counted, refused before the 2D meshing on
  an estimate that does not exceed the count (a built-in shape's from its area and element
  size, `shape_cells`; a `.geo` file's from its boundary meshed in 1D), and after it on the
  count. An element size 1e4 times too small used to end in `std::bad_alloc`, a hang or a
  traceback after minutes.
- **The mesh** (`mesh_problems`, on the nodes and quadrilaterals): surfaces must share their
  interface curves (a boundary edge lying on another boundary edge is a seam that does not
  connect: two surfaces drawn with duplicated interface lines carried no load across it, and
  the forces came out as 1e-17 N); the mesh is one piece; every corner of every quadrilateral
  turns the same way with an angle between 1 and 179 degrees (scaled Jacobian above
  `MIN_SCALED_JACOBIAN`); a plane part lies in the x-y plane.
"""

import math
import re
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from rve_rod.errors import InputError
from rve_rod.limits import PART_CELLS

__all__ = [
    "MEMORY_PER_CELL_MB",
    "MIN_SCALED_JACOBIAN",
    "check_cells",
    "check_geo_parameters",
    "check_gmsh_mesh",
    "estimated_geo_cells",
    "geo_parameters",
    "mesh_problems",
]

MIN_SCALED_JACOBIAN = math.sin(math.radians(1.0))
"""The smallest scaled Jacobian (sine of the corner angle) of a quadrilateral's corner."""

MEMORY_PER_CELL_MB = 358.0 / 40_000
"""Memory of the membrane's solve per cell at degree 1 (MB): 358 MB for the 200 x 200 patch
(80 802 unknowns, MUMPS on one rank, docs/benchmarks.md); the budget's estimate."""


def geo_parameters(path: Path | str) -> dict[str, tuple[float | None, float | None]]:
    """The parameters a `.geo` file declares with `DefineConstant` (its `Include`d files too):
    name -> (Min, Max) as declared, None for a bound it does not declare."""
    path = Path(path)
    text = _without_comments(path.read_text(encoding="utf-8", errors="replace"))
    found: dict[str, tuple[float | None, float | None]] = {}
    for include in re.finditer(r'\bInclude\s+"([^"]+)"', text):
        included = path.parent / include.group(1)
        if included.is_file() and included != path:
            found.update(geo_parameters(included))
    for start in re.finditer(r"\bDefineConstant\s*\[", text):
        body = _bracketed(text, start.end() - 1)
        for item in _top_level_items(body):
            named = re.match(r"\s*([A-Za-z_]\w*)\s*=(.*)", item, re.DOTALL)
            if named is None:
                continue
            low = re.search(r"\bMin\s+([-+]?[\d.]+(?:[eE][-+]?\d+)?)", named.group(2))
            high = re.search(r"\bMax\s+([-+]?[\d.]+(?:[eE][-+]?\d+)?)", named.group(2))
            found[named.group(1)] = (
                float(low.group(1)) if low else None,
                float(high.group(1)) if high else None,
            )
    return found


def _without_comments(text: str) -> str:
    """`.geo` text without // and /* */ comments (strings kept)."""
    pattern = r'("(?:\\.|[^"\\])*")|//[^\n]*|/\*.*?\*/'
    return re.sub(pattern, lambda m: m.group(1) or " ", text, flags=re.DOTALL)


def _bracketed(text: str, opening: int) -> str:
    """The text inside the bracket at `opening` up to its matching one."""
    depth = 0
    for index in range(opening, len(text)):
        if text[index] in "[{(":
            depth += 1
        elif text[index] in "]})":
            depth -= 1
            if depth == 0:
                return text[opening + 1 : index]
    return text[opening + 1 :]


def _top_level_items(body: str) -> list[str]:
    """The `name = value` items of a DefineConstant's body: each starts at a `name =` outside
    brackets and strings (gmsh takes commas or line breaks between them)."""
    depth, quoted, starts = 0, False, []
    for index, character in enumerate(body):
        if character == '"':
            quoted = not quoted
        elif quoted:
            continue
        elif character in "[{(":
            depth += 1
        elif character in "]})":
            depth -= 1
        elif depth == 0 and re.match(r"[A-Za-z_]\w*\s*=(?!=)", body[index:]):
            before = body[:index].rstrip()
            if not before or before[-1] in ",}])" or before[-1].isdigit():
                starts.append(index)
    return [body[a:b] for a, b in zip(starts, [*starts[1:], len(body)], strict=True)]


def check_geo_parameters(path: Path | str, parameters: dict[str, float]) -> list[str]:
    """The problems of `parameters` for the `.geo` file at `path`, one per parameter (see the
    module docstring): "size: ..." naming the parameter, its value and what is valid."""
    if not parameters:
        return []
    if Path(path).suffix != ".geo":
        return [f"{', '.join(parameters)}: a .msh file has no parameters (only a .geo file)"]
    declared = geo_parameters(path)
    listed = ", ".join(sorted(declared)) or "none"
    problems = []
    for name, value in parameters.items():
        if name not in declared:
            problems.append(
                f"{name}: {Path(path).name} declares no parameter {name!r} (its DefineConstant "
                f"parameters: {listed}); a variable set with a plain assignment cannot be set"
            )
        elif not math.isfinite(value):
            problems.append(f"{name}: {value} is not a finite number")
        else:
            low, high = declared[name]
            if low is None and high is None and value <= 0.0:
                problems.append(
                    f"{name}: {value:g} must be > 0 (a .geo parameter is a length or a size "
                    "unless its DefineConstant declares Min and Max)"
                )
            elif (low is not None and value < low) or (high is not None and value > high):
                low, high = (
                    (-math.inf if low is None else low),
                    (math.inf if high is None else high),
                )
                problems.append(
                    f"{name}: {value:g} is outside the range [{low:g}, {high:g}] that "
                    f"{Path(path).name} declares"
                )
    return problems


def check_cells(what: str, cells: float, refinements: int) -> None:
    """InputError when `cells` before `refinements` (each x 4) exceed the budget
    (`rve_rod.limits.PART_CELLS`); `what` says where the count comes from."""
    total = cells * 4.0**refinements
    if total <= PART_CELLS:
        return
    refined = f" after {refinements} refinement(s)" if refinements else ""
    memory = total * MEMORY_PER_CELL_MB / 1000.0
    raise InputError(
        f"{what} gives about {total:.3g} cells{refined} (about {memory:.3g} GB for the solver); "
        f"a part may have at most {PART_CELLS} cells (rve_rod.limits.PART_CELLS, "
        f"{PART_CELLS * MEMORY_PER_CELL_MB / 1000.0:.2g} GB)"
    )


def estimated_geo_cells(budget: int = PART_CELLS) -> float:
    """At least how many cells the current gmsh model (geometry only, not meshed) will have,
    from its boundary meshed in 1D: per surface, its area (the boundary polygon's vector
    area) over the square of its boundary segments' mean length. Structured surfaces get
    about that many; unstructured recombined ones up to 8 times more (gmsh 4.8 splits the
    triangles), and a curved surface's projected area is smaller than its own, so the count
    after meshing has the last word. The 1D mesh is removed; `Mesh.MeshSizeMin` is raised to
    half the edge of `budget` square cells filling the bounding box, so that no meshing of
    the model can run away (at most about 4 times the budget, times gmsh's splitting)."""
    from fabric_dolfinx.gmsh_api import gmsh  # noqa: PLC0415 (gmsh only for meshes)

    box = np.array(gmsh.model.getBoundingBox(-1, -1)).reshape(2, 3)
    extents = np.sort(box[1] - box[0])[::-1]
    floor = math.sqrt(max(extents[0] * extents[1], extents[0] ** 2 * 1e-6) / budget) / 2.0
    size_min = gmsh.option.getNumber("Mesh.MeshSizeMin")
    gmsh.option.setNumber("Mesh.MeshSizeMin", max(size_min, floor))
    gmsh.model.mesh.generate(1)
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    coordinates = dict(zip(tags, np.reshape(xyz, (-1, 3)), strict=True))
    cells = 0.0
    for _, surface in gmsh.model.getEntities(2):
        vector_area, lengths = np.zeros(3), []
        for _, curve in gmsh.model.getBoundary([(2, surface)], combined=False, oriented=True):
            types, _, nodes = gmsh.model.mesh.getElements(1, abs(curve))
            for kind, element_nodes in zip(types, nodes, strict=True):
                count = gmsh.model.mesh.getElementProperties(kind)[3]
                pairs = np.reshape(element_nodes, (-1, count))[:, :2]
                start = np.array([coordinates[n] for n in pairs[:, 0]])
                end = np.array([coordinates[n] for n in pairs[:, 1]])
                vector_area += math.copysign(0.5, curve) * np.cross(start, end).sum(axis=0)
                lengths.extend(np.linalg.norm(end - start, axis=1))
        if lengths:
            cells += float(np.linalg.norm(vector_area)) / float(np.mean(lengths)) ** 2
    gmsh.model.mesh.clear()
    return cells


def mesh_problems(points: np.ndarray, quads: np.ndarray, *, plane: bool) -> list[str]:
    """What is wrong with a quadrilateral mesh (see the module docstring), one sentence each.

    Args:
        points: (n, 3) node coordinates (mm).
        quads: (m, 4) node indices of each quadrilateral, in order around it.
        plane: the mesh must lie in the x-y plane (a plane part).
    """
    problems = []
    size = float(np.ptp(points, axis=0).max()) or 1.0
    if plane and np.abs(points[:, 2]).max() > 1e-9 * size:
        spans = ", ".join(f"{a} {np.ptp(points[:, i]):.4g} mm" for i, a in enumerate("xyz"))
        problems.append(
            f"the mesh is not in the x-y plane (it spans {spans}): a plane part is drawn at "
            "z = 0; a part in space needs [space]"
        )
    seams = _seams(points, quads)
    if len(seams):
        x, y, z = points[seams[0]]
        problems.append(
            f"the mesh is not conforming: {len(seams)} boundary edges lie on other boundary "
            f"edges (e.g. at ({x:.4g}, {y:.4g}, {z:.4g}) mm), so the surfaces on either side "
            "are not joined; let the surfaces share their interface curves (the same Line in "
            "both Curve Loops, or Coherence)"
        )
    _, label = connected_components(_node_graph(quads, len(points)), directed=False)
    if len(np.unique(label[quads])) > 1:
        counts = np.bincount(label[quads[:, 0]])
        problems.append(
            f"the mesh is in {np.count_nonzero(counts)} pieces that share no node "
            f"({', '.join(str(c) for c in counts[counts > 0])} cells): a part is one piece"
        )
    worst = _scaled_jacobians(points, quads)
    bad = np.flatnonzero(worst < MIN_SCALED_JACOBIAN)
    if bad.size:
        x, y, z = points[quads[bad[np.argmin(worst[bad])]]].mean(axis=0)
        problems.append(
            f"{bad.size} of {len(quads)} cells are degenerate or inverted (smallest scaled "
            f"Jacobian {worst.min():.3g} at ({x:.4g}, {y:.4g}, {z:.4g}) mm; every corner angle "
            "of a cell must lie between 1 and 179 degrees)"
        )
    return problems


def _node_graph(quads: np.ndarray, nodes: int):
    rows = np.repeat(quads[:, 0], 4)
    return coo_matrix((np.ones(rows.size), (rows, quads.ravel())), shape=(nodes, nodes))


def _seams(points: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Nodes (one per seam edge) of boundary edges whose midpoint lies on another boundary
    edge: non-conforming interfaces."""
    edges = np.sort(np.stack([quads, np.roll(quads, -1, axis=1)], axis=-1).reshape(-1, 2), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    boundary = unique[counts == 1]
    if len(boundary) < 2:
        return np.zeros(0, dtype=int)
    start, end = points[boundary[:, 0]], points[boundary[:, 1]]
    middle = 0.5 * (start + end)
    lengths = np.linalg.norm(end - start, axis=1)
    tree = cKDTree(middle)
    found = []
    for i, near in enumerate(tree.query_ball_point(middle, r=lengths.max())):
        for j in near:
            if j == i:
                continue
            direction = end[j] - start[j]
            if not lengths[j]:
                continue  # a collapsed edge: the cell is refused as degenerate
            t = np.clip(np.dot(middle[i] - start[j], direction) / lengths[j] ** 2, 0, 1)
            if np.linalg.norm(start[j] + t * direction - middle[i]) <= 1e-6 * lengths[i]:
                found.append(boundary[i, 0])
                break
    return np.array(found, dtype=int)


def _scaled_jacobians(points: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """(m,) the smallest scaled Jacobian of each quadrilateral's four corners: the sine of the
    corner's angle, negative where the corner turns against the cell (a reflex corner, a
    crossed cell), 0 where two of its nodes coincide."""
    corner = points[quads]  # (m, 4, 3)
    forward = np.roll(corner, -1, axis=1) - corner
    backward = np.roll(corner, 1, axis=1) - corner
    normals = np.cross(forward, backward)  # (m, 4, 3)
    cell = normals.sum(axis=1)
    cell /= np.maximum(np.linalg.norm(cell, axis=1, keepdims=True), 1e-300)
    lengths = np.linalg.norm(forward, axis=2) * np.linalg.norm(backward, axis=2)
    return (np.einsum("mci,mi->mc", normals, cell) / np.maximum(lengths, 1e-300)).min(axis=1)


def check_gmsh_mesh(source: str, refinements: int = 0, *, plane: bool) -> None:
    """InputError when the current gmsh model's 2D mesh has more cells than the budget after
    `refinements`, or listing its `mesh_problems`."""
    from fabric_dolfinx.gmsh_api import gmsh  # noqa: PLC0415 (gmsh only for meshes)

    tags, xyz, _ = gmsh.model.mesh.getNodes()
    index = np.full(int(tags.max()) + 1 if len(tags) else 1, -1)
    index[tags] = np.arange(len(tags))
    types, _, nodes = gmsh.model.mesh.getElements(2)
    quads = [np.reshape(n, (-1, 4)) for t, n in zip(types, nodes, strict=True) if t == 3]
    if not quads:
        return  # no quadrilaterals: `physical_groups` names the element types
    quads = index[np.concatenate(quads)]
    check_cells(source, len(quads), refinements)
    problems = mesh_problems(np.reshape(xyz, (-1, 3)), quads, plane=plane)
    if problems:
        raise InputError(f"{source}: " + "; ".join(problems))
