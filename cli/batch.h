/* squama batch: a manifest's rows fitted one by one into DIR/<id>/, on local cores
 * (--jobs), over MPI ranks (batch_mpi.c) or over Slurm array tasks (--shard), into one
 * catalogue (DIR/catalogue.csv and DIR/index.html, batch_catalogue.c). */
#ifndef SQUAMA_CLI_BATCH_H
#define SQUAMA_CLI_BATCH_H

#include <pthread.h>

#include "fit_job.h"
#include "manifest.h"

typedef enum BatchStatus { BATCH_PENDING = 0, BATCH_OK, BATCH_ERROR } BatchStatus;

/* One row's outcome. Plain bytes: MPI sends it as it is between ranks of one program. */
typedef struct BatchResult {
    int row;                   /* index in Batch.rows */
    int status;                /* BatchStatus */
    int fitted;                /* the fitted SqPatternType, or -1 */
    int resumed;               /* read back from DIR/<id>/done.json, not fitted by this run */
    int rank;                  /* the MPI rank that fitted it (0 without MPI) */
    double score, obj[SQ_OBJ_COUNT];
    double seconds;            /* the fit's wall time */
    long evals;
    double strip_widths;       /* the photo's strip in body widths (0: not known) */
    char error[1024];          /* why the row failed */
} BatchResult;

typedef struct Batch {
    const char *outdir;
    int nrows;
    const CliManifestRow *rows;
    BatchResult *results;      /* nrows, by row */
    unsigned char *mine;       /* nrows: 1 when this run (its shard) fits the row */
    CliFitJob job;             /* the fit of every row; photo, mask and outdir set per row */
    int jobs;                  /* rows fitted at once in this process */
    int rank;                  /* this process's MPI rank (0 without MPI) */
    int threads;               /* threads of each fit */
    int quiet, json;
    /* progress, shared by the threads that fit rows */
    pthread_mutex_t lock;
    int done, total;           /* rows finished / rows of this run */
    int fitted_now;            /* rows fitted (not resumed) so far */
    double t0;
    SqError write_err;         /* the last catalogue write failure */
    int write_failed;
} Batch;

/* Fits row i into DIR/<id>/ (in DIR/.tmp-<id>/ first, renamed when complete, done.json
 * written last) and fills *out; a row that fails gets its error in *out and a done.json
 * saying so. Safe to call from several threads for different rows. */
void batch_fit_row(const Batch *b, int i, BatchResult *out);

/* A row's DIR/<id>/done.json, read back. */
enum { BATCH_DIGEST = 17 }; /* 16 hex digits and the terminator */
typedef struct BatchDone {
    char id[CLI_ID_MAX + 1], photo[4096], mask[4096], body_line[4096], species[256];
    char photo_digest[BATCH_DIGEST], mask_digest[BATCH_DIGEST], line_digest[BATCH_DIGEST]; /* "": not recorded */
    char settings[256];        /* the fit's settings (batch_settings) */
    int has_settings;          /* 0: an older done.json without them */
    int line, expected;        /* expected: an SqPatternType or -1 */
    BatchResult r;             /* row unset, resumed set */
} BatchDone;

/* Parses done.json's text: 1 when it is a complete squama-batch-row/1, else 0. */
int batch_parse_done(const char *text, size_t len, BatchDone *d);

/* DIR/done.json of a row's folder dir read and parsed: 1, or 0 when missing or broken. */
int batch_load_done(const char *dir, BatchDone *d);

/* The fit settings a row's result depends on, as one line (kept in done.json). */
void batch_settings(const CliFitJob *job, char *out, size_t n);

/* Reads DIR/<id>/done.json of row i: 1 when it holds a fit of the same photo, mask and line
 * (by their contents; by their paths when it recorded no digest) with the same settings
 * (*out filled, resumed set); 0 otherwise (missing, broken, other inputs or settings, a
 * failure). A row of another shard is listed as that shard left it, failures too: matched
 * by id and settings, its inputs not read. */
int batch_read_done(const Batch *b, int i, int other_shard, BatchResult *out);

/* The progress line of a finished row (a JSON line with --json); the caller holds the
 * lock or is alone. */
void batch_report_row(const Batch *b, const BatchResult *r);

/* Records a finished row: the result, the progress line, the catalogue rewritten. Takes
 * the lock. */
void batch_record(Batch *b, const BatchResult *r);

/* Fits the rows of this run still pending on `jobs` local threads, taking the next row
 * from next(). */
typedef int (*BatchNextFn)(void *ctx); /* the next row index, or -1 */
void batch_run_local(Batch *b, int jobs, BatchNextFn next, void *ctx);

/* DIR/catalogue.csv and DIR/index.html, each written atomically. */
SqStatus batch_write_catalogue(const char *outdir, const CliManifestRow *rows, const BatchResult *res, int n,
                               SqError *err);

/* The confusion matrix of expected against fitted categories (rows with both). */
typedef struct BatchConfusion {
    int m[SQ_PATTERN_COUNT][SQ_PATTERN_COUNT]; /* [expected][fitted] */
    int expected_total[SQ_PATTERN_COUNT];
    int correct, total;
} BatchConfusion;
void batch_confusion(const CliManifestRow *rows, const BatchResult *res, int n, BatchConfusion *c);

/* MPI (batch_mpi.c; without MPI these say no). */
int batch_mpi_launched(void);      /* 1 when started by an MPI launcher and built with MPI;
                                      -1 when started as several ranks but built without */
int batch_mpi_init(int *rank, int *size, int *local_size);  /* 0, or -1 (message printed) */
void batch_mpi_finalize(void);
/* Rank 0 hands the pending rows of this run out one at a time (fitting too, on one thread)
 * and records the results; the other ranks fit what they are given. */
void batch_mpi_run(Batch *b, int rank, int size, const int *pending, int npending);

#endif
