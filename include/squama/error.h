/* squama — status codes and error messages shared by every module.
 *
 * Functions that can fail return an SqStatus (0 ok, negative on error) and, when the
 * caller passes an SqError, fill it with what went wrong ("what") and where ("where":
 * file, key, line). The CLI prints them as "squama: <what> (<where>)". There is no
 * global error state: evaluation is threaded, so each caller owns its SqError.
 *
 * Everything here is header-only so that every module can use it without depending
 * on another module.
 */
#ifndef SQUAMA_ERROR_H
#define SQUAMA_ERROR_H


#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum SqStatus {
    SQ_OK = 0,
    SQ_ERR_NOMEM = -1,       /* an allocation failed */
    SQ_ERR_IO = -2,          /* a file could not be opened, read or written */
    SQ_ERR_PARSE = -3,       /* malformed text: JSON, CA descriptor, image data */
    SQ_ERR_INVALID = -4,     /* well-formed but wrong: unknown key, type, range */
    SQ_ERR_LIMIT = -5,       /* a configured limit was exceeded (pixels, sizes) */
    SQ_ERR_UNSUPPORTED = -6, /* a format or feature squama does not handle */
    SQ_ERR_INTERNAL = -7     /* a bug: please report */
} SqStatus;

enum { SQ_ERROR_WHAT_MAX = 512, SQ_ERROR_WHERE_MAX = 512 };

typedef struct SqError {
    SqStatus status;
    char what[SQ_ERROR_WHAT_MAX];   /* e.g. unknown key "Spots_Tilling" (did you mean ...) */
    char where[SQ_ERROR_WHERE_MAX]; /* e.g. presets/x.json:12 ; empty when unknown */
} SqError;

/* A short, static description of a status code. */
static inline const char *sq_strerror(SqStatus s)
{
    switch (s) {
    case SQ_OK: return "success";
    case SQ_ERR_NOMEM: return "out of memory";
    case SQ_ERR_IO: return "input/output error";
    case SQ_ERR_PARSE: return "malformed input";
    case SQ_ERR_INVALID: return "invalid value";
    case SQ_ERR_LIMIT: return "limit exceeded";
    case SQ_ERR_UNSUPPORTED: return "unsupported";
    case SQ_ERR_INTERNAL: return "internal error";
    }
    return "unknown status";
}

/* Fills err (if not NULL) and returns status, so callers can write
 * `return sq_error_set(err, SQ_ERR_IO, path, "cannot open: %s", strerror(errno));` */
#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
static inline SqStatus sq_error_set(SqError *err, SqStatus status, const char *where,
                                    const char *fmt, ...)
{
    if (err) {
        va_list ap;
        err->status = status;
        va_start(ap, fmt);
        vsnprintf(err->what, sizeof err->what, fmt, ap);
        va_end(ap);
        snprintf(err->where, sizeof err->where, "%s", where ? where : "");
    }
    return status;
}

/* Clears err (if not NULL). */
static inline void sq_error_clear(SqError *err)
{
    if (err) {
        err->status = SQ_OK;
        err->what[0] = '\0';
        err->where[0] = '\0';
    }
}

#ifdef __cplusplus
}
#endif

#endif /* SQUAMA_ERROR_H */
