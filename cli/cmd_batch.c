/* squama batch: every row of a manifest fitted into DIR/<id>/, and a catalogue of them. */
#define _XOPEN_SOURCE 700

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>
#include <omp.h>

#include "batch.h"
#include "cli.h"
#include "squama/io.h"

static const char help[] =
    "usage: squama batch MANIFEST -o DIR [--budget 60s | --evals N] [--jobs J] [--shard I/N] [options]\n"
    "       squama batch --merge DIR [DIR...] -o OUT\n"
    "\n"
    "Fits every row of MANIFEST as 'squama fit' would, each into DIR/<id>/ (best.json, fit.json,\n"
    "front/, the maps, preview.png, report.html, ... and thumbnails), and keeps a catalogue of\n"
    "them: DIR/catalogue.csv (id, species, expected, fitted, score, the five objectives, preset,\n"
    "status, error, line, seconds, evaluations, strip_widths) and DIR/index.html (thumbnails:\n"
    "photo, mask, strips, texture, preview; filters by category, rows fitted on a strip under 3\n"
    "body widths marked, and the confusion matrix of expected against fitted category with\n"
    "per-category and overall accuracy), both rewritten after every row.\n"
    "\n"
    "MANIFEST is CSV (RFC 4180) with a header naming its columns, in any order and any case:\n"
    "  id        the row's name and folder: letters, digits, '_', '-', '.' (required)\n"
    "  photo     the photo, relative to the manifest's folder (required; or 'file', 'image')\n"
    "  mask      the snake's mask (optional: else made automatically)\n"
    "  body_line the body's centre line and width (optional; see 'squama prepare')\n"
    "  expected  the expected pattern category, for the confusion matrix (optional; or\n"
    "            'category', 'pattern_category', 'pattern_category_guess')\n"
    "  species   shown in the catalogue (optional)\n"
    "Other columns are ignored. A bad row (no or repeated id, a missing or unreadable photo, a\n"
    "bad mask, an unknown category) is listed with its error and the batch goes on. Each row\n"
    "is fitted by a 'squama fit' process of its own: a fit that crashes costs only its row.\n"
    "\n"
    "A row is fitted in DIR/.tmp-<id>/ and renamed to DIR/<id>/ when complete, done.json last:\n"
    "run the same command again after a crash or Ctrl-C and only the rows not done are\n"
    "fitted: those without a done.json, those that failed, those whose photo, mask or line changed\n"
    "(by content: moving them, or spelling the manifest's path otherwise, changes nothing) and\n"
    "those fitted with other settings (--budget, --evals, --seed, --categories, --size,\n"
    "--work-size, the starting presets' contents). A done.json from before squama recorded\n"
    "these is matched by the paths.\n"
    "\n";
static const char help_more[] =
    "Parallel work:\n"
    "  on one machine, each fit uses every core (OpenMP); --jobs J fits J rows at once with\n"
    "  cores/J threads each (keeps the cores busy through each fit's serial parts).\n"
    "  MPI: 'mpirun -np N squama batch ...' (when squama was built with MPI) gives rows to\n"
    "  ranks as they become free: rank 0 hands them out, fits too, and writes the catalogue;\n"
    "  each fit uses the node's cores divided among the ranks on that node.\n"
    "  Slurm arrays: --shard I/N fits the rows r (counted from 0) with r % N == I; by default\n"
    "  I and N come from SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_COUNT.\n"
    "  The shards may share DIR; 'squama batch --merge DIR -o DIR' (or the plain command again)\n"
    "  then makes the whole catalogue. Shards in separate folders are joined with\n"
    "  'squama batch --merge DIR1 DIR2 ... -o OUT' (OUT/<id> become links to the rows); it\n"
    "  warns when the rows were fitted with different settings (budget, seed, kinds...).\n"
    "\n"
    "options:\n"
    "  -o, --output DIR     where everything goes (required)\n"
    "  -b, --budget TIME    each row's wall time, as fit's (its preparation and outputs\n"
    "                       included): 60s (default), 90, 2m\n"
    "      --evals N        each row's evaluation budget instead (deterministic for a seed)\n"
    "  -s, --seed N         every fit's seed (default 1)\n"
    "  -j, --threads N      threads of each fit (default: the cores shared out, see above)\n"
    "      --jobs J         rows fitted at once on this machine (default 1)\n"
    "      --size N         size of the written maps (default 1024)\n"
    "      --categories L   only these pattern types, comma-separated (as fit)\n"
    "      --work-size N    longest side the photos are prepared at (default 1024)\n"
    "      --start P        a starting preset or folder of them, repeatable (as fit)\n"
    "      --no-starts      no starting presets (as fit)\n"
    "      --shard I/N      only every N-th row, from row I (see above)\n"
    "      --merge          the arguments are batch folders to join into OUT's catalogue\n"
    "  -q, --quiet          no progress and no summary\n"
    "      --json           one JSON line per row on stdout, then a summary object\n"
    "  -h, --help           show this help\n"
    "\n"
    "A line per row on stderr: row i/n, id, fitted category, time, and the time left. The\n"
    "exit status is 0 when the batch went through, failed rows included (they are in the\n"
    "catalogue); 1 when the manifest is malformed (nothing is written) or DIR cannot be\n"
    "written.\n";

