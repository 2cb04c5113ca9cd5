/* squama — search: Pareto ranking (NSGA-II), CMA-ES, the genome and its GP operators, and
 * the fit driver. All minimise. */
#ifndef SQUAMA_SEARCH_H
#define SQUAMA_SEARCH_H

#include <stdint.h>

#include "error.h"
#include "fitness.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 1 when a (m objectives) Pareto-dominates b: no worse in all, better in one. */
int sq_pareto_dominates(const double *a, const double *b, int m);

/* Fast non-dominated sorting (Deb, Pratap, Agarwal & Meyarivan 2002): rank[i] is the
 * front of point i (0 = not dominated by any). obj holds n rows of m objectives.
 * Returns the number of fronts, or -1 when out of memory. */
int sq_nsga2_rank(const double *obj, int n, int m, int *rank);

/* Crowding distance of every point within its front (the same paper): the sum over
 * objectives of the normalised gap between its neighbours; the extremes get INFINITY. */
void sq_nsga2_crowding(const double *obj, int n, int m, const int *rank, double *crowd);

/* ---- CMA-ES (cmaes.c) ----
 * Hansen's (mu/mu_w, lambda)-CMA-ES as in "The CMA Evolution Strategy: A Tutorial"
 * (2016), with an ask/tell loop: the caller evaluates (batched, threaded, cached as it
 * likes). Box bounds are kept by reflecting samples into the box. Coordinates with
 * discrete levels get the margin of Hamano et al. (GECCO 2022): the marginal probability
 * of leaving the mean's level is kept at least alpha = 1/(n lambda). IPOP restarts double
 * lambda after a local stop. */

typedef enum SqCmaesStop {
    SQ_CMAES_RUNNING = 0,
    SQ_CMAES_FTARGET,    /* the target value was reached */
    SQ_CMAES_MAXEVALS,   /* the evaluation budget is used up */
    SQ_CMAES_TOLFUN,     /* recent f values all within tolfun (local stop) */
    SQ_CMAES_TOLX,       /* every step below tolx (local stop) */
    SQ_CMAES_CONDITION,  /* covariance condition number above 1e14 (local stop) */
    SQ_CMAES_NOEFFECT    /* steps no longer change the mean (local stop) */
} SqCmaesStop;

typedef struct SqCmaesConfig {
    int n;                     /* dimension, >= 1 */
    int lambda;                /* population; default 4 + floor(3 ln n) */
    double sigma0;             /* initial step size; default 0.3 (of a unit box) */
    const double *x0;          /* initial mean (n values); NULL: the box centre, or 0 */
    const double *lower;       /* box bounds (n values each); NULL: unbounded */
    const double *upper;
    const int *levels;         /* per coordinate: 0 continuous, k >= 2 discrete levels of
                                  equal width over [lower, upper]; NULL: all continuous */
    const double *init_lower;  /* IPOP restarts draw a new mean uniformly in this box; */
    const double *init_upper;  /* NULL: restart from x0 */
    uint64_t seed;
    long max_evals;            /* 0: no limit */
    double ftarget;            /* stop when the best f <= ftarget; default -INFINITY */
    double tolfun;             /* default 1e-12 */
    double tolx;               /* default 1e-11 * sigma0 */
    int restarts;              /* IPOP restarts allowed; default 0 */
} SqCmaesConfig;

typedef struct SqCmaes SqCmaes;

SqCmaesConfig sq_cmaes_config_default(int n);

/* Checks the configuration and allocates the optimizer. */
SqStatus sq_cmaes_new(const SqCmaesConfig *c, SqCmaes **out, SqError *err);
void sq_cmaes_free(SqCmaes *es);

/* The current population size (it doubles on each IPOP restart). */
int sq_cmaes_lambda(const SqCmaes *es);

/* Samples a population: lambda rows of n values, valid until the next call. */
const double *sq_cmaes_ask(SqCmaes *es);

/* Hands back the f values of the last population, in the same order (lower is better;
 * NaN counts as worst), updates the distribution, and restarts (IPOP) after a local stop
 * while restarts remain. */
void sq_cmaes_tell(SqCmaes *es, const double *f);

/* Why the run has ended, or SQ_CMAES_RUNNING. */
SqCmaesStop sq_cmaes_stop(const SqCmaes *es);
const char *sq_cmaes_stop_name(SqCmaesStop s);

