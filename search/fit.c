/* The fit driver: screen every category, evolve the promising ones, re-score the finalists,
 * polish the champion. See search.h for the stages. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <nlopt.h>
#include <omp.h>

#include "rng.h"
#include "search_internal.h"
#include "squama/search.h"

enum {
    ARCHIVE_MAX = 64,
    CATEGORIES = SQ_FIT_KINDS /* the kinds of skin the fit tells apart (sq_fit_kind_of) */
};

/* A simpler category (see simplicity()) scoring within this fraction of the best is
 * preferred to it. */
static const double PARSIMONY = 0.05;

/* A plain skin scoring within this fraction of the best is preferred to any pattern. On a
 * plain photo every pattern niche spends its genes imitating the scales' shading and the
 * photo's noise, and its re-scored best still comes out luckier than the plain skin's:
 * over 337 recovery fits (sessions 13 to 19, seeds 1 to 3, main and trial variants), the
 * plain niche's best was within 5% of the best on 28 of the 58 plain photos, within 30% on
 * 47; of the 279 patterned photos, the 20 where it came within 30% were fitted wrong
 * already (docs/recovery.md, session 19). */
static const double PLAIN_PARSIMONY = 0.30;

/* A layered skin searched over the champion leads only when it scores this fraction
 * better (layer_search). */
static const double LAYER_LEAD = 0.2;

/* The reaction-diffusion grid of the fit's complex candidates (RD_Cells). */
enum { FIT_RD_CELLS = 48 };

/* A pattern is visible when more than VISIBLE_MIN of the texels the fit looks at (the
 * band around band_centre) differ from the skin's dominant colour by more than
 * VISIBLE_DE (CIEDE2000, a difference anyone sees side by side). */
static const double VISIBLE_DE = 5.0, VISIBLE_MIN = 0.02;

/* The search (screening and evolution) ends at this share of the budget; re-scoring, the
 * layer search and the polish have the rest. */
static const double SEARCH_END = 0.8;

/* A baseline, which has no layer search or polish, searches to this share of a time
 * budget; of an evaluation budget, to all of it but its one finalist's re-scoring (counted
 * down in Baseline.left). */
static const double BASELINE_END = 0.95;

/* The view scale gene: log scale over lo..hi (the niches': SQ__VIEW_LO..SQ__VIEW_HI). */
static double view_to_x_in(double v, double lo, double hi)
{
    return log(fmax(v, lo) / lo) / log(hi / lo);
}

static double x_to_view_in(double x, double lo, double hi)
{
    return lo * pow(hi / lo, fmin(fmax(x, 0), 1));
}

static double view_to_x(double v)
{
    return view_to_x_in(v, SQ__VIEW_LO, SQ__VIEW_HI);
}

