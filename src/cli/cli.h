/* cli.h - subcommands of the granary driver. Each returns the process exit status
 * (0 success, 1 failure reported on stderr, 2 usage error). */
#ifndef GRANARY_CLI_H
#define GRANARY_CLI_H
#include "granary.h"

int cli_info(int argc, char **argv);
int cli_run(int argc, char **argv);
int cli_theory(int argc, char **argv);

#endif
