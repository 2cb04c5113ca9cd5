/* Colour science: sRGB to CIELAB (D65) through lookup tables, and CIEDE2000 written
 * from Sharma, Wu & Dalal, "The CIEDE2000 colour-difference formula: implementation
 * notes, supplementary test data, and mathematical observations" (2005). */
#include <math.h>
#include <pthread.h>

#include "fitness_internal.h"

enum { LIN_N = SQ_LIN_N, F_N = 8192 };
float sq__lin_lut[SQ_LIN_N + 2]; /* sRGB code value -> linear */
static float f_lut[F_N + 2];     /* CIELAB f(t), t in [0, F_MAX] */
float sq__srgb_lut[SQ_LIN_N + 2]; /* linear (i / LIN_N)^2 -> sRGB code value */
static const float F_MAX = 1.25f;
static pthread_once_t once = PTHREAD_ONCE_INIT;

static double srgb_to_linear(double v)
{
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

static double linear_to_srgb(double v)
{
    v = v < 0 ? 0 : v > 1 ? 1 : v;
    return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
}

static double lab_f(double t)
{
    const double d = 6.0 / 29.0;
    return t > d * d * d ? cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
}

static void init_luts(void)
{
    for (int i = 0; i <= LIN_N + 1; i++)
        sq__lin_lut[i] = (float)srgb_to_linear(i > LIN_N ? 1.0 : (double)i / LIN_N);
    for (int i = 0; i <= F_N + 1; i++)
        f_lut[i] = (float)lab_f((double)(i > F_N ? F_N : i) / F_N * F_MAX);
    for (int i = 0; i <= LIN_N + 1; i++) {
        double t = (double)(i > LIN_N ? LIN_N : i) / LIN_N;
        sq__srgb_lut[i] = (float)linear_to_srgb(t * t);
    }
}

/* Nearest entry of a table over [0, n / scale]: the tables are fine enough (4096 and
 * 8192 entries) that interpolating adds nothing a colour statistic could see. */
static inline float lut(const float *t, int n, float x, float scale)
{
    int i = (int)(x * scale + 0.5f);
    return t[i < 0 ? 0 : (i > n ? n : i)];
}

void sq__lab_init(void)
{
    pthread_once(&once, init_luts);
}

void sq_fit_srgb_to_lab(const float rgb[3], float lab[3])
{
    sq__lab_init();
    float r = lut(sq__lin_lut, LIN_N, rgb[0], LIN_N), g = lut(sq__lin_lut, LIN_N, rgb[1], LIN_N),
          b = lut(sq__lin_lut, LIN_N, rgb[2], LIN_N);
    /* linear sRGB to XYZ (D65), divided by the white point */
    float x = (0.4124564f * r + 0.3575761f * g + 0.1804375f * b) / 0.95047f;
    float y = 0.2126729f * r + 0.7151522f * g + 0.0721750f * b;
    float z = (0.0193339f * r + 0.1191920f * g + 0.9503041f * b) / 1.08883f;
    const float s = F_N / F_MAX;
    float fx = lut(f_lut, F_N, x, s), fy = lut(f_lut, F_N, y, s), fz = lut(f_lut, F_N, z, s);
    lab[0] = 116.0f * fy - 16.0f;
    lab[1] = 500.0f * (fx - fy);
    lab[2] = 200.0f * (fy - fz);
}

static double lab_finv(double t)
{
    const double d = 6.0 / 29.0;
    return t > d ? t * t * t : 3 * d * d * (t - 4.0 / 29.0);
}


void sq_fit_lab_to_srgb(const float lab[3], float rgb[3])
{
    double fy = (lab[0] + 16.0) / 116.0, fx = fy + lab[1] / 500.0, fz = fy - lab[2] / 200.0;
    double x = 0.95047 * lab_finv(fx), y = lab_finv(fy), z = 1.08883 * lab_finv(fz);
    double r = 3.2404542 * x - 1.5371385 * y - 0.4985314 * z;
    double g = -0.9692660 * x + 1.8760108 * y + 0.0415560 * z;
    double b = 0.0556434 * x - 0.2040259 * y + 1.0572252 * z;
    rgb[0] = (float)linear_to_srgb(r);
    rgb[1] = (float)linear_to_srgb(g);
    rgb[2] = (float)linear_to_srgb(b);
}

static double deg(double rad)
{
    return rad * 180.0 / M_PI;
}

static double rad(double degrees)
{
    return degrees * M_PI / 180.0;
}

double sq_fit_ciede2000(const double lab1[3], const double lab2[3])
{
    const double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2];
    const double L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];
    const double p25_7 = 6103515625.0; /* 25^7 */
    /* 1. a' from the mean chroma (G), C', h' */
    const double cbar = (hypot(a1, b1) + hypot(a2, b2)) / 2, cbar7 = pow(cbar, 7);
    const double g = 0.5 * (1 - sqrt(cbar7 / (cbar7 + p25_7)));
    const double ap1 = (1 + g) * a1, ap2 = (1 + g) * a2;
    const double cp1 = hypot(ap1, b1), cp2 = hypot(ap2, b2);
    double hp1 = cp1 == 0 ? 0 : deg(atan2(b1, ap1)), hp2 = cp2 == 0 ? 0 : deg(atan2(b2, ap2));
    if (hp1 < 0) hp1 += 360;
    if (hp2 < 0) hp2 += 360;
    /* 2. dL', dC', dH' */
    const double dLp = L2 - L1, dCp = cp2 - cp1;
    double dhp = 0;
    if (cp1 * cp2 != 0) {
        dhp = hp2 - hp1;
        if (dhp > 180) dhp -= 360;
        else if (dhp < -180) dhp += 360;
    }
    const double dHp = 2 * sqrt(cp1 * cp2) * sin(rad(dhp / 2));
    /* 3. the weighting functions */
    const double lbar = (L1 + L2) / 2, cpbar = (cp1 + cp2) / 2;
    double hbar = hp1 + hp2;
    if (cp1 * cp2 != 0) {
        if (fabs(hp1 - hp2) > 180)
            hbar = hbar < 360 ? (hbar + 360) / 2 : (hbar - 360) / 2;
        else
            hbar /= 2;
    }
    const double t = 1 - 0.17 * cos(rad(hbar - 30)) + 0.24 * cos(rad(2 * hbar)) +
                     0.32 * cos(rad(3 * hbar + 6)) - 0.20 * cos(rad(4 * hbar - 63));
    const double dtheta = 30 * exp(-pow((hbar - 275) / 25, 2));
    const double cpbar7 = pow(cpbar, 7), rc = 2 * sqrt(cpbar7 / (cpbar7 + p25_7));
    const double l50 = (lbar - 50) * (lbar - 50);
    const double sl = 1 + 0.015 * l50 / sqrt(20 + l50), sc = 1 + 0.045 * cpbar, sh = 1 + 0.015 * cpbar * t;
    const double rt = -sin(rad(2 * dtheta)) * rc;
    const double x = dLp / sl, y = dCp / sc, z = dHp / sh;
    return sqrt(x * x + y * y + z * z + rt * y * z);
}
