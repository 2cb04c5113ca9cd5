/* Seeding artists: diverse, plausible presets of a category, or variations around a preset,
 * chosen by how different the fit would find them. See search.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "rng.h"
#include "search_internal.h"
#include "squama/search.h"

enum {
    STRIP_ROWS = 256,  /* the strip's length, as the fit's */
    MEDOID_SAMPLE = 32 /* the first pick is the most typical against this many */
};

/* Candidates drawn when too few are plausible: at most this many times the pool. */
enum { DRAW_ROUNDS = 8 };

/* Each objective's typical value between two random presets: the median over 600 random
 * pairs of sq_seed_category's plausible candidates of all six categories (64 of each, 128
 * pixels, seed 1), measured before the sparse genes (search/draw.c) were drawn at their
 * default half the time: a scale, not a calibration, and close enough for one. The
 * distance divides by these, so that no objective drowns the others (the palette's
 * CIEDE2000 units would). */
static const double TYPICAL[SQ_OBJ_COUNT] = {21.5, 0.51, 0.30, 0.54, 0.49};

/* A pattern counts when it covers this share of the skin or more, and leaves this much or
 * more to the background; and when its most distinct colour differs from the background
 * by at least this many CIEDE2000 units (below about 10 a pattern reads as a stain). */
static const double COVERAGE_MIN = 0.05, COVERAGE_MAX = 0.80, CONTRAST_MIN = 20;

SqSeedOptions sq_seed_options_default(void)
{
    SqSeedOptions o = {0};
    o.n = 12;
    o.seed = 1;
    o.size = 128;
    o.distance = 0.1;
    return o;
}

void sq_seed_result_free(SqSeedResult *r)
{
    if (!r)
        return;
    free(r->picks);
    free(r->pool);
    r->picks = r->pool = NULL;
    r->n = r->npool = 0;
}

double sq_seed_objective_distance(const double *obj)
{
    double s = 0;
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        s += obj[k] / TYPICAL[k];
    return s / SQ_OBJ_COUNT;
}

double sq_seed_distance(const SqFeatures *a, const SqFeatures *b)
{
    double ab[SQ_OBJ_COUNT], ba[SQ_OBJ_COUNT];
    sq_fit_objectives(a, b, ab);
    sq_fit_objectives(b, a, ba);
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        ab[k] = 0.5 * (ab[k] + ba[k]);
    return sq_seed_objective_distance(ab);
}

/* ---- colours: palettes of snake colours ---- */

/* A family of colours: hue in degrees, saturation and value (HSV of the gamma-space
 * colour), each a range. */
typedef struct Family {
    float h0, h1, s0, s1, v0, v1;
} Family;

enum { BLACK, DARK_BROWN, BROWN, TAN, OLIVE, GREY, CREAM, RED, ORANGE, YELLOW, GREEN, NFAMILIES };

static const Family families[NFAMILIES] = {
    [BLACK] = {0, 40, 0.00f, 0.35f, 0.04f, 0.13f},      [DARK_BROWN] = {10, 32, 0.45f, 0.75f, 0.15f, 0.30f},
    [BROWN] = {15, 36, 0.40f, 0.70f, 0.32f, 0.58f},     [TAN] = {25, 42, 0.25f, 0.50f, 0.55f, 0.80f},
    [OLIVE] = {45, 80, 0.30f, 0.60f, 0.25f, 0.52f},     [GREY] = {20, 60, 0.00f, 0.12f, 0.30f, 0.70f},
    [CREAM] = {36, 55, 0.10f, 0.32f, 0.78f, 0.95f},     [RED] = {0, 12, 0.65f, 0.90f, 0.55f, 0.85f},
    [ORANGE] = {12, 28, 0.60f, 0.90f, 0.65f, 0.92f},    [YELLOW] = {42, 56, 0.55f, 0.90f, 0.72f, 0.95f},
    [GREEN] = {80, 140, 0.40f, 0.75f, 0.30f, 0.62f},
};

/* A colour scheme: the background from one list, the pattern's main colour from another,
 * its other colours (bands, rims, cores) from a third. -1 ends a list. */
typedef struct Scheme {
    double weight;
    int bg[6], main[6], accent[6];
} Scheme;

