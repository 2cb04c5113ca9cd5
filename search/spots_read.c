/* Spot lattices read off a photo's strip. The thesis' spots (§4.2.3) sit on a grid of
 * Spots_Tiling * 10 round the body, every other row shifted by Spots_Offset, each spot
 * moved a little at random: a lattice, which shows in the autocorrelation of the strip's
 * lightness as peaks at the lattice's vectors and troughs half way along them, whatever
 * the spots' colour or size. Every lattice the generator can make (its spots round the
 * body, the rows' spacing along, the offset) is scored by the autocorrelation at its short
 * vectors, their longest multiples in reach and the texture tile's length along (where
 * the whole pattern repeats, spots moved at random included) less at points half a
 * vector short of them. The autocorrelation comes from one FFT a column (GSL), the
 * columns' cross-spectra summed for each shift across; with the scan of the lattices,
 * 45 ms a strip of 700 rows on one core (scripts/bench read), a few evaluations' worth.
 * Random spot positions (a third of a cell or more) leave no lattice to read: the fit's
 * random draws are left those. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_fft_complex.h>

#include "squama/fitness.h"
#include "squama/search.h"

enum {
    W = SQ_FIT_STRIP_W,
    DX = 48,         /* shifts across: -DX to DX columns (a lattice vector is reduced to
                      * within half a spacing; the widest spacing, 192 / (NX_MIN - 1)) */
    DY = 384,        /* shifts along: 0 to DY rows (a tile at view scale 2) */
    NX_MIN = 5,      /* spots round the body tried */
    NX_MAX = 48,
    TREND = 24,      /* the lightness' trend along: a box of 2 TREND + 1 rows */
    OFFSETS = 16,    /* offsets tried, 0 to 15/16 */
    SUB = 4          /* spacings along tried a row: a quarter of a row */
};
static const double CY_MIN = 2.5, CY_MAX = 96; /* the rows of spots' spacings tried, strip rows */
enum { Q_MAX = 4 }; /* the longest multiple of v2 scored: the spacing's grid, a quarter row, is off by
                     * at most half a row there */
/* A lattice scores about as well at a multiple of its spacing along, whose vectors are
 * its own: the smallest spacing that scores NEAR the best or better, a peak, at a whole
 * fraction of it (1 / K_MAX or more; the ratio within DIVISOR of a whole number), is read. */
static const double NEAR = 0.8, DIVISOR = 0.15;
enum { K_MAX = 8 };

/* Rows of spots a texture tile for nx round the body at offset o: as many (the fit's
 * maps are square), made even when the rows are offset, as the generator's grid. */
static int tile_rows(int nx, double o)
{
    return nx + (o > 0 && nx % 2);
}

/* The autocorrelation at a fractional shift (dx, dy), dy >= 0 after the symmetry A(-d) =
 * A(d); bilinear; NAN outside the table. */
static double at(const float *A, double dx, double dy)
{
    if (dy < 0) {
        dx = -dx;
        dy = -dy;
    }
    const double x = dx + DX;
    if (x < 0 || x > 2 * DX || dy > DY)
        return NAN;
    int x0 = (int)floor(x), y0 = (int)floor(dy);
    if (x0 == 2 * DX)
        x0--;
    if (y0 == DY)
        y0--;
    const double tx = x - x0, ty = dy - y0;
    const float *r0 = A + (size_t)y0 * (2 * DX + 1), *r1 = r0 + 2 * DX + 1;
    return (1 - ty) * ((1 - tx) * r0[x0] + tx * r0[x0 + 1]) + ty * ((1 - tx) * r1[x0] + tx * r1[x0 + 1]);
}

/* dx reduced by whole spacings cx to within (-cx / 2, cx / 2]. */
static double reduce(double dx, double cx)
{
    return dx - cx * ceil(dx / cx - 0.5);
}

/* The strip's lightness less its column means and its trend along, 0 where the strip is not
 * valid; w: 1 where valid. Returns the skewness of the values (negative: the pattern is
 * darker than the skin). */