/* The best point seen so far and its value. */
const double *sq_cmaes_best(const SqCmaes *es, double *fbest);
const double *sq_cmaes_mean(const SqCmaes *es);
double sq_cmaes_sigma(const SqCmaes *es);
long sq_cmaes_evals(const SqCmaes *es);
int sq_cmaes_restarts(const SqCmaes *es);

/* Moves the mean (e.g. to an elite found by other operators), keeping C and sigma. */
void sq_cmaes_set_mean(SqCmaes *es, const double *m);

/* ---- the genome (genome.c) ----
 * The searchable genes of one pattern category, taken from the parameter table: each a
 * component of a parameter (a colour's r, g, b; a vector's x or y), mapped to [0, 1] over
 * its suggested range (on a log scale where the table says so). Small integers and booleans
 * are discrete genes with equal-width levels (CMA-ES keeps its margin on them); large
 * integers are searched as continuous values and rounded. The pattern category itself is
 * categorical and never a gene: the fit keeps one niche per category. Structures (the
 * cellular automaton) are moved by the GP operators below. */

enum { SQ_GENOME_MAX = 64 };

typedef enum SqGeneKind { SQ_GENE_REAL, SQ_GENE_LOG, SQ_GENE_INT, SQ_GENE_BOOL } SqGeneKind;

typedef struct SqGene {
    const SqParamSpec *spec;
    int comp;        /* component of a vec2 or colour */
    int layer;       /* -1: the base's parameter; l >= 0: pattern layer l's own copy */
    SqGeneKind kind;
    int levels;      /* discrete levels (0: continuous) */
    double lo, hi;   /* the range that [0, 1] maps onto */
} SqGene;

typedef struct SqGenome {
    int category;    /* SqPatternType of the base */
    int layer_category; /* the one pattern layer's type, or -1: no layer */
    int n;
    SqGene genes[SQ_GENOME_MAX];
    int has_ca;      /* the category draws a cellular automaton */
} SqGenome;

/* The genes of a category. SQ_ERR_UNSUPPORTED for a category without genes. */
SqStatus sq_genome_init(SqGenome *g, int category, SqError *err);

/* The layered kind: the genes of `category` and, after them, a pattern layer of type
 * `layer` (its own pattern genes, Layer_Blend and Layer_Opacity). The base is a stripe,
 * band, spot or automaton pattern; the layer stripes, bands or spots of another type
 * (sq_genome_layerable). */
SqStatus sq_genome_init_layered(SqGenome *g, int category, int layer, SqError *err);
int sq_genome_layerable(int base, int layer);

/* The genome that searches a preset as it is (its type, and its one layer if it has one). */
SqStatus sq_genome_of(SqGenome *g, const SqParams *p, SqError *err);

/* Gene values of p in [0, 1] (clamped to the range). */
void sq_genome_encode(const SqGenome *g, const SqParams *p, double *x);

/* Writes the genes x (values outside [0, 1] are clamped) into p; every other field of p is
 * kept. Sets p->Pattern_Type to the genome's category and the layer stack to the genome's:
 * none, or one layer of its type (reset to the defaults when p had another). */
void sq_genome_decode(const SqGenome *g, const double *x, SqParams *p);

/* Per gene, the discrete levels (0 for continuous), as CMA-ES wants them. */
void sq_genome_levels(const SqGenome *g, int *levels);

/* ---- GP operators on cellular automata (gp.c), after Hewgill & Ross 2003 ---- */

/* A random, valid automaton of plausible size for a snake pattern. */
void sq_gp_ca_random(uint64_t *rng, SqCa *out);

/* Point mutation: flips one cell, one rule bit, or nudges a rule's length or the shift. */
void sq_gp_ca_point_mutate(uint64_t *rng, SqCa *ca);

/* Structural mutation: inserts or deletes a rule, grows or shrinks the initial row by
 * repeating or cutting a segment, changes the epochs, or switches the automaton type. */
void sq_gp_ca_struct_mutate(uint64_t *rng, SqCa *ca);

/* Segment crossover: the child is a with a segment of b's initial row (at the same relative
 * place) and a's rule schedule cut at one point and completed by b's. */
void sq_gp_ca_crossover(uint64_t *rng, const SqCa *a, const SqCa *b, SqCa *child);

/* ---- automata read off a photo (ca_read.c) ---- */

typedef struct SqCaReading {
    SqCa ca;
    double diameter, blur, contrast; /* CA_CircleDiameter, Pattern_BlurAmount, Pattern_Contrast */
    double view_scale; /* the strip's period along the body, as a view scale */
    double corr;       /* correlation of the pattern with the folded strip's lightness
                        * (positive: the pattern is lighter than the skin) */
} SqCaReading;

