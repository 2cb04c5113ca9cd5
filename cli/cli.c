#define _XOPEN_SOURCE 700

#include <ctype.h>
#include <errno.h>
#include <ftw.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "squama/io.h"

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

/* 1 when word is "--name=value" for the long option (or the one long option name begins)
 * whose value is val: getopt refused it a value, and optopt is its val */
static int long_refused(const char *word, int val, const struct option *opts)
{
    const char *eq = strchr(word, '=');
    if (strncmp(word, "--", 2) != 0 || !eq)
        return 0;
    const size_t len = (size_t)(eq - word - 2);
    const struct option *hit = NULL;
    int hits = 0;
    for (const struct option *o = opts; o && o->name; o++)
        if (strncmp(o->name, word + 2, len) == 0) {
            if (strlen(o->name) == len)
                return o->val == val;
            hit = o;
            hits++;
        }
    return hits == 1 && hit->val == val;
}

int cli_bad_option(const char *cmd, char *const argv[], int c, const struct option *opts)
{
    const char *word = optind > 0 ? argv[optind - 1] : "?";
    /* getopt moves optind past a cluster of short options only after its last letter: a
     * letter refused inside one leaves optind on it (argv ends in NULL, so argv[optind] is
     * safe to look at) */
    const char *cur = optind > 0 ? argv[optind] : NULL;
    if (cur && cur[0] == '-' && cur[1] && cur[1] != '-' && optopt > 0 && optopt < 128 && strchr(cur + 1, optopt) &&
        !(c != ':' && long_refused(word, optopt, opts)))
        word = cur;
    if (strncmp(word, "--", 2) != 0) { /* a short option, perhaps in a cluster: the letter */
        if (c == ':')
            return cli_usage(cmd, "-%c needs a value", optopt);
        return cli_usage(cmd, "unknown option '-%c'", optopt ? optopt : '?');
    }
    const char *eq = strchr(word, '='); /* as typed, up to its '=' */
    const int len = eq ? (int)(eq - word) : (int)strlen(word);
    if (c == ':')
        return cli_usage(cmd, "%.*s needs a value", len, word);
    if (eq && optopt) /* a known option given a value it does not take */
        return cli_usage(cmd, "%.*s takes no value", len, word);
    /* a prefix of several long options (an exact name or one match getopt takes) */
    char names[256] = "";
    int matches = 0;
    for (const struct option *o = opts; o && o->name; o++)
        if (len > 2 && strncmp(o->name, word + 2, (size_t)(len - 2)) == 0) {
            size_t k = strlen(names);
            snprintf(names + k, sizeof names - k, "%s--%s", matches ? ", " : "", o->name);
            matches++;
        }
    if (matches > 1)
        return cli_usage(cmd, "ambiguous option '%.*s': %s?", len, word, names);
    return cli_usage(cmd, "unknown option '%.*s'", len, word);
}

SqStatus cli_staging_open(CliStaging *s, const char *pattern, int cap, SqError *err)
{
    memset(s, 0, sizeof *s);
    s->files = calloc(cap > 0 ? (size_t)cap : 1, sizeof *s->files);
    if (!s->files)
        return sq_error_set(err, SQ_ERR_NOMEM, pattern, "out of memory");
    s->cap = cap;
    snprintf(s->dir, sizeof s->dir, "%s", pattern);
    if (!mkdtemp(s->dir)) {
        SqStatus st = sq_error_set(err, SQ_ERR_IO, pattern, "cannot create a temporary folder: %s", strerror(errno));
        s->dir[0] = 0;
        cli_staging_free(s);
        return st;
    }
    sq_io_temp_add(s->dir);
    return SQ_OK;
}

void cli_staging_path(CliStaging *s, const char *name, char *path, size_t n)
{
    snprintf(path, n, "%s/%s", s->dir, name);
    if (s->nfiles < s->cap) {
        snprintf(s->files[s->nfiles++], sizeof s->files[0], "%s", name);
        sq_io_temp_add(path);
    }
}

void cli_staging_release(CliStaging *s, int remove)
{
    char path[4200];
    for (int i = 0; i < s->nfiles; i++) {
        snprintf(path, sizeof path, "%s/%s", s->dir, s->files[i]);
        if (remove)
            unlink(path);
        sq_io_temp_forget(path);
    }
    if (s->dir[0]) {
        if (remove)
            rmdir(s->dir);
        sq_io_temp_forget(s->dir);
    }
    s->nfiles = 0;
    s->dir[0] = 0;
}

void cli_staging_free(CliStaging *s)
{
    cli_staging_release(s, 1);
    free(s->files);
    s->files = NULL;
}

/* the paths of s's file i: staged (from), set aside (old) and in place (to); 4200 bytes each */
static void staged_paths(const CliStaging *s, const char *outdir, int i, char *from, char *old, char *to)
{
    snprintf(from, 4200, "%s/%s", s->dir, s->files[i]);
    snprintf(old, 4200, "%s/old-%s", s->dir, s->files[i]);
    snprintf(to, 4200, "%s/%s", outdir, s->files[i]);
}