/* "I/N" with 0 <= I < N; 1 on success. */
static int parse_shard(const char *s, int *i, int *n)
{
    char *end;
    long a = strtol(s, &end, 10);
    if (end == s || *end != '/')
        return 0;
    const char *t = end + 1;
    long b = strtol(t, &end, 10);
    if (end == t || *end || b < 1 || b > 1000000 || a < 0 || a >= b)
        return 0;
    *i = (int)a;
    *n = (int)b;
    return 1;
}

/* The shard from Slurm's array variables: 1 set, 0 none, -1 inconsistent (message printed). */
static int slurm_shard(int *i, int *n)
{
    const char *id = getenv("SLURM_ARRAY_TASK_ID"), *count = getenv("SLURM_ARRAY_TASK_COUNT");
    const char *min = getenv("SLURM_ARRAY_TASK_MIN");
    if (!id || !*id)
        return 0;
    char none[] = "", *e1, *e2 = none, *e3 = none;
    errno = 0;
    long t = strtol(id, &e1, 10), c = count ? strtol(count, &e2, 10) : 0, m = min ? strtol(min, &e3, 10) : 0;
    const int numbers = !*e1 && !*e2 && !*e3 && errno != ERANGE && labs(t) < 1L << 30 && labs(m) < 1L << 30;
    if (!numbers || c < 1 || t - m < 0 || t - m >= c) { /* not (small) numbers, or no shard */
        fprintf(stderr,
                "squama: SLURM_ARRAY_TASK_ID %s with SLURM_ARRAY_TASK_MIN %s and SLURM_ARRAY_TASK_COUNT %s is no "
                "shard I/N (give --shard I/N; arrays must be contiguous, e.g. --array=0-7)\n",
                id, min ? min : "(unset)", count ? count : "(unset)");
        return -1;
    }
    *i = (int)(t - m);
    *n = (int)c;
    return 1;
}

typedef struct Queue {
    const int *rows;
    int n, next;
} Queue;

static int queue_next(void *ctx)
{
    Queue *q = ctx;
    return q->next < q->n ? q->rows[q->next++] : -1;
}

static int short_strip(const BatchResult *r)
{
    return r->status == BATCH_OK && r->strip_widths > 0 && r->strip_widths < CLI_SHORT_STRIP;
}

/* The closing lines: counts, the confusion matrix (text, or a JSON object) and the rows
 * fitted on short strips. */
