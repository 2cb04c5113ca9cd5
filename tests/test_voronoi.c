/* The Voronoi scale layout (Scales_Layout voronoi): the tessellation (cell count, the
 * fixed lateral line, relaxation, anisotropy), the height map it paints (no holes,
 * seams, thread counts), the grid left as it was, and refusals. */
#define _DEFAULT_SOURCE
#include <math.h>
#include <stdlib.h>

#include "gen_internal.h"
#include "sq_test.h"
#include "squama/generator.h"
#include "squama/preset.h"

static void voronoi_params(SqParams *p)
{
    sq_params_default(p);
    p->Scales_Layout = SQ_LAYOUT_VORONOI;
}

static void build(const SqParams *p, int iterations, SqVoronoi *vo)
{
    SqError err;
    if (sq__voronoi_build(p, iterations, vo, &err) != SQ_OK)
        fail_msg("voronoi: %s (%s)", err.what, err.where);
}

/* Coefficient of variation of the cells' areas. */
static double area_spread(const SqVoronoi *vo)
{
    double m = 0, v = 0;
    for (int k = 0; k < vo->n; k++)
        m += vo->area[k];
    m /= vo->n;
    for (int k = 0; k < vo->n; k++)
        v += (vo->area[k] - m) * (vo->area[k] - m);
    return sqrt(v / vo->n) / m;
}

/* Mean over cells of (extent along v) / (extent across, u), both in scale spacings. */
static double elongation(const SqVoronoi *vo)
{
    double r = 0;
    for (int k = 0; k < vo->n; k++) {
        double eu = (vo->bu1[k] - vo->bu0[k] + 1.0 / vo->rw) * vo->X * M_SQRT2;
        double ev = (vo->bv1[k] - vo->bv0[k] + 1.0 / vo->rh) * vo->Y / M_SQRT2;
        r += ev / eu;
    }
    return r / vo->n;
}

static void one_cell_per_site(void **state)
{
    (void)state;
    static const int sizes[][2] = {{16, 32}, {7, 5}, {17, 47}, {1, 1}, {3, 64}, {40, 9}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        SqParams p;
        voronoi_params(&p);
        p.Scales_XAmount = sizes[i][0];
        p.Scales_YAmount = sizes[i][1];
        for (int a = 0; a < 3; a++) {
            p.Scales_VoronoiAnisotropy = a * 2.0; /* up to the hard maximum, 4 */
            SqVoronoi vo;
            build(&p, SQ_VORONOI_ITERATIONS, &vo);
            assert_int_equal(vo.n, sizes[i][0] * sizes[i][1]);
            int cells = 0;
            for (int k = 0; k < vo.n; k++)
                cells += vo.area[k] > 0;
            if (cells != vo.n)
                fail_msg("%dx%d alpha %g: %d cells for %d sites", sizes[i][0], sizes[i][1],
                         p.Scales_VoronoiAnisotropy, cells, vo.n);
            sq__voronoi_free(&vo);
        }
    }
}

/* Every sample of the final raster lies in the cell of its nearest site by the segment
 * distance (recomputed here over every site, to rounding), on layouts whose farthest
 * sample is more than a spacing from every site (beyond the search's reach: 64 x 1, and
 * jittered grids before relaxation) and on ordinary ones, round and elongated; and the
 * search with a short reach, most samples left to its fallback, gives the same cells. */
