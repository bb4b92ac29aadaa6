/* Helpers for tests that drive the evo program from the shell: where evo
 * is, a fresh temporary folder, commands built printf-style, files read
 * back. */
#ifndef EVO_TEST_CLI_H
#define EVO_TEST_CLI_H

#include <stddef.h>

extern char cli_evo[256]; /* $EVO_BUILD/evo (default build/evo) */
extern char cli_tmp[128]; /* made by cli_setup, removed by cli_cleanup */

/* Where tests make their files: $TMPDIR, else /tmp. */
const char *cli_tmp_root(void);

/* Fill cli_evo and make cli_tmp (ROOT/evo-test-<name>-XXXXXX, ROOT from
 * cli_tmp_root). 0 or -1. */
int cli_setup(const char *name);
void cli_cleanup(void);

/* Run a shell command; its exit status, or -1 when it did not exit. */
int cli_sh(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Run a shell command with its stdout and stderr in out (NUL-ended). */
int cli_capture(char *out, size_t cap, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/* A file's whole text (free it), or NULL. */
char *cli_read(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Write text as the file at the printf-style path, whole. 0 or -1. */
int cli_write(const char *text, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* Lines of text that start with prefix (text may be NULL: 0). */
int cli_count_lines(const char *text, const char *prefix);

/* A learning run's log.csv without its two time columns, so runs can be
 * compared (free it), or NULL. */
char *cli_fitness_log(const char *run_dir);

/* Start `sh -c CMD` (SIGINT and SIGTERM at their defaults; CMD begins
 * with `exec`, or the signal kills the shell and not the program), wait
 * until the file `ready` holds the text `mark` (at most 60 s), then
 * `delay` seconds more, send it signal sig and wait for it to end (at
 * most 10 s; then SIGKILL). Fills *status (as waitpid gives it) and
 * *seconds (from the signal to the end). Returns 0, or -1 when it ended
 * before the signal or had to be killed. */
int cli_stop(const char *cmd, const char *ready, const char *mark,
	     double delay, int sig, int *status, double *seconds);

#endif
