#define _XOPEN_SOURCE 700

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <ftw.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
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

/* The staging open now (one at a time), for cli_staging_shown. */
static const CliStaging *open_staging;
/* What the program is doing, for the fatal signals' handler (cli_signal_waits): a commit
 * and the handler's ending of the program exclude each other; a signal held back by a
 * commit, which raises it again when its files are in. */
enum { IDLE, COMMITTING, DYING };
static _Atomic int program_state = IDLE, held_signal;
_Static_assert(ATOMIC_INT_LOCK_FREE == 2, "the signal handler's atomics must be lock-free");

/* Staging folders of pattern's kind beside s's, left by a run that was killed (SIGKILL, a
 * crash, a power cut): named on stderr, since one stopped while its files moved in holds
 * the only copy of the outputs it had set aside (old-*). Nothing is removed. */
static void folder_of(const char *path, char *dir, size_t n)
{
    const char *slash = strrchr(path, '/');
    snprintf(dir, n, "%.*s", slash ? (slash == path ? 1 : (int)(slash - path)) : 1, slash ? path : ".");
}

static void warn_leftovers(const CliStaging *s, const char *pattern)
{
    const char *slash = strrchr(pattern, '/'), *base = slash ? slash + 1 : pattern;
    const char *own_slash = strrchr(s->dir, '/'), *own = own_slash ? own_slash + 1 : s->dir;
    const size_t len = strlen(base), k = len > 6 ? len - 6 : 0; /* without XXXXXX */
    const int lead = slash ? (int)(slash - pattern) + 1 : 0; /* the folder, as given, with its slash */
    char dir[4096], path[8400];
    folder_of(pattern, dir, sizeof dir);
    DIR *d = opendir(dir);
    if (!d)
        return;
    const struct dirent *e;
    while ((e = readdir(d))) {
        struct stat sb;
        if (k == 0 || strncmp(e->d_name, base, k) != 0 || strlen(e->d_name) != k + 6 || strcmp(e->d_name, own) == 0)
            continue;
        snprintf(path, sizeof path, "%.*s%s", lead, pattern, e->d_name);
        if (lstat(path, &sb) != 0 || !S_ISDIR(sb.st_mode))
            continue;
        int old = 0;
        DIR *in = opendir(path);
        for (const struct dirent *f; in && (f = readdir(in)) && !old;)
            old = strncmp(f->d_name, "old-", 4) == 0;
        if (in)
            closedir(in);
        fprintf(stderr, "squama: warning: %s is another run's temporary folder (one that was stopped, or one "
                "under way)%s\n", path,
                old ? "; it holds outputs that run had set aside (old-*): once it is over, move back what you need "
                      "and remove it"
                    : "; once it is over, remove it");
    }
    closedir(d);
}

SqStatus cli_staging_open(CliStaging *s, const char *pattern, const char *outdir, int cap, SqError *err)
{
    memset(s, 0, sizeof *s);
    s->cap = cap > 0 ? cap : 8;
    s->files = calloc((size_t)s->cap, sizeof *s->files);
    if (!s->files)
        return sq_error_set(err, SQ_ERR_NOMEM, pattern, "out of memory");
    snprintf(s->outdir, sizeof s->outdir, "%s", outdir);
    snprintf(s->dir, sizeof s->dir, "%s", pattern);
    if (!mkdtemp(s->dir)) {
        const int e = errno;
        char where[4096]; /* the folder it was to be made in, not the pattern */
        folder_of(pattern, where, sizeof where);
        SqStatus st = sq_error_set(err, SQ_ERR_IO, where, "cannot create a temporary folder in it: %s", strerror(e));
        s->dir[0] = 0;
        cli_staging_free(s);
        return st;
    }
    sq_io_temp_add(s->dir);
    open_staging = s;
    warn_leftovers(s, pattern);
    return SQ_OK;
}

