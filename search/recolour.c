/* A candidate's colours moved toward a photo's palette (sq__recoloured,
 * search_internal.h): a fit's alternatives, each kind's best but the champion's, are
 * recoloured so once the champion is picked. */
#include <math.h>

#include "search_internal.h"
#include "squama/fitness.h"
#include "squama/search.h"

/* The colours a skin shows: its ground, its pattern's colours and its layers', and the
 * outline when it has one; a colour switched off (alpha 0) left out. Returns how many. */
enum { SHOWN_MAX = 2 + 4 * (SQ_MAX_PATTERN_LAYERS + 1) };
static int shown_colours(SqParams *p, double **list)
{
    int n = 0;
    double *pat[8];
    list[n++] = p->Background_Color;
    for (int l = 0; l <= p->Pattern_Layers.count; l++) {
        SqPatternSpec *spec = l == 0 ? &p->pattern : &p->Pattern_Layers.layer[l - 1].spec;
        sq__pattern_colours(spec, spec->Pattern_Type, pat);
        for (int i = 0; pat[i] && n < SHOWN_MAX - 1; i++)
            if (pat[i][3] > 0)
                list[n++] = pat[i];
    }
    if (p->Has_Outline)
        list[n++] = p->Outline_Color;
    return n;
}

/* The colour at lab moved: through gain and offset per axis, plus shift. */
static void move(double *rgb_param, const float lab[3], const double *gain, const double *offset, const double *shift)
{
    float moved[3], rgb[3];
    for (int a = 0; a < 3; a++)
        moved[a] = (float)(gain[a] * lab[a] + offset[a] + shift[a]);
    sq_fit_lab_to_srgb(moved, rgb);
    for (int a = 0; a < 3; a++)
        rgb_param[a] = fmin(fmax(rgb[a], 0), 1);
}

void sq__recoloured(const SqFeatures *target, const SqFitCandidate *c, const SqFeatures *feat, SqFitCandidate *out)
{
    enum { K = SQ_FIT_PALETTE };
    /* m[j]: how much of the candidate's dominant colour j the palette objective moved;
     * T[j]: onto what mean colour of the photo's */
    double flow[K][K], m[K] = {0}, T[K][3] = {{0}};
    sq_fit_palette_flow(target, feat, flow);
    for (int j = 0; j < K; j++) {
        for (int i = 0; i < K; i++) {
            m[j] += flow[i][j];
            for (int a = 0; a < 3; a++)
                T[j][a] += flow[i][j] * target->palette[i][a];
        }
        for (int a = 0; a < 3 && m[j] > 0; a++)
            T[j][a] /= m[j];
    }
    /* per axis, the weighted least-squares line from the dominant colours to their
     * matches (a gain of 1 where they spread over less than 2 units), and the mean shift */
    double gain[3] = {1, 1, 1}, offset[3] = {0, 0, 0}, mean_shift[3] = {0, 0, 0}, one[3] = {1, 1, 1},
           none[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++) {
        double sw = 0, sc = 0, st = 0, vc = 0, cov = 0;
        for (int j = 0; j < K; j++) {
            sw += m[j];
            sc += m[j] * feat->palette[j][a];
            st += m[j] * T[j][a];
        }
        if (!(sw > 0))
            continue;
        sc /= sw;
        st /= sw;
        for (int j = 0; j < K; j++) {
            vc += m[j] * (feat->palette[j][a] - sc) * (feat->palette[j][a] - sc) / sw;
            cov += m[j] * (feat->palette[j][a] - sc) * (T[j][a] - st) / sw;
        }
        gain[a] = vc > 4 ? fmin(fmax(cov / vc, 0.5), 2) : 1;
        offset[a] = st - gain[a] * sc;
        mean_shift[a] = st - sc;
    }
    for (int w = 0; w < SQ_RECOLOUR_WAYS; w++) {
        out[w] = *c;
        double *list[SHOWN_MAX];
        const int n = shown_colours(&out[w].params, list);
        for (int k = 0; k < n; k++) {
            float rgb[3] = {(float)list[k][0], (float)list[k][1], (float)list[k][2]}, lab[3];
            sq_fit_srgb_to_lab(rgb, lab);
            if (w == 0) { /* by the dominant colour nearest it */
                int near = -1;
                double dn = INFINITY, shift[3] = {0, 0, 0};
                for (int j = 0; j < K; j++) {
                    double d = 0;
                    for (int a = 0; a < 3; a++)
                        d += (lab[a] - feat->palette[j][a]) * (lab[a] - feat->palette[j][a]);
                    if (m[j] > 0 && d < dn) {
                        dn = d;
                        near = j;
                    }
                }
                for (int a = 0; a < 3 && near >= 0; a++)
                    shift[a] = T[near][a] - feat->palette[near][a];
                move(list[k], lab, one, none, shift);
            } else if (w == 1) {
                move(list[k], lab, gain, offset, none);
            } else {
                move(list[k], lab, one, mean_shift, none);
            }
        }
    }
}
