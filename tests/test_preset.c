/* Presets: strict loading (a test per error), exact round trips, shipped presets. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>

#include "sq_test.h"
#include "squama/preset.h"

static SqStatus parse(const char *text, SqParams *p, SqError *err)
{
    return sq_preset_parse(text, strlen(text), "p.json", p, NULL, err);
}

static void only_format_gives_defaults(void **state)
{
    (void)state;
    SqParams p, d;
    SqError err;
    assert_int_equal(parse("{\"format\": \"squama-preset/1\"}", &p, &err), SQ_OK);
    sq_params_default(&d);
    assert_true(sq_params_equal(&p, &d));
}

static void values_of_every_type(void **state)
{
    (void)state;
    const char *text =
        "{\n"
        "  \"format\": \"squama-preset/1\",\n"
        "  \"name\": \"test\",\n"
        "  \"Pattern_Type\": \"spots\",\n"
        "  \"Spots_Tiling\": 2.5,\n"
        "  \"Scales_XAmount\": 17,\n"
        "  \"Has_Outline\": true,\n"
        "  \"Spots_Interstice\": [0.7, 0],\n"
        "  \"Spots_Color\": [0.8, 0.35, 0],\n"
        "  \"Outline_Color\": [0.1, 0.2, 0.3, 0.5],\n"
        "  \"CA_Descriptor\": {\"initial\": [1, 1, 0, 1], \"type\": \"triangular\",\n"
        "                      \"epochs\": 3, \"rules\": [\"100 x\"]}\n"
        "}\n";
    SqParams p;
    SqPresetInfo info;
    SqError err;
    assert_int_equal(sq_preset_parse(text, strlen(text), "p.json", &p, &info, &err), SQ_OK);
    assert_string_equal(info.name, "test");
    assert_int_equal(p.Pattern_Type, SQ_PATTERN_SPOTS);
    assert_true(p.Spots_Tiling == 2.5);
    assert_int_equal(p.Scales_XAmount, 17);
    assert_int_equal(p.Has_Outline, 1);
    assert_true(p.Spots_Interstice[0] == 0.7 && p.Spots_Interstice[1] == 0);
    assert_true(p.Spots_Color[3] == 1.0); /* [r, g, b] means opaque */
    assert_true(p.Outline_Color[3] == 0.5);
    assert_int_equal(p.CA_Descriptor.type, SQ_CA_TRIANGULAR);
    assert_int_equal(p.CA_Descriptor.ncells, 4);
    assert_int_equal(p.CA_Descriptor.shift_mirror, 0);
}

/* Layers: every pattern parameter, the CA descriptor in either form, blend and opacity;
 * missing keys take the table's defaults. */
