/* squama — the parameter set of the procedural model and the one table describing it.
 *
 * SqParams holds every parameter of the thesis' model (Chapter 4 and Appendix D: the 59
 * parameters of its Substance graph) plus squama's own. Field names follow the thesis'
 * parameter names; `sq_params_table()` describes each field: the name used in presets
 * (thesis spelling), type, default, hard range, the thesis' suggested range, group and
 * help. That one table drives defaults, validation, preset I/O, `squama params` and
 * docs/parameters.md. SqParams is plain data: copy it with `=` or memcpy.
 *
 * Colours are gamma-space (sRGB-encoded) RGBA in [0,1], as in the thesis' Appendix D.
 */
#ifndef SQUAMA_PARAMS_H
#define SQUAMA_PARAMS_H

#include <stddef.h>

#include "ca.h"
#include "error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum SqPatternType {
    SQ_PATTERN_NONE = 0,
    SQ_PATTERN_LONGITUDINAL,
    SQ_PATTERN_TRANSVERSAL,
    SQ_PATTERN_SPOTS,
    SQ_PATTERN_OTHER_SIMPLE,
    SQ_PATTERN_COMPLEX,
    SQ_PATTERN_COUNT
} SqPatternType;

/* Reaction-diffusion systems (Turk 1991) and cascades, for Pattern_Type complex. */
typedef enum SqRdSystem {
    SQ_RD_SPOTS = 0, /* Turing's two-chemical system: spots */
    SQ_RD_STRIPES,   /* Meinhardt's five-chemical system: random stripes */
    SQ_RD_SYSTEM_COUNT
} SqRdSystem;

typedef enum SqRdCascade {
    SQ_RD_CASCADE_NONE = 0,
    SQ_RD_CASCADE_SPOTS,    /* small spots between the frozen first features (cheetah) */
    SQ_RD_CASCADE_ROSETTES, /* the same with the frozen cells reset to rest (leopard) */
    SQ_RD_CASCADE_STRIPES,  /* stripes between the frozen first features (giraffe, multi-width) */
    SQ_RD_CASCADE_NET,      /* lines where the first features' zones meet (reticulation) */
    SQ_RD_CASCADE_COUNT
} SqRdCascade;

/* How the scales are laid out (Scales_Layout): the thesis' staggered grid (§4.3.2) or an
 * anisotropic centroidal Voronoi tessellation (Landreneau 2011, Chapter V). */
typedef enum SqScalesLayout {
    SQ_LAYOUT_GRID = 0,
    SQ_LAYOUT_VORONOI,
    SQ_LAYOUT_COUNT
} SqScalesLayout;

/* The pattern part of the parameters: its type and every pattern group's parameters,
 * post-process and warp included. One list, used for SqPatternSpec and, member for
 * member, inside SqParams, so that a pattern layer holds exactly what the base pattern
 * does and `p->Spots_Scale` keeps working. */
#define SQ_PATTERN_FIELDS                                                                  \
    /* pattern type (§4.1) */                                                              \
    int Pattern_Type; /* SqPatternType */                                                  \
                                                                                           \
    /* transversal stripes (§4.2.1) */                                                     \
    double Transversal_Color[4][4];                                                        \
    double Transversal_BeginEnd[4][2];                                                     \
    double Transversal_ZigzagAmplitude;                                                    \
    int Transversal_ZigzagCount;                                                           \
                                                                                           \
    /* longitudinal stripes (§4.2.2) */                                                    \
    int Longitudinal_NumberOfStripes;                                                      \
    double Longitudinal_StripesWidth;                                                      \
    double Longitudinal_StripesColor[4];                                                   \
    double Longitudinal_Pinch;                                                             \
    double Longitudinal_ZigzagAmplitude;                                                   \
    int Longitudinal_ZigzagCount;                                                          \
                                                                                           \
    /* spots (§4.2.3) */                                                                   \
    double Spots_Scale;                                                                    \
    double Spots_ScaleVariation;                                                           \
    double Spots_PositionRandom[2];                                                        \
    double Spots_Offset;                                                                   \
    double Spots_Color[4];                                                                 \
    double Spots_Interstice[2];                                                            \
    double Spots_IntersticeRandom[2];                                                      \
    double Spots_Rotation;                                                                 \
    double Spots_RotationRandom;                                                           \
    double Spots_Tiling;                                                                   \
                                                                                           \
    /* other simple pattern: colouring of the automaton image (Appendix D.11) */           \
    double CustomPattern_Color_Inside[4];                                                  \
    double CustomPattern_Color_Outside[4];                                                 \
    double CustomPattern_LevelInLow;                                                       \
    double CustomPattern_LevelInHigh;                                                      \
    double CustomPattern_LevelInMid;                                                       \
                                                                                           \
    /* cellular automaton (§4.2.4, Appendix E) */                                          \
    SqCa CA_Descriptor;                                                                    \
    double CA_CircleDiameter;                                                              \
                                                                                           \
    /* complex pattern: reaction-diffusion (Turk 1991; thesis §4.2.5 and §6.1) */          \
    int RD_System;  /* SqRdSystem */                                                       \
    int RD_Cascade; /* SqRdCascade */                                                      \
    int RD_Cells;                                                                          \
    double RD_ReactionSpeed;                                                               \
    double RD_ReactionSpeed2;                                                              \
    double RD_BetaVariation;                                                               \
    double RD_StripeDiffusion;                                                             \
    double RD_StripeDiffusion2;                                                            \
    double RD_Anisotropy;                                                                  \
    double RD_FlankSpeed;                                                                  \
    double RD_Color1[4];                                                                   \
    double RD_Threshold1;                                                                  \
    double RD_Color2[4];                                                                   \
    double RD_Threshold2;                                                                  \
    double RD_Color3[4];                                                                   \
    double RD_Softness;                                                                    \
    double RD_NetWidth;                                                                    \
    double RD_RosetteWidth;                                                                \
    double RD_CascadeGap;                                                                  \
                                                                                           \
    /* pattern post-process (§4.2.4, §4.2.7): per pattern, so a layer has its own */      \
    int Pattern_RotatePattern90Degrees;                                                    \
    double Pattern_BlurAmount;                                                             \
    double Pattern_Contrast;                                                               \
    double Pattern_Warp_Small;                                                             \
    double Pattern_Warp_Large;

