"""The HDF5 surface file (docs/surface-format.md): atomic writer and checking reader.

`write_surface` stores a `ResponseSurface` with its samples, parameters and provenance (package
version and git revision); `read_surface` checks every member and names the file and the
problem in a `SurfaceFileError`.
"""

import datetime
import json
import logging
import os
import subprocess
from pathlib import Path

import h5py
import numpy as np

from rve_rod import __version__
from rve_rod.atomic import atomic_write
from rve_rod.errors import InputError
from rve_rod.surface.response import (
    EXTENSION_ORDERS,
    GROUP_INPUTS,
    STRESS_GROUPS,
    FitSamples,
    ResidualStats,
    ResponseSurface,
)
from rve_rod.surface.splines import Spline1D, Spline2D, degree_list, extension_orders, knot_list

__all__ = [
    "FORMAT",
    "UNITS",
    "VERSION",
    "SurfaceFileError",
    "generator_info",
    "read_surface",
    "write_surface",
]

logger = logging.getLogger(__name__)

FORMAT = "knit-response-surface"
"""Value of the root attribute `format`."""
VERSION = 1
"""The file version this module writes and reads."""
UNITS = "E: 1 (Green-Lagrange); S: N/mm (per unit undeformed width)"
"""Value of the root attribute `units`."""


class SurfaceFileError(InputError):
    """A surface file cannot be used; the message names the file and the problem."""


def generator_info() -> dict:
    """Package name, version and git revision of the source tree (None if not a checkout)."""
    try:
        revision = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=Path(__file__).parent,
            capture_output=True,
            text=True,
            timeout=5,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        revision = None
    return {"package": "knitmech", "version": __version__, "git_revision": revision or None}


def write_surface(path: str | os.PathLike, surface: ResponseSurface) -> Path:
    """Write `surface` to `path` atomically (temporary file in the same folder, then rename).

    `created` and `generator` are filled in when empty. Returns the final path.
    """
    path = Path(path)
    created = surface.created or datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")
    generator = dict(surface.generator) or generator_info()
    try:
        parameters = json.dumps(surface.parameters, sort_keys=True, allow_nan=False)
    except (TypeError, ValueError) as error:
        raise InputError(f"surface parameters are not JSON-serializable: {error}") from None
    with atomic_write(path) as temporary, h5py.File(temporary, "w") as h5:
        h5.attrs["format"] = FORMAT
        h5.attrs["version"] = VERSION
        h5.attrs["kind"] = surface.kind
        h5.attrs["units"] = UNITS
        h5.attrs["created"] = created
        h5.attrs["generator"] = json.dumps(generator, sort_keys=True)
        h5.attrs["parameters"] = parameters
        for name, spline in surface.groups().items():
            _write_group(h5.create_group(name), name, spline, surface.samples.get(name))
    logger.info("wrote response surface %s (kind %s)", path, surface.kind)
    return path


def _write_group(group: h5py.Group, name: str, spline, samples: FitSamples | None) -> None:
    inputs = GROUP_INPUTS[name]
    group.attrs["inputs"] = list(inputs)
    group.attrs["degree"] = np.array(degree_list(spline), dtype=np.int64)
    group.attrs["extension_order"] = np.array(extension_orders(spline), dtype=np.int64)
    for label, knots in zip(inputs, knot_list(spline), strict=True):
        group.create_dataset(f"knots_{label}", data=knots)
    group.create_dataset("coefficients", data=spline.coefficients)
    domain = spline.domain.reshape(len(inputs), 2)
    group.create_dataset("domain", data=domain)
    if name not in STRESS_GROUPS:
        return
    if samples is None:
        samples = FitSamples(np.zeros((0, len(inputs))), np.zeros(0), np.zeros(0))
    sample_group = group.create_group("samples")
    sample_group.create_dataset("inputs", data=samples.inputs)
    sample_group.create_dataset("values", data=samples.values)
    sample_group.create_dataset("residuals", data=samples.residuals)
    for key, value in samples.stats()._asdict().items():
        group.attrs[f"residual_{key}"] = value


def read_surface(path: str | os.PathLike) -> ResponseSurface:
    """Read and check a surface file; SurfaceFileError names the file and the problem.

    Checked: HDF5 and readable (not truncated), format, version, kind, the groups of the kind,
    every member, shapes, knot vectors, extension orders, domains, and for `energy` files that
    the stress groups are the derivatives of the potentials.
    """
    path = Path(path)
    if not path.is_file():
        raise SurfaceFileError(f"{path}: no such file")
    if not h5py.is_hdf5(path):
        raise SurfaceFileError(f"{path}: not an HDF5 file (wrong format or damaged header)")
    try:
        with h5py.File(path, "r") as h5:
            return _read_file(h5, path)
    except SurfaceFileError:
        raise
    except InputError as error:
        raise SurfaceFileError(f"{path}: {error}") from None
    except (OSError, KeyError, ValueError, TypeError, RuntimeError) as error:
        raise SurfaceFileError(
            f"{path}: cannot be read as HDF5 (truncated or corrupt file): {error}"
        ) from None


