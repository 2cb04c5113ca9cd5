/* One photo fitted and its outputs written (squama fit, and squama batch per row). */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>
#include <omp.h>

#include "cli.h"
#include "fit_job.h"
#include "fit_report.h"
#include "json_util.h"
#include "squama/fitness.h"
#include "squama/io.h"
#include "squama/preset.h"

typedef struct Ctx {
    const char *outdir;
    int quiet, json, tty;
    double last_checkpoint, last_draw, budget;
    long max_evals;
    double offset_s;  /* time spent before the search: earlier runs' (a resume) and the preparation */
    long offset_evals; /* evaluations spent by earlier runs (a resume) */
    char checkpoint_error[SQ_ERROR_WHAT_MAX + SQ_ERROR_WHERE_MAX + 8];
} Ctx;

SqStatus cli_fit_write_preset(const char *path, const SqFitCandidate *c, const char *name, SqError *err)
{
    SqPresetInfo info = {0};
    snprintf(info.name, sizeof info.name, "%s", name);
    snprintf(info.notes, sizeof info.notes,
             "fitted by squama fit; view scale %.3f (body circumferences per texture tile)",
             c->view_scale);
    char *text = sq_preset_to_json(&c->params, &info, err);
    if (!text)
        return err ? err->status : SQ_ERR_INTERNAL;
    SqStatus st = sq_io_write_file(path, text, strlen(text), err);
    free(text);
    return st;
}

static cJSON *objectives_json(const double *obj)
{
    cJSON *o = cJSON_CreateObject();
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        cJSON_AddItemToObject(o, sq_fit_objective_name(k), sq__json_exact_number(obj[k]));
    return o;
}

/* DIR/checkpoint: the front so far as presets plus an index with view scales and the time
 * spent; every file atomic, the index last. */
static void write_checkpoint(Ctx *x, const SqFitProgress *p)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/checkpoint", x->outdir);
    if (cli_mkdirs(path) != 0)
        return;
    SqError err;
    cJSON *root = cJSON_CreateObject(), *arr = cJSON_CreateArray();
    cJSON_AddStringToObject(root, "format", "squama-checkpoint/1");
    cJSON_AddNumberToObject(root, "seconds", p->elapsed + x->offset_s);
    cJSON_AddNumberToObject(root, "evaluations", (double)(p->evals + x->offset_evals));
    for (int i = 0; i < p->nfront; i++) {
        snprintf(path, sizeof path, "%s/checkpoint/%02d.json", x->outdir, i);
        if (cli_fit_write_preset(path, &p->front[i], "checkpoint", &err) != SQ_OK) {
            snprintf(x->checkpoint_error, sizeof x->checkpoint_error, "%s (%s)", err.what, err.where);
            continue;
        }
        cJSON *e = cJSON_CreateObject();
        snprintf(path, sizeof path, "%02d.json", i);
        cJSON_AddStringToObject(e, "preset", path);
        cJSON_AddItemToObject(e, "view_scale", sq__json_exact_number(p->front[i].view_scale));
        cJSON_AddItemToArray(arr, e);
    }
    cJSON_AddItemToObject(root, "front", arr);
    char *text = sq__json_print(root);
    cJSON_Delete(root);
    snprintf(path, sizeof path, "%s/checkpoint/checkpoint.json", x->outdir);
    if (text && sq_io_write_file(path, text, strlen(text), &err) != SQ_OK)
        snprintf(x->checkpoint_error, sizeof x->checkpoint_error, "%s (%s)", err.what, err.where);
    free(text);
}

