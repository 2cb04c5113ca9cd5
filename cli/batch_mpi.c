/* squama batch over MPI: a dynamic work queue. Rank 0 hands out row indices as ranks become
 * free, fits rows itself on a second thread, and records every result (the catalogue is
 * its alone); the other ranks fit the rows they are given. Only rank 0's main thread
 * calls MPI (MPI_THREAD_FUNNELED). Without MPI at build time, the functions say no. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "batch.h"

#ifdef SQUAMA_HAVE_MPI

#include <time.h>

#include <mpi.h>

enum { TAG_RESULT = 1, TAG_ROW = 2 };

int batch_mpi_launched(void)
{
    /* Open MPI, MPICH/Hydra and PMIx launchers (mpirun, srun) set these */
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
        if (getenv(vars[i]))
            return 1;
    return 0;
}

int batch_mpi_init(int *rank, int *size, int *local_size)
{
    int provided = 0;
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        fprintf(stderr, "squama: MPI could not be started\n");
        return -1;
    }
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    MPI_Comm node;
    *local_size = 1;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node) == MPI_SUCCESS) {
        MPI_Comm_size(node, local_size);
        MPI_Comm_free(&node);
    }
    if (provided < MPI_THREAD_FUNNELED && *size > 1 && *rank == 0)
        fprintf(stderr, "squama: warning: this MPI does not promise MPI_THREAD_FUNNELED; rank 0 will not fit rows\n");
    return 0;
}

void batch_mpi_finalize(void)
{
    MPI_Finalize();
}

/* The queue both rank 0's fitting thread and the other ranks take rows from. */
typedef struct Shared {
    Batch *b;
    const int *pending;
    int npending, next;
    pthread_mutex_t lock;
} Shared;

static int take(Shared *s)
{
    pthread_mutex_lock(&s->lock);
    int i = s->next < s->npending ? s->pending[s->next++] : -1;
    pthread_mutex_unlock(&s->lock);
    return i;
}

static int take_cb(void *ctx)
{
    return take(ctx);
}

static void *rank0_fitter(void *arg)
{
    Shared *s = arg;
    batch_run_local(s->b, 1, take_cb, s);
    return NULL;
}

static void sleep_ms(int ms)
{
    struct timespec t = {0, ms * 1000000L};
    nanosleep(&t, NULL);
}

void batch_mpi_run(Batch *b, int rank, int size, const int *pending, int npending)
{
    if (rank > 0) {
        /* ask (with the last result, row -1 at first), fit, until told -1 */
        BatchResult r;
        memset(&r, 0, sizeof r);
        r.row = -1;
        for (;;) {
            MPI_Send(&r, (int)sizeof r, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
            int row;
            MPI_Recv(&row, 1, MPI_INT, 0, TAG_ROW, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (row < 0 || row >= b->nrows)
                return;
            batch_fit_row(b, row, &r);
        }
    }
    Shared s = {.b = b, .pending = pending, .npending = npending};
    pthread_mutex_init(&s.lock, NULL);
    int provided = 0;
    MPI_Query_thread(&provided);
    pthread_t th;
    int fitter = provided >= MPI_THREAD_FUNNELED && npending > 0 &&
                 pthread_create(&th, NULL, rank0_fitter, &s) == 0;
    int workers = size - 1;
    while (workers > 0) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, TAG_RESULT, MPI_COMM_WORLD, &flag, &st);
        if (!flag) { /* a blocking receive would spin a core that rank 0's fit needs */
            sleep_ms(20);
            continue;
        }
        BatchResult r;
        MPI_Recv(&r, (int)sizeof r, MPI_BYTE, st.MPI_SOURCE, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (r.row >= 0 && r.row < b->nrows) {
            r.error[sizeof r.error - 1] = '\0';
            batch_record(b, &r);
        }
        int next = take(&s);
        MPI_Send(&next, 1, MPI_INT, st.MPI_SOURCE, TAG_ROW, MPI_COMM_WORLD);
        if (next < 0)
            workers--;
    }
    if (fitter)
        pthread_join(th, NULL);
    pthread_mutex_destroy(&s.lock);
}

#else

int batch_mpi_launched(void)
{
    /* several copies of a program without MPI would all fit every row into one DIR */
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++) {
        const char *v = getenv(vars[i]);
        if (v && strtol(v, NULL, 10) > 1)
            return -1;
    }
    return 0;
}

int batch_mpi_init(int *rank, int *size, int *local_size)
{
    *rank = 0;
    *size = *local_size = 1;
    return 0;
}

void batch_mpi_finalize(void)
{
}

void batch_mpi_run(Batch *b, int rank, int size, const int *pending, int npending)
{
    (void)rank;
    (void)size;
    (void)b;
    (void)pending;
    (void)npending;
}

#endif
