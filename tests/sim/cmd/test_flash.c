/* sim/cmd/flash.c: `evo flash` as a user runs it. Against a robot played
 * by this test (core's receiver on a slot in memory, behind an slcan
 * adapter on a pseudo-terminal, as the firmware test has under QEMU): the
 * image arrives and evo flash says when the new mind runs; a robot for
 * other names refuses it and evo flash prints why. Without a robot: a
 * corrupt image file is not sent, a bus with nobody on it is said so, and
 * a command line without --can is refused. */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "evo/flash.h"
#include "harness.h"
#include "remote/can.h"
#include "support/cli.h"

static _Alignas(8) uint8_t slot[8192];

static int slot_write(void *ctx, uint32_t offset, const uint8_t word[4])
{
	(void)ctx;
	memcpy(slot + offset, word, 4);
	return 0;
}

/* The robot's key and transfer counter, for the next flash_to_robot. */
static const uint8_t *robot_key;
static size_t robot_key_len;
static uint32_t robot_counter;

/* Run `evo flash ARGS --can slcan:PTY` against a robot with names hash
 * `names`; its exit status, its output in out, and the switches the
 * robot made. */
static int flash_to_robot(const char *args, uint32_t names, char *out,
			  size_t cap, int *switches)
{
	evo_err err;
	evo_can *bus = evo_can_open("slcan-pty:", &err);
	if (!bus) {
		printf("  %s\n", err.msg);
		return -1;
	}
	evo_flash_rx rx;
	evo_flash_rx_def def = {names,	    1024, 3000,
				32,	    slot_write, NULL,
				robot_key, (uint32_t)robot_key_len};
	evo_flash_rx_init(&rx, &def);
	rx.counter = robot_counter;
	evo_flash_rx_target(&rx, slot, sizeof slot);
	memset(slot, 0xFF, sizeof slot);
	*switches = 0;
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec %s flash %s --can slcan:%s > %s/out 2>&1", cli_evo, args,
		 evo_can_pty_name(bus), cli_tmp);
	fflush(stdout);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	int st = 0;
	for (int ms = 0; ms < 30000; ms++) {
		evo_can_frame f, r[EVO_FLASH_RX_REPLIES];
		if (evo_can_recv(bus, 1, &f, &err) == 1) {
			switch (evo_flash_rx_frame(&rx, &f, (uint32_t)ms, r)) {
			case EVO_FLASH_RX_REPLY:
				for (unsigned i = 0; i < rx.replies; i++)
					evo_can_send(bus, &r[i], &err);
				break;
			case EVO_FLASH_RX_SWITCH:
				(*switches)++;
				evo_flash_rx_switched(&rx, 41, r);
				for (unsigned i = 0; i < rx.replies; i++)
					evo_can_send(bus, &r[i], &err);
				break;
			default:
				break;
			}
		}
		if (waitpid(pid, &st, WNOHANG) == pid)
			break;
		if (ms == 29999) {
			kill(pid, SIGKILL);
			waitpid(pid, &st, 0);
		}
	}
	evo_can_close(bus);
	char *text = cli_read("%s/out", cli_tmp);
	snprintf(out, cap, "%s", text ? text : "");
	free(text);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static uint32_t image_names(const char *path)
{
	char *img = cli_read("%s", path);
	uint32_t h = img ? evo_wire_get_u32((const uint8_t *)img + 16) : 0;
	free(img);
	return h;
}

static uint32_t image_names_of_collect(void)
{
	char path[300];
	if (cli_sh("%s export minds/Collect -o %s/c.bin > /dev/null", cli_evo,
		   cli_tmp) != 0)
		return 0;
	snprintf(path, sizeof path, "%s/c.bin", cli_tmp);
	return image_names(path);
}

