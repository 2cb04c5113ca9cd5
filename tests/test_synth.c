/* Synthetic photos: deterministic, the mask is where the body is, the body shows the
 * preset's colours, the truth describes what was drawn. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "sq_test.h"
#include "squama/fitness.h"

static void photo_of_a_plain_red_snake(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Background_Color[0] = 0.8;
    p.Background_Color[1] = 0.1;
    p.Background_Color[2] = 0.1;
    SqPhotoOptions o = sq_fit_photo_options_default();
    o.width = 400;
    o.height = 300;
    o.seed = 7;
    o.body_radius = 14;
    o.view_scale = 1;
    o.backdrop = SQ_BACKDROP_GRASS;
    o.texture_size = 128;
    SqImage photo, mask;
    SqPhotoTruth t;
    SqError err;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &photo, &mask, &t, &err), SQ_OK);
    assert_int_equal(photo.width, 400);
    assert_int_equal(mask.channels, 1);
    assert_true(t.body_radius == 14 && t.view_scale == 1);
    assert_true(t.npoints > 10 && t.length > 200);
    /* the mask covers about the body's length times its width (less the tapered tail and
     * where the body crosses itself or leaves the frame) */
    double area = 0, red_on = 0, red_off = 0, n_off = 0;
    for (int i = 0; i < 400 * 300; i++) {
        const float *px = photo.px + 3 * i;
        float redness = px[0] - 0.5f * (px[1] + px[2]);
        if (mask.px[i] > 0.5f) {
            area++;
            red_on += redness;
        } else {
            red_off += redness;
            n_off++;
        }
    }
    double expect = t.length * 2 * t.body_radius;
    if (area < 0.45 * expect || area > 1.05 * expect)
        fail_msg("mask area %.0f, body %.0f", area, expect);
    assert_true(red_on / area > 0.25);    /* the body is red */
    assert_true(red_off / n_off < 0.05);  /* the grass is not */
    /* the truth's centre line runs over the mask */
    int on = 0, inside = 0;
    for (int k = 0; k < t.npoints; k++) {
        int x = (int)t.points[2 * k], y = (int)t.points[2 * k + 1];
        if (x >= 0 && y >= 0 && x < 400 && y < 300) {
            inside++;
            on += mask.px[y * 400 + x] > 0.5f;
        }
    }
    if (on < 0.9 * inside)
        fail_msg("%d of %d centre-line points on the mask", on, inside);

    /* the same seed, the same photo, on one thread as on two */
    SqImage photo2, mask2;
    const int threads = omp_get_max_threads();
    omp_set_num_threads(threads > 1 ? 1 : 2);
    assert_int_equal(sq_fit_synth_photo(&p, &o, &photo2, &mask2, NULL, &err), SQ_OK);
    omp_set_num_threads(threads);
    assert_memory_equal(photo.px, photo2.px, sizeof(float) * 400 * 300 * 3);
    assert_memory_equal(mask.px, mask2.px, sizeof(float) * 400 * 300);
    sq_image_free(&photo2);
    sq_image_free(&mask2);
    o.seed = 8;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &photo2, &mask2, NULL, &err), SQ_OK);
    double diff = 0;
    for (int i = 0; i < 400 * 300; i++)
        diff += fabsf(mask.px[i] - mask2.px[i]);
    assert_true(diff > 1000); /* another curve */
    sq_image_free(&photo2);
    sq_image_free(&mask2);
    sq_image_free(&photo);
    sq_image_free(&mask);
    sq_fit_truth_free(&t);
}

static void degradations_change_the_photo(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    SqPhotoOptions o = sq_fit_photo_options_default();
    o.width = 200;
    o.height = 150;
    o.texture_size = 64;
    SqImage a, b, m;
    SqError err;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &a, &m, NULL, &err), SQ_OK);
    sq_image_free(&m);
    o.noise = 0.05;
    o.blur = 2;
    o.cast = 0.5;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &b, &m, NULL, &err), SQ_OK);
    double d = 0;
    for (int i = 0; i < 200 * 150 * 3; i++)
        d += fabsf(a.px[i] - b.px[i]);
    assert_true(d / (200 * 150 * 3) > 0.02);
    sq_image_free(&a);
    sq_image_free(&b);
    sq_image_free(&m);
}

/* The mean absolute difference (sRGB) of two photos over the pixels wholly inside the
 * body of mask m (the outline's pixels mix in the backdrop by coverage). */
static double body_difference(const SqImage *a, const SqImage *b, const SqImage *m, long *n)
{
    double d = 0;
    *n = 0;
    for (int y = 1; y < m->height - 1; y++)
        for (int x = 1; x < m->width - 1; x++) {
            int inside = 1;
            for (int j = -1; j <= 1; j++)
                for (int i = -1; i <= 1; i++)
                    inside &= m->px[(y + j) * m->width + x + i] > 0.5f;
            if (!inside)
                continue;
            for (int k = 0; k < 3; k++)
                d += fabsf(a->px[3 * (y * m->width + x) + k] - b->px[3 * (y * m->width + x) + k]);
            ++*n;
        }
    return *n ? d / (3.0 * *n) : 0;
}

