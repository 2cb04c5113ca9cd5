/* squama batch's manifest: columns by header name, paths resolved, every row checked. */
#define _POSIX_C_SOURCE 200809L

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "manifest.h"
#include "squama/io.h"
#include "squama/params.h"

static const char *const id_names[] = {CLI_MANIFEST_ID, NULL};
static const char *const photo_names[] = {CLI_MANIFEST_PHOTO, NULL};
static const char *const mask_names[] = {CLI_MANIFEST_MASK, NULL};
static const char *const line_names[] = {CLI_MANIFEST_LINE, NULL};
static const char *const expected_names[] = {CLI_MANIFEST_EXPECTED, NULL};
static const char *const species_names[] = {CLI_MANIFEST_SPECIES, NULL};

/* 1 when header field f, trimmed, is name (any case). */
static int is_column(const char *f, const char *name)
{
    while (*f == ' ' || *f == '\t')
        f++;
    size_t n = strlen(f);
    while (n > 0 && (f[n - 1] == ' ' || f[n - 1] == '\t'))
        n--;
    return n == strlen(name) && strncasecmp(f, name, n) == 0;
}

/* The column whose trimmed header equals (any case) one of names, or -1; -2 when two
 * columns do (which one holds the rows' values?), their headers then in two[0], two[1]. */
static int find_column(const SqCsvRecord *h, const char *const *names, const char *two[2])
{
    int found = -1;
    for (int i = 0; i < h->nfields; i++)
        for (const char *const *n = names; *n; n++)
            if (is_column(h->fields[i], *n)) {
                if (found >= 0) {
                    two[0] = h->fields[found];
                    two[1] = h->fields[i];
                    return -2;
                }
                found = i;
                break;
            }
    return found;
}

int cli_manifest_id_ok(const char *id)
{
    size_t n = strlen(id);
    if (n == 0 || n > CLI_ID_MAX)
        return 0;
    for (size_t i = 0; i < n; i++) {
        char c = id[i];
        int alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
        if (!alnum && (i == 0 || (c != '_' && c != '-' && c != '.')))
            return 0;
    }
    return strcmp(id, "catalogue.csv") != 0 && strcmp(id, "index.html") != 0;
}

int cli_manifest_category(const char *name)
{
    char norm[32];
    size_t n = strlen(name);
    if (n == 0 || n >= sizeof norm)
        return -1;
    for (size_t i = 0; i <= n; i++)
        norm[i] = name[i] == '-' || name[i] == ' ' ? '_' : name[i];
    for (int c = 0; c < SQ_PATTERN_COUNT; c++)
        if (strcasecmp(norm, sq_pattern_type_name(c)) == 0)
            return c;
    return -1;
}

static char *dup_printf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static char *dup_printf(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (s) {
        va_start(ap, fmt);
        vsnprintf(s, (size_t)n + 1, fmt, ap);
        va_end(ap);
    }
    return s;
}

/* rel against the folder of the manifest (dir, dirlen bytes; 0: the current folder). */
static char *resolve(const char *dir, size_t dirlen, const char *rel)
{
    if (rel[0] == '/' || dirlen == 0)
        return dup_printf("%s", rel);
    return dup_printf("%.*s/%s", (int)dirlen, dir, rel);
}

void cli_manifest_free(CliManifest *m)
{
    if (!m)
        return;
    for (int i = 0; i < m->nrows; i++) {
        free(m->rows[i].photo);
        free(m->rows[i].mask);
        free(m->rows[i].body_line);
        free(m->rows[i].error);
    }
    free(m->rows);
    if (m->csv_) {
        sq_io_csv_free(m->csv_);
        free(m->csv_);
    }
    memset(m, 0, sizeof *m);
}

typedef struct IdRow {
    const char *id;
    int row;
} IdRow;

/* by id, then by row */
static int by_id(const void *a, const void *b)
{
    const IdRow *x = a, *y = b;
    int c = strcmp(x->id, y->id);
    return c ? c : (x->row > y->row) - (x->row < y->row);
}

