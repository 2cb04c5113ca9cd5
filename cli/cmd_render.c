/* squama render: a preset (or a thesis CA descriptor) to the four texture maps. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "cli.h"
#include "sheet.h"
#include "squama/fitness.h"
#include "squama/generator.h"
#include "squama/io.h"
#include "squama/preset.h"

static const char help[] =
    "usage: squama render [PRESET] -o DIR [options]\n"
    "       squama render --sheet OUT.png PRESET... [--size N] [--cols C]\n"
    "\n"
    "Renders a preset's four maps into DIR: basecolor, height, roughness and normal\n"
    "(.png or .exr), as a set: all new, or the old ones kept. With --ca FILE the pattern\n"
    "is that cellular-automaton descriptor (the thesis' text format, Appendix E), over\n"
    "PRESET's other parameters or the defaults.\n"
    "\n"
    "With --sheet, every PRESET's base colour is rendered at --size (default 256) and laid\n"
    "out in a grid with its name beneath it: a contact sheet to choose from by looking.\n"
    "\n"
    "options:\n"
    "  -o, --output DIR     folder for the maps (created if missing)\n"
    "  -s, --size N|WxH     texture size in pixels (default 1024)\n"
    "  -f, --format F       png (default) or exr\n"
    "  -b, --bits N         PNG: 8 or 16 for every map (default 8, height 16);\n"
    "                       EXR: 16 (half, default) or 32\n"
    "      --ca FILE        use this CA descriptor as the pattern (other_simple)\n"
    "      --seed N         override the preset's Seed\n"
    "      --directx        DirectX normal map (-Y); default OpenGL (+Y)\n"
    "      --preview        also preview.png: the texture on a lit snake body\n"
    "      --sheet OUT.png  a contact sheet of the PRESETs instead of their maps\n"
    "      --cols C         the sheet's columns (default: about the square root)\n"
    "  -j, --threads N      threads (default: all cores)\n"
    "  -q, --quiet          print nothing but errors\n"
    "  -h, --help           show this help\n";


static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

/* A contact sheet of preset files, named by their file names (without folder and
 * extension). Nothing is written unless every preset loads and renders. */
static int render_sheet(const char *out, char **files, int n, int size, int cols, SqGenOptions go, long seed,
                        int quiet)
{
    SqError err;
    SqParams *presets = malloc(sizeof *presets * (size_t)n);
    char(*names)[256] = malloc(sizeof *names * (size_t)n);
    const char **labels = malloc(sizeof *labels * (size_t)n);
    int rc = CLI_OK;
    if (!presets || !names || !labels) {
        sq_error_set(&err, SQ_ERR_NOMEM, out, "out of memory for %d presets", n);
        rc = cli_fail(&err);
    }
    for (int i = 0; i < n && rc == CLI_OK; i++) {
        if (sq_preset_load(files[i], &presets[i], NULL, &err) != SQ_OK) {
            rc = cli_fail(&err);
            break;
        }
        if (seed >= 0)
            presets[i].Seed = (int)seed;
        const char *base = strrchr(files[i], '/');
        snprintf(names[i], sizeof names[i], "%s", base ? base + 1 : files[i]);
        char *dot = strrchr(names[i], '.');
        if (dot && dot != names[i])
            *dot = '\0';
        labels[i] = names[i];
    }
    if (rc == CLI_OK && cli_sheet_write(out, presets, labels, n, size, &cols, go, &err) != SQ_OK)
        rc = cli_fail(&err);
    if (rc == CLI_OK && !quiet)
        printf("wrote %s: %d preset%s, %d x %d\n", out, n, n == 1 ? "" : "s", cols, (n + cols - 1) / cols);
    free(presets);
    free(names);
    free(labels);
    return rc;
}

/* The maps (and the preview) into a temporary folder inside outdir, then moved into place
 * as a set (cli_staging_commit): a failure or an interruption leaves the maps that were
 * there before, not some new and some old. A folder the command made is removed on failure. */
