/* Random candidates as the fit's screening and the artists' seeds draw them: genes over
 * narrower ranges than the table suggests, bands as banded snakes wear them. */
#include <math.h>
#include <string.h>

#include "rng.h"
#include "search_internal.h"
#include "squama/search.h"

/* Narrower ranges than the table's suggested ones, for random draws only: those bound what
 * the generator can make, not what a snake looks like, and uniform draws over them are
 * mostly extremes (skins drowned in colour noise, ten stripes pinched into one, spots as
 * big as the body or as fine as sand, blurred or melted patterns, features stretched into
 * streaks). Searches and variations move over the genome's own ranges. */
static const struct {
    const char *name;
    double lo, hi;
} draw_ranges[] = {
    {"Color_NoiseIntensity", 0, 0.3},  {"Scales_XAmount", 12, 48},     {"Scales_YAmount", 16, 64},
    {"Longitudinal_Pinch", 0.7, 3},    {"Spots_Tiling", 0.6, 4},       {"Pattern_BlurAmount", 0, 4},
    {"Pattern_Warp_Large", 0, 4},      {"Outline_Edge_Width", 0.5, 6}, {"RD_ReactionSpeed", 0.03, 0.12},
    {"RD_Anisotropy", 0.5, 2},         {"RD_BetaVariation", 0, 2},     {"Longitudinal_StripesWidth", 0.05, 0.5},
    {"Spots_Interstice", 0, 0.6},       {"RD_StripeDiffusion", 0.005, 0.05}, {"RD_FlankSpeed", 0.7, 2},
    {"RD_Threshold1", 0.3, 0.65},
};

void sq__genome_narrow(SqGenome *g)
{
    for (int i = 0; i < g->n; i++) {
        SqGene *e = &g->genes[i];
        for (size_t k = 0; k < sizeof draw_ranges / sizeof draw_ranges[0]; k++)
            if (!e->levels && strcmp(e->spec->name, draw_ranges[k].name) == 0) {
                e->lo = draw_ranges[k].lo;
                e->hi = draw_ranges[k].hi;
                if (e->kind == SQ_GENE_LOG && e->lo <= 0)
                    e->lo = e->hi * 1e-3;
            }
    }
}

/* What most skins lack: colour noise, a blurred, contrasted or warped pattern, an outline.
 * Each gene is drawn at its default (none) half the time, on its own (Has_Outline is then
 * false three times in four): a skin with all of them at random values over their ranges
 * is no snake's, and a random candidate would have several. Every one is linear, boolean
 * or integer with its default at the bottom of its range, so that the default survives
 * sq_genome_encode and decode exactly (a log gene's bottom is above 0). */
static const char *const sparse[] = {
    "Color_NoiseIntensity", "Pattern_BlurAmount", "Pattern_Contrast", "Pattern_Warp_Small",
    "Pattern_Warp_Large",   "Has_Outline",        NULL,
};

static int is_sparse(const SqGene *e)
{
    for (int k = 0; sparse[k]; k++)
        if (strcmp(e->spec->name, sparse[k]) == 0)
            return 1;
    return 0;
}

void sq__genome_draw(SqRng *r, const SqGenome *g, SqParams *p)
{
    double x[SQ_GENOME_MAX], none[SQ_GENOME_MAX];
    sq_params_default(p);
    sq_genome_encode(g, p, none);
    for (int i = 0; i < g->n; i++) {
        x[i] = sq__rng_uniform(r);
        if (is_sparse(&g->genes[i]) && sq__rng_uniform(r) < 0.5)
            x[i] = none[i];
    }
    sq_genome_decode(g, x, p);
}

/* Rings as banded snakes wear them, instead of three uniform intervals (which mostly fill
 * the tile): a first band 4% to 35% of the repeat long; a second one, half the time nested
 * in the first (drawn over it: a black-yellow-black triad of a coral snake), else elsewhere
 * or absent; a third, a third of the time, likewise within the second. */
static void transversal_bands(SqRng *r, SqPatternSpec *p)
{
    double c = sq__rng_uniform(r), w = sq__rng_between(r, 0.04, 0.35);
    for (int i = 0; i < 3; i++) {
        if (i > 0) {
            const double u = sq__rng_uniform(r);
            if (u < (i == 1 ? 0.5 : 0.33)) {
                w *= sq__rng_between(r, 0.2, 0.6); /* nested */
            } else if (u < (i == 1 ? 0.8 : 0.6)) {
                c = sq__rng_uniform(r);
                w = sq__rng_between(r, 0.03, 0.2);
            } else {
                p->Transversal_BeginEnd[i][0] = p->Transversal_BeginEnd[i][1] = 1; /* omitted */
                continue;
            }
        }
        p->Transversal_BeginEnd[i][0] = fmod(c - w / 2 + 1, 1);
        p->Transversal_BeginEnd[i][1] = fmod(c + w / 2 + 1, 1);
    }
}

void sq__draw_bands(SqRng *r, const SqGenome *g, SqParams *p)
{
    if (g->category == SQ_PATTERN_TRANSVERSAL)
        transversal_bands(r, &p->pattern);
    if (g->layer_category == SQ_PATTERN_TRANSVERSAL)
        transversal_bands(r, &p->Pattern_Layers.layer[0].spec);
}
