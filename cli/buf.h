/* A growing text buffer for the pages and tables the program writes. */
#ifndef SQUAMA_CLI_BUF_H
#define SQUAMA_CLI_BUF_H

#include <stddef.h>

typedef struct CliBuf {
    char *s;    /* NUL-terminated once anything was put */
    size_t n, cap;
    int fail;   /* an allocation failed: every later put is ignored */
} CliBuf;

/* printf onto the end of b. */
void cli_buf_put(CliBuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* s with <, >, &, " and ' escaped for HTML text and attributes. */
void cli_buf_html(CliBuf *b, const char *s);

#endif
