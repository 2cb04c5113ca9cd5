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

/* ---- a strict check of JSON text, for exact error positions ----
 *
 * cJSON takes some text that RFC 8259 does not ("010", "1.", a "\u0000" that cuts its string
 * short) and places some errors a byte late or at the text's last byte. The check below walks
 * the text once by the RFC's grammar and stops at the first byte in error, saying what was
 * expected there; cJSON then parses only text that passed. Written here rather than taken
 * from a library: it is a hundred lines, and the parser itself stays cJSON. */

enum { JSON_DEPTH_MAX = 1000 }; /* cJSON's CJSON_NESTING_LIMIT */

typedef struct Scan {
    const char *s;
    size_t n, i;
    const char *what; /* set at the first error; i is then its offset */
} Scan;

static int scan_fail(Scan *sc, const char *what)
{
    sc->what = what;
    return -1;
}

static void scan_ws(Scan *sc)
{
    while (sc->i < sc->n && (sc->s[sc->i] == ' ' || sc->s[sc->i] == '\t' || sc->s[sc->i] == '\n' ||
                             sc->s[sc->i] == '\r'))
        sc->i++;
}

static int hex4(const Scan *sc, size_t at, unsigned *v)
{
    *v = 0;
    for (size_t k = at; k < at + 4; k++) {
        if (k >= sc->n)
            return -1;
        char c = sc->s[k];
        unsigned d = c >= '0' && c <= '9' ? (unsigned)(c - '0')
                     : c >= 'a' && c <= 'f' ? (unsigned)(c - 'a' + 10)
                     : c >= 'A' && c <= 'F' ? (unsigned)(c - 'A' + 10)
                                            : 16u;
        if (d > 15)
            return -1;
        *v = *v * 16 + d;
    }
    return 0;
}

static int scan_string(Scan *sc)
{
    sc->i++; /* the opening quote */
    while (sc->i < sc->n) {
        unsigned char c = (unsigned char)sc->s[sc->i];
        if (c == '"') {
            sc->i++;
            return 0;
        }
        if (c < 0x20)
            return scan_fail(sc, "a control character inside a string (write it as \\n, \\t or \\u00XX)");
        if (c != '\\') {
            sc->i++;
            continue;
        }
        if (sc->i + 1 >= sc->n) {
            sc->i = sc->n;
            break;
        }
        char e = sc->s[sc->i + 1];
        if (strchr("\"\\/bfnrt", e) && e) {
            sc->i += 2;
            continue;
        }
        if (e != 'u')
            return scan_fail(sc, "an unknown escape in a string (JSON has \\\" \\\\ \\/ \\b \\f \\n \\r \\t \\uXXXX)");
        unsigned v, w;
        if (hex4(sc, sc->i + 2, &v) != 0)
            return scan_fail(sc, "\\u needs four hexadecimal digits");
        if (v == 0)
            return scan_fail(sc, "\\u0000 (a NUL character) inside a string");
        if (v >= 0xDC00 && v <= 0xDFFF)
            return scan_fail(sc, "a lone low surrogate \\uDC00-\\uDFFF inside a string");
        if (v >= 0xD800 && v <= 0xDBFF) {
            if (sc->i + 7 >= sc->n || sc->s[sc->i + 6] != '\\' || sc->s[sc->i + 7] != 'u' ||
                hex4(sc, sc->i + 8, &w) != 0 || w < 0xDC00 || w > 0xDFFF)
                return scan_fail(sc, "a high surrogate \\uD800-\\uDBFF not followed by a low one");
            sc->i += 6;
        }
        sc->i += 6;
    }
    return scan_fail(sc, "the text ends inside a string");
}

static int digits(Scan *sc)
{
    size_t at = sc->i;
    while (sc->i < sc->n && sc->s[sc->i] >= '0' && sc->s[sc->i] <= '9')
        sc->i++;
    return sc->i > at;
}

static int scan_number(Scan *sc)
{
    const size_t start = sc->i;
    if (sc->s[sc->i] == '-')
        sc->i++;
    if (sc->i < sc->n && sc->s[sc->i] == '0') {
        sc->i++;
        if (sc->i < sc->n && sc->s[sc->i] >= '0' && sc->s[sc->i] <= '9') {
            sc->i = start;
            return scan_fail(sc, "a number with a leading zero");
        }
    } else if (!digits(sc)) {
        sc->i = start;
        return scan_fail(sc, "a '-' without digits");
    }
    if (sc->i < sc->n && sc->s[sc->i] == '.') {
        sc->i++;
        if (!digits(sc))
            return scan_fail(sc, "a number needs digits after its '.'");
    }
    if (sc->i < sc->n && (sc->s[sc->i] == 'e' || sc->s[sc->i] == 'E')) {
        sc->i++;
        if (sc->i < sc->n && (sc->s[sc->i] == '+' || sc->s[sc->i] == '-'))
            sc->i++;
        if (!digits(sc))
            return scan_fail(sc, "a number needs digits in its exponent");
    }
    return 0;
}

static int scan_value(Scan *sc, int depth);

