/* The height map: one leaf-shaped scale (§4.3.1) tiled over the texture (§4.3.2) with
 * the ventral scales stretched at the belly (§4.3.3).
 *
 * The single scale is the minimum of two cones shifted left and right (a leaf), with
 * raised midtones, blurred, contrasted, multiplied by a vertical gradient that rises
 * towards its free (lower) edge, plus an optional keel and ridge. It is stamped
 * Scales_XAmount x Scales_YAmount times, every row shifted by about half a scale
 * (exactly floor(Y/2)/Y of a column, so the shifts add up to whole columns over the
 * texture and it tiles), painted from the bottom row up so upper rows cover lower ones,
 * and left to right. A scale's lens is Scales_ScaleSize x Scales_ScaleSizeXY[0] columns
 * wide and Scales_ScaleSize x Scales_ScaleSizeXY[1] rows tall.
 *
 * Ventral scales: in every row, the scale whose centre is nearest Scales_BellyScalesPct
 * of the width (and nearest 1 - that) is the last lateral scale; scales beyond it are
 * left out and its centre column is stretched to the seam, giving one wide ventral
 * scale per row across the belly.
 *
 * With Scales_Layout voronoi the scales sit on a relaxed Voronoi tessellation instead
 * (voronoi.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen_internal.h"

static const double CONE_R = SQ__CONE_R, CONE_D = SQ__CONE_D;
#define LENS_HW SQ__LENS_HW
#define LENS_HH SQ__LENS_HH

int sq__scale_stamp(const SqParams *p, float *stamp, int s)
{
    const double gamma = 1.0 / (1.0 + 8.0 * p->ScaleShape_Contrast);
    const double grow = 1.0 + 0.3 * p->Scales_Expansion;
    const double r = CONE_R * grow, d = CONE_D * grow;
    float *lens = sq__falloc((size_t)s * s);
    if (!lens)
        return -1;
    for (int j = 0; j < s; j++) {
        double Y = (j + 0.5) / s * 2 - 1;
        for (int i = 0; i < s; i++) {
            double X = (i + 0.5) / s * 2 - 1;
            double c1 = 1 - sqrt((X - d) * (X - d) + Y * Y) / r;
            double c2 = 1 - sqrt((X + d) * (X + d) + Y * Y) / r;
            double c = c1 < c2 ? c1 : c2;
            lens[j * s + i] = c > 0 ? (float)pow(c, gamma) : 0.0f;
        }
    }
    /* the stamp has an empty margin, so the wrap-around of the blur is harmless */
    if (sq__blur(lens, s, s, 1, p->ScaleShape_Blur * s / 256.0) != 0) {
        sq__ffree(lens);
        return -1;
    }

    const double g = p->ScaleShape_Gradient;
    const double keel_hw = p->ScaleShape_KeelThickness * LENS_HW;
    float hmax = 0;
    for (int j = 0; j < s; j++) {
        double Y = (j + 0.5) / s * 2 - 1;
        double t = (Y / (LENS_HH * grow) + 1) / 2; /* 0 at the top of the lens, 1 at its bottom */
        t = t < 0 ? 0 : (t > 1 ? 1 : t);
        double m = 1 - g + g * t;
        double keel_x = p->ScaleShape_KeelDistortion * 0.12 * sin(9.0 * Y + 1.3);
        for (int i = 0; i < s; i++) {
            double X = (i + 0.5) / s * 2 - 1;
            float v = sq__contrast(lens[j * s + i], 0.3f);
            float a = sq__clamp01(v * 10.0f); /* occlusion: solid inside the lens */
            double hgt = v * m;
            if (p->ScaleShape_IsKeeled && keel_hw > 0) {
                double k = 1 - fabs(X - keel_x) / keel_hw;
                if (k > 0)
                    hgt += 0.35 * k * a * m;
            }
            double rx = X / (LENS_HW * grow);
            if (p->ScaleShape_Ridge > 0 && rx * rx < 1)
                hgt += p->ScaleShape_Ridge * 0.5 * (1 - rx * rx) * a * m;
            stamp[2 * (j * s + i)] = (float)hgt;
            stamp[2 * (j * s + i) + 1] = a;
            if (hgt > hmax)
                hmax = (float)hgt;
        }
    }
    if (hmax > 0)
        for (int k = 0; k < s * s; k++)
            stamp[2 * k] /= hmax;
    sq__ffree(lens);
    return 0;
}

