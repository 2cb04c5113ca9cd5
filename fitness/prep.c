/* Photo preparation: mask, centre line, straightening, light (see squama/fitness.h).
 *
 * The centre line is the longest path through the mask's skeleton; where the body is
 * much wider or thinner than its median (crossings, touching parts, the tail) the path is
 * not trusted, and every run of trusted path a body width long or more is straightened,
 * the runs one after another in the strip (a coiled snake shows several). Across the body the
 * photo is sampled at d = r sin(theta) for theta evenly spaced in +-60 degrees, so the
 * strip's columns are equal lengths of skin; along it, rows are the same length apart. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cv_bridge.h"
#include "fitness_internal.h"
#include "gen_internal.h"
#include "squama/io.h"

#define THETA_MAX (M_PI * SQ_FIT_BAND_WIDTH) /* half the band: 60 degrees */

SqPrepOptions sq_fit_prep_options_default(void)
{
    SqPrepOptions o = {.work_size = 1024, .debug_dir = NULL};
    return o;
}

void sq_fit_prepared_free(SqPrepared *p)
{
    if (!p)
        return;
    sq_image_free(&p->photo);
    sq_image_free(&p->mask);
    sq_image_free(&p->strip);
    sq_image_free(&p->valid);
    free(p->centre);
    free(p->run_points);
    memset(p, 0, sizeof *p);
}

const char *sq_mask_source_name(SqMaskSource s)
{
    static const char *const name[] = {"given", "alpha", "automatic", "line"};
    return s >= SQ_MASK_GIVEN && s <= SQ_MASK_LINE ? name[s] : "unknown";
}

SqStatus sq_fit_prepared_line(const SqPrepared *p, SqBodyLine *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    const double gap = fmax(0.5 * p->body_width, 2.0);
    out->count = calloc((size_t)(p->nruns > 0 ? p->nruns : 1), sizeof(int));
    out->xy = malloc(sizeof(float) * 2 * (size_t)(p->npoints + 2 * p->nruns + 1));
    if (!out->count || !out->xy) {
        sq_body_line_free(out);
        return sq_error_set(err, SQ_ERR_NOMEM, "body line", "out of memory");
    }
    out->width = p->body_width;
    int j = 0;
    for (int k = 0, i0 = 0; k < p->nruns; i0 += p->run_points[k++]) {
        const int n = p->run_points[k];
        if (n < 2)
            continue;
        /* the first point, then one each `gap` along, and the last */
        double since = 0;
        int m = 0;
        for (int i = 0; i < n; i++) {
            const float *c = p->centre + 2 * (size_t)(i0 + i);
            if (i > 0)
                since += hypot(c[0] - c[-2], c[1] - c[-1]);
            if (i == 0 || i == n - 1 || since >= gap) {
                out->xy[2 * j] = c[0];
                out->xy[2 * j + 1] = c[1];
                j++;
                m++;
                since = 0;
            }
        }
        out->count[out->nstretches++] = m;
    }
    if (out->nstretches == 0) {
        sq_body_line_free(out);
        return sq_error_set(err, SQ_ERR_INVALID, "body line", "the preparation followed no centre line");
    }
    return SQ_OK;
}

double sq_fit_strip_blur(double step, double edge_blur)
{
    if (!(step > 0))
        return 0;
    const double e = edge_blur > 0 ? edge_blur : 0.5, v = (e / step) * (e / step) - 1.0 / 12;
    return v > 0 ? fmin(sqrt(v), SQ_FIT_BLUR_MAX) : 0;
}

SqStatus sq_fit_photo_target(const SqPrepared *p, SqFeatures *target, SqError *err)
{
    SqStatus st = sq_fit_features(&p->strip, &p->valid, target, err);
    if (st == SQ_OK) {
        target->light = p->light;
        target->blur = (float)sq_fit_strip_blur(p->step, p->edge_blur);
    }
    return st;
}

static void debug_save(const SqPrepOptions *o, const char *name, const SqImage *img)
{
    if (!o->debug_dir || !img->px)
        return;
    char path[4096];
    SqError err;
    snprintf(path, sizeof path, "%s/%s", o->debug_dir, name);
    if (sq_io_write_image(path, img, NULL, &err) != SQ_OK)
        fprintf(stderr, "squama: cannot save a debug image: %s (%s)\n", err.what, err.where);
}

/* Zhang-Suen thinning (Zhang & Suen 1984, as OpenCV's ximgproc has it) of the mask's
 * nonzero pixels to a one-pixel skeleton of 255s, within the mask's bounding box and a pixel
 * of margin. The box's own edge is kept as it is (OpenCV's rule): where the body touches the
 * image's edge, so does its skeleton. Written here rather than taken from ximgproc, which
 * brings GDAL, HDF5 and a hundred more libraries with it: a tenth of a second at every start
 * of squama. Returns 0, or -1 out of memory. */
int sq__thin(const uint8_t *mask, int w, int h, uint8_t *skel)
{
    int x0 = w, y0 = h, x1 = -1, y1 = -1;
    size_t body = 0;
    memset(skel, 0, (size_t)w * h);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            if (mask[(size_t)y * w + x]) {
                x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
                y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
                skel[(size_t)y * w + x] = 1;
                body++;
            }
    if (!body)
        return 0;
    x0 = x0 > 0 ? x0 - 1 : 0, y0 = y0 > 0 ? y0 - 1 : 0;
    x1 = x1 < w - 1 ? x1 + 1 : w - 1, y1 = y1 < h - 1 ? y1 + 1 : h - 1;
    size_t *live = malloc(sizeof *live * body), *gone = malloc(sizeof *gone * body), n = 0;
    if (!live || !gone) {
        free(live), free(gone);
        return -1;
    }
    for (int y = y0 + 1; y < y1; y++) /* the pixels that may go: the body's, off the box's edge */
        for (int x = x0 + 1; x < x1; x++)
            if (skel[(size_t)y * w + x])
                live[n++] = (size_t)y * w + x;
    for (int changed = 1; changed;) {
        changed = 0;
        for (int pass = 0; pass < 2; pass++) {
            size_t ng = 0;
            for (size_t k = 0; k < n; k++) {
                const uint8_t *p = skel + live[k];
                const int p2 = p[-w], p3 = p[1 - w], p4 = p[1], p5 = p[w + 1], p6 = p[w], p7 = p[w - 1],
                          p8 = p[-1], p9 = p[-w - 1];
                const int a = (!p2 && p3) + (!p3 && p4) + (!p4 && p5) + (!p5 && p6) + (!p6 && p7) +
                              (!p7 && p8) + (!p8 && p9) + (!p9 && p2); /* 0-to-1 steps around it */
                const int b = p2 + p3 + p4 + p5 + p6 + p7 + p8 + p9;
                const int m1 = pass == 0 ? p2 && p4 && p6 : p2 && p4 && p8;
                const int m2 = pass == 0 ? p4 && p6 && p8 : p2 && p6 && p8;
                if (a == 1 && b >= 2 && b <= 6 && !m1 && !m2)
                    gone[ng++] = live[k];
            }
            for (size_t g = 0; g < ng; g++) /* after the pass: each pixel judged on the same image */
                skel[gone[g]] = 0;
            if (ng) {
                changed = 1;
                size_t m = 0;
                for (size_t k = 0; k < n; k++)
                    if (skel[live[k]])
                        live[m++] = live[k];
                n = m;
            }
        }
    }
    free(live), free(gone);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            skel[(size_t)y * w + x] = skel[(size_t)y * w + x] ? 255 : 0;
    return 0;
}

/* The longest path (in pixels) through the skeleton: the farthest pixel from any pixel,
 * then the farthest from that one (exact for a tree). Returns the path's length and its
 * pixel indices in path (malloc'd). */
static int longest_path(const uint8_t *skel, int w, int h, int **path)
{
    *path = NULL;
    int n = w * h, start = -1;
    for (int i = 0; i < n && start < 0; i++)
        if (skel[i])
            start = i;
    if (start < 0)
        return 0;
    int *dist = malloc(sizeof(int) * (size_t)n), *parent = malloc(sizeof(int) * (size_t)n);
    int *queue = malloc(sizeof(int) * (size_t)n);
    if (!dist || !parent || !queue) {
        free(dist);
        free(parent);
        free(queue);
        return -1;
    }
    int far = start;
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < n; i++)
            dist[i] = -1;
        int head = 0, tail = 0;
        queue[tail++] = far;
        dist[far] = 0;
        parent[far] = -1;
        int last = far;
        while (head < tail) {
            int k = queue[head++], x = k % w, y = k / w;
            last = k;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int xx = x + dx, yy = y + dy;
                    if ((!dx && !dy) || xx < 0 || yy < 0 || xx >= w || yy >= h)
                        continue;
                    int q = yy * w + xx;
                    if (skel[q] && dist[q] < 0) {
                        dist[q] = dist[k] + 1;
                        parent[q] = k;
                        queue[tail++] = q;
                    }
                }
        }
        far = last; /* BFS visits in order of distance: the last is the farthest */
    }
    int len = dist[far] + 1;
    *path = malloc(sizeof(int) * (size_t)len);
    if (*path)
        for (int k = far, i = len - 1; k >= 0 && i >= 0; k = parent[k], i--)
            (*path)[i] = k;
    free(dist);
    free(parent);
    free(queue);
    return *path ? len : -1;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* The k-th smallest of v[0..n) (v is reordered): Hoare's selection. */
static float select_k(float *v, int n, int k)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        float pivot = v[(lo + hi) / 2];
        int i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot)
                i++;
            while (v[j] > pivot)
                j--;
            if (i <= j) {
                float t = v[i];
                v[i] = v[j];
                v[j] = t;
                i++;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return v[k];
}

/* Gaussian smoothing of a 1-D signal, the ends clamped. */
static void smooth1d(float *v, int n, double sigma)
{
    if (sigma < 0.5 || n < 2)
        return;
    int rad = (int)ceil(3 * sigma);
    /* the weights from -rad to rad, and v padded with its ends rad wide: the sums run
     * without a clamp in the loop (a candidate strip's light is smoothed over 385 taps) */
    float *wgt = malloc(sizeof(float) * (size_t)(2 * rad + 1)), *pad = malloc(sizeof(float) * (size_t)(n + 2 * rad));
    if (!wgt || !pad) {
        free(wgt);
        free(pad);
        return;
    }
    double ws = 0;
    for (int k = 0; k <= rad; k++) {
        wgt[rad + k] = wgt[rad - k] = (float)exp(-0.5 * k * k / (sigma * sigma));
        ws += k ? 2 * wgt[rad + k] : wgt[rad];
    }
    for (int j = 0; j < n + 2 * rad; j++)
        pad[j] = v[j < rad ? 0 : (j - rad >= n ? n - 1 : j - rad)];
    for (int i = 0; i < n; i++) {
        double s = 0;
        for (int k = 0; k <= 2 * rad; k++)
            s += wgt[k] * pad[i + k];
        v[i] = (float)(s / ws);
    }
    free(wgt);
    free(pad);
}