/* s's entry for name, NULL when there is none */
static CliStaged *staged_find(CliStaging *s, const char *name, size_t len)
{
    for (int i = 0; i < s->nfiles; i++)
        if (strlen(s->files[i].name) == len && strncmp(s->files[i].name, name, len) == 0)
            return &s->files[i];
    return NULL;
}

/* a new entry for the first len bytes of name, or NULL with err set */
static CliStaged *staged_add(CliStaging *s, const char *name, size_t len, SqError *err)
{
    const char *what = s->what ? s->what : "output";
    if (len == 0 || len >= sizeof s->files[0].name || name[0] == '/' || name[len - 1] == '/' || strstr(name, "//") ||
        strcmp(name, ".") == 0 || strncmp(name, "./", 2) == 0 || strstr(name, "/.") || strncmp(name, "..", 2) == 0) {
        sq_error_set(err, SQ_ERR_INVALID, name, "not a name for a %s in the output folder", what);
        return NULL;
    }
    if (staged_find(s, name, len)) {
        sq_error_set(err, SQ_ERR_INVALID, name, "this %s is written twice", what);
        return NULL;
    }
    if (s->nfiles == s->cap) {
        CliStaged *more = realloc(s->files, sizeof *more * (size_t)s->cap * 2);
        if (!more) {
            sq_error_set(err, SQ_ERR_NOMEM, name, "out of memory");
            return NULL;
        }
        s->files = more;
        s->cap *= 2;
    }
    CliStaged *f = &s->files[s->nfiles++];
    memset(f, 0, sizeof *f);
    memcpy(f->name, name, len);
    return f;
}

SqStatus cli_staging_path(CliStaging *s, const char *name, char *path, size_t n, SqError *err)
{
    for (const char *sl = strchr(name, '/'); sl; sl = strchr(sl + 1, '/')) { /* its folders first */
        const size_t len = (size_t)(sl - name);
        if (staged_find(s, name, len))
            continue;
        CliStaged *f = staged_add(s, name, len, err);
        if (!f)
            return err->status;
        f->folder = 1;
        snprintf(path, n, "%s/%s", s->dir, f->name);
        if (mkdir(path, 0777) != 0) {
            s->nfiles--;
            return sq_error_set(err, SQ_ERR_IO, path, "cannot create the folder: %s", strerror(errno));
        }
        sq_io_temp_add(path);
    }
    CliStaged *f = staged_add(s, name, strlen(name), err);
    if (!f)
        return err->status;
    if (cli_pathf(path, n, "%s/%s", s->dir, name) != 0) {
        s->nfiles--;
        return sq_error_set(err, SQ_ERR_INVALID, s->dir, "the output folder's name is too long");
    }
    sq_io_temp_add(path);
    return SQ_OK;
}

SqStatus cli_staging_drop(CliStaging *s, const char *name, SqError *err)
{
    CliStaged *f = staged_find(s, name, strlen(name));
    if (f && !f->folder && !f->drop) { /* named for the set already: what was written goes */
        char path[4200];
        snprintf(path, sizeof path, "%s/%s", s->dir, f->name);
        unlink(path);
        sq_io_temp_forget(path);
        f->drop = 1;
        return SQ_OK;
    }
    f = staged_add(s, name, strlen(name), err);
    if (!f)
        return err->status;
    f->drop = 1;
    return SQ_OK;
}

void cli_staging_release(CliStaging *s, int remove)
{
    char path[4200];
    for (int pass = 0; pass < 2; pass++) /* the files, then their folders, the deepest first */
        for (int i = pass ? s->nfiles - 1 : 0; pass ? i >= 0 : i < s->nfiles; i += pass ? -1 : 1) {
            const CliStaged *f = &s->files[i];
            if (f->drop || f->folder != pass)
                continue;
            snprintf(path, sizeof path, "%s/%s", s->dir, f->name);
            if (remove)
                pass ? rmdir(path) : unlink(path);
            sq_io_temp_forget(path);
        }
    if (s->dir[0]) {
        if (remove)
            rmdir(s->dir);
        sq_io_temp_forget(s->dir);
    }
    s->nfiles = 0;
    s->dir[0] = 0;
    if (open_staging == s)
        open_staging = NULL;
}