static const Scheme schemes[] = {
    /* dark markings on an earth colour: vipers, most colubrids */
    {0.32, {BROWN, TAN, OLIVE, GREY, -1}, {BLACK, DARK_BROWN, -1}, {DARK_BROWN, CREAM, BROWN, BLACK, -1}},
    /* pale markings on a dark skin: kingsnakes, garter snakes */
    {0.16, {BLACK, DARK_BROWN, OLIVE, -1}, {CREAM, YELLOW, TAN, ORANGE, -1}, {CREAM, YELLOW, BLACK, -1}},
    /* warning colours: coral snakes and their mimics */
    {0.12, {RED, ORANGE, -1}, {BLACK, -1}, {YELLOW, CREAM, BLACK, -1}},
    /* a bright skin with dark markings */
    {0.10, {YELLOW, GREEN, CREAM, -1}, {BLACK, DARK_BROWN, OLIVE, -1}, {DARK_BROWN, BLACK, GREEN, -1}},
    /* greys */
    {0.10, {GREY, CREAM, -1}, {BLACK, DARK_BROWN, -1}, {GREY, BLACK, CREAM, -1}},
    /* red or orange blotches on a pale or earth skin: corn snakes */
    {0.10, {TAN, GREY, CREAM, BROWN, -1}, {RED, ORANGE, -1}, {BLACK, DARK_BROWN, CREAM, -1}},
    /* one colour, lighter and darker */
    {0.10, {BROWN, OLIVE, GREY, TAN, -1}, {-1}, {-1}},
};
enum { NSCHEMES = sizeof schemes / sizeof schemes[0] };

static void hsv_to_rgb(double h, double s, double v, double *rgb)
{
    h = fmod(h, 360.0);
    if (h < 0)
        h += 360.0;
    double c = v * s, x = c * (1 - fabs(fmod(h / 60.0, 2.0) - 1)), m = v - c, r = 0, g = 0, b = 0;
    switch ((int)(h / 60.0)) {
    case 0: r = c; g = x; break;
    case 1: r = x; g = c; break;
    case 2: g = c; b = x; break;
    case 3: g = x; b = c; break;
    case 4: r = x; b = c; break;
    default: r = c; b = x; break;
    }
    rgb[0] = r + m;
    rgb[1] = g + m;
    rgb[2] = b + m;
}

static void family_colour(SqRng *r, int fam, double *out)
{
    const Family *f = &families[fam];
    hsv_to_rgb(sq__rng_between(r, f->h0, f->h1), sq__rng_between(r, f->s0, f->s1),
               sq__rng_between(r, f->v0, f->v1), out);
    out[3] = 1;
}

static int pick_from(SqRng *r, const int *list)
{
    int n = 0;
    while (n < 6 && list[n] >= 0)
        n++;
    return list[sq__rng_int(r, n)];
}

/* A shade of the same colour: value times k, a little more saturated when darker. */
static void shade(const double *src, double k, double *out)
{
    for (int c = 0; c < 3; c++)
        out[c] = fmin(fmax(src[c] * k, 0), 1);
    out[3] = 1;
}

/* Background, pattern and outline colours from one scheme. */
static void colour_scheme(SqRng *r, SqParams *p, int category)
{
    double total = 0;
    for (int i = 0; i < NSCHEMES; i++)
        total += schemes[i].weight;
    double u = sq__rng_uniform(r) * total;
    int k = 0;
    while (k < NSCHEMES - 1 && u >= schemes[k].weight) {
        u -= schemes[k].weight;
        k++;
    }
    const Scheme *s = &schemes[k];
    family_colour(r, pick_from(r, s->bg), p->Background_Color);
    for (int l = 0; l <= p->Pattern_Layers.count; l++) { /* the base pattern, then a layer's: */
        SqPatternSpec *spec = l ? &p->Pattern_Layers.layer[l - 1].spec : &p->pattern;
        double *list[8]; /* the main colour, then accents */
        int n = sq__pattern_colours(spec, l ? spec->Pattern_Type : category, list);
        for (int i = 0; i < n; i++) {
            const int *from = i == 0 && l == 0 ? s->main : s->accent;
            if (from[0] >= 0)
                family_colour(r, pick_from(r, from), list[i]);
            else /* tonal: a darker or, now and then, lighter shade of the skin */
                shade(p->Background_Color,
                      sq__rng_uniform(r) < 0.75 ? sq__rng_between(r, 0.35, 0.6) : sq__rng_between(r, 1.35, 1.7),
                      list[i]);
        }
    }
    family_colour(r, sq__rng_uniform(r) < 0.7 ? BLACK : DARK_BROWN, p->Outline_Color);
}

/* This share of the smooth-scaled skins show the skin between their scales
 * (Scales_GapColor): a dark shade of the ground, now and then a pale one, over rounder
 * scales (ScaleShape_Blur) so that it reads as outlines. Not on keeled scales, where the
 * gap colour would follow the grooves beside the keels as scratches, nor on a near-black
 * ground, where no shade of it would show. */
static const double GAP_SHARE = 0.5;