/* The mask (0/255) at (x, y), bilinear, 0 outside. */
static float mask_at(const uint8_t *m8, int w, int h, float x, float y)
{
    x -= 0.5f;
    y -= 0.5f;
    int x0 = (int)floorf(x), y0 = (int)floorf(y);
    float tx = x - x0, ty = y - y0, v = 0;
    for (int k = 0; k < 4; k++) {
        int xi = x0 + (k & 1), yi = y0 + (k >> 1);
        if (xi >= 0 && yi >= 0 && xi < w && yi < h && m8[(size_t)yi * w + xi])
            v += ((k & 1) ? tx : 1 - tx) * ((k >> 1) ? ty : 1 - ty);
    }
    return v;
}

/* Moves a smoothed centre line (n points, about a pixel apart) to the middle between the
 * mask's edges, measured along its normals, and takes the local radius from the same
 * edges. A skeleton wanders off the middle by a few pixels at bends and ragged edges,
 * which turns straight stripes into wavy ones in the strip. Where the edges are not a
 * body's width apart (the body touches itself or another part lies across it) the point
 * keeps its place and clean[i] (n flags) is 0, within half a radius of it too. Returns
 * the share of points whose edges were found a body's width apart. */
static double centre_between_edges(const uint8_t *m8, int w, int h, float *px, float *py, float *pr, int n,
                                   double r, unsigned char *clean)
{
    memset(clean, 1, (size_t)n);
    float *off = malloc(sizeof(float) * (size_t)n), *rad = malloc(sizeof(float) * (size_t)n);
    float *nrm = malloc(sizeof(float) * 2 * (size_t)n);
    unsigned char *ok = malloc((size_t)n);
    if (!off || !rad || !nrm || !ok || n < 8) {
        free(off);
        free(rad);
        free(nrm);
        free(ok);
        return 0;
    }
    const int k = r / 2 > 2 ? (int)(r / 2) : 2;
    const float dstep = 0.25f, dmax = (float)(1.6 * r);
    int good = 0;
    for (int iter = 0; iter < 2; iter++) {
        good = 0;
        for (int i = 0; i < n; i++) {
            int a = i - k < 0 ? 0 : i - k, b = i + k >= n ? n - 1 : i + k;
            float tx = px[b] - px[a], ty = py[b] - py[a], tl = hypotf(tx, ty);
            ok[i] = 0;
            off[i] = 0;
            rad[i] = pr[i];
            nrm[2 * i] = nrm[2 * i + 1] = 0;
            if (!(tl > 0))
                continue;
            const float nx = -ty / tl, ny = tx / tl;
            nrm[2 * i] = nx;
            nrm[2 * i + 1] = ny;
            float edge[2] = {-1, -1};
            for (int side = 0; side < 2 && mask_at(m8, w, h, px[i], py[i]) >= 0.5f; side++) {
                const float sg = side ? -1.0f : 1.0f;
                float prev = 1;
                for (float d = dstep; d <= dmax; d += dstep) {
                    float v = mask_at(m8, w, h, px[i] + sg * d * nx, py[i] + sg * d * ny);
                    if (v < 0.5f) { /* the crossing, linearly between the two samples */
                        edge[side] = d - dstep * (0.5f - v) / (prev - v + 1e-6f);
                        break;
                    }
                    prev = v;
                }
            }
            /* both edges at about a radius, and the width the distance map says: a far
             * edge is another part of the body touching this one */
            if (edge[0] > 0.4f * pr[i] && edge[1] > 0.4f * pr[i] && fabsf(edge[0] + edge[1] - 2 * pr[i]) < 0.3 * r) {
                off[i] = 0.5f * (edge[0] - edge[1]);
                rad[i] = 0.5f * (edge[0] + edge[1]);
                ok[i] = 1;
                good++;
            }
        }
        if (good < n / 2)
            break;
        smooth1d(off, n, 0.5 * r);
        for (int i = 0; i < n; i++) { /* along the normals the edges were measured on */
            px[i] += off[i] * nrm[2 * i];
            py[i] += off[i] * nrm[2 * i + 1];
        }
    }
    /* where both edges were found: the radius from them, the rest unclean */
    if (good >= n / 2) {
        for (int i = 0; i < n; i++)
            if (ok[i])
                pr[i] = rad[i];
        smooth1d(pr, n, 2 * r);
        const int grow = (int)(r / 2);
        int kept = n;
        for (int i = 0; i < n; i++)
            if (!ok[i])
                for (int j = i - grow < 0 ? 0 : i - grow; j <= i + grow && j < n; j++) {
                    kept -= clean[j];
                    clean[j] = 0;
                }
        if (kept < 2 * n / 3) /* a short run loses too much: its few bad rows stay */
            memset(clean, 1, (size_t)n);
    }
    free(off);
    free(rad);
    free(nrm);
    free(ok);
    return (double)good / n;
}

enum { MAX_RUNS = 16 };

/* The photo with the skeleton (red), its longest path (yellow) and the runs that may be
 * straightened (green; those whose edges are not clean are then left out). */
static void debug_centre_line(const SqPrepOptions *o, const SqImage *photo, const uint8_t *skel,
                              const int *path, int n, int nruns, const int (*runs)[2])
{
    if (!o->debug_dir)
        return;
    const int w = photo->width, h = photo->height;
    SqImage ov;
    if (sq_image_alloc(&ov, w, h, 3, SQ_SPACE_SRGB) != 0)
        return;
    memcpy(ov.px, photo->px, sizeof(float) * 3 * (size_t)w * h);
    for (size_t i = 0; i < (size_t)w * h; i++)
        if (skel[i]) {
            ov.px[3 * i] = 1;
            ov.px[3 * i + 1] = ov.px[3 * i + 2] = 0;
        }
    for (int i = 0; i < n; i++) {
        int inrun = 0, x = path[i] % w, y = path[i] / w;
        for (int k = 0; k < nruns; k++)
            inrun |= i >= runs[k][0] && i < runs[k][0] + runs[k][1];
        for (int k = -inrun; k <= inrun; k++)
            for (int l = -inrun; l <= inrun; l++)
                if (x + l >= 0 && y + k >= 0 && x + l < w && y + k < h) {
                    float *p3 = ov.px + 3 * ((size_t)(y + k) * w + x + l);
                    p3[0] = inrun ? 0.0f : 1.0f;
                    p3[1] = 1;
                    p3[2] = 0;
                }
    }
    debug_save(o, "4_centre_line.png", &ov);
    sq_image_free(&ov);
}

/* What a mask says about the body: cleaned, its distance map and skeleton, the longest
 * skeleton path, the median radius, the longest run of trusted path and every run of
 * trusted path a body width long (start, length; in path order, the longest among them). */
typedef struct Body {
    uint8_t *m8;
    float *dist;
    uint8_t *skel;
    int *path, n;
    double r;
    int run0, runn;
    int nruns, runs[MAX_RUNS][2];
    SqStatus st;
    char why[256];
} Body;

static void body_free(Body *b)
{
    free(b->m8);
    free(b->dist);
    free(b->skel);
    free(b->path);
    memset(b, 0, sizeof *b);
}

/* A body covers at least 1/MIN_SHARE of the photo: the mask given or found, and what is
 * left of it once cleaned (one body, no specks), so that the mask a fit writes is one it
 * would take back with --mask. */
enum { MIN_SHARE = 500 };

