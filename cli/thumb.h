/* squama batch's thumbnails: what a catalogue row shows at a glance. */
#ifndef SQUAMA_CLI_THUMB_H
#define SQUAMA_CLI_THUMB_H

#include "squama/error.h"
#include "squama/image.h"

enum { CLI_THUMB = 160 }; /* a thumbnail's longest side */

/* src shrunk (box filter) to at most CLI_THUMB pixels a side, written as PNG to dst. With
 * mask (a file the size of src; NULL: none), what lies outside it keeps CLI_THUMB_KEEP of
 * itself under a veil of CLI_THUMB_VEIL (a blue that few snakes and fewer backdrops
 * are): the part of the photo the fit saw stands out, dark photos too. */
#define CLI_THUMB_KEEP 0.35
#define CLI_THUMB_VEIL {0.12, 0.2, 0.6}
SqStatus cli_thumbnail(const char *src, const char *mask, const char *dst, SqError *err);

/* The photo's strip and the fitted strip (files of one size, the body running down them),
 * turned to run across, one above the other with a white gap, shrunk to at most
 * CLI_THUMB pixels wide, written as PNG to dst. */
SqStatus cli_thumbnail_strips(const char *strip, const char *fitted, const char *dst, SqError *err);

/* The same in memory, for other tools (a sheet of many). Each returns 0, or -1 out of
 * memory; *out is allocated (sq_image_free). */
/* img shrunk to at most side pixels a side, what mask (img's size, or NULL) leaves out veiled */
int cli_thumb_shrink(const SqImage *img, const SqImage *mask, int side, SqImage *out);
/* a strip (the body running down it) turned to run across, at most side pixels wide */
int cli_thumb_turned(const SqImage *strip, int side, SqImage *out);
/* img's first channel taken to w x h by its nearest pixel (a mask to another size of its
 * picture) */
int cli_thumb_nearest(const SqImage *img, int w, int h, SqImage *out);
/* src's RGB copied into dst at (x0, y0), cut at dst's edges */
void cli_thumb_paste(SqImage *dst, const SqImage *src, int x0, int y0);

#endif
