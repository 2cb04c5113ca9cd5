/* The genome (parameter table <-> unit cube) and the GP operators on automata. */
#include <math.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "../search/search_internal.h" /* the random draws */
#include "sq_test.h"
#include "squama/generator.h"
#include "squama/preset.h"
#include "squama/search.h"

static const int categories[] = {SQ_PATTERN_NONE, SQ_PATTERN_LONGITUDINAL, SQ_PATTERN_TRANSVERSAL,
                                 SQ_PATTERN_SPOTS, SQ_PATTERN_OTHER_SIMPLE, SQ_PATTERN_COMPLEX};

static double uniform(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * 0x1.0p-53;
}

static void genes_of_each_category(void **state)
{
    (void)state;
    for (size_t c = 0; c < sizeof categories / sizeof categories[0]; c++) {
        SqGenome g;
        assert_int_equal(sq_genome_init(&g, categories[c], NULL), SQ_OK);
        assert_true(g.n >= 6 && g.n <= SQ_GENOME_MAX);
        for (int i = 0; i < g.n; i++) {
            assert_false(g.genes[i].spec->flags & SQ_PF_NOSEARCH);
            assert_true(g.genes[i].hi > g.genes[i].lo);
            for (int j = 0; j < i; j++) /* no gene twice */
                assert_false(g.genes[i].spec == g.genes[j].spec && g.genes[i].comp == g.genes[j].comp);
        }
        assert_int_equal(g.has_ca, categories[c] == SQ_PATTERN_OTHER_SIMPLE);
    }
    SqGenome g;
    SqError err;
    assert_int_equal(sq_genome_init(&g, SQ_PATTERN_COUNT, &err), SQ_ERR_UNSUPPORTED);
}

/* Reaction-diffusion's system and cascade are categorical genes, one level per choice; its
 * grid is no gene (it sets the cost of a candidate). */
static void complex_genes(void **state)
{
    (void)state;
    SqGenome g;
    assert_int_equal(sq_genome_init(&g, SQ_PATTERN_COMPLEX, NULL), SQ_OK);
    int sys = -1, cascade = -1, cells = -1, speed = -1;
    for (int i = 0; i < g.n; i++) {
        const char *n = g.genes[i].spec->name;
        if (strcmp(n, "RD_System") == 0)
            sys = i;
        if (strcmp(n, "RD_Cascade") == 0)
            cascade = i;
        if (strcmp(n, "RD_Cells") == 0)
            cells = i;
        if (strcmp(n, "RD_ReactionSpeed") == 0)
            speed = i;
    }
    assert_true(sys >= 0 && cascade >= 0 && speed >= 0);
    assert_int_equal(cells, -1);
    assert_int_equal(g.genes[sys].kind, SQ_GENE_INT);
    assert_int_equal(g.genes[sys].levels, SQ_RD_SYSTEM_COUNT);
    assert_int_equal(g.genes[cascade].levels, SQ_RD_CASCADE_COUNT);
    assert_int_equal(g.genes[speed].kind, SQ_GENE_LOG);
    /* every level of the cascade decodes to its choice and back */
    double x[SQ_GENOME_MAX], y[SQ_GENOME_MAX];
    for (int i = 0; i < g.n; i++)
        x[i] = 0.5;
    SqParams p;
    sq_params_default(&p);
    for (int k = 0; k < SQ_RD_CASCADE_COUNT; k++) {
        x[cascade] = (k + 0.5) / SQ_RD_CASCADE_COUNT;
        sq_genome_decode(&g, x, &p);
        assert_int_equal(p.RD_Cascade, k);
        assert_int_equal(p.Pattern_Type, SQ_PATTERN_COMPLEX);
        assert_int_equal(sq_params_validate(&p, NULL), SQ_OK);
        sq_genome_encode(&g, &p, y);
        assert_true(fabs(y[cascade] - x[cascade]) < 1e-9);
    }
}

static const SqGene *gene(const SqGenome *g, const char *name, int comp)
{
    for (int i = 0; i < g->n; i++)
        if (strcmp(g->genes[i].spec->name, name) == 0 && g->genes[i].comp == comp)
            return &g->genes[i];
    return NULL;
}

