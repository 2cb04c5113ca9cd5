/* squama: fits a procedural snake-skin texture generator to photos.
 * `squama <command> [options]`; every command has --help. */
#define _XOPEN_SOURCE 700

#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "squama/io.h"

static const CliCommand commands[] = {
    {"params", "list the generator's parameters (table, --json or --markdown)", cmd_params},
    {"presets", "list the shipped presets; validate preset and CA descriptor files",
     cmd_presets},
    {"render", "render a preset's basecolor, height, roughness and normal maps", cmd_render},
    {"photo", "a synthetic photo of a preset on a snake body, with mask and truth", cmd_photo},
    {"prepare", "find the snake in a photo and straighten its body into a strip", cmd_prepare},
    {"score", "score presets against a photo: objectives and Pareto rank", cmd_score},
    {"fit", "fit the generator to a photo: best preset, front, textures, report", cmd_fit},
    {"seed", "starting presets for artists: diverse, near a preset, or from a photo", cmd_seed},
    {"batch", "fit every photo of a manifest into a browsable catalogue (cores, MPI, Slurm)", cmd_batch},
};
enum { NCOMMANDS = sizeof commands / sizeof commands[0] };

static void usage(FILE *f)
{
    fprintf(f,
            "usage: squama <command> [options]\n"
            "\n"
            "Fits a procedural snake-skin texture generator (Pinheiro 2017) to photos.\n"
            "\n"
            "commands:\n");
    for (int i = 0; i < NCOMMANDS; i++)
        fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(f,
            "\n"
            "options:\n"
            "  -h, --help     show this help\n"
            "  --version      show the version\n"
            "\n"
            "'squama <command> --help' describes a command.\n");
}

/* SIGINT, SIGTERM or SIGHUP: the files being written are removed, then the signal ends
 * the program as it would have (cli.h). */
void cli_fatal_signal(int sig)
{
    if (cli_signal_waits(sig)) /* outputs moving into place: the signal comes back after */
        return;
    sq_io_remove_temps();
    signal(sig, SIG_DFL);
    raise(sig);
}

/* At exit: a write that a library ended the program in (libjpeg on a full disk) said in
 * squama's words, and every temporary file removed. */
static void at_exit(void)
{
    const char *w = sq_io_image_under_way();
    char shown[4200];
    if (w)
        fprintf(stderr, "squama: cannot write image: the write failed (is the disk full?) (%s)\n",
                cli_staging_shown(w, shown, sizeof shown));
    sq_io_remove_temps();
}

int main(int argc, char **argv)
{
    cli_batch_child();
    static const int fatal[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++) {
        struct sigaction sa = {0}, old;
        sa.sa_handler = cli_fatal_signal;
        sa.sa_flags = SA_RESTART; /* it returns, on a thread other than a commit's (cli_signal_waits) */
        sigemptyset(&sa.sa_mask);
        if (sigaction(fatal[i], NULL, &old) == 0 && old.sa_handler != SIG_IGN) /* nohup's stays */
            sigaction(fatal[i], &sa, NULL);
    }
    /* a file size limit (ulimit -f) makes a write fail, which is reported, rather than kill
     * the program; a library that exit()s on a failed write (libjpeg) still leaves no
     * temporary file behind */
    signal(SIGXFSZ, SIG_IGN);
    atexit(at_exit);
    if (argc < 2)
        return cli_usage(NULL, "no command given");
    const char *cmd = argv[1];
    if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0) {
        usage(stdout);
        return CLI_OK;
    }
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        printf("squama %s\n", SQUAMA_VERSION);
        return CLI_OK;
    }
    for (int i = 0; i < NCOMMANDS; i++)
        if (strcmp(cmd, commands[i].name) == 0)
            return commands[i].run(argc - 1, argv + 1);
    if (cmd[0] == '-')
        return cli_usage(NULL, "unknown option '%s'", cmd);
    return cli_usage(NULL, "unknown command '%s'", cmd);
}
