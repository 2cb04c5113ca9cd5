/* Transversal bands read off a photo's strip. Bands across the body (the thesis' §4.2.2)
 * make every row of the strip one colour, and the rows' colours repeat along the body: the
 * autocorrelation of the rows' mean CIELAB colour peaks at the repeat (the shortest lag
 * that scores near the best, so not a multiple of it). Folded at that period, the rows'
 * colours give one repeat's profile, split into two or three colours by k-means: the
 * commonest is the skin, each run of the others a band, a run of one colour holding a run
 * of the other a band with a band drawn over it (a coral snake's black-yellow-black
 * triad). A tile holds one repeat, or as many as its bands allow (the generator draws
 * three bands a tile) when one would be shorter than the shortest tile the fit views.
 * Written here rather than taken from a library: it is a fold and a small k-means over a
 * few dozen bins, on the strip's own conventions (rows, view scale, valid mask). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "search_internal.h"
#include "squama/fitness.h"
#include "squama/search.h"

enum {
    W = SQ_FIT_STRIP_W,
    MIN_VALID = W / 8, /* valid pixels a row needs to count */
    LAG_MIN = 6,       /* the shortest repeat read, rows */
    KMEANS_ITERS = 20
};
/* strip rows a tile at view scale 1: the strip's columns span SQ_FIT_BAND_WIDTH of the way
 * round */
#define ROWS_PER_TILE (W / SQ_FIT_BAND_WIDTH)
enum { BINS_MAX = 1600 }; /* a repeat's bins (a row each), at most: a tile at view scale 8 */
static const double NEAR = 0.85; /* a repeat scoring this share of the best, or more, is read
                                    when shorter */

static double dist2(const double a[3], const double b[3])
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

/* k-means of the profile's nb bins (Lab, 3 each) into k colours, started from the darkest
 * and the lightest bin and (k = 3) the bin farthest from both; class[] and centre[]
 * filled. */
static void kmeans(const double (*prof)[3], int nb, int k, int *cls, double (*centre)[3])
{
    int lo = 0, hi = 0;
    for (int b = 1; b < nb; b++) {
        lo = prof[b][0] < prof[lo][0] ? b : lo;
        hi = prof[b][0] > prof[hi][0] ? b : hi;
    }
    memcpy(centre[0], prof[lo], sizeof centre[0]);
    memcpy(centre[1], prof[hi], sizeof centre[1]);
    if (k == 3) { /* the bin farthest from both */
        int far = 0;
        double best = -1;
        for (int b = 0; b < nb; b++) {
            const double d = fmin(dist2(prof[b], centre[0]), dist2(prof[b], centre[1]));
            if (d > best) {
                best = d;
                far = b;
            }
        }
        memcpy(centre[2], prof[far], sizeof centre[2]);
    }
    for (int it = 0; it < KMEANS_ITERS; it++) {
        for (int b = 0; b < nb; b++) {
            double best = INFINITY;
            for (int c = 0; c < k; c++) {
                const double e = dist2(prof[b], centre[c]);
                if (e < best) {
                    best = e;
                    cls[b] = c;
                }
            }
        }
        for (int c = 0; c < k; c++) {
            double s[3] = {0}, n = 0;
            for (int b = 0; b < nb; b++)
                if (cls[b] == c) {
                    for (int j = 0; j < 3; j++)
                        s[j] += prof[b][j];
                    n++;
                }
            if (n > 0)
                for (int j = 0; j < 3; j++)
                    centre[c][j] = s[j] / n;
        }
    }
}

static void to_srgb(const double lab[3], double out[3])
{
    const float l[3] = {(float)lab[0], (float)lab[1], (float)lab[2]};
    float rgb[3];
    sq_fit_lab_to_srgb(l, rgb);
    for (int j = 0; j < 3; j++)
        out[j] = fmin(fmax(rgb[j], 0), 1);
}

/* The bands of a folded profile: runs of its bins' colours (cls, nb bins, read from bin
 * s0 on), each from and to as fractions of the repeat, in its colour. */
typedef struct Runs {
    const int *cls;
    int nb, s0, n;
    double be[2 * SQ_BANDS_MAX][2];
    int colour[2 * SQ_BANDS_MAX];
} Runs;

