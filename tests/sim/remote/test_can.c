/* CAN on the host (sim/remote/can.h): cannelloni datagrams and candump
 * lines laid out by hand against evo's encoders and decoders; frames that
 * are not evo's (extended ids, remote frames, CAN FD) and malformed input
 * counted, never taken; slcan over a pseudo-terminal both as the adapter
 * a peer drives and as the program that drives an adapter (its bit rate
 * and open commands, and a refusal); cannelloni over UDP between two
 * endpoints; a candump log read as a source of frames; SocketCAN opened
 * where the kernel has it, and refused with the reason where it has not. */
#define _DEFAULT_SOURCE
#define _XOPEN_SOURCE 600
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "remote/can.h"
#include "support/cli.h"

static evo_can_frame frame(unsigned id, unsigned len, const char *bytes)
{
	evo_can_frame f = {(uint16_t)id, (uint8_t)len, {0}};
	memcpy(f.data, bytes, len);
	return f;
}

TEST(cannelloni_datagrams_are_laid_out_as_cannelloni_lays_them)
{
	evo_can_frame f[2] = {frame(0x123, 2, "\xAB\xCD"), frame(0x7FF, 0, "")};
	uint8_t d[64];
	size_t n = evo_cannelloni_encode(f, 2, 9, d, sizeof d);
	static const uint8_t want[] = {2,    0,    9, 0, 2,	       /* header */
				       0,    0,    1, 0x23, 2, 0xAB, 0xCD,
				       0,    0,    7, 0xFF, 0};
	CHECK_EQ_INT(n, sizeof want);
	CHECK(memcmp(d, want, sizeof want) == 0);
	evo_can_frame out[4];
	int got;
	unsigned long bad[EVO_CAN_BAD_COUNT] = {0};
	CHECK_EQ_INT(evo_cannelloni_decode(d, n, out, 4, &got, bad), 0);
	CHECK_EQ_INT(got, 2);
	CHECK(out[0].id == 0x123 && out[0].len == 2 && out[0].data[1] == 0xCD);
	CHECK(out[1].id == 0x7FF && out[1].len == 0);
}

TEST(cannelloni_frames_not_evos_are_counted_and_bad_datagrams_refused)
{
	/* an extended id, a remote frame, a CAN FD frame of 12 bytes, then
	 * one of evo's */
	static const uint8_t d[] = {
	    2,	  0,	1,    0,    4,					 /**/
	    0x80, 0,	0x12, 0x34, 1,	  0xEE,				 /* EFF */
	    0x40, 0,	0x01, 0x00, 0,					 /* RTR */
	    0,	  0,	0x01, 0x01, 0x8C, 0x01, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10,
	    11,	  12,						 /* FD */
	    0,	  0,	0x01, 0x40, 1,	  0x42};
	evo_can_frame out[4];
	int got;
	unsigned long bad[EVO_CAN_BAD_COUNT] = {0};
	CHECK_EQ_INT(evo_cannelloni_decode(d, sizeof d, out, 4, &got, bad), 0);
	CHECK_EQ_INT(got, 1);
	CHECK(out[0].id == 0x140 && out[0].data[0] == 0x42);
	CHECK_EQ_INT(bad[EVO_CAN_BAD_NOT_OURS], 3);
	/* cut anywhere: refused */
	int refused = 0;
	for (size_t len = 0; len < sizeof d; len++) {
		unsigned long b2[EVO_CAN_BAD_COUNT] = {0};
		refused += evo_cannelloni_decode(d, len, out, 4, &got, b2) == -1;
	}
	CHECK_EQ_INT(refused, (int)sizeof d);
	/* another version, another op code */
	uint8_t v[5] = {1, 0, 0, 0, 0};
	CHECK_EQ_INT(evo_cannelloni_decode(v, 5, out, 4, &got, bad), -1);
	v[0] = 2;
	v[1] = 1; /* ACK */
	CHECK_EQ_INT(evo_cannelloni_decode(v, 5, out, 4, &got, bad), -1);
	CHECK_EQ_INT(bad[EVO_CAN_BAD_VERSION], 2);
}

