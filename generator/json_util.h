/* Internal helpers for JSON text shared by the generator and the CLI (not public API). */
#ifndef SQUAMA_JSON_UTIL_H
#define SQUAMA_JSON_UTIL_H

#include <stddef.h>

#include <cjson/cJSON.h>

#include "squama/error.h"

/* Writes the shortest "%.Ng" text (N = 15..17) that reads back as exactly d. */
void sq__format_exact(double d, char *buf, size_t size);

/* A cJSON number item printed with sq__format_exact (cJSON's own printer rounds). */
cJSON *sq__json_exact_number(double d);

/* Prints item with two-space indentation and a final newline; malloc'd (free()), or NULL
 * when out of memory. */
char *sq__json_print(const cJSON *item);

/* Checks text (len bytes) as one JSON value by RFC 8259 with only white space after it,
 * more strictly than cJSON (no leading zeros, no "\u0000", no unpaired surrogates, nesting
 * at most 1000 deep): 0 when it is JSON, else -1 with the offset of the first byte in error
 * in *off (len when the text ends early) and what is wrong there in *what. */
int sq__json_check(const char *text, size_t len, size_t *off, const char **what);

/* "name:line:col" of byte offset off in text, the column counted in UTF-8 characters. */
void sq__json_where(const char *text, size_t off, const char *name, char *where, size_t size);

/* Parses text (len bytes, NUL-terminated or not) into *root after sq__json_check: an error
 * names name:line:col of the first byte in error and what was expected there. */
SqStatus sq__json_parse(const char *text, size_t len, const char *name, cJSON **root, SqError *err);

#endif
