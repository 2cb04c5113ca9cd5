/* Seeding artists: n presets of the category, valid and plausible, the same for a seed on 1
 * or 2 threads, more diverse than random picks from the same pool; variations that keep
 * their origin's category and structure and move further as the step grows; a fit's front
 * as seeds; bad options refused. Small renders (64 pixels) keep it quick. */
#include <math.h>

#include "sq_test.h"
#include "squama/preset.h"
#include "squama/search.h"

static SqSeedOptions small(int n, int threads)
{
    SqSeedOptions o = sq_seed_options_default();
    o.n = n;
    o.size = 64;
    o.threads = threads;
    o.seed = 7;
    return o;
}

static double min_pairwise(const SqSeedCandidate *const *c, int n)
{
    double m = INFINITY;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            m = fmin(m, sq_seed_distance(&c[i]->features, &c[j]->features));
    return m;
}

/* A preset file that loads back to the same parameters. */
static void loads_back(const SqParams *p)
{
    SqError err;
    char *text = sq_preset_to_json(p, NULL, &err);
    assert_non_null(text);
    SqParams back;
    assert_int_equal(sq_preset_parse(text, strlen(text), "seed", &back, NULL, &err), SQ_OK);
    assert_true(sq_params_equal(&back, p));
    free(text);
}

static void distance_is_a_distance(void **state)
{
    (void)state;
    SqSeedResult r;
    SqError err;
    SqSeedOptions o = small(3, 2);
    assert_int_equal(sq_seed_category(SQ_PATTERN_NONE, &o, &r, &err), SQ_OK);
    const SqFeatures *a = &r.picks[0].features, *b = &r.picks[1].features;
    assert_true(sq_seed_distance(a, a) < 1e-9);
    assert_true(sq_seed_distance(a, b) > 0.01);
    assert_true(fabs(sq_seed_distance(a, b) - sq_seed_distance(b, a)) < 1e-12);
    /* the reported nearest is the nearest */
    for (int i = 0; i < r.n; i++) {
        const SqSeedCandidate *c = &r.picks[i];
        assert_true(c->nearest_index >= 0 && c->nearest_index < r.n && c->nearest_index != i);
        for (int j = 0; j < r.n; j++)
            if (j != i)
                assert_true(c->nearest <= sq_seed_distance(&c->features, &r.picks[j].features) + 1e-12);
        assert_true(r.min_distance <= c->nearest);
    }
    sq_seed_result_free(&r);
}

/* A seed's skin between the scales: a darker or paler shade of its ground, over rounder,
 * smooth scales; returns 1 (fails otherwise). */
static int gap_is_a_shade_of_the_ground(const SqParams *p)
{
    assert_true(p->Scales_GapExtent >= 0.35 && p->Scales_GapExtent <= 0.6);
    assert_true(p->ScaleShape_Blur >= 5 && p->ScaleShape_Blur <= 12);
    assert_false(p->ScaleShape_IsKeeled);
    double k = NAN;
    for (int c = 0; c < 3; c++) {
        const double g = p->Scales_GapColor[c], b = p->Background_Color[c];
        if (b < 0.02 || g >= 1)
            continue; /* no ratio to read, or clamped */
        if (isnan(k))
            k = g / b;
        assert_true(fabs(g / b - k) < 1e-9);
    }
    assert_false(isnan(k));
    assert_true((k >= 0.15 && k <= 0.45) || (k >= 1.3 && k <= 1.6));
    return 1;
}

/* n presets, of the category, valid, loadable as presets, plausible; the pool's counts add
 * up; the same on 1 and 2 threads. */