static void pattern_layers_parse(void **state)
{
    (void)state;
    const char *text =
        "{\n"
        "  \"format\": \"squama-preset/1\",\n"
        "  \"Pattern_Type\": \"spots\",\n"
        "  \"Spots_Scale\": 0.75,\n"
        "  \"Pattern_Layers\": [\n"
        "    {\"Pattern_Type\": \"longitudinal\", \"Layer_Blend\": \"multiply\",\n"
        "     \"Layer_Opacity\": 0.8, \"Longitudinal_NumberOfStripes\": 3,\n"
        "     \"Pattern_Warp_Small\": 0.5},\n"
        "    {\"Pattern_Type\": \"other_simple\",\n"
        "     \"CA_Descriptor\": {\"initial\": [1, 1, 0, 1], \"type\": \"triangular\",\n"
        "                       \"epochs\": 3, \"rules\": [\"100 x\"]}},\n"
        "    {\"Pattern_Type\": \"complex\", \"RD_System\": \"stripes\",\n"
        "     \"CA_Descriptor\": \"0 1 1 0\\nrectangular\\n0\\n4\\n1110 x\"}\n"
        "  ]\n"
        "}\n";
    SqParams p, d;
    SqError err;
    if (parse(text, &p, &err) != SQ_OK)
        fail_msg("%s (%s)", err.what, err.where);
    sq_params_default(&d);
    assert_int_equal(p.Pattern_Type, SQ_PATTERN_SPOTS);
    assert_true(p.Spots_Scale == 0.75);
    assert_int_equal(p.Pattern_Layers.count, 3);
    const SqPatternLayer *l = p.Pattern_Layers.layer;
    assert_int_equal(l[0].spec.Pattern_Type, SQ_PATTERN_LONGITUDINAL);
    assert_int_equal(l[0].Layer_Blend, SQ_BLEND_MULTIPLY);
    assert_true(l[0].Layer_Opacity == 0.8);
    assert_int_equal(l[0].spec.Longitudinal_NumberOfStripes, 3);
    assert_true(l[0].spec.Pattern_Warp_Small == 0.5);
    assert_true(l[0].spec.Spots_Scale == d.Spots_Scale); /* the table's default, not 0.75 */
    assert_int_equal(l[1].spec.Pattern_Type, SQ_PATTERN_OTHER_SIMPLE);
    assert_int_equal(l[1].Layer_Blend, SQ_BLEND_NORMAL);
    assert_true(l[1].Layer_Opacity == 1.0);
    assert_int_equal(l[1].spec.CA_Descriptor.type, SQ_CA_TRIANGULAR);
    assert_int_equal(l[1].spec.CA_Descriptor.ncells, 4);
    assert_int_equal(l[2].spec.RD_System, SQ_RD_STRIPES);
    assert_int_equal(l[2].spec.CA_Descriptor.epochs, 4);
    /* the base pattern and everything else untouched */
    assert_true(sq_ca_equal(&p.CA_Descriptor, &d.CA_Descriptor));

    /* an empty list is no layers, and the same preset as none */
    SqParams e;
    assert_int_equal(parse("{\"format\": \"squama-preset/1\", \"Pattern_Layers\": []}", &e, &err),
                     SQ_OK);
    assert_int_equal(e.Pattern_Layers.count, 0);
    assert_true(sq_params_equal(&e, &d));

    /* save -> load -> save: the same text, every layer parameter written */
    char *saved = sq_preset_to_json(&p, NULL, &err);
    assert_non_null(saved);
    SqParams q;
    if (parse(saved, &q, &err) != SQ_OK)
        fail_msg("%s (%s)\n%s", err.what, err.where, saved);
    assert_true(sq_params_equal(&p, &q));
    char *again = sq_preset_to_json(&q, NULL, &err);
    assert_string_equal(saved, again);
    assert_contains(saved, "\"Pattern_Layers\": [{\n      \"Pattern_Type\": \"longitudinal\",\n"
                           "      \"Layer_Blend\": \"multiply\",\n      \"Layer_Opacity\": 0.8,\n");
    size_t rows, in_layer = 0;
    const SqParamSpec *t = sq_params_table(&rows);
    for (size_t i = 0; i < rows; i++)
        in_layer += sq_param_in_layer(&t[i]);
    size_t keys = 0;
    for (const char *c = strstr(saved, "\"Pattern_Layers\""); c && *c; c++)
        keys += c[0] == '\n' && c[1] == ' ' && c[2] == ' ' && c[3] == ' ' && c[4] == ' ' &&
                c[5] == ' ' && c[6] == ' ' && c[7] == '"';
    assert_int_equal(keys, 3 * in_layer);
    free(saved);
    free(again);
}

