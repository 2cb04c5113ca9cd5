/* The presets a fit's screening starts from as well (--start, --no-starts; by default the
 * shipped complex and layered ones): loaded once the options are read. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "fit_job.h"
#include "squama/io.h"
#include "squama/preset.h"
#include "squama/search.h"

/* The shipped folders the default starts come from, under the presets folder: the
 * reaction-diffusion patterns the fit's own search rarely finds from random draws
 * (docs/recovery.md, session 48), and the layered skins. */
static const char *const DEFAULT_DIRS[] = {"complex", "layered"};

enum { STARTS_MAX = 256 };

static int ends_with_json(const char *s)
{
    size_t n = strlen(s);
    return n > 5 && strcmp(s + n - 5, ".json") == 0;
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The *.json files in dir (not its subfolders), sorted; *n of them in a malloc'd list of
 * malloc'd paths. 0, or -1 when the folder cannot be read or memory runs out. */
static int list_json(const char *dir, char ***out, int *n)
{
    *out = NULL;
    *n = 0;
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    char **v = NULL;
    int cap = 0, rc = 0;
    struct dirent *e;
    while (rc == 0 && (e = readdir(d))) {
        if (e->d_name[0] == '.' || !ends_with_json(e->d_name))
            continue;
        if (*n == cap) {
            char **w = realloc(v, sizeof *w * (size_t)(cap = cap ? 2 * cap : 16));
            if (!w) {
                rc = -1;
                break;
            }
            v = w;
        }
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        if (!(v[*n] = malloc(len)))
            rc = -1;
        else
            snprintf(v[(*n)++], len, "%s/%s", dir, e->d_name);
    }
    closedir(d);
    if (rc != 0) {
        for (int i = 0; i < *n; i++)
            free(v[i]);
        free(v);
        *n = 0;
        return -1;
    }
    qsort(v, (size_t)*n, sizeof *v, cmp_str);
    *out = v;
    return 0;
}

/* Loads path as a starting preset into s: 1 when taken, 0 when it is a preset the fit
 * cannot search (more than one layer, a layer over reaction-diffusion; why in *why), -1
 * with err set when it cannot be read or parsed. A preset taken has its file's bytes
 * hashed into the digest. */
static int load_one(CliStarts *s, const char *path, char *why, size_t nwhy, SqError *err)
{
    char *text;
    size_t len;
    if (sq_io_read_file(path, SQ_PRESET_MAX_BYTES, &text, &len, err) != SQ_OK)
        return -1;
    SqParams *p = &s->params[s->n];
    SqGenome g;
    SqError e;
    int took = sq_preset_parse(text, len, path, p, NULL, err) == SQ_OK ? 1 : -1;
    if (took > 0 && sq_genome_of(&g, p, &e) != SQ_OK) {
        snprintf(why, nwhy, "%s", e.what);
        took = 0;
    }
    if (took > 0 && !(s->path[s->n] = strdup(path))) {
        sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
        took = -1;
    }
    if (took > 0) {
        for (size_t i = 0; i < len; i++)
            s->digest = (s->digest ^ (unsigned char)text[i]) * 0x100000001b3u;
        s->n++;
    }
    free(text);
    return took;
}

/* A folder's presets: those the fit cannot search are skipped (with a warning unless
 * quiet). */
static SqStatus load_dir(CliStarts *s, const char *dir, int quiet, SqError *err)
{
    char **files;
    int nf;
    if (list_json(dir, &files, &nf) != 0)
        return sq_error_set(err, SQ_ERR_IO, dir, "cannot list the starting presets' folder");
    SqStatus st = SQ_OK;
    for (int i = 0; i < nf && st == SQ_OK; i++) {
        char why[sizeof ((SqError *)0)->what];
        if (s->n == STARTS_MAX)
            st = sq_error_set(err, SQ_ERR_INVALID, files[i], "more than %d starting presets", STARTS_MAX);
        else {
            const int took = load_one(s, files[i], why, sizeof why, err);
            if (took < 0)
                st = err->status;
            else if (took == 0 && !quiet)
                fprintf(stderr, "squama: warning: %s is not a start: the fit cannot search it (%s)\n", files[i],
                        why);
        }
    }
    for (int i = 0; i < nf; i++)
        free(files[i]);
    free(files);
    return st;
}

SqStatus cli_starts_load(CliStarts *s, int quiet, SqError *err)
{
    s->n = 0;
    s->digest = 0xcbf29ce484222325u;
    if (s->none)
        return SQ_OK;
    if (!(s->params = malloc(sizeof *s->params * STARTS_MAX)) || !(s->path = calloc(STARTS_MAX, sizeof *s->path)))
        return sq_error_set(err, SQ_ERR_NOMEM, "fit", "out of memory for the starting presets");
    if (s->nargs == 0) { /* the shipped ones, where they are installed; quietly none else */
        for (size_t k = 0; k < sizeof DEFAULT_DIRS / sizeof DEFAULT_DIRS[0]; k++) {
            char dir[4200];
            struct stat sb;
            snprintf(dir, sizeof dir, "%s/%s", cli_presets_dir(), DEFAULT_DIRS[k]);
            if (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode) && load_dir(s, dir, 1, err) != SQ_OK)
                return err->status;
        }
        return SQ_OK;
    }
    for (int a = 0; a < s->nargs; a++) {
        struct stat sb;
        if (stat(s->arg[a], &sb) != 0)
            return sq_error_set(err, SQ_ERR_IO, s->arg[a], "no such starting preset or folder");
        if (S_ISDIR(sb.st_mode)) {
            if (load_dir(s, s->arg[a], quiet, err) != SQ_OK)
                return err->status;
            continue;
        }
        char why[sizeof ((SqError *)0)->what];
        if (s->n == STARTS_MAX)
            return sq_error_set(err, SQ_ERR_INVALID, s->arg[a], "more than %d starting presets", STARTS_MAX);
        const int took = load_one(s, s->arg[a], why, sizeof why, err);
        if (took < 0)
            return err->status;
        if (took == 0)
            return sq_error_set(err, SQ_ERR_INVALID, s->arg[a], "the fit cannot start from this preset: %s", why);
    }
    return SQ_OK;
}

void cli_starts_free(CliStarts *s)
{
    for (int i = 0; s->path && i < s->n; i++)
        free(s->path[i]);
    free(s->path);
    free(s->params);
    s->path = NULL;
    s->params = NULL;
    s->n = 0;
}

void cli_starts_json(cJSON *parent, char *const *path, int n, int screened)
{
    cJSON *st = cJSON_AddObjectToObject(parent, "starts");
    cJSON *sp = cJSON_AddArrayToObject(st, "presets");
    for (int i = 0; i < n; i++)
        cJSON_AddItemToArray(sp, cJSON_CreateString(path[i]));
    cJSON_AddNumberToObject(st, "screened", screened);
}
