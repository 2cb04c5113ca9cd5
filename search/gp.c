/* Genetic-programming operators on the variable structures of the genome (the cellular
 * automaton), and tournament selection, after Hewgill & Ross 2003: tournaments of 5,
 * crossover of segments, point and structural mutation. Every operator leaves a valid
 * automaton (sq_ca_validate passes). */
#include <string.h>

#include "rng.h"
#include "squama/search.h"

/* The automata squama builds: rows like the thesis' (18 to 32 cells, 4 to 6 epochs). */
enum { CELLS_MIN = 8, CELLS_MAX = 48, EPOCHS_MIN = 2, EPOCHS_MAX = 12, RULES_MAX = 4 };

static double uni(uint64_t *r)
{
    return (double)(sq__splitmix(r) >> 11) * 0x1.0p-53;
}

static int pick(uint64_t *r, int n)
{
    return n <= 1 ? 0 : (int)(uni(r) * n);
}

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* Makes the schedule valid: rule bits within the type, the last rule runs for the
 * remaining epochs, no rule after an 'x'. */
static void repair(SqCa *ca)
{
    int maxbits = (1 << sq_ca_rule_bits(ca->type)) - 1;
    ca->ncells = clampi(ca->ncells, 2, SQ_CA_MAX_CELLS);
    ca->epochs = clampi(ca->epochs, 1, SQ_CA_MAX_EPOCHS);
    ca->nrules = clampi(ca->nrules, 1, SQ_CA_MAX_RULES);
    for (int i = 0; i < ca->nrules; i++) {
        SqCaRule *q = &ca->rules[i];
        q->bits &= (uint8_t)maxbits;
        if (q->epochs == SQ_CA_REMAINING && i != ca->nrules - 1) {
            ca->nrules = i + 1;
            break;
        }
        if (q->epochs != SQ_CA_REMAINING)
            q->epochs = clampi(q->epochs, 1, 8);
    }
    ca->rules[ca->nrules - 1].epochs = SQ_CA_REMAINING;
    if (ca->shift_mirror > SQ_CA_MAX_SHIFT || ca->shift_mirror < -SQ_CA_MAX_SHIFT)
        ca->shift_mirror = 0;
}

static void random_rule(uint64_t *r, const SqCa *ca, SqCaRule *q)
{
    q->bits = (uint8_t)pick(r, 1 << sq_ca_rule_bits(ca->type));
    q->epochs = 1 + pick(r, 3);
}

void sq_gp_ca_random(uint64_t *rng, SqCa *out)
{
    memset(out, 0, sizeof *out);
    out->type = uni(rng) < 0.5 ? SQ_CA_RECTANGULAR : SQ_CA_TRIANGULAR;
    out->ncells = CELLS_MIN + pick(rng, CELLS_MAX - CELLS_MIN + 1);
    /* runs of ones and zeros, as the thesis' rows are */
    int v = uni(rng) < 0.5, run = 0;
    for (int i = 0; i < out->ncells; i++) {
        if (run-- <= 0) {
            v = !v;
            run = pick(rng, 6);
        }
        out->cells[i] = (uint8_t)v;
    }
    out->shift_mirror = uni(rng) < 0.7 ? 0 : pick(rng, 5) - 2;
    out->epochs = EPOCHS_MIN + pick(rng, EPOCHS_MAX - EPOCHS_MIN + 1);
    out->nrules = 1 + pick(rng, RULES_MAX);
    for (int i = 0; i < out->nrules; i++)
        random_rule(rng, out, &out->rules[i]);
    repair(out);
}

void sq_gp_ca_point_mutate(uint64_t *rng, SqCa *ca)
{
    switch (pick(rng, 4)) {
    case 0: {
        int i = pick(rng, ca->ncells);
        ca->cells[i] ^= 1;
        break;
    }
    case 1: {
        SqCaRule *q = &ca->rules[pick(rng, ca->nrules)];
        q->bits ^= (uint8_t)(1u << pick(rng, sq_ca_rule_bits(ca->type)));
        break;
    }
    case 2: {
        SqCaRule *q = &ca->rules[pick(rng, ca->nrules)];
        if (q->epochs != SQ_CA_REMAINING)
            q->epochs += uni(rng) < 0.5 ? -1 : 1;
        else
            ca->epochs += uni(rng) < 0.5 ? -1 : 1;
        break;
    }
    default:
        ca->shift_mirror += uni(rng) < 0.5 ? -1 : 1;
        if (ca->shift_mirror > 4 || ca->shift_mirror < -4)
            ca->shift_mirror = 0;
        break;
    }
    repair(ca);
}

