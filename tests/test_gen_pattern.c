/* The pattern types, by measurable properties: bands where begin/end put them, N stripes
 * as N runs, spot counts as the tiling says, automaton rows as the rule arithmetic. */
#include <math.h>
#include <stdlib.h>

#include "gen_internal.h"
#include "sq_test.h"
#include "squama/generator.h"

static SqParams base(SqPatternType type)
{
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = type;
    p.Background_Color[0] = p.Background_Color[1] = p.Background_Color[2] = 0.0;
    return p;
}

static void render(const SqParams *p, int size, SqTextures *t)
{
    SqGenOptions o = sq_gen_options_default(size);
    SqError err;
    if (sq_gen_render(p, &o, t, &err) != SQ_OK)
        fail_msg("render: %s (%s)", err.what, err.where);
}

/* Table 4.1: each colour covers exactly the rows its begin/end ask for (no warp). */
static void transversal_bands_cover_their_rows(void **state)
{
    (void)state;
    SqParams p = base(SQ_PATTERN_TRANSVERSAL);
    static const double be[4][2] = {{0.0, 0.25}, {0.3, 0.45}, {0.6, 0.65}, {0.8, 1.0}};
    static const double col[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}};
    for (int i = 0; i < 4; i++) {
        for (int c = 0; c < 3; c++)
            p.Transversal_Color[i][c] = col[i][c];
        p.Transversal_Color[i][3] = 1;
        p.Transversal_BeginEnd[i][0] = be[i][0];
        p.Transversal_BeginEnd[i][1] = be[i][1];
    }
    const int n = 200; /* band edges fall on pixel edges: 0.25 * 200 = 50 */
    SqTextures t;
    render(&p, n, &t);
    for (int y = 0; y < n; y++) {
        double v = (y + 0.5) / n;
        int want = -1;
        for (int i = 0; i < 4; i++)
            if (v >= be[i][0] && v < be[i][1])
                want = i;
        for (int x = 0; x < n; x += 37) {
            const float *px = sq_image_at(&t.basecolor, x, y);
            for (int c = 0; c < 3; c++) {
                double exp = want < 0 ? 0.0 : col[want][c];
                if (fabs(px[c] - exp) > 1e-6)
                    fail_msg("row %d (v=%.3f) channel %d: %g, want %g", y, v, c, px[c], exp);
            }
        }
    }
    sq_gen_textures_free(&t);
}

/* Later colours occlude earlier ones, and begin = end or alpha 0 omits a colour. */
static void transversal_order_and_omission(void **state)
{
    (void)state;
    SqParams p = base(SQ_PATTERN_TRANSVERSAL); /* Table 4.2 */
    double black[4] = {0, 0, 0, 1}, yellow[4] = {0.9, 0.8, 0.5, 1}, blue[4] = {0, 0, 1, 1};
    memcpy(p.Transversal_Color[0], black, sizeof black);
    memcpy(p.Transversal_Color[1], yellow, sizeof yellow);
    memcpy(p.Transversal_Color[2], yellow, sizeof yellow);
    memcpy(p.Transversal_Color[3], blue, sizeof blue);
    double be[4][2] = {{0.1, 0.9}, {0.3, 0.4}, {0.6, 0.7}, {1.0, 1.0}};
    memcpy(p.Transversal_BeginEnd, be, sizeof be);
    p.Background_Color[0] = 0.8;
    SqTextures t;
    render(&p, 100, &t);
    assert_true(fabsf(sq_image_at(&t.basecolor, 5, 35)[0] - 0.9f) < 1e-6f); /* yellow over black */
    assert_true(sq_image_at(&t.basecolor, 5, 20)[0] < 1e-6f);               /* black */
    assert_true(fabsf(sq_image_at(&t.basecolor, 5, 95)[0] - 0.8f) < 1e-6f); /* background */
    for (int y = 0; y < 100; y++)
        assert_true(sq_image_at(&t.basecolor, 50, y)[2] < 0.51f); /* no blue anywhere */
    sq_gen_textures_free(&t);

    p.Transversal_Color[0][3] = 0; /* alpha 0: black omitted */
    render(&p, 100, &t);
    assert_true(fabsf(sq_image_at(&t.basecolor, 5, 20)[0] - 0.8f) < 1e-6f);
    sq_gen_textures_free(&t);
}