/* an object or array, at its opening bracket */
static int scan_container(Scan *sc, int depth)
{
    const char close = sc->s[sc->i] == '{' ? '}' : ']';
    const int object = close == '}';
    if (depth >= JSON_DEPTH_MAX)
        return scan_fail(sc, "nested more than 1000 deep");
    sc->i++;
    scan_ws(sc);
    if (sc->i < sc->n && sc->s[sc->i] == close) {
        sc->i++;
        return 0;
    }
    for (;;) {
        if (object) {
            if (sc->i >= sc->n || sc->s[sc->i] != '"')
                return scan_fail(sc, sc->i < sc->n && sc->s[sc->i] == '}' ? "a ',' before the '}' (a trailing comma)"
                                                                          : "expected a key in double quotes");
            if (scan_string(sc) != 0)
                return -1;
            scan_ws(sc);
            if (sc->i >= sc->n || sc->s[sc->i] != ':')
                return scan_fail(sc, "expected a ':' after the key");
            sc->i++;
        } else if (sc->i < sc->n && sc->s[sc->i] == ']') {
            return scan_fail(sc, "a ',' before the ']' (a trailing comma)");
        }
        if (scan_value(sc, depth + 1) != 0)
            return -1;
        scan_ws(sc);
        if (sc->i < sc->n && sc->s[sc->i] == close) {
            sc->i++;
            return 0;
        }
        if (sc->i >= sc->n || sc->s[sc->i] != ',')
            return scan_fail(sc, object ? "expected a ',' or a '}'" : "expected a ',' or a ']'");
        sc->i++;
        scan_ws(sc);
    }
}

static int scan_value(Scan *sc, int depth)
{
    scan_ws(sc);
    if (sc->i >= sc->n)
        return scan_fail(sc, "expected a value");
    const char c = sc->s[sc->i];
    if (c == '{' || c == '[')
        return scan_container(sc, depth);
    if (c == '"')
        return scan_string(sc);
    if (c == '-' || (c >= '0' && c <= '9'))
        return scan_number(sc);
    static const char *const words[] = {"true", "false", "null"};
    for (int k = 0; k < 3; k++) {
        size_t l = strlen(words[k]);
        if (sc->n - sc->i >= l && memcmp(sc->s + sc->i, words[k], l) == 0) {
            sc->i += l;
            return 0;
        }
    }
    return scan_fail(sc, "expected a value (a string, a number, an object, an array, true, false or null)");
}

int sq__json_check(const char *text, size_t len, size_t *off, const char **what)
{
    Scan sc = {text, len, 0, NULL};
    if (scan_value(&sc, 0) == 0) {
        scan_ws(&sc);
        if (sc.i < len)
            scan_fail(&sc, "unexpected text after the JSON value");
    }
    if (!sc.what)
        return 0;
    *off = sc.i < len ? sc.i : len;
    *what = sc.what;
    return -1;
}

static void line_col(const char *text, size_t off, int *line, int *col)
{
    *line = 1;
    *col = 1;
    const size_t bom = off >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0; /* no column of its own */
    for (size_t i = bom; i < off; i++) {
        if (text[i] == '\n' || (text[i] == '\r' && text[i + 1] != '\n')) { /* LF, CRLF or CR alone */
            ++*line;
            *col = 1;
        } else if (((unsigned char)text[i] & 0xC0) != 0x80) { /* a column a character */
            ++*col;
        }
    }
}

void sq__json_where(const char *text, size_t off, const char *name, char *where, size_t size)
{
    int line, col;
    line_col(text, off, &line, &col);
    snprintf(where, size, "%s:%d:%d", name, line, col);
}

SqStatus sq__json_parse(const char *text, size_t len, const char *name, cJSON **root, SqError *err)
{
    char where[SQ_ERROR_WHERE_MAX];
    *root = NULL;
    if (len == 0) {
        snprintf(where, sizeof where, "%s:1:1", name);
        return sq_error_set(err, SQ_ERR_PARSE, where, "malformed JSON: the file is empty");
    }
    const char *nul = memchr(text, '\0', len);
    if (nul) {
        sq__json_where(text, (size_t)(nul - text), name, where, sizeof where);
        return sq_error_set(err, SQ_ERR_PARSE, where, "contains a NUL byte: not a JSON text file");
    }
    size_t off;
    const char *what;
    /* a UTF-8 byte order mark is not JSON, but RFC 8259 lets a reader ignore it (cJSON did) */
    const size_t bom = len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    if (len == bom) {
        snprintf(where, sizeof where, "%s:1:1", name);
        return sq_error_set(err, SQ_ERR_PARSE, where, "malformed JSON: the file is empty (a byte order mark alone)");
    }
    if (sq__json_check(text + bom, len - bom, &off, &what) != 0) {
        off += bom;
        if (off >= len) { /* the text ends early: its last character */
            size_t last = len - 1;
            while (last > 0 && ((unsigned char)text[last] & 0xC0) == 0x80)
                last--;
            sq__json_where(text, last, name, where, sizeof where);
            return sq_error_set(err, SQ_ERR_PARSE, where, "malformed JSON at the end of the text (unfinished?): %s",
                                what);
        }
        sq__json_where(text, off, name, where, sizeof where);
        /* the text from there: up to 20 bytes, whole characters, no control bytes */
        int show = len - off < 20 ? (int)(len - off) : 20; /* text need not end in NUL */
        for (int k = 0; k < show; k++)
            if ((unsigned char)text[off + (size_t)k] < 0x20 || text[off + (size_t)k] == 0x7F)
                show = k;
        if (off + (size_t)show < len)
            while (show > 0 && ((unsigned char)text[off + (size_t)show] & 0xC0) == 0x80)
                show--;
        if (show == 0)
            return sq_error_set(err, SQ_ERR_PARSE, where, "malformed JSON: %s", what);
        return sq_error_set(err, SQ_ERR_PARSE, where, "malformed JSON: %s, at \"%.*s\"", what, show, text + off);
    }
    *root = cJSON_ParseWithLength(text + bom, len - bom);
    if (!*root) /* the text is JSON: cJSON ran out of memory */
        return sq_error_set(err, SQ_ERR_NOMEM, name, "out of memory parsing JSON");
    return SQ_OK;
}
