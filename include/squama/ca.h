/* squama — cellular-automaton descriptors (thesis §4.2.4, Appendix E).
 *
 * The thesis describes an automaton in a small text format, one item per line:
 *
 *     0 0 1 1 1 1 0 0 //Initial values
 *     rectangular     //Automaton type (rectangular | triangular)
 *     0               //Shift mirror (integer, 1/3 of a circle diameter per step)
 *     6               //Epochs (rows before duplicating and mirroring)
 *     1110 1          //transition rule and the epochs it is used for ...
 *     1100 1
 *     1000 x          //... 'x': for all remaining epochs (last rule only)
 *
 * Text after "//" is a comment; blank lines are skipped. Rules have 4 bits for
 * rectangular and 3 for triangular automata; the leftmost bit is the new cell's value
 * when the neighbourhood sum is largest, the rightmost when it is 0. The parser is
 * strict and names the line of every error. SqCa is plain data (fixed-size arrays) so a
 * parameter set holding one can be copied with memcpy.
 */
#ifndef SQUAMA_CA_H
#define SQUAMA_CA_H


#include <stddef.h>
#include <stdint.h>

#include "error.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    SQ_CA_MAX_CELLS = 512,  /* initial row length */
    SQ_CA_MAX_RULES = 32,   /* transition rules in a schedule */
    SQ_CA_MAX_EPOCHS = 1024,
    SQ_CA_MAX_SHIFT = 999,  /* |shift mirror| */
    SQ_CA_REMAINING = -1    /* SqCaRule.epochs value for 'x' */
};

typedef enum SqCaType { SQ_CA_RECTANGULAR = 0, SQ_CA_TRIANGULAR = 1 } SqCaType;

typedef struct SqCaRule {
    uint8_t bits;  /* bit k = new value for neighbourhood sum k (rule "1110" = 0xE) */
    int epochs;    /* how many epochs it is used for, or SQ_CA_REMAINING */
} SqCaRule;

typedef struct SqCa {
    int ncells;
    uint8_t cells[SQ_CA_MAX_CELLS]; /* initial row, 0 or 1 */
    SqCaType type;
    int shift_mirror;
    int epochs;
    int nrules;
    SqCaRule rules[SQ_CA_MAX_RULES];
} SqCa;

/* Number of bits in a transition rule of this automaton type (4 or 3). */
int sq_ca_rule_bits(SqCaType type);

/* Parses descriptor text. `name` (a file name, may be NULL) is used in error
 * locations as "name:line". On error *out is unspecified. */
SqStatus sq_ca_parse(const char *text, size_t len, const char *name, SqCa *out, SqError *err);

/* Reads and parses a descriptor file. */
SqStatus sq_ca_load(const char *path, SqCa *out, SqError *err);

/* Checks an automaton built in memory (e.g. from JSON or by the optimizer) against the
 * same rules the parser enforces. `where` locates errors. */
SqStatus sq_ca_validate(const SqCa *ca, const char *where, SqError *err);

/* Writes the canonical descriptor text (without comments) into buf; returns the
 * length it needs (excluding the NUL), like snprintf. */
size_t sq_ca_format(const SqCa *ca, char *buf, size_t size);

/* Formats one rule as the thesis writes it ("1110 1", "1000 x") into buf (>= 16 bytes). */
void sq_ca_format_rule(const SqCa *ca, int i, char *buf, size_t size);

/* Parses one rule ("1110 1", "100 x") for an automaton of the given type. */
SqStatus sq_ca_parse_rule(const char *s, SqCaType type, SqCaRule *out, const char *where,
                          SqError *err);

/* Parses an initial row ("0 0 1 1", "0011", or a mix of both). */
SqStatus sq_ca_parse_row(const char *s, SqCa *ca, const char *where, SqError *err);

/* Compares two automata (all fields that matter). */
int sq_ca_equal(const SqCa *a, const SqCa *b);

const char *sq_ca_type_name(SqCaType type);

#ifdef __cplusplus
}
#endif

#endif /* SQUAMA_CA_H */
