/* Image and file I/O: round trips per format, orientation, masks, limits, and every
 * way a file can be bad. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sq_test.h"
#include "io_internal.h"
#include "squama/io.h"

static void make_gradient(SqImage *img, int w, int h, int ch, SqColorSpace space)
{
    assert_int_equal(sq_image_alloc(img, w, h, ch, space), 0);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < ch; c++)
                sq_image_at(img, x, y)[c] = (float)((x * 7 + y * 13 + c * 29) % 256) / 255.0f;
}

static float max_diff(const SqImage *a, const SqImage *b, int channels)
{
    float m = 0;
    for (int y = 0; y < a->height; y++)
        for (int x = 0; x < a->width; x++)
            for (int c = 0; c < channels; c++) {
                float d = fabsf(sq_image_at(a, x, y)[c] - sq_image_at(b, x, y)[c]);
                if (d > m)
                    m = d;
            }
    return m;
}

/* No temporary files of this process (NAME.tmp-PID-K) are left beside the outputs. The
 * folder is shared: tests that run at the same time write their own temporary files. */
static void assert_no_temp_files(void)
{
    char mine[64], left[256] = "";
    snprintf(mine, sizeof mine, ".tmp-%ld-", (long)getpid());
    DIR *d = opendir(SQUAMA_TEST_TMP);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)))
        if (strstr(e->d_name, mine))
            snprintf(left, sizeof left, "%s", e->d_name);
    closedir(d);
    if (left[0])
        fail_msg("temporary file left behind: %s", left);
}

static void png8_round_trip_rgba(void **state)
{
    (void)state;
    char path[1024];
    SqImage a, b, mask;
    SqError err;
    make_gradient(&a, 31, 17, 4, SQ_SPACE_SRGB);
    for (int y = 0; y < 17; y++)
        for (int x = 0; x < 31; x++)
            sq_image_at(&a, x, y)[3] = x < 10 ? 0.0f : 1.0f;
    assert_int_equal(sq_io_write_image(tmp_path(path, sizeof path, "rt8.png"), &a, NULL, &err),
                     SQ_OK);
    assert_int_equal(sq_io_read_image(path, NULL, &b, &mask, &err), SQ_OK);
    assert_int_equal(b.width, 31);
    assert_int_equal(b.height, 17);
    assert_int_equal(b.channels, 4);
    assert_int_equal(b.space, SQ_SPACE_SRGB);
    /* colours survive beside transparent alpha (no premultiplication) */
    assert_true(max_diff(&a, &b, 4) <= 0.5f / 255.0f + 1e-6f);
    assert_non_null(mask.px);
    assert_int_equal(mask.channels, 1);
    assert_true(mask.px[9] == 0.0f && mask.px[10] == 1.0f);
    sq_image_free(&a);
    sq_image_free(&b);
    sq_image_free(&mask);
    assert_no_temp_files();
}

static void png16_round_trip_grey(void **state)
{
    (void)state;
    char path[1024];
    SqImage a, b, mask;
    SqError err;
    make_gradient(&a, 20, 9, 1, SQ_SPACE_DATA);
    SqWriteOptions o = {.format = SQ_FORMAT_PNG, .bits = 16};
    assert_int_equal(sq_io_write_image(tmp_path(path, sizeof path, "rt16.png"), &a, &o, &err),
                     SQ_OK);
    assert_int_equal(sq_io_read_image(path, NULL, &b, &mask, &err), SQ_OK);
    assert_null(mask.px); /* no alpha, no mask */
    assert_int_equal(b.channels, 4);
    for (int i = 0; i < 20 * 9; i++) {
        assert_true(fabsf(b.px[i * 4] - a.px[i]) <= 0.5f / 65535.0f + 1e-6f);
        assert_true(b.px[i * 4 + 1] == b.px[i * 4] && b.px[i * 4 + 2] == b.px[i * 4]);
        assert_true(b.px[i * 4 + 3] == 1.0f);
    }
    sq_image_free(&a);
    sq_image_free(&b);
}