static void category_presets(void **state)
{
    (void)state;
    const int cats[] = {SQ_PATTERN_LONGITUDINAL, SQ_PATTERN_TRANSVERSAL, SQ_PATTERN_SPOTS, SQ_PATTERN_OTHER_SIMPLE};
    int gaps = 0, smooth_plain = 0, picks = 0;
    for (size_t k = 0; k < sizeof cats / sizeof cats[0]; k++) {
        SqSeedResult r1, r2 = {0};
        SqError err;
        SqSeedOptions o1 = small(5, 1), o2 = small(5, 2);
        assert_int_equal(sq_seed_category(cats[k], &o1, &r1, &err), SQ_OK);
        /* the thread comparison runs in the plain build (sq_sanitized) */
        if (!sq_sanitized)
            assert_int_equal(sq_seed_category(cats[k], &o2, &r2, &err), SQ_OK);
        const SqSeedResult *two = sq_sanitized ? &r1 : &r2;
        printf("  %-13s drawn %d, implausible %d, failed %d, pool %d, smallest distance %.3f\n",
               sq_pattern_type_name(cats[k]), r1.drawn, r1.implausible, r1.failed, r1.npool, r1.min_distance);
        assert_int_equal(r1.n, 5);
        assert_true(r1.npool >= r1.n);
        assert_true(r1.drawn >= r1.npool + r1.implausible + r1.failed);
        assert_int_equal(r1.drawn, two->drawn);
        for (int i = 0; i < r1.n; i++) {
            const SqSeedCandidate *c = &r1.picks[i];
            assert_int_equal(c->params.Pattern_Type, cats[k]);
            assert_int_equal(sq_params_validate(&c->params, &err), SQ_OK);
            /* plausible: the pattern shows, and leaves skin to show */
            assert_true(c->coverage >= 0.05 && c->coverage <= 0.8);
            assert_true(c->contrast >= 20);
            assert_true(isnan(c->to_origin));
            /* thread count independent, to the bit */
            assert_true(sq_params_equal(&c->params, &two->picks[i].params));
            assert_memory_equal(&c->features, &two->picks[i].features, sizeof c->features);
            loads_back(&c->params);
            picks++;
            if (c->params.Scales_GapExtent > 0)
                gaps += gap_is_a_shade_of_the_ground(&c->params);
            else
                smooth_plain += !c->params.ScaleShape_IsKeeled;
        }
        /* no two picks the same candidate */
        for (int i = 0; i < r1.n; i++)
            for (int j = i + 1; j < r1.n; j++)
                assert_false(sq_params_equal(&r1.picks[i].params, &r1.picks[j].params));
        sq_seed_result_free(&r1);
        sq_seed_result_free(&r2);
    }
    /* some smooth-scaled skins, not all, show the skin between their scales */
    printf("  %d of %d picks show the skin between their scales, %d smooth-scaled ones do not\n", gaps, picks,
           smooth_plain);
    assert_true(gaps >= 1 && smooth_plain >= 1);
}

/* Reaction-diffusion: a preset of the complex category, valid, plausible, loadable (on one
 * thread, no thread comparison: each candidate is a simulation; one preset, so a pool of 12
 * where two would draw at least 64; the picking, which every category shares, is
 * category_presets' and layered_presets' to check). */
static void complex_presets(void **state)
{
    (void)state;
    SqSeedOptions o = small(1, 1);
    SqSeedResult r;
    SqError err;
    assert_int_equal(sq_seed_category(SQ_PATTERN_COMPLEX, &o, &r, &err), SQ_OK);
    printf("  complex drawn %d, implausible %d, pool %d\n", r.drawn, r.implausible, r.npool);
    assert_int_equal(r.n, 1);
    for (int i = 0; i < r.n; i++) {
        const SqSeedCandidate *c = &r.picks[i];
        assert_int_equal(c->params.Pattern_Type, SQ_PATTERN_COMPLEX);
        assert_int_equal(sq_params_validate(&c->params, &err), SQ_OK);
        assert_true(c->coverage >= 0.05 && c->coverage <= 0.8);
        assert_true(c->contrast >= 20);
        loads_back(&c->params);
    }
    sq_seed_result_free(&r);
}

/* The layered kind: one layer of stripes, bands or spots over another simple pattern, the
 * pairs mixed, the layer showing over its base as a pattern over the skin; the same on 1
 * and 2 threads; presets that load back as they were. */
