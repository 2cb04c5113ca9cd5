/* Reaction-diffusion (generator/rd.c, pattern_rd.c): stability, equilibrium, feature size
 * against Turk's s, seamlessness, determinism over thread counts, cascades, refusals. */
#include <float.h>
#include <math.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "gen_internal.h"
#include "sq_test.h"
#include "squama/preset.h"

static void set_threads(int n)
{
#ifdef _OPENMP
    omp_set_num_threads(n);
#else
    (void)n;
#endif
}

static void assert_finite_within(const float *v, size_t n, float lo, float hi, const char *what)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]) || v[i] < lo || v[i] > hi)
            fail_msg("%s[%zu] = %g, outside [%g, %g]", what, i, (double)v[i], (double)lo,
                     (double)hi);
}

static double mean(const float *v, size_t n)
{
    double s = 0;
    for (size_t i = 0; i < n; i++)
        s += v[i];
    return s / (double)n;
}

static void spots_stay_finite_and_bounded(void **state)
{
    (void)state;
    const double speeds[] = {0.02, 0.05, 0.2, 1.0}; /* 1.0: the hard maximum */
    for (int k = 0; k < 4; k++) {
        SqRd rd;
        assert_int_equal(sq__rd_init_spots(&rd, 48, 40, speeds[k], 2.0, 3.0, 7, 1), 0);
        sq__rd_steps(&rd, 3000);
        const size_t n = 48 * 40;
        float amax = 0, bmax = 0;
        for (size_t i = 0; i < n; i++) {
            amax = rd.cur[0][i] > amax ? rd.cur[0][i] : amax;
            bmax = rd.cur[1][i] > bmax ? rd.cur[1][i] : bmax;
        }
        print_message("s = %g: max a %g, max b %g\n", speeds[k], (double)amax, (double)bmax);
        assert_finite_within(rd.cur[0], n, 0.0f, 1e4f, "a");
        assert_finite_within(rd.cur[1], n, 0.0f, 64.0f, "b");
        sq__rd_free(&rd);
    }
}

/* Diffusion on a periodic grid moves chemical around without creating any, so once the
 * field has settled the reaction must balance on average: the mean of s (16 - a b) is 0,
 * i.e. the mean of a b is Turk's 16, however far a and b are from 4 locally. */
static void settled_spots_balance_their_reaction(void **state)
{
    (void)state;
    const double speeds[] = {0.05, 0.2};
    for (int k = 0; k < 2; k++) {
        SqRd rd;
        assert_int_equal(sq__rd_init_spots(&rd, 64, 64, speeds[k], 1.0, 0.1, 3, 1), 0);
        sq__rd_solve(&rd, 2e-4, 100, 30000);
        assert_true(rd.converged);
        double ab = 0;
        for (int i = 0; i < 64 * 64; i++)
            ab += (double)rd.cur[0][i] * rd.cur[1][i];
        ab /= 64 * 64;
        print_message("s = %g: settled after %ld steps, mean a b = %.3f\n", speeds[k], rd.steps, ab);
        if (fabs(ab - 16) > 0.5)
            fail_msg("s = %g: mean a b %.3f, the reaction does not balance (16)", speeds[k], ab);
        sq__rd_free(&rd);
    }
}

static void stripes_stay_finite_and_bounded(void **state)
{
    (void)state;
    const double dx[] = {0.002, 0.02, 0.2};
    for (int k = 0; k < 3; k++) {
        SqRd rd;
        assert_int_equal(sq__rd_init_stripes(&rd, 40, 48, dx[k], 4.0, 3, 1), 0);
        sq__rd_steps(&rd, 4000);
        const size_t n = 40 * 48;
        /* g1, g2 are held in [0, 20]; s1, s2 follow them; r balances c s g^2 / beta */
        assert_finite_within(rd.cur[0], n, 0.0f, 20.0f, "g1");
        assert_finite_within(rd.cur[1], n, 0.0f, 20.0f, "g2");
        assert_finite_within(rd.cur[2], n, 1e-4f, 5e5f, "r");
        assert_finite_within(rd.cur[3], n, 0.0f, 25.0f, "s1");
        assert_finite_within(rd.cur[4], n, 0.0f, 25.0f, "s2");
        float *v = malloc(sizeof(float) * n);
        sq__rd_value(&rd, v);
        assert_finite_within(v, n, 0.0f, 1.0f, "stripe value");
        /* g1 and g2 share the cells: both colours present, neither taking over */
        double m = mean(v, n);
        if (m < 0.2 || m > 0.8)
            fail_msg("D_x = %g: mean stripe value %.3f, one chemical took over", dx[k], m);
        free(v);
        sq__rd_free(&rd);
    }
}

