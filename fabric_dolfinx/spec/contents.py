"""What a part's mesh holds, read before anything runs (no DOLFINx): its named boundaries and
regions, the centres and corners of its cells. The scene check meshes the part with gmsh in a
child process (`part_contents`; `fabric_dolfinx.spec.gmsh_child`), because some of gmsh 4.8's
meshing algorithms crash the process (`Mesh.Algorithm = 8`: a segmentation fault) and a check
must report that, not die of it; `read_part_contents` does the same in this process.
"""

import functools
import hashlib
import json
import signal
import subprocess
import sys
import tempfile
from dataclasses import asdict
from pathlib import Path
from typing import NamedTuple

import numpy as np

from fabric_dolfinx.spec.mesh_checks import check_geo_parameters, check_gmsh_mesh
from fabric_dolfinx.spec.part import MeshSpec, mesh_gmsh_file, physical_groups, shape_size
from fabric_dolfinx.spec.shapes import build_shape, shape_parameters
from rve_rod.errors import InputError

__all__ = [
    "GMSH_TIMEOUT_S",
    "GmshContents",
    "part_contents",
    "read_part_contents",
]

GMSH_TIMEOUT_S = 300.0
"""Seconds the scene check gives gmsh to mesh a part (the cell budget bounds the meshing;
this bounds what it cannot foresee)."""


