/* The genome of each pattern category, read from the parameter table. Which parameters are
 * genes is listed per category below (those the photo can show: colours, the pattern, its
 * post-processing, the outline, the scale layout); ranges, scales and types come from the
 * table, so a change there reaches the optimizer without touching this file. */
#include <math.h>
#include <string.h>

#include "search_internal.h"
#include "squama/search.h"

/* Parameters every category searches. Roughness reaches a photo as the gloss of its
 * highlights, which candidate strips draw; the scale layout (grid or Voronoi) as the
 * relief's shading. */
static const char *const common[] = {
    "Background_Color", "Color_NoiseIntensity", "Scales_XAmount", "Scales_YAmount",
    "ScaleShape_IsKeeled", "Scales_RoughnessMin", "Scales_RoughnessMax", "Scales_Layout",
    "Scales_VoronoiAnisotropy", NULL,
};

/* The pattern post-process and the outline, for every category with a pattern. */
static const char *const pattern_common[] = {
    "Pattern_BlurAmount", "Pattern_Contrast", "Pattern_Warp_Small", "Pattern_Warp_Large",
    "Has_Outline", "Outline_Color", "Outline_Edge_Width", NULL,
};

/* Not the zig-zag (Longitudinal_ZigzagAmplitude): drawn uniformly over its range it would
 * bend nearly every stripe, while most striped snakes have straight ones. */
static const char *const longitudinal[] = {
    "Longitudinal_NumberOfStripes", "Longitudinal_StripesWidth", "Longitudinal_StripesColor",
    "Longitudinal_Pinch", NULL,
};

static const char *const transversal[] = {
    "Transversal_Color1", "Transversal_BeginEnd1", "Transversal_Color2",
    "Transversal_BeginEnd2", "Transversal_Color3", "Transversal_BeginEnd3", NULL,
};

static const char *const spots[] = {
    "Spots_Scale", "Spots_ScaleVariation", "Spots_PositionRandom", "Spots_Offset",
    "Spots_Color", "Spots_Interstice", "Spots_RotationRandom", "Spots_Tiling", NULL,
};

static const char *const other_simple[] = {
    "CustomPattern_Color_Inside", "CA_CircleDiameter", "Pattern_RotatePattern90Degrees", NULL,
};

/* Reaction-diffusion. RD_Cells is not a gene: it sets the cost of a simulation (its
 * square), and the feature size follows RD_ReactionSpeed and the view scale as well (the
 * fit sets it; search/fit.c). */
static const char *const complex_rd[] = {
    "RD_System", "RD_Cascade", "RD_ReactionSpeed", "RD_ReactionSpeed2", "RD_BetaVariation",
    "RD_StripeDiffusion", "RD_StripeDiffusion2", "RD_Anisotropy", "RD_FlankSpeed", "RD_Color1",
    "RD_Threshold1", "RD_Color2", "RD_Threshold2", "RD_Color3", "RD_Softness", "RD_NetWidth",
    "RD_RosetteWidth", "RD_CascadeGap", NULL,
};

/* A layer's own settings, for the layered kind's one layer. */
static const char *const layer_own[] = {"Layer_Blend", "Layer_Opacity", NULL};

/* Integers with at most this many values in their suggested range are discrete genes. */
enum { DISCRETE_MAX = 16 };