TEST(candump_lines_parse_and_format_as_candump_writes_them)
{
	const char *l = "(1436509052.249713) vcan0 044#2A366C2BBA";
	double t;
	char iface[EVO_CANDUMP_IFACE_MAX];
	evo_can_frame f;
	evo_can_bad why;
	CHECK_EQ_INT(evo_candump_parse(l, strlen(l), &t, iface, &f, &why), 1);
	CHECK_EQ_STR(iface, "vcan0");
	CHECK(f.id == 0x44 && f.len == 5 && f.data[0] == 0x2A &&
	      f.data[4] == 0xBA);
	CHECK(t > 1436509052.2497 && t < 1436509052.2498);
	char out[EVO_CANDUMP_LINE_MAX];
	size_t n = evo_candump_format(&f, t, "vcan0", out);
	CHECK_EQ_STR(out, "(1436509052.249713) vcan0 044#2A366C2BBA\n");
	CHECK_EQ_INT(n, strlen(out));
	/* no data */
	l = "(0.000001) can1 7FF#";
	CHECK_EQ_INT(evo_candump_parse(l, strlen(l), &t, iface, &f, &why), 1);
	CHECK(f.id == 0x7FF && f.len == 0);
}

TEST(candump_lines_not_evos_or_malformed_are_refused_by_reason)
{
	static const struct {
		const char *line;
		evo_can_bad why;
	} cases[] = {
	    {"(1.5) can0 12345678#00", EVO_CAN_BAD_NOT_OURS}, /* extended */
	    {"(1.5) can0 123#R", EVO_CAN_BAD_NOT_OURS},	      /* remote */
	    {"(1.5) can0 123##1AABB", EVO_CAN_BAD_NOT_OURS},  /* CAN FD */
	    {"(1.5) can0 123#001122334455667788", EVO_CAN_BAD_LENGTH},
	    {"(1.5) can0 123#0", EVO_CAN_BAD_SYNTAX},
	    {"(1.5) can0 123#0G", EVO_CAN_BAD_SYNTAX},
	    {"(1.5) can0 12#00", EVO_CAN_BAD_SYNTAX},
	    {"(1.5) can0 800#00", EVO_CAN_BAD_SYNTAX},
	    {"1.5 can0 123#00", EVO_CAN_BAD_SYNTAX},
	    {"(15) can0 123#00", EVO_CAN_BAD_SYNTAX},
	    {"(1.5)can0 123#00", EVO_CAN_BAD_SYNTAX},
	    {"(1.5) can0", EVO_CAN_BAD_SYNTAX},
	    {"", EVO_CAN_BAD_SYNTAX},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		double t;
		char iface[EVO_CANDUMP_IFACE_MAX];
		evo_can_frame f;
		evo_can_bad why = EVO_CAN_BAD_COUNT;
		int r = evo_candump_parse(cases[i].line, strlen(cases[i].line),
					  &t, iface, &f, &why);
		CHECK_EQ_INT(r, 0);
		CHECK_EQ_STR(evo_can_bad_name(why),
			     evo_can_bad_name(cases[i].why));
		if (r || why != cases[i].why)
			printf("  line '%s'\n", cases[i].line);
	}
}

/* ---- slcan over a pseudo-terminal ---------------------------------------- */

static int open_peer(const char *name)
{
	int fd = open(name, O_RDWR | O_NOCTTY);
	if (fd < 0)
		return -1;
	struct termios t;
	tcgetattr(fd, &t);
	cfmakeraw(&t);
	tcsetattr(fd, TCSANOW, &t);
	return fd;
}

/* Bytes readable on fd within ms, NUL-ended, into buf. */
static size_t read_for(int fd, int ms, char *buf, size_t cap)
{
	size_t n = 0;
	struct pollfd p = {fd, POLLIN, 0};
	while (n + 1 < cap && poll(&p, 1, ms) > 0) {
		ssize_t r = read(fd, buf + n, cap - 1 - n);
		if (r <= 0)
			break;
		n += (size_t)r;
		ms = 50;
	}
	buf[n] = 0;
	return n;
}