TEST(the_robot_runs_the_new_mind)
{
	char out[4096];
	int switches;
	CHECK_EQ_INT(cli_sh("%s export minds/Collect -o %s/c.bin > /dev/null",
			    cli_evo, cli_tmp),
		     0);
	char path[300];
	snprintf(path, sizeof path, "%s/c.bin", cli_tmp);
	uint32_t names = image_names(path);
	CHECK(names != 0);
	int rc =
	    flash_to_robot("minds/Collect", names, out, sizeof out, &switches);
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_INT(switches, 1);
	CHECK_CONTAINS(out, "evo flash: mind Collect, image 1164 bytes in 167 "
			    "segments, to slcan:");
	CHECK_CONTAINS(out, "evo flash: the robot runs mind Collect from the "
			    "tick after 41 (169 frames sent, 0 segments sent "
			    "again");
	char *img = cli_read("%s", path);
	CHECK(img && memcmp(slot, img, 1164) == 0);
	free(img);
	/* an image file, as evo export wrote it */
	char args[400];
	snprintf(args, sizeof args, "%s --window 4", path);
	rc = flash_to_robot(args, names, out, sizeof out, &switches);
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_INT(switches, 1);
}

TEST(another_robot_refuses_it)
{
	char out[4096];
	int switches;
	int rc = flash_to_robot("minds/Collect", 0x12345678u, out, sizeof out,
				&switches);
	CHECK_EQ_INT(rc, 1);
	CHECK_EQ_INT(switches, 0);
	CHECK_CONTAINS(out, "evo flash: the robot refused the image: the image "
			    "was built for another robot: other sensors, "
			    "actuators or variables (the image's names hash "
			    "53de2502, the robot's 12345678); it keeps "
			    "running the mind it had");
}

TEST(corrupt_image_file_is_not_sent)
{
	char out[2048];
	CHECK_EQ_INT(cli_sh("%s export minds/Collect -o %s/c.bin > /dev/null",
			    cli_evo, cli_tmp),
		     0);
	char *img = cli_read("%s/c.bin", cli_tmp);
	CHECK(img != NULL);
	if (!img)
		return;
	img[500] ^= 1;
	char path[300];
	snprintf(path, sizeof path, "%s/bad.bin", cli_tmp);
	FILE *w = fopen(path, "wb");
	CHECK(w && fwrite(img, 1, 1164, w) == 1164);
	if (w)
		fclose(w);
	free(img);
	int rc = cli_capture(out, sizeof out,
			     "%s flash %s --can candump:/dev/null 2>&1",
			     cli_evo, path);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "bad.bin: not sent: mind image is corrupt "
			    "(CRC-32 mismatch)");
}

TEST(nobody_on_the_bus)
{
	char out[2048];
	int rc = cli_capture(out, sizeof out,
			     "%s flash minds/Collect --can "
			     "'cannelloni:127.0.0.1:64917?local=64918' "
			     "--wait 10 --tries 2 2>&1",
			     cli_evo);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "no answer from the robot on "
			    "cannelloni:127.0.0.1:64917?local=64918 (2 "
			    "tries of 10 ms)");
	/* a log with no robot's replies in it ends, and says so */
	rc = cli_capture(out, sizeof out,
			 "%s flash minds/Collect --can candump:/dev/null 2>&1",
			 cli_evo);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "evo flash: candump:/dev/null: the log ends after "
			    "0 frames");
}

/* Issue 27, item 12: a CAN log that plays a robot's replies, READY, an
 * ACK of every segment and DONE, with no robot behind them. The ACK and
 * the DONE answer nothing evo flash sent when they come: evo flash does
 * not say the robot runs the mind, says what it ignored, and fails. */