static double x_to_view(double x)
{
    return x_to_view_in(x, SQ__VIEW_LO, SQ__VIEW_HI);
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Spot lattices read off the photo that start screening candidates (spot_candidates). */
enum { SPOT_READINGS = 3 };

typedef struct Fit {
    const SqFeatures *target;
    SqFitOptions o;
    SqFitResult *r;
    SqRng rng;
    int threads;
    SqTextures *maps; /* one per thread */
    double t0;
    long evals;
    float pal[SQ_FIT_PALETTE][3]; /* the photo's palette, sRGB, by weight */
    int npal;
    SqFitCandidate *archive; /* the non-dominated candidates so far */
    int narchive;
    int history_cap;
    double best_score, best_obj[SQ_OBJ_COUNT];
    double gen_best; /* the last generation's lowest score (NAN: none since the last report) */
    int generation;
    struct {
        double tiling, offset, view;
    } spot_read[SPOT_READINGS]; /* the spot lattices read that started screening candidates */
    int nspot_read;
    double tail_s; /* a time budget's seconds kept for what follows the polish (tail_seconds) */
} Fit;

SqFitOptions sq_fit_options_default(void)
{
    SqFitOptions o = {0};
    o.budget = 60;
    o.coarse_size = 128;
    o.fine_size = 256;
    o.screen = 48;
    o.niches = 2;
    o.reseeds = 4;
    o.front_max = 24;
    o.band_centre = 0.5;
    o.polish = 1;
    o.seed = 1;
    return o;
}

const char *sq_fit_method_name(SqFitMethod m)
{
    static const char *const names[] = {"squama", "random", "esch", "crs2", "isres"};
    return (unsigned)m < sizeof names / sizeof names[0] ? names[m] : "?";
}

int sq_fit_kind_of(const SqParams *p)
{
    return p->Pattern_Layers.count > 0 ? SQ_FIT_LAYERED : p->Pattern_Type;
}

const char *sq_fit_kind_name(int kind)
{
    return kind == SQ_FIT_LAYERED ? "layered" : sq_pattern_type_name(kind);
}

int sq_fit_kind_from_name(const char *name)
{
    for (int k = 0; k < SQ_FIT_KINDS; k++)
        if (strcmp(name, sq_fit_kind_name(k)) == 0)
            return k;
    return -1;
}

void sq_fit_result_free(SqFitResult *r)
{
    if (!r)
        return;
    free(r->front);
    free(r->history);
    r->front = NULL;
    r->history = NULL;
    r->nfront = r->nhistory = 0;
}

static double elapsed(const Fit *f)
{
    return now() - f->t0;
}

/* 1 when the caller asked to stop or the clock is past fraction of a time budget. */
static int out_of_time(const Fit *f, double fraction)
{
    return (f->o.stop && *f->o.stop) || (f->o.budget > 0 && elapsed(f) >= fraction * f->o.budget);
}

/* 1 when the search must end: the caller's flag, the clock, or the evaluations (each as a
 * fraction of the whole budget). */
static int out_of_budget(const Fit *f, double fraction)
{
    return out_of_time(f, fraction) ||
           (f->o.max_evals > 0 && f->evals >= (long)(fraction * (double)f->o.max_evals));
}

/* How far the search is through its budget: the larger of its clock's and its
 * evaluations' share (0 with neither). */
static double progress(const Fit *f)
{
    double p = 0;
    if (f->o.budget > 0)
        p = elapsed(f) / f->o.budget;
    if (f->o.max_evals > 0)
        p = fmax(p, (double)f->evals / (double)f->o.max_evals);
    return p;
}

static void score_of(const Fit *f, SqFitCandidate *c)
{
    double s = 0;
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        s += c->obj[k] / f->r->norm[k];
    c->score = isfinite(s) ? s : INFINITY;
}

static void set_failed(SqFitCandidate *c)
{
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        c->obj[k] = INFINITY;
    c->score = INFINITY;
}

/* One candidate at a fixed view scale, its render on `threads` threads; its strip's
 * features in *feat. Returns 0, or -1 when it failed (its objectives infinite). */
static int evaluate_features(const Fit *f, SqFitCandidate *c, int size, int threads, SqTextures *maps,
                             SqFeatures *feat)
{
    SqGenOptions go = sq_gen_options_default(size);
    go.threads = threads;
    SqImage strip = {0};
    if (sq_gen_render_into(&c->params, &go, maps, NULL) != SQ_OK ||
        sq_fit_candidate_strip(&maps->basecolor, &maps->normal, &maps->roughness, &f->target->light, c->view_scale, f->o.band_centre,
                               SQ_FIT_CANDIDATE_ROWS, &strip, NULL) != SQ_OK ||
        sq_fit_features_blurred(&strip, NULL, f->target->blur, feat, NULL) != SQ_OK) {
        sq_image_free(&strip);
        set_failed(c);
        return -1;
    }
    sq_image_free(&strip);
    sq_fit_objectives(f->target, feat, c->obj);
    return 0;
}

static void evaluate(const Fit *f, SqFitCandidate *c, int size, int threads, SqTextures *maps)
{
    SqFeatures feat;
    evaluate_features(f, c, size, threads, maps, &feat);
}

/* Candidates in parallel: grid = 1 searches the view scale grid (screening). Each result
 * depends only on its candidate, so any thread count gives the same numbers. */
static void evaluate_all(Fit *f, SqFitCandidate *c, int n, int size, int grid)
{
#pragma omp parallel for schedule(dynamic, 1) num_threads(f->threads)
    for (int i = 0; i < n; i++) {
        SqTextures *maps = &f->maps[omp_get_thread_num()];
        if (grid) {
            if (sq_fit_score(f->target, &c[i].params, size, f->o.band_centre, 0, maps, c[i].obj,
                             &c[i].view_scale, NULL, NULL) != SQ_OK)
                set_failed(&c[i]);
        } else {
            evaluate(f, &c[i], size, 1, maps);
        }
    }
    f->evals += n;
}

/* ---- the archive: non-dominated candidates, pruned by crowding ---- */

static int archive_add(Fit *f, const SqFitCandidate *c, int n)
{
    int total = f->narchive + n;
    if (total <= 0)
        return 0;
    SqFitCandidate *all = malloc(sizeof *all * (size_t)total);
    double *obj = malloc(sizeof(double) * SQ_OBJ_COUNT * (size_t)total);
    int *rank = malloc(sizeof(int) * (size_t)total);
    double *crowd = malloc(sizeof(double) * (size_t)total);
    if (!all || !obj || !rank || !crowd) {
        free(all);
        free(obj);
        free(rank);
        free(crowd);
        return -1;
    }
    memcpy(all, f->archive, sizeof *all * (size_t)f->narchive);
    memcpy(all + f->narchive, c, sizeof *all * (size_t)n);
    for (int i = 0; i < total; i++)
        memcpy(obj + (size_t)i * SQ_OBJ_COUNT, all[i].obj, sizeof all[i].obj);
    int fail = sq_nsga2_rank(obj, total, SQ_OBJ_COUNT, rank) < 0;
    int kept = 0;
    if (!fail) {
        sq_nsga2_crowding(obj, total, SQ_OBJ_COUNT, rank, crowd);
        /* rank 0 only; beyond the cap the most crowded go first */
        for (int i = 0; i < total; i++)
            if (rank[i] == 0 && isfinite(all[i].score))
                kept++;
        while (kept > ARCHIVE_MAX) {
            int worst = -1;
            for (int i = 0; i < total; i++)
                if (rank[i] == 0 && isfinite(all[i].score) &&
                    (worst < 0 || crowd[i] < crowd[worst] ||
                     (crowd[i] == crowd[worst] && all[i].score > all[worst].score)))
                    worst = i;
            rank[worst] = 1;
            kept--;
        }
        int k = 0;
        for (int i = 0; i < total && k < ARCHIVE_MAX; i++)
            if (rank[i] == 0 && isfinite(all[i].score))
                f->archive[k++] = all[i];
        f->narchive = k;
    }
    free(all);
    free(obj);
    free(rank);
    free(crowd);
    return fail ? -1 : 0;
}

static void note_best(Fit *f, const SqFitCandidate *c, int n)
{
    for (int i = 0; i < n; i++) {
        f->best_score = fmin(f->best_score, c[i].score);
        if (isfinite(c[i].score))
            f->gen_best = isnan(f->gen_best) ? c[i].score : fmin(f->gen_best, c[i].score);
        for (int k = 0; k < SQ_OBJ_COUNT; k++)
            f->best_obj[k] = fmin(f->best_obj[k], c[i].obj[k]);
    }
}

static void report(Fit *f, const char *stage, int category)
{
    SqFitResult *r = f->r;
    if (r->nhistory == f->history_cap) {
        int cap = f->history_cap ? 2 * f->history_cap : 64;
        SqFitHistory *h = realloc(r->history, sizeof *h * (size_t)cap);
        if (h) {
            r->history = h;
            f->history_cap = cap;
        }
    }
    const int gen = !strcmp(stage, "evolve") || !strcmp(stage, "layer");
    const double gen_best = gen ? f->gen_best : NAN;
    f->gen_best = NAN;
    if (r->nhistory < f->history_cap) {
        SqFitHistory *h = &r->history[r->nhistory++];
        h->evals = f->evals;
        h->seconds = elapsed(f);
        h->best_score = f->best_score;
        memcpy(h->best, f->best_obj, sizeof h->best);
        h->stage = stage;
        h->category = gen ? category : -1;
        h->generation_best = gen_best;
    }
    if (!f->o.progress)
        return;
    SqFitProgress p = {0};
    p.stage = stage;
    p.generation = f->generation;
    p.evals = f->evals;
    p.elapsed = elapsed(f);
    p.budget = f->o.budget;
    p.best_score = f->best_score;
    p.generation_best = gen_best;
    memcpy(p.best, f->best_obj, sizeof p.best);
    p.category = category;
    p.front = f->archive;
    p.nfront = f->narchive;
    f->o.progress(&p, f->o.ctx);
}

/* ---- stage 1: screening ---- */

static void set_colour(Fit *f, double *dst, int k)
{
    for (int c = 0; c < 3; c++)
        dst[c] = fmin(fmax(f->pal[k][c] + 0.03 * sq__rng_normal(&f->rng), 0), 1);
    dst[3] = 1;
}

/* Background and pattern colours from the photo's palette: usually the dominant colour
 * under a minor one, sometimes the other way round. */
static void colours_from_palette(Fit *f, SqParams *p, int category)
{
    if (f->npal == 0)
        return;
    int bg = 0;
    if (f->npal > 1 && sq__rng_uniform(&f->rng) < 0.3)
        bg = 1;
    set_colour(f, p->Background_Color, bg);
    double *list[8];
    sq__pattern_colours(&p->pattern, category, list);
    for (int l = 0; l <= p->Pattern_Layers.count; l++) {
        if (l > 0) /* a layer's pattern: other palette colours than the ground's too */
            sq__pattern_colours(&p->Pattern_Layers.layer[l - 1].spec, p->Pattern_Layers.layer[l - 1].spec.Pattern_Type,
                            list);
        for (int i = 0; list[i]; i++) {
            int k = bg;
            if (f->npal > 1)
                while (k == bg)
                    k = sq__rng_int(&f->rng, f->npal);
            set_colour(f, list[i], k);
        }
    }
    /* the outline: the darkest palette colour */
    int dark = 0;
    float lab[3], dl = 1e9f;
    for (int k = 0; k < f->npal; k++) {
        sq_fit_srgb_to_lab(f->pal[k], lab);
        if (lab[0] < dl) {
            dl = lab[0];
            dark = k;
        }
    }
    set_colour(f, p->Outline_Color, dark);
}

/* A screening candidate: genes drawn over plausible ranges (g narrowed), colours from the
 * photo's palette. */
static void random_candidate(Fit *f, const SqGenome *g, SqFitCandidate *c)
{
    sq__genome_draw(&f->rng, g, &c->params);
    colours_from_palette(f, &c->params, g->category);
    sq__draw_bands(&f->rng, g, &c->params);
    if (g->has_ca) {
        uint64_t s = sq__rng_next(&f->rng);
        sq_gp_ca_random(&s, &c->params.CA_Descriptor);
    }
    if (g->category == SQ_PATTERN_COMPLEX) {
        /* a simulation costs the square of its grid: the fit's is as small as the shipped
         * presets' (36 to 56 cells); RD_ReactionSpeed and the view scale set the feature
         * size */
        c->params.RD_Cells = FIT_RD_CELLS;
        /* a rim or core, and a cascade's centres: on or off */
        c->params.RD_Color2[3] = sq__rng_uniform(&f->rng) < 0.5;
        c->params.RD_Color3[3] = sq__rng_uniform(&f->rng) < 0.5;
    }
    c->params.Seed = (int)(sq__rng_next(&f->rng) & 0x7fffffff);
    c->view_scale = 1;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int cmp_score(const void *a, const void *b)
{
    const SqFitCandidate *x = a, *y = b;
    return (x->score > y->score) - (x->score < y->score);
}

/* Whether the fit tries category c. */
static int fitted(const SqFitOptions *o, int c)
{
    const unsigned kinds = o->categories ? o->categories : SQ_FIT_DEFAULT_KINDS;
    return c >= 0 && c < CATEGORIES && ((kinds >> c) & 1u);
}

static int ncategories(const SqFitOptions *o)
{
    int n = 0;
    for (int c = 0; c < CATEGORIES; c++)
        n += fitted(o, c);
    return n;
}

/* The skin the dominant colour, the pattern the palette's farthest in lightness the way
 * of sign (> 0: lighter); none that way: the dominant colour is the pattern's, the skin
 * the farthest the other way. Nothing with a palette of one colour. */
static void polar_colours(Fit *f, double sign, double *skin, double *pattern)
{
    if (f->npal < 2)
        return;
    float lab[3];
    sq_fit_srgb_to_lab(f->pal[0], lab);
    const double l0 = lab[0];
    sign = sign > 0 ? 1 : -1;
    int in = 0, bg = 0;
    double most = 0, least = 0;
    for (int q = 1; q < f->npal; q++) {
        sq_fit_srgb_to_lab(f->pal[q], lab);
        const double d = (lab[0] - l0) * sign;
        if (d > most) {
            most = d;
            in = q;
        }
        if (d < least) {
            least = d;
            bg = q;
        }
    }
    if (in > 0)
        bg = 0;
    set_colour(f, skin, bg);
    set_colour(f, pattern, in);
}

/* Screening candidates from automata read off the photo's strip: two a reading, at its
 * view scale, diameter, blur and contrast; the first coloured by the reading's polarity
 * (the pattern lighter or darker than the skin's dominant colour), the second as any
 * screening candidate is. They are used only when the best reading correlates READ_MIN
 * or better with the strip: an automaton can imitate any pattern that repeats within a
 * texture tile (reaction-diffusion and spots tile too), and a weak reading only helps it
 * to. Returns how many candidates were made (at most 2 * READINGS). */
enum { READINGS = 4 };
static const double READ_MIN = 0.8;
static int read_candidates(Fit *f, SqFitCandidate *c)
{
    if (!f->o.strip || !fitted(&f->o, SQ_PATTERN_OTHER_SIMPLE))
        return 0;
    SqCaReading rd[READINGS];
    const int nr = sq_fit_read_automata(f->o.strip, f->o.valid, f->o.band_centre, f->o.seed, rd, READINGS);
    if (nr == 0)
        return 0;
    f->r->read_view_scale = rd[0].view_scale;
    f->r->read_corr = rd[0].corr;
    SqGenome g;
    if (fabs(rd[0].corr) < READ_MIN)
        return 0;
    if (sq_genome_init_layered(&g, SQ_PATTERN_OTHER_SIMPLE, -1, NULL) != SQ_OK)
        return 0;
    sq__genome_narrow(&g);
    f->r->automata_read = nr;
    int k = 0;
    for (int i = 0; i < nr; i++)
        for (int v = 0; v < 2; v++) {
            SqFitCandidate *x = &c[k++];
            random_candidate(f, &g, x);
            SqParams *p = &x->params;
            p->CA_Descriptor = rd[i].ca;
            p->CA_CircleDiameter = rd[i].diameter;
            p->Pattern_BlurAmount = rd[i].blur;
            p->Pattern_Contrast = rd[i].contrast;
            p->Pattern_RotatePattern90Degrees = 0;
            p->Pattern_Warp_Small = p->Pattern_Warp_Large = 0;
            p->CustomPattern_LevelInLow = 0;
            p->CustomPattern_LevelInHigh = 1;
            p->CustomPattern_LevelInMid = 0.5;
            x->view_scale = rd[i].view_scale;
            if (v == 0)
                polar_colours(f, rd[i].corr, p->Background_Color, p->CustomPattern_Color_Inside);
        }
    return k;
}

/* Screening candidates from spot lattices read off the photo's strip (sq_fit_read_spots):
 * SPOT_SIZES a lattice, its count round the body (Spots_Tiling), offset and, from its
 * spacing along, view scale; the spots in place, unturned, without warps, blur or
 * contrast, their semi-axes across and along a ladder of shares of the spacings; the skin
 * and the spots coloured as the strip's middle lightness and its 2% farthest the skew's
 * way (the palette blends small spots with the skin around them: coloured from it, row
 * 18's read candidates scored 3 to 10 on the palette objective, the truth 0.9). A spots
 * niche searched from random draws settles on imitations (the scales' lattice at
 * another view scale) while the truth's basin is narrow: a tenth more tiling, or spots
 * a third narrower, double or triple the spectral objectives
 * (docs/recovery.md, sessions 20 and 21). Used only when the best lattice scores
 * SPOT_READ_MIN or better. On the recovery benchmark's 38 photos at seed 3 the three spot
 * lattices read 0.62 to 1.22 and the three photos of spots moved at random 0.30 to 0.40;
 * plain skins 0.13 to 0.46 but one 0.66 (its scales' lattice, at view scale 0.14, beyond
 * the fit's views; a clean render reads up to 0.77), stripes 0.28 at most, bands 0.41 to
 * 0.78, automata 0.35 to 1.04, complex photos 0.25 to 0.56. Session 21 set it at 0.8: the
 * lattices read, in the colours read off the strip, made spots the impostor on 3 of the 6
 * complex photos when started on every photo. Recoloured (spot_recoloured), at 0.55 they
 * turned 4 of 6 wrong spot and automata rows right at seed 3 and lost none (session 49).
 * The best reading is kept in the result either way. Returns how many candidates were
 * made (at most SPOT_READINGS * SPOT_SIZES). */
enum { SPOT_STEPS = 5, SPOT_SIZES = SPOT_STEPS * SPOT_STEPS };
static const double SPOT_READ_MIN = 0.55;
static int spot_candidates(Fit *f, SqFitCandidate *c)
{
    if (!f->o.strip || !fitted(&f->o, SQ_PATTERN_SPOTS))
        return 0;
    SqSpotsReading rd[SPOT_READINGS];
    const int nr = sq_fit_read_spots(f->o.strip, f->o.valid, rd, SPOT_READINGS);
    if (nr > 0) {
        f->r->spots_read_across = rd[0].across;
        f->r->spots_read_view_scale = rd[0].view_scale;
        f->r->spots_read_score = rd[0].score;
    }
    SqGenome g;
    if (nr == 0 || rd[0].score < SPOT_READ_MIN || sq_genome_init_layered(&g, SQ_PATTERN_SPOTS, -1, NULL) != SQ_OK)
        return 0;
    sq__genome_narrow(&g);
    int k = 0;
    for (int i = 0; i < nr; i++) {
        if (rd[i].view_scale < SQ__VIEW_LO || rd[i].view_scale > SQ__VIEW_HI)
            continue;
        for (int v = 0; v < SPOT_SIZES; v++) {
            SqFitCandidate *x = &c[k++];
            random_candidate(f, &g, x);
            SqParams *p = &x->params;
            p->Spots_Tiling = rd[i].across / 10.0;
            p->Spots_Offset = rd[i].offset;
            p->Spots_PositionRandom[0] = p->Spots_PositionRandom[1] = 0;
            /* the semi-axes: 0.08 to 0.4 of the spacing across and of the rows' along,
             * each a ladder of SPOT_STEPS a factor of 1.5 apart */
            const double ra = 0.08 * pow(1.5, v % SPOT_STEPS), rb = 0.08 * pow(1.5, v / SPOT_STEPS),
                         m = fmax(ra, rb);
            p->Spots_Scale = 2 * m;
            p->Spots_ScaleVariation = 0;
            p->Spots_Interstice[0] = 1 - ra / m;
            p->Spots_Interstice[1] = 1 - rb / m;
            p->Spots_IntersticeRandom[0] = p->Spots_IntersticeRandom[1] = 0;
            p->Spots_Rotation = p->Spots_RotationRandom = 0;
            p->Pattern_RotatePattern90Degrees = 0;
            p->Pattern_Warp_Small = p->Pattern_Warp_Large = 0;
            p->Pattern_BlurAmount = p->Pattern_Contrast = p->Color_NoiseIntensity = 0;
            x->view_scale = rd[i].view_scale;
            if (rd[i].coloured)
                for (int ch = 0; ch < 3; ch++) {
                    p->Background_Color[ch] = rd[i].skin[ch];
                    p->Spots_Color[ch] = rd[i].spot[ch];
                }
            else
                polar_colours(f, rd[i].skew, p->Background_Color, p->Spots_Color);
        }
        f->spot_read[f->nspot_read].tiling = rd[i].across / 10.0;
        f->spot_read[f->nspot_read].offset = rd[i].offset;
        f->spot_read[f->nspot_read++].view = rd[i].view_scale;
    }
    f->r->spots_read = k;
    return k;
}

/* Transversal bands read off the photo's strip (sq_fit_read_bands), its first reading
 * kept in the result (the repeat and the share explained are every reading's): none of
 * it starts a screening candidate. Tried and not kept (session
 * 37): BANDS_VARIANTS = 4 candidates a reading (two colours and three), its bands, colours
 * and view scale, unturned, without warps, blur, contrast or colour noise, the other genes
 * drawn, when the best reading repeats 0.5 or more and its rows hold 0.75 or more of the
 * strip's colour variance (spots and automata repeat along the body as well, their rows of
 * several colours). On the recovery benchmark's photos the transversal rows read 0.84 to
 * 1.0 with 0.89 to 1.0 explained but for two (a repeat of 0.31; 0.33 explained), the
 * automata 0.96 to 0.99 with 0.35 to 0.72 explained, a spot lattice 0.92 with 0.10; the
 * four transversal rows read fitted at seeds 1 and 3 (5000 evaluations) kept their
 * categories but for row 17 at seed 1, lost to an automaton (its kind's best 1.31, the
 * truth 1.04: the niche started from the reading settled short of the truth). On a real
 * photo (the banded kingsnake lampropeltis_zonata__jv0077 along its body line: 0.55, 0.82
 * explained) it turned the pick from layered to bands, whose best then drifted to warped
 * bands at view scale 4. */
static void read_bands(Fit *f)
{
    if (!f->o.strip || !fitted(&f->o, SQ_PATTERN_TRANSVERSAL))
        return;
    SqBandsReading rd;
    if (sq_fit_read_bands(f->o.strip, f->o.valid, &rd, 1) > 0) {
        f->r->bands_read_view_scale = rd.view_scale;
        f->r->bands_read_corr = rd.corr;
        f->r->bands_read_explained = rd.explained;
    }
}

/* Each of c's n candidates scored at size (grid: at the best view scale of the screening's
 * grid, else at its own), in place, and its colours moved toward the photo's palette the
 * SQ_RECOLOUR_WAYS ways of sq__recoloured from the features of its strip, into out
 * (SQ_RECOLOUR_WAYS * n, scored at size); a candidate that fails is copied there. */
static void recoloured_all(Fit *f, SqFitCandidate *c, int n, int size, int grid, SqFitCandidate *out)
{
    enum { W = SQ_RECOLOUR_WAYS };
#pragma omp parallel for schedule(dynamic, 1) num_threads(f->threads)
    for (int i = 0; i < n; i++) {
        SqTextures *maps = &f->maps[omp_get_thread_num()];
        SqFeatures feat;
        int ok;
        if (grid) { /* the grid's strip at the scale chosen gives the features */
            SqImage strip = {0};
            ok = sq_fit_score(f->target, &c[i].params, size, f->o.band_centre, 0, maps, c[i].obj, &c[i].view_scale,
                              &strip, NULL) == SQ_OK &&
                 sq_fit_features_blurred(&strip, NULL, f->target->blur, &feat, NULL) == SQ_OK;
            sq_image_free(&strip);
            if (!ok)
                set_failed(&c[i]);
        } else {
            ok = evaluate_features(f, &c[i], size, 1, maps, &feat) == 0;
        }
        if (ok)
            sq__recoloured(f->target, &c[i], &feat, out + W * i);
        else
            for (int w = 0; w < W; w++)
                out[W * i + w] = c[i];
    }
    f->evals += n;
    evaluate_all(f, out, W * n, size, 0);
}

/* Screening candidates from the starting presets (o->starts, e.g. the shipped complex
 * ones), those of a kind fitted: each at the view scale of the screening's grid that
 * suits it best, as it is and its colours moved toward the photo's palette the
 * SQ_RECOLOUR_WAYS ways of sq__recoloured; a reaction-diffusion pattern on the fit's
 * grid. Returns how many candidates were made (at most (1 + SQ_RECOLOUR_WAYS) * nstarts). */
static int start_candidates(Fit *f, SqFitCandidate *c)
{
    enum { W = SQ_RECOLOUR_WAYS };
    int n = 0;
    for (int i = 0; i < f->o.nstarts; i++) {
        if (!fitted(&f->o, sq_fit_kind_of(&f->o.starts[i])))
            continue;
        SqFitCandidate *x = &c[n++];
        memset(x, 0, sizeof *x);
        x->params = f->o.starts[i];
        if (x->params.Pattern_Type == SQ_PATTERN_COMPLEX)
            x->params.RD_Cells = FIT_RD_CELLS;
        x->params.Seed = (int)(sq__rng_next(&f->rng) & 0x7fffffff);
        x->view_scale = 1;
    }
    if (n == 0)
        return 0;
    recoloured_all(f, c, n, f->o.coarse_size, 1, c + n);
    f->r->starts_used = n;
    return (1 + W) * n;
}

/* The spot lattices read that suit the photo's layout best (the lowest shape + along +
 * across, the objectives colours move least), SPOT_RECOLOURED of them, their colours moved
 * toward the photo's palette the SQ_RECOLOUR_WAYS ways of sq__recoloured and scored at the
 * view scale read. A reading's own colours come off the photo's strip, which is lit: a
 * candidate painted in them is lit once more, darker and flatter than the photo (row 18 of
 * the recovery benchmark, seed 3: its truth's lattice in the read colours scored 5.0 on the
 * palette objective, 0.80 in the truth's; the spots niche started from it ended at 1.36
 * against the truth's 0.51, an automaton won; recoloured, it ended at 0.60 and won). The
 * lowest palette objective before and after goes to the result. Writes SPOT_RECOLOURED *
 * SQ_RECOLOUR_WAYS candidates at most to out (sp: the ns spot lattice candidates, scored);
 * returns how many. */
enum { SPOT_RECOLOURED = 3 };
static int spot_recoloured(Fit *f, const SqFitCandidate *sp, int ns, SqFitCandidate *out)
{
    enum { W = SQ_RECOLOUR_WAYS };
    int pick[SPOT_RECOLOURED], n = 0;
    double as_read = INFINITY;
    for (int i = 0; i < ns; i++)
        as_read = fmin(as_read, sp[i].obj[SQ_OBJ_PALETTE]);
    while (n < SPOT_RECOLOURED) {
        int b = -1;
        double bv = INFINITY;
        for (int i = 0; i < ns; i++) {
            int taken = 0;
            for (int j = 0; j < n; j++)
                taken |= pick[j] == i;
            const double v = sp[i].obj[SQ_OBJ_SHAPE] + sp[i].obj[SQ_OBJ_ALONG] + sp[i].obj[SQ_OBJ_ACROSS];
            if (!taken && isfinite(v) && v < bv) {
                bv = v;
                b = i;
            }
        }
        if (b < 0)
            break;
        pick[n++] = b;
    }
    if (n == 0)
        return 0;
    SqFitCandidate x[SPOT_RECOLOURED];
    for (int i = 0; i < n; i++)
        x[i] = sp[pick[i]];
    recoloured_all(f, x, n, f->o.coarse_size, 0, out);
    double after = INFINITY;
    for (int i = 0; i < W * n; i++)
        after = fmin(after, out[i].obj[SQ_OBJ_PALETTE]);
    f->r->spots_recoloured = W * n;
    f->r->spots_palette_read = as_read;
    f->r->spots_palette_recoloured = after;
    return W * n;
}

/* Screens every category fitted; fills norm and category_score; leaves the candidates
 * sorted by score in *out. */
static SqStatus screen(Fit *f, SqFitCandidate **out, int *nout, SqError *err)
{
    const int ncat = ncategories(&f->o);
    int per = f->o.screen;
    if (f->o.max_evals > 0) { /* at most 30% of an evaluation budget, at least 4 a category */
        long cap = (long)(0.3 * (double)f->o.max_evals) / ncat;
        per = (int)(cap < per ? (cap > 4 ? cap : 4) : per);
    }
    int n = per * ncat + f->o.nseeds;
    /* beyond the draws: the automata read (two a reading), the spot lattices read and the
     * best of them recoloured, and each start as it is and recoloured */
    const size_t nextra = 2 * READINGS + SPOT_READINGS * SPOT_SIZES + SPOT_RECOLOURED * SQ_RECOLOUR_WAYS +
                          (size_t)f->o.nstarts * (1 + SQ_RECOLOUR_WAYS);
    SqFitCandidate *c = calloc((size_t)n + nextra, sizeof *c);
    double *col = malloc(sizeof(double) * ((size_t)n + nextra));
    if (!c || !col) {
        free(c);
        free(col);
        return sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory");
    }
    int k = 0;
    for (int kind = 0; kind < CATEGORIES; kind++) {
        SqGenome g;
        if (!fitted(&f->o, kind))
            continue;
        for (int i = 0; i < per; i++) {
            int base = kind, layer = -1;
            while (kind == SQ_FIT_LAYERED && !sq_genome_layerable(base, layer)) { /* a pair at random */
                base = sq__rng_int(&f->rng, SQ_PATTERN_COUNT);
                layer = sq__rng_int(&f->rng, SQ_PATTERN_COUNT);
            }
            if (i == 0 || kind == SQ_FIT_LAYERED) {
                if (sq_genome_init_layered(&g, base, layer, err) != SQ_OK) {
                    free(c);
                    free(col);
                    return err ? err->status : SQ_ERR_INTERNAL;
                }
                sq__genome_narrow(&g); /* drawn over plausible ranges; the niches search all */
            }
            random_candidate(f, &g, &c[k++]);
        }
    }
    for (int i = 0; i < f->o.nseeds; i++)
        c[k++] = f->o.seeds[i];
    /* the automata and spot lattices read off the photo: scored at the view scale read
     * with them; the spot lattices that suit best then recoloured */
    const int nca = read_candidates(f, c + k), nread = nca + spot_candidates(f, c + k + nca);
    read_bands(f);
    const int nstart = start_candidates(f, c + k + nread);
    const int rounds_n = n;
    evaluate_all(f, c + k, nread, f->o.coarse_size, 0);
    n += nread + nstart;
    n += spot_recoloured(f, c + k + nca, nread - nca, c + n);
    /* Scored round by round: the starting candidates and 4 of every kind, then 2 more of
     * every kind at a time. With a time budget screening stops after the round that reaches
     * 30% of it, every kind having had as many; the candidates left are dropped. */
    SqFitCandidate *batch = malloc(sizeof *batch * (size_t)n);
    int *in_round = malloc(sizeof(int) * (size_t)n);
    if (!batch || !in_round) {
        free(batch);
        free(in_round);
        free(c);
        free(col);
        return sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory");
    }
    int rounds_done = 0, scored = 0;
    while (rounds_done < per) {
        int upto = rounds_done == 0 ? (per < 4 ? per : 4) : rounds_done + 2, m = 0;
        upto = upto < per ? upto : per;
        for (int i = 0; i < rounds_n; i++) {
            int r = i < per * ncat ? i % per : -1; /* a starting candidate: the first round */
            if ((r < 0 && rounds_done == 0) || (r >= rounds_done && r < upto)) {
                in_round[m] = i;
                batch[m++] = c[i];
            }
        }
        evaluate_all(f, batch, m, f->o.coarse_size, 1);
        for (int j = 0; j < m; j++)
            c[in_round[j]] = batch[j];
        scored += m;
        rounds_done = upto;
        if ((f->o.budget > 0 && elapsed(f) >= 0.3 * f->o.budget) || (f->o.stop && *f->o.stop))
            break; /* a stop (Ctrl-C) at the end of a round, not of the screening */
    }
    free(batch);
    free(in_round);
    if (scored < n) { /* the rounds not scored leave, in order */
        int kept = 0;
        for (int i = 0; i < n; i++)
            if (i >= per * ncat || i % per < rounds_done)
                c[kept++] = c[i];
        n = kept;
    }
    /* the score's scale: each objective's median over the screened candidates */
    for (int o = 0; o < SQ_OBJ_COUNT; o++) {
        int m = 0;
        for (int i = 0; i < n; i++)
            if (isfinite(c[i].obj[o]))
                col[m++] = c[i].obj[o];
        qsort(col, (size_t)m, sizeof *col, cmp_double);
        double med = m ? col[m / 2] : 1;
        f->r->norm[o] = med > 1e-9 ? med : 1e-9;
    }
    free(col);
    for (int i = 0; i < CATEGORIES; i++)
        f->r->category_score[i] = INFINITY;
    for (int i = 0; i < n; i++) {
        score_of(f, &c[i]);
        int cat = sq_fit_kind_of(&c[i].params);
        f->r->category_score[cat] = fmin(f->r->category_score[cat], c[i].score);
    }
    qsort(c, (size_t)n, sizeof *c, cmp_score);
    note_best(f, c, n);
    if (archive_add(f, c, n) != 0) {
        free(c);
        return sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory");
    }
    *out = c;
    *nout = n;
    return SQ_OK;
}

/* ---- stage 2: niches ---- */

typedef struct Niche {
    int category;
    SqGenome g;
    SqCmaes *es;
    int n;                 /* genes + the view scale */
    SqFitCandidate best;   /* the niche's best by score (noisy) */
    SqFitCandidate recent; /* its best since it was last judged (score INFINITY: none) */
    SqFitCandidate *pool;  /* GP: the automata's parents, lambda of them */
    int npool, pool_cap;
    uint64_t gp_rng;
    double view_lo, view_hi; /* the view scale gene's range */
} Niche;

static void niche_free(Niche *z)
{
    sq_cmaes_free(z->es);
    free(z->pool);
}

/* Whether c is a screening candidate started from a spot lattice read (spot_candidates). */
static int read_lattice(const Fit *f, const SqFitCandidate *c)
{
    const SqParams *p = &c->params;
    if (p->Pattern_Type != SQ_PATTERN_SPOTS || p->Pattern_Layers.count != 0)
        return 0;
    for (int i = 0; i < f->nspot_read; i++)
        if (p->Spots_Tiling == f->spot_read[i].tiling && p->Spots_Offset == f->spot_read[i].offset &&
            c->view_scale == f->spot_read[i].view)
            return 1;
    return 0;
}

/* A spots niche starts from the best screened candidate of a lattice read, when there
 * is one (it starts with the palette's colours, and a random spots candidate may screen
 * better for its colours alone), and searches that lattice: its count round the body
 * held, its offset within a sixteenth, its spots within 0.2 of their places and its view
 * scale within 10%. Left free, the CMA-ES's mean leaves the lattice's narrow basin at
 * once (its neighbours score far worse, and it keeps no elite), for the scales' lattice
 * at another view scale. Returns 1 when it held one. */
static int hold_spot_lattice(const Fit *f, Niche *z, const SqFitCandidate *start)
{
    if (!read_lattice(f, start))
        return 0;
    const double nx = lround(10 * start->params.Spots_Tiling), o = start->params.Spots_Offset;
    for (int j = 0; j < z->g.n; j++) {
        SqGene *e = &z->g.genes[j];
        if (e->layer >= 0)
            continue;
        if (strcmp(e->spec->name, "Spots_Tiling") == 0) {
            e->lo = (nx - 0.45) / 10;
            e->hi = (nx + 0.45) / 10;
        } else if (strcmp(e->spec->name, "Spots_Offset") == 0) {
            e->lo = fmax(o - 1.0 / 16, 0);
            e->hi = fmin(o + 1.0 / 16, 1);
        } else if (strcmp(e->spec->name, "Spots_PositionRandom") == 0) {
            e->lo = 0;
            e->hi = 0.2;
        }
    }
    z->view_lo = start->view_scale / 1.1;
    z->view_hi = start->view_scale * 1.1;
    return 1;
}

/* A CMA-ES over n genes of the unit box from x0, for a noisy objective: a population of
 * lambda (0: a little larger than the default), IPOP restarts from anywhere in the box. */
static SqStatus noisy_cmaes(Fit *f, int n, const double *x0, const int *levels, int lambda, SqCmaes **es,
                            SqError *err)
{
    double lo[SQ_GENOME_MAX + 1], hi[SQ_GENOME_MAX + 1];
    for (int i = 0; i < n; i++) {
        lo[i] = 0;
        hi[i] = 1;
    }
    SqCmaesConfig c = sq_cmaes_config_default(n);
    c.x0 = x0;
    c.lower = lo;
    c.upper = hi;
    c.levels = levels;
    c.sigma0 = 0.15;
    c.lambda = lambda > 0 ? lambda : 4 + (int)floor(3 * log((double)n)) + 4; /* the default, and 4 for the noise */
    c.seed = sq__rng_next(&f->rng);
    c.init_lower = lo;
    c.init_upper = hi;
    c.restarts = 4;
    c.tolfun = 1e-4;
    c.tolx = 1e-4;
    return sq_cmaes_new(&c, es, err);
}

static SqStatus niche_init(Fit *f, Niche *z, int category, const SqFitCandidate *screened, int ns,
                           SqError *err)
{
    memset(z, 0, sizeof *z);
    z->category = category;
    const SqFitCandidate *start = NULL;
    if (category == SQ_PATTERN_SPOTS) /* a strong lattice read starts it, however coloured */
        for (int i = 0; i < ns && !start; i++)
            if (read_lattice(f, &screened[i]))
                start = &screened[i];
    for (int i = 0; i < ns && !start; i++)
        if (sq_fit_kind_of(&screened[i].params) == category)
            start = &screened[i];
    if (!start)
        return sq_error_set(err, SQ_ERR_INTERNAL, "fit", "no screened candidate of a niche");
    /* the layered niche searches the pair of its best screened candidate */
    SqStatus st = sq_genome_of(&z->g, &start->params, err);
    if (st != SQ_OK)
        return st;
    z->n = z->g.n + 1;
    z->best = *start;
    z->recent.score = INFINITY;
    z->view_lo = SQ__VIEW_LO;
    z->view_hi = SQ__VIEW_HI;
    if (category == SQ_PATTERN_SPOTS)
        f->r->spots_held = hold_spot_lattice(f, z, start);
    double x0[SQ_GENOME_MAX + 1];
    int levels[SQ_GENOME_MAX + 1];
    sq_genome_encode(&z->g, &start->params, x0);
    x0[z->g.n] = view_to_x_in(start->view_scale, z->view_lo, z->view_hi);
    sq_genome_levels(&z->g, levels);
    levels[z->g.n] = 0;
    st = noisy_cmaes(f, z->n, x0, levels, 0, &z->es, err);
    if (st != SQ_OK)
        return st;
    z->gp_rng = sq__rng_next(&f->rng);
    if (z->g.has_ca) {
        /* the automata of the best screened candidates of the category are the first parents */
        int l = sq_cmaes_lambda(z->es);
        z->pool = calloc((size_t)l, sizeof *z->pool);
        if (!z->pool)
            return sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory");
        z->pool_cap = l;
        for (int i = 0; i < ns && z->npool < l; i++)
            if (screened[i].params.Pattern_Type == SQ_PATTERN_OTHER_SIMPLE)
                z->pool[z->npool++] = screened[i];
    }
    return SQ_OK;
}

/* The share of an automata niche's children that keep its best automaton: the CMA-ES
 * then ranks its continuous genes (circle diameter, blur, contrast, colours, view scale)
 * against one automaton, not against a new one each time (with every child a GP child,
 * 84% of them through crossover or a mutation), and a good automaton read off the photo
 * is not moved away. In whole recovery fits (seeds 3 and 1) the automata photos came out
 * right 9 times of 12 against 5, the whole table 52 of 76 against 50 (docs/recovery.md,
 * sessions 17 and 20). */
static const double CA_KEEP = 0.7;

/* Child automata for a generation (sq_gp_ca_children). */
static void gp_children(Niche *z, SqFitCandidate *c, int l)
{
    int np = z->npool;
    int *rank = malloc(sizeof(int) * (size_t)np);
    double *crowd = malloc(sizeof(double) * (size_t)np), *obj = malloc(sizeof(double) * SQ_OBJ_COUNT * (size_t)np);
    SqCa *parents = malloc(sizeof *parents * (size_t)np), *child = malloc(sizeof *child * (size_t)l);
    if (rank && crowd && obj && parents && child) { /* else every child keeps the best automaton */
        for (int i = 0; i < np; i++) {
            memcpy(obj + (size_t)i * SQ_OBJ_COUNT, z->pool[i].obj, sizeof z->pool[i].obj);
            parents[i] = z->pool[i].params.CA_Descriptor;
        }
        if (sq_nsga2_rank(obj, np, SQ_OBJ_COUNT, rank) < 0)
            memset(rank, 0, sizeof(int) * (size_t)np);
        sq_nsga2_crowding(obj, np, SQ_OBJ_COUNT, rank, crowd);
        sq_gp_ca_children(&z->gp_rng, parents, np, rank, crowd, &z->best.params.CA_Descriptor, CA_KEEP, child, l);
        for (int k = 0; k < l; k++)
            c[k].params.CA_Descriptor = child[k];
    }
    free(rank);
    free(crowd);
    free(obj);
    free(parents);
    free(child);
}

/* The pool keeps the best lambda of parents and children (NSGA-II rank, then crowding). */
static void gp_survive(Niche *z, const SqFitCandidate *c, int l)
{
    int total = z->npool + l;
    SqFitCandidate *all = malloc(sizeof *all * (size_t)total);
    double *obj = malloc(sizeof(double) * SQ_OBJ_COUNT * (size_t)total);
    int *rank = malloc(sizeof(int) * (size_t)total), *order = malloc(sizeof(int) * (size_t)total);
    double *crowd = malloc(sizeof(double) * (size_t)total);
    if (all && obj && rank && order && crowd) {
        memcpy(all, z->pool, sizeof *all * (size_t)z->npool);
        memcpy(all + z->npool, c, sizeof *all * (size_t)l);
        for (int i = 0; i < total; i++)
            memcpy(obj + (size_t)i * SQ_OBJ_COUNT, all[i].obj, sizeof all[i].obj);
        if (sq_nsga2_rank(obj, total, SQ_OBJ_COUNT, rank) >= 0) {
            sq_nsga2_crowding(obj, total, SQ_OBJ_COUNT, rank, crowd);
            for (int i = 0; i < total; i++)
                order[i] = i;
            for (int i = 1; i < total; i++) { /* insertion sort: rank, then crowding */
                int v = order[i], j = i;
                while (j > 0 && (rank[order[j - 1]] > rank[v] ||
                                 (rank[order[j - 1]] == rank[v] && crowd[order[j - 1]] < crowd[v]))) {
                    order[j] = order[j - 1];
                    j--;
                }
                order[j] = v;
            }
            int keep = l < total ? l : total;
            for (int i = 0; i < keep; i++)
                z->pool[i] = all[order[i]];
            z->npool = keep;
        }
    }
    free(all);
    free(obj);
    free(rank);
    free(order);
    free(crowd);
}

/* One generation of a niche. Returns -1 when out of memory. */
static int niche_step(Fit *f, Niche *z)
{
    int l = sq_cmaes_lambda(z->es), n = z->n;
    const double *X = sq_cmaes_ask(z->es);
    SqFitCandidate *c = malloc(sizeof *c * (size_t)l);
    double *fv = malloc(sizeof(double) * (size_t)l), *obj = malloc(sizeof(double) * SQ_OBJ_COUNT * (size_t)l);
    int *rank = malloc(sizeof(int) * (size_t)l);
    if (!c || !fv || !obj || !rank) {
        free(c);
        free(fv);
        free(obj);
        free(rank);
        return -1;
    }
    int seed = (int)(sq__rng_next(&f->rng) & 0x7fffffff); /* common random numbers */
    for (int k = 0; k < l; k++) {
        c[k].params = z->best.params;
        sq_genome_decode(&z->g, X + (size_t)k * n, &c[k].params);
        c[k].params.Seed = seed;
        c[k].view_scale = x_to_view_in(X[(size_t)k * n + z->g.n], z->view_lo, z->view_hi);
    }
    if (z->g.has_ca) {
        if (z->pool_cap < l) { /* IPOP grew lambda: so does the pool */
            SqFitCandidate *p = realloc(z->pool, sizeof *p * (size_t)l);
            if (!p) {
                free(c);
                free(fv);
                free(obj);
                free(rank);
                return -1;
            }
            z->pool = p;
            z->pool_cap = l;
        }
        gp_children(z, c, l);
    }
    evaluate_all(f, c, l, f->o.coarse_size, 0);
    for (int k = 0; k < l; k++) {
        score_of(f, &c[k]);
        memcpy(obj + (size_t)k * SQ_OBJ_COUNT, c[k].obj, sizeof c[k].obj);
    }
    if (sq_nsga2_rank(obj, l, SQ_OBJ_COUNT, rank) < 0)
        memset(rank, 0, sizeof(int) * (size_t)l);
    /* CMA-ES sees the Pareto rank first and the score within a front */
    for (int k = 0; k < l; k++)
        fv[k] = isfinite(c[k].score) ? rank[k] + c[k].score / (1 + c[k].score) : NAN;
    sq_cmaes_tell(z->es, fv);
    if (z->g.has_ca)
        gp_survive(z, c, l);
    for (int k = 0; k < l; k++) {
        if (c[k].score < z->best.score)
            z->best = c[k];
        if (c[k].score < z->recent.score)
            z->recent = c[k];
    }
    note_best(f, c, l);
    int st = archive_add(f, c, l);
    free(c);
    free(fv);
    free(obj);
    free(rank);
    return st;
}

/* ---- stage 3: re-scoring and the polish ---- */

/* Each candidate's objectives replaced by their mean over `seeds` pattern seeds (k *
 * seed_step, the same for everyone) at size x size, and its score with them. */
static void rescore_over(Fit *f, SqFitCandidate *c, int n, int seeds, int size, int seed_step)
{
    const int R = seeds > 0 ? seeds : 1;
    SqFitCandidate *t = malloc(sizeof *t * (size_t)n * (size_t)R);
    if (!t) { /* out of memory: keep the noisy values */
        return;
    }
    for (int i = 0; i < n; i++)
        for (int s = 0; s < R; s++) {
            t[i * R + s] = c[i];
            t[i * R + s].params.Seed = seed_step * (s + 1);
        }
    evaluate_all(f, t, n * R, size, 0);
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < SQ_OBJ_COUNT; k++) {
            double m = 0;
            for (int s = 0; s < R; s++)
                m += t[i * R + s].obj[k];
            c[i].obj[k] = m / R;
        }
        c[i].params.Seed = t[i * R].params.Seed;
        score_of(f, &c[i]);
    }
    free(t);
}

