/* Strip features and the objectives between two feature sets (see squama/fitness.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_fft_real.h>
#include <gsl/gsl_wavelet2d.h>

#include "fitness_internal.h"

enum { NB = SQ_FIT_HIST_BINS, W = SQ_FIT_STRIP_W, MAX_PALETTE_PX = 1024 };
static const float A_RANGE = 80.0f; /* a*, b* histogram span: [-80, 80] */
/* Spectrum bands, in cycles per strip width: up to periods of 8 strip pixels. Finer
 * detail is the scales' texture, noise and compression, which no candidate models. */
static const double F_LO = 0.25, F_HI = 8.0;

static inline void hist_add(float *hist, const float lab[3])
{
    int i = (int)(lab[0] * (NB / 100.0f));
    int j = (int)((lab[1] + A_RANGE) * (NB / (2 * A_RANGE)));
    int k = (int)((lab[2] + A_RANGE) * (NB / (2 * A_RANGE)));
    i = i < 0 ? 0 : (i >= NB ? NB - 1 : i);
    j = j < 0 ? 0 : (j >= NB ? NB - 1 : j);
    k = k < 0 ? 0 : (k >= NB ? NB - 1 : k);
    hist[(i * NB + j) * NB + k] += 1.0f;
}

/* Smooths the histogram with [1 2 1]/4 along each axis (clamped at the ends), so that a
 * colour near a bin edge counts in both bins: soft binning at a fraction of its cost. */
static void hist_smooth(float *hist)
{
    float tmp[NB * NB * NB];
    for (int axis = 0; axis < 3; axis++) {
        int stride = axis == 0 ? NB * NB : (axis == 1 ? NB : 1);
        for (int idx = 0; idx < NB * NB * NB; idx++) {
            int pos = (idx / stride) % NB;
            float prev = pos > 0 ? hist[idx - stride] : hist[idx];
            float next = pos < NB - 1 ? hist[idx + stride] : hist[idx];
            tmp[idx] = 0.25f * prev + 0.5f * hist[idx] + 0.25f * next;
        }
        memcpy(hist, tmp, sizeof tmp);
    }
}

/* Where frequency f (cycles per strip width) falls among the bands: its power is shared
 * between the two bands whose centres (in log frequency) enclose it, *lo getting 1 - *t and
 * *lo + 1 getting *t, so a pattern whose period moves a little moves its power a little
 * instead of jumping from one band to the next. Returns 0 outside F_LO..F_HI. */
static int band_of(double f, int *lo, float *t)
{
    if (f < F_LO || f >= F_HI)
        return 0;
    const double p = log(f / F_LO) / log(F_HI / F_LO) * SQ_FIT_BANDS - 0.5;
    int b = (int)floor(p);
    double frac = p - b;
    if (b < 0) { /* below the first centre, or above the last: all in the end band */
        b = 0;
        frac = 0;
    } else if (b >= SQ_FIT_BANDS - 1) {
        b = SQ_FIT_BANDS - 1;
        frac = 0;
    }
    *lo = b;
    *t = (float)frac;
    return 1;
}

/* Power spectrum of each of `count` lines of n samples (stride between samples `step`,
 * between lines `next`), Hann-windowed, accumulated into bands by cycles per strip
 * width. Returns the total power per sample. */
