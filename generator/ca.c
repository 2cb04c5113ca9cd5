/* Cellular-automaton descriptors: the thesis' text format (§4.2.4, Appendix E).
 * Strict parser with line numbers, canonical formatter, validation. */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "squama/ca.h"
#include "textbuf.h"

int sq_ca_rule_bits(SqCaType type)
{
    return type == SQ_CA_TRIANGULAR ? 3 : 4;
}

const char *sq_ca_type_name(SqCaType type)
{
    return type == SQ_CA_TRIANGULAR ? "triangular" : "rectangular";
}

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* Parses a decimal integer token in [lo, hi]; the whole token must be the number. */
static int parse_int(const char *s, size_t len, long lo, long hi, long *out)
{
    char buf[32];
    if (len == 0 || len >= sizeof buf)
        return 0;
    memcpy(buf, s, len);
    buf[len] = '\0';
    char *end;
    errno = 0;
    long v = strtol(buf, &end, 10);
    if (errno || *end || end == buf || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}

SqStatus sq_ca_parse_row(const char *s, SqCa *ca, const char *where, SqError *err)
{
    ca->ncells = 0;
    for (const char *c = s; *c; c++) {
        if (is_space(*c))
            continue;
        if (*c != '0' && *c != '1')
            return sq_error_set(err, SQ_ERR_PARSE, where,
                                "initial values must be 0s and 1s, found '%c'", *c);
        if (ca->ncells == SQ_CA_MAX_CELLS)
            return sq_error_set(err, SQ_ERR_LIMIT, where,
                                "the initial row has more than %d cells", SQ_CA_MAX_CELLS);
        ca->cells[ca->ncells++] = (uint8_t)(*c - '0');
    }
    if (ca->ncells < 2)
        return sq_error_set(err, SQ_ERR_INVALID, where,
                            "the initial row needs at least 2 cells, found %d", ca->ncells);
    return SQ_OK;
}

SqStatus sq_ca_parse_rule(const char *s, SqCaType type, SqCaRule *out, const char *where,
                          SqError *err)
{
    int nbits = sq_ca_rule_bits(type);
    const char *p = s;
    while (is_space(*p)) p++;
    const char *bits = p;
    while (*p && !is_space(*p)) p++;
    size_t blen = (size_t)(p - bits);
    while (is_space(*p)) p++;
    const char *count = p;
    while (*p && !is_space(*p)) p++;
    size_t clen = (size_t)(p - count);
    while (is_space(*p)) p++;

    if (blen == 0)
        return sq_error_set(err, SQ_ERR_PARSE, where, "expected a transition rule");
    if (blen != (size_t)nbits)
        return sq_error_set(err, SQ_ERR_INVALID, where,
                            "%s rules have %d bits, \"%.*s\" has %zu", sq_ca_type_name(type),
                            nbits, (int)(blen > 16 ? 16 : blen), bits, blen);
    uint8_t v = 0;
    for (size_t i = 0; i < blen; i++) {
        if (bits[i] != '0' && bits[i] != '1')
            return sq_error_set(err, SQ_ERR_PARSE, where,
                                "rule bits must be 0 or 1, found '%c'", bits[i]);
        v = (uint8_t)((v << 1) | (bits[i] - '0'));
    }
    if (clen == 0)
        return sq_error_set(err, SQ_ERR_PARSE, where,
                            "rule \"%.*s\" needs an epoch count or 'x' after it", (int)blen,
                            bits);
    if (*p)
        return sq_error_set(err, SQ_ERR_PARSE, where, "unexpected text after the rule: \"%.20s\"",
                            p);
    out->bits = v;
    if (clen == 1 && (count[0] == 'x' || count[0] == 'X')) {
        out->epochs = SQ_CA_REMAINING;
        return SQ_OK;
    }
    long n;
    if (!parse_int(count, clen, 1, SQ_CA_MAX_EPOCHS, &n))
        return sq_error_set(err, SQ_ERR_INVALID, where,
                            "rule epoch count must be 'x' or an integer in [1, %d], got \"%.*s\"",
                            SQ_CA_MAX_EPOCHS, (int)(clen > 16 ? 16 : clen), count);
    out->epochs = (int)n;
    return SQ_OK;
}

SqStatus sq_ca_validate(const SqCa *ca, const char *where, SqError *err)
{
    if (ca->ncells < 2 || ca->ncells > SQ_CA_MAX_CELLS)
        return sq_error_set(err, SQ_ERR_INVALID, where,
                            "the initial row must have 2 to %d cells, has %d", SQ_CA_MAX_CELLS,
                            ca->ncells);
    for (int i = 0; i < ca->ncells; i++)
        if (ca->cells[i] > 1)
            return sq_error_set(err, SQ_ERR_INVALID, where, "cell %d of the initial row is not 0 or 1", i);
    if (ca->type != SQ_CA_RECTANGULAR && ca->type != SQ_CA_TRIANGULAR)
        return sq_error_set(err, SQ_ERR_INVALID, where, "automaton type must be rectangular or triangular");
    if (ca->shift_mirror < -SQ_CA_MAX_SHIFT || ca->shift_mirror > SQ_CA_MAX_SHIFT)
        return sq_error_set(err, SQ_ERR_INVALID, where, "shift mirror %d is outside [%d, %d]",
                            ca->shift_mirror, -SQ_CA_MAX_SHIFT, SQ_CA_MAX_SHIFT);
    if (ca->epochs < 1 || ca->epochs > SQ_CA_MAX_EPOCHS)
        return sq_error_set(err, SQ_ERR_INVALID, where, "epochs %d is outside [1, %d]",
                            ca->epochs, SQ_CA_MAX_EPOCHS);
    if (ca->nrules < 1 || ca->nrules > SQ_CA_MAX_RULES)
        return sq_error_set(err, SQ_ERR_INVALID, where, "an automaton needs 1 to %d transition rules, has %d",
                            SQ_CA_MAX_RULES, ca->nrules);
    int maxbits = (1 << sq_ca_rule_bits(ca->type)) - 1;
    long covered = 0;
    for (int i = 0; i < ca->nrules; i++) {
        const SqCaRule *r = &ca->rules[i];
        if (r->bits > maxbits)
            return sq_error_set(err, SQ_ERR_INVALID, where, "rule %d has more than %d bits",
                                i + 1, sq_ca_rule_bits(ca->type));
        if (r->epochs == SQ_CA_REMAINING) {
            if (i != ca->nrules - 1)
                return sq_error_set(err, SQ_ERR_INVALID, where,
                                    "rule %d runs for the remaining epochs ('x'), so rule %d is "
                                    "never used",
                                    i + 1, i + 2);
            covered = LONG_MAX;
        } else if (r->epochs < 1 || r->epochs > SQ_CA_MAX_EPOCHS) {
            return sq_error_set(err, SQ_ERR_INVALID, where,
                                "rule %d lasts %d epochs, outside [1, %d]", i + 1, r->epochs,
                                SQ_CA_MAX_EPOCHS);
        } else {
            covered += r->epochs;
        }
    }
    /* The initial row is the first of `epochs` rows: epochs - 1 rows are computed. */
    if (covered < ca->epochs - 1)
        return sq_error_set(err, SQ_ERR_INVALID, where,
                            "the rules cover %ld epochs but %d rows must be computed; give "
                            "the last rule 'x' to use it for the rest",
                            covered, ca->epochs - 1);
    return SQ_OK;
}

SqStatus sq_ca_parse(const char *text, size_t len, const char *name, SqCa *out, SqError *err)
{
    enum { ITEM_ROW, ITEM_TYPE, ITEM_SHIFT, ITEM_EPOCHS, ITEM_RULES } item = ITEM_ROW;
    char line[4096], where[600];
    int lineno = 0, last_rule_line = 0;
    size_t pos = 0;
    if (!name)
        name = "descriptor";
    memset(out, 0, sizeof *out);

    while (pos < len) {
        size_t start = pos;
        while (pos < len && text[pos] != '\n')
            pos++;
        size_t n = pos - start;
        if (pos < len)
            pos++; /* the '\n' */
        lineno++;
        snprintf(where, sizeof where, "%s:%d", name, lineno);
        if (memchr(text + start, '\0', n))
            return sq_error_set(err, SQ_ERR_PARSE, where, "the descriptor contains a NUL byte");
        if (n >= sizeof line)
            return sq_error_set(err, SQ_ERR_LIMIT, where, "line longer than %zu characters",
                                sizeof line - 1);
        memcpy(line, text + start, n);
        line[n] = '\0';
        char *c = strstr(line, "//");
        if (c)
            *c = '\0';
        /* trim */
        char *b = line;
        while (is_space(*b)) b++;
        char *e = b + strlen(b);
        while (e > b && is_space(e[-1])) *--e = '\0';
        if (*b == '\0')
            continue;

        SqStatus st;
        long v;
        switch (item) {
        case ITEM_ROW:
            if ((st = sq_ca_parse_row(b, out, where, err)) != SQ_OK)
                return st;
            item = ITEM_TYPE;
            break;
        case ITEM_TYPE:
            if (strcmp(b, "rectangular") == 0)
                out->type = SQ_CA_RECTANGULAR;
            else if (strcmp(b, "triangular") == 0)
                out->type = SQ_CA_TRIANGULAR;
            else
                return sq_error_set(err, SQ_ERR_INVALID, where,
                                    "automaton type must be \"rectangular\" or \"triangular\", "
                                    "got \"%.40s\"",
                                    b);
            item = ITEM_SHIFT;
            break;
        case ITEM_SHIFT:
            if (!parse_int(b, strlen(b), -SQ_CA_MAX_SHIFT, SQ_CA_MAX_SHIFT, &v))
                return sq_error_set(err, SQ_ERR_INVALID, where,
                                    "shift mirror must be an integer in [%d, %d], got \"%.40s\"",
                                    -SQ_CA_MAX_SHIFT, SQ_CA_MAX_SHIFT, b);
            out->shift_mirror = (int)v;
            item = ITEM_EPOCHS;
            break;
        case ITEM_EPOCHS:
            if (!parse_int(b, strlen(b), 1, SQ_CA_MAX_EPOCHS, &v))
                return sq_error_set(err, SQ_ERR_INVALID, where,
                                    "epochs must be an integer in [1, %d], got \"%.40s\"",
                                    SQ_CA_MAX_EPOCHS, b);
            out->epochs = (int)v;
            item = ITEM_RULES;
            break;
        case ITEM_RULES:
            if (out->nrules > 0 && out->rules[out->nrules - 1].epochs == SQ_CA_REMAINING)
                return sq_error_set(err, SQ_ERR_INVALID, where,
                                    "this rule is never used: the rule on line %d runs for all "
                                    "remaining epochs ('x')",
                                    last_rule_line);
            if (out->nrules == SQ_CA_MAX_RULES)
                return sq_error_set(err, SQ_ERR_LIMIT, where, "more than %d transition rules",
                                    SQ_CA_MAX_RULES);
            if ((st = sq_ca_parse_rule(b, out->type, &out->rules[out->nrules], where, err)) != SQ_OK)
                return st;
            out->nrules++;
            last_rule_line = lineno;
            break;
        }
    }

    if (lineno > 0)
        snprintf(where, sizeof where, "%s:%d", name, lineno);
    else
        snprintf(where, sizeof where, "%s", name);
    static const char *const missing[] = {"the initial values", "the automaton type",
                                           "the shift mirror", "the number of epochs",
                                           "a transition rule"};
    if (item != ITEM_RULES || out->nrules == 0)
        return sq_error_set(err, SQ_ERR_PARSE, where, "the descriptor ends before %s",
                            missing[item == ITEM_RULES ? 4 : item]);
    return sq_ca_validate(out, name, err);
}

SqStatus sq_ca_load(const char *path, SqCa *out, SqError *err)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return sq_error_set(err, SQ_ERR_IO, path, "cannot open: %s", strerror(errno));
    enum { MAX = 1 << 20 };
    char *buf = malloc(MAX + 1);
    if (!buf) {
        fclose(f);
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory");
    }
    size_t n = fread(buf, 1, MAX + 1, f);
    const int bad = ferror(f), e = errno;
    fclose(f);
    SqStatus st;
    if (bad)
        st = sq_error_set(err, SQ_ERR_IO, path, "cannot read: %s", strerror(e));
    else if (n > MAX)
        st = sq_error_set(err, SQ_ERR_LIMIT, path, "a descriptor file over 1 MiB is not plausible");
    else
        st = sq_ca_parse(buf, n, path, out, err);
    free(buf);
    return st;
}

