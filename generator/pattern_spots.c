/* Spots, §4.2.3: a soft disc (a cone 1 at the centre, 0 at the edge, its midtones raised
 * so it turns opaque) placed by a tile generator: 10 x 10 per texture at Spots_Tiling 1,
 * every other row shifted by Spots_Offset, with random size, position, shape and
 * rotation per spot. The counts are rounded to whole spots (and the rows to an even
 * number when rows are offset) so the pattern tiles. */
#include <math.h>
#include <stdlib.h>

#include "gen_internal.h"

typedef struct Spot {
    float cx, cy;   /* centre, pixels */
    float ia, ib;   /* 1 / semi-axes, pixels */
    float c, s;     /* rotation */
    float extent;   /* bounding radius, pixels */
} Spot;

enum { LUT_N = 1024 };
static const float SPOT_GAMMA = 0.3f; /* the "levels" that make the cone opaque */

void sq__spots_grid(const SqParams *p, int w, int h, int *nx, int *ny)
{
    *nx = (int)lround(10.0 * p->Spots_Tiling);
    *ny = (int)lround(10.0 * p->Spots_Tiling * h / w);
    if (*nx < 1) *nx = 1;
    if (*ny < 1) *ny = 1;
    if (p->Spots_Offset > 0.0 && *ny % 2 == 1)
        ++*ny;
}

SqStatus sq__pattern_spots(const SqParams *p, SqPattern *pat, SqError *err)
{
    const int w = pat->w, h = pat->h;
    int nx, ny;
    sq__spots_grid(p, w, h, &nx, &ny);
    SqLayer *l = sq__pattern_add(pat, SQ_LAYER_2D, p->Spots_Color, err);
    if (!l)
        return err ? err->status : SQ_ERR_NOMEM;
    Spot *spots = malloc(sizeof(Spot) * (size_t)nx * ny);
    if (!spots)
        return sq_error_set(err, SQ_ERR_NOMEM, "spots", "out of memory for %d spots", nx * ny);

    const uint64_t seed = (uint64_t)p->Seed;
    const double cw = (double)w / nx, ch = (double)h / ny, r = 0.5 * p->Spots_Scale;
    float max_extent = 0;
    for (int j = 0; j < ny; j++) {
        for (int i = 0; i < nx; i++) {
            uint64_t id = ((uint64_t)j * (uint64_t)nx + (uint64_t)i) * 8;
            double shift = (j % 2) ? p->Spots_Offset : 0.0;
            double u = i + 0.5 + shift + p->Spots_PositionRandom[0] * sq__rand11(seed, SQ_STREAM_SPOTS, id);
            double v = j + 0.5 + p->Spots_PositionRandom[1] * sq__rand11(seed, SQ_STREAM_SPOTS, id + 1);
            double size = r * (1.0 - p->Spots_ScaleVariation * sq__rand01(seed, SQ_STREAM_SPOTS, id + 2));
            double fa = (1.0 - p->Spots_Interstice[0]) *
                        (1.0 - p->Spots_IntersticeRandom[0] * sq__rand01(seed, SQ_STREAM_SPOTS, id + 3));
            double fb = (1.0 - p->Spots_Interstice[1]) *
                        (1.0 - p->Spots_IntersticeRandom[1] * sq__rand01(seed, SQ_STREAM_SPOTS, id + 4));
            double deg = p->Spots_Rotation + p->Spots_RotationRandom * sq__rand11(seed, SQ_STREAM_SPOTS, id + 5);
            double a = size * fa * cw, b = size * fb * ch, th = deg * M_PI / 180.0;
            Spot *s = &spots[j * nx + i];
            s->cx = (float)(u * cw);
            s->cy = (float)(v * ch);
            s->ia = a > 1e-3 ? (float)(1.0 / a) : 0.0f;
            s->ib = b > 1e-3 ? (float)(1.0 / b) : 0.0f;
            s->c = (float)cos(th);
            s->s = (float)sin(th);
            s->extent = s->ia > 0 && s->ib > 0 ? (float)(a > b ? a : b) + 1.0f : 0.0f;
            if (s->extent > max_extent)
                max_extent = s->extent;
        }
    }
    float lut[LUT_N + 2];
    for (int k = 0; k <= LUT_N + 1; k++)
        lut[k] = powf(k > LUT_N ? 1.0f : (float)k / LUT_N, SPOT_GAMMA);

    /* Rows of the image in bands; each band looks at the grid rows that can reach it,
     * unwrapped so spots crossing an edge appear on the other side. max() is
     * order-independent, so the result does not depend on the thread count. */
    const int band = 16, nbands = (h + band - 1) / band;
    const int kr = (int)ceil(max_extent / ch + p->Spots_PositionRandom[1]) + 1;
    float *cov = l->cov;
#pragma omp parallel for schedule(dynamic, 1)
    for (int bi = 0; bi < nbands; bi++) {
        int y0 = bi * band, y1 = y0 + band < h ? y0 + band : h;
        int j_lo = (int)floor(y0 / ch) - kr, j_hi = (int)floor((y1 - 1) / ch) + kr;
        for (int jj = j_lo; jj <= j_hi; jj++) {
            int j = sq__wrap(jj, ny);
            float yoff = (float)((jj - j) / ny) * (float)h;
            for (int i = 0; i < nx; i++) {
                const Spot *s = &spots[j * nx + i];
                if (s->extent <= 0)
                    continue;
                float cy = s->cy + yoff;
                int sy0 = (int)floorf(cy - s->extent), sy1 = (int)ceilf(cy + s->extent);
                if (sy0 < y0) sy0 = y0;
                if (sy1 > y1) sy1 = y1;
                if (sy0 >= sy1)
                    continue;
                for (int copy = -1; copy <= 1; copy++) {
                    float cx = s->cx + (float)copy * (float)w;
                    int sx0 = (int)floorf(cx - s->extent), sx1 = (int)ceilf(cx + s->extent);
                    if (sx0 < 0) sx0 = 0;
                    if (sx1 > w) sx1 = w;
                    for (int y = sy0; y < sy1; y++) {
                        float dy = (float)y + 0.5f - cy;
                        float *row = cov + (size_t)y * w;
                        for (int x = sx0; x < sx1; x++) {
                            float dx = (float)x + 0.5f - cx;
                            float lx = (dx * s->c + dy * s->s) * s->ia;
                            float ly = (-dx * s->s + dy * s->c) * s->ib;
                            float t = 1.0f - sqrtf(lx * lx + ly * ly);
                            if (t <= 0.0f)
                                continue;
                            float f = t * LUT_N;
                            int k = (int)f;
                            float a = lut[k] + (lut[k + 1] - lut[k]) * (f - (float)k);
                            if (a > row[x])
                                row[x] = a;
                        }
                    }
                }
            }
        }
    }
    free(spots);
    return SQ_OK;
}
