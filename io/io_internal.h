/* io/ internals shared by the C and C++ files of the module. */
#ifndef SQUAMA_IO_INTERNAL_H
#define SQUAMA_IO_INTERNAL_H

#include <stddef.h>

#include "squama/error.h"

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

#ifdef __cplusplus
}
#endif

#endif
