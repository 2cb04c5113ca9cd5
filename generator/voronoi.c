/* The Voronoi scale layout (Scales_Layout voronoi): the leaf-shaped scale of §4.3.1 on
 * an anisotropic centroidal Voronoi tessellation (Landreneau 2011, Chapter V) instead of
 * the thesis' staggered grid (§4.3.2).
 *
 * Metric. Distances are in scale spacings: u is scaled by X sqrt(2) and v by Y / sqrt(2)
 * (X, Y = Scales_XAmount, Scales_YAmount), which makes the grid layout's cells (rhombi
 * one column wide and two rows tall: the Voronoi cells of its staggered rows) squares
 * of unit area turned 45 degrees. An isotropic tessellation thus keeps the grid's
 * proportions for any X and Y. Landreneau's anisotropy makes every site a line segment
 * along the body (v) of half-length alpha = Scales_VoronoiAnisotropy: a point's
 * distance to a site is its distance to the nearest point of that segment,
 * sqrt(du^2 + max(0, |dv| - alpha)^2) (plus TIE dv^2, below), which stretches the
 * cells along the body and turns hexagons towards rhombi, as in his Figure 17.
 * Everything wraps in u and v.
 *
 * Sites. The X * Y sites start on a staggered grid (odd rows half a column over),
 * jittered by up to JITTER of a column and a row from the preset's Seed. The lateral
 * line: Landreneau's artist-drawn row of scales that fixes the rest's orientation; for
 * reptiles "the closest analog to a lateral line ... might be backbone scales ... a row
 * of scales corresponding directly to the spine" (Chapter IV), and his lizard has it
 * "painted down its back" (Figure 28). Here it is the dorsal midline u = 0.5: the
 * first site of every other starting row (the stagger's spacing), evenly spaced along
 * v, unjittered and held fixed by the relaxation. It is straight along v, so the
 * orientation field he smooths from it is v everywhere: sites need no orientation.
 *
 * Relaxation. Lloyd's algorithm on a raster of RELAX samples per spacing each way (a
 * property of the parameters, never of the texture size: a preset looks the same at any
 * size): every sample finds its nearest site (each site, row by row, marks the span of
 * samples within a spacing of it where it is nearer than what they have; a sample with
 * no site that near tries them all), then every free
 * site moves to its cell's centroid. The cells the scales are
 * fitted to come from a last, finer raster (FINE per spacing). Sums run in raster order,
 * so the result is the same on any thread count.
 *
 * Scales. Each cell gets one stamp, upright along the body (plus
 * Scales_RotationRandom), centred on the cell's bounding box, with the box's
 * proportions, and enlarged until its lens covers every sample of the cell: no cell
 * shows a hole, and like the grid's lenses (which cover their rhombi exactly) each
 * scale reaches a little over its neighbours. Scales_ScaleSize and Scales_ScaleSizeXY
 * scale that, relative to the default (1, 2) that gives the grid's scales their cells.
 * The painting order is the grid's: scales higher up (lower v) cover lower ones, and
 * of two at one height the right one covers the left.
 *
 * Ventral scales (§4.3.3) as in the grid: in every starting row the cell nearest
 * Scales_BellyScalesPct of the width (and nearest 1 - that) is the last lateral scale;
 * cells beyond it are left out and its centre column is stretched to the seam. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen_internal.h"

enum { RELAX = 3, FINE = 6, MAX_SAMPLES = 1 << 20 };
static const double JITTER = 0.35;  /* of a column and of a row */
static const double COVER = 1.04;   /* lens margin over the cell, for the stamp's soft edge */
/* Where segments overlap (sites one above the other, closer than 2 alpha) the segment
 * distance ties at 0 and a site could lose its whole cell; a small share of the
 * distance along v to the site's centre splits such ties by the nearer centre. */
static const double TIE = 0.05;
/* How far each site looks for the samples it may be nearest to, in spacings: nearly
 * every sample has a site this near (the farthest, 1.19, on layouts one row tall); the
 * rest try every site. Nearer (0.8, 0.9) or farther (1.15, 1.3) is no faster. */
static const double REACH = 1.0;
/* A ventral stretch bends to its row's place over the first 1 / BEND of its length and
 * runs straight from there to the seam. */
static const float BEND = 3.0f;

static double wrapd(double d, double D) /* into [-D/2, D/2) */
{
    return d - D * floor(d / D + 0.5);
}

/* wrapd for |d| < 1.5 D, without floor(): the inner loop of the nearest-site search */
static inline double wrap_near(double d, double D)
{
    return d >= 0.5 * D ? d - D : (d < -0.5 * D ? d + D : d);
}