/* One case per way a preset can be wrong: status, location and message. */
static void every_error_named_with_its_place(void **state)
{
    (void)state;
    static const struct { const char *text, *where, *what; SqStatus st; } cases[] = {
        /* unknown key, with the closest valid name and its line */
        {"{\"format\": \"squama-preset/1\",\n \"Spots_Tilling\": 2}", "p.json:2",
         "unknown key \"Spots_Tilling\" (did you mean \"Spots_Tiling\"?)", SQ_ERR_INVALID},
        /* wrong type: the allowed range is given */
        {"{\"format\": \"squama-preset/1\",\n\n \"Spots_Scale\": \"big\"}", "p.json:3",
         "\"Spots_Scale\" must be a number in [0, 8], got the string \"big\"", SQ_ERR_INVALID},
        /* out of the hard range, with the thesis' suggestion */
        {"{\"format\": \"squama-preset/1\", \"Spots_Scale\": 9}", "p.json:1",
         "\"Spots_Scale\" is 9, outside its range [0, 8]; suggested 0 to 2", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Spots_Scale\": -0.5}", "p.json:1",
         "outside its range", SQ_ERR_INVALID},
        /* infinity (JSON has no NaN/Inf literals; an overflowing number is infinite) */
        {"{\"format\": \"squama-preset/1\", \"Spots_Scale\": 1e999}", "p.json:1",
         "\"Spots_Scale\" is not a finite number", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Spots_Scale\": NaN}", "p.json:1:46",
         "malformed JSON", SQ_ERR_PARSE},
        /* integers */
        {"{\"format\": \"squama-preset/1\", \"Scales_XAmount\": 17.5}", "p.json:1",
         "\"Scales_XAmount\" must be an integer in [1, 256], got 17.5", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Scales_XAmount\": 0}", "p.json:1",
         "outside its range [1, 256]", SQ_ERR_INVALID},
        /* booleans */
        {"{\"format\": \"squama-preset/1\", \"Has_Outline\": 1}", "p.json:1",
         "\"Has_Outline\" must be true or false, got 1", SQ_ERR_INVALID},
        /* enums list their choices */
        {"{\"format\": \"squama-preset/1\", \"Pattern_Type\": \"stripes\"}", "p.json:1",
         "must be one of none, longitudinal, transversal, spots, other_simple, complex",
         SQ_ERR_INVALID},
        /* vectors and colours */
        {"{\"format\": \"squama-preset/1\", \"Spots_Interstice\": [0.5]}", "p.json:1",
         "must be an array [x, y]", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Spots_Color\": [1, 0, 0, 1, 1]}", "p.json:1",
         "must be an array [r, g, b, a]", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Spots_Color\": [1, 0, 2, 1]}", "p.json:1",
         "\"Spots_Color\"[2] is 2, outside its range [0, 1]", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Spots_Color\": [1, \"a\", 0]}", "p.json:1",
         "\"Spots_Color\"[1] must be a number", SQ_ERR_INVALID},
        /* duplicates: the second occurrence's line */
        {"{\"format\": \"squama-preset/1\",\n\"Spots_Scale\": 1,\n\"Spots_Scale\": 2}",
         "p.json:3", "key \"Spots_Scale\" appears twice", SQ_ERR_INVALID},
        /* format */
        {"{\"Spots_Scale\": 1}", "p.json", "missing \"format\"", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/9\"}", "p.json:1", "unsupported preset format",
         SQ_ERR_UNSUPPORTED},
        {"[1, 2]", "p.json", "a preset must be a JSON object, got an array of 2",
         SQ_ERR_INVALID},
        /* malformed JSON: line and column */
        {"{\"format\": \"squama-preset/1\",\n  \"Spots_Scale\": 1,\n}", "p.json:3:1",
         "malformed JSON", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\"", "p.json:1:28", "at the end of the text", SQ_ERR_PARSE},
        {"", "p.json:1:1", "the file is empty", SQ_ERR_PARSE},
        /* the byte in error named, not the one after it nor the text's last */
        {"{\"format\": \"squama-preset/1\",, \"Seed\": 1}", "p.json:1:30",
         "malformed JSON: expected a key in double quotes, at \", \"Seed\": 1}\"", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\",}", "p.json:1:30", "a ',' before the '}' (a trailing comma)",
         SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"Scales_XAmount\": [4,]}", "p.json:1:52",
         "a ',' before the ']'", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\" \"Seed\": 1}", "p.json:1:30", "expected a ',' or a '}'",
         SQ_ERR_PARSE},
        {"{\"format\" \"squama-preset/1\"}", "p.json:1:11", "expected a ':' after the key", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"Seed\": tru}", "p.json:1:39", "expected a value", SQ_ERR_PARSE},
        /* what cJSON would take: a leading zero, a bare '.', a NUL escape that cuts the string */
        {"{\"format\": \"squama-preset/1\",\n \"Seed\": 010}", "p.json:2:10", "a number with a leading zero",
         SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"Spots_Scale\": 1.}", "p.json:1:48",
         "a number needs digits after its '.'", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"Spots_Scale\": -}", "p.json:1:46", "a '-' without digits",
         SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"Spots_Scale\": 1e}", "p.json:1:48",
         "digits in its exponent", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"name\": \"a\\u0000b\"}", "p.json:1:41",
         "\\u0000 (a NUL character) inside a string", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"name\": \"\\ud800x\"}", "p.json:1:40",
         "a high surrogate", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"name\": \"\\udc00\"}", "p.json:1:40",
         "a lone low surrogate", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"name\": \"\\x\"}", "p.json:1:40", "an unknown escape",
         SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"name\": \"a\nb\"}", "p.json:1:41", "a control character",
         SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"name\": \"abc", "p.json:1:42",
         "at the end of the text (unfinished?): the text ends inside a string", SQ_ERR_PARSE},
        /* a byte order mark is skipped (and takes no column); CR alone ends a line; an
         * unfinished string ending in a backslash, or in a character of several bytes, is
         * named at its last character; the text quoted stops before a control byte */
        {"\xEF\xBB\xBF{\"format\": \"squama-preset/1\",}", "p.json:1:30", "a trailing comma", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\",\r\"Seed\": 01}", "p.json:2:9", "a leading zero", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"name\": \"abc\\", "p.json:1:43",
         "at the end of the text (unfinished?): the text ends inside a string", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"name\": \"ab\xc3\xa9", "p.json:1:42",
         "at the end of the text (unfinished?): the text ends inside a string", SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\", \"Seed\": x\x1b[31m}", "p.json:1:39",
         "expected a value (a string, a number, an object, an array, true, false or null), at \"x\"", SQ_ERR_PARSE},
        /* columns count characters, not bytes */
        {"{\"name\": \"caf\xc3\xa9\", \"format\": \"squama-preset/1\",}", "p.json:1:46", "a trailing comma",
         SQ_ERR_PARSE},
        {"{\"format\": \"squama-preset/1\"} {}", "p.json:1:31", "unexpected text after",
         SQ_ERR_PARSE},
        /* meta keys */
        {"{\"format\": \"squama-preset/1\", \"name\": 3}", "p.json:1",
         "\"name\" must be a string", SQ_ERR_INVALID},
        /* text that is not UTF-8: Latin-1, an overlong '/', a surrogate, a cut sequence */
        {"{\"format\": \"squama-preset/1\", \"name\": \"caf\xe9\"}", "p.json:1",
         "\"name\" is not UTF-8 text (a stray byte 0xE9 at its byte 3)", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"notes\": \"a\xc0\xaf" "b\"}", "p.json:1",
         "\"notes\" is not UTF-8 text (a stray byte 0xC0 at its byte 1)", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"name\": \"\xed\xa0\x80\"}", "p.json:1",
         "not UTF-8 text (a stray byte 0xED at its byte 0)", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"name\": \"x\xe2\x82\"}", "p.json:1",
         "not UTF-8 text (a stray byte 0xE2 at its byte 1)", SQ_ERR_INVALID},
        /* cellular automaton as text: the descriptor's own line */
        {"{\"format\": \"squama-preset/1\",\n\"CA_Descriptor\": \"0 1\\nrectangular\\n0\\n6\\n11 x\"}",
         "p.json:2, CA_Descriptor text line:5", "rectangular rules have 4 bits", SQ_ERR_INVALID},
        /* cellular automaton as an object */
        {"{\"format\": \"squama-preset/1\", \"CA_Descriptor\": {\"initial\": \"01\", \"typ\": 1}}",
         "p.json:1", "unknown key \"typ\"", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"CA_Descriptor\": {\"initial\": \"01\"}}",
         "p.json:1", "needs the keys initial, type, epochs and rules", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"CA_Descriptor\": {\"initial\": [0, 2], "
         "\"type\": \"rectangular\", \"epochs\": 2, \"rules\": [\"1000 x\"]}}",
         "p.json:1", "must hold only 0 and 1", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"CA_Descriptor\": {\"initial\": \"0110\", "
         "\"type\": \"rectangular\", \"epochs\": 6, \"rules\": [\"1000 2\"]}}",
         "p.json:1", "the rules cover 2 epochs but 5 rows", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"CA_Descriptor\": 5}", "p.json:1",
         "descriptor text (a string) or an object", SQ_ERR_INVALID},
        /* pattern layers: the layer's index and the key's line inside it */
        {"{\"format\": \"squama-preset/1\",\n\"Pattern_Layers\": [\n {\"Pattern_Type\": \"spots\"},\n"
         " {\"Pattern_Type\": \"spots\",\n  \"Spots_Tilling\": 2}]}",
         "p.json:5",
         "Pattern_Layers[1] has an unknown key \"Spots_Tilling\" (did you mean \"Spots_Tiling\"?)",
         SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Scales_XAmount\": 4,\n\"Pattern_Layers\": [\n"
         " {\"Pattern_Type\": \"spots\",\n  \"Scales_XAmount\": 4}]}",
         "p.json:4", "\"Scales_XAmount\" (group scales) cannot be set in Pattern_Layers[0]",
         SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Pattern_Layers\": [{}, {}, {}, {}]}", "p.json:1",
         "\"Pattern_Layers\" has 4 layers; at most 3 are allowed", SQ_ERR_LIMIT},
        {"{\"format\": \"squama-preset/1\",\n\"Pattern_Layers\": [{},\n{\"Layer_Blend\": \"darken\"}]}",
         "p.json:3",
         "\"Pattern_Layers[1].Layer_Blend\" must be one of normal, multiply, screen, overlay; "
         "got the string \"darken\"",
         SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\",\n\"Pattern_Layers\": [\n{\"Layer_Opacity\": 1.5}]}",
         "p.json:3", "\"Pattern_Layers[0].Layer_Opacity\" is 1.5, outside its range [0, 1]",
         SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\",\n\"Pattern_Layers\": [{},\n\n \"spots\"]}", "p.json:4",
         "Pattern_Layers[1] must be an object of pattern parameters", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Pattern_Layers\": {\"Pattern_Type\": \"spots\"}}",
         "p.json:1", "\"Pattern_Layers\" must be an array of layer objects, got an object",
         SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\", \"Layer_Opacity\": 0.5}", "p.json:1",
         "\"Layer_Opacity\" belongs inside a layer of \"Pattern_Layers\"", SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\",\n\"Pattern_Layers\": [{\"Spots_Scale\": 1,\n"
         "\"Spots_Scale\": 2}]}",
         "p.json:3", "Pattern_Layers[0] has the key \"Spots_Scale\" twice", SQ_ERR_INVALID},
        /* the same key at the top level and in a layer: the layer's line is named */
        {"{\"format\": \"squama-preset/1\", \"Spots_Scale\": 1,\n\"Pattern_Layers\": [\n"
         "{\"Spots_Scale\": 1}, {\"Pattern_Type\": \"spots\",\n\"Spots_Scale\": \"big\"}]}",
         "p.json:4", "\"Pattern_Layers[1].Spots_Scale\" must be a number in [0, 8]",
         SQ_ERR_INVALID},
        {"{\"format\": \"squama-preset/1\",\n\"Pattern_Layers\": [{\"Pattern_Type\": \"other_simple\",\n"
         "\"CA_Descriptor\": \"0 1\\nrectangular\\n0\\n6\\n11 x\"}]}",
         "p.json:3, Pattern_Layers[0].CA_Descriptor text line:5",
         "rectangular rules have 4 bits", SQ_ERR_INVALID},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        SqParams p;
        SqError err;
        SqStatus st = parse(cases[i].text, &p, &err);
        if (st != cases[i].st)
            fail_msg("case %zu: status %d, want %d (%s | %s)", i, st, cases[i].st, err.what,
                     err.where);
        if (strcmp(err.where, cases[i].where) != 0)
            fail_msg("case %zu: where \"%s\", want \"%s\" (%s)", i, err.where, cases[i].where,
                     err.what);
        assert_contains(err.what, cases[i].what);
    }
}

