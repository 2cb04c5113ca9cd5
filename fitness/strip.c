/* A candidate's strip: the dorsal band of its base colour map in surface units. */
#include <math.h>
#include <string.h>

#include "fitness_internal.h"

/* The key light in the tangent frame (x across, y up the texture, z out). */
static const float KEY[3] = {-0.35f, 0.55f, 0.76f};

enum { SUB_MAX = 4 }; /* sub-samples per strip pixel and direction, at most */

/* The light at strip row j (see SqLight); L and the half vector H towards a camera
 * straight above, both unit. */
static void light_at(const SqLight *light, int j, float L[3], float H[3])
{
    float l[3] = {KEY[0], KEY[1], KEY[2]};
    int key = 1;
    if (light && light->rows > 0) {
        key = 0;
        const int m = light->rows < SQ_FIT_LIGHT_ROWS ? light->rows : SQ_FIT_LIGHT_ROWS;
        float x = (float)j / SQ_FIT_LIGHT_STEP;
        if (m > 1) { /* back and forth: x in [0, m - 1] */
            x = fmodf(x, 2.0f * (m - 1));
            x = x > m - 1 ? 2.0f * (m - 1) - x : x;
        } else
            x = 0;
        const int a = (int)x, b = a + 1 < m ? a + 1 : a;
        const float t = x - (float)a;
        for (int k = 0; k < 3; k++)
            l[k] = light->dir[a][k] + (light->dir[b][k] - light->dir[a][k]) * t;
    }
    float ll = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if (!(ll > 1e-6f) || !isfinite(ll)) { /* a broken light: the key's */
        memcpy(l, KEY, sizeof l);
        ll = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
        key = 1;
    }
    for (int k = 0; k < 3; k++)
        L[k] = l[k] / ll;
    /* the half vector of the unit light; the key's of its 1.001-long self, as it always was */
    const float *h = key ? l : L;
    H[0] = h[0], H[1] = h[1], H[2] = h[2] + 1.0f;
    const float hl = sqrtf(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= hl;
}

SqStatus sq_fit_candidate_strip(const SqImage *basecolor, const SqImage *normal,
                                const SqImage *roughness, const SqLight *light, double view_scale,
                                double band_centre, int length, SqImage *strip, SqError *err)
{
    if (!basecolor || !basecolor->px || basecolor->channels < 3)
        return sq_error_set(err, SQ_ERR_INVALID, "strip", "no base colour map");
    if (!(view_scale > 0) || !isfinite(view_scale) || length < SQ_FIT_STRIP_W)
        return sq_error_set(err, SQ_ERR_INVALID, "strip",
                            "view scale %g or strip length %d out of range", view_scale, length);
    if (normal && (!normal->px || normal->width != basecolor->width ||
                   normal->height != basecolor->height || normal->channels < 3))
        return sq_error_set(err, SQ_ERR_INVALID, "strip", "the normal map does not match the base colour");
    if (!normal != !roughness || (roughness && (!roughness->px || roughness->width != basecolor->width ||
                                                roughness->height != basecolor->height)))
        return sq_error_set(err, SQ_ERR_INVALID, "strip",
                            "the roughness map does not match the base colour, or comes without the normal map");
    if (sq_image_alloc(strip, SQ_FIT_STRIP_W, length, 3, SQ_SPACE_SRGB) != 0)
        return sq_error_set(err, SQ_ERR_NOMEM, "strip", "out of memory for a strip");
    const int w = basecolor->width, h = basecolor->height, ch = basecolor->channels;
    const double du = SQ_FIT_BAND_WIDTH / SQ_FIT_STRIP_W, dv = du / view_scale;
    const double u0 = band_centre - SQ_FIT_BAND_WIDTH / 2;
    /* A strip pixel covers du*w by dv*h texels: where that is more than one, it is the
     * mean of a grid of samples (as a camera pixel averages the skin it sees), so a strip
     * looks about the same from a 256 or a 1024 texture, and fine scales do not alias. At
     * most SUB_MAX samples a direction: a 1024 texture at the smallest view scales (a
     * footprint of 20 texels along) is still undersampled, which fits never ask for. */
    const int sx_n = (int)fmax(1, fmin(SUB_MAX, ceil(du * w - 1e-6)));
    const int sy_n = (int)fmax(1, fmin(SUB_MAX, ceil(dv * h - 1e-6)));
    const float inv_n = 1.0f / (float)(sx_n * sy_n);
    /* columns: fixed for every row */
    int xs[SQ_FIT_STRIP_W * SUB_MAX][2];
    float txs[SQ_FIT_STRIP_W * SUB_MAX];
    for (int i = 0; i < SQ_FIT_STRIP_W * sx_n; i++) {
        double x = (u0 + (i + 0.5) * du / sx_n) * w - 0.5, fx = floor(x);
        long xi = (long)fx % w;
        xs[i][0] = (int)(xi < 0 ? xi + w : xi);
        xs[i][1] = xs[i][0] + 1 == w ? 0 : xs[i][0] + 1;
        txs[i] = (float)(x - fx);
    }
    /* the cylinder: column i looks at angle theta (the photo's strip is even in theta) */
    float cyl[SQ_FIT_STRIP_W][2];
    for (int i = 0; i < SQ_FIT_STRIP_W; i++)
        sq__fit_column_angle(i, cyl[i]);
    /* The smooth body's shading (the cylinder without the relief) changes along the strip
     * as the light turns. Each row's departure of that shading from its mean over the
     * rows is divided out here, exactly (the highlights with it), as the photo's strip has
     * its own divided out row by row before its normalisation (divide_turning_light,
     * prep.c); the light normalisation alone, smoothed over a strip width, would leave
     * dark and bright blocks where the pieces of the photo's light join (a 60-degree swing
     * of the shading's tilt over 24 rows, say). The mean across profile stays for the
     * normalisation below, as in the photo. A light that does not turn (the key light, or
     * one row) leaves the strip as it was, bit for bit. */
    const int turns = normal && light && light->rows > 1;
    float mean_shade[SQ_FIT_STRIP_W];
    if (turns) {
        double sum[SQ_FIT_STRIP_W] = {0};
        for (int j = 0; j < length; j++) {
            float L[3], H[3];
            light_at(light, j, L, H);
            for (int i = 0; i < SQ_FIT_STRIP_W; i++)
                sum[i] += sq__fit_smooth_shade(cyl[i], L);
        }
        for (int i = 0; i < SQ_FIT_STRIP_W; i++)
            mean_shade[i] = (float)(sum[i] / length);
    }
    sq__lab_init();
    for (int j = 0; j < length; j++) {
        float L[3], H[3], acc[SQ_FIT_STRIP_W][3];
        light_at(light, j, L, H);
        memset(acc, 0, sizeof acc);
        for (int sy = 0; sy < sy_n; sy++) {
            double y = ((j + (sy + 0.5) / sy_n) * dv) * h - 0.5, fy = floor(y);
            long yi = (long)fy % h;
            int y0 = (int)(yi < 0 ? yi + h : yi), y1 = y0 + 1 == h ? 0 : y0 + 1;
            float ty = (float)(y - fy);
            const float *r0 = basecolor->px + (size_t)y0 * w * ch, *r1 = basecolor->px + (size_t)y1 * w * ch;
            for (int ii = 0; ii < SQ_FIT_STRIP_W * sx_n; ii++) {
                const int i = ii / sx_n;
                const float *a = r0 + (size_t)xs[ii][0] * ch, *b = r0 + (size_t)xs[ii][1] * ch;
                const float *c = r1 + (size_t)xs[ii][0] * ch, *d = r1 + (size_t)xs[ii][1] * ch;
                const float tx = txs[ii];
                float o[3];
                for (int k = 0; k < 3; k++) {
                    float top = a[k] + (b[k] - a[k]) * tx, bot = c[k] + (d[k] - c[k]) * tx;
                    o[k] = top + (bot - top) * ty;
                }
                if (normal) { /* the glossy cylinder of squama photo, summed in linear light */
                    float n[3], t[3], rr = 0;
                    const int nc = normal->channels, rc = roughness->channels;
                    const size_t q[4] = {(size_t)y0 * w + xs[ii][0], (size_t)y0 * w + xs[ii][1],
                                         (size_t)y1 * w + xs[ii][0], (size_t)y1 * w + xs[ii][1]};
                    const float wq[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
                    t[0] = t[1] = t[2] = 0;
                    for (int k = 0; k < 4; k++) {
                        for (int c2 = 0; c2 < 3; c2++)
                            t[c2] += wq[k] * (2.0f * normal->px[q[k] * nc + c2] - 1.0f);
                        rr += wq[k] * roughness->px[q[k] * rc];
                    }
                    /* tangent frame at the column's angle: across, up the texture, out (as KEY) */
                    const float sn = cyl[i][0], cs = cyl[i][1];
                    n[0] = t[0] * cs + t[2] * sn;
                    n[1] = t[1];
                    n[2] = -t[0] * sn + t[2] * cs;
                    float nl = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) + 1e-6f;
                    float diff = (n[0] * L[0] + n[1] * L[1] + n[2] * L[2]) / nl;
                    float nh = (n[0] * H[0] + n[1] * H[1] + n[2] * H[2]) / nl;
                    float g = 1.0f - rr, spec = 0;
                    if (nh > 0.8f && g > 0) /* below, at most 0.01 for the roughest skins */
                        spec = 0.35f * g * g * powf(nh, 2.0f + 300.0f * g * g * g);
                    float shade = sq__fit_shade(diff, cs);
                    for (int k = 0; k < 3; k++)
                        acc[i][k] += sq__srgb_to_linear_lut(o[k]) * shade + spec;
                } else { /* base colour only: averaged in linear light too */
                    for (int k = 0; k < 3; k++)
                        acc[i][k] += sq__srgb_to_linear_lut(o[k]);
                }
            }
        }
        for (int i = 0; i < SQ_FIT_STRIP_W; i++) {
            float *o = sq_image_at(strip, i, j);
            const float k0 = turns ? mean_shade[i] / sq__fit_smooth_shade(cyl[i], L) : 1.0f;
            for (int k = 0; k < 3; k++)
                o[k] = sq__linear_to_srgb_lut(acc[i][k] * inv_n * k0);
        }
    }
    sq__fit_normalise_light(strip, NULL); /* as the photo's strip */
    return SQ_OK;
}
