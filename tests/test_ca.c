/* Cellular-automaton descriptors: the thesis' examples parse, every error names its
 * line, and the canonical text reads back identically. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>

#include "sq_test.h"
#include "squama/ca.h"

static SqStatus parse(const char *text, SqCa *ca, SqError *err)
{
    return sq_ca_parse(text, strlen(text), "t.ca", ca, err);
}

static void figure_4_9_example(void **state)
{
    (void)state;
    const char *text = "0 0 1 1 1 1 0 0 //Initial values\n"
                       "rectangular //Automaton type\n"
                       "0 //Shift mirror\n"
                       "6 //Epochs\n"
                       "1110 1 //First transition rule for 1 epoch\n"
                       "1100 1 //Second transition rule for 1 epoch\n"
                       "1000 x //Third transition rule for remaining epochs\n";
    SqCa ca;
    SqError err;
    assert_int_equal(parse(text, &ca, &err), SQ_OK);
    assert_int_equal(ca.ncells, 8);
    static const uint8_t row[] = {0, 0, 1, 1, 1, 1, 0, 0};
    assert_memory_equal(ca.cells, row, 8);
    assert_int_equal(ca.type, SQ_CA_RECTANGULAR);
    assert_int_equal(ca.shift_mirror, 0);
    assert_int_equal(ca.epochs, 6);
    assert_int_equal(ca.nrules, 3);
    assert_int_equal(ca.rules[0].bits, 0xE);
    assert_int_equal(ca.rules[0].epochs, 1);
    assert_int_equal(ca.rules[1].bits, 0xC);
    assert_int_equal(ca.rules[2].bits, 0x8);
    assert_int_equal(ca.rules[2].epochs, SQ_CA_REMAINING);
}

static void triangular_blank_lines_crlf_and_packed_bits(void **state)
{
    (void)state;
    SqCa ca;
    SqError err;
    assert_int_equal(parse("\r\n1110111\r\n\r\ntriangular\r\n  3  \r\n6\r\n100 2\r\n000 X\r\n",
                           &ca, &err),
                     SQ_OK);
    assert_int_equal(ca.ncells, 7);
    assert_int_equal(ca.type, SQ_CA_TRIANGULAR);
    assert_int_equal(ca.shift_mirror, 3);
    assert_int_equal(ca.rules[0].bits, 4);
    assert_int_equal(ca.rules[1].epochs, SQ_CA_REMAINING);
    assert_int_equal(sq_ca_rule_bits(ca.type), 3);
}

/* One test per error, each naming its line. */
static void errors_name_their_line(void **state)
{
    (void)state;
    static const struct { const char *text, *where, *what; SqStatus st; } cases[] = {
        {"0 0 2 1\nrectangular\n0\n6\n1110 x\n", "t.ca:1", "0s and 1s", SQ_ERR_PARSE},
        {"1\nrectangular\n0\n6\n1110 x\n", "t.ca:1", "at least 2 cells", SQ_ERR_INVALID},
        {"0 1\nhexagonal\n0\n6\n1110 x\n", "t.ca:2", "\"rectangular\" or \"triangular\"", SQ_ERR_INVALID},
        {"0 1\nrectangular\nnone\n6\n1110 x\n", "t.ca:3", "shift mirror", SQ_ERR_INVALID},
        {"0 1\nrectangular\n0\n0\n1110 x\n", "t.ca:4", "epochs must be", SQ_ERR_INVALID},
        {"0 1\nrectangular\n0\n2000\n1110 x\n", "t.ca:4", "[1, 1024]", SQ_ERR_INVALID},
        {"0 1\nrectangular\n0\n6\n110 x\n", "t.ca:5", "rectangular rules have 4 bits", SQ_ERR_INVALID},
        {"0 1\ntriangular\n0\n6\n1110 x\n", "t.ca:5", "triangular rules have 3 bits", SQ_ERR_INVALID},
        {"0 1\nrectangular\n0\n6\n1120 x\n", "t.ca:5", "rule bits must be 0 or 1", SQ_ERR_PARSE},
        {"0 1\nrectangular\n0\n6\n1110\n", "t.ca:5", "needs an epoch count", SQ_ERR_PARSE},
        {"0 1\nrectangular\n0\n6\n1110 0\n", "t.ca:5", "'x' or an integer", SQ_ERR_INVALID},
        {"0 1\nrectangular\n0\n6\n1110 1 2\n", "t.ca:5", "unexpected text", SQ_ERR_PARSE},
        {"0 1\nrectangular\n0\n6\n1110 x\n1100 1\n", "t.ca:6", "never used", SQ_ERR_INVALID},
        {"0 1\nrectangular\n0\n6\n1110 2\n", "t.ca", "cover 2 epochs but 5 rows", SQ_ERR_INVALID},
        {"0 1\nrectangular\n0\n", "t.ca:3", "ends before the number of epochs", SQ_ERR_PARSE},
        {"", "t.ca", "ends before the initial values", SQ_ERR_PARSE},
        {"// only a comment\n\n", "t.ca:2", "ends before the initial values", SQ_ERR_PARSE},
        {"0 1\nrectangular\n0\n6\n", "t.ca:4", "ends before a transition rule", SQ_ERR_PARSE},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        SqCa ca;
        SqError err;
        SqStatus st = parse(cases[i].text, &ca, &err);
        if (st != cases[i].st)
            fail_msg("case %zu: status %d, want %d (%s)", i, st, cases[i].st, err.what);
        assert_string_equal(err.where, cases[i].where);
        assert_contains(err.what, cases[i].what);
    }
}