static void kinds_follow_the_table(void **state)
{
    (void)state;
    SqGenome g;
    assert_int_equal(sq_genome_init(&g, SQ_PATTERN_LONGITUDINAL, NULL), SQ_OK);
    const SqGene *e = gene(&g, "Longitudinal_NumberOfStripes", 0);
    assert_non_null(e);
    assert_int_equal(e->kind, SQ_GENE_INT);
    assert_int_equal(e->levels, 10); /* suggested 1..10 */
    e = gene(&g, "ScaleShape_IsKeeled", 0);
    assert_int_equal(e->kind, SQ_GENE_BOOL);
    assert_int_equal(e->levels, 2);
    e = gene(&g, "Scales_XAmount", 0); /* 64 values on a log scale: continuous, rounded */
    assert_int_equal(e->kind, SQ_GENE_LOG);
    assert_int_equal(e->levels, 0);
    assert_non_null(gene(&g, "Background_Color", 2));
    assert_null(gene(&g, "Background_Color", 3)); /* alpha is not searched */
    assert_null(gene(&g, "Seed", 0));
    assert_null(gene(&g, "Spots_Tiling", 0)); /* another category's parameter */
    assert_int_equal(sq_genome_init(&g, SQ_PATTERN_SPOTS, NULL), SQ_OK);
    assert_int_equal(gene(&g, "Spots_Tiling", 0)->kind, SQ_GENE_LOG);
}

/* decode(x) is valid for any x, and encode(decode(x)) decodes to the same parameters. */
static void decode_encode_round_trip(void **state)
{
    (void)state;
    uint64_t s = 42;
    for (size_t c = 0; c < sizeof categories / sizeof categories[0]; c++) {
        SqGenome g;
        assert_int_equal(sq_genome_init(&g, categories[c], NULL), SQ_OK);
        for (int trial = 0; trial < 200; trial++) {
            double x[SQ_GENOME_MAX], y[SQ_GENOME_MAX];
            for (int i = 0; i < g.n; i++)
                x[i] = -0.5 + 2 * uniform(&s);
            SqParams p, q;
            sq_params_default(&p);
            sq_genome_decode(&g, x, &p);
            assert_int_equal(p.Pattern_Type, categories[c]);
            SqError err;
            if (sq_params_validate(&p, &err) != SQ_OK)
                fail_msg("decoded parameters invalid: %s (%s)", err.what, err.where);
            sq_genome_encode(&g, &p, y);
            for (int i = 0; i < g.n; i++)
                assert_true(y[i] >= 0 && y[i] <= 1);
            q = p;
            sq_genome_decode(&g, y, &q);
            for (int i = 0; i < g.n; i++) {
                const SqGene *e = &g.genes[i];
                const void *a = sq_param_cptr(&p, e->spec), *b = sq_param_cptr(&q, e->spec);
                if (e->spec->type == SQ_PT_INT || e->spec->type == SQ_PT_BOOL || e->spec->type == SQ_PT_ENUM)
                    assert_int_equal(*(const int *)a, *(const int *)b);
                else
                    assert_float_equal(((const double *)a)[e->comp], ((const double *)b)[e->comp], 1e-9);
            }
        }
    }
}

/* The layered kind: the base's genes, then the layer's own; decoding makes one layer of the
 * type; a round trip gives the same values, in the layer and not in the base. */
