/* Transversal stripes (rings), §4.2.1: up to four coloured bands along v, drawn in order
 * (later colours occlude earlier ones). A colour is omitted by alpha 0 or begin = end;
 * begin > end makes a band that wraps over the texture's top and bottom edges.
 *
 * Optionally zig-zagged round the body (Transversal_ZigzagAmplitude, squama's addition:
 * real rings seldom run square across a photo's straightened strip, and vipers' crossbands
 * are chevrons): column x's rings shifted along v by a triangle wave of u, its first peak
 * on the dorsal midline, a whole number of periods round the body so that u = 0 meets
 * u = 1; one period makes chevrons. */
#include <math.h>

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

/* Length of the span [y0, y1) (y1 - y0 <= 1, y0 in [0, 1)) covered by the band [b0, b1),
 * wrapping at 1 as the texture does. */
static double span_coverage(double y0, double y1, double b0, double b1)
{
    double c = 0;
    for (int k = 0; k < 2; k++, y0 -= 1, y1 -= 1) /* the span, and its part past 1 */
        c += b0 <= b1 ? overlap(y0, y1, b0, b1) : overlap(y0, y1, b0, 1.0) + overlap(y0, y1, 0.0, b1);
    return c;
}

/* The triangle wave of u (-1 to 1, count periods, +1 at u = 0.5) at column x's centre. */
static double zigzag_wave(int x, int w, int count)
{
    const double t = ((x + 0.5) / w - 0.5) * count + 0.5, f = t - floor(t);
    return f < 0.5 ? 4.0 * f - 1.0 : 3.0 - 4.0 * f;
}

static SqStatus zigzag(const SqParams *p, SqPattern *pat, SqError *err)
{
    const int w = pat->w, h = pat->h;
    const double a = p->Transversal_ZigzagAmplitude;
    for (int i = 0; i < 4; i++) {
        const double b0 = p->Transversal_BeginEnd[i][0], b1 = p->Transversal_BeginEnd[i][1];
        if (p->Transversal_Color[i][3] <= 0.0 || b0 == b1)
            continue;
        SqLayer *l = sq__pattern_add(pat, SQ_LAYER_2D, p->Transversal_Color[i], err);
        if (!l)
            return err ? err->status : SQ_ERR_NOMEM;
#pragma omp parallel for schedule(static)
        for (int x = 0; x < w; x++) {
            const double s = a * zigzag_wave(x, w, p->Transversal_ZigzagCount);
            for (int y = 0; y < h; y++) {
                double y0 = (double)y / h - s;
                y0 -= floor(y0);
                l->cov[(size_t)y * w + x] = (float)(span_coverage(y0, y0 + 1.0 / h, b0, b1) * h);
            }
        }
    }
    return SQ_OK;
}

SqStatus sq__pattern_transversal(const SqParams *p, SqPattern *pat, SqError *err)
{
    if (p->Transversal_ZigzagAmplitude > 0)
        return zigzag(p, pat, err);
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
