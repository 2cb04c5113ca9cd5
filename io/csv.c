/* CSV after RFC 4180: one pass that unquotes every field into one buffer. */
#include <stdlib.h>
#include <string.h>

#include "squama/io.h"

/* The records' fields are collected as offsets first (the buffers move while growing). */
typedef struct Rec {
    int line, first, nfields; /* first: index into the field-offset array */
} Rec;

typedef struct Grow {
    void *p;
    size_t n, cap, size;
} Grow;

static int grow_push(Grow *g, const void *item)
{
    if (g->n == g->cap) {
        size_t cap = g->cap ? 2 * g->cap : 64;
        void *p = realloc(g->p, cap * g->size);
        if (!p)
            return -1;
        g->p = p;
        g->cap = cap;
    }
    memcpy((char *)g->p + g->n * g->size, item, g->size);
    g->n++;
    return 0;
}

static SqStatus fail(SqError *err, SqStatus st, const char *name, int line, const char *what)
{
    char where[SQ_ERROR_WHERE_MAX];
    snprintf(where, sizeof where, "%s:%d", name ? name : "csv", line);
    return sq_error_set(err, st, where, "%s", what);
}

SqStatus sq_io_csv_parse(const char *text, size_t len, const char *name, SqCsv *out,
                         SqError *err)
{
    memset(out, 0, sizeof *out);
    size_t i = 0;
    if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0)
        i = 3;
    /* every field's bytes plus its NUL fit in len + 1 + one byte per separator */
    char *store = malloc(len + 2);
    Grow offs = {.size = sizeof(size_t)}, recs = {.size = sizeof(Rec)};
    if (!store)
        return sq_error_set(err, SQ_ERR_NOMEM, name, "out of memory");
    size_t w = 0;
    int line = 1;
    SqStatus st = SQ_OK;
    while (i < len && st == SQ_OK) {
        /* an empty line is skipped */
        if (text[i] == '\n' || text[i] == '\r') {
            if (text[i] == '\r' && i + 1 < len && text[i + 1] == '\n')
                i++;
            i++;
            line++;
            continue;
        }
        Rec r = {.line = line, .first = (int)offs.n, .nfields = 0};
        for (;;) { /* one field */
            if (r.nfields == SQ_CSV_MAX_FIELDS) {
                st = fail(err, SQ_ERR_LIMIT, name, line, "more than 1024 fields in a record");
                break;
            }
            size_t start = w;
            if (grow_push(&offs, &start) != 0) {
                st = sq_error_set(err, SQ_ERR_NOMEM, name, "out of memory");
                break;
            }
            r.nfields++;
            if (i < len && text[i] == '"') {
                int qline = line;
                i++;
                for (;;) {
                    if (i >= len) {
                        st = fail(err, SQ_ERR_PARSE, name, qline, "unterminated quoted field");
                        break;
                    }
                    char c = text[i];
                    if (c == '"') {
                        if (i + 1 < len && text[i + 1] == '"') {
                            store[w++] = '"';
                            i += 2;
                            continue;
                        }
                        i++;
                        break;
                    }
                    if (c == '\0') {
                        st = fail(err, SQ_ERR_PARSE, name, line, "a NUL byte in the text");
                        break;
                    }
                    if (c == '\n' || (c == '\r' && !(i + 1 < len && text[i + 1] == '\n')))
                        line++;
                    store[w++] = c;
                    i++;
                }
                if (st != SQ_OK)
                    break;
                if (i < len && text[i] != ',' && text[i] != '\n' && text[i] != '\r') {
                    st = fail(err, SQ_ERR_PARSE, name, line,
                              "a closing quote must end the field (a quote inside a quoted field is written \"\")");
                    break;
                }
            } else {
                while (i < len && text[i] != ',' && text[i] != '\n' && text[i] != '\r') {
                    if (text[i] == '\0') {
                        st = fail(err, SQ_ERR_PARSE, name, line, "a NUL byte in the text");
                        break;
                    }
                    if (text[i] == '"') {
                        st = fail(err, SQ_ERR_PARSE, name, line,
                                  "a quote inside an unquoted field (quote the whole field)");
                        break;
                    }
                    store[w++] = text[i++];
                }
                if (st != SQ_OK)
                    break;
            }
            store[w++] = '\0';
            if (i < len && text[i] == ',') {
                i++;
                continue;
            }
            /* end of record: a line break or the end of the text */
            if (i < len && text[i] == '\r')
                i++;
            if (i < len && text[i] == '\n')
                i++;
            line++;
            break;
        }
        if (st == SQ_OK && grow_push(&recs, &r) != 0)
            st = sq_error_set(err, SQ_ERR_NOMEM, name, "out of memory");
    }
    char **ptrs = NULL;
    SqCsvRecord *records = NULL;
    if (st == SQ_OK) {
        ptrs = malloc((offs.n ? offs.n : 1) * sizeof *ptrs);
        records = malloc((recs.n ? recs.n : 1) * sizeof *records);
        if (!ptrs || !records)
            st = sq_error_set(err, SQ_ERR_NOMEM, name, "out of memory");
    }
    if (st != SQ_OK) {
        free(ptrs);
        free(records);
        free(store);
        free(offs.p);
        free(recs.p);
        return st;
    }
    const size_t *off = offs.p;
    for (size_t k = 0; k < offs.n; k++)
        ptrs[k] = store + off[k];
    const Rec *rr = recs.p;
    for (size_t k = 0; k < recs.n; k++)
        records[k] = (SqCsvRecord){.line = rr[k].line, .nfields = rr[k].nfields, .fields = ptrs + rr[k].first};
    free(offs.p);
    free(recs.p);
    out->nrecords = (int)recs.n;
    out->records = records;
    out->store_ = store;
    out->ptrs_ = ptrs;
    return SQ_OK;
}

SqStatus sq_io_csv_read(const char *path, SqCsv *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    char *text;
    size_t len;
    SqStatus st = sq_io_read_file(path, SQ_CSV_MAX_BYTES, &text, &len, err);
    if (st != SQ_OK)
        return st;
    st = sq_io_csv_parse(text, len, path, out, err);
    free(text);
    return st;
}

void sq_io_csv_free(SqCsv *csv)
{
    if (!csv)
        return;
    free(csv->store_);
    free(csv->ptrs_);
    free(csv->records);
    memset(csv, 0, sizeof *csv);
}

int sq_io_csv_append(char **buf, size_t *len, size_t *cap, const char *field, char end)
{
    size_t n = strlen(field), need = 2 * n + 3;
    if (*len + need + 1 > *cap) {
        size_t c = *cap ? *cap : 256;
        while (*len + need + 1 > c)
            c *= 2;
        char *p = realloc(*buf, c);
        if (!p)
            return -1;
        *buf = p;
        *cap = c;
    }
    /* a field that starts with a byte-order mark is quoted: first in a file, the reader would drop the mark */
    int quote = strpbrk(field, ",\"\r\n") != NULL || strncmp(field, "\xEF\xBB\xBF", 3) == 0;
    char *o = *buf + *len;
    if (quote)
        *o++ = '"';
    for (const char *s = field; *s; s++) {
        if (*s == '"')
            *o++ = '"';
        *o++ = *s;
    }
    if (quote)
        *o++ = '"';
    *o++ = end;
    *o = '\0';
    *len = (size_t)(o - *buf);
    return 0;
}