static void layered_genome(void **state)
{
    (void)state;
    SqGenome g, base;
    SqError err;
    assert_int_equal(sq_genome_init_layered(&g, SQ_PATTERN_SPOTS, SQ_PATTERN_LONGITUDINAL, &err), SQ_OK);
    assert_int_equal(sq_genome_init(&base, SQ_PATTERN_SPOTS, &err), SQ_OK);
    assert_int_equal(g.layer_category, SQ_PATTERN_LONGITUDINAL);
    assert_true(g.n > base.n && g.n <= SQ_GENOME_MAX);
    int layer_genes = 0, blend = 0;
    for (int i = 0; i < g.n; i++) {
        assert_int_equal(g.genes[i].layer, i < base.n ? -1 : 0);
        layer_genes += g.genes[i].layer == 0;
        blend += strcmp(g.genes[i].spec->name, "Layer_Blend") == 0;
        for (int j = 0; j < i; j++)
            assert_false(g.genes[i].spec == g.genes[j].spec && g.genes[i].comp == g.genes[j].comp &&
                         g.genes[i].layer == g.genes[j].layer);
    }
    assert_true(layer_genes >= 4);
    assert_int_equal(blend, 1);
    uint64_t s = 7;
    for (int trial = 0; trial < 100; trial++) {
        double x[SQ_GENOME_MAX], y[SQ_GENOME_MAX];
        for (int i = 0; i < g.n; i++)
            x[i] = uniform(&s);
        SqParams p, q;
        sq_params_default(&p);
        sq_genome_decode(&g, x, &p);
        assert_int_equal(p.Pattern_Type, SQ_PATTERN_SPOTS);
        assert_int_equal(p.Pattern_Layers.count, 1);
        assert_int_equal(p.Pattern_Layers.layer[0].spec.Pattern_Type, SQ_PATTERN_LONGITUDINAL);
        assert_int_equal(sq_fit_kind_of(&p), SQ_FIT_LAYERED);
        if (sq_params_validate(&p, &err) != SQ_OK)
            fail_msg("decoded parameters invalid: %s (%s)", err.what, err.where);
        sq_params_default(&q);
        assert_int_equal(sq_genome_of(&base, &p, &err), SQ_OK); /* the genome of the preset */
        assert_int_equal(base.n, g.n);
        sq_genome_encode(&g, &p, y);
        sq_genome_decode(&g, y, &q);
        assert_float_equal(q.Pattern_Layers.layer[0].spec.Longitudinal_StripesWidth,
                           p.Pattern_Layers.layer[0].spec.Longitudinal_StripesWidth, 1e-9);
        assert_float_equal(q.Pattern_Layers.layer[0].Layer_Opacity, p.Pattern_Layers.layer[0].Layer_Opacity, 1e-9);
        assert_int_equal(q.Pattern_Layers.layer[0].Layer_Blend, p.Pattern_Layers.layer[0].Layer_Blend);
        assert_float_equal(q.Spots_Scale, p.Spots_Scale, 1e-9);
        /* the layer's stripes are not the base's */
        assert_float_equal(q.Longitudinal_StripesWidth, 0.3, 1e-12);
    }
    /* decoding a base genome drops the layer */
    SqParams p;
    sq_params_default(&p);
    double x[SQ_GENOME_MAX] = {0};
    sq_genome_decode(&g, x, &p);
    assert_int_equal(sq_genome_init(&base, SQ_PATTERN_SPOTS, &err), SQ_OK);
    sq_genome_decode(&base, x, &p);
    assert_int_equal(p.Pattern_Layers.count, 0);
    /* pairs the fit does not search */
    assert_int_equal(sq_genome_init_layered(&g, SQ_PATTERN_SPOTS, SQ_PATTERN_SPOTS, &err), SQ_ERR_UNSUPPORTED);
    assert_int_equal(sq_genome_init_layered(&g, SQ_PATTERN_NONE, SQ_PATTERN_SPOTS, &err), SQ_ERR_UNSUPPORTED);
    assert_int_equal(sq_genome_init_layered(&g, SQ_PATTERN_SPOTS, SQ_PATTERN_COMPLEX, &err), SQ_ERR_UNSUPPORTED);
    for (int b = 0; b < SQ_PATTERN_COUNT; b++) /* every pair allowed has a genome that fits */
        for (int l = 0; l < SQ_PATTERN_COUNT; l++)
            if (sq_genome_layerable(b, l))
                assert_int_equal(sq_genome_init_layered(&g, b, l, &err), SQ_OK);
}

static void levels_for_cmaes(void **state)
{
    (void)state;
    SqGenome g;
    assert_int_equal(sq_genome_init(&g, SQ_PATTERN_OTHER_SIMPLE, NULL), SQ_OK);
    int levels[SQ_GENOME_MAX];
    sq_genome_levels(&g, levels);
    int discrete = 0;
    for (int i = 0; i < g.n; i++) {
        assert_int_equal(levels[i], g.genes[i].levels);
        discrete += levels[i] > 0;
    }
    assert_true(discrete >= 3); /* IsKeeled, RotatePattern90Degrees, Has_Outline */
}

static void gp_operators_keep_automata_valid(void **state)
{
    (void)state;
    uint64_t r = 7;
    SqCa a, b, c;
    int changed_point = 0, changed_struct = 0, mixed = 0;
    for (int t = 0; t < 3000; t++) {
        sq_gp_ca_random(&r, &a);
        sq_gp_ca_random(&r, &b);
        SqError err;
        if (sq_ca_validate(&a, "random", &err) != SQ_OK)
            fail_msg("%s", err.what);
        c = a;
        sq_gp_ca_point_mutate(&r, &c);
        assert_int_equal(sq_ca_validate(&c, "point", NULL), SQ_OK);
        changed_point += !sq_ca_equal(&a, &c);
        c = a;
        sq_gp_ca_struct_mutate(&r, &c);
        assert_int_equal(sq_ca_validate(&c, "struct", NULL), SQ_OK);
        changed_struct += !sq_ca_equal(&a, &c);
        sq_gp_ca_crossover(&r, &a, &b, &c);
        assert_int_equal(sq_ca_validate(&c, "crossover", NULL), SQ_OK);
        assert_int_equal(c.ncells, a.ncells); /* the row keeps a's length */
        mixed += !sq_ca_equal(&a, &c) && !sq_ca_equal(&b, &c);
        /* long chains stay valid too */
        for (int k = 0; k < 5; k++) {
            sq_gp_ca_struct_mutate(&r, &a);
            sq_gp_ca_point_mutate(&r, &a);
        }
        assert_int_equal(sq_ca_validate(&a, "chain", NULL), SQ_OK);
        uint8_t rows[SQ_CA_MAX_CELLS * 16];
        assert_true(a.ncells * a.epochs <= (int)sizeof rows);
    }
    assert_true(changed_point > 2400);  /* a flip can be undone by repair only rarely */
    assert_true(changed_struct > 1500); /* some structural moves hit a size limit */
    assert_true(mixed > 2000);
}