static void scale_gaps(SqRng *r, SqParams *p)
{
    if (p->ScaleShape_IsKeeled || sq__rng_uniform(r) >= GAP_SHARE)
        return;
    const double *bg = p->Background_Color;
    if (fmax(bg[0], fmax(bg[1], bg[2])) < 0.2)
        return;
    shade(bg, sq__rng_uniform(r) < 0.8 ? sq__rng_between(r, 0.15, 0.45) : sq__rng_between(r, 1.3, 1.6),
          p->Scales_GapColor);
    p->Scales_GapExtent = sq__rng_between(r, 0.35, 0.6);
    p->ScaleShape_Blur = sq__rng_between(r, 5, 12);
}

/* ---- drawing and judging candidates ---- */

/* A random candidate of the genome (sq__genome_draw: genes uniform over the narrowed
 * ranges, the sparse ones at their default half the time), then colours from a scheme,
 * the skin between the scales now and then, rings, an automaton, and the
 * reaction-diffusion grid the fit uses. */
static void draw_candidate(SqRng *r, const SqGenome *g, SqParams *p)
{
    sq__genome_draw(r, g, p);
    colour_scheme(r, p, g->category);
    scale_gaps(r, p);
    sq__draw_bands(r, g, p);
    if (g->has_ca) {
        uint64_t s = sq__rng_next(r);
        sq_gp_ca_random(&s, &p->CA_Descriptor);
    }
    if (g->category == SQ_PATTERN_COMPLEX) {
        p->RD_Cells = 48;
        p->RD_Color2[3] = sq__rng_uniform(r) < 0.5;
        p->RD_Color3[3] = sq__rng_uniform(r) < 0.5;
    }
    p->Seed = (int)(sq__rng_next(r) & 0x7fffffff);
}

/* What a pattern changed: compared with the same skin rendered without a pattern (same
 * seed, hence the same colour noise), the share of pixels more than DIFF_MIN CIELAB units
 * away (coverage), and their mean CIEDE2000 from the plain skin (contrast); every other
 * pixel of every other row counted. */
static const float DIFF_MIN = 10;

static void pattern_change(const SqImage *with, const SqImage *plain, double *coverage, double *contrast)
{
    long changed = 0, all = 0;
    double sum = 0;
    for (int y = 0; y < with->height; y += 2)
        for (int x = 0; x < with->width; x += 2) {
            float a[3], b[3];
            sq_fit_srgb_to_lab(with->px + ((size_t)y * with->width + x) * with->channels, a);
            sq_fit_srgb_to_lab(plain->px + ((size_t)y * plain->width + x) * plain->channels, b);
            const float d = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
            if (d > DIFF_MIN * DIFF_MIN) {
                const double la[3] = {a[0], a[1], a[2]}, lb[3] = {b[0], b[1], b[2]};
                sum += sq_fit_ciede2000(la, lb);
                changed++;
            }
            all++;
        }
    *coverage = all ? (double)changed / (double)all : 0;
    *contrast = changed ? sum / (double)changed : 0;
}

/* A variation of an origin that fails plausible() itself (rings over most of the skin, a
 * faint pattern) is held to the origin's own measures, halfway to the extremes. */
static int plausible_near(const SqSeedCandidate *c, const SqSeedCandidate *origin)
{
    if (c->params.Pattern_Type == SQ_PATTERN_NONE)
        return 1;
    const double lo = fmin(COVERAGE_MIN, 0.5 * origin->coverage);
    const double hi = fmax(COVERAGE_MAX, origin->coverage + 0.5 * (1 - origin->coverage));
    return c->coverage >= lo && c->coverage <= fmin(hi, 0.99) && c->contrast >= fmin(CONTRAST_MIN, 0.5 * origin->contrast);
}

/* A layered preset's layer must show over its base as a pattern does over the skin,
 * and leave some of the base to show. */
static int plausible(const SqSeedCandidate *c)
{
    if (c->params.Pattern_Type == SQ_PATTERN_NONE)
        return 1;
    return c->coverage >= COVERAGE_MIN && c->coverage <= COVERAGE_MAX && c->contrast >= CONTRAST_MIN &&
           (c->params.Pattern_Layers.count == 0 ||
            (c->layer_coverage >= COVERAGE_MIN && c->layer_coverage <= COVERAGE_MAX &&
             c->layer_contrast >= CONTRAST_MIN));
}

/* Renders a candidate and takes its features, its coverage (a second render, without the
 * pattern, into plain; NULL: not measured) and its contrast; 0, or -1 when it cannot be
 * rendered or its features are not finite. */
