#!/usr/bin/env python3
"""Replays the fit's final pick over kept recovery fits, at other margins.

Every fit.json keeps each kind's best re-scored score (category_scores), the numbers the
final pick chooses among (search/fit.c, finish()); every niche's best reaches the pick even
when its niche was dropped. So a change to the pick rule alone can be tried on the fits of
earlier recovery runs without fitting again: for each margin given, a plain skin within
that fraction of the best score is picked, else the simplest kind within --parsimony of it.

With --weights the five objectives are weighed anew instead: each kind's final objectives
(kinds.KIND.objectives) over the fit's norms, every combination of the weights given
(palette, histogram, shape, along, across), the pick's margins as search/fit.c has them;
it prints the best combinations and, as a check against fitting 38 rows, the best one on
the even rows scored on the odd ones and back (docs/recovery.md, session 45).

With --recoloured the pick is made again after the recolouring, on each kind's final score
(kinds.KIND.score, recoloured where that scored better), the layered kind (the layer
searched over the champion, not the layered niche's best) leading only when it beats the
others' pick by LAYER_LEAD, as search/fit.c's sq__fit_repick does. Fits since session 59 pick again themselves (fit.json first_pick,
repicked): on their runs it names only the rows where the pattern picked could not be seen
and the first pick stayed; on older runs, the rows a second pick would move.

With --self-distance the same second pick is made on each kind's final score less ALPHA
times its distance to itself: the mean of the fit's objectives (over its norms) between
four instances of that kind's best, each under another pattern seed and lit and blurred
as the photo (`bench_recovery selfdist`, --tool; kept beside each fit.json as
self_distance.json). A kind whose pattern is drawn at random (spots, reaction-diffusion,
a layer) cannot match one photo's instance as closely as a kind whose pattern is fixed
by its genes (an automaton, stripes, bands), and the truth's own instances score no
better; what a kind scores beyond its own instances' scatter is what it fails to explain
(for squared distances, half the self-distance is the scatter's share: docs/recovery.md,
session 60).

usage: bench/pick_replay.py RUN_DIR [RUN_DIR ...] [--plain 0.05,0.1,0.3] [--parsimony 0.05]
       bench/pick_replay.py RUN_DIR [RUN_DIR ...] --weights 0.25,0.5,1,2,4
       bench/pick_replay.py RUN_DIR [RUN_DIR ...] --recoloured
       bench/pick_replay.py RUN_DIR [RUN_DIR ...] --self-distance 0.1,0.25,0.5 --tool BENCH_RECOVERY
(RUN_DIR: a recovery --out folder, e.g. build-bench/recovery; its NN_category/squama/fit.json)
"""
import argparse
import concurrent.futures
import glob
import itertools
import json
import os
import subprocess

OBJECTIVES = ("palette", "histogram", "shape", "along", "across")
PLAIN = 0.3  # search/fit.c PLAIN_PARSIMONY
LAYER_LEAD = 0.2  # search/fit.c: a layered skin leads when it beats the champion by this

# search/fit.c simplicity(): the simpler explanation first
SIMPLICITY = {"none": 0, "longitudinal": 1, "transversal": 1, "spots": 2, "other_simple": 3,
              "layered": 4, "complex": 5}


def pick(scores, plain, parsimony):
    best = min(scores.values())
    if "none" in scores and scores["none"] <= (1 + plain) * best:
        return "none"
    near = [k for k, v in scores.items() if v <= (1 + parsimony) * best]
    return min(near, key=lambda k: (SIMPLICITY[k], scores[k]))


def repick(j, less=None):
    """The pick made on the kinds' final scores, each less[kind] lower (kept above 0.02)."""
    lead = "layered" not in j.get("niches", []) or j.get("layer_search", {}).get("kind_best", False)
    final = {k: max(0.02, v["score"] - less.get(k, 0)) if less else v["score"] for k, v in j["kinds"].items()}
    scores = {k: v for k, v in final.items() if not (lead and k == "layered")}
    p = pick(scores, PLAIN, 0.05) if scores else None
    if lead and "layered" in final and (p is None or final["layered"] * (1 + LAYER_LEAD) < scores[p]):
        p = "layered"
    return p


def recoloured(fits):
    """The pick made again on the kinds' final scores; the rows it would move."""
    right = mine = 0
    for name, truth, j in fits:
        p = repick(j)
        right += p == truth
        mine += j["category"] == truth
        if p != j["category"]:
            print("%s: %s -> %s (%s); %s" % (name, j.get("first_pick", j["category"]), p, "right" if p == truth else "wrong", ", ".join(
                "%s %.3f" % kv for kv in sorted(((k, v["score"]) for k, v in j["kinds"].items()), key=lambda kv: kv[1])[:3])))
    print("re-picked after the recolouring: %d of %d right (the fits' own: %d)" % (right, len(fits), mine))


