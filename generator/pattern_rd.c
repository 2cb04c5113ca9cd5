/* Complex pattern (thesis §4.2.5, left there as future work: §6.1): reaction-diffusion
 * after Turk (1991), simulated on a grid whose size sets the features' size and
 * upsampled smoothly to the texture, as Turk did, then coloured by ramps of the pattern
 * value: the first system's features in a cascade (RD_Color3), then the two thresholds
 * (RD_Color1, RD_Color2), the lower threshold painted first so the higher one shows as a
 * core inside it. */
#include <math.h>
#include <stdlib.h>

#include "gen_internal.h"

/* A smooth step from t - soft/2 to t + soft/2. Never sharper than about one texture pixel
 * at the grid's scale, so edges stay antialiased at any softness. */
static void ramp(const float *value, float *cov, size_t n, float t, float soft)
{
    const float lo = t - 0.5f * soft, inv = 1.0f / soft;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        const float x = sq__clamp01((value[i] - lo) * inv);
        cov[i] = x * x * (3.0f - 2.0f * x);
    }
}

SqStatus sq__pattern_rd(const SqParams *p, SqPattern *pat, SqError *err)
{
    const int w = pat->w, h = pat->h;
    const size_t n = (size_t)w * h;
    SqRdResult r;
    SqStatus st = sq__rd_run(p, w, h, &r, err);
    if (st != SQ_OK)
        return st;
    float *value = sq__falloc_raw(n);
    if (!value || sq__rd_upsample(r.value, r.nu * r.fine, r.nv * r.fine, value, w, h)) {
        st = sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the complex pattern");
        goto done;
    }
    const float soft = (float)fmax(p->RD_Softness, 0.02);
    if (r.first && p->RD_Color3[3] > 0) {
        SqLayer *l = sq__pattern_add(pat, SQ_LAYER_2D, p->RD_Color3, err);
        if (!l || sq__rd_upsample(r.first, r.nu, r.nv, l->cov, w, h)) {
            st = l ? sq_error_set(err, SQ_ERR_NOMEM, "render", "out of memory for the complex pattern")
                   : (err ? err->status : SQ_ERR_NOMEM);
            goto done;
        }
        ramp(l->cov, l->cov, n, 0.5f, soft);
    }
    const double *col[2] = {p->RD_Color1, p->RD_Color2};
    const double thr[2] = {p->RD_Threshold1, p->RD_Threshold2};
    const int first = thr[1] < thr[0]; /* the lower threshold is painted first */
    for (int k = 0; k < 2; k++) {
        const int i = k == 0 ? first : 1 - first;
        if (col[i][3] <= 0)
            continue;
        SqLayer *l = sq__pattern_add(pat, SQ_LAYER_2D, col[i], err);
        if (!l) {
            st = err ? err->status : SQ_ERR_NOMEM;
            goto done;
        }
        ramp(value, l->cov, n, (float)thr[i], soft);
    }
done:
    sq__ffree(value);
    sq__rd_result_free(&r);
    return st;
}
