"""What a run reports: meso against macro forces, Poisson ratios, stage timings, the Fig. 8a plot.

Forces are compared at REPORT_STRAINS (5, 10 and 20 %): the patch's clamp force per width
(macro) against the RVE's uniaxial force per width (meso) of the same direction, both in
gf/cm. Values between output states are interpolated linearly; strains beyond a curve's end
(a run that stopped early, or a smaller max_strain) are reported as None.
"""

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from knitmech.records import MesoSummary, PatchSummary
from knitmech.stage_cache import StageRecord
from knitmech.stages import DIRECTION_CASES

__all__ = [
    "POISSON_STRAINS",
    "REPORT_STRAINS",
    "compare_forces",
    "plot_comparison",
    "poisson_ratios",
    "stage_timings",
    "summary_table",
    "value_at",
]

REPORT_STRAINS = (0.05, 0.10, 0.20)
"""Strains at which forces are compared (-)."""

POISSON_STRAINS = (0.10, 0.20)
"""Strains at which Poisson ratios are reported (-)."""

POISSON_NAMES = {"course": "nu12", "wale": "nu21"}
"""nu12 = -eps22/eps11 under course-wise load, nu21 = -eps11/eps22 under wale-wise load."""

STAGES = ("geometry", "meso", "surface", "macro", "fabric")


def value_at(strain: Sequence[float], values: Sequence[float | None], target: float):
    """values interpolated linearly at `target` strain; None beyond the last state."""
    pairs = [(s, v) for s, v in zip(strain, values, strict=True) if v is not None]
    if len(pairs) < 2 or target > pairs[-1][0] + 1e-12 or target < pairs[0][0]:
        return None
    xs, ys = zip(*pairs, strict=True)
    return float(np.interp(target, xs, ys))


def compare_forces(meso: Mapping[str, MesoSummary], macro: Mapping[str, PatchSummary]) -> dict:
    """Per direction at REPORT_STRAINS (gf/cm): the RVE's uniaxial force (meso), the surface's
    own uniaxial force (the material alone, homogeneous) and the patch's clamp force (macro),
    and (macro - meso) / meso."""
    table = {}
    for direction in ("course", "wale"):
        rve, patch = meso.get(DIRECTION_CASES[direction]), macro.get(direction)
        if rve is None and patch is None:
            continue
        columns = {
            "meso_gf_per_cm": (rve, "force_gf_per_cm"),
            "surface_gf_per_cm": (patch, "material_uniaxial_gf_per_cm"),
            "macro_gf_per_cm": (patch, "force_gf_per_cm"),
        }
        entry = {"strain": list(REPORT_STRAINS)}
        for column, (record, key) in columns.items():
            entry[column] = [
                None if record is None else value_at(record.strain, getattr(record, key), target)
                for target in REPORT_STRAINS
            ]
        entry["relative_difference"] = [
            None
            if None in (force_meso, force_macro) or force_meso == 0
            else (force_macro - force_meso) / force_meso
            for force_meso, force_macro in zip(
                entry["meso_gf_per_cm"], entry["macro_gf_per_cm"], strict=True
            )
        ]
        table[direction] = entry
    return table


def poisson_ratios(meso: Mapping[str, MesoSummary], macro: Mapping[str, PatchSummary]) -> dict:
    """nu12 and nu21 of the RVE (uniaxial cases) and of the patch (across its middle)."""
    ratios = {}
    for direction, name in POISSON_NAMES.items():
        sources = {"meso": meso.get(DIRECTION_CASES[direction]), "macro": macro.get(direction)}
        entry = {"strain": list(POISSON_STRAINS)}
        for scale, record in sources.items():
            lateral = [
                None if record is None else value_at(record.strain, record.lateral_strain, t)
                for t in POISSON_STRAINS
            ]
            entry[scale] = [
                None if value is None else -value / t
                for value, t in zip(lateral, POISSON_STRAINS, strict=True)
            ]
        ratios[name] = entry
    return ratios


