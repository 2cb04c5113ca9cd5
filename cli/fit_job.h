/* One photo fitted and its outputs written: what `squama fit` does, and what `squama batch`
 * does for every row of a manifest. */
#ifndef SQUAMA_CLI_FIT_JOB_H
#define SQUAMA_CLI_FIT_JOB_H

#include <getopt.h>

#include "cli.h"
#include "squama/fitness.h"
#include "squama/search.h"

/* The presets the fit's screening starts from as well (SqFitOptions.starts). */
enum { CLI_START_ARGS = 64 };
typedef struct CliStarts {
    const char *arg[CLI_START_ARGS]; /* --start's values: presets, or folders of them */
    int nargs;
    int none;                  /* --no-starts */
    SqParams *params;          /* what cli_starts_load loaded: n presets, and their files */
    char **path;
    int n;
    uint64_t digest;           /* FNV-1a over the files taken, in order */
} CliStarts;

/* Loads the starts: each --start file (one the fit cannot search is an error) and each
 * --start folder's *.json (one the fit cannot search is skipped, with a warning unless
 * quiet); with neither --start nor --no-starts, the shipped complex/ and layered/ presets
 * (quietly none when they are not installed). SQ_OK, or an error naming the file. */
SqStatus cli_starts_load(CliStarts *s, int quiet, SqError *err);
void cli_starts_free(CliStarts *s);

/* fit.json's search.starts and seeds.json's starts: {"presets": the n paths, "screened": how
 * many the fit screened (those of kinds fitted)}, added to parent. */
struct cJSON;
void cli_starts_json(struct cJSON *parent, char *const *path, int n, int screened);

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
    CliStarts starts;          /* loaded by cli_fit_job_options_done */
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
 * --threads (-j), --size, --categories, --work-size, --start, --no-starts. */
enum { CLI_FITOPT_EVALS = 1000, CLI_FITOPT_SIZE, CLI_FITOPT_CATEGORIES, CLI_FITOPT_WORK,
       CLI_FITOPT_START, CLI_FITOPT_NO_STARTS, CLI_FITOPT_END };
#define CLI_FIT_LONGOPTS                                                                       \
    {"budget", required_argument, NULL, 'b'}, {"evals", required_argument, NULL, CLI_FITOPT_EVALS}, \
    {"seed", required_argument, NULL, 's'}, {"threads", required_argument, NULL, 'j'},          \
    {"size", required_argument, NULL, CLI_FITOPT_SIZE},                                        \
    {"categories", required_argument, NULL, CLI_FITOPT_CATEGORIES},                            \
    {"work-size", required_argument, NULL, CLI_FITOPT_WORK},                                   \
    {"start", required_argument, NULL, CLI_FITOPT_START},                                      \
    {"no-starts", no_argument, NULL, CLI_FITOPT_NO_STARTS}

/* Takes one getopt_long code of the shared options: CLI_OK when taken, CLI_USAGE (the
 * message printed, naming cmd) when its value is wrong, -1 when c is not one of them. */
int cli_fit_job_option(CliFitJob *job, int c, const char *arg, const char *cmd);

/* After the options: an evaluation budget without --budget is the only budget (the result
 * then depends only on the seed), and the starts are loaded (cli_starts_load). CLI_OK, or
 * CLI_FAIL with the error printed. */
int cli_fit_job_options_done(CliFitJob *job, const char *cmd);

/* Frees what the options loaded. */
void cli_fit_job_free(CliFitJob *job);

#endif
