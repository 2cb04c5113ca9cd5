/* A candidate's strip: the dorsal band of its base colour map in surface units. */
#include <math.h>

#include "fitness_internal.h"

SqStatus sq_fit_candidate_strip(const SqImage *basecolor, double view_scale, double band_centre,
                                int length, SqImage *strip, SqError *err)
{
    if (!basecolor || !basecolor->px || basecolor->channels < 3)
        return sq_error_set(err, SQ_ERR_INVALID, "strip", "no base colour map");
    if (!(view_scale > 0) || !isfinite(view_scale) || length < SQ_FIT_STRIP_W)
        return sq_error_set(err, SQ_ERR_INVALID, "strip",
                            "view scale %g or strip length %d out of range", view_scale, length);
    if (sq_image_alloc(strip, SQ_FIT_STRIP_W, length, 3, SQ_SPACE_SRGB) != 0)
        return sq_error_set(err, SQ_ERR_NOMEM, "strip", "out of memory for a strip");
    const int w = basecolor->width, h = basecolor->height, ch = basecolor->channels;
    const double du = SQ_FIT_BAND_WIDTH / SQ_FIT_STRIP_W, dv = du / view_scale;
    const double u0 = band_centre - SQ_FIT_BAND_WIDTH / 2;
    /* columns: fixed for every row */
    int xs[SQ_FIT_STRIP_W][2];
    float txs[SQ_FIT_STRIP_W];
    for (int i = 0; i < SQ_FIT_STRIP_W; i++) {
        double x = (u0 + (i + 0.5) * du) * w - 0.5, fx = floor(x);
        long xi = (long)fx % w;
        xs[i][0] = (int)(xi < 0 ? xi + w : xi);
        xs[i][1] = xs[i][0] + 1 == w ? 0 : xs[i][0] + 1;
        txs[i] = (float)(x - fx);
    }
    for (int j = 0; j < length; j++) {
        double y = ((j + 0.5) * dv) * h - 0.5, fy = floor(y);
        long yi = (long)fy % h;
        int y0 = (int)(yi < 0 ? yi + h : yi), y1 = y0 + 1 == h ? 0 : y0 + 1;
        float ty = (float)(y - fy);
        const float *r0 = basecolor->px + (size_t)y0 * w * ch, *r1 = basecolor->px + (size_t)y1 * w * ch;
        for (int i = 0; i < SQ_FIT_STRIP_W; i++) {
            const float *a = r0 + (size_t)xs[i][0] * ch, *b = r0 + (size_t)xs[i][1] * ch;
            const float *c = r1 + (size_t)xs[i][0] * ch, *d = r1 + (size_t)xs[i][1] * ch;
            float *o = sq_image_at(strip, i, j);
            const float tx = txs[i];
            for (int k = 0; k < 3; k++) {
                float top = a[k] + (b[k] - a[k]) * tx, bot = c[k] + (d[k] - c[k]) * tx;
                o[k] = top + (bot - top) * ty;
            }
        }
    }
    return SQ_OK;
}
