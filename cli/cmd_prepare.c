/* squama prepare: a photo's mask, centre line and straightened strip, for looking at
 * (and for correcting the mask). */
#define _POSIX_C_SOURCE 200809L

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
#include "json_util.h"
#include "thumb.h"
#include "squama/fitness.h"
#include "squama/io.h"

static const char help[] =
    "usage: squama prepare PHOTO [--mask MASK] [--line LINE] -o DIR [--debug]\n"
    "\n"
    "Finds the snake in PHOTO (MASK if given: white on the snake, the photo's size; else\n"
    "the photo's alpha; else an automatic GrabCut), follows the body's centre line and\n"
    "straightens its clean stretches (between crossings) into a strip, with the light evened\n"
    "out. Where no mask can say where the body runs (its coils touch, the ground has its\n"
    "colours), a body line can: LINE, a JSON file of the centre line's stretches and the\n"
    "body's width in photo pixels, followed as it is (within its width, the body told from\n"
    "the ground beside it by colour).\n"
    "Writes DIR/mask.png (the photo's size: correct it and pass it back with --mask),\n"
    "DIR/line.json (the centre line followed, a point every half body width: correct it and\n"
    "pass it back with --line; not with --line), DIR/line.png (that line over the photo, its\n"
    "points numbered, with a grid in the photo's pixels to read them off), DIR/strip.png,\n"
    "DIR/prepared.json (body width, length,\n"
    "stretches, mask source, the light's direction in the photo), all of them as a set (a\n"
    "run that fails leaves an earlier run's as they were), and, with --debug, every step\n"
    "as an image in DIR/debug/.\n"
    "\n"
    "The body line's form (x right, y down, from the photo's top-left corner):\n"
    "  {\"format\": \"squama-body-line/1\", \"width\": 58,\n"
    "   \"stretches\": [[[120, 400], [180, 352], [260, 330]], [[500, 210], [610, 190]]]}\n"
    "\n"
    "options:\n"
    "  -m, --mask MASK      the snake's mask (with a line: which pixels within its width are body)\n"
    "  -l, --line LINE      the body's centre line and width\n"
    "  -o, --output DIR     where to write\n"
    "      --work-size N    longest side the photo is prepared at (default 1024)\n"
    "      --debug          save each step\n"
    "  -h, --help           show this help\n";

/* Makes dir and its parents (like mkdir -p); each folder it made, if any, in made. */
int cli_mkdirs_new(const char *path, CliMade *made)
{
    char buf[4096];
    CliMade own; /* the folders made, removed again when a deeper one cannot be made */
    if (!made)
        made = &own;
    made->n = 0;
    if (!path[0] || snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf) {
        errno = path[0] ? ENAMETOOLONG : ENOENT;
        return -1;
    }
    for (char *c = buf + 1;; c++) {
        if (*c != '/' && *c != '\0')
            continue;
        const char end = *c;
        *c = '\0';
        if (mkdir(buf, 0777) == 0) {
            if (made->n < CLI_MADE_MAX)
                made->len[made->n++] = (int)(c - buf);
        } else if (errno != EEXIST) {
            const int e = errno;
            cli_rmdirs_new(path, made);
            made->n = 0;
            errno = e;
            return -1;
        }
        if (!end)
            break;
        *c = '/';
    }
    struct stat st;
    return stat(buf, &st) == 0 && S_ISDIR(st.st_mode) ? 0 : -1;
}

int cli_mkdirs(const char *path)
{
    return cli_mkdirs_new(path, NULL);
}

void cli_made_register(const char *path, const CliMade *made)
{
    char buf[4096];
    for (int i = made->n - 1; i >= 0; i--)
        if (snprintf(buf, sizeof buf, "%.*s", made->len[i], path) < (int)sizeof buf)
            sq_io_temp_add(buf);
}

void cli_made_forget(const char *path, const CliMade *made)
{
    char buf[4096];
    for (int i = 0; i < made->n; i++)
        if (snprintf(buf, sizeof buf, "%.*s", made->len[i], path) < (int)sizeof buf)
            sq_io_temp_forget(buf);
}

void cli_rmdirs_new(const char *path, const CliMade *made)
{
    char buf[4096];
    for (int i = made ? made->n - 1 : -1; i >= 0; i--) /* the last made first; each only if empty */
        if (snprintf(buf, sizeof buf, "%.*s", made->len[i], path) < (int)sizeof buf && rmdir(buf) != 0)
            return;
}

SqStatus cli_write_full_mask(CliStaging *s, const char *dir, const SqPrepared *prep, const CliPhoto *in,
                             const char *mask_path, SqError *err)
{
    char path[4200];
    if (cli_pathf(path, sizeof path, "%s/mask.png", dir) != 0)
        return sq_error_set(err, SQ_ERR_IO, dir, "path too long");
    if (mask_path && cli_same_file(mask_path, path))
        return SQ_OK; /* the mask given is this one: kept as it is */
    SqStatus st = cli_staging_path(s, "mask.png", path, sizeof path, err);
    if (st != SQ_OK)
        return st;
    SqImage full;
    if (cli_thumb_nearest(&prep->mask, in->photo.width, in->photo.height, &full) != 0)
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory for the mask");
    st = sq_io_write_image(path, &full, NULL, err);
    sq_image_free(&full);
    return st;
}

