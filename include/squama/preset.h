/* squama — presets: a parameter set as a JSON file.
 *
 *     {
 *       "format": "squama-preset/1",
 *       "name": "Micrurus altirostris",          (optional)
 *       "notes": "thesis Table 4.2 ...",          (optional)
 *       "Pattern_Type": "transversal",
 *       "Background_Color": [0.8, 0.1, 0.05, 1],
 *       "Transversal_BeginEnd1": [0.1, 0.9],
 *       "CA_Descriptor": "0 0 1 1 ...\nrectangular\n0\n6\n1110 1\n...",  (or an object)
 *       ...
 *     }
 *
 * Loading is strict: an unknown key is an error that names the closest valid key; a
 * wrong type or a value outside the hard range is an error that gives the allowed
 * range; a duplicate key, NaN or infinity is refused; a missing key takes its default.
 * Saving writes every parameter and loads back to identical values.
 */
#ifndef SQUAMA_PRESET_H
#define SQUAMA_PRESET_H


#include <stddef.h>

#include "error.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SQ_PRESET_FORMAT "squama-preset/1"

typedef struct SqPresetInfo {
    char name[256];   /* "name", may be empty */
    char notes[2048]; /* "notes", may be empty */
} SqPresetInfo;

/* Parses JSON text into *out (starting from defaults). `name` (a file name, may be NULL)
 * is used in error locations as "name:line". info may be NULL. */
SqStatus sq_preset_parse(const char *text, size_t len, const char *name, SqParams *out,
                         SqPresetInfo *info, SqError *err);

/* Reads and parses a preset file. */
SqStatus sq_preset_load(const char *path, SqParams *out, SqPresetInfo *info, SqError *err);

/* Serialises p (validated first) as preset JSON text ending in a newline. Returns a
 * malloc'd string the caller frees, or NULL with err filled. info may be NULL. */
char *sq_preset_to_json(const SqParams *p, const SqPresetInfo *info, SqError *err);

/* Largest preset file squama reads. */
enum { SQ_PRESET_MAX_BYTES = 4 << 20 };

#ifdef __cplusplus
}
#endif

#endif /* SQUAMA_PRESET_H */