typedef struct SqPatternSpec {
    SQ_PATTERN_FIELDS
} SqPatternSpec;

/* How a pattern layer is blended over the colour map below it (gamma-space colours, the
 * W3C compositing formulas): normal paints over, multiply darkens, screen lightens,
 * overlay multiplies the darks and screens the lights of what is below. */
typedef enum SqLayerBlend {
    SQ_BLEND_NORMAL = 0,
    SQ_BLEND_MULTIPLY,
    SQ_BLEND_SCREEN,
    SQ_BLEND_OVERLAY,
    SQ_BLEND_COUNT
} SqLayerBlend;

enum { SQ_MAX_PATTERN_LAYERS = 3 };

/* A pattern layer: a whole pattern (any type) with its own colours, blended over the
 * colour map made so far. Its randomness is seeded from Seed and the layer's index. */
typedef struct SqPatternLayer {
    SqPatternSpec spec;
    int Layer_Blend;      /* SqLayerBlend */
    double Layer_Opacity; /* 0 changes nothing, 1 the full blend */
} SqPatternLayer;

/* The stack of layers over the base pattern, bottom first; layer[count..] are unused
 * (kept at their defaults by parsing, ignored by comparison and rendering). */
typedef struct SqPatternLayers {
    int count;
    SqPatternLayer layer[SQ_MAX_PATTERN_LAYERS];
} SqPatternLayers;

typedef struct SqParams {
    /* background (§4.2) */
    double Background_Color[4];
    double Color_NoiseIntensity;

    /* the base pattern: its fields by name, or all of it as `pattern` */
    union {
        struct {
            SQ_PATTERN_FIELDS
        };
        SqPatternSpec pattern;
    };

    /* pattern layers over the base pattern (squama) */
    SqPatternLayers Pattern_Layers;

    /* outline (§4.2.6) */
    int Has_Outline;
    double Outline_Color[4];
    double Outline_Edge_Width;
    double Outline_Blur;
    double Outline_Edge_Roundness;
    double Outline_Distortion_Intensity;

    /* single scale shape (§4.3.1) */
    double ScaleShape_Contrast;
    double ScaleShape_Blur;
    double ScaleShape_Gradient;
    double ScaleShape_Ridge;
    int ScaleShape_IsKeeled;
    double ScaleShape_KeelThickness;
    double ScaleShape_KeelDistortion;

    /* scales tiling and ventral scales (§4.3.2, §4.3.3) */
    double Scales_DetailNormal;
    int Scales_XAmount;
    int Scales_YAmount;
    double Scales_ScaleSize;
    double Scales_ScaleSizeXY[2];
    double Scales_Expansion;
    double Scales_SizeRandom;
    double Scales_PositionRandom[2];
    double Scales_RotationRandom;
    double Scales_BellyScalesPct;
    double Scales_BellyWarpIntensity;
    int Scales_Layout; /* SqScalesLayout */
    double Scales_VoronoiAnisotropy;
    double Scales_GapColor[4];
    double Scales_GapExtent;

    /* roughness (§4.4) and normal map (§5) */
    double Scales_RoughnessMin;
    double Scales_RoughnessMax;
    double Normal_Intensity;

    /* squama */
    int Seed;
} SqParams;

typedef enum SqParamType {
    SQ_PT_FLOAT,  /* double */
    SQ_PT_INT,    /* int */
    SQ_PT_BOOL,   /* int, 0 or 1; JSON true/false */
    SQ_PT_ENUM,   /* int index into `choices`; JSON string */
    SQ_PT_VEC2,   /* double[2]; JSON [x, y] */
    SQ_PT_COLOR,  /* double[4] RGBA; JSON [r, g, b, a] (or [r, g, b], a = 1) */
    SQ_PT_CA,     /* SqCa; JSON descriptor text or object */
    SQ_PT_LAYERS  /* SqPatternLayers; JSON array of layer objects */
} SqParamType;