static void nul_byte_size_and_key_limits(void **state)
{
    (void)state;
    SqParams p;
    SqError err;
    const char nul[] = "{\"format\": \"squama-preset/1\"\0}";
    assert_int_equal(sq_preset_parse(nul, sizeof nul - 1, "p.json", &p, NULL, &err),
                     SQ_ERR_PARSE);
    assert_contains(err.what, "NUL byte");
    assert_string_equal(err.where, "p.json:1:29");
    /* a preset saved with a byte order mark loads */
    assert_int_equal(parse("\xEF\xBB\xBF{\"format\": \"squama-preset/1\", \"Seed\": 4}", &p, &err), SQ_OK);
    assert_int_equal(p.Seed, 4);

    /* nesting: 1000 deep is JSON (not a preset), 1001 deep is refused where it passes 1000 */
    char deep[2 * 1001 + 1];
    for (int d = 1000; d <= 1001; d++) {
        memset(deep, '[', (size_t)d);
        memset(deep + d, ']', (size_t)d);
        assert_int_equal(sq_preset_parse(deep, 2 * (size_t)d, "p.json", &p, NULL, &err), d == 1000 ? SQ_ERR_INVALID : SQ_ERR_PARSE);
        assert_contains(err.what, d == 1000 ? "a preset must be a JSON object" : "nested more than 1000 deep");
        if (d == 1001)
            assert_string_equal(err.where, "p.json:1:1001");
    }

    /* many keys: refused without quadratic work */
    size_t cap = 64 * 2000;
    char *big = malloc(cap);
    size_t k = (size_t)snprintf(big, cap, "{\"format\": \"squama-preset/1\"");
    for (int i = 0; i < 1500; i++)
        k += (size_t)snprintf(big + k, cap - k, ", \"k%d\": 1", i);
    snprintf(big + k, cap - k, "}");
    assert_int_equal(parse(big, &p, &err), SQ_ERR_LIMIT);
    assert_contains(err.what, "more than 1000 keys");

    /* notes longer than the buffer */
    k = (size_t)snprintf(big, cap, "{\"format\": \"squama-preset/1\", \"notes\": \"");
    memset(big + k, 'a', 3000);
    snprintf(big + k + 3000, cap - k - 3000, "\"}");
    assert_int_equal(parse(big, &p, &err), SQ_ERR_LIMIT);
    assert_contains(err.what, "\"notes\" is longer than 2047 bytes");
    free(big);

    assert_int_equal(sq_preset_parse("{}", (size_t)SQ_PRESET_MAX_BYTES + 1, "p.json", &p, NULL,
                                     &err),
                     SQ_ERR_LIMIT);
}

