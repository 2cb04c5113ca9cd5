/* Do the objectives mean something? Synthetic photos of known presets (squama photo) are
 * prepared like any photo and scored against the right preset (re-seeded: another random
 * instance) and against wrong ones: every other category, the colours swapped, the
 * stripe count or ring spacing or spot density changed, the pattern rotated 90 degrees.
 * The right preset must never be dominated, must beat each wrong one on at least two
 * objectives, and by 10% or more on an objective that sees the change (the colour
 * objectives for swapped colours, the across layout for a stripe count, ...). The margins
 * are printed. */
#include <math.h>
#include <stdlib.h>

#include "sq_test.h"
#include "squama/fitness.h"
#include "squama/preset.h"

static void load(const char *name, SqParams *p)
{
    char rel[256], path[1024];
    SqError err;
    snprintf(rel, sizeof rel, "presets/thesis/%s.json", name);
    if (sq_preset_load(src_path(path, sizeof path, rel), p, NULL, &err) != SQ_OK)
        fail_msg("%s: %s", rel, err.what);
}

/* The pattern's main colour, for swapping with the background. */
static double *main_colour(SqParams *p)
{
    switch (p->Pattern_Type) {
    case SQ_PATTERN_TRANSVERSAL: return p->Transversal_Color[0];
    case SQ_PATTERN_LONGITUDINAL: return p->Longitudinal_StripesColor;
    case SQ_PATTERN_SPOTS: return p->Spots_Color;
    default: return p->CustomPattern_Color_Inside;
    }
}

enum { ALL = 0x1F, COLOUR = 1 << SQ_OBJ_PALETTE | 1 << SQ_OBJ_HISTOGRAM, SHAPE = 1 << SQ_OBJ_SHAPE,
       ALONG = 1 << SQ_OBJ_ALONG, ACROSS = 1 << SQ_OBJ_ACROSS };

typedef struct Case {
    const char *what;
    SqParams p;
    unsigned sees; /* the objectives that see this change */
} Case;

static int wins(const double *a, const double *b)
{
    int n = 0;
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        n += a[k] < b[k];
    return n;
}

static int dominated(const double *a, const double *b) /* a dominated by b */
{
    int better = 0;
    for (int k = 0; k < SQ_OBJ_COUNT; k++) {
        if (b[k] > a[k])
            return 0;
        better |= b[k] < a[k];
    }
    return better;
}

/* A synthetic photo of p (640 x 480, its maps at 256), prepared with its mask: the
 * preparation, the target it makes, and the truth (may be NULL). */
static void prepared_photo(const char *what, const SqParams *p, unsigned seed, double coil, double noise,
                           SqPrepared *prep, SqFeatures *target, SqPhotoTruth *truth)
{
    SqPhotoOptions po = sq_fit_photo_options_default();
    po.width = 640;
    po.height = 480;
    po.seed = seed;
    po.coil = coil;
    po.noise = noise;
    po.texture_size = 256;
    SqImage photo, mask;
    SqError err;
    assert_int_equal(sq_fit_synth_photo(p, &po, &photo, &mask, truth, &err), SQ_OK);
    if (sq_fit_prepare(&photo, &mask, NULL, prep, &err) != SQ_OK)
        fail_msg("%s: prepare: %s", what, err.what);
    assert_int_equal(sq_fit_photo_target(prep, target, &err), SQ_OK);
    sq_image_free(&photo);
    sq_image_free(&mask);
}

