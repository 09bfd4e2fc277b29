"""What a run reports: meso against macro forces, Poisson ratios, stage timings, the Fig. 8a plot.

Forces are compared at REPORT_STRAINS (5, 10 and 20 %): the patch's clamp force per width
(macro) against the RVE's uniaxial force per width (meso) of the same direction, both in
gf/cm, twice: at the patch's nominal strain (clamp to clamp: the clamps, which hold the fabric's
width at both ends, stiffen a fabric that contracts) and at the strain of the gauge at the
patch's centre (`knitmech.jobs.patch.PatchProbe`; a tensile test's extensometer), where the fabric
is free to narrow and the material alone is measured. Values between output states are
interpolated linearly; strains beyond a curve's end (a run that stopped early, or a smaller
max_strain) are reported as None.
"""

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from knitmech.stages import DIRECTION_CASES
from knitmech.stages.cache import StageRecord
from knitmech.stages.records import MesoSummary, PatchSummary

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
    own uniaxial force (the material alone, homogeneous), the patch's clamp force at that
    nominal strain (macro) and where its centre gauge reads that strain (centre), and
    (macro - meso) / meso, (centre - meso) / meso."""
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
        entry["centre_gf_per_cm"] = [
            None if patch is None else value_at(patch.gauge_strain, patch.force_gf_per_cm, target)
            for target in REPORT_STRAINS
        ]
        for name, column in (
            ("relative_difference", "macro_gf_per_cm"),
            ("centre_relative_difference", "centre_gf_per_cm"),
        ):
            entry[name] = [
                None if None in (meso_force, force) or meso_force == 0 else force / meso_force - 1
                for meso_force, force in zip(entry["meso_gf_per_cm"], entry[column], strict=True)
            ]
        table[direction] = entry
    return table


def poisson_ratios(meso: Mapping[str, MesoSummary], macro: Mapping[str, PatchSummary]) -> dict:
    """nu12 and nu21 at POISSON_STRAINS: of the RVE (uniaxial cases; meso), of the patch across
    its middle at its nominal strain (macro), and of its centre gauge where that reads the
    strain (centre: -lateral / axial strain of the gauge, as the tests' extensometer)."""
    ratios = {}
    for direction, name in POISSON_NAMES.items():
        rve, patch = meso.get(DIRECTION_CASES[direction]), macro.get(direction)
        sources = {
            "meso": (rve, "strain", "lateral_strain"),
            "macro": (patch, "strain", "lateral_strain"),
            "centre": (patch, "gauge_strain", "gauge_lateral_strain"),
        }
        entry = {"strain": list(POISSON_STRAINS)}
        for scale, (record, strain, lateral) in sources.items():
            values = [
                None
                if record is None
                else value_at(getattr(record, strain), getattr(record, lateral), t)
                for t in POISSON_STRAINS
            ]
            entry[scale] = [
                None if value is None else -value / t
                for value, t in zip(values, POISSON_STRAINS, strict=True)
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


def _percent(fraction) -> str:
    return f"{'-':>9}" if fraction is None else f"{100 * fraction:>+8.1f}%"


def summary_table(summary: dict) -> str:
    """The printed summary: forces meso vs macro, Poisson ratios, stages and their times."""
    lines = [f"{summary['scene']['name']} (fidelity {summary['fidelity']['name']})"]
    forces = summary["forces"]
    columns = ("meso_gf_per_cm", "surface_gf_per_cm", "macro_gf_per_cm")
    patch = any(v is not None for e in forces.values() for v in e["macro_gf_per_cm"])
    for direction, entry in forces.items():
        header = f"{'strain':>8}{'meso':>9}"
        if patch:  # a part scene has no patch: these columns would be all "-"
            header += f"{'surface':>9}{'macro':>9}{'diff':>9}{'centre':>9}{'diff':>9}"
        lines += ["", f"{header}   {direction}-wise force (gf/cm)"]
        for row, target in enumerate(REPORT_STRAINS):
            cells = f"{100 * target:>6.0f} %"
            shown = columns if patch else columns[:1]
            cells += "".join(_number(entry[column][row], ".2f", 9) for column in shown)
            if patch:
                cells += _percent(entry["relative_difference"][row])
                cells += _number(entry["centre_gf_per_cm"][row], ".2f", 9)
                cells += _percent(entry["centre_relative_difference"][row])
            lines.append(cells)
    if forces:
        lines.append(
            "  meso: RVE uniaxial"
            + (
                "; surface: the fitted material alone in uniaxial tension; macro: clamped "
                "patch at its nominal strain; centre: the same where the gauge at its centre "
                "reads the strain; diff: against meso"
                if patch
                else ""
            )
        )
    ratios = summary["poisson_ratios"]
    scales = ("meso", "macro", "centre")
    known = any(v is not None for e in ratios.values() for k in scales for v in e.get(k, ()))
    if known:
        lines += ["", f"{'Poisson ratio':<16}" + "".join(f"{k:>8}" for k in scales)]
    for name, entry in ratios.items() if known else ():
        for index, target in enumerate(entry["strain"]):
            label = f"{name} at {100 * target:.0f} %"
            lines.append(
                f"  {label:<14}" + "".join(_number(entry[k][index], ".3f", 8) for k in scales)
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
    """Force-strain of the patch (markers: against its nominal strain, clamp to clamp, and
    against the strain its centre gauge reads) and of the RVE (dashed), as the paper's Fig. 8a,
    titled `title` (the scene's name and level); no file when there is neither a patch nor a
    uniaxial RVE case."""
    from fabric_dolfinx.io.plot import plot_force_strain  # noqa: PLC0415 (matplotlib on demand)

    curves = {}
    if not macro and not any(case in meso for case in DIRECTION_CASES.values()):
        return  # nothing to draw (a part scene with no uniaxial RVE case)
    for d, record in macro.items():
        curves[f"patch, {d}-wise, clamp to clamp"] = (record.strain, record.force_gf_per_cm)
        curves[f"patch, {d}-wise, centre gauge"] = (record.gauge_strain, record.force_gf_per_cm)
    references = {
        f"RVE uniaxial, {d}-wise": (
            meso[case].strain,
            [np.nan if f is None else f for f in meso[case].force_gf_per_cm],
        )
        for d, case in DIRECTION_CASES.items()
        if case in meso
    }
    plot_force_strain(curves, path, references=references, title=title, xlabel="strain (%)")
