/* The pattern as coverage layers: post-process (§4.2.4: rotate 90 degrees, blur,
 * contrast) and composition into one premultiplied RGBA image. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen_internal.h"

void sq__pattern_free(SqPattern *pat)
{
    for (int i = 0; i < pat->n; i++)
        sq__ffree(pat->layers[i].cov);
    pat->n = 0;
}

static size_t layer_len(const SqPattern *pat, SqLayerKind kind)
{
    switch (kind) {
    case SQ_LAYER_ROWS: return (size_t)pat->h;
    case SQ_LAYER_COLS: return (size_t)pat->w;
    case SQ_LAYER_2D: return (size_t)pat->w * pat->h;
    default: return 0;
    }
}

/* Rotates a layer 90 degrees clockwise: a (w x h) layer becomes (h x w):
 * new(x, y) = old(y, h - 1 - x). */
static SqStatus rotate_layer(SqPattern *pat, SqLayer *l, SqError *err)
{
    const int ow = pat->w, oh = pat->h, nw = oh;
    if (l->kind == SQ_LAYER_ROWS) { /* old depends on its y: new depends on x, reversed */
        for (int a = 0, b = oh - 1; a < b; a++, b--) {
            float t = l->cov[a];
            l->cov[a] = l->cov[b];
            l->cov[b] = t;
        }
        l->kind = SQ_LAYER_COLS;
    } else if (l->kind == SQ_LAYER_COLS) { /* old depends on its x: new depends on y */
        l->kind = SQ_LAYER_ROWS;
    } else if (l->kind == SQ_LAYER_2D) {
        float *r = sq__falloc((size_t)ow * oh);
        if (!r)
            return sq_error_set(err, SQ_ERR_NOMEM, "pattern", "out of memory rotating the pattern");
#pragma omp parallel for schedule(static)
        for (int y = 0; y < ow; y++)
            for (int x = 0; x < nw; x++)
                r[(size_t)y * nw + x] = l->cov[(size_t)(oh - 1 - x) * ow + y];
        sq__ffree(l->cov);
        l->cov = r;
    }
    return SQ_OK;
}

/* A wide Gaussian on a large image, computed where it is cheap: for sigma of 6 pixels
 * and more, on the image box-averaged by a power of two f (while f divides the sides),
 * then interpolated back. The box average and the interpolation blur too; their
 * variances ((f^2 - 1)/12 and about f^2/6 per axis) are taken out of the small blur. */
static int blur_2d(float *img, int w, int h, double sigma)
{
    int f = 1;
    while (sigma >= 6.0 * f && w % (2 * f) == 0 && h % (2 * f) == 0 && w / (2 * f) >= 32 &&
           h / (2 * f) >= 32)
        f *= 2;
    if (f == 1)
        return sq__blur(img, w, h, 1, sigma);
    const int dw = w / f, dh = h / f;
    float *small = sq__falloc_raw((size_t)dw * dh);
    if (!small)
        return -1;
    const float norm = 1.0f / (float)(f * f);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < dh; y++)
        for (int x = 0; x < dw; x++) {
            float sum = 0;
            for (int j = 0; j < f; j++) {
                const float *r = img + (size_t)(y * f + j) * w + (size_t)x * f;
                for (int i = 0; i < f; i++)
                    sum += r[i];
            }
            small[(size_t)y * dw + x] = sum * norm;
        }
    double var = sigma * sigma - (f * f - 1) / 12.0 - f * f / 6.0;
    int rc = sq__blur(small, dw, dh, 1, var > 0 ? sqrt(var) / f : 0);
    rc |= sq__resample(small, dw, dh, img, w, h);
    sq__ffree(small);
    return rc;
}

SqStatus sq__pattern_postprocess(const SqParams *p, SqPattern *pat, SqError *err)
{
    SqStatus st;
    if (p->Pattern_RotatePattern90Degrees) {
        for (int i = 0; i < pat->n; i++)
            if ((st = rotate_layer(pat, &pat->layers[i], err)) != SQ_OK)
                return st;
        int t = pat->w;
        pat->w = pat->h;
        pat->h = t;
    }
    const double sigma = sq__px(p->Pattern_BlurAmount, pat->w);
    const float c = (float)p->Pattern_Contrast;
    for (int i = 0; i < pat->n; i++) {
        SqLayer *l = &pat->layers[i];
        size_t n = layer_len(pat, l->kind);
        if (n == 0)
            continue;
        if (l->kind == SQ_LAYER_2D) {
            if (blur_2d(l->cov, pat->w, pat->h, sigma) != 0)
                return sq_error_set(err, SQ_ERR_NOMEM, "pattern", "out of memory blurring the pattern");
        } else if (sq__blur_line(l->cov, (int)n, sigma) != 0) {
            return sq_error_set(err, SQ_ERR_NOMEM, "pattern", "out of memory blurring the pattern");
        }
        if (c > 0.0f || l->has_levels) {
#pragma omp parallel for schedule(static)
            for (size_t k = 0; k < n; k++) {
                float v = sq__contrast(l->cov[k], c);
                if (l->has_levels)
                    v = sq__levels(v, l->levels[0], l->levels[1], l->levels[2]);
                l->cov[k] = v;
            }
        }
    }
    return SQ_OK;
}

void sq__pattern_composite(const SqPattern *pat, float *rgba)
{
    const int w = pat->w, h = pat->h;
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++) {
        float *row = rgba + (size_t)y * w * 4;
        memset(row, 0, sizeof(float) * (size_t)w * 4);
        for (int i = 0; i < pat->n; i++) {
            const SqLayer *l = &pat->layers[i];
            const float r = l->color[0], g = l->color[1], b = l->color[2], o = l->color[3];
            if (o <= 0.0f)
                continue;
            for (int x = 0; x < w; x++) {
                float cov = l->kind == SQ_LAYER_FULL   ? 1.0f
                            : l->kind == SQ_LAYER_ROWS ? l->cov[y]
                            : l->kind == SQ_LAYER_COLS ? l->cov[x]
                                                       : l->cov[(size_t)y * w + x];
                float a = cov * o, k = 1.0f - a;
                float *px = row + 4 * x;
                px[0] = r * a + px[0] * k;
                px[1] = g * a + px[1] * k;
                px[2] = b * a + px[2] * k;
                px[3] = a + px[3] * k;
            }
        }
    }
}

/* Adds a layer; its coverage buffer is allocated for the kind (zeroed). */
SqLayer *sq__pattern_add(SqPattern *pat, SqLayerKind kind, const double color[4], SqError *err)
{
    if (pat->n == SQ_MAX_LAYERS) {
        sq_error_set(err, SQ_ERR_INTERNAL, "pattern", "too many pattern layers");
        return NULL;
    }
    SqLayer *l = &pat->layers[pat->n];
    memset(l, 0, sizeof *l);
    l->kind = kind;
    for (int c = 0; c < 4; c++)
        l->color[c] = (float)color[c];
    size_t n = layer_len(pat, kind);
    if (n) {
        l->cov = sq__falloc(n);
        if (!l->cov) {
            sq_error_set(err, SQ_ERR_NOMEM, "pattern", "out of memory for a pattern layer");
            return NULL;
        }
    }
    pat->n++;
    return l;
}


