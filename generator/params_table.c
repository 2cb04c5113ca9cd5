/* The parameter table: every parameter of the procedural model, in preset order.
 *
 * The 59 parameters of the thesis (Pinheiro 2017) are the parameters of its Substance
 * graph: 48 are named and described in Chapter 4-5; 11 more appear only as labels in the
 * parameter listing of Appendix D.11 (marked SQ_ORIGIN_THESIS_D11, with the label in
 * `ref`). Where the text gives a range it is the suggested range here; hard ranges are
 * what the generator accepts at all. Appendix D labels that differ from the Chapter 4
 * names: "Expansion" (Pattern group) is Pattern_Contrast, "Longitudinal_Separation" is
 * Longitudinal_Pinch, "Keel_Keel_keel_thinness" t is ScaleShape_KeelThickness 1 - t,
 * "Scales_Scales_normal" is Normal_Intensity.
 */
#include <assert.h>
#include <stddef.h>

#include "squama/params.h"

#define F(field) offsetof(SqParams, field)
/* A layer's own setting: the field in the first layer (see SQ_PF_LAYER). */
#define L(field) offsetof(SqParams, Pattern_Layers.layer[0].field)

/* The base pattern's fields by name lie where `pattern` has them. */
static_assert(offsetof(SqParams, Pattern_Type) == offsetof(SqParams, pattern),
              "SqParams' pattern fields start where its SqPatternSpec does");
static_assert(offsetof(SqParams, CA_Descriptor) ==
                  offsetof(SqParams, pattern) + offsetof(SqPatternSpec, CA_Descriptor),
              "SqParams' pattern fields are laid out as SqPatternSpec's");
static_assert(offsetof(SqParams, Pattern_Warp_Large) ==
                  offsetof(SqParams, pattern) + offsetof(SqPatternSpec, Pattern_Warp_Large),
              "SqParams' pattern fields are laid out as SqPatternSpec's");
static_assert(offsetof(SqParams, Pattern_Warp_Large) + sizeof(double) ==
                  offsetof(SqParams, pattern) + sizeof(SqPatternSpec),
              "SqPatternSpec ends with Pattern_Warp_Large, unpadded");
#define UNIT .min = 0, .max = 1, .smin = 0, .smax = 1

const char *const sq_pattern_type_names[] = {
    "none", "longitudinal", "transversal", "spots", "other_simple", "complex", NULL,
};

const char *const sq_rd_system_names[] = {"spots", "stripes", NULL};
const char *const sq_rd_cascade_names[] = {"none", "spots", "rosettes", "stripes",
                                                "net", NULL};
const char *const sq_scales_layout_names[] = {"grid", "voronoi", NULL};
const char *const sq_layer_blend_names[] = {"normal", "multiply", "screen", "overlay", NULL};

/* Figure 4.9's example automaton: the default for Pattern_Type other_simple. */
static const char ca_default[] =
    "0 0 1 1 1 1 0 0\nrectangular\n0\n6\n1110 1\n1100 1\n1000 x\n";

#define COLOR(field, r, g, b, a) \
    .type = SQ_PT_COLOR, .offset = F(field), .def = {r, g, b, a}, UNIT

#define TRANSVERSAL(i, r, g, b, b0, b1)                                                   \
    {.name = "Transversal_Color" #i, COLOR(Transversal_Color[i - 1], r, g, b, 1),         \
     .group = "transversal", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.1",                 \
     .help = "colour of transversal stripe " #i "; alpha 0 omits it"},                    \
    {.name = "Transversal_BeginEnd" #i, .type = SQ_PT_VEC2,                               \
     .offset = F(Transversal_BeginEnd[i - 1]), .def = {b0, b1}, UNIT,                     \
     .group = "transversal", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.1",                 \
     .help = "where stripe " #i " begins and ends along v (texture height); equal "       \
             "values omit it"}

