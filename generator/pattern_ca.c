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

SqStatus sq__ca_coverage(const SqParams *p, float *cov, int w, int h, SqError *err)
{
    const SqCa *ca = &p->CA_Descriptor;
    const int n = ca->ncells, e = ca->epochs, rows = 2 * e;
    uint8_t *data = malloc((size_t)n * e);
    if (!data)
        return sq_error_set(err, SQ_ERR_NOMEM, "CA_Descriptor", "out of memory for the automaton");
    sq_ca_evolve(ca, data);

    const double d = p->CA_CircleDiameter, rad = d / 2;
    const double mirror_shift = ca->shift_mirror * d / 3.0; /* cells */
    const int k = (int)ceil(rad + 0.5) + 1;                  /* neighbour cells to test */
    const double sx = (double)n / w, sy = (double)rows / h;  /* cells per pixel */
    const double aa = sx > sy ? sx : sy;                     /* edge softness, cells */

#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++) {
        double Y = (y + 0.5) * sy;
        int t0 = (int)floor(Y);
        for (int x = 0; x < w; x++) {
            double X = (x + 0.5) * sx, best = 0;
            for (int t = t0 - k; t <= t0 + k; t++) {
                int tw = sq__wrap(t, rows);
                int top = tw < e;                  /* the mirrored copy is on top */
                int r = top ? e - 1 - tw : tw - e; /* row of the automaton */
                double off = (ca->type == SQ_CA_TRIANGULAR && r % 2 == 1 ? 0.5 : 0.0) +
                             (top ? mirror_shift : 0.0);
                double cy = t + 0.5, dy = Y - cy;
                if (fabs(dy) > rad + aa)
                    continue;
                int c0 = (int)floor(X - off);
                for (int c = c0 - k; c <= c0 + k; c++) {
                    if (!data[(size_t)r * n + sq__wrap(c, n)])
                        continue;
                    double dx = X - (c + 0.5 + off);
                    double edge = rad - sqrt(dx * dx + dy * dy); /* > 0 inside */
                    double a = edge / aa + 0.5;
                    if (a > best)
                        best = a > 1 ? 1 : a;
                }
            }
            cov[(size_t)y * w + x] = (float)best;
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
    return sq__ca_coverage(p, in->cov, pat->w, pat->h, err);
}