/* Automata whose pattern matches a photo's strip (SQ_FIT_STRIP_W wide, sRGB; valid, its
 * valid pixels, may be NULL), seen in the band centred on u = band_centre: the strip's
 * lightness is folded at the periods along the body where it repeats best, and automata
 * (random, then the best hill-climbed by the GP mutations, with their circle diameter,
 * blur and contrast) are scored by the correlation of their pattern with the fold at the
 * best phase along, either way along, and rotation or reversal of the initial row (the
 * reading's row is turned the way it fitted), less the distance between the
 * distributions of the pattern's coverage and of the fold's values stretched to [0, 1]
 * (so that the pattern is as strong and covers as much as the photo's). Up to max
 * readings, best first; returns how many (0: the strip does not repeat, or bad
 * arguments). Deterministic for a seed, whatever the thread count. */
int sq_fit_read_automata(const SqImage *strip, const SqImage *valid, double band_centre, uint64_t seed,
                         SqCaReading *out, int max);

/* A spot lattice read off a photo's strip (sq_fit_read_spots). */
typedef struct SqSpotsReading {
    int across;     /* spots round the body (Spots_Tiling * 10) */
    double spacing; /* strip rows between rows of spots */
    double offset;  /* every other row's shift, a share of the spacing across (Spots_Offset) */
    double view_scale; /* the view scale the spacing gives: as many rows of spots a tile as
                        * round the body (square maps), even when offset (the generator's
                        * grid) */
    double score;   /* the lattice's autocorrelation less its midpoints' (0 to 2) */
    double skew;    /* the strip's lightness' skewness (< 0: the pattern darker than the skin) */
    int coloured;   /* 1: skin and spot hold the strip's colours */
    double skin[3]; /* sRGB: the mean colour of the strip's middle 40% by lightness (less its
                     * columns' means and its trend along) */
    double spot[3]; /* and of its 2% farthest the skew's way: the spots' cores (the
                     * palette blends small spots with the skin around them) */
} SqSpotsReading;

/* Spot lattices that match a photo's strip (SQ_FIT_STRIP_W wide and at least twice as
 * long, sRGB; valid, its valid pixels, may be NULL). Every lattice the spots pattern makes
 * (5 to 48 spots round the body, rows of spots a quarter row apart, offsets 0 and 1/8 to
 * 7/8 in sixteenths) is scored by the autocorrelation of the strip's lightness
 * (less its columns' means and its trend along) at its short vectors, their longest
 * multiples within reach and the texture tile's length along, less at the points half a
 * vector short of them. Per count round the body the best is read at the
 * smallest spacing it is a whole multiple of (at most 8) scoring within 80% of it (a
 * lattice scores as well at multiples of its spacing); the counts that score better than
 * both neighbours are returned, up to max with a positive score, best first. Returns how
 * many (0: bad arguments, a flat strip, or out of memory). Deterministic; under 0.15 s. */
int sq_fit_read_spots(const SqImage *strip, const SqImage *valid, SqSpotsReading *out, int max);

/* Transversal bands read off a photo's strip (sq_fit_read_bands): one tile's bands, as the
 * thesis' Transversal_BeginEnd and Transversal_Color give them. */
enum { SQ_BANDS_MAX = 3 }; /* the bands a tile the fit searches */
typedef struct SqBandsReading {
    double period;     /* strip rows between repeats of the bands */
    int repeats;       /* repeats a tile (more than one when one would be a tile shorter
                        * than the fit's shortest view) */
    double view_scale; /* of a tile of `repeats` repeats */
    double corr;       /* the rows' colours' autocorrelation at the period (-1 to 1) */
    double explained;  /* the share of the strip's colour variance between its rows (bands:
                        * near 1; spots and automata vary along the rows as well) */
    int colours;       /* the colours the repeat was split into (2 or 3), skin included */
    int nbands;        /* 1 to SQ_BANDS_MAX, in drawing order (a later band over an earlier) */
    double begin_end[SQ_BANDS_MAX][2]; /* shares of the tile along (end < begin: the band wraps) */
    double colour[SQ_BANDS_MAX][3];    /* sRGB */
    double skin[3];    /* sRGB: the commonest colour, between the bands */
} SqBandsReading;

