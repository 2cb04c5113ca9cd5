/* The parameter table itself: invariants that every later module relies on. */
#include <math.h>
#include <stddef.h>
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
        [SQ_PT_CA] = sizeof(SqCa), [SQ_PT_LAYERS] = sizeof(SqPatternLayers)};
    const size_t layers0 = offsetof(SqParams, Pattern_Layers.layer[0]);
    for (size_t i = 0; i < n; i++) {
        size_t a0 = t[i].offset, a1 = a0 + size_of[t[i].type];
        assert_true(a1 <= sizeof(SqParams));
        if (t[i].flags & SQ_PF_LAYER) /* a layer's own setting: a field of layer[0] */
            assert_true(a0 >= layers0 && a1 <= layers0 + sizeof(SqPatternLayer) &&
                        a0 - layers0 >= sizeof(SqPatternSpec));
        for (size_t j = 0; j < n; j++) {
            if (i == j || (t[i].type == SQ_PT_LAYERS && (t[j].flags & SQ_PF_LAYER)) ||
                (t[j].type == SQ_PT_LAYERS && (t[i].flags & SQ_PF_LAYER)))
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

/* The pattern rows are exactly the fields of SqParams.pattern, and inside a layer each
 * lands on its own field of SqPatternLayer. */
static void layer_rows_map_onto_the_layer(void **state)
{
    (void)state;
    size_t n, in_layer = 0, bytes = 0;
    const SqParamSpec *t = sq_params_table(&n);
    for (size_t i = 0; i < n; i++)
        if (sq_param_in_layer(&t[i]) && !(t[i].flags & SQ_PF_LAYER)) {
            in_layer++;
            bytes += t[i].type == SQ_PT_CA      ? sizeof(SqCa)
                     : t[i].type == SQ_PT_FLOAT ? sizeof(double)
                     : t[i].type == SQ_PT_VEC2  ? 2 * sizeof(double)
                     : t[i].type == SQ_PT_COLOR ? 4 * sizeof(double)
                                                : sizeof(int);
        }
    /* every byte of the spec but padding belongs to a row: none is forgotten */
    assert_true(bytes <= sizeof(SqPatternSpec) && bytes + 64 > sizeof(SqPatternSpec));
    assert_true(in_layer > 40);
    assert_true(sq_param_in_layer(sq_params_find("Pattern_Type")));
    assert_true(sq_param_in_layer(sq_params_find("Pattern_Warp_Large")));
    assert_true(sq_param_in_layer(sq_params_find("RD_Softness")));
    assert_true(sq_param_in_layer(sq_params_find("Layer_Opacity")));
    assert_false(sq_param_in_layer(sq_params_find("Background_Color")));
    assert_false(sq_param_in_layer(sq_params_find("Has_Outline")));
    assert_false(sq_param_in_layer(sq_params_find("Scales_XAmount")));
    assert_false(sq_param_in_layer(sq_params_find("Pattern_Layers")));
    assert_false(sq_param_in_layer(sq_params_find("Seed")));

    SqPatternLayer l;
    sq_pattern_layer_default(&l);
    assert_int_equal(l.Layer_Blend, SQ_BLEND_NORMAL);
    assert_true(l.Layer_Opacity == 1.0);
    SqParams d;
    sq_params_default(&d);
    assert_memory_equal(&l.spec, &d.pattern, sizeof l.spec); /* same defaults as the base */
    *(double *)sq_param_layer_ptr(&l, sq_params_find("Spots_Scale")) = 1.75;
    *(int *)sq_param_layer_ptr(&l, sq_params_find("Longitudinal_NumberOfStripes")) = 5;
    *(double *)sq_param_layer_ptr(&l, sq_params_find("Layer_Opacity")) = 0.25;
    *(int *)sq_param_layer_ptr(&l, sq_params_find("Layer_Blend")) = SQ_BLEND_SCREEN;
    assert_true(l.spec.Spots_Scale == 1.75);
    assert_int_equal(l.spec.Longitudinal_NumberOfStripes, 5);
    assert_true(l.Layer_Opacity == 0.25);
    assert_int_equal(l.Layer_Blend, SQ_BLEND_SCREEN);
    assert_null(sq_param_layer_ptr(&l, sq_params_find("Scales_XAmount")));

    /* the base pattern's fields by name and as a whole are the same memory */
    d.pattern.Spots_Tiling = 2.5;
    assert_true(d.Spots_Tiling == 2.5);
    d.CA_Descriptor.epochs = 9;
    assert_int_equal(d.pattern.CA_Descriptor.epochs, 9);
}

static void layers_validated_compared_and_formatted(void **state)
{
    (void)state;
    SqParams a, b;
    SqError err;
    sq_params_default(&a);
    assert_int_equal(a.Pattern_Layers.count, 0);
    a.Pattern_Layers.count = 2;
    a.Pattern_Layers.layer[0].spec.Pattern_Type = SQ_PATTERN_SPOTS;
    a.Pattern_Layers.layer[1].spec.Pattern_Type = SQ_PATTERN_LONGITUDINAL;
    a.Pattern_Layers.layer[1].Layer_Blend = SQ_BLEND_MULTIPLY;
    a.Pattern_Layers.layer[1].Layer_Opacity = 0.5;
    assert_int_equal(sq_params_validate(&a, &err), SQ_OK);

    b = a;
    b.Pattern_Layers.layer[1].spec.Spots_Tiling = 100;
    assert_int_equal(sq_params_validate(&b, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "Pattern_Layers[1].Spots_Tiling");
    assert_contains(err.what, "[0.05, 32]");
    b = a;
    b.Pattern_Layers.layer[0].Layer_Opacity = 1.5;
    assert_int_equal(sq_params_validate(&b, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "Pattern_Layers[0].Layer_Opacity");
    b = a;
    b.Pattern_Layers.layer[0].spec.CA_Descriptor.nrules = 0;
    assert_int_equal(sq_params_validate(&b, &err), SQ_ERR_INVALID);
    assert_contains(err.where, "Pattern_Layers[0].CA_Descriptor");
    b = a;
    b.Pattern_Layers.count = SQ_MAX_PATTERN_LAYERS + 1;
    assert_int_equal(sq_params_validate(&b, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "Pattern_Layers");
    b = a; /* an unused layer is neither checked nor compared */
    b.Pattern_Layers.layer[2].Layer_Opacity = 7;
    assert_int_equal(sq_params_validate(&b, &err), SQ_OK);
    assert_true(sq_params_equal(&a, &b));

    b = a;
    assert_true(sq_params_equal(&a, &b));
    b.Pattern_Layers.layer[1].spec.Longitudinal_Pinch = 2;
    assert_false(sq_params_equal(&a, &b));
    b = a;
    b.Pattern_Layers.count = 1;
    assert_false(sq_params_equal(&a, &b));

    char buf[256];
    sq_param_format(&a, sq_params_find("Pattern_Layers"), 6, buf, sizeof buf);
    assert_string_equal(buf, "[spots normal 1, longitudinal multiply 0.5]");
    sq_params_default(&b);
    sq_param_format(&b, sq_params_find("Pattern_Layers"), 6, buf, sizeof buf);
    assert_string_equal(buf, "[]");
    sq_param_format(&b, sq_params_find("Layer_Blend"), 6, buf, sizeof buf);
    assert_string_equal(buf, "normal");
    sq_param_format(&b, sq_params_find("Layer_Opacity"), 6, buf, sizeof buf);
    assert_string_equal(buf, "1");
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
        cmocka_unit_test(layer_rows_map_onto_the_layer),
        cmocka_unit_test(layers_validated_compared_and_formatted),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
