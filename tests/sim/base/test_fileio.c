/* Errors and files (sim/base/err.c, sim/base/fileio.c): evo_fail formats
 * and tolerates a NULL message; a file reads back byte for byte, NUL
 * included; a missing file's message names it and why; an atomic write
 * replaces a file whole and leaves no temporary file beside it (with
 * its fsync or, for a run's per-generation files, without), and
 * writes through no symbolic link a mind folder plants, at the temporary
 * name or the final one; a file larger than the limit is refused with its
 * name and the limit before it costs memory, and a FIFO or a device before
 * it is read. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/fileio.h"
#include "harness.h"
#include "support/cli.h"

static char dir[64];

TEST(fail_formats_and_returns_minus_one)
{
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_fail(&err, "%s:%d: expected %s", "a.ades", 3, "x"),
		     -1);
	CHECK_EQ_STR(err.msg, "a.ades:3: expected x");
	CHECK_EQ_INT(evo_fail(NULL, "nobody reads %d", 1), -1);
	/* a message longer than the buffer is cut, never overflows */
	char big[2000];
	memset(big, 'x', sizeof big - 1);
	big[sizeof big - 1] = 0;
	evo_fail(&err, "%s", big);
	CHECK_EQ_INT((long long)strlen(err.msg), (long long)sizeof err.msg - 1);
}

TEST(write_then_read_back_byte_for_byte)
{
	char path[128];
	snprintf(path, sizeof path, "%s/data.bin", dir);
	const char data[] = {'a', 0, 'b', '\n', (char)0xFF};
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_write_file_atomic(path, data, sizeof data, &err), 0);
	CHECK(evo_file_exists(path));
	char *back = NULL;
	size_t len = 0;
	CHECK_EQ_INT(evo_read_file(path, &back, &len, &err), 0);
	CHECK_EQ_INT((long long)len, (long long)sizeof data);
	CHECK(back && memcmp(back, data, sizeof data) == 0);
	CHECK(back && back[len] == 0);
	free(back);
}

TEST(a_missing_file_is_named_with_the_reason)
{
	char path[128];
	snprintf(path, sizeof path, "%s/nothere.txt", dir);
	evo_err err = {{0}};
	char *back = NULL;
	size_t len = 0;
	CHECK_EQ_INT(evo_read_file(path, &back, &len, &err), -1);
	CHECK_CONTAINS(err.msg, path);
	CHECK_CONTAINS(err.msg, "No such file");
	CHECK(!evo_file_exists(path));
	CHECK(!evo_file_exists(dir)); /* a folder is not a file */
}

TEST(an_atomic_write_replaces_whole_and_leaves_nothing_beside)
{
	char path[128];
	snprintf(path, sizeof path, "%s/net.txt", dir);
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_write_file_atomic(path, "old old old", 11, &err), 0);
	CHECK_EQ_INT(evo_write_file_atomic(path, "new", 3, &err), 0);
	char *back = NULL;
	size_t len = 0;
	CHECK_EQ_INT(evo_read_file(path, &back, &len, &err), 0);
	CHECK_EQ_STR(back, "new");
	free(back);
	int n = 0;
	DIR *d = opendir(dir);
	struct dirent *e;
	while (d && (e = readdir(d)))
		n += e->d_name[0] != '.';
	if (d)
		closedir(d);
	CHECK_EQ_INT(n, 2); /* data.bin and net.txt, no temporary file */
	/* a folder that does not exist is an error naming the path */
	char bad[160];
	snprintf(bad, sizeof bad, "%s/no/such/folder/x", dir);
	CHECK_EQ_INT(evo_write_file_atomic(bad, "x", 1, &err), -1);
	CHECK_CONTAINS(err.msg, "no/such/folder");
}

/* log.csv and best/ are replaced each generation without a sync of
 * their own: the same whole-file replacement, nothing left beside it;
 * the sync the checkpoint does first names a file that is not there. */