/* Reads the rows' mean colours' repeat along the strip (valid: where the body is, or NULL):
 * the shortest lag whose autocorrelation peaks within 15% of the best, two repeats in the
 * strip at least; the rows folded at it into one repeat's profile, split into two and
 * into three colours (k-means), each a reading when its bands fit a tile and it has as
 * many colours. Any positive peak gives a reading, however weak (noise reads a repeat of
 * 0.05): corr says how far to trust it. Returns how many (up to max; 0: bad arguments, too
 * few valid rows, no positive peak, no bands that fit a tile, or out of memory).
 * Deterministic. */
int sq_fit_read_bands(const SqImage *strip, const SqImage *valid, SqBandsReading *out, int max);

/* Tournament selection (size k, 5 in Hewgill & Ross) among n individuals ranked by NSGA-II:
 * the lowest rank wins, ties go to the larger crowding distance. */
int sq_gp_tournament(uint64_t *rng, int n, int k, const int *rank, const double *crowd);

/* A generation's l child automata: each is `best` as it is with probability keep, else the
 * winner of a tournament among the n parents (ranked by NSGA-II), crossed with another
 * winner 60% of the time, then point-mutated 50% and structurally mutated 20% of the
 * time. */
void sq_gp_ca_children(uint64_t *rng, const SqCa *parents, int n, const int *rank, const double *crowd,
                       const SqCa *best, double keep, SqCa *out, int l);

/* ---- the fit driver (fit.c) ----
 * From a photo's target features to the best preset, in three stages:
 *  1. screen: every kind of skin (the categories the generator can make, and layered
 *     patterns; SQ_FIT_KINDS below), with random genes and the photo's
 *     palette as colours, each candidate scored at every view scale of the grid (the view
 *     scale is estimated on its own here, before anything else moves); the genes are
 *     drawn over plausible ranges, and colour noise, each post-process gene (blur,
 *     contrast, the two warps) and Has_Outline are each at their default (none) half the
 *     time (search/draw.c); automata and spot lattices read off the photo's strip
 *     (sq_fit_read_automata, sq_fit_read_spots) start more, at the view scale read
 *     with them, when the best reading is strong (spots in the colours read with them;
 *     bands are read, sq_fit_read_bands, and only recorded);
 *  2. evolve: every kind as a niche, CMA-ES moving each niche's continuous and
 *     discrete genes plus the view scale (started from the niche's best screened
 *     candidate; a spots niche starts from a lattice read when there is one, and
 *     searches that lattice, its count round the body held, its offset and view scale
 *     near the reading), GP operators moving its automata (most children keeping the niche's
 *     best automaton, so the CMA-ES ranks its genes against one); every generation
 *     ranked by NSGA-II on the five objectives, one seed per generation (common random
 *     numbers); the worst niche is dropped one at a time until `niches` remain, the drops
 *     splitting the stage's budget into equal rounds (successive halving);
 *  3. finish: the finalists (the archive's Pareto front and each niche's best) re-scored
 *     over several seeds at the fine size; the champion picked from the re-scored front
 *     (see SqFitResult.norm; a plain skin within 30% of the best is preferred, as the best
 *     pattern's plain twin when that scores better; else the simplest kind within 5%: plain,
 *     stripes or bands, spots, automata, layered, reaction-diffusion); a stripe, band or
 *     spot champion (an automaton champion: the best of those finalists) given one layer of
 *     another type, searched with the base held (its start the best of the other kinds'
 *     finalists and best screened candidates as a layer, then a CMA-ES on the layer's
 *     genes for half of the evaluations left), the layered skin leading when it beats the
 *     champion by 20% and its layer is visible (sq_fit_layer_visibility: it changes 5% of
 *     the band; by default, and whenever the layered kind is fitted); the champion polished by
 *     nlopt's SBPLX and kept polished only when the re-scored polish is better; a champion
 *     whose pattern nobody can see becomes its plain twin (sq_fit_pattern_visibility)
 *     unless the twin scores more than 5% worse;
 *  4. every kind's best (SqFitResult.kind_best), the champion's included, with its colours
 *     moved toward the photo's palette three ways, kept when it scores better re-scored
 *     (the champion's only when a pattern that showed still shows, and a layer; beyond an
 *     evaluation budget, within a time budget: the layer search and the polish leave it
 *     the time, at the pace the re-scoring's fine renders went); then the pick made again
 *     on those bests (sq_fit_pick_kind; SqFitResult.repicked), a kind whose pattern
 *     nobody can see not taken.
 * Evaluations run in parallel (OpenMP). With an evaluation budget and no time budget the
 * result depends only on the seed: it is the same for any number of threads. A time budget
 * ends the search wherever the clock stops it. */

