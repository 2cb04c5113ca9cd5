/* Pattern layers: whole patterns blended over the colour map. What must hold: a preset
 * without layers (or with layers that do nothing) renders as before; a layer paints where
 * its pattern covers; the blend modes darken and lighten as they say; same pixels on any
 * thread count. */
#include <math.h>
#include <stdlib.h>

#include "sq_test.h"
#include "squama/generator.h"
#include "squama/preset.h"

static void render_t(const SqParams *p, int size, int threads, SqTextures *t)
{
    SqGenOptions o = sq_gen_options_default(size);
    o.threads = threads;
    SqError err;
    if (sq_gen_render(p, &o, t, &err) != SQ_OK)
        fail_msg("render: %s (%s)", err.what, err.where);
}

static void render(const SqParams *p, int size, SqTextures *t)
{
    render_t(p, size, 0, t);
}

static size_t npx(const SqImage *m)
{
    return (size_t)m->width * m->height * m->channels;
}

static int same_image(const SqImage *a, const SqImage *b)
{
    return a->width == b->width && a->height == b->height && a->channels == b->channels &&
           memcmp(a->px, b->px, sizeof(float) * npx(a)) == 0;
}

static void assert_same_maps(const SqTextures *a, const SqTextures *b, const char *what)
{
    if (!same_image(&a->basecolor, &b->basecolor))
        fail_msg("%s: basecolor differs", what);
    if (!same_image(&a->height, &b->height) || !same_image(&a->roughness, &b->roughness) ||
        !same_image(&a->normal, &b->normal))
        fail_msg("%s: a surface map differs", what);
}

/* Mean luminance (Rec. 709 weights on the gamma-space values: only compared). */
static double mean_luma(const SqImage *m)
{
    double s = 0;
    size_t n = (size_t)m->width * m->height;
    for (size_t i = 0; i < n; i++)
        s += 0.2126 * m->px[3 * i] + 0.7152 * m->px[3 * i + 1] + 0.0722 * m->px[3 * i + 2];
    return s / (double)n;
}

static void set_rgb(double *c, double r, double g, double b)
{
    c[0] = r;
    c[1] = g;
    c[2] = b;
    c[3] = 1;
}

/* A spotted preset with some of everything that could leak into the layers' path. */
static SqParams spotted(void)
{
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_SPOTS;
    p.Spots_PositionRandom[0] = p.Spots_PositionRandom[1] = 0.3;
    p.Spots_ScaleVariation = 0.4;
    p.Pattern_Warp_Large = 2;
    p.Color_NoiseIntensity = 0.2;
    p.Seed = 7;
    return p;
}

static void no_layers_or_idle_layers_change_nothing(void **state)
{
    (void)state;
    SqParams p = spotted();
    SqTextures ref, t;
    render(&p, 96, &ref);

    SqParams q = p; /* one layer of type none */
    q.Pattern_Layers.count = 1;
    q.Pattern_Layers.layer[0].spec.Pattern_Type = SQ_PATTERN_NONE;
    q.Pattern_Layers.layer[0].Layer_Blend = SQ_BLEND_MULTIPLY;
    render(&q, 96, &t);
    assert_same_maps(&ref, &t, "a layer of type none");
    sq_gen_textures_free(&t);

    q = p; /* layers at opacity 0, of every blend */
    q.Pattern_Layers.count = 3;
    for (int k = 0; k < 3; k++) {
        q.Pattern_Layers.layer[k].spec.Pattern_Type = k == 0 ? SQ_PATTERN_LONGITUDINAL
                                                             : SQ_PATTERN_SPOTS;
        q.Pattern_Layers.layer[k].Layer_Blend = k + 1;
        q.Pattern_Layers.layer[k].Layer_Opacity = 0;
    }
    render(&q, 96, &t);
    assert_same_maps(&ref, &t, "layers at opacity 0");
    sq_gen_textures_free(&t);

    q = p; /* unused layers hold anything */
    q.Pattern_Layers.layer[0].spec.Pattern_Type = SQ_PATTERN_TRANSVERSAL;
    render(&q, 96, &t);
    assert_same_maps(&ref, &t, "an unused layer");
    sq_gen_textures_free(&t);

    /* and through a preset: no key, an empty list, a layer of type none */
    static const char *const texts[] = {
        "{\"format\": \"squama-preset/1\", \"Pattern_Type\": \"spots\", \"Seed\": 7}",
        "{\"format\": \"squama-preset/1\", \"Pattern_Type\": \"spots\", \"Seed\": 7, "
        "\"Pattern_Layers\": []}",
        "{\"format\": \"squama-preset/1\", \"Pattern_Type\": \"spots\", \"Seed\": 7, "
        "\"Pattern_Layers\": [{\"Pattern_Type\": \"none\", \"Layer_Blend\": \"screen\"}]}",
    };
    SqTextures first;
    for (int i = 0; i < 3; i++) {
        SqError err;
        if (sq_preset_parse(texts[i], strlen(texts[i]), "p.json", &q, NULL, &err) != SQ_OK)
            fail_msg("%s (%s)", err.what, err.where);
        render(&q, 64, i == 0 ? &first : &t);
        if (i > 0) {
            assert_same_maps(&first, &t, texts[i]);
            sq_gen_textures_free(&t);
        }
    }
    sq_gen_textures_free(&first);
    sq_gen_textures_free(&ref);
}