TEST(slcan_pty_is_an_adapter_a_peer_can_drive)
{
	evo_err err = {{0}};
	evo_can *c = evo_can_open("slcan-pty:", &err);
	CHECK(c != NULL);
	if (!c)
		return;
	const char *name = evo_can_pty_name(c);
	CHECK(name && strncmp(name, "/dev/pts/", 9) == 0);
	int peer = open_peer(name);
	CHECK(peer >= 0);
	/* what python-can's slcan interface writes when it opens: close,
	 * bit rate, open; each is answered with CR */
	CHECK(write(peer, "C\rS6\rO\r", 7) == 7);
	evo_can_frame f;
	CHECK_EQ_INT(evo_can_recv(c, 200, &f, &err), 0);
	char buf[256];
	read_for(peer, 500, buf, sizeof buf);
	CHECK_EQ_STR(buf, "\r\r\r");
	/* a frame each way; a BEL, an extended frame and a bad line between */
	CHECK(write(peer, "\aT1234567810\rt12Z0\rt1232ABCD\r", 29) == 29);
	CHECK_EQ_INT(evo_can_recv(c, 1000, &f, &err), 1);
	CHECK(f.id == 0x123 && f.len == 2 && f.data[0] == 0xAB &&
	      f.data[1] == 0xCD);
	const unsigned long *bad = evo_can_dropped(c);
	CHECK_EQ_INT(bad[EVO_CAN_BAD_REPLY], 1);
	CHECK_EQ_INT(bad[EVO_CAN_BAD_NOT_OURS], 1);
	CHECK_EQ_INT(bad[EVO_CAN_BAD_SYNTAX], 1);
	evo_can_frame out = frame(0x180, 3, "\x01\x02\x03");
	CHECK_EQ_INT(evo_can_send(c, &out, &err), 0);
	read_for(peer, 500, buf, sizeof buf);
	CHECK_EQ_STR(buf, "t1803010203\r");
	close(peer);
	evo_can_close(c);
}

TEST(slcan_pty_links_its_device_and_never_waits_for_a_reader)
{
	char url[300], link[256];
	snprintf(link, sizeof link, "%s/robot-tty", cli_tmp);
	snprintf(url, sizeof url, "slcan-pty:?link=%s", link);
	/* a link an evo killed left behind is replaced */
	CHECK_EQ_INT(symlink("/dev/pts/nowhere", link), 0);
	evo_err err = {{0}};
	evo_can *c = evo_can_open(url, &err);
	CHECK(c != NULL);
	if (!c)
		return;
	char to[64] = "";
	CHECK(readlink(link, to, sizeof to - 1) > 0);
	CHECK_EQ_STR(to, evo_can_pty_name(c));
	CHECK_EQ_STR(evo_can_pty_link(c), link);
	/* nobody has the device open: it takes some 16 KB, then nothing,
	 * and the frames after are counted, not waited for */
	evo_can_frame f = frame(0x100, 8, "\1\2\3\4\5\6\7\x08");
	int failed = 0;
	for (int i = 0; i < 2000; i++)
		failed += evo_can_send(c, &f, &err) != 0;
	CHECK_EQ_INT(failed, 0);
	CHECK(evo_can_unsent(c) > 0);
	CHECK(evo_can_unsent(c) < 2000);
	evo_can_close(c);
	CHECK(access(link, F_OK) != 0 && errno == ENOENT);
	/* something that is no link is not replaced */
	cli_write("mine", "%s", link);
	CHECK(evo_can_open(url, &err) == NULL);
	CHECK_CONTAINS(err.msg, "exists and is no symbolic link");
	char *kept = cli_read("%s", link);
	CHECK_EQ_STR(kept, "mine");
	free(kept);
	unlink(link);
	CHECK(evo_can_url_check("slcan-pty:?link=x", &err) == 0);
	CHECK(evo_can_url_check("can0", &err) != 0);
	CHECK_CONTAINS(err.msg, "'can0' is no CAN URL evo knows");
}

/* A fake adapter on a pty: answers CR (or BEL to S when `refuse`), and
 * writes what it received to `log`; then echoes one frame line. It waits
 * up to about 4 s for evo to open the pty, and ends when evo closes it. */
