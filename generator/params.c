/* The engine behind the parameter table: defaults, lookup, validation, comparison.
 * Written once per type, never once per parameter. */
#include <ctype.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "json_util.h"
#include "squama/params.h"
#include "textbuf.h"

const char *sq_pattern_type_name(int type)
{
    if (type < 0 || type >= SQ_PATTERN_COUNT)
        return "?";
    return sq_pattern_type_names[type];
}

int sq_param_components(SqParamType type)
{
    switch (type) {
    case SQ_PT_VEC2: return 2;
    case SQ_PT_COLOR: return 4;
    case SQ_PT_CA:
    case SQ_PT_LAYERS: return 0;
    default: return 1;
    }
}

const char *sq_param_type_name(SqParamType type)
{
    static const char *const names[] = {"float", "int",   "bool", "enum",
                                        "vec2",  "color", "ca",   "layers"};
    return (unsigned)type < sizeof names / sizeof names[0] ? names[type] : "?";
}

void *sq_param_ptr(SqParams *p, const SqParamSpec *spec)
{
    return (char *)p + spec->offset;
}

const void *sq_param_cptr(const SqParams *p, const SqParamSpec *spec)
{
    return (const char *)p + spec->offset;
}

int sq_param_in_layer(const SqParamSpec *spec)
{
    if (spec->flags & SQ_PF_LAYER)
        return 1;
    return spec->offset >= offsetof(SqParams, pattern) &&
           spec->offset < offsetof(SqParams, pattern) + sizeof(SqPatternSpec);
}

/* A layer row's field relative to the layer: pattern rows shifted from SqParams.pattern to
 * SqPatternLayer.spec, a layer's own settings from Pattern_Layers.layer[0]. */
static size_t layer_offset(const SqParamSpec *spec)
{
    if (spec->flags & SQ_PF_LAYER)
        return spec->offset - offsetof(SqParams, Pattern_Layers.layer[0]);
    return spec->offset - offsetof(SqParams, pattern) + offsetof(SqPatternLayer, spec);
}

void *sq_param_layer_ptr(SqPatternLayer *l, const SqParamSpec *spec)
{
    return sq_param_in_layer(spec) ? (char *)l + layer_offset(spec) : NULL;
}

const void *sq_param_layer_cptr(const SqPatternLayer *l, const SqParamSpec *spec)
{
    return sq_param_in_layer(spec) ? (const char *)l + layer_offset(spec) : NULL;
}

const SqParamSpec *sq_params_find(const char *name)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    for (size_t i = 0; i < n; i++)
        if (strcmp(t[i].name, name) == 0)
            return &t[i];
    return NULL;
}

/* Case-insensitive Levenshtein distance, capped to keep it cheap on long input. */
static size_t edit_distance(const char *a, const char *b)
{
    enum { MAXLEN = 64 };
    size_t la = strlen(a), lb = strlen(b);
    if (la > MAXLEN) la = MAXLEN;
    if (lb > MAXLEN) lb = MAXLEN;
    size_t row[MAXLEN + 1];
    for (size_t j = 0; j <= lb; j++)
        row[j] = j;
    for (size_t i = 1; i <= la; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= lb; j++) {
            size_t up = row[j];
            int same = tolower((unsigned char)a[i - 1]) == tolower((unsigned char)b[j - 1]);
            size_t best = diag + (same ? 0 : 1);
            if (up + 1 < best) best = up + 1;
            if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[lb];
}

const SqParamSpec *sq_params_closest(const char *name)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    const SqParamSpec *best = &t[0];
    size_t bestd = (size_t)-1;
    for (size_t i = 0; i < n; i++) {
        size_t d = edit_distance(name, t[i].name);
        if (d < bestd) {
            bestd = d;
            best = &t[i];
        }
    }
    return best;
}

/* One field at its default; the engine below is written per type and used both on the
 * top level and inside each pattern layer. */
