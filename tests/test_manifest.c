/* cli/manifest.c: squama batch's manifest, columns by header name, rows checked; and
 * cli/batch_done.c, a finished row's done.json read back. */
#include <math.h>

#include "sq_test.h"

#include "batch.h"
#include "manifest.h"
#include "squama/io.h"
#include "squama/params.h"

static CliManifest parse_ok(const char *text, const char *path)
{
    CliManifest m;
    SqError err;
    if (cli_manifest_parse(text, strlen(text), path, &m, &err) != SQ_OK)
        fail_msg("%s (%s)", err.what, err.where);
    return m;
}

static void columns_by_name_and_paths(void **state)
{
    (void)state;
    CliManifest m = parse_ok("Species, FILE ,ID,pattern_category_guess,Mask,other,Body_Line\n"
                             "\"Boa, constrictor\",p/a.jpg,a1,Transversal,m/a.png,x,l/a.json\n"
                             "Philodryas,/abs/b.jpg,b.2,other simple,,y,\n"
                             "Short,c.jpg,c3\n",
                             "runs/m.csv");
    assert_int_equal(m.nrows, 3);
    const CliManifestRow *r = m.rows;
    assert_null(r[0].error);
    assert_string_equal(r[0].id, "a1");
    assert_string_equal(r[0].photo, "runs/p/a.jpg");
    assert_string_equal(r[0].mask, "runs/m/a.png");
    assert_string_equal(r[0].body_line, "runs/l/a.json");
    assert_string_equal(r[0].species, "Boa, constrictor");
    assert_int_equal(r[0].expected, SQ_PATTERN_TRANSVERSAL);
    assert_string_equal(r[1].photo, "/abs/b.jpg");
    assert_null(r[1].mask);
    assert_null(r[1].body_line);
    assert_int_equal(r[1].expected, SQ_PATTERN_OTHER_SIMPLE);
    assert_null(r[2].error); /* missing trailing fields are empty */
    assert_int_equal(r[2].expected, -1);
    assert_int_equal(r[2].line, 4);
    cli_manifest_free(&m);
    m = parse_ok("id,photo\nx,y.jpg\n", "m.csv"); /* no folder: as written */
    assert_string_equal(m.rows[0].photo, "y.jpg");
    cli_manifest_free(&m);
    cli_manifest_free(NULL);
}

static void bad_rows_carry_their_error(void **state)
{
    (void)state;
    CliManifest m = parse_ok("id,photo,expected\n"
                             "a,a.jpg,\n"
                             ",b.jpg,\n"
                             "a,c.jpg,\n"
                             "../x,d.jpg,\n"
                             "e,,\n"
                             "f,f.jpg,zigzag\n"
                             "g,g.jpg,,extra\n"
                             "index.html,h.jpg,\n"
                             "a,i.jpg,\n",
                             "m.csv");
    assert_int_equal(m.nrows, 9);
    const char *want[] = {NULL, "no id", "the id a is repeated (first on line 2)", "cannot name a folder",
                          "no photo", "\"zigzag\"", "the row has 4 fields, the header 3", "cannot name a folder",
                          "the id a is repeated (first on line 2)"};
    for (int i = 0; i < 9; i++) {
        if (!want[i])
            assert_null(m.rows[i].error);
        else if (!m.rows[i].error)
            fail_msg("row %d has no error, want \"%s\"", i, want[i]);
        else
            assert_contains(m.rows[i].error, want[i]);
    }
    cli_manifest_free(&m);
}