static void exr_data_exact_and_colour_linearised(void **state)
{
    (void)state;
    char path[1024];
    SqImage a, b;
    SqError err;
    make_gradient(&a, 16, 8, 1, SQ_SPACE_DATA);
    a.px[5] = 3.75f;  /* EXR keeps values outside [0,1] */
    a.px[6] = -0.5f;
    SqWriteOptions o = {.format = SQ_FORMAT_EXR, .bits = 32};
    assert_int_equal(sq_io_write_image(tmp_path(path, sizeof path, "h.exr"), &a, &o, &err),
                     SQ_OK);
    assert_int_equal(sq_io_read_image(path, NULL, &b, NULL, &err), SQ_OK);
    for (int i = 0; i < 16 * 8; i++)
        assert_true(b.px[i * 4] == a.px[i]);
    sq_image_free(&a);
    sq_image_free(&b);

    /* sRGB colour is stored linear in EXR (half floats) and read back as linear */
    make_gradient(&a, 16, 8, 3, SQ_SPACE_SRGB);
    assert_int_equal(sq_io_write_image(tmp_path(path, sizeof path, "c.exr"), &a, NULL, &err),
                     SQ_OK);
    assert_int_equal(sq_io_read_image(path, NULL, &b, NULL, &err), SQ_OK);
    assert_int_equal(b.space, SQ_SPACE_LINEAR);
    for (int i = 0; i < 16 * 8; i++)
        for (int c = 0; c < 3; c++) {
            float want = sq_io_srgb_to_linear(a.px[i * 3 + c]);
            assert_true(fabsf(b.px[i * 4 + c] - want) <= 1e-3f * (1 + want));
        }
    sq_image_free(&a);
    sq_image_free(&b);
}

static void jpeg_round_trip(void **state)
{
    (void)state;
    char path[1024];
    SqImage a, b;
    SqError err;
    assert_int_equal(sq_image_alloc(&a, 48, 32, 4, SQ_SPACE_SRGB), 0);
    for (int i = 0; i < 48 * 32; i++) { /* smooth, so JPEG keeps it well */
        a.px[4 * i] = (float)(i % 48) / 47.0f;
        a.px[4 * i + 1] = (float)(i / 48) / 31.0f;
        a.px[4 * i + 2] = 0.5f;
        a.px[4 * i + 3] = 0.0f; /* dropped */
    }
    SqWriteOptions o = {.format = SQ_FORMAT_AUTO, .bits = 0, .quality = 95};
    assert_int_equal(sq_io_write_image(tmp_path(path, sizeof path, "q.jpg"), &a, &o, &err), SQ_OK);
    assert_int_equal(sq_io_read_image(path, NULL, &b, NULL, &err), SQ_OK);
    assert_int_equal(b.width, 48);
    double d = 0;
    for (int i = 0; i < 48 * 32; i++)
        for (int c = 0; c < 3; c++)
            d += fabsf(a.px[4 * i + c] - b.px[4 * i + c]);
    assert_true(d / (48 * 32 * 3) < 0.02);
    assert_true(b.px[3] == 1.0f);
    o.quality = 101;
    assert_int_equal(sq_io_write_image(path, &a, &o, &err), SQ_ERR_INVALID);
    o.quality = 90;
    o.bits = 16;
    assert_int_equal(sq_io_write_image(path, &a, &o, &err), SQ_ERR_INVALID);
    sq_image_free(&a);
    sq_image_free(&b);
}

static void srgb_transfer_functions(void **state)
{
    (void)state;
    assert_true(sq_io_srgb_to_linear(0) == 0);
    assert_true(fabsf(sq_io_srgb_to_linear(1) - 1) < 1e-6f);
    assert_true(fabsf(sq_io_srgb_to_linear(0.5f) - 0.214041f) < 1e-5f);
    for (int i = 0; i <= 100; i++) {
        float v = (float)i / 100.0f;
        assert_true(fabsf(sq_io_linear_to_srgb(sq_io_srgb_to_linear(v)) - v) < 1e-5f);
    }
}

/* EXIF orientation 6 (stored 8x4, left red, right blue) displays 4x8, red on top. */
static void exif_orientation_applied(void **state)
{
    (void)state;
    char path[1024];
    SqImage img;
    SqError err;
    assert_int_equal(sq_io_read_image(src_path(path, sizeof path, "tests/data/orient6.jpg"), NULL,
                                      &img, NULL, &err),
                     SQ_OK);
    assert_int_equal(img.width, 4);
    assert_int_equal(img.height, 8);
    const float *top = sq_image_at(&img, 2, 1), *bottom = sq_image_at(&img, 2, 6);
    assert_true(top[0] > 0.8f && top[2] < 0.2f);
    assert_true(bottom[2] > 0.8f && bottom[0] < 0.2f);
    sq_image_free(&img);
}

