#!/usr/bin/python3
"""Dynamic contact against exact solutions: runs contact-sim on the scenes of this folder
(and on variants of them: finer meshes, other time steps, other angles), measures what the
exact solution predicts, and writes a table of errors and figures.

  /usr/bin/python3 examples/validation/validate.py [--sim build/bin/contact-sim]
                                                   [--out build/output/validation]

1. bar_impact.toml: an elastic bar (nu = 0) hits a rigid wall at v0. 1D waves: contact for
   2L/c, contact stress rho c v0, rebound at -v0 with the kinetic energy 1/2 m v0^2 back.
   Errors against the number of elements along the bar and the time step.
2. sliding_block.toml: a block sliding with Coulomb friction mu from v0 under gravity stops
   after v0 / (mu g) having slid v0^2 / (2 mu g).
3. incline.toml: a block on an incline sticks for tan(theta) <= mu, else slides with
   a = g (sin theta - mu cos theta).
"""
import argparse
import json
import math
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "plot"))
from plot_scene import read_csv  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
E, RHO, G = 2e8, 7800.0, 9.81


def run(sim, scene_text, name, out, extra=()):
    """Writes the scene variant, runs contact-sim --json into out/name, returns the JSON."""
    d = os.path.join(out, name)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "scene.toml")
    with open(path, "w") as f:
        f.write(scene_text)
    r = subprocess.run([sim, path, "--json", "--quiet", "--output", d, *extra],
                       capture_output=True, text=True)
    summary = json.loads(r.stdout)
    if summary["status"] != "completed":
        raise RuntimeError(f"{name}: {summary['status']}: {summary['message']}")
    return d, summary


def replace(text, old, new):
    assert old in text, old
    return text.replace(old, new)


def node_weights(d):
    """Lumped (row-sum) mass weights of the nodes of a mesh of equal rectangles: each node
    gets 1/4 of the mass of every element it belongs to."""
    e = read_csv(os.path.join(d, "mesh_elements.csv"))
    nodes = read_csv(os.path.join(d, "mesh_nodes.csv"))
    w = np.zeros(len(nodes["node"]))
    for k in (key for key in e if key.startswith("n")):
        np.add.at(w, e[k].astype(int), 0.25)
    return w / w.sum()


def mean_displacement(d):
    """Mass-weighted mean displacement (ux, uy) at every written time."""
    w = node_weights(d)
    u = read_csv(os.path.join(d, "displacement.csv"))
    times = np.unique(u["time"])
    out = []
    for t in times:
        sel = u["time"] == t
        nodes = u["node"][sel].astype(int)
        out.append([np.dot(w[nodes], u["ux"][sel]), np.dot(w[nodes], u["uy"][sel])])
    return times, np.array(out)


