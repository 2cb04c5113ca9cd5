/* Colour science, features and objectives: reference values, and each objective
 * reacting to the change it is meant to see. */
#include <math.h>
#include <stdlib.h>

#include "fitness_internal.h"
#include "sq_test.h"
#include "squama/fitness.h"
#include "squama/generator.h"

/* Sharma, Wu & Dalal (2005), Table 1: all 34 pairs. */
static const double sharma[34][7] = {
    {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
    {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
    {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
    {50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
    {50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461},
    {50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065},
    {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
    {50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977},
    {50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030},
    {50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000},
    {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
    {63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630},
    {61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731},
    {35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645},
    {22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373},
    {36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146},
    {90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441},
    {90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381},
    {6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377},
    {2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082},
};

static void ciede2000_sharma_pairs(void **state)
{
    (void)state;
    for (int i = 0; i < 34; i++) {
        double d1 = sq_fit_ciede2000(&sharma[i][0], &sharma[i][3]);
        double d2 = sq_fit_ciede2000(&sharma[i][3], &sharma[i][0]);
        if (fabs(d1 - sharma[i][6]) > 1e-4 || fabs(d2 - sharma[i][6]) > 1e-4)
            fail_msg("pair %d: %.4f / %.4f, want %.4f", i + 1, d1, d2, sharma[i][6]);
    }
}

static void srgb_to_lab_reference(void **state)
{
    (void)state;
    static const struct { float rgb[3]; float lab[3]; } ref[] = {
        {{1, 0, 0}, {53.24f, 80.09f, 67.20f}}, {{0, 1, 0}, {87.73f, -86.18f, 83.18f}},
        {{0, 0, 1}, {32.30f, 79.19f, -107.86f}}, {{1, 1, 1}, {100, 0, 0}},
        {{0, 0, 0}, {0, 0, 0}}, {{0.5f, 0.5f, 0.5f}, {53.39f, 0, 0}},
    };
    for (size_t i = 0; i < sizeof ref / sizeof ref[0]; i++) {
        float lab[3];
        sq_fit_srgb_to_lab(ref[i].rgb, lab);
        for (int c = 0; c < 3; c++)
            if (fabsf(lab[c] - ref[i].lab[c]) > 0.1f)
                fail_msg("colour %zu channel %d: %.3f, want %.3f", i, c, lab[c], ref[i].lab[c]);
    }
}

/* Lab -> sRGB inverts sRGB -> Lab inside the gamut: the colour comes back within a
 * fraction of a just-noticeable difference (the forward conversion uses tables). */
static void lab_to_srgb_round_trip(void **state)
{
    (void)state;
    for (int i = 0; i < 1000; i++) {
        float rgb[3] = {(i % 10) / 9.0f, (i / 10 % 10) / 9.0f, (i / 100) / 9.0f}, lab[3], back[3], lab2[3];
        sq_fit_srgb_to_lab(rgb, lab);
        sq_fit_lab_to_srgb(lab, back);
        sq_fit_srgb_to_lab(back, lab2);
        double a[3] = {lab[0], lab[1], lab[2]}, b[3] = {lab2[0], lab2[1], lab2[2]};
        assert_true(sq_fit_ciede2000(a, b) < 1.0); /* 0.6 at worst, near black */
        for (int k = 0; k < 3; k++)
            assert_float_equal(back[k], rgb[k], 5e-3);
    }
    float far[3] = {50, 200, -200}, out[3]; /* out of gamut: clipped */
    sq_fit_lab_to_srgb(far, out);
    for (int k = 0; k < 3; k++)
        assert_true(out[k] >= 0 && out[k] <= 1);
}

static void features_of(const SqParams *p, double view_scale, SqFeatures *f)
{
    SqGenOptions o = sq_gen_options_default(256);
    SqTextures t;
    SqError err;
    if (sq_gen_render(p, &o, &t, &err) != SQ_OK)
        fail_msg("render: %s", err.what);
    SqImage strip;
    assert_int_equal(sq_fit_candidate_strip(&t.basecolor, NULL, NULL, NULL, view_scale, 0.5, 256, &strip, &err), SQ_OK);
    if (sq_fit_features(&strip, NULL, f, &err) != SQ_OK)
        fail_msg("features: %s", err.what);
    sq_image_free(&strip);
    sq_gen_textures_free(&t);
}

static void objectives(const SqFeatures *a, const SqFeatures *b, double *o)
{
    sq_fit_objectives(a, b, o);
    for (int i = 0; i < SQ_OBJ_COUNT; i++)
        assert_true(isfinite(o[i]) && o[i] >= 0);
}

static SqParams stripes(int n)
{
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_LONGITUDINAL;
    p.Longitudinal_NumberOfStripes = n;
    p.Longitudinal_StripesWidth = 0.5;
    p.Longitudinal_Pinch = 2.5; /* all stripes inside the dorsal band */
    p.Pattern_Warp_Small = 0.2;
    return p;
}

static void identical_features_score_zero(void **state)
{
    (void)state;
    SqParams p = stripes(3);
    SqFeatures a, b;
    features_of(&p, 1.0, &a);
    features_of(&p, 1.0, &b);
    double o[SQ_OBJ_COUNT];
    sq_fit_objectives(&a, &b, o);
    for (int i = 0; i < SQ_OBJ_COUNT; i++)
        assert_true(o[i] < 1e-9);
}

/* The palette's matching: it moves each side's weights whole (as far as the other side
 * holds them), costs what the palette objective says, and pairs a colour with its own
 * where it can. */
static void palette_flow_moves_the_weights(void **state)
{
    (void)state;
    SqParams p = stripes(3), q = stripes(3);
    q.Background_Color[0] = 0.9; /* a redder ground */
    SqFeatures a, b;
    features_of(&p, 1.0, &a);
    features_of(&q, 1.0, &b);
    double flow[SQ_FIT_PALETTE][SQ_FIT_PALETTE], o[SQ_OBJ_COUNT];
    const double d = sq_fit_palette_flow(&a, &b, flow);
    objectives(&a, &b, o);
    assert_true(fabs(d - o[SQ_OBJ_PALETTE]) < 1e-12 && d > 1);
    double total = 0;
    for (int i = 0; i < SQ_FIT_PALETTE; i++) {
        double row = 0, col = 0;
        for (int j = 0; j < SQ_FIT_PALETTE; j++) {
            assert_true(flow[i][j] >= 0);
            row += flow[i][j];
            col += flow[j][i];
        }
        assert_true(row <= a.palette_w[i] + 1e-6 && col <= b.palette_w[i] + 1e-6);
        total += row;
    }
    assert_true(fabs(total - 1) < 1e-4);
    /* the same features: every colour onto itself, at no cost */
    assert_true(sq_fit_palette_flow(&a, &a, flow) < 1e-9);
    for (int i = 0; i < SQ_FIT_PALETTE; i++)
        assert_true(fabs(flow[i][i] - a.palette_w[i]) < 1e-6);
}

/* Each objective sees its change more than a re-seeding of the same preset. */
static void objectives_see_their_changes(void **state)
{
    (void)state;
    double same[SQ_OBJ_COUNT], other[SQ_OBJ_COUNT];
    SqFeatures ref, reseeded, changed;

    /* stripe count: across */
    SqParams p = stripes(3), q;
    features_of(&p, 1.0, &ref);
    q = p;
    q.Seed = 99;
    features_of(&q, 1.0, &reseeded);
    objectives(&ref, &reseeded, same);
    q = stripes(5);
    features_of(&q, 1.0, &changed);
    objectives(&ref, &changed, other);
    if (!(other[SQ_OBJ_ACROSS] > 3 * same[SQ_OBJ_ACROSS] + 0.05))
        fail_msg("stripe count: across %.4f vs reseeded %.4f", other[SQ_OBJ_ACROSS], same[SQ_OBJ_ACROSS]);

    /* colours swapped: palette and histogram (when the colours' areas differ), and the
     * across profile (which colour lies where) */
    p.Longitudinal_StripesWidth = 0.25;
    features_of(&p, 1.0, &ref);
    q = p;
    q.Seed = 99;
    features_of(&q, 1.0, &reseeded);
    objectives(&ref, &reseeded, same);
    q = p;
    memcpy(q.Background_Color, p.Longitudinal_StripesColor, sizeof q.Background_Color);
    memcpy(q.Longitudinal_StripesColor, p.Background_Color, sizeof q.Background_Color);
    features_of(&q, 1.0, &changed);
    objectives(&ref, &changed, other);
    if (!(other[SQ_OBJ_HISTOGRAM] > 3 * same[SQ_OBJ_HISTOGRAM] + 0.05))
        fail_msg("colour swap: histogram %.4f vs %.4f", other[SQ_OBJ_HISTOGRAM], same[SQ_OBJ_HISTOGRAM]);
    if (!(other[SQ_OBJ_PALETTE] > 3 * same[SQ_OBJ_PALETTE] + 2))
        fail_msg("colour swap: palette %.4f vs %.4f", other[SQ_OBJ_PALETTE], same[SQ_OBJ_PALETTE]);
    if (!(other[SQ_OBJ_ACROSS] > 3 * same[SQ_OBJ_ACROSS] + 0.05))
        fail_msg("colour swap: across %.4f vs %.4f", other[SQ_OBJ_ACROSS], same[SQ_OBJ_ACROSS]);

    /* rotated 90 degrees: stripes become rings: shape and both layouts */
    q = p;
    q.Pattern_RotatePattern90Degrees = 1;
    features_of(&q, 1.0, &changed);
    objectives(&ref, &changed, other);
    if (!(other[SQ_OBJ_SHAPE] > 3 * same[SQ_OBJ_SHAPE] + 0.1))
        fail_msg("rotation: shape %.4f vs %.4f", other[SQ_OBJ_SHAPE], same[SQ_OBJ_SHAPE]);
    if (!(other[SQ_OBJ_ALONG] > 3 * same[SQ_OBJ_ALONG] + 0.1))
        fail_msg("rotation: along %.4f vs %.4f", other[SQ_OBJ_ALONG], same[SQ_OBJ_ALONG]);

    /* ring spacing: along */
    SqParams r;
    sq_params_default(&r);
    r.Pattern_Type = SQ_PATTERN_TRANSVERSAL;
    r.Transversal_BeginEnd[0][0] = 0.0;
    r.Transversal_BeginEnd[0][1] = 0.1;
    r.Transversal_BeginEnd[1][0] = 0.5;
    r.Transversal_BeginEnd[1][1] = 0.6;
    r.Transversal_Color[1][0] = r.Transversal_Color[1][1] = r.Transversal_Color[1][2] = 0.05;
    features_of(&r, 0.5, &ref);
    q = r;
    q.Seed = 7;
    q.Pattern_Warp_Small = 0.05;
    features_of(&q, 0.5, &reseeded);
    objectives(&ref, &reseeded, same);
    features_of(&r, 1.0, &changed); /* the same rings, twice as far apart in the photo */
    objectives(&ref, &changed, other);
    if (!(other[SQ_OBJ_ALONG] > 3 * same[SQ_OBJ_ALONG] + 0.05))
        fail_msg("ring spacing: along %.4f vs %.4f", other[SQ_OBJ_ALONG], same[SQ_OBJ_ALONG]);
}

/* How much pattern there is counts, each direction on its own; at a plain skin's noise
 * level (variances of a few 1e-4) the direction of the noise is chance and costs little,
 * a pattern's worth of variance costs much. */
static void spectra_weigh_amounts(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_NONE;
    SqFeatures t, c, patterned;
    features_of(&p, 1.0, &t);
    c = patterned = t;
    t.along_power = 4e-4, t.across_power = 2e-4;   /* noise, a little more of it along */
    c.along_power = 2e-4, c.across_power = 4e-4;   /* and across */
    patterned.along_power = 2e-2, patterned.across_power = 2e-4; /* rings */
    double noise[SQ_OBJ_COUNT], rings[SQ_OBJ_COUNT];
    objectives(&t, &c, noise);
    objectives(&t, &patterned, rings);
    printf("  noise: along %.3f across %.3f; rings: along %.3f\n", noise[SQ_OBJ_ALONG], noise[SQ_OBJ_ACROSS],
           rings[SQ_OBJ_ALONG]);
    assert_true(noise[SQ_OBJ_ALONG] < 0.1 && noise[SQ_OBJ_ACROSS] < 0.1); /* as a power share: 0.25 each */
    assert_true(rings[SQ_OBJ_ALONG] > 10 * noise[SQ_OBJ_ALONG]);
    assert_true(rings[SQ_OBJ_ACROSS] < 1e-9); /* nothing changed across */
}

static void lit_features(const SqParams *p, int size, double grain, SqFeatures *f)
{
    SqGenOptions o = sq_gen_options_default(size);
    SqTextures t;
    SqError err;
    if (sq_gen_render(p, &o, &t, &err) != SQ_OK)
        fail_msg("render: %s", err.what);
    SqImage strip;
    assert_int_equal(sq_fit_candidate_strip(&t.basecolor, &t.normal, &t.roughness, NULL, 1.0, 0.5, 256, &strip, &err), SQ_OK);
    uint64_t x = 88172645463325252ull; /* xorshift: a camera's grain */
    for (size_t i = 0; grain > 0 && i < (size_t)strip.width * strip.height * 3; i++) {
        double g = 0;
        for (int k = 0; k < 4; k++) { /* about normal, variance 1 */
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            g += (double)(x >> 11) / 9007199254740992.0 - 0.5;
        }
        strip.px[i] = (float)fmin(1, fmax(0, strip.px[i] + grain * g * sqrt(3.0)));
    }
    if (sq_fit_features(&strip, NULL, f, &err) != SQ_OK)
        fail_msg("features: %s", err.what);
    sq_image_free(&strip);
    sq_gen_textures_free(&t);
}

/* A strip pixel is the mean of the skin it covers: a 1024 texture's strip is about its 512
 * one's, not an aliased sampling of its scales; and a camera's grain on a plain skin does
 * not reshape its wavelet energies. */
static void strips_are_stable(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_NONE;
    SqFeatures a, b, noisy;
    double o[SQ_OBJ_COUNT];
    lit_features(&p, 512, 0, &a);
    lit_features(&p, 1024, 0, &b);
    objectives(&a, &b, o);
    printf("  512 vs 1024: palette %.3f shape %.3f along %.3f across %.3f\n", o[SQ_OBJ_PALETTE], o[SQ_OBJ_SHAPE],
           o[SQ_OBJ_ALONG], o[SQ_OBJ_ACROSS]);
    assert_true(o[SQ_OBJ_PALETTE] < 0.5 && o[SQ_OBJ_SHAPE] < 0.08); /* point-sampled: 0.66, 0.10 */
    lit_features(&p, 512, 0.015, &noisy);
    objectives(&a, &noisy, o);
    printf("  grain 0.015: palette %.3f shape %.3f\n", o[SQ_OBJ_PALETTE], o[SQ_OBJ_SHAPE]);
    assert_true(o[SQ_OBJ_SHAPE] < 0.05);
}

/* The maps of the default preset without a pattern, at 256². */
static void plain_maps(SqTextures *t)
{
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_NONE;
    SqGenOptions o = sq_gen_options_default(256);
    SqError err;
    assert_int_equal(sq_gen_render(&p, &o, t, &err), SQ_OK);
}

/* A light path of one row is that light all along: the key light's direction given that
 * way gives the key light's strip (but for its highlights: the key's half vector is made
 * from its 1.001-long self, as it always was, a path's from its unit light); a light from
 * the other side gives another strip. */
static void strips_take_the_light(void **state)
{
    (void)state;
    SqTextures t;
    SqError err;
    plain_maps(&t);
    SqLight light = {.rows = 1, .dir = {{-0.35f, 0.55f, 0.76f}}};
    SqImage a, b, c;
    assert_int_equal(sq_fit_candidate_strip(&t.basecolor, &t.normal, &t.roughness, NULL, 1.0, 0.5, 128, &a, &err), SQ_OK);
    assert_int_equal(sq_fit_candidate_strip(&t.basecolor, &t.normal, &t.roughness, &light, 1.0, 0.5, 128, &b, &err), SQ_OK);
    light.dir[0][0] = 0.35f; /* from the right */
    light.dir[0][1] = -0.55f;
    assert_int_equal(sq_fit_candidate_strip(&t.basecolor, &t.normal, &t.roughness, &light, 1.0, 0.5, 128, &c, &err), SQ_OK);
    double same = 0, other = 0;
    const size_t n = (size_t)a.width * a.height * 3;
    for (size_t i = 0; i < n; i++) {
        same = fmax(same, fabs(a.px[i] - b.px[i]));
        other += fabs(a.px[i] - c.px[i]) / n;
    }
    printf("  the key light given as a path: largest difference %.2g; lit from the right: mean %.4f\n", same, other);
    assert_true(same < 2e-3);
    assert_true(other > 0.005);
    sq_image_free(&a);
    sq_image_free(&b);
    sq_image_free(&c);
    sq_gen_textures_free(&t);
}

/* The tilt of a strip's rows (mean log lightness of the left half less the right half's),
 * smoothed over 8 rows: the largest minus the smallest. */
static double tilt_swing(const SqImage *s)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int y = 0; y + 8 <= s->height; y += 8) {
        double t = 0;
        for (int r = y; r < y + 8; r++)
            for (int x = 0; x < s->width; x++) {
                const float *q = sq_image_at(s, x, r);
                const double l = log(0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2] + 1e-3);
                t += (x < s->width / 2 ? l : -l) / (8.0 * s->width / 2);
            }
        lo = fmin(lo, t);
        hi = fmax(hi, t);
    }
    return hi - lo;
}

/* A photo's light turns where the pieces of it join (over 24 rows), faster than the strip's
 * light normalisation follows; the smooth body's shading must not turn with it (it left
 * dark and bright blocks in every lit candidate, which no photo's strip has). A plain skin
 * under a light swinging from the left to the right tilts a little more than under one
 * light (its relief and highlights turn with the light), not as much as its whole body
 * would (0.65 before). */
static void a_turning_light_leaves_no_blocks(void **state)
{
    (void)state;
    SqTextures t;
    SqError err;
    plain_maps(&t);
    SqLight one = {.rows = 1, .dir = {{-0.6f, 0.2f, 0.77f}}}, turning = {.rows = SQ_FIT_LIGHT_ROWS};
    for (int i = 0; i < SQ_FIT_LIGHT_ROWS; i++) { /* from the left, then over 6 light rows from the right */
        const double a = fmin(fmax((i - 29) / 6.0, 0), 1) * acos(-1.0);
        turning.dir[i][0] = (float)(-0.6 * cos(a));
        turning.dir[i][1] = (float)(0.2 - 0.4 * sin(a));
        turning.dir[i][2] = 0.77f;
    }
    SqImage a, b;
    assert_int_equal(sq_fit_candidate_strip(&t.basecolor, &t.normal, &t.roughness, &one, 1.0, 0.5, 256, &a, &err), SQ_OK);
    assert_int_equal(sq_fit_candidate_strip(&t.basecolor, &t.normal, &t.roughness, &turning, 1.0, 0.5, 256, &b, &err),
                     SQ_OK);
    const double steady = tilt_swing(&a), swung = tilt_swing(&b);
    printf("  the rows' tilt varies by %.3f under one light, %.3f under the turning one\n", steady, swung);
    assert_true(swung < steady + 0.15);
    sq_image_free(&a);
    sq_image_free(&b);
    sq_gen_textures_free(&t);
}

/* A candidate seen through a photo's blur: no blur is sq_fit_features itself; more blur
 * takes the fine detail (rings a few strip pixels apart) out of the spectrum along the
 * body, and brings its features nearer those of the blurred photo of it. */
static void blur_takes_fine_detail(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_TRANSVERSAL;
    SqGenOptions o = sq_gen_options_default(256);
    SqTextures t;
    SqError err;
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_OK);
    SqImage strip;
    assert_int_equal(sq_fit_candidate_strip(&t.basecolor, NULL, NULL, NULL, 0.5, 0.5, 256, &strip, &err), SQ_OK);
    SqFeatures plain, zero, some, more;
    assert_int_equal(sq_fit_features(&strip, NULL, &plain, &err), SQ_OK);
    assert_int_equal(sq_fit_features_blurred(&strip, NULL, 0, &zero, &err), SQ_OK);
    assert_int_equal(sq_fit_features_blurred(&strip, NULL, 1, &some, &err), SQ_OK);
    assert_int_equal(sq_fit_features_blurred(&strip, NULL, 3, &more, &err), SQ_OK);
    assert_memory_equal(&plain, &zero, sizeof plain);
    print_message("along power: blur 0 %.3g, 1 %.3g, 3 %.3g\n", plain.along_power, some.along_power, more.along_power);
    assert_true(some.along_power < plain.along_power && more.along_power < some.along_power);
    double a[SQ_OBJ_COUNT], b[SQ_OBJ_COUNT];
    objectives(&more, &plain, a); /* a blurred strip against the sharp and the blurred candidate */
    objectives(&more, &more, b);
    assert_true(a[SQ_OBJ_ALONG] > b[SQ_OBJ_ALONG] + 0.05);
    assert_int_equal(sq_fit_features_blurred(&strip, NULL, -1, &some, &err), SQ_ERR_INVALID);
    assert_int_equal(sq_fit_features_blurred(&strip, NULL, SQ_FIT_BLUR_MAX + 1, &some, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "blur");
    sq_image_free(&strip);
    sq_gen_textures_free(&t);
}

static void refusals(void **state)
{
    (void)state;
    SqImage strip, valid;
    SqFeatures f;
    SqError err;
    sq_image_alloc(&strip, 32, 100, 3, SQ_SPACE_SRGB);
    assert_int_equal(sq_fit_features(&strip, NULL, &f, &err), SQ_ERR_INVALID);
    sq_image_free(&strip);
    sq_image_alloc(&strip, SQ_FIT_STRIP_W, 100, 3, SQ_SPACE_SRGB);
    sq_image_alloc(&valid, SQ_FIT_STRIP_W, 100, 1, SQ_SPACE_DATA); /* nothing valid */
    assert_int_equal(sq_fit_features(&strip, &valid, &f, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "too little of the body");
    sq_image_free(&valid);
    sq_image_alloc(&valid, SQ_FIT_STRIP_W, 90, 1, SQ_SPACE_DATA);
    assert_int_equal(sq_fit_features(&strip, &valid, &f, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "another size");
    sq_image_free(&valid);
    SqImage none = {0};
    assert_int_equal(sq_fit_candidate_strip(&none, NULL, NULL, NULL, 1, 0.5, 64, &valid, &err), SQ_ERR_INVALID);
    assert_int_equal(sq_fit_candidate_strip(&strip, NULL, NULL, NULL, 0, 0.5, 64, &valid, &err), SQ_ERR_INVALID);
    sq_image_free(&strip);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ciede2000_sharma_pairs),
        cmocka_unit_test(srgb_to_lab_reference),
        cmocka_unit_test(lab_to_srgb_round_trip),
        cmocka_unit_test(identical_features_score_zero),
        cmocka_unit_test(palette_flow_moves_the_weights),
        cmocka_unit_test(objectives_see_their_changes),
        cmocka_unit_test(spectra_weigh_amounts),
        cmocka_unit_test(strips_are_stable),
        cmocka_unit_test(strips_take_the_light),
        cmocka_unit_test(a_turning_light_leaves_no_blocks),
        cmocka_unit_test(blur_takes_fine_detail),
        cmocka_unit_test(refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
