/* Reaction-diffusion (Turk 1991) on a periodic grid, so the texture tiles in u and v:
 * Turing's two-chemical spot system with Turk's constants, Meinhardt's five-chemical
 * stripe system from Turk's appendix, and cascades in which the first system's features
 * are frozen while a second system runs between them.
 *
 * Both systems are stepped explicitly with the 5-point Laplacian. A row is updated in
 * three parts: the interior, a branch-free loop over plain arrays that the compiler
 * vectorises, and its two wrap-around cells. Rows are shared among OpenMP threads and
 * every step writes a second set of arrays, so no cell depends on the thread order.
 *
 * Anisotropy is a change of variables: features k times longer along v are simulated on
 * a grid with k times fewer rows and stretched back when upsampled, which is diffusion
 * k^2 times faster along v than across (Turk's Figure 8), at a fraction of the cost and
 * with the isotropic kernel's stability. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen_internal.h"

/* Turk (1991), "Reaction-Diffusion": a = b = 4 at start, beta = 12 +- variation. */
#define TURING_DA 0.25f
#define TURING_DB 0.0625f

/* Meinhardt's stripe system as printed in Turk's appendix:
 *   g1' = c s2 g1^2 / r - alpha g1 + Dg lap g1 + rho0,  g2' likewise with s1,
 *   r'  = c s2 g1^2 + c s1 g2^2 - beta r,
 *   s1' = gamma (g1 - s1) + Ds lap s1 + rho1,           s2' likewise with g2.
 * Turk gives only D_x (here Dg, RD_StripeDiffusion: 0.1 broad, 0.008 thin stripes) and
 * D_y = 0.06. The other constants are squama's own tuning (by rendering a scan of
 * them): with Turk's D_y for Ds the domains coarsened into blobs, and with rho1 = 0 a wide
 * stripe never splits (the g2 growth inside a g1 domain is beta s1 / g1^2 - alpha, which
 * rho1 > 0 makes positive); Ds = 0.2, rho1 = 0.001 give labyrinths of random stripes whose
 * width follows Dg. c = 1 +- 2% seeds them, as beta's variation does for Turing's spots.
 * The system keeps drifting slowly (it never settles completely), so its cap matters. */
#ifndef STRIPE_DS
#define STRIPE_DS 0.2f
#endif
#ifndef STRIPE_ALPHA
#define STRIPE_ALPHA 0.04f
#endif
#ifndef STRIPE_BETA
#define STRIPE_BETA 0.04f
#endif
#ifndef STRIPE_GAMMA
#define STRIPE_GAMMA 0.02f
#endif
#ifndef STRIPE_RHO0
#define STRIPE_RHO0 0.001f
#endif
#ifndef STRIPE_RHO1
#define STRIPE_RHO1 0.001f
#endif
#ifndef STRIPE_C_VAR
#define STRIPE_C_VAR 0.02
#endif

enum { G1, G2, R, S1, S2 };
enum { A, B };

/* max(x, 0) as a comparison: fmaxf's NaN rules keep GCC from vectorising it */
static inline float pos(float x)
{
    return x > 0.0f ? x : 0.0f;
}

static inline float floor_at(float x, float lo)
{
    return x > lo ? x : lo;
}

/* g1 and g2 kept in [0, STRIPE_GMAX] and r above STRIPE_RMIN: the explicit steps of the
 * stripe system, whose production divides by r, then cannot run away to infinity */
#define STRIPE_GMAX 20.0f
#define STRIPE_RMIN 1e-3f

static inline float g_clamp(float x)
{
    x = x > 0.0f ? x : 0.0f;
    return x < STRIPE_GMAX ? x : STRIPE_GMAX;
}

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(__SANITIZE_ADDRESS__)
/* One build runs on any x86-64 and uses AVX2 where the CPU has it. No FMA contraction
 * happens in either clone (neither target has FMA), so both give the same bits. */
#define SQ_CLONES __attribute__((target_clones("avx2", "default"), noinline))
#elif defined(__GNUC__)
#define SQ_CLONES __attribute__((noinline)) /* inlined, its restrict pointers are lost */
#else
#define SQ_CLONES
#endif

/* ---- kernels ---- */

/* Turing's spots: one cell x with neighbours xl, xr in its row and the rows above (u)
 * and below (d). b cannot go below 0 (Turk). `live` 0 keeps a frozen cell. */
