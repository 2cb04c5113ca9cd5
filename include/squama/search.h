/* squama — search: Pareto ranking (NSGA-II), CMA-ES, the genome and its GP operators, and
 * the fit driver. All minimise. */
#ifndef SQUAMA_SEARCH_H
#define SQUAMA_SEARCH_H

#include <stdint.h>

#include "error.h"

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

#ifdef __cplusplus
}
#endif

#endif
