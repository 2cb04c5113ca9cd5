/* Wrap-around image filters: Gaussian blur by three box passes, levels, resampling. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "gen_internal.h"

static float *falloc(size_t n, int zero)
{
    if (n == 0 || n > SIZE_MAX / sizeof(float) - (2u << 20))
        return NULL;
    const size_t huge = (size_t)2 << 20;
    size_t bytes = n * sizeof(float);
    float *p;
    if (bytes >= huge) {
        bytes = (bytes + huge - 1) & ~(huge - 1);
        p = aligned_alloc(huge, bytes);
        if (!p)
            return NULL;
#ifdef MADV_HUGEPAGE
        madvise(p, bytes, MADV_HUGEPAGE);
#endif
        if (zero) {
            const size_t nchunks = bytes / huge;
#pragma omp parallel for schedule(static)
            for (size_t c = 0; c < nchunks; c++)
                memset((char *)p + c * huge, 0, huge);
        }
        return p;
    }
    bytes = (bytes + 63) & ~(size_t)63;
    p = aligned_alloc(64, bytes);
    if (p && zero)
        memset(p, 0, bytes);
    return p;
}

float *sq__falloc(size_t n)
{
    return falloc(n, 1);
}

float *sq__falloc_raw(size_t n)
{
    return falloc(n, 0);
}

int sq__image_raw(SqImage *img, int w, int h, int ch, SqColorSpace space)
{
    memset(img, 0, sizeof *img);
    img->px = falloc((size_t)w * h * ch, 0);
    if (!img->px)
        return -1;
    img->width = w;
    img->height = h;
    img->channels = ch;
    img->space = space;
    return 0;
}

void sq__ffree(float *p)
{
    free(p);
}

int sq__lerp_init(SqLerp *l, int n, int m)
{
    l->i0 = malloc(sizeof(int) * (size_t)n);
    l->i1 = malloc(sizeof(int) * (size_t)n);
    l->t = malloc(sizeof(float) * (size_t)n);
    if (!l->i0 || !l->i1 || !l->t) {
        sq__lerp_free(l);
        return -1;
    }
    const double scale = (double)m / n;
    for (int k = 0; k < n; k++) {
        double f = (k + 0.5) * scale - 0.5, fl = floor(f);
        l->i0[k] = sq__wrap((int)fl, m);
        l->i1[k] = l->i0[k] + 1 == m ? 0 : l->i0[k] + 1;
        l->t[k] = (float)(f - fl);
    }
    return 0;
}

void sq__lerp_free(SqLerp *l)
{
    free(l->i0);
    free(l->i1);
    free(l->t);
    l->i0 = l->i1 = NULL;
    l->t = NULL;
}

float sq__levels(float x, float lo, float hi, float mid)
{
    float t = hi > lo ? (x - lo) / (hi - lo) : (x >= lo ? 1.0f : 0.0f);
    t = sq__clamp01(t);
    if (mid > 0.0f && mid < 1.0f && mid != 0.5f)
        t = powf(t, logf(0.5f) / logf(mid)); /* mid maps to 0.5 */
    return t;
}

/* Radii of n box passes whose succession approximates a Gaussian of sigma (W. Jarosz,
 * "Fast image convolutions"; P. Kovesi 2010). */
static void box_radii(double sigma, int n, int *radii)
{
    double ideal = sqrt(12.0 * sigma * sigma / n + 1.0);
    int wl = (int)floor(ideal);
    if (wl % 2 == 0)
        wl--;
    int wu = wl + 2;
    double m_ideal = (12.0 * sigma * sigma - n * wl * wl - 4.0 * n * wl - 3.0 * n) / (-4.0 * wl - 4.0);
    int m = (int)lround(m_ideal);
    for (int i = 0; i < n; i++)
        radii[i] = ((i < m ? wl : wu) - 1) / 2;
}

/* One horizontal box pass of radius r over a row of w pixels x ch channels; ext is
 * scratch of (w + 2r + 1) floats. */
static void box_row(float *row, int w, int ch, int r, float *ext)
{
    const float norm = 1.0f / (float)(2 * r + 1);
    for (int c = 0; c < ch; c++) {
        for (int i = 0; i <= w + 2 * r; i++)
            ext[i] = row[sq__wrap(i - r, w) * ch + c];
        double sum = 0;
        for (int i = 0; i < 2 * r + 1; i++)
            sum += ext[i];
        for (int x = 0; x < w; x++) {
            row[x * ch + c] = (float)sum * norm;
            sum += ext[x + 2 * r + 1] - ext[x];
        }
    }
}

