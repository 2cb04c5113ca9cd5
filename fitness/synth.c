/* Synthetic photos with ground truth: a preset's maps on a lit tube along a random
 * smooth curve, over a natural backdrop. The test bed for photo preparation, features
 * and fitting; also `squama render --preview`.
 *
 * The tube: centre line c(s) with unit tangent T and normal N, radius r. A pixel at
 * signed distance d from the centre line sees the surface at angle th = asin(d / r) from
 * the top, so texture u = band_centre + th / 2pi (the visible half) and v = s / (view
 * scale * 2 pi r). Where the body crosses itself the later part lies on top. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fitness_internal.h"
#include "gen_internal.h"
#include "squama/io.h"

SqPhotoOptions sq_fit_photo_options_default(void)
{
    SqPhotoOptions o = {.width = 1024, .height = 768, .seed = 1, .band_centre = 0.5, .coil = 0.5,
                        .texture_size = 512, .samples = 4};
    return o;
}

void sq_fit_truth_free(SqPhotoTruth *t)
{
    if (t) {
        free(t->points);
        memset(t, 0, sizeof *t);
    }
}

enum { STREAM_CURVE = 101, STREAM_BACK = 102, STREAM_LEAVES = 103, STREAM_NOISE = 104, STREAM_PICK = 105 };

typedef struct Curve {
    int n;
    float *x, *y, *tx, *ty; /* points one pixel apart and their unit tangents */
    float *r;               /* body radius there: a rounded head, a tapering tail */
} Curve;

static void curve_free(Curve *c)
{
    free(c->x);
    free(c->y);
    free(c->tx);
    free(c->ty);
    free(c->r);
    memset(c, 0, sizeof *c);
}

static int curve_alloc(Curve *c, int n)
{
    c->x = malloc(sizeof(float) * (size_t)n);
    c->y = malloc(sizeof(float) * (size_t)n);
    c->tx = malloc(sizeof(float) * (size_t)n);
    c->ty = malloc(sizeof(float) * (size_t)n);
    c->r = malloc(sizeof(float) * (size_t)n);
    c->n = 0;
    return c->x && c->y && c->tx && c->ty && c->r ? 0 : -1;
}

enum { WALK_ATTEMPTS = 64 };

/* One random walk into c, its heading turning smoothly (three sines of random wavelength
 * and phase), steered back towards the middle near the frame's edges, its bends never
 * tighter than 1.3 body radii; attempt 0, 1, ... draw different ones. Returns
 * how far the body leaves the frame: the sum over its samples of how much of the radius,
 * and a margin of two pixels, is past an edge (0: all in). */
static double walk(const SqPhotoOptions *o, double r, int attempt, Curve *c)
{
    const int w = o->width, h = o->height;
    const uint64_t seed = o->seed;
    const int max = (int)(1.4 * (w + h)) + 16, k0 = 64 * attempt;
    const double margin = 1.5 * r;
    double x = margin + sq__rand01(seed, STREAM_CURVE, k0 + 0) * (w - 2 * margin);
    double y = margin + sq__rand01(seed, STREAM_CURVE, k0 + 1) * (h - 2 * margin);
    double head = 2 * M_PI * sq__rand01(seed, STREAM_CURVE, k0 + 2);
    double amp[3], wl[3], ph[3], cut = 0;
    for (int k = 0; k < 3; k++) {
        amp[k] = (0.3 + 0.7 * sq__rand01(seed, STREAM_CURVE, k0 + 10 + k)) * (0.15 + 0.85 * o->coil);
        wl[k] = r * (6 + 24 * sq__rand01(seed, STREAM_CURVE, k0 + 20 + k));
        ph[k] = 2 * M_PI * sq__rand01(seed, STREAM_CURVE, k0 + 30 + k);
    }
    const double kmax = 1.0 / (1.3 * r);
    const double length = 0.9 * (w + h);
    c->n = 0;
    for (int i = 0; i < max && i < length; i++) {
        c->x[c->n] = (float)x;
        c->y[c->n] = (float)y;
        c->n++;
        double k = 0;
        for (int j = 0; j < 3; j++)
            k += amp[j] * sin(2 * M_PI * i / wl[j] + ph[j]);
        k *= kmax;
        /* near an edge, turn towards the middle */
        double edge = fmin(fmin(x, w - x), fmin(y, h - y));
        cut += fmax(0, r + 2 - edge); /* a pixel or two of grass beyond the outline */
        if (edge < 3 * r) {
            double want = atan2(h / 2.0 - y, w / 2.0 - x), diff = remainder(want - head, 2 * M_PI);
            k += (diff > 0 ? 1 : -1) * kmax * (1 - fmax(edge, 0) / (3 * r));
        }
        k = fmax(-kmax, fmin(kmax, k));
        head += k;
        x += cos(head);
        y += sin(head);
    }
    return cut;
}

