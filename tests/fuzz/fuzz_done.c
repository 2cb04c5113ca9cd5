/* libFuzzer harness: squama batch's done.json, the record of a finished row read back when
 * a batch resumes or merges (cli/batch_done.c). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "batch.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    BatchDone *d = malloc(sizeof *d);
    if (!d)
        return 0;
    if (batch_parse_done((const char *)data, size, d)) {
        /* a complete record: an id, a status, a known category when it is a fit */
        if (!d->id[0] || strlen(d->id) > CLI_ID_MAX || !d->r.resumed)
            abort();
        if (d->r.status == BATCH_OK && (d->r.fitted < 0 || d->r.fitted >= SQ_PATTERN_COUNT))
            abort();
        if (d->r.status != BATCH_OK && d->r.status != BATCH_ERROR)
            abort();
        size_t p = strlen(d->photo_digest), m = strlen(d->mask_digest), l = strlen(d->line_digest);
        if ((p && p != BATCH_DIGEST - 1) || (m && m != BATCH_DIGEST - 1) || (l && l != BATCH_DIGEST - 1))
            abort();
        if (d->expected < -1 || d->expected >= SQ_PATTERN_COUNT)
            abort();
    }
    free(d);
    return 0;
}