static int add_param(SqGenome *g, const char *name, int layer)
{
    const SqParamSpec *s = sq_params_find(name);
    if (!s || (s->flags & SQ_PF_NOSEARCH) || (layer >= 0 && !sq_param_in_layer(s)) ||
        (layer < 0 && (s->flags & SQ_PF_LAYER)))
        return -1;
    int comps = s->type == SQ_PT_COLOR ? 3 /* alpha is not searched */ : sq_param_components(s->type);
    for (int c = 0; c < comps; c++) {
        if (g->n >= SQ_GENOME_MAX)
            return -1;
        SqGene *e = &g->genes[g->n++];
        memset(e, 0, sizeof *e);
        e->spec = s;
        e->comp = c;
        e->layer = layer;
        e->lo = s->smin;
        e->hi = s->smax;
        switch (s->type) {
        case SQ_PT_BOOL:
            e->kind = SQ_GENE_BOOL;
            e->levels = 2;
            e->lo = 0;
            e->hi = 1;
            break;
        case SQ_PT_ENUM: /* categorical: one level per choice */
            e->kind = SQ_GENE_INT;
            e->levels = (int)(s->smax - s->smin + 1);
            break;
        case SQ_PT_INT:
            if (s->smax - s->smin + 1 <= DISCRETE_MAX) {
                e->kind = SQ_GENE_INT;
                e->levels = (int)(s->smax - s->smin + 1);
            } else {
                e->kind = (s->flags & SQ_PF_LOG) ? SQ_GENE_LOG : SQ_GENE_REAL;
            }
            break;
        default:
            e->kind = (s->flags & SQ_PF_LOG) ? SQ_GENE_LOG : SQ_GENE_REAL;
            break;
        }
        if (e->kind == SQ_GENE_LOG && e->lo <= 0)
            e->lo = fmax(s->min, e->hi * 1e-3);
    }
    return 0;
}

static int add_list(SqGenome *g, const char *const *names, int layer)
{
    for (int i = 0; names[i]; i++)
        if (add_param(g, names[i], layer) != 0)
            return -1;
    return 0;
}

/* A category's own genes (NULL for a plain skin); -1 for a category without a genome. */
static int own_genes(int category, const char *const **own)
{
    switch (category) {
    case SQ_PATTERN_NONE: *own = NULL; return 0;
    case SQ_PATTERN_LONGITUDINAL: *own = longitudinal; return 0;
    case SQ_PATTERN_TRANSVERSAL: *own = transversal; return 0;
    case SQ_PATTERN_SPOTS: *own = spots; return 0;
    case SQ_PATTERN_OTHER_SIMPLE: *own = other_simple; return 0;
    case SQ_PATTERN_COMPLEX: *own = complex_rd; return 0;
    default: return -1;
    }
}

SqStatus sq_genome_init(SqGenome *g, int category, SqError *err)
{
    return sq_genome_init_layered(g, category, -1, err);
}

int sq_genome_layerable(int base, int layer)
{
    return base != layer &&
           (base == SQ_PATTERN_LONGITUDINAL || base == SQ_PATTERN_TRANSVERSAL || base == SQ_PATTERN_SPOTS ||
            base == SQ_PATTERN_OTHER_SIMPLE) &&
           (layer == SQ_PATTERN_LONGITUDINAL || layer == SQ_PATTERN_TRANSVERSAL || layer == SQ_PATTERN_SPOTS);
}

SqStatus sq_genome_init_layered(SqGenome *g, int category, int layer, SqError *err)
{
    memset(g, 0, sizeof *g);
    g->category = category;
    g->layer_category = -1;
    const char *const *own = NULL, *const *lown = NULL;
    if (own_genes(category, &own) != 0)
        return sq_error_set(err, SQ_ERR_UNSUPPORTED, "genome", "pattern type \"%s\" has no genome yet",
                            sq_pattern_type_name(category));
    if (layer >= 0 && (!sq_genome_layerable(category, layer) || own_genes(layer, &lown) != 0))
        return sq_error_set(err, SQ_ERR_UNSUPPORTED, "genome", "no layered genome for %s under %s",
                            sq_pattern_type_name(category), sq_pattern_type_name(layer));
    g->has_ca = category == SQ_PATTERN_OTHER_SIMPLE;
    if (add_list(g, common, -1) || (own && (add_list(g, own, -1) || add_list(g, pattern_common, -1))))
        return sq_error_set(err, SQ_ERR_INTERNAL, "genome", "the gene list names a parameter the table lacks");
    if (layer >= 0) {
        g->layer_category = layer;
        if (add_list(g, lown, 0) || add_list(g, layer_own, 0))
            return sq_error_set(err, SQ_ERR_INTERNAL, "genome", "too many genes, or a layer gene the table lacks");
    }
    return SQ_OK;
}

