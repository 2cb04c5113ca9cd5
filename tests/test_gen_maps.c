/* The four maps together: seams, thread-count invariance, determinism, the normal map's
 * convention, the ventral stretch, resolution independence, golden images of the
 * thesis presets, and refusals. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <unistd.h>

#include "gen_internal.h"
#include "sq_test.h"
#include "squama/generator.h"
#include "squama/io.h"
#include "squama/preset.h"

static void render(const SqParams *p, int size, int threads, SqTextures *t)
{
    SqGenOptions o = sq_gen_options_default(size);
    o.threads = threads;
    SqError err;
    if (sq_gen_render(p, &o, t, &err) != SQ_OK)
        fail_msg("render: %s (%s)", err.what, err.where);
}

static void load(const char *rel, SqParams *p)
{
    char path[1024];
    SqError err;
    if (sq_preset_load(src_path(path, sizeof path, rel), p, NULL, &err) != SQ_OK)
        fail_msg("%s: %s (%s)", rel, err.what, err.where);
}

/* Every stage at once, with randomness everywhere. */
static void stress_params(SqParams *p)
{
    sq_params_default(p);
    p->Pattern_Type = SQ_PATTERN_SPOTS;
    p->Spots_Tiling = 0.8;
    p->Spots_Scale = 0.9;
    p->Spots_ScaleVariation = 0.4;
    p->Spots_PositionRandom[0] = p->Spots_PositionRandom[1] = 0.3;
    p->Spots_RotationRandom = 30;
    p->Spots_Interstice[1] = 0.4;
    p->Pattern_BlurAmount = 2;
    p->Pattern_Contrast = 0.5;
    p->Pattern_Warp_Large = 3;
    p->Pattern_Warp_Small = 0.4;
    p->Has_Outline = 1;
    p->Outline_Distortion_Intensity = 3;
    p->Color_NoiseIntensity = 0.2;
    p->ScaleShape_IsKeeled = 1;
    p->ScaleShape_Ridge = 0.3;
    p->Scales_SizeRandom = 0.2;
    p->Scales_PositionRandom[0] = p->Scales_PositionRandom[1] = 0.1;
    p->Scales_RotationRandom = 10;
    p->Scales_BellyWarpIntensity = 5;
    p->Scales_GapExtent = 0.3;
    p->Seed = 12345;
}

/* Mean absolute difference between column a and column b (or rows) over channel c. */
static double col_diff(const SqImage *m, int a, int b, int c)
{
    double s = 0;
    for (int y = 0; y < m->height; y++)
        s += fabs(sq_image_at(m, a, y)[c] - sq_image_at(m, b, y)[c]);
    return s / m->height;
}

static double row_diff(const SqImage *m, int a, int b, int c)
{
    double s = 0;
    for (int x = 0; x < m->width; x++)
        s += fabs(sq_image_at(m, x, a)[c] - sq_image_at(m, x, b)[c]);
    return s / m->width;
}

/* The step across an edge of the tile is no larger than the steps beside it. */
static void assert_seamless(const SqImage *m, const char *what, int check_u)
{
    const int w = m->width, h = m->height;
    for (int c = 0; c < m->channels; c++) {
        float lo = 1e9f, hi = -1e9f;
        for (size_t i = 0; i < (size_t)w * h; i++) {
            lo = fminf(lo, m->px[i * m->channels + c]);
            hi = fmaxf(hi, m->px[i * m->channels + c]);
        }
        const double eps = 0.002 * (hi - lo) + 1e-6;
        if (check_u) {
            double seam = col_diff(m, w - 1, 0, c);
            double next = fmax(col_diff(m, 0, 1, c), col_diff(m, w - 2, w - 1, c));
            if (seam > 2 * next + eps)
                fail_msg("%s channel %d: u seam step %.4f, beside it %.4f", what, c, seam, next);
        }
        double seam = row_diff(m, h - 1, 0, c);
        double next = fmax(row_diff(m, 0, 1, c), row_diff(m, h - 2, h - 1, c));
        if (seam > 2 * next + eps)
            fail_msg("%s channel %d: v seam step %.4f, beside it %.4f", what, c, seam, next);
    }
}

