/* cli.h - subcommands of the granary driver. Each returns the process exit status
 * (0 success, 1 failure reported on stderr, 2 usage error). */
#ifndef GRANARY_CLI_H
#define GRANARY_CLI_H
#include <string>

#include "granary.h"

/* --verbose: error messages are followed by where the library detected them */
extern int cli_verbose;
/* the last error message, with its location when --verbose (static buffer) */
const char *cli_error(void);

/* Processes (src/cli/mpi.cpp): build/granary-mpi runs the replicas of `granary run` on the MPI
 * processes it is started on; build/granary is one process (these are then trivial). */
int cli_mpi_init(int *argc, char ***argv); /* 0 on success */
void cli_mpi_finalize(void);
int cli_mpi_rank(void);
int cli_mpi_size(void);
int cli_mpi_local_size(void); /* the processes on this machine (build/granary: 1) */
int cli_mpi_all(int ok); /* collective: 1 when every process passes ok != 0 */
int cli_mpi_bcast(std::string *b); /* collective: rank 0's bytes to every process, waited for at most the timeout; 0 on success */
void cli_mpi_stats(long long *steps, long long *bytes); /* gathers, and bytes rank 0 received */
/* the process group of a decomposed GSRD run (src/srd/bricks.h): MPI_COMM_WORLD in
 * build/granary-mpi, one process in build/granary */
const struct srd_bricks_comm *cli_mpi_bricks_comm(void);
void cli_mpi_abort(int code); /* stops every process (build/granary: nothing) */
/* collective: the processes in `groups` groups of consecutive ranks, each the process group of one
 * replica's split gas (srd_bricks_set_run_comm_); nothing when groups <= 1 or does not divide the
 * processes (the run driver refuses that); 0 on success */
int cli_mpi_bricks_groups(int groups);
/* the longest one process waits in one exchange, reduction or distributed transform of a decomposed
 * run, or in one gather or broadcast of the replicas, before it stops every process, naming the
 * process that does not answer where it can; a wait stuck inside MPI is ended by a watchdog thread a
 * second later (0: no limit; default 600 s, which `granary run` sets to its --timeout, 0 unless given) */
void cli_mpi_set_timeout(double seconds);
/* an option's value as seconds in [0, 1e7], the whole string a number (main.cpp): 1, else 0 */
int cli_seconds(const char *v, double *out);

int cli_info(int argc, char **argv);
int cli_run(int argc, char **argv);
int cli_theory(int argc, char **argv);
int cli_keys(int argc, char **argv); /* keys.cpp */
int cli_decompose(int argc, char **argv); /* decompose.cpp */

#endif