void sq_ca_format_rule(const SqCa *ca, int i, char *buf, size_t size)
{
    int nbits = sq_ca_rule_bits(ca->type);
    char bits[8];
    for (int b = 0; b < nbits; b++)
        bits[b] = (char)('0' + ((ca->rules[i].bits >> (nbits - 1 - b)) & 1));
    bits[nbits] = '\0';
    if (ca->rules[i].epochs == SQ_CA_REMAINING)
        snprintf(buf, size, "%s x", bits);
    else
        snprintf(buf, size, "%s %d", bits, ca->rules[i].epochs);
}

size_t sq_ca_format(const SqCa *ca, char *buf, size_t size)
{
    size_t n = 0;
    for (int i = 0; i < ca->ncells; i++)
        sq__appendf(buf, size, &n, "%s%d", i ? " " : "", ca->cells[i]);
    sq__appendf(buf, size, &n, "\n%s\n%d\n%d\n", sq_ca_type_name(ca->type), ca->shift_mirror, ca->epochs);
    for (int i = 0; i < ca->nrules; i++) {
        char r[32];
        sq_ca_format_rule(ca, i, r, sizeof r);
        sq__appendf(buf, size, &n, "%s\n", r);
    }
    return n;
}

int sq_ca_equal(const SqCa *a, const SqCa *b)
{
    if (a->ncells != b->ncells || a->type != b->type || a->shift_mirror != b->shift_mirror ||
        a->epochs != b->epochs || a->nrules != b->nrules)
        return 0;
    if (memcmp(a->cells, b->cells, (size_t)a->ncells) != 0)
        return 0;
    for (int i = 0; i < a->nrules; i++)
        if (a->rules[i].bits != b->rules[i].bits || a->rules[i].epochs != b->rules[i].epochs)
            return 0;
    return 1;
}