TEST(replies_a_log_injects_do_not_make_a_robot)
{
	uint32_t total = evo_flash_segments(1164);
	evo_can_frame r[3];
	evo_flash_reply(&r[0], EVO_FLASH_READY, 16, 0, 0);
	evo_flash_reply(&r[1], EVO_FLASH_ACK, 0, total, 0);
	evo_flash_reply(&r[2], EVO_FLASH_DONE, 0, total, 41);
	char log[1024];
	size_t n = 0;
	for (int i = 0; i < 3; i++)
		n += evo_candump_format(&r[i], 100.0 + 0.05 * i, "can0",
					log + n);
	CHECK_EQ_INT(cli_write(log, "%s/forged.log", cli_tmp), 0);
	char out[4096];
	int rc = cli_capture(out, sizeof out,
			     "%s flash minds/Collect --can candump:%s/forged.log "
			     "2>&1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK(!strstr(out, "the robot runs mind"));
	CHECK_CONTAINS(out, "the log ends after 3 frames");
	CHECK_CONTAINS(out, "ignored 2 replies that answered nothing evo flash "
			    "sent");
}

/* Issue 27, item 12: over cannelloni, a second sender on evo flash's UDP
 * port plays the robot (READY, then an ACK and a DONE for whatever was
 * sent); the robot evo flash was told of is silent. Its datagrams are
 * not from the peer the URL names: dropped, counted, and said. */
TEST(a_second_sender_on_the_cannelloni_port_is_not_the_robot)
{
	char out[4096], url[128];
	const int evo_port = 64921, robot_port = 64922, forger_port = 64923;
	snprintf(url, sizeof url, "cannelloni:127.0.0.1:%d?local=%d",
		 robot_port, evo_port);
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
		 "exec %s flash minds/Collect --can '%s' --wait 300 --tries 3 "
		 "> %s/out 2>&1",
		 cli_evo, url, cli_tmp);
	fflush(stdout);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	/* the forger: sends to evo's port from its own */
	char furl[128];
	snprintf(furl, sizeof furl, "cannelloni:127.0.0.1:%d?local=%d",
		 evo_port, forger_port);
	evo_err err;
	evo_can *forger = evo_can_open(furl, &err);
	CHECK(forger != NULL);
	int st = 0;
	uint32_t total = evo_flash_segments(1164);
	for (int i = 0; i < 400 && forger; i++) {
		evo_can_frame r;
		evo_flash_reply(&r, EVO_FLASH_READY, 16, 0, 0);
		evo_can_send(forger, &r, &err);
		evo_flash_reply(&r, EVO_FLASH_ACK, 0, total, 0);
		evo_can_send(forger, &r, &err);
		evo_flash_reply(&r, EVO_FLASH_DONE, 0, total, 41);
		evo_can_send(forger, &r, &err);
		struct timespec ten_ms = {0, 10000000};
		nanosleep(&ten_ms, NULL);
		if (waitpid(pid, &st, WNOHANG) == pid)
			break;
	}
	if (waitpid(pid, &st, WNOHANG) == 0) {
		kill(pid, SIGKILL);
		waitpid(pid, &st, 0);
	}
	evo_can_close(forger);
	char *text = cli_read("%s/out", cli_tmp);
	snprintf(out, sizeof out, "%s", text ? text : "");
	free(text);
	CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 1);
	CHECK(!strstr(out, "the robot runs mind"));
	CHECK_CONTAINS(out, "no answer from the robot on");
	CHECK_CONTAINS(out, "no frames of evo's (");
	CHECK_CONTAINS(out, " not from the peer)");
}

/* Issue 27, item 13: a counter not above the robot's is refused, with
 * both numbers; --force sends it anyway; without --counter, evo flash
 * goes on from the robot's. */
TEST(a_stale_counter_is_refused_unless_forced)
{
	char out[4096];
	int switches;
	uint32_t names = image_names_of_collect();
	robot_counter = 5;
	int rc = flash_to_robot("minds/Collect --counter 3", names, out,
				sizeof out, &switches);
	CHECK_EQ_INT(rc, 1);
	CHECK_EQ_INT(switches, 0);
	CHECK_CONTAINS(out, "evo flash: the robot refused the image: the "
			    "transfer's counter is not above the robot's: a "
			    "transfer replayed, or one older than the robot's "
			    "mind (the transfer's 3, the robot's 5;");
	rc = flash_to_robot("minds/Collect --counter 3 --force", names, out,
			    sizeof out, &switches);
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_INT(switches, 1);
	CHECK_CONTAINS(out, "transfer counter 3)");
	/* the counter is kept after the image in the slot */
	CHECK_EQ_INT(evo_wire_get_u32(slot + 1164), 3);
	rc = flash_to_robot("minds/Collect", names, out, sizeof out,
			    &switches);
	CHECK_EQ_INT(rc, 0);
	CHECK_CONTAINS(out, "transfer counter 6)");
	robot_counter = 0;
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s flash minds/Collect --can x --counter 0 "
				 "2>&1",
				 cli_evo),
		     2);
	CHECK_CONTAINS(out, "--counter expects a whole number from 1 to "
			    "4294967294, found '0'");
}

