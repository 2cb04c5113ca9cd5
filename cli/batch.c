/* squama batch: one row fitted into its folder, read back, recorded; rows on local threads. */
#define _GNU_SOURCE /* posix_spawn_file_actions_addclosefrom_np */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <spawn.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "batch.h"
#include "cli.h"
#include "json_util.h"
#include "squama/io.h"
#include "squama/search.h"
#include "thumb.h"

/* The batch's pid, in the environment of the fits it starts (cli_batch_child). */
#define BATCH_PARENT_ENV "SQUAMA_BATCH_PARENT"

/* FNV-1a (64 bits) of a file's bytes as 16 hex digits, "" when it cannot be read: a row
 * is known by its photo's and mask's contents, not by how their paths were spelled. */
static void file_digest(const char *path, char out[BATCH_DIGEST])
{
    out[0] = 0;
    FILE *fp = path ? fopen(path, "rb") : NULL;
    if (!fp)
        return;
    uint64_t h = 0xcbf29ce484222325u;
    unsigned char buf[8192]; /* small: rows are fitted on threads with default stacks */
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, fp)) > 0)
        for (size_t i = 0; i < n; i++)
            h = (h ^ buf[i]) * 0x100000001b3u;
    if (!ferror(fp))
        snprintf(out, BATCH_DIGEST, "%016llx", (unsigned long long)h);
    fclose(fp);
}

/* DIR/thumb_strips.png from DIR's strip.png and fitted_strip.png. */
static SqStatus strips_thumbnail(const char *dir, SqError *err)
{
    char strip[4200], fitted[4200], dst[4200];
    snprintf(strip, sizeof strip, "%s/strip.png", dir);
    snprintf(fitted, sizeof fitted, "%s/fitted_strip.png", dir);
    snprintf(dst, sizeof dst, "%s/thumb_strips.png", dir);
    return cli_thumbnail_strips(strip, fitted, dst, err);
}

void batch_settings(const CliFitJob *job, char *out, size_t n)
{
    const SqFitOptions *o = &job->fo;
    int k = snprintf(out, n, "budget=%g evals=%ld seed=%llu categories=%u size=%d work-size=%d", o->budget,
                     o->max_evals, (unsigned long long)o->seed, o->categories, job->size, job->po.work_size);
    if (job->starts.n > 0 && k >= 0 && (size_t)k < n) /* the starting presets, by their contents */
        snprintf(out + k, n - (size_t)k, " starts=%d:%016llx", job->starts.n, (unsigned long long)job->starts.digest);
}

/* DIR/<id>/done.json: the row and its outcome, everything the catalogue needs, and what
 * tells a later run whether it still stands (the inputs' digests, the fit's settings). */
static SqStatus write_done(const char *dir, const Batch *b, const CliManifestRow *row, const BatchResult *r,
                           const char *photo_digest, const char *mask_digest, const char *line_digest,
                           SqError *err)
{
    char settings[sizeof ((BatchDone *)0)->settings];
    batch_settings(&b->job, settings, sizeof settings);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", "squama-batch-row/1");
    cJSON_AddStringToObject(root, "id", row->id);
    cJSON_AddNumberToObject(root, "line", row->line);
    cJSON_AddStringToObject(root, "photo", row->photo ? row->photo : "");
    if (row->mask)
        cJSON_AddStringToObject(root, "mask", row->mask);
    if (row->body_line)
        cJSON_AddStringToObject(root, "body_line", row->body_line);
    if (photo_digest[0])
        cJSON_AddStringToObject(root, "photo_digest", photo_digest);
    if (mask_digest[0])
        cJSON_AddStringToObject(root, "mask_digest", mask_digest);
    if (line_digest[0])
        cJSON_AddStringToObject(root, "line_digest", line_digest);
    cJSON_AddStringToObject(root, "settings", settings);
    cJSON_AddStringToObject(root, "species", row->species);
    if (row->expected >= 0)
        cJSON_AddStringToObject(root, "expected", sq_pattern_type_name(row->expected));
    cJSON_AddStringToObject(root, "status", r->status == BATCH_OK ? "ok" : "error");
    if (r->status == BATCH_OK) {
        cJSON_AddStringToObject(root, "category", sq_pattern_type_name(r->fitted));
        cJSON_AddItemToObject(root, "score", sq__json_exact_number(r->score));
        cJSON *o = cJSON_AddObjectToObject(root, "objectives");
        for (int k = 0; k < SQ_OBJ_COUNT; k++)
            cJSON_AddItemToObject(o, sq_fit_objective_name(k), sq__json_exact_number(r->obj[k]));
        cJSON_AddNumberToObject(root, "evaluations", (double)r->evals);
        if (r->strip_widths > 0)
            cJSON_AddItemToObject(root, "strip_body_widths", sq__json_exact_number(r->strip_widths));
    } else {
        cJSON_AddStringToObject(root, "error", r->error);
    }
    cJSON_AddNumberToObject(root, "seconds", r->seconds);
    char *text = sq__json_print(root);
    cJSON_Delete(root);
    char path[4096];
    if (cli_pathf(path, sizeof path, "%s/done.json", dir) != 0) {
        free(text);
        return sq_error_set(err, SQ_ERR_IO, dir, "the path is too long");
    }
    if (!text)
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    SqStatus st = sq_io_write_file(path, text, strlen(text), err);
    free(text);
    return st;
}