static void progress(const SqFitProgress *p, void *ctx)
{
    Ctx *x = ctx;
    double t = cli_now_s();
    /* every 5 s, and at each stage's end but the evolution's generations and the layer's
     * steps: a finished fit's checkpoint holds its front and evaluations */
    if (t - x->last_checkpoint > 5 || (strcmp(p->stage, "evolve") != 0 && strcmp(p->stage, "layer") != 0)) {
        write_checkpoint(x, p);
        x->last_checkpoint = t;
    }
    double rate = p->elapsed > 0 ? p->evals / p->elapsed : 0;
    if (x->json) {
        char gen[48] = "";
        if (isfinite(p->generation_best))
            snprintf(gen, sizeof gen, ", \"generation_best\": %.4f", p->generation_best);
        printf("{\"stage\": \"%s\", \"generation\": %d, \"evaluations\": %ld, \"seconds\": %.2f, "
               "\"evaluations_per_s\": %.1f, \"best_score\": %.4f%s, \"category\": \"%s\"}\n",
               p->stage, p->generation, p->evals, p->elapsed, rate, p->best_score, gen,
               sq_fit_kind_name(p->category));
        fflush(stdout);
        return;
    }
    if (x->quiet || !x->tty || (t - x->last_draw < 0.2 && strcmp(p->stage, "evolve") == 0))
        return;
    x->last_draw = t;
    double frac = x->budget > 0 ? p->elapsed / x->budget
                  : x->max_evals > 0 ? (double)p->evals / (double)x->max_evals : 0;
    frac = frac < 0 ? 0 : frac > 1 ? 1 : frac;
    char bar[21];
    int fill = (int)(frac * 20 + 0.5);
    for (int i = 0; i < 20; i++)
        bar[i] = i < fill ? '#' : '.';
    bar[20] = 0;
    char left[32] = "";
    if (x->budget > 0)
        snprintf(left, sizeof left, "%3.0fs left", fmax(0, x->budget - p->elapsed));
    char gen[24] = ""; /* what the generation just scored: the best so far can be one lucky instance */
    if (isfinite(p->generation_best))
        snprintf(gen, sizeof gen, "  this gen %.3f", p->generation_best);
    fprintf(stderr, "\r[%s] %-7s gen %4d  %6ld evals %5.0f/s  best %.3f (pal %.2f shape %.2f along %.2f)%s %-12s %s\033[K",
            bar, p->stage, p->generation, p->evals, rate, p->best_score, p->best[SQ_OBJ_PALETTE],
            p->best[SQ_OBJ_SHAPE], p->best[SQ_OBJ_ALONG], gen, sq_fit_kind_name(p->category), left);
    fflush(stderr);
}

/* A job's clock: when it started, and the seconds its photo's preparation and its search
 * took; the budget it was given (the whole command's; the search's share is fo.budget). */
typedef struct Clock {
    double t0, prepare, search, budget;
    double resumed_s; /* what the runs before a resume spent */
    long resumed_evals;
} Clock;