def self_distance(tool, d, j):
    """Each kind's best's distance to itself (over the fit's norms), computed once and kept
    in d/squama/self_distance.json: {kind: {view_scale, score, objectives: the mean
    objectives between its instances}}, computed again where the fit has changed since."""
    path = os.path.join(d, "squama", "self_distance.json")
    kept = {}
    if os.path.exists(path):
        with open(path) as f:
            kept = json.load(f)
    failed = None
    for k, v in j["kinds"].items():
        e = kept.get(k)
        if isinstance(e, dict) and e.get("view_scale") == v["view_scale"] and e.get("score") == v["score"]:
            continue
        try:
            out = subprocess.run([tool, "selfdist", os.path.join(d, "squama", "kinds", k + ".json"),
                                  "%.6f" % v["view_scale"], os.path.join(d, "photo.jpg"),
                                  os.path.join(d, "photo_mask.png"), "10"], capture_output=True, text=True)
        except OSError as x:
            failed = "cannot run %s: %s" % (tool, x)
            break
        if out.returncode != 0:
            failed = "bench_recovery selfdist failed in %s: %s" % (d, out.stderr.strip())
            break
        kept[k] = {"view_scale": v["view_scale"], "score": v["score"], "objectives": json.loads(out.stdout)}
    with open(path + ".tmp", "w") as f:  # what was measured is kept, even when a kind failed
        json.dump(kept, f)
    os.replace(path + ".tmp", path)
    if failed:
        raise SystemExit("pick_replay: " + failed)
    return {k: sum(x / j["norm"][o] for x, o in zip(kept[k]["objectives"], OBJECTIVES)) for k in j["kinds"]}


def self_distanced(fits, tool, alphas):
    """The second pick on each kind's score less alpha times its self-distance."""
    with concurrent.futures.ThreadPoolExecutor(os.cpu_count() or 1) as pool:
        ds = list(pool.map(lambda f: self_distance(tool, f[0], f[3]), fits))
    rule = {d: repick(j) for d, _, _, j in fits}  # the rule's pick without the self-distance
    for a in alphas:
        right, moved = 0, []
        for (d, name, truth, j), sd in zip(fits, ds):
            own = j["category"]  # the fit's own pick (it keeps the first where the new one cannot be seen)
            p = repick(j, {k: a * v for k, v in sd.items()})
            p = own if p == rule[d] else p
            right += p == truth
            if p != own:
                moved.append("%s/%s %s -> %s%s" % (os.path.basename(os.path.dirname(d)), name[:2], own, p,
                                                   " (right)" if p == truth else (" (was right)" if own == truth else "")))
        print("less %.2f of the self-distance: %d of %d right; moved: %s" % (a, right, len(fits), ", ".join(moved) or "none"))


def weighed(fits, grid):
    """The pick under every combination of objective weights from grid."""
    def picks(w):
        out = []
        for _, truth, j in fits:
            scores = {k: sum(wi * v["objectives"][o] / j["norm"][o] for wi, o in zip(w, OBJECTIVES))
                      for k, v in j["kinds"].items()}
            out.append(pick(scores, PLAIN, 0.05) == truth)
        return out
    equal = picks((1,) * len(OBJECTIVES))
    print("equal weights: %d of %d right" % (sum(equal), len(fits)))
    res = []
    for w in itertools.product(grid, repeat=len(OBJECTIVES)):
        p = picks(w)
        res.append((sum(p), sum(x for x, f in zip(p, fits) if f[0] % 2 == 0),
                    sum(x for x, f in zip(p, fits) if f[0] % 2 == 1), w))
    res.sort(key=lambda r: -r[0])
    for r in res[:5]:
        print("weights %s: %d right (even rows %d, odd %d)" % (",".join("%g" % x for x in r[3]), *r[:3]))
    for half, other, name in ((1, 2, "even"), (2, 1, "odd")):
        b = max(res, key=lambda r: r[half])
        rows = [x for x, f in zip(equal, fits) if f[0] % 2 == other - 1]
        print("best on the %s rows (%s): %d of %d on the others, equal weights %d" % (
            name, ",".join("%g" % x for x in b[3]), b[other], len(rows), sum(rows)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--plain", default="0.05,0.1,0.2,0.3,0.4,0.5",
                    help="margins for a plain skin, comma-separated (default 0.05 to 0.5)")
    ap.add_argument("--parsimony", type=float, default=0.05,
                    help="the margin for every other kind (default 0.05, as search/fit.c)")
    ap.add_argument("--weights", help="weigh the objectives anew: the weights each may take, comma-separated")
    ap.add_argument("--recoloured", action="store_true", help="pick again on the kinds' recoloured scores")
    ap.add_argument("--self-distance", help="pick again on the final scores less these fractions of each kind's "
                    "distance to itself, comma-separated (needs --tool)")
    ap.add_argument("--tool", help="bench_recovery, for --self-distance")
    args = ap.parse_args()
    kept = []  # (run, NN_category, fit.json)
    for run in args.runs:
        for d in sorted(glob.glob(os.path.join(run, "[0-9][0-9]_*"))):
            path = os.path.join(d, "squama", "fit.json")
            if os.path.exists(path):
                with open(path) as f:
                    kept.append((run, os.path.basename(d), json.load(f)))
    if not kept:
        raise SystemExit("pick_replay: no fit.json under " + ", ".join(args.runs))
    if args.self_distance:
        if not args.tool or not os.path.isfile(args.tool) or not os.access(args.tool, os.X_OK):
            raise SystemExit("pick_replay: --self-distance needs --tool, the bench_recovery program (%s)"
                             % (args.tool or "not given"))
        self_distanced([(os.path.join(run, name), name, name[3:], j) for run, name, j in kept], args.tool,
                       [float(x) for x in args.self_distance.split(",")])
        return
    if args.recoloured:
        recoloured([("%s/%s" % (os.path.basename(run.rstrip("/")), name), name[3:], j) for run, name, j in kept])
        return
    if args.weights:
        weighed([(int(name[:2]), name[3:], j) for _, name, j in kept], [float(x) for x in args.weights.split(",")])
        return
    fits = [(run, name, name[3:], j["category"], j["category_scores"]) for run, name, j in kept]
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