static int evaluate(SqSeedCandidate *c, int size, int threads, SqTextures *maps, SqTextures *plain, SqError *err)
{
    SqGenOptions go = sq_gen_options_default(size);
    go.threads = threads;
    SqImage strip = {0};
    if (sq_gen_render_into(&c->params, &go, maps, err) != SQ_OK ||
        sq_fit_candidate_strip(&maps->basecolor, &maps->normal, &maps->roughness, NULL, 1.0, 0.5, STRIP_ROWS, &strip,
                               err) != SQ_OK ||
        sq_fit_features(&strip, NULL, &c->features, err) != SQ_OK) {
        sq_image_free(&strip);
        return -1;
    }
    sq_image_free(&strip);
    c->contrast = c->coverage = c->layer_coverage = c->layer_contrast = 0;
    if (plain && c->params.Pattern_Type != SQ_PATTERN_NONE) {
        SqParams *q = malloc(sizeof *q);
        if (!q) {
            sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
            return -1;
        }
        *q = c->params;
        q->Pattern_Type = SQ_PATTERN_NONE;
        q->Pattern_Layers.count = 0;
        q->Has_Outline = 0;
        SqStatus st = sq_gen_render_into(q, &go, plain, err);
        if (st == SQ_OK)
            pattern_change(&maps->basecolor, &plain->basecolor, &c->coverage, &c->contrast);
        if (st == SQ_OK && c->params.Pattern_Layers.count > 0) { /* the base alone */
            *q = c->params;
            q->Pattern_Layers.count = 0;
            if ((st = sq_gen_render_into(q, &go, plain, err)) == SQ_OK)
                pattern_change(&maps->basecolor, &plain->basecolor, &c->layer_coverage, &c->layer_contrast);
        }
        free(q);
        if (st != SQ_OK)
            return -1;
    }
    SqFeatures self = c->features;
    double d = sq_seed_distance(&c->features, &self);
    if (!isfinite(d)) {
        sq_error_set(err, SQ_ERR_INVALID, "seed", "the candidate's features are not finite");
        return -1;
    }
    c->nearest = INFINITY;
    c->nearest_index = -1;
    c->to_origin = NAN;
    return 0;
}

SqStatus sq_seed_features(const SqParams *p, int size, SqTextures *maps, SqFeatures *f, SqError *err)
{
    SqTextures own = {0};
    SqSeedCandidate *c = malloc(sizeof *c);
    if (!c)
        return sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
    c->params = *p;
    SqStatus st = SQ_OK;
    if (evaluate(c, size, 0, maps ? maps : &own, NULL, err) != 0)
        st = err && err->status != SQ_OK ? err->status : SQ_ERR_INVALID;
    else
        *f = c->features;
    sq_gen_textures_free(&own);
    free(c);
    return st;
}

/* ---- the run: draw, render, select ---- */

typedef struct Run {
    const SqSeedOptions *o;
    int threads;
    SqTextures *maps;  /* one per thread */
    SqTextures *plain; /* one per thread: the renders without a pattern */
} Run;

static void report(const Run *r, const char *stage, int done, int total)
{
    if (r->o->progress) {
        SqSeedProgress p = {.stage = stage, .done = done, .total = total};
        r->o->progress(&p, r->o->ctx);
    }
}

/* Renders c[0..n) in parallel, a chunk at a time (progress between chunks); ok[i] is 1 for
 * those rendered. */
static void render_all(Run *r, SqSeedCandidate *c, int n, int *ok, int done0, int total)
{
    const int chunk = 8 * r->threads;
    for (int s = 0; s < n; s += chunk) {
        int e = s + chunk < n ? s + chunk : n;
#pragma omp parallel for schedule(dynamic, 1) num_threads(r->threads)
        for (int i = s; i < e; i++)
            ok[i] = evaluate(&c[i], r->o->size, 1, &r->maps[omp_get_thread_num()], &r->plain[omp_get_thread_num()],
                             NULL) == 0;
        report(r, "render", done0 + e, total);
    }
}

/* Farthest-point sampling: picks n of the m candidates into pick[], each the one farthest
 * (in feature distance) from those picked before; the first is `anchor` when given (not
 * among the picks: sq_seed_near's origin), else the pool's most typical candidate (least
 * total distance to a sample of it). Ties go to the lower index. */