static double spectrum(const float *data, int n, int step, int count, int next, float *bands)
{
    if (n < 4)
        return 0;
    double *x = malloc(sizeof(double) * (size_t)n), *hann = malloc(sizeof(double) * (size_t)n);
    int *band = malloc(sizeof(int) * (size_t)n);
    float *share = malloc(sizeof(float) * (size_t)n);
    gsl_fft_real_wavetable *wt = gsl_fft_real_wavetable_alloc((size_t)n);
    gsl_fft_real_workspace *ws = gsl_fft_real_workspace_alloc((size_t)n);
    double total = 0;
    if (x && hann && band && share && wt && ws) {
        for (int i = 0; i < n; i++) {
            hann[i] = 0.5 - 0.5 * cos(2 * M_PI * (i + 0.5) / n);
            if (!band_of((double)i / n * W, &band[i], &share[i]))
                band[i] = -1;
        }
        for (int line = 0; line < count; line++) {
            const float *p = data + (size_t)line * next;
            double mean = 0;
            for (int i = 0; i < n; i++)
                mean += p[(size_t)i * step];
            mean /= n;
            for (int i = 0; i < n; i++)
                x[i] = (p[(size_t)i * step] - mean) * hann[i];
            gsl_fft_real_transform(x, 1, (size_t)n, wt, ws);
            /* halfcomplex: x[0] = DC, then (re, im) pairs */
            for (int k = 1; k <= (n - 1) / 2; k++) {
                double pw = x[2 * k - 1] * x[2 * k - 1] + x[2 * k] * x[2 * k];
                total += pw;
                if (band[k] >= 0) {
                    bands[band[k]] += (float)pw * (1 - share[k]);
                    if (share[k] > 0)
                        bands[band[k] + 1] += (float)pw * share[k];
                }
            }
        }
    }
    free(x);
    free(hann);
    free(band);
    free(share);
    gsl_fft_real_wavetable_free(wt);
    gsl_fft_real_workspace_free(ws);
    /* Parseval with the Hann window's mean square (3/8) */
    return total / ((double)n * n * count * 0.375 / 2);
}

static void normalise(float *v, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++)
        s += v[i];
    for (int i = 0; i < n; i++)
        v[i] = s > 0 ? (float)(v[i] / s) : 0.0f;
}

/* Below this share of the energy a sub-band holds only what neither side models: sensor
 * noise, the fine texture of scales. */
static const double WAVELET_FLOOR = 3e-3; /* of the total energy */
/* Every sub-band also holds this much energy per coefficient, (L/100)^2: the grain of a
 * camera's noise (sigma 0.015). A plain skin's few patterns then weigh as little as they
 * are visible, instead of its noise deciding the shape of its energy. */
static const double WAVELET_GRAIN = 2.25e-4;

/* Mean energy per level and orientation of the 2-D Daubechies-4 wavelet transform of
 * 64 x 64 windows along the strip (half-overlapping), as log10 above a floor. */
static int wavelet_energies(const float *L, int len, float out[SQ_FIT_LEVELS][3])
{
    gsl_wavelet *wv = gsl_wavelet_alloc(gsl_wavelet_daubechies, 4);
    gsl_wavelet_workspace *ws = gsl_wavelet_workspace_alloc(W);
    double *win = malloc(sizeof(double) * W * W);
    double e[SQ_FIT_LEVELS][3] = {{0}};
    int windows = 0, ok = wv && ws && win;
    for (int y0 = 0; ok && y0 + W <= len; y0 += W / 2) {
        for (int i = 0; i < W * W; i++)
            win[i] = L[(size_t)y0 * W + i];
        if (gsl_wavelet2d_nstransform_forward(wv, win, W, W, W, ws) != GSL_SUCCESS) {
            ok = 0;
            break;
        }
        /* non-standard layout: detail quadrants of side s at (0,s), (s,0), (s,s); the
         * finest level (details of 2 pixels: the scales' texture, noise) is left out */
        for (int lvl = 0, s = W / 4; lvl < SQ_FIT_LEVELS; lvl++, s /= 2) {
            double q[3] = {0, 0, 0};
            for (int r = 0; r < s; r++)
                for (int c = 0; c < s; c++) {
                    double h = win[r * W + s + c], v = win[(s + r) * W + c], d = win[(s + r) * W + s + c];
                    q[0] += h * h;
                    q[1] += v * v;
                    q[2] += d * d;
                }
            for (int k = 0; k < 3; k++)
                e[lvl][k] += q[k] / ((double)s * s);
        }
        windows++;
    }
    /* the energies' distribution over levels and orientations (the pattern's contrast is
     * the colour objectives' business), on a log scale above a floor */
    double total = 0;
    for (int lvl = 0; lvl < SQ_FIT_LEVELS; lvl++)
        for (int k = 0; k < 3; k++)
            total += (windows ? e[lvl][k] / windows : 0) + WAVELET_GRAIN;
    for (int lvl = 0; lvl < SQ_FIT_LEVELS; lvl++)
        for (int k = 0; k < 3; k++)
            out[lvl][k] = (float)log10(WAVELET_FLOOR + ((windows ? e[lvl][k] / windows : 0) + WAVELET_GRAIN) /
                                                           (total + 12 * WAVELET_FLOOR));
    gsl_wavelet_free(wv);
    gsl_wavelet_workspace_free(ws);
    free(win);
    return ok ? 0 : -1;
}

