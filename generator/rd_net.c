/* The geometry of a cascade's first features: how far every cell of the periodic grid is
 * from the nearest feature and from the nearest *other* feature. The net cascade draws
 * its lines where the two are equal (the features' zones of influence meet: Turk's
 * reticulation, the lines a second system's stripes draw midway between frozen spots);
 * the rosette cascade keeps its second system within a ring around each first feature.
 *
 * Features are the 4-connected components of the mask, wrapping around both edges.
 * Distances are propagated as nearest seeds (Danielsson): every cell keeps its nearest
 * feature cell and its nearest cell of a different feature, passes them to its
 * neighbours in raster sweeps forward and back, and the sweeps repeat until nothing
 * changes, which also carries seeds across the wrap. The result is exact for nearly every
 * cell and within a fraction of a cell elsewhere; it depends only on the mask. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen_internal.h"

typedef struct Near {
    int s1, l1, s2, l2; /* nearest seed cell and its feature; nearest of another feature */
    float e1, e2;       /* their squared distances */
} Near;

int sq__rd_label_features(const unsigned char *mask, int nu, int nv, int *lab)
{
    const int n = nu * nv;
    int *stack = malloc(sizeof(int) * (size_t)n);
    if (!stack)
        return -1;
    for (int i = 0; i < n; i++)
        lab[i] = -1;
    int count = 0;
    for (int s = 0; s < n; s++) {
        if (!mask[s] || lab[s] >= 0)
            continue;
        int top = 0;
        stack[top++] = s;
        lab[s] = count;
        while (top) {
            const int c = stack[--top], x = c % nu, y = c / nu;
            const int nb[4] = {y * nu + (x + 1) % nu, y * nu + (x + nu - 1) % nu,
                               ((y + 1) % nv) * nu + x, ((y + nv - 1) % nv) * nu + x};
            for (int k = 0; k < 4; k++)
                if (mask[nb[k]] && lab[nb[k]] < 0) {
                    lab[nb[k]] = count;
                    stack[top++] = nb[k];
                }
        }
        count++;
    }
    free(stack);
    return count;
}

static float dist2(int c, int s, int nu, int nv, float aspect)
{
    int dx = abs(c % nu - s % nu), dy = abs(c / nu - s / nu);
    dx = dx < nu - dx ? dx : nu - dx;
    dy = dy < nv - dy ? dy : nv - dy;
    const float fy = (float)dy * aspect;
    return (float)(dx * dx) + fy * fy;
}

/* Offers seed s of feature l to cell c; 1 when c's nearest ones changed. */
static int offer(Near *c, int ci, int s, int l, int nu, int nv, float aspect)
{
    if (s < 0)
        return 0;
    const float e = dist2(ci, s, nu, nv, aspect);
    if (l == c->l1) {
        if (e < c->e1) {
            c->s1 = s;
            c->e1 = e;
            return 1;
        }
        return 0;
    }
    if (e < c->e1) {
        c->s2 = c->s1;
        c->l2 = c->l1;
        c->e2 = c->e1;
        c->s1 = s;
        c->l1 = l;
        c->e1 = e;
        return 1;
    }
    if (e < c->e2) {
        c->s2 = s;
        c->l2 = l;
        c->e2 = e;
        return 1;
    }
    return 0;
}

static int pass_on(Near *near, int ci, int ni, int nu, int nv, float aspect)
{
    const Near nb = near[ni];
    return offer(&near[ci], ci, nb.s1, nb.l1, nu, nv, aspect) |
           offer(&near[ci], ci, nb.s2, nb.l2, nu, nv, aspect);
}

enum { MAX_SWEEPS = 32 };

int sq__rd_feature_distances(const unsigned char *mask, int nu, int nv, float aspect,
                             float *d1, float *d2)
{
    const int n = nu * nv;
    int *lab = malloc(sizeof(int) * (size_t)n);
    Near *near = malloc(sizeof(Near) * (size_t)n);
    if (!lab || !near || sq__rd_label_features(mask, nu, nv, lab) < 0) {
        free(lab);
        free(near);
        return -1;
    }
    for (int i = 0; i < n; i++) {
        const int in = lab[i] >= 0;
        near[i] = (Near){.s1 = in ? i : -1, .l1 = lab[i], .s2 = -1, .l2 = -1,
                         .e1 = in ? 0.0f : FLT_MAX, .e2 = FLT_MAX};
    }
    for (int sweep = 0; sweep < MAX_SWEEPS; sweep++) {
        int changed = 0;
        for (int y = 0; y < nv; y++) {
            const int up = (y + nv - 1) % nv;
            for (int x = 0; x < nu; x++) {
                const int c = y * nu + x, xl = (x + nu - 1) % nu, xr = (x + 1) % nu;
                changed |= pass_on(near, c, y * nu + xl, nu, nv, aspect);
                changed |= pass_on(near, c, up * nu + xl, nu, nv, aspect);
                changed |= pass_on(near, c, up * nu + x, nu, nv, aspect);
                changed |= pass_on(near, c, up * nu + xr, nu, nv, aspect);
            }
        }
        for (int y = nv - 1; y >= 0; y--) {
            const int dn = (y + 1) % nv;
            for (int x = nu - 1; x >= 0; x--) {
                const int c = y * nu + x, xl = (x + nu - 1) % nu, xr = (x + 1) % nu;
                changed |= pass_on(near, c, y * nu + xr, nu, nv, aspect);
                changed |= pass_on(near, c, dn * nu + xr, nu, nv, aspect);
                changed |= pass_on(near, c, dn * nu + x, nu, nv, aspect);
                changed |= pass_on(near, c, dn * nu + xl, nu, nv, aspect);
            }
        }
        if (!changed)
            break;
    }
    for (int i = 0; i < n; i++) {
        d1[i] = near[i].s1 >= 0 ? sqrtf(near[i].e1) : FLT_MAX;
        d2[i] = near[i].s2 >= 0 ? sqrtf(near[i].e2) : FLT_MAX;
    }
    free(lab);
    free(near);
    return 0;
}
