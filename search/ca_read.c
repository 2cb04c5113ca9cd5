/* Automata read off a photo's strip. A cellular automaton's pattern fills one texture
 * tile, so a photo of it repeats along the body at the tile's length: the strip's
 * lightness is folded at the periods where it repeats, and automata are searched for the
 * one whose pattern, seen in the same band, correlates best with the fold. The search
 * costs well under a millisecond an automaton (a 96 x 48 coverage and a correlation over
 * the phases along and every rotation round the body) where a fit's evaluation costs 20 ms,
 * so thousands are tried: random ones first, then the best hill-climbed by the GP
 * mutations. The fit's screening starts its automata from what is read here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"
#include "squama/fitness.h"
#include "squama/generator.h"
#include "squama/search.h"

enum {
    BW = 32,        /* fold columns: the strip's 64, in pairs */
    TW = 3 * BW,    /* the texture's columns round the body (the band is a third) */
    R = 48,         /* fold rows: one period along */
    PERIODS = 2,    /* periods tried */
    INIT = 512,     /* random automata a period */
    NMAX = 24,      /* their cells: 6 to NMAX (the thesis' species have 8 to 32, median
                     * 19; mutations may grow them) */
    CLIMBERS = 12,  /* the best of them, hill-climbed */
    STEPS = 250,    /* mutations a climber */
    TMIN = 40,      /* shortest period, strip rows (a view scale of about 0.2) */
    G = 4,          /* groups of columns whose profiles along pick the phases */
    PHASES = 3      /* phases each way along where the whole correlation is computed */
};

/* A correlation sees neither how strong a pattern is nor how much of the skin it covers:
 * a faint or grey pattern, a crisp one, a blob and the same blob grown correlate alike
 * with the fold, but their colours differ. So the pattern's values (coverage, 0 to 1) are
 * compared with the fold's, stretched to 0 to 1 between its 2nd and 98th percentiles (the
 * band is taken to show both colours): their distributions' distance (the earth
 * mover's, over HB bins) costs DIST_W correlation a unit. */
static const double DIST_W = 0.5;
enum { HB = 32 };

/* One fold of the strip: lightness at zero mean and unit norm. */
typedef struct Fold {
    double T;
    float p[2][BW * R];   /* as folded, and turned end for end (read the other way along) */
    float g[2][R * G];    /* p summed over each of G groups of columns: row by row, the
                           * groups of a row together */
    float cdf[2][HB]; /* its values stretched to [0, 1]: their cumulative histogram, as
                       * they are (the pattern lighter) and flipped (darker) */
} Fold;

typedef struct Ind {
    SqCa ca;
    double diameter, blur, contrast;
    double corr; /* signed */
    double fit;  /* |corr| less DIST_W times the distributions' distance: what is maximised */
    int k, rev;  /* the rotation and reversal of the initial row that gave it */
} Ind;

/* The cumulative histogram of n values over HB bins of [0, 1] (those outside counted at
 * the ends), of v or, flip, 1 - v. */
static void cumulative(const float *v, int n, int flip, float *cdf)
{
    int h[4][HB] = {{0}}; /* four counts, so that runs of one bin do not wait on each other */
    for (int i = 0; i < n; i++) {
        const float x = flip ? 1 - v[i] : v[i];
        const int b = x > 0 ? (int)(x * HB) : 0; /* floor, for x > 0 */
        h[i & 3][b < HB ? b : HB - 1]++;
    }
    int c = 0;
    for (int b = 0; b < HB; b++)
        cdf[b] = (float)(c += h[0][b] + h[1][b] + h[2][b] + h[3][b]) / (float)n;
}

static double emd(const float *a, const float *b)
{
    double s = 0;
    for (int i = 0; i < HB; i++)
        s += fabs(a[i] - b[i]);
    return s / HB;
}

