/* squama seed: starting presets for artists: diverse ones of a category, variations around a
 * preset, or the fitted alternatives for a photo; with a summary and a contact sheet. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "fit_job.h"
#include "json_util.h"
#include "sheet.h"
#include "squama/fitness.h"
#include "squama/io.h"
#include "squama/preset.h"
#include "squama/search.h"

static const char help[] =
    "usage: squama seed --category C -o DIR [-n N] [--seed S]\n"
    "       squama seed --near PRESET -o DIR [-n N] [--distance D] [--seed S]\n"
    "       squama seed --from-photo PHOTO -o DIR [--mask M] [--line L] [--budget 60s | --evals N]\n"
    "                                             [--start P ... | --no-starts]\n"
    "\n"
    "Starting presets for an artist to tweak by hand.\n"
    "\n"
    "--category C draws a pool of random presets of pattern type C (none, longitudinal,\n"
    "  transversal, spots, other_simple, complex; or layered: one layer of stripes, bands or\n"
    "  spots over another simple pattern, the pair at random) over the genes' suggested ranges, with\n"
    "  colours from palettes of snake colours; drops the implausible ones (a pattern covering\n"
    "  almost none or almost all of the skin, or hardly differing from the background); and\n"
    "  picks the N most different from each other: farthest-point sampling on the feature\n"
    "  distance (the fit's five objectives on a 128-pixel render's dorsal band, each over its\n"
    "  typical value between random presets, averaged: about 1 between unrelated presets).\n"
    "--near PRESET makes N variations of PRESET: every gene moved by a normal step of\n"
    "  standard deviation D of its suggested range (default 0.1; colours in CIELAB), the\n"
    "  category and structure (automaton, reaction-diffusion system, layers) kept; of 4N\n"
    "  such variations, the N most different among the nearer half are kept, each with its\n"
    "  feature distance to PRESET (which grows with D; D itself is a step in the genes).\n"
    "--from-photo PHOTO fits the generator to the photo (as 'squama fit', from the same\n"
    "  starting presets) and writes its best preset, each other kind's best by score, then\n"
    "  the rest of the fit's Pareto front (at most N of them), each with its distance to the\n"
    "  photo.\n"
    "\n"
    "DIR (new or empty) receives, all at once when everything is ready:\n"
    "  NN.json     the presets ('squama render' takes them as they are)\n"
    "  seeds.json  per preset its category, the feature distance to the nearest other pick\n"
    "              and to the original (PRESET or PHOTO); how the pool went; the fit's starts\n"
    "  sheet.png   a contact sheet of the presets, labelled\n"
    "\n"
    "options:\n"
    "  -c, --category C     pattern type of the presets, or layered\n"
    "      --near PRESET    variations around this preset\n"
    "      --from-photo P   the fit of this photo: its best, each kind's best, its front\n"
    "  -o, --output DIR     where the presets go (required; new or empty)\n"
    "  -n N                 how many presets, 1 to 256 (default 12; --from-photo: all\n"
    "                       the fit offers, at most 24)\n"
    "  -d, --distance D     --near: the genes' step, 0.01 to 1 (default 0.1)\n"
    "  -s, --seed S         the seed of every random choice (default 1)\n"
    "      --pool K         candidates drawn per preset (default 12; --near 4)\n"
    "  -m, --mask MASK      --from-photo: the snake's mask\n"
    "  -l, --line LINE      --from-photo: the body's centre line and width (see 'squama prepare')\n"
    "  -b, --budget TIME    --from-photo: the wall time of it all, as fit's (default 60s)\n"
    "      --evals N        --from-photo: an evaluation budget instead (deterministic)\n"
    "      --start P        --from-photo: a preset, or a folder of presets, the fit's screening\n"
    "                       starts from (repeatable; default the shipped complex/ and layered/)\n"
    "      --no-starts      --from-photo: no starting presets\n"
    "      --size N         the sheet's tiles, 32 to 1024 pixels (default 256)\n"
    "      --cols C         the sheet's columns (default: about the square root)\n"
    "  -j, --threads N      threads (default: all cores); the result does not depend on it\n"
    "  -q, --quiet          no progress and no summary\n"
    "      --json           the summary (seeds.json) on stdout\n"
    "  -h, --help           show this help\n";

enum { MODE_CATEGORY = 1, MODE_NEAR, MODE_PHOTO };

static const char *const mode_names[] = {"", "category", "near", "photo"};

typedef struct Progress {
    int tty, quiet;
    const char *what;
} Progress;

static void on_progress(const SqSeedProgress *p, void *ctx)
{
    const Progress *x = ctx;
    if (!x->tty || x->quiet)
        return;
    fprintf(stderr, "\r%s: %-6s %4d/%-4d\033[K", x->what, p->stage, p->done, p->total);
    fflush(stderr);
}

static void on_fit_progress(const SqFitProgress *p, void *ctx)
{
    const Progress *x = ctx;
    if (!x->tty || x->quiet)
        return;
    fprintf(stderr, "\r%s: fit %-7s gen %4d  %6ld evals  %5.0f s  best %.3f %-12s\033[K", x->what, p->stage,
            p->generation, p->evals, p->elapsed, p->best_score, sq_fit_kind_name(p->category));
    fflush(stderr);
}

/* 1 when path does not exist or is an empty folder; 0 with err filled otherwise. */
static int usable_dir(const char *path, SqError *err)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return errno == ENOENT ? 1 : (sq_error_set(err, SQ_ERR_IO, path, "cannot use the folder: %s", strerror(errno)), 0);
    if (!S_ISDIR(st.st_mode)) {
        sq_error_set(err, SQ_ERR_IO, path, "exists and is not a folder");
        return 0;
    }
    DIR *d = opendir(path);
    if (!d) {
        sq_error_set(err, SQ_ERR_IO, path, "cannot read the folder: %s", strerror(errno));
        return 0;
    }
    struct dirent *e;
    int empty = 1;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0)
            empty = 0;
    closedir(d);
    if (!empty)
        sq_error_set(err, SQ_ERR_IO, path,
                     "the output folder is not empty; squama seed writes into a new or empty folder");
    return empty;
}