static double wrap01(double x, double D) /* into [0, D) */
{
    x -= D * floor(x / D);
    return x >= D ? 0 : x;
}

void sq__voronoi_free(SqVoronoi *vo)
{
    if (!vo)
        return;
    free(vo->u);
    free(vo->v);
    free(vo->fixed);
    free(vo->owner);
    free(vo->area);
    free(vo->cu);
    free(vo->cv);
    free(vo->bu0);
    free(vo->bu1);
    free(vo->bv0);
    free(vo->bv1);
    memset(vo, 0, sizeof *vo);
}

/* Sites in spacings (U in [0, DU), V in [0, DV)), sorted into bands along v. */
typedef struct Space {
    double DU, DV, a, reach;
    int n, nbv, kv;
    double *U, *V;
    int *start, *list; /* bands: the sites of band b are list[start[b] .. start[b + 1]) */
} Space;

static void space_free(Space *S)
{
    free(S->U);
    free(S->V);
    free(S->start);
    free(S->list);
}

static int band_of(const Space *S, double V)
{
    int b = (int)(V / S->DV * S->nbv);
    return b < 0 ? 0 : (b >= S->nbv ? S->nbv - 1 : b);
}

/* Counting sort of the sites into bands, in site order. */
static void band_sites(Space *S)
{
    memset(S->start, 0, sizeof(int) * (size_t)(S->nbv + 1));
    for (int k = 0; k < S->n; k++)
        S->start[band_of(S, S->V[k]) + 1]++;
    for (int b = 0; b < S->nbv; b++)
        S->start[b + 1] += S->start[b];
    int *fill = S->start + S->nbv + 1; /* nbv more ints of room */
    memcpy(fill, S->start, sizeof(int) * (size_t)S->nbv);
    for (int k = 0; k < S->n; k++)
        S->list[fill[band_of(S, S->V[k])]++] = k;
}

/* An offset on a wrapped axis of length D, folded into [0, D / 2]. */
static inline double fold(double d, double D)
{
    d = fabs(d);
    return d < D - d ? d : D - d;
}

/* The segment distance from the folded offsets across (du) and along (dc), dv = dc less
 * the segment's half-length (at least 0): in one place for both of assign()'s paths, so
 * that equal is equal on any compiler (a fused multiply-add contracts it alike). */
static inline double seg_dist(double du, double dv, double dc)
{
    return du * du + dv * dv + TIE * dc * dc;
}

/* Threads for rasters big enough to pay for waking them (a relaxation raster of the
 * default 16 x 32 scales has about 4600 samples). */
enum { PARALLEL_SAMPLES = 1 << 12 };

/* Every sample's nearest site by the segment distance, ties to the lower index. Row by
 * row, each site within S->reach along v marks the samples within reach of it (a span
 * of the row) where it is nearer than what they have; the sites within reach of a
 * sample are all visited, so a sample left with nothing that near (a few, where the
 * jittered grid leaves a hole) has every site tried. bestd: rw * rh doubles of
 * scratch; ucol: the rw columns' U. */