static void missing_file_and_directory(void **state)
{
    (void)state;
    SqParams p;
    SqError err;
    assert_int_equal(sq_preset_load("/nonexistent/p.json", &p, NULL, &err), SQ_ERR_IO);
    assert_string_equal(err.where, "/nonexistent/p.json");
    assert_contains(err.what, "No such file");
    char dir[1024];
    assert_int_not_equal(sq_preset_load(src_path(dir, sizeof dir, "presets"), &p, NULL, &err),
                         SQ_OK);
}

/* A deterministic generator for random parameter sets. */
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static void random_field(void *f, const SqParamSpec *s)
{
    double lo = s->min, hi = s->max;
    switch (s->type) {
    case SQ_PT_FLOAT:
        /* awkward doubles: full 53-bit mantissas, tiny values, exact ends */
        *(double *)f = rnd() < 0.1 ? (rnd() < 0.5 ? lo : hi) : lo + (hi - lo) * rnd();
        break;
    case SQ_PT_INT:
    case SQ_PT_BOOL:
    case SQ_PT_ENUM:
    {
        double v = lo + floor((hi - lo + 1) * rnd());
        *(int *)f = (int)(v > hi ? hi : v);
        break;
    }
    case SQ_PT_VEC2:
    case SQ_PT_COLOR:
        for (int c = 0; c < sq_param_components(s->type); c++)
            ((double *)f)[c] = lo + (hi - lo) * rnd() * rnd();
        break;
    case SQ_PT_CA: {
        SqCa *ca = f;
        ca->ncells = 2 + (int)(rnd() * 40);
        for (int c = 0; c < ca->ncells; c++)
            ca->cells[c] = rnd() < 0.5;
        ca->type = rnd() < 0.5 ? SQ_CA_RECTANGULAR : SQ_CA_TRIANGULAR;
        ca->shift_mirror = (int)(rnd() * 7) - 3;
        ca->epochs = 1 + (int)(rnd() * 20);
        ca->nrules = 1 + (int)(rnd() * 4);
        for (int r = 0; r < ca->nrules; r++) {
            ca->rules[r].bits = (uint8_t)(rnd() * (1 << sq_ca_rule_bits(ca->type)));
            ca->rules[r].epochs = 1 + (int)(rnd() * 3);
        }
        ca->rules[ca->nrules - 1].epochs = SQ_CA_REMAINING;
        break;
    }
    case SQ_PT_LAYERS: { /* every layer field random, through the same table rows */
        SqPatternLayers *ls = f;
        size_t n;
        const SqParamSpec *t = sq_params_table(&n);
        ls->count = (int)(rnd() * (SQ_MAX_PATTERN_LAYERS + 1));
        for (int k = 0; k < ls->count; k++)
            for (size_t i = 0; i < n; i++)
                if (sq_param_in_layer(&t[i]))
                    random_field(sq_param_layer_ptr(&ls->layer[k], &t[i]), &t[i]);
        break;
    }
    }
}