TEST(a_replace_write_is_atomic_and_a_sync_names_a_missing_file)
{
	char path[200], sub[100];
	snprintf(sub, sizeof sub, "%s/run", dir);
	CHECK_EQ_INT(mkdir(sub, 0755), 0);
	snprintf(path, sizeof path, "%s/log.csv", sub);
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_write_file_replace(path, "generation,best\n", 16, &err),
		     0);
	CHECK_EQ_INT(evo_write_file_replace(path, "0,9\n", 4, &err), 0);
	char *back = NULL;
	size_t len = 0;
	CHECK_EQ_INT(evo_read_file(path, &back, &len, &err), 0);
	CHECK_EQ_STR(back, "0,9\n");
	free(back);
	int n = 0;
	DIR *d = opendir(sub);
	struct dirent *e;
	while (d && (e = readdir(d)))
		n += e->d_name[0] != '.';
	if (d)
		closedir(d);
	CHECK_EQ_INT(n, 1); /* log.csv, no temporary file */
	CHECK_EQ_INT(evo_file_sync(path, &err), 0);
	char gone[200];
	snprintf(gone, sizeof gone, "%s/checkpoint.lua", sub);
	CHECK_EQ_INT(evo_file_sync(gone, &err), -1);
	CHECK_CONTAINS(err.msg, gone);
	CHECK_CONTAINS(err.msg, "No such file");
	unlink(path);
	rmdir(sub);
}

/* The text of the file at path, or "" (static). */
static const char *text_of(const char *path)
{
	static char buf[256];
	buf[0] = 0;
	FILE *f = fopen(path, "r");
	if (f) {
		size_t n = fread(buf, 1, sizeof buf - 1, f);
		buf[n] = 0;
		fclose(f);
	}
	return buf;
}