static SqStatus write_maps(const char *outdir, const SqParams *p, const SqTextures *tex, SqGenOptions go,
                           const char *ext, int bits, int preview, int quiet, SqError *err)
{
    CliMade made;
    if (cli_mkdirs_new(outdir, &made) != 0)
        return sq_error_set(err, SQ_ERR_IO, outdir, "cannot create the output folder: %s", strerror(errno));
    cli_made_register(outdir, &made); /* an interrupted render removes them when empty */
    const int png = strcmp(ext, "png") == 0;
    struct { const char *name; const SqImage *img; int bits; } maps[] = {
        {"basecolor", &tex->basecolor, 8}, {"height", &tex->height, 16},
        {"roughness", &tex->roughness, 8}, {"normal", &tex->normal, 8}};
    enum { NMAPS = sizeof maps / sizeof maps[0] };
    char name[32], pattern[4200], path[4200];
    snprintf(pattern, sizeof pattern, "%s/.render.tmp-XXXXXX", outdir);
    CliStaging stg;
    SqStatus st = cli_staging_open(&stg, pattern, outdir, NMAPS + 1, err);
    stg.what = "map";
    for (int i = 0; i < NMAPS && st == SQ_OK; i++) {
        snprintf(name, sizeof name, "%s.%s", maps[i].name, ext);
        if ((st = cli_staging_path(&stg, name, path, sizeof path, err)) != SQ_OK)
            break;
        SqWriteOptions wo = {.format = png ? SQ_FORMAT_PNG : SQ_FORMAT_EXR,
                             .bits = bits ? bits : (png ? maps[i].bits : 16)};
        st = sq_io_write_image(path, maps[i].img, &wo, err);
    }
    if (st == SQ_OK && preview) {
        SqPhotoOptions po = sq_fit_photo_options_default();
        po.width = 1024;
        po.height = 640;
        po.preview = 1;
        po.view_scale = 1.5;
        po.texture_size = go.width < 1024 ? go.width : 1024;
        SqImage photo, mask;
        st = cli_staging_path(&stg, "preview.png", path, sizeof path, err);
        if (st == SQ_OK)
            st = sq_fit_synth_photo(p, &po, &photo, &mask, NULL, err);
        if (st == SQ_OK) {
            st = sq_io_write_image(path, &photo, NULL, err);
            sq_image_free(&photo);
            sq_image_free(&mask);
        }
    }
    if (st == SQ_OK) /* all written: into place as a set */
        st = cli_staging_commit(&stg, quiet, err);
    else
        cli_staging_where(&stg, err);
    cli_staging_free(&stg);
    if (st != SQ_OK)
        cli_rmdirs_new(outdir, &made);
    cli_made_forget(outdir, &made);
    return st;
}

