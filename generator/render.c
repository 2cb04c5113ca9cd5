/* The generator's driver (thesis §4.1): height (scales + micro detail), roughness and
 * normal maps; the colour map as background, pattern layers, post-process, outline and
 * warp, and last the skin between the scales. */
#include <string.h>
#include <time.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "gen_internal.h"

/* The fractal sum shared by the height map's micro detail and the roughness (§4.4). */
enum { DETAIL_CELLS = 32, DETAIL_OCTAVES = 4, COLOR_CELLS = 4, COLOR_OCTAVES = 4 };

SqGenOptions sq_gen_options_default(int size)
{
    SqGenOptions o = {.width = size, .height = size, .normal_directx = 0, .threads = 0,
                      .timings = NULL};
    return o;
}

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

void sq_gen_textures_free(SqTextures *t)
{
    if (!t)
        return;
    sq_image_free(&t->basecolor);
    sq_image_free(&t->height);
    sq_image_free(&t->roughness);
    sq_image_free(&t->normal);
}

/* A pattern ready to be sampled row by row: its coverage layers (or, with an outline,
 * their premultiplied image) and its warp. The base pattern is one; each pattern layer
 * of the preset is another. */
typedef struct PatternSource {
    SqPattern pat;
    SqWarp warp;
    SqLerp wx, wy;         /* the warp grid interpolated to pixels */
    float *rgba;           /* premultiplied pattern image (outline only) */
    int sample_layers;     /* the coverage layers are sampled directly */
    int blend;             /* pattern layers: SqLayerBlend */
    float opacity;         /* pattern layers: Layer_Opacity */
} PatternSource;

static void source_free(PatternSource *s)
{
    sq__lerp_free(&s->wx);
    sq__lerp_free(&s->wy);
    sq__pattern_free(&s->pat);
    sq__warp_free(&s->warp);
    sq__ffree(s->rgba);
    memset(s, 0, sizeof *s);
}

/* Makes the pattern of q's pattern parameters: its layers, post-process, outline (when q
 * has one) and warp field. The colour map samples it through the warp; patterns made
 * only of stripe profiles are sampled from the profiles, with no pattern image at all. */
static SqStatus source_make(const SqParams *q, const float *height, int w, int h,
                            PatternSource *s, SqError *err)
{
    SqStatus st = SQ_OK;
    s->pat.w = w;
    s->pat.h = h;
    if (q->Pattern_RotatePattern90Degrees) { /* generated on its side, rotated after */
        s->pat.w = h;
        s->pat.h = w;
    }
    switch (q->Pattern_Type) {
    case SQ_PATTERN_TRANSVERSAL: st = sq__pattern_transversal(q, &s->pat, err); break;
    case SQ_PATTERN_LONGITUDINAL: st = sq__pattern_longitudinal(q, &s->pat, err); break;
    case SQ_PATTERN_SPOTS: st = sq__pattern_spots(q, &s->pat, err); break;
    case SQ_PATTERN_OTHER_SIMPLE: st = sq__pattern_ca(q, &s->pat, err); break;
    case SQ_PATTERN_COMPLEX: st = sq__pattern_rd(q, &s->pat, err); break;
    default: break;
    }
    if (st == SQ_OK)
        st = sq__pattern_postprocess(q, &s->pat, err);
    /* without an outline the layers are sampled where the colour map needs them; the
     * outline needs the pattern as an image */
    s->sample_layers = s->pat.n > 0 && !q->Has_Outline;
    if (st == SQ_OK && s->pat.n > 0 && !s->sample_layers) {
        if (!(s->rgba = sq__falloc_raw((size_t)w * h * 4)))
            st = sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the pattern");
        else
            sq__pattern_composite(&s->pat, s->rgba);
        if (st == SQ_OK && q->Has_Outline)
            st = sq__outline(q, s->rgba, height, w, h, err);
    }
    if (st == SQ_OK && s->pat.n > 0)
        st = sq__warp_field(q, w, h, &s->warp, err);
    if (st == SQ_OK && s->warp.dx &&
        (sq__lerp_init(&s->wx, w, s->warp.gw) || sq__lerp_init(&s->wy, h, s->warp.gh)))
        st = sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the warp");
    return st;
}

/* Row y of a pattern, premultiplied, into pr, pg, pb, pa: the displaced coordinates
 * (fxs, fys; rowx, rowy hold the warp grid's row), then the pattern sampled there. */
