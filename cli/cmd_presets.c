/* squama presets: list the shipped presets, validate and normalise preset files. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "json_util.h"
#include "squama/io.h"
#include "squama/preset.h"

static const char help[] =
    "usage: squama presets list [--json] [DIR]\n"
    "       squama presets validate [--quiet] FILE...\n"
    "       squama presets format FILE [-o OUT]\n"
    "\n"
    "list      the presets (*.json) and cellular-automaton descriptors (*.ca) under DIR,\n"
    "          by default the shipped presets ($SQUAMA_PRESETS overrides where they are)\n"
    "validate  loads each FILE strictly (presets as JSON, anything else as a thesis CA\n"
    "          descriptor) and reports every problem with its place; exit 1 if any fails\n"
    "format    writes FILE back in canonical form, every parameter present, to OUT\n"
    "          (atomically) or to standard output\n"
    "\n"
    "options:\n"
    "  --json       list: an array of {path, kind, name, pattern}\n"
    "  -q, --quiet  validate: print only problems\n"
    "  -o OUT       format: write here instead of standard output\n"
    "  -h, --help   show this help\n";

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* ---- list ---- */

typedef struct PathList {
    char **v;
    size_t n, cap;
} PathList;

static int push(PathList *l, const char *path)
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? l->cap * 2 : 64;
        char **v = realloc(l->v, cap * sizeof *v);
        if (!v)
            return -1;
        l->v = v;
        l->cap = cap;
    }
    if (!(l->v[l->n] = strdup(path)))
        return -1;
    l->n++;
    return 0;
}

static int collect(const char *dir, PathList *l, int depth)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    struct dirent *e;
    int rc = 0;
    while (rc == 0 && (e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        struct stat st;
        if (stat(path, &st) != 0)
            continue;
        if (S_ISDIR(st.st_mode)) {
            if (depth < 8 && collect(path, l, depth + 1) == -2)
                rc = -2; /* out of memory; an unreadable subfolder is skipped */
        } else if (S_ISREG(st.st_mode) && (has_suffix(path, ".json") || has_suffix(path, ".ca")))
            rc = push(l, path) ? -2 : 0;
    }
    closedir(d);
    return rc;
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int list(const char *dir, int json)
{
    PathList l = {0};
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        SqError e;
        sq_error_set(&e, SQ_ERR_IO, dir, "no presets folder here");
        return cli_fail(&e);
    }
    if (collect(dir, &l, 0) == -2) {
        SqError e;
        sq_error_set(&e, SQ_ERR_NOMEM, dir, "out of memory listing presets");
        return cli_fail(&e);
    }
    qsort(l.v, l.n, sizeof *l.v, cmp_str);
    size_t skip = strlen(dir) + 1;
    cJSON *arr = json ? cJSON_CreateArray() : NULL;
    int bad = 0;
    for (size_t i = 0; i < l.n; i++) {
        const char *rel = l.v[i] + skip;
        SqError err;
        const char *kind, *name = "", *pattern = "";
        SqPresetInfo info;
        static SqParams p;
        SqCa ca;
        if (has_suffix(l.v[i], ".json")) {
            kind = "preset";
            if (sq_preset_load(l.v[i], &p, &info, &err) != SQ_OK) {
                cli_fail(&err);
                bad = 1;
                continue;
            }
            name = info.name;
            pattern = sq_pattern_type_name(p.Pattern_Type);
        } else {
            kind = "ca";
            if (sq_ca_load(l.v[i], &ca, &err) != SQ_OK) {
                cli_fail(&err);
                bad = 1;
                continue;
            }
            pattern = sq_ca_type_name(ca.type);
        }
        if (json) {
            cJSON *o = cJSON_CreateObject();
            cJSON_AddStringToObject(o, "path", l.v[i]);
            cJSON_AddStringToObject(o, "kind", kind);
            cJSON_AddStringToObject(o, "name", name);
            cJSON_AddStringToObject(o, "pattern", pattern);
            cJSON_AddItemToArray(arr, o);
        } else {
            printf("%-44s %-7s %-13s %s\n", rel, kind, pattern, name);
        }
    }
    if (json) {
        char *text = sq__json_print(arr);
        if (text)
            fputs(text, stdout);
        free(text);
        cJSON_Delete(arr);
    }
    for (size_t i = 0; i < l.n; i++)
        free(l.v[i]);
    free(l.v);
    return bad ? CLI_FAIL : CLI_OK;
}

