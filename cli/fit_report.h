/* The fit's report.html: pictures side by side, the objectives, convergence and the front. */
#ifndef SQUAMA_CLI_FIT_REPORT_H
#define SQUAMA_CLI_FIT_REPORT_H

#include "squama/search.h"

/* Writes report.html at path (atomic), in the folder of the images squama fit writes; warning (or
 * NULL) says what about the photo's strip the reader should doubt; line_given: the fit
 * followed a body line given (no line.json of its own). */
SqStatus cli_fit_report(const char *path, const char *photo_path, const SqFitResult *r, const char *warning,
                        int line_given, double prepare_s, double search_s, double total_s, SqError *err);

#endif
