#define _POSIX_C_SOURCE 200809L
#include "base/fileio.h"

#include <errno.h>
#include <stdarg.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int evo_file_exists(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int evo_read_file(const char *path, char **data, size_t *len, evo_err *err)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return evo_fail(err, "%s: cannot open: %s", path,
				strerror(errno));
	size_t cap = 4096, n = 0;
	char *buf = malloc(cap);
	for (;;) {
		if (!buf) {
			fclose(f);
			return evo_fail(err, "%s: out of memory", path);
		}
		n += fread(buf + n, 1, cap - n - 1, f);
		if (n < cap - 1)
			break;
		char *bigger = realloc(buf, cap * 2);
		if (!bigger)
			free(buf);
		buf = bigger;
		cap *= 2;
	}
	int bad = ferror(f);
	fclose(f);
	if (bad) {
		free(buf);
		return evo_fail(err, "%s: read error", path);
	}
	buf[n] = 0;
	*data = buf;
	*len = n;
	return 0;
}

int evo_write_file_atomic(const char *path, const void *data, size_t len,
			  evo_err *err)
{
	size_t plen = strlen(path);
	char *tmp = malloc(plen + 32);
	if (!tmp)
		return evo_fail(err, "%s: out of memory", path);
	snprintf(tmp, plen + 32, "%s.tmp.%ld", path, (long)getpid());
	int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	if (fd < 0) {
		evo_fail(err, "%s: cannot create: %s", tmp, strerror(errno));
		free(tmp);
		return -1;
	}
	const char *p = data;
	size_t left = len;
	while (left) {
		ssize_t w = write(fd, p, left);
		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0) {
			evo_fail(err, "%s: write failed: %s", tmp,
				 strerror(errno));
			close(fd);
			unlink(tmp);
			free(tmp);
			return -1;
		}
		p += w;
		left -= (size_t)w;
	}
	if (fsync(fd) != 0 || close(fd) != 0 || rename(tmp, path) != 0) {
		evo_fail(err, "%s: cannot save: %s", path, strerror(errno));
		unlink(tmp);
		free(tmp);
		return -1;
	}
	free(tmp);
	return 0;
}

int evo_path_fmt(char *buf, size_t cap, evo_err *err, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	int n = vsnprintf(buf, cap, fmt, ap);
	va_end(ap);
	if (n >= 0 && (size_t)n < cap)
		return 0;
	/* The start of the path says which one; all of it would not fit
	 * the message either. */
	return evo_fail(err, "%.80s...: path too long (%d bytes; at most %zu)",
			buf, n, cap ? cap - 1 : 0);
}