static void fake_adapter(int master, int refuse, const char *log)
{
	char got[512];
	size_t n = 0;
	double until = 0;
	for (int rounds = 0; rounds < 400; rounds++) {
		struct pollfd p = {master, POLLIN, 0};
		if (poll(&p, 1, 10) <= 0)
			continue;
		char b[128];
		ssize_t r = read(master, b, sizeof b);
		if (r <= 0) {
			/* no side open (EIO, POLLHUP): once evo has spoken it
			 * has closed, and the adapter is done; before, evo has
			 * not opened it yet, so wait for it rather than spin
			 * through the rounds and take the pty away with us */
			if (n > 0)
				break;
			struct timespec ts = {0, 10 * 1000 * 1000};
			nanosleep(&ts, NULL);
			continue;
		}
		for (ssize_t i = 0; i < r && n + 1 < sizeof got; i++) {
			got[n++] = b[i];
			if (b[i] != '\r')
				continue;
			/* the line just ended */
			size_t start = n - 1;
			while (start > 0 && got[start - 1] != '\r')
				start--;
			char cmd = got[start];
			if (cmd == 'S' && refuse)
				(void)!write(master, "\a", 1);
			else if (cmd == 't')
				(void)!write(master, "z\rt7FF0\r", 8);
			else
				(void)!write(master, "\r", 1);
		}
		(void)until;
	}
	got[n] = 0;
	cli_write(got, "%s", log);
	_exit(0);
}

static pid_t start_adapter(int refuse, const char *log, char *name,
			   size_t cap)
{
	int m = posix_openpt(O_RDWR | O_NOCTTY);
	if (m < 0 || grantpt(m) || unlockpt(m))
		return -1;
	snprintf(name, cap, "%s", ptsname(m));
	int s = open(name, O_RDWR | O_NOCTTY);
	struct termios t;
	tcgetattr(s, &t);
	cfmakeraw(&t);
	tcsetattr(s, TCSANOW, &t);
	close(s);
	pid_t pid = fork();
	if (pid == 0)
		fake_adapter(m, refuse, log);
	close(m);
	return pid;
}

TEST(slcan_drives_an_adapter_with_its_bit_rate_and_reads_its_frames)
{
	char name[64], log[512], url[200];
	snprintf(log, sizeof log, "%s/adapter.log", cli_tmp);
	pid_t a = start_adapter(0, log, name, sizeof name);
	CHECK(a > 0);
	snprintf(url, sizeof url, "slcan:%s?bitrate=250000", name);
	evo_err err = {{0}};
	evo_can *c = evo_can_open(url, &err);
	CHECK(c != NULL);
	if (c) {
		evo_can_frame f = frame(0x100, 1, "\x07"), in;
		CHECK_EQ_INT(evo_can_send(c, &f, &err), 0);
		/* the adapter's "z" acknowledgement is no frame and no error */
		CHECK_EQ_INT(evo_can_recv(c, 2000, &in, &err), 1);
		CHECK(in.id == 0x7FF && in.len == 0);
		CHECK_EQ_INT(evo_can_dropped(c)[EVO_CAN_BAD_SYNTAX], 0);
		evo_can_close(c);
	}
	int st;
	waitpid(a, &st, 0);
	char *got = cli_read("%s", log);
	/* close, 250 kbit/s (S5), open, the frame, close */
	CHECK(got && strstr(got, "C\rS5\rO\rt100107\rC\r"));
	free(got);
	/* an adapter that refuses the bit rate */
	snprintf(log, sizeof log, "%s/refusing.log", cli_tmp);
	a = start_adapter(1, log, name, sizeof name);
	snprintf(url, sizeof url, "slcan:%s", name);
	c = evo_can_open(url, &err);
	CHECK(c == NULL);
	CHECK_CONTAINS(err.msg, "the adapter refused 'S6' (BEL)");
	kill(a, SIGKILL);
	waitpid(a, &st, 0);
	/* an adapter whose process dies (its pseudo-terminal's other side
	 * closes): a frame sent then is lost, as on a line nobody reads,
	 * not an error that ends the run; the link's timeout reports the
	 * silence (test_can_robot's killed body) */
	snprintf(log, sizeof log, "%s/dying.log", cli_tmp);
	a = start_adapter(0, log, name, sizeof name);
	snprintf(url, sizeof url, "slcan:%s", name);
	c = evo_can_open(url, &err);
	CHECK(c != NULL);
	kill(a, SIGKILL);
	waitpid(a, &st, 0);
	if (c) {
		evo_can_frame f = frame(0x100, 1, "\x07"), in;
		CHECK_EQ_INT(evo_can_send(c, &f, &err), 0);
		CHECK_EQ_INT(evo_can_recv(c, 100, &in, &err), 0);
		evo_can_close(c);
	}
	/* URL mistakes */
	CHECK(evo_can_open("slcan:/dev/null?bitrate=300000", &err) == NULL);
	CHECK_CONTAINS(err.msg, "bitrate 300000 is none of slcan's");
	CHECK(evo_can_open("slcan:/no/such/tty", &err) == NULL);
	CHECK_CONTAINS(err.msg, "cannot open /no/such/tty");
	CHECK(evo_can_open("can:vcan0", &err) == NULL);
	CHECK_CONTAINS(err.msg, "no CAN URL evo knows");
}

