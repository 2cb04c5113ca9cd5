/* squama fit: from a photo to the best preset, its front, its textures and a report. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "fit_job.h"
#include "json_util.h"
#include "squama/io.h"
#include "squama/preset.h"

static const char help[] =
    "usage: squama fit PHOTO -o DIR [--mask MASK] [--line LINE] [--budget 60s] [--seed N] [options]\n"
    "\n"
    "Fits the generator to the snake in PHOTO: screens every pattern category (automata\n"
    "read off the photo's strip among them), evolves the promising ones (CMA-ES and GP,\n"
    "Pareto-ranked on the five objectives of 'squama score'), re-scores the finalists over\n"
    "several seeds and polishes the champion with nlopt.\n"
    "\n"
    "DIR receives:\n"
    "  best.json        the best preset (the front's lowest score: each objective divided by\n"
    "                   its median over the screening, summed; a plain skin within 30% of\n"
    "                   it is preferred, else the simplest category within 5%: plain,\n"
    "                   stripes or bands, spots, automata);\n"
    "                   'squama render' takes it as is\n"
    "  fit.json         the fit itself: objectives, view scale, category scores, inputs, seed,\n"
    "                   budget, timings, convergence\n"
    "  front/NN.json    the Pareto front of alternatives, best first\n"
    "  kinds/KIND.json  each kind's best (best.json for its own kind), to start from when\n"
    "                   the snake is known to be of another kind than the one chosen\n"
    "  kinds.png        the photo's straightened body with each kind's best under it\n"
    "  basecolor.png height.png roughness.png normal.png   the best preset's maps\n"
    "  preview.png      the best preset on a snake body, at the fitted view scale\n"
    "  photo.jpg mask.png strip.png fitted_strip.png   the prepared photo and the fit's view\n"
    "  line.json        the centre line followed (not with --line): correct it and pass it back\n"
    "  line.png         that line over the photo, its points numbered, on a grid of photo pixels\n"
    "  report.html      all of it side by side, with convergence and Pareto-front plots\n"
    "  checkpoint/      the front so far, for --resume\n"
    "All but checkpoint/ are written as a set once the search is done: a fit that fails or\n"
    "is stopped while writing them leaves an earlier fit's outputs in DIR as they were.\n"
    "\n"
    "options:\n"
    "  -m, --mask MASK      the snake's mask (white on the snake, the photo's size);\n"
    "                       without one a mask is made and saved as mask.png to correct\n"
    "  -l, --line LINE      the body's centre line and width, followed as it is where no\n"
    "                       mask can say where the body runs (see 'squama prepare')\n"
    "  -o, --output DIR     where everything goes (required)\n"
    "  -b, --budget TIME    the whole command's wall time, the photo's preparation and the\n"
    "                       outputs included: 60s (default), 90, 2m\n"
    "      --evals N        an evaluation budget instead (deterministic for a seed)\n"
    "  -s, --seed N         the search's seed (default 1)\n"
    "  -j, --threads N      threads (default: all cores)\n"
    "      --size N         size of the written maps (default 1024)\n"
    "      --resume DIR     start from the front in DIR/checkpoint with the budget left\n"
    "      --method M       squama (default), or a baseline: random, esch, crs2, isres\n"
    "      --categories L   only these kinds, comma-separated: none, longitudinal,\n"
    "                       transversal, spots, other_simple, complex (reaction-diffusion),\n"
    "                       layered (a pattern under a layer of another: a niche, and a\n"
    "                       layer searched over the champion), or all; default the six\n"
    "                       categories and a layer over the champion (no layered niche)\n"
    "      --work-size N    longest side the photo is prepared at (default 1024)\n"
    "      --start P        a preset, or a folder of presets, the screening starts from\n"
    "                       as well (repeatable): each of a kind fitted is screened at\n"
    "                       the view scale that suits it, as it is and recoloured toward\n"
    "                       the photo; default the shipped complex/ and layered/ presets\n"
    "                       (reaction-diffusion is hard to find from random draws)\n"
    "      --no-starts      no starting presets\n"
    "  -q, --quiet          no progress and no summary\n"
    "      --json           progress as JSON lines on stdout, then a summary object\n"
    "  -h, --help           show this help\n"
    "\n"
    "Ctrl-C stops the search early and still writes the best found so far.\n";

static volatile sig_atomic_t interrupted;
static volatile int stop_flag;

static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
    stop_flag = 1;
    signal(SIGINT, cli_fatal_signal); /* a second Ctrl-C ends the program */
}

