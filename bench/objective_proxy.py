#!/usr/bin/env python3
"""Screens a change to the comparison in minutes instead of a benchmark's hour.

A recovery run keeps, for every row, the truth and each kind's best its fit found
(NN_category/squama/kinds/KIND.json). Scored against the row's photo with `squama score`,
the truth and each kind's best over four pattern seeds each, under the fit's own norms,
they say whether the comparison prefers the truth to every impostor the search found: the
count of such rows bounds the category a fit with a perfect search could reach with these
objectives. A trial build (a switch in the environment, say) scored the same way, and the
two counts compared, says whether a change to the objectives moves that bound before a
benchmark's worth of fitting is spent on it. It is necessary, not sufficient: the fits'
impostors were found under the old objectives, and a search under the new ones finds new
ones; and they were recoloured toward the photo's palette after the pick, the truth not, so
the count leans to the impostors, alike for base and trial (docs/recovery.md, sessions 46
and 56). A change that stops charging what the kinds' bests can tune and the fixed truth
cannot (its contrast, its colours) raises that count without helping a fit (session 57:
27 to 34, the fits 29 to 24); the count of rows whose lowest kind is a right one moved
with the fits there (27 to 24), so a change that raises the first and not the second is
suspect before any fitting.

usage: bench/objective_proxy.py score RUN_DIR --squama BIN --out SCORES.json [--jobs N]
       bench/objective_proxy.py compare BASE.json [TRIAL.json ...]
(RUN_DIR: a recovery --out folder with rows.json; the environment is passed to BIN)

compare prints, for each row, the truth's mean score and the best wrong kind's, and
counts the rows where the truth scores below every wrong kind (a layered fit of a complex
truth is not wrong, as the benchmark counts it). A trial's objectives may have another
scale than the base's: each objective's norm is scaled by the ratio of its medians over
the row's scored presets, trial over base, as a screening's median would move.
"""
import argparse
import concurrent.futures
import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile

OBJECTIVES = ("palette", "histogram", "shape", "along", "across")
TRUTH_SEEDS = (2001, 2002, 2003, 2004)
KIND_SEEDS = (11, 12, 13, 14)


