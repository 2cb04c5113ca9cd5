/* libFuzzer harness: preset JSON parsing, then a save/load round trip of what parsed. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "squama/preset.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static SqParams p, q;
    SqError err;
    if (sq_preset_parse((const char *)data, size, "fuzz.json", &p, NULL, &err) != SQ_OK) {
        if (err.what[0] == '\0')
            abort(); /* every failure explains itself */
        return 0;
    }
    if (sq_params_validate(&p, &err) != SQ_OK)
        abort();
    char *text = sq_preset_to_json(&p, NULL, &err);
    if (!text)
        abort();
    if (sq_preset_parse(text, strlen(text), "again.json", &q, NULL, &err) != SQ_OK ||
        !sq_params_equal(&p, &q))
        abort(); /* save -> load must be exact */
    free(text);
    return 0;
}