static void tiff_reads(void **state)
{
    (void)state;
    char path[1024];
    SqImage img;
    SqError err;
    assert_int_equal(sq_io_read_image(src_path(path, sizeof path, "tests/data/gradient16.tif"),
                                      NULL, &img, NULL, &err),
                     SQ_OK);
    assert_int_equal(img.width, 6);
    assert_int_equal(img.height, 5);
    assert_true(fabsf(sq_image_at(&img, 0, 0)[0] - 0.2f) < 0.01f);
    sq_image_free(&img);
}

static void pixel_limit_checked_before_decoding(void **state)
{
    (void)state;
    char path[1024];
    SqImage a, b;
    SqError err;
    make_gradient(&a, 100, 60, 3, SQ_SPACE_SRGB);
    assert_int_equal(sq_io_write_image(tmp_path(path, sizeof path, "big.png"), &a, NULL, &err),
                     SQ_OK);
    SqReadOptions o = {.max_pixels = 5000};
    assert_int_equal(sq_io_read_image(path, &o, &b, NULL, &err), SQ_ERR_LIMIT);
    assert_null(b.px);
    assert_contains(err.what, "100x60");
    assert_contains(err.what, "over the limit");
    assert_string_equal(err.where, path);
    o.max_pixels = 6000;
    assert_int_equal(sq_io_read_image(path, &o, &b, NULL, &err), SQ_OK);
    sq_image_free(&a);
    sq_image_free(&b);
}

static void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    fclose(f);
}

/* Writes a valid file in `ext` format (through our writer, or the JPEG fixture), then
 * keeps only `keep` of its bytes. */
static void truncated_copy(const char *src, const char *dst, double keep)
{
    char *data;
    size_t n;
    SqError err;
    assert_int_equal(sq_io_read_file(src, 1 << 24, &data, &n, &err), SQ_OK);
    write_bytes(dst, data, (size_t)(n * keep));
    free(data);
}

static void corrupt_files_refused_cleanly(void **state)
{
    (void)state;
    char good[1024], bad[1024], jpg[1024];
    SqImage a, b;
    SqError err;
    make_gradient(&a, 64, 64, 3, SQ_SPACE_SRGB);
    assert_int_equal(sq_io_write_image(tmp_path(good, sizeof good, "good.png"), &a, NULL, &err),
                     SQ_OK);
    sq_image_free(&a);

    truncated_copy(good, tmp_path(bad, sizeof bad, "trunc.png"), 0.5);
    assert_int_equal(sq_io_read_image(bad, NULL, &b, NULL, &err), SQ_ERR_PARSE);
    assert_null(b.px);
    assert_string_equal(err.where, bad);

    truncated_copy(good, tmp_path(bad, sizeof bad, "header.png"), 0.05);
    assert_true(sq_io_read_image(bad, NULL, &b, NULL, &err) < 0);
    assert_null(b.px);

    src_path(jpg, sizeof jpg, "tests/data/orient6.jpg");
    truncated_copy(jpg, tmp_path(bad, sizeof bad, "trunc.jpg"), 0.6);
    assert_true(sq_io_read_image(bad, NULL, &b, NULL, &err) < 0);
    assert_null(b.px);

    static const char garbage[] = "this is not an image at all, just some text\n";
    write_bytes(tmp_path(bad, sizeof bad, "garbage.png"), garbage, sizeof garbage);
    assert_int_equal(sq_io_read_image(bad, NULL, &b, NULL, &err), SQ_ERR_PARSE);
    assert_contains(err.what, "not a readable image");

    write_bytes(tmp_path(bad, sizeof bad, "empty.jpg"), "", 0);
    assert_true(sq_io_read_image(bad, NULL, &b, NULL, &err) < 0);

    assert_int_equal(sq_io_read_image("/nonexistent/photo.jpg", NULL, &b, NULL, &err),
                     SQ_ERR_IO);
    assert_contains(err.what, "No such file");
    assert_true(sq_io_read_image(SQUAMA_TEST_TMP, NULL, &b, NULL, &err) < 0);
}