static SqStatus farthest_points(Run *r, const SqSeedCandidate *c, int m, const SqFeatures *anchor, int n,
                                int *pick, SqError *err)
{
    double *mind = malloc(sizeof(double) * (size_t)m);
    if (!mind)
        return sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
    int k = 0;
    if (anchor) {
#pragma omp parallel for schedule(static) num_threads(r->threads)
        for (int i = 0; i < m; i++)
            mind[i] = sq_seed_distance(anchor, &c[i].features);
    } else {
        const int ns = m < MEDOID_SAMPLE ? m : MEDOID_SAMPLE;
#pragma omp parallel for schedule(static) num_threads(r->threads)
        for (int i = 0; i < m; i++) {
            double s = 0;
            for (int j = 0; j < ns; j++)
                s += sq_seed_distance(&c[i].features, &c[j * (m / ns)].features);
            mind[i] = s;
        }
        int first = 0;
        for (int i = 1; i < m; i++)
            if (mind[i] < mind[first])
                first = i;
        pick[k++] = first;
#pragma omp parallel for schedule(static) num_threads(r->threads)
        for (int i = 0; i < m; i++)
            mind[i] = sq_seed_distance(&c[first].features, &c[i].features);
        mind[first] = -1;
    }
    while (k < n) {
        int best = -1;
        for (int i = 0; i < m; i++)
            if (mind[i] >= 0 && (best < 0 || mind[i] > mind[best]))
                best = i;
        pick[k++] = best;
        const SqFeatures *f = &c[best].features;
#pragma omp parallel for schedule(static) num_threads(r->threads)
        for (int i = 0; i < m; i++)
            if (mind[i] >= 0)
                mind[i] = fmin(mind[i], sq_seed_distance(f, &c[i].features));
        mind[best] = -1;
        report(r, "select", k, n);
    }
    free(mind);
    return SQ_OK;
}

/* The picks, each with its nearest other pick. */
static SqStatus gather(SqSeedResult *out, const SqSeedCandidate *pool, const int *pick, int n, SqError *err)
{
    out->picks = malloc(sizeof *out->picks * (size_t)n);
    if (!out->picks)
        return sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
    out->n = n;
    for (int i = 0; i < n; i++)
        out->picks[i] = pool[pick[i]];
    out->min_distance = INFINITY;
    for (int i = 0; i < n; i++) {
        SqSeedCandidate *a = &out->picks[i];
        a->nearest = INFINITY;
        a->nearest_index = -1;
        for (int j = 0; j < n; j++) {
            if (j == i)
                continue;
            double d = sq_seed_distance(&a->features, &out->picks[j].features);
            if (d < a->nearest) {
                a->nearest = d;
                a->nearest_index = j;
            }
        }
        out->min_distance = fmin(out->min_distance, a->nearest);
    }
    return SQ_OK;
}

static SqStatus check_options(const SqSeedOptions *o, int near, SqError *err)
{
    if (o->n < 1 || o->n > SQ_SEED_MAX)
        return sq_error_set(err, SQ_ERR_INVALID, "seed", "n must be 1 to %d, got %d", SQ_SEED_MAX, o->n);
    if (o->pool < 0 || o->pool > 64)
        return sq_error_set(err, SQ_ERR_INVALID, "seed", "pool must be 0 (the default) to 64 per preset, got %d",
                            o->pool);
    if (o->size < 32 || o->size > 1024)
        return sq_error_set(err, SQ_ERR_INVALID, "seed", "the render size must be 32 to 1024, got %d", o->size);
    if (near && !(o->distance > 0 && o->distance <= 1))
        return sq_error_set(err, SQ_ERR_INVALID, "seed", "the distance must be in (0, 1], got %g", o->distance);
    return SQ_OK;
}

static SqStatus run_begin(Run *r, const SqSeedOptions *o, SqSeedResult *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    r->o = o;
    r->threads = o->threads > 0 ? o->threads : omp_get_max_threads();
    r->maps = calloc((size_t)r->threads, sizeof *r->maps);
    r->plain = calloc((size_t)r->threads, sizeof *r->plain);
    return r->maps && r->plain ? SQ_OK : sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
}

static void run_end(Run *r)
{
    for (int i = 0; i < r->threads; i++) {
        if (r->maps)
            sq_gen_textures_free(&r->maps[i]);
        if (r->plain)
            sq_gen_textures_free(&r->plain[i]);
    }
    free(r->maps);
    free(r->plain);
}

/* How far a colour moves in a variation, per unit of step: CIELAB lightness and a*, b*
 * (a gene step of 0.1 moves a colour about 6 CIEDE2000 units: the same skin, a little
 * lighter or warmer). Colours move together rather than channel by channel: independent
 * steps of r, g and b turn a brown purple or green at once. */
static const double COLOUR_STEP_L = 40, COLOUR_STEP_AB = 25;

