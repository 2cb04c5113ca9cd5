/* Transversal stripes (rings), §4.2.1: up to four coloured bands along v, drawn in order
 * (later colours occlude earlier ones). A colour is omitted by alpha 0 or begin = end;
 * begin > end makes a band that wraps over the texture's top and bottom edges. */
#include "gen_internal.h"

/* Length of [a, b) ∩ [lo, hi). */
static double overlap(double a, double b, double lo, double hi)
{
    double s = a > lo ? a : lo, e = b < hi ? b : hi;
    return e > s ? e - s : 0.0;
}

/* Fraction of pixel row y (of h) covered by the band [b0, b1) (wrapping if b0 > b1). */
double sq__band_coverage(int y, int h, double b0, double b1)
{
    double y0 = (double)y / h, y1 = (double)(y + 1) / h, c;
    if (b0 <= b1)
        c = overlap(y0, y1, b0, b1);
    else
        c = overlap(y0, y1, b0, 1.0) + overlap(y0, y1, 0.0, b1);
    return c * h;
}

SqStatus sq__pattern_transversal(const SqParams *p, SqPattern *pat, SqError *err)
{
    for (int i = 0; i < 4; i++) {
        double b0 = p->Transversal_BeginEnd[i][0], b1 = p->Transversal_BeginEnd[i][1];
        if (p->Transversal_Color[i][3] <= 0.0 || b0 == b1)
            continue;
        SqLayer *l = sq__pattern_add(pat, SQ_LAYER_ROWS, p->Transversal_Color[i], err);
        if (!l)
            return err ? err->status : SQ_ERR_NOMEM;
        for (int y = 0; y < pat->h; y++)
            l->cov[y] = (float)sq__band_coverage(y, pat->h, b0, b1);
    }
    return SQ_OK;
}
