/* squama — fitness: how far a candidate's textures are from the snake in a photo.
 *
 * Both sides are reduced to a *strip*: an image whose rows run along the body and whose
 * columns go across it, in surface units (a pixel is the same length of skin in both
 * directions). A photo's strip comes from straightening the masked body; a candidate's
 * strip is the dorsal band of its base colour map, u in [c - b/2, c + b/2] around the band
 * centre c (0.5: the dorsal midline; b: SQ_FIT_BAND_WIDTH), sampled along v at the view
 * scale (texture tiles per body circumference... see sq_fit_candidate_strip).
 *
 * Statistics of the strips are compared, never pixels (Hewgill & Ross §6): colour
 * (masked CIELAB histograms, a dominant palette matched with CIEDE2000), shape (wavelet
 * sub-band energies of lightness per level and orientation) and layout (the spectra of
 * the pattern along and across the body, and the across profile). Each comparison is one
 * objective; they are ranked by Pareto dominance, never summed.
 */
#ifndef SQUAMA_FITNESS_H
#define SQUAMA_FITNESS_H

#include "error.h"
#include "generator.h"
#include "image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The visible band: +-60 degrees around the band centre of a cylinder seen from above,
 * beyond which foreshortening is extreme. As a fraction of the circumference: 1/3. */
#define SQ_FIT_BAND_WIDTH (1.0 / 3.0)

enum {
    SQ_FIT_STRIP_W = 64,   /* strip columns (across the body) */
    SQ_FIT_HIST_BINS = 8,  /* per CIELAB axis */
    SQ_FIT_PALETTE = 6,    /* dominant colours */
    SQ_FIT_LEVELS = 4,     /* wavelet levels */
    SQ_FIT_BANDS = 12,     /* spectrum bands, log-spaced */
    SQ_FIT_PROFILE = SQ_FIT_STRIP_W / 2
};

/* The light a strip is seen under, as unit vectors in its tangent frame (x across, the
 * way the columns run; y up the texture, against the rows; z out of the skin), along the
 * body: a candidate's strip row j takes dir[j / SQ_FIT_LIGHT_STEP], linear in between,
 * back and forth past the ends. rows 0: the default key light, from the upper left
 * (x -0.35, y 0.55, z 0.76). A photo's light (SqPrepared.light) is four pieces of the
 * light along its body, each at the body's own rate, SQ_FIT_CANDIDATE_ROWS strip rows
 * in all, turning smoothly where they join: the light there, not at the photo strip's
 * row 4i. */
enum {
    SQ_FIT_CANDIDATE_ROWS = 256, /* the length of a candidate's strip when it is scored */
    SQ_FIT_LIGHT_STEP = 4,
    SQ_FIT_LIGHT_ROWS = SQ_FIT_CANDIDATE_ROWS / SQ_FIT_LIGHT_STEP
};
typedef struct SqLight {
    int rows;
    float dir[SQ_FIT_LIGHT_ROWS][3];
} SqLight;

typedef struct SqFeatures {
    int valid_pixels;
    float hist[SQ_FIT_HIST_BINS * SQ_FIT_HIST_BINS * SQ_FIT_HIST_BINS]; /* sums to 1 */
    float palette[SQ_FIT_PALETTE][3]; /* Lab, by decreasing weight */
    float palette_w[SQ_FIT_PALETTE];  /* sums to 1 */
    float wavelet[SQ_FIT_LEVELS][3];  /* log mean energy: horizontal, vertical, diagonal */
    float along[SQ_FIT_BANDS];        /* lightness power along the body, per band, sums to 1 */
    float across[SQ_FIT_BANDS];       /* the same across the body */
    float along_power, across_power;  /* total variance of lightness detail */
    float profile[SQ_FIT_PROFILE];    /* mean lightness across the body, folded, centred */
    SqLight light;                    /* the light the strip was seen under (sq_fit_features
                                       * leaves it at the key light; a photo's target takes
                                       * SqPrepared.light): candidates are lit the same way */
    float blur;                       /* how much blurrier the strip is than a candidate's, a
                                       * Gaussian's sigma in strip pixels (sq_fit_features
                                       * leaves 0; a photo's target takes it from its
                                       * step and its own blur, sq_fit_strip_blur):
                                       * candidates are seen through it
                                       * (sq_fit_features_blurred) */
} SqFeatures;

