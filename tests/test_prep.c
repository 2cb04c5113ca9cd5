/* Photo preparation: straightening a synthetic photo recovers its truth; bad input is
 * refused with a message; real photos (../shared/photos) are prepared without crashing. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fitness_internal.h"
#include "sq_test.h"
#include "squama/fitness.h"
#include "squama/io.h"
#include "squama/preset.h"

static void synthetic_coil(SqImage *photo, SqImage *mask, SqPhotoTruth *t, unsigned seed, int w, int h,
                           SqBackdrop backdrop, double coil)
{
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_TRANSVERSAL; /* rings: straight across a well-made strip */
    p.Transversal_BeginEnd[0][0] = 0.0;
    p.Transversal_BeginEnd[0][1] = 0.5;
    SqPhotoOptions o = sq_fit_photo_options_default();
    o.width = w;
    o.height = h;
    o.seed = seed;
    o.coil = coil;
    o.texture_size = 128;
    o.backdrop = backdrop;
    SqError err;
    assert_int_equal(sq_fit_synth_photo(&p, &o, photo, mask, t, &err), SQ_OK);
}

static void synthetic(SqImage *photo, SqImage *mask, SqPhotoTruth *t, unsigned seed, int w, int h,
                      SqBackdrop backdrop)
{
    synthetic_coil(photo, mask, t, seed, w, h, backdrop, 0.3);
}

/* The largest distance from the prepared centre line to the truth's. */
static double worst_distance(const SqPrepared *prep, const SqPhotoTruth *t)
{
    double worst = 0;
    for (int i = 0; i < prep->npoints; i += 3) {
        double best = 1e9;
        for (int k = 0; k < t->npoints; k++)
            best = fmin(best, hypot(prep->centre[2 * i] - t->points[2 * k], prep->centre[2 * i + 1] - t->points[2 * k + 1]));
        worst = fmax(worst, best);
    }
    return worst;
}

/* The skeleton of a bar, a ring and a bar on the image's edge: one pixel wide, in one
 * 8-connected piece, inside the shape; the bar's straight down its middle, the ring's closed
 * (no ends), the edge bar's reaching the edge (the box's edge is kept, as OpenCV's ximgproc
 * keeps it). */
static int skeleton_facts(const uint8_t *mask, const uint8_t *skel, int w, int h, int *ends, int *left)
{
    int n = 0, first = -1;
    *ends = 0, *left = w;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const int i = y * w + x;
            if (!skel[i])
                continue;
            assert_int_equal(skel[i], 255);
            assert_true(mask[i]); /* inside the shape */
            if (x + 1 < w && y + 1 < h) /* one pixel wide: no 2x2 block */
                assert_false(skel[i + 1] && skel[i + w] && skel[i + w + 1]);
            int nb = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++)
                    nb += (dx || dy) && x + dx >= 0 && x + dx < w && y + dy >= 0 && y + dy < h &&
                          skel[(y + dy) * w + x + dx];
            *ends += nb == 1;
            *left = x < *left ? x : *left;
            n++, first = first < 0 ? i : first;
        }
    /* one piece: a flood from the first pixel reaches them all */
    int *stack = malloc(sizeof(int) * (size_t)w * h), top = 0, seen = 0;
    uint8_t *mark = calloc((size_t)w * h, 1);
    assert_non_null(stack), assert_non_null(mark);
    if (first >= 0)
        stack[top++] = first, mark[first] = 1;
    while (top) {
        const int i = stack[--top], x = i % w, y = i / w;
        seen++;
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                const int j = (y + dy) * w + x + dx;
                if ((dx || dy) && x + dx >= 0 && x + dx < w && y + dy >= 0 && y + dy < h && skel[j] && !mark[j])
                    mark[j] = 1, stack[top++] = j;
            }
    }
    assert_int_equal(seen, n);
    free(stack), free(mark);
    return n;
}

static void thinning_leaves_a_centre_line(void **state)
{
    (void)state;
    enum { W = 80, H = 60 };
    uint8_t mask[W * H], skel[W * H];
    int ends, left;
    memset(mask, 0, sizeof mask);
    assert_int_equal(sq__thin(mask, W, H, skel), 0);
    for (int i = 0; i < W * H; i++)
        assert_int_equal(skel[i], 0); /* nothing from nothing */

    for (int y = 20; y < 32; y++) /* a bar 60 long, 12 thick */
        for (int x = 10; x < 70; x++)
            mask[y * W + x] = 255;
    assert_int_equal(sq__thin(mask, W, H, skel), 0);
    const int bar = skeleton_facts(mask, skel, W, H, &ends, &left);
    assert_true(bar >= 40 && bar <= 70);
    assert_int_equal(ends, 2);
    int row = -1; /* straight, down the middle */
    for (int i = 0; i < W * H; i++)
        if (skel[i]) {
            assert_true(row < 0 || i / W == row);
            row = i / W;
        }
    assert_true(row == 25 || row == 26);

    memset(mask, 0, sizeof mask);
    for (int y = 0; y < H; y++) /* a ring, radii 12 to 20 */
        for (int x = 0; x < W; x++) {
            const double r = hypot(x - 40, y - 30);
            mask[y * W + x] = r >= 12 && r <= 20 ? 255 : 0;
        }
    assert_int_equal(sq__thin(mask, W, H, skel), 0);
    const int ring = skeleton_facts(mask, skel, W, H, &ends, &left);
    assert_true(ring > 2 * 3.14 * 14 && ring < 2 * 3.14 * 18 * 1.5);
    assert_int_equal(ends, 0);

    memset(mask, 0, sizeof mask);
    for (int y = 20; y < 32; y++) /* a bar from the image's left edge */
        for (int x = 0; x < 50; x++)
            mask[y * W + x] = 255;
    assert_int_equal(sq__thin(mask, W, H, skel), 0);
    skeleton_facts(mask, skel, W, H, &ends, &left);
    assert_int_equal(left, 0);
}

