/* Contact sheets (sheet.h). */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "sheet.h"
#include "squama/io.h"

/* The sheet's look: tiles `size` square, a label band beneath each, gaps between. */
enum { SHEET_GAP = 8, SHEET_LABEL = 22 };

/* A label too long for its tile loses its words of letters only, keeping the index and
 * the figures: "00  nearest 1.49" becomes "00 1.49". */
static void drop_words(char *label)
{
    char out[256];
    size_t n = 0;
    for (const char *p = label; *p;) {
        while (*p == ' ')
            p++;
        const char *w = p;
        int letters = 1;
        for (; *p && *p != ' '; p++)
            letters &= isalpha((unsigned char)*p) != 0;
        const size_t len = (size_t)(p - w);
        if (len && !letters && n + len + 1 < sizeof out) {
            if (n)
                out[n++] = ' ';
            memcpy(out + n, w, len);
            n += len;
        }
    }
    out[n] = 0;
    if (n)
        memcpy(label, out, n + 1);
}

static void paste(SqImage *dst, const SqImage *src, int x0, int y0)
{
    for (int y = 0; y < src->height; y++)
        for (int x = 0; x < src->width; x++) {
            const float *s = src->px + ((size_t)y * src->width + x) * src->channels;
            float *d = dst->px + ((size_t)(y0 + y) * dst->width + x0 + x) * 3;
            memcpy(d, s, sizeof(float) * 3);
        }
}

SqStatus cli_sheet_write(const char *out, const SqParams *presets, const char *const *labels, int n, int size,
                         int *cols, SqGenOptions go, SqError *err)
{
    if (*cols <= 0)
        for (*cols = 1; *cols * *cols < n; (*cols)++)
            ;
    const int cn = *cols, rows = (n + cn - 1) / cn;
    const int cw = size + SHEET_GAP, ch = size + SHEET_LABEL + SHEET_GAP;
    SqImage sheet;
    if (sq_image_alloc(&sheet, SHEET_GAP + cn * cw, SHEET_GAP + rows * ch, 3, SQ_SPACE_SRGB) != 0)
        return sq_error_set(err, SQ_ERR_NOMEM, out, "out of memory for a sheet of %d x %d tiles of %d pixels", cn,
                            rows, size);
    for (size_t i = 0; i < (size_t)sheet.width * sheet.height * 3; i++)
        sheet.px[i] = 0.16f;
    go.width = go.height = size;
    SqStatus st = SQ_OK;
    int labelled = 1;
    for (int i = 0; i < n && st == SQ_OK; i++) {
        SqTextures tex;
        if ((st = sq_gen_render(&presets[i], &go, &tex, err)) != SQ_OK)
            break;
        const int x = SHEET_GAP + (i % cn) * cw, y = SHEET_GAP + (i / cn) * ch;
        paste(&sheet, &tex.basecolor, x, y);
        sq_gen_textures_free(&tex);
        /* as much of the label as fits: DejaVu Sans at 13 px is about 7.5 px a glyph */
        char label[256];
        snprintf(label, sizeof label, "%s", labels[i]);
        const size_t fit = (size_t)(size / 7.5);
        if (strlen(label) > fit)
            drop_words(label);
        if (strlen(label) > fit && fit > 3)
            strcpy(label + fit - 3, "...");
        static const float ink[3] = {0.92f, 0.92f, 0.92f};
        SqError terr;
        if (labelled && sq_io_draw_text(&sheet, x + 2, y + size + 16, 13, label, ink, &terr) != SQ_OK) {
            labelled = 0; /* no font: the sheet goes unlabelled, in the order given */
            fprintf(stderr, "squama: the sheet has no labels (%s); the presets are in the order given\n",
                    terr.what);
        }
    }
    if (st == SQ_OK)
        st = sq_io_write_image(out, &sheet, NULL, err);
    sq_image_free(&sheet);
    return st;
}
