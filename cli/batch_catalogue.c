/* squama batch's catalogue: catalogue.csv, and index.html with thumbnails, category filters
 * and the confusion matrix of expected against fitted categories. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "batch.h"
#include "buf.h"
#include "cli.h"
#include "squama/io.h"

void batch_confusion(const CliManifestRow *rows, const BatchResult *res, int n, BatchConfusion *c)
{
    memset(c, 0, sizeof *c);
    for (int i = 0; i < n; i++) {
        int e = rows[i].expected, f = res[i].fitted;
        if (res[i].status != BATCH_OK || e < 0 || f < 0)
            continue;
        c->m[e][f]++;
        c->expected_total[e]++;
        c->total++;
        c->correct += e == f;
    }
}

static const char *cat_name(int c)
{
    return c >= 0 ? sq_pattern_type_name(c) : "";
}

/* catalogue.csv's columns: these, the objectives (named as squama score names them), and
 * these. */
enum { NLEAD = 5, NTRAIL = 7 };
static const char *const lead_head[NLEAD] = {"id", "species", "expected", "fitted", "score"};
static const char *const trail_head[NTRAIL] = {"preset", "status", "error", "line", "seconds", "evaluations",
                                                   "strip_widths"};

/* Appends one line of catalogue.csv; returns nonzero when out of memory. */
static int csv_line(char **buf, size_t *len, size_t *cap, const char *const *lead, const char *const *obj,
                    const char *const *trail)
{
    int oom = 0;
    for (int k = 0; k < NLEAD; k++)
        oom |= sq_io_csv_append(buf, len, cap, lead[k], ',');
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        oom |= sq_io_csv_append(buf, len, cap, obj[k], ',');
    for (int k = 0; k < NTRAIL; k++)
        oom |= sq_io_csv_append(buf, len, cap, trail[k], k + 1 < NTRAIL ? ',' : '\n');
    return oom;
}

