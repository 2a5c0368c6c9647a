#!/usr/bin/env python3
"""The §3.3 table from `whisker maze-slam … --json` reports: per condition, image set and
variant, the mean ± sd of ARR, ARCR and EM over the seeds, and between two conditions an
exact two-sided Mann–Whitney p on each metric (all rank assignments; fine for n ≤ 10).

    python3 scripts/maze-table.py LABEL=REPORT.json [LABEL=REPORT.json …] [--compare A B]
        [--variants]

`--variants` adds normal against kidnapped within each condition and image set.

A report's runs are grouped by (images without their control prefix, variant), so the
open-loop and RCP reports line up on max_angle / contact_angle × normal / kidnapped.
"""
import itertools
import json
import statistics
import sys


def mann_whitney(a, b):
    """Exact two-sided p of the U statistic (midranks for ties), by enumeration."""
    pooled = a + b
    order = sorted(range(len(pooled)), key=lambda i: pooled[i])
    ranks = [0.0] * len(pooled)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and pooled[order[j + 1]] == pooled[order[i]]:
            j += 1
        for k in range(i, j + 1):
            ranks[order[k]] = (i + j) / 2 + 1
        i = j + 1
    n = len(a)
    observed = sum(ranks[:n])
    mean = n * (len(pooled) + 1) / 2
    extreme = 0
    total = 0
    for chosen in itertools.combinations(range(len(pooled)), n):
        s = sum(ranks[c] for c in chosen)
        total += 1
        if abs(s - mean) >= abs(observed - mean) - 1e-9:
            extreme += 1
    return extreme / total


def main():
    args = sys.argv[1:]
    compare = None
    variants = "--variants" in args
    args = [a for a in args if a != "--variants"]
    if "--compare" in args:
        i = args.index("--compare")
        compare = args[i + 1 : i + 3]
        args = args[:i] + args[i + 3 :]
    groups = {}
    for spec in args:
        label, path = spec.split("=", 1)
        for r in json.load(open(path))["runs"]:
            images = r["images"].split("/")[-1]
            groups.setdefault((label, images, r["variant"]), []).append(r)
    print("| condition | images | variant | n | ARR | ARCR | EM | threshold, energy |")
    print("|---|---|---|---|---|---|---|---|")
    fmt = lambda v: f"{statistics.mean(v):.4f} ± {statistics.stdev(v) if len(v) > 1 else 0:.4f}"
    for (label, images, variant), runs in sorted(groups.items()):
        pairs = sorted({(r["match_threshold"], r["inject_energy"]) for r in runs})
        print(
            f"| {label} | {images} | {variant} | {len(runs)} | "
            f"{fmt([r['arr'] for r in runs])} | {fmt([r['arcr'] for r in runs])} | "
            f"{fmt([r['energy_metric'] for r in runs])} | {pairs} |"
        )
    if compare:
        a, b = compare
        print(f"\nMann–Whitney {a} vs {b} (exact, two-sided):\n")
        print("| images | variant | p ARR | p ARCR | p EM |")
        print("|---|---|---|---|---|")
        for (label, images, variant), runs in sorted(groups.items()):
            if label != a or (b, images, variant) not in groups:
                continue
            other = groups[(b, images, variant)]
            p = [
                mann_whitney([r[m] for r in runs], [r[m] for r in other])
                for m in ("arr", "arcr", "energy_metric")
            ]
            print(f"| {images} | {variant} | {p[0]:.3f} | {p[1]:.3f} | {p[2]:.3f} |")

    if variants:
        print("\nMann–Whitney normal vs kidnapped (exact, two-sided):\n")
        print("| condition | images | p ARR | p ARCR | p EM |")
        print("|---|---|---|---|---|")
        for (label, images, variant), runs in sorted(groups.items()):
            other = groups.get((label, images, "kidnapped"))
            if variant != "normal" or other is None:
                continue
            p = [
                mann_whitney([r[m] for r in runs], [r[m] for r in other])
                for m in ("arr", "arcr", "energy_metric")
            ]
            print(f"| {label} | {images} | {p[0]:.3f} | {p[1]:.3f} | {p[2]:.3f} |")


if __name__ == "__main__":
    main()
