/* sdftrace — the command-line tool: a table of subcommands. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "sdftrace/error.h"

static const cli_command commands[] = {
    {"scenes", "list the procedural scenes, one per line", cmd_scenes, cmd_scenes_help},
    {"render", "render a scene to OpenEXR (and PNG, heatmaps, JSON statistics)", cmd_render, cmd_render_help},
    {"bake", "sample a scene into an OpenVDB level set (.vdb) or NanoVDB grid (.nvdb)", cmd_bake, cmd_bake_help},
};
enum { COMMAND_COUNT = sizeof commands / sizeof commands[0] };

void cli_error(const char *cmd, const char *msg)
{
    fprintf(stderr, "sdftrace%s%s: %s\n", cmd ? " " : "", cmd ? cmd : "", msg);
}

static void help(FILE *out)
{
    fprintf(out, "sdftrace: sphere tracing of signed distance fields with four tracing variants\n\n"
                 "usage: sdftrace COMMAND [OPTIONS]    (sdftrace COMMAND --help for one command)\n"
                 "       sdftrace --version\n\ncommands:\n");
    for (int i = 0; i < COMMAND_COUNT; i++)
        fprintf(out, "  %-8s  %s\n", commands[i].name, commands[i].summary);
    for (int i = 0; i < COMMAND_COUNT; i++) {
        fprintf(out, "\n");
        commands[i].help(out);
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        help(stderr);
        return 2;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
        help(stdout);
        return 0;
    }
    if (strcmp(argv[1], "--version") == 0) {
        const int v = sdft_version();
        printf("sdftrace %d.%d.%d\n", v / 10000, v / 100 % 100, v % 100);
        return 0;
    }
    for (int i = 0; i < COMMAND_COUNT; i++)
        if (strcmp(argv[1], commands[i].name) == 0)
            return commands[i].run(argc - 1, argv + 1);
    char msg[256];
    snprintf(msg, sizeof msg, "unknown command '%s' (try: sdftrace --help)", argv[1]);
    cli_error(NULL, msg);
    return 2;
}