static void assign(const Space *S, int rw, int rh, const double *ucol, int *owner, double *bestd)
{
    const double DU = S->DU, DV = S->DV, a = S->a, R2 = S->reach * S->reach, step = DU / rw;
#pragma omp parallel for schedule(static) if ((size_t)rw * rh >= PARALLEL_SAMPLES)
    for (int y = 0; y < rh; y++) {
        const double V = (y + 0.5) / rh * DV;
        int *own = owner + (size_t)y * rw;
        double *bd = bestd + (size_t)y * rw;
        for (int x = 0; x < rw; x++) {
            bd[x] = INFINITY;
            own[x] = -1;
        }
        const int b = band_of(S, V);
        const int lo = 2 * S->kv + 1 >= S->nbv ? 0 : b - S->kv, hi = 2 * S->kv + 1 >= S->nbv ? S->nbv - 1 : b + S->kv;
        for (int jb = lo; jb <= hi; jb++) {
            const int c = sq__wrap(jb, S->nbv);
            for (int i = S->start[c]; i < S->start[c + 1]; i++) {
                const int k = S->list[i];
                const double dc = fold(V - S->V[k], DV), dv = dc - a > 0 ? dc - a : 0, Uk = S->U[k];
                const double dva = seg_dist(0, dv, dc); /* no less than any sample's in the row */
                if (dva >= R2) /* no sample of the row within reach */
                    continue;
                /* the samples within reach across, in columns, and one more either way for
                 * rounding */
                const double w = sqrt(R2 - dva) / step;
                int x0 = (int)floor(Uk / step - 0.5 - w) - 1, x1 = (int)ceil(Uk / step - 0.5 + w) + 1;
                if (x1 - x0 + 1 >= rw) {
                    x0 = 0;
                    x1 = rw - 1;
                }
                /* the span as at most two runs of the row: the wrap taken apart */
                int a0 = x0, a1 = x1, b1 = -1;
                if (x0 < 0) {
                    a0 = x0 + rw;
                    a1 = rw - 1;
                    b1 = x1;
                } else if (x1 >= rw) {
                    a1 = rw - 1;
                    b1 = x1 - rw;
                }
                const int runs[2][2] = {{a0, a1}, {0, b1}};
                for (int r = 0; r < 2; r++)
                    for (int x = runs[r][0]; x <= runs[r][1]; x++) {
                        const double d = seg_dist(fold(ucol[x] - Uk, DU), dv, dc);
                        const int nearer = (d < bd[x]) | ((d == bd[x]) & (k < own[x]));
                        bd[x] = nearer ? d : bd[x];
                        own[x] = nearer ? k : own[x];
                    }
            }
        }
        for (int x = 0; x < rw; x++)
            if (!(bd[x] < R2)) /* nothing within reach: every site */
                for (int k = 0; k < S->n; k++) {
                    const double dc = fold(V - S->V[k], DV), dv = dc - a > 0 ? dc - a : 0;
                    const double d = seg_dist(fold(ucol[x] - S->U[k], DU), dv, dc);
                    if (d < bd[x] || (d == bd[x] && k < own[x])) {
                        bd[x] = d;
                        own[x] = k;
                    }
                }
    }
}

/* A raster of about k samples per spacing each way, at most MAX_SAMPLES in all. */
static void raster_size(const Space *S, double k, int *rw, int *rh)
{
    if (S->DU * S->DV * k * k > MAX_SAMPLES)
        k = sqrt(MAX_SAMPLES / (S->DU * S->DV));
    *rw = (int)ceil(S->DU * k) > 8 ? (int)ceil(S->DU * k) : 8;
    *rh = (int)ceil(S->DV * k) > 8 ? (int)ceil(S->DV * k) : 8;
}

SqStatus sq__voronoi_build(const SqParams *p, int iterations, SqVoronoi *vo, SqError *err)
{
    return sq__voronoi_build_reach(p, iterations, REACH, vo, err);
}