TEST(cannelloni_endpoints_exchange_frames_over_udp)
{
	int pa = 20000 + getpid() % 20000, pb = pa + 1;
	char ua[128], ub[128];
	snprintf(ua, sizeof ua, "cannelloni:127.0.0.1:%d?local=%d", pb, pa);
	snprintf(ub, sizeof ub, "cannelloni:127.0.0.1:%d?local=%d", pa, pb);
	evo_err err = {{0}};
	evo_can *a = evo_can_open(ua, &err), *b = evo_can_open(ub, &err);
	CHECK(a && b);
	if (a && b) {
		evo_can_frame f = frame(0x1C5, 8, "\x01\x02\x03\x04\x05\x06\x07\x08"),
			      in;
		CHECK_EQ_INT(evo_can_send(a, &f, &err), 0);
		CHECK_EQ_INT(evo_can_recv(b, 2000, &in, &err), 1);
		CHECK(in.id == 0x1C5 && in.len == 8 && in.data[7] == 8);
		f = frame(0x140, 4, "\x10\x00\x00\x00");
		CHECK_EQ_INT(evo_can_send(b, &f, &err), 0);
		CHECK_EQ_INT(evo_can_recv(a, 2000, &in, &err), 1);
		CHECK(in.id == 0x140 && in.data[0] == 0x10);
		CHECK_EQ_INT(evo_can_recv(a, 100, &in, &err), 0);
	}
	evo_can_close(a);
	evo_can_close(b);
	CHECK(evo_can_open("cannelloni:127.0.0.1", &err) == NULL);
	CHECK_CONTAINS(err.msg, "expected cannelloni:HOST:PORT");
}

TEST(a_candump_log_is_a_source_of_frames)
{
	CHECK_EQ_INT(cli_write("(1.000000) can0 100#0100000002000000\n"
			       "(1.000100) can0 12345678#00\n"
			       "garbage\n"
			       "\n"
			       "(1.000200) can0 140#00000000\n",
			       "%s/in.log", cli_tmp),
		     0);
	char url[200];
	snprintf(url, sizeof url, "candump:%s/in.log", cli_tmp);
	evo_err err = {{0}};
	evo_can *c = evo_can_open(url, &err);
	CHECK(c != NULL);
	if (!c)
		return;
	evo_can_frame f;
	CHECK_EQ_INT(evo_can_recv(c, 100, &f, &err), 1);
	CHECK(f.id == 0x100 && f.len == 8 && f.data[4] == 2);
	CHECK_EQ_INT(evo_can_recv(c, 100, &f, &err), 1);
	CHECK(f.id == 0x140 && f.len == 4);
	CHECK_EQ_INT(evo_can_recv(c, 100, &f, &err), -1);
	CHECK(evo_can_ended(c));
	CHECK_EQ_INT(evo_can_dropped(c)[EVO_CAN_BAD_NOT_OURS], 1);
	CHECK_EQ_INT(evo_can_dropped(c)[EVO_CAN_BAD_SYNTAX], 1);
	f = frame(0x180, 2, "\xAA\xBB");
	CHECK_EQ_INT(evo_can_send(c, &f, &err), 0);
	evo_can_close(c);
	char *sent = cli_read("%s/in.log.sent", cli_tmp);
	CHECK(sent && strstr(sent, ") evo 180#AABB\n"));
	free(sent);
}