/* Analyses b->m8 (w x h, 0/255) in place. On failure b->st and b->why say why. */
static void analyse(Body *b, int w, int h)
{
    size_t area = 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        area += b->m8[i] != 0;
    b->dist = malloc(sizeof(float) * (size_t)w * h);
    b->skel = malloc((size_t)w * h);
    b->st = SQ_OK;
#define WHY(code, ...)                                           \
    do {                                                         \
        b->st = code;                                            \
        snprintf(b->why, sizeof b->why, __VA_ARGS__);            \
        return;                                                  \
    } while (0)
    if (!b->dist || !b->skel)
        WHY(SQ_ERR_NOMEM, "out of memory");
    /* clean-up: small specks and holes, one body */
    const int side = w > h ? w : h;
    if (sq__cv_clean_mask(b->m8, w, h, side / 300 > 1 ? side / 300 : 1, area * 0.01) < 0)
        WHY(SQ_ERR_INTERNAL, "OpenCV could not clean the mask");
    size_t kept = 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        kept += b->m8[i] != 0;
    if (kept < (size_t)w * h / MIN_SHARE)
        WHY(SQ_ERR_INVALID, "the body found in the mask covers %.2f%% of the photo (%.1f%% at least): no snake to see",
            100.0 * kept / ((double)w * h), 100.0 / MIN_SHARE);
    /* distance to the edge, skeleton, its longest path */
    if (sq__cv_distance(b->m8, w, h, b->dist))
        WHY(SQ_ERR_INTERNAL, "OpenCV could not find the body's centre line");
    if (sq__thin(b->m8, w, h, b->skel))
        WHY(SQ_ERR_NOMEM, "out of memory thinning the body to its centre line");
    b->n = longest_path(b->skel, w, h, &b->path);
    if (b->n < 0)
        WHY(SQ_ERR_NOMEM, "out of memory following the centre line");
    if (b->n < 16)
        WHY(SQ_ERR_INVALID, "the masked shape has no centre line to follow: is it a snake?");
    float *radii = malloc(sizeof(float) * (size_t)b->n);
    if (!radii)
        WHY(SQ_ERR_NOMEM, "out of memory");
    for (int i = 0; i < b->n; i++)
        radii[i] = b->dist[b->path[i]];
    qsort(radii, (size_t)b->n, sizeof(float), cmp_float);
    b->r = radii[b->n / 2] + 0.5; /* the distance is to the nearest background pixel centre */
    free(radii);
    if (b->r < 3)
        WHY(SQ_ERR_INVALID, "the body is %.1f pixels wide at %d px: too thin to see a pattern", 2 * b->r, side);
    /* the longest run of trusted centre line: not where the body is much wider than usual
     * (a crossing) or thinner (touching parts, the tail), nor within a radius of it */
    const int n = b->n;
    const double r = b->r;
    int *bad = calloc((size_t)n, sizeof(int));
    float *width = malloc(sizeof(float) * (size_t)n);
    if (!bad || !width) {
        free(bad);
        free(width);
        WHY(SQ_ERR_NOMEM, "out of memory");
    }
    /* the width along the path, smoothed over half a body width: a ragged mask edge is
     * not a crossing */
    for (int i = 0; i < n; i++)
        width[i] = b->dist[b->path[i]];
    smooth1d(width, n, 0.5 * r);
    for (int i = 0; i < n; i++) {
        float d = width[i];
        if (d > 1.35 * r || d < 0.55 * r) {
            int lo = i - (int)r < 0 ? 0 : i - (int)r, hi = i + (int)r >= n ? n - 1 : i + (int)r;
            for (int k = lo; k <= hi; k++)
                bad[k] = 1;
        }
    }
    /* the runs that may be straightened: every run a body width long (MAX_RUNS - 1 of
     * them at most, in path order), and the longest */
    for (int i = 0, j; i < n; i = j) {
        for (j = i; j < n && !bad[j]; j++)
            ;
        if (j == i) {
            j++;
            continue;
        }
        if (j - i > b->runn) {
            b->runn = j - i;
            b->run0 = i;
        }
        if (j - i >= 2 * r && b->nruns < MAX_RUNS - 1) {
            b->runs[b->nruns][0] = i;
            b->runs[b->nruns][1] = j - i;
            b->nruns++;
        }
    }
    int have = 0, at = b->nruns;
    for (int k = 0; k < b->nruns; k++) {
        have |= b->runs[k][0] == b->run0;
        if (b->runs[k][0] > b->run0 && at == b->nruns)
            at = k;
    }
    if (!have && b->runn > 0) { /* in its place along the path */
        memmove(b->runs[at + 1], b->runs[at], sizeof b->runs[0] * (size_t)(b->nruns - at));
        b->runs[at][0] = b->run0;
        b->runs[at][1] = b->runn;
        b->nruns++;
    }
    free(bad);
    free(width);
    if (b->runn < 8)
        WHY(SQ_ERR_INVALID, "no clean stretch of body: it crosses or touches itself everywhere");
#undef WHY
}

static SqStatus fail(SqPrepared *out, SqStatus st)
{
    sq_fit_prepared_free(out);
    return st;
}

/* The linear luminance of an sRGB pixel (after sq__lab_init). */
static float luminance(const float *p)
{
    return 0.2126f * sq__srgb_to_linear_lut(p[0]) + 0.7152f * sq__srgb_to_linear_lut(p[1]) +
           0.0722f * sq__srgb_to_linear_lut(p[2]);
}

/* The slope over t in [-1, 1] across a strip row of lv (log luminance), by least squares
 * over the valid pixels (valid NULL: all); NAN where fewer than half are. */
static float row_tilt(const double *lv, const float *valid)
{
    enum { W = SQ_FIT_STRIP_W };
    double sl = 0, st = 0, stt = 0, sll = 0;
    int m = 0;
    for (int x = 0; x < W; x++)
        if (!valid || valid[x] > 0.5f) {
            double t = (x + 0.5) / W * 2 - 1;
            sl += lv[x];
            st += t;
            stt += t * t;
            sll += lv[x] * t;
            m++;
        }
    double den = stt - st * st / (m ? m : 1);
    return m >= W / 2 && den > 1e-6 ? (float)((sll - sl * st / m) / den) : NAN;
}

/* The largest left-right tilt divided out locally: a log-luminance slope of 0.7 over the
 * half width, the one edge of the band twice as bright as the middle and four times the
 * other edge. */
static const float MAX_TILT = 0.7f;

/* Divides out the light: across, a smooth quadratic in theta fitted to the log of the
 * column medians (the round body's shading); along, the luminance averaged over a strip
 * width. Patterns finer than the strip's width keep their contrast; broader ones (a pale
 * dorsal stripe, wide bands) are flattened too, so candidate strips go through the same. */
void sq__fit_normalise_light(SqImage *strip, const SqImage *valid)
{
    enum { W = SQ_FIT_STRIP_W };
    const int n = strip->height;
    sq__lab_init();
    float *lum = malloc(sizeof(float) * (size_t)n * W), *col = malloc(sizeof(float) * (size_t)n);
    float *row = malloc(sizeof(float) * (size_t)n);
    if (!lum || !col || !row) {
        free(lum);
        free(col);
        free(row);
        return;
    }
    for (int i = 0; i < n * W; i++) {
        const float *p = strip->px + 3 * (size_t)i;
        lum[i] = luminance(p) + 1e-4f;
    }
    /* across: least squares of log median = a + b t + c t^2 */
    double S[5] = {0}, T[3] = {0};
    for (int x = 0; x < W; x++) {
        int m = 0;
        for (int y = 0; y < n; y++)
            if (!valid || valid->px[(size_t)y * W + x] > 0.5f)
                col[m++] = lum[(size_t)y * W + x];
        if (m < 8)
            continue;
        double t = (x + 0.5) / W * 2 - 1, lv = log(select_k(col, m, m / 2));
        double tp = 1;
        for (int k = 0; k < 5; k++, tp *= t)
            S[k] += tp;
        T[0] += lv;
        T[1] += lv * t;
        T[2] += lv * t * t;
    }
    double coef[3] = {0, 0, 0};
    {
        /* 3 x 3 normal equations, Cramer's rule */
        double A[3][3] = {{S[0], S[1], S[2]}, {S[1], S[2], S[3]}, {S[2], S[3], S[4]}};
        double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                     A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
        if (fabs(det) > 1e-12)
            for (int k = 0; k < 3; k++) {
                double B[3][3];
                memcpy(B, A, sizeof B);
                for (int r = 0; r < 3; r++)
                    B[r][k] = T[r];
                coef[k] = (B[0][0] * (B[1][1] * B[2][2] - B[1][2] * B[2][1]) -
                           B[0][1] * (B[1][0] * B[2][2] - B[1][2] * B[2][0]) +
                           B[0][2] * (B[1][0] * B[2][1] - B[1][1] * B[2][0])) / det;
            }
    }
    /* a lit round body darkens towards the sides by about half at most: a steeper fall is
     * the pattern (dark flanks), and dividing it out would amplify their noise */
    double colf[W], mean = 0;
    for (int x = 0; x < W; x++) {
        double t = (x + 0.5) / W * 2 - 1;
        colf[x] = exp(coef[1] * t + coef[2] * t * t);
        mean += colf[x] / W;
    }
    double top = 0;
    for (int x = 0; x < W; x++)
        top = fmax(top, colf[x]);
    mean = 0;
    for (int x = 0; x < W; x++) {
        colf[x] = fmax(colf[x], 0.5 * top);
        mean += colf[x] / W;
    }
    /* A body that turns turns its flank to the light: the left-right tilt of the shading
     * changes along the body, which one fit over the whole strip cannot follow. The
     * tilt of each row (the slope of log luminance over t, after the fit above) is
     * smoothed over a strip width and divided out where it departs from its mean; a
     * pattern's own asymmetry, constant along the body, stays. */
    float *tilt = malloc(sizeof(float) * (size_t)n), *tf = malloc(sizeof(float) * (size_t)n * W);
    if (!tilt || !tf) { /* out of memory: the tilt stays */
        free(tilt);
        free(tf);
        tilt = tf = NULL;
    }
    if (tilt) {
        double tsum = 0;
        int tcount = 0;
        for (int y = 0; y < n; y++) {
            double lv[W];
            for (int x = 0; x < W; x++)
                lv[x] = log(lum[(size_t)y * W + x] / colf[x]);
            tilt[y] = row_tilt(lv, valid ? valid->px + (size_t)y * W : NULL);
            if (isfinite(tilt[y])) {
                tsum += tilt[y];
                tcount++;
            }
        }
        const float tmean = tcount ? (float)(tsum / tcount) : 0.0f;
        for (int y = 0; y < n; y++)
            tilt[y] = isfinite(tilt[y]) ? tilt[y] - tmean : 0.0f;
        smooth1d(tilt, n, W);
        for (int y = 0; y < n; y++) {
            const float g = fminf(fmaxf(tilt[y], -MAX_TILT), MAX_TILT);
            for (int x = 0; x < W; x++) { /* kept for the pixels themselves below */
                tf[(size_t)y * W + x] = expf(g * (float)((x + 0.5) / W * 2 - 1));
                lum[(size_t)y * W + x] /= tf[(size_t)y * W + x];
            }
        }
    }
    /* along: the mean luminance per row (after the across correction), smoothed */
    double total = 0;
    int tn = 0;
    for (int y = 0; y < n; y++) {
        double s = 0;
        int m = 0;
        for (int x = 0; x < W; x++)
            if (!valid || valid->px[(size_t)y * W + x] > 0.5f) {
                s += lum[(size_t)y * W + x] / (colf[x] / mean);
                m++;
            }
        row[y] = m ? (float)(s / m) : -1.0f;
        if (m) {
            total += row[y];
            tn++;
        }
    }
    const float gmean = tn ? (float)(total / tn) : 1.0f;
    for (int y = 0; y < n; y++)
        if (row[y] < 0)
            row[y] = gmean;
    smooth1d(row, n, W);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < W; x++) {
            float k = (float)(gmean / (row[y] * (colf[x] / mean)));
            if (tf)
                k /= tf[(size_t)y * W + x];
            float *p = strip->px + 3 * ((size_t)y * W + x);
            for (int c = 0; c < 3; c++)
                p[c] = sq__linear_to_srgb_lut(sq__srgb_to_linear_lut(p[c]) * k);
        }
    free(lum);
    free(col);
    free(row);
    free(tilt);
    free(tf);
}

/* The elevation's part of the light of estimate_light (the key light's: 50 degrees up). */
static const double LIGHT_UP = 0.758f; /* as it always was, in float */

/* The light in the strip's frame (across, up the texture, out; not unit) of a row whose
 * body heads along the unit (tx, ty) in the photo, the light's in-plane part (lx, ly). */