static double highpass(const SqImage *s, const SqImage *valid, double *y, double *w)
{
    const int L = s->height, ch = s->channels;
    for (int j = 0; j < L; j++)
        for (int i = 0; i < W; i++) {
            const float *px = s->px + ((size_t)j * s->width + i) * ch;
            const int ok = !valid || valid->px[((size_t)j * valid->width + i) * valid->channels] > 0.5f;
            y[(size_t)j * W + i] = ok ? 0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2] : 0;
            w[(size_t)j * W + i] = ok;
        }
    for (int i = 0; i < W; i++) { /* the columns' means: the body's shading across */
        double sy = 0, sw = 0;
        for (int j = 0; j < L; j++) {
            sy += y[(size_t)j * W + i];
            sw += w[(size_t)j * W + i];
        }
        const double m = sw > 0 ? sy / sw : 0;
        for (int j = 0; j < L; j++)
            y[(size_t)j * W + i] -= m * w[(size_t)j * W + i];
    }
    /* the trend along: the mean of the rows within TREND (a running sum) */
    double *row = malloc(sizeof(double) * 2 * (size_t)L), *cnt = row ? row + L : NULL;
    if (row) {
        for (int j = 0; j < L; j++) {
            row[j] = cnt[j] = 0;
            for (int i = 0; i < W; i++) {
                row[j] += y[(size_t)j * W + i];
                cnt[j] += w[(size_t)j * W + i];
            }
        }
        double sy = 0, sw = 0;
        int lo = 0, hi = 0; /* the window [lo, hi) */
        for (int j = 0; j < L; j++) {
            while (hi < L && hi <= j + TREND) {
                sy += row[hi];
                sw += cnt[hi++];
            }
            while (lo < j - TREND) {
                sy -= row[lo];
                sw -= cnt[lo++];
            }
            const double m = sw > 0 ? sy / sw : 0;
            for (int i = 0; i < W; i++)
                y[(size_t)j * W + i] -= m * w[(size_t)j * W + i];
        }
        free(row);
    }
    double m2 = 0, m3 = 0, n = 0;
    for (size_t k = 0; k < (size_t)L * W; k++) {
        m2 += y[k] * y[k];
        m3 += y[k] * y[k] * y[k];
        n += w[k];
    }
    if (n < 1 || m2 <= 0)
        return 0;
    m2 /= n;
    return m3 / n / pow(m2, 1.5);
}

static int cmp_dbl(const void *a, const void *b)
{
    const double x = *(const double *)a, z = *(const double *)b;
    return (x > z) - (x < z);
}

/* The skin's and the spots' colours (sRGB): the mean colour of the strip's valid pixels
 * whose high-passed lightness y lies in its middle SKIN_SHARE, and of those in its
 * SPOT_SHARE farthest the skew's way (< 0: the darkest). The photo's palette blends small
 * spots with the skin around them; these are the spots' own. 0 on failure. */
static const double SKIN_SHARE = 0.4, SPOT_SHARE = 0.02;

static int strip_colours(const SqImage *s, const double *y, const double *w, double skew, double skin[3],
                         double spot[3])
{
    const size_t N = (size_t)s->height * W;
    double *v = malloc(sizeof(double) * N);
    if (!v)
        return 0;
    size_t n = 0;
    for (size_t k = 0; k < N; k++)
        if (w[k] > 0)
            v[n++] = y[k];
    if (n < 100) {
        free(v);
        return 0;
    }
    qsort(v, n, sizeof *v, cmp_dbl);
    const double s_lo = v[(size_t)((0.5 - SKIN_SHARE / 2) * (double)n)];
    const double s_hi = v[(size_t)((0.5 + SKIN_SHARE / 2) * (double)n)];
    const double cut = skew < 0 ? v[(size_t)(SPOT_SHARE * (double)n)] : v[(size_t)((1 - SPOT_SHARE) * (double)n)];
    free(v);
    double sk[4] = {0}, sp[4] = {0};
    for (size_t k = 0; k < N; k++) {
        if (!(w[k] > 0))
            continue;
        const float *px = s->px + ((k / W) * (size_t)s->width + k % W) * (size_t)s->channels;
        double *acc = y[k] >= s_lo && y[k] <= s_hi ? sk : (skew < 0 ? y[k] <= cut : y[k] >= cut) ? sp : NULL;
        if (!acc)
            continue;
        for (int c = 0; c < 3; c++)
            acc[c] += px[c];
        acc[3] += 1;
    }
    if (sk[3] < 1 || sp[3] < 1)
        return 0;
    for (int c = 0; c < 3; c++) {
        skin[c] = sk[c] / sk[3];
        spot[c] = sp[c] / sp[3];
    }
    return 1;
}

/* The autocorrelation of y (weights w) for shifts dx in [-DX, DX], dy in [0, DY]: the sum
 * of products over the valid pairs, over their count, over the same at shift 0; A is
 * (DY + 1) rows of 2 DX + 1. Returns 0, or -1 when out of memory. */