int batch_load_done(const char *dir, BatchDone *d)
{
    char path[4096], *text;
    size_t len;
    if (cli_pathf(path, sizeof path, "%s/done.json", dir) != 0 ||
        sq_io_read_file(path, 1 << 20, &text, &len, NULL) != SQ_OK)
        return 0;
    int ok = batch_parse_done(text, len, d);
    free(text);
    return ok;
}

/* A record of row's photo, mask and body line: by their contents, wherever they are now;
 * by their paths when it has no digest (the photo could not be read, or an older record). */
static int same_inputs(const BatchDone *d, const CliManifestRow *row)
{
    if (!d->photo_digest[0])
        return strcmp(d->photo, row->photo ? row->photo : "") == 0 &&
               strcmp(d->mask, row->mask ? row->mask : "") == 0 &&
               strcmp(d->body_line, row->body_line ? row->body_line : "") == 0;
    char pd[BATCH_DIGEST], md[BATCH_DIGEST], ld[BATCH_DIGEST];
    file_digest(row->photo, pd);
    file_digest(row->mask, md);
    file_digest(row->body_line, ld);
    return strcmp(d->photo_digest, pd) == 0 && strcmp(d->mask_digest, md) == 0 && !row->mask == !d->mask[0] &&
           strcmp(d->line_digest, ld) == 0 && !row->body_line == !d->body_line[0];
}

int batch_read_done(const Batch *b, int i, int other_shard, BatchResult *out)
{
    const CliManifestRow *row = &b->rows[i];
    char dir[4096], settings[sizeof ((BatchDone *)0)->settings];
    snprintf(dir, sizeof dir, "%s/%s", b->outdir, row->id);
    batch_settings(&b->job, settings, sizeof settings);
    BatchDone *d = malloc(sizeof *d);
    if (!d)
        return 0;
    int ok = batch_load_done(dir, d) && strcmp(d->id, row->id) == 0 &&
             (d->r.status == BATCH_OK || other_shard) && (other_shard || same_inputs(d, row)) &&
             (!d->has_settings || strcmp(d->settings, settings) == 0); /* other settings: fitted again */
    if (ok) {
        *out = d->r;
        out->row = i;
        struct stat sb; /* a row of an older squama: its strips' thumbnail made now */
        char strips[4200];
        snprintf(strips, sizeof strips, "%s/thumb_strips.png", dir);
        if (out->status == BATCH_OK && stat(strips, &sb) != 0)
            strips_thumbnail(dir, NULL);
    }
    free(d);
    return ok;
}

extern char **environ;

/* What batch_fit_row reads back of a row's fit. */
typedef struct RowFit {
    int fitted; /* SqPatternType */
    double score, obj[SQ_OBJ_COUNT], seconds;
    long evals;
    double strip_widths;
} RowFit;