static void transversal_band_wraps(void **state)
{
    (void)state;
    assert_true(fabs(sq__band_coverage(0, 10, 0.9, 0.1) - 1.0) < 1e-9);
    assert_true(fabs(sq__band_coverage(9, 10, 0.9, 0.1) - 1.0) < 1e-9);
    assert_true(sq__band_coverage(5, 10, 0.9, 0.1) == 0.0);
    assert_true(fabs(sq__band_coverage(2, 10, 0.25, 0.5) - 0.5) < 1e-12);
}

/* Runs of coverage above one half along a periodic line. */
static int count_runs(const float *v, int n, int stride)
{
    int runs = 0;
    for (int i = 0; i < n; i++) {
        int on = v[(size_t)i * stride] > 0.5f, prev = v[(size_t)((i + n - 1) % n) * stride] > 0.5f;
        runs += on && !prev;
    }
    return runs;
}

static void longitudinal_n_stripes_n_runs(void **state)
{
    (void)state;
    for (int n = 1; n <= 10; n++) {
        SqParams p = base(SQ_PATTERN_LONGITUDINAL);
        p.Longitudinal_NumberOfStripes = n;
        p.Longitudinal_StripesWidth = 0.4;
        p.Longitudinal_StripesColor[0] = 1;
        p.Longitudinal_Pinch = n % 2 ? 1.0 : 1.8;
        SqTextures t;
        render(&p, 256, &t);
        int runs = count_runs(t.basecolor.px + 3 * 256 * 100, 256, 3);
        if (runs != n)
            fail_msg("%d stripes (pinch %g) gave %d runs", n, p.Longitudinal_Pinch, runs);
        sq_gen_textures_free(&t);
    }
}

/* Pinch 2 squeezes the pattern into the middle half; widths add up. */
static void longitudinal_pinch_and_width(void **state)
{
    (void)state;
    const int w = 400;
    double total = 0, outside = 0;
    for (int x = 0; x < w; x++) {
        double c = sq__stripe_coverage(x, w, 3, 0.3, 2.0);
        total += c;
        if (x < w / 4 || x >= 3 * w / 4)
            outside += c;
    }
    assert_true(outside == 0.0);
    assert_true(fabs(total / w - 0.3 / 2) < 1e-9); /* the stripes' share halves */
    total = 0;
    for (int x = 0; x < w; x++)
        total += sq__stripe_coverage(x, w, 5, 0.2, 1.0);
    assert_true(fabs(total / w - 0.2) < 1e-9);
    /* the pattern is symmetric about the dorsal midline, so u = 0 meets u = 1 */
    for (int x = 0; x < w; x++)
        assert_true(fabs(sq__stripe_coverage(x, w, 4, 0.5, 0.7) -
                         sq__stripe_coverage(w - 1 - x, w, 4, 0.5, 0.7)) < 1e-9);
}

/* The zig-zag: every row holds the one stripe, its centre follows a triangle wave of v
 * with the amplitude and count asked for, and the texture still tiles along v. */
