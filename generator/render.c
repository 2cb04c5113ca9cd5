/* The generator's driver (thesis §4.1): height (scales + micro detail), roughness and
 * normal maps; the colour map as background, pattern layers, post-process, outline and
 * warp. */
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "gen_internal.h"

/* The fractal sum shared by the height map's micro detail and the roughness (§4.4). */
enum { DETAIL_CELLS = 32, DETAIL_OCTAVES = 5, COLOR_CELLS = 4, COLOR_OCTAVES = 4 };

SqGenOptions sq_gen_options_default(int size)
{
    SqGenOptions o = {.width = size, .height = size, .normal_directx = 0, .threads = 0};
    return o;
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

/* The colour map (§4.2, §4.1 step 3): the background with its noise, the pattern over
 * it. The pattern is sampled through the warp's displacement; patterns made only of
 * stripe profiles are sampled from the profiles, with no pattern image at all. */
static SqStatus render_color(const SqParams *p, const float *height, float *col, int w, int h,
                             SqError *err)
{
    const size_t n = (size_t)w * h;
    SqPattern pat = {.w = w, .h = h};
    SqWarp warp = {0};
    float *rgba = NULL, *noise = NULL;
    SqStatus st = SQ_OK;
    if (p->Pattern_RotatePattern90Degrees) { /* generated on its side, rotated after */
        pat.w = h;
        pat.h = w;
    }
    switch (p->Pattern_Type) {
    case SQ_PATTERN_TRANSVERSAL: st = sq__pattern_transversal(p, &pat, err); break;
    case SQ_PATTERN_LONGITUDINAL: st = sq__pattern_longitudinal(p, &pat, err); break;
    case SQ_PATTERN_SPOTS: st = sq__pattern_spots(p, &pat, err); break;
    case SQ_PATTERN_OTHER_SIMPLE: st = sq__pattern_ca(p, &pat, err); break;
    default: break;
    }
    if (st == SQ_OK)
        st = sq__pattern_postprocess(p, &pat, err);
    const int sample_1d = pat.n > 0 && sq__pattern_is_1d(&pat) && !p->Has_Outline;
    if (st == SQ_OK && pat.n > 0 && !sample_1d) {
        if (!(rgba = sq__falloc_raw(n * 4)))
            st = sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the pattern");
        else
            sq__pattern_composite(&pat, rgba);
        if (st == SQ_OK && p->Has_Outline)
            st = sq__outline(p, rgba, height, w, h, err);
    }
    if (st == SQ_OK && pat.n > 0)
        st = sq__warp_field(p, w, h, &warp, err);
    const float ni = (float)p->Color_NoiseIntensity;
    if (st == SQ_OK && ni > 0) {
        if (!(noise = sq__falloc_raw(n)) ||
            sq__fbm(noise, w, h, (uint64_t)p->Seed, SQ_STREAM_COLOR_NOISE, COLOR_CELLS, COLOR_OCTAVES, 0.5))
            st = sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the colour noise");
    }
    SqLerp wx = {0}, wy = {0};
    if (st == SQ_OK && warp.dx && (sq__lerp_init(&wx, w, warp.gw) || sq__lerp_init(&wy, h, warp.gh)))
        st = sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the warp");
    if (st == SQ_OK) {
        const float bg[3] = {(float)p->Background_Color[0], (float)p->Background_Color[1],
                             (float)p->Background_Color[2]};
#pragma omp parallel for schedule(static)
        for (int y = 0; y < h; y++) {
            const float *dx0 = NULL, *dx1 = NULL, *dy0 = NULL, *dy1 = NULL;
            float ty = 0;
            if (warp.dx) {
                dx0 = warp.dx + (size_t)wy.i0[y] * warp.gw;
                dx1 = warp.dx + (size_t)wy.i1[y] * warp.gw;
                dy0 = warp.dy + (size_t)wy.i0[y] * warp.gw;
                dy1 = warp.dy + (size_t)wy.i1[y] * warp.gw;
                ty = wy.t[y];
            }
            for (int x = 0; x < w; x++) {
                const size_t i = (size_t)y * w + x;
                float pc[4] = {0, 0, 0, 0}, fx = (float)x, fy = (float)y;
                if (warp.dx) {
                    const int a = wx.i0[x], b = wx.i1[x];
                    const float tx = wx.t[x];
                    float t0 = dx0[a] + (dx0[b] - dx0[a]) * tx, t1 = dx1[a] + (dx1[b] - dx1[a]) * tx;
                    fx += t0 + (t1 - t0) * ty;
                    t0 = dy0[a] + (dy0[b] - dy0[a]) * tx;
                    t1 = dy1[a] + (dy1[b] - dy1[a]) * tx;
                    fy += t0 + (t1 - t0) * ty;
                }
                if (sample_1d) {
                    sq__pattern_sample_1d(&pat, fx, fy, pc);
                } else if (rgba && warp.dx) {
                    for (int c = 0; c < 4; c++)
                        pc[c] = sq__sample(rgba, w, h, 4, c, fx, fy);
                } else if (rgba) {
                    for (int c = 0; c < 4; c++)
                        pc[c] = rgba[4 * i + c];
                }
                const float f = noise ? 1.0f + ni * (2.0f * noise[i] - 1.0f) : 1.0f, k = 1.0f - pc[3];
                for (int c = 0; c < 3; c++)
                    col[3 * i + c] = sq__clamp01(bg[c] * f * k + pc[c]);
            }
        }
    }
    sq__lerp_free(&wx);
    sq__lerp_free(&wy);
    sq__pattern_free(&pat);
    sq__warp_free(&warp);
    sq__ffree(rgba);
    sq__ffree(noise);
    return st;
}

static SqStatus render(const SqParams *p, int w, int h, int directx, SqTextures *out, SqError *err)
{
    /* every map is written in full: no zeroing */
    if (sq__image_raw(&out->basecolor, w, h, 3, SQ_SPACE_SRGB) ||
        sq__image_raw(&out->height, w, h, 1, SQ_SPACE_DATA) ||
        sq__image_raw(&out->roughness, w, h, 1, SQ_SPACE_DATA) ||
        sq__image_raw(&out->normal, w, h, 3, SQ_SPACE_DATA))
        return sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for %dx%d maps", w, h);
    /* the roughness map is the scales' scratch until the fractal sum fills it */
    SqStatus st = sq__scales(p, out->height.px, out->roughness.px, w, h, err);
    if (st != SQ_OK)
        return st;

    /* micro detail and roughness from one fractal sum (kept in the roughness map) */
    float *rough = out->roughness.px, *height = out->height.px;
    if (sq__fbm(rough, w, h, (uint64_t)p->Seed, SQ_STREAM_DETAIL, DETAIL_CELLS, DETAIL_OCTAVES, 0.5))
        return sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the detail noise");
    const float detail = (float)p->Scales_DetailNormal;
    const float rmin = (float)p->Scales_RoughnessMin, rspan = (float)(p->Scales_RoughnessMax - p->Scales_RoughnessMin);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++)
        for (size_t i = (size_t)y * w; i < (size_t)(y + 1) * w; i++) {
            float f = rough[i];
            height[i] = sq__clamp01(height[i] + detail * (2.0f * f - 1.0f));
            rough[i] = rmin + rspan * f;
        }
    sq__normals(height, w, h, p->Normal_Intensity, directx, out->normal.px);
    return render_color(p, height, out->basecolor.px, w, h, err);
}