static void row_light(double lx, double ly, double tx, double ty, double L[3])
{
    L[0] = lx * -ty + ly * tx; /* across: the columns' way */
    L[1] = -(lx * tx + ly * ty); /* up the texture: against the rows */
    L[2] = LIGHT_UP;
}

/* The light from the shading: the log luminance of a lit round body slopes across it
 * as the light's component across the body (a left-right tilt), and as the body turns
 * that component follows the light's direction in the photo. One light fixed in the
 * photo: the tilt of each row is t . G, t the row's across direction in the photo, G
 * found by least squares over the rows (with a little ridge: a straight body shows only
 * the across part). The light's part in the photo's plane is G's direction, as long as
 * the key light's (0.65, 50 degrees up) when G is as large as that light's tilt, shorter
 * (the light higher) when the shading tilts less: a soft or overhead light. Each row's
 * light in the strip's frame is that light across and along the body there. Kept, every
 * SQ_FIT_LIGHT_STEP rows: as much of the path as a candidate's strip is long, in four
 * pieces from along the body (each at the photo's own rate: the light turns as fast as
 * there, and the candidate sees the lights of the whole body), the rows between runs
 * skipped. Where two pieces join, the body's heading turns from one to the other over
 * BLEND rows, as round a bend (a sudden turn would draw a seam across the candidate's
 * strip that no photo has). tangent: the rows' unit tangent in the photo (x NAN between
 * runs). */
static void estimate_light(const SqImage *strip, const SqImage *valid, float (*tangent)[2], SqLight *light,
                           float light_xy[2])
{
    enum { W = SQ_FIT_STRIP_W };
    /* the tilt of squama photo's key light straight across (its full in-plane part) */
    static const float FULL_TILT = 0.65f, IN_PLANE = 0.652f;
    const int n = strip->height;
    memset(light, 0, sizeof *light);
    float *tilt = malloc(sizeof(float) * (size_t)n);
    if (!tilt)
        return; /* the key light */
    sq__lab_init();
    for (int y = 0; y < n; y++) {
        double lv[W];
        for (int x = 0; x < W; x++) {
            const float *p = strip->px + 3 * ((size_t)y * W + x);
            lv[x] = log(luminance(p) + 1e-3);
        }
        tilt[y] = isfinite(tangent[y][0]) ? row_tilt(lv, valid->px + (size_t)y * W) : NAN;
    }
    double a = 0, b = 0, c = 0, ra = 0, rb = 0;
    int m = 0;
    for (int y = 0; y < n; y++)
        if (isfinite(tilt[y])) {
            const double nx = -tangent[y][1], ny = tangent[y][0];
            a += nx * nx;
            b += nx * ny;
            c += ny * ny;
            ra += nx * tilt[y];
            rb += ny * tilt[y];
            m++;
        }
    free(tilt);
    if (m < W)
        return;
    a += 0.05 * m;
    c += 0.05 * m;
    const double det = a * c - b * b, gx = (c * ra - b * rb) / det, gy = (a * rb - b * ra) / det;
    const double g = hypot(gx, gy);
    if (!(g > 1e-3) || !isfinite(g))
        return;
    const double k = IN_PLANE * fmin(1.0, g / FULL_TILT) / g; /* G to the in-plane light */
    const double lx = gx * k, ly = gy * k;
    light_xy[0] = (float)lx;
    light_xy[1] = (float)ly;
    /* the rows along the body (not the gaps), and the pieces of them kept */
    int *along = malloc(sizeof(int) * (size_t)n), rows = 0;
    if (!along)
        return;
    for (int y = 0; y < n; y++)
        if (isfinite(tangent[y][0]))
            along[rows++] = y;
    enum { SPAN = SQ_FIT_CANDIDATE_ROWS, PIECES = 4, PIECE = SPAN / PIECES, BLEND = 24 };
    _Static_assert(PIECE % SQ_FIT_LIGHT_STEP == 0, "a piece is whole light rows");
    const int used = rows < SPAN ? rows : SPAN;
    double acc[SQ_FIT_LIGHT_ROWS][3] = {{0}};
    int start[PIECES]; /* each piece's first row along the body */
    for (int j = 0; j < PIECES; j++)
        start[j] = rows <= SPAN ? j * PIECE : j * (rows - PIECE) / (PIECES - 1);
    for (int r = 0; r < used; r++) {
        /* piece p's row r % PIECE; near a joint, blended with the next piece's path
         * running on (or the previous one's) so the light turns there as round a bend */
        const int p = r / PIECE, q = r % PIECE;
        int i0 = start[p] + q, i1 = i0;
        double t = 0;
        if (rows > SPAN && q >= PIECE - BLEND / 2 && p + 1 < PIECES) {
            i1 = start[p + 1] + q - PIECE;
            t = (q - (PIECE - BLEND / 2) + 0.5) / BLEND;
        } else if (rows > SPAN && q < BLEND / 2 && p > 0) {
            i1 = start[p - 1] + q + PIECE;
            t = (BLEND / 2 - q - 0.5) / BLEND;
        }
        i1 = i1 < 0 ? 0 : (i1 >= rows ? rows - 1 : i1);
        const double a0 = atan2(tangent[along[i0]][1], tangent[along[i0]][0]);
        const double a1 = atan2(tangent[along[i1]][1], tangent[along[i1]][0]);
        const double ang = a0 + t * remainder(a1 - a0, 2 * M_PI); /* the shorter way round */
        double L[3], *o = acc[r / SQ_FIT_LIGHT_STEP];
        row_light(lx, ly, cos(ang), sin(ang), L);
        for (int k2 = 0; k2 < 3; k2++)
            o[k2] += L[k2];
    }
    free(along);
    light->rows = (used + SQ_FIT_LIGHT_STEP - 1) / SQ_FIT_LIGHT_STEP;
    for (int i = 0; i < light->rows; i++) {
        const double len = sqrt(acc[i][0] * acc[i][0] + acc[i][1] * acc[i][1] + acc[i][2] * acc[i][2]);
        for (int k2 = 0; k2 < 3; k2++)
            light->dir[i][k2] = (float)(acc[i][k2] / len);
    }
}

/* A candidate's strip is lit row by row by the photo's light as it turns along the body,
 * and has each row's departure of the smooth body's shading from its mean over the rows
 * divided out exactly (sq_fit_candidate_strip). The photo's strip gets the same here, from
 * the same light at each row's own heading (the key light of estimate_light: light_xy
 * in the photo's plane), before sq__fit_normalise_light, whose smoothing over a strip
 * width follows a bend's light only in part. Without it, what a bend leaves of its
 * light (periods of two to four body widths along) counted as pattern that only a
 * wrong candidate could match: on a plain skin on a coiled body, the strip's lightness
 * varied twice as much along the body as the truth's own candidate. Rows between runs
 * (tangent NAN) stay. Nothing when no light was found (a candidate's light does not
 * turn either). */
static void divide_turning_light(SqImage *strip, float (*tangent)[2], const SqLight *light,
                                 const float light_xy[2])
{
    enum { W = SQ_FIT_STRIP_W };
    const int n = strip->height;
    if (light->rows <= 1)
        return;
    float cyl[W][2];
    for (int i = 0; i < W; i++)
        sq__fit_column_angle(i, cyl[i]);
    float *shade = malloc(sizeof(float) * (size_t)n * W);
    if (!shade)
        return; /* out of memory: the turning stays, as it always did */
    double mean[W] = {0};
    int m = 0;
    for (int y = 0; y < n; y++) {
        if (!isfinite(tangent[y][0]))
            continue;
        double l[3];
        row_light(light_xy[0], light_xy[1], tangent[y][0], tangent[y][1], l);
        const double ll = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
        const float L[3] = {(float)(l[0] / ll), (float)(l[1] / ll), (float)(l[2] / ll)};
        for (int i = 0; i < W; i++)
            mean[i] += shade[(size_t)y * W + i] = sq__fit_smooth_shade(cyl[i], L);
        m++;
    }
    sq__lab_init();
    for (int y = 0; y < n && m > 0; y++) {
        if (!isfinite(tangent[y][0]))
            continue;
        for (int i = 0; i < W; i++) {
            const float k = (float)(mean[i] / m) / shade[(size_t)y * W + i];
            float *p = strip->px + 3 * ((size_t)y * W + i);
            for (int c = 0; c < 3; c++)
                p[c] = sq__linear_to_srgb_lut(sq__srgb_to_linear_lut(p[c]) * k);
        }
    }
    free(shade);
}

/* One run of the centre line made ready to straighten: smoothed, moved between the
 * edges, with its local radius, clean flags and arc length. */
typedef struct Curve {
    int i0, n, rows; /* its first point along the skeleton's path, points, strip rows */
    double good; /* share of the points with both edges a body's width apart */
    float *px, *py, *pr;
    unsigned char *clean;
    double *arc;
} Curve;

enum { RUN_GAP = 4 }; /* strip rows between two runs */

/* A run is straightened with the others when its edges are found a body's width apart at
 * this share of its points. */
static const double MIN_RUN_GOOD = 0.85;

static void curve_free(Curve *c)
{
    free(c->px);
    free(c->py);
    free(c->pr);
    free(c->clean);
    free(c->arc);
    memset(c, 0, sizeof *c);
}

/* A curve of n points, its arrays allocated (-1: out of memory, c freeable as it is). */
static int curve_alloc(Curve *c, int n)
{
    memset(c, 0, sizeof *c);
    c->n = n;
    c->px = malloc(sizeof(float) * (size_t)n);
    c->py = malloc(sizeof(float) * (size_t)n);
    c->pr = malloc(sizeof(float) * (size_t)n);
    c->clean = malloc((size_t)n);
    c->arc = malloc(sizeof(double) * (size_t)n);
    return c->px && c->py && c->pr && c->clean && c->arc ? 0 : -1;
}

/* The arc length at each of the curve's points. */
static void curve_arc(Curve *c)
{
    c->arc[0] = 0;
    for (int i = 1; i < c->n; i++)
        c->arc[i] = c->arc[i - 1] + hypot(c->px[i] - c->px[i - 1], c->py[i] - c->py[i - 1]);
}

