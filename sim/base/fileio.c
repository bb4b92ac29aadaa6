#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* sync() */
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

/* max as a user reads it: "16 MiB", "1 GiB", else bytes. */
static void size_text(char *buf, size_t cap, size_t max)
{
	if (max >= (1u << 30) && max % (1u << 30) == 0)
		snprintf(buf, cap, "%zu GiB", max >> 30);
	else if (max >= (1u << 20) && max % (1u << 20) == 0)
		snprintf(buf, cap, "%zu MiB", max >> 20);
	else
		snprintf(buf, cap, "%zu bytes", max);
}

static int too_large(const char *path, unsigned long long size, size_t max,
		     evo_err *err)
{
	char limit[32];
	size_text(limit, sizeof limit, max);
	return evo_fail(err,
			"%s: %llu bytes, larger than evo reads (at most %s)",
			path, size, limit);
}

int evo_read_file_max(const char *path, size_t max, char **data, size_t *len,
		      evo_err *err)
{
	/* O_NONBLOCK: opening a FIFO would wait for a writer; fstat then
	 * refuses it, and anything else that is no regular file (a device
	 * such as /dev/zero never ends), before a byte is read. */
	int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
	if (fd < 0)
		return evo_fail(err, "%s: cannot open: %s", path,
				strerror(errno));
	struct stat st;
	if (fstat(fd, &st) != 0) {
		int e = errno;
		close(fd);
		return evo_fail(err, "%s: cannot read: %s", path, strerror(e));
	}
	if (!S_ISREG(st.st_mode)) {
		close(fd);
		return evo_fail(err, "%s: not a regular file", path);
	}
	/* The size is known before the read, so a file that is too large
	 * costs no memory; one that grows while it is read is cut off at
	 * max + 1 bytes and refused the same way. */
	if (st.st_size < 0 || (unsigned long long)st.st_size > max) {
		close(fd);
		return too_large(path, (unsigned long long)st.st_size, max,
				 err);
	}
	size_t cap = (size_t)st.st_size + 2, n = 0;
	char *buf = malloc(cap);
	if (!buf) {
		close(fd);
		return evo_fail(err, "%s: out of memory", path);
	}
	for (;;) {
		if (n == cap - 1) {
			if (n > max)
				break;
			size_t more = cap <= max / 2 ? 2 * cap : max + 2;
			char *bigger = realloc(buf, more);
			if (!bigger) {
				free(buf);
				close(fd);
				return evo_fail(err, "%s: out of memory", path);
			}
			buf = bigger;
			cap = more;
		}
		ssize_t r = read(fd, buf + n, cap - 1 - n);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			int e = errno;
			free(buf);
			close(fd);
			return evo_fail(err, "%s: cannot read: %s", path,
					strerror(e));
		}
		if (r == 0)
			break;
		n += (size_t)r;
	}
	close(fd);
	if (n > max) {
		free(buf);
		return too_large(path, (unsigned long long)n, max, err);
	}
	buf[n] = 0;
	*data = buf;
	*len = n;
	return 0;
}

int evo_read_file(const char *path, char **data, size_t *len, evo_err *err)
{
	return evo_read_file_max(path, EVO_FILE_MAX, data, len, err);
}

/* O_EXCL fails on any name that exists, a symbolic link included (which
 * O_NOFOLLOW says again), so a file or link planted under the name, or one
 * a killed run left, is never written through; the next name is tried
 * instead. */
int evo_create_beside(const char *path, char *tmp, size_t cap, evo_err *err)
{
	long pid = (long)getpid();
	if (cap < strlen(path) + 48)
		return evo_fail(err, "%.80s...: path too long", path);
	for (int k = 0; k < 100; k++) {
		if (k == 0)
			snprintf(tmp, cap, "%s.tmp.%ld", path, pid);
		else
			snprintf(tmp, cap, "%s.tmp.%ld.%d", path, pid, k);
		int fd = open(tmp,
			      O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW |
				  O_CLOEXEC,
			      0644);
		if (fd >= 0)
			return fd;
		if (errno != EEXIST)
			return evo_fail(err, "%s: cannot create: %s", tmp,
					strerror(errno));
	}
	return evo_fail(err,
			"%s: cannot create a temporary file beside it: "
			"%s.tmp.%ld and 99 more names are taken",
			path, path, pid);
}

/* evo_write_file_atomic and evo_write_file_replace: the same, with or
 * without the fsync before the rename. */
static int write_beside(const char *path, const void *data, size_t len,
			int sync, evo_err *err)
{
	size_t cap = strlen(path) + 48;
	char *tmp = malloc(cap);
	if (!tmp)
		return evo_fail(err, "%s: out of memory", path);
	int fd = evo_create_beside(path, tmp, cap, err);
	if (fd < 0) {
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
	/* rename replaces path's directory entry: a symbolic link planted
	 * at path is replaced by the file, never followed. */
	int bad = sync && fsync(fd) != 0;
	bad |= close(fd) != 0;
	if (bad || rename(tmp, path) != 0) {
		evo_fail(err, "%s: cannot save: %s", path, strerror(errno));
		unlink(tmp);
		free(tmp);
		return -1;
	}
	free(tmp);
	return 0;
}

int evo_write_file_atomic(const char *path, const void *data, size_t len,
			  evo_err *err)
{
	return write_beside(path, data, len, 1, err);
}

int evo_write_file_replace(const char *path, const void *data, size_t len,
			   evo_err *err)
{
	return write_beside(path, data, len, 0, err);
}

int evo_file_sync(const char *path, evo_err *err)
{
	int fd = open(path, O_RDONLY | O_NOFOLLOW);
	if (fd < 0)
		return evo_fail(err, "%s: cannot open it to sync it: %s", path,
				strerror(errno));
	int bad = fsync(fd) != 0;
	int e = errno;
	close(fd);
	if (bad)
		return evo_fail(err, "%s: cannot sync it: %s", path,
				strerror(e));
	return 0;
}

void evo_sync_all(void) { sync(); }

int evo_folder_check_links(const char *root, const char *rel, evo_err *err)
{
	char p[1400];
	if (evo_path_fmt(p, sizeof p, err, "%s/%s", root, rel))
		return -1;
	size_t base = strlen(p) - strlen(rel);
	for (size_t i = base;; i++) {
		char c = p[i];
		if (c != '/' && c != 0)
			continue;
		p[i] = 0;
		struct stat st;
		if (i > base && lstat(p, &st) == 0 && S_ISLNK(st.st_mode))
			return evo_fail(err,
					"%s is a symbolic link: evo writes "
					"into a mind folder's own folders, "
					"never through a link it ships "
					"(replace it by a folder)",
					p);
		p[i] = c;
		if (!c)
			return 0;
	}
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
