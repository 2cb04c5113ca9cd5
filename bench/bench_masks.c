/* The automatic mask on a folder of photos: each photo prepared as `squama fit` prepares
 * it without a mask, laid out in one contact sheet (the photo with what the mask leaves
 * out veiled in blue, the straightened strip beneath it, turned to run across), one line each on
 * stdout (what was found or why not), the median time a photo, and the median length of
 * clean body straightened in body widths with the count under 3. The sheet is cut into
 * pages of --rows rows (OUT-1.png, OUT-2.png, ...), each small enough to look at whole.
 * With --lines DIR, a photo with a body line drawn by hand (DIR/<photo name less its
 * extension>.json, as refs/photo_lines holds) has the body width found set against the
 * line's: the median ratio and how many are 1.5 times as wide or more (touching coils or
 * ground taken for one wide body) or under 0.67 (a stripe or one coil's edge).
 * Usage: bench_masks PHOTO_DIR OUT.png [--cols C] [--rows R] [--work-size N] [--lines DIR] */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../cli/thumb.h"
#include "bench_util.h"
#include "squama/fitness.h"
#include "squama/io.h"

enum { CELL = 160, STRIP_H = 64, GAP = 4 };

static int cmp_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int is_photo(const char *n)
{
    const char *dot = strrchr(n, '.');
    return dot && (!strcmp(dot, ".jpg") || !strcmp(dot, ".jpeg") || !strcmp(dot, ".png"));
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_masks PHOTO_DIR OUT.png [--cols C] [--rows R] [--work-size N] [--lines DIR]\n");
        return 2;
    }
    int cols = 6, prows = 4;
    const char *lines = NULL;
    SqPrepOptions po = sq_fit_prep_options_default();
    for (int i = 3; i + 1 < argc; i += 2)
        if (!strcmp(argv[i], "--cols"))
            cols = atoi(argv[i + 1]) > 0 ? atoi(argv[i + 1]) : 6;
        else if (!strcmp(argv[i], "--rows"))
            prows = atoi(argv[i + 1]) > 0 ? atoi(argv[i + 1]) : 4;
        else if (!strcmp(argv[i], "--work-size"))
            po.work_size = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--lines"))
            lines = argv[i + 1];
    DIR *d = opendir(argv[1]);
    if (!d) {
        fprintf(stderr, "bench_masks: cannot open %s\n", argv[1]);
        return 1;
    }
    char **names = NULL;
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        if (is_photo(e->d_name)) {
            names = realloc(names, sizeof *names * (size_t)(n + 1));
            names[n++] = strdup(e->d_name);
        }
    closedir(d);
    if (n == 0) {
        fprintf(stderr, "bench_masks: no photos in %s\n", argv[1]);
        return 1;
    }
    qsort(names, (size_t)n, sizeof *names, cmp_name);
    const int per_page = cols * prows, pages = (n + per_page - 1) / per_page, ch = CELL + STRIP_H + GAP;
    SqImage sheet = {0};
    char out[4096];
    double *ms = malloc(sizeof *ms * (size_t)n), *widths = malloc(sizeof *widths * (size_t)n);
    double *vs_line = malloc(sizeof *vs_line * (size_t)n);
    int lined = 0, wide = 0, narrow = 0;
    if (!ms || !widths || !vs_line) {
        fprintf(stderr, "bench_masks: out of memory\n");
        return 1;
    }
    int ok = 0, short_strips = 0;
    printf("%4s  %-44s %s\n", "cell", "photo", "body width px, stretches, strip rows, body widths | why not");
    for (int k = 0; k < n; k++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", argv[1], names[k]);
        SqImage photo;
        SqPrepared p = {0};
        SqError err;
        const double t0 = now_ms();
        SqStatus st = sq_io_read_image(path, NULL, &photo, NULL, &err);
        if (st == SQ_OK) {
            st = sq_fit_prepare(&photo, NULL, &po, &p, &err);
            sq_image_free(&photo);
        }
        ms[k] = now_ms() - t0;
        ok += st == SQ_OK;
        const int cell = k % per_page, x0 = (cell % cols) * (CELL + GAP), y0 = (cell / cols) * (ch + GAP);
        if (cell == 0) {
            const int rows = (n - k < per_page ? (n - k + cols - 1) / cols : prows);
            if (sq_image_alloc(&sheet, cols * (CELL + GAP), rows * (ch + GAP), 3, SQ_SPACE_SRGB) != 0)
                return 1;
            for (size_t i = 0; i < (size_t)sheet.width * sheet.height * 3; i++)
                sheet.px[i] = 1;
        }
        SqImage t;
        if (p.photo.px && cli_thumb_shrink(&p.photo, p.mask.px ? &p.mask : NULL, CELL, &t) == 0) {
            cli_thumb_paste(&sheet, &t, x0, y0);
            sq_image_free(&t);
        }
        if (st == SQ_OK && cli_thumb_turned(&p.strip, CELL, &t) == 0) {
            cli_thumb_paste(&sheet, &t, x0, y0 + CELL + GAP);
            sq_image_free(&t);
        }
        if (st == SQ_OK) { /* the clean body straightened, in body widths (3 to see a pattern repeat) */
            widths[ok - 1] = p.length / p.body_width;
            short_strips += widths[ok - 1] < 3;
            printf("%4d  %-44s %.0f, %d, %d, %.1f", k, names[k], p.body_width, p.nruns, p.strip.height, widths[ok - 1]);
            char lpath[4096] = "";
            SqBodyLine line;
            if (lines) /* a photo's name has its extension (is_photo) */
                snprintf(lpath, sizeof lpath, "%s/%.*s.json", lines, (int)(strrchr(names[k], '.') - names[k]), names[k]);
            if (lines && access(lpath, R_OK) == 0 && sq_body_line_read(lpath, &line, &err) == SQ_OK) {
                const double q = p.body_width / line.width;
                vs_line[lined++] = q;
                wide += q >= 1.5;
                narrow += q < 0.67;
                printf(", %.2f of the drawn line's width", q);
                sq_body_line_free(&line);
            }
            printf("\n");
        } else
            printf("%4d  %-44s | %s (%s)\n", k, names[k], err.what, err.where);
        fflush(stdout);
        sq_fit_prepared_free(&p);
        if (cell == per_page - 1 || k == n - 1) {
            const char *dot = strrchr(argv[2], '.');
            const int stem = dot ? (int)(dot - argv[2]) : (int)strlen(argv[2]);
            if (pages > 1)
                snprintf(out, sizeof out, "%.*s-%d%s", stem, argv[2], k / per_page + 1, dot ? dot : ".png");
            else
                snprintf(out, sizeof out, "%s", argv[2]);
            if (sq_io_write_image(out, &sheet, NULL, &err) != SQ_OK) {
                fprintf(stderr, "bench_masks: %s (%s)\n", err.what, err.where);
                return 1;
            }
            sq_image_free(&sheet);
            printf("sheet: %s (cells %d to %d, %d a row: the photo, what the mask leaves out veiled, its strip)\n",
                   out, k / per_page * per_page, k, cols);
        }
    }
    printf("RESULT masks n=%d prepared=%d median_ms=%.0f widths_median=%.2f under_3_widths=%d", n, ok, median(ms, n),
           ok ? median(widths, ok) : 0.0, short_strips);
    if (lines)
        printf(" lined=%d width_vs_line_median=%.2f wide_1_5x=%d narrow_0_67x=%d", lined,
               lined ? median(vs_line, lined) : 0.0, wide, narrow);
    printf("\n");
    for (int k = 0; k < n; k++)
        free(names[k]);
    free(names);
    free(ms);
    free(widths);
    free(vs_line);
    return 0;
}