static void source_row(const PatternSource *s, int y, int w, int h, float *fxs, float *fys,
                       float *rowx, float *rowy, float *pr, float *pg, float *pb, float *pa)
{
    const SqPattern *pat = &s->pat;
    const SqWarp *warp = &s->warp;
    const SqLerp *wx = &s->wx, *wy = &s->wy;
    const int gw = warp->gw;
    if (warp->dx) {
        const float *dx0 = warp->dx + (size_t)wy->i0[y] * gw, *dx1 = warp->dx + (size_t)wy->i1[y] * gw;
        const float *dy0 = warp->dy + (size_t)wy->i0[y] * gw, *dy1 = warp->dy + (size_t)wy->i1[y] * gw;
        const float ty = wy->t[y];
        for (int g = 0; g < gw; g++) {
            rowx[g] = dx0[g] + (dx1[g] - dx0[g]) * ty;
            rowy[g] = dy0[g] + (dy1[g] - dy0[g]) * ty;
        }
        for (int x = 0; x < w; x++) {
            const int a = wx->i0[x], c = wx->i1[x];
            fxs[x] = (float)x + rowx[a] + (rowx[c] - rowx[a]) * wx->t[x];
            fys[x] = (float)y + rowy[a] + (rowy[c] - rowy[a]) * wx->t[x];
        }
    } else {
        for (int x = 0; x < w; x++) {
            fxs[x] = (float)x;
            fys[x] = (float)y;
        }
    }
    for (int x = 0; x < w; x++)
        pr[x] = pg[x] = pb[x] = pa[x] = 0.0f;
    if (s->sample_layers && !warp->dx) { /* profiles read directly */
        for (int li = 0; li < pat->n; li++) {
            const SqLayer *l = &pat->layers[li];
            const float lr = l->color[0], lg = l->color[1], lb = l->color[2], lo = l->color[3];
            if (l->kind == SQ_LAYER_COLS || l->kind == SQ_LAYER_2D) {
                const float *cv = l->cov + (l->kind == SQ_LAYER_2D ? (size_t)y * w : 0);
                for (int x = 0; x < w; x++) {
                    float al = cv[x] * lo, k = 1.0f - al;
                    pr[x] = lr * al + pr[x] * k;
                    pg[x] = lg * al + pg[x] * k;
                    pb[x] = lb * al + pb[x] * k;
                    pa[x] = al + pa[x] * k;
                }
            } else {
                const float al = (l->kind == SQ_LAYER_ROWS ? l->cov[y] : 1.0f) * lo, k = 1.0f - al;
                for (int x = 0; x < w; x++) {
                    pr[x] = lr * al + pr[x] * k;
                    pg[x] = lg * al + pg[x] * k;
                    pb[x] = lb * al + pb[x] * k;
                    pa[x] = al + pa[x] * k;
                }
            }
        }
    } else if (s->sample_layers) {
        for (int li = 0; li < pat->n; li++) {
            const SqLayer *l = &pat->layers[li];
            const float lr = l->color[0], lg = l->color[1], lb = l->color[2], lo = l->color[3];
            for (int x = 0; x < w; x++) {
                float cov = l->kind == SQ_LAYER_COLS   ? sq__profile_at(l->cov, pat->w, fxs[x])
                            : l->kind == SQ_LAYER_ROWS ? sq__profile_at(l->cov, pat->h, fys[x])
                            : l->kind == SQ_LAYER_2D   ? sq__sample(l->cov, w, h, 1, 0, fxs[x], fys[x])
                                                       : 1.0f;
                float al = cov * lo, k = 1.0f - al;
                pr[x] = lr * al + pr[x] * k;
                pg[x] = lg * al + pg[x] * k;
                pb[x] = lb * al + pb[x] * k;
                pa[x] = al + pa[x] * k;
            }
        }
    } else if (s->rgba) {
        for (int x = 0; x < w; x++) {
            float c4[4];
            if (warp->dx) {
                for (int c = 0; c < 4; c++)
                    c4[c] = sq__sample(s->rgba, w, h, 4, c, fxs[x], fys[x]);
            } else {
                memcpy(c4, s->rgba + ((size_t)y * w + x) * 4, sizeof c4);
            }
            pr[x] = c4[0];
            pg[x] = c4[1];
            pb[x] = c4[2];
            pa[x] = c4[3];
        }
    }
}