static void layered_presets(void **state)
{
    (void)state;
    SqSeedResult r, r1 = {0};
    SqError err;
    SqSeedOptions o = small(6, 2), o1 = small(6, 1);
    assert_int_equal(sq_seed_category(SQ_FIT_LAYERED, &o, &r, &err), SQ_OK);
    if (!sq_sanitized) /* the thread comparison runs in the plain build */
        assert_int_equal(sq_seed_category(SQ_FIT_LAYERED, &o1, &r1, &err), SQ_OK);
    const SqSeedResult *one = sq_sanitized ? &r : &r1;
    printf("  layered: drawn %d, implausible %d, pool %d\n", r.drawn, r.implausible, r.npool);
    assert_int_equal(r.n, 6);
    unsigned pairs = 0;
    for (int i = 0; i < r.n; i++) {
        const SqSeedCandidate *c = &r.picks[i];
        assert_int_equal(sq_fit_kind_of(&c->params), SQ_FIT_LAYERED);
        assert_int_equal(c->params.Pattern_Layers.count, 1);
        const int base = c->params.Pattern_Type, layer = c->params.Pattern_Layers.layer[0].spec.Pattern_Type;
        assert_true(sq_genome_layerable(base, layer));
        pairs |= 1u << (base * SQ_PATTERN_COUNT + layer);
        assert_int_equal(sq_params_validate(&c->params, &err), SQ_OK);
        assert_true(c->coverage >= 0.05 && c->coverage <= 0.8 && c->contrast >= 20);
        assert_true(c->layer_coverage >= 0.05 && c->layer_coverage <= 0.8 && c->layer_contrast >= 20);
        assert_true(sq_params_equal(&c->params, &one->picks[i].params));
        loads_back(&c->params);
        for (int j = 0; j < i; j++)
            assert_false(sq_params_equal(&r.picks[j].params, &c->params));
        printf("  %02d %s under %s: layer coverage %.2f contrast %.0f\n", i, sq_pattern_type_name(base),
               sq_pattern_type_name(layer), c->layer_coverage, c->layer_contrast);
    }
    assert_true(__builtin_popcount(pairs) >= 3); /* not one pair six times */
    sq_seed_result_free(&r);
    sq_seed_result_free(&r1);
}

/* Another seed, other presets. */
static void seed_matters(void **state)
{
    (void)state;
    SqSeedResult a, b;
    SqError err;
    SqSeedOptions o = small(2, 2);
    assert_int_equal(sq_seed_category(SQ_PATTERN_SPOTS, &o, &a, &err), SQ_OK);
    o.seed = 8;
    assert_int_equal(sq_seed_category(SQ_PATTERN_SPOTS, &o, &b, &err), SQ_OK);
    assert_false(sq_params_equal(&a.picks[0].params, &b.picks[0].params));
    sq_seed_result_free(&a);
    sq_seed_result_free(&b);
}

/* Farthest-point sampling against random subsets of the same pool: its smallest pairwise
 * distance is larger than that of (nearly) every random subset of the same size. */
static void picks_are_diverse(void **state)
{
    (void)state;
    enum { N = 6, TRIALS = 40 };
    SqSeedResult r;
    SqError err;
    SqSeedOptions o = small(N, 2);
    assert_int_equal(sq_seed_category(SQ_PATTERN_SPOTS, &o, &r, &err), SQ_OK);
    const SqSeedCandidate *set[N];
    for (int i = 0; i < N; i++)
        set[i] = &r.picks[i];
    const double picked = min_pairwise(set, N);
    assert_true(fabs(picked - r.min_distance) < 1e-12);
    uint64_t x = 12345;
    int beaten = 0;
    double mean = 0;
    for (int t = 0; t < TRIALS; t++) {
        int idx[N];
        for (int i = 0; i < N; i++) {
            int fresh;
            do { /* N distinct indices */
                x = x * 6364136223846793005ull + 1442695040888963407ull;
                idx[i] = (int)((x >> 33) % (uint64_t)r.npool);
                fresh = 1;
                for (int j = 0; j < i; j++)
                    fresh &= idx[j] != idx[i];
            } while (!fresh);
            set[i] = &r.pool[idx[i]];
        }
        const double m = min_pairwise(set, N);
        mean += m / TRIALS;
        beaten += picked > m;
    }
    printf("  smallest distance: picked %.3f, random subsets %.3f on average; picked larger in %d of %d\n", picked,
           mean, beaten, TRIALS);
    assert_true(picked > 1.5 * mean);
    assert_true(beaten >= TRIALS * 9 / 10);
    sq_seed_result_free(&r);
}

