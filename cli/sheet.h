/* Contact sheets: presets' base colours side by side, each named, in one PNG. Shared by
 * `squama render --sheet` and `squama seed`. */
#ifndef SQUAMA_CLI_SHEET_H
#define SQUAMA_CLI_SHEET_H

#include "squama/generator.h"

/* Renders each preset's base colour at size x size (go's other options kept) into a grid
 * of *cols columns (*cols <= 0: about the square root of n; set to the columns used), with
 * labels[i] beneath preset i (cut to fit), and writes it to out (PNG, atomically). Nothing
 * is written unless every preset renders. Without a font the sheet goes unlabelled, with a
 * warning on stderr. */
SqStatus cli_sheet_write(const char *out, const SqParams *presets, const char *const *labels, int n, int size,
                         int *cols, SqGenOptions go, SqError *err);

#endif