static void field_default(void *f, const SqParamSpec *s)
{
    switch (s->type) {
    case SQ_PT_FLOAT: *(double *)f = s->def[0]; break;
    case SQ_PT_INT:
    case SQ_PT_BOOL:
    case SQ_PT_ENUM: *(int *)f = (int)s->def[0]; break;
    case SQ_PT_VEC2:
    case SQ_PT_COLOR:
        memcpy(f, s->def, sizeof(double) * (size_t)sq_param_components(s->type));
        break;
    case SQ_PT_CA:
        /* The default text is part of the table and tested to parse. */
        (void)sq_ca_parse(s->def_text, strlen(s->def_text), s->name, (SqCa *)f, NULL);
        break;
    case SQ_PT_LAYERS: {
        SqPatternLayers *ls = f;
        ls->count = 0;
        for (int i = 0; i < SQ_MAX_PATTERN_LAYERS; i++)
            sq_pattern_layer_default(&ls->layer[i]);
        break;
    }
    }
}

void sq_pattern_layer_default(SqPatternLayer *l)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    memset(l, 0, sizeof *l);
    for (size_t i = 0; i < n; i++)
        if (sq_param_in_layer(&t[i]))
            field_default(sq_param_layer_ptr(l, &t[i]), &t[i]);
}

void sq_params_default(SqParams *p)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    memset(p, 0, sizeof *p);
    for (size_t i = 0; i < n; i++)
        if (!(t[i].flags & SQ_PF_LAYER)) /* set with their layers */
            field_default(sq_param_ptr(p, &t[i]), &t[i]);
}

/* `name` is how messages call the field: the table name, or "Pattern_Layers[i].Name". */
static SqStatus field_validate(const void *f, const SqParamSpec *s, const char *name,
                               SqError *err)
{
    switch (s->type) {
    case SQ_PT_INT:
    case SQ_PT_BOOL:
    case SQ_PT_ENUM: {
        int v = *(const int *)f;
        if (v < s->min || v > s->max)
            return sq_error_set(err, SQ_ERR_INVALID, name,
                                "%s is %d, outside its range [%.10g, %.10g]", name, v, s->min,
                                s->max);
        break;
    }
    case SQ_PT_FLOAT:
    case SQ_PT_VEC2:
    case SQ_PT_COLOR: {
        const double *v = f;
        for (int c = 0; c < sq_param_components(s->type); c++) {
            if (!isfinite(v[c]))
                return sq_error_set(err, SQ_ERR_INVALID, name, "%s is not a finite number",
                                    name);
            if (v[c] < s->min || v[c] > s->max)
                return sq_error_set(err, SQ_ERR_INVALID, name,
                                    "%s is %.10g, outside its range [%.10g, %.10g]", name, v[c],
                                    s->min, s->max);
        }
        break;
    }
    case SQ_PT_CA: return sq_ca_validate(f, name, err);
    case SQ_PT_LAYERS: {
        const SqPatternLayers *ls = f;
        if (ls->count < 0 || ls->count > SQ_MAX_PATTERN_LAYERS)
            return sq_error_set(err, SQ_ERR_INVALID, name,
                                "%s holds %d layers; at most %d are allowed", name, ls->count,
                                SQ_MAX_PATTERN_LAYERS);
        size_t n;
        const SqParamSpec *t = sq_params_table(&n);
        for (int k = 0; k < ls->count; k++)
            for (size_t i = 0; i < n; i++) {
                if (!sq_param_in_layer(&t[i]))
                    continue;
                char sub[160];
                snprintf(sub, sizeof sub, "%s[%d].%s", name, k, t[i].name);
                SqStatus st =
                    field_validate(sq_param_layer_cptr(&ls->layer[k], &t[i]), &t[i], sub, err);
                if (st != SQ_OK)
                    return st;
            }
        break;
    }
    }
    return SQ_OK;
}

SqStatus sq_params_validate(const SqParams *p, SqError *err)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    for (size_t i = 0; i < n; i++) {
        if (t[i].flags & SQ_PF_LAYER) /* checked with the layers in use */
            continue;
        SqStatus st = field_validate(sq_param_cptr(p, &t[i]), &t[i], t[i].name, err);
        if (st != SQ_OK)
            return st;
    }
    return SQ_OK;
}