static void longitudinal_zigzag_follows_a_triangle_wave(void **state)
{
    (void)state;
    enum { W = 256, H = 256 };
    SqParams p = base(SQ_PATTERN_LONGITUDINAL);
    p.Longitudinal_NumberOfStripes = 1;
    p.Longitudinal_StripesWidth = 0.1;
    p.Longitudinal_StripesColor[0] = 1;
    p.Longitudinal_ZigzagAmplitude = 0.08;
    p.Longitudinal_ZigzagCount = 4;
    SqTextures t;
    render(&p, W, &t);
    double lo = 1, hi = 0;
    for (int y = 0; y < H; y++) {
        const float *row = t.basecolor.px + (size_t)3 * W * y;
        assert_int_equal(count_runs(row, W, 3), 1);
        double m = 0, s = 0;
        for (int x = 0; x < W; x++) {
            m += row[3 * x] * (x + 0.5);
            s += row[3 * x];
        }
        const double c = m / s / W, f = fmod((y + 0.5) / H * 4, 1.0);
        const double want = 0.5 + 0.08 * (f < 0.5 ? 4 * f - 1 : 3 - 4 * f);
        if (fabs(c - want) > 0.01)
            fail_msg("row %d: stripe centre %.4f, the triangle wave says %.4f", y, c, want);
        lo = c < lo ? c : lo;
        hi = c > hi ? c : hi;
    }
    assert_true(hi - lo > 0.15); /* twice the amplitude */
    /* the last row meets the first */
    double d = 0;
    for (int x = 0; x < W; x++)
        d += fabs(t.basecolor.px[3 * x] - t.basecolor.px[(size_t)3 * W * (H - 1) + 3 * x]);
    assert_true(d / W < 0.05);
    sq_gen_textures_free(&t);
}

/* The rings' zig-zag: every column holds the one band, its centre follows a triangle wave
 * of u with the amplitude and count asked for (a peak on the dorsal midline), each column
 * still covers exactly the band's length, and u = 0 meets u = 1. A band that wraps over
 * the texture's top and bottom edges is shifted as well, and keeps its length. */
static const double TAU = 6.283185307179586;

static double column_centre(const SqTextures *t, int x, int w, int h, double *length)
{
    double s = 0, cx = 0, cy = 0; /* a circular mean: the band may wrap */
    for (int y = 0; y < h; y++) {
        const double v = t->basecolor.px[((size_t)y * w + x) * 3], th = TAU * (y + 0.5) / h;
        s += v;
        cx += v * cos(th);
        cy += v * sin(th);
    }
    *length = s / h;
    const double c = atan2(cy, cx) / TAU;
    return c - floor(c);
}

static void transversal_zigzag_follows_a_triangle_wave(void **state)
{
    (void)state;
    enum { W = 256, H = 256 };
    SqParams p = base(SQ_PATTERN_TRANSVERSAL);
    for (int i = 1; i < 4; i++)
        p.Transversal_BeginEnd[i][0] = p.Transversal_BeginEnd[i][1] = 1;
    p.Transversal_Color[0][0] = p.Transversal_Color[0][1] = p.Transversal_Color[0][2] = 1;
    p.Transversal_ZigzagAmplitude = 0.1;
    p.Transversal_ZigzagCount = 3;
    static const double band[2][2] = {{0.4, 0.6}, {0.9, 0.05}}; /* the second wraps */
    for (int b = 0; b < 2; b++) {
        p.Transversal_BeginEnd[0][0] = band[b][0];
        p.Transversal_BeginEnd[0][1] = band[b][1];
        const double centre = b ? 0.975 : 0.5, length = b ? 0.15 : 0.2;
        SqTextures t;
        render(&p, W, &t);
        double lo = 1, hi = -1;
        for (int x = 0; x < W; x++) {
            double len;
            const double c = column_centre(&t, x, W, H, &len);
            const double tw = ((x + 0.5) / W - 0.5) * 3 + 0.5, f = tw - floor(tw);
            const double wave = f < 0.5 ? 4 * f - 1 : 3 - 4 * f;
            double d = c - (centre + 0.1 * wave);
            d -= floor(d + 0.5); /* the nearest way round */
            if (fabs(d) > 0.005 || fabs(len - length) > 1e-4)
                fail_msg("band %d, column %d: centre %.4f and length %.5f; the triangle wave says %.4f and %.2f", b,
                         x, c, len, centre + 0.1 * wave, length);
            lo = d + 0.1 * wave < lo ? d + 0.1 * wave : lo;
            hi = d + 0.1 * wave > hi ? d + 0.1 * wave : hi;
        }
        assert_true(hi - lo > 0.19); /* twice the amplitude */
        double seam = 0;
        for (int y = 0; y < H; y++)
            seam += fabs(t.basecolor.px[(size_t)y * W * 3] - t.basecolor.px[((size_t)y * W + W - 1) * 3]);
        assert_true(seam / H < 0.05);
        sq_gen_textures_free(&t);
    }
}