/* Every output into the staging folder s; write_outputs moves them into outdir as a set. */
static SqStatus stage_outputs(CliStaging *s, const char *outdir, const char *photo_path, const char *mask_path,
                              const char *line_path, const CliPhoto *given, const SqPrepared *prep, const SqFeatures *target, const SqFitOptions *fo,
                              char *const *starts, const SqFitResult *r, int size, const Clock *clock, SqError *err)
{
    char path[4200], file[64];
    SqStatus st = SQ_OK;
    /* the front and the best preset */
    for (int i = 0; i < r->nfront && st == SQ_OK; i++) {
        snprintf(file, sizeof file, "front/%02d.json", i);
        char name[64];
        snprintf(name, sizeof name, "front %d of the fit", i);
        st = cli_staging_path(s, file, path, sizeof path, err);
        if (st == SQ_OK)
            st = cli_fit_write_preset(path, &r->front[i], name, err);
    }
    for (int i = r->nfront; i < 1000 && st == SQ_OK; i++) { /* a longer front an earlier fit left here */
        struct stat sb;
        snprintf(file, sizeof file, "front/%02d.json", i);
        if (cli_pathf(path, sizeof path, "%s/%s", outdir, file) != 0 || lstat(path, &sb) != 0)
            break;
        st = cli_staging_drop(s, file, err);
    }
    const char *base = strrchr(photo_path, '/');
    char name[256];
    snprintf(name, sizeof name, "fit of %s", base ? base + 1 : photo_path);
    if (st == SQ_OK)
        st = cli_staging_path(s, "best.json", path, sizeof path, err);
    if (st == SQ_OK)
        st = cli_fit_write_preset(path, &r->best, name, err);
    if (st != SQ_OK)
        return st;

    /* the maps, the preview, the prepared photo and the fitted strip */
    SqGenOptions go = sq_gen_options_default(size);
    SqTextures tex;
    st = sq_gen_render(&r->best.params, &go, &tex, err);
    if (st != SQ_OK)
        return st;
    struct { const char *name; const SqImage *img; int bits; } maps[] = {
        {"basecolor", &tex.basecolor, 8}, {"height", &tex.height, 16},
        {"roughness", &tex.roughness, 8}, {"normal", &tex.normal, 8}};
    for (size_t i = 0; i < sizeof maps / sizeof maps[0] && st == SQ_OK; i++) {
        snprintf(file, sizeof file, "%s.png", maps[i].name);
        SqWriteOptions wo = {.bits = maps[i].bits};
        st = cli_staging_path(s, file, path, sizeof path, err);
        if (st == SQ_OK)
            st = sq_io_write_image(path, maps[i].img, &wo, err);
    }
    SqImage strip = {0};
    if (st == SQ_OK)
        st = sq_fit_candidate_strip(&tex.basecolor, &tex.normal, &tex.roughness, &prep->light, r->best.view_scale, fo->band_centre,
                                    prep->strip.height, &strip, err);
    if (st == SQ_OK)
        st = cli_staging_path(s, "fitted_strip.png", path, sizeof path, err);
    if (st == SQ_OK)
        st = sq_io_write_image(path, &strip, NULL, err);
    sq_gen_textures_free(&tex);
    if (st == SQ_OK)
        st = cli_fit_write_kinds(s, prep, fo->band_centre, r, &strip, size, base ? base + 1 : photo_path, err);
    sq_image_free(&strip);
    if (st == SQ_OK) {
        SqPhotoOptions po = sq_fit_photo_options_default();
        po.width = 1024;
        po.height = 640;
        po.preview = 1;
        po.view_scale = r->best.view_scale; /* the pattern as big on the body as in the photo */
        po.texture_size = 512;
        SqImage photo, mask;
        st = sq_fit_synth_photo(&r->best.params, &po, &photo, &mask, NULL, err);
        if (st == SQ_OK) {
            st = cli_staging_path(s, "preview.png", path, sizeof path, err);
            if (st == SQ_OK)
                st = sq_io_write_image(path, &photo, NULL, err);
            sq_image_free(&photo);
            sq_image_free(&mask);
        }
    }
    if (st == SQ_OK) { /* the prepared photo; not over the photo fitted, when it is this one */
        if (cli_pathf(path, sizeof path, "%s/photo.jpg", outdir) != 0)
            st = sq_error_set(err, SQ_ERR_INVALID, outdir, "the output folder's name is too long");
        else if (!cli_same_file(photo_path, path) && (st = cli_staging_path(s, "photo.jpg", path, sizeof path, err)) == SQ_OK)
            st = sq_io_write_image(path, &prep->photo, NULL, err);
    }
    if (st == SQ_OK)
        st = cli_write_full_mask(s, outdir, prep, given, mask_path, err);
    if (st == SQ_OK)
        st = cli_staging_path(s, "strip.png", path, sizeof path, err);
    if (st == SQ_OK)
        st = sq_io_write_image(path, &prep->strip, NULL, err);
    if (st == SQ_OK)
        st = cli_write_line(s, outdir, prep, line_path ? &given->line : NULL, line_path, err);
    if (st != SQ_OK)
        return st;

    /* fit.json */
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", "squama-fit/1");
    cJSON_AddStringToObject(root, "best", "best.json");
    cJSON *in = cJSON_AddObjectToObject(root, "inputs");
    cJSON_AddStringToObject(in, "photo", photo_path);
    if (mask_path)
        cJSON_AddStringToObject(in, "mask", mask_path);
    if (line_path)
        cJSON_AddStringToObject(in, "line", line_path);
    cJSON_AddStringToObject(in, "mask_source", sq_mask_source_name(prep->mask_source));
    cJSON_AddNumberToObject(in, "body_width_px", prep->body_width);
    cJSON_AddNumberToObject(in, "strip_length_px", prep->length);
    cJSON_AddItemToObject(in, "strip_body_widths", sq__json_exact_number(prep->length / prep->body_width));
    char warning[512];
    const int short_strip = cli_short_strip(prep, line_path != NULL, warning, sizeof warning);
    if (short_strip)
        cJSON_AddStringToObject(in, "warning", warning);
    cJSON_AddNumberToObject(in, "strip_stretches", prep->nruns);
    cJSON_AddNumberToObject(in, "strip_step_px", round(prep->step * 1e3) / 1e3);
    cJSON_AddNumberToObject(in, "edge_blur_px", round(prep->edge_blur * 1e3) / 1e3);
    cJSON_AddNumberToObject(in, "strip_blur", round(sq_fit_strip_blur(prep->step, prep->edge_blur) * 1e3) / 1e3);
    const double lxy[2] = {round(prep->light_xy[0] * 1e3) / 1e3, round(prep->light_xy[1] * 1e3) / 1e3};
    cJSON_AddItemToObject(in, "light", cJSON_CreateDoubleArray(lxy, 2)); /* in the photo's plane */
    cJSON *se = cJSON_AddObjectToObject(root, "search");
    cJSON_AddStringToObject(se, "method", sq_fit_method_name(fo->method));
    cJSON_AddNumberToObject(se, "seed", (double)fo->seed);
    cJSON_AddNumberToObject(se, "budget_s", clock->budget); /* the whole command's */
    cJSON_AddNumberToObject(se, "search_budget_s", fo->budget); /* less the photo's and the outputs' */
    cJSON_AddNumberToObject(se, "max_evaluations", (double)fo->max_evals);
    cJSON_AddNumberToObject(se, "evaluations", (double)r->evals);
    cli_starts_json(se, starts, fo->nstarts, r->starts_used);
    if (clock->resumed_evals > 0 || clock->resumed_s > 0) { /* a resume: what the runs before it spent */
        cJSON *re = cJSON_AddObjectToObject(se, "resumed");
        cJSON_AddNumberToObject(re, "evaluations", (double)clock->resumed_evals);
        cJSON_AddNumberToObject(re, "seconds", round(clock->resumed_s * 1e3) / 1e3);
    }
    cJSON_AddNumberToObject(se, "evaluations_per_s", clock->search > 0 ? r->evals / clock->search : 0);
    cJSON_AddBoolToObject(se, "stopped_early", r->stopped);
    cJSON *ti = cJSON_AddObjectToObject(se, "seconds");
    static const char *const stages[SQ_FIT_STAGES] = {"screen", "evolve", "rescore", "polish"};
    for (int i = 0; i < SQ_FIT_STAGES; i++)
        cJSON_AddNumberToObject(ti, stages[i], r->seconds[i]);
    cJSON_AddNumberToObject(ti, "layer", r->layer_seconds); /* between the re-scoring and the polish */
    cJSON_AddNumberToObject(ti, "recolour", r->recolour_seconds); /* every kind's best, after the polish */
    cJSON_AddNumberToObject(se, "recolour_evaluations", (double)r->recolour_evals); /* beyond evaluations */
    cJSON_AddNumberToObject(ti, "search", clock->search);
    cJSON_AddNumberToObject(ti, "prepare", clock->prepare); /* reading and preparing the photo */
    const double total = cli_now_s() - clock->t0;
    cJSON_AddNumberToObject(ti, "outputs", total - clock->prepare - clock->search); /* up to fit.json */
    cJSON_AddNumberToObject(ti, "total", total);
    cJSON_AddItemToObject(root, "objectives", objectives_json(r->best.obj));
    cJSON_AddItemToObject(root, "score", sq__json_exact_number(r->best.score));
    cJSON_AddStringToObject(root, "pick_rule",
                            "the front member with the lowest score: the sum over objectives of each "
                            "objective divided by its median over the screening (norm); a plain skin "
                            "within 30% of that score is preferred (the plain twin of the best pattern "
                            "when it scores better than the plain niche's best: plain_of_pattern), else "
                            "the simplest category within 5% of it (none, then longitudinal "
                            "or transversal, then spots, then other_simple, then layered, then complex), being the simpler "
                            "explanation; a pattern nobody can see (visibility below 0.02: the share of the "
                            "band's texels more than 5 CIEDE2000 from its dominant colour) is a plain skin, and "
                            "the champion becomes its plain twin, unless the twin scores more than 5% worse; a "
                            "stripe, band or spot champion (an automaton champion: the best of those) is given "
                            "a layer of another type, searched with it held, and the layered skin leads when it "
                            "beats the champion by 20% and its layer is visible (it changes at least 5% of the "
                            "band's texels by more than 5 CIEDE2000; layer_search); last, the champion and each "
                            "other kind's best have their colours moved toward the photo's palette, kept when "
                            "that scores better (kinds.KIND.recoloured; recolour) and, for the champion, when a "
                            "pattern or layer that showed still shows; then the pick is made again by the same "
                            "rule on the kinds' bests so recoloured (the layer searched over the champion still "
                            "needing its 20%, layer_search.kind_best; a pattern nobody can see not taken): "
                            "first_pick is the kind picked before, repicked says whether another one leads now");
    cJSON_AddStringToObject(root, "first_pick", sq_fit_kind_name(r->first_pick));
    cJSON_AddBoolToObject(root, "repicked", r->repicked);
    cJSON_AddItemToObject(root, "visibility", sq__json_exact_number(r->visibility));
    cJSON_AddBoolToObject(root, "plain_twin", r->plain_twin);
    cJSON_AddBoolToObject(root, "plain_of_pattern", r->plain_of_pattern);
    if (r->twin_score > 0)
        cJSON_AddItemToObject(root, "plain_twin_score", sq__json_exact_number(r->twin_score));
    if (r->read_corr != 0) {
        cJSON *ar = cJSON_AddObjectToObject(root, "automata_read");
        cJSON_AddNumberToObject(ar, "used", r->automata_read);
        cJSON_AddItemToObject(ar, "view_scale", sq__json_exact_number(r->read_view_scale));
        cJSON_AddItemToObject(ar, "correlation", sq__json_exact_number(r->read_corr));
    }
    if (r->bands_read_corr != 0) {
        cJSON *br = cJSON_AddObjectToObject(root, "bands_read");
        cJSON_AddItemToObject(br, "view_scale", sq__json_exact_number(r->bands_read_view_scale));
        cJSON_AddItemToObject(br, "correlation", sq__json_exact_number(r->bands_read_corr));
        cJSON_AddItemToObject(br, "explained", sq__json_exact_number(r->bands_read_explained));
    }
    if (r->spots_read_across > 0) {
        cJSON *sr = cJSON_AddObjectToObject(root, "spots_read");
        cJSON_AddNumberToObject(sr, "used", r->spots_read);
        cJSON_AddNumberToObject(sr, "across", r->spots_read_across);
        cJSON_AddItemToObject(sr, "view_scale", sq__json_exact_number(r->spots_read_view_scale));
        cJSON_AddItemToObject(sr, "score", sq__json_exact_number(r->spots_read_score));
        cJSON_AddBoolToObject(sr, "held", r->spots_held);
        if (r->spots_recoloured > 0) {
            cJSON_AddNumberToObject(sr, "recoloured", r->spots_recoloured);
            cJSON_AddItemToObject(sr, "palette_read", sq__json_exact_number(r->spots_palette_read));
            cJSON_AddItemToObject(sr, "palette_recoloured", sq__json_exact_number(r->spots_palette_recoloured));
        }
    }
    if (r->layer_searched) {
        cJSON *ls = cJSON_AddObjectToObject(root, "layer_search");
        cJSON_AddStringToObject(ls, "base", sq_pattern_type_name(r->layer_base));
        cJSON_AddStringToObject(ls, "layer", sq_pattern_type_name(r->layer_kind));
        cJSON_AddNumberToObject(ls, "evaluations", (double)r->layer_evals);
        cJSON_AddItemToObject(ls, "score", sq__json_exact_number(r->layer_score));
        cJSON_AddItemToObject(ls, "champion_score", sq__json_exact_number(r->layer_under));
        if (r->layer_visibility >= 0)
            cJSON_AddItemToObject(ls, "visibility", sq__json_exact_number(r->layer_visibility));
        cJSON_AddBoolToObject(ls, "leads", r->layer_lead); /* then; the pick made again: repicked */
        cJSON_AddBoolToObject(ls, "kind_best", r->layer_best_searched); /* kinds.layered is this skin */
    }
    cJSON_AddItemToObject(root, "norm", objectives_json(r->norm));
    cJSON_AddItemToObject(root, "view_scale", sq__json_exact_number(r->best.view_scale));
    cJSON_AddItemToObject(root, "band_centre", sq__json_exact_number(fo->band_centre));
    cJSON_AddStringToObject(root, "category", sq_fit_kind_name(sq_fit_kind_of(&r->best.params)));
    cJSON *pt = cJSON_AddArrayToObject(root, "pattern_types"); /* the base's, then each layer's */
    cJSON_AddItemToArray(pt, cJSON_CreateString(sq_pattern_type_name(r->best.params.Pattern_Type)));
    for (int l = 0; l < r->best.params.Pattern_Layers.count; l++)
        cJSON_AddItemToArray(pt, cJSON_CreateString(sq_pattern_type_name(r->best.params.Pattern_Layers.layer[l].spec.Pattern_Type)));
    cJSON *cs = cJSON_AddObjectToObject(root, "category_scores");
    for (int c = 0; c < SQ_FIT_KINDS; c++)
        if (isfinite(r->category_score[c]))
            cJSON_AddItemToObject(cs, sq_fit_kind_name(c), sq__json_exact_number(r->category_score[c]));
    cJSON *kb = cJSON_AddObjectToObject(root, "kinds"); /* each kind's best, best.json for its own */
    int offered[SQ_FIT_KINDS];
    const int noffered = sq_fit_kinds_offered(r, offered);
    for (int i = 0; i < noffered; i++) {
        const int c = offered[i];
        const SqFitCandidate *k = &r->kind_best[c];
        cJSON *e = cJSON_AddObjectToObject(kb, sq_fit_kind_name(c));
        snprintf(path, sizeof path, "kinds/%s.json", sq_fit_kind_name(c));
        cJSON_AddStringToObject(e, "preset", path);
        cJSON_AddNumberToObject(e, "rank", i); /* 0: best.json's kind, then by score */
        cJSON_AddItemToObject(e, "score", sq__json_exact_number(k->score));
        cJSON_AddItemToObject(e, "view_scale", sq__json_exact_number(k->view_scale));
        cJSON_AddItemToObject(e, "objectives", objectives_json(k->obj));
        cJSON_AddBoolToObject(e, "recoloured", r->kind_recoloured[c]);
    }
    cJSON *ni = cJSON_AddArrayToObject(root, "niches");
    for (int c = 0; c < SQ_FIT_KINDS; c++)
        if (r->niche[c])
            cJSON_AddItemToArray(ni, cJSON_CreateString(sq_fit_kind_name(c)));
    int order[SQ_FIT_KINDS], nd = 0; /* the niches dropped, in the order they went */
    for (int c = 0; c < SQ_FIT_KINDS; c++)
        if (r->dropped_at[c] > 0) {
            int j = nd++;
            for (; j > 0 && r->dropped_at[order[j - 1]] > r->dropped_at[c]; j--)
                order[j] = order[j - 1];
            order[j] = c;
        }
    cJSON *dr = cJSON_AddArrayToObject(root, "drops");
    for (int i = 0; i < nd; i++) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddStringToObject(e, "category", sq_fit_kind_name(order[i]));
        cJSON_AddNumberToObject(e, "evaluations", (double)r->dropped_at[order[i]]);
        cJSON_AddItemToObject(e, "judged", sq__json_exact_number(r->judged[order[i]]));
        cJSON_AddItemToArray(dr, e);
    }
    cJSON *po = cJSON_AddObjectToObject(root, "polish");
    cJSON_AddItemToObject(po, "score_before", sq__json_exact_number(r->polish_before));
    cJSON_AddItemToObject(po, "score_after", sq__json_exact_number(r->polish_after));
    cJSON_AddBoolToObject(po, "kept", r->polish_kept);
    if (r->recolour_before > 0) { /* the champion's colours moved toward the photo's palette, after the polish */
        cJSON *rc = cJSON_AddObjectToObject(root, "recolour");
        cJSON_AddItemToObject(rc, "score_before", sq__json_exact_number(r->recolour_before));
        if (r->recolour_after > 0)
            cJSON_AddItemToObject(rc, "score_after", sq__json_exact_number(r->recolour_after));
        cJSON_AddBoolToObject(rc, "kept", r->kind_recoloured[sq_fit_kind_of(&r->best.params)]);
    }
    cJSON *fr = cJSON_AddArrayToObject(root, "front");
    for (int i = 0; i < r->nfront; i++) {
        cJSON *e = cJSON_CreateObject();
        snprintf(path, sizeof path, "front/%02d.json", i);
        cJSON_AddStringToObject(e, "preset", path);
        cJSON_AddStringToObject(e, "category", sq_fit_kind_name(sq_fit_kind_of(&r->front[i].params)));
        cJSON_AddItemToObject(e, "objectives", objectives_json(r->front[i].obj));
        cJSON_AddItemToObject(e, "score", sq__json_exact_number(r->front[i].score));
        cJSON_AddItemToObject(e, "view_scale", sq__json_exact_number(r->front[i].view_scale));
        cJSON_AddItemToArray(fr, e);
    }
    cJSON *hi = cJSON_AddArrayToObject(root, "history");
    for (int i = 0; i < r->nhistory; i++) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "evaluations", (double)r->history[i].evals);
        cJSON_AddNumberToObject(e, "seconds", r->history[i].seconds);
        cJSON_AddNumberToObject(e, "best_score", r->history[i].best_score);
        cJSON_AddItemToObject(e, "best", objectives_json(r->history[i].best));
        if (r->history[i].stage)
            cJSON_AddStringToObject(e, "stage", r->history[i].stage);
        if (r->history[i].category >= 0 && isfinite(r->history[i].generation_best)) {
            cJSON_AddStringToObject(e, "category", sq_fit_kind_name(r->history[i].category));
            cJSON_AddNumberToObject(e, "generation_best", r->history[i].generation_best);
        }
        cJSON_AddItemToArray(hi, e);
    }
    (void)target;
    char *text = sq__json_print(root);
    cJSON_Delete(root);
    if (!text)
        return sq_error_set(err, SQ_ERR_NOMEM, "fit.json", "out of memory");
    st = cli_staging_path(s, "fit.json", path, sizeof path, err);
    if (st == SQ_OK)
        st = sq_io_write_file(path, text, strlen(text), err);
    free(text);
    if (st == SQ_OK)
        st = cli_staging_path(s, "report.html", path, sizeof path, err);
    if (st != SQ_OK)
        return st;
    return cli_fit_report(path, photo_path, r, short_strip ? warning : NULL, line_path != NULL, clock->prepare,
                          clock->search, total, err);
}