static void straightening_follows_the_body(void **state)
{
    (void)state;
    SqImage photo, mask;
    SqPhotoTruth t;
    synthetic(&photo, &mask, &t, 3, 640, 480, SQ_BACKDROP_RANDOM);
    SqPrepared prep;
    SqError err;
    assert_int_equal(sq_fit_prepare(&photo, &mask, NULL, &prep, &err), SQ_OK);
    assert_true(fabs(prep.body_width - 2 * t.body_radius) < 0.1 * 2 * t.body_radius);
    assert_true(prep.length > 4 * t.body_radius);
    assert_int_equal(prep.strip.width, SQ_FIT_STRIP_W);
    /* every point of the centre line lies near the truth's centre line, most of them
     * within a pixel or two (mid-way between the edges, not where the skeleton wanders) */
    double worst = 0;
    int near = 0, count = 0;
    for (int i = 0; i < prep.npoints; i += 5, count++) {
        double best = 1e9;
        for (int k = 0; k < t.npoints; k++)
            best = fmin(best, hypot(prep.centre[2 * i] - t.points[2 * k], prep.centre[2 * i + 1] - t.points[2 * k + 1]));
        worst = fmax(worst, best);
        near += best < 0.07 * t.body_radius;
    }
    if (worst > 0.25 * t.body_radius)
        fail_msg("centre line strays %.1f px from the truth (radius %.1f)", worst, t.body_radius);
    if (near < 0.9 * count)
        fail_msg("only %d of %d centre line points within %.1f px of the truth", near, count, 0.07 * t.body_radius);
    /* rings become rows: along a row, a ring edge is nearly flat */
    int valid = 0;
    for (int i = 0; i < prep.valid.width * prep.valid.height; i++)
        valid += prep.valid.px[i] > 0.5f;
    assert_true(valid > 0.9 * prep.valid.width * prep.valid.height);
    sq_fit_prepared_free(&prep);

    
    sq_image_free(&photo);
    sq_image_free(&mask);
    sq_fit_truth_free(&t);
}

/* A snake that crosses itself is straightened stretch by stretch: more than the longest
 * one where others are clean, and every stretch on the body, none cutting through a
 * crossing. */
static void coiled_body_in_stretches(void **state)
{
    (void)state;
    int several = 0, failed = 0;
    for (unsigned seed = 1; seed <= 12; seed++) {
        SqImage photo, mask;
        SqPhotoTruth t;
        synthetic_coil(&photo, &mask, &t, seed, 640, 480, SQ_BACKDROP_PLAIN, 0.8);
        SqPrepared prep;
        SqError err;
        if (sq_fit_prepare(&photo, &mask, NULL, &prep, &err) == SQ_OK) {
            assert_true(prep.nruns >= 1);
            if (prep.nruns > 1) {
                several++;
                double worst = worst_distance(&prep, &t);
                if (worst > 0.25 * t.body_radius)
                    fail_msg("seed %u: a stretch strays %.1f px from the body's centre line (radius %.1f)", seed,
                             worst, t.body_radius);
                /* the stretches are apart in the strip: some rows show no body at all */
                int empty = 0;
                for (int y = 0; y < prep.valid.height; y++) {
                    float any = 0;
                    for (int x = 0; x < prep.valid.width; x++)
                        any += *sq_image_at(&prep.valid, x, y);
                    empty += any == 0;
                }
                assert_true(empty >= 4 * (prep.nruns - 1)); /* a few rows between stretches */
            }
            sq_fit_prepared_free(&prep);
        } else {
            failed++;
            print_message("seed %u: %s\n", seed, err.what);
        }
        sq_image_free(&photo);
        sq_image_free(&mask);
        sq_fit_truth_free(&t);
    }
    print_message("%d of 12 coiled snakes straightened in several stretches, %d refused\n", several, failed);
    assert_true(several >= 2);
    assert_true(failed <= 1); /* the tightest coils may leave no body width clean */
}

/* The light comes from where squama photo puts it (the upper left, x -0.35, y -0.55 in the
 * photo), found from the shading as the body turns; the strip's light is that light in
 * the body's frame, at the key light's elevation. */
static void light_from_the_shading(void **state)
{
    (void)state;
    const double truth = atan2(-0.55, -0.35), deg = atan(1.0) / 45;
    for (unsigned seed = 1; seed <= 3; seed++) {
        SqImage photo, mask;
        SqPhotoTruth t;
        synthetic_coil(&photo, &mask, &t, seed, 640, 480, SQ_BACKDROP_RANDOM, 0.6);
        SqPrepared prep;
        SqError err;
        assert_int_equal(sq_fit_prepare(&photo, &mask, NULL, &prep, &err), SQ_OK);
        double a = atan2(prep.light_xy[1], prep.light_xy[0]), off = fabs(remainder(a - truth, 360 * deg));
        print_message("  seed %u: light (%.2f, %.2f), %.0f degrees off, %d rows\n", seed, prep.light_xy[0],
                      prep.light_xy[1], off / deg, prep.light.rows);
        assert_true(off < 20 * deg);
        assert_true(hypot(prep.light_xy[0], prep.light_xy[1]) > 0.4);
        assert_true(prep.light.rows > 0 && prep.light.rows <= SQ_FIT_LIGHT_ROWS);
        for (int i = 0; i < prep.light.rows; i++) {
            const float *d = prep.light.dir[i];
            assert_true(fabs(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1) < 1e-4);
            assert_true(d[2] > 0.7f && d[2] < 0.8f); /* the key's elevation: the full tilt found */
            /* the light turns as round a bend, where the strip's four pieces of the body
             * join too: at most 30 degrees from one light row to the next */
            if (i > 0) {
                const float *e = prep.light.dir[i - 1];
                double turn = fabs(remainder(atan2(d[1], d[0]) - atan2(e[1], e[0]), 360 * deg));
                if (turn > 30 * deg)
                    fail_msg("seed %u: the light turns %.0f degrees between rows %d and %d", seed, turn / deg,
                             i - 1, i);
            }
        }
        sq_fit_prepared_free(&prep);
        sq_fit_truth_free(&t);
        sq_image_free(&photo);
        sq_image_free(&mask);
    }
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* A body that bends turns its flank to the light row after row. A candidate's strip has
 * that turning divided out exactly (sq_fit_candidate_strip), and the photo's strip has it
 * divided out too, from its light at each row's heading: so on a plain skin (nothing
 * along the body but the scales) the photo's strip varies along the body about as much
 * as the truth's own candidate: over five coiled bodies 0.70 to 1.78 times (median 0.93;
 * without the division 1.06 to 2.38, median 2.16: a variation only a wrong candidate
 * could match). */
