/* The normal map from the height map (thesis §5): central differences with wrap-around,
 * scaled by Normal_Intensity per 1/256 of the texture width so the look does not
 * depend on the resolution. OpenGL convention (+Y up the texture) unless directx. */
#include <math.h>

#include "gen_internal.h"

void sq__normals(const float *height, int w, int h, double intensity, int directx, float *normal)
{
    const float k = (float)(intensity * w / 256.0) * 0.5f;
    const float ysign = directx ? -1.0f : 1.0f;
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++) {
        const float *up = height + (size_t)sq__wrap(y - 1, h) * w, *dn = height + (size_t)sq__wrap(y + 1, h) * w;
        const float *row = height + (size_t)y * w;
        float *out = normal + (size_t)y * w * 3;
        for (int x = 0; x < w; x++) {
            float gx = (row[x + 1 < w ? x + 1 : 0] - row[x > 0 ? x - 1 : w - 1]) * k;
            float gy = (dn[x] - up[x]) * k; /* image y grows downwards */
            float nx = -gx, ny = ysign * gy, inv = 1.0f / sqrtf(nx * nx + ny * ny + 1.0f);
            out[3 * x] = 0.5f + 0.5f * nx * inv;
            out[3 * x + 1] = 0.5f + 0.5f * ny * inv;
            out[3 * x + 2] = 0.5f + 0.5f * inv;
        }
    }
}