static SqStatus stage_file(CliStaging *s, const char *name, const void *data, size_t len, SqError *err)
{
    char path[4200];
    SqStatus st = cli_staging_path(s, name, path, sizeof path, err);
    return st == SQ_OK ? sq_io_write_file(path, data, len, err) : st;
}

typedef struct Seeding {
    int mode, category;
    const char *origin;      /* the preset or photo */
    const char *origin_name; /* its "name", or file name */
    uint64_t seed;
    double distance;
    const SqFitResult *fit;
    const CliStarts *starts; /* the fit's starting presets */
    const SqSeedResult *r;
} Seeding;

static cJSON *summary(const Seeding *s)
{
    const SqSeedResult *r = s->r;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", "squama-seeds/1");
    cJSON_AddStringToObject(root, "mode", mode_names[s->mode]);
    cJSON_AddStringToObject(root, "category", sq_fit_kind_name(s->category));
    if (s->origin)
        cJSON_AddStringToObject(root, s->mode == MODE_PHOTO ? "photo" : "preset", s->origin);
    cJSON_AddNumberToObject(root, "seed", (double)s->seed);
    if (s->mode == MODE_NEAR)
        cJSON_AddItemToObject(root, "gene_step", sq__json_exact_number(s->distance));
    cJSON_AddStringToObject(root, "distance",
                            "feature distance: the fit's five objectives between 128-pixel renders' dorsal "
                            "bands (view scale 1), both ways round, each over its typical value between two "
                            "random presets, averaged; about 1 between unrelated presets");
    if (s->mode == MODE_PHOTO) {
        cJSON_AddStringToObject(root, "to_origin",
                                "the fit's objectives against the photo (its view scale), on the same scale");
        cli_starts_json(root, s->starts ? s->starts->path : NULL, s->starts ? s->starts->n : 0,
                        s->fit ? s->fit->starts_used : 0);
    }
    cJSON *pool = cJSON_AddObjectToObject(root, "pool");
    cJSON_AddNumberToObject(pool, "drawn", r->drawn);
    cJSON_AddNumberToObject(pool, "failed", r->failed);
    cJSON_AddNumberToObject(pool, "implausible", r->implausible);
    cJSON_AddNumberToObject(pool, "kept", r->npool);
    cJSON_AddItemToObject(root, "min_distance", sq__json_exact_number(isfinite(r->min_distance) ? r->min_distance : 0));
    cJSON *arr = cJSON_AddArrayToObject(root, "presets");
    for (int i = 0; i < r->n; i++) {
        const SqSeedCandidate *c = &r->picks[i];
        char file[32];
        cJSON *e = cJSON_CreateObject();
        snprintf(file, sizeof file, "%02d.json", i);
        cJSON_AddStringToObject(e, "preset", file);
        cJSON_AddStringToObject(e, "category", sq_fit_kind_name(sq_fit_kind_of(&c->params)));
        if (c->nearest_index >= 0) {
            cJSON_AddItemToObject(e, "nearest", sq__json_exact_number(c->nearest));
            snprintf(file, sizeof file, "%02d.json", c->nearest_index);
            cJSON_AddStringToObject(e, "nearest_preset", file);
        }
        if (isfinite(c->to_origin))
            cJSON_AddItemToObject(e, "to_origin", sq__json_exact_number(c->to_origin));
        if (c->params.Pattern_Type != SQ_PATTERN_NONE) {
            cJSON_AddItemToObject(e, "coverage", sq__json_exact_number(c->coverage));
            cJSON_AddItemToObject(e, "contrast", sq__json_exact_number(c->contrast));
        }
        if (s->fit) {
            const SqFitCandidate *f = c->fitted;
            if (c->source >= 0)
                cJSON_AddNumberToObject(e, "front_index", c->source);
            else
                cJSON_AddBoolToObject(e, "kind_best", 1); /* its kind's best, not in the front */
            cJSON *o = cJSON_AddObjectToObject(e, "objectives");
            for (int k = 0; k < SQ_OBJ_COUNT; k++)
                cJSON_AddItemToObject(o, sq_fit_objective_name(k), sq__json_exact_number(f->obj[k]));
            cJSON_AddItemToObject(e, "score", sq__json_exact_number(f->score));
            cJSON_AddItemToObject(e, "view_scale", sq__json_exact_number(f->view_scale));
        }
        cJSON_AddItemToArray(arr, e);
    }
    return root;
}