static void random_params(SqParams *p)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    sq_params_default(p);
    for (size_t i = 0; i < n; i++)
        if (!(t[i].flags & SQ_PF_LAYER))
            random_field(sq_param_ptr(p, &t[i]), &t[i]);
    p->Spots_Tiling = 0.1 + 0.2; /* 0.30000000000000004: needs 17 digits */
    p->Spots_Scale = 1e-300;
    p->Pattern_Warp_Small = 1.0 / 3.0;
}

static void save_load_round_trip_is_exact(void **state)
{
    (void)state;
    for (int iter = 0; iter < 200; iter++) {
        SqParams a, b;
        SqError err;
        random_params(&a);
        if (sq_params_validate(&a, &err) != SQ_OK)
            fail_msg("random params invalid: %s (%s)", err.what, err.where);
        SqPresetInfo info = {.name = "round \"trip\"\n", .notes = "ünïcode \\ notes"};
        char *text = sq_preset_to_json(&a, &info, &err);
        assert_non_null(text);
        SqPresetInfo back;
        if (sq_preset_parse(text, strlen(text), "rt.json", &b, &back, &err) != SQ_OK)
            fail_msg("iteration %d: %s (%s)\n%s", iter, err.what, err.where, text);
        if (!sq_params_equal(&a, &b))
            fail_msg("iteration %d: values changed through save/load", iter);
        assert_string_equal(back.name, info.name);
        assert_string_equal(back.notes, info.notes);
        /* saving again gives the same text */
        char *again = sq_preset_to_json(&b, &back, &err);
        assert_string_equal(text, again);
        free(text);
        free(again);
    }
}