/* Issue 27, item 13: a robot with a key takes the transfer made with it;
 * evo flash without the key does not send, and a key file is checked and
 * never printed. */
TEST(a_keyed_robot_takes_only_its_key)
{
	static const char hex[] =
	    "00112233445566778899aabbccddeeff0123456789abcdef0011223344556677";
	static uint8_t key[32];
	for (int i = 0; i < 32; i++) {
		unsigned v;
		sscanf(hex + 2 * i, "%2x", &v);
		key[i] = (uint8_t)v;
	}
	CHECK_EQ_INT(cli_write(hex, "%s/robot.key", cli_tmp), 0);
	robot_key = key;
	robot_key_len = sizeof key;
	char out[4096], args[512];
	int switches;
	uint32_t names = image_names_of_collect();
	snprintf(args, sizeof args, "minds/Collect --key %s/robot.key",
		 cli_tmp);
	int rc = flash_to_robot(args, names, out, sizeof out, &switches);
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_INT(switches, 1);
	CHECK_CONTAINS(out, "the robot runs mind Collect");
	CHECK(!strstr(out, "00112233"));
	rc = flash_to_robot("minds/Collect", names, out, sizeof out,
			    &switches);
	CHECK_EQ_INT(rc, 1);
	CHECK_EQ_INT(switches, 0);
	CHECK_CONTAINS(out, "evo flash: not sent: the robot takes only "
			    "transfers sent with its key (give evo flash --key "
			    "FILE)");
	/* a key of another length, and a file with more than a key */
	CHECK_EQ_INT(cli_write("0011223344\n", "%s/short.key", cli_tmp), 0);
	rc = cli_capture(out, sizeof out,
			 "%s flash minds/Collect --can x --key %s/short.key "
			 "2>&1",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "short.key:2: a key is 32 to 128 hex digits");
	CHECK(!strstr(out, "0011223344"));
	char two[200];
	snprintf(two, sizeof two, "%s\nsecret\n", hex);
	CHECK_EQ_INT(cli_write(two, "%s/two.key", cli_tmp), 0);
	rc = cli_capture(out, sizeof out,
			 "%s flash minds/Collect --can x --key %s/two.key 2>&1",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "two.key:2: a key is 32 to 128 hex digits");
	CHECK(!strstr(out, "secret") && !strstr(out, "00112233"));
	robot_key = NULL;
	robot_key_len = 0;
}

TEST(command_line_is_checked)
{
	char out[2048];
	CHECK_EQ_INT(cli_capture(out, sizeof out, "%s flash minds/Collect 2>&1",
				 cli_evo),
		     2);
	CHECK_CONTAINS(out, "--can URL is required");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s flash minds/Collect --can x --window 65 "
				 "2>&1",
				 cli_evo),
		     2);
	CHECK_CONTAINS(out, "--window expects a whole number from 1 to 64");
	CHECK_EQ_INT(cli_capture(out, sizeof out,
				 "%s flash minds/Collect --can nowhere: 2>&1",
				 cli_evo),
		     1);
	CHECK_CONTAINS(out, "is no CAN URL evo knows");
}

int main(void)
{
	if (cli_setup("flash") != 0)
		return 1;
	RUN(the_robot_runs_the_new_mind);
	RUN(another_robot_refuses_it);
	RUN(corrupt_image_file_is_not_sent);
	RUN(nobody_on_the_bus);
	RUN(replies_a_log_injects_do_not_make_a_robot);
	RUN(a_second_sender_on_the_cannelloni_port_is_not_the_robot);
	RUN(a_stale_counter_is_refused_unless_forced);
	RUN(a_keyed_robot_takes_only_its_key);
	RUN(command_line_is_checked);
	cli_cleanup();
	return test_summary();
}