def stage_timings(records: Sequence[StageRecord]) -> dict[str, float]:
    """Wall time per stage (s), summed over its items."""
    return {
        stage: sum(r.wall_time_s for r in records if r.stage == stage)
        for stage in STAGES
        if any(r.stage == stage for r in records)
    }


def _number(value, spec: str, width: int) -> str:
    return f"{'-':>{width}}" if value is None else f"{value:{width}{spec}}"


def summary_table(summary: dict) -> str:
    """The printed summary: forces meso vs macro, Poisson ratios, stages and their times."""
    lines = [f"{summary['scene']['name']} (fidelity {summary['fidelity']['name']})"]
    forces = summary["forces"]
    if forces:
        header = "".join(f"{d + '-wise force (gf/cm)':^36}" for d in forces)
        columns = f"{'meso':>9}{'surface':>9}{'macro':>9}{'diff':>9}"
        lines += ["", f"{'':8}{header}", f"{'strain':>8}" + columns * len(forces)]
        for row, target in enumerate(REPORT_STRAINS):
            cells = f"{100 * target:>6.0f} %"
            for entry in forces.values():
                for column in ("meso_gf_per_cm", "surface_gf_per_cm", "macro_gf_per_cm"):
                    cells += _number(entry[column][row], ".2f", 9)
                difference = entry["relative_difference"][row]
                cells += f"{'-':>9}" if difference is None else f"{100 * difference:>+8.1f}%"
            lines.append(cells)
        lines.append(
            "  meso: RVE uniaxial; surface: the fitted material alone in uniaxial tension; "
            "macro: clamped patch; diff: macro vs meso"
        )
    ratios = summary["poisson_ratios"]
    known = any(v is not None for e in ratios.values() for k in ("meso", "macro") for v in e[k])
    if known:
        lines += ["", f"{'Poisson ratio':<16}{'meso':>8}{'macro':>8}"]
    for name, entry in ratios.items() if known else ():
        for index, target in enumerate(entry["strain"]):
            label = f"{name} at {100 * target:.0f} %"
            lines.append(
                f"  {label:<14}"
                + _number(entry["meso"][index], ".3f", 8)
                + _number(entry["macro"][index], ".3f", 8)
            )
    lines += ["", f"{'stage':<10}{'items':>6}{'computed':>10}{'cached':>8}{'time (s)':>10}"]
    records = summary["stages"]
    for stage, seconds in summary["timings_s"].items():
        own = [r for r in records if r["stage"] == stage]
        computed = sum(r["status"] == "computed" for r in own)
        cached = sum(r["status"] == "cached" for r in own)
        items = str(len(own)) if own else ""
        counts = (f"{computed:>10}{cached:>8}") if own else f"{'':>18}"
        lines.append(f"  {stage:<8}{items:>6}{counts}{seconds:>10.1f}")
    surface = summary.get("surface", {})
    if "runs" in surface:
        incomplete = len(surface["incomplete_runs"])
        lines.append(
            f"  surface RVE runs when the surface was made: {surface['runs']} "
            f"({surface['runs_computed']} computed, "
            f"{surface['runs_cached']} cached, {incomplete} stopped early)"
        )
    return "\n".join(lines)


def plot_comparison(
    meso: Mapping[str, MesoSummary],
    macro: Mapping[str, PatchSummary],
    path: Path,
    title: str = "",
) -> None:
    """Force-strain of the patch (markers) and of the RVE (dashed), as the paper's Fig. 8a,
    titled `title` (the scene's name and level)."""
    from fabric_dolfinx.plot import plot_force_strain  # noqa: PLC0415 (matplotlib on demand)

    curves = {
        f"patch, {d}-wise": (record.strain, record.force_gf_per_cm) for d, record in macro.items()
    }
    references = {
        f"RVE uniaxial, {d}-wise": (
            meso[case].strain,
            [np.nan if f is None else f for f in meso[case].force_gf_per_cm],
        )
        for d, case in DIRECTION_CASES.items()
        if case in meso
    }
    plot_force_strain(curves, path, references=references, title=title)