static void every_sample_in_its_nearest_cell(void **state)
{
    (void)state;
    static const int sizes[][2] = {{16, 32}, {64, 1}, {40, 9}, {1, 1}, {3, 64}, {2, 3}, {7, 5}};
    double farthest = 0;
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        for (int a = 0; a < 3; a++)
            for (int seed = 0; seed < 2; seed++) {
                const int iterations = seed % 2 ? SQ_VORONOI_ITERATIONS : 0;
                SqParams p;
                voronoi_params(&p);
                p.Scales_XAmount = sizes[i][0];
                p.Scales_YAmount = sizes[i][1];
                p.Scales_VoronoiAnisotropy = a * 1.25;
                p.Seed = seed;
                SqVoronoi vo;
                build(&p, iterations, &vo);
                const double DU = vo.X * M_SQRT2, DV = vo.Y / M_SQRT2, al = p.Scales_VoronoiAnisotropy;
                for (int y = 0; y < vo.rh; y++)
                    for (int x = 0; x < vo.rw; x++) {
                        const double U = (x + 0.5) / vo.rw * DU, V = (y + 0.5) / vo.rh * DV;
                        double best = INFINITY, mine = INFINITY;
                        for (int k = 0; k < vo.n; k++) {
                            double du = fabs(U - vo.u[k] * DU), dc = fabs(V - vo.v[k] * DV);
                            du = fmin(du, DU - du);
                            dc = fmin(dc, DV - dc);
                            const double dv = fmax(dc - al, 0), d = du * du + dv * dv + 0.05 * dc * dc;
                            best = fmin(best, d);
                            if (k == vo.owner[y * vo.rw + x])
                                mine = d;
                        }
                        if (!(mine <= best + 1e-9))
                            fail_msg("%dx%d alpha %g seed %d, %d iterations: sample (%d, %d) in a cell at "
                                     "distance^2 %.6f, a site is at %.6f",
                                     vo.X, vo.Y, al, seed, iterations, x, y, mine, best);
                        farthest = fmax(farthest, best);
                    }
                /* a short reach leaves most samples to the fallback: the same cells */
                SqVoronoi vs;
                SqError err;
                if (sq__voronoi_build_reach(&p, iterations, 0.3, &vs, &err) != SQ_OK)
                    fail_msg("voronoi: %s (%s)", err.what, err.where);
                assert_int_equal(vs.rw * vs.rh, vo.rw * vo.rh);
                assert_memory_equal(vs.owner, vo.owner, sizeof(int) * vo.rw * vo.rh);
                assert_memory_equal(vs.u, vo.u, sizeof(double) * vo.n);
                assert_memory_equal(vs.v, vo.v, sizeof(double) * vo.n);
                sq__voronoi_free(&vs);
                sq__voronoi_free(&vo);
            }
    if (!(sqrt(farthest) > 1.0))
        fail_msg("no sample farther than a spacing from every site (%.3f): the fallback is not tried",
                 sqrt(farthest));
}

static void lateral_line_held_fixed(void **state)
{
    (void)state;
    SqParams p;
    voronoi_params(&p);
    p.Seed = 77;
    SqVoronoi v0, v1;
    build(&p, 0, &v0);
    build(&p, SQ_VORONOI_ITERATIONS, &v1);
    int fixed = 0, moved = 0;
    for (int k = 0; k < v0.n; k++) {
        assert_int_equal(v0.fixed[k], v1.fixed[k]);
        if (v0.fixed[k]) {
            fixed++;
            assert_true(v0.u[k] == 0.5 && v1.u[k] == 0.5); /* the dorsal midline */
            assert_true(v0.v[k] == v1.v[k]);
        } else if (fabs(v0.u[k] - v1.u[k]) + fabs(v0.v[k] - v1.v[k]) > 1e-3) {
            moved++;
        }
    }
    assert_int_equal(fixed, p.Scales_YAmount / 2); /* every other row */
    assert_true(moved > v0.n / 2);                  /* the others did relax */
    sq__voronoi_free(&v0);
    sq__voronoi_free(&v1);
}

static void relaxation_evens_the_cells(void **state)
{
    (void)state;
    for (int a = 0; a < 3; a++) {
        SqParams p;
        voronoi_params(&p);
        p.Scales_VoronoiAnisotropy = a * 0.5;
        p.Seed = 5 + a;
        SqVoronoi v0, v1;
        build(&p, 0, &v0);
        build(&p, SQ_VORONOI_ITERATIONS, &v1);
        double s0 = area_spread(&v0), s1 = area_spread(&v1);
        if (!(s1 < 0.75 * s0))
            fail_msg("alpha %g: area spread %.4f before relaxation, %.4f after", p.Scales_VoronoiAnisotropy, s0, s1);
        if (a == 0) { /* isotropic: Lloyd's algorithm lowers the centroidal energy */
            double e0 = sq__voronoi_energy(&v0), e1 = sq__voronoi_energy(&v1);
            if (!(e1 < e0))
                fail_msg("centroidal energy %.5f before relaxation, %.5f after", e0, e1);
        }
        sq__voronoi_free(&v0);
        sq__voronoi_free(&v1);
    }
}