static void saved_text_is_readable(void **state)
{
    (void)state;
    SqParams p;
    SqError err;
    sq_params_default(&p);
    p.Spots_Tiling = 0.3;
    char *text = sq_preset_to_json(&p, NULL, &err);
    assert_non_null(text);
    assert_contains(text, "{\n  \"format\": \"squama-preset/1\",\n");
    assert_contains(text, "\n  \"Spots_Tiling\": 0.3,\n");
    assert_contains(text, "\"Background_Color\": [0.42, 0.36, 0.26, 1]");
    assert_contains(text, "\"Pattern_Type\": \"none\"");
    assert_contains(text, "\"rules\": [\"1110 1\", \"1100 1\", \"1000 x\"]");
    assert_null(strchr(text, '\t'));
    assert_int_equal(text[strlen(text) - 1], '\n');
    free(text);

    p.Spots_Tiling = 1000; /* invalid values are never written */
    assert_null(sq_preset_to_json(&p, NULL, &err));
    assert_string_equal(err.where, "Spots_Tiling");
}

static void load_preset(const char *path, void *ctx)
{
    (void)ctx;
    SqParams p;
    SqError err;
    if (sq_preset_load(path, &p, NULL, &err) != SQ_OK)
        fail_msg("%s: %s (%s)", path, err.what, err.where);
}

