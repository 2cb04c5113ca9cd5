/* libFuzzer harness: the thesis' cellular-automaton descriptor format. */
#include <stdint.h>
#include <stdlib.h>

#include "squama/ca.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    SqCa a, b;
    SqError err;
    if (sq_ca_parse((const char *)data, size, "fuzz.ca", &a, &err) != SQ_OK) {
        if (err.what[0] == '\0' || err.where[0] == '\0')
            abort();
        return 0;
    }
    char text[8192];
    size_t n = sq_ca_format(&a, text, sizeof text);
    if (n >= sizeof text)
        return 0;
    if (sq_ca_parse(text, n, "again.ca", &b, &err) != SQ_OK || !sq_ca_equal(&a, &b))
        abort(); /* format -> parse must give the same automaton */
    return 0;
}