/* Connected components of coverage > 0.5, wrapping at the edges (4-neighbours). */
static int count_blobs(const float *cov, int w, int h)
{
    int *lab = calloc((size_t)w * h, sizeof(int)), *stack = malloc(sizeof(int) * (size_t)w * h);
    int blobs = 0;
    for (int i = 0; i < w * h; i++) {
        if (lab[i] || cov[i] <= 0.5f)
            continue;
        blobs++;
        int top = 0;
        stack[top++] = i;
        lab[i] = blobs;
        while (top) {
            int k = stack[--top], x = k % w, y = k / w;
            int nb[4] = {y * w + (x + 1) % w, y * w + (x + w - 1) % w, ((y + 1) % h) * w + x,
                         ((y + h - 1) % h) * w + x};
            for (int d = 0; d < 4; d++)
                if (!lab[nb[d]] && cov[nb[d]] > 0.5f) {
                    lab[nb[d]] = blobs;
                    stack[top++] = nb[d];
                }
        }
    }
    free(lab);
    free(stack);
    return blobs;
}

static void spot_count_matches_tiling(void **state)
{
    (void)state;
    static const struct { double tiling, offset; int want; } cases[] = {
        {1.0, 0.0, 100}, {0.5, 0.0, 25}, {2.0, 0.0, 400}, {1.5, 0.0, 225}, {0.7, 0.5, 56},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        SqParams p = base(SQ_PATTERN_SPOTS);
        p.Spots_Tiling = cases[k].tiling;
        p.Spots_Offset = cases[k].offset;
        p.Spots_Scale = 0.6;
        p.Spots_ScaleVariation = 0.3;
        p.Spots_PositionRandom[0] = p.Spots_PositionRandom[1] = 0.15;
        p.Spots_RotationRandom = 40;
        p.Spots_Interstice[0] = 0.3;
        SqPattern pat = {.w = 400, .h = 400};
        SqError err;
        assert_int_equal(sq__pattern_spots(&p, &pat, &err), SQ_OK);
        int nx, ny;
        sq__spots_grid(&p, 400, 400, &nx, &ny);
        assert_int_equal(nx * ny, cases[k].want);
        int blobs = count_blobs(pat.layers[0].cov, 400, 400);
        if (blobs != cases[k].want)
            fail_msg("tiling %g: %d spots, want %d", cases[k].tiling, blobs, cases[k].want);
        sq__pattern_free(&pat);
    }
}

/* Spot shapes: interstice narrows the width; rotation turns the ellipse. */
static void spot_shape_follows_interstice(void **state)
{
    (void)state;
    SqParams p = base(SQ_PATTERN_SPOTS);
    p.Spots_Tiling = 0.1; /* one spot */
    p.Spots_Scale = 0.8;
    p.Spots_Interstice[0] = 0.5;
    SqPattern pat = {.w = 200, .h = 200};
    SqError err;
    assert_int_equal(sq__pattern_spots(&p, &pat, &err), SQ_OK);
    int wide = 0, tall = 0;
    for (int i = 0; i < 200; i++) {
        wide += pat.layers[0].cov[100 * 200 + i] > 0.5f;
        tall += pat.layers[0].cov[i * 200 + 100] > 0.5f;
    }
    /* diameter 0.8 of the texture (160 px; coverage passes 1/2 at 90% of the radius, the
     * soft rim of the thesis' cone with raised midtones), width halved */
    assert_true(tall >= 140 && tall <= 162);
    assert_true(abs(2 * wide - tall) <= 4);
    sq__pattern_free(&pat);
}