/* The outcome of a fit from its DIR/fit.json. */
static SqStatus read_fit_json(const char *dir, RowFit *out, SqError *err)
{
    char path[4200], *text = NULL;
    size_t len;
    snprintf(path, sizeof path, "%s/fit.json", dir);
    SqStatus st = sq_io_read_file(path, 64 << 20, &text, &len, err);
    if (st != SQ_OK)
        return st;
    cJSON *root = cJSON_ParseWithLength(text, len);
    free(text);
    const cJSON *cat = cJSON_GetObjectItemCaseSensitive(root, "category"),
                *score = cJSON_GetObjectItemCaseSensitive(root, "score"),
                *obj = cJSON_GetObjectItemCaseSensitive(root, "objectives"),
                *se = cJSON_GetObjectItemCaseSensitive(root, "search"),
                *ev = cJSON_GetObjectItemCaseSensitive(se, "evaluations"),
                *secs = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(se, "seconds"), "total");
    out->fitted = -1;
    if (cJSON_IsString(cat)) { /* a layered skin combines pattern types: the thesis' complex category (its Sec. 4.2.5) */
        int k = sq_fit_kind_from_name(cat->valuestring);
        out->fitted = k == SQ_FIT_LAYERED ? SQ_PATTERN_COMPLEX : k;
    }
    int ok = out->fitted >= 0 && cJSON_IsNumber(score) && cJSON_IsNumber(ev) && cJSON_IsNumber(secs);
    for (int k = 0; ok && k < SQ_OBJ_COUNT; k++) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, sq_fit_objective_name(k));
        ok = cJSON_IsNumber(v);
        if (ok)
            out->obj[k] = v->valuedouble;
    }
    if (ok) {
        out->score = score->valuedouble;
        out->evals = (long)ev->valuedouble;
        out->seconds = secs->valuedouble;
        const cJSON *in = cJSON_GetObjectItemCaseSensitive(root, "inputs"),
                    *slen = cJSON_GetObjectItemCaseSensitive(in, "strip_length_px"),
                    *wid = cJSON_GetObjectItemCaseSensitive(in, "body_width_px");
        out->strip_widths = cJSON_IsNumber(slen) && cJSON_IsNumber(wid) && wid->valuedouble > 0
                                ? slen->valuedouble / wid->valuedouble
                                : 0;
    }
    cJSON_Delete(root);
    return ok ? SQ_OK : sq_error_set(err, SQ_ERR_PARSE, path, "the fit's record lacks its category, score or objectives");
}

/* The last line of a file that is not empty, without a leading "squama: ". */
static void last_line(const char *path, char *out, size_t n)
{
    out[0] = 0;
    FILE *fp = fopen(path, "r");
    if (!fp)
        return;
    char line[2048];
    while (fgets(line, sizeof line, fp)) {
        line[strcspn(line, "\r\n")] = 0;
        if (line[0]) {
            const char *t = strncmp(line, "squama: ", 8) == 0 ? line + 8 : line;
            size_t m = strlen(t) < n ? strlen(t) : n - 1;
            memcpy(out, t, m);
            out[m] = 0;
        }
    }
    fclose(fp);
}

/* Fits a row in a process of its own, `squama fit` with the batch's settings, so that a
 * fit that crashes (a library's failed assertion, say) costs its row and not the batch:
 * the program is this squama, or $SQUAMA_FIT_PROGRAM (the tests' way to make a row
 * crash). Its error output goes to log; a fit that fails leaves its message there. */