void sq_gp_ca_struct_mutate(uint64_t *rng, SqCa *ca)
{
    switch (pick(rng, 5)) {
    case 0: /* insert a rule before a random place */
        if (ca->nrules < RULES_MAX) {
            int at = pick(rng, ca->nrules);
            memmove(&ca->rules[at + 1], &ca->rules[at], sizeof(SqCaRule) * (size_t)(ca->nrules - at));
            random_rule(rng, ca, &ca->rules[at]);
            ca->nrules++;
        }
        break;
    case 1: /* delete a rule */
        if (ca->nrules > 1) {
            int at = pick(rng, ca->nrules);
            memmove(&ca->rules[at], &ca->rules[at + 1], sizeof(SqCaRule) * (size_t)(ca->nrules - at - 1));
            ca->nrules--;
        }
        break;
    case 2: { /* repeat a segment of the row */
        int len = 1 + pick(rng, 6), at = pick(rng, ca->ncells);
        if (ca->ncells + len <= CELLS_MAX && at + len <= ca->ncells) {
            memmove(&ca->cells[at + len], &ca->cells[at], (size_t)(ca->ncells - at));
            ca->ncells += len;
        }
        break;
    }
    case 3: { /* cut a segment */
        int len = 1 + pick(rng, 6), at = pick(rng, ca->ncells);
        if (ca->ncells - len >= CELLS_MIN && at + len <= ca->ncells) {
            memmove(&ca->cells[at], &ca->cells[at + len], (size_t)(ca->ncells - at - len));
            ca->ncells -= len;
        }
        break;
    }
    default: /* the other neighbourhood: rules keep their low bits */
        ca->type = ca->type == SQ_CA_RECTANGULAR ? SQ_CA_TRIANGULAR : SQ_CA_RECTANGULAR;
        break;
    }
    ca->epochs = clampi(ca->epochs, EPOCHS_MIN, EPOCHS_MAX);
    repair(ca);
}

void sq_gp_ca_crossover(uint64_t *rng, const SqCa *a, const SqCa *b, SqCa *child)
{
    SqCa c = *a;
    /* a segment of b's row at the same relative place */
    int i0 = pick(rng, c.ncells), i1 = i0 + 1 + pick(rng, c.ncells - i0);
    for (int i = i0; i < i1 && i < c.ncells; i++) {
        int j = (int)((long)i * b->ncells / c.ncells);
        c.cells[i] = b->cells[j];
    }
    /* a's schedule up to a cut, then b's from its cut */
    int ca_cut = pick(rng, a->nrules + 1), cb_cut = pick(rng, b->nrules);
    int n = ca_cut;
    for (int k = cb_cut; k < b->nrules && n < RULES_MAX; k++)
        c.rules[n++] = b->rules[k];
    c.nrules = n > 0 ? n : 1;
    if (n == 0)
        c.rules[0] = b->rules[b->nrules - 1];
    if (uni(rng) < 0.5)
        c.epochs = b->epochs;
    repair(&c);
    *child = c;
}

int sq_gp_tournament(uint64_t *rng, int n, int k, const int *rank, const double *crowd)
{
    int best = pick(rng, n);
    for (int t = 1; t < k; t++) {
        int c = pick(rng, n);
        if (rank[c] < rank[best] || (rank[c] == rank[best] && crowd && crowd[c] > crowd[best]))
            best = c;
    }
    return best;
}

void sq_gp_ca_children(uint64_t *rng, const SqCa *parents, int n, const int *rank, const double *crowd,
                       const SqCa *best, double keep, SqCa *out, int l)
{
    for (int k = 0; k < l; k++) {
        if (uni(rng) < keep) {
            out[k] = *best;
            continue;
        }
        const SqCa *a = &parents[sq_gp_tournament(rng, n, 5, rank, crowd)];
        out[k] = *a;
        if (uni(rng) < 0.6)
            sq_gp_ca_crossover(rng, a, &parents[sq_gp_tournament(rng, n, 5, rank, crowd)], &out[k]);
        if (uni(rng) < 0.5)
            sq_gp_ca_point_mutate(rng, &out[k]);
        if (uni(rng) < 0.2)
            sq_gp_ca_struct_mutate(rng, &out[k]);
    }
}