static inline void turing_cell(int x, int xl, int xr, float *restrict an, float *restrict bn,
                               const float *restrict a, const float *restrict au,
                               const float *restrict ad, const float *restrict b,
                               const float *restrict bu, const float *restrict bd,
                               const float *restrict beta, const float *restrict rate,
                               float da, float db, float live)
{
    const float av = a[x], bv = b[x], ab = av * bv;
    const float la = a[xl] + a[xr] + au[x] + ad[x] - 4.0f * av;
    const float lb = b[xl] + b[xr] + bu[x] + bd[x] - 4.0f * bv;
    const float dav = rate[x] * (16.0f - ab) + da * la;
    const float dbv = rate[x] * (ab - bv - beta[x]) + db * lb;
    an[x] = av + live * dav;
    bn[x] = pos(bv + live * dbv);
}

SQ_CLONES
static void turing_row(int nu, float *restrict an, float *restrict bn, const float *restrict a,
                       const float *restrict au, const float *restrict ad,
                       const float *restrict b, const float *restrict bu,
                       const float *restrict bd, const float *restrict beta,
                       const float *restrict rate, float da, float db)
{
    for (int x = 1; x < nu - 1; x++)
        turing_cell(x, x - 1, x + 1, an, bn, a, au, ad, b, bu, bd, beta, rate, da, db, 1.0f);
    turing_cell(0, nu - 1, 1, an, bn, a, au, ad, b, bu, bd, beta, rate, da, db, 1.0f);
    turing_cell(nu - 1, nu - 2, 0, an, bn, a, au, ad, b, bu, bd, beta, rate, da, db, 1.0f);
}

SQ_CLONES
static void turing_row_frozen(int nu, float *restrict an, float *restrict bn,
                              const float *restrict a, const float *restrict au,
                              const float *restrict ad, const float *restrict b,
                              const float *restrict bu, const float *restrict bd,
                              const float *restrict beta, const float *restrict rate,
                              float da, float db, const float *restrict live)
{
    for (int x = 1; x < nu - 1; x++)
        turing_cell(x, x - 1, x + 1, an, bn, a, au, ad, b, bu, bd, beta, rate, da, db, live[x]);
    turing_cell(0, nu - 1, 1, an, bn, a, au, ad, b, bu, bd, beta, rate, da, db, live[0]);
    turing_cell(nu - 1, nu - 2, 0, an, bn, a, au, ad, b, bu, bd, beta, rate, da, db,
                live[nu - 1]);
}

/* Meinhardt's stripes, one row. Every array is its own restrict parameter: through a
 * struct of pointers GCC no longer knows they do not overlap and does not vectorise.
 * o* the outputs, g1 .. s2 this row, u* and d* the rows above and below (r does not
 * diffuse). */
#define STRIPE_CELL(x, xl, xr, live)                                                        \
    do {                                                                                  \
        const float g1v = g1[x], g2v = g2[x], rv = r[x], s1v = s1[x], s2v = s2[x];        \
        const float k = rate[x] * (live), c = cc[x], dgl = dg * (live), dsl = ds * (live); \
        const float p1 = c * s2v * g1v * g1v, p2 = c * s1v * g2v * g2v, ir = 1.0f / rv;   \
        const float l1 = g1[xl] + g1[xr] + ug1[x] + dg1[x] - 4.0f * g1v;                  \
        const float l2 = g2[xl] + g2[xr] + ug2[x] + dg2[x] - 4.0f * g2v;                  \
        const float m1 = s1[xl] + s1[xr] + us1[x] + ds1[x] - 4.0f * s1v;                  \
        const float m2 = s2[xl] + s2[xr] + us2[x] + ds2[x] - 4.0f * s2v;                  \
        og1[x] = g_clamp(g1v + k * (p1 * ir - STRIPE_ALPHA * g1v + STRIPE_RHO0) + dgl * l1); \
        og2[x] = g_clamp(g2v + k * (p2 * ir - STRIPE_ALPHA * g2v + STRIPE_RHO0) + dgl * l2); \
        or_[x] = floor_at(rv + k * (p1 + p2 - STRIPE_BETA * rv), STRIPE_RMIN);            \
        os1[x] = s1v + k * (STRIPE_GAMMA * (g1v - s1v) + STRIPE_RHO1) + dsl * m1;         \
        os2[x] = s2v + k * (STRIPE_GAMMA * (g2v - s2v) + STRIPE_RHO1) + dsl * m2;         \
    } while (0)

