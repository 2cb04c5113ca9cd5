#!/usr/bin/env python3
"""Replays the fit's final pick over kept recovery fits, at other margins.

Every fit.json keeps each kind's best re-scored score (category_scores), the numbers the
final pick chooses among (search/fit.c, finish()); every niche's best reaches the pick even
when its niche was dropped. So a change to the pick rule alone can be tried on the fits of
earlier recovery runs without fitting again: for each margin given, a plain skin within
that fraction of the best score is picked, else the simplest kind within --parsimony of it.

usage: bench/pick_replay.py RUN_DIR [RUN_DIR ...] [--plain 0.05,0.1,0.3] [--parsimony 0.05]
(RUN_DIR: a recovery --out folder, e.g. build-bench/recovery; its NN_category/squama/fit.json)
"""
import argparse
import glob
import json
import os

# search/fit.c simplicity(): the simpler explanation first
SIMPLICITY = {"none": 0, "longitudinal": 1, "transversal": 1, "spots": 2, "other_simple": 3,
              "layered": 4, "complex": 5}


def pick(scores, plain, parsimony):
    best = min(scores.values())
    if "none" in scores and scores["none"] <= (1 + plain) * best:
        return "none"
    near = [k for k, v in scores.items() if v <= (1 + parsimony) * best]
    return min(near, key=lambda k: (SIMPLICITY[k], scores[k]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--plain", default="0.05,0.1,0.2,0.3,0.4,0.5",
                    help="margins for a plain skin, comma-separated (default 0.05 to 0.5)")
    ap.add_argument("--parsimony", type=float, default=0.05,
                    help="the margin for every other kind (default 0.05, as search/fit.c)")
    args = ap.parse_args()
    fits = []
    for run in args.runs:
        for d in sorted(glob.glob(os.path.join(run, "[0-9][0-9]_*"))):
            path = os.path.join(d, "squama", "fit.json")
            if os.path.exists(path):
                with open(path) as f:
                    j = json.load(f)
                truth = os.path.basename(d)[3:]
                fits.append((run, os.path.basename(d), truth, j["category"], j["category_scores"]))
    if not fits:
        raise SystemExit("pick_replay: no fit.json under " + ", ".join(args.runs))
    print("%d fits from %d runs" % (len(fits), len(args.runs)))
    base = [pick(s, args.parsimony, args.parsimony) for _, _, _, _, s in fits]
    agree = sum(b == c for b, (_, _, _, c, _) in zip(base, fits))
    print("the rule with one margin agrees with the fits' own picks on %d (the rest moved by the polish "
          "or the plain twin)" % agree)
    for m in [float(x) for x in args.plain.split(",")]:
        right, per, lost = 0, {}, []
        for b, (run, name, truth, _, s) in zip(base, fits):
            p = pick(s, m, args.parsimony)
            per.setdefault(truth, [0, 0])
            per[truth][0] += p == truth
            per[truth][1] += 1
            right += p == truth
            if b == truth and p != truth:
                lost.append("%s/%s" % (os.path.basename(run.rstrip("/")), name))
        print("plain within %4.0f%%: %d of %d right  %s  lost: %s" % (
            100 * m, right, len(fits), " ".join("%s %d/%d" % (k, v[0], v[1]) for k, v in sorted(per.items())),
            ", ".join(lost) or "none"))


if __name__ == "__main__":
    main()