/* The dominant wavelength (cells) of a periodic field: the first peak after zero of the
 * autocorrelation along rows and columns, averaged. */
static double wavelength(const float *v, int nu, int nv)
{
    const double m = mean(v, (size_t)nu * nv);
    double total = 0;
    for (int axis = 0; axis < 2; axis++) {
        const int len = axis == 0 ? nu : nv;
        double prev = 1e30, best = 0;
        int dropped = 0;
        for (int lag = 1; lag < len / 2; lag++) {
            double s = 0;
            for (int y = 0; y < nv; y++)
                for (int x = 0; x < nu; x++) {
                    const int x2 = axis == 0 ? (x + lag) % nu : x;
                    const int y2 = axis == 0 ? y : (y + lag) % nv;
                    s += (v[y * nu + x] - m) * (v[y2 * nu + x2] - m);
                }
            if (s < 0)
                dropped = 1;
            if (dropped && s < prev) {
                prev = s;
                continue;
            }
            if (dropped && s > prev) { /* past the minimum: the next maximum */
                double peak = s;
                int at = lag;
                for (int l2 = lag + 1; l2 < len / 2; l2++) {
                    double t = 0;
                    for (int y = 0; y < nv; y++)
                        for (int x = 0; x < nu; x++) {
                            const int x2 = axis == 0 ? (x + l2) % nu : x;
                            const int y2 = axis == 0 ? y : (y + l2) % nv;
                            t += (v[y * nu + x] - m) * (v[y2 * nu + x2] - m);
                        }
                    if (t < peak)
                        break;
                    peak = t;
                    at = l2;
                }
                best = at;
                break;
            }
            prev = s;
        }
        total += best;
    }
    return total / 2;
}

static double spot_wavelength(double s)
{
    SqRd rd;
    enum { N = 96 };
    assert_int_equal(sq__rd_init_spots(&rd, N, N, s, 1.0, 0.1, 11, 1), 0);
    sq__rd_solve(&rd, 2e-4, 100, 30000);
    float *v = malloc(sizeof(float) * N * N);
    sq__rd_value(&rd, v);
    double wl = wavelength(v, N, N);
    free(v);
    sq__rd_free(&rd);
    return wl;
}

static void larger_s_makes_smaller_spots(void **state)
{
    (void)state;
    /* Turk: s = 0.05 large spots, s = 0.2 small ones. Linear analysis scales the
     * wavelength as 1 / sqrt(s): a ratio near 2. */
    const double big = spot_wavelength(0.05), small = spot_wavelength(0.2);
    print_message("wavelength s=0.05: %.1f cells, s=0.2: %.1f cells\n", big, small);
    assert_true(small > 2);
    if (big / small < 1.4 || big / small > 3.0)
        fail_msg("wavelengths %.1f (s = 0.05) and %.1f (s = 0.2): ratio %.2f, expected about 2",
                 big, small, big / small);
}

static void complex_params(SqParams *p)
{
    sq_params_default(p);
    p->Pattern_Type = SQ_PATTERN_COMPLEX;
    p->RD_Cells = 40;
    p->RD_ReactionSpeed = 0.1;
    p->Background_Color[0] = p->Background_Color[1] = p->Background_Color[2] = 1;
    p->RD_Color1[0] = p->RD_Color1[1] = p->RD_Color1[2] = 0;
}