static SqStatus write_csv(const char *outdir, const CliManifestRow *rows, const BatchResult *res, int n, SqError *err)
{
    char *buf = NULL;
    size_t len = 0, cap = 0;
    const char *names[SQ_OBJ_COUNT];
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        names[k] = sq_fit_objective_name(k);
    int oom = csv_line(&buf, &len, &cap, lead_head, names, trail_head);
    for (int i = 0; i < n; i++) {
        const BatchResult *r = &res[i];
        if (r->status == BATCH_PENDING)
            continue;
        int ok = r->status == BATCH_OK;
        char score[64], obj[SQ_OBJ_COUNT][64], line[32], seconds[64], evals[32], widths[32] = "",
            preset[CLI_ID_MAX + 16] = "";
        const char *objp[SQ_OBJ_COUNT];
        snprintf(score, sizeof score, "%.6g", r->score);
        for (int k = 0; k < SQ_OBJ_COUNT; k++) {
            snprintf(obj[k], sizeof obj[k], "%.6g", r->obj[k]);
            objp[k] = ok ? obj[k] : "";
        }
        snprintf(line, sizeof line, "%d", rows[i].line);
        snprintf(seconds, sizeof seconds, "%.1f", isfinite(r->seconds) ? r->seconds : 0);
        snprintf(evals, sizeof evals, "%ld", r->evals);
        if (ok && r->strip_widths > 0)
            snprintf(widths, sizeof widths, "%.2f", r->strip_widths);
        if (ok)
            snprintf(preset, sizeof preset, "%s/best.json", rows[i].id);
        const char *lead[NLEAD] = {rows[i].id, rows[i].species, cat_name(rows[i].expected),
                                   ok ? cat_name(r->fitted) : "", ok ? score : ""};
        const char *trail[NTRAIL] = {preset, ok ? "ok" : "error", ok ? "" : r->error, line, ok ? seconds : "",
                                     ok ? evals : "", widths};
        oom |= csv_line(&buf, &len, &cap, lead, objp, trail);
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/catalogue.csv", outdir);
    SqStatus st = oom ? sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory")
                      : sq_io_write_file(path, buf ? buf : "", len, err);
    free(buf);
    return st;
}

static const char *const short_name[SQ_PATTERN_COUNT] = {"none", "longit.", "transv.", "spots", "other s.",
                                                        "complex"};

static void confusion_html(CliBuf *b, const BatchConfusion *c, int errors, int without)
{
    cli_buf_put(b, "<h2>Expected against fitted category</h2>\n");
    if (c->total == 0) {
        cli_buf_put(b, "<p>No fitted row has an expected category yet.</p>\n");
        return;
    }
    cli_buf_put(b, "<table class='cm'><tr><th>expected \\ fitted</th>");
    for (int f = 0; f < SQ_PATTERN_COUNT; f++)
        cli_buf_put(b, "<th title='%s'>%s</th>", sq_pattern_type_name(f), short_name[f]);
    cli_buf_put(b, "<th>rows</th><th>accuracy</th></tr>\n");
    for (int e = 0; e < SQ_PATTERN_COUNT; e++) {
        cli_buf_put(b, "<tr><th>%s</th>", sq_pattern_type_name(e));
        for (int f = 0; f < SQ_PATTERN_COUNT; f++) {
            const char *cls = e == f ? "diag" : c->m[e][f] ? "off" : "";
            if (c->m[e][f])
                cli_buf_put(b, "<td class='%s'>%d</td>", cls, c->m[e][f]);
            else
                cli_buf_put(b, "<td class='%s'>&middot;</td>", cls);
        }
        if (c->expected_total[e])
            cli_buf_put(b, "<td>%d</td><td>%.0f%%</td></tr>\n", c->expected_total[e],
                        100.0 * c->m[e][e] / c->expected_total[e]);
        else
            cli_buf_put(b, "<td>0</td><td></td></tr>\n");
    }
    cli_buf_put(b, "</table>\n<p>Overall: <b>%d of %d</b> rows fitted to their expected category (%.0f%%)", c->correct,
                c->total, 100.0 * c->correct / c->total);
    if (errors || without)
        cli_buf_put(b, "; not counted: %d rows that failed, %d without an expected category", errors, without);
    cli_buf_put(b, ".</p>\n");
}

/* A link to the row's file id/rel when it is there. */
static void link_if_there(CliBuf *b, const char *outdir, const char *id, const char *rel, const char *text)
{
    char path[4096];
    if (cli_pathf(path, sizeof path, "%s/%s/%s", outdir, id, rel) != 0 || access(path, R_OK) != 0)
        return;
    cli_buf_put(b, ", <a href='");
    cli_buf_html(b, id);
    cli_buf_put(b, "/%s'>%s</a>", rel, text);
}

/* A row fitted to another category than expected: links to each kind's best (kinds.png)
 * and to the expected kind's best preset, when the fit made them (a complex row: the best
 * reaction-diffusion and the best layered skin, both of which the batch counts complex). */
static void differs_html(CliBuf *b, const char *outdir, const char *id, int expected)
{
    cli_buf_put(b, "category differs");
    link_if_there(b, outdir, id, "kinds.png", "each kind's best");
    char rel[64], text[64];
    snprintf(rel, sizeof rel, "kinds/%s.json", cat_name(expected));
    snprintf(text, sizeof text, "the best %s", cat_name(expected));
    link_if_there(b, outdir, id, rel, text);
    if (expected == SQ_PATTERN_COMPLEX)
        link_if_there(b, outdir, id, "kinds/layered.json", "the best layered");
}

static SqStatus write_html(const char *outdir, const CliManifestRow *rows, const BatchResult *res, int n, SqError *err)
{
    CliBuf b = {0};
    int done = 0, errors = 0, without = 0;
    for (int i = 0; i < n; i++) {
        done += res[i].status != BATCH_PENDING;
        errors += res[i].status == BATCH_ERROR;
        without += res[i].status == BATCH_OK && rows[i].expected < 0;
    }
    cli_buf_put(&b,
                "<!doctype html>\n<html><head><meta charset='utf-8'><title>squama batch</title>\n"
                "<style>body{font-family:sans-serif;margin:24px;color:#222}table{border-collapse:collapse;font-size:13px}"
                "td,th{border:1px solid #ccc;padding:3px 6px;vertical-align:middle}th{background:#eee}"
                "td.n{text-align:right}img{max-height:80px;max-width:160px;border:1px solid #ccc}"
                "table.cm td{text-align:right;min-width:3em}td.diag{background:#cfc}td.off{background:#fdd}"
                "tr.error td{background:#fee}button{margin:0 4px 6px 0}button.on{background:#346;color:#fff}"
                "</style></head><body>\n<h1>squama batch</h1>\n<p>%d of %d rows done, %d failed. The same rows as "
                "<a href='catalogue.csv'>catalogue.csv</a>; each row links to its fit's report.</p>\n",
                done, n, errors);
    BatchConfusion c;
    batch_confusion(rows, res, n, &c);
    confusion_html(&b, &c, errors, without);
    cli_buf_put(&b, "<h2>Rows</h2>\n<p>Show: <button data-f='' class='on'>all</button>");
    for (int f = 0; f < SQ_PATTERN_COUNT; f++)
        cli_buf_put(&b, "<button data-f='%s'>%s</button>", sq_pattern_type_name(f), sq_pattern_type_name(f));
    cli_buf_put(&b, "<button data-f='error'>errors</button> by <label><input type='radio' name='by' value='fitted' "
                    "checked> fitted</label> <label><input type='radio' name='by' value='expected'> expected</label> "
                    "category</p>\n<table id='rows'><tr><th>id</th><th>species</th><th>expected</th><th>fitted</th>"
                    "<th>score</th><th>photo (outside the mask veiled blue)</th><th>strip: photo above, fit below</th>"
                    "<th>fitted texture</th><th>preview</th><th>note</th></tr>\n");
    for (int i = 0; i < n; i++) {
        const BatchResult *r = &res[i];
        if (r->status == BATCH_PENDING)
            continue;
        int ok = r->status == BATCH_OK;
        const char *id = rows[i].id;
        cli_buf_put(&b, "<tr class='%s' data-fitted='%s' data-expected='%s'><td>", ok ? "ok" : "error",
                    ok ? cat_name(r->fitted) : "error", cat_name(rows[i].expected));
        if (ok) {
            cli_buf_put(&b, "<a href='");
            cli_buf_html(&b, id);
            cli_buf_put(&b, "/report.html'>");
        }
        cli_buf_html(&b, id[0] ? id : "(no id)");
        cli_buf_put(&b, "%s</td><td><i>", ok ? "</a>" : "");
        cli_buf_html(&b, rows[i].species);
        cli_buf_put(&b, "</i></td><td>%s</td><td>%s</td>", cat_name(rows[i].expected), ok ? cat_name(r->fitted) : "");
        if (ok) {
            cli_buf_put(&b, "<td class='n'>%.3f</td>", r->score);
            static const char *const th[] = {"thumb_photo.png", "thumb_strips.png", "thumb_texture.png",
                                             "thumb_preview.png"};
            static const char *const full[] = {"photo.jpg", "report.html", "basecolor.png", "preview.png"};
            for (int k = 0; k < 4; k++) {
                cli_buf_put(&b, "<td><a href='");
                cli_buf_html(&b, id);
                cli_buf_put(&b, "/%s'><img loading='lazy' src='", full[k]);
                cli_buf_html(&b, id);
                cli_buf_put(&b, "/%s' alt=''></a></td>", th[k]);
            }
            cli_buf_put(&b, "<td>");
            if (rows[i].expected >= 0 && rows[i].expected != r->fitted)
                differs_html(&b, outdir, id, rows[i].expected);
            if (r->strip_widths > 0 && r->strip_widths < CLI_SHORT_STRIP) {
                cli_buf_put(&b, "%s<b>short strip</b>: %.1f body widths of the body, too few to see a pattern "
                                "repeat; %s (see <a href='",
                            rows[i].expected >= 0 && rows[i].expected != r->fitted ? "<br>" : "",
                            floor(r->strip_widths * 10) / 10,
                            rows[i].body_line ? "draw its body line along a longer stretch"
                                              : "give the row a body line or a mask");
                cli_buf_html(&b, id);
                cli_buf_put(&b, "/line.png'>the line followed</a>)");
            }
            cli_buf_put(&b, "</td></tr>\n");
        } else {
            cli_buf_put(&b, "<td colspan='6'>");
            cli_buf_html(&b, r->error);
            cli_buf_put(&b, "</td></tr>\n");
        }
    }
    cli_buf_put(&b, "</table>\n<script>\n"
                    "let f = '';\n"
                    "function show() {\n"
                    "  const by = document.querySelector('input[name=by]:checked').value;\n"
                    "  for (const tr of document.querySelectorAll('#rows tr[data-fitted]'))\n"
                    "    tr.style.display = !f || (f == 'error' ? tr.className == 'error' : tr.dataset[by] == f) ? '' : 'none';\n"
                    "  for (const bt of document.querySelectorAll('button')) bt.className = bt.dataset.f == f ? 'on' : '';\n"
                    "}\n"
                    "for (const bt of document.querySelectorAll('button')) bt.onclick = () => { f = bt.dataset.f; show(); };\n"
                    "for (const r of document.querySelectorAll('input[name=by]')) r.onchange = show;\n"
                    "</script>\n</body></html>\n");
    char path[4096];
    snprintf(path, sizeof path, "%s/index.html", outdir);
    SqStatus st = b.fail ? sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory")
                         : sq_io_write_file(path, b.s, b.n, err);
    free(b.s);
    return st;
}

SqStatus batch_write_catalogue(const char *outdir, const CliManifestRow *rows, const BatchResult *res, int n,
                               SqError *err)
{
    SqStatus st = write_csv(outdir, rows, res, n, err);
    return st != SQ_OK ? st : write_html(outdir, rows, res, n, err);
}