static int curve_make(const Body *b, int w, int h, int i0, int n, Curve *c)
{
    if (curve_alloc(c, n) != 0)
        return -1;
    c->i0 = i0;
    const double r = b->r;
    for (int i = 0; i < n; i++) {
        int k = b->path[i0 + i];
        c->px[i] = (float)(k % w) + 0.5f;
        c->py[i] = (float)(k / w) + 0.5f;
        c->pr[i] = b->dist[k];
    }
    smooth1d(c->px, n, 0.5 * r);
    smooth1d(c->py, n, 0.5 * r);
    smooth1d(c->pr, n, 2 * r);
    c->good = centre_between_edges(b->m8, w, h, c->px, c->py, c->pr, n, r, c->clean);
    /* where the frame cuts the body one edge is the frame's: those points are not good */
    int framed = 0;
    for (int i = 0; i < n; i++)
        framed += c->px[i] < r || c->py[i] < r || c->px[i] > w - r || c->py[i] > h - r;
    c->good = fmax(c->good - (double)framed / n, 0.0);
    curve_arc(c);
    return 0;
}

/* Stretch k of a body line (its points from `first` on) as a curve at working size
 * (scale): a Catmull-Rom spline through its points (a line clicked by hand has corners;
 * smoothed instead, a tight bend would shrink), a pixel apart, of radius r all along and
 * clean everywhere. */
static int line_curve(const SqBodyLine *L, int k, int first, double scale, double r, Curve *c)
{
    const float *q = L->xy + 2 * (size_t)first;
    const int m = L->count[k];
    /* the spline, densely: 4 samples a pixel of chord (the line's length is bounded by the
     * caller) */
    size_t nd = 1;
    for (int i = 1; i < m; i++)
        nd += 1 + (size_t)ceil(4 * scale * hypot(q[2 * i] - q[2 * i - 2], q[2 * i + 1] - q[2 * i - 1]));
    double *dx = malloc(sizeof(double) * nd), *dy = malloc(sizeof(double) * nd);
    memset(c, 0, sizeof *c);
    if (!dx || !dy) {
        free(dx);
        free(dy);
        return -1;
    }
    size_t j = 0;
    double len = 0;
    for (int i = 0; i + 1 < m; i++) {
        const float *p0 = q + 2 * (i > 0 ? i - 1 : i), *p1 = q + 2 * i, *p2 = q + 2 * (i + 1),
                    *p3 = q + 2 * (i + 2 < m ? i + 2 : i + 1);
        const int steps = 1 + (int)ceil(4 * scale * hypot(p2[0] - p1[0], p2[1] - p1[1]));
        for (int a = i ? 1 : 0; a <= steps && j < nd; a++) {
            const double t = (double)a / steps, t2 = t * t, t3 = t2 * t;
            double v[2];
            for (int d = 0; d < 2; d++)
                v[d] = 0.5 * (2 * p1[d] + (p2[d] - p0[d]) * t + (2 * p0[d] - 5 * p1[d] + 4 * p2[d] - p3[d]) * t2 +
                              (3 * p1[d] - p0[d] - 3 * p2[d] + p3[d]) * t3);
            dx[j] = scale * v[0];
            dy[j] = scale * v[1];
            if (j > 0)
                len += hypot(dx[j] - dx[j - 1], dy[j] - dy[j - 1]);
            j++;
        }
    }
    nd = j;
    /* resampled a pixel apart along it */
    const int n = len > 1 ? (int)ceil(len) + 1 : 2;
    if (curve_alloc(c, n) != 0) {
        free(dx);
        free(dy);
        return -1;
    }
    double at = 0; /* arc length at dense point seg */
    size_t seg = 0;
    for (int i = 0; i < n; i++) {
        const double s = len * i / (n - 1);
        double sl = 0;
        for (; seg < nd - 1; seg++) {
            sl = hypot(dx[seg + 1] - dx[seg], dy[seg + 1] - dy[seg]);
            if (at + sl >= s || seg == nd - 2)
                break;
            at += sl;
        }
        const size_t s1 = seg + 1 < nd ? seg + 1 : seg;
        const double t = sl > 0 ? fmin(fmax((s - at) / sl, 0), 1) : 0;
        c->px[i] = (float)(dx[seg] + t * (dx[s1] - dx[seg]));
        c->py[i] = (float)(dy[seg] + t * (dy[s1] - dy[seg]));
        c->pr[i] = (float)r;
    }
    free(dx);
    free(dy);
    memset(c->clean, 1, (size_t)n);
    c->good = 1;
    curve_arc(c);
    return 0;
}

/* The body a line's curves sweep at radius r: every pixel whose middle lies within r of
 * a point is set in m8 (w x h). The points are a pixel apart; discs a quarter radius apart
 * (and the last) miss at most r / 128 of the edge, at a cost that grows as r, not r^2. */
static void fill_disc(uint8_t *m8, int w, int h, double cx, double cy, double r)
{
    const int y0 = (int)fmax(0, floor(cy - r)), y1 = (int)fmin(h - 1, ceil(cy + r));
    for (int y = y0; y <= y1; y++) {
        const double dy = y + 0.5 - cy;
        if (dy * dy > r * r)
            continue;
        const double half = sqrt(r * r - dy * dy);
        const int x0 = (int)fmax(0, ceil(cx - half - 0.5)), x1 = (int)fmin(w - 1, floor(cx + half - 0.5));
        if (x1 >= x0)
            memset(m8 + (size_t)y * w + x0, 255, (size_t)(x1 - x0 + 1));
    }
}

static void line_mask(const Curve *curves, int ncurves, double r, int w, int h, uint8_t *m8)
{
    memset(m8, 0, (size_t)w * h);
    const int every = r > 8 ? (int)(r / 4) : 1;
    for (int k = 0; k < ncurves; k++) {
        const Curve *c = &curves[k];
        for (int i = 0; i < c->n; i += every)
            fill_disc(m8, w, h, c->px[i], c->py[i], r);
        if ((c->n - 1) % every) /* the last point, when the step passed it */
            fill_disc(m8, w, h, c->px[c->n - 1], c->py[c->n - 1], r);
    }
}

/* A body line's band is drawn by hand: wider than the body, or off its middle, it takes in
 * the ground, a branch, the next coil. The band's body found by colour (GrabCut: the line's
 * middle, LINE_CORE of the radius, certainly body, the band's rest probably, as far again
 * round it probably not); kept unless it leaves less than LINE_KEEP of the band outside
 * the middle (which is always kept), where the colours did not tell body from backdrop
 * and the band is taken as drawn. */
static const double LINE_CORE = 0.4, LINE_KEEP = 0.25;

static void band_body(const SqImage *photo, const Curve *curves, int ncurves, double r, uint8_t *band)
{
    const int w = photo->width, h = photo->height;
    uint8_t *core = malloc((size_t)w * h), *found = malloc((size_t)w * h);
    if (core && found) {
        line_mask(curves, ncurves, LINE_CORE * r, w, h, core);
        if (sq__cv_grabcut_band(photo->px, w, h, band, core, (int)ceil(r), found) == 0) {
            size_t n = 0, kept = 0;
            for (size_t i = 0; i < (size_t)w * h; i++) {
                n += band[i] && !core[i];
                kept += found[i] && !core[i];
            }
            if (kept >= LINE_KEEP * (double)n)
                memcpy(band, found, (size_t)w * h);
        }
    }
    free(core);
    free(found);
}

/* The photo's own blur, from the body's outline: across each edge (both sides of the
 * clean stretches, every other pixel along them) the linear luminance rises from the
 * backdrop's to the body's; where both sides are flat and differ enough, the distance
 * between the 20% and 80% points of that rise is 1.683 sigma of a Gaussian-blurred step.
 * The median over the edges, in photo pixels (at working size), the pixel's own box
 * included; 0 when fewer than EDGE_MIN edges were clean enough to measure. */
enum { EDGE_MIN = 24, EDGE_REACH = 20 }; /* EDGE_REACH quarter pixels each side of the edge */

static double edge_blur(const Curve *curves, int ncurves, const SqImage *photo)
{
    const int w = photo->width, h = photo->height;
    int cap = 0;
    for (int k = 0; k < ncurves; k++)
        cap += curves[k].n;
    float *sig = malloc(sizeof(float) * (size_t)(cap + 1));
    if (!sig)
        return 0;
    int m = 0;
    sq__lab_init();
    for (int k = 0; k < ncurves; k++) {
        const Curve *c = &curves[k];
        for (int i = 3; i + 3 < c->n; i += 2) {
            if (!c->clean[i])
                continue;
            double tx = c->px[i + 3] - c->px[i - 3], ty = c->py[i + 3] - c->py[i - 3], tl = hypot(tx, ty);
            if (!(tl > 0))
                continue;
            const double nx = -ty / tl, ny = tx / tl;
            for (int side = -1; side <= 1; side += 2) {
                float e[2 * EDGE_REACH + 1];
                int inside = 1;
                for (int q = -EDGE_REACH; q <= EDGE_REACH && inside; q++) {
                    const double d = side * (c->pr[i] + 0.25 * q);
                    const float sx = (float)(c->px[i] + d * nx - 0.5), sy = (float)(c->py[i] + d * ny - 0.5);
                    inside = sx >= 0 && sy >= 0 && sx <= w - 1 && sy <= h - 1;
                    if (inside) {
                        float rgb[3];
                        for (int ch = 0; ch < 3; ch++)
                            rgb[ch] = sq__sample(photo->px, w, h, 3, ch, sx, sy);
                        e[q + EDGE_REACH] = luminance(rgb);
                    }
                }
                if (!inside)
                    continue;
                /* the plateaus: 3 to 5 pixels in and out */
                double a = 0, b = 0, va = 0, vb = 0;
                for (int q = 0; q <= 8; q++) {
                    a += e[q] / 9;
                    b += e[2 * EDGE_REACH - q] / 9;
                }
                for (int q = 0; q <= 8; q++) {
                    va += (e[q] - a) * (e[q] - a) / 9;
                    vb += (e[2 * EDGE_REACH - q] - b) * (e[2 * EDGE_REACH - q] - b) / 9;
                }
                const double step = a - b;
                if (fabs(step) < 0.05 || sqrt(va) > 0.1 * fabs(step) || sqrt(vb) > 0.1 * fabs(step))
                    continue;
                /* from inside out: the first fall below 80% and below 20%, and nothing back
                 * above 50% after it */
                double t80 = NAN, t20 = NAN;
                int ok = 1;
                for (int q = 1; q <= 2 * EDGE_REACH; q++) {
                    const double f0 = (e[q - 1] - b) / step, f1 = (e[q] - b) / step;
                    if (isnan(t80) && f0 >= 0.8 && f1 < 0.8)
                        t80 = q - 1 + (f0 - 0.8) / (f0 - f1);
                    if (!isnan(t80) && isnan(t20) && f0 >= 0.2 && f1 < 0.2)
                        t20 = q - 1 + (f0 - 0.2) / (f0 - f1);
                    if (!isnan(t20) && f1 > 0.5)
                        ok = 0;
                }
                if (ok && !isnan(t80) && !isnan(t20))
                    sig[m++] = (float)(0.25 * (t20 - t80) / 1.683);
            }
        }
    }
    const double r = m >= EDGE_MIN ? select_k(sig, m, m / 2) : 0;
    free(sig);
    return r;
}