/* The Figure 4.9 example, row by row: 1110 once, 1100 once, 1000 for the rest. */
static void ca_rows_follow_the_rules(void **state)
{
    (void)state;
    SqCa ca;
    SqError err;
    const char *text = "0 0 1 1 1 1 0 0\nrectangular\n0\n6\n1110 1\n1100 1\n1000 x\n";
    assert_int_equal(sq_ca_parse(text, strlen(text), "t", &ca, &err), SQ_OK);
    uint8_t rows[6 * 8];
    sq_ca_evolve(&ca, rows);
    static const uint8_t want[6][8] = {
        {0, 0, 1, 1, 1, 1, 0, 0}, /* initial values */
        {0, 1, 1, 1, 1, 1, 1, 0}, /* 1110: 0 only where the cell and both neighbours are 0 */
        {0, 1, 1, 1, 1, 1, 1, 0}, /* 1100: 1 where the sum is 2 or 3: duplicates */
        {0, 0, 1, 1, 1, 1, 0, 0}, /* 1000: 1 only where all three are 1 */
        {0, 0, 0, 1, 1, 0, 0, 0},
        {0, 0, 0, 0, 0, 0, 0, 0},
    };
    assert_memory_equal(rows, want, sizeof want);

    /* wrap-around: a 1 at the right end reaches the left end */
    const char *wrap = "1 0 0 0 0 1\nrectangular\n0\n2\n1110 x\n";
    assert_int_equal(sq_ca_parse(wrap, strlen(wrap), "t", &ca, &err), SQ_OK);
    uint8_t r2[12];
    sq_ca_evolve(&ca, r2);
    static const uint8_t w2[6] = {1, 1, 0, 0, 1, 1};
    assert_memory_equal(r2 + 6, w2, 6);
}

/* Triangular: odd rows sit half a cell right and read cells c and c + 1 above; even rows
 * read c - 1 and c. Rule bits: sum 2, 1, 0. */
static void ca_triangular_neighbourhoods(void **state)
{
    (void)state;
    SqCa ca;
    SqError err;
    const char *text = "0 1 0 0 0\ntriangular\n0\n3\n110 x\n"; /* 1 where the sum >= 1 */
    assert_int_equal(sq_ca_parse(text, strlen(text), "t", &ca, &err), SQ_OK);
    uint8_t rows[15];
    sq_ca_evolve(&ca, rows);
    static const uint8_t want[3][5] = {
        {0, 1, 0, 0, 0},
        {1, 1, 0, 0, 0}, /* odd: cells c, c+1 above: c=0 sees (0,1), c=1 sees (1,0) */
        {1, 1, 1, 0, 0}, /* even: cells c-1, c above: c=2 sees (1,0) */
    };
    assert_memory_equal(rows, want, sizeof want);
}

/* The automaton image: 2 x epochs rows (the mirror on top) over the texture height, the
 * cells across its width; a 1 cell paints a circle of CA_CircleDiameter. */
static void ca_image_mirrors_and_shifts(void **state)
{
    (void)state;
    SqParams p = base(SQ_PATTERN_OTHER_SIMPLE);
    SqError err;
    const char *text = "1 0 0 0\nrectangular\n0\n2\n0000 x\n"; /* row 0: one cell; row 1: empty */
    assert_int_equal(sq_ca_parse(text, strlen(text), "t", &p.CA_Descriptor, &err), SQ_OK);
    const int w = 80, h = 80; /* 4 x 4 cells of 20 px */
    float *cov = calloc((size_t)w * h, sizeof(float));
    assert_int_equal(sq_ca_coverage(&p.CA_Descriptor, p.CA_CircleDiameter, cov, w, h, &err), SQ_OK);
    /* display rows: 0 = mirror of row 1 (empty), 1 = mirror of row 0, 2 = row 0, 3 = row 1 */
    assert_true(cov[(1 * 20 + 10) * w + 10] > 0.99f); /* mirror of row 0, cell 0 */
    assert_true(cov[(2 * 20 + 10) * w + 10] > 0.99f); /* row 0, cell 0 */
    assert_true(cov[(0 * 20 + 10) * w + 10] < 0.01f);
    assert_true(cov[(3 * 20 + 10) * w + 10] < 0.01f);
    assert_true(cov[(2 * 20 + 10) * w + 30] < 0.01f);
    /* shift mirror 3 moves the mirrored copy by one circle diameter: cell 1 */
    p.CA_Descriptor.shift_mirror = 3;
    assert_int_equal(sq_ca_coverage(&p.CA_Descriptor, p.CA_CircleDiameter, cov, w, h, &err), SQ_OK);
    assert_true(cov[(1 * 20 + 10) * w + 30] > 0.99f);
    assert_true(cov[(1 * 20 + 10) * w + 10] < 0.01f);
    assert_true(cov[(2 * 20 + 10) * w + 10] > 0.99f); /* the original stays */
    free(cov);
}