static void summary(const Batch *b, double seconds, int resumed)
{
    int ok = 0, failed = 0, pending = 0, nshort = 0;
    for (int i = 0; i < b->nrows; i++) {
        ok += b->results[i].status == BATCH_OK;
        failed += b->results[i].status == BATCH_ERROR;
        pending += b->results[i].status == BATCH_PENDING;
        nshort += short_strip(&b->results[i]);
    }
    BatchConfusion c;
    batch_confusion(b->rows, b->results, b->nrows, &c);
    if (b->json) {
        char path[4200];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "rows", b->nrows);
        cJSON_AddNumberToObject(o, "ok", ok);
        cJSON_AddNumberToObject(o, "errors", failed);
        cJSON_AddNumberToObject(o, "pending", pending);
        cJSON_AddNumberToObject(o, "fitted_now", b->fitted_now);
        cJSON_AddNumberToObject(o, "resumed", resumed);
        cJSON_AddNumberToObject(o, "seconds", round(seconds * 10) / 10);
        cJSON_AddNumberToObject(o, "rows_per_minute", seconds > 0 ? round(6e4 * b->fitted_now / seconds) / 1e3 : 0);
        cJSON_AddNumberToObject(o, "short_strips", nshort);
        cJSON_AddNumberToObject(o, "correct", c.correct);
        cJSON_AddNumberToObject(o, "with_expected", c.total);
        snprintf(path, sizeof path, "%s/catalogue.csv", b->outdir);
        cJSON_AddStringToObject(o, "catalogue", path);
        snprintf(path, sizeof path, "%s/index.html", b->outdir);
        cJSON_AddStringToObject(o, "index", path);
        cJSON *cm = cJSON_AddObjectToObject(o, "confusion");
        for (int e = 0; e < SQ_PATTERN_COUNT; e++)
            cJSON_AddItemToObject(cm, sq_pattern_type_name(e), cJSON_CreateIntArray(c.m[e], SQ_PATTERN_COUNT));
        char *text = cJSON_PrintUnformatted(o);
        cJSON_Delete(o);
        if (text)
            printf("%s\n", text);
        free(text);
        return;
    }
    if (b->quiet)
        return;
    printf("%d rows: %d ok, %d failed%s; %d fitted now in %.1f s, %d done before\n", b->nrows, ok, failed,
           pending ? " (the rest for other shards)" : "", b->fitted_now, seconds, resumed);
    if (c.total > 0) {
        printf("expected category \\ fitted:\n%14s", "");
        for (int f = 0; f < SQ_PATTERN_COUNT; f++)
            printf(" %8.8s", sq_pattern_type_name(f));
        printf("  accuracy\n");
        for (int e = 0; e < SQ_PATTERN_COUNT; e++) {
            printf("%-14s", sq_pattern_type_name(e));
            for (int f = 0; f < SQ_PATTERN_COUNT; f++)
                printf(" %8d", c.m[e][f]);
            if (c.expected_total[e])
                printf("  %d/%d\n", c.m[e][e], c.expected_total[e]);
            else
                printf("  -\n");
        }
        printf("overall: %d of %d right (%.0f%%)\n", c.correct, c.total, 100.0 * c.correct / c.total);
    }
    if (nshort > 0) {
        printf("%d row%s fitted on a strip of under %.0f body widths, too short to see a pattern repeat (", nshort,
               nshort == 1 ? "" : "s", CLI_SHORT_STRIP);
        for (int i = 0, k = 0; i < b->nrows; i++)
            if (short_strip(&b->results[i]) && k++ < 3)
                printf("%s%s", k > 1 ? ", " : "", b->rows[i].id);
        printf("%s): see their line.png, and give them a body line along a longer stretch of the body (the "
               "manifest's body_line column) or a mask\n",
               nshort > 3 ? ", ..." : "");
    }
    printf("catalogue: %s/catalogue.csv, %s/index.html\n", b->outdir, b->outdir);
}

static int same_settings(const BatchDone *a, const BatchDone *b)
{
    return a->has_settings == b->has_settings && strcmp(a->settings, b->settings) == 0;
}

/* Warns when the merged rows were fitted with different settings (budget, seed, kinds...):
 * the catalogue then compares fits that are not alike. Each setting is listed with its
 * number of rows and the first of them; rows from before settings were recorded count apart. */
static void warn_mixed_settings(const BatchDone *done, int n)
{
    int mixed = 0;
    for (int i = 1; i < n && !mixed; i++)
        mixed = !same_settings(&done[0], &done[i]);
    if (!mixed)
        return;
    fprintf(stderr, "squama: these rows were fitted with different settings, and the catalogue mixes them:\n");
    for (int i = 0; i < n; i++) {
        int seen = 0, count = 0;
        for (int j = 0; j < i && !seen; j++)
            seen = same_settings(&done[j], &done[i]);
        if (seen)
            continue;
        for (int j = i; j < n; j++)
            count += same_settings(&done[j], &done[i]);
        fprintf(stderr, "  %d row%s (%s, ...): %s\n", count, count == 1 ? "" : "s", done[i].id,
                done[i].has_settings ? done[i].settings : "not recorded (an older batch)");
    }
}

