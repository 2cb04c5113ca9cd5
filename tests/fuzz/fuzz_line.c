/* libFuzzer harness: the body line (fitness/line.c), a photo's centre line given by hand
 * (squama prepare/fit --line, a manifest's body_line column). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "squama/fitness.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    SqBodyLine line;
    SqError err;
    if (sq_body_line_parse((const char *)data, size, "fuzz", &line, &err) == SQ_OK) {
        /* what prep relies on: 1 to 16 stretches of 2 points at least, finite, a width */
        if (line.nstretches < 1 || line.nstretches > SQ_BODY_LINE_MAX_STRETCHES || !(line.width >= 1))
            abort();
        int total = 0;
        for (int k = 0; k < line.nstretches; k++) {
            if (line.count[k] < 2)
                abort();
            total += line.count[k];
        }
        for (int i = 0; i < 2 * total; i++)
            if (!isfinite(line.xy[i]))
                abort();
        sq_body_line_free(&line);
    } else if (line.nstretches != 0 || line.xy || line.count || !err.what[0]) {
        abort(); /* nothing held, and a reason */
    }
    return 0;
}
