/* Pattern outline, §4.2.6: edge detection on the pattern (the image minus its blur,
 * levels up), distorted by the scales' height map, blurred and contrasted, drawn in
 * Outline_Color over the pattern. */
#include <math.h>
#include <stdlib.h>

#include "gen_internal.h"

SqStatus sq__outline(const SqParams *p, float *rgba, const float *height, int w, int h,
                     SqError *err)
{
    const size_t n = (size_t)w * h;
    float *blur = sq__falloc(n * 4), *edge = sq__falloc(n), *dist = sq__falloc(n);
    if (!blur || !edge || !dist) {
        sq__ffree(blur);
        sq__ffree(edge);
        sq__ffree(dist);
        return sq_error_set(err, SQ_ERR_NOMEM, "outline", "out of memory for the outline");
    }
    /* 1. edges: |pattern - blur(pattern)| over the premultiplied channels, levelled up */
    for (size_t i = 0; i < n * 4; i++)
        blur[i] = rgba[i];
    double width = sq__px(p->Outline_Edge_Width, w) / 2;
    sq__blur(blur, w, h, 4, width > 0.5 ? width : 0.5);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            float e = 0;
            for (int c = 0; c < 4; c++)
                e += fabsf(rgba[4 * i + c] - blur[4 * i + c]);
            edge[i] = sq__clamp01(e * 4.0f);
        }

    /* 2. distortion along the height map's gradient */
    const double k = p->Outline_Distortion_Intensity * ((double)w / 256) * ((double)w / 256);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++) {
        const float *up = height + (size_t)sq__wrap(y - 1, h) * w, *dn = height + (size_t)sq__wrap(y + 1, h) * w;
        const float *row = height + (size_t)y * w;
        for (int x = 0; x < w; x++) {
            float gx = (row[x + 1 < w ? x + 1 : 0] - row[x > 0 ? x - 1 : w - 1]) * 0.5f;
            float gy = (dn[x] - up[x]) * 0.5f;
            dist[(size_t)y * w + x] =
                k > 0 ? sq__sample(edge, w, h, 1, 0, (float)(x + k * gx), (float)(y + k * gy))
                      : edge[(size_t)y * w + x];
        }
    }
    /* 3. blur and contrast; roundness blurs more and re-thresholds, rounding corners */
    sq__blur(dist, w, h, 1, sq__px(p->Outline_Blur, w) / 2);
    const double round = sq__px(p->Outline_Edge_Roundness, w) / 2;
    if (round >= 0.5)
        sq__blur(dist, w, h, 1, round);
    const float c = round >= 0.5 ? 0.75f : 0.5f;
    const float oc[4] = {(float)p->Outline_Color[0], (float)p->Outline_Color[1],
                         (float)p->Outline_Color[2], (float)p->Outline_Color[3]};
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            float a = sq__contrast(sq__clamp01(dist[i] * 1.5f), c) * oc[3], kk = 1 - a;
            for (int ch = 0; ch < 3; ch++)
                rgba[4 * i + ch] = oc[ch] * a + rgba[4 * i + ch] * kk;
            rgba[4 * i + 3] = a + rgba[4 * i + 3] * kk;
        }
    sq__ffree(blur);
    sq__ffree(edge);
    sq__ffree(dist);
    return SQ_OK;
}
