/* CMA-ES, written from Hansen, "The CMA Evolution Strategy: A Tutorial" (arXiv:1604.00772),
 * with the stop tests of Hansen's c-cmaes, IPOP restarts (Auger & Hansen 2005) and the
 * integer margin of Hamano, Saito, Nomura & Shirakawa, "CMA-ES with Margin" (GECCO 2022).
 * The eigendecomposition is GSL's. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_eigen.h>

#include "rng.h"
#include "squama/search.h"

struct SqCmaes {
    SqCmaesConfig c;
    int n, lambda, lambda_max, mu, restarts;
    double *lower, *upper, *init_lower, *init_upper, *x0; /* owned copies */
    int *levels;
    double *w, mueff, cc, cs, c1, cmu, damps, alpha;
    double sigma, *m, *ps, *pc, *C, *B, *D, *A; /* C, B: n x n row-major; A: margin */
    double *y, *x, *tmp, *fsorted;             /* y: lambda x n steps; x: lambda x n points */
    int *order;
    long evals, gen, eigen_gen;
    double *hist;                              /* best f of recent generations */
    int hist_len, hist_n, hist_pos;
    double *best, fbest;
    SqCmaesStop stop;
    SqRng rng;
    gsl_eigen_symmv_workspace *ws;
    gsl_matrix *gm, *gv;
    gsl_vector *gd;
};

SqCmaesConfig sq_cmaes_config_default(int n)
{
    SqCmaesConfig c = {0};
    c.n = n;
    c.sigma0 = 0.3;
    c.ftarget = -INFINITY;
    c.tolfun = 1e-12;
    c.tolx = 0; /* 1e-11 * sigma0 */
    return c;
}

static double *dup_vec(const double *v, int n, int *fail)
{
    if (!v)
        return NULL;
    double *d = malloc(sizeof(double) * (size_t)n);
    if (!d) {
        *fail = 1;
        return NULL;
    }
    memcpy(d, v, sizeof(double) * (size_t)n);
    return d;
}

/* Strategy parameters for the current lambda (tutorial, Table 1). */
static void set_lambda(SqCmaes *es, int lambda)
{
    int n = es->n;
    es->lambda = lambda;
    es->mu = lambda / 2;
    double sw = 0, sw2 = 0;
    for (int i = 0; i < es->mu; i++) {
        es->w[i] = log((lambda + 1) / 2.0) - log(i + 1.0);
        sw += es->w[i];
    }
    for (int i = 0; i < es->mu; i++) {
        es->w[i] /= sw;
        sw2 += es->w[i] * es->w[i];
    }
    es->mueff = 1 / sw2;
    double me = es->mueff;
    es->cc = (4 + me / n) / (n + 4 + 2 * me / n);
    es->cs = (me + 2) / (n + me + 5);
    es->c1 = 2 / ((n + 1.3) * (n + 1.3) + me);
    es->cmu = fmin(1 - es->c1, 2 * (me - 2 + 1 / me) / ((n + 2) * (n + 2) + me));
    es->damps = 1 + 2 * fmax(0, sqrt((me - 1) / (n + 1)) - 1) + es->cs;
    es->alpha = 1.0 / (n * lambda);
    es->hist_len = 10 + (int)ceil(30.0 * n / lambda);
}

static void reset_state(SqCmaes *es, int redraw)
{
    int n = es->n;
    for (int i = 0; i < n; i++) {
        double m = es->x0[i];
        if (redraw && es->init_lower)
            m = es->init_lower[i] + (es->init_upper[i] - es->init_lower[i]) * sq__rng_uniform(&es->rng);
        es->m[i] = m;
        es->ps[i] = es->pc[i] = 0;
        es->D[i] = 1;
        es->A[i] = 1;
        for (int j = 0; j < n; j++)
            es->C[i * n + j] = es->B[i * n + j] = i == j;
    }
    es->sigma = es->c.sigma0;
    es->gen = es->eigen_gen = 0;
    es->hist_n = es->hist_pos = 0;
}

