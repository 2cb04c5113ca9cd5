/* squama batch's thumbnails (cli/thumb.c): the photo with the mask's outside veiled, and
 * the two strips turned to run across. */
#include "sq_test.h"

#include <math.h>

#include "squama/image.h"
#include "squama/io.h"
#include "thumb.h"

/* A w x h sRGB image of colour rgb (left of split) and rgb2 (from split on). */
static void write_halves(const char *path, int w, int h, int split, const float rgb[3], const float rgb2[3])
{
    SqImage img;
    SqError err;
    assert_int_equal(sq_image_alloc(&img, w, h, 3, SQ_SPACE_SRGB), 0);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                sq_image_at(&img, x, y)[c] = x < split ? rgb[c] : rgb2[c];
    assert_int_equal(sq_io_write_image(path, &img, NULL, &err), SQ_OK);
    sq_image_free(&img);
}

static void read_back(const char *path, SqImage *img)
{
    SqError err;
    assert_int_equal(sq_io_read_image(path, NULL, img, NULL, &err), SQ_OK);
}

static void assert_near(const float *px, double r, double g, double b)
{
    if (fabs(px[0] - r) > 0.02 || fabs(px[1] - g) > 0.02 || fabs(px[2] - b) > 0.02)
        fail_msg("pixel (%.3f %.3f %.3f), expected (%.3f %.3f %.3f)", px[0], px[1], px[2], r, g, b);
}

static void the_photo_thumbnail_veils_what_the_mask_leaves_out(void **state)
{
    (void)state;
    char photo[4096], mask[4096], thumb[4096], small[4096];
    const float red[3] = {1, 0, 0}, blue[3] = {0, 0, 1}, white[3] = {1, 1, 1}, black[3] = {0};
    write_halves(tmp_path(photo, sizeof photo, "thumb_photo_in.png"), 320, 200, 160, red, blue);
    write_halves(tmp_path(mask, sizeof mask, "thumb_mask_in.png"), 320, 200, 160, white, black);
    SqError err;
    assert_int_equal(cli_thumbnail(photo, mask, tmp_path(thumb, sizeof thumb, "thumb_photo.png"), &err), SQ_OK);
    SqImage t;
    read_back(thumb, &t);
    assert_int_equal(t.width, CLI_THUMB);
    assert_int_equal(t.height, 100);
    assert_near(sq_image_at(&t, 10, 50), 1, 0, 0);                 /* inside: as it was */
    const double veil[3] = CLI_THUMB_VEIL, keep = CLI_THUMB_KEEP; /* outside: veiled */
    assert_near(sq_image_at(&t, 150, 50), (1 - keep) * veil[0], (1 - keep) * veil[1], keep + (1 - keep) * veil[2]);
    sq_image_free(&t);
    /* without a mask, nothing veiled */
    assert_int_equal(cli_thumbnail(photo, NULL, thumb, &err), SQ_OK);
    read_back(thumb, &t);
    assert_near(sq_image_at(&t, 150, 50), 0, 0, 1);
    sq_image_free(&t);
    /* a small image is not enlarged */
    write_halves(tmp_path(small, sizeof small, "thumb_small_in.png"), 40, 30, 20, red, blue);
    assert_int_equal(cli_thumbnail(small, NULL, thumb, &err), SQ_OK);
    read_back(thumb, &t);
    assert_int_equal(t.width, 40);
    assert_int_equal(t.height, 30);
    sq_image_free(&t);
    /* a fit's full-size mask over its prepared photo, whose sides were rounded (3000x450
     * prepared at 256 px wide: 256x38, 1% off in aspect): taken to the photo's pixels */
    char wide[4096], widemask[4096];
    write_halves(tmp_path(wide, sizeof wide, "thumb_wide_in.png"), 256, 38, 128, red, blue);
    write_halves(tmp_path(widemask, sizeof widemask, "thumb_wide_mask.png"), 3000, 450, 1500, white, black);
    assert_int_equal(cli_thumbnail(wide, widemask, thumb, &err), SQ_OK);
    read_back(thumb, &t);
    assert_near(sq_image_at(&t, 5, t.height / 2), 1, 0, 0);
    assert_near(sq_image_at(&t, t.width - 5, t.height / 2), (1 - keep) * veil[0], (1 - keep) * veil[1],
                keep + (1 - keep) * veil[2]);
    sq_image_free(&t);
    /* a mask of another size, a missing photo: errors naming the file, nothing written */
    assert_int_equal(cli_thumbnail(photo, small, tmp_path(thumb, sizeof thumb, "thumb_bad.png"), &err),
                     SQ_ERR_INVALID);
    assert_contains(err.what, "the mask is 40x30 but the photo is 320x200");
    assert_contains(err.where, "thumb_small_in.png");
    assert_true(cli_thumbnail(tmp_path(photo, sizeof photo, "thumb_gone.png"), NULL, thumb, &err) != SQ_OK);
    struct stat sb;
    assert_true(stat(thumb, &sb) != 0);
}

static void the_strips_run_across_photo_above_fit_below(void **state)
{
    (void)state;
    char strip[4096], fitted[4096], thumb[4096];
    SqImage s;
    SqError err;
    /* the photo's strip: red rising along the body (down the strip), the fit's green */
    assert_int_equal(sq_image_alloc(&s, 64, 304, 3, SQ_SPACE_SRGB), 0);
    for (int y = 0; y < s.height; y++)
        for (int x = 0; x < s.width; x++)
            sq_image_at(&s, x, y)[0] = (float)y / (s.height - 1);
    assert_int_equal(sq_io_write_image(tmp_path(strip, sizeof strip, "thumb_strip_in.png"), &s, NULL, &err), SQ_OK);
    sq_image_free(&s);
    const float green[3] = {0, 1, 0};
    write_halves(tmp_path(fitted, sizeof fitted, "thumb_fitted_in.png"), 64, 304, 64, green, green);
    assert_int_equal(cli_thumbnail_strips(strip, fitted, tmp_path(thumb, sizeof thumb, "thumb_strips.png"), &err),
                     SQ_OK);
    SqImage t;
    read_back(thumb, &t);
    assert_int_equal(t.width, 152); /* 304 along, halved to fit CLI_THUMB */
    assert_int_equal(t.height, 32 + 2 + 32);
    assert_true(sq_image_at(&t, 2, 10)[0] < 0.05f && sq_image_at(&t, 149, 10)[0] > 0.95f); /* along: across */
    assert_near(sq_image_at(&t, 80, 33), 1, 1, 1);  /* the gap */
    assert_near(sq_image_at(&t, 80, 50), 0, 1, 0);  /* the fit, below */
    sq_image_free(&t);
    /* strips of two sizes: an error naming the fitted strip */
    const float black[3] = {0};
    write_halves(fitted, 64, 300, 64, black, black);
    assert_int_equal(cli_thumbnail_strips(strip, fitted, thumb, &err), SQ_ERR_INVALID);
    assert_contains(err.what, "the fitted strip is 64x300 but the photo's is 64x304");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(the_photo_thumbnail_veils_what_the_mask_leaves_out),
        cmocka_unit_test(the_strips_run_across_photo_above_fit_below),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