static void maps_tile_seamlessly(void **state)
{
    (void)state;
    static const char *const presets[] = {
        "presets/thesis/d11_five_lined_skink.json", "presets/thesis/table_4_2_micrurus_altirostris.json",
        "presets/thesis/table_4_4_spots.json", "presets/thesis/table_4_5_spots_interleaved.json",
        "presets/thesis/figure_4_9_other_simple.json"};
    for (size_t i = 0; i <= sizeof presets / sizeof presets[0]; i++) {
        SqParams p;
        if (i < sizeof presets / sizeof presets[0])
            load(presets[i], &p);
        else
            stress_params(&p);
        SqTextures t;
        render(&p, 192, 0, &t);
        assert_seamless(&t.basecolor, "basecolor", 1);
        assert_seamless(&t.roughness, "roughness", 1);
        /* the ventral stretch breaks the u seam on purpose when scales move randomly */
        int exact_scales = p.Scales_PositionRandom[0] == 0 && p.Scales_SizeRandom == 0 &&
                           p.Scales_RotationRandom == 0 && p.Scales_BellyWarpIntensity == 0;
        assert_seamless(&t.height, "height", exact_scales);
        assert_seamless(&t.normal, "normal", exact_scales);
        sq_gen_textures_free(&t);
    }
}

static void same_pixels_on_any_thread_count(void **state)
{
    (void)state;
    SqParams p;
    stress_params(&p);
    SqTextures a, b;
    render(&p, 160, 1, &a);
    for (int threads = 2; threads <= 3; threads++) {
        render(&p, 160, threads, &b);
        assert_memory_equal(a.basecolor.px, b.basecolor.px, sizeof(float) * 160 * 160 * 3);
        assert_memory_equal(a.height.px, b.height.px, sizeof(float) * 160 * 160);
        assert_memory_equal(a.roughness.px, b.roughness.px, sizeof(float) * 160 * 160);
        assert_memory_equal(a.normal.px, b.normal.px, sizeof(float) * 160 * 160 * 3);
        sq_gen_textures_free(&b);
    }
    /* a CA pattern with rotation, too */
    load("presets/thesis/figure_4_9_other_simple.json", &p);
    p.Pattern_RotatePattern90Degrees = 1;
    p.Has_Outline = 1;
    SqTextures c, d;
    render(&p, 96, 1, &c);
    render(&p, 96, 2, &d);
    assert_memory_equal(c.basecolor.px, d.basecolor.px, sizeof(float) * 96 * 96 * 3);
    sq_gen_textures_free(&a);
    sq_gen_textures_free(&c);
    sq_gen_textures_free(&d);
}

static void seed_decides_the_instance(void **state)
{
    (void)state;
    SqParams p;
    stress_params(&p);
    SqTextures a, b;
    render(&p, 96, 0, &a);
    render(&p, 96, 0, &b);
    assert_memory_equal(a.basecolor.px, b.basecolor.px, sizeof(float) * 96 * 96 * 3);
    sq_gen_textures_free(&b);
    p.Seed = 777;
    render(&p, 96, 0, &b);
    double diff = 0;
    for (int i = 0; i < 96 * 96 * 3; i++)
        diff += fabs(a.basecolor.px[i] - b.basecolor.px[i]);
    assert_true(diff / (96 * 96 * 3) > 0.01);
    sq_gen_textures_free(&a);
    sq_gen_textures_free(&b);
}

/* OpenGL: green grows where the height rises towards the bottom of the image (the
 * surface faces up the texture); DirectX flips green. Red falls where height rises to
 * the right. */
static void normal_map_convention(void **state)
{
    (void)state;
    const int w = 32, h = 32;
    float height[32 * 32], n[32 * 32 * 3];
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            height[y * w + x] = 0.01f * (float)y + 0.02f * (float)x;
    sq__normals(height, w, h, 2.0, 0, n);
    const float *c = n + 3 * (16 * w + 16);
    assert_true(c[0] < 0.5f);
    assert_true(c[1] > 0.5f);
    assert_true(c[2] > 0.5f);
    double len = sqrt(pow(2 * c[0] - 1, 2) + pow(2 * c[1] - 1, 2) + pow(2 * c[2] - 1, 2));
    assert_true(fabs(len - 1) < 1e-5);
    sq__normals(height, w, h, 2.0, 1, n);
    assert_true(n[3 * (16 * w + 16) + 1] < 0.5f);
    /* flat height: (0.5, 0.5, 1) */
    for (int i = 0; i < w * h; i++)
        height[i] = 0.3f;
    sq__normals(height, w, h, 5.0, 0, n);
    assert_true(fabsf(n[0] - 0.5f) < 1e-6f && fabsf(n[1] - 0.5f) < 1e-6f && fabsf(n[2] - 1.0f) < 1e-6f);
}