void sq_cmaes_free(SqCmaes *es)
{
    if (!es)
        return;
    free(es->lower);
    free(es->upper);
    free(es->init_lower);
    free(es->init_upper);
    free(es->x0);
    free(es->levels);
    free(es->w);
    free(es->m);
    free(es->ps);
    free(es->pc);
    free(es->C);
    free(es->B);
    free(es->D);
    free(es->A);
    free(es->y);
    free(es->x);
    free(es->tmp);
    free(es->fsorted);
    free(es->order);
    free(es->hist);
    free(es->best);
    if (es->ws)
        gsl_eigen_symmv_free(es->ws);
    if (es->gm)
        gsl_matrix_free(es->gm);
    if (es->gv)
        gsl_matrix_free(es->gv);
    if (es->gd)
        gsl_vector_free(es->gd);
    free(es);
}

/* Room for populations up to this size; IPOP stops doubling beyond it. */
static int max_lambda(const SqCmaesConfig *c, int lambda0)
{
    int l = lambda0;
    for (int r = 0; r < c->restarts && l < (1 << 14); r++)
        l *= 2;
    return l;
}

SqStatus sq_cmaes_new(const SqCmaesConfig *c, SqCmaes **out, SqError *err)
{
    *out = NULL;
    int n = c->n;
    if (n < 1 || n > 10000)
        return sq_error_set(err, SQ_ERR_INVALID, "cmaes", "dimension %d outside 1..10000", n);
    if (!(c->sigma0 > 0) || !isfinite(c->sigma0))
        return sq_error_set(err, SQ_ERR_INVALID, "cmaes", "sigma0 must be positive");
    if ((c->lower == NULL) != (c->upper == NULL))
        return sq_error_set(err, SQ_ERR_INVALID, "cmaes", "give both bounds or neither");
    if ((c->init_lower == NULL) != (c->init_upper == NULL))
        return sq_error_set(err, SQ_ERR_INVALID, "cmaes", "give both initial bounds or neither");
    if (c->restarts < 0 || c->lambda < 0 || c->lambda == 1)
        return sq_error_set(err, SQ_ERR_INVALID, "cmaes", "lambda must be >= 2, restarts >= 0");
    for (int i = 0; i < n; i++) {
        if (c->lower && !(c->lower[i] < c->upper[i]))
            return sq_error_set(err, SQ_ERR_INVALID, "cmaes", "empty bound box in coordinate %d", i);
        if (c->levels && c->levels[i] != 0 && (c->levels[i] < 2 || !c->lower))
            return sq_error_set(err, SQ_ERR_INVALID, "cmaes",
                                "coordinate %d: discrete levels need bounds and at least 2 levels", i);
    }
    SqCmaes *es = calloc(1, sizeof *es);
    if (!es)
        return sq_error_set(err, SQ_ERR_NOMEM, "cmaes", "out of memory");
    es->c = *c;
    es->n = n;
    int lambda0 = c->lambda ? c->lambda : 4 + (int)floor(3 * log((double)n));
    int lmax = max_lambda(c, lambda0);
    es->lambda_max = lmax;
    size_t nn = (size_t)n;
    int fail = 0;
    es->lower = dup_vec(c->lower, n, &fail);
    es->upper = dup_vec(c->upper, n, &fail);
    es->init_lower = dup_vec(c->init_lower, n, &fail);
    es->init_upper = dup_vec(c->init_upper, n, &fail);
    es->x0 = calloc(nn, sizeof(double));
    if (es->x0) {
        for (int i = 0; i < n; i++)
            es->x0[i] = c->x0 ? c->x0[i] : c->lower ? 0.5 * (c->lower[i] + c->upper[i]) : 0;
    }
    es->levels = calloc(nn, sizeof(int));
    if (es->levels && c->levels)
        memcpy(es->levels, c->levels, sizeof(int) * nn);
    es->w = malloc(sizeof(double) * (size_t)lmax);
    es->m = malloc(sizeof(double) * nn);
    es->ps = malloc(sizeof(double) * nn);
    es->pc = malloc(sizeof(double) * nn);
    es->C = malloc(sizeof(double) * nn * nn);
    es->B = malloc(sizeof(double) * nn * nn);
    es->D = malloc(sizeof(double) * nn);
    es->A = malloc(sizeof(double) * nn);
    es->y = malloc(sizeof(double) * nn * (size_t)lmax);
    es->x = malloc(sizeof(double) * nn * (size_t)lmax);
    es->tmp = malloc(sizeof(double) * nn * 2);
    es->fsorted = malloc(sizeof(double) * (size_t)lmax);
    es->order = malloc(sizeof(int) * (size_t)lmax);
    es->hist = malloc(sizeof(double) * (size_t)(10 + 30 * n / 2 + 1));
    es->best = malloc(sizeof(double) * nn);
    es->ws = gsl_eigen_symmv_alloc(nn);
    es->gm = gsl_matrix_alloc(nn, nn);
    es->gv = gsl_matrix_alloc(nn, nn);
    es->gd = gsl_vector_alloc(nn);
    if (fail || !es->x0 || !es->levels || !es->w || !es->m || !es->ps || !es->pc || !es->C ||
        !es->B || !es->D || !es->A || !es->y || !es->x || !es->tmp || !es->fsorted ||
        !es->order || !es->hist || !es->best || !es->ws || !es->gm || !es->gv || !es->gd) {
        sq_cmaes_free(es);
        return sq_error_set(err, SQ_ERR_NOMEM, "cmaes", "out of memory");
    }
    if (es->c.tolx <= 0)
        es->c.tolx = 1e-11 * c->sigma0;
    if (es->c.tolfun <= 0)
        es->c.tolfun = 1e-12;
    sq__rng_seed(&es->rng, c->seed);
    set_lambda(es, lambda0);
    reset_state(es, 0);
    es->fbest = INFINITY;
    memcpy(es->best, es->x0, sizeof(double) * nn);
    *out = es;
    return SQ_OK;
}

