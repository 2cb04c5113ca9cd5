/* fitness/ internals (tests may use them). */
#ifndef SQUAMA_FITNESS_INTERNAL_H
#define SQUAMA_FITNESS_INTERNAL_H

#include "squama/fitness.h"

/* Builds the lookup tables of sq_fit_srgb_to_lab once (thread-safe). */
void sq__lab_init(void);

/* k-means in CIELAB: the k dominant colours of n Lab pixels (by decreasing weight). */
void sq__palette(const float *lab, int n, int k, float (*centre)[3], float *weight);

#endif
