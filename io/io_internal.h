/* io/ internals shared by the C and C++ files of the module. */
#ifndef SQUAMA_IO_INTERNAL_H
#define SQUAMA_IO_INTERNAL_H

#include <stddef.h>

#include "squama/error.h"
#include "squama/io.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Creates an empty, unique temporary file beside `path` and writes its name into tmp.
 * Returns 0, or -1 with errno set. */
int sq__io_make_temp(const char *path, char *tmp, size_t size);

/* Renames tmp over path after fsync; on failure removes tmp and fills err. */
SqStatus sq__io_commit(const char *tmp, const char *path, SqError *err);

/* Removes tmp, a write that failed (sq_io_remove_temps forgets it too). */
void sq__io_drop_temp(const char *tmp);

/* The image module, libsquama_image.so (image.cpp): io's functions that need OpenImageIO,
 * whose 260 shared libraries take a third of a second to load. module.c opens it at the
 * first image read or written, so that a command without images starts at once. */
enum { SQ_IMAGE_MODULE_ABI = 1 }; /* raised when the table below changes */
typedef struct SqImageModule {
    int abi; /* SQ_IMAGE_MODULE_ABI of the build that made the module */
    SqStatus (*read)(const char *path, const SqReadOptions *opt, SqImage *rgba, SqImage *mask,
                     SqError *err);
    SqStatus (*write)(const char *path, const SqImage *img, const SqWriteOptions *opt, SqError *err);
    SqStatus (*draw_text)(SqImage *img, int x, int y, int px_size, const char *text,
                          const float color[3], SqError *err);
    const char *(*under_way)(void);
} SqImageModule;

/* The module's one entry point, looked up by name. */
const SqImageModule *sq__image_module(void);
#define SQ_IMAGE_MODULE_ENTRY "sq__image_module"
#define SQ_IMAGE_MODULE_FILE "libsquama_image.so"

#ifdef __cplusplus
}
#endif

#endif