/* Across the belly every row is one stretched ventral scale: constant along u. */
static void ventral_scales_are_stretched(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Scales_BellyScalesPct = 0.2;
    p.Scales_DetailNormal = 0;
    SqTextures t;
    render(&p, 256, 0, &t);
    int flat_rows = 0, lateral_varies = 0;
    for (int y = 0; y < 256; y++) {
        float a = sq_image_at(&t.height, 2, y)[0];
        int flat = 1;
        for (int x = 3; x < 20; x++) /* well inside the belly (u < 0.08) */
            flat &= fabsf(sq_image_at(&t.height, x, y)[0] - a) < 1e-6f;
        flat_rows += flat;
        float b = sq_image_at(&t.height, 128, y)[0];
        for (int x = 110; x < 150; x++)
            lateral_varies |= fabsf(sq_image_at(&t.height, x, y)[0] - b) > 0.05f;
    }
    assert_int_equal(flat_rows, 256);
    assert_true(lateral_varies);
    sq_gen_textures_free(&t);
}

static void roughness_between_its_levels(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Scales_RoughnessMin = 0.6;
    p.Scales_RoughnessMax = 0.9;
    SqTextures t;
    render(&p, 128, 0, &t);
    float lo = 1, hi = 0;
    for (int i = 0; i < 128 * 128; i++) {
        lo = fminf(lo, t.roughness.px[i]);
        hi = fmaxf(hi, t.roughness.px[i]);
    }
    assert_true(lo >= 0.6f - 1e-6f && hi <= 0.9f + 1e-6f);
    assert_true(hi - lo > 0.25f); /* the noise spans the range */
    sq_gen_textures_free(&t);
}

/* The skin between the scales: the gap colour at its alpha where the height map is 0,
 * fading linearly to nothing at Scales_GapExtent, over the finished colour (pattern,
 * layers, outline, noise); the other maps untouched; alpha 0 changes nothing. */
static void gap_colour_where_the_scales_are_low(void **state)
{
    (void)state;
    SqParams p;
    stress_params(&p);
    p.Pattern_Layers.count = 1;
    p.Pattern_Layers.layer[0].spec = p.pattern;
    p.Pattern_Layers.layer[0].spec.Pattern_Type = SQ_PATTERN_LONGITUDINAL;
    p.Pattern_Layers.layer[0].Layer_Opacity = 0.7;
    p.Scales_GapExtent = 0;
    SqTextures a, b;
    render(&p, 128, 0, &a);
    const double extent = 0.45, gap[4] = {0.1, 0.9, 0.3, 0.8};
    p.Scales_GapExtent = extent;
    for (int c = 0; c < 4; c++)
        p.Scales_GapColor[c] = gap[c];
    render(&p, 128, 0, &b);
    const int n = 128 * 128;
    int full = 0, none = 0;
    for (int i = 0; i < n; i++) {
        const float h = a.height.px[i];
        assert_float_equal(b.height.px[i], h, 0);
        assert_float_equal(b.roughness.px[i], a.roughness.px[i], 0);
        for (int c = 0; c < 3; c++)
            assert_float_equal(b.normal.px[3 * i + c], a.normal.px[3 * i + c], 0);
        double e = 1 - h / extent;
        e = e < 0 ? 0 : e > 1 ? 1 : e;
        full += e > 0.5;
        none += e == 0;
        for (int c = 0; c < 3; c++) {
            const double want = a.basecolor.px[3 * i + c] + (gap[c] - a.basecolor.px[3 * i + c]) * e * gap[3];
            if (fabs(b.basecolor.px[3 * i + c] - want) > 1e-5)
                fail_msg("texel %d channel %d at height %.3f: %.5f, want %.5f", i, c, h, b.basecolor.px[3 * i + c], want);
        }
    }
    if (full < n / 50 || none < n / 5)
        fail_msg("the test sees too little of either side: %d texels over half gap, %d none", full, none);
    p.Scales_GapColor[3] = 0;
    sq_gen_textures_free(&b);
    render(&p, 128, 0, &b);
    assert_memory_equal(b.basecolor.px, a.basecolor.px, sizeof(float) * 3 * (size_t)n);
    sq_gen_textures_free(&a);
    sq_gen_textures_free(&b);
}

/* A preset looks the same at every resolution: 256 box-filtered to 128 matches 128. */
static void resolution_independent(void **state)
{
    (void)state;
    SqParams p;
    load("presets/thesis/table_4_5_spots_interleaved.json", &p);
    p.Pattern_BlurAmount = 2;
    SqTextures a, b;
    render(&p, 128, 0, &a);
    render(&p, 256, 0, &b);
    double diff = 0;
    for (int y = 0; y < 128; y++)
        for (int x = 0; x < 128; x++)
            for (int c = 0; c < 3; c++) {
                double m = (sq_image_at(&b.basecolor, 2 * x, 2 * y)[c] + sq_image_at(&b.basecolor, 2 * x + 1, 2 * y)[c] +
                            sq_image_at(&b.basecolor, 2 * x, 2 * y + 1)[c] +
                            sq_image_at(&b.basecolor, 2 * x + 1, 2 * y + 1)[c]) / 4;
                diff += fabs(m - sq_image_at(&a.basecolor, x, y)[c]);
            }
    diff /= 128 * 128 * 3;
    if (diff > 0.02)
        fail_msg("256 and 128 differ by %.4f on average", diff);
    sq_gen_textures_free(&a);
    sq_gen_textures_free(&b);
}