def score(squama, row_dir, presets, view):
    out = subprocess.run([squama, "score", os.path.join(row_dir, "photo.jpg"), "--mask",
                          os.path.join(row_dir, "photo_mask.png"), "--json", "--view", "%.6f" % view] + presets,
                         capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("objective_proxy: squama score failed in %s: %s" % (row_dir, out.stderr.strip()))
    return [[x["objectives"][o] for o in OBJECTIVES] for x in json.loads(out.stdout)]


def reseeded(path, seeds, tmp, tag):
    files = []
    for s in seeds:
        with open(path) as f:
            p = json.load(f)
        p["Seed"] = s
        name = os.path.join(tmp, "%s_%d.json" % (tag, s))
        with open(name, "w") as f:
            json.dump(p, f)
        files.append(name)
    return files


def score_row(squama, run, row):
    i = row["i"]
    found = glob.glob(os.path.join(run, "%02d_*" % i))
    if not found:
        sys.exit("objective_proxy: no folder for row %d in %s" % (i, run))
    d = found[0]
    if not os.path.isfile(os.path.join(d, "squama", "fit.json")):
        sys.exit("objective_proxy: row %d was not fitted (no %s)" % (i, os.path.join(d, "squama", "fit.json")))
    with open(os.path.join(d, "squama", "fit.json")) as f:
        fit = json.load(f)
    e = {"category": row["category"], "fitted": row["fitted"], "norm": [fit["norm"][o] for o in OBJECTIVES],
         "kinds": {}}
    with tempfile.TemporaryDirectory() as tmp:
        e["truth"] = score(squama, d, reseeded(os.path.join(d, "truth.json"), TRUTH_SEEDS, tmp, "truth"),
                           row["view_t"])
        for kind, k in fit["kinds"].items():
            path = os.path.join(d, "squama", "kinds", kind + ".json")
            if os.path.exists(path):
                e["kinds"][kind] = score(squama, d, reseeded(path, KIND_SEEDS, tmp, kind), k["view_scale"])
    return i, e


def cmd_score(a):
    if not os.path.isfile(os.path.join(a.run, "rows.json")):
        sys.exit("objective_proxy: no recovery run here (no %s)" % os.path.join(a.run, "rows.json"))
    with open(os.path.join(a.run, "rows.json")) as f:
        rows = json.load(f)
    out = {}
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for i, e in pool.map(lambda r: score_row(a.squama, a.run, r), rows):
            out[str(i)] = e
            print("row %d scored" % i, file=sys.stderr, flush=True)
    with open(a.out, "w") as f:
        json.dump(out, f)


def mean(v):
    return sum(v) / len(v)


def judged(e, norm):
    """The truth's mean score, and each kind's, over their seeds."""
    def total(objs):
        return sum(x / n for x, n in zip(objs, norm))
    return mean([total(o) for o in e["truth"]]), {k: mean([total(o) for o in v]) for k, v in e["kinds"].items()}


def wrong_kinds(e, kinds):
    cat = e["category"]
    return {k: v for k, v in kinds.items() if k != cat and not (cat == "complex" and k == "layered")}


def scaled_norm(base, trial):
    """The trial's norms: the base's, each scaled by the ratio of the objective's medians."""
    norm = list(base["norm"])
    for j in range(len(OBJECTIVES)):
        b = [o[j] for o in base["truth"]] + [o[j] for v in base["kinds"].values() for o in v]
        t = [o[j] for o in trial["truth"]] + [o[j] for v in trial["kinds"].values() for o in v]
        mb, mt = statistics.median(b), statistics.median(t)
        if mb > 0 and mt > 0:
            norm[j] *= mt / mb
    return norm


def cmd_compare(a):
    runs = []
    for path in a.scores:
        with open(path) as f:
            runs.append(json.load(f))
    base = runs[0]
    for path, run in zip(a.scores[1:], runs[1:]):
        if set(run) != set(base):
            sys.exit("objective_proxy: %s scored other rows than %s" % (path, a.scores[0]))
    beats = [0] * len(runs)
    lowest = [0] * len(runs)
    lost = [[0.0] * len(OBJECTIVES) for _ in runs], [[0.0] * len(OBJECTIVES) for _ in runs]
    for r in sorted(base, key=int):
        line = "%2s %-13s fitted %-13s" % (r, base[r]["category"], base[r]["fitted"])
        for n, run in enumerate(runs):
            e = run[r]
            norm = e["norm"] if n == 0 else scaled_norm(base[r], e)
            truth, kinds = judged(e, norm)
            wrong = wrong_kinds(e, kinds)
            w = min(wrong, key=wrong.get) if wrong else None
            ok = w is None or truth < wrong[w]
            beats[n] += ok
            lowest[n] += bool(kinds) and min(kinds, key=kinds.get) not in wrong
            line += " | truth %.2f, %s %.2f%s" % (truth, w or "-", wrong[w] if w else 0, "" if ok else " *")
            if not ok:  # where the impostor gains: each objective's mean over the seeds, normalised
                for j in range(len(OBJECTIVES)):
                    lost[0][n][j] += mean([o[j] for o in e["truth"]]) / norm[j]
                    lost[1][n][j] += mean([o[j] for o in e["kinds"][w]]) / norm[j]
        print(line)
    for n, path in enumerate(a.scores):
        print("%s: the truth below every wrong kind in %d of %d rows; the lowest of the kinds found right in %d"
              % (path, beats[n], len(base), lowest[n]))
        print("  where not, summed over those rows (%s): truth %s, impostor %s"
              % (" ".join(OBJECTIVES), " ".join("%.2f" % x for x in lost[0][n]),
                 " ".join("%.2f" % x for x in lost[1][n])))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("score")
    s.add_argument("run")
    s.add_argument("--squama", required=True)
    s.add_argument("--out", required=True)
    s.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    c = sub.add_parser("compare")
    c.add_argument("scores", nargs="+")
    a = ap.parse_args()
    cmd_score(a) if a.cmd == "score" else cmd_compare(a)


if __name__ == "__main__":
    main()
