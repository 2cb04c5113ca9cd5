/* fitness/ internals (tests may use them). */
#ifndef SQUAMA_FITNESS_INTERNAL_H
#define SQUAMA_FITNESS_INTERNAL_H

#include <math.h>
#include <stdint.h>

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

/* Zhang-Suen thinning of mask's nonzero pixels to a one-pixel skeleton (255) in skel (prep.c).
 * Returns 0, or -1 out of memory. */
int sq__thin(const uint8_t *mask, int w, int h, uint8_t *skel);

/* k-means in CIELAB: the k dominant colours of n Lab pixels (by decreasing weight). */
void sq__palette(const float *lab, int n, int k, float (*centre)[3], float *weight);

/* The diffuse shading of squama photo's body: ambient, Lambert, and a darkening towards
 * the sides (cs: the cosine of the column's angle round the body). */
static inline float sq__fit_shade(float diff, float cs)
{
    return (0.30f + 0.85f * (diff > 0 ? diff : 0)) * (0.75f + 0.25f * cs);
}

/* Strip column i's angle round the body, as (sin, cos): the band of SQ_FIT_BAND_WIDTH of
 * the circumference centred on the top. */
static inline void sq__fit_column_angle(int i, float cyl[2])
{
    const double th = 3.14159265358979323846 * SQ_FIT_BAND_WIDTH * (2.0 * (i + 0.5) / SQ_FIT_STRIP_W - 1.0);
    cyl[0] = (float)sin(th);
    cyl[1] = (float)cos(th);
}

/* The shading of the smooth body (the cylinder's own normal) in a column at angle
 * (sin, cos) = cyl, under the unit light L (x across, y up the texture, z out). */
static inline float sq__fit_smooth_shade(const float cyl[2], const float L[3])
{
    return sq__fit_shade(cyl[0] * L[0] + cyl[1] * L[2], cyl[1]);
}

/* Divides the large-scale light out of a strip (SQ_FIT_STRIP_W wide, sRGB RGB), in place;
 * valid (1 channel, the same size) marks the pixels that show the body, NULL for all. */
void sq__fit_normalise_light(SqImage *strip, const SqImage *valid);

#endif
