/* report.html for squama fit: one self-contained page (images beside it, plots inline as
 * SVG), readable without a server. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "buf.h"
#include "fit_report.h"
#include "squama/io.h"

enum { W = 520, H = 300, ML = 60, MR = 16, MT = 16, MB = 44 };

/* A colour for each kind, in the convergence plot's dots and legend. */
static const char *const KIND_COLOUR[SQ_FIT_KINDS] = {"#7f8c8d", "#2980b9", "#8e44ad", "#e67e22",
                                                      "#16a085", "#c0392b", "#d4ac0d"};

static int history_dot(const SqFitHistory *h)
{
    return h->category >= 0 && h->category < SQ_FIT_KINDS && isfinite(h->generation_best) && h->generation_best > 0;
}

/* Each generation's best score as a dot in its kind's colour, the best so far as a line
 * (one pattern instance's luck can hold it: the dots show what the search is doing), and
 * the re-scored champion in green, against evaluations. */
static void convergence_svg(CliBuf *b, const SqFitResult *r)
{
    cli_buf_put(b, "<svg width='%d' height='%d' viewBox='0 0 %d %d' font-size='11' font-family='sans-serif'>\n", W, H, W, H);
    cli_buf_put(b, "<rect x='%d' y='%d' width='%d' height='%d' fill='#fafafa' stroke='#999'/>\n", ML, MT, W - ML - MR, H - MT - MB);
    if (r->nhistory < 1) {
        cli_buf_put(b, "</svg>\n");
        return;
    }
    double xmax = (double)r->history[r->nhistory - 1].evals, ymin = INFINITY, ymax = -INFINITY;
    unsigned kinds = 0;
    for (int i = 0; i < r->nhistory; i++) {
        const SqFitHistory *h = &r->history[i];
        if (isfinite(h->best_score) && h->best_score > 0) {
            ymin = fmin(ymin, log10(h->best_score));
            ymax = fmax(ymax, log10(h->best_score));
        }
        if (history_dot(h)) {
            ymin = fmin(ymin, log10(h->generation_best));
            ymax = fmax(ymax, log10(h->generation_best));
            kinds |= 1u << h->category;
        }
    }
    if (isfinite(r->best.score) && r->best.score > 0) {
        ymin = fmin(ymin, log10(r->best.score));
        ymax = fmax(ymax, log10(r->best.score));
    }
    if (!isfinite(ymin)) {
        cli_buf_put(b, "</svg>\n");
        return;
    }
    ymin = floor(ymin * 10) / 10 - 0.05;
    ymax = ceil(ymax * 10) / 10 + 0.05;
    double pw = W - ML - MR, ph = H - MT - MB;
#define PX(e) (ML + pw * (double)(e) / fmax(xmax, 1))
#define PY(v) (MT + ph * (ymax - log10(v)) / (ymax - ymin))
    for (int t = 0; t <= 4; t++) { /* axes */
        double ly = ymin + (ymax - ymin) * t / 4;
        cli_buf_put(b, "<text x='%d' y='%.1f' text-anchor='end'>%.2f</text>\n", ML - 4, MT + ph * (1 - t / 4.0) + 4, pow(10, ly));
        cli_buf_put(b, "<text x='%.1f' y='%d' text-anchor='middle'>%.0f</text>\n", ML + pw * t / 4, H - MB + 16, xmax * t / 4);
    }
    cli_buf_put(b, "<text x='%.1f' y='%d' text-anchor='middle'>evaluations</text>\n", ML + pw / 2, H - 8);
    cli_buf_put(b, "<text x='12' y='%.1f' transform='rotate(-90 12 %.1f)' text-anchor='middle'>score (log)</text>\n",
        MT + ph / 2, MT + ph / 2);
    for (int i = 0; i < r->nhistory; i++) {
        const SqFitHistory *h = &r->history[i];
        if (history_dot(h))
            cli_buf_put(b, "<circle cx='%.1f' cy='%.1f' r='2.5' fill='%s' fill-opacity='0.75'><title>%s, a generation's best %.3f</title></circle>\n",
                PX(h->evals), PY(h->generation_best), KIND_COLOUR[h->category], sq_fit_kind_name(h->category), h->generation_best);
    }
    cli_buf_put(b, "<polyline fill='none' stroke='#222' stroke-width='1.5' points='");
    for (int i = 0; i < r->nhistory; i++)
        if (isfinite(r->history[i].best_score) && r->history[i].best_score > 0)
            cli_buf_put(b, "%.1f,%.1f ", PX(r->history[i].evals), PY(r->history[i].best_score));
    cli_buf_put(b, "'><title>the best score so far</title></polyline>\n");
    if (isfinite(r->best.score) && r->best.score > 0)
        cli_buf_put(b, "<circle cx='%.1f' cy='%.1f' r='5' fill='#27ae60'><title>re-scored champion %.3f</title></circle>\n",
            PX(r->evals), PY(r->best.score), r->best.score);
    double lx = ML;
    for (int k = 0; k < SQ_FIT_KINDS; k++) /* the legend, above the frame */
        if ((kinds >> k) & 1u) {
            cli_buf_put(b, "<circle cx='%.1f' cy='%d' r='3' fill='%s'/><text x='%.1f' y='%d' font-size='10'>%s</text>\n",
                lx + 3, MT - 7, KIND_COLOUR[k], lx + 8, MT - 3, sq_fit_kind_name(k));
            lx += 14 + 5.5 * (double)strlen(sq_fit_kind_name(k));
        }
#undef PX
#undef PY
    cli_buf_put(b, "</svg>\n");
}

