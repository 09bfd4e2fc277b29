"""The trade our RVE's ingredients make between force and contraction (issue 27): a figure.

Reads the sensitivity table of docs/validation.md ("The paper group's RVE", written by
`benchmarks/paper_rve_sensitivity.py`) and plots, for every variant at one stitch value, our
uniaxial force at 20 % against the group's (the mean of the README's two readings) on one axis
and our Poisson ratio against theirs on the other, course-wise and wale-wise: the group's RVE
is the point (1, 1). Prints the same ratios as a table whose numbers label the points; a row
whose run stopped before 20 % (nan) or whose Poisson ratio is not positive (the cell widened:
a run that snapped) is left off the figure and named.

    .venv/bin/python benchmarks/paper_rve_trade.py [--stitch 5.5]
        [--figure docs/figures/paper_rve_trade.png]
"""

import argparse
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

VALIDATION = Path(__file__).resolve().parents[1] / "docs" / "validation.md"
VALUE = re.compile(r"^\s*(nan|[-\d.]+)\s*\((.*)\)\s*$")


def reading(cell: str) -> tuple[float, float]:
    """Ours and the mean of their readings from a cell "ours (a / b)" ("-" readings skipped)."""
    match = VALUE.match(cell)
    ours = float(match.group(1))
    theirs = [float(v) for v in match.group(2).split("/") if v.strip() != "-"]
    return ours, sum(theirs) / len(theirs)


def sensitivity_rows(stitch: float) -> dict[str, dict[str, float]]:
    """{variant: {"course", "nu12", "wale", "nu21": ours / theirs}} at `stitch`."""
    rows = {}
    for line in VALIDATION.read_text(encoding="utf-8").splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) < 10 or cells[1] != f"{stitch:g}" or "(" not in cells[6]:
            continue
        ratios = {}
        for name, cell in zip(("course", "nu12", "wale", "nu21"), cells[6:10], strict=True):
            ours, theirs = reading(cell)
            ratios[name] = ours / theirs
        rows.setdefault(cells[0], ratios)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--stitch", type=float, default=5.5)
    parser.add_argument("--figure", type=Path, default=None)
    args = parser.parse_args()
    rows = sensitivity_rows(args.stitch)
    print("| # | variant | course F / theirs | nu12 / theirs | wale F / theirs | nu21 / theirs |")
    print("|---:|---|---:|---:|---:|---:|")
    for number, (name, r) in enumerate(rows.items(), 1):
        print(
            f"| {number} | {name} | {r['course']:.2f} | {r['nu12']:.2f} | {r['wale']:.2f} | "
            f"{r['nu21']:.2f} |"
        )
    if args.figure is None:
        return
    figure, axes = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True)
    left_off = set()
    for ax, (force, ratio, title) in zip(
        axes, (("course", "nu12", "course-wise"), ("wale", "nu21", "wale-wise")), strict=True
    ):
        for number, (name, r) in enumerate(rows.items(), 1):
            if not (r[force] > 0 and r[ratio] > 0):  # nan: our run stopped; <= 0: it snapped
                left_off.add(f"{number} ({title})")
                continue
            section = name.startswith("section")
            ax.plot(
                r[force],
                r[ratio],
                "s" if section else "o",
                ms=5,
                alpha=0.6,
                color="tab:blue" if section else "tab:orange",
            )
            ax.annotate(
                str(number),
                (r[force], r[ratio]),
                fontsize=6,
                xytext=(3, 2),
                textcoords="offset points",
            )
        ax.plot(1.0, 1.0, "k*", ms=14)
        ax.axhline(1.0, color="0.8", lw=0.8)
        ax.axvline(1.0, color="0.8", lw=0.8)
        ax.set_xscale("log")
        ax.set_xlabel("force at 20 %: ours / theirs")
        ax.set_ylabel("Poisson ratio at 20 %: ours / theirs")
        ax.set_xticks([0.2, 0.3, 0.5, 1, 2, 3], labels=["0.2", "0.3", "0.5", "1", "2", "3"])
        ax.set_title(f"{title}, stitch {args.stitch:g}")
    figure.suptitle(
        "Our variants (numbers of the table; squares: section rigidity, dots: free fibres) "
        "against the group's RVE (star)",
        fontsize=10,
    )
    figure.savefig(args.figure, dpi=150)
    print(
        f"figure: {args.figure}; left off (a run that stopped, or a ratio <= 0): {sorted(left_off)}"
    )


if __name__ == "__main__":
    main()
