/* Terminal or not (sim/base/terminal.h). */
#define _POSIX_C_SOURCE 200809L
#include "base/terminal.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Ancestors looked at before giving up (mpirun, orted, a shell between). */
#define MAX_HOPS 16

static int launched_by_mpi(void)
{
	static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK",
					   "PMI_RANK"};
	for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
		if (getenv(vars[i]))
			return 1;
	return 0;
}

/* The parent of pid from /proc/PID/stat (the field after the state,
 * which follows the last ')' of the command name), or -1. */
static long parent_of(long pid)
{
	char path[64], buf[512];
	snprintf(path, sizeof path, "/proc/%ld/stat", pid);
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	size_t n = fread(buf, 1, sizeof buf - 1, f);
	fclose(f);
	buf[n] = 0;
	const char *p = strrchr(buf, ')');
	char state;
	long ppid;
	if (!p || sscanf(p + 1, " %c %ld", &state, &ppid) != 2)
		return -1;
	return ppid;
}

/* Is /proc/PID/fd/FD a terminal? 0 for a file, a pipe, /dev/null or what
 * cannot be opened. */
static int proc_fd_is_terminal(const char *path, const struct stat *st)
{
	if (!S_ISCHR(st->st_mode))
		return 0;
	int fd = open(path, O_RDONLY | O_NOCTTY | O_NONBLOCK);
	if (fd < 0)
		return 0;
	int tty = isatty(fd);
	close(fd);
	return tty;
}

int evo_terminal_output(int fd)
{
	if (!isatty(fd))
		return 0;
	if (!launched_by_mpi())
		return 1;
	struct stat own;
	if (fstat(fd, &own))
		return 0;
	long pid = (long)getppid();
	for (int hop = 0; hop < MAX_HOPS && pid > 1; hop++) {
		char path[64];
		struct stat st;
		snprintf(path, sizeof path, "/proc/%ld/fd/%d", pid, fd);
		if (stat(path, &st))
			return 0;
		if (st.st_dev != own.st_dev || st.st_ino != own.st_ino ||
		    st.st_rdev != own.st_rdev)
			return proc_fd_is_terminal(path, &st);
		pid = parent_of(pid);
	}
	return 0;
}