/* Both sides are seen at one common resolution: a Gaussian of BLUR_SIGMA strip pixels over
 * the CIELAB strip (normalised by the valid pixels, so the backdrop does not bleed in). A
 * photo's strip is blurred by its lens, its JPEG and its few pixels across a body; a
 * candidate's is sharp. On top of a common blur the difference between the two shrinks;
 * what the photo's few pixels add is known (SqFeatures.blur), and a candidate is blurred
 * that much more. */
static const double BLUR_SIGMA = 1.0;

enum { BLUR_R_MAX = 16 }; /* taps each side, at most: 3 sigma of 5.3 strip pixels */

/* The common blur's two passes over the strip's rows of W pixels (4 floats a pixel: the
 * weighted L*, a*, b* and the weight), each output the sum over the 2 r + 1 taps of k, in
 * the taps' order, clamped at the ends. The taps are the outer loop and a row's floats the
 * inner one, so that the sums run side by side in SIMD lanes, each summed in the same
 * order as one pixel's taps one after another. */

/* Across: each of len rows along its W pixels, clamped at the band's edges. */
static void blur_across(const float *restrict src, float *restrict dst, int len, const float *k, int r)
{
    float ext[4 * (W + 2 * BLUR_R_MAX)]; /* the row, its end pixels repeated r times */
    for (int y = 0; y < len; y++) {
        const float *row = src + (size_t)4 * W * y;
        for (int i = -r; i < W + r; i++) {
            const int j = i < 0 ? 0 : i >= W ? W - 1 : i;
            memcpy(ext + 4 * (i + r), row + 4 * j, 4 * sizeof(float));
        }
        float *restrict out = dst + (size_t)4 * W * y;
        for (int q = 0; q < 4 * W; q++)
            out[q] = 0;
        for (int d = 0; d <= 2 * r; d++) {
            const float w = k[d], *p = ext + 4 * d;
            for (int q = 0; q < 4 * W; q++)
                out[q] += w * p[q];
        }
    }
}

/* Along: each of the W columns along its len rows, clamped at the strip's ends. */
static void blur_along(const float *restrict src, float *restrict dst, int len, const float *k, int r)
{
    for (int y = 0; y < len; y++) {
        float *restrict out = dst + (size_t)4 * W * y;
        for (int q = 0; q < 4 * W; q++)
            out[q] = 0;
        for (int d = -r; d <= r; d++) {
            const int j = y + d < 0 ? 0 : y + d >= len ? len - 1 : y + d;
            const float w = k[d + r], *p = src + (size_t)4 * W * j;
            for (int q = 0; q < 4 * W; q++)
                out[q] += w * p[q];
        }
    }
}

static int common_blur(float *lab, const SqImage *valid, int len, double sigma)
{
    float k[2 * BLUR_R_MAX + 1], ks = 0;
    const int r = (int)fmin(BLUR_R_MAX, ceil(3 * sigma));
    for (int i = -r; i <= r; i++)
        ks += k[i + r] = (float)exp(-0.5 * i * i / (sigma * sigma));
    for (int i = 0; i <= 2 * r; i++)
        k[i] /= ks;
    const size_t n = (size_t)W * len;
    float *a = malloc(sizeof(float) * 4 * n), *b = malloc(sizeof(float) * 4 * n);
    if (!a || !b || len < 1) {
        free(a);
        free(b);
        return -1;
    }
    for (size_t i = 0; i < n; i++) { /* weighted values and the weight */
        float wv = !valid || valid->px[i] > 0.5f ? 1.0f : 0.0f;
        a[4 * i] = lab[3 * i] * wv;
        a[4 * i + 1] = lab[3 * i + 1] * wv;
        a[4 * i + 2] = lab[3 * i + 2] * wv;
        a[4 * i + 3] = wv;
    }
    blur_across(a, b, len, k, r);
    blur_along(b, a, len, k, r);
    for (size_t i = 0; i < n; i++)
        if (a[4 * i + 3] > 1e-3f && (!valid || valid->px[i] > 0.5f))
            for (int c = 0; c < 3; c++)
                lab[3 * i + c] = a[4 * i + c] / a[4 * i + 3];
    free(a);
    free(b);
    return 0;
}