/* Blends a pattern layer's premultiplied row (pr, pg, pb, pa) over the colour row `out`
 * (RGB, opaque) with its mode and opacity: out (1 - a) + B(out, colour) a, the W3C
 * separable blend modes written on premultiplied values, so no division by coverage. */
static void blend_row(const PatternSource *s, float *out, int w, const float *pr,
                      const float *pg, const float *pb, const float *pa)
{
    const float o = s->opacity;
    for (int x = 0; x < w; x++) {
        const float a = pa[x] * o;
        if (a <= 0.0f)
            continue;
        const float l[3] = {pr[x] * o, pg[x] * o, pb[x] * o};
        float *px = out + 3 * x;
        for (int c = 0; c < 3; c++) {
            const float cb = px[c];
            float v;
            switch (s->blend) {
            case SQ_BLEND_MULTIPLY: v = cb * (1.0f - a) + cb * l[c]; break;
            case SQ_BLEND_SCREEN: v = cb + l[c] - cb * l[c]; break;
            case SQ_BLEND_OVERLAY:
                v = cb * (1.0f - a) +
                    (cb <= 0.5f ? 2.0f * cb * l[c] : a - 2.0f * (1.0f - cb) * (a - l[c]));
                break;
            default: v = cb * (1.0f - a) + l[c]; break;
            }
            px[c] = sq__clamp01(v);
        }
    }
}

/* The skin between the scales (Scales_GapColor, squama's): its colour over the finished
 * row where the height map is below the extent, at its alpha at height 0 and fading
 * linearly to none at the extent (the height map is within 0 to 1). Real scales part to
 * show it, darker or paler than the scales. */
static void gap_row(float *out, const float *height, int w, const float gap[4], float extent)
{
    for (int x = 0; x < w; x++) {
        const float e = 1.0f - height[x] / extent;
        if (e <= 0)
            continue;
        for (int c = 0; c < 3; c++)
            out[3 * x + c] += (gap[c] - out[3 * x + c]) * e * gap[3];
    }
}

/* The parameters of pattern layer k: p with the layer's pattern, no outline (the outline
 * belongs to the base pattern) and a seed of its own, from Seed and k. */
static void layer_params(const SqParams *p, int k, SqParams *q)
{
    *q = *p;
    q->pattern = p->Pattern_Layers.layer[k].spec;
    q->Has_Outline = 0;
    q->Seed = (int)(sq__hash((uint64_t)p->Seed, SQ_STREAM_LAYER, (uint64_t)k) & 0x7fffffff);
    q->Pattern_Layers.count = 0;
}

/* The colour map (§4.2, §4.1 step 3): the background with its noise, the base pattern over
 * it, then each pattern layer blended over what is below it, then the skin between the
 * scales. */