static void vary_colour(SqRng *r, double d, double *rgba)
{
    float rgb[3] = {(float)rgba[0], (float)rgba[1], (float)rgba[2]}, lab[3];
    sq_fit_srgb_to_lab(rgb, lab);
    lab[0] += (float)(d * COLOUR_STEP_L * sq__rng_normal(r));
    lab[1] += (float)(d * COLOUR_STEP_AB * sq__rng_normal(r));
    lab[2] += (float)(d * COLOUR_STEP_AB * sq__rng_normal(r));
    sq_fit_lab_to_srgb(lab, rgb);
    for (int c = 0; c < 3; c++)
        rgba[c] = fmin(fmax(rgb[c], 0), 1);
}

/* A band's begin and end (transversal) move as its centre and its length, so that a band
 * stays a band rather than wrapping over the whole tile when its end passes its begin: the
 * centre by a normal step of d/2 of the tile, the length by a factor exp(2 d N(0,1)), within
 * 1% to 90% of the tile. A band left out (begin = end) stays out. */
static void vary_band(SqRng *r, double d, double *be)
{
    if (be[0] == be[1])
        return;
    const double len = be[1] > be[0] ? be[1] - be[0] : be[1] + 1 - be[0];
    const double c = be[0] + len / 2 + 0.5 * d * sq__rng_normal(r);
    const double w = fmin(fmax(len * exp(2 * d * sq__rng_normal(r)), 0.01), 0.9);
    be[0] = fmod(fmod(c - w / 2, 1) + 1, 1);
    be[1] = fmod(fmod(c + w / 2, 1) + 1, 1);
}

/* A variation: every gene but the categorical ones (structure) moved by a normal step of
 * standard deviation d in its [0, 1] range, in value space so that a value outside the
 * suggested range is moved from where it is, not first clamped into it; kept within the
 * hard range. Colours move in CIELAB instead (vary_colour), bands as bands (vary_band). */
static void vary(SqRng *r, const SqGenome *g, const SqParams *origin, double d, SqParams *p)
{
    *p = *origin;
    for (int i = 0; i < g->n; i++) {
        const SqGene *e = &g->genes[i];
        const SqParamSpec *s = e->spec;
        if (s->type == SQ_PT_COLOR) {
            if (e->comp == 0)
                vary_colour(r, d, (double *)sq__gene_ptr(e, p));
            continue;
        }
        if (strncmp(s->name, "Transversal_BeginEnd", 20) == 0) {
            if (e->comp == 0)
                vary_band(r, d, (double *)sq__gene_ptr(e, p));
            continue;
        }
        const double step = d * sq__rng_normal(r);
        if (s->type == SQ_PT_ENUM)
            continue;
        if (s->type == SQ_PT_INT || s->type == SQ_PT_BOOL) {
            int *v = (int *)sq__gene_ptr(e, p);
            double nv = e->levels ? *v + lround(step * e->levels) : lround(*v + step * (e->hi - e->lo));
            *v = (int)fmin(fmax(nv, s->min), s->max);
            continue;
        }
        double *v = (double *)sq__gene_ptr(e, p) + e->comp;
        double nv;
        if (e->kind == SQ_GENE_LOG)
            nv = (*v < e->lo && step < 0) ? *v : fmax(*v, e->lo) * pow(e->hi / e->lo, step);
        else
            nv = *v + step * (e->hi - e->lo);
        *v = fmin(fmax(nv, s->min), s->max);
    }
}

/* Ascending to_origin; ties (equal features) in the order drawn, by the parameters' seed
 * and bytes so that qsort's order does not matter. */
static int by_distance_to_origin(const void *a, const void *b)
{
    const SqSeedCandidate *x = a, *y = b;
    if (x->to_origin != y->to_origin)
        return x->to_origin < y->to_origin ? -1 : 1;
    return memcmp(&x->params, &y->params, sizeof x->params);
}

/* Where candidates come from: random draws of a genome (of one of ng, at random: the
 * layered kind's pairs), or variations of an origin. */
typedef struct Source {
    const SqGenome *g;
    int ng;
    int kind;                     /* what they are (SqPatternType or SQ_FIT_LAYERED) */
    const SqParams *origin;       /* NULL: random draws */
    const SqSeedCandidate *anchor; /* the rendered origin: plausibility and distances */
} Source;

/* Rounds of `want` candidates drawn and rendered until `want` are plausible (or
 * DRAW_ROUNDS rounds), then n picked among them by farthest-point sampling. */