static void tournament_prefers_low_ranks(void **state)
{
    (void)state;
    enum { n = 50 };
    int rank[n];
    double crowd[n];
    for (int i = 0; i < n; i++) {
        rank[i] = i / 5;
        crowd[i] = i % 5;
    }
    uint64_t r = 3;
    double mean = 0;
    int hist[n] = {0};
    for (int t = 0; t < 10000; t++) {
        int w = sq_gp_tournament(&r, n, 5, rank, crowd);
        assert_true(w >= 0 && w < n);
        hist[w]++;
        mean += rank[w];
    }
    mean /= 10000;
    /* the expected best of 5 uniform ranks on 0..9 is 1.21; the population mean is 4.5 */
    assert_true(mean > 1.1 && mean < 1.32);
    assert_true(hist[4] > hist[0]); /* same rank: the larger crowding distance wins */
    assert_int_equal(hist[n - 5], 0); /* worst rank, smallest crowding: wins only alone */
}

/* A generation's children: the kept share are the best automaton as it is, the others
 * the parents' offspring (valid, mostly changed), the better-ranked parents more often. */
static void children_keep_the_best_automaton(void **state)
{
    (void)state;
    enum { n = 20, l = 4000 };
    SqCa parents[n], best;
    int rank[n];
    double crowd[n];
    uint64_t r = 11;
    for (int i = 0; i < n; i++) {
        sq_gp_ca_random(&r, &parents[i]);
        rank[i] = i < 5 ? 0 : 1;
        crowd[i] = 1;
    }
    sq_gp_ca_random(&r, &best); /* no parent's (nor, but by a fluke, any offspring's) */
    for (int i = 0; i < n; i++)
        assert_false(sq_ca_equal(&best, &parents[i]));
    static SqCa out[l];
    for (int keep = 0; keep <= 1; keep++) {
        sq_gp_ca_children(&r, parents, n, rank, crowd, &best, keep ? 0.7 : 0.0, out, l);
        int kept = 0, unchanged = 0, from_front = 0;
        for (int k = 0; k < l; k++) {
            assert_int_equal(sq_ca_validate(&out[k], "child", NULL), SQ_OK);
            if (sq_ca_equal(&out[k], &best)) {
                kept++;
                continue;
            }
            for (int i = 0; i < n; i++)
                if (sq_ca_equal(&out[k], &parents[i])) {
                    unchanged++;
                    from_front += i < 5;
                    break;
                }
        }
        const int bred = l - kept;
        if (keep)
            assert_true(kept > 0.66 * l && kept < 0.74 * l);
        else
            assert_int_equal(kept, 0);
        /* untouched: no crossover, no mutation (0.4 x 0.5 x 0.8 = 16%), a few more
         * where an operator changed nothing */
        assert_true(unchanged > 0.12 * bred && unchanged < 0.25 * bred);
        /* a tournament of 5 among 5 of rank 0 and 15 of rank 1 picks rank 0 with
         * probability 1 - (15/20)^5 = 0.76 */
        assert_true(from_front > 0.66 * unchanged);
    }
}

/* Random candidates are drawn over narrower ranges than the search moves over, and most
 * lack colour noise, a post-process and an outline; a search's genome keeps its ranges. */
