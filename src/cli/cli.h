/* cli.h - subcommands of the granary driver. Each returns the process exit status
 * (0 success, 1 failure reported on stderr, 2 usage error). */
#ifndef GRANARY_CLI_H
#define GRANARY_CLI_H
#include "granary.h"

/* --verbose: error messages are followed by where the library detected them */
extern int cli_verbose;
/* the last error message, with its location when --verbose (static buffer) */
const char *cli_error(void);

int cli_info(int argc, char **argv);
int cli_run(int argc, char **argv);
int cli_theory(int argc, char **argv);

#endif
