/* A preset against a target: render, cut strips at every view scale of the grid, keep
 * the scale that fits best (a view parameter, not part of the preset). */
#include <math.h>
#include <string.h>

#include "fitness_internal.h"


double sq_fit_scale_at(int i)
{
    return 0.25 * pow(2.0, i / 3.0);
}

SqStatus sq_fit_score(const SqFeatures *target, const SqParams *p, int size, double band_centre,
                      double fixed_view, SqTextures *maps, double *objectives, double *view_scale,
                      SqImage *best_strip, SqError *err)
{
    if (best_strip)
        memset(best_strip, 0, sizeof *best_strip);
    if (fixed_view < 0 || !isfinite(fixed_view))
        return sq_error_set(err, SQ_ERR_INVALID, "score", "view scale %g out of range", fixed_view);
    SqTextures own = {0};
    if (!maps)
        maps = &own;
    SqGenOptions go = sq_gen_options_default(size);
    SqStatus st = sq_gen_render_into(p, &go, maps, err);
    double best = INFINITY;
    const int n = fixed_view > 0 ? 1 : SQ_FIT_SCALES;
    for (int i = 0; st == SQ_OK && i < n; i++) {
        const double vs = fixed_view > 0 ? fixed_view : sq_fit_scale_at(i);
        SqImage strip;
        SqFeatures f;
        double o[SQ_OBJ_COUNT];
        st = sq_fit_candidate_strip(&maps->basecolor, &maps->normal, &maps->roughness, &target->light, vs, band_centre, SQ_FIT_CANDIDATE_ROWS,
                                    &strip, err);
        if (st != SQ_OK)
            break;
        st = sq_fit_features_blurred(&strip, NULL, target->blur, &f, err);
        if (st != SQ_OK) {
            sq_image_free(&strip);
            break;
        }
        sq_fit_objectives(target, &f, o);
        double key = o[SQ_OBJ_SHAPE] + o[SQ_OBJ_ALONG];
        if (i == 0 || key < best || isnan(best)) {
            best = key;
            memcpy(objectives, o, sizeof o);
            *view_scale = vs;
            if (best_strip) {
                sq_image_free(best_strip);
                *best_strip = strip;
                strip.px = NULL;
            }
        }
        sq_image_free(&strip);
    }
    sq_gen_textures_free(&own);
    return st;
}