/* Appends to rows and res (after the n there) the rows the folders' catalogues list as
 * failed that no row folder holds: the manifest's bad rows (no, a malformed or a repeated
 * id, an unknown category), which a merge would otherwise drop. A row is its id and its
 * manifest line, each once however many shards list it. Returns how many; their strings
 * stay in cats. */
static int merge_bad_rows(const SqCsv *cats, int ncats, CliManifestRow *rows, BatchResult *res, int n)
{
    static const char *const names[] = {"id", "species", "expected", "status", "error", "line"};
    int added = 0;
    for (int k = 0; k < ncats; k++) {
        if (cats[k].nrecords < 1)
            continue;
        const SqCsvRecord *h = &cats[k].records[0];
        int col[6] = {-1, -1, -1, -1, -1, -1};
        for (int f = 0; f < h->nfields; f++)
            for (int q = 0; q < 6; q++)
                if (strcmp(h->fields[f], names[q]) == 0)
                    col[q] = f;
        if (col[0] < 0 || col[3] < 0 || col[4] < 0 || col[5] < 0)
            continue; /* not a catalogue */
        for (int r = 1; r < cats[k].nrecords; r++) {
            const SqCsvRecord *rec = &cats[k].records[r];
            const char *f[6];
            for (int q = 0; q < 6; q++)
                f[q] = col[q] >= 0 && col[q] < rec->nfields ? rec->fields[col[q]] : "";
            if (strcmp(f[3], "error") != 0)
                continue;
            const int line = atoi(f[5]);
            int known = 0;
            for (int i = 0; i < n + added && !known; i++)
                known = rows[i].line == line && strcmp(rows[i].id, f[0]) == 0;
            if (known)
                continue;
            rows[n + added] = (CliManifestRow){.line = line, .id = f[0], .species = f[1],
                                               .expected = cli_manifest_category(f[2])};
            res[n + added] = (BatchResult){.status = BATCH_ERROR, .fitted = -1};
            snprintf(res[n + added].error, sizeof res[n + added].error, "%s", f[4]);
            added++;
        }
    }
    return added;
}

