#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_util.h"

void sq__format_exact(double d, char *buf, size_t size)
{
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, size, "%.*g", prec, d);
        if (strtod(buf, NULL) == d)
            return;
    }
}

cJSON *sq__json_exact_number(double d)
{
    char buf[40];
    sq__format_exact(d, buf, sizeof buf);
    return cJSON_CreateRaw(buf);
}

char *sq__json_print(const cJSON *item)
{
    char *raw = cJSON_Print(item);
    if (!raw)
        return NULL;
    /* cJSON indents with tabs and puts one after each ':'; we want two spaces and one.
     * Tabs occur nowhere else (inside strings they are escaped). */
    size_t tabs = 0, len = strlen(raw);
    for (size_t i = 0; i < len; i++)
        tabs += raw[i] == '\t';
    char *out = malloc(len + tabs + 2);
    if (out) {
        size_t k = 0;
        for (size_t i = 0; i < len; i++) {
            if (raw[i] != '\t') {
                out[k++] = raw[i];
            } else if (i > 0 && raw[i - 1] == ':') {
                out[k++] = ' ';
            } else {
                out[k++] = ' ';
                out[k++] = ' ';
            }
        }
        out[k++] = '\n';
        out[k] = '\0';
    }
    cJSON_free(raw);
    return out;
}