/* Loads DIR/checkpoint into seed candidates. */
static int load_checkpoint(const char *dir, SqFitCandidate **seeds, int *n, double *seconds, long *evals,
                           SqError *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/checkpoint/checkpoint.json", dir);
    char *text;
    size_t len;
    if (sq_io_read_file(path, 1 << 20, &text, &len, err) != SQ_OK)
        return -1;
    cJSON *root;
    SqStatus st = sq__json_parse(text, len, path, &root, err);
    free(text);
    if (st != SQ_OK)
        return -1;
    const cJSON *fmt = cJSON_GetObjectItemCaseSensitive(root, "format");
    const cJSON *front = cJSON_GetObjectItemCaseSensitive(root, "front");
    const cJSON *secs = cJSON_GetObjectItemCaseSensitive(root, "seconds");
    const cJSON *ev = cJSON_GetObjectItemCaseSensitive(root, "evaluations"); /* absent: none known */
    if (!cJSON_IsString(fmt) || strcmp(fmt->valuestring, "squama-checkpoint/1") != 0 ||
        !cJSON_IsArray(front) || !cJSON_IsNumber(secs) || !(secs->valuedouble >= 0 && secs->valuedouble <= 1e9) ||
        (ev && (!cJSON_IsNumber(ev) || !(ev->valuedouble >= 0 && ev->valuedouble <= 1e15) ||
                ev->valuedouble != floor(ev->valuedouble)))) {
        cJSON_Delete(root);
        sq_error_set(err, SQ_ERR_PARSE, path,
                     "not a squama checkpoint (format squama-checkpoint/1, a front, seconds from 0 to 1e9 and a "
                     "whole number of evaluations >= 0)");
        return -1;
    }
    int cnt = cJSON_GetArraySize(front);
    *seeds = calloc(cnt > 0 ? (size_t)cnt : 1, sizeof **seeds);
    *n = 0;
    *seconds = secs->valuedouble;
    *evals = ev ? (long)ev->valuedouble : 0;
    if (!*seeds) {
        cJSON_Delete(root);
        sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
        return -1;
    }
    const cJSON *e;
    cJSON_ArrayForEach(e, front)
    {
        const cJSON *pr = cJSON_GetObjectItemCaseSensitive(e, "preset");
        const cJSON *vs = cJSON_GetObjectItemCaseSensitive(e, "view_scale");
        if (!cJSON_IsString(pr) || !cJSON_IsNumber(vs) || strchr(pr->valuestring, '/')) {
            sq_error_set(err, SQ_ERR_PARSE, path, "front entry %d needs a preset file name and a view_scale", *n);
            cJSON_Delete(root);
            return -1;
        }
        char pp[4096];
        snprintf(pp, sizeof pp, "%s/checkpoint/%s", dir, pr->valuestring);
        SqFitCandidate *c = &(*seeds)[*n];
        if (sq_preset_load(pp, &c->params, NULL, err) != SQ_OK) {
            cJSON_Delete(root);
            return -1;
        }
        c->view_scale = vs->valuedouble;
        (*n)++;
    }
    cJSON_Delete(root);
    if (*n == 0) {
        sq_error_set(err, SQ_ERR_PARSE, path, "the checkpoint's front is empty");
        return -1;
    }
    return 0;
}