static SqStatus fit_in_child(const CliFitJob *job, const char *log, RowFit *out, SqError *err)
{
    const SqFitOptions *fo = &job->fo;
    char budget[64], evals[32], seed[32], threads[32], size[32], work[32], cats[256] = "";
    const char *argv[32 + 2 * CLI_START_ARGS];
    int a = 0;
    argv[a++] = "squama";
    argv[a++] = "fit";
    argv[a++] = "-o";
    argv[a++] = job->outdir;
    if (job->mask) {
        argv[a++] = "--mask";
        argv[a++] = job->mask;
    }
    if (job->line) {
        argv[a++] = "--line";
        argv[a++] = job->line;
    }
    if (fo->budget > 0) {
        snprintf(budget, sizeof budget, "%.17gs", fo->budget);
        argv[a++] = "--budget";
        argv[a++] = budget;
    }
    if (fo->max_evals > 0) {
        snprintf(evals, sizeof evals, "%ld", fo->max_evals);
        argv[a++] = "--evals";
        argv[a++] = evals;
    }
    snprintf(seed, sizeof seed, "%llu", (unsigned long long)fo->seed);
    snprintf(threads, sizeof threads, "%d", fo->threads); /* the batch sets 1 or more */
    snprintf(size, sizeof size, "%d", job->size);
    snprintf(work, sizeof work, "%d", job->po.work_size);
    argv[a++] = "--seed";
    argv[a++] = seed;
    argv[a++] = "--threads";
    argv[a++] = threads;
    argv[a++] = "--size";
    argv[a++] = size;
    argv[a++] = "--work-size";
    argv[a++] = work;
    if (fo->categories) {
        for (int k = 0; k < SQ_FIT_KINDS; k++)
            if ((fo->categories >> k) & 1u)
                snprintf(cats + strlen(cats), sizeof cats - strlen(cats), "%s%s", cats[0] ? "," : "", sq_fit_kind_name(k));
        argv[a++] = "--categories";
        argv[a++] = cats;
    }
    if (job->starts.none) /* the starts as given: the fit loads them as the batch did */
        argv[a++] = "--no-starts";
    for (int i = 0; i < job->starts.nargs; i++) {
        argv[a++] = "--start";
        argv[a++] = job->starts.arg[i];
    }
    argv[a++] = "-q";
    argv[a++] = "--"; /* a photo named -x.jpg is a photo */
    argv[a++] = job->photo;
    argv[a] = NULL;

    const char *prog = getenv("SQUAMA_FIT_PROGRAM");
    if (!prog || !prog[0])
        prog = "/proc/self/exe";
    /* posix_spawn, not fork: glibc's shares the batch's memory until the exec (vfork), so a
     * rank whose memory an MPI transport has registered never copies it into a child. The
     * fit dies with the thread that started it (cli_batch_child): a batch killed outright
     * leaves no fit writing into a .tmp- folder that the next run is fitting again. */
    size_t nenv = 0;
    while (environ[nenv])
        nenv++;
    char die_with[64];
    snprintf(die_with, sizeof die_with, "%s=%ld", BATCH_PARENT_ENV, (long)getpid());
    char **env = malloc(sizeof *env * (nenv + 2));
    if (!env)
        return sq_error_set(err, SQ_ERR_NOMEM, "batch", "out of memory");
    size_t k = 0;
    for (size_t i = 0; i < nenv; i++)
        if (strncmp(environ[i], BATCH_PARENT_ENV "=", sizeof BATCH_PARENT_ENV) != 0)
            env[k++] = environ[i];
    env[k++] = die_with;
    env[k] = NULL;
    posix_spawn_file_actions_t fa;
    pid_t pid = -1;
    int rc = posix_spawn_file_actions_init(&fa);
    if (rc == 0) {
        /* none of the batch's other files (another row's log, an MPI socket) in the fit */
        if ((rc = posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0)) == 0 &&
            (rc = posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0)) == 0 &&
            (rc = posix_spawn_file_actions_addopen(&fa, 2, log, O_WRONLY | O_CREAT | O_TRUNC, 0644)) == 0 &&
            (rc = posix_spawn_file_actions_addclosefrom_np(&fa, 3)) == 0)
            rc = posix_spawn(&pid, prog, &fa, NULL, (char *const *)argv, env);
        posix_spawn_file_actions_destroy(&fa);
    }
    free(env);
    if (rc != 0)
        return sq_error_set(err, SQ_ERR_IO, "batch", "cannot start the fit (%s): %s", prog, strerror(rc));
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            return sq_error_set(err, SQ_ERR_INTERNAL, "batch", "lost the fit's process: %s", strerror(errno));
    char msg[900];
    last_line(log, msg, sizeof msg);
    if (WIFSIGNALED(status))
        return sq_error_set(err, SQ_ERR_INTERNAL, NULL, "the fit crashed (signal %d, %s)%s%s", WTERMSIG(status),
                            strsignal(WTERMSIG(status)), msg[0] ? ": " : "", msg);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        if (!msg[0])
            snprintf(msg, sizeof msg, "the fit failed (exit %d) without saying why", WEXITSTATUS(status));
        return sq_error_set(err, SQ_ERR_INTERNAL, NULL, "%s", msg);
    }
    return read_fit_json(job->outdir, out, err);
}

/* In a fit that a batch started (BATCH_PARENT_ENV, set by the batch): it dies with the
 * batch thread that started it (SIGKILL when that thread ends), and at once when the batch
 * has gone already. A wrapper between them (SQUAMA_FIT_PROGRAM) is taken as the parent. */
