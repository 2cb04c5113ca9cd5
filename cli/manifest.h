/* squama batch's manifest: CSV with a header naming the columns (RFC 4180, io/csv.c). */
#ifndef SQUAMA_CLI_MANIFEST_H
#define SQUAMA_CLI_MANIFEST_H

#include <stddef.h>

#include "squama/error.h"

/* Columns are found by their header name (any case; the first name of a list that is
 * present wins): */
#define CLI_MANIFEST_ID "id"
#define CLI_MANIFEST_PHOTO "photo", "file", "image", "path"
#define CLI_MANIFEST_MASK "mask"
#define CLI_MANIFEST_LINE "body_line"
#define CLI_MANIFEST_EXPECTED "expected", "expected_category", "category", "pattern_category", \
                              "pattern_category_guess"
#define CLI_MANIFEST_SPECIES "species"

enum { CLI_ID_MAX = 64, CLI_MANIFEST_MAX_ROWS = 1000000 };

typedef struct CliManifestRow {
    int line;         /* where the row starts in the manifest */
    const char *id;   /* as written ("" when empty) */
    char *photo;      /* resolved against the manifest's folder; NULL when empty */
    char *mask;       /* resolved likewise; NULL when not given */
    char *body_line;  /* a body line (squama-body-line JSON), likewise */
    const char *species; /* "" when not given */
    int expected;     /* an SqPatternType, or -1 when not given */
    char *error;      /* NULL, or why the row cannot be fitted (empty, malformed or repeated
                         id, no photo, an unknown category, too many fields) */
} CliManifestRow;

typedef struct CliManifest {
    int nrows;
    CliManifestRow *rows;
    void *csv_;       /* internal: the parsed text the rows point into */
} CliManifest;

/* Parses a manifest; path names it in messages and gives the folder relative paths are
 * resolved against. A manifest without a header naming an id and a photo column, or whose
 * CSV is malformed, is an error "what (path:line)"; a bad row is not: it carries its
 * error. On error nothing is allocated in m. */
SqStatus cli_manifest_parse(const char *text, size_t len, const char *path, CliManifest *m, SqError *err);

/* Reads and parses the file at path. */
SqStatus cli_manifest_read(const char *path, CliManifest *m, SqError *err);

/* NULL-safe; zeroes m. */
void cli_manifest_free(CliManifest *m);

/* 1 when id can name a folder of the batch's output: 1 to CLI_ID_MAX letters, digits, '_',
 * '-' or '.', starting with a letter or digit, and not a name the batch writes itself. */
int cli_manifest_id_ok(const char *id);

/* The pattern category called name (any case, '-' or ' ' for '_'), or -1. */
int cli_manifest_category(const char *name);

#endif