static SqStatus pool_and_pick(Run *r, const Source *src, int want, SqSeedResult *out, SqError *err)
{
    const SqSeedOptions *o = r->o;
    SqRng rng;
    sq__rng_seed(&rng, o->seed);
    SqSeedCandidate *batch = malloc(sizeof *batch * (size_t)want);
    int *ok = malloc(sizeof(int) * (size_t)want), *pick = malloc(sizeof(int) * (size_t)o->n);
    out->pool = malloc(sizeof *out->pool * (size_t)want);
    SqStatus st = SQ_OK;
    if (!batch || !ok || !pick || !out->pool) {
        st = sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
        goto done;
    }
    for (int round = 0; round < DRAW_ROUNDS && out->npool < want; round++) {
        for (int i = 0; i < want; i++) {
            if (src->origin)
                vary(&rng, src->g, src->origin, o->distance, &batch[i].params);
            else
                draw_candidate(&rng, &src->g[src->ng > 1 ? sq__rng_int(&rng, src->ng) : 0], &batch[i].params);
        }
        render_all(r, batch, want, ok, round * want, round * want + want);
        out->drawn += want;
        for (int i = 0; i < want; i++) {
            if (!ok[i])
                out->failed++;
            else if (src->anchor ? !plausible_near(&batch[i], src->anchor) : !plausible(&batch[i]))
                out->implausible++;
            else if (out->npool < want) {
                batch[i].source = out->drawn - want + i;
                out->pool[out->npool++] = batch[i];
            }
        }
    }
    if (out->npool < o->n) {
        st = sq_error_set(err, SQ_ERR_LIMIT, sq_fit_kind_name(src->kind),
                          "only %d of %d %s drawn were plausible, fewer than the %d asked for%s", out->npool,
                          out->drawn, src->origin ? "variations" : "candidates", o->n,
                          src->origin ? "; try a smaller distance" : "");
        goto done;
    }
    const SqFeatures *anchor = src->anchor ? &src->anchor->features : NULL;
    int m = out->npool;
    if (anchor) {
        /* the nearer half (at least n) of the variations: the far ones are mostly broken
         * (spots that vanish, stripes that merge), and farthest-point sampling would take
         * them first */
        for (int i = 0; i < out->npool; i++)
            out->pool[i].to_origin = sq_seed_distance(anchor, &out->pool[i].features);
        qsort(out->pool, (size_t)out->npool, sizeof *out->pool, by_distance_to_origin);
        m = out->npool / 2 > o->n ? out->npool / 2 : o->n;
    }
    if ((st = farthest_points(r, out->pool, m, anchor, o->n, pick, err)) == SQ_OK)
        st = gather(out, out->pool, pick, o->n, err);
done:
    free(batch);
    free(ok);
    free(pick);
    return st;
}

SqStatus sq_seed_category(int category, const SqSeedOptions *o, SqSeedResult *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    SqStatus st = check_options(o, 0, err);
    if (st != SQ_OK)
        return st;
    if (category < 0 || category > SQ_FIT_LAYERED)
        return sq_error_set(err, SQ_ERR_INVALID, "seed", "kind %d is none of the %d there are", category,
                            (int)SQ_FIT_KINDS);
    /* one genome, or for the layered kind every pair the fit searches (one layer of
     * stripes, bands or spots over another simple pattern), drawn at random */
    SqGenome *g = malloc(sizeof *g * SQ_PATTERN_COUNT * SQ_PATTERN_COUNT);
    int ng = 0;
    if (!g)
        return sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
    for (int base = 0; base < SQ_PATTERN_COUNT && st == SQ_OK; base++)
        for (int layer = -1; layer < SQ_PATTERN_COUNT && st == SQ_OK; layer++)
            if (category == SQ_FIT_LAYERED ? sq_genome_layerable(base, layer) : base == category && layer < 0)
                if ((st = sq_genome_init_layered(&g[ng], base, layer, err)) == SQ_OK)
                    sq__genome_narrow(&g[ng++]);
    Run r = {0};
    if (st == SQ_OK && (st = run_begin(&r, o, out, err)) == SQ_OK) {
        int want = o->n * (o->pool > 0 ? o->pool : 12);
        if (want < 2 * MEDOID_SAMPLE && o->n > 1)
            want = 2 * MEDOID_SAMPLE; /* a few presets still choose among enough */
        const Source src = {.g = g, .ng = ng, .kind = category};
        st = pool_and_pick(&r, &src, want, out, err);
    }
    run_end(&r);
    free(g);
    if (st != SQ_OK)
        sq_seed_result_free(out);
    return st;
}