void cli_batch_child(void)
{
    const char *v = getenv(BATCH_PARENT_ENV);
    if (!v)
        return;
    char *end;
    errno = 0;
    const long parent = strtol(v, &end, 10);
    const int ok = errno == 0 && end != v && !*end && parent > 0;
    unsetenv(BATCH_PARENT_ENV); /* not for whatever this process starts */
    if (!ok)
        return;
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0)
        return;
    if (getppid() != (pid_t)parent && kill((pid_t)parent, 0) != 0 && errno == ESRCH)
        _exit(127);
}

void batch_fit_row(const Batch *b, int i, BatchResult *out)
{
    const CliManifestRow *row = &b->rows[i];
    memset(out, 0, sizeof *out);
    out->row = i;
    out->fitted = -1;
    out->rank = b->rank;
    char tmp[4096], final[4096], log[4200];
    SqError err;
    sq_error_clear(&err);
    SqStatus st = SQ_OK;
    if (cli_pathf(tmp, sizeof tmp, "%s/.tmp-%s", b->outdir, row->id) != 0 ||
        cli_pathf(final, sizeof final, "%s/%s", b->outdir, row->id) != 0 ||
        cli_pathf(log, sizeof log, "%s/.tmp-%s/stderr.log", b->outdir, row->id) != 0) {
        out->status = BATCH_ERROR;
        snprintf(out->error, sizeof out->error, "the output folder's path is too long");
        return;
    }
    if (cli_remove_tree(tmp) != 0) /* a partial row of an interrupted run */
        st = sq_error_set(&err, SQ_ERR_IO, tmp, "cannot remove the partial output: %s", strerror(errno));
    else if (cli_mkdirs(tmp) != 0) /* the fit's folder, its log in it */
        st = sq_error_set(&err, SQ_ERR_IO, tmp, "cannot create the output folder: %s", strerror(errno));
    char photo_digest[BATCH_DIGEST], mask_digest[BATCH_DIGEST], line_digest[BATCH_DIGEST];
    file_digest(row->photo, photo_digest); /* of what is fitted */
    file_digest(row->mask, mask_digest);
    file_digest(row->body_line, line_digest);
    CliFitJob job = b->job;
    job.photo = row->photo;
    job.mask = row->mask;
    job.line = row->body_line;
    job.outdir = tmp;
    job.quiet = 1;
    job.json = 0;
    job.fo.threads = b->threads;
    RowFit fit;
    if (st == SQ_OK)
        st = fit_in_child(&job, log, &fit, &err);
    remove(log);
    if (st == SQ_OK) {
        /* the photo with what the mask leaves out veiled, the textures, the strips */
        static const char *const thumbs[][3] = {{"photo.jpg", "mask.png", "thumb_photo.png"},
                                                {"basecolor.png", NULL, "thumb_texture.png"},
                                                {"preview.png", NULL, "thumb_preview.png"}};
        for (size_t k = 0; k < sizeof thumbs / sizeof thumbs[0] && st == SQ_OK; k++) {
            char src[4200], mask[4200], dst[4200];
            snprintf(src, sizeof src, "%s/%s", tmp, thumbs[k][0]);
            snprintf(mask, sizeof mask, "%s/%s", tmp, thumbs[k][1] ? thumbs[k][1] : "");
            snprintf(dst, sizeof dst, "%s/%s", tmp, thumbs[k][2]);
            st = cli_thumbnail(src, thumbs[k][1] ? mask : NULL, dst, &err);
        }
        if (st == SQ_OK)
            st = strips_thumbnail(tmp, &err);
    }
    if (st == SQ_OK) {
        out->status = BATCH_OK;
        out->fitted = fit.fitted;
        out->score = fit.score;
        memcpy(out->obj, fit.obj, sizeof out->obj);
        out->evals = fit.evals;
        out->seconds = fit.seconds;
        out->strip_widths = fit.strip_widths;
    } else {
        /* an error row keeps only its done.json */
        out->status = BATCH_ERROR;
        if (err.where[0])
            snprintf(out->error, sizeof out->error, "%s (%s)", err.what, err.where);
        else
            snprintf(out->error, sizeof out->error, "%s", err.what);
        cli_remove_tree(tmp);
        if (cli_mkdirs(tmp) != 0) {
            snprintf(out->error, sizeof out->error, "cannot create %.900s: %s", tmp, strerror(errno));
            return;
        }
    }
    /* done.json last, then the whole folder renamed into place */
    if (write_done(tmp, b, row, out, photo_digest, mask_digest, line_digest, &err) != SQ_OK || cli_remove_tree(final) != 0 || rename(tmp, final) != 0) {
        out->status = BATCH_ERROR;
        out->fitted = -1;
        snprintf(out->error, sizeof out->error, "cannot complete %.900s: %.100s", final,
                 err.status != SQ_OK ? err.what : strerror(errno));
    }
}

