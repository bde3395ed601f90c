#!/usr/bin/python3
"""Thesis section 6.2 (fig. 16 and the energies) from Python: the 2D block pressed by a
sudden edge load against a flat wall with Coulomb friction (examples/thesis/friction_2d_flat.toml),
drawn with matplotlib from the arrays contact.run returns - no CSV files.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/thesis_scene.py [OUT.png] [--friction F]

Left: normal and friction stress [Pa] along Gamma_c (the edge x = 5 m) at every output
time, darker = later (fig. 16; compressive normal stress positive).  Middle: the same
stresses over time at the middle of Gamma_c, (5, 0) m (the marked node; figs. 19, 21).
Right: kinetic and strain energy, the external work and the friction dissipation [J].
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import contact  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "thesis", "friction_2d_flat.toml")


def main(argv=None):
    cli = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    cli.add_argument("out", nargs="?", default="thesis_friction_2d_flat.png")
    cli.add_argument("--friction", type=float, help="override the friction coefficient")
    args = cli.parse_args(argv)

    scene = contact.load_scene(SCENE)
    if args.friction is not None:  # through a dict: the same keys as the file
        import tomllib
        with open(SCENE, "rb") as f:
            d = tomllib.load(f)
        d["friction"]["coefficient"] = args.friction
        scene = contact.scene_from_dict(d, base_dir=os.path.dirname(SCENE))
    result = contact.run(scene, progress=True)
    print(result)
    if not result.completed:
        raise SystemExit(f"run failed: {result.summary['message']}")

    y = result.contact_coordinates[:, 1]  # position along Gamma_c [m]
    order = np.argsort(y)
    fig, (ax_s, ax_h, ax_e) = plt.subplots(1, 3, figsize=(15, 4.2))
    for k, t in enumerate(result.output_times):
        shade = plt.cm.Blues(0.3 + 0.7 * (k + 1) / len(result.output_times))
        ax_s.plot(y[order], result.normal_stress[k, order], "-o", ms=3, color=shade,
                  label=f"normal, t = {t:.3f} s" if k == len(result.output_times) - 1 else None)
        ax_s.plot(y[order], result.friction_stress[k, order, 0], "--", color=shade,
                  label="friction" if k == len(result.output_times) - 1 else None)
    ax_s.set_xlabel("y along $\\Gamma_c$ [m]")
    ax_s.set_ylabel("stress [Pa]")
    ax_s.set_title(f"contact stresses, {scene.name}")
    ax_s.legend(fontsize=8)
    c = result.nearest_contact_node([5.0, 0.0])
    area = result.contact_area[c]  # [m^2] per unit thickness
    ax_h.plot(result.times, result.history_normal_force[:, c] / area, label="normal")
    ax_h.plot(result.times, result.history_friction_force[:, c, 0] / area, label="friction")
    ax_h.set_xlabel("t [s]")
    ax_h.set_ylabel("stress [Pa]")
    ax_h.set_title(f"contact node at ({result.contact_coordinates[c][0]:g}, {result.contact_coordinates[c][1]:g}) m")
    ax_h.legend(fontsize=8)
    rec = result.records
    for name in ("kinetic_energy", "strain_energy", "external_work", "friction_dissipation"):
        ax_e.plot(result.times, rec[name], label=name.replace("_", " "))
    ax_e.set_xlabel("t [s]")
    ax_e.set_ylabel("energy [J]")
    ax_e.set_title(f"energy balance error <= {result.summary['energy_balance_error']:.1e} J")
    ax_e.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print("wrote", args.out)
    return result


if __name__ == "__main__":
    main()