SqStatus sq__voronoi_build_reach(const SqParams *p, int iterations, double reach, SqVoronoi *vo, SqError *err)
{
    memset(vo, 0, sizeof *vo);
    const int X = p->Scales_XAmount, Y = p->Scales_YAmount, n = X * Y;
    Space S = {.DU = X * M_SQRT2, .DV = Y / M_SQRT2, .a = p->Scales_VoronoiAnisotropy, .reach = reach, .n = n};
    int rw, rh, qw, qh; /* the final raster and the relaxation's */
    raster_size(&S, FINE, &rw, &rh);
    raster_size(&S, RELAX, &qw, &qh);
    S.nbv = S.DV >= 2 ? (int)S.DV : 1;
    /* a band is a spacing wide or more (or all of v): the sites within reach of a row, plus the
     * segment's reach along v, are in the bands this far either way */
    S.kv = (int)ceil((reach + S.a) / (S.DV / S.nbv));
    const size_t ns = (size_t)rw * rh, nq = (size_t)qw * qh;
    S.U = malloc(sizeof(double) * (size_t)n);
    S.V = malloc(sizeof(double) * (size_t)n);
    S.start = malloc(sizeof(int) * (size_t)(2 * S.nbv + 1));
    S.list = malloc(sizeof(int) * (size_t)n);
    double *bestd = malloc(sizeof(double) * (ns > nq ? ns : nq));
    double *ucol = malloc(sizeof(double) * (size_t)(rw > qw ? rw : qw));
    double *sum = malloc(sizeof(double) * 4 * (size_t)n); /* du, dv and, for the box, ranges */
    vo->n = n;
    vo->X = X;
    vo->Y = Y;
    vo->rw = rw;
    vo->rh = rh;
    vo->u = malloc(sizeof(double) * (size_t)n);
    vo->v = malloc(sizeof(double) * (size_t)n);
    vo->fixed = calloc((size_t)n, 1);
    vo->owner = malloc(sizeof(int) * (ns > nq ? ns : nq));
    vo->area = malloc(sizeof(int) * (size_t)n);
    vo->cu = malloc(sizeof(double) * (size_t)n);
    vo->cv = malloc(sizeof(double) * (size_t)n);
    vo->bu0 = malloc(sizeof(double) * (size_t)n);
    vo->bu1 = malloc(sizeof(double) * (size_t)n);
    vo->bv0 = malloc(sizeof(double) * (size_t)n);
    vo->bv1 = malloc(sizeof(double) * (size_t)n);
    if (!S.U || !S.V || !S.start || !S.list || !bestd || !ucol || !sum || !vo->u || !vo->v || !vo->fixed ||
        !vo->owner || !vo->area || !vo->cu || !vo->cv || !vo->bu0 || !vo->bu1 || !vo->bv0 ||
        !vo->bv1) {
        space_free(&S);
        free(bestd);
        free(ucol);
        free(sum);
        sq__voronoi_free(vo);
        return sq_error_set(err, SQ_ERR_NOMEM, "Scales_Layout",
                            "out of memory for the Voronoi layout of %d scales", n);
    }

    /* the jittered staggered grid, and the lateral line down the back */
    const uint64_t seed = (uint64_t)p->Seed;
    for (int j = 0; j < Y; j++)
        for (int c = 0; c < X; c++) {
            const int s = j * X + c;
            const double ju = JITTER * sq__rand11(seed, SQ_STREAM_VORONOI, 2 * (uint64_t)s);
            const double jv = JITTER * sq__rand11(seed, SQ_STREAM_VORONOI, 2 * (uint64_t)s + 1);
            S.U[s] = wrap01((0.5 + (c + 0.5 * (j & 1) + ju) / X) * S.DU, S.DU);
            S.V[s] = wrap01((j + 0.5 + jv) / Y * S.DV, S.DV);
        }
    const int lines = Y / 2 > 0 ? Y / 2 : 1;
    for (int i = 0; i < lines; i++) {
        const int s = 2 * i * X; /* column 0 of row 2i: its unjittered place is u = 0.5 */
        S.U[s] = 0.5 * S.DU;
        S.V[s] = (i + 0.25) / lines * S.DV;
        vo->fixed[s] = 1;
    }

    for (int it = 0; it < iterations; it++) {
        band_sites(&S);
        for (int x = 0; x < qw; x++)
            ucol[x] = (x + 0.5) / qw * S.DU;
        assign(&S, qw, qh, ucol, vo->owner, bestd);
        memset(sum, 0, sizeof(double) * 2 * (size_t)n);
        memset(vo->area, 0, sizeof(int) * (size_t)n);
        for (int y = 0; y < qh; y++) {
            const double V = (y + 0.5) / qh * S.DV;
            for (int x = 0; x < qw; x++) {
                const int o = vo->owner[(size_t)y * qw + x];
                sum[2 * o] += wrap_near((x + 0.5) / qw * S.DU - S.U[o], S.DU);
                sum[2 * o + 1] += wrap_near(V - S.V[o], S.DV);
                vo->area[o]++;
            }
        }
        for (int s = 0; s < n; s++)
            if (!vo->fixed[s] && vo->area[s] > 0) {
                S.U[s] = wrap01(S.U[s] + sum[2 * s] / vo->area[s], S.DU);
                S.V[s] = wrap01(S.V[s] + sum[2 * s + 1] / vo->area[s], S.DV);
            }
    }

    band_sites(&S);
    for (int x = 0; x < rw; x++)
        ucol[x] = (x + 0.5) / rw * S.DU;
    assign(&S, rw, rh, ucol, vo->owner, bestd);
    free(bestd);
    free(ucol);

    /* the cells: area, centroid and bounding box, in texture units */
    for (int s = 0; s < n; s++) {
        vo->area[s] = 0;
        sum[4 * s] = sum[4 * s + 1] = 0;
        vo->bu0[s] = vo->bv0[s] = INFINITY;
        vo->bu1[s] = vo->bv1[s] = -INFINITY;
    }
    for (int y = 0; y < rh; y++) {
        const double V = (y + 0.5) / rh * S.DV;
        for (int x = 0; x < rw; x++) {
            const int o = vo->owner[(size_t)y * rw + x];
            const double du = wrap_near((x + 0.5) / rw * S.DU - S.U[o], S.DU) / S.DU;
            const double dv = wrap_near(V - S.V[o], S.DV) / S.DV;
            sum[4 * o] += du;
            sum[4 * o + 1] += dv;
            vo->area[o]++;
            vo->bu0[o] = du < vo->bu0[o] ? du : vo->bu0[o];
            vo->bu1[o] = du > vo->bu1[o] ? du : vo->bu1[o];
            vo->bv0[o] = dv < vo->bv0[o] ? dv : vo->bv0[o];
            vo->bv1[o] = dv > vo->bv1[o] ? dv : vo->bv1[o];
        }
    }
    for (int s = 0; s < n; s++) {
        vo->u[s] = S.U[s] / S.DU;
        vo->v[s] = S.V[s] / S.DV;
        if (vo->area[s] == 0) { /* a site without samples: an empty box at the site */
            vo->bu0[s] = vo->bu1[s] = vo->bv0[s] = vo->bv1[s] = 0;
            vo->cu[s] = vo->u[s];
            vo->cv[s] = vo->v[s];
            continue;
        }
        vo->cu[s] = vo->u[s] + sum[4 * s] / vo->area[s];
        vo->cv[s] = vo->v[s] + sum[4 * s + 1] / vo->area[s];
    }
    space_free(&S);
    free(sum);
    return SQ_OK;
}

