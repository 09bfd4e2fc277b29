"""The strain-force curve of an RVE run as a PNG (matplotlib); imported on demand."""

from pathlib import Path

from matplotlib.figure import Figure

from rve_rod.rve.simulation import RveResult

__all__ = [
    "plot_curve",
]


def plot_curve(result: RveResult, path) -> Path:
    """Force per width (gf/cm) over the control strain (%), and the lateral strain of a
    uniaxial case on a second axis; returns the path written."""
    path = Path(path)
    strain = 100 * result.series("strain")
    figure = Figure(figsize=(6.0, 4.0), dpi=110)
    axes = figure.subplots()
    axes.plot(strain, result.series("force_gf_per_cm"), "o-", color="C0", ms=3, label="force")
    axes.set_xlabel(f"{result.case.name} strain (%)")
    axes.set_ylabel("force per width (gf/cm)", color="C0")
    axes.grid(alpha=0.3)
    lateral = [step.lateral_strain for step in result.steps]
    if lateral[0] is not None:
        twin = axes.twinx()
        twin.plot(strain, [100 * value for value in lateral], "s--", color="C1", ms=3)
        twin.set_ylabel("lateral strain (%)", color="C1")
    name = result.fabric.name or "fabric"
    stitch = result.fabric.knit.stitch_value
    title = f"{name}" + (f", stitch {stitch:g}" if stitch is not None else "")
    if not result.complete:
        title += f" (stopped at {strain[-1]:.3g} %)"
    axes.set_title(title)
    figure.tight_layout()
    figure.savefig(path)
    return path