static void atomic_writes_and_write_errors(void **state)
{
    (void)state;
    char path[1024];
    SqImage a;
    SqError err;
    make_gradient(&a, 8, 8, 3, SQ_SPACE_SRGB);

    assert_int_equal(sq_io_write_image("/nonexistent/dir/x.png", &a, NULL, &err), SQ_ERR_IO);
    assert_string_equal(err.where, "/nonexistent/dir/x.png");
    assert_int_equal(sq_io_write_image(tmp_path(path, sizeof path, "x.tga"), &a, NULL, &err),
                     SQ_ERR_UNSUPPORTED);
    SqWriteOptions o = {.format = SQ_FORMAT_PNG, .bits = 12};
    assert_int_equal(sq_io_write_image(tmp_path(path, sizeof path, "x.png"), &a, &o, &err),
                     SQ_ERR_INVALID);
    assert_contains(err.what, "12-bit PNG");
    SqImage empty = {0};
    assert_int_equal(sq_io_write_image(path, &empty, NULL, &err), SQ_ERR_INVALID);

    /* replacing an existing file */
    write_bytes(tmp_path(path, sizeof path, "replace.png"), "old", 3);
    assert_int_equal(sq_io_write_image(path, &a, NULL, &err), SQ_OK);
    SqImage b;
    assert_int_equal(sq_io_read_image(path, NULL, &b, NULL, &err), SQ_OK);
    sq_image_free(&b);
    sq_image_free(&a);

    /* text files */
    assert_int_equal(sq_io_write_file(tmp_path(path, sizeof path, "t.txt"), "hello\n", 6, &err),
                     SQ_OK);
    char *data;
    size_t n;
    assert_int_equal(sq_io_read_file(path, 100, &data, &n, &err), SQ_OK);
    assert_int_equal(n, 6);
    assert_string_equal(data, "hello\n");
    free(data);
    assert_int_equal(sq_io_read_file(path, 3, &data, &n, &err), SQ_ERR_LIMIT);
    assert_null(data);
    assert_int_equal(sq_io_write_file("/nonexistent/t.txt", "x", 1, &err), SQ_ERR_IO);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true((st.st_mode & 0444) == 0444 || (st.st_mode & 0400)); /* readable */
    assert_no_temp_files();
}

/* A write under way (its temporary file made, not yet renamed) is what a signal handler
 * removes with sq_io_remove_temps, however long its path; the files already written stay,
 * and a temporary file renamed into place is forgotten (not removed under its old name's
 * reuse). */
static void interrupted_writes_leave_no_temp_files(void **state)
{
    (void)state;
    char path[1024], tmp[1200], done[1024], deep[4096], deep_tmp[4096];
    struct stat st;
    SqError err;
    tmp_path(path, sizeof path, "half.png");
    assert_int_equal(sq__io_make_temp(path, tmp, sizeof tmp), 0);
    assert_int_equal(stat(tmp, &st), 0);
    /* a path of some 2,000 bytes: folders of 250 bytes, eight deep */
    char seg[251];
    memset(seg, 'd', 250);
    seg[250] = '\0';
    int n = snprintf(deep, sizeof deep, "%s", SQUAMA_TEST_TMP);
    for (int i = 0; i < 8; i++) {
        n += snprintf(deep + n, sizeof deep - (size_t)n, "/%s", seg);
        assert_true(mkdir(deep, 0777) == 0 || errno == EEXIST);
    }
    snprintf(deep + n, sizeof deep - (size_t)n, "/half.png");
    assert_true(strlen(deep) > 2000);
    assert_int_equal(sq__io_make_temp(deep, deep_tmp, sizeof deep_tmp), 0);
    assert_int_equal(stat(deep_tmp, &st), 0);
    assert_int_equal(sq_io_write_file(tmp_path(done, sizeof done, "whole.txt"), "x", 1, &err), SQ_OK);
    sq_io_remove_temps();
    assert_int_not_equal(stat(tmp, &st), 0);
    assert_int_not_equal(stat(deep_tmp, &st), 0);
    assert_int_equal(stat(done, &st), 0);
    assert_int_equal(stat(path, &st) == 0, 0);
    assert_no_temp_files();
    for (int i = 0; i < 8; i++) { /* the folders, deepest first */
        *strrchr(deep, '/') = '\0';
        assert_int_equal(rmdir(deep), 0);
    }
}

/* Pixels of img that differ from the flat grey v; their bounding box in *box (x0, y0,
 * x1, y1). */