/* The outputs into DIR/.fit.tmp-XXXXXX, then moved into DIR as a set (cli_staging_commit):
 * a failure or an interruption leaves an earlier fit's outputs whole, not some of each. */
static SqStatus write_outputs(const char *outdir, const char *photo_path, const char *mask_path,
                              const char *line_path, const CliPhoto *given, const SqPrepared *prep, const SqFeatures *target, const SqFitOptions *fo,
                              char *const *starts, const SqFitResult *r, int size, const Clock *clock, SqError *err)
{
    char pattern[4200];
    if (cli_pathf(pattern, sizeof pattern, "%s/.fit.tmp-XXXXXX", outdir) != 0)
        return sq_error_set(err, SQ_ERR_INVALID, outdir, "the output folder's name is too long");
    CliStaging stg;
    SqStatus st = cli_staging_open(&stg, pattern, outdir, 64, err);
    if (st != SQ_OK)
        return st;
    st = stage_outputs(&stg, outdir, photo_path, mask_path, line_path, given, prep, target, fo, starts, r, size, clock,
                       err);
    if (st == SQ_OK)
        st = cli_staging_commit(&stg, 1, err);
    else
        cli_staging_where(&stg, err);
    cli_staging_free(&stg);
    return st;
}

void cli_fit_job_init(CliFitJob *job)
{
    memset(job, 0, sizeof *job);
    job->fo = sq_fit_options_default();
    job->po = sq_fit_prep_options_default();
    job->size = 1024;
}