/* squama batch --merge DIR... -o OUT */
static int merge(char **dirs, int ndirs, Batch *b)
{
    SqError err;
    CliMade made;
    if (cli_mkdirs_new(b->outdir, &made) != 0) {
        sq_error_set(&err, SQ_ERR_IO, b->outdir, "cannot create the output folder: %s", strerror(errno));
        return cli_fail(&err);
    }
    char outreal[PATH_MAX];
    if (!realpath(b->outdir, outreal)) {
        sq_error_set(&err, SQ_ERR_IO, b->outdir, "cannot resolve: %s", strerror(errno));
        cli_rmdirs_new(b->outdir, &made);
        return cli_fail(&err);
    }
    BatchDone *done = NULL;
    SqCsv *cats = calloc((size_t)ndirs, sizeof *cats); /* each folder's catalogue: its bad rows */
    int n = 0, cap = 0, rc = CLI_OK;
    if (!cats) {
        sq_error_set(&err, SQ_ERR_NOMEM, b->outdir, "out of memory");
        rc = cli_fail(&err);
    }
    for (int k = 0; k < ndirs && rc == CLI_OK; k++) {
        char real[PATH_MAX];
        DIR *d = realpath(dirs[k], real) ? opendir(real) : NULL;
        if (!d) {
            sq_error_set(&err, SQ_ERR_IO, dirs[k], "cannot read the batch folder: %s", strerror(errno));
            rc = cli_fail(&err);
            break;
        }
        char cpath[PATH_MAX + 16];
        SqError cerr;
        if (cli_pathf(cpath, sizeof cpath, "%s/catalogue.csv", real) == 0 && access(cpath, F_OK) == 0 &&
            sq_io_csv_read(cpath, &cats[k], &cerr) != SQ_OK && !b->quiet)
            fprintf(stderr, "squama: warning: the bad rows listed in %s are left out: %s\n", cpath, cerr.what);
        int same = strcmp(real, outreal) == 0;
        struct dirent *e;
        while ((e = readdir(d)) && rc == CLI_OK) {
            if (e->d_name[0] == '.' || !cli_manifest_id_ok(e->d_name))
                continue;
            if (n == cap) {
                cap = cap ? 2 * cap : 64;
                BatchDone *p = realloc(done, (size_t)cap * sizeof *p);
                if (!p) {
                    sq_error_set(&err, SQ_ERR_NOMEM, dirs[k], "out of memory");
                    rc = cli_fail(&err);
                    break;
                }
                done = p;
            }
            char row[PATH_MAX + 80];
            if (cli_pathf(row, sizeof row, "%s/%s", real, e->d_name) != 0)
                continue;
            if (!batch_load_done(row, &done[n]) || strcmp(done[n].id, e->d_name) != 0)
                continue;
            int dup = -1;
            for (int q = 0; q < n && dup < 0; q++)
                if (strcmp(done[q].id, done[n].id) == 0)
                    dup = q;
            if (dup >= 0) {
                if (!b->quiet)
                    fprintf(stderr, "squama: %s is in more than one folder; the first is kept (%s left out)\n",
                            done[n].id, row);
                continue;
            }
            if (!same) { /* OUT/<id> becomes a link to the row, replaced atomically */
                char link[4096], tmp[4200];
                struct stat st;
                if (cli_pathf(link, sizeof link, "%s/%s", outreal, e->d_name) != 0 ||
                    cli_pathf(tmp, sizeof tmp, "%s/.tmp-link-%s", outreal, e->d_name) != 0)
                    continue;
                if (lstat(link, &st) == 0 && !S_ISLNK(st.st_mode)) {
                    if (!b->quiet)
                        fprintf(stderr, "squama: %s already holds a row %s; %s left out\n", b->outdir, e->d_name, row);
                    continue;
                }
                unlink(tmp);
                if (symlink(row, tmp) != 0 || rename(tmp, link) != 0) {
                    sq_error_set(&err, SQ_ERR_IO, link, "cannot link the row: %s", strerror(errno));
                    rc = cli_fail(&err);
                    break;
                }
            }
            n++;
        }
        closedir(d);
    }
    if (rc == CLI_OK) {
        /* manifest order: by line, then id */
        for (int i = 1; i < n; i++)
            for (int j = i; j > 0 && (done[j].line < done[j - 1].line ||
                                      (done[j].line == done[j - 1].line && strcmp(done[j].id, done[j - 1].id) < 0));
                 j--) {
                BatchDone t = done[j];
                done[j] = done[j - 1];
                done[j - 1] = t;
            }
        if (!b->quiet)
            warn_mixed_settings(done, n);
        int nbad = 0;
        for (int k = 0; k < ndirs; k++)
            nbad += cats[k].nrecords;
        CliManifestRow *rows = calloc((size_t)(n + nbad) + 1, sizeof *rows);
        BatchResult *res = calloc((size_t)(n + nbad) + 1, sizeof *res);
        if (!rows || !res) {
            sq_error_set(&err, SQ_ERR_NOMEM, b->outdir, "out of memory");
            rc = cli_fail(&err);
        }
        for (int i = 0; i < n && rc == CLI_OK; i++) {
            rows[i] = (CliManifestRow){.line = done[i].line, .id = done[i].id, .photo = done[i].photo,
                                       .mask = done[i].mask[0] ? done[i].mask : NULL,
                                       .body_line = done[i].body_line[0] ? done[i].body_line : NULL, .species = done[i].species,
                                       .expected = done[i].expected};
            res[i] = done[i].r;
        }
        const int nrows = rc == CLI_OK ? n + merge_bad_rows(cats, ndirs, rows, res, n) : n;
        /* manifest order: by line, then id */
        for (int i = 1; i < nrows; i++)
            for (int j = i; j > 0 && (rows[j].line < rows[j - 1].line ||
                                      (rows[j].line == rows[j - 1].line && strcmp(rows[j].id, rows[j - 1].id) < 0));
                 j--) {
                const CliManifestRow t = rows[j];
                rows[j] = rows[j - 1];
                rows[j - 1] = t;
                const BatchResult u = res[j];
                res[j] = res[j - 1];
                res[j - 1] = u;
            }
        for (int i = 0; i < nrows; i++)
            res[i].row = i;
        if (rc == CLI_OK && batch_write_catalogue(b->outdir, rows, res, nrows, &err) != SQ_OK)
            rc = cli_fail(&err);
        if (rc == CLI_OK) {
            b->rows = rows;
            b->results = res;
            b->nrows = nrows;
            summary(b, 0, nrows);
        }
        free(rows);
        free(res);
    }
    free(done);
    for (int k = 0; cats && k < ndirs; k++)
        sq_io_csv_free(&cats[k]);
    free(cats);
    if (rc != CLI_OK) /* the folder it made, while nothing was linked into it */
        cli_rmdirs_new(b->outdir, &made);
    return rc;
}