typedef struct Layout {
    int X, Y;
    double shift;     /* columns per row */
    double lens_w, lens_h; /* lens size: columns, rows */
    uint64_t seed;
    const SqParams *p;
    int *left, *right; /* per row: the column of the last lateral scale, or -1 */
} Layout;

/* Centre of scale (c, j) in columns and rows (unwrapped by the caller). */
static void scale_centre(const Layout *L, int c, int j, double *u, double *v)
{
    uint64_t id = ((uint64_t)j * (uint64_t)L->X + (uint64_t)c) * 4;
    *u = c + 0.5 + j * L->shift + L->p->Scales_PositionRandom[0] * sq__rand11(L->seed, SQ_STREAM_SCALES, id);
    *v = j + 0.5 + L->p->Scales_PositionRandom[1] * sq__rand11(L->seed, SQ_STREAM_SCALES, id + 1);
}

static double frac(double x)
{
    return x - floor(x);
}

/* For each row, the columns of the last lateral scales next to the belly. */
static void find_belly(Layout *L)
{
    const double pct = L->p->Scales_BellyScalesPct;
    for (int j = 0; j < L->Y; j++) {
        L->left[j] = L->right[j] = -1;
        if (pct <= 0)
            continue;
        double bl = 2, br = 2;
        for (int c = 0; c < L->X; c++) {
            double u, v;
            scale_centre(L, c, j, &u, &v);
            double f = frac(u / L->X);
            if (fabs(f - pct) < bl) {
                bl = fabs(f - pct);
                L->left[j] = c;
            }
            if (fabs(f - (1 - pct)) < br) {
                br = fabs(f - (1 - pct));
                L->right[j] = c;
            }
        }
    }
}

/* 0: a lateral scale; 1: the last one on the left (belly to its left); 2: on the right;
 * 3: both (a belly wider than the back); -1: inside the belly, not drawn. */
static int belly_role(const Layout *L, int c, int j)
{
    if (L->left[j] < 0)
        return 0;
    double u, v, ul, ur;
    scale_centre(L, c, j, &u, &v);
    scale_centre(L, L->left[j], j, &ul, &v);
    scale_centre(L, L->right[j], j, &ur, &v);
    double f = frac(u / L->X), fl = frac(ul / L->X), fr = frac(ur / L->X);
    int role = (c == L->left[j] ? 1 : 0) | (c == L->right[j] ? 2 : 0);
    if (role)
        return role;
    return (f < fl || f > fr) ? -1 : 0;
}