double sq__voronoi_energy(const SqVoronoi *vo)
{
    const double DU = vo->X * M_SQRT2, DV = vo->Y / M_SQRT2;
    double e = 0;
    for (int y = 0; y < vo->rh; y++)
        for (int x = 0; x < vo->rw; x++) {
            const int o = vo->owner[(size_t)y * vo->rw + x];
            const double du = wrapd((x + 0.5) / vo->rw - vo->cu[o], 1) * DU;
            const double dv = wrapd((y + 0.5) / vo->rh - vo->cv[o], 1) * DV;
            e += du * du + dv * dv;
        }
    return e / ((double)vo->rw * vo->rh);
}

/* ---- painting ---- */

/* One scale, in texture units: centre, lens half-sizes, and how it is drawn. */
typedef struct Scale {
    double u, v, hu, hv; /* centre in [0, 1); lens half-width and half-height */
    double th;           /* rotation, radians */
    int role;            /* belly role as in scales.c: 0 lateral, 1/2/3 last lateral, -1 none */
    int row;             /* starting row (the belly's wobble phase) */
    double sv, shv;      /* ventral stretch: centre offset and half-height at the seam */
} Scale;

typedef struct Inst {
    double cx, cy; /* unwrapped centre, pixels */
    int k;
} Inst;

static int inst_cmp(const void *a, const void *b)
{
    const Inst *x = a, *y = b;
    if (x->cy != y->cy)
        return x->cy < y->cy ? -1 : 1;
    if (x->cx != y->cx) /* the right one in front */
        return x->cx > y->cx ? -1 : 1;
    return (x->k > y->k) - (x->k < y->k);
}

/* The smallest factor by which the lens (half-sizes LENS_HW x LENS_HH in stamp units)
 * must grow to contain the point (X, Y), X >= 0: where (|X| / l + D)^2 + (Y / l)^2 = R^2. */
static double lens_reach(double X, double Y)
{
    const double A = X * X + Y * Y, B = 2 * SQ__CONE_D * X;
    const double C = SQ__CONE_D * SQ__CONE_D - SQ__CONE_R * SQ__CONE_R;
    if (A <= 0)
        return 0;
    const double t = (-B + sqrt(B * B - 4 * A * C)) / (2 * A);
    return 1 / t;
}

