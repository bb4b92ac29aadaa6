/* Host file helpers: whole-file reads, and writes that are never left
 * half done (a temporary file, fsync, rename). */
#ifndef EVO_FILEIO_H
#define EVO_FILEIO_H

#include <stddef.h>

#include "base/err.h"

/* The largest file evo_read_file reads: a file of a mind folder, a task,
 * a mind image, a PNG. The largest a user writes is a few hundred
 * kilobytes (a .net of EVO_NET_MAX_LINKS links); a larger one is damaged
 * or hostile, and reading it whole would cost its size in memory.
 * docs/formats.md, "Sizes". */
#define EVO_FILE_MAX ((size_t)16 << 20)

/* The largest file of a run folder evo reads back (log.csv,
 * checkpoint.lua, the networks a learning loop saved): a checkpoint holds
 * a whole population. */
#define EVO_RUN_FILE_MAX ((size_t)1 << 30)

/* Read a whole regular file of at most EVO_FILE_MAX bytes into a malloc'd
 * buffer (NUL-terminated, *len excludes the NUL). A larger file, or one
 * that is no regular file (a FIFO, a device), is refused before it is
 * read, with a message naming it (and the limit). Returns 0, or -1 with
 * err set. */
int evo_read_file(const char *path, char **data, size_t *len, evo_err *err);

/* evo_read_file with a limit of max bytes. */
int evo_read_file_max(const char *path, size_t max, char **data, size_t *len,
		      evo_err *err);

/* 1 when path names an existing regular file. */
int evo_file_exists(const char *path);

/* Write data to path atomically: readers see the old file or the whole
 * new one, never a part, even if the process is killed. The data goes to
 * a new file beside path (PATH.tmp.PID, or PATH.tmp.PID.N when that name
 * is taken), created with O_EXCL, so that nothing already there, a
 * symbolic link included, is written through; then it is renamed over
 * path, which replaces whatever path was (a symbolic link is replaced,
 * not followed). */
int evo_write_file_atomic(const char *path, const void *data, size_t len,
			  evo_err *err);

/* evo_write_file_atomic without its fsync: a killed process still leaves
 * the old file or the new one whole, but after a power cut the disk may
 * hold the old one. For files rewritten every generation of a learning
 * run (log.csv, best/): a sync each would cost more than a generation of
 * a fast task, and the checkpoint that follows syncs them
 * (evo_file_sync). */
int evo_write_file_replace(const char *path, const void *data, size_t len,
			   evo_err *err);

/* fsync the file at path (a regular file, not through a symbolic link).
 * 0, or -1 with err. */
int evo_file_sync(const char *path, evo_err *err);

/* Flush every file written so far to disk (sync): one flush for many
 * files written with evo_write_file_replace (MAP-Elites' thousands of
 * elites), where an fsync each would cost seconds. */
void evo_sync_all(void);

/* Create a new file beside path for writing (mode 0644 less the umask),
 * to be renamed over path once written: PATH.tmp.PID, or PATH.tmp.PID.N
 * when that name exists. Nothing that exists, a symbolic link included,
 * is opened. cap is tmp's size, at least strlen(path) + 48. Returns the
 * descriptor, with the name in tmp, or -1 with err. */
int evo_create_beside(const char *path, char *tmp, size_t cap, evo_err *err);

/* 0 when no folder of rel ("Skills/Avoid", "Runs/Avoid-seed1") under root
 * is a symbolic link, or -1 with err naming the first one that is. A mind
 * folder comes from anyone: a folder of it evo writes into must be its
 * own, not a link that sends the files elsewhere. Folders that do not
 * exist yet are fine; root itself is the user's and not looked at. */
int evo_folder_check_links(const char *root, const char *rel, evo_err *err);

/* Format a path into buf (cap bytes). Returns 0, or -1 with err set to
 * "PATH...: path too long (N bytes; at most M)" when it does not fit: a
 * cut path would name another file. */
int evo_path_fmt(char *buf, size_t cap, evo_err *err, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

#endif