static void check_photo_of(const char *name, unsigned seed)
{
    SqParams p;
    load(name, &p);
    SqPhotoTruth truth;
    SqPrepared prep;
    SqFeatures target;
    SqError err;
    prepared_photo(name, &p, seed, 0.3, 0.01, &prep, &target, &truth);
    double width_err = fabs(prep.body_width - 2 * truth.body_radius) / (2 * truth.body_radius);
    if (width_err > 0.1)
        fail_msg("%s: body width %.1f, truth %.1f", name, prep.body_width, 2 * truth.body_radius);

    /* the cases */
    Case cases[12];
    int n = 0;
    cases[n] = (Case){"the preset, re-seeded", p, 0};
    cases[n++].p.Seed = p.Seed + 100;
    static const char *const others[] = {"table_4_2_micrurus_altirostris", "table_4_3_longitudinal",
                                         "table_4_4_spots", "figure_4_9_other_simple"};
    for (size_t k = 0; k < sizeof others / sizeof others[0]; k++) {
        SqParams q;
        load(others[k], &q);
        if (q.Pattern_Type == p.Pattern_Type)
            continue;
        cases[n].what = others[k];
        cases[n].sees = ALL;
        cases[n++].p = q;
    }
    if (p.Pattern_Type != SQ_PATTERN_NONE) {
        SqParams q = p;
        cases[n].what = "plain (no pattern)";
        cases[n].sees = ALL;
        q.Pattern_Type = SQ_PATTERN_NONE;
        cases[n++].p = q;
        q = p;
        double tmp[4];
        memcpy(tmp, q.Background_Color, sizeof tmp);
        memcpy(q.Background_Color, main_colour(&q), sizeof tmp);
        memcpy(main_colour(&q), tmp, sizeof tmp);
        cases[n].what = "colours swapped";
        cases[n].sees = COLOUR | ACROSS;
        cases[n++].p = q;
        /* rotation changes what only an oriented pattern shows: stripes, rings, ellipses */
        int oriented = p.Pattern_Type == SQ_PATTERN_LONGITUDINAL || p.Pattern_Type == SQ_PATTERN_TRANSVERSAL ||
                       (p.Pattern_Type == SQ_PATTERN_SPOTS && p.Spots_Interstice[0] != p.Spots_Interstice[1]);
        if (oriented) {
            q = p;
            q.Pattern_RotatePattern90Degrees = !q.Pattern_RotatePattern90Degrees;
            cases[n].what = "rotated 90 degrees";
            cases[n].sees = SHAPE | ALONG | ACROSS;
            cases[n++].p = q;
        }
        q = p;
        if (p.Pattern_Type == SQ_PATTERN_LONGITUDINAL) {
            q.Longitudinal_NumberOfStripes += q.Longitudinal_NumberOfStripes > 2 ? -2 : 2;
            cases[n].what = "stripe count changed";
            cases[n].sees = ACROSS;
        } else if (p.Pattern_Type == SQ_PATTERN_TRANSVERSAL) {
            for (int i = 0; i < 4; i++) /* the rings repeat twice per tile: twice as close */
                for (int j = 0; j < 2; j++)
                    q.Transversal_BeginEnd[i][j] *= 0.5;
            cases[n].what = "ring spacing halved";
            cases[n].sees = ALONG;
        } else if (p.Pattern_Type == SQ_PATTERN_SPOTS) {
            q.Spots_Tiling *= 2;
            cases[n].what = "spot density doubled";
            cases[n].sees = SHAPE | ALONG | ACROSS;
        } else {
            q.CA_Descriptor.rules[0].bits ^= 0x6;
            cases[n].what = "another automaton rule";
            cases[n].sees = ALL & ~(1u << SQ_OBJ_PALETTE);
        }
        cases[n++].p = q;
    }
    double obj[12][SQ_OBJ_COUNT], scale[12];
    SqTextures maps = {0};
    for (int i = 0; i < n; i++)
        if (sq_fit_score(&target, &cases[i].p, 256, 0.5, 0, &maps, obj[i], &scale[i], NULL, &err) != SQ_OK)
            fail_msg("%s: score %s: %s", name, cases[i].what, err.what);
    sq_gen_textures_free(&maps);

    print_message("photo of %s (seed %u, view scale %.2f, fitted %.2f): body width %.1f px (truth %.1f)\n",
                  name, seed, truth.view_scale, scale[0], prep.body_width, 2 * truth.body_radius);
    print_message("  %-24s %9s %9s %9s %9s %9s\n", "", "palette", "histogram", "shape", "along", "across");
    for (int i = 0; i < n; i++) {
        print_message("  %-24s", cases[i].what);
        for (int k = 0; k < SQ_OBJ_COUNT; k++)
            print_message(" %9.4f", obj[i][k]);
        if (i > 0)
            print_message("   right wins %d/5", wins(obj[0], obj[i]));
        print_message("\n");
    }
    for (int i = 1; i < n; i++) {
        if (dominated(obj[0], obj[i]))
            fail_msg("%s: the right preset is dominated by '%s'", name, cases[i].what);
        if (wins(obj[0], obj[i]) < 2)
            fail_msg("%s: the right preset beats '%s' on only %d of 5 objectives", name, cases[i].what,
                     wins(obj[0], obj[i]));
        int seen = 0;
        for (int k = 0; k < SQ_OBJ_COUNT; k++)
            seen |= (cases[i].sees >> k & 1) && obj[0][k] * 1.10 < obj[i][k];
        if (!seen)
            fail_msg("%s: no objective that should see '%s' tells it from the right preset", name,
                     cases[i].what);
    }
    sq_fit_prepared_free(&prep);
    sq_fit_truth_free(&truth);
}

static void transversal(void **state)
{
    (void)state;
    check_photo_of("table_4_2_micrurus_altirostris", 21);
    check_photo_of("table_4_1_transversal", 5);
}

static void longitudinal(void **state)
{
    (void)state;
    check_photo_of("table_4_3_longitudinal", 21);
    check_photo_of("d11_five_lined_skink", 8);
}

