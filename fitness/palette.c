/* The dominant colours of a strip: k-means in CIELAB, started deterministically from a
 * coarse histogram. */
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
    /* start: a coarse CIELAB histogram's well-filled cells, the heaviest first, then each
     * time the cell that is heavy and far from those chosen (weight x squared distance:
     * a deterministic k-means++). Colours of one lightness, red and green, or a few small
     * bright spots, each get a centre; noise and highlights (thin cells) do not. */
    enum { CB = 8 };
    int *label = malloc(sizeof(int) * (size_t)n);
    int *cell = malloc(sizeof(int) * CB * CB * CB);
    float(*mean)[3] = malloc(sizeof(float) * 3 * CB * CB * CB);
    if (!label || !cell || !mean) {
        free(label);
        free(cell);
        free(mean);
        return;
    }
    memset(cell, 0, sizeof(int) * CB * CB * CB);
    memset(mean, 0, sizeof(float) * 3 * CB * CB * CB);
    for (int i = 0; i < n; i++) {
        const float *p = lab + 3 * i;
        int l = (int)(p[0] * (CB / 100.0f)), a = (int)((p[1] + 80) * (CB / 160.0f)), b = (int)((p[2] + 80) * (CB / 160.0f));
        l = l < 0 ? 0 : (l >= CB ? CB - 1 : l);
        a = a < 0 ? 0 : (a >= CB ? CB - 1 : a);
        b = b < 0 ? 0 : (b >= CB ? CB - 1 : b);
        int c = (l * CB + a) * CB + b;
        cell[c]++;
        for (int q = 0; q < 3; q++)
            mean[c][q] += p[q];
    }
    const int least = n / 100 > 2 ? n / 100 : 2;
    int chosen = 0;
    for (int c = 0; c < CB * CB * CB; c++)
        if (cell[c])
            for (int q = 0; q < 3; q++)
                mean[c][q] /= (float)cell[c];
    for (; chosen < k; chosen++) {
        int best = -1;
        double best_v = 0;
        for (int c = 0; c < CB * CB * CB; c++) {
            if (cell[c] < least)
                continue;
            double dmin = 1e30;
            for (int j = 0; j < chosen; j++) {
                double d0 = mean[c][0] - centre[j][0], d1 = mean[c][1] - centre[j][1], d2 = mean[c][2] - centre[j][2];
                dmin = fmin(dmin, d0 * d0 + d1 * d1 + d2 * d2);
            }
            double v = chosen ? cell[c] * dmin : cell[c];
            if (v > best_v) {
                best_v = v;
                best = c;
            }
        }
        if (best < 0)
            break;
        memcpy(centre[chosen], mean[best], sizeof(float) * 3);
    }
    free(cell);
    free(mean);
    if (chosen == 0) { /* every cell thin: the first pixel */
        memcpy(centre[0], lab, sizeof(float) * 3);
        chosen = 1;
    }
    k = chosen; /* the others keep weight 0 */
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