# ---------------------------------------------------------------------------- bar
def bar(sim, out):
    text = open(os.path.join(HERE, "bar_impact.toml")).read()
    L, h, v0 = 1.0, 0.1, 1.0
    c = math.sqrt(E / RHO)
    T, sigma, E0 = 2 * L / c, RHO * c * v0, 0.5 * RHO * L * h * v0**2
    cases = [(n, 0.5) for n in (10, 20, 40, 80)] + [(40, f) for f in (0.9, 0.25)]
    rows, histories = [], {}
    for n, courant in cases:
        dt = courant * (L / n) / c
        t = replace(text, "cells = [40, 1]", f"cells = [{n}, 1]")
        t = replace(t, "dt = 1e-4 ", f"dt = {dt:.6e} ")
        d, s = run(sim, t, f"bar_n{n}_c{courant}", out)
        st = read_csv(os.path.join(d, "steps.csv"))
        force = st["normal_force_sum"]
        on = force > 0.01 * sigma * h
        duration = on.sum() * dt
        plateau = (st["time"] > 0.1 * T) & (st["time"] < 0.9 * T) & on
        stress = force[plateau].mean() / h
        times, ubar = mean_displacement(d)
        after = times > T + 5 * dt
        v_rebound = np.polyfit(times[after], ubar[after, 0], 1)[0]
        energy_end = st["kinetic_energy"][-1] + st["strain_energy"][-1]
        rows.append(dict(n=n, courant=courant, dt=dt, steps=s["steps"], jac=s["jacobian_evaluations"],
                         duration_err=(duration - T) / T, stress_err=(stress - sigma) / sigma,
                         rebound_err=(v_rebound + v0) / v0, energy_err=(energy_end - E0) / E0,
                         balance=s["energy_balance_error"] / E0, penetration=s["max_penetration"]))
        histories[(n, courant)] = st
    # Figures: contact stress history against the exact box, energy history.
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    tt = np.linspace(0, 0.02, 1000)
    axes[0].plot(tt * 1e3, np.where(tt < T, sigma, 0.0) / 1e6, "k-", lw=2.5, alpha=0.35,
                 label=r"exact: $\rho c v_0$ for $t < 2L/c$")
    for n in (10, 40, 80):
        st = histories[(n, 0.5)]
        axes[0].plot(st["time"] * 1e3, st["normal_force_sum"] / h / 1e6, lw=1,
                     label=f"{n} elements, dt = h/(2c)")
    axes[0].set_xlabel("time [ms]")
    axes[0].set_ylabel("mean contact stress [MPa]")
    axes[0].set_title("contact stress at the wall")
    axes[0].legend(fontsize=8)
    st = histories[(40, 0.5)]
    axes[1].plot(st["time"] * 1e3, st["kinetic_energy"], label="kinetic")
    axes[1].plot(st["time"] * 1e3, st["strain_energy"], label="strain")
    axes[1].plot(st["time"] * 1e3, st["kinetic_energy"] + st["strain_energy"], "k-",
                 label="kinetic + strain")
    axes[1].axhline(E0, color="0.5", ls="--", label=r"exact: $\frac{1}{2} m v_0^2$")
    axes[1].axvline(T * 1e3, color="0.7", ls=":", label="2L/c")
    axes[1].set_xlabel("time [ms]")
    axes[1].set_ylabel("energy [J]")
    axes[1].set_title("energy, 40 elements, dt = h/(2c)")
    axes[1].legend(fontsize=8, loc="center right")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle(f"Elastic bar hits a rigid wall: L = {L} m, v0 = {v0} m/s, c = {c:.1f} m/s")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "figures", "bar_impact.png"), dpi=90)
    plt.close(fig)
    lines = ["| elements | dt / (h/c) | dt [s] | steps | N_Jac | duration | stress (plateau) | "
             "rebound velocity | energy at end | energy balance | max penetration [m] |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['n']} | {r['courant']} | {r['dt']:.3e} | {r['steps']} | {r['jac']} | "
                     f"{r['duration_err']:+.2%} | {r['stress_err']:+.2%} | {r['rebound_err']:+.2%} | "
                     f"{r['energy_err']:+.2%} | {r['balance']:.1e} | {r['penetration']:.1e} |")
    head = (f"Elastic bar (L = {L} m, h = {h} m, nu = 0, lumped mass) at v0 = {v0} m/s: relative "
            f"errors against 2L/c = {T * 1e3:.3f} ms, rho c v0 = {sigma / 1e6:.4f} MPa, rebound -v0, "
            f"energy 1/2 m v0^2 = {E0:.1f} J (energy balance: the discrete balance error of "
            "central differences / E0).")
    return head + "\n\n" + "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------- sliding
def sliding(sim, out):
    text = open(os.path.join(HERE, "sliding_block.toml")).read()
    mu, v0 = 0.3, 1.0
    t_stop, distance = v0 / (mu * G), v0**2 / (2 * mu * G)
    mass = RHO * 0.4 * 0.1
    rows, runs = [], {}
    for dt in (2e-4, 1e-4, 5e-5):
        t = replace(text, "dt = 1e-4 ", f"dt = {dt:g} ")
        d, s = run(sim, t, f"sliding_dt{dt:g}", out)
        st = read_csv(os.path.join(d, "steps.csv"))
        speed = np.sqrt(2 * st["kinetic_energy"] / mass)
        fit = (speed > 0.2 * v0) & (speed < 0.8 * v0)
        slope, intercept = np.polyfit(st["time"][fit], speed[fit], 1)
        stop = -intercept / slope
        times, ubar = mean_displacement(d)
        rows.append(dict(dt=dt, steps=s["steps"], jac=s["jacobian_evaluations"],
                         decel_err=(-slope - mu * G) / (mu * G), stop_err=(stop - t_stop) / t_stop,
                         dist_err=(ubar[-1, 0] - distance) / distance,
                         dissipation=st["friction_dissipation"][-1] / (0.5 * mass * v0**2) - 1))
        runs[dt] = st
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    tt = np.linspace(0, 0.5, 500)
    ax.plot(tt, np.maximum(v0 - mu * G * tt, 0), "k-", lw=2.5, alpha=0.35,
            label=r"exact: $v_0 - \mu g t$")
    st = runs[1e-4]
    ax.plot(st["time"], np.sqrt(2 * st["kinetic_energy"] / mass), lw=1,
            label=r"$\sqrt{2 E_{kin} / m}$, dt = 1e-4 s")
    ax.axvline(t_stop, color="0.6", ls=":", label=r"$v_0 / (\mu g)$")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("speed [m/s]")
    ax.set_title(f"Block sliding to rest: mu = {mu}, v0 = {v0} m/s")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "figures", "sliding_block.png"), dpi=90)
    plt.close(fig)
    lines = ["| dt [s] | steps | N_Jac | deceleration | stopping time | distance | friction dissipation |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['dt']:g} | {r['steps']} | {r['jac']} | {r['decel_err']:+.2%} | "
                     f"{r['stop_err']:+.2%} | {r['dist_err']:+.2%} | {r['dissipation']:+.2%} |")
    head = (f"Block sliding to rest (mu = {mu}, v0 = {v0} m/s, g = {G} m/s^2): relative errors "
            f"against mu g = {mu * G:.4f} m/s^2, v0/(mu g) = {t_stop:.4f} s, v0^2/(2 mu g) = "
            f"{distance:.4f} m and 1/2 m v0^2 (deceleration and stopping time from a line fitted "
            "to the speed sqrt(2 E_kin / m) between 0.2 and 0.8 v0; distance from the mean "
            "displacement at the end).")
    return head + "\n\n" + "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------- incline