SQ_CLONES
static void stripe_row(int nu, float *restrict og1, float *restrict og2, float *restrict or_,
                       float *restrict os1, float *restrict os2, const float *restrict g1,
                       const float *restrict g2, const float *restrict r,
                       const float *restrict s1, const float *restrict s2,
                       const float *restrict ug1, const float *restrict ug2,
                       const float *restrict us1, const float *restrict us2,
                       const float *restrict dg1, const float *restrict dg2,
                       const float *restrict ds1, const float *restrict ds2,
                       const float *restrict cc, const float *restrict rate, float dg, float ds,
                       const float *restrict live)
{
    if (live) {
        for (int x = 1; x < nu - 1; x++)
            STRIPE_CELL(x, x - 1, x + 1, live[x]);
        STRIPE_CELL(0, nu - 1, 1, live[0]);
        STRIPE_CELL(nu - 1, nu - 2, 0, live[nu - 1]);
    } else {
        for (int x = 1; x < nu - 1; x++)
            STRIPE_CELL(x, x - 1, x + 1, 1.0f);
        STRIPE_CELL(0, nu - 1, 1, 1.0f);
        STRIPE_CELL(nu - 1, nu - 2, 0, 1.0f);
    }
}

/* ---- state ---- */

void sq__rd_free(SqRd *rd)
{
    if (!rd)
        return;
    for (int i = 0; i < 5; i++) {
        sq__ffree(rd->cur[i]);
        sq__ffree(rd->nxt[i]);
    }
    sq__ffree(rd->sub);
    sq__ffree(rd->rate);
    sq__ffree(rd->live);
    memset(rd, 0, sizeof *rd);
}

static int rd_alloc(SqRd *rd, int system, int nchem, int nu, int nv)
{
    memset(rd, 0, sizeof *rd);
    rd->system = system;
    rd->nu = nu;
    rd->nv = nv;
    rd->nchem = nchem;
    const size_t n = (size_t)nu * nv;
    int bad = !(rd->sub = sq__falloc(n)) || !(rd->rate = sq__falloc((size_t)nu));
    for (int i = 0; i < nchem && !bad; i++)
        bad = !(rd->cur[i] = sq__falloc(n)) || !(rd->nxt[i] = sq__falloc(n));
    if (bad) {
        sq__rd_free(rd);
        return -1;
    }
    return 0;
}

/* The flank factor at column x: `flank` at u = 0 and 1 (the belly's midline), 1 at
 * u = 0.5 (the back), geometric in between along a cosine, so the change is smooth and
 * periodic. */
static double flank_factor(int x, int nu, double flank)
{
    const double u = ((double)x + 0.5) / nu;
    return pow(flank, 0.5 * (1.0 + cos(2.0 * M_PI * u)));
}

/* The time step of Turing's system for a largest speed smax (see sq__rd_init_spots). */
static float turing_dt(double smax)
{
    return (float)fmin(0.8, 1.8 / (8.0 * TURING_DA + 40.0 * smax));
}

int sq__rd_init_spots(SqRd *rd, int nu, int nv, double s, double flank, double beta_var,
                      uint64_t seed, uint64_t stream)
{
    if (rd_alloc(rd, SQ_RD_SPOTS, 2, nu, nv))
        return -1;
    /* Explicit Euler with Turk's D_a = 0.25 is unstable at dt = 1 in two dimensions (the
     * checkerboard mode of a grows by 1 + s b per step); stable needs
     * dt < 2 / (8 D_a + s b). b grows with s (to about 25 at s = 0.2, 85 at s = 2), so
     * dt is set for b up to 40, with a 10% margin. */
    const double smax = s * (flank > 1 ? flank : 1);
    rd->dt = turing_dt(smax);
    rd->diff[A] = TURING_DA * rd->dt;
    rd->diff[B] = TURING_DB * rd->dt;
    for (int x = 0; x < nu; x++)
        rd->rate[x] = (float)(s * flank_factor(x, nu, flank) * rd->dt);
    const size_t n = (size_t)nu * nv;
    for (size_t i = 0; i < n; i++) {
        rd->cur[A][i] = rd->cur[B][i] = 4.0f;
        rd->sub[i] = (float)(12.0 + beta_var * sq__rand11(seed, stream, i));
    }
    return 0;
}

