/* The dominant colours of a strip: k-means in CIELAB, started from lightness quantiles
 * so the result is deterministic. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fitness_internal.h"

void sq__palette(const float *lab, int n, int k, float (*centre)[3], float *weight)
{
    if (k > 16)
        k = 16;
    memset(centre, 0, sizeof(float) * 3 * (size_t)k);
    memset(weight, 0, sizeof(float) * (size_t)k);
    if (n <= 0)
        return;
    /* start: the pixels nearest the lightness quantiles, found with a histogram of L */
    int *label = malloc(sizeof(int) * (size_t)n);
    if (!label)
        return;
    int lh[101] = {0};
    for (int i = 0; i < n; i++) {
        int b = (int)lab[3 * i];
        lh[b < 0 ? 0 : (b > 100 ? 100 : b)]++;
    }
    for (int c = 0; c < k; c++) {
        int want = (int)((c + 0.5) / k * n), acc = 0, b = 0;
        while (b < 100 && acc + lh[b] <= want)
            acc += lh[b++];
        float target = (float)b + 0.5f;
        int best = 0;
        for (int i = 0; i < n; i++)
            if (fabsf(lab[3 * i] - target) < fabsf(lab[3 * best] - target))
                best = i;
        memcpy(centre[c], lab + 3 * best, sizeof(float) * 3);
    }
    for (int iter = 0; iter < 10; iter++) {
        double sum[16][3] = {{0}};
        int cnt[16] = {0}, moved = 0;
        for (int i = 0; i < n; i++) {
            const float *p = lab + 3 * i;
            int best = 0;
            float bd = 1e30f;
            for (int c = 0; c < k; c++) {
                float d0 = p[0] - centre[c][0], d1 = p[1] - centre[c][1], d2 = p[2] - centre[c][2];
                float d = d0 * d0 + d1 * d1 + d2 * d2;
                if (d < bd) {
                    bd = d;
                    best = c;
                }
            }
            moved |= iter == 0 || label[i] != best;
            label[i] = best;
            cnt[best]++;
            for (int a = 0; a < 3; a++)
                sum[best][a] += p[a];
        }
        for (int c = 0; c < k; c++)
            if (cnt[c])
                for (int a = 0; a < 3; a++)
                    centre[c][a] = (float)(sum[c][a] / cnt[c]);
        for (int c = 0; c < k; c++)
            weight[c] = (float)cnt[c] / (float)n;
        if (!moved)
            break;
    }
    /* by decreasing weight */
    for (int a = 0; a < k; a++)
        for (int b = a + 1; b < k; b++)
            if (weight[b] > weight[a]) {
                float tw = weight[a], tc[3];
                weight[a] = weight[b];
                weight[b] = tw;
                memcpy(tc, centre[a], sizeof tc);
                memcpy(centre[a], centre[b], sizeof tc);
                memcpy(centre[b], tc, sizeof tc);
            }
    free(label);
}