int cli_fit_job_option(CliFitJob *job, int c, const char *arg, const char *cmd)
{
    long v;
    SqError err;
    SqFitOptions *fo = &job->fo;
    switch (c) {
    case 'b':
        fo->budget = cli_parse_time(arg);
        if (fo->budget <= 0)
            return cli_usage(cmd, "--budget takes a time such as 60s, 90 or 2m (a week at most), got '%s'", arg);
        job->budget_given = 1;
        return CLI_OK;
    case CLI_FITOPT_EVALS:
        if (cli_parse_int("--evals", arg, 100, 100000000, &v, &err) != 0)
            return cli_usage(cmd, "%s", err.what);
        fo->max_evals = v;
        return CLI_OK;
    case 's':
        if (cli_parse_int("--seed", arg, 0, 2147483647L, &v, &err) != 0)
            return cli_usage(cmd, "%s", err.what);
        fo->seed = (uint64_t)v;
        return CLI_OK;
    case 'j':
        if (cli_parse_int("--threads", arg, 1, 1024, &v, &err) != 0)
            return cli_usage(cmd, "%s", err.what);
        fo->threads = (int)v;
        return CLI_OK;
    case CLI_FITOPT_SIZE:
        if (cli_parse_int("--size", arg, 64, 8192, &v, &err) != 0)
            return cli_usage(cmd, "%s", err.what);
        job->size = (int)v;
        return CLI_OK;
    case CLI_FITOPT_WORK:
        if (cli_parse_int("--work-size", arg, 256, 8192, &v, &err) != 0)
            return cli_usage(cmd, "%s", err.what);
        job->po.work_size = (int)v;
        return CLI_OK;
    case CLI_FITOPT_CATEGORIES: {
        fo->categories = 0;
        char list[256];
        if (strlen(arg) >= sizeof list)
            return cli_usage(cmd, "--categories is too long");
        snprintf(list, sizeof list, "%s", arg);
        for (char *save = NULL, *name = strtok_r(list, ",", &save); name; name = strtok_r(NULL, ",", &save)) {
            if (strcmp(name, "all") == 0) {
                fo->categories |= SQ_FIT_ALL_KINDS;
                continue;
            }
            int found = sq_fit_kind_from_name(name);
            if (found < 0)
                return cli_usage(cmd,
                                 "--categories takes kinds among none, longitudinal, transversal, "
                                 "spots, other_simple, complex, layered, or all; got '%s'",
                                 name);
            fo->categories |= 1u << found;
        }
        if (fo->categories == 0)
            return cli_usage(cmd, "--categories needs at least one pattern type");
        return CLI_OK;
    }
    case CLI_FITOPT_START:
        if (job->starts.nargs == CLI_START_ARGS)
            return cli_usage(cmd, "--start is given more than %d times: give a folder instead", CLI_START_ARGS);
        job->starts.arg[job->starts.nargs++] = arg;
        return CLI_OK;
    case CLI_FITOPT_NO_STARTS:
        job->starts.none = 1;
        return CLI_OK;
    default:
        return -1;
    }
}