/* The scales of a tessellation; NULL when out of memory. */
static Scale *make_scales(const SqParams *p, const SqVoronoi *vo)
{
    const int n = vo->n, X = vo->X, Y = vo->Y;
    Scale *sc = malloc(sizeof(Scale) * (size_t)n);
    double *lam = calloc((size_t)n, sizeof(double));
    if (!sc || !lam) {
        free(sc);
        free(lam);
        return NULL;
    }
    const double hsu = 0.5 / vo->rw, hsv = 0.5 / vo->rh; /* half a raster step */
    for (int s = 0; s < n; s++) {
        sc[s].hu = (vo->bu1[s] - vo->bu0[s]) / 2 + hsu;
        sc[s].hv = (vo->bv1[s] - vo->bv0[s]) / 2 + hsv;
        sc[s].u = wrap01(vo->u[s] + (vo->bu0[s] + vo->bu1[s]) / 2, 1);
        sc[s].v = wrap01(vo->v[s] + (vo->bv0[s] + vo->bv1[s]) / 2, 1);
    }
    /* the lens, with the box's proportions, grown to reach every sample's far corner */
    for (int y = 0; y < vo->rh; y++)
        for (int x = 0; x < vo->rw; x++) {
            const int o = vo->owner[(size_t)y * vo->rw + x];
            const double du = fabs(wrap_near((x + 0.5) / vo->rw - sc[o].u, 1)) + hsu;
            const double dv = fabs(wrap_near((y + 0.5) / vo->rh - sc[o].v, 1)) + hsv;
            const double l = lens_reach(du / sc[o].hu * SQ__LENS_HW, dv / sc[o].hv * SQ__LENS_HH);
            lam[o] = l > lam[o] ? l : lam[o];
        }
    const double rot_max = p->Scales_RotationRandom * M_PI / 180.0;
    const double fu = p->Scales_ScaleSize * p->Scales_ScaleSizeXY[0];
    const double fv = p->Scales_ScaleSize * p->Scales_ScaleSizeXY[1] / 2;
    const uint64_t seed = (uint64_t)p->Seed;
    for (int s = 0; s < n; s++) {
        const uint64_t id = 4 * (uint64_t)s;
        const double size = 1.0 - p->Scales_SizeRandom * sq__rand01(seed, SQ_STREAM_SCALES, id + 2);
        const double l = (lam[s] > 1 ? lam[s] : 1) * COVER * size;
        sc[s].hu *= l * fu;
        sc[s].hv *= l * fv;
        sc[s].th = rot_max * sq__rand11(seed, SQ_STREAM_SCALES, id + 3);
        sc[s].row = s / X;
        sc[s].role = 0;
        sc[s].sv = 0;
        sc[s].shv = sc[s].hv;
    }
    free(lam);

    /* ventral scales: per starting row, the last lateral cells beside the belly */
    const double pct = p->Scales_BellyScalesPct;
    if (pct > 0)
        for (int j = 0; j < Y; j++) {
            int left = 0, right = 0;
            double bl = 2, br = 2;
            for (int c = 0; c < X; c++) {
                const double f = sc[j * X + c].u;
                if (fabs(f - pct) < bl) {
                    bl = fabs(f - pct);
                    left = c;
                }
                if (fabs(f - (1 - pct)) < br) {
                    br = fabs(f - (1 - pct));
                    right = c;
                }
            }
            Scale *L = &sc[j * X + left], *R = &sc[j * X + right];
            const double fl = L->u, fr = R->u;
            for (int c = 0; c < X; c++) {
                Scale *e = &sc[j * X + c];
                e->role = (c == left ? 1 : 0) | (c == right ? 2 : 0);
                if (!e->role && (e->u < fl || e->u > fr))
                    e->role = -1;
            }
            /* The two stretches of a row meet at the seam: each bends (from its scale's
             * centre, over a third of the way) to the row's place and the grid layout's
             * scale height, so the ventral scale is whole across the seam and the ventral
             * scales are even along the belly, as a snake's are, whatever the cells. */
            if (left != right) {
                const double vj = (j + 0.5) / Y;
                const double mh = p->Scales_ScaleSize * p->Scales_ScaleSizeXY[1] / (2.0 * Y);
                L->sv = wrapd(vj - L->v, 1);
                R->sv = wrapd(vj - R->v, 1);
                L->shv = R->shv = mh;
            }
        }
    return sc;
}