static int changed(const SqImage *img, float v, int box[4])
{
    int n = 0;
    box[0] = box[1] = 1 << 30;
    box[2] = box[3] = -1;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            if (fabsf(sq_image_at(img, x, y)[0] - v) > 1e-6f) {
                n++;
                box[0] = x < box[0] ? x : box[0];
                box[1] = y < box[1] ? y : box[1];
                box[2] = x > box[2] ? x : box[2];
                box[3] = y > box[3] ? y : box[3];
            }
    return n;
}

/* Text lands where it is put, and text running over any edge, or wholly outside, is
 * clipped: OpenImageIO 2.4 aborted on a label above the top edge (a body line's first
 * point near the top of a real photo killed a whole batch). */
static void text_drawn_and_clipped_at_the_edges(void **state)
{
    (void)state;
    const float red[3] = {1, 0, 0};
    /* inside; over the top edge; wholly above (what aborted); over the left, right and
     * bottom edges; wholly outside */
    const int pos[][2] = {{10, 20}, {10, 4}, {10, -3}, {-6, 20}, {50, 20}, {10, 36}, {-40, -40}, {500, 500}};
    for (int ch = 3; ch <= 4; ch++)
        for (size_t k = 0; k < sizeof pos / sizeof pos[0]; k++) {
            SqImage img;
            SqError err;
            assert_int_equal(sq_image_alloc(&img, 64, 32, ch, SQ_SPACE_SRGB), 0);
            for (size_t i = 0; i < (size_t)64 * 32 * ch; i++)
                img.px[i] = 0.5f;
            const int x = pos[k][0], y = pos[k][1];
            SqStatus st = sq_io_draw_text(&img, x, y, 11, "0:0", red, &err);
            if (st == SQ_ERR_UNSUPPORTED) { /* no font on this machine */
                sq_image_free(&img);
                skip();
            }
            assert_int_equal(st, SQ_OK);
            int box[4];
            const int n = changed(&img, 0.5f, box);
            if (k == 0) { /* wholly inside: glyphs about 11 pixels tall above the baseline */
                assert_true(n > 20);
                assert_true(box[0] >= x && box[2] < x + 30 && box[1] >= y - 12 && box[3] <= y + 3);
            } else if (k == 1 || k == 3 || k == 4) { /* over the top, left or right edge */
                assert_true(n > 5);
            } else if (k == 2 || k >= 6) { /* wholly outside */
                assert_int_equal(n, 0);
            }
            for (int yy = 0; yy < 32; yy++) /* only towards red; alpha only raised */
                for (int xx = 0; xx < 64; xx++) {
                    const float *p = sq_image_at(&img, xx, yy);
                    assert_true(p[0] >= 0.5f - 1e-6f && p[1] <= 0.5f + 1e-6f);
                    if (ch == 4)
                        assert_true(p[3] >= 0.5f - 1e-6f && p[3] <= 1.0f + 1e-6f);
                }
            sq_image_free(&img);
        }
}

/* Real photos from ../shared/photos decode when the folder is there. */
static void real_photos_decode(void **state)
{
    (void)state;
    char path[2048];
    snprintf(path, sizeof path, "%s/photos/bitis_arietans__jv0206.jpg", SQUAMA_SHARED_DIR);
    if (access(path, R_OK) != 0)
        skip();
    SqImage img;
    SqError err;
    assert_int_equal(sq_io_read_image(path, NULL, &img, NULL, &err), SQ_OK);
    assert_true(img.width > 100 && img.height > 100);
    double mean = 0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
        mean += img.px[i * 4 + 1];
    mean /= (double)img.width * img.height;
    assert_true(mean > 0.05 && mean < 0.95);
    sq_image_free(&img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(png8_round_trip_rgba),
        cmocka_unit_test(png16_round_trip_grey),
        cmocka_unit_test(exr_data_exact_and_colour_linearised),
        cmocka_unit_test(jpeg_round_trip),
        cmocka_unit_test(srgb_transfer_functions),
        cmocka_unit_test(exif_orientation_applied),
        cmocka_unit_test(tiff_reads),
        cmocka_unit_test(pixel_limit_checked_before_decoding),
        cmocka_unit_test(corrupt_files_refused_cleanly),
        cmocka_unit_test(atomic_writes_and_write_errors),
        cmocka_unit_test(interrupted_writes_leave_no_temp_files),
        cmocka_unit_test(text_drawn_and_clipped_at_the_edges),
        cmocka_unit_test(real_photos_decode),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