static void refusals(void **state)
{
    (void)state;
    SqParams p;
    SqTextures t;
    SqError err;
    sq_params_default(&p);
    SqGenOptions o = sq_gen_options_default(4);
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "outside 8 to 16384");
    assert_null(t.basecolor.px);
    o = sq_gen_options_default(64);
    p.Pattern_Type = SQ_PATTERN_COMPLEX; /* reaction-diffusion: rendered, no longer refused */
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_OK);
    sq_gen_textures_free(&t);
    p.RD_Cells = 8;
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "RD_Cells");
    assert_null(t.basecolor.px);
    sq_params_default(&p);
    p.Spots_Tiling = -1;
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "Spots_Tiling");
}

/* Golden images (OpenImageIO's testsuite rule): fail when more than 1% of pixels differ
 * by over 0.02 or any by over 0.25. SQ_UPDATE_GOLDEN=1 rewrites them (scripts/update-golden). */
static void compare_golden(const SqImage *img, const char *name)
{
    char path[1024], rel[256];
    SqError err;
    snprintf(rel, sizeof rel, "tests/golden/%s.png", name);
    src_path(path, sizeof path, rel);
    SqWriteOptions o = {.format = SQ_FORMAT_PNG, .bits = 8}; /* 1/255 steps, well inside the tolerance */
    if (getenv("SQ_UPDATE_GOLDEN")) {
        if (sq_io_write_image(path, img, &o, &err) != SQ_OK)
            fail_msg("%s: %s", path, err.what);
        return;
    }
    SqImage g;
    if (sq_io_read_image(path, NULL, &g, NULL, &err) != SQ_OK)
        fail_msg("golden image missing (%s): run scripts/update-golden on purpose", err.where);
    assert_int_equal(g.width, img->width);
    assert_int_equal(g.height, img->height);
    int over = 0;
    float worst = 0;
    SqImage diff;
    sq_image_alloc(&diff, img->width, img->height, 1, SQ_SPACE_DATA);
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            float d = 0;
            for (int c = 0; c < img->channels; c++)
                d = fmaxf(d, fabsf(sq_image_at(img, x, y)[c] - sq_image_at(&g, x, y)[c]));
            *sq_image_at(&diff, x, y) = d;
            over += d > 0.02f;
            worst = fmaxf(worst, d);
        }
    if (over > img->width * img->height / 100 || worst > 0.25f) {
        char out[1024];
        snprintf(rel, sizeof rel, "%s_actual.png", name);
        sq_io_write_image(tmp_path(out, sizeof out, rel), img, &o, &err);
        snprintf(rel, sizeof rel, "%s_diff.png", name);
        sq_io_write_image(tmp_path(out, sizeof out, rel), &diff, &o, &err);
        fail_msg("%s: %d pixels differ by over 0.02, worst %.3f (actual and diff in %s)", name, over,
                 worst, SQUAMA_TEST_TMP);
    }
    sq_image_free(&g);
    sq_image_free(&diff);
}

static void golden_thesis_presets(void **state)
{
    (void)state;
    static const char *const names[] = {
        "d11_five_lined_skink", "figure_4_9_other_simple", "table_4_1_transversal",
        "table_4_2_micrurus_altirostris", "table_4_3_longitudinal", "table_4_4_spots",
        "table_4_5_spots_interleaved"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char rel[256], name[256];
        SqParams p;
        snprintf(rel, sizeof rel, "presets/thesis/%s.json", names[i]);
        load(rel, &p);
        SqTextures t;
        render(&p, 128, 0, &t);
        snprintf(name, sizeof name, "%s_basecolor", names[i]);
        compare_golden(&t.basecolor, name);
        snprintf(name, sizeof name, "%s_height", names[i]);
        compare_golden(&t.height, name);
        snprintf(name, sizeof name, "%s_normal", names[i]);
        compare_golden(&t.normal, name);
        sq_gen_textures_free(&t);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(maps_tile_seamlessly),
        cmocka_unit_test(same_pixels_on_any_thread_count),
        cmocka_unit_test(seed_decides_the_instance),
        cmocka_unit_test(normal_map_convention),
        cmocka_unit_test(ventral_scales_are_stretched),
        cmocka_unit_test(roughness_between_its_levels),
        cmocka_unit_test(gap_colour_where_the_scales_are_low),
        cmocka_unit_test(resolution_independent),
        cmocka_unit_test(refusals),
        cmocka_unit_test(golden_thesis_presets),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
