/* squama — files: images through OpenImageIO, and atomic writes.
 *
 * Reading accepts anything OpenImageIO reads (PNG, JPEG, TIFF, EXR, ...), applies the
 * EXIF orientation, and returns float RGBA. The pixel count is checked from the header
 * before any decoding, so a hostile or huge file is refused cheaply. Writing goes to a
 * temporary file beside the target that is renamed over it when complete: an
 * interrupted write never leaves a half-written file.
 */
#ifndef SQUAMA_IO_H
#define SQUAMA_IO_H


#include <stddef.h>

#include "error.h"
#include "image.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { SQ_IO_DEFAULT_MAX_PIXELS = 100000000 }; /* 100 megapixels */

typedef struct SqReadOptions {
    long long max_pixels; /* refuse larger images; <= 0 means the default */
} SqReadOptions;

/* Reads an image as RGBA floats (grey is replicated, missing alpha is 1). When the
 * file has an alpha channel and mask is not NULL, *mask receives a 1-channel
 * SQ_SPACE_DATA image, 1 where alpha >= 0.5 and 0 elsewhere; otherwise mask->px is
 * NULL. Colour files decode as SQ_SPACE_SRGB unless they declare linear data (EXR). */
SqStatus sq_io_read_image(const char *path, const SqReadOptions *opt, SqImage *rgba,
                          SqImage *mask, SqError *err);

typedef enum SqImageFormat {
    SQ_FORMAT_AUTO = 0, /* from the file name's extension (.png, .exr, .jpg/.jpeg) */
    SQ_FORMAT_PNG,
    SQ_FORMAT_EXR,
    SQ_FORMAT_JPEG
} SqImageFormat;

typedef struct SqWriteOptions {
    SqImageFormat format;
    int bits;    /* PNG: 8 (default) or 16; EXR: 16 (half, default) or 32 (float); JPEG: 8 */
    int quality; /* JPEG: 1..100, 0 = 90 */
} SqWriteOptions;

/* Writes img atomically. PNG and JPEG store sRGB-encoded colour (linear input is
 * encoded), EXR stores linear colour (sRGB input is decoded); SQ_SPACE_DATA is stored as
 * is. Values are clamped to [0,1] for PNG and JPEG; JPEG drops alpha. opt may be NULL
 * (format from the name, 8 bits). */
SqStatus sq_io_write_image(const char *path, const SqImage *img, const SqWriteOptions *opt,
                           SqError *err);

/* Draws text into img (3 or 4 channels) with its baseline's left end at (x, y), glyphs
 * px_size pixels tall, in color (the image's own encoding), with the system's DejaVu Sans
 * (Debian's fonts-dejavu-core). SQ_ERR_UNSUPPORTED when no font can be found. */
SqStatus sq_io_draw_text(SqImage *img, int x, int y, int px_size, const char *text,
                         const float color[3], SqError *err);

/* Removes the temporary files of the writes under way in this process (each write goes
 * to a temporary file renamed into place when whole). Async-signal-safe: for a handler
 * of SIGINT or SIGTERM, so that an interrupted program leaves no half-written file. */
void sq_io_remove_temps(void);

/* Files or folders that are temporary too (a staging folder and what it holds, until it is
 * renamed into place): removed by sq_io_remove_temps (files first, folders when empty)
 * until forgotten. Thread-safe. */
void sq_io_temp_add(const char *path);
void sq_io_temp_forget(const char *path);

/* The image a write of this process had under way, or NULL: for a program's exit handler,
 * since libjpeg ends the program (exit) when a write fails, without returning an error. */
const char *sq_io_image_under_way(void);

/* Writes len bytes atomically (temporary file, fsync, rename). */
SqStatus sq_io_write_file(const char *path, const void *data, size_t len, SqError *err);

/* Reads a whole file (at most max_bytes) into a NUL-terminated malloc'd buffer. */
SqStatus sq_io_read_file(const char *path, size_t max_bytes, char **data, size_t *len,
                         SqError *err);

/* ---- CSV (csv.c) ----
 * RFC 4180 text: fields separated by commas, records by CRLF or LF; a field in double
 * quotes may hold commas, line breaks and doubled quotes (""). A UTF-8 byte-order mark
 * at the start is skipped, and so are empty lines. An unterminated quote, a character
 * after a closing quote or a NUL byte is an error naming the line. */

enum { SQ_CSV_MAX_FIELDS = 1024 };          /* per record */
enum { SQ_CSV_MAX_BYTES = 64 << 20 };       /* per file read by sq_io_csv_read */

typedef struct SqCsvRecord {
    int line;        /* 1-based line on which the record starts */
    int nfields;     /* >= 1 */
    char **fields;   /* NUL-terminated, unquoted */
} SqCsvRecord;

typedef struct SqCsv {
    int nrecords;
    SqCsvRecord *records;
    char *store_;    /* internal: the fields' bytes */
    char **ptrs_;    /* internal: every record's field pointers */
} SqCsv;

/* Parses len bytes of text (no NUL needed); name is used in messages ("name:line"). On
 * error nothing is allocated in out. */
SqStatus sq_io_csv_parse(const char *text, size_t len, const char *name, SqCsv *out,
                         SqError *err);

/* Reads and parses a file of at most SQ_CSV_MAX_BYTES. */
SqStatus sq_io_csv_read(const char *path, SqCsv *out, SqError *err);

/* NULL-safe; zeroes csv. */
void sq_io_csv_free(SqCsv *csv);

/* Appends field to a growing, NUL-terminated buffer as one RFC 4180 field (quoted when it
 * holds a comma, a quote or a line break), followed by `end` (',' or '\n'); -1 when out
 * of memory. */
int sq_io_csv_append(char **buf, size_t *len, size_t *cap, const char *field, char end);

/* sRGB transfer functions (IEC 61966-2-1). */
float sq_io_srgb_to_linear(float v);
float sq_io_linear_to_srgb(float v);

#ifdef __cplusplus
}
#endif

#endif /* SQUAMA_IO_H */
