/* Pattern post-process, §4.2.7: the pattern is distorted by two Perlin noises, one of
 * low frequency (Pattern_Warp_Large, macro variation) and one of high frequency
 * (Pattern_Warp_Small, micro variation). A warp amount of 1 moves the pattern by up to
 * about 1% of the texture width. The displacement field is computed on a coarse grid
 * and interpolated where the colour map samples the pattern; the noises are periodic,
 * so the result still tiles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen_internal.h"

enum { LARGE_CELLS = 4, SMALL_CELLS = 32 };

void sq__warp_free(SqWarp *warp)
{
    sq__ffree(warp->dx);
    sq__ffree(warp->dy);
    memset(warp, 0, sizeof *warp);
}

static int cells_y(int cells, int w, int h)
{
    int c = (int)lround((double)cells * h / w);
    return c > 0 ? c : 1;
}

SqStatus sq__warp_field(const SqParams *p, int w, int h, SqWarp *warp, SqError *err)
{
    memset(warp, 0, sizeof *warp);
    const double big = p->Pattern_Warp_Large * 0.01 * w, small = p->Pattern_Warp_Small * 0.01 * w;
    if (big * 4 < 0.05 && small * 4 < 0.05) /* under a twentieth of a pixel */
        return SQ_OK;
    /* 8 samples per small-noise cell at most, never more than the image */
    const int gw = w < SMALL_CELLS * 8 ? w : SMALL_CELLS * 8;
    int gh = (int)lround((double)gw * h / w);
    gh = gh < 1 ? 1 : (gh > h ? h : gh);
    const uint64_t seed = (uint64_t)p->Seed;
    SqPerlin n[6] = {{0}};
    const int cl = cells_y(LARGE_CELLS, w, h), cs = cells_y(SMALL_CELLS, w, h);
    int bad = sq__perlin_init(&n[0], seed, SQ_STREAM_WARP_LARGE_X, LARGE_CELLS, cl) |
              sq__perlin_init(&n[1], seed, SQ_STREAM_WARP_LARGE_Y, LARGE_CELLS, cl) |
              sq__perlin_init(&n[2], seed, SQ_STREAM_WARP_LARGE_X + 100, 2 * LARGE_CELLS, 2 * cl) |
              sq__perlin_init(&n[3], seed, SQ_STREAM_WARP_LARGE_Y + 100, 2 * LARGE_CELLS, 2 * cl) |
              sq__perlin_init(&n[4], seed, SQ_STREAM_WARP_SMALL_X, SMALL_CELLS, cs) |
              sq__perlin_init(&n[5], seed, SQ_STREAM_WARP_SMALL_Y, SMALL_CELLS, cs);
    warp->dx = sq__falloc((size_t)gw * gh);
    warp->dy = sq__falloc((size_t)gw * gh);
    if (bad || !warp->dx || !warp->dy) {
        for (int k = 0; k < 6; k++)
            sq__perlin_free(&n[k]);
        sq__warp_free(warp);
        return sq_error_set(err, SQ_ERR_NOMEM, "warp", "out of memory for the warp");
    }
    warp->gw = gw;
    warp->gh = gh;
#pragma omp parallel for schedule(static)
    for (int j = 0; j < gh; j++) {
        double v = (j + 0.5) / gh;
        for (int i = 0; i < gw; i++) {
            double u = (i + 0.5) / gw;
            double lx = sq__perlin(&n[0], u, v) + 0.5 * sq__perlin(&n[2], u, v);
            double ly = sq__perlin(&n[1], u, v) + 0.5 * sq__perlin(&n[3], u, v);
            warp->dx[(size_t)j * gw + i] = (float)(big * lx / 1.5 + small * sq__perlin(&n[4], u, v));
            warp->dy[(size_t)j * gw + i] = (float)(big * ly / 1.5 + small * sq__perlin(&n[5], u, v));
        }
    }
    for (int k = 0; k < 6; k++)
        sq__perlin_free(&n[k]);
    return SQ_OK;
}
