/* Benchmark: the cost of scoring one candidate beyond its render: strip extraction,
 * features and objectives, for a coarse (128^2) render, as a fit evaluates thousands.
 * Ends with: RESULT fitness strip_us=... features_us=... objectives_us=... render_ms=... */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "bench_util.h"
#include "squama/fitness.h"
#include "squama/generator.h"
#include "squama/preset.h"

static double now_us(void)
{
    return now_ms() * 1e3;
}

int main(int argc, char **argv)
{
    SqParams p;
    SqError err;
    sq_params_default(&p);
    if (argc > 1 && sq_preset_load(argv[1], &p, NULL, &err) != SQ_OK) {
        fprintf(stderr, "bench: %s (%s)\n", err.what, err.where);
        return 1;
    }
    enum { MAXRUNS = 2001, LEN = 128 };
    int RUNS = getenv("SQ_BENCH_RUNS") ? atoi(getenv("SQ_BENCH_RUNS")) : 51;
    RUNS = RUNS < 3 ? 3 : (RUNS > MAXRUNS ? MAXRUNS : RUNS);
    SqGenOptions o = sq_gen_options_default(128);
    o.threads = 1; /* a fit scores candidates in parallel, one thread each */
    SqTextures t = {0};
    SqFeatures target, cand;
    static double tr[MAXRUNS], ts[MAXRUNS], tf[MAXRUNS], to[MAXRUNS];
    double obj[SQ_OBJ_COUNT];
    for (int r = 0; r < RUNS; r++) {
        double t0 = now_us();
        if (sq_gen_render_into(&p, &o, &t, &err) != SQ_OK) {
            fprintf(stderr, "bench: %s\n", err.what);
            return 1;
        }
        double t1 = now_us();
        SqImage strip;
        if (sq_fit_candidate_strip(&t.basecolor, &t.normal, &t.roughness, NULL, 1.0, 0.5, LEN, &strip, &err) != SQ_OK)
            return 1;
        double t2 = now_us();
        if (sq_fit_features(&strip, NULL, r == 0 ? &target : &cand, &err) != SQ_OK)
            return 1;
        double t3 = now_us();
        sq_fit_objectives(&target, r == 0 ? &target : &cand, obj);
        double t4 = now_us();
        sq_image_free(&strip);
        tr[r] = (t1 - t0) / 1e3;
        ts[r] = t2 - t1;
        tf[r] = t3 - t2;
        to[r] = t4 - t3;
    }
    const double render = median(tr, RUNS), st = median(ts, RUNS), fe = median(tf, RUNS), ob = median(to, RUNS);
    printf("one candidate, 128^2 render on 1 thread, %dx%d strip (medians of %d)\n", SQ_FIT_STRIP_W, LEN, RUNS);
    printf("  render      %8.3f ms\n  strip       %8.1f us\n  features    %8.1f us\n  objectives  %8.1f us\n",
           render, st, fe, ob);
    printf("  beyond the render: %.1f us = %.1f%% of it\n", st + fe + ob, 100 * (st + fe + ob) / (render * 1e3));
    printf("RESULT fitness render_ms=%.3f strip_us=%.1f features_us=%.1f objectives_us=%.1f "
           "beyond_render_us=%.1f\n",
           render, st, fe, ob, st + fe + ob);
    sq_gen_textures_free(&t);
    return 0;
}
