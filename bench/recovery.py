#!/usr/bin/env python3
"""The recovery benchmark: ground-truth presets of every category squama can fit, each
turned into a synthetic photo (`squama photo`: varied curve, view scale, light, backdrop,
blur, noise, colour cast), fitted with `squama fit` (with the photo's true mask: this
measures the fit, not the masking; its starting presets the shipped complex and layered
ones but the truth's own base, which would start it next to the answer), and compared
with the truth in texture space by
bench_recovery. The same photos are fitted by nlopt's global optimisers and by random
search with squama's own evaluation count.

Prints a table per category and overall: category accuracy, median CIEDE2000 between the
true and fitted dominant colours, median distance ratio (the fit's feature distance to the
photo over the true preset's: 1 = the fit explains the photo as well as the truth does; the
texture-space ratio over a reseeded truth is kept in rows.json but degenerates for patterns
without randomness, whose reseeded distance is near 0), and how far off the fitted scale grid
is (median |log2| of fitted over true scales across the body, and along it per body
circumference); then, per baseline, the median ratio of its final score
to squama's on the same photo (> 1: squama is better) and how often squama won; and where
the truth's kind stands among the kinds the fit offers (kinds/: best.json's, then each other
kind's best by score), with, for each wrong row, that kind's best scored against the photo.
Ends with: RESULT recovery n=... accuracy=... de00_median=... ratio_median=... scales_across=...
scales_along=... top3=... <method>_score_ratio=...

Work goes to --out (default build-bench/recovery); finished steps are kept and skipped on
a rerun with the same options, so a long run can be interrupted and continued. A fit is
kept by its command line alone: fits made by a squama before kinds/ (session 27) give no
kind's best for the wrong rows, and their rank comes from fit.json's category_scores.

With --fidelity nothing is fitted: each truth is scored against its own photo at its true
view scale (`squama score --view`), which says how well the objectives can recognise the
right answer at all (0 = the photo's statistics exactly), its textures rendered at
--fidelity-size (default 256, as the fit's re-scoring; the search renders at 128, and fine
scale grids shade unlike their photos there: docs/recovery.md, session 45). Ends with:
RESULT fidelity n=... size=... palette=... histogram=... shape=... along=... across=... (means)

With --niche KIND each truth of that kind (or the --rows given) is fitted with KIND alone
(`squama fit --categories KIND`, --evals or 1500), and the fit's score is divided by the
truth's, the mean over 4 other pattern seeds at its true view scale, both under the fit's
norms: how near that kind's own search comes to what is reachable, apart from the pick
among kinds (1 = as near as another instance of the true pattern). Ends with:
RESULT niche kind=... n=... geomean=... near=... (near: ratios within 1.1)"""
import argparse
import json
import math
import os
import random
import statistics
import subprocess
import sys
import time

# The first SIMPLE_ROWS truths cycle through the five simple categories, as they did before
# the complex patterns landed (so earlier runs stay comparable); complex and layered truths follow.
SIMPLE = ["none", "longitudinal", "transversal", "spots", "other_simple"]
SIMPLE_ROWS = 30
CATEGORIES = SIMPLE + ["complex", "layered"]
OBJECTIVES = ["palette", "histogram", "shape", "along", "across"]  # as squama score names them, in its order
RESEEDS = 4  # pattern seeds a truth is scored under, as bench_recovery compare does (its RESEEDS)
COMPLEX_ROWS = 6
NICHE_EVALS = 1500  # --niche's evaluation budget when --evals is not given (a single kind's fit)
BASES = {
    "none": ["d11_five_lined_skink.json", "table_4_4_spots.json"],
    "longitudinal": ["d11_five_lined_skink.json", "table_4_3_longitudinal.json"],
    "transversal": ["table_4_1_transversal.json", "table_4_2_micrurus_altirostris.json"],
    "spots": ["table_4_4_spots.json", "table_4_5_spots_interleaved.json"],
    "other_simple": ["figure_4_9_other_simple.json"],
    "complex": ["../complex/viper_blotches.json", "../complex/boa_saddles.json", "../complex/cheetah.json",
                "../complex/leopard.json", "../complex/python_reticulated.json", "../complex/giraffe.json"],
    "layered": ["../layered/garter_snake.json", "../layered/banded_flecked.json"],
}


