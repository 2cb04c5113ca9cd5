/* io/csv.c: RFC 4180 parsing, errors that name their line, and field quoting. */
#include "sq_test.h"

#include "squama/io.h"

static SqCsv parse_ok(const char *text)
{
    SqCsv csv;
    SqError err;
    size_t n = strlen(text);
    char *exact = malloc(n ? n : 1); /* no NUL after the text, as the fuzzer sees it */
    memcpy(exact, text, n);
    SqStatus st = sq_io_csv_parse(exact, n, "t.csv", &csv, &err);
    free(exact);
    if (st != SQ_OK)
        fail_msg("\"%s\" failed: %s (%s)", text, err.what, err.where);
    return csv;
}

static void parse_err(const char *text, const char *what, const char *where)
{
    SqCsv csv;
    SqError err;
    assert_int_not_equal(sq_io_csv_parse(text, strlen(text), "t.csv", &csv, &err), SQ_OK);
    assert_contains(err.what, what);
    assert_string_equal(err.where, where);
    assert_null(csv.records);
}

static void plain_records_crlf_and_bom(void **state)
{
    (void)state;
    SqCsv c = parse_ok("\xEF\xBB\xBFid,photo\r\na,b.jpg\r\n\r\nc,\n");
    assert_int_equal(c.nrecords, 3);
    assert_string_equal(c.records[0].fields[0], "id");
    assert_int_equal(c.records[1].line, 2);
    assert_string_equal(c.records[1].fields[1], "b.jpg");
    assert_int_equal(c.records[2].line, 4); /* the empty line is skipped, still counted */
    assert_int_equal(c.records[2].nfields, 2);
    assert_string_equal(c.records[2].fields[1], "");
    sq_io_csv_free(&c);
    c = parse_ok("x"); /* no final line break */
    assert_int_equal(c.nrecords, 1);
    assert_string_equal(c.records[0].fields[0], "x");
    sq_io_csv_free(&c);
    c = parse_ok("");
    assert_int_equal(c.nrecords, 0);
    sq_io_csv_free(&c);
    sq_io_csv_free(NULL);
}

static void quoted_fields(void **state)
{
    (void)state;
    SqCsv c = parse_ok("a,\"b, c\",\"say \"\"hi\"\"\"\n\"two\nlines\",\"\",z\nnext,1,2");
    assert_int_equal(c.nrecords, 3);
    assert_string_equal(c.records[0].fields[1], "b, c");
    assert_string_equal(c.records[0].fields[2], "say \"hi\"");
    assert_string_equal(c.records[1].fields[0], "two\nlines");
    assert_string_equal(c.records[1].fields[1], "");
    assert_int_equal(c.records[1].line, 2);
    assert_int_equal(c.records[2].line, 4); /* the quoted line break counts */
    sq_io_csv_free(&c);
}

static void errors_name_their_line(void **state)
{
    (void)state;
    parse_err("id,photo\na,\"b.jpg\n", "unterminated quoted field", "t.csv:2");
    parse_err("id,photo\n\na,\"b\"x\n", "closing quote must end the field", "t.csv:3");
    parse_err("id,photo\na,b\"c\n", "quote inside an unquoted field", "t.csv:2");
    SqCsv csv;
    SqError err;
    assert_int_equal(sq_io_csv_parse("a,b\nc\0d\n", 8, "t.csv", &csv, &err), SQ_ERR_PARSE);
    assert_string_equal(err.where, "t.csv:2");
    char many[4000] = "";
    for (int i = 0; i < 1100; i++)
        strcat(many, ",");
    assert_int_equal(sq_io_csv_parse(many, strlen(many), "t.csv", &csv, &err), SQ_ERR_LIMIT);
    char path[1024];
    assert_int_equal(sq_io_csv_read(tmp_path(path, sizeof path, "nonexistent.csv"), &csv, &err), SQ_ERR_IO);
}

static void append_quotes_what_needs_it(void **state)
{
    (void)state;
    char *buf = NULL;
    size_t len = 0, cap = 0;
    const char *fields[] = {"plain", "a,b", "say \"hi\"", "two\nlines", ""};
    for (int i = 0; i < 5; i++)
        assert_int_equal(sq_io_csv_append(&buf, &len, &cap, fields[i], i < 4 ? ',' : '\n'), 0);
    assert_string_equal(buf, "plain,\"a,b\",\"say \"\"hi\"\"\",\"two\nlines\",\n");
    assert_int_equal(len, strlen(buf));
    SqCsv c = parse_ok(buf); /* and back */
    assert_int_equal(c.nrecords, 1);
    for (int i = 0; i < 5; i++)
        assert_string_equal(c.records[0].fields[i], fields[i]);
    sq_io_csv_free(&c);
    free(buf);
}

/* A field that starts with a byte-order mark, first in the file, keeps its mark when read back
   (fuzz_manifest found the reader dropping it). */
static void a_leading_mark_survives(void **state)
{
    (void)state;
    char *buf = NULL;
    size_t len = 0, cap = 0;
    assert_int_equal(sq_io_csv_append(&buf, &len, &cap, "\xEF\xBB\xBFid", ','), 0);
    assert_int_equal(sq_io_csv_append(&buf, &len, &cap, "photo", '\n'), 0);
    SqCsv c = parse_ok(buf);
    assert_int_equal(c.nrecords, 1);
    assert_string_equal(c.records[0].fields[0], "\xEF\xBB\xBFid");
    sq_io_csv_free(&c);
    free(buf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plain_records_crlf_and_bom),
        cmocka_unit_test(quoted_fields),
        cmocka_unit_test(errors_name_their_line),
        cmocka_unit_test(append_quotes_what_needs_it),
        cmocka_unit_test(a_leading_mark_survives),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