int sq_cmaes_lambda(const SqCmaes *es) { return es->lambda; }
SqCmaesStop sq_cmaes_stop(const SqCmaes *es) { return es->stop; }
const double *sq_cmaes_mean(const SqCmaes *es) { return es->m; }
double sq_cmaes_sigma(const SqCmaes *es) { return es->sigma; }
long sq_cmaes_evals(const SqCmaes *es) { return es->evals; }
int sq_cmaes_restarts(const SqCmaes *es) { return es->restarts; }

const double *sq_cmaes_best(const SqCmaes *es, double *fbest)
{
    if (fbest)
        *fbest = es->fbest;
    return es->best;
}

void sq_cmaes_set_mean(SqCmaes *es, const double *m)
{
    memcpy(es->m, m, sizeof(double) * (size_t)es->n);
}

const char *sq_cmaes_stop_name(SqCmaesStop s)
{
    static const char *const names[] = {"running", "ftarget", "maxevals", "tolfun",
                                        "tolx", "condition", "noeffect"};
    return (unsigned)s < sizeof names / sizeof names[0] ? names[s] : "?";
}

/* Reflects v into [lo, hi] (repeatedly, as a mirror). */
static double reflect(double v, double lo, double hi)
{
    double w = hi - lo;
    double t = fmod(v - lo, 2 * w);
    if (t < 0)
        t += 2 * w;
    return lo + (t <= w ? t : 2 * w - t);
}

const double *sq_cmaes_ask(SqCmaes *es)
{
    int n = es->n;
    double *z = es->tmp;
    for (int k = 0; k < es->lambda; k++) {
        double *y = es->y + (size_t)k * n, *x = es->x + (size_t)k * n;
        for (int i = 0; i < n; i++)
            z[i] = es->D[i] * sq__rng_normal(&es->rng);
        for (int i = 0; i < n; i++) {
            double s = 0;
            for (int j = 0; j < n; j++)
                s += es->B[i * n + j] * z[j];
            y[i] = s;
            x[i] = es->m[i] + es->sigma * es->A[i] * s;
        }
        if (es->lower) {
            for (int i = 0; i < n; i++) {
                double r = reflect(x[i], es->lower[i], es->upper[i]);
                if (r != x[i]) { /* the step that was actually taken */
                    x[i] = r;
                    y[i] = (r - es->m[i]) / (es->sigma * es->A[i]);
                }
            }
        }
    }
    return es->x;
}

static void decompose(SqCmaes *es)
{
    int n = es->n;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) /* enforce symmetry */
            gsl_matrix_set(es->gm, (size_t)i, (size_t)j, 0.5 * (es->C[i * n + j] + es->C[j * n + i]));
    gsl_eigen_symmv(es->gm, es->gd, es->gv, es->ws);
    for (int i = 0; i < n; i++) {
        double ev = gsl_vector_get(es->gd, (size_t)i);
        es->D[i] = sqrt(fmax(ev, 1e-300));
        for (int j = 0; j < n; j++)
            es->B[j * n + i] = gsl_matrix_get(es->gv, (size_t)j, (size_t)i);
    }
    es->eigen_gen = es->gen;
}