int cmd_fit(int argc, char **argv)
{
    enum { O_RESUME = CLI_FITOPT_END, O_METHOD, O_JSON };
    static const struct option opts[] = {
        CLI_FIT_LONGOPTS,
        {"mask", required_argument, NULL, 'm'},     {"output", required_argument, NULL, 'o'},
        {"line", required_argument, NULL, 'l'},
        {"resume", required_argument, NULL, O_RESUME}, {"method", required_argument, NULL, O_METHOD},
        {"quiet", no_argument, NULL, 'q'},          {"json", no_argument, NULL, O_JSON},
        {"help", no_argument, NULL, 'h'},           {NULL, 0, NULL, 0}};
    const char *resume = NULL;
    CliFitJob job;
    cli_fit_job_init(&job);
    int c;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":hm:l:o:b:s:j:q", opts, NULL)) != -1) {
        int taken = cli_fit_job_option(&job, c, optarg, "fit");
        if (taken >= 0) {
            if (taken != CLI_OK)
                return taken;
            continue;
        }
        switch (c) {
        case 'm': job.mask = optarg; break;
        case 'l': job.line = optarg; break;
        case 'o': job.outdir = optarg; break;
        case O_RESUME: resume = optarg; break;
        case O_METHOD: {
            int found = 0;
            for (int m = SQ_FIT_SQUAMA; m <= SQ_FIT_ISRES; m++)
                if (strcmp(optarg, sq_fit_method_name((SqFitMethod)m)) == 0) {
                    job.fo.method = (SqFitMethod)m;
                    found = 1;
                }
            if (!found)
                return cli_usage("fit", "--method is squama, random, esch, crs2 or isres, got '%s'", optarg);
            break;
        }
        case 'q': job.quiet = 1; break;
        case O_JSON: job.json = 1; break;
        case 'h': fputs(help, stdout); return CLI_OK;
        default:
            return cli_bad_option("fit", argv, c, opts);
        }
    }
    if (argc - optind != 1)
        return cli_usage("fit", "give one PHOTO");
    if (!job.outdir)
        return cli_usage("fit", "say where the results go with -o DIR");
    int rc = cli_fit_job_options_done(&job, "fit");
    if (rc != CLI_OK)
        return rc;
    job.photo = argv[optind];
    SqError err;
    SqFitCandidate *seeds = NULL;
    if (resume) {
        double spent = 0;
        long spent_evals = 0;
        if (load_checkpoint(resume, &seeds, &job.fo.nseeds, &spent, &spent_evals, &err) != 0) {
            cli_fit_job_free(&job);
            return cli_fail(&err);
        }
        if (job.fo.categories) { /* the checkpoint's presets of categories left out stay behind */
            int kept = 0;
            for (int i = 0; i < job.fo.nseeds; i++)
                if ((job.fo.categories >> sq_fit_kind_of(&seeds[i].params)) & 1u)
                    seeds[kept++] = seeds[i];
            if (kept < job.fo.nseeds && !job.quiet)
                fprintf(stderr, "squama: %d of the checkpoint's %d presets are of categories left out\n",
                        job.fo.nseeds - kept, job.fo.nseeds);
            job.fo.nseeds = kept;
        }
        job.fo.seeds = seeds;
        job.offset_s = spent;
        job.offset_evals = spent_evals;
        /* the budgets left, each at least what a fit needs to finish (10 s, 100 evaluations) */
        if (job.fo.budget > 0)
            job.fo.budget = fmax(10.0, job.fo.budget - spent);
        if (job.fo.max_evals > 0)
            job.fo.max_evals = spent_evals < job.fo.max_evals - 100 ? job.fo.max_evals - spent_evals : 100;
        if (!job.quiet && !job.json) {
            fprintf(stderr, "squama: resuming from %s: %d presets, %.1f s and %ld evaluations spent; ", resume,
                    job.fo.nseeds, spent, spent_evals);
            if (job.fo.max_evals > 0 && job.fo.budget > 0)
                fprintf(stderr, "%ld evaluations and %.1f s left\n", job.fo.max_evals, job.fo.budget);
            else if (job.fo.max_evals > 0)
                fprintf(stderr, "%ld evaluations left\n", job.fo.max_evals);
            else
                fprintf(stderr, "%.1f s left\n", job.fo.budget);
        }
    }
    job.stop = &stop_flag;
    struct sigaction sa = {0}, old;
    sa.sa_handler = on_sigint;
    sigaction(SIGINT, NULL, &old);
    if (old.sa_handler != SIG_IGN) /* a fit started in the background ignores Ctrl-C, as it was told */
        sigaction(SIGINT, &sa, NULL);
    CliFitOutcome r;
    SqStatus st = cli_fit_job_run(&job, &r, &err);
    sigaction(SIGINT, &old, NULL);
    free(seeds);
    cli_fit_job_free(&job);
    if (st != SQ_OK)
        return cli_fail(&err);
    const char *outdir = job.outdir;
    if (job.json) {
        printf("{\"best\": \"%s/best.json\", \"report\": \"%s/report.html\", \"category\": \"%s\", "
               "\"score\": %.4f, \"view_scale\": %.3f, \"evaluations\": %ld, \"seconds\": %.1f, \"stopped_early\": %s}\n",
               outdir, outdir, sq_fit_kind_name(sq_fit_kind_of(&r.best.params)), r.best.score,
               r.best.view_scale, r.evals, r.seconds, r.stopped ? "true" : "false");
    } else if (!job.quiet) {
        printf("%s: %s pattern, score %.3f, view scale %.2f; %ld evaluations in %.1f s of search (%.0f/s), "
               "%.1f s in all%s\n",
               job.photo, sq_fit_kind_name(sq_fit_kind_of(&r.best.params)), r.best.score, r.best.view_scale,
               r.evals, r.search_seconds, r.evals / fmax(r.search_seconds, 1e-9), r.seconds,
               r.stopped ? ", stopped early" : "");
        printf("  objectives:");
        for (int k = 0; k < SQ_OBJ_COUNT; k++)
            printf(" %s %.3f", sq_fit_objective_name(k), r.best.obj[k]);
        printf("\n  wrote %s/best.json, %d alternatives in %s/front, each kind's best in %s/kinds, maps, preview\n"
               "  report: %s/report.html\n",
               outdir, r.nfront, outdir, outdir, outdir);
    }
    if (interrupted)
        return 130;
    return CLI_OK;
}
