/* The genome of each pattern category, read from the parameter table. Which parameters are
 * genes is listed per category below (those the photo can show: colours, the pattern, its
 * post-processing, the outline, the scale layout); ranges, scales and types come from the
 * table, so a change there reaches the optimizer without touching this file. */
#include <math.h>
#include <string.h>

#include "search_internal.h"
#include "squama/search.h"

/* Parameters every category searches. Roughness reaches a photo as the gloss of its
 * highlights, which candidate strips draw. */
static const char *const common[] = {
    "Background_Color", "Color_NoiseIntensity", "Scales_XAmount", "Scales_YAmount",
    "ScaleShape_IsKeeled", "Scales_RoughnessMin", "Scales_RoughnessMax", NULL,
};

/* The pattern post-process and the outline, for every category with a pattern. */
static const char *const pattern_common[] = {
    "Pattern_BlurAmount", "Pattern_Contrast", "Pattern_Warp_Small", "Pattern_Warp_Large",
    "Has_Outline", "Outline_Color", "Outline_Edge_Width", NULL,
};

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
    "RD_Threshold1", "RD_Color2", "RD_Threshold2", "RD_Color3", "RD_Softness", NULL,
};

/* Integers with at most this many values in their suggested range are discrete genes. */
enum { DISCRETE_MAX = 16 };

static int add_param(SqGenome *g, const char *name)
{
    const SqParamSpec *s = sq_params_find(name);
    if (!s || (s->flags & SQ_PF_NOSEARCH))
        return -1;
    int comps = s->type == SQ_PT_COLOR ? 3 /* alpha is not searched */ : sq_param_components(s->type);
    for (int c = 0; c < comps; c++) {
        if (g->n >= SQ_GENOME_MAX)
            return -1;
        SqGene *e = &g->genes[g->n++];
        memset(e, 0, sizeof *e);
        e->spec = s;
        e->comp = c;
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

static int add_list(SqGenome *g, const char *const *names)
{
    for (int i = 0; names[i]; i++)
        if (add_param(g, names[i]) != 0)
            return -1;
    return 0;
}

SqStatus sq_genome_init(SqGenome *g, int category, SqError *err)
{
    memset(g, 0, sizeof *g);
    g->category = category;
    const char *const *own = NULL;
    switch (category) {
    case SQ_PATTERN_NONE: break;
    case SQ_PATTERN_LONGITUDINAL: own = longitudinal; break;
    case SQ_PATTERN_TRANSVERSAL: own = transversal; break;
    case SQ_PATTERN_SPOTS: own = spots; break;
    case SQ_PATTERN_OTHER_SIMPLE:
        own = other_simple;
        g->has_ca = 1;
        break;
    case SQ_PATTERN_COMPLEX: own = complex_rd; break;
    default:
        return sq_error_set(err, SQ_ERR_UNSUPPORTED, "genome",
                            "pattern type \"%s\" has no genome yet", sq_pattern_type_name(category));
    }
    if (add_list(g, common) || (own && (add_list(g, own) || add_list(g, pattern_common))))
        return sq_error_set(err, SQ_ERR_INTERNAL, "genome", "the gene list names a parameter the table lacks");
    return SQ_OK;
}

static double *field(const SqGene *e, SqParams *p)
{
    return (double *)sq_param_ptr(p, e->spec) + e->comp;
}

void sq_genome_encode(const SqGenome *g, const SqParams *p, double *x)
{
    for (int i = 0; i < g->n; i++) {
        const SqGene *e = &g->genes[i];
        const void *ptr = sq_param_cptr(p, e->spec);
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
    for (int i = 0; i < g->n; i++) {
        const SqGene *e = &g->genes[i];
        double t = fmin(fmax(x[i], 0), 1);
        if (e->levels) {
            int level = (int)fmin(floor(t * e->levels), e->levels - 1);
            *(int *)sq_param_ptr(p, e->spec) = (int)e->lo + level;
            continue;
        }
        double v = e->kind == SQ_GENE_LOG ? e->lo * pow(e->hi / e->lo, t) : e->lo + t * (e->hi - e->lo);
        v = fmin(fmax(v, e->spec->min), e->spec->max);
        if (e->spec->type == SQ_PT_INT)
            *(int *)sq_param_ptr(p, e->spec) = (int)lround(v);
        else
            *field(e, p) = v;
    }
}

void sq_genome_levels(const SqGenome *g, int *levels)
{
    for (int i = 0; i < g->n; i++)
        levels[i] = g->genes[i].levels;
}

int sq__pattern_colours(SqParams *p, int category, double **list)
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