/* The objectives, in order. */
typedef enum SqObjective {
    SQ_OBJ_PALETTE = 0, /* earth mover's distance of the palettes in CIEDE2000 units */
    SQ_OBJ_HISTOGRAM,   /* chi-square between CIELAB histograms */
    SQ_OBJ_SHAPE,       /* mean absolute difference of log wavelet energies */
    SQ_OBJ_ALONG,       /* chi-square of the along-body spectra, with the power ratio */
    SQ_OBJ_ACROSS,      /* the same across the body, with the folded profile */
    SQ_OBJ_COUNT
} SqObjective;

/* Names ("palette", "histogram", "shape", "along", "across"). */
const char *sq_fit_objective_name(int i);

/* Features of a strip: sRGB (3 or 4 channels, SQ_SPACE_SRGB); valid (1 channel, same
 * size, may be NULL) marks the pixels that count. The strip must be SQ_FIT_STRIP_W wide
 * and at least SQ_FIT_STRIP_W long. */
SqStatus sq_fit_features(const SqImage *strip, const SqImage *valid, SqFeatures *f, SqError *err);

/* The largest blur sq_fit_features_blurred takes, strip pixels. */
#define SQ_FIT_BLUR_MAX 5.0

/* The same, the strip seen through a further Gaussian blur of sigma `blur` strip pixels
 * (0 to SQ_FIT_BLUR_MAX): a candidate's strip as a photo's target sees it, blur =
 * target->blur. sq_fit_features is blur 0. */
SqStatus sq_fit_features_blurred(const SqImage *strip, const SqImage *valid, double blur, SqFeatures *f,
                                 SqError *err);

/* The objectives vector (SQ_OBJ_COUNT values, lower is better, 0 for identical features). */
void sq_fit_objectives(const SqFeatures *target, const SqFeatures *candidate, double *out);

/* The palette objective (SQ_OBJ_PALETTE) of a against b, and with flow not NULL how it
 * matched them: flow[i][j], the weight of a's dominant colour i moved onto b's colour j
 * (the cheapest pairs in CIEDE2000 first, as much as both hold). */
double sq_fit_palette_flow(const SqFeatures *a, const SqFeatures *b, double flow[SQ_FIT_PALETTE][SQ_FIT_PALETTE]);

/* A candidate's strip from its maps: SQ_FIT_STRIP_W columns across the band centred on
 * u = band_centre, `length` rows along v. view_scale is the number of body
 * circumferences one texture tile spans along the body (the UV layout's repeat): rows
 * step by band_width / SQ_FIT_STRIP_W / view_scale in v. With the normal and roughness
 * maps the body is lit as a glossy cylinder the way `squama photo` lights it, specular
 * highlight included (its diffuse fall-off is divided out again with the photo's light
 * normalisation; as the light turns along the strip, the smooth body's shading departs
 * from its mean over the rows, and that departure is divided out exactly, as a photo's
 * normalisation does where its light turns slowly), by `light` (see SqLight; NULL or no
 * rows: the key light); without the maps (both NULL) the strip is the base colour as it
 * is. */
SqStatus sq_fit_candidate_strip(const SqImage *basecolor, const SqImage *normal,
                                const SqImage *roughness, const SqLight *light, double view_scale,
                                double band_centre, int length, SqImage *strip, SqError *err);

/* ---- scoring a preset against a target (score.c) ---- */

enum { SQ_FIT_SCALES = 16 }; /* view scales tried: 0.25 * 2^(i/3), 0.25 to 8 */

/* The view scale of grid step i. */
double sq_fit_scale_at(int i);

/* Renders p's maps at size x size and scores them, lit by the target's light, against
 * the target's features at every view scale of the grid, keeping the scale where the
 * scale-dependent objectives (shape, along) are lowest: objectives (SQ_OBJ_COUNT) and
 * *view_scale.
 * A fixed_view > 0 scores at that view scale only (0: search the grid).
 * maps may be NULL, or reused between calls; best_strip (may be NULL) receives the strip
 * at the chosen scale. */
SqStatus sq_fit_score(const SqFeatures *target, const SqParams *p, int size, double band_centre,
                      double fixed_view, SqTextures *maps, double *objectives, double *view_scale,
                      SqImage *best_strip, SqError *err);

/* ---- photo preparation (prep.c) ---- */

