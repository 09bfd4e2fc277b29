"""Input of membrane comparisons: the RVE's uniaxial curve as `rve-rod simulate --json`
prints it (the cell fields and their XDMF output are `fabric_dolfinx.part.fields`)."""

import json
from pathlib import Path
from typing import NamedTuple

import numpy as np

from rve_rod.errors import InputError

__all__ = [
    "RVECurve",
    "read_rve_curve",
]


class RVECurve(NamedTuple):
    """A uniaxial force-strain curve of the RVE (as `rve-rod simulate --json` prints it).

    Attributes:
        strain: (k,) nominal strain (-).
        force_gf_per_cm: (k,) force per width (gf/cm).
    """

    strain: np.ndarray
    force_gf_per_cm: np.ndarray


def read_rve_curve(path: Path | str) -> RVECurve:
    """Read a JSON object with equal-length lists `strain` and `force_gf_per_cm`."""
    path = Path(path)
    try:
        data = json.loads(path.read_text())
        strain = np.asarray(data["strain"], dtype=float)
        force = np.asarray(data["force_gf_per_cm"], dtype=float)
    except FileNotFoundError:
        raise InputError(f"RVE curve file {path} does not exist") from None
    except (OSError, ValueError, TypeError, KeyError) as error:
        raise InputError(
            f"RVE curve file {path} is not a JSON object with lists 'strain' and "
            f"'force_gf_per_cm' ({type(error).__name__}: {error})"
        ) from None
    if strain.ndim != 1 or strain.shape != force.shape or strain.size < 2:
        raise InputError(
            f"RVE curve file {path}: 'strain' and 'force_gf_per_cm' must be lists of equal "
            f"length >= 2, got {strain.shape} and {force.shape}"
        )
    if not (np.all(np.isfinite(strain)) and np.all(np.isfinite(force))):
        raise InputError(f"RVE curve file {path}: values must be finite numbers")
    return RVECurve(strain=strain, force_gf_per_cm=force)
