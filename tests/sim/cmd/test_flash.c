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
	evo_flash_rx_def def = {names, 1024, 3000, 32, slot_write, NULL};
	evo_flash_rx_init(&rx, &def);
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
		evo_can_frame f, r;
		if (evo_can_recv(bus, 1, &f, &err) == 1) {
			switch (evo_flash_rx_frame(&rx, &f, (uint32_t)ms, &r)) {
			case EVO_FLASH_RX_REPLY:
				evo_can_send(bus, &r, &err);
				break;
			case EVO_FLASH_RX_SWITCH:
				(*switches)++;
				evo_flash_rx_switched(&rx, 41, &r);
				evo_can_send(bus, &r, &err);
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
			     "%s flash minds/Collect --can candump:/dev/null "
			     "--wait 10 --tries 2 2>&1",
			     cli_evo);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "no answer from the robot on candump:/dev/null (2 "
			    "tries of 10 ms)");
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
	RUN(command_line_is_checked);
	cli_cleanup();
	return test_summary();
}
