/* squama — in-memory images: float pixels, 1 to 4 interleaved channels.
 *
 * The colour encoding travels with the pixels: SQ_SPACE_SRGB for gamma-encoded colour
 * (photos, base colour maps, preset colours), SQ_SPACE_LINEAR for linear colour (EXR),
 * SQ_SPACE_DATA for values that are not colour (height, roughness, normals, masks) and
 * are never converted. Header-only so every module can share the type.
 */
#ifndef SQUAMA_IMAGE_H
#define SQUAMA_IMAGE_H


#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum SqColorSpace {
    SQ_SPACE_SRGB = 0,
    SQ_SPACE_LINEAR = 1,
    SQ_SPACE_DATA = 2
} SqColorSpace;

typedef struct SqImage {
    int width, height, channels; /* channels 1..4 */
    SqColorSpace space;
    float *px; /* width * height * channels, row-major, top row first */
} SqImage;

/* Allocates width x height x channels pixels set to 0; returns 0 on success, -1 on bad
 * dimensions or when out of memory (img is then zeroed). */
static inline int sq_image_alloc(SqImage *img, int width, int height, int channels,
                                 SqColorSpace space)
{
    memset(img, 0, sizeof *img);
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
        return -1;
    size_t n = (size_t)width * (size_t)height;
    if (n > SIZE_MAX / sizeof(float) / (size_t)channels)
        return -1;
    img->px = (float *)calloc(n * (size_t)channels, sizeof(float));
    if (!img->px)
        return -1;
    img->width = width;
    img->height = height;
    img->channels = channels;
    img->space = space;
    return 0;
}

/* Frees the pixels and zeroes img; NULL-safe and safe on a zeroed image. */
static inline void sq_image_free(SqImage *img)
{
    if (img) {
        free(img->px);
        memset(img, 0, sizeof *img);
    }
}

/* Pointer to pixel (x, y). */
static inline float *sq_image_at(const SqImage *img, int x, int y)
{
    return img->px + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)img->channels;
}

#ifdef __cplusplus
}
#endif

#endif /* SQUAMA_IMAGE_H */