/* Paints the scales into a w x h height map (trans: w x h scratch). */
static SqStatus paint(const SqParams *p, const Scale *sc, int n, const float *stamp, int s,
                      const int *span, double ex, double ey, float *height, float *trans, int w,
                      int h, SqError *err)
{
    /* every copy of every drawn scale that reaches the texture, sorted front to back */
    size_t ni = 0, cap = (size_t)n * 2 + 16;
    Inst *in = malloc(sizeof(Inst) * cap);
    double *ext = malloc(sizeof(double) * 2 * (size_t)n); /* pixel half-extents */
    float *wob = malloc(sizeof(float) * (size_t)w);
    if (!in || !ext || !wob) {
        free(in);
        free(ext);
        free(wob);
        return sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
    }
    double ry_max = 0;
    for (int k = 0; k < n; k++) {
        double rx = ex * sc[k].hu * w / SQ__LENS_HW, ry = ey * sc[k].hv * h / SQ__LENS_HH;
        if (sc[k].th != 0)
            rx = ry = sqrt(rx * rx + ry * ry);
        if (sc[k].role > 0) { /* the stretch bends towards the seam */
            const double rs = ey * sc[k].shv * h / SQ__LENS_HH + fabs(sc[k].sv) * h;
            ry = rs > ry ? rs : ry;
        }
        ext[2 * k] = rx;
        ext[2 * k + 1] = ry;
        if (sc[k].role < 0)
            continue;
        ry_max = ry > ry_max ? ry : ry_max;
        const double cx = sc[k].u * w, cy = sc[k].v * h;
        /* the ventral extension reaches the tile's edge: every copy in u is needed */
        const double rxe = sc[k].role > 0 ? w : rx;
        for (int m = (int)floor((-ry - cy) / h); m <= (int)floor((h + ry - cy) / h); m++)
            for (int q = (int)floor((-rxe - cx) / w); q <= (int)floor((w + rxe - cx) / w); q++) {
                if (ni == cap) {
                    Inst *t = realloc(in, sizeof(Inst) * cap * 2);
                    if (!t) {
                        free(in);
                        free(ext);
                        free(wob);
                        return sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
                    }
                    in = t;
                    cap *= 2;
                }
                in[ni++] = (Inst){.cx = cx + (double)q * w, .cy = cy + (double)m * h, .k = k};
            }
    }
    qsort(in, ni, sizeof(Inst), inst_cmp);
    const double belly_amp = p->Scales_BellyWarpIntensity / 256.0 * h * 0.1;
    for (int x = 0; x < w; x++)
        wob[x] = (float)(belly_amp * sin(2 * M_PI * 2 * (x + 0.5) / w));

    const int band = 32, nbands = (h + band - 1) / band;
#pragma omp parallel for schedule(dynamic, 1)
    for (int bi = 0; bi < nbands; bi++) {
        const int y0 = bi * band, y1 = y0 + band < h ? y0 + band : h;
        for (size_t i = (size_t)y0 * w; i < (size_t)y1 * w; i++) {
            trans[i] = 1.0f;
            height[i] = 0.0f;
        }
        /* the instances whose centre is within ry_max of the band */
        size_t lo = 0, hi = ni;
        while (lo < hi) {
            size_t mid = (lo + hi) / 2;
            if (in[mid].cy < y0 - ry_max)
                lo = mid + 1;
            else
                hi = mid;
        }
        for (size_t ii = lo; ii < ni && in[ii].cy <= y1 + ry_max; ii++) {
            const Scale *e = &sc[in[ii].k];
            const double cx = in[ii].cx, cy = in[ii].cy, rx = ext[2 * in[ii].k], ry = ext[2 * in[ii].k + 1];
            const int role = e->role;
            int sx0, sx1, sy0, sy1;
            if (!sq__stamp_footprint(cx, cy, rx, ry, role, w, y0, y1, &sx0, &sx1, &sy0, &sy1))
                continue;
            const float cs = (float)cos(e->th), sn = (float)sin(e->th);
            const float iax = (float)(SQ__LENS_HW / (e->hu * w)), iay = (float)(SQ__LENS_HH / (e->hv * h));
            const float half_s = 0.5f * (float)s;
            /* the stretch: 0 at the centre, 1 from 1 / BEND of the way to the tile's edge */
            const double tile = floor(cx / w) * w;
            const float inv_l = (float)(1.0 / (tile - cx)), inv_r = (float)(1.0 / (tile + w - cx));
            const float sv_px = (float)(e->sv * h), iay_seam = (float)(SQ__LENS_HH / (e->shv * h));
            for (int y = sy0; y < sy1; y++) {
                float *row = height + (size_t)y * w, *tr = trans + (size_t)y * w;
                const float dy0 = (float)(y + 0.5 - cy);
                const float belly_v = belly_amp > 0 ? (float)sin(2 * M_PI * (y + 0.5) / h * 3 + e->row) : 0.0f;
                int xa = sx0, xb = sx1;
                /* only the columns where this stamp row has content, and the stretch */
                const float fyr = (dy0 * iay + 1) * half_s - 0.5f;
                if (e->th == 0 && (fyr < 0 || (int)fyr + 1 >= s)) {
                    if (!role)
                        continue;
                    if (role == 1)
                        xb = (int)ceil(cx);
                    if (role == 2)
                        xa = (int)floor(cx);
                } else if (e->th == 0) {
                    int r0 = (int)fyr, r1 = r0 + 1;
                    int clo = span[2 * r0] < span[2 * r1] ? span[2 * r0] : span[2 * r1];
                    int chi = span[2 * r0 + 1] > span[2 * r1 + 1] ? span[2 * r0 + 1] : span[2 * r1 + 1];
                    if (clo > chi && !role)
                        continue;
                    double xl = cx + ((clo - 0.5) / half_s - 1) / iax, xr = cx + ((chi + 1.5) / half_s - 1) / iax;
                    if (!(role & 1) && xl > xa)
                        xa = (int)floor(xl);
                    if (!(role & 2) && xr < xb)
                        xb = (int)ceil(xr);
                    if (clo > chi) { /* empty row: only the ventral extension is left */
                        if (role & 1) xb = (int)ceil(cx);
                        if (role & 2) xa = (int)floor(cx);
                    }
                }
                if (xa < sx0) xa = sx0;
                if (xb > sx1) xb = sx1;
                for (int x = xa; x < xb; x++) {
                    if (tr[x] <= 0.0f)
                        continue;
                    float dx = (float)(x + 0.5 - cx), dy = dy0;
                    float iy = iay;
                    if (((role & 1) && dx < 0) || ((role & 2) && dx > 0)) {
                        /* the ventral scale: this scale's centre column, stretched and
                         * bent to meet the row's other stretch at the seam */
                        float t = dx * (dx < 0 ? inv_l : inv_r) * BEND;
                        t = t < 1.0f ? t : 1.0f;
                        t = t * t * (3.0f - 2.0f * t); /* no kink at either end */
                        dy -= t * sv_px;
                        /* the height (not its inverse) goes straight to the seam's */
                        iy = iay * iay_seam / (iay_seam + t * (iay - iay_seam));
                        dx = 0;
                        dy += wob[x] * belly_v;
                    }
                    sq__stamp_over(stamp, s, (dx * cs + dy * sn) * iax, (-dx * sn + dy * cs) * iy, &row[x],
                                   &tr[x]);
                }
            }
        }
    }
    free(in);
    free(ext);
    free(wob);
    return SQ_OK;
}