/* The preset's name and notes: where it came from. */
static void preset_info(const Seeding *s, int i, SqPresetInfo *info)
{
    const SqSeedCandidate *c = &s->r->picks[i];
    const char *cat = sq_fit_kind_name(sq_fit_kind_of(&c->params));
    char near[96] = "";
    if (c->nearest_index >= 0)
        snprintf(near, sizeof near, "; feature distance to the nearest other pick (%02d) %.3f", c->nearest_index,
                 c->nearest);
    switch (s->mode) {
    case MODE_CATEGORY:
        snprintf(info->name, sizeof info->name, "seed %s %02d", cat, i);
        snprintf(info->notes, sizeof info->notes,
                 "squama seed --category %s --seed %llu: pick %d of %d plausible random presets, by farthest-point "
                 "sampling in feature space%s",
                 cat, (unsigned long long)s->seed, i + 1, s->r->npool, near);
        break;
    case MODE_NEAR:
        snprintf(info->name, sizeof info->name, "%.200s, variation %02d", s->origin_name, i);
        snprintf(info->notes, sizeof info->notes,
                 "squama seed --near %s --distance %g --seed %llu: a variation (genes moved by normal steps of "
                 "%g of their ranges); feature distance to the original %.3f%s",
                 s->origin, s->distance, (unsigned long long)s->seed, s->distance, c->to_origin, near);
        break;
    default: {
        char which[40], what[128]; /* a front member, or a kind's best outside the front */
        if (c->source < 0) {
            snprintf(which, sizeof which, "the best %s skin", cat);
            snprintf(what, sizeof what, "the fit's best %s skin (each kind's best follows the champion)", cat);
        } else {
            snprintf(which, sizeof which, "front %02d", c->source);
            snprintf(what, sizeof what, "member %d of the fit's Pareto front (best first)", c->source);
        }
        snprintf(info->name, sizeof info->name, "fit of %.200s, %s", s->origin_name, which);
        snprintf(info->notes, sizeof info->notes,
                 "squama seed --from-photo %s --seed %llu: %s, view scale %.3f; distance to the photo %.3f%s",
                 s->origin, (unsigned long long)s->seed, what, c->fitted->view_scale, c->to_origin, near);
        break;
    }
    }
}