/* Mean absolute difference across the seam against that between interior neighbours. */
static void seam_ratio(const float *v, int w, int h, double *ru, double *rv)
{
    double seam_u = 0, in_u = 0, seam_v = 0, in_v = 0;
    for (int y = 0; y < h; y++) {
        seam_u += fabs(v[y * w + w - 1] - v[y * w]);
        for (int x = 0; x < w - 1; x++)
            in_u += fabs(v[y * w + x + 1] - v[y * w + x]);
    }
    for (int x = 0; x < w; x++) {
        seam_v += fabs(v[(h - 1) * w + x] - v[x]);
        for (int y = 0; y < h - 1; y++)
            in_v += fabs(v[(y + 1) * w + x] - v[y * w + x]);
    }
    *ru = (seam_u / h) / (in_u / ((double)h * (w - 1)));
    *rv = (seam_v / w) / (in_v / ((double)w * (h - 1)));
}

static void texture_is_seamless(void **state)
{
    (void)state;
    SqParams p;
    complex_params(&p);
    p.RD_Anisotropy = 1.7; /* a grid of another shape than the texture */
    SqError err;
    SqRdResult r;
    assert_int_equal(sq__rd_run(&p, 200, 150, &r, &err), SQ_OK);
    float *up = malloc(sizeof(float) * 200 * 150);
    assert_int_equal(sq__rd_upsample(r.value, r.nu, r.nv, up, 200, 150), 0);
    double ru, rv;
    seam_ratio(up, 200, 150, &ru, &rv);
    print_message("seam / interior differences: u %.2f, v %.2f\n", ru, rv);
    assert_true(ru < 2.0 && rv < 2.0);
    /* the rendered colour map too */
    SqTextures t;
    SqGenOptions o = sq_gen_options_default(128);
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_OK);
    float *g = malloc(sizeof(float) * 128 * 128);
    for (int i = 0; i < 128 * 128; i++)
        g[i] = t.basecolor.px[3 * i];
    seam_ratio(g, 128, 128, &ru, &rv);
    assert_true(ru < 2.0 && rv < 2.0);
    free(g);
    sq_gen_textures_free(&t);
    free(up);
    sq__rd_result_free(&r);
}

static void same_pixels_on_one_and_two_threads(void **state)
{
    (void)state;
    /* a grid large enough for the stepping to run on several threads */
    enum { N = 256 };
    float *res[2];
    for (int k = 0; k < 2; k++) {
        set_threads(k + 1);
        SqRd rd;
        assert_int_equal(sq__rd_init_spots(&rd, N, N, 0.2, 2.0, 1.0, 5, 1), 0);
        sq__rd_steps(&rd, 301);
        res[k] = malloc(sizeof(float) * N * N);
        memcpy(res[k], rd.cur[1], sizeof(float) * N * N);
        sq__rd_free(&rd);
    }
    assert_memory_equal(res[0], res[1], sizeof(float) * N * N);
    free(res[0]);
    free(res[1]);
    /* and a whole cascade render */
    SqParams p;
    complex_params(&p);
    p.RD_Cascade = SQ_RD_CASCADE_STRIPES;
    SqTextures t[2];
    SqError err;
    for (int k = 0; k < 2; k++) {
        SqGenOptions o = sq_gen_options_default(96);
        o.threads = k + 1;
        assert_int_equal(sq_gen_render(&p, &o, &t[k], &err), SQ_OK);
    }
    assert_memory_equal(t[0].basecolor.px, t[1].basecolor.px, sizeof(float) * 96 * 96 * 3);
    sq_gen_textures_free(&t[0]);
    sq_gen_textures_free(&t[1]);
    set_threads(2);
}

