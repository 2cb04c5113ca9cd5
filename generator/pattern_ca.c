/* Other simple pattern, §4.2.4: a rectangular or triangular cellular automaton (after
 * Cocho et al. 1987) computed row by row, painted as circles (1 cells black: the
 * pattern), duplicated above itself mirrored vertically (the mirror copy shifted by
 * Shift Mirror x 1/3 of the circle diameter) and stretched over the texture: the cells
 * across u, the 2 x Epochs rows along v. Coloured by the CustomPattern parameters. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen_internal.h"

void sq_ca_evolve(const SqCa *ca, uint8_t *rows)
{
    const int n = ca->ncells;
    memcpy(rows, ca->cells, (size_t)n);
    int rule = 0, used = 0;
    for (int r = 1; r < ca->epochs; r++) {
        while (rule < ca->nrules - 1 && ca->rules[rule].epochs != SQ_CA_REMAINING &&
               used >= ca->rules[rule].epochs) {
            rule++;
            used = 0;
        }
        const uint8_t bits = ca->rules[rule].bits;
        const uint8_t *prev = rows + (size_t)(r - 1) * n;
        uint8_t *cur = rows + (size_t)r * n;
        for (int c = 0; c < n; c++) {
            int sum;
            if (ca->type == SQ_CA_RECTANGULAR) /* the cell above and its two neighbours */
                sum = prev[sq__wrap(c - 1, n)] + prev[c] + prev[(c + 1) % n];
            else if (r % 2 == 1) /* odd rows sit half a cell right: cells c and c + 1 above */
                sum = prev[c] + prev[(c + 1) % n];
            else /* even rows: the shifted row above has cells c - 1 and c over this one */
                sum = prev[sq__wrap(c - 1, n)] + prev[c];
            cur[c] = (uint8_t)((bits >> sum) & 1);
        }
        used++;
    }
}

SqStatus sq_ca_coverage(const SqCa *ca, double diameter, float *cov, int w, int h, SqError *err)
{
    if (!ca || !cov || w <= 0 || h <= 0 || ca->ncells < 1 || ca->epochs < 1)
        return sq_error_set(err, SQ_ERR_INVALID, "CA_Descriptor", "no automaton or no image to paint");
    const int n = ca->ncells, e = ca->epochs, rows = 2 * e;
    uint8_t *data = malloc((size_t)n * e);
    if (!data)
        return sq_error_set(err, SQ_ERR_NOMEM, "CA_Descriptor", "out of memory for the automaton");
    sq_ca_evolve(ca, data);

    const float d = (float)diameter, rad = d / 2;
    const float mirror_shift = (float)(ca->shift_mirror * diameter / 3.0); /* cells */
    const float sx = (float)n / (float)w, sy = (float)rows / (float)h; /* cells per pixel */
    const float aa = sx > sy ? sx : sy;                                 /* edge softness, cells */
    const float reach = rad + aa;                                       /* beyond it: nothing */
    const int k = (int)ceilf(reach) + 1;

#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++) {
        const float Y = ((float)y + 0.5f) * sy;
        const int t0 = sq__ifloor(Y);
        float *out = cov + (size_t)y * w;
        for (int x = 0; x < w; x++)
            out[x] = 0.0f;
        /* for each display row near this pixel row, the circles of its 1 cells */
        for (int t = t0 - k; t <= t0 + k; t++) {
            const float dy = Y - ((float)t + 0.5f);
            if (fabsf(dy) >= reach)
                continue;
            const int tw = sq__wrap(t, rows);
            const int top = tw < e;                  /* the mirrored copy is on top */
            const int r = top ? e - 1 - tw : tw - e; /* row of the automaton */
            const float off = (ca->type == SQ_CA_TRIANGULAR && r % 2 == 1 ? 0.5f : 0.0f) +
                              (top ? mirror_shift : 0.0f);
            const uint8_t *cells = data + (size_t)r * n;
            const float half = sqrtf(reach * reach - dy * dy); /* circle half-chord */
            for (int x = 0; x < w; x++) {
                const float X = ((float)x + 0.5f) * sx - off;
                const int c0 = sq__ifloor(X - half), c1 = sq__ifloor(X + half);
                float best = out[x];
                for (int c = c0; c <= c1; c++) {
                    if (!cells[sq__wrap(c, n)])
                        continue;
                    const float dx = X - ((float)c + 0.5f);
                    const float a = (rad - sqrtf(dx * dx + dy * dy)) / aa + 0.5f;
                    if (a > best)
                        best = a > 1.0f ? 1.0f : a;
                }
                out[x] = best;
            }
        }
    }
    free(data);
    return SQ_OK;
}

SqStatus sq__pattern_ca(const SqParams *p, SqPattern *pat, SqError *err)
{
    if (!sq__pattern_add(pat, SQ_LAYER_FULL, p->CustomPattern_Color_Outside, err))
        return err ? err->status : SQ_ERR_NOMEM;
    SqLayer *in = sq__pattern_add(pat, SQ_LAYER_2D, p->CustomPattern_Color_Inside, err);
    if (!in)
        return err ? err->status : SQ_ERR_NOMEM;
    in->has_levels = 1;
    in->levels[0] = (float)p->CustomPattern_LevelInLow;
    in->levels[1] = (float)p->CustomPattern_LevelInHigh;
    in->levels[2] = (float)p->CustomPattern_LevelInMid;
    return sq_ca_coverage(&p->CA_Descriptor, p->CA_CircleDiameter, in->cov, pat->w, pat->h, err);
}
