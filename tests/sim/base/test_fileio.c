/* Errors and files (sim/base/err.c, sim/base/fileio.c): evo_fail formats
 * and tolerates a NULL message; a file reads back byte for byte, NUL
 * included; a missing file's message names it and why; an atomic write
 * replaces a file whole and leaves no temporary file beside it. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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

int main(void)
{
	snprintf(dir, sizeof dir, "%s/evo-fileio-XXXXXX", cli_tmp_root());
	if (!mkdtemp(dir))
		return 1;
	RUN(fail_formats_and_returns_minus_one);
	RUN(write_then_read_back_byte_for_byte);
	RUN(a_missing_file_is_named_with_the_reason);
	RUN(an_atomic_write_replaces_whole_and_leaves_nothing_beside);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
	if (system(cmd) != 0)
		printf("could not remove %s\n", dir);
	return test_summary();
}
