#!/usr/bin/env python3
"""Summarise recognition batches for docs/physics-results.md.

Usage: scripts/physics-table.py LABEL=DIR [LABEL=DIR ...] [--filter COLUMN=VALUE]

For each batch directory of `whisker trials` and each object: trials finished, correctly
identified, wrongly identified, none; the search/recognition time (SRT, whisks) median and
IQR (MATLAB prctile); the whisks that touched nothing; and the re-localisations made on a
whisk without contact (read from each run's explore.csv: `relocalised` = 1 with
`contacts` = 0). Two batches' SRTs per object are compared by the exact two-sided
Mann-Whitney U test of scipy when scipy is installed (a cross-check of the report's own
test in `whisker trials report`, which works within one batch).
"""
import csv, os, sys


def prctile(v, p):
    v = sorted(v)
    n = len(v)
    if n == 0:
        return float("nan")
    pos = p / 100 * n - 0.5
    if pos <= 0:
        return v[0]
    if pos >= n - 1:
        return v[-1]
    i = int(pos)
    return v[i] + (pos - i) * (v[i + 1] - v[i])


def batch(d, filters):
    out = {}
    with open(os.path.join(d, "trials.csv"), newline="") as f:
        for r in csv.DictReader(f):
            if r["status"] != "ok" or any(k in r and r[k] != v for k, v in filters):
                continue
            o = r["object"]
            e = out.setdefault(o, dict(n=0, correct=0, wrong=0, none=0, srt=[], empty=0, whisks=0, empty_votes=0))
            e["n"] += 1
            outcome = r["recognition.outcome"]
            e["correct" if outcome == "correct" else "wrong" if outcome in ("wrong", "incorrect") else "none"] += 1
            if r["recognition.srt"]:
                e["srt"].append(float(r["recognition.srt"]))
            with open(os.path.join(d, "runs", r["key"], "explore.csv"), newline="") as g:
                for w in csv.DictReader(g):
                    e["whisks"] += 1
                    if w["contacts"] == "0":
                        e["empty"] += 1
                        if w["relocalised"] == "1":
                            e["empty_votes"] += 1
    return out


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--filter")]
    filters = []
    for i, a in enumerate(sys.argv):
        if a == "--filter":
            filters.append(tuple(sys.argv[i + 1].split("=", 1)))
    args = [a for a in args if "=" in a and a.split("=", 1)[0] not in [f[0] for f in filters] and a not in [f"{k}={v}" for k, v in filters]]
    batches = [(a.split("=", 1)[0], batch(a.split("=", 1)[1], filters)) for a in args]
    print("| batch | object | trials | correct | wrong | none | SRT median (IQR), whisks | empty whisks | re-localisations on an empty whisk |")
    print("|---|---|---|---|---|---|---|---|---|")
    for label, b in batches:
        for o, e in sorted(b.items()):
            s = e["srt"]
            srt = f"{prctile(s, 50):.0f} ({prctile(s, 25):.0f}–{prctile(s, 75):.0f})" if s else "—"
            print(f"| {label} | {o} | {e['n']} | {e['correct']} | {e['wrong']} | {e['none']} | {srt} | {e['empty']} of {e['whisks']} | {e['empty_votes']} |")
    try:
        from scipy.stats import mannwhitneyu
    except ImportError:
        return
    if len(batches) == 2:
        (la, a), (lb, b) = batches
        for o in sorted(set(a) & set(b)):
            x, y = a[o]["srt"], b[o]["srt"]
            if x and y:
                p = mannwhitneyu(x, y, alternative="two-sided").pvalue
                print(f"\nSRT {o}: {la} vs {lb}: Mann–Whitney p = {p:.3g} (n = {len(x)}, {len(y)})")


main()
