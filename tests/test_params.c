/* The parameter table itself: invariants that every later module relies on. */
#include <math.h>
#include <stdlib.h>

#include "sq_test.h"
#include "squama/params.h"

static void table_names_unique_and_well_formed(void **state)
{
    (void)state;
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    assert_true(n > 59);
    for (size_t i = 0; i < n; i++) {
        assert_non_null(t[i].name);
        assert_non_null(t[i].group);
        assert_non_null(t[i].help);
        assert_non_null(t[i].ref);
        if (strlen(t[i].help) < 10)
            fail_msg("%s: help too short", t[i].name);
        if (strlen(t[i].help) > 100)
            fail_msg("%s: help is one line, at most 100 characters", t[i].name);
        for (const char *c = t[i].name; *c; c++)
            if (!(*c == '_' || (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') ||
                  (*c >= '0' && *c <= '9')))
                fail_msg("%s: name has '%c'", t[i].name, *c);
        for (size_t j = i + 1; j < n; j++) {
            if (strcmp(t[i].name, t[j].name) == 0)
                fail_msg("duplicate name %s", t[i].name);
            if (t[i].offset == t[j].offset)
                fail_msg("%s and %s share a field", t[i].name, t[j].name);
        }
    }
}

static void table_fields_inside_struct_and_disjoint(void **state)
{
    (void)state;
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    static const size_t size_of[] = {
        [SQ_PT_FLOAT] = sizeof(double), [SQ_PT_INT] = sizeof(int),
        [SQ_PT_BOOL] = sizeof(int), [SQ_PT_ENUM] = sizeof(int),
        [SQ_PT_VEC2] = 2 * sizeof(double), [SQ_PT_COLOR] = 4 * sizeof(double),
        [SQ_PT_CA] = sizeof(SqCa)};
    for (size_t i = 0; i < n; i++) {
        size_t a0 = t[i].offset, a1 = a0 + size_of[t[i].type];
        assert_true(a1 <= sizeof(SqParams));
        for (size_t j = 0; j < n; j++) {
            if (i == j)
                continue;
            size_t b0 = t[j].offset, b1 = b0 + size_of[t[j].type];
            if (a0 < b1 && b0 < a1)
                fail_msg("%s overlaps %s", t[i].name, t[j].name);
        }
    }
}

static void ranges_ordered_and_defaults_inside(void **state)
{
    (void)state;
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    for (size_t i = 0; i < n; i++) {
        const SqParamSpec *s = &t[i];
        if (s->type == SQ_PT_CA) {
            assert_non_null(s->def_text);
            continue;
        }
        if (!(s->min <= s->smin && s->smin < s->smax && s->smax <= s->max))
            fail_msg("%s: need min <= suggested min < suggested max <= max", s->name);
        int nc = sq_param_components(s->type);
        for (int c = 0; c < nc; c++)
            if (s->def[c] < s->min || s->def[c] > s->max)
                fail_msg("%s: default component %d (%g) outside [%g, %g]", s->name, c,
                         s->def[c], s->min, s->max);
        if (s->type == SQ_PT_INT || s->type == SQ_PT_BOOL || s->type == SQ_PT_ENUM)
            assert_true(s->def[0] == floor(s->def[0]));
        if (s->type == SQ_PT_ENUM) {
            int k = 0;
            while (s->choices[k])
                k++;
            assert_int_equal(s->max, k - 1);
        }
    }
    SqParams p;
    sq_params_default(&p);
    SqError err;
    if (sq_params_validate(&p, &err) != SQ_OK)
        fail_msg("defaults do not validate: %s (%s)", err.what, err.where);
}

/* Every parameter the thesis names in Chapters 4-5, spelled as there, plus the Appendix
 * D.11 ones: 59 in all, as the thesis says. */
static void every_thesis_parameter_present(void **state)
{
    (void)state;
    static const char *const text[] = {
        "Pattern_Type", "Background_Color",
        "Transversal_Color1", "Transversal_Color2", "Transversal_Color3", "Transversal_Color4",
        "Transversal_BeginEnd1", "Transversal_BeginEnd2", "Transversal_BeginEnd3",
        "Transversal_BeginEnd4",
        "Longitudinal_NumberOfStripes", "Longitudinal_StripesWidth",
        "Longitudinal_StripesColor", "Longitudinal_Pinch",
        "Spots_Scale", "Spots_ScaleVariation", "Spots_PositionRandom", "Spots_Offset",
        "Spots_Color", "Spots_Interstice", "Spots_IntersticeRandom", "Spots_Rotation",
        "Spots_RotationRandom", "Spots_Tiling",
        "Pattern_RotatePattern90Degrees", "Pattern_BlurAmount", "Pattern_Contrast",
        "Has_Outline", "Outline_Color", "Outline_Edge_Width", "Outline_Blur",
        "Outline_Edge_Roundness", "Outline_Distortion_Intensity",
        "Pattern_Warp_Small", "Pattern_Warp_Large",
        "ScaleShape_Contrast", "ScaleShape_Blur", "ScaleShape_Gradient",
        "ScaleShape_IsKeeled", "ScaleShape_KeelThickness",
        "Scales_DetailNormal", "Scales_XAmount", "Scales_YAmount", "Scales_ScaleSize",
        "Scales_BellyScalesPct", "Scales_RoughnessMin", "Scales_RoughnessMax",
        "Normal_Intensity",
    };
    static const char *const d11[] = {
        "Color_NoiseIntensity", "CustomPattern_Color_Inside", "CustomPattern_Color_Outside",
        "CustomPattern_LevelInLow", "CustomPattern_LevelInHigh", "CustomPattern_LevelInMid",
        "ScaleShape_Ridge", "ScaleShape_KeelDistortion", "Scales_ScaleSizeXY",
        "Scales_Expansion", "Scales_BellyWarpIntensity",
    };
    size_t ntext = sizeof text / sizeof text[0], nd11 = sizeof d11 / sizeof d11[0];
    assert_int_equal(ntext + nd11, 59);
    for (size_t i = 0; i < ntext; i++) {
        const SqParamSpec *s = sq_params_find(text[i]);
        if (!s)
            fail_msg("thesis parameter %s missing", text[i]);
        assert_int_equal(s->origin, SQ_ORIGIN_THESIS);
    }
    for (size_t i = 0; i < nd11; i++) {
        const SqParamSpec *s = sq_params_find(d11[i]);
        if (!s)
            fail_msg("Appendix D.11 parameter %s missing", d11[i]);
        assert_int_equal(s->origin, SQ_ORIGIN_THESIS_D11);
    }
    /* and nothing else claims to be from the thesis' 59 except the automaton's own */
    size_t n, counted = 0;
    const SqParamSpec *t = sq_params_table(&n);
    for (size_t i = 0; i < n; i++)
        if (t[i].origin != SQ_ORIGIN_SQUAMA && strncmp(t[i].name, "CA_", 3) != 0)
            counted++;
    assert_int_equal(counted, 59);
}

static void thesis_suggested_ranges(void **state)
{
    (void)state;
    static const struct { const char *name; double lo, hi; } want[] = {
        {"Longitudinal_NumberOfStripes", 1, 10}, {"Longitudinal_Pinch", 0, 10},
        {"Spots_Scale", 0, 2},      {"Spots_Offset", 0, 0.5},
        {"Spots_RotationRandom", 0, 180}, {"Spots_Tiling", 0.1, 5},
        {"Pattern_BlurAmount", 0, 16}, {"Outline_Edge_Width", 0, 16},
        {"Outline_Distortion_Intensity", 0, 10}, {"Pattern_Warp_Small", 0, 1},
        {"Pattern_Warp_Large", 0, 10}, {"ScaleShape_KeelThickness", 0.02, 0.1},
        {"Scales_DetailNormal", 0, 0.05}, {"Scales_XAmount", 1, 64},
        {"Scales_ScaleSize", 0, 2}, {"Scales_BellyScalesPct", 0.1, 0.2},
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        const SqParamSpec *s = sq_params_find(want[i].name);
        assert_non_null(s);
        if (s->smin != want[i].lo || s->smax != want[i].hi)
            fail_msg("%s: suggested %g..%g, thesis says %g..%g", s->name, s->smin, s->smax,
                     want[i].lo, want[i].hi);
    }
}

static void find_and_closest(void **state)
{
    (void)state;
    assert_non_null(sq_params_find("Spots_Tiling"));
    assert_null(sq_params_find("spots_tiling")); /* exact */
    assert_string_equal(sq_params_closest("Spots_Tilling")->name, "Spots_Tiling");
    assert_string_equal(sq_params_closest("spots_tiling")->name, "Spots_Tiling");
    assert_string_equal(sq_params_closest("Transversal_Colour2")->name, "Transversal_Color2");
    assert_string_equal(sq_params_closest("Normal_Intensty")->name, "Normal_Intensity");
}

static void validate_rejects_out_of_range_and_nan(void **state)
{
    (void)state;
    SqParams p;
    SqError err;
    sq_params_default(&p);
    p.Spots_Tiling = 100;
    assert_int_equal(sq_params_validate(&p, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "Spots_Tiling");
    assert_contains(err.what, "[0.05, 32]");

    sq_params_default(&p);
    p.Background_Color[2] = NAN;
    assert_int_equal(sq_params_validate(&p, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "finite");

    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_COUNT;
    assert_int_equal(sq_params_validate(&p, &err), SQ_ERR_INVALID);

    sq_params_default(&p);
    p.CA_Descriptor.nrules = 0;
    assert_int_equal(sq_params_validate(&p, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "CA_Descriptor");
}

static void equal_and_format(void **state)
{
    (void)state;
    SqParams a, b;
    sq_params_default(&a);
    b = a;
    assert_true(sq_params_equal(&a, &b));
    b.Spots_PositionRandom[1] = 0.25;
    assert_false(sq_params_equal(&a, &b));

    char buf[256];
    assert_int_equal(sq_param_format(&b, sq_params_find("Spots_PositionRandom"), 6, buf,
                                     sizeof buf),
                     strlen("[0, 0.25]"));
    assert_string_equal(buf, "[0, 0.25]");
    sq_param_format(&a, sq_params_find("Pattern_Type"), 6, buf, sizeof buf);
    assert_string_equal(buf, "none");
    sq_param_format(&a, sq_params_find("CA_Descriptor"), 6, buf, sizeof buf);
    assert_string_equal(buf, "0 0 1 1 1 1 0 0 / rectangular / 0 / 6 / 1110 1 / 1100 1 / 1000 x");
    /* truncation still terminates */
    char small[8];
    sq_param_format(&a, sq_params_find("CA_Descriptor"), 6, small, sizeof small);
    assert_int_equal(strlen(small), 7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(table_names_unique_and_well_formed),
        cmocka_unit_test(table_fields_inside_struct_and_disjoint),
        cmocka_unit_test(ranges_ordered_and_defaults_inside),
        cmocka_unit_test(every_thesis_parameter_present),
        cmocka_unit_test(thesis_suggested_ranges),
        cmocka_unit_test(find_and_closest),
        cmocka_unit_test(validate_rejects_out_of_range_and_nan),
        cmocka_unit_test(equal_and_format),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
