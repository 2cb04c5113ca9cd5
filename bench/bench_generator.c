/* Benchmark: median time to generate all four maps in memory (no file encoding) at
 * 256^2 .. 4096^2, beside the thesis' Table 5.1 (Substance Designer on a GTX 1070),
 * and the time per pixel against a memory-bandwidth probe run in the same process.
 *
 * usage: bench_generator [PRESET] [--sizes 256,512,...] [--runs N]
 * Renders reuse their output maps (sq_gen_render_into), as a fit or batch does; the
 * first, cold render of each size (fresh memory: allocation and page faults) is shown
 * apart. A last row renders the same preset with Scales_Layout voronoi at 1024^2.
 * Ends with: RESULT generator ms_<size>=... ratio_<size>=... ns_px_<size>=...
 * voronoi_ms_1024=... voronoi_ratio_1024=... gbs=... */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bench_util.h"
#include "squama/generator.h"
#include "squama/preset.h"

/* Median of `n` warm renders at `size` (after one cold one); the median run's stages. */
static int median_ms(const SqParams *p, int size, int n, double *med, SqGenTimings *stages)
{
    double t[32], sorted[32];
    SqGenTimings st[32];
    SqGenOptions o = sq_gen_options_default(size);
    SqTextures tex = {0};
    SqError err;
    n = n < 1 ? 1 : (n > 31 ? 31 : n);
    for (int r = 0; r <= n; r++) {
        o.timings = &st[r > 0 ? r - 1 : 0];
        double t0 = now_ms();
        if (sq_gen_render_into(p, &o, &tex, &err) != SQ_OK) {
            fprintf(stderr, "bench: %s (%s)\n", err.what, err.where);
            sq_gen_textures_free(&tex);
            return -1;
        }
        if (r > 0)
            t[r - 1] = now_ms() - t0;
    }
    sq_gen_textures_free(&tex);
    memcpy(sorted, t, sizeof(double) * (size_t)n);
    qsort(sorted, (size_t)n, sizeof sorted[0], cmp_double);
    *med = sorted[n / 2];
    *stages = st[0];
    for (int r = 0; r < n; r++)
        if (t[r] == *med)
            *stages = st[r];
    return 0;
}

/* Write bandwidth (GB/s) of all threads filling a 256 MiB buffer: the floor of any
 * stage that writes its output once. */
static double bandwidth_probe(void)
{
    const size_t n = (size_t)64 << 20; /* floats */
    float *buf = malloc(n * sizeof(float));
    if (!buf)
        return 0;
    double best = 1e30;
    for (int rep = 0; rep < 5; rep++) {
        double t0 = now_ms();
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; i++)
            buf[i] = (float)(i & 255);
        double t = now_ms() - t0;
        best = t < best ? t : best;
    }
    volatile float sink = buf[n / 3];
    (void)sink;
    free(buf);
    return (double)n * sizeof(float) / (best * 1e6);
}