/* Variations keep the category and the structure, stay valid, and move further from the
 * origin as the step grows. */
static void near_variations(void **state)
{
    (void)state;
    char path[4096];
    SqParams origin;
    SqError err;
    assert_int_equal(sq_preset_load(src_path(path, sizeof path, "presets/thesis/figure_4_9_other_simple.json"),
                                     &origin, NULL, &err),
                     SQ_OK);
    const double steps[] = {0.03, 0.12, 0.4};
    double prev = 0;
    for (int s = 0; s < 3; s++) {
        SqSeedResult r;
        SqSeedOptions o = small(4, 2);
        o.distance = steps[s];
        assert_int_equal(sq_seed_near(&origin, &o, &r, &err), SQ_OK);
        assert_int_equal(r.n, 4);
        double mean = 0;
        for (int i = 0; i < r.npool; i++)
            mean += r.pool[i].to_origin / r.npool;
        printf("  step %.2f: mean feature distance to the origin %.3f over %d variations\n", steps[s], mean, r.npool);
        for (int i = 0; i < r.n; i++) {
            const SqSeedCandidate *c = &r.picks[i];
            assert_int_equal(c->params.Pattern_Type, SQ_PATTERN_OTHER_SIMPLE);
            assert_memory_equal(&c->params.CA_Descriptor, &origin.CA_Descriptor, sizeof origin.CA_Descriptor);
            assert_int_equal(c->params.Seed, origin.Seed);
            assert_int_equal(sq_params_validate(&c->params, &err), SQ_OK);
            assert_true(isfinite(c->to_origin) && c->to_origin > 0);
            assert_false(sq_params_equal(&c->params, &origin));
        }
        assert_true(mean > prev);
        prev = mean;
        sq_seed_result_free(&r);
    }
    /* a layered preset: its layer's genes move too, the layer's type stays */
    assert_int_equal(sq_preset_load(src_path(path, sizeof path, "presets/layered/garter_snake.json"), &origin, NULL,
                                    &err),
                     SQ_OK);
    SqSeedResult r;
    SqSeedOptions o = small(3, 2);
    assert_int_equal(sq_seed_near(&origin, &o, &r, &err), SQ_OK);
    const SqPatternLayer *ol = &origin.Pattern_Layers.layer[0];
    for (int i = 0; i < r.n; i++) {
        const SqPatternLayer *l = &r.picks[i].params.Pattern_Layers.layer[0];
        assert_int_equal(r.picks[i].params.Pattern_Layers.count, 1);
        assert_int_equal(l->spec.Pattern_Type, ol->spec.Pattern_Type);
        assert_true(l->Layer_Opacity != ol->Layer_Opacity ||
                    memcmp(l->spec.Longitudinal_StripesColor, ol->spec.Longitudinal_StripesColor,
                           sizeof ol->spec.Longitudinal_StripesColor) != 0);
    }
    sq_seed_result_free(&r);
}

/* What a fit offers as seeds: its champion, each other kind's best by score, the rest of
 * its front; each once, each with its objectives' distance to the photo. */