/* The manifest of a parsed CSV (csv is taken over, freed on error). */
static SqStatus from_csv(SqCsv *csv, const char *path, CliManifest *m, SqError *err)
{
    char where[SQ_ERROR_WHERE_MAX];
    if (csv->nrecords == 0) {
        sq_io_csv_free(csv);
        free(csv);
        snprintf(where, sizeof where, "%s:1", path);
        return sq_error_set(err, SQ_ERR_PARSE, where, "the manifest is empty: it needs a header naming an id and a photo column");
    }
    const SqCsvRecord *h = &csv->records[0];
    static const char *const *const names[] = {id_names, photo_names, mask_names, expected_names, species_names,
                                               line_names};
    static const char *const roles[] = {"id", "photo", "mask", "expected", "species", "body_line"};
    int cols[6];
    snprintf(where, sizeof where, "%s:%d", path, h->line);
    for (int k = 0; k < 6; k++) {
        const char *two[2] = {"", ""};
        cols[k] = find_column(h, names[k], two);
        if (cols[k] == -2) {
            sq_error_set(err, SQ_ERR_PARSE, where,
                         "the manifest's header names its %s column twice, \"%.60s\" and \"%.60s\": keep one", roles[k],
                         two[0], two[1]);
            sq_io_csv_free(csv);
            free(csv);
            return SQ_ERR_PARSE;
        }
    }
    const int cid = cols[0], cphoto = cols[1], cmask = cols[2], cexp = cols[3], cspecies = cols[4], cline = cols[5];
    if (cid < 0 || cphoto < 0) {
        sq_error_set(err, SQ_ERR_PARSE, where,
                     "the manifest's header has no %s column (the first line must name the columns: "
                     "id, photo, and optionally mask, body_line, expected, species; it reads \"%.80s%s\")",
                     cid < 0 ? "'id'" : "'photo' (or 'file')", h->fields[0], h->nfields > 1 ? ", ..." : "");
        sq_io_csv_free(csv);
        free(csv);
        return SQ_ERR_PARSE;
    }
    if (csv->nrecords - 1 > CLI_MANIFEST_MAX_ROWS) {
        sq_io_csv_free(csv);
        free(csv);
        return sq_error_set(err, SQ_ERR_LIMIT, path, "more than %d rows", CLI_MANIFEST_MAX_ROWS);
    }
    m->csv_ = csv;
    m->nrows = csv->nrecords - 1;
    m->rows = calloc(m->nrows > 0 ? (size_t)m->nrows : 1, sizeof *m->rows);
    if (!m->rows) {
        cli_manifest_free(m);
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    }
    const char *slash = strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path) : 0;
    if (slash && dirlen == 0)
        dirlen = 1; /* "/manifest.csv": the root */
    int oom = 0;
    for (int i = 0; i < m->nrows; i++) {
        const SqCsvRecord *r = &csv->records[i + 1];
        CliManifestRow *row = &m->rows[i];
#define FIELD(col) ((col) >= 0 && (col) < r->nfields ? r->fields[col] : "")
        row->line = r->line;
        row->id = FIELD(cid);
        row->species = FIELD(cspecies);
        const char *photo = FIELD(cphoto), *mask = FIELD(cmask), *line = FIELD(cline), *exp = FIELD(cexp);
#undef FIELD
        row->expected = -1;
        if (photo[0] && !(row->photo = resolve(path, dirlen, photo)))
            oom = 1;
        if (mask[0] && !(row->mask = resolve(path, dirlen, mask)))
            oom = 1;
        if (line[0] && !(row->body_line = resolve(path, dirlen, line)))
            oom = 1;
        if (r->nfields > h->nfields)
            row->error = dup_printf("the row has %d fields, the header %d", r->nfields, h->nfields);
        else if (!row->id[0])
            row->error = dup_printf("the row has no id");
        else if (!cli_manifest_id_ok(row->id))
            row->error = dup_printf("the id \"%.80s\" cannot name a folder: 1 to %d letters, digits, '_', '-' "
                                    "or '.', starting with a letter or digit",
                                    row->id, CLI_ID_MAX);
        else if (!photo[0])
            row->error = dup_printf("the row has no photo");
        else if (exp[0] && (row->expected = cli_manifest_category(exp)) < 0)
            row->error = dup_printf("the expected category \"%.40s\" is none of none, longitudinal, transversal, "
                                    "spots, other_simple, complex",
                                    exp);
        else
            continue;
        if (!row->error)
            oom = 1;
    }
    /* a repeated id: the first good row keeps it, the later ones are errors */
    IdRow *order = oom ? NULL : malloc((m->nrows > 0 ? (size_t)m->nrows : 1) * sizeof *order);
    if (!order)
        oom = 1;
    int n = 0;
    for (int i = 0; i < m->nrows && !oom; i++)
        if (!m->rows[i].error)
            order[n++] = (IdRow){m->rows[i].id, i};
    if (!oom)
        qsort(order, (size_t)n, sizeof *order, by_id);
    for (int k = 1, first = 0; k < n && !oom; k++) {
        if (strcmp(order[first].id, order[k].id) != 0) {
            first = k;
            continue;
        }
        CliManifestRow *row = &m->rows[order[k].row];
        row->error = dup_printf("the id %s is repeated (first on line %d)", row->id, m->rows[order[first].row].line);
        if (!row->error)
            oom = 1;
    }
    free(order);
    if (oom) {
        cli_manifest_free(m);
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    }
    return SQ_OK;
}

/* text (or the file at path when text is NULL) parsed as CSV, then as a manifest */
static SqStatus parse(const char *text, size_t len, const char *path, CliManifest *m, SqError *err)
{
    memset(m, 0, sizeof *m);
    SqCsv *csv = calloc(1, sizeof *csv);
    if (!csv)
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    SqStatus st = text ? sq_io_csv_parse(text, len, path, csv, err) : sq_io_csv_read(path, csv, err);
    if (st != SQ_OK) {
        free(csv);
        return st;
    }
    return from_csv(csv, path, m, err);
}

SqStatus cli_manifest_parse(const char *text, size_t len, const char *path, CliManifest *m, SqError *err)
{
    return parse(text ? text : "", len, path, m, err);
}

SqStatus cli_manifest_read(const char *path, CliManifest *m, SqError *err)
{
    return parse(NULL, 0, path, m, err);
}