static void a_bends_light_is_divided_out(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Pattern_Type = SQ_PATTERN_NONE;
    p.Color_NoiseIntensity = 0;
    SqTextures maps;
    SqGenOptions go = sq_gen_options_default(256);
    SqError err;
    assert_int_equal(sq_gen_render(&p, &go, &maps, &err), SQ_OK);
    double ratios[5];
    for (unsigned seed = 1; seed <= 5; seed++) {
        SqPhotoOptions o = sq_fit_photo_options_default();
        o.width = 800;
        o.height = 600;
        o.seed = seed;
        o.coil = 0.6;
        o.body_radius = 30;
        o.view_scale = 0.7;
        o.backdrop = SQ_BACKDROP_PLAIN;
        SqImage photo, mask, strip;
        SqPhotoTruth t;
        SqPrepared prep;
        SqFeatures target, cand;
        assert_int_equal(sq_fit_synth_photo(&p, &o, &photo, &mask, &t, &err), SQ_OK);
        assert_int_equal(sq_fit_prepare(&photo, &mask, NULL, &prep, &err), SQ_OK);
        assert_int_equal(sq_fit_photo_target(&prep, &target, &err), SQ_OK);
        assert_true(prep.light.rows > 1); /* the light turns */
        assert_int_equal(sq_fit_candidate_strip(&maps.basecolor, &maps.normal, &maps.roughness, &prep.light,
                                                t.view_scale, t.band_centre, SQ_FIT_CANDIDATE_ROWS, &strip, &err),
                         SQ_OK);
        assert_int_equal(sq_fit_features_blurred(&strip, NULL, target.blur, &cand, &err), SQ_OK);
        const double ratio = target.along_power / cand.along_power;
        print_message("  seed %u: along the body, the photo's strip varies %.2f times as much as the truth's\n",
                      seed, ratio);
        ratios[seed - 1] = ratio;
        sq_image_free(&strip);
        sq_fit_prepared_free(&prep);
        sq_fit_truth_free(&t);
        sq_image_free(&photo);
        sq_image_free(&mask);
    }
    sq_gen_textures_free(&maps);
    qsort(ratios, 5, sizeof ratios[0], cmp_double);
    assert_true(ratios[2] > 0.7 && ratios[2] < 1.3); /* the median */
}

/* GrabCut finds the snake on bare soil. (In grass or leaf litter it often does not: the
 * automatic mask is a best effort, saved for the user to correct.) */
static void automatic_mask(void **state)
{
    (void)state;
    SqParams p;
    char path[1024];
    SqError err;
    assert_int_equal(sq_preset_load(src_path(path, sizeof path, "presets/thesis/table_4_2_micrurus_altirostris.json"),
                                    &p, NULL, &err),
                     SQ_OK);
    SqPhotoOptions o = sq_fit_photo_options_default();
    o.width = 480;
    o.height = 360;
    o.seed = 3;
    o.coil = 0.3;
    o.texture_size = 128;
    o.backdrop = SQ_BACKDROP_SOIL;
    SqImage photo, mask;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &photo, &mask, NULL, &err), SQ_OK);
    SqPrepared prep;
    if (sq_fit_prepare(&photo, NULL, NULL, &prep, &err) != SQ_OK)
        fail_msg("automatic mask: %s", err.what);
    assert_int_equal(prep.mask_source, SQ_MASK_AUTOMATIC);
    /* the automatic mask overlaps the true one */
    double inter = 0, uni = 0;
    for (int i = 0; i < 480 * 360; i++) {
        int a = mask.px[i] > 0.5f, b = prep.mask.px[i] > 0.5f;
        inter += a && b;
        uni += a || b;
    }
    print_message("automatic mask: intersection over union %.2f\n", inter / uni);
    assert_true(inter / uni > 0.6);
    /* the same photo, the same mask: what ran before on the thread (GrabCut draws from
     * OpenCV's per-thread generator) changes nothing */
    SqPrepared again;
    assert_int_equal(sq_fit_prepare(&photo, NULL, NULL, &again, &err), SQ_OK);
    assert_memory_equal(prep.mask.px, again.mask.px, sizeof(float) * 480 * 360);
    sq_fit_prepared_free(&again);
    sq_fit_prepared_free(&prep);
    sq_image_free(&photo);
    sq_image_free(&mask);
}

/* The truth's centre line as a body line: a point every 20 pixels. */
static void truth_line(const SqPhotoTruth *t, SqBodyLine *line)
{
    line->nstretches = 1;
    line->count = malloc(sizeof(int));
    line->xy = malloc(sizeof(float) * 2 * (size_t)t->npoints);
    assert_non_null(line->count);
    assert_non_null(line->xy);
    int n = 0;
    for (int k = 0; k < t->npoints; k += 5, n++) { /* the truth's points are 4 px apart */
        line->xy[2 * n] = t->points[2 * k];
        line->xy[2 * n + 1] = t->points[2 * k + 1];
    }
    line->count[0] = n;
    line->width = 2 * t->body_radius;
}

/* A body line is followed as drawn, at its width: no mask needed, the strip as long as the
 * line; a mask given with it says which of the strip is body. */
