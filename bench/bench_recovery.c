/* The recovery benchmark's measuring tools (bench/recovery.py drives the first two):
 *
 *   bench_recovery truth BASE.json CATEGORY SEED OUT.json
 *       a ground-truth preset: BASE with the pattern type CATEGORY (or, for "layered",
 *       BASE's own base and layer types), every gene of that kind moved by up to +-0.2 of its suggested range (and the automaton mutated),
 *       all from SEED; drawn again (up to 20 times) while its pattern is invisible
 *       (sq_fit_pattern_visibility below 0.02)
 *   bench_recovery compare TRUTH.json VIEW_T FIT.json VIEW_F PHOTO MASK NORM1..NORM5
 *       how close a fitted preset is to the truth; distances are the fit's score (each
 *       objective over its NORM, summed), means over 4 seeds of the preset(s) rendered:
 *         palette_de00  earth mover's distance between the dominant colours (6-colour
 *                       palettes, CIEDE2000 ground distance) of truth and fit, in texture
 *                       space (the strip each shows at its view scale)
 *         tex_fit       texture space: the fit's distance to the truth
 *         tex_reseed    texture space: the truth's distance to itself under other seeds
 *                       (near 0 for patterns without randomness: stripes, bands, automata)
 *         photo_fit     the fit's distance to the photo
 *         photo_truth   the truth's distance to the photo
 *         ratio         photo_fit / photo_truth: 1 = the fit explains the photo as well as
 *                       the true preset does
 *   and prints them as one JSON object.
 *   bench_recovery features PHOTO MASK|-
 *       the photo's features as a fit's target sees them, and the best automaton and spot
 *       lattice read off its strip, as one JSON object ("-": the mask made as squama fit
 *       makes one)
 *   bench_recovery texfeatures PRESET VIEW SIZE [PHOTO MASK|-]
 *       the same (without the readings) for the preset's candidate strip at view scale VIEW
 *       under the key light, its maps SIZE texels square; with a photo, under the photo's
 *       light and blur, as a fit scores it against that photo
 *   bench_recovery selfdist PRESET VIEW PHOTO MASK|- SEED0
 *       the preset's distance to itself: its 4 instances under the pattern seeds SEED0+1
 *       to SEED0+4, at view scale VIEW, each lit and blurred as the photo; the mean of the
 *       fit's objectives between every pair, as a JSON array in sq_fit_objective_name's
 *       order (bench/pick_replay.py --self-distance)
 *   (the kind-prior experiment's inputs: docs/recovery.md, session 35) */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "squama/fitness.h"
#include "squama/io.h"
#include "squama/generator.h"
#include "squama/preset.h"
#include "squama/search.h"

enum { SIZE = 256, ROWS = 256, RESEEDS = 4 };

static int fail(const SqError *e)
{
    fprintf(stderr, "bench_recovery: %s (%s)\n", e->what, e->where);
    return 1;
}