/* Issue 27, item 14: a log is played at the pace of its time stamps, as
 * canplayer plays it, waits without spinning, and ends with a message
 * instead of reading nothing forever. */
TEST(a_candump_log_is_played_at_its_pace_and_ends)
{
	CHECK_EQ_INT(cli_write("(50.000000) can0 100#01\n"
			       "(50.300000) can0 101#02\n"
			       "(50.600000) can0 102#03\n"
			       "(52.600000) can0 103#04\n",
			       "%s/paced.log", cli_tmp),
		     0);
	char url[300];
	snprintf(url, sizeof url, "candump:%s/paced.log", cli_tmp);
	evo_err err = {{0}};
	evo_can *c = evo_can_open(url, &err);
	CHECK(c != NULL);
	if (!c)
		return;
	evo_can_frame f;
	struct timespec w0, w1;
	clock_gettime(CLOCK_MONOTONIC, &w0);
	clock_t cpu0 = clock();
	for (unsigned i = 0; i < 3; i++) {
		CHECK_EQ_INT(evo_can_recv(c, 1000, &f, &err), 1);
		CHECK_EQ_INT(f.id, 0x100 + i);
	}
	clock_gettime(CLOCK_MONOTONIC, &w1);
	double took = (double)(w1.tv_sec - w0.tv_sec) +
		      (double)(w1.tv_nsec - w0.tv_nsec) * 1e-9;
	CHECK(took > 0.55 && took < 1.5);
	/* the fourth is 2 s later: each wait of 200 ms gives nothing */
	int none = 0;
	for (unsigned i = 0; i < 5; i++)
		none += evo_can_recv(c, 200, &f, &err) == 0;
	CHECK_EQ_INT(none, 5);
	CHECK_EQ_INT(evo_can_recv(c, 3000, &f, &err), 1);
	CHECK_EQ_INT(f.id, 0x103);
	/* 2.6 s of waiting took little of the processor */
	double cpu = (double)(clock() - cpu0) / CLOCKS_PER_SEC;
	CHECK(cpu < 0.3);
	if (cpu >= 0.3)
		printf("  %.2f s of CPU while waiting\n", cpu);
	CHECK_EQ_INT(evo_can_recv(c, 1000, &f, &err), -1);
	CHECK_CONTAINS(err.msg, "paced.log: the log ends after 4 frames");
	CHECK_EQ_INT(evo_can_recv(c, 1000, &f, &err), -1);
	evo_can_close(c);
	/* ?pace=0: as fast as it reads */
	snprintf(url, sizeof url, "candump:%s/paced.log?pace=0", cli_tmp);
	c = evo_can_open(url, &err);
	CHECK(c != NULL);
	if (!c)
		return;
	clock_gettime(CLOCK_MONOTONIC, &w0);
	for (unsigned i = 0; i < 4; i++)
		CHECK_EQ_INT(evo_can_recv(c, 0, &f, &err), 1);
	clock_gettime(CLOCK_MONOTONIC, &w1);
	CHECK(w1.tv_sec - w0.tv_sec < 1);
	CHECK_EQ_INT(evo_can_recv(c, 0, &f, &err), -1);
	evo_can_close(c);
}

/* The siblings: evo run and evo serve over a log stop at its end, saying
 * so, where they waited for more, using a whole processor. */
TEST(run_and_serve_stop_at_the_end_of_a_log)
{
	CHECK_EQ_INT(cli_write("(1.000000) can0 7FF#00\n", "%s/short.log",
			       cli_tmp),
		     0);
	char out[4096];
	int rc = cli_capture(out, sizeof out,
			     "timeout 20 %s serve "
			     "minds/Avoid/Tasks/Avoid-ROBOT.simbatch --can "
			     "candump:%s/short.log 2>&1",
			     cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "short.log: the log ends after 1 frame\n");
	rc = cli_capture(out, sizeof out,
			 "timeout 20 %s run minds/Avoid/Tasks/Avoid-ROBOT.simbatch "
			 "-nog --ticks 10 --can candump:%s/short.log 2>&1",
			 cli_evo, cli_tmp);
	CHECK_EQ_INT(rc, 1);
	CHECK_CONTAINS(out, "short.log: the log ends after 1 frame\n");
}