/* Largest number of samples a strip pixel averages in each direction. */
enum { SUBSAMPLE_MAX = 6 };

/* Samples the photo perpendicular to the curve into c->rows rows of the strip from row0:
 * every `step` pixels along it, across at d = r sin(theta). Where a strip pixel covers
 * more than a photo pixel (step > 1) it is the mean, in linear light, of a grid of samples
 * over its footprint, as a candidate's strip pixel is of the texels it covers: a big snake's
 * scales do not alias. */
static void curve_sample(const Curve *c, const SqImage *photo, const uint8_t *m8, double step,
                         SqImage *strip, SqImage *valid, int row0, float (*tangent)[2])
{
    const int w = photo->width, h = photo->height, n = c->n;
    const int k = (int)fmin(SUBSAMPLE_MAX, fmax(1, ceil(step - 1e-6)));
    const double dth = 2 * THETA_MAX / SQ_FIT_STRIP_W;
    int seg = 0;
    sq__lab_init();
    for (int j = 0; j < c->rows; j++) {
        float acc[SQ_FIT_STRIP_W][3];
        int row_clean = 1, in[SQ_FIT_STRIP_W], body[SQ_FIT_STRIP_W];
        memset(acc, 0, sizeof acc);
        for (int i = 0; i < SQ_FIT_STRIP_W; i++)
            in[i] = body[i] = 1;
        for (int a = 0; a < k; a++) {
            /* the centre line at arc length s: point, radius, unit normal */
            const double s = (j + (a + 0.5) / k) * step;
            while (seg < n - 2 && c->arc[seg + 1] < s)
                seg++;
            double t = c->arc[seg + 1] > c->arc[seg] ? (s - c->arc[seg]) / (c->arc[seg + 1] - c->arc[seg]) : 0;
            double cx = c->px[seg] + (c->px[seg + 1] - c->px[seg]) * t;
            double cy = c->py[seg] + (c->py[seg + 1] - c->py[seg]) * t;
            double rr = c->pr[seg] + (c->pr[seg + 1] - c->pr[seg]) * t;
            int lo = seg > 2 ? seg - 3 : 0, hi = seg + 3 < n ? seg + 3 : n - 1;
            double tx = c->px[hi] - c->px[lo], ty = c->py[hi] - c->py[lo], tl = hypot(tx, ty);
            tx /= tl > 0 ? tl : 1;
            ty /= tl > 0 ? tl : 1;
            double nx = -ty, ny = tx;
            if (a == k / 2) { /* the row's own: its middle sample's */
                tangent[row0 + j][0] = (float)tx;
                tangent[row0 + j][1] = (float)ty;
                row_clean = c->clean[seg] && c->clean[seg + 1 < n ? seg + 1 : seg];
            }
            for (int i = 0; i < SQ_FIT_STRIP_W; i++)
                for (int b = 0; b < k; b++) {
                    double th = -THETA_MAX + (i + (b + 0.5) / k) * dth;
                    double d = rr * sin(th);
                    float sx = (float)(cx + d * nx - 0.5), sy = (float)(cy + d * ny - 0.5);
                    const int inside = sx >= 0 && sy >= 0 && sx <= w - 1 && sy <= h - 1;
                    in[i] &= inside;
                    if (!inside)
                        continue;
                    if (k == 1) { /* as it is: one sample */
                        for (int ch = 0; ch < 3; ch++)
                            acc[i][ch] = sq__sample(photo->px, w, h, 3, ch, sx, sy);
                        body[i] = m8[(int)(sy + 0.5f) * w + (int)(sx + 0.5f)] != 0;
                        continue;
                    }
                    for (int ch = 0; ch < 3; ch++)
                        acc[i][ch] += sq__srgb_to_linear_lut(sq__sample(photo->px, w, h, 3, ch, sx, sy));
                    if (a == k / 2 && b == k / 2) /* the mask at the pixel's middle */
                        body[i] = m8[(int)(sy + 0.5f) * w + (int)(sx + 0.5f)] != 0;
                }
        }
        for (int i = 0; i < SQ_FIT_STRIP_W; i++) {
            float *o3 = sq_image_at(strip, i, row0 + j);
            for (int ch = 0; ch < 3; ch++)
                o3[ch] = !in[i] ? 0.0f : k == 1 ? acc[i][ch] : sq__linear_to_srgb_lut(acc[i][ch] / (float)(k * k));
            *sq_image_at(valid, i, row0 + j) = in[i] && body[i] && row_clean ? 1.0f : 0.0f;
        }
    }
}

/* A candidate for the automatic mask (m, mw x mh, 0/255) at w x h, analysed into *c: its
 * area first (a snake is neither a speck nor most of the photo), then as a body. */
static void analyse_candidate(const uint8_t *m, int mw, int mh, int w, int h, Body *c)
{
    memset(c, 0, sizeof *c);
    float *mf = malloc(sizeof(float) * (size_t)mw * mh), *mb = malloc(sizeof(float) * (size_t)w * h);
    c->m8 = malloc((size_t)w * h);
    if (!mf || !mb || !c->m8) {
        c->st = SQ_ERR_NOMEM;
        snprintf(c->why, sizeof c->why, "out of memory");
    } else {
        for (size_t i = 0; i < (size_t)mw * mh; i++)
            mf[i] = m[i] ? 1.0f : 0.0f;
        size_t area = 0;
        if (sq__cv_resize(mf, mw, mh, 1, mb, w, h)) {
            c->st = SQ_ERR_INTERNAL;
            snprintf(c->why, sizeof c->why, "OpenCV could not resize the mask");
        } else {
            for (size_t i = 0; i < (size_t)w * h; i++) {
                c->m8[i] = mb[i] >= 0.5f ? 255 : 0;
                area += c->m8[i] != 0;
            }
            if (area < (size_t)w * h / MIN_SHARE || area > (size_t)w * h * 7 / 10) {
                c->st = SQ_ERR_INVALID;
                snprintf(c->why, sizeof c->why, "the automatic mask covers %.1f%% of the photo",
                         100.0 * area / ((double)w * h));
            } else {
                analyse(c, w, h);
            }
        }
    }
    free(mf);
    free(mb);
}

/* How snake-like an analysed candidate (w x h) is: its clean run in body widths, times how
 * well the shape is a tube of that width along its centre line (a patch of backdrop is
 * far wider than its skeleton says), squared, less the share of the run that hugs the
 * frame (the edge of a backdrop region, not a snake). -1 when it is no body at all. */
static double snake_likeness(const Body *c, int w, int h)
{
    if (c->st != SQ_OK)
        return -1;
    size_t area = 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        area += c->m8[i] != 0;
    double tube = area / (c->n * 2 * c->r);
    tube = tube > 1 ? 1 / tube : tube;
    int near = 0;
    const int side = w > h ? w : h, margin = side / 20;
    for (int i = c->run0; i < c->run0 + c->runn; i++) {
        const int x = c->path[i] % w, y = c->path[i] / w;
        near += x < margin || y < margin || x >= w - margin || y >= h - margin;
    }
    return c->runn / (2 * c->r) * tube * tube * (1.0 - (double)near / c->runn);
}

/* With a debug folder: candidate k's mask (m, w x h) saved as 2_candidate_K_<what>_<score>.png. */
static void debug_candidate(const SqPrepOptions *o, int k, const char *what, double score, const uint8_t *m, int w,
                            int h)
{
    SqImage img;
    if (!o->debug_dir || sq_image_alloc(&img, w, h, 1, SQ_SPACE_DATA) != 0)
        return;
    for (size_t i = 0; i < (size_t)w * h; i++)
        img.px[i] = m[i] ? 1.0f : 0.0f;
    char name[64];
    snprintf(name, sizeof name, "2_candidate_%d_%s_%.2f.png", k, what, score);
    debug_save(o, name, &img);
    sq_image_free(&img);
}

/* The automatic mask: candidates found by GrabCut on a copy AUTO_SIDE pixels long, started
 * from two rectangles (snakes often leave the frame, which GrabCut takes for background)
 * and from the photo's saliency, and each of them again with the backdrop's colours taken
 * out (sq__cv_backdrop_out: GrabCut takes the ground that a loop of the body encloses for
 * body, and the centre line then crosses it; 57 of the 75 photos of ../shared/photos
 * prepared before, 62 after, their median strip 2.5 body widths before, 3.4 after). Each
 * is analysed at the working size (the photo's) and judged by snake_likeness; the most
 * snake-like becomes *body, or when none is a body, the first that was analysed as one (not
 * refused for its area alone), else the first, to say why. Returns 0, or
 * -1 when OpenCV failed or memory ran out for a GrabCut (a candidate with the backdrop
 * out that could not be made is left out).
 * Tried and not kept (`scripts/bench masks` on the 75 photos of ../shared/photos, by eye):
 * the photo's six k-means colour regions as candidates too, as they are and as GrabCut's
 * start: they won with thin slivers, a stripe or a twig, on most photos, where the
 * rectangles had found the snake; and judging the candidates at half the working size
 * (26% faster): it changed the choice on 12 photos, better on one, worse on three. */
enum { AUTO_SIDE = 400, AUTO_CANDIDATES = 3 };
static const double AUTO_KEEP = 0.4, AUTO_COVER = 0.7;

/* One GrabCut candidate and the same with the backdrop's colours out, each analysed, on a
 * thread of their own (GrabCut and k-means draw from OpenCV's per-thread generator,
 * seeded in each call: the masks are the same on any thread). The second is made only
 * when the first covers at most AUTO_COVER of the photo (more is refused as no body
 * anyway), and left out when it is the first again or keeps less than AUTO_KEEP of it: a
 * sliver of one of the body's colours (a stripe, a highlight), which the likeness would
 * take for a long thin body. Of the two the one more snake-like is kept (the first on a
 * tie), the other freed. */
