/* The normal map from the height map (thesis §5): central differences with wrap-around,
 * scaled by Normal_Intensity per 1/256 of the texture width so the look does not
 * depend on the resolution. OpenGL convention (+Y up the texture) unless directx. */
#include <math.h>

#include "gen_internal.h"

static inline void normal_at(float gx, float gy, float ysign, float *out)
{
    float nx = -gx, ny = ysign * gy, inv = 1.0f / sqrtf(nx * nx + ny * ny + 1.0f);
    out[0] = 0.5f + 0.5f * nx * inv;
    out[1] = 0.5f + 0.5f * ny * inv;
    out[2] = 0.5f + 0.5f * inv;
}

void sq__normals(const float *height, int w, int h, double intensity, int directx, float *normal)
{
    const float k = (float)(intensity * w / 256.0) * 0.5f;
    const float ysign = directx ? -1.0f : 1.0f;
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++) {
        const float *up = height + (size_t)sq__wrap(y - 1, h) * w, *dn = height + (size_t)sq__wrap(y + 1, h) * w;
        const float *row = height + (size_t)y * w;
        float *out = normal + (size_t)y * w * 3;
        /* the two edge columns wrap; the interior is a plain loop the compiler vectorises */
        normal_at((row[1 % w] - row[w - 1]) * k, (dn[0] - up[0]) * k, ysign, out);
        for (int x = 1; x < w - 1; x++)
            normal_at((row[x + 1] - row[x - 1]) * k, (dn[x] - up[x]) * k, ysign, out + 3 * x);
        normal_at((row[0] - row[w - 2]) * k, (dn[w - 1] - up[w - 1]) * k, ysign, out + 3 * (w - 1));
    }
}