/* The runs of bins in [from, upto) not of colour `other`, each a band in its first bin's
 * colour; with `inner`, within each the runs not of that colour again (a band drawn over
 * a band). -1 when there are more than 2 * SQ_BANDS_MAX. */
static int runs(Runs *r, int from, int upto, int other, int inner)
{
    for (int i = from; i < upto;) {
        const int c = r->cls[(r->s0 + i) % r->nb];
        if (c == other) {
            i++;
            continue;
        }
        int j = i;
        while (j < upto && r->cls[(r->s0 + j) % r->nb] != other)
            j++;
        if (r->n >= 2 * SQ_BANDS_MAX)
            return -1;
        r->be[r->n][0] = (double)(r->s0 + i) / r->nb;
        r->be[r->n][1] = (double)(r->s0 + j) / r->nb;
        r->colour[r->n++] = c;
        if (inner && runs(r, i, j, c, 0) != 0)
            return -1;
        i = j;
    }
    return 0;
}

/* One reading of the profile (nb bins a repeat of `period` rows) in k colours; 0 when its
 * bands do not fit a tile. */
static int reading(const double (*prof)[3], int nb, double period, double corr, int k, SqBandsReading *out)
{
    int cls[BINS_MAX], count[3] = {0};
    double centre[3][3];
    kmeans(prof, nb, k, cls, centre);
    for (int b = 0; b < nb; b++)
        count[cls[b]]++;
    int skin = 0;
    for (int c = 0; c < k; c++) {
        if (count[c] == 0) /* fewer colours than k: the reading with fewer says it */
            return 0;
        skin = count[c] > count[skin] ? c : skin;
    }
    /* start at a skin bin, so that no run wraps round */
    int s0 = 0;
    while (cls[s0] != skin)
        s0++;
    memset(out, 0, sizeof *out);
    Runs r = {.cls = cls, .nb = nb, .s0 = s0};
    if (runs(&r, 0, nb, skin, 1) != 0)
        return 0;
    /* as many repeats a tile as make it SQ__VIEW_LO long, when the bands allow */
    int rep = 1;
    while (rep * period / ROWS_PER_TILE < SQ__VIEW_LO)
        rep++;
    if (r.n * rep > SQ_BANDS_MAX || rep * period / ROWS_PER_TILE > SQ__VIEW_HI)
        return 0;
    out->period = period;
    out->repeats = rep;
    out->view_scale = rep * period / ROWS_PER_TILE;
    out->corr = corr;
    out->colours = k;
    to_srgb(centre[skin], out->skin);
    for (int t = 0; t < rep; t++)
        for (int i = 0; i < r.n; i++) {
            const int n = out->nbands++;
            out->begin_end[n][0] = fmod((t + r.be[i][0]) / rep, 1.0);
            out->begin_end[n][1] = fmod((t + r.be[i][1]) / rep, 1.0);
            to_srgb(centre[r.colour[i]], out->colour[n]);
        }
    return 1;
}