typedef struct GrabJob {
    const float *small;
    int gw, gh, w, h, k, failed;
    uint8_t *mask[2];
    Body c[2];
    double score[2];
    int made[2], kept; /* made: analysed; kept: which of them is kept */
} GrabJob;

static void *grab_candidate(void *arg)
{
    GrabJob *j = arg;
    static const double insets[2] = {0.03, 0.005};
    const size_t gn = (size_t)j->gw * j->gh;
    j->failed = j->k < 2 ? sq__cv_grabcut(j->small, j->gw, j->gh, insets[j->k], j->mask[0]) != 0
                         : sq__cv_grabcut_salient(j->small, j->gw, j->gh, j->mask[0]) != 0;
    j->score[0] = j->score[1] = -1;
    if (j->failed)
        return NULL;
    analyse_candidate(j->mask[0], j->gw, j->gh, j->w, j->h, &j->c[0]);
    j->score[0] = snake_likeness(&j->c[0], j->w, j->h);
    j->made[0] = 1;
    size_t before = 0, after = 0;
    for (size_t i = 0; i < gn; i++)
        before += j->mask[0][i] != 0;
    memcpy(j->mask[1], j->mask[0], gn);
    if ((double)before <= AUTO_COVER * (double)gn && sq__cv_backdrop_out(j->small, j->gw, j->gh, j->mask[1]) == 0)
        for (size_t i = 0; i < gn; i++)
            after += j->mask[1][i] != 0;
    if (after < before && (double)after >= AUTO_KEEP * (double)before) {
        analyse_candidate(j->mask[1], j->gw, j->gh, j->w, j->h, &j->c[1]);
        j->score[1] = snake_likeness(&j->c[1], j->w, j->h);
        j->made[1] = 1;
        j->kept = j->score[1] > j->score[0];
        body_free(&j->c[!j->kept]);
    }
    return NULL;
}

static int automatic_mask(const SqImage *photo, const SqPrepOptions *o, Body *body)
{
    const int w = photo->width, h = photo->height, side = w > h ? w : h;
    const double gs = fmin(1.0, (double)AUTO_SIDE / side);
    const int gw = (int)lround(w * gs) > 16 ? (int)lround(w * gs) : 16;
    const int gh = (int)lround(h * gs) > 16 ? (int)lround(h * gs) : 16;
    const size_t gn = (size_t)gw * gh;
    float *small = malloc(sizeof(float) * 3 * gn);
    uint8_t *cand = malloc(gn * 2 * AUTO_CANDIDATES); /* each GrabCut's, and with the backdrop out */
    int bad = !small || !cand || sq__cv_resize(photo->px, w, h, 3, small, gw, gh);
    /* the three candidates at once (about half of the preparation's time, one after another) */
    GrabJob job[AUTO_CANDIDATES] = {0};
    pthread_t th[AUTO_CANDIDATES];
    int started[AUTO_CANDIDATES] = {0};
    for (int k = 0; !bad && k < AUTO_CANDIDATES; k++) {
        job[k] = (GrabJob){.small = small, .gw = gw, .gh = gh, .w = w, .h = h, .k = k,
                           .mask = {cand + gn * 2 * k, cand + gn * (2 * k + 1)}};
        started[k] = pthread_create(&th[k], NULL, grab_candidate, &job[k]) == 0;
        if (!started[k]) /* no thread to be had: run it here */
            grab_candidate(&job[k]);
    }
    for (int k = 0; !bad && k < AUTO_CANDIDATES; k++)
        if (started[k])
            pthread_join(th[k], NULL);
    int ncand = 0; /* the candidates before the first that failed */
    while (!bad && ncand < AUTO_CANDIDATES && !job[ncand].failed)
        ncand++;
    if (!bad && ncand < 2) /* a rectangle's GrabCut: OpenCV failed; the saliency's: none to start from */
        bad = 1;
    double best = -1;
    for (int j = 0; !bad && j < 2 * ncand; j++) { /* the GrabCuts' first, then those with the backdrop out */
        const int k = j % ncand, v = j / ncand;
        if (!job[k].made[v])
            continue;
        static const char *const what[2][2] = {{"rectangle", "salient"}, {"rectangle_backdrop_out", "salient_backdrop_out"}};
        debug_candidate(o, k + AUTO_CANDIDATES * v, what[v][k == 2], job[k].score[v], job[k].mask[v], gw, gh);
        if (v != job[k].kept)
            continue;
        /* none a body so far: the first, or the first that got as far as analysing, to say why */
        const int further = best < 0 && job[k].score[v] < 0 && job[k].c[v].dist && !body->dist;
        if (job[k].score[v] > best || (best < 0 && !body->m8) || further) {
            best = job[k].score[v] > best ? job[k].score[v] : best;
            body_free(body);
            *body = job[k].c[v];
            job[k].c[v] = (Body){0};
        }
    }
    for (int k = 0; k < AUTO_CANDIDATES; k++) {
        body_free(&job[k].c[0]);
        body_free(&job[k].c[1]);
    }
    free(small);
    free(cand);
    return bad ? -1 : 0;
}

