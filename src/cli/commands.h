/* sdftrace CLI — the subcommands. Each takes the arguments after its name
 * (argv[0] is the subcommand) and returns the process exit status: 0 ok,
 * 1 a failure while working, 2 a bad command line. Errors are one line on
 * stderr; results go to stdout. To add a command, declare its two functions
 * here and add one line to the table in main.c. */
#ifndef SDFTRACE_COMMANDS_H
#define SDFTRACE_COMMANDS_H

#include <stdio.h>

typedef struct cli_command {
    const char *name;
    const char *summary; /* one line for `sdftrace --help` */
    int (*run)(int argc, char **argv);
    void (*help)(FILE *out); /* usage and every option with its default */
} cli_command;

int cmd_scenes(int argc, char **argv);
void cmd_scenes_help(FILE *out);

int cmd_render(int argc, char **argv);
void cmd_render_help(FILE *out);

int cmd_bake(int argc, char **argv);
void cmd_bake_help(FILE *out);

/* Prints "sdftrace CMD: MSG" as one line on stderr (CMD NULL: "sdftrace: MSG"). */
void cli_error(const char *cmd, const char *msg);

#endif