/* Mean area (cells) of the 4-connected components of mask. */
static double mean_component(const unsigned char *mask, int nu, int nv)
{
    unsigned char *seen = calloc((size_t)nu * nv, 1);
    int *stack = malloc(sizeof(int) * (size_t)nu * nv);
    long cells = 0, comps = 0;
    for (int s = 0; s < nu * nv; s++) {
        if (!mask[s] || seen[s])
            continue;
        comps++;
        int top = 0;
        stack[top++] = s;
        seen[s] = 1;
        while (top) {
            int c = stack[--top], x = c % nu, y = c / nu;
            cells++;
            const int nb[4] = {y * nu + (x + 1) % nu, y * nu + (x + nu - 1) % nu,
                               ((y + 1) % nv) * nu + x, ((y + nv - 1) % nv) * nu + x};
            for (int k = 0; k < 4; k++)
                if (mask[nb[k]] && !seen[nb[k]]) {
                    seen[nb[k]] = 1;
                    stack[top++] = nb[k];
                }
        }
    }
    free(seen);
    free(stack);
    return comps ? (double)cells / comps : 0;
}

static void cascade_makes_two_feature_sizes(void **state)
{
    (void)state;
    SqParams p;
    complex_params(&p);
    p.RD_Cells = 64;
    p.RD_ReactionSpeed = 0.05;
    p.RD_ReactionSpeed2 = 0.2;
    p.RD_Cascade = SQ_RD_CASCADE_SPOTS; /* cheetah */
    SqError err;
    SqRdResult r;
    assert_int_equal(sq__rd_run(&p, 256, 256, &r, &err), SQ_OK);
    assert_non_null(r.first);
    const int n = r.nu * r.nv;
    unsigned char *big = malloc((size_t)n), *small = malloc((size_t)n);
    int nsmall = 0;
    for (int i = 0; i < n; i++) {
        big[i] = r.first[i] > 0.5f;
        small[i] = !big[i] && r.value[i] > 0.5f;
        nsmall += small[i];
    }
    const double a_big = mean_component(big, r.nu, r.nv), a_small = mean_component(small, r.nu, r.nv);
    print_message("cheetah: large spots %.1f cells, small %.1f cells (%d cells)\n", a_big, a_small, nsmall);
    assert_true(nsmall > 0);
    if (a_big < 2.0 * a_small)
        fail_msg("large spots %.1f cells, small %.1f: not two scales", a_big, a_small);
    free(big);
    free(small);
    sq__rd_result_free(&r);
}

/* Feature distances: two one-cell features on a periodic grid, the second reached across
 * the wrap; a feature cell is 0 from its own feature; anisotropy scales the v steps. */
static void feature_distances_are_nearest_and_other(void **state)
{
    (void)state;
    enum { NU = 20, NV = 10 };
    unsigned char mask[NU * NV] = {0};
    mask[5 * NU + 2] = 1;  /* feature A at (2, 5) */
    mask[5 * NU + 15] = 1; /* feature B at (15, 5): 7 cells from A across the wrap */
    float d1[NU * NV], d2[NU * NV];
    assert_int_equal(sq__rd_feature_distances(mask, NU, NV, 1.0f, d1, d2), 0);
    assert_true(d1[5 * NU + 2] == 0.0f);
    assert_true(fabsf(d2[5 * NU + 2] - 7.0f) < 1e-5f);   /* A to B through the wrap */
    assert_true(fabsf(d1[5 * NU + 19] - 3.0f) < 1e-5f);  /* (19, 5): A is 3 away across */
    assert_true(fabsf(d2[5 * NU + 19] - 4.0f) < 1e-5f);  /* and B 4 */
    assert_true(fabsf(d1[0 * NU + 2] - 5.0f) < 1e-5f);   /* (2, 0): 5 rows from A */
    assert_true(fabsf(d1[8 * NU + 8] - sqrtf(9 + 36)) < 1e-4f);
    assert_int_equal(sq__rd_feature_distances(mask, NU, NV, 2.0f, d1, d2), 0);
    assert_true(fabsf(d1[0 * NU + 2] - 10.0f) < 1e-5f);  /* a v step counts 2 */
    /* one feature: no other */
    mask[5 * NU + 15] = 0;
    assert_int_equal(sq__rd_feature_distances(mask, NU, NV, 1.0f, d1, d2), 0);
    assert_true(d2[0] == FLT_MAX);
}

/* 4-connected components of mask on the periodic grid. */
static int count_components(const unsigned char *mask, int nu, int nv)
{
    const double mean = mean_component(mask, nu, nv);
    long cells = 0;
    for (int i = 0; i < nu * nv; i++)
        cells += mask[i];
    return mean > 0 ? (int)lround((double)cells / mean) : 0;
}

