/* squama batch's thumbnails (see thumb.h). */
#include <stdlib.h>

#include "squama/image.h"
#include "squama/io.h"
#include "thumb.h"

/* The mean of img's channel c over the f x f box at (x, y) of the shrunk image. */
static double box_mean(const SqImage *img, int x, int y, int f, int c)
{
    double sum = 0;
    int n = 0;
    for (int yy = y * f; yy < (y + 1) * f && yy < img->height; yy++)
        for (int xx = x * f; xx < (x + 1) * f && xx < img->width; xx++, n++)
            sum += sq_image_at(img, xx, yy)[c < img->channels ? c : 0];
    return n ? sum / n : 0;
}

static SqStatus write_free(const char *dst, SqImage *t, SqError *err)
{
    SqStatus st = sq_io_write_image(dst, t, NULL, err);
    sq_image_free(t);
    return st;
}

SqStatus cli_thumbnail(const char *src, const char *mask, const char *dst, SqError *err)
{
    SqImage img, m = {0}, t;
    SqStatus st = sq_io_read_image(src, NULL, &img, NULL, err);
    if (st != SQ_OK)
        return st;
    if (mask && (st = sq_io_read_image(mask, NULL, &m, NULL, err)) != SQ_OK) {
        sq_image_free(&img);
        return st;
    }
    if (mask && (m.width != img.width || m.height != img.height)) {
        st = sq_error_set(err, SQ_ERR_INVALID, mask, "the mask is %dx%d but the photo is %dx%d", m.width, m.height,
                          img.width, img.height);
        sq_image_free(&img);
        sq_image_free(&m);
        return st;
    }
    const int big = img.width > img.height ? img.width : img.height;
    const int f = big > CLI_THUMB ? (big + CLI_THUMB - 1) / CLI_THUMB : 1;
    const int w = (img.width + f - 1) / f, h = (img.height + f - 1) / f;
    if (sq_image_alloc(&t, w, h, 3, img.space) != 0) {
        sq_image_free(&img);
        sq_image_free(&m);
        return sq_error_set(err, SQ_ERR_NOMEM, dst, "out of memory");
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const double in = mask ? box_mean(&m, x, y, f, 0) : 1;
            const double k = CLI_THUMB_DIM + (1 - CLI_THUMB_DIM) * (in < 0 ? 0 : in > 1 ? 1 : in);
            for (int c = 0; c < 3; c++)
                sq_image_at(&t, x, y)[c] = (float)(k * box_mean(&img, x, y, f, c));
        }
    sq_image_free(&img);
    sq_image_free(&m);
    return write_free(dst, &t, err);
}

SqStatus cli_thumbnail_strips(const char *strip, const char *fitted, const char *dst, SqError *err)
{
    SqImage s[2];
    SqStatus st = sq_io_read_image(strip, NULL, &s[0], NULL, err);
    if (st != SQ_OK)
        return st;
    if ((st = sq_io_read_image(fitted, NULL, &s[1], NULL, err)) != SQ_OK) {
        sq_image_free(&s[0]);
        return st;
    }
    if (s[0].width != s[1].width || s[0].height != s[1].height) {
        st = sq_error_set(err, SQ_ERR_INVALID, fitted, "the fitted strip is %dx%d but the photo's is %dx%d",
                          s[1].width, s[1].height, s[0].width, s[0].height);
        sq_image_free(&s[0]);
        sq_image_free(&s[1]);
        return st;
    }
    /* turned: the strip's rows (along the body) become columns */
    const int along = s[0].height, across = s[0].width;
    const int f = along > CLI_THUMB ? (along + CLI_THUMB - 1) / CLI_THUMB : 1;
    const int w = (along + f - 1) / f, h1 = (across + f - 1) / f, gap = 2;
    SqImage t;
    if (sq_image_alloc(&t, w, 2 * h1 + gap, 3, s[0].space) != 0) {
        sq_image_free(&s[0]);
        sq_image_free(&s[1]);
        return sq_error_set(err, SQ_ERR_NOMEM, dst, "out of memory");
    }
    for (int i = 0; i < t.width * t.height * 3; i++)
        t.px[i] = 1;
    for (int k = 0; k < 2; k++)
        for (int y = 0; y < h1; y++)
            for (int x = 0; x < w; x++)
                for (int c = 0; c < 3; c++) /* thumbnail (x, y) is the strip's box at (y, x) */
                    sq_image_at(&t, x, k * (h1 + gap) + y)[c] = (float)box_mean(&s[k], y, x, f, c);
    sq_image_free(&s[0]);
    sq_image_free(&s[1]);
    return write_free(dst, &t, err);
}