int cli_load_photo(const char *photo_path, const char *mask_path, const char *line_path, CliPhoto *in,
                   SqError *err)
{
    memset(in, 0, sizeof *in);
    if (sq_io_read_image(photo_path, NULL, &in->photo, NULL, err) != SQ_OK)
        return -1;
    if (mask_path) {
        SqImage m;
        if (sq_io_read_image(mask_path, NULL, &m, NULL, err) != SQ_OK) {
            cli_photo_free(in);
            return -1;
        }
        if (m.width != in->photo.width || m.height != in->photo.height) {
            sq_error_set(err, SQ_ERR_INVALID, mask_path, "the mask is %dx%d but the photo is %dx%d", m.width,
                         m.height, in->photo.width, in->photo.height);
            sq_image_free(&m);
            cli_photo_free(in);
            return -1;
        }
        /* white (or opaque) marks the snake */
        if (sq_image_alloc(&in->mask, m.width, m.height, 1, SQ_SPACE_DATA) != 0) {
            sq_error_set(err, SQ_ERR_NOMEM, mask_path, "out of memory");
            sq_image_free(&m);
            cli_photo_free(in);
            return -1;
        }
        for (size_t i = 0; i < (size_t)m.width * m.height; i++)
            in->mask.px[i] = (m.px[4 * i] + m.px[4 * i + 1] + m.px[4 * i + 2]) / 3 * m.px[4 * i + 3] >= 0.5f;
        sq_image_free(&m);
    }
    if (line_path && sq_body_line_read(line_path, &in->line, err) != SQ_OK) {
        cli_photo_free(in);
        return -1;
    }
    return 0;
}

void cli_photo_free(CliPhoto *in)
{
    sq_image_free(&in->photo);
    sq_image_free(&in->mask);
    sq_body_line_free(&in->line);
}

SqStatus cli_prepare(const CliPhoto *in, const SqPrepOptions *o, SqPrepared *prep, SqError *err)
{
    SqPrepOptions po = o ? *o : sq_fit_prep_options_default();
    po.line = in->line.nstretches > 0 ? &in->line : NULL;
    return sq_fit_prepare(&in->photo, in->mask.px ? &in->mask : NULL, &po, prep, err);
}

int cli_short_strip(const SqPrepared *prep, int line_given, char *buf, size_t n)
{
    const double widths = prep->length / prep->body_width;
    if (!(widths < CLI_SHORT_STRIP))
        return 0;
    static const char *const what[] = {
        [SQ_MASK_GIVEN] = "the mask shows", [SQ_MASK_ALPHA] = "the photo's alpha shows",
        [SQ_MASK_AUTOMATIC] = "the automatic mask found", [SQ_MASK_LINE] = "the body line covers"};
    snprintf(buf, n, "%s only %.1f body widths of clean body (%.0f at least to see a pattern repeat); see line.png, %s",
             line_given ? "the body line covers" : what[prep->mask_source],
             floor(widths * 10) / 10, /* never "3.0" */ CLI_SHORT_STRIP,
             line_given ? "and draw the line (--line) along a longer stretch of the body"
                        : "and give a body line (--line) along a longer stretch of the body or a mask (--mask) of it");
    return 1;
}

/* Where the light comes from, in words: one of eight directions in the photo. */
static const char *light_words(const float xy[2])
{
    static const char *const from[8] = {"lit from the right", "lit from the lower right", "lit from below",
                                        "lit from the lower left", "lit from the left", "lit from the upper left",
                                        "lit from above", "lit from the upper right"};
    if (hypot(xy[0], xy[1]) < 0.1)
        return "no clear light direction";
    double a = atan2(xy[1], xy[0]); /* y down: 90 degrees is below */
    int k = (int)lround(a / atan(1.0)); /* eighths of a turn */
    return from[(k + 8) % 8];
}