/* Rings on whole pixel rows (64 px: bands at multiples of 1/64): a layer repeating the
 * base pattern with its colours changes nothing; in another colour it changes exactly
 * the pixels the base pattern covers. */
static void a_layer_covers_where_its_pattern_does(void **state)
{
    (void)state;
    SqParams none;
    sq_params_default(&none);
    set_rgb(none.Background_Color, 0.5, 0.45, 0.3);
    SqParams p = none;
    p.Pattern_Type = SQ_PATTERN_TRANSVERSAL;
    set_rgb(p.Transversal_Color[0], 0.9, 0.1, 0.1);
    p.Transversal_BeginEnd[0][0] = 0.25;
    p.Transversal_BeginEnd[0][1] = 0.5;
    set_rgb(p.Transversal_Color[1], 0.1, 0.1, 0.1);
    p.Transversal_BeginEnd[1][0] = 0.75;
    p.Transversal_BeginEnd[1][1] = 0.875;

    SqParams q = p;
    q.Pattern_Layers.count = 1;
    q.Pattern_Layers.layer[0].spec = p.pattern;
    SqTextures t0, tb, tl;
    render(&none, 64, &t0);
    render(&p, 64, &tb);
    render(&q, 64, &tl);
    assert_same_maps(&tb, &tl, "the base pattern again, normal, opacity 1");
    sq_gen_textures_free(&tl);

    set_rgb(q.Pattern_Layers.layer[0].spec.Transversal_Color[0], 0.1, 0.2, 0.9);
    set_rgb(q.Pattern_Layers.layer[0].spec.Transversal_Color[1], 0.95, 0.95, 0.9);
    render(&q, 64, &tl);
    size_t n = (size_t)64 * 64, covered = 0;
    for (size_t i = 0; i < n; i++) {
        int base_covers = memcmp(&t0.basecolor.px[3 * i], &tb.basecolor.px[3 * i], 12) != 0;
        int layer_paints = memcmp(&tb.basecolor.px[3 * i], &tl.basecolor.px[3 * i], 12) != 0;
        if (base_covers != layer_paints)
            fail_msg("pixel %zu: base covers %d, layer paints %d", i, base_covers, layer_paints);
        covered += base_covers;
        if (layer_paints) /* opaque: the layer's colour exactly (both have blue 0.9) */
            assert_true(tl.basecolor.px[3 * i + 2] == 0.9f);
    }
    assert_int_equal(covered, (size_t)(16 + 8) * 64);
    sq_gen_textures_free(&tl);

    /* spots: soft edges, so the same test by sets: a differently coloured layer repeating
     * the base spots changes exactly the pixels the base spots cover */
    SqParams s = none;
    s.Pattern_Type = SQ_PATTERN_SPOTS;
    s.Spots_Tiling = 0.4;
    set_rgb(s.Spots_Color, 0.1, 0.05, 0.0);
    SqParams sl = s;
    sl.Pattern_Layers.count = 1;
    sl.Pattern_Layers.layer[0].spec = s.pattern;
    set_rgb(sl.Pattern_Layers.layer[0].spec.Spots_Color, 0.9, 0.8, 0.2);
    SqTextures ts, tsl;
    render(&s, 64, &ts);
    render(&sl, 64, &tsl);
    covered = 0;
    for (size_t i = 0; i < n; i++) {
        int base_covers = memcmp(&t0.basecolor.px[3 * i], &ts.basecolor.px[3 * i], 12) != 0;
        int layer_paints = memcmp(&ts.basecolor.px[3 * i], &tsl.basecolor.px[3 * i], 12) != 0;
        if (base_covers != layer_paints)
            fail_msg("spots, pixel %zu: base covers %d, layer paints %d", i, base_covers,
                     layer_paints);
        covered += base_covers;
    }
    assert_true(covered > n / 10 && covered < n * 9 / 10);
    sq_gen_textures_free(&ts);
    sq_gen_textures_free(&tsl);
    sq_gen_textures_free(&t0);
    sq_gen_textures_free(&tb);
}