/* How much of the body touches or lies on another part of itself: samples (every other
 * pixel) nearer than a body width plus a pixel or two to a sample more than four radii
 * further along. */
static int touching(const Curve *c, double r)
{
    const int gap = (int)ceil(4 * r);
    const double near = (2 * r + 2) * (2 * r + 2);
    int n = 0;
    for (int i = 0; i < c->n; i += 2)
        for (int j = i + gap; j < c->n; j += 2) {
            double dx = c->x[j] - c->x[i], dy = c->y[j] - c->y[i];
            if (dx * dx + dy * dy < near) {
                n++;
                break;
            }
        }
    return n;
}

/* The body's centre line: a gentle S for a preview, else a random walk (see walk) that
 * keeps the body in the frame (and a gently coiled one clear of itself) where one of
 * WALK_ATTEMPTS does. */
static int make_curve(const SqPhotoOptions *o, double r, Curve *c)
{
    const int w = o->width, h = o->height;
    const int max = (int)(1.4 * (w + h)) + 16;
    if (curve_alloc(c, max))
        return -1;
    if (o->preview) { /* a gentle S, walked in one-pixel steps */
        double x = w * 0.06, y;
        while (x < w * 0.94 && c->n < max) {
            double t = x / w - 0.06;
            y = h * (0.5 + 0.22 * sin(2 * M_PI * 1.25 * t / 0.88 + 0.4));
            double slope = h * 0.22 * cos(2 * M_PI * 1.25 * t / 0.88 + 0.4) * 2 * M_PI * 1.25 / 0.88 / w;
            c->x[c->n] = (float)x;
            c->y[c->n] = (float)y;
            c->n++;
            x += 1.0 / sqrt(1 + slope * slope);
        }
    } else {
        /* walks until one keeps the whole body in the frame, as a photographer frames a
         * snake, and clear of itself (above coil 0.5, a share of coil - 0.5 may touch:
         * partial coils); else the one that leaves the frame least, then touches itself
         * least */
        double least = INFINITY;
        int best = 0;
        for (int attempt = 0; attempt < WALK_ATTEMPTS; attempt++) {
            double cut = walk(o, r, attempt, c);
            double bad = cut * 1e6 + fmax(0, touching(c, r) - fmax(0, o->coil - 0.5) * c->n / 2);
            if (bad < least) {
                least = bad;
                best = attempt;
            }
            if (bad == 0)
                break;
        }
        if (least > 0)
            walk(o, r, best, c);
    }
    /* the radius: a half-disc head over the first radius, the tail thinning over the last
     * eight radii to a sixth */
    for (int i = 0; i < c->n; i++) {
        double head_t = i < r ? 1 - i / r : 0, tail_t = (c->n - 1 - i) / (8 * r);
        double k = sqrt(fmax(0, 1 - head_t * head_t));
        if (tail_t < 1)
            k = fmin(k, 1.0 / 6 + 5.0 / 6 * tail_t);
        c->r[i] = (float)(r * k);
    }
    /* tangents by central differences */
    for (int i = 0; i < c->n; i++) {
        int a = i > 0 ? i - 1 : i, b = i + 1 < c->n ? i + 1 : i;
        double dx = c->x[b] - c->x[a], dy = c->y[b] - c->y[a], l = hypot(dx, dy);
        c->tx[i] = l > 0 ? (float)(dx / l) : 1.0f;
        c->ty[i] = l > 0 ? (float)(dy / l) : 0.0f;
    }
    return c->n > 8 ? 0 : -1;
}

/* The pixel's owner on the body: the curve sample nearest along the body; where two
 * parts of the body overlap, the later one (it lies on top). */
typedef struct Owner {
    float s, d, a; /* arc length, signed distance across, distance along */
} Owner;