/* Drops the finalists met before (a niche's best is often in the archive too): the front
 * would show it twice and the re-scoring pay for it twice. Keeps the order. */
static int unique(SqFitCandidate *c, int n)
{
    int k = 0;
    for (int i = 0; i < n; i++) {
        int seen = 0;
        for (int j = 0; j < k && !seen; j++)
            seen = c[j].view_scale == c[i].view_scale && memcmp(&c[j].params, &c[i].params, sizeof c[i].params) == 0;
        if (!seen)
            c[k++] = c[i];
    }
    return k;
}

/* Rounds of n renders on the fit's threads. */
static double rounds(const Fit *f, int n)
{
    return ceil((double)n / f->threads);
}

/* What a time budget keeps back for what follows the polish, at `per` seconds a round of
 * fine renders on every thread (the re-scoring's pace): the polish's re-score and the
 * plain twin's, and the kinds' recolouring: a render, SQ_RECOLOUR_WAYS renders and a
 * re-score for each kind's best (recolour_kinds), counted for every kind fitted and the
 * layered skin the layer over the champion makes. So the whole fit ends within its budget,
 * not that much after it. */
static double tail_seconds(const Fit *f, double per)
{
    const int kinds = ncategories(&f->o) + !fitted(&f->o, SQ_FIT_LAYERED);
    return per * (2 * rounds(f, f->o.reseeds) + rounds(f, kinds) + rounds(f, kinds * SQ_RECOLOUR_WAYS) +
                  rounds(f, kinds * f->o.reseeds));
}

