/* sdftrace scenes — one line per procedural scene: name and description. */
#include <string.h>

#include "commands.h"
#include "sdftrace/scene.h"

void cmd_scenes_help(FILE *out)
{
    fprintf(out, "usage: sdftrace scenes\n  lists the procedural scenes: NAME  DESCRIPTION, one per line\n");
}

int cmd_scenes(int argc, char **argv)
{
    if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        cmd_scenes_help(stdout);
        return 0;
    }
    if (argc > 1) {
        char msg[256];
        snprintf(msg, sizeof msg, "unexpected argument '%s'", argv[1]);
        cli_error("scenes", msg);
        return 2;
    }
    size_t n = 0;
    const sdft_scene *const *all = sdft_scenes(&n);
    for (size_t i = 0; i < n; i++)
        printf("%-14s %s\n", all[i]->name, all[i]->description);
    return 0;
}