/* The margin (Hamano et al. 2022, integer case). For each discrete coordinate, with the
 * mean in level [a, b) and marginal deviation s = sigma A sqrt(C_ii): the probabilities of
 * sampling below a and above b are each kept at least alpha/2 (an end level, with one
 * neighbour, keeps alpha on its one side). Raising a small tail takes the excess
 * proportionally from all three parts, so a tail that is already large (the mean about to
 * move to the next level) stays large; the mean and A are then solved for the new tails. */
static void apply_margin(SqCmaes *es)
{
    int n = es->n;
    double al = es->alpha, zal = gsl_cdf_ugaussian_Qinv(al);
    for (int i = 0; i < n; i++) {
        int k = es->levels[i];
        if (!k)
            continue;
        double lo = es->lower[i], wid = (es->upper[i] - lo) / k;
        int cell = (int)floor((es->m[i] - lo) / wid);
        cell = cell < 0 ? 0 : cell >= k ? k - 1 : cell;
        double a = lo + cell * wid, b = a + wid, m = es->m[i];
        double base = es->sigma * sqrt(es->C[i * n + i]), s = base * es->A[i];
        if (!(base > 0))
            continue;
        if (cell == 0 || cell == k - 1) {
            /* one neighbour: put the mean where that tail holds alpha */
            double tail = cell == 0 ? gsl_cdf_ugaussian_Q((b - m) / s) : gsl_cdf_ugaussian_P((a - m) / s);
            if (tail < al)
                es->m[i] = cell == 0 ? b - zal * s : a + zal * s;
            continue;
        }
        double pl = gsl_cdf_ugaussian_P((a - m) / s), pu = gsl_cdf_ugaussian_Q((b - m) / s);
        if (fmin(pl, pu) >= al / 2)
            continue;
        double pm = fmax(0.0, 1 - pl - pu);
        pl = fmax(pl, al / 2);
        pu = fmax(pu, al / 2);
        double excess = pl + pm + pu - 1, share = pl + pm + pu - 1.5 * al;
        double npl = pl - excess * (pl - al / 2) / share, npu = pu - excess * (pu - al / 2) / share;
        npl = fmin(fmax(npl, 1e-10), 0.5 - 1e-10);
        npu = fmin(fmax(npu, 1e-10), 0.5 - 1e-10);
        double ql = gsl_cdf_ugaussian_Qinv(npl), qu = gsl_cdf_ugaussian_Qinv(npu);
        es->A[i] = (b - a) / ((ql + qu) * base);
        es->m[i] = (a * qu + b * ql) / (ql + qu);
    }
}

/* -1, 0, 1 as f[a] is better, equal, worse than f[b]; NaN is worst */
static int cmp_f(const double *f, int a, int b)
{
    double x = f[a], y = f[b];
    if (isnan(x))
        return isnan(y) ? 0 : 1;
    if (isnan(y))
        return -1;
    return (x > y) - (x < y);
}

/* A stable insertion sort of indices by f (lambda is small). */
static void sort_order(int *order, int l, const double *f)
{
    for (int i = 0; i < l; i++)
        order[i] = i;
    for (int i = 1; i < l; i++) {
        int v = order[i], j = i;
        while (j > 0 && cmp_f(f, order[j - 1], v) > 0) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = v;
    }
}

static SqCmaesStop local_stop(SqCmaes *es, const double *f)
{
    int n = es->n;
    /* TolFun: the best values of recent generations and this one all within tolfun */
    if (es->hist_n >= 1) {
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < es->hist_n; i++) {
            lo = fmin(lo, es->hist[i]);
            hi = fmax(hi, es->hist[i]);
        }
        for (int k = 0; k < es->lambda; k++)
            if (!isnan(f[k])) {
                lo = fmin(lo, f[k]);
                hi = fmax(hi, f[k]);
            }
        if (hi - lo < es->c.tolfun)
            return SQ_CMAES_TOLFUN;
    }
    int tolx = 1;
    for (int i = 0; i < n && tolx; i++)
        tolx = es->sigma * sqrt(es->C[i * n + i]) < es->c.tolx && es->sigma * fabs(es->pc[i]) < es->c.tolx;
    if (tolx)
        return SQ_CMAES_TOLX;
    double dmax = 0, dmin = INFINITY;
    for (int i = 0; i < n; i++) {
        dmax = fmax(dmax, es->D[i]);
        dmin = fmin(dmin, es->D[i]);
    }
    if (dmax > 1e7 * dmin)
        return SQ_CMAES_CONDITION;
    int axis = (int)(es->gen % n), noeffect = 1;
    for (int i = 0; i < n && noeffect; i++)
        noeffect = es->m[i] == es->m[i] + 0.1 * es->sigma * es->D[axis] * es->B[i * n + axis];
    if (noeffect)
        return SQ_CMAES_NOEFFECT;
    for (int i = 0; i < n; i++)
        if (es->m[i] == es->m[i] + 0.2 * es->sigma * sqrt(es->C[i * n + i]))
            return SQ_CMAES_NOEFFECT;
    return SQ_CMAES_RUNNING;
}