/* The finalists: over `reseeds` seeds at the fine size. */
static void rescore(Fit *f, SqFitCandidate *c, int n)
{
    rescore_over(f, c, n, f->o.reseeds, f->o.fine_size, 7919);
}

/* How simple an explanation a kind is: a plain skin, then stripes or bands, then spots,
 * then an automaton (which can imitate the others), then two patterns layered, then
 * reaction-diffusion. */
static int simplicity(int category)
{
    switch (category) {
    case SQ_PATTERN_NONE: return 0;
    case SQ_PATTERN_LONGITUDINAL:
    case SQ_PATTERN_TRANSVERSAL: return 1;
    case SQ_PATTERN_SPOTS: return 2;
    case SQ_PATTERN_OTHER_SIMPLE: return 3;
    case SQ_FIT_LAYERED: return 4;
    default: return 5;
    }
}

int sq_fit_pick_kind(const double score[SQ_FIT_KINDS], int layer_lead)
{
    double low = INFINITY;
    for (int k = 0; k < SQ_FIT_KINDS; k++)
        if (!(layer_lead && k == SQ_FIT_LAYERED) && score[k] < low)
            low = score[k];
    int pick = -1;
    for (int k = 0; k < SQ_FIT_KINDS; k++) {
        const double margin = k == SQ_PATTERN_NONE ? PLAIN_PARSIMONY : PARSIMONY;
        if ((layer_lead && k == SQ_FIT_LAYERED) || !(score[k] < INFINITY) || !(score[k] <= (1 + margin) * low))
            continue;
        if (pick < 0 || simplicity(k) < simplicity(pick) ||
            (simplicity(k) == simplicity(pick) && score[k] < score[pick]))
            pick = k;
    }
    const double l = score[SQ_FIT_LAYERED];
    if (layer_lead && l < INFINITY && (pick < 0 || l * (1 + LAYER_LEAD) < score[pick]))
        pick = SQ_FIT_LAYERED;
    return pick;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The share of a's band texels more than VISIBLE_DE from the same texel of b (a render of
 * the same size), or from lab when b is NULL. */