SqStatus sq__scales_voronoi(const SqParams *p, float *height, float *scratch, int w, int h,
                            SqError *err)
{
    if (p->Scales_ScaleSize * p->Scales_ScaleSizeXY[0] <= 0 ||
        p->Scales_ScaleSize * p->Scales_ScaleSizeXY[1] <= 0) {
        memset(height, 0, sizeof(float) * (size_t)w * h);
        return SQ_OK;
    }
    SqVoronoi vo;
    SqStatus st = sq__voronoi_build(p, SQ_VORONOI_ITERATIONS, &vo, err);
    if (st != SQ_OK)
        return st;
    Scale *sc = make_scales(p, &vo);
    const int n = vo.n;
    sq__voronoi_free(&vo);
    if (!sc)
        return sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");

    /* pixels per stamp unit of the largest scale decide the stamp's resolution */
    double amax = 0;
    for (int k = 0; k < n; k++) {
        const double ax = sc[k].hu * w / SQ__LENS_HW, ay = sc[k].hv * h / SQ__LENS_HH;
        amax = ax > amax ? ax : amax;
        amax = ay > amax ? ay : amax;
    }
    int s = 32;
    while (s < 512 && s < 2 * amax)
        s *= 2;
    /* as in the grid: a coarse stamp is painted at half resolution and interpolated up */
    int pw = w, ph = h;
    float *ph_height = height, *ph_trans = scratch;
    const int half = 2 * amax / s > 1.25 && w % 2 == 0 && h % 2 == 0 && w >= 512 && h >= 512;
    if (half) {
        pw = w / 2;
        ph = h / 2;
        ph_height = scratch;
        ph_trans = scratch + (size_t)pw * ph;
    }
    float *stamp = sq__falloc((size_t)2 * s * s);
    int *span = malloc(sizeof(int) * 2 * (size_t)s);
    if (!stamp || !span || sq__scale_stamp(p, stamp, s) != 0) {
        sq__ffree(stamp);
        free(span);
        free(sc);
        return sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
    }
    /* extent of the stamp's content (stamp units) and, per stamp row, its columns */
    double ex = 0, ey = 0;
    for (int j = 0; j < s; j++) {
        span[2 * j] = s;
        span[2 * j + 1] = -1;
        for (int i = 0; i < s; i++)
            if (stamp[2 * (j * s + i) + 1] > 0 || stamp[2 * (j * s + i)] > 0) {
                double X = fabs((i + 0.5) / s * 2 - 1) + 1.0 / s, Y = fabs((j + 0.5) / s * 2 - 1) + 1.0 / s;
                ex = X > ex ? X : ex;
                ey = Y > ey ? Y : ey;
                span[2 * j] = i < span[2 * j] ? i : span[2 * j];
                span[2 * j + 1] = i;
            }
    }
    st = paint(p, sc, n, stamp, s, span, ex, ey, ph_height, ph_trans, pw, ph, err);
    sq__ffree(stamp);
    free(span);
    free(sc);
    if (st == SQ_OK && half && sq__resample(ph_height, pw, ph, height, w, h) != 0)
        st = sq_error_set(err, SQ_ERR_NOMEM, "scales", "out of memory for the scales");
    return st;
}