/* The kinds of skin the fit tells apart, each a niche: the six pattern categories, and
 * "layered", a stripe, band, spot or automaton pattern under one layer of stripes, bands
 * or spots of another type (the pair is drawn at random while screening; the niche
 * searches the pair of its best screened candidate). */
enum { SQ_FIT_LAYERED = SQ_PATTERN_COUNT, SQ_FIT_KINDS };

/* The kinds a fit screens and evolves unless told otherwise: the six categories. Layered
 * skins as a niche only on request (SqFitOptions.categories): in the recovery benchmark
 * they won on photos of stripes, spots and reaction-diffusion, as impostors, more often
 * than anything else. A layer searched over the champion (stage 3 above) runs by default
 * and whenever the layered kind is asked for; it leads only past its two tests. */
#define SQ_FIT_DEFAULT_KINDS ((1u << SQ_PATTERN_COUNT) - 1u)
#define SQ_FIT_ALL_KINDS ((1u << SQ_FIT_KINDS) - 1u)

/* A preset's kind: SQ_FIT_LAYERED when it has pattern layers, else its pattern type. */
int sq_fit_kind_of(const SqParams *p);

/* "none" ... "complex", "layered". */
const char *sq_fit_kind_name(int kind);

/* The kind named exactly `name` (as sq_fit_kind_name spells it), or -1. */
int sq_fit_kind_from_name(const char *name);

typedef enum SqFitMethod {
    SQ_FIT_SQUAMA = 0, /* the three stages above */
    SQ_FIT_RANDOM,     /* baselines: after the same screening, the best category's genome */
    SQ_FIT_ESCH,       /* searched by random sampling or one of nlopt's global optimisers */
    SQ_FIT_CRS2,       /* on one scalar (the pick rule's score) to the end of the budget, */
    SQ_FIT_ISRES       /* less the re-scoring of its best, which follows (no layer or polish) */
} SqFitMethod;

typedef struct SqFitCandidate {
    SqParams params;
    double view_scale;
    double obj[SQ_OBJ_COUNT];
    double score; /* the pick rule: sum of obj[k] / norm[k] */
} SqFitCandidate;

typedef struct SqFitProgress {
    const char *stage;       /* "screen", "evolve", "rescore", "layer", "polish" */
    int generation;
    long evals;
    double elapsed, budget;  /* seconds (budget 0: none) */
    double best_score;       /* the lowest score so far (noisy before re-scoring) */
    double generation_best;  /* the last generation's lowest ("evolve", "layer"); else NAN */
    double best[SQ_OBJ_COUNT]; /* the lowest value of each objective so far */
    int category;            /* the kind (niche) of the last generation */
    const SqFitCandidate *front; /* the archive's Pareto front so far */
    int nfront;
} SqFitProgress;

typedef struct SqFitOptions {
    double budget;           /* seconds of wall time; 0: none (then max_evals must be set) */
    long max_evals;          /* 0: none */
    uint64_t seed;           /* the search's seed (1) */
    int threads;             /* 0: the OpenMP default */
    int coarse_size;         /* render size while screening and evolving (128) */
    int fine_size;           /* render size when re-scoring and polishing (256) */
    int screen;              /* random candidates per category (48) */
    unsigned categories;     /* bit k set: kind k is fitted (SQ_FIT_KINDS bits); 0: the
                                default kinds, SQ_FIT_DEFAULT_KINDS */
    int niches;              /* kinds left evolving after the racing (2) */
    int reseeds;             /* seeds the finalists are re-scored over (4) */
    int front_max;           /* largest front kept (24) */
    double band_centre;      /* texture u facing the camera (0.5) */
    int polish;              /* 1: the nlopt polish (default) */
    SqFitMethod method;
    const SqFitCandidate *seeds; /* extra starting candidates (e.g. a checkpoint's front) */
    const SqImage *strip, *valid; /* the photo's strip and its valid pixels (SqPrepared; may
                                     be NULL): the screening's automata start from the
                                     automata read off it (sq_fit_read_automata) */
    int nseeds;
    const SqParams *starts;  /* presets the screening starts from as well (e.g. the shipped
                                complex ones), each at its best view scale and recoloured
                                toward the photo's palette; those of kinds not fitted skipped */
    int nstarts;
    volatile int *stop;      /* becomes nonzero (e.g. on SIGINT): finish with what is there */
    void (*progress)(const SqFitProgress *p, void *ctx); /* after each generation */
    void *ctx;
} SqFitOptions;