static void body_line_followed(void **state)
{
    (void)state;
    SqImage photo, mask;
    SqPhotoTruth t;
    synthetic(&photo, &mask, &t, 3, 640, 480, SQ_BACKDROP_RANDOM);
    SqBodyLine line;
    truth_line(&t, &line);
    SqPrepOptions o = sq_fit_prep_options_default();
    o.line = &line;
    SqPrepared prep, pm;
    SqError err;
    assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &prep, &err), SQ_OK);
    assert_int_equal(prep.mask_source, SQ_MASK_LINE);
    assert_string_equal(sq_mask_source_name(prep.mask_source), "line");
    assert_true(fabs(prep.body_width - 2 * t.body_radius) < 1e-6);
    assert_int_equal(prep.nruns, 1);
    double len = 0;
    for (int i = 1; i < line.count[0]; i++)
        len += hypot(line.xy[2 * i] - line.xy[2 * i - 2], line.xy[2 * i + 1] - line.xy[2 * i - 1]);
    if (!(prep.length > 0.9 * len && prep.length < 1.02 * len))
        fail_msg("%.0f px straightened along a line of %.0f px", prep.length, len);
    double worst = worst_distance(&prep, &t);
    if (worst > 0.1 * t.body_radius)
        fail_msg("the strip strays %.1f px from the line (radius %.1f)", worst, t.body_radius);
    /* a strip like the mask's own: the same rings (transversal) in the same colours */
    assert_int_equal(sq_fit_prepare(&photo, &mask, NULL, &pm, &err), SQ_OK);
    double a = 0, b = 0;
    for (int i = 0; i < prep.strip.width * prep.strip.height * 3; i++)
        a += prep.strip.px[i];
    for (int i = 0; i < pm.strip.width * pm.strip.height * 3; i++)
        b += pm.strip.px[i];
    a /= prep.strip.width * prep.strip.height * 3;
    b /= pm.strip.width * pm.strip.height * 3;
    if (fabs(a - b) > 0.05)
        fail_msg("mean of the line's strip %.3f, of the mask's %.3f", a, b);
    sq_fit_prepared_free(&pm);
    sq_fit_prepared_free(&prep);

    /* with a mask: body only where it says so too (the body beyond the middle of its
     * centre line left out: about half the strip invalid) */
    const double mid_x = t.points[2 * (t.npoints / 2)];
    const int rising = t.points[2 * (t.npoints - 1)] > t.points[0];
    SqImage half;
    assert_int_equal(sq_image_alloc(&half, 640, 480, 1, SQ_SPACE_DATA), 0);
    for (int y = 0; y < 480; y++)
        for (int x = 0; x < 640; x++)
            half.px[y * 640 + x] = (rising ? x < mid_x : x > mid_x) ? mask.px[y * 640 + x] : 0.0f;
    assert_int_equal(sq_fit_prepare(&photo, &half, &o, &prep, &err), SQ_OK);
    assert_int_equal(prep.mask_source, SQ_MASK_GIVEN);
    assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &pm, &err), SQ_OK);
    double va = 0, vb = 0;
    for (int i = 0; i < prep.valid.width * prep.valid.height; i++) {
        va += prep.valid.px[i];
        vb += pm.valid.px[i];
    }
    print_message("valid with the half mask %.0f, with the line alone %.0f\n", va, vb);
    assert_true(va < 0.75 * vb);
    sq_fit_prepared_free(&pm);
    sq_fit_prepared_free(&prep);
    sq_image_free(&half);

    /* the line a preparation followed, given back, is followed again */
    assert_int_equal(sq_fit_prepare(&photo, &mask, NULL, &pm, &err), SQ_OK);
    SqBodyLine again;
    assert_int_equal(sq_fit_prepared_line(&pm, &again, &err), SQ_OK);
    assert_int_equal(again.nstretches, pm.nruns);
    assert_true(fabs(again.width - pm.body_width) < 1e-6);
    o.line = &again;
    assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &prep, &err), SQ_OK);
    if (fabs(prep.length - pm.length) > 0.05 * pm.length)
        fail_msg("%.0f px straightened again, %.0f the first time", prep.length, pm.length);
    assert_true(worst_distance(&prep, &t) < 0.25 * t.body_radius);
    sq_fit_prepared_free(&prep);
    sq_fit_prepared_free(&pm);

    /* refused, with where: outside the photo, too thin, too short */
    line.xy[2] = 700;
    o.line = &line;
    assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.where, "body line");
    assert_contains(err.what, "stretches[0][1] (700.0,");
    assert_contains(err.what, "outside the 640x480 photo");
    assert_null(prep.strip.px);
    line.xy[2] = line.xy[0] + 1;
    line.width = 4;
    assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "too thin");
    line.width = 500;
    assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "the body is 500 pixels wide, wider than the 640x480 photo");
    line.width = 2 * t.body_radius;
    const int n0 = line.count[0];
    line.count[0] = 2;
    assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "too short to straighten");
    assert_null(prep.strip.px);
    /* a line that winds up: corner to corner and back, far longer than any body here */
    line.count[0] = n0;
    for (int i = 0; i < n0; i++) {
        line.xy[2 * i] = i % 2 ? 639 : 0;
        line.xy[2 * i + 1] = i % 2 ? 479 : 0;
    }
    assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "more than 16 times the photo's longest side");
    /* a mask that misses the line */
    SqBodyLine fresh;
    truth_line(&t, &fresh);
    SqImage away; /* a square in the corner farthest from the body */
    assert_int_equal(sq_image_alloc(&away, 640, 480, 1, SQ_SPACE_DATA), 0);
    int far = 0;
    double farthest = 0;
    for (int c = 0; c < 4; c++) {
        double near = 1e9;
        for (int k = 0; k < t.npoints; k++)
            near = fmin(near, hypot(t.points[2 * k] - (c & 1) * 640, t.points[2 * k + 1] - (c >> 1) * 480));
        if (near > farthest) {
            farthest = near;
            far = c;
        }
    }
    for (int y = 0; y < 60; y++)
        for (int x = 0; x < 60; x++)
            away.px[((far >> 1) ? 479 - y : y) * 640 + ((far & 1) ? 639 - x : x)] = 1;
    o.line = &fresh;
    assert_int_equal(sq_fit_prepare(&photo, &away, &o, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "of the body line's band (10% at least)");
    sq_image_free(&away);
    sq_body_line_free(&fresh);
    sq_body_line_free(&again);
    sq_body_line_free(&line);
    sq_image_free(&photo);
    sq_image_free(&mask);
    sq_fit_truth_free(&t);
}

static void replay_line(const char *path, void *ctx)
{
    SqBodyLine line;
    SqError err;
    if (sq_body_line_read(path, &line, &err) == SQ_OK) {
        assert_true(line.nstretches >= 1 && line.count[0] >= 2 && line.width >= 1);
        sq_body_line_free(&line);
        ++*(int *)ctx;
    } else {
        assert_true(err.what[0] && err.where[0]);
        assert_null(line.xy);
    }
}

/* A line drawn wider than the body (by 60%) takes in the ground beside it; the band's body
 * is found by colour, and the mask is the body's, not the band's. */