/* Where the body's outline came from: a mask given, the photo's alpha, the automatic mask
 * (GrabCut), or a body line's width (SqPrepOptions.line, no mask given). */
typedef enum SqMaskSource { SQ_MASK_GIVEN, SQ_MASK_ALPHA, SQ_MASK_AUTOMATIC, SQ_MASK_LINE } SqMaskSource;

/* "given", "alpha", "automatic", "line" */
const char *sq_mask_source_name(SqMaskSource s);

/* ---- the body line (line.c) ----
 * Where the body runs in a photo, for photos whose mask cannot say it (a coiled body whose
 * coils touch, a snake on ground of its own colours): one or more stretches of its centre
 * line, each a polyline of points in pixels of the photo (x right, y down, from the
 * photo's top-left corner), and the body's width in the same pixels. As JSON:
 *   {"format": "squama-body-line/1", "width": 58,
 *    "stretches": [[[x, y], [x, y], ...], ...]}
 * The preparation writes the line it followed in this form (line.json of squama prepare
 * and squama fit), to be corrected by hand and passed back (--line). */
#define SQ_BODY_LINE_FORMAT "squama-body-line/1"
enum { SQ_BODY_LINE_MAX_BYTES = 4 << 20, SQ_BODY_LINE_MAX_STRETCHES = 16, SQ_BODY_LINE_MAX_POINTS = 100000 };

typedef struct SqBodyLine {
    int nstretches;
    int *count;    /* points of each stretch (2 at least) */
    float *xy;     /* every stretch's points in turn: x, y */
    double width;  /* the body's width */
} SqBodyLine;

/* Parses len bytes of JSON; name is used in messages ("name: stretches[1][3]"). On error
 * nothing is allocated in out. */
SqStatus sq_body_line_parse(const char *text, size_t len, const char *name, SqBodyLine *out, SqError *err);
SqStatus sq_body_line_read(const char *path, SqBodyLine *out, SqError *err);
/* Writes atomically, a stretch a line, coordinates to a tenth of a pixel. */
SqStatus sq_body_line_write(const char *path, const SqBodyLine *line, SqError *err);
void sq_body_line_free(SqBodyLine *line); /* NULL-safe; zeroes line */

typedef struct SqPrepOptions {
    int work_size;          /* longest side the photo is prepared at (default 1024) */
    const char *debug_dir;  /* when set, every step is saved there as an image */
    const SqBodyLine *line; /* when set, the body is followed along it, at its width: no
                             * mask is made, and a mask given only says which of the
                             * pixels within the width are body */
} SqPrepOptions;

typedef struct SqPrepared {
    SqImage photo;          /* the photo at working size, sRGB RGB */
    SqImage mask;           /* the cleaned mask at working size (save it to correct it) */
    SqImage strip;          /* the straightened body: SQ_FIT_STRIP_W wide, light-normalised */
    SqImage valid;          /* strip pixels that show the body */
    SqMaskSource mask_source;
    double scale;           /* working size / original size */
    double body_width;      /* median body width, pixels of the original photo */
    double length;          /* length straightened, pixels of the original */
    int nruns;              /* stretches of body straightened (between crossings) */
    int npoints;
    float *centre;          /* the runs' centre lines, x, y in pixels of the original */
    int *run_points;        /* points of each run in centre (nruns) */
    SqLight light;          /* the light along the body (see SqLight), from the shading's
                             * tilt as the body turns (one light fixed in the photo) */
    float light_xy[2];      /* that light's part in the photo's plane (x right, y down;
                             * 0.65 long at most, 0 0: none found) */
    double step;            /* photo pixels (at working size) a strip pixel spans at the
                             * body's middle: below 1 the strip is blurrier than a
                             * candidate's (sq_fit_strip_blur) */
    double edge_blur;       /* the photo's blur, a Gaussian's sigma in photo pixels at
                             * working size (the pixel's own box included), measured
                             * across the body's outline; 0: not measured */
} SqPrepared;

SqPrepOptions sq_fit_prep_options_default(void);

/* Prepares a photo (sRGB, 3 or 4 channels) with an optional mask (1 channel, the same
 * size; NULL: the photo's alpha if it has one, else made automatically by GrabCut):
 * cleans the mask, follows the centre line of its clean runs (those a body width long
 * whose edges are a body's width apart nearly all along, one after another with a few rows
 * of not-body between them, when the longest of them fills a strip; else the longest run
 * alone), resamples the body across at asin-spaced angles within +-60
 * degrees into a strip, and divides out large-scale shading. */