static double uniform(uint64_t *s)
{
    *s += 0x9e3779b97f4a7c15ull;
    uint64_t z = *s;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static int truth(const char *base, const char *category, long seed, const char *out)
{
    SqParams p;
    SqError e;
    if (sq_preset_load(base, &p, NULL, &e) != SQ_OK)
        return fail(&e);
    int cat = -1;
    for (int c = 0; c < SQ_FIT_KINDS; c++)
        if (strcmp(sq_fit_kind_name(c), category) == 0)
            cat = c;
    SqGenome g;
    if (cat < 0 || (cat == SQ_FIT_LAYERED) != (sq_fit_kind_of(&p) == SQ_FIT_LAYERED)) {
        fprintf(stderr, "bench_recovery: unknown kind '%s', or a layered kind without a layered base\n", category);
        return 1;
    }
    if ((cat == SQ_FIT_LAYERED ? sq_genome_of(&g, &p, &e) : sq_genome_init(&g, cat, &e)) != SQ_OK)
        return fail(&e);
    uint64_t r = 0x5eed0000u + (uint64_t)seed;
    double x0[SQ_GENOME_MAX], x[SQ_GENOME_MAX];
    sq_genome_encode(&g, &p, x0);
    const SqParams base_p = p;
    /* a truth whose pattern nobody can see would be a plain skin: drawn again */
    for (int tries = 0; tries < 20; tries++) {
        p = base_p;
        for (int i = 0; i < g.n; i++)
            x[i] = x0[i] + 0.4 * (uniform(&r) - 0.5);
        sq_genome_decode(&g, x, &p);
        if (g.has_ca)
            for (int k = 0; k < 2; k++)
                sq_gp_ca_point_mutate(&r, &p.CA_Descriptor);
        p.Seed = (int)(seed % 100000);
        double dom[3];
        if (cat == SQ_PATTERN_NONE || sq_fit_pattern_visibility(&p, SIZE, 0.5, dom, NULL) >= 0.02)
            break;
    }
    SqPresetInfo info = {0};
    snprintf(info.name, sizeof info.name, "recovery truth %s %ld", category, seed);
    snprintf(info.notes, sizeof info.notes, "%s, genes moved by up to 0.2 (bench_recovery)", base);
    char *json = sq_preset_to_json(&p, &info, &e);
    if (!json)
        return fail(&e);
    FILE *f = fopen(out, "w");
    if (!f || fputs(json, f) < 0 || fclose(f) != 0) {
        fprintf(stderr, "bench_recovery: cannot write %s\n", out);
        free(json);
        return 1;
    }
    free(json);
    return 0;
}

/* A preset's features at a view scale, its maps size texels square: under the key light
 * (texture space; key NULL: not wanted), and when photo is not NULL under the photo's
 * light too (as the fit sees it against the photo). */
static int features(const SqParams *p, int seed, int size, double view, SqTextures *maps, SqFeatures *key,
                    const SqFeatures *photo, SqFeatures *lit)
{
    SqParams q = *p;
    q.Seed = seed;
    SqGenOptions go = sq_gen_options_default(size);
    SqError e;
    if (sq_gen_render_into(&q, &go, maps, &e) != SQ_OK)
        return fail(&e);
    for (int k = key ? 0 : 1; k < (photo ? 2 : 1); k++) {
        SqImage strip = {0};
        if (sq_fit_candidate_strip(&maps->basecolor, &maps->normal, &maps->roughness, k ? &photo->light : NULL, view,
                                   0.5, ROWS, &strip, &e) != SQ_OK ||
            sq_fit_features_blurred(&strip, NULL, k ? photo->blur : 0, k ? lit : key, &e) != SQ_OK) {
            sq_image_free(&strip);
            return fail(&e);
        }
        sq_image_free(&strip);
    }
    return 0;
}

static double distance(const SqFeatures *a, const SqFeatures *b, const double *norm)
{
    double obj[SQ_OBJ_COUNT], d = 0;
    sq_fit_objectives(a, b, obj);
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        d += obj[k] / norm[k];
    return d;
}

/* The photo's features, prepared with its mask as squama fit does ("-": no mask, made as
 * squama fit makes one). With prep not NULL the preparation is kept there (the caller
 * frees it with sq_fit_prepared_free). */
static int photo_features(const char *photo, const char *mask, SqFeatures *out, SqPrepared *prep)
{
    SqImage img, m = {0}, bin = {0};
    SqError e;
    const int automatic = strcmp(mask, "-") == 0;
    if (sq_io_read_image(photo, NULL, &img, NULL, &e) != SQ_OK)
        return fail(&e);
    if (!automatic && sq_io_read_image(mask, NULL, &m, NULL, &e) != SQ_OK) {
        sq_image_free(&img);
        return fail(&e);
    }
    int rc = 0, prepared = 0;
    if (!automatic) {
        rc = sq_image_alloc(&bin, m.width, m.height, 1, SQ_SPACE_DATA) != 0;
        for (size_t i = 0; !rc && i < (size_t)m.width * m.height; i++)
            bin.px[i] = m.px[4 * i] >= 0.5f;
    }
    SqPrepOptions po = sq_fit_prep_options_default();
    SqPrepared own, *pp = prep ? prep : &own;
    if (!rc) {
        prepared = sq_fit_prepare(&img, automatic ? NULL : &bin, &po, pp, &e) == SQ_OK;
        rc = !prepared || sq_fit_photo_target(pp, out, &e) != SQ_OK;
        if (rc)
            fail(&e);
    }
    if (prepared && (rc || !prep))
        sq_fit_prepared_free(pp);
    sq_image_free(&img);
    sq_image_free(&m);
    sq_image_free(&bin);
    return rc;
}

static int compare(char **argv)
{
    SqParams t, f;
    SqError e;
    if (sq_preset_load(argv[0], &t, NULL, &e) != SQ_OK || sq_preset_load(argv[2], &f, NULL, &e) != SQ_OK)
        return fail(&e);
    double vt = atof(argv[1]), vf = atof(argv[3]), norm[SQ_OBJ_COUNT];
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        norm[k] = atof(argv[6 + k]);
    SqTextures maps = {0};
    SqFeatures ph, ft, fx, fy, px, py;
    double tfit = 0, tre = 0, pfit = 0, ptru = 0, pal = 0, obj[SQ_OBJ_COUNT];
    if (photo_features(argv[4], argv[5], &ph, NULL) || features(&t, t.Seed, SIZE, vt, &maps, &ft, NULL, NULL))
        return 1;
    for (int s = 1; s <= RESEEDS; s++) { /* texture space under the key light, the photo under its own */
        if (features(&f, 1000 + s, SIZE, vf, &maps, &fx, &ph, &px) ||
            features(&t, 2000 + s, SIZE, vt, &maps, &fy, &ph, &py))
            return 1;
        tfit += distance(&ft, &fx, norm) / RESEEDS;
        tre += distance(&ft, &fy, norm) / RESEEDS;
        pfit += distance(&ph, &px, norm) / RESEEDS;
        ptru += distance(&ph, &py, norm) / RESEEDS;
        sq_fit_objectives(&ft, &fx, obj);
        pal += obj[SQ_OBJ_PALETTE] / RESEEDS;
    }
    sq_gen_textures_free(&maps);
    printf("{\"palette_de00\": %.4f, \"tex_fit\": %.4f, \"tex_reseed\": %.4f, \"photo_fit\": %.4f, "
           "\"photo_truth\": %.4f, \"ratio\": %.4f}\n",
           pal, tfit, tre, pfit, ptru, ptru > 0 ? pfit / ptru : 0.0);
    return 0;
}

static void put_floats(const char *name, const float *v, int n)
{
    printf("\"%s\": [", name);
    for (int i = 0; i < n; i++)
        printf("%s%.6g", i ? ", " : "", v[i]);
    printf("], ");
}

/* Features as one JSON object: the target's (wavelet, spectra, profile, palette) and, with
 * readings, the best automaton's and spot lattice's read off the strip (the kind-prior
 * experiment's inputs, docs/recovery.md, session 35). */
static void print_features(const SqFeatures *f, const SqImage *strip, const SqImage *valid, double body_width,
                           int readings)
{
    SqCaReading ca[4];
    SqSpotsReading sp[4];
    const int nca = readings ? sq_fit_read_automata(strip, valid, 0.5, 1, ca, 4) : 0;
    const int nsp = readings ? sq_fit_read_spots(strip, valid, sp, 4) : 0;
    printf("{");
    put_floats("wavelet", &f->wavelet[0][0], SQ_FIT_LEVELS * 3);
    put_floats("along", f->along, SQ_FIT_BANDS);
    put_floats("across", f->across, SQ_FIT_BANDS);
    put_floats("profile", f->profile, SQ_FIT_PROFILE);
    put_floats("palette", &f->palette[0][0], SQ_FIT_PALETTE * 3);
    put_floats("palette_w", f->palette_w, SQ_FIT_PALETTE);
    printf("\"along_power\": %.6g, \"across_power\": %.6g, \"blur\": %.6g, \"body_width\": %.6g, "
           "\"ca_corr\": %.6g, \"ca_view\": %.6g, \"spots_score\": %.6g, \"spots_skew\": %.6g, "
           "\"spots_across\": %d}\n",
           f->along_power, f->across_power, f->blur, body_width, nca ? ca[0].corr : 0, nca ? ca[0].view_scale : 0,
           nsp ? sp[0].score : 0, nsp ? sp[0].skew : 0, nsp ? sp[0].across : 0);
}

static int photo_features_json(const char *photo, const char *mask)
{
    SqPrepared prep;
    SqFeatures f;
    if (photo_features(photo, mask, &f, &prep))
        return 1;
    print_features(&f, &prep.strip, &prep.valid, prep.body_width, 1);
    sq_fit_prepared_free(&prep);
    return 0;
}

/* The same, without the readings, for a preset's candidate strip at a view scale under the
 * key light, its maps SIZE texels square, its reaction-diffusion grid the fit's (48 cells);
 * with a photo (and its mask), under the photo's light and blur, as the fit sees it. */
static int tex_features_json(const char *preset, double view, int size, const char *photo, const char *mask)
{
    if (size < 16 || size > 4096 || !(view > 0)) {
        fprintf(stderr, "bench_recovery: texfeatures wants a view scale over 0 and a size of 16 to 4096\n");
        return 1;
    }
    SqParams p;
    SqError e;
    if (sq_preset_load(preset, &p, NULL, &e) != SQ_OK)
        return fail(&e);
    p.RD_Cells = 48; /* as the fit's candidates are (search/fit.c FIT_RD_CELLS) */
    SqTextures maps = {0};
    SqFeatures f, ph, lit;
    if (photo && photo_features(photo, mask, &ph, NULL))
        return 1;
    const int rc = features(&p, p.Seed, size, view, &maps, &f, photo ? &ph : NULL, &lit);
    if (!rc)
        print_features(photo ? &lit : &f, NULL, NULL, 0, 0);
    sq_gen_textures_free(&maps);
    return rc;
}

/* The mean objectives between the preset's RESEEDS instances (seeds seed0 + 1 on), each
 * lit and blurred as the photo. */
static int self_distance(const char *preset, double view, const char *photo, const char *mask, int seed0)
{
    if (!(view > 0) || !isfinite(view)) {
        fprintf(stderr, "bench_recovery: selfdist wants a view scale over 0\n");
        return 1;
    }
    SqParams p;
    SqError e;
    if (sq_preset_load(preset, &p, NULL, &e) != SQ_OK)
        return fail(&e);
    SqFeatures ph, lit[RESEEDS];
    SqTextures maps = {0};
    if (photo_features(photo, mask, &ph, NULL))
        return 1;
    for (int s = 0; s < RESEEDS; s++)
        if (features(&p, seed0 + 1 + s, SIZE, view, &maps, NULL, &ph, &lit[s])) {
            sq_gen_textures_free(&maps);
            return 1;
        }
    sq_gen_textures_free(&maps);
    double mean[SQ_OBJ_COUNT] = {0}, obj[SQ_OBJ_COUNT];
    int pairs = 0;
    for (int a = 0; a < RESEEDS; a++)
        for (int b = a + 1; b < RESEEDS; b++, pairs++) {
            sq_fit_objectives(&lit[a], &lit[b], obj);
            for (int k = 0; k < SQ_OBJ_COUNT; k++)
                mean[k] += obj[k];
        }
    printf("[");
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        printf("%s%.6g", k ? ", " : "", mean[k] / pairs);
    printf("]\n");
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 6 && strcmp(argv[1], "truth") == 0)
        return truth(argv[2], argv[3], atol(argv[4]), argv[5]);
    if (argc == 8 + SQ_OBJ_COUNT && strcmp(argv[1], "compare") == 0)
        return compare(argv + 2);
    if (argc == 4 && strcmp(argv[1], "features") == 0)
        return photo_features_json(argv[2], argv[3]);
    if ((argc == 5 || argc == 7) && strcmp(argv[1], "texfeatures") == 0)
        return tex_features_json(argv[2], atof(argv[3]), atoi(argv[4]), argc == 7 ? argv[5] : NULL,
                                 argc == 7 ? argv[6] : NULL);
    if (argc == 7 && strcmp(argv[1], "selfdist") == 0)
        return self_distance(argv[2], atof(argv[3]), argv[4], argv[5], atoi(argv[6]));
    fprintf(stderr, "usage: bench_recovery truth BASE.json CATEGORY SEED OUT.json\n"
                    "       bench_recovery compare TRUTH.json VIEW_T FIT.json VIEW_F PHOTO MASK NORM...\n"
                    "       (one NORM per objective, in the order of sq_fit_objective_name)\n"
                    "       bench_recovery features PHOTO MASK|-\n"
                    "       bench_recovery texfeatures PRESET VIEW SIZE [PHOTO MASK|-]\n"
                    "       bench_recovery selfdist PRESET VIEW PHOTO MASK|- SEED0\n");
    return 2;
}