class GmshContents(NamedTuple):
    """What a part's mesh holds, read before anything runs.

    Attributes:
        curves: physical curve names (the boundaries).
        surfaces: physical surface names (the regions).
        centres: physical surface name -> (n, 2) centres (mm) of its cells (after the
            refinements), where regions, course directions and stitch values are checked.
        corners: (m, 4, 2) the corners of every cell (mm), in order around it: which points
            lie in the part (probes).
    """

    curves: list[str]
    surfaces: list[str]
    centres: dict[str, np.ndarray]
    corners: np.ndarray

    def contains(self, points: np.ndarray) -> np.ndarray:
        """(n,) whether each point (n, 2) mm lies in a cell (on its edges included)."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        edges = np.roll(self.corners, -1, axis=1) - self.corners  # (m, 4, 2)
        inside = np.zeros(len(points), dtype=bool)
        scale = np.abs(self.corners).max() if self.corners.size else 1.0
        for index, point in enumerate(points):
            offset = point - self.corners
            cross = edges[..., 0] * offset[..., 1] - edges[..., 1] * offset[..., 0]
            tolerance = 1e-9 * scale * np.linalg.norm(edges, axis=2)
            # convex cells of either orientation: the point is on one side of every edge
            inside[index] = bool(
                np.any(np.all(cross >= -tolerance, axis=1) | np.all(cross <= tolerance, axis=1))
            )
        return inside


def part_contents(spec: MeshSpec, *, plane: bool = True) -> GmshContents:
    """`read_part_contents` in a child process (the module docstring). InputError when a
    check fails, gmsh cannot read or mesh the part, crashes, or takes longer than
    GMSH_TIMEOUT_S. Kept in this process per request and file content, so that a design,
    which checks its scene at every evaluation, meshes the part once (0.65 s a time under
    cProfile)."""
    request = json.dumps({"mesh": asdict(spec), "plane": plane}, sort_keys=True)
    file = Path(spec.file) if spec.file is not None else None
    digest = hashlib.sha256(file.read_bytes()).hexdigest() if file and file.is_file() else ""
    return _contents_of(request, digest)


@functools.lru_cache(maxsize=8)
def _contents_of(request: str, digest: str) -> GmshContents:
    """`part_contents` of the JSON `request` (a file's `digest` names its content)."""
    mesh = json.loads(request)["mesh"]
    name = Path(mesh["file"]).name if mesh["file"] is not None else f"shape {mesh['shape']}"
    with tempfile.TemporaryDirectory(prefix="knitmech-gmsh-") as folder:
        result = Path(folder) / "contents.npz"
        command = [sys.executable, "-m", "fabric_dolfinx.spec.gmsh_child", request]
        try:
            run = subprocess.run(
                [*command, str(result)],
                capture_output=True,
                text=True,
                timeout=GMSH_TIMEOUT_S,
                check=False,
            )
        except subprocess.TimeoutExpired:
            raise InputError(f"{name}: gmsh did not mesh it in {GMSH_TIMEOUT_S:g} s") from None
        if run.returncode < 0:
            raise InputError(
                f"{name}: gmsh crashed while meshing it; another Mesh.Algorithm may help (gmsh "
                f"4.8 crashes with 8; {signal.Signals(-run.returncode).name})"
            )
        if run.returncode != 0:
            lines = run.stderr.strip().splitlines() or ["no message"]
            raise InputError(lines[-1] if run.returncode == 2 else f"{name}: {lines[-1]}")
        with np.load(result) as stored:
            curves, surfaces = json.loads(str(stored["names"]))
            centres = {s: stored[f"centres_{i}"] for i, s in enumerate(surfaces)}
            corners = stored["corners"]
    for array in (*centres.values(), corners):
        array.flags.writeable = False  # shared by the calls the cache answers
    return GmshContents(curves, surfaces, centres, corners)


def read_part_contents(spec: MeshSpec, *, plane: bool = True) -> GmshContents:
    """The contents of the part's mesh, made in this process: a file's parameters checked, the
    file or built-in shape meshed (`mesh_gmsh_file`, `build_shape`; not the tube), the mesh
    checked (`fabric_dolfinx.spec.mesh_checks.check_gmsh_mesh`, `plane`: a plane part's),
    refined, its physical groups checked (`physical_groups`)."""
    from fabric_dolfinx.gmsh_api import gmsh  # noqa: PLC0415 (gmsh only for parts)

    if spec.file is not None:
        source = Path(spec.file).name
        problems = check_geo_parameters(spec.file, spec.parameters)
        if problems:
            raise InputError(f"{source}: parameters " + "; ".join(problems))
        parameters = spec.parameters
    else:
        source = f"shape {spec.shape}"
        size = spec.element_size or shape_size(spec) / 10.0
        parameters = shape_parameters(spec, size)
    arguments = ["fabric_dolfinx"]
    for key, value in parameters.items():
        arguments += ["-setnumber", key, repr(float(value))]
    gmsh.initialize(arguments)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        if spec.file is not None:
            mesh_gmsh_file(spec.file, spec.refinements)
        else:
            build_shape(spec, size)
        check_gmsh_mesh(source, spec.refinements, plane=plane)
        for _ in range(spec.refinements):
            gmsh.model.mesh.refine()
        curves, surfaces = physical_groups(source)
        centres = {}
        for name, tag in surfaces.items():
            points = [np.zeros((0, 2))]
            for entity in gmsh.model.getEntitiesForPhysicalGroup(2, tag):
                for kind in gmsh.model.mesh.getElementTypes(2, entity):
                    centre = gmsh.model.mesh.getBarycenters(kind, entity, False, True)
                    points.append(np.reshape(centre, (-1, 3))[:, :2])
            centres[name] = np.concatenate(points)
        corners = _corners()
    finally:
        gmsh.finalize()
    return GmshContents(list(curves), list(surfaces), centres, corners)


def _corners() -> np.ndarray:
    """(m, 4, 2) corner coordinates of the current gmsh model's quadrilaterals (mm)."""
    from fabric_dolfinx.gmsh_api import gmsh  # noqa: PLC0415 (gmsh only for parts)

    tags, xyz, _ = gmsh.model.mesh.getNodes()
    index = np.full(int(tags.max()) + 1 if len(tags) else 1, -1)
    index[tags] = np.arange(len(tags))
    points = np.reshape(xyz, (-1, 3))[:, :2]
    types, _, nodes = gmsh.model.mesh.getElements(2)
    quads = [np.reshape(n, (-1, 4)) for t, n in zip(types, nodes, strict=True) if t == 3]
    if not quads:
        return np.zeros((0, 4, 2))
    return points[index[np.concatenate(quads)]]
