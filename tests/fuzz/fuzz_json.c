/* libFuzzer harness: the strict JSON check every squama JSON reader runs before cJSON
 * (generator/json_util.c). It is stricter than cJSON: what it passes, cJSON parses, and
 * whatever it refuses is named at a byte of the text. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "json_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *text = (const char *)data;
    size_t off = 0;
    const char *what = NULL;
    if (sq__json_check(text, size, &off, &what) != 0) {
        if (!what || !*what || off > size)
            abort();
        return 0;
    }
    if (memchr(text, '\0', size))
        return 0; /* sq__json_parse refuses NUL bytes before the check */
    cJSON *root = cJSON_ParseWithLength(text, size);
    if (!root)
        abort(); /* passed the check, refused by cJSON */
    cJSON_Delete(root);
    return 0;
}
