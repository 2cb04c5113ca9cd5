/* Internal interfaces of the generator's stages (not public API; tests may use them). */
#ifndef SQUAMA_GEN_INTERNAL_H
#define SQUAMA_GEN_INTERNAL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "squama/generator.h"

/* ---- deterministic randomness: a counter-based hash, independent of thread order ---- */

static inline uint64_t sq__mix(uint64_t z)
{
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* A hash of (seed, stream, index). */
static inline uint64_t sq__hash(uint64_t seed, uint64_t stream, uint64_t index)
{
    return sq__mix(seed ^ sq__mix(stream * 0x632BE59BD9B4E019ull ^ sq__mix(index)));
}

/* Uniform in [0, 1). */
static inline double sq__rand01(uint64_t seed, uint64_t stream, uint64_t index)
{
    return (double)(sq__hash(seed, stream, index) >> 11) * (1.0 / 9007199254740992.0);
}

/* Uniform in [-1, 1). */
static inline double sq__rand11(uint64_t seed, uint64_t stream, uint64_t index)
{
    return 2.0 * sq__rand01(seed, stream, index) - 1.0;
}

/* Streams: one per use, so that changing one stage never reshuffles another. */
enum {
    SQ_STREAM_SPOTS = 1,
    SQ_STREAM_SCALES,
    SQ_STREAM_DETAIL,
    SQ_STREAM_WARP_LARGE_X,
    SQ_STREAM_WARP_LARGE_Y,
    SQ_STREAM_WARP_SMALL_X,
    SQ_STREAM_WARP_SMALL_Y,
    SQ_STREAM_COLOR_NOISE,
    SQ_STREAM_KEEL,
    SQ_STREAM_BELLY,
    SQ_STREAM_RD,
    SQ_STREAM_RD2,
    SQ_STREAM_VORONOI,
    SQ_STREAM_LAYER /* the seeds of the pattern layers */
};

/* ---- small helpers ---- */

static inline int sq__wrap(int i, int n)
{
    if ((unsigned)i < (unsigned)n)
        return i;
    i %= n;
    return i < 0 ? i + n : i;
}

/* floor() for values well inside the int range, without a libm call (the baseline
 * x86-64 target has no SSE4.1 rounding instruction). */
static inline int sq__ifloor(float x)
{
    int i = (int)x;
    return i - (x < (float)i);
}

/* The triangle wave of period 1: -1 at whole t, +1 half way between (the zig-zags). */
static inline double sq__triangle(double t)
{
    const double f = t - floor(t);
    return f < 0.5 ? 4.0 * f - 1.0 : 3.0 - 4.0 * f;
}

static inline float sq__clamp01(float x)
{
    return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
}

/* Texture lengths in 1/256 of the width, in pixels of a texture `width` wide. */
static inline double sq__px(double amount, int width)
{
    return amount * (double)width / 256.0;
}

/* 64-byte aligned, zeroed float buffer of n elements (NULL when n is 0 or no memory).
 * Large buffers are aligned to 2 MiB and asked for transparent huge pages, and zeroed
 * by all threads: page faults were a tenth of the generator's time. Free with free(). */
float *sq__falloc(size_t n);
void sq__ffree(float *p);

/* The same without zeroing, for buffers that are written in full before being read. */
float *sq__falloc_raw(size_t n);

/* An image whose pixels come from sq__falloc_raw (not zeroed); 0 or -1. */
int sq__image_raw(SqImage *img, int w, int h, int ch, SqColorSpace space);

/* Precomputed linear interpolation along one axis: sample k of a resampling to n
 * points from a periodic line of m values (centres aligned) reads i0, i1 with weight t. */
typedef struct SqLerp {
    int *i0, *i1;
    float *t;
} SqLerp;

int sq__lerp_init(SqLerp *l, int n, int m);
void sq__lerp_free(SqLerp *l);

/* ---- filters (filter.c): every one wraps around the edges ---- */

/* Gaussian blur of standard deviation sigma (pixels) by three box passes, in place, on an
 * interleaved image of ch channels. Returns -1 when out of memory. */
int sq__blur(float *img, int w, int h, int ch, double sigma);

/* The same along one line of n samples (stride 1). Returns -1 when out of memory. */
int sq__blur_line(float *line, int n, double sigma);

/* Contrast around 0.5: 0 none, 1 a hard threshold. */
static inline float sq__contrast(float x, float c)
{
    if (c <= 0.0f)
        return x;
    float k = c >= 0.999f ? 1000.0f : 1.0f / (1.0f - c);
    return sq__clamp01((x - 0.5f) * k + 0.5f);
}

/* Levels: input black/white points and midtone (0.5 = linear), output [0,1]. */
float sq__levels(float x, float lo, float hi, float mid);

/* Bilinear sample at pixel coordinates (x, y) (pixel centres at integers), wrapping,
 * of channel c of an interleaved image. */
static inline float sq__sample(const float *img, int w, int h, int ch, int c, float x, float y)
{
    int ix = sq__ifloor(x), iy = sq__ifloor(y);
    float fx = (float)ix, fy = (float)iy;
    int x0 = sq__wrap(ix, w), y0 = sq__wrap(iy, h);
    int x1 = x0 + 1 == w ? 0 : x0 + 1, y1 = y0 + 1 == h ? 0 : y0 + 1;
    float tx = x - fx, ty = y - fy;
    const float *r0 = img + (size_t)y0 * w * ch, *r1 = img + (size_t)y1 * w * ch;
    float a = r0[x0 * ch + c] + (r0[x1 * ch + c] - r0[x0 * ch + c]) * tx;
    float b = r1[x0 * ch + c] + (r1[x1 * ch + c] - r1[x0 * ch + c]) * tx;
    return a + (b - a) * ty;
}

/* Resamples a periodic single-channel image (sw x sh) to (dw x dh), bilinear. Returns -1
 * when out of memory. */
int sq__resample(const float *src, int sw, int sh, float *dst, int dw, int dh);

/* ---- noise (noise.c): periodic over the texture ---- */

/* Fractal sum of smooth value noise, octave k having (cells << k) cells across the
 * width, amplitude gain^k; normalised to [0,1] over the image. Octaves finer than half
 * the image resolution are left out (they would alias). Returns -1 when out of memory. */
int sq__fbm(float *out, int w, int h, uint64_t seed, uint64_t stream, int cells, int octaves,
            double gain);

/* The same before its final resampling to w x h: a *rx x *ry image (sq__falloc'd, free
 * with sq__ffree), NULL when out of memory. */
float *sq__fbm_coarse(int w, int h, uint64_t seed, uint64_t stream, int cells, int octaves,
                      double gain, int *rx, int *ry);

/* Periodic Perlin gradient noise (about [-1, 1]) on a lattice of cx x cy cells over the
 * texture. The gradients are drawn once, at init. */
typedef struct SqPerlin {
    int cx, cy;
    float *g; /* cx * cy unit gradients (x, y) */
} SqPerlin;

int sq__perlin_init(SqPerlin *n, uint64_t seed, uint64_t stream, int cx, int cy);
void sq__perlin_free(SqPerlin *n);

/* Noise at texture coordinates (u, v), any real values (periodic). */
float sq__perlin(const SqPerlin *n, double u, double v);

/* ---- the pattern (pattern_*.c): coverage layers composited over the background ---- */

typedef enum SqLayerKind {
    SQ_LAYER_FULL, /* coverage 1 everywhere, no buffer */
    SQ_LAYER_ROWS, /* coverage depends on y only: h values */
    SQ_LAYER_COLS, /* coverage depends on x only: w values */
    SQ_LAYER_2D    /* w * h values */
} SqLayerKind;

typedef struct SqLayer {
    SqLayerKind kind;
    float *cov;      /* coverage in [0,1] */
    float color[4];  /* straight RGBA; alpha is the layer's opacity */
    int has_levels;  /* apply levels (lo, hi, mid) after blur and contrast */
    float levels[3];
} SqLayer;

enum { SQ_MAX_LAYERS = 6 };

typedef struct SqPattern {
    int w, h, n;
    SqLayer layers[SQ_MAX_LAYERS]; /* painted in order */
} SqPattern;

void sq__pattern_free(SqPattern *pat);

/* Adds a layer of the given kind (coverage allocated and zeroed) and colour; NULL with
 * err filled when full or out of memory. */
SqLayer *sq__pattern_add(SqPattern *pat, SqLayerKind kind, const double color[4], SqError *err);

/* Each pattern type adds its layers to pat (w, h set by the caller). */
SqStatus sq__pattern_transversal(const SqParams *p, SqPattern *pat, SqError *err);
SqStatus sq__pattern_longitudinal(const SqParams *p, SqPattern *pat, SqError *err);
SqStatus sq__pattern_spots(const SqParams *p, SqPattern *pat, SqError *err);
SqStatus sq__pattern_ca(const SqParams *p, SqPattern *pat, SqError *err);
SqStatus sq__pattern_rd(const SqParams *p, SqPattern *pat, SqError *err);

/* Fraction of pixel row y (of h) inside the band [b0, b1) (wrapping when b0 > b1). */
double sq__band_coverage(int y, int h, double b0, double b1);

/* Fraction of pixel column x (of w) covered by n pinched longitudinal stripes. */
double sq__stripe_coverage(int x, int w, int n, double stripes_width, double pinch);

/* Spots per row and rows of spots for a w x h texture. */
void sq__spots_grid(const SqParams *p, int w, int h, int *nx, int *ny);

/* Post-process (§4.2.4): rotate 90 degrees, blur, contrast, applied to every layer. */
SqStatus sq__pattern_postprocess(const SqParams *p, SqPattern *pat, SqError *err);

/* Paints the layers into a premultiplied RGBA image (w x h x 4). */
void sq__pattern_composite(const SqPattern *pat, float *rgba);

/* Linear interpolation of a periodic profile at t (sample centres at integers). */
static inline float sq__profile_at(const float *v, int n, float t)
{
    int f = sq__ifloor(t);
    int a = sq__wrap(f, n), b = a + 1 == n ? 0 : a + 1;
    return v[a] + (v[b] - v[a]) * (t - (float)f);
}

/* ---- reaction-diffusion (rd.c): Turk 1991 on a periodic grid ---- */

/* One system's state on an nu x nv periodic grid (u across, v along the body). The
 * chemicals are Turing's a, b (spots) or Meinhardt's g1, g2, r, s1, s2 (stripes). */
typedef struct SqRd {
    int system;     /* SqRdSystem */
    int nu, nv, nchem;
    float *cur[5], *nxt[5];
    float *sub;     /* per cell: Turing's beta, or Meinhardt's c */
    float *rate;    /* per column: the reaction's speed times the time step */
    float *live;    /* per cell: 1 simulated, 0 frozen (NULL: all simulated) */
    float dt;
    float diff[5];  /* diffusion constant times the time step, per chemical */
    long steps;     /* steps taken */
    int converged;
} SqRd;

/* A Turing spot system (Turk's constants: a = b = 4, beta = 12 +- beta_var, D_a = 0.25,
 * D_b = 0.0625) of speed s, times flank at u = 0 and 1 (a cosine in u); 0 or -1. */
int sq__rd_init_spots(SqRd *rd, int nu, int nv, double s, double flank, double beta_var,
                      uint64_t seed, uint64_t stream);

/* A Meinhardt stripe system with diffusion dx of g1 and g2; 0 or -1. */
int sq__rd_init_stripes(SqRd *rd, int nu, int nv, double dx, double flank, uint64_t seed,
                        uint64_t stream);

void sq__rd_free(SqRd *rd);

/* n explicit steps (OpenMP over rows; the same result on any number of threads). */
void sq__rd_steps(SqRd *rd, int n);

/* The largest change of the pattern chemical (b or g1) per unit time in the last step. */
float sq__rd_last_change(const SqRd *rd);

/* Steps until the largest change per unit time falls below tol (checked every `every`
 * steps) or `cap` steps; sets rd->converged. */
void sq__rd_solve(SqRd *rd, double tol, int every, long cap);

/* The pattern value per cell in [0, 1]: 1 in a feature's core, 0.5 at its edge, 0 at
 * rest (spots: 1 - b/8, Turk's spots being b < 4; stripes: g1 / (g1 + g2)). */
void sq__rd_value(const SqRd *rd, float *value);

/* The whole complex pattern on its grid: the first system, the cascade, the value. */
typedef struct SqRdResult {
    int nu, nv;
    int fine;     /* value's grid is fine times finer than the simulation's (net: up to 4, else 1) */
    float *value; /* final pattern value, (fine nu) * (fine nv) */
    float *first; /* the first system's value in a cascade (NULL without one) */
    long steps[2];
    int converged[2];
} SqRdResult;

/* Grid size for a w x h texture: RD_Cells across, the rows set by the aspect ratio and
 * RD_Anisotropy (features k times longer along v take k times fewer rows). */
void sq__rd_grid(const SqParams *p, int w, int h, int *nu, int *nv);

SqStatus sq__rd_run(const SqParams *p, int w, int h, SqRdResult *out, SqError *err);

/* For every cell of an nu x nv periodic grid, the distance d1 to the nearest cell of a
 * feature (a 4-connected component of mask, wrapping; 0 inside one) and d2 to the nearest
 * cell of another feature, FLT_MAX where there is none; a step along v counts `aspect`
 * steps along u. 0, or -1 when out of memory. (rd_net.c) */
int sq__rd_feature_distances(const unsigned char *mask, int nu, int nv, float aspect,
                             float *d1, float *d2);

/* The features of mask: lab[i] the 4-connected component (wrapping) of cell i, numbered
 * from 0 in the order of their first cells, -1 outside. Their count, or -1 (memory). */
int sq__rd_label_features(const unsigned char *mask, int nu, int nv, int *lab);
void sq__rd_result_free(SqRdResult *r);

/* Periodic Catmull-Rom upsampling of an sw x sh grid to dw x dh (cell centres aligned);
 * -1 when out of memory. */
int sq__rd_upsample(const float *src, int sw, int sh, float *dst, int dw, int dh);

/* ---- outline (outline.c), warp (warp.c) ---- */

/* Adds the outline of the premultiplied pattern image `rgba` over it, using the height
 * map for its distortion (§4.2.6). */
SqStatus sq__outline(const SqParams *p, float *rgba, const float *height, int w, int h,
                     SqError *err);

/* The warp of §4.2.7 as a displacement field (pixels) on a coarse gw x gh grid, to be
 * interpolated; n == 0 (and nothing allocated) when the warp is below a pixel. */
typedef struct SqWarp {
    int gw, gh;
    float *dx, *dy;
} SqWarp;

SqStatus sq__warp_field(const SqParams *p, int w, int h, SqWarp *warp, SqError *err);
void sq__warp_free(SqWarp *warp);

/* ---- height, roughness, normal (scales.c, surface.c) ---- */

/* The height map of the tiled scales with the ventral stretch (§4.3.1-4.3.3), without
 * micro detail. scratch holds w x h floats the function may overwrite. */
SqStatus sq__scales(const SqParams *p, float *height, float *scratch, int w, int h, SqError *err);

/* The single scale (§4.3.1) as an s x s image of height (channel 0) and coverage
 * (channel 1), interleaved. Returns -1 when out of memory. */
int sq__scale_stamp(const SqParams *p, float *stamp, int s);

/* The pixels a scale centred at (cx, cy), rx by ry pixels either side, covers in rows
 * y0..y1 of a w-wide map: [*sx0, *sx1) x [*sy0, *sy1). A belly scale at the seam (role
 * bit 1: left end, bit 2: right end) stops at its tile's edge. 0 when it covers none. */
static inline int sq__stamp_footprint(double cx, double cy, double rx, double ry, int role, int w, int y0, int y1,
                                      int *sx0, int *sx1, int *sy0, int *sy1)
{
    *sy0 = (int)floor(cy - ry);
    *sy1 = (int)ceil(cy + ry);
    if (*sy0 < y0) *sy0 = y0;
    if (*sy1 > y1) *sy1 = y1;
    double xmin = cx - rx, xmax = cx + rx;
    const double tile = floor(cx / w) * w;
    if (role & 1)
        xmin = tile;
    if (role & 2)
        xmax = tile + w;
    *sx0 = (int)floor(xmin);
    *sx1 = (int)ceil(xmax);
    if (*sx0 < 0) *sx0 = 0;
    if (*sx1 > w) *sx1 = w;
    return *sy0 < *sy1 && *sx0 < *sx1;
}

/* Paints the stamp (s x s, from sq__scale_stamp) at stamp coordinates X, Y (inside
 * (-1, 1) x (-1, 1); outside, nothing) over one pixel, front to back: *height gains the
 * stamp's bilinear height times its coverage under the transparency left, *clear, which
 * the coverage then shrinks. Shared by the grid and the Voronoi layouts. */
static inline void sq__stamp_over(const float *stamp, int s, float X, float Y, float *height, float *clear)
{
    if (X <= -1 || X >= 1 || Y <= -1 || Y >= 1)
        return;
    const float half_s = 0.5f * (float)s;
    float fx = (X + 1) * half_s - 0.5f, fy = (Y + 1) * half_s - 0.5f;
    fx = fx < 0 ? 0 : (fx > s - 1.001f ? s - 1.001f : fx);
    fy = fy < 0 ? 0 : (fy > s - 1.001f ? s - 1.001f : fy);
    const int x0 = (int)fx, y0 = (int)fy;
    const float tx = fx - x0, ty = fy - y0;
    const float *p00 = stamp + 2 * (y0 * s + x0), *p01 = p00 + 2 * s;
    const float a0 = p00[1] + (p00[3] - p00[1]) * tx, a1 = p01[1] + (p01[3] - p01[1]) * tx;
    const float a = a0 + (a1 - a0) * ty;
    if (a <= 0)
        return;
    const float h0 = p00[0] + (p00[2] - p00[0]) * tx, h1 = p01[0] + (p01[2] - p01[0]) * tx;
    const float t = *clear;
    *height += t * a * (h0 + (h1 - h0) * ty);
    *clear = t * (1.0f - a);
}

/* The lens inside the stamp, in stamp units ([-1, 1] square): cones of radius
 * SQ__CONE_R centred at +-SQ__CONE_D intersect in a lens SQ__LENS_HW wide (half) and
 * SQ__LENS_HH tall (half), before Scales_Expansion grows it. */
#define SQ__CONE_R 0.75
#define SQ__CONE_D 0.375
#define SQ__LENS_HW (SQ__CONE_R - SQ__CONE_D)
#define SQ__LENS_HH 0.649519052838329 /* sqrt(R^2 - D^2) */

/* ---- the Voronoi scale layout (voronoi.c) ---- */

/* An anisotropic centroidal Voronoi tessellation of the periodic texture (Landreneau
 * 2011, Chapter V): Scales_XAmount x Scales_YAmount sites, each a line segment along v
 * (the body) of half-length Scales_VoronoiAnisotropy spacings, relaxed by Lloyd's
 * algorithm on a raster that depends only on the parameters (never on the texture
 * size), the dorsal row (the "lateral line", u = 0.5) held fixed. Site k started in
 * row k / X, column k % X of a staggered, jittered grid. */
typedef struct SqVoronoi {
    int n, X, Y;
    double *u, *v;         /* n site centres, texture units in [0, 1) */
    unsigned char *fixed;  /* n: 1 for the lateral line's sites */
    int rw, rh;            /* the raster: rw x rh samples over the texture */
    int *owner;            /* rw * rh: the cell of each sample */
    int *area;             /* n: samples per cell */
    double *cu, *cv;       /* n: cell centroids, texture units (unwrapped near the site) */
    double *bu0, *bu1, *bv0, *bv1; /* n: cell bounding box relative to its site, texture units */
} SqVoronoi;

enum { SQ_VORONOI_ITERATIONS = 5 };

/* Builds the tessellation with `iterations` Lloyd steps (0: the jittered grid as is). */
SqStatus sq__voronoi_build(const SqParams *p, int iterations, SqVoronoi *vo, SqError *err);
/* The same with the nearest-site search's reach in spacings (sq__voronoi_build's: 1):
 * any reach > 0 gives the same tessellation, only faster or slower (tests try a short one). */
SqStatus sq__voronoi_build_reach(const SqParams *p, int iterations, double reach, SqVoronoi *vo, SqError *err);
void sq__voronoi_free(SqVoronoi *vo);

/* The centroidal energy: mean squared distance (in scale spacings, isotropic) of the
 * raster samples from their cell's centroid. Lloyd's steps lower it. */
double sq__voronoi_energy(const SqVoronoi *vo);

/* The height map of the Voronoi layout (sq__scales with Scales_Layout voronoi). */
SqStatus sq__scales_voronoi(const SqParams *p, float *height, float *scratch, int w, int h,
                            SqError *err);

/* Normal map (3 channels) from a height map. */
void sq__normals(const float *height, int w, int h, double intensity, int directx,
                 float *normal);

#endif