static int field_equal(const void *fa, const void *fb, const SqParamSpec *s)
{
    switch (s->type) {
    case SQ_PT_INT:
    case SQ_PT_BOOL:
    case SQ_PT_ENUM: return *(const int *)fa == *(const int *)fb;
    case SQ_PT_FLOAT:
    case SQ_PT_VEC2:
    case SQ_PT_COLOR:
        for (int c = 0; c < sq_param_components(s->type); c++)
            if (((const double *)fa)[c] != ((const double *)fb)[c])
                return 0;
        return 1;
    case SQ_PT_CA: return sq_ca_equal(fa, fb);
    case SQ_PT_LAYERS: {
        const SqPatternLayers *a = fa, *b = fb;
        if (a->count != b->count)
            return 0;
        size_t n;
        const SqParamSpec *t = sq_params_table(&n);
        for (int k = 0; k < a->count; k++)
            for (size_t i = 0; i < n; i++)
                if (sq_param_in_layer(&t[i]) &&
                    !field_equal(sq_param_layer_cptr(&a->layer[k], &t[i]),
                                 sq_param_layer_cptr(&b->layer[k], &t[i]), &t[i]))
                    return 0;
        return 1;
    }
    }
    return 0;
}

int sq_params_equal(const SqParams *a, const SqParams *b)
{
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    for (size_t i = 0; i < n; i++)
        if (!(t[i].flags & SQ_PF_LAYER) &&
            !field_equal(sq_param_cptr(a, &t[i]), sq_param_cptr(b, &t[i]), &t[i]))
            return 0;
    return 1;
}

static void put_number(char *buf, size_t size, size_t *n, int digits, double v)
{
    char tmp[40];
    if (digits > 0)
        snprintf(tmp, sizeof tmp, "%.*g", digits, v);
    else
        sq__format_exact(v, tmp, sizeof tmp);
    sq__appendf(buf, size, n, "%s", tmp);
}

size_t sq_param_format(const SqParams *p, const SqParamSpec *s, int digits, char *buf,
                       size_t size)
{
    const void *f = sq_param_cptr(p, s);
    size_t n = 0;
    switch (s->type) {
    case SQ_PT_FLOAT: put_number(buf, size, &n, digits, *(const double *)f); break;
    case SQ_PT_INT: sq__appendf(buf, size, &n, "%d", *(const int *)f); break;
    case SQ_PT_BOOL: sq__appendf(buf, size, &n, "%s", *(const int *)f ? "true" : "false"); break;
    case SQ_PT_ENUM: sq__appendf(buf, size, &n, "%s", s->choices[*(const int *)f]); break;
    case SQ_PT_VEC2:
    case SQ_PT_COLOR:
        for (int c = 0; c < sq_param_components(s->type); c++)
        {
            sq__appendf(buf, size, &n, "%s", c ? ", " : "[");
            put_number(buf, size, &n, digits, ((const double *)f)[c]);
        }
        sq__appendf(buf, size, &n, "]");
        break;
    case SQ_PT_CA: {
        char text[4 * SQ_CA_MAX_CELLS + 64 * SQ_CA_MAX_RULES];
        sq_ca_format(f, text, sizeof text);
        size_t len = strlen(text);
        if (len && text[len - 1] == '\n')
            text[--len] = '\0';
        for (char *c = text; *c; c++) {
            if (*c == '\n')
                sq__appendf(buf, size, &n, " / ");
            else
                sq__appendf(buf, size, &n, "%c", *c);
        }
        break;
    }
    case SQ_PT_LAYERS: {
        const SqPatternLayers *ls = f;
        sq__appendf(buf, size, &n, "[");
        for (int k = 0; k < ls->count; k++) {
            const SqPatternLayer *l = &ls->layer[k];
            sq__appendf(buf, size, &n, "%s%s %s ", k ? ", " : "",
                        sq_pattern_type_name(l->spec.Pattern_Type),
                        (unsigned)l->Layer_Blend < SQ_BLEND_COUNT
                            ? sq_layer_blend_names[l->Layer_Blend]
                            : "?");
            put_number(buf, size, &n, digits, l->Layer_Opacity);
        }
        sq__appendf(buf, size, &n, "]");
        break;
    }
    }
    if (size && n >= size)
        buf[size - 1] = '\0';
    return n;
}
