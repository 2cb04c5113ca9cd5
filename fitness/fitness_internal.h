/* fitness/ internals (tests may use them). */
#ifndef SQUAMA_FITNESS_INTERNAL_H
#define SQUAMA_FITNESS_INTERNAL_H

#include <math.h>

#include "squama/fitness.h"

/* Builds the lookup tables of sq_fit_srgb_to_lab once (thread-safe). */
void sq__lab_init(void);

/* sRGB code value <-> linear through those tables (call sq__lab_init first); the inverse
 * is indexed by the square root, for precision in the shadows. Clamped to [0, 1]. */
enum { SQ_LIN_N = 4096 };
extern float sq__lin_lut[SQ_LIN_N + 2], sq__srgb_lut[SQ_LIN_N + 2];

static inline float sq__srgb_to_linear_lut(float v)
{
    int i = (int)(v * SQ_LIN_N + 0.5f);
    return sq__lin_lut[i < 0 ? 0 : (i > SQ_LIN_N ? SQ_LIN_N : i)];
}

static inline float sq__linear_to_srgb_lut(float v)
{
    int i = (int)(sqrtf(v > 0 ? v : 0) * SQ_LIN_N + 0.5f);
    return sq__srgb_lut[i > SQ_LIN_N ? SQ_LIN_N : i];
}

/* k-means in CIELAB: the k dominant colours of n Lab pixels (by decreasing weight). */
void sq__palette(const float *lab, int n, int k, float (*centre)[3], float *weight);

/* Divides the large-scale light out of a strip (SQ_FIT_STRIP_W wide, sRGB RGB), in place;
 * valid (1 channel, the same size) marks the pixels that show the body, NULL for all. */
void sq__fit_normalise_light(SqImage *strip, const SqImage *valid);

#endif