static void draws_are_plausible(void **state)
{
    (void)state;
    SqGenome full, g;
    assert_int_equal(sq_genome_init(&full, SQ_PATTERN_SPOTS, NULL), SQ_OK);
    g = full;
    sq__genome_narrow(&g);
    int tiling = -1;
    for (int i = 0; i < g.n; i++)
        if (strcmp(g.genes[i].spec->name, "Spots_Tiling") == 0)
            tiling = i;
    assert_true(tiling >= 0);
    assert_true(g.genes[tiling].lo == 0.6 && g.genes[tiling].hi == 4);
    assert_true(full.genes[tiling].lo < 0.6 && full.genes[tiling].hi > 4); /* untouched */
    SqRng r;
    sq__rng_seed(&r, 7);
    enum { N = 2000 };
    int noise0 = 0, blur0 = 0, warp0 = 0, outline0 = 0, scale_default = 0;
    for (int k = 0; k < N; k++) {
        SqParams p;
        sq__genome_draw(&r, &g, &p);
        assert_int_equal(sq_params_validate(&p, NULL), SQ_OK);
        assert_int_equal(p.Pattern_Type, SQ_PATTERN_SPOTS);
        assert_true(p.pattern.Spots_Tiling >= 0.6 && p.pattern.Spots_Tiling <= 4);
        assert_true(p.Color_NoiseIntensity <= 0.3);
        noise0 += p.Color_NoiseIntensity == 0;
        blur0 += p.pattern.Pattern_BlurAmount == 0;
        warp0 += p.pattern.Pattern_Warp_Large == 0;
        outline0 += !p.Has_Outline;
        scale_default += p.pattern.Spots_Scale == 0.5;
    }
    printf("  at the default: noise %d, blur %d, warp %d, no outline %d, spot scale %d of %d\n", noise0, blur0,
           warp0, outline0, scale_default, N);
    /* half the time at the default, else drawn (a continuous draw is never exactly 0) */
    assert_true(noise0 > 0.45 * N && noise0 < 0.55 * N);
    assert_true(blur0 > 0.45 * N && blur0 < 0.55 * N);
    assert_true(warp0 > 0.45 * N && warp0 < 0.55 * N);
    assert_true(outline0 > 0.70 * N && outline0 < 0.80 * N); /* and half the draws are false */
    assert_int_equal(scale_default, 0);                       /* the pattern's own genes: always drawn */
}

/* The rows' mean lightness of a strip (n rows). */
static void row_lightness(const SqImage *s, double *out)
{
    for (int y = 0; y < s->height; y++) {
        double t = 0;
        for (int x = 0; x < s->width; x++) {
            float lab[3];
            sq_fit_srgb_to_lab(s->px + ((size_t)y * s->width + x) * s->channels, lab);
            t += lab[0];
        }
        out[y] = t / s->width;
    }
}

/* The best correlation of two row profiles (n rows) over shifts along of up to n / 2. */
static double best_shifted_corr(const double *a, const double *b, int n)
{
    double best = -1;
    for (int d = 0; d < n / 2; d++) {
        double ma = 0, mb = 0, sab = 0, saa = 0, sbb = 0;
        const int m = n - d;
        for (int y = 0; y < m; y++) {
            ma += a[y];
            mb += b[y + d];
        }
        ma /= m;
        mb /= m;
        for (int y = 0; y < m; y++) {
            sab += (a[y] - ma) * (b[y + d] - mb);
            saa += (a[y] - ma) * (a[y] - ma);
            sbb += (b[y + d] - mb) * (b[y + d] - mb);
        }
        best = fmax(best, sab / sqrt(saa * sbb + 1e-12));
    }
    return best;
}

/* Bands of the thesis' Tables 4.1 and 4.2 (four plain bands; a coral snake's triads), seen
 * in a strip at several view scales, are read back: the view scale within 3% (a tile
 * shorter than the fit's shortest view, 0.25, holding more repeats: one band every 0.2
 * read as two a tile at 0.4, each an eighth of it, half a tile apart), and the reading's
 * bands (one repeat a tile),
 * rendered, the same strip as the truth's (their rows' lightness correlated 0.95 or better
 * at the best shift); a flat strip, a striped one and no strip give no repeat. */
