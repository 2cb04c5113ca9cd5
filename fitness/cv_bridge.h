/* The OpenCV calls of photo preparation, behind a C interface (cv_bridge.cpp). Every
 * function returns 0, or -1 when OpenCV failed or memory ran out. Masks are 8-bit, 0 or
 * 255, row-major w x h. */
#ifndef SQUAMA_CV_BRIDGE_H
#define SQUAMA_CV_BRIDGE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Resizes an interleaved float image (area averaging when shrinking). */
int sq__cv_resize(const float *src, int sw, int sh, int ch, float *dst, int dw, int dh);

/* Foreground by GrabCut, started from a rectangle inset by `inset` of each side. */
int sq__cv_grabcut(const float *rgb, int w, int h, double inset, uint8_t *mask);

/* Foreground by GrabCut started from the image's saliency (OpenCV's fine-grained static
 * saliency): the most salient sixth probably the object, the least salient half not. */
int sq__cv_grabcut_salient(const float *rgb, int w, int h, uint8_t *mask);

/* A mask with the backdrop's colours taken out: the image's colours clustered (k-means in
 * CIELAB, 8 clusters), and the mask's pixels of every cluster that lies mostly outside the
 * mask set to 0 (the ground that a loop of the body encloses, which GrabCut takes for
 * body); what is left is closed again, within the mask, with a disc 1.5 times the 95th
 * percentile of its pixels' distance to its edge (at most an eighth of the image's longer
 * side), over the body's colours that went with the backdrop's (black rings on dark
 * ground). Returns 0, or -1 on failure (the mask then undefined). */
int sq__cv_backdrop_out(const float *rgb, int w, int h, uint8_t *mask);

/* Which of a band is body, by GrabCut: the core certainly body, the rest of the band
 * probably, `reach` pixels round the band probably not, everything further certainly
 * not; run on the part of the image that holds the band and its surround. mask: 255
 * where the band is found body, else 0. Returns 0, or -1 on failure (mask untouched). */
int sq__cv_grabcut_band(const float *rgb, int w, int h, const uint8_t *band, const uint8_t *core, int reach,
                        uint8_t *mask);

/* Opening and closing with a disc of `radius`, the largest connected component kept,
 * its holes of at most max_hole pixels filled. Returns the number of components found
 * before keeping one (>= 0). */
int sq__cv_clean_mask(uint8_t *mask, int w, int h, int radius, double max_hole);

/* Euclidean distance of every mask pixel to the nearest background pixel. */
int sq__cv_distance(const uint8_t *mask, int w, int h, float *dist);

#ifdef __cplusplus
}
#endif

#endif
