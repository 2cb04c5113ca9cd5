/* Shared inside the search module only. */
#ifndef SQ_SEARCH_INTERNAL_H
#define SQ_SEARCH_INTERNAL_H

#include "rng.h"
#include "squama/params.h"

/* The range of view scales the fit searches (body circumferences a texture tile), which
 * the readings off the photo keep to as well. */
static const double SQ__VIEW_LO = 0.25, SQ__VIEW_HI = 8.0;

/* The colour parameters a category paints its pattern with (in the base's pattern,
 * &p->pattern, or a layer's), main colour first, into list (room for 4), NULL after the
 * last; returns how many. */
int sq__pattern_colours(SqPatternSpec *p, int category, double **list);

struct SqGene;
/* Where a gene lives in p: the base's parameter, or its layer's. */
void *sq__gene_ptr(const struct SqGene *e, SqParams *p);

struct SqGenome;
/* Random draws (draw.c). sq__genome_narrow narrows a genome's ranges to those random
 * candidates are drawn over (a search moves over the whole ranges of another copy);
 * sq__genome_draw draws p's genes uniformly over g's ranges (colour noise, the
 * post-process genes and Has_Outline each at their default half the time), other
 * parameters at their defaults; sq__draw_bands replaces a transversal pattern's (or
 * layer's) uniform bands with rings as banded snakes wear them. */
void sq__genome_narrow(struct SqGenome *g);
void sq__genome_draw(SqRng *r, const struct SqGenome *g, SqParams *p);
void sq__draw_bands(SqRng *r, const struct SqGenome *g, SqParams *p);

struct SqFeatures;
struct SqFitCandidate;
enum { SQ_RECOLOUR_WAYS = 3 };
/* c's colours moved toward the photo's palette (target), SQ_RECOLOUR_WAYS ways, into
 * out[0] to out[2] (recolour.c; feat: c's features). The palette objective matches c's dominant colours with the photo's; each
 * of c's colours seen at all (its ground, its pattern's and its layers' colours not
 * switched off, the outline when it has one) is aimed at what they were matched with:
 *  out[0]: each shifted in CIELAB as far as the dominant colour nearest it lies from its
 *          match (a pattern colour gone astray comes back on its own);
 *  out[1]: every one through the one gain and offset per CIELAB axis that best carry the
 *          dominant colours onto their matches (the light and shading the skin is seen
 *          under change all of its colours alike);
 *  out[2]: every one shifted by the dominant colours' mean shift (their weights' mean).
 * Only the colours change; out[k]'s objectives are c's until evaluated. */
void sq__recoloured(const struct SqFeatures *target, const struct SqFitCandidate *c,
                    const struct SqFeatures *feat, struct SqFitCandidate *out);

struct SqFitResult;
struct SqFitOptions;
/* The fit's pick made again on every kind's best once recoloured (r->kind_best;
 * sq_fit_pick_kind, the layered kind leading only by 20% unless it is the layered niche's
 * best, not the layer searched over the champion: r->layer_best_searched), so that no kind
 * the fit offers scores better than best.json's under the rule that chose it. A pattern
 * nobody can see (sq_fit_pattern_visibility below 0.02 at o->fine_size) is not picked:
 * the champion stays. A new champion (r->repicked) goes ahead of it in the front (r->front
 * from malloc; whom it dominates and its own copy leave, o->front_max at most); the plain twin's
 * facts were the first pick's and are cleared, and r->recolour_before/after become
 * before[k] and after[k] of its kind k (each kind's score before its recolouring and its
 * best recoloured way's, 0: none). r->first_pick must be the kind of r->best. */
void sq__fit_repick(struct SqFitResult *r, const struct SqFitOptions *o, const double before[],
                    const double after[]);

#endif
