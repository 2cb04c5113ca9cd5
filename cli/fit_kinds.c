/* Each kind's best of a fit: kinds/<kind>.json, and kinds.png, the photo's strip with
 * each kind's fitted strip under it, to see why the fit chose the kind it chose. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "fit_job.h"
#include "squama/io.h"

enum {
    ALONG = 768, /* strip rows shown, turned: twelve body widths */
    LABEL_W = 190,
    GAP = 8,
    PAD = 10
};

/* What each kind looks like, beside its name in the picture. */
static const char *gloss(int kind)
{
    static const char *const g[SQ_FIT_KINDS] = {"a plain skin", "stripes along the body", "bands across it",
                                                "spots, in a lattice or at random", "a cellular automaton", "reaction-diffusion",
                                                "a pattern over another"};
    return kind >= 0 && kind < SQ_FIT_KINDS ? g[kind] : "";
}

/* strip turned (along the body to the right), its first `along` rows, at (x0, y0) of dst. */
static void paste_turned(SqImage *dst, const SqImage *strip, int x0, int y0, int along)
{
    for (int y = 0; y < strip->width && y0 + y < dst->height; y++)
        for (int x = 0; x < along && x < strip->height && x0 + x < dst->width; x++) {
            const float *s = sq_image_at(strip, y, x);
            float *d = sq_image_at(dst, x0 + x, y0 + y);
            for (int c = 0; c < 3; c++)
                d[c] = s[c < strip->channels ? c : 0];
        }
}

/* The picture: a row for the photo's strip, then one for each kind's strip (NULL: none),
 * each labelled; the champion's kind in green. Without a font the rows go unlabelled, in
 * the order of the kinds. */
static SqStatus kinds_picture(const char *path, const SqImage *photo_strip, const SqImage *const *strips,
                              const SqFitResult *r, SqError *err)
{
    const int champion = sq_fit_kind_of(&r->best.params);
    int rows = 1;
    for (int k = 0; k < SQ_FIT_KINDS; k++)
        rows += strips[k] != NULL;
    const int along = photo_strip->height < ALONG ? photo_strip->height : ALONG;
    const int h = SQ_FIT_STRIP_W;
    SqImage img;
    if (sq_image_alloc(&img, LABEL_W + along + PAD, PAD + rows * (h + GAP) - GAP + PAD, 3, SQ_SPACE_SRGB) != 0)
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    for (size_t i = 0; i < (size_t)img.width * img.height * 3; i++)
        img.px[i] = 1;
    static const float ink[3] = {0.13f, 0.13f, 0.13f}, grey[3] = {0.4f, 0.4f, 0.4f}, green[3] = {0.1f, 0.5f, 0.2f};
    SqError terr;
    int labelled = 1, y = PAD;
    paste_turned(&img, photo_strip, LABEL_W, y, along);
    labelled = sq_io_draw_text(&img, PAD, y + 18, 13, "photo", ink, &terr) == SQ_OK;
    if (labelled)
        sq_io_draw_text(&img, PAD, y + 34, 11, "the straightened body", grey, &terr);
    for (int k = 0; k < SQ_FIT_KINDS; k++) {
        if (!strips[k])
            continue;
        y += h + GAP;
        paste_turned(&img, strips[k], LABEL_W, y, along);
        if (!labelled)
            continue;
        char t[64];
        const float *c = k == champion ? green : ink;
        sq_io_draw_text(&img, PAD, y + 18, 13, sq_fit_kind_name(k), c, &terr);
        sq_io_draw_text(&img, PAD, y + 34, 11, gloss(k), grey, &terr);
        snprintf(t, sizeof t, "score %.3f%s", r->kind_best[k].score,
                 k == champion ? (r->kind_recoloured[k] ? ", best.json, recoloured" : ", best.json")
                 : r->kind_recoloured[k] ? ", recoloured" : "");
        sq_io_draw_text(&img, PAD, y + 50, 11, t, c, &terr);
    }
    char shown[4200];
    if (!labelled)
        fprintf(stderr, "squama: warning: %s goes unlabelled: %s\n", cli_staging_shown(path, shown, sizeof shown),
                terr.what);
    SqStatus st = sq_io_write_image(path, &img, NULL, err);
    sq_image_free(&img);
    return st;
}

SqStatus cli_fit_write_kinds(CliStaging *s, const SqPrepared *prep, double band_centre, const SqFitResult *r,
                             const SqImage *champion_strip, int size, const char *photo_name, SqError *err)
{
    char path[4200], file[64];
    /* the presets; a kind this fit has none of loses the one an earlier fit left */
    for (int k = 0; k < SQ_FIT_KINDS; k++) {
        const SqFitCandidate *c = &r->kind_best[k];
        snprintf(file, sizeof file, "kinds/%s.json", sq_fit_kind_name(k));
        if (!isfinite(c->score)) {
            SqStatus st = cli_staging_drop(s, file, err);
            if (st != SQ_OK)
                return st;
            continue;
        }
        char name[256];
        snprintf(name, sizeof name, "the best %s skin of the fit of %s", sq_fit_kind_name(k), photo_name);
        SqStatus st = cli_staging_path(s, file, path, sizeof path, err);
        if (st == SQ_OK)
            st = cli_fit_write_preset(path, c, name, err);
        if (st != SQ_OK)
            return st;
    }
    /* the picture: each kind's strip (the champion's is made already) */
    const int champion = sq_fit_kind_of(&r->best.params);
    SqImage own[SQ_FIT_KINDS] = {{0}};
    const SqImage *show[SQ_FIT_KINDS] = {0};
    SqGenOptions go = sq_gen_options_default(size);
    SqTextures tex = {0};
    SqError perr;
    SqStatus st = SQ_OK;
    for (int k = 0; k < SQ_FIT_KINDS && st == SQ_OK; k++) {
        const SqFitCandidate *c = &r->kind_best[k];
        if (!isfinite(c->score))
            continue;
        if (k == champion) {
            show[k] = champion_strip;
            continue;
        }
        st = sq_gen_render_into(&c->params, &go, &tex, &perr);
        if (st == SQ_OK)
            st = sq_fit_candidate_strip(&tex.basecolor, &tex.normal, &tex.roughness, &prep->light, c->view_scale,
                                        band_centre, prep->strip.height, &own[k], &perr);
        show[k] = &own[k];
    }
    sq_gen_textures_free(&tex);
    if (st == SQ_OK)
        st = cli_staging_path(s, "kinds.png", path, sizeof path, &perr);
    if (st == SQ_OK)
        st = kinds_picture(path, &prep->strip, show, r, &perr);
    if (st != SQ_OK) { /* not the picture of an earlier fit either */
        if (cli_staging_drop(s, "kinds.png", err) != SQ_OK) {
            for (int k = 0; k < SQ_FIT_KINDS; k++)
                sq_image_free(&own[k]);
            return err->status;
        }
        cli_staging_where(s, &perr);
        fprintf(stderr, "squama: warning: no kinds.png: %s (%s)\n", perr.what, perr.where);
    }
    for (int k = 0; k < SQ_FIT_KINDS; k++)
        sq_image_free(&own[k]);
    return SQ_OK;
}
