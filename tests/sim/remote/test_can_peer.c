/* evo speaks what the CAN ecosystem speaks: python-can (from PyPI, in
 * build/venv from `make deps`), with its own slcan interface, drives the
 * pseudo-terminal on which evo is the adapter (sim/remote/can.h,
 * slcan-pty:). python-can opens it as it would a USB adapter, its frame
 * reaches evo, and evo's frame reaches python-can. Without build/venv the
 * test fails, saying `make deps`. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"
#include "remote/can.h"
#include "support/cli.h"

static char venv_python[512];

TEST(python_can_and_evo_exchange_frames_over_slcan)
{
	CHECK(access(venv_python, X_OK) == 0);
	if (access(venv_python, X_OK) != 0) {
		printf("  %s is missing: run `make deps` (it makes build/venv "
		       "with python-can from PyPI)\n",
		       venv_python);
		return;
	}
	evo_err err = {{0}};
	evo_can *c = evo_can_open("slcan-pty:", &err);
	CHECK(c != NULL);
	if (!c)
		return;
	char cmd[2048], out[256];
	snprintf(out, sizeof out, "%s/peer.out", cli_tmp);
	snprintf(cmd, sizeof cmd, "exec %s tests/sim/remote/can_peer.py %s >%s "
				  "2>&1",
		 venv_python, evo_can_pty_name(c), out);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	evo_can_frame f = {0, 0, {0}};
	int got = 0;
	for (int i = 0; i < 300 && got == 0; i++)
		got = evo_can_recv(c, 100, &f, &err);
	CHECK_EQ_INT(got, 1);
	CHECK(f.id == 0x123 && f.len == 3 && f.data[0] == 1 &&
	      f.data[2] == 3);
	evo_can_frame answer = {0x180, 3, {0xAA, 0xBB, 0xCC}};
	CHECK_EQ_INT(evo_can_send(c, &answer, &err), 0);
	/* serve the pty while python-can finishes and closes it */
	int st = 0;
	for (int i = 0; i < 300 && waitpid(pid, &st, WNOHANG) != pid; i++)
		evo_can_recv(c, 50, &f, &err);
	if (waitpid(pid, &st, WNOHANG) == 0) {
		kill(pid, SIGKILL);
		waitpid(pid, &st, 0);
	}
	CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	char *said = cli_read("%s", out);
	CHECK(said && strstr(said, "got 180#AABBCC"));
	if (!said || !strstr(said, "got 180#AABBCC"))
		printf("  python-can said:\n%s\n", said ? said : "(nothing)");
	free(said);
	/* python-can's opening (close, bit rate, open) was answered, not
	 * counted as garbage */
	CHECK_EQ_INT(evo_can_dropped(c)[EVO_CAN_BAD_SYNTAX], 0);
	evo_can_close(c);
}

/* Issue 27, item 14: a log python-can wrote (its CanutilsLogWriter, with
 * the direction after each frame) is a source of frames for evo, at its
 * pace, and ends with a message. */
TEST(a_log_python_can_wrote_is_read_as_a_source)
{
	if (access(venv_python, X_OK) != 0) {
		CHECK(0);
		printf("  %s is missing: run `make deps`\n", venv_python);
		return;
	}
	CHECK_EQ_INT(
	    cli_sh("%s -c 'import can\n"
		   "w = can.CanutilsLogWriter(\"%s/py.log\", channel=\"vcan0\")\n"
		   "w.on_message_received(can.Message(timestamp=10.0, "
		   "arbitration_id=0x123, data=[1, 2, 3], is_extended_id=False, "
		   "is_rx=True))\n"
		   "w.on_message_received(can.Message(timestamp=10.2, "
		   "arbitration_id=0x140, data=[7, 0, 0, 0], is_extended_id=False, "
		   "is_rx=False))\n"
		   "w.on_message_received(can.Message(timestamp=10.3, "
		   "arbitration_id=0x12345, data=[1], is_extended_id=True))\n"
		   "w.stop()\n'",
		   venv_python, cli_tmp),
	    0);
	char *log = cli_read("%s/py.log", cli_tmp);
	CHECK(log && strstr(log, "123#010203 R\n") &&
	      strstr(log, "140#07000000 T\n"));
	free(log);
	char url[300];
	snprintf(url, sizeof url, "candump:%s/py.log", cli_tmp);
	evo_err err = {{0}};
	evo_can *c = evo_can_open(url, &err);
	CHECK(c != NULL);
	if (!c)
		return;
	evo_can_frame f;
	CHECK_EQ_INT(evo_can_recv(c, 1000, &f, &err), 1);
	CHECK(f.id == 0x123 && f.len == 3 && f.data[2] == 3);
	CHECK_EQ_INT(evo_can_recv(c, 1000, &f, &err), 1);
	CHECK(f.id == 0x140 && f.len == 4 && f.data[0] == 7);
	CHECK_EQ_INT(evo_can_recv(c, 1000, &f, &err), -1);
	CHECK_CONTAINS(err.msg, "py.log: the log ends after 2 frames");
	CHECK_EQ_INT(evo_can_dropped(c)[EVO_CAN_BAD_NOT_OURS], 1);
	CHECK_EQ_INT(evo_can_dropped(c)[EVO_CAN_BAD_SYNTAX], 0);
	evo_can_close(c);
}

int main(void)
{
	if (cli_setup("can-peer"))
		return 1;
	const char *v = getenv("EVO_VENV");
	snprintf(venv_python, sizeof venv_python, "%s/bin/python",
		 v && v[0] ? v : "build/venv");
	RUN(python_can_and_evo_exchange_frames_over_slcan);
	RUN(a_log_python_can_wrote_is_read_as_a_source);
	cli_cleanup();
	return test_summary();
}