SqStatus sq_fit_prepare(const SqImage *photo, const SqImage *mask_in, const SqPrepOptions *opt,
                        SqPrepared *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    SqPrepOptions o = opt ? *opt : sq_fit_prep_options_default();
    if (o.work_size < 64)
        o.work_size = 1024;
    if (!photo || !photo->px || photo->channels < 3)
        return sq_error_set(err, SQ_ERR_INVALID, "photo", "no colour photo");
    const int W0 = photo->width, H0 = photo->height;
    if (W0 < 64 || H0 < 64)
        return sq_error_set(err, SQ_ERR_INVALID, "photo", "the photo is %dx%d: too small to show a snake (64x64 at least)", W0, H0);
    if (mask_in && (mask_in->width != W0 || mask_in->height != H0))
        return sq_error_set(err, SQ_ERR_INVALID, "mask", "the mask is %dx%d but the photo is %dx%d",
                            mask_in ? mask_in->width : 0, mask_in ? mask_in->height : 0, W0, H0);

    /* 1. working size */
    const double scale = fmin(1.0, (double)o.work_size / (W0 > H0 ? W0 : H0));
    const int w = (int)lround(W0 * scale) > 32 ? (int)lround(W0 * scale) : 32;
    const int h = (int)lround(H0 * scale) > 32 ? (int)lround(H0 * scale) : 32;
    out->scale = scale;
    float *rgb0 = malloc(sizeof(float) * 3 * (size_t)W0 * H0);
    uint8_t *m8 = malloc((size_t)w * h);
    Body body = {0};
    Curve curves[MAX_RUNS];
    int ncurves = 0;
    float (*tangent)[2] = NULL; /* per strip row */
    SqStatus st = SQ_OK;
#define FAIL(...)                                    \
    do {                                             \
        st = sq_error_set(err, __VA_ARGS__);         \
        goto done;                                   \
    } while (0)
    if (!rgb0 || !m8 || sq_image_alloc(&out->photo, w, h, 3, SQ_SPACE_SRGB) ||
        sq_image_alloc(&out->mask, w, h, 1, SQ_SPACE_DATA))
        FAIL(SQ_ERR_NOMEM, "photo", "out of memory preparing a %dx%d photo", W0, H0);
    for (size_t i = 0; i < (size_t)W0 * H0; i++)
        for (int c = 0; c < 3; c++)
            rgb0[3 * i + c] = photo->px[i * photo->channels + c];
    if (sq__cv_resize(rgb0, W0, H0, 3, out->photo.px, w, h))
        FAIL(SQ_ERR_INTERNAL, "photo", "OpenCV could not resize the photo");
    debug_save(&o, "1_photo.png", &out->photo);

    /* 2. the mask: given, from alpha, or by GrabCut */
    int have_alpha = 0;
    if (!mask_in && photo->channels == 4 && !o.line) /* a line given says where the body is */
        for (size_t i = 0; i < (size_t)W0 * H0 && !have_alpha; i++)
            have_alpha = photo->px[4 * i + 3] < 0.5f;
    static const char *const source_name[] = {"the given mask", "the photo's alpha", "the automatic mask"};
    if (mask_in || have_alpha) {
        float *m0 = malloc(sizeof(float) * (size_t)W0 * H0), *m1 = malloc(sizeof(float) * (size_t)w * h);
        if (!m0 || !m1) {
            free(m0);
            free(m1);
            FAIL(SQ_ERR_NOMEM, "mask", "out of memory for the mask");
        }
        for (size_t i = 0; i < (size_t)W0 * H0; i++)
            m0[i] = mask_in ? mask_in->px[i * mask_in->channels] : photo->px[4 * i + 3];
        int bad = sq__cv_resize(m0, W0, H0, 1, m1, w, h);
        for (size_t i = 0; i < (size_t)w * h; i++)
            m8[i] = m1[i] >= 0.5f ? 255 : 0;
        free(m0);
        free(m1);
        if (bad)
            FAIL(SQ_ERR_INTERNAL, "mask", "OpenCV could not resize the mask");
        out->mask_source = mask_in ? SQ_MASK_GIVEN : SQ_MASK_ALPHA;
        size_t area = 0;
        for (size_t i = 0; i < (size_t)w * h; i++)
            area += m8[i] != 0;
        const char *src = source_name[out->mask_source];
        if (area < (size_t)w * h / MIN_SHARE)
            FAIL(SQ_ERR_INVALID, "mask", "%s covers %.2f%% of the photo: no snake to see", src,
                 100.0 * area / ((double)w * h));
        if (area > (size_t)w * h * 9 / 10)
            FAIL(SQ_ERR_INVALID, "mask", "%s covers %.0f%% of the photo: it cannot be the snake alone", src,
                 100.0 * area / ((double)w * h));
        for (size_t i = 0; i < (size_t)w * h; i++)
            out->mask.px[i] = m8[i] ? 1.0f : 0.0f;
        debug_save(&o, "2_mask.png", &out->mask);
        if (!o.line) {
            body.m8 = m8;
            m8 = NULL;
            analyse(&body, w, h);
        }
    } else if (!o.line) {
        out->mask_source = SQ_MASK_AUTOMATIC;
        /* one flat colour: nothing to find, and GrabCut's graph cut on it takes minutes */
        double spread = 0;
        for (int c = 0; c < 3; c++) {
            double m = 0, v = 0;
            const size_t np = (size_t)w * h;
            for (size_t i = 0; i < np; i++)
                m += out->photo.px[3 * i + c];
            m /= np;
            for (size_t i = 0; i < np; i++)
                v += (out->photo.px[3 * i + c] - m) * (out->photo.px[3 * i + c] - m);
            spread = fmax(spread, sqrt(v / np));
        }
        if (spread < 1.0 / 255)
            FAIL(SQ_ERR_INVALID, "photo", "the photo is one flat colour (its spread %.2f levels of 255): no snake to find",
                 255 * spread);
        if (automatic_mask(&out->photo, &o, &body) != 0)
            FAIL(SQ_ERR_INTERNAL, "mask", "the automatic mask failed (GrabCut, out of memory)");
    }
    if (o.line) { /* the body where the line says, at its width; a mask given says which of it is body */
        const SqBodyLine *L = o.line;
        if (L->nstretches < 1 || L->nstretches > MAX_RUNS || !L->count || !L->xy)
            FAIL(SQ_ERR_INVALID, "body line", "no stretches (1 to %d)", MAX_RUNS);
        for (int k = 0, j = 0; k < L->nstretches; k++) {
            if (L->count[k] < 2)
                FAIL(SQ_ERR_INVALID, "body line", "stretches[%d] has %d point%s: 2 at least", k, L->count[k],
                     L->count[k] == 1 ? "" : "s");
            for (int i = 0; i < L->count[k]; i++, j++)
                if (!(L->xy[2 * j] >= 0 && L->xy[2 * j] <= W0 && L->xy[2 * j + 1] >= 0 && L->xy[2 * j + 1] <= H0))
                    FAIL(SQ_ERR_INVALID, "body line", "stretches[%d][%d] (%.1f, %.1f) lies outside the %dx%d photo", k,
                         i, L->xy[2 * j], L->xy[2 * j + 1], W0, H0);
        }
        body.r = 0.5 * L->width * scale;
        if (!(body.r >= 3))
            FAIL(SQ_ERR_INVALID, "body line", "the body is %.1f pixels wide at %d px: too thin to see a pattern",
                 2 * body.r, w > h ? w : h);
        if (L->width > (W0 < H0 ? W0 : H0))
            FAIL(SQ_ERR_INVALID, "body line", "the body is %.0f pixels wide, wider than the %dx%d photo", L->width, W0,
                 H0);
        /* a strip of a sane length: a line may wind, not wind up */
        double total = 0;
        for (int k = 0, j = 0; k < L->nstretches; j += L->count[k++])
            for (int i = 1; i < L->count[k]; i++)
                total += hypot(L->xy[2 * (j + i)] - L->xy[2 * (j + i - 1)], L->xy[2 * (j + i) + 1] - L->xy[2 * (j + i - 1) + 1]);
        if (total > 16.0 * (W0 > H0 ? W0 : H0))
            FAIL(SQ_ERR_INVALID, "body line", "its stretches add up to %.0f pixels, more than 16 times the photo's longest side",
                 total);
        for (int k = 0, first = 0; k < L->nstretches; first += L->count[k++])
            if (line_curve(L, k, first, scale, body.r, &curves[ncurves++]) != 0)
                FAIL(SQ_ERR_NOMEM, "body line", "out of memory");
        body.m8 = malloc((size_t)w * h);
        if (!body.m8)
            FAIL(SQ_ERR_NOMEM, "body line", "out of memory");
        line_mask(curves, ncurves, body.r, w, h, body.m8);
        if (mask_in) { /* the mask given: body only where it says so too */
            size_t band = 0, kept = 0;
            for (size_t i = 0; i < (size_t)w * h; i++) {
                band += body.m8[i] != 0;
                body.m8[i] &= m8[i];
                kept += body.m8[i] != 0;
            }
            if (kept < band / 10)
                FAIL(SQ_ERR_INVALID, "mask", "the mask given covers %.0f%% of the body line's band (10%% at least): do they "
                     "belong to the same photo?", 100.0 * kept / (double)(band ? band : 1));
        } else {
            out->mask_source = SQ_MASK_LINE;
            band_body(&out->photo, curves, ncurves, body.r, body.m8);
        }
    }
    if (body.m8) {
        for (size_t i = 0; i < (size_t)w * h; i++)
            out->mask.px[i] = body.m8[i] ? 1.0f : 0.0f;
        debug_save(&o, "3_mask_clean.png", &out->mask);
    }
    if (body.path)
        debug_centre_line(&o, &out->photo, body.skel, body.path, body.n, body.nruns,
                          (const int(*)[2])body.runs);
    if (body.st != SQ_OK)
        FAIL(body.st, "mask", "%s%s", body.why,
             out->mask_source == SQ_MASK_AUTOMATIC ? " (automatic mask: give a body line with --line, or draw a mask and pass it with --mask)" : "");
    const double r = body.r;
    const double step = 2 * THETA_MAX * r / SQ_FIT_STRIP_W; /* one strip pixel of skin */

    /* 6. each run as a smooth curve with its local radius (a line's, made above) */
    for (int k = 0; k < body.nruns && !o.line; k++) {
        Curve *c = &curves[ncurves++]; /* freed at the end even if half made */
        if (curve_make(&body, w, h, body.runs[k][0], body.runs[k][1], c) != 0)
            FAIL(SQ_ERR_NOMEM, "mask", "out of memory");
    }
    for (int k = 0; k < ncurves; k++)
        curves[k].rows = (int)(curves[k].arc[curves[k].n - 1] / step);
    /* the runs whose edges are a body's width apart nearly all along (where the skeleton's
     * longest path cuts through a crossing or runs along the frame, they are not), if the
     * longest of them fills a strip; else the longest run alone, as it is; a line's
     * stretches all */
    int kept = 0, longest = 0;
    for (int k = 0; k < ncurves; k++)
        if (o.line || (curves[k].good >= MIN_RUN_GOOD && curves[k].n >= 2 * r)) {
            Curve t = curves[kept];
            curves[kept] = curves[k];
            curves[k] = t;
            if (curves[kept].rows > curves[longest].rows)
                longest = kept;
            kept++;
        }
    if (!o.line && (kept == 0 || curves[longest].rows < SQ_FIT_STRIP_W)) {
        for (int k = 0; k < ncurves; k++)
            if (curves[k].i0 == body.run0) {
                Curve t = curves[0];
                curves[0] = curves[k];
                curves[k] = t;
            }
        kept = 1;
        longest = 0;
    }
    while (ncurves > kept)
        curve_free(&curves[--ncurves]);
    int rows = 0;
    for (int k = 0; k < ncurves; k++)
        rows += curves[k].rows + (k ? RUN_GAP : 0);
    if (curves[longest].rows < SQ_FIT_STRIP_W) {
        double len = curves[longest].arc[curves[longest].n - 1];
        if (o.line)
            FAIL(SQ_ERR_INVALID, "body line",
                 "its longest stretch is %.0f pixels, %.1f body widths: too short to straighten (%.1f at least)",
                 len / scale, len / (2 * r), SQ_FIT_STRIP_W * step / (2 * r));
        FAIL(SQ_ERR_INVALID, "mask",
             "the longest clean stretch of body (not crossing or touching itself) is %.0f pixels, "
             "%.1f body widths: too short to straighten (%.1f at least)",
             len, len / (2 * r), SQ_FIT_STRIP_W * step / (2 * r));
    }
    tangent = malloc(sizeof *tangent * (size_t)rows);
    if (!tangent || sq_image_alloc(&out->strip, SQ_FIT_STRIP_W, rows, 3, SQ_SPACE_SRGB) ||
        sq_image_alloc(&out->valid, SQ_FIT_STRIP_W, rows, 1, SQ_SPACE_DATA))
        FAIL(SQ_ERR_NOMEM, "strip", "out of memory for the strip");
    for (int y = 0; y < rows; y++)
        tangent[y][0] = tangent[y][1] = NAN; /* the gaps between runs */
    /* 7. resample perpendicular to the centre lines, run after run (the gaps between them
     * count as not body) */
    double length = 0;
    for (int k = 0, row0 = 0; k < ncurves; k++) {
        curve_sample(&curves[k], &out->photo, body.m8, step, &out->strip, &out->valid, row0, tangent);
        row0 += curves[k].rows + RUN_GAP;
        length += curves[k].rows * step;
    }
    debug_save(&o, "5_strip_raw.png", &out->strip);
    estimate_light(&out->strip, &out->valid, tangent, &out->light, out->light_xy);
    divide_turning_light(&out->strip, tangent, &out->light, out->light_xy);
    /* the light of each stretch on its own: another part of the body lies another way */
    for (int k = 0, row0 = 0; k < ncurves; k++) {
        SqImage sv = out->strip, vv = out->valid;
        sv.px += (size_t)row0 * SQ_FIT_STRIP_W * 3;
        vv.px += (size_t)row0 * SQ_FIT_STRIP_W;
        sv.height = vv.height = curves[k].rows;
        if (curves[k].rows > 0)
            sq__fit_normalise_light(&sv, &vv);
        row0 += curves[k].rows + RUN_GAP;
    }
    debug_save(&o, "6_strip.png", &out->strip);
    debug_save(&o, "7_strip_valid.png", &out->valid);

    out->step = step;
    out->edge_blur = edge_blur(curves, ncurves, &out->photo);
    out->body_width = 2 * r / scale;
    out->length = length / scale;
    out->nruns = ncurves;
    for (int k = 0; k < ncurves; k++)
        out->npoints += curves[k].n;
    out->centre = malloc(sizeof(float) * 2 * (size_t)out->npoints);
    out->run_points = malloc(sizeof(int) * (size_t)ncurves);
    if (!out->centre || !out->run_points)
        FAIL(SQ_ERR_NOMEM, "mask", "out of memory");
    for (int k = 0; k < ncurves; k++)
        out->run_points[k] = curves[k].n;
    for (int k = 0, j = 0; k < ncurves; k++)
        for (int i = 0; i < curves[k].n; i++, j++) {
            out->centre[2 * j] = (float)(curves[k].px[i] / scale);
            out->centre[2 * j + 1] = (float)(curves[k].py[i] / scale);
        }
#undef FAIL
done:
    free(tangent);
    free(rgb0);
    free(m8);
    body_free(&body);
    for (int k = 0; k < ncurves; k++)
        curve_free(&curves[k]);
    return st == SQ_OK ? SQ_OK : fail(out, st);
}