/* Every file into a temporary folder beside outdir, the sheet last, then the folder renamed
 * to outdir: either all of it appears or none. */
static SqStatus write_all(const char *outdir, const Seeding *s, int size, int cols, int threads, int json,
                          SqError *err)
{
    const SqSeedResult *r = s->r;
    CliStaging stg = {0};
    size_t len = strlen(outdir);
    while (len > 1 && outdir[len - 1] == '/') /* "out/" -> "out.tmp-..." */
        len--;
    /* the parent first: mkdtemp makes one folder only */
    char pattern[4200];
    snprintf(pattern, sizeof pattern, "%.*s", (int)len, outdir);
    char *slash = strrchr(pattern, '/');
    if (slash && slash != pattern) {
        *slash = '\0';
        if (cli_mkdirs(pattern) != 0)
            return sq_error_set(err, SQ_ERR_IO, pattern, "cannot create the folder: %s", strerror(errno));
    }
    snprintf(pattern, sizeof pattern, "%.*s.tmp-XXXXXX", (int)len, outdir);
    if (cli_staging_open(&stg, pattern, outdir, r->n + 2, err) != SQ_OK)
        return err->status;
    SqStatus st = SQ_OK;
    SqPresetInfo *info = malloc(sizeof *info);
    char(*labels)[64] = malloc(sizeof *labels * (size_t)r->n);
    const char **lp = malloc(sizeof *lp * (size_t)r->n);
    SqParams *presets = malloc(sizeof *presets * (size_t)r->n);
    if (!info || !labels || !lp || !presets)
        st = sq_error_set(err, SQ_ERR_NOMEM, outdir, "out of memory");
    for (int i = 0; i < r->n && st == SQ_OK; i++) {
        memset(info, 0, sizeof *info);
        preset_info(s, i, info);
        char *text = sq_preset_to_json(&r->picks[i].params, info, err);
        if (!text) {
            st = err->status;
            break;
        }
        char name[32];
        snprintf(name, sizeof name, "%02d.json", i);
        st = stage_file(&stg, name, text, strlen(text), err);
        free(text);
        presets[i] = r->picks[i].params;
        const SqSeedCandidate *c = &r->picks[i];
        if (s->mode == MODE_CATEGORY)
            snprintf(labels[i], sizeof labels[i], "%02d  nearest %.2f", i, c->nearest_index >= 0 ? c->nearest : 0);
        else
            snprintf(labels[i], sizeof labels[i], "%02d  %s %.2f", i, s->mode == MODE_NEAR ? "from original" : "from photo",
                     c->to_origin);
        lp[i] = labels[i];
    }
    char *text = NULL;
    if (st == SQ_OK) {
        cJSON *root = summary(s);
        text = sq__json_print(root);
        cJSON_Delete(root);
        st = text ? stage_file(&stg, "seeds.json", text, strlen(text), err)
                  : sq_error_set(err, SQ_ERR_NOMEM, outdir, "out of memory");
    }
    if (st == SQ_OK) {
        char path[4200];
        SqGenOptions go = sq_gen_options_default(size);
        go.threads = threads;
        st = cli_staging_path(&stg, "sheet.png", path, sizeof path, err);
        if (st == SQ_OK)
            st = cli_sheet_write(path, presets, lp, r->n, size, &cols, go, err);
    }
    if (st == SQ_OK) {
        /* DIR was checked new or empty; a rename over an empty folder replaces it. mkdtemp
         * made the folder private (0700): it gets the mode of the empty folder it replaces,
         * or a new folder's under the umask */
        struct stat was;
        if (stat(outdir, &was) == 0) {
            chmod(stg.dir, was.st_mode & 07777);
        } else {
            const mode_t mask = umask(0);
            umask(mask);
            chmod(stg.dir, 0777 & ~mask);
        }
        if (rename(stg.dir, outdir) != 0)
            st = sq_error_set(err, SQ_ERR_IO, outdir, "cannot move the presets into place: %s", strerror(errno));
        else /* in place: nothing of it is temporary now */
            cli_staging_release(&stg, 0);
    }
    if (st == SQ_OK && json)
        fputs(text, stdout);
    free(text);
    free(info);
    free(labels);
    free(lp);
    free(presets);
    cli_staging_free(&stg);
    return st;
}

