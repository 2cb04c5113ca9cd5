/* Internal helpers for JSON text shared by the generator and the CLI (not public API). */
#ifndef SQUAMA_JSON_UTIL_H
#define SQUAMA_JSON_UTIL_H

#include <stddef.h>

#include <cjson/cJSON.h>

/* Writes the shortest "%.Ng" text (N = 15..17) that reads back as exactly d. */
void sq__format_exact(double d, char *buf, size_t size);

/* A cJSON number item printed with sq__format_exact (cJSON's own printer rounds). */
cJSON *sq__json_exact_number(double d);

/* Prints item with two-space indentation and a final newline; malloc'd (free()), or NULL
 * when out of memory. */
char *sq__json_print(const cJSON *item);

#endif
