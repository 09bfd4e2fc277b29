"""Figures of docs/contact.md: the contact law of the cotton fabrics and a friction hysteresis.

Left: normal line load f_n(g) of the compressible-yarn law for the six cotton 20s/2 fabrics
(r = min(r0, w/8)) and the uncompressed yarn (p = 2). Right: rod 0 of two crossed rods,
pressed 0.03 mm into rod 1 and slid along rod 1 by +-0.05 mm and back (k_t = 2 MPa, so the
stick branches are visible): the friction resultant against the slide, with +-mu times the
weighted sum of the normal line loads for reference.

    .venv/bin/python benchmarks/contact_figures.py [--output docs/figures/contact.png]
"""

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rve_rod.contact import CompressibleYarnLaw, ContactModel, CoulombFriction
from rve_rod.geometry.loop import adjusted_radius
from rve_rod.presets import load_preset, stitch_values

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.contact_scenes import crossed_rods  # the tests' scenes


def law_panel(axis):
    for stitch in stitch_values("cotton-20s2"):
        fabric = load_preset("cotton-20s2", stitch)
        r0 = fabric.yarn.minimal_radius
        r = adjusted_radius(r0, fabric.knit.wale_width)
        law = CompressibleYarnLaw.from_yarn(r0, r, fabric.yarn.youngs_modulus)
        gaps = np.linspace(0, 0.3 * r, 200)
        axis.plot(gaps / r, law.line_load(gaps), label=f"stitch {stitch}: p = {law.exponent:.2f}")
    law = CompressibleYarnLaw.from_yarn(0.19, 0.19, 80.0)
    gaps = np.linspace(0, 0.3 * 0.19, 200)
    axis.plot(gaps / 0.19, law.line_load(gaps), "k--", label="r = r0: p = 2")
    axis.set_xlabel("penetration g / r")
    axis.set_ylabel("normal line load f_n (N/mm)")
    axis.set_title("compressible-yarn law, cotton 20s/2")
    axis.legend(fontsize=7)


def hysteresis_panel(axis):
    radius, n, amplitude = 0.15, 96, 0.05
    law = CompressibleYarnLaw(stiffness=5.0, exponent=1.5, yarn_radius=radius)
    friction = CoulombFriction(coefficient=0.15, tangential_stiffness=2.0)
    scene = crossed_rods(separation=2 * radius, length=3.0, n_control_points=n)
    model = ContactModel(scene.patches, scene.positions, law, friction=friction, yarns=scene.yarns)
    pressed = scene.positions.copy()
    pressed[:n, 2] -= 0.03
    model.commit(model.evaluate(pressed))
    path = np.concatenate(
        [
            np.linspace(0, amplitude, 21),
            np.linspace(amplitude, -amplitude, 41)[1:],
            np.linspace(-amplitude, amplitude, 41)[1:],
        ]
    )
    tangential, normal = [], []
    for shift in path:
        positions = pressed.copy()
        positions[:n, 1] += shift
        result = model.evaluate(positions, tangent=False)
        model.commit(result)
        loads = result.line_load[:, :n] * model.collocation_weights[:n]
        tangential.append(loads[1].sum())
        contacts = result.contacts
        on_rod_0 = contacts.slave < n
        weights = model.collocation_weights[contacts.slave[on_rod_0]]
        normal.append(np.sum(weights * contacts.normal_load[on_rod_0]))
    axis.plot(1e3 * path, 1e3 * np.array(tangential), "o-", ms=2, label="friction resultant")
    level = 1e3 * 0.15 * np.mean(normal)
    axis.axhline(level, color="gray", ls=":", label="+- mu x sum of normal line loads")
    axis.axhline(-level, color="gray", ls=":")
    axis.set_xlabel("slide of rod 0 along rod 1 (um)")
    axis.set_ylabel("tangential force on rod 0 (mN)")
    axis.set_title("crossed rods: load-unload slide, mu = 0.15")
    axis.legend(fontsize=7)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="docs/figures/contact.png")
    args = parser.parse_args()
    figure, axes = plt.subplots(1, 2, figsize=(10, 4))
    law_panel(axes[0])
    hysteresis_panel(axes[1])
    figure.tight_layout()
    figure.savefig(args.output, dpi=110)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
