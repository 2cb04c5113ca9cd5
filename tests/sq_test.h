/* Shared test helpers: cmocka and paths. */
#ifndef SQ_TEST_H
#define SQ_TEST_H

#include <dirent.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

/* SQ_TEST_FILTER=name (cmocka's pattern: * and ? wildcards) runs only the tests it
 * matches, e.g. SQ_TEST_FILTER=an_invisible* build/tests/test_fit. */
__attribute__((constructor)) static void sq_test_filter(void)
{
    const char *f = getenv("SQ_TEST_FILTER");
    if (f && *f)
        cmocka_set_test_filter(f);
}

/* Asserts that `hay` contains `needle`, printing both when it does not. */
#define assert_contains(hay, needle)                                                  \
    do {                                                                              \
        const char *h_ = (hay), *n_ = (needle);                                       \
        if (!strstr(h_, n_))                                                          \
            fail_msg("expected \"%s\" to contain \"%s\"", h_, n_);                    \
    } while (0)

/* Set in the sanitized build (scripts/build --sanitize), where everything runs 3 to 5 times
 * slower. Checks of a fit's quality, which need long fits, and repeats that only compare
 * results (one thread against two) run in the plain build alone: the sanitized build runs
 * the same code in the shorter checks. */
#ifdef SQUAMA_SANITIZED
static const int sq_sanitized = 1;
#else
static const int sq_sanitized = 0;
#endif

/* Skips a check that runs in the plain build alone (see sq_sanitized). */
#define SKIP_WHEN_SANITIZED()                                                         \
    do {                                                                              \
        if (sq_sanitized) {                                                           \
            printf("  skipped under the sanitizers: the plain build runs it\n");     \
            skip();                                                                   \
        }                                                                             \
    } while (0)

/* SQUAMA_SOURCE_DIR "/" rel into a static buffer (one per call site is enough). */
static inline const char *src_path(char *buf, size_t n, const char *rel)
{
    snprintf(buf, n, "%s/%s", SQUAMA_SOURCE_DIR, rel);
    return buf;
}

static inline const char *tmp_path(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", SQUAMA_TEST_TMP, name);
    return buf;
}

/* Reads a whole file into a buffer of exactly its size (no terminating NUL), so that
 * AddressSanitizer sees any read past the end, as the fuzzers do. */
static inline char *read_exact(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    *n = 0;
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc(len > 0 ? (size_t)len : 1);
    *n = buf ? fread(buf, 1, (size_t)len, f) : 0;
    fclose(f);
    return buf;
}

/* Calls fn(path, ctx) for every file under dir whose name ends in suffix ("" for all;
 * names starting with '.' are skipped), descending into subfolders when recurse is set.
 * Returns the number of files, or -1 when dir cannot be opened. */
static inline int for_each_file(const char *dir, const char *suffix, int recurse,
                                void (*fn)(const char *path, void *ctx), void *ctx)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int count = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        char path[4096];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path)
            continue;
        struct stat st;
        if (stat(path, &st) != 0)
            continue;
        size_t len = strlen(e->d_name), k = strlen(suffix);
        if (S_ISDIR(st.st_mode)) {
            if (recurse) {
                int c = for_each_file(path, suffix, recurse, fn, ctx);
                count += c > 0 ? c : 0;
            }
        } else if (len >= k && strcmp(e->d_name + len - k, suffix) == 0) {
            fn(path, ctx);
            count++;
        }
    }
    closedir(d);
    return count;
}

#endif