/* A photo's pixel is the mean of the skin it covers, as a camera's is: on a fine scale
 * grid seen small (15 x 52 scales, a scale about 2.5 pixels along the body), the photo
 * at its default 4 x 4 points a pixel is close to the same photo at 16 x 16, and one
 * point a pixel (how photos were made before) is not: it aliases the scales' relief
 * into a crisp shimmer. */
static void pixels_are_the_mean_of_the_skin(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    p.Scales_XAmount = 15;
    p.Scales_YAmount = 52;
    SqPhotoOptions o = sq_fit_photo_options_default();
    o.width = 320;
    o.height = 240;
    o.seed = 8;
    o.body_radius = 12;
    o.view_scale = 0.66;
    o.backdrop = SQ_BACKDROP_PLAIN;
    SqImage photo[3], mask[3];
    const int samples[3] = {16, 4, 1};
    SqError err;
    for (int k = 0; k < 3; k++) {
        o.samples = samples[k];
        assert_int_equal(sq_fit_synth_photo(&p, &o, &photo[k], &mask[k], NULL, &err), SQ_OK);
    }
    long n;
    const double d4 = body_difference(&photo[1], &photo[0], &mask[0], &n);
    const double d1 = body_difference(&photo[2], &photo[0], &mask[0], &n);
    print_message("  %ld pixels inside the body, off the mean of 16 x 16 points: %.4f at 4 x 4, %.4f at one\n", n,
                  d4, d1);
    assert_true(n > 1000);
    assert_true(d4 < 0.01);
    assert_true(d1 > 3 * d4);
    for (int k = 0; k < 3; k++) {
        sq_image_free(&photo[k]);
        sq_image_free(&mask[k]);
    }
    o.samples = 0;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &photo[0], &mask[0], NULL, &err), SQ_ERR_INVALID);
    assert_non_null(strstr(err.what, "0 samples a pixel"));
    assert_null(photo[0].px);
}

/* The body lies wholly in the frame, as a photographer would frame it: no part of it is cut
 * off by an edge, whatever the seed, radius and coiling (the benchmark's ranges). */
static void the_whole_body_stays_in_the_frame(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    SqPhotoOptions o = sq_fit_photo_options_default();
    o.width = 400;
    o.height = 300;
    o.texture_size = 32;
    o.backdrop = SQ_BACKDROP_PLAIN;
    for (unsigned seed = 1; seed <= 24; seed++) {
        o.seed = seed;
        o.coil = 0.2 + 0.6 * (seed % 4) / 3.0;
        SqImage photo, mask;
        SqPhotoTruth t;
        SqError err;
        assert_int_equal(sq_fit_synth_photo(&p, &o, &photo, &mask, &t, &err), SQ_OK);
        for (int k = 0; k < t.npoints; k++) {
            double x = t.points[2 * k], y = t.points[2 * k + 1];
            double edge = fmin(fmin(x, 400 - x), fmin(y, 300 - y));
            if (edge < t.body_radius)
                fail_msg("seed %u: centre-line point %d of %d at (%.0f, %.0f), %.1f px from the edge, radius %.1f",
                         seed, k, t.npoints, x, y, edge, t.body_radius);
        }
        int border = 0;
        for (int x = 0; x < 400; x++)
            border += (mask.px[x] > 0.5f) + (mask.px[299 * 400 + x] > 0.5f);
        for (int y = 0; y < 300; y++)
            border += (mask.px[y * 400] > 0.5f) + (mask.px[y * 400 + 399] > 0.5f);
        if (border)
            fail_msg("seed %u: %d mask pixels on the frame's edge", seed, border);
        sq_image_free(&photo);
        sq_image_free(&mask);
        sq_fit_truth_free(&t);
    }
}

static void refusals(void **state)
{
    (void)state;
    SqParams p;
    sq_params_default(&p);
    SqPhotoOptions o = sq_fit_photo_options_default();
    SqImage a, m;
    SqError err;
    o.width = 10;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &a, &m, NULL, &err), SQ_ERR_INVALID);
    assert_null(a.px);
    o.width = 300;
    o.body_radius = 200;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &a, &m, NULL, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "does not fit");
    o.body_radius = 0;
    p.Pattern_Type = SQ_PATTERN_COMPLEX;
    p.RD_Anisotropy = 100;
    assert_int_equal(sq_fit_synth_photo(&p, &o, &a, &m, NULL, &err), SQ_ERR_INVALID);
    assert_string_equal(err.where, "RD_Anisotropy");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(photo_of_a_plain_red_snake),
        cmocka_unit_test(degradations_change_the_photo),
        cmocka_unit_test(pixels_are_the_mean_of_the_skin),
        cmocka_unit_test(the_whole_body_stays_in_the_frame),
        cmocka_unit_test(refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