/* Issue 27, item 14: python-can writes a direction after the frame, " R"
 * received, " T" sent; both are frames that were on the bus. */
TEST(candump_lines_with_python_cans_direction_are_taken)
{
	static const char *const ok[] = {"(1.500000) vcan0 123#010203 R",
					 "(1.750000) vcan0 140#00000000 T",
					 "(1.800000) vcan0 7FF# R"};
	static const unsigned id[] = {0x123, 0x140, 0x7FF}, len[] = {3, 4, 0};
	for (unsigned i = 0; i < 3; i++) {
		double t;
		char iface[EVO_CANDUMP_IFACE_MAX];
		evo_can_frame f;
		evo_can_bad why;
		CHECK_EQ_INT(evo_candump_parse(ok[i], strlen(ok[i]), &t, iface,
					       &f, &why),
			     1);
		CHECK_EQ_INT(f.id, id[i]);
		CHECK_EQ_INT(f.len, len[i]);
	}
	static const struct {
		const char *line;
		evo_can_bad why;
	} bad[] = {
	    {"(1.5) vcan0 123#0102 X", EVO_CAN_BAD_SYNTAX},
	    {"(1.5) vcan0 123#0102 RR", EVO_CAN_BAD_SYNTAX},
	    {"(1.5) vcan0 123#0102R", EVO_CAN_BAD_SYNTAX},
	    {"(1.5) vcan0 100#R R", EVO_CAN_BAD_NOT_OURS},
	    {"(1.5) vcan0 00012345#01 R", EVO_CAN_BAD_NOT_OURS},
	};
	for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		double t;
		char iface[EVO_CANDUMP_IFACE_MAX];
		evo_can_frame f;
		evo_can_bad why = EVO_CAN_BAD_COUNT;
		CHECK_EQ_INT(evo_candump_parse(bad[i].line, strlen(bad[i].line),
					       &t, iface, &f, &why),
			     0);
		CHECK_EQ_STR(evo_can_bad_name(why),
			     evo_can_bad_name(bad[i].why));
	}
}

/* Issue 27, item 14: a DLC of 9 (or 9 bytes) is a length past 8 in every
 * format, as docs/can.md says, never a syntax error. */
TEST(a_dlc_of_9_is_a_length_in_every_format)
{
	unsigned long bad[EVO_CAN_BAD_COUNT] = {0};
	evo_slcan_reader r = {0};
	evo_can_frame out[4];
	int got;
	char reply[8];
	size_t reply_len = 0;
	/* 8 bytes with DLC 9, then 9 bytes with DLC 9 */
	const char *lines = "t1239001122334455667788\r"
			    "t12390011223344556677889\r"
			    "t123900112233445566778899\r";
	evo_slcan_read(&r, lines, strlen(lines), out, 4, &got, bad, reply,
		       sizeof reply, &reply_len);
	CHECK_EQ_INT(got, 0);
	CHECK_EQ_INT(bad[EVO_CAN_BAD_LENGTH], 3);
	CHECK_EQ_INT(bad[EVO_CAN_BAD_SYNTAX], 0);
	double t;
	char iface[EVO_CANDUMP_IFACE_MAX];
	evo_can_frame f;
	evo_can_bad why = EVO_CAN_BAD_COUNT;
	const char *l = "(1.0) can0 123#112233445566778899";
	CHECK_EQ_INT(evo_candump_parse(l, strlen(l), &t, iface, &f, &why), 0);
	CHECK_EQ_INT(why, EVO_CAN_BAD_LENGTH);
	static const uint8_t d[] = {2, 0, 0, 0, 1, 0, 0, 1, 0x23, 9,
				    1, 2, 3, 4, 5, 6, 7, 8, 9};
	unsigned long cb[EVO_CAN_BAD_COUNT] = {0};
	int n;
	CHECK_EQ_INT(evo_cannelloni_decode(d, sizeof d, out, 4, &n, cb), -1);
	CHECK_EQ_INT(cb[EVO_CAN_BAD_LENGTH], 1);
}