/* The net cascade (giraffe, reticulated python): thin lines that make one connected net
 * across the periodic domain, around many patches, off the first features. */
static void net_cascade_is_one_thin_connected_net(void **state)
{
    (void)state;
    SqParams p;
    complex_params(&p);
    p.RD_ReactionSpeed = 0.05;
    p.RD_BetaVariation = 1;
    p.RD_Cascade = SQ_RD_CASCADE_NET;
    p.RD_NetWidth = 5;
    SqError err;
    SqRdResult r;
    assert_int_equal(sq__rd_run(&p, 256, 256, &r, &err), SQ_OK);
    assert_non_null(r.first);
    assert_true(r.fine > 1);
    const int fu = r.nu * r.fine, fv = r.nv * r.fine, n = fu * fv;
    assert_finite_within(r.value, (size_t)n, 0.0f, 1.0f, "net value");
    unsigned char *net = calloc((size_t)n, 1), *patch = calloc((size_t)n, 1);
    int on = 0;
    for (int i = 0; i < n; i++) {
        net[i] = r.value[i] > 0.5f;
        patch[i] = !net[i];
        on += net[i];
    }
    const double frac = (double)on / n;
    const int nets = count_components(net, fu, fv), patches = count_components(patch, fu, fv);
    print_message("net: %.1f%% of the cells, %d component(s) around %d patches\n", 100 * frac,
                  nets, patches);
    if (frac < 0.03 || frac > 0.3)
        fail_msg("the net covers %.1f%% of the texture: not thin lines", 100 * frac);
    if (nets != 1)
        fail_msg("the net is %d pieces, not one", nets);
    if (patches < 8)
        fail_msg("the net encloses %d patches", patches);
    /* the lines run between the first features, never through their cores */
    float *first = malloc(sizeof(float) * (size_t)n);
    assert_int_equal(sq__rd_upsample(r.first, r.nu, r.nv, first, fu, fv), 0);
    long through = 0;
    for (int i = 0; i < n; i++)
        through += net[i] && first[i] > 0.8f;
    if (through > n / 1000)
        fail_msg("%ld net cells inside the first features' cores", through);
    free(first);
    free(net);
    free(patch);
    sq__rd_result_free(&r);
}

/* The rosette cascade with a ring: the small spots lie within RD_RosetteWidth of the
 * large ones, and most large spots are ringed by them on three sides or more. */