static double band_share_apart(const SqImage *a, const SqImage *b, const double lab[3], double band_centre)
{
    const int w = a->width, h = a->height;
    const int x0 = (int)floor((band_centre - SQ_FIT_BAND_WIDTH / 2) * w);
    const int nx = (int)ceil(SQ_FIT_BAND_WIDTH * w);
    size_t seen = 0;
    for (int y = 0; y < h; y++)
        for (int i = 0; i < nx; i++) {
            const size_t x = (size_t)(((x0 + i) % w + w) % w);
            float la[3], lb[3] = {0};
            sq_fit_srgb_to_lab(a->px + ((size_t)y * w + x) * a->channels, la);
            if (b)
                sq_fit_srgb_to_lab(b->px + ((size_t)y * w + x) * b->channels, lb);
            const double da[3] = {la[0], la[1], la[2]}, db[3] = {lb[0], lb[1], lb[2]};
            seen += sq_fit_ciede2000(da, b ? db : lab) > VISIBLE_DE;
        }
    return (double)seen / ((double)nx * (double)h);
}

/* The visibility of one base colour map's band and its dominant (per-channel median) colour. */
static double band_visibility(const SqImage *im, double band_centre, double dominant[3])
{
    const int w = im->width, h = im->height, ch = im->channels;
    const int x0 = (int)floor((band_centre - SQ_FIT_BAND_WIDTH / 2) * w);
    const int nx = (int)ceil(SQ_FIT_BAND_WIDTH * w);
    const size_t n = (size_t)nx * (size_t)h;
    float *v = malloc(sizeof(float) * n);
    if (!v)
        return -1;
    float med[3];
    for (int c = 0; c < 3; c++) {
        size_t k = 0;
        for (int y = 0; y < h; y++)
            for (int i = 0; i < nx; i++) {
                int x = ((x0 + i) % w + w) % w;
                v[k++] = im->px[((size_t)y * w + x) * ch + c];
            }
        qsort(v, n, sizeof *v, cmp_float);
        med[c] = v[n / 2];
        dominant[c] = med[c];
    }
    free(v);
    float lm[3];
    sq_fit_srgb_to_lab(med, lm);
    const double m[3] = {lm[0], lm[1], lm[2]};
    return band_share_apart(im, NULL, m, band_centre);
}

double sq_fit_layer_visibility(const SqParams *p, int size, double band_centre, SqError *err)
{
    SqParams base = *p;
    base.Pattern_Layers.count = 0;
    SqGenOptions go = sq_gen_options_default(size);
    go.threads = 1;
    SqTextures tp = {0}, tb = {0};
    double v = -1;
    if (sq_gen_render(p, &go, &tp, err) == SQ_OK && sq_gen_render(&base, &go, &tb, err) == SQ_OK)
        v = band_share_apart(&tp.basecolor, &tb.basecolor, NULL, band_centre);
    sq_gen_textures_free(&tp);
    sq_gen_textures_free(&tb);
    return v;
}

double sq_fit_pattern_visibility(const SqParams *p, int size, double band_centre, double dominant[3],
                                 SqError *err)
{
    SqParams plain = *p;
    plain.Pattern_Type = SQ_PATTERN_NONE;
    plain.Pattern_Layers.count = 0;
    SqGenOptions go = sq_gen_options_default(size);
    go.threads = 1;
    SqTextures tp = {0}, tq = {0};
    double vp = -1, vq = -1, dq[3];
    if (sq_gen_render(p, &go, &tp, err) == SQ_OK && sq_gen_render(&plain, &go, &tq, err) == SQ_OK) {
        vp = band_visibility(&tp.basecolor, band_centre, dominant);
        vq = band_visibility(&tq.basecolor, band_centre, dq);
        if (vp < 0 || vq < 0)
            sq_error_set(err, SQ_ERR_NOMEM, "visibility", "out of memory");
    }
    sq_gen_textures_free(&tp);
    sq_gen_textures_free(&tq);
    if (vp < 0 || vq < 0)
        return -1;
    return vp - vq > 0 ? vp - vq : 0;
}

/* c's plain twin: no pattern, no layers, the background c's dominant colour (dom). */
static SqFitCandidate twin_of(const SqFitCandidate *c, const double dom[3])
{
    SqFitCandidate twin = *c;
    twin.params.Pattern_Type = SQ_PATTERN_NONE;
    twin.params.Pattern_Layers.count = 0;
    for (int k = 0; k < 3; k++)
        twin.params.Background_Color[k] = dom[k];
    twin.params.Background_Color[3] = 1;
    return twin;
}

/* A plain skin that leads by PLAIN_PARSIMONY over a pattern scoring better comes from a
 * niche searched less than the pattern's (often dropped early): its scales, view scale and
 * light can be far rougher (a plain photo's plain skin with scales stretched four times
 * along, where the bands that beat it had them right). The best pattern's plain twin keeps
 * the pattern's scales, view scale and light: it leads instead when it scores better. */
static void plain_of_the_best_pattern(Fit *f)
{
    SqFitResult *r = f->r;
    if (sq_fit_kind_of(&r->best.params) != SQ_PATTERN_NONE)
        return;
    const SqFitCandidate *p = NULL;
    for (int i = 1; i < r->nfront; i++)
        if (sq_fit_kind_of(&r->front[i].params) != SQ_PATTERN_NONE && (!p || r->front[i].score < p->score))
            p = &r->front[i];
    double dom[3];
    if (!p || !(p->score < r->best.score) ||
        sq_fit_pattern_visibility(&p->params, f->o.fine_size, f->o.band_centre, dom, NULL) < 0)
        return;
    SqFitCandidate twin = twin_of(p, dom);
    rescore(f, &twin, 1);
    if (!(twin.score < r->best.score))
        return;
    r->front[0] = r->best = twin;
    r->plain_of_pattern = 1;
}

/* A champion whose pattern nobody can see is a plain skin: it becomes its plain twin,
 * re-scored, and leads the front with the invisible original behind it, when the twin
 * scores within PARSIMONY of it. A twin that scores worse shows that the objectives see
 * what the eye test does not (a pattern of small differences all over the skin): the
 * pattern stays. */
static void plain_twin(Fit *f)
{
    SqFitResult *r = f->r;
    SqFitCandidate *b = &r->best;
    r->visibility = 0;
    r->twin_score = 0;
    if (b->params.Pattern_Type == SQ_PATTERN_NONE && b->params.Pattern_Layers.count == 0)
        return;
    double dom[3];
    r->visibility = sq_fit_pattern_visibility(&b->params, f->o.fine_size, f->o.band_centre, dom, NULL);
    if (r->visibility < 0 || r->visibility >= VISIBLE_MIN)
        return;
    SqFitCandidate twin = twin_of(b, dom);
    rescore(f, &twin, 1);
    if (!isfinite(twin.score)) /* a twin that cannot be rendered: nothing to report */
        return;
    r->twin_score = twin.score;
    if (twin.score > (1 + PARSIMONY) * b->score)
        return;
    SqFitCandidate *grown = realloc(r->front, sizeof *grown * (size_t)(r->nfront + 1)); /* room for it */
    if (!grown)
        return;
    r->front = grown;
    int k = r->nfront < f->o.front_max ? r->nfront : r->nfront - 1;
    memmove(r->front + 1, r->front, sizeof *r->front * (size_t)k);
    r->front[0] = twin;
    r->nfront = k + 1;
    r->best = twin;
    r->plain_twin = 1;
}

/* The niche to drop: the worst by the better of its best candidate and its best of the
 * round, both re-scored over JUDGE_SEEDS fresh seeds (a niche's best single score is the
 * luckiest of many noisy draws, and random patterns draw far luckier minima than plain
 * skins and stripes do; a best from the screening, at the best view scale of a grid, is
 * luckier still and can stand for rounds while the niche's search moves on); but of the niches
 * within PARSIMONY of the worst, the least simple goes, as the final choice keeps the
 * simplest within PARSIMONY of the best. *judged_worst receives the judged score of the
 * niche returned. Every niche's best of the round starts again. */
enum { JUDGE_SEEDS = 3 };

static int worst_niche(Fit *f, Niche *niches, const int *alive, int nn, double *judged_worst)
{
    SqFitCandidate c[2 * CATEGORIES];
    int idx[CATEGORIES], from[2 * CATEGORIES], m = 0, k = 0;
    for (int i = 0; i < nn; i++)
        if (alive[i]) {
            from[k] = m;
            c[k++] = niches[i].best;
            if (isfinite(niches[i].recent.score)) {
                from[k] = m;
                c[k++] = niches[i].recent;
            }
            niches[i].recent.score = INFINITY; /* the next round's */
            idx[m++] = i;
        }
    rescore_over(f, c, k, JUDGE_SEEDS, f->o.coarse_size, 104729);
    double judged[CATEGORIES], worst_score = -INFINITY;
    for (int j = 0; j < m; j++)
        judged[j] = INFINITY;
    for (int i = 0; i < k; i++)
        judged[from[i]] = fmin(judged[from[i]], c[i].score);
    for (int j = 0; j < m; j++)
        worst_score = fmax(worst_score, judged[j]);
    int worst = -1;
    for (int j = 0; j < m; j++) {
        if (!(judged[j] * (1 + PARSIMONY) >= worst_score))
            continue;
        if (worst < 0) {
            worst = j;
            continue;
        }
        int sj = simplicity(niches[idx[j]].category), sw = simplicity(niches[idx[worst]].category);
        if (sj > sw || (sj == sw && judged[j] > judged[worst]))
            worst = j;
    }
    if (worst < 0)
        worst = 0;
    *judged_worst = judged[worst];
    return idx[worst];
}

typedef struct Polish {
    Fit *f;
    const SqGenome *g;
    SqFitCandidate base;
    int idx[SQ_GENOME_MAX + 1]; /* the continuous genes polished, g->n = the view scale */
    int n;
    double x[SQ_GENOME_MAX + 1];
    nlopt_opt opt;
    double best;
} Polish;

static void polish_candidate(const Polish *p, const double *y, SqFitCandidate *c)
{
    double x[SQ_GENOME_MAX + 1];
    memcpy(x, p->x, sizeof x);
    for (int i = 0; i < p->n; i++)
        x[p->idx[i]] = y[i];
    *c = p->base;
    sq_genome_decode(p->g, x, &c->params);
    c->view_scale = x_to_view(x[p->g->n]);
}

static double polish_objective(unsigned n, const double *y, double *grad, void *data)
{
    (void)n;
    (void)grad;
    Polish *p = data;
    Fit *f = p->f;
    if (out_of_budget(f, 1.0))
        nlopt_force_stop(p->opt);
    SqFitCandidate c;
    polish_candidate(p, y, &c);
    /* one fixed seed (common random numbers) and the generator's own threads */
    evaluate(f, &c, f->o.fine_size, f->threads, &f->maps[0]);
    score_of(f, &c);
    f->evals++;
    if (!isfinite(c.score))
        return HUGE_VAL;
    return c.score;
}

/* Polishes the champion's continuous genes with SBPLX; keeps the result only when its
 * re-scored score is lower. */