SqStatus cli_staging_commit(CliStaging *s, const char *outdir, int quiet, SqError *err)
{
    char *kept = calloc(s->nfiles > 0 ? (size_t)s->nfiles : 1, 1);
    if (!kept)
        return sq_error_set(err, SQ_ERR_NOMEM, outdir, "out of memory");
    char from[4200], old[4200], to[4200];
    sigset_t fatal, saved;
    sigemptyset(&fatal);
    sigaddset(&fatal, SIGINT);
    sigaddset(&fatal, SIGTERM);
    sigaddset(&fatal, SIGHUP);
    sigprocmask(SIG_BLOCK, &fatal, &saved);
    SqStatus st = SQ_OK;
    int moved = 0;
    for (int i = 0; i < s->nfiles && st == SQ_OK; i++) {
        struct stat sb;
        staged_paths(s, outdir, i, from, old, to);
        const int exists = lstat(to, &sb) == 0;
        if (stat(to, &sb) == 0 && S_ISDIR(sb.st_mode)) {
            st = sq_error_set(err, SQ_ERR_IO, to, "a folder is where the map goes; no map was written");
        } else if (exists && rename(to, old) != 0) {
            st = sq_error_set(err, SQ_ERR_IO, to, "cannot replace the map: %s; no map was written", strerror(errno));
        } else if (rename(from, to) != 0) {
            st = sq_error_set(err, SQ_ERR_IO, to, "cannot move the map into place: %s; no map was written",
                              strerror(errno));
            kept[i] = exists && rename(old, to) != 0;
        } else {
            kept[i] = (char)exists;
            moved = i + 1;
        }
    }
    for (int i = moved - 1; i >= 0 && st != SQ_OK; i--) { /* the old set back */
        staged_paths(s, outdir, i, from, old, to);
        if (kept[i] ? rename(old, to) == 0 : unlink(to) == 0)
            kept[i] = 0;
    }
    for (int i = 0; i < s->nfiles; i++) {
        staged_paths(s, outdir, i, from, old, to);
        if (st == SQ_OK && i < moved) {
            if (kept[i])
                unlink(old);
            if (!quiet)
                printf("wrote %s\n", to);
        } else if (st != SQ_OK && kept[i]) { /* could not be put back: stays, set aside */
            fprintf(stderr, "squama: the old %s is kept as %s\n", to, old);
        }
    }
    cli_staging_release(s, 1);
    sigprocmask(SIG_SETMASK, &saved, NULL);
    free(kept);
    return st;
}

/* path with its folder resolved (realpath), in out (n bytes); 0, or -1 when the folder
 * does not exist */
static int resolved(const char *path, char *out, size_t n)
{
    char dir[4096], real[PATH_MAX];
    const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (slash == path)
        snprintf(dir, sizeof dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    if (!realpath(dir, real))
        return -1;
    return snprintf(out, n, "%s/%s", real, base) < (int)n ? 0 : -1;
}

int cli_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) == 0 && stat(b, &sb) == 0)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    char ra[PATH_MAX + 256], rb[PATH_MAX + 256];
    return resolved(a, ra, sizeof ra) == 0 && resolved(b, rb, sizeof rb) == 0 && strcmp(ra, rb) == 0;
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
    if (*end && end[1] == 0)
        v *= *end == 's' ? 1 : *end == 'm' ? 60 : *end == 'h' ? 3600 : -1;
    else if (*end)
        return -1;
    return v > 0 && v <= 7 * 24 * 3600.0 ? v : -1;
}

/* Right after strtol or strtod (errno 0 before): they skip leading spaces, stop at the first
 * stray character and set ERANGE on overflow; an option's value is the number and nothing
 * else. */
static int whole_number(const char *arg, const char *end)
{
    return end != arg && *end == '\0' && !isspace((unsigned char)arg[0]) && errno != ERANGE;
}

int cli_parse_int(const char *opt, const char *arg, long lo, long hi, long *out, SqError *err)
{
    char *end;
    errno = 0;
    long v = strtol(arg, &end, 10);
    if (!whole_number(arg, end) || v < lo || v > hi) {
        sq_error_set(err, SQ_ERR_INVALID, "", "%s must be %ld to %ld, got '%s'", opt, lo, hi, arg);
        return -1;
    }
    *out = v;
    return 0;
}

int cli_parse_real(const char *opt, const char *arg, double lo, double hi, double *out, SqError *err)
{
    char *end;
    errno = 0;
    double v = strtod(arg, &end);
    if (!whole_number(arg, end) || !isfinite(v) || !(v >= lo && v <= hi)) {
        sq_error_set(err, SQ_ERR_INVALID, "", "%s must be %g to %g, got '%s'", opt, lo, hi, arg);
        return -1;
    }
    *out = v;
    return 0;
}

static int remove_one(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st;
    (void)ftw;
    return flag == FTW_DP ? rmdir(path) : unlink(path);
}

int cli_remove_tree(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return errno == ENOENT ? 0 : -1;
    if (!S_ISDIR(st.st_mode))
        return unlink(path);
    return nftw(path, remove_one, 16, FTW_DEPTH | FTW_PHYS);
}

int cli_pathf(char *buf, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(buf, n, fmt, ap);
    va_end(ap);
    if (len < 0 || (size_t)len >= n) {
        if (n)
            buf[0] = '\0';
        errno = ENAMETOOLONG;
        return -1;
    }
    return 0;
}

double cli_now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

double cli_search_budget(double budget, double spent, int size)
{
    const double side = (double)size / 1024;
    const double outputs = 1.0 + 2.0 * side * side;
    return fmax(0.25 * budget, budget - spent - outputs);
}