/* Rest values of the stripe system where g2 holds the cell ("white" for g1): g2 at its
 * high level (alpha g = beta + rho0 with r at its balance), g1 at its low one. */
static void stripe_white(float *v)
{
    const float hi = (STRIPE_BETA + STRIPE_RHO0) / STRIPE_ALPHA, lo = STRIPE_RHO0 / STRIPE_ALPHA;
    v[G1] = lo;
    v[G2] = hi;
    v[S1] = lo;
    v[S2] = hi;
    v[R] = (lo * lo * hi + lo * hi * hi) / STRIPE_BETA;
}

/* The homogeneous balance of the stripe system: g1 = g2 = s1 = s2 = g, r = 2 c g^3 / beta,
 * with alpha g = beta / 2 + rho0. */
static void stripe_balance(float *v)
{
    const float g = (0.5f * STRIPE_BETA + STRIPE_RHO0) / STRIPE_ALPHA;
    v[G1] = v[G2] = v[S1] = v[S2] = g;
    v[R] = 2.0f * g * g * g / STRIPE_BETA;
}

int sq__rd_init_stripes(SqRd *rd, int nu, int nv, double dx, double flank, uint64_t seed,
                        uint64_t stream)
{
    if (rd_alloc(rd, SQ_RD_STRIPES, 5, nu, nv))
        return -1;
    /* reactions are slow (rates of a few hundredths); diffusion at most 0.2 per step is
     * within the explicit limit of 0.25 at dt = 1 */
    rd->dt = 1.0f;
    rd->diff[G1] = rd->diff[G2] = (float)dx;
    rd->diff[S1] = rd->diff[S2] = STRIPE_DS;
    for (int x = 0; x < nu; x++)
        rd->rate[x] = (float)flank_factor(x, nu, flank);
    /* the homogeneous balance: g1 = g2 = s1 = s2 = g, r = 2 c g^3 / beta, with
     * alpha g = beta / 2 + rho0 */
    const float g = (0.5f * STRIPE_BETA + STRIPE_RHO0) / STRIPE_ALPHA;
    const size_t n = (size_t)nu * nv;
    for (size_t i = 0; i < n; i++) {
        /* c's variation acts on g1 and g2 alike; the system is symmetric in them, so
         * the start needs a difference between the two as well */
        const float e = (float)(STRIPE_C_VAR * sq__rand11(seed, stream + 1000, i));
        rd->sub[i] = (float)(1.0 + STRIPE_C_VAR * sq__rand11(seed, stream, i));
        rd->cur[G1][i] = g * (1.0f + e);
        rd->cur[G2][i] = g * (1.0f - e);
        rd->cur[S1][i] = rd->cur[S2][i] = g;
        rd->cur[R][i] = 2.0f * g * g * g / STRIPE_BETA;
    }
    return 0;
}

/* ---- stepping ---- */

enum { RD_PARALLEL_MIN = 65536, RD_MIN_STEPS = 1500 };

static void step_rows(const SqRd *rd, float *const *cur, float *const *nxt)
{
    const int nu = rd->nu, nv = rd->nv;
#pragma omp for schedule(static)
    for (int y = 0; y < nv; y++) {
        const size_t o = (size_t)y * nu;
        const size_t ou = (size_t)(y == 0 ? nv - 1 : y - 1) * nu;
        const size_t od = (size_t)(y == nv - 1 ? 0 : y + 1) * nu;
        if (rd->system == SQ_RD_SPOTS) {
            const float *a = cur[A], *b = cur[B];
            if (rd->live)
                turing_row_frozen(nu, nxt[A] + o, nxt[B] + o, a + o, a + ou, a + od, b + o,
                                  b + ou, b + od, rd->sub + o, rd->rate, rd->diff[A],
                                  rd->diff[B], rd->live + o);
            else
                turing_row(nu, nxt[A] + o, nxt[B] + o, a + o, a + ou, a + od, b + o, b + ou,
                           b + od, rd->sub + o, rd->rate, rd->diff[A], rd->diff[B]);
        } else {
            float *const *c = cur, *const *m = nxt;
            stripe_row(nu, m[G1] + o, m[G2] + o, m[R] + o, m[S1] + o, m[S2] + o, c[G1] + o,
                       c[G2] + o, c[R] + o, c[S1] + o, c[S2] + o, c[G1] + ou, c[G2] + ou,
                       c[S1] + ou, c[S2] + ou, c[G1] + od, c[G2] + od, c[S1] + od, c[S2] + od,
                       rd->sub + o, rd->rate, rd->diff[G1], rd->diff[S1],
                       rd->live ? rd->live + o : NULL);
        }
    }
}