static void polish(Fit *f, SqFitCandidate *champ)
{
    SqGenome g;
    if (sq_genome_of(&g, &champ->params, NULL) != SQ_OK)
        return;
    Polish p = {.f = f, .g = &g, .base = *champ};
    sq_genome_encode(&g, &champ->params, p.x);
    p.x[g.n] = view_to_x(champ->view_scale);
    for (int i = 0; i < g.n; i++)
        if (!g.genes[i].levels)
            p.idx[p.n++] = i;
    p.idx[p.n++] = g.n;
    double y[SQ_GENOME_MAX + 1], lo[SQ_GENOME_MAX + 1], hi[SQ_GENOME_MAX + 1];
    for (int i = 0; i < p.n; i++) {
        y[i] = p.x[p.idx[i]];
        lo[i] = 0;
        hi[i] = 1;
    }
    /* an evaluation budget: what the re-scoring left, less the final re-score and the plain
     * twin's (plain_twin) */
    long evals = f->o.max_evals > 0 ? f->o.max_evals - f->evals - 2L * f->o.reseeds : 100000;
    if (evals < 10)
        return;
    p.opt = nlopt_create(NLOPT_LN_SBPLX, (unsigned)p.n);
    if (!p.opt)
        return;
    nlopt_set_lower_bounds(p.opt, lo);
    nlopt_set_upper_bounds(p.opt, hi);
    nlopt_set_min_objective(p.opt, polish_objective, &p);
    nlopt_set_initial_step1(p.opt, 0.03);
    nlopt_set_xtol_abs1(p.opt, 1e-3);
    nlopt_set_maxeval(p.opt, (int)evals);
    if (f->o.budget > 0) {
        double left = f->o.budget - f->tail_s - elapsed(f);
        nlopt_set_maxtime(p.opt, left > 0.1 ? left : 0.1);
    }
    double minf = HUGE_VAL;
    nlopt_optimize(p.opt, y, &minf); /* any result: y holds the best point nlopt saw */
    nlopt_destroy(p.opt);
    SqFitCandidate c;
    polish_candidate(&p, y, &c);
    rescore(f, &c, 1);
    f->r->polish_before = champ->score;
    f->r->polish_after = c.score;
    if (c.score < champ->score) {
        *champ = c;
        f->r->polish_kept = 1;
    }
}

/* ---- a layer over the champion ---- */

/* When layered skins are asked for, the layered niche searches a pair drawn at random
 * while screening, and a layered photo was often fitted as one of its parts: its base
 * alone, or an automaton imitating both. So a stripe, band or spot champion is given
 * one layer of another type with the champion itself held: the patterns of the other
 * types' finalists and of their LAYER_STARTS best screened candidates are tried as its
 * layer, and a CMA-ES moves the best one's layer genes and the view scale (within
 * LAYER_VIEW) for LAYER_SHARE of the evaluations the re-scoring left (the polish has the
 * rest). An automaton champion is not a base (an automaton with a layer's freedom beat
 * the automaton of its own photo by 41%): the best stripe, band or spot finalist is
 * layered instead. The layered skin leads, re-scored, when it beats the champion by
 * LAYER_LEAD (a layer's extra freedom gains a single pattern up to 19%: docs/recovery.md,
 * session 22) and its layer shows: it changes LAYER_VISIBLE of the band, as a layered
 * preset of squama seed must (a spots photo was lost to spots under a stripes layer at
 * opacity 0.51 that nobody could see: session 23). By default, and when layered skins are
 * asked for. */
/* LAYER_LAMBDA: a small population, for many generations in a few hundred evaluations: on
 * row 37 of the recovery benchmark (seed 1) it found bands under spots at 1.52 against the
 * bands' 1.99, where the niches' population (17 here) ended at 1.99 (session 23). */
enum { LAYER_STARTS = 8, LAYER_LAMBDA = 4 };
/* c, re-scored, as its kind's best when it scores better than the best so far. */
static void keep_kind_best(SqFitResult *r, const SqFitCandidate *c)
{
    const int kind = sq_fit_kind_of(&c->params);
    if (c->score < r->kind_best[kind].score) {
        r->kind_best[kind] = *c;
        r->category_score[kind] = c->score;
    }
}

static const double LAYER_SHARE = 0.5, LAYER_VIEW = 1.05, LAYER_VISIBLE = 0.05;

/* c with src's pattern as its one layer, blended normally at full opacity. */
static SqFitCandidate layered_over(const SqFitCandidate *c, const SqFitCandidate *src)
{
    SqFitCandidate t = *c;
    SqPatternLayer *l = &t.params.Pattern_Layers.layer[0];
    sq_pattern_layer_default(l);
    l->spec = src->params.pattern;
    t.params.Pattern_Layers.count = 1;
    return t;
}

/* Whether the layer stage may use another evaluation generation of n: within its share of
 * the evaluations (end) and of the time (deadline, seconds since the start). */
static int layer_room(const Fit *f, long end, double deadline, int n)
{
    if (f->o.stop && *f->o.stop)
        return 0;
    if (f->o.max_evals > 0 && f->evals + n > end)
        return 0;
    return !(f->o.budget > 0 && elapsed(f) >= deadline);
}

/* Whether a kind can be the base of the layer search: stripes, bands or spots. */
static int layer_base(int kind)
{
    return kind == SQ_PATTERN_LONGITUDINAL || kind == SQ_PATTERN_TRANSVERSAL || kind == SQ_PATTERN_SPOTS;
}

static void layer_search(Fit *f, const SqFitCandidate *fin, int nfin, const SqFitCandidate *screened, int ns)
{
    SqFitResult *r = f->r;
    const SqFitCandidate champ = r->best;
    const int ck = sq_fit_kind_of(&champ.params);
    const SqFitCandidate *under = NULL; /* the base */
    if (layer_base(ck))
        under = &champ;
    else if (ck == SQ_PATTERN_OTHER_SIMPLE) /* an automaton imitates the others, and under a layer both */
        for (int i = 0; i < nfin; i++)
            if (layer_base(sq_fit_kind_of(&fin[i].params)) && isfinite(fin[i].score) &&
                (!under || fin[i].score < under->score))
                under = &fin[i];
    if (!under)
        return;
    const int base = under->params.Pattern_Type;
    const long left = f->o.max_evals > 0 ? f->o.max_evals - f->evals - 2L * f->o.reseeds : 0;
    const long end = f->evals + (long)(LAYER_SHARE * (double)left);
    const double deadline = elapsed(f) + LAYER_SHARE * (f->o.budget - f->tail_s - elapsed(f));
    SqFitCandidate *c = malloc(sizeof *c * (size_t)(nfin + ns));
    if (!c)
        return;
    int m = 0;
    for (int t = 0; t < SQ_PATTERN_COUNT; t++) {
        if (!sq_genome_layerable(base, t))
            continue;
        for (int i = 0; i < nfin; i++)
            if (sq_fit_kind_of(&fin[i].params) == t)
                c[m++] = layered_over(under, &fin[i]);
        for (int i = 0, k = 0; i < ns && k < LAYER_STARTS; i++) /* screened is sorted by score */
            if (sq_fit_kind_of(&screened[i].params) == t) {
                c[m++] = layered_over(under, &screened[i]);
                k++;
            }
    }
    const long e0 = f->evals;
    if (m == 0 || !layer_room(f, end, deadline, m)) {
        free(c);
        return;
    }
    for (int i = 0; i < m; i++)
        c[i].params.Seed = 1;
    evaluate_all(f, c, m, f->o.coarse_size, 0);
    int b = 0;
    for (int i = 0; i < m; i++) {
        score_of(f, &c[i]);
        if (c[i].score < c[b].score)
            b = i;
    }
    SqFitCandidate best = c[b];
    free(c);
    SqGenome g;
    int idx[SQ_GENOME_MAX + 1], levels[SQ_GENOME_MAX + 1], n = 0;
    double x[SQ_GENOME_MAX + 1], x0[SQ_GENOME_MAX + 1];
    SqCmaes *es = NULL;
    if (isfinite(best.score) && sq_genome_of(&g, &best.params, NULL) == SQ_OK) {
        /* the layer's genes and the view scale; the base's are held */
        const double vlo = under->view_scale / LAYER_VIEW, vhi = under->view_scale * LAYER_VIEW;
        sq_genome_encode(&g, &best.params, x);
        for (int i = 0; i < g.n; i++)
            if (g.genes[i].layer >= 0) {
                idx[n] = i;
                levels[n] = g.genes[i].levels;
                x0[n++] = x[i];
            }
        idx[n] = g.n;
        levels[n] = 0;
        x0[n++] = view_to_x_in(best.view_scale, vlo, vhi);
        if (noisy_cmaes(f, n, x0, levels, LAYER_LAMBDA, &es, NULL) != SQ_OK)
            es = NULL;
        while (es && layer_room(f, end, deadline, sq_cmaes_lambda(es))) {
            const int l = sq_cmaes_lambda(es);
            const double *X = sq_cmaes_ask(es);
            SqFitCandidate *k = malloc(sizeof *k * (size_t)l);
            double *fv = malloc(sizeof(double) * (size_t)l);
            if (!k || !fv) {
                free(k);
                free(fv);
                break;
            }
            const int seed = (int)(sq__rng_next(&f->rng) & 0x7fffffff); /* common random numbers */
            for (int j = 0; j < l; j++) {
                SqParams p = best.params;
                for (int i = 0; i + 1 < n; i++)
                    x[idx[i]] = X[(size_t)j * n + i];
                sq_genome_decode(&g, x, &p);
                k[j] = *under; /* the base exactly as it was: only the layer is taken */
                k[j].params.Pattern_Layers = p.Pattern_Layers;
                k[j].params.Seed = seed;
                k[j].view_scale = x_to_view_in(X[(size_t)j * n + n - 1], vlo, vhi);
            }
            evaluate_all(f, k, l, f->o.coarse_size, 0);
            for (int j = 0; j < l; j++) {
                score_of(f, &k[j]);
                fv[j] = isfinite(k[j].score) ? k[j].score : NAN;
                if (k[j].score < best.score)
                    best = k[j];
            }
            sq_cmaes_tell(es, fv);
            note_best(f, k, l);
            free(k);
            free(fv);
            f->generation++;
            report(f, "layer", SQ_FIT_LAYERED);
        }
        sq_cmaes_free(es);
    }
    rescore(f, &best, 1);
    r->layer_searched = 1;
    r->layer_visibility = -1;
    r->layer_evals = f->evals - e0;
    r->layer_score = best.score;
    r->layer_under = champ.score;
    r->layer_base = base;
    r->layer_kind = best.params.Pattern_Layers.layer[0].spec.Pattern_Type;
    keep_kind_best(r, &best);
    r->layer_best_searched = r->kind_best[SQ_FIT_LAYERED].score == best.score;
    if (!(best.score * (1 + LAYER_LEAD) < champ.score))
        return;
    r->layer_visibility = sq_fit_layer_visibility(&best.params, f->o.fine_size, f->o.band_centre, NULL);
    if (!(r->layer_visibility >= LAYER_VISIBLE))
        return;
    SqFitCandidate *grown = realloc(r->front, sizeof *grown * (size_t)(r->nfront + 1));
    if (!grown)
        return;
    r->front = grown;
    memmove(r->front + 1, r->front, sizeof *r->front * (size_t)r->nfront);
    r->nfront = r->nfront + 1 < f->o.front_max ? r->nfront + 1 : f->o.front_max;
    r->front[0] = r->best = best;
    r->layer_lead = 1;
}

/* ---- baselines: one optimiser on the scalar score of the best category ---- */

typedef struct Baseline {
    Fit *f;
    const SqGenome *g;
    SqFitCandidate base, best;
    nlopt_opt opt;
    long left;
    int seed;
    double t0; /* when its search began, and the evaluations then: its pace */
    long evals0;
    int over; /* 1: stopped (nlopt's CRS2 asks on through its first population regardless) */
} Baseline;

/* A baseline reports its progress (the history, the progress bar) every this many
 * evaluations, a generation each. */
enum { BASELINE_GENERATION = 50 };

/* c, a baseline's candidate just scored, counted: the best kept, a generation reported
 * every BASELINE_GENERATION evaluations. */
static void baseline_scored(Baseline *b, const SqFitCandidate *c)
{
    Fit *f = b->f;
    f->evals++;
    b->left--;
    note_best(f, c, 1);
    if (c->score < b->best.score)
        b->best = *c;
    if (f->evals % BASELINE_GENERATION == 0) {
        f->generation++;
        report(f, "evolve", sq_fit_kind_of(&b->base.params));
    }
}

/* 1 when a baseline must stop: the caller's flag, its evaluations, or a time budget at
 * BASELINE_END or where what follows would overrun it (tail_seconds: its finalist's
 * re-scoring standing for the polish's, the plain twin's, the kinds' recolouring), at the
 * pace of its own coarse renders, one thread each (a round of fine renders on every
 * thread costs (fine / coarse)^2 of one). */
static int baseline_over(const Baseline *b)
{
    const Fit *f = b->f;
    if (b->left <= 0 || out_of_time(f, BASELINE_END))
        return 1;
    const long n = f->evals - b->evals0;
    if (f->o.budget <= 0 || n < 1)
        return 0;
    const double ratio = (double)f->o.fine_size / f->o.coarse_size;
    const double per = (now() - b->t0) / (double)n * ratio * ratio;
    return elapsed(f) + tail_seconds(f, per) >= f->o.budget;
}