static const SqParamSpec table[] = {
    /* ---- pattern type and background colour ---- */
    {.name = "Pattern_Type", .type = SQ_PT_ENUM, .offset = F(Pattern_Type),
     .choices = sq_pattern_type_names, .def = {SQ_PATTERN_NONE},
     .min = 0, .max = SQ_PATTERN_COUNT - 1, .smin = 0, .smax = SQ_PATTERN_COUNT - 1,
     .group = "pattern type", .origin = SQ_ORIGIN_THESIS, .ref = "§3.1, §4.1",
     .help = "pattern category; other_simple is drawn by a cellular automaton"},
    {.name = "Background_Color", COLOR(Background_Color, 0.42, 0.36, 0.26, 1),
     .group = "background", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2",
     .help = "the snake's predominant skin colour, under the pattern"},
    {.name = "Color_NoiseIntensity", .type = SQ_PT_FLOAT, .offset = F(Color_NoiseIntensity),
     .def = {0}, .min = 0, .max = 1, .smin = 0, .smax = 0.5,
     .group = "background", .origin = SQ_ORIGIN_THESIS_D11, .ref = "D.11 \"Noise Intensity\"",
     .help = "strength of a low-frequency noise that varies the base colour"},

    /* ---- transversal stripes (rings) ---- */
    TRANSVERSAL(1, 0.05, 0.05, 0.05, 0.0, 0.25),
    TRANSVERSAL(2, 0.90, 0.85, 0.60, 1.0, 1.0),
    TRANSVERSAL(3, 0.80, 0.10, 0.05, 1.0, 1.0),
    TRANSVERSAL(4, 0.20, 0.20, 0.80, 1.0, 1.0),
    {.name = "Transversal_ZigzagAmplitude", .type = SQ_PT_FLOAT,
     .offset = F(Transversal_ZigzagAmplitude), .def = {0}, .min = 0, .max = 0.5, .smin = 0,
     .smax = 0.2, .group = "transversal", .origin = SQ_ORIGIN_SQUAMA, .ref = "issue 5",
     .help = "rings zig-zag along the body by this fraction of the length either way; 0 straight"},
    {.name = "Transversal_ZigzagCount", .type = SQ_PT_INT,
     .offset = F(Transversal_ZigzagCount), .def = {1}, .min = 1, .max = 64, .smin = 1,
     .smax = 8, .group = "transversal", .origin = SQ_ORIGIN_SQUAMA, .ref = "issue 5",
     .help = "zig-zag periods round the body, a peak on the dorsal midline; 1 makes chevrons"},

    /* ---- longitudinal stripes ---- */
    {.name = "Longitudinal_NumberOfStripes", .type = SQ_PT_INT,
     .offset = F(Longitudinal_NumberOfStripes), .def = {1}, .min = 1, .max = 64,
     .smin = 1, .smax = 10, .group = "longitudinal", .origin = SQ_ORIGIN_THESIS,
     .ref = "§4.2.2", .help = "how many stripes run along the body"},
    {.name = "Longitudinal_StripesWidth", .type = SQ_PT_FLOAT,
     .offset = F(Longitudinal_StripesWidth), .def = {0.3}, UNIT, .group = "longitudinal",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.2",
     .help = "stripe width as a fraction of the texture width, divided by the number "
             "of stripes"},
    {.name = "Longitudinal_StripesColor", COLOR(Longitudinal_StripesColor, 0.85, 0.75, 0.30, 1),
     .group = "longitudinal", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.2",
     .help = "colour of the stripes"},
    {.name = "Longitudinal_Pinch", .type = SQ_PT_FLOAT, .offset = F(Longitudinal_Pinch),
     .def = {1}, .min = 0, .max = 64, .smin = 0, .smax = 10, .group = "longitudinal",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.2 (D.11 \"Longitudinal_Separation\")",
     .help = "squeezes the stripes towards the dorsal midline: 1 no change, 2 half the "
             "width, 4 a quarter"},
    {.name = "Longitudinal_ZigzagAmplitude", .type = SQ_PT_FLOAT,
     .offset = F(Longitudinal_ZigzagAmplitude), .def = {0}, .min = 0, .max = 0.25, .smin = 0,
     .smax = 0.1, .group = "longitudinal", .origin = SQ_ORIGIN_SQUAMA, .ref = "issue 6",
     .help = "stripes zig-zag across by this fraction of the width either way (adders); 0 straight"},
    {.name = "Longitudinal_ZigzagCount", .type = SQ_PT_INT,
     .offset = F(Longitudinal_ZigzagCount), .def = {8}, .min = 1, .max = 64, .smin = 3,
     .smax = 24, .group = "longitudinal", .origin = SQ_ORIGIN_SQUAMA, .ref = "issue 6",
     .help = "zig-zag periods along the texture's length (whole, so it tiles)"},

    /* ---- spots ---- */
    {.name = "Spots_Scale", .type = SQ_PT_FLOAT, .offset = F(Spots_Scale), .def = {0.5},
     .min = 0, .max = 8, .smin = 0, .smax = 2, .group = "spots", .origin = SQ_ORIGIN_THESIS,
     .ref = "§4.2.3", .help = "overall size of each spot"},
    {.name = "Spots_ScaleVariation", .type = SQ_PT_FLOAT, .offset = F(Spots_ScaleVariation),
     .def = {0}, UNIT, .group = "spots", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.3",
     .help = "random size variation: 0.5 gives sizes from 50% to 100%"},
    {.name = "Spots_PositionRandom", .type = SQ_PT_VEC2, .offset = F(Spots_PositionRandom),
     .def = {0, 0}, UNIT, .group = "spots", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.3",
     .help = "random displacement in x and y; 1 reaches the neighbouring spot's place"},
    {.name = "Spots_Offset", .type = SQ_PT_FLOAT, .offset = F(Spots_Offset), .def = {0},
     .min = 0, .max = 1, .smin = 0, .smax = 0.5, .group = "spots", .origin = SQ_ORIGIN_THESIS,
     .ref = "§4.2.3",
     .help = "shift of every other row: 0 a grid, 0.5 a grid rotated 45 degrees"},
    {.name = "Spots_Color", COLOR(Spots_Color, 0.10, 0.07, 0.05, 1), .group = "spots",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.3", .help = "colour of the spots"},
    {.name = "Spots_Interstice", .type = SQ_PT_VEC2, .offset = F(Spots_Interstice),
     .def = {0, 0}, UNIT, .group = "spots", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.3",
     .help = "narrows each spot's width and height: 0 round, 0.5 half the radius"},
    {.name = "Spots_IntersticeRandom", .type = SQ_PT_VEC2,
     .offset = F(Spots_IntersticeRandom), .def = {0, 0}, UNIT, .group = "spots",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.3",
     .help = "random variation of each spot's width and height"},
    {.name = "Spots_Rotation", .type = SQ_PT_FLOAT, .offset = F(Spots_Rotation), .def = {0},
     .min = 0, .max = 360, .smin = 0, .smax = 360, .group = "spots",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.3", .help = "rotation of every spot, degrees"},
    {.name = "Spots_RotationRandom", .type = SQ_PT_FLOAT, .offset = F(Spots_RotationRandom),
     .def = {0}, .min = 0, .max = 180, .smin = 0, .smax = 180, .group = "spots",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.3",
     .help = "random rotation of each spot, up to this many degrees either way"},
    {.name = "Spots_Tiling", .type = SQ_PT_FLOAT, .offset = F(Spots_Tiling), .def = {1},
     .min = 0.05, .max = 32, .smin = 0.1, .smax = 5, .flags = SQ_PF_LOG, .group = "spots",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.3",
     .help = "1 gives 10x10 spots per texture; less zooms in, more repeats"},

    /* ---- other simple pattern: the automaton image, coloured ---- */
    {.name = "CustomPattern_Color_Inside",
     COLOR(CustomPattern_Color_Inside, 0.12, 0.09, 0.06, 1), .group = "custom pattern",
     .origin = SQ_ORIGIN_THESIS_D11, .ref = "D.11 \"CustomPattern_Color_inside\"",
     .help = "colour of the pattern (the automaton's 1 cells)"},
    {.name = "CustomPattern_Color_Outside",
     COLOR(CustomPattern_Color_Outside, 0.0, 0.0, 0.0, 0), .group = "custom pattern",
     .origin = SQ_ORIGIN_THESIS_D11, .ref = "D.11 \"CustomPattern_Color_outsid\"",
     .help = "colour between the pattern (0 cells); alpha 0 shows the background"},
    {.name = "CustomPattern_LevelInLow", .type = SQ_PT_FLOAT,
     .offset = F(CustomPattern_LevelInLow), .def = {0}, UNIT, .group = "custom pattern",
     .origin = SQ_ORIGIN_THESIS_D11, .ref = "D.11 \"CustomPattern_Levelinlow\"",
     .help = "levels: input black point of the pattern image"},
    {.name = "CustomPattern_LevelInHigh", .type = SQ_PT_FLOAT,
     .offset = F(CustomPattern_LevelInHigh), .def = {1}, UNIT, .group = "custom pattern",
     .origin = SQ_ORIGIN_THESIS_D11, .ref = "D.11 \"CustomPattern_Levelinhigh\"",
     .help = "levels: input white point of the pattern image"},
    {.name = "CustomPattern_LevelInMid", .type = SQ_PT_FLOAT,
     .offset = F(CustomPattern_LevelInMid), .def = {0.5}, UNIT, .group = "custom pattern",
     .origin = SQ_ORIGIN_THESIS_D11, .ref = "D.11 \"CustomPattern_Levelinmid\"",
     .help = "levels: midtone of the pattern image (0.5 linear)"},

    /* ---- cellular automaton ---- */
    {.name = "CA_Descriptor", .type = SQ_PT_CA, .offset = F(CA_Descriptor),
     .def_text = ca_default, .group = "cellular automaton", .origin = SQ_ORIGIN_THESIS,
     .ref = "§4.2.4, App. E",
     .help = "the automaton: initial row, type, shift mirror, epochs, rule schedule "
             "(descriptor text or object)"},
    {.name = "CA_CircleDiameter", .type = SQ_PT_FLOAT, .offset = F(CA_CircleDiameter),
     .def = {1}, .min = 0.05, .max = 4, .smin = 0.5, .smax = 2, .group = "cellular automaton",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.4",
     .help = "diameter of the circle painted per cell, relative to the cell spacing"},

    /* ---- complex pattern: reaction-diffusion (Turk 1991), simulated on a periodic grid ---- */
    {.name = "RD_System", .type = SQ_PT_ENUM, .offset = F(RD_System),
     .choices = sq_rd_system_names, .def = {SQ_RD_SPOTS}, .min = 0,
     .max = SQ_RD_SYSTEM_COUNT - 1, .smin = 0, .smax = SQ_RD_SYSTEM_COUNT - 1,
     .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "§4.2.5; Turk 1991",
     .help = "first system: spots (Turing, Turk's constants) or stripes (Meinhardt)"},
    {.name = "RD_Cascade", .type = SQ_PT_ENUM, .offset = F(RD_Cascade),
     .choices = sq_rd_cascade_names, .def = {SQ_RD_CASCADE_NONE}, .min = 0,
     .max = SQ_RD_CASCADE_COUNT - 1, .smin = 0, .smax = SQ_RD_CASCADE_COUNT - 1,
     .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, Cascade",
     .help = "second stage: spots, rosettes or stripes among the frozen first features, or a net "
             "between them"},
    {.name = "RD_Cells", .type = SQ_PT_INT, .offset = F(RD_Cells), .def = {96}, .min = 16,
     .max = 1024, .smin = 48, .smax = 256, .flags = SQ_PF_LOG, .group = "reaction-diffusion",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991",
     .help = "simulation cells around the body (u): more cells, more and smaller features"},
    {.name = "RD_ReactionSpeed", .type = SQ_PT_FLOAT, .offset = F(RD_ReactionSpeed),
     .def = {0.05}, .min = 0.005, .max = 1, .smin = 0.02, .smax = 0.3, .flags = SQ_PF_LOG,
     .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, s",
     .help = "Turk's s of the spot system: larger gives smaller spots (0.05 large, 0.2 small)"},
    {.name = "RD_ReactionSpeed2", .type = SQ_PT_FLOAT, .offset = F(RD_ReactionSpeed2),
     .def = {0.2}, .min = 0.005, .max = 1, .smin = 0.05, .smax = 0.5, .flags = SQ_PF_LOG,
     .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, s",
     .help = "s of the cascade's second spot system (Turk: 0.2 after 0.05)"},
    {.name = "RD_BetaVariation", .type = SQ_PT_FLOAT, .offset = F(RD_BetaVariation),
     .def = {0.1}, .min = 0, .max = 6, .smin = 0, .smax = 3, .group = "reaction-diffusion",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, beta = 12 +- variation",
     .help = "random variation of the substrate beta around 12: 0.1 round spots, 3 irregular"},
    {.name = "RD_StripeDiffusion", .type = SQ_PT_FLOAT, .offset = F(RD_StripeDiffusion),
     .def = {0.1}, .min = 0.002, .max = 0.2, .smin = 0.005, .smax = 0.15, .flags = SQ_PF_LOG,
     .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, D_x",
     .help = "diffusion of the stripe system's g1, g2: smaller gives thinner stripes"},
    {.name = "RD_StripeDiffusion2", .type = SQ_PT_FLOAT, .offset = F(RD_StripeDiffusion2),
     .def = {0.008}, .min = 0.002, .max = 0.2, .smin = 0.005, .smax = 0.15,
     .flags = SQ_PF_LOG, .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA,
     .ref = "Turk 1991, D_x", .help = "D_x of the cascade's second stripe system (Turk: 0.008)"},
    {.name = "RD_Anisotropy", .type = SQ_PT_FLOAT, .offset = F(RD_Anisotropy), .def = {1},
     .min = 0.25, .max = 8, .smin = 0.5, .smax = 3, .flags = SQ_PF_LOG,
     .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, Fig. 8",
     .help = "stretch of the features along the body (v): 2 twice as long, below 1 across"},
    {.name = "RD_FlankSpeed", .type = SQ_PT_FLOAT, .offset = F(RD_FlankSpeed), .def = {1},
     .min = 0.25, .max = 4, .smin = 0.5, .smax = 2, .flags = SQ_PF_LOG,
     .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, Stripes",
     .help = "reaction speed at the flanks and belly relative to the back: >1 smaller there"},
    {.name = "RD_Color1", COLOR(RD_Color1, 0.12, 0.08, 0.05, 1), .group = "reaction-diffusion",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "",
     .help = "colour where the pattern value passes RD_Threshold1 (spots, dark stripes)"},
    {.name = "RD_Threshold1", .type = SQ_PT_FLOAT, .offset = F(RD_Threshold1), .def = {0.5},
     UNIT, .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "",
     .help = "pattern value (0 rest, 0.5 a feature's edge, 1 its core) where RD_Color1 begins"},
    {.name = "RD_Color2", COLOR(RD_Color2, 0.30, 0.20, 0.10, 0), .group = "reaction-diffusion",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "",
     .help = "colour past RD_Threshold2: a rim below RD_Threshold1, a core above; alpha 0 off"},
    {.name = "RD_Threshold2", .type = SQ_PT_FLOAT, .offset = F(RD_Threshold2), .def = {0.8},
     UNIT, .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "",
     .help = "pattern value where RD_Color2 begins"},
    {.name = "RD_Color3", COLOR(RD_Color3, 0.55, 0.40, 0.20, 0), .group = "reaction-diffusion",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "",
     .help = "colour of the first system's features in a cascade (rosette centres); alpha 0 off"},
    {.name = "RD_Softness", .type = SQ_PT_FLOAT, .offset = F(RD_Softness), .def = {0.1},
     .min = 0, .max = 1, .smin = 0, .smax = 0.4, .group = "reaction-diffusion",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "",
     .help = "width of the colour ramps around the thresholds: 0 hard edges"},
    {.name = "RD_NetWidth", .type = SQ_PT_FLOAT, .offset = F(RD_NetWidth), .def = {4},
     .min = 0.25, .max = 64, .smin = 1, .smax = 16, .flags = SQ_PF_LOG,
     .group = "reaction-diffusion", .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, Fig. 3",
     .help = "net cascade: line width at pattern value 0.5 (1/256 of the texture width per unit)"},
    {.name = "RD_RosetteWidth", .type = SQ_PT_FLOAT, .offset = F(RD_RosetteWidth),
     .def = {0}, .min = 0, .max = 64, .smin = 0, .smax = 24, .group = "reaction-diffusion",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, Fig. 2",
     .help = "rosette cascade: small spots grow only this far from the large (1/256 width); 0 anywhere"},
    {.name = "RD_CascadeGap", .type = SQ_PT_FLOAT, .offset = F(RD_CascadeGap), .def = {0},
     .min = 0, .max = 32, .smin = 0, .smax = 8, .group = "reaction-diffusion",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "Turk 1991, Fig. 3",
     .help = "cascade: the second system keeps this far from the first features (1/256 width)"},

    /* ---- pattern post-process ---- */
    {.name = "Pattern_RotatePattern90Degrees", .type = SQ_PT_BOOL,
     .offset = F(Pattern_RotatePattern90Degrees), .def = {0}, UNIT,
     .group = "pattern post-process", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.4",
     .help = "rotates the pattern 90 degrees (automata that read better along the body)"},
    {.name = "Pattern_BlurAmount", .type = SQ_PT_FLOAT, .offset = F(Pattern_BlurAmount),
     .def = {0}, .min = 0, .max = 64, .smin = 0, .smax = 16, .group = "pattern post-process",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.4",
     .help = "blur applied to the whole pattern"},
    {.name = "Pattern_Contrast", .type = SQ_PT_FLOAT, .offset = F(Pattern_Contrast),
     .def = {0}, UNIT, .group = "pattern post-process", .origin = SQ_ORIGIN_THESIS,
     .ref = "§4.2.4 (D.11 \"Expansion\")",
     .help = "contrast applied to the whole pattern after the blur"},
    {.name = "Pattern_Warp_Small", .type = SQ_PT_FLOAT, .offset = F(Pattern_Warp_Small),
     .def = {0}, .min = 0, .max = 4, .smin = 0, .smax = 1, .group = "pattern post-process",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.7",
     .help = "distortion by high-frequency Perlin noise (micro variation)"},
    {.name = "Pattern_Warp_Large", .type = SQ_PT_FLOAT, .offset = F(Pattern_Warp_Large),
     .def = {0}, .min = 0, .max = 40, .smin = 0, .smax = 10, .group = "pattern post-process",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.7",
     .help = "distortion by low-frequency Perlin noise (macro variation)"},

    /* ---- pattern layers: whole patterns stacked over the base pattern ---- */
    {.name = "Pattern_Layers", .type = SQ_PT_LAYERS, .offset = F(Pattern_Layers),
     .min = 0, .max = SQ_MAX_PATTERN_LAYERS, .smin = 0, .smax = SQ_MAX_PATTERN_LAYERS,
     .flags = SQ_PF_NOSEARCH, .group = "pattern layers", .origin = SQ_ORIGIN_SQUAMA,
     .ref = "issue 6",
     .help = "up to 3 objects, bottom first: Pattern_Type, pattern parameters, Layer_Blend, "
             "Layer_Opacity"},
    {.name = "Layer_Blend", .type = SQ_PT_ENUM, .offset = L(Layer_Blend),
     .choices = sq_layer_blend_names, .def = {SQ_BLEND_NORMAL}, .min = 0,
     .max = SQ_BLEND_COUNT - 1, .smin = 0, .smax = SQ_BLEND_COUNT - 1,
     .flags = SQ_PF_LAYER, .group = "pattern layers",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "W3C Compositing, separable blend modes",
     .help = "in a layer: how it meets the colours below: normal, multiply, screen, overlay"},
    {.name = "Layer_Opacity", .type = SQ_PT_FLOAT, .offset = L(Layer_Opacity), .def = {1},
     UNIT, .flags = SQ_PF_LAYER, .group = "pattern layers",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "",
     .help = "in a layer: 0 changes nothing, 1 the full blend"},

    /* ---- outline ---- */
    {.name = "Has_Outline", .type = SQ_PT_BOOL, .offset = F(Has_Outline), .def = {0}, UNIT,
     .group = "outline", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.6",
     .help = "draws an outline around the pattern; the other Outline_ parameters need it"},
    {.name = "Outline_Color", COLOR(Outline_Color, 0.015, 0.015, 0.015, 1),
     .group = "outline", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.6",
     .help = "colour of the outline"},
    {.name = "Outline_Edge_Width", .type = SQ_PT_FLOAT, .offset = F(Outline_Edge_Width),
     .def = {2}, .min = 0, .max = 64, .smin = 0, .smax = 16, .group = "outline",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.6", .help = "thickness of the outline"},
    {.name = "Outline_Blur", .type = SQ_PT_FLOAT, .offset = F(Outline_Blur), .def = {1},
     .min = 0, .max = 64, .smin = 0, .smax = 16, .group = "outline",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.6", .help = "blur of the distorted outline"},
    {.name = "Outline_Edge_Roundness", .type = SQ_PT_FLOAT, .offset = F(Outline_Edge_Roundness),
     .def = {0}, .min = 0, .max = 64, .smin = 0, .smax = 16, .group = "outline",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.6", .help = "rounds the outline's hard edges"},
    {.name = "Outline_Distortion_Intensity", .type = SQ_PT_FLOAT,
     .offset = F(Outline_Distortion_Intensity), .def = {0}, .min = 0, .max = 40, .smin = 0,
     .smax = 10, .group = "outline", .origin = SQ_ORIGIN_THESIS, .ref = "§4.2.6",
     .help = "distortion of the outline by the scales' height map"},

    /* ---- single scale shape ---- */
    {.name = "ScaleShape_Contrast", .type = SQ_PT_FLOAT, .offset = F(ScaleShape_Contrast),
     .def = {0.5}, UNIT, .group = "scale shape", .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.1",
     .help = "midtones of the scale's circle: higher makes the scale more solid"},
    {.name = "ScaleShape_Blur", .type = SQ_PT_FLOAT, .offset = F(ScaleShape_Blur),
     .def = {2}, .min = 0, .max = 64, .smin = 0, .smax = 16, .group = "scale shape",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.1", .help = "blur of the leaf shape"},
    {.name = "ScaleShape_Gradient", .type = SQ_PT_FLOAT, .offset = F(ScaleShape_Gradient),
     .def = {0.5}, UNIT, .group = "scale shape", .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.1",
     .help = "contrast of the linear gradient that makes the scale's height"},
    {.name = "ScaleShape_Ridge", .type = SQ_PT_FLOAT, .offset = F(ScaleShape_Ridge),
     .def = {0}, UNIT, .group = "scale shape", .origin = SQ_ORIGIN_THESIS_D11,
     .ref = "D.11 \"Ridge\"", .help = "height of a soft ridge along the scale's middle"},
    {.name = "ScaleShape_IsKeeled", .type = SQ_PT_BOOL, .offset = F(ScaleShape_IsKeeled),
     .def = {0}, UNIT, .group = "scale shape", .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.1",
     .help = "keeled scales (a longitudinal keel) instead of smooth ones"},
    {.name = "ScaleShape_KeelThickness", .type = SQ_PT_FLOAT,
     .offset = F(ScaleShape_KeelThickness), .def = {0.05}, .min = 0, .max = 1, .smin = 0.02,
     .smax = 0.1, .group = "scale shape", .origin = SQ_ORIGIN_THESIS,
     .ref = "§4.3.1 (D.11 \"Keel_Keel_keel_thinness\" = 1 - thickness)",
     .help = "width of the keel: 0 vanishes, 1 the scale's whole width"},
    {.name = "ScaleShape_KeelDistortion", .type = SQ_PT_FLOAT,
     .offset = F(ScaleShape_KeelDistortion), .def = {0}, UNIT, .group = "scale shape",
     .origin = SQ_ORIGIN_THESIS_D11, .ref = "D.11 \"Keel Distortion\"",
     .help = "irregularity of the keel line"},

    /* ---- scales ---- */
    {.name = "Scales_DetailNormal", .type = SQ_PT_FLOAT, .offset = F(Scales_DetailNormal),
     .def = {0.02}, .min = 0, .max = 1, .smin = 0, .smax = 0.05, .group = "scales",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.2",
     .help = "intensity of the fractal-sum micro detail on the height map"},
    {.name = "Scales_XAmount", .type = SQ_PT_INT, .offset = F(Scales_XAmount), .def = {16},
     .min = 1, .max = 256, .smin = 1, .smax = 64, .flags = SQ_PF_LOG, .group = "scales",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.2", .help = "scales across the texture (u)"},
    {.name = "Scales_YAmount", .type = SQ_PT_INT, .offset = F(Scales_YAmount), .def = {32},
     .min = 1, .max = 256, .smin = 1, .smax = 64, .flags = SQ_PF_LOG, .group = "scales",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.2", .help = "scales along the texture (v)"},
    {.name = "Scales_ScaleSize", .type = SQ_PT_FLOAT, .offset = F(Scales_ScaleSize),
     .def = {1}, .min = 0, .max = 4, .smin = 0, .smax = 2, .group = "scales",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.2", .help = "size of each scale"},
    {.name = "Scales_ScaleSizeXY", .type = SQ_PT_VEC2, .offset = F(Scales_ScaleSizeXY),
     .def = {1, 2}, .min = 0.1, .max = 4, .smin = 0.5, .smax = 3, .group = "scales",
     .origin = SQ_ORIGIN_THESIS_D11, .ref = "D.11 second \"Scale Size\"",
     .help = "width (in columns) and height (in rows) of each scale, times Scales_ScaleSize"},
    {.name = "Scales_Expansion", .type = SQ_PT_FLOAT, .offset = F(Scales_Expansion),
     .def = {0}, UNIT, .group = "scales", .origin = SQ_ORIGIN_THESIS_D11,
     .ref = "D.11 \"Expansion\" (Scales)",
     .help = "grows each scale into the gaps between scales (0 none, 1 gaps closed)"},
    {.name = "Scales_SizeRandom", .type = SQ_PT_FLOAT, .offset = F(Scales_SizeRandom),
     .def = {0}, .min = 0, .max = 1, .smin = 0, .smax = 0.3, .group = "scales",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "§4.3.2 (unnamed there)",
     .help = "random size variation of each scale"},
    {.name = "Scales_PositionRandom", .type = SQ_PT_VEC2, .offset = F(Scales_PositionRandom),
     .def = {0, 0}, .min = 0, .max = 1, .smin = 0, .smax = 0.3, .group = "scales",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "§4.3.2 (unnamed there)",
     .help = "random displacement of each scale in x and y, in scale spacings"},
    {.name = "Scales_RotationRandom", .type = SQ_PT_FLOAT, .offset = F(Scales_RotationRandom),
     .def = {0}, .min = 0, .max = 180, .smin = 0, .smax = 20, .group = "scales",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "§4.3.2 (unnamed there)",
     .help = "random rotation of each scale, up to this many degrees either way"},
    {.name = "Scales_BellyScalesPct", .type = SQ_PT_FLOAT, .offset = F(Scales_BellyScalesPct),
     .def = {0.15}, .min = 0, .max = 0.5, .smin = 0.1, .smax = 0.2, .group = "scales",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.3.3",
     .help = "width of the ventral area at each side edge, as a fraction of the texture "
             "width"},
    {.name = "Scales_BellyWarpIntensity", .type = SQ_PT_FLOAT,
     .offset = F(Scales_BellyWarpIntensity), .def = {0}, .min = 0, .max = 40, .smin = 0,
     .smax = 10, .group = "scales", .origin = SQ_ORIGIN_THESIS_D11,
     .ref = "D.11 \"Belly_warp_intensity\"",
     .help = "distortion of the stretched ventral scales"},
    {.name = "Scales_Layout", .type = SQ_PT_ENUM, .offset = F(Scales_Layout),
     .choices = sq_scales_layout_names, .def = {SQ_LAYOUT_GRID},
     .min = 0, .max = SQ_LAYOUT_COUNT - 1, .smin = 0, .smax = SQ_LAYOUT_COUNT - 1,
     .group = "scales", .origin = SQ_ORIGIN_SQUAMA, .ref = "Landreneau 2011, Ch. V",
     .help = "grid: the thesis' staggered rows; voronoi: as many scales on a relaxed "
             "Voronoi tessellation"},
    {.name = "Scales_VoronoiAnisotropy", .type = SQ_PT_FLOAT,
     .offset = F(Scales_VoronoiAnisotropy), .def = {0.5}, .min = 0, .max = 4, .smin = 0,
     .smax = 1.5, .group = "scales", .origin = SQ_ORIGIN_SQUAMA,
     .ref = "Landreneau 2011, Ch. V (alpha)",
     .help = "voronoi layout: half-length of the sites' segments along v, in scale "
             "spacings (0 round cells)"},
    {.name = "Scales_GapColor", COLOR(Scales_GapColor, 0.08, 0.07, 0.06, 1), .group = "scales",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "issue 5 (real photos)",
     .help = "colour of the skin between the scales (alpha its opacity), where Scales_GapExtent reaches"},
    {.name = "Scales_GapExtent", .type = SQ_PT_FLOAT, .offset = F(Scales_GapExtent),
     .def = {0}, .min = 0, .max = 1, .smin = 0, .smax = 0.6, .group = "scales",
     .origin = SQ_ORIGIN_SQUAMA, .ref = "issue 5 (real photos)",
     .help = "height up to which Scales_GapColor shows: full at 0, fading linearly to none here"},

    /* ---- roughness and normal map ---- */
    {.name = "Scales_RoughnessMin", .type = SQ_PT_FLOAT, .offset = F(Scales_RoughnessMin),
     .def = {0.3}, .min = 0, .max = 1, .smin = 0.2, .smax = 0.9, .group = "roughness",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.4",
     .help = "minimum roughness (black level of the noise); 0.2-0.4 smooth, 0.6-0.9 keeled"},
    {.name = "Scales_RoughnessMax", .type = SQ_PT_FLOAT, .offset = F(Scales_RoughnessMax),
     .def = {0.4}, .min = 0, .max = 1, .smin = 0.2, .smax = 0.9, .group = "roughness",
     .origin = SQ_ORIGIN_THESIS, .ref = "§4.4",
     .help = "maximum roughness (white level of the noise)"},
    {.name = "Normal_Intensity", .type = SQ_PT_FLOAT, .offset = F(Normal_Intensity),
     .def = {2}, .min = 0, .max = 32, .smin = 0, .smax = 8, .group = "normal",
     .origin = SQ_ORIGIN_THESIS, .ref = "§5 (D.11 \"Scales_Scales_normal\")",
     .help = "strength of the normal map made from the height map"},

    /* ---- squama ---- */
    {.name = "Seed", .type = SQ_PT_INT, .offset = F(Seed), .def = {1}, .min = 0,
     .max = 2147483647.0, .smin = 0, .smax = 2147483647.0, .flags = SQ_PF_NOSEARCH,
     .group = "squama", .origin = SQ_ORIGIN_SQUAMA, .ref = "",
     .help = "seed of every random choice: same preset and seed, same pixels"},
};

const SqParamSpec *sq_params_table(size_t *count)
{
    if (count)
        *count = sizeof table / sizeof table[0];
    return table;
}