static void body_line_band_found_by_colour(void **state)
{
    (void)state;
    for (unsigned seed = 3; seed <= 4; seed++) {
        SqImage photo, mask;
        SqPhotoTruth t;
        synthetic(&photo, &mask, &t, seed, 640, 480, SQ_BACKDROP_RANDOM);
        SqBodyLine line;
        truth_line(&t, &line);
        line.width = 1.6 * 2 * t.body_radius;
        SqPrepOptions o = sq_fit_prep_options_default();
        o.line = &line;
        SqPrepared prep;
        SqError err;
        assert_int_equal(sq_fit_prepare(&photo, NULL, &o, &prep, &err), SQ_OK);
        assert_true(prep.scale == 1.0);
        double masked = 0, ground = 0, body = 0, band = 0;
        for (int i = 0; i < 640 * 480; i++) {
            masked += prep.mask.px[i] > 0.5f;
            ground += prep.mask.px[i] > 0.5f && mask.px[i] < 0.5f;
        }
        /* the true body within the band: every body pixel near the truth's centre line */
        for (int y = 0; y < 480; y++)
            for (int x = 0; x < 640; x++) {
                if (mask.px[y * 640 + x] < 0.5f)
                    continue;
                double near = 1e9;
                for (int k = 0; k < t.npoints; k++)
                    near = fmin(near, hypot(x - t.points[2 * k], y - t.points[2 * k + 1]));
                if (near < 0.8 * t.body_radius) {
                    band++;
                    body += prep.mask.px[y * 640 + x] > 0.5f;
                }
            }
        print_message("seed %u: %.1f%% of the mask is ground, %.1f%% of the body's middle kept\n", seed,
                      100 * ground / masked, 100 * body / band);
        if (ground > 0.15 * masked)
            fail_msg("seed %u: %.0f%% of the mask is ground", seed, 100 * ground / masked);
        if (body < 0.95 * band)
            fail_msg("seed %u: %.0f%% of the body's middle kept", seed, 100 * body / band);
        sq_fit_prepared_free(&prep);
        sq_body_line_free(&line);
        sq_image_free(&photo);
        sq_image_free(&mask);
        sq_fit_truth_free(&t);
    }
}