static int is_regular(const char *path)
{
	struct stat st;
	return lstat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* A shared mind folder ships Skills/Avoid/Avoid.net.tmp.<pid> as a
 * symbolic link to a file of the user's, and Avoid.net itself as a link
 * to another: saving the champion must change neither, and leave
 * Avoid.net a file of its own with the champion in it. */
TEST(an_atomic_write_goes_through_no_planted_link)
{
	char skill[128], victim[160], victim2[160], absent[160];
	snprintf(skill, sizeof skill, "%s/Skills", dir);
	mkdir(skill, 0755);
	snprintf(skill, sizeof skill, "%s/Skills/Avoid", dir);
	CHECK_EQ_INT(mkdir(skill, 0755), 0);
	snprintf(victim, sizeof victim, "%s/bashrc", dir);
	snprintf(victim2, sizeof victim2, "%s/profile", dir);
	snprintf(absent, sizeof absent, "%s/made-by-evo", dir);
	CHECK_EQ_INT(cli_write("precious\n", "%s", victim), 0);
	CHECK_EQ_INT(cli_write("also precious\n", "%s", victim2), 0);
	char net[200], tmp[240], tmp1[240];
	snprintf(net, sizeof net, "%s/Avoid.net", skill);
	snprintf(tmp, sizeof tmp, "%s.tmp.%ld", net, (long)getpid());
	snprintf(tmp1, sizeof tmp1, "%s.tmp.%ld.1", net, (long)getpid());
	CHECK_EQ_INT(symlink(victim, tmp), 0);
	/* a dangling link, which O_CREAT alone would create a file for */
	CHECK_EQ_INT(symlink(absent, tmp1), 0);
	CHECK_EQ_INT(symlink(victim2, net), 0);
	evo_err err = {{0}};
	CHECK_EQ_INT(evo_write_file_atomic(net, "champion\n", 9, &err), 0);
	CHECK_EQ_STR(err.msg, "");
	CHECK_EQ_STR(text_of(victim), "precious\n");
	CHECK_EQ_STR(text_of(victim2), "also precious\n");
	CHECK(access(absent, F_OK) != 0);
	CHECK(is_regular(net));
	CHECK_EQ_STR(text_of(net), "champion\n");
	/* and again, with the links still planted: the same */
	CHECK_EQ_INT(evo_write_file_atomic(net, "second\n", 7, &err), 0);
	CHECK_EQ_STR(text_of(victim), "precious\n");
	CHECK_EQ_STR(text_of(net), "second\n");
	CHECK(access(absent, F_OK) != 0);
}

/* Resident memory now, in kilobytes (the high-water mark). */
static long max_rss_kb(void)
{
	struct rusage ru;
	getrusage(RUSAGE_SELF, &ru);
	return ru.ru_maxrss;
}

/* A sparse file one byte past the limit costs no disk, and would cost
 * 16 MiB of memory read whole: it is refused by its size, naming the file
 * and the limit, and memory stays as it was. */
TEST(a_file_past_the_limit_is_refused_by_name_before_it_is_read)
{
	char path[128];
	snprintf(path, sizeof path, "%s/huge.net", dir);
	int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	CHECK(fd >= 0);
	CHECK_EQ_INT(ftruncate(fd, (off_t)(16 << 20) + 1), 0);
	close(fd);
	long before = max_rss_kb();
	evo_err err = {{0}};
	char *back = NULL;
	size_t len = 0;
	CHECK_EQ_INT(evo_read_file(path, &back, &len, &err), -1);
	CHECK(back == NULL);
	CHECK_CONTAINS(err.msg, path);
	CHECK_CONTAINS(err.msg, "16777217 bytes");
	CHECK_CONTAINS(err.msg, "at most 16 MiB");
	CHECK(max_rss_kb() - before < 4096);
	/* 1.5 GB, as a hostile mind folder would ship it, for a run
	 * folder's limit of 1 GiB */
	fd = open(path, O_WRONLY | O_TRUNC);
	CHECK(fd >= 0);
	CHECK_EQ_INT(ftruncate(fd, (off_t)1500000000), 0);
	close(fd);
	CHECK_EQ_INT(evo_read_file_max(path, (size_t)1 << 30, &back, &len,
				       &err),
		     -1);
	CHECK_CONTAINS(err.msg, "1500000000 bytes");
	CHECK_CONTAINS(err.msg, "at most 1 GiB");
	CHECK(max_rss_kb() - before < 4096);
	unlink(path);
	/* at the limit it reads; one byte more it does not */
	snprintf(path, sizeof path, "%s/small.txt", dir);
	CHECK_EQ_INT(cli_write("0123456789", "%s", path), 0);
	CHECK_EQ_INT(evo_read_file_max(path, 10, &back, &len, &err), 0);
	CHECK_EQ_INT((long long)len, 10);
	free(back);
	back = NULL;
	CHECK_EQ_INT(evo_read_file_max(path, 9, &back, &len, &err), -1);
	CHECK_CONTAINS(err.msg, "10 bytes");
	CHECK_CONTAINS(err.msg, "at most 9 bytes");
	unlink(path);
}

/* A FIFO a mind folder ships as a .net would wait for a writer forever;
 * /dev/zero never ends. Neither is read. */
TEST(a_fifo_or_a_device_is_no_file_to_read)
{
	char path[128];
	snprintf(path, sizeof path, "%s/fifo.net", dir);
	CHECK_EQ_INT(mkfifo(path, 0644), 0);
	evo_err err = {{0}};
	char *back = NULL;
	size_t len = 0;
	CHECK_EQ_INT(evo_read_file(path, &back, &len, &err), -1);
	CHECK_CONTAINS(err.msg, path);
	CHECK_CONTAINS(err.msg, "not a regular file");
	unlink(path);
	CHECK_EQ_INT(evo_read_file("/dev/zero", &back, &len, &err), -1);
	CHECK_CONTAINS(err.msg, "/dev/zero: not a regular file");
	CHECK(back == NULL);
}

int main(void)
{
	snprintf(dir, sizeof dir, "%s/evo-fileio-XXXXXX", cli_tmp_root());
	if (!mkdtemp(dir))
		return 1;
	RUN(fail_formats_and_returns_minus_one);
	RUN(write_then_read_back_byte_for_byte);
	RUN(a_missing_file_is_named_with_the_reason);
	RUN(an_atomic_write_replaces_whole_and_leaves_nothing_beside);
	RUN(an_atomic_write_goes_through_no_planted_link);
	RUN(a_replace_write_is_atomic_and_a_sync_names_a_missing_file);
	RUN(a_file_past_the_limit_is_refused_by_name_before_it_is_read);
	RUN(a_fifo_or_a_device_is_no_file_to_read);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
	if (system(cmd) != 0)
		printf("could not remove %s\n", dir);
	return test_summary();
}
