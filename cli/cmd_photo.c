/* squama photo: a synthetic photo of a preset on a snake body, with its mask and the
 * truth (curve, body radius, view scale), for testing fits. */
#define _POSIX_C_SOURCE 200809L

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "json_util.h"
#include "squama/fitness.h"
#include "squama/io.h"
#include "squama/preset.h"

static const char help[] =
    "usage: squama photo PRESET -o PHOTO [options]\n"
    "\n"
    "Renders PRESET onto a snake-like body lying along a random smooth curve (partial\n"
    "coils, foreshortening, key light and ambient using the normal and roughness maps)\n"
    "over a soil, leaf-litter or grass backdrop, then blurs, adds noise and a colour cast.\n"
    "The whole body lies in the frame, clear of itself unless --coil is over 0.5.\n"
    "Writes PHOTO (.jpg or .png), its mask and a JSON of the truth: the preset, the body's\n"
    "centre line, radius and the view scale (body circumferences per texture tile).\n"
    "\n"
    "options:\n"
    "  -o, --output PHOTO   the photo (.jpg or .png)\n"
    "  -m, --mask FILE      the mask (default: PHOTO's name + _mask.png)\n"
    "  -t, --truth FILE     the truth JSON (default: PHOTO's name + _truth.json)\n"
    "  -s, --size WxH       photo size (default 1024x768)\n"
    "      --seed N         the layout, backdrop and noise (default 1)\n"
    "      --scale K        view scale (default: random 0.5..2)\n"
    "      --radius R       body radius in pixels (default: random)\n"
    "      --coil C         0 gentle .. 1 tight bends and partial coils (default 0.5)\n"
    "      --backdrop B     soil, litter, grass, plain or random (default)\n"
    "      --blur S         Gaussian blur sigma in pixels (default 0)\n"
    "      --noise S        sensor noise sigma, 0..1 (default 0)\n"
    "      --cast C         colour cast strength 0..1 (default 0)\n"
    "      --quality Q      JPEG quality 1..100 (default 90)\n"
    "  -h, --help           show this help\n";

/* PHOTO without its extension, plus suffix. */
static void sibling(const char *photo, const char *suffix, char *out, size_t n)
{
    snprintf(out, n, "%s", photo);
    char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (dot && (!slash || dot > slash))
        *dot = '\0';
    strncat(out, suffix, n - strlen(out) - 1);
}

static char *truth_json(const char *preset_path, const SqParams *p, const SqPhotoOptions *o,
                        const SqPhotoTruth *t, SqError *err)
{
    char *text = sq_preset_to_json(p, NULL, err);
    if (!text)
        return NULL;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", "squama-photo-truth/1");
    cJSON_AddStringToObject(root, "preset_file", preset_path);
    cJSON_AddItemToObject(root, "preset", cJSON_Parse(text));
    free(text);
    cJSON_AddNumberToObject(root, "width", o->width);
    cJSON_AddNumberToObject(root, "height", o->height);
    cJSON_AddNumberToObject(root, "seed", o->seed);
    cJSON_AddItemToObject(root, "view_scale", sq__json_exact_number(t->view_scale));
    cJSON_AddItemToObject(root, "body_radius", sq__json_exact_number(t->body_radius));
    cJSON_AddItemToObject(root, "band_centre", sq__json_exact_number(t->band_centre));
    cJSON_AddItemToObject(root, "length", sq__json_exact_number(t->length));
    cJSON *curve = cJSON_AddArrayToObject(root, "centre_line");
    for (int i = 0; i < t->npoints; i++) {
        cJSON *pt = cJSON_CreateArray();
        char buf[32];
        snprintf(buf, sizeof buf, "%.1f", t->points[2 * i]);
        cJSON_AddItemToArray(pt, cJSON_CreateRaw(buf));
        snprintf(buf, sizeof buf, "%.1f", t->points[2 * i + 1]);
        cJSON_AddItemToArray(pt, cJSON_CreateRaw(buf));
        cJSON_AddItemToArray(curve, pt);
    }
    char *out = sq__json_print(root);
    cJSON_Delete(root);
    if (!out)
        sq_error_set(err, SQ_ERR_NOMEM, "", "out of memory");
    return out;
}