/* Issue 27, item 12: a cannelloni endpoint takes datagrams only from the
 * peer its URL names, address and port, as the reference cannelloni
 * takes only its remote's; the others are counted. */
TEST(cannelloni_takes_datagrams_only_from_its_peer)
{
	int pa = 20000 + (getpid() + 7) % 20000, pb = pa + 1, pc = pa + 2;
	char ua[128], ub[128], uc[128];
	snprintf(ua, sizeof ua, "cannelloni:127.0.0.1:%d?local=%d", pb, pa);
	snprintf(ub, sizeof ub, "cannelloni:127.0.0.1:%d?local=%d", pa, pb);
	/* another sender, to a's port from a port of its own */
	snprintf(uc, sizeof uc, "cannelloni:127.0.0.1:%d?local=%d", pa, pc);
	evo_err err = {{0}};
	evo_can *a = evo_can_open(ua, &err), *b = evo_can_open(ub, &err),
		*c = evo_can_open(uc, &err);
	CHECK(a && b && c);
	if (a && b && c) {
		evo_can_frame f = frame(0x1D3, 8, "\x03\x00\xA7\x00\x29\x00\x00\x00"),
			      in;
		CHECK_EQ_INT(evo_can_send(c, &f, &err), 0);
		CHECK_EQ_INT(evo_can_send(c, &f, &err), 0);
		f = frame(0x140, 4, "\x10\x00\x00\x00");
		CHECK_EQ_INT(evo_can_send(b, &f, &err), 0);
		CHECK_EQ_INT(evo_can_recv(a, 2000, &in, &err), 1);
		CHECK(in.id == 0x140 && in.data[0] == 0x10);
		CHECK_EQ_INT(evo_can_recv(a, 200, &in, &err), 0);
		CHECK_EQ_INT(evo_can_dropped(a)[EVO_CAN_BAD_SOURCE], 2);
		CHECK_EQ_STR(evo_can_bad_name(EVO_CAN_BAD_SOURCE),
			     "not from the peer");
	}
	evo_can_close(a);
	evo_can_close(b);
	evo_can_close(c);
}

TEST(socketcan_opens_or_says_why_not)
{
	evo_err err = {{0}};
	evo_can *c = evo_can_open("socketcan:vcan0", &err);
	if (c) {
		printf("  SocketCAN: vcan0 opened\n");
		evo_can_close(c);
		return;
	}
	/* this kernel: no AF_CAN (or no vcan0): the reason is given */
	printf("  SocketCAN not tested here: %s\n", err.msg);
	CHECK(strstr(err.msg, "has no SocketCAN") ||
	      strstr(err.msg, "no CAN interface vcan0"));
}

int main(void)
{
	if (cli_setup("can"))
		return 1;
	RUN(cannelloni_datagrams_are_laid_out_as_cannelloni_lays_them);
	RUN(cannelloni_frames_not_evos_are_counted_and_bad_datagrams_refused);
	RUN(candump_lines_parse_and_format_as_candump_writes_them);
	RUN(candump_lines_not_evos_or_malformed_are_refused_by_reason);
	RUN(slcan_pty_is_an_adapter_a_peer_can_drive);
	RUN(slcan_pty_links_its_device_and_never_waits_for_a_reader);
	RUN(slcan_drives_an_adapter_with_its_bit_rate_and_reads_its_frames);
	RUN(cannelloni_endpoints_exchange_frames_over_udp);
	RUN(a_candump_log_is_a_source_of_frames);
	RUN(a_candump_log_is_played_at_its_pace_and_ends);
	RUN(candump_lines_with_python_cans_direction_are_taken);
	RUN(run_and_serve_stop_at_the_end_of_a_log);
	RUN(a_dlc_of_9_is_a_length_in_every_format);
	RUN(cannelloni_takes_datagrams_only_from_its_peer);
	RUN(socketcan_opens_or_says_why_not);
	cli_cleanup();
	return test_summary();
}
