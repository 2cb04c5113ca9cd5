/* squama params: the parameter table as a table, JSON or Markdown (docs/parameters.md). */
#define _POSIX_C_SOURCE 200809L

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "json_util.h"
#include "squama/params.h"

static const char help[] =
    "usage: squama params [--json | --markdown] [FILTER...]\n"
    "\n"
    "Lists every parameter of the procedural model: name (as the thesis spells it),\n"
    "type, default, hard range, the thesis' suggested range, group and help. FILTER\n"
    "words keep the parameters whose name or group contains one of them (any case).\n"
    "\n"
    "options:\n"
    "  --json       an array of objects, one per parameter\n"
    "  --markdown   the reference page docs/parameters.md\n"
    "  -h, --help   show this help\n";

static const char *origin_name(SqParamOrigin o)
{
    switch (o) {
    case SQ_ORIGIN_THESIS: return "thesis";
    case SQ_ORIGIN_THESIS_D11: return "thesis-d11";
    case SQ_ORIGIN_SQUAMA: return "squama";
    }
    return "?";
}

static int matches(const SqParamSpec *s, int nfilters, char **filters)
{
    if (nfilters == 0)
        return 1;
    for (int i = 0; i < nfilters; i++) {
        size_t n = strlen(filters[i]);
        for (const char *c = s->name; *c; c++)
            if (strncasecmp(c, filters[i], n) == 0)
                return 1;
        for (const char *c = s->group; *c; c++)
            if (strncasecmp(c, filters[i], n) == 0)
                return 1;
    }
    return 0;
}

static void fmt_range(const SqParamSpec *s, double lo, double hi, char *buf, size_t n)
{
    if (s->type == SQ_PT_CA)
        snprintf(buf, n, "-");
    else if (s->type == SQ_PT_BOOL)
        snprintf(buf, n, "false|true");
    else if (s->type == SQ_PT_ENUM)
        snprintf(buf, n, "%s..%s", s->choices[(int)lo], s->choices[(int)hi]);
    else
        snprintf(buf, n, "%.10g..%.10g", lo, hi);
}

static void print_table(const SqParams *def, int nf, char **filters)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    const char *group = NULL;
    printf("  %-31s %-5s %-26s %-16s %-14s %s\n", "NAME", "TYPE", "DEFAULT", "RANGE",
           "SUGGESTED", "HELP");
    for (size_t i = 0; i < n; i++) {
        const SqParamSpec *s = &t[i];
        if (!matches(s, nf, filters))
            continue;
        if (!group || strcmp(group, s->group) != 0) {
            printf("\n%s\n", s->group);
            group = s->group;
        }
        char dv[256], range[64], sugg[64];
        sq_param_format(def, s, 6, dv, sizeof dv);
        if (s->type == SQ_PT_CA)
            snprintf(dv, sizeof dv, "(Figure 4.9)");
        fmt_range(s, s->min, s->max, range, sizeof range);
        fmt_range(s, s->smin, s->smax, sugg, sizeof sugg);
        printf("  %-31s %-5s %-26s %-16s %-14s %s\n", s->name, sq_param_type_name(s->type), dv,
               range, sugg, s->help);
    }
}

static int print_json(const SqParams *def, int nf, char **filters)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    cJSON *arr = cJSON_CreateArray();
    for (size_t i = 0; arr && i < n; i++) {
        const SqParamSpec *s = &t[i];
        if (!matches(s, nf, filters))
            continue;
        cJSON *o = cJSON_CreateObject();
        char dv[4096];
        cJSON_AddStringToObject(o, "name", s->name);
        cJSON_AddStringToObject(o, "type", sq_param_type_name(s->type));
        cJSON_AddStringToObject(o, "group", s->group);
        sq_param_format(def, s, 0, dv, sizeof dv);
        cJSON_AddStringToObject(o, "default", dv);
        if (s->type != SQ_PT_CA) {
            cJSON_AddNumberToObject(o, "min", s->min);
            cJSON_AddNumberToObject(o, "max", s->max);
            cJSON_AddNumberToObject(o, "suggested_min", s->smin);
            cJSON_AddNumberToObject(o, "suggested_max", s->smax);
        }
        if (s->choices) {
            cJSON *c = cJSON_AddArrayToObject(o, "choices");
            for (int k = 0; s->choices[k]; k++)
                cJSON_AddItemToArray(c, cJSON_CreateString(s->choices[k]));
        }
        cJSON_AddStringToObject(o, "origin", origin_name(s->origin));
        cJSON_AddStringToObject(o, "ref", s->ref);
        cJSON_AddBoolToObject(o, "log_scale", (s->flags & SQ_PF_LOG) != 0);
        cJSON_AddBoolToObject(o, "searched", (s->flags & SQ_PF_NOSEARCH) == 0);
        cJSON_AddStringToObject(o, "help", s->help);
        cJSON_AddItemToArray(arr, o);
    }
    char *text = arr ? sq__json_print(arr) : NULL;
    cJSON_Delete(arr);
    if (!text) {
        SqError e;
        sq_error_set(&e, SQ_ERR_NOMEM, "", "out of memory");
        return cli_fail(&e);
    }
    fputs(text, stdout);
    free(text);
    return CLI_OK;
}

