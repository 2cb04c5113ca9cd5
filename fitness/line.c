/* The body line: where the body runs in a photo, drawn by hand (or written by the
 * preparation for editing), read and written as JSON (include/squama/fitness.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "squama/fitness.h"
#include "squama/io.h"

#include "json_util.h"

void sq_body_line_free(SqBodyLine *line)
{
    if (!line)
        return;
    free(line->count);
    free(line->xy);
    memset(line, 0, sizeof *line);
}

/* A finite number in [lo, hi]. */
static int number_in(const cJSON *it, double lo, double hi, double *v)
{
    if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble) || it->valuedouble < lo || it->valuedouble > hi)
        return 0;
    *v = it->valuedouble;
    return 1;
}

static SqStatus parse_root(const cJSON *root, const char *name, SqBodyLine *out, SqError *err)
{
    char where[SQ_ERROR_WHERE_MAX];
    if (!cJSON_IsObject(root))
        return sq_error_set(err, SQ_ERR_INVALID, name, "a body line must be a JSON object");
    const cJSON *format = NULL, *width = NULL, *stretches = NULL;
    for (const cJSON *it = root->child; it; it = it->next) {
        const cJSON **slot = strcmp(it->string, "format") == 0  ? &format
                             : strcmp(it->string, "width") == 0 ? &width
                             : strcmp(it->string, "stretches") == 0 ? &stretches
                                                                     : NULL;
        snprintf(where, sizeof where, "%s: %.60s", name, it->string);
        if (!slot)
            return sq_error_set(err, SQ_ERR_INVALID, where,
                                "unknown key (a body line has \"format\", \"width\" and \"stretches\")");
        if (*slot)
            return sq_error_set(err, SQ_ERR_INVALID, where, "the key appears twice");
        *slot = it;
    }
    if (!format || !cJSON_IsString(format) || strcmp(format->valuestring, SQ_BODY_LINE_FORMAT) != 0)
        return sq_error_set(err, format ? SQ_ERR_UNSUPPORTED : SQ_ERR_INVALID, name,
                            "\"format\" must be \"" SQ_BODY_LINE_FORMAT "\" (is this a body line?)");
    snprintf(where, sizeof where, "%s: width", name);
    if (!width || !number_in(width, 1, 1e6, &out->width))
        return sq_error_set(err, SQ_ERR_INVALID, where,
                            "the body's width in photo pixels must be a number from 1 to 1e6");
    snprintf(where, sizeof where, "%s: stretches", name);
    const int ns = cJSON_IsArray(stretches) ? cJSON_GetArraySize(stretches) : 0;
    if (ns < 1 || ns > SQ_BODY_LINE_MAX_STRETCHES)
        return sq_error_set(err, SQ_ERR_INVALID, where,
                            "must be a list of 1 to %d stretches, each a list of [x, y] points",
                            SQ_BODY_LINE_MAX_STRETCHES);
    int total = 0, k = 0;
    for (const cJSON *s = stretches->child; s; s = s->next, k++) {
        const int np = cJSON_IsArray(s) ? cJSON_GetArraySize(s) : 0;
        snprintf(where, sizeof where, "%s: stretches[%d]", name, k);
        if (np < 2 || np > SQ_BODY_LINE_MAX_POINTS - total)
            return sq_error_set(err, np < 2 ? SQ_ERR_INVALID : SQ_ERR_LIMIT, where,
                                np < 2 ? "a stretch is a list of 2 points at least, each [x, y]"
                                       : "more than %d points in all",
                                SQ_BODY_LINE_MAX_POINTS);
        total += np;
    }
    out->nstretches = ns;
    out->count = malloc(sizeof(int) * (size_t)ns);
    out->xy = malloc(sizeof(float) * 2 * (size_t)total);
    if (!out->count || !out->xy)
        return sq_error_set(err, SQ_ERR_NOMEM, name, "out of memory");
    k = 0;
    int j = 0;
    for (const cJSON *s = stretches->child; s; s = s->next, k++) {
        out->count[k] = cJSON_GetArraySize(s);
        int i = 0;
        for (const cJSON *p = s->child; p; p = p->next, i++, j++) {
            double x, y;
            snprintf(where, sizeof where, "%s: stretches[%d][%d]", name, k, i);
            if (!cJSON_IsArray(p) || cJSON_GetArraySize(p) != 2 || !number_in(p->child, -1e6, 1e6, &x) ||
                !number_in(p->child->next, -1e6, 1e6, &y))
                return sq_error_set(err, SQ_ERR_INVALID, where, "a point must be [x, y], two numbers (photo pixels)");
            out->xy[2 * j] = (float)x;
            out->xy[2 * j + 1] = (float)y;
        }
    }
    return SQ_OK;
}

