/* Presets: strict JSON loading and exact saving, driven by the parameter table. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "json_util.h"
#include "squama/preset.h"

enum { MAX_KEYS = 1000 };

/* Where keys are looked up and how fields are named: the whole preset, or one pattern
 * layer's object (its text span, and "Pattern_Layers[i]." before every name). */
typedef struct Ctx {
    const char *text;
    size_t len;
    const char *name;
    SqError *err;
    size_t from, to;    /* the span searched for keys' lines */
    const char *prefix; /* "" or "Pattern_Layers[i]." */
} Ctx;

/* 1-based line of byte offset off. */
static int line_of(const Ctx *c, size_t off)
{
    int line = 1;
    for (size_t i = 0; i < off && i < c->len; i++)
        line += c->text[i] == '\n';
    return line;
}

/* Byte offset of the `occurrence`-th (1-based) appearance of "key" used as an object key
 * (followed by optional white space and ':') inside the context's span; the offset just
 * past the ':' goes to *after. (size_t)-1 when not found. */
static size_t key_offset(const Ctx *c, const char *key, int occurrence, size_t *after)
{
    size_t klen = strlen(key);
    int seen = 0;
    for (size_t i = c->from; i < c->to; i++) {
        if (c->text[i] != '"' || i + klen + 2 > c->to)
            continue;
        if (memcmp(c->text + i + 1, key, klen) != 0 || c->text[i + 1 + klen] != '"')
            continue;
        size_t j = i + klen + 2;
        while (j < c->to && (c->text[j] == ' ' || c->text[j] == '\t' || c->text[j] == '\r' ||
                             c->text[j] == '\n'))
            j++;
        if (j < c->to && c->text[j] == ':' && ++seen == occurrence) {
            if (after)
                *after = j + 1;
            return i;
        }
    }
    return (size_t)-1;
}

/* 1-based line of a key (as key_offset finds it), or of the span's start inside a layer,
 * or 0 when unknown. */
static int key_line(const Ctx *c, const char *key, int occurrence)
{
    size_t off = key ? key_offset(c, key, occurrence, NULL) : (size_t)-1;
    if (off != (size_t)-1)
        return line_of(c, off);
    return c->from > 0 ? line_of(c, c->from) : 0;
}

static const char *where_key(const Ctx *c, const char *key, int occurrence, char *buf, size_t n)
{
    int line = key_line(c, key, occurrence);
    if (line > 0)
        snprintf(buf, n, "%s:%d", c->name, line);
    else
        snprintf(buf, n, "%s", c->name);
    return buf;
}