int sq__blur_line(float *line, int n, double sigma)
{
    if (sigma < 0.5 || n < 2)
        return 0;
    int radii[3];
    box_radii(sigma, 3, radii);
    int rmax = radii[0] > radii[2] ? radii[0] : radii[2];
    float *ext = malloc(sizeof(float) * (size_t)(n + 2 * rmax + 1));
    if (!ext)
        return -1;
    for (int k = 0; k < 3; k++)
        if (radii[k] > 0)
            box_row(line, n, 1, radii[k], ext);
    free(ext);
    return 0;
}

enum { STRIP = 64 }; /* columns blurred together in the vertical pass */

int sq__blur(float *img, int w, int h, int ch, double sigma)
{
    if (sigma < 0.5)
        return 0;
    int radii[3];
    box_radii(sigma, 3, radii);
    int rmax = radii[0] > radii[2] ? radii[0] : radii[2];
    const int wc = w * ch; /* floats per row */
    int failed = 0;

#pragma omp parallel
    {
        float *ext = malloc(sizeof(float) * (size_t)(w + 2 * rmax + 1));
        float *col = malloc(sizeof(float) * (size_t)h * STRIP);
        if (!ext || !col) {
#pragma omp atomic write
            failed = 1;
        }
#pragma omp barrier
        if (!failed) {
            /* horizontal passes, row by row */
#pragma omp for schedule(static)
            for (int y = 0; y < h; y++)
                for (int k = 0; k < 3; k++)
                    if (radii[k] > 0)
                        box_row(img + (size_t)y * wc, w, ch, radii[k], ext);

            /* vertical passes, STRIP columns at a time (rows stay contiguous) */
#pragma omp for schedule(static)
            for (int x0 = 0; x0 < wc; x0 += STRIP) {
                int n = wc - x0 < STRIP ? wc - x0 : STRIP;
                for (int k = 0; k < 3; k++) {
                    int r = radii[k];
                    if (r == 0)
                        continue;
                    const float norm = 1.0f / (float)(2 * r + 1);
                    for (int y = 0; y < h; y++)
                        memcpy(col + (size_t)y * STRIP, img + (size_t)y * wc + x0,
                               sizeof(float) * (size_t)n);
                    double sum[STRIP];
                    for (int i = 0; i < n; i++)
                        sum[i] = 0;
                    for (int d = -r; d <= r; d++) {
                        const float *src = col + (size_t)sq__wrap(d, h) * STRIP;
                        for (int i = 0; i < n; i++)
                            sum[i] += src[i];
                    }
                    for (int y = 0; y < h; y++) {
                        float *dst = img + (size_t)y * wc + x0;
                        for (int i = 0; i < n; i++)
                            dst[i] = (float)sum[i] * norm;
                        const float *add = col + (size_t)sq__wrap(y + r + 1, h) * STRIP;
                        const float *sub = col + (size_t)sq__wrap(y - r, h) * STRIP;
                        for (int i = 0; i < n; i++)
                            sum[i] += add[i] - sub[i];
                    }
                }
            }
        }
        free(ext);
        free(col);
    }
    return failed ? -1 : 0;
}

int sq__resample(const float *src, int sw, int sh, float *dst, int dw, int dh)
{
    SqLerp lx = {0}, ly = {0};
    if (sq__lerp_init(&lx, dw, sw) || sq__lerp_init(&ly, dh, sh)) {
        sq__lerp_free(&lx);
        return -1;
    }
#pragma omp parallel for schedule(static)
    for (int y = 0; y < dh; y++) {
        const float *r0 = src + (size_t)ly.i0[y] * sw, *r1 = src + (size_t)ly.i1[y] * sw;
        const float ty = ly.t[y];
        float *out = dst + (size_t)y * dw;
        for (int x = 0; x < dw; x++) {
            float a = r0[lx.i0[x]] + (r0[lx.i1[x]] - r0[lx.i0[x]]) * lx.t[x];
            float b = r1[lx.i0[x]] + (r1[lx.i1[x]] - r1[lx.i0[x]]) * lx.t[x];
            out[x] = a + (b - a) * ty;
        }
    }
    sq__lerp_free(&lx);
    sq__lerp_free(&ly);
    return 0;
}
