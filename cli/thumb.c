/* squama batch's thumbnails (see thumb.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

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

int cli_thumb_shrink(const SqImage *img, const SqImage *mask, int side, SqImage *out)
{
    const int big = img->width > img->height ? img->width : img->height;
    const int f = big > side ? (big + side - 1) / side : 1;
    const int w = (img->width + f - 1) / f, h = (img->height + f - 1) / f;
    if (sq_image_alloc(out, w, h, 3, img->space) != 0)
        return -1;
    static const double veil[3] = CLI_THUMB_VEIL;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const double in = mask ? box_mean(mask, x, y, f, 0) : 1, k = in < 0 ? 0 : in > 1 ? 1 : in;
            for (int c = 0; c < 3; c++) {
                const double px = box_mean(img, x, y, f, c);
                sq_image_at(out, x, y)[c] =
                    (float)(k * px + (1 - k) * (CLI_THUMB_KEEP * px + (1 - CLI_THUMB_KEEP) * veil[c]));
            }
        }
    return 0;
}

int cli_thumb_turned(const SqImage *strip, int side, SqImage *out)
{
    const int along = strip->height, across = strip->width;
    const int f = along > side ? (along + side - 1) / side : 1;
    const int w = (along + f - 1) / f, h = (across + f - 1) / f;
    if (sq_image_alloc(out, w, h, 3, strip->space) != 0)
        return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++) /* (x, y) is the strip's box at (y, x) */
                sq_image_at(out, x, y)[c] = (float)box_mean(strip, y, x, f, c);
    return 0;
}

void cli_thumb_paste(SqImage *dst, const SqImage *src, int x0, int y0)
{
    for (int y = 0; y < src->height && y0 + y < dst->height; y++)
        for (int x = 0; x < src->width && x0 + x < dst->width; x++)
            memcpy(sq_image_at(dst, x0 + x, y0 + y), sq_image_at(src, x, y), 3 * sizeof(float));
}

int cli_thumb_nearest(const SqImage *img, int w, int h, SqImage *out)
{
    if (sq_image_alloc(out, w, h, 1, SQ_SPACE_DATA) != 0)
        return -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            *sq_image_at(out, x, y) =
                *sq_image_at(img, (int)((x + 0.5) * img->width / w), (int)((y + 0.5) * img->height / h));
    return 0;
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
    /* a fit's mask.png is the photo's own size, its photo.jpg the prepared one's (each side
     * rounded to whole pixels): the same picture, the mask taken to the photo's pixels */
    const double cross = (double)m.width * img.height - (double)m.height * img.width,
                 rounding = 0.5 * (fmax(m.width, img.width) + fmax(m.height, img.height)) + 1;
    if (mask && (m.width != img.width || m.height != img.height) && fabs(cross) <= rounding) {
        SqImage r;
        if (cli_thumb_nearest(&m, img.width, img.height, &r) != 0) {
            sq_image_free(&img);
            sq_image_free(&m);
            return sq_error_set(err, SQ_ERR_NOMEM, dst, "out of memory");
        }
        sq_image_free(&m);
        m = r;
    }
    if (mask && (m.width != img.width || m.height != img.height))
        st = sq_error_set(err, SQ_ERR_INVALID, mask, "the mask is %dx%d but the photo is %dx%d", m.width, m.height,
                          img.width, img.height);
    else if (cli_thumb_shrink(&img, mask ? &m : NULL, CLI_THUMB, &t) != 0)
        st = sq_error_set(err, SQ_ERR_NOMEM, dst, "out of memory");
    sq_image_free(&img);
    sq_image_free(&m);
    return st == SQ_OK ? write_free(dst, &t, err) : st;
}

SqStatus cli_thumbnail_strips(const char *strip, const char *fitted, const char *dst, SqError *err)
{
    SqImage s[2], r[2] = {{0}}, t = {0};
    SqStatus st = sq_io_read_image(strip, NULL, &s[0], NULL, err);
    if (st != SQ_OK)
        return st;
    if ((st = sq_io_read_image(fitted, NULL, &s[1], NULL, err)) != SQ_OK) {
        sq_image_free(&s[0]);
        return st;
    }
    enum { GAP = 2 };
    if (s[0].width != s[1].width || s[0].height != s[1].height)
        st = sq_error_set(err, SQ_ERR_INVALID, fitted, "the fitted strip is %dx%d but the photo's is %dx%d",
                          s[1].width, s[1].height, s[0].width, s[0].height);
    else if (cli_thumb_turned(&s[0], CLI_THUMB, &r[0]) != 0 || cli_thumb_turned(&s[1], CLI_THUMB, &r[1]) != 0 ||
             sq_image_alloc(&t, r[0].width, 2 * r[0].height + GAP, 3, s[0].space) != 0)
        st = sq_error_set(err, SQ_ERR_NOMEM, dst, "out of memory");
    if (st == SQ_OK) {
        for (size_t i = 0; i < (size_t)t.width * t.height * 3; i++)
            t.px[i] = 1;
        cli_thumb_paste(&t, &r[0], 0, 0);
        cli_thumb_paste(&t, &r[1], 0, r[0].height + GAP);
    }
    for (int k = 0; k < 2; k++) {
        sq_image_free(&s[k]);
        sq_image_free(&r[k]);
    }
    if (st != SQ_OK) {
        sq_image_free(&t);
        return st;
    }
    return write_free(dst, &t, err);
}