static void paint_body(const Curve *c, double r, int w, int h, Owner *own)
{
    for (size_t i = 0; i < (size_t)w * h; i++)
        own[i].s = -1;
    const float far = (float)(4 * r);
    for (int i = 0; i < c->n; i++) {
        const float px = c->x[i], py = c->y[i], tx = c->tx[i], ty = c->ty[i];
        const float reach = c->r[i] + 1.0f;
        int x0 = (int)floorf(px - reach), x1 = (int)ceilf(px + reach);
        int y0 = (int)floorf(py - reach), y1 = (int)ceilf(py + reach);
        x0 = x0 < 0 ? 0 : x0;
        y0 = y0 < 0 ? 0 : y0;
        x1 = x1 > w - 1 ? w - 1 : x1;
        y1 = y1 > h - 1 ? h - 1 : y1;
        for (int y = y0; y <= y1; y++)
            for (int x = x0; x <= x1; x++) {
                float dx = (float)x + 0.5f - px, dy = (float)y + 0.5f - py;
                float a = dx * tx + dy * ty, d = -dx * ty + dy * tx;
                if (fabsf(a) > 1.0f || fabsf(d) > reach)
                    continue;
                /* samples come in order: one far behind the owner is a later part
                 * of the body, on top; a nearby one wins when it is nearer */
                Owner *o = &own[(size_t)y * w + x];
                if (o->s < 0 || (float)i - o->s > far || fabsf(a) < fabsf(o->a)) {
                    o->s = (float)i;
                    o->d = d;
                    o->a = a;
                }
            }
    }
}

static float srgb_lin(float v)
{
    return sq_io_srgb_to_linear(v < 0 ? 0 : (v > 1 ? 1 : v));
}

/* Bilinear, wrapping sample of a map at texture (u, v). */
static void tex(const SqImage *m, double u, double v, float *out)
{
    float x = (float)(u * m->width - 0.5), y = (float)(v * m->height - 0.5);
    for (int c = 0; c < m->channels; c++)
        out[c] = sq__sample(m->px, m->width, m->height, m->channels, c, x, y);
}

/* Natural backdrops in linear RGB. */
static int backdrop(const SqPhotoOptions *o, SqBackdrop kind, float *rgb)
{
    const int w = o->width, h = o->height;
    const uint64_t seed = o->seed;
    float *n1 = sq__falloc((size_t)w * h), *n2 = sq__falloc((size_t)w * h);
    if (!n1 || !n2 || sq__fbm(n1, w, h, seed, STREAM_BACK, 6, 5, 0.55) ||
        sq__fbm(n2, w, h, seed, STREAM_BACK + 1, 24, 4, 0.6)) {
        sq__ffree(n1);
        sq__ffree(n2);
        return -1;
    }
    static const float soil[2][3] = {{0.09f, 0.06f, 0.035f}, {0.30f, 0.22f, 0.14f}};
    static const float litter[2][3] = {{0.05f, 0.035f, 0.02f}, {0.20f, 0.13f, 0.07f}};
    static const float grass[2][3] = {{0.03f, 0.06f, 0.015f}, {0.16f, 0.26f, 0.07f}};
    static const float plain[2][3] = {{0.55f, 0.55f, 0.56f}, {0.75f, 0.75f, 0.76f}};
    const float(*pal)[3] = kind == SQ_BACKDROP_SOIL     ? soil
                           : kind == SQ_BACKDROP_LITTER ? litter
                           : kind == SQ_BACKDROP_GRASS  ? grass
                                                        : plain;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            float t = kind == SQ_BACKDROP_PLAIN ? 1.0f - (float)y / h : n1[i];
            float g = kind == SQ_BACKDROP_PLAIN ? 1.0f : 0.75f + 0.5f * n2[i];
            for (int c = 0; c < 3; c++)
                rgb[3 * i + c] = (pal[0][c] + (pal[1][c] - pal[0][c]) * t) * g;
        }
    if (kind == SQ_BACKDROP_LITTER || kind == SQ_BACKDROP_GRASS) {
        /* leaves (ellipses with a midrib) or blades (thin long ellipses) */
        static const float leaf[5][3] = {{0.25f, 0.12f, 0.04f}, {0.40f, 0.22f, 0.06f}, {0.15f, 0.08f, 0.03f},
                                         {0.45f, 0.33f, 0.12f}, {0.30f, 0.10f, 0.03f}};
        static const float blade[3][3] = {{0.10f, 0.22f, 0.04f}, {0.22f, 0.35f, 0.08f}, {0.30f, 0.30f, 0.12f}};
        const int count = kind == SQ_BACKDROP_LITTER ? w * h / 900 : w * h / 300;
        const double size = (w < h ? w : h) / 22.0;
        for (int k = 0; k < count; k++) {
            uint64_t id = (uint64_t)k * 8;
            double cx = sq__rand01(seed, STREAM_LEAVES, id) * w, cy = sq__rand01(seed, STREAM_LEAVES, id + 1) * h;
            double ang = M_PI * sq__rand01(seed, STREAM_LEAVES, id + 2);
            double len = size * (kind == SQ_BACKDROP_LITTER ? 0.6 + 0.9 * sq__rand01(seed, STREAM_LEAVES, id + 3)
                                                            : 1.5 + 2.5 * sq__rand01(seed, STREAM_LEAVES, id + 3));
            double wid = kind == SQ_BACKDROP_LITTER ? len * (0.35 + 0.2 * sq__rand01(seed, STREAM_LEAVES, id + 4))
                                                    : len * 0.04;
            const float *col = kind == SQ_BACKDROP_LITTER
                                   ? leaf[(int)(5 * sq__rand01(seed, STREAM_LEAVES, id + 5))]
                                   : blade[(int)(3 * sq__rand01(seed, STREAM_LEAVES, id + 5))];
            float shade = (float)(0.6 + 0.6 * sq__rand01(seed, STREAM_LEAVES, id + 6));
            double ca = cos(ang), sa = sin(ang), ext = len;
            for (int y = (int)fmax(0, cy - ext); y < (int)fmin(h, cy + ext + 1); y++)
                for (int x = (int)fmax(0, cx - ext); x < (int)fmin(w, cx + ext + 1); x++) {
                    double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
                    double a = (dx * ca + dy * sa) / len, b = (-dx * sa + dy * ca) / wid;
                    double q = a * a + b * b;
                    if (q > 1)
                        continue;
                    float edge = (float)(0.55 + 0.45 * sqrt(1 - q)); /* darker rim */
                    if (kind == SQ_BACKDROP_LITTER && fabs(b) < 0.08)
                        edge *= 0.7f; /* midrib */
                    size_t i = (size_t)y * w + x;
                    for (int c = 0; c < 3; c++)
                        rgb[3 * i + c] = col[c] * shade * edge;
                }
        }
    }
    sq__ffree(n1);
    sq__ffree(n2);
    return 0;
}

