/* squama score: how well each preset matches the snake in a photo. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "json_util.h"
#include "squama/fitness.h"
#include "squama/io.h"
#include "squama/preset.h"
#include "squama/search.h"

static const char help[] =
    "usage: squama score PHOTO [--mask MASK] [--line LINE] [--json] PRESET...\n"
    "\n"
    "Prepares PHOTO (see 'squama prepare') and scores every PRESET against it: the\n"
    "objectives (lower is better; 0 for identical statistics), the view scale that fits\n"
    "it best (body circumferences per texture tile), and the preset's Pareto rank among\n"
    "the presets given (0: not dominated by any).\n"
    "\n"
    "objectives: palette (earth mover's distance of the dominant colours, CIEDE2000),\n"
    "histogram (chi-square of CIELAB histograms), shape (wavelet energies), along and\n"
    "across (the pattern's spectra along and across the body, and its across profile)\n"
    "\n"
    "options:\n"
    "  -m, --mask MASK      the snake's mask (white on the snake, the photo's size)\n"
    "  -l, --line LINE      the body's centre line and width (see 'squama prepare')\n"
    "      --json           an array of {preset, objectives, view_scale, rank}\n"
    "      --size N         candidate texture size (default 256)\n"
    "      --debug DIR      save the photo's preparation steps there\n"
    "      --view S         score at view scale S only (default: the best of a grid)\n"
    "  -h, --help           show this help\n";

int cmd_score(int argc, char **argv)
{
    enum { O_JSON = 1000, O_SIZE, O_DEBUG, O_VIEW };
    static const struct option opts[] = {{"mask", required_argument, NULL, 'm'},
                                         {"line", required_argument, NULL, 'l'},
                                         {"json", no_argument, NULL, O_JSON},
                                         {"size", required_argument, NULL, O_SIZE},
                                         {"debug", required_argument, NULL, O_DEBUG},
                                         {"view", required_argument, NULL, O_VIEW},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    const char *mask_path = NULL, *line_path = NULL;
    int json = 0, size = 256, c;
    long v;
    double view = 0;
    SqPrepOptions po = sq_fit_prep_options_default();
    SqError err;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":hm:l:", opts, NULL)) != -1) {
        switch (c) {
        case 'm': mask_path = optarg; break;
        case 'l': line_path = optarg; break;
        case O_JSON: json = 1; break;
        case O_SIZE:
            if (cli_parse_int("--size", optarg, 64, 2048, &v, &err) != 0)
                return cli_usage("score", "%s", err.what);
            size = (int)v;
            break;
        case O_DEBUG: po.debug_dir = optarg; break;
        case O_VIEW:
            if (cli_parse_real("--view", optarg, 0.05, 64, &view, &err) != 0)
                return cli_usage("score", "%s", err.what);
            break;
        case 'h': fputs(help, stdout); return CLI_OK;
        default:
            return cli_bad_option("score", argv, c, opts);
        }
    }
    if (argc - optind < 2)
        return cli_usage("score", "give a PHOTO and at least one PRESET");
    const char *photo_path = argv[optind];
    const int n = argc - optind - 1;
    char **presets = argv + optind + 1;
    CliMade made = {0};
    if (po.debug_dir && cli_mkdirs_new(po.debug_dir, &made) != 0) {
        sq_error_set(&err, SQ_ERR_IO, po.debug_dir, "cannot create the folder: %s", strerror(errno));
        return cli_fail(&err);
    }
    /* every preset is loaded first: a typo should not cost a photo's preparation */
    SqParams *params = malloc(sizeof(SqParams) * (size_t)n);
    double *obj = malloc(sizeof(double) * SQ_OBJ_COUNT * (size_t)n), *scale = malloc(sizeof(double) * (size_t)n);
    int *rank = malloc(sizeof(int) * (size_t)n);
    if (!params || !obj || !scale || !rank) {
        free(params);
        free(obj);
        free(scale);
        free(rank);
        sq_error_set(&err, SQ_ERR_NOMEM, "", "out of memory");
        if (po.debug_dir)
            cli_rmdirs_new(po.debug_dir, &made);
        return cli_fail(&err);
    }
    int rc = CLI_OK;
    for (int i = 0; i < n && rc == CLI_OK; i++)
        if (sq_preset_load(presets[i], &params[i], NULL, &err) != SQ_OK)
            rc = cli_fail(&err);
    CliPhoto in = {0};
    SqPrepared prep = {0};
    SqFeatures target;
    if (rc == CLI_OK && cli_load_photo(photo_path, mask_path, line_path, &in, &err) != 0)
        rc = cli_fail(&err);
    if (rc == CLI_OK && cli_prepare(&in, &po, &prep, &err) != SQ_OK)
        rc = cli_fail(&err);
    if (rc == CLI_OK && sq_fit_photo_target(&prep, &target, &err) != SQ_OK)
        rc = cli_fail(&err);
    SqTextures maps = {0};
    for (int i = 0; i < n && rc == CLI_OK; i++) {
        SqImage strip;
        if (sq_fit_score(&target, &params[i], size, 0.5, view, &maps, obj + (size_t)i * SQ_OBJ_COUNT, &scale[i],
                         po.debug_dir ? &strip : NULL, &err) != SQ_OK) {
            snprintf(err.where, sizeof err.where, "%s", presets[i]);
            rc = cli_fail(&err);
        } else if (po.debug_dir) { /* the candidate's strip at its best scale, beside the photo's */
            char path[4096];
            const char *base = strrchr(presets[i], '/');
            snprintf(path, sizeof path, "%s/candidate_%02d_%s.png", po.debug_dir, i, base ? base + 1 : presets[i]);
            if (sq_io_write_image(path, &strip, NULL, &err) != SQ_OK)
                rc = cli_fail(&err);
            sq_image_free(&strip);
        }
    }
    sq_gen_textures_free(&maps);
    if (rc == CLI_OK && sq_nsga2_rank(obj, n, SQ_OBJ_COUNT, rank) < 0) {
        sq_error_set(&err, SQ_ERR_NOMEM, "", "out of memory ranking");
        rc = cli_fail(&err);
    }
    if (rc == CLI_OK && json) {
        cJSON *arr = cJSON_CreateArray();
        for (int i = 0; i < n; i++) {
            cJSON *o = cJSON_CreateObject(), *ob = cJSON_CreateObject();
            cJSON_AddStringToObject(o, "preset", presets[i]);
            for (int k = 0; k < SQ_OBJ_COUNT; k++)
                cJSON_AddItemToObject(ob, sq_fit_objective_name(k), sq__json_exact_number(obj[(size_t)i * SQ_OBJ_COUNT + k]));
            cJSON_AddItemToObject(o, "objectives", ob);
            cJSON_AddItemToObject(o, "view_scale", sq__json_exact_number(scale[i]));
            cJSON_AddNumberToObject(o, "rank", rank[i]);
            cJSON_AddItemToArray(arr, o);
        }
        char *text = sq__json_print(arr);
        cJSON_Delete(arr);
        if (text)
            fputs(text, stdout);
        free(text);
    } else if (rc == CLI_OK) {
        printf("%s: body %.0f px wide, %.0f px straightened in %d stretch%s (%s mask)\n\n", photo_path,
               prep.body_width, prep.length, prep.nruns, prep.nruns == 1 ? "" : "es", sq_mask_source_name(prep.mask_source));
        printf("%4s %6s", "rank", "scale");
        for (int k = 0; k < SQ_OBJ_COUNT; k++)
            printf(" %9s", sq_fit_objective_name(k));
        printf("  preset\n");
        for (int r = 0, shown = 0; shown < n; r++)
            for (int i = 0; i < n; i++) {
                if (rank[i] != r)
                    continue;
                printf("%4d %6.2f", rank[i], scale[i]);
                for (int k = 0; k < SQ_OBJ_COUNT; k++)
                    printf(" %9.4f", obj[(size_t)i * SQ_OBJ_COUNT + k]);
                printf("  %s\n", presets[i]);
                shown++;
            }
    }
    sq_fit_prepared_free(&prep);
    cli_photo_free(&in);
    free(params);
    free(obj);
    free(scale);
    free(rank);
    if (rc != CLI_OK && po.debug_dir) /* the folder it made, when nothing was written into it */
        cli_rmdirs_new(po.debug_dir, &made);
    return rc;
}
