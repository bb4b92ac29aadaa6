/* evo — whether what evo prints goes to a person at a terminal, so that a
 * progress line may be rewritten in place ('\r', an escape code to clear
 * the rest of the line), or to a file or pipe that must get plain lines.
 *
 * One rule for a plain run and a launched one: the answer is isatty of
 * where the output ends up. Under mpirun a rank's stdout is a terminal
 * that mpirun made to forward it, whatever mpirun's own output is (a
 * SLURM log, `mpirun ... > file`); there the answer is that of the
 * launcher's own output. */
#ifndef EVO_TERMINAL_H
#define EVO_TERMINAL_H

/* 1 when output written to fd ends at a terminal, else 0. Under an MPI
 * launcher (its environment says so) that is the first ancestor process
 * whose same fd is not this process's: a terminal there answers 1, a
 * file, pipe or anything that cannot be looked at (no /proc) answers 0,
 * the safe side for a log. */
int evo_terminal_output(int fd);

#endif
