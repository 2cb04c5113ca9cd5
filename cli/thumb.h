/* squama batch's thumbnails: what a catalogue row shows at a glance. */
#ifndef SQUAMA_CLI_THUMB_H
#define SQUAMA_CLI_THUMB_H

#include "squama/error.h"

enum { CLI_THUMB = 160 }; /* a thumbnail's longest side */

/* src shrunk (box filter) to at most CLI_THUMB pixels a side, written as PNG to dst. With
 * mask (a file the size of src; NULL: none), what lies outside it is dimmed to
 * CLI_THUMB_DIM of its brightness: the part of the photo the fit saw stands out. */
#define CLI_THUMB_DIM 0.3
SqStatus cli_thumbnail(const char *src, const char *mask, const char *dst, SqError *err);

/* The photo's strip and the fitted strip (files of one size, the body running down them),
 * turned to run across, one above the other with a white gap, shrunk to at most
 * CLI_THUMB pixels wide, written as PNG to dst. */
SqStatus cli_thumbnail_strips(const char *strip, const char *fitted, const char *dst, SqError *err);

#endif