/* Multiply darkens, screen lightens, overlay keeps mid-grey as it is; opacity scales the
 * change. */
static void blend_modes_darken_and_lighten(void **state)
{
    (void)state;
    SqParams p = spotted();
    set_rgb(p.Background_Color, 0.6, 0.5, 0.3);
    p.Pattern_Layers.count = 1;
    SqPatternLayer *l = &p.Pattern_Layers.layer[0];
    l->spec.Pattern_Type = SQ_PATTERN_LONGITUDINAL;
    l->spec.Longitudinal_NumberOfStripes = 3;
    l->spec.Longitudinal_StripesWidth = 0.5;
    set_rgb(l->spec.Longitudinal_StripesColor, 0.5, 0.5, 0.5);

    SqParams base = p;
    base.Pattern_Layers.count = 0;
    SqTextures tb, t;
    render(&base, 64, &tb);
    const double lb = mean_luma(&tb.basecolor);
    double luma[SQ_BLEND_COUNT];
    for (int mode = 0; mode < SQ_BLEND_COUNT; mode++) {
        l->Layer_Blend = mode;
        render(&p, 64, &t);
        luma[mode] = mean_luma(&t.basecolor);
        size_t n = (size_t)64 * 64;
        for (size_t i = 0; i < 3 * n; i++) { /* pixel by pixel, never the other way */
            const float b = tb.basecolor.px[i], v = t.basecolor.px[i];
            if ((mode == SQ_BLEND_MULTIPLY && v > b + 1e-6f) ||
                (mode == SQ_BLEND_SCREEN && v < b - 1e-6f))
                fail_msg("mode %d, value %zu: %g from %g", mode, i, v, b);
        }
        sq_gen_textures_free(&t);
    }
    assert_true(luma[SQ_BLEND_MULTIPLY] < lb - 0.05);
    assert_true(luma[SQ_BLEND_SCREEN] > lb + 0.05);
    assert_true(luma[SQ_BLEND_MULTIPLY] < luma[SQ_BLEND_OVERLAY] &&
                luma[SQ_BLEND_OVERLAY] < luma[SQ_BLEND_SCREEN]);

    /* overlay with mid-grey leaves dark colours as they are (2 x 0.5 x cb) */
    l->Layer_Blend = SQ_BLEND_OVERLAY;
    set_rgb(base.Background_Color, 0.2, 0.3, 0.4);
    set_rgb(p.Background_Color, 0.2, 0.3, 0.4);
    base.Color_NoiseIntensity = p.Color_NoiseIntensity = 0;
    base.Pattern_Type = p.Pattern_Type = SQ_PATTERN_NONE;
    sq_gen_textures_free(&tb);
    render(&base, 64, &tb);
    render(&p, 64, &t);
    for (size_t i = 0; i < npx(&t.basecolor); i++)
        assert_true(fabsf(t.basecolor.px[i] - tb.basecolor.px[i]) < 1e-6f);
    sq_gen_textures_free(&t);

    /* opacity: half the multiply's darkening, near enough */
    const SqPatternLayer stripes = *l; /* l points into p */
    p = spotted();
    set_rgb(p.Background_Color, 0.6, 0.5, 0.3);
    p.Pattern_Layers.count = 1;
    p.Pattern_Layers.layer[0] = stripes;
    p.Pattern_Layers.layer[0].Layer_Blend = SQ_BLEND_MULTIPLY;
    p.Pattern_Layers.layer[0].Layer_Opacity = 0.5;
    render(&p, 64, &t);
    double half = mean_luma(&t.basecolor);
    assert_true(fabs((lb - half) - 0.5 * (lb - luma[SQ_BLEND_MULTIPLY])) < 0.01);
    sq_gen_textures_free(&t);
    sq_gen_textures_free(&tb);
}