SqStatus sq_seed_near(const SqParams *origin, const SqSeedOptions *o, SqSeedResult *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    Run r;
    SqGenome g;
    SqStatus st = check_options(o, 1, err);
    if (st != SQ_OK)
        return st;
    if ((st = sq_params_validate(origin, err)) != SQ_OK)
        return st;
    /* the genome the fit would search (a layered preset's layer included); a stack of
     * several layers, which the fit does not search, varies its base only */
    if (origin->Pattern_Layers.count > 1 ? (st = sq_genome_init(&g, origin->Pattern_Type, err)) != SQ_OK
                                         : (st = sq_genome_of(&g, origin, err)) != SQ_OK)
        return st;
    SqSeedCandidate *orig = malloc(sizeof *orig);
    if (!orig)
        return sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
    if ((st = run_begin(&r, o, out, err)) == SQ_OK) {
        orig->params = *origin;
        if (evaluate(orig, o->size, r.threads, &r.maps[0], &r.plain[0], err) != 0) {
            st = err && err->status != SQ_OK ? err->status : SQ_ERR_INVALID;
        } else {
            /* held to plausible(), or to the origin's own measures when it fails them */
            const Source src = {.g = &g, .ng = 1, .kind = sq_fit_kind_of(origin), .origin = origin, .anchor = orig};
            st = pool_and_pick(&r, &src, o->n * (o->pool > 0 ? o->pool : 4), out, err);
        }
    }
    run_end(&r);
    free(orig);
    if (st != SQ_OK)
        sq_seed_result_free(out);
    return st;
}

/* Where c stands in the fit's front, or -1. */
static int front_index(const SqFitResult *fit, const SqFitCandidate *c)
{
    for (int i = 0; i < fit->nfront; i++)
        if (fit->front[i].view_scale == c->view_scale && sq_params_equal(&fit->front[i].params, &c->params))
            return i;
    return -1;
}

SqStatus sq_seed_from_fit(const SqFitResult *fit, const SqSeedOptions *o, SqSeedResult *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    Run r;
    SqStatus st = check_options(o, 0, err);
    if (st != SQ_OK)
        return st;
    if (!fit || fit->nfront < 1)
        return sq_error_set(err, SQ_ERR_INVALID, "seed", "the fit has no front");
    if ((st = run_begin(&r, o, out, err)) != SQ_OK)
        return st;
    /* the offers: the champion, each other kind's best by score (the front may hold one or
     * two kinds only, and an artist may know the snake's kind better than the fit), then
     * the rest of the front */
    const int most = fit->nfront + SQ_FIT_KINDS;
    int n = 0, noffer = 0;
    const SqFitCandidate **offer = malloc(sizeof *offer * (size_t)most);
    int *ok = malloc(sizeof(int) * (size_t)most), *pick = malloc(sizeof(int) * (size_t)most);
    out->pool = malloc(sizeof *out->pool * (size_t)most);
    if (!offer || !ok || !pick || !out->pool) {
        free(offer);
        st = sq_error_set(err, SQ_ERR_NOMEM, "seed", "out of memory");
        goto done;
    }
    int kinds[SQ_FIT_KINDS];
    const int nkinds = sq_fit_kinds_offered(fit, kinds);
    offer[noffer++] = &fit->front[0];
    for (int i = 1; i < nkinds; i++)
        offer[noffer++] = &fit->kind_best[kinds[i]];
    for (int i = 1; i < fit->nfront; i++)
        offer[noffer++] = &fit->front[i];
    /* the first o->n distinct presets: one preset may stand in the front at two view
     * scales, and a kind's best in the front too, and a preset sheet shows no view scale */
    for (int i = 0; i < noffer && n < o->n; i++) {
        int seen = 0;
        for (int j = 0; j < n && !seen; j++)
            seen = sq_params_equal(&out->pool[j].params, &offer[i]->params);
        if (seen)
            continue;
        out->pool[n].params = offer[i]->params;
        out->pool[n].source = front_index(fit, offer[i]);
        out->pool[n].fitted = offer[i];
        pick[n] = n;
        n++;
    }
    free(offer);
    render_all(&r, out->pool, n, ok, 0, n);
    for (int i = 0; i < n; i++)
        if (!ok[i]) {
            st = out->pool[i].source >= 0
                     ? sq_error_set(err, SQ_ERR_INTERNAL, "seed", "front member %d of the fit cannot be rendered",
                                    out->pool[i].source)
                     : sq_error_set(err, SQ_ERR_INTERNAL, "seed", "the fit's best %s skin cannot be rendered",
                                    sq_fit_kind_name(sq_fit_kind_of(&out->pool[i].params)));
            goto done;
        }
    for (int i = 0; i < n; i++)
        out->pool[i].to_origin = sq_seed_objective_distance(out->pool[i].fitted->obj);
    out->npool = out->drawn = n;
    st = gather(out, out->pool, pick, n, err);
done:
    free(ok);
    free(pick);
    run_end(&r);
    if (st != SQ_OK)
        sq_seed_result_free(out);
    return st;
}