static SqStatus render_color(const SqParams *p, const float *height, float *col, int w, int h,
                             SqGenTimings *tm, SqError *err)
{
    double t0 = now_ms();
    PatternSource src[1 + SQ_MAX_PATTERN_LAYERS];
    int nsrc = 0;
    float *noise = NULL;
    memset(src, 0, sizeof src);
    SqStatus st = source_make(p, height, w, h, &src[nsrc++], err);
    for (int k = 0; st == SQ_OK && k < p->Pattern_Layers.count; k++) {
        const SqPatternLayer *l = &p->Pattern_Layers.layer[k];
        if (l->spec.Pattern_Type == SQ_PATTERN_NONE || l->Layer_Opacity <= 0)
            continue; /* changes nothing */
        SqParams q;
        layer_params(p, k, &q);
        PatternSource *s = &src[nsrc++];
        s->blend = l->Layer_Blend;
        s->opacity = (float)l->Layer_Opacity;
        st = source_make(&q, height, w, h, s, err);
        if (st == SQ_OK && s->pat.n == 0) /* a pattern with nothing drawn */
            source_free(&src[--nsrc]);
    }
    /* the colour noise is smooth (its finest octave has 32 cells): made at no more than
     * 256 pixels across and interpolated */
    const float ni = (float)p->Color_NoiseIntensity;
    const int nw = w < 256 ? w : 256, nh = h * nw / w > 0 ? h * nw / w : 1;
    SqLerp nx = {0}, ny = {0};
    if (st == SQ_OK && ni > 0) {
        if (!(noise = sq__falloc_raw((size_t)nw * nh)) ||
            sq__fbm(noise, nw, nh, (uint64_t)p->Seed, SQ_STREAM_COLOR_NOISE, COLOR_CELLS, COLOR_OCTAVES, 0.5) ||
            sq__lerp_init(&nx, w, nw) || sq__lerp_init(&ny, h, nh))
            st = sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the colour noise");
    }
    tm->pattern = now_ms() - t0;
    t0 = now_ms();
    if (st == SQ_OK) {
        const float bg[3] = {(float)p->Background_Color[0], (float)p->Background_Color[1],
                             (float)p->Background_Color[2]};
        const float gap[4] = {(float)p->Scales_GapColor[0], (float)p->Scales_GapColor[1],
                              (float)p->Scales_GapColor[2], (float)p->Scales_GapColor[3]};
        const float gap_extent = p->Scales_GapColor[3] > 0 ? (float)p->Scales_GapExtent : 0;
        int gw = 1;
        for (int i = 0; i < nsrc; i++)
            if (src[i].warp.dx && src[i].warp.gw > gw)
                gw = src[i].warp.gw;
        int failed = 0;
        /* Row by row, in simple passes over arrays: the displaced coordinates, the pattern,
         * the noise, then the composition; then each layer's row, blended over it. */
#pragma omp parallel
        {
            float *buf = malloc(sizeof(float) * ((size_t)7 * w + 2 * (size_t)gw + (size_t)nw));
            if (!buf) {
#pragma omp atomic write
                failed = 1;
            }
#pragma omp barrier
            if (!failed) {
                float *fxs = buf, *fys = fxs + w, *pr = fys + w, *pg = pr + w, *pb = pg + w,
                      *pa = pb + w, *nf = pa + w, *rowx = nf + w, *rowy = rowx + gw, *nrow = rowy + gw;
#pragma omp for schedule(static)
                for (int y = 0; y < h; y++) {
                    source_row(&src[0], y, w, h, fxs, fys, rowx, rowy, pr, pg, pb, pa);
                    if (noise) {
                        const float *n0 = noise + (size_t)ny.i0[y] * nw, *n1 = noise + (size_t)ny.i1[y] * nw;
                        const float ty = ny.t[y];
                        for (int g = 0; g < nw; g++)
                            nrow[g] = n0[g] + (n1[g] - n0[g]) * ty;
                        for (int x = 0; x < w; x++) {
                            const int a = nx.i0[x], c = nx.i1[x];
                            nf[x] = 1.0f + ni * (2.0f * (nrow[a] + (nrow[c] - nrow[a]) * nx.t[x]) - 1.0f);
                        }
                    } else {
                        for (int x = 0; x < w; x++)
                            nf[x] = 1.0f;
                    }
                    float *out = col + (size_t)y * w * 3;
                    for (int x = 0; x < w; x++) {
                        const float k = nf[x] * (1.0f - pa[x]);
                        out[3 * x] = sq__clamp01(bg[0] * k + pr[x]);
                        out[3 * x + 1] = sq__clamp01(bg[1] * k + pg[x]);
                        out[3 * x + 2] = sq__clamp01(bg[2] * k + pb[x]);
                    }
                    for (int i = 1; i < nsrc; i++) {
                        source_row(&src[i], y, w, h, fxs, fys, rowx, rowy, pr, pg, pb, pa);
                        blend_row(&src[i], out, w, pr, pg, pb, pa);
                    }
                    if (gap_extent > 0)
                        gap_row(out, height + (size_t)y * w, w, gap, gap_extent);
                }
            }
            free(buf);
        }
        if (failed)
            st = sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the colour map");
    }
    sq__lerp_free(&nx);
    sq__lerp_free(&ny);
    tm->color = now_ms() - t0;
    for (int i = 0; i < nsrc; i++)
        source_free(&src[i]);
    sq__ffree(noise);
    return st;
}