SqStatus sq_fit_features(const SqImage *strip, const SqImage *valid, SqFeatures *f, SqError *err)
{
    return sq_fit_features_blurred(strip, valid, 0, f, err);
}

SqStatus sq_fit_features_blurred(const SqImage *strip, const SqImage *valid, double blur, SqFeatures *f,
                                 SqError *err)
{
    memset(f, 0, sizeof *f);
    if (!(blur >= 0) || blur > SQ_FIT_BLUR_MAX)
        return sq_error_set(err, SQ_ERR_INVALID, "strip", "blur %g is outside 0 to %g strip pixels", blur,
                            (double)SQ_FIT_BLUR_MAX);
    if (!strip || !strip->px || strip->width != W || strip->height < W || strip->channels < 3)
        return sq_error_set(err, SQ_ERR_INVALID, "strip",
                            "a strip must be %d pixels wide, at least %d long, with colour", W, W);
    if (valid && (valid->width != W || valid->height != strip->height || valid->channels != 1))
        return sq_error_set(err, SQ_ERR_INVALID, "strip", "the strip's mask has another size");
    gsl_set_error_handler_off();
    sq__lab_init();
    const int len = strip->height, n = W * len;
    float *lab = malloc(sizeof(float) * 3 * (size_t)n), *L = malloc(sizeof(float) * (size_t)n);
    float *sel = malloc(sizeof(float) * 3 * MAX_PALETTE_PX);
    if (!lab || !L || !sel) {
        free(lab);
        free(L);
        free(sel);
        return sq_error_set(err, SQ_ERR_NOMEM, "strip", "out of memory for features");
    }
    int count = 0;
    double lsum = 0;
    for (int i = 0; i < n; i++)
        sq_fit_srgb_to_lab(strip->px + (size_t)i * strip->channels, lab + 3 * i);
    if (common_blur(lab, valid, len, sqrt(BLUR_SIGMA * BLUR_SIGMA + blur * blur)) != 0) {
        free(lab);
        free(L);
        free(sel);
        return sq_error_set(err, SQ_ERR_NOMEM, "strip", "out of memory for features");
    }
    for (int i = 0; i < n; i++) {
        if (!valid || valid->px[i] > 0.5f) {
            hist_add(f->hist, lab + 3 * i);
            lsum += lab[3 * i];
            count++;
        }
    }
    f->valid_pixels = count;
    if (count < W * 4) {
        free(lab);
        free(L);
        free(sel);
        return sq_error_set(err, SQ_ERR_INVALID, "strip",
                            "the strip has %d valid pixels: too little of the body is visible", count);
    }
    hist_smooth(f->hist);
    normalise(f->hist, NB * NB * NB);
    /* lightness in [0,1]; pixels that do not count take the mean (they add no detail) */
    const float lmean = (float)(lsum / count / 100.0);
    for (int i = 0; i < n; i++)
        L[i] = (!valid || valid->px[i] > 0.5f) ? lab[3 * i] / 100.0f : lmean;

    /* palette from an even subsample of the valid pixels */
    int stride = count / MAX_PALETTE_PX + 1, ns = 0, seen = 0;
    for (int i = 0; i < n && ns < MAX_PALETTE_PX; i++)
        if (!valid || valid->px[i] > 0.5f) {
            if (seen++ % stride == 0) {
                memcpy(sel + 3 * ns, lab + 3 * i, sizeof(float) * 3);
                ns++;
            }
        }
    sq__palette(sel, ns, SQ_FIT_PALETTE, f->palette, f->palette_w);

    int bad = wavelet_energies(L, len, f->wavelet);
    /* every other line is plenty for the mean spectrum, at half the cost */
    f->along_power = (float)spectrum(L, len, W, W / 2, 2, f->along);
    f->across_power = (float)spectrum(L, W, 1, len / 2, 2 * W, f->across);
    normalise(f->along, SQ_FIT_BANDS);
    normalise(f->across, SQ_FIT_BANDS);

    /* the across profile, folded about the centre (left and right are not told apart) */
    double col[W] = {0};
    for (int y = 0; y < len; y++)
        for (int x = 0; x < W; x++)
            col[x] += L[(size_t)y * W + x];
    double pm = 0;
    for (int i = 0; i < SQ_FIT_PROFILE; i++) {
        f->profile[i] = (float)((col[W / 2 - 1 - i] + col[W / 2 + i]) / (2.0 * len));
        pm += f->profile[i];
    }
    for (int i = 0; i < SQ_FIT_PROFILE; i++)
        f->profile[i] -= (float)(pm / SQ_FIT_PROFILE);
    free(lab);
    free(L);
    free(sel);
    if (bad)
        return sq_error_set(err, SQ_ERR_NOMEM, "strip", "out of memory for the wavelet transform");
    return SQ_OK;
}