static int autocorrelation(const double *y, const double *w, int L, float *A)
{
    size_t n = 1;
    while (n < (size_t)L + DY + 1)
        n *= 2;
    /* each column's spectrum, of the values and of the weights */
    double *F = malloc(sizeof(double) * 2 * n * 2 * W), *acc = malloc(sizeof(double) * 2 * n * 2);
    if (!F || !acc) {
        free(F);
        free(acc);
        return -1;
    }
    gsl_error_handler_t *old = gsl_set_error_handler_off();
    for (int i = 0; i < W; i++)
        for (int v = 0; v < 2; v++) {
            double *c = F + (size_t)(2 * i + v) * 2 * n;
            memset(c, 0, sizeof(double) * 2 * n);
            for (int j = 0; j < L; j++)
                c[2 * j] = (v ? w : y)[(size_t)j * W + i];
            gsl_fft_complex_radix2_forward(c, 1, n);
        }
    double a0 = 1;
    for (int dx = 0; dx <= DX; dx++) /* dx >= 0: pairs (i, i + dx); dx < 0 from A(-d) = A(d) */
        for (int sgn = 1; sgn >= (dx ? -1 : 1); sgn -= 2) {
            /* corr(a, b)[d] = sum_j a[j] b[j + d]: the inverse transform of conj(A) B; sgn < 0
             * gives the shift (-dx, d) as (dx, -d): read at n - d */
            memset(acc, 0, sizeof(double) * 2 * n * 2);
            for (int i = 0; i + dx < W; i++)
                for (int v = 0; v < 2; v++) {
                    const double *a = F + (size_t)(2 * i + v) * 2 * n, *b = F + (size_t)(2 * (i + dx) + v) * 2 * n;
                    double *s = acc + (size_t)v * 2 * n;
                    for (size_t k = 0; k < n; k++) {
                        s[2 * k] += a[2 * k] * b[2 * k] + a[2 * k + 1] * b[2 * k + 1];
                        s[2 * k + 1] += a[2 * k] * b[2 * k + 1] - a[2 * k + 1] * b[2 * k];
                    }
                }
            gsl_fft_complex_radix2_inverse(acc, 1, n);
            gsl_fft_complex_radix2_inverse(acc + 2 * n, 1, n);
            for (int d = 0; d <= DY; d++) {
                const size_t k = sgn > 0 ? (size_t)d : (n - (size_t)d) % n;
                const double num = acc[2 * k], den = acc[2 * n + 2 * k];
                const double v = den > 0.5 ? num / den : 0;
                if (dx == 0 && d == 0)
                    a0 = v > 0 ? v : 1;
                /* (dx, d) for sgn > 0; (dx, -d), i.e. (-dx, d), for sgn < 0 */
                A[(size_t)d * (2 * DX + 1) + (size_t)(DX + sgn * dx)] = (float)v;
            }
        }
    gsl_set_error_handler(old);
    for (size_t k = 0; k < (size_t)(DY + 1) * (2 * DX + 1); k++)
        A[k] = (float)(A[k] / a0);
    free(F);
    free(acc);
    return 0;
}

/* A lattice's score: the autocorrelation at its vectors less at points half way between
 * its spots. The vectors: across a row (v1), to the next row (v2, shifted by the offset)
 * and v2 - v1, whose midpoints are troughs; the longest multiples of v1 (half the strip's
 * columns overlapping) and of v2 in the table, against the points half a vector short of
 * them, which pin the spacings down (a spacing a few percent off drifts a whole spot from
 * the multiple); and the tile's length, when in the table, against half a row short of
 * it: a lattice read at a multiple of its spacing has its tile out of reach. NAN when a
 * vector is outside the table. */
static double lattice_score(const float *A, int nx, double cy, double o)
{
    const double sx = (double)W / (SQ_FIT_BAND_WIDTH * nx); /* strip columns between spots */
    const int m = (int)(0.5 * W / sx), q = (int)fmin(DY / cy, Q_MAX); /* m: half the strip's columns overlap */
    const double ox = o * sx;
    /* peak, trough */
    const double pt[5][2][2] = {
        {{sx, 0}, {0.5 * sx, 0}},
        {{reduce(ox, sx), cy}, {0.5 * reduce(ox, sx), 0.5 * cy}},
        {{reduce(ox, sx) - sx, cy}, {0.5 * (reduce(ox, sx) - sx), 0.5 * cy}},
        {{m * sx, 0}, {(m - 0.5) * sx, 0}},
        {{reduce(q * ox, sx), q * cy}, {reduce((q - 0.5) * ox, sx), (q - 0.5) * cy}},
    };
    const int n = m >= 2 ? (q >= 2 ? 5 : 4) : 3;
    double peak = 0, trough = 0;
    for (int k = 0; k < n; k++) {
        const double p = at(A, pt[k][0][0], pt[k][0][1]), t = at(A, pt[k][1][0], pt[k][1][1]);
        if (!isfinite(p) || !isfinite(t))
            return NAN;
        peak += p;
        trough += t;
    }
    /* the texture tile: the whole pattern repeats there, spots moved at random included */
    const double T = tile_rows(nx, o) * cy, pT = at(A, 0, T), tT = at(A, 0, T - 0.5 * cy);
    if (isfinite(pT) && isfinite(tT))
        return (peak - trough + pT - tT) / (n + 1);
    return (peak - trough) / n;
}