/* The body line's JSON: read back as written; bad files refused naming the place. */
static void body_line_files(void **state)
{
    (void)state;
    SqBodyLine line, back;
    SqError err;
    const char *good = "{\"format\": \"squama-body-line/1\", \"width\": 58,\n"
                       " \"stretches\": [[[120, 400], [180, 352.25], [260, 330]], [[500, 210], [610, 190]]]}";
    assert_int_equal(sq_body_line_parse(good, strlen(good), "l.json", &line, &err), SQ_OK);
    assert_int_equal(line.nstretches, 2);
    assert_int_equal(line.count[0], 3);
    assert_int_equal(line.count[1], 2);
    assert_true(line.width == 58);
    assert_true(line.xy[3] == 352.25f && line.xy[8] == 610);
    char path[] = "/tmp/sq_line_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    assert_int_equal(sq_body_line_write(path, &line, &err), SQ_OK);
    assert_int_equal(sq_body_line_read(path, &back, &err), SQ_OK);
    assert_int_equal(back.nstretches, 2);
    for (int i = 0; i < 5; i++) /* to a tenth of a pixel */
        assert_true(fabsf(back.xy[2 * i] - line.xy[2 * i]) <= 0.05f && fabsf(back.xy[2 * i + 1] - line.xy[2 * i + 1]) <= 0.05f);
    sq_body_line_free(&back);
    sq_body_line_free(&line);
    unlink(path);
    assert_int_equal(sq_body_line_read(path, &back, &err), SQ_ERR_IO);

    static const struct { const char *text, *where, *what; } bad[] = {
        {"[1, 2]", "l.json", "must be a JSON object"},
        {"{\"width\": 5, \"stretches\": [[[0, 0], [1, 1]]]}", "l.json", "\"format\" must be"},
        {"{\"format\": \"squama-preset/1\"}", "l.json", "\"format\" must be"},
        {"{\"format\": \"squama-body-line/1\", \"stretches\": [[[0, 0], [1, 1]]]}", "l.json: width", "width"},
        {"{\"format\": \"squama-body-line/1\", \"width\": -3, \"stretches\": [[[0, 0], [1, 1]]]}", "l.json: width",
         "from 1 to"},
        {"{\"format\": \"squama-body-line/1\", \"width\": 9, \"stretches\": []}", "l.json: stretches", "1 to 16"},
        {"{\"format\": \"squama-body-line/1\", \"width\": 9, \"stretches\": [[[0, 0]]]}", "l.json: stretches[0]",
         "2 points at least"},
        {"{\"format\": \"squama-body-line/1\", \"width\": 9, \"stretches\": [[[0, 0], [1, 1]], [[0, 0], [1]]]}",
         "l.json: stretches[1][1]", "[x, y]"},
        {"{\"format\": \"squama-body-line/1\", \"width\": 9, \"stretches\": [[[0, 0], [1, \"a\"]]]}",
         "l.json: stretches[0][1]", "[x, y]"},
        {"{\"format\": \"squama-body-line/1\", \"width\": 9, \"stretches\": [[[0, 0], [1, 1]]], \"colour\": 1}",
         "l.json: colour", "unknown key"},
        {"{\"format\": \"squama-body-line/1\", \"width\": 9, \"width\": 9, \"stretches\": [[[0, 0], [1, 1]]]}",
         "l.json: width", "twice"},
        {"{\"format\": \"squama-body-line/1\",\n \"width\": 9,\n \"stretches\": [[[0, 0], [1, 1]]}", "l.json:3:32",
         "malformed JSON: expected a ',' or a ']'"},
        {"{\"format\": \"squama-body-line/1\", \"width\": 9, \"stretches\": [[[0, 0], [1, 1]]]} [2]",
         "l.json:1:79", "unexpected text after the JSON value"},
        {"{\"format\": \"squama-body-line/1\", \"width\": 09, \"stretches\": [[[0, 0], [1, 1]]]}",
         "l.json:1:43", "a number with a leading zero"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        line.nstretches = 7;
        if (sq_body_line_parse(bad[i].text, strlen(bad[i].text), "l.json", &line, &err) == SQ_OK)
            fail_msg("accepted: %s", bad[i].text);
        assert_int_equal(line.nstretches, 0); /* nothing held */
        assert_null(line.xy);
        assert_contains(err.where, bad[i].where);
        assert_contains(err.what, bad[i].what);
    }
    assert_int_equal(sq_body_line_parse("{\"a\"\0}", 6, "l.json", &line, &err), SQ_ERR_PARSE);

    /* the fuzz harness' regressions: read, or refused with a reason */
    char dir[1024];
    int read = 0;
    if (for_each_file(src_path(dir, sizeof dir, "tests/fuzz/regressions/line"), "", 0, replay_line, &read) < 3)
        fail_msg("tests/fuzz/regressions/line: the hand-written inputs are missing");
    assert_int_equal(read, 1); /* two-stretches.json */
}

static void bad_input_refused(void **state)
{
    (void)state;
    SqImage photo, mask, m2;
    SqPhotoTruth t;
    SqPrepared prep;
    SqError err;
    synthetic(&photo, &mask, &t, 7, 320, 240, SQ_BACKDROP_RANDOM);
    /* an empty mask */
    sq_image_alloc(&m2, 320, 240, 1, SQ_SPACE_DATA);
    assert_int_equal(sq_fit_prepare(&photo, &m2, NULL, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "the given mask covers 0.00% of the photo: no snake to see");
    assert_null(prep.strip.px);
    /* a mask of everything */
    for (int i = 0; i < 320 * 240; i++)
        m2.px[i] = 1;
    assert_int_equal(sq_fit_prepare(&photo, &m2, NULL, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "covers 100% of the photo");
    sq_image_free(&m2);
    /* a mask of another size */
    sq_image_alloc(&m2, 100, 100, 1, SQ_SPACE_DATA);
    assert_int_equal(sq_fit_prepare(&photo, &m2, NULL, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "the mask is 100x100 but the photo is 320x240");
    sq_image_free(&m2);
    /* scattered blobs, enough of the photo together (0.55%) but not the one body that is
     * kept of them (0.15%, under the 0.2% a mask must cover): the floor holds for what is
     * fitted, so a fit never straightens a mask that it would refuse back from mask.png */
    sq_image_alloc(&m2, 320, 240, 1, SQ_SPACE_DATA);
    for (int y = 0; y < 240; y++)
        for (int x = 0; x < 320; x++)
            for (int k = 0; k < 4; k++)
                m2.px[y * 320 + x] += hypot(x - 40 - 80 * k, y - (k % 2 ? 60 : 180)) < (k ? 5.5 : 6.5);
    assert_int_equal(sq_fit_prepare(&photo, &m2, NULL, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "the body found in the mask covers 0.1");
    assert_contains(err.what, "(0.2% at least): no snake to see");
    assert_null(prep.strip.px);
    sq_image_free(&m2);
    /* a blob, not a snake: too short to straighten */
    sq_image_alloc(&m2, 320, 240, 1, SQ_SPACE_DATA);
    for (int y = 0; y < 240; y++)
        for (int x = 0; x < 320; x++)
            m2.px[y * 320 + x] = hypot(x - 160, y - 120) < 50;
    assert_int_equal(sq_fit_prepare(&photo, &m2, NULL, &prep, &err), SQ_ERR_INVALID);
    print_message("a disc as the mask: %s\n", err.what);
    sq_image_free(&m2);
    /* a tiny photo */
    SqImage tiny;
    sq_image_alloc(&tiny, 40, 30, 3, SQ_SPACE_SRGB);
    assert_int_equal(sq_fit_prepare(&tiny, NULL, NULL, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "too small");
    sq_image_free(&tiny);
    /* a photo with no snake: whatever GrabCut finds in plain noise is refused or straightened,
     * never a crash */
    SqImage noise;
    sq_image_alloc(&noise, 200, 150, 3, SQ_SPACE_SRGB);
    for (int i = 0; i < 200 * 150 * 3; i++)
        noise.px[i] = (float)((i * 7919) % 101) / 100.0f;
    SqStatus st = sq_fit_prepare(&noise, NULL, NULL, &prep, &err);
    print_message("a photo of noise: %s\n", st == SQ_OK ? "straightened something" : err.what);
    sq_fit_prepared_free(&prep);
    /* a plain photo, a little grain on it: nothing found, and the two ways to say where the
     * snake is named */
    for (int i = 0; i < 200 * 150 * 3; i++)
        noise.px[i] = 0.45f + 0.012f * (float)((int)(((unsigned)(i / 3) * 2654435761u) >> 13) % 3 - 1);
    assert_int_equal(sq_fit_prepare(&noise, NULL, NULL, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "automatic mask: give a body line with --line, or draw a mask and pass it with --mask");
    /* one flat colour: refused before GrabCut, whose graph cut takes minutes on it */
    for (int i = 0; i < 200 * 150 * 3; i++)
        noise.px[i] = 0.45f;
    assert_int_equal(sq_fit_prepare(&noise, NULL, NULL, &prep, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "the photo is one flat colour (its spread 0.00 levels of 255): no snake to find");
    sq_image_free(&noise);
    sq_image_free(&photo);
    sq_image_free(&mask);
    sq_fit_truth_free(&t);
}

/* A large photo is prepared at the working size; lengths come back in its pixels. */
static void large_photo(void **state)
{
    (void)state;
    SqImage photo, mask;
    SqPhotoTruth t;
    synthetic(&photo, &mask, &t, 3, 1600, 1200, SQ_BACKDROP_RANDOM);
    SqPrepared prep;
    SqError err;
    SqPrepOptions o = sq_fit_prep_options_default();
    assert_int_equal(sq_fit_prepare(&photo, &mask, &o, &prep, &err), SQ_OK);
    assert_true(prep.photo.width == 1024);
    assert_true(fabs(prep.body_width - 2 * t.body_radius) < 0.1 * 2 * t.body_radius);
    sq_fit_prepared_free(&prep);
    sq_image_free(&photo);
    sq_image_free(&mask);
    sq_fit_truth_free(&t);
}

/* A big snake: a strip pixel spans about five photo pixels, and is their mean (in linear
 * light), as a candidate's strip pixel is of its texels. Point samples of a one-pixel
 * checkerboard would be anything from black to white (sd 0.18); the means are its
 * mid grey. */
static void big_body_is_area_sampled(void **state)
{
    (void)state;
    const int w = 1024, h = 480, y0 = 90, y1 = 390;
    SqImage photo, mask;
    assert_int_equal(sq_image_alloc(&photo, w, h, 3, SQ_SPACE_SRGB), 0);
    assert_int_equal(sq_image_alloc(&mask, w, h, 1, SQ_SPACE_DATA), 0);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const int body = y >= y0 && y < y1;
            float *p = sq_image_at(&photo, x, y);
            p[0] = p[1] = p[2] = body ? (float)((x + y) & 1) : 0.3f;
            *sq_image_at(&mask, x, y) = (float)body;
        }
    SqPrepared prep;
    SqError err;
    assert_int_equal(sq_fit_prepare(&photo, &mask, NULL, &prep, &err), SQ_OK);
    assert_true(prep.step > 4 && prep.step < 6);
    assert_true(sq_fit_strip_blur(prep.step, prep.edge_blur) == 0); /* as sharp as a candidate's */
    double s = 0, ss = 0;
    int n = 0;
    for (int y = 0; y < prep.strip.height; y++)
        for (int x = 0; x < SQ_FIT_STRIP_W; x++)
            if (*sq_image_at(&prep.valid, x, y) > 0.5f) {
                const double v = sq_image_at(&prep.strip, x, y)[1];
                s += v;
                ss += v * v;
                n++;
            }
    assert_true(n > SQ_FIT_STRIP_W * 16);
    const double mean = s / n, sd = sqrt(fmax(0, ss / n - mean * mean));
    print_message("big body: step %.2f, strip mean %.3f, sd %.3f over %d pixels\n", prep.step, mean, sd, n);
    /* mid grey: between the samples' sRGB mean (0.5: bilinear samples are sRGB) and the
     * checkerboard's mean in linear light (0.735) */
    assert_true(mean > 0.45 && mean < 0.76);
    assert_true(sd < 0.05);
    sq_fit_prepared_free(&prep);
    sq_image_free(&photo);
    sq_image_free(&mask);
}

/* A default preset's synthetic photo (640 x 480, soil) with body radius r (0: the photo's
 * choice) and camera blur, prepared: its strip step, measured blur and target blur. */
static void blur_of(double r, double blur, unsigned seed, double *step, double *edge, double *target_blur)
{
    SqParams p;
    sq_params_default(&p);
    SqPhotoOptions o = sq_fit_photo_options_default();
    o.width = 640;
    o.height = 480;
    o.seed = seed;
    o.texture_size = 128;
    o.backdrop = SQ_BACKDROP_SOIL;
    o.body_radius = r;
    o.blur = blur;
    SqImage photo, mask;
    SqPhotoTruth t;
    SqError err;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &photo, &mask, &t, &err), SQ_OK);
    SqPrepared prep;
    SqFeatures target;
    assert_int_equal(sq_fit_prepare(&photo, &mask, NULL, &prep, &err), SQ_OK);
    assert_int_equal(sq_fit_photo_target(&prep, &target, &err), SQ_OK);
    assert_true(fabs(target.blur - sq_fit_strip_blur(prep.step, prep.edge_blur)) < 1e-6);
    *step = prep.step;
    *edge = prep.edge_blur;
    *target_blur = target.blur;
    print_message("radius %.0f, camera blur %.1f: step %.2f, measured blur %.2f px, target blur %.2f\n", r, blur,
                  *step, *edge, *target_blur);
    sq_fit_prepared_free(&prep);
    sq_image_free(&photo);
    sq_image_free(&mask);
    sq_fit_truth_free(&t);
}

/* A small snake's strip is upsampled from its few pixels: its target says how much blurrier
 * than a candidate's it is, and a big snake's is not. */
static void small_body_target_is_blurred(void **state)
{
    (void)state;
    assert_true(sq_fit_strip_blur(0.5, 0) > sq_fit_strip_blur(0.8, 0));
    assert_true(sq_fit_strip_blur(0.8, 0) > sq_fit_strip_blur(1.0, 0));
    assert_true(fabs(sq_fit_strip_blur(0.5, 0) - sqrt(1.0 - 1.0 / 12)) < 1e-9);
    assert_true(sq_fit_strip_blur(2.0, 0) == 0 && sq_fit_strip_blur(0, 0) == 0);
    assert_true(sq_fit_strip_blur(0.01, 0) == SQ_FIT_BLUR_MAX);
    double step, edge, target_blur;
    blur_of(12, 0, 5, &step, &edge, &target_blur); /* a strip pixel: 0.4 photo pixels */
    assert_true(step > 0.3 && step < 0.5);
    assert_true(target_blur > 1);
}

/* The photo's own blur, measured across the body's outline, follows the camera blur
 * `squama photo` applies (its sharp photos: about 0.5 pixel, the pixels' box and the
 * sampling between them), and the target's blur with it. */
static void photo_blur_from_the_outline(void **state)
{
    (void)state;
    static const double blur[3] = {0, 1.0, 2.0};
    double step, edge[3], target_blur[3];
    for (int k = 0; k < 3; k++)
        blur_of(0, blur[k], 4, &step, &edge[k], &target_blur[k]);
    assert_true(edge[0] > 0.3 && edge[0] < 0.8);
    for (int k = 1; k < 3; k++) {
        const double expect = sqrt(blur[k] * blur[k] + edge[0] * edge[0]);
        assert_true(fabs(edge[k] - expect) < 0.35 * expect);
        assert_true(edge[k] > edge[k - 1] && target_blur[k] > target_blur[k - 1]);
    }
    assert_true(sq_fit_strip_blur(1, 2) > sq_fit_strip_blur(1, 1) && sq_fit_strip_blur(1, 1) > sq_fit_strip_blur(1, 0));
}

/* ../shared/photos/<name> read into *photo; 0 when it is not here. */
static int shared_photo(const char *name, SqImage *photo)
{
    char path[2048];
    SqError err;
    snprintf(path, sizeof path, "%s/photos/%s", SQUAMA_SHARED_DIR, name);
    if (access(path, R_OK) != 0)
        return 0;
    assert_int_equal(sq_io_read_image(path, NULL, photo, NULL, &err), SQ_OK);
    return 1;
}

/* Real photos, where they are here: each straightened or refused with a reason. Two of
 * them had their automatic mask take the ground within a loop of the body for body
 * (GrabCut's rectangle holds far more ground than snake; the centre line then crossed the
 * loop): a coral snake loosely looped on dry soil, before 1.7 body widths of strip, and a
 * banded krait whose dark rings go with the dark litter, before refused. They must give
 * more than 3 body widths of clean body. */
static void real_photos(void **state)
{
    (void)state;
    static const struct {
        const char *name;
        int work_size, loop; /* loop: must give 3 body widths */
        const char *refused; /* the automatic mask must fail, saying this */
    } photos[] = {
        {"micrurus_frontalis__br0353.jpg", 512, 0, NULL},
        {"philodryas_olfersii__br0067.jpg", 512, 0, NULL},
        {"micrurus_ibiboboca__ccj0207.jpg", 1024, 1, NULL},
        {"bungarus_fasciatus__th0079.jpg", 1024, 1, NULL},
        /* a jararaca the colour of the ground: GrabCut finds nothing but a red stick in a
         * corner, 0.16% of the photo once cleaned, which was once straightened and fitted */
        {"bothrops_jararaca__br0181.jpg", 1024, 0, "the body found in the mask covers 0.16% of the photo"},
    };
    int tried = 0;
    for (size_t i = 0; i < sizeof photos / sizeof photos[0]; i++) {
        SqImage photo;
        SqPrepared prep;
        SqError err;
        if (!shared_photo(photos[i].name, &photo))
            continue;
        SqPrepOptions o = sq_fit_prep_options_default();
        o.work_size = photos[i].work_size;
        SqStatus st = sq_fit_prepare(&photo, NULL, &o, &prep, &err);
        tried++;
        if (photos[i].refused) {
            if (st == SQ_OK)
                fail_msg("%s: straightened, where the automatic mask finds no snake", photos[i].name);
            assert_contains(err.what, photos[i].refused);
            assert_contains(err.what, "give a body line with --line");
        } else if (st == SQ_OK) {
            assert_int_equal(prep.strip.width, SQ_FIT_STRIP_W);
            assert_true(prep.body_width > 4);
            const double widths = prep.length / prep.body_width;
            print_message("%s: body %.0f px wide, %.1f body widths straightened\n", photos[i].name, prep.body_width,
                          widths);
            if (photos[i].loop && widths < 3)
                fail_msg("%s: %.1f body widths straightened", photos[i].name, widths);
        } else {
            assert_true(err.what[0] != '\0');
            print_message("%s: %s\n", photos[i].name, err.what);
            if (photos[i].loop)
                fail_msg("%s: %s", photos[i].name, err.what);
        }
        sq_fit_prepared_free(&prep);
        sq_image_free(&photo);
    }
    if (!tried)
        skip();
}

/* The body lines drawn for real photos (refs/photo_lines/<id>.json, <id> the photo's file
 * name): each reads, and where the photo is here, is followed along its whole length,
 * every point within the photo. The sanitized build follows about a quarter of them (those
 * whose name's bytes sum to a multiple of 4), the same code on other photos: all 43 cost
 * it a minute. */
static void photo_line(const char *path, void *ctx)
{
    SqBodyLine line;
    SqError err;
    if (sq_body_line_read(path, &line, &err) != SQ_OK)
        fail_msg("%s (%s)", err.what, err.where);
    const char *base = strrchr(path, '/') + 1;
    unsigned sum = 0;
    for (const char *c = base; *c; c++)
        sum += (unsigned char)*c;
    char photo_path[2048];
    snprintf(photo_path, sizeof photo_path, "%s/photos/%.*s.jpg", SQUAMA_SHARED_DIR, (int)(strlen(base) - 5), base);
    SqImage photo;
    if ((!sq_sanitized || sum % 4 == 0) && access(photo_path, R_OK) == 0 &&
        sq_io_read_image(photo_path, NULL, &photo, NULL, &err) == SQ_OK) {
        SqPrepOptions o = sq_fit_prep_options_default();
        o.line = &line;
        o.work_size = 512; /* the length followed is the same as at 1024, in a third of the time */
        SqPrepared prep;
        if (sq_fit_prepare(&photo, NULL, &o, &prep, &err) != SQ_OK)
            fail_msg("%s: %s (%s)", base, err.what, err.where);
        double len = 0;
        for (int k = 0, j = 0; k < line.nstretches; j += line.count[k++])
            for (int i = 1; i < line.count[k]; i++)
                len += hypot(line.xy[2 * (j + i)] - line.xy[2 * (j + i - 1)], line.xy[2 * (j + i) + 1] - line.xy[2 * (j + i - 1) + 1]);
        if (!(prep.length > 0.95 * len))
            fail_msg("%s: %.0f px straightened along a line of %.0f", base, prep.length, len);
        ++*(int *)ctx;
        sq_fit_prepared_free(&prep);
        sq_image_free(&photo);
    }
    sq_body_line_free(&line);
}

static void photo_lines(void **state)
{
    (void)state;
    char dir[1024];
    int followed = 0;
    if (for_each_file(src_path(dir, sizeof dir, "refs/photo_lines"), ".json", 0, photo_line, &followed) < 1)
        fail_msg("refs/photo_lines holds no body line");
    print_message("%d photo lines followed on their photos\n", followed);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(thinning_leaves_a_centre_line),
        cmocka_unit_test(straightening_follows_the_body),
        cmocka_unit_test(coiled_body_in_stretches),
        cmocka_unit_test(light_from_the_shading),
        cmocka_unit_test(a_bends_light_is_divided_out),
        cmocka_unit_test(automatic_mask),
        cmocka_unit_test(bad_input_refused),
        cmocka_unit_test(body_line_followed),
        cmocka_unit_test(body_line_band_found_by_colour),
        cmocka_unit_test(body_line_files),
        cmocka_unit_test(photo_lines),
        cmocka_unit_test(large_photo),
        cmocka_unit_test(big_body_is_area_sampled),
        cmocka_unit_test(small_body_target_is_blurred),
        cmocka_unit_test(photo_blur_from_the_outline),
        cmocka_unit_test(real_photos),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