static double chi2(const float *p, const float *q, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++)
        if (p[i] + q[i] > 0)
            s += (double)(p[i] - q[i]) * (p[i] - q[i]) / (p[i] + q[i]);
    return 0.5 * s;
}

/* A spectrum's shape counts in proportion to how much pattern there is to have a shape;
 * the amount is compared on a log scale, each direction on its own, so a little
 * straightening wobble in a photo of plain stripes costs little. (It used to be compared
 * as this direction's share of both directions' power: at the powers of a plain skin's
 * light and noise that share is chance, yet it decided 2 of the 5 spectral units, and
 * faint impostor patterns won by copying it. Scored again, the recovery benchmark's
 * fronts and truths pick the right category for 36 of 52 photos this way, against 22.) */
static double spectral(const float *bt, const float *bc, double pt, double pc)
{
    const double eps = 1e-3; /* the variance of a barely visible pattern, (L/100)^2 */
    double m = pt < pc ? pt : pc;
    return m / (m + eps) * chi2(bt, bc, SQ_FIT_BANDS) + 0.5 * fabs(log((pt + eps) / (pc + eps)));
}

double sq_fit_palette_flow(const SqFeatures *a, const SqFeatures *b, double flow[SQ_FIT_PALETTE][SQ_FIT_PALETTE])
{
    enum { K = SQ_FIT_PALETTE };
    double d[K][K], ma[K], mb[K];
    int used[K][K] = {{0}};
    for (int i = 0; i < K; i++) {
        ma[i] = a->palette_w[i];
        mb[i] = b->palette_w[i];
        for (int j = 0; j < K; j++) {
            double x[3] = {a->palette[i][0], a->palette[i][1], a->palette[i][2]};
            double y[3] = {b->palette[j][0], b->palette[j][1], b->palette[j][2]};
            d[i][j] = sq_fit_ciede2000(x, y);
            if (flow)
                flow[i][j] = 0;
        }
    }
    double cost = 0, moved = 0;
    for (int step = 0; step < K * K; step++) {
        int bi = -1, bj = -1;
        for (int i = 0; i < K; i++)
            for (int j = 0; j < K; j++)
                if (!used[i][j] && ma[i] > 0 && mb[j] > 0 && (bi < 0 || d[i][j] < d[bi][bj])) {
                    bi = i;
                    bj = j;
                }
        if (bi < 0)
            break;
        double f = ma[bi] < mb[bj] ? ma[bi] : mb[bj];
        cost += f * d[bi][bj];
        moved += f;
        ma[bi] -= f;
        mb[bj] -= f;
        used[bi][bj] = 1;
        if (flow)
            flow[bi][bj] = f;
    }
    return moved > 0 ? cost / moved : 0.0;
}

void sq_fit_objectives(const SqFeatures *t, const SqFeatures *c, double *out)
{
    out[SQ_OBJ_PALETTE] = sq_fit_palette_flow(t, c, NULL);
    out[SQ_OBJ_HISTOGRAM] = chi2(t->hist, c->hist, NB * NB * NB);
    double s = 0;
    for (int l = 0; l < SQ_FIT_LEVELS; l++)
        for (int k = 0; k < 3; k++)
            s += fabs(t->wavelet[l][k] - c->wavelet[l][k]);
    out[SQ_OBJ_SHAPE] = s / (SQ_FIT_LEVELS * 3);
    out[SQ_OBJ_ALONG] = spectral(t->along, c->along, t->along_power, c->along_power);
    double prof = 0;
    for (int i = 0; i < SQ_FIT_PROFILE; i++)
        prof += fabs(t->profile[i] - c->profile[i]);
    out[SQ_OBJ_ACROSS] = spectral(t->across, c->across, t->across_power, c->across_power) +
                         2.0 * prof / SQ_FIT_PROFILE;
}