SqStatus sq_gen_render(const SqParams *p, const SqGenOptions *opt, SqTextures *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    SqStatus st = sq_params_validate(p, err);
    if (st != SQ_OK)
        return st;
    SqGenOptions o = opt ? *opt : sq_gen_options_default(1024);
    if (o.width < 8 || o.height < 8 || o.width > SQ_GEN_MAX_SIZE || o.height > SQ_GEN_MAX_SIZE)
        return sq_error_set(err, SQ_ERR_INVALID, "size",
                            "texture size %dx%d is outside 8 to %d pixels per side", o.width,
                            o.height, SQ_GEN_MAX_SIZE);
    if (p->Pattern_Type == SQ_PATTERN_COMPLEX)
        return sq_error_set(err, SQ_ERR_UNSUPPORTED, "Pattern_Type",
                            "the complex pattern type needs reaction-diffusion, which squama "
                            "does not have yet");
#ifdef _OPENMP
    int saved = omp_get_max_threads();
    if (o.threads > 0)
        omp_set_num_threads(o.threads);
#endif
    st = render(p, o.width, o.height, o.normal_directx, out, err);
#ifdef _OPENMP
    omp_set_num_threads(saved);
#endif
    if (st != SQ_OK)
        sq_gen_textures_free(out);
    return st;
}