int sq_fit_read_spots(const SqImage *strip, const SqImage *valid, SqSpotsReading *out, int max)
{
    if (!strip || !strip->px || strip->width != W || strip->channels < 3 || max <= 0 || strip->height < 2 * W ||
        (valid && (!valid->px || valid->width != strip->width || valid->height != strip->height)))
        return 0;
    const int L = strip->height;
    double *y = malloc(sizeof(double) * (size_t)L * W), *w = malloc(sizeof(double) * (size_t)L * W);
    float *A = malloc(sizeof(float) * (DY + 1) * (2 * DX + 1));
    int found = 0;
    if (!y || !w || !A)
        goto done;
    const double skew = highpass(strip, valid, y, w);
    double skin[3] = {0}, spot[3] = {0};
    const int coloured = strip_colours(strip, y, w, skew, skin, spot);
    if (autocorrelation(y, w, L, A) != 0)
        goto done;
    /* per count round the body: the best score over spacings and offsets, read at the
     * smallest spacing it is a multiple of (NEAR) */
    const int nc = (int)(fmin(CY_MAX, 0.25 * L) * SUB);
    SqSpotsReading best[NX_MAX + 2] = {{0}}; /* NX_MIN - 1 and NX_MAX + 1: the ends' neighbours */
    double *S = malloc(sizeof(double) * (size_t)(nc + 1));
    int *O = malloc(sizeof(int) * (size_t)(nc + 1));
    if (!S || !O) {
        free(S);
        free(O);
        goto done;
    }
    for (int nx = NX_MIN - 1; nx <= NX_MAX + 1; nx++) {
        double top = -INFINITY;
        for (int ci = (int)(CY_MIN * SUB); ci <= nc; ci++) {
            S[ci] = -INFINITY;
            /* none within a sixteenth of 0 or 1: rows offset have an even count a tile,
             * so one spot fewer round, offset that little, would mimic a lattice with an
             * odd count of rows unshifted, tile and all */
            for (int oi = 0; oi < OFFSETS - 1; oi += oi == 0 ? 2 : 1) {
                const double sc = lattice_score(A, nx, (double)ci / SUB, (double)oi / OFFSETS);
                if (isfinite(sc) && sc > S[ci]) {
                    S[ci] = sc;
                    O[ci] = oi;
                }
            }
            top = fmax(top, S[ci]);
        }
        int tc = -1; /* the best spacing */
        for (int ci = (int)(CY_MIN * SUB); ci <= nc; ci++)
            if (tc < 0 || S[ci] > S[tc])
                tc = ci;
        best[nx].score = top;
        for (int ci = (int)(CY_MIN * SUB); ci <= tc; ci++) {
            const double k = (double)tc / ci;
            if (S[ci] >= NEAR * top && round(k) <= K_MAX && fabs(k - round(k)) < DIVISOR &&
                (ci == tc || (ci > (int)(CY_MIN * SUB) && S[ci] >= S[ci - 1] && S[ci] >= S[ci + 1]))) {
                const double cy = (double)ci / SUB, o = (double)O[ci] / OFFSETS;
                best[nx] = (SqSpotsReading){.across = nx, .spacing = cy, .offset = o,
                                            .view_scale = cy * tile_rows(nx, o) * SQ_FIT_BAND_WIDTH / W,
                                            .score = top, .skew = skew};
                best[nx].coloured = coloured;
                memcpy(best[nx].skin, skin, sizeof skin);
                memcpy(best[nx].spot, spot, sizeof spot);
                break;
            }
        }
    }
    free(S);
    free(O);
    /* the counts that score better than their neighbours, best first */
    for (int nx = NX_MIN; nx <= NX_MAX; nx++) {
        const double sc = best[nx].score;
        if (!(sc > 0) || best[nx - 1].score > sc || best[nx + 1].score > sc)
            continue;
        if (found == max && out[max - 1].score >= sc)
            continue;
        int k = found < max ? found++ : max - 1;
        out[k] = best[nx];
        for (; k > 0 && out[k].score > out[k - 1].score; k--) {
            SqSpotsReading t = out[k];
            out[k] = out[k - 1];
            out[k - 1] = t;
        }
    }
done:
    free(y);
    free(w);
    free(A);
    return found;
}