static void bands_read_off_their_strip(void **state)
{
    (void)state;
    static const struct {
        const char *preset;
        double view;
        int one_band, repeats; /* one_band: the preset's first band only */
    } cases[] = {{"table_4_1_transversal", 0.6, 0, 1},          {"table_4_1_transversal", 1.3, 0, 1},
                 {"table_4_2_micrurus_altirostris", 0.3, 0, 1}, {"table_4_2_micrurus_altirostris", 0.8, 0, 1},
                 {"table_4_2_micrurus_altirostris", 1.6, 0, 1}, {"table_4_1_transversal", 0.2, 1, 2}};
    SqError err;
    char rel[256], path[1024];
    enum { ROWS = 700 };
    SqImage strip = {0}, again = {0};
    double a[ROWS], b[ROWS];
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        SqParams p;
        snprintf(rel, sizeof rel, "presets/thesis/%s.json", cases[c].preset);
        assert_int_equal(sq_preset_load(src_path(path, sizeof path, rel), &p, NULL, &err), SQ_OK);
        for (int k = 1; k < 4 && cases[c].one_band; k++)
            p.Transversal_BeginEnd[k][0] = p.Transversal_BeginEnd[k][1] = 1;
        SqGenOptions go = sq_gen_options_default(256);
        SqTextures maps = {0};
        assert_int_equal(sq_gen_render_into(&p, &go, &maps, &err), SQ_OK);
        sq_image_free(&strip);
        assert_int_equal(sq_fit_candidate_strip(&maps.basecolor, NULL, NULL, NULL, cases[c].view, 0.5, ROWS, &strip, &err),
                         SQ_OK);
        sq_gen_textures_free(&maps);
        SqBandsReading rd[2];
        const int n = sq_fit_read_bands(&strip, NULL, rd, 2);
        assert_true(n >= 1 && n <= 2);
        row_lightness(&strip, a);
        double best = -1;
        for (int i = 0; i < n; i++) {
            /* the reading as a preset */
            SqParams q = p;
            for (int k = 0; k < 4; k++) {
                q.Transversal_BeginEnd[k][0] = q.Transversal_BeginEnd[k][1] = 1;
                if (k < rd[i].nbands) {
                    memcpy(q.Transversal_BeginEnd[k], rd[i].begin_end[k], sizeof q.Transversal_BeginEnd[k]);
                    for (int j = 0; j < 3; j++)
                        q.Transversal_Color[k][j] = rd[i].colour[k][j];
                    q.Transversal_Color[k][3] = 1;
                }
            }
            for (int j = 0; j < 3; j++)
                q.Background_Color[j] = rd[i].skin[j];
            assert_int_equal(sq_gen_render_into(&q, &go, &maps, &err), SQ_OK);
            sq_image_free(&again);
            assert_int_equal(
                sq_fit_candidate_strip(&maps.basecolor, NULL, NULL, NULL, rd[i].view_scale, 0.5, ROWS, &again, &err),
                SQ_OK);
            sq_gen_textures_free(&maps);
            row_lightness(&again, b);
            const double corr = best_shifted_corr(a, b, ROWS);
            printf("  %s at view %.2f (period %.2f, %.2f..%.2f): %d colours, %d band%s, %d repeat%s a tile at view %.3f (corr %.2f); "
                   "rendered, %.3f like the truth\n",
                   cases[c].preset, cases[c].view, rd[i].period, rd[i].begin_end[0][0], rd[i].begin_end[0][1], rd[i].colours, rd[i].nbands, rd[i].nbands == 1 ? "" : "s",
                   rd[i].repeats, rd[i].repeats == 1 ? "" : "s", rd[i].view_scale, rd[i].corr, corr);
            assert_true(fabs(rd[i].view_scale / rd[i].repeats / cases[c].view - 1) < 0.03);
            assert_int_equal(rd[i].repeats, cases[c].repeats);
            assert_true(rd[i].explained > 0.95); /* every row one colour */
            best = fmax(best, corr);
        }
        if (cases[c].repeats == 1) {
            assert_true(best > 0.95);
        } else { /* rendered at another view, the scales would differ: the bands themselves */
            assert_int_equal(rd[0].nbands, 2);
            const double w0 = fmod(rd[0].begin_end[0][1] - rd[0].begin_end[0][0] + 1, 1),
                         w1 = fmod(rd[0].begin_end[1][1] - rd[0].begin_end[1][0] + 1, 1),
                         apart = fmod(rd[0].begin_end[1][0] - rd[0].begin_end[0][0] + 1, 1);
            assert_true(fabs(w0 - 0.125) < 0.02 && fabs(w1 - 0.125) < 0.02 && fabs(apart - 0.5) < 0.01);
        }
    }
    /* spots in a lattice (its rows unshifted) repeat along the body too, their rows of two
     * colours */
    SqParams p;
    assert_int_equal(sq_preset_load(src_path(path, sizeof path, "presets/thesis/table_4_4_spots.json"), &p, NULL, &err),
                     SQ_OK);
    p.Spots_Offset = 0;
    p.Spots_PositionRandom[0] = p.Spots_PositionRandom[1] = 0;
    SqGenOptions go = sq_gen_options_default(256);
    SqTextures maps = {0};
    assert_int_equal(sq_gen_render_into(&p, &go, &maps, &err), SQ_OK);
    sq_image_free(&strip);
    /* at a view scale whose rows of spots are far enough apart for a tile to hold them
     * (the generator's three bands a tile) */
    assert_int_equal(sq_fit_candidate_strip(&maps.basecolor, NULL, NULL, NULL, 3.0, 0.5, ROWS, &strip, &err), SQ_OK);
    sq_gen_textures_free(&maps);
    SqBandsReading rd[2];
    const int ns = sq_fit_read_bands(&strip, NULL, rd, 2);
    printf("  spots: %d readings, repeat %.2f, %.2f of the variance between rows\n", ns, ns ? rd[0].corr : 0,
           ns ? rd[0].explained : 0);
    assert_true(ns >= 1 && rd[0].corr > 0.5 && rd[0].explained < 0.5);
    assert_int_equal(sq_fit_read_bands(NULL, NULL, rd, 2), 0);
    for (size_t k = 0; k < (size_t)strip.width * strip.height * 3; k++)
        strip.px[k] = 0.4f;
    assert_int_equal(sq_fit_read_bands(&strip, NULL, rd, 2), 0);
    for (int y = 0; y < strip.height; y++) /* stripes along: every row the same */
        for (int x = 0; x < strip.width; x++)
            for (int j = 0; j < 3; j++)
                strip.px[((size_t)y * strip.width + x) * 3 + j] = x % 16 < 6 ? 0.9f : 0.1f;
    assert_int_equal(sq_fit_read_bands(&strip, NULL, rd, 2), 0);
    sq_image_free(&strip);
    sq_image_free(&again);
}