static SqStatus fail(const Ctx *c, SqStatus st, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static SqStatus fail(const Ctx *c, SqStatus st, const char *key, const char *fmt, ...)
{
    char where[SQ_ERROR_WHERE_MAX], what[SQ_ERROR_WHAT_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    where_key(c, key, 1, where, sizeof where);
    return sq_error_set(c->err, st, where, "%s", what);
}

/* "a string", "an array", ... for messages about wrong types. */
static const char *describe(const cJSON *v, char *buf, size_t n)
{
    if (cJSON_IsNumber(v)) snprintf(buf, n, "%.10g", v->valuedouble);
    else if (cJSON_IsString(v)) snprintf(buf, n, "the string \"%.40s\"", v->valuestring);
    else if (cJSON_IsTrue(v)) snprintf(buf, n, "true");
    else if (cJSON_IsFalse(v)) snprintf(buf, n, "false");
    else if (cJSON_IsNull(v)) snprintf(buf, n, "null");
    else if (cJSON_IsArray(v)) snprintf(buf, n, "an array of %d", cJSON_GetArraySize(v));
    else if (cJSON_IsObject(v)) snprintf(buf, n, "an object");
    else snprintf(buf, n, "an unknown value");
    return buf;
}

static const char *range_hint(const SqParamSpec *s, char *buf, size_t n)
{
    if (s->smin != s->min || s->smax != s->max)
        snprintf(buf, n, "; suggested %.10g to %.10g", s->smin, s->smax);
    else
        buf[0] = '\0';
    return buf;
}

/* How messages call a field: its name, "Pattern_Layers[i]." before it inside a layer. */
static void field_name(const Ctx *c, const SqParamSpec *s, char *buf, size_t n)
{
    snprintf(buf, n, "%s%s", c->prefix, s->name);
}

static SqStatus get_number(const Ctx *c, const SqParamSpec *s, const cJSON *v, const char *what,
                           double *out)
{
    char got[80], hint[80], name[160];
    field_name(c, s, name, sizeof name);
    if (!cJSON_IsNumber(v))
        return fail(c, SQ_ERR_INVALID, s->name, "\"%s\"%s must be a number in [%.10g, %.10g], got %s",
                    name, what, s->min, s->max, describe(v, got, sizeof got));
    double d = v->valuedouble;
    if (!isfinite(d))
        return fail(c, SQ_ERR_INVALID, s->name, "\"%s\"%s is not a finite number", name, what);
    if (d < s->min || d > s->max)
        return fail(c, SQ_ERR_INVALID, s->name, "\"%s\"%s is %.10g, outside its range [%.10g, %.10g]%s",
                    name, what, d, s->min, s->max, range_hint(s, hint, sizeof hint));
    *out = d;
    return SQ_OK;
}

/* ---- the cellular automaton as a JSON object ---- */

static SqStatus ca_from_object(const Ctx *c, const SqParamSpec *s, const cJSON *obj, SqCa *ca)
{
    static const char *const keys[] = {"initial", "type", "shift_mirror", "epochs", "rules", NULL};
    char where[SQ_ERROR_WHERE_MAX], got[80], name[160];
    SqStatus st;
    field_name(c, s, name, sizeof name);
    memset(ca, 0, sizeof *ca);
    where_key(c, s->name, 1, where, sizeof where);

    for (const cJSON *it = obj->child; it; it = it->next) {
        int known = 0;
        for (int k = 0; keys[k]; k++)
            known |= strcmp(it->string, keys[k]) == 0;
        if (!known)
            return fail(c, SQ_ERR_INVALID, s->name,
                        "\"%s\" has an unknown key \"%.60s\" (keys: initial, type, "
                        "shift_mirror, epochs, rules)",
                        name, it->string);
        for (const cJSON *o = it->next; o; o = o->next)
            if (strcmp(o->string, it->string) == 0)
                return fail(c, SQ_ERR_INVALID, s->name, "\"%s\" has the key \"%s\" twice",
                            name, it->string);
    }
    const cJSON *initial = cJSON_GetObjectItemCaseSensitive(obj, "initial");
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(obj, "type");
    const cJSON *shift = cJSON_GetObjectItemCaseSensitive(obj, "shift_mirror");
    const cJSON *epochs = cJSON_GetObjectItemCaseSensitive(obj, "epochs");
    const cJSON *rules = cJSON_GetObjectItemCaseSensitive(obj, "rules");
    if (!initial || !type || !epochs || !rules)
        return fail(c, SQ_ERR_INVALID, s->name,
                    "\"%s\" needs the keys initial, type, epochs and rules (shift_mirror is "
                    "optional)",
                    name);

    if (cJSON_IsString(initial)) {
        if ((st = sq_ca_parse_row(initial->valuestring, ca, where, c->err)) != SQ_OK)
            return st;
    } else if (cJSON_IsArray(initial)) {
        int n = cJSON_GetArraySize(initial);
        if (n > SQ_CA_MAX_CELLS)
            return fail(c, SQ_ERR_LIMIT, s->name, "\"%s\".initial has more than %d cells",
                        name, SQ_CA_MAX_CELLS);
        ca->ncells = 0;
        for (const cJSON *b = initial->child; b; b = b->next) {
            if (!cJSON_IsNumber(b) || (b->valuedouble != 0 && b->valuedouble != 1))
                return fail(c, SQ_ERR_INVALID, s->name,
                            "\"%s\".initial must hold only 0 and 1, got %s", name,
                            describe(b, got, sizeof got));
            ca->cells[ca->ncells++] = (uint8_t)b->valuedouble;
        }
    } else {
        return fail(c, SQ_ERR_INVALID, s->name,
                    "\"%s\".initial must be a string of 0s and 1s or an array, got %s",
                    name, describe(initial, got, sizeof got));
    }

    if (cJSON_IsString(type) && strcmp(type->valuestring, "rectangular") == 0)
        ca->type = SQ_CA_RECTANGULAR;
    else if (cJSON_IsString(type) && strcmp(type->valuestring, "triangular") == 0)
        ca->type = SQ_CA_TRIANGULAR;
    else
        return fail(c, SQ_ERR_INVALID, s->name,
                    "\"%s\".type must be \"rectangular\" or \"triangular\", got %s", name,
                    describe(type, got, sizeof got));

    if (shift) {
        if (!cJSON_IsNumber(shift) || shift->valuedouble != floor(shift->valuedouble) ||
            fabs(shift->valuedouble) > SQ_CA_MAX_SHIFT)
            return fail(c, SQ_ERR_INVALID, s->name,
                        "\"%s\".shift_mirror must be an integer in [%d, %d], got %s", name,
                        -SQ_CA_MAX_SHIFT, SQ_CA_MAX_SHIFT, describe(shift, got, sizeof got));
        ca->shift_mirror = (int)shift->valuedouble;
    }
    if (!cJSON_IsNumber(epochs) || epochs->valuedouble != floor(epochs->valuedouble) ||
        epochs->valuedouble < 1 || epochs->valuedouble > SQ_CA_MAX_EPOCHS)
        return fail(c, SQ_ERR_INVALID, s->name,
                    "\"%s\".epochs must be an integer in [1, %d], got %s", name,
                    SQ_CA_MAX_EPOCHS, describe(epochs, got, sizeof got));
    ca->epochs = (int)epochs->valuedouble;

    if (!cJSON_IsArray(rules) || cJSON_GetArraySize(rules) < 1)
        return fail(c, SQ_ERR_INVALID, s->name,
                    "\"%s\".rules must be a non-empty array of rules like \"1110 1\" or "
                    "\"1000 x\", got %s",
                    name, describe(rules, got, sizeof got));
    if (cJSON_GetArraySize(rules) > SQ_CA_MAX_RULES)
        return fail(c, SQ_ERR_LIMIT, s->name, "\"%s\" has more than %d rules", name,
                    SQ_CA_MAX_RULES);
    for (const cJSON *r = rules->child; r; r = r->next) {
        if (!cJSON_IsString(r))
            return fail(c, SQ_ERR_INVALID, s->name,
                        "\"%s\".rules must hold strings like \"1110 1\", got %s", name,
                        describe(r, got, sizeof got));
        if ((st = sq_ca_parse_rule(r->valuestring, ca->type, &ca->rules[ca->nrules], where,
                                   c->err)) != SQ_OK)
            return st;
        ca->nrules++;
    }
    return sq_ca_validate(ca, where, c->err);
}

static SqStatus layers_from_array(const Ctx *c, const SqParamSpec *s, const cJSON *v,
                                  SqPatternLayers *ls);

/* Sets the field f (of SqParams or of a pattern layer) described by s from v. */
static SqStatus set_field(const Ctx *c, const SqParamSpec *s, const cJSON *v, void *f)
{
    char got[80], what[32], name[160];
    SqStatus st;
    double d;
    field_name(c, s, name, sizeof name);

    switch (s->type) {
    case SQ_PT_FLOAT:
        return get_number(c, s, v, "", (double *)f);
    case SQ_PT_INT:
        if (cJSON_IsNumber(v) && isfinite(v->valuedouble) &&
            v->valuedouble != floor(v->valuedouble))
            return fail(c, SQ_ERR_INVALID, s->name, "\"%s\" must be an integer in [%.10g, %.10g], got %.10g",
                        name, s->min, s->max, v->valuedouble);
        if ((st = get_number(c, s, v, "", &d)) != SQ_OK)
            return st;
        *(int *)f = (int)d;
        return SQ_OK;
    case SQ_PT_BOOL:
        if (!cJSON_IsBool(v))
            return fail(c, SQ_ERR_INVALID, s->name, "\"%s\" must be true or false, got %s", name,
                        describe(v, got, sizeof got));
        *(int *)f = cJSON_IsTrue(v) ? 1 : 0;
        return SQ_OK;
    case SQ_PT_ENUM:
        if (cJSON_IsString(v))
            for (int k = 0; s->choices[k]; k++)
                if (strcmp(v->valuestring, s->choices[k]) == 0) {
                    *(int *)f = k;
                    return SQ_OK;
                }
        {
            char list[256] = "";
            for (int k = 0; s->choices[k]; k++) {
                strncat(list, k ? ", " : "", sizeof list - strlen(list) - 1);
                strncat(list, s->choices[k], sizeof list - strlen(list) - 1);
            }
            return fail(c, SQ_ERR_INVALID, s->name, "\"%s\" must be one of %s; got %s", name, list,
                        describe(v, got, sizeof got));
        }
    case SQ_PT_VEC2:
    case SQ_PT_COLOR: {
        int want = sq_param_components(s->type);
        int n = cJSON_IsArray(v) ? cJSON_GetArraySize(v) : -1;
        int ok = s->type == SQ_PT_VEC2 ? n == 2 : (n == 3 || n == 4);
        if (!ok)
            return fail(c, SQ_ERR_INVALID, s->name, "\"%s\" must be %s with components in [%.10g, %.10g], got %s",
                        name,
                        s->type == SQ_PT_VEC2 ? "an array [x, y]" : "an array [r, g, b, a] (or [r, g, b])",
                        s->min, s->max, describe(v, got, sizeof got));
        double tmp[4] = {0, 0, 0, 1};
        int k = 0;
        for (const cJSON *e = v->child; e; e = e->next, k++) {
            snprintf(what, sizeof what, "[%d]", k);
            if ((st = get_number(c, s, e, what, &tmp[k])) != SQ_OK)
                return st;
        }
        memcpy(f, tmp, sizeof(double) * (size_t)want);
        return SQ_OK;
    }
    case SQ_PT_CA:
        if (cJSON_IsString(v)) {
            char where[SQ_ERROR_WHERE_MAX], text_name[SQ_ERROR_WHERE_MAX + 200];
            where_key(c, s->name, 1, where, sizeof where);
            snprintf(text_name, sizeof text_name, "%s, %s text line", where, name);
            return sq_ca_parse(v->valuestring, strlen(v->valuestring), text_name, f, c->err);
        }
        if (cJSON_IsObject(v))
            return ca_from_object(c, s, v, f);
        return fail(c, SQ_ERR_INVALID, s->name,
                    "\"%s\" must be descriptor text (a string) or an object, got %s", name,
                    describe(v, got, sizeof got));
    case SQ_PT_LAYERS:
        return layers_from_array(c, s, v, f);
    }
    return fail(c, SQ_ERR_INTERNAL, s->name, "parameter \"%s\" has an unknown type", name);
}

/* ---- pattern layers: an array of objects, each parsed by the same table rows ---- */

/* Skips white space from i (bounded by the context's span). */
static size_t skip_space(const Ctx *c, size_t i)
{
    while (i < c->to && (c->text[i] == ' ' || c->text[i] == '\t' || c->text[i] == '\r' ||
                         c->text[i] == '\n'))
        i++;
    return i;
}

/* The text span [*from, *to) of element k of the JSON array that starts at or after
 * offset `at` (already parsed, so well formed; bounds are checked all the same). Used
 * only to name lines in messages: on any surprise the whole span of c is kept. */
static void element_span(const Ctx *c, size_t at, int k, size_t *from, size_t *to)
{
    *from = c->from;
    *to = c->to;
    size_t i = skip_space(c, at);
    if (i >= c->to || c->text[i] != '[')
        return;
    int depth = 0, idx = 0, in_str = 0;
    size_t start = skip_space(c, i + 1);
    for (; i < c->to; i++) {
        char ch = c->text[i];
        if (in_str) {
            if (ch == '\\')
                i++;
            else if (ch == '"')
                in_str = 0;
            continue;
        }
        if (ch == '"') {
            in_str = 1;
        } else if (ch == '[' || ch == '{') {
            depth++;
        } else if (ch == ']' || ch == '}' || (ch == ',' && depth == 1)) {
            if (depth == 1) { /* the end of element idx */
                if (idx == k) {
                    *from = start;
                    *to = i;
                    return;
                }
                idx++;
                start = skip_space(c, i + 1);
            }
            if (ch != ',')
                depth--;
            if (depth == 0)
                return;
        }
    }
}

static SqStatus layer_from_object(const Ctx *c, int k, const cJSON *obj, SqPatternLayer *l)
{
    char got[80];
    int nkeys = 0;
    sq_pattern_layer_default(l);
    if (!cJSON_IsObject(obj))
        return fail(c, SQ_ERR_INVALID, NULL,
                    "Pattern_Layers[%d] must be an object of pattern parameters "
                    "(Pattern_Type, Layer_Blend, Layer_Opacity, ...), got %s",
                    k, describe(obj, got, sizeof got));
    for (const cJSON *it = obj->child; it; it = it->next) {
        if (++nkeys > MAX_KEYS)
            return fail(c, SQ_ERR_LIMIT, NULL, "Pattern_Layers[%d] has more than %d keys", k,
                        MAX_KEYS);
        for (const cJSON *o = it->next; o; o = o->next)
            if (strcmp(o->string, it->string) == 0) {
                char where[SQ_ERROR_WHERE_MAX];
                return sq_error_set(c->err, SQ_ERR_INVALID,
                                    where_key(c, it->string, 2, where, sizeof where),
                                    "Pattern_Layers[%d] has the key \"%.100s\" twice", k,
                                    it->string);
            }
        const SqParamSpec *s = sq_params_find(it->string);
        if (!s)
            return fail(c, SQ_ERR_INVALID, it->string,
                        "Pattern_Layers[%d] has an unknown key \"%.100s\" (did you mean "
                        "\"%s\"?)",
                        k, it->string, sq_params_closest(it->string)->name);
        if (!sq_param_in_layer(s))
            return fail(c, SQ_ERR_INVALID, it->string,
                        "\"%s\" (group %s) cannot be set in Pattern_Layers[%d]: a layer takes "
                        "only Pattern_Type, the pattern groups' parameters, Layer_Blend and "
                        "Layer_Opacity",
                        s->name, s->group, k);
        SqStatus st = set_field(c, s, it, sq_param_layer_ptr(l, s));
        if (st != SQ_OK)
            return st;
    }
    return SQ_OK;
}

static SqStatus layers_from_array(const Ctx *c, const SqParamSpec *s, const cJSON *v,
                                  SqPatternLayers *ls)
{
    char got[80];
    if (!cJSON_IsArray(v))
        return fail(c, SQ_ERR_INVALID, s->name,
                    "\"%s\" must be an array of layer objects, got %s", s->name,
                    describe(v, got, sizeof got));
    int n = cJSON_GetArraySize(v);
    if (n > SQ_MAX_PATTERN_LAYERS)
        return fail(c, SQ_ERR_LIMIT, s->name, "\"%s\" has %d layers; at most %d are allowed",
                    s->name, n, SQ_MAX_PATTERN_LAYERS);
    size_t value_at = 0;
    if (key_offset(c, s->name, 1, &value_at) == (size_t)-1)
        value_at = c->to; /* no span: lines are not named */
    ls->count = 0;
    int k = 0;
    for (const cJSON *e = v->child; e; e = e->next, k++) {
        char prefix[64];
        snprintf(prefix, sizeof prefix, "%s[%d].", s->name, k);
        Ctx sub = *c;
        sub.prefix = prefix;
        element_span(c, value_at, k, &sub.from, &sub.to);
        SqStatus st = layer_from_object(&sub, k, e, &ls->layer[k]);
        if (st != SQ_OK)
            return st;
    }
    ls->count = n;
    return SQ_OK;
}

/* The byte offset of s's first byte that is not well-formed UTF-8 (RFC 3629: no overlong
 * forms, no surrogates, nothing past U+10FFFF), or -1. */
static long utf8_bad(const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    for (long i = 0; p[i];) {
        const unsigned b = p[i];
        int len = b < 0x80 ? 1 : (b >> 5) == 6 ? 2 : (b >> 4) == 14 ? 3 : (b >> 3) == 30 ? 4 : 0;
        if (!len)
            return i;
        unsigned cp = len == 1 ? b : b & (0x7Fu >> len);
        for (int k = 1; k < len; k++) {
            if ((p[i + k] & 0xC0) != 0x80)
                return i;
            cp = cp << 6 | (p[i + k] & 0x3F);
        }
        static const unsigned least[5] = {0, 0, 0x80, 0x800, 0x10000};
        if (cp < least[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
            return i;
        i += len;
    }
    return -1;
}

static SqStatus copy_string(const Ctx *c, const cJSON *v, const char *key, char *dst, size_t n)
{
    char got[80];
    if (!cJSON_IsString(v))
        return fail(c, SQ_ERR_INVALID, key, "\"%s\" must be a string, got %s", key,
                    describe(v, got, sizeof got));
    const long bad = utf8_bad(v->valuestring);
    if (bad >= 0)
        return fail(c, SQ_ERR_INVALID, key, "\"%s\" is not UTF-8 text (a stray byte 0x%02X at its byte %ld)", key,
                    (unsigned char)v->valuestring[bad], bad);
    if (strlen(v->valuestring) >= n)
        return fail(c, SQ_ERR_LIMIT, key, "\"%s\" is longer than %zu bytes", key, n - 1);
    if (dst)
        memcpy(dst, v->valuestring, strlen(v->valuestring) + 1);
    return SQ_OK;
}

static SqStatus parse_root(const Ctx *c, const cJSON *root, SqParams *out, SqPresetInfo *info)
{
    SqPresetInfo scratch;
    SqStatus st;
    char got[80];
    int have_format = 0, nkeys = 0;

    if (!cJSON_IsObject(root))
        return fail(c, SQ_ERR_INVALID, NULL, "a preset must be a JSON object, got %s",
                    describe(root, got, sizeof got));
    if (!info)
        info = &scratch;
    info->name[0] = info->notes[0] = '\0';
    sq_params_default(out);

    for (const cJSON *it = root->child; it; it = it->next)
        if (++nkeys > MAX_KEYS)
            return fail(c, SQ_ERR_LIMIT, NULL, "more than %d keys: not a preset", MAX_KEYS);
    for (const cJSON *it = root->child; it; it = it->next) {
        for (const cJSON *o = it->next; o; o = o->next)
            if (strcmp(o->string, it->string) == 0) {
                char where[SQ_ERROR_WHERE_MAX];
                return sq_error_set(c->err, SQ_ERR_INVALID,
                                    where_key(c, it->string, 2, where, sizeof where),
                                    "key \"%.100s\" appears twice", it->string);
            }
        if (strcmp(it->string, "format") == 0) {
            if (!cJSON_IsString(it) || strcmp(it->valuestring, SQ_PRESET_FORMAT) != 0)
                return fail(c, SQ_ERR_UNSUPPORTED, "format",
                            "unsupported preset format %s (this squama reads \"" SQ_PRESET_FORMAT
                            "\")",
                            describe(it, got, sizeof got));
            have_format = 1;
        } else if (strcmp(it->string, "name") == 0) {
            if ((st = copy_string(c, it, "name", info->name, sizeof info->name)) != SQ_OK)
                return st;
        } else if (strcmp(it->string, "notes") == 0) {
            if ((st = copy_string(c, it, "notes", info->notes, sizeof info->notes)) != SQ_OK)
                return st;
        } else {
            const SqParamSpec *s = sq_params_find(it->string);
            if (!s)
                return fail(c, SQ_ERR_INVALID, it->string,
                            "unknown key \"%.100s\" (did you mean \"%s\"?)", it->string,
                            sq_params_closest(it->string)->name);
            if (s->flags & SQ_PF_LAYER)
                return fail(c, SQ_ERR_INVALID, it->string,
                            "\"%s\" belongs inside a layer of \"Pattern_Layers\", not at the "
                            "top level",
                            s->name);
            if ((st = set_field(c, s, it, sq_param_ptr(out, s))) != SQ_OK)
                return st;
        }
    }
    if (!have_format)
        return fail(c, SQ_ERR_INVALID, NULL,
                    "missing \"format\": \"" SQ_PRESET_FORMAT "\" (is this a squama preset?)");
    SqError tmp;
    if ((st = sq_params_validate(out, &tmp)) != SQ_OK)
        return fail(c, st, tmp.where, "%s", tmp.what);
    return SQ_OK;
}

SqStatus sq_preset_parse(const char *text, size_t len, const char *name, SqParams *out,
                         SqPresetInfo *info, SqError *err)
{
    Ctx c = {text, len, name ? name : "preset", err, 0, len, ""};
    if (len > SQ_PRESET_MAX_BYTES)
        return fail(&c, SQ_ERR_LIMIT, NULL, "preset larger than %d bytes", SQ_PRESET_MAX_BYTES);
    cJSON *root;
    SqStatus st = sq__json_parse(text, len, c.name, &root, err);
    if (st != SQ_OK)
        return st;
    st = parse_root(&c, root, out, info);
    cJSON_Delete(root);
    return st;
}

SqStatus sq_preset_load(const char *path, SqParams *out, SqPresetInfo *info, SqError *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return sq_error_set(err, SQ_ERR_IO, path, "cannot open preset: %s", strerror(errno));
    char *buf = malloc((size_t)SQ_PRESET_MAX_BYTES + 1);
    if (!buf) {
        fclose(f);
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    }
    size_t n = fread(buf, 1, (size_t)SQ_PRESET_MAX_BYTES + 1, f);
    const int bad = ferror(f), e = errno;
    fclose(f);
    SqStatus st;
    if (bad)
        st = sq_error_set(err, SQ_ERR_IO, path, "cannot read preset: %s", strerror(e));
    else if (n > (size_t)SQ_PRESET_MAX_BYTES)
        st = sq_error_set(err, SQ_ERR_LIMIT, path, "preset larger than %d bytes",
                          SQ_PRESET_MAX_BYTES);
    else
        st = sq_preset_parse(buf, n, path, out, info, err);
    free(buf);
    return st;
}

/* ---- saving ---- */

static cJSON *ca_to_object(const SqCa *ca)
{
    cJSON *o = cJSON_CreateObject();
    char row[2 * SQ_CA_MAX_CELLS + 1];
    size_t k = 0;
    for (int i = 0; i < ca->ncells; i++) {
        if (i)
            row[k++] = ' ';
        row[k++] = (char)('0' + ca->cells[i]);
    }
    row[k] = '\0';
    cJSON_AddStringToObject(o, "initial", row);
    cJSON_AddStringToObject(o, "type", sq_ca_type_name(ca->type));
    cJSON_AddNumberToObject(o, "shift_mirror", ca->shift_mirror);
    cJSON_AddNumberToObject(o, "epochs", ca->epochs);
    cJSON *rules = cJSON_AddArrayToObject(o, "rules");
    for (int i = 0; i < ca->nrules; i++) {
        char r[32];
        sq_ca_format_rule(ca, i, r, sizeof r);
        cJSON_AddItemToArray(rules, cJSON_CreateString(r));
    }
    return o;
}

static cJSON *field_to_json(const void *f, const SqParamSpec *s);

/* A layer's object: Pattern_Type, its blend and opacity first, then every other pattern
 * parameter in table order. */
static cJSON *layers_to_array(const SqPatternLayers *ls)
{
    static const char *const first[] = {"Pattern_Type", "Layer_Blend", "Layer_Opacity", NULL};
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    cJSON *arr = cJSON_CreateArray();
    for (int k = 0; arr && k < ls->count; k++) {
        const SqPatternLayer *l = &ls->layer[k];
        cJSON *o = cJSON_CreateObject();
        if (!o || !cJSON_AddItemToArray(arr, o))
            goto nomem;
        for (int pass = 0; pass < 2; pass++)
            for (size_t i = 0; i < n; i++) {
                if (!sq_param_in_layer(&t[i]))
                    continue;
                int is_first = 0;
                for (int j = 0; first[j]; j++)
                    is_first |= strcmp(t[i].name, first[j]) == 0;
                if (is_first != (pass == 0))
                    continue;
                cJSON *v = field_to_json(sq_param_layer_cptr(l, &t[i]), &t[i]);
                if (!v || !cJSON_AddItemToObject(o, t[i].name, v)) {
                    cJSON_Delete(v);
                    goto nomem;
                }
            }
    }
    return arr;
nomem:
    cJSON_Delete(arr);
    return NULL;
}

static cJSON *field_to_json(const void *f, const SqParamSpec *s)
{
    cJSON *v = NULL;
    switch (s->type) {
    case SQ_PT_FLOAT: v = sq__json_exact_number(*(const double *)f); break;
    case SQ_PT_INT: v = cJSON_CreateNumber(*(const int *)f); break;
    case SQ_PT_BOOL: v = cJSON_CreateBool(*(const int *)f); break;
    case SQ_PT_ENUM: v = cJSON_CreateString(s->choices[*(const int *)f]); break;
    case SQ_PT_VEC2:
    case SQ_PT_COLOR:
        v = cJSON_CreateArray();
        for (int c = 0; v && c < sq_param_components(s->type); c++)
            cJSON_AddItemToArray(v, sq__json_exact_number(((const double *)f)[c]));
        break;
    case SQ_PT_CA: v = ca_to_object(f); break;
    case SQ_PT_LAYERS: v = layers_to_array(f); break;
    }
    return v;
}

char *sq_preset_to_json(const SqParams *p, const SqPresetInfo *info, SqError *err)
{
    SqStatus st = sq_params_validate(p, err);
    if (st != SQ_OK)
        return NULL;
    size_t n;
    const SqParamSpec *t = sq_params_table(&n);
    cJSON *root = cJSON_CreateObject();
    if (!root)
        goto nomem;
    cJSON_AddStringToObject(root, "format", SQ_PRESET_FORMAT);
    if (info && info->name[0])
        cJSON_AddStringToObject(root, "name", info->name);
    if (info && info->notes[0])
        cJSON_AddStringToObject(root, "notes", info->notes);
    for (size_t i = 0; i < n; i++) {
        if (t[i].flags & SQ_PF_LAYER) /* written inside each layer */
            continue;
        cJSON *v = field_to_json(sq_param_cptr(p, &t[i]), &t[i]);
        if (!v)
            goto nomem;
        cJSON_AddItemToObject(root, t[i].name, v);
    }
    char *out = sq__json_print(root);
    cJSON_Delete(root);
    if (out)
        return out;
    root = NULL;
nomem:
    cJSON_Delete(root);
    sq_error_set(err, SQ_ERR_NOMEM, "", "out of memory while writing a preset");
    return NULL;
}