void cli_staging_free(CliStaging *s)
{
    cli_staging_release(s, 1);
    free(s->files);
    s->files = NULL;
}

/* the paths of s's entry i: staged (from), set aside (old, its folders flattened) and in
 * place (to); 4200 bytes each */
static void staged_paths(const CliStaging *s, int i, char *from, char *old, char *to)
{
    snprintf(from, 4200, "%s/%s", s->dir, s->files[i].name);
    snprintf(old, 4200, "%s/old-%s", s->dir, s->files[i].name);
    for (char *c = old + strlen(s->dir) + 1; *c; c++)
        if (*c == '/')
            *c = '_';
    snprintf(to, 4200, "%s/%s", s->outdir, s->files[i].name);
}

/* 1 when the program is now ending (no commit under way, none to start from now on) */
static int dying(void)
{
    int was = IDLE;
    return atomic_compare_exchange_strong(&program_state, &was, DYING) || was == DYING;
}

int cli_signal_waits(int sig)
{
    if (dying())
        return 0;
    atomic_store(&held_signal, sig);
    /* a commit that ended meanwhile may have looked already: the signal goes on here */
    return !dying();
}

/* err for a rename to `to` that failed with errno e: "cannot VERB WHAT TAIL: why" */
static SqStatus rename_error(SqError *err, const char *to, const char *verb, const char *what, const char *tail,
                             int e)
{
    if (e == EXDEV)
        return sq_error_set(err, SQ_ERR_IO, to,
                            "cannot %s %s%s: its folder is on another file system than the output folder (a link?), "
                            "and the outputs move in as a set by renaming; no %s was written",
                            verb, what, tail, what);
    return sq_error_set(err, SQ_ERR_IO, to, "cannot %s %s%s: %s; no %s was written", verb, what, tail, strerror(e),
                        what);
}