/* Spot lattices of the thesis' Table 4.4 (its spots moved about by 0 to 0.2 of a cell),
 * seen in a strip, are read back: the count round the body exactly, the view scale from
 * the rows' spacing within 8%, best first, not at a multiple of the spacing, the skin's and
 * the spots' colours within 0.1 and 0.15 (small spots blur); a flat strip and no strip give
 * none. */
static void spot_lattices_read_off_their_strip(void **state)
{
    (void)state;
    static const struct {
        double tiling, offset, view, random;
    } cases[] = {{1.3, 0.5, 0.65, 0}, {0.8, 0, 1.0, 0}, {2.0, 0.5, 0.5, 0}, {1.0, 0.5, 0.8, 0.1}, {0.7, 0.5, 2.5, 0},
                 {1.3, 0.5, 0.65, 0.2}, {0.6, 0.25, 1.5, 0}};
    SqParams p;
    SqError err;
    char path[1024];
    assert_int_equal(sq_preset_load(src_path(path, sizeof path, "presets/thesis/table_4_4_spots.json"), &p, NULL, &err),
                     SQ_OK);
    SqImage strip = {0};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        p.Spots_Tiling = cases[c].tiling;
        p.Spots_Offset = cases[c].offset;
        p.Spots_PositionRandom[0] = p.Spots_PositionRandom[1] = cases[c].random;
        SqGenOptions go = sq_gen_options_default(256);
        SqTextures maps = {0};
        assert_int_equal(sq_gen_render_into(&p, &go, &maps, &err), SQ_OK);
        sq_image_free(&strip);
        assert_int_equal(sq_fit_candidate_strip(&maps.basecolor, NULL, NULL, NULL, cases[c].view, 0.5, 700, &strip, &err),
                         SQ_OK);
        sq_gen_textures_free(&maps);
        SqSpotsReading rd[4];
        const int n = sq_fit_read_spots(&strip, NULL, rd, 4);
        assert_true(n >= 1 && n <= 4);
        const int nx = (int)lround(10 * cases[c].tiling), ny = nx + (cases[c].offset > 0 && nx % 2);
        const double view = rd[0].spacing * ny * SQ_FIT_BAND_WIDTH / SQ_FIT_STRIP_W;
        printf("  tiling %.1f offset %.2f view %.2f: %d round at view %.3f (offset %.3f, score %.2f)\n",
               cases[c].tiling, cases[c].offset, cases[c].view, rd[0].across, view, rd[0].offset, rd[0].score);
        assert_int_equal(rd[0].across, nx);
        assert_true(fabs(view / cases[c].view - 1) < 0.08);
        assert_true(rd[0].skew > 0); /* yellow spots on black */
        /* the colours: the spots' own and the skin's, each near the preset's */
        printf("    skin %.2f %.2f %.2f, spots %.2f %.2f %.2f\n", rd[0].skin[0], rd[0].skin[1], rd[0].skin[2],
               rd[0].spot[0], rd[0].spot[1], rd[0].spot[2]);
        assert_true(rd[0].coloured);
        for (int k = 0; k < 3; k++) {
            assert_true(fabs(rd[0].skin[k] - p.Background_Color[k]) < 0.1);
            assert_true(fabs(rd[0].spot[k] - p.Spots_Color[k]) < 0.15); /* small spots blur */
        }
        for (int i = 1; i < n; i++) {
            assert_true(rd[i].score <= rd[i - 1].score);
            assert_true(rd[i].across != rd[0].across);
        }
    }
    SqSpotsReading rd[4];
    for (size_t k = 0; k < (size_t)strip.width * strip.height * 3; k++)
        strip.px[k] = 0.4f;
    assert_int_equal(sq_fit_read_spots(&strip, NULL, rd, 4), 0);
    assert_int_equal(sq_fit_read_spots(NULL, NULL, rd, 4), 0);
    sq_image_free(&strip);
}

