/* Transversal stripes (rings), §4.2.1: up to four coloured bands along v, drawn in order
 * (later colours occlude earlier ones). A colour is omitted by alpha 0 or begin = end;
 * begin > end makes a band that wraps over the texture's top and bottom edges.
 *
 * Optionally zig-zagged round the body (Transversal_ZigzagAmplitude, squama's addition for
 * vipers' chevron crossbands and rings serrated along the scale rows; the fit does not
 * search it, docs/recovery.md session 40): column x's rings shifted along v by a triangle
 * wave of u, its first peak on the dorsal midline, a whole number of periods round the
 * body so that u = 0 meets u = 1; one period makes chevrons. */
#include <math.h>
#include <stdlib.h>

#include "gen_internal.h"

/* Length of [a, b) ∩ [lo, hi). */
static double overlap(double a, double b, double lo, double hi)
{
    double s = a > lo ? a : lo, e = b < hi ? b : hi;
    return e > s ? e - s : 0.0;
}

/* Length of the span [y0, y1) (y1 - y0 <= 1, y0 in [0, 1)) covered by the band [b0, b1),
 * wrapping at 1 as the texture does (begin > end: over the top and bottom edges). */
static double span_coverage(double y0, double y1, double b0, double b1)
{
    double c = 0;
    for (int k = 0; k < 2; k++, y0 -= 1, y1 -= 1) /* the span, and its part past 1 */
        c += b0 <= b1 ? overlap(y0, y1, b0, b1) : overlap(y0, y1, b0, 1.0) + overlap(y0, y1, 0.0, b1);
    return c;
}

/* Fraction of pixel row y (of h) covered by the band [b0, b1) (wrapping if b0 > b1). */
double sq__band_coverage(int y, int h, double b0, double b1)
{
    return span_coverage((double)y / h, (double)(y + 1) / h, b0, b1) * h;
}

enum { ZIGZAG_SUB_MAX = 16 }; /* sub-columns a pixel column, at most */

/* Each pixel's coverage is exact along v for a shift, and the mean over sub-columns
 * across: as many as make the shift change by at most half a pixel from one to the next,
 * so that a steep edge is smooth instead of a staircase of columns and a zig-zag finer
 * than the pixels averages out instead of aliasing. */
static SqStatus zigzag(const SqParams *p, SqPattern *pat, SqError *err)
{
    const int w = pat->w, h = pat->h, count = p->Transversal_ZigzagCount;
    const double a = p->Transversal_ZigzagAmplitude;
    const double step = 4.0 * a * count * h / w; /* pixels along, per column across */
    const int n = (int)fmin(ZIGZAG_SUB_MAX, fmax(1, ceil(2 * step)));
    double *shift = malloc(sizeof(double) * (size_t)w * n);
    if (!shift)
        return sq_error_set(err, SQ_ERR_NOMEM, "pattern", "out of memory for the rings' zig-zag");
    for (int x = 0; x < w; x++)
        for (int j = 0; j < n; j++)
            shift[(size_t)x * n + j] = a * sq__triangle(((x + (j + 0.5) / n) / w - 0.5) * count + 0.5);
    for (int i = 0; i < 4; i++) {
        const double b0 = p->Transversal_BeginEnd[i][0], b1 = p->Transversal_BeginEnd[i][1];
        if (p->Transversal_Color[i][3] <= 0.0 || b0 == b1)
            continue;
        SqLayer *l = sq__pattern_add(pat, SQ_LAYER_2D, p->Transversal_Color[i], err);
        if (!l) {
            free(shift);
            return err ? err->status : SQ_ERR_NOMEM;
        }
#pragma omp parallel for schedule(static)
        for (int y = 0; y < h; y++) {
            float *row = l->cov + (size_t)y * w;
            for (int x = 0; x < w; x++) {
                double c = 0;
                for (int j = 0; j < n; j++) {
                    double y0 = (double)y / h - shift[(size_t)x * n + j];
                    y0 -= floor(y0);
                    c += span_coverage(y0, y0 + 1.0 / h, b0, b1);
                }
                row[x] = (float)(c * h / n);
            }
        }
    }
    free(shift);
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