def incline(sim, out):
    text = open(os.path.join(HERE, "incline.toml")).read()
    mu, ramp = 0.3, 0.02
    rows, curves = [], {}
    for deg in (10, 15, 20, 30):
        th = math.radians(deg)
        f = f"body_force = [{RHO * G * math.sin(th):.1f}, {-RHO * G * math.cos(th):.1f}]"
        t = replace(text, "body_force = [26170.7, -71903.4]", f)
        t = replace(t, "stress_times = [0.1, 0.2, 0.3]",
                    "stress_times = [" + ", ".join(f"{x:g}" for x in np.arange(0.025, 0.4, 0.025)) + "]")
        d, s = run(sim, t, f"incline_{deg}deg", out)
        times, ubar = mean_displacement(d)
        a_exact = G * (math.sin(th) - mu * math.cos(th))
        sticks = math.tan(th) <= mu
        # After the ramp x(t) = a/2 t^2 + b t + c: the fitted curvature is the acceleration.
        late = times >= 0.1
        a = 2 * np.polyfit(times[late], ubar[late, 0], 2)[0]
        slip = ubar[-1, 0] - ubar[times >= 0.1][0, 0]
        rows.append(dict(deg=deg, tan=math.tan(th), sticks=sticks, a_exact=a_exact if not sticks else 0.0,
                         a=a, slip=slip, steps=s["steps"], jac=s["jacobian_evaluations"]))
        curves[deg] = (times, ubar[:, 0], a_exact, sticks)
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    tt = np.linspace(ramp, 0.4, 200)
    for k, (deg, (times, ux, a_exact, sticks)) in enumerate(curves.items()):
        colour = f"C{k}"
        ax.plot(times, ux * 1e3, "o", color=colour, ms=4,
                label=f"{deg} deg ({'sticks' if sticks else 'slides'})")
        if not sticks:
            # Exact rigid-body slide with the ramped gravity: a(t) = a min(t / ramp, 1).
            x = a_exact * (ramp**2 / 6 + ramp * (tt - ramp) / 2 + (tt - ramp) ** 2 / 2)
            ax.plot(tt, x * 1e3, "-", color=colour, lw=1, alpha=0.7)
        else:
            ax.plot(tt, 0 * tt, "-", color=colour, lw=1, alpha=0.7)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("mean displacement down the slope [mm]")
    ax.set_title(f"Block on an incline, mu = {mu} (lines: exact)")
    ax.set_yscale("symlog", linthresh=1e-3)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "figures", "incline.png"), dpi=90)
    plt.close(fig)
    lines = ["| theta [deg] | tan theta | exact | a exact [m/s^2] | a measured [m/s^2] | error | "
             "slip 0.1-0.4 s [m] | N_Jac |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        err = "-" if r["sticks"] else f"{(r['a'] - r['a_exact']) / r['a_exact']:+.2%}"
        lines.append(f"| {r['deg']} | {r['tan']:.3f} | {'sticks' if r['sticks'] else 'slides'} | "
                     f"{r['a_exact']:.4f} | {r['a']:.4f} | {err} | {r['slip']:.2e} | {r['jac']} |")
    head = (f"Block on an incline (mu = {mu}, gravity ramped over {ramp} s): acceleration from a "
            "parabola fitted to the mean displacement for t >= 0.1 s; slip = mean displacement "
            "gained between 0.1 s and 0.4 s.")
    return head + "\n\n" + "\n".join(lines) + "\n"


def main():
    root = os.path.normpath(os.path.join(HERE, "..", ".."))
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--sim", default=os.path.join(root, "build", "bin", "contact-sim"))
    p.add_argument("--out", default=os.path.join(root, "build", "output", "validation"))
    args = p.parse_args()
    os.makedirs(os.path.join(args.out, "figures"), exist_ok=True)
    parts = [bar(args.sim, args.out), sliding(args.sim, args.out), incline(args.sim, args.out)]
    text = "\n".join(parts)
    with open(os.path.join(args.out, "validation.md"), "w") as f:
        f.write(text)
    print(text)
    print(f"table:   {os.path.join(args.out, 'validation.md')}")
    print(f"figures: {os.path.join(args.out, 'figures')}/")


if __name__ == "__main__":
    main()