/* ---- validate ---- */

static int validate(int n, char **files, int quiet)
{
    int failed = 0;
    for (int i = 0; i < n; i++) {
        SqError err;
        if (has_suffix(files[i], ".json")) {
            static SqParams p;
            SqPresetInfo info;
            if (sq_preset_load(files[i], &p, &info, &err) != SQ_OK) {
                cli_fail(&err);
                failed++;
            } else if (!quiet) {
                printf("ok  %s  (%s%s%s)\n", files[i], sq_pattern_type_name(p.Pattern_Type),
                       info.name[0] ? ", " : "", info.name);
            }
        } else {
            SqCa ca;
            if (sq_ca_load(files[i], &ca, &err) != SQ_OK) {
                cli_fail(&err);
                failed++;
            } else if (!quiet) {
                printf("ok  %s  (%s automaton, %d cells, %d epochs)\n", files[i],
                       sq_ca_type_name(ca.type), ca.ncells, ca.epochs);
            }
        }
    }
    if (failed && n > 1)
        fprintf(stderr, "squama: %d of %d files failed validation\n", failed, n);
    return failed ? CLI_FAIL : CLI_OK;
}

/* ---- format ---- */

static int format(const char *file, const char *out)
{
    static SqParams p;
    SqPresetInfo info;
    SqError err;
    if (sq_preset_load(file, &p, &info, &err) != SQ_OK)
        return cli_fail(&err);
    char *text = sq_preset_to_json(&p, &info, &err);
    if (!text)
        return cli_fail(&err);
    int rc = CLI_OK;
    if (out) {
        if (sq_io_write_file(out, text, strlen(text), &err) != SQ_OK)
            rc = cli_fail(&err);
    } else {
        fputs(text, stdout);
    }
    free(text);
    return rc;
}

int cmd_presets(int argc, char **argv)
{
    static const struct option opts[] = {{"json", no_argument, NULL, 'j'},
                                         {"quiet", no_argument, NULL, 'q'},
                                         {"output", required_argument, NULL, 'o'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    int json = 0, quiet = 0, c;
    const char *out = NULL;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":hqo:", opts, NULL)) != -1) {
        switch (c) {
        case 'j': json = 1; break;
        case 'q': quiet = 1; break;
        case 'o': out = optarg; break;
        case 'h': fputs(help, stdout); return CLI_OK;
        case ':':
        case '?':
        default:
            return cli_bad_option("presets", argv, c, opts);
        }
    }
    if (optind >= argc)
        return cli_usage("presets", "say what to do: list, validate or format");
    const char *sub = argv[optind++];
    int nargs = argc - optind;
    char **args = argv + optind;
    if (strcmp(sub, "list") == 0) {
        if (nargs > 1)
            return cli_usage("presets", "list takes at most one folder");
        return list(nargs ? args[0] : cli_presets_dir(), json);
    }
    if (strcmp(sub, "validate") == 0) {
        if (nargs == 0)
            return cli_usage("presets", "validate needs at least one FILE");
        return validate(nargs, args, quiet);
    }
    if (strcmp(sub, "format") == 0) {
        if (nargs != 1)
            return cli_usage("presets", "format takes exactly one FILE");
        return format(args[0], out);
    }
    return cli_usage("presets", "unknown subcommand '%s' (list, validate or format)", sub);
}