/* squama photo's key light (from the upper left) and its half vector towards a camera
 * straight above, both unit. */
typedef struct Light {
    double L[3], H[3];
} Light;

static Light key_light(void)
{
    const double lx = -0.35, ly = -0.55, lz = 0.76, ln = sqrt(lx * lx + ly * ly + lz * lz);
    Light l = {.L = {lx / ln, ly / ln, lz / ln}};
    const double hz = l.L[2] + 1, hn = sqrt(l.L[0] * l.L[0] + l.L[1] * l.L[1] + hz * hz);
    l.H[0] = l.L[0] / hn;
    l.H[1] = l.L[1] / hn;
    l.H[2] = hz / hn;
    return l;
}

/* The lit colour (linear RGB) of the body at arc length s (pixels along the curve,
 * heading (tx, ty)) and sn = signed distance across / radius: the glossy tube that
 * candidates' strips imitate (fitness/strip.c). tile: pixels along the body one
 * texture tile spans. */
static void lit_point(const SqTextures *maps, const Light *light, double tx, double ty, double s, double sn,
                      double band_centre, double tile, double lit[3])
{
    sn = fmax(-0.999, fmin(0.999, sn));
    const double th = asin(sn), cs = cos(th);
    const double u = band_centre + th / (2 * M_PI), v = s / tile;
    float base[3], nm[3], rough;
    tex(&maps->basecolor, u, v, base);
    tex(&maps->normal, u, v, nm);
    tex(&maps->roughness, u, v, &rough);
    /* frame: across (+u), along (+v), out of the surface */
    const double Nx = -ty, Ny = tx;
    const double eu[3] = {Nx * cs, Ny * cs, -sn}, ev[3] = {tx, ty, 0}, n0[3] = {Nx * sn, Ny * sn, cs};
    const double tn[3] = {2 * nm[0] - 1.0, 2 * nm[1] - 1.0, 2 * nm[2] - 1.0};
    double n[3];
    for (int k = 0; k < 3; k++) /* OpenGL: +Y points to -v */
        n[k] = tn[0] * eu[k] - tn[1] * ev[k] + tn[2] * n0[k];
    const double nl = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++)
        n[k] /= nl;
    const double diff = fmax(0, n[0] * light->L[0] + n[1] * light->L[1] + n[2] * light->L[2]);
    const double gl = 1 - rough, nh = fmax(0, n[0] * light->H[0] + n[1] * light->H[1] + n[2] * light->H[2]);
    const double spec = 0.35 * gl * gl * pow(nh, 2 + 300 * gl * gl * gl);
    const double ao = 0.75 + 0.25 * cs;
    for (int k = 0; k < 3; k++)
        lit[k] = srgb_lin(base[k]) * (0.30 + 0.85 * diff) * ao + spec;
}