static double clampd(double v, double lo, double hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

static int cmp_float(const void *a, const void *b)
{
    const float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The strip's lightness in BW columns (weights: the valid share), column means removed. */
static void lightness(const SqImage *s, const SqImage *valid, float *y, float *w)
{
    const int L = s->height, ch = s->channels;
    for (int j = 0; j < L; j++)
        for (int x = 0; x < BW; x++) {
            double sy = 0, sw = 0;
            for (int d = 0; d < 2; d++) {
                const int i = 2 * x + d;
                const float *px = s->px + ((size_t)j * s->width + i) * ch;
                const double v = valid ? valid->px[((size_t)j * valid->width + i) * valid->channels] : 1;
                const double wt = v > 0.5 ? 1 : 0;
                sy += wt * (0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2]);
                sw += wt;
            }
            y[(size_t)j * BW + x] = sw > 0 ? (float)(sy / sw) : 0;
            w[(size_t)j * BW + x] = (float)(sw / 2);
        }
    for (int x = 0; x < BW; x++) {
        double sy = 0, sw = 0;
        for (int j = 0; j < L; j++) {
            sy += w[(size_t)j * BW + x] * y[(size_t)j * BW + x];
            sw += w[(size_t)j * BW + x];
        }
        const float m = sw > 0 ? (float)(sy / sw) : 0;
        for (int j = 0; j < L; j++)
            y[(size_t)j * BW + x] -= m;
    }
}

/* The periods along the strip where its lightness repeats best (local maxima of the
 * autocorrelation above 0.25, at most PERIODS, none a multiple of a stronger one), to a
 * tenth of a row; returns how many. */
static int periods(const float *y, const float *w, int L, double *T)
{
    const int hi = L / 2;
    if (hi <= TMIN + 1)
        return 0;
    double *a = calloc((size_t)hi + 2, sizeof *a);
    if (!a)
        return 0;
    for (int t = 0; t <= hi + 1; t++) {
        if (t > 0 && t < TMIN - 1)
            continue;
        double s = 0, n = 0;
        for (int j = 0; j + t < L; j++)
            for (int x = 0; x < BW; x++) {
                const size_t i0 = (size_t)j * BW + x, i1 = (size_t)(j + t) * BW + x;
                const double ww = (double)w[i0] * w[i1];
                s += ww * y[i0] * y[i1];
                n += ww;
            }
        a[t] = n > 0 ? s / n : 0;
    }
    int np = 0;
    double peak[64], val[64];
    for (int t = TMIN; t <= hi && a[0] > 0; t++)
        if (a[t] > a[t - 1] && a[t] >= a[t + 1] && a[t] / a[0] > 0.25 && np < 64) {
            const double den = a[t - 1] - 2 * a[t] + a[t + 1];
            peak[np] = t + (den < 0 ? clampd(0.5 * (a[t - 1] - a[t + 1]) / den, -0.5, 0.5) : 0);
            val[np++] = a[t];
        }
    free(a);
    int n = 0;
    while (n < PERIODS) {
        int b = -1;
        for (int i = 0; i < np; i++)
            if (val[i] > -1 && (b < 0 || val[i] > val[b]))
                b = i;
        if (b < 0)
            break;
        val[b] = -2;
        int multiple = 0;
        for (int i = 0; i < n; i++) {
            const double r = peak[b] / T[i], k = round(r);
            multiple |= k >= 2 && fabs(r - k) < 0.04 * k;
        }
        if (!multiple)
            T[n++] = peak[b];
    }
    return n;
}

/* img (BW x R) summed over each of G groups of columns, row by row: g[r * G + group]. */
static void group_profiles(const float *img, float *g)
{
    for (int r = 0; r < R; r++)
        for (int gi = 0; gi < G; gi++) {
            float sum = 0;
            for (int x = gi * (BW / G); x < (gi + 1) * (BW / G); x++)
                sum += img[r * BW + x];
            g[r * G + gi] = sum;
        }
}

/* The dot product of n floats, n a multiple of 16: the score's inner loop, in sixteen
 * partial sums (four SIMD registers adding independently, not one waiting on the last).
 * The sums are one vector value rather than a stack array, which a sanitizer would check
 * at every step. */
typedef float F16 __attribute__((vector_size(64)));
static float dot(const float *a, const float *b, int n)
{
    F16 s = {0}, va, vb;
    for (int i = 0; i < n; i += 16) {
        memcpy(&va, a + i, sizeof va);
        memcpy(&vb, b + i, sizeof vb);
        s += va * vb;
    }
    float sum = 0;
    for (int j = 0; j < 16; j++)
        sum += s[j];
    return sum;
}

/* Reverses the initial row of ca. */
static void reverse_row(SqCa *ca)
{
    for (int i = 0, j = ca->ncells - 1; i < j; i++, j--) {
        const uint8_t t = ca->cells[i];
        ca->cells[i] = ca->cells[j];
        ca->cells[j] = t;
    }
}

/* Folds the lightness at period T into R rows; returns 0 when it has no contrast. */
static int fold(const float *y, const float *w, int L, double T, Fold *f)
{
    double acc[BW * R] = {0}, cnt[BW * R] = {0};
    for (int j = 0; j < L; j++) {
        const double ph = j / T - floor(j / T);
        const int t = (int)(ph * R) % R;
        for (int x = 0; x < BW; x++) {
            acc[t * BW + x] += w[(size_t)j * BW + x] * y[(size_t)j * BW + x];
            cnt[t * BW + x] += w[(size_t)j * BW + x];
        }
    }
    double m = 0, nm = 0;
    for (int i = 0; i < BW * R; i++)
        if (cnt[i] > 0) {
            acc[i] /= cnt[i];
            m += acc[i];
            nm++;
        }
    m = nm > 0 ? m / nm : 0;
    double ss = 0;
    for (int i = 0; i < BW * R; i++) {
        acc[i] = cnt[i] > 0 ? acc[i] - m : 0;
        ss += acc[i] * acc[i];
    }
    if (!(ss > 1e-12))
        return 0;
    const double inv = 1 / sqrt(ss);
    f->T = T;
    for (int t = 0; t < R; t++)
        for (int x = 0; x < BW; x++)
            f->p[1][(R - 1 - t) * BW + x] = f->p[0][t * BW + x] = (float)(acc[t * BW + x] * inv);
    float v[BW * R];
    memcpy(v, f->p[0], sizeof v);
    qsort(v, BW * R, sizeof *v, cmp_float);
    const float lo = v[BW * R / 50], hi = v[BW * R - 1 - BW * R / 50];
    for (int i = 0; i < BW * R; i++)
        v[i] = hi > lo ? (f->p[0][i] - lo) / (hi - lo) : 0.5f;
    for (int dir = 0; dir < 2; dir++)
        group_profiles(f->p[dir], f->g[dir]);
    cumulative(v, BW * R, 0, f->cdf[0]);
    cumulative(v, BW * R, 1, f->cdf[1]);
    return 1;
}

/* The radius of the box blur that, three times over, is close to a Gaussian of sigma
 * samples, on a cyclic line of n (at most n - 1; 0: no blur). */
static int box_radius(double sigma, int n)
{
    const int r = (int)lround((sqrt(4 * sigma * sigma + 1) - 1) / 2);
    return r < 1 ? 0 : r < n ? r : n - 1;
}

/* A cyclic blur of one line of n values (n <= TW) close to a Gaussian of sigma samples:
 * three box blurs of the same variance, by running sums over the line wrapped. */
static void blur_line(float *v, int n, double sigma)
{
    const int rr = box_radius(sigma, n);
    if (rr < 1)
        return;
    float ext[TW + 2 * TW];
    for (int pass = 0; pass < 3; pass++) {
        for (int i = -rr; i < n + rr; i++)
            ext[i + rr] = v[(i + n) % n];
        double acc = 0;
        for (int i = 0; i < 2 * rr + 1; i++)
            acc += ext[i];
        for (int i = 0; i < n; i++) {
            v[i] = (float)(acc / (2 * rr + 1));
            if (i + 1 < n)
                acc += ext[i + 2 * rr + 1] - ext[i];
        }
    }
}

/* blur_line on each of the TW columns of c (TW x R), all columns at once: the same sums
 * in the same order, a row of them at a time. */
static void blur_columns(float *c, double sigma)
{
    const int rr = box_radius(sigma, R);
    if (rr < 1)
        return;
    float in[R * TW];
    double acc[TW];
    for (int pass = 0; pass < 3; pass++) {
        memcpy(in, c, sizeof in);
        for (int x = 0; x < TW; x++)
            acc[x] = 0;
        for (int i = -rr; i <= rr; i++) {
            const float *row = in + (size_t)((i + R) % R) * TW;
            for (int x = 0; x < TW; x++)
                acc[x] += row[x];
        }
        for (int i = 0; i < R; i++) {
            for (int x = 0; x < TW; x++)
                c[i * TW + x] = (float)(acc[x] / (2 * rr + 1));
            if (i + 1 < R) {
                const float *add = in + (size_t)((i + rr + 1) % R) * TW, *sub = in + (size_t)((i - rr + R) % R) * TW;
                for (int x = 0; x < TW; x++)
                    acc[x] += add[x] - sub[x];
            }
        }
    }
}

/* The pattern of a, TW x R over the whole tile: coverage, blurred (amount in 1/256 of a
 * square texture's width, as Pattern_BlurAmount) and sharpened (Pattern_Contrast). */
static int pattern(const SqCa *ca, const Ind *a, float *c)
{
    if (sq_ca_coverage(ca, a->diameter, c, TW, R, NULL) != SQ_OK)
        return -1;
    const double su = a->blur * TW / 256.0, sv = a->blur * R / 256.0;
    for (int t = 0; t < R; t++)
        blur_line(c + (size_t)t * TW, TW, su);
    blur_columns(c, sv);
    if (a->contrast > 0) {
        const float k = a->contrast >= 0.999 ? 1000.0f : (float)(1 / (1 - a->contrast));
        for (int i = 0; i < TW * R; i++) {
            const float v = (c[i] - 0.5f) * k + 0.5f;
            c[i] = v < 0 ? 0 : v > 1 ? 1 : v;
        }
    }
    return 0;
}

/* Scores a: the largest correlation, in size, of its pattern in the band with the fold,
 * over every phase along, both directions, every rotation of its initial row by whole
 * cells and its reversal. */
static void score(const Fold *f, double band_centre, Ind *a)
{
    /* the band twice over along, so that every phase d is a contiguous run from row d */
    float c[TW * R], band[2 * R * BW], g[2 * R * G];
    a->corr = 0;
    a->fit = -INFINITY;
    a->k = a->rev = 0;
    SqCa ca = a->ca;
    const int n = ca.ncells;
    for (int rev = 0; rev < 2; rev++) {
        if (rev)
            reverse_row(&ca);
        if (pattern(&ca, a, c) != 0)
            return;
        for (int k = 0; k < n; k++) {
            /* rotated right by k cells, the pattern moves by k/n of the width */
            const double x0 = (band_centre - 1.0 / 6) * TW - (double)k * TW / n;
            for (int x = 0; x < BW; x++) {
                const double X = x0 + x, fx = floor(X);
                const float t = (float)(X - fx);
                const int i0 = (((int)fx % TW) + TW) % TW, i1 = (i0 + 1) % TW;
                for (int r = 0; r < R; r++)
                    band[r * BW + x] = c[r * TW + i0] * (1 - t) + c[r * TW + i1] * t;
            }
            memcpy(band + R * BW, band, sizeof(float) * R * BW);
            float m = 0;
#pragma omp simd reduction(+ : m)
            for (int i = 0; i < BW * R; i++)
                m += band[i];
            m /= BW * R;
            float ss = 0;
#pragma omp simd reduction(+ : ss)
            for (int i = 0; i < BW * R; i++)
                ss += (band[i] - m) * (band[i] - m);
            if (!(ss > 1e-9f))
                continue;
            const double inv = 1 / sqrt(ss);
            float cdf[HB];
            cumulative(band, BW * R, 0, cdf);
            const double dist[2] = {emd(cdf, f->cdf[0]), emd(cdf, f->cdf[1])}; /* + and - correlated */
            /* the phases along where the band's and the fold's profiles in G groups of
             * columns agree best (either way along), then the whole correlation there */
            group_profiles(band, g);
            memcpy(g + R * G, g, sizeof(float) * R * G);
            for (int dir = 0; dir < 2; dir++) {
                float pc[R];
                for (int d = 0; d < R; d++)
                    pc[d] = fabsf(dot(f->g[dir], g + d * G, R * G));
                for (int pick = 0; pick < PHASES; pick++) {
                    int d = 0;
                    for (int e = 1; e < R; e++)
                        if (pc[e] > pc[d])
                            d = e;
                    pc[d] = -1;
                    const double corr = dot(f->p[dir], band + d * BW, R * BW) * inv;
                    const double fit = fabs(corr) - DIST_W * dist[corr < 0];
                    if (fit > a->fit) {
                        a->fit = fit;
                        a->corr = corr;
                        a->k = k;
                        a->rev = rev;
                    }
                }
            }
        }
    }
}

/* a's automaton turned the way its best correlation saw it. */
static SqCa realised(const Ind *a)
{
    SqCa ca = a->ca;
    const int n = ca.ncells;
    if (a->rev)
        reverse_row(&ca);
    uint8_t row[SQ_CA_MAX_CELLS];
    for (int i = 0; i < n; i++)
        row[(i + a->k) % n] = ca.cells[i];
    memcpy(ca.cells, row, (size_t)n);
    return ca;
}

static double uni(uint64_t *r)
{
    return (double)(sq__splitmix(r) >> 11) * 0x1.0p-53;
}

static double normal(uint64_t *r)
{
    const double u = uni(r) + 1e-12, v = uni(r);
    return sqrt(-2 * log(u)) * cos(6.283185307179586 * v);
}

static void random_ind(uint64_t *r, Ind *a)
{
    sq_gp_ca_random(r, &a->ca);
    if (a->ca.ncells > NMAX)
        a->ca.ncells = 6 + (int)(uni(r) * (NMAX - 5));
    a->diameter = 0.5 + uni(r);
    a->blur = 12 * uni(r);
    a->contrast = 0.9 * uni(r);
}

static void mutate(uint64_t *r, Ind *a)
{
    const double u = uni(r);
    if (u < 0.45)
        sq_gp_ca_point_mutate(r, &a->ca);
    else if (u < 0.65)
        sq_gp_ca_struct_mutate(r, &a->ca);
    else if (u < 0.8)
        a->diameter = clampd(a->diameter * exp(0.2 * normal(r)), 0.3, 2.0);
    else if (u < 0.9)
        a->blur = clampd(a->blur + 2 * normal(r), 0, 16);
    else
        a->contrast = clampd(a->contrast + 0.15 * normal(r), 0, 0.95);
}

static int by_fit(const void *x, const void *y)
{
    const double a = ((const Ind *)x)->fit, b = ((const Ind *)y)->fit;
    return (a < b) - (a > b);
}

int sq_fit_read_automata(const SqImage *strip, const SqImage *valid, double band_centre, uint64_t seed,
                         SqCaReading *out, int max)
{
    if (!strip || !strip->px || strip->width != SQ_FIT_STRIP_W || strip->channels < 3 || max <= 0 ||
        (valid && (!valid->px || valid->width != strip->width || valid->height != strip->height)))
        return 0;
    const int L = strip->height;
    float *y = malloc(sizeof(float) * (size_t)L * BW), *w = malloc(sizeof(float) * (size_t)L * BW);
    Ind *pop = malloc(sizeof *pop * INIT * PERIODS);
    Fold *folds = malloc(sizeof *folds * PERIODS);
    int found = 0;
    if (!y || !w || !pop || !folds)
        goto done;
    lightness(strip, valid, y, w);
    double T[PERIODS];
    int np = periods(y, w, L, T), nf = 0;
    for (int i = 0; i < np; i++)
        nf += fold(y, w, L, T[i], &folds[nf]);
    Ind best[PERIODS * CLIMBERS];
    int nbest = 0;
    for (int p = 0; p < nf; p++) {
        Ind *pp = pop + (size_t)p * INIT;
#pragma omp parallel for schedule(dynamic, 8)
        for (int i = 0; i < INIT; i++) {
            uint64_t r = seed ^ (0x9e3779b97f4a7c15ULL * (uint64_t)(p * INIT + i + 1));
            random_ind(&r, &pp[i]);
            score(&folds[p], band_centre, &pp[i]);
        }
        qsort(pp, INIT, sizeof *pp, by_fit);
        Ind *cl = best + nbest;
#pragma omp parallel for schedule(dynamic, 1)
        for (int c = 0; c < CLIMBERS; c++) {
            uint64_t r = seed ^ (0xd1b54a32d192ed03ULL * (uint64_t)(p * CLIMBERS + c + 1));
            Ind a = pp[c];
            for (int s = 0; s < STEPS; s++) {
                Ind b = a;
                mutate(&r, &b);
                score(&folds[p], band_centre, &b);
                if (b.fit >= a.fit)
                    a = b;
            }
            cl[c] = a;
        }
        nbest += CLIMBERS;
    }
    /* best first, one reading per distinct automaton */
    int order[PERIODS * CLIMBERS];
    for (int i = 0; i < nbest; i++)
        order[i] = i;
    for (int i = 1; i < nbest; i++)
        for (int j = i; j > 0 && best[order[j]].fit > best[order[j - 1]].fit; j--) {
            int t = order[j];
            order[j] = order[j - 1];
            order[j - 1] = t;
        }
    for (int i = 0; i < nbest && found < max; i++) {
        const Ind *a = &best[order[i]];
        SqCa ca = realised(a);
        int dup = 0;
        for (int j = 0; j < found; j++)
            dup |= sq_ca_equal(&out[j].ca, &ca);
        if (dup)
            continue;
        SqCaReading *o = &out[found++];
        o->ca = ca;
        o->diameter = a->diameter;
        o->blur = a->blur;
        o->contrast = a->contrast;
        o->corr = a->corr;
        o->view_scale = folds[order[i] / CLIMBERS].T / (SQ_FIT_STRIP_W / SQ_FIT_BAND_WIDTH);
    }
done:
    free(y);
    free(w);
    free(pop);
    free(folds);
    return found;
}
