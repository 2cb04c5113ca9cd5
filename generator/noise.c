/* Periodic noise: Perlin gradient noise (the warp, §4.2.7) and a fractal sum of smooth
 * value noise (micro detail and roughness, §4.3.2, §4.4). Both repeat exactly over the
 * texture, so the maps tile. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen_internal.h"

static inline double fade(double t)
{
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

int sq__perlin_init(SqPerlin *n, uint64_t seed, uint64_t stream, int cx, int cy)
{
    n->cx = cx;
    n->cy = cy;
    n->g = malloc(sizeof(float) * 2 * (size_t)cx * cy);
    if (!n->g)
        return -1;
    for (int j = 0; j < cy; j++)
        for (int i = 0; i < cx; i++) {
            double a = 6.283185307179586 * sq__rand01(seed, stream, ((uint64_t)(uint32_t)i << 32) | (uint32_t)j);
            n->g[2 * (j * cx + i)] = (float)cos(a);
            n->g[2 * (j * cx + i) + 1] = (float)sin(a);
        }
    return 0;
}

void sq__perlin_free(SqPerlin *n)
{
    free(n->g);
    n->g = NULL;
}

float sq__perlin(const SqPerlin *n, double u, double v)
{
    const int cx = n->cx, cy = n->cy;
    double x = u * cx, y = v * cy;
    double fx = floor(x), fy = floor(y);
    int i0 = sq__wrap((int)fx, cx), j0 = sq__wrap((int)fy, cy);
    int i1 = i0 + 1 == cx ? 0 : i0 + 1, j1 = j0 + 1 == cy ? 0 : j0 + 1;
    float tx = (float)(x - fx), ty = (float)(y - fy);
    const float *g00 = n->g + 2 * (j0 * cx + i0), *g10 = n->g + 2 * (j0 * cx + i1);
    const float *g01 = n->g + 2 * (j1 * cx + i0), *g11 = n->g + 2 * (j1 * cx + i1);
    float n00 = g00[0] * tx + g00[1] * ty;
    float n10 = g10[0] * (tx - 1) + g10[1] * ty;
    float n01 = g01[0] * tx + g01[1] * (ty - 1);
    float n11 = g11[0] * (tx - 1) + g11[1] * (ty - 1);
    float sx = (float)fade(tx), sy = (float)fade(ty);
    float a = n00 + (n10 - n00) * sx, b = n01 + (n11 - n01) * sx;
    return (a + (b - a) * sy) * 1.41421356f;
}

/* One octave of value noise with cx x cy lattice cells, cubic-smoothed, sampled at
 * rx x ry pixels, added with amplitude amp. */
static int value_octave(float *img, int rx, int ry, uint64_t seed, uint64_t stream, int cx,
                        int cy, float amp)
{
    float *lat = malloc(sizeof(float) * (size_t)cx * cy);
    int *i0 = malloc(sizeof(int) * (size_t)rx * 2);
    float *sx = malloc(sizeof(float) * (size_t)rx);
    if (!lat || !i0 || !sx) {
        free(lat);
        free(i0);
        free(sx);
        return -1;
    }
    for (int j = 0; j < cy; j++)
        for (int i = 0; i < cx; i++)
            lat[j * cx + i] = (float)sq__rand11(seed, stream, (uint64_t)j * 65536u + (uint64_t)i);
    for (int x = 0; x < rx; x++) {
        double fx = ((double)x + 0.5) / rx * cx, fl = floor(fx), tx = fx - fl;
        i0[2 * x] = sq__wrap((int)fl, cx);
        i0[2 * x + 1] = i0[2 * x] + 1 == cx ? 0 : i0[2 * x] + 1;
        sx[x] = (float)(tx * tx * (3 - 2 * tx));
    }
#pragma omp parallel for schedule(static)
    for (int y = 0; y < ry; y++) {
        double fy = ((double)y + 0.5) / ry * cy;
        int j0 = (int)floor(fy);
        double ty = fy - j0;
        float sy = (float)(ty * ty * (3 - 2 * ty));
        const float *r0 = lat + (size_t)sq__wrap(j0, cy) * cx, *r1 = lat + (size_t)sq__wrap(j0 + 1, cy) * cx;
        float *out = img + (size_t)y * rx;
        for (int x = 0; x < rx; x++) {
            int a = i0[2 * x], b = i0[2 * x + 1];
            float top = r0[a] + (r0[b] - r0[a]) * sx[x], bot = r1[a] + (r1[b] - r1[a]) * sx[x];
            out[x] += amp * (top + (bot - top) * sy);
        }
    }
    free(lat);
    free(i0);
    free(sx);
    return 0;
}

float *sq__fbm_coarse(int w, int h, uint64_t seed, uint64_t stream, int cells, int octaves,
                     double gain, int *rx_out, int *ry_out)
{
    /* Pyramid: each octave is evaluated at about 4 pixels per lattice cell, the running
     * sum upsampled as the resolution grows; the cost stays near 4/3 of the finest level. */
    float *acc = NULL;
    int ax = 0, ay = 0;
    double amp = 1.0;
    for (int k = 0; k < octaves; k++, amp *= gain) {
        int cx = cells << k;
        if (cx > w / 2 && k > 0)
            break;
        int cy = (int)lround((double)cx * h / w);
        if (cy < 1)
            cy = 1;
        int rx = cx * 4 < w ? cx * 4 : w, ry = cy * 4 < h ? cy * 4 : h;
        float *lvl = sq__falloc((size_t)rx * ry);
        if (!lvl) {
            sq__ffree(acc);
            return NULL;
        }
        int bad = acc ? sq__resample(acc, ax, ay, lvl, rx, ry) : 0;
        sq__ffree(acc);
        acc = lvl;
        if (bad || value_octave(lvl, rx, ry, seed, stream * 64 + (uint64_t)k, cx, cy, (float)amp)) {
            sq__ffree(acc);
            return NULL;
        }
        ax = rx;
        ay = ry;
    }
    float lo = acc[0], hi = acc[0];
    for (size_t i = 0; i < (size_t)ax * ay; i++) {
        lo = acc[i] < lo ? acc[i] : lo;
        hi = acc[i] > hi ? acc[i] : hi;
    }
    const float s = hi > lo ? 1.0f / (hi - lo) : 0.0f;
    for (size_t i = 0; i < (size_t)ax * ay; i++)
        acc[i] = (acc[i] - lo) * s;
    *rx_out = ax;
    *ry_out = ay;
    return acc;
}

int sq__fbm(float *out, int w, int h, uint64_t seed, uint64_t stream, int cells, int octaves,
            double gain)
{
    int ax, ay;
    float *acc = sq__fbm_coarse(w, h, seed, stream, cells, octaves, gain, &ax, &ay);
    if (!acc)
        return -1;
    /* bilinear resampling stays inside [0, 1] */
    int rc = 0;
    if (ax != w || ay != h)
        rc = sq__resample(acc, ax, ay, out, w, h);
    else
        memcpy(out, acc, sizeof(float) * (size_t)w * h);
    sq__ffree(acc);
    return rc;
}