int cmd_photo(int argc, char **argv)
{
    enum { O_SEED = 1000, O_SCALE, O_RADIUS, O_COIL, O_BACK, O_BLUR, O_NOISE, O_CAST, O_QUALITY };
    static const struct option opts[] = {
        {"output", required_argument, NULL, 'o'}, {"mask", required_argument, NULL, 'm'},
        {"truth", required_argument, NULL, 't'},  {"size", required_argument, NULL, 's'},
        {"seed", required_argument, NULL, O_SEED}, {"scale", required_argument, NULL, O_SCALE},
        {"radius", required_argument, NULL, O_RADIUS}, {"coil", required_argument, NULL, O_COIL},
        {"backdrop", required_argument, NULL, O_BACK}, {"blur", required_argument, NULL, O_BLUR},
        {"noise", required_argument, NULL, O_NOISE}, {"cast", required_argument, NULL, O_CAST},
        {"quality", required_argument, NULL, O_QUALITY}, {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0}};
    SqPhotoOptions po = sq_fit_photo_options_default();
    const char *out = NULL, *mask_path = NULL, *truth_path = NULL;
    int quality = 90, c;
    long n;
    SqError err;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":ho:m:t:s:", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case 'm': mask_path = optarg; break;
        case 't': truth_path = optarg; break;
        case 's':
            if (!cli_parse_size(optarg, 64, 8192, &po.width, &po.height))
                return cli_usage("photo", "--size must be WxH with sides from 64 to 8192, got '%s'", optarg);
            break;
        case O_SEED: /* as squama render's and fit's */
            if (cli_parse_int("--seed", optarg, 0, 2147483647L, &n, &err) != 0)
                return cli_usage("photo", "%s", err.what);
            po.seed = (unsigned)n;
            break;
        case O_SCALE:
            if (cli_parse_real("--scale", optarg, 0.05, 20, &po.view_scale, NULL) != 0)
                return cli_usage("photo", "--scale must be in [0.05, 20], got '%s'", optarg);
            break;
        case O_RADIUS:
            if (cli_parse_real("--radius", optarg, 4, 2000, &po.body_radius, NULL) != 0)
                return cli_usage("photo", "--radius must be in [4, 2000] pixels, got '%s'", optarg);
            break;
        case O_COIL:
            if (cli_parse_real("--coil", optarg, 0, 1, &po.coil, NULL) != 0)
                return cli_usage("photo", "--coil must be in [0, 1], got '%s'", optarg);
            break;
        case O_BACK: {
            static const char *const names[] = {"random", "soil", "litter", "grass", "plain", NULL};
            int k = 0;
            while (names[k] && strcmp(names[k], optarg) != 0)
                k++;
            if (!names[k])
                return cli_usage("photo", "--backdrop must be soil, litter, grass, plain or random, got '%s'", optarg);
            po.backdrop = (SqBackdrop)k;
            break;
        }
        case O_BLUR:
            if (cli_parse_real("--blur", optarg, 0, 50, &po.blur, NULL) != 0)
                return cli_usage("photo", "--blur must be in [0, 50], got '%s'", optarg);
            break;
        case O_NOISE:
            if (cli_parse_real("--noise", optarg, 0, 1, &po.noise, NULL) != 0)
                return cli_usage("photo", "--noise must be in [0, 1], got '%s'", optarg);
            break;
        case O_CAST:
            if (cli_parse_real("--cast", optarg, 0, 1, &po.cast, NULL) != 0)
                return cli_usage("photo", "--cast must be in [0, 1], got '%s'", optarg);
            break;
        case O_QUALITY:
            if (cli_parse_int("--quality", optarg, 1, 100, &n, &err) != 0)
                return cli_usage("photo", "%s", err.what);
            quality = (int)n;
            break;
        case 'h': fputs(help, stdout); return CLI_OK;
        default:
            return cli_bad_option("photo", argv, c, opts);
        }
    }
    if (argc - optind != 1)
        return cli_usage("photo", "give exactly one PRESET");
    if (!out)
        return cli_usage("photo", "say where the photo goes with -o PHOTO");
    char mbuf[4096], tbuf[4096];
    if (!mask_path) {
        sibling(out, "_mask.png", mbuf, sizeof mbuf);
        mask_path = mbuf;
    }
    if (!truth_path) {
        sibling(out, "_truth.json", tbuf, sizeof tbuf);
        truth_path = tbuf;
    }
    /* three files, or one would be written over another */
    if (cli_same_file(out, mask_path) || cli_same_file(out, truth_path) || cli_same_file(mask_path, truth_path))
        return cli_usage("photo", "the photo (%s), its mask (%s) and its truth (%s) must be three different files",
                         out, mask_path, truth_path);

    SqParams p;
    if (sq_preset_load(argv[optind], &p, NULL, &err) != SQ_OK)
        return cli_fail(&err);
    SqImage photo, mask;
    SqPhotoTruth truth;
    if (sq_fit_synth_photo(&p, &po, &photo, &mask, &truth, &err) != SQ_OK)
        return cli_fail(&err);
    int rc = CLI_OK;
    SqWriteOptions wo = {.format = SQ_FORMAT_AUTO, .bits = 0, .quality = quality};
    char *json = truth_json(argv[optind], &p, &po, &truth, &err);
    if (!json || sq_io_write_image(out, &photo, &wo, &err) != SQ_OK ||
        sq_io_write_image(mask_path, &mask, NULL, &err) != SQ_OK ||
        sq_io_write_file(truth_path, json, strlen(json), &err) != SQ_OK)
        rc = cli_fail(&err);
    else
        printf("wrote %s, %s, %s (body radius %.1f px, view scale %.3f)\n", out, mask_path, truth_path,
               truth.body_radius, truth.view_scale);
    free(json);
    sq_image_free(&photo);
    sq_image_free(&mask);
    sq_fit_truth_free(&truth);
    return rc;
}