def category_of(i):
    """The category of truth i and which of its bases it uses."""
    if i < SIMPLE_ROWS:
        return SIMPLE[i % len(SIMPLE)], i // len(SIMPLE)
    if i < SIMPLE_ROWS + COMPLEX_ROWS:
        return "complex", i - SIMPLE_ROWS
    return "layered", i - SIMPLE_ROWS - COMPLEX_ROWS
BASELINES = ["random", "esch", "crs2", "isres"]
STARTS = ["../complex", "../layered"]  # squama fit's default starting presets, relative to --presets


def run(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit("recovery: %s failed (exit %d), see %s" % (" ".join(cmd[:2]), r.returncode, log))


def starts_without(args, base, d):
    """`squama fit`'s starting presets (the shipped complex and layered ones) but the
    truth's own base, as a folder of links in d: a truth is its base with every gene moved
    a little, so starting from the base would start next to the answer; the other presets
    stand for the library of known species a photo of a new one is fitted with. (A folder,
    as the default's are: squama skips the presets in it that the fit cannot search.)"""
    out = os.path.join(d, "starts")
    os.makedirs(out, exist_ok=True)
    for folder in STARTS:
        src = os.path.join(args.presets, folder)
        for name in sorted(os.listdir(src)):
            path = os.path.realpath(os.path.join(src, name))
            link = os.path.join(out, os.path.basename(folder) + "_" + name)
            if name.endswith(".json") and path != os.path.realpath(base) and not os.path.lexists(link):
                os.symlink(path, link)
    return ["--start", out]


def fit(args, photo, mask, out, extra, base):
    """A fit, kept for a rerun only when the same command (program, budget) made it."""
    cmd = [args.squama, "fit", photo, "--mask", mask, "-o", out, "--seed", str(args.seed), "--size", "256", "-q"]
    cmd += starts_without(args, base, os.path.dirname(out))
    if args.threads:
        cmd += ["-j", str(args.threads)]
    cmd += extra
    stamp = os.path.join(out, "command.txt")
    same = os.path.exists(stamp) and open(stamp).read() == " ".join(cmd)
    if not (same and os.path.exists(os.path.join(out, "fit.json"))):
        run(cmd, out + ".log")
        with open(stamp, "w") as f:
            f.write(" ".join(cmd))
    with open(os.path.join(out, "fit.json")) as f:
        return json.load(f)


def compare(args, truth, view_t, fitted, photo, mask, norm, preset="best.json"):
    out = subprocess.run([args.tool, "compare", truth, "%.6f" % view_t, os.path.join(fitted["dir"], preset),
                          "%.6f" % fitted["view_scale"], photo, mask] + ["%.9g" % norm[k] for k in OBJECTIVES],
                         capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("recovery: compare failed: " + out.stderr)
    return json.loads(out.stdout)


def scale_errors(truth, view_t, fitted):
    """How far the fitted scale grid is from the truth's, in octaves (|log2| of the ratio):
    across the body (Scales_XAmount: the band's width is fixed) and along it, as the photo
    shows it (Scales_YAmount over the view scale: scales per body circumference)."""
    with open(truth) as f:
        t = json.load(f)
    with open(os.path.join(fitted["dir"], "best.json")) as f:
        b = json.load(f)
    across = abs(math.log2(b["Scales_XAmount"] / t["Scales_XAmount"]))
    along = abs(math.log2((b["Scales_YAmount"] / fitted["view_scale"]) / (t["Scales_YAmount"] / view_t)))
    return across, along


def truth_reseeded(args, photo, mask, truth, norm, out_dir, view=None):
    """The truth's score against its photo, its mean over RESEEDS other pattern seeds (as
    `bench_recovery compare` scores the truth), under the fit's norms: at the given view
    scale, or at the best of `squama score`'s grid when view is None. The photo's strip need
    not see the truth at exactly its true view scale (the body's width is measured from the
    photo), and the truth at another view scale is a candidate the search could have found
    as well. Not under the truth's own seed: that draws the photo's very pattern instance,
    which no search can find (row 30, viper blotches: 0.53 against a mean of 1.05 under five
    other seeds; docs/recovery.md, session 32)."""
    with open(truth) as f:
        t = json.load(f)
    files = []
    for s in range(1, RESEEDS + 1):
        t["Seed"] = 3000 + s
        files.append(os.path.join(out_dir, "truth_reseed%d.json" % s))
        with open(files[-1], "w") as f:
            json.dump(t, f)
    out = subprocess.run([args.squama, "score", photo, "--mask", mask, "--json"] +
                         ([] if view is None else ["--view", "%.6f" % view]) + files,
                         capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("recovery: score failed: " + out.stderr)
    return statistics.mean(sum(e["objectives"][k] / norm[k] for k in OBJECTIVES) for e in json.loads(out.stdout))


def niche_row(args, i, cat, d, photo, mask, truth, view_t, base):
    """--niche: the truth's photo fitted with the truth's kind alone (`--categories KIND`),
    and the fit's score over the truth's mean over RESEEDS other seeds at its true view
    scale, both under the fit's norms: how near the kind's own search comes to what is
    reachable (1 = as near as another instance of the true pattern; docs/recovery.md,
    session 32). Kept in DIR/niche_KIND and skipped on a rerun as a fit is."""
    out = os.path.join(d, "niche_" + args.niche)
    sq = fit(args, photo, mask, out, ["--evals", str(args.evals or NICHE_EVALS), "--categories", args.niche], base)
    t = truth_reseeded(args, photo, mask, truth, sq["norm"], out, view_t)
    row = {"i": i, "category": cat, "fit": sq["score"], "truth": t, "ratio": sq["score"] / t,
           "view_t": view_t, "view_f": sq["view_scale"]}
    print("[%2d/%d] %-12s fit %.3f  truth %.3f  ratio %.3f  view %.2f/%.2f" %
          (i + 1, args.n, cat, row["fit"], t, row["ratio"], view_t, sq["view_scale"]), file=sys.stderr, flush=True)
    return row


def niche_table(args, rows):
    with open(os.path.join(args.out, "niche_%s.json" % args.niche), "w") as f:
        json.dump(rows, f, indent=1)
    if not rows:
        return print("\nRESULT niche kind=%s n=0" % args.niche)
    g = math.exp(statistics.mean(math.log(r["ratio"]) for r in rows))
    near = sum(r["ratio"] <= 1.1 for r in rows)
    print("\nniche %s: %d photos fitted with that kind alone (--evals %d); the fit's score over the truth's "
          "mean over %d other seeds, at its true view scale: geometric mean %.3f, within 10%% of the truth %d" %
          (args.niche, len(rows), args.evals or NICHE_EVALS, RESEEDS, g, near))
    print("\nRESULT niche kind=%s n=%d geomean=%.3f near=%d" % (args.niche, len(rows), g, near))


def niche_best(args, truth, view_t, sq, cat, photo, mask, norm):
    """The truth's kind's best in the fit (kinds/CAT.json, at its view scale) against the photo,
    scored as the fit is: how near the truth's own niche came. None when the fit has no such
    kind (a fit before kinds/, or the kind not searched)."""
    k = sq.get("kinds", {}).get(cat)
    if k is None:
        return None
    c = compare(args, truth, view_t, {"dir": sq["dir"], "view_scale": k["view_scale"]}, photo, mask, norm,
                k["preset"])
    return c["photo_fit"]


def kind_rank(sq, cat):
    """Where the truth's kind stands among the kinds the fit offers (kinds/, as squama seed
    --from-photo offers them): 0 the champion's, then the others by score; None when the
    kind was not searched."""
    if "kinds" in sq:
        return sq["kinds"][cat]["rank"] if cat in sq["kinds"] else None
    scores = sq["category_scores"]  # a fit before kinds/: the order the pick's scores give
    order = [sq["category"]] + sorted((k for k in scores if k != sq["category"]), key=scores.get)
    return order.index(cat) if cat in order else None


def blame(row):
    """Whose fault a wrong category is: the fitness's when the fit scores better against the
    photo than the truth itself, at its true view scale and at the best of the grid (more
    search cannot help), else the search's."""
    return "fitness" if row["photo_fit"] < truth_score(row) else "search"


def truth_score(row):
    return min(row["photo_truth"], row.get("photo_truth_grid", math.inf))


def fidelity(args, i, cat, photo, mask, truth, view_t):
    out = subprocess.run([args.squama, "score", photo, "--mask", mask, "--view", "%.6f" % view_t,
                          "--size", str(args.fidelity_size), "--json", truth], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("recovery: score failed: " + out.stderr)
    o = json.loads(out.stdout)[0]["objectives"]
    print("[%2d] %-12s " % (i, cat) + " ".join("%s %.3f" % (k, v) for k, v in o.items()), file=sys.stderr)
    return {"i": i, "category": cat, "objectives": o}


def fidelity_table(rows, size):
    keys = OBJECTIVES
    print("\nfidelity: each truth scored against its own photo at its true view scale, rendered at %d "
          "(lower is better)" % size)
    print("%-14s %3s " % ("category", "n") + " ".join("%10s" % k for k in keys))
    for cat in CATEGORIES + ["all"]:
        rs = [r for r in rows if cat in ("all", r["category"])]
        if rs:
            print("%-14s %3d " % (cat, len(rs)) + " ".join("%10.3f" % statistics.mean(r["objectives"][k] for r in rs)
                                                        for k in keys))
    if not rows:
        return print("\nRESULT fidelity n=0 size=%d" % size)
    print("\nRESULT fidelity n=%d size=%d " % (len(rows), size) + " ".join("%s=%.3f" % (k, statistics.mean(r["objectives"][k] for r in rows))
                                                       for k in keys))


def med(xs):
    return statistics.median(xs) if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--squama", required=True)
    ap.add_argument("--tool", required=True)
    ap.add_argument("--presets", required=True)
    ap.add_argument("--n", type=int, default=38,
                    help="ground truths (default 38: 30 of the simple categories, 6 complex, 2 layered)")
    ap.add_argument("--first", type=int, default=0,
                    help="start at this truth (default 0): two runs on disjoint rows can share --out, "
                         "and a last run over all of them reuses their fits for the whole table")
    ap.add_argument("--budget", default="60s", help="squama's time budget per photo (default 60s)")
    ap.add_argument("--evals", type=int, default=0,
                    help="an evaluation budget per photo instead of --budget: deterministic, the "
                         "same on a busy machine (e.g. 5000, about 20 s on 2 cores)")
    ap.add_argument("--baseline-every", type=int, default=3,
                    help="run the baselines on every K-th photo (default 3; 0: none)")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--seed", type=int, default=1,
                    help="the fits' seed (default 1); the photos stay the same: a second seed says "
                         "how much of a difference between two runs is one fit's luck")
    ap.add_argument("--rows", default="",
                    help="only these truths, e.g. 4,9,14 (a quick read of one category's rows; "
                         "the table is over them alone)")
    ap.add_argument("--out", default="build-bench/recovery")
    ap.add_argument("--fidelity", action="store_true",
                    help="score each truth against its own photo instead of fitting")
    ap.add_argument("--fidelity-size", type=int, default=256,
                    help="--fidelity: the truths' texture size (default 256; the search's is 128)")
    ap.add_argument("--niche", choices=CATEGORIES,
                    help="fit each truth of this kind with that kind alone (--evals, default %d) and "
                         "print the fit's score over the truth's reseeded score (other rows with --rows)"
                         % NICHE_EVALS)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    t0 = time.time()
    only = {int(x) for x in args.rows.split(",") if x.strip()}
    if args.niche and not only:
        only = {i for i in range(args.n) if category_of(i)[0] == args.niche}
    for i in range(args.first, args.n):
        if only and i not in only:
            continue
        cat, k = category_of(i)
        bases = BASES[cat]
        base = os.path.join(args.presets, bases[k % len(bases)])
        d = os.path.join(args.out, "%02d_%s" % (i, cat))
        os.makedirs(d, exist_ok=True)
        truth = os.path.join(d, "truth.json")
        photo = os.path.join(d, "photo.jpg")
        if not os.path.exists(os.path.join(d, "photo_truth.json")):
            run([args.tool, "truth", base, cat, str(i + 1), truth], os.path.join(d, "truth.log"))
            r = random.Random(i)
            run([args.squama, "photo", truth, "-o", photo, "--seed", str(i + 1), "--size", "800x600",
                 "--coil", "%.2f" % r.uniform(0.2, 0.8), "--blur", "%.2f" % r.uniform(0, 1.2),
                 "--noise", "%.3f" % r.uniform(0, 0.03), "--cast", "%.2f" % r.uniform(0, 0.1)],
                os.path.join(d, "photo.log"))
        with open(os.path.join(d, "photo_truth.json")) as f:
            view_t = json.load(f)["view_scale"]
        mask = os.path.join(d, "photo_mask.png")
        if args.fidelity:
            rows.append(fidelity(args, i, cat, photo, mask, truth, view_t))
            continue
        if args.niche:
            rows.append(niche_row(args, i, cat, d, photo, mask, truth, view_t, base))
            continue
        sq = fit(args, photo, mask, os.path.join(d, "squama"),
                 ["--evals", str(args.evals)] if args.evals else ["--budget", args.budget], base)
        sq["dir"] = os.path.join(d, "squama")
        norm = sq["norm"]
        row = {"i": i, "category": cat, "fitted": sq["category"], "score": sq["score"],
               "evals": sq["search"]["evaluations"], "view_t": view_t, "view_f": sq["view_scale"]}
        row.update(compare(args, truth, view_t, sq, photo, mask, norm))
        row["scales_across"], row["scales_along"] = scale_errors(truth, view_t, sq)
        row["kind_rank"] = kind_rank(sq, cat)
        if row["fitted"] != cat:
            row["photo_truth_grid"] = truth_reseeded(args, photo, mask, truth, norm, d)
            row["photo_niche"] = niche_best(args, truth, view_t, sq, cat, photo, mask, norm)
        row["baselines"] = {}
        if args.baseline_every and i % args.baseline_every == 0:
            for m in BASELINES:
                b = fit(args, photo, mask, os.path.join(d, m), ["--method", m, "--evals", str(row["evals"])], base)
                b["dir"] = os.path.join(d, m)
                c = compare(args, truth, view_t, b, photo, mask, norm)
                row["baselines"][m] = {"score": b["score"], "ratio": c["ratio"], "category": b["category"]}
        rows.append(row)
        print("[%2d/%d] %-12s -> %-12s dE00 %5.2f  ratio %5.2f  view %.2f/%.2f  %d evals  %s%s  (%.0f min)" %
              (i + 1, args.n, cat, sq["category"], row["palette_de00"], row["ratio"], view_t, sq["view_scale"],
               row["evals"], " ".join("%s %.2f" % (m, v["score"] / sq["score"]) for m, v in
                                      row["baselines"].items()),
               "" if row["fitted"] == cat else "  [%s: fit %.2f truth %.2f%s]" % (
                   blame(row), row["photo_fit"], truth_score(row),
                   "" if row.get("photo_niche") is None else ", its kind's best %.2f" % row["photo_niche"]),
               (time.time() - t0) / 60),
              file=sys.stderr, flush=True)

    if args.fidelity:
        return fidelity_table(rows, args.fidelity_size)
    if args.niche:
        return niche_table(args, rows)
    how = "--evals %d" % args.evals if args.evals else "--budget %s" % args.budget
    print("\nrecovery: %d ground truths, squama fit %s, true masks" % (len(rows), how))
    print("%-14s %3s %9s %10s %12s %14s" % ("category", "n", "accuracy", "dE00 med", "ratio med", "scales off x/y"))
    for cat in CATEGORIES + ["all"]:
        rs = [r for r in rows if cat in ("all", r["category"])]
        if not rs:
            continue
        acc = sum(r["fitted"] == r["category"] for r in rs) / len(rs)
        print("%-14s %3d %8.0f%% %10.2f %12.2f %7.2f/%-6.2f" % (cat, len(rs), 100 * acc,
                                                             med([r["palette_de00"] for r in rs]),
                                                             med([r["ratio"] for r in rs]),
                                                             med([r["scales_across"] for r in rs]),
                                                             med([r["scales_along"] for r in rs])))
    print("(scales off: the median distance between the fitted and the true scale grid, in octaves, "
          "across the body and along it)")
    wrong = [r for r in rows if r["fitted"] != r["category"]]
    if wrong:
        fitness = sum(blame(r) == "fitness" for r in wrong)
        print("\n%d wrong: %d where the fit scores better against the photo than the truth does, at its true "
              "view scale and at the grid's best (the fitness prefers the wrong answer), %d where the search "
              "missed a better one" %
              (len(wrong), fitness, len(wrong) - fitness))
        searched = [r for r in wrong if blame(r) == "search" and r.get("photo_niche") is not None]
        if searched:
            near = sum(r["photo_niche"] <= truth_score(r) for r in searched)
            print("of those %d with the truth's kind's best (kinds/): %d where it scores as well as the truth or "
                  "better (its niche found it; the pick chose another kind), %d where it scores worse (its "
                  "niche never came as near)" % (len(searched), near, len(searched) - near))
    ranked = [r["kind_rank"] for r in rows if r.get("kind_rank") is not None]
    if ranked:
        print("\nthe truth's kind among the kinds offered (best.json's, then each other kind's best by score): "
              "first %d, in the first two %d, in the first three %d, of %d" %
              (sum(k == 0 for k in ranked), sum(k <= 1 for k in ranked), sum(k <= 2 for k in ranked), len(ranked)))
    acc = sum(r["fitted"] == r["category"] for r in rows) / len(rows)
    result = ["n=%d" % len(rows), "budget=%s" % (("%devals" % args.evals) if args.evals else args.budget), "accuracy=%.3f" % acc,
              "de00_median=%.2f" % med([r["palette_de00"] for r in rows]),
              "ratio_median=%.2f" % med([r["ratio"] for r in rows]),
              "scales_across=%.2f" % med([r["scales_across"] for r in rows]),
              "scales_along=%.2f" % med([r["scales_along"] for r in rows])]
    if ranked:
        result.append("top3=%.3f" % (sum(k <= 2 for k in ranked) / len(ranked)))
    withb = [r for r in rows if r["baselines"]]
    if withb:
        print("\nbaselines on %d photos at squama's evaluation count (score ratio > 1: squama better)" % len(withb))
        print("%-8s %12s %10s %12s %9s" % ("method", "score ratio", "squama won", "dist ratio", "accuracy"))
        print("%-8s %12s %10s %12.2f %8.0f%%" % ("squama", "1.00", "-", med([r["ratio"] for r in withb]),
                                               100 * sum(r["fitted"] == r["category"] for r in withb) / len(withb)))
        for m in BASELINES:
            sr = [r["baselines"][m]["score"] / r["score"] for r in withb]
            won = sum(s > 1 for s in sr)
            print("%-8s %12.2f %7d/%-2d %12.2f %8.0f%%" % (m, med(sr), won, len(sr),
                                                         med([r["baselines"][m]["ratio"] for r in withb]),
                                                         100 * sum(r["baselines"][m]["category"] == r["category"]
                                                                   for r in withb) / len(withb)))
            result.append("%s_score_ratio=%.2f" % (m, med(sr)))
    with open(os.path.join(args.out, "rows.json"), "w") as f:
        json.dump(rows, f, indent=1)
    print("\nRESULT recovery " + " ".join(result))


if __name__ == "__main__":
    main()