int sq_fit_read_bands(const SqImage *strip, const SqImage *valid, SqBandsReading *out, int max)
{
    if (!strip || !strip->px || strip->width != W || strip->channels < 3 || max < 1 ||
        (valid && (!valid->px || valid->width != W || valid->height != strip->height || valid->channels < 1)))
        return 0;
    const int n = strip->height;
    double(*m)[3] = calloc((size_t)n, sizeof *m);
    unsigned char *ok = calloc((size_t)n, 1);
    double *r = calloc((size_t)n, sizeof *r);
    int found = 0;
    if (!m || !ok || !r)
        goto done;
    /* each row's mean colour, less the strip's; the share of the colours' variance between
     * the rows, every row weighing the same (bands: nearly all of it; spots and automata
     * vary along the rows too. Tried: the columns' means, the body's shading across, taken
     * out first; it read the automata nearer to bands) */
    double mean[3] = {0}, within = 0;
    int rows = 0;
    for (int y = 0; y < n; y++) {
        double s[3] = {0}, s2 = 0;
        int c = 0;
        for (int x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            if (valid && valid->px[i * valid->channels] <= 0.5f)
                continue;
            float lab[3];
            sq_fit_srgb_to_lab(strip->px + i * strip->channels, lab);
            for (int j = 0; j < 3; j++) {
                s[j] += lab[j];
                s2 += (double)lab[j] * lab[j];
            }
            c++;
        }
        if (c >= MIN_VALID) {
            ok[y] = 1;
            rows++;
            for (int j = 0; j < 3; j++) {
                m[y][j] = s[j] / c;
                mean[j] += m[y][j];
                s2 -= c * m[y][j] * m[y][j];
            }
            within += s2 / c;
        }
    }
    if (rows < 4 * LAG_MIN)
        goto done;
    for (int j = 0; j < 3; j++)
        mean[j] /= rows;
    double between = 0;
    for (int y = 0; y < n; y++)
        for (int j = 0; j < 3 && ok[y]; j++) {
            m[y][j] -= mean[j];
            between += m[y][j] * m[y][j];
        }
    const double explained = between + within > 0 ? between / (between + within) : 0;
    /* the normalised autocorrelation at each lag: two repeats at least in the strip */
    const int lag_max = n / 2 < ROWS_PER_TILE * SQ__VIEW_HI ? n / 2 : (int)(ROWS_PER_TILE * SQ__VIEW_HI);
    if (lag_max <= LAG_MIN + 1)
        goto done;
    for (int L = LAG_MIN - 1; L <= lag_max; L++) {
        double sab = 0, saa = 0, sbb = 0;
        for (int y = 0; y + L < n; y++) {
            if (!ok[y] || !ok[y + L])
                continue;
            for (int j = 0; j < 3; j++) {
                sab += m[y][j] * m[y + L][j];
                saa += m[y][j] * m[y][j];
                sbb += m[y + L][j] * m[y + L][j];
            }
        }
        r[L] = saa > 0 && sbb > 0 ? sab / sqrt(saa * sbb) : 0;
    }
    double best = 0;
    for (int L = LAG_MIN; L < lag_max; L++)
        if (r[L] > r[L - 1] && r[L] >= r[L + 1])
            best = fmax(best, r[L]);
    if (!(best > 0))
        goto done;
    int lag = 0;
    for (int L = LAG_MIN; L < lag_max && !lag; L++)
        if (r[L] > r[L - 1] && r[L] >= r[L + 1] && r[L] >= NEAR * best)
            lag = L;
    /* the peak to a fraction of a row (a parabola through it and its neighbours) */
    const double den = r[lag - 1] - 2 * r[lag] + r[lag + 1];
    const double period = lag + (den < 0 ? 0.5 * (r[lag - 1] - r[lag + 1]) / den : 0);
    /* one repeat's profile: the rows folded at the period, a bin a row */
    const int nb = (int)lround(period);
    if (nb > BINS_MAX)
        goto done;
    double(*prof)[3] = calloc((size_t)nb, sizeof *prof);
    double *cnt = calloc((size_t)nb, sizeof *cnt);
    if (prof && cnt) {
        for (int y = 0; y < n; y++) {
            if (!ok[y])
                continue;
            const double ph = fmod(y / period, 1.0);
            const int b = (int)(ph * nb) % nb;
            for (int j = 0; j < 3; j++)
                prof[b][j] += m[y][j] + mean[j];
            cnt[b]++;
        }
        int empty = 0;
        for (int b = 0; b < nb; b++) {
            if (cnt[b] > 0)
                for (int j = 0; j < 3; j++)
                    prof[b][j] /= cnt[b];
            else
                empty++;
        }
        for (int b = 0; b < nb && empty < nb; b++) /* a bin no row fell in: its neighbour's */
            if (cnt[b] == 0) {
                int a = b;
                while (cnt[a] == 0)
                    a = (a + nb - 1) % nb;
                memcpy(prof[b], prof[a], sizeof prof[b]);
            }
        for (int k = 2; k <= 3 && found < max && empty < nb; k++)
            if (reading((const double(*)[3])prof, nb, period, r[lag], k, &out[found]))
                out[found++].explained = explained;
    }
    free(prof);
    free(cnt);
done:
    free(m);
    free(ok);
    free(r);
    return found;
}
