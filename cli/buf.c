/* A growing text buffer. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "buf.h"

void cli_buf_put(CliBuf *b, const char *fmt, ...)
{
    if (b->fail)
        return;
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (len < 0 || b->n + (size_t)len + 1 > b->cap) {
        size_t cap = (b->cap ? 2 * b->cap : 16384) + (size_t)(len > 0 ? len : 0);
        char *s = realloc(b->s, cap);
        if (!s || len < 0) {
            b->fail = 1;
            return;
        }
        b->s = s;
        b->cap = cap;
    }
    va_start(ap, fmt);
    vsnprintf(b->s + b->n, b->cap - b->n, fmt, ap);
    va_end(ap);
    b->n += (size_t)len;
}

void cli_buf_html(CliBuf *b, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '<': cli_buf_put(b, "&lt;"); break;
        case '>': cli_buf_put(b, "&gt;"); break;
        case '&': cli_buf_put(b, "&amp;"); break;
        case '"': cli_buf_put(b, "&quot;"); break;
        case '\'': cli_buf_put(b, "&#39;"); break;
        default: cli_buf_put(b, "%c", *s); break;
        }
    }
}
