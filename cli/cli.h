/* The squama program: shared helpers of the command files. */
#ifndef SQUAMA_CLI_H
#define SQUAMA_CLI_H

#include <stddef.h>

#include "squama/error.h"
#include "squama/fitness.h"
#include "squama/image.h"

/* One command: `squama NAME ...`. */
typedef struct CliCommand {
    const char *name;
    const char *summary;
    int (*run)(int argc, char **argv); /* argv[0] is the command name */
} CliCommand;

int cmd_params(int argc, char **argv);
int cmd_presets(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_photo(int argc, char **argv);
int cmd_prepare(int argc, char **argv);
int cmd_score(int argc, char **argv);
int cmd_fit(int argc, char **argv);
int cmd_seed(int argc, char **argv);
int cmd_batch(int argc, char **argv);
/* At the start of every squama process: a fit started by a batch dies with it (batch.c). */
void cli_batch_child(void);

/* The handler main() sets for SIGINT, SIGTERM and SIGHUP: removes the temporary files of
 * the writes under way (sq_io_remove_temps), then ends the program by the signal. */
void cli_fatal_signal(int sig);

/* mkdir -p; 0 or -1 with errno. */
int cli_mkdirs(const char *path);
/* The same, recording the folders it made (as lengths of path's prefixes); and after a
 * run that failed, exactly those removed again, the last made first, each only if empty:
 * a refused command leaves no empty folder behind, and never anything else. */
enum { CLI_MADE_MAX = 64 };
typedef struct CliMade {
    int n, len[CLI_MADE_MAX];
} CliMade;
int cli_mkdirs_new(const char *path, CliMade *made);
void cli_rmdirs_new(const char *path, const CliMade *made);
/* The folders made, registered with the io module's temporary files (an interrupted run
 * removes them when empty), and forgotten again once the run is through. */
void cli_made_register(const char *path, const CliMade *made);
void cli_made_forget(const char *path, const CliMade *made);

/* A temporary folder that outputs are written into first, then renamed into place, so
 * that a failure or an interruption leaves either the new outputs or the old ones. The
 * folder and each file named in it are registered with the io module's temporary files,
 * which an interrupted run removes (cli_fatal_signal). A file's name may hold folders
 * ("front/00.json"), made in the staging folder as it is named and in the output folder
 * as the set moves in. */
typedef struct CliStaged {
    char name[64];
    char drop;   /* an old file that goes with the set (cli_staging_drop) */
    char folder; /* a folder made in the staging folder for the files below it */
} CliStaged;
typedef struct CliStaging {
    char dir[4096];
    char outdir[4096]; /* where the files go */
    const char *what; /* what a file is called in errors ("map"); "output" when NULL */
    int nfiles, cap;
    CliStaged *files;
} CliStaging;
/* mkdtemp(pattern), pattern ending in XXXXXX, for files that go into outdir, with room for
 * cap names at first */
SqStatus cli_staging_open(CliStaging *s, const char *pattern, const char *outdir, int cap, SqError *err);
/* s's next file name (under 64 bytes, no "." or ".." in it), its path in path (n bytes),
 * registered; its folders made in s */
SqStatus cli_staging_path(CliStaging *s, const char *name, char *path, size_t n, SqError *err);
/* outdir's file name removed with the set (put back when the set does not go in): the
 * output of an earlier run that this one has none of. A name staged already is unwritten. */
SqStatus cli_staging_drop(CliStaging *s, const char *name, SqError *err);
/* s's files and folder no longer temporary; removed first when remove is set (a file
 * already renamed away is not there to remove) */
void cli_staging_release(CliStaging *s, int remove);
/* cli_staging_release(s, 1), and s's memory freed */
void cli_staging_free(CliStaging *s);
/* Every file of s moved into its outdir under its name, as a set: each old file there set
 * aside in s until every new one is in, and put back when a move fails (a folder where a
 * file goes stops it too); SIGINT, SIGTERM and SIGHUP wait meanwhile (cli_signal_waits),
 * as their handler would remove the new files still in s. "wrote PATH" for each unless
 * quiet. An old file that cannot be put back stays in s's folder, and is named on stderr. */
SqStatus cli_staging_commit(CliStaging *s, int quiet, SqError *err);
/* err's place, when it is a file in s, named as the file in outdir it was to become */
void cli_staging_where(const CliStaging *s, SqError *err);
/* path, when it is a file in the staging open now, as the file it is to become, in buf (n
 * bytes); else path itself */
const char *cli_staging_shown(const char *path, char *buf, size_t n);
/* For the fatal signals' handler, on any thread: 1 when sig must wait, a staging's files
 * being moved into place (the commit raises it again when they are in); 0 to go on and end
 * the program, no commit starting from then on (one about to waits for the end). */
int cli_signal_waits(int sig);

/* 1 when a and b name the same file: the same inode if both exist, else the same path
 * once their folders are resolved. */
int cli_same_file(const char *a, const char *b);

/* Seconds on the monotonic clock. */
double cli_now_s(void);

/* The search's share of a command's time budget (--budget is the whole command's): less
 * `spent` (reading and preparing the photo) and a reserve for writing the outputs with
 * size-pixel maps (1 s, and 2 s more at 1024: fit's measured 1.4 to 1.6 s there on 2
 * cores), but at least a quarter of it. */
double cli_search_budget(double budget, double spent, int size);

/* snprintf into a path buffer: 0, or -1 (errno ENAMETOOLONG, buf emptied) when it does
 * not fit. */
int cli_pathf(char *buf, size_t n, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* rm -rf (symbolic links removed, never followed); 0 (also when path is missing) or -1
 * with errno. */
int cli_remove_tree(const char *path);

/* A photo with what may be given with it: a mask and a body line. */
typedef struct CliPhoto {
    SqImage photo;
    SqImage mask;      /* 1 channel, 1 on the snake; px NULL when none was given */
    SqBodyLine line;   /* nstretches 0 when none was given */
} CliPhoto;

/* Reads a photo and, when set, its mask (white or opaque on the snake, the photo's size)
 * and its body line (squama-body-line JSON); 0, or -1 with err filled and nothing held. */
int cli_load_photo(const char *photo_path, const char *mask_path, const char *line_path, CliPhoto *in,
                   SqError *err);
void cli_photo_free(CliPhoto *in);

/* dir/mask.png: prep's mask at in's photo size (to correct and pass back with --mask);
 * left as it is when it is the mask given (mask_path). */
SqStatus cli_write_full_mask(CliStaging *s, const char *dir, const SqPrepared *prep, const CliPhoto *in, const char *mask_path,
                             SqError *err);

/* sq_fit_prepare with what in holds (o NULL: the defaults). */
SqStatus cli_prepare(const CliPhoto *in, const SqPrepOptions *o, SqPrepared *prep, SqError *err);

/* A strip shorter than CLI_SHORT_STRIP body widths shows too little of the skin to see a
 * pattern repeat (a band or a blotch every body width or two). For such a prep: 1 and
 * the warning, saying what to do (line_given: a body line was followed), in buf (n
 * bytes); else 0. */
#define CLI_SHORT_STRIP 3.0
int cli_short_strip(const SqPrepared *prep, int line_given, char *buf, size_t n);

/* The centre line prep followed, in dir: line.json (a point every half body width, to
 * correct and give back with --line), unless a line was given (given, read from
 * given_path: the user's own file, never overwritten; a line.json of an earlier run
 * there that is not it is removed, as it is not the line followed), and line.png: the prepared photo with a grid in the photo's own pixels
 * (labelled), each stretch followed (its centre line in red, its edges dotted in cyan) and
 * the line's points (given's, or line.json's) numbered within their stretch. */
SqStatus cli_write_line(CliStaging *s, const char *dir, const SqPrepared *prep, const SqBodyLine *given, const char *given_path,
                        SqError *err);

enum { CLI_OK = 0, CLI_FAIL = 1, CLI_USAGE = 2 };

/* Prints "squama: <what> (<where>)" to stderr; returns CLI_FAIL. */
int cli_fail(const SqError *err);

/* Prints "squama: <message> (see 'squama <cmd> --help')" to stderr; returns CLI_USAGE. */
int cli_usage(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* getopt_long's refusal c (':' a value missing, with ':' leading the option string; else
 * an unknown or ambiguous option, ambiguous ones named with the long options they begin)
 * as a usage error naming the option as typed. */
struct option;
int cli_bad_option(const char *cmd, char *const argv[], int c, const struct option *opts);

/* Parses "N" or "WxH" with both sides in [lo, hi]; 1 on success. */
int cli_parse_size(const char *s, int lo, int hi, int *w, int *h);

/* A time: "60", "60s", "2m", "1.5m", "1h" -> seconds; -1 when malformed, not > 0 or over
 * a week. */
double cli_parse_time(const char *s);

/* An option's value, all of it, as a decimal integer in [lo, hi]: 0, or -1 with err (when
 * not NULL) saying "<opt> must be <lo> to <hi>, got '<arg>'". Empty values, leading
 * spaces, trailing characters and overflow are refused. */
int cli_parse_int(const char *opt, const char *arg, long lo, long hi, long *out, SqError *err);

/* The same for a real number in [lo, hi]; NaN and infinities are refused too. */
int cli_parse_real(const char *opt, const char *arg, double lo, double hi, double *out, SqError *err);

/* Where the shipped presets live: $SQUAMA_PRESETS, else the source tree's presets/. */
const char *cli_presets_dir(void);

#endif