/* Where a parameter comes from. */
typedef enum SqParamOrigin {
    SQ_ORIGIN_THESIS,     /* named and described in the thesis' text (Chapters 4-5) */
    SQ_ORIGIN_THESIS_D11, /* one of the 59, known only from a label in Appendix D.11 */
    SQ_ORIGIN_SQUAMA      /* added by squama */
} SqParamOrigin;

enum {
    SQ_PF_LOG = 1u << 0,      /* the optimizer searches it on a log scale */
    SQ_PF_NOSEARCH = 1u << 1, /* the optimizer never changes it */
    SQ_PF_LAYER = 1u << 2     /* a layer's own setting (Layer_Blend, ...): found only inside
                                 a pattern layer; its offset is the field in
                                 Pattern_Layers.layer[0] */
};

typedef struct SqParamSpec {
    const char *name;      /* preset key, thesis spelling */
    SqParamType type;
    size_t offset;         /* offsetof(SqParams, field) */
    const char *group;
    double def[4];         /* default (components as the type has them; enum: index) */
    double min, max;       /* hard range, per component */
    double smin, smax;     /* suggested range (thesis where it gives one), per component */
    const char *const *choices; /* SQ_PT_ENUM: NULL-terminated names */
    const char *def_text;  /* SQ_PT_CA: default descriptor text */
    SqParamOrigin origin;
    const char *ref;       /* thesis section, or Appendix D.11 label */
    unsigned flags;        /* SQ_PF_* */
    const char *help;      /* one line */
} SqParamSpec;

/* The table, in preset order, and its length. */
const SqParamSpec *sq_params_table(size_t *count);

/* The entry for a name (exact, case-sensitive), or NULL. */
const SqParamSpec *sq_params_find(const char *name);

/* The table entry whose name is closest to `name` (edit distance, case-insensitive);
 * never NULL. Used for "did you mean" hints. */
const SqParamSpec *sq_params_closest(const char *name);

/* Number of components of a type: 1, 2 (vec2) or 4 (colour); 0 for SQ_PT_CA and
 * SQ_PT_LAYERS. */
int sq_param_components(SqParamType type);

/* Human name of a type ("float", "int", "bool", "enum", "vec2", "color", "ca"). */
const char *sq_param_type_name(SqParamType type);

/* Pointer to the field of a spec inside p. */
void *sq_param_ptr(SqParams *p, const SqParamSpec *spec);
const void *sq_param_cptr(const SqParams *p, const SqParamSpec *spec);

/* Pattern layers reuse the table: a row belongs in a layer object when it is a pattern
 * parameter (its field lies in SqParams.pattern) or a layer's own setting (SQ_PF_LAYER).
 * Its field in layer l is at the same place relative to l->spec (or to l). */
int sq_param_in_layer(const SqParamSpec *spec);

/* Pointer to the field of a layer row inside l; NULL when !sq_param_in_layer(spec). */
void *sq_param_layer_ptr(SqPatternLayer *l, const SqParamSpec *spec);
const void *sq_param_layer_cptr(const SqPatternLayer *l, const SqParamSpec *spec);

/* A layer at its defaults: every pattern parameter as the table has it, blend normal,
 * opacity 1. */
void sq_pattern_layer_default(SqPatternLayer *l);

/* Every parameter at its default (no pattern layers; the unused layers at their
 * defaults too). */
void sq_params_default(SqParams *p);

/* Checks every field against its hard range (and enum/CA validity, finite numbers), and
 * in each pattern layer in use, each of its fields; an error in a layer is named
 * "Pattern_Layers[i].Name". */
SqStatus sq_params_validate(const SqParams *p, SqError *err);

/* Field-by-field equality of every table entry (exact for numbers); pattern layers
 * compare by count and then the layers in use. */
int sq_params_equal(const SqParams *a, const SqParams *b);

/* Writes a parameter's value as text ("0.5", "[0.1, 0.2]", "spots", "true", CA descriptor
 * on one line with " / " between items, layers as "[spots multiply 0.5, ...]" with their
 * type, blend and opacity); returns the length needed, like snprintf. A layer's own
 * setting (SQ_PF_LAYER) reads the first layer.
 * Numbers use %.*g with `digits` significant digits, or with digits <= 0 the shortest
 * text that reads back exactly. */
size_t sq_param_format(const SqParams *p, const SqParamSpec *s, int digits, char *buf,
                       size_t size);

/* Pattern type names, as used in presets ("none", "longitudinal", ...). */
const char *sq_pattern_type_name(int type);
extern const char *const sq_pattern_type_names[];

/* Names of the reaction-diffusion systems and cascades, as used in presets. */
extern const char *const sq_rd_system_names[];
extern const char *const sq_rd_cascade_names[];

/* Scales layout names, as used in presets ("grid", "voronoi"). */
extern const char *const sq_scales_layout_names[];

/* Names of the layer blend modes, as used in presets ("normal", "multiply", ...). */
extern const char *const sq_layer_blend_names[];

#ifdef __cplusplus
}
#endif

#endif /* SQUAMA_PARAMS_H */