static void anisotropy_stretches_cells_along_the_body(void **state)
{
    (void)state;
    double r[3];
    for (int a = 0; a < 3; a++) {
        SqParams p;
        voronoi_params(&p);
        p.Scales_VoronoiAnisotropy = a * 0.75;
        SqVoronoi vo;
        build(&p, SQ_VORONOI_ITERATIONS, &vo);
        r[a] = elongation(&vo);
        sq__voronoi_free(&vo);
    }
    /* round cells are about as tall as wide; segments make them longer along v */
    if (!(r[0] < 1.25 && r[1] > 1.3 && r[2] > r[1] && r[1] > r[0]))
        fail_msg("elongation (v / u extent) at alpha 0, 0.75, 1.5: %.3f %.3f %.3f", r[0], r[1], r[2]);
}

/* The painted height: every cell's scale covers it (no holes in the lateral skin). */
static void no_holes_between_scales(void **state)
{
    (void)state;
    const int w = 256, h = 256;
    float *height = malloc(sizeof(float) * w * h), *trans = malloc(sizeof(float) * w * h);
    assert_non_null(height);
    assert_non_null(trans);
    for (int a = 0; a < 3; a++) {
        SqParams p;
        voronoi_params(&p);
        p.Scales_VoronoiAnisotropy = a * 0.75;
        p.Scales_BellyScalesPct = 0;
        SqError err;
        assert_int_equal(sq__scales_voronoi(&p, height, trans, w, h, &err), SQ_OK);
        /* trans is the light still passing each pixel after every scale */
        int open = 0;
        for (int i = 0; i < w * h; i++)
            open += trans[i] > 0.5f;
        if (open > w * h / 1000)
            fail_msg("alpha %g: %d of %d pixels uncovered", p.Scales_VoronoiAnisotropy, open, w * h);
    }
    free(height);
    free(trans);
}

static void render(const SqParams *p, int size, int threads, SqTextures *t)
{
    SqGenOptions o = sq_gen_options_default(size);
    o.threads = threads;
    SqError err;
    if (sq_gen_render(p, &o, t, &err) != SQ_OK)
        fail_msg("render: %s (%s)", err.what, err.where);
}

/* Mean absolute step between columns a and b (or rows a and b). */
static double col_diff(const SqImage *m, int a, int b)
{
    double s = 0;
    for (int y = 0; y < m->height; y++)
        s += fabs(sq_image_at(m, a, y)[0] - sq_image_at(m, b, y)[0]);
    return s / m->height;
}

static double row_diff(const SqImage *m, int a, int b)
{
    double s = 0;
    for (int x = 0; x < m->width; x++)
        s += fabs(sq_image_at(m, x, a)[0] - sq_image_at(m, x, b)[0]);
    return s / m->width;
}

/* The step across the tile's edge against the steps between neighbours inside: no more
 * than 1.5 times their mean; along v with the belly (whose ventral scales' straight edges
 * run across it and may fall on the edge) no more than the largest of them. */
static void assert_seamless(const SqImage *m, const char *what, int belly)
{
    const int w = m->width, h = m->height;
    double iu = 0, iv = 0, mv = 0;
    for (int x = 0; x + 1 < w; x++)
        iu += col_diff(m, x, x + 1);
    for (int y = 0; y + 1 < h; y++) {
        double d = row_diff(m, y, y + 1);
        iv += d;
        mv = d > mv ? d : mv;
    }
    iu /= w - 1;
    iv /= h - 1;
    double su = col_diff(m, w - 1, 0), sv = row_diff(m, h - 1, 0);
    if (su > 1.5 * iu + 1e-4)
        fail_msg("%s: u seam step %.4f, inside mean %.4f", what, su, iu);
    if (sv > (belly ? mv : 1.5 * iv) + 1e-4)
        fail_msg("%s: v seam step %.4f, inside mean %.4f, max %.4f", what, sv, iv, mv);
}

static void height_map_tiles(void **state)
{
    (void)state;
    for (int belly = 0; belly < 2; belly++)
        for (int a = 0; a < 3; a++) {
            SqParams p;
            voronoi_params(&p);
            p.Scales_VoronoiAnisotropy = 0.3 + 0.9 * a;
            p.Scales_BellyScalesPct = belly ? 0.15 : 0;
            p.Scales_XAmount = 13;
            p.Scales_YAmount = 27;
            p.Seed = 3 + a;
            SqTextures t;
            render(&p, 256, 0, &t);
            assert_seamless(&t.height, belly ? "height (belly)" : "height", belly);
            assert_seamless(&t.roughness, "roughness", 0);
            sq_gen_textures_free(&t);
        }
}

