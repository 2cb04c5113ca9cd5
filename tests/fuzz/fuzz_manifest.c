/* libFuzzer harness: squama batch's manifest (CSV after RFC 4180, columns by header). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "manifest.h"
#include "squama/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A record that is one empty field is written as an empty line, which reads as no record. */
static int blank(const SqCsvRecord *r)
{
    return r->nfields == 1 && r->fields[0][0] == '\0';
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    CliManifest m;
    SqError err;
    if (cli_manifest_parse((const char *)data, size, "dir/fuzz.csv", &m, &err) != SQ_OK) {
        if (err.what[0] == '\0' || err.where[0] == '\0')
            abort();
    } else {
        for (int i = 0; i < m.nrows; i++) {
            const CliManifestRow *r = &m.rows[i];
            if (r->error)
                continue; /* a good row names a folder and a photo beside the manifest */
            if (!cli_manifest_id_ok(r->id) || !r->photo || (strncmp(r->photo, "dir/", 4) != 0 && r->photo[0] != '/'))
                abort();
            for (int k = 0; k < i; k++)
                if (!m.rows[k].error && strcmp(m.rows[k].id, r->id) == 0)
                    abort();
        }
        cli_manifest_free(&m);
    }
    /* the CSV layer: what is written back reads as the same fields */
    SqCsv a, b;
    if (sq_io_csv_parse((const char *)data, size, "fuzz.csv", &a, &err) != SQ_OK)
        return 0;
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (int r = 0; r < a.nrecords; r++)
        for (int f = 0; f < a.records[r].nfields && !blank(&a.records[r]); f++)
            if (sq_io_csv_append(&buf, &len, &cap, a.records[r].fields[f], f + 1 < a.records[r].nfields ? ',' : '\n'))
                abort();
    if (sq_io_csv_parse(buf ? buf : "", len, "again.csv", &b, &err) != SQ_OK)
        abort();
    int k = 0;
    for (int r = 0; r < a.nrecords; r++) {
        if (blank(&a.records[r]))
            continue;
        if (k >= b.nrecords || b.records[k].nfields != a.records[r].nfields)
            abort();
        for (int f = 0; f < a.records[r].nfields; f++)
            if (strcmp(a.records[r].fields[f], b.records[k].fields[f]) != 0)
                abort();
        k++;
    }
    if (k != b.nrecords)
        abort();
    free(buf);
    sq_io_csv_free(&a);
    sq_io_csv_free(&b);
    return 0;
}