/* Two objectives of the front against each other, the champion in green. */
static void front_svg(CliBuf *b, const SqFitResult *r, int ox, int oy)
{
    cli_buf_put(b, "<svg width='%d' height='%d' viewBox='0 0 %d %d' font-size='11' font-family='sans-serif'>\n", W, H, W, H);
    cli_buf_put(b, "<rect x='%d' y='%d' width='%d' height='%d' fill='#fafafa' stroke='#999'/>\n", ML, MT, W - ML - MR, H - MT - MB);
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int i = 0; i < r->nfront; i++) {
        x0 = fmin(x0, r->front[i].obj[ox]);
        x1 = fmax(x1, r->front[i].obj[ox]);
        y0 = fmin(y0, r->front[i].obj[oy]);
        y1 = fmax(y1, r->front[i].obj[oy]);
    }
    if (r->nfront == 0 || !isfinite(x0) || !isfinite(y0)) {
        cli_buf_put(b, "</svg>\n");
        return;
    }
    double dx = fmax(x1 - x0, 1e-9) * 0.1, dy = fmax(y1 - y0, 1e-9) * 0.1;
    x0 -= dx;
    x1 += dx;
    y0 -= dy;
    y1 += dy;
    double pw = W - ML - MR, ph = H - MT - MB;
    for (int t = 0; t <= 4; t++) {
        cli_buf_put(b, "<text x='%d' y='%.1f' text-anchor='end'>%.3g</text>\n", ML - 4, MT + ph * (1 - t / 4.0) + 4, y0 + (y1 - y0) * t / 4);
        cli_buf_put(b, "<text x='%.1f' y='%d' text-anchor='middle'>%.3g</text>\n", ML + pw * t / 4, H - MB + 16, x0 + (x1 - x0) * t / 4);
    }
    cli_buf_put(b, "<text x='%.1f' y='%d' text-anchor='middle'>%s</text>\n", ML + pw / 2, H - 8, sq_fit_objective_name(ox));
    cli_buf_put(b, "<text x='12' y='%.1f' transform='rotate(-90 12 %.1f)' text-anchor='middle'>%s</text>\n", MT + ph / 2,
        MT + ph / 2, sq_fit_objective_name(oy));
    for (int i = r->nfront - 1; i >= 0; i--) {
        double px = ML + pw * (r->front[i].obj[ox] - x0) / (x1 - x0);
        double py = MT + ph * (y1 - r->front[i].obj[oy]) / (y1 - y0);
        cli_buf_put(b, "<circle cx='%.1f' cy='%.1f' r='%d' fill='%s' fill-opacity='0.8'><title>front/%02d.json (%s), score %.3f</title></circle>\n",
            px, py, i == 0 ? 7 : 4, i == 0 ? "#27ae60" : "#2c3e80", i,
            sq_fit_kind_name(sq_fit_kind_of(&r->front[i].params)), r->front[i].score);
    }
    cli_buf_put(b, "</svg>\n");
}

