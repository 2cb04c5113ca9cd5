#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli.h"

int cli_fail(const SqError *err)
{
    if (err->where[0])
        fprintf(stderr, "squama: %s (%s)\n", err->what, err->where);
    else
        fprintf(stderr, "squama: %s\n", err->what);
    return CLI_FAIL;
}

int cli_usage(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    fputs("squama: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, " (see 'squama %s%s--help')\n", cmd ? cmd : "", cmd ? " " : "");
    return CLI_USAGE;
}

const char *cli_presets_dir(void)
{
    const char *env = getenv("SQUAMA_PRESETS");
    return env && *env ? env : SQUAMA_PRESETS_DIR;
}

int cli_parse_size(const char *s, int lo, int hi, int *w, int *h)
{
    char *end;
    long a = strtol(s, &end, 10), b = a;
    if (end == s)
        return 0;
    if (*end == 'x' || *end == 'X')
        b = strtol(end + 1, &end, 10);
    if (*end || a < lo || b < lo || a > hi || b > hi)
        return 0;
    *w = (int)a;
    *h = (int)b;
    return 1;
}

/* "60", "60s", "2m", "1.5m" -> seconds; -1 when malformed. */
double cli_parse_time(const char *s)
{
    char *end;
    double v = strtod(s, &end);
    if (end == s || !(v > 0) || !isfinite(v))
        return -1;
    if (*end == 's' && end[1] == 0)
        return v;
    if (*end == 'm' && end[1] == 0)
        return 60 * v;
    if (*end == 'h' && end[1] == 0)
        return 3600 * v;
    return *end ? -1 : v;
}