int main(int argc, char **argv)
{
    const char *preset = NULL;
    int sizes[8] = {256, 512, 1024, 2048, 4096}, nsizes = 5, runs = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--sizes") == 0 && i + 1 < argc) {
            nsizes = 0;
            for (char *t = strtok(argv[++i], ","); t && nsizes < 8; t = strtok(NULL, ","))
                sizes[nsizes++] = atoi(t);
        } else if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) {
            runs = atoi(argv[++i]);
        } else {
            preset = argv[i];
        }
    }
    static const struct { int size; double ms; } thesis[] = {
        {256, 51}, {512, 56.7}, {1024, 82.73}, {2048, 163.06}, {4096, 554.82}};

    SqParams p;
    SqError err;
    sq_params_default(&p);
    if (preset && sq_preset_load(preset, &p, NULL, &err) != SQ_OK) {
        fprintf(stderr, "bench: %s (%s)\n", err.what, err.where);
        return 1;
    }
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    double gbs = bandwidth_probe();
    printf("preset %s, %d threads, write bandwidth %.1f GB/s\n", preset ? preset : "(defaults)",
           threads, gbs);
    printf("%6s %10s %10s %8s %9s %10s %9s\n", "size", "squama ms", "thesis ms", "ratio", "ns/pixel",
           "x bw floor", "cold ms");
    char result[2048];
    int rn = snprintf(result, sizeof result, "RESULT generator");
    for (int s = 0; s < nsizes; s++) {
        int size = sizes[s], n = runs ? runs : (size >= 4096 ? 5 : size >= 2048 ? 7 : 11);
        n = n < 1 ? 1 : (n > 31 ? 31 : n);
        double t[32];
        SqGenTimings stages[32];
        SqGenOptions o = sq_gen_options_default(size);
        SqTextures tex = {0};
        double cold = 0;
        for (int r = 0; r <= n && r < 32; r++) { /* the first run is the cold one */
            o.timings = &stages[r > 0 ? r - 1 : 0];
            double t0 = now_ms();
            if (sq_gen_render_into(&p, &o, &tex, &err) != SQ_OK) {
                fprintf(stderr, "bench: %s (%s)\n", err.what, err.where);
                return 1;
            }
            double dt = now_ms() - t0;
            if (r > 0)
                t[r - 1] = dt;
            else
                cold = dt;
        }
        sq_gen_textures_free(&tex);
        /* the stage times of the median run */
        double sorted[32];
        memcpy(sorted, t, sizeof(double) * (size_t)n);
        qsort(sorted, (size_t)n, sizeof sorted[0], cmp_double);
        double med = sorted[n / 2], ref = 0;
        const SqGenTimings *st = &stages[0];
        for (int r = 0; r < n; r++)
            if (t[r] == med)
                st = &stages[r];
        for (size_t k = 0; k < sizeof thesis / sizeof thesis[0]; k++)
            if (thesis[k].size == size)
                ref = thesis[k].ms;
        double px = (double)size * size, nspx = med * 1e6 / px;
        /* the four maps hold 8 floats a pixel: writing them once at the probe's rate */
        double floor_ms = px * 8 * sizeof(float) / (gbs * 1e6);
        printf("%6d %10.2f %10.2f %8.2f %9.2f %10.1f %9.2f   (scales %.1f, detail %.1f, "
               "normal %.1f, pattern %.1f, colour %.1f)\n",
               size, med, ref, ref > 0 ? ref / med : 0, nspx, med / floor_ms, cold, st->scales,
               st->detail, st->normal, st->pattern, st->color);
        rn += snprintf(result + rn, sizeof result - (size_t)rn, " ms_%d=%.2f", size, med);
        if (ref > 0)
            rn += snprintf(result + rn, sizeof result - (size_t)rn, " ratio_%d=%.2f", size, ref / med);
        rn += snprintf(result + rn, sizeof result - (size_t)rn, " ns_px_%d=%.2f bwx_%d=%.1f cold_%d=%.1f",
                       size, nspx, size, med / floor_ms, size, cold);
    }
    /* the Voronoi layout of the same preset (its relaxation and painting are in "scales") */
    SqParams pv = p;
    pv.Scales_Layout = SQ_LAYOUT_VORONOI;
    double vmed;
    SqGenTimings vst;
    if (median_ms(&pv, 1024, runs ? runs : 11, &vmed, &vst) != 0)
        return 1;
    printf("%6s %10.2f %10.2f %8.2f %9.2f %10s %9s   (scales %.1f, detail %.1f, normal %.1f, "
           "pattern %.1f, colour %.1f)\n",
           "vor1024", vmed, 82.73, 82.73 / vmed, vmed * 1e6 / (1024.0 * 1024.0), "", "", vst.scales,
           vst.detail, vst.normal, vst.pattern, vst.color);
    rn += snprintf(result + rn, sizeof result - (size_t)rn, " voronoi_ms_1024=%.2f voronoi_ratio_1024=%.2f",
                   vmed, 82.73 / vmed);
    printf("%s gbs=%.1f threads=%d\n", result, gbs, threads);
    return 0;
}