typedef struct SqFitHistory {
    long evals;
    double seconds, best_score, best[SQ_OBJ_COUNT];
    const char *stage;       /* as SqFitProgress's */
    int category;            /* the kind of the generation ("evolve", "layer"); -1: none */
    double generation_best;  /* that generation's lowest score; NAN for the other stages. The
                                best score so far is one lucky pattern instance's: what the
                                search is doing shows in these */
} SqFitHistory;

enum { SQ_FIT_STAGES = 4 }; /* screen, evolve, rescore, polish */

typedef struct SqFitResult {
    SqFitCandidate best;     /* the champion, re-scored at the fine size */
    SqFitCandidate *front;   /* the re-scored Pareto front, by score (best first) */
    int nfront;
    double norm[SQ_OBJ_COUNT]; /* each objective's median over the screening: the score's scale */
    double category_score[SQ_FIT_KINDS]; /* best score per kind, as the first pick compared
                                            them (before the polish); INFINITY: not tried */
    SqFitCandidate kind_best[SQ_FIT_KINDS]; /* each kind's best, re-scored (score INFINITY:
                                               none; a result made by hand must say so):
                                               the champion for its own kind, else the
                                               best finalist or front member (after the
                                               polish) of the kind; no layered skin whose
                                               layer does not show */
    int kind_recoloured[SQ_FIT_KINDS]; /* 1: this kind's best (best.json for its own kind)
                                          had its colours moved toward the photo's palette
                                          after the pick, and scores better so */
    int first_pick;          /* the kind picked from the re-scored front (after the layer
                                search, the polish and the plain twin) */
    int repicked;            /* 1: picked again once every kind's best was recoloured, another
                                kind leads (sq_fit_pick_kind); best.json is its best */
    int starts_used;         /* starting presets screened (of kinds fitted) */
    long recolour_evals;     /* the evaluations that recolouring took, beyond evals */
    double recolour_seconds; /* and the time */
    int niche[SQ_FIT_KINDS]; /* 1: evolved in stage 2 */
    int survivor[SQ_FIT_KINDS]; /* 1: still evolving when stage 2 ended */
    long dropped_at[SQ_FIT_KINDS]; /* evaluations done when the niche was dropped; 0: it was not */
    double judged[SQ_FIT_KINDS]; /* a dropped niche's judged score then (its best and its best
                                    of the round re-scored, the better) */
    SqFitHistory *history;   /* one row per generation */
    int nhistory;
    long evals;
    double seconds[SQ_FIT_STAGES];
    int stopped;             /* 1: the caller stopped the fit early */
    double polish_before, polish_after; /* champion score before and after the polish */
    int polish_kept;
    double recolour_before, recolour_after; /* the champion's score before its recolouring
                                               and its best recoloured way's, re-scored (0:
                                               none scored better where it was tried) */
    double visibility;       /* the fitted pattern's visibility (sq_fit_pattern_visibility) */
    int plain_twin;          /* 1: it was invisible, and the champion is its plain twin */
    int plain_of_pattern;    /* 1: a plain skin led (PLAIN_PARSIMONY), and the plain twin of
                                the best pattern scored better than the plain niche's best:
                                the champion is that twin */
    double twin_score;       /* the plain twin's score when the pattern was invisible, else 0;
                                more than 5% above the champion's, the pattern stays */
    int automata_read;       /* automata read off the photo's strip that started the screening
                                (0: none: no strip given, it does not repeat, or the best
                                reading correlates less than 0.8 with it) */
    double read_view_scale, read_corr; /* the best reading's view scale and correlation (0:
                                          nothing read) */
    int spots_read;          /* screening candidates started from spot lattices read off the
                              * photo's strip (sq_fit_read_spots) */
    int spots_read_across;   /* the best lattice's spots round the body (0: none read) */
    double spots_read_view_scale, spots_read_score; /* its view scale and score */
    int spots_held;          /* 1: the spots niche searched a lattice read (started from it) */
    int spots_recoloured;    /* screening candidates of the best lattices read, recoloured
                              * toward the photo's palette (0: none read) */
    double spots_palette_read, spots_palette_recoloured; /* the lowest palette objective of
                              * the lattices read as read and of those recoloured */
    double bands_read_view_scale, bands_read_corr, bands_read_explained; /* bands read off the
                              * photo's strip (sq_fit_read_bands; none start a candidate): the
                              * best reading's view scale, repeat and share of the colours'
                              * variance between rows (corr 0: nothing read) */
    int layer_searched;      /* 1: a layer was searched over the champion when it is
                                stripes, bands or spots, or over the best of those finalists
                                when it is an automaton (by default, or with the layered kind
                                asked for) */
    long layer_evals;        /* the evaluations it took */
    double layer_seconds;    /* and the time */
    double layer_score;      /* the layered skin's re-scored score */
    double layer_under;      /* the champion's score, which it had to beat */
    int layer_base, layer_kind; /* its base's and its layer's pattern types */
    double layer_visibility; /* when it beat the champion by 20%: how visible its layer is
                                (sq_fit_layer_visibility); else -1, not measured */
    int layer_lead;          /* 1: it beat the champion by 20%, its layer visible, and led
                                (the pick made again may have moved the lead since: repicked) */
    int layer_best_searched; /* 1: kind_best[SQ_FIT_LAYERED] is that layered skin, which leads
                                only by 20%, not the layered niche's best */
} SqFitResult;