static void shipped_presets_validate(void **state)
{
    (void)state;
    char dir[1024];
    assert_true(for_each_file(src_path(dir, sizeof dir, "presets"), ".json", 1, load_preset,
                              NULL) >= 7);
}

/* The thesis' examples carry the values printed in the thesis. */
static void thesis_presets_hold_the_thesis_values(void **state)
{
    (void)state;
    char path[1024];
    SqParams p;
    SqError err;
    assert_int_equal(sq_preset_load(src_path(path, sizeof path,
                                             "presets/thesis/table_4_2_micrurus_altirostris.json"),
                                    &p, NULL, &err),
                     SQ_OK);
    assert_int_equal(p.Pattern_Type, SQ_PATTERN_TRANSVERSAL);
    assert_true(p.Transversal_BeginEnd[0][0] == 0.1 && p.Transversal_BeginEnd[0][1] == 0.9);
    assert_true(p.Transversal_BeginEnd[3][0] == 1.0 && p.Transversal_BeginEnd[3][1] == 1.0);

    assert_int_equal(sq_preset_load(src_path(path, sizeof path,
                                             "presets/thesis/table_4_5_spots_interleaved.json"),
                                    &p, NULL, &err),
                     SQ_OK);
    assert_true(p.Spots_Scale == 1.2 && p.Spots_Offset == 0.5 && p.Spots_RotationRandom == 10);
    assert_true(p.Spots_Interstice[0] == 0.7);

    assert_int_equal(sq_preset_load(src_path(path, sizeof path,
                                             "presets/thesis/d11_five_lined_skink.json"),
                                    &p, NULL, &err),
                     SQ_OK);
    assert_int_equal(p.Longitudinal_NumberOfStripes, 5);
    assert_true(p.Longitudinal_StripesWidth == 0.193704);
    assert_int_equal(p.Scales_XAmount, 17);
    assert_int_equal(p.Scales_YAmount, 47);
    assert_true(p.ScaleShape_Contrast == 0.421545);
    assert_true(p.Normal_Intensity == 2.779079);

    assert_int_equal(sq_preset_load(src_path(path, sizeof path,
                                             "presets/thesis/figure_4_9_other_simple.json"),
                                    &p, NULL, &err),
                     SQ_OK);
    SqCa ca;
    assert_int_equal(sq_ca_load(src_path(path, sizeof path,
                                         "presets/thesis/ca/figure_4_9_example.ca"),
                                &ca, &err),
                     SQ_OK);
    assert_true(sq_ca_equal(&p.CA_Descriptor, &ca));
}

/* Inputs that once crashed the fuzzer stay fixed: each must parse or fail cleanly. */
static void replay(const char *path, void *ctx)
{
    (void)ctx;
    SqParams p;
    SqError err;
    size_t n = 0;
    char *data = read_exact(path, &n);
    assert_non_null(data);
    SqStatus st = sq_preset_parse(data, n, path, &p, NULL, &err);
    free(data);
    if (st == SQ_OK)
        assert_int_equal(sq_params_validate(&p, &err), SQ_OK);
    else
        assert_true(err.what[0] != '\0');
}

static void fuzz_regressions(void **state)
{
    (void)state;
    char dir[1024];
    if (for_each_file(src_path(dir, sizeof dir, "tests/fuzz/regressions/preset"), "", 0, replay,
                      NULL) < 0)
        skip();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(only_format_gives_defaults),
        cmocka_unit_test(values_of_every_type),
        cmocka_unit_test(every_error_named_with_its_place),
        cmocka_unit_test(pattern_layers_parse),
        cmocka_unit_test(nul_byte_size_and_key_limits),
        cmocka_unit_test(missing_file_and_directory),
        cmocka_unit_test(save_load_round_trip_is_exact),
        cmocka_unit_test(saved_text_is_readable),
        cmocka_unit_test(shipped_presets_validate),
        cmocka_unit_test(thesis_presets_hold_the_thesis_values),
        cmocka_unit_test(fuzz_regressions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
