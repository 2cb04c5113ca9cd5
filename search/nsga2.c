/* NSGA-II's fast non-dominated sort and crowding distance, written from Deb, Pratap,
 * Agarwal & Meyarivan, "A fast and elitist multiobjective genetic algorithm: NSGA-II",
 * IEEE TEC 6(2), 2002. */
#include <math.h>
#include <stdlib.h>

#include "squama/search.h"

int sq_pareto_dominates(const double *a, const double *b, int m)
{
    int better = 0;
    for (int k = 0; k < m; k++) {
        if (a[k] > b[k])
            return 0;
        better |= a[k] < b[k];
    }
    return better;
}

int sq_nsga2_rank(const double *obj, int n, int m, int *rank)
{
    if (n <= 0)
        return 0;
    /* S_p as one flat list per point, n_p counts */
    int *count = calloc((size_t)n, sizeof(int));
    int *start = malloc(sizeof(int) * ((size_t)n + 1));
    int *front = malloc(sizeof(int) * (size_t)n), *next = malloc(sizeof(int) * (size_t)n);
    int *dom = malloc(sizeof(int) * (size_t)n * (size_t)n);
    if (!count || !start || !front || !next || !dom) {
        free(count);
        free(start);
        free(front);
        free(next);
        free(dom);
        return -1;
    }
    int nd = 0;
    for (int p = 0; p < n; p++) {
        start[p] = nd;
        for (int q = 0; q < n; q++) {
            if (p == q)
                continue;
            if (sq_pareto_dominates(obj + (size_t)p * m, obj + (size_t)q * m, m))
                dom[nd++] = q;
            else if (sq_pareto_dominates(obj + (size_t)q * m, obj + (size_t)p * m, m))
                count[p]++;
        }
    }
    start[n] = nd;
    int nf = 0, fronts = 0;
    for (int p = 0; p < n; p++)
        if (count[p] == 0) {
            rank[p] = 0;
            front[nf++] = p;
        }
    while (nf > 0) {
        int nn = 0;
        for (int i = 0; i < nf; i++) {
            int p = front[i];
            for (int k = start[p]; k < start[p + 1]; k++) {
                int q = dom[k];
                if (--count[q] == 0) {
                    rank[q] = fronts + 1;
                    next[nn++] = q;
                }
            }
        }
        fronts++;
        int *t = front;
        front = next;
        next = t;
        nf = nn;
    }
    free(count);
    free(start);
    free(front);
    free(next);
    free(dom);
    return fronts;
}

typedef struct Key {
    double v;
    int i;
} Key;

static int cmp_key(const void *a, const void *b)
{
    const Key *x = a, *y = b;
    if (x->v != y->v)
        return x->v < y->v ? -1 : 1;
    return x->i - y->i; /* ties by index: deterministic */
}

void sq_nsga2_crowding(const double *obj, int n, int m, const int *rank, double *crowd)
{
    for (int i = 0; i < n; i++)
        crowd[i] = 0;
    Key *keys = malloc(sizeof(Key) * (size_t)(n > 0 ? n : 1));
    if (!keys)
        return;
    int maxrank = 0;
    for (int i = 0; i < n; i++)
        maxrank = rank[i] > maxrank ? rank[i] : maxrank;
    for (int r = 0; r <= maxrank; r++) {
        for (int k = 0; k < m; k++) {
            int c = 0;
            for (int i = 0; i < n; i++)
                if (rank[i] == r)
                    keys[c++] = (Key){obj[(size_t)i * m + k], i};
            if (c == 0)
                continue;
            qsort(keys, (size_t)c, sizeof(Key), cmp_key);
            crowd[keys[0].i] = INFINITY;
            crowd[keys[c - 1].i] = INFINITY;
            double span = keys[c - 1].v - keys[0].v;
            if (span <= 0)
                continue;
            for (int j = 1; j < c - 1; j++)
                if (isfinite(crowd[keys[j].i]))
                    crowd[keys[j].i] += (keys[j + 1].v - keys[j - 1].v) / span;
        }
    }
    free(keys);
}