int cli_fit_job_options_done(CliFitJob *job, const char *cmd)
{
    if (job->fo.max_evals > 0 && !job->budget_given)
        job->fo.budget = 0; /* an evaluation budget alone: deterministic */
    if (job->starts.none && job->starts.nargs > 0)
        return cli_usage(cmd, "--start and --no-starts contradict each other");
    SqError err;
    if (cli_starts_load(&job->starts, job->quiet, &err) != SQ_OK) {
        cli_starts_free(&job->starts);
        return cli_fail(&err);
    }
    job->fo.starts = job->starts.params;
    job->fo.nstarts = job->starts.n;
    return CLI_OK;
}

void cli_fit_job_free(CliFitJob *job)
{
    cli_starts_free(&job->starts);
    job->fo.starts = NULL;
    job->fo.nstarts = 0;
}

SqStatus cli_fit_job_run(const CliFitJob *job, CliFitOutcome *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    CliMade made;
    if (cli_mkdirs_new(job->outdir, &made) != 0)
        return sq_error_set(err, SQ_ERR_IO, job->outdir, "cannot create the output folder: %s", strerror(errno));
    if (access(job->outdir, W_OK) != 0) /* found now, not after the search */
        return sq_error_set(err, SQ_ERR_IO, job->outdir, "cannot write into the output folder: %s", strerror(errno));
    /* an input that an output would replace (photo.jpg, mask.png and line.json are left as
     * they are when they are the inputs) */
    static const char *const outputs[] = {"best.json", "fit.json", "report.html", "basecolor.png", "height.png",
                                          "roughness.png", "normal.png", "preview.png", "strip.png",
                                          "fitted_strip.png", "kinds.png", "line.png"};
    const char *const inputs[] = {job->photo, job->mask, job->line};
    for (size_t i = 0; i < sizeof inputs / sizeof inputs[0]; i++)
        for (size_t k = 0; inputs[i] && k < sizeof outputs / sizeof outputs[0]; k++) {
            char path[4200];
            snprintf(path, sizeof path, "%s/%s", job->outdir, outputs[k]);
            if (cli_same_file(inputs[i], path)) {
                cli_rmdirs_new(job->outdir, &made);
                return sq_error_set(err, SQ_ERR_INVALID, inputs[i], "the fit writes %s over it: give another -o",
                                    outputs[k]);
            }
        }
    if (job->fo.threads > 0)
        omp_set_num_threads(job->fo.threads); /* this thread's renders and photos too */
    Clock clock = {.t0 = cli_now_s(), .budget = job->fo.budget, .resumed_s = job->offset_s, .resumed_evals = job->offset_evals};
    CliPhoto in = {0};
    SqPrepared prep = {0};
    SqFeatures target;
    SqFitResult res = {0};
    SqFitOptions fo = job->fo;
    Ctx x = {0};
    SqStatus st = SQ_OK;
    if (cli_load_photo(job->photo, job->mask, job->line, &in, err) != 0)
        st = err->status != SQ_OK ? err->status : SQ_ERR_IO;
    if (st == SQ_OK)
        st = cli_prepare(&in, &job->po, &prep, err);
    if (st == SQ_OK)
        st = sq_fit_photo_target(&prep, &target, err);
    clock.prepare = cli_now_s() - clock.t0;
    char warning[512];
    if (st == SQ_OK && !job->quiet && cli_short_strip(&prep, job->line != NULL, warning, sizeof warning))
        fprintf(stderr, "squama: warning: %s\n", warning);
    if (fo.budget > 0) { /* the budget is the whole command's */
        fo.budget = cli_search_budget(fo.budget, clock.prepare, job->size);
        if (st == SQ_OK && !job->quiet && fo.budget < 0.5 * clock.budget)
            fprintf(stderr,
                    "squama: warning: the photo's preparation (%.1f s) and the outputs' reserve leave the search "
                    "%.2f s of the %.1f s budget; a longer --budget fits better\n",
                    clock.prepare, fo.budget, clock.budget);
    }
    if (st == SQ_OK) {
        x.outdir = job->outdir;
        x.quiet = job->quiet;
        x.json = job->json;
        x.tty = isatty(STDERR_FILENO);
        x.budget = fo.budget;
        x.max_evals = fo.max_evals;
        x.offset_s = job->offset_s + clock.prepare; /* a resume is charged for the preparation too */
        x.offset_evals = job->offset_evals;
        fo.progress = progress;
        fo.ctx = &x;
        fo.stop = job->stop;
        fo.strip = &prep.strip;
        fo.valid = &prep.valid;
        const double t = cli_now_s();
        st = sq_fit_run(&target, &fo, &res, err);
        clock.search = cli_now_s() - t;
        if (x.tty && !x.quiet && !x.json)
            fputs("\n", stderr);
    }
    if (st == SQ_OK)
        st = write_outputs(job->outdir, job->photo, job->mask, job->line, &in, &prep, &target, &fo, job->starts.path, &res,
                           job->size, &clock, err);
    if (st == SQ_OK) {
        if (x.checkpoint_error[0] && !job->quiet)
            fprintf(stderr, "squama: warning: a checkpoint could not be written: %s\n", x.checkpoint_error);
        out->best = res.best;
        out->nfront = res.nfront;
        out->evals = res.evals;
        out->seconds = cli_now_s() - clock.t0;
        out->search_seconds = clock.search;
        out->stopped = res.stopped;
    }
    sq_fit_result_free(&res);
    sq_fit_prepared_free(&prep);
    cli_photo_free(&in);
    if (st != SQ_OK) /* a refused photo leaves no empty folder */
        cli_rmdirs_new(job->outdir, &made);
    return st;
}