SqStatus sq_body_line_parse(const char *text, size_t len, const char *name, SqBodyLine *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    name = name ? name : "body line";
    if (len > SQ_BODY_LINE_MAX_BYTES)
        return sq_error_set(err, SQ_ERR_LIMIT, name, "larger than %d bytes: not a body line", SQ_BODY_LINE_MAX_BYTES);
    cJSON *root;
    SqStatus st = sq__json_parse(text, len, name, &root, err);
    if (st != SQ_OK)
        return st;
    st = parse_root(root, name, out, err);
    cJSON_Delete(root);
    if (st != SQ_OK)
        sq_body_line_free(out);
    return st;
}

SqStatus sq_body_line_read(const char *path, SqBodyLine *out, SqError *err)
{
    char *text = NULL;
    size_t len = 0;
    memset(out, 0, sizeof *out);
    SqStatus st = sq_io_read_file(path, SQ_BODY_LINE_MAX_BYTES, &text, &len, err);
    if (st == SQ_OK)
        st = sq_body_line_parse(text, len, path, out, err);
    free(text);
    return st;
}

SqStatus sq_body_line_write(const char *path, const SqBodyLine *line, SqError *err)
{
    /* by hand, one stretch a line: short enough to edit; what the parser takes only */
    int total = 0;
    for (int k = 0; k < line->nstretches; k++)
        total += line->count[k];
    int sane = line->nstretches >= 1 && line->nstretches <= SQ_BODY_LINE_MAX_STRETCHES && total <= SQ_BODY_LINE_MAX_POINTS &&
               line->width >= 1 && line->width <= 1e6;
    for (int i = 0; i < 2 * total && sane; i++)
        sane = fabsf(line->xy[i]) <= 1e6f;
    if (!sane)
        return sq_error_set(err, SQ_ERR_INVALID, path, "not a body line: 1 to %d stretches, %d points at most, "
                            "coordinates and width within 1e6", SQ_BODY_LINE_MAX_STRETCHES, SQ_BODY_LINE_MAX_POINTS);
    const size_t cap = 128 + 64 * (size_t)total + 16 * (size_t)line->nstretches;
    char *text = malloc(cap);
    if (!text)
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    size_t o = (size_t)snprintf(text, cap, "{\n  \"format\": \"%s\",\n  \"width\": %.1f,\n  \"stretches\": [",
                                SQ_BODY_LINE_FORMAT, line->width);
    for (int k = 0, j = 0; k < line->nstretches; k++) {
        o += (size_t)snprintf(text + o, cap - o, "%s\n    [", k ? "," : "");
        for (int i = 0; i < line->count[k]; i++, j++)
            o += (size_t)snprintf(text + o, cap - o, "%s[%.1f, %.1f]", i ? ", " : "", line->xy[2 * j],
                                  line->xy[2 * j + 1]);
        o += (size_t)snprintf(text + o, cap - o, "]");
    }
    o += (size_t)snprintf(text + o, cap - o, "\n  ]\n}\n");
    SqStatus st = sq_io_write_file(path, text, o, err);
    free(text);
    return st;
}