int cmd_render(int argc, char **argv)
{
    enum { OPT_CA = 1000, OPT_SEED, OPT_DIRECTX, OPT_PREVIEW, OPT_SHEET, OPT_COLS };
    static const struct option opts[] = {
        {"output", required_argument, NULL, 'o'}, {"size", required_argument, NULL, 's'},
        {"format", required_argument, NULL, 'f'}, {"bits", required_argument, NULL, 'b'},
        {"ca", required_argument, NULL, OPT_CA},  {"seed", required_argument, NULL, OPT_SEED},
        {"directx", no_argument, NULL, OPT_DIRECTX}, {"threads", required_argument, NULL, 'j'},
        {"preview", no_argument, NULL, OPT_PREVIEW}, {"sheet", required_argument, NULL, OPT_SHEET},
        {"cols", required_argument, NULL, OPT_COLS},
        {"quiet", no_argument, NULL, 'q'},        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0}};
    const char *outdir = NULL, *ca_file = NULL, *ext = "png", *sheet = NULL;
    int bits = 0, quiet = 0, preview = 0, cols = 0, size_given = 0, c;
    long seed = -1, v;
    SqGenOptions go = sq_gen_options_default(1024);
    SqError err;
    optind = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":ho:s:f:b:j:q", opts, NULL)) != -1) {
        switch (c) {
        case 'o': outdir = optarg; break;
        case 's':
            if (!cli_parse_size(optarg, 8, SQ_GEN_MAX_SIZE, &go.width, &go.height))
                return cli_usage("render", "--size must be N or WxH with sides from 8 to %d, got '%s'",
                                 SQ_GEN_MAX_SIZE, optarg);
            size_given = 1;
            break;
        case OPT_SHEET: sheet = optarg; break;
        case OPT_COLS:
            if (cli_parse_int("--cols", optarg, 1, 64, &v, &err) != 0)
                return cli_usage("render", "%s", err.what);
            cols = (int)v;
            break;
        case 'f':
            if (strcmp(optarg, "png") != 0 && strcmp(optarg, "exr") != 0)
                return cli_usage("render", "--format must be png or exr, got '%s'", optarg);
            ext = optarg;
            break;
        case 'b':
            if (cli_parse_int("--bits", optarg, 8, 32, &v, NULL) != 0 || (v != 8 && v != 16 && v != 32))
                return cli_usage("render", "--bits must be 8, 16 or 32, got '%s'", optarg);
            bits = (int)v;
            break;
        case 'j':
            if (cli_parse_int("--threads", optarg, 1, 1024, &v, &err) != 0)
                return cli_usage("render", "%s", err.what);
            go.threads = (int)v;
            break;
        case OPT_CA: ca_file = optarg; break;
        case OPT_SEED:
            if (cli_parse_int("--seed", optarg, 0, 2147483647L, &seed, &err) != 0)
                return cli_usage("render", "%s", err.what);
            break;
        case OPT_DIRECTX: go.normal_directx = 1; break;
        case OPT_PREVIEW: preview = 1; break;
        case 'q': quiet = 1; break;
        case 'h': fputs(help, stdout); return CLI_OK;
        default:
            return cli_bad_option("render", argv, c, opts);
        }
    }
    const int png = strcmp(ext, "png") == 0;
    if (!sheet && cols)
        return cli_usage("render", "--cols is for --sheet");
    if (sheet) {
        if (argc - optind < 1)
            return cli_usage("render", "--sheet needs the PRESETs to lay out");
        if (outdir || ca_file || preview || bits || go.normal_directx || !png)
            return cli_usage("render", "--sheet makes one PNG of base colours: -o, --ca, --preview, --format, "
                                       "--bits and --directx do not go with it");
        if (size_given && (go.width != go.height || go.width < 32 || go.width > 1024))
            return cli_usage("render", "a sheet's --size is one side from 32 to 1024, got %dx%d", go.width,
                             go.height);
        return render_sheet(sheet, argv + optind, argc - optind, size_given ? go.width : 256, cols, go, seed,
                            quiet);
    }
    if (bits && (png ? bits == 32 : bits == 8))
        return cli_usage("render", "--bits %d does not fit --format %s (PNG: 8 or 16, EXR: 16 or 32)", bits, ext);
    if (!outdir)
        return cli_usage("render", "say where the maps go with -o DIR");
    if (argc - optind > 1)
        return cli_usage("render", "one preset at a time, got %d", argc - optind);
    if (argc - optind == 0 && !ca_file)
        return cli_usage("render", "give a PRESET or --ca FILE");

    SqParams p;
    sq_params_default(&p);
    if (argc - optind == 1 && sq_preset_load(argv[optind], &p, NULL, &err) != SQ_OK)
        return cli_fail(&err);
    if (ca_file) {
        if (sq_ca_load(ca_file, &p.CA_Descriptor, &err) != SQ_OK)
            return cli_fail(&err);
        p.Pattern_Type = SQ_PATTERN_OTHER_SIMPLE;
    }
    if (seed >= 0)
        p.Seed = (int)seed;

    double t0 = now_ms();
    SqTextures tex;
    if (sq_gen_render(&p, &go, &tex, &err) != SQ_OK)
        return cli_fail(&err);
    double t1 = now_ms();
    const int rc = write_maps(outdir, &p, &tex, go, ext, bits, preview, quiet, &err) == SQ_OK ? CLI_OK : cli_fail(&err);
    if (!quiet && rc == CLI_OK)
        printf("%dx%d %s pattern: generated in %.0f ms, written in %.0f ms\n", go.width, go.height,
               sq_pattern_type_name(p.Pattern_Type), t1 - t0, now_ms() - t1);
    sq_gen_textures_free(&tex);
    return rc;
}