def _read_file(h5: h5py.File, path: Path) -> ResponseSurface:
    def fail(problem: str):
        raise SurfaceFileError(f"{path}: {problem}")

    if "format" not in h5.attrs:
        fail(f"not a response-surface file (no 'format' attribute; expected {FORMAT!r})")
    file_format = _attribute(h5, "format", path)
    if file_format != FORMAT:
        fail(f"not a response-surface file (format={file_format!r}, expected {FORMAT!r})")
    version = _attribute(h5, "version", path)
    if not isinstance(version, int | np.integer) or int(version) != VERSION:
        fail(f"file version {version!r} is not supported (this reader reads version {VERSION})")
    units = _attribute(h5, "units", path)
    if units != UNITS:
        fail(f"units={units!r}: this reader reads {UNITS!r} only (convert the stresses)")
    kind = _attribute(h5, "kind", path)
    if kind not in EXTENSION_ORDERS:
        fail(f"kind={kind!r} is unknown (expected one of {sorted(EXTENSION_ORDERS)})")
    try:
        parameters = json.loads(_attribute(h5, "parameters", path))
        generator = json.loads(_attribute(h5, "generator", path))
    except (TypeError, json.JSONDecodeError) as error:
        fail(f"attribute parameters or generator is not valid JSON: {error}")
    if not isinstance(parameters, dict) or not isinstance(generator, dict):
        fail("attributes parameters and generator must hold JSON objects")
    created = str(_attribute(h5, "created", path))
    splines, samples = {}, {}
    for name in EXTENSION_ORDERS[kind]:
        if name not in h5 or not isinstance(h5[name], h5py.Group):
            fail(f"missing group {name!r} (required for kind {kind!r})")
        try:
            splines[name], group_samples = _read_group(h5[name], name)
        except InputError as error:
            fail(f"group {name}: {error}")
        if group_samples is not None:
            samples[name] = group_samples
    return ResponseSurface(
        kind=kind,
        s11=splines["S11"],
        s22=splines["S22"],
        s12=splines["S12"],
        psi=splines.get("psi"),
        psi_shear=splines.get("psi_shear"),
        samples=samples,
        parameters=parameters,
        created=created,
        generator=generator,
    )


def _attribute(node, name: str, path: Path):
    if name not in node.attrs:
        where = "root" if node.name == "/" else f"group {node.name.lstrip('/')}"
        raise SurfaceFileError(f"{path}: missing attribute {name!r} of {where}")
    value = node.attrs[name]
    return value.decode() if isinstance(value, bytes) else value


def _member(group: h5py.Group, name: str) -> np.ndarray:
    if name not in group or not isinstance(group[name], h5py.Dataset):
        raise InputError(f"missing member {name!r}")
    return np.asarray(group[name][()], dtype=float)


def _group_attribute(group: h5py.Group, name: str) -> np.ndarray:
    if name not in group.attrs:
        raise InputError(f"missing attribute {name!r}")
    return np.atleast_1d(group.attrs[name])


def _read_group(group: h5py.Group, name: str):
    expected_inputs = GROUP_INPUTS[name]
    inputs = tuple(
        value.decode() if isinstance(value, bytes) else str(value)
        for value in _group_attribute(group, "inputs")
    )
    if inputs != expected_inputs:
        raise InputError(f"inputs {list(inputs)}, expected {list(expected_inputs)}")
    dimension = len(inputs)
    degrees = [int(p) for p in _group_attribute(group, "degree")]
    orders = [int(k) for k in _group_attribute(group, "extension_order")]
    if len(degrees) != dimension or len(orders) != dimension:
        raise InputError(f"degree and extension_order need {dimension} entries")
    knots = [_member(group, f"knots_{label}") for label in inputs]
    coefficients = _member(group, "coefficients")
    shape = tuple(t.size - p - 1 for t, p in zip(knots, degrees, strict=True))
    if coefficients.shape != shape:
        raise InputError(
            f"coefficients have shape {coefficients.shape}; the knot vectors and degrees "
            f"{degrees} need {shape}"
        )
    if dimension == 1:
        spline = Spline1D(degrees[0], knots[0], coefficients, orders[0])
    else:
        spline = Spline2D(tuple(degrees), tuple(knots), coefficients, tuple(orders))
    domain = _member(group, "domain")
    if domain.shape != (dimension, 2) or not np.allclose(
        domain, spline.domain.reshape(dimension, 2), rtol=0.0, atol=1e-14
    ):
        raise InputError(f"domain {domain.tolist()} does not match the knot vectors")
    if name not in STRESS_GROUPS:
        return spline, None
    if "samples" not in group:
        raise InputError("missing member 'samples'")
    sample_group = group["samples"]
    sample_inputs = _member(sample_group, "inputs")
    if sample_inputs.ndim != 2 or sample_inputs.shape[1] != dimension:
        raise InputError(
            f"samples/inputs has shape {sample_inputs.shape}, expected (m, {dimension})"
        )
    samples = FitSamples(
        inputs=sample_inputs,
        values=_member(sample_group, "values"),
        residuals=_member(sample_group, "residuals"),
    )
    for key in ResidualStats._fields:
        _group_attribute(group, f"residual_{key}")
    return spline, (samples if samples.values.size else None)