/* Rotate 90 degrees turns rings into stripes along the body. */
static void rotate_turns_rings_into_stripes(void **state)
{
    (void)state;
    SqParams p = base(SQ_PATTERN_TRANSVERSAL);
    p.Transversal_Color[0][0] = 1;
    p.Transversal_BeginEnd[0][0] = 0.2;
    p.Transversal_BeginEnd[0][1] = 0.4;
    p.Pattern_RotatePattern90Degrees = 1;
    SqTextures t;
    render(&p, 100, &t);
    for (int y = 0; y < 100; y += 13) {
        /* rows of the unrotated pattern 20..39 become columns 60..79 */
        assert_true(sq_image_at(&t.basecolor, 70, y)[0] > 0.99f);
        assert_true(sq_image_at(&t.basecolor, 30, y)[0] < 0.01f);
    }
    sq_gen_textures_free(&t);
}

/* Blur softens the edges; full contrast makes them hard again. */
static void blur_and_contrast(void **state)
{
    (void)state;
    SqParams p = base(SQ_PATTERN_TRANSVERSAL);
    p.Transversal_Color[0][0] = 1;
    p.Transversal_BeginEnd[0][0] = 0.25;
    p.Transversal_BeginEnd[0][1] = 0.75;
    p.Pattern_BlurAmount = 8;
    SqTextures t;
    render(&p, 256, &t);
    float edge = sq_image_at(&t.basecolor, 0, 64)[0], inside = sq_image_at(&t.basecolor, 0, 128)[0];
    assert_true(edge > 0.3f && edge < 0.7f);
    assert_true(inside > 0.99f);
    assert_true(sq_image_at(&t.basecolor, 0, 60)[0] > 0.05f); /* soft */
    sq_gen_textures_free(&t);
    p.Pattern_Contrast = 1;
    render(&p, 256, &t);
    assert_true(sq_image_at(&t.basecolor, 0, 60)[0] < 0.01f); /* hard again */
    assert_true(sq_image_at(&t.basecolor, 0, 68)[0] > 0.99f);
    sq_gen_textures_free(&t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(transversal_bands_cover_their_rows),
        cmocka_unit_test(transversal_order_and_omission),
        cmocka_unit_test(transversal_band_wraps),
        cmocka_unit_test(longitudinal_n_stripes_n_runs),
        cmocka_unit_test(longitudinal_pinch_and_width),
        cmocka_unit_test(longitudinal_zigzag_follows_a_triangle_wave),
        cmocka_unit_test(transversal_zigzag_follows_a_triangle_wave),
        cmocka_unit_test(spot_count_matches_tiling),
        cmocka_unit_test(spot_shape_follows_interstice),
        cmocka_unit_test(ca_rows_follow_the_rules),
        cmocka_unit_test(ca_triangular_neighbourhoods),
        cmocka_unit_test(ca_image_mirrors_and_shifts),
        cmocka_unit_test(rotate_turns_rings_into_stripes),
        cmocka_unit_test(blur_and_contrast),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
