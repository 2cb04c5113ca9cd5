/* squama — the procedural generator (thesis Chapter 4): parameters in, four maps out.
 *
 * Texture space: u = x across the texture (wraps once around the body, seam on the
 * ventral midline: u = 0 and 1 are the belly's centre, u = 0.5 the dorsal midline),
 * v = y along the body, top row first. Every map tiles in u and v, except where the
 * ventral stretch deliberately breaks the pattern at the belly seam.
 *
 * Lengths the thesis gives as blur or width "amounts" are in units of 1/256 of the
 * texture width, so a preset looks the same at every resolution.
 *
 * Maps: basecolor is sRGB-encoded RGB (SQ_SPACE_SRGB); height, roughness are one
 * channel in [0,1] (SQ_SPACE_DATA); normal is RGB in [0,1] encoding a tangent-space
 * normal, OpenGL convention (+Y: green grows where the surface faces up the texture, v
 * decreasing) unless SqGenOptions.normal_directx flips it (-Y).
 *
 * Same parameters (Seed included) give the same pixels on any number of threads.
 */
#ifndef SQUAMA_GENERATOR_H
#define SQUAMA_GENERATOR_H

#include "error.h"
#include "image.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Where a render's time went, in milliseconds (filled when SqGenOptions.timings is set). */
typedef struct SqGenTimings {
    double alloc;   /* the four output maps */
    double scales;  /* height map: stamp and tiling */
    double detail;  /* fractal sum, micro detail, roughness */
    double normal;  /* normal map */
    double pattern; /* pattern layers, post-process, outline, warp field */
    double color;   /* colour map: sampling, background, composition */
    double total;
} SqGenTimings;

typedef struct SqGenOptions {
    int width, height;     /* output size in pixels (both >= 8) */
    int normal_directx;    /* 1: DirectX normal maps (-Y) */
    int threads;           /* OpenMP threads; 0 = the OpenMP default */
    SqGenTimings *timings; /* optional: filled with the time per stage */
} SqGenOptions;

typedef struct SqTextures {
    SqImage basecolor; /* 3 channels, sRGB */
    SqImage height;    /* 1 channel */
    SqImage roughness; /* 1 channel */
    SqImage normal;    /* 3 channels, data */
} SqTextures;

enum { SQ_GEN_MAX_SIZE = 16384 };

/* Options for a square texture of `size` pixels. */
SqGenOptions sq_gen_options_default(int size);

/* Renders the four maps. p is validated first. On error the textures are freed. */
SqStatus sq_gen_render(const SqParams *p, const SqGenOptions *opt, SqTextures *out,
                       SqError *err);

/* The same into maps from an earlier render (or zeroed): maps of the requested size are
 * overwritten in place, others (re)allocated. A caller rendering many times (a fit, a
 * batch) keeps one SqTextures and saves the allocation and the page faults of fresh
 * memory. On error the maps stay allocated with unspecified contents. */
SqStatus sq_gen_render_into(const SqParams *p, const SqGenOptions *opt, SqTextures *maps,
                            SqError *err);

/* Frees the four maps; NULL-safe. */
void sq_gen_textures_free(SqTextures *t);

/* The rows of a cellular automaton (§4.2.4), before mirroring: rows[r * ncells + c],
 * r < ca->epochs, each 0 or 1. rows must hold epochs * ncells bytes. */
void sq_ca_evolve(const SqCa *ca, uint8_t *rows);

/* The automaton's pattern over a w x h texture tile (thesis §4.2.4): the ncells cells
 * across u, its epochs and their mirror image along v, a circle of `diameter` cell
 * spacings painted for every 1 cell, as coverage in [0, 1] (soft over a pixel at the
 * circles' edges) before the pattern's post-process (rotation, blur, contrast). */
SqStatus sq_ca_coverage(const SqCa *ca, double diameter, float *cov, int w, int h, SqError *err);

#ifdef __cplusplus
}
#endif

#endif /* SQUAMA_GENERATOR_H */