/* Each layer draws its own random instance (its seed from Seed and its index), and a
 * layer's randomness follows the preset's Seed. */
static void layers_have_their_own_randomness(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Spots_PositionRandom[0] = p.Spots_PositionRandom[1] = 0.5;
    p.Spots_ScaleVariation = 0.5;
    SqParams as_base = p, as_layer = p;
    as_base.Pattern_Type = SQ_PATTERN_SPOTS;
    as_layer.Pattern_Layers.count = 1;
    as_layer.Pattern_Layers.layer[0].spec = as_base.pattern;
    SqTextures a, b, c;
    render(&as_base, 64, &a);
    render(&as_layer, 64, &b);
    assert_false(same_image(&a.basecolor, &b.basecolor));
    as_layer.Seed = 2;
    render(&as_layer, 64, &c);
    assert_false(same_image(&b.basecolor, &c.basecolor));
    sq_gen_textures_free(&a);
    sq_gen_textures_free(&b);
    sq_gen_textures_free(&c);
}

/* A layered preset with every kind of layer source (profiles, a warped 2-D pattern, an
 * automaton with blur, reaction-diffusion): the same pixels on 1, 2 and 3 threads. */
static void same_pixels_on_any_thread_count(void **state)
{
    (void)state;
    SqParams p = spotted();
    p.Has_Outline = 1;
    p.Pattern_Layers.count = 3;
    SqPatternLayer *l = p.Pattern_Layers.layer;
    l[0].spec.Pattern_Type = SQ_PATTERN_LONGITUDINAL;
    l[0].spec.Pattern_Warp_Small = 0.5;
    l[0].Layer_Blend = SQ_BLEND_OVERLAY;
    l[1].spec.Pattern_Type = SQ_PATTERN_OTHER_SIMPLE;
    l[1].spec.Pattern_BlurAmount = 2;
    l[1].spec.Pattern_RotatePattern90Degrees = 1;
    l[1].Layer_Opacity = 0.6;
    l[2].spec.Pattern_Type = SQ_PATTERN_COMPLEX;
    l[2].spec.RD_Cells = 32;
    l[2].spec.Pattern_Warp_Large = 3;
    l[2].Layer_Blend = SQ_BLEND_MULTIPLY;
    SqTextures a, b;
    render_t(&p, 80, 1, &a);
    for (int threads = 2; threads <= 3; threads++) {
        render_t(&p, 80, threads, &b);
        assert_same_maps(&a, &b, "threads");
        sq_gen_textures_free(&b);
    }
    SqParams none = p;
    none.Pattern_Layers.count = 0;
    render_t(&none, 80, 2, &b);
    assert_false(same_image(&a.basecolor, &b.basecolor));
    sq_gen_textures_free(&b);
    sq_gen_textures_free(&a);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(no_layers_or_idle_layers_change_nothing),
        cmocka_unit_test(a_layer_covers_where_its_pattern_does),
        cmocka_unit_test(blend_modes_darken_and_lighten),
        cmocka_unit_test(layers_have_their_own_randomness),
        cmocka_unit_test(same_pixels_on_any_thread_count),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