SqStatus sq_fit_synth_photo(const SqParams *p, const SqPhotoOptions *opt, SqImage *photo,
                            SqImage *mask, SqPhotoTruth *truth, SqError *err)
{
    memset(photo, 0, sizeof *photo);
    memset(mask, 0, sizeof *mask);
    if (truth)
        memset(truth, 0, sizeof *truth);
    SqPhotoOptions o = opt ? *opt : sq_fit_photo_options_default();
    if (o.width < 64 || o.height < 64 || o.width > 8192 || o.height > 8192)
        return sq_error_set(err, SQ_ERR_INVALID, "photo", "photo size %dx%d is outside 64 to 8192",
                            o.width, o.height);
    if (o.texture_size <= 0)
        o.texture_size = 512;
    if (o.samples < 1 || o.samples > 16)
        return sq_error_set(err, SQ_ERR_INVALID, "photo", "%d samples a pixel is outside 1 to 16", o.samples);
    const uint64_t seed = o.seed;
    const int w = o.width, h = o.height, side = w < h ? w : h;
    double r = o.body_radius > 0 ? o.body_radius
                                 : side * (0.035 + 0.035 * sq__rand01(seed, STREAM_PICK, 0));
    if (o.preview && o.body_radius <= 0)
        r = side * 0.08;
    double scale = o.view_scale > 0 ? o.view_scale : 0.5 * pow(4.0, sq__rand01(seed, STREAM_PICK, 1));
    SqBackdrop kind = o.preview ? SQ_BACKDROP_PLAIN : o.backdrop;
    if (kind == SQ_BACKDROP_RANDOM)
        kind = (SqBackdrop)(SQ_BACKDROP_SOIL + (int)(3 * sq__rand01(seed, STREAM_PICK, 2)));
    if (r < 4 || r > side / 3.0)
        return sq_error_set(err, SQ_ERR_INVALID, "photo", "body radius %.1f px does not fit a %dx%d photo",
                            r, w, h);

    SqTextures maps;
    SqGenOptions go = sq_gen_options_default(o.texture_size);
    SqStatus st = sq_gen_render(p, &go, &maps, err);
    if (st != SQ_OK)
        return st;
    Curve c = {0};
    Owner *own = malloc(sizeof(Owner) * (size_t)w * h);
    float *rgb = sq__falloc((size_t)w * h * 3), *cover = sq__falloc((size_t)w * h);
    if (!own || !rgb || !cover || make_curve(&o, r, &c) || backdrop(&o, kind, rgb)) {
        st = sq_error_set(err, SQ_ERR_NOMEM, "photo", "out of memory for a %dx%d photo", w, h);
        goto done;
    }
    paint_body(&c, r, w, h, own);

    /* the body's soft shadow, cast down and right */
    for (size_t i = 0; i < (size_t)w * h; i++)
        cover[i] = own[i].s >= 0 && fabsf(own[i].d) < c.r[(int)own[i].s] ? 1.0f : 0.0f;
    {
        float *shadow = sq__falloc((size_t)w * h);
        if (!shadow) {
            st = sq_error_set(err, SQ_ERR_NOMEM, "photo", "out of memory");
            goto done;
        }
        int off = (int)(0.35 * r);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                shadow[(size_t)y * w + x] = (x >= off && y >= off) ? cover[(size_t)(y - off) * w + (x - off)] : 0;
        sq__blur(shadow, w, h, 1, 0.4 * r);
        for (size_t i = 0; i < (size_t)w * h; i++)
            for (int ch = 0; ch < 3; ch++)
                rgb[3 * i + ch] *= 1.0f - 0.55f * shadow[i];
        sq__ffree(shadow);
    }

    /* the lit body, a row at a time on each thread (each pixel on its own: the same
     * photo on any thread count) */
    const Light light = key_light();
    const double circ = 2 * M_PI * r;
#pragma omp parallel for schedule(dynamic, 8)
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            const Owner *ow = &own[i];
            if (ow->s < 0)
                continue;
            int si = (int)ow->s;
            const double rs = c.r[si];
            float alpha = sq__clamp01((float)rs - fabsf(ow->d) + 0.5f);
            if (alpha <= 0 || rs < 0.5)
                continue;
            /* A camera pixel is the mean of the skin it sees: o.samples x o.samples
             * points over the pixel, each moved across and along the body from the
             * pixel's centre (the curve's tangent there), lit and summed in linear light.
             * One point a pixel (at a view scale of 0.66 and a 512 texture, four texels
             * along the body between pixels) aliased the scales' fine relief into a
             * crisp shimmer no camera shows, which the candidates' strips, each pixel
             * the mean of the skin it covers, could not match. */
            const double tx = c.tx[si], ty = c.ty[si];
            double acc[3] = {0, 0, 0};
            for (int sy = 0; sy < o.samples; sy++)
                for (int sx = 0; sx < o.samples; sx++) {
                    const double ox = (sx + 0.5) / o.samples - 0.5, oy = (sy + 0.5) / o.samples - 0.5;
                    double lit[3];
                    lit_point(&maps, &light, tx, ty, ow->s + ((double)ow->a + ox * tx + oy * ty),
                              (ow->d - ox * ty + oy * tx) / rs, o.band_centre, scale * circ, lit);
                    for (int k = 0; k < 3; k++)
                        acc[k] += lit[k];
                }
            for (int k = 0; k < 3; k++) {
                const double lit = acc[k] / (o.samples * o.samples);
                rgb[3 * i + k] = (float)(lit * alpha + rgb[3 * i + k] * (1 - alpha));
            }
            cover[i] = alpha;
        }

    /* the camera: blur, colour cast, sensor noise, to sRGB */
    if (o.blur > 0.3)
        sq__blur(rgb, w, h, 3, o.blur);
    if (sq_image_alloc(photo, w, h, 3, SQ_SPACE_SRGB) || sq_image_alloc(mask, w, h, 1, SQ_SPACE_DATA)) {
        st = sq_error_set(err, SQ_ERR_NOMEM, "photo", "out of memory");
        goto done;
    }
    float castf[3] = {1, 1, 1};
    for (int k = 0; k < 3; k++)
        castf[k] = (float)(1 + o.cast * (0.6 * sq__rand11(seed, STREAM_PICK, 10 + (uint64_t)k)));
    for (size_t i = 0; i < (size_t)w * h; i++) {
        for (int k = 0; k < 3; k++) {
            double g = 0;
            if (o.noise > 0) { /* Box-Muller */
                double u1 = sq__rand01(seed, STREAM_NOISE, 6 * i + 2 * k) + 1e-12, u2 = sq__rand01(seed, STREAM_NOISE, 6 * i + 2 * k + 1);
                g = sqrt(-2 * log(u1)) * cos(2 * M_PI * u2) * o.noise;
            }
            photo->px[3 * i + k] = sq__clamp01(sq_io_linear_to_srgb(fmaxf(0, rgb[3 * i + k] * castf[k])) + (float)g);
        }
        mask->px[i] = cover[i] >= 0.5f ? 1.0f : 0.0f;
    }
    if (truth) {
        truth->view_scale = scale;
        truth->body_radius = r;
        truth->band_centre = o.band_centre;
        truth->length = c.n;
        truth->npoints = (c.n + 3) / 4;
        truth->points = malloc(sizeof(float) * 2 * (size_t)truth->npoints);
        if (!truth->points) {
            st = sq_error_set(err, SQ_ERR_NOMEM, "photo", "out of memory");
            goto done;
        }
        for (int k = 0; k < truth->npoints; k++) {
            truth->points[2 * k] = c.x[4 * k];
            truth->points[2 * k + 1] = c.y[4 * k];
        }
    }
done:
    if (st != SQ_OK) {
        sq_image_free(photo);
        sq_image_free(mask);
        if (truth)
            sq_fit_truth_free(truth);
    }
    sq_gen_textures_free(&maps);
    curve_free(&c);
    free(own);
    sq__ffree(rgb);
    sq__ffree(cover);
    return st;
}
