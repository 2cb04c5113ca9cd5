/* One photo fitted and its outputs written: what `squama fit` does, and what `squama batch`
 * does for every row of a manifest. */
#ifndef SQUAMA_CLI_FIT_JOB_H
#define SQUAMA_CLI_FIT_JOB_H

#include <getopt.h>

#include "cli.h"
#include "squama/fitness.h"
#include "squama/search.h"

typedef struct CliFitJob {
    const char *photo, *mask;  /* mask NULL: the photo's alpha, else made automatically */
    const char *line;          /* a body line to follow, or NULL */
    const char *outdir;        /* created when missing */
    SqFitOptions fo;           /* progress, ctx and stop are the job's own */
    SqPrepOptions po;
    int size;                  /* side of the written maps (1024) */
    int quiet, json;           /* progress: a bar on a terminal's stderr unless quiet;
                                  JSON lines on stdout with json */
    double offset_s;           /* seconds spent before a resume */
    long offset_evals;         /* evaluations spent before a resume */
    volatile int *stop;        /* nonzero: finish with the best so far */
    int budget_given;          /* --budget was given (with --evals: both apply) */
} CliFitJob;

typedef struct CliFitOutcome {
    SqFitCandidate best;       /* best.json and its objectives and score */
    int nfront;
    long evals;
    double seconds;            /* the whole job, from loading the photo to the report: within
                                  fo.budget, when it is a time budget, as near as the
                                  preparation and the outputs' reserve allow */
    double search_seconds;     /* the search's part of it */
    int stopped;               /* stopped early through job->stop */
} CliFitOutcome;

/* Writes a candidate as a preset file (atomically), named name, its view scale in its notes. */
SqStatus cli_fit_write_preset(const char *path, const SqFitCandidate *c, const char *name, SqError *err);

/* kinds/<kind>.json staged in s, each kind's best (r->kind_best) as a preset (an earlier
 * fit's of a kind this one has none of goes), and kinds.png: prep's strip with each kind's fitted strip under it (rendered at
 * size, seen at its view scale in the band centred on band_centre; the champion's is
 * champion_strip), labelled with the kind and its score. A picture that cannot be made is
 * a warning on stderr; a preset that cannot be written an error. */
SqStatus cli_fit_write_kinds(CliStaging *s, const SqPrepared *prep, double band_centre, const SqFitResult *r,
                             const SqImage *champion_strip, int size, const char *photo_name, SqError *err);

/* fit's defaults: 60 s, seed 1, every core, 1024-pixel maps. */
void cli_fit_job_init(CliFitJob *job);

/* Loads and prepares the photo, fits it, and writes into job->outdir everything
 * `squama fit --help` lists. SQ_OK, or an error naming the file that failed. */
SqStatus cli_fit_job_run(const CliFitJob *job, CliFitOutcome *out, SqError *err);

/* The options fit and batch share, for getopt_long: --budget (-b), --evals, --seed (-s),
 * --threads (-j), --size, --categories, --work-size. */
enum { CLI_FITOPT_EVALS = 1000, CLI_FITOPT_SIZE, CLI_FITOPT_CATEGORIES, CLI_FITOPT_WORK,
       CLI_FITOPT_END };
#define CLI_FIT_LONGOPTS                                                                       \
    {"budget", required_argument, NULL, 'b'}, {"evals", required_argument, NULL, CLI_FITOPT_EVALS}, \
    {"seed", required_argument, NULL, 's'}, {"threads", required_argument, NULL, 'j'},          \
    {"size", required_argument, NULL, CLI_FITOPT_SIZE},                                        \
    {"categories", required_argument, NULL, CLI_FITOPT_CATEGORIES},                            \
    {"work-size", required_argument, NULL, CLI_FITOPT_WORK}

/* Takes one getopt_long code of the shared options: CLI_OK when taken, CLI_USAGE (the
 * message printed, naming cmd) when its value is wrong, -1 when c is not one of them. */
int cli_fit_job_option(CliFitJob *job, int c, const char *arg, const char *cmd);

/* After the options: an evaluation budget without --budget is the only budget (the result
 * then depends only on the seed). */
void cli_fit_job_options_done(CliFitJob *job);

#endif