static void malformed_manifests(void **state)
{
    (void)state;
    static const struct { const char *text, *what, *where; } cases[] = {
        {"", "the manifest is empty", "m.csv:1"},
        {"\n\n", "the manifest is empty", "m.csv:1"},
        {"a1,a.jpg\nb1,b.jpg\n", "no 'id' column", "m.csv:1"},
        {"id,picture\na,a.jpg\n", "no 'photo' (or 'file') column", "m.csv:1"},
        {"id,photo\na,\"a.jpg\nb,b.jpg\n", "unterminated quoted field", "m.csv:2"},
        {"id,photo,ID\na,a.jpg,b\n", "names its id column twice", "m.csv:1"},
        {"id,photo, Species ,species\na,a.jpg,x,y\n", "names its species column twice", "m.csv:1"},
        /* two names of one role: which holds the photos? */
        {"id,photo,image\na,a.jpg,b.jpg\n", "names its photo column twice, \"photo\" and \"image\": keep one", "m.csv:1"},
        {"file,id,category,pattern_category_guess\na.jpg,a,spots,bands\n",
         "names its expected column twice, \"category\" and \"pattern_category_guess\"", "m.csv:1"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        CliManifest m;
        SqError err;
        assert_int_not_equal(cli_manifest_parse(cases[i].text, strlen(cases[i].text), "m.csv", &m, &err), SQ_OK);
        assert_contains(err.what, cases[i].what);
        assert_string_equal(err.where, cases[i].where);
        assert_null(m.rows);
    }
    CliManifest m;
    SqError err;
    char path[1024];
    assert_int_equal(cli_manifest_read(tmp_path(path, sizeof path, "no-manifest.csv"), &m, &err), SQ_ERR_IO);
}

static void ids_and_categories(void **state)
{
    (void)state;
    assert_true(cli_manifest_id_ok("RS01"));
    assert_true(cli_manifest_id_ok("boa_constrictor__br0009.v2-b"));
    assert_false(cli_manifest_id_ok(""));
    assert_false(cli_manifest_id_ok(".tmp-x"));
    assert_false(cli_manifest_id_ok("a/b"));
    assert_false(cli_manifest_id_ok("a b"));
    assert_false(cli_manifest_id_ok("catalogue.csv"));
    char longid[80];
    memset(longid, 'a', 65);
    longid[65] = '\0';
    assert_false(cli_manifest_id_ok(longid));
    longid[64] = '\0';
    assert_true(cli_manifest_id_ok(longid));
    assert_int_equal(cli_manifest_category("none"), SQ_PATTERN_NONE);
    assert_int_equal(cli_manifest_category("Other-Simple"), SQ_PATTERN_OTHER_SIMPLE);
    assert_int_equal(cli_manifest_category("COMPLEX"), SQ_PATTERN_COMPLEX);
    assert_int_equal(cli_manifest_category("stripes"), -1);
    assert_int_equal(cli_manifest_category(""), -1);
}

static int parse_done(const char *text, BatchDone *d)
{
    return batch_parse_done(text, strlen(text), d);
}

static void done_records_read_back(void **state)
{
    (void)state;
    BatchDone *d = malloc(sizeof *d);
    assert_non_null(d);
    char path[1024], *text;
    size_t n;
    text = read_exact(src_path(path, sizeof path, "tests/fuzz/regressions/done/ok.json"), &n);
    assert_non_null(text);
    assert_int_equal(batch_parse_done(text, n, d), 1);
    free(text);
    assert_string_equal(d->id, "bands");
    assert_int_equal(d->line, 2);
    assert_string_equal(d->photo_digest, "0f3a9c1d2e4b5a67");
    assert_string_equal(d->mask_digest, "89abcdef01234567");
    assert_string_equal(d->body_line, "/data/photos/bands_line.json");
    assert_string_equal(d->line_digest, "76543210fedcba98");
    assert_true(d->has_settings);
    assert_string_equal(d->settings, "budget=0 evals=1500 seed=1 categories=0 size=256 work-size=1024");
    assert_int_equal(d->r.status, BATCH_OK);
    assert_int_equal(d->r.fitted, SQ_PATTERN_TRANSVERSAL);
    assert_int_equal(d->expected, SQ_PATTERN_TRANSVERSAL);
    assert_int_equal(d->r.evals, 1480);
    assert_true(d->r.resumed);
    for (int k = 0; k < SQ_OBJ_COUNT; k++)
        assert_true(isfinite(d->r.obj[k]));
    assert_true(fabs(d->r.obj[1] - 0.31) < 1e-12);
    /* an older record: no digests, no settings (matched by path) */
    assert_int_equal(parse_done("{\"format\":\"squama-batch-row/1\",\"id\":\"gone\",\"photo\":\"p.jpg\","
                                "\"status\":\"error\",\"error\":\"cannot open\"}", d), 1);
    assert_int_equal(d->r.status, BATCH_ERROR);
    assert_string_equal(d->r.error, "cannot open");
    assert_string_equal(d->photo_digest, "");
    assert_false(d->has_settings);
    /* a digest of the wrong length is no digest; an unknown category or status, another
     * format, a missing id or photo: not a record */
    assert_int_equal(parse_done("{\"format\":\"squama-batch-row/1\",\"id\":\"a\",\"photo\":\"p\","
                                "\"photo_digest\":\"123\",\"status\":\"error\"}", d), 1);
    assert_string_equal(d->photo_digest, "");
    assert_int_equal(parse_done("{\"format\":\"squama-batch-row/1\",\"id\":\"a\",\"photo\":\"p\","
                                "\"status\":\"ok\",\"category\":\"zigzag\",\"objectives\":{}}", d), 0);
    assert_int_equal(parse_done("{\"format\":\"squama-batch-row/1\",\"id\":\"a\",\"photo\":\"p\","
                                "\"status\":\"running\"}", d), 0);
    assert_int_equal(parse_done("{\"format\":\"squama-batch-row/2\",\"id\":\"a\",\"photo\":\"p\","
                                "\"status\":\"error\"}", d), 0);
    assert_int_equal(parse_done("{\"format\":\"squama-batch-row/1\",\"photo\":\"p\",\"status\":\"error\"}", d), 0);
    assert_int_equal(parse_done("{\"format\":\"squama-batch-row/1\",\"id\":\"a\"", d), 0);
    assert_int_equal(parse_done("{\"format\":\"squama-batch-row/1\",\"id\":\"../x\",\"photo\":\"p\","
                                "\"status\":\"error\"}", d), 0);
    free(d);
}

static void replay_done(const char *path, void *ctx)
{
    (void)ctx;
    size_t n;
    char *data = read_exact(path, &n);
    assert_non_null(data);
    BatchDone *d = malloc(sizeof *d);
    assert_non_null(d);
    if (batch_parse_done(data, n, d))
        assert_true(d->id[0] && (d->r.status != BATCH_OK || d->r.fitted >= 0));
    free(d);
    free(data);
}

static void replay(const char *path, void *ctx)
{
    (void)ctx;
    size_t n;
    char *data = read_exact(path, &n);
    assert_non_null(data);
    CliManifest m;
    SqError err;
    if (cli_manifest_parse(data, n, path, &m, &err) == SQ_OK) {
        for (int i = 0; i < m.nrows; i++)
            assert_true(m.rows[i].error || (cli_manifest_id_ok(m.rows[i].id) && m.rows[i].photo));
        cli_manifest_free(&m);
    } else {
        assert_true(err.what[0] != '\0' && err.where[0] != '\0');
    }
    free(data);
}

static void fuzz_regressions(void **state)
{
    (void)state;
    char dir[1024];
    if (for_each_file(src_path(dir, sizeof dir, "tests/fuzz/regressions/manifest"), "", 0, replay, NULL) < 0 ||
        for_each_file(src_path(dir, sizeof dir, "tests/fuzz/regressions/done"), "", 0, replay_done, NULL) < 0)
        skip();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(columns_by_name_and_paths),
        cmocka_unit_test(bad_rows_carry_their_error),
        cmocka_unit_test(malformed_manifests),
        cmocka_unit_test(ids_and_categories),
        cmocka_unit_test(done_records_read_back),
        cmocka_unit_test(fuzz_regressions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
