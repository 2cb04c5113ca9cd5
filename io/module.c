/* The image module opened at first use: sq_io_read_image, sq_io_write_image and
 * sq_io_draw_text pass through to it (io_internal.h says why it is a module). */
#define _POSIX_C_SOURCE 200809L

#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "io_internal.h"
#include "squama/io.h"

#ifndef SQUAMA_MODULE_DIR
#error "SQUAMA_MODULE_DIR names the folder the build puts its modules in"
#endif

#if defined(__SANITIZE_ADDRESS__)
/* The module's thread-local storage is dynamic (it is opened, not linked), and the sanitizer
 * runtime of GCC 13 and older now and then misreads a dynamic TLS block as glibc 2.19's,
 * whereupon LeakSanitizer's tracer crashes at exit ("Tracer caught signal 11"). Leaving
 * __tls_get_addr alone avoids it; ASAN_OPTIONS can still say otherwise. */
const char *__asan_default_options(void);
const char *__asan_default_options(void)
{
    return "intercept_tls_get_addr=0";
}
#endif

static pthread_once_t image_once = PTHREAD_ONCE_INIT;
static _Atomic(const SqImageModule *) image_table; /* NULL until it loaded */
static SqError image_failure;                      /* why it did not */

/* Beside the program that runs (a squama moved with its module), else where the build put it
 * (the tests and benchmarks, which live in folders of their own). */
static void load_image_module(void)
{
    char path[PATH_MAX + 64], exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    const char *slash = n > 0 ? (exe[n] = '\0', strrchr(exe, '/')) : NULL;
    if (!slash || snprintf(path, sizeof path, "%.*s/%s", (int)(slash - exe), exe, SQ_IMAGE_MODULE_FILE) < 0 ||
        access(path, F_OK) != 0)
        snprintf(path, sizeof path, "%s/%s", SQUAMA_MODULE_DIR, SQ_IMAGE_MODULE_FILE);
    /* lazily bound, as a linked library is: binding all of OpenImageIO's libraries' functions
     * now costs 40 ms a command (and the module's calls into io are checked by every write) */
    void *h = dlopen(path, RTLD_LAZY | RTLD_LOCAL);
    if (!h) {
        const char *why = dlerror();
        size_t len = strlen(path); /* glibc's reason starts with the path, which goes last */
        if (why && strncmp(why, path, len) == 0 && why[len] == ':')
            why += len + (why[len + 1] == ' ' ? 2 : 1);
        sq_error_set(&image_failure, SQ_ERR_UNSUPPORTED, path,
                     "cannot read or write images: squama's image module did not load: %.300s",
                     why ? why : "unknown reason");
        return;
    }
    const SqImageModule *(*entry)(void);
    void *sym = dlsym(h, SQ_IMAGE_MODULE_ENTRY);
    memcpy(&entry, &sym, sizeof entry); /* POSIX: an object pointer that holds a function */
    const SqImageModule *t = sym ? entry() : NULL;
    if (!t || t->abi != SQ_IMAGE_MODULE_ABI) {
        sq_error_set(&image_failure, SQ_ERR_UNSUPPORTED, path,
                     "cannot read or write images: squama's image module is from another build");
        return; /* left open: its code may be on a stack somewhere, and it costs nothing */
    }
    atomic_store(&image_table, t);
}

static const SqImageModule *image_module(SqError *err)
{
    pthread_once(&image_once, load_image_module);
    const SqImageModule *t = atomic_load(&image_table);
    if (!t && err)
        *err = image_failure;
    return t;
}

SqStatus sq_io_read_image(const char *path, const SqReadOptions *opt, SqImage *rgba, SqImage *mask,
                          SqError *err)
{
    memset(rgba, 0, sizeof *rgba);
    if (mask)
        memset(mask, 0, sizeof *mask);
    const SqImageModule *t = image_module(err);
    return t ? t->read(path, opt, rgba, mask, err) : image_failure.status;
}

SqStatus sq_io_write_image(const char *path, const SqImage *img, const SqWriteOptions *opt, SqError *err)
{
    const SqImageModule *t = image_module(err);
    return t ? t->write(path, img, opt, err) : image_failure.status;
}

SqStatus sq_io_draw_text(SqImage *img, int x, int y, int px_size, const char *text, const float color[3],
                         SqError *err)
{
    const SqImageModule *t = image_module(err);
    return t ? t->draw_text(img, x, y, px_size, text, color, err) : image_failure.status;
}

/* No module, no image written: an exit handler does not load it to ask. */
const char *sq_io_image_under_way(void)
{
    const SqImageModule *t = atomic_load(&image_table);
    return t ? t->under_way() : NULL;
}