static void nul_byte_and_limits(void **state)
{
    (void)state;
    SqCa ca;
    SqError err;
    const char text[] = "0 1\nrect\0angular\n0\n6\n1110 x\n";
    assert_int_equal(sq_ca_parse(text, sizeof text - 1, "t.ca", &ca, &err), SQ_ERR_PARSE);
    assert_string_equal(err.where, "t.ca:2");

    char *row = malloc(2 * SQ_CA_MAX_CELLS + 64);
    size_t k = 0;
    for (int i = 0; i <= SQ_CA_MAX_CELLS; i++) {
        row[k++] = '1';
        row[k++] = ' ';
    }
    memcpy(row + k, "\nrectangular\n0\n6\n1110 x\n", 25);
    assert_int_equal(sq_ca_parse(row, strlen(row), "t.ca", &ca, &err), SQ_ERR_LIMIT);
    assert_contains(err.what, "more than 512 cells");
    free(row);
}

static void format_round_trip(void **state)
{
    (void)state;
    SqCa a, b;
    SqError err;
    assert_int_equal(parse("0 0 1 1 1 0 0 0 0 1 1 1 0 0 0 0 1 1 1 0 0\ntriangular\n-2\n6\n110 2\n100 x\n",
                           &a, &err),
                     SQ_OK);
    char text[1024];
    size_t n = sq_ca_format(&a, text, sizeof text);
    assert_int_equal(n, strlen(text));
    assert_string_equal(text, "0 0 1 1 1 0 0 0 0 1 1 1 0 0 0 0 1 1 1 0 0\ntriangular\n-2\n6\n110 2\n100 x\n");
    assert_int_equal(parse(text, &b, &err), SQ_OK);
    assert_true(sq_ca_equal(&a, &b));
    b.rules[1].bits = 0;
    assert_false(sq_ca_equal(&a, &b));
    /* a too-small buffer reports the size it needs and stays terminated */
    char small[5];
    assert_int_equal(sq_ca_format(&a, small, sizeof small), n);
    assert_int_equal(strlen(small), 4);
}

static void validate_in_memory(void **state)
{
    (void)state;
    SqCa ca;
    SqError err;
    assert_int_equal(parse("0 1 1 0\nrectangular\n0\n4\n1110 x\n", &ca, &err), SQ_OK);
    SqCa bad = ca;
    bad.rules[0].bits = 0x1F;
    assert_int_equal(sq_ca_validate(&bad, "x", &err), SQ_ERR_INVALID);
    bad = ca;
    bad.cells[0] = 2;
    assert_int_equal(sq_ca_validate(&bad, "x", &err), SQ_ERR_INVALID);
    bad = ca;
    bad.type = (SqCaType)7;
    assert_int_equal(sq_ca_validate(&bad, "x", &err), SQ_ERR_INVALID);
    bad = ca;
    bad.shift_mirror = 5000;
    assert_int_equal(sq_ca_validate(&bad, "x", &err), SQ_ERR_INVALID);
}

/* Every shipped descriptor (thesis §4.2.4, Appendices D and E) parses. */
static void load_descriptor(const char *path, void *ctx)
{
    (void)ctx;
    SqCa ca;
    SqError err;
    if (sq_ca_load(path, &ca, &err) != SQ_OK)
        fail_msg("%s: %s (%s)", path, err.what, err.where);
}

static void shipped_descriptors_parse(void **state)
{
    (void)state;
    char dir[1024];
    assert_true(for_each_file(src_path(dir, sizeof dir, "presets"), ".ca", 1, load_descriptor,
                              NULL) >= 9);
}

static void missing_file(void **state)
{
    (void)state;
    SqCa ca;
    SqError err;
    assert_int_equal(sq_ca_load("/nonexistent/x.ca", &ca, &err), SQ_ERR_IO);
    assert_string_equal(err.where, "/nonexistent/x.ca");
    assert_contains(err.what, "No such file");
}

/* Inputs that once crashed the fuzzer stay fixed: each must parse or fail cleanly. */
static void replay(const char *path, void *ctx)
{
    (void)ctx;
    SqCa ca;
    SqError err;
    size_t n = 0;
    char *data = read_exact(path, &n);
    assert_non_null(data);
    SqStatus st = sq_ca_parse(data, n, path, &ca, &err);
    free(data);
    if (st == SQ_OK)
        assert_int_equal(sq_ca_validate(&ca, "x", &err), SQ_OK);
    else
        assert_true(err.what[0] != '\0');
}

static void fuzz_regressions(void **state)
{
    (void)state;
    char dir[1024];
    if (for_each_file(src_path(dir, sizeof dir, "tests/fuzz/regressions/ca"), "", 0, replay,
                      NULL) < 0)
        skip();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(figure_4_9_example),
        cmocka_unit_test(triangular_blank_lines_crlf_and_packed_bits),
        cmocka_unit_test(errors_name_their_line),
        cmocka_unit_test(nul_byte_and_limits),
        cmocka_unit_test(format_round_trip),
        cmocka_unit_test(validate_in_memory),
        cmocka_unit_test(shipped_descriptors_parse),
        cmocka_unit_test(missing_file),
        cmocka_unit_test(fuzz_regressions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