static void from_fit(void **state)
{
    (void)state;
    char path[4096];
    SqFitCandidate front[4];
    SqError err;
    memset(front, 0, sizeof front);
    const char *files[] = {"presets/thesis/table_4_4_spots.json", "presets/thesis/table_4_3_longitudinal.json",
                           "presets/thesis/table_4_1_transversal.json"};
    for (int i = 0; i < 3; i++) {
        const int k = i == 0 ? 0 : i + 1; /* front[1] is front[0] again, as fits' fronts can have it */
        assert_int_equal(sq_preset_load(src_path(path, sizeof path, files[i]), &front[k].params, NULL, &err), SQ_OK);
        for (int j = 0; j < SQ_OBJ_COUNT; j++)
            front[k].obj[j] = 0.1 * (k + 1);
        front[k].score = 0.1 * (k + 1);
        front[k].view_scale = 1;
    }
    front[1] = front[0];
    SqFitResult fit = {.front = front, .nfront = 4, .best = front[0]};
    for (int k = 0; k < SQ_FIT_KINDS; k++)
        fit.kind_best[k].score = INFINITY;
    fit.kind_best[SQ_PATTERN_SPOTS] = front[0];
    fit.kind_best[SQ_PATTERN_LONGITUDINAL] = front[2];
    fit.kind_best[SQ_PATTERN_TRANSVERSAL] = front[3];
    SqSeedResult r;
    SqSeedOptions o = small(2, 2);
    assert_int_equal(sq_seed_from_fit(&fit, &o, &r, &err), SQ_OK);
    assert_int_equal(r.n, 2);
    assert_true(sq_params_equal(&r.picks[0].params, &front[0].params));
    assert_true(sq_params_equal(&r.picks[1].params, &front[2].params));
    assert_int_equal(r.picks[0].source, 0);
    assert_int_equal(r.picks[1].source, 2);
    assert_true(r.picks[0].to_origin < r.picks[1].to_origin);
    assert_true(fabs(r.picks[1].to_origin - sq_seed_objective_distance(front[2].obj)) < 1e-12);
    assert_int_equal(r.picks[0].nearest_index, 1);
    assert_true(r.min_distance > 0.05);
    sq_seed_result_free(&r);
    o.n = 10; /* more than the front: the whole front, once each */
    assert_int_equal(sq_seed_from_fit(&fit, &o, &r, &err), SQ_OK);
    assert_int_equal(r.n, 3);
    sq_seed_result_free(&r);
    /* a plain skin's best, not in the front, scoring between the stripes and the bands:
     * offered after the stripes and before the bands, which the front would have put first */
    SqFitCandidate plain = front[2];
    plain.params.Pattern_Type = SQ_PATTERN_NONE;
    plain.score = 0.35;
    for (int j = 0; j < SQ_OBJ_COUNT; j++)
        plain.obj[j] = 0.35;
    fit.kind_best[SQ_PATTERN_NONE] = plain;
    front[2].score = front[3].score = 0.5; /* the order is the kind bests' scores, not these */
    assert_int_equal(sq_seed_from_fit(&fit, &o, &r, &err), SQ_OK);
    assert_int_equal(r.n, 4);
    const int want[] = {0, 2, -1, 3};
    for (int i = 0; i < 4; i++)
        assert_int_equal(r.picks[i].source, want[i]);
    assert_true(sq_params_equal(&r.picks[2].params, &plain.params));
    assert_ptr_equal(r.picks[2].fitted, &fit.kind_best[SQ_PATTERN_NONE]);
    assert_true(fabs(r.picks[2].to_origin - sq_seed_objective_distance(plain.obj)) < 1e-12);
    sq_seed_result_free(&r);
}

static void bad_options(void **state)
{
    (void)state;
    SqSeedResult r;
    SqError err;
    SqSeedOptions o = small(0, 1);
    assert_int_equal(sq_seed_category(SQ_PATTERN_SPOTS, &o, &r, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "n must be 1 to 256, got 0");
    assert_null(r.picks);
    o.n = 257;
    assert_int_equal(sq_seed_category(SQ_PATTERN_SPOTS, &o, &r, &err), SQ_ERR_INVALID);
    o.n = 2;
    assert_int_equal(sq_seed_category(99, &o, &r, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "kind 99");
    SqParams p;
    sq_params_default(&p);
    o.distance = 0;
    assert_int_equal(sq_seed_near(&p, &o, &r, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "distance must be in (0, 1]");
    o.distance = 1.5;
    assert_int_equal(sq_seed_near(&p, &o, &r, &err), SQ_ERR_INVALID);
    o.distance = 0.1;
    p.Spots_Scale = 99; /* beyond its hard range */
    assert_int_equal(sq_seed_near(&p, &o, &r, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "Spots_Scale");
    assert_null(r.picks);
    SqFitResult empty = {0};
    assert_int_equal(sq_seed_from_fit(&empty, &o, &r, &err), SQ_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(distance_is_a_distance), cmocka_unit_test(category_presets),
        cmocka_unit_test(seed_matters),           cmocka_unit_test(picks_are_diverse),
        cmocka_unit_test(near_variations),        cmocka_unit_test(from_fit),
        cmocka_unit_test(bad_options),            cmocka_unit_test(layered_presets),
        cmocka_unit_test(complex_presets),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