SqFitOptions sq_fit_options_default(void);

/* How visible p's pattern is: the share of texels, in the band of the base colour map
 * (size x size) centred on u = band_centre, that differ from the band's dominant colour by
 * more than a CIEDE2000 of 5, less that share for p without its pattern and layers (so
 * colour noise does not count). Below 0.02 nobody sees a pattern: the fit calls the skin
 * plain. dominant (sRGB) receives the band's per-channel median colour. -1 on error. */
double sq_fit_pattern_visibility(const SqParams *p, int size, double band_centre, double dominant[3],
                                 SqError *err);

/* How visible p's layers are over its base: the share of texels, in the band of the base
 * colour map (size x size) centred on u = band_centre, where p and p without its layers
 * differ by more than a CIEDE2000 of 5. The fit's layered skin leads only when at least
 * 0.05 (as a layered preset of squama seed must). -1 on error. */
double sq_fit_layer_visibility(const SqParams *p, int size, double band_centre, SqError *err);

/* The pick rule over each kind's best score (score[k]; INFINITY: none): a plain skin
 * within 30% of the lowest score, else the simplest kind within 5% of it (plain, stripes
 * or bands, spots, automata, layered, reaction-diffusion; of two as simple, the lower
 * score), being the simpler explanation. With layer_lead the layered kind (a layer
 * searched over the champion, not a niche) is not among those: it is picked only when it
 * scores 20% better than their pick. -1: no kind has a score. */
int sq_fit_pick_kind(const double score[SQ_FIT_KINDS], int layer_lead);

/* The kinds a fit offers, in the order it offers them (best.json's kind, then each other
 * kind with a best by that best's score) into order; returns how many. */
int sq_fit_kinds_offered(const SqFitResult *r, int order[SQ_FIT_KINDS]);

/* Fits the generator to a target. On error nothing is allocated in out. */
SqStatus sq_fit_run(const SqFeatures *target, const SqFitOptions *o, SqFitResult *out, SqError *err);

void sq_fit_result_free(SqFitResult *r);

const char *sq_fit_method_name(SqFitMethod m);

/* ---- seeding artists with starting presets (seed.c) ----
 * Diverse, plausible presets of one category, or variations around a preset. Every
 * candidate is rendered at a coarse size (the fit's 128) and seen as the fit sees a
 * candidate: its dorsal band at view scale 1, lit, reduced to features (fitness.h). Two
 * candidates are as far apart as sq_seed_distance says: the fit's five objectives taken
 * both ways round, each divided by its typical value between two random presets, averaged
 * (so two random presets of different categories are about 1 apart, a preset and itself 0).
 *
 * sq_seed_category draws a pool of random candidates of the category's genome (colours from
 * palettes of snake colours rather than the genes' uniform RGB), drops the implausible
 * ones (render errors; a pattern that changes almost none or almost all of the skin
 * against the same skin rendered without it, or changes it too little to be seen) and picks n of the rest by farthest-point
 * sampling in feature space (each pick the candidate farthest from those picked so far;
 * Gonzalez 1985: within a factor 2 of the largest smallest pairwise distance).
 *
 * sq_seed_near moves every gene of the origin's genome by a normal step of standard
 * deviation `distance` in the gene's [0, 1] range (discrete genes change level when the
 * step crosses one; colours move in CIELAB, by distance x 40 in lightness and x 25 in a*
 * and b*, rather than channel by channel), keeping its category, its structure (the automaton, the
 * reaction-diffusion system and cascade, the pattern layers) and every parameter that is
 * not a gene, and picks n of a pool of such variations by farthest-point sampling started
 * from the origin.
 *
 * Candidates render in parallel (OpenMP), each on one thread, and every random choice is
 * made before rendering: the result depends on the seed only, not on the thread count. */

