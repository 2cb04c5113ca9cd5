/* Benchmark: the cost of reading automata off a photo's strip (sq_fit_read_automata), which
 * every fit pays before its screening, whether the reading is used or not. Two strips as a
 * fit sees them: the thesis' figure 4.9 automaton at view scale 0.6 (the reading is used)
 * and the spots of Table 4.4 (it is not), 700 rows each; on one thread and on all of them.
 * Then reading spot lattices off the spots' strip (sq_fit_read_spots, one thread).
 * Ends with: RESULT read automaton_ms_1t=... automaton_ms=... spots_ms_1t=... spots_ms=...
 * lattice_ms=... threads=N (medians of SQ_BENCH_RUNS runs, default 5). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bench_util.h"
#include "squama/fitness.h"
#include "squama/generator.h"
#include "squama/preset.h"
#include "squama/search.h"

/* The median time of runs readings of strip on threads threads; the best reading in *best. */
static double time_reading(const SqImage *strip, int threads, int runs, SqCaReading *best, int *found)
{
    double t[64];
    set_threads(threads);
    for (int r = 0; r < runs; r++) {
        SqCaReading rd[4];
        const double t0 = now_ms();
        *found = sq_fit_read_automata(strip, NULL, 0.5, 7, rd, 4);
        t[r] = now_ms() - t0;
        if (*found > 0)
            *best = rd[0];
    }
    return median(t, runs);
}

int main(void)
{
    static const char *const names[2] = {"automaton", "spots"};
    static const char *const presets[2] = {"presets/thesis/figure_4_9_other_simple.json",
                                           "presets/thesis/table_4_4_spots.json"};
    int runs = getenv("SQ_BENCH_RUNS") ? atoi(getenv("SQ_BENCH_RUNS")) : 5;
    runs = runs < 1 ? 1 : runs > 64 ? 64 : runs;
#ifdef _OPENMP
    const int all = omp_get_max_threads();
#else
    const int all = 1;
#endif
    const double view = 0.6;
    double ms[2][2], lattice_ms = 0;
    printf("automata read off a %d x 700 strip (medians of %d runs)\n", SQ_FIT_STRIP_W, runs);
    for (int s = 0; s < 2; s++) {
        SqParams p;
        SqError err;
        if (sq_preset_load(presets[s], &p, NULL, &err) != SQ_OK) {
            fprintf(stderr, "bench: %s: %s (%s); run from the source tree\n", presets[s], err.what, err.where);
            return 1;
        }
        SqGenOptions go = sq_gen_options_default(256);
        SqTextures maps = {0};
        SqImage strip;
        if (sq_gen_render_into(&p, &go, &maps, &err) != SQ_OK ||
            sq_fit_candidate_strip(&maps.basecolor, NULL, NULL, NULL, view, 0.5, 700, &strip, &err) != SQ_OK) {
            fprintf(stderr, "bench: %s: %s\n", presets[s], err.what);
            return 1;
        }
        sq_gen_textures_free(&maps);
        SqCaReading best = {0};
        int found = 0;
        ms[s][0] = time_reading(&strip, 1, runs, &best, &found);
        ms[s][1] = time_reading(&strip, all, runs, &best, &found);
        printf("  %-9s  1 thread %8.0f ms   %d threads %8.0f ms   ", names[s], ms[s][0], all, ms[s][1]);
        if (found > 0)
            printf("best reading: correlation %+.3f, view scale %.3f (true %.2f)\n", best.corr, best.view_scale,
                   view);
        else
            printf("no reading\n");
        if (s == 1) { /* the spot lattice */
            double t[64];
            SqSpotsReading rd[3];
            int n = 0;
            for (int r = 0; r < runs; r++) {
                const double t0 = now_ms();
                n = sq_fit_read_spots(&strip, NULL, rd, 3);
                t[r] = now_ms() - t0;
            }
            lattice_ms = median(t, runs);
            printf("  spot lattice  %8.1f ms   ", lattice_ms);
            if (n > 0)
                printf("best: %d round, rows %.2f strip rows apart, offset %.3f (true %ld round)\n", rd[0].across,
                       rd[0].spacing, rd[0].offset, lround(10 * p.Spots_Tiling));
            else
                printf("none\n");
        }
        sq_image_free(&strip);
    }
    printf("RESULT read automaton_ms_1t=%.0f automaton_ms=%.0f spots_ms_1t=%.0f spots_ms=%.0f lattice_ms=%.1f "
           "threads=%d\n",
           ms[0][0], ms[0][1], ms[1][0], ms[1][1], lattice_ms, all);
    return 0;
}