/* The thesis' automaton (figure 4.9) seen in a strip at view scale 0.6 is read back: the
 * strip's period gives the view scale, the automata read correlate with the strip, are
 * valid, come best first, and do not depend on the thread count; a strip that does not
 * repeat gives none. */
static void automata_read_off_their_strip(void **state)
{
    (void)state;
    SqParams p;
    SqError err;
    char path[1024];
    assert_int_equal(sq_preset_load(src_path(path, sizeof path, "presets/thesis/figure_4_9_other_simple.json"), &p,
                                    NULL, &err),
                     SQ_OK);
    SqGenOptions go = sq_gen_options_default(256);
    SqTextures maps = {0};
    assert_int_equal(sq_gen_render_into(&p, &go, &maps, &err), SQ_OK);
    const double view = 0.6;
    SqImage strip;
    assert_int_equal(sq_fit_candidate_strip(&maps.basecolor, NULL, NULL, NULL, view, 0.5, 700, &strip, &err),
                     SQ_OK);
    sq_gen_textures_free(&maps);

    SqCaReading rd[4], again[4];
    const int n = sq_fit_read_automata(&strip, NULL, 0.5, 7, rd, 4);
    assert_true(n >= 1 && n <= 4);
    assert_true(fabs(rd[0].view_scale / view - 1) < 0.02);
    assert_true(fabs(rd[0].corr) > 0.85);
    for (int i = 0; i < n; i++) {
        assert_int_equal(sq_ca_validate(&rd[i].ca, "reading", &err), SQ_OK);
        assert_true(rd[i].diameter > 0.05 && rd[i].diameter <= 4);
        assert_true(rd[i].blur >= 0 && rd[i].blur <= 16 && rd[i].contrast >= 0 && rd[i].contrast < 1);
        if (i > 0)
            assert_true(fabs(rd[i].corr) <= fabs(rd[i - 1].corr));
        for (int j = 0; j < i; j++)
            assert_false(sq_ca_equal(&rd[i].ca, &rd[j].ca));
    }
#ifdef _OPENMP
    const int threads = omp_get_max_threads();
    omp_set_num_threads(threads > 1 ? 1 : 2);
#endif
    assert_int_equal(sq_fit_read_automata(&strip, NULL, 0.5, 7, again, 4), n);
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    for (int i = 0; i < n; i++) {
        assert_true(sq_ca_equal(&rd[i].ca, &again[i].ca));
        assert_true(rd[i].corr == again[i].corr && rd[i].diameter == again[i].diameter);
    }

    /* a strip that does not repeat: a gradient along it */
    for (int j = 0; j < strip.height; j++)
        for (int i = 0; i < strip.width; i++)
            for (int c = 0; c < 3; c++)
                strip.px[((size_t)j * strip.width + i) * 3 + c] = (float)j / (float)strip.height;
    assert_int_equal(sq_fit_read_automata(&strip, NULL, 0.5, 7, rd, 4), 0);
    /* nothing to read from */
    assert_int_equal(sq_fit_read_automata(NULL, NULL, 0.5, 7, rd, 4), 0);
    sq_image_free(&strip);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(genes_of_each_category),
        cmocka_unit_test(complex_genes),
        cmocka_unit_test(kinds_follow_the_table),
        cmocka_unit_test(decode_encode_round_trip),
        cmocka_unit_test(layered_genome),
        cmocka_unit_test(levels_for_cmaes),
        cmocka_unit_test(gp_operators_keep_automata_valid),
        cmocka_unit_test(tournament_prefers_low_ranks),
        cmocka_unit_test(children_keep_the_best_automaton),
        cmocka_unit_test(draws_are_plausible),
        cmocka_unit_test(automata_read_off_their_strip),
        cmocka_unit_test(spot_lattices_read_off_their_strip),
        cmocka_unit_test(bands_read_off_their_strip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