static double baseline_objective(unsigned n, const double *x, double *grad, void *data)
{
    (void)n;
    (void)grad;
    Baseline *b = data;
    if (b->over)
        return 1e30;
    SqFitCandidate c = b->base;
    sq_genome_decode(b->g, x, &c.params);
    c.view_scale = x_to_view(x[b->g->n]);
    c.params.Seed = b->seed;
    /* nlopt's optimisers move the continuous genes only: the automaton stays the screened one */
    evaluate(b->f, &c, b->f->o.coarse_size, 1, &b->f->maps[0]);
    score_of(b->f, &c);
    baseline_scored(b, &c);
    if (baseline_over(b)) {
        b->over = 1;
        nlopt_force_stop(b->opt);
    }
    return isfinite(c.score) ? c.score : 1e30;
}

static void run_baseline(Fit *f, const SqFitCandidate *start, SqFitCandidate *out)
{
    SqGenome g;
    *out = *start;
    if (sq_genome_of(&g, &start->params, NULL) != SQ_OK)
        return;
    int n = g.n + 1;
    Baseline b = {.f = f, .g = &g, .base = *start, .best = *start, .seed = start->params.Seed, .t0 = now(),
                  .evals0 = f->evals};
    long total = f->o.max_evals > 0 ? f->o.max_evals - f->evals - f->o.reseeds : 1000000;
    b.left = total > 1 ? total : 1;
    double x[SQ_GENOME_MAX + 1];
    sq_genome_encode(&g, &start->params, x);
    x[g.n] = view_to_x(start->view_scale);
    if (f->o.method == SQ_FIT_RANDOM) {
        while (!baseline_over(&b)) {
            for (int i = 0; i < n; i++)
                x[i] = sq__rng_uniform(&f->rng);
            b.opt = NULL;
            SqFitCandidate c = b.base;
            sq_genome_decode(&g, x, &c.params);
            c.view_scale = x_to_view(x[g.n]);
            if (g.has_ca) {
                uint64_t s = sq__rng_next(&f->rng);
                sq_gp_ca_random(&s, &c.params.CA_Descriptor);
            }
            evaluate(f, &c, f->o.coarse_size, 1, &f->maps[0]);
            score_of(f, &c);
            baseline_scored(&b, &c);
        }
    } else {
        nlopt_algorithm alg = f->o.method == SQ_FIT_ESCH ? NLOPT_GN_ESCH
                              : f->o.method == SQ_FIT_CRS2 ? NLOPT_GN_CRS2_LM
                                                          : NLOPT_GN_ISRES;
        b.opt = nlopt_create(alg, (unsigned)n);
        if (!b.opt)
            return;
        double lo[SQ_GENOME_MAX + 1], hi[SQ_GENOME_MAX + 1];
        for (int i = 0; i < n; i++) {
            lo[i] = 0;
            hi[i] = 1;
        }
        nlopt_set_lower_bounds(b.opt, lo);
        nlopt_set_upper_bounds(b.opt, hi);
        nlopt_set_min_objective(b.opt, baseline_objective, &b);
        nlopt_set_maxeval(b.opt, (int)(b.left < 100000000 ? b.left : 100000000));
        nlopt_srand(sq__rng_next(&f->rng)); /* nlopt's generator is global */
        double minf;
        nlopt_optimize(b.opt, x, &minf);
        nlopt_destroy(b.opt);
    }
    *out = b.best;
}

/* ---- the driver ---- */

static void palette_of(Fit *f)
{
    f->npal = 0;
    for (int k = 0; k < SQ_FIT_PALETTE; k++) {
        if (f->target->palette_w[k] <= 0.02f)
            continue;
        sq_fit_lab_to_srgb(f->target->palette[k], f->pal[f->npal]);
        f->npal++;
    }
}

static SqStatus check_options(const SqFitOptions *o, SqError *err)
{
    if (!(o->budget >= 0) || !isfinite(o->budget))
        return sq_error_set(err, SQ_ERR_INVALID, "fit", "the time budget must be a number of seconds >= 0");
    if (o->max_evals < 0 || (o->budget == 0 && o->max_evals == 0))
        return sq_error_set(err, SQ_ERR_INVALID, "fit", "give a time budget or an evaluation budget");
    if (o->coarse_size < 32 || o->fine_size < 32 || o->coarse_size > 2048 || o->fine_size > 2048)
        return sq_error_set(err, SQ_ERR_INVALID, "fit", "render sizes must be 32 to 2048 pixels");
    if (o->screen < 2 || o->screen > 10000 || o->niches < 1 || o->niches > CATEGORIES ||
        o->reseeds < 1 || o->reseeds > 64 || o->front_max < 1)
        return sq_error_set(err, SQ_ERR_INVALID, "fit",
                            "screen (2..10000), niches (1..%d), reseeds (1..64) and front_max (>= 1) "
                            "are out of range",
                            (int)CATEGORIES);
    if ((o->categories >> CATEGORIES) != 0)
        return sq_error_set(err, SQ_ERR_INVALID, "fit", "the categories name a kind beyond the %d there are",
                            (int)CATEGORIES);
    if (o->nseeds < 0 || (o->nseeds > 0 && !o->seeds))
        return sq_error_set(err, SQ_ERR_INVALID, "fit", "seed candidates missing");
    for (int i = 0; i < o->nseeds; i++) {
        SqStatus st = sq_params_validate(&o->seeds[i].params, err);
        if (st != SQ_OK)
            return st;
        SqGenome g;
        if (sq_genome_of(&g, &o->seeds[i].params, err) != SQ_OK)
            return sq_error_set(err, SQ_ERR_INVALID, "fit", "a starting preset cannot be searched: %s",
                                err ? err->what : "");
        int t = sq_fit_kind_of(&o->seeds[i].params);
        if (!fitted(o, t))
            return sq_error_set(err, SQ_ERR_INVALID, "fit",
                                "a starting preset is of the kind \"%s\", which this fit leaves out",
                                sq_fit_kind_name(t));
    }
    if (o->nstarts < 0 || (o->nstarts > 0 && !o->starts))
        return sq_error_set(err, SQ_ERR_INVALID, "fit", "starting presets missing");
    for (int i = 0; i < o->nstarts; i++) {
        SqGenome g;
        SqError e;
        if (sq_params_validate(&o->starts[i], &e) != SQ_OK || sq_genome_of(&g, &o->starts[i], &e) != SQ_OK)
            return sq_error_set(err, SQ_ERR_INVALID, "fit", "starting preset %d cannot be searched: %s", i + 1,
                                e.what);
    }
    return SQ_OK;
}

/* Whether a and b are one candidate in two places (a front member and its copy as a kind's
 * best or a pick): the same kind, score and view scale. */
static int same_candidate(const SqFitCandidate *a, const SqFitCandidate *b)
{
    return a->score == b->score && a->view_scale == b->view_scale &&
           sq_fit_kind_of(&a->params) == sq_fit_kind_of(&b->params);
}

/* The finalists' Pareto front, by score; the champion is its first. */
static SqStatus finish(Fit *f, SqFitCandidate *fin, int nfin, SqError *err)
{
    SqFitResult *r = f->r;
    double *obj = malloc(sizeof(double) * SQ_OBJ_COUNT * (size_t)nfin);
    int *rank = malloc(sizeof(int) * (size_t)nfin);
    r->front = malloc(sizeof *r->front * (size_t)nfin);
    if (!obj || !rank || !r->front) {
        free(obj);
        free(rank);
        return sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory");
    }
    for (int i = 0; i < nfin; i++)
        memcpy(obj + (size_t)i * SQ_OBJ_COUNT, fin[i].obj, sizeof fin[i].obj);
    if (sq_nsga2_rank(obj, nfin, SQ_OBJ_COUNT, rank) < 0)
        memset(rank, 0, sizeof(int) * (size_t)nfin);
    r->nfront = 0;
    for (int i = 0; i < nfin; i++)
        if (rank[i] == 0 && isfinite(fin[i].score))
            r->front[r->nfront++] = fin[i];
    free(obj);
    free(rank);
    if (r->nfront == 0)
        return sq_error_set(err, SQ_ERR_INTERNAL, "fit", "no candidate could be rendered");
    qsort(r->front, (size_t)r->nfront, sizeof *r->front, cmp_score);
    /* the simpler explanation (sq_fit_pick_kind): the simplest kind with a candidate within
     * PARSIMONY of the best (a plain skin: PLAIN_PARSIMONY) leads the front (a pattern whose
     * colours match the background is a plain skin too; an automaton stretched along the
     * body is stripes); the layered kind, when it is a niche, as simple as its rank */
    const SqFitCandidate *low[CATEGORIES] = {0};
    double score[CATEGORIES];
    for (int i = 0; i < nfin; i++) {
        const int k = sq_fit_kind_of(&fin[i].params);
        if (isfinite(fin[i].score) && (!low[k] || fin[i].score < low[k]->score))
            low[k] = &fin[i];
    }
    for (int k = 0; k < CATEGORIES; k++)
        score[k] = low[k] ? low[k]->score : INFINITY;
    const int pick = sq_fit_pick_kind(score, 0);
    const SqFitCandidate *simple = pick >= 0 ? low[pick] : NULL;
    if (simple && simplicity(sq_fit_kind_of(&simple->params)) < simplicity(sq_fit_kind_of(&r->front[0].params))) {
        const SqFitCandidate lead = *simple;
        int k = r->nfront < nfin ? r->nfront : nfin - 1;
        memmove(r->front + 1, r->front, sizeof *r->front * (size_t)k);
        r->front[0] = lead;
        r->nfront = k + 1;
        for (int i = 1; i < r->nfront; i++) /* once only */
            if (same_candidate(&r->front[i], &lead)) {
                memmove(r->front + i, r->front + i + 1, sizeof *r->front * (size_t)(r->nfront - i - 1));
                r->nfront--;
                break;
            }
    }
    if (r->nfront > f->o.front_max)
        r->nfront = f->o.front_max;
    r->best = r->front[0];
    /* the categories' scores: re-scored values only (screening scores are noisier) */
    for (int i = 0; i < CATEGORIES; i++) {
        r->category_score[i] = INFINITY;
        r->kind_best[i].score = INFINITY;
    }
    for (int i = 0; i < nfin; i++)
        keep_kind_best(r, &fin[i]);
    return SQ_OK;
}

/* c, the champion changed after the pick (polished, recoloured), leads the front as
 * best.json; whoever it dominates leaves the front, but for a plain twin's invisible
 * pattern behind it (plain_twin). With ahead, c is another candidate, picked again: it goes
 * ahead of the champion, which stays unless c dominates it, the front growing by one up to
 * front_max (out of memory: c replaces it), and c's copy in the front, if any, leaves. */
static void lead_front(SqFitResult *r, const SqFitCandidate *c, int ahead, int front_max)
{
    const SqFitCandidate lead = *c;
    SqFitCandidate *grown = ahead ? realloc(r->front, sizeof *grown * (size_t)(r->nfront + 1)) : NULL;
    if (grown) {
        r->front = grown;
        memmove(r->front + 1, r->front, sizeof *r->front * (size_t)r->nfront);
        r->nfront++;
    }
    int k = 1;
    for (int i = 1; i < r->nfront; i++) {
        const SqFitCandidate *m = &r->front[i];
        if (ahead && same_candidate(m, &lead))
            continue;
        if ((i == 1 && r->plain_twin) || !sq_pareto_dominates(lead.obj, m->obj, SQ_OBJ_COUNT))
            r->front[k++] = *m;
    }
    r->nfront = k < front_max ? k : front_max;
    r->front[0] = r->best = lead;
}

/* Candidates' colours moved toward the photo's palette (sq__recoloured), each way scored
 * at the fine size with the candidate's own seed: better[i] the best way when it scores
 * better than c[i] does there, else its score INFINITY. 1 + SQ_RECOLOUR_WAYS evaluations a
 * candidate. */
static void recolour(Fit *f, const SqFitCandidate *c, int n, SqFitCandidate *better)
{
    enum { W = SQ_RECOLOUR_WAYS };
    const int size = f->o.fine_size;
    for (int i = 0; i < n; i++)
        better[i].score = INFINITY;
    SqFitCandidate *v = malloc(sizeof *v * (size_t)n * (W + 1));
    if (!v) /* out of memory: nothing recoloured */
        return;
    SqFitCandidate *as_is = v + (size_t)n * W; /* c[i] scored at this size */
    for (int i = 0; i < n; i++)
        as_is[i] = c[i];
    recoloured_all(f, as_is, n, size, 0, v);
    for (int i = 0; i < n; i++) {
        score_of(f, &as_is[i]);
        const SqFitCandidate *b = &as_is[i];
        for (int w = 0; w < W; w++) {
            score_of(f, &v[W * i + w]);
            if (v[W * i + w].score < b->score)
                b = &v[W * i + w];
        }
        if (b != &as_is[i])
            better[i] = *b;
    }
    free(v);
}

/* Every kind's best recoloured once the champion is picked: its colours moved toward the
 * photo's palette three ways and scored at the fine size with its own seed; the best way,
 * when it scores better there, is re-scored as the finalists were and replaces the kind's
 * best when it scores better so too. A niche's CMA-ES moves every colour with every other
 * gene, and colours settle slowly: on the recovery benchmark's wrong rows the truth's kind's
 * best always scored worse than the truth on the palette objective (docs/recovery.md,
 * session 28), so the alternatives a user is handed were often the right pattern in the
 * wrong colours; and on real photos the champion too (the polish moves its colours little).
 * Not before the pick: recoloured niches lost more categories than they gained (a pattern
 * aimed at the photo's palette imitates a plain skin's shading); after it, the pick is
 * made again on the recoloured bests (sq__fit_repick). The champion, recoloured, must
 * still show what it showed: a visible pattern stays visible, a layer stays
 * LAYER_VISIBLE. It comes after the search: up to SQ_FIT_KINDS * (1 + SQ_RECOLOUR_WAYS +
 * reseeds) renders at the fine size, beyond an evaluation budget; a time budget kept their
 * time back (tail_seconds). before and after receive each kind's score before its
 * recolouring and its best recoloured way's, re-scored (0: none scored better at the fine
 * size). */