void sq__rd_steps(SqRd *rd, int n)
{
    if (n <= 0)
        return;
    /* One parallel region for all n steps: every thread swaps its own copy of the
     * pointers after each step's barrier, the same way, so no thread waits on another
     * to publish them. A step of a small grid takes microseconds, less than a barrier
     * costs when the cores are shared: below RD_PARALLEL_MIN cells one thread runs. */
    const int parallel = (long)rd->nu * rd->nv >= RD_PARALLEL_MIN;
#pragma omp parallel if (parallel)
    {
        float *cur[5], *nxt[5];
        memcpy(cur, rd->cur, sizeof cur);
        memcpy(nxt, rd->nxt, sizeof nxt);
        for (int k = 0; k < n; k++) {
            step_rows(rd, cur, nxt); /* ends with the barrier of its omp for */
            for (int i = 0; i < 5; i++) {
                float *t = cur[i];
                cur[i] = nxt[i];
                nxt[i] = t;
            }
        }
    }
    if (n % 2) {
        for (int i = 0; i < 5; i++) {
            float *t = rd->cur[i];
            rd->cur[i] = rd->nxt[i];
            rd->nxt[i] = t;
        }
    }
    rd->steps += n;
}

float sq__rd_last_change(const SqRd *rd)
{
    const int c = rd->system == SQ_RD_SPOTS ? B : G1;
    const float *a = rd->cur[c], *b = rd->nxt[c];
    const long n = (long)rd->nu * rd->nv;
    float m = 0.0f;
    /* a maximum does not depend on the order it is taken in */
#pragma omp parallel for reduction(max : m) schedule(static) if (n >= RD_PARALLEL_MIN)
    for (long i = 0; i < n; i++)
    {
        const float d = fabsf(a[i] - b[i]);
        m = d > m ? d : m;
    }
    return m / rd->dt;
}

void sq__rd_solve(SqRd *rd, double tol, int every, long cap)
{
    rd->converged = 0;
    while (rd->steps < cap) {
        long left = cap - rd->steps;
        sq__rd_steps(rd, (int)(left < every ? left : every));
        /* the start is nearly uniform and changes slowly too: no verdict before the
         * pattern has had time to grow */
        if (rd->steps >= RD_MIN_STEPS && sq__rd_last_change(rd) < tol) {
            rd->converged = 1;
            break;
        }
    }
}

void sq__rd_value(const SqRd *rd, float *value)
{
    const size_t n = (size_t)rd->nu * rd->nv;
    if (rd->system == SQ_RD_SPOTS) {
        const float *b = rd->cur[B];
        for (size_t i = 0; i < n; i++)
            value[i] = sq__clamp01(1.0f - b[i] * 0.125f);
    } else {
        const float *g1 = rd->cur[G1], *g2 = rd->cur[G2];
        for (size_t i = 0; i < n; i++)
            value[i] = g1[i] / (g1[i] + g2[i] + 1e-12f);
    }
}

/* ---- the complex pattern ---- */

/* Convergence: the pattern chemical changes by less than this per unit time... */
#define RD_TOL_SPOTS 2e-4
#define RD_TOL_STRIPES 2e-3
/* ...checked this often, and never more than this many steps per system. */
enum { RD_EVERY = 100, RD_CAP_SPOTS = 30000, RD_CAP_STRIPES = 10000 };

void sq__rd_grid(const SqParams *p, int w, int h, int *nu, int *nv)
{
    *nu = p->RD_Cells;
    long rows = lround((double)p->RD_Cells * h / w / p->RD_Anisotropy);
    *nv = (int)(rows < 8 ? 8 : rows > 8192 ? 8192 : rows);
}

void sq__rd_result_free(SqRdResult *r)
{
    if (!r)
        return;
    sq__ffree(r->value);
    sq__ffree(r->first);
    memset(r, 0, sizeof *r);
}

