"""The design's figure: what was wanted against what the design achieves (matplotlib)."""

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from knitmech.design.family import SurfaceFamily
from knitmech.design.material import UniaxialTarget
from knitmech.design.sleeve import SleeveSpec
from rve_rod.units import GF_PER_CM_PER_N_PER_MM

__all__ = ["plot_material", "plot_part", "plot_sleeve"]


def _save(figure, path: Path) -> None:
    import matplotlib.pyplot as plt  # noqa: PLC0415 (matplotlib on demand)

    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def plot_material(
    family: SurfaceFamily, targets: Sequence[UniaxialTarget], stitch: float, path: Path
) -> None:
    """The target curves (markers) and the family's at the designed stitch (lines), gf/cm."""
    import matplotlib.pyplot as plt  # noqa: PLC0415

    figure, axes = plt.subplots(figsize=(5.5, 4))
    colours = {"course": "C0", "wale": "C1"}
    for target in targets:
        axes.plot(
            100 * target.strain,
            target.force * GF_PER_CM_PER_N_PER_MM,
            "o",
            color=colours[target.direction],
            label=f"target, {target.direction}",
        )
    for direction in sorted({target.direction for target in targets}):
        largest = max(t.strain.max() for t in targets if t.direction == direction)
        strain = np.linspace(0.0, largest, 41)[1:]
        force = family.uniaxial(stitch, strain, direction) * GF_PER_CM_PER_N_PER_MM
        axes.plot(
            100 * strain, force, "-", color=colours[direction], label=f"stitch {stitch:.3f} mm"
        )
    axes.set_xlabel("strain (%)")
    axes.set_ylabel("uniaxial force per width (gf/cm)")
    axes.set_title("material design: target and designed knit")
    axes.legend()
    axes.grid(alpha=0.3)
    _save(figure, path)


def plot_sleeve(sleeve: SleeveSpec, wanted: tuple, bands: Sequence[dict], path: Path) -> None:
    """The target pressure profile `wanted` = (z (k,) mm, pressure (k,)) (line), the bands'
    Laplace pressures (steps) and, where the bands carry one, the contact model's (markers),
    against z; the limb's radius below."""
    import matplotlib.pyplot as plt  # noqa: PLC0415

    figure, (pressure_axes, limb_axes) = plt.subplots(
        2, 1, figsize=(6, 6), sharex=True, height_ratios=(2, 1)
    )
    pressure_axes.plot(*wanted, "k-", label="target")
    achieved = [row["achieved"] for row in bands]
    pressure_axes.stairs(
        achieved, sleeve.edges, baseline=None, color="C0", label="designed (Laplace model)"
    )
    contact = [row.get("contact") for row in bands]
    if any(value is not None for value in contact):
        pressure_axes.plot(sleeve.centres, contact, "s", color="C3", label="contact model")
    pressure_axes.set_ylabel(f"interface pressure ({bands[0]['unit']})")
    pressure_axes.legend()
    pressure_axes.grid(alpha=0.3)
    z = np.linspace(*sleeve.limb.extent, 201)
    limb_axes.plot(z, sleeve.limb.radius(z), "k-")
    limb_axes.set_xlabel("z from the ankle (mm)")
    limb_axes.set_ylabel("limb radius (mm)")
    limb_axes.grid(alpha=0.3)
    _save(figure, path)


def plot_part(targets: Sequence[dict], path: Path) -> None:
    """Each target's achieved value over its target value (1: met exactly)."""
    import matplotlib.pyplot as plt  # noqa: PLC0415

    figure, axes = plt.subplots(figsize=(5.5, 0.6 * len(targets) + 1.5))
    names = [row["name"] for row in targets]
    ratios = [row["achieved"] / row["target"] for row in targets]
    axes.barh(names, ratios, color=["C2" if row["met"] else "C3" for row in targets])
    for row in targets:
        axes.axvspan(1 - row["tolerance"], 1 + row["tolerance"], color="0.9", zorder=0)
    axes.axvline(1.0, color="k")
    axes.set_xlabel("achieved / target")
    _save(figure, path)