void sq_cmaes_tell(SqCmaes *es, const double *f)
{
    if (es->stop != SQ_CMAES_RUNNING)
        return;
    int n = es->n, l = es->lambda;
    es->evals += l;
    es->gen++;
    sort_order(es->order, l, f);
    int b = es->order[0];
    if (f[b] < es->fbest) {
        es->fbest = f[b];
        memcpy(es->best, es->x + (size_t)b * n, sizeof(double) * (size_t)n);
    }
    /* recombination: ymean in C-space, the mean moves by sigma A ymean */
    double *ymean = es->tmp, *t = es->tmp + n;
    for (int i = 0; i < n; i++) {
        double s = 0;
        for (int k = 0; k < es->mu; k++)
            s += es->w[k] * es->y[(size_t)es->order[k] * n + i];
        ymean[i] = s;
        es->m[i] += es->sigma * es->A[i] * s;
    }
    /* C^(-1/2) ymean = B D^-1 B^T ymean */
    for (int j = 0; j < n; j++) {
        double s = 0;
        for (int i = 0; i < n; i++)
            s += es->B[i * n + j] * ymean[i];
        t[j] = s / es->D[j];
    }
    double psn = 0, cs = es->cs, cc = es->cc, me = es->mueff;
    for (int i = 0; i < n; i++) {
        double s = 0;
        for (int j = 0; j < n; j++)
            s += es->B[i * n + j] * t[j];
        es->ps[i] = (1 - cs) * es->ps[i] + sqrt(cs * (2 - cs) * me) * s;
        psn += es->ps[i] * es->ps[i];
    }
    psn = sqrt(psn);
    double chin = sqrt((double)n) * (1 - 1.0 / (4 * n) + 1.0 / (21.0 * n * n));
    int hsig = psn / sqrt(1 - pow(1 - cs, 2.0 * es->gen)) / chin < 1.4 + 2.0 / (n + 1);
    for (int i = 0; i < n; i++)
        es->pc[i] = (1 - cc) * es->pc[i] + hsig * sqrt(cc * (2 - cc) * me) * ymean[i];
    double c1 = es->c1, cmu = es->cmu;
    double keep = 1 - c1 - cmu + (1 - hsig) * c1 * cc * (2 - cc);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j <= i; j++) {
            double r = 0;
            for (int k = 0; k < es->mu; k++) {
                const double *y = es->y + (size_t)es->order[k] * n;
                r += es->w[k] * y[i] * y[j];
            }
            double v = keep * es->C[i * n + j] + c1 * es->pc[i] * es->pc[j] + cmu * r;
            es->C[i * n + j] = es->C[j * n + i] = v;
        }
    }
    es->sigma *= exp(cs / es->damps * (psn / chin - 1));
    if (es->gen - es->eigen_gen > l / (c1 + cmu) / n / 10)
        decompose(es);
    apply_margin(es);

    /* stop tests */
    if (es->fbest <= es->c.ftarget) {
        es->stop = SQ_CMAES_FTARGET;
        return;
    }
    if (es->c.max_evals > 0 && es->evals >= es->c.max_evals) {
        es->stop = SQ_CMAES_MAXEVALS;
        return;
    }
    SqCmaesStop s = local_stop(es, f);
    es->hist[es->hist_pos] = f[b];
    es->hist_pos = (es->hist_pos + 1) % es->hist_len;
    if (es->hist_n < es->hist_len)
        es->hist_n++;
    if (s == SQ_CMAES_RUNNING)
        return;
    if (es->restarts < es->c.restarts && es->lambda * 2 <= es->lambda_max) {
        es->restarts++;
        set_lambda(es, es->lambda * 2);
        reset_state(es, 1);
        return;
    }
    es->stop = s;
}
