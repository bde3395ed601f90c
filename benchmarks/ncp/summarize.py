#!/usr/bin/python3
"""Summaries of an ncp-bench CSV (run with Debian's /usr/bin/python3 and matplotlib).

    /usr/bin/python3 summarize.py results.csv --out DIR

Writes to DIR:
  summary.md                  solved counts and shifted geometric means per solver
  performance_profile.png     Dolan-More profiles over every instance
  performance_profile_common.png  ... over the instances every solver attempted
  iterations_vs_size.png      iterations against n for the scalable families

Definitions (also printed in summary.md):
  instance      (family, problem, start, tolerance)
  solved        status = converged and natural residual <= 1e-6 (decided by ncp-bench)
  charged time  the time of a solved run, the time limit otherwise; not_applicable runs
                are charged the time limit too (the solver could not take the problem)
  shifted geometric mean   exp(mean(log(t + s))) - s with shift s = 10 ms, over all
                instances (Mittelmann's convention; the shift keeps sub-millisecond
                runs from dominating)
  performance profile      rho_s(tau) = share of instances with t_s <= tau min_s' t_s'
                (Dolan and More 2002); an unsolved run has ratio +inf
"""
import argparse
import collections
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SHIFT_S = 0.010


def read_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["solved"] = r["solved"] == "1"
        r["n"] = int(r["n"])
        r["iterations"] = int(r["iterations"])
        r["charged_time_s"] = float(r["charged_time_s"])
        r["tolerance"] = float(r["tolerance"])
    return rows


def instance_key(r):
    return (r["family"], r["problem"], r["start"], r["tolerance"])


def shifted_geometric_mean(times, shift=SHIFT_S):
    return math.exp(sum(math.log(t + shift) for t in times) / len(times)) - shift


def profiles(rows, solvers, instances, path, title):
    time = {(instance_key(r), r["solver"]): r for r in rows}
    ratios = {s: [] for s in solvers}
    for key in instances:
        solved_times = [time[(key, s)]["charged_time_s"] for s in solvers
                        if (key, s) in time and time[(key, s)]["solved"]]
        if not solved_times:
            for s in solvers:
                ratios[s].append(math.inf)
            continue
        best = max(min(solved_times), 1e-6)
        for s in solvers:
            r = time.get((key, s))
            ratios[s].append(max(r["charged_time_s"], 1e-6) / best
                             if r is not None and r["solved"] else math.inf)
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=90)
    tau_max = 1e3
    colors = plt.get_cmap("tab20").colors
    for k, s in enumerate(solvers):
        values = sorted(ratios[s])
        xs, ys = [1.0], [0.0]
        for i, v in enumerate(values):
            if math.isinf(v):
                break
            xs += [v, v]
            ys += [ys[-1], (i + 1) / len(values)]
        xs.append(tau_max)
        ys.append(ys[-1])
        ax.plot(xs, ys, "-" if s.startswith("ncp") else "--", color=colors[k % 20],
                label=s, linewidth=1.3)
    ax.set_xscale("log")
    ax.set_xlim(1.0, tau_max)
    ax.set_ylim(0.0, 1.02)
    ax.set_xlabel("tau (time / best time on the instance)")
    ax.set_ylabel("share of instances solved within tau")
    ax.set_title(f"{title} ({len(instances)} instances)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right", ncol=2)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def iterations_vs_size(rows, path):
    families = sorted({r["family"] for r in rows if r["family"] != "collection"})
    tol = min(r["tolerance"] for r in rows)
    # Dense, KLU and SparseLU take the same Newton steps as UMFPACK: plot one backend.
    solvers = [s for s in dict.fromkeys(r["solver"] for r in rows)
               if s.endswith("-umfpack") or s.startswith("siconos")]
    colors = plt.get_cmap("tab10").colors
    cols = 3
    nrows = math.ceil(len(families) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(11, 3.2 * nrows), dpi=80, squeeze=False)
    for ax, family in zip(axes.flat, families):
        for k, s in enumerate(solvers):
            # Mean iterations over the starts of a size, solved runs only.
            by_n = collections.defaultdict(list)
            for r in rows:
                if r["family"] == family and r["solver"] == s and r["tolerance"] == tol \
                        and r["solved"]:
                    by_n[r["n"]].append(r["iterations"])
            if by_n:
                ns = sorted(by_n)
                style = "o-" if s.startswith("ncp") else "s--"
                ax.plot(ns, [sum(by_n[n]) / len(by_n[n]) for n in ns], style, label=s,
                        color=colors[k % 10], markersize=3, linewidth=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(family, fontsize=9)
        ax.set_xlabel("n")
        ax.set_ylabel("iterations (solved runs)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(families):]:
        ax.axis("off")
    handles, labels = {}, {}
    for ax in axes.flat:
        for h, l in zip(*ax.get_legend_handles_labels()):
            handles[l] = h
    fig.legend(list(handles.values()), list(handles.keys()), fontsize=7, loc="lower right",
               ncol=2, bbox_to_anchor=(0.98, 0.05))
    fig.suptitle(f"Iterations against size, tolerance {tol:g}", fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv")
    parser.add_argument("--out", default=".")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = read_rows(args.csv)
    solvers = list(dict.fromkeys(r["solver"] for r in rows))
    instances = list(dict.fromkeys(instance_key(r) for r in rows))
    attempted = collections.defaultdict(set)
    for r in rows:
        if r["status"] != "not_applicable":
            attempted[instance_key(r)].add(r["solver"])
    common = [k for k in instances if attempted[k] == set(solvers)]

    lines = ["| solver | attempted | solved | claimed but residual > 1e-6 | "
             f"shifted geo. mean time, all {len(instances)} [ms] | "
             f"solved, common {len(common)} | shifted geo. mean, common [ms] |",
             "|---|---|---|---|---|---|---|"]
    for s in solvers:
        mine = [r for r in rows if r["solver"] == s]
        att = [r for r in mine if r["status"] != "not_applicable"]
        solved = [r for r in mine if r["solved"]]
        false_claims = [r for r in mine if r["status"] == "converged" and not r["solved"]]
        common_rows = [r for r in mine if instance_key(r) in set(common)]
        sgm_all = shifted_geometric_mean([r["charged_time_s"] for r in mine])
        sgm_common = shifted_geometric_mean([r["charged_time_s"] for r in common_rows]) \
            if common_rows else float("nan")
        lines.append(f"| {s} | {len(att)} | {len(solved)} | {len(false_claims)} | "
                     f"{1e3 * sgm_all:.1f} | {sum(r['solved'] for r in common_rows)} | "
                     f"{1e3 * sgm_common:.2f} |")
    statuses = collections.Counter((r["solver"], r["status"]) for r in rows)
    vocabulary = sorted({r["status"] for r in rows})
    lines += ["", "| solver | " + " | ".join(vocabulary) + " |",
              "|---|" + "---|" * len(vocabulary)]
    for s in solvers:
        lines.append(f"| {s} | " + " | ".join(str(statuses[(s, v)]) for v in vocabulary)
                     + " |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write(text)
    print(text)
    profiles(rows, solvers, instances, os.path.join(args.out, "performance_profile.png"),
             "Performance profile, all instances")
    if common:
        profiles(rows, solvers, common,
                 os.path.join(args.out, "performance_profile_common.png"),
                 "Performance profile, instances every solver attempted")
    iterations_vs_size(rows, os.path.join(args.out, "iterations_vs_size.png"))


if __name__ == "__main__":
    main()