int cmd_seed(int argc, char **argv)
{
    enum { O_NEAR = 1000, O_PHOTO, O_POOL, O_EVALS, O_SIZE, O_COLS, O_JSON, O_START, O_NO_STARTS };
    static const struct option opts[] = {
        {"category", required_argument, NULL, 'c'}, {"near", required_argument, NULL, O_NEAR},
        {"from-photo", required_argument, NULL, O_PHOTO}, {"output", required_argument, NULL, 'o'},
        {"distance", required_argument, NULL, 'd'}, {"seed", required_argument, NULL, 's'},
        {"pool", required_argument, NULL, O_POOL},  {"mask", required_argument, NULL, 'm'}, {"line", required_argument, NULL, 'l'},
        {"budget", required_argument, NULL, 'b'},   {"evals", required_argument, NULL, O_EVALS},
        {"size", required_argument, NULL, O_SIZE},  {"cols", required_argument, NULL, O_COLS},
        {"threads", required_argument, NULL, 'j'},  {"quiet", no_argument, NULL, 'q'},
        {"json", no_argument, NULL, O_JSON},        {"help", no_argument, NULL, 'h'},
        {"start", required_argument, NULL, O_START}, {"no-starts", no_argument, NULL, O_NO_STARTS},
        {NULL, 0, NULL, 0}};
    const char *outdir = NULL, *origin = NULL, *mask_path = NULL, *line_path = NULL;
    int mode = 0, category = -1, n = 0, size = 256, cols = 0, json = 0, quiet = 0, distance_given = 0;
    double budget = 0;
    long max_evals = 0;
    SqSeedOptions so = sq_seed_options_default();
    CliStarts starts = {0}; /* fit's default: the shipped complex and layered presets */
    SqError err;
    int c;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":hc:o:n:d:s:m:l:b:j:q", opts, NULL)) != -1) {
        long v;
        int m = 0;
        switch (c) {
        case 'c':
            m = MODE_CATEGORY;
            category = sq_fit_kind_from_name(optarg);
            if (category < 0)
                return cli_usage("seed",
                                 "--category is one of none, longitudinal, transversal, spots, other_simple, "
                                 "complex, layered; got '%s'",
                                 optarg);
            break;
        case O_NEAR: m = MODE_NEAR; origin = optarg; break;
        case O_PHOTO: m = MODE_PHOTO; origin = optarg; break;
        case 'o': outdir = optarg; break;
        case 'n':
            if (cli_parse_int("-n", optarg, 1, SQ_SEED_MAX, &v, &err) != 0)
                return cli_usage("seed", "%s", err.what);
            n = (int)v;
            break;
        case 'd':
            if (cli_parse_real("--distance", optarg, 0.01, 1, &so.distance, &err) != 0)
                return cli_usage("seed", "%s", err.what);
            distance_given = 1;
            break;
        case 's':
            if (cli_parse_int("--seed", optarg, 0, 2147483647L, &v, &err) != 0)
                return cli_usage("seed", "%s", err.what);
            so.seed = (uint64_t)v;
            break;
        case O_POOL:
            if (cli_parse_int("--pool", optarg, 1, 64, &v, &err) != 0)
                return cli_usage("seed", "%s", err.what);
            so.pool = (int)v;
            break;
        case 'm': mask_path = optarg; break;
        case 'l': line_path = optarg; break;
        case 'b':
            budget = cli_parse_time(optarg);
            if (budget <= 0)
                return cli_usage("seed", "--budget takes a time such as 60s, 90 or 2m (a week at most), got '%s'", optarg);
            break;
        case O_EVALS:
            if (cli_parse_int("--evals", optarg, 100, 100000000, &v, &err) != 0)
                return cli_usage("seed", "%s", err.what);
            max_evals = v;
            break;
        case O_SIZE:
            if (cli_parse_int("--size", optarg, 32, 1024, &v, &err) != 0)
                return cli_usage("seed", "%s", err.what);
            size = (int)v;
            break;
        case O_COLS:
            if (cli_parse_int("--cols", optarg, 1, 64, &v, &err) != 0)
                return cli_usage("seed", "%s", err.what);
            cols = (int)v;
            break;
        case 'j':
            if (cli_parse_int("--threads", optarg, 1, 1024, &v, &err) != 0)
                return cli_usage("seed", "%s", err.what);
            so.threads = (int)v;
            break;
        case 'q': quiet = 1; break;
        case O_JSON: json = 1; break;
        case O_START:
            if (starts.nargs == CLI_START_ARGS)
                return cli_usage("seed", "--start is given more than %d times: give a folder instead", CLI_START_ARGS);
            starts.arg[starts.nargs++] = optarg;
            break;
        case O_NO_STARTS: starts.none = 1; break;
        case 'h': fputs(help, stdout); return CLI_OK;
        default:
            return cli_bad_option("seed", argv, c, opts);
        }
        if (m) {
            if (mode && mode != m)
                return cli_usage("seed", "--category, --near and --from-photo exclude each other");
            mode = m;
        }
    }
    if (optind < argc)
        return cli_usage("seed", "unexpected argument '%s'", argv[optind]);
    if (!mode)
        return cli_usage("seed", "say what to start from: --category C, --near PRESET or --from-photo PHOTO");
    if (!outdir)
        return cli_usage("seed", "say where the presets go with -o DIR");
    if (distance_given && mode != MODE_NEAR)
        return cli_usage("seed", "--distance is for --near");
    if ((mask_path || line_path || budget > 0 || max_evals > 0 || starts.nargs > 0 || starts.none) &&
        mode != MODE_PHOTO)
        return cli_usage("seed", "--mask, --line, --budget, --evals, --start and --no-starts are for --from-photo");
    if (starts.none && starts.nargs > 0)
        return cli_usage("seed", "--start and --no-starts contradict each other");
    if (so.pool && mode == MODE_PHOTO)
        return cli_usage("seed", "--pool is for --category and --near");
    so.n = n ? n : mode == MODE_PHOTO ? 24 : 12;

    if (!usable_dir(outdir, &err))
        return cli_fail(&err);
    if (mode == MODE_PHOTO && cli_starts_load(&starts, quiet || json, &err) != SQ_OK) {
        cli_starts_free(&starts);
        return cli_fail(&err);
    }
    Progress px = {.tty = isatty(STDERR_FILENO), .quiet = quiet || json};
    so.progress = on_progress;
    so.ctx = &px;
    Seeding s = {.mode = mode, .category = category, .origin = origin, .seed = so.seed, .distance = so.distance};
    SqSeedResult r = {0};
    SqFitResult fit = {0};
    SqParams *orig = NULL;
    SqPresetInfo *oinfo = NULL;
    char oname[256];
    int rc = CLI_OK;
    if (origin) {
        const char *base = strrchr(origin, '/');
        snprintf(oname, sizeof oname, "%s", base ? base + 1 : origin);
        s.origin_name = oname;
    }
    if (mode == MODE_CATEGORY) {
        px.what = sq_fit_kind_name(category);
        if (sq_seed_category(category, &so, &r, &err) != SQ_OK)
            rc = cli_fail(&err);
    } else if (mode == MODE_NEAR) {
        orig = malloc(sizeof *orig);
        oinfo = calloc(1, sizeof *oinfo);
        if (!orig || !oinfo) {
            sq_error_set(&err, SQ_ERR_NOMEM, origin, "out of memory");
            rc = cli_fail(&err);
        } else if (sq_preset_load(origin, orig, oinfo, &err) != SQ_OK) {
            rc = cli_fail(&err);
        } else {
            if (oinfo->name[0])
                s.origin_name = oinfo->name;
            s.category = sq_fit_kind_of(orig);
            px.what = s.origin_name;
            if (sq_seed_near(orig, &so, &r, &err) != SQ_OK)
                rc = cli_fail(&err);
        }
    } else {
        CliPhoto in = {0};
        SqPrepared prep = {0};
        SqFeatures target;
        px.what = s.origin_name;
        const double t0 = cli_now_s();
        if (cli_load_photo(origin, mask_path, line_path, &in, &err) != 0 || cli_prepare(&in, NULL, &prep, &err) != SQ_OK ||
            sq_fit_photo_target(&prep, &target, &err) != SQ_OK) {
            rc = cli_fail(&err);
        } else {
            SqFitOptions fo = sq_fit_options_default();
            fo.seed = so.seed;
            fo.threads = so.threads;
            fo.budget = max_evals > 0 && budget == 0 ? 0 : budget > 0 ? budget : 60;
            if (fo.budget > 0) /* the whole command's, as fit's */
                fo.budget = cli_search_budget(fo.budget, cli_now_s() - t0, size);
            fo.max_evals = max_evals;
            fo.front_max = so.n > 24 ? so.n : 24;
            fo.progress = on_fit_progress;
            fo.ctx = &px;
            fo.starts = starts.params;
            fo.nstarts = starts.n;
            if (sq_fit_run(&target, &fo, &fit, &err) != SQ_OK || sq_seed_from_fit(&fit, &so, &r, &err) != SQ_OK)
                rc = cli_fail(&err);
            else {
                s.fit = &fit;
                s.category = sq_fit_kind_of(&fit.best.params);
            }
        }
        sq_fit_prepared_free(&prep);
        cli_photo_free(&in);
    }
    if (px.tty && !px.quiet)
        fputs("\r\033[K", stderr);
    if (rc == CLI_OK) {
        s.r = &r;
        s.starts = &starts;
        if (write_all(outdir, &s, size, cols, so.threads, json, &err) != SQ_OK)
            rc = cli_fail(&err);
    }
    if (rc == CLI_OK && !quiet && !json) {
        printf("  preset   category      nearest  %s\n", mode == MODE_CATEGORY ? "" : mode == MODE_NEAR ? "to original" : "to photo");
        for (int i = 0; i < r.n; i++) {
            const SqSeedCandidate *p = &r.picks[i];
            printf("  %02d.json  %-12s  %7.3f", i, sq_fit_kind_name(sq_fit_kind_of(&p->params)),
                   p->nearest_index >= 0 ? p->nearest : 0.0);
            if (isfinite(p->to_origin))
                printf("  %7.3f", p->to_origin);
            printf("\n");
        }
        printf("wrote %s: %d preset%s, seeds.json, sheet.png (%d drawn, %d implausible, smallest distance %.3f)\n",
               outdir, r.n, r.n == 1 ? "" : "s", r.drawn, r.implausible, isfinite(r.min_distance) ? r.min_distance : 0);
    }
    sq_seed_result_free(&r);
    sq_fit_result_free(&fit);
    cli_starts_free(&starts);
    free(orig);
    free(oinfo);
    return rc;
}