static void rosette_ring_surrounds_the_large_spots(void **state)
{
    (void)state;
    SqParams p;
    complex_params(&p);
    p.RD_Cells = 64;
    p.RD_ReactionSpeed = 0.04;
    p.RD_ReactionSpeed2 = 0.3;
    p.RD_Cascade = SQ_RD_CASCADE_ROSETTES;
    p.RD_RosetteWidth = 5;
    SqError err;
    SqRdResult r;
    assert_int_equal(sq__rd_run(&p, 256, 256, &r, &err), SQ_OK);
    const int nu = r.nu, nv = r.nv, n = nu * nv;
    unsigned char *big = malloc((size_t)n);
    float *d1 = malloc(sizeof(float) * (size_t)n), *d2 = malloc(sizeof(float) * (size_t)n);
    for (int i = 0; i < n; i++)
        big[i] = r.first[i] > 0.5f;
    assert_int_equal(sq__rd_feature_distances(big, nu, nv, 1.0f, d1, d2), 0);
    const float reach = (float)(5.0 / 256 * nu);
    int small = 0;
    for (int i = 0; i < n; i++) {
        if (r.value[i] <= 0.5f)
            continue;
        small++;
        if (big[i] || d1[i] > reach + 1e-4f)
            fail_msg("small spot cell %d at %.2f cells from a large spot, beyond the ring (%.2f)",
                     i, (double)d1[i], (double)reach);
    }
    /* quadrants around each large spot's centroid holding small-spot cells */
    int *lab = malloc(sizeof(int) * (size_t)n);
    const int spots = sq__rd_label_features(big, nu, nv, lab);
    assert_true(spots >= 8);
    int *ref = malloc(sizeof(int) * (size_t)spots), *cells = calloc((size_t)spots, sizeof(int));
    double *cx = calloc((size_t)spots, sizeof(double)), *cy = calloc((size_t)spots, sizeof(double));
    for (int i = n - 1; i >= 0; i--) /* each spot's first cell, its cells unwrapped around it */
        if (lab[i] >= 0)
            ref[lab[i]] = i;
    for (int i = 0; i < n; i++) {
        const int k = lab[i];
        if (k < 0)
            continue;
        int dx = i % nu - ref[k] % nu, dy = i / nu - ref[k] / nu;
        dx -= dx > nu / 2 ? nu : dx < -nu / 2 ? -nu : 0;
        dy -= dy > nv / 2 ? nv : dy < -nv / 2 ? -nv : 0;
        cx[k] += dx;
        cy[k] += dy;
        cells[k]++;
    }
    int ringed = 0;
    for (int k = 0; k < spots; k++) {
        const double x0 = ref[k] % nu + cx[k] / cells[k], y0 = ref[k] / nu + cy[k] / cells[k];
        const int rad = (int)ceil(sqrt(cells[k]) + reach + 2), ix = (int)lround(x0), iy = (int)lround(y0);
        int quad = 0;
        for (int dy = -rad; dy <= rad; dy++)
            for (int dx = -rad; dx <= rad; dx++) {
                const int i = ((iy + dy + 4 * nv) % nv) * nu + (ix + dx + 4 * nu) % nu;
                if (r.value[i] > 0.5f && d1[i] <= reach + 1e-4f)
                    quad |= 1 << ((ix + dx >= x0) + 2 * (iy + dy >= y0));
            }
        ringed += (quad & 1) + (quad >> 1 & 1) + (quad >> 2 & 1) + (quad >> 3 & 1) >= 3;
    }
    print_message("rosettes: %d small-spot cells; %d of %d large spots ringed\n", small, ringed,
                  spots);
    if (ringed < 0.6 * spots)
        fail_msg("only %d of %d large spots are ringed by small spots", ringed, spots);
    free(lab);
    free(ref);
    free(cells);
    free(cx);
    free(cy);
    free(big);
    free(d1);
    free(d2);
    sq__rd_result_free(&r);
}

/* Stripes between stripes (Turk's lionfish): the second system makes stripes in the gaps
 * between the frozen broad ones, rather than filling them. */
static void stripes_between_stripes_leave_gaps(void **state)
{
    (void)state;
    SqParams p;
    complex_params(&p);
    p.RD_System = SQ_RD_STRIPES;
    p.RD_Cascade = SQ_RD_CASCADE_STRIPES;
    p.RD_Cells = 96;
    p.RD_StripeDiffusion = 0.06;
    p.RD_StripeDiffusion2 = 0.015;
    SqError err;
    SqRdResult r;
    assert_int_equal(sq__rd_run(&p, 256, 256, &r, &err), SQ_OK);
    const int n = r.nu * r.nv;
    long live = 0, on = 0;
    for (int i = 0; i < n; i++) {
        if (r.first[i] > 0.5f)
            continue;
        live++;
        on += r.value[i] > 0.5f;
    }
    const double frac = (double)on / (double)live;
    print_message("stripes between stripes: %.0f%% of the gaps striped\n", 100 * frac);
    assert_true(live > n / 5);
    if (frac < 0.15 || frac > 0.75)
        fail_msg("the second stripes fill %.0f%% of the gaps between the first", 100 * frac);
    sq__rd_result_free(&r);
    /* with a gap, none of them comes nearer the first than RD_CascadeGap */
    p.RD_CascadeGap = 3;
    assert_int_equal(sq__rd_run(&p, 256, 256, &r, &err), SQ_OK);
    unsigned char *first = malloc((size_t)n);
    float *d1 = malloc(sizeof(float) * (size_t)n), *d2 = malloc(sizeof(float) * (size_t)n);
    for (int i = 0; i < n; i++)
        first[i] = r.first[i] > 0.5f;
    assert_int_equal(sq__rd_feature_distances(first, r.nu, r.nv, 1.0f, d1, d2), 0);
    const float gap = (float)(3.0 / 256 * r.nu);
    long near = 0;
    on = 0;
    for (int i = 0; i < n; i++) {
        on += r.value[i] > 0.5f;
        near += r.value[i] > 0.0f && d1[i] <= gap;
    }
    print_message("with a gap of %.2f cells: %ld cells striped, %ld nearer\n", (double)gap, on, near);
    assert_true(on > n / 50);
    if (near)
        fail_msg("%ld second-system cells within the gap", near);
    free(first);
    free(d1);
    free(d2);
    sq__rd_result_free(&r);
}

