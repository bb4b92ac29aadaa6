/* Host file helpers: whole-file reads, and writes that are never left
 * half done (a temporary file, fsync, rename). */
#ifndef EVO_FILEIO_H
#define EVO_FILEIO_H

#include <stddef.h>

#include "base/err.h"

/* Read a whole file into a malloc'd buffer (NUL-terminated, *len excludes
 * the NUL). Returns 0, or -1 with err set. */
int evo_read_file(const char *path, char **data, size_t *len, evo_err *err);

/* 1 when path names an existing regular file. */
int evo_file_exists(const char *path);

/* Write data to path atomically: readers see the old file or the whole
 * new one, never a part, even if the process is killed. */
int evo_write_file_atomic(const char *path, const void *data, size_t len,
			  evo_err *err);

/* Format a path into buf (cap bytes). Returns 0, or -1 with err set to
 * "PATH...: path too long (N bytes; at most M)" when it does not fit: a
 * cut path would name another file. */
int evo_path_fmt(char *buf, size_t cap, evo_err *err, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

#endif