static int run(int argc, char **argv, int rank, int size, int local_ranks)
{
    enum { O_JOBS = CLI_FITOPT_END, O_SHARD, O_MERGE, O_JSON };
    static const struct option opts[] = {
        CLI_FIT_LONGOPTS,
        {"output", required_argument, NULL, 'o'}, {"jobs", required_argument, NULL, O_JOBS},
        {"shard", required_argument, NULL, O_SHARD}, {"merge", no_argument, NULL, O_MERGE},
        {"quiet", no_argument, NULL, 'q'},
        {"json", no_argument, NULL, O_JSON}, {"help", no_argument, NULL, 'h'}, {NULL, 0, NULL, 0}};
    Batch b = {0};
    b.rank = rank;
    cli_fit_job_init(&b.job);
    int c, jobs = 1, shard_i = 0, shard_n = 1, shard_given = 0, merging = 0;
    long v;
    SqError err;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":ho:b:s:j:q", opts, NULL)) != -1) {
        int taken = cli_fit_job_option(&b.job, c, optarg, "batch");
        if (taken >= 0) {
            if (taken != CLI_OK)
                return taken;
            continue;
        }
        switch (c) {
        case 'o': b.outdir = optarg; break;
        case O_JOBS:
            if (cli_parse_int("--jobs", optarg, 1, 64, &v, &err) != 0)
                return cli_usage("batch", "%s", err.what);
            jobs = (int)v;
            break;
        case O_SHARD:
            if (!parse_shard(optarg, &shard_i, &shard_n))
                return cli_usage("batch", "--shard takes I/N with 0 <= I < N, got '%s'", optarg);
            shard_given = 1;
            break;
        case O_MERGE: merging = 1; break;
        case 'q': b.quiet = 1; break;
        case O_JSON: b.json = 1; break;
        case 'h':
            fputs(help, stdout);
            fputs(help_more, stdout);
            return CLI_OK;
        default:
            return cli_bad_option("batch", argv, c, opts);
        }
    }
    if (!b.outdir)
        return cli_usage("batch", "say where the results go with -o DIR");
    if (merging) {
        if (argc - optind < 1)
            return cli_usage("batch", "--merge needs the batch folders to join");
        if (size > 1)
            return cli_usage("batch", "--merge runs on one process, not under mpirun");
        return merge(argv + optind, argc - optind, &b);
    }
    if (argc - optind != 1)
        return cli_usage("batch", "give one MANIFEST");
    if (size > 1 && jobs > 1)
        return cli_usage("batch", "under MPI each rank fits one row at a time: start more ranks instead of --jobs");
    if (!shard_given) {
        int s = slurm_shard(&shard_i, &shard_n);
        if (s < 0)
            return CLI_USAGE;
    }
    const char *manifest = argv[optind];
    CliManifest m;
    if (cli_manifest_read(manifest, &m, &err) != SQ_OK)
        return cli_fail(&err);
    int rc = cli_fit_job_options_done(&b.job, "batch");
    if (rc != CLI_OK) {
        cli_manifest_free(&m);
        return rc;
    }

    int cores = omp_get_num_procs();
    b.jobs = jobs;
    b.threads = b.job.fo.threads > 0 ? b.job.fo.threads : cores / (jobs * (local_ranks > 0 ? local_ranks : 1));
    if (b.threads < 1)
        b.threads = 1;
    b.rows = m.rows;
    b.nrows = m.nrows;
    b.results = calloc(m.nrows > 0 ? (size_t)m.nrows : 1, sizeof *b.results);
    b.mine = calloc(m.nrows > 0 ? (size_t)m.nrows : 1, 1);
    int *pending = calloc(m.nrows > 0 ? (size_t)m.nrows : 1, sizeof *pending);
    int npending = 0, resumed = 0;
    pthread_mutex_init(&b.lock, NULL);
    if (!b.results || !b.mine || !pending) {
        sq_error_set(&err, SQ_ERR_NOMEM, manifest, "out of memory");
        rc = rank == 0 ? cli_fail(&err) : CLI_FAIL;
    }
    if (rc == CLI_OK && rank == 0 && cli_mkdirs(b.outdir) != 0) {
        sq_error_set(&err, SQ_ERR_IO, b.outdir, "cannot create the output folder: %s", strerror(errno));
        rc = cli_fail(&err);
    }
    b.t0 = cli_now_s();
    if (rc == CLI_OK && rank == 0) {
        /* bad rows, rows done before (by this run's shard or any other), rows to fit */
        for (int i = 0; i < m.nrows; i++) {
            b.mine[i] = i % shard_n == shard_i;
            b.total += b.mine[i];
        }
        for (int i = 0; i < m.nrows; i++) {
            BatchResult *r = &b.results[i];
            r->row = i;
            r->fitted = -1;
            if (m.rows[i].error) {
                r->status = BATCH_ERROR;
                snprintf(r->error, sizeof r->error, "%s (%s:%d)", m.rows[i].error, manifest, m.rows[i].line);
            } else if (batch_read_done(&b, i, !b.mine[i], r)) { /* another shard's failures stay listed */
                resumed += b.mine[i];
            } else if (b.mine[i]) {
                pending[npending++] = i;
            }
            if (b.mine[i] && r->status != BATCH_PENDING) {
                b.done++;
                if (b.json || (!b.quiet && m.rows[i].error))
                    batch_report_row(&b, r);
            }
        }
        if (!b.quiet && !b.json && (resumed || shard_n > 1))
            fprintf(stderr, "squama batch: %d rows%s: %d done before, %d to fit%s\n", b.total,
                    shard_n > 1 ? " in this shard" : "", resumed, npending,
                    size > 1 ? " over the MPI ranks" : jobs > 1 ? " on local jobs" : "");
        if (batch_write_catalogue(b.outdir, b.rows, b.results, b.nrows, &err) != SQ_OK)
            rc = cli_fail(&err);
    }
    if (rc == CLI_OK || size > 1) {
        if (rc != CLI_OK)
            npending = 0; /* rank 0 failed: the workers are only told to stop */
        if (size > 1) {
            batch_mpi_run(&b, rank, size, pending, npending);
        } else {
            Queue q = {pending, npending, 0};
            batch_run_local(&b, jobs < npending ? jobs : (npending > 0 ? npending : 1), queue_next, &q);
        }
    }
    if (rc == CLI_OK && rank == 0) {
        /* the rows other shards finished meanwhile */
        for (int i = 0; i < m.nrows; i++)
            if (!b.mine[i] && b.results[i].status == BATCH_PENDING)
                batch_read_done(&b, i, 1, &b.results[i]);
        if (batch_write_catalogue(b.outdir, b.rows, b.results, b.nrows, &err) != SQ_OK)
            rc = cli_fail(&err);
        else if (b.write_failed)
            rc = cli_fail(&b.write_err);
        if (rc == CLI_OK)
            summary(&b, cli_now_s() - b.t0, resumed);
    }
    pthread_mutex_destroy(&b.lock);
    free(pending);
    free(b.results);
    free(b.mine);
    cli_manifest_free(&m);
    cli_fit_job_free(&b.job);
    return rc;
}

int cmd_batch(int argc, char **argv)
{
    int rank = 0, size = 1, local = 1, mpi = batch_mpi_launched();
    if (mpi < 0) {
        fprintf(stderr, "squama: this squama was built without MPI, so its copies under mpirun would all fit "
                        "every row: run it alone (--jobs J for more rows at once) or build with -DSQUAMA_MPI=ON\n");
        return CLI_FAIL;
    }
    if (mpi && batch_mpi_init(&rank, &size, &local) != 0)
        return CLI_FAIL;
    int saved[2] = {-1, -1};
    if (rank > 0) { /* the workers' messages would repeat rank 0's */
        fflush(stdout);
        fflush(stderr);
        int null = open("/dev/null", O_WRONLY);
        for (int k = 0; k < 2 && null >= 0; k++) {
            saved[k] = dup(k + 1);
            dup2(null, k + 1);
        }
        if (null >= 0)
            close(null);
    }
    int rc = run(argc, argv, rank, size, local);
    if (mpi)
        batch_mpi_finalize();
    for (int k = 0; k < 2; k++)
        if (saved[k] >= 0) {
            fflush(k ? stderr : stdout);
            dup2(saved[k], k + 1);
            close(saved[k]);
        }
    return rc;
}