static void spots(void **state)
{
    (void)state;
    check_photo_of("table_4_4_spots", 21);
    check_photo_of("table_4_5_spots_interleaved", 3);
}

static void other_simple(void **state)
{
    (void)state;
    check_photo_of("figure_4_9_other_simple", 21);
}

/* A candidate lit the way the photo is lit (the light turning with the body) looks more
 * like the photo of itself than one under the fixed key light: the truth's shape and
 * layout objectives fall, summed over plain, striped, banded and spotted photos of a
 * winding body, five of each: by over a fifth since the smooth body's shading no longer
 * turns with the candidate's light (12.5 key, 9.1 lit; 11.0 lit before). Photo by photo it
 * varies: spots gain least, about even. */
static void lit_like_the_photo(void **state)
{
    (void)state;
    static const char *const names[] = {"table_4_3_longitudinal", "table_4_4_spots", "table_4_1_transversal"};
    double key = 0, lit = 0;
    for (unsigned seed = 1; seed <= 5; seed++)
        for (int i = 0; i < 4; i++) {
            SqParams p;
            load(names[i % 3], &p);
            if (i == 3)
                p.Pattern_Type = SQ_PATTERN_NONE;
            SqPhotoTruth truth;
            SqPrepared prep;
            SqFeatures target;
            SqError err;
            prepared_photo(names[i % 3], &p, seed, 0.7, 0, &prep, &target, &truth);
            assert_true(target.light.rows > 0);
            double o[2][SQ_OBJ_COUNT], k, sum[2] = {0};
            assert_int_equal(sq_fit_score(&target, &p, 256, 0.5, truth.view_scale, NULL, o[1], &k, NULL, &err), SQ_OK);
            target.light.rows = 0;
            assert_int_equal(sq_fit_score(&target, &p, 256, 0.5, truth.view_scale, NULL, o[0], &k, NULL, &err), SQ_OK);
            for (int j = SQ_OBJ_SHAPE; j <= SQ_OBJ_ACROSS; j++) {
                sum[0] += o[0][j];
                sum[1] += o[1][j];
            }
            print_message("  seed %u %-24s shape + along + across: key light %.3f, the photo's %.3f\n", seed,
                          i == 3 ? "plain" : names[i], sum[0], sum[1]);
            key += sum[0];
            lit += sum[1];
            sq_fit_prepared_free(&prep);
            sq_fit_truth_free(&truth);
        }
    print_message("  summed: key light %.3f, the photo's %.3f\n", key, lit);
    assert_true(lit < 0.8 * key);
}

/* The same preset re-seeded scores alike: a fit can compare candidates by one instance. */
static void stable_across_reseeding(void **state)
{
    (void)state;
    SqParams p;
    load("table_4_4_spots", &p);
    SqPrepared prep;
    SqFeatures target;
    SqError err;
    prepared_photo("table_4_4_spots", &p, 4, sq_fit_photo_options_default().coil, 0, &prep, &target, NULL);
    double lo[SQ_OBJ_COUNT], hi[SQ_OBJ_COUNT];
    for (int s = 0; s < 5; s++) {
        double o[SQ_OBJ_COUNT], k;
        p.Seed = 1000 + s;
        assert_int_equal(sq_fit_score(&target, &p, 256, 0.5, 0, NULL, o, &k, NULL, &err), SQ_OK);
        for (int j = 0; j < SQ_OBJ_COUNT; j++) {
            lo[j] = s ? fmin(lo[j], o[j]) : o[j];
            hi[j] = s ? fmax(hi[j], o[j]) : o[j];
        }
    }
    print_message("spots photo scored by its preset under 5 seeds: objective ranges\n");
    for (int j = 0; j < SQ_OBJ_COUNT; j++)
        print_message("  %-10s %.4f .. %.4f\n", sq_fit_objective_name(j), lo[j], hi[j]);
    /* a re-seeding moves an objective by less than the gap to a wrong preset */
    SqParams q;
    load("table_4_2_micrurus_altirostris", &q);
    double w[SQ_OBJ_COUNT], k;
    assert_int_equal(sq_fit_score(&target, &q, 256, 0.5, 0, NULL, w, &k, NULL, &err), SQ_OK);
    for (int j = 0; j < SQ_OBJ_COUNT; j++)
        if (!(hi[j] < w[j]))
            fail_msg("%s: re-seeded up to %.4f, a coral preset %.4f", sq_fit_objective_name(j), hi[j], w[j]);
    sq_fit_prepared_free(&prep);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(transversal),
        cmocka_unit_test(longitudinal),
        cmocka_unit_test(spots),
        cmocka_unit_test(other_simple),
        cmocka_unit_test(stable_across_reseeding),
        cmocka_unit_test(lit_like_the_photo),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