int cmd_prepare(int argc, char **argv)
{
    enum { O_WORK = 1000, O_DEBUG };
    static const struct option opts[] = {{"mask", required_argument, NULL, 'm'},
                                         {"line", required_argument, NULL, 'l'},
                                         {"output", required_argument, NULL, 'o'},
                                         {"work-size", required_argument, NULL, O_WORK},
                                         {"debug", no_argument, NULL, O_DEBUG},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    const char *mask_path = NULL, *line_path = NULL, *outdir = NULL;
    int debug = 0, c;
    long v;
    SqPrepOptions po = sq_fit_prep_options_default();
    SqError err;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":hm:l:o:", opts, NULL)) != -1) {
        switch (c) {
        case 'm': mask_path = optarg; break;
        case 'l': line_path = optarg; break;
        case 'o': outdir = optarg; break;
        case O_WORK:
            if (cli_parse_int("--work-size", optarg, 128, 8192, &v, &err) != 0)
                return cli_usage("prepare", "%s", err.what);
            po.work_size = (int)v;
            break;
        case O_DEBUG: debug = 1; break;
        case 'h': fputs(help, stdout); return CLI_OK;
        default:
            return cli_bad_option("prepare", argv, c, opts);
        }
    }
    if (argc - optind != 1)
        return cli_usage("prepare", "give exactly one PHOTO");
    if (!outdir)
        return cli_usage("prepare", "say where to write with -o DIR");
    char dbg[4096];
    snprintf(dbg, sizeof dbg, "%s/debug", outdir);
    CliMade made;
    if (cli_mkdirs_new(debug ? dbg : outdir, &made) != 0) {
        sq_error_set(&err, SQ_ERR_IO, outdir, "cannot create the folder: %s", strerror(errno));
        return cli_fail(&err);
    }
    if (access(outdir, W_OK) != 0) { /* found now, not after the preparation */
        sq_error_set(&err, SQ_ERR_IO, outdir, "cannot write into the output folder: %s", strerror(errno));
        cli_rmdirs_new(debug ? dbg : outdir, &made);
        return cli_fail(&err);
    }
    if (debug)
        po.debug_dir = dbg;
    CliPhoto in;
    if (cli_load_photo(argv[optind], mask_path, line_path, &in, &err) != 0) {
        cli_rmdirs_new(debug ? dbg : outdir, &made);
        return cli_fail(&err);
    }
    SqPrepared prep;
    SqStatus st = cli_prepare(&in, &po, &prep, &err);
    int rc = CLI_OK;
    if (st != SQ_OK) {
        rc = cli_fail(&err);
    } else {
        /* into DIR/.prepare.tmp-XXXXXX first, then into DIR as a set */
        char path[4200];
        CliStaging stg = {0};
        if (cli_pathf(path, sizeof path, "%s/.prepare.tmp-XXXXXX", outdir) != 0)
            st = sq_error_set(&err, SQ_ERR_INVALID, outdir, "the output folder's name is too long");
        else
            st = cli_staging_open(&stg, path, outdir, 8, &err);
        if (st == SQ_OK)
            st = cli_write_full_mask(&stg, outdir, &prep, &in, mask_path, &err);
        if (st == SQ_OK)
            st = cli_staging_path(&stg, "strip.png", path, sizeof path, &err);
        if (st == SQ_OK)
            st = sq_io_write_image(path, &prep.strip, NULL, &err);
        if (st == SQ_OK)
            st = cli_write_line(&stg, outdir, &prep, line_path ? &in.line : NULL, line_path, &err);
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "photo", argv[optind]);
        cJSON_AddStringToObject(o, "mask_source", sq_mask_source_name(prep.mask_source));
        cJSON_AddNumberToObject(o, "body_width", prep.body_width);
        cJSON_AddNumberToObject(o, "length", prep.length);
        cJSON_AddNumberToObject(o, "stretches", prep.nruns);
        cJSON_AddNumberToObject(o, "strip_rows", prep.strip.height);
        cJSON_AddNumberToObject(o, "strip_step_px", round(prep.step * 1e3) / 1e3);
        cJSON_AddNumberToObject(o, "edge_blur_px", round(prep.edge_blur * 1e3) / 1e3);
        cJSON_AddNumberToObject(o, "strip_blur", round(sq_fit_strip_blur(prep.step, prep.edge_blur) * 1e3) / 1e3);
        const double lxy[2] = {round(prep.light_xy[0] * 1e3) / 1e3, round(prep.light_xy[1] * 1e3) / 1e3};
        cJSON_AddItemToObject(o, "light", cJSON_CreateDoubleArray(lxy, 2));
        char *text = sq__json_print(o);
        cJSON_Delete(o);
        if (st == SQ_OK && !text)
            st = sq_error_set(&err, SQ_ERR_NOMEM, outdir, "out of memory");
        if (st == SQ_OK)
            st = cli_staging_path(&stg, "prepared.json", path, sizeof path, &err);
        if (st == SQ_OK)
            st = sq_io_write_file(path, text, strlen(text), &err);
        free(text);
        if (st == SQ_OK)
            st = cli_staging_commit(&stg, 1, &err);
        else
            cli_staging_where(&stg, &err);
        cli_staging_free(&stg);
        if (st != SQ_OK)
            rc = cli_fail(&err);
        char warning[512];
        if (rc == CLI_OK && cli_short_strip(&prep, line_path != NULL, warning, sizeof warning))
            fprintf(stderr, "squama: warning: %s\n", warning);
        if (rc == CLI_OK)
            printf("%s: %s mask, body %.0f px wide, %.0f px of it in %d stretch%s straightened into a "
                   "%dx%d strip, %s\n",
                   argv[optind], sq_mask_source_name(prep.mask_source), prep.body_width, prep.length, prep.nruns,
                   prep.nruns == 1 ? "" : "es", prep.strip.width, prep.strip.height, light_words(prep.light_xy));
        sq_fit_prepared_free(&prep);
    }
    cli_photo_free(&in);
    if (rc != CLI_OK)
        cli_rmdirs_new(debug ? dbg : outdir, &made);
    return rc;
}