static void same_pixels_on_one_or_two_threads(void **state)
{
    (void)state;
    SqParams p;
    voronoi_params(&p);
    p.Scales_SizeRandom = 0.2;
    p.Scales_RotationRandom = 8;
    p.Scales_BellyWarpIntensity = 4;
    p.Seed = 4242;
    SqTextures a, b;
    render(&p, 200, 1, &a);
    render(&p, 200, 2, &b);
    const SqImage *ma[] = {&a.basecolor, &a.height, &a.roughness, &a.normal};
    const SqImage *mb[] = {&b.basecolor, &b.height, &b.roughness, &b.normal};
    for (int i = 0; i < 4; i++)
        assert_memory_equal(ma[i]->px, mb[i]->px,
                            sizeof(float) * (size_t)ma[i]->width * ma[i]->height * ma[i]->channels);
    sq_gen_textures_free(&a);
    sq_gen_textures_free(&b);
}

/* The layout is a real switch, the grid is the default, and the seed moves the cells. */
static void grid_default_voronoi_different(void **state)
{
    (void)state;
    SqParams g, v, v2;
    sq_params_default(&g);
    assert_int_equal(g.Scales_Layout, SQ_LAYOUT_GRID);
    voronoi_params(&v);
    v2 = v;
    v2.Seed = 99;
    SqTextures tg, tv, tv2;
    render(&g, 128, 0, &tg);
    render(&v, 128, 0, &tv);
    render(&v2, 128, 0, &tv2);
    const size_t n = (size_t)128 * 128 * sizeof(float);
    assert_true(memcmp(tg.height.px, tv.height.px, n) != 0);
    assert_true(memcmp(tv.height.px, tv2.height.px, n) != 0);
    sq_gen_textures_free(&tg);
    sq_gen_textures_free(&tv);
    sq_gen_textures_free(&tv2);
}

static void refusals_name_the_key(void **state)
{
    (void)state;
    static const struct { const char *json, *key; } bad[] = {
        {"{\"format\": \"squama-preset/1\", \"Scales_Layout\": \"hexagonal\"}", "Scales_Layout"},
        {"{\"format\": \"squama-preset/1\", \"Scales_Layout\": 1}", "Scales_Layout"},
        {"{\"format\": \"squama-preset/1\", \"Scales_VoronoiAnisotropy\": 9}", "Scales_VoronoiAnisotropy"},
        {"{\"format\": \"squama-preset/1\", \"Scales_VoronoiAnisotropy\": -0.5}", "Scales_VoronoiAnisotropy"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        SqParams p;
        SqError err;
        assert_int_not_equal(sq_preset_parse(bad[i].json, strlen(bad[i].json), "bad.json", &p, NULL, &err), SQ_OK);
        assert_contains(err.what, bad[i].key);
    }
    const char *good = "{\"format\": \"squama-preset/1\", \"Scales_Layout\": \"voronoi\", "
                       "\"Scales_VoronoiAnisotropy\": 0.8}";
    SqParams p;
    SqError err;
    assert_int_equal(sq_preset_parse(good, strlen(good), "good.json", &p, NULL, &err), SQ_OK);
    assert_int_equal(p.Scales_Layout, SQ_LAYOUT_VORONOI);
    assert_true(p.Scales_VoronoiAnisotropy == 0.8);
    /* and a bad value set in code is refused by the render, naming the key */
    p.Scales_Layout = 7;
    SqTextures t;
    assert_int_not_equal(sq_gen_render(&p, NULL, &t, &err), SQ_OK);
    assert_contains(err.what, "Scales_Layout");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(one_cell_per_site),
        cmocka_unit_test(every_sample_in_its_nearest_cell),
        cmocka_unit_test(lateral_line_held_fixed),
        cmocka_unit_test(relaxation_evens_the_cells),
        cmocka_unit_test(anisotropy_stretches_cells_along_the_body),
        cmocka_unit_test(no_holes_between_scales),
        cmocka_unit_test(height_map_tiles),
        cmocka_unit_test(same_pixels_on_one_or_two_threads),
        cmocka_unit_test(grid_default_voronoi_different),
        cmocka_unit_test(refusals_name_the_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