static int init_system(SqRd *rd, int system, const SqParams *p, int nu, int nv, int second)
{
    const uint64_t seed = (uint64_t)p->Seed;
    const uint64_t stream = second ? SQ_STREAM_RD2 : SQ_STREAM_RD;
    if (system == SQ_RD_SPOTS)
        return sq__rd_init_spots(rd, nu, nv, second ? p->RD_ReactionSpeed2 : p->RD_ReactionSpeed,
                                 p->RD_FlankSpeed, p->RD_BetaVariation, seed, stream);
    return sq__rd_init_stripes(rd, nu, nv, second ? p->RD_StripeDiffusion2 : p->RD_StripeDiffusion,
                               p->RD_FlankSpeed, seed, stream);
}

static void solve(SqRd *rd)
{
    if (rd->system == SQ_RD_SPOTS)
        sq__rd_solve(rd, RD_TOL_SPOTS, RD_EVERY, RD_CAP_SPOTS);
    else
        sq__rd_solve(rd, RD_TOL_STRIPES, RD_EVERY, RD_CAP_STRIPES);
}

/* Grid steps along v per step along u in texture space: the feature distances of the net
 * and rosette cascades are measured on the texture, not the (anisotropic) grid. */
static float grid_aspect(int w, int h, int nu, int nv)
{
    return (float)(((double)h / nv) / ((double)w / nu));
}

/* The net cascade: the first features' zones of influence, on a grid up to NET_FINE times
 * finer than the simulation's (at most NET_MAX_CELLS cells) so lines narrower than a cell
 * stay whole. The value is 1 where two zones meet, falling linearly with the distance from
 * there to 0 at RD_NetWidth (0.5 at half of it: lines RD_NetWidth wide at threshold 0.5). */
enum { NET_FINE = 4, NET_MAX_CELLS = 1 << 22 };

static int net_value(const SqParams *p, int w, int h, SqRdResult *out)
{
    int fine = NET_FINE;
    while (fine > 1 && (double)out->nu * out->nv * fine * fine > NET_MAX_CELLS)
        fine--;
    const int fu = out->nu * fine, fv = out->nv * fine;
    const size_t fn = (size_t)fu * fv;
    float *d1 = sq__falloc_raw(fn), *d2 = sq__falloc_raw(fn);
    unsigned char *mask = malloc(fn);
    int rc = -1;
    if (d1 && d2 && mask && (out->value = sq__falloc_raw(fn)) &&
        !sq__rd_upsample(out->first, out->nu, out->nv, d1, fu, fv)) {
        for (size_t i = 0; i < fn; i++)
            mask[i] = d1[i] > 0.5f;
        if (!sq__rd_feature_distances(mask, fu, fv, grid_aspect(w, h, fu, fv), d1, d2)) {
            const float width = (float)(p->RD_NetWidth / 256.0 * fu);
            for (size_t i = 0; i < fn; i++) {
                /* half the difference: the distance to where the two zones meet */
                const float m = d2[i] == FLT_MAX ? width : 0.5f * (d2[i] - d1[i]);
                out->value[i] = sq__clamp01(1.0f - m / width);
            }
            out->fine = fine;
            rc = 0;
        }
    }
    sq__ffree(d1);
    sq__ffree(d2);
    free(mask);
    return rc;
}

/* Where a cascade's second system runs when its reach is bounded: off the first features,
 * farther than RD_CascadeGap from them and, for rosettes with RD_RosetteWidth, within that
 * of them (a ring each); 1 live, 0 frozen. `keep` is what of its value is kept: live, and
 * beyond a gap fading in over a cell with the distance, so the value's edge there follows
 * the first features' outline rather than the cells'. */
