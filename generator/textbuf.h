/* Internal: snprintf-style appending that keeps counting past the end of the buffer, so
 * a formatter can return the length it needs (as snprintf does). */
#ifndef SQUAMA_TEXTBUF_H
#define SQUAMA_TEXTBUF_H

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
static inline void sq__appendf(char *buf, size_t size, size_t *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(*n < size ? buf + *n : NULL, *n < size ? size - *n : 0, fmt, ap);
    va_end(ap);
    if (k > 0)
        *n += (size_t)k;
}

#endif
