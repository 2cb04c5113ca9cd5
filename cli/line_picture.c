/* line.json and line.png: the centre line a preparation followed, written to be corrected
 * and given back, and drawn over the photo to correct it by eye. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "squama/io.h"

static void blend(SqImage *img, int x, int y, const float c[3], float a)
{
    if (x < 0 || y < 0 || x >= img->width || y >= img->height)
        return;
    float *p = img->px + ((size_t)y * img->width + x) * img->channels;
    for (int k = 0; k < 3; k++)
        p[k] += (c[k] - p[k]) * a;
}

/* A segment, a pixel wide (a step of at most a pixel along its longer axis). */
static void segment(SqImage *img, double x0, double y0, double x1, double y1, const float c[3], float a)
{
    const double len = fmax(fabs(x1 - x0), fabs(y1 - y0));
    const int n = (int)fmin(ceil(len), 1 << 16);
    for (int i = 0; i <= n; i++) {
        const double t = n ? (double)i / n : 0;
        blend(img, (int)floor(x0 + (x1 - x0) * t), (int)floor(y0 + (y1 - y0) * t), c, a);
    }
}

static void disc(SqImage *img, double cx, double cy, double r, const float c[3])
{
    for (int y = (int)floor(cy - r); y <= (int)ceil(cy + r); y++)
        for (int x = (int)floor(cx - r); x <= (int)ceil(cx + r); x++)
            if ((x + 0.5 - cx) * (x + 0.5 - cx) + (y + 0.5 - cy) * (y + 0.5 - cy) <= r * r)
                blend(img, x, y, c, 1);
}

/* line.png, with L's points (L's stretches need not be those followed). */
static SqStatus line_picture(const SqPrepared *prep, const SqBodyLine *L, const char *path, SqError *err)
{
    static const float grid_c[3] = {1, 1, 0.3f}, centre_c[3] = {1, 0.15f, 0.1f}, edge_c[3] = {0.2f, 0.9f, 1},
                       ink[3] = {1, 1, 1}, dark[3] = {0, 0, 0};
    SqImage img;
    if (sq_image_alloc(&img, prep->photo.width, prep->photo.height, 3, SQ_SPACE_SRGB) != 0)
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    memcpy(img.px, prep->photo.px, sizeof(float) * 3 * (size_t)img.width * img.height);
    const double s = prep->scale;
    /* a grid in the photo's own pixels, labelled: where to read a point's coordinates */
    const double side = fmax(img.width, img.height) / s;
    const int step = side > 2000 ? 200 : side > 800 ? 100 : 50;
    int labels = 1;
    SqError terr;
    for (int g = step; g * s < img.width; g += step) {
        segment(&img, g * s, 0, g * s, img.height - 1, grid_c, 0.35f);
        char t[16];
        snprintf(t, sizeof t, "%d", g);
        labels = labels && sq_io_draw_text(&img, (int)(g * s) + 2, 12, 11, t, grid_c, &terr) == SQ_OK;
    }
    for (int g = step; g * s < img.height; g += step) {
        segment(&img, 0, g * s, img.width - 1, g * s, grid_c, 0.35f);
        char t[16];
        snprintf(t, sizeof t, "%d", g);
        labels = labels && sq_io_draw_text(&img, 2, (int)(g * s) - 2, 11, t, grid_c, &terr) == SQ_OK;
    }
    /* each stretch followed: its centre line and its edges, the body's half width out */
    const double r = 0.5 * prep->body_width * s;
    for (int k = 0, i0 = 0; k < prep->nruns; i0 += prep->run_points[k++]) {
        const float *c = prep->centre + 2 * (size_t)i0;
        const int n = prep->run_points[k];
        for (int i = 1; i < n; i++) {
            const int a = i > 3 ? i - 4 : 0, b = i + 3 < n ? i + 3 : n - 1;
            const double tx = c[2 * b] - c[2 * a], ty = c[2 * b + 1] - c[2 * a + 1], tl = hypot(tx, ty);
            segment(&img, c[2 * i - 2] * s, c[2 * i - 1] * s, c[2 * i] * s, c[2 * i + 1] * s, centre_c, 1);
            if (tl > 0 && i % 2 == 0) /* the edges dotted */
                for (int side2 = -1; side2 <= 1; side2 += 2)
                    blend(&img, (int)floor(c[2 * i] * s - side2 * r * ty / tl),
                          (int)floor(c[2 * i + 1] * s + side2 * r * tx / tl), edge_c, 1);
        }
    }
    /* the line's points, numbered within their stretch */
    for (int k = 0, j = 0; k < L->nstretches; k++)
        for (int i = 0; i < L->count[k]; i++, j++) {
            const double x = L->xy[2 * j] * s, y = L->xy[2 * j + 1] * s;
            disc(&img, x, y, 3.5, dark);
            disc(&img, x, y, 2.5, centre_c);
            char t[24];
            if (i == 0)
                snprintf(t, sizeof t, "%d:%d", k, i);
            else
                snprintf(t, sizeof t, "%d", i);
            if (labels) {
                sq_io_draw_text(&img, (int)x + 5, (int)y - 3, 11, t, dark, &terr);
                sq_io_draw_text(&img, (int)x + 4, (int)y - 4, 11, t, ink, &terr);
            }
        }
    SqStatus st = sq_io_write_image(path, &img, NULL, err);
    sq_image_free(&img);
    return st;
}

SqStatus cli_write_line(CliStaging *s, const char *dir, const SqPrepared *prep, const SqBodyLine *given,
                        const char *given_path, SqError *err)
{
    char path[4200];
    SqBodyLine own = {0};
    SqStatus st = SQ_OK;
    if (given) { /* an earlier run's line.json is not the line followed now */
        if (cli_pathf(path, sizeof path, "%s/line.json", dir) != 0)
            return sq_error_set(err, SQ_ERR_IO, dir, "path too long");
        if (!(given_path && cli_same_file(given_path, path)))
            st = cli_staging_drop(s, "line.json", err);
    } else {
        st = sq_fit_prepared_line(prep, &own, err);
        if (st == SQ_OK)
            st = cli_staging_path(s, "line.json", path, sizeof path, err);
        if (st == SQ_OK)
            st = sq_body_line_write(path, &own, err);
    }
    if (st == SQ_OK)
        st = cli_staging_path(s, "line.png", path, sizeof path, err);
    if (st == SQ_OK)
        st = line_picture(prep, given ? given : &own, path, err);
    sq_body_line_free(&own);
    return st;
}