static int cascade_live(const SqParams *p, int w, int h, const SqRdResult *out, float *live,
                        float *keep)
{
    const int nu = out->nu, nv = out->nv;
    const size_t n = (size_t)nu * nv;
    float *d1 = sq__falloc_raw(n), *d2 = sq__falloc_raw(n);
    unsigned char *mask = malloc(n);
    int rc = -1;
    if (d1 && d2 && mask) {
        for (size_t i = 0; i < n; i++)
            mask[i] = out->first[i] > 0.5f;
        if (!sq__rd_feature_distances(mask, nu, nv, grid_aspect(w, h, nu, nv), d1, d2)) {
            const int ring = p->RD_Cascade == SQ_RD_CASCADE_ROSETTES && p->RD_RosetteWidth > 0;
            const float reach = ring ? (float)(p->RD_RosetteWidth / 256.0 * nu) : FLT_MAX;
            const float gap = (float)(p->RD_CascadeGap / 256.0 * nu);
            for (size_t i = 0; i < n; i++) {
                live[i] = !mask[i] && d1[i] > gap && d1[i] <= reach ? 1.0f : 0.0f;
                keep[i] = gap > 0 ? live[i] * sq__clamp01(d1[i] - gap) : live[i];
            }
            rc = 0;
        }
    }
    sq__ffree(d1);
    sq__ffree(d2);
    free(mask);
    return rc;
}

SqStatus sq__rd_run(const SqParams *p, int w, int h, SqRdResult *out, SqError *err)
{
    memset(out, 0, sizeof *out);
    int nu, nv;
    sq__rd_grid(p, w, h, &nu, &nv);
    const size_t n = (size_t)nu * nv;
    out->nu = nu;
    out->nv = nv;
    out->fine = 1;
    SqRd one, two;
    memset(&two, 0, sizeof two);
    if (init_system(&one, p->RD_System, p, nu, nv, 0) || !(out->value = sq__falloc(n))) {
        sq__rd_free(&one);
        sq__rd_result_free(out);
        return sq_error_set(err, SQ_ERR_NOMEM, "RD_Cells",
                            "out of memory for a %dx%d reaction-diffusion grid", nu, nv);
    }
    solve(&one);
    out->steps[0] = one.steps;
    out->converged[0] = one.converged;
    sq__rd_value(&one, out->value);
    if (p->RD_Cascade == SQ_RD_CASCADE_NONE) {
        sq__rd_free(&one);
        return SQ_OK;
    }
    out->first = out->value;
    out->value = NULL;
    if (p->RD_Cascade == SQ_RD_CASCADE_NET) {
        sq__rd_free(&one);
        if (net_value(p, w, h, out)) {
            sq__rd_result_free(out);
            return sq_error_set(err, SQ_ERR_NOMEM, "RD_Cascade", "out of memory for the net");
        }
        return SQ_OK;
    }

    /* Cascade (Turk): the first system's features (value above 0.5, Turk's b < 4) are
     * frozen; the second system runs around them, the frozen cells still taking part in
     * its Laplacians. */
    const int second = p->RD_Cascade == SQ_RD_CASCADE_STRIPES ? SQ_RD_STRIPES : SQ_RD_SPOTS;
    const int keep = p->RD_Cascade == SQ_RD_CASCADE_SPOTS && p->RD_System == SQ_RD_SPOTS;
    const int bounded = (p->RD_Cascade == SQ_RD_CASCADE_ROSETTES && p->RD_RosetteWidth > 0) ||
                        p->RD_CascadeGap > 0;
    int bad = !(out->value = sq__falloc(n));
    if (!bad && keep) { /* cheetah: the same chemicals go on at the second speed */
        two = one;
        memset(&one, 0, sizeof one);
        const double s2 = p->RD_ReactionSpeed2;
        const double smax = s2 * (p->RD_FlankSpeed > 1 ? p->RD_FlankSpeed : 1);
        const float dt = turing_dt(smax);
        two.dt = dt;
        two.diff[A] = TURING_DA * dt;
        two.diff[B] = TURING_DB * dt;
        for (int x = 0; x < nu; x++)
            two.rate[x] = (float)(s2 * flank_factor(x, nu, p->RD_FlankSpeed) * dt);
        two.steps = 0;
    } else if (!bad) {
        bad = init_system(&two, second, p, nu, nv, 1) != 0;
    }
    if (!bad)
        bad = !(two.live = sq__falloc(n));
    float *keep_value = NULL;
    if (!bad && bounded)
        bad = !(keep_value = sq__falloc(n)) || cascade_live(p, w, h, out, two.live, keep_value) != 0;
    if (bad) {
        sq__rd_free(&one);
        sq__rd_free(&two);
        sq__ffree(keep_value);
        sq__rd_result_free(out);
        return sq_error_set(err, SQ_ERR_NOMEM, "RD_Cascade", "out of memory for the cascade");
    }
    float rest[5] = {4.0f, 4.0f, 0, 0, 0}; /* leopard: Turing's rest, a = b = 4 */
    if (second == SQ_RD_STRIPES && p->RD_System == SQ_RD_STRIPES)
        stripe_balance(rest); /* lionfish: neutral, so the new stripes are not pushed */
    else if (second == SQ_RD_STRIPES)
        stripe_white(rest); /* giraffe: the white of the stripe system */
    for (size_t i = 0; i < n; i++) {
        /* bounded: the cells out of reach are frozen (at rest) as well */
        const int frozen = bounded ? two.live[i] == 0.0f : out->first[i] > 0.5f;
        two.live[i] = frozen ? 0.0f : 1.0f;
        if (frozen && !keep)
            for (int c = 0; c < two.nchem; c++)
                two.cur[c][i] = rest[c];
    }
    solve(&two);
    out->steps[1] = two.steps;
    out->converged[1] = two.converged;
    sq__rd_value(&two, out->value);
    /* the frozen cells keep their features only in the cheetah cascade; otherwise they
     * are the first system's (coloured by RD_Color3) */
    if (!keep)
        for (size_t i = 0; i < n; i++)
            out->value[i] *= keep_value ? keep_value[i] : two.live[i];
    sq__ffree(keep_value);
    sq__rd_free(&one);
    sq__rd_free(&two);
    return SQ_OK;
}