SqStatus sq__scales(const SqParams *p, float *height, float *scratch, int w, int h, SqError *err)
{
    if (p->Scales_Layout == SQ_LAYOUT_VORONOI)
        return sq__scales_voronoi(p, height, scratch, w, h, err);
    Layout L = {.X = p->Scales_XAmount, .Y = p->Scales_YAmount, .seed = (uint64_t)p->Seed, .p = p};
    L.shift = (double)(L.Y / 2) / L.Y;
    L.lens_w = p->Scales_ScaleSize * p->Scales_ScaleSizeXY[0];
    L.lens_h = p->Scales_ScaleSize * p->Scales_ScaleSizeXY[1];
    if (L.lens_w <= 0 || L.lens_h <= 0) {
        memset(height, 0, sizeof(float) * (size_t)w * h);
        return SQ_OK;
    }

    const double colw = (double)w / L.X, rowh = (double)h / L.Y; /* pixels */
    /* pixels per stamp unit: the lens (LENS_HW half-width) spans lens_w columns */
    const double ax = L.lens_w * colw / 2 / LENS_HW, ay = L.lens_h * rowh / 2 / LENS_HH;
    int s = 32;
    while (s < 512 && (s < 2 * ax || s < 2 * ay)) /* no axis undersampled */
        s *= 2;
    /* When one texel of the largest stamp spans more than 1.25 pixels, the tiling holds
     * no detail a half-resolution tiling would miss: render it there (into the scratch
     * buffer, which has room for both half-size images) and interpolate up. */
    if (2 * (ax > ay ? ax : ay) / s > 1.25 && w % 2 == 0 && h % 2 == 0 && w >= 512 && h >= 512) {
        float *half_h = scratch, *half_t = scratch + (size_t)(w / 2) * (h / 2);
        SqStatus st = sq__scales(p, half_h, half_t, w / 2, h / 2, err);
        if (st == SQ_OK && sq__resample(half_h, w / 2, h / 2, height, w, h) != 0)
            st = sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
        return st;
    }
    float *stamp = sq__falloc((size_t)2 * s * s);
    L.left = malloc(sizeof(int) * (size_t)L.Y);
    L.right = malloc(sizeof(int) * (size_t)L.Y);
    if (!stamp || !L.left || !L.right) {
        sq__ffree(stamp);
        free(L.left);
        free(L.right);
        return sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
    }
    if (sq__scale_stamp(p, stamp, s) != 0) {
        sq__ffree(stamp);
        free(L.left);
        free(L.right);
        return sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
    }
    find_belly(&L);

    /* extent of the stamp's content, stamp units */
    double ex = 0, ey = 0;
    for (int j = 0; j < s; j++)
        for (int i = 0; i < s; i++)
            if (stamp[2 * (j * s + i) + 1] > 0 || stamp[2 * (j * s + i)] > 0) {
                double X = fabs((i + 0.5) / s * 2 - 1) + 1.0 / s, Y = fabs((j + 0.5) / s * 2 - 1) + 1.0 / s;
                ex = X > ex ? X : ex;
                ey = Y > ey ? Y : ey;
            }
    /* per stamp row, the columns with content: unrotated scales visit only those */
    int *span = malloc(sizeof(int) * 2 * (size_t)s);
    if (!span) {
        sq__ffree(stamp);
        free(L.left);
        free(L.right);
        return sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
    }
    for (int j = 0; j < s; j++) {
        span[2 * j] = s;
        span[2 * j + 1] = -1;
        for (int i = 0; i < s; i++)
            if (stamp[2 * (j * s + i) + 1] > 0 || stamp[2 * (j * s + i)] > 0) {
                span[2 * j] = i < span[2 * j] ? i : span[2 * j];
                span[2 * j + 1] = i;
            }
    }
    const double rot_max = p->Scales_RotationRandom * M_PI / 180.0;
    double rx = ex * ax, ry = ey * ay; /* pixel half-extents */
    if (rot_max > 0) {
        double rr = sqrt(rx * rx + ry * ry);
        rx = ry = rr;
    }
    const int kx = (int)ceil(rx / colw + p->Scales_PositionRandom[0]) + 2;
    const double belly_amp = p->Scales_BellyWarpIntensity / 256.0 * h * 0.1;
    const int half = L.Y / 2;
    float *trans = scratch;                         /* light still passing, front to back */
    float *wob = malloc(sizeof(float) * (size_t)w); /* the belly's wobble across u */
    if (!wob) {
        sq__ffree(stamp);
        free(L.left);
        free(L.right);
        return sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
    }
    for (int x = 0; x < w; x++)
        wob[x] = (float)(belly_amp * sin(2 * M_PI * 2 * (x + 0.5) / w));

    /* Painted front to back: the top row first (upper rows cover lower ones) and, in a
     * row, right to left (the right scale covers its left neighbour). Each pixel keeps
     * the light still passing (trans); a pixel already covered is skipped. The result is
     * the painter's algorithm from the bottom row up, left to right. */
    const int band = 32, nbands = (h + band - 1) / band;
#pragma omp parallel for schedule(dynamic, 1)
    for (int bi = 0; bi < nbands; bi++) {
        const int y0 = bi * band, y1 = y0 + band < h ? y0 + band : h;
        for (size_t i = (size_t)y0 * w; i < (size_t)y1 * w; i++) {
            trans[i] = 1.0f;
            height[i] = 0.0f;
        }
        const double pry = p->Scales_PositionRandom[1];
        const int j_hi = (int)floor((y1 + ry) / rowh + pry) + 1;
        const int j_lo = (int)floor((y0 - ry) / rowh - pry) - 1;
        for (int jj = j_lo; jj <= j_hi; jj++) {
            const int j = sq__wrap(jj, L.Y), m = (jj - j) / L.Y;
            /* instance ii of row jj sits near column ii + jj * shift: cover the image */
            const int ii_lo = (int)floor(-kx - jj * L.shift), ii_hi = (int)ceil(L.X + kx - jj * L.shift);
            for (int ii = ii_hi - 1; ii >= ii_lo; ii--) {
                const int c = sq__wrap(ii + m * half, L.X);
                const int role = belly_role(&L, c, j);
                if (role < 0)
                    continue;
                double u, v;
                scale_centre(&L, c, j, &u, &v);
                /* unwrapped centre, pixels */
                const double cx = (u + (ii + m * half - c)) * colw;
                const double cy = (v + (double)m * L.Y) * rowh;
                int sx0, sx1, sy0, sy1;
                if (!sq__stamp_footprint(cx, cy, rx, ry, role, w, y0, y1, &sx0, &sx1, &sy0, &sy1))
                    continue;
                const uint64_t id = ((uint64_t)j * (uint64_t)L.X + (uint64_t)c) * 4;
                const double size = 1.0 - p->Scales_SizeRandom * sq__rand01(L.seed, SQ_STREAM_SCALES, id + 2);
                const double th = rot_max * sq__rand11(L.seed, SQ_STREAM_SCALES, id + 3);
                const float cs = (float)cos(th), sn = (float)sin(th);
                const float iax = (float)(1.0 / (ax * size)), iay = (float)(1.0 / (ay * size));
                const float half_s = 0.5f * (float)s;
                for (int y = sy0; y < sy1; y++) {
                    float *row = height + (size_t)y * w, *tr = trans + (size_t)y * w;
                    const float dy0 = (float)(y + 0.5 - cy);
                    const float belly_v = belly_amp > 0 ? (float)sin(2 * M_PI * (y + 0.5) / h * 3 + j) : 0.0f;
                    int xa = sx0, xb = sx1;
                    if (th == 0) { /* only the columns where this stamp row has content */
                        float fyr = (dy0 * iay + 1) * half_s - 0.5f;
                        int r0 = (int)fyr, r1 = r0 + 1;
                        if (fyr < 0 || r1 >= s)
                            continue;
                        int lo = span[2 * r0] < span[2 * r1] ? span[2 * r0] : span[2 * r1];
                        int hi = span[2 * r0 + 1] > span[2 * r1 + 1] ? span[2 * r0 + 1] : span[2 * r1 + 1];
                        if (lo > hi && !role)
                            continue;
                        double xl = cx + ((lo - 0.5) / half_s - 1) / iax, xr = cx + ((hi + 1.5) / half_s - 1) / iax;
                        if (!(role & 1) && xl > xa)
                            xa = (int)floor(xl);
                        if (!(role & 2) && xr < xb)
                            xb = (int)ceil(xr);
                        if (lo > hi) { /* empty row: only the ventral extension is left */
                            if (role & 1) xb = (int)ceil(cx);
                            if (role & 2) xa = (int)floor(cx);
                        }
                    }
                    for (int x = xa; x < xb; x++) {
                        if (tr[x] <= 0.0f)
                            continue;
                        float dx = (float)(x + 0.5 - cx), dy = dy0;
                        if (((role & 1) && dx < 0) || ((role & 2) && dx > 0)) {
                            /* the ventral scale: this scale's centre column, stretched */
                            dx = 0;
                            dy += wob[x] * belly_v;
                        }
                        sq__stamp_over(stamp, s, (dx * cs + dy * sn) * iax, (-dx * sn + dy * cs) * iay,
                                       &row[x], &tr[x]);
                    }
                }
            }
        }
    }
    free(wob);
    sq__ffree(stamp);
    free(span);
    free(L.left);
    free(L.right);
    return SQ_OK;
}