SqStatus cli_fit_report(const char *path, const char *photo_path, const SqFitResult *r, const char *warning,
                        int line_given, double prepare_s, double search_s, double total_s, SqError *err)
{
    CliBuf b = {0};
    cli_buf_put(&b, "<!doctype html>\n<html><head><meta charset='utf-8'><title>squama fit: ");
    cli_buf_html(&b, photo_path);
    cli_buf_put(&b, "</title>\n<style>body{font-family:sans-serif;margin:24px;color:#222}"
            "figure{display:inline-block;margin:0 12px 12px 0;vertical-align:top}"
            "figure img{max-height:320px;max-width:420px;border:1px solid #ccc;image-rendering:auto}"
            "figure img.wide{max-height:none;max-width:100%%}"
            /* a strip at twice its size from its start, not a long one squeezed to a sliver */
            "figure img.strip{width:128px;height:auto;max-height:480px;max-width:none;object-fit:cover;"
            "object-position:top}"
            "figcaption{font-size:12px;color:#555}table{border-collapse:collapse;font-size:13px}"
            "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#eee}"
            "td.l{text-align:left}.plots svg{margin-right:16px}</style></head><body>\n");
    cli_buf_put(&b, "<h1>squama fit</h1>\n<p>");
    cli_buf_html(&b, photo_path);
    cli_buf_put(&b, ": <b>%s</b> pattern, score %.3f, view scale %.2f body circumferences per texture tile. "
            "%ld evaluations in %.1f s of search (%.0f per second), %.1f s in all%s.</p>\n",
        sq_fit_kind_name(sq_fit_kind_of(&r->best.params)), r->best.score, r->best.view_scale, r->evals,
        search_s, r->evals / fmax(search_s, 1e-9), total_s, r->stopped ? "; <b>stopped early</b>" : "");
    if (warning) {
        cli_buf_put(&b, "<p style='background:#fed;padding:6px'><b>Warning:</b> ");
        cli_buf_html(&b, warning);
        cli_buf_put(&b, ".</p>\n");
    }
    cli_buf_put(&b, "<div>\n");
    const char *const pics[][2] = {
        {"photo.jpg", "photo"}, {"mask.png", "mask (pass a corrected one back with --mask)"},
        {"line.png", line_given ? "centre line followed (the body line given)"
                                : "centre line followed (line.json: correct it and pass it back with --line)"},
        {"strip.png", "straightened body, from its start"}, {"fitted_strip.png", "the fit, seen the same way"},
        {"basecolor.png", "fitted texture (base colour)"}, {"normal.png", "normal map"},
        {"preview.png", "preview on a snake body, at the fitted view scale"}};
    for (size_t i = 0; i < sizeof pics / sizeof pics[0]; i++)
        cli_buf_put(&b, "<figure><a href='%s'><img%s src='%s' alt='%s'></a><figcaption>%s</figcaption></figure>\n",
            pics[i][0], strstr(pics[i][0], "strip") ? " class='strip'" : "", pics[i][0], pics[i][1], pics[i][1]);
    cli_buf_put(&b, "</div>\n<h2>Objectives (lower is better)</h2>\n<table><tr><th></th>");
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        cli_buf_put(&b, "<th>%s</th>", sq_fit_objective_name(k));
    cli_buf_put(&b, "<th>score</th></tr>\n<tr><td class='l'>best.json</td>");
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        cli_buf_put(&b, "<td>%.4f</td>", r->best.obj[k]);
    cli_buf_put(&b, "<td>%.3f</td></tr>\n<tr><td class='l'>norm (median of the screening)</td>", r->best.score);
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        cli_buf_put(&b, "<td>%.4f</td>", r->norm[k]);
    cli_buf_put(&b, "<td></td></tr></table>\n");
    cli_buf_put(&b, "<p>The score is the sum of the objectives, each divided by its norm. best.json is the member of the "
            "re-scored Pareto front with the lowest score, except that a plain skin within 30%% of it is preferred, "
            "else the simplest category within 5%% of it (plain, then stripes or bands, then spots, then automata, "
            "then layered patterns, then reaction-diffusion: the simpler explanation). ");
    if (r->repicked)
        cli_buf_put(&b, "Every kind's best had its colours moved toward the photo's palette after the pick, and the pick "
                "was made again on them by the same rule: %s (%.3f) leads now, where %s (%.3f) was picked first. ",
            sq_fit_kind_name(sq_fit_kind_of(&r->best.params)), r->best.score, sq_fit_kind_name(r->first_pick),
            r->kind_best[r->first_pick].score);
    if (r->plain_of_pattern)
        cli_buf_put(&b, "The plain skin is the best pattern's plain twin (its scales, view scale and light, no "
                "pattern), which scored better than the best plain skin searched for. ");
    if (r->plain_twin)
        cli_buf_put(&b, "The fitted pattern was invisible (%.1f%% of the band more than 5 CIEDE2000 from the dominant "
                "colour): best.json is its plain twin%s. ",
            100 * r->visibility, r->nfront > 1 ? ", and the pattern itself is front/01.json" : "");
    else if (r->twin_score > 0)
        cli_buf_put(&b, "The fitted pattern looks faint (%.1f%% of the band more than 5 CIEDE2000 from the dominant "
                "colour), but its plain twin scored %.3f, more than 5%% worse: the pattern stays. ",
            100 * r->visibility, r->twin_score);
    if (r->polish_before > 0)
        cli_buf_put(&b, "The nlopt polish moved %s from %.3f to %.3f (%s).",
            r->repicked ? "the first pick" : "it", r->polish_before, r->polish_after,
            r->polish_kept ? "kept" : "not kept");
    else
        cli_buf_put(&b, "The nlopt polish did not run (%s).", r->stopped ? "stopped early" : "no budget left");
    if (r->kind_recoloured[sq_fit_kind_of(&r->best.params)])
        cli_buf_put(&b, " best.json's colours, moved toward the photo's palette, took it from %.3f to %.3f.", r->recolour_before,
            r->recolour_after);
    cli_buf_put(&b, "</p>\n");
    cli_buf_put(&b, "<h2>Categories</h2>\n");
    if (r->read_corr != 0)
        cli_buf_put(&b, "<p>The photo's strip repeats along the body every %.0f strip rows (view scale %.2f). "
                "The automaton read off it best correlates %.2f with its lightness: %s.</p>\n",
            r->read_view_scale * SQ_FIT_STRIP_W / SQ_FIT_BAND_WIDTH, r->read_view_scale, fabs(r->read_corr),
            r->automata_read > 0 ? "the automata read started the screening"
                                 : "below 0.8, too weak to start the screening (an automaton can imitate any "
                                   "pattern that repeats)");
    if (r->spots_read_across > 0)
        cli_buf_put(&b, "<p>The best spot lattice read off the strip has %d spots round the body at view scale %.2f "
                "(score %.2f): %s.</p>\n",
            r->spots_read_across, r->spots_read_view_scale, r->spots_read_score,
            r->spots_read == 0 ? "below 0.55, too weak to start the screening"
            : r->spots_held    ? "the lattices read started the spots' screening, and the spots niche searched the one "
                                 "its best started from"
                               : "the lattices read started the spots' screening");
    if (r->spots_recoloured > 0)
        cli_buf_put(&b, "<p>The lattices read that suited the strip's layout best were recoloured toward its palette "
                "(%d candidates): the best palette objective went from %.2f to %.2f.</p>\n",
            r->spots_recoloured, r->spots_palette_read, r->spots_palette_recoloured);
    if (r->layer_searched) {
        cli_buf_put(&b, "<p>A layer of %s was searched over the best %s skin (%ld evaluations): the layered skin "
                "re-scored %.3f against the champion's %.3f, ",
            sq_pattern_type_name(r->layer_kind), sq_pattern_type_name(r->layer_base), r->layer_evals, r->layer_score,
            r->layer_under);
        if (r->layer_visibility >= 0)
            cli_buf_put(&b, "better by more than 20%%, and its layer changes %.1f%% of the band by more than 5 CIEDE2000%s",
                100 * r->layer_visibility, r->layer_lead ? ": it leads" : ", under the 5% a visible layer must: it does not lead");
        else
            cli_buf_put(&b, "not the 20%% better a layered skin must be to lead (one pattern with a layer's freedom "
                            "gains up to that)");
        if (r->repicked)
            cli_buf_put(&b, "; that was before the recolouring, after which the pick was made again (above)");
        cli_buf_put(&b, ".</p>\n");
    }
    cli_buf_put(&b, "<figure><a href='kinds.png'><img class='wide' src='kinds.png' alt='each kind&#39;s best'></a>"
            "<figcaption>The straightened body and, under it, each kind's best fit seen the same way (the first "
            "twelve body widths); best.json's kind in green. Each is a preset in kinds/; a <em>recoloured</em> one had its "
            "colours moved toward the photo's palette after the pick, and scores better so. The pick was then made "
            "again on those scores by the same rule, a simpler kind within its margin still going first (the table's "
            "\"at the pick\" gives the scores the first pick compared).</figcaption></figure>\n");
    cli_buf_put(&b, "<table><tr><th>category</th><th>best re-scored score</th><th>at the pick</th><th>preset</th><th>view scale</th>"
            "<th>evolved</th></tr>\n");
    for (int c = 0; c < SQ_FIT_KINDS; c++) {
        const SqFitCandidate *k = &r->kind_best[c];
        if (!isfinite(k->score))
            continue;
        char pick[32] = "";
        if (isfinite(r->category_score[c]))
            snprintf(pick, sizeof pick, "%.3f", r->category_score[c]);
        cli_buf_put(&b, "<tr><td class='l'>%s</td><td>%.3f</td><td>%s</td><td class='l'><a href='kinds/%s.json'>kinds/%s.json</a>%s</td>"
                "<td>%.2f</td><td class='l'>",
            sq_fit_kind_name(c), k->score, pick, sq_fit_kind_name(c), sq_fit_kind_name(c),
            c == sq_fit_kind_of(&r->best.params) ? (r->kind_recoloured[c] ? " (best.json, recoloured)" : " (best.json)")
            : r->kind_recoloured[c] ? " (recoloured)" : "",
            k->view_scale);
        if (r->survivor[c])
            cli_buf_put(&b, "to the end");
        else if (r->dropped_at[c] > 0)
            cli_buf_put(&b, "dropped after %ld evaluations, judged %.3f", r->dropped_at[c], r->judged[c]);
        else if (c == SQ_FIT_LAYERED && r->layer_searched)
            cli_buf_put(&b, "a layer over the champion");
        cli_buf_put(&b, "</td></tr>\n");
    }
    cli_buf_put(&b, "</table>\n<h2>Convergence and the Pareto front</h2>\n<div class='plots'>\n");
    convergence_svg(&b, r);
    front_svg(&b, r, SQ_OBJ_PALETTE, SQ_OBJ_SHAPE);
    front_svg(&b, r, SQ_OBJ_ALONG, SQ_OBJ_ACROSS);
    cli_buf_put(&b, "<p style='font-size:12px;color:#555;max-width:1100px'>Left: each dot is one generation's best score "
            "in its kind, the line the best score so far, and the green dot best.json's score once re-scored at "
            "the finer size over several pattern seeds. A pattern is one random instance: the best so far can be "
            "one instance's luck, which the dots do not share. The other two plots: the re-scored Pareto front, two objectives at a "
            "time, best.json in green.</p>\n");
    cli_buf_put(&b, "</div>\n<h2>Front</h2>\n<table><tr><th>preset</th><th>category</th><th>view scale</th>");
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        cli_buf_put(&b, "<th>%s</th>", sq_fit_objective_name(k));
    cli_buf_put(&b, "<th>score</th></tr>\n");
    for (int i = 0; i < r->nfront; i++) {
        cli_buf_put(&b, "<tr><td class='l'><a href='front/%02d.json'>front/%02d.json</a></td><td class='l'>%s</td><td>%.2f</td>", i, i,
            sq_fit_kind_name(sq_fit_kind_of(&r->front[i].params)), r->front[i].view_scale);
        for (int k = 0; k < SQ_OBJ_COUNT; k++)
            cli_buf_put(&b, "<td>%.4f</td>", r->front[i].obj[k]);
        cli_buf_put(&b, "<td>%.3f</td></tr>\n", r->front[i].score);
    }
    cli_buf_put(&b, "</table>\n<p>Timings: the photo read and prepared %.1f s; screen %.1f s, evolve %.1f s, re-score %.1f s, "
            "layer %.1f s, polish %.1f s, the kinds recoloured %.1f s; the outputs written %.1f s. All numbers are "
            "in <a href='fit.json'>fit.json</a>.</p>\n</body></html>\n",
        prepare_s, r->seconds[0], r->seconds[1], r->seconds[2], r->layer_seconds, r->seconds[3], r->recolour_seconds,
        total_s - prepare_s - search_s);
    if (b.fail) {
        free(b.s);
        return sq_error_set(err, SQ_ERR_NOMEM, "report.html", "out of memory");
    }
    SqStatus st = sq_io_write_file(path, b.s, b.n, err);
    free(b.s);
    return st;
}