SqStatus cli_staging_commit(CliStaging *s, int quiet, SqError *err)
{
    const char *what = s->what ? s->what : "output";
    char *kept = calloc(s->nfiles > 0 ? (size_t)s->nfiles : 1, 1); /* set aside; for a folder, made */
    if (!kept)
        return sq_error_set(err, SQ_ERR_NOMEM, s->outdir, "out of memory");
    char from[4200], old[4200], to[4200];
    sigset_t fatal, saved;
    sigemptyset(&fatal);
    sigaddset(&fatal, SIGINT);
    sigaddset(&fatal, SIGTERM);
    sigaddset(&fatal, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &fatal, &saved); /* this thread's; the others' wait in the handler */
    int was = IDLE;
    if (!atomic_compare_exchange_strong(&program_state, &was, COMMITTING))
        for (;;) /* a signal's handler on another thread is removing the files and ends the program */
            pause();
    SqStatus st = SQ_OK;
    int moved = 0;
    for (int i = 0; i < s->nfiles && st == SQ_OK; i++) {
        const CliStaged *f = &s->files[i];
        struct stat sb;
        staged_paths(s, i, from, old, to);
        const int exists = lstat(to, &sb) == 0, folder = stat(to, &sb) == 0 && S_ISDIR(sb.st_mode);
        if (f->folder) {
            if (exists && !folder)
                st = sq_error_set(err, SQ_ERR_IO, to, "not a folder; no %s was written", what);
            else if (!exists && mkdir(to, 0777) != 0)
                st = sq_error_set(err, SQ_ERR_IO, to, "cannot create the folder: %s; no %s was written",
                                  strerror(errno), what);
            else
                kept[i] = (char)!exists;
        } else if (f->drop) { /* set aside; a folder there is not an earlier output */
            if (exists && !folder && rename(to, old) != 0)
                st = rename_error(err, to, "remove the earlier", what, "", errno);
            else
                kept[i] = (char)(exists && !folder);
        } else if (folder) {
            st = sq_error_set(err, SQ_ERR_IO, to, "a folder is where the %s goes; no %s was written", what, what);
        } else if (exists && rename(to, old) != 0) {
            st = rename_error(err, to, "replace the", what, "", errno);
        } else if (rename(from, to) != 0) {
            st = rename_error(err, to, "move the", what, " into place", errno);
            kept[i] = exists && rename(old, to) != 0;
        } else {
            kept[i] = (char)exists;
        }
        if (st == SQ_OK)
            moved = i + 1;
    }
    for (int i = moved - 1; i >= 0 && st != SQ_OK; i--) { /* the old set back, the folders made last */
        const CliStaged *f = &s->files[i];
        staged_paths(s, i, from, old, to);
        if (f->folder)
            continue;
        if (kept[i] ? rename(old, to) == 0 : f->drop || unlink(to) == 0)
            kept[i] = 0;
        else if (!kept[i]) /* a new file with no old one under it */
            fprintf(stderr, "squama: warning: the new %s stays (cannot remove it: %s), though the rest of its set "
                    "was not written\n", to, strerror(errno));
    }
    for (int i = moved - 1; i >= 0 && st != SQ_OK; i--)
        if (s->files[i].folder && kept[i]) {
            staged_paths(s, i, from, old, to);
            rmdir(to);
        }
    for (int i = 0; i < s->nfiles; i++) {
        const CliStaged *f = &s->files[i];
        if (f->folder)
            continue;
        staged_paths(s, i, from, old, to);
        if (st == SQ_OK && i < moved) {
            if (kept[i])
                unlink(old);
            if (!quiet && !f->drop)
                printf("wrote %s\n", to);
        } else if (st != SQ_OK && kept[i]) { /* could not be put back: stays, set aside */
            fprintf(stderr, "squama: the old %s is kept as %s\n", to, old);
        }
    }
    cli_staging_release(s, 1);
    atomic_store(&program_state, IDLE);
    const int held = atomic_exchange(&held_signal, 0);
    pthread_sigmask(SIG_SETMASK, &saved, NULL);
    free(kept);
    if (held) /* from another thread: it ends the program now, as it would have */
        raise(held);
    return st;
}

/* path as the file in s's outdir it is to become, in buf (n bytes); NULL when it is not in s */
static const char *shown_as(const CliStaging *s, const char *path, char *buf, size_t n)
{
    const size_t k = strlen(s->dir);
    if (!s->dir[0] || strncmp(path, s->dir, k) != 0 || path[k] != '/')
        return NULL;
    char staged[64]; /* the file's own name, not the staging folder's */
    snprintf(staged, sizeof staged, "%.63s", path + k + 1);
    if (cli_pathf(buf, n, "%s/%s", s->outdir, staged) != 0)
        snprintf(buf, n, "%s", staged);
    return buf;
}

void cli_staging_where(const CliStaging *s, SqError *err)
{
    char buf[sizeof err->where];
    if (shown_as(s, err->where, buf, sizeof buf))
        snprintf(err->where, sizeof err->where, "%s", buf);
    /* a library's message may name the staged file too (OpenEXR's does) */
    const size_t k = strlen(s->dir);
    char *at = k ? strstr(err->what, s->dir) : NULL;
    if (at && at[k] == '/') {
        char tail[sizeof err->what];
        snprintf(tail, sizeof tail, "%s", at + k);
        const size_t room = sizeof err->what - (size_t)(at - err->what);
        snprintf(at, room, "%s%s", s->outdir, tail); /* cut at what's size */
    }
}

const char *cli_staging_shown(const char *path, char *buf, size_t n)
{
    const CliStaging *s = open_staging;
    const char *shown = s ? shown_as(s, path, buf, n) : NULL;
    return shown ? shown : path;
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
