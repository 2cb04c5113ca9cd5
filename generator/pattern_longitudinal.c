/* Longitudinal stripes, §4.2.2: one white stripe on black, tiled N times across u
 * (each stripe Longitudinal_StripesWidth / N of the width, centred in its tile), then
 * squeezed towards the dorsal midline u = 0.5 by Longitudinal_Pinch (2: the pattern
 * fills the middle half; below 1 it spreads beyond the edges and is cut there), and
 * optionally zig-zagged along the body (Longitudinal_ZigzagAmplitude, squama's addition
 * for the adders' dorsal zig-zag). */
#include <math.h>

#include "gen_internal.h"

/* Measure of the stripes within [0, t], t in [0, 1]. */
static double stripes_cdf(double t, int n, double width)
{
    double m = 0;
    for (int k = 0; k < n; k++) {
        double c = (k + 0.5) / n, a = c - width / 2, b = c + width / 2;
        if (t > a)
            m += (t < b ? t : b) - a;
    }
    return m;
}

static double clamp01d(double x)
{
    return x < 0 ? 0 : (x > 1 ? 1 : x);
}

/* Fraction of [u0, u1] covered by the pinched stripes. */
static double span_coverage(double u0, double u1, int n, double stripes_width, double pinch)
{
    double width = stripes_width / n;
    double a = 0.5 + (u0 - 0.5) * pinch, b = 0.5 + (u1 - 0.5) * pinch;
    if (b - a < 1e-12) { /* pinch 0: the whole texture shows the point u = 0.5 */
        return stripes_cdf(clamp01d(a + 1e-9), n, width) - stripes_cdf(clamp01d(a - 1e-9), n, width) > 0
                   ? 1.0
                   : 0.0;
    }
    return (stripes_cdf(clamp01d(b), n, width) - stripes_cdf(clamp01d(a), n, width)) / (b - a);
}

/* Fraction of pixel column x (of w) covered by the pinched stripes. */
double sq__stripe_coverage(int x, int w, int n, double stripes_width, double pinch)
{
    return span_coverage((double)x / w, (double)(x + 1) / w, n, stripes_width, pinch);
}

/* The zig-zag: row y's stripes shifted across by a triangle wave of v (amplitude a of the
 * width, `count` periods per tile), each pixel's coverage that of its shifted span,
 * wrapped around u so the texture still tiles. */
static SqStatus zigzag(const SqParams *p, SqPattern *pat, SqError *err)
{
    const int w = pat->w, h = pat->h;
    SqLayer *l = sq__pattern_add(pat, SQ_LAYER_2D, p->Longitudinal_StripesColor, err);
    if (!l)
        return err ? err->status : SQ_ERR_NOMEM;
    const double a = p->Longitudinal_ZigzagAmplitude;
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++) {
        const double shift = a * sq__triangle(((double)y + 0.5) / h * p->Longitudinal_ZigzagCount);
        for (int x = 0; x < w; x++) {
            double u0 = (double)x / w - shift;
            u0 -= floor(u0);
            l->cov[(size_t)y * w + x] =
                (float)span_coverage(u0, u0 + 1.0 / w, p->Longitudinal_NumberOfStripes,
                                     p->Longitudinal_StripesWidth, p->Longitudinal_Pinch);
        }
    }
    return SQ_OK;
}

SqStatus sq__pattern_longitudinal(const SqParams *p, SqPattern *pat, SqError *err)
{
    if (p->Longitudinal_ZigzagAmplitude > 0)
        return zigzag(p, pat, err);
    SqLayer *l = sq__pattern_add(pat, SQ_LAYER_COLS, p->Longitudinal_StripesColor, err);
    if (!l)
        return err ? err->status : SQ_ERR_NOMEM;
    for (int x = 0; x < pat->w; x++)
        l->cov[x] = (float)sq__stripe_coverage(x, pat->w, p->Longitudinal_NumberOfStripes,
                                                p->Longitudinal_StripesWidth, p->Longitudinal_Pinch);
    return SQ_OK;
}
