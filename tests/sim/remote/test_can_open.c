/* What evo_can_open (sim/remote/can.c) takes from a URL, which may come
 * with a task from someone else: a candump source's FILE.sent is never
 * written through a symbolic link planted at its name, and a rate or port
 * with a sign, junk after it or past any range (atol took "500000x" for
 * 500000) is refused with the text it found. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "remote/can.h"
#include "support/cli.h"

TEST(a_candump_logs_sent_file_is_written_through_no_link)
{
	CHECK_EQ_INT(cli_write("(1.000000) can0 100#0100000002000000\n",
			       "%s/shared.log", cli_tmp),
		     0);
	CHECK_EQ_INT(cli_write("export PATH=/usr/bin\n", "%s/bashrc", cli_tmp),
		     0);
	char link[300], target[300], url[320];
	snprintf(link, sizeof link, "%s/shared.log.sent", cli_tmp);
	snprintf(target, sizeof target, "%s/bashrc", cli_tmp);
	CHECK_EQ_INT(symlink(target, link), 0);
	snprintf(url, sizeof url, "candump:%s/shared.log", cli_tmp);
	evo_err err = {{0}};
	evo_can *c = evo_can_open(url, &err);
	CHECK(c == NULL);
	if (c) {
		evo_can_frame f = {.id = 0x180, .len = 1};
		evo_can_send(c, &f, &err);
		evo_can_close(c);
	}
	CHECK_CONTAINS(err.msg, link);
	CHECK_CONTAINS(err.msg, "a symbolic link, which evo does not write "
				"through");
	char *text = cli_read("%s/bashrc", cli_tmp);
	CHECK(text && strcmp(text, "export PATH=/usr/bin\n") == 0);
	free(text);
	/* without the link, FILE.sent is made and written as before */
	unlink(link);
	c = evo_can_open(url, &err);
	CHECK(c != NULL);
	if (c) {
		evo_can_frame f = {.id = 0x180, .len = 1, .data = {0xAA}};
		CHECK_EQ_INT(evo_can_send(c, &f, &err), 0);
		evo_can_close(c);
	}
	text = cli_read("%s", link);
	CHECK(text && strstr(text, ") evo 180#AA\n"));
	free(text);
}

TEST(a_url_number_with_a_sign_junk_or_overflow_is_refused)
{
	static const struct {
		const char *url, *want;
	} bad[] = {
	    {"slcan:/dev/null?bitrate=500000x", "bitrate 500000x is none"},
	    {"slcan:/dev/null?bitrate=-500000", "bitrate -500000 is none"},
	    {"slcan:/dev/null?bitrate=+500000", "bitrate +500000 is none"},
	    {"slcan:/dev/null?bitrate=99999999999999999999",
	     "bitrate 99999999999999999999 is none"},
	    {"slcan:/dev/null?baud=115200x", "baud 115200x is not a serial"},
	    {"slcan:/dev/null?baud=18446744073709666816",
	     "baud 18446744073709666816 is not a serial"},
	    {"cannelloni:127.0.0.1:20000?local=20001x",
	     "local port 20001x is not a port"},
	    {"cannelloni:127.0.0.1:20000?local=-1", "local port -1 is not"},
	};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		evo_err err = {{0}};
		evo_can *c = evo_can_open(bad[k].url, &err);
		CHECK(c == NULL);
		if (c)
			evo_can_close(c);
		CHECK_CONTAINS(err.msg, bad[k].want);
	}
}

int main(void)
{
	if (cli_setup("can-open"))
		return 1;
	RUN(a_candump_logs_sent_file_is_written_through_no_link);
	RUN(a_url_number_with_a_sign_junk_or_overflow_is_refused);
	cli_cleanup();
	return test_summary();
}