/* ---- upsampling ---- */

/* Catmull-Rom weights for the four samples around a point t in [0, 1) past the second. */
static void cubic_weights(float t, float *wt)
{
    const float t2 = t * t, t3 = t2 * t;
    wt[0] = 0.5f * (-t3 + 2.0f * t2 - t);
    wt[1] = 0.5f * (3.0f * t3 - 5.0f * t2 + 2.0f);
    wt[2] = 0.5f * (-3.0f * t3 + 4.0f * t2 + t);
    wt[3] = 0.5f * (t3 - t2);
}

typedef struct Taps {
    int *i; /* 4 indices per output sample */
    float *w;
} Taps;

static int taps_init(Taps *t, int n, int m)
{
    t->i = malloc(sizeof(int) * 4 * (size_t)n);
    t->w = malloc(sizeof(float) * 4 * (size_t)n);
    if (!t->i || !t->w)
        return -1;
    for (int k = 0; k < n; k++) {
        const double pos = ((double)k + 0.5) * m / n - 0.5;
        const int f = (int)floor(pos);
        cubic_weights((float)(pos - f), t->w + 4 * k);
        for (int j = 0; j < 4; j++)
            t->i[4 * k + j] = sq__wrap(f - 1 + j, m);
    }
    return 0;
}

static void taps_free(Taps *t)
{
    free(t->i);
    free(t->w);
}

int sq__rd_upsample(const float *src, int sw, int sh, float *dst, int dw, int dh)
{
    Taps tx = {0}, ty = {0};
    float *tmp = sq__falloc_raw((size_t)sh * dw);
    int rc = -1;
    if (tmp && !taps_init(&tx, dw, sw) && !taps_init(&ty, dh, sh)) {
#pragma omp parallel
        {
#pragma omp for schedule(static)
            for (int y = 0; y < sh; y++) {
                const float *s = src + (size_t)y * sw;
                float *o = tmp + (size_t)y * dw;
                for (int x = 0; x < dw; x++) {
                    const int *i = tx.i + 4 * x;
                    const float *w = tx.w + 4 * x;
                    o[x] = w[0] * s[i[0]] + w[1] * s[i[1]] + w[2] * s[i[2]] + w[3] * s[i[3]];
                }
            }
#pragma omp for schedule(static)
            for (int y = 0; y < dh; y++) {
                const int *i = ty.i + 4 * y;
                const float *w = ty.w + 4 * y;
                const float *r0 = tmp + (size_t)i[0] * dw, *r1 = tmp + (size_t)i[1] * dw;
                const float *r2 = tmp + (size_t)i[2] * dw, *r3 = tmp + (size_t)i[3] * dw;
                float *o = dst + (size_t)y * dw;
                for (int x = 0; x < dw; x++)
                    o[x] = w[0] * r0[x] + w[1] * r1[x] + w[2] * r2[x] + w[3] * r3[x];
            }
        }
        rc = 0;
    }
    taps_free(&tx);
    taps_free(&ty);
    sq__ffree(tmp);
    return rc;
}