static void bad_parameters_are_refused_by_name(void **state)
{
    (void)state;
    SqParams p;
    SqError err;
    SqTextures t;
    SqGenOptions o = sq_gen_options_default(32);
    complex_params(&p);
    p.RD_Cells = 8;
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "RD_Cells");
    complex_params(&p);
    p.RD_Anisotropy = 0;
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "RD_Anisotropy");
    complex_params(&p);
    p.RD_ReactionSpeed = NAN;
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "RD_ReactionSpeed");
    complex_params(&p);
    p.RD_Cascade = 9;
    assert_int_equal(sq_gen_render(&p, &o, &t, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "RD_Cascade");
    static const char bad[] =
        "{\"format\": \"squama-preset/1\", \"Pattern_Type\": \"complex\", \"RD_System\": \"waves\"}";
    SqError perr;
    assert_int_not_equal(sq_preset_parse(bad, sizeof bad - 1, "bad.json", &p, NULL, &perr), SQ_OK);
    assert_contains(perr.what, "RD_System");
    assert_contains(perr.what, "spots, stripes");
}

static void shipped_complex_presets_render(void **state)
{
    (void)state;
    static const char *const names[] = {"cheetah", "leopard", "giraffe", "python_reticulated",
                                        "boa_saddles", "viper_blotches", "viper_zigzag",
                                        "stripes_on_stripes"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        char rel[256], path[1024];
        snprintf(rel, sizeof rel, "presets/complex/%s.json", names[k]);
        SqParams p;
        SqError err;
        if (sq_preset_load(src_path(path, sizeof path, rel), &p, NULL, &err) != SQ_OK)
            fail_msg("%s: %s", rel, err.what);
        assert_int_equal(p.Pattern_Type, SQ_PATTERN_COMPLEX);
        SqTextures t;
        SqGenOptions o = sq_gen_options_default(64);
        if (sq_gen_render(&p, &o, &t, &err) != SQ_OK)
            fail_msg("%s: %s", rel, err.what);
        /* a pattern: the colour map is not one flat colour */
        float lo = 1, hi = 0;
        for (int i = 0; i < 64 * 64; i++) {
            float g = t.basecolor.px[3 * i + 1];
            lo = g < lo ? g : lo;
            hi = g > hi ? g : hi;
        }
        if (hi - lo < 0.1f)
            fail_msg("%s: flat colour map (%g..%g)", rel, (double)lo, (double)hi);
        sq_gen_textures_free(&t);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spots_stay_finite_and_bounded),
        cmocka_unit_test(settled_spots_balance_their_reaction),
        cmocka_unit_test(stripes_stay_finite_and_bounded),
        cmocka_unit_test(larger_s_makes_smaller_spots),
        cmocka_unit_test(texture_is_seamless),
        cmocka_unit_test(same_pixels_on_one_and_two_threads),
        cmocka_unit_test(cascade_makes_two_feature_sizes),
        cmocka_unit_test(feature_distances_are_nearest_and_other),
        cmocka_unit_test(net_cascade_is_one_thin_connected_net),
        cmocka_unit_test(rosette_ring_surrounds_the_large_spots),
        cmocka_unit_test(stripes_between_stripes_leave_gaps),
        cmocka_unit_test(bad_parameters_are_refused_by_name),
        cmocka_unit_test(shipped_complex_presets_render),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
