/* Benchmark: reaction-diffusion (generator/rd.c).
 *
 * 1. The plain Turing kernel (Turk's spots, s = 0.05) on a 512 x 512 periodic grid: cell
 *    updates per second per core on one thread and on all threads, medians of 7 runs.
 * 2. A memory-bandwidth probe in the same process (a triad over 3 x 64 MiB, all threads,
 *    best of 5): the kernel moves 20 bytes a cell (reads a, b, beta; writes a, b), so
 *    cups x 20 B against the probe says how far from memory-bound it is.
 * 3. A complex preset rendered end to end at 1024^2 (all four maps in memory), median
 *    of 5 after a cold run; with it, the grid, steps and convergence of each system.
 *
 * usage: bench_rd [PRESET] [--runs N]
 * Ends with: RESULT rd cups_1t=... cups_nt=... bw_gbs=... complex_ms_1024=... */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>


#include "bench_util.h"
#include "gen_internal.h"
#include "squama/generator.h"
#include "squama/preset.h"

/* Triad bandwidth (GB/s, reads + writes) of all threads. */
static double bandwidth_probe(void)
{
    const size_t n = (size_t)16 << 20; /* floats per array: 64 MiB */
    float *a = malloc(n * sizeof(float)), *b = malloc(n * sizeof(float)),
          *c = malloc(n * sizeof(float));
    double best = 1e30;
    if (a && b && c) {
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; i++) {
            a[i] = 0;
            b[i] = (float)(i & 255);
            c[i] = 1.0f;
        }
        for (int rep = 0; rep < 5; rep++) {
            double t0 = now_ms();
#pragma omp parallel for schedule(static)
            for (size_t i = 0; i < n; i++)
                a[i] = b[i] + 0.5f * c[i];
            double t = now_ms() - t0;
            best = t < best ? t : best;
        }
        volatile float sink = a[n / 3];
        (void)sink;
    }
    free(a);
    free(b);
    free(c);
    return best < 1e30 ? 3.0 * (double)n * sizeof(float) / (best * 1e6) : 0;
}

/* Median cell updates per second of the plain Turing kernel on `threads` threads. */
static double kernel_cups(int threads, int runs)
{
    enum { N = 512, STEPS = 200 };
    SqRd rd;
    if (sq__rd_init_spots(&rd, N, N, 0.05, 1.0, 0.1, 1, 1))
        return 0;
    set_threads(threads);
    sq__rd_steps(&rd, 50); /* warm: pages touched, threads started */
    double t[32];
    for (int r = 0; r < runs; r++) {
        double t0 = now_ms();
        sq__rd_steps(&rd, STEPS);
        t[r] = now_ms() - t0;
    }
    sq__rd_free(&rd);
    return (double)N * N * STEPS / (median(t, runs) * 1e-3);
}

int main(int argc, char **argv)
{
    const char *preset = "presets/complex/leopard.json";
    int runs = 7;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
            runs = atoi(argv[++i]);
        else
            preset = argv[i];
    }
    runs = runs < 1 ? 1 : runs > 31 ? 31 : runs;
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    SqParams p;
    SqError err;
    sq_params_default(&p);
    if (sq_preset_load(preset, &p, NULL, &err) != SQ_OK) {
        fprintf(stderr, "bench: %s (%s)\n", err.what, err.where);
        return 1;
    }

    const double bw = bandwidth_probe();
    const double c1 = kernel_cups(1, runs);
    const double cn = kernel_cups(threads, runs);
    set_threads(threads);
    printf("Turing kernel, 512^2 grid, medians of %d runs of 200 steps:\n", runs);
    printf("  1 thread : %6.2f G cell-updates/s\n", c1 * 1e-9);
    printf("  %d threads: %6.2f G cell-updates/s (%.2f per core, %.2fx of 1 thread)\n", threads,
           cn * 1e-9, cn * 1e-9 / threads, cn / c1);
    printf("memory triad bandwidth, %d threads: %.1f GB/s; the kernel at 20 B/cell would need "
           "%.1f GB/s from memory (%.2fx the probe: the grid stays in cache)\n",
           threads, bw, cn * 20e-9, cn * 20e-9 / bw);

    /* the grid and the solver's work for this preset at 1024^2 */
    SqRdResult r;
    double t0 = now_ms();
    if (sq__rd_run(&p, 1024, 1024, &r, &err) != SQ_OK) {
        fprintf(stderr, "bench: %s (%s)\n", err.what, err.where);
        return 1;
    }
    const double sim_ms = now_ms() - t0;
    printf("%s: grid %dx%d, system 1 %ld steps (%s), system 2 %ld steps (%s), simulation "
           "%.1f ms\n",
           preset, r.nu, r.nv, r.steps[0], r.converged[0] ? "converged" : "cap",
           r.steps[1], r.first ? (r.converged[1] ? "converged" : "cap") : "none", sim_ms);
    sq__rd_result_free(&r);

    SqGenOptions o = sq_gen_options_default(1024);
    SqTextures tex = {0};
    double t[32];
    int n = runs < 5 ? runs : 5;
    for (int k = 0; k <= n; k++) { /* the first run is cold */
        t0 = now_ms();
        if (sq_gen_render_into(&p, &o, &tex, &err) != SQ_OK) {
            fprintf(stderr, "bench: %s (%s)\n", err.what, err.where);
            return 1;
        }
        if (k > 0)
            t[k - 1] = now_ms() - t0;
    }
    sq_gen_textures_free(&tex);
    const double ms = median(t, n);
    printf("complex preset at 1024^2, all four maps: %.1f ms (median of %d; target < 250 ms "
           "on 2 cores)\n", ms, n);
    printf("RESULT rd cups_1t=%.3g cups_nt=%.3g cups_nt_total=%.3g bw_gbs=%.1f "
           "complex_ms_1024=%.1f threads=%d\n",
           c1, cn / threads, cn, bw, ms, threads);
    return 0;
}