typedef struct SqSeedProgress {
    const char *stage; /* "render", "select" */
    int done, total;
} SqSeedProgress;

typedef struct SqSeedOptions {
    int n;              /* presets wanted, 1..SQ_SEED_MAX */
    int pool;           /* candidates drawn per preset wanted (category: 12, near: 4) */
    uint64_t seed;      /* (1) */
    int threads;        /* 0: the OpenMP default */
    int size;           /* render size of the features (128, as the fit's coarse size) */
    double distance;    /* sq_seed_near: the genes' step, (0, 1] (0.1) */
    void (*progress)(const SqSeedProgress *p, void *ctx);
    void *ctx;
} SqSeedOptions;

enum { SQ_SEED_MAX = 256 };

typedef struct SqSeedCandidate {
    SqParams params;
    SqFeatures features;
    double coverage;    /* share of the texture the pattern changes (against the plain skin) */
    double contrast;    /* how much: the changed pixels' mean CIEDE2000 from the plain skin */
    double layer_coverage, layer_contrast; /* a layered preset's layer: the same against its
                                              base pattern alone (else 0) */
    double nearest;     /* feature distance to the nearest other pick (INFINITY when n = 1) */
    int nearest_index;  /* that pick's index, or -1 */
    double to_origin;   /* sq_seed_near: feature distance to the origin; NAN otherwise */
    int source;         /* which one it was: the draw's number (from 0), or the index of
                           the fit's front member (sq_seed_from_fit; -1: a kind's best not
                           in the front) */
    const SqFitCandidate *fitted; /* sq_seed_from_fit: the fit's candidate it is (in the
                                     fit's front or kind_best: valid while that result
                                     is); else NULL */
} SqSeedCandidate;

typedef struct SqSeedResult {
    SqSeedCandidate *picks; /* n of them, in the order picked */
    int n;
    SqSeedCandidate *pool;  /* the plausible candidates they were picked from */
    int npool;
    int drawn;              /* candidates drawn */
    int failed;             /* could not be rendered */
    int implausible;        /* rendered, but dropped as implausible */
    double min_distance;    /* the smallest feature distance between two picks */
} SqSeedResult;

SqSeedOptions sq_seed_options_default(void);

/* The feature distance between two candidates (symmetric, 0 for equal features). */
double sq_seed_distance(const SqFeatures *a, const SqFeatures *b);

/* The same scale for an objectives vector (SQ_OBJ_COUNT values, e.g. a fit's against its
 * photo): each objective over its typical value, averaged. */
double sq_seed_objective_distance(const double *obj);

/* A preset's features as the seeding sees it: rendered at size x size, its dorsal band
 * at view scale 1 (the maps may be NULL, or reused between calls). */
SqStatus sq_seed_features(const SqParams *p, int size, SqTextures *maps, SqFeatures *f, SqError *err);

/* n diverse, plausible presets of a category, or of the layered kind (SQ_FIT_LAYERED: one
 * layer of stripes, bands or spots over another simple pattern, the pair drawn at random
 * per candidate, as the fit's layered niche). On error nothing is allocated in out. */
SqStatus sq_seed_category(int category, const SqSeedOptions *o, SqSeedResult *out, SqError *err);

/* n variations around origin (valid; any category), each with its distance to it. */
SqStatus sq_seed_near(const SqParams *origin, const SqSeedOptions *o, SqSeedResult *out, SqError *err);

/* The first n distinct presets a fit offers (all of them when it offers fewer): its
 * champion, each other kind's best by score, then the rest of its front; each with its
 * distance to the photo (sq_seed_objective_distance of its objectives, in to_origin) and
 * to the nearest other; coverage and contrast as for sq_seed_category. */
SqStatus sq_seed_from_fit(const SqFitResult *fit, const SqSeedOptions *o, SqSeedResult *out, SqError *err);

void sq_seed_result_free(SqSeedResult *r);

#ifdef __cplusplus
}
#endif

#endif