SqStatus sq_genome_of(SqGenome *g, const SqParams *p, SqError *err)
{
    if (p->Pattern_Layers.count == 0)
        return sq_genome_init(g, p->Pattern_Type, err);
    if (p->Pattern_Layers.count > 1)
        return sq_error_set(err, SQ_ERR_UNSUPPORTED, "genome", "the fit searches one pattern layer, not %d",
                            p->Pattern_Layers.count);
    return sq_genome_init_layered(g, p->Pattern_Type, p->Pattern_Layers.layer[0].spec.Pattern_Type, err);
}

void *sq__gene_ptr(const SqGene *e, SqParams *p)
{
    return e->layer >= 0 ? sq_param_layer_ptr(&p->Pattern_Layers.layer[e->layer], e->spec) : sq_param_ptr(p, e->spec);
}

static double *field(const SqGene *e, SqParams *p)
{
    return (double *)sq__gene_ptr(e, p) + e->comp;
}

void sq_genome_encode(const SqGenome *g, const SqParams *p, double *x)
{
    for (int i = 0; i < g->n; i++) {
        const SqGene *e = &g->genes[i];
        const void *ptr = sq__gene_ptr(e, (SqParams *)p); /* read only */
        double v = (e->spec->type == SQ_PT_INT || e->spec->type == SQ_PT_BOOL || e->spec->type == SQ_PT_ENUM)
                       ? *(const int *)ptr
                       : ((const double *)ptr)[e->comp];
        double t;
        if (e->levels) /* the middle of the value's level */
            t = (fmin(fmax(v - e->lo, 0), e->levels - 1) + 0.5) / e->levels;
        else if (e->kind == SQ_GENE_LOG)
            t = log(fmax(v, e->lo) / e->lo) / log(e->hi / e->lo);
        else
            t = (v - e->lo) / (e->hi - e->lo);
        x[i] = fmin(fmax(t, 0), 1);
    }
}

void sq_genome_decode(const SqGenome *g, const double *x, SqParams *p)
{
    p->Pattern_Type = g->category;
    if (g->layer_category >= 0) {
        if (p->Pattern_Layers.count != 1 || p->Pattern_Layers.layer[0].spec.Pattern_Type != g->layer_category) {
            sq_pattern_layer_default(&p->Pattern_Layers.layer[0]);
            p->Pattern_Layers.layer[0].spec.Pattern_Type = g->layer_category;
        }
        p->Pattern_Layers.count = 1;
    } else {
        p->Pattern_Layers.count = 0;
    }
    for (int i = 0; i < g->n; i++) {
        const SqGene *e = &g->genes[i];
        double t = fmin(fmax(x[i], 0), 1);
        if (e->levels) {
            int level = (int)fmin(floor(t * e->levels), e->levels - 1);
            *(int *)sq__gene_ptr(e, p) = (int)e->lo + level;
            continue;
        }
        double v = e->kind == SQ_GENE_LOG ? e->lo * pow(e->hi / e->lo, t) : e->lo + t * (e->hi - e->lo);
        v = fmin(fmax(v, e->spec->min), e->spec->max);
        if (e->spec->type == SQ_PT_INT)
            *(int *)sq__gene_ptr(e, p) = (int)lround(v);
        else
            *field(e, p) = v;
    }
}

void sq_genome_levels(const SqGenome *g, int *levels)
{
    for (int i = 0; i < g->n; i++)
        levels[i] = g->genes[i].levels;
}

int sq__pattern_colours(SqPatternSpec *p, int category, double **list)
{
    int n = 0;
    switch (category) {
    case SQ_PATTERN_LONGITUDINAL: list[n++] = p->Longitudinal_StripesColor; break;
    case SQ_PATTERN_TRANSVERSAL:
        for (int i = 0; i < 3; i++)
            list[n++] = p->Transversal_Color[i];
        break;
    case SQ_PATTERN_SPOTS: list[n++] = p->Spots_Color; break;
    case SQ_PATTERN_OTHER_SIMPLE: list[n++] = p->CustomPattern_Color_Inside; break;
    case SQ_PATTERN_COMPLEX:
        list[n++] = p->RD_Color1;
        list[n++] = p->RD_Color2;
        list[n++] = p->RD_Color3;
        break;
    default: break;
    }
    list[n] = NULL;
    return n;
}