static void recolour_kinds(Fit *f, int champion, double before[SQ_FIT_KINDS], double after[SQ_FIT_KINDS])
{
    SqFitResult *r = f->r;
    const double t = now();
    const long e0 = f->evals;
    SqFitCandidate c[SQ_FIT_KINDS], better[SQ_FIT_KINDS];
    int kind[SQ_FIT_KINDS], n = 0;
    for (int k = 0; k < SQ_FIT_KINDS; k++) {
        before[k] = r->kind_best[k].score;
        after[k] = 0;
        if (isfinite(r->kind_best[k].score)) {
            kind[n] = k;
            c[n++] = r->kind_best[k];
        }
    }
    recolour(f, c, n, better);
    int m = 0;
    for (int i = 0; i < n; i++)
        if (isfinite(better[i].score)) {
            better[m] = better[i];
            kind[m++] = kind[i];
        }
    rescore(f, better, m);
    for (int i = 0; i < m; i++) {
        const SqParams *p = &better[i].params;
        after[kind[i]] = better[i].score;
        if (!(better[i].score < r->kind_best[kind[i]].score))
            continue;
        if (kind[i] == SQ_FIT_LAYERED && /* a layer recoloured into its ground is none */
            !(sq_fit_layer_visibility(p, f->o.fine_size, f->o.band_centre, NULL) >= LAYER_VISIBLE))
            continue;
        /* nor a pattern that showed into its skin; a plain champion (a plain twin's
         * visibility is its invisible pattern's) keeps its visibility */
        double vis = r->visibility;
        if (kind[i] == champion && champion != SQ_PATTERN_NONE) {
            double dom[3];
            vis = sq_fit_pattern_visibility(p, f->o.fine_size, f->o.band_centre, dom, NULL);
            if (vis < VISIBLE_MIN && r->visibility >= VISIBLE_MIN)
                continue;
        }
        r->kind_best[kind[i]] = better[i];
        r->kind_recoloured[kind[i]] = 1;
        if (kind[i] == champion) {
            lead_front(r, &better[i], 0, f->o.front_max);
            r->visibility = vis;
        }
    }
    r->recolour_evals = f->evals - e0;
    r->recolour_seconds = now() - t;
}

/* The pick made again once every kind's best is recoloured (search_internal.h). */
void sq__fit_repick(SqFitResult *r, const SqFitOptions *o, const double before[], const double after[])
{
    double score[SQ_FIT_KINDS];
    for (int k = 0; k < SQ_FIT_KINDS; k++)
        score[k] = r->kind_best[k].score;
    const int pick = sq_fit_pick_kind(score, !r->niche[SQ_FIT_LAYERED] || r->layer_best_searched);
    if (pick < 0 || pick == r->first_pick)
        return;
    double vis = 0, dom[3];
    if (pick != SQ_PATTERN_NONE) {
        vis = sq_fit_pattern_visibility(&r->kind_best[pick].params, o->fine_size, o->band_centre, dom, NULL);
        if (!(vis >= VISIBLE_MIN))
            return;
    }
    r->repicked = 1;
    r->plain_twin = r->plain_of_pattern = 0;
    r->twin_score = 0;
    r->visibility = vis;
    r->recolour_before = before[pick];
    r->recolour_after = after[pick];
    lead_front(r, &r->kind_best[pick], 1, o->front_max);
}

/* Each kind's best once the champion is polished: the front's members after the polish and
 * the plain twin count too (the polished pattern behind its plain twin is its kind's best),
 * the champion stands for its own kind (best.json), and a layered skin whose layer does not
 * show (LAYER_VISIBLE, as the layered champion's must) is none; then every kind's best,
 * the champion's included, is recoloured (recolour_kinds) and the pick made again on them
 * (sq__fit_repick). The category scores stay the ones the first pick compared. */
static void kinds_final(Fit *f)
{
    SqFitResult *r = f->r;
    for (int i = 0; i < r->nfront; i++) {
        const int kind = sq_fit_kind_of(&r->front[i].params);
        if (r->front[i].score < r->kind_best[kind].score) {
            r->kind_best[kind] = r->front[i];
            if (kind == SQ_FIT_LAYERED) /* the layer that led (behind its plain twin), or the niche's */
                r->layer_best_searched = r->layer_lead && i == (r->plain_twin ? 1 : 0);
        }
    }
    const int champion = sq_fit_kind_of(&r->best.params);
    r->kind_best[champion] = r->best;
    if (champion == SQ_FIT_LAYERED)
        r->layer_best_searched = r->layer_lead;
    r->first_pick = champion;
    SqFitCandidate *l = &r->kind_best[SQ_FIT_LAYERED];
    if (champion != SQ_FIT_LAYERED && isfinite(l->score) &&
        !(sq_fit_layer_visibility(&l->params, f->o.fine_size, f->o.band_centre, NULL) >= LAYER_VISIBLE))
        l->score = INFINITY;
    if (r->stopped || f->o.method != SQ_FIT_SQUAMA)
        return;
    r->recolour_before = r->best.score;
    double before[SQ_FIT_KINDS], after[SQ_FIT_KINDS];
    recolour_kinds(f, champion, before, after);
    r->recolour_after = after[champion];
    sq__fit_repick(r, &f->o, before, after);
}

int sq_fit_kinds_offered(const SqFitResult *r, int order[SQ_FIT_KINDS])
{
    const int champion = sq_fit_kind_of(&r->best.params);
    int n = 0;
    order[n++] = champion;
    for (int k = 0; k < SQ_FIT_KINDS; k++)
        if (k != champion && isfinite(r->kind_best[k].score)) {
            int j = n++;
            for (; j > 1 && r->kind_best[order[j - 1]].score > r->kind_best[k].score; j--)
                order[j] = order[j - 1];
            order[j] = k;
        }
    return n;
}

SqStatus sq_fit_run(const SqFeatures *target, const SqFitOptions *o, SqFitResult *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    SqStatus st = check_options(o, err);
    if (st != SQ_OK)
        return st;
    Fit f = {.target = target, .o = *o, .r = out, .t0 = now(), .best_score = INFINITY, .gen_best = NAN};
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        f.best_obj[k] = INFINITY;
    sq__rng_seed(&f.rng, o->seed);
    f.threads = o->threads > 0 ? o->threads : omp_get_max_threads();
    f.maps = calloc((size_t)f.threads, sizeof *f.maps);
    f.archive = malloc(sizeof *f.archive * ARCHIVE_MAX);
    SqFitCandidate *screened = NULL, *fin = NULL;
    int nscreened = 0;
    Niche niches[CATEGORIES];
    int nn = 0;
    if (!f.maps || !f.archive) {
        st = sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory");
        goto done;
    }
    palette_of(&f);

    /* 1. screening */
    double t = now();
    st = screen(&f, &screened, &nscreened, err);
    if (st != SQ_OK)
        goto done;
    out->seconds[0] = now() - t;
    report(&f, "screen", sq_fit_kind_of(&screened[0].params));

    /* 2. evolution: every category is a niche at first; the worst (judged by
     * worst_niche) is dropped one at a time until o->niches remain. The drops split the
     * stage's budget into equal rounds, as successive halving does (a niche dropped first
     * still had a share of the budget, not a fixed few generations); a round ends with
     * every niche having had as many generations, ROUND at least. That floor decides on
     * small budgets, where a round's share is less than ROUND generations of every niche:
     * the drops then come later, and the last may not come before the search ends (more
     * than o->niches survive; their bests are finalists anyway). */
    t = now();
    int nfin_max = ARCHIVE_MAX + CATEGORIES + 1;
    fin = malloc(sizeof *fin * (size_t)nfin_max);
    if (!fin) {
        st = sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory");
        goto done;
    }
    int nfin = 0;
    if (o->method == SQ_FIT_SQUAMA) {
        enum { ROUND = 4 };
        int alive[CATEGORIES], nalive = 0;
        for (int cat = 0; cat < CATEGORIES; cat++) {
            if (!fitted(o, cat))
                continue;
            st = niche_init(&f, &niches[nn], cat, screened, nscreened, err);
            if (st != SQ_OK)
                goto done;
            out->niche[cat] = 1;
            alive[nn++] = 1;
            nalive++;
        }
        const double start = progress(&f);
        const int rounds = nalive > o->niches ? nalive - o->niches + 1 : 1;
        int z = 0, steps = 0, drops = 0;
        while (!out_of_budget(&f, SEARCH_END)) {
            Niche *nz = &niches[z];
            if (niche_step(&f, nz) != 0) {
                st = sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory");
                goto done;
            }
            f.generation++;
            report(&f, "evolve", nz->category);
            ++steps;
            if (nalive > o->niches && steps >= ROUND * nalive && steps % nalive == 0 &&
                progress(&f) >= start + (SEARCH_END - start) * (drops + 1) / rounds) {
                double judged;
                int worst = worst_niche(&f, niches, alive, nn, &judged);
                alive[worst] = 0;
                out->dropped_at[niches[worst].category] = f.evals;
                out->judged[niches[worst].category] = judged;
                nalive--;
                drops++;
                steps = 0;
            }
            do
                z = (z + 1) % nn;
            while (!alive[z]);
        }
        for (int i = 0; i < nn; i++) {
            fin[nfin++] = niches[i].best;
            out->survivor[niches[i].category] = alive[i];
        }
    } else {
        out->niche[sq_fit_kind_of(&screened[0].params)] = 1;
        out->survivor[sq_fit_kind_of(&screened[0].params)] = 1;
        run_baseline(&f, &screened[0], &fin[nfin++]);
        f.generation++;
        report(&f, "evolve", sq_fit_kind_of(&screened[0].params));
    }
    out->seconds[1] = now() - t;
    out->stopped = o->stop && *o->stop;

    /* 3. re-scoring: the archive's front (squama) and the niches' bests */
    t = now();
    if (o->method == SQ_FIT_SQUAMA) {
        /* the archive by score; an evaluation budget keeps the re-scoring within 90% of it */
        long room = nfin_max - nfin;
        if (o->max_evals > 0) {
            long cap = ((long)(0.9 * (double)o->max_evals) - f.evals) / o->reseeds - nfin;
            room = cap < room ? (cap > 0 ? cap : 0) : room;
        }
        /* a time budget keeps it within 95% of it, at the pace so far (a fine render costs
         * up to (fine / coarse)^2 coarse ones); the niches' bests are re-scored anyway */
        if (o->budget > 0 && f.evals > 0) {
            const double ratio = (double)o->fine_size / o->coarse_size;
            const double per = elapsed(&f) / (double)f.evals * ratio * ratio * o->reseeds;
            long cap = (long)((0.95 * o->budget - elapsed(&f)) / per) - nfin;
            room = cap < room ? (cap > 0 ? cap : 0) : room;
        }
        qsort(f.archive, (size_t)f.narchive, sizeof *f.archive, cmp_score);
        for (int i = 0; i < f.narchive && i < room; i++)
            fin[nfin++] = f.archive[i];
    }
    nfin = unique(fin, nfin);
    const double t_rescore = now();
    rescore(&f, fin, nfin);
    if (o->budget > 0 && nfin > 0)
        f.tail_s = tail_seconds(&f, (now() - t_rescore) / rounds(&f, nfin * o->reseeds));
    st = finish(&f, fin, nfin, err);
    if (st != SQ_OK)
        goto done;
    plain_of_the_best_pattern(&f);
    out->seconds[2] = now() - t;
    report(&f, "rescore", sq_fit_kind_of(&out->best.params));
    if (o->method == SQ_FIT_SQUAMA && !out->stopped && (!o->categories || fitted(o, SQ_FIT_LAYERED))) {
        t = now();
        layer_search(&f, fin, nfin, screened, nscreened);
        out->layer_seconds = now() - t;
    }
    if (o->polish && o->method == SQ_FIT_SQUAMA && !out->stopped) {
        t = now();
        SqFitCandidate champ = out->best;
        polish(&f, &champ);
        if (out->polish_kept)
            lead_front(out, &champ, 0, o->front_max);
        out->front[0] = out->best;
        out->seconds[3] = now() - t;
        report(&f, "polish", sq_fit_kind_of(&out->best.params));
    }
    plain_twin(&f);
    out->evals = f.evals; /* the search's: the kinds' recolouring comes beyond it */
    kinds_final(&f);

done:
    for (int i = 0; i < nn; i++)
        niche_free(&niches[i]);
    if (f.maps)
        for (int i = 0; i < f.threads; i++)
            sq_gen_textures_free(&f.maps[i]);
    free(f.maps);
    free(f.archive);
    free(screened);
    free(fin);
    if (st != SQ_OK)
        sq_fit_result_free(out);
    return st;
}
