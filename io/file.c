/* Atomic file writes, whole-file reads and the sRGB transfer functions. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io_internal.h"
#include "squama/io.h"

/* The temporary files being written (and what sq_io_temp_add registers), for
 * sq_io_remove_temps in a signal handler: a slot is 0 free, 1 being filled, 2 holding a
 * name. Lock-free, so a handler that interrupts a write never waits; a table full goes
 * unregistered. Room for a staging folder of squama seed's 256 presets beside the writes
 * under way. A slot holds any path the system can open (PATH_MAX); the states lie apart
 * from the names, so that a scan touches only the pages of the slots in use. */
enum { TEMP_SLOTS = 512, TEMP_NAME = PATH_MAX };
static atomic_int temp_state[TEMP_SLOTS];
static char temp_name[TEMP_SLOTS][TEMP_NAME];

void sq_io_temp_add(const char *tmp)
{
    if (strlen(tmp) >= TEMP_NAME) /* no such file: open and mkdir refuse the name */
        return;
    for (int i = 0; i < TEMP_SLOTS; i++) {
        int free_slot = 0;
        if (atomic_compare_exchange_strong(&temp_state[i], &free_slot, 1)) {
            strcpy(temp_name[i], tmp);
            atomic_store(&temp_state[i], 2);
            return;
        }
    }
}

void sq_io_temp_forget(const char *tmp)
{
    for (int i = 0; i < TEMP_SLOTS; i++)
        if (atomic_load(&temp_state[i]) == 2 && strcmp(temp_name[i], tmp) == 0) {
            atomic_store(&temp_state[i], 0);
            return;
        }
}

void sq_io_remove_temps(void)
{
    for (int i = 0; i < TEMP_SLOTS; i++) /* the files, then the folders they were in */
        if (atomic_load(&temp_state[i]) == 2)
            unlink(temp_name[i]);
    for (int pass = 0; pass < 8; pass++) { /* a folder inside another goes first, whatever their slots */
        int gone = 0;
        for (int i = 0; i < TEMP_SLOTS; i++)
            if (atomic_load(&temp_state[i]) == 2 && rmdir(temp_name[i]) == 0)
                gone++;
        if (!gone)
            break;
    }
}

void sq__io_drop_temp(const char *tmp)
{
    unlink(tmp);
    sq_io_temp_forget(tmp);
}

int sq__io_make_temp(const char *path, char *tmp, size_t size)
{
    static atomic_uint counter;
    for (int attempt = 0; attempt < 100; attempt++) {
        unsigned k = atomic_fetch_add(&counter, 1);
        int n = snprintf(tmp, size, "%s.tmp-%ld-%u", path, (long)getpid(), k);
        if (n < 0 || (size_t)n >= size) {
            errno = ENAMETOOLONG;
            return -1;
        }
        int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            close(fd);
            sq_io_temp_add(tmp);
            return 0;
        }
        if (errno != EEXIST)
            return -1;
    }
    return -1;
}

SqStatus sq__io_commit(const char *tmp, const char *path, SqError *err)
{
    int fd = open(tmp, O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
        /* a file system that cannot fsync says so (EINVAL, EROFS, ENOTSUP); any other
         * failure (EIO, ENOSPC, EDQUOT) means the data did not reach the disk */
        int e = fsync(fd) == 0 ? 0 : errno;
        close(fd);
        if (e && e != EINVAL && e != EROFS && e != ENOTSUP && e != EBADF) {
            sq__io_drop_temp(tmp);
            return sq_error_set(err, SQ_ERR_IO, path, "cannot write: %s", strerror(e));
        }
    }
    if (rename(tmp, path) != 0) {
        int e = errno;
        sq__io_drop_temp(tmp);
        return sq_error_set(err, SQ_ERR_IO, path, "cannot write: %s", strerror(e));
    }
    sq_io_temp_forget(tmp);
    return SQ_OK;
}

SqStatus sq_io_write_file(const char *path, const void *data, size_t len, SqError *err)
{
    char tmp[4096];
    if (sq__io_make_temp(path, tmp, sizeof tmp) != 0)
        return sq_error_set(err, SQ_ERR_IO, path, "cannot create a file here: %s",
                            strerror(errno));
    int fd = open(tmp, O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        sq__io_drop_temp(tmp);
        return sq_error_set(err, SQ_ERR_IO, path, "cannot write: %s", strerror(e));
    }
    const char *p = data;
    size_t left = len;
    while (left > 0) {
        ssize_t w = write(fd, p, left);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            int e = w < 0 ? errno : EIO;
            close(fd);
            sq__io_drop_temp(tmp);
            return sq_error_set(err, SQ_ERR_IO, path, "cannot write: %s", strerror(e));
        }
        p += w;
        left -= (size_t)w;
    }
    if (close(fd) != 0) {
        int e = errno;
        sq__io_drop_temp(tmp);
        return sq_error_set(err, SQ_ERR_IO, path, "cannot write: %s", strerror(e));
    }
    return sq__io_commit(tmp, path, err);
}

SqStatus sq_io_read_file(const char *path, size_t max_bytes, char **data, size_t *len,
                         SqError *err)
{
    *data = NULL;
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return sq_error_set(err, SQ_ERR_IO, path, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(f);
        return sq_error_set(err, SQ_ERR_IO, path, "cannot open: it is a folder");
    }
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap + 1);
    while (buf) {
        if (n == cap) {
            if (cap > max_bytes)
                break;
            char *nb = realloc(buf, cap * 2 + 1);
            if (!nb) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t r = fread(buf + n, 1, cap - n, f);
        n += r;
        if (r == 0)
            break;
    }
    const int bad = ferror(f), e = errno;
    fclose(f);
    if (!buf)
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory reading the file");
    if (bad) {
        free(buf);
        return sq_error_set(err, SQ_ERR_IO, path, "cannot read: %s", strerror(e));
    }
    if (n > max_bytes) {
        free(buf);
        return sq_error_set(err, SQ_ERR_LIMIT, path, "file larger than %zu bytes", max_bytes);
    }
    buf[n] = '\0';
    *data = buf;
    *len = n;
    return SQ_OK;
}

float sq_io_srgb_to_linear(float v)
{
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

float sq_io_linear_to_srgb(float v)
{
    if (v <= 0.0031308f)
        return v * 12.92f;
    return 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}