static SqStatus render(const SqParams *p, int w, int h, int directx, SqTextures *out,
                       SqGenTimings *tm, SqError *err)
{
    double t0 = now_ms();
    /* maps of the right size are reused (written in full: no zeroing) */
    if (out->basecolor.px == NULL || out->basecolor.width != w || out->basecolor.height != h ||
        !out->height.px || !out->roughness.px || !out->normal.px) {
        sq_gen_textures_free(out);
        if (sq__image_raw(&out->basecolor, w, h, 3, SQ_SPACE_SRGB) ||
            sq__image_raw(&out->height, w, h, 1, SQ_SPACE_DATA) ||
            sq__image_raw(&out->roughness, w, h, 1, SQ_SPACE_DATA) ||
            sq__image_raw(&out->normal, w, h, 3, SQ_SPACE_DATA))
            return sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for %dx%d maps", w, h);
    }
    tm->alloc = now_ms() - t0;
    t0 = now_ms();
    /* the roughness map is the scales' scratch until the fractal sum fills it */
    SqStatus st = sq__scales(p, out->height.px, out->roughness.px, w, h, err);
    if (st != SQ_OK)
        return st;
    tm->scales = now_ms() - t0;
    t0 = now_ms();

    /* micro detail and roughness from one fractal sum, interpolated from its finest level
     * in the same pass that writes both maps */
    float *rough = out->roughness.px, *height = out->height.px;
    int fw, fh;
    float *fbm = sq__fbm_coarse(w, h, (uint64_t)p->Seed, SQ_STREAM_DETAIL, DETAIL_CELLS,
                                DETAIL_OCTAVES, 0.5, &fw, &fh);
    SqLerp lx = {0}, ly = {0};
    if (!fbm || sq__lerp_init(&lx, w, fw) || sq__lerp_init(&ly, h, fh)) {
        sq__ffree(fbm);
        sq__lerp_free(&lx);
        return sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the detail noise");
    }
    const float detail = (float)p->Scales_DetailNormal;
    const float rmin = (float)p->Scales_RoughnessMin, rspan = (float)(p->Scales_RoughnessMax - p->Scales_RoughnessMin);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++) {
        const float *r0 = fbm + (size_t)ly.i0[y] * fw, *r1 = fbm + (size_t)ly.i1[y] * fw;
        const float ty = ly.t[y];
        float *hr = height + (size_t)y * w, *rr = rough + (size_t)y * w;
        for (int x = 0; x < w; x++) {
            const int a = lx.i0[x], b = lx.i1[x];
            const float e0 = r0[a] + (r0[b] - r0[a]) * lx.t[x], e1 = r1[a] + (r1[b] - r1[a]) * lx.t[x];
            const float f = e0 + (e1 - e0) * ty;
            hr[x] = sq__clamp01(hr[x] + detail * (2.0f * f - 1.0f));
            rr[x] = rmin + rspan * f;
        }
    }
    sq__ffree(fbm);
    sq__lerp_free(&lx);
    sq__lerp_free(&ly);
    tm->detail = now_ms() - t0;
    t0 = now_ms();
    sq__normals(height, w, h, p->Normal_Intensity, directx, out->normal.px);
    tm->normal = now_ms() - t0;
    return render_color(p, height, out->basecolor.px, w, h, tm, err);
}

SqStatus sq_gen_render_into(const SqParams *p, const SqGenOptions *opt, SqTextures *maps,
                            SqError *err)
{
    SqStatus st = sq_params_validate(p, err);
    if (st != SQ_OK)
        return st;
    SqGenOptions o = opt ? *opt : sq_gen_options_default(1024);
    if (o.width < 8 || o.height < 8 || o.width > SQ_GEN_MAX_SIZE || o.height > SQ_GEN_MAX_SIZE)
        return sq_error_set(err, SQ_ERR_INVALID, "size",
                            "texture size %dx%d is outside 8 to %d pixels per side", o.width,
                            o.height, SQ_GEN_MAX_SIZE);
#ifdef _OPENMP
    int saved = omp_get_max_threads();
    if (o.threads > 0)
        omp_set_num_threads(o.threads);
#endif
    SqGenTimings tm = {0};
    double t0 = now_ms();
    st = render(p, o.width, o.height, o.normal_directx, maps, &tm, err);
    tm.total = now_ms() - t0;
    if (o.timings)
        *o.timings = tm;
#ifdef _OPENMP
    omp_set_num_threads(saved);
#endif
    return st;
}

SqStatus sq_gen_render(const SqParams *p, const SqGenOptions *opt, SqTextures *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    SqStatus st = sq_gen_render_into(p, opt, out, err);
    if (st != SQ_OK)
        sq_gen_textures_free(out);
    return st;
}
