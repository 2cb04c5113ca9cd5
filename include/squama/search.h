/* squama — search: Pareto ranking (NSGA-II), and later CMA-ES, GP operators and the fit
 * driver. All minimise. */
#ifndef SQUAMA_SEARCH_H
#define SQUAMA_SEARCH_H

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

#ifdef __cplusplus
}
#endif

#endif