/* Escapes '|' for a Markdown table cell. */
static void md_cell(const char *s)
{
    for (; *s; s++) {
        if (*s == '|')
            fputs("\\|", stdout);
        else
            putchar(*s);
    }
}

static void print_markdown(const SqParams *def)
{
    size_t n, counts[3] = {0, 0, 0};
    const SqParamSpec *t = sq_params_table(&n);
    for (size_t i = 0; i < n; i++)
        counts[t[i].origin]++;
    printf("# squama parameters\n\n"
           "<!-- Generated by `squama params --markdown`; do not edit. A test fails when this\n"
           "     file is stale: regenerate it with `scripts/update-docs`. -->\n\n"
           "Every parameter of the procedural model, as presets name them. The thesis\n"
           "(Pinheiro 2017) has 59: %zu named in its text (Chapters 4-5) and %zu known only\n"
           "from the parameter listing of its Appendix D.11 (origin `thesis-d11`, with the\n"
           "label there in *ref*). squama adds %zu (origin `squama`). Colours are\n"
           "gamma-space RGBA in [0,1]. *Range* is what a preset may hold; *suggested* is the\n"
           "thesis' advice where it gives one, otherwise squama's.\n",
           counts[SQ_ORIGIN_THESIS], counts[SQ_ORIGIN_THESIS_D11], counts[SQ_ORIGIN_SQUAMA]);
    /* the groups a layer object takes, as the table has them */
    printf("\n`Pattern_Layers` stacks up to %d whole patterns over the base pattern, bottom\n"
           "first. Each is an object of the parameters of the groups",
           SQ_MAX_PATTERN_LAYERS);
    const char *last = NULL;
    for (size_t i = 0; i < n; i++) {
        if (!sq_param_in_layer(&t[i]) || (t[i].flags & SQ_PF_LAYER) ||
            (last && strcmp(last, t[i].group) == 0))
            continue;
        printf("%s*%s*", last ? ", " : " ", t[i].group);
        last = t[i].group;
    }
    printf(",\nplus `Layer_Blend` and `Layer_Opacity`; a missing key takes its default below.\n"
           "A layer has its own post-process and warp, draws its own random instance (seeded\n"
           "from `Seed` and its index) and is blended over the colour map below it; the\n"
           "outline stays with the base pattern.\n");
    const char *group = NULL;
    for (size_t i = 0; i < n; i++) {
        const SqParamSpec *s = &t[i];
        if (!group || strcmp(group, s->group) != 0) {
            printf("\n## %s\n\n| name | type | default | range | suggested | origin | ref | help |\n"
                   "|---|---|---|---|---|---|---|---|\n",
                   s->group);
            group = s->group;
        }
        char dv[4096], range[64], sugg[64];
        sq_param_format(def, s, 6, dv, sizeof dv);
        fmt_range(s, s->min, s->max, range, sizeof range);
        fmt_range(s, s->smin, s->smax, sugg, sizeof sugg);
        printf("| `%s` | %s | ", s->name, sq_param_type_name(s->type));
        md_cell(dv);
        printf(" | %s | %s | %s | ", range, sugg, origin_name(s->origin));
        md_cell(s->ref);
        printf(" | ");
        md_cell(s->help);
        printf(" |\n");
    }
}

int cmd_params(int argc, char **argv)
{
    static const struct option opts[] = {{"json", no_argument, NULL, 'j'},
                                         {"markdown", no_argument, NULL, 'm'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    int json = 0, md = 0, c;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "+:h", opts, NULL)) != -1) {
        switch (c) {
        case 'j': json = 1; break;
        case 'm': md = 1; break;
        case 'h': fputs(help, stdout); return CLI_OK;
        default: return cli_bad_option("params", argv, c, opts);
        }
    }
    if (json && md)
        return cli_usage("params", "--json and --markdown exclude each other");
    SqParams def;
    sq_params_default(&def);
    if (md) {
        if (optind < argc)
            return cli_usage("params", "--markdown lists every parameter: drop the filter");
        print_markdown(&def);
        return CLI_OK;
    }
    if (json)
        return print_json(&def, argc - optind, argv + optind);
    print_table(&def, argc - optind, argv + optind);
    return CLI_OK;
}