SqStatus sq_fit_prepare(const SqImage *photo, const SqImage *mask, const SqPrepOptions *o,
                        SqPrepared *out, SqError *err);

void sq_fit_prepared_free(SqPrepared *p);

/* The centre line the preparation followed as a body line (a point every half body width
 * or so, and the body's width), to be saved, corrected and given back. */
SqStatus sq_fit_prepared_line(const SqPrepared *p, SqBodyLine *out, SqError *err);

/* How much blurrier than a candidate's strip a photo's strip is, a Gaussian's sigma in
 * strip pixels, when a strip pixel spans `step` photo pixels and the photo's own blur is
 * edge_blur photo pixels (SqPrepared.edge_blur; 0: unknown, taken as 0.5, a sharp
 * photo's: its pixels' box and the bilinear sampling between them). That blur is
 * edge_blur / step strip pixels, against a candidate pixel's box (variance 1 / 12). At most
 * SQ_FIT_BLUR_MAX. */
double sq_fit_strip_blur(double step, double edge_blur);

/* The target a prepared photo makes: its strip's features, with its light and its blur. */
SqStatus sq_fit_photo_target(const SqPrepared *p, SqFeatures *target, SqError *err);

/* ---- synthetic photos with ground truth (synth.c) ---- */

typedef enum SqBackdrop {
    SQ_BACKDROP_RANDOM = 0, /* one of soil, litter, grass, from the seed */
    SQ_BACKDROP_SOIL,
    SQ_BACKDROP_LITTER,
    SQ_BACKDROP_GRASS,
    SQ_BACKDROP_PLAIN
} SqBackdrop;

typedef struct SqPhotoOptions {
    int width, height;    /* the photo, pixels (default 1024 x 768) */
    unsigned seed;        /* the body's curve, the backdrop, the noise */
    double body_radius;   /* pixels; 0: random, 3.5% to 7% of the shorter side */
    double view_scale;    /* body circumferences one texture tile spans; 0: random 0.5..2 */
    double band_centre;   /* texture u facing the camera (0.5: the dorsal midline) */
    double coil;          /* 0: a gentle curve .. 1: tight bends and partial coils */
    SqBackdrop backdrop;
    double blur;          /* Gaussian blur of the photo, sigma in pixels */
    double noise;         /* sensor noise, sigma in [0,1] units */
    double cast;          /* colour cast strength, 0..1 */
    int texture_size;     /* the preset's maps are rendered this big (default 512) */
    int samples;          /* points a pixel sees of the skin, per direction, averaged as a
                             camera's pixel does (default 4; 1 to 16) */
    int preview;          /* 1: a gentle S across the frame on a plain backdrop */
} SqPhotoOptions;

/* What the photo shows, for tests and benchmarks. */
typedef struct SqPhotoTruth {
    double view_scale, body_radius, band_centre, length; /* length: pixels along the body */
    int npoints;
    float *points; /* x, y of the centre line every 4 pixels (malloc'd) */
} SqPhotoTruth;

SqPhotoOptions sq_fit_photo_options_default(void);

/* Renders the preset's maps onto a snake-like tube lying along a random smooth curve,
 * lit by a key light and ambient (normal and roughness maps), over a natural backdrop;
 * then blur, noise and colour cast. photo: sRGB RGB; mask: 1 on the body; truth may be
 * NULL (else free it with sq_fit_truth_free). */
SqStatus sq_fit_synth_photo(const SqParams *p, const SqPhotoOptions *o, SqImage *photo,
                            SqImage *mask, SqPhotoTruth *truth, SqError *err);

void sq_fit_truth_free(SqPhotoTruth *t);

/* ---- colour science (colour.c) ---- */

/* sRGB-encoded RGB in [0,1] to CIELAB (D65). */
void sq_fit_srgb_to_lab(const float rgb[3], float lab[3]);

/* CIELAB (D65) to sRGB-encoded RGB in [0,1], clipped to the gamut. */
void sq_fit_lab_to_srgb(const float lab[3], float rgb[3]);

/* CIEDE2000 colour difference (Sharma, Wu & Dalal 2005). */
double sq_fit_ciede2000(const double lab1[3], const double lab2[3]);

#ifdef __cplusplus
}
#endif

#endif /* SQUAMA_FITNESS_H */
