/* Shared inside the search module only. */
#ifndef SQ_SEARCH_INTERNAL_H
#define SQ_SEARCH_INTERNAL_H

#include "squama/params.h"

/* The colour parameters a category paints its pattern with (in the base's pattern,
 * &p->pattern, or a layer's), main colour first, into list (room for 4), NULL after the
 * last; returns how many. */
int sq__pattern_colours(SqPatternSpec *p, int category, double **list);

struct SqGene;
/* Where a gene lives in p: the base's parameter, or its layer's. */
void *sq__gene_ptr(const struct SqGene *e, SqParams *p);

#endif