void batch_report_row(const Batch *b, const BatchResult *r)
{
    const CliManifestRow *row = &b->rows[r->row];
    double el = cli_now_s() - b->t0;
    double eta = b->fitted_now > 0 ? el / b->fitted_now * (b->total - b->done) : NAN;
    const char *cat = r->status == BATCH_OK ? sq_pattern_type_name(r->fitted) : "error";
    if (b->json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "row", b->done);
        cJSON_AddNumberToObject(o, "of", b->total);
        cJSON_AddStringToObject(o, "id", row->id);
        cJSON_AddNumberToObject(o, "line", row->line);
        cJSON_AddStringToObject(o, "status", r->status == BATCH_OK ? "ok" : "error");
        cJSON_AddStringToObject(o, "category", cat);
        cJSON_AddStringToObject(o, "expected", row->expected >= 0 ? sq_pattern_type_name(row->expected) : "");
        cJSON_AddBoolToObject(o, "resumed", r->resumed);
        if (!r->resumed)
            cJSON_AddNumberToObject(o, "rank", r->rank);
        cJSON_AddNumberToObject(o, "seconds", round(r->seconds * 100) / 100);
        cJSON_AddNumberToObject(o, "eta_s", isfinite(eta) ? round(eta) : -1);
        if (r->status != BATCH_OK)
            cJSON_AddStringToObject(o, "error", r->error);
        char *text = cJSON_PrintUnformatted(o);
        cJSON_Delete(o);
        if (text)
            printf("%s\n", text);
        free(text);
        fflush(stdout);
    } else if (!b->quiet) {
        char when[64] = "";
        if (isfinite(eta))
            snprintf(when, sizeof when, ", ETA %dm%02ds", (int)(eta / 60), (int)fmod(eta, 60));
        if (r->status == BATCH_OK)
            fprintf(stderr, "squama batch: [%d/%d] %s: %s%s%s%s, score %.3f, %.1f s%s\n", b->done, b->total,
                    row->id, cat, row->expected >= 0 ? " (expected " : "",
                    row->expected >= 0 ? sq_pattern_type_name(row->expected) : "", row->expected >= 0 ? ")" : "",
                    r->score, r->seconds, r->resumed ? " (done before)" : when);
        else
            fprintf(stderr, "squama batch: [%d/%d] %s: error: %s%s\n", b->done, b->total, row->id[0] ? row->id : "?",
                    r->error, r->resumed ? " (done before)" : when);
    }
}

void batch_record(Batch *b, const BatchResult *r)
{
    pthread_mutex_lock(&b->lock);
    b->results[r->row] = *r;
    b->done++;
    if (!r->resumed)
        b->fitted_now++;
    batch_report_row(b, r);
    SqError err;
    if (batch_write_catalogue(b->outdir, b->rows, b->results, b->nrows, &err) != SQ_OK) {
        b->write_err = err;
        b->write_failed = 1;
    }
    pthread_mutex_unlock(&b->lock);
}

typedef struct Local {
    Batch *b;
    BatchNextFn next;
    void *ctx;
    pthread_mutex_t lock;
} Local;

static void *local_worker(void *arg)
{
    Local *l = arg;
    for (;;) {
        pthread_mutex_lock(&l->lock);
        int i = l->next(l->ctx);
        pthread_mutex_unlock(&l->lock);
        if (i < 0)
            return NULL;
        BatchResult r;
        batch_fit_row(l->b, i, &r);
        batch_record(l->b, &r);
    }
}

void batch_run_local(Batch *b, int jobs, BatchNextFn next, void *ctx)
{
    Local l = {.b = b, .next = next, .ctx = ctx};
    pthread_mutex_init(&l.lock, NULL);
    pthread_t th[64];
    int n = 0;
    for (int k = 1; k < jobs && k < 64; k++) /* this thread is the first job */
        if (pthread_create(&th[n], NULL, local_worker, &l) == 0)
            n++;
    local_worker(&l);
    for (int k = 0; k < n; k++)
        pthread_join(th[k], NULL);
    pthread_mutex_destroy(&l.lock);
}
